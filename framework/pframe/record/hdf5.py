"""The result file of one run (see docs/netcdf.md): netCDF-4 following the CF conventions.

Coordinate ``t`` (s), dimensions ``node``, ``story``, ``contact`` with the label variables
``node_name``, ``story_name``, ``contact_name`` (and the connectivity: ``story_lower``,
``story_upper``, ``contact_left``, ``contact_right``, ``contact_gap``); variables
``displacement(t, node)`` etc. for histories and ``peak_<quantity>(node|story|contact)`` for
envelopes, each with ``units`` and ``long_name``; attributes that reproduce the run (the scene
text, the records it read, versions, date, command). Laid out by :mod:`pframe.record.netcdf`.
It is written under a temporary name and renamed when complete, so a reader never sees half a
file and an existing file is never damaged; on Linux the file's space is allocated on the disk
first (:func:`_reserve`), so that HDF5 never meets a full disk (libhdf5 crashes when it does).

Two ways in, one writer (:class:`ResultWriter`):

- ``pframe solve`` opens the writer before the run and hands its :meth:`ResultWriter.append`
  to the kernel as the ``sink``: each block of history rows goes to its place in the file as
  soon as it is computed, so memory stays bounded whatever the duration. The histories are
  laid out at their full length and cut to the states computed if the run stops early;
- :func:`write_result` writes a result whose histories are in memory (sweeps, tests).

The target may also be a binary file object, or a :class:`~pframe.record.netcdf.DatasetWriter`:
``pframe.solve`` builds its xarray Dataset through this same layout code, so a Dataset and a
file agree by construction (and a test checks they are identical).
"""

from __future__ import annotations

import contextlib
import errno
import math
import os
from pathlib import Path

import numpy as np

from pframe import outputs
from pframe.quantities import QUANTITIES
from pframe.record.netcdf import DatasetWriter, Writer, provenance, with_units
from pframe.verdict import of_result

UNITS = {q: (units, name) for q, (_, units, name) in QUANTITIES.items()}
DIMENSION = {q: dim for q, (dim, _, _) in QUANTITIES.items()}
#: kernel counter (pframe.kernel.state.COUNTER_NAMES) -> file attribute, in the file's order
COUNTER_ATTRIBUTES = (("solves", "newton_solves"), ("split_steps", "split_steps"),
                      ("events", "events_located"), ("factorisations", "factorisations"),
                      ("evaluations", "residual_evaluations"), ("gathers", "gathered_values"))
#: files whose writing failed inside HDF5: never closed (closing one crashes libhdf5)
_FAILED: list = []
#: rows of a time coordinate computed at once (bounded memory for long runs)
_TIME_BLOCK = 2**16
#: a floor's rotation in a scene in plan: the variable each node quantity's theta goes to
ROTATION = {"displacement": ("displacement_rz", "rad", "floor rotation about the vertical "
                             "(counter-clockwise)"),
            "velocity": ("velocity_rz", "rad/s", "floor angular velocity about the vertical"),
            "acceleration": ("acceleration_rz", "rad/s^2", "floor angular acceleration about "
                             "the vertical"),
            "absolute_acceleration": ("absolute_acceleration_rz", "rad/s^2", "floor angular "
                                      "acceleration about the vertical (the ground does not "
                                      "turn)")}
#: the label variable and long name of each named dimension
LABELS = {"node": ("node_name", "floor node (building/floor)"),
          "story": ("story_name", "storey (named by the floor above it)"),
          "contact": ("contact_name", "contact element"),
          "link": ("link_name", "link element (damper, coupling, tuned mass spring)"),
          "building": ("building_name", "building"),
          "foundation": ("foundation_name", "foundation on soil (named by its building)"),
          "direction": ("direction_name", "horizontal direction of the site (x, y)"),
          "point": ("point_name", "named plan point of a floor (<floor>:<point>)"),
          "axis": ("axis_name", "axis of the point's building (x, y)"),
          "support": ("support_name", "support: a piece of ground that moves as one")}


def _free_bytes(folder: Path) -> int | None:
    """Bytes an unprivileged writer may still use on the disk of ``folder`` (None: unknown)."""
    try:
        stat = os.statvfs(folder)
    except (OSError, AttributeError):
        return None
    return stat.f_bavail * stat.f_frsize


#: FALLOC_FL_KEEP_SIZE of Linux's fallocate(2): allocate blocks without changing the size
_KEEP_SIZE = 1
#: room reserved beyond the histories' bytes and the texts kept as attributes: HDF5's
#: metadata, labels, envelopes (the paper's example: 1.2 MB over 11.2 MB of histories)
_RESERVE_MARGIN = 4 * 2**20


def _reserve(path: Path, nbytes: int) -> bool:
    """Allocate ``nbytes`` of disk to the file ``path`` without changing its size (Linux
    ``fallocate`` with ``FALLOC_FL_KEEP_SIZE``), so that HDF5's writes into it never meet a
    full disk, whatever other processes write meanwhile; closing trims the file to its data.
    False where that is not supported (another system, a file system without it): the
    free-space check before each block is then the guard. Raises ENOSPC if the disk cannot
    hold the file now."""
    import ctypes
    import sys

    if not sys.platform.startswith("linux"):
        return False
    try:
        # the C library is in the process already: its symbols without looking for the file
        # (ctypes.util.find_library runs ldconfig, a process of its own, at every write)
        libc = ctypes.CDLL(None, use_errno=True)
        fallocate = libc.fallocate
    except (OSError, AttributeError):
        return False
    fallocate.argtypes = [ctypes.c_int, ctypes.c_int, ctypes.c_int64, ctypes.c_int64]
    fallocate.restype = ctypes.c_int
    fd = os.open(path, os.O_WRONLY)
    try:
        if fallocate(fd, _KEEP_SIZE, 0, int(nbytes)) == 0:
            return True
        number = ctypes.get_errno()
    finally:
        os.close(fd)
    if number in (errno.ENOSPC, errno.EDQUOT):
        raise OSError(number, os.strerror(number), str(path))
    return False  # EOPNOTSUPP, ENOSYS, EINVAL: not on this file system


def _temporary(path: Path) -> Path:
    return outputs.temporary(path)


def integrator_text(plan) -> str:
    """How the plan integrates, in words (the ``integrator`` attribute)."""
    each = "stage" if plan.integrator.stages > 1 else "step"
    return plan.integrator_name + (
        "" if plan.integrator.explicit
        else (f", linear: one solve per {each}" if plan.linear else ", full Newton")
        + (", event-aware" if plan.integrator.events and plan.contact_names else ""))


#: the labels of each kind of element's two ends in the file: (variable, long name)
END_LABELS = {
    "story": (("story_lower", "node below the storey ('ground' at the base)"),
              ("story_upper", "node above the storey")),
    "link": (("link_first", "first node of the link ('ground': anchored to the ground)"),
             ("link_second", "second node of the link (deformation = u_second - u_first)")),
    "contact": (("contact_left", "left node of the contact (penetration = u_left - u_right "
                 "- gap)"), ("contact_right", "right node of the contact")),
}


class ResultWriter:
    """One batch member's result file, written under a temporary name and renamed when done.

    ``target`` is a path, or a binary file object (written in place: an in-memory result).
    ``states`` is the number of states the histories are laid out for: the run's
    ``plan.steps + 1`` when streaming (the default; the file is cut to the states computed
    by :meth:`finish`), or the states already computed when the histories are in memory.
    History rows are given to :meth:`append` (the kernel's ``sink``: batch axis first, node
    columns in DOF order, SI units) in any order and any block sizes; :meth:`finish` writes
    the rest and renames the file, :meth:`abort` removes it. For the quantities in ``track``
    the writer keeps the running peak of ``|value|`` per column (DOF order, SI) in
    :attr:`peaks`, of every row it was given. ``compress`` deflates the histories (shuffle +
    gzip level 1); ``call`` is the command line or API call for the ``history`` attribute.
    """

    def __init__(self, target, plan, loaded, member: int = 0, states: int | None = None,
                 track: tuple[str, ...] = (), compress: bool = False, call: str | None = None):
        self.in_memory = not isinstance(target, (str, Path))  # a file object or a Dataset
        self.path = None if self.in_memory else Path(target)
        self.tmp = None if self.in_memory else _temporary(self.path)
        self.plan, self.loaded, self.member = plan, loaded, member
        self.convert = loaded.units  # the scene's unit system, or dimensionless
        self.call = call
        states = plan.steps + 1 if states is None else states
        self.track = tuple(q for q, _ in plan.history if q in track)
        self.peaks: dict[str, np.ndarray] = {}
        self.file = None
        self.reserved = False  # the file's whole size is allocated on the disk (_reserve)
        self.verdict = None  # the run's verdict (pframe.verdict), judged by finish
        try:
            self.file = (target if isinstance(target, DatasetWriter)
                         else Writer(target if self.in_memory else self.tmp, compress=compress))
            if self.tmp is not None:
                histories = self._bytes(states)
                self.reserved = _reserve(self.tmp, histories + histories // 8 + _RESERVE_MARGIN
                                         + 2 * self._texts())
            self._layout(states)
        except BaseException:
            self.abort()
            raise

    def __enter__(self):
        return self

    def __exit__(self, kind, value, traceback):
        if kind is not None:
            self.abort()

    def _bytes(self, states: int) -> int:
        """The histories and their time coordinates at full length, uncompressed (bytes)."""
        plan = self.plan
        widths = {"node": plan.n_dof if plan.planar else 3 * len(plan.node_names),
                  "story": len(plan.story_names), "point": 2 * len(plan.point_names),
                  "contact": len(plan.contact_names), "link": len(plan.link_names), None: 1,
                  "foundation": len(plan.foundations)}
        total = 0
        for every in {every for _, every in plan.history}:
            total += 8 * ((states - 1) // every + 1)
        for q, every in plan.history:
            total += 8 * ((states - 1) // every + 1) * widths[DIMENSION[q]]
        return total

    def _texts(self) -> int:
        """Bytes of the scene's and its record's texts, which the attributes copy."""
        total = len(getattr(self.loaded, "text", "") or "")
        excitation = getattr(getattr(self.loaded, "scene", None), "excitation", None)
        if excitation is not None and excitation.kind == "record":
            with contextlib.suppress(OSError, TypeError):
                total += os.path.getsize(Path(self.loaded.base_dir) / excitation.file)
        return total

    def _layout(self, states: int):
        """Coordinates, labels, connectivity and the (still empty) history variables."""
        f, plan, dt = self.file, self.plan, float(self.plan.dt[self.member])
        strides = sorted({every for _, every in plan.history})
        self.time_dims = {}  # every -> name of its time coordinate
        for every in strides:
            dim = "t" if every == strides[0] else f"t_every_{every}"
            rows = (states - 1) // every + 1
            f.dimension(dim, None)
            f.resize(dim, rows)
            _, units, long_name = self.convert.time(np.zeros(0))
            f.variable(dim, (dim,), chunk_rows=True, units=units, long_name=long_name)
            var = f.rows(dim)
            for lo in range(0, rows, _TIME_BLOCK):
                hi = min(rows, lo + _TIME_BLOCK)
                self.room(8 * (hi - lo))
                var[lo:hi] = self.convert.time(np.arange(lo, hi) * every * dt)[0]
            self.time_dims[every] = dim
        names = {"node": plan.node_names, "story": plan.story_names,
                 "contact": plan.contact_names, "link": plan.link_names,
                 "foundation": plan.foundations}
        if not plan.planar or self._axes() == ("x", "y"):
            names["direction"] = ("x", "y")
        if plan.node_support:
            names["support"] = plan.supports
        if plan.point_names and any(DIMENSION[q] == "point" for q in
                                    [*(q for q, _ in plan.history), *plan.envelope]):
            names["point"] = plan.point_names
            names["axis"] = ("x", "y")
        for dim, values in names.items():
            if values or dim == "node":
                f.labels(dim, LABELS[dim][0], list(values), long_name=LABELS[dim][1])
        self._connectivity()
        for q, every in plan.history:
            dim = self.time_dims[every]
            dims = (dim,) if DIMENSION[q] is None else (dim, DIMENSION[q])
            for name, units, long_name, shape in self._variables(q):
                _, units, long_name = self.convert.variable(np.zeros(0), units, long_name)
                f.variable(name, dims + shape, chunk_rows=True, units=units,
                           long_name=long_name, comment=self._undefined(name))

    def _variables(self, q: str) -> list[tuple[str, str, str, tuple]]:
        """(name, units, long name, trailing dimensions) of the variables quantity ``q``
        writes: itself, and in a scene in plan a node quantity along the site's x and y
        (dimension ``direction``) and its rotation (:data:`ROTATION`)."""
        units, long_name = UNITS[q]
        if DIMENSION[q] == "point":
            return [(q, units, long_name, ("axis",))]
        if DIMENSION[q] is None and self.plan.node_support:  # each support's, each axis
            two = self._axes() == ("x", "y")
            return [(q, units, long_name + " of each support" + (" along the site's x and y"
                                                                  if two else ""),
                     ("support", "direction") if two else ("support",))]
        if DIMENSION[q] is None and len(self.plan.channels) > 1:  # along the site's x and y
            return [(q, units, long_name + " along the site's x and y", ("direction",))]
        if self.plan.planar or DIMENSION[q] != "node":
            return [(q, units, long_name, ())]
        name, rotation_units, rotation_name = ROTATION[q]
        return [(q, units, long_name.replace("floor ", "floor centre of mass "),
                 ("direction",)), (name, rotation_units, rotation_name, ())]

    def _axes(self) -> tuple[str, ...]:
        """The site's axes the ground motion loads (a channel per support and axis)."""
        return tuple(dict.fromkeys(c.rsplit(":", 1)[-1] for c in self.plan.channels))

    def _undefined(self, q: str) -> str | None:
        """Why some values of ``q`` are NaN by definition (the drift ratio of a storey without
        a height), for the variable's ``comment``; None when none is."""
        if q != "story_drift_ratio" or self.plan.story_height is None:
            return None
        names = self.plan.story_names
        heights = self.plan.story_height[self.member, :len(names)]
        missing = [n for n, h in zip(names, heights) if not np.isfinite(h)]
        if not missing:
            return None
        return (f"NaN at {', '.join(missing)}: no height was given, so the drift ratio is not "
                "defined there (never 0); their drift is in story_drift, and height on the "
                "storey gives the ratio")

    def _connectivity(self):
        """Which nodes each storey and contact joins, and the contact gaps: a file draws its
        figures without its scene."""
        f, ex = self.file, self.loaded.expanded
        names = ex.node_names

        def node(i):
            return "ground" if i < 0 else names[i]

        def labels(name, dim, values, long_name):
            f.strings(name, (dim,), values, auxiliary=True, long_name=long_name)

        if not self.plan.planar and ex.node_centre is not None:
            for axis, column in (("x", 0), ("y", 1)):
                data, units = ex.node_centre[:, column], "m"
                if not self.convert.dimensionless:  # the scene's units (a dimensionless file
                    data, units, _ = self.convert.variable(data, units, "")  # keeps m)
                f.variable(f"node_{axis}", ("node",), data, auxiliary=True, units=units,
                           long_name=f"{axis} of the floor's centre of mass on the site")
        for dim, elements in (("story", ex.stories), ("link", ex.links),
                              ("contact", ex.contacts)):
            for end, (name, long_name) in enumerate(END_LABELS[dim] if elements else ()):
                labels(name, dim, [node(e.nodes[end]) for e in elements], long_name)
        if ex.contacts:
            gaps = self.plan.contact_gap[self.member]
            data, units, long_name = self.convert.variable(gaps, "m", "initial gap")
            f.variable("contact_gap", ("contact",), data, auxiliary=True, units=units,
                       long_name=long_name)
            sides = [e.column_side for e in ex.contacts]
            if any(side is not None for side in sides):  # floor-to-column contacts
                labels("contact_column", "contact",
                       ["none" if s is None else ("left", "right")[s] for s in sides],
                       "side whose node tops the storey struck mid-height (floor-to-column "
                       "contact; none: floor to floor)")
                labels("contact_column_lower", "contact",
                       ["none" if s is None else node(e.lower[s])
                        for e, s in zip(ex.contacts, sides)],
                       "lower floor of the struck storey ('ground' at the base; none: floor "
                       "to floor)")
                at = [math.nan if s is None else e.at[s] for e, s in zip(ex.contacts, sides)]
                f.variable("contact_at", ("contact",), np.array(at), auxiliary=True,
                           fill=np.nan, units="1", long_name="where the column is struck: "
                           "fraction of the struck storey's height above its lower floor")

    def _columns(self, q: str, data) -> list:
        """The values of each of :meth:`_variables`' variables from the kernel's columns (a
        node quantity in DOF order; in plan, a DOF the scene does not move is 0)."""
        if DIMENSION[q] == "point":
            data = np.asarray(data)
            return [data.reshape(data.shape[:-1] + (data.shape[-1] // 2, 2))]
        if DIMENSION[q] is None and self.plan.node_support:  # (support, axis) of each channel
            data = np.asarray(data)
            axes = len(self._axes())
            shape = data.shape[:-1] + (data.shape[-1] // axes, axes)
            return [data.reshape(shape) if axes > 1 else data]
        if DIMENSION[q] != "node":
            return [data]
        plan = self.plan
        if plan.planar:
            return [data[..., plan.node_dof]]
        data = np.asarray(data)
        nodes = len(plan.node_names)
        out = np.zeros(data.shape[:-1] + (nodes, 3))
        own = plan.dof_node >= 0
        out[..., plan.dof_node[own], plan.dof_component[own]] = data[..., own]
        return [out[..., :2], out[..., 2]]

    def append(self, quantity: str, first_row: int, rows) -> None:
        """History rows ``first_row ..`` of ``quantity`` for the whole batch, as the kernel's
        ``sink`` delivers them; this writer keeps its member's."""
        self.put(quantity, first_row, rows[self.member])

    def put(self, quantity: str, first_row: int, rows) -> None:
        """History rows ``first_row ..`` of ``quantity`` for this writer's member (rows past
        the file's length are ignored)."""
        var = self.file.rows(quantity)
        stop = min(first_row + len(rows), var.shape[0])
        if stop <= first_row:
            return
        rows = np.asarray(rows[:stop - first_row])
        if quantity in self.track:
            # max |x| from the column extremes; NaN rows (not computed) are ignored, as by
            # np.nanmax. Each column's values made contiguous first: numpy reduces a narrow
            # block along its rows one row at a time, ten times slower than along a column
            # (a third of the writing); extremes are exact, whatever the order
            columns = np.ascontiguousarray(np.moveaxis(rows, 0, -1))
            peak = np.fmax(np.abs(np.fmax.reduce(columns, axis=-1)),
                           np.abs(np.fmin.reduce(columns, axis=-1)))
            seen = self.peaks.get(quantity)
            self.peaks[quantity] = peak if seen is None else np.fmax(seen, peak)
        for (name, units, long_name, _), values in zip(self._variables(quantity),
                                                       self._columns(quantity, rows)):
            data, _, _ = self.convert.variable(values, units, long_name)
            self.room(data.nbytes)
            try:
                self.file.rows(name)[first_row:stop] = data
            except OSError:
                self.failed = True  # HDF5 met a failing disk: never flushed again (see abort)
                raise

    def room(self, nbytes: int) -> None:
        """Raise ENOSPC *before* a block of ``nbytes`` is handed to HDF5 if the disk cannot
        take it and what HDF5 still holds (its chunk caches, 1 MiB a variable, and the
        metadata written on closing). libhdf5 that meets ENOSPC while writing leaves its
        metadata cache damaged, and closing the file then crashes the process (segmentation
        fault): pframe never lets it meet a full disk it can see coming."""
        if self.tmp is None or self.reserved:  # reserved: the disk space is the file's own
            return
        free = _free_bytes(self.tmp.parent)
        if free is not None and free < nbytes + (len(self.plan.history) + 4) * 2**20:
            raise OSError(errno.ENOSPC, "no space left on the device", str(self.tmp))

    def finish(self, result):
        """Cut the histories to the states computed, write envelopes, impact counts and
        attributes, close and rename. Returns the final path (the file object in memory)."""
        try:
            self._trim(result.states_done(self.member))
            self._summaries(result)
            self._attributes(result)
            self.file.close()
            if self.in_memory:
                return None
            outputs.commit(self.tmp, self.path)
        except BaseException as exc:
            if isinstance(exc, OSError) and self.file is not None:
                self.failed = True  # HDF5 met a failing disk: never flushed again (abort)
            self.abort()
            raise
        return self.path

    def abort(self) -> None:
        """Remove the temporary file, then close it (nothing is left behind). Its space is
        freed first (truncated to nothing), so that closing, which flushes HDF5's metadata,
        finds room on a disk that filled up; and its name is gone even if closing fails."""
        try:
            if self.tmp is not None:
                with contextlib.suppress(OSError):
                    os.truncate(self.tmp, 0)
        finally:  # whatever arrives meanwhile (a second Ctrl-C), the name goes
            if self.tmp is not None:
                outputs.discard(self.tmp)
        if self.file is not None:
            file, self.file = self.file, None
            if getattr(self, "failed", False):
                # closing flushes HDF5's metadata, which a failed write left damaged (libhdf5
                # crashes): the handle is kept, unflushed, until the process ends
                _FAILED.append(file)
                return
            with contextlib.suppress(Exception):  # the file is gone: its errors do not matter
                file.close()

    def _trim(self, done: int):
        for every, dim in self.time_dims.items():
            rows = (done - 1) // every + 1
            if self.file.rows(dim).shape[0] != rows:
                self.file.resize(dim, rows)

    def _summaries(self, result):
        f, member = self.file, self.member
        for q, peak in result.envelope.items():
            dims = () if DIMENSION[q] is None else (DIMENSION[q],)
            for (name, units, long_name, shape), values in zip(
                    self._variables(q), self._columns(q, np.asarray(peak[member]))):
                data, units, long_name = self.convert.variable(values, units, long_name)
                f.variable(f"peak_{name}", dims + shape, data, units=units,
                           long_name=f"peak absolute {long_name}",
                           comment=self._undefined(name))
        if self.plan.contact_names:
            f.variable("impact_count", ("contact",), result.impacts[member].astype(np.int32),
                       long_name="number of impacts (contact onsets)")
        if "point_drift" in result.envelope and not self.plan.planar:
            from pframe.irregularity import LONG_NAME, torsional_irregularity

            ex = self.loaded.expanded
            peak = np.asarray(result.envelope["point_drift"][member]).reshape(-1, 2)
            ratio = torsional_irregularity(ex.point_names, ex.point_positions, peak,
                                           self.plan.node_names)
            f.variable("torsional_irregularity", ("node", "axis"), ratio, units="1",
                       long_name=LONG_NAME)
        if any(e.column_side is not None for e in self.loaded.expanded.contacts):
            self._column_shears(result)
        if getattr(self.loaded.scene, "limits", None) is not None:
            self._limits(result)

    def _limits(self, result):
        """Each storey's drift ratio limit and each floor's acceleration limit, with the
        margin (limit - demand) and utilisation (demand / limit) of the run's peaks, and what
        they exceed (pframe.limits)."""
        from pframe.limits import BASIS, evaluate

        f, ex = self.file, self.loaded.expanded
        check = evaluate(ex, self.plan, self.loaded.scene.limits, result.envelope, self.member)
        missing = check.missing_heights()
        reason = (f"NaN at {', '.join(missing)}: no height was given, so the drift ratio is "
                  "not defined there (never 0)" if missing else None)
        if np.any(np.isfinite(check.drift_limit)) or any("footnote" in w
                                                          for w in check.drift_why):
            f.variable("story_drift_ratio_limit", ("story",), check.drift_limit, units="1",
                       long_name="allowed peak storey drift ratio",
                       comment="; ".join(dict.fromkeys(check.drift_why)))
            f.variable("story_drift_ratio_margin", ("story",), check.drift_margin, units="1",
                       long_name="drift ratio limit less the peak storey drift ratio "
                       "(negative: exceeded)", comment=reason)
            f.variable("story_drift_ratio_utilisation", ("story",), check.drift_utilisation,
                       units="1", long_name="peak storey drift ratio over its limit (above "
                       "1: exceeded)", comment=reason)
        if np.isfinite(check.acceleration_limit):
            for name, values, long_name in (
                    ("floor_acceleration_limit", np.full(len(check.node_names),
                                                         check.acceleration_limit),
                     "allowed peak absolute floor acceleration"),
                    ("floor_acceleration_margin", check.acceleration_margin,
                     "acceleration limit less the peak absolute floor acceleration (negative: "
                     "exceeded)")):
                data, units, long_name = self.convert.variable(values, "m/s^2", long_name)
                f.variable(name, ("node",), data, units=units, long_name=long_name,
                           comment=check.acceleration_why)
            f.variable("floor_acceleration_utilisation", ("node",),
                       check.acceleration_utilisation, units="1", long_name="peak absolute "
                       "floor acceleration over its limit (above 1: exceeded)")
        self.limit_attributes = {"limits": BASIS,
                                 "limits_exceeded": "\n".join(check.exceeded())}

    def _column_shears(self, result):
        """The shear the floor-to-column contacts put into the struck columns: the peak of
        each contact over the run (``peak_column_shear``, from the kernel's envelope of the
        contact force) and, with a ``contact_force`` history, that of each impact seen in it
        (``impact_column_shear`` along the dimension ``impact``, at ``impact_time``, the
        sample of its peak force): max(psi, 1 - psi) times the contact force
        (``Element.column_weight``)."""
        from pframe.episodes import positive_runs

        f, contacts = self.file, self.loaded.expanded.contacts
        name = "shear put into the struck column (floor-to-column contact)"
        data, units, long_name = self.convert.variable(result.column_shear(self.member), "N",
                                                       name)
        f.variable("peak_column_shear", ("contact",), data, fill=np.nan, units=units,
                   long_name=f"peak absolute {long_name}")
        every = dict(self.plan.history).get("contact_force")
        if every is None:
            return
        dim = self.time_dims[every]
        force, times = f.values("contact_force"), f.values(dim)
        rows = []  # (contact, time of the peak, column shear), in file units
        for c, contact in enumerate(contacts):
            weight = contact.column_weight
            if weight is None:
                continue
            column = np.nan_to_num(force[:, c])
            for i, j in positive_runs(column):
                k = i + int(np.argmax(column[i:j + 1]))
                rows.append((contact.name, float(times[k]), weight * float(column[k])))
        rows.sort(key=lambda row: row[1])
        f.labels("impact", "impact_contact", [r[0] for r in rows],
                 long_name="floor-to-column contact of the impact")
        _, time_units, _ = self.convert.time(np.zeros(0))
        f.variable("impact_time", ("impact",), np.array([r[1] for r in rows]),
                   units=time_units, long_name="time of the impact's peak contact force "
                   "(its sample in the contact_force history)")
        _, units, long_name = self.convert.variable(np.zeros(0), "N", name)
        f.variable("impact_column_shear", ("impact",), np.array([r[2] for r in rows]),
                   units=units, long_name=f"peak {long_name} in one impact")

    def _attributes(self, result):
        f, plan, loaded, member = self.file, self.plan, self.loaded, self.member
        convert = self.convert
        attrs = provenance(self.call)
        attrs["title"] = getattr(loaded.scene, "title", "") or Path(loaded.source).stem
        attrs["source"] = str(loaded.source)
        attrs["input_yaml"] = loaded.text
        attrs.update(record_attributes(loaded))
        attrs["integrator"] = integrator_text(plan)
        attrs["integrator_scheme"] = plan.integrator.describe_scheme()
        if plan.damping_text:  # each building's damping as applied (docs/theory.md#damping)
            attrs["damping"] = "\n".join(plan.damping_text)
        if plan.foundations:  # the soil applied (docs/soil.md)
            attrs["soil"] = "\n".join(f"{b}: {text}" for b, text in
                                      zip(plan.foundations, plan.foundation_soil))
            attrs.update(soil_attributes(plan, member))
        # the verdict the file states, kept for the caller to tell (not judged twice)
        self.verdict = verdict = of_result(result, member)
        attrs["warnings"] = "\n".join(plan.warnings + verdict.warnings)
        attrs.update(getattr(self, "limit_attributes", {}))
        attrs["dt"] = float(plan.dt[member])
        attrs["steps"] = np.int64(plan.steps)
        attrs["steps_completed"] = np.int64(result.states_done(member) - 1)
        attrs["solve_seconds"] = float(result.solve_seconds)
        for counter, name in COUNTER_ATTRIBUTES:
            attrs[name] = np.int64(result.counter(counter, member))
        attrs["status"] = result.describe_failure(member)
        attrs["complete"] = np.int8(result.completed(member))
        attrs["energy_balance_error"] = verdict.balance_error
        attrs["algorithmic_dissipation"] = verdict.algorithmic
        attrs["accuracy"] = verdict.level
        attrs["trusted"] = np.int8(verdict.trusted)
        for term, value in result.energy_terms(member).items():
            attrs[f"energy_{term}"] = float(convert.energy(value))
        attrs.update(reference_attributes(loaded))
        attrs.update(convert.attributes(float(plan.dt[member])))
        f.attrs.update(convert.restated(with_units(attrs, convert.energy_units)))


def reference_attributes(loaded) -> dict:
    """The reference scales m_b, a_p, w_p, l_e of the paper's dimensionless variables
    (``reference_*`` attributes; none for a scene that has neither an excitation with an
    amplitude and a frequency nor ``output.scales``: ``loaded.reference`` is None)."""
    if loaded.reference is None:
        return {}
    m, a, w = (float(loaded.reference[k]) for k in ("m_b", "a_p", "w_p"))
    try:  # scales from an absurd record (DT = 1e-300 s) overflow: then there are none
        values = {"reference_m_b": m, "reference_a_p": a, "reference_w_p": w,
                  "reference_l_e": a / w**2}
    except (OverflowError, ZeroDivisionError):
        return {}
    return values if all(math.isfinite(v) for v in values.values()) else {}


def record_attributes(loaded) -> dict:
    """The ground motion a run applied, so that the file alone reproduces and confirms the run.

    For every excitation: ``excitation_applied`` (the motion in words, as ``pframe validate``
    prints it), ``excitation_pga`` (m/s^2, the peak |a_g| after every scaling),
    ``excitation_pga_g`` (the same in g), ``excitation_pga_time`` (s, when it occurs),
    ``excitation_end`` (s, when the ground comes to rest; inf for a sine without end) and
    ``excitation_applied_peak`` (m/s^2, the peak within the analysis). For a record besides:
    ``record_file`` (as the scene names it), ``record_sha256``, ``record_text`` (the file's
    whole text) and ``record_read_as`` (format, units and where they were read, points, step,
    duration, PGA applied and when, what part the analysis covers). Two components
    (``kind: components``): ``excitation_applied`` says both and the angle, and each
    component's facts carry its axis, ``excitation_x_pga``, ``record_x_file``, ...,
    ``excitation_y_pga``, ``record_y_file``, ... (a component has its own peak, the
    site's axes each a mix of the two). A scene on supports (docs/supports.md): the motion a
    wave passage carries (``excitation_applied`` with each support's delay) or the scene's,
    and each support's own under its name (``excitation_east_pga``, ``record_east_file``,
    ...)."""
    scene = loaded.scene
    expanded = getattr(loaded, "expanded", None)
    duration = None if expanded is None else float(expanded.dt * expanded.steps)
    supports = list(getattr(scene, "supports", ()) or ())
    own = [s.excitation is not None for s in supports]
    motions = tuple(getattr(expanded, "support_motions", ()) or ())
    shared = next((m for m, mine in zip(motions, own) if not mine), None)
    out = {}
    excitation = scene.excitation
    if excitation is not None and excitation.kind == "wave_passage":
        out.update(_excitation_attributes(excitation.motion, shared, expanded, loaded,
                                          duration, ""))
        out["excitation_applied"] = (
            f"a wave passage at {excitation.velocity:g} m/s towards {excitation.direction:g} "
            "degrees (" + ", ".join(f"{name} {tau:.4g} s" for name, tau in zip(
                expanded.supports, expanded.support_delays)) + "): "
            + out.get("excitation_applied", excitation.motion.kind))
    elif excitation is not None and not (supports and all(own)):
        out.update(_excitation_attributes(excitation, shared, expanded, loaded, duration, ""))
    for support, mine, motion in zip(supports, own, motions):
        if mine:  # its own motion: its facts under its name
            out.update(_excitation_attributes(support.excitation, motion, expanded, loaded,
                                              duration, f"{support.name}_"))
    if expanded is not None:  # how the supports' displacements were had, where used
        from pframe.model.support_motion import displacement_lines

        said = displacement_lines(expanded)
        if said:
            out["ground_displacement_method"] = "\n".join(said)
    return out


def _excitation_attributes(excitation, ground, expanded, loaded, duration, name) -> dict:
    """:func:`record_attributes` of one excitation (a motion or two components) as applied
    (``ground`` its GroundMotion, None: the scene's one), its attributes' names with
    ``name`` after ``excitation_`` and ``record_`` (a support's: ``east_``)."""
    record = ground.record if ground is not None else getattr(expanded, "record", None)
    if excitation.kind != "components":
        return _motion_attributes(excitation, record, loaded, duration,
                                  f"excitation_{name}", f"record_{name}")
    records = dict(ground.records if ground is not None
                   else getattr(expanded, "component_records", ()) or ())
    out, said = {}, []
    for axis, motion in excitation.motions():
        part = _motion_attributes(motion, records.get(axis), loaded, duration,
                                  f"excitation_{name}{axis}_", f"record_{name}{axis}_")
        said.append(f"{axis}: {part.pop(f'excitation_{name}{axis}_applied', motion.kind)}")
        out.update(part)
    out[f"excitation_{name}applied"] = (f"two components, x at {excitation.angle:g} degrees "
                                       "from the site's x axis and y at 90 degrees to it: "
                                       + "; ".join(said))
    return out


def _motion_attributes(excitation, record, loaded, duration, facts_prefix: str,
                       record_prefix: str) -> dict:
    """:func:`record_attributes` of one motion, its names with the prefixes given."""
    out = {}
    try:  # what the ground did: a fact we cannot state is left out, never a failed write
        from pframe.excitation.describe import (
            applied_motion,
            describe_line,
            describe_scene_record,
            motion_line,
        )

        facts = applied_motion(excitation, record, duration)
        out.update({f"{facts_prefix}pga": facts["pga"], f"{facts_prefix}pga_g": facts["pga_g"],
                    f"{facts_prefix}pga_time": facts["pga_time"]})
        if np.isfinite(facts["end"]):  # a sine without end has none
            out[f"{facts_prefix}end"] = facts["end"]
        if duration is not None:
            out[f"{facts_prefix}applied_peak"] = facts["applied_peak"]
        if excitation.kind != "record":
            out[f"{facts_prefix}applied"] = motion_line(facts).removeprefix("excitation: ")
    except Exception:
        pass
    if excitation.kind != "record":
        return out
    import hashlib

    path = Path(loaded.base_dir) / excitation.file
    try:
        content = path.read_bytes()
    except OSError:
        return out | {f"{record_prefix}file": excitation.file}
    out.update({f"{record_prefix}file": excitation.file,
                f"{record_prefix}sha256": hashlib.sha256(content).hexdigest(),
                f"{record_prefix}text": content.decode("utf-8", errors="replace")})
    for quantity in ("displacement", "velocity"):  # its other files: pframe.load restores
        name = getattr(excitation, quantity, None)
        try:
            other = (Path(loaded.base_dir) / name).read_bytes() if name else None
        except OSError:
            other = None
        if other is not None:
            out.update({f"{record_prefix}{quantity}_file": name,
                        f"{record_prefix}{quantity}_sha256": hashlib.sha256(other).hexdigest(),
                        f"{record_prefix}{quantity}_text": other.decode("utf-8",
                                                                       errors="replace")})
    try:  # how the record was read and applied (pframe validate prints it)
        read = describe_scene_record(excitation, loaded.base_dir)
        line = describe_line(read, duration).removeprefix(f"record {read['file']}: ")
        out[f"{record_prefix}read_as"] = line
        out[f"{facts_prefix}applied"] = f"record {excitation.file}: {line}"
    except Exception:
        pass
    return out


def write_result(target, result, loaded, member: int = 0, compress: bool = False,
                 call: str | None = None):
    """Write one batch member's result, histories in memory, to ``target`` (a path: via a
    temporary file and an atomic rename; or a binary file object)."""
    writer = ResultWriter(target, result.plan, loaded, member, states=result.states_done(member),
                          compress=compress, call=call)
    with writer:
        for q, _ in result.plan.history:
            writer.put(q, 0, result.history[q][member])
        return writer.finish(result)


def soil_attributes(plan, member: int = 0) -> dict:
    """The soil's springs and dashpots as applied, one value per foundation (docs/soil.md):
    ``soil_sway_stiffness`` (N/m), ``soil_sway_damping`` (N s/m), ``soil_rocking_stiffness``
    (N m/rad), ``soil_rocking_damping`` (N m s/rad)."""
    first = plan.n_springs - 2 * len(plan.foundations)
    values = np.zeros((plan.n_springs, 2))
    for group in plan.story_groups:
        for j, e in enumerate(group.index):
            if e >= first:
                values[e] = group.params[member, j, :2]
    sway, rocking = values[first::2], values[first + 1::2]
    return {"soil_sway_stiffness": sway[:, 0], "soil_sway_damping": sway[:, 1],
            "soil_rocking_stiffness": rocking[:, 0], "soil_rocking_damping": rocking[:, 1]}
