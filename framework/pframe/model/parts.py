"""The base of a scene's parts, how they print, the field types several of them share, and the
sine, the common ground motion.

Apart from :mod:`pframe.model.scene` so that :mod:`pframe.model.scene_motions` (the rarer
motions, made when a scene names one) builds on them without importing the scene.
"""

from typing import Annotated, Literal

from pydantic import BaseModel, Field, model_validator

from pframe.objects import Frozen

Positive = Annotated[float, Field(gt=0, allow_inf_nan=False)]
NodeName = Annotated[
    str,
    Field(
        pattern=r"^[A-Za-z0-9_.-]+/[A-Za-z0-9_.-]+$",
        description="'<building>/<floor>', e.g. 'A/1' for the first floor above ground of A.",
    ),
]
BuildingName = Annotated[str, Field(pattern=r"^[A-Za-z0-9_.-]+$")]
SupportName = Annotated[str, Field(pattern=r"^[A-Za-z0-9_.-]+$")]

#: the fields that say which kind of object a part is (its tag in a union)
TAGS = ("kind", "type", "law", "material")


# -- how a scene and its parts print (repr): the fields given, under their public names --------

#: fields shown first (which object, which nodes), then the others in the model's order
_FIRST = ("kind", "type", "law", "material", "name", "nodes", "gap")
#: items of a list shown in full; a longer list shows its first and last ones
_LIST_ITEMS = 8


def public_name(cls) -> str:
    """The name a user builds the object with: ``Contact`` (not ``Contact_improved_kelvin``),
    ``Story``, ``StoryProperties``, else the class name."""
    name = cls.__name__
    if name.startswith("Contact_"):
        return "Contact"
    if name.startswith("Story_"):
        return "Story"
    if name.startswith("Link_"):
        return "Link"
    if name.endswith("Storeys"):
        return "StoryProperties"
    return name


def shown_fields(model) -> list[str]:
    """The fields given and the tags that say what the object is (not ``kind``/``type``
    where the class says it: ``Sine``, ``Newmark``)."""
    info = type(model).model_fields
    fields = [n for n in info if (n in model.model_fields_set or n in TAGS) and not (
        n in ("kind", "type") and not info[n].is_required())]
    return sorted(fields, key=lambda n: (_FIRST.index(n) if n in _FIRST else len(_FIRST)))


def shown_items(values, show) -> list[str]:
    values = list(values)
    if len(values) <= _LIST_ITEMS:
        return [show(v) for v in values]
    return ([show(v) for v in values[:3]] + [f"... {len(values) - 5} more ..."]
            + [show(v) for v in values[-2:]])


def brief(value) -> str:
    """One line: ``Contact(law='improved_kelvin', name='floor-1', nodes=('A/1', 'B/1'),
    gap=0.124245, ...)``: the fields that were given (and the tags), numbers to 6 digits,
    long lists cut in the middle; what ``pframe.Contact(...)`` etc. would be called with."""
    if isinstance(value, BaseModel):
        args = ", ".join(f"{n}={brief(getattr(value, n))}" for n in shown_fields(value))
        return f"{public_name(type(value))}({args})"
    if isinstance(value, bool) or value is None:
        return repr(value)
    if isinstance(value, float):
        return f"{value:.6g}"
    if isinstance(value, (list, tuple)):
        inner = ", ".join(shown_items(value, brief))
        return f"({inner}{',' if len(value) == 1 else ''})" if isinstance(value, tuple) \
            else f"[{inner}]"
    if isinstance(value, dict):
        return "{" + ", ".join(shown_items(value.items(), lambda kv: f"{kv[0]!r}: {brief(kv[1])}"))\
            + "}"
    return repr(value)


class Base(Frozen):
    """A part of a scene: frozen, unknown fields refused, misuse an InputError
    (:mod:`pframe.objects`)."""

    @classmethod
    def public_name(cls) -> str:
        return public_name(cls)

    def __repr__(self) -> str:
        return brief(self)

    __str__ = __repr__


class Sine(Base):
    """Ground acceleration a_p sin(w_p t), optionally limited to some cycles or a duration."""

    kind: Literal["sine"] = "sine"
    amplitude: float = Field(allow_inf_nan=False, description="a_p (m/s^2).")
    frequency: Positive = Field(description="Circular frequency w_p (rad/s).")
    cycles: Positive | None = Field(None, description="Number of cycles, then zero.")
    duration: Positive | None = Field(None, description="Duration (s), then zero.")

    @model_validator(mode="after")
    def _not_both(self):
        if self.cycles is not None and self.duration is not None:
            raise ValueError("give cycles or duration, not both")
        return self
