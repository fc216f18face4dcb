"""Variants as scenes: the base scene's data with the swept values set, validated by the loader.

Each variant goes through the same steps as a scene file (Pi-form expansion, plug-in laws, the
pydantic model, expansion to numbers) from YAML data that is composed once for the whole sweep;
composing YAML text is most of what :func:`pframe.reader.parse_scene` costs, and a sweep has
thousands of variants. ``tests/test_sweep.py`` checks that both roads give the same scene.
"""

from __future__ import annotations

import atexit
import copy
import shutil
import tempfile
from pathlib import Path

from pframe.reader import LoadedScene, scene_from_data
from pframe.sweep.paths import put


def load_variant(data: dict, lines: dict, source: str, base_dir: Path) -> LoadedScene:
    """Validate scene data as :func:`pframe.reader.parse_scene` validates the data of a file;
    ``lines`` are the base scene's (a variant has the base's layout, so they still apply)."""
    return scene_from_data(data, lines, source, base_dir)


def variant_data(spec, index: int, record_path=None) -> dict:
    """The base scene's data with variant ``index``'s values set. Record files are named by
    ``record_path(key)`` (default: the key, a file in the folder :func:`materialise` fills)."""
    record_path = record_path or (lambda key: key)
    data = copy.deepcopy(spec.base_data)
    if spec.base_record is not None:
        put(data, ("excitation", "file"), record_path(spec.base_record))
    for axis, position in zip(spec.axes, spec.positions(index)):
        value = axis.values[position]
        if axis.is_file:
            value = record_path(value)
        for path in axis.paths:
            put(data, path, value)
    return data


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
