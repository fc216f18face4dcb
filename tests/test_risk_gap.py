"""The gap at a target annual frequency of pounding, from runs made up with a known answer
(no kernel): the curve pframe uses is non-increasing in the gap and its root is the largest
crossing of the refitted curve (every wider gap pounds no more often than the target); a
Monte Carlo over suites drawn from a population with a closed-form answer recovers it; the
code rules at the target's intensity are exact for an elastic pair (log-log interpolation);
fits the data cannot fix are NaN with the reason, and the fitting functions refuse
arguments that are not stripes, capacities or runs (pframe.InputError, never IndexError)."""

from __future__ import annotations

import math
import types

import numpy as np
import pytest

from pframe.errors import InputError
from pframe.risk import (
    HazardCurve,
    closed_form_maf,
    fit_capacities,
    fit_cloud,
    fit_msa,
    mean_annual_frequency,
)
from pframe.risk.analysis import analyse, fit
from pframe.risk.study import StudyFile

K0, K = 1e-4, 2.5


def _study(levels, target, **design):
    return StudyFile(scene="made-up.yaml", design={"kind": "msa", "levels": list(levels),
                                                   **design},
                     pounding_runs=False, hazard={"power_law": {"k0": K0, "k": K}},
                     target={"annual_frequency": target}, bootstrap=0)


def _analyse(g_req, levels, target, peaks=None, gap=0.124):
    """analyse() over made-up runs without contacts: ``g_req`` (records, levels) critical
    gaps (m); ``peaks`` (records, levels) the peak displacement of each building at the
    contact (m; default: half the critical gap each)."""
    R, L = g_req.shape
    peaks = g_req / 2 if peaks is None else peaks
    rows = {"free_g_req": g_req.reshape(-1, 1), "free_complete": np.ones(R * L, np.int8),
            "free_peak_left": peaks.reshape(-1, 1), "free_peak_right": peaks.reshape(-1, 1),
            "free_gap": np.full(R * L, gap)}
    inputs = types.SimpleNamespace(
        factors=np.ones((R, L)), levels=np.asarray(levels, float),
        intensities=np.ones(R), pairs=types.SimpleNamespace(gaps=[gap]),
        periods=np.array([0.5, 0.8]), damping=np.array([0.05, 0.05]))
    return analyse(_study(levels, target), inputs, rows, HazardCurve.power_law(K0, K))


LEVELS = np.array([0.1, 0.2, 0.3, 0.4, 0.6, 0.8, 1.0, 1.5, 2.0, 2.5])


def _records(seed, records=4):
    """Critical gaps eps_r x^b_r (m): each record its own scale and growth with the IM."""
    rng = np.random.default_rng(seed)
    eps = 0.08 * np.exp(0.3 * rng.standard_normal(records))
    b = np.exp(0.3 * rng.standard_normal(records))
    return eps[:, None] * LEVELS[None, :] ** b[:, None]


def _raw(g_req, levels, g):
    """The msa fit of pounding at the uniform gap g integrated over the hazard (the refitted
    curve, recomputed here from the counts)."""
    R, L = g_req.shape
    z = (g_req > g).sum(axis=0)
    f = fit("msa", np.tile(levels, R), (g_req / g).ravel(), np.ones(R * L, bool), levels, R,
            checked=False)
    if f.fitted:
        return mean_annual_frequency(f.probability, HazardCurve.power_law(K0, K), 800)[0]
    if not z.any():
        return 0.0
    # the likelihood's limit, a step: at the first level where a run pounds if some of its
    # runs do not (separated stripes), else between it and the level below
    first = int(np.argmax(z > 0))
    x = (levels[first] if first == 0 or z[first] < R
         else math.sqrt(levels[first - 1] * levels[first]))
    return K0 * x ** -K


def test_the_gap_at_target_is_the_largest_crossing_of_a_non_monotone_curve():
    """Four records whose refitted curve crosses 1/2475 per year three times (64.8, 72.5 and
    86.2 mm; the root search reported 72.5 mm): gaps between the first and the last crossing
    still pound more often than the target, so the gap is the last; the curve the file holds
    never rises with the gap, and a warning says the refitted one did."""
    g_req = _records(55)
    target = 1 / 2475
    out = _analyse(g_req, LEVELS, target)
    gaps = np.unique(g_req)
    rates = np.array([_raw(g_req, LEVELS, g) for g in gaps])
    crossings = [b for a, b, ra, rb in zip(gaps[:-1], gaps[1:], rates[:-1], rates[1:])
                 if ra > target >= rb]
    assert len(crossings) == 3  # the case is the one it is meant to be
    # the curve fitted at all gaps at once (vectorised) is the fit at each gap, one by one
    from pframe.risk.analysis import _gap_curve

    R, L = g_req.shape
    curve = _gap_curve("msa", np.tile(LEVELS, R), g_req.ravel(), np.ones(R * L, bool), LEVELS,
                       R, HazardCurve.power_law(K0, K))
    np.testing.assert_allclose(curve.values, rates, rtol=1e-5)  # to the fits' tolerance
    assert out.gap == pytest.approx(crossings[-1], rel=1e-9)
    assert all(r <= target for g, r in zip(gaps, rates) if g >= out.gap)
    assert _raw(g_req, LEVELS, out.gap * 0.999) > target
    assert np.all(np.diff(out.gap_rates) <= 0)
    assert np.all(out.gap_rates >= out.gap_rates_raw)
    said = [w for w in out.warnings if "not monotone" in w]
    assert said and "crosses the target 3 times" in said[0]


@pytest.mark.slow
def test_the_gap_searched_block_by_block_is_the_gap_of_the_whole_curve(monkeypatch):
    """A bootstrap resample's curve is searched for the gap at a target from its widest gap
    down, a block of gaps at a time, each rate only bounded where the bound tells its side
    of the target: the gap found is the one of the curve computed at every gap, for targets
    at each of the non-monotone curve's values (where a bound's side is in doubt), an ulp
    either side, and past both ends, wherever the search is told to expect it (which sizes
    its blocks)."""
    from pframe.risk import gapcurve
    from pframe.risk.analysis import _gap_curve

    monkeypatch.setattr(gapcurve, "SCAN", 3)  # blocks of 3 of its 40 gaps
    monkeypatch.setattr(gapcurve, "WIDE", 7)  # and of 7 above where it is told to expect it
    g_req = _records(55)
    R, L = g_req.shape

    def curve(near=None):
        return _gap_curve("msa", np.tile(LEVELS, R), g_req.ravel(), np.ones(R * L, bool),
                          LEVELS, R, HazardCurve.power_law(K0, K), near=near)

    whole = curve()
    values = whole.values
    assert whole.rise() is not None  # the case is a non-monotone curve
    picked = values[np.isfinite(values) & (values > 0)][::6]
    targets = [*picked, *np.nextafter(picked, 0.0), *np.nextafter(picked, 1.0),
               0.5 * np.nanmin(values), 2 * np.nanmax(values)]
    grid = whole.grid
    for target in targets:
        for near in (None, grid[0] / 2, grid[5], grid[20], grid[-3], 2 * grid[-1], math.nan):
            fresh = curve(near)
            assert fresh.gap(target) == whole.gap(target) or math.isnan(whole.gap(target))
            assert fresh._values is None  # the search alone did not compute the curve


def test_the_bootstrap_resamples_shared_among_processes_give_the_loops_gaps_in_order():
    """The gap of each record resample, computed in two processes (a share each), is the gap
    computed one resample after another, in the order of the resamples."""
    from pframe.risk.analysis import _gap_curve, _resampled_gaps

    g_req = _records(55, records=12)
    R, L = g_req.shape
    im, ok = np.tile(LEVELS, R), np.ones(R * L, bool)
    hazard, target = HazardCurve.power_law(K0, K), 1 / 2475
    picks = [np.random.default_rng(seed).integers(0, R, R) for seed in range(7)]
    expected = []
    for pick in picks:
        idx = (pick[:, None] * L + np.arange(L)[None, :]).ravel()
        expected.append(_gap_curve("msa", im[idx], g_req.ravel()[idx], ok[idx], LEVELS, R,
                                   hazard).gap(target))
    assert len(set(expected)) > 3  # resamples with gaps of their own
    data = ("msa", im, g_req.ravel(), ok, LEVELS, R, hazard, None, target)
    assert _resampled_gaps(data, picks, 2) == expected
    assert _resampled_gaps(data, picks, 1) == expected


@pytest.mark.slow
def test_the_gap_at_target_against_a_population_with_a_known_answer():
    """Critical gaps eps_r x (an elastic pair: the gap a record needs grows in proportion to
    its scaling), eps lognormal (median 50 mm, dispersion 0.35): pounding at g is then a
    lognormal fragility of median g / 0.05 g/m and dispersion 0.35, and lambda(g) =
    k0 (g / 0.05)^-k exp(k^2 0.35^2 / 2) (Cornell et al. 2002). Suites of 30 records drawn
    from it (one million runs' critical gaps behind the check of lambda itself): the gap at
    1/475 per year, median over 20 suites, is within 5 % of the closed form, and above
    every gap found the refitted curve is at most the target."""
    sigma, median = 0.35, 0.05
    target = 1 / 475
    exact = median * (K0 * math.exp(0.5 * (K * sigma) ** 2) / target) ** (1 / K)
    # the closed form itself against a million sampled critical gaps at random intensities
    rng = np.random.default_rng(11)
    u = rng.random(1_000_000)
    x_min = 0.05  # below it pounding needs eps 7 dispersions above its median
    x = x_min * u ** (-1 / K)  # intensities drawn from the hazard above x_min
    pounds = median * np.exp(sigma * rng.standard_normal(x.size)) * x > exact
    mc = K0 * x_min ** -K * pounds.mean()
    assert mc == pytest.approx(target, rel=0.03)
    levels = np.geomspace(0.05, 1.5, 9)
    found = []
    for seed in range(20):
        eps = median * np.exp(sigma * np.random.default_rng(seed).standard_normal(30))
        g_req = eps[:, None] * levels[None, :]
        out = _analyse(g_req, levels, target)
        found.append(out.gap)
        above = np.unique(g_req[g_req >= out.gap])
        assert all(_raw(g_req, levels, g) <= target for g in above)
    assert float(np.median(found)) == pytest.approx(exact, rel=0.05)


def test_pounding_counts_at_every_gap_are_the_fits_counts():
    """The msa curve's counts of pounding runs per stripe, found for every gap by sorting, are
    the fit's own count at each gap, g_req / g > 1 over the runs that count: failed runs and
    NaNs left out, a critical gap equal to g not pounding, nor one an ulp above g whose ratio
    rounds to 1."""
    from pframe.risk.analysis import _pounding_counts

    rng = np.random.default_rng(1)
    records = 300
    g_req = rng.lognormal(-3.0, 1.0, (records, 4)).ravel()
    g_req[::7] = np.nan
    ok = rng.random(g_req.size) > 0.1
    grid = np.unique(g_req[np.isfinite(g_req)])
    g_req[5:60] = np.nextafter(grid[5:60], 1.0)  # an ulp above a gap of the grid
    g_req[60:90] = np.nextafter(grid[60:90], 0.0)  # and below one
    grid = np.unique(np.concatenate([grid, g_req[np.isfinite(g_req)], [0.5 * grid[0], 1.0]]))
    expected = np.array([((g_req / g > 1) & ok).reshape(records, -1).sum(axis=0)
                         for g in grid])
    assert np.array_equal(_pounding_counts(grid, g_req, ok, records), expected)


def test_code_rules_at_the_target_intensity_are_exact_for_an_elastic_pair():
    """Peak displacements proportional to the intensity: ABS (their sum) and the simulated
    critical gap at the target's intensity between two stripes a factor 2 apart are the
    power law's value, to rounding (linear in ln IM was 6 % off)."""
    levels = np.array([0.2, 0.4, 0.8])
    c = np.array([0.02, 0.03, 0.05])  # m per g, one per record
    g_req = c[:, None] * levels[None, :]
    target = 1 / 475
    out = _analyse(g_req, levels, target, peaks=g_req * 0.7)
    x = (K0 / target) ** (1 / K)
    assert 0.2 < x < 0.4 and out.im_at_target == pytest.approx(x, rel=1e-9)
    assert out.rules_at_target["simulated"] == pytest.approx(0.03 * x, rel=1e-9)
    assert out.rules_at_target["ABS"] == pytest.approx(2 * 0.7 * 0.03 * x, rel=1e-9)


def test_a_target_below_the_hazard_table_gives_no_gap():
    """A table that stops at 1 g (exceeded 1e-4 per year) and a target of 1e-5 per year: the
    frequency of pounding there rests on the term above the table (a lower bound), so the
    gap is NaN with the reason."""
    g_req = _records(3, records=6)
    R, L = g_req.shape
    rows = {"free_g_req": g_req.reshape(-1, 1), "free_complete": np.ones(R * L, np.int8),
            "free_peak_left": g_req.reshape(-1, 1), "free_peak_right": g_req.reshape(-1, 1)}
    inputs = types.SimpleNamespace(
        factors=np.ones((R, L)), levels=LEVELS, intensities=np.ones(R),
        pairs=types.SimpleNamespace(gaps=[0.124]), periods=np.array([0.5, 0.8]),
        damping=np.array([0.05, 0.05]))
    short = HazardCurve.power_law(K0, K, 0.01, 1.0)
    out = analyse(_study(LEVELS, 1e-5), inputs, rows, short)
    assert math.isnan(out.gap)
    assert any("below the hazard table's smallest" in w for w in out.warnings)


# --------------------------------------------------------------------------------------------
# fits the data cannot fix, and the fitting functions' arguments
# --------------------------------------------------------------------------------------------

@pytest.mark.parametrize("exceeded", [[0] * 9 + [1], [0] * 8 + [2, 4]])
def test_a_fit_the_data_cannot_fix_is_nan_with_the_reason(exceeded):
    """Every exceedance at the top stripes and none below: the likelihood grows without end
    as the dispersion goes to 0, so no finite estimate stands (it was printed with bounds
    0-inf)."""
    f = fit_msa(LEVELS, [4] * 10, exceeded)
    assert not f.fitted and math.isnan(f.median)
    assert "do not fix" in f.note


def test_a_study_warns_of_every_fit_it_leaves_out():
    """A limit no run reaches: NaN in the table, and the reason in the warnings."""
    g_req = _records(3)
    out = _analyse(g_req, LEVELS, 1 / 475, gap=10.0)
    frag = out.fragilities[("pounding", "without_pounding")]
    assert not frag.fitted
    assert any("pounding (without pounding): no fragility" in w and "no run exceeds" in w
               for w in out.warnings)


@pytest.mark.parametrize("call, says", [
    (lambda: fit_msa([0.2, 0.4, 0.6], [5, 5, 5], [1, 6, 5]), r"exceeded\[1\] is 6"),
    (lambda: fit_msa([0.2, 0.4, 0.6], [5, 5], [1, 2, 3]), "one value per level"),
    (lambda: fit_msa([-0.2, 0.4, 0.6], [5, 5, 5], [0, 2, 5]), r"levels\[0\] is -0.2"),
    (lambda: fit_msa([0.2, math.nan], [5, 5], [0, 2]), r"levels\[1\] is nan"),
    (lambda: fit_msa([0.2, 0.4], [5, 5], [0, -1]), r"exceeded\[1\] is -1"),
    (lambda: fit_msa("abc", [5], [1]), "levels"),
    (lambda: fit_capacities([0.5, -0.6, 0.7]), r"capacities\[1\]"),
    (lambda: fit_capacities([0.5, 0.6, 0.7], [True, False]), "one value per"),
    (lambda: fit_cloud([0.1, 0.2, 0.3], [1.0, 2.0]), "one value per"),
    (lambda: fit_cloud([0.1, 0.0, 0.3], [1.0, 2.0, 3.0]), r"intensities\[1\]"),
    (lambda: HazardCurve.power_law(K0, K).intensity(0.0), "number > 0"),
    (lambda: mean_annual_frequency(lambda x: x, "hazard.csv"), "HazardCurve"),
    (lambda: closed_form_maf(-0.5, 0.3, K0, K), "median"),
    (lambda: HazardCurve([0.1, 0.2, 0.3], [1e-2, np.nan, 1e-4]), "point 2"),
])
def test_fitting_functions_refuse_what_is_not_data(call, says):
    with pytest.raises(InputError, match=says):
        call()


def test_a_resamples_fits_started_from_the_whole_samples_are_the_same_maxima():
    """A bootstrap resample's probit fits, started from the whole sample's fits at the same
    gaps (Newton's steps), are the fits of the cold start (Fisher scoring from the
    default): the same coefficients to the scoring's tolerance where the likelihood has an
    interior maximum, a log-likelihood nowhere lower (beyond its rounding), and the same
    rows fitted; the gap at target of each resample is the same."""
    from scipy.special import log_ndtr

    from pframe.risk.analysis import _gap_curve, _msa_fits, _warm_fits

    g_req = _records(3, records=40)
    g_req *= np.exp(0.2 * np.random.default_rng(4).standard_normal(g_req.shape))
    R, L = g_req.shape
    im, ok, g = np.tile(LEVELS, R), np.ones(R * L, bool), g_req.ravel()
    warm = _warm_fits(g, ok, LEVELS, R)
    hazard = HazardCurve.power_law(K0, K)
    started = 0
    for seed in range(4):
        pick = np.random.default_rng(seed).integers(0, R, R)
        idx = (pick[:, None] * L + np.arange(L)[None, :]).ravel()
        grid = np.unique(g[idx])
        cold = _msa_fits(grid, g[idx], ok[idx], LEVELS, R)
        hot = _msa_fits(grid, g[idx], ok[idx], LEVELS, R, warm)
        rows, tried = cold[0], cold[3]
        assert np.array_equal(hot[3], tried) and np.array_equal(hot[5], cold[5])
        z = rows[tried].astype(float)

        def loglik(c, z=z):
            eta = c[:, :1] + c[:, 1:] * np.log(LEVELS)
            return np.sum(z * log_ndtr(eta) + (R - z) * log_ndtr(-eta), axis=1)

        assert np.all(loglik(hot[4]) >= loglik(cold[4]) - 1e-9)
        # a slope c1 above 20 (a dispersion below 0.05) is a row the data nearly separate:
        # its likelihood rises ever more slowly towards c1 -> inf, and where a scoring stops
        # there depends on its start (above: the warm one's is no lower)
        interior = cold[5] & (cold[4][:, 1] < 20) & (hot[4][:, 1] < 20)
        assert interior.mean() > 0.8
        np.testing.assert_allclose(hot[4][interior], cold[4][interior], rtol=1e-7, atol=1e-9)
        started += int(np.isfinite(warm[1]).all(axis=1).sum())
        target = 1 / 475
        assert (_gap_curve("msa", im[idx], g[idx], ok[idx], LEVELS, R, hazard,
                           warm=warm).gap(target)
                == _gap_curve("msa", im[idx], g[idx], ok[idx], LEVELS, R, hazard).gap(target))
    assert started  # the case has fits to start from


def test_the_distinct_count_rows_over_increasing_gaps_are_np_uniques():
    """The rows of pounding counts the msa curve fits once each, found by comparing
    neighbours over increasing gaps, are np.unique's rows (in another order), and every
    gap's row is its own counts; gaps not increasing take np.unique itself."""
    from pframe.risk.analysis import _distinct, _pounding_counts

    g_req = _records(7, records=30)
    R, L = g_req.shape
    ok = np.ones(R * L, bool)
    grid = np.unique(np.concatenate([g_req.ravel(), g_req.ravel()[:40] * 1.0000001]))
    counts = _pounding_counts(grid, g_req.ravel(), ok, R)
    rows, back = _distinct(counts, grid)
    assert np.array_equal(rows[back], counts)
    assert np.array_equal(np.unique(rows, axis=0), np.unique(counts, axis=0))
    assert len(rows) == len(np.unique(counts, axis=0)) < len(grid)  # rows repeat: found
    shuffled = np.random.default_rng(0).permutation(len(grid))
    rows, back = _distinct(counts[shuffled], grid[shuffled])
    assert np.array_equal(rows[back], counts[shuffled])
    assert len(rows) == len(np.unique(counts, axis=0))


@pytest.mark.slow
def test_a_resamples_scoring_stopped_once_its_side_is_settled_finds_the_same_gap(monkeypatch):
    """A resample's fits from the whole sample's stop once a Newton step is small and the
    rate is on one side of the target by more than 1e-3 (analysis.SETTLED): the gap found
    is the one of the same curve with every fit taken to its stopping tolerance, for
    targets at every fourth value of that curve (where the side is in most doubt) and an
    ulp either side; and the search did stop some fits early."""
    from pframe.risk import fragility
    from pframe.risk.analysis import _gap_curve, _warm_fits

    g_req = _records(3, records=40)
    g_req *= np.exp(0.2 * np.random.default_rng(4).standard_normal(g_req.shape))
    R, L = g_req.shape
    im, ok, g = np.tile(LEVELS, R), np.ones(R * L, bool), g_req.ravel()
    warm = _warm_fits(g, ok, LEVELS, R)
    hazard = HazardCurve.power_law(K0, K)
    settled = []
    probit_rows = fragility.probit_rows

    def counted(*args, **kwargs):  # probit_rows, counting the rows it stops early
        ask = kwargs.get("settled")
        if ask is not None:
            kwargs["settled"] = lambda c: settled.append(ask(c)) or settled[-1]
        return probit_rows(*args, **kwargs)

    monkeypatch.setattr(fragility, "probit_rows", counted)
    for seed in range(2):
        pick = np.random.default_rng(seed).integers(0, R, R)
        idx = (pick[:, None] * L + np.arange(L)[None, :]).ravel()

        def curve(idx=idx):
            return _gap_curve("msa", im[idx], g[idx], ok[idx], LEVELS, R, hazard, warm=warm)

        whole = curve()
        values = whole.values  # every fit to its tolerance (no target: nothing settles)
        picked = values[np.isfinite(values) & (values > 0)][::4]
        for target in [*picked, *np.nextafter(picked, 0.0), *np.nextafter(picked, 1.0)]:
            found = curve().gap(target)
            assert found == whole.gap(target) or math.isnan(whole.gap(target))
    assert sum(int(np.sum(s)) for s in settled)  # fits did stop early
