"""Risk studies of a scene in plan (docs/risk.md#scenes-in-plan): the demand on the gap is the
closing of each contact's points along its normal, as in the gap audit; stochastic motions
come in two components; the demands per building are the scene's own run's under the same
motion."""

from __future__ import annotations

import copy
import json

import numpy as np
import pytest
import yaml
from test_plan_gap import SCENE

import pframe
from pframe.cli import main
from pframe.gap import audit
from pframe.risk import risk
from pframe.risk.study import open_study

PARAMETERS = {"d595": 3.0, "tmid": 2.0, "frequency": 4.0, "slope": -0.1, "damping": 0.3}
PAIR = {"x": {"model": "rezaeian2010", "parameters": {"arias": 0.5, **PARAMETERS}},
        "y": {"model": "rezaeian2010", "parameters": {"arias": 0.3, **PARAMETERS}},
        "angle": 30}
LEVELS = [0.2, 0.4]


def _study(folder, **more) -> dict:
    (folder / "scene.yaml").write_text(json.dumps(SCENE), encoding="utf-8")
    study = {"scene": "scene.yaml", "measure": "pga",
             "stochastic": {**PAIR, "realisations": 2, "seed": 5},
             "design": {"kind": "msa", "levels": LEVELS}, "duration": 4.0,
             "limits": {"drift": {"IO": 0.01}, "acceleration": {"A": 0.5}}, "bootstrap": 0}
    study.update(more)
    (folder / "study.yaml").write_text(yaml.safe_dump(study), encoding="utf-8")
    return study


@pytest.mark.slow
def test_a_study_in_plan_takes_the_points_closing_and_its_runs_demands(tmp_path):
    """Under stochastic pairs at 30 degrees (two seeds a motion), the study's critical gap of
    each contact is the gap audit's simulated gap under the same pairs (the closing of its
    points along its normal), and its demands without pounding, per building, are those of
    the scene run alone without contacts under the same motion: the largest storey drift
    of its lines and the largest absolute acceleration of its centres along x or y."""
    _study(tmp_path)
    ds = risk(tmp_path / "study.yaml")
    assert list(ds.record_name.values) == [
        "rezaeian2010-seed5+rezaeian2010-seed6@30", "rezaeian2010-seed7+rezaeian2010-seed8@30"]
    (tmp_path / "suite.yaml").write_text(yaml.safe_dump({"stochastic": [
        {**PAIR, "seeds": [[5, 6], [7, 8]]}], "measure": {"kind": "pga"},
        "levels": LEVELS}), encoding="utf-8")
    gaps = audit(tmp_path / "scene.yaml", tmp_path / "suite.yaml", duration=4.0)
    np.testing.assert_array_equal(
        ds.critical_gap.values,
        gaps.gap_required.sel(rule_name="simulated").values)
    assert float(ds.critical_gap.max()) > 0.0

    inputs = open_study(tmp_path / "study.yaml").inputs
    assert inputs.channels == ("x", "y")
    ground = inputs.accelerations([3])[0]  # record 1 at level 0.4 g, along the site's axes
    times = np.arange(inputs.steps + 1) * inputs.dt
    for axis, row in zip("xy", ground):
        (tmp_path / f"{axis}.txt").write_text("".join(
            f"{float(t)!r} {float(v)!r}\n" for t, v in zip(times, row)), encoding="utf-8")
    alone = copy.deepcopy(SCENE)
    alone["contacts"] = []
    alone["excitation"] = {"kind": "components", "angle": 0,
                           "x": {"kind": "record", "file": "x.txt", "units": "m/s2"},
                           "y": {"kind": "record", "file": "y.txt", "units": "m/s2"}}
    alone["analysis"]["duration"] = inputs.steps * inputs.dt
    alone["recorders"] = [{"kind": "envelope", "quantities": [
        "displacement", "story_drift", "absolute_acceleration"]}]
    (tmp_path / "alone.yaml").write_text(json.dumps(alone), encoding="utf-8")
    run = pframe.solve(tmp_path / "alone.yaml")
    free = ds.sel(condition_name="without_pounding").isel(record=1, level=1)
    for b, building in enumerate(("A", "B")):
        nodes = [i for i, n in enumerate(run.node_name.values)
                 if str(n).startswith(f"{building}/")]
        storeys = [i for i, n in enumerate(run.story_name.values)
                   if str(n).startswith(f"{building}/")]
        assert float(free.peak_floor_acceleration[b]) * 9.80665 == pytest.approx(
            float(run.peak_absolute_acceleration.values[nodes].max()), rel=1e-12)
        assert float(free.peak_story_drift[b]) == float(run.peak_story_drift.values[storeys].max())


def test_a_single_stochastic_component_under_two_is_refused(tmp_path, capsys):
    """A stochastic motion without a direction under a scene shaken in two components is
    refused before anything runs, saying how to write it."""
    _study(tmp_path, stochastic={"model": "rezaeian2010",
                                 "parameters": {"arias": 0.5, **PARAMETERS},
                                 "realisations": 2})
    assert main(["risk", str(tmp_path / "study.yaml"), "-o", str(tmp_path / "r.nc")]) == 2
    said = capsys.readouterr().err
    assert "shaken in two components" in said and "angle" in said
    assert not (tmp_path / "r.nc").exists() and "Traceback" not in said


def test_a_stationary_motion_of_a_subset_design_stands_at_its_angle():
    """The subset design's stationary motion along an angle loads the site's x and y by the
    cosine and sine of it, one white noise for both."""
    from pframe.reader import parse_scene
    from pframe.risk.uncertain import SubsetProblem

    loaded = parse_scene(json.dumps(SCENE))
    motion = {"model": "clough_penzien", "intensity": 0.01, "ground_frequency": 15.0,
              "ground_damping": 0.6, "duration": 1.0, "angle": 30.0}
    problem = SubsetProblem(loaded, [], motion, 200, 0.005, channels=("x", "y"))
    u = np.random.default_rng(3).standard_normal((2, problem.dim))
    a = problem.accelerations(u)
    along = SubsetProblem(loaded, [], {**motion, "angle": 0.0}, 200, 0.005).accelerations(u)
    assert a.shape == (2, 2, 201) and along.shape == (2, 1, 201)
    np.testing.assert_allclose(a[:, 0], np.cos(np.radians(30)) * along[:, 0], rtol=1e-14)
    np.testing.assert_allclose(a[:, 1], np.sin(np.radians(30)) * along[:, 0], rtol=1e-14)


def test_members_of_their_own_geometry_close_at_their_own_points():
    """Uncertain values that move a building's centre of mass (a risk study's members) move
    its contacts' arms: each member of a batch closes at its own points, as it does run
    alone."""
    from pframe.gap.runs import contact_pairs
    from pframe.reader import parse_scene
    from pframe.risk.runs import run_batch

    members = []
    for x in (5.0, 7.5):
        scene = copy.deepcopy(SCENE)
        scene["buildings"][0]["centre_of_mass"] = [x, 3.0]
        scene["analysis"]["duration"] = 0.6
        members.append(parse_scene(json.dumps(scene)))
    steps, dt = 120, 0.005
    t = np.arange(steps + 1) * dt
    ground = np.array([[3.0 * np.sin(6.0 * t), 2.0 * np.sin(9.0 * t)]] * 2)
    both = run_batch(members, contact_pairs(members[0]), ground, steps, dt, contacts=False)
    for b, member in enumerate(members):
        alone = run_batch([member], contact_pairs(member), ground[b:b + 1], steps, dt,
                          contacts=False)
        for key in ("g_req", "peak_left", "peak_right"):
            np.testing.assert_array_equal(both[key][b], alone[key][0], err_msg=key)
    assert not np.array_equal(both["g_req"][0], both["g_req"][1])
