"""``pframe scale`` knows the dimension of every number a scene may hold (generated from the
scene model: every numeric field outside the laws' parameters, which the laws declare), so a
scene with storey heights, P-delta loads, Park-Ang drifts or floor-to-column contacts scales;
what it cannot scale is refused naming the file, the line and the field. The scaled scene is
the similar one."""

from __future__ import annotations

import typing

import numpy as np
import pytest
import yaml
from pydantic import BaseModel

from pframe.cli import main
from pframe.model.scene import scene_class
from pframe.model.tagged import unfold
from pframe.nondim.fields import scene_field_dimension

#: fields whose numbers pframe scale does not take through SCENE_FIELDS: the laws' parameters
#: (declared by each law), soil (refused: docs/soil.md) and a stochastic motion (refused unless
#: S_T = S_a = 1), and recorders (kept as they are)
BY_LAWS = ("story", "stories", "contacts", "links")
ELSEWHERE = ("soil", "recorders")


def _numeric(annotation) -> bool:
    if annotation in (int, float):
        return True
    return any(_numeric(a) for a in typing.get_args(unfold(annotation)))


def _models(annotation) -> list:
    if isinstance(annotation, type) and issubclass(annotation, BaseModel):
        return [annotation]
    return [m for a in typing.get_args(unfold(annotation)) for m in _models(a)]


def _numeric_paths(cls, path=(), out=None):
    """Every path to a number in a scene's data, with 0 for a list index and 'A/1' for a
    mapping key (initial conditions by node)."""
    out = [] if out is None else out
    for name, field in cls.model_fields.items():
        here = path + (name,)
        annotation = field.annotation
        listed = "list" in str(annotation) or "dict" in str(annotation)
        if _numeric(annotation) and (cls.__module__ == "pframe.model.scene" or path[:1] not in
                                     [(k,) for k in BY_LAWS]):
            out.append(here + (("A/1",) if "dict" in str(annotation) else ()))
        for model in _models(annotation):
            if name in ELSEWHERE or model.__name__ == "Stochastic":
                continue
            _numeric_paths(model, here + ((0,) if listed else ()), out)
    return out


def _is_law_parameter(path) -> bool:
    from pframe.laws.registry import builtin_laws

    params = {f for kind in ("contact", "material") for law in builtin_laws(kind)
              for f in law.Params.model_fields}
    scene_fields = {"nodes", "name", "height", "gravity_load", "park_ang", "gap", "column",
                    "at", "shear_capacity", "position", "direction", "storeys", "points",
                    "normal"}
    inside = path[0] in ("stories", "contacts", "links") or path[2:3] in (("story",), ("lines",))
    return inside and path[-1] in params and path[-1] not in scene_fields \
        and "park_ang" not in path


def test_every_number_of_a_scene_has_a_dimension():
    paths = _numeric_paths(scene_class())
    assert ("buildings", 0, "height") in paths  # the walk reaches the fields that matter
    missing = [p for p in paths if not _is_law_parameter(p) and scene_field_dimension(p) is None]
    assert not missing, missing


SCENE = {
    "buildings": [
        {"name": "A", "floors": 2, "mass": 1000.0, "height": 3.0, "p_delta": True,
         "story": {"material": "bilinear", "stiffness": 1.0e6, "yield_drift": 0.02,
                   "alpha": 0.1},
         "park_ang": {"ultimate_drift": 0.1, "beta": 0.05}},
        {"name": "B", "floors": 2, "mass": 1000.0, "height": [3.5, 3.0],
         "story": {"material": "elastic", "stiffness": 2.0e6}}],
    "nodes": [{"name": "C/1", "mass": 500.0}],
    "stories": [{"nodes": ["ground", "C/1"], "material": "elastic", "stiffness": 1.0e6,
                 "height": 7.0, "gravity_load": 1000.0,
                 "park_ang": {"ultimate_drift": 0.1, "beta": 0.05}}],
    "contacts": [
        {"nodes": ["A/2", "B/2"], "gap": 0.01, "law": "linear", "stiffness": 1.0e7},
        {"nodes": ["B/1", "C/1"], "gap": 0.01, "law": "linear", "stiffness": 1.0e7,
         "column": "right", "at": 0.5, "shear_capacity": 1.0e5}],
    "excitation": {"kind": "sine", "amplitude": 3.0, "frequency": 6.0},
    "analysis": {"dt": 0.001, "duration": 0.2},
}


@pytest.mark.slow
def test_a_scene_with_heights_scales_to_the_similar_scene(tmp_path, capsys):
    """S_L = 1/16, S_E = 1, S_a = 1: S_T = 1/4, S_F = 1/256. Heights, drifts and gaps x 1/16,
    forces x 1/256, the fraction 'at' and beta kept."""
    from pframe.reader import load_scene

    (tmp_path / "scene.yaml").write_text(yaml.safe_dump(SCENE), encoding="utf-8")
    assert main(["scale", str(tmp_path / "scene.yaml"), "--length", "1/16", "--modulus", "1",
                 "--acceleration", "1", "-o", str(tmp_path / "model.yaml")]) == 0
    scaled = yaml.safe_load((tmp_path / "model.yaml").read_text(encoding="utf-8"))
    a, b = scaled["buildings"]
    assert a["height"] == 3.0 / 16 and b["height"] == [3.5 / 16, 3.0 / 16]
    assert a["park_ang"] == {"ultimate_drift": 0.1 / 16, "beta": 0.05}
    column = scaled["stories"][0]
    assert column["height"] == 7.0 / 16 and column["gravity_load"] == 1000.0 / 256
    struck = scaled["contacts"][1]
    assert struck["at"] == 0.5 and struck["shear_capacity"] == 1.0e5 / 256
    prototype = load_scene(tmp_path / "scene.yaml").expanded
    model = load_scene(tmp_path / "model.yaml").expanded
    assert np.allclose(model.story_height, prototype.story_height / 16, rtol=1e-15)
    assert np.allclose(model.story_gravity, prototype.story_gravity / 256, rtol=1e-12)
    capsys.readouterr()


def test_a_value_it_cannot_scale_names_the_file_line_and_field(tmp_path, capsys):
    scene = {**SCENE, "links": [{"nodes": ["A/1", "B/1"], "material": "viscous",
                                 "damping": 100.0, "exponent": 0.5}]}
    (tmp_path / "scene.yaml").write_text(yaml.safe_dump(scene), encoding="utf-8")
    assert main(["scale", str(tmp_path / "scene.yaml"), "--length", "1/16", "--modulus", "1",
                 "--acceleration", "1"]) == 2
    err = capsys.readouterr().err
    assert err.startswith(f"pframe: {tmp_path / 'scene.yaml'}, line ")
    assert "links[0].damping: cannot scale this value" in err and "Traceback" not in err


def test_a_stochastic_motion_is_kept_only_at_its_own_time_and_acceleration(tmp_path, capsys):
    scene = {**SCENE, "excitation": {"kind": "stochastic", "model": "clough_penzien",
                                     "intensity": 0.01, "ground_frequency": 15.0,
                                     "ground_damping": 0.6, "duration": 1.0}}
    (tmp_path / "scene.yaml").write_text(yaml.safe_dump(scene), encoding="utf-8")
    assert main(["scale", str(tmp_path / "scene.yaml"), "--length", "1/16", "--modulus", "1",
                 "--acceleration", "1"]) == 2
    assert "write the motion as a record file" in capsys.readouterr().err
    assert main(["scale", str(tmp_path / "scene.yaml"), "--length", "1", "--time", "1",
                 "--mass", "1/2", "-o", str(tmp_path / "half.yaml")]) == 0
    half = yaml.safe_load((tmp_path / "half.yaml").read_text(encoding="utf-8"))
    assert half["excitation"] == scene["excitation"]
    assert half["buildings"][0]["mass"] == 500.0
