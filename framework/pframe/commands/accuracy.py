"""``pframe accuracy MODEL.yaml``: each integrator on a ladder of time steps against the
reference solution; a table, a CSV file and a work-precision plot."""

from __future__ import annotations

import math
import sys
from pathlib import Path

from pframe.integrators import TABLE


def _accuracy(args) -> int:
    from pframe import accuracy
    from pframe.errors import InputError
    from pframe.reader import load_scene

    loaded = load_scene(args.model)
    names = args.integrators.split(",") if args.integrators else list(accuracy.INTEGRATORS)
    unknown = [n for n in names if n not in accuracy.INTEGRATORS]
    if unknown:
        raise InputError(f"unknown integrator {unknown[0]!r}; choose from "
                         f"{', '.join(accuracy.INTEGRATORS)}")
    from pframe import outputs

    factors = _factors(args.factors)
    accuracy.check_factors(factors, loaded)
    out = outputs.check_folder(
        args.output if args.output is not None else Path(args.model).stem + "-accuracy",
        "accuracy study (accuracy.csv and work-precision.png)", inputs=[args.model])
    if out.is_dir():  # its two files: never replaced without --overwrite, nor a device
        for name in ("accuracy.csv", "work-precision.png"):
            outputs.check_output(out / name, inputs=[args.model], overwrite=args.overwrite,
                                 what="accuracy file")
    print(f"{loaded.source}: reference solution, then {len(names)} integrators x "
          f"{len(factors)} time steps", file=sys.stderr)
    rows, reference = accuracy.study(
        loaded, {n: accuracy.INTEGRATORS[n] for n in names}, factors, args.repeats,
        progress=lambda row: print(f"  {row.integrator} dt={row.dt:.4g}: {row.status}",
                                   file=sys.stderr))
    print(f"reference: {reference.method} rtol={reference.rtol:g}, {reference.segments} "
          f"segments, {reference.seconds:.1f} s; impacts {[int(i) for i in reference.impacts]}")
    print(accuracy.table(rows))
    for tol, row in accuracy.recommend(rows):
        pick = f"{row.integrator} with dt = {row.dt:.4g} s ({row.solve_seconds:.3f} s)" if row \
            else "none of these runs"
        print(f"displacement error <= {tol:g}: {pick}")
    outputs.make_folder(out)  # only now: a refused study leaves no folder
    accuracy.write_csv(rows, out / "accuracy.csv")
    try:
        accuracy.plot(rows, out / "work-precision.png", title=Path(args.model).name)
        print(f"wrote {out / 'accuracy.csv'} and {out / 'work-precision.png'}")
    except ImportError:
        print(f"wrote {out / 'accuracy.csv'}; the plot needs matplotlib: "
              'pip install "pframe[plot]"')
    return 0


def _factors(text: str) -> tuple[float, ...]:
    from pframe.errors import InputError

    try:
        factors = tuple(float(f) for f in text.split(","))
    except ValueError:
        raise InputError(f"--factors {text}: give numbers separated by commas, such as "
                         "4,2,1,0.5") from None
    if not all(math.isfinite(f) and f > 0 for f in factors):
        raise InputError(f"--factors {text}: the factors must be positive numbers")
    return factors


def register(sub) -> None:
    p = sub.add_parser("accuracy", help="integrators x time steps against a reference solution")
    p.add_argument("model", help="scene file (YAML)")
    p.add_argument("--integrators", help="comma-separated (default: all): newmark, "
                   "newmark+events, " + ", ".join(name for name in TABLE if name != "newmark"))
    p.add_argument("--factors", default="4,2,1,0.5,0.25",
                   help="dt factors on the scene's dt, powers of two (default 4,2,1,0.5,0.25)")
    p.add_argument("--repeats", type=int, default=3, help="timed runs per case, best kept")
    p.add_argument("-o", "--output", help="folder for accuracy.csv and work-precision.png")
    p.add_argument("--overwrite", action="store_true",
                   help="replace accuracy.csv and work-precision.png in that folder")
    p.set_defaults(run=_accuracy)
