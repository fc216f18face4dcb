"""Cost per time step against the number of floors: a row of buildings, every adjacent pair in
contact at every level.

    python benchmarks/scaling.py [--steps 8000] [--repeats 3] [--baseline FOLDER]

Scenes of 2 x 3, 10 x 6 and 10 x 60 buildings x storeys (6, 60 and 600 floors), then rows of
a fixed width made taller (2 x 30, 2 x 300, 10 x 30, 10 x 120): bilinear storeys, improved
Kelvin contacts (gap 2 mm) between every adjacent pair at every floor level ((b - 1) x n
contacts), Newmark average acceleration with full Newton. One variant, one thread, the
kernel's own time (``simulate(plan).solve_seconds``, best of ``--repeats`` after a warm-up that
compiles it). pframe only: nothing is compared with another program. ``--baseline FOLDER``:
the kernel's C sources of another revision (as in benchmarks/kernel_limit.py), its runs
alternated with the installed kernel's on each scene, in this process (best of ``--repeats``
each): its ns per step and the ratio kernel / baseline are printed too.

The scenes must pound, or the benchmark times elastic-like buildings with idle contacts. The
ground acceleration is -6 sin(4 pi t) m/s^2: a sine starting from rest drives the ground one
way only (its velocity never changes sign), and in a tall building the floors lag behind the
ground by a shear wave that climbs the slower (softer) building later. With the minus sign
the lag pushes a softer building into its right neighbour. In the two-building rows the
softer building is the left one, so their contacts close level by level as the wave climbs
(with the former plus sign and 2,000 steps those rows never pounded: 0 impacts); the
ten-building rows mix both orders and pound either way. 8,000 steps of 0.25 ms (2 s) let the
wave reach the top of the 300-storey row. Each scene prints its impacts and how many of its
contacts closed at least once.

The kernel numbers the DOFs by reverse Cuthill-McKee, which puts a row of floors at one level
next to each other: the half-bandwidth stays at about the number of buildings, and the banded
LDL^T costs O(n bw^2) per solve instead of O(n^3). So the cost per step grows about linearly
with the number of floors at a fixed number of buildings; from 2 to 10 buildings the band
widens (2 -> 10), which costs more per floor.
"""

from __future__ import annotations

import argparse
import json
import math
import sys
import tempfile
from pathlib import Path

from _common import load_average, print_header, table
from kernel_limit import compile_baseline

#: the issue's three scenes (6, 60, 600 floors), then rows of a fixed width made taller
SCENES = ((2, 3), (10, 6), (10, 60))
TALLER = ((2, 30), (2, 300), (10, 30), (10, 120))


def row_scene(buildings: int, storeys: int, steps: int) -> str:
    """YAML (JSON) text of ``buildings`` buildings of ``storeys`` storeys in a row."""
    dt = 2.5e-4
    out = {"title": f"{buildings} x {storeys} row", "buildings": [], "contacts": []}
    for b in range(buildings):
        out["buildings"].append({
            "name": f"B{b}", "floors": storeys, "mass": 1000.0 * (1.0 + 0.5 * (b % 2)),
            "story": {"material": "bilinear", "stiffness": 4.0e6 * (1.0 + 1.5 * (b % 3)),
                      "yield_drift": 0.004, "alpha": 0.1}})
    for b in range(buildings - 1):
        for level in range(1, storeys + 1):
            out["contacts"].append({
                "name": f"B{b}-B{b + 1}-{level}", "nodes": [f"B{b}/{level}", f"B{b + 1}/{level}"],
                "gap": 0.002, "law": "improved_kelvin", "stiffness": 2.0e7, "restitution": 0.5})
    out["damping"] = {"ratio": 0.05, "modes": [1, 2]}
    # negative: the ground's one-way drift makes the softer left buildings lag into their
    # right neighbours (see the module's docstring)
    out["excitation"] = {"kind": "sine", "amplitude": -6.0, "frequency": 2 * math.pi * 2.0}
    out["analysis"] = {"dt": dt, "duration": steps * dt}
    out["recorders"] = [{"kind": "envelope",
                         "quantities": ["displacement", "story_drift", "contact_force"]}]
    return json.dumps(out)


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--steps", type=int, default=8000, help="steps per run (default 8000)")
    parser.add_argument("--repeats", type=int, default=3, help="timed runs, best kept")
    parser.add_argument("--baseline", type=Path, default=None,
                        help="a folder of the kernel's C sources to time after the kernel")
    args = parser.parse_args(argv)
    print_header()
    with tempfile.TemporaryDirectory(prefix="pframe-scaling-") as tmp:
        library = None if args.baseline is None else compile_baseline(args.baseline, Path(tmp))
        return _measure(args, library)


def _best(plan, repeats: int, library=None) -> tuple[float, float]:
    """The best solve_seconds of ``repeats`` runs of the kernel and, with ``library``, of
    the baseline kernel there (inf without), the two alternated run by run."""
    from pframe.kernel import ckernel, simulate

    ours, theirs = math.inf, math.inf
    for _ in range(repeats):
        ours = min(ours, simulate(plan, threads=1).solve_seconds)
        if library is not None:
            with ckernel.baseline(library):
                theirs = min(theirs, simulate(plan, threads=1).solve_seconds)
    return ours, theirs


def _measure(args, library) -> int:
    from pframe.assemble import assemble
    from pframe.kernel import simulate
    from pframe.reader import parse_scene

    rows = []
    for buildings, storeys in SCENES + TALLER:
        plan = assemble(parse_scene(row_scene(buildings, storeys, args.steps)).expanded)
        warm = simulate(plan, threads=1)
        assert warm.completed(0), warm.describe_failure(0)
        best, base = _best(plan, args.repeats, library)
        floors, contacts = plan.n_dof, len(plan.contact_names)
        per_step = best / plan.steps * 1e9
        solves = warm.iterations[0] / plan.steps
        impacts = warm.impacts[0]
        closed = int((impacts > 0).sum())
        rows.append((buildings, storeys, floors, contacts, plan.bandwidth, per_step,
                     per_step / floors, solves, int(impacts.sum()), closed))
        print(f"  {buildings} x {storeys}: {floors} floors, {contacts} contacts, half-bandwidth "
              f"{plan.bandwidth}: {per_step:,.0f} ns per step ({per_step / floors:,.0f} ns per "
              f"step and floor), {solves:.2f} Newton solves per step, {int(impacts.sum())} "
              f"impacts, {closed} of {contacts} contacts closed at least once", flush=True)
        if library is not None:
            base = base / plan.steps * 1e9
            print(f"    baseline {base:,.0f} ns per step: kernel / baseline "
                  f"{per_step / base:.3f}", flush=True)
    print(f"\nsummary ({args.steps} steps, one thread, kernel time, best of {args.repeats}):")
    header = ("buildings x storeys", "floors", "contacts", "band", "ns/step", "ns/step/floor",
              "solves/step", "impacts", "contacts closed")
    print("\n".join(table(header, [
        (f"{b} x {s}", str(n), str(c), str(bw), f"{ns:,.0f}", f"{nsf:,.0f}", f"{it:.2f}",
         str(imp), f"{closed}/{c}") for b, s, n, c, bw, ns, nsf, it, imp, closed in rows])))
    by_shape = {(r[0], r[1]): r for r in rows}
    print("\ncost per step and floor at a fixed row width (the half-bandwidth fixed):")
    for width, heights in ((2, (3, 30, 300)), (10, (30, 60, 120))):
        cells = [by_shape[(width, h)] for h in heights]
        print(f"  {width} buildings: " + ", ".join(
            f"{r[2]} floors {r[6]:,.0f} ns" for r in cells)
              + f"  (x{cells[-1][2] / cells[0][2]:.0f} floors: cost per step "
                f"x{cells[-1][5] / cells[0][5]:.1f})")
    print(f"load average (1, 5, 15 min) at the end: {load_average()}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
