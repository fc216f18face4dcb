"""Finished chunks on disk, beside the result file: ``OUT.h5.parts/chunk-00012.npz``.

Each chunk is written under a temporary name and renamed when complete (an ``os.replace``), so
a chunk file either holds a whole chunk or does not exist, whenever the process is killed. A
manifest names the sweep (its definition's digest); a second run of the same sweep takes up the
chunks it finds, and a different sweep is refused rather than mixed in. Each chunk file also
holds its own index and the sweep's digest: a file moved or copied under another chunk's name
(another index's valid chunk, another sweep's) is not taken for that chunk, but removed with a
note and run again. A lock keeps two processes from writing one folder.
"""

from __future__ import annotations

import json
import os
import re
import shutil
import sys
import zipfile
from pathlib import Path

import numpy as np

from pframe import outputs
from pframe.errors import InputError, option

MANIFEST = "sweep.json"
#: what reading a damaged chunk file raises
_DAMAGED = (OSError, ValueError, EOFError, KeyError, TypeError, AttributeError,
            zipfile.BadZipFile)


#: the arrays every chunk file holds besides its data: which chunk of which sweep it is
_INDEX, _DIGEST = "__chunk_index__", "__sweep_digest__"


def _read(path: Path) -> dict:
    """Every array of a chunk file (a zip checks its CRCs); raises one of :data:`_DAMAGED`."""
    with np.load(path, allow_pickle=False) as data:
        arrays = {key: data[key] for key in data.files}
    if not arrays:
        raise ValueError("no arrays")
    return arrays


def _misplaced(arrays: dict, chunk: int, digest: str) -> str | None:
    """Why a whole chunk file is not chunk ``chunk`` of the sweep ``digest`` (None if it is)."""
    index, own = arrays.get(_INDEX), arrays.get(_DIGEST)
    if index is None or own is None:
        return "it does not say which chunk of which sweep it holds"
    if str(own) != digest:
        return "it holds a chunk of another sweep"
    if int(index) != chunk:
        return f"it holds chunk {int(index)}, not chunk {chunk} (moved or copied there)"
    return None
_CHUNK = re.compile(r"^chunk-(\d{5,})\.npz$")


def parts_folder(output: Path) -> Path:
    return output.with_name(output.name + ".parts")


def kept(output: Path) -> int:
    """How many finished chunk files ``OUT.parts`` holds (for the messages on stop and
    resume; whether they belong to this run is decided when it opens them)."""
    try:
        return sum(1 for p in parts_folder(Path(output)).iterdir() if _CHUNK.match(p.name))
    except OSError:
        return 0


class Parts:
    """The folder of finished chunks of one sweep's result file."""

    def __init__(self, output: Path, definition, spec):
        self.output = Path(output)
        self.folder = parts_folder(self.output)
        self.definition = definition
        self.spec = spec
        self._lock = None

    def _manifest(self) -> dict:
        import pframe

        return {"sweep_digest": self.definition.digest, "source": self.definition.source,
                "variants": self.spec.count, "chunk": self.definition.chunk,
                "chunks": self.spec.chunks, "pframe_version": pframe.__version__}

    def open(self, restart: bool = False) -> set[int]:
        """Lock the folder (creating it) and return the chunks already finished.

        A folder of another sweep is an error unless ``restart``, which empties it.
        """
        if self.folder.exists() and not self.folder.is_dir():
            raise InputError(f"{self.folder}: exists and is not a folder; pframe sweep keeps "
                             "its finished chunks there")
        if self.folder.is_dir():
            found = self._read_manifest()
            if found is None or found.get("sweep_digest") != self.definition.digest:
                if not restart:
                    what = (f"chunks of another sweep ({found.get('source', '?')}, "
                            f"{found.get('variants', '?')} variants)" if found else
                            "no readable manifest")
                    raise InputError(
                        f"{self.folder}: holds {what}; the sweep, its base scene, its record "
                        "files, the chunk size or pframe's code have changed since those "
                        f"chunks were computed. Pass {option('overwrite')} to discard them and "
                        f"start again, or choose another output name with {option('output')}")
                self._take_lock()
                self._clear()
        self.folder.mkdir(parents=True, exist_ok=True)
        self._take_lock()
        outputs.remove_stale(self.folder)  # chunks being written when a run was killed
        self._write_atomic(self.folder / MANIFEST,
                           json.dumps(self._manifest(), indent=1).encode())
        return self.finished()

    def _read_manifest(self) -> dict | None:
        try:
            return json.loads((self.folder / MANIFEST).read_text(encoding="utf-8"))
        except (OSError, ValueError):
            return None

    def _take_lock(self):
        if self._lock is not None:
            return
        try:
            import fcntl
        except ImportError:  # not on POSIX: no lock, as before
            return
        self.folder.mkdir(parents=True, exist_ok=True)
        handle = open(self.folder / "lock", "a+b")  # noqa: SIM115 (held until close)
        try:
            fcntl.flock(handle, fcntl.LOCK_EX | fcntl.LOCK_NB)
        except OSError:
            handle.close()
            raise InputError(f"{self.folder}: another pframe sweep is writing this output "
                             f"now; wait for it, or choose another name with {option('output')}"
                             ) from None
        self._lock = handle

    def _clear(self):
        for path in self.folder.iterdir():
            if path.name != "lock":
                path.unlink()

    def finished(self) -> set[int]:
        """The chunks saved whole; a damaged one (truncated, not an archive) is removed, with
        a note, and runs again."""
        done = set()
        for path in sorted(self.folder.iterdir()):
            match = _CHUNK.match(path.name)
            if match and int(match.group(1)) < self.spec.chunks:
                chunk = int(match.group(1))
                try:
                    why = _misplaced(_read(path), chunk, self.definition.digest)
                except _DAMAGED:
                    why = "damaged (not a whole chunk)"
                if why is not None:
                    path.unlink(missing_ok=True)
                    print(f"pframe: {path}: {why}; removed, it runs again", file=sys.stderr)
                    continue
                done.add(chunk)
        return done

    def path(self, chunk: int) -> Path:
        return self.folder / f"chunk-{chunk:05d}.npz"

    @staticmethod
    def _write_atomic(path: Path, payload: bytes | None = None, arrays: dict | None = None):
        with outputs.replacing(path, overwrite=True, clean=False) as tmp, open(tmp, "wb") as handle:
            if arrays is not None:
                np.savez(handle, **arrays)
            else:
                handle.write(payload)
            handle.flush()
            os.fsync(handle.fileno())

    def save(self, chunk: int, arrays: dict) -> None:
        self._write_atomic(self.path(chunk), arrays={
            **arrays, _INDEX: np.int64(chunk), _DIGEST: np.str_(self.definition.digest)})

    def load_finished(self, restart: bool, whose: str) -> dict[int, dict]:
        """Open the folder (as :meth:`open`) and load its finished chunks; a folder of another
        study says so with ``whose`` (what may have changed: "scene, suite, design, ...")."""
        try:
            return {c: self.load(c) for c in self.open(restart=restart)}
        except InputError as exc:
            if "holds" not in str(exc):
                raise
            raise InputError(f"{self.folder}: holds batches of another study (another "
                             f"{whose} or pframe code); pass {option('overwrite')} to discard "
                             f"them, or choose another {option('output')}") from None

    def load(self, chunk: int) -> dict:
        """The arrays of a finished chunk (as saved, without its index and digest)."""
        try:
            arrays = _read(self.path(chunk))
        except _DAMAGED as exc:
            raise InputError(f"{self.path(chunk)}: a finished chunk is damaged ({exc}); "
                             "delete it and run the same command again") from None
        why = _misplaced(arrays, chunk, self.definition.digest)
        if why is not None:  # replaced since the folder was opened
            raise InputError(f"{self.path(chunk)}: not this sweep's chunk {chunk}: {why}; "
                             "delete it and run the same command again")
        return {k: v for k, v in arrays.items() if k not in (_INDEX, _DIGEST)}

    def close(self):
        """Release the lock; a folder that holds no finished chunk (a run stopped or refused
        before its first chunk, a wrong scheduler address) is removed with it: it has
        nothing to resume from, and its lock and manifest would only be left behind."""
        if self._lock is None:
            return
        try:
            if not kept(self.output):
                shutil.rmtree(self.folder, ignore_errors=True)
        finally:
            self._lock.close()
            self._lock = None

    def remove(self):
        """Delete the folder (after the result file is complete)."""
        self.close()
        shutil.rmtree(self.folder, ignore_errors=True)
