"""Stability and resolution checks made before a run.

The highest frequency of the scene with its contacts closed bounds the explicit step
(central difference: dt < 2 / w_max); the shortest contact period tells whether an implicit
step resolves an impact (pframe warns below about 20 steps per contact period).
"""

from __future__ import annotations

import math

import numpy as np

from pframe.errors import InputError

#: steps per contact period below which an implicit run is warned about
STEPS_PER_CONTACT = 20


def reference_velocity(ground_acceleration: np.ndarray, dt: float, initial_velocity) -> float:
    """A generous closing velocity for sizing power-law contacts: ten times the peak ground
    velocity (structures amplify it; of the vector of a motion in two components) or the
    largest initial velocity difference."""
    ground = np.atleast_2d(ground_acceleration)
    ground_velocity = np.sqrt(np.sum((np.cumsum(ground, axis=-1) * dt) ** 2, axis=0))
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


def _springs(plan, member: int, velocity: float, matrix: bool = True):
    """The stiffness K (scipy.sparse; None without ``matrix``) of every storey, link and
    closed contact, and each contact's period (s): a contact's effective mass is
    1 / (1/m_left + 1/m_right) of the masses its sides present along it (a wall: the
    floor's)."""
    from pframe.assemble.incidence import incidence, side_mobility

    n = plan.n_dof
    mass = plan.mass[member]
    K = None
    if matrix:
        from scipy.sparse import diags

        stories = incidence(plan.story_dofs, plan.story_sides, member, n)
        K = stories.T @ diags(plan.story_k0[member]) @ stories
    periods = np.full(len(plan.contact_names), np.inf)
    stiffness = np.zeros(len(plan.contact_names))
    for group in plan.contact_groups:
        plain = _plain_mobility(plan, member, mass, group.index)
        if plain is not None:  # each distinct (numbers, mass) once: a tall pair's levels
            _distinct_contacts(group, member, 1.0 / plain, velocity, stiffness, periods)
            continue
        for j, c in enumerate(group.index):
            mobility = sum(side_mobility(plan.contact_dofs, plan.contact_sides, member, mass,
                                         int(c), s) for s in range(2))
            m_eff = 1.0 / mobility
            stiffness[c], periods[c] = _contact_period(group.law, group.params[member, j],
                                                       m_eff, velocity)
    if matrix and len(plan.contact_names):
        from scipy.sparse import diags

        contacts = incidence(plan.contact_dofs, plan.contact_sides, member, n, contact=True)
        K = K + contacts.T @ diags(stiffness) @ contacts
    return K, periods


def _contact_period(law, params, m_eff: float, velocity: float) -> tuple[float, float]:
    """A contact's linear stiffness (:func:`contact_stiffness`) and period (s) for the
    effective mass ``m_eff``."""
    k = contact_stiffness(law, params, m_eff, velocity)
    # a stiffness that vanishes (an impact too slow to compress a power law) has no finite
    # period: it limits nothing
    return k, 2.0 * math.pi * math.sqrt(float(m_eff) / k) if k > 0.0 else math.inf


def _plain_mobility(plan, member: int, mass: np.ndarray, index) -> np.ndarray | None:
    """(g,) 1/m_left + 1/m_right (1/kg; the ground's 0) of contacts ``index`` when each is
    plain (its two DOFs) and the sum is positive and finite (None otherwise: each is then
    taken on its own, as :func:`pframe.assemble.incidence.side_mobility` does)."""
    index = np.asarray(index, dtype=np.int64)
    sides = plan.contact_sides
    if len(sides.start) > 1 and np.any(sides.general()[index]):
        return None
    dofs = np.asarray(plan.contact_dofs, dtype=np.int64).reshape(-1, 2)[index]
    with np.errstate(all="ignore"):
        mobility = np.where(dofs >= 0, 1.0 / mass[np.maximum(dofs, 0)], 0.0)
    total = mobility[:, 0] + mobility[:, 1]
    if not np.all(np.isfinite(mobility)) or not np.all(total > 0.0):
        return None
    return total


def _distinct_contacts(group, member, m_eff, velocity, stiffness, periods) -> None:
    """:func:`_contact_period` of each contact of ``group`` (its effective masses
    ``m_eff``), computed once per distinct numbers and mass, into ``stiffness`` and
    ``periods``."""
    table = np.ascontiguousarray(np.column_stack([group.params[member], m_eff]))
    whole = np.dtype((np.void, table.dtype.itemsize * table.shape[1]))
    rows, inverse = np.unique(table.view(whole).ravel(), return_inverse=True)
    rows = rows.view(table.dtype).reshape(-1, table.shape[1])
    found = np.array([_contact_period(group.law, row[:-1], float(row[-1]), velocity)
                      for row in rows]).reshape(-1, 2)
    index = np.asarray(group.index, dtype=np.int64)
    stiffness[index] = found[inverse.ravel(), 0]
    periods[index] = found[inverse.ravel(), 1]


#: above this many degrees of freedom w_max is bounded (Gershgorin), not computed
DENSE_LIMIT = 2000


def highest_frequency(plan, member: int = 0, frequency: bool = True
                      ) -> tuple[float, np.ndarray]:
    """w_max (rad/s) of the scene with every contact closed, and each contact's period (s);
    without ``frequency`` (an implicit integrator, which w_max does not limit) the periods
    only, w_max NaN.

    Up to :data:`DENSE_LIMIT` degrees of freedom the eigenvalue is computed; above, the
    Gershgorin bound of M^-1/2 K M^-1/2 (its largest absolute row sum) is taken from the
    sparse stiffness, which is safe (never below w_max) and cheap for any number of floors."""
    velocity = reference_velocity(plan.ground_channels[member], float(plan.dt[member]),
                                  plan.initial_velocity[member])
    with np.errstate(all="ignore"):  # masses or stiffnesses beyond arithmetic: see _parts
        K, periods = _springs(plan, member, velocity, matrix=frequency)
        if not frequency:
            return math.nan, periods
        scale = 1.0 / np.sqrt(plan.mass[member])
        from scipy.sparse import diags

        scaled = diags(scale) @ K @ diags(scale)
        if plan.n_dof <= DENSE_LIMIT:
            top = float(np.linalg.eigvalsh(scaled.toarray())[-1])
        else:
            top = float(np.max(np.abs(scaled).sum(axis=1)))
    return math.sqrt(max(top, 0.0)), periods


def _member_numbers(plan, member: int) -> bytes:
    """Everything :func:`highest_frequency` reads of a member: its masses, storey stiffnesses,
    sides, contact parameters, and the closing velocity its ground motion gives when a
    contact law is a power law (a linear one's stiffness does not depend on it)."""
    parts = [plan.mass[member], plan.story_k0[member], plan.story_sides.coef[member],
             plan.contact_sides.coef[member]]
    power = False
    for group in plan.contact_groups:
        params = group.params[member]
        parts.append(params)
        names = group.law.param_names
        exponents = (params[:, names.index("exponent")] if "exponent" in names
                     else np.array([float(group.law.exponent)]))
        power = power or bool(np.any(exponents != 1.0))
    if power:
        parts.append(np.array([reference_velocity(plan.ground_channels[member],
                                                  float(plan.dt[member]),
                                                  plan.initial_velocity[member])]))
    return b"".join(np.ascontiguousarray(p, dtype=float).tobytes() for p in parts)


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
    found: dict = {}  # members of the same numbers (a batch of ground motions) share theirs
    for b in range(batch):
        dt = float(plan.dt[b])
        key = _member_numbers(plan, b)
        if key not in found:
            found[key] = highest_frequency(plan, b, frequency=explicit)
        w_max, periods = found[key]
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
