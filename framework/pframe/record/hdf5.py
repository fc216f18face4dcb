"""The HDF5 output contract (see docs/hdf5.md).

Coordinates ``time`` (s), ``node``, ``story``, ``contact``; variables ``displacement(time,
node)`` etc. for histories and ``peak_<quantity>(node|story|contact)`` for envelopes, each with
``units`` and ``long_name``. The file is netCDF4-compatible: dimension scales, creation order
tracked, strings as variable-length UTF-8. It is written under a temporary name and renamed
when complete, so a reader never sees half a file and an existing file is never damaged.

Two ways in, one writer (:class:`ResultWriter`):

- ``pframe solve`` opens the writer before the run and hands its :meth:`ResultWriter.append`
  to the kernel as the ``sink``: each block of history rows goes to its place in the file as
  soon as it is computed, so memory stays bounded whatever the duration. The histories are
  laid out at their full length (chunked) and cut to the states computed if the run stops
  early;
- :func:`write_result` writes a result whose histories are in memory (sweeps, tests), laid
  out at the length computed (contiguous).

Both give the same variables, coordinates and attributes, value for value.
"""

from __future__ import annotations

from pathlib import Path

import h5py
import numpy as np

import pframe
from pframe import outputs
from pframe.nondim.output import output_units
from pframe.quantities import QUANTITIES

UNITS = {q: (units, name) for q, (_, units, name) in QUANTITIES.items()}
DIMENSION = {q: dim for q, (dim, _, _) in QUANTITIES.items()}
ENERGY_TERMS = ("input", "kinetic", "damping", "storeys", "contacts", "initial_kinetic")
#: kernel counter (pframe.kernel.state.COUNTER_NAMES) -> file attribute, in the file's order
COUNTER_ATTRIBUTES = (("solves", "newton_solves"), ("split_steps", "split_steps"),
                      ("factorisations", "factorisations"),
                      ("evaluations", "residual_evaluations"), ("gathers", "gathered_values"))
#: bytes of one HDF5 chunk of a streamed history (a few chunks per variable fit HDF5's 1 MiB
#: chunk cache, so blocks that end inside a chunk are completed in memory)
CHUNK_BYTES = 256 * 2**10
#: rows of a time coordinate computed at once (bounded memory for long runs)
_TIME_BLOCK = 2**16


def _temporary(path: Path) -> Path:
    return outputs.temporary(path)


def _coordinate(f: h5py.File, name: str, values, **attrs):
    dset = f.create_dataset(name, data=values, track_order=True)
    dset.make_scale(name)
    for key, value in attrs.items():
        dset.attrs[key] = value
    return dset


def _variable(f: h5py.File, name: str, data, dims: tuple[str, ...], units: str, long_name: str):
    dset = f.create_dataset(name, data=data, track_order=True)
    _describe(f, dset, dims, units, long_name)
    return dset


def _describe(f: h5py.File, dset, dims: tuple[str, ...], units: str, long_name: str):
    for axis, dim in enumerate(dims):
        dset.dims[axis].attach_scale(f[dim])
    dset.attrs["units"] = units
    dset.attrs["long_name"] = long_name


def _empty(f: h5py.File, name: str, shape: tuple[int, ...], resizable: bool):
    """A float64 dataset of ``shape`` filled later; chunked along its first axis and
    shrinkable (never growable: the dimension stays fixed for netCDF) when ``resizable``."""
    if not resizable:
        return f.create_dataset(name, shape=shape, dtype="f8", track_order=True)
    width = int(np.prod(shape[1:], dtype=np.int64))
    if width == 0:  # no columns (h5py picks a chunk shape a zero-size dataset accepts)
        chunks = True
    else:
        chunks = (max(1, min(shape[0], CHUNK_BYTES // (8 * width))),) + shape[1:]
    return f.create_dataset(name, shape=shape, dtype="f8", chunks=chunks, maxshape=shape,
                            track_order=True)


class ResultWriter:
    """One batch member's result file, written under a temporary name and renamed when done.

    ``states`` is the number of states the histories are laid out for: the run's
    ``plan.steps + 1`` when streaming (the default; the file is cut to the states computed
    by :meth:`finish`), or the states already computed when the histories are in memory.
    History rows are given to :meth:`append` (the kernel's ``sink``: batch axis first, node
    columns in DOF order, SI units) in any order and any block sizes; :meth:`finish` writes
    the rest and renames the file, :meth:`abort` removes it. For the quantities in ``track``
    the writer keeps the running peak of ``|value|`` per column (DOF order, SI) in
    :attr:`peaks`, of every row it was given.
    """

    def __init__(self, path: str | Path, plan, loaded, member: int = 0, states: int | None = None,
                 track: tuple[str, ...] = ()):
        self.path = Path(path)
        self.tmp = _temporary(self.path)
        self.plan, self.loaded, self.member = plan, loaded, member
        self.convert = output_units(loaded.scene, loaded.expanded)  # SI, or dimensionless
        self.streamed = states is None
        states = plan.steps + 1 if states is None else states
        self.track = tuple(q for q, _ in plan.history if q in track)
        self.peaks: dict[str, np.ndarray] = {}
        self.file = None
        try:
            self.file = h5py.File(self.tmp, "w", track_order=True)
            self._layout(states)
        except BaseException:
            self.abort()
            raise

    def __enter__(self):
        return self

    def __exit__(self, kind, value, traceback):
        if kind is not None:
            self.abort()

    def _layout(self, states: int):
        """Coordinates and the (still empty) history variables."""
        f, plan, dt = self.file, self.plan, float(self.plan.dt[self.member])
        text = h5py.string_dtype()
        strides = sorted({every for _, every in plan.history})
        self.time_dims = {}  # every -> name of its time coordinate
        for every in strides:
            dim = "time" if every == strides[0] else f"time_every_{every}"
            rows = (states - 1) // every + 1
            dset = _empty(f, dim, (rows,), self.streamed)
            for lo in range(0, rows, _TIME_BLOCK):
                hi = min(rows, lo + _TIME_BLOCK)
                values, units, long_name = self.convert.time(np.arange(lo, hi) * every * dt)
                dset[lo:hi] = values
            dset.make_scale(dim)
            dset.attrs.update({"units": units, "long_name": long_name, "axis": "T"})
            self.time_dims[every] = dim
        _coordinate(f, "node", np.array(plan.node_names, dtype=object).astype(text),
                    long_name="floor node (building/floor)")
        if plan.story_names:
            _coordinate(f, "story", np.array(plan.story_names, dtype=object).astype(text),
                        long_name="storey (named by the floor above it)")
        if plan.contact_names:
            _coordinate(f, "contact", np.array(plan.contact_names, dtype=object).astype(text),
                        long_name="contact element")
        widths = {"node": len(plan.node_names), "story": len(plan.story_names),
                  "contact": len(plan.contact_names)}
        for q, every in plan.history:
            dim = self.time_dims[every]
            rows = f[dim].shape[0]
            if DIMENSION[q] is None:
                shape, dims = (rows,), (dim,)
            else:
                shape, dims = (rows, widths[DIMENSION[q]]), (dim, DIMENSION[q])
            _, units, long_name = self.convert.variable(np.zeros(0), *UNITS[q])
            _describe(f, _empty(f, q, shape, self.streamed), dims, units, long_name)

    def _columns(self, q: str, data):
        return data[..., self.plan.node_dof] if DIMENSION[q] == "node" else data

    def append(self, quantity: str, first_row: int, rows) -> None:
        """History rows ``first_row ..`` of ``quantity`` for the whole batch, as the kernel's
        ``sink`` delivers them; this writer keeps its member's."""
        self.put(quantity, first_row, rows[self.member])

    def put(self, quantity: str, first_row: int, rows) -> None:
        """History rows ``first_row ..`` of ``quantity`` for this writer's member (rows past
        the file's length are ignored)."""
        dset = self.file[quantity]
        stop = min(first_row + len(rows), dset.shape[0])
        if stop <= first_row:
            return
        rows = np.asarray(rows[:stop - first_row])
        if quantity in self.track:
            # max |x| from the column extremes (no |rows| copy); NaN rows (not computed) are
            # ignored, as by np.nanmax
            peak = np.fmax(np.abs(np.fmax.reduce(rows, axis=0)),
                           np.abs(np.fmin.reduce(rows, axis=0)))
            seen = self.peaks.get(quantity)
            self.peaks[quantity] = peak if seen is None else np.fmax(seen, peak)
        data, _, _ = self.convert.variable(self._columns(quantity, rows), *UNITS[quantity])
        dset[first_row:stop] = data

    def finish(self, result) -> Path:
        """Cut the histories to the states computed, write envelopes, impact counts and
        attributes, close and rename. Returns the final path."""
        try:
            self._trim(result.states_done(self.member))
            self._summaries(result)
            self._attributes(result)
            self.file.close()
            outputs.commit(self.tmp, self.path)
        except BaseException:
            self.abort()
            raise
        return self.path

    def abort(self) -> None:
        """Close and remove the temporary file (nothing is left behind)."""
        try:
            if self.file is not None and self.file.id.valid:
                self.file.close()
        finally:
            outputs.discard(self.tmp)

    def _trim(self, done: int):
        f = self.file
        for every, dim in self.time_dims.items():
            rows = (done - 1) // every + 1
            if f[dim].shape[0] == rows:
                continue
            f[dim].resize(rows, axis=0)
            for q, stride in self.plan.history:
                if stride == every:
                    f[q].resize(rows, axis=0)

    def _summaries(self, result):
        f, member = self.file, self.member
        for q, peak in result.envelope.items():
            data, units, long_name = self.convert.variable(
                np.asarray(self._columns(q, peak[member])), *UNITS[q])
            dims = () if DIMENSION[q] is None else (DIMENSION[q],)
            _variable(f, f"peak_{q}", data, dims, units, f"peak absolute {long_name}")
        if self.plan.contact_names:
            dset = _variable(f, "impact_count", result.impacts[member].astype(np.int32),
                             ("contact",), "1", "number of impacts (contact onsets)")
            del dset.attrs["units"]

    def _attributes(self, result):
        f, plan, loaded, member = self.file, self.plan, self.loaded, self.member
        convert = self.convert
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
        f.attrs["steps_completed"] = int(result.states_done(member) - 1)
        f.attrs["solve_seconds"] = float(result.solve_seconds)
        for counter, name in COUNTER_ATTRIBUTES:
            f.attrs[name] = result.counter(counter, member)
        f.attrs["status"] = result.describe_failure(member)
        f.attrs["complete"] = np.int8(result.completed(member))
        f.attrs["energy_balance_error"] = float(result.energy_error(member))
        for term, value in zip(ENERGY_TERMS, result.energy[member]):
            f.attrs[f"energy_{term}"] = float(convert.energy(value))
        for key, value in convert.attributes(float(plan.dt[member])).items():
            f.attrs[key] = value


def write_result(path: str | Path, result, loaded, member: int = 0) -> Path:
    """Write one batch member's result, histories in memory, to ``path`` via a temporary file
    and an atomic rename."""
    writer = ResultWriter(path, result.plan, loaded, member, states=result.states_done(member))
    with writer:
        for q, _ in result.plan.history:
            writer.put(q, 0, result.history[q][member])
        return writer.finish(result)
