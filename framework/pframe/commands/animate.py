"""``pframe animate RUN.nc [-o RUN.html]``: the buildings of a run swaying, as one
self-contained HTML page with play, pause and a time slider (``pframe.plot.animate``); a
scene in plan is seen from above, one floor level at a time (``pframe.plot.plan_view``)."""

from __future__ import annotations

from pathlib import Path


def _animate(args) -> int:
    from pframe.plot.animate import write_animation

    output = args.output if args.output is not None else Path(args.result).with_suffix(".html")
    path = write_animation(args.result, output, overwrite=args.overwrite)
    if not args.quiet:
        print(f"{args.result}: wrote {path} (open it in a web browser)")
    return 0


def register(sub) -> None:
    p = sub.add_parser("animate", help="an HTML page of the buildings swaying, contacts lighting "
                       "up when closed (buildings in plan: seen from above, level by level)")
    p.add_argument("result", help="result file of pframe solve with a displacement history (.nc)")
    p.add_argument("-o", "--output", metavar="PAGE.html",
                   help="the page (default: RESULT's name with .html)")
    p.add_argument("--overwrite", action="store_true", help="replace an existing page")
    p.add_argument("-q", "--quiet", action="store_true", help="print nothing on success")
    p.set_defaults(run=_animate)
