"""The gap audit of a scene in plan (docs/gap-audit.md#scenes-in-plan): the critical gap is the
closing of each contact's two points along its normal, the code rules take each building's
peak displacement at that point along the normal, and a suite says how its records stand on
the site (pairs at angles, a record along a direction).

Checked against the small-rotation kinematics of the floors' histories (u_P = u_c + theta x
(P - c)), against the rules by hand, against the planar audit of the same scene written in
plan, and against the scene's own motion in two components given as a suite's pair."""

from __future__ import annotations

import copy
import json
import math

import numpy as np
import pytest
import yaml
from conftest import REPO

import pframe
from pframe.cli import main
from pframe.excitation.suite import GroundMotion, Measure, intensity
from pframe.gap import audit
from pframe.reader import load_scene, parse_scene

#: degrees of B's turn on the site
B_ANGLE = -4.0
SCENE = {
    "title": "an eccentric storey beside a turned one",
    "buildings": [
        {"name": "A", "floors": 1, "mass": 1.0e5, "height": 3.0,
         "plan": {"size": [10.0, 6.0]}, "centre_of_mass": [6.5, 3.0],
         "lines": [
             {"name": "X1", "position": [0, 0], "direction": "x", "material": "elastic",
              "stiffness": 4.0e7},
             {"name": "X2", "position": [0, 6], "direction": "x", "material": "elastic",
              "stiffness": 4.0e7},
             {"name": "Y1", "position": [0, 0], "direction": "y", "material": "elastic",
              "stiffness": 6.0e7},
             {"name": "Y2", "position": [10, 0], "direction": "y", "material": "elastic",
              "stiffness": 1.5e7}]},
        {"name": "B", "floors": 1, "mass": 1.5e5, "height": 3.0, "origin": [10.05, 0.0],
         "angle": B_ANGLE, "plan": {"size": [8.0, 6.0]},
         "lines": [
             {"name": "X1", "position": [0, 0], "direction": "x", "material": "elastic",
              "stiffness": 9.0e7},
             {"name": "X2", "position": [0, 6], "direction": "x", "material": "elastic",
              "stiffness": 9.0e7},
             {"name": "Y1", "position": [0, 0], "direction": "y", "material": "elastic",
              "stiffness": 9.0e7},
             {"name": "Y2", "position": [8, 0], "direction": "y", "material": "elastic",
              "stiffness": 9.0e7}]}],
    "contacts": [
        {"name": "south", "nodes": ["A/1", "B/1"], "points": ["SE", "SW"], "normal": [1, 0],
         "gap": 0.05, "law": "linear", "stiffness": 1.0e9},
        {"name": "north", "nodes": ["A/1", "B/1"], "points": ["NE", "NW"], "normal": [1, 0],
         "gap": 0.05, "law": "linear", "stiffness": 1.0e9},
        {"name": "oblique", "nodes": ["A/1", "B/1"], "points": [[10, 3], [0, 3]],
         "normal": [0.8, 0.6], "gap": 0.05, "law": "linear", "stiffness": 1.0e9}],
    "damping": {"ratio": 0.05, "modes": [1, 2]},
    "excitation": {"kind": "components", "angle": 30,
                   "x": {"kind": "sine", "amplitude": 3.0, "frequency": 6.0, "cycles": 3},
                   "y": {"kind": "sine", "amplitude": 2.0, "frequency": 9.0, "cycles": 3}},
    "analysis": {"dt": 0.005, "duration": 2.0},
}


def _site(origin, angle, point):
    c, s = math.cos(math.radians(angle)), math.sin(math.radians(angle))
    return np.array([origin[0] + c * point[0] - s * point[1],
                     origin[1] + s * point[0] + c * point[1]])


#: each contact's points on the site (m) and normal, from the scene's geometry
POINTS = {"south": (_site((0, 0), 0, (10, 0)), _site((10.05, 0), B_ANGLE, (0, 0)), (1, 0)),
          "north": (_site((0, 0), 0, (10, 6)), _site((10.05, 0), B_ANGLE, (0, 6)), (1, 0)),
          "oblique": (_site((0, 0), 0, (10, 3)), _site((10.05, 0), B_ANGLE, (0, 3)),
                      (0.8, 0.6))}


def _write(folder, name: str, scene: dict):
    path = folder / name
    path.write_text(json.dumps(scene), encoding="utf-8")
    return path


def _along(run, node: str, point, normal) -> np.ndarray:
    """n . u_P(t) of a floor's point P (site coordinates): u_P = u_c + theta x (P - c), the
    small-rotation kinematics of a rigid floor."""
    i = [str(n) for n in run.node_name.values].index(node)
    u = run.displacement.values[:, i, :]
    theta = run.displacement_rz.values[:, i]
    c = np.array([float(run.node_x[i]), float(run.node_y[i])])
    arm = np.asarray(point, float) - c
    ux, uy = u[:, 0] - theta * arm[1], u[:, 1] + theta * arm[0]
    return normal[0] * ux + normal[1] * uy


@pytest.fixture(scope="module")
def audited(tmp_path_factory):
    """The audit of the scene under its own motion, and the run of the scene without its
    contacts (the audit's runs are that run)."""
    folder = tmp_path_factory.mktemp("plan-gap")
    scene = _write(folder, "scene.yaml", SCENE)
    ds = audit(scene, codes="asce7")
    free = copy.deepcopy(SCENE)
    free["contacts"] = []
    free["recorders"] = [{"kind": "history", "quantities": ["displacement"]}]
    run = pframe.solve(_write(folder, "free.yaml", free))
    return folder, ds, run


@pytest.mark.slow
def test_the_critical_gap_is_the_closing_of_the_points_along_the_normal(audited):
    """The simulated gap of each contact is max_t n . (u_P - u_Q) of its two points, u_P
    from the floors' histories by the small-rotation kinematics; each building's peak at the
    contact is max_t |n . u_P|; ABS and SRSS are their sum and root-sum-square, ASCE 7's
    same-property rule C_d / R times the SRSS (the elastic peak over R / I_e, then C_d /
    I_e). The corners' closings are not the centres': twist matters."""
    _, ds, run = audited
    table = ds.gap_required.isel(record=0, level=0)
    for c, (p, q, normal) in POINTS.items():
        left, right = _along(run, "A/1", p, normal), _along(run, "B/1", q, normal)
        rules = table.sel(contact_name=c)
        closing = float(np.max(left - right))
        assert float(rules.sel(rule_name="simulated")) == pytest.approx(
            max(closing, 0.0), rel=1e-12, abs=1e-15)
        u_a, u_b = float(np.max(np.abs(left))), float(np.max(np.abs(right)))
        for side, u in (("left", u_a), ("right", u_b)):
            peak = ds[f"peak_displacement_{side}"].isel(record=0, level=0)
            assert float(peak.sel(contact_name=c)) == pytest.approx(u, rel=1e-12)
        assert float(rules.sel(rule_name="ABS")) == pytest.approx(u_a + u_b, rel=1e-12)
        assert float(rules.sel(rule_name="SRSS")) == pytest.approx(math.hypot(u_a, u_b),
                                                                    rel=1e-12)
        assert float(rules.sel(rule_name="ASCE7_same_property")) == pytest.approx(
            5.5 / 8.0 * math.hypot(u_a, u_b), rel=1e-12)
    centres = run.displacement.values[:, 0, 0] - run.displacement.values[:, 1, 0]
    assert float(table.sel(contact_name="north", rule_name="simulated")) != pytest.approx(
        max(float(np.max(centres)), 0.0), rel=1e-3)
    assert np.max(np.abs(run.displacement_rz.values[:, 0])) > 1e-4  # A twists


@pytest.mark.slow
def test_a_pair_of_the_suite_gives_the_scenes_own_two_components(audited):
    """The scene's two sine components at 30 degrees, written as two-column records and
    given as a suite's pair at angle 30 (and among angles [0, 30]), give the audit of the
    scene's own motion bit for bit; one component along a direction, the same as the scene
    with that component alone."""
    folder, own, _ = audited
    scene = load_scene(folder / "scene.yaml")
    times = np.arange(scene.expanded.steps + 1) * scene.expanded.dt
    for axis in ("x", "y"):  # the scene's own samples of each sine: the files hold its bits
        (folder / f"{axis}.txt").write_text("".join(f"{float(t)!r} {float(v)!r}\n" for t, v in zip(
            times, _component(scene, axis))), encoding="utf-8")
    (folder / "suite.yaml").write_text(yaml.safe_dump({"records": [
        {"x": "x.txt", "y": "y.txt", "angles": [0, 30], "units": "m/s2"},
        {"file": "x.txt", "angle": 30, "units": "m/s2"}]}), encoding="utf-8")
    ds = audit(folder / "scene.yaml", folder / "suite.yaml", duration=2.0,
                          codes="asce7")
    assert list(ds.record_name.values) == ["x.txt+y.txt@0", "x.txt+y.txt@30", "x.txt@30"]
    np.testing.assert_array_equal(ds.gap_required.isel(record=1).values,
                                  own.gap_required.isel(record=0).values)
    assert not np.array_equal(ds.gap_required.isel(record=0).values,
                              ds.gap_required.isel(record=1).values)
    alone = copy.deepcopy(SCENE)
    del alone["excitation"]["y"]
    single = audit(_write(folder, "alone.yaml", alone), codes="asce7")
    np.testing.assert_array_equal(ds.gap_required.isel(record=2).values,
                                  single.gap_required.isel(record=0).values)


def _component(loaded, axis: str) -> np.ndarray:
    """The samples of one of the scene's sine components (before the turn)."""
    from pframe.excitation import ground_acceleration

    ex = loaded.expanded
    motion = getattr(loaded.scene.excitation, axis)
    return ground_acceleration(motion, np.arange(ex.steps + 1) * ex.dt)


def _in_plan(data: dict) -> dict:
    """A planar scene written in plan: each building a plan and one line along x through its
    centre of mass; the contacts at the centres (no points), along x."""
    out = copy.deepcopy(data)
    for building in out["buildings"]:
        story = building.pop("story")
        building["plan"] = {"size": [12.0, 8.0]}
        building["lines"] = [{"name": "F", "position": [6.0, 4.0], "direction": "x", **story}]
    for contact in out["contacts"]:
        contact["normal"] = [1, 0]
    return out


@pytest.mark.slow
def test_a_planar_scene_in_plan_form_gives_the_planar_audit():
    """The paper's pair, its storeys written as lines through the centres of mass: the audit
    (critical gaps, peaks, every rule) is the planar audit's, bit for bit."""
    data = yaml.safe_load((REPO / "models" / "wu2021-eq14.yaml").read_text())
    data["analysis"]["duration"] = 1.0
    audits = []
    for scene in (data, _in_plan(data)):
        loaded = parse_scene(json.dumps(scene), base_dir=REPO / "models")
        audits.append(audit(loaded, codes="asce7,tbdy2018"))
    for name in ("gap_required", "peak_displacement_left", "peak_displacement_right",
                 "period", "correlation"):
        np.testing.assert_array_equal(audits[0][name].values, audits[1][name].values)


@pytest.mark.slow
def test_a_pairs_intensity_is_its_maximum_direction():
    """The PGA of a pair is the peak of its horizontal vector; its Sa is w^2 times the peak
    of the vector of the two oscillators' displacements (RotD100), which the peak over
    turned single components approaches from below as the angles grow dense."""
    from pframe.excitation.spectrum import spectral_acceleration

    t = np.arange(2001) * 0.01
    a1 = 3.0 * np.sin(5.0 * t) * np.exp(-0.2 * t)
    a2 = 2.0 * np.sin(7.0 * t + 0.4) * np.exp(-0.1 * t)
    pair = GroundMotion("pair", t, a1, "", second=a2, directed=True)
    g = 9.80665
    assert intensity(pair, Measure(kind="pga")) == float(np.max(np.hypot(a1, a2))) / g
    sa = intensity(pair, Measure(kind="sa"), period=0.8)
    turns = np.radians(np.arange(0, 180, 0.5))
    along = max(spectral_acceleration(np.cos(a) * a1 + np.sin(a) * a2, 0.01, 0.8) / g
                for a in turns)
    assert along <= sa * (1 + 1e-12) and sa <= along / math.cos(math.radians(0.25))
    turned = GroundMotion("turned", t, a1, "", second=a2, angle=40.0, directed=True)
    assert intensity(turned, Measure(kind="sa"), period=0.8) == sa  # the angle changes none


def test_a_scene_in_two_components_refuses_a_record_that_says_no_direction(tmp_path, capsys):
    """A plain record (or a folder's) under a scene shaken in two components could mean
    either axis or a pair: refused, saying what to write; the same record with its angle
    runs."""
    scene = _write(tmp_path, "scene.yaml", SCENE)
    t = np.arange(101) * 0.01
    (tmp_path / "r.txt").write_text("".join(f"{a} {1.0 * math.sin(8 * a)}\n" for a in t))
    (tmp_path / "plain.yaml").write_text("records: [{file: r.txt, units: m/s2}]\n")
    assert main(["gap", str(scene), "--suite", str(tmp_path / "plain.yaml"), "-q",
                 "--duration", "0.2"]) == 2
    said = capsys.readouterr().err
    assert "r.txt" in said and "shaken in two components" in said
    assert "{x: FILE, y: FILE, angle: DEGREES}" in said and "either axis" in said and "Traceback" not in said


def test_a_scene_along_x_refuses_a_pair_it_cannot_resist(tmp_path, capsys):
    """A planar scene (storeys along x alone) under a suite's pair: its storeys cannot hold
    the motion along y, which the message says comes from the suite."""
    data = yaml.safe_load((REPO / "models" / "wu2021-eq14.yaml").read_text())
    scene = _write(tmp_path, "scene.yaml", data)
    t = np.arange(101) * 0.01
    for name in ("a.txt", "b.txt"):
        (tmp_path / name).write_text("".join(f"{a} {math.sin(8 * a)}\n" for a in t))
    (tmp_path / "pair.yaml").write_text(
        "records: [{x: a.txt, y: b.txt, angle: 10, units: m/s2}]\n")
    assert main(["gap", str(scene), "--suite", str(tmp_path / "pair.yaml"), "-q",
                 "--duration", "0.2"]) == 2
    said = capsys.readouterr().err
    assert "move the site's y axis" in said and "Traceback" not in said


def test_an_audit_never_writes_over_a_pairs_second_record(tmp_path, capsys):
    """The second record of a suite's pair is an input like the first: an audit told to
    write over it (even with --overwrite) is refused, and the record is untouched."""
    scene = _write(tmp_path, "scene.yaml", SCENE)
    t = np.arange(101) * 0.01
    for name in ("a.txt", "b.txt"):
        (tmp_path / name).write_text("".join(f"{a} {math.sin(8 * a)}\n" for a in t))
    (tmp_path / "pair.yaml").write_text("records: [{x: a.txt, y: b.txt, units: m/s2}]\n")
    assert main(["validate", str(tmp_path / "pair.yaml")]) == 0
    listed = capsys.readouterr().out
    assert "a.txt" in listed and "b.txt" in listed  # both of the pair's records are read
    before = (tmp_path / "b.txt").read_bytes()
    assert main(["gap", str(scene), "--suite", str(tmp_path / "pair.yaml"), "-q",
                 "--duration", "0.2", "-o", str(tmp_path / "b.txt"), "--overwrite"]) == 2
    assert "b.txt" in capsys.readouterr().err
    assert (tmp_path / "b.txt").read_bytes() == before
