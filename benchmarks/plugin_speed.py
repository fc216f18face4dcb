"""A plug-in law against the built-in law it copies: kernel time of the same scene.

    python benchmarks/plugin_speed.py [--repeats R] [--steps N]

The test plug-in package (tests/plugin_pkg, installed with ``pip install --target`` into a
temporary folder that only this script's subprocess sees) registers ``improved_kelvin_copy``:
pframe's improved Kelvin law as a plug-in. The built-in law is C inside the compiled kernel;
the plug-in's Python force is compiled by numba into a C function the kernel calls through a
pointer (pframe.kernel.plugins). The scene is models/wu2021-eq14.yaml with its three contacts
on one law or the other (tests/test_plugin.py checks that they give the same bits).

Printed: the plug-in's first compilation (empty cache) and its load from the cache; the
kernel time (``Result.solve_seconds``, wall) and the CPU time of ``simulate`` (the process's,
every thread: the kernel runs in a pool thread) of
each law, R runs each, interleaved, after an untimed one; medians and the ratio built-in /
plug-in (the plug-in's share of the built-in law's speed; the issue asks for at least 80 %).
Nothing is asserted.
"""

from __future__ import annotations

import argparse
import json
import os
import shutil
import subprocess
import sys
import tempfile
from pathlib import Path

from _common import REPO, load_average, print_header

_PROBE = r"""
import json, statistics, sys, time
import yaml
from pframe.assemble import assemble
from pframe.kernel import simulate
from pframe.reader import parse_scene

repeats, steps = int(sys.argv[1]), int(sys.argv[2])
data = yaml.safe_load(open(sys.argv[3], encoding="utf-8"))
if steps:
    data["analysis"]["duration"] = steps * data["analysis"]["dt"]
plans = {}
for law in ("improved_kelvin", "improved_kelvin_copy"):
    for contact in data["contacts"]:
        contact["law"] = law
    plans[law] = assemble(parse_scene(json.dumps(data)).expanded)
start = time.perf_counter()
simulate(plans["improved_kelvin_copy"], threads=1)
first = time.perf_counter() - start
out = {"first_plugin_run": first, "kernel": {}, "cpu": {}}
for law, plan in plans.items():
    simulate(plan, threads=1)  # untimed
for _ in range(repeats):
    for law, plan in plans.items():
        tick = time.process_time()  # every thread's: the kernel runs in a pool thread
        result = simulate(plan, threads=1)
        out["cpu"].setdefault(law, []).append(time.process_time() - tick)
        out["kernel"].setdefault(law, []).append(result.solve_seconds)
print(json.dumps(out))
"""


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--repeats", type=int, default=7)
    parser.add_argument("--steps", type=int, default=0, help="shorten the scene (0: whole)")
    args = parser.parse_args()
    print_header()
    with tempfile.TemporaryDirectory() as tmp:
        tmp = Path(tmp)
        source, site = tmp / "plugin_pkg", tmp / "site"
        shutil.copytree(REPO / "tests" / "plugin_pkg", source)
        for isolation in (["--no-build-isolation"], []):  # offline first, as the tests do
            shutil.rmtree(site, ignore_errors=True)
            done = subprocess.run([sys.executable, "-m", "pip", "install", "-q", "--no-deps",
                                   *isolation, "--target", str(site), str(source)],
                                  capture_output=True, text=True)
            if done.returncode == 0:
                break
        if done.returncode != 0:
            print("cannot install the test plug-in:", done.stderr[-2000:])
            return 1
        env = dict(os.environ, PFRAME_CACHE_DIR=str(tmp / "cache"))
        env["PYTHONPATH"] = os.pathsep.join([str(site)] + (
            [env["PYTHONPATH"]] if env.get("PYTHONPATH") else []))
        model = REPO / "models" / "wu2021-eq14.yaml"
        done = subprocess.run([sys.executable, "-c", _PROBE, str(args.repeats), str(args.steps),
                               str(model)], capture_output=True, text=True, env=env)
        if done.returncode != 0:
            print(done.stderr[-3000:])
            return 1
        out = json.loads(done.stdout.strip().splitlines()[-1])
    print(f"\nscene: {model.name}, three contacts on the built-in improved_kelvin or the "
          "plug-in improved_kelvin_copy")
    print(f"first plug-in run in a fresh process with an empty cache (numba compiles the law): "
          f"{out['first_plugin_run']:.2f} s")
    import statistics

    rows = {}
    for law in ("improved_kelvin", "improved_kelvin_copy"):
        kernel = statistics.median(out["kernel"][law])
        cpu = statistics.median(out["cpu"][law])
        rows[law] = (kernel, cpu)
        print(f"  {law:22s} kernel {kernel:.4f} s (best {min(out['kernel'][law]):.4f}), "
              f"simulate CPU {cpu:.4f} s (medians of {args.repeats})")
    built, plug = rows["improved_kelvin"], rows["improved_kelvin_copy"]
    print(f"\nplug-in speed / built-in speed: kernel {built[0] / plug[0]:.2f}, "
          f"simulate CPU {built[1] / plug[1]:.2f} (1.00: as fast; the issue asks >= 0.80)")
    print(f"load average (1, 5, 15 min) at the end: {load_average()}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
