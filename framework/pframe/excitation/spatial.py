"""Ground motions at several supports: what every generator returns (:class:`SupportMotions`),
the delays of a plane wave, and one motion delayed by it (:func:`wave_passage`); coherent
simulated motions are :func:`pframe.excitation.simulated.simulate`, motions conditioned on a
record :func:`pframe.excitation.conditioned.conditioned`
(docs/stochastic-motions.md#motions-at-several-supports).

Plain numbers and arrays in, :class:`SupportMotions` out: accelerations (m/s^2) of every
support on one time grid t_k = k dt from 0, with when the waves reach each support. The grid
starts when the waves reach the first support, so that every motion is zero before it
arrives and none is cut: the motions last longer than the motion they come from by the
largest delay, and their notes say by how much.

Every support's motion is zero at t = 0: a motion that does not start at zero is preceded by
one zero sample. Linear between samples and zero before the grid, each motion is then what
the trapezoid rule integrates from rest (:mod:`pframe.excitation.kinematics`, the kernel's
relations), the same at every support: two supports with the same motion delayed have the
same velocity and displacement, delayed (a motion whose first sample is not zero, taken
from rest at t = 0, would jump there, and its copy delayed by whole steps would ramp up over
a step instead: their velocities would differ by a_0 dt / 2 for good).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from pframe.excitation.coherency import WavePassage, support_positions

#: a delay within this many steps of a whole number of steps is applied as that whole number
#: (an exact copy of the samples, shifted)
WHOLE_STEP = 1e-9
#: the fractional delay is a band-limited interpolation: a record whose first or last sample
#: exceeds this part of its peak, or whose spectrum holds more than this part of its energy
#: above 0.8 of the Nyquist frequency, is not band-limited enough for it to be exact, and the
#: motions' notes say so
BAND_LIMIT = 1e-3


@dataclass(frozen=True)
class SupportMotions:
    """The ground accelerations of several supports on one time grid.

    ``acceleration`` (supports, samples), m/s^2, at t_k = k ``step`` from 0 (read-only), zero
    at t = 0; ``delays`` (s, >= 0): support s's motion is the motion it comes from (the
    record, the simulated motion), whose first sample is at its t = 0, shifted to t =
    ``delays[s]`` (zero before, to round-off for a fractional delay: docs); ``notes``: what a
    user must know about them (longer than the motion they come from, a delay that cannot be
    exact, ...)."""

    step: float
    acceleration: np.ndarray
    delays: np.ndarray
    description: str
    seed: int | None = None
    notes: tuple[str, ...] = field(default=())

    @property
    def times(self) -> np.ndarray:
        return np.arange(self.acceleration.shape[-1]) * self.step

    def kinematics(self, baseline=None):
        """(acceleration, velocity, displacement) of every support: the trapezoid rule twice
        from rest (:func:`pframe.excitation.kinematics.integrate`), after the baseline
        correction ``baseline`` (a :func:`pframe.excitation.kinematics.baseline_correct`
        keyword dict, e.g. ``{"fit": "displacement", "degree": 1}``) if given."""
        from pframe.excitation import kinematics

        if baseline is None:
            v, d = kinematics.integrate(self.acceleration, self.step)
            return self.acceleration, v, d
        done = kinematics.baseline_correct(self.acceleration, self.step, **baseline)
        return done.acceleration, done.velocity, done.displacement


#: a motion whose first sample is at most this part of its peak starts at rest: no zero is put
#: before it (the jump it would make there changes its velocity by a_0 dt / 2, negligible)
AT_REST = 1e-9


def starts_at_rest(samples) -> bool:
    """Whether every row of ``samples`` starts at zero (within :data:`AT_REST` of its peak)."""
    a = np.atleast_2d(np.asarray(samples, float))
    return bool(np.all(np.abs(a[:, 0]) <= AT_REST * np.max(np.abs(a), axis=1)))


def frozen(array: np.ndarray) -> np.ndarray:
    """``array``, made read-only (what :class:`SupportMotions` holds)."""
    array.setflags(write=False)
    return array


def check_step(step) -> float:
    """``step`` (s) as a float, or ValueError when it is not a finite number > 0."""
    if not (isinstance(step, (int, float, np.floating)) and math.isfinite(step) and step > 0):
        raise ValueError(f"the time step must be a finite number > 0 (s), got {step!r}")
    return float(step)


def check_samples(samples, what: str) -> np.ndarray:
    """``samples`` as a float array, or ValueError naming ``what`` when they are not at least
    two finite accelerations in one dimension."""
    a = np.asarray(samples, dtype=float)
    if a.ndim != 1 or a.size < 2:
        raise ValueError(f"{what} must be a one-dimensional array of at least 2 accelerations, "
                         f"got shape {a.shape}")
    if not np.all(np.isfinite(a)):
        raise ValueError(f"{what} holds a value that is not a finite number (sample "
                         f"{int(np.flatnonzero(~np.isfinite(a))[0])})")
    return a


def fast_length(count: int, even: bool = True) -> int:
    """The smallest length >= ``count`` that the FFT handles fast (even if ``even``)."""
    from scipy import fft

    n = fft.next_fast_len(int(count), real=True)
    while even and n % 2:
        n = fft.next_fast_len(n + 1, real=True)
    return n


# ----------------------------------------------------------------------------------------
# Delays


def delayed(samples, step: float, delay: float, length: int | None = None) -> np.ndarray:
    """The samples of a(t - ``delay``) at t_k = k ``step``, k < ``length`` (default: the
    samples' count plus the delay, rounded up), a(t) being zero before t = 0 and after its last
    sample.

    A delay that is a whole number of steps (to :data:`WHOLE_STEP`) shifts the samples: an
    exact copy, zeros before it. Any other delay multiplies the spectrum by exp(-i w delay):
    the FFT of the samples zero-padded to at least twice the output's length (so that nothing
    wraps round into it), i.e. the band-limited (sinc) interpolation of the samples, which is
    exact for a motion with no energy at or above the Nyquist frequency that starts and ends at
    zero; a motion that starts abruptly rings by about its first sample over the samples before
    it arrives."""
    a = np.asarray(samples, dtype=float)
    step = check_step(step)
    if not (math.isfinite(delay) and delay >= 0.0):
        raise ValueError(f"a delay must be a finite number >= 0 (s), got {delay!r}")
    shift = delay / step
    if length is None:
        length = a.size + int(math.ceil(shift - WHOLE_STEP))
    whole = round(shift)
    out = np.zeros(a.shape[:-1] + (length,))
    if abs(shift - whole) <= WHOLE_STEP:
        count = max(0, min(a.shape[-1], length - whole))
        out[..., whole:whole + count] = a[..., :count]
        return out
    size = fast_length(2 * max(length, a.shape[-1]))
    spectrum = np.fft.rfft(a, size)
    omega = 2.0 * math.pi * np.fft.rfftfreq(size, step)
    # irfft reads the Nyquist bin's real part: X_N cos(w_N delay), the symmetric choice
    out[...] = np.fft.irfft(spectrum * np.exp(-1j * omega * delay), size)[..., :length]
    return out


def support_delays(positions, step: float, wave: WavePassage | None,
                   reference: int | None = None, lead: int = 0) -> np.ndarray:
    """When the wave reaches each support (s) from t = 0 of the motions: tau_s - tau_min
    (``reference`` None: the first support reached is reached at t = 0), or tau_s - tau_r + P
    ``step`` with P the fewest whole steps that keep every delay >= 0 (``reference`` r: the
    reference support's delay is whole steps, so its motion is the given samples unchanged),
    all plus ``lead`` whole steps (a zero before every motion: module docstring).
    tau_s = (x_s, y_s) . (cos phi, sin phi) / v_app (:class:`WavePassage`)."""
    p = support_positions(positions)
    if wave is None:
        return np.full(len(p), lead * step)
    tau = wave.arrivals(p)
    if reference is None:
        return tau - np.min(tau) + lead * step
    first = tau[reference] - np.min(tau)  # how long before the reference the first is reached
    whole = lead + (int(math.ceil(first / step - WHOLE_STEP)) if first > 0 else 0)
    delays = tau - tau[reference] + whole * step
    delays[reference] = whole * step
    return np.maximum(delays, 0.0)


def band_notes(samples: np.ndarray, step: float, delays: np.ndarray, what: str) -> list[str]:
    """What makes a fractional delay of ``samples`` not exact (:data:`BAND_LIMIT`)."""
    shifts = delays / step
    if np.all(np.abs(shifts - np.round(shifts)) <= WHOLE_STEP):
        return []
    notes = []
    peak = float(np.max(np.abs(samples)))
    if peak == 0.0:
        return []
    edge = max(abs(samples[0]), abs(samples[-1])) / peak
    if edge > BAND_LIMIT:
        notes.append(f"{what} starts or ends at {100 * edge:.2g} % of its peak: a delay that is "
                     "not a whole number of steps interpolates it band-limited, which rings "
                     "about its ends (the motions before they arrive are not exactly zero)")
    power = np.abs(np.fft.rfft(samples)) ** 2
    high = float(np.sum(power[int(0.8 * (len(power) - 1)):]) / np.sum(power))
    if high > BAND_LIMIT:
        notes.append(f"{what} holds {100 * high:.2g} % of its energy above 0.8 of the Nyquist "
                     f"frequency ({0.4 / step:.4g} Hz): a delay that is not a whole number of "
                     "steps, a band-limited interpolation, is not exact for it; a smaller step "
                     "(resampled record) makes it so")
    return notes


def longer_note(delays: np.ndarray, extra: float = 0.0, why: str = "",
                 lead_why: str = "a zero before a motion that does not start at zero") -> list:
    """The note that the motions are longer than the motion they come from, and why: the
    lead before the first arrival, the wave's crossing, ``extra`` s for ``why``."""
    first, last = float(np.min(delays)), float(np.max(delays))
    parts = []
    if first > 0.0:
        parts.append(f"{first:.4g} s before the first arrival for {lead_why}")
    if last > first:
        parts.append(f"the wave reaches the last support {last - first:.4g} s after the first")
    if extra > 0.0:
        parts.append(f"{extra:.4g} s for {why}")
    if not parts:
        return []
    return [f"the support motions last {last + extra:.4g} s longer than the motion they come "
            "from: " + "; ".join(parts) + " (the analysis needs that long to see them whole)"]


def start_notes(samples: np.ndarray, step: float, what: str) -> list[str]:
    """What a user must know when ``samples`` do not start at zero: every support's motion is
    then preceded by a zero (module docstring), and so taken the motion may not end at rest
    (its baseline was corrected for a jump at its first sample)."""
    if starts_at_rest(samples):
        return []
    from pframe.excitation.kinematics import integrate

    v, d = integrate(np.concatenate([[0.0], samples]), step)
    text = (f"{what} starts at {samples[0]:.4g} m/s^2, not zero: every support's motion starts "
            "one step before it, from zero (the motions start at rest)")
    if abs(v[-1]) > 1e-3 * np.max(np.abs(v)) or abs(d[-1]) > 1e-3 * np.max(np.abs(d)):
        text += (f"; so taken it ends with a velocity of {v[-1]:.4g} m/s and a displacement of "
                 f"{d[-1]:.4g} m (peak {np.max(np.abs(d)):.4g} m): every support's motion has "
                 "that drift, which kinematics.baseline_correct(fit='rest') removes")
    return [text]


def wave_passage(record, step: float, positions, wave: WavePassage,
                 reference: int | None = None) -> SupportMotions:
    """One motion at every support, arriving as a plane wave crosses the site: support s gets
    a(t - d_s), d_s from :func:`support_delays` (exact for whole steps, band-limited
    interpolation otherwise: :func:`delayed`). ``record``: accelerations (m/s^2) every
    ``step`` s from t = 0; ``positions``: (x, y) of each support (m, site axes); ``reference``:
    the support whose motion is the record's samples unchanged (default: the first reached,
    whose delay is 0, or one step when the record does not start at zero). The motions are the
    record's length plus the largest delay (nothing is cut)."""
    a = check_samples(record, "the record")
    step = check_step(step)
    p = support_positions(positions)
    if reference is not None and not 0 <= reference < len(p):
        raise ValueError(f"reference support {reference} is not one of the {len(p)} supports")
    delays = support_delays(p, step, wave, reference, lead=int(not starts_at_rest(a)))
    length = a.size + int(math.ceil(float(np.max(delays)) / step - WHOLE_STEP))
    acc = np.array([delayed(a, step, float(d), length) for d in delays])
    notes = (longer_note(delays) + start_notes(a, step, "the record")
             + band_notes(a, step, delays, "the record"))
    description = (f"one record at {len(p)} supports, wave passage at {wave.velocity:g} m/s "
                   f"towards {wave.direction:g} degrees")
    return SupportMotions(step, frozen(acc), frozen(delays), description, None, tuple(notes))


def describe(coherency, wave, sites) -> str:
    """The coherency, wave passage and soil columns of a simulation, in words."""
    parts = [f"coherency {coherency!r}" if coherency is not None else "full coherence"]
    if wave is not None:
        parts.append(f"wave passage at {wave.velocity:g} m/s towards {wave.direction:g} degrees")
    if sites is not None and any(s is not None for s in sites):
        parts.append("site transfer functions " + ", ".join(repr(s) for s in sites))
    return "; ".join(parts)
