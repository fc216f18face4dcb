"""Sweeps of a scene in plan (docs/sweeps.md#scenes-in-plan): each variant is written with its
nodes' x, y and rotation, its points' axes and its storeys' torsional irregularity, as
``pframe solve`` writes the same scene; variants over the eccentricity, the incidence, a
contact's points and a building's angle run as one batch and each gives its own run's bits."""

from __future__ import annotations

import json

import numpy as np
import pytest
import yaml

import pframe
from pframe.cli import main

#: an eccentric two-storey building A beside a symmetric B, corner contacts on the second
#: floor, two sine components at 30 degrees; 160 steps
PAIR = {
    "title": "a pair in plan",
    "buildings": [
        {"name": "A", "floors": 2, "mass": 1.0e5, "height": 3.0,
         "plan": {"size": [10.0, 6.0]}, "centre_of_mass": [6.0, 3.0],
         "lines": [
             {"name": "X1", "position": [0, 0], "direction": "x", "material": "elastic",
              "stiffness": 4.0e7},
             {"name": "X2", "position": [0, 6], "direction": "x", "material": "elastic",
              "stiffness": 4.0e7},
             {"name": "Y1", "position": [0, 0], "direction": "y", "material": "bilinear",
              "stiffness": 5.0e7, "yield_drift": 0.004, "alpha": 0.1},
             {"name": "Y2", "position": [10, 0], "direction": "y", "material": "elastic",
              "stiffness": 2.0e7}]},
        {"name": "B", "floors": 2, "mass": 1.2e5, "height": 3.0, "origin": [10.02, 0.0], "angle": 0.0,
         "plan": {"size": [8.0, 6.0]},
         "lines": [
             {"name": "X1", "position": [0, 0], "direction": "x", "material": "elastic",
              "stiffness": 8.0e7},
             {"name": "X2", "position": [0, 6], "direction": "x", "material": "elastic",
              "stiffness": 8.0e7},
             {"name": "Y1", "position": [0, 0], "direction": "y", "material": "elastic",
              "stiffness": 8.0e7},
             {"name": "Y2", "position": [8, 0], "direction": "y", "material": "elastic",
              "stiffness": 8.0e7}]}],
    "contacts": [
        {"name": "s2", "nodes": ["A/2", "B/2"], "points": [[10, 1.0], [0, 1.0]],
         "normal": [1, 0], "gap": 0.004, "law": "linear", "stiffness": 1.0e9},
        {"name": "n2", "nodes": ["A/2", "B/2"], "points": ["NE", "NW"], "normal": [1, 0],
         "gap": 0.004, "law": "linear", "stiffness": 1.0e9}],
    "damping": {"ratio": 0.05, "modes": [1, 3]},
    "excitation": {"kind": "components", "angle": 30,
                   "x": {"kind": "sine", "amplitude": 4.0, "frequency": 6.0, "cycles": 3},
                   "y": {"kind": "sine", "amplitude": 3.0, "frequency": 9.0, "cycles": 3}},
    "analysis": {"dt": 0.005, "duration": 0.8},
}

#: eccentricity, incidence, a contact's points and B's angle, zipped
AXES = [
    {"name": "eccentricity", "path": "buildings.A.centre_of_mass.0", "values": [5.0, 6.0, 7.5]},
    {"name": "incidence", "path": "excitation.angle", "values": [0.0, 30.0, 90.0]},
    {"name": "point_y", "path": "contacts.s2.points.0.1", "values": [0.0, 1.0, 2.5]},
    {"name": "b_angle", "path": "buildings.B.angle", "values": [0.0, -3.0, -6.0]},
]
CHUNK = 3
KEEP = ["peak_displacement", "peak_story_drift", "peak_contact_force", "impact_count",
        "peak_point_displacement", "peak_point_drift", "building_peak_displacement",
        "peak_absolute_acceleration"]


@pytest.fixture(scope="module")
def swept(tmp_path_factory):
    folder = tmp_path_factory.mktemp("plan-sweep")
    (folder / "pair.yaml").write_text(json.dumps(PAIR), encoding="utf-8")
    (folder / "sweep.yaml").write_text(yaml.safe_dump({
        "base": "pair.yaml", "axes": AXES, "combine": "zip",
        "keep": {"envelopes": KEEP, "histories": ["displacement", "ground_acceleration"]},
        "chunk": CHUNK}), encoding="utf-8")
    out = folder / "sweep.h5"
    assert main(["sweep", str(folder / "sweep.yaml"), "-o", str(out), "-q"]) == 0
    return folder, out


def _variant(folder, index: int) -> dict:
    data = json.loads(json.dumps(PAIR))
    for axis in AXES:
        keys = axis["path"].split(".")
        target = data
        for key in keys[:-1]:
            if isinstance(target, list):
                target = next(t for t in target if t["name"] == key) if not key.isdigit() \
                    else target[int(key)]
            else:
                target = target[key]
        target[int(keys[-1]) if keys[-1].isdigit() else keys[-1]] = axis["values"][index]
    data["recorders"] = [
        {"kind": "envelope", "quantities": ["displacement", "story_drift", "contact_force",
                                            "point_displacement", "point_drift",
                                            "absolute_acceleration"]},
        {"kind": "history", "quantities": ["displacement", "ground_acceleration"]}]
    return data


@pytest.mark.slow
def test_a_sweep_in_plan_holds_each_variants_single_run(swept):
    """Each variant of a zipped sweep over A's eccentricity, the incidence of two sine
    components, a contact's point and B's angle holds, bit for bit, what ``pframe.solve``
    writes for that variant alone: the centres of mass along x and y, the rotations, the
    points along their buildings' axes, the storeys' torsional irregularity, the contacts,
    and the histories; the building's peak is the largest of its centres along x or y."""
    folder, out = swept
    with pframe.open(out) as ds:
        assert ds.peak_displacement.dims == ("variant", "node", "direction")
        assert ds.peak_displacement_rz.dims == ("variant", "node")
        assert ds.peak_point_drift.dims == ("variant", "point", "axis")
        assert ds.torsional_irregularity.dims == ("variant", "node", "axis")
        assert ds.displacement.dims == ("variant", "t", "node", "direction")
        assert ds.displacement_rz.dims == ("variant", "t", "node")
        assert ds.ground_acceleration.dims == ("variant", "t", "direction")
        assert list(ds.direction_name.values) == ["x", "y"]
        assert (ds.complete == 1).all()
        for index in range(len(AXES[0]["values"])):
            path = folder / f"variant-{index}.yaml"
            path.write_text(json.dumps(_variant(folder, index)), encoding="utf-8")
            single = pframe.solve(path)
            row = ds.isel(variant=index)
            for name in ("peak_displacement", "peak_displacement_rz", "peak_story_drift",
                         "peak_contact_force", "impact_count", "peak_point_displacement",
                         "peak_point_drift", "torsional_irregularity",
                         "peak_absolute_acceleration", "peak_absolute_acceleration_rz",
                         "displacement", "displacement_rz", "ground_acceleration"):
                np.testing.assert_array_equal(row[name].values, single[name].values,
                                              err_msg=f"variant {index}: {name}")
            assert row.peak_displacement.dims[1:] == single.peak_displacement.dims[1:]
            for b, building in enumerate(("A", "B")):
                own = [i for i, n in enumerate(single.node_name.values)
                       if str(n).startswith(building + "/")]
                assert float(row.building_peak_displacement[b]) == float(
                    single.peak_displacement.values[own].max())
        # the variants differ: the incidence turns the motion, the eccentricity the floors
        assert not np.array_equal(ds.peak_displacement_rz.values[0],
                                  ds.peak_displacement_rz.values[2])


def test_a_planar_base_refuses_a_variant_that_moves_in_plan(tmp_path, capsys):
    """A base scene that neither moves in plan nor is written in plan (a generic node, both
    storeys through its centre of mass) has the planar layout; a variant whose storey stands
    off the centre (its floor then turns) cannot be written in it: refused before anything
    runs when the checks meet it (an axis's last value), not run with the reason when only
    its chunk does (a middle value), the planar variants beside it run."""
    base = {
        "nodes": [{"name": "A/1", "mass": 1.0e5, "polar_inertia": 2.0e6}],
        "stories": [
            {"name": "A/1/a", "nodes": ["ground", "A/1"], "position": [0.0, 0.0],
             "direction": "x", "material": "elastic", "stiffness": 4.0e7},
            {"name": "A/1/b", "nodes": ["ground", "A/1"], "position": [0.0, 0.0],
             "direction": "x", "material": "elastic", "stiffness": 4.0e7}],
        "damping": {"ratio": 0.05},
        "excitation": {"kind": "sine", "amplitude": 1.0, "frequency": 6.0, "cycles": 1},
        "analysis": {"dt": 0.01, "duration": 0.2},
    }
    (tmp_path / "base.yaml").write_text(json.dumps(base), encoding="utf-8")
    for values, name in (([0.0, 3.0], "last"), ([0.0, 3.0, 0.0], "middle")):
        (tmp_path / f"{name}.yaml").write_text(yaml.safe_dump({
            "base": "base.yaml",
            "axes": [{"name": "arm", "path": "stories.A/1/b.position.1", "values": values}]}),
            encoding="utf-8")
    out = tmp_path / "sweep.h5"
    assert main(["sweep", str(tmp_path / "last.yaml"), "-o", str(out), "-q"]) == 2
    said = capsys.readouterr().err
    assert "axis 'arm', variant 1" in said and "moves its floors in plan" in said
    assert "Traceback" not in said and not out.exists()
    main(["sweep", str(tmp_path / "middle.yaml"), "-o", str(out), "-q"])
    with pframe.open(out) as ds:
        assert ds.peak_displacement.dims == ("arm", "node")
        assert list(ds.complete.values) == [1, 0, 1]
        status = str(ds.status.values[1])
        assert "moves its floors in plan" in status and "planar layout" in status
        assert np.isnan(ds.peak_displacement.values[1]).all()
