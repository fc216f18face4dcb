"""pframe from Python: scenes as objects, results as xarray Datasets (docs/python.md).

The command line is a shell over the same functions: ``pframe.solve(scene)`` gives the
Dataset that ``pframe solve`` writes (the file is laid out by one writer, in memory here), and
``pframe.open`` reads any pframe result file back as such a Dataset.
"""

from __future__ import annotations

import os
import shutil
import warnings
import weakref
from pathlib import Path

from pframe.errors import InputError
from pframe.objects import describe

#: suffixes of result files (``load`` of one rebuilds the scene it holds)
RESULT_SUFFIXES = (".nc", ".h5", ".hdf5", ".nc4")


class IncompleteRun(UserWarning):
    """A run stopped early: the Dataset holds the states computed (``complete = 0``, its
    ``status`` attribute says why, when and where)."""


# -- arguments: a wrong type is an InputError naming the call and the argument --------------

def path_argument(value, name: str, call: str, what: str) -> Path:
    """``value`` as a path (a ``str`` or ``os.PathLike``: ``pathlib.Path``); an InputError
    naming ``call``'s argument ``name`` for anything else, an empty name or a NUL byte."""
    text = os.fspath(value) if isinstance(value, os.PathLike) else value
    if not isinstance(text, str):
        raise InputError(f"{call}: {name} is {describe(value)}; give {what} as a str or a "
                         "pathlib.Path")
    if not text.strip():
        raise InputError(f"{call}: {name}={text!r} is an empty name; give {what}")
    if "\0" in text:
        raise InputError(f"{call}: {name}={text!r} holds a NUL character, which no file name "
                         f"has; give {what}")
    return Path(text)


def flag_argument(value, name: str, call: str, none: bool = False) -> bool | None:
    """``value`` as True or False (None too when ``none``); an InputError for anything else
    (a string "no" is true to Python: it is refused rather than read)."""
    import numpy as np

    if isinstance(value, (bool, np.bool_)) or (none and value is None):
        return None if value is None else bool(value)
    allowed = "True, False or None" if none else "True or False"
    raise InputError(f"{call}: {name} is {describe(value)}; give {allowed}")


def count_argument(value, name: str, call: str) -> int | None:
    """``value`` as a whole number of at least 1, or None; an InputError otherwise."""
    import numpy as np

    if value is None:
        return None
    if isinstance(value, (bool, np.bool_)) or not isinstance(value, (int, np.integer)):
        raise InputError(f"{call}: {name} is {describe(value)}; give a whole number of at least 1")
    if value < 1:
        raise InputError(f"{call}: {name}={int(value)}: give at least 1")
    return int(value)


def result_argument(result, call: str):
    """The result a function of results reads: an xarray Dataset as it is, a path as a
    :class:`~pathlib.Path`; an InputError naming ``call`` for anything else."""
    if isinstance(result, (str, os.PathLike)):
        return path_argument(result, "result", call, "a result file's path")
    import xarray as xr

    if isinstance(result, xr.Dataset):
        return result
    raise InputError(f"{call}: the result is {describe(result)}; give the Dataset of pframe.solve or "
                     "pframe.open, or a result file's path (str or pathlib.Path)")


def result_dataset(result, call: str):
    """The Dataset of ``result`` (a Dataset, or a result file's path, read whole) with the
    names as coordinates (:func:`indexed`); anything else is an InputError naming ``call``."""
    result = result_argument(result, call)
    if isinstance(result, Path):
        ds = open(result)
        ds.load()
        ds.close()
        return ds
    return indexed(result)


# -- scenes ---------------------------------------------------------------------------------

def load(source, *, base_dir: str | Path | None = None):
    """A validated scene (:class:`pframe.Scene`) from a file, YAML text data or objects.

    ``source`` is a scene file (dimensional or in Pi numbers), a pframe result file (the
    scene it ran, with the ground-motion record it read), a ``dict`` with the fields of the
    YAML, or a scene object. Files are checked exactly as ``pframe validate`` checks them;
    a problem raises :class:`pframe.InputError` naming the file, line and field. Record files
    are found relative to the scene file (``base_dir`` for data and objects: default, the
    current folder); a copy of a loaded scene (``model_copy``, with or without ``update``)
    keeps the folder its record was read from.
    """
    loaded = _loaded(source, base_dir)
    return _scene_of(loaded)


#: id(scene object) -> (weak reference to it, where it was read from, without the scene):
#: the file a loaded scene came from (record paths, the result's input_yaml), kept off the
#: scene's data; the entry holds no reference to the scene, so it goes when the scene does
_ORIGIN: dict[int, tuple] = {}


def _scene_of(loaded):
    import dataclasses

    from pframe.model.scene import attach_facts

    scene = loaded.scene
    key = id(scene)
    stripped = dataclasses.replace(loaded, scene=None)  # no cycle back to the scene
    _ORIGIN[key] = (weakref.ref(scene, lambda _, key=key, origin=_ORIGIN: origin.pop(key, None)),
                    stripped)
    attach_facts(scene, lambda: _periods(stripped.expanded))
    return scene


def _periods(expanded) -> list[str]:
    """The periods of a loaded scene's buildings (its repr ends with them)."""
    from pframe.assemble.modes import period_lines

    return period_lines(expanded)


def _origin(scene):
    import dataclasses

    entry = _ORIGIN.get(id(scene))
    if entry is None or entry[0]() is not scene:
        return None
    return dataclasses.replace(entry[1], scene=scene)


def to_opensees(scene, *, base_dir: str | Path | None = None) -> str:
    """A standalone OpenSeesPy script of a scene (anything :func:`load` takes), planar or in
    plan, each law written as its OpenSees twin (docs/python.md#a-scene-for-opensees); it
    runs without pframe, to cross-check it. A scene OpenSees cannot model is refused with
    every reason at once; where the script's model is not pframe's (a twin's own conditions,
    event location), each difference is warned of and written in the script."""
    loaded = _loaded(scene, base_dir)
    text, differences = opensees_script(loaded)
    for difference in differences:
        warnings.warn(f"{loaded.source}: the OpenSees script's model is not pframe's: "
                      f"{difference}", stacklevel=2)
    return text


def opensees_script(loaded) -> tuple[str, tuple[str, ...]]:
    """The OpenSeesPy script of a loaded scene (:func:`loaded_scene`) and where its model is
    not pframe's (``pframe opensees`` prints them, :func:`to_opensees` warns of them)."""
    from pframe.assemble import assemble
    from pframe.peers.from_plan import peer_scene
    from pframe.peers.opensees import script_text

    expanded = loaded.expanded
    peer = peer_scene(assemble(expanded), centres=expanded.node_centre)
    system = getattr(loaded, "system", None)
    written_in = None if system is None or system.si else system.name
    return script_text(peer, written_in=written_in), peer.differences


def loaded_scene(source, base_dir=None):
    """The validated scene with where it came from (:class:`pframe.reader.LoadedScene`)
    of anything :func:`load` takes."""
    return _loaded(source, base_dir)


def _loaded(source, base_dir=None):
    """The :class:`pframe.reader.LoadedScene` of any ``source`` that :func:`load` takes."""
    from pframe.model.scene import given_fields
    from pframe.reader import LoadedScene, load_scene, scene_from_data

    if isinstance(source, LoadedScene):
        return source
    if base_dir is not None:
        base_dir = path_argument(base_dir, "base_dir", "pframe.load",
                                 "the folder record files are found in")
    if isinstance(source, (str, os.PathLike)):
        path = path_argument(source, "source", "pframe.load", "a scene file's path")
        if path.suffix.lower() in RESULT_SUFFIXES:
            return _from_result(path)
        return load_scene(path)
    if isinstance(source, dict):
        # no lines: messages name the dict's keys (a line of text the user never saw would
        # not help); the text the result file keeps is made of the data when it is written
        return scene_from_data(given_fields(source, "pframe.load(dict)"), {},
                               "pframe.load(dict)", Path(base_dir or "."))
    loaded = _origin(source)
    if loaded is not None:
        return loaded
    from pydantic import BaseModel

    if isinstance(source, BaseModel) and hasattr(source, "to_yaml"):  # a scene object
        where = f"pframe.{type(source).__name__}"
        # its fields as data, checked as a dict's (a value model_construct let in is named by
        # its key), then validated and expanded once, as a file's data is: no text between
        data = given_fields(source, where)
        # a copy of a loaded scene (model_copy) finds its record where the original did
        excitation = getattr(source, "excitation", None)
        base = base_dir or getattr(excitation, "_folder", None) or "."
        return scene_from_data(data, {}, where, Path(base))
    raise InputError(f"pframe.load: cannot read a scene from {describe(source)}; give a scene "
                     "file's path (str or pathlib.Path), a dict with the fields of the YAML, "
                     "or a pframe.Scene")


def _from_result(path: Path):
    """The scene a result file ran: its ``input_yaml``, and its record restored from
    ``record_text`` into a private folder laid out so that the scene's relative record path
    finds it."""
    import h5py

    result_file(path, "pframe.load")
    try:
        with h5py.File(path, "r") as f:
            attrs = {k: f.attrs[k] for k in f.attrs
                     if k in ("input_yaml", "sweep_yaml") or _record_attribute(k)}
    except FileNotFoundError:
        raise InputError(f"{path}: no such result file") from None
    except OSError as exc:
        raise InputError(f"{path}: not a pframe result file (HDF5/netCDF-4): {exc}") from None
    return scene_of_attributes(attrs, path, Path(path).parent)


def scene_of_attributes(attrs: dict, path, base: Path):
    """The scene of a result's attributes (``input_yaml``, ``record_file``, ``record_text``:
    a file's or a Dataset's); ``path`` names it in messages."""
    from pframe.reader import parse_scene

    attrs = {k: v.decode() if isinstance(v, bytes) else str(v) for k, v in attrs.items()
             if k in ("input_yaml", "sweep_yaml") or _record_attribute(k)}
    if "sweep_yaml" in attrs:
        raise InputError(f"{path}: a sweep's result file holds many scenes; load its base "
                         "scene from the sweep file, or a variant with pframe sweep --variant")
    text = attrs.get("input_yaml")
    if not text:
        raise InputError(f"{path}: the file holds no scene (no input_yaml attribute)")
    records = [(Path(attrs[k]), attrs[k[:-len("file")] + "text"]) for k in sorted(attrs)
               if k.endswith("file") and k[:-len("file")] + "text" in attrs]
    for relative, _ in records:
        if relative.is_absolute():
            raise InputError(f"{path}: the scene names its record by the absolute path "
                             f"{relative}; run it from its scene file")
    if records:
        base = _restored_records(records, path)
    return parse_scene(text, f"{path} (input_yaml)", base)


def _record_attribute(name: str) -> bool:
    """Whether a result's attribute is a record's file name or text: ``record_file``,
    ``record_text``, of each component (``record_x_file``), of each support's own motion
    (``record_east_file``, ``record_east_y_text``)."""
    return name.startswith("record_") and name.endswith(("_file", "_text"))


#: the folder this process restores the records of result files into (one, removed at exit)
_RECORDS: list[Path] = []


def _restored_records(records, path) -> Path:
    """The folder from which each ``relative`` of ``records`` [(relative, text), ...] names
    its record ``text`` of the result ``path``: one sub-folder per set of records (by their
    names and contents) of one private folder per process, removed at exit. Loading a result
    again (or a hundred results of one record) reuses it, and the copies and variants of a
    loaded scene, which read the record again, find it for as long as the process runs."""
    import atexit
    import hashlib
    import tempfile  # with random: imported by the calls that make a folder only

    depth = max(sum(1 for part in relative.parts if part == "..") for relative, _ in records)
    if not _RECORDS:
        _RECORDS.append(Path(tempfile.mkdtemp(prefix="pframe-record-")))
        atexit.register(shutil.rmtree, str(_RECORDS[0]), ignore_errors=True)
    key = hashlib.sha256("\0".join(f"{relative}\0{text}" for relative, text in records)
                         .encode()).hexdigest()[:24]
    root = _RECORDS[0] / key
    base = root.joinpath(*(["d"] * depth))
    for relative, text in records:
        target = (base / relative).resolve()
        if root.resolve() not in target.parents:
            raise InputError(f"{path}: the record name {str(relative)!r} leaves its folder")
        if target.is_file():
            continue
        from pframe import outputs

        try:
            base.mkdir(parents=True, exist_ok=True)  # base/../x needs base itself
            target.parent.mkdir(parents=True, exist_ok=True)
        except OSError as exc:
            raise outputs.failure(target, exc) from None
        with outputs.replacing(target, overwrite=True) as tmp:
            tmp.write_text(text, encoding="utf-8")
    return base


# -- runs -----------------------------------------------------------------------------------

def solve(scene, *, output: str | Path | None = None, overwrite: bool = False,
          compress: bool = False, progress: bool | None = None):
    """Run a scene; return its results as an :class:`xarray.Dataset`.

    ``scene``: anything :func:`load` takes. The Dataset has exactly the layout of the file
    ``pframe solve`` writes (docs/netcdf.md): the same variables, coordinates, units and
    attributes. With ``output`` the histories stream to that file as they are computed (memory
    stays bounded) and the Dataset is opened from it, lazily; without, they are kept in
    memory. ``progress``: True, False, or None to draw a bar on a terminal or in a notebook.

    Raises :class:`pframe.InputError` for a bad scene or output path, or a run too large for
    the machine (docs/getting-started.md, limits), and :class:`pframe.EnvironmentFailure` when
    the output cannot be written (disk full, permission denied; nothing is left behind); a run
    that stops early returns what was computed (``complete`` attribute 0) with an
    :class:`IncompleteRun` warning.
    """
    from pframe.assemble import assemble
    from pframe.kernel import simulate
    from pframe.progress import bar
    from pframe.record import ResultWriter

    call = "pframe.solve"
    overwrite = flag_argument(overwrite, "overwrite", call)
    compress = flag_argument(compress, "compress", call)
    progress = flag_argument(progress, "progress", call, none=True)
    if output is not None:
        output = path_argument(output, "output", call, "the result file's path")
    loaded = _loaded(scene)
    if output is not None:
        output = check_output(output, overwrite, loaded)
    _check_resources(loaded, output)
    plan = assemble(loaded.expanded)
    from pframe.verdict import AccuracyWarning

    for text in plan.warnings:
        warnings.warn(f"{loaded.source}: {text}", AccuracyWarning, stacklevel=2)
    from pframe.record.netcdf import DatasetWriter

    target = DatasetWriter() if output is None else output
    progress_bar = bar(progress, "steps", Path(str(loaded.source)).name)
    call = _call("solve", loaded, output)
    try:
        with ResultWriter(target, plan, loaded, compress=compress and output is not None,
                          call=call) as writer:
            try:
                result = simulate(plan, progress=progress_bar, sink=writer.append)
            finally:
                if progress_bar is not None:
                    progress_bar.close()
            writer.finish(result)
    except OSError as exc:
        from pframe import outputs

        raise outputs.failure(output, exc) from None
    for text in writer.verdict.warnings:
        warnings.warn(f"{loaded.source}: {text}", AccuracyWarning, stacklevel=2)
    if not result.completed():
        warnings.warn(f"{loaded.source}: the run stopped early: {result.describe_failure()}; "
                      f"the Dataset holds the {result.states_done() - 1} steps computed",
                      IncompleteRun, stacklevel=2)
    if output is None:
        return indexed(target.dataset())
    return _opened(output)  # the file just written: not checked as a file of unknown origin


def _check_resources(loaded, output) -> None:
    """Refuse a run that cannot fit (pframe.resources); warn about a very large one."""
    import shutil

    from pframe import resources

    free = None
    if output is not None:
        try:
            free = shutil.disk_usage(Path(output).parent).free
        except OSError:
            pass
    estimate = resources.of_expanded(loaded.expanded, streaming=output is not None)
    for text in resources.check(estimate, str(loaded.source), free_disk=free):
        warnings.warn(f"{loaded.source}: {text}", stacklevel=3)


def _call(command: str, loaded, output) -> str:
    where = repr(str(loaded.source))
    out = "" if output is None else f", output={str(output)!r}"
    return f"pframe.{command}({where}{out}) (Python)"


def check_output(output, overwrite: bool, loaded=None) -> Path:
    """The output path, checked before a run (:func:`pframe.outputs.check_output`): not empty,
    not a folder, its folder exists and can be written, not an existing file unless
    ``overwrite``, not the scene or record the run reads, not being written by another run."""
    from pframe import outputs

    return outputs.check_output(output, inputs=run_inputs(loaded), overwrite=overwrite,
                                what="result file")


def run_inputs(loaded) -> list[Path]:
    """The files a loaded scene reads (the scene, its records with their displacement and
    velocity files): never an output."""
    inputs = []
    if loaded is not None:
        inputs.append(Path(str(loaded.source)))
        from pframe.model.scene import scene_motions

        scene = loaded.scene
        for motion in scene_motions(scene) if hasattr(scene, "excitation") else ():
            if motion.kind == "record":  # its files, and each support's record's
                inputs += [Path(loaded.base_dir) / name for name in
                           (motion.file, motion.displacement, motion.velocity) if name]
    return inputs


def sweep(definition, *, output: str | Path | None = None, overwrite: bool = False,
          threads: int | None = None, chunk: int | None = None, progress: bool | None = None):
    """Run a parametric study (a sweep file, docs/sweeps.md); return its labelled Dataset.

    With ``output`` the sweep is resumable (finished chunks are kept beside it until the file
    is complete, and a second call continues) and the Dataset is opened from it; without, it
    runs in a private folder and the Dataset is in memory.
    """
    from pframe import outputs
    from pframe.progress import bar
    from pframe.sweep import load_sweep, run_sweep

    call = "pframe.sweep"
    definition = path_argument(definition, "definition", call, "a sweep file's path")
    overwrite = flag_argument(overwrite, "overwrite", call)
    progress = flag_argument(progress, "progress", call, none=True)
    threads = count_argument(threads, "threads", call)
    chunk = count_argument(chunk, "chunk", call)
    if output is not None:
        output = path_argument(output, "output", call, "the sweep file's path")
    loaded = load_sweep(definition, chunk=chunk)
    folder = None
    if output is None:
        import tempfile

        folder = tempfile.TemporaryDirectory(prefix="pframe-sweep-")
        out = Path(folder.name) / "sweep.nc"
    else:
        out = outputs.check_output(output, inputs=sweep_inputs(loaded), overwrite=True,
                                   what="sweep file")
        from pframe.sweep.store import parts_folder

        if out.exists() and not parts_folder(out).exists() and not overwrite:
            raise InputError(f"{out}: the output file exists; pass overwrite=True to replace "
                             "it, or choose another name")
    progress_bar = bar(progress, "variants", Path(str(definition)).name)
    try:
        run = run_sweep(loaded, out, restart=overwrite, threads=threads, progress=progress_bar,
                        call=f"pframe.sweep({str(definition)!r}) (Python)")
        if run.failed:
            warnings.warn(f"{definition}: {len(run.failed)} of {run.count} variants failed "
                          "(complete = 0; status says why)", IncompleteRun, stacklevel=2)
        from pframe.verdict import AccuracyWarning

        if run.untrusted:
            warnings.warn(f"{definition}: {len(run.untrusted)} of {run.count} variants "
                          "completed but are not to be trusted (their energy balance; trusted "
                          "= 0)", AccuracyWarning, stacklevel=2)
        ds = open(out)
        for line in str(ds.attrs.get("warnings", "")).splitlines():
            if "the analysis stops at" in line:  # a record cut (docs/sweeps.md)
                warnings.warn(f"{definition}: {line}", AccuracyWarning, stacklevel=2)
        if folder is None:
            return ds
        with ds:
            return ds.load()
    finally:
        if progress_bar is not None:
            progress_bar.close()
        if folder is not None:
            folder.cleanup()


def sweep_inputs(definition) -> list:
    """The files a sweep reads (its file, its base scene, its records): never its output."""
    return [definition.source, definition.base_source or None,
            *(path for _, _, _, path in definition.records)]


# -- results --------------------------------------------------------------------------------

def open(path: str | Path):  # noqa: A001 - the public name, as xarray.open_dataset
    """A pframe result file (``pframe solve``, ``pframe sweep`` or ``pframe gap``) as an
    xarray Dataset, opened lazily; the names of nodes, storeys, contacts, ... are the
    coordinate values of their dimensions (:func:`indexed`), so ``ds.sel(node="A/3")`` and
    ``ds.peak_displacement.to_series()`` take and show names."""
    from pframe.record.check import check_file

    path = result_file(path, "pframe.open")
    check_file(path)  # a damaged file: what is wrong, not h5py's KeyError
    try:
        return _opened(path)
    except (OSError, ValueError) as exc:
        raise InputError(f"{path}: not a pframe result file (netCDF-4/HDF5): {exc}") from None


def result_file(path, call: str) -> Path:
    """A result file's path, checked before anything opens it: it exists and is a regular
    file (a folder is named as such, a FIFO would block the reader, a device be read
    without end)."""
    from pframe.outputs import not_regular

    path = path_argument(path, "path", call, "a result file's path")
    if not path.exists():
        raise InputError(f"{path}: no such result file")
    kind = not_regular(path)
    if kind is not None:
        raise InputError(f"{path}: is {kind}, not a result file; give the file pframe solve, "
                         "sweep, gap or risk wrote")
    return path


def _opened(source, load_now: bool = False):
    import xarray as xr

    ds = xr.open_dataset(source, engine="h5netcdf")
    if load_now:
        ds = ds.load()
        ds.close()
    return indexed(ds)


def indexed(ds):
    """``ds`` with its named positions as coordinates: each dimension with a label
    (``node_name`` along ``node``, ``story_name``, ``contact_name``, ``building_name``, ...)
    gets the names as its coordinate values, so ``to_series``, ``to_dataframe``, xarray's
    legends and ``.sel(node="A/3")`` show and take names; a swept record axis
    (``<axis>_file``) gets the records' names (file names without folder and suffix, the
    paths when two share a name). The labels stay, indexed (``.sel(node_name="A/3")``). The
    file keeps the labels only (CF has no string coordinate variables): writing the Dataset
    with :func:`pframe.record.netcdf.write_dataset` drops the name coordinates again."""
    import numpy as np

    for name, coord in list(ds.coords.items()):
        if coord.ndim != 1 or coord.dtype.kind not in "OU" or name in ds.indexes:
            continue
        dim = coord.dims[0]
        values = [str(v) for v in coord.values.tolist()]
        if len(set(values)) != coord.size:
            continue
        if name == f"{dim}_name" and dim not in ds.coords:
            ds = ds.assign_coords({dim: (dim, np.array(values, dtype=object),
                                         _label_attrs(coord))})
        elif name == f"{dim}_file" and dim not in ds.coords:
            stems = [Path(v).stem for v in values]
            names = stems if len(set(stems)) == len(stems) else values
            attrs = {"long_name": "ground-motion record (file name)"}
            ds = ds.assign_coords({dim: (dim, np.array(names, dtype=object), attrs)})
            continue
        if name.endswith("_name"):
            ds = ds.set_xindex(name)
    return ds


def _label_attrs(coord) -> dict:
    return {k: coord.attrs[k] for k in ("long_name",) if k in coord.attrs}


# -- building blocks of a scene (the names and fields of the YAML) ---------------------------

def _item_type(field: str):
    """The type of one item of the Scene's list field ``field`` (built-in laws)."""
    from typing import get_args

    from pframe.model.scene import scene_class

    return get_args(scene_class().model_fields[field].annotation)[0]


def _validated(annotation, what: str, args: tuple, fields: dict):
    """An object of ``annotation`` (a union of laws' models) built from keywords, as
    :class:`pframe.objects.Frozen` builds one: InputError for positional values, a problem
    pydantic finds, or a boolean given for a number."""
    from pydantic import TypeAdapter, ValidationError

    from pframe.objects import dotted, number_given_as_boolean, problems, value_at

    call = f"pframe.{what}({', '.join(f'{k}=...' for k in fields)})"
    if args:
        raise InputError(f"pframe.{what}: give its fields by name, as the YAML writes them, "
                         f"not {len(args)} value{'s' if len(args) > 1 else ''} by position")
    try:
        out = TypeAdapter(annotation).validate_python(fields)
    except ValidationError as exc:
        raise InputError(f"{call}: {problems(exc)}") from None
    path = number_given_as_boolean(fields, out)
    if path is not None:
        raise InputError(f"{call}: {dotted(path)}: expected a number, got the boolean "
                         f"{value_at(fields, path)}")
    return out


def Contact(*args, **fields):  # noqa: N802 - builds an object, as a class would
    """A contact element (YAML ``contacts:`` item): ``law`` (linear, kelvin, improved_kelvin,
    hertz, hertzdamp, jankowski), ``nodes`` [left, right], ``gap`` and the law's parameters."""
    return _validated(_item_type("contacts"), "Contact", args, fields)


def Story(*args, **fields):  # noqa: N802
    """A storey between two nodes (YAML ``stories:`` item): ``material`` (elastic, bilinear),
    ``nodes`` [lower or 'ground', upper] and the material's parameters."""
    return _validated(_item_type("stories"), "Story", args, fields)


def StoryProperties(*args, **fields):  # noqa: N802
    """The storeys of a building (YAML ``buildings[].story``): ``material`` and its parameters,
    each a number or one value per storey, bottom up."""
    annotation = _item_type("buildings").model_fields["story"].annotation
    return _validated(annotation, "StoryProperties", args, fields)


def __getattr__(name: str):
    if name == "Building":
        return _item_type("buildings")
    if name == "Scene":
        from pframe.model.scene import scene_class

        return scene_class()
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
