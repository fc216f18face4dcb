"""pframe.assemble: the plan of a scene (DOF order, masses, Rayleigh damping, law groups,
ground motion) against what the definitions and closed forms say."""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.linalg import eigh

from pframe.assemble import assemble
from pframe.reader import parse_scene

SCENE = """
buildings:
  - {name: A, floors: 3, mass: [250.0, 240.0, 230.0],
     story: {material: bilinear, stiffness: [2.0e5, 1.8e5, 1.5e5], yield_drift: 0.02, alpha: 0.1}}
  - {name: B, floors: 4, mass: 1000.0, story: {material: elastic, stiffness: 2.0e6},
     damping: {ratio: 0.03, modes: [1, 3]}}
contacts:
  - {nodes: [A/1, B/1], gap: 0.01, law: linear, stiffness: 1.0e7}
  - {nodes: [A/3, B/3], gap: 0.02, law: hertz, stiffness: 1.0e9}
  - {nodes: [A/2, B/2], gap: 0.015, law: linear, stiffness: 2.0e7}
damping: {ratio: 0.05, modes: [1, 2]}
excitation: {kind: sine, amplitude: 2.0, frequency: 7.0}
analysis: {dt: 0.001, duration: 0.5}
"""


@pytest.fixture(scope="module")
def plan():
    return assemble(parse_scene(SCENE).expanded)


def _building(plan, name):
    nodes = [i for i, n in enumerate(plan.node_names) if n.startswith(f"{name}/")]
    stories = [i for i, n in enumerate(plan.story_names) if n.startswith(f"{name}/")]
    return nodes, stories


def test_dofs_are_a_banded_ordering_of_the_nodes(plan):
    """Every node has one DOF; storeys and contacts couple DOFs at most 2 apart (the reverse
    Cuthill-McKee order of two buildings side by side), which the banded solver relies on."""
    assert sorted(plan.node_dof.tolist()) == list(range(len(plan.node_names)))
    pairs = [tuple(d) for d in plan.story_dofs] + [tuple(d) for d in plan.contact_dofs]
    width = max(abs(i - j) for i, j in pairs if min(i, j) >= 0)
    assert width <= 2


def test_masses_and_stiffnesses_land_on_their_dofs(plan):
    masses = {"A/1": 250.0, "A/2": 240.0, "A/3": 230.0}
    for i, name in enumerate(plan.node_names):
        assert plan.mass[0, plan.node_dof[i]] == masses.get(name, 1000.0)
    k0 = dict(zip(plan.story_names, plan.story_k0[0]))
    assert (k0["A/1"], k0["A/2"], k0["A/3"], k0["B/4"]) == (2.0e5, 1.8e5, 1.5e5, 2.0e6)


@pytest.mark.parametrize(("name", "ratio", "modes"), [("A", 0.05, (1, 2)), ("B", 0.03, (1, 3))])
def test_rayleigh_damping_gives_the_ratio_on_its_two_modes(plan, name, ratio, modes):
    """a0 M + a1 K of each building, fitted on that building alone (fixed base): the modal
    damping ratio a0 / (2 w) + a1 w / 2 equals the ratio asked for on the two modes named, and
    differs on the others (a building's own setting overrides the scene's)."""
    nodes, stories = _building(plan, name)
    dofs = plan.node_dof[nodes]
    n = len(nodes)
    K = np.zeros((n, n))
    k = plan.story_k0[0, stories]
    for j in range(n):  # storey j joins floor j - 1 (or the ground) and floor j
        K[j, j] += k[j]
        if j > 0:
            K[j - 1, j - 1] += k[j]
            K[j - 1, j] -= k[j]
            K[j, j - 1] -= k[j]
    M = np.diag(plan.mass[0, dofs])
    w = np.sqrt(eigh(K, M, eigvals_only=True))
    a0 = plan.mass_damping[0, dofs] / plan.mass[0, dofs]
    a1 = plan.story_beta[0, stories]
    assert np.allclose(a0, a0[0]) and np.allclose(a1, a1[0])
    xi = a0[0] / (2 * w) + a1[0] * w / 2
    for mode in range(n):
        if mode + 1 in modes:
            assert xi[mode] == pytest.approx(ratio, rel=1e-10)
        else:
            assert abs(xi[mode] - ratio) > 1e-3


def test_contacts_are_grouped_by_law_in_declaration_order(plan):
    groups = {g.law.name: g for g in plan.contact_groups}
    assert sorted(groups) == ["hertz", "linear"]
    assert groups["linear"].index.tolist() == [0, 2] and groups["hertz"].index.tolist() == [1]
    assert groups["linear"].params[0, :, 0].tolist() == [1.0e7, 2.0e7]
    assert plan.contact_gap[0].tolist() == [0.01, 0.02, 0.015]
    assert plan.contact_names == ("A/1-B/1", "A/3-B/3", "A/2-B/2")  # default names


def test_ground_motion_is_the_sine_on_the_time_grid(plan):
    t = plan.times
    assert plan.steps == 500 and t[-1] == pytest.approx(0.5)
    np.testing.assert_allclose(plan.ground_acceleration[0], 2.0 * np.sin(7.0 * t),
                               rtol=0, atol=1e-14)


def test_a_scene_without_contacts_has_no_contact_groups_and_is_linear_if_elastic():
    text = SCENE.split("contacts:")[0] + "excitation: {kind: sine, amplitude: 2.0, frequency: 7.0}\n" \
        "analysis: {dt: 0.001, duration: 0.5}\n"
    plan = assemble(parse_scene(text.replace("material: bilinear", "material: elastic")
                                .replace(", yield_drift: 0.02, alpha: 0.1", "")).expanded)
    assert plan.contact_groups == () and plan.linear
    assert math.isclose(plan.dt[0], 0.001)
