"""Errors pframe reports to its users (no traceback: the CLI prints the message and exits)."""


class PframeError(Exception):
    """A problem the user can act on; the message is complete in itself."""


class InputError(PframeError):
    """Bad input: a model file, a record file or a command-line argument (exit code 2)."""


class EnvironmentFailure(PframeError):
    """The machine, not the input: a disk that is full, a folder that cannot be written, too
    little memory, a signal that stopped the run (exit code 3). The message names the path and
    the cause; nothing is left half-written and an existing result is untouched."""
