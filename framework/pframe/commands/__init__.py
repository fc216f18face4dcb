"""The ``pframe`` sub-commands, one module each.

Each module defines ``register(subparsers)``, which adds its parser and sets ``run`` to a
function of the parsed arguments returning the exit code. Modules import only argparse and
the standard library at the top; the library is imported inside ``run``, so ``pframe --help``
stays fast and a command never pays for another's imports.
"""

#: sub-command modules, in the order ``pframe --help`` lists them
COMMANDS = ("solve", "validate", "modes", "schema", "pi", "expand", "scale", "plot", "accuracy", "sweep",
            "gap", "risk", "compile", "opensees", "summary", "export", "animate")


def checked_output(output, overwrite: bool, inputs=(), what: str = "output file"):
    """The output path, checked before any work is done (None: standard output)."""
    if output is None:
        return None
    from pframe import outputs

    return outputs.check_output(output, inputs=inputs, overwrite=overwrite, what=what)


def write_text_output(text: str, output, overwrite: bool, inputs=()) -> None:
    """Write generated YAML to ``output`` (refusing to replace a file without ``overwrite``,
    or one of the ``inputs``), or, without one, to standard output."""
    import sys

    from pframe import outputs

    if output is not None:
        out = outputs.check_output(output, inputs=inputs, overwrite=overwrite,
                                   what="output file")
        with outputs.replacing(out) as tmp:
            tmp.write_text(text, encoding="utf-8")
        print(f"wrote {out}")
    else:
        sys.stdout.write(text)
