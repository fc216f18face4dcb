"""Floor-to-column contacts: a floor striking a neighbour's column between two of its floors.

The struck point's displacement is psi u_upper + (1 - psi) u_lower with the fixed-fixed
column's shape psi = 3 at^2 - 2 at^3, and the contact force is shared between the two floors
with the same weights. A hand-derived case: a mass striking the mid-height of a column joining
two free masses is an elastic impact of two bodies, the struck point's mass being
1 / (psi^2 / m_upper + (1 - psi)^2 / m_lower); the impulse goes to the two floors as psi and
1 - psi.
"""

from __future__ import annotations

import json
import math
import warnings

import numpy as np
import pytest
from conftest import REPO, record_file, run_text, runnable_model

from pframe.errors import InputError


def _scene(at: float, m_a=500.0, m1=1000.0, m2=2000.0, k_c=1e8, v0=0.5, capacity=None,
           law=None, duration=0.01):
    contact = {"name": "f2c", "nodes": ["A/1", "B/2"], "gap": 0.0, "column": "right",
               "at": at} | (law or {"law": "linear", "stiffness": k_c})
    if capacity is not None:
        contact["shear_capacity"] = capacity
    return json.dumps({
        "buildings": [{"name": "A", "floors": 1, "mass": m_a,
                       "story": {"material": "elastic", "stiffness": 1e-3}},
                      {"name": "B", "floors": 2, "mass": [m1, m2],
                       "story": {"material": "elastic", "stiffness": 1e-3}}],
        "contacts": [contact],
        "damping": {"ratio": 0.0},
        "initial_conditions": {"velocity": {"A/1": v0}},
        "analysis": {"dt": 2e-6, "duration": duration,
                     "integrator": {"type": "newmark", "events": True}},
        "recorders": [{"kind": "history", "quantities": ["velocity", "contact_force"]}],
    })


@pytest.mark.parametrize("at", [0.5, 0.25, 0.8])
def test_an_impact_on_a_column_is_a_two_body_impact(at):
    m_a, m1, m2, k_c, v0 = 500.0, 1000.0, 2000.0, 1e8, 0.5
    psi = at * at * (3.0 - 2.0 * at)
    plan, result = run_text(_scene(at))
    assert result.completed(0) and int(result.impacts[0, 0]) == 1
    v = result.history["velocity"][0][:, plan.node_dof]
    m_point = 1.0 / (psi**2 / m2 + (1.0 - psi) ** 2 / m1)
    m_eff = m_a * m_point / (m_a + m_point)
    impulse = 2.0 * m_eff * v0
    np.testing.assert_allclose(v[-1], [v0 * (m_a - m_point) / (m_a + m_point),
                                       (1.0 - psi) * impulse / m1, psi * impulse / m2],
                               rtol=1e-8, atol=1e-10)
    force = result.history["contact_force"][0, :, 0]
    duration = np.count_nonzero(force > 0) * 2e-6
    assert duration == pytest.approx(math.pi * math.sqrt(m_eff / k_c), abs=4e-6)
    assert result.energy_error(0) < 1e-12
    # the struck column's local shear: the larger segment, max(psi, 1 - psi) F
    np.testing.assert_allclose(result.column_shear(0),
                               [max(psi, 1 - psi) * np.max(force)], rtol=1e-12)


def test_the_calibrated_restitution_uses_the_struck_points_mass():
    """exact calibration for the effective mass of the floor and the column point: the
    relative velocity of the two points rebounds with e."""
    at, e = 0.5, 0.6
    psi = at * at * (3.0 - 2.0 * at)
    plan, result = run_text(_scene(at, law={"law": "hertzdamp", "stiffness": 1e9,
                                           "restitution": e, "calibration": "exact"},
                                   duration=0.05))
    force = result.history["contact_force"][0, :, 0]
    assert force[-1] == 0.0 and int(result.impacts[0, 0]) == 1  # separated
    v = result.history["velocity"][0][:, plan.node_dof]
    point = psi * v[:, 2] + (1 - psi) * v[:, 1]
    assert -(v[-1, 0] - point[-1]) / 0.5 == pytest.approx(e, abs=2e-4)


def test_the_capacity_check_warns_everywhere(tmp_path):
    import pframe

    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        ds = pframe.solve(pframe.load(json.loads(_scene(0.5, capacity=1e4))),
                          output=tmp_path / "run.nc")
    assert any("exceeds the column's shear capacity" in str(w.message) for w in caught)
    assert "exceeds the column's shear capacity" in ds.attrs["warnings"]
    _, quiet = run_text(_scene(0.5, capacity=1e9))
    assert quiet.column_shear(0)[0] < 1e9


def test_floor_to_column_errors_are_clear():
    from pframe.reader import parse_scene

    data = json.loads(_scene(0.5))
    del data["contacts"][0]["at"]
    with pytest.raises(InputError, match="needs both column"):
        _ = parse_scene(json.dumps(data)).expanded
    data = json.loads(_scene(0.5))
    data["contacts"][0]["column"] = "left"  # A/1 tops a storey, B/2 is the node: fine
    _ = parse_scene(json.dumps(data)).expanded
    data["contacts"][0]["nodes"] = ["ground", "B/2"]
    with pytest.raises(InputError, match="tops no storey"):
        _ = parse_scene(json.dumps(data)).expanded


def test_the_example(tmp_path):
    """models/floor-to-column.yaml: floors and columns pound, the balance closes, its columns
    hold (no warning: the example solves cleanly), and with columns half as strong those the
    impacts overload are named."""
    from pframe.assemble import assemble
    from pframe.kernel import simulate
    from pframe.reader import load_scene
    from pframe.verdict import of_result

    record_file("elCentro.AT2")
    loaded = load_scene(runnable_model(REPO / "models" / "floor-to-column.yaml", tmp_path))
    plan = assemble(loaded.expanded)
    result = simulate(plan)
    assert result.completed(0) and result.energy_error(0) < 1e-10
    assert int(result.impacts[0].sum()) >= 5
    shear = result.column_shear(0)
    assert np.all(shear[np.isfinite(shear)] < plan.contact_capacity[np.isfinite(shear)])
    assert not [w for w in of_result(result).warnings if "shear capacity" in w]
    # columns half as strong: those the impacts overload are named, and only those
    import dataclasses

    weaker = dataclasses.replace(result, plan=dataclasses.replace(
        plan, contact_capacity=plan.contact_capacity / 2))
    over = [w for w in of_result(weaker).warnings if "shear capacity" in w]
    assert len(over) == int(np.sum(shear > plan.contact_capacity / 2)) >= 1
