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

from collections.abc import Callable
from typing import Annotated, Union, get_args

from pydantic import Discriminator, Field, Tag, TypeAdapter, ValidationError
from pydantic_core import core_schema


class LazyUnion:
    """Pydantic metadata of ``Annotated[Union[...], LazyUnion(...)]``: the union validated
    by the model its tag names (see the module's docstring).

    ``union`` is the tagged union as pydantic would validate it; ``tag`` reads the tag of a
    value (a dict or a model object; None if it has none); ``members`` maps each tag to its
    model."""

    def __init__(self, union, tag: Callable, members: dict[str, type]):
        self.union, self.tag, self.members = union, tag, members
        self._adapter: TypeAdapter | None = None

    def adapter(self) -> TypeAdapter:
        """Pydantic's own validator of the whole union (built on first need)."""
        if self._adapter is None:
            self._adapter = TypeAdapter(self.union)
        return self._adapter

    def validate(self, value):
        tag = self.tag(value)
        member = self.members.get(tag) if isinstance(tag, str) else None
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
        return f"LazyUnion({', '.join(self.members)})"


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
        choices = Union[tuple(members)]  # noqa: UP007
        union = Annotated[choices, Field(discriminator=discriminator)]
        table = {value: model for model in members
                 for value in get_args(model.model_fields[discriminator].annotation)}
        reader = _key_reader(discriminator)
    else:
        choices = Union[tuple(Annotated[model, Tag(name)]  # noqa: UP007
                              for name, model in members.items())]
        union = Annotated[choices, Discriminator(discriminator)]
        table, reader = dict(members), discriminator
    # the annotation holds the same choices as pydantic's union (what a reader of the model's
    # fields sees); only their validation differs
    return Annotated[choices, LazyUnion(union, reader, table)]
