"""``pframe gap SCENE.yaml [--suite ...]``: code minimum separations beside the simulated
no-pounding gap, over a suite of records scaled to intensity levels."""

from __future__ import annotations

import sys
import warnings
from pathlib import Path


def _levels(text: str) -> list[float]:
    from pframe.errors import InputError

    try:
        return [float(x) for x in text.replace(",", " ").split()]
    except ValueError:
        raise InputError(f"--levels {text}: write intensities in g separated by commas, e.g. "
                         "--levels 0.1,0.2,0.4") from None


def table(ds, statistic: str = "median") -> str:
    """The terminal table: per level and contact, each rule's separation (mm) at one
    statistic over the records, and the pounding fraction when a gap was given."""
    from pframe.record.netcdf import short_units

    rules = [str(r) for r in ds.rule_name.values]
    widths = [max(13, len(r) + 1) for r in rules]  # the code rules' names are longer
    head = f"{'level':>8} {'contact':<12}" + "".join(f"{r:>{w}}" for r, w in zip(rules, widths))
    gap = "provided_gap" in ds
    if gap:
        head += f"{'pound':>8}"
    lines = [f"{statistic} over {ds.sizes['record']} records, separations in mm"
             + (f"; provided gap {1000 * float(ds.provided_gap):.1f} mm" if gap else ""), head,
             "-" * len(head)]
    stats = ds.gap_statistics.sel(statistic_name=statistic)
    for level in ds.level.values:
        for contact in ds.contact_name.values:
            row = stats.sel(level=level, contact_name=contact)
            text = f"{level:>8.4g} {contact:<12}" + "".join(
                f"{1000 * float(row.sel(rule_name=r)):>{w}.1f}" for r, w in zip(rules, widths))
            if gap:
                text += f"{float(ds.pounding_fraction.sel(level=level, contact_name=contact)):>8.0%}"
            lines.append(text)
    if gap and ds.sizes["level"] > 1:
        median, beta = float(ds.fragility_median_any), float(ds.fragility_dispersion_any)
        lines.append(f"fragility of pounding at any contact: median {median:.4g} "
                     f"{short_units(ds.level.attrs.get('units', ''))}, dispersion {beta:.3g}"
                     if median == median else
                     "fragility: not fitted (no level where some but not all records pound)")
    return "\n".join(lines)


def _gap(args) -> int:
    from pframe.gap import audit

    if args.en_coincident:
        print("pframe: warning: --en-coincident is deprecated: --codes en1998 gives EN 1998-1 "
              "4.4.2.7 with the aligned floors decided from the storey heights (--aligned yes "
              "to assert them); --en-coincident still adds SRSS_EN_0.7", file=sys.stderr)

    suite = None
    if args.suite:
        suite = args.suite[0] if len(args.suite) == 1 else args.suite
    if args.output == "":
        from pframe.errors import InputError

        raise InputError("-o '': the audit file needs a name")
    output = Path(args.output) if args.output else Path(args.scene).with_suffix(".gap.nc")
    timings: dict = {}
    progress = None
    if not args.quiet and sys.stderr.isatty():
        def progress(done, total):
            sys.stderr.write(f"\r  pframe gap: {done:,.0f}/{total} runs ")
            sys.stderr.flush()
    from pframe.sweep.store import kept, parts_folder

    found = kept(output)
    if found and not args.quiet:
        print(f"pframe gap: resuming: {found} finished batch{'es' if found != 1 else ''} of "
              f"a stopped audit found in {parts_folder(output)} (taken up if they are this "
              "audit's; the other batches run now)", file=sys.stderr)
    try:
        with warnings.catch_warnings():  # printed below from the result, as pframe: warning
            warnings.simplefilter("ignore", UserWarning)
            ds = audit(args.scene, suite, gap=args.gap,
                       levels=_levels(args.levels) if args.levels else None,
                       measure=args.measure, en_coincident=args.en_coincident, codes=args.codes,
                       aligned=args.aligned,
                       duration=args.duration, dt=args.dt, records_folder=args.records_folder,
                       output=output, overwrite=args.overwrite, chunk=args.chunk,
                       threads=args.threads, progress=progress, timings=timings)
    except KeyboardInterrupt as exc:
        if progress is not None:
            sys.stderr.write("\n")  # off the progress line
        signum = getattr(exc, "signum", None)
        now = kept(output)
        what = "interrupted" if signum is None else f"stopped by signal {signum}"
        if not now:
            print(f"pframe: {what}; no output written", file=sys.stderr)
        else:
            print(f"pframe: {what}; {now} finished batch{'es' if now != 1 else ''} kept in "
                  f"{parts_folder(output)}, no audit file written: run the same command to "
                  "resume from them", file=sys.stderr)
        return 130 if signum is None else 128 + signum
    if progress is not None:
        sys.stderr.write("\n")
    for line in str(ds.attrs.get("warnings", "")).splitlines():
        print(f"pframe: warning: {args.scene}: {line}", file=sys.stderr)
    if not args.quiet:
        print(table(ds, args.statistic))
        failed = int((ds.complete == 0).sum())
        batches = -(-timings["variants"] // (args.chunk or timings["variants"]))
        print(f"{timings['variants']} runs x {timings['steps']} steps in "
              f"{'one batch' if batches == 1 else f'{batches} batches'}: "
              f"{timings['wall_seconds']:.1f} s ({timings['solve_seconds']:.1f} s kernel)"
              + (f"; {failed} runs failed (left out)" if failed else "") + f"; wrote {output}")
    return 1 if int((ds.complete == 0).sum()) else 0


def register(sub) -> None:
    from pframe.gap.codes import codes_help

    gap = sub.add_parser(
        "gap", help="how far apart two buildings must stand: code rules beside simulation",
        description="For each contact level of the scene and each record of a suite: the ABS, "
                    "SRSS and DDC minimum separations from the buildings' peak displacements "
                    "run without contact, the building codes' rules chosen with --codes, and "
                    "the simulated critical gap g_req = max over time "
                    "of (u_left - u_right); their median, 84th percentile and maximum over the "
                    "suite; with --gap, the fraction of records that pound and a lognormal "
                    "fragility over --levels. Writes a labelled file (netCDF4/HDF5) that "
                    "pframe plot draws. See docs/gap-audit.md.")
    gap.add_argument("scene", help="scene file (.yaml) with the two buildings and contacts")
    gap.add_argument("--suite", nargs="+", metavar="SUITE",
                     help="a suite file (.yaml), a folder of .AT2 records, or record files "
                          "(default: the scene's own excitation)")
    gap.add_argument("--records-folder", metavar="DIR",
                     help="where the records a suite file names are (default: beside it)")
    gap.add_argument("--gap", type=float, metavar="G", help="the gap provided (m)")
    gap.add_argument("--levels", metavar="L1,L2,...",
                     help="scale every record to each intensity (g) of --measure")
    gap.add_argument("--measure", metavar="pga|sa:T",
                     help="intensity measure of the levels: pga (default), sa:0.5 (Sa at "
                          "0.5 s, 5 %% damping) or sa:A (at building A's first period)")
    gap.add_argument("--en-coincident", action="store_true",
                     help="deprecated: add SRSS_EN_0.7 (0.7 x SRSS); use --codes en1998")
    gap.add_argument("--codes", metavar="CODE[:K=V...],...|RULES.yaml",
                     help="add the building codes' rules on the elastic peak displacements, "
                          "factors after the name (tbdy2018:R=6:I=1.2; R.B=6 for building B "
                          "alone), 'all' for every one, or a YAML file with rules of your own: "
                          + codes_help().replace("%", "%%")
                          + " (docs/gap-audit.md#code-rules)")
    gap.add_argument("--aligned", choices=("yes", "no"),
                     help="the two buildings' floors are (not) aligned, instead of the "
                          "decision from the storey heights (floors within 0.05 m up to the "
                          "lower roof)")
    gap.add_argument("--duration", type=float, metavar="S",
                     help="analysed time (s); default: the longest record plus three of the "
                          "longest first period")
    gap.add_argument("--dt", type=float, metavar="S",
                     help="time step of the record runs (default: the scene's; without "
                          "contacts a step that resolves the buildings' modes is enough)")
    gap.add_argument("--statistic", choices=("median", "p84", "max"), default="median",
                     help="statistic over the suite the table shows (default: median)")
    gap.add_argument("-o", "--output", metavar="OUT.nc",
                     help="result file (default: SCENE.gap.nc)")
    gap.add_argument("--overwrite", action="store_true", help="replace an existing result file")
    gap.add_argument("--chunk", type=int, metavar="N",
                     help="run N records x levels per batch, each saved as it finishes so "
                          "that a stopped audit resumes (default: all in one batch)")
    gap.add_argument("--threads", type=int, metavar="N", help="threads (default: one per CPU)")
    gap.add_argument("-q", "--quiet", action="store_true", help="print nothing on success")
    gap.set_defaults(run=_gap)
