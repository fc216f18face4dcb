"""Errors pframe reports to its users (no traceback: the CLI prints the message and exits)."""


class PframeError(Exception):
    """A problem the user can act on; the message is complete in itself."""


class InputError(PframeError):
    """Bad input: a model file, a record file or a command-line argument (exit code 2)."""
