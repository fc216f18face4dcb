"""Readable paths into scene data: ``contacts.floor-1.gap``, ``buildings.A.story.yield_drift``,
``contacts.*.gap``, ``pi.Pi_d``.

A segment is a mapping key, or the ``name`` of a list item (contacts and storeys without a name
answer to their default names, ``<left>-<right>`` and the upper node), or a list index, or
``*`` for every item. A path must end at a value the base scene gives: a sweep varies numbers
that are written down, and the loader validates each variant as it validates any scene.
"""

from __future__ import annotations

import math

from pframe.errors import InputError


def _default_name(container: str | None, item: dict):
    nodes = item.get("nodes")
    if isinstance(nodes, list) and len(nodes) == 2:
        from pframe.model.scene import (
            default_contact_name,
            default_link_name,
            default_story_name,
        )

        if container == "contacts":
            return default_contact_name(nodes)
        if container == "links":
            return default_link_name(nodes)
        if container == "stories":
            return default_story_name(nodes)
    return None


def _item_names(container, items: list) -> list:
    names = []
    for item in items:
        name = item.get("name") if isinstance(item, dict) else None
        names.append(name if name is not None else
                     (_default_name(container, item) if isinstance(item, dict) else None))
    return names


def _shown(path) -> str:
    return ".".join(str(p) for p in path) or "(top level)"


def _dotted_hint(segment) -> str:
    """For ``contacts[0]`` or ``stories['A/1']``: how a path names a list item (a dot, then
    the index, the item's name or ``*``)."""
    import re

    found = re.fullmatch(r"(\w+)\[\s*['\"]?([^\]'\"]*)['\"]?\s*\]", str(segment))
    if not found:
        return ""
    return (f" (a path names a list item after a dot: {found.group(1)}.{found.group(2).strip()}, "
            f"by index or name, or {found.group(1)}.* for every item)")


def resolve(data, segments: tuple) -> list[tuple]:
    """Every concrete path (keys and list indices) that ``segments`` names in ``data``.

    Raises :class:`InputError` (without a location: the caller adds the sweep file's) when a
    segment names nothing.
    """
    found: list[tuple] = []

    def walk(node, rest, prefix, container):
        if not rest:
            found.append(prefix)
            return
        segment, rest = rest[0], rest[1:]
        if isinstance(node, dict):
            if segment == "*":
                keys = list(node)
            elif segment in node:
                keys = [segment]
            else:
                raise InputError(f"{_shown(prefix)} has no {segment!r}; it has "
                                 f"{', '.join(map(str, node)) or 'nothing'}"
                                 + _dotted_hint(segment))
            for key in keys:
                walk(node[key], rest, prefix + (key,), key)
        elif isinstance(node, list):
            names = _item_names(container, node)
            if segment == "*":
                indices = list(range(len(node)))
            elif segment in names:
                indices = [i for i, name in enumerate(names) if name == segment]
            elif isinstance(segment, int) or (isinstance(segment, str) and segment.isdigit()):
                index = int(segment)
                if not 0 <= index < len(node):
                    raise InputError(f"{_shown(prefix)} has {len(node)} items; no item {index}")
                indices = [index]
            else:
                shown = ", ".join(str(n) for n in names if n is not None)
                raise InputError(f"{_shown(prefix)} has no item named {segment!r}"
                                 + (f"; its items are {shown}" if shown else
                                    "; its items have no names: use an index (0, 1, ...)"))
            for index in indices:
                walk(node[index], rest, prefix + (index,), container)
        else:
            raise InputError(f"{_shown(prefix)} is a value ({node!r}), not a mapping or a list; "
                             f"the path cannot go on to {segment!r}")

    walk(data, tuple(segments), (), None)
    return found


def get(data, path: tuple):
    for part in path:
        data = data[part]
    return data


def put(data, path: tuple, value) -> None:
    """Set the value at a concrete path (the containers must exist: see :func:`resolve`)."""
    for part in path[:-1]:
        data = data[part]
    data[path[-1]] = value


def _numeric(value) -> bool:
    """A number, or text YAML 1.1 left as text but that is one (1.0e10: no exponent sign),
    which the scene model reads as a number too."""
    if isinstance(value, str):
        try:
            return math.isfinite(float(value))
        except ValueError:
            return False
    return isinstance(value, (int, float)) and not isinstance(value, bool)


def check_targets(data, paths: list[tuple], files: bool) -> None:
    """The values an axis replaces must be numbers (or per-storey lists of numbers), or a file
    name for a records axis."""
    for path in paths:
        value = get(data, path)
        if files:
            if not isinstance(value, str):
                raise InputError(f"{_shown(path)} is {value!r}, not a file name")
            continue
        items = value if isinstance(value, list) else [value]
        if not items or not all(_numeric(v) for v in items):
            raise InputError(f"{_shown(path)} is {value!r}, not a number: a sweep varies "
                             "numbers (and record files through excitation.file)")


def scene_records(data) -> list[tuple[tuple, dict]]:
    """(path, motion) of each record of scene data besides its excitation's own (a record
    excitation is the sweep's base record): the components of a pair, the motion a wave
    passage carries, each support's own motion and its components."""
    places = []
    excitation = data.get("excitation") if isinstance(data, dict) else None
    if isinstance(excitation, dict) and not isinstance(excitation.get("file"), str):
        places.append((("excitation",), excitation))
    for i, support in enumerate((data.get("supports") or []) if isinstance(data, dict) else []):
        if isinstance(support, dict) and isinstance(support.get("excitation"), dict):
            places.append((("supports", i, "excitation"), support["excitation"]))
    out = []
    while places:
        path, motion = places.pop(0)
        if isinstance(motion.get("file"), str):
            out.append((path, motion))
        for key in ("x", "y", "motion"):
            if isinstance(motion.get(key), dict):
                places.append((path + (key,), motion[key]))
    return out


#: a record's files besides its acceleration (docs/supports.md#displacements-from-a-record)
SERIES_FIELDS = ("displacement", "velocity")


def series_files(data) -> list[tuple]:
    """The path of each displacement or velocity file scene data names: of its record
    excitation, and of every record of :func:`scene_records`."""
    excitation = data.get("excitation") if isinstance(data, dict) else None
    motions = ([(("excitation",), excitation)] if isinstance(excitation, dict)
               and isinstance(excitation.get("file"), str) else [])
    return [path + (field,) for path, motion in motions + scene_records(data)
            for field in SERIES_FIELDS if isinstance(motion.get(field), str)]
