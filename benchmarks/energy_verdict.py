"""The measurements behind pframe.verdict's thresholds: the balance error and the integrator's
own dissipation of the shipped scenes, for every integrator at 1/2, 1, 4 (and optionally more)
times the scene's step, beside the peak displacement (how wrong the response got).

    python benchmarks/energy_verdict.py [--factors 0.5 1 4 8 16 32] [MODEL.yaml ...]

No timing: this prints what the verdict judges, so the thresholds can be checked against it.
"""

from __future__ import annotations

import argparse
import copy
import json
import warnings
from pathlib import Path

import yaml

from pframe.assemble import assemble
from pframe.kernel import simulate
from pframe.reader import parse_scene
from pframe.verdict import of_result

ROOT = Path(__file__).resolve().parents[1]
MODELS = [ROOT / "models" / name for name in ("wu2021-eq14.yaml", "hust-4x3.yaml",
                                              "wu2021-pulse.yaml")]
INTEGRATORS = [{"type": "newmark"}, {"type": "newmark", "gamma": 0.6, "beta": 0.3025},
               {"type": "hht", "alpha": 0.05}, {"type": "hht", "alpha": 1 / 3},
               {"type": "generalized_alpha", "rho_infinity": 0.8},
               {"type": "generalized_alpha", "rho_infinity": 0.0},
               {"type": "central_difference", "substeps": "auto"},
               {"type": "newmark", "events": True}]


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("models", nargs="*", type=Path, default=MODELS)
    parser.add_argument("--factors", nargs="+", type=float, default=[0.5, 1.0, 4.0])
    args = parser.parse_args()
    print(f"{'scene':16s} {'integrator':52s} {'dt x':>5s} {'balance':>9s} {'D_alg':>10s} "
          f"{'peak (m)':>9s}  verdict")
    for model in args.models:
        base = yaml.safe_load(model.read_text(encoding="utf-8"))
        for integrator in INTEGRATORS:
            for factor in args.factors:
                scene = copy.deepcopy(base)
                scene["analysis"]["integrator"] = integrator
                scene["analysis"]["dt"] *= factor
                scene["recorders"] = [{"kind": "envelope", "quantities": ["displacement"]}]
                loaded = parse_scene(yaml.safe_dump(scene), str(model), model.parent)
                with warnings.catch_warnings():
                    warnings.simplefilter("ignore")
                    result = simulate(assemble(loaded.expanded))
                verdict = of_result(result)
                status = "" if result.completed(0) else f" ({result.describe_failure(0)})"
                print(f"{model.stem:16s} {json.dumps(integrator):52s} {factor:5g} "
                      f"{verdict.balance_error:9.2e} {verdict.algorithmic:+10.2e} "
                      f"{result.envelope['displacement'][0].max():9.4g}  "
                      f"{verdict.level}{status}", flush=True)


if __name__ == "__main__":
    main()
