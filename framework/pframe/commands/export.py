"""``pframe export RUN.nc --csv DIR``: every history of a result as CSV, one file per
variable (time, then a column per node, storey or contact; ``pframe.tables.export_csv``)."""

from __future__ import annotations


def _export(args) -> int:
    from pframe.tables import export_csv

    written = export_csv(args.result, args.csv)
    print(f"wrote {len(written)} files in {args.csv}: "
          + ", ".join(p.name for p in written))
    return 0


def register(sub) -> None:
    p = sub.add_parser("export", help="a result's histories as CSV files")
    p.add_argument("result", help="result file of pframe solve (.nc)")
    p.add_argument("--csv", required=True, metavar="DIR",
                   help="folder for the CSV files (made if missing; files in it are replaced)")
    p.set_defaults(run=_export)
