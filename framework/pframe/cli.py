"""The ``pframe`` command: thin argument parsing around the library.

Exit codes: 0 success, 1 a run that stopped early (results written, marked incomplete),
2 bad input (model, record file, arguments or output path), with a one-paragraph message and
no traceback. Sub-commands live in :mod:`pframe.commands`, one module each.
"""

from __future__ import annotations

import argparse
import importlib
import sys

from pframe.commands import COMMANDS
from pframe.errors import InputError, PframeError


def parser() -> argparse.ArgumentParser:
    from pframe import __version__

    top = argparse.ArgumentParser(
        prog="pframe", description="Earthquake-induced pounding of adjacent inelastic buildings.")
    top.add_argument("--version", action="version", version=f"pframe {__version__}")
    sub = top.add_subparsers(dest="command", required=True)
    for name in COMMANDS:
        importlib.import_module(f"pframe.commands.{name}").register(sub)
    return top


def main(argv: list[str] | None = None) -> int:
    import shlex

    argv = sys.argv[1:] if argv is None else list(argv)
    args = parser().parse_args(argv)
    args.command_line = shlex.join(["pframe", *argv])  # the files' history attribute
    try:
        return args.run(args)
    except InputError as exc:
        print(f"pframe: {exc}", file=sys.stderr)
        return 2
    except PframeError as exc:
        print(f"pframe: {exc}", file=sys.stderr)
        return 1
    except KeyboardInterrupt:
        print("pframe: interrupted; no output written", file=sys.stderr)
        return 130
    except BrokenPipeError:  # output piped into a reader that stopped (pframe pi | head)
        import os

        os.dup2(os.open(os.devnull, os.O_WRONLY), sys.stdout.fileno())
        return 0


#: commands short enough to run without the cyclic garbage collector: it costs start-up time
#: while imports build long-lived objects (numba's and pydantic's registries), and a full
#: pass at exit that only finds what the operating system reclaims anyway
_SHORT = {"solve", "validate", "compile", "schema", "pi", "expand", "scale"}


def console_main() -> int:
    """The installed ``pframe`` command: :func:`main`, with the garbage collector off for short
    commands and the objects alive at the end frozen, so that leaving the interpreter does not
    examine them (about 0.2 s of a warm ``pframe solve``)."""
    import gc

    if next((a for a in sys.argv[1:] if not a.startswith("-")), None) in _SHORT:
        gc.disable()
    try:
        return main()
    finally:
        gc.freeze()


if __name__ == "__main__":
    sys.exit(console_main())
