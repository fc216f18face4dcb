"""What a run did, as tables people read: the summary of a result (``pframe.summary``,
``pframe summary``, ``pframe solve --summary``) and its histories as CSV (``pframe export``).

The summary is one long table (pandas DataFrame), a row per fact: ``part`` (run, energy,
node, story, contact, impact, warning), ``name`` (the node, storey or contact; empty for the run),
``quantity``, ``value`` and ``units``. It is written as CSV (that table) or Markdown (a
section per part, one row per node, storey or contact). Peaks come from the envelopes when
the run recorded them, else from the histories. Storey ductility is the peak drift over the
yield drift of a yielding storey (its material's own: bilinear f_y / k, IMK My / K0,
Bouc-Wen z_y), read from the scene the result holds. With the storeys' histories the summary
adds the demand quantities of :mod:`pframe.demands`: residual drift, hysteretic energy, the
Park-Ang damage index, the storey shear of the contact forces, and a row per impact.
"""

from __future__ import annotations

import os
from pathlib import Path

from pframe.errors import InputError

#: the entities of a result, in the order the summary shows them
ENTITIES = ("node", "story", "contact", "building", "point")
#: run attributes shown (attribute, quantity, units)
RUN = (("status", "status", ""), ("accuracy", "accuracy (energy verdict)", ""),
       ("trusted", "trusted (1: yes)", "1"), ("complete", "complete (1: yes)", "1"),
       ("steps_completed", "steps computed", "1"), ("dt", "time step", "s"),
       ("energy_balance_error", "energy balance error (of the input)", "1"),
       ("algorithmic_dissipation", "numerical dissipation (of the input)", "1"))


def _text(value) -> str:
    return value.decode("utf-8") if isinstance(value, bytes) else str(value)


def result_dataset(result, call: str = "pframe.summary"):
    """The Dataset of ``result`` (a Dataset, or a result file's path, read whole) with the
    names as coordinates (:func:`pframe.api.indexed`); anything else is an InputError naming
    ``call``."""
    from pframe.api import result_dataset as dataset

    return dataset(result, call)


def _where(result) -> str:
    return str(result) if isinstance(result, (str, os.PathLike)) else "the Dataset"


def _peaks(ds, entity: str) -> dict[str, tuple]:
    """quantity -> (values along ``entity``, units): the envelopes ``peak_*``, else the
    largest absolute value of each history over time."""
    import numpy as np

    out = {}
    for name, var in ds.data_vars.items():
        if var.dims == (entity,) and name.startswith("peak_"):
            out[name[len("peak_"):]] = (np.asarray(var.values, float), var.attrs.get("units", ""))
        elif (len(var.dims) == 2 and var.dims[0] == entity and name.startswith("peak_")
              and var.dims[1] in ("direction", "axis")):
            # along the site's x, y (direction) or a building's (axis): a column each
            for j, label in enumerate(ds[var.dims[1]].values):
                out[f"{name[len('peak_'):]} {label}"] = (np.asarray(var.values[:, j], float),
                                                         var.attrs.get("units", ""))
    for name, var in ds.data_vars.items():
        if len(var.dims) == 2 and var.dims[1] == entity and var.dims[0].startswith("t") \
                and name not in out and var.dtype.kind == "f":
            values = np.nanmax(np.abs(np.asarray(var.values)), axis=0)
            out[name] = (values, var.attrs.get("units", ""))
    return out


def _torsion(ds, i: int, name: str) -> list[tuple]:
    """The summary's rows of the torsional irregularity of the storey below floor ``i``
    (ASCE 7-22 Table 12.3-1), where its plan gives one."""
    import numpy as np

    from pframe.irregularity import TORSIONAL_IRREGULARITY

    out = []
    for j, axis in enumerate(ds.axis.values):
        ratio = float(ds.torsional_irregularity.values[i, j])
        if np.isnan(ratio):
            continue
        kind = ("extreme (1b)" if ratio > TORSIONAL_IRREGULARITY[1] else "irregular (1a)"
                if ratio > TORSIONAL_IRREGULARITY[0] else "regular")
        out += [("node", name, f"torsional irregularity ratio {axis}", ratio, "1"),
                ("node", name, f"torsion {axis} (ASCE 7-22 Table 12.3-1)", kind, "")]
    return out


def _yield_drifts(ds) -> tuple[dict[str, float], str]:
    """Yield drift of each yielding storey, in the file's units, from the scene the result
    holds; with the reason when there is none."""
    if "input_yaml" not in ds.attrs:
        return {}, "the result holds no scene (input_yaml)"
    from pframe.api import scene_of_attributes

    try:
        loaded = scene_of_attributes(dict(ds.attrs), "the result", Path("."))
    except InputError as exc:
        return {}, f"the result's scene cannot be read: {exc}"
    from pframe.demands import si_factor, yield_properties

    scale = si_factor(ds, "m")  # the scene is read in SI; the file may be in mm
    if _text(ds.attrs.get("units_system", "")) == "dimensionless":
        if "scale_l_e" not in ds.attrs:
            return {}, "a dimensionless result without its length scale (scale_l_e)"
        scale = float(ds.attrs["scale_l_e"])

    out = {}
    for story in loaded.expanded.stories:
        props = yield_properties(story)
        if props is not None:
            out[story.name] = props[0] / scale
    return out, ""


def study_kind(ds) -> str | None:
    """What a result holds when it is not one run: "sweep", "gap audit" or "risk study";
    None for a run."""
    if "sweep_axes" in ds.attrs:
        return "sweep"
    kind = _text(ds.attrs.get("pframe_kind", ""))
    if not kind:
        return None
    from pframe.gap.output import KIND as GAP
    from pframe.risk.output import KIND as RISK

    return {GAP: "gap audit", RISK: "risk study"}.get(kind)


def summary(result, output: str | Path | None = None, *, overwrite: bool = False):
    """The summary of a run (a Dataset of :func:`pframe.solve` or :func:`pframe.open`, or a
    result file's path) as a pandas DataFrame with columns part, name, quantity, value,
    units: the run's status and energy verdict, its energy balance, the peaks per node and
    storey, storey ductility (peak drift / yield drift, yielding storeys), the demand
    quantities of :mod:`pframe.demands` (residual drift, hysteretic energy, Park-Ang index,
    impact storey shear, a row per impact), impacts and peak force per contact, and its
    warnings. ``output``: also write it, as CSV (``.csv``) or
    Markdown (``.md``); an existing file is replaced only with ``overwrite``."""
    import numpy as np
    import pandas as pd

    from pframe.api import flag_argument, path_argument

    overwrite = flag_argument(overwrite, "overwrite", "pframe.summary")
    if output is not None:  # checked before the work
        output = check_summary_path(
            path_argument(output, "output", "pframe.summary", "the summary file's path"),
            overwrite, inputs=[result] if isinstance(result, (str, os.PathLike)) else [])
    ds = result_dataset(result)
    kind = study_kind(ds)
    if kind is not None:
        raise InputError(f"{_where(result)}: the summary table is of one run (pframe solve); "
                         f"this is a {kind}'s result, which holds many: read it as a Dataset "
                         "(pframe.open) or draw it with pframe plot"
                         + ("" if kind == "sweep" else ", or print its summary with pframe "
                            "summary"))
    rows = []
    energy_units = "1" if _text(ds.attrs.get("units_system", "")) == "dimensionless" else "J"
    rows.append(("run", "", "title", _text(ds.attrs.get("title", "")), ""))
    for key, quantity, units in RUN:
        if key in ds.attrs:
            value = ds.attrs[key]
            value = _text(value) if isinstance(value, (str, bytes)) else float(
                np.asarray(value).item())
            rows.append(("run", "", quantity, value, units))
    for key, value in ds.attrs.items():
        if (key.startswith("energy_") and key != "energy_balance_error"
                and not key.endswith("_units")):  # an energy's unit (docs/netcdf.md)
            rows.append(("energy", "", key[len("energy_"):].replace("_", " "), float(value),
                         _text(ds.attrs.get(f"{key}_units", energy_units))))
    ductility, why = _yield_drifts(ds) if "story" in ds.dims else ({}, "")
    demands, impact_rows, demand_warnings = _demands(ds)
    for entity in ENTITIES:
        if entity not in ds.dims:
            continue
        names = [str(n) for n in ds[entity].values]
        peaks = _peaks(ds, entity)
        for i, name in enumerate(names):
            for quantity, (values, units) in peaks.items():
                if quantity == "column_shear" and values[i] != values[i]:
                    continue  # a floor-to-floor contact: no column between floors
                rows.append((entity, name, f"peak {quantity.replace('_', ' ')}",
                             float(values[i]), units))
            if entity == "story" and "story_drift" in peaks and name in ductility:
                drift, units = peaks["story_drift"]
                rows.append((entity, name, "yield drift", float(ductility[name]), units))
                rows.append((entity, name, "ductility (peak drift / yield drift)",
                             float(drift[i] / ductility[name]), "1"))
            if entity == "node" and "torsional_irregularity" in ds:
                rows += _torsion(ds, i, name)
            if entity == "contact" and "impact_count" in ds:
                rows.append((entity, name, "impacts", int(ds.impact_count.values[i]), "1"))
            if entity == "story":
                rows += demands.get(name, [])
            rows += _limit_rows(ds, entity, i, name)
    if why and not ductility:
        rows.append(("warning", "", "ductility not computed", why, ""))
    for name in ("peak_story_drift_ratio", "story_drift_ratio"):
        if name in ds and ds[name].attrs.get("comment"):  # storeys without a height
            rows.append(("warning", "", "drift ratio not defined",
                         _text(ds[name].attrs["comment"]), ""))
            break
    rows += impact_rows + demand_warnings
    for line in _text(ds.attrs.get("limits_exceeded", "")).splitlines():
        rows.append(("warning", "", "limit exceeded", line, ""))
    for line in _text(ds.attrs.get("warnings", "")).splitlines():
        if line.strip():
            rows.append(("warning", "", "warning", line, ""))
    table = pd.DataFrame(rows, columns=["part", "name", "quantity", "value", "units"])
    if output is not None:
        write(table, output, overwrite)
    return table


#: the limit variables of a result (pframe.limits) by entity, and the summary's words
LIMIT_ROWS = {"story": (("story_drift_ratio_limit", "drift ratio limit"),
                        ("story_drift_ratio_margin", "drift ratio margin"),
                        ("story_drift_ratio_utilisation", "drift ratio utilisation")),
              "node": (("floor_acceleration_limit", "acceleration limit"),
                       ("floor_acceleration_margin", "acceleration margin"),
                       ("floor_acceleration_utilisation", "acceleration utilisation"))}


def _limit_rows(ds, entity: str, i: int, name: str) -> list[tuple]:
    """The summary's rows of a storey's or floor's limit, margin and utilisation; NaN where
    the demand is not defined (the file's comment says why)."""
    return [(entity, name, quantity, float(ds[variable].values[i]),
             _text(ds[variable].attrs.get("units", "")))
            for variable, quantity in LIMIT_ROWS.get(entity, ()) if variable in ds]


def _demands(ds) -> tuple[dict, list, list]:
    """The summary's demand rows (pframe.demands): per storey name, the rows of residual
    drift, hysteretic energy, Park-Ang index and impact storey shear; the rows of the impact
    table; and warnings (a run ending in strong motion, what was not recorded)."""
    import numpy as np

    from pframe import demands

    per_story, impacts, warnings = {}, [], []
    if "story" not in ds.dims or "input_yaml" not in ds.attrs:
        return per_story, impacts, warnings
    names = [str(n) for n in ds["story"].values]
    units = "1" if _text(ds.attrs.get("units_system", "")) == "dimensionless" else "m"
    residual = demands.residual_drift(ds)
    if residual is not None:
        final, swing = residual
        peak = np.nanmax(np.abs(np.asarray(ds.story_drift.values, float)), axis=0) \
            * demands.si_factor(ds, "m")  # in SI, as the residual drift
        moving = demands.still_moving(final, swing, peak)
        if units != "1":  # written in the file's units, as its drifts
            final, units = demands.in_file_units(ds, final, "m")
        for i, name in enumerate(names):
            per_story.setdefault(name, []).append(("story", name, "residual drift",
                                                   float(final[i]), units))
        if moving.any():
            which = ", ".join(f"{names[i]} ({swing[i] / peak[i]:.0%} of its peak drift)"
                              for i in np.flatnonzero(moving))
            warnings.append(("warning", "", "warning",
                             f"the run ends while storeys still swing: {which} over the "
                             f"run's last {demands.TAIL_SHARE:.0%}; their residual drift is "
                             "the drift at the end, not the permanent drift: run past the end "
                             "of the ground motion (a free-vibration tail) for it", ""))
    if _text(ds.attrs.get("units_system", "")) == "dimensionless":
        return per_story, impacts, warnings
    try:
        loaded = demands.scene_of(ds)
    except InputError:
        return per_story, impacts, warnings
    if "story_force" in ds.data_vars and "story_drift" in ds.data_vars:
        try:
            for name, row in demands.park_ang(ds, loaded).items():
                per_story.setdefault(name, []).append(
                    ("story", name, "hysteretic energy",
                     *demands.in_file_units(ds, row["energy"], "J")))
                if "index" in row:
                    per_story[name].append(("story", name, "Park-Ang damage index",
                                            row["index"], "1"))
        except InputError:
            pass
    if "contact" in ds.dims and "contact_force" in ds.data_vars:
        try:
            shear = np.max(np.abs(demands.impact_storey_shear(ds, loaded)), axis=0)
            for i, name in enumerate(names):
                per_story.setdefault(name, []).append(
                    ("story", name, "peak impact storey shear",
                     *demands.in_file_units(ds, float(shear[i]), "N")))
        except InputError:
            pass
    if "contact" in ds.dims:
        try:
            table = demands.impacts(ds)
        except InputError as exc:
            warnings.append(("warning", "", "impact table not computed", str(exc), ""))
            impacts += _column_impacts(ds)
        else:
            for n, row in enumerate(table.itertuples(), start=1):
                label = f"{n}: {row.contact}"
                for column, unit in demands.IMPACT_COLUMNS[1:7]:
                    value = float(getattr(row, column))
                    if column == "column_shear" and value != value:
                        continue  # a floor-to-floor contact: no column between floors
                    impacts.append(("impact", label, column.replace("_", " "),
                                    *demands.in_file_units(ds, value, unit)))
    return per_story, impacts, warnings


def _column_impacts(ds) -> list:
    """The summary's rows of the impacts on struck columns the result file holds
    (``impact_column_shear``), when the impact table cannot be computed."""
    if "impact_column_shear" not in ds:
        return []
    rows = []
    for n, (contact, time, shear) in enumerate(zip(
            ds.impact_contact.values, ds.impact_time.values, ds.impact_column_shear.values),
            start=1):
        label = f"{n}: {contact}"
        rows.append(("impact", label, "time of peak force", float(time),
                     _text(ds.impact_time.attrs.get("units", ""))))
        rows.append(("impact", label, "column shear", float(shear),
                     _text(ds.impact_column_shear.attrs.get("units", ""))))
    return rows


def markdown(table) -> str:
    """The summary as Markdown: the run, its energies, then a table per part (one row per
    node, storey or contact, a column per quantity), then the warnings."""
    lines = []
    title = table[(table.part == "run") & (table.quantity == "title")]
    lines.append(f"# Summary: {title.value.iloc[0]}" if len(title) else "# Summary")
    for part, heading in (("run", "Run"), ("energy", "Energy balance")):
        rows = table[(table.part == part) & (table.quantity != "title")]
        if len(rows):
            lines += ["", f"## {heading}", "", "| quantity | value | units |", "|---|---|---|"]
            lines += [f"| {r.quantity} | {_cell(r.value)} | {r.units} |"
                      for r in rows.itertuples()]
    for part, heading in (("node", "Nodes"), ("story", "Storeys"), ("contact", "Contacts"),
                          ("building", "Buildings"), ("point", "Plan points"),
                          ("impact", "Impacts")):
        rows = table[table.part == part]
        if not len(rows):
            continue
        quantities = list(dict.fromkeys(rows.quantity))
        units = {q: rows[rows.quantity == q].units.iloc[0] for q in quantities}
        header = [part] + [f"{q} ({units[q]})" if units[q] else q for q in quantities]
        lines += ["", f"## {heading}", "", "| " + " | ".join(header) + " |",
                  "|" + "---|" * len(header)]
        for name in dict.fromkeys(rows.name):
            mine = rows[rows.name == name].set_index("quantity").value
            lines.append("| " + " | ".join([name] + [_cell(mine.get(q, "")) for q in quantities])
                         + " |")
    warnings = table[table.part == "warning"]
    lines += ["", "## Warnings", ""]
    lines += [f"- {r.quantity}: {r.value}" if r.quantity != "warning" else f"- {r.value}"
              for r in warnings.itertuples()] or ["none"]
    return "\n".join(lines) + "\n"


def _cell(value) -> str:
    if isinstance(value, float):
        return f"{value:.6g}"
    return str(value).replace("|", "\\|")


def check_summary_path(output: str | Path, overwrite: bool = True, inputs=(),
                       named_by: str = "output") -> Path:
    """The path of a summary file, checked before any work: ``.csv`` or ``.md``, its folder
    exists, not an existing file unless ``overwrite``; messages name option ``named_by``
    (``pframe solve --summary``: ``"summary"``)."""
    from pframe import outputs

    path = Path(output)
    kind = path.suffix.lower()
    if kind not in (".csv", ".md"):
        raise InputError(f"{path}: a summary is written as .csv or .md, not "
                         f"{kind or 'a file without a suffix'}")
    return outputs.check_output(path, inputs=inputs, overwrite=overwrite, what="summary file",
                                named_by=named_by)


def write(table, output: str | Path, overwrite: bool = True, named_by: str = "output") -> Path:
    """Write a summary table as CSV (``.csv``) or Markdown (``.md``), whole or not at all
    (``named_by``: as :func:`check_summary_path`'s)."""
    from pframe import outputs

    path = check_summary_path(output, overwrite, named_by=named_by)
    kind = path.suffix.lower()
    with outputs.replacing(path) as tmp:
        if kind == ".csv":
            table.to_csv(tmp, index=False)
        else:
            tmp.write_text(markdown(table), encoding="utf-8")
    return path


def export_csv(result, folder: str | Path) -> list[Path]:
    """Every history of a result as CSV, one file per variable (``displacement.csv``: a
    column of time, then one per node, each header with its units, e.g. ``A/3 [m]``), in
    ``folder`` (made if missing). Returns the files written."""
    import numpy as np

    from pframe import outputs

    folder = outputs.check_folder(folder, "CSV files", inputs=[
        result] if isinstance(result, (str, os.PathLike)) else [], named_by="csv")
    ds = result_dataset(result, "pframe export")
    outputs.make_folder(folder)
    written = []
    for name, var in ds.data_vars.items():
        if var.ndim not in (1, 2, 3) or not var.dims[0].startswith("t") \
                or var.dtype.kind not in "fi":
            continue
        time = ds[var.dims[0]]
        columns = [f"{var.dims[0]} [{_text(time.attrs.get('units', ''))}]"]
        units = _text(var.attrs.get("units", ""))
        if var.ndim == 3:  # in plan: a column per node (or point) and direction
            columns += [f"{n} {d} [{units}]" for n in ds[var.dims[1]].values
                        for d in ds[var.dims[2]].values]
        elif var.ndim == 2:
            columns += [f"{n} [{units}]" for n in ds[var.dims[1]].values]
        else:
            columns += [f"{name} [{units}]"]
        data = np.column_stack([np.asarray(time.values), np.asarray(var.values).reshape(
            time.size, -1)])
        path = folder / f"{name}.csv"
        with outputs.replacing(path) as tmp:
            with open(tmp, "w", encoding="utf-8", newline="") as f:
                f.write(",".join(_csv_field(c) for c in columns) + "\n")
                np.savetxt(f, data, delimiter=",", fmt="%.10g")
        written.append(path)
    if not written:
        raise InputError("the result holds no histories to export (its recorders kept "
                         "envelopes only); add a 'kind: history' recorder")
    if "contact" in ds.dims and "contact_force" in ds.data_vars and "velocity" in ds.data_vars:
        from pframe.demands import impacts

        try:  # the impact table (pframe.impacts) of a result in SI units
            table = impacts(ds)
        except InputError:  # dimensionless, or the two at other strides: not listed
            return written
        path = folder / "impacts.csv"
        with outputs.replacing(path) as tmp:
            table.to_csv(tmp, index=False, float_format="%.10g")
        written.append(path)
    return written


def _csv_field(text: str) -> str:
    return f'"{text}"' if any(c in text for c in ',"\n') else text
