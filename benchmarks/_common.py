"""What the benchmark scripts share: a description of the machine, and shortened models."""

from __future__ import annotations

import os
import platform
import sys
from importlib import metadata
from pathlib import Path

import yaml


def version(package: str) -> str:
    try:
        return metadata.version(package)
    except metadata.PackageNotFoundError:
        return "not installed"


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
        f"cpu: {cpu}; {os.cpu_count()} CPUs ({usable} usable); load average "
        f"{os.getloadavg()[0]:.2f} at the start",
        f"python {platform.python_version()} ({sys.executable}); numpy {version('numpy')}, "
        f"numba {version('numba')}, openseespy {version('openseespy')}, "
        f"pframe {version('pframe')}",
    ]


def shortened_model(model: Path, steps: int | None, folder: Path) -> Path:
    """The model itself, or a copy in ``folder`` shortened to ``steps`` steps."""
    if steps is None:
        return model
    data = yaml.safe_load(model.read_text(encoding="utf-8"))
    data["analysis"]["duration"] = steps * float(data["analysis"]["dt"])
    path = folder / f"{model.stem}-{steps}.yaml"
    path.write_text(yaml.safe_dump(data, sort_keys=False), encoding="utf-8")
    return path
