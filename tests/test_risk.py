"""The risk chain (docs/risk.md): maximum-likelihood fragilities recover known parameters and
their Fisher-information bounds cover them as often as they claim; the mean annual frequency
against Cornell et al.'s closed form; hazard tables in the USGS and OpenQuake forms; subset
simulation against crude Monte Carlo at about 1e-3; a study on the paper's pair under a pulse:
pounding in the runs with contacts exactly when the critical gap of the runs without them
exceeds the gap, and the gap at target recomputed from the file's own runs; bad input."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest
from scipy.stats import norm

from pframe.cli import main
from pframe.errors import InputError
from pframe.risk import (
    HazardCurve,
    Uncertain,
    closed_form_maf,
    crude_monte_carlo,
    fit_capacities,
    fit_cloud,
    fit_msa,
    latin_hypercube,
    mean_annual_frequency,
    read_hazard,
    subset_simulation,
)

REPO = Path(__file__).resolve().parents[1]


# --------------------------------------------------------------------------------------------
# fragilities by maximum likelihood
# --------------------------------------------------------------------------------------------

@pytest.mark.slow
def test_msa_fit_recovers_known_parameters_and_its_bounds_cover_them():
    """Binomial stripes drawn from theta = 0.6 g, beta = 0.4: the estimates are close with many
    runs, and the 90 % Fisher-information interval of theta covers the truth in about 90 % of
    replications with few runs."""
    theta, beta = 0.6, 0.4
    levels = np.array([0.2, 0.3, 0.45, 0.6, 0.8, 1.0, 1.3])
    rng = np.random.default_rng(1)
    p = norm.cdf(np.log(levels / theta) / beta)
    big = fit_msa(levels, np.full(7, 4000), rng.binomial(4000, p))
    assert big.median == pytest.approx(theta, rel=0.02)
    assert big.dispersion == pytest.approx(beta, rel=0.04)
    covered = [0, 0]
    trials = 300
    for _ in range(trials):
        f = fit_msa(levels, np.full(7, 30), rng.binomial(30, p))
        (m_lo, m_hi), (b_lo, b_hi) = f.bounds(0.90)
        covered[0] += m_lo <= theta <= m_hi
        covered[1] += b_lo <= beta <= b_hi
    assert 0.84 <= covered[0] / trials <= 0.96
    assert 0.80 <= covered[1] / trials <= 0.97


def test_msa_fit_says_why_it_is_absent():
    levels = [0.2, 0.4, 0.6]
    assert "no run exceeds" in fit_msa(levels, [5, 5, 5], [0, 0, 0]).note
    assert "all-or-nothing" in fit_msa(levels, [5, 5, 5], [0, 5, 5]).note
    assert not fit_msa(levels, [5, 5, 5], [0, 5, 5]).fitted


def test_capacity_fit_with_censoring_recovers_the_lognormal():
    """IDA capacities lnN(ln 0.8, 0.35), those above 1.2 g censored there."""
    rng = np.random.default_rng(2)
    c = 0.8 * np.exp(0.35 * rng.standard_normal(5000))
    cens = c > 1.2
    f = fit_capacities(np.minimum(c, 1.2), cens)
    assert cens.mean() > 0.1
    assert f.median == pytest.approx(0.8, rel=0.02)
    assert f.dispersion == pytest.approx(0.35, rel=0.04)
    # ignoring the censoring is biased: the check can fail
    naive = fit_capacities(np.minimum(c, 1.2))
    assert abs(naive.dispersion - 0.35) > 0.02


def test_cloud_regression_with_censoring_gives_the_implied_fragility():
    """ln D = ln 0.02 + 1.1 ln IM + N(0, 0.3^2): P(D > d | IM) is lognormal with
    theta = exp((ln d - a) / b), beta = s / b; demands above 0.04 censored."""
    rng = np.random.default_rng(3)
    im = np.exp(rng.uniform(np.log(0.1), np.log(3.0), 20000))
    d = 0.02 * im ** 1.1 * np.exp(0.3 * rng.standard_normal(im.size))
    reg = fit_cloud(im, np.minimum(d, 0.04), censor=0.04)
    assert (d >= 0.04).mean() > 0.1
    assert reg.b == pytest.approx(1.1, rel=0.02) and reg.s == pytest.approx(0.3, rel=0.03)
    f = reg.fragility(0.03)
    assert f.median == pytest.approx(math.exp((math.log(0.03) - math.log(0.02)) / 1.1),
                                      rel=0.02)
    assert f.dispersion == pytest.approx(0.3 / 1.1, rel=0.04)


# --------------------------------------------------------------------------------------------
# hazard and mean annual frequency
# --------------------------------------------------------------------------------------------

@pytest.mark.parametrize("theta, beta, k0, k", [(0.5, 0.4, 1e-4, 2.5), (1.2, 0.6, 3e-4, 3.0),
                                                (0.2, 0.25, 5e-5, 1.8)])
def test_maf_against_the_closed_form(theta, beta, k0, k):
    """lambda = k0 theta^-k exp(k^2 beta^2 / 2) (Cornell et al. 2002) for a lognormal
    fragility over a power-law hazard curve."""
    curve = HazardCurve.power_law(k0, k, 1e-4, 1e3)
    got, above = mean_annual_frequency(lambda x: norm.cdf(np.log(x / theta) / beta), curve)
    assert got == pytest.approx(closed_form_maf(theta, beta, k0, k), rel=2e-3)
    assert above < 1e-6


def test_maf_tells_the_share_from_above_a_short_table():
    curve = HazardCurve.power_law(1e-4, 2.5, 0.01, 0.6)
    total, above = mean_annual_frequency(lambda x: norm.cdf(np.log(x / 0.5) / 0.4), curve)
    assert above > 0.2
    assert total < closed_form_maf(0.5, 0.4, 1e-4, 2.5)


def _power(x):
    return 2e-4 * x ** -2.2


@pytest.mark.parametrize("form", ["columns", "header", "usgs", "openquake"])
def test_hazard_tables(tmp_path, form):
    x = np.geomspace(0.05, 3.0, 20)
    path = tmp_path / "hazard.csv"
    if form == "columns":
        path.write_text("".join(f"{a:.17g},{_power(a):.17g}\n" for a in x))
    elif form == "header":
        path.write_text("# site\nIML (g), AFE\n" + "".join(f"{a:.17g}, {_power(a):.17g}\n" for a in x))
    elif form == "usgs":
        path.write_text("lon,lat," + ",".join(f'{a:.17g}' for a in x) + "\n-118.2,34.05,"
                        + ",".join(f'{_power(a):.17g}' for a in x) + "\n")
    else:
        poe = -np.expm1(-_power(x) * 50.0)
        path.write_text('#,,,,"generated_by=\'OpenQuake engine\', imt=\'SA(0.5)\', '
                        'investigation_time=50.0"\nlon,lat,depth,'
                        + ",".join(f"poe-{a:.17g}" for a in x) + "\n-118.2,34.05,0.0,"
                        + ",".join(f'{p:.17g}' for p in poe) + "\n")
    curve = read_hazard(path)
    probe = np.array([0.06, 0.3, 2.5])
    assert curve.rate(probe) == pytest.approx(_power(probe), rel=1e-9)
    assert curve.intensity(_power(0.3)) == pytest.approx(0.3, rel=1e-9)


@pytest.mark.parametrize("text, says", [
    ("IM,AFE\n0.1,0.01\n0.2,x\n", "data row 2"),
    ("0.1,0.001\n0.2,0.01\n", "must not grow"),
    ("", "empty"),
    ("lon,lat,depth,poe-0.1,poe-0.2\n1,2,0,0.1,0.05\n", "investigation_time"),
])
def test_bad_hazard_tables_are_named(tmp_path, text, says):
    path = tmp_path / "bad.csv"
    path.write_text(text)
    with pytest.raises(InputError, match=says) as info:
        read_hazard(path)
    assert str(path) in str(info.value)


# --------------------------------------------------------------------------------------------
# subset simulation against crude Monte Carlo
# --------------------------------------------------------------------------------------------

def _pounding_limit_state(u):
    """Two SDOFs (periods lognormal about 0.5 s and 0.8 s) in their steady state under a
    sine of 1.5 m/s^2 at 0.6 s, 5 % damping, a gap lognormal about 0.18 m: g = gap - peak
    relative displacement (closed form), negative where they pound. Cheap: a million
    evaluations take a second."""
    ta = Uncertain("buildings.A.period", "lognormal", 0.5, 0.1).value(u[:, 0])
    tb = Uncertain("buildings.B.period", "lognormal", 0.8, 0.1).value(u[:, 1])
    gap = Uncertain("contacts.*.gap", "lognormal", 0.18, 0.15).value(u[:, 2])
    w = 2 * np.pi / 0.6

    def amplitude(t):
        wn = 2 * np.pi / t
        return -1.5 / (wn * wn - w * w + 2j * 0.05 * wn * w)

    return gap - np.abs(amplitude(ta) - amplitude(tb))


def test_subset_simulation_agrees_with_crude_monte_carlo_near_1e_3():
    crude = crude_monte_carlo(_pounding_limit_state, 3, 2_000_000, np.random.default_rng(5))
    assert 3e-4 < crude.probability < 3e-3
    agree = 0
    for seed in range(6):
        ss = subset_simulation(_pounding_limit_state, 3, 1000, np.random.default_rng(seed))
        assert ss.evaluations < 6000  # hundreds of times fewer than crude Monte Carlo
        agree += ss.low <= crude.high and crude.low <= ss.high
        assert 0.1 < ss.cov < 0.6
    assert agree >= 5  # 95 % intervals: one miss in six is possible


def test_latin_hypercube_fills_every_stratum_once():
    u = latin_hypercube(50, 3, np.random.default_rng(0))
    strata = np.floor(norm.cdf(u) * 50).astype(int)
    for j in range(3):
        assert sorted(strata[:, j]) == list(range(50))
    x = Uncertain("contacts.*.gap", "uniform", 0.02, 0.08).value(u[:, 0])
    assert x.min() >= 0.02 and x.max() <= 0.08
    with pytest.raises(InputError, match="high > low"):
        Uncertain("contacts.*.gap", "uniform", 0.08, 0.02)


# --------------------------------------------------------------------------------------------
# a study of the paper's pair under a pulse (no records needed)
# --------------------------------------------------------------------------------------------

def pulse_study(folder: Path, **extra) -> Path:
    import yaml

    study = {"scene": str(REPO / "models" / "wu2021-pulse.yaml"), "measure": "pga",
             "design": {"kind": "msa", "levels": [0.2, 0.3, 0.4, 0.5, 0.6, 0.8, 1.0]},
             "limits": {"drift": {"LS": 0.05}, "acceleration": {"A": 1.0}},
             "hazard": {"power_law": {"k0": 1e-4, "k": 2.5}},
             "target": {"return_period": 475}, "bootstrap": 0, **extra}
    path = folder / "study.yaml"
    path.write_text(yaml.safe_dump(study))
    return path


@pytest.fixture(scope="module")
def pulse(tmp_path_factory):
    import xarray as xr

    folder = tmp_path_factory.mktemp("risk")
    out = folder / "risk.nc"
    assert main(["risk", str(pulse_study(folder)), "-o", str(out), "-q", "--threads", "2"]) == 0
    return xr.open_dataset(out), folder


@pytest.mark.slow
def test_pounding_with_contacts_exactly_when_the_critical_gap_exceeds_the_gap(pulse):
    ds, _ = pulse
    gap = float(ds.limit_value.sel(limit_name="pounding"))
    critical = ds.critical_gap.max("contact").values
    impacts = ds.impact_count.sum("contact").values
    clear = np.abs(critical - gap) > 1e-3 * gap
    assert clear.sum() >= 5 and (critical > gap).any() and (critical < gap).any()
    assert np.array_equal((critical > gap)[clear], (impacts > 0)[clear])


@pytest.mark.slow
def test_gap_at_target_is_the_root_of_the_pounding_frequency(pulse):
    """lambda(gap at target) recomputed from the file's critical gaps: the target frequency
    just above the gap found, more than the target just below it."""
    ds, _ = pulse
    curve = HazardCurve.power_law(1e-4, 2.5)
    levels = ds.level.values
    critical = ds.critical_gap.max("contact").values  # (record, level)

    def rate(g):
        z = (critical > g).sum(axis=0)
        f = fit_msa(levels, np.ones_like(levels), z)
        if f.fitted:
            return mean_annual_frequency(f.probability, curve)[0]
        first = int(np.argmax(z > 0))  # one record: each stripe is 0 or 1, a step
        return float(curve.rate(math.sqrt(levels[first - 1] * levels[first])))

    g = float(ds.gap_at_target)
    target = float(ds.target_annual_frequency)
    assert target == pytest.approx(1 / 475)
    assert rate(g * 1.001) <= target < rate(g * 0.999)
    assert float(ds.intensity_at_target) == pytest.approx((1e-4 * 475) ** (1 / 2.5), rel=1e-6)


def test_the_file_is_whole_and_warns_what_it_leaves_out(pulse):
    ds, folder = pulse
    assert ds.attrs["pframe_kind"] == "risk_study" and ds.attrs["Conventions"] == "CF-1.8"
    assert not (folder / "risk.nc.parts").exists()
    assert set(ds.limit_name.values) == {"pounding", "LS", "A"}


@pytest.mark.parametrize("edit, says", [
    ({"design": {"kind": "msa", "levels": [0.2]}}, "design.levels"),
    ({"design": {"kind": "cloud", "levels": [0.2, 0.4]}}, "design.levels"),
    ({"target": {"return_period": 475, "annual_frequency": 0.002}}, "at target"),
    ({"limits": {"drift": {"LS": -1}}}, "limits.drift.LS"),
    ({"hazard": {}}, "at hazard"),
    ({"colour": "red"}, "colour"),
])
def test_bad_study_exits_2_naming_the_place(tmp_path, capsys, edit, says):
    path = pulse_study(tmp_path, **edit)
    out = tmp_path / "out.nc"
    assert main(["risk", str(path), "-o", str(out), "-q"]) == 2
    err = capsys.readouterr().err
    assert str(path) in err and says in err and "Traceback" not in err
    assert not out.exists()


@pytest.mark.slow
def test_a_drift_ratio_limit_is_the_drift_limit_over_the_storey_height(tmp_path):
    """With storeys 3 m high, the file's peak drift ratios are the peak drifts over 3 and a
    drift-ratio limit r has the fragility of the drift limit 3 r (the same runs, the same
    fit); without heights a drift-ratio limit is refused, naming the place."""
    import xarray as xr
    import yaml

    text = (REPO / "models" / "wu2021-eq14.yaml").read_text()
    scene = tmp_path / "pair-heights.yaml"
    scene.write_text(text.replace("    floors: 3\n", "    floors: 3\n    height: 3.0\n"))
    assert scene.read_text().count("height: 3.0") == 2
    study = {"scene": str(scene), "measure": "pga",
             "stochastic": {"model": "clough_penzien", "intensity": 0.02,
                            "ground_frequency": 15.0, "ground_damping": 0.6, "duration": 8.0,
                            "step": 0.01, "realisations": 12, "seed": 3},
             "design": {"kind": "msa", "levels": [0.2, 0.4, 0.6, 0.8, 1.0, 1.3, 1.6]},
             "dt": 0.002, "pounding_runs": False, "bootstrap": 0,
             "limits": {"drift": {"LS": 0.1}, "drift_ratio": {"LSr": 0.1 / 3.0}}}
    path = tmp_path / "study.yaml"
    path.write_text(yaml.safe_dump(study))
    out = tmp_path / "risk.nc"
    assert main(["risk", str(path), "-o", str(out), "-q", "--threads", "2"]) == 0
    with xr.open_dataset(out) as ds:
        free = dict(condition=0)
        np.testing.assert_allclose(ds.peak_story_drift_ratio[free].values,
                                   ds.peak_story_drift[free].values / 3.0, rtol=1e-12)
        ls = ds.fragility_median.sel(limit_name="LS").values
        lsr = ds.fragility_median.sel(limit_name="LSr").values
        assert np.isfinite(ls[0])
        np.testing.assert_allclose(lsr, ls, rtol=1e-9)
        assert str(ds.limit_units.sel(limit_name="LSr").values) == "1"
    study["scene"] = str(REPO / "models" / "wu2021-eq14.yaml")
    path.write_text(yaml.safe_dump(study))
    assert main(["risk", str(path), "-o", str(tmp_path / "bare.nc"), "-q"]) == 2
    assert not (tmp_path / "bare.nc").exists()


def test_ida_capacities_from_a_grid_recover_the_records_capacities():
    """Demand / limit = (IM / c_r)^1.3 for record r: the IM where it passes 1 is c_r, found
    exactly by log-log interpolation between grid levels; capacities drawn lnN(ln 0.7, 0.3),
    those above the top level (1 g) censored."""
    from pframe.risk.analysis import fit

    rng = np.random.default_rng(4)
    levels = np.geomspace(0.1, 1.0, 12)
    caps = 0.7 * np.exp(0.3 * rng.standard_normal(3000))
    ratio = ((levels[None, :] / caps[:, None]) ** 1.3).ravel()
    ok = np.ones(ratio.size, bool)
    im = np.tile(levels, caps.size)
    f = fit("ida", im, ratio, ok, levels, caps.size)
    assert (caps > levels[-1]).mean() > 0.05
    assert f.median == pytest.approx(0.7, rel=0.02)
    assert f.dispersion == pytest.approx(0.3, rel=0.05)


def test_a_fragility_the_data_hardly_fix_has_infinite_bounds():
    """A variance of ln theta of 1e6 overflowed exp() while the file was built."""
    from pframe.risk import Fragility

    f = Fragility(1.0, 0.5, np.diag([1e6, 1e6]))
    (m_lo, m_hi), (b_lo, b_hi) = f.bounds()
    assert m_hi == math.inf and m_lo == 0.0 and b_hi == math.inf


@pytest.mark.slow
def test_a_stopped_study_resumes_from_its_saved_batches(tmp_path, pulse):
    """Stopped after its first batch, the study runs only the others the second time and
    gives the file of an uninterrupted run."""
    import xarray as xr

    from pframe.risk import risk

    whole, _ = pulse
    study = pulse_study(tmp_path, chunk=3)
    out = tmp_path / "stopped.nc"

    def stop(done, total):
        raise KeyboardInterrupt

    with pytest.raises(KeyboardInterrupt):
        risk(study, output=out, progress=stop)
    assert not out.exists() and (tmp_path / "stopped.nc.parts" / "chunk-00000.npz").exists()
    seen = []
    risk(study, output=out, progress=lambda done, total: seen.append(done))
    assert seen == [6, 7]  # batches 1 and 2 of 3 (7 variants); batch 0 was taken up
    again = xr.open_dataset(out)
    assert np.array_equal(again.critical_gap.values, whole.critical_gap.values)
    assert np.array_equal(again.impact_count.values, whole.impact_count.values)
    assert float(again.gap_at_target) == float(whole.gap_at_target)


@pytest.mark.slow
def test_a_study_without_chunk_runs_in_batches_its_memory_holds(tmp_path, pulse, monkeypatch):
    """Without chunk, a study runs as many variants at once as BATCH_BYTES of ground motion
    hold (memory bounded whatever their number), saving each batch as a given chunk is, and
    gives the file of one batch of all."""
    import xarray as xr

    import pframe.risk.study as study_module
    from pframe.risk import risk

    whole, _ = pulse
    study = pulse_study(tmp_path)
    inputs = study_module.open_study(study).inputs
    scene_dt = float(inputs.loaded.expanded.dt)
    steps = max(inputs.steps, math.ceil(inputs.steps * inputs.dt / scene_dt - 1e-9))
    monkeypatch.setattr(study_module, "BATCH_BYTES",
                        3 * study_module.GROUND_BYTES * (steps + 1) + 1)
    seen = []
    out = tmp_path / "batched.nc"
    risk(study, output=out, progress=lambda done, total: seen.append(done))
    assert seen == [3, 6, 7]
    again = xr.open_dataset(out)
    assert np.array_equal(again.critical_gap.values, whole.critical_gap.values)
    assert np.array_equal(again.impact_count.values, whole.impact_count.values)
    assert float(again.gap_at_target) == float(whole.gap_at_target)


@pytest.mark.slow
def test_pframe_plot_draws_the_figure_set(pulse, tmp_path):
    pytest.importorskip("matplotlib")
    _, folder = pulse
    assert main(["plot", str(folder / "risk.nc"), "-o", str(tmp_path / "risk.png"), "-q"]) == 0
    assert sorted(p.name for p in tmp_path.glob("risk-*.png")) == [
        "risk-fragility.png", "risk-gap.png", "risk-hazard.png"]


def test_msa_data_separated_at_one_level_have_no_fit():
    """997 of 1000 runs exceed at the lowest level and all at the others: the likelihood
    rises towards a step at that level (c1 -> infinity) and has no maximum, so no fit is
    reported, one row at a time or many at once; two mixed levels still fit."""
    from pframe.risk.fragility import msa_fit, probit_rows

    levels = [0.2, 0.4, 0.6, 0.8]
    n = np.full(4, 1000)
    separated = [(997, 1000, 1000, 1000), (0, 0, 3, 1000), (0, 0, 1, 1000)]
    mixed = [(0, 2, 995, 1000), (990, 999, 1000, 1000)]
    for z in separated:
        assert not msa_fit(levels, n, z).fitted, z  # as the gap's curve fits (unchecked)
        assert not fit_msa(levels, n, z).fitted, z
        assert "no interior maximum" in fit_msa(levels, n, z).note
    for z in mixed:
        assert fit_msa(levels, n, z).fitted, z
    c, good = probit_rows(np.log(levels), n.astype(float), np.array(separated + mixed, float))
    assert list(good) == [False] * len(separated) + [True] * len(mixed)
