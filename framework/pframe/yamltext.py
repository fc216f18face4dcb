"""YAML text to plain data, bounded and with line numbers: the one place pframe reads YAML
(and writes a scene's, :func:`dump`).

- ``safe_load`` semantics: only plain data (mappings, lists, strings, numbers, booleans,
  null); a Python tag (``!!python/object``) is refused.
- Numbers are read the YAML 1.2 way: ``1.0e9``, ``11.9e6`` and ``1e-3`` are numbers (PyYAML
  follows YAML 1.1, where a number without a dot or without a sign in its exponent is text),
  ``010`` is ten, ``0o10`` eight and ``0x10`` sixteen; ``1:30`` and ``1_000`` are text.
- Bounded: a file whose aliases (``*name``) would expand beyond :data:`MAX_NODES` values, or
  that nests deeper than :data:`MAX_DEPTH`, is refused with a message before memory grows (a
  1 kB "billion laughs" file would otherwise expand to gigabytes).
- A mapping key must be a scalar, and each key appears once; merge keys (``<<: *defaults``)
  bring the keys of an anchored mapping, which keys written beside them replace.

:func:`compose` returns the data and the line of every value (a path of keys and list indices
to a line number), which :func:`where` turns into ``file, line N, a.b[2].c`` for messages.
"""

from __future__ import annotations

import os
import re
import stat

import yaml

from pframe.errors import InputError

#: values (mappings, lists and scalars, aliases counted as often as they are used) a file may
#: hold: far above any real scene (a 100,000-floor building with per-floor lists has ~10^6)
MAX_NODES = 5_000_000
#: nesting depth of mappings and lists (a scene nests about 6 deep)
MAX_DEPTH = 100
#: values reached through aliases (``*name``): real files reuse a block a few times
MAX_ALIAS_NODES = 100_000

#: bytes of a scene, sweep or suite file pframe reads: real ones are a few kB, and a
#: 10,000-floor building written out floor by floor about 0.5 MiB; reading YAML takes about
#: 1 s per MiB with libyaml (10 s with PyYAML's Python parser), so a larger file is refused
#: at once rather than read for minutes
MAX_YAML_BYTES = 2**20
#: how to give a scene that would pass the size limit, said when a scene file (``model``, or
#: an ``input`` that pframe validate reads) does
LARGE_SCENE = ("a tall building is one line, `floors: N` with one mass and one storey for all "
               "floors, a contact at every floor level two buildings share is one line, "
               "`nodes: [A, B]` (docs/first-scene.md), and a scene built in Python "
               "(pframe.Scene, docs/python.md) has no file to read")
LARGE_INPUT = {"model": LARGE_SCENE, "input": LARGE_SCENE}


def read_bounded(path, what: str, limit: int = MAX_YAML_BYTES, errors: str = "strict") -> str:
    """The text of an input file, read only if it is a regular file of at most ``limit``
    bytes: a device (``/dev/zero``), a FIFO or a folder is refused at once, never read.

    The one guard of every input pframe reads (scenes, sweeps, suites, records). Raises
    :class:`InputError` naming the file and the limit; ``FileNotFoundError`` when it does
    not exist (the callers say which file is missing).
    """
    data = read_bounded_bytes(path, what, limit)
    try:
        return data.decode("utf-8", errors=errors)
    except UnicodeDecodeError as exc:
        raise InputError(f"{path}: the {what} file is not UTF-8 text (byte {exc.start + 1}); "
                         "save it as UTF-8") from None


def read_bounded_bytes(path, what: str, limit: int = MAX_YAML_BYTES) -> bytes:
    """The bytes of an input file, under the guard of :func:`read_bounded`."""
    path = os.fspath(path)
    try:  # O_NONBLOCK: opening a FIFO must not wait for a writer
        fd = os.open(path, os.O_RDONLY | getattr(os, "O_NONBLOCK", 0))
    except FileNotFoundError:
        raise
    except IsADirectoryError:
        raise InputError(f"{path}: is a folder, not a {what} file") from None
    except OSError as exc:
        raise InputError(f"{path}: cannot read the {what} file: "
                         f"{exc.strerror or exc}") from None
    mode = os.fstat(fd).st_mode
    if not stat.S_ISREG(mode):  # before fdopen, which refuses a folder with its own error
        os.close(fd)
        kind = ("a folder" if stat.S_ISDIR(mode) else "a named pipe (FIFO)"
                if stat.S_ISFIFO(mode) else "a device" if stat.S_ISCHR(mode) or
                stat.S_ISBLK(mode) else "not a regular file")
        raise InputError(f"{path}: is {kind}; pframe reads a {what} only from a regular "
                         "file")
    with os.fdopen(fd, "rb") as handle:
        size = os.fstat(fd).st_size
        data = handle.read(limit + 1) if size <= limit else b""
        if size > limit or len(data) > limit:
            size = max(size, len(data))
            how = LARGE_INPUT.get(what)
            raise InputError(
                f"{path}: the {what} file is {size / 2**20:.1f} MiB; pframe reads {what} files "
                f"of up to {limit / 2**20:g} MiB (docs/getting-started.md#limits): is it "
                f"the right file?" + (f" A large scene is written short: {how}." if how else ""))
    return data


_INT = re.compile(r"^[-+]?[0-9]+$|^0o[0-7]+$|^0x[0-9a-fA-F]+$")
_FLOAT = re.compile(r"^[-+]?(?:\.[0-9]+|[0-9]+(?:\.[0-9]*)?)(?:[eE][-+]?[0-9]+)?$"
                    r"|^[-+]?\.(?:inf|Inf|INF)$|^\.(?:nan|NaN|NAN)$")


_PLAIN = ("tag:yaml.org,2002:map", "tag:yaml.org,2002:seq")
_MERGE = "tag:yaml.org,2002:merge"


class _TooDeep(Exception):
    """Raised by :class:`Loader` at the first node nested beyond :data:`MAX_DEPTH`."""

    def __init__(self, mark):
        super().__init__()
        self.mark = mark


class Loader(yaml.SafeLoader):
    """PyYAML's safe loader with YAML 1.2 (core schema) integers and floats, that stops at
    the first node nested deeper than :data:`MAX_DEPTH`: PyYAML's scanner costs time in
    proportion to the open brackets for every token, so a file of thousands of ``[`` would
    otherwise take seconds to be refused."""

    _depth = 0

    def compose_node(self, parent, index):
        if self._depth > MAX_DEPTH and not self.check_event(yaml.AliasEvent):
            raise _TooDeep(self.peek_event().start_mark)
        self._depth += 1
        try:
            return super().compose_node(parent, index)
        finally:
            self._depth -= 1

    def fetch_flow_collection_start(self, TokenClass):
        # the scanner reads up to 1,024 characters of a line ahead of the nodes, each at a
        # cost in proportion to the open brackets: stop at the bracket that passes the limit
        # (on the line where the nodes would pass it)
        if self.flow_level > MAX_DEPTH:
            raise _TooDeep(self.get_mark())
        super().fetch_flow_collection_start(TokenClass)


#: libyaml's parser where PyYAML has it (the wheels do): the same nodes and line marks, about
#: ten times faster than the Python one (a 10,000-sample list: 30 ms, not 0.5 s), and it
#: stops by itself at 1,000 nested brackets (the Python scanner, which :class:`Loader`
#: guards, slows with every open bracket). Text it refuses is read again by :class:`Loader`,
#: whose messages say more.
CLoader = (type("CLoader", (yaml.CSafeLoader,), {"yaml_implicit_resolvers": {}})
           if getattr(yaml, "__with_libyaml__", False) else None)

for _loader in (Loader, CLoader):
    if _loader is None:
        continue
    _loader.yaml_implicit_resolvers = {
        first: [(tag, regexp) for tag, regexp in resolvers
                if tag not in ("tag:yaml.org,2002:int", "tag:yaml.org,2002:float")]
        for first, resolvers in yaml.SafeLoader.yaml_implicit_resolvers.items()
    }
    _loader.add_implicit_resolver("tag:yaml.org,2002:int", _INT, list("-+0123456789"))
    _loader.add_implicit_resolver("tag:yaml.org,2002:float", _FLOAT, list("-+0123456789."))


def _construct_int(loader, node):
    text = loader.construct_scalar(node)
    if text.startswith("0o"):
        return int(text[2:], 8)
    if text.startswith("0x"):
        return int(text[2:], 16)
    try:
        return int(text, 10)
    except ValueError:  # an explicit !!int tag on something else
        raise yaml.constructor.ConstructorError(
            None, None, f"{text!r} is not an integer", node.start_mark) from None


def _construct_float(loader, node):
    text = loader.construct_scalar(node).lower()
    if text.endswith(".inf"):
        return float("-inf") if text.startswith("-") else float("inf")
    if text == ".nan":
        return float("nan")
    try:
        return float(text)
    except ValueError:
        raise yaml.constructor.ConstructorError(
            None, None, f"{text!r} is not a number", node.start_mark) from None


for _loader in (Loader, CLoader):
    if _loader is not None:
        _loader.add_constructor("tag:yaml.org,2002:int", _construct_int)
        _loader.add_constructor("tag:yaml.org,2002:float", _construct_float)


#: libyaml's emitter where PyYAML has it: the same text as PyYAML's Python emitter (checked on
#: every scene of models/), about four times faster
_DUMPER = yaml.CSafeDumper if getattr(yaml, "__with_libyaml__", False) else yaml.SafeDumper


def dump(data) -> str:
    """Plain data (a scene's fields) as YAML text, as pframe writes a scene: keys in their
    order, text as it is (not escaped), lines of up to 100 characters. Made only where text
    is needed (a result file's ``input_yaml``, ``Scene.to_yaml``), never to be read again."""
    return yaml.dump(data, Dumper=_DUMPER, sort_keys=False, allow_unicode=True, width=100)


def dotted(path: tuple) -> str:
    """``buildings[0].story.stiffness`` for a path of keys and list indices."""
    out = ""
    for part in path:
        out += f"[{part}]" if isinstance(part, int) else (f".{part}" if out else str(part))
    return out or "(top level)"


def where(source: str, lines: dict, path: tuple) -> str:
    """``source, line N, a.b[2]``: the line of the deepest part of ``path`` that has one."""
    path = tuple(path)
    for cut in range(len(path), -1, -1):
        if path[:cut] in lines:
            return f"{source}, line {lines[path[:cut]]}, {dotted(path)}"
    return f"{source}, {dotted(path)}"


def _too_large(source: str, node, what: str) -> InputError:
    mark = getattr(node, "start_mark", node)  # a node, or the mark where one starts
    return InputError(
        f"{source}, line {mark.line + 1}: {what}; pframe reads YAML files of up to "
        f"{MAX_NODES:,} values ({MAX_ALIAS_NODES:,} through aliases), nested up to {MAX_DEPTH} "
        "deep (a scene needs a small part of that). If the file uses aliases (*name), write the "
        "values out instead")


def compose(text: str, source: str = "<string>", loader_class=None) -> tuple[object, dict]:
    """The plain data of a YAML document and the line of each value (1-based, by path).

    Raises :class:`InputError` naming the line for invalid YAML, a Python tag, a key given
    twice or that is not a scalar, and a document beyond the size limits. ``loader_class``
    forces a loader (:class:`Loader`, the Python one; by default libyaml's where PyYAML has it).
    """
    loader_class = loader_class or CLoader or Loader
    loader = loader_class(text)
    lines: dict = {}
    count = [0, 0]  # values, values reached through aliases

    def convert(node, path, depth, aliased):
        count[0] += 1
        count[1] += aliased
        if count[0] > MAX_NODES or count[1] > MAX_ALIAS_NODES:
            raise _too_large(source, node, "the file expands to more values than pframe reads"
                             + (" (its aliases multiply)" if count[1] > MAX_ALIAS_NODES else ""))
        if depth > MAX_DEPTH:
            raise _too_large(source, node, f"the data nests more than {MAX_DEPTH} levels deep")
        if not aliased:
            lines.setdefault(path, node.start_mark.line + 1)
        if not isinstance(node, yaml.ScalarNode) and node.tag not in _PLAIN:
            python = " (Python tags are not read: a scene holds plain data only)" if (
                "python/" in node.tag) else ""
            raise InputError(f"{source}, line {node.start_mark.line + 1}, {dotted(path)}: the "
                             f"tag {node.tag.replace('tag:yaml.org,2002:', '!!')} is not "
                             f"read{python}; write plain mappings and lists")
        if isinstance(node, yaml.MappingNode):
            out = {}
            for key_node, value_node in node.value:
                if key_node.tag == _MERGE:
                    out.update(merged(key_node, value_node, path, depth))
            own: set = set()
            for key_node, value_node in node.value:
                if key_node.tag == _MERGE:
                    continue
                if not isinstance(key_node, yaml.ScalarNode):
                    kind = "list" if isinstance(key_node, yaml.SequenceNode) else "mapping"
                    raise InputError(
                        f"{source}, line {key_node.start_mark.line + 1}: a key in "
                        f"{dotted(path)} is a {kind}; keys are names (text)")
                key = loader.construct_object(key_node, deep=True)
                if key in own:
                    raise InputError(
                        f"{source}, line {key_node.start_mark.line + 1}: the key {key!r} "
                        f"appears twice in {dotted(path)}; each key may be given once"
                    )
                own.add(key)
                if not aliased:
                    lines[path + (key,)] = key_node.start_mark.line + 1
                out[key] = convert(value_node, path + (key,), depth + 1,
                                   aliased or id(value_node) in seen)
                seen.add(id(value_node))
            return out
        if isinstance(node, yaml.SequenceNode):
            out = []
            for i, item in enumerate(node.value):
                out.append(convert(item, path + (i,), depth + 1, aliased or id(item) in seen))
                seen.add(id(item))
            return out
        return loader.construct_object(node, deep=True)

    def merged(key_node, value_node, path, depth) -> dict:
        """The keys a merge key (``<<: *defaults`` or ``<<: [*a, *b]``) brings: the first
        mapping listed wins, keys written beside ``<<`` win over all; counted as aliases."""
        sources = (value_node.value if isinstance(value_node, yaml.SequenceNode)
                   else [value_node])
        out: dict = {}
        for source_node in reversed(sources):
            if not isinstance(source_node, yaml.MappingNode):
                raise InputError(f"{source}, line {key_node.start_mark.line + 1}, "
                                 f"{dotted(path)}: a merge key (<<) takes a mapping (*anchor) "
                                 "or a list of them")
            out.update(convert(source_node, path, depth, True))
        for key in out:
            lines.setdefault(path + (key,), key_node.start_mark.line + 1)
        return out

    seen: set = set()  # nodes converted once: a second visit comes through an alias
    try:
        try:
            root = loader.get_single_node()
        except _TooDeep as exc:
            raise _too_large(source, exc.mark, f"the data nests more than {MAX_DEPTH} levels "
                             "deep") from None
        except RecursionError:
            raise InputError(f"{source}: the data nests more than {MAX_DEPTH} levels deep; "
                             "pframe reads YAML nested up to that depth") from None
        data = convert(root, (), 0, False) if root is not None else None
    except yaml.YAMLError as exc:
        mark = getattr(exc, "problem_mark", None)
        if loader_class is not Loader:
            # read again by the Python loader, which says more (the character or alias it
            # found, the line where the data passes pframe's nesting limit where libyaml
            # stops at 1,000 brackets): the same line, a clearer message
            return compose(text, source, Loader)
        line = f", line {mark.line + 1}, column {mark.column + 1}" if mark else ""
        problem = getattr(exc, "problem", None) or str(exc)
        if "python/" in str(problem) or "python/" in str(getattr(exc, "context", "") or ""):
            problem = f"{problem} (Python tags are not read: a scene holds plain data only)"
        raise InputError(f"{source}{line}: not valid YAML: {problem}") from None
    finally:
        loader.dispose()
    return data, lines


def load(text: str, source: str = "<string>"):
    """The plain data of a YAML document (:func:`compose` without the lines)."""
    return compose(text, source)[0]
