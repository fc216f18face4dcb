"""Damaged result files (issue 20): a file with dangling references, a missing variable, or
a header that claims a history of 10^9 x 6 values it does not hold is answered with a pframe
error naming the file and what is wrong (exit 2 from the command line, InputError from
Python), never a KeyError, AttributeError or MemoryError from h5py or xarray. Each file is
damaged the way an HDF5 tool that does not know netCDF damages it (h5py's ``del`` and
``resize``)."""

from __future__ import annotations

import shutil
from pathlib import Path

import h5py
import pytest

import pframe
from pframe.cli import main
from pframe.errors import EnvironmentFailure, InputError

REPO = Path(__file__).resolve().parents[1]


@pytest.fixture(scope="module")
def whole(tmp_path_factory) -> Path:
    path = tmp_path_factory.mktemp("damaged") / "eq14.nc"
    assert main(["solve", str(REPO / "models" / "wu2021-eq14.yaml"), "-o", str(path), "-q"]) == 0
    return path


def _dangling(f):
    del f["node_name"]  # the names of the nodes, which the histories name as coordinates
    del f["t"]  # the time dimension: every history's DIMENSION_LIST now points at nothing


def _missing(f):
    del f["contact_gap"]  # the contact panel needs it; contact variables name it


def _lies(f):
    f["t"].resize((10**9,))
    for name in ("displacement", "velocity", "story_drift", "story_force", "contact_force"):
        if name in f:
            f[name].resize((10**9,) + f[name].shape[1:])


DAMAGE = {"dangling": (_dangling, "dangling reference"),
          "missing": (_missing, "contact_gap"),
          "lies": (_lies, "1,000,000,000 x 6")}


@pytest.mark.slow
def test_a_truncated_file_is_named_truncated(whole, tmp_path, capsys):
    """A file cut short (a copy that did not finish) says so, with its two sizes, rather
    than "not a netCDF-4/HDF5 file"."""
    path = tmp_path / "cut.nc"
    path.write_bytes(whole.read_bytes()[: whole.stat().st_size // 2])
    assert main(["plot", str(path), "-o", str(tmp_path / "fig.png")]) == 2
    err = capsys.readouterr().err
    assert f"{path}: a truncated result file" in err and f"{whole.stat().st_size:,}" in err, err
    with pytest.raises(InputError, match="truncated result file"):
        pframe.open(path)


@pytest.fixture(params=sorted(DAMAGE))
def damaged(request, whole, tmp_path) -> tuple[Path, str]:
    damage, expected = DAMAGE[request.param]
    path = tmp_path / f"{request.param}.nc"
    shutil.copy(whole, path)
    with h5py.File(path, "r+") as f:
        damage(f)
    return path, expected


def test_plot_names_the_file_and_the_damage(damaged, tmp_path, capsys):
    path, expected = damaged
    code = main(["plot", str(path), "-o", str(tmp_path / "fig.png")])
    err = capsys.readouterr().err
    assert code == 2, err
    assert "Traceback" not in err and "KeyError" not in err and "MemoryError" not in err
    assert err.startswith(f"pframe: {path}: a damaged result file") and expected in err, err
    assert not list(tmp_path.glob("fig*")), "nothing half-written"


def test_open_and_plot_from_python_raise_input_error(damaged):
    path, expected = damaged
    with pytest.raises(InputError, match="damaged result file") as caught:
        pframe.open(path)
    assert str(path) in str(caught.value) and expected in str(caught.value)
    pytest.importorskip("matplotlib")
    with pytest.raises(InputError, match="damaged result file"):
        pframe.plot(path)


def test_load_reads_the_intact_scene_of_a_damaged_file(damaged, whole):
    """``pframe.load`` needs only ``input_yaml`` (and the record's text): a file whose
    histories are damaged still gives back the scene it ran, equal to the whole file's."""
    path, _ = damaged
    assert pframe.load(path) == pframe.load(whole)


def test_load_of_a_file_without_its_scene_is_input_error(whole, tmp_path):
    path = tmp_path / "noscene.nc"
    shutil.copy(whole, path)
    with h5py.File(path, "r+") as f:
        del f.attrs["input_yaml"]
    with pytest.raises(InputError, match="holds no scene"):
        pframe.load(path)


@pytest.mark.slow
def test_an_honest_file_larger_than_memory_is_refused_before_reading(whole, tmp_path,
                                                                      monkeypatch, capsys):
    """A whole file whose histories do not fit in the memory pframe may use: an environment
    error (exit 3) naming the file and the size, not a MemoryError mid-read."""
    monkeypatch.setenv("PFRAME_MEMORY_LIMIT", "1000000")  # 1 MB; the histories hold 12 MB
    code = main(["plot", str(whole), "-o", str(tmp_path / "fig.png")])
    err = capsys.readouterr().err
    assert code == 3 and f"{whole}: its histories need" in err and "Traceback" not in err, err
    pytest.importorskip("matplotlib")
    with pytest.raises(EnvironmentFailure, match="PFRAME_MEMORY_LIMIT"):
        pframe.plot(whole)


@pytest.mark.slow
def test_whole_files_of_every_kind_pass_the_check(whole, tmp_path):
    """No false alarm: a solve, a streamed incomplete run's shape, a sweep and a gap audit,
    as pframe writes them, are whole."""
    from pframe.record.check import check_file

    check_file(whole)
    sweep, gap = tmp_path / "sweep.nc", tmp_path / "gap.nc"
    assert main(["sweep", str(REPO / "models" / "sweeps" / "wu2021-pi-d.yaml"), "-o",
                 str(sweep), "-q"]) == 0
    assert main(["gap", str(REPO / "models" / "wu2021-pulse.yaml"), "--levels", "0.2",
                 "--gap", "0.1", "-o", str(gap), "-q"]) == 0
    for path in (sweep, gap):
        check_file(path)
        pframe.open(path).close()


def test_a_sparse_file_of_another_writer_is_not_called_damaged(tmp_path):
    """netCDF-C leaves values never written unstored (they read as the fill value): only a
    file of pframe's is held to storing every value it claims."""
    netCDF4 = pytest.importorskip("netCDF4", reason="netCDF4-python writes the sparse file")
    from pframe.record.check import check_file

    path = tmp_path / "sparse.nc"
    with netCDF4.Dataset(path, "w") as nc:
        nc.createDimension("t", None)
        nc.createVariable("x", "f8", ("t",), chunksizes=(10,))[95] = 1.0
    check_file(path)
    with h5py.File(path, "r+") as f:  # the same file claimed by pframe: 1 of 10 chunks
        f.attrs["pframe_version"] = "0.1.0"
    with pytest.raises(InputError, match="x claims 96 values but the file stores only 1 of"):
        check_file(path)
