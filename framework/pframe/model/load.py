"""Reading a scene from YAML, with the line of every value kept for error messages."""

from __future__ import annotations

import math
from pathlib import Path

from pydantic import BaseModel, ValidationError

from pframe.errors import InputError
from pframe.laws.registry import available_names
from pframe.objects import number_given_as_boolean, value_at
from pframe.yamltext import compose, dotted, where

Path_ = tuple  # a path into the YAML data: keys and list indices


class ModelError(Exception):
    """A problem found at ``path`` of the YAML data (mapped to a line by the loader)."""

    def __init__(self, path: Path_, message: str):
        super().__init__(message)
        self.path = tuple(path)
        self.message = message


_dotted = dotted
_where = where
_compose = compose  # the reader of every YAML file (pframe.yamltext)


def plugin_names(data: dict, lines: dict, source: str) -> tuple[tuple, tuple]:
    """Law names the scene uses that are not built in; unknown names are reported here."""
    wanted = {"contact": set(), "material": set()}
    places = []
    def items(key):  # a list, or nothing (the model reports what else it is)
        value = data.get(key)
        return value if isinstance(value, list) else []

    for i, c in enumerate(items("contacts")):
        if isinstance(c, dict) and isinstance(c.get("law"), str):
            places.append(("contact", c["law"], ("contacts", i, "law")))
    for i, s in enumerate(items("stories")):
        if isinstance(s, dict) and isinstance(s.get("material"), str):
            places.append(("material", s["material"], ("stories", i, "material")))
    for i, b in enumerate(items("buildings")):
        story = b.get("story") if isinstance(b, dict) else None
        if isinstance(story, dict) and isinstance(story.get("material"), str):
            places.append(("material", story["material"], ("buildings", i, "story", "material")))
    from pframe.laws.registry import builtin_names

    for kind, name, path in places:
        if name in builtin_names(kind):
            continue
        known = available_names(kind)
        if name not in known:
            what = "contact law" if kind == "contact" else "material"
            raise InputError(
                f"{_where(source, lines, path)}: unknown {what} {name!r}; "
                f"known: {', '.join(known)}"
            )
        wanted[kind].add(name)
    return tuple(
        tuple(sorted(wanted[k] - set(builtin_names(k)))) for k in ("contact", "material")
    )


def _format_validation(exc: ValidationError, data, lines: dict, source: str) -> str:
    messages = []
    for err in exc.errors(include_url=False):
        path, node = [], data
        for part in err["loc"]:
            if isinstance(node, dict) and part in node:
                node = node[part]
                path.append(part)
            elif isinstance(node, list) and isinstance(part, int) and part < len(node):
                node = node[part]
                path.append(part)
            elif err["type"] == "missing" and part == err["loc"][-1]:
                path.append(part)
        msg = err["msg"].removeprefix("Value error, ")
        if err["type"] == "missing":
            msg = "this field is required"
        elif err["type"] == "extra_forbidden":
            msg = _not_this_laws(data, path) or (
                "unknown field (check the spelling; see the YAML reference)")
        elif "input" in err and not isinstance(err["input"], (dict, list)):
            msg += f" (got {err['input']!r})"
        messages.append(f"{_where(source, lines, path)}: {msg}")
    more = f" ({len(messages) - 3} more problems not shown)" if len(messages) > 3 else ""
    return "; ".join(messages[:3]) + more


def _not_this_laws(data, path: Path_) -> str | None:
    """For a field its law does not take but other built-in laws do (a line left behind
    when the law was changed: ``calibration`` on a ``linear`` contact), what to say instead
    of "unknown field"; None otherwise."""
    from pframe.laws.registry import builtin_laws

    parent = data
    for part in path[:-1]:
        try:
            parent = parent[part]
        except (KeyError, IndexError, TypeError):
            return None
    if not path or not isinstance(parent, dict):
        return None
    field = path[-1]
    for kind, tag, what in (("contact", "law", "contact law"), ("material", "material",
                                                                  "material")):
        name = parent.get(tag)
        laws = {law.name: law for law in builtin_laws(kind)}
        if name not in laws:
            continue
        others = [n for n, law in laws.items() if field in law.Params.model_fields]
        if not others:
            return None
        own = [f for f in laws[name].Params.model_fields if f != tag]
        return (f"the {what} {name} takes no {field!r} (it takes {', '.join(own)}); "
                f"{', '.join(others)} take it. Remove the line, or choose one of those")
    return None


#: the largest magnitude of a number in a scene: SI values of real buildings and motions are
#: far below (a mass of 1e308 kg overflows the first product). Tiny values (subnormals) are
#: numbers; where they break the arithmetic (a floor mass of 1e-320 kg), the step that fails
#: says so.
LARGEST = 1e100


def _numbers(node, path: Path_ = ()):
    """(path, value) of every number (not boolean) in composed YAML data."""
    if isinstance(node, (int, float)) and not isinstance(node, bool):
        yield path, node
    elif isinstance(node, dict):
        for key, value in node.items():
            yield from _numbers(value, path + (key,))
    elif isinstance(node, list):
        for i, value in enumerate(node):
            yield from _numbers(value, path + (i,))


def check_numbers(data, lines: dict, source: str) -> None:
    """Every number is finite and at most :data:`LARGEST` in magnitude (NaN, inf and 1e308
    are refused at their line)."""
    for path, value in _numbers(data):
        try:
            size = abs(float(value))
            shown = f"{value:.4g}"
        except OverflowError:  # an integer beyond any float
            size, shown = math.inf, f"an integer of {len(str(abs(value)))} digits"
        if math.isnan(size):
            why = "NaN is not a number pframe computes with"
        elif math.isinf(size) and isinstance(value, float):
            why = "an infinite value is not allowed"
        elif size > LARGEST:
            why = f"{shown} is larger than the {LARGEST:g} pframe computes with"
        else:
            continue
        raise InputError(f"{_where(source, lines, path)}: {why}; give a finite number in the "
                         "scene's units (SI unless its units say otherwise; check the units "
                         "and the exponent)")


def validated(model: type[BaseModel], data, lines: dict, source: str):
    """``model.model_validate(data)``, with problems raised as :class:`InputError` naming the
    file, line and field. A YAML boolean in a number field is one: YAML reads true/false,
    yes/no and on/off as booleans, and pydantic would quietly take them for 1 and 0 (a gap
    written ``gap: on`` would become 1 m)."""
    check_numbers(data, lines, source)
    try:
        out = model.model_validate(data)
    except ValidationError as exc:
        raise InputError(_format_validation(exc, data, lines, source)) from None
    path = number_given_as_boolean(data, out)
    if path is not None:
        raise InputError(
            f"{_where(source, lines, path)}: expected a number, got the boolean "
            f"{str(value_at(data, path)).lower()} (YAML reads true/false, yes/no and on/off as "
            "booleans)")
    return out


def read_input(path: Path, what: str) -> str:
    """The text of an input file (``what``: 'model', 'sweep'); InputError if unreadable."""
    from pframe.yamltext import read_bounded

    try:  # a regular file of bounded size: a device or FIFO is refused, never read
        return read_bounded(path, what)
    except FileNotFoundError:
        raise InputError(f"{path}: no such {what} file") from None
    except (OSError, UnicodeDecodeError) as exc:
        raise InputError(f"{path}: cannot read the {what} file: {exc}") from None
