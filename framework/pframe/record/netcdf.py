"""netCDF-4 files that follow the CF conventions (1.8), written through h5netcdf.

The one place where pframe's result files (``pframe solve``, ``pframe sweep``) are laid out,
so both pass ``compliance-checker --test=cf:1.8`` and ``cfchecks`` without errors and read as
they are in xarray, ncdump, MATLAB and ParaView:

- numeric coordinate variables only: a dimension whose positions are named (``node``,
  ``story``, ``contact``, ``building``, a swept record file) has no coordinate variable but a
  *label* variable (``node_name``: CF 1.8 section 6.1, a character array decoded to strings by
  xarray, named in the ``coordinates`` attribute of the variables that use it);
- the simulated time is ``t`` in seconds (``units = "s"``): a duration since the start of the
  analysis, not a calendar time, so it carries no ``since <epoch>`` and no ``axis = "T"``;
- variables are float64, int32 or int8 (no int64), strings are character arrays;
- global attributes name the conventions and record provenance (``history``,
  ``date_created``, versions; :func:`provenance`).
"""

from __future__ import annotations

import datetime
import platform
import re
import sys
import weakref
from pathlib import Path

import h5netcdf
import h5py
import numpy as np

CONVENTIONS = "CF-1.8"
#: bytes of one HDF5 chunk of a history (a few chunks per variable fit HDF5's 1 MiB cache)
CHUNK_BYTES = 256 * 2**10
#: deflate settings of ``compress=True`` (shuffle + gzip level 1: the paper's example,
#: 11.8 MB, becomes 7.5 MB; level 4 saves 1 % more for 10 % more time)
COMPRESSION = {"compression": "gzip", "compression_opts": 1, "shuffle": True}


def _encoded(strings) -> np.ndarray:
    """UTF-8 character array (..., n) of a string array (n: the longest, at least 1)."""
    values = np.asarray(strings, dtype=object)
    encoded = np.array([str(s).encode("utf-8") for s in values.ravel()], dtype=bytes)
    width = max(1, encoded.dtype.itemsize)
    encoded = encoded.astype(f"S{width}")
    return encoded.view("S1").reshape(values.shape + (width,))


class _Found(h5py.File):
    """An HDF5 file whose objects are each found once. h5netcdf looks a dataset up by its
    path on every use of it (a variable's shape, each dimension's length, attaching a scale),
    and each lookup makes a new h5py object: laying out a result file made about 400 of them,
    most of its cost. A lookup by path is kept; deleting an object (h5netcdf replaces a
    dimension's placeholder by its coordinate variable) forgets them all."""

    def __init__(self, *args, **kwargs):
        super().__init__(*args, **kwargs)
        self._found: dict = {}

    def __getitem__(self, name):
        if not isinstance(name, str):  # an object reference
            return super().__getitem__(name)
        found = self._found.get(name)
        if found is None:
            found = super().__getitem__(name)
            if name == "/":  # the root group: what is deleted through it is seen
                found = _FoundGroup(found.id, self)
            self._found[name] = found
        return found

    def __delitem__(self, name):
        self._found.clear()
        super().__delitem__(name)


class _FoundGroup(h5py.Group):
    """The root group of a :class:`_Found` file: its lookups and deletions are the file's
    (which it refers to weakly: the file keeps it)."""

    def __init__(self, bind, file: _Found):
        super().__init__(bind)
        self._file = weakref.ref(file)

    def __getitem__(self, name):
        file = self._file()
        if isinstance(name, str) and file is not None:
            return file[name]
        return super().__getitem__(name)

    def __delitem__(self, name):
        file = self._file()
        if file is not None:
            file._found.clear()
        super().__delitem__(name)


def _open(target):
    """``h5netcdf.File(target, "w")`` on a :class:`_Found` file, safe against a signal inside
    its constructor: h5netcdf marks a half-built file closed only when an ``Exception``
    interrupts it, so a stop (Ctrl-C, SIGTERM: ``BaseException``) there left a file whose
    destructor printed a traceback. h5netcdf closes a file it was given open only when told:
    :meth:`Writer.close` does."""
    h5 = _Found(target, "w", track_order=True)  # what h5netcdf opens a new file with
    try:
        f = h5netcdf.File.__new__(h5netcdf.File)
        f._closed = True  # until the constructor says otherwise
        f.__init__(h5, "w", track_order=True)
    except BaseException:
        h5.close()
        raise
    return f


class Writer:
    """A netCDF-4 file being written: ``target`` is a path or a binary file object (an
    in-memory result); ``compress`` deflates the large variables (histories)."""

    def __init__(self, target, compress: bool = False):
        if isinstance(target, (str, Path)):
            target = str(target)
        self.file = _open(target)
        self.compress = compress
        self._coordinates: dict[str, list[str]] = {}  # dimension -> its auxiliary coordinates
        # dimension -> its length (0 for an unlimited one until resized): h5netcdf finds an
        # unlimited dimension's length by scanning every variable along it
        self._sizes: dict[str, int] = {}
        # name -> its HDF5 dataset: h5netcdf finds one by a lookup in the file each time
        self._datasets: dict = {}
        # whether an h5netcdf variable was handed out (__getitem__): text set on its
        # attributes is h5netcdf's variable-length kind, which close then rewrites
        self._handed_out = False

    # -- structure --------------------------------------------------------------------------
    def dimension(self, name: str, size: int | None) -> None:
        """A dimension; ``size`` None makes it unlimited (resizable: streamed histories)."""
        self.file.dimensions[name] = size
        self._sizes[name] = size or 0

    def coordinate(self, name: str, values, **attrs):
        """A numeric coordinate variable: dimension ``name`` with values ``values``."""
        values = np.asarray(values)
        if name not in self.file.dimensions:
            self.dimension(name, len(values))
        var = self._create(name, (name,), data=values)
        self._put(name, var, attrs)
        return var

    def labels(self, dimension: str, name: str, strings, **attrs):
        """Names of the positions along ``dimension`` (a string-valued auxiliary coordinate);
        every variable along ``dimension`` names it in its ``coordinates``."""
        if dimension not in self.file.dimensions:
            self.dimension(dimension, len(strings))
        return self.strings(name, (dimension,), strings, auxiliary=True, **attrs)

    def strings(self, name: str, dims: tuple[str, ...], strings, auxiliary: bool = False,
                **attrs):
        """A string-valued variable, stored as a UTF-8 character array (``auxiliary``: an
        auxiliary coordinate along its dimension)."""
        chars = _encoded(strings)
        width = f"string{chars.shape[-1]}"
        if width not in self.file.dimensions:
            self.dimension(width, chars.shape[-1])
        var = self._create(name, tuple(dims) + (width,), data=chars)
        self._put(name, var, {"_Encoding": "utf-8"})
        self._place(name, var, tuple(dims), auxiliary)
        self._put(name, var, attrs)
        return var

    def _place(self, name: str, var, dims: tuple[str, ...], auxiliary: bool,
               coordinates: tuple[str, ...] = ()) -> None:
        """Register an auxiliary coordinate, or name the auxiliary coordinates of the
        variable's dimensions in its ``coordinates`` attribute."""
        if auxiliary:
            self._coordinates.setdefault(dims[0], []).append(name)
            return
        named = [c for d in dims for c in self._coordinates.get(d, ())]
        named += [c for c in coordinates if c not in named]
        if named:
            self._put(name, var, {"coordinates": " ".join(named)})

    def variable(self, name: str, dims: tuple[str, ...], data=None, *, dtype="f8",
                 fill=None, chunk_rows: bool = False, coordinates: tuple[str, ...] = (),
                 auxiliary: bool = False, **attrs):
        """A data variable. ``data`` None leaves it to be filled (``chunk_rows``: chunked along
        its first dimension, for rows given block by block, and deflated when the writer
        compresses). ``coordinates``: further auxiliary coordinates to name; ``auxiliary``:
        the variable is itself one, along its (only) dimension."""
        dims = tuple(dims)
        kwargs: dict = {}
        if data is not None:
            data = np.asarray(data)
            dtype = data.dtype
        if np.dtype(dtype) == np.int64:
            raise TypeError(f"{name}: CF files hold no int64 variables; use int32")
        if chunk_rows:
            shape = tuple(self._sizes[d] for d in dims)
            width = int(np.prod(shape[1:], dtype=np.int64)) if len(shape) > 1 else 1
            rows = max(1, CHUNK_BYTES // (8 * max(1, width)))
            kwargs["chunks"] = (max(1, min(rows, shape[0] or rows)),) + tuple(
                max(1, s) for s in shape[1:])
            if self.compress:
                kwargs.update(COMPRESSION)
        var = self._create(name, dims, dtype=dtype, data=data, fillvalue=fill, **kwargs)
        self._place(name, var, dims, auxiliary, coordinates)
        self._put(name, var, {k: v for k, v in attrs.items() if v is not None})
        return var

    def _create(self, name: str, dims, **kwargs):
        # a variable named as a dimension replaces that dimension's placeholder dataset
        self._datasets.pop(name, None)
        return self.file.create_variable(name, dims, **kwargs)

    def _put(self, name: str, var, values: dict) -> None:
        """Set attributes of variable ``var`` (see :func:`_put`)."""
        if values:
            _put(_Lazy(lambda: var.attrs), self.rows(name).attrs, values)

    def resize(self, dimension: str, size: int) -> None:
        """Set the length of an unlimited dimension (and of every variable along it)."""
        self.file.resize_dimension(dimension, size)
        self._sizes[dimension] = size

    def __getitem__(self, name: str):
        self._handed_out = True
        return self.file[name]

    def rows(self, name: str):
        """Where a block of rows of ``name`` is written: its HDF5 dataset itself. h5netcdf's
        variable finds its shape by scanning every variable of an unlimited dimension on each
        access, which costs more than the writing for a streamed history (the variable's
        layout and attributes are h5netcdf's; only the values go this way)."""
        dataset = self._datasets.get(name)
        if dataset is None:
            var = self.file[name]
            dataset = self._datasets[name] = getattr(var, "_h5ds", var)
        return dataset

    def values(self, name: str) -> np.ndarray:
        """The values written so far of ``name`` (read back: a history the file holds)."""
        return np.asarray(self.rows(name)[...])

    @property
    def attrs(self):
        """The global attributes, to be set: ``update`` and item assignment write text as
        fixed-length strings at once (see :func:`_put`)."""
        return _Attributes(self.file.attrs, self.file._h5file.attrs)

    def close(self) -> None:
        if self.file is not None:
            try:
                if sys.exc_info()[0] is None:  # a whole file (not one being abandoned)
                    self.file.flush()
                    # what the writer's own methods set is fixed-length already (_put): the
                    # scan (3 ms of a short run) only when a variable was handed out
                    if self._handed_out:
                        fixed_length_text(self.file._h5file)
            finally:
                h5 = self.file._h5file
                self.file.close()  # h5netcdf flushes; a file it was given stays open
                h5.close()  # (not after a failed flush: see ResultWriter.abort)
                self.file = None


def provenance(call: str | None = None) -> dict:
    """Global attributes that say when and by what a file was written: ``date_created``
    (ISO 8601, UTC), ``history`` (CF: the date and the command line or API call), the
    versions of pframe (and of its compiled kernel's sources), Python, numpy and numba (which
    compiles plug-in laws: read from the installed metadata, never imported), and the
    platform."""
    import pframe
    from pframe.kernel.ckernel import library

    numba_version = installed_version("numba")
    now = datetime.datetime.now(datetime.timezone.utc).replace(microsecond=0)
    stamp = now.isoformat().replace("+00:00", "Z")
    if call is None:
        call = " ".join(["pframe"] + sys.argv[1:]) if Path(sys.argv[0]).name == "pframe" else (
            " ".join(sys.argv) or "python")
    return {
        "Conventions": CONVENTIONS,
        "date_created": stamp,
        "history": f"{stamp} pframe {pframe.__version__}: {call}",
        "pframe_version": pframe.__version__,
        "software": (f"pframe {pframe.__version__}; Python {platform.python_version()}; "
                     f"numpy {np.__version__}; numba {numba_version}; "
                     f"kernel {library().pframe_source_hash().decode()}; "
                     f"h5netcdf {h5netcdf.__version__}; {platform.platform()}"),
    }


def installed_version(name: str) -> str:
    """The version of the installed distribution ``name`` as ``importlib.metadata.version``
    gives it, or ``"not installed"``.

    importlib.metadata finds the first ``<name>-<version>.dist-info`` (or ``.egg-info``)
    folder along ``sys.path`` and reads the ``Version`` field of its metadata with the email
    package: importing the two costs a short command about 15 ms. The common case, that
    folder a ``.dist-info`` in a directory on the path, is read here as importlib.metadata
    reads it (the same names, in the same order of the path and of each directory's
    listing); anything else (an ``.egg-info``, an archive on the path, no such folder) is
    left to importlib.metadata itself."""
    import os

    def normalized(text: str) -> str:  # importlib.metadata.Prepared.normalize
        return re.sub(r"[-_.]+", "-", text).lower().replace("-", "_")

    wanted = normalized(name)
    for entry in sys.path:
        folder = entry or "."
        if not os.path.isdir(folder) or folder.lower().endswith(".egg"):
            if os.path.exists(folder):
                break  # an archive or an egg on the path: importlib.metadata's to read
            continue
        try:
            children = os.listdir(folder)
        except OSError:
            break
        found = next((c for c in children if c.lower().endswith((".dist-info", ".egg-info"))
                      and normalized(c.lower().rpartition(".")[0].partition("-")[0]) == wanted),
                     None)
        if found is None:
            continue
        if found.lower().endswith(".dist-info"):
            try:
                text = Path(folder, found, "METADATA").read_text(encoding="utf-8")
            except OSError:
                break
            header = text.split("\n\n", 1)[0].splitlines()
            version = next((line.partition(":")[2].strip() for line in header
                            if line.partition(":")[0] == "Version"), None)
            if version:
                return version
        break
    from importlib.metadata import PackageNotFoundError, version

    try:
        return version(name)
    except PackageNotFoundError:
        return "not installed"


#: the unit of each numeric global attribute that has one. CF gives attributes no units, so
#: pframe writes each beside its attribute as a text attribute ``<name>_units`` (UDUNITS
#: syntax, as a variable's ``units``): ``dt = 0.001``, ``dt_units = "s"``. Counts and flags
#: (``steps``, ``complete``) have none; ratios have ``"1"``. Energies are in J, or ``"1"`` in
#: a dimensionless file (``energy_units`` of :func:`with_units`).
ATTRIBUTE_UNITS = {
    "dt": "s", "duration": "s", "solve_seconds": "s", "dtau": "1",
    "excitation_pga": "m/s^2", "excitation_pga_g": "9.80665 m/s^2",  # STANDARD_GRAVITY
    "excitation_pga_time": "s", "excitation_end": "s", "excitation_applied_peak": "m/s^2",
    "energy_balance_error": "1", "algorithmic_dissipation": "1",
    "reference_m_b": "kg", "reference_a_p": "m/s^2", "reference_w_p": "rad/s",
    "reference_l_e": "m",
    "scale_m_b": "kg", "scale_a_p": "m/s^2", "scale_w_p": "rad/s", "scale_l_e": "m",
    "soil_sway_stiffness": "N/m", "soil_sway_damping": "N s/m",
    "soil_rocking_stiffness": "N m/rad", "soil_rocking_damping": "N m s/rad",
}
# each of two components' facts (kind: components) as the one motion's
ATTRIBUTE_UNITS.update({f"excitation_{axis}_{name[len('excitation_'):]}": units
                        for axis in ("x", "y") for name, units in list(ATTRIBUTE_UNITS.items())
                        if name.startswith("excitation_")})
#: one standard gravity (an acceleration "in g") in UDUNITS: ``"g"`` there is the gram
STANDARD_GRAVITY = "9.80665 m/s^2"
#: the unit of every annual frequency a file holds (hazard curves, rates of limit states,
#: targets), in UDUNITS' terms: one spelling, so that a reader comparing two files' units
#: as text finds them equal
PER_YEAR = "year-1"


def short_units(units) -> str:
    """A unit as a label shows it: ``g`` for :data:`STANDARD_GRAVITY` (and for the ``g``
    that gap-audit files written before it meant)."""
    units = units.decode() if isinstance(units, bytes) else str(units)
    return "g" if units in ("g", STANDARD_GRAVITY) else units


#: suffix of the text attribute that holds another attribute's unit
UNITS_SUFFIX = "_units"


def attribute_unit(name: str, energy_units: str = "J") -> str | None:
    """The unit of global attribute ``name`` (None: it has none)."""
    if name in ATTRIBUTE_UNITS:
        return ATTRIBUTE_UNITS[name]
    if name.startswith("excitation_"):  # a support's own motion: excitation_east_pga, ...
        for known, unit in ATTRIBUTE_UNITS.items():
            if known.startswith("excitation_") and name.endswith(known[len("excitation"):]):
                return unit
    if name.startswith("energy_"):
        return energy_units
    return None


def with_units(attrs: dict, energy_units: str = "J") -> dict:
    """``attrs`` with ``<name>_units`` right after each numeric attribute that has a unit
    (:data:`ATTRIBUTE_UNITS`)."""
    out = {}
    for name, value in attrs.items():
        out[name] = value
        unit = attribute_unit(name, energy_units)
        if unit is not None and not isinstance(value, (str, bytes)):
            out[name + UNITS_SUFFIX] = unit
    return out


def is_unit_attribute(name: str, attrs) -> bool:
    """True for ``<name>_units``, the unit of attribute ``<name>`` of ``attrs``."""
    return name.endswith(UNITS_SUFFIX) and name[:-len(UNITS_SUFFIX)] in attrs


def write_dataset(ds, path, call: str | None = None) -> Path:
    """Write an xarray Dataset that follows the layout above (names as ``<dim>_name`` label
    coordinates, no string coordinate variables) to ``path``: strings as character arrays,
    int64 as int32, no fill value on coordinates, provenance attributes added; via a
    temporary file in the same folder, renamed when complete (the file is whole or absent)."""

    path = Path(path)
    ds = ds.copy()
    for name, _index in list(ds.xindexes.items()):
        if name not in ds.dims:  # an index on a label: the file keeps the labels only
            ds = ds.drop_indexes(name)
    encoding = {}
    for dim in list(ds.dims):  # names as coordinate values (pframe.indexed): labels only
        if dim in ds.coords and ds[dim].dtype.kind in "OUS":
            if f"{dim}_name" not in ds.coords and f"{dim}_file" not in ds.coords:
                ds = ds.assign_coords({f"{dim}_name": (dim, ds[dim].values, ds[dim].attrs)})
            ds = ds.drop_vars(dim)
    for name, var in ds.variables.items():
        if var.dtype.kind in "OUS":
            encoding[name] = {"dtype": "S1"}
        elif var.dtype == np.int64:
            ds[name] = var.astype(np.int32)
        if name in ds.coords and var.dtype.kind == "f":
            encoding.setdefault(name, {})["_FillValue"] = None
    ds.attrs = {**provenance(call), **{k: v for k, v in ds.attrs.items()
                                       if k not in ("date_created", "history")}}
    from pframe import outputs

    with outputs.replacing(path) as tmp:
        ds.to_netcdf(tmp, engine="h5netcdf", encoding=encoding)
        import h5py

        with h5py.File(tmp, "r+") as f:
            fixed_length_text(f)
    return path


def _text_attribute(attrs, name: str, text: str) -> None:
    """Write ``text`` as a fixed-length string attribute (what netCDF-C writes for NC_CHAR:
    null-terminated, ASCII or UTF-8 character set; an empty text is one null byte)."""
    import h5py

    data = text.encode("utf-8")
    kind = h5py.h5t.C_S1.copy()
    kind.set_size(max(1, len(data)))
    kind.set_strpad(h5py.h5t.STR_NULLTERM)
    kind.set_cset(h5py.h5t.CSET_ASCII if text.isascii() else h5py.h5t.CSET_UTF8)
    if name in attrs:
        del attrs[name]
    space = h5py.h5s.create(h5py.h5s.SCALAR)
    attribute = h5py.h5a.create(attrs._id, name.encode("utf-8"), kind, space)
    attribute.write(np.array(data.ljust(max(1, len(data)), b"\0")), mtype=kind)


def _variable_text(attrs) -> dict[str, bool]:
    """Each attribute of ``attrs`` (but the HDF5 structure's): whether it is a
    variable-length text (a scalar NC_STRING)."""
    import h5py

    out = {}
    for name in attrs:
        if name in _STRUCTURE:
            continue
        attribute = attrs.get_id(name)
        kind = attribute.get_type()
        out[name] = (isinstance(kind, h5py.h5t.TypeStringID) and kind.is_variable_str()
                     and attribute.shape == ())
    return out


def _objects(group):
    """A group and everything under it that carries netCDF attributes (variables, groups)."""
    import h5py

    yield group
    for item in group.values():
        if isinstance(item, h5py.Group):
            yield from _objects(item)
        else:
            yield item


class _Lazy:
    """A mapping made when first written to (h5netcdf's attributes of a variable cost a
    lookup of the variable in the file: only numbers and arrays go through them)."""

    def __init__(self, make):
        self._make, self._made = make, None

    def __setitem__(self, name: str, value) -> None:
        if self._made is None:
            self._made = self._make()
        self._made[name] = value


def _put(attrs, h5attrs, values: dict) -> None:
    """Set attributes of a variable or of the file: text as a fixed-length string (NC_CHAR)
    through h5py at once, the rest through h5netcdf (``attrs``). h5netcdf writes text as a
    variable-length string, which :func:`fixed_length_text` would rewrite at the end: written
    right the first time, a file's attributes cost a third of what they did (the rewrite
    deleted and re-created most of them). The order is kept: both write in creation order."""
    for name, value in values.items():
        if isinstance(value, str) and name not in _STRUCTURE:
            _text_attribute(h5attrs, name, value)
        else:
            attrs[name] = value


class _Attributes:
    """A file's global attributes as :attr:`Writer.attrs` gives them, to be set (``update``,
    item assignment): text written fixed-length by :func:`_put`."""

    def __init__(self, attrs, h5attrs):
        self._attrs, self._h5attrs = attrs, h5attrs

    def update(self, values: dict) -> None:
        _put(self._attrs, self._h5attrs, dict(values))

    def __setitem__(self, name: str, value) -> None:
        _put(self._attrs, self._h5attrs, {name: value})


def fixed_length_text(f) -> None:
    """Turn every text attribute of an open h5py file (root, groups and variables) from a
    variable-length string (netCDF's NC_STRING, which h5netcdf writes and which Octave's
    netcdf package, among others, cannot read) into a fixed-length one (NC_CHAR, what every
    netCDF reader reads). Attributes keep their order: from an object's first text
    attribute on, all are rewritten. What :class:`Writer`'s own methods write is
    fixed-length already (:func:`_put`): it calls this (a scan, about 3 ms for the paper's
    example) only when it handed out a variable, whose attributes may have been set through
    h5netcdf."""
    for obj in _objects(f):
        attrs = obj.attrs
        text = _variable_text(attrs)
        names = list(text)
        first = next((i for i, n in enumerate(names) if text[n]), None)
        if first is None:
            continue
        for n in names[first:]:  # from the first text on, in order
            value = attrs[n]
            if text[n]:
                _text_attribute(attrs, n, value.decode("utf-8") if isinstance(value, bytes)
                                else str(value))
            else:
                dtype = attrs.get_id(n).dtype
                del attrs[n]
                attrs.create(n, value, dtype=dtype)


#: attributes of the HDF5 structure netCDF-4 is built on (dimension scales, netCDF's own)
_STRUCTURE = frozenset(("REFERENCE_LIST", "DIMENSION_LIST", "CLASS", "NAME", "_Netcdf4Dimid",
                        "_Netcdf4Coordinates", "_NCProperties", "_nc3_strict"))


class DatasetWriter:
    """The interface of :class:`Writer`, building an xarray Dataset in memory instead of a
    file: the same layout code (``pframe.record.hdf5.ResultWriter``) makes both, and the
    Dataset is what xarray reads from the file (strings decoded, auxiliary coordinates as
    coordinates, attributes as netCDF gives them). ``tests/test_api.py`` checks the two are
    identical."""

    def __init__(self):
        self.sizes: dict[str, int | None] = {}
        self.variables: dict[str, tuple[tuple[str, ...], np.ndarray, dict]] = {}
        self.auxiliary: list[str] = []
        self.attrs: dict = {}
        self._coordinates: dict[str, list[str]] = {}

    def dimension(self, name: str, size: int | None) -> None:
        self.sizes[name] = 0 if size is None else size

    def coordinate(self, name: str, values, **attrs):
        values = np.asarray(values)
        if name not in self.sizes:
            self.dimension(name, len(values))
        return self._add(name, (name,), values, attrs)

    def labels(self, dimension: str, name: str, strings, **attrs):
        if dimension not in self.sizes:
            self.dimension(dimension, len(strings))
        return self.strings(name, (dimension,), strings, auxiliary=True, **attrs)

    def strings(self, name: str, dims, strings, auxiliary: bool = False, **attrs):
        values = np.array([str(s) for s in np.asarray(strings, dtype=object).ravel()],
                          dtype=object).reshape(np.shape(strings))
        if auxiliary:
            self.auxiliary.append(name)
        return self._add(name, tuple(dims), values, attrs)

    def variable(self, name: str, dims, data=None, *, dtype="f8", fill=None,
                 chunk_rows: bool = False, coordinates=(), auxiliary: bool = False, **attrs):
        dims = tuple(dims)
        if data is None:
            data = np.full(tuple(self.sizes[d] for d in dims), np.nan, dtype=dtype)
        if auxiliary:
            self.auxiliary.append(name)
        return self._add(name, dims, np.array(data), {k: v for k, v in attrs.items()
                                                       if v is not None})

    def _add(self, name, dims, values, attrs):
        self.variables[name] = (dims, values, dict(attrs))
        return _Rows(self, name)

    def resize(self, dimension: str, size: int) -> None:
        self.sizes[dimension] = size
        for name, (dims, values, attrs) in self.variables.items():
            if dims and dims[0] == dimension:
                if values.shape[0] < size:
                    grown = np.full((size,) + values.shape[1:], np.nan, dtype=values.dtype)
                    grown[:values.shape[0]] = values
                    values = grown
                self.variables[name] = (dims, values[:size], attrs)

    def __getitem__(self, name: str):
        return _Rows(self, name)

    rows = __getitem__

    def values(self, name: str) -> np.ndarray:
        return self.variables[name][1]

    def close(self) -> None:
        pass

    def dataset(self):
        """The Dataset (xarray imported here: only an in-memory result needs it)."""
        import xarray as xr

        data, coords = {}, {}
        for name, (dims, values, attrs) in self.variables.items():
            variable = xr.Variable(dims, values, attrs)
            if name in self.auxiliary or (len(dims) == 1 and dims[0] == name):
                coords[name] = variable
            else:
                data[name] = variable
        return xr.Dataset(data, coords=coords, attrs=dict(self.attrs))


class _Rows:
    """``writer[name][lo:hi] = rows`` and ``.shape`` of a variable being built in memory."""

    def __init__(self, writer: DatasetWriter, name: str):
        self.writer, self.name = writer, name

    @property
    def shape(self):
        return self.writer.variables[self.name][1].shape

    @property
    def attrs(self):
        return self.writer.variables[self.name][2]

    def __setitem__(self, index, values):
        self.writer.variables[self.name][1][index] = values
