"""The sweep's result file: a labelled N-D array in netCDF4-compatible HDF5 (docs/sweeps.md).

The sweep axes are dimensions with coordinates (``combine: zip`` gives one dimension
``variant`` and the axes as coordinates along it); responses follow them, then their entity
(``node``, ``story``, ``contact``, ``building``) and, for histories, ``time`` first. So
``xarray.open_dataset(OUT, engine="h5netcdf")`` gives ``peak_contact_force(gap, frequency,
contact)`` as it is. The file is written from the finished chunk files in one deterministic
order, under a temporary name, then renamed: an interrupted and resumed sweep ends with the
same bytes as an uninterrupted one. Wall-clock timings are printed, never written.
"""

from __future__ import annotations

import dataclasses
from pathlib import Path

import numpy as np

from pframe import outputs
from pframe.quantities import QUANTITIES
from pframe.record.hdf5 import LABELS, ROTATION, integrator_text
from pframe.record.netcdf import Writer, provenance, with_units
from pframe.sweep.grid import Spec

#: long names of the responses that are not peaks of a recorded quantity
_LONG_NAMES = {
    "ductility": ("1", "storey ductility demand: peak drift / yield drift (NaN: elastic storey)"),
    "impact_count": (None, "number of impacts (contact onsets)"),
    "building_peak_displacement": (
        "m", "peak absolute floor displacement relative to the ground, largest of the building"),
    "building_peak_story_drift": ("m", "peak absolute storey drift, largest of the building"),
    "building_peak_ductility": (
        "1", "storey ductility demand, largest of the building (NaN: no yielding storey)"),
}
_STATUS = {
    "complete": ("int8", None, "1 if the variant ran to its end, else 0"),
    "status": ("str", None, "'completed', or why the variant stopped or did not run"),
    "steps_completed": ("int32", None, "time steps computed"),
    "energy_balance_error": ("float64", "1", "energy balance error relative to the largest "
                             "energy term"),
    "algorithmic_dissipation": ("float64", "1", "the integrator's own dissipation relative to "
                                "the largest energy term (negative: energy created)"),
    "trusted": ("int8", None, "0 if the energy verdict says the variant is not to be trusted "
                "(docs/theory.md, the verdict on a run), else 1"),
    "newton_solves": ("int32", None, "Newton iterations (linear solves)"),
    "split_steps": ("int32", None, "steps retried in sub-steps"),
    "dt": ("float64", "s", "time step"),
    "duration": ("float64", "s", "time analysed (steps x dt; under records: the variant's "
                 "record plus the base scene's time after its own record)"),
    "record_duration": ("float64", "s", "time of the last sample of the variant's record as "
                        "applied"),
}


#: a floor's rotation in a scene in plan (``displacement_rz``) -> its quantity, units and name
_ROTATIONS = {name: (q, units, long_name) for q, (name, units, long_name) in ROTATION.items()}


def _quantity_name(name: str, convert, in_plan: bool, channels: int) -> tuple[str, str]:
    """Units and long name of a recorded quantity's variable (``displacement``, or in plan
    its rotation ``displacement_rz``), as ``pframe solve`` names it."""
    if name in _ROTATIONS:
        return _ROTATIONS[name][1:]
    entity, units, long_name = QUANTITIES[name]
    if in_plan and entity == "node":
        long_name = long_name.replace("floor ", "floor centre of mass ")
    elif entity is None and channels > 1:
        long_name += " along the site's x and y"
    _, units, long_name = convert.variable(np.zeros(0), units, long_name)
    return units, long_name


def _units_and_name(name: str, convert, in_plan: bool = False,
                    channels: int = 1) -> tuple[str | None, str]:
    if name in QUANTITIES or name in _ROTATIONS:
        return _quantity_name(name, convert, in_plan, channels)
    if name == "torsional_irregularity":
        from pframe.irregularity import LONG_NAME

        return "1", LONG_NAME
    if name in _LONG_NAMES:
        units, long_name = _LONG_NAMES[name]
        if in_plan and name == "building_peak_displacement":
            long_name = ("peak absolute displacement of a floor's centre of mass relative to "
                         "the ground along the site's x or y, largest of the building")
        if units == "m":
            _, units, long_name = convert.variable(np.zeros(0), units, long_name)
        return units, long_name
    quantity = name[len("peak_"):]
    units, long_name = _quantity_name(quantity, convert, in_plan, channels)
    if quantity == "story_drift_ratio":  # the kernel's peak of a storey without a height
        long_name += " (NaN at a storey without a height: not defined there)"
    return units, f"peak absolute {long_name}"


@dataclasses.dataclass(frozen=True)
class BaseRun:
    """What the file says about the runs, taken from the base scene."""

    title: str
    node_names: tuple
    story_names: tuple
    contact_names: tuple
    buildings: tuple
    integrator: str
    steps: int
    dt: float
    convert: object
    link_names: tuple = ()
    #: the variants' arrays (pframe.sweep.chunk.Layout), the base's named plan points, its
    #: foundations on soil and the ground motion's channels
    layout: object = None
    point_names: tuple = ()
    foundations: tuple = ()
    channels: int = 1


def base_run(spec: Spec) -> BaseRun:
    from pframe.assemble import assemble
    from pframe.sweep.chunk import layout

    base = spec.base_scene()
    plan = assemble(dataclasses.replace(base.expanded, recorders=spec.recorders))
    integrator = integrator_text(plan)
    title = spec.model.title or getattr(base.scene, "title", "") or Path(spec.definition.source).stem
    return BaseRun(title, plan.node_names, plan.story_names, plan.contact_names,
                   plan.buildings, integrator, plan.steps, float(plan.dt[0]),
                   base.units, plan.link_names, layout(spec, base.expanded),
                   base.expanded.point_names, plan.foundations, len(plan.channels))


def write_sweep(path: Path, spec: Spec, load_chunk, call: str | None = None) -> dict:
    """Write the result file from the finished chunks (``load_chunk(i)`` returns chunk ``i``'s
    arrays) via a temporary file and an atomic rename; return a summary (failed variants)."""
    path = Path(path)
    with outputs.replacing(path) as tmp:
        f = Writer(tmp)
        try:
            summary = _write(f, spec, load_chunk, call)
        finally:
            f.close()
    return summary


def _write(f: Writer, spec: Spec, load_chunk, call: str | None = None) -> dict:
    definition = spec.definition
    run = base_run(spec)
    shape, dims = spec.shape, spec.dims
    zipped = spec.model.combine == "zip"

    # small per-variant arrays of every chunk, in variant order
    small: dict[str, list] = {}
    warnings: list[str] = []
    histories = [q for q, trailing in run.layout.dims.items() if trailing[:1] == ("t",)]
    rows = run.steps // spec.model.keep.every + 1  # the longest variant's, for histories
    for chunk in range(spec.chunks):
        arrays = load_chunk(chunk)
        warnings += [str(w) for w in arrays["warnings"]]
        for key, value in arrays.items():
            if key in histories:
                rows = max(rows, value.shape[1])
            if key in histories or key in ("warnings", "solve_seconds", "compile_seconds"):
                continue
            small.setdefault(key, []).append(value)
    small = {key: np.concatenate(values) for key, values in small.items()}
    complete = small["complete"].astype(bool)

    attrs = provenance(call)
    attrs.update({
        "title": run.title,
        "source": definition.source,
        "sweep_yaml": definition.text,
        "base_source": definition.base_source,
        "input_yaml": definition.base_text,
        "sweep_digest": definition.digest,
        "sweep_axes": " ".join(a.name for a in spec.axes),
        "sweep_combine": spec.model.combine,
        "variants": np.int64(spec.count),
        "variants_failed": np.int64(np.count_nonzero(~complete)),
        "variants_untrusted": np.int64(np.count_nonzero(complete & (small["trusted"] == 0))),
        "chunk": np.int64(definition.chunk),
        "integrator": run.integrator,
        "steps": np.int64(run.steps),
        "warnings": "\n".join(sorted(set(warnings))),
    })
    same = True
    if run.convert.dimensionless:
        scales = small["scales"]
        same = bool(np.all(np.isnan(scales) | (scales == scales[complete.argmax()])))
        for key, value in run.convert.attributes(run.dt).items():
            if same or not key.startswith(("scale_", "dtau")):
                attrs[key] = value
    else:  # the unit system its responses are written in (docs/units.md)
        attrs.update(run.convert.attributes(run.dt))
    f.attrs.update(with_units(attrs))

    if zipped:
        f.coordinate("variant", np.arange(spec.count, dtype=np.int32),
                     long_name="variant (the i-th values of the zipped axes)")
    for axis in spec.axes:
        values = axis.coordinates
        attrs = {"long_name": f"swept {axis.path_text}"}
        if axis.units:
            attrs["units"] = axis.units
        if axis.is_file:  # strings: a label variable (no string coordinate variables in CF)
            attrs["long_name"] = f"record file ({axis.path_text})"
            if zipped:
                f.strings(axis.name, ("variant",), list(values), auxiliary=True, **attrs)
            else:
                f.labels(axis.name, f"{axis.name}_file", list(values), **attrs)
        elif zipped:
            f.variable(axis.name, ("variant",), np.asarray(values), auxiliary=True, **attrs)
        else:
            f.coordinate(axis.name, np.asarray(values), **attrs)
    entities = {"node": run.node_names, "story": run.story_names,
                "contact": run.contact_names, "building": run.buildings,
                "link": run.link_names}
    used = {d for trailing in run.layout.dims.values() for d in trailing}
    # the dimensions of scenes in plan and on soil, labelled where a variable runs along them
    entities.update((d, names) for d, names in (
        ("direction", ("x", "y")), ("point", run.point_names), ("axis", ("x", "y")),
        ("foundation", run.foundations)) if d in used)
    every = spec.model.keep.every
    if histories:
        values, units, long_name = run.convert.time(np.arange(rows) * every * run.dt)
        f.coordinate("t", values, units=units, long_name=long_name)
    for entity, names in entities.items():
        if names:
            f.labels(entity, LABELS[entity][0], list(names), long_name=LABELS[entity][1])

    for name, trailing in run.layout.dims.items():
        if name not in small or trailing[:1] == ("t",):
            continue
        data = small[name].reshape(shape + small[name].shape[1:])
        if data.dtype == np.int64:
            data = data.astype(np.int32)
        units, long_name = _units_and_name(name, run.convert, run.layout.in_plan,
                                           run.channels)
        fill = np.int32(-1) if name == "impact_count" else None
        f.variable(name, dims + trailing, data, fill=fill, units=units,
                   long_name=long_name)
    for name, (dtype, units, long_name) in _STATUS.items():
        if name == "record_duration" and spec.base_record is None:
            continue
        data = small[name].reshape(shape)
        if dtype == "str":
            f.strings(name, dims, np.array(data.tolist(), dtype=object), long_name=long_name)
            continue
        f.variable(name, dims, data.astype(dtype), units=units, long_name=long_name)
    if run.convert.dimensionless and not same:
        for k, key in enumerate(("m_b", "a_p", "w_p")):
            f.variable(f"scale_{key}", dims, scales[:, k].reshape(shape),
                       units={"m_b": "kg", "a_p": "m/s^2", "w_p": "rad/s"}[key],
                       long_name=f"reference scale {key} of the dimensionless output")

    datasets = {}
    for q in histories:
        units, long_name = _quantity_name(q, run.convert, run.layout.in_plan, run.channels)
        datasets[q] = f.variable(q, dims + run.layout.dims[q], units=units,
                                 long_name=long_name)
    if datasets:  # one chunk in memory at a time: histories are large
        for chunk in range(spec.chunks):
            arrays = load_chunk(chunk)
            for q, var in datasets.items():
                for row, index in enumerate(spec.chunk_range(chunk)):
                    values = arrays[q][row]
                    if len(values) < rows:  # a shorter run: NaN after its end
                        values = np.concatenate([values, np.full(
                            (rows - len(values),) + values.shape[1:], np.nan)])
                    var[np.unravel_index(index, shape)] = values

    failed = [(i, str(small["status"][i])) for i in np.flatnonzero(~complete)]
    untrusted = [int(i) for i in np.flatnonzero(complete & (small["trusted"] == 0))]
    return {"failed": failed, "untrusted": untrusted, "count": spec.count,
            "durations": small["duration"]}
