"""The ``pframe`` command: thin argument parsing around the library.

Exit codes: 0 success, 1 a run that stopped early (results written, marked incomplete),
2 bad input (model, record file, arguments or output path, a run too large for the machine),
3 the environment failed (disk full, a folder that cannot be written, out of memory), 130 Ctrl-C
and 128 + N signal N (SIGTERM, SIGHUP): always a one-paragraph message, no traceback, and
no temporary file left. Sub-commands live in :mod:`pframe.commands`, one module each.
"""

from __future__ import annotations

import argparse
import importlib
import sys

from pframe.commands import COMMANDS
from pframe.errors import EnvironmentFailure, InputError, PframeError, command_line


def parser(command: str | None = None) -> argparse.ArgumentParser:
    """The ``pframe`` parser; with ``command`` (one of :data:`COMMANDS`), holding that
    sub-command only: building every sub-command's parser cost 14 ms, most of a quick
    ``validate``, and no other is needed to read its arguments. Without one (``pframe``,
    ``pframe --help``, an unknown command), every sub-command, for the listing."""
    from pframe import __version__

    top = argparse.ArgumentParser(
        prog="pframe", description="Earthquake-induced pounding of adjacent inelastic buildings.")
    top.add_argument("--version", action="version", version=f"pframe {__version__}")
    sub = top.add_subparsers(dest="command", required=True)
    for name in (command,) if command in COMMANDS else COMMANDS:
        importlib.import_module(f"pframe.commands.{name}").register(sub)
    return top


def main(argv: list[str] | None = None) -> int:
    import shlex

    from pframe import outputs

    argv = sys.argv[1:] if argv is None else list(argv)
    _said.clear()  # a new command (main may be called again in one process)
    # the sub-command comes first (an option before it is the top level's: all are listed)
    args = parser(argv[0] if argv else None).parse_args(argv)
    args.command_line = shlex.join(["pframe", *argv])  # the files' history attribute
    before = outputs.handle_signals()
    hook, excepthook = sys.unraisablehook, sys.excepthook
    sys.unraisablehook = _quiet_h5py(hook)
    sys.excepthook = _quiet_h5py_print(excepthook)
    try:
        with command_line():
            return args.run(args)
    except InputError as exc:
        print(f"pframe: {exc}", file=sys.stderr)
        return 2
    except EnvironmentFailure as exc:
        print(f"pframe: {exc}", file=sys.stderr)
        return 3
    except PframeError as exc:
        print(f"pframe: {exc}", file=sys.stderr)
        return 1
    except outputs.Terminated as exc:
        print(f"pframe: stopped by signal {exc.signum}; no output written", file=sys.stderr)
        return 128 + exc.signum
    except KeyboardInterrupt:
        _interrupted()
        return 130
    except MemoryError:
        print("pframe: the machine ran out of memory; nothing was written. Check the step "
              "count first (analysis.duration / analysis.dt, both in seconds), then the size "
              "of the scene, then what the run records (every k-th step, envelopes only)",
              file=sys.stderr)
        return 3
    except OSError as exc:  # an operating-system failure no command turned into a message
        if isinstance(exc, BrokenPipeError):
            return _broken_pipe()
        where = exc.filename or "pframe"
        print(f"pframe: {where}: {outputs.cause(exc)}; nothing was written", file=sys.stderr)
        return 3
    finally:
        sys.unraisablehook, sys.excepthook = hook, excepthook
        outputs.restore_signals(before)


_said: list[str] = []  # the stop message, once printed


def _interrupted() -> None:
    if not _said:
        _said.append("interrupted")
        print("pframe: interrupted; no output written", file=sys.stderr)


def _quiet_h5py(hook):
    """h5py reports a file it cannot close (disk full) again while collecting its objects,
    and a signal that arrives in a destructor is reported there: the command says either
    once, itself."""

    def quiet(unraisable):
        if isinstance(unraisable.exc_value, KeyboardInterrupt):
            return  # a stop that arrived in a destructor: pframe raises it again at once
        if isinstance(unraisable.exc_value, (OSError, RuntimeError)) and "h5py" in repr(
                getattr(unraisable, "object", "")) + str(getattr(unraisable, "err_msg", "")):
            return
        hook(unraisable)

    return quiet


def _quiet_h5py_print(hook):
    """The same reports, printed through ``sys.excepthook`` by h5py's compiled code."""

    def quiet(kind, value, traceback):
        if isinstance(value, (OSError, RuntimeError)) and "errno = " in str(value):
            return
        hook(kind, value, traceback)

    return quiet


def _broken_pipe() -> int:
    """Output piped into a reader that stopped (pframe pi | head): a quiet success."""
    import os

    os.dup2(os.open(os.devnull, os.O_WRONLY), sys.stdout.fileno())
    return 0


#: commands short enough to run without the cyclic garbage collector: it costs start-up time
#: while imports build long-lived objects (numba's and pydantic's registries), and a full
#: pass at exit that only finds what the operating system reclaims anyway
_SHORT = {"solve", "validate", "compile", "schema", "pi", "expand", "scale"}


#: the environment of a short command where the user has not set it. numpy's OpenBLAS starts
#: a thread per core when it is imported, and an idle thread spins 2^28 cycles (about 0.1 s)
#: before it sleeps: a third of numpy's import, about 30 ms of CPU a short command spends on
#: nothing. 2^4 cycles, OpenBLAS's least, puts them to sleep at once. Their number is kept:
#: it decides how a threaded routine splits its sums (a dense eigen-solve of 300 DOFs differs
#: in the last bits between one thread and two), so results stay those of numpy's defaults.
#: Pydantic looks for plug-ins (packages that observe every validation, as a tracer does)
#: by reading the entry points of every installed package when it builds its first
#: validator: about 5 ms with a hundred packages, for observers of the scene's validation
#: alone. ``PYDANTIC_DISABLE_PLUGINS`` (pydantic's documented switch) skips the scan; a value
#: the user set, even empty (every plug-in), is kept. With it ``__all__``, the loader's module
#: itself is left out (:func:`_without_plugin_loader`)
_SHORT_ENVIRONMENT = {"OPENBLAS_THREAD_TIMEOUT": "4", "PYDANTIC_DISABLE_PLUGINS": "__all__"}


def console_main() -> int:
    """The installed ``pframe`` command: :func:`main`, with the garbage collector off for short
    commands and the objects alive at the end frozen, so that leaving the interpreter does not
    examine them (about 0.2 s of a warm ``pframe solve``), and OpenBLAS's idle threads asleep
    at once and pydantic's scan for plug-ins skipped (:data:`_SHORT_ENVIRONMENT`, set before
    numpy and pydantic are imported)."""
    import gc
    import os

    if next((a for a in sys.argv[1:] if not a.startswith("-")), None) in _SHORT:
        gc.disable()
        for name, value in _SHORT_ENVIRONMENT.items():
            os.environ.setdefault(name, value)
        if os.environ["PYDANTIC_DISABLE_PLUGINS"] == "__all__":
            _without_plugin_loader()
    try:
        try:
            code = main()
        finally:
            _leaving()
            gc.freeze()
    except KeyboardInterrupt:
        # a Ctrl-C that arrived as main() put the signal handlers back: exit 130 as for any
        # Ctrl-C, not a traceback; the command has already said how it ended (its files are
        # complete or removed), or this says so
        if not _said:
            print("pframe: interrupted as the command ended; what it printed above stands",
                  file=sys.stderr)
        code = 130
    if code == 3:
        # after a failed write (disk full), a library may hold files it cannot close; leave
        # without the interpreter's clean-up, which would try again (the message is out)
        sys.stdout.flush()
        sys.stderr.flush()
        import os

        os._exit(code)
    return code


def _without_plugin_loader() -> None:
    """Pydantic's plug-in loader (``pydantic.plugin._loader``, imported when pydantic builds
    its first validator) imports importlib.metadata, and with it the email package that
    parses metadata (about 15 ms of a short command), for ``get_plugins`` to return no
    plug-in when ``PYDANTIC_DISABLE_PLUGINS`` is ``__all__``. In its place: a module whose
    ``get_plugins`` returns that same nothing, and which loads the real module for any other
    name pydantic may ask it for."""
    import types

    name = "pydantic.plugin._loader"
    if name in sys.modules:
        return
    stand_in = types.ModuleType(name)
    stand_in.get_plugins = tuple  # () -> (): no plug-in, as pydantic's own under "__all__"

    def real(attribute: str):
        import importlib

        if attribute.startswith("__"):  # what the import system asks a module (__path__, ...)
            raise AttributeError(attribute)
        if sys.modules.get(name) is stand_in:
            del sys.modules[name]
        return getattr(importlib.import_module(name), attribute)

    stand_in.__getattr__ = real
    sys.modules[name] = stand_in


def _leaving() -> None:
    """From here on a Ctrl-C could only interrupt the interpreter's clean-up (the command has
    said how it ended, and its files are complete or removed): ignore it."""
    import signal
    import threading

    if threading.current_thread() is threading.main_thread():
        signal.signal(signal.SIGINT, signal.SIG_IGN)


if __name__ == "__main__":
    sys.exit(console_main())
