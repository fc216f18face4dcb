"""Reading a sweep: its file, base scene and record files into a :class:`SweepDefinition`."""

from __future__ import annotations

import hashlib
import os
from pathlib import Path

from pframe.errors import InputError, given
from pframe.excitation.records import MAX_RECORD_BYTES, read_record, read_series
from pframe.model.load import read_input
from pframe.objects import value_at
from pframe.sweep.definition import validated_sweep
from pframe.sweep.paths import scene_records, series_files
from pframe.sweep.spec import SweepDefinition, code_fingerprint
from pframe.yamltext import MAX_YAML_BYTES, read_bounded_bytes
from pframe.yamltext import compose as _compose
from pframe.yamltext import where as _where


def _read_bytes(path: Path, where: str, what: str, limit: int = MAX_YAML_BYTES) -> bytes:
    """A file the sweep names, read under the guard of every input (a regular file of
    bounded size: a FIFO or a device is refused, never read)."""
    try:
        return read_bounded_bytes(path, what, limit)
    except FileNotFoundError:
        raise InputError(f"{where}: {what} {str(path)!r} not found") from None
    except InputError as exc:
        raise InputError(f"{where}: {exc}") from None


def _record(path: Path, folder: Path, where: str, quantity: str | None = None) -> bytes:
    """A record file's bytes (or of its ``quantity`` file: 'displacement', 'velocity'). One
    outside ``folder`` (the file that names it is in ``folder``) is read here, so that a
    problem in it is told without its text (the copy every variant reads lies in a private
    folder, where it would be quoted)."""
    content = _read_bytes(path, where, "record file", MAX_RECORD_BYTES)
    if not path.resolve().is_relative_to(folder.resolve()):
        try:
            if quantity is None:
                read_record(path, within=folder)
            else:
                read_series(path, quantity, within=folder)
        except (ValueError, OSError) as exc:
            raise InputError(f"{where}: malformed record: {exc}") from None
    return content


def _record_key(content: bytes, name: str) -> str:
    return f"{hashlib.sha256(content).hexdigest()[:16]}-{Path(name).name}"


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
    model, lines = validated_sweep(text, source)
    if chunk is not None and chunk < 1:
        raise InputError(f"{given('chunk', chunk)}: a chunk holds at least one variant")
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
        content = _record(file, base_dir, base_source or source)
        key = _record_key(content, file.name)
        files[key] = content
        records.append(("base", excitation["file"], key, str(file.resolve())))
    for path, motion in scene_records(base_data):  # components, a wave passage, supports
        file = base_dir / motion["file"]
        content = _record(file, base_dir, base_source or source)
        key = _record_key(content, file.name)
        files[key] = content
        records.append(("scene", ".".join(map(str, path)), key, str(file.resolve())))
    for path in series_files(base_data):  # a record's displacement and velocity files
        file = base_dir / value_at(base_data, path)
        content = _record(file, base_dir, base_source or source, path[-1])
        key = _record_key(content, file.name)
        files[key] = content
        records.append(("scene", ".".join(map(str, path)), key, str(file.resolve())))
    for i, axis in enumerate(model.axes):
        if not axis.is_file:
            continue
        for j, value in enumerate(axis.points()):
            if not isinstance(value, str):
                raise InputError(f"{_where(source, lines, ('axes', i, 'values', j))}: a records "
                                 f"axis (path excitation.file) takes file names, not {value!r}")
            file = folder / value
            content = _record(file, folder, _where(source, lines, ("axes", i, "values", j)))
            key = _record_key(content, file.name)
            files[key] = content
            records.append(("axis", value, key, str(file.resolve())))

    definition = SweepDefinition(
        source=source, text=text, base_source=base_source, base_text=base_text,
        base_dir=str(Path(base_dir).resolve()), files=tuple(sorted(files.items())),
        records=tuple(records), chunk=chunk or model.chunk, code=code_fingerprint())
    from pframe.sweep.probing import check

    check(definition)
    return definition
