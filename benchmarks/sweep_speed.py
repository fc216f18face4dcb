"""A 1,000-variant gap sweep: pframe's batched sweep against OpenSeesPy run once per variant.

    python benchmarks/sweep_speed.py [--variants 1000] [--sample 5] [--steps N] [--threads T]

pframe
    ``pframe sweep`` as a subprocess (wall time of the whole command: start-up, validation,
    every chunk, the result file) on a sweep of ``models/wu2021-eq14.yaml`` (improved Kelvin
    contacts, bilinear storeys, 50,000 steps) over the gap of its three contacts,
    ``contacts.*.gap`` from 0 to 0.3 m. The kernel is compiled (or loaded from the on-disk
    cache) once before the timed run, and the command's own report of its compile/load time
    is printed.
OpenSees
    What a researcher's script does today: one OpenSeesPy analysis per variant, one after
    another. OpenSees has no stock improved-Kelvin material, so it runs
    ``models/wu2021-eq14-linear.yaml`` (the same buildings, damping, excitation and steps with
    linear ``ElasticPPGap`` contacts, as benchmarks/opensees_speed.py does) with the same gaps.
    ``--sample`` variants spread over the gaps are run through ``pframe.peers.opensees.run``;
    the mean time of the ``analyze`` call alone (model building and output excluded, which
    favours OpenSees) is scaled to the number of variants.

The ratio is OpenSees (scaled) / pframe (measured): above 1 means pframe is faster. Nothing
is asserted: timings depend on the machine and on what else runs on it.
"""

from __future__ import annotations

import argparse
import dataclasses
import os
import re
import resource
import shlex
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np
from _common import machine_lines, shortened_model

REPO = Path(__file__).resolve().parents[1]
KELVIN = REPO / "models" / "wu2021-eq14.yaml"
LINEAR = REPO / "models" / "wu2021-eq14-linear.yaml"
GAPS = (0.0, 0.3)  # m; the models' gap is 0.124 m (Pi_d = 0.5)


def _pframe(sweep: Path, out: Path, threads: int | None) -> tuple[float, float, str, list[str]]:
    """(wall seconds, CPU seconds of the process, its report, the command)."""
    command = [str(Path(sys.executable).with_name("pframe")), "sweep", str(sweep), "-o",
               str(out), "--overwrite"]
    if not Path(command[0]).exists():
        command[:1] = [sys.executable, "-c", "import sys; from pframe.cli import main; "
                                             "sys.exit(main())"]
    if threads:
        command += ["--threads", str(threads)]
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    start = time.perf_counter()
    done = subprocess.run(command, capture_output=True, text=True)
    seconds = time.perf_counter() - start
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    cpu = (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)
    if done.returncode != 0:
        raise SystemExit(f"{shlex.join(command)} failed:\n{done.stderr}")
    return seconds, cpu, done.stdout, command


def _opensees(model: Path, gaps: np.ndarray) -> list[tuple[float, float, float, float]]:
    """(gap, analyze seconds, whole-variant seconds, whole-variant CPU seconds) of OpenSeesPy
    runs of ``model``."""
    from pframe.assemble import assemble, peer_scene
    from pframe.model import load_scene
    from pframe.peers.opensees import run

    expanded = load_scene(model).expanded
    out = []
    for gap in gaps:
        start, cpu = time.perf_counter(), time.process_time()
        contacts = tuple(dataclasses.replace(c, gap=float(gap)) for c in expanded.contacts)
        plan = assemble(dataclasses.replace(expanded, contacts=contacts))
        result = run(peer_scene(plan))
        out.append((float(gap), result["analyze_seconds"], time.perf_counter() - start,
                    time.process_time() - cpu))
        print(f"  OpenSees gap {gap:.4f} m: analyze {result['analyze_seconds']:.3f} s, "
              f"whole variant {out[-1][2]:.3f} s", flush=True)
    return out


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--variants", type=int, default=1000, help="gaps swept (default 1000)")
    parser.add_argument("--sample", type=int, default=5,
                        help="OpenSees runs timed and scaled (default 5)")
    parser.add_argument("--steps", type=int, default=None,
                        help="steps per variant (default: the models' 50,000)")
    parser.add_argument("--threads", type=int, default=None,
                        help="pframe threads (default: one per CPU)")
    args = parser.parse_args(argv)

    print("command: " + shlex.join([sys.executable, *sys.argv]))
    print("\n".join(machine_lines()))
    with tempfile.TemporaryDirectory(prefix="pframe-sweep-bench-") as tmp:
        folder = Path(tmp)
        kelvin = shortened_model(KELVIN, args.steps, folder)
        linear = shortened_model(LINEAR, args.steps, folder)
        sweep = folder / "gaps.yaml"
        sweep.write_text(
            f"title: gap sweep of {KELVIN.name}\n"
            f"base: {kelvin}\n"
            "axes:\n"
            f"  - {{name: gap, path: contacts.*.gap, linspace: [{GAPS[0]}, {GAPS[1]}, "
            f"{args.variants}], units: m}}\n", encoding="utf-8")
        from pframe.model import load_scene
        from pframe.sweep import load_sweep
        from pframe.sweep.chunk import warm_up

        steps = load_scene(kelvin).expanded.steps
        print(f"\npframe: {args.variants} variants of {kelvin.name} (improved Kelvin contacts), "
              f"gap {GAPS[0]} .. {GAPS[1]} m, {steps} steps each")
        print(f"  kernel compiled/loaded before timing in {warm_up(load_sweep(sweep)):.2f} s")
        seconds, cpu, report, command = _pframe(sweep, folder / "gaps.h5", args.threads)
        print("  " + shlex.join(command).replace(str(folder), "$TMP"))
        print("  " + report.strip().replace(str(folder), "$TMP").replace("\n", "\n  "))
        variant_steps = args.variants * steps
        per_step = seconds / variant_steps * 1e9
        print(f"  wall time of the whole command: {seconds:.2f} s = {per_step:,.0f} ns per "
              f"variant-step ({variant_steps:,} variant-steps); CPU time {cpu:.1f} s = "
              f"{cpu / variant_steps * 1e9:,.0f} ns per variant-step")
        import h5py

        with h5py.File(folder / "gaps.h5", "r") as f:
            failed = int(f.attrs["variants_failed"])
            impacts = f["impact_count"][...].sum(axis=1)
        print(f"  {failed} failed variants; impacts per variant from {impacts.min()} to "
              f"{impacts.max()}")

        try:
            import openseespy.opensees  # noqa: F401
        except Exception as exc:  # ImportError, or OSError for a missing liblapack
            print(f"\nOpenSeesPy not available ({type(exc).__name__}: {exc}); no ratio")
            return 0
        sample = np.linspace(GAPS[0], GAPS[1], args.sample)
        print(f"\nOpenSees: {args.sample} variants of {linear.name} (linear ElasticPPGap "
              f"contacts), the same gaps, {steps} steps each, one after another")
        runs = _opensees(linear, sample)
        analyze = float(np.mean([r[1] for r in runs]))
        whole = float(np.mean([r[2] for r in runs]))
        whole_cpu = float(np.mean([r[3] for r in runs]))
        scaled, scaled_whole = analyze * args.variants, whole * args.variants
        print(f"  mean analyze() {analyze:.3f} s per variant = {analyze / steps * 1e9:,.0f} ns "
              f"per step; scaled to {args.variants} variants: {scaled:,.0f} s "
              f"({scaled_whole:,.0f} s with model building and output)")

    print("\nsummary")
    print(f"  pframe sweep ({KELVIN.name}, {args.variants} variants, measured): {seconds:9.1f} s"
          f"  ({per_step:,.0f} ns per variant-step)")
    print(f"  OpenSeesPy  ({LINEAR.name}, {args.sample} timed, scaled):   {scaled:9.1f} s"
          f"  ({analyze / steps * 1e9:,.0f} ns per step, analyze only)")
    print(f"  ratio OpenSees / pframe: {scaled / seconds:.1f}x (analyze only), "
          f"{scaled_whole / seconds:.1f}x (whole variant)")
    print(f"  CPU time: OpenSees {whole_cpu * 1e9 / steps:,.0f} ns per step (whole variant), "
          f"pframe {cpu / variant_steps * 1e9:,.0f} ns per variant-step: "
          f"{whole_cpu * args.variants / cpu:.1f}x per core; the wall-time ratio reaches that "
          f"times the cores pframe gets ({os.cpu_count()} here when nothing else runs; load "
          f"average now {os.getloadavg()[0]:.2f})")
    match = re.search(r"compile/load ([0-9.]+) s", report)
    if match:
        print(f"  (pframe's time includes its own start-up and a kernel load of {match.group(1)} s)")
    return 0


if __name__ == "__main__":
    sys.exit(main())
