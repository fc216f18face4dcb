"""Streamed result files: ``pframe solve`` writes the histories as they are computed.

- the streamed file equals, variable for variable and attribute for attribute, the file
  :func:`pframe.record.write_result` writes from the same run held in memory, however the run
  is cut into chunks (small chunks forced through ``pframe.kernel.run.STREAM_BYTES``), with
  several strides and in dimensionless output;
- a run that stops early gives histories of exactly the states computed;
- an interrupted run leaves nothing behind, and the summary ``pframe solve`` prints is the
  same as from histories in memory;
- memory stays bounded: a 2,000,000-step run with full histories peaks far below what
  holding them would take.

Every scene has the structure of models/wu2021-eq14.yaml, so it reuses that scene's kernel.
"""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import h5py
import numpy as np
import pytest
import xarray as xr

import pframe.kernel.run as kernel_run
from pframe.assemble import assemble
from pframe.cli import main
from pframe.commands import solve as solve_command
from pframe.kernel import simulate
from pframe.reader import load_scene
from pframe.record import ResultWriter, write_result

REPO = Path(__file__).resolve().parents[1]
WU2021 = REPO / "models" / "wu2021-eq14.yaml"
WU2021_PI = REPO / "models" / "wu2021-eq14-pi.yaml"
DURATION = "  duration: 7.957747154594767\n"
#: several strides (three time coordinates), a history without columns, dimensionless output
STRIDES = """\
recorders:
  - kind: history
    quantities: [displacement, story_drift]
  - kind: history
    every: 3
    quantities: [velocity, ground_acceleration]
  - kind: history
    every: 7
    quantities: [contact_force]
  - kind: envelope
    quantities: [displacement, contact_force]
output: {units: dimensionless}
"""
#: attributes that differ between two runs of the same scene: the wall time, and the
#: factorisations (each call of the kernel starts with a fresh factorisation, so their
#: number depends on how the run is cut into chunks)
#: what differs between two runs of one scene: wall time, calls, and when they were made
VARYING = {"solve_seconds", "factorisations", "date_created", "history"}


def _pi_with_strides() -> str:
    text = WU2021_PI.read_text(encoding="utf-8")
    return text[:text.index("recorders:")] + STRIDES


def _scene(tmp_path: Path, text: str, name: str = "scene.yaml") -> Path:
    path = tmp_path / name
    path.write_text(text, encoding="utf-8")
    return path


def _contents(path: Path) -> dict:
    """Everything a reader sees: variables in creation order (shape, dtype, values, dimension
    names, attributes in order) and the global attributes in order."""
    out = {}
    with h5py.File(path, "r") as f:
        out["/"] = (list(f), list(f.attrs), {k: v for k, v in f.attrs.items()})
        for name, dset in f.items():
            attrs = {k: v for k, v in dset.attrs.items()
                     if k not in ("DIMENSION_LIST", "REFERENCE_LIST")}
            dims = [[scale.name for scale in dim.values()] for dim in dset.dims]
            out[name] = (dset.shape, dset.dtype, dset[()], list(dset.attrs), attrs, dims,
                         dset.is_scale)
    return out


def _assert_same_file(streamed: Path, written: Path, ignore=VARYING):
    a, b = _contents(streamed), _contents(written)
    assert a["/"][:2] == b["/"][:2]  # the same variables and attributes, in the same order
    for key in a["/"][1]:
        if key not in ignore:
            assert a["/"][2][key] == b["/"][2][key], key
    assert a.keys() == b.keys()
    for name in a:
        if name == "/":
            continue
        shape, dtype, values, order, attrs, dims, scale = a[name]
        assert (shape, dtype, order, dims, scale) == b[name][:2] + b[name][3:4] + b[name][5:], name
        assert attrs.keys() == b[name][4].keys(), name
        assert all(str(attrs[k]) == str(b[name][4][k]) for k in attrs), name
        if dtype.kind == "f":
            np.testing.assert_array_equal(values, b[name][2], err_msg=name)  # bit for bit
        else:
            assert np.array_equal(values, b[name][2]), name


def _stream(plan, loaded, out: Path):
    """Run with the writer as the sink, as ``pframe solve`` does; returns the result, the
    writer and the number of blocks delivered."""
    blocks = []
    writer = ResultWriter(out, plan, loaded, track=("displacement", "story_drift",
                                                    "contact_force"))

    def sink(quantity, first_row, rows):
        blocks.append((quantity, first_row, rows.shape))
        writer.append(quantity, first_row, rows)

    with writer:
        result = simulate(plan, sink=sink)
        writer.finish(result)
    return result, writer, blocks


@pytest.mark.slow
@pytest.mark.parametrize("kind", ["dimensional", "strides"])
def test_streamed_file_equals_the_written_file(tmp_path, monkeypatch, kind):
    source = WU2021 if kind == "dimensional" else _scene(tmp_path, _pi_with_strides())
    loaded = load_scene(source)
    plan = assemble(loaded.expanded)
    reference = simulate(plan)  # histories in memory
    written = write_result(tmp_path / "written.h5", reference, loaded)

    # blocks of a few dozen steps, which do not line up with the HDF5 chunks nor the strides
    monkeypatch.setattr(kernel_run, "STREAM_BYTES", 10_007)
    result, writer, blocks = _stream(plan, loaded, tmp_path / "streamed.h5")
    assert result.history == {}
    assert len(blocks) > 100 * len(plan.history)
    assert result.completed() and reference.completed()
    assert sorted(p.name for p in tmp_path.glob("*.h5")) == ["streamed.h5", "written.h5"]
    assert not list(tmp_path.glob(".*.tmp"))

    _assert_same_file(tmp_path / "streamed.h5", written)
    with h5py.File(tmp_path / "streamed.h5", "r") as f:
        for counter, name in (("solves", "newton_solves"), ("split_steps", "split_steps"),
                              ("factorisations", "factorisations"),
                              ("evaluations", "residual_evaluations"),
                              ("gathers", "gathered_values")):
            value = np.asarray(f.attrs[name])  # netCDF attributes are 1-D arrays
            assert value.dtype == np.int64 and value.size == 1  # counts may exceed 2^31
            assert value.item() == result.counter(counter)
            assert value.item() > 0 or counter == "split_steps"
        history = [q for q, _ in plan.history]
        assert f[history[0]].chunks is not None  # streamed: chunked storage
    # the running peaks are those of the histories in memory, column for column
    for q, peak in writer.peaks.items():
        np.testing.assert_array_equal(peak, np.nanmax(np.abs(reference.history[q][0]), axis=0))
    assert set(writer.peaks) == {"displacement", "story_drift", "contact_force"} & set(history)

    with xr.open_dataset(tmp_path / "streamed.h5", engine="h5netcdf") as ds:
        for q, every in plan.history:
            assert ds[q].sizes[ds[q].dims[0]] == plan.steps // every + 1
        if kind == "strides":
            assert {"t", "t_every_3", "t_every_7"} <= set(ds.coords)
            assert ds["ground_acceleration"].dims == ("t_every_3",)
            assert ds["t"].attrs["units"] == "1" and ds.attrs["units_system"] == "dimensionless"


def _failing(tmp_path: Path) -> Path:
    """The strides scene with a Newton tolerance at round-off: it stops early. The step
    depends on round-off, so the first tolerance that stops it in the middle of the run is
    taken (1e-18 stops it in its first step)."""
    for tolerance in ("8.0e-17", "6.0e-17", "1.0e-16", "1.0e-18"):
        text = _pi_with_strides().replace(
            "  tau: 50\n", f"  tau: 50\n  newton: {{tolerance: {tolerance}}}\n")
        model = _scene(tmp_path, text, "failing.yaml")
        loaded = load_scene(model)
        result = simulate(assemble(loaded.expanded))
        if 1 < result.states_done() < result.plan.steps:
            break
    return model


@pytest.mark.slow
def test_run_that_stops_early_streams_the_states_computed(tmp_path, monkeypatch, capsys):
    model = _failing(tmp_path)
    out = tmp_path / "failing.h5"
    monkeypatch.setattr(kernel_run, "STREAM_BYTES", 10_007)  # it stops inside a block
    assert main(["solve", str(model), "-o", str(out)]) == 1
    assert "marked incomplete" in capsys.readouterr().err
    assert sorted(p.name for p in tmp_path.iterdir()) == ["failing.h5", "failing.yaml"]

    loaded = load_scene(model)
    plan = assemble(loaded.expanded)
    reference = simulate(plan)
    assert not reference.completed()
    done = reference.states_done()
    assert done < plan.steps
    _assert_same_file(out, write_result(tmp_path / "written.h5", reference, loaded))
    with xr.open_dataset(out, engine="h5netcdf") as ds:
        assert ds.attrs["complete"] == 0 and ds.attrs["steps_completed"] == done - 1
        for q, every in plan.history:
            rows = (done - 1) // every + 1
            assert ds[q].shape[0] == ds[ds[q].dims[0]].size == rows  # exactly the states computed
            assert np.all(np.isfinite(ds[q].values))
            np.testing.assert_allclose(ds[ds[q].dims[0]].values,
                                       np.arange(rows) * every * ds.attrs["dtau"], rtol=1e-12)


@pytest.mark.slow
def test_rows_after_a_stop_are_nan_held_and_streamed(tmp_path, monkeypatch):
    """The kernel leaves the rows of the states after a member's stop unwritten (the history
    buffers are not filled beforehand): they are NaN, in the histories held in memory and in
    the rows streamed to a sink, and every row before the stop is finite."""
    loaded = load_scene(_failing(tmp_path))
    plan = assemble(loaded.expanded)
    held = simulate(plan)
    done = held.states_done()
    assert not held.completed() and 0 < done < plan.steps
    monkeypatch.setattr(kernel_run, "STREAM_BYTES", 10_007)  # it stops inside a call
    streamed = {}

    def sink(quantity, first, rows):
        streamed.setdefault(quantity, []).append((first, rows.copy()))

    simulate(plan, sink=sink)
    for q, every in plan.history:
        rows = held.history[q][0]
        computed = (done - 1) // every + 1  # rows of the states 0 .. done - 1
        assert rows.shape[0] == plan.steps // every + 1
        assert np.all(np.isfinite(rows[:computed])) and np.all(np.isnan(rows[computed:]))
        pieces = streamed[q]
        assert [first for first, _ in pieces] == list(
            np.cumsum([0] + [p.shape[1] for _, p in pieces[:-1]]))
        joined = np.concatenate([p[0] for _, p in pieces])
        assert joined.shape[0] > computed  # the call it stopped in went on past its stop
        np.testing.assert_array_equal(joined, rows[:joined.shape[0]])


def test_interrupted_run_leaves_nothing(tmp_path, monkeypatch, capsys):
    model = _scene(tmp_path, WU2021.read_text(encoding="utf-8"))
    out = tmp_path / "result.h5"
    out.write_bytes(b"an earlier result")
    monkeypatch.setattr(kernel_run, "STREAM_BYTES", 100_000)
    calls = []
    original = ResultWriter.append

    def interrupted(self, quantity, first_row, rows):
        calls.append(quantity)
        if len(calls) == 20:  # Ctrl-C in the middle of the run
            assert self.tmp.exists()
            raise KeyboardInterrupt
        original(self, quantity, first_row, rows)

    monkeypatch.setattr(ResultWriter, "append", interrupted)
    assert main(["solve", str(model), "-o", str(out), "--overwrite"]) == 130
    assert "interrupted; no output written" in capsys.readouterr().err
    assert len(calls) == 20
    assert sorted(p.name for p in tmp_path.iterdir()) == ["result.h5", "scene.yaml"]
    assert out.read_bytes() == b"an earlier result"


def test_summary_peaks_from_streamed_histories(tmp_path, capsys):
    """Without envelopes the summary takes the peaks from the histories: the streamed run
    prints what the histories in memory give."""
    text = WU2021.read_text(encoding="utf-8")
    text = text[:text.index("  - kind: envelope")]
    model = _scene(tmp_path, text)
    out = tmp_path / "result.h5"
    assert main(["solve", str(model), "-o", str(out)]) == 0
    streamed = capsys.readouterr().out.splitlines()

    loaded = load_scene(model)
    plan = assemble(loaded.expanded)
    result = simulate(plan)
    assert result.envelope == {} and result.history
    solve_command._summary(loaded, plan, result, out)
    in_memory = capsys.readouterr().out.splitlines()
    assert "peak force" in "\n".join(in_memory) and "peak storey drift" in "\n".join(in_memory)
    # all but the last line (timings)
    assert streamed[:-1] == in_memory[:-1] and len(streamed) == len(in_memory)


@pytest.mark.slow
def test_memory_stays_bounded(tmp_path):
    """2,000,000 steps with the paper's histories (27 columns): 412 MiB in memory. The
    streamed run's peak RSS stays below half of that above the same command's for a short run
    (interpreter, numba, h5py, the kernel)."""
    text = WU2021.read_text(encoding="utf-8")
    assert DURATION in text
    long = _scene(tmp_path, text.replace(DURATION, f"  duration: {7.957747154594767 * 40!r}\n"),
                  "long.yaml")
    short = _scene(tmp_path, text.replace(DURATION, f"  duration: {7.957747154594767 / 50!r}\n"),
                   "short.yaml")
    plan = assemble(load_scene(long).expanded)
    assert plan.steps == 2_000_000
    columns = sum(len(plan.node_names) if q in ("displacement", "velocity")
                  else len(plan.story_names) if q.startswith("story")
                  else len(plan.contact_names) for q, _ in plan.history)
    assert columns == 27
    held = (plan.steps + 1) * columns * 8

    script = Path(sys.executable).with_name("pframe")
    command = [str(script)] if script.exists() else [sys.executable, "-m", "pframe.cli"]
    # each run in its own parent, so that RUSAGE_CHILDREN is that run's peak alone
    measure = ("import resource, subprocess, sys; "
               "run = subprocess.run(sys.argv[1:], capture_output=True, text=True); "
               "sys.stderr.write(run.stderr); "
               "print(run.returncode, resource.getrusage(resource.RUSAGE_CHILDREN).ru_maxrss)")

    def peak(model: Path) -> int:
        out = model.with_suffix(".h5")
        run = subprocess.run([sys.executable, "-c", measure, *command, "solve", str(model),
                              "-q", "-o", str(out)], capture_output=True, text=True, timeout=120)
        code, kib = run.stdout.split()
        assert code == "0", run.stderr
        return int(kib) * 1024

    allowance = peak(short)
    streamed = peak(long)
    with h5py.File(tmp_path / "long.h5", "r") as f:
        assert f["displacement"].shape == (plan.steps + 1, 6)
        assert f.attrs["complete"] == 1
    assert streamed < allowance + held / 2, (
        f"peak {streamed / 2**20:.0f} MiB, short run {allowance / 2**20:.0f} MiB, "
        f"histories {held / 2**20:.0f} MiB")


@pytest.mark.slow
def test_a_result_file_is_the_one_h5netcdf_writes_alone(tmp_path, monkeypatch):
    """The writer finds each HDF5 object once (record.netcdf._Found), where h5netcdf looks
    it up again at every use: the file is the one h5netcdf writes alone, object for object,
    attribute for attribute, though h5netcdf replaces each time coordinate's placeholder (a
    deletion a kept lookup must not outlive)."""
    import h5netcdf

    from pframe.record import netcdf

    loaded = load_scene(_scene(tmp_path, _pi_with_strides()))
    result = simulate(assemble(loaded.expanded))
    found = write_result(tmp_path / "found.nc", result, loaded)

    def alone(target):
        f = h5netcdf.File.__new__(h5netcdf.File)
        f._closed = True
        f.__init__(target, "w", track_order=True)
        return f

    monkeypatch.setattr(netcdf, "_open", alone)
    reference = write_result(tmp_path / "alone.nc", result, loaded)
    _assert_same_file(found, reference, ignore={"date_created", "history"})
    with h5py.File(found, "r") as f:
        assert {"t", "t_every_3", "t_every_7"} <= set(f)
        assert f["t_every_3"].is_scale and f["t_every_3"][1] > 0  # the values written
