"""Modal damping against Rayleigh damping: kernel time of the same building.

    python benchmarks/modal_damping.py [--repeats R] [--floors 5 20 50]

A uniform bilinear shear building (30 t floors, 40 MN/m storeys, 1 % yield drift, 5 %
hardening) under El Centro 1940 (records folder beside the project), 6,000 steps of 5 ms,
with 5 % Rayleigh damping and with 5 % modal damping (a dense block over its floors: the
half-bandwidth grows from 1 to floors - 1, the residual takes floors^2 more operations per
evaluation). Each pair is run R times, interleaved, after an untimed run each; printed: the
median kernel time (``Result.solve_seconds``), the half-bandwidth and the ratio modal /
Rayleigh. Nothing is asserted.
"""

from __future__ import annotations

import argparse
import json
import statistics

from _common import REPO, load_average, print_header

from pframe.assemble import assemble
from pframe.kernel import simulate
from pframe.reader import parse_scene

RECORD = REPO.parent / "shared" / "records" / "elCentro.AT2"


def _plan(floors: int, damping: dict):
    scene = {"buildings": [{"name": "A", "floors": floors, "mass": 3.0e4,
                            "story": {"material": "bilinear", "stiffness": 4.0e7,
                                      "yield_drift": 0.01, "alpha": 0.05}}],
             "damping": damping,
             "excitation": {"kind": "record", "file": str(RECORD)},
             "analysis": {"dt": 0.005, "duration": 30.0},
             "recorders": [{"kind": "envelope", "quantities": ["story_drift"]}]}
    return assemble(parse_scene(json.dumps(scene)).expanded)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--repeats", type=int, default=5)
    parser.add_argument("--floors", type=int, nargs="+", default=[5, 20, 50])
    args = parser.parse_args()
    print_header()
    for floors in args.floors:
        plans = {"rayleigh": _plan(floors, {"ratio": 0.05}),
                 "modal": _plan(floors, {"kind": "modal", "ratio": 0.05})}
        times = {name: [] for name in plans}
        for plan in plans.values():  # untimed: loads the kernel
            simulate(plan)
        for _ in range(args.repeats):
            for name, plan in plans.items():
                result = simulate(plan)
                assert result.completed(), result.describe_failure()
                times[name].append(result.solve_seconds)
        median = {name: statistics.median(values) for name, values in times.items()}
        for name, plan in plans.items():
            print(f"{floors:3d} floors, {name:8s}: kernel {median[name] * 1e3:.1f} ms, "
                  f"half-bandwidth {plan.bandwidth}")
        print(f"{floors:3d} floors, modal / rayleigh: {median['modal'] / median['rayleigh']:.2f}")
    print(f"load average after: {load_average()}")


if __name__ == "__main__":
    main()
