"""Walls: contacts whose other side is the ground (a moat or retaining wall, a stop).

A floor of mass m hitting a wall is the two-body impact of the contact matrix with an
effective mass m: with m = M_EFF of the matrix's pair and the same law numbers, every law and
calibration rebounds as its formula implies (tests/test_contact_matrix.py), whichever side the
wall stands on, and a wall never pulls.
"""

from __future__ import annotations

import json

import numpy as np
import pytest
from conftest import (
    CONTEXT,
    IMPACT_VARIANTS,
    M_EFF,
    V_IMPACT,
    impact_contact,
    reference_impact,
    run_batch,
    run_text,
    scene_text,
)
from test_contact_matrix import _expected

from pframe.errors import InputError
from pframe.laws import ContactContext

STEPS_PER_CONTACT = 400
CASES = [("linear", None), ("hertz", None)] + [
    (case, calibration) for case in IMPACT_VARIANTS for calibration in ("published", "exact")]


def _wall_text(contact: dict, side: str, dt: float, duration: float, gap: float) -> str:
    """One storey-less mass W/1 of mass M_EFF moving at V_IMPACT toward a wall ``gap`` away."""
    right = side == "right"
    nodes = ["W/1", "ground"] if right else ["ground", "W/1"]
    return scene_text(
        nodes=[{"name": "W/1", "mass": M_EFF}],
        contacts=[{"name": "wall", "nodes": nodes, "gap": gap} | contact],
        damping={"ratio": 0.0},
        initial_conditions={"velocity": {"W/1": V_IMPACT if right else -V_IMPACT}},
        analysis={"dt": dt, "duration": duration,
                  "integrator": {"type": "newmark", "events": True}},
        recorders=[{"kind": "history", "quantities": ["velocity", "contact_force",
                                                      "contact_penetration"]}],
    )


def test_a_wall_is_an_infinite_mass():
    """The law numbers of a wall contact are those of a pair with the floor's effective mass."""
    wall = ContactContext(M_EFF, float("inf"))
    assert wall.effective_mass == M_EFF
    assert ContactContext(float("inf"), M_EFF).effective_mass == M_EFF
    assert CONTEXT.effective_mass == pytest.approx(M_EFF, rel=1e-15)


@pytest.mark.slow
@pytest.mark.parametrize("side", ["right", "left"])
def test_every_law_rebounds_off_a_wall_as_its_formula_implies(side):
    """Every law x calibration x e = 0.2, 0.8 against a wall on either side, a gap closed in
    the first steps: one impact, the restitution the law's formula implies for the floor's
    mass (within the event stepping's 1e-4; Jankowski's infinite slope 1e-3), the energy
    balance closed, and the wall's force never a pull."""
    texts, expected = [], []
    for case, calibration in CASES:
        for e in ((None,) if calibration is None else (0.2, 0.8)):
            duration = reference_impact(case, e, calibration)[1]
            dt = duration / STEPS_PER_CONTACT
            texts.append(_wall_text(impact_contact(case, e, calibration), side, dt,
                                    (1.25 * STEPS_PER_CONTACT + 30) * dt, 10.37 * V_IMPACT * dt))
            expected.append((case, calibration, e, _expected(case, e, calibration)))
    for text, (case, calibration, e, rebound) in zip(texts, expected):
        plan, result = run_text(text)
        label = f"{case} {calibration} e = {e}, wall on the {side}"
        assert result.completed(0), f"{label}: {result.describe_failure(0)}"
        assert int(result.impacts[0, 0]) == 1, label
        v = result.history["velocity"][0, :, 0]
        ratio = -v[-1] / v[0]
        tolerance = 1e-3 if case == "jankowski" else 1e-4
        assert abs(ratio - rebound) <= tolerance, f"{label}: rebound {ratio:.6f}, expected {rebound:.6f}"
        assert result.energy_error(0) < 1e-9, label
        force = result.history["contact_force"][0, :, 0]
        if not (case == "kelvin-tension"):
            assert np.all(force >= 0.0), label
        assert np.max(force) > 0.0, label


def test_a_wall_stops_a_building_and_the_file_names_the_ground(tmp_path):
    """A building between two walls: its floor never passes either wall by more than the
    contact's deformation, and the result file labels the wall's side 'ground'."""
    import pframe

    scene = {
        "buildings": [{"name": "A", "floors": 2, "mass": 1000.0,
                       "story": {"material": "elastic", "stiffness": 2.0e5}}],
        "contacts": [
            {"name": "east", "nodes": ["A/2", "ground"], "gap": 0.02, "law": "linear",
             "stiffness": 1.0e8},
            {"name": "west", "nodes": ["ground", "A/2"], "gap": 0.02, "law": "linear",
             "stiffness": 1.0e8}],
        "damping": {"ratio": 0.02},
        "excitation": {"kind": "sine", "amplitude": 3.0, "frequency": 8.0},
        "analysis": {"dt": 0.0005, "duration": 3.0},
        "recorders": [{"kind": "history", "quantities": ["displacement", "contact_force"]}],
    }
    ds = pframe.solve(pframe.load(scene))
    u = ds.displacement.sel(node="A/2").values
    assert ds.attrs["status"] == "completed"
    assert int(ds.impact_count.sum()) > 2
    # a floor of 1000 kg arriving at well under 1 m/s on 1e8 N/m compresses the contact by
    # v sqrt(m / k) < 3 mm; the force is k times the overlap and never a pull
    assert 0.02 < np.max(u) < 0.02 + 3e-3 and -0.02 - 3e-3 < np.min(u) < -0.02
    force = ds.contact_force.sel(contact="east").values
    overlap = np.clip(u - 0.02, 0.0, None)
    np.testing.assert_allclose(force, 1.0e8 * overlap, rtol=1e-9, atol=1e-6)
    assert list(ds.contact_right.values) == ["ground", "A/2"]
    assert list(ds.contact_left.values) == ["A/2", "ground"]


def test_a_contact_needs_a_node():
    from pframe.reader import parse_scene

    text = json.loads(_wall_text({"law": "linear", "stiffness": 1e7}, "right", 1e-4, 0.01, 0.0))
    text["contacts"][0]["nodes"] = ["ground", "ground"]
    with pytest.raises(InputError, match="node on at least one side"):
        _ = parse_scene(json.dumps(text)).expanded


def test_walls_in_a_batch():
    """A sweep over the wall's gap runs as one batch (walls change no topology)."""
    contact = {"law": "linear", "stiffness": 1e7}
    texts = [_wall_text(contact, "right", 1e-4, 0.2, gap) for gap in (0.0, 0.01, 0.05)]
    plan, result = run_batch(texts)
    assert [bool(result.completed(b)) for b in range(3)] == [True] * 3
    assert list(result.impacts[:, 0]) == [1, 1, 1]


def test_the_gap_audit_refuses_walls_saying_why(tmp_path):
    from pframe.gap.runs import contact_pairs
    from pframe.reader import parse_scene

    loaded = parse_scene(_wall_text({"law": "linear", "stiffness": 1e7}, "left", 1e-4, 0.01,
                                    0.0))
    with pytest.raises(InputError, match="does not audit walls"):
        contact_pairs(loaded)


def test_the_isolated_building_against_its_moat_wall(tmp_path):
    """models/isolated-moat-wall.yaml: the Bouc-Wen isolation level reaches the moat wall
    under El Centro x 2; the bumpered wall stops it within the bumper's thickness (the same
    building without the wall moves further), never pulls, and the balance closes."""
    from conftest import REPO, record_file, runnable_model

    from pframe.assemble import assemble
    from pframe.kernel import simulate
    from pframe.model.expand import expand
    from pframe.reader import load_scene

    record_file("elCentro.AT2")
    loaded = load_scene(runnable_model(REPO / "models" / "isolated-moat-wall.yaml", tmp_path))
    slab = {}
    for label, scene in (("wall", loaded.scene),
                         ("free", loaded.scene.model_copy(update={"contacts": []}))):
        plan = assemble(expand(scene, loaded.base_dir))
        result = simulate(plan)
        assert result.completed(0) and result.energy_error(0) < 1e-9, label
        u = result.history["displacement"][0][:, plan.node_dof[plan.node_names.index("ISO/1")]]
        slab[label] = np.max(np.abs(u))
        if label == "wall":
            assert int(result.impacts[0].sum()) >= 2
            assert np.all(result.history["contact_force"][0] >= 0.0)
    assert slab["free"] > 0.12  # without the wall the slab moves past it
    assert 0.10 < slab["wall"] < 0.10 + 0.05  # stopped within the bumper's thickness
