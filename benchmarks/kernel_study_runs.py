"""The kernel's own time per step on the stochastic risk study's runs without contacts.

    python benchmarks/kernel_study_runs.py [--variants 40] [--repeats 7] [--rounds 5]
                                           [--baseline FOLDER] [--kept]

The batch is the one benchmarks/risk_stochastic.py's study runs first in each chunk: the
paper's pair (models/wu2021-eq14.yaml) without its contacts, on a 1 ms step for 8 s (8,000
steps), under ``--variants`` ``rezaeian2010`` motions of its site, with what
``pframe.risk.runs.prepare`` records (the envelopes of displacements, drifts, drift ratios
and absolute accelerations; the displacements' history streamed to a sink, as the study's
runs did before the kernel kept their critical gap: ``--kept``),
assembled by ``pframe.risk.study.free_batch`` as the study does. Timed: the C calls alone
(the CPU time of the thread that makes each call, summed over a run's calls: the Python
between calls and the sink are left out), per member and step; each side the best of
``--repeats`` runs, a run ``simulate`` of the batch in one thread.

``--baseline FOLDER``: the kernel's C sources of another revision (as in
benchmarks/kernel_limit.py), run alternately with the installed kernel in each round, in this
process under the same load; its envelopes, streamed histories, energy terms and counters are
compared with the kernel's, bit for bit (NaN alike: the drift ratios of storeys without a height).

``--kept``: the study's own path beside, in each round (``pframe.gap.runs.GapSink.run``: the
critical gap's running maximum kept by the kernel, no history streamed), its gaps compared
with the maxima of the streamed rows, and its envelopes and energies with theirs, to the bit.
Nothing is asserted.
"""

from __future__ import annotations

import argparse
import functools
import sys
import tempfile
import time
from pathlib import Path

import numpy as np
from _common import load_average, print_header
from kernel_limit import compile_baseline
from risk_stochastic import write_study


def study_batch(variants: int):
    """The study's scenes and batch without contacts (pframe.risk.study.free_batch)."""
    from pframe.risk.study import free_batch, open_study

    with tempfile.TemporaryDirectory(prefix="pframe-study-runs-") as tmp:
        opened = open_study(write_study(Path(tmp), variants, 10, None))
        return free_batch(opened.inputs, np.arange(variants))


class _Timed:
    """ckernel.run with the CPU time of its calls summed (the calling thread's)."""

    def __init__(self, ckernel):
        self.ckernel, self.original, self.seconds = ckernel, ckernel.run, 0.0

    def __call__(self, *args):
        start = time.thread_time()
        try:
            return self.original(*args)
        finally:
            self.seconds += time.thread_time() - start


def _keep(rows: list, name: str, first: int, block: np.ndarray) -> None:
    """The study's sink stand-in: the streamed displacement rows, kept."""
    rows.append(block.copy())


def run_side(batch, repeats: int, pairs=None) -> tuple[float, dict]:
    """The best ns per member and step of ``repeats`` runs, and the last run's numbers:
    the displacements streamed (kept whole), or with ``pairs`` (the scene's contacts) the
    study's path, the critical gap's running maximum kept by the kernel (GapSink.run)."""
    from pframe.gap.runs import GapSink
    from pframe.kernel import ckernel, simulate

    plan, best, out = batch.plan, np.inf, {}
    timed = _Timed(ckernel)
    ckernel.run = timed
    try:
        for _ in range(repeats):
            timed.seconds = 0.0
            rows: list[np.ndarray] = []
            if pairs is None:
                result = simulate(plan, threads=1, sink=functools.partial(_keep, rows))
            else:
                sink = GapSink(plan, pairs)
                result = sink.run(plan, threads=1)
            best = min(best, timed.seconds / (plan.batch * plan.steps) * 1e9)
            out = {**result.envelope, "energy": result.energy}
            if pairs is None:
                out["history"] = np.concatenate(rows, axis=1)
                out["counters"] = result.counters
            else:
                out["g_req"] = sink.gap
    finally:
        ckernel.run = timed.original
    return best, out


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--variants", type=int, default=40)
    parser.add_argument("--repeats", type=int, default=7)
    parser.add_argument("--rounds", type=int, default=5)
    parser.add_argument("--baseline", type=Path, default=None,
                        help="a folder of the kernel's C sources to run as the other side")
    parser.add_argument("--kept", action="store_true",
                        help="time the study's path beside (the critical gap kept by the kernel, "
                        "no history streamed) and compare its gaps with the streamed rows'")
    args = parser.parse_args(argv)
    print_header()
    scene, batch = study_batch(args.variants)
    plan = batch.plan
    print(f"{plan.batch} members, {plan.steps} steps, {plan.n_dof} DOFs, {plan.n_springs} "
          f"storeys, {len(plan.contact_names)} contacts")
    with tempfile.TemporaryDirectory(prefix="pframe-study-runs-") as tmp:
        library = None if args.baseline is None else compile_baseline(args.baseline, Path(tmp))
        run_side(batch, 1)  # the kernel loaded before the clock
        best, best_base, best_kept, ours, theirs, kept = np.inf, np.inf, np.inf, {}, {}, {}
        for k in range(args.rounds):
            ns, ours = run_side(batch, args.repeats)
            best = min(best, ns)
            line = f"round {k + 1}: kernel {ns:.1f} ns/step"
            if args.kept:
                from pframe.gap.runs import contact_pairs

                kept_ns, kept = run_side(batch, args.repeats, contact_pairs(scene))
                best_kept = min(best_kept, kept_ns)
                line += f", the gap kept in the kernel {kept_ns:.1f} ({kept_ns / ns:.3f})"
            if library is not None:
                from pframe.kernel import ckernel

                with ckernel.baseline(library):
                    base_ns, theirs = run_side(batch, args.repeats)
                best_base = min(best_base, base_ns)
                line += f", baseline {base_ns:.1f} ns/step, kernel / baseline {ns / base_ns:.3f}"
            print(f"{line}; load average {load_average()}", flush=True)
    print(f"best of all rounds: kernel {best:.1f} ns/step")
    if args.kept:
        u = ours["history"]
        streamed = np.stack([np.max(u[:, :, i] - u[:, :, j], axis=1)
                             for i, j in batch.sink.closing_dofs()], axis=1)
        same = np.array_equal(kept["g_req"], streamed) and all(
            np.array_equal(kept[q], ours[q], equal_nan=True) for q in kept if q != "g_req")
        print(f"the gap kept in the kernel: best {best_kept:.1f} ns/step, "
              f"{best_kept / best:.3f} of the streamed; critical gaps, envelopes and energies "
              f"{'identical' if same else 'DIFFERENT'} to the bit")
    if library is not None:
        same = all(np.array_equal(ours[q], theirs[q], equal_nan=True) for q in ours)
        print(f"baseline ({args.baseline}): best {best_base:.1f} ns/step, kernel / baseline "
              f"{best / best_base:.3f}; envelopes, histories, energies and counters "
              f"{'identical' if same else 'DIFFERENT'} to the bit")
    return 0


if __name__ == "__main__":
    sys.exit(main())
