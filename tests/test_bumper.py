"""The bumper contact law: a mass hitting an elastomeric bumper, against an ODE solution.

Two free masses (1000 kg at 0.5 m/s into 3000 kg at rest, no damping, no ground motion)
meet through a bumper: the rubber's Hertz-damp stage, then, past the crush depth, the hard
contact added. The reference integrates m_eff delta'' = -F(delta, delta') with the force
written out here from the law's formula (scipy DOP853, rtol 1e-12): restitution, peak force,
contact duration. The restitution has a closed form for either stage (the Hunt-Crossley
relation of chi, whatever the spring), so ``calibration: exact`` rebounds with e whether the
bumper is crushed or not; crushing raises the peak force and shortens the contact.
"""

from __future__ import annotations

import json
import math

import numpy as np
import pytest
from conftest import (
    M_EFF,
    M_LEFT,
    M_RIGHT,
    V_IMPACT,
    element_history,
    hunt_crossley_restitution,
    node_history,
    run_text,
    two_free_masses_text,
)
from scipy.integrate import solve_ivp

from pframe.laws import ContactContext, get_law

BUMPER = get_law("contact", "bumper")
K_RUBBER, K_HARD = 1.0e8, 1.0e10  # N/m^1.5
#: the rubber alone would penetrate (5 m_eff v^2 / (4 k_r))^(2/5) = 5.6 mm at 0.5 m/s
RUBBER_ONLY = (5 * M_EFF * V_IMPACT**2 / (4 * K_RUBBER)) ** 0.4
STEPS_PER_CONTACT = 2000


def _contact(thickness, e, calibration="exact", **extra):
    return {"law": "bumper", "stiffness": K_RUBBER, "hard_stiffness": K_HARD,
            "thickness": thickness, "restitution": e, "calibration": calibration} | extra


def _reference(contact):
    """(restitution, peak force, contact duration) of the impact, from the ODE."""
    params = BUMPER.Params(**contact)
    chi = BUMPER.chi(params)
    depth = params.crush_ratio * params.thickness

    def force(x, r):
        x = max(x, 0.0)  # the dense output may dip below 0 at the ends
        spring = K_RUBBER * x**1.5 + K_HARD * max(x - depth, 0.0) ** 1.5
        return max(spring * (1.0 + chi * r / V_IMPACT), 0.0)

    def rhs(t, y):
        return [y[1], -force(y[0], y[1]) / M_EFF if y[0] > 0 else 0.0]

    def separated(t, y):
        return y[0]

    separated.terminal, separated.direction = True, -1
    sol = solve_ivp(rhs, (0.0, 1.0), [0.0, V_IMPACT], method="DOP853", rtol=1e-12,
                    atol=1e-16, events=separated, first_step=1e-9, dense_output=True)
    assert sol.status == 1
    duration = sol.t_events[0][0]
    t = np.linspace(0.0, duration, 20001)
    x, r = sol.sol(t)
    peak = max(force(a, b) for a, b in zip(x, r))
    return -sol.y_events[0][0][1] / V_IMPACT, peak, duration, float(x.max()), depth


def _run(contact, duration):
    dt = duration / STEPS_PER_CONTACT
    text = two_free_masses_text(M_LEFT, M_RIGHT, contact, V_IMPACT, 0.0, dt, 1.3 * duration)
    data = json.loads(text)
    data["recorders"][0]["quantities"].append("contact_penetration")
    plan, result = run_text(json.dumps(data))
    assert result.completed(), result.describe_failure()
    assert result.impacts[0, 0] == 1
    v_left = node_history(plan, result, "velocity", "L/1")
    v_right = node_history(plan, result, "velocity", "R/1")
    force = element_history(plan, result, "contact_force", "c")
    closed = np.flatnonzero(force > 0.0)
    return (-(v_left[-1] - v_right[-1]) / V_IMPACT, force.max(),
            (closed[-1] - closed[0] + 1) * dt, dt, result)


@pytest.mark.parametrize(("thickness", "crushed"), [(0.02, False), (0.004, True),
                                                    (0.0025, True)])
@pytest.mark.parametrize("e", [0.3, 0.7])
def test_mass_hitting_a_bumper_matches_the_ode(thickness, crushed, e):
    """Restitution, peak force and contact duration of the kernel's impact against the ODE's
    (400 steps a contact: within 2e-4 in e, 1e-3 in force and 2 steps in duration), and the
    exact calibration's e, crushed or not (the ODE's e equals it to 1e-9)."""
    contact = _contact(thickness, e)
    e_ode, peak_ode, duration_ode, x_max, depth = _reference(contact)
    assert (x_max > depth) == crushed
    assert e_ode == pytest.approx(e, abs=1e-9)
    e_run, peak_run, duration_run, dt, result = _run(contact, duration_ode)
    assert e_run == pytest.approx(e_ode, abs=2e-4)
    assert peak_run == pytest.approx(peak_ode, rel=1e-3)
    assert abs(duration_run - duration_ode) <= 2 * dt
    assert result.energy_error() <= 1e-9


@pytest.mark.slow
def test_crushing_the_bumper_raises_the_force_and_shortens_the_contact():
    """The same impact on thinner and thinner bumpers: once crushed (thickness below the
    rubber-only penetration / crush_ratio) the peak force grows and the contact shortens,
    toward the hard contact's; never crushed, it is the rubber's Hertz impact, whose peak
    force (5/4)^(3/5) ... closed form: F_max = k_r delta_m^1.5 at e = 1."""
    free = _reference(_contact(1.0, 1.0))
    delta_m = RUBBER_ONLY
    assert free[3] == pytest.approx(delta_m, rel=1e-9)
    assert free[1] == pytest.approx(K_RUBBER * delta_m**1.5, rel=1e-8)
    peaks, durations = [], []
    for thickness in (0.02, 0.006, 0.004, 0.002, 0.001):
        _, peak, duration, _, _ = _reference(_contact(thickness, 0.6))
        peaks.append(peak)
        durations.append(duration)
    assert peaks[0] == pytest.approx(peaks[1], rel=1e-12)  # neither is crushed
    assert np.all(np.diff(peaks[1:]) > 0) and np.all(np.diff(durations[1:]) < 0)


def test_published_calibration_rebounds_with_the_hunt_crossley_e_of_its_chi():
    """calibration: published packs Muthukumar's chi = 3 (1 - e^2) / 4; the impact rebounds
    with that chi's Hunt-Crossley restitution, crushed or not, and solve warns about it when it
    misses e by more than 0.02 (here 0.30 -> 0.68)."""
    contact = _contact(0.004, 0.3, calibration="published")
    chi = 0.75 * (1 - 0.3**2)
    packed = BUMPER.pack(BUMPER.Params(**contact), ContactContext(M_LEFT, M_RIGHT))
    assert packed[2] == chi
    e_ode = _reference(contact)[0]
    assert e_ode == pytest.approx(hunt_crossley_restitution(chi), abs=1e-9)
    assert BUMPER.rebound(BUMPER.Params(**contact)) == pytest.approx(e_ode, abs=1e-9)


def test_bumper_parameters_are_validated():
    """A thickness, a crush ratio in (0, 1], positive stiffnesses: one message per field."""
    from pframe.errors import InputError
    from pframe.reader import parse_scene

    for bad, field in (({"thickness": -0.01}, "thickness"), ({"crush_ratio": 1.5}, "crush_ratio"),
                       ({"hard_stiffness": 0.0}, "hard_stiffness")):
        text = two_free_masses_text(M_LEFT, M_RIGHT, _contact(0.01, 0.5) | bad, V_IMPACT, 0.0,
                                    1e-5, 0.01)
        with pytest.raises(InputError, match=field):
            parse_scene(text)
    missing = {k: v for k, v in _contact(0.01, 0.5).items() if k != "thickness"}
    with pytest.raises(InputError, match="thickness"):
        parse_scene(two_free_masses_text(M_LEFT, M_RIGHT, missing, V_IMPACT, 0.0, 1e-5, 0.01))


def test_hard_stage_is_c1_at_the_crush_depth():
    """The hard term starts with zero force and zero slope: force and tangent are continuous
    across delta_c (no event needed there); the tangent's jump over [delta_c - h, delta_c + h]
    is the hard term's 1.5 k_h sqrt(h) and vanishes with h."""
    params = BUMPER.Params(**_contact(0.004, 0.5))
    packed = np.array(BUMPER.pack(params, ContactContext(M_LEFT, M_RIGHT)))
    depth = packed[5]
    committed = np.array([V_IMPACT, 1.0])
    for h in (1e-8 * depth, 1e-12 * depth):
        below = BUMPER.force(packed, committed, np.zeros(2), depth - h, 0.1)
        above = BUMPER.force(packed, committed, np.zeros(2), depth + h, 0.1)
        factor = 1.0 + packed[2] * 0.1 / V_IMPACT
        assert above[0] - below[0] == pytest.approx(2 * h * below[1], rel=1e-2)
        assert above[1] - below[1] == pytest.approx(1.5 * K_HARD * math.sqrt(h) * factor,
                                                    rel=1e-2)


def test_bumper_pi_numbers_and_similitude():
    """pframe pi names a bumper by k_h (the rubber's), k_hard / k_h and delta_c beside e; a
    1:4 scale model (same acceleration and modulus) of a bumper impact rebounds with the same
    e and its force scales by S_F = S_L^2 (the peak penetration by S_L)."""
    from pframe.nondim import scale_scene, similitude

    packed = BUMPER.pack(BUMPER.Params(**_contact(0.004, 0.5)), ContactContext(M_LEFT, M_RIGHT))
    assert BUMPER.governing(packed) == {"k_h": ("hertz_stiffness", K_RUBBER),
                                        "hard_ratio": ("dimensionless", K_HARD / K_RUBBER),
                                        "delta_c": ("length", pytest.approx(0.0036))}
    duration = _reference(_contact(0.004, 0.5))[2]
    proto = json.loads(two_free_masses_text(M_LEFT, M_RIGHT, _contact(0.004, 0.5), V_IMPACT,
                                            0.0, duration / 1000, 1.3 * duration))
    model = scale_scene(proto, similitude({"length": "1/4", "acceleration": 1, "modulus": 1}))
    assert model["contacts"][0]["thickness"] == pytest.approx(0.001)
    peaks = []
    for data in (proto, model):
        plan, result = run_text(json.dumps(data))
        assert result.completed()
        peaks.append(element_history(plan, result, "contact_force", "c").max())
        v = [node_history(plan, result, "velocity", n)[-1] for n in ("L/1", "R/1")]
        v0 = data["initial_conditions"]["velocity"]["L/1"]
        assert -(v[0] - v[1]) / v0 == pytest.approx(0.5, abs=2e-4)
    assert peaks[1] / peaks[0] == pytest.approx(1 / 16, rel=1e-9)
