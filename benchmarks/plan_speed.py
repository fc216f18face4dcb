"""Buildings in plan: the cost per step of a scene in plan against its planar twin and against
OpenSeesPy, side by side in one run.

    python benchmarks/plan_speed.py [--floors 3,30,300] [--steps 4000] [--repeats 3]

Two buildings of n storeys each, pounding at every level. The planar twin: one bilinear
storey spring per storey and a linear contact between the floors (one DOF per floor). The
scene in plan: each storey four bilinear lines of resistance at the plan's edges (two along x,
two along y, half the twin's stiffness each along x), the centre of mass 10 % of the plan off
its centre, and the contacts at a point of the floors' edges off their centres (both floors
twist at every impact): three DOFs per floor, four elements per storey instead of one. The
same sine along x drives both. pframe: the kernel's own time (``simulate(plan, threads=1)``,
``solve_seconds``, best of ``--repeats`` after a warm-up). OpenSeesPy: the scene in plan as
``pframe opensees`` writes it (rigid diaphragms, ``zeroLength`` lines at their positions,
``ElasticPPGap`` contacts), its ``analyze`` call alone, best of the repeats. Both integrate
Newmark average acceleration with Newton to the same tolerance and record the same
envelopes' worth of histories (none kept: pframe's envelopes, OpenSees' recorders of the peer).

Printed: ns per step per floor of each, and the ratios plan / planar per floor (the goal:
within 3x) and per degree of freedom (a floor in plan has three), and OpenSees / pframe for
the scene in plan (above 1: pframe is faster; OpenSeesPy up to ``--opensees-floors``
storeys). Nothing is asserted; timings depend on the machine (benchmarks/README.md).
"""

from __future__ import annotations

import argparse
import json
import math

from _common import opensees_unavailable, print_header, table


def scene(floors: int, steps: int, in_plan: bool) -> str:
    """YAML (JSON) text of the pair (see the module)."""
    dt = 5e-4
    k, mass, size = 4.0e7, 1.0e5, (20.0, 12.0)
    out = {"title": f"2 x {floors} {'in plan' if in_plan else 'planar'}", "buildings": [],
           "contacts": []}
    for b, name in enumerate(("A", "B")):
        storey = {"material": "bilinear", "stiffness": k * (1.0 + b), "yield_drift": 0.01,
                  "alpha": 0.1}
        building = {"name": name, "floors": floors, "mass": mass}
        if in_plan:
            half = {**storey, "stiffness": storey["stiffness"] / 2}
            building.update(
                origin=[(size[0] + 0.05) * b, 0.0], plan={"size": list(size)},
                centre_of_mass=[size[0] / 2 * (1.1 if b == 0 else 0.9), size[1] / 2],
                lines=[{"name": "X1", "position": [0, 0], "direction": "x", **half},
                       {"name": "X2", "position": [0, size[1]], "direction": "x", **half},
                       {"name": "Y1", "position": [0, 0], "direction": "y", **half},
                       {"name": "Y2", "position": [size[0], 0], "direction": "y", **half}])
        else:
            building["story"] = storey
        out["buildings"].append(building)
    for level in range(1, floors + 1):
        contact = {"name": f"c{level}", "nodes": [f"A/{level}", f"B/{level}"], "gap": 0.01,
                   "law": "linear", "stiffness": 2.0e9}
        if in_plan:
            contact.update(points=[[size[0], size[1] * 0.8], [0.0, size[1] * 0.8]],
                           normal=[1.0, 0.0])
        out["contacts"].append(contact)
    out["damping"] = {"ratio": 0.05, "modes": [1, 2]}
    out["excitation"] = {"kind": "sine", "amplitude": 6.0, "frequency": 2 * math.pi * 1.5}
    out["analysis"] = {"dt": dt, "duration": steps * dt}
    out["recorders"] = [{"kind": "envelope", "quantities": ["displacement", "contact_force"]}]
    return json.dumps(out)


def _pframe(text: str, repeats: int):
    from pframe.assemble import assemble
    from pframe.kernel import simulate
    from pframe.reader import parse_scene

    plan = assemble(parse_scene(text).expanded)
    result = simulate(plan, threads=1)  # warm-up (and the impacts it makes)
    if not result.completed():
        raise RuntimeError(result.describe_failure())
    best = min(simulate(plan, threads=1).solve_seconds for _ in range(repeats))
    return plan, best, int(result.impacts[0].sum())


def _opensees(plan, repeats: int) -> float:
    from pframe.peers.from_plan import peer_scene
    from pframe.peers.opensees import run

    peer = peer_scene(plan)
    return min(run(peer)["analyze_seconds"] for _ in range(repeats))


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--floors", default="3,30,300", help="storeys per building")
    parser.add_argument("--steps", type=int, default=4000, help="steps per run")
    parser.add_argument("--repeats", type=int, default=3, help="timed runs, best kept")
    parser.add_argument("--opensees-floors", type=int, default=30,
                        help="OpenSeesPy runs up to this many storeys (it takes minutes at 300)")
    args = parser.parse_args(argv)
    print_header()
    missing = opensees_unavailable()
    rows = []
    for floors in (int(f) for f in args.floors.split(",")):
        planar_plan, planar, _ = _pframe(scene(floors, args.steps, False), args.repeats)
        plan_plan, in_plan, impacts = _pframe(scene(floors, args.steps, True), args.repeats)
        count = 2 * floors * args.steps
        opensees = (None if missing or floors > args.opensees_floors
                    else _opensees(plan_plan, args.repeats))
        rows.append([
            f"2 x {floors}", f"{planar_plan.n_dof} / {plan_plan.n_dof}", str(impacts),
            f"{1e9 * planar / count:.0f}", f"{1e9 * in_plan / count:.0f}",
            f"{in_plan / planar:.2f}",
            f"{in_plan / planar * planar_plan.n_dof / plan_plan.n_dof:.2f}",
            "-" if opensees is None else f"{1e9 * opensees / count:.0f}",
            "-" if opensees is None else f"{opensees / in_plan:.1f}"])
    print("\n".join(table(["scene", "DOFs planar / in plan", "impacts in plan",
                 "planar ns/step/floor", "in plan ns/step/floor", "in plan / planar",
                 "per DOF",
                 "OpenSees in plan ns/step/floor", "OpenSees / pframe"], rows)))
    if missing:
        print(f"OpenSeesPy columns left out: {missing}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
