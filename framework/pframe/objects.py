"""The base of the objects a user builds in Python: scene parts and integrators.

They are frozen pydantic models, and pydantic's own errors are not pframe's: a misuse of one
raises :class:`~pframe.errors.InputError` naming the object and the field, as a scene file's
problem does, whether it is

- building one with a value of the wrong type or range, an unknown field, or positionally
  (``pframe.Node("A/1")``; fields are given by name, as the YAML writes them);
- a boolean where a number belongs (pydantic takes ``True`` for 1.0: a ``gap=True`` would be
  a 1 m gap);
- ``model_copy(update=...)``, which pydantic does not validate at all: the copy is checked
  as the object would be built with those values (an unknown field, a value of the wrong
  type or range, a boolean for a number);
- assigning a field (the objects are frozen: ``model_copy(update=...)`` makes a changed copy).

What needs the whole scene (a contact's nodes exist, NaN, the limits of a run) is checked
when the scene is used, as for a file.
"""

from __future__ import annotations

from pydantic import BaseModel, ConfigDict, ValidationError

from pframe.errors import InputError

_MISSING = object()


def booleans(node, path: tuple = ()):
    """(path, value) of every boolean in plain data (mappings, lists, tuples)."""
    if isinstance(node, bool):
        yield path, node
    elif isinstance(node, dict):
        for key, value in node.items():
            yield from booleans(value, path + (key,))
    elif isinstance(node, (list, tuple)):
        for i, value in enumerate(node):
            yield from booleans(value, path + (i,))


def describe(value) -> str:
    """``None``, ``a int (5)``, ``a list``: what a wrong argument is, for messages."""
    import numpy as np

    if value is None:
        return "None"
    if isinstance(value, np.ndarray):
        return f"a numpy array of shape {value.shape}"
    kind = type(value).__name__
    article = "an" if kind[:1].lower() in "aeiou" else "a"
    shown = repr(value)
    return (f"{article} {kind} ({shown})" if len(shown) <= 40 and "\n" not in shown
            and not isinstance(value, dict) else f"{article} {kind}")


def value_at(obj, path: tuple):
    """What a validated model holds at a path of the data it was built from (a sentinel if
    the path does not lead anywhere)."""
    for part in path:
        if isinstance(obj, BaseModel) and isinstance(part, str):
            obj = getattr(obj, part, _MISSING)
        elif isinstance(obj, dict):
            obj = obj.get(part, _MISSING)
        elif isinstance(obj, (list, tuple)) and isinstance(part, int) and part < len(obj):
            obj = obj[part]
        else:
            return _MISSING
        if obj is _MISSING:
            return obj
    return obj


def number_given_as_boolean(data, validated) -> tuple | None:
    """The path of the first boolean in ``data`` that ``validated`` holds as a number."""
    for path, _ in booleans(data):
        value = value_at(validated, path)
        if isinstance(value, (int, float)) and not isinstance(value, bool):
            return path
    return None


def dotted(path) -> str:
    out = ""
    for part in path:
        out += f"[{part}]" if isinstance(part, int) else (f".{part}" if out else str(part))
    return out


def shown(value, width: int = 60) -> str:
    """``repr(value)`` on one line, cut to about ``width`` characters (an array's)."""
    text = " ".join(repr(value).split())
    return text if len(text) <= width else text[:width - 5] + " ...)"


def problems(exc: ValidationError, limit: int = 3) -> str:
    """The errors of a pydantic validation, one clause each: ``field: what is wrong (got
    value)``."""
    out = []
    for err in exc.errors(include_url=False):
        where = dotted(err["loc"]) or "the object"
        msg = " ".join(err["msg"].removeprefix("Value error, ").split())  # on one line
        if err["type"] == "missing":
            msg = "this field is required"
        elif err["type"] == "extra_forbidden":
            msg = "unknown field (check the spelling; see the YAML reference)"
        elif "input" in err and not isinstance(err["input"], (dict, list, BaseModel)):
            msg += f" (got {shown(err['input'])})"
        out.append(f"{where}: {msg}")
    more = f" ({len(out) - limit} more problems not shown)" if len(out) > limit else ""
    return "; ".join(out[:limit]) + more


def _keys(update: dict) -> str:
    return "{" + ", ".join(f"{k!r}: ..." for k in update) + "}"


def _call(name: str, fields) -> str:
    return f"pframe.{name}({', '.join(f'{k}=...' for k in fields)})"


class Frozen(BaseModel):
    """A frozen model with unknown fields refused, whose misuse raises InputError."""

    model_config = ConfigDict(extra="forbid", frozen=True, defer_build=True)

    @classmethod
    def public_name(cls) -> str:
        """The name a user builds the object with (messages)."""
        return cls.__name__

    def __init__(self, /, *args, **data):
        name = type(self).public_name()
        if args:
            raise InputError(
                f"pframe.{name}: give its fields by name, as the YAML writes them "
                f"({name}({', '.join(f'{f}=...' for f in list(type(self).model_fields)[:3])}"
                f", ...)), not {len(args)} value{'s' if len(args) > 1 else ''} by position")
        try:
            super().__init__(**data)
        except ValidationError as exc:
            raise InputError(f"{_call(name, data)}: {problems(exc)}") from None
        path = number_given_as_boolean(data, self)
        if path is not None:
            raise InputError(f"{_call(name, data)}: {dotted(path)}: expected a number, got "
                             f"the boolean {value_at(data, path)}")

    # validation (model_validate, a nested object read from data) goes straight to pydantic's
    # validator, as for BaseModel.__init__: only a call by the user comes here
    __init__.__pydantic_base_init__ = True

    def model_copy(self, *, update=None, deep: bool = False):
        """A copy, with the fields in ``update`` changed; the copy is validated as the object
        built with those values would be (pydantic's does not validate)."""
        name = type(self).public_name()
        if update is not None and not isinstance(update, dict):
            raise InputError(f"pframe.{name}.model_copy(update=...): give a dict of field "
                             f"names and values, not a {type(update).__name__}")
        if update:
            fields = type(self).model_fields
            unknown = [k for k in update if k not in fields]
            if unknown:
                raise InputError(
                    f"pframe.{name}.model_copy(update={_keys(update)}): "
                    f"{name} has no field {', '.join(map(repr, unknown))}; its fields are "
                    f"{', '.join(fields)}")
            data = {k: getattr(self, k) for k in fields if k in self.model_fields_set}
            # a field not given and set to its default stays not given: the object is the
            # same, and a check of which fields were given (a model's own) sees no change
            data.update({k: v for k, v in update.items() if k in self.model_fields_set
                         or fields[k].is_required() or v is not fields[k].default})
            try:
                checked = type(self).model_validate(data)
            except ValidationError as exc:
                raise InputError(f"pframe.{name}.model_copy(update={_keys(update)}): "
                                 f"{problems(exc)}") from None
            path = number_given_as_boolean(update, checked)
            if path is not None:
                raise InputError(f"pframe.{name}.model_copy(update={_keys(update)}): "
                                 f"{dotted(path)}: expected a number, got the boolean "
                                 f"{value_at(update, path)}")
            # the validated values (a dict given for a nested object becomes that object)
            update = {k: getattr(checked, k) for k in update}
        return super().model_copy(update=update, deep=deep)

    def __setattr__(self, name: str, value) -> None:
        if name.startswith("_"):  # private attributes (where a record was read from)
            super().__setattr__(name, value)
            return
        raise InputError(
            f"pframe.{type(self).public_name()}.{name} = ...: the objects of a scene are "
            f"frozen (a scene is a value); make a changed copy: "
            f"obj.model_copy(update={{{name!r}: ...}})")

    def __delattr__(self, name: str) -> None:
        if name.startswith("_"):
            super().__delattr__(name)
            return
        raise InputError(f"del pframe.{type(self).public_name()}.{name}: the objects of a "
                         "scene are frozen; make a copy without it: "
                         f"obj.model_copy(update={{{name!r}: None}}) where None is allowed")
