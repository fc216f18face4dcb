"""``pframe solve MODEL.yaml``: run a scene and write its results (netCDF-4, docs/netcdf.md)."""

from __future__ import annotations

import sys
from pathlib import Path


def _solve(args) -> int:
    from pframe.api import check_output
    from pframe.model import load_scene

    loaded = load_scene(args.model)
    out = check_output(Path(Path(args.model).stem + ".nc") if args.output is None
                       else args.output, args.overwrite, loaded)

    from pframe.assemble import assemble
    from pframe.kernel import simulate
    from pframe.progress import bar
    from pframe.record import ResultWriter

    plan = assemble(loaded.expanded)
    for warning in plan.warnings:
        print(f"pframe: warning: {loaded.source}: {warning}", file=sys.stderr)
    if not args.quiet:
        from pframe.commands.validate import record_lines

        for line in record_lines(loaded):
            print(f"{loaded.source}: {line}", flush=True)
    on_terminal = sys.stderr.isatty() and not args.quiet
    progress = bar(False if args.quiet else None, "steps")
    announce = ((lambda message: print(f"pframe: {message}", file=sys.stderr, flush=True))
                if on_terminal else None)
    # The histories go to the (temporary) file as they are computed, not held in memory; on
    # any error or Ctrl-C the temporary file is removed and nothing is written.
    with ResultWriter(out, plan, loaded, track=_PEAKS, compress=args.compress,
                      call=getattr(args, "command_line", None)) as writer:
        try:
            result = simulate(plan, progress=progress, announce=announce, sink=writer.append)
        finally:
            if progress is not None:
                progress.close()
        writer.finish(result)
    if not args.quiet:
        _summary(loaded, plan, result, out, writer.peaks)
    if not result.completed():
        print(f"pframe: {loaded.source}: the run stopped early: {result.describe_failure()}; "
              f"{out} holds the {result.states_done() - 1} steps computed, marked incomplete",
              file=sys.stderr)
        return 1
    return 0


#: the quantities whose peaks the summary prints
_PEAKS = ("displacement", "story_drift", "contact_force")


def _summary(loaded, plan, result, out: Path, streamed: dict | None = None):
    """What the run did; peaks come from the envelopes, else from the histories (``streamed``:
    the running peaks per column that the writer kept of the streamed histories)."""
    import numpy as np

    dt = float(plan.dt[0])
    print(f"{loaded.source}: {plan.steps} steps of dt = {dt:.4g} s ({plan.steps * dt:.4g} s), "
          f"{len(plan.node_names)} nodes, {len(plan.story_names)} storeys, "
          f"{len(plan.contact_names)} contacts")
    peaks = {}
    for q in _PEAKS:
        if q in result.envelope:
            peaks[q] = result.envelope[q][0]
        elif streamed and q in streamed:
            peaks[q] = streamed[q]
        elif q in result.history:
            peaks[q] = np.nanmax(np.abs(result.history[q][0]), axis=0)
    if "displacement" in peaks:
        values = peaks["displacement"][plan.node_dof]
        for b in plan.buildings:
            idx = [i for i, n in enumerate(plan.node_names) if n.split("/")[0] == b]
            top = max(idx, key=lambda i: values[i])
            print(f"  building {b}: peak displacement {values[top]:.4g} m at {plan.node_names[top]}")
    if "story_drift" in peaks:
        s = int(np.argmax(peaks["story_drift"]))
        print(f"  peak storey drift {peaks['story_drift'][s]:.4g} m at {plan.story_names[s]}")
    for c, name in enumerate(plan.contact_names):
        force = f", peak force {peaks['contact_force'][c]:.4g} N" if "contact_force" in peaks else ""
        print(f"  contact {name}: {int(result.impacts[0, c])} impacts{force}")
    print(f"  status: {result.describe_failure()}; energy balance error "
          f"{result.energy_error():.2e}")
    print(f"  solve {result.solve_seconds:.3f} s ({result.iterations[0]} Newton solves), "
          f"kernel compile/load {result.compile_seconds:.2f} s; wrote {out}")


def register(sub) -> None:
    solve = sub.add_parser("solve", help="run a scene and write its results (netCDF-4)")
    solve.add_argument("model", help="scene file (YAML)")
    solve.add_argument("-o", "--output", help="result file (default: MODEL's name with .nc)")
    solve.add_argument("--overwrite", action="store_true", help="replace an existing output")
    solve.add_argument("--compress", action="store_true",
                       help="deflate the histories (shuffle + gzip: about 2/3 of the size, "
                            "several times the kernel's time to write)")
    solve.add_argument("-q", "--quiet", action="store_true", help="print nothing on success")
    solve.set_defaults(run=_solve)
