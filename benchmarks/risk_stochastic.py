"""Risk runs under stochastic motions, end to end: N analyses of the paper's pair (8,000 steps
each), each under its own rezaeian2010 realisation generated here, against OpenSeesPy one by
one on a sample.

    python benchmarks/risk_stochastic.py [--runs 100000] [--batch 250] [--sample 5]
                                         [--threads T] [--no-overlap]

pframe
    Motion b is the rezaeian2010 realisation of seed b at a site of magnitude 6.5, R_rup
    20 km, Vs30 400 m/s, strike-slip (parameters sampled per realisation from the predictive
    relations), on its own step of 0.01 s (``pframe.excitation.stochastic.rezaeian_batch``,
    a chunk of motions at once). The analysis is the paper's pair (models/wu2021-eq14.yaml,
    improved Kelvin contacts at its gap) at dt = 0.001 s over 8,000 steps: the 8 s of the
    motion from max(0, t_mid - 4 s), its strong phase (a realisation lasts 10-60 s; 8,000
    steps of 1 ms, as benchmarks/risk_runs.py, keep the contacts resolved), scaled to a PGA
    drawn uniformly in 0.2-1.5 g (as risk_runs.py scales its record windows: an intensity
    range where most runs pound, so that the kernel's cost is that of pounding runs). A motion is
    generated only up to the end of its window (``until``: the same samples as the whole
    motion's, every filter being causal). Each chunk runs in one batch of the compiled kernel
    on threads (``pframe.risk.runs.run_batch``: critical gap, peak drift and absolute
    acceleration per building, impacts; running maxima only), while the next chunk's motions
    are generated on another thread (``--no-overlap``: one after the other). Memory is
    bounded by two chunks of motions. Printed: wall time of the whole (generation included),
    runs per second, CPU time of generation and of the kernel, peak resident memory, the load
    average before and after (the machine is shared: the figure depends on it).
OpenSees
    OpenSeesPy models linear contacts (ElasticPPGap) and Rayleigh damping on the initial
    stiffness, not the paper's improved Kelvin law with damping on the current stiffness. The
    ratio is therefore taken on the scene both model: the paper's pair's OpenSees twin
    (models/wu2021-eq14-linear.yaml: the same buildings, gaps and steps, linear contacts,
    initial-stiffness damping) on both sides, under the same ``--sample`` windows: OpenSees
    one analysis after another (the model of ``pframe.peers.opensees``, contacts included,
    recording the floor displacements), pframe the same runs in one batch, with contacts
    (recording what ``run_batch`` keeps). Each side's wall time per run, and their ratio.

Nothing is asserted: timings depend on the machine and on what else runs on it.
"""

from __future__ import annotations

import argparse
import os
import resource
import sys
import tempfile
import time
from concurrent.futures import ThreadPoolExecutor
from pathlib import Path

import numpy as np
from _common import KELVIN, LINEAR, load_average, opensees_unavailable, print_header

STEPS, DT = 8000, 0.001
MOTION_STEP = 0.01
SITE = {"magnitude": 6.5, "distance": 20.0, "vs30": 400.0, "mechanism": "strike_slip"}
WINDOW = STEPS * DT
PGA_G = (0.2, 1.5)  # each window scaled to a PGA drawn in this range (g), as in risk_runs.py
G = 9.80665


def window_start(params) -> float:
    """The analysis window's start in the motion (s): its strong phase around t_mid."""
    return max(0.0, params.tmid - 0.5 * WINDOW)


def motions(lo: int, hi: int) -> tuple[np.ndarray, float]:
    """The ground accelerations (hi - lo, STEPS + 1) on the analysis grid of the realisations
    of seeds lo..hi-1, and the CPU time of this thread to make them."""
    from pframe.excitation.stochastic import RezaeianParameters, rezaeian_batch

    cpu = time.thread_time()
    batch = rezaeian_batch(range(lo, hi), MOTION_STEP, SITE,
                           until=lambda p: window_start(p) + WINDOW + MOTION_STEP)
    grid = np.arange(STEPS + 1) * DT
    grounds = np.empty((hi - lo, STEPS + 1))
    pga = np.random.default_rng(lo).uniform(*PGA_G, hi - lo) * G
    for b, m in enumerate(batch):
        start = window_start(RezaeianParameters(**m.parameters))
        grounds[b] = np.interp(start + grid, m.times, m.acceleration, right=0.0)
        grounds[b] *= pga[b] / max(float(np.max(np.abs(grounds[b]))), 1e-12)
    return grounds, time.thread_time() - cpu


def peak_rss_mb() -> float:
    return resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024.0  # kB on Linux


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--runs", type=int, default=100_000)
    parser.add_argument("--batch", type=int, default=250)
    parser.add_argument("--sample", type=int, default=5, help="OpenSees analyses timed")
    parser.add_argument("--threads", type=int, default=None, help="kernel threads")
    parser.add_argument("--no-overlap", action="store_true",
                        help="generate each chunk's motions before its runs, not beside them")
    args = parser.parse_args(argv)
    from pframe.gap.runs import contact_pairs
    from pframe.reader import load_scene
    from pframe.risk.runs import run_batch

    print_header()
    loaded = load_scene(KELVIN)
    pairs = contact_pairs(loaded)
    warm, _ = motions(10**9, 10**9 + 2)  # imports and the kernel loaded before the clock
    run_batch(loaded, pairs, warm, STEPS, DT, contacts=True, threads=args.threads)

    load_before = load_average()
    chunks = [(lo, min(lo + args.batch, args.runs)) for lo in range(0, args.runs, args.batch)]
    generation_cpu = solve = 0.0
    pounding = 0
    g_req = np.empty((args.runs, len(pairs.names)))
    wall, cpu = time.perf_counter(), time.process_time()
    with ThreadPoolExecutor(1) as generator:
        pending = generator.submit(motions, *chunks[0]) if not args.no_overlap else None
        for k, (lo, hi) in enumerate(chunks):
            grounds, used = pending.result() if pending is not None else motions(lo, hi)
            generation_cpu += used
            if not args.no_overlap and k + 1 < len(chunks):
                pending = generator.submit(motions, *chunks[k + 1])
            out = run_batch(loaded, pairs, grounds, STEPS, DT, contacts=True,
                            threads=args.threads)
            solve += float(out["solve_seconds"])
            pounding += int((out["impacts"].sum(axis=1) > 0).sum())
            g_req[lo:hi] = out["g_req"]
            del grounds, out
    wall, cpu = time.perf_counter() - wall, time.process_time() - cpu
    rate = args.runs / wall
    print(f"pframe, {args.runs} runs x {STEPS} steps under stochastic motions (generation "
          f"included{'' if args.no_overlap else ', beside the kernel'}), batches of "
          f"{args.batch}: {wall:.1f} s wall ({wall / 60:.2f} min), {rate:.0f} runs/s; "
          f"10^5 runs {'took' if args.runs == 100_000 else 'projected'} "
          f"{1e5 / rate / 60:.1f} min")
    print(f"  CPU {cpu:.0f} s ({cpu / args.runs * 1e3:.2f} ms/run) on {os.cpu_count()} CPUs, of "
          f"which generating the motions {generation_cpu:.0f} s "
          f"({generation_cpu / args.runs * 1e3:.2f} ms/run); kernel wall {solve:.0f} s; "
          f"{pounding} runs pound; median critical gap {np.median(g_req.max(axis=1)):.4f} m")
    print(f"  peak resident memory {peak_rss_mb():.0f} MB; load average before {load_before}, "
          f"after {load_average()}")
    return opensees_ratio(args, load_scene, contact_pairs, run_batch)


def opensees_ratio(args, load_scene, contact_pairs, run_batch) -> int:
    why_not = opensees_unavailable()
    if why_not is not None:
        print(f"OpenSeesPy not available ({why_not}); no ratio")
        return 0
    sys.path.insert(0, str(Path(__file__).parent))
    from gap_audit import _OpenSeesLoop

    from pframe.gap.runs import batch_plan
    from pframe.peers.from_plan import peer_scene

    twin = load_scene(LINEAR)
    pairs = contact_pairs(twin)
    grounds, _ = motions(0, args.sample)
    gaps = np.tile([c.gap for c in twin.expanded.contacts], (args.sample, 1))
    plan = batch_plan(twin, grounds, STEPS, contacts_gaps=gaps, dt=DT)
    dof = dict(zip(plan.node_names, plan.node_dof))
    left = np.array([dof[n] for n in pairs.left])
    right = np.array([dof[n] for n in pairs.right])
    with tempfile.TemporaryDirectory(prefix="pframe-risk-bench-") as tmp:
        loop = _OpenSeesLoop(peer_scene(plan, 0), Path(tmp))
        timings = [loop.analysis(g, left, right)[3] for g in grounds]
    per_run = float(np.mean([t.wall for t in timings]))
    per_run_cpu = float(np.mean([t.cpu for t in timings]))
    # pframe on the same twin and windows, batched: repeated to a batch as large as the
    # benchmark's so that the cost per run is that of a batch, not of a handful
    reps = max(1, args.batch // args.sample)
    batch = np.tile(grounds, (reps, 1))
    run_batch(twin, pairs, batch[:2], STEPS, DT, contacts=True, threads=args.threads)
    wall, cpu = time.perf_counter(), time.process_time()
    run_batch(twin, pairs, batch, STEPS, DT, contacts=True, threads=args.threads)
    ours = (time.perf_counter() - wall) / len(batch)
    ours_cpu = (time.process_time() - cpu) / len(batch)
    print(f"the OpenSees twin (linear contacts, initial-stiffness damping) on both sides, "
          f"{args.sample} windows: OpenSeesPy one by one {per_run * 1e3:.0f} ms/run wall, "
          f"{per_run_cpu * 1e3:.0f} ms CPU; pframe batched {ours * 1e3:.2f} ms/run wall, "
          f"{ours_cpu * 1e3:.2f} ms CPU; ratio {per_run / ours:.0f}x wall, "
          f"{per_run_cpu / ours_cpu:.0f}x CPU (10^5 runs in OpenSeesPy: "
          f"{1e5 * per_run / 3600:.1f} h on one core); load average {load_average()}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
