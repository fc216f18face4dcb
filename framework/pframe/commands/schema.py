"""``pframe schema [--check]``: write or check the JSON Schemas of the input files.

Five files (``pframe.schema``): the scene schema (``-o``, default ``schemas/model.schema.json``)
and, next to it, ``pi-scene.schema.json``,
``sweep.schema.json``, ``suite.schema.json`` and ``risk.schema.json``.
The package ships the same files (``pframe/schemas/``); in a source checkout ``pframe schema``
rewrites those too, and ``--check`` fails when either copy is stale.
"""

from __future__ import annotations

import json
import sys
from pathlib import Path


def _is_pframe_schema(file: Path) -> bool:
    """Whether ``file`` is a regular file holding one of pframe's JSON Schemas (its ``$id``
    starts with ``urn:pframe:schema:``): that file is refreshed without ``--overwrite``."""
    try:
        if not file.is_file() or file.stat().st_size > 2**22:
            return False
        data = json.loads(file.read_text(encoding="utf-8"))
    except (OSError, ValueError):
        return False
    return isinstance(data, dict) and str(data.get("$id", "")).startswith("urn:pframe:schema:")


def _source_checkout() -> bool:
    """Whether pframe runs from its repository (not from an installed wheel)."""
    from pframe.schema import packaged

    pyproject = packaged().parents[2] / "pyproject.toml"
    return pyproject.is_file() and 'name = "pframe"' in pyproject.read_text(encoding="utf-8")


def _schema(args) -> int:
    from pframe.schema import packaged, texts

    if not args.output.strip():
        from pframe.errors import InputError

        raise InputError("-o '': the schema file needs a name")
    path = Path(args.output)
    generated = texts()
    # beside it: parent / name, not with_name, which raises on '.' (a folder, refused below
    # as every command's output folder is)
    files = [(path if name == "model.schema.json" else path.parent / name, text)
             for name, text in generated.items()]
    if (args.check or _source_checkout()) and packaged().resolve() != path.parent.resolve():
        files += [(packaged() / name, text) for name, text in generated.items()]
    if args.check:
        stale = 0
        for file, text in files:
            current = file.read_text(encoding="utf-8") if file.exists() else None
            if current != text:
                print(f"pframe: {file} is stale or missing; run 'pframe schema' and commit it",
                      file=sys.stderr)
                stale += 1
            else:
                print(f"{file} is up to date")
        return 1 if stale else 0
    from pframe import outputs

    for file, _ in files:  # every file checked before any is written
        if file.parent != packaged():
            outputs.make_folder(file.parent)
        outputs.check_output(file, overwrite=args.overwrite or _is_pframe_schema(file),
                             what="schema file")
    for file, text in files:
        with outputs.replacing(file) as tmp:
            tmp.write_text(text, encoding="utf-8")
        print(f"wrote {file}")
    return 0


def register(sub) -> None:
    schema = sub.add_parser("schema", help="write the JSON Schemas of the input files")
    schema.add_argument("--check", action="store_true", help="fail if a file is stale")
    schema.add_argument("--overwrite", action="store_true",
                        help="replace existing files that are not pframe schemas (a file "
                             "holding one of pframe's schemas is refreshed without it)")
    schema.add_argument("-o", "--output", default="schemas/model.schema.json",
                        help="the scene schema; pi-scene.schema.json, sweep.schema.json, "
                             "suite.schema.json and risk.schema.json are written next to it")
    schema.set_defaults(run=_schema)
