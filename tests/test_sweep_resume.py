"""Nothing lost: a sweep killed with SIGKILL part way and started again with the same command
continues from its finished chunks and ends with the very file an uninterrupted run writes.

The sweeps share the kernel of tests/test_sweep.py (same laws, default envelopes).
"""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import pytest
from conftest import assert_same_result_file, kill_after  # noqa: E402
from test_sweep import BASE  # noqa: E402

from pframe.cli import main

#: 12 variants of 50,000 steps, one per chunk, on one thread: long enough to be killed midway
SWEEP = """\
base: base.yaml
axes:
  - {name: gap, path: contacts.*.gap, linspace: [0.0, 0.022, 12], units: m}
  - {name: restitution, path: contacts.floor-2.restitution, values: [0.5]}
chunk: 1
"""
CHUNKS = 12


@pytest.fixture(scope="module")
def folder(tmp_path_factory):
    path = tmp_path_factory.mktemp("resume")
    (path / "base.yaml").write_text(BASE.replace("duration: 1.5", "duration: 10.0"),
                                    encoding="utf-8")
    (path / "sweep.yaml").write_text(SWEEP, encoding="utf-8")
    return path


def _command(folder: Path, out: str) -> list[str]:
    return [sys.executable, "-c", "import sys; from pframe.cli import main; sys.exit(main())",
            "sweep", "sweep.yaml", "-o", out, "--threads", "1", "-q"]


def _kill_after(folder: Path, out: str, chunks: int) -> int:
    """Start the sweep, SIGKILL it as soon as ``chunks`` chunk files exist in total; return
    how many there are then."""
    return kill_after(_command(folder, out), folder, folder / f"{out}.parts", chunks)


@pytest.mark.slow
def test_kill_and_resume_gives_the_same_file(folder, monkeypatch):
    whole = folder / "whole.h5"
    done = subprocess.run(_command(folder, whole.name), cwd=folder, capture_output=True,
                          text=True, timeout=900)
    assert done.returncode == 0, done.stderr

    first = _kill_after(folder, "resumed.h5", 1)
    assert 1 <= first < CHUNKS
    assert not (folder / "resumed.h5").exists()
    second = _kill_after(folder, "resumed.h5", first + 2)  # continues, killed again
    assert first < second < CHUNKS, (first, second)
    assert not (folder / "resumed.h5").exists()

    monkeypatch.chdir(folder)
    assert main(["sweep", "sweep.yaml", "-o", "resumed.h5", "-q"]) == 0
    assert not (folder / "resumed.h5.parts").exists()
    # the same file, bit for bit, but for when and by which command it was written
    assert_same_result_file(folder / "resumed.h5", whole)
