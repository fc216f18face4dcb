"""Where the compiled kernel lives on disk, and the decorators every kernel function uses.

numba caches a compiled function beside a stamp of its own source file only; a change in a
function it calls does not invalidate it. The cache therefore lives in a folder named after
pframe's version, numba's and Python's, and a hash of the source of every module compiled into
the kernel (the kernel package but for its Python driver, and the law modules): an upgrade or
an edit gets a fresh folder, and nothing stale is ever loaded. The folder is
``$PFRAME_CACHE_DIR/kernels/<key>`` (default ``~/.cache/pframe``); pointing
``PFRAME_CACHE_DIR`` at an empty folder gives the cold start a user sees right after
installing.
"""

from __future__ import annotations

import contextlib
import hashlib
import os
import sys
import tempfile
from pathlib import Path

import numba

#: what every kernel function is compiled with; cached on disk, and free of the GIL so that
#: members of a batch run in threads
jit = numba.njit(cache=True, nogil=True, _nrt=False)
#: a kernel function called only from other kernel functions (no Python entry)
compiled = numba.njit(cache=True, nogil=True, _nrt=False, no_cpython_wrapper=True)
#: small helpers, inlined into their callers before compilation (numba IR inlining): no call,
#: and no reference counting of the arrays they receive
inline = numba.njit(inline="always")

_PACKAGE = Path(__file__).resolve().parents[1]  # framework/pframe
#: the kernel's Python driver, which is not compiled: editing it needs no new kernel
_DRIVER = ("__init__.py", "run.py", "build.py", "plugins.py")
#: written into a cache folder once its kernel has been compiled and saved
MARKER = "compiled"


def skip_blas_probe() -> None:
    """Import numba's array functions without their probe of scipy's BLAS.

    Loading a cached kernel makes numba import ``numba.np.arraymath``, which imports
    ``scipy.linalg`` (about 0.15 s, and a second OpenBLAS) only to learn whether
    ``np.convolve`` and ``np.correlate`` may call BLAS. The kernel uses neither. A ``None`` entry
    in ``sys.modules`` makes that one import fail as if scipy had no BLAS module, which numba
    handles; it is removed at once, so ``scipy.linalg`` imports normally afterwards. (In this
    process numba's ``np.convolve`` then runs its own loop: the same sums.)
    """
    name = "scipy.linalg.cython_blas"
    if "numba.np.arraymath" in sys.modules or name in sys.modules:
        return
    sys.modules[name] = None
    try:
        import numba.np.arraymath  # noqa: F401
    finally:
        if sys.modules.get(name, 0) is None:
            del sys.modules[name]


def source_key(extra: tuple[str, ...] = ()) -> str:
    """A name for the cache folder: versions and a hash of the compiled sources."""
    from pframe import __version__

    digest = hashlib.sha256()
    compiled = [p for p in (_PACKAGE / "kernel").glob("*.py") if p.name not in _DRIVER]
    for path in sorted(compiled + list((_PACKAGE / "laws").rglob("*.py"))):
        digest.update(path.relative_to(_PACKAGE).as_posix().encode())
        digest.update(path.read_bytes())
    for part in extra:
        digest.update(part.encode())
    python = f"py{sys.version_info[0]}{sys.version_info[1]}"
    return f"{__version__}-numba{numba.__version__}-{python}-{digest.hexdigest()[:16]}"


def root() -> Path:
    return Path(os.environ.get("PFRAME_CACHE_DIR") or Path.home() / ".cache" / "pframe")


def folder(key: str) -> Path:
    """The cache folder for ``key``, created; a temporary one if it cannot be written (the
    kernel is then compiled again by the next process, which is slow but never wrong)."""
    path = root() / "kernels" / key
    try:
        path.mkdir(parents=True, exist_ok=True)
        with tempfile.TemporaryFile(dir=path):
            pass
        return path
    except OSError:
        fallback = Path(tempfile.gettempdir()) / f"pframe-{os.getuid() if hasattr(os, 'getuid') else 0}" / key
        fallback.mkdir(parents=True, exist_ok=True)
        return fallback


@contextlib.contextmanager
def caching_into(path: Path):
    """Functions decorated with :data:`jit` inside this block cache into ``path``.

    numba picks a function's cache folder when it is decorated, from ``numba.config.CACHE_DIR``;
    the setting is restored afterwards, so other numba code in the process is not affected.
    """
    before = numba.config.CACHE_DIR
    numba.config.CACHE_DIR = str(path)
    try:
        yield
    finally:
        numba.config.CACHE_DIR = before


def is_compiled(path: Path) -> bool:
    return (path / MARKER).exists()


def mark_compiled(path: Path) -> None:
    with contextlib.suppress(OSError):
        (path / MARKER).write_text("the kernel in this folder is compiled\n", encoding="utf-8")
