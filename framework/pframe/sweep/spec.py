"""A sweep's definition: what a run depends on, as plain data (picklable for a cluster).

Everything a variant's numbers depend on is in :class:`SweepDefinition`: the sweep file's text,
the base scene's text, the contents of every record file, the chunk size and pframe's code.
Its :attr:`~SweepDefinition.digest` keys the resumable output; a chunk is a pure function of
the definition and the chunk's index, whichever process or machine computes it.

The sweep package, one idea per module: ``definition`` (the sweep file's model), ``spec``
(this: what a run depends on), ``reading`` (files to a definition), ``grid`` (the variants:
axes resolved in the base scene), ``probing`` (the checks before a run), ``variants``,
``chunk``, ``store``, ``runner``, ``output``.
"""

from __future__ import annotations

import functools
import hashlib
import json
from dataclasses import dataclass
from pathlib import Path

#: bumped when the chunk files' contents change meaning
FORMAT_VERSION = "2"
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
