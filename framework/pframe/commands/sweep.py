"""``pframe sweep SWEEP.yaml``: run every variant of a parametric study into one labelled file."""

from __future__ import annotations

import sys
import time
from pathlib import Path

from pframe.errors import InputError


class _Progress:
    """Variants done, rate and time left: a bar on a terminal (tqdm, sized to it), a plain
    line every ``every`` seconds (and at the end) otherwise."""

    def __init__(self, stream, tty: bool, every: float = 10.0):
        from pframe.progress import Bar

        self.stream = stream
        self.bar = Bar("variants", stream=stream) if tty else None
        self.every = every
        self.start = None  # (time, variants done) when this run started computing
        self.last_line = 0.0

    def __call__(self, done: int, total: int, failed: int):
        now = time.perf_counter()
        if self.start is None:
            self.start = (now, done)
            self.last_line = now
            if done:
                self._write(f"resuming: {done} of {total} variants already done", now)
            if self.bar is not None:
                self.bar(done, total, failed)
            return
        if self.bar is not None:
            self.bar(done, total, failed)
            return
        elapsed = now - self.start[0]
        rate = (done - self.start[1]) / elapsed if elapsed > 0 else 0.0
        left = (total - done) / rate if rate > 0 else float("nan")
        failures = f" ({failed} failed)" if failed else ""
        text = (f"{done}/{total} variants{failures}, {rate:,.2f} variants/s, "
                + (f"{left:.0f} s left" if done < total else f"{elapsed:.1f} s"))
        if done == total or now - self.last_line >= self.every:
            self._write(text, now)

    def _write(self, text, now):
        self.last_line = now
        self.stream.write(f"pframe sweep: {text}\n")
        self.stream.flush()

    def close(self):
        if self.bar is not None:
            self.bar.close()


def _existing_digest(path: Path) -> str | None:
    import h5py

    try:
        with h5py.File(path, "r") as f:
            value = f.attrs.get("sweep_digest")
    except OSError:
        return None
    return value.decode() if isinstance(value, bytes) else (str(value) if value is not None else None)


def _show_variant(definition, index: int) -> int:
    import yaml

    from pframe.sweep import parse
    from pframe.sweep.variants import materialise, steps_override, variant_data

    spec = parse(definition)
    if not 0 <= index < spec.count:
        raise InputError(f"--variant {index}: the sweep has variants 0 to {spec.count - 1}")
    paths = {key: path for _, _, key, path in definition.records}
    # under records, its duration follows its record (docs/sweeps.md)
    steps = steps_override(spec, index, materialise(definition))
    data = variant_data(spec, index, record_path=lambda key: paths[key], steps=steps)
    print(f"# variant {index} of {definition.source}: {spec.describe(index)}")
    print(f"# base scene: {definition.base_source or '(inline)'}; record files as absolute paths")
    sys.stdout.write(yaml.safe_dump(data, sort_keys=False))
    return 0


def _sweep(args) -> int:
    from pframe.sweep import load_sweep, parse

    definition = load_sweep(args.sweep, chunk=args.chunk)
    if args.variant is not None:
        return _show_variant(definition, args.variant)
    if args.threads is not None and args.threads < 1:
        raise InputError(f"--threads {args.threads}: give at least 1")
    spec = parse(definition)
    from pframe import outputs

    out = Path(args.output if args.output is not None else Path(args.sweep).stem + ".nc")
    if args.output == "":
        raise InputError("-o '': the sweep file needs a name")
    from pframe.api import sweep_inputs

    outputs.check_output(out, inputs=sweep_inputs(definition), overwrite=True,
                         what="sweep file")
    _check_resources(spec, out, args.quiet)
    from pframe.sweep.store import parts_folder

    if out.exists() and not parts_folder(out).exists():
        if _existing_digest(out) == definition.digest and not args.overwrite:
            if not args.quiet:
                print(f"{out}: already holds this sweep, complete; nothing to do "
                      "(--overwrite runs it again)")
            return 0
        if not args.overwrite:
            raise InputError(f"{out}: the output file exists; pass --overwrite to replace it, "
                             "or choose another name with -o")

    from pframe.sweep import run_sweep

    say = (lambda text: None) if args.quiet else (lambda text: print(text, file=sys.stderr))
    axes = ", ".join(f"{a.name}: {len(a.values)}" for a in spec.axes)
    where = f" on the Dask cluster at {args.scheduler}" if args.scheduler else ""
    say(f"pframe sweep: {args.sweep}: {spec.count} variants ({spec.model.combine} of {axes}) "
        f"in {_plural(spec.chunks, 'chunk')} of up to {definition.chunk}{where}")
    from pframe.sweep.store import kept

    found = kept(out)
    if found:
        say(f"pframe sweep: resuming: {_plural(found, 'finished chunk')} of an earlier run "
            f"found in {parts_folder(out)} (taken up if they are this sweep's; the other "
            "chunks run now)")
    progress = None if args.quiet else _Progress(sys.stderr, sys.stderr.isatty())
    try:
        run = run_sweep(definition, out, restart=args.overwrite, threads=args.threads,
                        scheduler=args.scheduler, progress=progress,
                        call=getattr(args, "command_line", None))
    except KeyboardInterrupt as exc:
        if progress is not None:
            progress.close()
        signum = getattr(exc, "signum", None)
        finished = kept(out)
        print(f"pframe: {'interrupted' if signum is None else f'stopped by signal {signum}'}; "
              + (f"{_plural(finished, 'finished chunk')} of {spec.chunks} kept in "
                 f"{parts_folder(out)}, no sweep file written: run the same command to resume "
                 "from them" if finished else "no chunk had finished: nothing kept, no sweep "
                 "file written"), file=sys.stderr)
        return 130 if signum is None else 128 + signum
    finally:
        if progress is not None:
            progress.close()
    for warning in _warnings(out):
        print(f"pframe: warning: {args.sweep}: {warning}", file=sys.stderr)
    if not args.quiet:
        _summary(run, spec)
    if run.untrusted:
        named = ", ".join(f"variant {i} ({spec.describe(i)})" for i in run.untrusted[:3])
        more = f" and {len(run.untrusted) - 3} more" if len(run.untrusted) > 3 else ""
        print(f"pframe: warning: {args.sweep}: {len(run.untrusted)} of {run.count} variants "
              f"completed but are not to be trusted (their energy balance; the file's "
              f"'trusted' variable is 0 for them): {named}{more}", file=sys.stderr)
    if run.failed:
        first = ", ".join(f"variant {i} ({spec.describe(i)}): {why}" for i, why in run.failed[:3])
        more = f" and {len(run.failed) - 3} more" if len(run.failed) > 3 else ""
        print(f"pframe: {args.sweep}: {len(run.failed)} of {run.count} variants failed "
              f"(marked in {out}: complete = 0, status says why): {first}{more}", file=sys.stderr)
        return 1
    return 0


def _check_resources(spec, out: Path, quiet: bool) -> None:
    """Refuse a sweep that cannot fit (memory per chunk, result file, variant count); warn
    about a very large one. Sweeps keep each chunk's histories in memory."""
    import shutil

    from pframe import resources
    from pframe.sweep.output import base_run

    run = base_run(spec)
    estimate = resources.estimate(
        run.steps, len(run.node_names), len(run.story_names), len(run.contact_names),
        spec.recorders, streaming=False, variants=spec.count,
        batch=min(spec.count, spec.definition.chunk))
    try:
        free = shutil.disk_usage(out.parent).free
    except OSError:
        free = None
    for warning in resources.check(estimate, spec.definition.source, free_disk=free):
        if not quiet:
            print(f"pframe: warning: {spec.definition.source}: {warning}", file=sys.stderr)


def _warnings(path: Path) -> list[str]:
    """The warnings a sweep file keeps (its variants' plans': restitution, time step)."""
    import h5py

    try:
        with h5py.File(path, "r") as f:
            text = f.attrs.get("warnings", "")
    except OSError:
        return []
    text = text.decode() if isinstance(text, bytes) else str(text)
    return [line for line in text.splitlines() if line]


def _plural(count: int, noun: str) -> str:
    return f"{count} {noun}{'' if count == 1 else 's'}"


def _summary(run, spec):
    resumed = f", {run.resumed_chunks} of them from an earlier run" if run.resumed_chunks else ""
    print(f"{spec.definition.source}: {_plural(run.count, 'variant')} in "
          f"{_plural(run.chunks, 'chunk')}{resumed}; "
          f"{run.count - len(run.failed)} completed, {len(run.failed)} failed")
    lines = run.duration_lines(spec.describe)
    if spec.base_record is not None or len(lines) > 1:  # records: each runs its own length
        print("  time analysed: " + "; ".join(lines))
    if run.variant_steps:
        computing = max(run.wall_seconds - run.compile_seconds, 1e-9)
        print(f"  {run.wall_seconds:.2f} s wall, of which kernel compile/load "
              f"{run.compile_seconds:.2f} s; {run.variant_steps:,} variant-steps in "
              f"{computing:.2f} s: {computing / run.variant_steps * 1e9:,.0f} ns per "
              f"variant-step (kernel time summed over threads {run.solve_seconds:.2f} s); "
              f"wrote {run.output}")
    else:
        print(f"  {run.wall_seconds:.2f} s; wrote {run.output}")


def register(sub) -> None:
    sweep = sub.add_parser(
        "sweep", help="run the variants of a parametric study into one labelled result file",
        description="Run every variant of a sweep file (a base scene and the numbers to vary: "
                    "gaps, yield drifts, excitations, Pi numbers, record files) as batches of "
                    "the compiled kernel, and write one netCDF4-compatible file whose "
                    "dimensions are the sweep axes. Finished chunks are kept beside the output "
                    "(OUT.nc.parts/): a sweep that was stopped continues where it stopped when "
                    "the same command is run again. See docs/sweeps.md.")
    sweep.add_argument("sweep", help="sweep file (YAML)")
    sweep.add_argument("-o", "--output", help="result file (default: SWEEP's name with .nc)")
    sweep.add_argument("--overwrite", action="store_true",
                       help="replace an existing output, and discard finished chunks of a "
                            "different sweep")
    sweep.add_argument("--chunk", type=int, metavar="N",
                       help="variants per chunk (default: the sweep file's chunk, else 64)")
    sweep.add_argument("--threads", type=int, metavar="N",
                       help="threads on this machine (default: one per CPU)")
    sweep.add_argument("--scheduler", metavar="tcp://HOST:PORT",
                       help="run the chunks on this Dask distributed scheduler's workers "
                            '(needs pip install "pframe[cluster]")')
    sweep.add_argument("--variant", type=int, metavar="I",
                       help="print variant I's scene (YAML for pframe solve) and exit")
    sweep.add_argument("-q", "--quiet", action="store_true",
                       help="print nothing but errors (no progress)")
    sweep.set_defaults(run=_sweep)
