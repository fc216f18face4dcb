"""A risk study on stochastic motions, end to end: the risk chain of docs/risk.md over N
variants of the paper's pair (8,000 steps each, one run without and one with contacts per
variant), motions, fits and file included; then the runs against OpenSeesPy one by one.

    python benchmarks/risk_stochastic.py [--variants 1000,10000] [--levels 10]
                                         [--threads T] [--bootstrap B] [--sample 5]
                                         [--no-opensees]

pframe
    ``pframe.risk`` of a study file written here: the paper's pair (models/wu2021-eq14.yaml,
    improved Kelvin contacts at its gap, Rayleigh damping on the current stiffness) on a step
    of 1 ms, ``duration: 8`` s (8,000 steps, which keep the contacts resolved, as
    benchmarks/risk_runs.py), under ``stochastic: rezaeian2010`` motions of a site of
    magnitude 6.5, R_rup 20 km, Vs30 400 m/s, strike-slip (each realisation's parameters
    sampled from the predictive relations), an msa design of ``--levels`` PGA stripes from
    0.2 to 1.5 g (realisations = variants / levels), ``pounding_runs: true``, two drift
    limits and an acceleration limit, a power-law hazard, a 475-year target and the gap's
    bootstrap (``--bootstrap``, default the study's 200), written to a netCDF file. Each size
    runs in a process of its own (its peak resident memory is its own), after an untimed
    run of 20 variants there (imports, the kernel loaded). Printed per size: the wall time
    of the whole call and of its parts (motions generated and the study opened; the runs;
    the fits, the gap curve and its bootstrap; the dataset and the file), the kernel's
    time, the CPU time of the process (and of the processes it starts), whole and by part
    (the measure that a loaded machine disturbs least), and how busy that
    keeps the CPUs (CPU / wall / CPUs: 1.0 is every CPU busy the whole time), peak resident
    memory, the load average before and after. Then 10^5 variants projected from the
    largest size: linearly (wall x 10^5 / N) and from the cost per variant between the two
    largest sizes (their difference, which leaves out the fixed costs).
OpenSees
    OpenSeesPy models linear contacts (ElasticPPGap) and Rayleigh damping on the initial
    stiffness, not the paper's improved Kelvin law with damping on the current stiffness. The
    ratio is therefore taken on the scene both model: the paper's pair's OpenSees twin
    (models/wu2021-eq14-linear.yaml: the same buildings, gaps and steps, linear contacts,
    initial-stiffness damping) on both sides, under ``--sample`` 8 s windows of the strong
    phase of such motions (scaled to a PGA drawn in 0.2-1.5 g): OpenSees one analysis after
    another (the model of ``pframe.peers.opensees``, contacts included, recording the floor
    displacements), pframe the same runs in one batch, with contacts (recording what
    ``pframe.risk.runs.run_batch`` keeps). Each side's wall time per run, and their ratio.

Nothing is asserted: timings depend on the machine and on what else runs on it (the load
average says how much).
"""

from __future__ import annotations

import argparse
import json
import os
import resource
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np
import yaml
from _common import KELVIN, LINEAR, load_average, opensees_unavailable, print_header

STEPS, DT = 8000, 0.001
MOTION_STEP = 0.01
SITE = {"magnitude": 6.5, "distance": 20.0, "vs30": 400.0, "mechanism": "strike_slip"}
WINDOW = STEPS * DT
PGA_G = (0.2, 1.5)  # the stripes span this range (g), as risk_runs.py scales its windows
G = 9.80665
TARGET = 10**5


def write_study(folder: Path, variants: int, levels: int, bootstrap: int | None) -> Path:
    """The study file (and its scene, the paper's pair on a 1 ms step) of ``variants``."""
    scene = yaml.safe_load(KELVIN.read_text(encoding="utf-8"))
    scene["analysis"].update(dt=DT, duration=WINDOW)
    (folder / "scene.yaml").write_text(yaml.safe_dump(scene, sort_keys=False), encoding="utf-8")
    study = {
        "scene": "scene.yaml",
        "stochastic": {"model": "rezaeian2010", **SITE,
                       "realisations": max(1, variants // levels), "seed": 0},
        "measure": "pga",
        "design": {"kind": "msa",
                   "levels": [round(float(x), 4) for x in np.linspace(*PGA_G, levels)]},
        "dt": DT, "duration": WINDOW, "pounding_runs": True,
        "limits": {"drift": {"IO": 0.05, "LS": 0.1}, "acceleration": {"A2": 1.5}},
        "hazard": {"power_law": {"k0": 1.0e-4, "k": 2.5}},
        "target": {"return_period": 475},
    }
    if bootstrap is not None:
        study["bootstrap"] = bootstrap
    path = folder / f"study-{variants}.yaml"
    path.write_text(yaml.safe_dump(study, sort_keys=False), encoding="utf-8")
    return path


def _cpu() -> float:
    """CPU seconds of this process and of its children that have ended (the processes the
    gap's bootstrap is shared among)."""
    children = resource.getrusage(resource.RUSAGE_CHILDREN)
    return time.process_time() + children.ru_utime + children.ru_stime


def child(study: Path, warm: Path, threads: int | None) -> None:
    """Run one study in this process and print its timings as JSON (the --child mode)."""
    import warnings

    import pframe.risk.study as study_module
    from pframe.risk import analysis as analysis_module
    from pframe.risk import output as output_module

    parts = {"open": 0.0, "runs": 0.0, "fits": 0.0, "file": 0.0}
    cpu_parts = dict(parts)

    def timed(module, name, part):
        original = getattr(module, name)

        def wrapper(*args, **kwargs):
            start, cpu = time.perf_counter(), _cpu()
            try:
                return original(*args, **kwargs)
            finally:
                parts[part] += time.perf_counter() - start
                cpu_parts[part] += _cpu() - cpu
        setattr(module, name, wrapper)

    timed(study_module, "open_study", "open")
    timed(study_module, "run_variants", "runs")
    timed(analysis_module, "analyse", "fits")
    timed(output_module, "build_dataset", "file")
    from pframe.record import netcdf

    timed(netcdf, "write_dataset", "file")
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        study_module.risk(warm, output=warm.with_suffix(".nc"), overwrite=True, threads=threads)
        for key in parts:
            parts[key] = cpu_parts[key] = 0.0
        load_before = load_average()
        timings: dict = {}
        wall, cpu = time.perf_counter(), _cpu()
        ds = study_module.risk(study, output=study.with_suffix(".nc"), overwrite=True,
                               threads=threads, timings=timings)
        wall, cpu = time.perf_counter() - wall, _cpu() - cpu
    impacts = ds["impact_count"].values
    pounding = float((impacts.sum(axis=-1) > 0).mean())
    print(json.dumps({
        "variants": int(timings["variants"]), "wall": wall, "cpu": cpu,
        "kernel": float(timings["solve_seconds"]), "parts": parts, "cpu_parts": cpu_parts,
        "rss_mb": resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024.0,
        "load_before": load_before, "load_after": load_average(), "pounding": pounding,
        "contact_runs": int(timings.get("contact_runs", 0)),
        "gap_mm": float(ds["gap_at_target"]) * 1e3 if "gap_at_target" in ds else float("nan"),
    }))


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--variants", default="1000,10000",
                        help="study sizes, comma-separated (variants = records x levels)")
    parser.add_argument("--levels", type=int, default=10)
    parser.add_argument("--threads", type=int, default=None, help="kernel threads")
    parser.add_argument("--bootstrap", type=int, default=None,
                        help="record resamples of the gap's interval (default: the study's)")
    parser.add_argument("--sample", type=int, default=5, help="OpenSees analyses timed")
    parser.add_argument("--no-opensees", action="store_true")
    parser.add_argument("--child", nargs=2, help=argparse.SUPPRESS)
    args = parser.parse_args(argv)
    if args.child:
        child(Path(args.child[0]), Path(args.child[1]), args.threads)
        return 0
    print_header()
    sizes = [int(v) for v in args.variants.split(",")]
    cpus = os.cpu_count() or 1
    done = []
    with tempfile.TemporaryDirectory(prefix="pframe-risk-study-") as tmp:
        folder = Path(tmp)
        warm = write_study(folder, 2 * args.levels, args.levels, args.bootstrap)
        for size in sizes:
            study = write_study(folder, size, args.levels, args.bootstrap)
            command = [sys.executable, __file__, "--child", str(study), str(warm)]
            if args.threads:
                command += ["--threads", str(args.threads)]
            if args.bootstrap is not None:
                command += ["--bootstrap", str(args.bootstrap)]
            out = subprocess.run(command, capture_output=True, text=True, check=False)
            if out.returncode != 0:
                print(f"{size} variants failed:\n{out.stderr[-2000:]}")
                return 1
            r = json.loads(out.stdout.strip().splitlines()[-1])
            done.append(r)
            p = r["parts"]
            print(f"pframe risk, {r['variants']} variants (x 2 runs of {STEPS} steps): "
                  f"{r['wall']:.1f} s wall = open (motions) {p['open']:.1f} + runs "
                  f"{p['runs']:.1f} (kernel {r['kernel']:.1f}) + fits {p['fits']:.1f} + file "
                  f"{p['file']:.1f}; {r['wall'] / r['variants'] * 1e3:.2f} ms/variant")
            c = r["cpu_parts"]
            print(f"  CPU {r['cpu']:.1f} s = open {c['open']:.1f} + runs {c['runs']:.1f} + fits "
                  f"{c['fits']:.1f} + file {c['file']:.1f} on {cpus} CPUs: busy "
                  f"{r['cpu'] / r['wall'] / cpus:.2f}"
                  f" of them; peak resident memory {r['rss_mb']:.0f} MB; "
                  f"{r['pounding']:.0%} of the runs with contacts pound, "
                  f"{r['contact_runs']} of them integrated (the others never close a gap: "
                  "their runs without contacts are reused); gap at target "
                  f"{r['gap_mm']:.1f} mm; load average before {r['load_before']}, after "
                  f"{r['load_after']}")
    big = done[-1]
    linear = big["wall"] * TARGET / big["variants"]
    line = (f"10^5 variants projected: {linear:.0f} s ({linear / 60:.1f} min) from "
            f"{big['variants']} x {TARGET // big['variants']}")
    if len(done) > 1 and done[-1]["variants"] > done[-2]["variants"]:
        a, b = done[-2], done[-1]
        per = (b["wall"] - a["wall"]) / (b["variants"] - a["variants"])
        fixed = b["wall"] - per * b["variants"]
        line += (f"; {fixed + per * TARGET:.0f} s ({(fixed + per * TARGET) / 60:.1f} min) from "
                 f"the cost per variant between {a['variants']} and {b['variants']} "
                 f"({per * 1e3:.2f} ms) and the fixed cost ({fixed:.1f} s)")
    print(line + " (goal: 180 s)")
    if args.no_opensees:
        return 0
    return opensees_ratio(args)


def windows(lo: int, hi: int) -> np.ndarray:
    """The ground accelerations (hi - lo, STEPS + 1): the 8 s strong phase (from
    max(0, t_mid - 4 s)) of the realisations of seeds lo..hi-1, each scaled to a PGA drawn
    uniformly in PGA_G (the windows where most runs pound, so that the kernel's cost is that
    of pounding runs)."""
    from pframe.excitation.stochastic import RezaeianParameters, rezaeian_batch

    def start(p):
        return max(0.0, p.tmid - 0.5 * WINDOW)

    batch = rezaeian_batch(range(lo, hi), MOTION_STEP, SITE,
                           until=lambda p: start(p) + WINDOW + MOTION_STEP)
    grid = np.arange(STEPS + 1) * DT
    grounds = np.empty((hi - lo, STEPS + 1))
    pga = np.random.default_rng(lo).uniform(*PGA_G, hi - lo) * G
    for b, m in enumerate(batch):
        grounds[b] = np.interp(start(RezaeianParameters(**m.parameters)) + grid, m.times,
                               m.acceleration, right=0.0)
        grounds[b] *= pga[b] / max(float(np.max(np.abs(grounds[b]))), 1e-12)
    return grounds


def opensees_ratio(args) -> int:
    why_not = opensees_unavailable()
    if why_not is not None:
        print(f"OpenSeesPy not available ({why_not}); no ratio")
        return 0
    sys.path.insert(0, str(Path(__file__).parent))
    from gap_audit import _OpenSeesLoop

    from pframe.gap.runs import batch_plan, contact_pairs
    from pframe.peers.from_plan import peer_scene
    from pframe.reader import load_scene
    from pframe.risk.runs import run_batch

    twin = load_scene(LINEAR)
    pairs = contact_pairs(twin)
    grounds = windows(0, args.sample)
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
    # pframe on the same twin and windows, batched: repeated to a batch of 250 so that the
    # cost per run is that of a batch, not of a handful
    batch = np.tile(grounds, (max(1, 250 // args.sample), 1))
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
