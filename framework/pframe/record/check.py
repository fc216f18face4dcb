"""Is a result file whole? Checks made before a file is opened for reading (``pframe.open``,
``pframe plot``), so that a damaged file is answered with a :class:`~pframe.errors.InputError`
naming the file and what is wrong, never a ``KeyError`` from deep in h5py or a
``MemoryError`` from a header that claims more than the file holds.

What is checked, with h5py, without reading any values:

- the file opens as HDF5;
- every reference between variables and their dimensions (netCDF-4's ``DIMENSION_LIST`` and
  ``REFERENCE_LIST``) leads to an object that is there: a variable removed with an HDF5 tool
  leaves its dimensions pointing at nothing (a *dangling reference*);
- every variable named in a ``coordinates`` attribute exists;
- every variable's data is stored: the chunks (or the contiguous block) a variable's shape
  claims are present. pframe writes every value of every variable it lays out, so in a file
  of pframe's (``pframe_version``) a variable with chunks missing has a header that does not
  match its data (a history "of 10^9 rows" in a file of a few MB);
- (:func:`check_fits`) the values about to be read fit in memory.
"""

from __future__ import annotations

import math
import re
from pathlib import Path

from pframe.errors import EnvironmentFailure, InputError

#: attributes that hold HDF5 object references (netCDF-4's dimension scales)
_REFERENCES = ("DIMENSION_LIST", "REFERENCE_LIST")
#: how netCDF-4 marks a dimension that is not a variable (its dataset holds no values)
_DIMENSION_ONLY = b"This is a netCDF dimension but not a netCDF variable"


def _referenced(f, ref) -> str | None:
    """The name of the object ``ref`` leads to in ``f`` (None: nothing, a dangling reference)."""
    try:
        if not ref:
            return None
        name = f[ref].name
    except (KeyError, ValueError, RuntimeError, OSError):
        return None
    return name


def _references(value):
    """The object references in a ``DIMENSION_LIST`` / ``REFERENCE_LIST`` attribute value."""
    import h5py

    if getattr(value, "dtype", None) is not None and value.dtype.names:  # REFERENCE_LIST
        for row in value:
            yield row[0]
        return
    for item in value:  # DIMENSION_LIST: an array (one per dimension) of arrays of refs
        yield from (item if not isinstance(item, h5py.Reference) else (item,))


def _stored(dataset) -> tuple[int, int]:
    """(units stored, units claimed) of a dataset's data: chunks for a chunked one, bytes for
    a contiguous one."""
    shape = dataset.shape or ()
    if dataset.chunks is None:
        claimed = math.prod(shape) * dataset.dtype.itemsize
        return (claimed if claimed == 0 else dataset.id.get_storage_size()), claimed
    claimed = math.prod(-(-n // c) for n, c in zip(shape, dataset.chunks))
    if claimed == 0:
        return 0, 0
    return dataset.id.get_num_chunks(), claimed


def file_kind(path: str | Path) -> str | None:
    """What wrote a result file: ``sweep`` (pframe sweep), its ``pframe_kind``
    (``gap_audit``, ``risk_study``), or None (pframe solve's, or a file that cannot be read
    as HDF5)."""
    import h5py

    try:
        with h5py.File(path, "r") as f:
            if "sweep_axes" in f.attrs:
                return "sweep"
            value = f.attrs.get("pframe_kind")
    except OSError:
        return None
    if value is None:
        return None
    return value.decode() if isinstance(value, bytes) else str(value)


def check_file(path: str | Path) -> None:
    """Raise :class:`InputError` if the netCDF-4 file ``path`` is not whole (see the module
    docstring); return quietly when it is."""
    import h5py

    from pframe.outputs import not_regular

    path = Path(path)
    kind = not_regular(path)
    if kind is not None:  # a FIFO would block the reader, a device be read without end
        raise InputError(f"{path}: is {kind}, not a result file; pframe reads the result files "
                         "that pframe solve, sweep and gap write")
    try:
        f = h5py.File(path, "r")
    except OSError as exc:
        found = re.search(r"truncated file: eof = (\d+).*stored_eof = (\d+)", str(exc))
        if found:
            raise InputError(
                f"{path}: a truncated result file: it ends after {int(found.group(1)):,} bytes "
                f"but its header says {int(found.group(2)):,} (a copy or a transfer that did "
                "not finish); copy it again from where pframe wrote it") from None
        raise InputError(f"{path}: not a netCDF-4/HDF5 file; pframe reads the result files "
                         "that pframe solve, sweep and gap write") from None
    with f:
        datasets = {}

        def visit(name, obj):
            if isinstance(obj, h5py.Dataset):
                datasets[name] = obj

        try:
            f.visititems(visit)
        except (KeyError, ValueError, RuntimeError, OSError) as exc:
            raise InputError(f"{path}: a damaged result file: its list of variables cannot be "
                             f"read ({exc})") from None
        dangling, absent, unreadable, lying = [], {}, [], []
        # pframe writes every value it lays out; netCDF-C and other writers may leave a
        # variable unwritten (read as its fill value): only a pframe file is held to it
        written_whole = "pframe_version" in f.attrs
        for name, dataset in datasets.items():
            try:
                attrs = dataset.attrs
                if any(_referenced(f, ref) is None for key in _REFERENCES if key in attrs
                       for ref in _references(attrs[key])):
                    dangling.append(name)
                coordinates = attrs.get("coordinates")
                if coordinates is not None:
                    text = coordinates.decode() if isinstance(coordinates, bytes) else str(
                        coordinates)
                    for c in text.split():
                        if c not in datasets:
                            absent.setdefault(c, []).append(name)
                if bytes(attrs.get("NAME", b"")).startswith(_DIMENSION_ONLY):
                    continue  # a dimension without values: netCDF stores none
                stored, claimed = _stored(dataset)
            except (KeyError, ValueError, RuntimeError, OSError) as exc:
                unreadable.append(f"{name} ({exc})")
                continue
            if written_whole and stored < claimed:
                lying.append((name, dataset, stored, claimed))
        problems = []
        if absent:
            problems.append("variable" + ("s " if len(absent) > 1 else " ") + ", ".join(absent)
                            + " (named as coordinates of " + ", ".join(sorted(
                                {v for names in absent.values() for v in names})[:4])
                            + ") " + ("are" if len(absent) > 1 else "is") + " missing")
        if dangling:
            problems.append(f"{_listed(dangling)} refer to dimensions or variables that are not "
                            "in the file (dangling references: a variable was removed by a tool "
                            "that does not know netCDF)")
        if lying:
            name, dataset, stored, claimed = max(lying, key=lambda x: x[1].size)  # the largest
            shape = " x ".join(f"{n:,}" for n in dataset.shape)
            unit = "chunks" if dataset.chunks is not None else "bytes"
            more = f" (and {len(lying) - 1} more variables)" if len(lying) > 1 else ""
            problems.append(f"{name} claims {shape} values but the file stores only {stored:,} "
                            f"of its {claimed:,} {unit}{more}: its header does not match its "
                            "data")
        if unreadable:
            problems.append(f"{_listed(unreadable)} cannot be read")
        if problems:
            raise InputError(f"{path}: a damaged result file (truncated or altered after pframe "
                             "wrote it): " + "; ".join(problems) + ". Write it again; pframe.load "
                             "still reads its scene if its input_yaml is intact")


def _listed(names: list[str], shown: int = 4) -> str:
    head = ", ".join(names[:shown])
    return head + (f" and {len(names) - shown} more" if len(names) > shown else "")


def check_fits(path, what: str, nbytes: int) -> None:
    """Raise :class:`EnvironmentFailure` if reading ``nbytes`` of ``path`` (``what``: which
    values) into memory would pass pframe's memory limit (:func:`pframe.resources.memory_limit`)."""
    from pframe.resources import human, memory_limit

    limit = memory_limit()
    if nbytes > limit:
        raise EnvironmentFailure(
            f"{path}: {what} need {human(nbytes)} of memory, more than the {human(limit)} "
            "pframe may use (PFRAME_MEMORY_LIMIT, else 80 % of the machine's memory); read a "
            "part of them with pframe.open(...).isel(t=slice(...))")
