"""Sweeps and gap audits over records of different lengths: each record runs to its end (plus
the time the base scene analyses after its own record), or the result says what was cut.

The long record is quiet for 2.5 s and carries its peak at 2.6 s, after the short record
(and the base scene's duration) has ended: a run cut at the base's duration never sees it.
Scenes share the structure of tests/test_sweep.py's (one kernel).
"""

from __future__ import annotations

import warnings

import numpy as np
import pytest
import yaml
from test_sweep import BASE

import pframe
from pframe.cli import main
from pframe.errors import InputError
from pframe.sweep import load_sweep, run_sweep

DT = 2.0e-4
SHORT_END = 1.0  # s
LONG_END = 3.0
PEAK_TIME = 2.6


def _records(folder):
    t = np.round(np.arange(0.0, SHORT_END + 1e-9, 0.01), 10)
    np.savetxt(folder / "short.txt", np.column_stack([t, 3.0 * np.sin(2 * np.pi * t)]))
    t = np.round(np.arange(0.0, LONG_END + 1e-9, 0.01), 10)
    a = 0.5 * np.sin(2 * np.pi * t)
    a += 25.0 * np.exp(-(((t - PEAK_TIME) / 0.08) ** 2)) * np.sin(2 * np.pi * 2.0 * (t - PEAK_TIME))
    np.savetxt(folder / "long.txt", np.column_stack([t, a]))
    assert abs(t[np.argmax(np.abs(a))] - PEAK_TIME) < 0.1


def _base(folder, duration: float, name: str = "base.yaml"):
    text = (BASE.replace("excitation: {kind: sine, amplitude: 9.81, frequency: 6.283185307179586}",
                         "excitation: {kind: record, file: short.txt}")
                .replace("duration: 1.5", f"duration: {duration!r}"))
    (folder / name).write_text(text, encoding="utf-8")
    return folder / name


def _sweep(folder, histories: bool = False, base: str = "base.yaml"):
    keep = ("keep: {envelopes: [peak_displacement, impact_count], histories: [displacement]}\n"
            if histories else "")
    (folder / "records.yaml").write_text(
        f"base: {base}\n"
        "axes:\n"
        "  - {name: record, path: excitation.file, values: [short.txt, long.txt]}\n"
        + keep, encoding="utf-8")
    return folder / "records.yaml"


def _single(folder, record: str, duration: float):
    """The variant as one scene given by hand: its record, run for ``duration``."""
    text = (folder / "base.yaml").read_text(encoding="utf-8")
    text = text.replace("file: short.txt", f"file: {record}")
    text = "\n".join(line if not line.strip().startswith("duration:")
                     else f"  duration: {duration!r}" for line in text.splitlines())
    (folder / f"single-{record}.yaml").write_text(text, encoding="utf-8")
    return pframe.solve(folder / f"single-{record}.yaml", progress=False)


@pytest.fixture(scope="module")
def swept(tmp_path_factory):
    """The base runs its 1 s record and 0.2 s after it; the sweep adds the 3 s record."""
    folder = tmp_path_factory.mktemp("records")
    _records(folder)
    _base(folder, SHORT_END + 0.2)
    out = folder / "records.h5"
    assert main(["sweep", str(_sweep(folder, histories=True)), "-o", str(out), "-q"]) == 0
    return folder, out


@pytest.mark.slow
def test_each_record_runs_to_its_end_plus_the_base_tail(swept, capsys):
    """The 3 s record runs 3.2 s (its length plus the base's 0.2 s after its record), reaches
    its late peak, and equals a single pframe.solve of that record over 3.2 s; cut at the
    base's 1.2 s (what a sweep did before) its peak is far smaller."""
    folder, out = swept
    with pframe.open(out) as ds:
        np.testing.assert_allclose(ds.duration.values, [SHORT_END + 0.2, LONG_END + 0.2],
                                   rtol=1e-12)
        np.testing.assert_allclose(ds.record_duration.values, [SHORT_END, LONG_END], rtol=1e-12)
        np.testing.assert_array_equal(ds.steps_completed.values,
                                      np.round(ds.duration.values / DT).astype(int))
        swept_long = ds.peak_displacement.values[1]
        swept_short = ds.peak_displacement.values[0]
        history = ds.displacement.values  # (record, t, node)
        assert np.all(np.isfinite(history[1]))
        short_rows = int(round((SHORT_END + 0.2) / DT)) + 1
        assert np.all(np.isfinite(history[0, :short_rows]))
        assert np.all(np.isnan(history[0, short_rows:]))  # the short run has ended
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        whole = _single(folder, "long.txt", LONG_END + 0.2)
        cut = _single(folder, "long.txt", SHORT_END + 0.2)
        short = _single(folder, "short.txt", SHORT_END + 0.2)
    np.testing.assert_allclose(swept_long, whole.peak_displacement.values, rtol=1e-12)
    np.testing.assert_allclose(swept_short, short.peak_displacement.values, rtol=1e-12)
    assert swept_long.max() > 3.0 * cut.peak_displacement.values.max()  # the late peak counts


def test_terminal_says_the_time_each_variant_ran(swept, capsys):
    folder, _ = swept
    out = folder / "again.h5"
    assert main(["sweep", str(folder / "records.yaml"), "-o", str(out)]) == 0
    text = capsys.readouterr().out
    assert "time analysed: 1.2 s: 1 variant (record=short.txt); 3.2 s: 1 variant " \
           "(record=long.txt)" in text


def test_variant_printed_for_pframe_solve_runs_its_record(swept, capsys):
    """pframe sweep --variant 1 prints the long record's variant with its fitted duration."""
    folder, _ = swept
    assert main(["sweep", str(folder / "records.yaml"), "--variant", "1"]) == 0
    data = yaml.safe_load(capsys.readouterr().out)
    assert data["analysis"]["duration"] == pytest.approx(LONG_END + 0.2, rel=1e-12)
    assert data["excitation"]["file"].endswith("long.txt")


@pytest.mark.slow
def test_a_base_that_cuts_its_record_keeps_the_cut_and_says_so(tmp_path, capsys):
    """A base that stops before its own record ends asks for a cut: every variant keeps its
    duration, and each variant whose record goes on says so in the file and on stderr."""
    _records(tmp_path)
    _base(tmp_path, 0.8)
    out = tmp_path / "cut.h5"
    assert main(["sweep", str(_sweep(tmp_path)), "-o", str(out), "-q"]) == 0
    err = capsys.readouterr().err
    with pframe.open(out) as ds:
        np.testing.assert_allclose(ds.duration.values, [0.8, 0.8], rtol=1e-12)
        text = ds.attrs["warnings"]
    for line in (text, err):
        assert "variant 0 (record=short.txt): the analysis stops at 0.8 s, but the record " \
               "runs to 1 s (its peak ground acceleration is inside)" in line
        assert "variant 1 (record=long.txt): the analysis stops at 0.8 s, but the record " \
               "runs to 3 s (its peak ground acceleration (t = 2.55 s) is past the end" in line


@pytest.mark.slow
def test_python_sweep_warns_of_a_cut_record(tmp_path):
    _records(tmp_path)
    _base(tmp_path, 0.8)
    with pytest.warns(UserWarning) as caught:
        ds = pframe.sweep(_sweep(tmp_path), progress=False)
    said = [str(w.message) for w in caught]
    assert any("variant 1 (record=long.txt): the analysis stops at 0.8 s" in w for w in said)
    assert any("variant 0 (record=short.txt): the analysis stops at 0.8 s" in w for w in said)
    assert ds.duration.values.tolist() == pytest.approx([0.8, 0.8])


def test_duration_axis_is_refused_under_records(tmp_path):
    _records(tmp_path)
    _base(tmp_path, 1.2)
    (tmp_path / "bad.yaml").write_text(
        "base: base.yaml\naxes:\n"
        "  - {name: record, path: excitation.file, values: [short.txt, long.txt]}\n"
        "  - {name: T, path: analysis.duration, values: [1.0, 2.0]}\n", encoding="utf-8")
    with pytest.raises(InputError, match="axis 'T' sets analysis.duration, but under a record"):
        run_sweep(load_sweep(tmp_path / "bad.yaml"), tmp_path / "bad.h5")


def test_gap_audit_runs_every_record_to_its_end(tmp_path):
    """A gap audit over the two records runs both past their ends (the default duration), so
    the long record's late peak sets its g_req as a single no-contact run of it does; a
    --duration that stops before a record's end says so per record."""
    from pframe.gap import audit

    _records(tmp_path)
    scene = _base(tmp_path, 1.2)
    files = [tmp_path / "short.txt", tmp_path / "long.txt"]
    ds = audit(scene, files)
    assert ds.attrs["duration"] >= LONG_END
    assert ds.attrs["warnings"] == ""
    np.testing.assert_allclose(ds.record_duration.values, [SHORT_END, LONG_END])
    # the long record alone, without contacts, as one pframe.solve over its length
    text = scene.read_text(encoding="utf-8").replace("file: short.txt", "file: long.txt")
    data = yaml.safe_load(text)
    data["contacts"] = []
    data["analysis"]["duration"] = float(ds.attrs["duration"])
    data["recorders"] = [{"kind": "history", "quantities": ["displacement"]}]
    (tmp_path / "alone.yaml").write_text(yaml.safe_dump(data), encoding="utf-8")
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        alone = pframe.solve(tmp_path / "alone.yaml", progress=False)
    u = alone.displacement
    g_req = max(float((u.sel(node_name=f"A/{k}") - u.sel(node_name=f"B/{k}")).max())
                for k in (1, 2))
    simulated = ds.gap_required.sel(rule_name="simulated", record_name="long.txt").values
    assert float(simulated.max()) == pytest.approx(g_req, rel=1e-9)

    with pytest.warns(UserWarning, match="record long.txt: the runs stop at 1.5 s, but the "
                                          r"record runs to 3 s \(its peak ground acceleration "
                                          r"\(t = 2.55 s\) is past the end"):
        cut = audit(scene, files, duration=1.5)
    assert "record long.txt: the runs stop at 1.5 s" in cut.attrs["warnings"]
    assert "short.txt" not in cut.attrs["warnings"]
    # the scene's own record, cut by its own duration
    with pytest.warns(UserWarning, match=r"record short.txt: the runs stop at 0.8 s, but the "
                                          r"record runs to 1 s \(its peak ground acceleration "
                                          r"is inside\); lengthen the scene's analysis.duration"):
        audit(_base(tmp_path, 0.8, "cut.yaml"))
