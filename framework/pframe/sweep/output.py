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

import h5py
import numpy as np

import pframe
from pframe import outputs
from pframe.quantities import QUANTITIES
from pframe.sweep.definition import RESPONSES
from pframe.sweep.spec import Spec

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
    "newton_solves": ("int64", None, "Newton iterations (linear solves)"),
    "split_steps": ("int64", None, "steps retried in sub-steps"),
    "dt": ("float64", "s", "time step"),
}


def _units_and_name(name: str, convert) -> tuple[str | None, str]:
    if name in QUANTITIES:
        _, units, long_name = QUANTITIES[name]
        _, units, long_name = convert.variable(np.zeros(0), units, long_name)
        return units, long_name
    if name in _LONG_NAMES:
        units, long_name = _LONG_NAMES[name]
        if units == "m":
            _, units, long_name = convert.variable(np.zeros(0), units, long_name)
        return units, long_name
    quantity = name[len("peak_"):]
    _, units, long_name = QUANTITIES[quantity]
    _, units, long_name = convert.variable(np.zeros(0), units, long_name)
    return units, f"peak absolute {long_name}"


def _coordinate(f, name, values, **attrs):
    dset = f.create_dataset(name, data=values, track_order=True)
    dset.make_scale(name)
    for key, value in attrs.items():
        dset.attrs[key] = value
    return dset


def _variable(f, name, data_or_shape, dims, dtype=None, units=None, long_name=None,
              coordinates=None, fill=None):
    if isinstance(data_or_shape, tuple):
        dset = f.create_dataset(name, shape=data_or_shape, dtype=dtype, track_order=True,
                                fillvalue=fill)
    else:
        dset = f.create_dataset(name, data=data_or_shape, track_order=True, fillvalue=fill)
    for axis, dim in enumerate(dims):
        dset.dims[axis].attach_scale(f[dim])
    if fill is not None:
        dset.attrs["_FillValue"] = np.array(fill, dtype=dset.dtype)
    if units is not None:
        dset.attrs["units"] = units
    if long_name is not None:
        dset.attrs["long_name"] = long_name
    if coordinates:
        dset.attrs["coordinates"] = coordinates
    return dset


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


def base_run(spec: Spec) -> BaseRun:
    from pframe.assemble import assemble
    from pframe.nondim.output import output_units
    from pframe.sweep.spec import variant_data_base
    from pframe.sweep.variants import load_variant, materialise

    base = load_variant(variant_data_base(spec), spec.base_lines, spec.base_where,
                        materialise(spec.definition))
    plan = assemble(dataclasses.replace(base.expanded, recorders=spec.recorders))
    integrator = plan.integrator_name + (
        "" if plan.integrator.explicit
        else (", linear: one solve per step" if plan.linear else ", full Newton")
        + (", event-aware" if plan.integrator.events and plan.contact_names else ""))
    title = spec.model.title or getattr(base.scene, "title", "") or Path(spec.definition.source).stem
    return BaseRun(title, plan.node_names, plan.story_names, plan.contact_names,
                   plan.buildings, integrator, plan.steps, float(plan.dt[0]),
                   output_units(base.scene, base.expanded))


def write_sweep(path: Path, spec: Spec, load_chunk) -> dict:
    """Write the result file from the finished chunks (``load_chunk(i)`` returns chunk ``i``'s
    arrays) via a temporary file and an atomic rename; return a summary (failed variants)."""
    path = Path(path)
    with outputs.replacing(path) as tmp:
        with h5py.File(tmp, "w", track_order=True) as f:
            summary = _write(f, spec, load_chunk)
    return summary


def _write(f, spec: Spec, load_chunk) -> dict:
    definition = spec.definition
    run = base_run(spec)
    text = h5py.string_dtype()
    shape, dims = spec.shape, spec.dims
    zipped = spec.model.combine == "zip"
    coordinates = " ".join(a.name for a in spec.axes) if zipped else None

    # small per-variant arrays of every chunk, in variant order
    small: dict[str, list] = {}
    warnings: list[str] = []
    histories = [q for q in spec.model.keep.histories
                 if not (QUANTITIES[q][0] == "contact" and not run.contact_names)]
    for chunk in range(spec.chunks):
        arrays = load_chunk(chunk)
        warnings += [str(w) for w in arrays["warnings"]]
        for key, value in arrays.items():
            if key in histories or key in ("warnings", "solve_seconds", "compile_seconds"):
                continue
            small.setdefault(key, []).append(value)
    small = {key: np.concatenate(values) for key, values in small.items()}
    complete = small["complete"].astype(bool)

    f.attrs["Conventions"] = "CF-1.8"
    f.attrs["title"] = run.title
    f.attrs["source"] = definition.source
    f.attrs["sweep_yaml"] = definition.text
    f.attrs["base_source"] = definition.base_source
    f.attrs["input_yaml"] = definition.base_text
    f.attrs["pframe_version"] = pframe.__version__
    f.attrs["sweep_digest"] = definition.digest
    f.attrs["sweep_axes"] = " ".join(a.name for a in spec.axes)
    f.attrs["sweep_combine"] = spec.model.combine
    f.attrs["variants"] = int(spec.count)
    f.attrs["variants_failed"] = int(np.count_nonzero(~complete))
    f.attrs["chunk"] = int(definition.chunk)
    f.attrs["integrator"] = run.integrator
    f.attrs["steps"] = int(run.steps)
    f.attrs["warnings"] = "\n".join(sorted(set(warnings)))
    if run.convert.dimensionless:
        scales = small["scales"]
        same = np.all(np.isnan(scales) | (scales == scales[complete.argmax()]))
        for key, value in run.convert.attributes(run.dt).items():
            if same or not key.startswith(("scale_", "dtau")):
                f.attrs[key] = value

    if zipped:
        _coordinate(f, "variant", np.arange(spec.count, dtype=np.int32),
                    long_name="variant (the i-th values of the zipped axes)")
    for axis in spec.axes:
        values = axis.coordinates
        attrs = {"long_name": f"swept {axis.path_text}"}
        if axis.units:
            attrs["units"] = axis.units
        if axis.is_file:
            values = np.array(list(values), dtype=object).astype(text)
            attrs["long_name"] = f"record file ({axis.path_text})"
        if zipped:
            dset = f.create_dataset(axis.name, data=values, track_order=True)
            dset.dims[0].attach_scale(f["variant"])
            for key, value in attrs.items():
                dset.attrs[key] = value
        else:
            _coordinate(f, axis.name, values, **attrs)
    entities = {"node": run.node_names, "story": run.story_names,
                "contact": run.contact_names, "building": run.buildings}
    long_names = {"node": "floor node (building/floor)",
                  "story": "storey (named by the floor above it)",
                  "contact": "contact element", "building": "building"}
    every = spec.model.keep.every
    if histories:
        values, units, long_name = run.convert.time(
            np.arange(run.steps // every + 1) * every * run.dt)
        _coordinate(f, "time", values, units=units, long_name=long_name, axis="T")
    for entity, names in entities.items():
        if names:
            _coordinate(f, entity, np.array(names, dtype=object).astype(text),
                        long_name=long_names[entity])

    for name in spec.responses:
        if name not in small:
            continue
        entity = RESPONSES[name]
        data = small[name].reshape(shape + small[name].shape[1:])
        units, long_name = _units_and_name(name, run.convert)
        fill = -1 if name == "impact_count" else None
        _variable(f, name, data, dims + ((entity,) if entity else ()), units=units,
                  long_name=long_name, coordinates=coordinates, fill=fill)
    for name, (dtype, units, long_name) in _STATUS.items():
        data = small[name].reshape(shape)
        if dtype == "str":
            data = np.array(data.tolist(), dtype=object).astype(text)
        _variable(f, name, data, dims, units=units, long_name=long_name,
                  coordinates=coordinates)
    if run.convert.dimensionless and not same:
        for k, key in enumerate(("m_b", "a_p", "w_p")):
            _variable(f, f"scale_{key}", scales[:, k].reshape(shape), dims,
                      units={"m_b": "kg", "a_p": "m/s^2", "w_p": "rad/s"}[key],
                      long_name=f"reference scale {key} of the dimensionless output",
                      coordinates=coordinates)

    datasets = {}
    for q in histories:
        entity = QUANTITIES[q][0]
        rows = run.steps // every + 1
        inner = (rows,) if entity is None else (rows, len(entities[entity]))
        _, units, long_name = QUANTITIES[q]
        _, units, long_name = run.convert.variable(np.zeros(0), units, long_name)
        datasets[q] = _variable(f, q, shape + inner,
                                dims + ("time",) + ((entity,) if entity else ()),
                                dtype="float64", units=units, long_name=long_name,
                                coordinates=coordinates)
    if datasets:  # one chunk in memory at a time: histories are large
        for chunk in range(spec.chunks):
            arrays = load_chunk(chunk)
            for q, dset in datasets.items():
                for row, index in enumerate(spec.chunk_range(chunk)):
                    dset[np.unravel_index(index, shape)] = arrays[q][row]

    failed = [(i, str(small["status"][i])) for i in np.flatnonzero(~complete)]
    return {"failed": failed, "count": spec.count}
