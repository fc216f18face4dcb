"""Read the histories a figure needs from a result file (docs/hdf5.md), without matplotlib.

A history is ``quantity(time, entity)`` with ``entity`` one of ``node``, ``story``,
``contact``. A file that is not a pframe result, or holds a sweep (extra leading dimensions
before ``time``), is refused with an :class:`~pframe.errors.InputError` naming the file: the
reader is the one place that knows the layout, so a later sweep layout changes this module
only (select one member here, and the figures stay as they are).
"""

from __future__ import annotations

from dataclasses import dataclass, field, replace
from pathlib import Path

import numpy as np

from pframe.errors import InputError
from pframe.plot.levels import Levels, group_by_level
from pframe.plot.scales import DIMENSIONLESS, Reference

#: the histories the figures draw, in the order of the paper's panels
PLOTTED = ("displacement", "contact_force", "velocity", "story_drift", "story_force")
ENTITIES = ("node", "story", "contact")


@dataclass(frozen=True)
class History:
    """One recorded history: ``values[k, j]`` is entity ``names[j]`` at ``time[k]``.

    Attributes
    ----------
    quantity : str
        The variable's name in the file, e.g. ``displacement``.
    time : ndarray, shape (n,)
        Its time coordinate (``time`` or ``time_every_N``), in ``time_units``.
    values : ndarray, shape (n, m)
        In ``units``.
    names : tuple of str
        The entity coordinate (node, storey or contact names).
    units, time_units : str
        The ``units`` attributes; ``"1"`` for dimensionless values.
    """

    quantity: str
    time: np.ndarray
    values: np.ndarray
    names: tuple[str, ...]
    units: str
    time_units: str

    def column(self, name: str) -> np.ndarray:
        """The history of one entity, by name."""
        return self.values[:, self.names.index(name)]


@dataclass(frozen=True)
class Result:
    """What a result file holds for plotting.

    Attributes
    ----------
    path : Path
        The file.
    title : str
        The scene's title.
    histories : dict
        ``quantity -> History`` for the recorded quantities of :data:`PLOTTED`.
    levels : Levels
        Nodes, storeys and contacts grouped by floor level.
    has_stories, has_contacts : bool
        Whether the scene has storeys and contacts (recorded or not).
    complete : bool
        False when the run stopped early (``status`` says why).
    status : str
    input_yaml : str or None
        The scene text the file holds.
    reference : Reference or None
        The scales used when the histories were made dimensionless by :meth:`dimensionless`.
    dropped : tuple of str
        Notes on histories left out by a conversion.
    """

    path: Path
    title: str
    histories: dict[str, History]
    levels: Levels
    has_stories: bool
    has_contacts: bool
    complete: bool
    status: str
    input_yaml: str | None = None
    reference: Reference | None = None
    dropped: tuple[str, ...] = field(default=())

    @property
    def is_dimensionless(self) -> bool:
        """True when the time axis is the paper's tau (``units`` ``"1"``)."""
        return any(h.time_units == DIMENSIONLESS for h in self.histories.values())

    def window(self, start: float, stop: float) -> Result:
        """The part ``start <= t <= stop`` of every history (in the units of its time)."""
        if not start < stop:
            raise InputError(f"{self.path}: --time-range {start:g} {stop:g}: the start must be "
                             "before the end")
        histories = {}
        for q, h in self.histories.items():
            keep = (h.time >= start) & (h.time <= stop)
            histories[q] = replace(h, time=h.time[keep], values=h.values[keep])
        if histories and not any(h.time.size for h in histories.values()):
            first = next(iter(self.histories.values())).time
            raise InputError(f"{self.path}: no recorded time in --time-range {start:g} {stop:g}; "
                             f"the histories run from {first[0]:g} to {first[-1]:g}")
        return replace(self, histories=histories)

    def dimensionless(self, reference: Reference) -> Result:
        """The histories in the paper's dimensionless variables (see :mod:`pframe.plot.scales`).

        A file already dimensionless is returned as it is; a history in units without a scale
        is left out with a note.
        """
        if self.is_dimensionless:
            return self
        histories, dropped = {}, list(self.dropped)
        for q, h in self.histories.items():
            scale, time_scale = reference.factor(h.units), reference.factor(h.time_units)
            if scale is None or time_scale is None:
                dropped.append(f"{q} in {h.units!r} has no dimensionless form; left out")
                continue
            histories[q] = replace(h, time=h.time * time_scale, values=h.values * scale,
                                   units=DIMENSIONLESS, time_units=DIMENSIONLESS)
        return replace(self, histories=histories, reference=reference, dropped=tuple(dropped))


def _text(value) -> str:
    return value.decode() if isinstance(value, bytes) else str(value)


def _dimension_names(dset) -> list[str | None]:
    names = []
    for dim in dset.dims:
        names.append(dim[0].name.rsplit("/", 1)[-1] if len(dim) else None)
    return names


def _read_history(f, path: Path, quantity: str) -> History | None:
    dset = f[quantity]
    dims = _dimension_names(dset)
    if dset.ndim > 2:
        shape = ", ".join(f"{d or '?'}={n}" for d, n in zip(dims, dset.shape))
        raise InputError(
            f"{path}: the file holds a sweep ({quantity} has the dimensions {shape}); "
            "pframe plot draws single runs, whose histories are (time, node|story|contact)")
    if dset.ndim != 2 or dims[1] not in ENTITIES or dims[0] is None \
            or not dims[0].startswith("time"):
        return None
    time = f[dims[0]]
    return History(quantity, np.asarray(time[...], dtype=float), np.asarray(dset[...], dtype=float),
                   tuple(f[dims[1]].asstr()[...]), _text(dset.attrs.get("units", "")),
                   _text(time.attrs.get("units", "")))


def read_result(path: str | Path) -> Result:
    """Read the plottable histories of a result file written by ``pframe solve``.

    Parameters
    ----------
    path : str or Path
        An HDF5 result file (layout in docs/hdf5.md).

    Raises
    ------
    InputError
        The file is missing, is not HDF5, is not a pframe result, or holds a sweep.
    """
    import h5py

    path = Path(path)
    if not path.exists():
        raise InputError(f"{path}: no such result file")
    if path.is_dir():
        raise InputError(f"{path}: a folder, not a result file; pass the .h5 file pframe solve wrote")
    try:
        f = h5py.File(path, "r")
    except OSError:
        raise InputError(f"{path}: not an HDF5 file; pframe plot reads the result files "
                         "that pframe solve writes") from None
    with f:
        if "pframe_version" not in f.attrs or "node" not in f:
            raise InputError(f"{path}: an HDF5 file, but not a pframe result (it has no "
                             "pframe_version attribute and node coordinate); pframe plot reads "
                             "the result files that pframe solve writes")
        histories = {}
        for quantity in PLOTTED:
            if quantity in f:
                history = _read_history(f, path, quantity)
                if history is not None:
                    histories[quantity] = history
        names = {e: tuple(f[e].asstr()[...]) if e in f else () for e in ENTITIES}
        input_yaml = _text(f.attrs["input_yaml"]) if "input_yaml" in f.attrs else None
        levels: Levels = group_by_level(names["node"], names["story"], names["contact"],
                                        input_yaml)
        return Result(
            path=path,
            title=_text(f.attrs.get("title", path.stem)),
            histories=histories,
            levels=levels,
            has_stories=bool(names["story"]),
            has_contacts=bool(names["contact"]),
            complete=bool(f.attrs.get("complete", 1)),
            status=_text(f.attrs.get("status", "")),
            input_yaml=input_yaml,
        )
