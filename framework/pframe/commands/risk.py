"""``pframe risk STUDY.yaml -o risk.nc``: a risk study from records to the gap at a target
annual frequency of pounding (docs/risk.md)."""

from __future__ import annotations

import sys
import warnings
from pathlib import Path


def _risk(args) -> int:
    from pframe.risk.output import summary
    from pframe.risk.study import risk
    from pframe.sweep.store import kept, parts_folder

    output = Path(args.output) if args.output else Path(args.study).with_suffix(".risk.nc")
    found = kept(output)
    if found and not args.quiet:
        print(f"pframe risk: resuming: {found} finished batch{'es' if found != 1 else ''} "
              f"found in {parts_folder(output)}", file=sys.stderr)
    progress = None
    if not args.quiet and sys.stderr.isatty():
        def progress(done, total):
            sys.stderr.write(f"\r  pframe risk: {done}/{total} runs " if total is not None
                             else f"\r  pframe risk: {done} runs (ida: hunt and fill) ")
            sys.stderr.flush()
    timings: dict = {}
    try:
        with warnings.catch_warnings():  # printed below from the result, as pframe: warning
            warnings.simplefilter("ignore", UserWarning)
            ds = risk(args.study, output=output, overwrite=args.overwrite,
                      records_folder=args.records_folder, threads=args.threads,
                      progress=progress, timings=timings, scheduler=args.scheduler)
    except KeyboardInterrupt:
        now = kept(output)
        print("pframe: interrupted; " + (f"{now} finished batches kept in "
              f"{parts_folder(output)}: run the same command to resume" if now else
              "no output written"), file=sys.stderr)
        return 130
    if progress is not None:
        sys.stderr.write("\n")
    for line in str(ds.attrs.get("warnings", "")).splitlines():
        print(f"pframe: warning: {args.study}: {line}", file=sys.stderr)
    if not args.quiet:
        print(summary(ds))
        kernel = timings["solve_seconds"]
        print(f"{timings['variants']} runs in {timings['wall_seconds']:.1f} s"
              + (f" ({kernel:.1f} s kernel)" if kernel == kernel else "") + f"; wrote {output}")
    if "complete" not in ds:  # subset simulation: failed runs count as pounding
        return 0
    return 1 if int((ds.complete.sel(condition_name="without_pounding") == 0).sum()) else 0


def register(sub) -> None:
    p = sub.add_parser(
        "risk", help="risk-based gap: fragilities, annual frequencies, gap at a target",
        description="Run a risk study (a YAML file: scene, record suite, analysis design, "
                    "limits, hazard curve, target): lognormal fragilities of pounding and of "
                    "demand limits with and without pounding, their mean annual frequencies, "
                    "and the gap whose annual frequency of pounding is the target, beside the "
                    "code rules. See docs/risk.md.")
    p.add_argument("study", help="study file (.yaml)")
    p.add_argument("--records-folder", metavar="DIR",
                   help="where the suite's records are (default: the study's records_folder, "
                        "else beside the suite)")
    p.add_argument("-o", "--output", metavar="OUT.nc", help="result file (default: "
                   "STUDY.risk.nc)")
    p.add_argument("--overwrite", action="store_true", help="replace an existing result file")
    p.add_argument("--threads", type=int, metavar="N",
                   help="threads of the runs and processes of the gap's bootstrap (default: "
                        "one per CPU)")
    p.add_argument("--scheduler", metavar="tcp://HOST:PORT",
                   help="run the batches on this Dask distributed scheduler's workers "
                        '(pip install "pframe[cluster]"); msa, grid ida and cloud designs')
    p.add_argument("-q", "--quiet", action="store_true", help="print nothing on success")
    p.set_defaults(run=_risk)
