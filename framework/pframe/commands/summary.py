"""``pframe summary RUN.nc [-o FILE.csv|FILE.md]``: what a run did, as a table (peaks per node
and storey, ductility, impacts and peak force per contact, energy balance, verdict, warnings;
``pframe.tables``)."""

from __future__ import annotations

import sys


def _summary(args) -> int:
    from pframe.tables import markdown, summary, write

    table = summary(args.result)
    if args.output is None:
        sys.stdout.write(markdown(table))
        return 0
    path = write(table, args.output, overwrite=args.overwrite)
    print(f"wrote {path}")
    return 0


def register(sub) -> None:
    p = sub.add_parser("summary", help="a run's summary table (Markdown, or CSV with -o .csv)")
    p.add_argument("result", help="result file of pframe solve (.nc)")
    p.add_argument("-o", "--output", help="write FILE.csv or FILE.md (default: Markdown on "
                   "standard output)")
    p.add_argument("--overwrite", action="store_true", help="replace an existing output")
    p.set_defaults(run=_summary)
