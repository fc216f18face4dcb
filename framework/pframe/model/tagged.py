"""Tagged unions of models (a contact's ``law``, a storey's ``material``, a motion's
``kind``...) validated by the one model their tag names, that model's validator built on
first use.

Pydantic builds a model's validator whole: every branch of every union it holds, so a scene
paid for the validators of all 16 laws, 5 motions and 6 integrators (about 50 ms, a tenth of
a whole ``pframe solve``) to read a file that uses three of them. A union made by
:func:`tagged` is validated instead by a plain function that reads the tag and hands the
value to the validator of the model it names, which pydantic builds when first asked
(``defer_build``). The result is the same object the union gives, and so is everything
else, because what the function cannot settle it leaves to pydantic's own union (built then,
once): a value without a known tag, a value of another type, and a value its model refuses
(pydantic's error, whose location holds the tag, is the union's, word for word). The JSON
Schema is the union's as well.
"""

from __future__ import annotations

import threading
from collections.abc import Callable
from typing import Annotated, Union, get_args, get_origin

from pydantic import Discriminator, Field, Tag, TypeAdapter, ValidationError
from pydantic_core import core_schema

#: held while a union's member is made (a model made once, its law's module imported once)
_MAKING = threading.RLock()


class LazyUnion:
    """Pydantic metadata of ``Annotated[Union[...], LazyUnion(...)]``: the union validated
    by the model its tag names (see the module's docstring).

    ``tag`` reads the tag of a value (a dict or a model object; None if it has none);
    ``discriminator`` is pydantic's (a field name, or ``tag`` itself when the members are
    given by tag). ``members`` maps each tag to its model; with ``make``, ``members`` is a
    tuple of tags and ``make(tag)`` builds a tag's model when it is first asked for
    (:func:`on_demand`)."""

    def __init__(self, tag: Callable, members, discriminator, make: Callable | None = None):
        self.tag, self.discriminator = tag, discriminator
        self._make = make
        self._made: dict[str, type] = {} if make is not None else dict(members)
        self._names = tuple(members)
        self._adapter: TypeAdapter | None = None

    def member(self, tag: str) -> type | None:
        """The model of ``tag`` (built on first need), None for a tag of no member."""
        model = self._made.get(tag)
        if model is None and self._make is not None and tag in self._names:
            with _MAKING:  # one model per tag, also when threads validate scenes at once
                model = self._made.get(tag)
                if model is None:
                    model = self._made[tag] = self._make(tag)
        return model

    @property
    def members(self) -> dict[str, type]:
        """Tag -> model, every member (all built)."""
        return {name: self.member(name) for name in self._names}

    @property
    def choices(self):
        """``Union[...]`` of the members' models (with their tags when read by a function)."""
        if isinstance(self.discriminator, str):
            return Union[tuple(dict.fromkeys(self.members.values()))]  # noqa: UP007
        return Union[tuple(Annotated[model, Tag(name)]  # noqa: UP007
                           for name, model in self.members.items())]

    @property
    def union(self):
        """The tagged union as pydantic would validate it."""
        if isinstance(self.discriminator, str):
            return Annotated[self.choices, Field(discriminator=self.discriminator)]
        return Annotated[self.choices, Discriminator(self.discriminator)]

    def adapter(self) -> TypeAdapter:
        """Pydantic's own validator of the whole union (built on first need)."""
        if self._adapter is None:
            self._adapter = TypeAdapter(self.union)
        return self._adapter

    def validate(self, value):
        tag = self.tag(value)
        member = self.member(tag) if isinstance(tag, str) else None
        # a dict (YAML data, keywords) or an object of the model itself; anything else (a
        # subclass, a mapping of another type) is pydantic's to judge
        if member is not None and (type(value) is dict or type(value) is member):
            try:
                return member.__pydantic_validator__.validate_python(value)
            except ValidationError:
                pass  # the union's own message, below (its location names the tag)
        return self.adapter().validate_python(value)

    def __get_pydantic_core_schema__(self, source, handler):
        # the union's own schema (handler) is never built: that is the point
        return core_schema.no_info_plain_validator_function(self.validate)

    def __get_pydantic_json_schema__(self, schema, handler):
        return handler(self.adapter().core_schema)

    def __repr__(self) -> str:
        return f"LazyUnion({', '.join(self._names)})"


class LazyModel:
    """Pydantic metadata of ``Annotated[base, LazyModel(make)]``: a field of the model that
    ``make()`` returns, made (and its module imported) when a value of the field is first
    validated, for the parts of a scene that most scenes leave out (soil, limits). The value
    is validated by that model's own validator, whose errors are the nested model's, word
    for word; the JSON Schema is the model's. A reader of the fields calls :func:`unfold`."""

    def __init__(self, make: Callable):
        self._make = make
        self._model: type | None = None

    @property
    def model(self) -> type:
        """The model (made on first need)."""
        if self._model is None:
            with _MAKING:
                if self._model is None:
                    self._model = self._make()
        return self._model

    def validate(self, value, _handler=None):
        return self.model.__pydantic_validator__.validate_python(value)

    def __get_pydantic_core_schema__(self, source, handler):
        # a wrap validator that never calls the schema it wraps: that schema (anything, with a
        # ref) only stands for the model to come, so that the field's JSON Schema is that of
        # a field of the model itself (pydantic titles a field unless its schema has a ref)
        return core_schema.no_info_wrap_validator_function(
            self.validate, core_schema.any_schema(ref=f"pframe-lazy-model-{id(self)}"))

    def __get_pydantic_json_schema__(self, schema, handler):
        # the model as a choice (a union of one): a $ref to its definition, as a field of the
        # model has, not the definition written in place
        return handler(core_schema.union_schema([TypeAdapter(self.model).core_schema]))

    def __repr__(self) -> str:
        return f"LazyModel({self._model.__name__ if self._model else '...'})"


def lazy_model(make: Callable, base: type):
    """A field of the model ``make()`` returns, made when a value first needs it:
    ``Annotated[base, LazyModel(make)]``, ``base`` a base class of the model."""
    return Annotated[base, LazyModel(make)]


def _key_reader(key: str):
    def tag(value):
        return value.get(key) if isinstance(value, dict) else getattr(value, key, None)

    return tag


def tagged(members, discriminator: str | Callable):
    """``Annotated[Union[members], LazyUnion]``: a tagged union of models, validated by the
    model its tag names.

    ``members`` is a list of models whose field ``discriminator`` (a name) holds a literal
    tag, or a dict tag -> model with ``discriminator`` a function reading the tag of a value
    (a dict or an object; a tag that may be left out: :func:`pframe.model.scene.tag_reader`).
    With one model, the model itself (no union)."""
    if isinstance(discriminator, str):
        if len(members) == 1:
            return members[0]
        table = {value: model for model in members
                 for value in get_args(model.model_fields[discriminator].annotation)}
        lazy = LazyUnion(_key_reader(discriminator), table, discriminator)
    else:
        lazy = LazyUnion(discriminator, members, discriminator)
    # the annotation holds the same choices as pydantic's union (what a reader of the model's
    # fields sees); only their validation differs
    return Annotated[lazy.choices, lazy]


def on_demand(names, make: Callable, discriminator: str | Callable, base: type):
    """A tagged union of one model per name in ``names``, each model made by ``make(name)``
    when a value first names it (its field ``discriminator`` holds the literal ``name``, or
    ``discriminator`` is a function reading the tag of a value, as for :func:`tagged`):
    ``Annotated[base, LazyUnion]``, ``base`` the members' common base.

    A scene names two or three of the laws' 40 models: making them all took about 20 ms of a
    whole ``pframe solve``. A reader of a model's fields who wants the members calls
    :func:`unfold` on each annotation it meets."""
    tag = _key_reader(discriminator) if isinstance(discriminator, str) else discriminator
    return Annotated[base, LazyUnion(tag, tuple(names), discriminator, make)]


def unfold(annotation):
    """``annotation`` with a union made by :func:`on_demand` as the union of its members
    (``Annotated[Union[...], LazyUnion]``, every member built) and a model made by
    :func:`lazy_model` as that model (``Annotated[model, LazyModel]``); anything else as it
    is."""
    if get_origin(annotation) is Annotated:
        for item in annotation.__metadata__:
            if isinstance(item, LazyUnion) and item._make is not None:
                return Annotated[item.choices, item]
            if isinstance(item, LazyModel):
                return Annotated[item.model, item]
    return annotation
