"""A risk study's demands as the table pelicun reads (FEMA P-58 loss assessment).

pelicun's ``DemandModel.load_sample`` takes a CSV whose first row names each column
``EVENT-TYPE-LOCATION-DIRECTION`` (``1-PID-2-1``: event 1, peak interstorey drift ratio,
storey 2, direction 1), whose second row, headed ``Units``, gives each column's units in
pelicun's names, and whose other rows are realisations, one per analysis. The types written
here are FEMA P-58's (FEMA P-58-1, 2018, ch. 5; pelicun's demand types):

- ``PFA``: peak absolute floor acceleration (``g``); location 0 is the ground (the run's peak
  ground acceleration), location k the floor carried by storey k;
- ``PID``: peak interstorey drift ratio of storey k (``rad``, drift over storey height).

Direction 1 is the scene's x (a planar scene moves along it alone). Rows are the study's
runs, record-major (record 1 at every level, then record 2, ...), or one level's runs (a
stripe: the demands at one intensity, what one pelicun assessment takes). A run that
failed (collapse, no convergence) keeps its row with ``ERROR`` 1, which pelicun drops with a
note in its log; pframe warns how many there are.
"""

from __future__ import annotations

import math
import warnings
from pathlib import Path

import numpy as np

from pframe.errors import InputError

#: the column pelicun reads as "this realisation failed" (1) and drops
ERROR = "1-ERROR"


def _conditions(ds) -> list[str]:
    """The conditions a study ran: without contacts always, with them when it ran them
    (a study without pounding runs has none of them complete)."""
    ran = bool((ds.complete.sel(condition="with_pounding") == 1).any())
    return ["without_pounding", "with_pounding"] if ran else ["without_pounding"]


def demand_table(result, building: str | None = None, condition: str | None = None,
                 level: float | None = None):
    """The demands of a risk study's runs as pelicun's demand sample.

    Parameters
    ----------
    result : str, Path or xarray.Dataset
        A file of ``pframe risk`` (msa, ida or cloud design of a planar scene), or the
        Dataset ``pframe.risk`` returned.
    building : str, optional
        The building assessed (pelicun assesses one); needed when the scene has several.
    condition : {"with_pounding", "without_pounding"}, optional
        The runs with the contacts at their gaps (default, when the study ran them) or
        without contacts.
    level : float, optional
        Only the runs of this level (a stripe, g; an msa or grid ida design): the demands at
        one intensity. Default: every run.

    Returns
    -------
    (pandas.DataFrame, dict)
        One row per run (index 0, 1, ...), columns ``1-PFA-0-1``, ``1-PFA-1-1``, ...,
        ``1-PID-1-1``, ... and ``1-ERROR`` (1: the run failed); and ``{column: units}`` in
        pelicun's names (``g``, ``rad``).

    Raises
    ------
    InputError
        A file that is not such a study, or that has no storey-by-storey demands (a scene
        in plan, or a file written before pframe kept them); a storey without a height (its
        drift ratio is unknown); an unknown building, condition or level.
    """
    ds, source = _study(result)
    names = [str(b) for b in ds.building_name.values]
    if building is None:
        if len(names) > 1:
            raise InputError(f"{source}: the scene has {len(names)} buildings "
                             f"({', '.join(names)}); name the one pelicun assesses "
                             f"(--building {names[0]}, or building='{names[0]}')")
        building = names[0]
    if building not in names:
        raise InputError(f"{source}: no building {building!r}; the buildings are "
                         f"{', '.join(names)}")
    ran = _conditions(ds)
    condition = condition or ran[-1]
    if condition not in ("with_pounding", "without_pounding"):
        raise InputError(f"condition {condition!r}: with_pounding or without_pounding")
    if condition not in ran:
        raise InputError(f"{source}: the study ran no runs with the contacts (pounding_runs: "
                         "false); export condition without_pounding")
    runs = ds.sel(condition=condition)
    if level is not None:
        runs = _stripe(runs, level, source)
    stories = np.flatnonzero(ds.story_building.values == building)
    floors = np.flatnonzero((ds.node_building.values == building)
                            & (ds.node_location.values > 0))
    drift = runs.story_peak_drift_ratio.values[..., stories]
    done = runs.complete.values == 1
    missing = [str(n) for n, ok in zip(ds.story_name.values[stories],
                                       np.isfinite(drift[done]).all(axis=0)) if not ok]
    if missing and done.any():
        raise InputError(f"{source}: storey {', '.join(missing)} of {building} has no height "
                         "in the scene, so no drift ratio (PID is drift over storey height); "
                         "give the storeys' height and run the study again")
    return _table(runs, ds, stories, floors, done)


def _table(runs, ds, stories, floors, done):
    """The DataFrame and units of the chosen runs (record-major) of one building."""
    import pandas as pd

    order = np.argsort(ds.node_location.values[floors], kind="stable")
    floors = floors[order]
    columns = {"1-PFA-0-1": runs.peak_ground_acceleration.values}
    for n in floors:
        columns[f"1-PFA-{int(ds.node_location.values[n])}-1"] = (
            runs.node_peak_absolute_acceleration.values[..., n])
    for s in stories:
        columns[f"1-PID-{int(ds.story_location.values[s])}-1"] = (
            runs.story_peak_drift_ratio.values[..., s])
    rows = {k: np.where(done, v, np.nan).reshape(-1) for k, v in columns.items()}
    rows[ERROR] = (~done).astype(np.int64).reshape(-1)
    keep = (runs.complete.values >= 0).reshape(-1)  # -1: a slot a hunt did not run
    table = pd.DataFrame(rows).loc[keep].reset_index(drop=True)
    units = {k: ("g" if "-PFA-" in k else "rad") for k in columns}
    units[ERROR] = ""
    failed = int((~done & (runs.complete.values >= 0)).sum())
    if failed:
        warnings.warn(f"{failed} of {int(keep.sum())} runs failed (collapse or no "
                      f"convergence): their rows have {ERROR} 1, and pelicun drops them "
                      "(model collapse in pelicun, or run them again)", stacklevel=3)
    return table, units


def _study(result):
    """The Dataset of a risk study with storey-by-storey demands, and its name for messages."""
    import xarray as xr

    if isinstance(result, xr.Dataset):
        ds, source = result, "the risk study"
    else:
        from pframe.api import open as open_result

        with open_result(result) as opened:
            ds = opened.load()
        source = str(result)
    kind = ds.attrs.get("pframe_kind")
    if kind != "risk_study" or "complete" not in ds:
        raise InputError(f"{source}: not the result of a risk study of records or motions "
                         "(pframe risk with an msa, ida or cloud design); a subset design "
                         "keeps no demands per run")
    if "story_peak_drift_ratio" not in ds:
        raise InputError(f"{source}: the file holds no demands storey by storey (a scene "
                         "in plan, whose storeys are lines of resistance, or a file of an "
                         "older pframe): pelicun's table needs them")
    from pframe.api import indexed

    return indexed(ds), source  # a Dataset xarray opened: names as coordinates


def _stripe(runs, level: float, source: str):
    """The runs of one level of an msa or grid-ida study."""
    from pframe.record.netcdf import short_units

    units = short_units(runs.level.attrs.get("units", ""))
    if units != "g":
        raise InputError(f"{source}: its runs are not at levels of an intensity ("
                         + ("a hunt and fill's runs" if units == "1" else "records as given")
                         + "); export every run (leave out the level)")
    try:
        value = float(level)
    except (TypeError, ValueError):
        value = math.nan
    levels = np.asarray(runs.level.values, float)
    match = np.flatnonzero(np.isclose(levels, value, rtol=1e-9, atol=0))
    if not match.size:
        raise InputError(f"level {level!r}: {source} has the levels "
                         + ", ".join(f"{x:g}" for x in levels) + " (g)")
    return runs.isel(level=int(match[0]))


def export_pelicun(result, path: str | Path, *, building: str | None = None,
                   condition: str | None = None, level: float | None = None,
                   overwrite: bool = False) -> Path:
    """Write :func:`demand_table` as pelicun's demand CSV (a header row, a ``Units`` row, a
    row per run) at ``path``; an existing file only with ``overwrite``, never the result
    read. Returns the path written."""
    from pframe import outputs

    inputs = [result] if isinstance(result, (str, Path)) else []
    path = outputs.check_output(path, inputs=inputs, overwrite=overwrite,
                                what="pelicun demand table", named_by="pelicun")
    table, units = demand_table(result, building, condition, level)
    lines = ["," + ",".join(table.columns), "Units," + ",".join(units[c] for c in table.columns)]
    for k, row in enumerate(table.itertuples(index=False)):
        lines.append(f"{k}," + ",".join(_cell(v) for v in row))
    with outputs.replacing(path, overwrite) as tmp:
        Path(tmp).write_text("\n".join(lines) + "\n")
    return path


def _cell(value) -> str:
    """A number as CSV text: repr's shortest round trip, empty for NaN (pelicun: missing)."""
    if isinstance(value, (int, np.integer)):
        return str(int(value))
    value = float(value)
    return repr(value) if math.isfinite(value) else ""
