"""The scene's tagged unions (a contact's law, a storey's material, a motion's kind, an
integrator's type...), validated by the one model their tag names (pframe.model.tagged):
the same objects and the same messages as pydantic's own union, and a scene's validator that
holds only the models its unions are asked for."""

from __future__ import annotations

import typing

import pytest
from conftest import REPO
from pydantic import BaseModel, TypeAdapter, ValidationError

from pframe.model.scene import Node, scene_class
from pframe.model.tagged import LazyUnion

TAGS = ("law", "material", "kind", "type")


def _unions(model: type[BaseModel], made: bool = True) -> dict[str, LazyUnion]:
    """Every tagged union reachable from ``model``, by where it was first found; through the
    members of a union made on demand too (``made``: they are unfolded, as every reader does;
    else only those of the unions made whole)."""
    from pframe.model.tagged import unfold

    found: dict[str, LazyUnion] = {}
    seen: set = set()

    def visit(annotation, where: str):
        if made:
            annotation = unfold(annotation)
        if isinstance(annotation, LazyUnion):
            found.setdefault(where, annotation)
            return
        if isinstance(annotation, type) and issubclass(annotation, BaseModel):
            if annotation in seen:
                return
            seen.add(annotation)
            for name, info in annotation.model_fields.items():
                for item in (info.annotation, *info.metadata):
                    visit(item, f"{annotation.__name__}.{name}")
            return
        for arg in typing.get_args(annotation):
            visit(arg, where)

    visit(model, model.__name__)
    return found


UNIONS = _unions(scene_class())


def _key(union: LazyUnion) -> str:
    """The field that holds the tag."""
    tag = next(iter(union.members))
    return next(k for k in TAGS if union.tag({k: tag}) == tag)


def _values(union: LazyUnion) -> list:
    """Values a union must judge as pydantic's would: no tag, an unknown tag, a tag of
    another type, each model with fields missing, an unknown field, a wrong type; objects."""
    key = _key(union)
    values = [None, "text", 3, [1, 2], {}, {key: "no_such"}, {key: ["a"]}, {key: 1},
              Node.model_construct(name="A/1", mass=1.0)]
    for tag, model in union.members.items():
        values += [{key: tag}, {key: tag, "no_such_field": 1.0},
                   {key: tag, **{name: "text" for name in model.model_fields if name != key}},
                   model.model_construct()]
    return values


def _outcome(adapter: TypeAdapter, value):
    try:
        return adapter.validate_python(value)
    except ValidationError as exc:
        return exc.errors(include_url=False, include_context=False)
    except AttributeError as exc:  # a model's own check of an object built without its fields
        return repr(exc)


def test_the_scene_has_its_tagged_unions():
    """Contacts, storeys, lines, links, motions, damping, integrators, recorders."""
    tags = {tag for union in UNIONS.values() for tag in union.members}
    assert {"linear", "hertz", "bilinear", "record", "sine", "newmark", "rayleigh", "modal",
            "history", "envelope", "components", "jennings"} <= tags
    assert len(UNIONS) >= 10


@pytest.mark.parametrize("where", sorted(UNIONS))
def test_a_tagged_union_judges_every_value_as_pydantic_s_union(where):
    union = UNIONS[where]
    lazy = TypeAdapter(typing.Annotated[typing.Union[tuple(union.members.values())],  # noqa: UP007
                                        union])
    eager = TypeAdapter(union.union)
    for value in _values(union):
        assert _outcome(lazy, value) == _outcome(eager, value), value


def test_a_valid_value_is_the_object_pydantic_s_union_makes():
    union = UNIONS["Scene.contacts"]
    lazy = TypeAdapter(typing.Annotated[typing.Union[tuple(union.members.values())],  # noqa: UP007
                                        union])
    data = {"law": "linear", "nodes": ["A/1", "B/1"], "gap": 0.01, "stiffness": 1e7}
    made = lazy.validate_python(data)
    assert type(made).__name__ == "Contact_linear"
    assert made == TypeAdapter(union.union).validate_python(data)
    assert made.model_fields_set == set(data)
    assert lazy.validate_python(made) is made  # an object of the model is taken as it is


def test_the_scene_validator_holds_no_model_of_a_union():
    """The scene's own validator dispatches on the tag: it does not hold every law's model
    (their validators are built when a scene uses them)."""
    schema = repr(scene_class().__pydantic_core_schema__)
    for name in ("Contact_hertz", "Story_bwbn", "Line_imk_peak", "Stochastic", "HHT"):
        assert f"'{name}'" not in schema and f".{name}:" not in schema


# ---------------------------------------------------------------------------------------------
# the laws' models, made when a scene names a law
# ---------------------------------------------------------------------------------------------

LAW_FIELDS = {"Scene.contacts": "law", "Scene.stories": "material", "Scene.links": "material",
              "Building.story": "material", "Building.lines": "material"}


def test_each_law_s_model_is_made_when_a_scene_first_names_it():
    """A scene of bilinear storeys and linear contacts makes those two laws' models and no
    other; its objects are those models', as pydantic's union of them all makes them."""
    from pframe.model.scene import _scene_class

    fresh = _scene_class.__wrapped__((), ())  # a class of its own, not the cached one
    unions = _unions(fresh, made=False)
    assert set(LAW_FIELDS) <= set(unions)
    assert all(not unions[where]._made for where in LAW_FIELDS)
    data = {"buildings": [{"name": "A", "floors": 1, "mass": 1e5,
                           "story": {"material": "bilinear", "stiffness": 1e7,
                                     "yield_drift": 0.01, "alpha": 0.1}},
                          {"name": "B", "floors": 1, "mass": 1e5,
                           "story": {"material": "elastic", "stiffness": 2e7}}],
            "contacts": [{"law": "linear", "nodes": ["A/1", "B/1"], "gap": 0.01,
                          "stiffness": 1e8}],
            "analysis": {"dt": 0.01, "duration": 0.1}}
    scene = fresh.model_validate(data)
    made = {where: sorted(unions[where]._made) for where in LAW_FIELDS}
    assert made == {"Scene.contacts": ["linear"], "Scene.stories": [], "Scene.links": [],
                    "Building.story": ["bilinear", "elastic"], "Building.lines": []}
    eager = TypeAdapter(unions["Scene.contacts"].union)  # every law's model made now
    assert scene.contacts[0] == eager.validate_python(data["contacts"][0])
    assert type(scene.contacts[0]) is unions["Scene.contacts"].member("linear")


def test_unfold_gives_a_lazy_union_s_every_member():
    from pframe.laws.registry import builtin_names
    from pframe.model.tagged import unfold

    scene = scene_class()
    annotation = typing.get_args(scene.model_fields["contacts"].annotation)[0]
    assert typing.get_args(annotation)[0].__name__ == "ContactBase"  # folded
    choices = typing.get_args(typing.get_args(unfold(annotation))[0])
    assert [model.__name__ for model in choices] == [
        f"Contact_{name}" for name in builtin_names("contact")]
    assert unfold(int) is int and unfold(annotation) is not annotation


def test_threads_asking_for_a_member_at_once_get_one_model():
    """A member is made once, however many threads validate at once (each make here takes
    long enough for every thread to ask before the first one is done)."""
    import time
    from concurrent.futures import ThreadPoolExecutor

    from pframe.model.tagged import on_demand, unfold

    def make(tag):
        time.sleep(0.05)
        return type(f"Model_{tag}", (BaseModel,), {"__annotations__": {"kind": str}})

    union = typing.get_args(unfold(on_demand(("a", "b"), make, "kind", BaseModel)))[1]
    union._made.clear()  # unfold made them: start again
    with ThreadPoolExecutor(8) as pool:
        made = list(pool.map(lambda _: union.member("a"), range(8)))
    assert all(model is made[0] for model in made)


def test_a_scene_ships_by_value_as_dask_sends_it_to_workers():
    """Dask sends a study's scene to its workers with cloudpickle, which carries the scene's
    classes (made per set of laws, not importable by name) by value. A law's storey model
    cached inside the class's factory could not be carried, and a study on Dask stopped
    before its first run; the scene now arrives equal to itself, and validates there."""
    import pickle

    import cloudpickle

    from pframe.reader import load_scene

    loaded = load_scene(str(REPO / "models" / "wu2021-pulse.yaml"))
    arrived = pickle.loads(cloudpickle.dumps(loaded))
    assert arrived.scene == loaded.scene
    again = type(arrived.scene).model_validate(arrived.scene.model_dump())
    assert again == loaded.scene


def test_a_model_made_on_demand_validates_and_describes_itself_as_the_model():
    """A field made by lazy_model makes its model at the first value, and judges every value
    as the field of the model itself does: the same objects, the same errors (type, place,
    message), the same JSON Schema."""
    from pydantic import ConfigDict, Field, ValidationError

    from pframe.model.tagged import lazy_model, unfold

    made = []

    class Inner(BaseModel):
        model_config = ConfigDict(extra="forbid", defer_build=True)
        a: float = Field(gt=0)
        b: int = 1

    def make():
        made.append(Inner)
        return Inner

    lazy = lazy_model(make, BaseModel)

    class Lazy(BaseModel):
        one: lazy | None = Field(None, description="one")
        many: list[lazy] = []

    class Eager(BaseModel):
        one: Inner | None = Field(None, description="one")
        many: list[Inner] = []

    assert not made  # the class is built, its field's model is not
    values = [{}, {"one": {"a": 1.0}}, {"one": {"a": -1, "c": 2}}, {"one": 3},
              {"many": [{"a": 2.0, "b": 3}, {"a": "x", "b": "y"}]}, {"many": [Inner(a=1.0)]}]
    for value in values:
        outcomes = []
        for model in (Lazy, Eager):
            try:
                outcomes.append(model.model_validate(value).model_dump())
            except ValidationError as exc:
                outcomes.append(exc.errors(include_url=False))
        assert outcomes[0] == outcomes[1], value
    assert made == [Inner]  # made once
    schemas = [m.model_json_schema() for m in (Lazy, Eager)]
    assert schemas[0] == {**schemas[1], "title": "Lazy"}
    assert typing.get_args(unfold(lazy))[0] is Inner
