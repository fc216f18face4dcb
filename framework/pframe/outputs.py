"""The life of an output file: checked, written under a temporary name, then put in place.

Every file pframe writes (result files, sweep files and their chunks, figures, CSV tables)
goes through this module, so that

- an output that is one of the run's inputs, a folder, an empty name, anything but a regular
  file (``/dev/null``, a device, a FIFO: even with ``--overwrite``) or an existing file
  (without ``--overwrite``) is refused before anything runs (:func:`check_output`);
- the data is written to ``.NAME.PID-N.tmp`` in the output's folder, created exclusively
  (:func:`temporary`), and moved into place in one step when complete (:func:`commit`):
  without ``--overwrite`` by a hard link that fails if the name was taken meanwhile, so a
  second writer never silently replaces the first; with it, by an atomic rename, so the old
  file stays whole until the new one is;
- a temporary file is removed on any error, on Ctrl-C and on SIGTERM/SIGHUP
  (:func:`handle_signals`), and one left by a process that was killed (SIGKILL, power loss) is
  removed by the next run writing the same output, which says so;
- an operating-system failure (disk full, permission denied, read-only file system, a
  folder where a file should be) becomes :class:`~pframe.errors.EnvironmentFailure` (exit 3)
  naming the path and the cause, never a traceback.
"""

from __future__ import annotations

import atexit
import contextlib
import errno
import itertools
import os
import re
import signal
import stat
import sys
import threading
from pathlib import Path

from pframe.errors import EnvironmentFailure, InputError, option

_TEMP = re.compile(r"^\.(?P<name>.+)\.(?P<pid>\d+)(?:-\d+)?\.tmp$")
_counter = itertools.count()
_lock = threading.Lock()
#: temporary files this process is writing (removed at exit and on SIGTERM/SIGHUP)
_live: set[Path] = set()
#: outputs checked by check_output: resolved path -> may an existing file be replaced
_claims: dict[str, bool] = {}
#: outputs checked by check_output: resolved path -> the option that named it (a key of
#: pframe.errors' options), which later messages about it advise changing
_named_by: dict[str, str] = {}

_CAUSES = {
    errno.ENOSPC: "the disk is full (no space left on the device)",
    errno.EDQUOT: "the disk quota is exceeded",
    errno.EACCES: "permission denied",
    errno.EPERM: "operation not permitted",
    errno.EROFS: "the file system is read-only",
    errno.EISDIR: "it is a folder",
    errno.ENOTDIR: "a part of the path is not a folder",
    errno.ENOENT: "the folder does not exist",
    errno.EEXIST: "it exists",
    errno.EIO: "input/output error (the device failed)",
    errno.ENAMETOOLONG: "the name is too long",
}


class Terminated(KeyboardInterrupt):
    """SIGTERM or SIGHUP arrived: handled like Ctrl-C (temporary files removed); the command
    exits with 128 + the signal number."""

    def __init__(self, signum: int):
        super().__init__(f"signal {signum}")
        self.signum = signum


def cause(exc: BaseException) -> str:
    """The reason an operating-system call failed, in words (h5py hides errno in its text)."""
    number = getattr(exc, "errno", None)
    if number is None:
        found = re.search(r"errno\s*=\s*(\d+)", str(exc))
        number = int(found.group(1)) if found else None
    if number in _CAUSES:
        return _CAUSES[number]
    text = getattr(exc, "strerror", None) or str(exc) or type(exc).__name__
    return text[0].lower() + text[1:] if text else type(exc).__name__


def failure(path: Path | str, exc: BaseException, doing: str = "write") -> EnvironmentFailure:
    """:class:`EnvironmentFailure` for an ``OSError`` met while ``doing`` ``path``."""
    return EnvironmentFailure(
        f"{path}: cannot {doing} the file: {cause(exc)}. Nothing was written there, and a file "
        f"already there is unchanged; free space or choose a writable folder "
        f"({_option_of(path)}), then run again")


def _option_of(path) -> str:
    """The option that named output ``path`` (:func:`check_output`; by default ``-o``)."""
    try:
        key = str(Path(path).resolve())
    except (OSError, RuntimeError):  # a link loop: the path is refused for what it is
        key = ""
    return option(_named_by.get(key, "output"))


def _alive(pid: int) -> bool:
    if pid == os.getpid():
        return True
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return False
    except OSError:  # exists, owned by another user
        return True
    return True


def _same_file(a: Path, b: Path) -> bool:
    try:
        return os.path.samefile(a, b)
    except OSError:
        return a.resolve() == b.resolve()


def others_writing(path: Path) -> list[tuple[Path, int]]:
    """Temporary files of ``path`` from other processes: (file, process id). Those of
    processes that are gone are removed, with a note on standard error."""
    return _scan(Path(path).parent, Path(path).name)


def remove_stale(folder) -> list[tuple[Path, int]]:
    """Remove the temporary files in ``folder`` left by processes that are gone; return those
    of processes still running."""
    return _scan(Path(folder), None)


def _scan(folder: Path, name: str | None) -> list[tuple[Path, int]]:
    found = []
    try:
        entries = list(os.scandir(folder))
    except OSError:
        return []
    for entry in entries:
        match = _TEMP.match(entry.name)
        if not match or (name is not None and match.group("name") != name):
            continue
        pid = int(match.group("pid"))
        tmp = Path(entry.path)
        if pid == os.getpid():
            continue
        if _alive(pid):
            found.append((tmp, pid))
            continue
        with contextlib.suppress(OSError):
            tmp.unlink()
            print(f"pframe: removed {tmp}, left by a run that was stopped (process {pid})",
                  file=sys.stderr)
    return found


_KINDS = ((stat.S_ISCHR, "a character device (such as /dev/null)"),
          (stat.S_ISBLK, "a block device (a disk)"), (stat.S_ISFIFO, "a named pipe (FIFO)"),
          (stat.S_ISSOCK, "a socket"), (stat.S_ISDIR, "a folder"))


def not_regular(path) -> str | None:
    """What ``path`` is when it exists and is not a regular file (``"a named pipe (FIFO)"``,
    ...), else None. A symbolic link is followed."""
    try:
        mode = os.stat(path).st_mode
    except OSError:
        return None
    if stat.S_ISREG(mode):
        return None
    for test, kind in _KINDS:
        if test(mode):
            return kind
    return "not a regular file"


def _refuse_special(path: Path, what: str, named_by: str = "output") -> None:
    kind = not_regular(path)
    if kind is not None and kind != "a folder":
        raise InputError(f"{path}: is {kind}, not a regular file; pframe writes its {what} "
                         "only to regular files, and never replaces anything else (even with "
                         f"{option('overwrite')}); choose a file name with {option(named_by)}")


def check_output(path, *, inputs=(), overwrite: bool = False, what: str = "output file",
                 named_by: str = "output") -> Path:
    """Refuse an output path that cannot or must not be written, before any work is done.

    Raises :class:`InputError` (exit 2) for an empty name, a folder, a device, FIFO or
    socket (anything but a regular file, even with ``overwrite``), one of the run's
    ``inputs``, an existing file without ``overwrite`` or a missing folder, and
    :class:`EnvironmentFailure` (exit 3) for a folder that cannot be written or another
    pframe process writing the same output. Stale temporary files of killed runs are removed.
    Messages advise changing option ``named_by`` (a key of :data:`pframe.errors._OPTIONS`:
    ``-o``, ``--summary``, ``--pelicun``, ...), now and when the output is written.
    """
    given = option(named_by)
    if path is None or str(path).strip() == "":
        raise InputError(f"{given.removesuffix('...')}'': the {what} needs a name")
    path = Path(path)
    if path.is_dir():
        raise InputError(f"{path}: is a folder; give a file name for the {what} ({given})")
    _refuse_special(path, what, named_by)
    for source in inputs:
        if source is not None and Path(source).exists() and _same_file(path, Path(source)):
            raise InputError(f"{path}: is one of this run's inputs ({source}); writing the "
                             f"{what} there would destroy it; choose another name with {given}")
    if path.exists() and not overwrite:
        raise InputError(f"{path}: the {what} exists; pass {option('overwrite')} to replace "
                         f"it, or choose another name with {given}")
    folder = path.parent
    if not folder.exists():
        raise InputError(f"{path}: the folder {str(folder)!r} does not exist")
    if not folder.is_dir():
        raise InputError(f"{path}: {str(folder)!r} is not a folder")
    busy = others_writing(path)
    if busy:
        raise EnvironmentFailure(
            f"{path}: another pframe run (process {busy[0][1]}) is writing this output now; "
            f"wait for it to finish, or choose another name with {given}")
    discard(temporary(path, clean=False))  # the folder can be written (else: why not)
    _claims[str(path.resolve())] = overwrite
    _named_by[str(path.resolve())] = named_by
    return path


def temporary(path, clean: bool = True) -> Path:
    """Create ``.NAME.PID-N.tmp`` beside ``path``, exclusively, and return its name; it is
    removed at exit or on a signal unless :func:`commit` or :func:`discard` is called first.
    ``clean``: first remove what killed runs left for ``path``."""
    path = Path(path)
    if clean:
        others_writing(path)
    while True:
        tmp = path.with_name(f".{path.name}.{os.getpid()}-{next(_counter)}.tmp")
        try:
            os.close(os.open(tmp, os.O_WRONLY | os.O_CREAT | os.O_EXCL, 0o666))
            break
        except FileExistsError:
            continue
        except OSError as exc:
            raise failure(path, exc) from None
    with _lock:
        _live.add(tmp)
    return tmp


def discard(tmp) -> None:
    """Remove a temporary file (no error if it is gone)."""
    tmp = Path(tmp)
    try:
        with contextlib.suppress(FileNotFoundError):
            tmp.unlink()
    finally:  # forgotten only once gone (a stop arriving here still finds it at exit)
        with _lock:
            if not tmp.exists():
                _live.discard(tmp)


def commit(tmp, path, overwrite: bool | None = None) -> Path:
    """Put the complete temporary file in place of ``path`` in one step.

    ``overwrite`` (default: what :func:`check_output` was told for ``path``, else yes) says
    whether a file at ``path`` may be replaced; if not and one appeared while this run was
    writing, :class:`EnvironmentFailure` is raised and the temporary file removed.
    """
    tmp, path = Path(tmp), Path(path)
    if overwrite is None:
        overwrite = _claims.get(str(path.resolve()), True)
    named_by = _named_by.get(str(path.resolve()), "output")
    try:
        _refuse_special(path, "output", named_by)  # a device or FIFO put there meanwhile
        if overwrite:
            os.replace(tmp, path)
        else:
            try:
                os.link(tmp, path)
            except FileExistsError:
                raise EnvironmentFailure(
                    f"{path}: appeared while this run was writing (another program wrote it); "
                    f"this run's result was not put there; pass {option('overwrite')} to replace "
                    f"it, or choose another name with {option(named_by)}") from None
            except OSError as exc:
                if exc.errno not in (errno.EPERM, errno.ENOTSUP, errno.EOPNOTSUPP, errno.EXDEV,
                                     errno.EMLINK):
                    raise
                if path.exists():  # a file system without hard links: check, then rename
                    raise EnvironmentFailure(
                        f"{path}: appeared while this run was writing; this run's result was "
                        f"not put there; pass {option('overwrite')} to replace it") from None
                os.replace(tmp, path)
    except OSError as exc:
        discard(tmp)
        raise failure(path, exc) from None
    except BaseException:
        discard(tmp)
        raise
    discard(tmp)  # after a link, the temporary name; after a rename, nothing
    return path


@contextlib.contextmanager
def replacing(path, overwrite: bool | None = None, clean: bool = True):
    """``with replacing(path) as tmp:`` write ``tmp``; it is committed to ``path`` when the
    block ends normally, removed otherwise. OSError becomes :class:`EnvironmentFailure`."""
    tmp = temporary(path, clean)
    try:
        yield tmp
    except OSError as exc:
        discard(tmp)
        raise failure(path, exc) from None
    except BaseException:
        discard(tmp)
        raise
    commit(tmp, path, overwrite)


def check_folder(path, what: str, inputs=(), named_by: str = "output") -> Path:
    """An output folder (its files written into it), checked before any work: a name, not
    an existing file, device or FIFO, not one of the run's ``inputs``, in a folder that
    exists; it may exist already. Raises :class:`InputError`; ``named_by`` as
    :func:`check_output`'s."""
    if path is None or str(path).strip() == "":
        raise InputError(f"{option(named_by).removesuffix('...')}'': the {what} needs a name")
    path = Path(path)
    for source in inputs:
        if source is not None and Path(source).exists() and _same_file(path, Path(source)):
            raise InputError(f"{path}: is one of this run's inputs ({source}); choose another "
                             f"folder for the {what}")
    kind = not_regular(path)
    if path.exists() and kind != "a folder":
        raise InputError(f"{path}: is {kind or 'a file'}, not a folder; give a folder for the "
                         f"{what}")
    parent = path.parent
    if not path.exists() and not parent.is_dir():
        raise InputError(f"{path}: the folder {str(parent)!r} "
                         + ("is not a folder" if parent.exists() else "does not exist"))
    return path


def make_folder(path) -> Path:
    """Create an output folder (and its parents); OSError becomes EnvironmentFailure."""
    path = Path(path)
    if path.exists() and not path.is_dir():
        raise InputError(f"{path}: exists and is not a folder")
    try:
        path.mkdir(parents=True, exist_ok=True)
    except OSError as exc:
        raise failure(path, exc, "create") from None
    return path


def _remove_live() -> None:
    with _lock:
        live = list(_live)
        _live.clear()
    for tmp in live:
        with contextlib.suppress(OSError):
            tmp.unlink()


#: the signal that asked this process to stop, until it has stopped
_pending: list[int] = []


def _stop(signum: int):
    return KeyboardInterrupt() if signum == signal.SIGINT else Terminated(signum)


def _on_signal(signum, frame):
    _pending.append(signum)
    raise _stop(signum)


def check_stop() -> None:
    """Raise the stop a signal asked for, if it has not been raised where it arrived: Python
    raises it in whatever code runs at that moment, and a destructor or a weak-reference
    callback swallows it. Called between the kernel's calls."""
    if _pending:
        raise _stop(_pending[-1])


def handle_signals() -> dict:
    """SIGINT (Ctrl-C), SIGTERM and SIGHUP stop the process (the ``finally`` blocks remove the
    temporary files), and the stop is never lost; called by the ``pframe`` command, not on
    import (a library leaves a program's signals alone). Returns the handlers replaced."""
    before = {}
    if threading.current_thread() is not threading.main_thread():
        return before
    _pending.clear()
    for name in ("SIGINT", "SIGTERM", "SIGHUP"):
        number = getattr(signal, name, None)
        if number is None:
            continue
        current = signal.getsignal(number)
        if current in (signal.SIG_DFL, signal.default_int_handler, None):
            before[number] = current
            signal.signal(number, _on_signal)
    return before


def restore_signals(before: dict) -> None:
    if threading.current_thread() is threading.main_thread():
        for number, handler in before.items():
            signal.signal(number, handler)
    _pending.clear()


atexit.register(_remove_live)
