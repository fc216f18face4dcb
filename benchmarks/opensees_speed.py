"""pframe against OpenSeesPy, side by side in one run: kernel time and whole-process time.

    python benchmarks/opensees_speed.py [--steps N] [--repeats R]

Kernel
    pframe: ``simulate(plan).solve_seconds`` (the compiled kernel's time, compilation excluded;
    best of R after a warm-up run) on models/wu2021-eq14-linear.yaml (linear contacts) and on
    models/wu2021-eq14.yaml (improved Kelvin contacts).
    OpenSees: the time of the single ``ops.analyze(steps, dt)`` call (``analyze_seconds`` of
    ``pframe.peers.opensees.run``; best of 3) on the linear-contact scene, the only one of the
    two that stock OpenSees components can model (ElasticPPGap).

Whole process
    Wall time of ``pframe solve MODEL -o OUT.h5 --overwrite`` as a subprocess (kernel cache
    warmed by one untimed run) against the wall time of the standalone OpenSeesPy script
    (``script_text``, run with this Python) on the linear-contact scene; best of 3 each. Both
    include interpreter start-up, imports, model set-up, the run and writing the results.

Ratios are OpenSees / pframe: above 1 means pframe is faster. Nothing is asserted; timings
depend on the machine (see benchmarks/README.md).
"""

from __future__ import annotations

import argparse
import shlex
import shutil
import subprocess
import sys
import tempfile
import time
from pathlib import Path

from _common import machine_lines, shortened_model

from pframe.assemble import assemble, peer_scene
from pframe.kernel import simulate
from pframe.model import load_scene

REPO = Path(__file__).resolve().parents[1]
KELVIN = REPO / "models" / "wu2021-eq14.yaml"
LINEAR = REPO / "models" / "wu2021-eq14-linear.yaml"
OPENSEES_REPEATS = 3
PROCESS_REPEATS = 3


def _plan(path: Path):
    return assemble(load_scene(path).expanded)


def _kernel_seconds(plan, repeats: int) -> tuple[float, float, int]:
    """(best solve seconds, first-call compile/load seconds, Newton solves of one run)."""
    warm = simulate(plan)  # compiles, or loads the kernel from the on-disk cache
    if not warm.completed():
        raise RuntimeError(warm.describe_failure())
    best = min(simulate(plan).solve_seconds for _ in range(repeats))
    return best, warm.compile_seconds, int(warm.iterations[0])


def _opensees_available() -> str | None:
    """None when OpenSeesPy imports, else why not."""
    try:
        import openseespy.opensees  # noqa: F401
    except Exception as exc:  # ImportError, or OSError for a missing liblapack
        return f"{type(exc).__name__}: {exc}"
    return None


def _pframe_command() -> list[str] | None:
    """The ``pframe`` console script of this Python's environment, if it has ``solve``."""
    beside = Path(sys.executable).with_name("pframe")
    candidates = [str(beside)] if beside.exists() else []
    found = shutil.which("pframe")
    if found and found not in candidates:
        candidates.append(found)
    for exe in candidates:
        try:
            probe = subprocess.run([exe, "solve", "--help"], capture_output=True, text=True,
                                   timeout=120)
        except (OSError, subprocess.TimeoutExpired):
            continue
        if probe.returncode == 0 and "--overwrite" in probe.stdout:
            return [exe]
    return None


def _wall(command: list[str], repeats: int, cwd: Path) -> float:
    """Best wall time of ``command`` over ``repeats`` runs; raises if a run fails."""
    best = float("inf")
    for _ in range(repeats):
        start = time.perf_counter()
        completed = subprocess.run(command, capture_output=True, text=True, cwd=cwd)
        elapsed = time.perf_counter() - start
        if completed.returncode != 0:
            raise RuntimeError(f"{shlex.join(command)} exited with {completed.returncode}:\n"
                               f"{completed.stderr.strip() or completed.stdout.strip()}")
        best = min(best, elapsed)
    return best


def _ratio(numerator: float | None, denominator: float | None) -> str:
    if numerator is None or denominator is None or denominator <= 0:
        return "-"
    ratio = numerator / denominator
    return f"{ratio:.1f}x" if ratio >= 10 else f"{ratio:.2f}x"


def _seconds(value: float | None) -> str:
    return "-" if value is None else f"{value:.4f} s"


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0],
                                     formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--steps", type=int, default=None,
                        help="time steps per run (default: the models' 50,000)")
    parser.add_argument("--repeats", type=int, default=5,
                        help="timed pframe kernel runs per scene, best kept (default 5)")
    parser.add_argument("--no-process", action="store_true",
                        help="skip the whole-process (subprocess) comparison")
    args = parser.parse_args(argv)
    if args.steps is not None and args.steps < 1:
        parser.error("--steps must be at least 1")
    if args.repeats < 1:
        parser.error("--repeats must be at least 1")

    print("command: " + shlex.join([sys.executable, *sys.argv]))
    for line in machine_lines():
        print(line)
    print()

    rows: list[tuple[str, str, str, str]] = []  # what, pframe, OpenSees, ratio
    with tempfile.TemporaryDirectory(prefix="pframe-bench-") as tmp:
        folder = Path(tmp)
        linear_file = shortened_model(LINEAR, args.steps, folder)
        kelvin_file = shortened_model(KELVIN, args.steps, folder)
        linear_plan, kelvin_plan = _plan(linear_file), _plan(kelvin_file)
        steps = linear_plan.steps
        dt = float(linear_plan.dt[0])
        print(f"scenes: {LINEAR.name} and {KELVIN.name}, {steps} steps of dt = {dt:.6g} s, "
              f"{linear_plan.n_dof} DOFs, {len(linear_plan.contact_names)} contacts")
        print()

        # -- kernel ---------------------------------------------------------------------------
        print(f"kernel: pframe best of {args.repeats} after a warm-up run; OpenSees best of "
              f"{OPENSEES_REPEATS} analyze({steps}, dt) calls")
        pf_linear, compile_linear, solves_linear = _kernel_seconds(linear_plan, args.repeats)
        print(f"  pframe  {LINEAR.name:<26} {pf_linear:.4f} s  ({solves_linear} Newton solves; "
              f"first call compiled/loaded the kernel in {compile_linear:.2f} s)")
        pf_kelvin, compile_kelvin, solves_kelvin = _kernel_seconds(kelvin_plan, args.repeats)
        print(f"  pframe  {KELVIN.name:<26} {pf_kelvin:.4f} s  ({solves_kelvin} Newton solves; "
              f"first call compiled/loaded the kernel in {compile_kelvin:.2f} s)")

        why_not = _opensees_available()
        os_analyze = None
        peer = None
        if why_not is None:
            from pframe.peers.opensees import run, script_text

            peer = peer_scene(linear_plan)
            os_analyze = min(run(peer)["analyze_seconds"] for _ in range(OPENSEES_REPEATS))
            print(f"  OpenSees {LINEAR.name:<25} {os_analyze:.4f} s  (NormDispIncr "
                  f"{peer.tolerance:g} m)")
            print(f"  ratio OpenSees / pframe: {_ratio(os_analyze, pf_linear)} against the "
                  f"linear-contact kernel, {_ratio(os_analyze, pf_kelvin)} against the "
                  "improved-Kelvin kernel")
        else:
            print(f"  OpenSeesPy not available ({why_not}): OpenSees columns left empty")
        rows.append((f"kernel, {LINEAR.stem}", _seconds(pf_linear), _seconds(os_analyze),
                     _ratio(os_analyze, pf_linear)))
        rows.append((f"kernel, {KELVIN.stem} (pframe only)", _seconds(pf_kelvin),
                     _seconds(os_analyze), _ratio(os_analyze, pf_kelvin)))
        print()

        # -- whole process --------------------------------------------------------------------
        if args.no_process:
            print("whole process: skipped (--no-process)")
        else:
            print(f"whole process: wall time of a subprocess, best of {PROCESS_REPEATS}")
            script_seconds = None
            if peer is not None:
                out_npz = folder / "opensees.npz"
                script = folder / "opensees_peer.py"
                script.write_text(script_text(peer, str(out_npz)), encoding="utf-8")
                script_command = [sys.executable, str(script)]
                script_seconds = _wall(script_command, PROCESS_REPEATS, folder)
                print(f"  {shlex.join(['python', script.name])} ({LINEAR.name}): "
                      f"{script_seconds:.3f} s")
            pframe_cli = _pframe_command()
            cli = {}
            if pframe_cli is None:
                print("  pframe CLI not available (no 'pframe solve' with --overwrite on PATH "
                      "or beside this Python): pframe columns left empty")
            else:
                for label, scene in ((KELVIN, kelvin_file), (LINEAR, linear_file)):
                    command = [*pframe_cli, "solve", str(scene), "-o",
                               str(folder / f"{scene.stem}.h5"), "--overwrite"]
                    try:
                        _wall(command, 1, REPO)  # warm the kernel cache, untimed
                        cli[label] = _wall(command, PROCESS_REPEATS, REPO)
                    except RuntimeError as exc:
                        print(f"  pframe solve failed: {exc}")
                        continue
                    shown = scene.relative_to(REPO) if scene.is_relative_to(REPO) else scene.name
                    print(f"  pframe solve {shown} -o {scene.stem}.h5 --overwrite: "
                          f"{cli[label]:.3f} s")
            if script_seconds is not None and cli:
                print("  ratio OpenSees script / pframe solve: "
                      + ", ".join(f"{_ratio(script_seconds, s)} ({label.name})"
                                  for label, s in cli.items()))
            rows.append((f"process, pframe solve {KELVIN.name}", _seconds(cli.get(KELVIN)),
                         _seconds(script_seconds), _ratio(script_seconds, cli.get(KELVIN))))
            rows.append((f"process, pframe solve {LINEAR.name}", _seconds(cli.get(LINEAR)),
                         _seconds(script_seconds), _ratio(script_seconds, cli.get(LINEAR))))
        print()

    header = ("", "pframe", f"OpenSees ({LINEAR.stem})", "OpenSees / pframe")
    widths = [max(len(r[i]) for r in [header, *rows]) for i in range(4)]
    print(f"summary ({steps} steps; OpenSees always runs the linear-contact scene):")
    line = "  ".join(h.ljust(w) if i == 0 else h.rjust(w) for i, (h, w) in
                     enumerate(zip(header, widths)))
    print(line)
    print("-" * len(line))
    for row in rows:
        print("  ".join(c.ljust(w) if i == 0 else c.rjust(w) for i, (c, w) in
                        enumerate(zip(row, widths))))
    return 0


if __name__ == "__main__":
    sys.exit(main())
