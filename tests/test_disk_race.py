"""Another process fills the disk while ``pframe solve`` writes: the run still completes,
because the result file's space is allocated on the disk before HDF5 writes into it
(``fallocate``, record/hdf5.py). Before, libhdf5 met ENOSPC in a write and the process ended
by a segmentation fault (exit 139), no message.

Needs a small disk of its own: a 20 MB tmpfs, which only root can mount (skipped otherwise).
"""

from __future__ import annotations

import os
import shutil
import subprocess
import sys
from pathlib import Path

import pytest

import pframe

REPO = Path(__file__).resolve().parents[1]
WU2021 = REPO / "models" / "wu2021-eq14.yaml"  # a 12.4 MB result file
FRAMEWORK = Path(pframe.__file__).resolve().parents[1]

#: pframe solve, with a disk filled to the last byte right after the free-space check before
#: the RACE_AT-th block (another process writing at the worst moment)
RACER = '''
import os, sys
from pframe.record import hdf5
real, calls = hdf5.ResultWriter.room, []
def room(self, nbytes):
    real(self, nbytes)
    calls.append(nbytes)
    if len(calls) == int(os.environ["RACE_AT"]):
        with open(sys.argv[1], "ab") as filler:
            try:
                while True:
                    filler.write(bytes(65536))
                    filler.flush()
            except OSError:
                pass
hdf5.ResultWriter.room = room
from pframe.cli import main
sys.exit(main(sys.argv[2:]))
'''


@pytest.fixture
def small_disk(tmp_path):
    disk = tmp_path / "disk"
    disk.mkdir()
    if os.name != "posix" or os.geteuid() != 0 or shutil.which("mount") is None:
        pytest.skip("mounting a 20 MB tmpfs needs root")
    mounted = subprocess.run(["mount", "-t", "tmpfs", "-o", "size=20m", "tmpfs", str(disk)],
                             capture_output=True, text=True)
    if mounted.returncode != 0:
        pytest.skip(f"cannot mount a tmpfs here: {mounted.stderr.strip()}")
    try:
        yield disk
    finally:
        subprocess.run(["umount", "-l", str(disk)], capture_output=True)


@pytest.mark.slow
@pytest.mark.parametrize("race_at", [1, 3, 8])
def test_a_disk_filled_by_another_process_meanwhile_does_not_crash_the_run_e2e(
        tmp_path, small_disk, race_at):
    racer = tmp_path / "racer.py"
    racer.write_text(RACER, encoding="utf-8")
    out, filler = small_disk / "out.nc", small_disk / "filler"
    run = subprocess.run(
        [sys.executable, str(racer), str(filler), "solve", str(WU2021), "-o", str(out), "-q"],
        capture_output=True, text=True, timeout=300,
        env=os.environ | {"PYTHONPATH": str(FRAMEWORK), "RACE_AT": str(race_at)})
    assert run.returncode == 0, (run.returncode, run.stderr)
    assert filler.stat().st_size > 0 and shutil.disk_usage(small_disk).free < 2**20 * 8
    assert sorted(p.name for p in small_disk.iterdir()) == ["filler", "out.nc"]
    import xarray as xr

    with xr.open_dataset(out) as result:
        assert result.attrs["complete"] == 1
        assert result["displacement"].shape == (50001, 6)
        assert bool(result["displacement"].notnull().all())
