"""Stochastic ground motions (pframe.excitation.stochastic) against the models' own equations:
the expected Arias intensity, D5-95 and t_mid of the modulating function, the zero-crossing
rate of the filtered noise (Rice), the Clough-Penzien PSD against the averaged periodogram;
reproducibility from the seed; the motion applied by a scene like a record."""

from __future__ import annotations

import math

import numpy as np
import pytest
from conftest import parse_scene, run_text, sdof_text
from scipy import stats

from pframe.errors import InputError
from pframe.excitation import stochastic as st
from pframe.excitation.records import G
from pframe.model.scene import Stochastic

PARAMS = st.RezaeianParameters(arias=0.5, d595=5.0, tmid=4.0, frequency=5.0, slope=0.0,
                               damping=0.3)


def _realisations(params, n, step=0.01, seed=0):
    rng = np.random.Generator(np.random.PCG64(seed))
    return [st.rezaeian_unfiltered(params, step, rng) for _ in range(n)]


def test_gamma_envelope_has_the_asked_intensity_duration_and_tmid():
    """q^2 / int q^2 is a gamma density: its 5, 45, 95 % quantiles give D5-95 and t_mid, and
    pi / (2 g) int q^2 the Arias intensity, here integrated numerically."""
    env = st.gamma_envelope(0.5, 5.0, 4.0)
    t5, t45, t95 = (env.energy_time(p) for p in (0.05, 0.45, 0.95))
    assert t95 - t5 == pytest.approx(5.0, rel=1e-9)
    assert t45 == pytest.approx(4.0, rel=1e-9)
    t = np.linspace(0.0, 200.0, 400001)
    q2 = env(t) ** 2
    assert math.pi / (2 * G) * np.trapezoid(q2, t) == pytest.approx(0.5, rel=1e-6)
    assert env.arias() == pytest.approx(0.5, rel=1e-12)


def test_infeasible_duration_and_tmid_are_refused():
    """D5-95 / t_mid of a gamma q with alpha_2 = 1 (q^2 exponential) is the largest there is."""
    limit = (stats.expon.ppf(0.95) - stats.expon.ppf(0.05)) / stats.expon.ppf(0.45)
    assert not st.envelope_feasible(limit * 1.01 * 2.0, 2.0)
    assert st.envelope_feasible(limit * 0.99 * 2.0, 2.0)
    with pytest.raises(ValueError, match="no gamma-form"):
        st.gamma_envelope(0.1, 30.0, 2.0)


@pytest.mark.slow
def test_rezaeian_mean_arias_duration_and_tmid_match_the_model():
    """The process before q has unit variance at every step (normalised by sigma_h), so
    E[I_a] is the modulating function's I_a; the Husid curve of the mean squared motion has
    its D5-95 and t_mid. Mean over 200 realisations, within 3 standard errors."""
    runs = _realisations(PARAMS, 200)
    step = 0.01
    arias = np.array([st.arias_intensity(a, step) for _, a, _, _ in runs])
    se = arias.std(ddof=1) / math.sqrt(len(arias))
    expected = st.arias_intensity(runs[0][2](runs[0][0]), step)  # the discrete int of q^2
    assert expected == pytest.approx(PARAMS.arias * st.ENERGY_COVERED, rel=2e-3)
    assert abs(arias.mean() - expected) < 3 * se
    mean_square = np.mean([a**2 for _, a, _, _ in runs], axis=0)
    t5, t45, t95 = st.energy_times(st.husid(np.sqrt(mean_square), step), step)
    assert t95 - t5 == pytest.approx(PARAMS.d595, rel=0.03)
    assert t45 == pytest.approx(PARAMS.tmid, rel=0.03)


@pytest.mark.slow
def test_rezaeian_zero_crossing_rate_is_the_filter_frequency():
    """The filter h is a damped oscillator's displacement impulse response: its stationary
    response to white noise has lambda_2 / lambda_0 = omega_f^2, so (Rice) it crosses zero
    omega_f / pi times a second whatever zeta_f. With f' = 0, over [t5, t95]: 2 f_mid a second."""
    step = 0.01
    runs = _realisations(PARAMS, 100, seed=3)
    rates = []
    for _, a, env, _ in runs:
        lo, hi = int(env.energy_time(0.05) / step), int(env.energy_time(0.95) / step)
        rates.append(st.zero_crossings(a, lo, hi) / ((hi - lo) * step))
    rates = np.array(rates)
    se = rates.std(ddof=1) / math.sqrt(len(rates))
    assert abs(rates.mean() - 2 * PARAMS.frequency) < max(3 * se, 0.02 * 2 * PARAMS.frequency)


@pytest.mark.slow
def test_rezaeian_slope_moves_the_crossings_as_the_filter_frequency():
    """With f' != 0 the crossings over [t5, t95] count int omega_f(t) / pi dt."""
    params = st.RezaeianParameters(0.5, 8.0, 6.0, 4.0, -0.2, 0.2)
    step = 0.01
    counts, expected = [], None
    for t, a, env, _ in _realisations(params, 60, seed=5):
        t5, t95 = env.energy_time(0.05), env.energy_time(0.95)
        lo, hi = int(t5 / step), int(t95 / step)
        counts.append(st.zero_crossings(a, lo, hi))
        f = params.frequency + params.slope * (t[lo:hi] - params.tmid)
        expected = 2.0 * np.sum(f) * step
    assert np.mean(counts) == pytest.approx(expected, rel=0.04)


def test_highpass_leaves_no_residual_velocity():
    """The critically damped post-filter s^2 / (s + w_c)^2 removes the zero frequency: the
    filtered motion's final velocity is a small part of its peak velocity."""
    rng = np.random.Generator(np.random.PCG64(11))
    t, raw, _, _ = st.rezaeian_unfiltered(st.RezaeianParameters(0.5, 10, 6, 1.0, 0, 0.5), 0.01,
                                          rng)
    raw = raw + 0.02 * (t < 5)  # a step of acceleration: a drift of velocity
    filtered = st.highpass(raw, 0.01)
    for a, small in ((raw, False), (filtered, True)):
        v = np.concatenate([[0.0], np.cumsum(0.5 * (a[1:] + a[:-1]) * 0.01)])
        ratio = abs(v[-1]) / np.max(np.abs(v))
        assert (ratio < 0.02) == small, ratio


def _integrated(a, step):
    """The ground velocity and displacement at the samples of the acceleration a scene
    applies (linear between samples, from rest), integrated exactly."""
    v = np.concatenate([[0.0], np.cumsum(0.5 * (a[1:] + a[:-1]) * step)])
    d = np.concatenate([[0.0], np.cumsum(v[:-1] * step + (2 * a[:-1] + a[1:]) * step**2 / 6)])
    return v, d


@pytest.mark.slow
def test_rezaeian_motions_end_at_rest():
    """After the modulated motion the high-pass filter runs on over 10 / w_c of zeros: its
    velocity and displacement there follow the free decay of a critically damped oscillator
    from their values at the motion's end (closed form), and what is left at the end, the
    motion's residual velocity and displacement, is below 1e-3 of their peaks over 240
    realisations of 12 sites (median below 1e-4). Without the zeros, the same motions stopped
    with up to 17 % of their peak velocity (median 1.4 %) and 28 % of their peak displacement
    (median 2.8 %)."""
    step, wc = 0.01, 2 * math.pi * st.HIGHPASS_HZ
    pad = st.settling_samples(step)
    assert pad == math.ceil(st.HIGHPASS_SETTLE / wc / step) == 796
    residual = []
    for magnitude in (5.5, 6.5, 7.5):
        for distance, vs30 in ((5.0, 200.0), (5.0, 760.0), (30.0, 200.0), (30.0, 760.0)):
            site = dict(magnitude=magnitude, distance=distance, vs30=vs30)
            for m in st.rezaeian_batch(range(20), step, site):
                v, d = _integrated(m.acceleration, step)
                end = m.times.size - pad  # the first zero of the input
                tail = m.times[end:] - m.times[end]
                free_v, free_d = st.settling(v[end], d[end], tail)
                scale = abs(v[end]) + wc * abs(d[end])
                assert np.max(np.abs(v[end:] - free_v)) < 1e-6 * scale
                assert np.max(np.abs(d[end:] - free_d)) < 1e-6 * scale / wc
                residual.append((abs(v[-1]) / np.max(np.abs(v)), abs(d[-1]) / np.max(np.abs(d))))
    residual = np.array(residual)
    assert np.all(residual < 1e-3), residual.max(axis=0)
    assert np.all(np.median(residual, axis=0) < 1e-4), np.median(residual, axis=0)


def test_clough_penzien_periodogram_is_the_psd():
    """The averaged periodogram of 100 stationary realisations (time-domain filters driven by
    held white noise) against S(omega) sinc^2(omega dt / 2), in bands of 1 rad/s from 0.5 to
    30 rad/s (omega dt <= 0.3: beyond, the samples' aliases add a few per cent), across the
    high-pass filter's cut (w_f = 1.5 rad/s) and the ground's peak (w_g = 15 rad/s)."""
    step, n = 0.01, 10000
    args = dict(intensity=0.02, wg=15.0, zg=0.6, wf=1.5, zf=0.6)
    rng = np.random.Generator(np.random.PCG64(2))
    omega = 2 * np.pi * np.fft.rfftfreq(n, step)
    pgram = np.zeros(omega.size)
    for _ in range(100):
        x = st.clough_penzien_stationary(n, step, rng=rng, **args)
        pgram += np.abs(np.fft.rfft(x)) ** 2 * step / (2 * np.pi * n)
    pgram /= 100
    model = st.clough_penzien_psd(omega, args["intensity"], args["wg"], args["zg"], args["wf"],
                                  args["zf"]) * np.sinc(omega * step / (2 * np.pi)) ** 2
    errors = []
    for lo in np.arange(0.5, 30.0, 1.0):
        band = (omega >= lo) & (omega < lo + 1.0)
        errors.append(pgram[band].mean() / model[band].mean() - 1.0)
    errors = np.array(errors)
    # about 16 bins x 100 realisations a band: a relative standard error of 2.5 %
    assert np.max(np.abs(errors)) < 0.1
    assert abs(errors.mean()) < 0.02


@pytest.mark.slow
def test_a_motion_models_filter_is_discretised_once(monkeypatch):
    """Realisations of one Clough-Penzien model, one by one (a scene's, a suite's) or in a
    batch (the first-passage check, a subset study), share one discretisation of its filters
    and are the same process: a batch of one row is the realisation of the same noise."""
    from scipy import signal

    from pframe.risk.firstpassage import clough_penzien_batch

    calls = []
    original = signal.cont2discrete
    monkeypatch.setattr(signal, "cont2discrete",
                        lambda *a, **k: calls.append(1) or original(*a, **k))
    args = dict(intensity=0.02, wg=15.1, zg=0.6, wf=1.3, zf=0.6)  # a model no test used
    alone = [st.clough_penzien_stationary(500, 0.01, rng=np.random.default_rng(s), **args)
             for s in range(3)]
    batch = clough_penzien_batch(1, 500, 0.01, rng=np.random.default_rng(2), **args)
    assert len(calls) == 1
    assert np.array_equal(batch[0], alone[2])


def test_same_seed_same_motion_other_seed_other_motion():
    site = dict(model="rezaeian2010", magnitude=6.8, distance=15.0, vs30=500.0)
    a = st.generate(Stochastic(**site, seed=4))
    st._generate.cache_clear()
    b = st.generate(Stochastic(**site, seed=4))
    c = st.generate(Stochastic(**site, seed=5))
    assert a is not b and np.array_equal(a.acceleration, b.acceleration)
    assert a.parameters == b.parameters and a.parameters != c.parameters


def test_site_relations_means_scale_with_magnitude_and_distance():
    """The predictive relations: larger magnitude, more Arias intensity and longer duration;
    farther, less intensity (signs of the published coefficients, through the marginals)."""
    near = st.from_normal(st.relation_means(7.0, 10.0, 400.0, "strike_slip"))
    far = st.from_normal(st.relation_means(7.0, 60.0, 400.0, "strike_slip"))
    small = st.from_normal(st.relation_means(6.0, 10.0, 400.0, "strike_slip"))
    assert near.arias > far.arias and near.arias > small.arias
    assert near.d595 > small.d595
    # ln I_a (s g) is normal: its value at nu_1 is mu + sigma nu_1 exactly
    nu = st.relation_means(7.0, 20.0, 400.0, "reverse")
    assert near.arias > 0 and st.from_normal(nu).arias == pytest.approx(
        G * math.exp(-4.8255 + 1.4318 * nu[0]), rel=1e-12)


def test_a_scene_applies_the_stochastic_motion_like_a_record():
    """An SDOF under a stochastic motion: the kernel's ground acceleration is the realisation
    interpolated on the analysis grid, the motion's scale applied; the run completes."""
    ex = {"kind": "stochastic", "model": "clough_penzien", "intensity": 0.01,
          "ground_frequency": 15.0, "ground_damping": 0.6, "filter_frequency": 1.5,
          "envelope": {"kind": "jennings", "rise": 1.0, "plateau": 3.0, "decay": 1.0},
          "seed": 9, "scale": 2.0}
    text = sdof_text(1000.0, 4e5, 0.05, ex, 0.005, 8.0)
    loaded = parse_scene(text)
    m = st.generate(loaded.scene.excitation)
    t = np.arange(loaded.expanded.steps + 1) * 0.005
    assert np.allclose(loaded.expanded.ground_acceleration,
                       2.0 * np.interp(t, m.times, m.acceleration, right=0.0))
    plan, result = run_text(text)
    assert result.completed()


def test_bad_stochastic_excitation_names_the_place():
    text = sdof_text(1000.0, 4e5, 0.05, {"kind": "stochastic", "model": "rezaeian2010",
                                          "magnitude": 7, "distance": 20}, 0.005, 1.0)
    with pytest.raises(InputError, match=r"excitation.*vs30"):
        parse_scene(text)
    text = sdof_text(1000.0, 4e5, 0.05, {"kind": "stochastic", "model": "clough_penzien",
                                          "intensity": 0.1, "ground_frequency": 15,
                                          "ground_damping": 0.6, "magnitude": 7,
                                          "duration": 5}, 0.005, 1.0)
    with pytest.raises(InputError, match="magnitude do not apply"):
        parse_scene(text)


@pytest.mark.parametrize("params", [
    PARAMS,  # f' = 0: one frequency
    st.RezaeianParameters(0.5, 8.0, 6.0, 4.0, -0.3, 0.2),  # falling, held at the floor
    st.RezaeianParameters(0.2, 12.0, 5.0, 2.0, 0.4, 0.05),  # rising, lightly damped
])
def test_compiled_filter_is_the_direct_sum(params):
    """The compiled filter (a complex recurrence a pulse) against the direct sum of h from exp
    and sin, lag by lag: the same unit-variance process to roundoff."""
    if st._filter_library() is None:
        pytest.skip("the compiled filter (pframe.excitation._cstochastic) is not built")
    step = 0.01
    env = st.gamma_envelope(params.arias, params.d595, params.tmid)
    times = np.arange(int(env.energy_time(st.ENERGY_COVERED) / step) + 1) * step
    omega, _ = st.filter_frequencies(params, times)
    u = np.random.Generator(np.random.PCG64(1)).standard_normal(times.size)
    fast = st.filtered_unit(omega, u, params.damping, step)
    slow = st.filtered_unit_numpy(omega, u, params.damping, step)
    assert np.max(np.abs(fast - slow)) < 1e-12 * np.max(np.abs(slow))


def test_batch_gives_each_seed_its_own_motion():
    """rezaeian_batch over seeds: each motion is, bit for bit, what a scene with that seed
    generates alone; ``until`` keeps a prefix of the same samples."""
    site = dict(magnitude=6.5, distance=20.0, vs30=400.0, mechanism="reverse")
    seeds = [3, 0, 11, 7]
    batch = st.rezaeian_batch(seeds, 0.01, site)
    for seed, m in zip(seeds, batch):
        alone = st.generate(Stochastic(model="rezaeian2010", seed=seed, **site))
        assert np.array_equal(m.acceleration, alone.acceleration)
        assert m.parameters == alone.parameters and m.sampled and m.warnings == alone.warnings
    early = st.rezaeian_batch(seeds, 0.01, site, until=lambda p: p.tmid + 1.0)
    for m, short in zip(batch, early):
        n, stop = short.times.size, m.parameters["tmid"] + 1.0
        assert short.times[-1] <= stop + 1e-9 < short.times[-1] + 0.01 and n < m.times.size
        assert np.array_equal(short.acceleration, m.acceleration[:n])


def test_envelopes_solved_together_have_their_duration_and_tmid():
    """gamma_envelopes over many (D5-95, t_mid), from nearly stationary (a long D5-95 for its
    t_mid: alpha_2 near 1) to a short pulse (a large shape): each has its D5-95 and t_mid."""
    ratio = np.array([0.05, 0.3, 1.0, 2.5, 4.9])
    tmid = np.array([3.0, 10.0, 6.0, 2.0, 4.0])
    a1, a2, a3 = st.gamma_envelopes(np.full(5, 0.3), ratio * tmid, tmid)
    for b in range(5):
        env = st.GammaEnvelope(a1[b], a2[b], a3[b])
        t5, t45, t95 = (env.energy_time(p) for p in (0.05, 0.45, 0.95))
        assert t95 - t5 == pytest.approx(ratio[b] * tmid[b], rel=1e-9)
        assert t45 == pytest.approx(tmid[b], rel=1e-9)
        assert env.arias() == pytest.approx(0.3, rel=1e-10)  # k ln(rate) - ln Gamma(k): large k
