"""Setting up a tall pair: pframe's reading, validation and plan against OpenSees' model build,
at several heights (is it linear?).

    python benchmarks/setup_speed.py [--floors 1000,3000,10000,30000] [--repeats 3]

The scene: two shear buildings of N floors each (bilinear storeys, the paper's masses and
stiffnesses), a linear contact at every floor level (``nodes: [A, B]``, the shorthand of a
contact at every level: 2 x 30,000 floors written out one contact a line would pass the
1 MiB a scene file may hold), Rayleigh damping on modes 1 and 2, ten steps of a sine.

pframe
    ``pframe.reader.load_scene`` (the YAML read, the scene validated, its floors, storeys
    and contacts resolved, packed and checked) and ``pframe.assemble.assemble`` (DOF
    numbering, damping fitted on each building's modes, the stability and time-scale
    checks): a process per measurement, imports done before the clock (``PFRAME_MAX_FLOORS``
    set: the scenes pass the 100,000 floors, storeys and contacts pframe sets up unasked).
OpenSees
    ``build()`` of the standalone script ``pframe opensees`` writes for the same scene
    (nodes and masses, Steel01 storeys and ElasticPPGap contacts on zeroLength elements,
    Rayleigh damping by region with pframe's coefficients): a process per measurement, the
    script's own data (its literal lists) read before the clock.

Each is measured ``--repeats`` times, the two interleaved; the table gives the median CPU
time (the machine is shared: wall time is printed too), the cost per floor, the cost per floor
added since the height above in the table (``added``: linear, the same at every height; the
cost per floor also spreads the fixed cost of any set-up, the scene's classes built on first
use) and pframe / OpenSees (below 1: pframe faster). Nothing is asserted.
"""

from __future__ import annotations

import argparse
import json
import os
import statistics
import subprocess
import sys
import tempfile
from pathlib import Path

from _common import load_average, opensees_unavailable, print_header, table

SCENE = """title: a tall pair, {n} floors each
buildings:
  - {{name: A, floors: {n}, mass: 250.0,
     story: {{material: bilinear, stiffness: 197392.0, yield_drift: 0.0248, alpha: 0.1}}}}
  - {{name: B, floors: {n}, mass: 1000.0,
     story: {{material: bilinear, stiffness: 1973920.0, yield_drift: 0.0149, alpha: 0.1}}}}
contacts:
  - {{nodes: [A, B], gap: 0.12, law: linear, stiffness: 3.0e7}}
damping: {{ratio: 0.05, modes: [1, 2]}}
excitation: {{kind: sine, amplitude: 9.81, frequency: 6.283185307179586}}
analysis: {{dt: 0.001, duration: 0.01}}
recorders: [{{kind: envelope, quantities: [displacement]}}]
"""

PFRAME = """
import json, sys, time
from pframe.reader import load_scene
from pframe.assemble import assemble
import scipy.linalg, scipy.sparse.linalg, scipy.sparse.csgraph
wall, cpu = time.perf_counter(), time.process_time()
plan = assemble(load_scene(sys.argv[1]).expanded)
print(json.dumps({"wall": time.perf_counter() - wall, "cpu": time.process_time() - cpu,
                  "dofs": int(plan.n_dof)}))
"""

OPENSEES = """
import json, sys, time
source = open(sys.argv[1]).read()
space = {"__name__": "benchmark"}
exec(compile(source, sys.argv[1], "exec"), space)
wall, cpu = time.perf_counter(), time.process_time()
space["build"]()
print(json.dumps({"wall": time.perf_counter() - wall, "cpu": time.process_time() - cpu}))
"""


def run(code: str, path: Path) -> dict:
    env = dict(os.environ, PFRAME_MAX_FLOORS=str(10**7))
    out = subprocess.run([sys.executable, "-c", code, str(path)], capture_output=True,
                         text=True, env=env, check=False)
    if out.returncode != 0:
        raise RuntimeError(out.stderr[-2000:])
    return json.loads(out.stdout.strip().splitlines()[-1])


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--floors", default="1000,3000,10000,30000")
    parser.add_argument("--repeats", type=int, default=3)
    args = parser.parse_args(argv)
    print_header()
    why_not = opensees_unavailable()
    if why_not:
        print(f"OpenSeesPy not available ({why_not}): pframe's column only")
    rows, previous = [], None
    with tempfile.TemporaryDirectory(prefix="pframe-setup-") as tmp:
        for n in (int(v) for v in args.floors.split(",")):
            scene = Path(tmp) / f"pair-{n}.yaml"
            scene.write_text(SCENE.format(n=n), encoding="utf-8")
            script = Path(tmp) / f"pair-{n}.py"
            if not why_not:  # untimed: the exporter's own time is not the build's
                subprocess.run([sys.executable, "-m", "pframe.cli", "opensees", str(scene),
                                "-o", str(script)], check=True, capture_output=True,
                               env=dict(os.environ, PFRAME_MAX_FLOORS=str(10**7)))
            ours, theirs = [], []
            for _ in range(args.repeats):
                ours.append(run(PFRAME, scene))
                if not why_not:
                    theirs.append(run(OPENSEES, script))
            cpu = statistics.median(r["cpu"] for r in ours)
            wall = statistics.median(r["wall"] for r in ours)
            added = (f"{(cpu - previous[1]) / (2 * (n - previous[0])) * 1e6:.1f}"
                     if previous and n > previous[0] else "")
            previous = (n, cpu)
            line = [f"2 x {n:,}", f"{cpu:.2f}", f"{wall:.2f}", f"{cpu / (2 * n) * 1e6:.1f}",
                    added]
            if theirs:
                os_cpu = statistics.median(r["cpu"] for r in theirs)
                os_wall = statistics.median(r["wall"] for r in theirs)
                line += [f"{os_cpu:.2f}", f"{os_wall:.2f}", f"{os_cpu / (2 * n) * 1e6:.1f}",
                         f"{cpu / os_cpu:.2f}x"]
            else:
                line += ["", "", "", ""]
            rows.append(tuple(line))
            print(f"  2 x {n:,} floors: pframe {cpu:.2f} s CPU ({wall:.2f} s wall), OpenSees "
                  f"{line[5] or '-'} s CPU; load average {load_average()}", flush=True)
    print()
    for line in table(("floors", "pframe CPU s", "wall s", "us/floor", "added", "OpenSees CPU s",
                       "wall s", "us/floor", "pframe / OpenSees"), rows):
        print(line)
    print(f"load average at the end {load_average()} (goal: pframe / OpenSees <= 1 at "
          "2 x 30,000, and the us per floor added the same at every height)")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
