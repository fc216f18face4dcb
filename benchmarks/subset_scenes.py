"""Building the member scenes of a subset study's batch (``pframe.risk.uncertain.scenes``):
each sample's scene made and validated whole, as before (YAML composed and the variant's
text written per sample) against now (the YAML composed once, no text for members that are
run and never written), side by side in one run; then a whole g(u) call (scenes and the
kernel batch) both ways.

    python benchmarks/subset_scenes.py [--samples 250] [--repeat 3]

On the paper's pair (models/wu2021-eq14.yaml) with three uncertain values (gap, storey
stiffness of A, damping ratio), 8 s at dt = 0.01 s without contacts."""

from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))
from _common import print_header  # noqa: E402

REPO = Path(__file__).resolve().parents[1]
UNCERTAIN = {"gap": {"distribution": "lognormal", "median": 0.124, "dispersion": 0.2},
             "buildings.A.story.stiffness": {"distribution": "lognormal",
                                             "median": 1.0e7, "dispersion": 0.1},
             "damping.ratio": {"distribution": "uniform", "low": 0.02, "high": 0.07}}


def before(loaded, params, u):
    """The member scenes as pframe made them before: variant() composing and dumping."""
    from pframe.reader import variant
    from pframe.sweep.paths import put, resolve

    out = []
    for row in u:
        values = [float(p.value(x)) for p, x in zip(params, row)]

        def change(data, values=values):
            for p, v in zip(params, values):
                for path in resolve(data, tuple(p.path.split("."))):
                    put(data, path, v)

        out.append(variant(loaded, change))
    return out


def best(f, repeat):
    times = []
    for _ in range(repeat):
        t = time.perf_counter()
        result = f()
        times.append(time.perf_counter() - t)
    return min(times), result


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("--samples", type=int, default=250)
    ap.add_argument("--repeat", type=int, default=3)
    args = ap.parse_args()
    print_header()
    import pframe.risk.uncertain as uncertain
    from pframe.reader import load_scene
    from pframe.risk.uncertain import parse, scenes

    loaded = load_scene(REPO / "models" / "wu2021-eq14.yaml")
    params = parse(UNCERTAIN, "uncertain")
    u = np.random.default_rng(0).standard_normal((args.samples, len(params)))
    old, a = best(lambda: before(loaded, params, u), args.repeat)
    new, b = best(lambda: scenes(loaded, params, u), args.repeat)
    same = all(x.scene == y.scene for x, y in zip(a, b))
    print(f"member scenes, {args.samples} samples: before {old:.3f} s, now {new:.3f} s, "
          f"ratio {old / new:.2f}x (same scenes: {same})")
    motion = {"model": "clough_penzien", "intensity": 0.02, "ground_frequency": 15.6,
              "ground_damping": 0.6, "duration": 8.0, "step": 0.01}
    problem = uncertain.SubsetProblem(loaded, params, motion, 800, 0.01, threads=2)
    uu = np.random.default_rng(1).standard_normal((args.samples, problem.dim))
    new_call, _ = best(lambda: problem(uu), args.repeat)
    real = uncertain.scenes
    uncertain.scenes = before
    try:
        old_call, _ = best(lambda: problem(uu), args.repeat)
    finally:
        uncertain.scenes = real
    print(f"g(u) call (scenes and the kernel), {args.samples} runs of 800 steps: before "
          f"{old_call:.3f} s, now {new_call:.3f} s, ratio {old_call / new_call:.2f}x")


if __name__ == "__main__":
    main()
