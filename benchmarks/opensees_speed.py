"""pframe against OpenSeesPy on the same scene with the same output: wall and CPU time.

    python benchmarks/opensees_speed.py [--steps N] [--repeats R] [--no-process]

Every ratio compares the same scene, models/wu2021-eq14-linear.yaml (two 3-storey bilinear
buildings, 3 linear contacts = OpenSees ElasticPPGap, Newmark average acceleration, Newton to
the same displacement-increment tolerance), and the same output: pframe runs a copy whose
recorders are exactly the four histories the OpenSees peer records at every step
(displacement, velocity, storey force, contact force).

In process: integrate a built model and write the four histories to a file
    pframe: ``simulate(plan, threads=1)`` then ``pframe.record.write_result`` (HDF5).
    OpenSees: ``ops.analyze(steps, dt)`` with the peer's four per-step binary recorders, then
    the ``ops.wipe()`` that flushes and closes their files (``pframe.peers.opensees.run``, with
    both calls timed from outside). Neither side's model building is timed.
Whole process
    ``pframe solve SCENE -o OUT.h5 --overwrite -q`` (kernel cache warmed by one untimed run)
    against the standalone OpenSeesPy script (``script_text``, run with this Python; it builds
    the model, analyses and saves the same four histories to .npz). Both include interpreter
    start-up and imports.

Each is measured R times, pframe and OpenSees interleaved, after one untimed run of each; the
median wall time and the median CPU time (``time.process_time`` in process; RUSAGE_CHILDREN of
a subprocess) are reported. pframe also runs models/wu2021-eq14.yaml (improved Kelvin contacts,
which stock OpenSees cannot model) with the same recorders: pframe-only rows, no ratio.

Ratios are OpenSees / pframe: above 1 means pframe is faster. Nothing is asserted; timings
depend on the machine (see benchmarks/README.md).
"""

from __future__ import annotations

import argparse
import contextlib
import sys
import tempfile
import time
from pathlib import Path

from _common import (
    KELVIN,
    LINEAR,
    PEER_RECORDERS,
    REPO,
    Timing,
    load_average,
    median_timing,
    opensees_script,
    opensees_unavailable,
    pframe_command,
    print_header,
    ratio,
    run_checked,
    scene_copy,
    seconds,
    table,
)

from pframe.assemble import assemble
from pframe.kernel import simulate
from pframe.peers.from_plan import peer_scene
from pframe.reader import load_scene
from pframe.record import write_result


class _PframeScene:
    """One scene run in process: simulate + write_result, timed."""

    def __init__(self, path: Path, out: Path):
        self.path, self.out = path, out
        self.loaded = load_scene(path)
        self.plan = assemble(self.loaded.expanded)
        self.timings: list[Timing] = []
        self.kernel: list[float] = []  # solve_seconds: the compiled kernel alone
        self.write: list[float] = []  # write_result alone

    def warm_up(self) -> tuple[float, int]:
        """(compile/load seconds, Newton solves) of an untimed first run."""
        result = simulate(self.plan, threads=1)
        if not result.completed():
            raise RuntimeError(f"{self.path.name}: {result.describe_failure()}")
        write_result(self.out, result, self.loaded)
        return result.compile_seconds, int(result.iterations[0])

    def measure(self) -> None:
        wall, cpu = time.perf_counter(), time.process_time()
        result = simulate(self.plan, threads=1)
        written = time.perf_counter()
        write_result(self.out, result, self.loaded)
        end = time.perf_counter()
        self.timings.append(Timing(end - wall, time.process_time() - cpu))
        self.kernel.append(result.solve_seconds)
        self.write.append(end - written)


@contextlib.contextmanager
def _analyze_timer():
    """Time each OpenSees ``analyze`` call together with the ``wipe`` after it (which flushes
    and closes the recorder files): yields the list the Timings are appended to."""
    import openseespy.opensees as ops

    analyze, wipe = ops.analyze, ops.wipe
    marks: list[Timing] = []
    started: list[tuple[float, float]] = []

    def timed_analyze(*args):
        started.append((time.perf_counter(), time.process_time()))
        return analyze(*args)

    def timed_wipe(*args):
        out = wipe(*args)
        if started:
            wall, cpu = started.pop()
            marks.append(Timing(time.perf_counter() - wall, time.process_time() - cpu))
        return out

    ops.analyze, ops.wipe = timed_analyze, timed_wipe
    try:
        yield marks
    finally:
        ops.analyze, ops.wipe = analyze, wipe


def _describe(label: str, timings: list[Timing]) -> str:
    t = median_timing(timings)
    return (f"  {label}: wall {t.wall:.4f} s, CPU {t.cpu:.4f} s (median of {len(timings)}; "
            f"wall from {min(x.wall for x in timings):.4f} to {max(x.wall for x in timings):.4f})")


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0],
                                     formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--steps", type=int, default=None,
                        help="time steps per run (default: the models' 50,000)")
    parser.add_argument("--repeats", type=int, default=5,
                        help="timed runs of each measurement, median kept (default 5)")
    parser.add_argument("--no-process", action="store_true",
                        help="skip the whole-process (subprocess) comparison")
    args = parser.parse_args(argv)
    if args.steps is not None and args.steps < 1:
        parser.error("--steps must be at least 1")
    if args.repeats < 1:
        parser.error("--repeats must be at least 1")

    print_header()
    print()
    why_not = opensees_unavailable()
    rows = []
    with tempfile.TemporaryDirectory(prefix="pframe-bench-") as tmp:
        folder = Path(tmp)
        linear_file = scene_copy(LINEAR, folder, args.steps, PEER_RECORDERS, "-peer-output")
        kelvin_file = scene_copy(KELVIN, folder, args.steps, PEER_RECORDERS, "-peer-output")
        linear = _PframeScene(linear_file, folder / "linear.h5")
        kelvin = _PframeScene(kelvin_file, folder / "kelvin.h5")
        plan = linear.plan
        steps, dt = plan.steps, float(plan.dt[0])
        print(f"scene: {LINEAR.name}, {steps} steps of dt = {dt:.6g} s, {plan.n_dof} DOFs, "
              f"{len(plan.contact_names)} linear contacts; both programs write the histories "
              f"{', '.join(PEER_RECORDERS[0]['quantities'])} at every step")
        print()

        # -- in process -----------------------------------------------------------------------
        print(f"in process: integrate and write the histories; {args.repeats} runs each, "
              "interleaved, after an untimed one")
        for scene in (linear, kelvin):
            compile_seconds, solves = scene.warm_up()
            print(f"  pframe {scene.path.name}: first call compiled/loaded the kernel in "
                  f"{compile_seconds:.2f} s; {solves} Newton solves per run")
        peer, os_marks = None, []
        if why_not is None:
            from pframe.peers.opensees import run

            peer = peer_scene(plan)
            run(peer)  # untimed
        else:
            print(f"  OpenSeesPy not available ({why_not}): OpenSees columns left empty")
        for _ in range(args.repeats):
            linear.measure()
            if peer is not None:
                with _analyze_timer() as marks:
                    run(peer)
                os_marks.extend(marks)
            kelvin.measure()
        print(_describe(f"pframe   simulate + write_result, {LINEAR.stem}", linear.timings))
        print(f"    of which kernel (solve_seconds) {min(linear.kernel):.4f} s best, HDF5 write "
              f"{min(linear.write):.4f} s best")
        if os_marks:
            print(_describe(f"OpenSees analyze + wipe,        {LINEAR.stem}", os_marks)
                  + f"; NormDispIncr {peer.tolerance:g} m")
        print(_describe(f"pframe   simulate + write_result, {KELVIN.stem} (pframe only)",
                        kelvin.timings))
        print(f"    of which kernel (solve_seconds) {min(kelvin.kernel):.4f} s best, HDF5 write "
              f"{min(kelvin.write):.4f} s best")
        pf, ko = median_timing(linear.timings), median_timing(kelvin.timings)
        os_t = median_timing(os_marks) if os_marks else None
        rows.append(("in process", LINEAR.stem, pf, os_t))
        rows.append(("in process", f"{KELVIN.stem} (pframe only)", ko, None))
        print()

        # -- whole process --------------------------------------------------------------------
        if args.no_process:
            print("whole process: skipped (--no-process)")
        else:
            print(f"whole process: wall and CPU time of a subprocess; {args.repeats} runs each, "
                  "interleaved, after an untimed one")
            cli = pframe_command()
            commands = {}
            if cli is None:
                print("  pframe CLI not available (no 'pframe solve' with --overwrite on PATH "
                      "or beside this Python): pframe columns left empty")
            else:
                commands["linear"] = [*cli, "solve", str(linear_file), "-o",
                                      str(folder / "linear-cli.h5"), "--overwrite", "-q"]
            if peer is not None:
                commands["opensees"] = opensees_script(linear_file, folder)
            if cli is not None:
                commands["kelvin"] = [*cli, "solve", str(kelvin_file), "-o",
                                      str(folder / "kelvin-cli.h5"), "--overwrite", "-q"]
            measured = {label: [] for label in commands}
            try:
                for command in commands.values():
                    run_checked(command, cwd=REPO)  # warms the kernel cache; untimed
                for _ in range(args.repeats):
                    for label, command in commands.items():
                        measured[label].append(run_checked(command, cwd=REPO))
            except RuntimeError as exc:
                print(f"  failed: {exc}")
                measured = {}
            names = {"linear": f"pframe solve {linear_file.name}",
                     "opensees": f"python opensees_peer.py ({linear_file.name})",
                     "kelvin": f"pframe solve {kelvin_file.name} (pframe only)"}
            for label, timings in measured.items():
                print(_describe(names[label], timings))
            result = {label: median_timing(t) for label, t in measured.items()}
            rows.append(("whole process", LINEAR.stem, result.get("linear"),
                         result.get("opensees")))
            rows.append(("whole process", f"{KELVIN.stem} (pframe only)", result.get("kelvin"),
                         None))
        print()

    header = ("", "scene", "pframe wall s", "pframe CPU s", "OpenSees wall s",
              "OpenSees CPU s", "OS/pf wall", "OS/pf CPU")
    cells = []
    for what, scene, pf_t, os_t in rows:
        cells.append((what, scene,
                      seconds(pf_t and pf_t.wall, 4), seconds(pf_t and pf_t.cpu, 4),
                      seconds(os_t and os_t.wall, 4), seconds(os_t and os_t.cpu, 4),
                      ratio(os_t and os_t.wall, pf_t and pf_t.wall),
                      ratio(os_t and os_t.cpu, pf_t and pf_t.cpu)))
    print(f"summary ({steps} steps; medians of {args.repeats}; output: the four histories at "
          "every step; OS/pf above 1: pframe faster):")
    for line in table(header, cells, left=2):
        print(line)
    print(f"load average (1, 5, 15 min) at the end: {load_average()}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
