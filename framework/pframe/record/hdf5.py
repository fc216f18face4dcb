"""The HDF5 output contract (see docs/hdf5.md).

Coordinates ``time`` (s), ``node``, ``story``, ``contact``; variables ``displacement(time,
node)`` etc. for histories and ``peak_<quantity>(node|story|contact)`` for envelopes, each with
``units`` and ``long_name``. The file is netCDF4-compatible: dimension scales, creation order
tracked, strings as variable-length UTF-8. It is written under a temporary name and renamed
when complete, so a reader never sees half a file and an existing file is never damaged.
"""

from __future__ import annotations

import os
from pathlib import Path

import h5py
import numpy as np

import pframe
from pframe.nondim.output import output_units
from pframe.quantities import QUANTITIES

UNITS = {q: (units, name) for q, (_, units, name) in QUANTITIES.items()}
DIMENSION = {q: dim for q, (dim, _, _) in QUANTITIES.items()}
ENERGY_TERMS = ("input", "kinetic", "damping", "storeys", "contacts", "initial_kinetic")


def _coordinate(f: h5py.File, name: str, values, **attrs):
    dset = f.create_dataset(name, data=values, track_order=True)
    dset.make_scale(name)
    for key, value in attrs.items():
        dset.attrs[key] = value
    return dset


def _variable(f: h5py.File, name: str, data, dims: tuple[str, ...], units: str, long_name: str):
    dset = f.create_dataset(name, data=data, track_order=True)
    for axis, dim in enumerate(dims):
        dset.dims[axis].attach_scale(f[dim])
    dset.attrs["units"] = units
    dset.attrs["long_name"] = long_name
    return dset


def _write(f: h5py.File, result, loaded, member: int):
    plan = result.plan
    done = result.states_done(member)
    convert = output_units(loaded.scene, loaded.expanded)  # SI, or dimensionless (pframe.nondim)
    dof = plan.node_dof  # DOF column of each declared node
    text = h5py.string_dtype()
    f.attrs["Conventions"] = "CF-1.8"
    f.attrs["title"] = getattr(loaded.scene, "title", "") or Path(loaded.source).stem
    f.attrs["source"] = str(loaded.source)
    f.attrs["input_yaml"] = loaded.text
    f.attrs["pframe_version"] = pframe.__version__
    f.attrs["integrator"] = plan.integrator_name + (
        "" if plan.integrator.explicit
        else (", linear: one solve per step" if plan.linear else ", full Newton")
        + (", event-aware" if plan.integrator.events and plan.contact_names else ""))
    f.attrs["warnings"] = "\n".join(plan.warnings)
    f.attrs["dt"] = float(plan.dt[member])
    f.attrs["steps"] = int(plan.steps)
    f.attrs["steps_completed"] = int(done - 1)
    f.attrs["solve_seconds"] = float(result.solve_seconds)
    f.attrs["newton_solves"] = int(result.iterations[member])
    f.attrs["split_steps"] = int(result.substeps[member])
    f.attrs["status"] = result.describe_failure(member)
    f.attrs["complete"] = np.int8(result.completed(member))
    f.attrs["energy_balance_error"] = float(result.energy_error(member))
    for term, value in zip(ENERGY_TERMS, result.energy[member]):
        f.attrs[f"energy_{term}"] = float(convert.energy(value))
    for key, value in convert.attributes(float(plan.dt[member])).items():
        f.attrs[key] = value

    strides = sorted({every for _, every in plan.history})
    time_dims = {}
    for every in strides:
        dim = "time" if every == strides[0] else f"time_every_{every}"
        rows = (done - 1) // every + 1
        values, units, long_name = convert.time(np.arange(rows) * every * float(plan.dt[member]))
        _coordinate(f, dim, values, units=units, long_name=long_name, axis="T")
        time_dims[every] = (dim, rows)
    _coordinate(f, "node", np.array(plan.node_names, dtype=object).astype(text),
                long_name="floor node (building/floor)")
    if plan.story_names:
        _coordinate(f, "story", np.array(plan.story_names, dtype=object).astype(text),
                    long_name="storey (named by the floor above it)")
    if plan.contact_names:
        _coordinate(f, "contact", np.array(plan.contact_names, dtype=object).astype(text),
                    long_name="contact element")

    def columns(q, data):
        return data[..., dof] if DIMENSION[q] == "node" else data

    for q, every in plan.history:
        dim, rows = time_dims[every]
        data = columns(q, result.history[q][member][:rows])
        dims = (dim,) if DIMENSION[q] is None else (dim, DIMENSION[q])
        data, units, long_name = convert.variable(data, *UNITS[q])
        _variable(f, q, data, dims, units, long_name)
    for q, peak in result.envelope.items():
        data, units, long_name = convert.variable(np.asarray(columns(q, peak[member])), *UNITS[q])
        dims = () if DIMENSION[q] is None else (DIMENSION[q],)
        _variable(f, f"peak_{q}", data, dims, units, f"peak absolute {long_name}")
    if plan.contact_names:
        dset = _variable(f, "impact_count", result.impacts[member].astype(np.int32),
                         ("contact",), "1", "number of impacts (contact onsets)")
        del dset.attrs["units"]


def write_result(path: str | Path, result, loaded, member: int = 0) -> Path:
    """Write one batch member's result to ``path`` via a temporary file and an atomic rename."""
    path = Path(path)
    tmp = path.with_name(f".{path.name}.{os.getpid()}.tmp")
    try:
        with h5py.File(tmp, "w", track_order=True) as f:
            _write(f, result, loaded, member)
        os.replace(tmp, path)
    finally:
        if tmp.exists():
            tmp.unlink()
    return path
