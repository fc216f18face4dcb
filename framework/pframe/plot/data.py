"""Read the histories a figure needs from a result (docs/netcdf.md), without matplotlib.

A result is a file or the xarray Dataset of ``pframe.solve``/``pframe.open``. A history is
``quantity(t, entity)`` with ``entity`` one of ``node``, ``story``, ``contact``, ``point``.
A scene in plan (its file has a ``direction`` dimension) writes a floor quantity along the
site's x and y, ``displacement(t, node, direction)``, and a named point's along its
building's axes, ``point_drift(t, point, axis)``: each component is read as a history of its
own, ``displacement_x``, ``displacement_y``, ``point_drift_x``, ... (with the rotations
``displacement_rz``, ...), so that every figure and conversion works on two-dimensional
histories. A file that is not a pframe result, or holds a sweep (extra leading dimensions
before ``t``), is refused with an :class:`~pframe.errors.InputError` naming the file: the
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
#: and those of a scene in plan: the floors' rotations, the named plan points
PLOTTED_PLAN = ("displacement_rz", "velocity_rz", "point_displacement", "point_drift")
ENTITIES = ("node", "story", "contact", "point")
#: the trailing dimension of a quantity of a scene in plan: its components, each read as the
#: history ``<quantity>_<component>`` (the site's x and y, or its building's axes)
COMPONENTS = ("direction", "axis")


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
    contacts, gaps, gap_units
        Each contact's two nodes and its gap (the pounding figure's gap line).
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
    #: the scene is in plan: floors move along x and y and turn (pframe.plot.plan draws it)
    plan: bool = False
    #: floor -> the torsional irregularity ratio of the storey below it along its building's
    #: x and y (``torsional_irregularity``; NaN where not defined)
    torsion: dict = field(default_factory=dict)
    attributes: dict = field(default_factory=dict, repr=False)
    #: contact -> (left node, right node), from the file's connectivity
    contacts: dict = field(default_factory=dict)
    #: contact -> its initial gap, in ``gap_units`` (the file's ``contact_gap``)
    gaps: dict = field(default_factory=dict)
    gap_units: str = ""
    #: contact -> the run's own count of impacts (``impact_count``; none for a time window)
    impacts: dict = field(default_factory=dict)
    #: floor-to-column contact -> (side 0 or 1 whose node tops the struck storey, the
    #: storey's lower floor or "ground", the weight psi of its upper floor, at)
    columns: dict = field(default_factory=dict)

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
        return replace(self, histories=histories, impacts={})

    def in_units(self, units) -> Result:
        """The histories in other units: ``"engineering"`` (mm, mm/s, kN, kN m) or a mapping
        from the stored units to the units wanted, e.g. ``{"m": "mm", "N": "kN"}``."""
        wanted = engineering_units(units)
        histories = {}
        for q, h in self.histories.items():
            target = wanted.get(h.units)
            if target is None or target == h.units:
                histories[q] = h
                continue
            histories[q] = replace(h, values=h.values * conversion(h.units, target),
                                   units=target)
        gaps, gap_units = self.gaps, self.gap_units
        target = wanted.get(gap_units)
        if target is not None and target != gap_units:
            factor = conversion(gap_units, target)
            gaps, gap_units = {k: v * factor for k, v in gaps.items()}, target
        return replace(self, histories=histories, gaps=gaps, gap_units=gap_units)

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
        gaps, gap_units = {}, self.gap_units
        scale = reference.factor(self.gap_units) if self.gaps else None
        if scale is not None:
            gaps = {k: v * scale for k, v in self.gaps.items()}
            gap_units = DIMENSIONLESS
        return replace(self, histories=histories, reference=reference, dropped=tuple(dropped),
                       gaps=gaps, gap_units=gap_units)


#: stored SI units -> {display units: factor}
CONVERSIONS = {
    "m": {"m": 1.0, "cm": 1e2, "mm": 1e3},
    "m/s": {"m/s": 1.0, "cm/s": 1e2, "mm/s": 1e3},
    "m/s^2": {"m/s^2": 1.0, "cm/s^2": 1e2, "mm/s^2": 1e3, "g": 1.0 / 9.80665},
    "N": {"N": 1.0, "kN": 1e-3, "MN": 1e-6},
    "s": {"s": 1.0, "ms": 1e3},
}
#: ``units="engineering"``
ENGINEERING = {"m": "mm", "m/s": "mm/s", "N": "kN"}


def engineering_units(units) -> dict:
    """The mapping stored units -> display units that ``units`` asks for (None: none)."""
    if units is None:
        return {}
    if isinstance(units, str) and units == "engineering":
        return dict(ENGINEERING)
    if isinstance(units, str):  # "mm,kN": each display unit finds its SI unit
        wanted = {}
        for unit in (u.strip() for u in units.split(",") if u.strip()):
            base = next((si for si, table in CONVERSIONS.items() if unit in table), None)
            if base is None:
                known = ", ".join(u for table in CONVERSIONS.values() for u in table)
                raise InputError(f"units {unit!r}: not a unit pframe converts to; choose from "
                                 f"{known}, or 'engineering' (mm, mm/s, kN)")
            wanted[base] = unit
        return wanted
    from collections.abc import Mapping

    if not isinstance(units, Mapping) or not all(
            isinstance(k, str) and isinstance(v, str) for k, v in units.items()):
        shown = " ".join(repr(units).split())[:60]
        raise InputError(f"units={shown}: give 'engineering', a string such as 'mm,kN', or a "
                         "mapping of stored units to the units shown, such as "
                         "{'m': 'mm', 'N': 'kN'}")
    return dict(units)


def conversion(stored: str, target: str) -> float:
    table = CONVERSIONS.get(stored, {})
    if target not in table:
        raise InputError(f"units: cannot show {stored!r} in {target!r}; "
                         f"choose one of {', '.join(table) or '(none)'}")
    return table[target]


def _text(value) -> str:
    return value.decode() if isinstance(value, bytes) else str(value)


def _names(ds, entity: str) -> tuple[str, ...]:
    """The names along ``entity``: its label variable (``node_name``), else (files of
    pframe 0.1 before the CF layout) a string coordinate named as the dimension."""
    for name in (f"{entity}_name", entity):
        if name in ds.variables and ds[name].dims == (entity,):
            return tuple(str(v) for v in ds[name].values.tolist())
    return ()


def _time_dimension(dim: str) -> bool:
    return dim in ("t", "time") or dim.startswith(("t_every_", "time_every_"))


def _read_histories(ds, source: str, quantity: str) -> list[History]:
    """The histories of one variable: itself, or each of its components (:data:`COMPONENTS`)."""
    var = ds[quantity]
    dims = var.dims
    components = var.ndim == 3 and dims[2] in COMPONENTS and dims[1] in ENTITIES
    if var.ndim > 2 and not components:
        shape = ", ".join(f"{d}={n}" for d, n in zip(dims, var.shape))
        raise InputError(
            f"{source}: the file holds a sweep ({quantity} has the dimensions {shape}); "
            "pframe plot draws single runs, whose histories are (t, node|story|contact)")
    if var.ndim not in (2, 3) or dims[1] not in ENTITIES or not _time_dimension(dims[0]):
        return []
    time = ds[dims[0]]
    values = np.asarray(var.values, dtype=float)
    read = [(quantity, values)] if not components else [
        (f"{quantity}_{label}", values[:, :, k])
        for k, label in enumerate(_names(ds, dims[2]) or ("x", "y")[:values.shape[2]])]
    return [History(name, np.asarray(time.values, dtype=float), columns, _names(ds, dims[1]),
                    _text(var.attrs.get("units", "")), _text(time.attrs.get("units", "")))
            for name, columns in read]


def _connectivity(ds) -> tuple[dict, dict] | None:
    """From the file: storey -> upper node and contact -> (left, right) (None for files
    written before connectivity was stored)."""
    stories, contacts = {}, {}
    if "story_upper" in ds.variables:
        stories = dict(zip(_names(ds, "story"), map(str, ds["story_upper"].values.tolist())))
    if "contact_left" in ds.variables:
        contacts = dict(zip(_names(ds, "contact"),
                            zip(map(str, ds["contact_left"].values.tolist()),
                                map(str, ds["contact_right"].values.tolist()))))
    has_stories = bool(_names(ds, "story"))
    has_contacts = bool(_names(ds, "contact"))
    if (has_stories and not stories) or (has_contacts and not contacts):
        return None
    return stories, contacts


def open_result(source):
    """``(dataset, name)`` of a result: a path (opened with xarray) or a Dataset."""
    from pframe.api import result_argument

    source = result_argument(source, "pframe.plot")
    if not isinstance(source, Path):
        return source, str(source.attrs.get("source", "the Dataset"))
    path = source
    if not path.exists():
        raise InputError(f"{path}: no such result file")
    if path.is_dir():
        raise InputError(f"{path}: a folder, not a result file; pass the file pframe solve "
                         "wrote")
    import xarray as xr

    from pframe.record.check import check_file

    check_file(path)  # a damaged file: what is wrong, not h5py's KeyError or MemoryError
    try:
        ds = xr.open_dataset(path, engine="h5netcdf", phony_dims="access")
    except (OSError, ValueError):
        raise InputError(f"{path}: not a netCDF-4/HDF5 file; pframe plot reads the result "
                         "files that pframe solve writes") from None
    return ds, str(path)


def read_result(source) -> Result:
    """Read the plottable histories of a result (``pframe solve``'s file, or the Dataset of
    ``pframe.solve``/``pframe.open``).

    Raises
    ------
    InputError
        The file is missing, is not netCDF-4/HDF5, is not a pframe result, or holds a sweep.
    """
    ds, name = open_result(source)
    path = Path(source) if isinstance(source, (str, Path)) else Path(name)
    if "pframe_version" not in ds.attrs or not _names(ds, "node"):
        raise InputError(f"{name}: a netCDF/HDF5 file, but not a pframe result (it has no "
                         "pframe_version attribute and node names); pframe plot reads "
                         "the result files that pframe solve writes")
    from pframe.record.check import check_fits

    plan = "direction" in ds.dims
    plotted = PLOTTED + PLOTTED_PLAN if plan else PLOTTED
    check_fits(name, "its histories", sum(
        ds[q].size * 8 + ds[q][ds[q].dims[0]].size * 8 for q in plotted
        if q in ds.variables and ds[q].ndim >= 1))
    histories = {}
    for quantity in plotted:
        if quantity in ds.variables:
            histories.update((h.quantity, h) for h in _read_histories(ds, name, quantity))
    names = {e: _names(ds, e) for e in ENTITIES}
    dropped, torsion = (), {}
    if plan:
        from pframe.plot.plan_data import CLOSING, contact_closing, torsion_ratios

        closing, why = contact_closing(ds, name, histories, names["contact"])
        if closing is not None:  # at the floors' times, in their units (m)
            floors = histories["displacement_x"]
            histories[CLOSING] = replace(floors, quantity=CLOSING, values=closing,
                                         names=names["contact"])
        dropped = (why,) if why else ()
        torsion = torsion_ratios(ds, names["node"])
    input_yaml = _text(ds.attrs["input_yaml"]) if "input_yaml" in ds.attrs else None
    known = _connectivity(ds)
    levels: Levels = group_by_level(names["node"], names["story"], names["contact"],
                                    input_yaml if known is None else None, known=known)
    gaps, gap_units = {}, ""
    if "contact_gap" in ds.variables and names["contact"]:
        values = np.asarray(ds["contact_gap"].values, dtype=float).ravel()
        if values.size == len(names["contact"]):
            gaps = dict(zip(names["contact"], map(float, values)))
            gap_units = _text(ds["contact_gap"].attrs.get("units", ""))
    columns = {}
    if "contact_column" in ds.variables and "contact_at" in ds.variables:
        from pframe.model.expand import column_share

        for name, side, lower, at in zip(names["contact"],
                                         map(str, ds["contact_column"].values.tolist()),
                                         map(str, ds["contact_column_lower"].values.tolist()),
                                         np.asarray(ds["contact_at"].values, float)):
            if side in ("left", "right"):
                columns[name] = (("left", "right").index(side), lower,
                                 column_share(float(at)), float(at))
    impacts = {}
    if "impact_count" in ds.variables and names["contact"]:
        counts = np.asarray(ds["impact_count"].values).ravel()
        if counts.size == len(names["contact"]):
            impacts = dict(zip(names["contact"], map(int, counts)))
    return Result(
        path=path,
        title=_text(ds.attrs.get("title", path.stem)),
        histories=histories,
        levels=levels,
        has_stories=bool(names["story"]),
        has_contacts=bool(names["contact"]),
        complete=bool(ds.attrs.get("complete", 1)),
        status=_text(ds.attrs.get("status", "")),
        input_yaml=input_yaml,
        reference=None,
        dropped=dropped,
        plan=plan,
        torsion=torsion,
        attributes=dict(ds.attrs),
        contacts=dict(known[1]) if known is not None else {},
        gaps=gaps,
        gap_units=gap_units,
        impacts=impacts,
        columns=columns,
    )
