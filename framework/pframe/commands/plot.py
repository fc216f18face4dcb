"""``pframe plot OUT.nc``: the paper's figures (histories and hysteresis loops) of a result.

matplotlib is imported only when this command runs, with the Agg backend, so the command works
on servers without a display and the other commands never load it.
"""

from __future__ import annotations

import sys
from pathlib import Path


def _plot(args) -> int:
    try:
        import matplotlib
    except ImportError:
        matplotlib = None
    if matplotlib is not None:
        # before any figure is made: no display is needed, and none is opened
        matplotlib.use("Agg")
    from pframe.plot import figures, output_paths, save
    from pframe.record.check import file_kind

    if args.output == "":
        from pframe.errors import InputError

        raise InputError("-o '': the figure needs a name ending in .png, .svg or .pdf")
    from pframe.api import result_file

    result_file(args.result, "pframe plot")  # before any reader opens it (a FIFO blocks)
    output = Path(args.output) if args.output else Path(args.result).with_suffix(".pdf")
    output_paths(output, ["check"])  # a bad name or folder fails before the drawing
    from pframe import outputs

    if output.suffix.lower() == ".pdf":  # PNG names per level are checked when saved
        outputs.check_output(output, inputs=[args.result], overwrite=args.overwrite,
                             what="figure")
    kind = file_kind(args.result)
    _check_options(args, kind == "sweep")
    if kind == "sweep":
        return _plot_sweep(args, output)
    if kind == "gap_audit":
        return _plot_gap(args, output)
    if kind == "risk_study":
        from pframe.plot import save
        from pframe.plot.risk import risk_figures

        written = save(risk_figures(args.result), output, title=f"pframe plot {args.result}",
                       overwrite=args.overwrite, inputs=[args.result])
        if not args.quiet:
            print(f"{args.result}: risk study; wrote " + ", ".join(str(p) for p in written))
        return 0
    say = (lambda text: None) if args.quiet else (
        lambda text: print(f"pframe: {args.result}: {text}", file=sys.stderr))
    time_range = tuple(args.time_range) if args.time_range else None
    figs = figures(args.result, kind=args.kind or "all", levels=args.story,
                   time_range=time_range, dimensionless=args.dimensionless, report=say,
                   units=args.units)
    written = save(figs, output, title=f"pframe plot {args.result}",
                   overwrite=args.overwrite, inputs=[args.result])
    if not args.quiet:
        levels = [k for k in figs if k not in ("links", "torsion", "supports")]
        what = " and ".join(([f"level{'s' if len(levels) > 1 else ''} {', '.join(levels)}"]
                             if levels else []) + [k for k in figs if k not in levels])
        print(f"{args.result}: {len(figs)} figure{'s' if len(figs) > 1 else ''} "
              f"({what}); wrote "
              + ", ".join(str(p) for p in written))
    return 0


#: options of a single run's figures and of a sweep's spectrum (argparse destinations)
_RUN_OPTIONS = {"kind": "--kind", "story": "--story", "time_range": "--time-range",
                "dimensionless": "--dimensionless", "units": "--units"}
_SWEEP_OPTIONS = {"response": "--response", "x": "--x", "curves": "--curves", "at": "--at"}


def _check_options(args, sweep_file: bool) -> None:
    """An option that does not apply to the file at hand is an error, not ignored."""
    from pframe.errors import InputError

    wrong, right = (_RUN_OPTIONS, _SWEEP_OPTIONS) if sweep_file else (_SWEEP_OPTIONS, _RUN_OPTIONS)
    given = [flag for dest, flag in wrong.items() if getattr(args, dest, None)]
    if given:
        what = ("a sweep file (pframe sweep), drawn as one response spectrum" if sweep_file
                else "the result of one run (pframe solve), drawn level by level")
        raise InputError(f"{args.result}: {', '.join(given)} "
                         f"{'does' if len(given) == 1 else 'do'} not apply: the file is {what}; "
                         f"its options are {', '.join(right.values())}")


def _plot_sweep(args, output: Path) -> int:
    """A sweep file (pframe sweep): one response-spectrum figure."""
    from pframe.errors import InputError
    from pframe.plot import save
    from pframe.plot.spectrum import spectrum

    at = {}
    for item in args.at or []:
        key, sep, value = item.partition("=")
        if not sep:
            raise InputError(f"--at {item}: write DIMENSION=VALUE, e.g. --at contact=floor-1")
        at[key.strip()] = value.strip()
    fig, notes = spectrum(args.result, response=args.response, x=args.x, curves=args.curves,
                          at=at)
    written = save({"spectrum": fig}, output, title=f"pframe plot {args.result}",
                   overwrite=args.overwrite, inputs=[args.result])
    if not args.quiet:
        print(f"{args.result}: response spectrum ({fig.axes[0].get_label().split()[-1]}"
              + (f"; {', '.join(notes)}" if notes else "") + "); wrote "
              + ", ".join(str(p) for p in written))
    return 0


def _plot_gap(args, output: Path) -> int:
    """A gap-audit file (pframe gap): the separations by rule and level, and the fragility."""
    from pframe.plot import save
    from pframe.plot.gap import gap_figure

    level = None
    for item in args.at or []:
        key, _, value = item.partition("=")
        if key.strip() == "level":
            level = float(value)
    fig, notes = gap_figure(args.result, statistic=args.statistic or "p84", level=level)
    written = save({"gap": fig}, output, title=f"pframe plot {args.result}",
                   overwrite=args.overwrite, inputs=[args.result])
    if not args.quiet:
        print(f"{args.result}: gap audit ({'; '.join(notes)}); wrote "
              + ", ".join(str(p) for p in written))
    return 0


def register(sub) -> None:
    plot = sub.add_parser(
        "plot", help="draw a result's histories and hysteresis loops (PNG, SVG or PDF)",
        description="Draw the paper's figures from a result file: one figure per floor level "
                    "with (a) displacement, (b) pounding force and (c) velocity histories of "
                    "the buildings' floors at that level and (d), (e) the hysteresis loops of "
                    "their storeys. Needs matplotlib (pip install \"pframe[plot]\").")
    plot.add_argument("result", help="result file written by pframe solve, sweep or gap (.nc)")
    plot.add_argument("-o", "--output", metavar="FIGURE",
                      help="FIGURE.pdf (one page per level), FIGURE.png or FIGURE.svg "
                           "(FIGURE-<level>.png for several levels); default: RESULT's name "
                           "with .pdf")
    plot.add_argument("--kind", choices=("all", "histories", "hysteresis", "pounding", "links",
                                         "torsion", "supports"),
                      default=None,
                      help="panels to draw (default: all); pounding: per contact, the relative "
                           "displacement of its nodes against the gap, closing shaded, "
                           "impacts marked; links: every link's force history and its force "
                           "against its deformation; torsion (buildings in plan): each "
                           "storey's torsional irregularity ratio against 1.2 and 1.4; "
                           "supports: each support's ground acceleration and displacement and "
                           "each contact's relative ground displacement")
    plot.add_argument("--story", action="append", metavar="N",
                      help="draw floor level N only (repeat for several; default: every level)")
    plot.add_argument("--time-range", nargs=2, type=float, metavar=("START", "END"),
                      help="draw START <= t <= END only (s, or tau with --dimensionless)")
    plot.add_argument("--dimensionless", action="store_true",
                      help="draw the paper's tau, x = X / l_e, ... scaled by the scene's sine "
                           "excitation (a file written dimensionless is drawn so anyway)")
    plot.add_argument("--units", metavar="UNITS",
                      help="units drawn: 'engineering' (mm, mm/s, kN) or a list such as "
                           "'mm,kN' or 'cm,kN' (default: the file's, SI)")
    sweep = plot.add_argument_group(
        "sweep files", "A file written by pframe sweep gives one response spectrum: a response "
        "against a swept axis, one curve per building (contact, storey, node) or per value of "
        "another axis; other dimensions are fixed with --at or reduced to their largest value.")
    sweep.add_argument("--response", metavar="VARIABLE",
                       help="the response to draw (default: building_peak_displacement, or "
                            "the first the file holds)")
    sweep.add_argument("--x", metavar="AXIS", help="swept axis along x (default: the first)")
    sweep.add_argument("--curves", metavar="DIMENSION",
                       help="one curve per value of this dimension (default: the response's "
                            "building, contact, storey or node)")
    sweep.add_argument("--at", action="append", metavar="DIMENSION=VALUE",
                       help="fix a dimension at a value (repeatable), e.g. --at contact=floor-1")
    plot.add_argument("--statistic", choices=("median", "p84", "max"),
                      help="gap-audit files (pframe gap): the statistic over the records "
                           "drawn (default: p84); --at level=L picks the intensity level")
    plot.add_argument("--overwrite", action="store_true",
                      help="replace existing figure files (never the result, nor a device)")
    plot.add_argument("-q", "--quiet", action="store_true", help="print nothing on success")
    plot.set_defaults(run=_plot)
