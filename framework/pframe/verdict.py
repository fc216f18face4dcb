"""The verdict on a run's own evidence of accuracy: is its energy balance what the integrator
promises?

Every run closes the balance

    W_input = dE_kinetic + W_damping + W_storeys + W_contacts + D_algorithmic

step by step (``kernel/c/energy.c``), with the integrator's own dissipation
D_algorithmic counted from its defining relations. Two numbers are judged, each relative to the
largest energy term of the run:

- the **balance error**: what the identity leaves over. Every implicit integrator closes it to
  round-off (at most 4e-12 on the shipped scenes at 1/2 to 4 times their step) and central
  difference to its velocity corrector's O(h^2) (at most 2e-6 at 4 times the paper's step).
  Above :data:`BALANCE_WARNING` the run did not solve the equations it claims to; above
  :data:`BALANCE_UNTRUSTED` it is not a result.
- **D_algorithmic**: zero for average acceleration; positive numerical damping for HHT,
  generalised alpha and Newmark with gamma > 1/2 (at most 0.7 % of the energy on the shipped
  scenes at 4 times their step). Evaluated at the alpha point, nonlinear laws (yield, contact
  onset) make it slightly negative (HHT and generalised alpha on the paper's scene: -0.07 % to
  -0.36 % at 1 to 4 times its step). More than :data:`DISSIPATION_WARNING` damped numerically
  changes the response; energy created beyond :data:`CREATION_WARNING` is a step that is too
  long for the nonlinearity or a law-integrator pair that does not conserve, and beyond
  :data:`CREATION_UNTRUSTED` the run is not a result (the Kelvin-with-tension event failure
  of issue 18 created 36 %).

``python benchmarks/energy_verdict.py`` measures these numbers on the shipped scenes.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

#: balance error above which a run is warned of
BALANCE_WARNING = 1e-4
#: balance error above which a run is not to be trusted
BALANCE_UNTRUSTED = 1e-2
#: numerical damping (fraction of the largest energy term) above which a run is warned of
DISSIPATION_WARNING = 0.05
#: energy created by the integrator above which a run is warned of
CREATION_WARNING = 1e-2
#: energy created by the integrator above which a run is not to be trusted
CREATION_UNTRUSTED = 5e-2

TRUSTED, IN_DOUBT, UNTRUSTED = "trusted", "in doubt", "not to be trusted"


class AccuracyWarning(UserWarning):
    """A run whose result may be wrong: its step, its energy balance or its inputs say so."""


# eq=False: verdicts are read, never compared or hashed; each generated function is compiled
# at every start
@dataclass(frozen=True, eq=False)
class Verdict:
    """What a run's energy evidence says: ``level`` is :data:`TRUSTED`, :data:`IN_DOUBT` or
    :data:`UNTRUSTED`; ``warnings`` say why and what to change."""

    balance_error: float
    algorithmic: float
    level: str
    warnings: tuple[str, ...]

    @property
    def trusted(self) -> bool:
        return self.level != UNTRUSTED


def judge(balance_error: float, algorithmic: float, completed: bool = True) -> Verdict:
    """The verdict on a run with this balance error and algorithmic dissipation (both
    relative to the largest energy term). A run that stopped early is judged on what it
    computed; its incompleteness is said elsewhere."""
    notes: list[str] = []
    level = TRUSTED

    def worse(new: str) -> None:
        nonlocal level
        if level == TRUSTED or new == UNTRUSTED:
            level = new

    if not (math.isfinite(balance_error) and math.isfinite(algorithmic)):
        worse(UNTRUSTED)
        notes.append("the energy balance is not a number: the run's arithmetic failed; the "
                     "result is not to be trusted")
        return Verdict(balance_error, algorithmic, level, tuple(notes))
    if balance_error > BALANCE_WARNING:
        bad = balance_error > BALANCE_UNTRUSTED
        worse(UNTRUSTED if bad else IN_DOUBT)
        notes.append(
            f"the energy balance does not close: error {balance_error:.2g} of the largest "
            f"energy term (integrators close it to about 1e-12; above {BALANCE_WARNING:g} "
            "the equations were not solved as stated)"
            + ("; the result is not to be trusted" if bad else "")
            + ": use a smaller dt, a tighter Newton tolerance, or another integrator")
    if algorithmic < -CREATION_WARNING:
        bad = -algorithmic > CREATION_UNTRUSTED
        worse(UNTRUSTED if bad else IN_DOUBT)
        notes.append(
            f"the integrator created energy: {-algorithmic:.2g} of the largest energy term "
            f"(more than {CREATION_WARNING:g})"
            + ("; the result is not to be trusted" if bad else "")
            + ": use a smaller dt, 'events: false', or average acceleration (newmark)")
    elif algorithmic > DISSIPATION_WARNING:
        worse(IN_DOUBT)
        notes.append(
            f"the integrator's numerical damping removed {algorithmic:.2g} of the largest "
            f"energy term (more than {DISSIPATION_WARNING:g}): the response is damped by the "
            "step, not by the structure; use a smaller dt or less numerical dissipation")
    return Verdict(balance_error, algorithmic, level, tuple(notes))


def of_result(result, member: int = 0) -> Verdict:
    """The verdict on member ``member`` of a kernel result (and, beside it, the struck columns
    whose local shear passed their capacity: a result, not a doubt on the arithmetic)."""
    verdict = judge(float(result.energy_error(member)),
                    float(result.algorithmic_dissipation(member)),
                    bool(result.completed(member)))
    plan = result.plan
    notes = small_rotations(result, member)
    if notes:
        worse = IN_DOUBT if verdict.level == TRUSTED else verdict.level
        verdict = Verdict(verdict.balance_error, verdict.algorithmic, worse,
                          verdict.warnings + tuple(notes))
    capacity = getattr(plan, "contact_capacity", None)
    if capacity is None or not np.any(np.isfinite(capacity)):
        return verdict
    shear = result.column_shear(member)
    notes = [f"contact {name}: the local shear it put into the struck column, {v:.4g} N, "
             f"exceeds the column's shear capacity {c:.4g} N (floor-to-column pounding)"
             for name, v, c in zip(plan.contact_names, shear, capacity)
             if np.isfinite(c) and np.isfinite(v) and v > c]
    return Verdict(verdict.balance_error, verdict.algorithmic, verdict.level,
                   verdict.warnings + tuple(notes)) if notes else verdict


#: the share of the smallest gap (or of the floor's own peak displacement) that the
#: small-rotation model's error at the edge of a floor may reach before a run is in doubt
ROTATION_ERROR = 0.01


def small_rotations(result, member: int = 0) -> list[str]:
    """The floors whose peak rotation theta is too large for the small-rotation model of a
    floor in plan: a point at r from the centre of mass moves by theta r where it moves by
    2 r sin(theta / 2) along a chord, off it by about r theta^2 / 2; past
    :data:`ROTATION_ERROR` of the smallest contact gap (or, without contacts, of the floor's
    peak motion at its edge: its centre's peak translation or r theta, the larger) at the edge
    of its plan (docs/plan.md)."""
    plan = result.plan
    if getattr(plan, "planar", True) or "displacement" not in result.envelope:
        return []
    peak = result.envelope["displacement"][member]
    extent = getattr(plan, "node_extent", None)
    gaps = plan.contact_gap[member] if len(plan.contact_names) else np.zeros(0)
    out = []
    for node, name in enumerate(plan.node_names):
        dofs = np.flatnonzero(plan.dof_node == node)
        turn = [d for d in dofs if plan.dof_component[d] == 2]
        if not turn or extent is None or not np.isfinite(extent[node]):
            continue
        theta = float(peak[turn[0]])
        error = extent[node] * theta * theta / 2.0
        moves = [d for d in dofs if plan.dof_component[d] < 2]
        # without contacts: the floor's largest motion at its edge, at least its centre's
        # peak and the twist's r theta (a floor that only twists is off by theta / 2 of it)
        scale = float(np.min(gaps[gaps > 0])) if np.any(gaps > 0) else max(
            float(np.max(peak[moves])) if moves else 0.0, extent[node] * theta)
        if scale > 0.0 and error > ROTATION_ERROR * scale:
            which = ("the smallest contact gap" if np.any(gaps > 0)
                     else "its peak motion at its edge")
            out.append(f"floor {name} turns by up to {theta:.3g} rad: the small-rotation model "
                       f"of a floor in plan moves its edge {error:.3g} m off its true path "
                       f"(r theta^2 / 2 over its plan's extent {extent[node]:.3g} m), "
                       f"{error / scale:.1%} of {which}; the result is in doubt")
    return out
