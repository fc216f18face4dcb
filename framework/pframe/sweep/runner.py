"""Running a sweep: the chunks not yet finished, on this machine's threads or on a Dask
cluster, each saved as it finishes; then the result file from all of them.

Locally, ``threads`` worker threads each take the next chunk and run its batch in the kernel
(which releases the GIL), so a chunk's Python work (validating and assembling its variants)
overlaps another chunk's time stepping and no thread waits for a slow chunk. With a scheduler
address, chunks are tasks on a ``dask.distributed`` cluster: a pure function of the sweep
definition (which carries its record files) and the chunk's index; the results come back here
and are saved and written exactly as local ones. ``dask`` is imported only then.
"""

from __future__ import annotations

import os
import time
from concurrent.futures import FIRST_COMPLETED, ThreadPoolExecutor, wait
from dataclasses import dataclass, field
from pathlib import Path

from pframe.sweep.chunk import run_chunk, warm_up
from pframe.sweep.cluster import check as check_scheduler
from pframe.sweep.cluster import dask_client
from pframe.sweep.grid import parse
from pframe.sweep.output import write_sweep
from pframe.sweep.spec import SweepDefinition
from pframe.sweep.store import Parts


@dataclass
class SweepRun:
    """What a sweep did: counts, failures and timing (printed, never written to the file)."""

    output: Path
    count: int
    chunks: int
    resumed_chunks: int = 0
    failed: list = field(default_factory=list)  # (variant index, reason)
    untrusted: list = field(default_factory=list)  # completed variants the verdict rejects
    wall_seconds: float = 0.0
    solve_seconds: float = 0.0  # kernel time summed over chunks (over threads/workers)
    compile_seconds: float = 0.0
    variant_steps: int = 0  # steps integrated in this run (variants x steps)
    durations: object = None  # (count,) time analysed per variant (s), NaN if not run

    def duration_lines(self, describe, limit: int = 3) -> list[str]:
        """``80 s: 2 variants (record=b.AT2, ...)``, one line per distinct duration run."""
        if self.durations is None:
            return []
        import numpy as np

        values = np.asarray(self.durations, dtype=float)
        out = []
        for value in np.unique(values[np.isfinite(values)]):
            which = np.flatnonzero(values == value)
            named = ", ".join(describe(int(i)) for i in which[:limit])
            more = f", and {which.size - limit} more" if which.size > limit else ""
            out.append(f"{value:.6g} s: {which.size} variant{'s' if which.size > 1 else ''} "
                       f"({named}{more})")
        return out

    @property
    def completed(self) -> bool:
        return not self.failed


def run_sweep(definition: SweepDefinition, output: str | Path, *, restart: bool = False,
              threads: int | None = None, scheduler: str | None = None,
              progress=None, call: str | None = None) -> SweepRun:
    """Run the chunks of ``definition`` that ``OUT.parts`` does not hold yet, then write
    ``output``. ``progress(done, total, failed)`` is called as chunks finish (``done`` counts
    variants, including those of chunks finished by an earlier run)."""
    start = time.perf_counter()
    spec = parse(definition)
    output = Path(output)
    if scheduler is not None:  # a wrong address is said before anything is written
        scheduler = check_scheduler(scheduler, "chunks")
    parts = Parts(output, definition, spec)
    try:
        finished = parts.open(restart=restart)
        todo = [c for c in range(spec.chunks) if c not in finished]
        run = SweepRun(output, spec.count, spec.chunks, resumed_chunks=len(finished))
        done = sum(len(spec.chunk_range(c)) for c in finished)
        failed = 0

        def started():  # the kernel is compiled: the rate counts from here
            if progress is not None:
                progress(done, spec.count, failed)

        def finish(chunk, arrays):
            nonlocal done, failed
            parts.save(chunk, arrays)
            done += len(spec.chunk_range(chunk))
            failed += int((arrays["complete"] == 0).sum())
            run.solve_seconds += float(arrays["solve_seconds"])
            run.compile_seconds += float(arrays["compile_seconds"])
            run.variant_steps += int(arrays["steps_completed"].sum())
            if progress is not None:
                progress(done, spec.count, failed)

        if not todo:
            started()
        elif scheduler:
            _on_cluster(definition, todo, scheduler, started, finish, run)
        else:
            _on_threads(definition, todo, threads, started, finish, run)
        summary = write_sweep(output, spec, parts.load, call)
        parts.remove()
    finally:
        parts.close()
    run.failed = summary["failed"]
    run.untrusted = summary["untrusted"]
    run.durations = summary["durations"]
    run.wall_seconds = time.perf_counter() - start
    return run


def _on_threads(definition, todo, threads, started, finish, run: SweepRun):
    threads = max(1, threads or os.cpu_count() or 1)
    run.compile_seconds += warm_up(definition)
    started()
    workers = min(threads, len(todo))
    inner = max(1, threads // workers)  # few chunks left: each batch uses several threads
    pool = ThreadPoolExecutor(workers, thread_name_prefix="pframe-sweep")
    pending = {pool.submit(run_chunk, definition, chunk, inner): chunk for chunk in todo}
    try:
        while pending:
            finished, _ = wait(pending, return_when=FIRST_COMPLETED)
            for future in finished:
                finish(pending.pop(future), future.result())
    except BaseException:
        # Ctrl-C or a failed save: start nothing new. Under the pframe command the chunks
        # already running see the stop too (check_stop between variants, and in the kernel's
        # driver) and end at once with it, unsaved; one that finished meanwhile is saved, so
        # a second run continues after it.
        for future in pending:
            future.cancel()
        for future in list(pending):
            if not future.cancelled():
                try:
                    finish(pending[future], future.result())
                except BaseException:  # the stop, met by the chunk itself
                    pass
        raise
    finally:
        pool.shutdown(wait=True, cancel_futures=True)


def _on_cluster(definition, todo, address: str, started, finish, run: SweepRun):
    client = dask_client(address, "chunks")
    from distributed import as_completed

    with client:
        remote = client.scatter(definition, broadcast=True)
        # compile (or load) the kernel once per worker before chunks run side by side
        compile_seconds = client.run(warm_up, definition)
        run.compile_seconds += max(compile_seconds.values(), default=0.0)
        started()
        futures = {client.submit(run_chunk, remote, chunk, 1, retries=2, pure=False,
                                 key=f"pframe-sweep-{definition.digest}-{chunk}"): chunk
                   for chunk in todo}
        for future in as_completed(list(futures)):
            finish(futures[future], future.result())
