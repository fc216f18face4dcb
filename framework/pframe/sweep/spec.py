"""A sweep as data: :class:`SweepDefinition` (what a run depends on, picklable for a cluster)
and :class:`Spec` (the same, parsed: axes resolved in the base scene, the variant grid).

Everything a variant's numbers depend on is in the definition: the sweep file's text, the base
scene's text, the contents of every record file, the chunk size and pframe's version. Its
:attr:`~SweepDefinition.digest` keys the resumable output; a chunk is a pure function of the
definition and the chunk's index, whichever process or machine computes it.
"""

from __future__ import annotations

import dataclasses
import functools
import hashlib
import json
import os
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from pframe.errors import InputError
from pframe.model.load import read_input, validated
from pframe.model.scene import Envelope, History
from pframe.sweep.definition import RESPONSES, SweepFile
from pframe.sweep.paths import check_targets, resolve
from pframe.yamltext import compose as _compose
from pframe.yamltext import where as _where

#: bumped when the chunk files' contents change meaning
FORMAT_VERSION = "1"
#: envelopes every sweep kernel records (one kernel structure for all default sweeps)
ENVELOPES = ("displacement", "story_drift", "contact_force")


@dataclass(frozen=True)
class SweepDefinition:
    """What a sweep's results depend on, as plain data.

    Attributes
    ----------
    source : str
        The sweep file as named on the command line (for messages and the result file).
    text : str
        The sweep file's YAML.
    base_source, base_text : str
        The base scene file (relative to the sweep file) and its YAML; empty for an inline
        ``scene:``.
    base_dir : str
        The base scene's folder (where ``pframe sweep --variant`` resolves record files).
    files : tuple of (key, bytes)
        Every record file a variant reads, under a key made of its contents' hash and its name.
    records : tuple of (origin, written, key, absolute path)
        Which file each record name of the base scene (origin ``base``) or of a records axis
        (origin ``axis``) stands for.
    chunk : int
        Variants per chunk.
    code : str
        :func:`code_fingerprint` of the process that loaded the sweep.
    """

    source: str
    text: str
    base_source: str
    base_text: str
    base_dir: str
    files: tuple = ()
    records: tuple = ()
    chunk: int = 64
    code: str = ""

    @functools.cached_property
    def digest(self) -> str:
        """A hash of everything the results depend on (not of where the files are)."""
        import pframe

        parts = [FORMAT_VERSION, pframe.__version__, self.code, self.text, self.base_text,
                 sorted(key for key, _ in self.files),
                 sorted((origin, written, key) for origin, written, key, _ in self.records),
                 self.chunk]
        return hashlib.sha256(json.dumps(parts).encode()).hexdigest()[:24]


#: the parts of pframe a sweep's numbers come from
_COMPUTING = ("model", "assemble", "kernel", "laws", "excitation", "integrators", "nondim",
              "sweep", "quantities.py")


@functools.cache
def code_fingerprint() -> str:
    """A hash of the source of the parts of pframe that compute a sweep's numbers (read once
    per process): results of other code are not mixed into a sweep, whether it is resumed
    after pframe changed or run on a worker that has another pframe."""
    import pframe

    root = Path(pframe.__file__).parent
    digest = hashlib.sha256()
    for part in _COMPUTING:
        paths = [root / part] if part.endswith(".py") else sorted((root / part).rglob("*.py"))
        for path in paths:
            digest.update(str(path.relative_to(root)).encode() + b"\0" + path.read_bytes())
    return digest.hexdigest()[:16]


@dataclass(frozen=True)
class AxisSpec:
    """One axis, resolved: the concrete paths it sets and its values."""

    name: str
    index: int  # position in the sweep file's axes list
    paths: tuple[tuple, ...]
    values: tuple  # what is set in the scene (record keys for a records axis)
    coordinates: np.ndarray  # what the result file holds (numbers, or file names as written)
    units: str | None
    path_text: str
    is_file: bool


@dataclass(frozen=True)
class Spec:
    """A parsed sweep: the variant grid over the base scene."""

    definition: SweepDefinition
    model: SweepFile
    lines: dict
    base_data: dict
    base_lines: dict
    base_where: str  # source name for messages about the base scene
    base_record: str | None
    axes: tuple[AxisSpec, ...]

    @property
    def shape(self) -> tuple[int, ...]:
        """The result's sweep dimensions: one per axis (product), or one ``variant`` (zip)."""
        if self.model.combine == "zip":
            return (len(self.axes[0].values),)
        return tuple(len(a.values) for a in self.axes)

    @property
    def dims(self) -> tuple[str, ...]:
        return ("variant",) if self.model.combine == "zip" else tuple(a.name for a in self.axes)

    @property
    def count(self) -> int:
        return int(np.prod(self.shape))

    @property
    def chunks(self) -> int:
        return -(-self.count // self.definition.chunk)

    def chunk_range(self, chunk: int) -> range:
        size = self.definition.chunk
        return range(chunk * size, min(self.count, (chunk + 1) * size))

    def positions(self, index: int) -> tuple[int, ...]:
        """The position on each axis of variant ``index`` (C order over the axes)."""
        if self.model.combine == "zip":
            return (index,) * len(self.axes)
        return tuple(int(p) for p in np.unravel_index(index, self.shape))

    def describe(self, index: int) -> str:
        """``gap=0.1, record=elcentro.AT2`` for variant ``index``."""
        parts = []
        for axis, position in zip(self.axes, self.positions(index)):
            value = axis.coordinates[position]
            parts.append(f"{axis.name}={value if isinstance(value, str) else f'{value:.6g}'}")
        return ", ".join(parts)

    @property
    def responses(self) -> tuple[str, ...]:
        return tuple(dict.fromkeys(self.model.keep.envelopes))

    @property
    def recorders(self) -> tuple:
        """The recorders every variant runs with (the base scene's own are replaced)."""
        keep = self.model.keep
        envelope = list(ENVELOPES) + [r[len("peak_"):] for r in self.responses
                                      if r.startswith("peak_") and r[len("peak_"):] not in ENVELOPES]
        out = []
        if keep.histories:
            out.append(History(kind="history", quantities=list(dict.fromkeys(keep.histories)),
                               every=keep.every))
        out.append(Envelope(kind="envelope", quantities=envelope))
        return tuple(out)

    def where(self, *path) -> str:
        return _where(self.definition.source, self.lines, path)


def _read_bytes(path: Path, where: str, what: str) -> bytes:
    try:
        return path.read_bytes()
    except FileNotFoundError:
        raise InputError(f"{where}: {what} {str(path)!r} not found") from None
    except OSError as exc:
        raise InputError(f"{where}: cannot read {what} {str(path)!r}: {exc}") from None


def _record_key(content: bytes, name: str) -> str:
    return f"{hashlib.sha256(content).hexdigest()[:16]}-{Path(name).name}"


def _validated(text: str, source: str) -> tuple[SweepFile, dict]:
    data, lines = _compose(text, source)
    if not isinstance(data, dict):
        raise InputError(f"{source}: a sweep file is a YAML mapping (base or scene, axes, "
                         "combine, keep, chunk)")
    return validated(SweepFile, data, lines, source), lines


def load_sweep(path: str | Path, chunk: int | None = None) -> SweepDefinition:
    """Read a sweep file, its base scene and its record files; check every axis.

    Raises :class:`InputError` naming the sweep file's line (or the base scene's) of the
    first problem found.
    """
    path = Path(path)
    return parse_sweep(read_input(path, "sweep"), str(path), path.parent, chunk)


def parse_sweep(text: str, source: str = "<string>", folder: str | Path = ".",
                chunk: int | None = None) -> SweepDefinition:
    """:func:`load_sweep` for YAML text; ``folder`` is where relative file names start."""
    folder = Path(folder)
    model, lines = _validated(text, source)
    if chunk is not None and chunk < 1:
        raise InputError(f"--chunk {chunk}: a chunk holds at least one variant")
    base_source, base_text, base_dir = "", "", folder
    if model.base is not None:
        base_path = Path(os.path.normpath(folder / model.base))
        base_text = _read_bytes(base_path, _where(source, lines, ("base",)),
                                "base scene").decode("utf-8", errors="replace")
        base_source, base_dir = str(base_path), base_path.parent
        base_data, _ = _compose(base_text, base_source)
    else:
        base_data = model.scene

    files: dict[str, bytes] = {}
    records = []
    excitation = base_data.get("excitation") if isinstance(base_data, dict) else None
    if isinstance(excitation, dict) and isinstance(excitation.get("file"), str):
        file = base_dir / excitation["file"]
        content = _read_bytes(file, base_source or source, "record file")
        key = _record_key(content, file.name)
        files[key] = content
        records.append(("base", excitation["file"], key, str(file.resolve())))
    for i, axis in enumerate(model.axes):
        if not axis.is_file:
            continue
        for j, value in enumerate(axis.points()):
            if not isinstance(value, str):
                raise InputError(f"{_where(source, lines, ('axes', i, 'values', j))}: a records "
                                 f"axis (path excitation.file) takes file names, not {value!r}")
            file = folder / value
            content = _read_bytes(file, _where(source, lines, ("axes", i, "values", j)),
                                  "record file")
            key = _record_key(content, file.name)
            files[key] = content
            records.append(("axis", value, key, str(file.resolve())))

    definition = SweepDefinition(
        source=source, text=text, base_source=base_source, base_text=base_text,
        base_dir=str(Path(base_dir).resolve()), files=tuple(sorted(files.items())),
        records=tuple(records), chunk=chunk or model.chunk, code=code_fingerprint())
    check(definition)
    return definition


@functools.lru_cache(maxsize=8)
def parse(definition: SweepDefinition) -> Spec:
    """The parsed sweep (cached: every chunk of a sweep parses the same definition)."""
    source = definition.source
    model, lines = _validated(definition.text, source)
    if definition.base_text:
        base_data, base_lines = _compose(definition.base_text, definition.base_source)
        base_where = definition.base_source
    else:
        base_data = model.scene
        base_lines = {p[1:]: line for p, line in lines.items() if p[:1] == ("scene",)}
        base_where = source
    if not isinstance(base_data, dict):
        raise InputError(f"{base_where}: the base scene is not a YAML mapping")
    keys = {(origin, written): key for origin, written, key, _ in definition.records}
    base_record = None
    excitation = base_data.get("excitation")
    if isinstance(excitation, dict) and isinstance(excitation.get("file"), str):
        base_record = keys[("base", excitation["file"])]

    names = [a.name for a in model.axes]
    for i, name in enumerate(names):
        if name in names[:i]:
            raise InputError(f"{_where(source, lines, ('axes', i, 'name'))}: the axis name "
                             f"{name!r} is used twice")
    if model.combine == "zip":
        lengths = {a.name: len(a.points()) for a in model.axes}
        if len(set(lengths.values())) > 1:
            raise InputError(f"{_where(source, lines, ('combine',))}: zipped axes must have "
                             "equal lengths; got "
                             + ", ".join(f"{k}: {v}" for k, v in lengths.items()))
    axes = []
    for i, axis in enumerate(model.axes):
        where = _where(source, lines, ("axes", i, "path"))
        try:
            paths = resolve(base_data, axis.segments)
            check_targets(base_data, paths, axis.is_file)
        except InputError as exc:
            raise InputError(f"{where}: axis {axis.name!r}, path {axis.path!r}: {exc}") from None
        if axis.is_file and base_record is None:
            raise InputError(f"{where}: axis {axis.name!r} sets record files, but the base "
                             "scene's excitation is not a record (kind: record, file: ...)")
        points = axis.points()
        if axis.is_file:
            values = tuple(keys[("axis", p)] for p in points)
            coordinates = np.array(points, dtype=object)
        else:
            values = tuple(_number(p, _where(source, lines, ("axes", i, "values", j)),
                                   axis.name) for j, p in enumerate(points))
            coordinates = np.array(values, dtype=float)
        path_text = axis.path if isinstance(axis.path, str) else ".".join(map(str, axis.path))
        axes.append(AxisSpec(axis.name, i, tuple(paths), values, coordinates, axis.units,
                             path_text, axis.is_file))
    taken = {}
    for axis in axes:
        for path in axis.paths:
            if path in taken:
                raise InputError(f"{_where(source, lines, ('axes', axis.index, 'path'))}: axes "
                                 f"{taken[path]!r} and {axis.name!r} both set "
                                 f"{'.'.join(map(str, path))}")
            taken[path] = axis.name
    for response in model.keep.envelopes:
        assert response in RESPONSES
    return Spec(definition, model, lines, base_data, base_lines, base_where, base_record,
                tuple(axes))


def _number(value, where: str, axis: str):
    """A number as YAML wrote it; YAML 1.1 reads 1e-3 (no dot) as text, so text that is a
    number is taken as one."""
    if not isinstance(value, str):
        return value
    try:
        number = float(value)
    except ValueError:
        raise InputError(f"{where}: axis {axis!r} sets a number, not {value!r}") from None
    if not np.isfinite(number):
        raise InputError(f"{where}: axis {axis!r}: {value!r} is not a finite number")
    return number


def topology(expanded, recorders) -> tuple:
    """What variants of one batch must share (as :func:`pframe.assemble.assemble_batch`
    requires), with the sweep's recorders."""
    from pframe.assemble import batch_key

    return batch_key(dataclasses.replace(expanded, recorders=recorders))


def check(definition: SweepDefinition, full: int = 2) -> None:
    """Validate probes of the sweep before anything runs: every value of every axis through
    the scene model, and variant 0, each axis's first and last values and every record file
    through the whole loader (expansion to numbers and the topology check). A problem only
    some combination of values has is found when its chunk runs (the variant is recorded as
    failed, with the reason)."""
    from pframe.sweep.variants import load_variant, materialise, variant_data

    spec = parse(definition)
    folder = materialise(definition)
    base = load_variant(variant_data_base(spec), spec.base_lines, spec.base_where, folder)
    reference = topology(base.expanded, spec.recorders)
    probes: dict[int, tuple[AxisSpec | None, bool]] = {0: (None, True)}
    for axis in spec.axes:
        count = len(axis.values)
        for position in range(count):
            whole = axis.is_file or position in (0, count - 1)
            index = _index_with(spec, axis, position)
            if index not in probes or (whole and not probes[index][1]):
                probes[index] = (axis, whole)
    for index, (axis, whole) in sorted(probes.items()):
        try:
            data = variant_data(spec, index)
            if whole:
                loaded = load_variant(data, spec.base_lines, spec.base_where, folder)
                if topology(loaded.expanded, spec.recorders) != reference:
                    from pframe.sweep.chunk import TOPOLOGY_CHANGED

                    raise InputError(TOPOLOGY_CHANGED)
            else:
                _validate_model(data, spec, folder)
        except InputError as exc:
            message = str(exc).replace(str(folder) + "/", "")
            axis = axis or spec.axes[0]
            raise InputError(f"{spec.where('axes', axis.index)}: axis {axis.name!r}, variant "
                             f"{index} ({spec.describe(index)}): {message}") from None


def variant_data_base(spec: Spec) -> dict:
    """The base scene's data as the variants see it (record file by key, nothing swept)."""
    import copy

    from pframe.sweep.paths import put

    data = copy.deepcopy(spec.base_data)
    if spec.base_record is not None:
        put(data, ("excitation", "file"), spec.base_record)
    return data


def _index_with(spec: Spec, axis: AxisSpec, position: int) -> int:
    if spec.model.combine == "zip":
        return position
    positions = [0] * len(spec.axes)
    positions[spec.axes.index(axis)] = position
    return int(np.ravel_multi_index(positions, spec.shape))


def _validate_model(data: dict, spec: Spec, folder) -> None:
    """The scene model's checks alone (no expansion to numbers): cheap enough for every value."""
    from pframe.model.load import plugin_names as _plugin_names
    from pframe.model.scene import scene_class

    lines, source = spec.base_lines, spec.base_where
    if "pi" in data:
        from pframe.nondim.pi_form import expand_pi_data

        data = expand_pi_data(data, lines, source, folder)  # a record is read from there
    plugins = _plugin_names(data, lines, source)
    validated(scene_class(*plugins), data, lines, source)
