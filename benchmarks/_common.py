"""What the benchmark scripts share: the machine's description, scene copies, the pframe and
OpenSees commands, timing of subprocesses (wall and CPU), and table printing."""

from __future__ import annotations

import os
import platform
import resource
import shlex
import shutil
import statistics
import subprocess
import sys
import time
from dataclasses import dataclass
from importlib import metadata
from pathlib import Path

import yaml

REPO = Path(__file__).resolve().parents[1]
KELVIN = REPO / "models" / "wu2021-eq14.yaml"  # the paper's scene: improved Kelvin contacts
LINEAR = REPO / "models" / "wu2021-eq14-linear.yaml"  # its twin with OpenSees' ElasticPPGap
#: the histories the OpenSees peer records (pframe.peers.opensees: displacement, velocity,
#: storey force, contact force at every step); a pframe scene recording exactly these writes
#: the same output
PEER_HISTORIES = ("displacement", "velocity", "story_force", "contact_force")
PEER_RECORDERS = [{"kind": "history", "quantities": list(PEER_HISTORIES)}]


def version(package: str) -> str:
    try:
        return metadata.version(package)
    except metadata.PackageNotFoundError:
        return "not installed"


def load_average() -> str:
    one, five, fifteen = os.getloadavg()
    return f"{one:.2f} {five:.2f} {fifteen:.2f}"


def machine_lines() -> list[str]:
    """Platform, CPU (and how many this process may use), load, versions."""
    cpu = platform.processor() or platform.machine()
    try:
        with open("/proc/cpuinfo", encoding="utf-8") as handle:
            cpu = next(line.split(":", 1)[1].strip() for line in handle
                       if line.startswith("model name"))
    except (OSError, StopIteration):
        pass
    usable = len(os.sched_getaffinity(0)) if hasattr(os, "sched_getaffinity") else os.cpu_count()
    return [
        f"platform: {platform.platform()}",
        f"cpu: {cpu}; {os.cpu_count()} CPUs ({usable} usable); load average (1, 5, 15 min) "
        f"{load_average()} at the start",
        f"python {platform.python_version()} ({sys.executable}); numpy {version('numpy')}, "
        f"numba {version('numba')}, openseespy {version('openseespy')}, "
        f"pframe {version('pframe')}",
    ]


def print_header() -> None:
    """The command line and the machine, first thing in every benchmark's output."""
    print("command: " + shlex.join([sys.executable, *sys.argv]))
    for line in machine_lines():
        print(line)


def scene_copy(model: Path, folder: Path, steps: int | None = None,
               recorders: list | None = None, tag: str = "") -> Path:
    """``model`` itself, or a copy in ``folder`` shortened to ``steps`` steps and/or with its
    recorders replaced by ``recorders``. Relative file paths in the scene are not rewritten:
    copy only scenes that name no files."""
    if steps is None and recorders is None:
        return model
    data = yaml.safe_load(model.read_text(encoding="utf-8"))
    name = model.stem
    if steps is not None:
        data["analysis"]["duration"] = steps * float(data["analysis"]["dt"])
        name += f"-{steps}"
    if recorders is not None:
        data["recorders"] = recorders
        name += tag or "-recorders"
    path = folder / f"{name}.yaml"
    path.write_text(yaml.safe_dump(data, sort_keys=False), encoding="utf-8")
    return path


def pframe_command() -> list[str] | None:
    """The command line of pframe's CLI: the ``pframe`` console script of this Python's
    environment, else the one on PATH, else ``python -c`` calling ``pframe.cli.main``; the
    first whose ``solve`` takes ``--overwrite``. None if there is none."""
    candidates = []
    beside = Path(sys.executable).with_name("pframe")
    if beside.exists():
        candidates.append([str(beside)])
    found = shutil.which("pframe")
    if found and [found] not in candidates:
        candidates.append([found])
    candidates.append([sys.executable, "-c",
                       "import sys; from pframe.cli import main; sys.exit(main())"])
    for command in candidates:
        try:
            probe = subprocess.run([*command, "solve", "--help"], capture_output=True,
                                   text=True, timeout=120)
        except (OSError, subprocess.TimeoutExpired):
            continue
        if probe.returncode == 0 and "--overwrite" in probe.stdout:
            return command
    return None


def opensees_unavailable(in_subprocess: bool = False) -> str | None:
    """None when OpenSeesPy imports (in this process, or in a new one of this Python when
    only scripts will run it), else why not."""
    if in_subprocess:
        done = subprocess.run([sys.executable, "-c", "import openseespy.opensees"],
                              capture_output=True, text=True)
        lines = (done.stderr or done.stdout).strip().splitlines()
        return None if done.returncode == 0 else (lines[-1] if lines else "import failed")
    try:
        import openseespy.opensees  # noqa: F401
    except Exception as exc:  # ImportError, or OSError/RuntimeError for a missing liblapack
        return f"{type(exc).__name__}: {exc}"
    return None


def opensees_script(model: Path, folder: Path, out_npz: Path | None = None) -> list[str]:
    """Write the standalone OpenSeesPy script of ``model`` (``pframe.peers.opensees
    .script_text``; it never imports pframe) into ``folder``; return the command running it
    with this Python. Run as a script it saves its four histories to ``out_npz``."""
    from pframe.assemble import assemble
    from pframe.peers.from_plan import peer_scene
    from pframe.peers.opensees import script_text
    from pframe.reader import load_scene

    peer = peer_scene(assemble(load_scene(model).expanded))
    out = folder / "opensees.npz" if out_npz is None else out_npz
    script = folder / "opensees_peer.py"
    script.write_text(script_text(peer, str(out)), encoding="utf-8")
    return [sys.executable, str(script)]


@dataclass
class Timing:
    """Wall and CPU seconds of one measured thing."""

    wall: float
    cpu: float


def children_cpu() -> float:
    """User + system CPU seconds of every waited-for child process so far."""
    usage = resource.getrusage(resource.RUSAGE_CHILDREN)
    return usage.ru_utime + usage.ru_stime


def run_timed(command: list[str], cwd: Path | None = None,
              env: dict | None = None) -> tuple[Timing, subprocess.CompletedProcess]:
    """Run ``command`` to its end: wall time, and its CPU time (all its threads and children)
    as the RUSAGE_CHILDREN difference. Never raises on a failed command."""
    cpu = children_cpu()
    start = time.perf_counter()
    done = subprocess.run(command, capture_output=True, text=True, cwd=cwd, env=env)
    wall = time.perf_counter() - start
    return Timing(wall, children_cpu() - cpu), done


def run_checked(command: list[str], cwd: Path | None = None, env: dict | None = None) -> Timing:
    """:func:`run_timed`, raising RuntimeError (with its stderr) when the command fails."""
    timing, done = run_timed(command, cwd=cwd, env=env)
    if done.returncode != 0:
        raise RuntimeError(f"{shlex.join(command)} exited with {done.returncode}:\n"
                           f"{done.stderr.strip() or done.stdout.strip()}")
    return timing


def median_timing(timings: list[Timing]) -> Timing:
    """Median wall and median CPU (each on its own) of repeated measurements."""
    return Timing(statistics.median(t.wall for t in timings),
                  statistics.median(t.cpu for t in timings))


def ratio(numerator: float | None, denominator: float | None) -> str:
    if numerator is None or denominator is None or denominator <= 0:
        return "-"
    value = numerator / denominator
    return f"{value:.1f}x" if value >= 10 else f"{value:.2f}x"


def seconds(value: float | None, digits: int = 3) -> str:
    return "-" if value is None else f"{value:.{digits}f}"


def table(header: tuple[str, ...], rows: list[tuple[str, ...]], left: int = 1) -> list[str]:
    """Lines of a plain table: the first ``left`` columns left-aligned, the others
    right-aligned."""
    widths = [max(len(row[i]) for row in [header, *rows]) for i in range(len(header))]

    def line(cells):
        return "  ".join(c.ljust(w) if i < left else c.rjust(w)
                         for i, (c, w) in enumerate(zip(cells, widths))).rstrip()

    head = line(header)
    return [head, "-" * len(head), *(line(row) for row in rows)]
