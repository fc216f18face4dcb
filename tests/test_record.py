"""pframe.record: the one layout of result files (netCDF-4, CF-1.8) and its two backends, the
file and the in-memory Dataset."""

from __future__ import annotations

import re

import h5py
import numpy as np
import pytest
import xarray as xr

from pframe.record.netcdf import DatasetWriter, Writer, provenance, write_dataset


def test_labels_are_character_arrays_that_xarray_reads_as_strings(tmp_path):
    path = tmp_path / "labels.nc"
    f = Writer(path)
    f.labels("node", "node_name", ["A/1", "B/10", "Ü/2"], long_name="node")
    f.variable("u", ("node",), np.array([1.0, 2.0, 3.0]), units="m", long_name="u")
    f.close()
    with h5py.File(path, "r") as h:
        assert h["node_name"].dtype == np.dtype("S1") and h["node_name"].shape == (3, 4)  # UTF-8 bytes
        assert h["u"].attrs["coordinates"] == b"node_name"  # NC_CHAR: bytes in h5py
    with xr.open_dataset(path, engine="h5netcdf") as ds:
        assert ds.node_name.values.tolist() == ["A/1", "B/10", "Ü/2"]
        assert "node_name" in ds.u.coords


def test_no_int64_variables(tmp_path):
    f = Writer(tmp_path / "x.nc")
    f.dimension("n", 2)
    with pytest.raises(TypeError, match="int32"):
        f.variable("count", ("n",), np.array([1, 2], dtype=np.int64))
    f.close()


def test_provenance_says_when_and_by_what():
    attrs = provenance("pframe solve scene.yaml")
    assert attrs["Conventions"] == "CF-1.8"
    assert re.fullmatch(r"\d{4}-\d\d-\d\dT\d\d:\d\d:\d\dZ", attrs["date_created"])
    assert attrs["history"] == f"{attrs['date_created']} pframe {attrs['pframe_version']}: " \
                               "pframe solve scene.yaml"
    assert "numpy" in attrs["software"] and "numba" in attrs["software"]


def test_compression_changes_the_size_not_the_values(tmp_path):
    rows = np.cumsum(np.random.default_rng(1).normal(size=(20000, 4)), axis=0)
    sizes = {}
    for compress in (False, True):
        path = tmp_path / f"{compress}.nc"
        f = Writer(path, compress=compress)
        f.dimension("t", None)
        f.resize("t", len(rows))
        f.dimension("node", 4)
        var = f.variable("u", ("t", "node"), chunk_rows=True)
        var[:] = rows
        f.close()
        sizes[compress] = path.stat().st_size
        with h5py.File(path, "r") as h:
            np.testing.assert_array_equal(h["u"][()], rows)
            assert (h["u"].compression == "gzip") == compress and h["u"].shuffle == compress
    assert sizes[True] < 0.95 * sizes[False]


def test_the_dataset_backend_builds_what_xarray_reads_from_the_file(tmp_path):
    """The same calls on a file and on a DatasetWriter give identical Datasets."""
    def build(f):
        f.dimension("t", None)
        f.resize("t", 4)
        t = f.variable("t", ("t",), chunk_rows=True, units="s", long_name="time")
        t[0:4] = np.arange(4) * 0.5
        f.labels("node", "node_name", ["A/1", "A/2"], long_name="node")
        f.strings("side", ("node",), ["left", "right"], auxiliary=True, long_name="side")
        f.variable("gap", ("node",), np.array([0.1, 0.2]), auxiliary=True, units="m")
        u = f.variable("u", ("t", "node"), chunk_rows=True, units="m", long_name="u")
        u[0:4] = np.arange(8.0).reshape(4, 2)
        f.resize("t", 3)  # a run that stopped early
        f.variable("count", ("node",), np.array([1, 2], dtype=np.int32), long_name="count")
        f.attrs.update({"title": "x", "steps": np.int64(3), "complete": np.int8(0)})

    path = tmp_path / "b.nc"
    writer = Writer(path)
    build(writer)
    writer.close()
    memory = DatasetWriter()
    build(memory)
    with xr.open_dataset(path, engine="h5netcdf") as ds:
        xr.testing.assert_identical(ds.load(), memory.dataset())


def test_write_dataset_writes_names_as_labels(tmp_path):
    """A Dataset with names as coordinate values (``pframe.indexed``) is written with a label
    ``<dim>_name`` instead (CF: no string coordinate variables), and reads back with them."""
    from pframe.api import indexed

    ds = xr.Dataset({"g": ("rule", [1.0, 2.0])}, coords={"rule": ["ABS", "SRSS"]})
    write_dataset(ds, tmp_path / "names.nc")
    with xr.open_dataset(tmp_path / "names.nc", engine="h5netcdf") as back:
        assert "rule" not in back.variables
        assert back.rule_name.values.tolist() == ["ABS", "SRSS"]
        assert {"date_created", "history", "Conventions"} <= set(back.attrs)
        assert indexed(back).g.to_series().index.tolist() == ["ABS", "SRSS"]
    with_label = indexed(ds.drop_vars("rule").assign_coords(
        rule_name=("rule", ["ABS", "SRSS"])))
    assert with_label.rule.values.tolist() == ["ABS", "SRSS"]
    write_dataset(with_label, tmp_path / "labels.nc")
    with xr.open_dataset(tmp_path / "labels.nc", engine="h5netcdf") as back:
        assert "rule" not in back.variables and back.rule_name.values.tolist() == ["ABS", "SRSS"]
    assert sorted(p.name for p in tmp_path.iterdir()) == ["labels.nc", "names.nc"]


def _fixed_length_text(attrs, name: str) -> bool:
    """Whether attribute ``name`` is a fixed-length string (netCDF's NC_CHAR), not a
    variable-length one (NC_STRING, which Octave's netcdf package cannot read)."""
    kind = attrs.get_id(name).get_type()
    return isinstance(kind, h5py.h5t.TypeStringID) and not kind.is_variable_str()


def test_text_attributes_are_fixed_length_characters(tmp_path):
    path = tmp_path / "text.nc"
    f = Writer(path)
    f.attrs.update({"title": "Ü-Bahn pounding", "warnings": "", "steps": np.int64(3)})
    f.coordinate("t", [0.0, 1.0], units="s", long_name="time")
    f.variable("u", ("t",), np.array([1.0, 2.0]), units="m", long_name="u")
    f.close()
    with h5py.File(path, "r") as h:
        for obj, names in ((h, ("title", "warnings")),
                           (h["t"], ("units", "long_name")), (h["u"], ("units", "long_name"))):
            for name in names:
                assert _fixed_length_text(obj.attrs, name), name
        assert list(h.attrs)[:3] == ["title", "warnings", "steps"]  # the order kept
    with xr.open_dataset(path, engine="h5netcdf") as back:
        assert back.attrs["title"] == "Ü-Bahn pounding" and back.attrs["warnings"] == ""
        assert back.attrs["steps"] == 3 and back.u.attrs == {"units": "m", "long_name": "u"}
    write_dataset(xr.Dataset({"u": ("t", [1.0])}, attrs={"title": "x"}), tmp_path / "ds.nc")
    with h5py.File(tmp_path / "ds.nc", "r") as h:
        assert all(_fixed_length_text(h.attrs, n) for n in ("title", "history"))
        assert _fixed_length_text(h["u"].attrs, "_FillValue") is False


def test_text_set_on_a_variable_handed_out_is_fixed_length_too(tmp_path):
    """The writer's own methods write text fixed-length at once (and close scans nothing);
    text set through a variable it hands out is h5netcdf's kind until close rewrites it."""
    path = tmp_path / "handed.nc"
    f = Writer(path)
    f.coordinate("t", [0.0, 1.0], units="s")
    f["t"].attrs["comment"] = "set afterwards"
    f.close()
    with h5py.File(path, "r") as h:
        assert _fixed_length_text(h["t"].attrs, "comment")
        assert list(h["t"].attrs).index("comment") > list(h["t"].attrs).index("units")


@pytest.mark.slow
@pytest.mark.filterwarnings("error::pytest.PytestUnraisableExceptionWarning")
def test_a_stop_inside_the_file_constructor_leaves_no_traceback(tmp_path, monkeypatch, capsys):
    """A signal raises where it arrives: inside h5netcdf's constructor, the half-built file
    must not print an error when it is collected (h5netcdf marks it closed only for an
    Exception; a stop is a BaseException)."""
    import gc

    import h5netcdf

    def interrupted(self, *args, **kwargs):
        raise KeyboardInterrupt

    monkeypatch.setattr(h5netcdf.File, "__init__", interrupted)
    with pytest.raises(KeyboardInterrupt):
        Writer(tmp_path / "x.nc")
    gc.collect()
    captured = capsys.readouterr()
    assert "Traceback" not in captured.err and "_closed" not in captured.err
