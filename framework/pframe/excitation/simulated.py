"""Coherent ground motions at several supports, simulated by the spectral representation
(Deodatis 1996): the firm-ground spectrum (:class:`CloughPenzienSpectrum`,
:class:`FilterSpectrum`), the coherency and soil columns of :mod:`pframe.excitation.coherency`,
a modulating function carried by the waves, and the wave passage
(docs/stochastic-motions.md#coherent-simulated-motions).
"""

from __future__ import annotations

import functools
import math
from dataclasses import dataclass

import numpy as np

from pframe.excitation.coherency import (
    WavePassage,
    cholesky_lower,
    lagged_matrix,
    support_positions,
)
from pframe.excitation.spatial import (
    WHOLE_STEP,
    SupportMotions,
    check_step,
    delayed,
    describe,
    fast_length,
    frozen,
    longer_note,
    starts_at_rest,
    support_delays,
)


@dataclass(frozen=True)
class CloughPenzienSpectrum:
    """The two-sided Clough-Penzien PSD ((m/s^2)^2 / (rad/s)) of the firm-ground motion, with
    the parameters of pframe's ``clough_penzien`` stochastic motion
    (:func:`pframe.excitation.stochastic.clough_penzien_psd`): ``intensity`` S_0 (m^2/s^3),
    ``ground_frequency`` w_g and ``filter_frequency`` w_f (rad/s), the dampings;
    ``filter_frequency`` 0 is Kanai-Tajimi."""

    intensity: float
    ground_frequency: float
    ground_damping: float
    filter_frequency: float = 0.0
    filter_damping: float = 0.0

    def __call__(self, omega) -> np.ndarray:
        from pframe.excitation.stochastic import clough_penzien_psd

        return clough_penzien_psd(omega, self.intensity, self.ground_frequency,
                                  self.ground_damping, self.filter_frequency, self.filter_damping)


@dataclass(frozen=True)
class FilterSpectrum:
    """The two-sided PSD of unit variance of the Rezaeian & Der Kiureghian (2008) filter at its
    mid-time: the response of an oscillator of frequency ``frequency`` f_mid (Hz) and damping
    ``damping`` zeta_f to white noise, whose impulse response is the model's
    h(tau) = w_f / sqrt(1 - zeta^2) exp(-zeta w_f tau) sin(w_f sqrt(1 - zeta^2) tau),

        S(w) = (2 zeta_f / (pi w_f)) w_f^4 / ((w_f^2 - w^2)^2 + 4 zeta_f^2 w_f^2 w^2),

    normalised so that int S dw over all w is 1 (int of w_f^4 / (...) is pi w_f / (2 zeta_f)).
    Times the model's modulating function q(t), the motion has q's expected Arias intensity
    (:func:`rezaeian_mid_time`)."""

    frequency: float
    damping: float

    def __call__(self, omega) -> np.ndarray:
        wf, z = 2.0 * math.pi * self.frequency, self.damping
        w2 = np.asarray(omega, float) ** 2
        return (2.0 * z / (math.pi * wf)) * wf**4 / ((wf * wf - w2) ** 2
                                                     + 4.0 * z * z * wf * wf * w2)


def rezaeian_mid_time(parameters):
    """(spectrum, envelope, duration) of a rezaeian2010 realisation's parameters
    (:class:`pframe.excitation.stochastic.RezaeianParameters`) for :func:`simulate`: the
    filter at its mid-time (:class:`FilterSpectrum` of f_mid, zeta_f: the slope f' is left
    out, a stationary filter), the gamma-form modulating function q of (I_a, D5-95, t_mid)
    and the time (s) by which q has delivered
    :data:`pframe.excitation.stochastic.ENERGY_COVERED` of I_a."""
    from pframe.excitation.stochastic import ENERGY_COVERED, gamma_envelope

    q = gamma_envelope(parameters.arias, parameters.d595, parameters.tmid)
    return (FilterSpectrum(parameters.frequency, parameters.damping), q,
            q.energy_time(ENERGY_COVERED))


# ----------------------------------------------------------------------------------------
# Coherent motions: the spectral representation (Deodatis 1996)


@functools.lru_cache(maxsize=8)
def _columns(positions: tuple, step: float, size: int, spectrum, coherency, sites) -> tuple:
    """The spectral representation's amplitudes 2 sqrt(dw) L_jm(w_ml) (Deodatis 1996), for each
    column m the rows j >= m over the frequencies w_ml = (l + (m + 1) / n) dw, l < size / 2:
    L the lower Cholesky factor of S_g(w) G(w) (:func:`lagged_matrix`, no wave passage)."""
    p = np.array(positions)
    n = len(p)
    dw = 2.0 * math.pi / (size * step)
    half = size // 2
    columns = []
    for m in range(n):
        omega = (np.arange(half) + (m + 1.0) / n) * dw
        psd = np.asarray(spectrum(omega), float) * np.ones(half)
        if not np.all(np.isfinite(psd) & (psd >= 0.0)):
            bad = omega[~(np.isfinite(psd) & (psd >= 0.0))][0]
            raise ValueError(f"the spectrum is not a finite number >= 0 at {bad:.6g} rad/s: a "
                             "power spectral density is")
        lower = cholesky_lower(lagged_matrix(omega, p, coherency, sites) * psd[:, None, None])
        columns.append(frozen(2.0 * math.sqrt(dw) * lower[:, m:, m].T))
    return tuple(columns)


def stationary(positions, step: float, count: int, spectrum, coherency=None, sites=None,
               rng=None) -> np.ndarray:
    """``count`` samples (every ``step`` s) at each support of a stationary Gaussian vector
    process of cross-spectral density S_g(w) G_jk(w) (:func:`lagged_matrix`: coherency and
    site transfer functions, no wave passage), by the spectral representation of Deodatis
    (1996, "Simulation of ergodic multivariate stochastic processes", J. Eng. Mech. 122(8);
    "Non-stationary stochastic vector processes: seismic ground motion applications", Prob.
    Eng. Mech. 11:149-167):

        f_j(t) = sum_{m <= j} sum_l 2 sqrt(dw) |L_jm(w_ml)| cos(w_ml t + arg L_jm(w_ml)
                                                                 + Phi_ml),
        w_ml = (l + m / n) dw,  l = 0 .. N - 1,  m = 1 .. n,  N dw = pi / step,

    L the lower Cholesky factor of the cross-spectral matrix, Phi_ml independent phases uniform
    on [0, 2 pi) (drawn from ``rng`` as one (n, N) array, row m the phases of column m), the
    frequencies double-indexed so that every sample function has the target cross-
    correlations over a period (ergodic). The sign of the phase follows this module's
    convention S_jk = E[X_j X_k^*] (coherency.py). Evaluated by one FFT per pair (j, m) of
    size 2N >= ``count``, times exp(i m dw t / n); the period 2 pi n / dw is longer than the
    motion."""
    p = support_positions(positions)
    size = fast_length(count)
    key = tuple(map(tuple, p.tolist()))
    sites_key = None if sites is None else tuple(sites)
    columns = _columns(key, float(step), size, spectrum, coherency, sites_key)
    n, half = len(p), size // 2
    phases = rng.uniform(0.0, 2.0 * math.pi, size=(n, half))
    k = np.arange(count)
    out = np.zeros((n, count))
    for m, column in enumerate(columns):
        coefficients = np.zeros((n - m, size), dtype=complex)
        coefficients[:, :half] = column * np.exp(1j * phases[m])
        series = np.fft.ifft(coefficients, axis=-1)[:, :count] * size
        out[m:] += (series * np.exp(2j * math.pi * (m + 1) * k / (n * size))).real
    return out


def simulate(positions, step: float, duration: float, spectrum, coherency=None, *, seed: int,
             envelope=None, wave: WavePassage | None = None, sites=None,
             highpass: bool = True) -> SupportMotions:
    """Coherent ground motions at the supports at ``positions`` ((x, y), m): the stationary
    process of :func:`stationary` (``spectrum``: a callable, the two-sided PSD S_g(w) of the
    firm-ground acceleration, (m/s^2)^2/(rad/s), e.g. :class:`CloughPenzienSpectrum`,
    :class:`FilterSpectrum`; ``coherency``: :class:`~pframe.excitation.coherency.LucoWong`,
    :class:`~pframe.excitation.coherency.HarichandranVanmarcke` or None for full coherence;
    ``sites``: one :class:`~pframe.excitation.coherency.SoilColumn` or None per support) over
    ``duration`` s, times the modulating function ``envelope`` q(t) (a callable of t in s, or
    None), each support's motion then delayed as the ``wave`` reaches it
    (:func:`support_delays`, :func:`delayed`):

        a_j(t) = q(t - d_j) f_j(t - d_j),

    so that the waves carry the modulating function with them and S_jk(w, t) = q(t - d_j)
    q(t - d_k) S_g H_j H_k^* |gamma_jk| exp(-i w (d_j - d_k)), Deodatis' (1996) uniformly
    modulated model with the wave-passage phase of the coherency.

    ``highpass``: then the critically damped high-pass post-filter of rezaeian2010
    (:func:`pframe.excitation.stochastic.highpass`, 0.2 Hz, run on over
    :func:`pframe.excitation.stochastic.settling_samples` of zeros) filters every support's
    motion alike: no residual velocity or displacement (at most 4.5e-4 of the end's), every
    auto- and cross-spectrum times the same |H_hp|^2, so the coherency is unchanged.

    ``seed``: numpy's PCG64, the phases drawn once as documented in :func:`stationary`: the
    same arguments give the same motions bit for bit."""
    from pframe.excitation.stochastic import highpass as post_filter
    from pframe.excitation.stochastic import settling_samples

    step = check_step(step)
    if not (isinstance(duration, (int, float)) and math.isfinite(duration) and duration > 0):
        raise ValueError(f"the duration must be a finite number > 0 (s), got {duration!r}")
    p = support_positions(positions)
    count = int(math.ceil(duration / step - WHOLE_STEP)) + 1
    rng = np.random.Generator(np.random.PCG64(int(seed)))
    motion = stationary(p, step, count, spectrum, coherency, sites, rng)
    if envelope is not None:
        motion *= np.asarray(envelope(np.arange(count) * step), float)
    lead = int(not starts_at_rest(motion))  # a zero before a motion that does not start at 0
    delays = support_delays(p, step, wave, lead=lead)
    length = count + int(math.ceil(float(np.max(delays)) / step - WHOLE_STEP))
    acc = np.array([delayed(row, step, float(d), length) for row, d in zip(motion, delays)])
    settle = 0.0
    if highpass:
        tail = settling_samples(step)
        acc = post_filter(np.concatenate([acc, np.zeros((len(p), tail))], axis=1), step)
        settle = tail * step
    notes = longer_note(delays, settle, "the high-pass filter to come to rest")
    description = (f"{len(p)} coherent simulated motions, seed {int(seed)}: "
                   f"{describe(coherency, wave, sites)}")
    return SupportMotions(step, frozen(acc), frozen(delays), description, int(seed),
                          tuple(notes))
