"""The characteristic amplitude ``a_p`` and circular frequency ``w_p`` of a ground motion.

Wu et al. (2021) make the equations dimensionless with the sine's amplitude ``a_p`` and
circular frequency ``w_p`` (length scale ``l_e = a_p / w_p^2``, time scale ``1 / w_p``). A
ground motion of any kind needs the same two numbers to have Pi groups (``pframe pi``), a
Pi form (``pframe expand``) and a dimensionless result file; :func:`characteristic` is the one
place that says what they are for each kind of excitation:

- a sine ``a_p sin(w_p t)``: its amplitude and circular frequency;
- a record: ``a_p`` its peak ground acceleration (PGA, the largest absolute value of its
  samples as applied) and ``w_p = 2 pi / T`` with ``T`` the characteristic period the scene
  states (``excitation.period``): ``mean``, the mean period ``T_m`` of Rathje, Abrahamson &
  Bray (1998), recommended by Rathje et al. (2004) as the best single frequency-content
  parameter, ``T_m = sum(C_i^2 / f_i) / sum(C_i^2)`` over the Fourier amplitudes ``C_i`` of
  0.25 to 20 Hz; or a period in seconds named by the user (the period of a pulse seen in the
  record, a site period, ...); or ``predominant``, the period ``T_p`` of the peak of the
  5%-damped pseudo-acceleration spectrum (Rathje et al. 1998, 2004).

A record may be scaled to a target PGA (``pga``) and compressed or stretched in time to a
target characteristic frequency (``frequency``), as shaking-table tests do with records:
:func:`apply_record` turns the record of the file into the record applied. The period is
always found on the file's own time axis (the 0.25-20 Hz band is a band of the file) and then
scaled with the time axis, so that a record and its time-scaled copy have exactly similar
characteristics.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from pframe.errors import InputError

#: the band of the mean period T_m (Hz of the record's own time axis), Rathje et al. (1998)
MEAN_PERIOD_BAND = (0.25, 20.0)


@dataclass(frozen=True)
class Characteristic:
    """``a_p`` (m/s^2) and ``w_p`` (rad/s) of an excitation, and what each was taken from."""

    amplitude: float
    frequency: float
    amplitude_is: str
    frequency_is: str


@dataclass(frozen=True, eq=False)
class AppliedRecord:
    """A record as the scene applies it (before ``scale``, which multiplies the acceleration).

    Attributes
    ----------
    times, acceleration : ndarray
        Sample times (s) and accelerations (m/s^2), with the PGA target and time scaling of
        the scene applied.
    amplitude_factor, time_factor : float
        What the file's accelerations and times were multiplied by.
    pga : float
        The peak absolute acceleration of the record as applied, ``scale`` included (m/s^2).
    period : float
        Its characteristic period as applied (s).
    period_is : str
        How the period was found (``mean period T_m ...`` or ``stated period``).
    """

    times: np.ndarray
    acceleration: np.ndarray
    amplitude_factor: float
    time_factor: float
    pga: float
    period: float
    period_is: str

    def __eq__(self, other) -> bool:
        if not isinstance(other, AppliedRecord):
            return NotImplemented
        return all(np.array_equal(getattr(self, f), getattr(other, f))
                   if isinstance(getattr(self, f), np.ndarray) else getattr(self, f) == getattr(other, f)
                   for f in self.__dataclass_fields__)

    __hash__ = None


def mean_period(times: np.ndarray, acceleration: np.ndarray) -> float:
    """``T_m = sum(C_i^2 / f_i) / sum(C_i^2)`` (s) over 0.25-20 Hz (Rathje et al. 1998).

    The samples are taken as equally spaced with the record's mean step (PEER records are).

    Raises
    ------
    InputError
        For a record that is zero, or has no Fourier amplitude in the band and above 0 Hz.
    """
    dt = float(times[-1] - times[0]) / (len(times) - 1)
    amplitude = np.abs(np.fft.rfft(acceleration))
    f = np.fft.rfftfreq(len(acceleration), dt)
    low, high = MEAN_PERIOD_BAND
    band = (f >= low) & (f <= high)
    if not np.any(band & (amplitude > 0)):
        band = f > 0
    c2 = amplitude[band] ** 2
    if not np.any(c2 > 0):
        raise InputError("the record is zero: it has no mean period")
    return float(np.sum(c2 / f[band]) / np.sum(c2))


def sdof_peak_displacements(times: np.ndarray, acceleration: np.ndarray, periods: np.ndarray,
                            damping: float = 0.05) -> np.ndarray:
    """Peak relative displacement (m) of linear oscillators of the given periods (s) and damping
    ratio under the ground acceleration taken as linear between (equally spaced) samples, at
    rest one step before the first sample (the record rises from zero over that step).

    Each step is exact for that piecewise-linear excitation (the method of Nigam & Jennings
    1969): with ``z = (u, v)``, ``z' = F z - a_g(t)`` and ``a_g`` linear over the step, the
    state after the step is the exponential of the augmented matrix
    ``[[F h, -e_2 h, 0], [0, 0, 1], [0, 0, 0]]`` applied to ``(z_n, a_n, a_{n+1} - a_n)``:
    ``z_{n+1} = Phi z_n + g_0 a_n + g_1 (a_{n+1} - a_n)``. For ``u`` alone that recurrence is a
    second-order filter, run by :func:`scipy.signal.lfilter`.
    """
    from scipy.linalg import expm
    from scipy.signal import lfilter

    step = float(times[-1] - times[0]) / (len(times) - 1)
    drive = np.concatenate(([0.0], acceleration))  # at rest before the first sample
    peaks = np.empty(len(periods))
    for i, period in enumerate(np.asarray(periods, dtype=float)):
        w = 2.0 * np.pi / period
        augmented = np.zeros((4, 4))
        augmented[:2, :2] = [[0.0, step], [-w * w * step, -2.0 * damping * w * step]]
        augmented[1, 2] = -step
        augmented[2, 3] = 1.0
        e = expm(augmented)
        phi, g0, g1 = e[:2, :2], e[:2, 2], e[:2, 3]
        b0, b1 = g0 - g1, g1  # z_{n+1} = Phi z_n + b0 a_n + b1 a_{n+1}
        numerator = [b1[0], b0[0] - phi[1, 1] * b1[0] + phi[0, 1] * b1[1],
                     -phi[1, 1] * b0[0] + phi[0, 1] * b0[1]]
        denominator = [1.0, -np.trace(phi), np.linalg.det(phi)]
        peaks[i] = np.max(np.abs(lfilter(numerator, denominator, drive)))
    return peaks


def predominant_period(times: np.ndarray, acceleration: np.ndarray) -> float:
    """``T_p`` (s): the period of the peak of the 5%-damped pseudo-acceleration spectrum
    ``w^2 max|u|`` over 0.02-4 s (Rathje et al. 1998, 2004), on 400 log-spaced periods, refined
    by a parabola through the peak and its two neighbours in log period. The record is
    sampled at steps of at most 1/8 of the shortest period (linearly between its samples, as
    the kernel applies it), so that a peak between samples is not missed by more than 8 %
    at 0.02 s and 0.5 % at 0.1 s."""
    periods = np.geomspace(0.02, 4.0, 400)
    parts = max(1, math.ceil((times[-1] - times[0]) / (len(times) - 1) / (periods[0] / 8)))
    fine = np.linspace(times[0], times[-1], (len(times) - 1) * parts + 1)
    acceleration = np.interp(fine, times, acceleration)
    psa = (2.0 * np.pi / periods) ** 2 * sdof_peak_displacements(fine, acceleration, periods)
    i = int(np.argmax(psa))
    if not np.any(psa > 0):
        raise InputError("the record is zero: it has no predominant period")
    if 0 < i < len(periods) - 1:
        x = np.log(periods[i - 1:i + 2])
        c = np.polyfit(x, psa[i - 1:i + 2], 2)
        if c[0] < 0:
            return float(np.exp(np.clip(-c[1] / (2 * c[0]), x[0], x[2])))
    return float(periods[i])


def record_period(how, times: np.ndarray, acceleration: np.ndarray) -> tuple[float, str]:
    """The characteristic period (s, on the file's time axis) and how it was found.

    ``how`` is ``"mean"`` (:func:`mean_period`), ``"predominant"``
    (:func:`predominant_period`) or a period in seconds stated by the user.
    """
    if how == "mean":
        low, high = MEAN_PERIOD_BAND
        return mean_period(times, acceleration), (
            f"mean period T_m (Rathje et al. 1998, 2004) over {low:g}-{high:g} Hz of the file")
    if how == "predominant":
        return predominant_period(times, acceleration), (
            "predominant period T_p, the peak of the 5%-damped acceleration spectrum "
            "(Rathje et al. 1998, 2004)")
    return float(how), "the period stated in the scene (excitation.period)"


def apply_record(excitation, times: np.ndarray, acceleration: np.ndarray) -> AppliedRecord:
    """The record of the file (``times`` s, ``acceleration`` m/s^2) as ``excitation`` applies it:
    scaled to ``excitation.pga`` when given, and with its time axis multiplied so that its
    characteristic frequency ``2 pi / T`` is ``excitation.frequency`` when given.

    Raises
    ------
    InputError
        For a record of zero acceleration given a ``pga`` target.
    """
    file_pga = float(np.max(np.abs(acceleration)))
    file_period, period_is = record_period(excitation.period, times, acceleration)
    amplitude_factor = 1.0
    if excitation.pga is not None:
        if file_pga == 0.0:
            raise InputError("the record is zero: it cannot be scaled to a PGA")
        amplitude_factor = excitation.pga / file_pga
    time_factor = 1.0
    if excitation.frequency is not None:
        time_factor = (2.0 * math.pi / file_period) / excitation.frequency
    pga = abs(excitation.scale) * amplitude_factor * file_pga
    if excitation.pga is not None and excitation.scale == 1.0:
        pga = float(excitation.pga)  # the target itself, not the target to roundoff
    period = file_period * time_factor
    if excitation.frequency is not None:
        period = 2.0 * math.pi / excitation.frequency
    return AppliedRecord(times * time_factor, acceleration * amplitude_factor, amplitude_factor,
                         time_factor, pga, period, period_is)


def characteristic(excitation, record: AppliedRecord | None = None) -> Characteristic | None:
    """``a_p`` and ``w_p`` of an excitation definition; None without excitation.

    Parameters
    ----------
    excitation : Sine, Record, a pulse (Cycloidal, Ricker) or None
        The scene's excitation definition.
    record : AppliedRecord, optional
        The record as applied (:func:`apply_record`), for a record excitation.

    Raises
    ------
    InputError
        For a kind of excitation that has no characteristic amplitude and frequency.
    """
    if excitation is None:
        return None
    if excitation.kind == "sine":
        return Characteristic(abs(float(excitation.amplitude)), float(excitation.frequency),
                              "sine amplitude", "sine circular frequency")
    if excitation.kind in ("record", "stochastic"):
        return Characteristic(record.pga, 2.0 * math.pi / record.period,
                              "peak ground acceleration (PGA)",
                              f"2 pi / T, T = {record.period:.6g} s the record's {record.period_is}")
    if hasattr(excitation, "characteristic_acceleration"):  # a pulse: a_p and 2 pi / T_p
        return Characteristic(float(excitation.characteristic_acceleration),
                              float(excitation.characteristic_frequency),
                              f"{excitation.kind} pulse amplitude a_p",
                              f"{excitation.kind} pulse circular frequency 2 pi / T_p")
    raise InputError(f"a {excitation.kind} excitation has no characteristic amplitude and "
                     "frequency (a_p, w_p) in pframe")
