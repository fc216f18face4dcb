"""Ctrl-C and SIGTERM stop a run at once in every mode, however much work a step or a kernel
call holds: the driver sets the kernel's stop flag, which it reads at every evaluation of the
residual (docs/getting-started.md#exit-codes).

Each case runs ``pframe`` in its own process on a pathological scene (a Newton loop allowed
10^9 iterations that never converges, central difference with about 10^5 sub-steps a step,
event stepping with thousands of sub-steps a step, a sweep's large batch), sends the signal
about a second into the run, and measures how long the process takes to exit. The bound is
generous (a loaded machine); the real figures are a few hundredths of a second
(``benchmarks/interrupt_latency.py`` prints them), against 3 s to minutes before.
"""

from __future__ import annotations

import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import pytest
import yaml

import pframe
from pframe.yamltext import load

REPO = Path(__file__).resolve().parents[1]
WU2021 = REPO / "models" / "wu2021-eq14.yaml"
#: the code under test (a checkout's framework folder)
FRAMEWORK = Path(pframe.__file__).resolve().parents[1]
#: seconds from the signal to the process's exit that the test accepts (measured: < 0.1 s)
LATENCY = 2.0
#: seconds into the writing of the result before the signal
DELAY = 1.0


def _base() -> dict:
    data = load(WU2021.read_text(encoding="utf-8"), str(WU2021))
    data["recorders"] = [{"kind": "envelope", "quantities": ["displacement"]}]
    return data


def newton_scene(iterations: int = 10**9) -> dict:
    """Newton allowed 10^9 iterations with a tolerance no step can meet: the first step
    iterates for hours."""
    data = _base()
    data["analysis"]["newton"] = {"tolerance": 1e-300, "max_iterations": iterations}
    return data


def central_difference_scene() -> dict:
    """Contacts 10^4 times stiffer than the paper's and dt = 0.05 s: central difference takes
    about 1.1 x 10^5 sub-steps a step."""
    data = _base()
    for contact in data["contacts"]:
        contact.update(frequency_ratio=6.5e5, gap=0.001)
    data["analysis"].update(integrator={"type": "central_difference", "substeps": "auto"},
                            dt=0.05, duration=5000.0)
    return data


def event_scene() -> dict:
    """Event stepping with 6,501 sub-steps a step while a contact is closed: a slow (0.1 Hz)
    shaking presses the softer building A on B for half of each cycle."""
    data = _base()
    data["excitation"]["frequency"] = 0.6283185307179586
    for contact in data["contacts"]:
        contact.update(frequency_ratio=65000, gap=0.0)
    data["analysis"].update(integrator={"type": "newmark", "events": True}, dt=0.05,
                            duration=1000.0)
    return data


def _write(folder: Path, data: dict, name: str) -> Path:
    path = folder / name
    path.write_text(yaml.safe_dump(data, sort_keys=False), encoding="utf-8")
    return path


def _start(argv: list[str]) -> subprocess.Popen:
    return subprocess.Popen(
        [sys.executable, "-m", "pframe.cli", *argv], stdout=subprocess.PIPE,
        stderr=subprocess.PIPE, text=True,
        env=os.environ | {"PYTHONPATH": str(FRAMEWORK)})


def _signal_and_time(process: subprocess.Popen, signum: int) -> tuple[float, str]:
    """Send ``signum``; the seconds until the process exited, and its standard error."""
    process.send_signal(signum)
    sent = time.monotonic()
    try:
        _, err = process.communicate(timeout=120)
    finally:
        process.kill()
    return time.monotonic() - sent, err


def _wait_for(found, process: subprocess.Popen, limit: float = 120.0) -> None:
    start = time.monotonic()
    while not found():
        assert process.poll() is None, process.communicate()
        assert time.monotonic() - start < limit, "the run never started"
        time.sleep(0.02)


@pytest.mark.slow
@pytest.mark.parametrize("scene, signum", [
    (newton_scene, signal.SIGINT),
    (newton_scene, signal.SIGTERM),
    (central_difference_scene, signal.SIGINT),
    (event_scene, signal.SIGINT),
], ids=["newton-1e9-sigint", "newton-1e9-sigterm", "central-difference-1e5-substeps",
        "events-6501-parts"])
def test_a_run_stops_at_once_in_every_mode_e2e(tmp_path, scene, signum):
    model = _write(tmp_path, scene(), "scene.yaml")
    out = tmp_path / "out.nc"
    process = _start(["solve", str(model), "-o", str(out), "-q"])
    _wait_for(lambda: list(tmp_path.glob(".out.nc.*.tmp")), process)
    time.sleep(DELAY)
    assert process.poll() is None, process.communicate()  # still running: the case holds
    latency, err = _signal_and_time(process, signum)
    expected = 130 if signum == signal.SIGINT else 128 + signum
    assert process.returncode == expected, err
    assert "Traceback" not in err
    assert err.strip().splitlines()[-1] == (
        "pframe: interrupted; no output written" if signum == signal.SIGINT
        else f"pframe: stopped by signal {signum}; no output written")
    assert sorted(p.name for p in tmp_path.iterdir()) == ["scene.yaml"]  # nothing half-written
    assert latency < LATENCY, f"{latency:.2f} s from the signal to the exit"


@pytest.mark.slow
def test_a_sweep_stops_at_once_with_its_chunks_running_e2e(tmp_path):
    """A sweep's chunks (batches of 64 variants of the scene whose Newton loop runs for hours)
    stop with the signal instead of running to their end; nothing unfinished is kept."""
    _write(tmp_path, newton_scene(), "base.yaml")
    sweep = _write(tmp_path, {"title": "large batches", "base": "base.yaml", "axes": [
        {"name": "gap", "path": "contacts.*.gap", "linspace": [0.0, 0.3, 256], "units": "m"}]},
        "sweep.yaml")
    out = tmp_path / "sweep.nc"
    process = _start(["sweep", str(sweep), "-o", str(out), "-q"])
    parts = tmp_path / "sweep.nc.parts"
    _wait_for(parts.exists, process)
    time.sleep(DELAY)
    assert process.poll() is None, process.communicate()
    latency, err = _signal_and_time(process, signal.SIGINT)
    assert process.returncode == 130, err
    assert "Traceback" not in err and "no chunk had finished: nothing kept" in err
    assert not out.exists()
    assert not parts.exists()  # nothing to resume from: no folder, no lock left behind
    assert latency < LATENCY, f"{latency:.2f} s from the signal to the exit"


@pytest.mark.slow
def test_the_python_api_raises_keyboard_interrupt_at_once_and_leaves_no_thread(tmp_path):
    """In a notebook or script (Python's own SIGINT handler), pframe.solve of the scene whose
    Newton loop runs for hours raises KeyboardInterrupt within a Newton iteration of Ctrl-C,
    and the kernel's threads have ended when it does."""
    import _thread
    import threading

    before = threading.active_count()
    # 2 x 10^6 iterations, 11 times (every split): tens of seconds without the stop flag
    scene = pframe.load(_write(tmp_path, newton_scene(2 * 10**6), "scene.yaml"))
    timer = threading.Timer(DELAY, _thread.interrupt_main)
    timer.start()
    start = time.monotonic()
    with pytest.raises(KeyboardInterrupt):
        pframe.solve(scene, progress=False)
    stopped = time.monotonic() - start
    timer.join()
    assert threading.active_count() == before
    assert stopped - DELAY < LATENCY, f"{stopped - DELAY:.2f} s from the interrupt"
