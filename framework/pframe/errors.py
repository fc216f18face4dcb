"""Errors pframe reports to its users (no traceback: the CLI prints the message and exits)."""


class PframeError(Exception):
    """A problem the user can act on; the message is complete in itself."""


class InputError(PframeError):
    """Bad input: a model file, a record file or a command-line argument (exit code 2)."""


class EnvironmentFailure(PframeError):
    """The machine, not the input: a disk that is full, a folder that cannot be written, too
    little memory, a signal that stopped the run (exit code 3). The message names the path and
    the cause; nothing is left half-written and an existing result is untouched."""


#: the options a message may tell the user to change, as the ``pframe`` command spells them
#: and as the Python API's keywords do; an output given otherwise than by ``-o`` has its own
#: (``pframe.outputs.check_output``'s ``named_by``)
_OPTIONS = {
    "output": ("-o", "output=..."),
    "summary": ("--summary", "output=..."),  # pframe solve --summary; pframe.summary
    "pelicun": ("--pelicun", "path=..."),  # pframe export --pelicun; export_pelicun
    "csv": ("--csv", "folder=..."),  # pframe export --csv; pframe.export_csv
    "overwrite": ("--overwrite", "overwrite=True"),
    "chunk": ("--chunk", "chunk="),
    "threads": ("--threads", "threads="),
    "scheduler": ("--scheduler", "scheduler="),
}
#: whether the ``pframe`` command is running (pframe.cli.main sets it while a command runs);
#: otherwise messages are for a Python caller
_command_line = [False]


def option(name: str) -> str:
    """How the user changes option ``name`` (a key of :data:`_OPTIONS`): ``--overwrite`` for
    the ``pframe`` command, ``overwrite=True`` from Python."""
    return _OPTIONS[name][0 if _command_line[0] else 1]


def given(name: str, value) -> str:
    """An option as the user gave it, for the start of a message: ``--scheduler localhost``
    on the command line, ``scheduler='localhost'`` from Python."""
    return f"{_OPTIONS[name][0]} {value}" if _command_line[0] else f"{name}={value!r}"


class command_line:  # noqa: N801 - a context manager used as a statement
    """``with command_line():`` messages name the ``pframe`` command's options."""

    def __enter__(self):
        self.before = _command_line[0]
        _command_line[0] = True

    def __exit__(self, *exc):
        _command_line[0] = self.before
