"""Motions at several supports (pframe.excitation: spatial, simulated, coherency, conditioned,
kinematics) against closed forms and the models' own statistics: a delayed analytic
band-limited signal, the trapezoid rule's exact cases, the coherency and the auto-spectra estimated from many
simulated motions, the conditional mean and covariance of the conditioned motions."""

from __future__ import annotations

import math

import numpy as np
import pytest

from pframe.excitation import coherency as co
from pframe.excitation import kinematics as kin
from pframe.excitation import simulated as sim
from pframe.excitation import spatial as sp

STEP = 0.01


def _pulse(t, t0=5.0, width=0.8, hz=3.0):
    """A Gaussian-modulated cosine: its spectrum is a Gaussian about ``hz`` of width
    1 / (pi width) Hz, below 1e-100 at 50 Hz: band-limited to round-off at this step."""
    return np.exp(-(((t - t0) / width) ** 2)) * np.cos(2.0 * math.pi * hz * (t - t0))


# ----------------------------------------------------------------------------------------
# Wave passage of one motion


def test_a_whole_step_delay_copies_the_samples():
    """37 steps: the samples themselves, shifted, and exact zeros before they arrive."""
    a = np.random.default_rng(0).standard_normal(500)
    out = sp.delayed(a, STEP, 37 * STEP)
    assert out.shape == (537,)
    assert np.array_equal(out[37:], a)
    assert np.array_equal(out[:37], np.zeros(37))


@pytest.mark.parametrize("delay", [0.3456, 1.234567, 0.005, 7.777])
def test_a_fractional_delay_is_the_analytic_signal_delayed(delay):
    """a(t - tau) of a band-limited signal at tau not a multiple of the step, to round-off; a
    delay longer than the signal's half does not wrap round (the padding)."""
    t = np.arange(1000) * STEP
    out = sp.delayed(_pulse(t), STEP, delay)
    assert out.size == 1000 + math.ceil(delay / STEP)
    exact = _pulse(np.arange(out.size) * STEP - delay)
    assert np.max(np.abs(out - exact)) < 1e-12


def test_wave_passage_delays_follow_the_plane_wave():
    """tau_s = r_s . n / v relative to the first support reached: along the direction, back
    against it, across it (no delay); the first support reached keeps the record."""
    a = _pulse(np.arange(1000) * STEP)
    positions = [(0.0, 0.0), (300.0, 0.0), (100.0, 200.0)]
    along = sp.wave_passage(a, STEP, positions, co.WavePassage(600.0, 0.0))
    assert along.delays == pytest.approx([0.0, 0.5, 1.0 / 6.0], abs=1e-15)
    assert np.array_equal(along.acceleration[0, :1000], a)
    back = sp.wave_passage(a, STEP, positions, co.WavePassage(600.0, 180.0))
    assert back.delays == pytest.approx([0.5, 0.0, 1.0 / 3.0], abs=1e-12)
    across = sp.wave_passage(a, STEP, [(0.0, 0.0), (0.0, 0.0), (0.0, 0.0)],
                             co.WavePassage(600.0, 37.0))
    assert np.array_equal(across.acceleration, np.array([a, a, a]))
    oblique = sp.wave_passage(a, STEP, positions, co.WavePassage(600.0, 30.0))
    tau = (np.array(positions) @ [math.cos(math.pi / 6), math.sin(math.pi / 6)]) / 600.0
    assert oblique.delays == pytest.approx(tau - tau.min(), abs=1e-15)
    for row, delay in zip(oblique.acceleration, oblique.delays):
        assert np.max(np.abs(row - _pulse(np.arange(row.size) * STEP - delay))) < 1e-12


def test_a_reference_support_keeps_the_record_and_earlier_ones_start_before_it():
    """The record does not start at zero: a zero before it at every support (one step), and
    the first support is reached 0.1234 s before the reference."""
    a = np.random.default_rng(1).standard_normal(400)
    m = sp.wave_passage(a, STEP, [(0.0, 0.0), (123.4, 0.0)], co.WavePassage(1000.0, 0.0),
                        reference=1)
    lead = 1 + math.ceil(0.1234 / STEP)
    assert m.delays[1] == pytest.approx(lead * STEP, abs=1e-15)
    assert m.delays[0] == pytest.approx(lead * STEP - 0.1234, abs=1e-12)
    assert np.array_equal(m.acceleration[1, lead:lead + 400], a)
    assert not np.any(m.acceleration[1, :lead])


def test_supports_with_one_motion_delayed_have_one_displacement_delayed():
    """A record that starts at 0.3 m/s^2, 0.37 s later at the second support: both supports'
    velocities and displacements, the trapezoid rule from rest, are the same delayed (the
    record is put after a zero at both, not jumping at t = 0 at the first), so the gap between
    them does not drift."""
    a = np.random.default_rng(6).standard_normal(800)
    a[0] = 0.3
    m = sp.wave_passage(a, STEP, [(0.0, 0.0), (185.0, 0.0)], co.WavePassage(500.0, 0.0))
    _, v, d = m.kinematics()
    assert np.max(np.abs(v[1, 37:] - v[0, :-37])) < 1e-13
    assert np.max(np.abs(d[1, 37:] - d[0, :-37])) < 1e-12


def test_wave_passage_says_what_the_motions_are():
    """The motions are longer than the record (never cut) and say so; an abrupt record, whose
    fractional delay rings and which gets a zero before it, is named."""
    a = np.random.default_rng(2).standard_normal(300)
    m = sp.wave_passage(a, STEP, [(0.0, 0.0), (12.345, 0.0)], co.WavePassage(500.0, 0.0))
    assert m.acceleration.shape == (2, 301 + math.ceil(12.345 / 500.0 / STEP))
    assert m.acceleration[0, 0] == 0.0 and np.array_equal(m.acceleration[0, 1:301], a)
    assert any("not zero: every support's motion starts one step before" in n
               for n in m.notes)
    assert any("0.03469 s longer than the motion" in n and "0.02469 s after the first" in n
               for n in m.notes)
    assert any("starts or ends at" in n for n in m.notes)
    assert any("above 0.8 of the Nyquist" in n for n in m.notes)
    smooth = sp.wave_passage(_pulse(np.arange(1000) * STEP), STEP,
                             [(0.0, 0.0), (12.345, 0.0)], co.WavePassage(500.0, 0.0))
    assert len(smooth.notes) == 1


@pytest.mark.parametrize("call, match", [
    (lambda: co.WavePassage(0.0), "apparent velocity must be a finite number > 0"),
    (lambda: co.WavePassage(math.inf), "apparent velocity"),
    (lambda: co.WavePassage(100.0, math.nan), "direction"),
    (lambda: co.support_positions([[0.0, 0.0, 1.0]]), r"\(x, y\) pairs"),
    (lambda: sp.delayed(np.ones(3), STEP, -1.0), "delay must be"),
    (lambda: sp.wave_passage(np.ones(3), 0.0, [(0, 0)], co.WavePassage(1.0)), "time step"),
    (lambda: sp.wave_passage([1.0, math.nan], STEP, [(0, 0)], co.WavePassage(1.0)),
     "not a finite number"),
    (lambda: co.LucoWong(0.2, -1.0), "shear_velocity"),
    (lambda: co.HarichandranVanmarcke(amplitude=1.5), "amplitude A must be in"),
    (lambda: co.SoilColumn(2.0, 0.1, kind="slab"), "kind must be"),
])
def test_bad_arguments_are_named(call, match):
    with pytest.raises(ValueError, match=match):
        call()


# ----------------------------------------------------------------------------------------
# Velocities and displacements


def test_the_trapezoid_rule_is_exact_for_a_constant_acceleration():
    t = np.arange(2001) * STEP
    v, d = kin.integrate(np.full(t.size, 0.7), STEP)
    assert np.max(np.abs(v - 0.7 * t)) < 1e-12
    assert np.max(np.abs(d - 0.35 * t * t)) < 1e-10


def test_the_integration_is_newmark_average_acceleration():
    """d_{n+1} = d_n + h v_n + h^2 (a_n + a_{n+1}) / 4 (gamma 1/2, beta 1/4), from rest."""
    a = np.random.default_rng(3).standard_normal((2, 500))
    v, d = kin.integrate(a, STEP)
    assert np.all(v[:, 0] == 0.0) and np.all(d[:, 0] == 0.0)
    newmark = d[:, :-1] + STEP * v[:, :-1] + STEP**2 * (a[:, :-1] + a[:, 1:]) / 4.0
    assert np.max(np.abs(d[:, 1:] - newmark)) < 1e-13
    assert np.max(np.abs(v[:, 1:] - v[:, :-1] - STEP * (a[:, :-1] + a[:, 1:]) / 2)) < 1e-14


def test_the_integration_converges_at_second_order():
    """a = -w^2 sin(w t): v = w (cos(w t) - 1) ... from rest, d = sin(w t) - w t."""
    w = 2.0 * math.pi
    errors = []
    for h in (0.02, 0.01):
        t = np.arange(int(round(4.0 / h)) + 1) * h
        v, d = kin.integrate(-w * w * np.sin(w * t), h)
        errors.append(np.max(np.abs(d - (np.sin(w * t) - w * t))))
    assert errors[0] / errors[1] == pytest.approx(4.0, rel=0.02)


@pytest.mark.parametrize("fit", ["velocity", "displacement"])
def test_a_baseline_of_the_family_is_removed_exactly(fit):
    """Least squares is linear: a drift a_c of the polynomial family added to a motion leaves
    the corrected motion as it was; a pure polynomial is removed to round-off; the corrected
    acceleration, velocity and displacement keep the trapezoid relations."""
    t = np.arange(3000) * STEP
    a = _pulse(t, t0=12.0, width=2.0, hz=1.0)
    drift = 0.003 - 0.0004 * t + 1e-5 * t * t
    clean = kin.baseline_correct(a, STEP, fit=fit, degree=2)
    dirty = kin.baseline_correct(a + drift, STEP, fit=fit, degree=2)
    assert np.max(np.abs(dirty.displacement - clean.displacement)) < 1e-9
    assert dirty.coefficients - clean.coefficients == pytest.approx([0.003, -0.0004, 1e-5],
                                                                    rel=1e-6)
    assert np.max(np.abs(kin.baseline_correct(drift, STEP, fit=fit, degree=2).acceleration)) \
        < 1e-12
    v, d = kin.integrate(dirty.acceleration, STEP)
    assert np.max(np.abs(v - dirty.velocity)) < 1e-12
    assert np.max(np.abs(d - dirty.displacement)) < 1e-10
    # the fitted quantity is left orthogonal to the family's
    basis_v, basis_d = kin.integrate(np.array([(t / t[-1]) ** j for j in range(3)]), STEP)
    fitted = dirty.velocity if fit == "velocity" else dirty.displacement
    family = basis_v if fit == "velocity" else basis_d
    assert np.max(np.abs(family @ fitted)) < 1e-9 * np.linalg.norm(family) * np.linalg.norm(
        fitted)


def test_a_rest_baseline_ends_the_motion_at_rest_and_says_so():
    t = np.arange(2000) * STEP
    a = np.stack([_pulse(t, 8.0, 2.0, 1.0) + 0.002, 2.0 * _pulse(t, 8.0, 2.0, 1.0) - 0.001])
    done = kin.baseline_correct(a, STEP, fit="rest")
    assert np.max(np.abs(done.velocity[:, -1])) < 1e-14
    assert np.max(np.abs(done.displacement[:, -1])) < 1e-13
    assert done.coefficients.shape == (2, 2)
    text = done.description[0]
    assert "brings the motion to rest" in text and "final displacement" in text
    assert f"{done.coefficients[0, 0]:.4g}" in text
    with pytest.raises(ValueError, match="degree must be a whole number from 1"):
        kin.baseline_correct(a, STEP, fit="rest", degree=0)


# ----------------------------------------------------------------------------------------
# Coherent simulated motions

CP = sim.CloughPenzienSpectrum(intensity=0.01, ground_frequency=15.6, ground_damping=0.6,
                              filter_frequency=1.6, filter_damping=0.6)
LINE = np.array([(0.0, 0.0), (60.0, 0.0), (150.0, 40.0)])


def _spectra(motions, window):
    """Cross-periodograms of each realisation (R, n, n, F) of the samples ``window`` of
    ``motions`` (R, n, N), Hann-tapered, and the frequencies (rad/s)."""
    x = motions[:, :, window]
    x = x * np.hanning(x.shape[-1])
    spectrum = np.fft.rfft(x, axis=-1)
    omega = 2.0 * math.pi * np.fft.rfftfreq(x.shape[-1], STEP)
    return spectrum[:, :, None, :] * np.conj(spectrum[:, None, :, :]), omega


def _smooth(values, bins=3):
    kernel = np.ones(2 * bins + 1) / (2 * bins + 1)
    return np.apply_along_axis(lambda v: np.convolve(v, kernel, mode="same"), -1, values)


def _coherency(total):
    """The smoothed coherency estimate of summed cross-periodograms (n, n, F)."""
    s = _smooth(total)
    auto = np.real(np.einsum("jjf->jf", s))
    return s / np.sqrt(auto[:, None, :] * auto[None, :, :])


def _jackknife(per_realisation, statistic, groups=20):
    """The statistic of the sum over realisations and its jackknife standard error over
    ``groups`` groups of realisations."""
    total = per_realisation.sum(axis=0)
    parts = np.array_split(np.arange(per_realisation.shape[0]), groups)
    left_out = np.array([statistic(total - per_realisation[p].sum(axis=0)) for p in parts])
    spread = np.sqrt((groups - 1) / groups * np.sum(
        np.abs(left_out - left_out.mean(axis=0)) ** 2, axis=0))
    return statistic(total), spread


def test_the_same_seed_gives_the_same_motions():
    args = (LINE, STEP, 10.0, CP, co.LucoWong(0.3, 400.0))
    kw = {"wave": co.WavePassage(900.0, 20.0), "envelope": lambda t: np.minimum(t / 2, 1.0)}
    one = sim.simulate(*args, seed=7, **kw)
    assert np.array_equal(one.acceleration, sim.simulate(*args, seed=7, **kw).acceleration)
    assert not np.allclose(one.acceleration, sim.simulate(*args, seed=8, **kw).acceleration)
    assert one.seed == 7 and "seed 7" in one.description
    assert not one.acceleration.flags.writeable


def test_fully_coherent_motions_are_one_motion_delayed():
    """|gamma| = 1 on firm ground: every support has the same stationary motion (the cross-
    spectral matrix has rank one), so each support's motion is the first's, delayed by the
    wave passage (whole steps here: 0.2 s and 0.5 s at 500 m/s), to round-off."""
    m = sim.simulate([(0.0, 0.0), (100.0, 0.0), (250.0, 0.0)], STEP, 20.0, CP, None, seed=3,
                    wave=co.WavePassage(500.0, 0.0), envelope=lambda t: np.minimum(t / 3, 1),
                    highpass=False)
    assert m.delays == pytest.approx([0.0, 0.2, 0.5], abs=1e-15)
    first = m.acceleration[0]
    peak = np.max(np.abs(first))
    for row, shift in zip(m.acceleration[1:], (20, 50)):
        assert not np.any(row[:shift])
        assert np.max(np.abs(row[shift:] - first[:first.size - shift])) < 1e-12 * peak


def test_a_simulated_motion_ends_at_rest():
    """The high-pass post-filter runs on until it has settled: the final velocity and
    displacement are below 1e-3 of their peaks at every support."""
    m = sim.simulate(LINE, STEP, 20.0, CP, co.HarichandranVanmarcke(), seed=5,
                    envelope=lambda t: np.sin(math.pi * np.clip(t / 20.0, 0, 1)) ** 2,
                    wave=co.WavePassage(700.0, 45.0))
    _, v, d = m.kinematics()
    assert np.all(np.abs(v[:, -1]) < 1e-3 * np.max(np.abs(v), axis=1))
    assert np.all(np.abs(d[:, -1]) < 1e-3 * np.max(np.abs(d), axis=1))
    assert any("7.96 s for the high-pass" in n for n in m.notes)


@pytest.mark.slow
@pytest.mark.parametrize("model", [co.HarichandranVanmarcke(), co.LucoWong(0.25, 400.0)],
                         ids=["harichandran_vanmarcke", "luco_wong"])
def test_the_simulated_coherency_is_the_model(model):
    """The coherency of 200 realisations (Hann-tapered cross-periodograms, smoothed over 7
    bins of 0.05 Hz) at three distances and four frequencies is the model's within four
    jackknife standard errors (plus 0.02 for the smoothing's bias): its modulus, and its phase
    the wave passage's exp(-i w tau_jk), here removed so that the real part is compared."""
    wave = co.WavePassage(800.0, 10.0)
    runs = np.array([sim.simulate(LINE, STEP, 30.0, CP, model, seed=s, wave=wave).acceleration
                     for s in range(200)])
    per, omega = _spectra(runs, slice(700, 700 + 2048))
    distance = co.separations(LINE)
    tau = wave.arrivals(LINE)
    for hz in (1.0, 2.5, 5.0, 8.0):
        b = int(np.argmin(np.abs(omega - 2 * math.pi * hz)))
        for j, k in ((0, 1), (1, 2), (0, 2)):
            def aligned(total, j=j, k=k, b=b):
                return np.real(_coherency(total)[j, k, b]
                               * np.exp(1j * omega[b] * (tau[j] - tau[k])))

            estimate, error = _jackknife(per, aligned)
            expected = float(model(omega[b], distance[j, k]))
            assert abs(estimate - expected) < 4 * error + 0.02, (hz, j, k, estimate, expected)


@pytest.mark.slow
def test_each_support_keeps_its_auto_spectrum_and_the_sites_their_phase():
    """Stationary motions (no modulating function, no high-pass) on firm ground and on two
    soil columns: each support's averaged periodogram is |H_j|^2 S_g in 0.5 Hz bands (within
    four jackknife standard errors), and the cross-spectrum's phase is arg(H_j H_k^*), the
    sign of the convention S_jk = E[X_j X_k^*]."""
    sites = [None, co.SoilColumn(2.0, 0.3), co.SoilColumn(1.2, 0.2, kind="layer")]
    runs = np.array([sim.simulate(LINE, STEP, 2047 * STEP, CP, co.LucoWong(0.1, 600.0),
                                 seed=s, sites=sites, highpass=False).acceleration
                     for s in range(150)])
    per, omega = _spectra(runs, slice(0, 2048))
    taper = np.sum(np.hanning(2048) ** 2)
    h = co.site_transfers(omega, sites, 3)
    for lo_hz in (0.5, 1.0, 2.0, 4.0, 8.0):
        band = (omega >= 2 * math.pi * lo_hz) & (omega < 2 * math.pi * (lo_hz + 0.5))
        for j in range(3):
            def level(total, j=j, band=band):
                return np.mean(np.real(total[j, j, band])) / per.shape[0]

            estimate, error = _jackknife(per, level)
            # E|X|^2 = (2 pi / dt) S sum(taper^2), a two-sided S
            expected = np.mean(np.abs(h[j, band]) ** 2 * CP(omega[band])) * 2 * math.pi \
                / STEP * taper
            assert abs(estimate - expected) < 4 * error, (lo_hz, j, estimate, expected)
    for hz in (0.5, 2.0, 3.5, 5.0):  # where the phases are nearly linear over the smoothing
        b = int(np.argmin(np.abs(omega - 2 * math.pi * hz)))
        for j, k in ((0, 1), (1, 2), (0, 2)):
            def phase(total, j=j, k=k, b=b):
                return np.angle(_smooth(total)[j, k, b])

            estimate, error = _jackknife(per, phase)
            expected = np.angle(h[j, b] * np.conj(h[k, b]))
            assert abs(estimate - expected) < 4 * error + 0.02, (hz, j, k, estimate, expected)


def test_the_mid_time_filter_spectrum_has_unit_variance():
    """int S dw = 1 over all w (the unit-variance process the model's q(t) modulates); q of
    rezaeian_mid_time has the parameters' I_a, D5-95 and t_mid."""
    from scipy import integrate

    from pframe.excitation.stochastic import RezaeianParameters

    params = RezaeianParameters(arias=0.3, d595=8.0, tmid=6.0, frequency=4.0, slope=-0.1,
                                damping=0.25)
    spectrum, q, duration = sim.rezaeian_mid_time(params)
    total, _ = integrate.quad(lambda w: 2.0 * spectrum(w), 0.0, np.inf, limit=400)
    assert total == pytest.approx(1.0, rel=1e-8)
    assert q.arias() == pytest.approx(0.3, rel=1e-12)
    assert q.energy_time(0.95) - q.energy_time(0.05) == pytest.approx(8.0, rel=1e-9)
    assert duration > q.energy_time(0.95)


def test_the_coherency_models_closed_forms():
    """Luco-Wong is exp(-1) at alpha w d / v_s = 1; Harichandran-Vanmarcke is 1 at d = 0 and
    its theta(f) is its scale of fluctuation, 2 int_0^inf |gamma| dd = theta(f) (the
    normalisation by 1 - A + alpha A), with the SMART-1 event 20 parameters by default."""
    from scipy import integrate

    lw = co.LucoWong(0.2, 500.0)
    assert lw(10.0, 500.0 / (0.2 * 10.0)) == pytest.approx(math.exp(-1.0), rel=1e-14)
    hv = co.HarichandranVanmarcke()
    assert (hv.amplitude, hv.alpha, hv.k, hv.f0, hv.b) == (0.736, 0.147, 5210.0, 1.09, 2.78)
    for hz in (0.2, 1.09, 3.0, 10.0):
        w = 2 * math.pi * hz
        assert hv(w, 0.0) == pytest.approx(1.0, abs=1e-15)
        theta = hv.k / math.sqrt(1.0 + (hz / hv.f0) ** hv.b)
        scale, _ = integrate.quad(lambda d, w=w: 2.0 * hv(w, d), 0.0, np.inf, limit=200)
        assert scale == pytest.approx(theta, rel=1e-8)


def test_the_soil_columns_amplify_and_respond_after_the_input():
    """SDOF column (Der Kiureghian 1996): H(0) = 1, |H(w_s)| = sqrt(1 + 4 zeta^2) / (2 zeta),
    causal in this module's convention (x(t) = sum X e^{+i w t}): a pulse filtered by H gives
    nothing before the pulse. Uniform layer (Kramer 1996): |H| at f_s and 3 f_s about
    2 / (pi zeta) and 2 / (3 pi zeta) for small damping; its frequency-independent
    (hysteretic) damping is not causal, and its precursor is the 0.2 % of the docs."""
    sdof = co.SoilColumn(2.0, 0.2)
    ws = 2 * math.pi * 2.0
    assert abs(sdof(0.0)) == pytest.approx(1.0)
    assert abs(sdof(ws)) == pytest.approx(math.sqrt(1 + 4 * 0.04) / 0.4, rel=1e-14)
    layer = co.SoilColumn(2.0, 0.01, kind="layer")
    assert abs(layer(0.0)) == pytest.approx(1.0)
    assert abs(layer(ws)) == pytest.approx(2 / (math.pi * 0.01), rel=0.01)
    assert abs(layer(3 * ws)) == pytest.approx(2 / (3 * math.pi * 0.01), rel=0.03)
    t = np.arange(8192) * STEP
    pulse = _pulse(t, t0=20.0, width=0.05, hz=0.0)
    omega = 2 * math.pi * np.fft.rfftfreq(t.size, STEP)
    for column, precursor in ((sdof, 1e-9), (co.SoilColumn(1.0, 0.1, kind="layer"), 3e-3)):
        out = np.fft.irfft(column(omega) * np.fft.rfft(pulse), t.size)
        before = np.max(np.abs(out[t < 19.7]))
        assert before < precursor * np.max(np.abs(out)), column


# ----------------------------------------------------------------------------------------
# Motions conditioned on a record


def _band_limited(noise, hz=15.0):
    """``noise`` without its content above ``hz``, tapered to zero over a second at each end
    (sin^2): a record whose fractional delays are exact to about 1e-7 of its peak."""
    spectrum = np.fft.rfft(noise)
    spectrum[np.fft.rfftfreq(noise.size, STEP) > hz] = 0.0
    ends = np.ones(noise.size)
    ramp = np.sin(0.5 * math.pi * np.arange(100) / 100) ** 2
    ends[:100], ends[-100:] = ramp, ramp[::-1]
    return np.fft.irfft(spectrum, noise.size) * ends


def test_the_recorded_support_keeps_the_record():
    """Bit for bit, from the whole step at which the wave reaches it; the supports the wave
    reaches first start before it, every motion starts at rest, and the notes say which
    support holds the record."""
    from pframe.excitation.conditioned import conditioned

    a = _band_limited(np.random.default_rng(4).standard_normal(1500))
    args = (a, STEP, LINE, co.HarichandranVanmarcke())
    kw = {"recorded": 1, "seed": 2, "wave": co.WavePassage(650.0, 0.0),
          "sites": [co.SoilColumn(2, 0.2), None, None]}
    m = conditioned(*args, **kw)
    start = round(m.delays[1] / STEP)  # after the conditional mean's part before the record
    assert m.delays[1] == start * STEP and m.delays[0] == pytest.approx(
        start * STEP - 60.0 / 650.0, abs=1e-12)
    assert np.array_equal(m.acceleration[1, start:start + a.size], a)
    assert not np.any(m.acceleration[1, :start]) and not np.any(m.acceleration[1, start + 1500:])
    # at rest at t = 0: the fractional delays' band-limited interpolation, to about 1e-6
    assert np.max(np.abs(m.acceleration[:, 0])) < 1e-5 * np.max(np.abs(m.acceleration))
    assert "support 1 keeps the record" in m.notes[0]
    assert np.array_equal(conditioned(*args, **kw).acceleration, m.acceleration)


def test_a_support_that_undoes_the_records_column_is_named():
    """Firm ground conditioned on a record on an SDOF column: |H_u / H_0| grows as
    w / (2 zeta_0 w_0), 1 / (2 * 0.2 * 2 Hz) per Hz, up to about 62 at 50 Hz."""
    from pframe.excitation.conditioned import conditioned

    m = conditioned(_pulse(np.arange(1000) * STEP), STEP, LINE[:2], co.LucoWong(0.2, 400.0),
                    seed=1, sites=[co.SoilColumn(2.0, 0.2), None])
    note = [n for n in m.notes if "amplifies the record" in n]
    assert len(note) == 1 and "support 1's conditional mean" in note[0] and "50 Hz" in note[0]


def test_fully_coherent_supports_get_the_record_delayed():
    """|gamma| = 1, firm ground: the conditional covariance is zero and the mean is the record,
    so every other support has the record arriving as the wave reaches it: the analytic
    a(t - d_s) of a band-limited record, to round-off."""
    from pframe.excitation.conditioned import conditioned

    t = np.arange(1200) * STEP
    m = conditioned(_pulse(t), STEP, [(50.0, 0.0), (0.0, 0.0), (180.0, 20.0)], None,
                    seed=1, wave=co.WavePassage(420.0, 0.0))
    for row, delay in zip(m.acceleration, m.delays):
        assert np.max(np.abs(row - _pulse(np.arange(row.size) * STEP - delay))) < 1e-12
    assert m.delays[0] == pytest.approx(math.ceil(50 / 420 / STEP) * STEP, abs=1e-12)
    assert m.delays[2] - m.delays[0] == pytest.approx(130.0 / 420.0, abs=1e-12)


def test_the_residual_follows_the_record_in_time():
    """Windows of 2 s: where the record is quiet (its first 10 s) the simulated motions are
    quiet too, their residual localised by the windows."""
    from pframe.excitation.conditioned import conditioned

    t = np.arange(2000) * STEP
    a = np.random.default_rng(5).standard_normal(t.size) * (t >= 10.0)
    m = conditioned(a, STEP, LINE, co.LucoWong(0.5, 300.0), seed=3, segment=2.0,
                    highpass=False)
    for row, delay in zip(m.acceleration[1:], m.delays[1:]):
        local = m.times - delay  # the record's time at this support
        assert np.sum(row[local < 8.5] ** 2) < 1e-6 * np.sum(row[(local > 11) & (local < 20)]
                                                             ** 2)


def _model_coherency(model, omega, positions, sites):
    """gamma_jk(w) without wave passage, site phases included: G_jk / sqrt(G_jj G_kk)."""
    g = co.lagged_matrix(omega, positions, model, sites)
    auto = np.real(np.einsum("fjj->fj", g))
    return g / np.sqrt(auto[:, :, None] * auto[:, None, :])


@pytest.mark.slow
def test_the_conditional_mean_and_covariance_are_the_theory():
    """One stationary segment, a fixed record, 300 realisations: the mean motion of each
    support is (H_u / H_0) |gamma_u0| applied to the record (within five standard errors of
    the mean at every sample; before the record, over the pre-roll, tapered to zero at t = 0;
    after it, the columns' free vibration alone), and the residual (motion less that mean)
    has the conditional covariance C_uv = G_uv - G_u0 G_0v / G_00 relative to the record's
    power: its power in 1 Hz bands over the record's is C_uu, and the coherency of the
    residuals at two supports is C_uv / sqrt(C_uu C_vv), within four jackknife standard
    errors (plus 0.02)."""
    from pframe.excitation.conditioned import conditioned

    model = co.LucoWong(0.4, 300.0)
    sites = [co.SoilColumn(3.0, 0.4), None, co.SoilColumn(1.5, 0.3)]
    record = sim.simulate(LINE, STEP, 2046 * STEP, CP, model, seed=99, sites=sites,
                         highpass=False).acceleration[0]
    assert record.size == 2048 and record[0] == 0.0  # a zero put before the stationary motion
    made = [conditioned(record, STEP, LINE, model, seed=s, sites=sites, segment=None,
                        highpass=False) for s in range(300)]
    runs = np.array([m.acceleration for m in made])
    lead = round(made[0].delays[0] / STEP)  # the conditional mean starts before the record
    span = slice(lead, lead + 2048)
    assert np.array_equal(runs[:, 0, span], np.broadcast_to(record, (300, 2048)))
    frame = runs.shape[-1]  # pre-roll, record, the soil columns' free vibration after it
    assert lead > 0 and frame == lead + 2048 + math.ceil(10.0 / (0.3 * 2 * math.pi * 1.5) / STEP)
    size = 8192
    omega = 2 * math.pi * np.fft.rfftfreq(size, STEP)
    g = co.lagged_matrix(omega, LINE, model, sites)
    gain = g[:, 1:, 0] / g[:, :1, 0].real
    framed = np.concatenate([np.zeros(lead), record])
    mean = np.fft.irfft(gain.T * np.fft.rfft(framed, size), size)[:, :frame]
    spread = runs[:, 1:, span].std(axis=0, ddof=1) / math.sqrt(300)
    assert np.max(np.abs(runs[:, 1:, span].mean(axis=0) - mean[:, span]) / spread) < 5.0
    after = slice(lead + 2048, frame)  # no residual there: the mean alone
    assert np.max(np.abs(runs[:, 1:, after] - mean[:, after])) < 1e-9 * np.max(np.abs(mean))
    # before the record too, but for the taper to zero at t = 0 of what is below 1e-4
    assert np.max(np.abs(runs[:, 1:, :lead] - mean[:, :lead])) < 1e-4 * np.max(np.abs(mean))
    assert np.all(runs[:, :, 0] == 0.0)
    residual = np.fft.rfft(runs[:, 1:, span] - mean[:, span], axis=-1)  # the coefficients
    per = residual[:, :, None, :] * np.conj(residual[:, None, :, :])
    omega = 2 * math.pi * np.fft.rfftfreq(2048, STEP)
    g = co.lagged_matrix(omega, LINE, model, sites)
    cov = (g[:, 1:, 1:] - g[:, 1:, :1] * g[:, :1, 1:] / g[:, :1, :1]) / g[:, :1, :1].real
    power = np.abs(np.fft.rfft(record)) ** 2
    for lo_hz in (1.0, 3.0, 6.0):
        band = (omega >= 2 * math.pi * lo_hz) & (omega < 2 * math.pi * (lo_hz + 1.0))
        for u in range(2):
            def ratio(total, u=u, band=band):
                return np.sum(np.real(total[u, u, band])) / (300 * np.sum(power[band]))

            estimate, error = _jackknife(per, ratio)
            expected = np.sum(np.real(cov[band, u, u]) * power[band]) / np.sum(power[band])
            assert abs(estimate - expected) < 4 * error + 0.02 * expected, (lo_hz, u)
        b = int(np.argmin(np.abs(omega - 2 * math.pi * (lo_hz + 0.5))))

        def conditional(total, b=b):
            c = _coherency(total)[0, 1, b]
            return np.array([c.real, c.imag])

        estimate, error = _jackknife(per, conditional)
        expected = cov[b, 0, 1] / np.sqrt(cov[b, 0, 0].real * cov[b, 1, 1].real)
        assert np.all(np.abs(estimate - [expected.real, expected.imag]) < 4 * error + 0.02), \
            (lo_hz, estimate, expected)


@pytest.mark.slow
@pytest.mark.parametrize("model, windows", [
    (co.HarichandranVanmarcke(), False), (co.LucoWong(0.25, 400.0), False),
    (co.HarichandranVanmarcke(), True)],
    ids=["harichandran_vanmarcke", "luco_wong", "harichandran_vanmarcke_windows"])
def test_records_of_the_model_conditioned_have_the_model_coherency(model, windows):
    """Records drawn from the model at support 0 (on a soil column), the other supports (one
    on another column) simulated conditioned on each: over 200 such arrays the coherency of
    every pair, the record's with the simulated ones' and between simulated ones, is the
    model's with its site phases (within four jackknife standard errors plus 0.02), and each
    support's power over the record's is |H_u / H_0|^2 (four standard errors plus 3 %); with
    one stationary segment, and with the defaults (windows of 4 s, the high-pass)."""
    from pframe.excitation.conditioned import conditioned

    options = {} if windows else {"segment": None, "highpass": False}

    sites = [co.SoilColumn(2.5, 0.4), None, co.SoilColumn(1.5, 0.3)]
    runs = []
    for s in range(200):
        record = sim.simulate(LINE, STEP, 2046 * STEP, CP, model, seed=1000 + s, sites=sites,
                             highpass=False).acceleration[0]
        made = conditioned(record, STEP, LINE, model, seed=s, sites=sites, **options)
        runs.append(made.acceleration)
    lead = round(made.delays[0] / STEP)
    per, omega = _spectra(np.array(runs), slice(lead, lead + 2048))
    gamma = _model_coherency(model, omega, LINE, sites)
    h = co.site_transfers(omega, sites, 3)
    for hz in (0.7, 2.0, 4.0, 7.0):
        b = int(np.argmin(np.abs(omega - 2 * math.pi * hz)))
        for j, k in ((0, 1), (0, 2), (1, 2)):
            def coherency(total, j=j, k=k, b=b):
                c = _coherency(total)[j, k, b]
                return np.array([c.real, c.imag])

            estimate, error = _jackknife(per, coherency)
            expected = gamma[b, j, k]
            assert np.all(np.abs(estimate - [expected.real, expected.imag]) < 4 * error
                          + 0.02), (hz, j, k, estimate, expected)
        band = (omega >= 2 * math.pi * hz) & (omega < 2 * math.pi * (hz + 0.5))
        for u in (1, 2):
            def gain(total, u=u, band=band):
                return np.sum(np.real(total[u, u, band])) / np.sum(np.real(total[0, 0, band]))

            estimate, error = _jackknife(per, gain)
            expected = np.mean(np.abs(h[u, band] / h[0, band]) ** 2)
            assert abs(estimate - expected) < 4 * error + 0.03 * expected, (hz, u)


@pytest.mark.slow
@pytest.mark.parametrize("name", ["ARL360.at2", "elCentro.AT2"])
def test_conditioned_supports_share_the_records_drift(name):
    """Real records, Harichandran-Vanmarcke at 60 and 160 m, the defaults (windows, high-pass):
    the simulated supports end with the record's velocity and displacement (what the record
    has, taken from rest after a zero), their final displacements within 1 % of the record's
    peak displacement of the record's, over 10 seeds: the residual adds no drift."""
    from conftest import record_file

    from pframe.excitation.conditioned import conditioned
    from pframe.excitation.records import read_record

    t, a = read_record(record_file(name))
    step = float(t[1] - t[0])
    for seed in range(10):
        m = conditioned(a, step, LINE, co.HarichandranVanmarcke(), seed=seed,
                        wave=co.WavePassage(800.0, 0.0))
        _, v, d = m.kinematics()
        peak_v, peak_d = np.max(np.abs(v[0])), np.max(np.abs(d[0]))
        assert np.all(np.abs(v[1:, -1] - v[0, -1]) < 3e-3 * peak_v)
        assert np.all(np.abs(d[1:, -1] - d[0, -1]) < 1e-2 * peak_d)
