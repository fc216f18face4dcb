"""The imk_peak storey against the bilinear one: kernel time of the same scene.

    python benchmarks/imk_peak_speed.py [--repeats R]

The scene is models/wu2021-eq14.yaml (the paper's pair, 50,000 steps, improved Kelvin
contacts) with its bilinear storeys, and its twin whose storeys are imk_peak with the same
backbone up to the cap (K0 = k, My = f_y, as = alpha, a cap beyond any drift of the run) and
every deterioration on (Lamda = 10 m: slow, so the runs stay alike). Both are run R times,
interleaved, after an untimed run each; printed: the medians of the kernel time
(``Result.solve_seconds``) and of the Newton solves, and the ratio imk_peak / bilinear.
Nothing is asserted.
"""

from __future__ import annotations

import argparse
import copy
import json
import statistics

import yaml
from _common import KELVIN, load_average, print_header

from pframe.assemble import assemble
from pframe.kernel import simulate
from pframe.reader import parse_scene


def _imk(story: dict) -> dict:
    k = float(story["stiffness"])
    fy = k * float(story["yield_drift"])
    side = {"as": float(story["alpha"]), "my": fy, "theta_p": 10.0, "theta_pc": 10.0,
            "res": 0.3, "theta_u": 20.0, "d": 1.0}
    out = {"material": "imk_peak", "k0": k}
    for name, value in side.items():
        out[f"{name}_plus"] = value
        out[f"{name}_neg"] = value
    for x in ("s", "c", "a", "k"):
        out[f"lamda_{x}"] = 10.0
        out[f"c_{x}"] = 1.0
    return out


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--repeats", type=int, default=5)
    args = parser.parse_args()
    base = yaml.safe_load(KELVIN.read_text(encoding="utf-8"))
    twin = copy.deepcopy(base)
    for building in twin["buildings"]:
        building["story"] = _imk(building["story"])
    plans = {name: assemble(parse_scene(json.dumps(data), base_dir=KELVIN.parent).expanded)
             for name, data in (("bilinear", base), ("imk_peak", twin))}
    times = {name: [] for name in plans}
    solves = {}
    for plan in plans.values():  # untimed: loads the kernel
        simulate(plan)
    for _ in range(args.repeats):
        for name, plan in plans.items():
            result = simulate(plan)
            assert result.completed(), result.describe_failure()
            times[name].append(result.solve_seconds)
            solves[name] = result.counter("solves")
    print_header()
    print(f"load average after: {load_average()}")
    for name in plans:
        print(f"{name:9s} kernel {statistics.median(times[name]):.4f} s (median of "
              f"{args.repeats}), {solves[name]} Newton solves")
    print(f"imk_peak / bilinear: "
          f"{statistics.median(times['imk_peak']) / statistics.median(times['bilinear']):.2f}")


if __name__ == "__main__":
    main()
