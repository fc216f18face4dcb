"""A response spectrum of a sweep file (``pframe sweep``): a response against one swept axis,
one curve per building, contact, storey or node, or per value of another axis.

::

    from pframe.plot.spectrum import spectrum

    fig, notes = spectrum("pi-d.h5")                            # building_peak_displacement(Pi_d)
    fig, notes = spectrum("gaps.h5", response="peak_contact_force", x="gap",
                          curves="frequency", at={"contact": "floor-1"})

Dimensions that are neither the x axis nor the curves are either fixed with ``at``
(``{"frequency": 3.0}``: the nearest value on the axis; ``{"node": "A/3"}``) or reduced to
their largest value (the envelope), and the figure says which. Variants that did not complete
are left out, with a note. Reading needs h5py only; drawing, matplotlib.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from pframe.errors import InputError

ENTITIES = ("node", "story", "contact", "building")
#: responses drawn when none is named, the first one the file holds
PREFERRED = ("building_peak_displacement", "peak_displacement", "peak_contact_force",
             "building_peak_ductility", "ductility", "peak_story_drift", "impact_count")
_NOT_RESPONSES = {"complete", "status", "steps_completed", "energy_balance_error",
                  "algorithmic_dissipation", "trusted",
                  "newton_solves", "split_steps", "dt", "duration", "record_duration",
                  "scale_m_b", "scale_a_p", "scale_w_p"}


def _text(value) -> str:
    return value.decode() if isinstance(value, bytes) else str(value)


def _strings_or_numbers(values) -> np.ndarray:
    values = np.asarray(values)
    if values.dtype.kind in "OSU":
        return np.array([_text(v) for v in values], dtype=object)
    return values


class _Sweep:
    """What a spectrum needs from a sweep file (read with xarray: names are label variables,
    ``node_name`` along ``node``, ``<axis>_file`` along a records axis)."""

    def __init__(self, path: Path):
        import xarray as xr

        from pframe.record.check import check_file

        check_file(path)  # a damaged file: what is wrong, not h5py's KeyError
        self.path = path
        with xr.open_dataset(path, engine="h5netcdf") as ds:
            self.title = _text(ds.attrs.get("title", path.stem))
            self.axes = _text(ds.attrs["sweep_axes"]).split()
            self.zipped = _text(ds.attrs.get("sweep_combine", "product")) == "zip"
            self.sweep_dims = ["variant"] if self.zipped else list(self.axes)
            self.coordinates, self.axis_units, self.shown = {}, {}, {}
            for a in self.axes:
                var = ds[a] if a in ds.variables else ds[f"{a}_file"]
                self.coordinates[a] = _strings_or_numbers(var.values)
                if a not in ds.variables or var.attrs.get("long_name", "").startswith(
                        "record file"):  # records: their names (file names) in legends
                    files = [str(v) for v in self.coordinates[a]]
                    stems = [Path(v).stem for v in files]
                    if len(set(stems)) == len(stems):
                        self.shown[a] = dict(zip(files, stems))
                self.axis_units[a] = _text(var.attrs.get("units", ""))
            self.entities = {e: _strings_or_numbers(ds[f"{e}_name"].values)
                             for e in ENTITIES if f"{e}_name" in ds.variables}
            self.complete = np.asarray(ds["complete"].values, dtype=bool).reshape(-1)
            self.responses = {}
            for name, var in ds.data_vars.items():
                if name in _NOT_RESPONSES or name in self.axes:
                    continue
                dims = list(var.dims)
                extra = dims[len(self.sweep_dims):]
                if dims[:len(self.sweep_dims)] != self.sweep_dims or len(extra) > 1 \
                        or (extra and extra[0] not in ENTITIES):
                    continue  # histories (t) and coordinates
                self.responses[name] = (extra[0] if extra else None,
                                        _text(var.attrs.get("units", "")),
                                        _text(var.attrs.get("long_name", name)))
            self._f_path = path

    def values(self, name: str) -> np.ndarray:
        """The response as (variants, entities) floats, failed variants NaN."""
        import xarray as xr

        with xr.open_dataset(self._f_path, engine="h5netcdf") as ds:
            data = np.asarray(ds[name].values, dtype=float)
        count = self.complete.size
        data = data.reshape(count, -1)
        data[~self.complete] = np.nan
        return data

    def axis_values(self, axis: str) -> np.ndarray:
        """The axis's value for each variant (flattened in C order)."""
        coordinate = self.coordinates[axis]
        if self.zipped:
            return coordinate
        shape = [len(self.coordinates[a]) for a in self.axes]
        index = self.axes.index(axis)
        grid = np.indices(shape)[index].reshape(-1)
        return coordinate[grid]


def _nearest(values: np.ndarray, wanted: str, what: str, path: Path):
    distinct = list(dict.fromkeys(values.tolist()))
    if values.dtype == object:
        if wanted not in distinct:
            raise InputError(f"{path}: --at {what}={wanted}: {what} has the values "
                             f"{', '.join(map(str, distinct))}")
        return wanted
    try:
        number = float(wanted)
    except ValueError:
        raise InputError(f"{path}: --at {what}={wanted}: {what} takes numbers") from None
    return distinct[int(np.argmin(np.abs(np.asarray(distinct, dtype=float) - number)))]


def _geometric(x: np.ndarray) -> bool:
    x = np.unique(x.astype(float))
    if x.size < 3 or np.any(x <= 0):
        return False
    ratios = x[1:] / x[:-1]
    return bool(np.allclose(ratios, ratios[0], rtol=1e-6)) and ratios[0] > 1.5


def spectrum(path: str | Path, *, response: str | None = None, x: str | None = None,
             curves: str | None = None, at: dict | None = None):
    """The response spectrum figure of a sweep file and notes on what it leaves out.

    Parameters
    ----------
    path : str or Path
        A result file of ``pframe sweep``.
    response : str, optional
        The variable to draw (default: the first of :data:`PREFERRED` in the file).
    x : str, optional
        The swept axis along the horizontal (default: the first axis).
    curves : str, optional
        One curve per value of this dimension: the response's entity (the default) or another
        axis (the default when the response has no entity and there is a second axis).
    at : dict, optional
        ``dimension -> value`` fixing other dimensions (default: their largest response).

    Returns
    -------
    (matplotlib.figure.Figure, list of str)
    """
    from pframe.plot.figure import matplotlib_figure

    path = Path(path)
    if not path.exists():
        raise InputError(f"{path}: no such result file")
    sweep = _Sweep(path)
    at = dict(at or {})
    if response is None:
        response = next((r for r in PREFERRED if r in sweep.responses),
                        next(iter(sweep.responses), None))
        if response is None:
            raise InputError(f"{path}: the sweep file holds no response to draw")
    if response not in sweep.responses:
        raise InputError(f"{path}: no response {response!r}; the file holds "
                         f"{', '.join(sweep.responses)}")
    entity, units, long_name = sweep.responses[response]
    x = x or sweep.axes[0]
    if x not in sweep.axes:
        raise InputError(f"{path}: --x {x}: not a swept axis; the axes are "
                         f"{', '.join(sweep.axes)}")
    dimensions = list(sweep.axes) + ([entity] if entity else [])
    along = f"{response} runs along {', '.join(dimensions)}"
    for key in at:
        if key == x:
            others = [a for a in sweep.axes if a != x]
            raise InputError(f"{path}: --at {key}=...: {key} is the x axis; --at fixes "
                             f"{_choices([d for d in dimensions if d != x])}"
                             + (f"; --x chooses another x axis ({', '.join(others)})"
                                if others else ""))
        if key not in dimensions:
            raise InputError(f"{path}: --at {key}=...: {along}, not {key}; --at fixes "
                             f"{_choices([d for d in dimensions if d != x])}"
                             + _elsewhere(sweep, key))
    if curves is None:
        others = [a for a in sweep.axes if a != x and a not in at]
        curves = entity if entity and entity not in at else (others[0] if others else None)
    elif curves == x or curves in at or curves not in dimensions:
        why = ("is the x axis" if curves == x else "is fixed with --at" if curves in at
               else f"is not a dimension of {response} (it runs along {', '.join(dimensions)})")
        raise InputError(f"{path}: --curves {curves}: {curves} {why}; --curves takes "
                         f"{_choices([d for d in dimensions if d != x and d not in at])}"
                         + ("" if curves in dimensions else _elsewhere(sweep, curves)))

    data = sweep.values(response)  # (variants, entities)
    keep = np.ones(data.shape[0], dtype=bool)
    notes = []
    for key, wanted in at.items():
        if key == entity:
            names = sweep.entities[entity]
            value = _nearest(names, wanted, key, path)
            data = data[:, list(names).index(value)][:, None]
        else:
            value = _nearest(sweep.axis_values(key), wanted, key, path)
            keep &= sweep.axis_values(key) == value
        notes.append(f"{key} = {value}")
    xs = sweep.axis_values(x)
    if entity and entity not in at and curves != entity:
        data = np.nanmax(np.where(np.isnan(data), -np.inf, data), axis=1, keepdims=True)
        data[np.isinf(data)] = np.nan
        notes.append(f"largest over {entity}")
    if curves is None or curves == entity:
        keys = list(sweep.entities[entity]) if curves == entity else [None]
        series = [(key, keep, data[:, j]) for j, key in enumerate(keys)]
    else:
        column = data[:, 0]
        values = sweep.axis_values(curves)
        series = [(key, keep & (values == key), column)
                  for key in dict.fromkeys(values[keep].tolist())]
    reduced = [a for a in sweep.axes if a not in (x, curves) and a not in at]
    if reduced:
        notes.append(f"largest over {', '.join(reduced)}")
    failed = int(np.count_nonzero(~sweep.complete))
    if failed:
        notes.append(f"{failed} failed variant{'s' if failed > 1 else ''} left out")

    Figure = matplotlib_figure()
    fig = Figure(figsize=(7.0, 4.4), layout="constrained")
    ax = fig.add_subplot()
    for i, (key, mask, column) in enumerate(series):
        grid = np.unique(xs[mask])
        peak = np.full(grid.size, np.nan)
        for k, value in enumerate(grid):
            chosen = column[mask & (xs == value)]
            if np.any(~np.isnan(chosen)):
                peak[k] = np.nanmax(chosen)
        label = None if key is None else (
            f"{curves} {key}" if curves in ENTITIES
            else sweep.shown[curves].get(str(key), str(key)) if curves in sweep.shown
            else f"{curves} = {_shown(key)}")
        ax.plot(grid.astype(float), peak, marker="o", markersize=3, linewidth=1.2,
                label=label, color=f"C{i % 10}")
    if _geometric(xs):
        ax.set_xscale("log")
    from pframe.plot.style import fitted

    ax.set_xlabel(x + _in(sweep.axis_units.get(x, "")), fontsize="medium")
    ax.set_ylabel(response + _in(units), fontsize="medium")
    ax.set_title(fitted(long_name + (f"; {', '.join(notes)}" if notes else ""),
                        fig.get_figwidth(), "small"), fontsize="small", loc="left")
    ax.grid(True, alpha=0.3, linewidth=0.6)
    ax.tick_params(labelsize=8)
    if any(key is not None for key, _, _ in series):
        ax.legend(fontsize="small", frameon=False)
    ax.set_label(f"spectrum {response}")
    fig.suptitle(fitted(sweep.title, fig.get_figwidth(), "large"), fontsize="large")
    return fig, notes


def _in(units: str) -> str:
    """An axis label's units: `` (m)``; a pure number's `` (dimensionless)``."""
    if not units:
        return ""
    return " (dimensionless)" if units == "1" else f" ({units})"


def _choices(names) -> str:
    """'one of a, b', or what to do when there is nothing to choose."""
    names = list(names)
    if not names:
        return "no dimension here (each is the x axis or fixed with --at): leave the option out"
    return f"one of {', '.join(names)}" if len(names) > 1 else names[0]


def _elsewhere(sweep, dimension: str) -> str:
    """The responses of the file that do run along ``dimension``, if any."""
    names = [name for name, (entity, _, _) in sweep.responses.items() if entity == dimension]
    if not names:
        return ""
    return f" (responses along {dimension}: {', '.join(names)}; choose one with --response)"


def _shown(value) -> str:
    return f"{value:.4g}" if isinstance(value, float) else str(value)
