"""What a new user waits for: installing pframe, its first run, and a warm run, side by side.

    python benchmarks/first_run.py [--repeats R] [--baseline-rev REV] [--no-opensees]

In one run, on this machine:

1. ``python -m venv`` + ``pip install -e .`` of this checkout in a fresh virtual environment
   (wall time; pip's download cache, if any, is the machine's);
2. in that environment, the first ``pframe solve models/wu2021-eq14.yaml -o OUT.nc
   --overwrite -q`` with an empty ``PFRAME_CACHE_DIR`` (a new temporary folder), against the
   same command warm (median of R): the ratio first / warm;
3. whole process, warm: ``pframe solve`` of models/wu2021-eq14-linear.yaml recording the four
   histories the OpenSees peer records, against OpenSeesPy's standalone script of the same
   scene (``pframe.peers.opensees.script_text``, run with this Python), R runs each,
   interleaved: the ratio pframe / OpenSees (below 1: pframe faster);
4. the kernel alone (``Result.solve_seconds``, median of R in one process) on the paper's
   scene and on its linear twin.

With ``--baseline-rev REV`` (a git revision of this repository, e.g. the last one with the
numba kernel), steps 1, 2 and 4 are repeated for that revision (extracted with ``git archive``
into a temporary folder, installed into its own fresh environment) and the ratios this/baseline
printed. Nothing is asserted: timings depend on the machine and its load (printed).
"""

from __future__ import annotations

import argparse
import json
import os
import subprocess
import sys
import tempfile
import time
from pathlib import Path

from _common import (
    KELVIN,
    LINEAR,
    PEER_RECORDERS,
    REPO,
    Timing,
    load_average,
    median_timing,
    opensees_script,
    opensees_unavailable,
    print_header,
    ratio,
    run_checked,
    scene_copy,
)

_KERNEL_PROBE = r"""
import json, statistics, sys
from pframe.assemble import assemble
from pframe.kernel import simulate
from pframe.reader import load_scene
repeats = int(sys.argv[1])
out = {}
for path in sys.argv[2:]:
    plan = assemble(load_scene(path).expanded)
    simulate(plan, threads=1)
    out[path] = statistics.median(simulate(plan, threads=1).solve_seconds for _ in range(repeats))
print(json.dumps(out))
"""


class Install:
    """A fresh virtual environment with one checkout installed in it (pip install -e)."""

    def __init__(self, label: str, checkout: Path, folder: Path):
        self.label, self.checkout = label, checkout
        self.venv = folder / f"venv-{label}"
        start = time.perf_counter()
        run_checked([sys.executable, "-m", "venv", str(self.venv)])
        bindir = self.venv / ("Scripts" if os.name == "nt" else "bin")
        self.python, self.pframe = bindir / "python", bindir / "pframe"
        run_checked([str(self.python), "-m", "pip", "install", "-q", "-e", str(checkout)])
        self.install_seconds = time.perf_counter() - start
        self.cache = folder / f"cache-{label}"
        self.env = {k: v for k, v in os.environ.items()
                    if k not in ("PYTHONPATH", "VIRTUAL_ENV", "PFRAME_CACHE_DIR")}
        self.env["PFRAME_CACHE_DIR"] = str(self.cache)

    def solve(self, model: Path, out: Path) -> Timing:
        return run_checked([str(self.pframe), "solve", str(model), "-o", str(out),
                            "--overwrite", "-q"], env=self.env)

    def kernel_seconds(self, repeats: int, models: list[Path]) -> dict:
        done = subprocess.run([str(self.python), "-c", _KERNEL_PROBE, str(repeats),
                               *map(str, models)], capture_output=True, text=True,
                              env=self.env, check=True)
        return json.loads(done.stdout.strip().splitlines()[-1])


def _first_and_warm(install: Install, folder: Path, repeats: int) -> tuple[Timing, Timing]:
    out = folder / f"{install.label}.nc"
    first = install.solve(KELVIN, out)  # empty cache: whatever a first run does
    warm = median_timing([install.solve(KELVIN, out) for _ in range(repeats)])
    return first, warm


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0],
                                     formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--repeats", type=int, default=5)
    parser.add_argument("--baseline-rev", default=None,
                        help="a git revision to compare with (e.g. the last numba kernel)")
    parser.add_argument("--no-opensees", action="store_true")
    args = parser.parse_args(argv)
    print_header()
    print()
    with tempfile.TemporaryDirectory(prefix="pframe-first-run-") as tmp:
        folder = Path(tmp)
        installs = []
        checkouts = [("this", REPO)]
        if args.baseline_rev:
            base = folder / "baseline"
            base.mkdir()
            archive = subprocess.run(["git", "-C", str(REPO), "archive", args.baseline_rev],
                                     capture_output=True, check=True).stdout
            subprocess.run(["tar", "-x", "-C", str(base)], input=archive, check=True)
            checkouts.append((f"baseline {args.baseline_rev}", base))
        rows = []
        for label, checkout in checkouts:
            print(f"{label}: python -m venv + pip install -e {checkout} ...", flush=True)
            install = Install(label.split()[0], checkout, folder)
            installs.append(install)
            print(f"  installed in {install.install_seconds:.1f} s", flush=True)
            first, warm = _first_and_warm(install, folder, args.repeats)
            print(f"  first pframe solve {KELVIN.name} (empty cache): wall {first.wall:.2f} s, "
                  f"CPU {first.cpu:.2f} s; warm (median of {args.repeats}): wall "
                  f"{warm.wall:.2f} s, CPU {warm.cpu:.2f} s; first/warm {ratio(first.wall, warm.wall)}",
                  flush=True)
            kernel = install.kernel_seconds(args.repeats, [KELVIN, LINEAR])
            print(f"  kernel alone (median of {args.repeats}): {KELVIN.name} "
                  f"{kernel[str(KELVIN)]:.4f} s, {LINEAR.name} {kernel[str(LINEAR)]:.4f} s",
                  flush=True)
            rows.append((label, install.install_seconds, first, warm, kernel))

        opensees = None
        if not args.no_opensees:
            why_not = opensees_unavailable(in_subprocess=True)
            if why_not:
                print(f"\nOpenSeesPy not available ({why_not}): no whole-process comparison")
            else:
                scene = scene_copy(LINEAR, folder, None, PEER_RECORDERS, "-peer-output")
                script = opensees_script(scene, folder)
                this = installs[0]
                this.solve(scene, folder / "peer.nc")  # untimed
                run_checked(script)
                pf, os_t = [], []
                for _ in range(args.repeats):
                    pf.append(this.solve(scene, folder / "peer.nc"))
                    os_t.append(run_checked(script))
                opensees = (median_timing(pf), median_timing(os_t))

        print("\nsummary (medians; ratios of wall times)")
        this = rows[0]
        print(f"  pip install -e . in a fresh venv: {this[1]:.1f} s")
        print(f"  first pframe solve / warm: {this[2].wall:.2f} s / {this[3].wall:.2f} s = "
              f"{ratio(this[2].wall, this[3].wall)} (target <= 1.5x)")
        if opensees:
            pf, os_t = opensees
            print(f"  whole pframe solve (warm) / OpenSeesPy whole script, {LINEAR.name} with "
                  f"the peer's four histories: {pf.wall:.3f} s / {os_t.wall:.3f} s = "
                  f"{ratio(pf.wall, os_t.wall)} (CPU {ratio(pf.cpu, os_t.cpu)})")
        for base in rows[1:]:
            print(f"  against {base[0]}:")
            print(f"    pip install -e: {this[1]:.1f} s vs {base[1]:.1f} s "
                  f"({this[1] - base[1]:+.1f} s)")
            print(f"    first pframe solve: {this[2].wall:.2f} s vs {base[2].wall:.2f} s; "
                  f"first/warm {ratio(this[2].wall, this[3].wall)} vs "
                  f"{ratio(base[2].wall, base[3].wall)}")
            print(f"    warm pframe solve: {this[3].wall:.2f} s vs {base[3].wall:.2f} s")
            for model in (KELVIN, LINEAR):
                mine, theirs = this[4][str(model)], base[4][str(model)]
                print(f"    kernel alone, {model.name}: {mine:.4f} s vs {theirs:.4f} s "
                      f"(baseline / this {ratio(theirs, mine)})")
        print(f"load average (1, 5, 15 min) at the end: {load_average()}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
