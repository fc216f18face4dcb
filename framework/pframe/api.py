"""pframe from Python: scenes as objects, results as xarray Datasets (docs/python.md).

The command line is a shell over the same functions: ``pframe.solve(scene)`` gives the
Dataset that ``pframe solve`` writes (the file is laid out by one writer, in memory here), and
``pframe.open`` reads any pframe result file back as such a Dataset.
"""

from __future__ import annotations

import os
import shutil
import tempfile
import warnings
import weakref
from pathlib import Path

from pframe.errors import InputError

#: suffixes of result files (``load`` of one rebuilds the scene it holds)
RESULT_SUFFIXES = (".nc", ".h5", ".hdf5", ".nc4")


class IncompleteRun(UserWarning):
    """A run stopped early: the Dataset holds the states computed (``complete = 0``, its
    ``status`` attribute says why, when and where)."""


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


#: id(scene object) -> (weak reference to it, where it was read from): the file a loaded
#: scene came from (record paths, the result's input_yaml), kept off the scene's data
_ORIGIN: dict[int, tuple] = {}


def _scene_of(loaded):
    import weakref

    from pframe.model.scene import attach_facts

    scene = loaded.scene
    key = id(scene)
    _ORIGIN[key] = (weakref.ref(scene, lambda _, key=key, origin=_ORIGIN: origin.pop(key, None)),
                    loaded)
    attach_facts(scene, lambda: _periods(loaded.expanded))
    return scene


def _periods(expanded) -> list[str]:
    """The periods of a loaded scene's buildings (its repr ends with them)."""
    from pframe.assemble.modes import period_lines

    return period_lines(expanded)


def _origin(scene):
    entry = _ORIGIN.get(id(scene))
    return entry[1] if entry is not None and entry[0]() is scene else None


def to_opensees(scene, *, base_dir: str | Path | None = None) -> str:
    """A standalone OpenSeesPy script of a scene (anything :func:`load` takes), planar or in
    plan: linear contacts, elastic or bilinear storeys, starting at rest; it runs without
    pframe, to cross-check it. Laws OpenSees cannot model are refused with every reason at
    once."""
    from pframe.assemble import assemble
    from pframe.assemble.plan import peer_scene
    from pframe.peers.opensees import script_text

    expanded = _loaded(scene, base_dir).expanded
    return script_text(peer_scene(assemble(expanded), centres=expanded.node_centre))


def loaded_scene(source, base_dir=None):
    """The validated scene with where it came from (:class:`pframe.reader.LoadedScene`)
    of anything :func:`load` takes."""
    return _loaded(source, base_dir)


def _loaded(source, base_dir=None):
    """The :class:`pframe.reader.LoadedScene` of any ``source`` that :func:`load` takes."""
    from pframe.reader import LoadedScene, load_scene, parse_scene

    if isinstance(source, LoadedScene):
        return source
    if isinstance(source, (str, os.PathLike)):
        path = Path(source)
        if path.suffix.lower() in RESULT_SUFFIXES:
            return _from_result(path)
        return load_scene(path)
    if isinstance(source, dict):
        import yaml

        text = yaml.safe_dump(source, sort_keys=False, allow_unicode=True)
        return parse_scene(text, "<dict>", Path(base_dir or "."))
    loaded = _origin(source)
    if loaded is not None:
        return loaded
    if hasattr(source, "to_yaml"):
        # a copy of a loaded scene (model_copy) finds its record where the original did
        excitation = getattr(source, "excitation", None)
        base = base_dir or getattr(excitation, "_folder", None) or "."
        return parse_scene(source.to_yaml(), "<python>", Path(base))
    if isinstance(source, (bytes, bytearray)):
        raise InputError("pframe.load: give a path, a dict or a scene object, not bytes")
    raise InputError(f"pframe.load: cannot read a scene from a {type(source).__name__}; give "
                     "a scene file's path, a dict with the fields of the YAML, or a "
                     "pframe.Scene")


def _from_result(path: Path):
    """The scene a result file ran: its ``input_yaml``, and its record restored from
    ``record_text`` into a private folder laid out so that the scene's relative record path
    finds it."""
    import h5py

    try:
        with h5py.File(path, "r") as f:
            attrs = {k: f.attrs[k] for k in ("input_yaml", "record_file", "record_text",
                                             "sweep_yaml") if k in f.attrs}
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
             if k in ("input_yaml", "record_file", "record_text", "sweep_yaml")}
    if "sweep_yaml" in attrs:
        raise InputError(f"{path}: a sweep's result file holds many scenes; load its base "
                         "scene from the sweep file, or a variant with pframe sweep --variant")
    text = attrs.get("input_yaml")
    if not text:
        raise InputError(f"{path}: the file holds no scene (no input_yaml attribute)")
    if "record_text" in attrs:
        relative = Path(attrs["record_file"])
        if relative.is_absolute():
            raise InputError(f"{path}: the scene names its record by the absolute path "
                             f"{relative}; run it from its scene file")
        depth = sum(1 for part in relative.parts if part == "..")
        root = Path(tempfile.mkdtemp(prefix="pframe-record-"))
        try:
            base = root.joinpath(*(["d"] * depth))
            base.mkdir(parents=True, exist_ok=True)  # base/../x needs base itself
            target = (base / relative).resolve()
            if root.resolve() not in target.parents:
                raise InputError(f"{path}: the record name {str(relative)!r} leaves its folder")
            target.parent.mkdir(parents=True, exist_ok=True)
            target.write_text(attrs["record_text"], encoding="utf-8")
            loaded = parse_scene(text, f"{path} (input_yaml)", base)
        except BaseException:
            shutil.rmtree(root, ignore_errors=True)
            raise
        # the folder lives as long as the scene (a variant re-reads the record), then goes
        weakref.finalize(loaded, shutil.rmtree, str(root), ignore_errors=True)
        return loaded
    return parse_scene(text, f"{path} (input_yaml)", base)


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

    loaded = _loaded(scene)
    if output is not None:
        output = check_output(output, overwrite, loaded)
    _check_resources(loaded, output)
    plan = assemble(loaded.expanded)
    from pframe.verdict import AccuracyWarning, of_result

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
    for text in of_result(result).warnings:
        warnings.warn(f"{loaded.source}: {text}", AccuracyWarning, stacklevel=2)
    if not result.completed():
        warnings.warn(f"{loaded.source}: the run stopped early: {result.describe_failure()}; "
                      f"the Dataset holds the {result.states_done() - 1} steps computed",
                      IncompleteRun, stacklevel=2)
    if output is None:
        return indexed(target.dataset())
    return open(output)


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
    """The files a loaded scene reads (the scene, its record): never an output."""
    inputs = []
    if loaded is not None:
        inputs.append(Path(str(loaded.source)))
        excitation = getattr(loaded.scene, "excitation", None)
        if getattr(excitation, "kind", None) == "record":
            inputs.append(Path(loaded.base_dir) / excitation.file)
    return inputs


def sweep(definition, *, output: str | Path | None = None, overwrite: bool = False,
          threads: int | None = None, chunk: int | None = None, progress: bool | None = None):
    """Run a parametric study (a sweep file, docs/sweeps.md); return its labelled Dataset.

    With ``output`` the sweep is resumable (finished chunks are kept beside it until the file
    is complete, and a second call continues) and the Dataset is opened from it; without, it
    runs in a private folder and the Dataset is in memory.
    """
    from pframe.progress import bar
    from pframe.sweep import load_sweep, run_sweep

    loaded = load_sweep(definition, chunk=chunk)
    if threads is not None and threads < 1:
        raise InputError(f"threads={threads}: give at least 1")
    folder = None
    if output is None:
        folder = tempfile.TemporaryDirectory(prefix="pframe-sweep-")
        out = Path(folder.name) / "sweep.nc"
    else:
        out = Path(output)
        if not out.parent.exists():
            raise InputError(f"{out}: the folder {str(out.parent)!r} does not exist")
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


# -- results --------------------------------------------------------------------------------

def open(path: str | Path):  # noqa: A001 - the public name, as xarray.open_dataset
    """A pframe result file (``pframe solve``, ``pframe sweep`` or ``pframe gap``) as an
    xarray Dataset, opened lazily; the names of nodes, storeys, contacts, ... are the
    coordinate values of their dimensions (:func:`indexed`), so ``ds.sel(node="A/3")`` and
    ``ds.peak_displacement.to_series()`` take and show names."""
    from pframe.record.check import check_file

    path = Path(path)
    if not path.exists():
        raise InputError(f"{path}: no such result file")
    check_file(path)  # a damaged file: what is wrong, not h5py's KeyError
    try:
        return _opened(path)
    except (OSError, ValueError) as exc:
        raise InputError(f"{path}: not a pframe result file (netCDF-4/HDF5): {exc}") from None


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


def _validated(field: str, what: str, fields: dict):
    from pydantic import TypeAdapter, ValidationError

    try:
        return TypeAdapter(_item_type(field)).validate_python(fields)
    except ValidationError as exc:
        problems = "; ".join(f"{'.'.join(map(str, e['loc'])) or what}: {e['msg']}"
                             for e in exc.errors(include_url=False)[:3])
        raise InputError(f"pframe.{what}({', '.join(f'{k}=...' for k in fields)}): "
                         f"{problems}") from None


def Contact(**fields):  # noqa: N802 - builds an object, as a class would
    """A contact element (YAML ``contacts:`` item): ``law`` (linear, kelvin, improved_kelvin,
    hertz, hertzdamp, jankowski), ``nodes`` [left, right], ``gap`` and the law's parameters."""
    return _validated("contacts", "Contact", fields)


def Story(**fields):  # noqa: N802
    """A storey between two nodes (YAML ``stories:`` item): ``material`` (elastic, bilinear),
    ``nodes`` [lower or 'ground', upper] and the material's parameters."""
    return _validated("stories", "Story", fields)


def StoryProperties(**fields):  # noqa: N802
    """The storeys of a building (YAML ``buildings[].story``): ``material`` and its parameters,
    each a number or one value per storey, bottom up."""
    from pydantic import TypeAdapter, ValidationError

    annotation = _item_type("buildings").model_fields["story"].annotation
    try:
        return TypeAdapter(annotation).validate_python(fields)
    except ValidationError as exc:
        problems = "; ".join(f"{'.'.join(map(str, e['loc']))}: {e['msg']}"
                             for e in exc.errors(include_url=False)[:3])
        raise InputError(f"pframe.StoryProperties: {problems}") from None


def __getattr__(name: str):
    if name == "Building":
        return _item_type("buildings")
    if name == "Scene":
        from pframe.model.scene import scene_class

        return scene_class()
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
