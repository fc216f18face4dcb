"""Buildings in plan (docs/plan.md): floors that translate along x and y and turn, lines of
resistance at plan points, contacts at corners.

Checked against the closed form of a torsionally coupled one-storey building (Chopra,
Dynamics of Structures, ch. 9), against today's planar scenes written in plan form (the same
bits), and for the input a plan scene may get wrong."""

from __future__ import annotations

import copy
import functools
import json
import math
import re

import numpy as np
import pytest
import yaml
from conftest import REPO, analysis, integrator_cases, run_text

from pframe.errors import InputError
from pframe.reader import parse_scene


def dof_history(plan, result, node: str, component: int, quantity: str = "displacement"):
    """History of one degree of freedom (component 0 u_x, 1 u_y, 2 theta) of a node."""
    i = plan.node_names.index(node)
    column = np.flatnonzero((plan.dof_node == i) & (plan.dof_component == component))
    return result.history[quantity][0, :, int(column[0])]


# --- a one-storey eccentric building: the closed form ---------------------------------------

MASS, SIDE, KX, KY = 1.0e5, 10.0, 4.0e7, 3.0e7


def eccentric(eccentricity: float, dt: float, duration: float, **more) -> str:
    """A square floor of side 10 m on four frames (two along x at y = 0 and 10 with KX each,
    two along y at x = 0 and 10 with KY each), its mass off the centre by ``eccentricity``
    along x: the centre of rigidity stays at the plan's centre."""
    scene = {
        "buildings": [{
            "name": "A", "floors": 1, "mass": MASS, "plan": {"size": [SIDE, SIDE]},
            "centre_of_mass": [SIDE / 2 + eccentricity, SIDE / 2],
            "lines": [
                {"name": "X1", "position": [0, 0], "direction": "x", "material": "elastic",
                 "stiffness": KX},
                {"name": "X2", "position": [0, SIDE], "direction": "x", "material": "elastic",
                 "stiffness": KX},
                {"name": "Y1", "position": [0, 0], "direction": "y", "material": "elastic",
                 "stiffness": KY},
                {"name": "Y2", "position": [SIDE, 0], "direction": "y", "material": "elastic",
                 "stiffness": KY}]}],
        "damping": {"ratio": 0.0},
        "analysis": analysis(dt, duration),
        "recorders": [{"kind": "history", "quantities": ["displacement"]}],
    } | more
    return json.dumps(scene)


def chopra_frequencies(eccentricity: float) -> np.ndarray:
    """The two coupled frequencies (rad/s) of the y-torsion motion of :func:`eccentric`:
    lambda / w_y^2 = [(1 + W^2 + eps^2) -/+ sqrt((1 + W^2 + eps^2)^2 - 4 W^2)] / 2, eps = e/r,
    W = w_theta / w_y with w_theta^2 = K_theta (about the centre of rigidity) / J (Chopra,
    Dynamics of Structures, section 9.5)."""
    r2 = (SIDE**2 + SIDE**2) / 12.0  # J / m of a uniform square slab
    k_y = 2 * KY
    k_theta = 2 * KX * (SIDE / 2) ** 2 + 2 * KY * (SIDE / 2) ** 2  # about the plan's centre
    w_y2, w_t2 = k_y / MASS, k_theta / (MASS * r2)
    big2, eps2 = w_t2 / w_y2, eccentricity**2 / r2
    s = 1.0 + big2 + eps2
    root = math.sqrt(s * s - 4.0 * big2)
    return np.sqrt(w_y2 * np.array([(s - root) / 2.0, (s + root) / 2.0]))


def exact_free_vibration(eccentricity: float, u0: np.ndarray, times: np.ndarray):
    """(u_y, theta) of the free vibration from rest at displacement u0 = (u_y, theta), by
    modal superposition of the stiffness and mass written from the geometry."""
    r2 = (SIDE**2 + SIDE**2) / 12.0
    e = eccentricity
    # about the centre of mass: u_y of the rigidity centre is u_y - e theta
    k_y = 2 * KY
    k_theta_cr = 2 * KX * (SIDE / 2) ** 2 + 2 * KY * (SIDE / 2) ** 2
    K = np.array([[k_y, -k_y * e], [-k_y * e, k_theta_cr + k_y * e * e]])
    M = np.diag([MASS, MASS * r2])
    scale = 1.0 / np.sqrt(np.diag(M))
    w2, phi = np.linalg.eigh(K * np.outer(scale, scale))
    modes = phi * scale[:, None]  # mass-normalised
    q0 = modes.T @ M @ u0
    return (modes * q0) @ np.cos(np.outer(np.sqrt(w2), times)), np.sqrt(w2)


def test_closed_form_frequencies_match_the_geometry():
    """The stiffness written from the frames' positions has the closed form's frequencies
    (the hand-written K of the next test is the physics, not pframe's code)."""
    for e in (0.0, 1.5, 3.0):
        _, w = exact_free_vibration(e, np.array([0.01, 0.0]), np.zeros(1))
        np.testing.assert_allclose(w, chopra_frequencies(e), rtol=1e-12)


@pytest.mark.parametrize("eccentricity", [1.5, 3.0])
def test_eccentric_building_vibrates_at_the_coupled_frequencies(eccentricity):
    """Free vibration from a push along y: the floor twists as it sways, and the kernel
    follows the exact modal solution to Newmark's period error, which falls as dt^2."""
    errors = []
    for dt in (4e-4, 2e-4):
        text = eccentric(eccentricity, dt, 1.0, initial_conditions={
            "displacement": {"A/1": [0.0, 0.01, 0.0]}})
        plan, result = run_text(text)
        assert result.completed(0)
        uy, theta = (dof_history(plan, result, "A/1", c) for c in (1, 2))
        (ey, et), _ = exact_free_vibration(eccentricity, np.array([0.01, 0.0]), plan.times)
        assert np.max(np.abs(theta)) > 0.05 * 0.01 / SIDE  # it twists
        errors.append(max(np.max(np.abs(uy - ey)) / 0.01,
                          np.max(np.abs(theta - et)) / np.max(np.abs(et))))
        assert result.energy_error(0) < 1e-10
        # the floor never moves along x: no frame is loaded that way
        assert np.all(dof_history(plan, result, "A/1", 0) == 0.0)
    assert errors[0] < 2e-3
    assert 3.5 < errors[0] / errors[1] < 4.5  # second order


def test_a_symmetric_floor_does_not_twist():
    """The centre of mass on the centre of rigidity: a push along y gives a pure sway at
    w_y = sqrt(2 KY / m), no rotation at all."""
    plan, result = run_text(eccentric(0.0, 2e-4, 0.5, initial_conditions={
        "displacement": {"A/1": [0.0, 0.01, 0.0]}}))
    assert np.all(dof_history(plan, result, "A/1", 2) == 0.0)
    w = math.sqrt(2 * KY / MASS)
    uy = dof_history(plan, result, "A/1", 1)
    np.testing.assert_allclose(uy, 0.01 * np.cos(w * plan.times), atol=2e-3 * 0.01)


# --- today's scenes written in plan form give today's bits ------------------------------------

def _in_plan(data: dict, size=(12.0, 8.0)) -> dict:
    """A scene's buildings written in plan: a floor plan, and one line of resistance along x
    through the centre of mass for the storey spring."""
    out = copy.deepcopy(data)
    for building in out.get("buildings", []):
        story = building.pop("story")
        building["plan"] = {"size": list(size)}
        building["lines"] = [{"name": "F", "position": [size[0] / 2, size[1] / 2],
                              "direction": "x", **story}]
    return out


@pytest.mark.parametrize("model", ["wu2021-eq14.yaml", "isolated-moat-wall.yaml"])
def test_a_planar_scene_in_plan_form_gives_the_same_bits(model):
    """The paper's pair and an isolated building at a moat wall, each storey written as one
    line through the centres of mass along x: the same DOFs, the same results to the bit."""
    from conftest import runnable_model

    from pframe.assemble import assemble
    from pframe.kernel import simulate
    from pframe.reader import load_scene

    path = REPO / "models" / model
    data = yaml.safe_load(path.read_text())
    data["analysis"]["duration"] = min(data["analysis"]["duration"], 2.0)
    runs = []
    for scene in (data, _in_plan(data)):
        loaded = parse_scene(json.dumps(scene), base_dir=path.parent)
        plan = assemble(loaded.expanded)
        assert plan.planar and plan.n_dof == len(plan.node_names)
        runs.append(simulate(plan))
    assert runs[0].completed(0)
    for q in runs[0].history:
        np.testing.assert_array_equal(runs[0].history[q], runs[1].history[q])
    np.testing.assert_array_equal(runs[0].energy, runs[1].energy)
    del runnable_model, load_scene


# --- input a scene in plan may get wrong ------------------------------------------------------

def _refused(text: str) -> str:
    with pytest.raises(InputError) as caught:
        parse_scene(text)
    return str(caught.value)


def test_a_corner_impact_needs_torsional_stiffness():
    """A planar building struck off its centre of mass has no torsional stiffness: refused,
    naming the storey and what turns it."""
    scene = {
        "buildings": [
            {"name": "A", "floors": 1, "mass": 1e5, "plan": {"size": [10, 10]},
             "story": {"material": "elastic", "stiffness": 1e8}},
            {"name": "B", "floors": 1, "mass": 1e5, "plan": {"size": [10, 10]},
             "story": {"material": "elastic", "stiffness": 1e8}}],
        "contacts": [{"nodes": ["A/1", "B/1"], "gap": 0.01, "law": "linear",
                      "stiffness": 1e9, "points": ["NE", "NW"]}],
        "excitation": {"kind": "sine", "amplitude": 1.0, "frequency": 5.0},
        "analysis": analysis(0.01, 1.0)}
    message = _refused(json.dumps(scene))
    assert "storey A/1" in message and "torsion" in message
    assert "A/1-B/1 acts on it" in message


def test_a_point_outside_the_plan_is_refused():
    text = eccentric(0.0, 0.01, 0.1, contacts=[
        {"nodes": ["A/1", "ground"], "gap": 0.01, "law": "linear", "stiffness": 1e9,
         "points": [[12.0, 5.0], None]}])
    assert "outside the plan" in _refused(text) and "contacts[0].points[0]" in _refused(text)


def test_a_normal_of_zero_length_is_refused():
    text = eccentric(0.0, 0.01, 0.1, contacts=[
        {"nodes": ["A/1", "ground"], "gap": 0.01, "law": "linear", "stiffness": 1e9,
         "points": ["NE", None], "normal": [0.0, 0.0]}])
    message = _refused(text)
    assert "normal" in message and "zero length" in message


def test_a_floor_that_turns_needs_its_polar_inertia():
    """Lines in plan but no plan and no polar_inertia: the floor's J is unknown."""
    scene = json.loads(eccentric(1.0, 0.01, 0.1))
    del scene["buildings"][0]["plan"]
    message = _refused(json.dumps(scene))
    assert "polar_inertia" in message and "A/1" in message


def test_lines_through_one_point_give_no_torsional_stiffness():
    scene = json.loads(eccentric(1.0, 0.01, 0.1))
    for line in scene["buildings"][0]["lines"]:
        line["position"] = [5.0, 5.0]
    message = _refused(json.dumps(scene))
    assert "no stiffness in torsion" in message and "place them apart" in message


def test_named_points_move_with_their_floors():
    """The corners of a two-storey building in plan, turned on the site: each point moves as
    its floor's centre of mass plus theta times its arm, along its building's axes; its drift
    is the same point of the floor below subtracted; an envelope is the peak of the history."""
    angle = 30.0
    scene = json.loads(eccentric(2.0, 1e-3, 0.5, initial_conditions={
        "displacement": {"A/1": [0.002, 0.01, 0.001], "A/2": [-0.001, 0.02, -0.002]}}))
    building = scene["buildings"][0]
    building.update(floors=2, angle=angle, origin=[3.0, -4.0], height=3.0,
                    points={"P": [2.0, 7.0]})
    scene["recorders"] = [{"kind": "history", "quantities": ["displacement", "point_displacement",
                                                             "point_drift"]},
                          {"kind": "envelope", "quantities": ["point_displacement"]}]
    plan, result = run_text(json.dumps(scene))
    assert result.completed(0) and plan.point_names[:5] == (
        "A/1:SW", "A/1:SE", "A/1:NE", "A/1:NW", "A/1:P")
    c, s = math.cos(math.radians(angle)), math.sin(math.radians(angle))
    centre_local = np.array([SIDE / 2 + 2.0, SIDE / 2])
    local = {"SW": (0, 0), "SE": (SIDE, 0), "NE": (SIDE, SIDE), "NW": (0, SIDE), "P": (2, 7)}
    moves = result.history["point_displacement"][0].reshape(plan.steps + 1, -1, 2)
    drifts = result.history["point_drift"][0].reshape(plan.steps + 1, -1, 2)
    floor_motion = {}
    for floor in ("A/1", "A/2"):
        ux, uy, th = (dof_history(plan, result, floor, k) for k in range(3))
        floor_motion[floor] = {}
        for label, (x, y) in local.items():
            arm = np.array([x, y]) - centre_local  # building axes
            # the point's motion in the site's axes, then along the building's axes
            site = np.stack([ux - th * (c * arm[1] + s * arm[0]),
                             uy + th * (c * arm[0] - s * arm[1])], axis=1)
            along = np.stack([c * site[:, 0] + s * site[:, 1], -s * site[:, 0] + c * site[:, 1]],
                             axis=1)
            floor_motion[floor][label] = along
            p = plan.point_names.index(f"{floor}:{label}")
            np.testing.assert_allclose(moves[:, p], along, rtol=0, atol=1e-15)
    for label in local:
        p = plan.point_names.index(f"A/2:{label}")
        np.testing.assert_allclose(drifts[:, p], floor_motion["A/2"][label]
                                   - floor_motion["A/1"][label], rtol=0, atol=1e-15)
        q = plan.point_names.index(f"A/1:{label}")
        np.testing.assert_allclose(drifts[:, q], floor_motion["A/1"][label], rtol=0, atol=1e-15)
    np.testing.assert_array_equal(result.envelope["point_displacement"][0],
                                  np.abs(result.history["point_displacement"][0]).max(axis=0))


def test_a_batch_over_eccentricity_equals_its_single_runs():
    """Variants whose centre of mass moves onto a line of resistance (its arm, hence a
    coefficient, is 0 there) and off the plan's centre: one batch, each member the bits of
    its own run; the floors twist more as the eccentricity grows."""
    from conftest import run_batch

    values = (0.0, 2.0, 5.0)  # 5: the centre of mass on line Y2 (x = 10)
    texts = [eccentric(e, 1e-3, 0.3, initial_conditions={
        "displacement": {"A/1": [0.0, 0.01, 0.0]}}) for e in values]
    plan, batch = run_batch(texts)
    twist = []
    for b, text in enumerate(texts):
        single_plan, single = run_text(text)
        order = [int(np.flatnonzero((plan.dof_node == n) & (plan.dof_component == c))[0])
                 for n, c in zip(single_plan.dof_node, single_plan.dof_component)]
        np.testing.assert_array_equal(batch.history["displacement"][b][:, order],
                                      single.history["displacement"][0])
        twist.append(np.max(np.abs(dof_history(single_plan, single, "A/1", 2))))
    assert twist[0] == 0.0 < twist[1] < twist[2]


def test_p_delta_softens_sway_and_twist():
    """P-delta in plan: the weight P = m g on a storey of height h takes P / h off its sway
    stiffness and P r^2 / h off its torsional stiffness (r^2 = J / m, the load spread as the
    mass), so a symmetric floor sways at sqrt((2 KY - P/h) / m) and twists at
    sqrt((K_theta - P r^2 / h) / J) (Wilson & Habibullah 1987: the geometric stiffness of a
    rigid floor's gravity load)."""
    height, g = 3.0, 9.80665
    r2 = (SIDE**2 + SIDE**2) / 12.0
    load = MASS * g
    k_theta = 2 * KX * (SIDE / 2) ** 2 + 2 * KY * (SIDE / 2) ** 2
    for push, component, w in (
            ([0.0, 0.01, 0.0], 1, math.sqrt((2 * KY - load / height) / MASS)),
            ([0.0, 0.0, 0.002], 2, math.sqrt((k_theta - load * r2 / height) / (MASS * r2)))):
        scene = json.loads(eccentric(0.0, 2e-4, 0.5, initial_conditions={
            "displacement": {"A/1": push}}))
        scene["buildings"][0].update(height=height, p_delta=True)
        plan, result = run_text(json.dumps(scene))
        assert result.completed(0) and result.energy_error(0) < 1e-10
        u = dof_history(plan, result, "A/1", component)
        np.testing.assert_allclose(u, push[component] * np.cos(w * plan.times),
                                   atol=2e-3 * push[component])
        without = math.sqrt((2 * KY / MASS) if component == 1 else k_theta / (MASS * r2))
        # without P-delta the floor would be ahead by more than the tolerance at the end
        assert np.max(np.abs(u - push[component] * np.cos(without * plan.times))) \
            > 1e-2 * push[component]


def test_a_rotation_too_large_for_the_small_rotation_model_is_said():
    """The floor's edge (14.1 m across) moves r theta^2 / 2 off the linearised path: 0.05 rad
    puts it 1.8 cm off, more than 1 % of the 0.5 m gap to the wall; 0.002 rad does not.
    Without a contact the edge's own motion is the scale: r theta^2 / 2 over r theta."""
    from pframe.verdict import IN_DOUBT, TRUSTED, of_result

    for theta, doubted in ((0.05, True), (0.002, False)):
        text = eccentric(0.0, 1e-3, 0.3, initial_conditions={
            "displacement": {"A/1": [0.0, 0.0, theta]}}, contacts=[
            {"nodes": ["A/1", "ground"], "gap": 0.5, "law": "linear", "stiffness": 1e9,
             "points": ["NE", None]}])
        _, result = run_text(text)
        verdict = of_result(result)
        rotation = [w for w in verdict.warnings if "small-rotation" in w]
        assert bool(rotation) == doubted
        assert verdict.level == (IN_DOUBT if doubted else TRUSTED)
        if doubted:
            assert "floor A/1 turns by up to 0.05 rad" in rotation[0]
    # without contacts, a floor that only twists is off by theta / 2 of its edge's motion
    for theta, doubted in ((0.05, True), (0.01, False)):
        _, result = run_text(eccentric(0.0, 1e-3, 0.3, initial_conditions={
            "displacement": {"A/1": [0.0, 0.0, theta]}}))
        rotation = [w for w in of_result(result).warnings if "small-rotation" in w]
        assert bool(rotation) == doubted
        if doubted:
            assert "2.5% of its peak motion at its edge" in rotation[0]


def test_the_pi_form_refuses_a_scene_in_plan(tmp_path, capsys):
    """pframe pi of a scene in plan: exit 2, the file named, the reason (its groups are not
    derived), nothing printed as if they were."""
    from pframe.cli import main

    path = tmp_path / "ecc.yaml"
    scene = json.loads(eccentric(1.0, 0.01, 0.1))
    scene["excitation"] = {"kind": "sine", "amplitude": 1.0, "frequency": 5.0}
    path.write_text(json.dumps(scene))
    assert main(["pi", str(path)]) == 2
    captured = capsys.readouterr()
    assert captured.out == "" and str(path) in captured.err
    assert "no buildings in plan yet" in captured.err


def test_rayleigh_damping_on_modes_named_by_direction():
    """damping modes [x1, torsion1] on the eccentric floor: the x mode (w^2 = 2 KX / M,
    uncoupled) and the torsional one of the coupled pair (the higher of Chopra's two, its
    twist dominant for W^2 = 3.5) get the ratio asked, (a0 / w + a1 w) / 2 = 5 %, and the
    lateral one of the pair does not; a direction with too few modes is refused by name."""
    from pframe.assemble import assemble

    e = 3.0
    data = json.loads(eccentric(e, 1e-3, 0.01))
    data["damping"] = {"ratio": 0.05, "modes": ["x1", "torsion1"]}
    plan = assemble(parse_scene(json.dumps(data)).expanded)
    a0 = plan.mass_damping[0] / plan.mass[0]
    assert np.allclose(a0, a0[0], rtol=1e-12)
    a1 = plan.story_beta[0]
    assert np.allclose(a1, a1[0], rtol=1e-12)

    def ratio(w):
        return (a0[0] / w + a1[0] * w) / 2.0

    lateral, torsional = chopra_frequencies(e)
    assert ratio(math.sqrt(2 * KX / MASS)) == pytest.approx(0.05, rel=1e-10)
    assert ratio(torsional) == pytest.approx(0.05, rel=1e-10)
    assert abs(ratio(lateral) - 0.05) > 0.002  # 5.47 %: not one of the two fitted
    data["damping"]["modes"] = ["x2", "y1"]
    with pytest.raises(InputError, match="1 mode\\(s\\) moving mostly in x.*'x2'"):
        assemble(parse_scene(json.dumps(data)).expanded)


def test_a_scene_in_plan_scales_to_the_similar_scene(tmp_path, capsys):
    """pframe scale with S_L = 1/16, S_E = 1, S_a = 1 (S_T = 1/4, S_M = S_F / S_a = 1/256): the model of
    a turned eccentric building under two sine components, started from [u_x, u_y, theta],
    moves as the prototype does, lengths x 1/16 at times x 1/4 and its rotation the same
    (similitude: every Pi group kept); its polar inertia is x S_M S_L^2."""
    import pframe
    from pframe.cli import main

    data = json.loads(eccentric(1.5, 1e-3, 0.4))
    building = data["buildings"][0]
    building |= {"origin": [4.0, -2.0], "angle": 15.0, "polar_inertia": 1.8e6}
    building["points"] = {"tip": [10.0, 10.0]}
    data["damping"] = {"ratio": 0.03, "modes": ["y1", "torsion1"]}
    data["excitation"] = {"kind": "components", "angle": 20.0,
                          "x": {"kind": "sine", "amplitude": 2.0, "frequency": 9.0},
                          "y": {"kind": "sine", "amplitude": 1.5, "frequency": 13.0}}
    data["initial_conditions"] = {"displacement": {"A/1": [0.01, -0.005, 0.001]},
                                  "velocity": {"A/1": [0.0, 0.1, 0.02]}}
    data["recorders"] = [{"kind": "history", "quantities": ["displacement", "point_drift"]}]
    (tmp_path / "scene.yaml").write_text(yaml.safe_dump(data), encoding="utf-8")
    assert main(["scale", str(tmp_path / "scene.yaml"), "--length", "1/16", "--modulus", "1",
                 "--acceleration", "1", "-o", str(tmp_path / "model.yaml")]) == 0
    capsys.readouterr()
    scaled = yaml.safe_load((tmp_path / "model.yaml").read_text(encoding="utf-8"))
    model_building = scaled["buildings"][0]
    assert model_building["origin"] == [0.25, -0.125] and model_building["angle"] == 15.0
    assert model_building["polar_inertia"] == pytest.approx(1.8e6 / 256 / 256, rel=1e-14)
    assert scaled["initial_conditions"]["displacement"]["A/1"] == pytest.approx(
        [0.01 / 16, -0.005 / 16, 0.001], rel=1e-14)
    assert scaled["initial_conditions"]["velocity"]["A/1"] == pytest.approx(
        [0.0, 0.1 / 4, 0.02 * 4], rel=1e-14)
    assert scaled["excitation"]["x"]["frequency"] == 36.0
    prototype = pframe.solve(pframe.load(tmp_path / "scene.yaml"), progress=False)
    model = pframe.solve(pframe.load(tmp_path / "model.yaml"), progress=False)
    for name in ("displacement", "point_drift"):
        p, m = prototype[name].values, model[name].values
        assert np.max(np.abs(m * 16 - p)) <= 1e-9 * np.max(np.abs(p))
    p, m = prototype["displacement_rz"].values, model["displacement_rz"].values
    assert np.max(np.abs(m - p)) <= 1e-9 * np.max(np.abs(p))
    np.testing.assert_allclose(model["t"].values * 4, prototype["t"].values, rtol=1e-12)


def _irregularity(initial: list, eccentricity: float):
    """The torsional irregularity ratios (x, y) of the eccentric storey's free vibration from
    ``initial`` = [u_x, u_y, theta] of its floor, undamped."""
    import pframe

    data = json.loads(eccentric(eccentricity, 1e-3, 0.3, initial_conditions={
        "displacement": {"A/1": initial}}))
    data["recorders"] = []
    ds = pframe.solve(pframe.load(data), progress=False)
    assert [str(p) for p in ds.point.values] == ["A/1:SW", "A/1:SE", "A/1:NE", "A/1:NW",
                                                  "A/1:centre"]
    return ds.torsional_irregularity.values[0]


def test_torsional_irregularity_of_one_mode_and_of_a_twist():
    """Free vibration in one lateral-torsional mode of the eccentric storey (the mode shape of
    the closed form's K and M as the initial displacement: every point's drift is that shape's
    times cos w t, so its peak is the start's): the ratio along y is the larger drift at the
    ends x = 0 and 10 over the drift at the middle x = 5, |u_y + theta (x - x_cm)| each, and
    along x, where the storey only twists (u_x = 0, the ends at y = 0 and 10 drift equal and
    opposite), inf; a square storey twisted from rest, inf along both."""
    e = 1.5
    _, w = exact_free_vibration(e, np.array([0.01, 0.0]), np.zeros(1))
    r2 = (SIDE**2 + SIDE**2) / 12.0
    K = np.array([[2 * KY, -2 * KY * e],
                  [-2 * KY * e, 2 * KX * 25 + 2 * KY * 25 + 2 * KY * e * e]])
    _, shapes = np.linalg.eigh(np.diag([1, 1 / math.sqrt(r2)]) @ K
                               @ np.diag([1, 1 / math.sqrt(r2)]) / MASS)
    for mode in range(2):
        uy, theta = shapes[0, mode], shapes[1, mode] / math.sqrt(r2)
        scale = 0.01 / max(abs(uy), abs(theta) * SIDE)
        uy, theta = uy * scale, theta * scale
        x_cm = SIDE / 2 + e
        ends = [abs(uy + theta * (x - x_cm)) for x in (0.0, SIDE)]
        expected = max(ends) / abs(uy + theta * (SIDE / 2 - x_cm))
        ratio = _irregularity([0.0, float(uy), float(theta)], e)
        assert ratio[1] == pytest.approx(expected, rel=1e-9)
        assert ratio[0] == np.inf
    twist = _irregularity([0.0, 0.0, 0.001], 0.0)
    assert np.all(twist == np.inf)
    translation = _irregularity([0.0, 0.01, 0.0], 0.0)
    assert translation[1] == pytest.approx(1.0, rel=1e-12)


def test_a_storey_drifting_by_round_off_along_an_axis_has_no_ratio_along_it():
    """A symmetric storey shaken along x drifts along y by round-off only (its ends by a
    twist of 1e-20 rad, its centre by 1e-36 m): no ratio along y (NaN), not the inf of a
    storey that twists, which the ratio of those two numbers would give; along x, 1."""
    from pframe.irregularity import torsional_irregularity

    names = [f"A/1:{p}" for p in ("SW", "SE", "NE", "NW", "centre")]
    positions = [[0, 0], [20, 0], [20, 12], [0, 12], [10, 6]]
    drift = [[0.01, 2e-19], [0.01, 2e-19], [0.01, 2e-19], [0.01, 2e-19], [0.01, 1e-36]]
    ratio = torsional_irregularity(names, positions, drift, ["A/1"])[0]
    assert ratio[0] == 1.0 and np.isnan(ratio[1])
    drift = [[5e-3, 5e-3], [5e-3, 5e-3], [5e-3, 5e-3], [5e-3, 5e-3], [1e-36, 1e-36]]
    assert np.all(torsional_irregularity(names, positions, drift, ["A/1"])[0] == np.inf)


def test_two_record_components_are_said_and_reproduce_from_the_file_alone(tmp_path, capsys):
    """Two PEER records as the components of a scene in plan: validate says how each is read
    and how they are turned onto the site; the result holds each record's text and checksum
    under its axis (record_x_..., record_y_...) and each component's peak; loading the result
    file (the scene folder and records gone) rebuilds the scene and its run, bit for bit."""
    import hashlib
    import shutil

    from conftest import record_file

    import pframe
    from pframe.cli import main

    sources = {"x": record_file("elCentro.AT2"), "y": record_file("A-ELC180.AT2")}
    folder = tmp_path / "project"
    (folder / "records").mkdir(parents=True)
    for source in sources.values():
        shutil.copy(source, folder / "records" / source.name)
    data = json.loads(eccentric(1.5, 0.005, 4.0))
    data["excitation"] = {"kind": "components", "angle": 30.0,
                          "x": {"kind": "record", "file": "records/elCentro.AT2"},
                          "y": {"kind": "record", "file": "records/A-ELC180.AT2"}}
    scene = folder / "scene.yaml"
    scene.write_text(yaml.safe_dump(data), encoding="utf-8")
    assert main(["validate", str(scene)]) == 0
    out, err = capsys.readouterr()
    assert "excitation: two components turned 30 degrees: x along (0.866, 0.5)" in out
    assert re.search(r"component x: record \S*records/elCentro.AT2: PEER NGA .AT2 in g, "
                     r"1559 points", out)
    assert re.search(r"component y: record \S*records/A-ELC180.AT2: PEER NGA .AT2 in g, "
                     r"4000 points", out)
    assert "not the two components of one recording" in err  # two events: said, not refused
    with pytest.warns(UserWarning, match="not the two components of one recording"):
        first = pframe.solve(scene, output=tmp_path / "run.nc", progress=False).load()
    for axis, source in sources.items():
        assert first.attrs[f"record_{axis}_sha256"] == hashlib.sha256(
            source.read_bytes()).hexdigest()
        assert first.attrs[f"record_{axis}_file"] == f"records/{source.name}"
    assert first.attrs["excitation_x_pga_g"] == pytest.approx(0.3188, abs=5e-5)
    assert first.attrs["excitation_applied"].startswith("two components, x at 30 degrees")
    shutil.rmtree(folder)
    with pytest.warns(UserWarning):
        again = pframe.solve(pframe.load(tmp_path / "run.nc"), progress=False)
    np.testing.assert_array_equal(again.displacement.values, first.displacement.values)
    np.testing.assert_array_equal(again.displacement_rz.values, first.displacement_rz.values)


def _corner_impacts(integrator: dict, dt: float) -> tuple:
    """The eccentric floor under two sine components, its NE corner striking a wall 5 mm
    away (Hertz-damped): every integrator's run and its energy balance."""
    from conftest import run_text

    text = eccentric(1.5, dt, 1.0, contacts=[
        {"nodes": ["A/1", "ground"], "gap": 0.005, "law": "hertzdamp", "stiffness": 2e10,
         "restitution": 0.7, "points": ["NE", None], "normal": [1.0, 0.0]}],
        excitation={"kind": "components", "angle": 20.0,
                    "x": {"kind": "sine", "amplitude": 4.0, "frequency": 25.0},
                    "y": {"kind": "sine", "amplitude": 3.0, "frequency": 31.0}})
    data = json.loads(text)
    data["damping"] = {"ratio": 0.03, "modes": ["y1", "torsion1"]}
    data["analysis"]["integrator"] = integrator
    data["recorders"] = [{"kind": "envelope", "quantities": ["displacement", "contact_force"]}]
    plan, result = run_text(json.dumps(data))
    return plan, result



@functools.cache
def _corner_reference():
    return _corner_impacts({"type": "newmark", "events": True}, 1.25e-4)[1]


@pytest.mark.parametrize("integrator, facts", integrator_cases())
def test_every_integrator_runs_a_corner_impact_in_plan(integrator, facts):
    """Every integrator (each example its facts declare, with located events where it has
    them) on impacts at a corner of a floor that sways and twists: the run completes, its
    energy balance closes to the integrator's declared tolerance, and its peaks (sway, twist,
    contact force) agree with Newmark's with located events at a quarter of the step, to the
    accuracy of a step that resolves the contact by about 14 steps, with the same impacts."""
    reference = _corner_reference()
    plan, result = _corner_impacts(integrator, 5e-4)
    assert result.completed(0), result.describe_failure()
    assert int(result.impacts[0].sum()) > 0
    assert result.energy_error(0) <= max(facts.balance_tolerance, 1e-9)
    ours, theirs = result.envelope["displacement"][0], reference.envelope["displacement"][0]
    np.testing.assert_allclose(ours, theirs, rtol=3e-3)  # measured: 1e-4 .. 1e-3
    force = result.envelope["contact_force"][0][0]
    assert force == pytest.approx(reference.envelope["contact_force"][0][0], rel=1e-2)
    assert result.impacts[0].tolist() == reference.impacts[0].tolist()
