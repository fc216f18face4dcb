"""What the demand quantities cost: recording the absolute floor acceleration against the
relative one, and the demand tables (pframe.impacts, pframe.summary) against the run itself.

    python benchmarks/demand_cost.py [--repeats R]

The scene is models/wu2021-eq14.yaml (50,000 steps, 24 impacts). Kernel runs (in process,
``Result.solve_seconds``) recording ``acceleration`` or ``absolute_acceleration`` as a
history at every step and as an envelope, R runs each, interleaved, after an untimed one:
medians and the ratio absolute / relative. Then, on the run's Dataset recording what the
impact table needs: the medians of pframe.impacts and pframe.summary against the median of
pframe.solve on the same scene. Nothing is asserted.
"""

from __future__ import annotations

import argparse
import statistics
import time
import warnings

import yaml
from _common import KELVIN, load_average, print_header

import pframe
from pframe.assemble import assemble
from pframe.kernel import simulate
from pframe.reader import parse_scene


def _scene(recorded: str) -> dict:
    data = yaml.safe_load(KELVIN.read_text(encoding="utf-8"))
    data["recorders"] = [{"kind": "history", "quantities": [recorded]},
                         {"kind": "envelope", "quantities": [recorded]}]
    return data


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeats", type=int, default=7)
    args = parser.parse_args()
    print_header()
    plans = {q: assemble(parse_scene(yaml.safe_dump(_scene(q))).expanded)
             for q in ("acceleration", "absolute_acceleration")}
    times = {q: [] for q in plans}
    for plan in plans.values():
        simulate(plan)  # untimed
    for _ in range(args.repeats):
        for q, plan in plans.items():
            times[q].append(simulate(plan).solve_seconds)
    rel, ab = (statistics.median(times[q]) for q in ("acceleration", "absolute_acceleration"))
    print(f"kernel, recording acceleration:          {1e3 * rel:8.2f} ms (median of "
          f"{args.repeats})")
    print(f"kernel, recording absolute_acceleration: {1e3 * ab:8.2f} ms")
    print(f"ratio absolute / relative:               {ab / rel:8.3f}")

    data = yaml.safe_load(KELVIN.read_text(encoding="utf-8"))
    data["recorders"] = [{"kind": "history", "quantities": [
        "velocity", "story_force", "story_drift", "contact_force", "contact_penetration"]}]
    solve, impacts, summary = [], [], []
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        for _ in range(args.repeats):
            t = time.perf_counter()
            ds = pframe.solve(data)
            solve.append(time.perf_counter() - t)
            t = time.perf_counter()
            table = pframe.impacts(ds)
            impacts.append(time.perf_counter() - t)
            t = time.perf_counter()
            pframe.summary(ds)
            summary.append(time.perf_counter() - t)
    s, i, m = (statistics.median(x) for x in (solve, impacts, summary))
    print(f"pframe.solve:   {1e3 * s:8.1f} ms; pframe.impacts {1e3 * i:8.1f} ms ({len(table)} "
          f"impacts, {i / s:.2f} of the solve); pframe.summary {1e3 * m:8.1f} ms "
          f"({m / s:.2f} of the solve)")
    print(f"load average at the end: {load_average()}")


if __name__ == "__main__":
    main()
