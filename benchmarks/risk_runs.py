"""Runs of a risk study: N analyses of the paper's pair (about 8,000 steps each) under varied
record windows, in batches of the compiled kernel on threads, against OpenSeesPy one by one.

    python benchmarks/risk_runs.py [--runs 2000] [--batch 250] [--sample 5] [--threads T]
                                   [--records-folder ../shared/records]

pframe
    ``pframe.risk.runs.run_batch`` (what ``pframe risk`` runs per chunk): the paper's pair
    (models/wu2021-eq14.yaml) with its improved Kelvin contacts at its gap, dt = 0.001 s,
    8,000 steps (8 s), each run under an 8 s window of a PEER record starting at a random
    time and scaled to a random PGA in 0.2-1.5 g; kept per run: critical gap, peak drift and
    absolute acceleration per building, impacts. Also the same runs without contacts. Wall
    time of all batches (assembly included), runs per second, and the projection to 10^5 runs.
OpenSees
    ``--sample`` of the no-contact runs, one after another, in OpenSeesPy with the model of
    ``pframe.peers.opensees`` (as benchmarks/gap_audit.py); their mean time scaled to the
    same N and to 10^5 (sampled and scaled: not all run). OpenSees without contacts is a lower
    bound of its cost with them.

Nothing is asserted: timings depend on the machine and on what else runs on it.
"""

from __future__ import annotations

import argparse
import sys
import tempfile
import time
from pathlib import Path

import numpy as np
from _common import KELVIN, REPO, load_average, opensees_unavailable, print_header

STEPS, DT = 8000, 0.001


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--runs", type=int, default=2000)
    parser.add_argument("--batch", type=int, default=250)
    parser.add_argument("--sample", type=int, default=5)
    parser.add_argument("--threads", type=int, default=None)
    parser.add_argument("--records-folder", type=Path,
                        default=(REPO / ".." / "shared" / "records").resolve())
    args = parser.parse_args(argv)
    from pframe.excitation.suite import folder_records, suite_from_files
    from pframe.gap.runs import contact_pairs
    from pframe.reader import load_scene
    from pframe.risk.runs import run_batch

    print_header()
    suite = suite_from_files(folder_records(args.records_folder))
    rng = np.random.default_rng(0)
    times = np.arange(STEPS + 1) * DT
    grounds = np.empty((args.runs, STEPS + 1))
    for k in range(args.runs):
        m = suite.motions[rng.integers(len(suite.motions))]
        start = rng.uniform(0, max(m.duration - STEPS * DT, 0.0))
        a = m.on_grid(times + start)
        grounds[k] = a * rng.uniform(0.2, 1.5) * 9.80665 / max(np.max(np.abs(a)), 1e-12)
    loaded = load_scene(KELVIN)
    pairs = contact_pairs(loaded)
    run_batch(loaded, pairs, grounds[:2], STEPS, DT, contacts=True, threads=args.threads)
    rates = {}
    for contacts in (True, False):
        wall = time.perf_counter()
        impacts = 0
        for lo in range(0, args.runs, args.batch):
            out = run_batch(loaded, pairs, grounds[lo:lo + args.batch], STEPS, DT,
                            contacts=contacts, threads=args.threads)
            impacts += int((out["impacts"].sum(axis=1) > 0).sum())
        wall = time.perf_counter() - wall
        rates[contacts] = args.runs / wall
        print(f"pframe {'with' if contacts else 'without'} contacts: {args.runs} runs x {STEPS} "
              f"steps in batches of {args.batch}: {wall:.1f} s, {rates[contacts]:.0f} runs/s; "
              f"10^5 runs projected {1e5 / rates[contacts] / 60:.1f} min"
              + (f"; {impacts} runs pound" if contacts else ""), flush=True)
    why_not = opensees_unavailable()
    if why_not is not None:
        print(f"OpenSeesPy not available ({why_not}); no ratio")
        return 0
    sys.path.insert(0, str(Path(__file__).parent))
    from gap_audit import _OpenSeesLoop

    from pframe.gap.runs import batch_plan
    from pframe.peers.from_plan import peer_scene

    picks = rng.choice(args.runs, args.sample, replace=False)
    plan = batch_plan(loaded, grounds[picks], STEPS, dt=DT)
    dof = dict(zip(plan.node_names, plan.node_dof))
    left = np.array([dof[n] for n in pairs.left])
    right = np.array([dof[n] for n in pairs.right])
    from pframe.errors import InputError

    try:
        peer = peer_scene(plan, 0)
    except InputError as exc:
        print(f"OpenSeesPy: no ratio ({exc})")
        return 0
    with tempfile.TemporaryDirectory(prefix="pframe-risk-bench-") as tmp:
        loop = _OpenSeesLoop(peer, Path(tmp))
        walls = [loop.analysis(grounds[i], left, right)[3].wall for i in picks]
    per_run = float(np.mean(walls))
    print(f"OpenSeesPy without contacts, {args.sample} runs one by one (sampled and scaled): "
          f"{per_run * 1e3:.0f} ms/run, {1 / per_run:.1f} runs/s; 10^5 runs projected "
          f"{1e5 * per_run / 3600:.1f} h")
    print(f"ratio of runs per second, pframe / OpenSeesPy (no contacts on both): "
          f"{rates[False] * per_run:.0f}; pframe with contacts / OpenSeesPy without: "
          f"{rates[True] * per_run:.0f}  (load average {load_average()})")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
