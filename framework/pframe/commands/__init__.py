"""The ``pframe`` sub-commands, one module each.

Each module defines ``register(subparsers)``, which adds its parser and sets ``run`` to a
function of the parsed arguments returning the exit code. Modules import only argparse and
the standard library at the top; the library is imported inside ``run``, so ``pframe --help``
stays fast and a command never pays for another's imports.
"""

#: sub-command modules, in the order ``pframe --help`` lists them
COMMANDS = ("solve", "validate", "schema", "pi", "expand", "scale", "plot", "accuracy", "sweep")
