"""Stability and resolution checks made before a run.

The highest frequency of the scene with its contacts closed bounds the explicit step
(central difference: dt < 2 / w_max); the shortest contact period tells whether an implicit
step resolves an impact (pframe warns below about 20 steps per contact period).
"""

from __future__ import annotations

import math

import numpy as np

from pframe.assemble.modes import spring_matrix
from pframe.errors import InputError

#: steps per contact period below which an implicit run is warned about
STEPS_PER_CONTACT = 20


def reference_velocity(ground_acceleration: np.ndarray, dt: float, initial_velocity) -> float:
    """A generous closing velocity for sizing power-law contacts: ten times the peak ground
    velocity (structures amplify it) or the largest initial velocity difference."""
    ground_velocity = np.cumsum(ground_acceleration) * dt
    peak = 10.0 * float(np.max(np.abs(ground_velocity))) if ground_velocity.size else 0.0
    spread = float(np.ptp(initial_velocity)) if np.size(initial_velocity) else 0.0
    return max(peak, spread, 1e-12)


def contact_stiffness(law, params: np.ndarray, effective_mass: float, velocity: float) -> float:
    """Linear stiffness equivalent to a contact law: k itself for a linear spring; for
    F = k delta^n the tangent n k delta^(n-1) at the penetration an impact at ``velocity``
    reaches (energy: m v^2 / 2 = k delta^(n+1) / (n + 1))."""
    exponent = float(law.exponent)  # the law says (Law.exponent); 1 for a linear spring
    if "exponent" in law.param_names:
        exponent = float(params[law.param_names.index("exponent")])
    k = float(params[0])
    if exponent == 1.0:
        return k
    depth = (0.5 * (exponent + 1.0) * effective_mass * velocity**2 / k) ** (1.0 / (exponent + 1.0))
    return exponent * k * depth ** (exponent - 1.0)


def wall_effective_mass(mass: np.ndarray, left: int, right: int) -> float:
    """m_l m_r / (m_l + m_r) of a contact's two DOFs; the floor's mass where one side is a
    wall (-1, the ground)."""
    if left < 0 or right < 0:
        return float(mass[max(left, right)])
    return float(mass[left] * mass[right] / (mass[left] + mass[right]))


def _springs(plan, member: int, velocity: float) -> tuple[list, np.ndarray]:
    """(i, j, k) of every storey and closed contact (i = -1: the ground), and each contact's
    period (s)."""
    springs = [(int(lo), int(up), float(plan.story_k0[member, s]))
               for s, (lo, up) in enumerate(plan.story_dofs)]
    periods = np.full(len(plan.contact_names), np.inf)
    mass = plan.mass[member]
    for group in plan.contact_groups:
        for j, c in enumerate(group.index):
            left, right = plan.contact_dofs[c]
            m_eff = wall_effective_mass(mass, left, right)
            k = contact_stiffness(group.law, group.params[member, j], m_eff, velocity)
            springs.append((int(left), int(right), k))
            # a stiffness that vanishes (an impact too slow to compress a power law) has no
            # finite period: it limits nothing
            periods[c] = 2.0 * math.pi * math.sqrt(float(m_eff) / k) if k > 0.0 else math.inf
    return springs, periods


#: above this many degrees of freedom w_max is bounded (Gershgorin), not computed
DENSE_LIMIT = 2000


def highest_frequency(plan, member: int = 0) -> tuple[float, np.ndarray]:
    """w_max (rad/s) of the scene with every contact closed, and each contact's period (s).

    Up to :data:`DENSE_LIMIT` degrees of freedom the eigenvalue is computed; above, the
    Gershgorin bound of M^-1/2 K M^-1/2 is taken from the springs themselves (no n x n
    matrix), which is safe (never below w_max) and cheap for any number of floors."""
    velocity = reference_velocity(plan.ground_acceleration[member], float(plan.dt[member]),
                                  plan.initial_velocity[member])
    with np.errstate(all="ignore"):  # masses or stiffnesses beyond arithmetic: see _parts
        springs, periods = _springs(plan, member, velocity)
    mass = plan.mass[member]
    n = plan.n_dof
    if n <= DENSE_LIMIT:
        K = spring_matrix(springs, n)
        if plan.story_theta is not None:  # soil: a storey's stiffness is k g g^T with
            for e in np.flatnonzero(plan.story_theta >= 0):  # g = (1, -1, -h): add the lever
                lo, up = plan.story_dofs[e]
                g, two = np.zeros(n), np.zeros(n)
                g[up] = two[up] = 1.0
                if lo >= 0:
                    g[lo] = two[lo] = -1.0
                g[plan.story_theta[e]] = -plan.story_height[member, e]
                K += plan.story_k0[member, e] * (np.outer(g, g) - np.outer(two, two))
        scale = 1.0 / np.sqrt(mass)
        top = float(np.linalg.eigvalsh(K * np.outer(scale, scale))[-1])
    else:
        if plan.story_theta is not None and np.any(plan.story_theta >= 0):
            raise InputError(f"a scene on soil of more than {DENSE_LIMIT} DOFs: its highest "
                             "frequency is not bounded here; use an implicit integrator")
        rows = np.zeros(n)
        if springs:
            i, j, k = (np.array(x) for x in zip(*springs))
            np.add.at(rows, j, k / mass[j])
            grounded = i >= 0
            i, j, k = i[grounded], j[grounded], k[grounded]
            off = k / np.sqrt(mass[i] * mass[j])
            np.add.at(rows, i, k / mass[i] + off)
            np.add.at(rows, j, off)
        top = float(np.max(rows))
    return math.sqrt(max(top, 0.0)), periods


#: sub-steps of one step beyond which the step is refused as far too large for the scene
MAX_PARTS = 10**6


def _parts(ratio: float, what: str, dt: float, needed: float) -> int:
    if not ratio <= MAX_PARTS:  # also NaN
        raise InputError(f"dt = {dt:.4g} s would need {ratio:.3g} {what} (a step of about "
                         f"{needed:.3g} s); the contact or storey stiffness and the masses are "
                         "far apart: check their units")
    return math.ceil(ratio)


def check(plan, integrator_params) -> tuple[np.ndarray, np.ndarray, tuple[str, ...]]:
    """Sub-step counts for central difference and for event-aware contact phases, and
    warnings; raises :class:`InputError` for an explicit step above its limit."""
    batch = plan.batch
    cd_parts = np.ones(batch, dtype=np.int64)
    event_parts = np.ones(batch, dtype=np.int64)
    warnings: list[str] = []
    explicit = plan.integrator.explicit
    if not explicit and not plan.contact_names:
        return cd_parts, event_parts, ()
    worst = None  # (steps per contact period, member, dt, period) of the worst member
    split = None  # (sub-steps, member, dt, limit, w_max) of the most split member
    for b in range(batch):
        dt = float(plan.dt[b])
        w_max, periods = highest_frequency(plan, b)
        if explicit and w_max > 0:
            limit = 2.0 * integrator_params.safety / w_max
            if dt > limit:
                if integrator_params.substeps != "auto":
                    raise InputError(
                        f"dt = {dt:.4g} s is above the central-difference stability limit "
                        f"{integrator_params.safety:g} x 2 / w_max = {limit:.4g} s (w_max = "
                        f"{w_max:.4g} rad/s with the contacts closed); use dt <= {limit:.4g} s "
                        "or 'substeps: auto' on the integrator, or an implicit integrator")
                cd_parts[b] = _parts(dt / limit, "central-difference sub-steps", dt, limit)
                if split is None or cd_parts[b] > split[0]:
                    split = (int(cd_parts[b]), b, dt, limit, w_max)
        if np.isfinite(periods).any():
            shortest = float(np.min(periods))
            steps = shortest / dt
            event_parts[b] = max(1, _parts(STEPS_PER_CONTACT / steps, "sub-steps per contact "
                                           "phase", dt, shortest / STEPS_PER_CONTACT))
            if worst is None or steps < worst[0]:
                worst = (steps, b, dt, shortest)
    if worst is not None and not explicit and not plan.integrator.events \
            and worst[0] < STEPS_PER_CONTACT:
        # the worst member of a batch (a sweep over stiffness has its stiffest variant there)
        steps, b, dt, shortest = worst
        member = f" (in member {b} of this batch of {batch})" if batch > 1 else ""
        warnings.append(
            f"dt = {dt:.4g} s resolves the shortest contact period ({shortest:.4g} s) "
            f"with {steps:.1f} steps, fewer than {STEPS_PER_CONTACT}{member}: impacts may be "
            f"inaccurate; use dt <= {shortest / STEPS_PER_CONTACT:.4g} s or "
            "'events: true' on the integrator")
    if split is not None:
        warnings.append(_split_text(split, batch, bool(plan.contact_names)))
    return cd_parts, event_parts, tuple(warnings)


def _split_text(split, batch: int, contacts: bool) -> str:
    """Why and how often central difference with ``substeps: auto`` splits a step."""
    parts, b, dt, limit, w_max = split
    member = f" (member {b} of this batch of {batch}, the most split)" if batch > 1 else ""
    closed = " with the contacts closed" if contacts else ""
    return (f"central difference takes {parts} sub-steps of {dt / parts:.4g} s per step of "
            f"dt = {dt:.4g} s{member}: dt is above its stability limit {limit:.4g} s (safety "
            f"x 2 / w_max, w_max = {w_max:.4g} rad/s{closed}, a period of "
            f"{2.0 * math.pi / w_max:.4g} s); the ground motion is interpolated within a step "
            f"and histories are recorded at the steps only; to integrate at the step itself use "
            f"dt <= {limit:.4g} s")
