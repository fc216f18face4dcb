"""``pframe export RUN.nc --csv DIR``: every history of a result as CSV, one file per
variable (time, then a column per node, storey or contact; ``pframe.tables.export_csv``).
``pframe export RISK.nc --pelicun EDP.csv``: a risk study's demands as the table pelicun
reads (``pframe.risk.pelicun``)."""

from __future__ import annotations

import sys
import warnings


def _export(args) -> int:
    from pframe.errors import InputError

    if (args.csv is None) == (args.pelicun is None):
        raise InputError("pframe export: give --csv DIR (a run's histories) or --pelicun "
                         "EDP.csv (a risk study's demands), one of them")
    pelicun_only = [flag for flag, value in (("--building", args.building),
                                             ("--condition", args.condition),
                                             ("--level", args.level),
                                             ("--overwrite", args.overwrite)) if value]
    if args.csv is not None:
        if pelicun_only:
            raise InputError(f"{', '.join(pelicun_only)}: options of --pelicun, not of --csv")
        from pframe.tables import export_csv

        written = export_csv(args.result, args.csv)
        print(f"wrote {len(written)} files in {args.csv}: "
              + ", ".join(p.name for p in written))
        return 0
    from pframe.risk.pelicun import export_pelicun

    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always", UserWarning)
        path = export_pelicun(args.result, args.pelicun, building=args.building,
                              condition=args.condition, level=args.level,
                              overwrite=args.overwrite)
    for w in caught:
        print(f"pframe: warning: {args.result}: {w.message}", file=sys.stderr)
    print(f"wrote {path}: pelicun's demand table (header, Units row, a row per run)")
    return 0


def register(sub) -> None:
    p = sub.add_parser("export", help="a result's histories as CSV files; a risk study's "
                       "demands for pelicun",
                       description="--csv DIR: every history of a run as CSV, one file per "
                       "variable. --pelicun EDP.csv: a risk study's peak demands (PFA, PID "
                       "by floor and storey) as the demand table pelicun (FEMA P-58) reads, "
                       "one row per run. See docs/risk.md#losses-with-pelicun.")
    p.add_argument("result", help="result file of pframe solve (--csv) or pframe risk "
                   "(--pelicun) (.nc)")
    p.add_argument("--csv", metavar="DIR",
                   help="folder for the CSV files (made if missing; files in it are replaced)")
    p.add_argument("--pelicun", metavar="EDP.csv",
                   help="pelicun's demand table of a risk study (an existing file only with "
                        "--overwrite)")
    p.add_argument("--building", metavar="NAME",
                   help="--pelicun: the building assessed (needed when there are several)")
    p.add_argument("--condition", choices=("with_pounding", "without_pounding"),
                   help="--pelicun: the runs with the contacts (default, when the study ran "
                        "them) or without")
    p.add_argument("--level", type=float, metavar="IM",
                   help="--pelicun: only the runs of this level (g): one stripe, the demands "
                        "at one intensity (default: every run)")
    p.add_argument("--overwrite", action="store_true",
                   help="--pelicun: replace an existing table (never the result)")
    p.set_defaults(run=_export)
