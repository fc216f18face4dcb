"""dt against every time scale of a scene, and scenes no building has (docs/accuracy.md).

A step resolves a vibration of period T with ``N = T / h`` steps. Every integrator pframe has
is second order: its numerical period is longer (or, for central difference, shorter) by a
relative error of order ``(w h)^2`` -- Newmark's average acceleration lengthens it by
``(w h)^2 / 12 = pi^2 / (3 N^2)``, 0.8 % at ``N = 20`` and 3.3 % at ``N = 10``
(:func:`period_error` computes it exactly for any of them). pframe warns below
:data:`STEPS_PER_PERIOD` steps per period of

- the modes that carry the response of each building: its lowest modes whose effective
  modal masses add up to :data:`MASS_SHARE` of its mass (fixed base, initial -- elastic --
  stiffness, so a yielding storey is judged on its elastic period);
- a sine's period and a pulse's period T_p;

and below 2 steps per period (the step's Nyquist limit: the vibration or the motion cannot be
represented, an alias is computed instead) the warning says that the result is not valid. A
record analysed with a step longer than its own skips samples (its peaks between them) and
aliases its content above the step's Nyquist frequency: the warning says by how much.

A first period outside :data:`PLAUSIBLE_PERIODS` is no building's: buildings have about
``T = 0.1 N`` s for N storeys, and a mass in tonnes or a stiffness in kN/m (a factor 1000)
moves the period by ``sqrt(1000) = 31.6``.
"""

from __future__ import annotations

import math

import numpy as np

from pframe.assemble.modes import (
    band_width,
    building_spring_arrays,
    one_blas_thread,
    scaled_band,
    scaled_triplets,
    sparse_lowest,
    spring_list,
    spring_matrix,
)
from pframe.model.rows import column

#: steps per period below which dt is warned about (Newmark's period error 0.8 % there)
STEPS_PER_PERIOD = 20
#: the modes judged are the lowest ones whose effective modal masses reach this share of the
#: building's mass (the 90 % that seismic codes ask a modal analysis to include)
MASS_SHARE = 0.90
#: below this many steps per period the step cannot represent the vibration (Nyquist)
NYQUIST_STEPS = 2.0
#: a record with more than this share of its energy above the step's Nyquist frequency is
#: aliased beyond use
ALIASED_SHARE = 0.10
#: first periods (s) that buildings have: 0.1 s per storey gives 0.1 s (one storey) to 10 s
#: (100 storeys); the bounds leave a factor 3 below (stiff one-storey frames, shaking-table
#: models) and none above (the tallest buildings have T_1 of 6 to 10 s)
PLAUSIBLE_PERIODS = (0.03, 10.0)
#: modes computed at most for a building of more floors than the dense limit, so many at a
#: time (a chain of storeys), or at once (other layouts)
LOWEST_MODES = 64
MODES_AT_A_TIME = 8
SPARSE_MODES = 16
#: buildings of up to this many floors get all their modes (a dense eigenproblem)
DENSE_FLOORS = 256


def period_error(coefficients, steps: float) -> float:
    """The relative period error ``T_numerical / T - 1`` of an undamped vibration integrated
    with ``steps`` steps per period, from the integrator's amplification matrix
    (:meth:`pframe.integrators.Coefficients.amplification`); ``inf``
    when the step cannot carry the vibration (no oscillating eigenvalue, or fewer than two
    steps per period)."""
    if not steps > NYQUIST_STEPS:
        return math.inf
    w = 2.0 * math.pi / steps  # w h
    values = np.linalg.eigvals(coefficients.amplification(w))
    angles = np.abs(np.angle(values[np.abs(values.imag) > 1e-12]))
    if angles.size == 0 or np.max(np.abs(values)) > 1.0 + 1e-9:
        return math.inf
    return w / float(np.max(angles)) - 1.0




def building_modes(ex, b: int, k0: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Circular frequencies (rad/s, ascending) and effective modal mass shares of building
    ``b`` on a fixed base with its storeys' initial stiffnesses ``k0`` (one per storey of the
    scene): all its modes up to :data:`DENSE_FLOORS` floors, else the lowest ones, a few at a
    time, until they carry :data:`MASS_SHARE` (at most :data:`LOWEST_MODES`; memory stays
    linear in the floors). The share of mode n is ``(phi_n^T M 1)^2 / sum(m)`` for ``phi_n``
    normalised on the mass: the shares of all modes add up to 1."""
    if ex.dofs is not None:  # in plan: the lateral-torsional modes
        from pframe.assemble.modes import modes_and_shares

        return modes_and_shares(ex, b, k0)
    nodes, ends, stiffness = building_spring_arrays(ex, b, k0)
    springs = spring_list(ends, stiffness) if len(nodes) <= DENSE_FLOORS or band_width(
        ends) > 1 else None
    mass = ex.masses[nodes]
    n = len(nodes)
    root = np.sqrt(mass)
    scale = 1.0 / root
    total = float(np.sum(mass))
    if n <= DENSE_FLOORS:
        values, vectors = np.linalg.eigh(spring_matrix(springs, n) * np.outer(scale, scale))
        return np.sqrt(np.clip(values, 0.0, None)), (vectors.T @ root) ** 2 / total
    if springs is not None:  # not a chain of storeys: a sparse shift-invert solve of the lowest modes
        from scipy.sparse import coo_matrix

        matrix = coo_matrix(scaled_triplets(springs, scale), shape=(n, n)).tocsc()
        values, vectors = sparse_lowest(matrix, SPARSE_MODES)
        return np.sqrt(np.clip(values, 0.0, None)), (vectors.T @ root) ** 2 / total
    from scipy.linalg import eigh_tridiagonal

    band = scaled_band(ends, stiffness, scale, 1)
    diagonal, off = band[0], band[1][:max(n - 1, 0)]
    omegas, shares = [], []
    for first in range(0, min(LOWEST_MODES, n), MODES_AT_A_TIME):
        last = min(first + MODES_AT_A_TIME, LOWEST_MODES, n) - 1
        with one_blas_thread():
            values, vectors = eigh_tridiagonal(diagonal, off, select="i",
                                               select_range=(first, last))
        omegas.append(np.sqrt(np.clip(values, 0.0, None)))
        shares.append((vectors.T @ root) ** 2 / total)
        if float(np.sum(np.concatenate(shares))) >= MASS_SHARE:
            break
    return np.concatenate(omegas), np.concatenate(shares)


def carrying_modes(omega: np.ndarray, shares: np.ndarray) -> int:
    """How many of the lowest modes carry :data:`MASS_SHARE` of the mass (all computed modes
    when they do not)."""
    reached = np.flatnonzero(np.cumsum(shares) >= MASS_SHARE - 1e-9)
    return int(reached[0]) + 1 if reached.size else len(omega)


class _Findings:
    """The worst member of a batch for each kind of warning."""

    def __init__(self, batch: int):
        self.batch = batch
        self.worst: dict = {}

    def add(self, key, badness: float, member: int, text: str) -> None:
        if key not in self.worst or badness > self.worst[key][0]:
            self.worst[key] = (badness, member, text)

    def texts(self) -> tuple[str, ...]:
        out = []
        for _, member, text in self.worst.values():
            if self.batch > 1:
                text += f" (member {member} of this batch of {self.batch}, the worst)"
            out.append(text)
        return tuple(out)


def _resolution(steps: float, coefficients) -> str:
    """What ``steps`` per period do to a vibration: the period error, or not valid."""
    if steps < NYQUIST_STEPS:
        return "fewer than 2 steps per period cannot represent it: the result is not valid"
    error = period_error(coefficients, steps)
    reference = period_error(coefficients, STEPS_PER_PERIOD)
    if not math.isfinite(error):
        return "the integrator cannot carry it at this step: the result is not valid"
    sense = "longer" if error > 0 else "shorter"
    return (f"the integrator makes its period {abs(error):.1%} {sense} "
            f"({abs(reference):.1%} at {STEPS_PER_PERIOD} steps)")


def _buildings(plan, ex, member: int, h: float, coefficients, findings, plausible: bool,
               modes: dict):
    k0 = plan.story_k0[member]
    for b, name in enumerate(ex.buildings):
        # members of a batch that share a building's masses and stiffnesses (a risk study's
        # records, a sweep over the excitation) share its modes: ``modes`` keeps them
        key = (b, ex.masses.tobytes(), k0.tobytes())
        if key not in modes:
            try:
                with np.errstate(all="ignore"):
                    modes[key] = building_modes(ex, b, k0)
            except (np.linalg.LinAlgError, ArithmeticError, ValueError):
                modes[key] = None
        if modes[key] is None:
            continue
        omega, shares = modes[key]
        if not (np.all(np.isfinite(omega)) and np.all(np.isfinite(shares))):
            continue
        count = carrying_modes(omega, shares)
        vibrating = omega > 1e-9 * max(float(np.max(omega)), 1e-300)
        if not vibrating[:count].any():
            continue  # free masses: no vibration of their own
        mode = count  # the highest (shortest) of the carrying modes
        shortest = 2.0 * math.pi / float(omega[count - 1])
        steps = shortest / h
        laws = column(ex.stories, "law")
        yielding = any(not laws[s].linear for s in np.flatnonzero(ex.story_building == b))
        elastic = " (elastic: its storeys' initial stiffness)" if yielding else ""
        if steps < STEPS_PER_PERIOD:
            carried = (f"mode {mode}, the shortest of the modes 1-{mode} that carry "
                       f"{float(np.sum(shares[:mode])):.0%} of its mass" if mode > 1
                       else f"mode 1, which carries {float(shares[0]):.0%} of its mass")
            step = f"dt = {h:.4g} s" if h == plan.dt[member] else \
                f"the central-difference sub-step h = {h:.4g} s"
            findings.add(("building", name), -steps, member,
                         f"{step} resolves the period {shortest:.4g} s{elastic} of "
                         f"building {name} ({carried}) with {steps:.2f} steps, fewer than "
                         f"{STEPS_PER_PERIOD}: {_resolution(steps, coefficients)}; use dt <= "
                         f"{shortest / STEPS_PER_PERIOD:.4g} s")
        if plausible is not None:
            first = 2.0 * math.pi / float(omega[vibrating][0])
            _plausibility(ex, b, name, first, elastic, k0, member, findings, plausible)


def _plausibility(ex, b, name, first, elastic, k0, member, findings, unit_hint: bool):
    low, high = PLAUSIBLE_PERIODS
    if low <= first <= high:
        return
    factor = math.sqrt(1000.0)
    nodes = np.flatnonzero(ex.node_building == b)
    stiff = k0[np.flatnonzero(ex.story_building == b)]
    which = "shorter" if first < low else "longer"
    text = (f"building {name}: its first period {first:.3g} s{elastic} is {which} than "
            f"buildings have ({low:g} s to {high:g} s, about 0.1 s per storey)")
    if unit_hint:
        masses = f"{np.min(ex.masses[nodes]):.3g}" + (
            f" to {np.max(ex.masses[nodes]):.3g}" if np.ptp(ex.masses[nodes]) else "")
        springs = (f"{np.min(stiff):.3g}" + (f" to {np.max(stiff):.3g}" if np.ptp(stiff) else "")
                   if stiff.size else "none")
        if first < low:
            hint = (f"if the masses are in tonnes, not kg, or the stiffnesses 1000 times too "
                    f"large, the first period is {first * factor:.3g} s")
        else:
            hint = (f"if the stiffnesses are in kN/m (or N/mm), not N/m, or the masses 1000 "
                    f"times too large, the first period is {first / factor:.3g} s")
        text += (f"; its floor masses are {masses} kg and storey stiffnesses {springs} N/m: "
                 f"{hint}; check the units (kg, N/m)")
    else:
        text += ("; this Pi-form scene sets a physical time scale (scales.w_p): check Pi_k "
                 "and w_p")
    findings.add(("plausible", name), abs(math.log(first / math.sqrt(low * high))), member,
                 text)


def _excitation(plan, ex, member: int, dt: float, coefficients, findings):
    from pframe.model.scene import plain_motions

    for motion in ex.motions or plain_motions(ex.excitation):
        _motion(motion, member, dt, coefficients, findings)


def _motion(excitation, member: int, dt: float, coefficients, findings):
    if excitation is None or excitation.kind in ("record", "stochastic"):  # _record's
        return
    if excitation.kind == "sine":
        period = 2.0 * math.pi / float(excitation.frequency)
        what = (f"the sine's period {period:.4g} s (w = {float(excitation.frequency):.4g} rad/s, "
                f"f = {1.0 / period:.4g} Hz)")
    else:
        period = float(excitation.period)
        kind = "Ricker wavelet" if excitation.kind == "ricker" else \
            f"cycloidal pulse (type {excitation.type})"
        what = f"the {kind}'s period T_p = {period:.4g} s"
    steps = period / dt
    if steps >= STEPS_PER_PERIOD:
        return
    if steps < NYQUIST_STEPS:
        frequency, rate = 1.0 / period, 1.0 / dt
        alias = abs(frequency - round(frequency / rate) * rate)
        consequence = (f"its frequency {frequency:.4g} Hz is above the step's Nyquist frequency "
                       f"{0.5 * rate:.4g} Hz, so the run sees an alias of {alias:.4g} Hz: the "
                       "result is not valid")
    else:
        consequence = (f"the motion is sampled coarsely and {_resolution(steps, coefficients)} "
                       "in the response to it")
    findings.add(("excitation",), -steps, member,
                 f"dt = {dt:.4g} s resolves {what} with {steps:.2f} steps, fewer than "
                 f"{STEPS_PER_PERIOD}: {consequence}; use dt <= {period / STEPS_PER_PERIOD:.4g} s")


def aliased_share(times: np.ndarray, acceleration: np.ndarray, dt: float) -> float:
    """The share of a record's energy (squared Fourier amplitude) above the Nyquist frequency
    ``1 / (2 dt)`` of a step ``dt``; the samples are taken as equally spaced (PEER records
    are)."""
    if len(times) < 4:
        return 0.0
    step = float(times[-1] - times[0]) / (len(times) - 1)
    power = np.abs(np.fft.rfft(acceleration)) ** 2
    total = float(np.sum(power))
    if total == 0.0:
        return 0.0
    frequencies = np.fft.rfftfreq(len(acceleration), step)
    return float(np.sum(power[frequencies > 0.5 / dt])) / total


def _record(plan, ex, member: int, dt: float, findings):
    if ex.component_records:
        motions = dict(ex.excitation.motions())
        for axis, record in ex.component_records:
            _one_record(plan, record, motions[axis].scale, member, dt, findings)
        return
    if ex.record is not None:
        _one_record(plan, ex.record, ex.excitation.scale, member, dt, findings)


def _one_record(plan, record, scale: float, member: int, dt: float, findings):
    if len(record.times) < 2:
        return
    step = float(record.times[-1] - record.times[0]) / (len(record.times) - 1)
    if not dt > step * (1.0 + 1e-6):
        return
    ratio = dt / step
    share = aliased_share(record.times, record.acceleration, dt)
    sampled = float(np.max(np.abs(plan.ground_channels[member]))) if plan.steps else 0.0
    full = float(np.max(np.abs(record.acceleration))) * abs(float(scale))
    verdict = "the result is not valid" if share > ALIASED_SHARE else "results may be inaccurate"
    times = f"{ratio:.0f}" if abs(ratio - round(ratio)) < 1e-6 else f"{ratio:.3g}"
    findings.add(("record",), ratio, member,
                 f"dt = {dt:.4g} s is {times} times the record's own step {step:.4g} s: the "
                 f"run reads the record between its samples and misses its peaks (its PGA "
                 f"as sampled is {sampled:.4g} m/s^2 of {full:.4g}), and {share:.1%} of its "
                 f"energy lies above the step's Nyquist frequency {0.5 / dt:.4g} Hz and is "
                 f"aliased: {verdict}; use dt <= {step:.4g} s (the record's step or a "
                 "fraction of it)")


def check(plan, variants, motions_only: bool = False) -> tuple[str, ...]:
    """Warnings of a plan whose step is coarse for one of its time scales, or whose buildings
    no building has (``variants``: the expanded scenes of its batch members). With
    ``motions_only`` (members that differ in their ground motion alone: the same buildings,
    stiffnesses and step), the first member's buildings stand for every member's: each
    member would find the same, and the first of equal findings is the one kept."""
    findings = _Findings(plan.batch)
    coefficients = plan.integrator
    modes: dict = {}
    for member, ex in enumerate(variants):
        dt = float(plan.dt[member])
        parts = int(plan.cd_parts[member]) if plan.cd_parts is not None else 1
        h = dt / parts if coefficients.explicit else dt
        unit = set(ex.unit_scales)
        plausible = None if "w_p" in unit else ("m_b" not in unit)
        if member == 0 or not motions_only:
            _buildings(plan, ex, member, h, coefficients, findings, plausible, modes)
        _excitation(plan, ex, member, dt, coefficients, findings)
        _record(plan, ex, member, dt, findings)
    return findings.texts()
