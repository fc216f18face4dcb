"""Cost per time step against the number of floors: a row of buildings, every adjacent pair in
contact at every level.

    python benchmarks/scaling.py [--steps 2000] [--repeats 3]

Scenes of 2 x 3, 10 x 6 and 10 x 60 buildings x storeys (6, 60 and 600 floors): bilinear
storeys, improved Kelvin contacts between every adjacent pair at every floor level
((b - 1) x n contacts), a sine ground motion strong enough for pounding, Newmark average
acceleration with full Newton. One variant, one thread, the kernel's own time
(``simulate(plan).solve_seconds``, best of ``--repeats`` after a warm-up that compiles it).

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
import platform
import shlex
import sys

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
    out["excitation"] = {"kind": "sine", "amplitude": 6.0, "frequency": 2 * math.pi * 2.0}
    out["analysis"] = {"dt": dt, "duration": steps * dt}
    out["recorders"] = [{"kind": "envelope",
                         "quantities": ["displacement", "story_drift", "contact_force"]}]
    return json.dumps(out)


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--steps", type=int, default=2000, help="steps per run (default 2000)")
    parser.add_argument("--repeats", type=int, default=3, help="timed runs, best kept")
    args = parser.parse_args(argv)

    from pframe.assemble import assemble
    from pframe.kernel import simulate
    from pframe.model import parse_scene

    print("command: " + shlex.join([sys.executable, *sys.argv]))
    print(f"{platform.platform()}, python {platform.python_version()}")
    rows = []
    for buildings, storeys in SCENES + TALLER:
        plan = assemble(parse_scene(row_scene(buildings, storeys, args.steps)).expanded)
        warm = simulate(plan, threads=1)
        assert warm.completed(0), warm.describe_failure(0)
        best = min(simulate(plan, threads=1).solve_seconds for _ in range(args.repeats))
        floors = plan.n_dof
        per_step = best / plan.steps * 1e9
        rows.append((buildings, storeys, floors, len(plan.contact_names), plan.bandwidth,
                     per_step, per_step / floors, warm.iterations[0] / plan.steps,
                     int(warm.impacts[0].sum())))
        print(f"  {buildings} x {storeys}: {floors} floors, {len(plan.contact_names)} contacts, "
              f"half-bandwidth {plan.bandwidth}: {per_step:,.0f} ns per step "
              f"({per_step / floors:,.0f} ns per step and floor), "
              f"{warm.iterations[0] / plan.steps:.2f} Newton solves per step, "
              f"{int(warm.impacts[0].sum())} impacts", flush=True)
    print(f"\nsummary ({args.steps} steps, one thread, kernel time, best of {args.repeats}):")
    print(f"{'buildings x storeys':>20} {'floors':>7} {'contacts':>9} {'band':>5} "
          f"{'ns/step':>11} {'ns/step/floor':>14} {'solves/step':>12} {'impacts':>8}")
    for b, s, n, c, bw, ns, nsf, it, imp in rows:
        print(f"{f'{b} x {s}':>20} {n:>7} {c:>9} {bw:>5} {ns:>11,.0f} {nsf:>14,.0f} "
              f"{it:>12.2f} {imp:>8}")
    by_shape = {(r[0], r[1]): r for r in rows}
    print("\ncost per step and floor at a fixed row width (the half-bandwidth fixed):")
    for width, heights in ((2, (3, 30, 300)), (10, (30, 60, 120))):
        cells = [by_shape[(width, h)] for h in heights]
        print(f"  {width} buildings: " + ", ".join(
            f"{r[2]} floors {r[6]:,.0f} ns" for r in cells)
              + f"  (x{cells[-1][2] / cells[0][2]:.0f} floors: cost per step "
                f"x{cells[-1][5] / cells[0][5]:.1f})")
    return 0


if __name__ == "__main__":
    sys.exit(main())
