"""Seconds from Ctrl-C (SIGINT) to the exit of ``pframe solve`` in the pathological modes of
tests/test_interrupt.py, signalled one second into the run; with ``--against FOLDER`` the same
cases run side by side with another checkout's framework folder (the ratio is printed).

    python benchmarks/interrupt_latency.py [--against ../other/framework]
"""

from __future__ import annotations

import argparse
import signal
import sys
import tempfile
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "tests"))

import test_interrupt as cases  # noqa: E402

SCENES = {"newton 1e9 iterations": cases.newton_scene,
          "central difference 1e5 sub-steps": cases.central_difference_scene,
          "events 6501 parts": cases.event_scene}


def latency(framework: Path, scene) -> float:
    cases.FRAMEWORK = framework
    with tempfile.TemporaryDirectory() as folder:
        folder = Path(folder)
        model = cases._write(folder, scene(), "scene.yaml")
        process = cases._start(["solve", str(model), "-o", str(folder / "out.nc"), "-q"])
        cases._wait_for(lambda: list(folder.glob(".out.nc.*.tmp")), process)
        time.sleep(cases.DELAY)
        try:
            seconds, _ = cases._signal_and_time(process, signal.SIGINT)
        except Exception:  # noqa: BLE001 (a run that ignores the signal for 120 s)
            seconds = float("inf")
    return seconds


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--against", type=Path, help="another checkout's framework folder")
    args = parser.parse_args()
    here = Path(__file__).resolve().parents[1] / "framework"
    for name, scene in SCENES.items():
        ours = latency(here, scene)
        line = f"{name:34s} {ours:7.3f} s"
        if args.against:
            theirs = latency(args.against.resolve(), scene)
            line += f"   against {theirs:7.3f} s   ratio {theirs / ours:8.1f}"
        print(line, flush=True)


if __name__ == "__main__":
    main()
