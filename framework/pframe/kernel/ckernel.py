"""The compiled kernel, loaded with ctypes, and the ctypes mirror of its structs.

``pip install`` compiles ``c/*.c`` into the extension ``pframe.kernel._ckernel``
(``setup.py``). The extension's Python module is empty: its file is loaded here with
:class:`ctypes.CDLL`, whose calls release the GIL, and the kernel is called with the data
pointers of the driver's numpy arrays (no numpy headers at build time). The structs are built
from :mod:`pframe.kernel.state`, the one list their C declarations (``c/state.h``) are
generated from; their sizes are checked against the compiled kernel's when it is loaded, and
the kernel's source hash against the C sources beside it, so that a kernel built from other
sources (an edit without a rebuild) is refused instead of giving silently wrong results.
"""

from __future__ import annotations

import ctypes
import hashlib
import importlib.util
from collections.abc import Iterator
from contextlib import contextmanager
from pathlib import Path

from pframe.errors import EnvironmentFailure
from pframe.kernel import state

C_FOLDER = Path(__file__).resolve().parent / "c"
#: the version of the driver-kernel interface (PFRAME_KERNEL_INTERFACE in c/kernel.h)
INTERFACE = 1

REBUILD = ("rebuild it with `pip install -e .` (or `python setup.py build_ext --inplace`) in "
           "the pframe checkout, or reinstall pframe")


def _field(ctype: str):
    if "[" in ctype:
        base, size = ctype.split("[", 1)
        count = state.C_COUNTS[size.rstrip("]")]
        return (ctypes.c_void_p if base.strip().endswith("*") else ctypes.c_int64) * count
    if ctype.endswith("*"):
        return ctypes.c_void_p
    return {"double": ctypes.c_double, "int64_t": ctypes.c_int64}[ctype]


def _structure(group: str, fields: tuple[str, ...]) -> type[ctypes.Structure]:
    types = state.C_TYPES[group]
    return type(group, (ctypes.Structure,),
                {"_fields_": [(name, _field(types.get(name, "double *"))) for name in fields]})


Model = _structure("Model", state.Model._fields + state.SIZES)
Settings = _structure("Settings", state.Settings._fields)
State = _structure("State", state.State._fields)
Recording = _structure("Recording", state.Recording._fields + state.RECORDING_SIZES)
Work = _structure("Work", state.Work._fields + state.WORK_PREPARED)
Saved = _structure("Saved", state.Saved._fields)
STRUCTS = (Model, Settings, State, Recording, Work, Saved)


def source_hash(folder: Path | None = None) -> str | None:
    """The hash setup.py compiles into the kernel: its C sources, line endings normalised
    (None when the sources are not installed beside the extension)."""
    return _hash_of(C_FOLDER if folder is None else folder)


def _hash_of(folder: Path) -> str | None:
    paths = sorted(p for p in folder.glob("*") if p.suffix in (".c", ".h"))
    if not paths:
        return None
    digest = hashlib.sha256()
    for path in paths:
        digest.update(path.name.encode())
        digest.update(path.read_bytes().replace(b"\r\n", b"\n"))
    return "h" + digest.hexdigest()[:16]


def _pointer(array) -> int:
    return array.ctypes.data


def _load():
    spec = importlib.util.find_spec("pframe.kernel._ckernel")
    if spec is None or not spec.origin:
        raise EnvironmentFailure(
            "pframe's compiled kernel (the extension pframe.kernel._ckernel) is not built: "
            f"{REBUILD}. Installing from a wheel needs no compiler; building from source "
            "needs a C compiler and the Python headers (docs/architecture.md)")
    library = _checked(ctypes.CDLL(spec.origin), spec.origin)
    built, here = library.pframe_source_hash().decode(), source_hash()
    if here is not None and built != here:
        raise EnvironmentFailure(f"pframe's compiled kernel ({spec.origin}) was built from other "
                                 f"C sources than those in {C_FOLDER} (a stale build): {REBUILD}")
    return library


def _checked(library: ctypes.CDLL, origin: str) -> ctypes.CDLL:
    """The library's functions typed, and its interface and struct sizes checked."""
    library.pframe_run.restype = ctypes.c_int64
    library.pframe_run.argtypes = [ctypes.c_void_p] * 6 + [ctypes.c_int64, ctypes.c_int64]
    library.pframe_interface.restype = ctypes.c_int64
    library.pframe_source_hash.restype = ctypes.c_char_p
    if library.pframe_interface() != INTERFACE:
        raise EnvironmentFailure(f"pframe's compiled kernel ({origin}) is of interface "
                                 f"{library.pframe_interface()}, this pframe needs {INTERFACE}: "
                                 f"{REBUILD}")
    sizes = (ctypes.c_int64 * len(STRUCTS))()
    library.pframe_layout(sizes)
    expected = [ctypes.sizeof(s) for s in STRUCTS]
    if list(sizes) != expected:
        raise EnvironmentFailure(f"pframe's compiled kernel ({origin}) has structs of "
                                 f"{list(sizes)} bytes, this pframe's state.py {expected}: "
                                 f"{REBUILD}")
    return library


_library = None


def library():
    """The loaded kernel (loaded and checked once per process)."""
    global _library
    if _library is None:
        _library = _load()
    return _library


@contextmanager
def baseline(path: Path) -> Iterator[None]:
    """Run this process's simulations with the kernel library at ``path``, built from other C
    sources of the same interface and structs (its source hash is not checked): a benchmark
    alternates it with the installed kernel (benchmarks/kernel_limit.py --baseline)."""
    global _library
    other = _checked(ctypes.CDLL(str(path)), str(path))
    kept, _library = library(), other
    try:
        yield
    finally:
        _library = kept


def run(model, settings, st, rec, work, saved, begin: int, end: int) -> int:
    """Call the kernel's pframe_run on ctypes structs (see :func:`structs`): advance every
    member from state ``begin`` to state ``end``. Releases the GIL."""
    return library().pframe_run(ctypes.addressof(model), ctypes.addressof(settings),
                                ctypes.addressof(st), ctypes.addressof(rec),
                                ctypes.addressof(work), ctypes.addressof(saved), begin, end)


def arrays(structure: type[ctypes.Structure], group, **values):
    """A struct of the named tuple ``group``'s arrays (their data pointers) and ``values``."""
    fields = {}
    for name, value in zip(group._fields, group):
        fields[name] = _pointer(value) if hasattr(value, "ctypes") else value
    fields.update(values)
    return structure(**fields)


def recording(rec) -> Recording:
    """The Recording struct of one call's buffers (a state.Recording of arrays)."""
    count = len(state.Recordable)
    pointers = ctypes.c_void_p * count
    sizes = ctypes.c_int64 * count
    enveloped = [q for q in range(count) if rec.enveloped[q]]
    return Recording(
        history=pointers(*[_pointer(h) for h in rec.history]),
        every=_pointer(rec.every), first_row=_pointer(rec.first_row),
        envelope=pointers(*[_pointer(e) for e in rec.envelope]),
        enveloped=_pointer(rec.enveloped),
        closing_dofs=_pointer(rec.closing_dofs), closing=_pointer(rec.closing),
        closings=rec.closing_dofs.shape[0],
        history_rows=sizes(*[h.shape[1] for h in rec.history]),
        history_width=sizes(*[h.shape[2] for h in rec.history]),
        envelope_width=sizes(*[e.shape[1] for e in rec.envelope]),
        envelope_count=len(enveloped), envelope_list=sizes(*enveloped))
