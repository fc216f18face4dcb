"""Every built-in contact law x calibration x integrator x ``events`` on a free two-body impact.

1000 kg at 0.5 m/s into 3000 kg at rest, no damping, no ground motion. Each member rebounds with
the restitution its law's packed numbers imply -- the closed form of the Hunt-Crossley family
(chi (1 + e) = ln((1 + chi) / (1 - chi e))) and of Kelvin (with tension
exp(-zeta pi / sqrt(1 - zeta^2)), clipped exp(-2 zeta arccos(zeta) / sqrt(1 - zeta^2))), an
independent ODE solution (scipy DOP853) for Jankowski, 1 for the undamped laws -- and closes its
energy balance; the undamped laws give the kinetic energy back.

Two placements of the impact: the bodies touching at t = 0 (gap 0, the contact at its onset
from the first step) and a gap closed 10.37 steps in (onset and separation both inside steps,
where event location works). dt = contact duration / STEPS_PER_CONTACT for each member.

Run ``python tests/test_contact_matrix.py`` to print the table docs/restitution.md summarises.
"""

from __future__ import annotations

import json
import math

import numpy as np
import pytest
from conftest import (  # tests/ is on sys.path under pytest and when run as a script
    IMPACT_VARIANTS,
    M_EFF,
    M_LEFT,
    M_RIGHT,
    UNDAMPED_VARIANTS,
    V_IMPACT,
    fact,
    hunt_crossley_restitution,
    impact_contact,
    impact_packed,
    integrator_class,
    integrator_configurations,
    node_history,
    reference_impact,
    run_batch,
    two_free_masses_text,
)

#: integrator configurations: every integrator of pframe.integrators' table in its reference
#: configuration (the first of its facts' examples), and with event location where it runs
#: on that path
INTEGRATORS = integrator_configurations()
#: (case, calibration) of every law; None: the law has no restitution
CASES = [("linear", None), ("hertz", None)] + [
    (case, calibration) for case in IMPACT_VARIANTS for calibration in ("published", "exact")]
TARGETS = (0.2, 0.5, 0.8)
#: steps per contact (from the ODE's contact duration)
STEPS_PER_CONTACT = 400
#: where the impact starts: touching at t = 0, or a gap closed this many steps in
GAP_STEPS = (0.0, 10.37)
#: steps of every member (one batch: the same count), past the separation
STEPS = int(1.25 * STEPS_PER_CONTACT) + 20

#: Tolerance on the restitution: each integrator's fact restitution_tolerance, whose reasons
#: follow. Measured worst errors at 400 steps per contact are in test_contact_matrix's table
#: (docs/restitution.md).
#: - Newmark and central difference are second order: errors ~ (pi / 400)^2 ~ 6e-5, apart from
#:   the O(dt) impulse error of a force that jumps at delta = 0 (Kelvin) *without* events, where
#:   the jump falls inside a step: measured up to 1.7e-3 (central difference, which has no
#:   event location), and Jankowski's 7.7e-4 (below).
#: - HHT (alpha = 0.1) and generalised-alpha (rho_inf = 0.6) damp the high modes by design; at
#:   w h = pi / 400 that costs little in e (measured <= 2.5e-6 on the undamped laws), and
#:   their worst errors are the same Kelvin jumps without events (1.1e-3).
#: - Wilson-theta (theta = 1.4) holds equilibrium at t + theta h, past the step end: a Kelvin
#:   jump without events acts over theta h of the step it falls in (measured 2.4e-3). With
#:   events every contact keeps its branch up to the located crossing (measured <= 2.6e-5 but
#:   Jankowski, 1.7e-3).
#: - Bathe (gamma = 2 - sqrt 2) is second order with both stages at their ends: its worst error
#:   is the Kelvin jump without events (measured 9.5e-4); with events <= 4e-6 but Jankowski,
#:   5.0e-4.
#: With events the force jumps of Kelvin fall on sub-step ends: every law but Jankowski within
#: this (measured <= 4e-5 at 400 steps per contact). Jankowski's damping ~ delta^(1/4) has an
#: infinite slope at delta = 0, whatever the stepping: about O(dt^1.25), measured 7.7e-4.
EVENTS_TOLERANCE = 1e-4
#: The energy balance |W_in - (dE_k + W_damping + W_storeys + W_contacts + D_alg)| / scale, per
#: run: each integrator's fact impact_balance_tolerance. The integrator's own dissipation is
#: counted (D_alg), so every integrator closes it to round-off, with events too (measured
#: <= 7.9e-12; HHT, generalised-alpha and Wilson-theta left 3e-6 to 8e-6 with events before
#: their modified kinetic energy was re-taken when the sub-step length changes).


def _expected(case: str, e, calibration) -> float:
    """The restitution the law's packed numbers imply: closed form where there is one (checked
    against the ODE), the ODE otherwise, 1 for the undamped laws."""
    ode = reference_impact(case, e, calibration)[0]
    if case in UNDAMPED_VARIANTS:
        assert ode == pytest.approx(1.0, abs=1e-9)
        return 1.0
    packed = impact_packed(case, e, calibration)
    law = IMPACT_VARIANTS[case][0]
    if law in ("improved_kelvin", "hertzdamp", "bumper"):
        # the restitution of m x'' = -P(x) (1 + chi x' / v0) is the same for any spring P
        closed = hunt_crossley_restitution(packed[2])
    elif law == "kelvin":
        k, c, tension = packed
        zeta = c / (2.0 * math.sqrt(k * M_EFF))
        root = math.sqrt(1.0 - zeta * zeta)
        closed = (math.exp(-zeta * math.pi / root) if tension
                  else math.exp(-2.0 * zeta * math.acos(zeta) / root))
    else:
        return ode
    assert ode == pytest.approx(closed, abs=1e-8), (case, e, calibration)
    return closed


def _members():
    """Members grouped by law (one batch a law: a batch shares its laws)."""
    groups: dict[str, list] = {}
    for case, calibration in CASES:
        targets = (None,) if calibration is None else TARGETS
        for e in targets:
            expected = _expected(case, e, calibration)
            duration = reference_impact(case, e, calibration)[1]
            dt = duration / STEPS_PER_CONTACT
            for gap_steps in GAP_STEPS:
                law = (UNDAMPED_VARIANTS.get(case) or IMPACT_VARIANTS[case])[0]
                groups.setdefault(law, []).append(
                    dict(case=case, calibration=calibration, e=e, expected=expected, dt=dt,
                         gap=V_IMPACT * gap_steps * dt))
    return groups


def run_matrix(name: str) -> list[dict]:
    """Every member under integrator configuration ``name``: one batch per law."""
    rows = []
    for members in _members().values():
        texts = []
        for member in members:
            text = two_free_masses_text(
                M_LEFT, M_RIGHT, impact_contact(member["case"], member["e"],
                                                member["calibration"]),
                V_IMPACT, 0.0, member["dt"], STEPS * member["dt"], gap=member["gap"])
            scene = json.loads(text)
            scene["analysis"]["integrator"] = INTEGRATORS[name]
            texts.append(json.dumps(scene))
        plan, result = run_batch(texts)
        for b, member in enumerate(members):
            v_left = node_history(plan, result, "velocity", "L/1", b)
            v_right = node_history(plan, result, "velocity", "R/1", b)
            kinetic = 0.5 * (M_LEFT * v_left[-1] ** 2 + M_RIGHT * v_right[-1] ** 2)
            rows.append(member | dict(
                integrator=name, completed=result.completed(b),
                why=result.describe_failure(b), impacts=int(result.impacts[b, 0]),
                rebound=-(v_left[-1] - v_right[-1]) / V_IMPACT,
                energy_error=result.energy_error(b),
                kinetic_ratio=kinetic / (0.5 * M_LEFT * V_IMPACT**2)))
    return rows


@pytest.mark.slow
@pytest.mark.parametrize("name", list(INTEGRATORS))
def test_every_law_rebounds_as_its_formula_implies(name):
    """Every law x calibration x target e x placement, under one integrator configuration:
    completed, one impact, the restitution its packed numbers imply within the integrator's
    TOLERANCE, the energy balance closed, and (undamped laws) the kinetic energy back within
    that tolerance (relative velocity recovered: 1 - e)."""
    cls = integrator_class(INTEGRATORS[name])
    worst = 0.0
    for row in run_matrix(name):
        label = (f"{row['case']} {row['calibration']} e = {row['e']} gap {row['gap']:.3g} m "
                 f"under {name}")
        assert row["completed"], f"{label}: {row['why']}"
        assert row["impacts"] == 1, label
        tolerance = fact(cls, "restitution_tolerance")
        if name.endswith("+events") and row["case"] != "jankowski":
            tolerance = EVENTS_TOLERANCE
        error = row["rebound"] - row["expected"]
        worst = max(worst, abs(error))
        assert abs(error) <= tolerance, f"{label}: rebound {row['rebound']:.6f}, " \
                                        f"expected {row['expected']:.6f}"
        assert row["energy_error"] <= fact(cls, "impact_balance_tolerance"), \
            f"{label}: energy balance error {row['energy_error']:.2e}"
        if row["calibration"] is None:
            assert row["kinetic_ratio"] == pytest.approx(1.0, abs=2 * tolerance), label
    print(f"{name}: worst |error in e| {worst:.2e}")


def test_every_law_and_integrator_is_in_the_matrix():
    """A new contact law fails here until the matrix covers it; every integrator is in it by
    its facts (tests/test_integrators.py checks that each declares them)."""
    from pframe.integrators import ALL_INTEGRATORS
    from pframe.laws import all_contact_laws

    laws = {(UNDAMPED_VARIANTS.get(c) or IMPACT_VARIANTS[c])[0] for c, _ in CASES}
    assert laws == {law.name for law in all_contact_laws()}
    assert {cfg["type"] for cfg in INTEGRATORS.values()} == {
        cls.type_name() for cls in ALL_INTEGRATORS}


def matrix_summary() -> str:
    """The worst error in e and in the energy balance, law by integrator configuration."""
    table: dict[tuple[str, str], tuple[float, float]] = {}
    for name in INTEGRATORS:
        for row in run_matrix(name):
            key = (f"{row['case']} ({row['calibration'] or 'e = 1'})", name)
            error = abs(row["rebound"] - row["expected"]) if row["completed"] else np.inf
            old = table.get(key, (0.0, 0.0))
            table[key] = (max(old[0], error), max(old[1], row["energy_error"]))
    names = list(INTEGRATORS)
    out = ["| law (calibration) | " + " | ".join(names) + " |",
           "|" + "---|" * (len(names) + 1)]
    for label in dict.fromkeys(k[0] for k in table):
        out.append(f"| {label} | " + " | ".join(f"{table[(label, n)][0]:.1e}" for n in names)
                   + " |")
    energy = max(v[1] for v in table.values())
    out.append("")
    out.append(f"Largest energy balance error of any member: {energy:.1e}.")
    return "\n".join(out)


if __name__ == "__main__":
    print(matrix_summary())


# ---------------------------------------------------------------------------------------------
# envelopes and impact counts see every sub-step
# ---------------------------------------------------------------------------------------------

#: a linear contact: the impact's peak force is v sqrt(k m_eff) (the half sine of the contact)
K_SUBSTEP = 1.0e7
#: a step longer than the whole contact (about 0.027 s): at every step end the bodies are apart
DT_COARSE = 0.05


def _coarse_impact(integrator: dict, dt: float):
    """Two free masses, linear contact, the gap closed at t = 0.01 s: (plan, result) with the
    contact force's envelope recorded."""
    text = two_free_masses_text(M_LEFT, M_RIGHT, {"law": "linear", "stiffness": K_SUBSTEP},
                                V_IMPACT, 0.0, dt, 4 * DT_COARSE, gap=0.01 * V_IMPACT)
    scene = json.loads(text)
    scene["analysis"]["integrator"] = integrator
    scene["recorders"] = [{"kind": "history", "quantities": ["velocity"]},
                          {"kind": "envelope", "quantities": ["contact_force",
                                                              "contact_penetration"]}]
    from conftest import run_text

    plan, result = run_text(json.dumps(scene))
    assert result.completed(0), result.describe_failure(0)
    return plan, result


def test_central_difference_substeps_reach_the_envelopes():
    """Central difference with ``substeps: auto`` (29 sub-steps of a 0.05 s step that holds
    the whole impact): the envelope's peak force and penetration, and the impact count, are
    those of the same scene run at the sub-step itself (no ground motion: the same arithmetic),
    and the peak force is the closed form v sqrt(k m_eff) to the sampling of a half sine in 16
    sub-steps. Before, the envelope saw only step ends, where the bodies are apart: 0 N."""
    plan, sub = _coarse_impact({"type": "central_difference", "substeps": "auto",
                                "safety": 0.1}, DT_COARSE)
    parts = int(plan.cd_parts[0])
    assert parts == 29
    _, direct = _coarse_impact({"type": "central_difference"}, DT_COARSE / parts)
    for quantity in ("contact_force", "contact_penetration"):
        assert sub.envelope[quantity][0, 0] == pytest.approx(direct.envelope[quantity][0, 0],
                                                            rel=1e-9)
    assert sub.impacts[0, 0] == direct.impacts[0, 0] == 1
    peak = V_IMPACT * math.sqrt(K_SUBSTEP * M_EFF)
    assert sub.envelope["contact_force"][0, 0] == pytest.approx(peak, rel=0.01)


@pytest.mark.parametrize("integrator", [{"type": "newmark", "events": True},
                                        {"type": "hht", "alpha": 0.1, "events": True}])
def test_event_substeps_reach_the_envelopes(integrator):
    """Event location with a step longer than the contact: the sub-steps while it is closed
    (event_parts of the step) update the envelope; the peak force is v sqrt(k m_eff) within the
    sampling of the half sine (1 %), and the rebound is 1. Before, 0 N."""
    plan, result = _coarse_impact(integrator, DT_COARSE)
    assert plan.event_parts[0] > 1
    assert result.impacts[0, 0] == 1
    peak = V_IMPACT * math.sqrt(K_SUBSTEP * M_EFF)
    assert result.envelope["contact_force"][0, 0] == pytest.approx(peak, rel=0.01)
    v_left = node_history(plan, result, "velocity", "L/1")
    v_right = node_history(plan, result, "velocity", "R/1")
    assert -(v_left[-1] - v_right[-1]) / V_IMPACT == pytest.approx(1.0, abs=0.01)
