"""``pframe schema [--check]``: write or check the JSON Schemas of scene files.

Two files: the dimensional scene schema (``-o``, default ``schemas/model.schema.json``) and,
next to it, ``pi-scene.schema.json`` for scenes written in Pi numbers.
"""

from __future__ import annotations

import sys
from pathlib import Path


def _schema(args) -> int:
    from pframe.schema import pi_schema_text, schema_text

    path = Path(args.output)
    files = ((path, schema_text()), (path.with_name("pi-scene.schema.json"), pi_schema_text()))
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
    path.parent.mkdir(parents=True, exist_ok=True)
    for file, text in files:
        file.write_text(text, encoding="utf-8")
        print(f"wrote {file}")
    return 0


def register(sub) -> None:
    schema = sub.add_parser("schema", help="write the JSON Schemas of scene files")
    schema.add_argument("--check", action="store_true", help="fail if a file is stale")
    schema.add_argument("-o", "--output", default="schemas/model.schema.json",
                        help="the dimensional scene schema; pi-scene.schema.json is written "
                        "next to it")
    schema.set_defaults(run=_schema)
