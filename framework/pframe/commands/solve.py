"""``pframe solve MODEL.yaml``: run a scene and write its results (netCDF-4, docs/netcdf.md)."""

from __future__ import annotations

import sys
from pathlib import Path

from pframe.errors import InputError


def _solve(args) -> int:
    from pframe import outputs
    from pframe.api import check_output
    from pframe.reader import load_scene

    out = args.output if args.output is not None else Path(args.model).stem + ".nc"
    outputs.check_output(out, inputs=[args.model], overwrite=args.overwrite, what="result file")
    loaded = load_scene(args.model)
    out = check_output(out, args.overwrite, loaded)
    if args.summary is not None:
        from pframe.tables import check_summary_path

        check_summary_path(args.summary, args.overwrite, inputs=[args.model, out],
                           named_by="summary")
    _check_resources(loaded, out)

    from pframe.assemble import assemble
    from pframe.kernel import simulate
    from pframe.record import ResultWriter

    try:
        plan = assemble(loaded.expanded)
    except InputError as exc:  # found while assembling: damping fit, stability, batch rules
        raise InputError(f"{loaded.source}: {exc}") from None
    for warning in plan.warnings:
        print(f"pframe: warning: {loaded.source}: {warning}", file=sys.stderr)
    if not args.quiet:
        from pframe.commands.validate import record_lines

        for line in record_lines(loaded):
            print(f"{loaded.source}: {line}", flush=True)
    try:
        return _run(args, loaded, plan, out, simulate, ResultWriter)
    except OSError as exc:
        raise outputs.failure(out, exc) from None
    except InputError as exc:  # found while running: numbers beyond floating point
        raise InputError(f"{loaded.source}: {exc}") from None


def _check_resources(loaded, out: Path) -> None:
    """Refuse a run that cannot fit (memory, disk), warn about a very large one."""
    import shutil

    from pframe import resources

    try:
        free = shutil.disk_usage(out.parent).free
    except OSError:
        free = None
    estimate = resources.of_expanded(loaded.expanded, streaming=True)
    for warning in resources.check(estimate, loaded.source, free_disk=free):
        print(f"pframe: warning: {loaded.source}: {warning}", file=sys.stderr)


def _kept_elsewhere(out: Path) -> Path | None:
    """Where an incomplete result goes when ``out`` holds a complete one (None: to ``out``)."""
    import h5py

    try:
        with h5py.File(out, "r") as f:
            complete = bool(f.attrs.get("complete", 0))
    except (OSError, ValueError):
        return None
    return out.with_name(f"{out.stem}.incomplete{out.suffix}") if complete else None


def _run(args, loaded, plan, out: Path, simulate, ResultWriter) -> int:
    from pframe.progress import bar

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
        kept = ""
        if not result.completed() and out.exists():
            # an incomplete run never replaces a complete result
            elsewhere = _kept_elsewhere(out)
            if elsewhere is not None:
                from pframe import outputs

                outputs.check_output(elsewhere, overwrite=True, what="result file")
                kept = (f"; the complete result already in {out} is kept (an incomplete run "
                        "never replaces it)")
                writer.path = out = elsewhere
        writer.finish(result)
    from pframe.verdict import TRUSTED

    verdict = writer.verdict
    for warning in verdict.warnings:  # warnings are printed even with -q
        print(f"pframe: warning: {loaded.source}: {warning}", file=sys.stderr)
    if not args.quiet:
        _summary(loaded, plan, result, out, writer.peaks, verdict)
    if args.summary is not None:  # the summary table of the file written (pframe.tables)
        from pframe.tables import summary, write

        write(summary(out), args.summary, overwrite=args.overwrite, named_by="summary")
        if not args.quiet:
            print(f"  summary table: {args.summary}")
    if not result.completed():
        print(f"pframe: {loaded.source}: the run stopped early: {result.describe_failure()}; "
              f"{out} holds the {max(0, result.states_done() - 1)} steps computed, marked "
              f"incomplete{kept}",
              file=sys.stderr)
        return 1
    if args.strict and (plan.warnings or verdict.level != TRUSTED):
        print(f"pframe: {loaded.source}: the run's accuracy is in doubt ({verdict.level}, "
              f"{len(plan.warnings) + len(verdict.warnings)} warnings above) and --strict was "
              f"given; {out} is written", file=sys.stderr)
        return 4
    return 0


#: the quantities whose peaks the summary prints
_PEAKS = ("displacement", "story_drift", "contact_force", "link_force", "absolute_acceleration",
          "point_displacement")


def _summary(loaded, plan, result, out: Path, streamed: dict | None = None, verdict=None):
    """What the run did; peaks come from the envelopes, else from the histories (``streamed``:
    the running peaks per column that the writer kept of the streamed histories)."""
    import numpy as np

    from pframe.nondim.output import OutputUnits
    from pframe.units import SI

    if verdict is None:
        from pframe.verdict import of_result

        verdict = of_result(result)
    show = OutputUnits(system=loaded.system or SI).show  # in the scene's units
    dt = float(plan.dt[0])
    print(f"{loaded.source}: {plan.steps} steps of dt = {dt:.4g} s ({plan.steps * dt:.4g} s), "
          f"{len(plan.node_names)} nodes, {len(plan.story_names)} storeys, "
          f"{len(plan.contact_names)} contacts"
          + (f", {len(plan.link_names)} links" if plan.link_names else ""))
    for building, soil in zip(plan.foundations, plan.foundation_soil):
        print(f"  soil under {building}: {soil}")
    peaks = {}
    for q in _PEAKS:
        if q in result.envelope:
            peaks[q] = result.envelope[q][0]
        elif streamed and q in streamed:
            peaks[q] = streamed[q]
        elif q in result.history:
            peaks[q] = np.nanmax(np.abs(result.history[q][0]), axis=0)
    if not plan.planar:
        _plan_peaks(plan, peaks, show)
    elif "displacement" in peaks:
        values = peaks["displacement"][plan.node_dof]
        for b in plan.buildings:
            idx = [i for i, n in enumerate(plan.node_names) if n.split("/")[0] == b]
            top = max(idx, key=lambda i: values[i])
            print(f"  building {b}: peak displacement {show(values[top], 'm')} at "
                  f"{plan.node_names[top]}")
    if "absolute_acceleration" in peaks and plan.planar:
        values = peaks["absolute_acceleration"][plan.node_dof]
        for b in plan.buildings:
            idx = [i for i, n in enumerate(plan.node_names) if n.split("/")[0] == b]
            top = max(idx, key=lambda i: values[i])
            print(f"  building {b}: peak absolute floor acceleration "
                  f"{show(values[top], 'm/s^2')} at {plan.node_names[top]}")
    if "story_drift" in peaks:
        s = int(np.argmax(peaks["story_drift"]))
        print(f"  peak storey drift {show(peaks['story_drift'][s], 'm')} at "
              f"{plan.story_names[s]}")
        heights = (plan.story_height[0, :len(plan.story_names)] if plan.story_height is not None
                   else np.full(len(plan.story_names), np.nan))
        if np.any(np.isfinite(heights)):
            ratios = np.where(np.isfinite(heights), peaks["story_drift"] / heights, -np.inf)
            r = int(np.argmax(ratios))
            missing = [n for n, h in zip(plan.story_names, heights) if not np.isfinite(h)]
            without = (f"; not defined at {', '.join(missing[:4])}"
                       f"{' ...' if len(missing) > 4 else ''} (no height)" if missing else "")
            print(f"  peak drift ratio {100 * ratios[r]:.3g} % at {plan.story_names[r]} "
                  f"(height {show(heights[r], 'm')}){without}")
    if getattr(loaded.scene, "limits", None) is not None:
        from pframe.limits import evaluate

        for line in evaluate(loaded.expanded, plan, loaded.scene.limits,
                             result.envelope).lines():
            print(f"  {line}")
    shear = result.column_shear(0)
    for c, name in enumerate(plan.contact_names):
        force = (f", peak force {show(peaks['contact_force'][c], 'N')}"
                 if "contact_force" in peaks else "")
        if np.isfinite(shear[c]):
            capacity = plan.contact_capacity[c]
            force += (f"; floor-to-column: local column shear {show(shear[c], 'N')}"
                      + (f" (capacity {show(capacity, 'N')})" if np.isfinite(capacity) else ""))
        count = int(result.impacts[0, c])
        print(f"  contact {name}: {count} impact{'' if count == 1 else 's'}{force}")
    if plan.link_names:
        work = result.energy_terms(0)["links"]
        forces = peaks.get("link_force")
        for j, name in enumerate(plan.link_names):
            force = f": peak force {show(forces[j], 'N')}" if forces is not None else ""
            print(f"  link {name}{force}")
        print(f"  links: work {show(work, 'J')} (dissipated by their dampers and held in their "
              "springs at the end)")
    print(f"  status: {result.describe_failure()}; energy balance error "
          f"{verdict.balance_error:.2e}, numerical dissipation {verdict.algorithmic:.2e}: "
          f"{_verdict_words(verdict, plan)}")
    print(f"  solve {result.solve_seconds:.3f} s ({result.iterations[0]} Newton solves), "
          f"kernel compile/load {result.compile_seconds:.2f} s; wrote {out}")


def _plan_peaks(plan, peaks: dict, show) -> None:
    """Each building in plan's peak displacement of its centres of mass and of its named
    points (the critical locations), its peak rotation, and its storeys' torsion (``show``:
    a value in the scene's units, :meth:`pframe.nondim.output.OutputUnits.show`)."""
    import numpy as np

    buildings = {b: [i for i, n in enumerate(plan.node_names) if n.split("/")[0] == b]
                 for b in plan.buildings}
    words = ("along x", "along y", "rotation")
    for b, nodes in buildings.items():
        parts = []
        if "displacement" in peaks:
            best = {}  # component -> (value, node)
            for d in range(plan.n_dof):
                node, c = int(plan.dof_node[d]), int(plan.dof_component[d])
                if node in nodes and peaks["displacement"][d] > best.get(c, (-1.0, 0))[0]:
                    best[c] = (float(peaks["displacement"][d]), node)
            parts += [f"{show(value, 'rad' if c == 2 else 'm')} {words[c]} at "
                      f"{plan.node_names[node]}" for c, (value, node) in sorted(best.items())]
        if "point_displacement" in peaks and plan.point_names:
            values = np.asarray(peaks["point_displacement"]).reshape(-1, 2)
            mine = [p for p, name in enumerate(plan.point_names) if name.split("/")[0] == b]
            if mine:
                p, axis = np.unravel_index(int(np.argmax(values[mine])), (len(mine), 2))
                parts.append(f"{show(values[mine][p, axis], 'm')} along its {'xy'[axis]} axis at "
                             f"{plan.point_names[mine[p]]}")
        if parts:
            print(f"  building {b}: peak displacement " + "; ".join(parts))


def _verdict_words(verdict, plan) -> str:
    """The summary's word on accuracy: the energy verdict, in doubt also for the warnings
    made before the run (dt, inputs)."""
    from pframe.verdict import TRUSTED, UNTRUSTED

    if verdict.level == UNTRUSTED:
        return "NOT TO BE TRUSTED (see the warnings)"
    if verdict.level != TRUSTED or plan.warnings:
        return "in doubt (see the warnings)"
    return "balance closed"


def register(sub) -> None:
    solve = sub.add_parser("solve", help="run a scene and write its results (netCDF-4)")
    solve.add_argument("model", help="scene file (YAML)")
    solve.add_argument("-o", "--output", help="result file (default: MODEL's name with .nc)")
    solve.add_argument("--overwrite", action="store_true", help="replace an existing output")
    solve.add_argument("--compress", action="store_true",
                       help="deflate the histories (shuffle + gzip: about 2/3 of the size, "
                            "several times the kernel's time to write)")
    solve.add_argument("-q", "--quiet", action="store_true", help="print nothing on success")
    solve.add_argument("--strict", action="store_true",
                       help="exit 4 when the run completed but its accuracy is in doubt (any "
                            "warning: dt, inputs, energy balance); the result is still written")
    solve.add_argument("--summary", metavar="FILE",
                       help="also write the run's summary table, as FILE.csv or FILE.md "
                            "(peaks, ductility, impacts, energy balance, warnings)")
    solve.set_defaults(run=_solve)
