"""Every misuse of the Python API raises :class:`pframe.InputError` (one message naming the
call, the argument or field, and what is expected), never pydantic's, YAML's, a TypeError or
an AttributeError: generated over every public function and every part of a scene, with
wrong types, None, wrong shapes and invalid values; ``model_copy(update=...)`` and assignment
included. And the messages speak Python: ``overwrite=True``, not ``--overwrite``."""

from __future__ import annotations

import gc
import inspect
import tempfile
import warnings
import weakref
from pathlib import Path

import numpy as np
import pytest
from conftest import assert_names

import pframe

ROOT = Path(__file__).resolve().parents[1]
TINY = {
    "buildings": [
        {"name": "A", "floors": 1, "mass": 1000.0, "story": {"material": "elastic",
                                                             "stiffness": 1.0e6}},
        {"name": "B", "floors": 1, "mass": 1000.0, "story": {"material": "elastic",
                                                             "stiffness": 2.0e6}}],
    "contacts": [{"nodes": ["A/1", "B/1"], "gap": 0.01, "law": "linear", "stiffness": 1.0e7}],
    "excitation": {"kind": "sine", "amplitude": 3.0, "frequency": 6.0},
    "analysis": {"dt": 0.01, "duration": 0.1},
    "recorders": [{"kind": "history", "quantities": ["displacement", "contact_force"]}],
}
#: wrong values of every kind: types, None, shapes, non-finite numbers, empty and NUL text
WRONG = [None, 0, -1, 2.5, float("nan"), float("inf"), True, "", "   ", "a\0b", b"bytes", [],
         [1.0, 2.0], {}, {"x": 1}, object(), np.float64(1.0), np.array([1.0, 2.0]),
         np.zeros((2, 2)), ("a",), {1, 2}, print, Path("/dev/null")]
#: the public functions, each with valid arguments (filled in by the fixture) and the ones to
#: replace; pframe.risk's arguments are the risk study's (tests/test_risk*.py)
FUNCTIONS = {
    "load": ["source", "base_dir"],
    "solve": ["scene", "output", "overwrite", "compress", "progress"],
    "sweep": ["definition", "output", "overwrite", "threads", "chunk", "progress"],
    "open": ["path"],
    "to_opensees": ["scene", "base_dir"],
    "summary": ["result", "output", "overwrite"],
    "impacts": ["result"],
    "modes": ["scene", "count", "base_dir"],
    "plot": ["result", "quantity", "names", "level", "kind", "units", "dimensionless",
             "time_range", "ax", "fig"],
}
CLASSES = [name for name in pframe.__all__ if name[0].isupper() and name not in (
    "AccuracyWarning", "EnvironmentFailure", "IncompleteRun", "InputError", "PframeError")]


def test_every_public_function_is_covered():
    public = {n for n in pframe.__all__ if callable(getattr(pframe, n)) and n[0].islower()}
    assert_names(public - {"risk"}, FUNCTIONS, "the public functions FUNCTIONS tries")
    for name, arguments in FUNCTIONS.items():
        signature = inspect.signature(getattr(pframe, name) if name not in ("sweep", "plot")
                                      else getattr(pframe, name).__call__)
        if name not in ("sweep", "plot"):  # made callable packages take *args, **kwargs
            assert_names(arguments, signature.parameters, f"the arguments of pframe.{name}")


@pytest.fixture(scope="module")
def valid(tmp_path_factory):
    """Valid arguments of each function: a tiny scene, its result, a sweep of it."""
    import yaml

    folder = tmp_path_factory.mktemp("misuse")
    (folder / "scene.yaml").write_text(yaml.safe_dump(TINY), encoding="utf-8")
    (folder / "sweep.yaml").write_text(
        "base: scene.yaml\naxes:\n  - {name: gap, path: contacts.*.gap, values: [0.01]}\n",
        encoding="utf-8")
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        ds = pframe.solve(folder / "scene.yaml", output=folder / "run.nc")
    scene = pframe.load(folder / "scene.yaml")
    return {
        "load": {"source": TINY},
        "solve": {"scene": scene},
        "sweep": {"definition": folder / "sweep.yaml"},
        "open": {"path": folder / "run.nc"},
        "to_opensees": {"scene": scene},
        "summary": {"result": ds},
        "impacts": {"result": ds},
        "modes": {"scene": scene},
        "plot": {"result": ds, "quantity": "displacement"},
        "folder": folder,
    }


def _cases():
    for name, arguments in FUNCTIONS.items():
        for argument in arguments:
            for i, value in enumerate(WRONG):
                yield pytest.param(name, argument, value, id=f"{name}-{argument}-{i}")


@pytest.mark.slow
@pytest.mark.parametrize("name, argument, value", list(_cases()))
def test_a_wrong_argument_is_an_input_error(valid, tmp_path, monkeypatch, name, argument,
                                            value):
    """Each argument of each function given each wrong value: InputError, or (a value that
    happens to be valid there: ``0`` levels, ``None`` defaults) an answer."""
    import matplotlib

    matplotlib.use("Agg")
    monkeypatch.chdir(tmp_path)  # an output given as a name lands here
    kwargs = dict(valid[name])
    kwargs[argument] = value
    first = next(iter(FUNCTIONS[name]))
    args = (kwargs.pop(first),)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        try:
            getattr(pframe, name)(*args, **kwargs)
        except pframe.InputError as exc:
            assert str(exc) and "\n" not in str(exc).strip()
        finally:
            import matplotlib.pyplot as plt

            plt.close("all")
    assert not (valid["folder"] / "print").exists()


def _field_cases():
    for cls in CLASSES:
        model = getattr(pframe, cls)
        fields = (list(model.model_fields) if hasattr(model, "model_fields")
                  else ["law", "nodes", "gap", "material", "stiffness"])
        for field in fields:
            for i, value in enumerate(WRONG):
                yield pytest.param(cls, field, value, id=f"{cls}-{field}-{i}")


@pytest.mark.slow  # each case takes milliseconds, the 3,000 of them seconds
@pytest.mark.parametrize("cls, field, value", list(_field_cases()))
def test_a_wrong_field_is_an_input_error(cls, field, value):
    """Every part of a scene built with each wrong value in each field (the others missing or
    given): InputError naming the part, or an object."""
    try:
        getattr(pframe, cls)(**{field: value})
    except pframe.InputError as exc:
        assert str(exc).startswith(f"pframe.{cls}") and "\n" not in str(exc)


@pytest.mark.parametrize("cls", CLASSES)
def test_positional_values_are_an_input_error(cls):
    with pytest.raises(pframe.InputError, match="by name"):
        getattr(pframe, cls)(1.0)


def _objects(value, path=()):
    """(path, object) of every part of a scene (the scene itself first)."""
    from pydantic import BaseModel

    if isinstance(value, BaseModel):
        yield path, value
        for name in type(value).model_fields:
            yield from _objects(getattr(value, name), path + (name,))
    elif isinstance(value, (list, tuple)):
        for i, item in enumerate(value):
            yield from _objects(item, path + (i,))


SCENES = sorted(p for p in (ROOT / "models").glob("*.yaml") if "-pi" not in p.name)


@pytest.mark.slow
@pytest.mark.parametrize("path", SCENES, ids=[p.stem for p in SCENES])
def test_model_copy_validates_every_field_of_every_part(path, tmp_path):
    """``model_copy(update={field: wrong})`` of every part of every example scene: an
    InputError naming the part and the field, or a copy that a scene using it is checked
    with on use (InputError again, or a valid scene); a copy with the same value is equal."""
    from conftest import runnable_model

    scene = pframe.load(runnable_model(path, tmp_path))
    for where, obj in _objects(scene):
        for field in type(obj).model_fields:
            same = obj.model_copy(update={field: getattr(obj, field)})
            assert same == obj, (where, field)
            for value in (None, -1, float("nan"), "text", True, [1.0, 2.0], object()):
                try:
                    copy = obj.model_copy(update={field: value})
                except pframe.InputError as exc:
                    assert f".model_copy(update={{'{field}': ...}})" in str(exc)
                    continue
                if obj is scene:
                    try:
                        pframe.load(copy)
                    except pframe.InputError:
                        pass


def test_assigning_a_field_says_how_to_copy():
    scene = pframe.load(TINY)
    for _, obj in _objects(scene):
        for field in type(obj).model_fields:
            with pytest.raises(pframe.InputError, match=r"model_copy\(update="):
                setattr(obj, field, getattr(obj, field))
            with pytest.raises(pframe.InputError, match="frozen"):
                delattr(obj, field)


def test_a_boolean_is_not_taken_for_a_number():
    """pydantic reads True as 1.0: a gap=True would be a 1 m gap."""
    with pytest.raises(pframe.InputError, match="gap: expected a number, got the boolean True"):
        pframe.Contact(law="linear", nodes=("A/1", "B/1"), gap=True, stiffness=1e7)
    scene = pframe.load(TINY)
    with pytest.raises(pframe.InputError, match="dt: expected a number, got the boolean"):
        scene.analysis.model_copy(update={"dt": True})
    with pytest.raises(pframe.InputError, match="mass: expected a number"):
        pframe.Node(name="A/1", mass=True)


def test_a_copy_checks_its_values_and_names_the_field():
    scene = pframe.load(TINY)
    with pytest.raises(pframe.InputError, match=r"pframe\.Scene\.model_copy\(update=\{'analysis"
                       r"': \.\.\.\}\): analysis: .*got 5"):
        scene.model_copy(update={"analysis": 5})
    with pytest.raises(pframe.InputError, match="Scene has no field 'analysys'"):
        scene.model_copy(update={"analysys": scene.analysis})
    copy = scene.model_copy(update={"analysis": {"dt": np.float64(0.005), "duration": 0.1}})
    assert copy.analysis == pframe.Analysis(dt=0.005, duration=0.1)  # validated, a float


def test_a_dict_with_numpy_numbers_is_a_scene():
    """pframe.load(dict) with numpy values (numbers, arrays) reads them as numbers and lists;
    another object names its key."""
    data = {**TINY, "analysis": {"dt": np.float64(0.01), "duration": np.float32(0.1)},
            "buildings": [{**TINY["buildings"][0], "mass": np.array([1000.0])},
                          TINY["buildings"][1]]}
    assert pframe.load(data) == pframe.load({**TINY, "buildings": [
        {**TINY["buildings"][0], "mass": [1000.0]}, TINY["buildings"][1]],
        "analysis": {"dt": 0.01, "duration": float(np.float32(0.1))}})
    bad = {**TINY, "analysis": {"dt": 0.01, "duration": {0.1}}}
    with pytest.raises(pframe.InputError, match=r"pframe\.load\(dict\): analysis\.duration is "
                       r"a set"):
        pframe.load(bad)


def test_messages_name_the_python_keywords(valid):
    folder = valid["folder"]
    with pytest.raises(pframe.InputError) as info:
        pframe.solve(valid["solve"]["scene"], output=folder / "run.nc")
    message = str(info.value)
    assert "overwrite=True" in message and "output=" in message
    assert "--overwrite" not in message and "-o" not in message.split()
    with pytest.raises(pframe.InputError) as info:
        pframe.summary(valid["summary"]["result"], output=folder / "scene.yaml.md",
                       overwrite=False) if (folder / "scene.yaml.md").write_text("x") else None
    assert "overwrite=True" in str(info.value)
    assert (folder / "scene.yaml.md").read_text() == "x"


def test_loading_a_result_leaves_one_folder_and_keeps_no_scene(tmp_path):
    """pframe.load of a result restores its record once per process (not a folder per call),
    and a scene nobody holds goes (its origin kept no reference to it)."""
    t = np.arange(0.0, 0.5, 0.01)
    np.savetxt(tmp_path / "rec.txt", np.column_stack([t, 3.0 * np.sin(6.0 * t)]))
    scene = {**TINY, "excitation": {"kind": "record", "file": "rec.txt"}}
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        pframe.solve(pframe.load(scene, base_dir=tmp_path), output=tmp_path / "r.nc")
    (tmp_path / "rec.txt").unlink()  # the result alone holds the record
    before = set(Path(tempfile.gettempdir()).glob("pframe-record-*"))
    refs = []
    for _ in range(5):
        loaded = pframe.load(tmp_path / "r.nc")
        copy = loaded.model_copy(update={"title": "a copy"})
        refs.append(weakref.ref(loaded))
        pframe.load(copy)  # a copy finds the record after the scene it came from is gone
        del loaded
    gc.collect()
    assert all(ref() is None for ref in refs)
    assert len(set(Path(tempfile.gettempdir()).glob("pframe-record-*")) - before) <= 1


def test_an_unchecked_object_is_checked_on_use():
    """model_construct skips validation (pydantic's): a scene built with it is checked when
    used, a value no scene holds named by its key, not YAML's representer error."""
    with pytest.raises(pframe.InputError, match=r"pframe\.Scene: analysis is an object"):
        pframe.load(pframe.Scene.model_construct(analysis=object()))
    with pytest.raises(pframe.InputError, match=r"title: Input should be a valid string"):
        pframe.load(pframe.Scene.model_construct(**{**pframe.load(TINY).__dict__, "title": 5}))
