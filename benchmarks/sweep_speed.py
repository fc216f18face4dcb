"""A 1,000-variant gap sweep: pframe's batched sweep against OpenSeesPy run once per variant,
on the same scene with the same output per variant.

    python benchmarks/sweep_speed.py [--variants 1000] [--sample 5] [--steps N] [--threads T]
                                     [--kelvin]

Scene and output (both sides)
    models/wu2021-eq14-linear.yaml (two 3-storey bilinear buildings, 3 linear contacts =
    OpenSees ElasticPPGap, 50,000 steps) with the gap of its three contacts swept from 0 to
    0.3 m. Each variant yields the sweep's default envelopes: peak displacement per floor,
    peak drift and ductility per storey, peak force and impact count per contact.
pframe
    ``pframe sweep`` as a subprocess (whole command: start-up, validation, every chunk, the
    result file), ``keep: {envelopes: [those five]}``; wall time and CPU time (RUSAGE_CHILDREN,
    every thread). The kernel is compiled or loaded beforehand by an untimed 2-variant sweep
    of the same scene.
OpenSees
    What a researcher's loop does: one OpenSeesPy analysis per variant, one after another, in
    one process. The peer's model (``build()`` of ``pframe.peers.opensees.script_text``) is
    rebuilt with each variant's gaps and analysed with the peer's settings (Newmark average
    acceleration, Newton, NormDispIncr); it records only what the five envelopes need (floor
    displacements and contact forces at every step, binary files) and reduces them to those
    envelopes. ``--sample`` variants spread over the gaps (points of pframe's own grid) are
    timed, wall (perf_counter) and CPU (process_time) for the whole variant, and scaled to
    ``--variants``; their envelopes are checked against pframe's.

Ratios are OpenSees (scaled) / pframe (measured): above 1 means pframe is faster. The CPU-time
ratio is the speed per core; the wall-time ratio is about that times the cores pframe used.
``--kelvin`` also times pframe's sweep of models/wu2021-eq14.yaml (improved Kelvin contacts,
no OpenSees counterpart): a pframe-only line. Nothing is asserted: timings depend on the
machine and on what else runs on it.
"""

from __future__ import annotations

import argparse
import os
import re
import shlex
import sys
import tempfile
import time
from pathlib import Path

import numpy as np
from _common import (
    KELVIN,
    LINEAR,
    Timing,
    load_average,
    opensees_unavailable,
    pframe_command,
    print_header,
    ratio,
    run_checked,
    run_timed,
    scene_copy,
    table,
)

GAPS = (0.0, 0.3)  # m; the models' gap is 0.124 m (Pi_d = 0.5)
ENVELOPES = ("peak_displacement", "peak_story_drift", "ductility", "peak_contact_force",
             "impact_count")


def _sweep_file(folder: Path, base: Path, variants: int, name: str) -> Path:
    path = folder / f"{name}.yaml"
    path.write_text(
        f"title: gap sweep of {base.name}\n"
        f"base: {base}\n"
        "axes:\n"
        f"  - {{name: gap, path: contacts.*.gap, linspace: [{GAPS[0]}, {GAPS[1]}, {variants}], "
        "units: m}\n"
        f"keep: {{envelopes: [{', '.join(ENVELOPES)}]}}\n", encoding="utf-8")
    return path


def _pframe_sweep(cli: list[str], sweep: Path, out: Path,
                  threads: int | None) -> tuple[Timing, str, list[str]]:
    """(wall and CPU time of the whole command, its report, the command)."""
    command = [*cli, "sweep", str(sweep), "-o", str(out), "--overwrite"]
    if threads:
        command += ["--threads", str(threads)]
    timing, done = run_timed(command)
    if done.returncode != 0:
        raise SystemExit(f"{shlex.join(command)} failed:\n{done.stderr}")
    return timing, done.stdout, command


class _OpenSeesLoop:
    """The OpenSees peer's model, rebuilt per variant, recording what the envelopes need."""

    def __init__(self, peer, folder: Path):
        from pframe.peers.opensees import script_text

        self.peer, self.folder = peer, folder
        path = folder / "opensees_peer.py"
        text = script_text(peer)
        path.write_text(text, encoding="utf-8")
        # defines build() and the scene's constants; the __main__ block does not run
        self.ns = {"__name__": "opensees_loop", "__file__": str(path)}
        exec(compile(text, str(path), "exec"), self.ns)
        self.story_nodes = np.asarray(peer.story_nodes, dtype=int).reshape(-1, 2)
        self.yield_drift = np.array([m[2] / m[1] if m[0] == "bilinear" else np.nan
                                     for m in peer.story_materials])

    def _read(self, path: Path, columns: int) -> np.ndarray:
        """Rows of a ``-binary -time`` recorder: time, ``columns`` doubles, a newline byte."""
        row = np.dtype([("values", "f8", (columns + 1,)), ("eol", "u1")])
        data = np.fromfile(path, dtype=row)
        if data.shape[0] != self.ns["STEPS"] or not np.all(data["eol"] == 10):
            raise RuntimeError(f"unexpected recorder layout in {path}")
        return data["values"][:, 1:]

    def variant(self, gap: float) -> tuple[dict, Timing, float]:
        """(envelopes, wall and CPU time of the whole variant, analyze + wipe seconds)."""
        ns, ops = self.ns, self.ns["ops"]
        wall, cpu = time.perf_counter(), time.process_time()
        ns["CONTACT_GAPS"] = [float(gap)] * len(ns["CONTACT_GAPS"])
        _, contacts, _ = ns["build"]()
        n = len(ns["MASSES"])
        displacement, force = self.folder / "displacement.bin", self.folder / "force.bin"
        ops.recorder("Node", "-binary", str(displacement), "-time", "-node",
                     *range(1, n + 1), "-dof", 1, "disp")
        ops.recorder("Element", "-binary", str(force), "-time", "-ele", *contacts, "basicForce")
        # the analysis commands of the peer's simulate() (pframe.peers.opensees), repeated
        # here; the envelopes' agreement with pframe's file checks that they still match
        ops.constraints("Plain")
        ops.numberer("RCM")
        ops.system("BandGeneral")
        ops.test("NormDispIncr", ns["TOL"], ns["MAX_ITER"])
        ops.algorithm("Newton")
        ops.integrator("Newmark", 0.5, 0.25)
        ops.analysis("Transient")
        start = time.perf_counter()
        status = ops.analyze(ns["STEPS"], ns["DT"])
        ops.wipe()  # flushes and closes the recorder files
        analyze = time.perf_counter() - start
        if status != 0:
            raise RuntimeError(f"OpenSees analyze failed (status {status}), gap {gap}")
        u = self._read(displacement, n)
        f = 0.0 - self._read(force, len(contacts))  # compression positive
        lower, upper = self.story_nodes[:, 0], self.story_nodes[:, 1]
        drift = u[:, upper] - np.where(lower >= 0, u[:, np.maximum(lower, 0)], 0.0)
        closed = np.vstack([np.zeros((1, f.shape[1]), bool), f > 0.0])  # at rest before step 1
        peak_drift = np.abs(drift).max(axis=0)
        out = {"peak_displacement": np.abs(u).max(axis=0),  # DOF order
               "peak_story_drift": peak_drift,
               "ductility": peak_drift / self.yield_drift,
               "peak_contact_force": np.abs(f).max(axis=0),
               "impact_count": (closed[1:] & ~closed[:-1]).sum(axis=0)}
        return out, Timing(time.perf_counter() - wall, time.process_time() - cpu), analyze


def _compare(path: Path, peer, index: int, opensees: dict) -> tuple[float, int]:
    """(largest relative difference of the peaks, impact counts that differ) between
    OpenSees' envelopes and pframe's sweep file at variant ``index``."""
    import h5py

    entities = {"node": peer.node_names, "story": peer.story_names,
                "contact": peer.contact_names}
    worst, impacts = 0.0, 0
    with h5py.File(path, "r") as f:
        for name in ENVELOPES:
            dim = {"peak_displacement": "node", "peak_story_drift": "story",
                   "ductility": "story"}.get(name, "contact")
            names = [b"".join(row).decode() for row in f[f"{dim}_name"][...]]  # char arrays
            order = [entities[dim].index(v) for v in names]
            ours = np.asarray(opensees[name])[order]
            theirs = f[name][index]
            if name == "impact_count":
                impacts += int(np.sum(ours != theirs))
                continue
            scale = np.maximum(np.abs(theirs), 1e-300)
            worst = max(worst, float(np.nanmax(np.abs(ours - theirs) / scale)))
    return worst, impacts


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--variants", type=int, default=1000, help="gaps swept (default 1000)")
    parser.add_argument("--sample", type=int, default=5,
                        help="OpenSees variants timed and scaled (default 5)")
    parser.add_argument("--steps", type=int, default=None,
                        help="steps per variant (default: the models' 50,000)")
    parser.add_argument("--threads", type=int, default=None,
                        help="pframe threads (default: one per CPU)")
    parser.add_argument("--kelvin", action="store_true",
                        help="also time pframe's sweep of the improved-Kelvin scene (pframe only)")
    args = parser.parse_args(argv)
    if args.variants < 2 or not 1 <= args.sample <= args.variants:
        parser.error("need --variants >= 2 and 1 <= --sample <= --variants")

    print_header()
    from pframe.assemble import assemble
    from pframe.peers.from_plan import peer_scene
    from pframe.reader import load_scene

    with tempfile.TemporaryDirectory(prefix="pframe-sweep-bench-") as tmp:
        folder = Path(tmp)
        linear = scene_copy(LINEAR, folder, args.steps)
        steps = load_scene(linear).expanded.steps
        variant_steps = args.variants * steps
        print(f"\nscene: {args.variants} variants of {LINEAR.name} (linear contacts), gap "
              f"{GAPS[0]} .. {GAPS[1]} m, {steps} steps each ({variant_steps:,} variant-steps); "
              f"output per variant: {', '.join(ENVELOPES)}")

        # -- pframe ---------------------------------------------------------------------------
        cli = pframe_command()
        if cli is None:
            raise SystemExit("pframe CLI not available (no 'pframe' with solve --overwrite)")
        warm = run_checked([*cli, "sweep", str(_sweep_file(folder, linear, 2, "warm-up")),
                            "-o", str(folder / "warm-up.h5"), "--overwrite", "-q"])
        print(f"\npframe: kernel compiled or loaded by an untimed 2-variant sweep "
              f"({warm.wall:.2f} s)")
        sweep = _sweep_file(folder, linear, args.variants, "gaps")
        pf, report, command = _pframe_sweep(cli, sweep, folder / "gaps.h5", args.threads)
        print("  " + shlex.join(command).replace(str(folder), "$TMP"))
        print("  " + report.strip().replace(str(folder), "$TMP").replace("\n", "\n  "))
        print(f"  whole command: wall {pf.wall:.2f} s = {pf.wall / variant_steps * 1e9:,.0f} ns "
              f"per variant-step; CPU {pf.cpu:.2f} s = {pf.cpu / variant_steps * 1e9:,.0f} ns "
              f"per variant-step ({pf.cpu / pf.wall:.2f} cores busy on average)")
        import h5py

        with h5py.File(folder / "gaps.h5", "r") as f:
            failed = int(np.asarray(f.attrs["variants_failed"]).item())
            impacts = f["impact_count"][...].sum(axis=1)
        print(f"  {failed} failed variants; impacts per variant from {impacts.min()} to "
              f"{impacts.max()}")
        kelvin = None
        if args.kelvin:
            kelvin_base = scene_copy(KELVIN, folder, args.steps)
            run_checked([*cli, "sweep", str(_sweep_file(folder, kelvin_base, 2, "warm-up-kelvin")),
                         "-o", str(folder / "warm-up-kelvin.h5"), "--overwrite", "-q"])
            kelvin_sweep = _sweep_file(folder, kelvin_base, args.variants, "gaps-kelvin")
            kelvin, _, _ = _pframe_sweep(cli, kelvin_sweep, folder / "gaps-kelvin.h5",
                                         args.threads)
            print(f"  pframe only, the same sweep of {KELVIN.name} (improved Kelvin): wall "
                  f"{kelvin.wall:.2f} s, CPU {kelvin.cpu:.2f} s")

        # -- OpenSees -------------------------------------------------------------------------
        why_not = opensees_unavailable()
        if why_not is not None:
            print(f"\nOpenSeesPy not available ({why_not}); no ratio")
            return 0
        gaps = np.linspace(GAPS[0], GAPS[1], args.variants)
        picks = np.unique(np.linspace(0, args.variants - 1, args.sample).round().astype(int))
        peer = peer_scene(assemble(load_scene(linear).expanded))
        loop = _OpenSeesLoop(peer, folder)
        print(f"\nOpenSees: {len(picks)} of the variants, one after another, in this process")
        timings, analyze, worst, mismatched = [], [], 0.0, 0
        for index in picks:
            envelopes, timing, seconds = loop.variant(float(gaps[index]))
            timings.append(timing)
            analyze.append(seconds)
            difference, impact_diff = _compare(folder / "gaps.h5", peer, int(index), envelopes)
            worst, mismatched = max(worst, difference), mismatched + impact_diff
            print(f"  gap {gaps[index]:.4f} m: whole variant wall {timing.wall:.3f} s, CPU "
                  f"{timing.cpu:.3f} s (analyze + wipe {seconds:.3f} s); "
                  f"{int(envelopes['impact_count'].sum())} impacts; largest relative "
                  f"difference from pframe's envelopes {difference:.1e}", flush=True)
        mean = Timing(float(np.mean([t.wall for t in timings])),
                      float(np.mean([t.cpu for t in timings])))
        os_t = Timing(mean.wall * args.variants, mean.cpu * args.variants)
        print(f"  mean per variant: wall {mean.wall:.3f} s, CPU {mean.cpu:.3f} s (analyze + wipe "
              f"{np.mean(analyze):.3f} s); scaled to {args.variants} variants: wall "
              f"{os_t.wall:,.1f} s, CPU {os_t.cpu:,.1f} s")
        print(f"  envelopes against pframe's: largest relative difference {worst:.1e}, "
              f"{mismatched} impact counts differ")

    def per_step(value: float) -> str:
        return f"{value / variant_steps * 1e9:,.0f}"

    print(f"\nsummary ({args.variants} variants x {steps} steps of {LINEAR.name}; the same five "
          "envelopes per variant on both sides):")
    header = ("", "wall s", "CPU s", "wall ns/variant-step", "CPU ns/variant-step")
    rows = [("pframe sweep (measured)", f"{pf.wall:,.1f}", f"{pf.cpu:,.1f}", per_step(pf.wall),
             per_step(pf.cpu)),
            (f"OpenSeesPy ({len(picks)} timed, scaled)", f"{os_t.wall:,.1f}", f"{os_t.cpu:,.1f}",
             per_step(os_t.wall), per_step(os_t.cpu)),
            ("OpenSees / pframe", ratio(os_t.wall, pf.wall), ratio(os_t.cpu, pf.cpu), "", "")]
    if kelvin is not None:
        rows.append((f"pframe sweep, {KELVIN.stem} (pframe only)", f"{kelvin.wall:,.1f}",
                     f"{kelvin.cpu:,.1f}", per_step(kelvin.wall), per_step(kelvin.cpu)))
    for line in table(header, rows):
        print("  " + line)
    print(f"  per core (CPU-time ratio): {ratio(os_t.cpu, pf.cpu)}; wall-time ratio "
          f"{ratio(os_t.wall, pf.wall)} with pframe keeping {pf.cpu / pf.wall:.2f} of "
          f"{os.cpu_count()} CPUs busy (OpenSees: {os_t.cpu / os_t.wall:.2f}); load average "
          f"(1, 5, 15 min) now {load_average()}")
    match = re.search(r"compile/load ([0-9.]+) s", report)
    if match:
        print(f"  (pframe's time includes its own start-up and a kernel load of {match.group(1)} s)")
    return 0


if __name__ == "__main__":
    sys.exit(main())
