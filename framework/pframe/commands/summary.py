"""``pframe summary RESULT.nc [-o FILE.csv|FILE.md]``: what a run did, as a table (peaks per
node and storey, ductility, impacts and peak force per contact, energy balance, verdict,
warnings; ``pframe.tables``); of a gap audit or a risk study, what its command prints at the
end, and the file's warnings. A sweep's file is refused, saying so."""

from __future__ import annotations

import sys


def _summary(args) -> int:
    from pframe.api import open as open_result
    from pframe.tables import markdown, study_kind, summary, write

    with open_result(args.result) as ds:
        kind = study_kind(ds)
        if kind is not None:
            print(study_summary(ds, kind, args))
            return 0
    table = summary(args.result)
    if args.output is None:
        sys.stdout.write(markdown(table))
        return 0
    path = write(table, args.output, overwrite=args.overwrite)
    print(f"wrote {path}")
    return 0


def study_summary(ds, kind: str, args) -> str:
    """A gap audit's or a risk study's summary: its title, the table its command prints
    (``pframe gap``, ``pframe risk``), and its warnings; a sweep's file (a run per variant,
    no summary of its own) or a table asked for with -o is refused."""
    from pframe.errors import InputError

    if kind == "sweep":
        raise InputError(f"{args.result}: a sweep's file holds a run per variant, and pframe "
                         "summary summarises one run, a gap audit or a risk study: read it as "
                         "a Dataset (pframe.open) or draw it with pframe plot")
    if args.output is not None:
        raise InputError(f"-o {args.output}: a {kind}'s summary is printed, not written as a "
                         "table (-o writes a run's .csv or .md); redirect the output instead")
    if kind == "gap audit":
        from pframe.commands.gap import table as body
    else:
        from pframe.risk.output import summary as body
    warnings = [line for line in str(ds.attrs.get("warnings", "")).splitlines() if line.strip()]
    return "\n".join([str(ds.attrs.get("title", kind)), body(ds), "warnings:",
                      *([f"  {line}" for line in warnings] or ["  none"])])


def register(sub) -> None:
    p = sub.add_parser("summary", help="a run's summary table (Markdown, or CSV with -o .csv); "
                       "a gap audit's or a risk study's summary")
    p.add_argument("result", help="result file of pframe solve, gap or risk (.nc)")
    p.add_argument("-o", "--output", help="write a run's table as FILE.csv or FILE.md "
                   "(default: Markdown on standard output)")
    p.add_argument("--overwrite", action="store_true", help="replace an existing output")
    p.set_defaults(run=_summary)
