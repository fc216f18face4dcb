"""Motions at several supports conditioned on a record at one of them (Konakli & Der
Kiureghian 2012, "Simulation of spatially varying ground motions including incoherence,
wave-passage and differential site-response effects", EESD 41:495-513; the conditional
Gaussian distribution of the Fourier coefficients, Kameda & Morikawa 1992, Vanmarcke & Fenton
1991): the recorded support keeps its record exactly, the others are simulated so that the
motions at all supports have the model's coherency (docs/stochastic-motions.md).

At each Fourier frequency w the Fourier coefficients of the motions are jointly complex
Gaussian with covariance proportional to S_jk(w) = S_g H_j H_k^* |gamma_jk| exp(-i w tau_jk)
(:mod:`pframe.excitation.coherency`). Given the record's coefficient X_0, those of the other
supports u are Gaussian with

    mean   E[X_u | X_0] = (S_u0 / S_00) X_0 = (H_u / H_0) |gamma_u0| exp(-i w tau_u0) X_0,
    covariance  (S_uv - S_u0 S_0v / S_00) = S_00 C_uv,
                C_uv = (H_u H_v^* / |H_0|^2) (|gamma_uv| exp(-i w tau_uv)
                        - |gamma_u0| |gamma_0v| exp(-i w (tau_u0 + tau_0v))),

so the firm-ground spectrum cancels: S_00, the spectrum of the motion at the recorded
support, is estimated from the record (its smoothed periodogram), and nothing else is needed.
The wave passage factors out of both (tau_u0 + tau_0v = tau_uv): pframe builds each support's
motion without it and then delays the whole motion by tau_u - tau_0 (:func:`spatial.delayed`),
as :func:`simulated.simulate` does.
"""

from __future__ import annotations

import math

import numpy as np

from pframe.excitation.coherency import (
    WavePassage,
    cholesky_lower,
    lagged_matrix,
    site_transfers,
    support_positions,
)
from pframe.excitation.spatial import (
    WHOLE_STEP,
    SupportMotions,
    band_notes,
    check_samples,
    check_step,
    delayed,
    describe,
    fast_length,
    frozen,
    longer_note,
    start_notes,
    starts_at_rest,
    support_delays,
)

#: the length (s) of the windows over which the record is taken as stationary (Hann windows,
#: overlapping by half)
SEGMENT = 4.0
#: the width (Hz) of the Hann kernel that smooths the record's periodogram in each window
SMOOTHING = 0.5
#: the filters' free vibration (soil columns, high-pass) is followed until it has decayed by
#: e^-DECAY
DECAY = 10.0
#: the conditional mean, the record through |gamma_u0| (real: not causal), starts before the
#: record: the motions start 1.5 times the time beyond which the filter's impulse response
#: stays below this part of its peak before its centre, and the mean is tapered to zero over
#: the first third (beyond that time)
PRECURSOR = 1e-4
#: a conditional mean that amplifies the record by more than this at some frequency is named
#: in the notes (a support without the soil column the record was taken on)
GAIN_NOTE = 10.0


def conditioned(record, step: float, positions, coherency=None, *, recorded: int = 0,
                seed: int, wave: WavePassage | None = None, sites=None,
                segment: float | None = SEGMENT, smoothing: float = SMOOTHING,
                highpass: bool = True) -> SupportMotions:
    """Motions at the supports at ``positions`` ((x, y), m) given the ``record`` (m/s^2 every
    ``step`` s from t = 0) at support ``recorded``: that support's motion is the record's
    samples unchanged; the others are their conditional mean (a filter of the record) plus a
    Gaussian residual of the conditional covariance (module docstring), each delayed as the
    ``wave`` reaches it. ``coherency``, ``sites``, ``wave`` as for
    :func:`pframe.excitation.simulated.simulate` (the recorded support's soil column is the one
    the record was taken on).

    Non-stationarity: the residual's spectrum is the record's in Hann windows of ``segment``
    s overlapping by half (the windows sum to 1, but over the first half window, where the
    sum rises from 0 at the record's start; each window's residual is generated with the
    periodogram of the windowed record, smoothed over ``smoothing`` Hz, divided by the
    window's mean square, and localised by the window's square root, so the residual's
    variance follows the record's mean square in time); ``segment`` None: the whole record is
    one stationary segment. The conditional mean is the whole record filtered: a filter that
    is not causal (|gamma| is real), whose part before the record's start is kept
    (:data:`PRECURSOR`: the motions start that much earlier, the mean tapered to zero at
    t = 0 (sin^2) over the first third, so that every motion starts at rest).

    ``highpass``: the residual, summed over the windows, goes through the rezaeian2010
    post-filter (:func:`pframe.excitation.stochastic.highpass`, 0.2 Hz): it ends at rest, and
    its spectrum is |H_hp|^2 times the conditional covariance's (the windows would otherwise
    bring power down to zero frequency, a drift of the simulated supports). The conditional
    mean's drift is the record's, filtered.

    The motions run on after the record until the soil columns' and the high-pass filter's
    free vibration has decayed by e^-:data:`DECAY`, plus the largest delay. ``delays``: where
    the record's first sample is at each support; the recorded support's is whole steps, the
    fewest that keep every delay >= 0 after the pre-roll. ``seed``: numpy's PCG64, the
    residual's normal variables drawn window by window in time order, for each a (2,
    unrecorded supports, frequencies) array."""
    a0 = check_samples(record, "the record")
    step = check_step(step)
    p = support_positions(positions)
    n = len(p)
    if not (isinstance(recorded, (int, np.integer)) and 0 <= recorded < n):
        raise ValueError(f"recorded support {recorded!r} is not one of the {n} supports")
    if segment is not None and not (math.isfinite(segment) and segment > 0):
        raise ValueError(f"the segment must be a finite length > 0 (s) or None, got {segment!r}")
    if not (math.isfinite(smoothing) and smoothing >= 0):
        raise ValueError(f"the smoothing must be a finite width >= 0 (Hz), got {smoothing!r}")
    order = [recorded] + [j for j in range(n) if j != recorded]  # recorded first
    site_list = None if sites is None else [sites[j] for j in order]
    tail = _tail_samples(step, site_list, highpass) if n > 1 else 0
    precursor = _precursor(a0.size + tail, step, p[order], coherency)
    lead = max(precursor + precursor // 2, int(not starts_at_rest(a0)))
    framed = np.concatenate([np.zeros(lead), a0, np.zeros(tail)])
    rng = np.random.Generator(np.random.PCG64(int(seed)))
    motions = np.zeros((n, framed.size))
    if n > 1:
        motions[1:] = _simulated(framed, lead, a0.size, step, p[order], coherency, site_list,
                                 segment, smoothing, highpass, rng)
    delays = support_delays(p, step, wave, recorded)[order]  # of the frame
    length = framed.size + int(math.ceil(float(np.max(delays)) / step - WHOLE_STEP))
    acc = np.zeros((n, length))
    whole = round(delays[0] / step) + lead
    acc[recorded, whole:whole + a0.size] = a0  # the record's samples themselves
    for row, j in enumerate(order[1:], start=1):
        acc[j] = delayed(motions[row], step, float(delays[row]), length)
    out_delays = np.empty(n)
    out_delays[order] = delays + lead * step
    notes = _notes(a0, step, out_delays, recorded, tail * step, segment, smoothing)
    notes += _gain_notes(step, p[order], site_list, order)
    description = (f"{n} motions conditioned on a record at support {recorded}, seed "
                   f"{int(seed)}: {describe(coherency, wave, sites)}")
    return SupportMotions(step, frozen(acc), frozen(out_delays), description, int(seed),
                          tuple(notes))


def _simulated(framed, lead, count, step, positions, coherency, sites, segment, smoothing,
               highpass, rng) -> np.ndarray:
    """The unrecorded supports' motions on the record's frame (``lead`` zeros, the ``count``
    samples of the record, the tail), before the wave passage: the conditional mean, its part
    before the record tapered to zero at the frame's start, plus the residual."""
    mean = _conditional_mean(framed, step, framed.size, positions, coherency, sites)
    taper = lead // 3
    if taper:
        mean[:, :taper] *= np.sin(0.5 * math.pi * np.arange(taper) / taper) ** 2
    else:
        mean[:, :lead] = 0.0
    residual = np.zeros_like(mean)
    record = framed[lead:lead + count]
    residual[:, lead:] = _residual(record, step, framed.size - lead, positions, coherency,
                                   sites, segment, smoothing, highpass, rng)
    return mean + residual


def _precursor(count: int, step: float, positions, coherency) -> int:
    """Samples before its centre beyond which the impulse response of every |gamma_u0|
    (zero phase) stays below :data:`PRECURSOR` of its peak (0 for full coherence)."""
    if coherency is None or len(positions) < 2:
        return 0
    size = fast_length(2 * count)
    omega = 2.0 * math.pi * np.fft.rfftfreq(size, step)
    d = np.hypot(*(positions[1:] - positions[0]).T)
    kernel = np.abs(np.fft.irfft(coherency(omega[None, :], d[:, None]), size))
    before = kernel[:, size // 2:]  # before[:, -1 - i]: i + 1 steps before the centre
    far = before > PRECURSOR * np.max(kernel, axis=1, keepdims=True)
    return int(max((before.shape[1] - int(np.argmax(row)) if row.any() else 0) for row in far))


def _tail_samples(step: float, sites, highpass: bool) -> int:
    """Samples after the record over which every filter's free vibration decays by
    e^-DECAY: a soil column's 1 / (zeta_s w_s), the high-pass filter's 1 / w_c."""
    from pframe.excitation.stochastic import HIGHPASS_HZ

    slowest = 1.0 / (2.0 * math.pi * HIGHPASS_HZ) if highpass else 0.0
    for site in sites or ():
        if site is not None:
            slowest = max(slowest, site.decay_time())
    return int(math.ceil(DECAY * slowest / step - WHOLE_STEP))


def _conditional_mean(a0, step, frame, positions, coherency, sites) -> np.ndarray:
    """(H_u / H_0) |gamma_u0| applied to the record (no wave passage), for u = 1 .. n - 1, on
    ``frame`` samples; zero-padded to twice that, so the filters' tails do not wrap round."""
    size = fast_length(2 * frame)
    omega = 2.0 * math.pi * np.fft.rfftfreq(size, step)
    g = lagged_matrix(omega, positions, coherency, sites)  # H_j H_k^* |gamma_jk|
    h0 = site_transfers(omega, None if sites is None else sites[:1], 1)[0]
    gain = g[:, 1:, 0] / (h0 * np.conj(h0))[:, None]  # = (H_u / H_0) |gamma_u0|
    return np.fft.irfft(gain.T * np.fft.rfft(a0, size), size)[:, :frame]


def _windows(count: int, step: float, segment: float | None):
    """(start, weights) of each Hann window: sin^2 of length 2 H samples every H samples from
    the record's start, clipped to its end: they sum to 1 but over the first H samples, where
    the sum rises from 0 (the residual starts from rest, as the record does); one window of
    ones without segments or when the record is shorter than one."""
    hop = 0 if segment is None else max(1, int(round(segment / (2.0 * step))))
    if segment is None or 2 * hop >= count:
        return [(0, np.ones(count))]
    shape = np.sin(0.5 * math.pi * np.arange(2 * hop) / hop) ** 2
    out = []
    for start in range(0, count - hop, hop):
        lo, hi = max(start, 0), min(start + 2 * hop, count)
        if hi > lo:
            out.append((lo, shape[lo - start:hi - start]))
    return out


def _smoothed(power: np.ndarray, step: float, size: int, width: float) -> np.ndarray:
    """``power`` smoothed over ``width`` Hz by a normalised Hann kernel, mirrored at 0 and at
    the Nyquist frequency (the periodogram is even about both)."""
    from scipy import ndimage

    half = int(round(0.5 * width * size * step))
    if half < 1:
        return power
    kernel = np.hanning(2 * half + 3)[1:-1]
    return ndimage.convolve1d(power, kernel / kernel.sum(), mode="mirror")


def _residual(a0, step, frame, positions, coherency, sites, segment, smoothing, highpass,
              rng) -> np.ndarray:
    """The Gaussian residual of the supports u = 1 .. n - 1, window by window (:func:`_windows`):
    in each, Fourier coefficients L_C(w) xi sqrt(size P(w) / sum w^2), P the windowed record's
    smoothed periodogram, L_C the Cholesky factor of the conditional covariance C (module
    docstring), xi complex standard normal (real at 0 and at the Nyquist frequency)."""
    from pframe.excitation.stochastic import highpass as highpass_filter

    windows = _windows(a0.size, step, segment)
    size = fast_length(max(len(w) for _, w in windows))
    omega = 2.0 * math.pi * np.fft.rfftfreq(size, step)
    g = lagged_matrix(omega, positions, coherency, sites)
    h0 = g[:, 0, 0].real  # |H_0|^2
    cov = (g[:, 1:, 1:] - g[:, 1:, :1] * g[:, :1, 1:] / h0[:, None, None]) / h0[:, None, None]
    factor = cholesky_lower(cov)  # (F, u, u)
    count = g.shape[1] - 1
    out = np.zeros((count, frame))
    for lo, weights in windows:
        span = len(weights)
        power = np.abs(np.fft.rfft(weights * a0[lo:lo + span], size)) ** 2
        scale = np.sqrt(size * _smoothed(power, step, size, smoothing) / np.sum(weights**2))
        normal = rng.standard_normal((2, count, omega.size))
        xi = (normal[0] + 1j * normal[1]) / math.sqrt(2.0)
        xi[:, 0] = normal[0, :, 0]
        if size % 2 == 0:
            xi[:, -1] = normal[0, :, -1]
        coefficients = np.einsum("fuv,vf->uf", factor, xi) * scale
        out[:, lo:lo + span] += np.sqrt(weights) * np.fft.irfft(coefficients, size)[:, :span]
    # the windows shift power down to zero frequency (a window's spectrum is as wide as the
    # inverse of its length): filtered after the sum, the residual ends at rest
    return highpass_filter(out, step) if highpass else out


def _notes(a0, step, delays, recorded, tail, segment, smoothing) -> list[str]:
    how = (f"the record taken as stationary in windows of {segment:g} s" if segment is not None
           else "the whole record taken as one stationary segment")
    notes = [f"support {recorded} keeps the record (its samples unchanged, from t = "
             f"{delays[recorded]:.6g} s); the others are simulated conditioned on it, {how}, "
             f"its periodogram smoothed over {smoothing:g} Hz"]
    notes += longer_note(delays, tail, "the soil columns' and the high-pass filter's free "
                          "vibration to decay", "the conditional mean's part before the record "
                          "(a filter that is not causal) or a zero before a record that does "
                          "not start at zero")
    return notes + start_notes(a0, step, "the record") + band_notes(a0, step, delays,
                                                                       "the record")


def _gain_notes(step, positions, sites, order) -> list[str]:
    """Supports whose conditional mean amplifies the record by more than :data:`GAIN_NOTE`:
    |H_u / H_0| grows with frequency where the recorded support's soil column filters high
    frequencies that the support's own column (or firm ground) lets through."""
    if sites is None or sites[0] is None:
        return []
    omega = 2.0 * math.pi * np.linspace(0.0, 0.5 / step, 2049)
    h = site_transfers(omega, sites, len(sites))
    notes = []
    for row in range(1, len(sites)):
        ratio = np.abs(h[row] / h[0])
        k = int(np.argmax(ratio))
        if ratio[k] > GAIN_NOTE:
            notes.append(f"support {order[row]}'s conditional mean amplifies the record by "
                         f"{ratio[k]:.3g} at {omega[k] / (2 * math.pi):.4g} Hz (|H_u / H_0|: the "
                         "recorded support's soil column filters what this support's lets "
                         "through), the record's noise there too")
    return notes
