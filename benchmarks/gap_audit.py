"""A 100-record x 10-level gap audit of the paper's pair: ``pframe gap`` (one batch of the
compiled kernel) against OpenSeesPy running the same no-contact analyses one by one.

    python benchmarks/gap_audit.py [--records 100] [--levels 10] [--sample 5] [--dt 0.005]
                                   [--threads T] [--records-folder ../shared/records]

Scene and output (both sides)
    models/wu2021-eq14.yaml (two 3-storey bilinear buildings) without its contacts, at
    ``--dt``, under the PEER records of ``--records-folder`` (repeated to reach ``--records``
    records), each scaled to ``--levels`` PGA levels from 0.1 to 1.0 g: records x levels
    analyses of the longest record plus three first periods. Per analysis and contact level,
    both sides produce the peak displacements of the two floors and g_req = max over time of
    (u_left - u_right) (pframe also the ABS, SRSS and DDC rules, statistics and the file).
pframe
    ``pframe gap`` as a subprocess (whole command: start-up, reading the records, the response
    of every record, one batch of all analyses, the result file); wall time and CPU time
    (RUSAGE_CHILDREN, every thread). The kernel is loaded beforehand by an untimed one-record
    audit.
OpenSees
    What a script calling OpenSees does: one OpenSeesPy analysis per record and level, one
    after another, in one process, with the model of ``pframe.peers.opensees`` (Newmark
    average acceleration, Newton, NormDispIncr) and a binary recorder of the floor
    displacements, reduced to the same peaks and g_req. ``--sample`` analyses spread over the
    audit are timed (wall and CPU, the whole analysis) and scaled to all of them; their values
    are checked against pframe's file.

Ratios are OpenSees (scaled) / pframe (measured). Nothing is asserted: timings depend on the
machine and on what else runs on it.
"""

from __future__ import annotations

import argparse
import os
import shlex
import sys
import tempfile
import time
from pathlib import Path

import numpy as np
from _common import (
    KELVIN,
    REPO,
    Timing,
    load_average,
    opensees_unavailable,
    pframe_command,
    print_header,
    ratio,
    run_checked,
    run_timed,
    table,
)

SCENE = KELVIN  # the paper's pair; its contacts are removed by the audit


def _suite(folder: Path, records: Path, count: int) -> Path:
    files = sorted(p for p in records.iterdir() if p.suffix.lower() == ".at2")
    if not files:
        raise SystemExit(f"{records}: no .AT2 records")
    names = [files[i % len(files)] for i in range(count)]
    path = folder / "suite.yaml"
    path.write_text("records:\n" + "".join(f"  - {p}\n" for p in names), encoding="utf-8")
    return path


class _OpenSeesLoop:
    """The OpenSees peer's model of the scene without contacts, rebuilt per analysis with its
    ground motion, recording the floor displacements."""

    def __init__(self, peer, folder: Path):
        from pframe.peers.opensees import script_text

        self.folder = folder
        path = folder / "opensees_peer.py"
        text = script_text(peer)
        path.write_text(text, encoding="utf-8")
        self.ns = {"__name__": "opensees_loop", "__file__": str(path)}
        exec(compile(text, str(path), "exec"), self.ns)

    def analysis(self, ground: np.ndarray, left: np.ndarray, right: np.ndarray):
        """(peak |u| of left and right floors, g_req, wall and CPU time of the analysis)."""
        ns, ops = self.ns, self.ns["ops"]
        wall, cpu = time.perf_counter(), time.process_time()
        ns["AG"] = ground
        ns["build"]()
        n = len(ns["MASSES"])
        displacement = self.folder / "displacement.bin"
        ops.recorder("Node", "-binary", str(displacement), "-time", "-node", *range(1, n + 1),
                     "-dof", 1, "disp")
        ops.constraints("Plain")
        ops.numberer("RCM")
        ops.system("BandGeneral")
        ops.test("NormDispIncr", ns["TOL"], ns["MAX_ITER"])
        ops.algorithm("Newton")
        ops.integrator("Newmark", 0.5, 0.25)
        ops.analysis("Transient")
        status = ops.analyze(ns["STEPS"], ns["DT"])
        ops.wipe()
        if status != 0:
            raise RuntimeError(f"OpenSees analyze failed (status {status})")
        row = np.dtype([("values", "f8", (n + 1,)), ("eol", "u1")])
        u = np.fromfile(displacement, dtype=row)["values"][:, 1:]
        u = np.vstack([np.zeros((1, n)), u])  # at rest at t = 0
        peaks_left, peaks_right = np.abs(u[:, left]).max(axis=0), np.abs(u[:, right]).max(axis=0)
        g_req = np.maximum((u[:, left] - u[:, right]).max(axis=0), 0.0)
        return peaks_left, peaks_right, g_req, Timing(time.perf_counter() - wall,
                                                       time.process_time() - cpu)


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--records", type=int, default=100, help="records (default 100)")
    parser.add_argument("--levels", type=int, default=10, help="PGA levels (default 10)")
    parser.add_argument("--sample", type=int, default=5, help="OpenSees analyses timed")
    parser.add_argument("--dt", type=float, default=0.005, help="time step (s), default 0.005")
    parser.add_argument("--threads", type=int, default=None, help="pframe threads")
    parser.add_argument("--records-folder", type=Path,
                        default=(REPO / ".." / "shared" / "records").resolve(),
                        help="PEER .AT2 records (default ../shared/records)")
    args = parser.parse_args(argv)
    if not args.records_folder.is_dir():
        raise SystemExit(f"{args.records_folder}: no such folder of PEER records")

    print_header()
    levels = np.round(np.linspace(0.1, 1.0, args.levels), 4)
    count = args.records * args.levels
    with tempfile.TemporaryDirectory(prefix="pframe-gap-bench-") as tmp:
        folder = Path(tmp)
        suite = _suite(folder, args.records_folder, args.records)
        cli = pframe_command()
        if cli is None:
            raise SystemExit("pframe CLI not available")
        level_text = ",".join(f"{x:g}" for x in levels)
        warm = run_checked([*cli, "gap", str(SCENE), "--suite", str(_suite(folder, args.records_folder, 1)),
                            "--dt", str(args.dt), "-o", str(folder / "warm.h5"), "-q"])
        suite = _suite(folder, args.records_folder, args.records)
        out = folder / "audit.h5"
        command = [*cli, "gap", str(SCENE), "--suite", str(suite), "--dt", str(args.dt),
                   "--levels", level_text, "--gap", "0.1242451014414167", "-o", str(out)]
        if args.threads:
            command += ["--threads", str(args.threads)]
        pf, done = run_timed(command)
        if done.returncode not in (0, 1):
            raise SystemExit(f"{shlex.join(command)} failed:\n{done.stderr}")
        report = done.stdout.strip().splitlines()
        print(f"\npframe: kernel loaded by an untimed one-record audit ({warm.wall:.2f} s)")
        print("  " + shlex.join(command).replace(str(folder), "$TMP"))
        print("  " + report[-1].replace(str(folder), "$TMP"))
        import xarray as xr

        ds = xr.open_dataset(out, engine="h5netcdf").load()
        steps = int(ds.attrs["steps"])
        variant_steps = count * steps
        print(f"  {count} analyses x {steps} steps = {variant_steps:,} analysis-steps; wall "
              f"{pf.wall:.2f} s, CPU {pf.cpu:.2f} s ({pf.cpu / pf.wall:.2f} cores busy)")

        why_not = opensees_unavailable()
        if why_not is not None:
            print(f"\nOpenSeesPy not available ({why_not}); no ratio")
            return 0
        from pframe.gap.audit import prepare
        from pframe.gap.runs import batch_plan
        from pframe.peers.from_plan import peer_scene

        inputs = prepare(SCENE, suite, levels=list(levels), dt=args.dt)
        picks = np.unique(np.linspace(0, count - 1, args.sample).round().astype(int))
        grounds = inputs.accelerations(picks)
        plan = batch_plan(inputs.loaded, grounds, inputs.steps, dt=inputs.dt)
        loop = _OpenSeesLoop(peer_scene(plan, 0), folder)
        dof = dict(zip(plan.node_names, plan.node_dof))
        left = np.array([dof[n] for n in inputs.pairs.left])
        right = np.array([dof[n] for n in inputs.pairs.right])
        print(f"\nOpenSees: {len(picks)} of the {count} analyses, one after another")
        timings, worst = [], 0.0
        for k, index in enumerate(picks):
            r, j = divmod(int(index), args.levels)
            ul, ur, g, timing = loop.analysis(grounds[k], left, right)
            timings.append(timing)
            ours = np.concatenate([ul, ur, g])
            theirs = np.concatenate([ds.peak_displacement_left[r, j].values,
                                     ds.peak_displacement_right[r, j].values,
                                     ds.gap_required.sel(rule="simulated")[r, j].values])
            difference = float(np.max(np.abs(ours - theirs) / np.maximum(np.abs(theirs), 1e-300)))
            worst = max(worst, difference)
            print(f"  {ds.record.values[r]} at {levels[j]:g} g: wall {timing.wall:.3f} s, CPU "
                  f"{timing.cpu:.3f} s; largest relative difference from pframe's peaks and "
                  f"g_req {difference:.1e}", flush=True)
        mean = Timing(float(np.mean([t.wall for t in timings])),
                      float(np.mean([t.cpu for t in timings])))
        os_t = Timing(mean.wall * count, mean.cpu * count)

    def per_step(value: float) -> str:
        return f"{value / variant_steps * 1e9:,.0f}"

    print(f"\nsummary ({args.records} records x {args.levels} levels = {count} no-contact "
          f"analyses of {SCENE.name} at dt = {args.dt} s, {steps} steps each):")
    header = ("", "wall s", "CPU s", "wall ns/analysis-step", "CPU ns/analysis-step")
    rows = [("pframe gap (measured)", f"{pf.wall:,.1f}", f"{pf.cpu:,.1f}", per_step(pf.wall),
             per_step(pf.cpu)),
            (f"OpenSeesPy ({len(picks)} timed, scaled)", f"{os_t.wall:,.1f}", f"{os_t.cpu:,.1f}",
             per_step(os_t.wall), per_step(os_t.cpu)),
            ("OpenSees / pframe", ratio(os_t.wall, pf.wall), ratio(os_t.cpu, pf.cpu), "", "")]
    for line in table(header, rows):
        print("  " + line)
    print(f"  peaks and g_req against pframe's: largest relative difference {worst:.1e}; "
          f"{os.cpu_count()} CPUs; load average now {load_average()}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
