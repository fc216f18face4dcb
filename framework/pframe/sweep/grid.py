"""The variant grid of a sweep: its axes resolved in the base scene (:class:`Spec`)."""

from __future__ import annotations

import functools
from dataclasses import dataclass

import numpy as np

from pframe.errors import InputError
from pframe.model.scene import Envelope, History
from pframe.sweep.definition import RESPONSES, SweepFile, validated_sweep
from pframe.sweep.paths import check_targets, resolve, scene_records, series_files
from pframe.sweep.spec import ENVELOPES, SweepDefinition
from pframe.yamltext import compose as _compose
from pframe.yamltext import where as _where


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
    #: ((path of a motion, its record's key), ...): the scene's other records
    scene_records: tuple
    axes: tuple[AxisSpec, ...]
    #: ((path of a record's displacement or velocity file, its key), ...)
    series_files: tuple = ()

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

    def base_scene(self):
        """The base scene as its variants see it (records by key, nothing swept), loaded
        and expanded: the one way the sweep loads its base."""
        from pframe.sweep.variants import load_variant, materialise

        return load_variant(variant_data_base(self), self.base_lines, self.base_where,
                            materialise(self.definition))


@functools.lru_cache(maxsize=8)
def parse(definition: SweepDefinition) -> Spec:
    """The parsed sweep (cached: every chunk of a sweep parses the same definition)."""
    source = definition.source
    model, lines = validated_sweep(definition.text, source)
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
    others = tuple((path, keys[("scene", ".".join(map(str, path)))])
                   for path, _ in scene_records(base_data))
    series = tuple((path, keys[("scene", ".".join(map(str, path)))])
                   for path in series_files(base_data))

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
    for axis in axes:
        timed = [p for p in axis.paths if p in (("analysis", "duration"), ("analysis", "tau"))]
        if timed and base_record is not None:
            raise InputError(
                f"{_where(source, lines, ('axes', axis.index, 'path'))}: axis {axis.name!r} "
                f"sets {'.'.join(timed[0])}, but under a record each variant runs its own "
                "record to its end, plus the time the base scene analyses after its record "
                "(docs/sweeps.md#durations-under-records); set that time in the base scene's "
                "duration instead")
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
                others, tuple(axes), series)


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


def variant_data_base(spec: Spec) -> dict:
    """The base scene's data as the variants see it (record file by key, nothing swept)."""
    import copy

    from pframe.sweep.paths import put

    data = copy.deepcopy(spec.base_data)
    if spec.base_record is not None:
        put(data, ("excitation", "file"), spec.base_record)
    for path, key in spec.scene_records:
        put(data, path + ("file",), key)
    for path, key in spec.series_files:
        put(data, path, key)
    return data
