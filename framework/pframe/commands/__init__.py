"""The ``pframe`` sub-commands, one module each.

Each module defines ``register(subparsers)``, which adds its parser and sets ``run`` to a
function of the parsed arguments returning the exit code. Modules import only argparse and
the standard library at the top; the library is imported inside ``run``, so ``pframe --help``
stays fast and a command never pays for another's imports.
"""

#: sub-command modules, in the order ``pframe --help`` lists them
COMMANDS = ("solve", "validate", "schema", "pi", "expand", "scale", "plot", "accuracy", "sweep",
            "gap", "compile", "opensees")


def write_text_output(text: str, output, overwrite: bool) -> None:
    """Write generated YAML to ``output`` (refusing to replace a file without ``overwrite``)
    or, without one, to standard output."""
    import sys
    from pathlib import Path

    from pframe.errors import InputError

    if output:
        out = Path(output)
        if out.exists() and not overwrite:
            raise InputError(f"{out}: the output file exists; pass --overwrite to replace it")
        out.write_text(text, encoding="utf-8")
        print(f"wrote {out}")
    else:
        sys.stdout.write(text)
