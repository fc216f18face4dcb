"""The gap audit: the combination rules' closed forms, the simulated critical gap against the
steady state of two SDOFs under a sine, its consistency with runs that have the contacts, the
fragility fit, resuming, and bad input."""

import json
import math
from pathlib import Path

import numpy as np
import pytest
import xarray as xr

import pframe
from pframe.cli import main
from pframe.errors import InputError
from pframe.gap import audit, cqc_correlation, fit_lognormal, lognormal_probability, separations
from pframe.gap.audit import prepare
from pframe.gap.runs import batch_plan
from pframe.kernel import simulate

REPO = Path(__file__).resolve().parents[1]
RECORDS = (REPO / ".." / "shared" / "records").resolve()
needs_records = pytest.mark.skipif(
    not RECORDS.is_dir(), reason=f"the PEER records folder {RECORDS} (../shared/records "
    "beside the repository) is absent; the records are not part of the project")


# --------------------------------------------------------------------------------------------
# the rules
# --------------------------------------------------------------------------------------------

@pytest.mark.parametrize("r, rho, ddc", [(0.5, 0.018486, 0.116), (0.9, 0.473, 0.089),
                                         (1.0, 1.000, 0.040)])
def test_worked_values(r, rho, ddc):
    """xi = 5 %, u_A = 0.10 m, u_B = 0.06 m. (The issue prints rho = 0.019 at r = 0.5; the
    formula gives 0.01849, which rounds to 0.018; the DDC value 0.116 is the same either way.)"""
    got = cqc_correlation(r * 1.7, 1.7, 0.05, 0.05)
    assert got == pytest.approx(rho, abs=5e-4 if rho != 0.018486 else 1e-6)
    out = separations(0.10, 0.06, got)
    assert out["DDC"] == pytest.approx(ddc, abs=5e-4)
    assert out["SRSS"] == pytest.approx(0.117, abs=5e-4)
    assert out["ABS"] == pytest.approx(0.160, abs=1e-12)


def test_equal_periods_correlate_fully_and_ddc_is_the_difference():
    for xi in (0.0, 0.02, 0.05, 0.3):
        assert cqc_correlation(0.8, 0.8, xi, xi) == pytest.approx(1.0, abs=1e-15)
    rho = cqc_correlation(0.8, 0.8, 0.05, 0.05)
    assert separations(0.1, 0.06, rho)["DDC"] == pytest.approx(0.04, rel=1e-12)


def test_correlation_is_symmetric_and_falls_with_period_ratio():
    ta, tb, xa, xb = 0.4, 1.1, 0.02, 0.07
    assert cqc_correlation(ta, tb, xa, xb) == pytest.approx(cqc_correlation(tb, ta, xb, xa),
                                                            rel=1e-14)
    r = np.linspace(0.2, 1.0, 50)
    rho = cqc_correlation(r, 1.0, 0.05, 0.05)
    assert np.all(np.diff(rho) > 0) and rho[-1] == pytest.approx(1.0)
    u_a, u_b = 0.1, 0.06
    out = separations(u_a, u_b, rho, en_coincident=True)
    assert np.all(out["DDC"] <= out["SRSS"] + 1e-15) and np.all(out["SRSS"] <= out["ABS"])
    assert out["SRSS_EN_0.7"] == pytest.approx(0.7 * out["SRSS"])


# --------------------------------------------------------------------------------------------
# the simulated critical gap: two SDOFs on their steady state under a sine
# --------------------------------------------------------------------------------------------

def _sdof_pair(tmp_path, period_a=0.4, period_b=0.9, xi=0.05, a=2.0, big_w=2 * math.pi / 0.6):
    mass = 1000.0
    amplitude = {}
    for name, period in (("A", period_a), ("B", period_b)):
        w = 2 * math.pi / period
        amplitude[name] = -a / (w * w - big_w * big_w + 2j * xi * w * big_w)
    scene = {
        "title": "two SDOFs on their steady state",
        "buildings": [{"name": n, "floors": 1, "mass": mass,
                       "story": {"material": "elastic",
                                 "stiffness": mass * (2 * math.pi / p) ** 2}}
                      for n, p in (("A", period_a), ("B", period_b))],
        "contacts": [{"name": "roof", "nodes": ["A/1", "B/1"], "gap": 0.5, "law": "linear",
                      "stiffness": 1.0e7}],
        "damping": {"ratio": xi},
        "excitation": {"kind": "sine", "amplitude": a, "frequency": big_w},
        "initial_conditions": {
            "displacement": {f"{n}/1": amplitude[n].imag for n in "AB"},
            "velocity": {f"{n}/1": (1j * big_w * amplitude[n]).imag for n in "AB"}},
        "analysis": {"dt": 0.0005, "duration": 12.0},
    }
    path = tmp_path / "pair.yaml"
    path.write_text(json.dumps(scene))
    return path, amplitude


def test_simulated_gap_is_the_steady_state_relative_amplitude(tmp_path):
    """u_A - u_B = Im((U_A - U_B) e^{i W t}) from t = 0: g_req = |U_A - U_B|, and the peaks
    are |U_A| and |U_B|. The plan's first periods and damping are the SDOFs' own."""
    path, amplitude = _sdof_pair(tmp_path)
    ds = audit(path)
    g = ds.gap_required.sel(contact_name="roof").isel(record=0, level=0)
    expected = abs(amplitude["A"] - amplitude["B"])
    assert float(g.sel(rule_name="simulated")) == pytest.approx(expected, rel=2e-4)
    assert float(ds.peak_displacement_left[0, 0, 0]) == pytest.approx(abs(amplitude["A"]), rel=2e-4)
    assert float(ds.peak_displacement_right[0, 0, 0]) == pytest.approx(abs(amplitude["B"]), rel=2e-4)
    assert ds.period.values == pytest.approx([0.4, 0.9], rel=1e-12)
    assert ds.damping_ratio.values == pytest.approx([0.05, 0.05], rel=1e-12)
    rho = cqc_correlation(0.4, 0.9, 0.05, 0.05)
    assert float(ds.correlation[0]) == pytest.approx(rho, rel=1e-12)
    u_a, u_b = abs(amplitude["A"]), abs(amplitude["B"])
    assert float(g.sel(rule_name="DDC")) == pytest.approx(
        math.sqrt(u_a**2 + u_b**2 - 2 * rho * u_a * u_b), rel=3e-4)
    assert float(g.sel(rule_name="ABS")) == pytest.approx(u_a + u_b, rel=2e-4)


def test_equal_sdofs_need_no_gap(tmp_path):
    """Identical buildings on identical ground move together: g_req = 0 and DDC (rho = 1)
    gives |u_A - u_B| = 0, while ABS and SRSS ask for a gap."""
    path, _ = _sdof_pair(tmp_path, period_a=0.7, period_b=0.7)
    ds = audit(path)
    g = ds.gap_required.isel(record=0, level=0, contact=0)
    assert float(g.sel(rule_name="simulated")) < 1e-12
    assert float(g.sel(rule_name="DDC")) < 1e-9
    assert float(g.sel(rule_name="SRSS")) > 1e-3


# --------------------------------------------------------------------------------------------
# consistency with runs that have the contacts
# --------------------------------------------------------------------------------------------

PAIR = """
title: a soft and a stiff 3-storey frame, linear contacts
buildings:
  - {name: A, floors: 3, mass: 250.0, story: {material: bilinear, stiffness: 197392.088,
                                              yield_drift: 0.05, alpha: 0.1}}
  - {name: B, floors: 3, mass: 1000.0, story: {material: elastic, stiffness: 1973920.88}}
contacts:
  - {name: floor-1, nodes: [A/1, B/1], gap: 0.05, law: linear, stiffness: 2.0e7}
  - {name: floor-2, nodes: [A/2, B/2], gap: 0.05, law: linear, stiffness: 2.0e7}
  - {name: floor-3, nodes: [A/3, B/3], gap: 0.05, law: linear, stiffness: 2.0e7}
damping: {ratio: 0.05}
excitation: {kind: cycloidal, type: B, amplitude: 4.0, period: 0.9}
analysis: {dt: 0.002, duration: 8.0}
"""


def _impacts(inputs, gaps):
    """Impacts per variant and contact of the audit's variants run with their contacts at
    ``gaps`` (variants, contacts)."""
    acc = inputs.accelerations(np.arange(inputs.count))
    plan = batch_plan(inputs.loaded, acc, inputs.steps, contacts_gaps=gaps, dt=inputs.dt)
    result = simulate(plan)
    assert all(result.completed(b) for b in range(plan.batch))
    return result.impacts


def _check_consistency(path, suite, levels):
    ds = audit(path, suite, levels=levels)
    inputs = prepare(path, suite, levels=levels)
    g = ds.gap_required.sel(rule_name="simulated").values.reshape(inputs.count, -1)
    assert np.all(g > 0)
    assert np.all(_impacts(inputs, g * (1 + 1e-6)) == 0)
    assert np.all(_impacts(inputs, g * (1 - 1e-3)).sum(axis=1) >= 1)


def test_critical_gap_is_consistent_with_contact_runs_under_pulses(tmp_path):
    """At g_req (1 + 1e-6) no contact closes; at g_req (1 - 1e-3) one does, for the scene's
    own pulse at three intensities (the nonlinear frame A yields at the largest)."""
    path = tmp_path / "pair.yaml"
    path.write_text(PAIR)
    _check_consistency(path, None, [0.2, 0.4, 0.8])


@needs_records
def test_critical_gap_is_consistent_with_contact_runs_over_the_records(tmp_path):
    path = tmp_path / "pair.yaml"
    path.write_text(PAIR)
    _check_consistency(path, RECORDS, [0.3])


# --------------------------------------------------------------------------------------------
# fragility, statistics, the file, resuming, bad input
# --------------------------------------------------------------------------------------------

def test_fragility_maximum_likelihood_recovers_a_lognormal():
    """With the expected counts of a lognormal (fractional counts), the likelihood's maximum
    is the lognormal itself; integer counts of a large sample land near it."""
    levels = np.array([0.1, 0.2, 0.3, 0.45, 0.6, 0.8, 1.0])
    n = np.full(levels.size, 1000.0)
    for median, beta in ((0.35, 0.4), (0.6, 0.25)):
        z = n * lognormal_probability(levels, median, beta)
        got = fit_lognormal(levels, n, z)
        assert got == pytest.approx((median, beta), rel=1e-5)
    rng = np.random.default_rng(5)
    z = rng.binomial(4000, lognormal_probability(levels, 0.35, 0.4))
    got = fit_lognormal(levels, np.full(levels.size, 4000), z)
    assert got == pytest.approx((0.35, 0.4), rel=0.05)
    assert all(math.isnan(x) for x in fit_lognormal(levels, n, np.zeros(levels.size)))
    step = np.where(levels > 0.4, n, 0.0)  # none, then all: no finite dispersion fits
    assert all(math.isnan(x) for x in fit_lognormal(levels, n, step))


@pytest.mark.slow
def test_statistics_pounding_and_file(tmp_path):
    path = tmp_path / "pair.yaml"
    path.write_text(PAIR)
    out = tmp_path / "audit.h5"
    ds = audit(path, levels=[0.2, 0.4, 0.8, 1.6], gap=0.03, output=out, en_coincident=True)
    read = pframe.open(out).load()
    assert read.gap_required.dims == ("record", "level", "contact", "rule")
    assert list(read.rule_name.values) == ["ABS", "SRSS", "DDC", "SRSS_EN_0.7", "simulated"]
    # names are the coordinate values of their dimensions, in the file's Dataset as in memory
    assert read.rule.values.tolist() == read.rule_name.values.tolist()
    assert read.gap_statistics.sel(rule="DDC", statistic="p84").to_series().index.names == [
        "level", "contact"]
    assert ds.gap_required.sel(rule="SRSS").to_series().index.get_level_values(
        "record").tolist()[0] == str(ds.record_name.values[0])
    # the file holds the Dataset, and says when and how it was written
    assert {"date_created", "history"} <= set(read.attrs)
    xr.testing.assert_equal(read, ds)
    g = ds.gap_required.sel(rule_name="simulated")
    pounds = (g > 0.03).values
    assert np.array_equal(ds.pounds.values == 1, pounds)
    assert ds.pounding_fraction.values == pytest.approx(pounds.mean(axis=0))
    stats = ds.gap_statistics.sel(rule_name="simulated")
    assert stats.sel(statistic_name="max").values == pytest.approx(g.max("record").values)
    assert stats.sel(statistic_name="median").values == pytest.approx(g.median("record").values)
    assert not list(tmp_path.glob("*.parts")) and not list(tmp_path.glob(".*tmp"))


@pytest.mark.slow
def test_stopped_audit_resumes_to_the_same_result(tmp_path):
    path = tmp_path / "pair.yaml"
    path.write_text(PAIR)
    levels = [0.2, 0.3, 0.5, 0.8, 1.2]
    whole = audit(path, levels=levels, chunk=2)

    calls = []

    def stop_after_first_chunk(done, total):
        calls.append(done)
        if done > 2:  # inside the second chunk: the first is saved
            raise KeyboardInterrupt

    out = tmp_path / "audit.h5"
    with pytest.raises(KeyboardInterrupt):
        audit(path, levels=levels, chunk=2, output=out, progress=stop_after_first_chunk)
    parts = tmp_path / "audit.h5.parts"
    assert not out.exists() and len(list(parts.glob("chunk-*.npz"))) == 1
    done_before = []
    resumed = audit(path, levels=levels, chunk=2, output=out,
                    progress=lambda done, total: done_before.append(done))
    assert min(done_before) >= 2  # the first chunk was not run again
    xr.testing.assert_identical(resumed, whole)
    assert out.exists() and not parts.exists()
    # batches of another audit are refused, not mixed in, unless --overwrite
    with pytest.raises(KeyboardInterrupt):
        audit(path, levels=levels, chunk=2, output=tmp_path / "other.h5",
              progress=stop_after_first_chunk)
    with pytest.raises(InputError, match="other.h5.parts: holds batches of another audit"):
        audit(path, levels=levels[:4], chunk=2, output=tmp_path / "other.h5")
    changed = audit(path, levels=levels[:4], chunk=2, output=tmp_path / "other.h5",
                    overwrite=True)
    xr.testing.assert_identical(changed.gap_required,
                                whole.gap_required.isel(level=slice(0, 4)))


@pytest.mark.parametrize("args, message", [
    (["--levels", "0.1,x"], "--levels"),
    (["--levels", "0.1,-0.2"], "positive"),
    (["--measure", "sd:1"], "--measure"),
    (["--measure", "sa:C", "--levels", "0.2"], "neither seconds nor a building"),
    (["--gap", "-0.1"], "--gap"),
    (["--chunk", "0"], "--chunk"),
    (["--suite", "missing-folder/x.AT2"], "not found"),
])
def test_bad_arguments_exit_2_and_write_nothing(tmp_path, capsys, args, message):
    path = tmp_path / "pair.yaml"
    path.write_text(PAIR)
    code = main(["gap", str(path), "-o", str(tmp_path / "out.h5"), *args])
    assert code == 2 and message in capsys.readouterr().err
    assert not (tmp_path / "out.h5").exists()


def test_scene_without_contacts_is_refused(tmp_path, capsys):
    path = tmp_path / "alone.yaml"
    path.write_text(PAIR.split("contacts:")[0] + PAIR.split("floor-3, nodes: [A/3, B/3], gap: "
                                                           "0.05, law: linear, stiffness: 2.0e7}")[1])
    with pytest.raises(InputError, match="alone.yaml: the scene has no contacts"):
        audit(path)
    assert main(["gap", str(path)]) == 2


@pytest.mark.slow
def test_command_prints_table_and_plot_draws_it(tmp_path, capsys):
    path = tmp_path / "pair.yaml"
    path.write_text(PAIR)
    out = tmp_path / "audit.h5"
    assert main(["gap", str(path), "--levels", "0.2,0.4,0.8,1.6", "--gap", "0.03", "-o",
                 str(out)]) == 0
    text = capsys.readouterr().out
    assert "ABS" in text and "simulated" in text and "fragility" in text
    ds = pframe.open(out).load()
    row = f"{float(ds.level[0]):>8.4g} floor-1"
    assert row in text
    pytest.importorskip("matplotlib")
    assert main(["plot", str(out), "-o", str(tmp_path / "gap.png")]) == 0
    assert (tmp_path / "gap.png").stat().st_size > 10_000
    # the figure says what was run (not the scene's own title), and that a dispersion
    # fitted to one record is rough
    from pframe.plot.gap import gap_figure

    fig, notes = gap_figure(out)
    title = fig.get_suptitle()
    assert "a soft and a stiff" not in title
    assert title == "Gap audit of pair.yaml: record cycloidal, scaled to PGA = 0.2, 0.4, 0.8, 1.6 g"
    # one record pounds at no level or every level: no fit; given one, the label says it
    # rests on one record (the file rewritten through the Dataset, names and all)
    from pframe.record.netcdf import write_dataset

    assert not np.isfinite(float(ds.fragility_dispersion_any))
    fitted = ds.assign(fragility_median_any=xr.full_like(ds.fragility_median_any, 0.5),
                       fragility_dispersion_any=xr.full_like(ds.fragility_dispersion_any, 0.04))
    write_dataset(fitted, tmp_path / "fitted.nc")
    fig, notes = gap_figure(tmp_path / "fitted.nc")
    labels = [line.get_label() for line in fig.axes[1].get_lines()
              if line.get_label().startswith("lognormal fit")]
    assert len(labels) == 1 and "dispersion 0.04" in labels[0]
    assert "from 1 record: a rough estimate (use 10 or more)" in labels[0]
    assert any("rough estimate" in note for note in notes)


def test_runs_cut_before_many_records_end_are_counted_not_listed():
    """The runs that stop before their record's end are named one by one up to ten; the
    others are one warning that counts them, and those whose peak ground acceleration is
    past the end (10^4 stochastic motions of a study are not 10^4 lines of warnings)."""
    from pframe.gap.audit import CUT_NAMED, cut_warnings

    names = [f"rec{i}" for i in range(25)]
    ends = [10.0] * 24 + [7.0]  # the last ends before the runs do
    peaks = [1.0] * 12 + [9.0] * 12 + [1.0]
    out = cut_warnings(names, ends, peaks, 8.0, 0.01, "shorten them")
    assert CUT_NAMED == 10 and len(out) == 11
    assert all(line.startswith(f"record rec{i}: the runs stop at 8 s") for i, line in
               enumerate(out[:10]))
    assert out[10].startswith("14 more records: the runs stop at 8 s")
    assert "12 of them have their peak ground acceleration past it" in out[10]
