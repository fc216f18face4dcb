"""Reading a scene from YAML, with the line of every value kept for error messages."""

from __future__ import annotations

import re
from dataclasses import dataclass, field
from pathlib import Path

import yaml
from pydantic import BaseModel, ValidationError

from pframe.errors import InputError
from pframe.laws.registry import available_names

Path_ = tuple  # a path into the YAML data: keys and list indices


class ModelError(Exception):
    """A problem found at ``path`` of the YAML data (mapped to a line by the loader)."""

    def __init__(self, path: Path_, message: str):
        super().__init__(message)
        self.path = tuple(path)
        self.message = message


@dataclass(frozen=True)
class LoadedScene:
    """A validated scene with where it came from."""

    scene: object
    text: str
    source: str
    base_dir: Path
    lines: dict = field(repr=False)
    expanded: object = field(repr=False, default=None)

    def where(self, path: Path_) -> str:
        return _where(self.source, self.lines, path)


def _dotted(path: Path_) -> str:
    out = ""
    for part in path:
        out += f"[{part}]" if isinstance(part, int) else (f".{part}" if out else str(part))
    return out or "(top level)"


def _where(source: str, lines: dict, path: Path_) -> str:
    path = tuple(path)
    for cut in range(len(path), -1, -1):
        if path[:cut] in lines:
            return f"{source}, line {lines[path[:cut]]}, {_dotted(path)}"
    return f"{source}, {_dotted(path)}"


class _Loader(yaml.SafeLoader):
    """PyYAML's safe loader, with YAML 1.2's numbers: ``1.0e10`` and ``1e-3`` (no sign, or no
    dot, in the exponent) are floats, as editors and other YAML 1.2 tools read them, not the
    text YAML 1.1 makes of them."""


_Loader.add_implicit_resolver(
    "tag:yaml.org,2002:float",
    re.compile(r"^[-+]?(?:[0-9][0-9_]*(?:\.[0-9_]*)?|\.[0-9_]+)[eE][-+]?[0-9]+$"),
    list("-+0123456789."),
)


def _compose(text: str, source: str):
    loader = _Loader(text)
    try:
        root = loader.get_single_node()
        lines: dict = {}

        def convert(node, path):
            lines.setdefault(path, node.start_mark.line + 1)
            if isinstance(node, yaml.MappingNode):
                # merge keys (<<: *defaults) first: their keys come first and may be overridden
                own = sum(1 for k, _ in node.value if k.tag != "tag:yaml.org,2002:merge")
                loader.flatten_mapping(node)
                merged = len(node.value) - own
                out, from_merge = {}, set()
                for i, (key_node, value_node) in enumerate(node.value):
                    key = loader.construct_object(key_node, deep=True)
                    if i < merged:
                        from_merge.add(key)
                    elif key in from_merge:
                        from_merge.discard(key)
                    elif key in out:
                        raise InputError(
                            f"{source}, line {key_node.start_mark.line + 1}: the key {key!r} "
                            f"appears twice in {_dotted(path)}; each key may be given once"
                        )
                    lines[path + (key,)] = key_node.start_mark.line + 1
                    out[key] = convert(value_node, path + (key,))
                return out
            if isinstance(node, yaml.SequenceNode):
                return [convert(item, path + (i,)) for i, item in enumerate(node.value)]
            return loader.construct_object(node, deep=True)

        data = convert(root, ()) if root is not None else None
    except yaml.YAMLError as exc:
        mark = getattr(exc, "problem_mark", None)
        line = f", line {mark.line + 1}, column {mark.column + 1}" if mark else ""
        problem = getattr(exc, "problem", None) or str(exc)
        raise InputError(f"{source}{line}: not valid YAML: {problem}") from None
    finally:
        loader.dispose()
    return data, lines


def _plugin_names(data: dict, lines: dict, source: str) -> tuple[tuple, tuple]:
    """Law names the scene uses that are not built in; unknown names are reported here."""
    wanted = {"contact": set(), "material": set()}
    places = []
    for i, c in enumerate(data.get("contacts") or []):
        if isinstance(c, dict) and isinstance(c.get("law"), str):
            places.append(("contact", c["law"], ("contacts", i, "law")))
    for i, s in enumerate(data.get("stories") or []):
        if isinstance(s, dict) and isinstance(s.get("material"), str):
            places.append(("material", s["material"], ("stories", i, "material")))
    for i, b in enumerate(data.get("buildings") or []):
        story = b.get("story") if isinstance(b, dict) else None
        if isinstance(story, dict) and isinstance(story.get("material"), str):
            places.append(("material", story["material"], ("buildings", i, "story", "material")))
    from pframe.laws.registry import _builtin_names

    for kind, name, path in places:
        if name in _builtin_names(kind):
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
        tuple(sorted(wanted[k] - set(_builtin_names(k)))) for k in ("contact", "material")
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
            msg = "unknown field (check the spelling; see the YAML reference)"
        elif "input" in err and not isinstance(err["input"], (dict, list)):
            msg += f" (got {err['input']!r})"
        messages.append(f"{_where(source, lines, path)}: {msg}")
    more = f" ({len(messages) - 3} more problems not shown)" if len(messages) > 3 else ""
    return "; ".join(messages[:3]) + more


_MISSING = object()


def _booleans(node, path: Path_ = ()):
    """(path, value) of every boolean in composed YAML data."""
    if isinstance(node, bool):
        yield path, node
    elif isinstance(node, dict):
        for key, value in node.items():
            yield from _booleans(value, path + (key,))
    elif isinstance(node, list):
        for i, value in enumerate(node):
            yield from _booleans(value, path + (i,))


def _value_at(obj, path: Path_):
    """What a validated model holds at a path of its YAML data (_MISSING if it moved)."""
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


def validated(model: type[BaseModel], data, lines: dict, source: str):
    """``model.model_validate(data)``, with problems raised as :class:`InputError` naming the
    file, line and field. A YAML boolean in a number field is one: YAML reads true/false,
    yes/no and on/off as booleans, and pydantic would quietly take them for 1 and 0 (a gap
    written ``gap: on`` would become 1 m)."""
    try:
        out = model.model_validate(data)
    except ValidationError as exc:
        raise InputError(_format_validation(exc, data, lines, source)) from None
    for path, flag in _booleans(data):
        value = _value_at(out, path)
        if isinstance(value, (int, float)) and not isinstance(value, bool):
            raise InputError(
                f"{_where(source, lines, path)}: expected a number, got the boolean "
                f"{str(flag).lower()} (YAML reads true/false, yes/no and on/off as booleans)")
    return out


def scene_from_data(data: dict, lines: dict, source: str, base_dir: Path | str = ".",
                    text: str = "") -> LoadedScene:
    """Validate composed YAML data (a Pi-form scene is expanded first) and resolve it;
    ``lines`` map data paths to lines of ``source`` for the messages."""
    from pframe.model.expand import expand
    from pframe.model.scene import scene_class

    if "pi" in data:  # a scene written in Pi numbers (pframe.nondim.pi_form)
        from pframe.nondim.pi_form import expand_pi_data

        data = expand_pi_data(data, lines, source, base_dir or ".")
        # a Pi-form scene is the paper's formulation: its contacts use the published damping
        # formula of their law unless the expansion says otherwise (a note, not a warning)
        for contact in data.get("contacts") or []:
            if isinstance(contact, dict) and "restitution" in contact:
                contact.setdefault("calibration", "published")
    plugins = _plugin_names(data, lines, source)
    scene = validated(scene_class(*plugins), data, lines, source)
    base_dir = Path(base_dir or ".")
    try:
        expanded = expand(scene, base_dir)
    except ModelError as exc:
        raise InputError(f"{_where(source, lines, exc.path)}: {exc.message}") from None
    if scene.output.units == "dimensionless":  # fail now, not after the run
        from pframe.nondim.scene_variables import reference_scales

        try:
            reference_scales(scene, expanded)
        except InputError as exc:
            raise InputError(f"{_where(source, lines, ('output',))}: {exc}") from None
    return LoadedScene(scene, text, source, base_dir, lines, expanded)


def parse_scene(text: str, source: str = "<string>", base_dir: Path | None = None) -> LoadedScene:
    """Validate a scene given as YAML text; raise :class:`InputError` naming the line."""
    data, lines = _compose(text, source)
    if not isinstance(data, dict):
        raise InputError(f"{source}: a scene is a YAML mapping (keys such as buildings, "
                         "contacts, excitation, analysis); this file holds "
                         f"{'nothing' if data is None else type(data).__name__}")
    return scene_from_data(data, lines, source, base_dir, text)


def read_input(path: Path, what: str) -> str:
    """The text of an input file (``what``: 'model', 'sweep'); InputError if unreadable."""
    try:
        return path.read_text(encoding="utf-8")
    except FileNotFoundError:
        raise InputError(f"{path}: no such {what} file") from None
    except (OSError, UnicodeDecodeError) as exc:
        raise InputError(f"{path}: cannot read the {what} file: {exc}") from None


def load_scene(path: str | Path) -> LoadedScene:
    """Read and validate a scene file."""
    path = Path(path)
    return parse_scene(read_input(path, "model"), str(path), path.parent)
