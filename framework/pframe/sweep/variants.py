"""Variants as scenes: the base scene's data with the swept values set, validated by the loader.

Each variant goes through the same steps as a scene file (Pi-form expansion, plug-in laws, the
pydantic model, expansion to numbers) from YAML data that is composed once for the whole sweep;
composing YAML text is most of what :func:`pframe.reader.parse_scene` costs, and a sweep has
thousands of variants. ``tests/test_sweep.py`` checks that both roads give the same scene.

**Durations under records** (docs/sweeps.md#durations-under-records). When the base scene's
excitation is a record, each variant runs its own record to its end: its duration is its
record's length (as applied: after ``frequency``) plus the base scene's *tail*, the time the
base analyses beyond the end of its own record (its free vibration; 0 when the base stops
at its record's end). A base scene that stops *before* its record ends asks for a cut: then
every variant keeps the base's duration and each one whose record goes on past it says so
(:func:`cut_warning`).
"""

from __future__ import annotations

import atexit
import copy
import math
import shutil
import tempfile
from pathlib import Path

from pframe.reader import LoadedScene, scene_from_data
from pframe.sweep.paths import put


def load_variant(data: dict, lines: dict, source: str, base_dir: Path) -> LoadedScene:
    """Validate scene data as :func:`pframe.reader.parse_scene` validates the data of a file;
    ``lines`` are the base scene's (a variant has the base's layout, so they still apply)."""
    return scene_from_data(data, lines, source, base_dir)


def variant_data(spec, index: int, record_path=None, steps: int | None = None) -> dict:
    """The base scene's data with variant ``index``'s values set. Record files are named by
    ``record_path(key)`` (default: the key, a file in the folder :func:`materialise` fills);
    ``steps`` sets the analysed duration to that many steps (:func:`fitted_steps`)."""
    record_path = record_path or (lambda key: key)
    data = copy.deepcopy(spec.base_data)
    if spec.base_record is not None:
        put(data, ("excitation", "file"), record_path(spec.base_record))
    for path, key in spec.scene_records:
        put(data, path + ("file",), record_path(key))
    for path, key in spec.series_files:  # a record's displacement and velocity files
        put(data, path, record_path(key))
    for axis, position in zip(spec.axes, spec.positions(index)):
        value = axis.values[position]
        if axis.is_file:
            value = record_path(value)
        for path in axis.paths:
            put(data, path, value)
    if steps is not None:
        analysis = data["analysis"]
        if "pi" in data:  # tau = w_p t: the same number of steps of dtau
            analysis["tau"] = steps * float(analysis["dt_tau"])
        else:
            analysis["duration"] = steps * float(analysis["dt"])
    return data


def record_end(expanded) -> float | None:
    """The time (s) of the last sample of the scene's record as applied, or None."""
    record = expanded.record
    return None if record is None else float(record.times[-1])


def record_peak_time(expanded) -> float | None:
    """The time (s) of the record's peak absolute acceleration, or None."""
    record = expanded.record
    if record is None:
        return None
    return float(record.times[int(abs(record.acceleration).argmax())])


def record_tail(spec) -> float | None:
    """The base scene's time (s) after the end of its record (>= 0), or None when the base has
    no record or stops before its record ends (then the variants keep its duration)."""
    cached = _tails.get(spec.definition.digest, False)
    if cached is not False:
        return cached
    tail = None
    if spec.base_record is not None:
        base = spec.base_scene().expanded
        tail = base.steps * base.dt - record_end(base)
        tail = None if tail < -0.5 * base.dt else max(tail, 0.0)
    _tails[spec.definition.digest] = tail
    return tail


_tails: dict[str, float | None] = {}


def fitted_steps(spec, loaded) -> int:
    """The steps variant ``loaded`` runs: its record's length plus the base's tail, on its
    own step (module docstring); its own steps when the base has no record or cuts it."""
    tail = record_tail(spec)
    expanded = loaded.expanded
    if tail is None or expanded.record is None:
        return expanded.steps
    return max(1, math.ceil((record_end(expanded) + tail) / expanded.dt - 1e-9))


def load_fitted(spec, index: int, folder: Path) -> LoadedScene:
    """Variant ``index`` loaded, with its duration fitted to its record (:func:`fitted_steps`)."""
    loaded = load_variant(variant_data(spec, index), spec.base_lines, spec.base_where, folder)
    steps = fitted_steps(spec, loaded)
    if steps != loaded.expanded.steps:
        loaded = load_variant(variant_data(spec, index, steps=steps), spec.base_lines,
                              spec.base_where, folder)
    return loaded


def steps_override(spec, index: int, folder: Path) -> int | None:
    """The steps :func:`load_fitted` sets in variant ``index``'s data (None: as written)."""
    loaded = load_variant(variant_data(spec, index), spec.base_lines, spec.base_where, folder)
    steps = fitted_steps(spec, loaded)
    return None if steps == loaded.expanded.steps else steps


def cut_warning(spec, index: int, expanded) -> str | None:
    """What a variant's analysis leaves out of its record (None if it runs it whole)."""
    end = record_end(expanded)
    if end is None:
        return None
    duration = expanded.steps * expanded.dt
    if end <= duration + 0.5 * expanded.dt:
        return None
    peak = record_peak_time(expanded)
    missed = (f"its peak ground acceleration (t = {peak:.4g} s) is past the end, so the "
              "response to it is missing" if peak > duration else
              "its peak ground acceleration is inside")
    return (f"variant {index} ({spec.describe(index)}): the analysis stops at "
            f"{duration:.4g} s, but the record runs to {end:.4g} s ({missed}); the base "
            "scene's analysis.duration is shorter than its own record, which a sweep reads "
            "as a cut every variant keeps: make the base's duration at least its record's "
            "length (and longer for free vibration) to run every record to its end")


_folders: dict[str, Path] = {}


def _remove_folders():
    for folder in _folders.values():
        shutil.rmtree(folder, ignore_errors=True)


def materialise(definition) -> Path:
    """A private folder of this process holding the sweep's record files under their keys.

    A sweep carries its record files' contents, so a variant reads the same bytes on this
    machine and on any cluster worker, whatever their file systems hold.
    """
    folder = _folders.get(definition.digest)
    if folder is None:
        if not _folders:
            atexit.register(_remove_folders)
        folder = Path(tempfile.mkdtemp(prefix="pframe-sweep-"))
        for key, content in definition.files:
            (folder / key).write_bytes(content)
        _folders[definition.digest] = folder
    return folder
