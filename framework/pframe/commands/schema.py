"""``pframe schema [--check]``: write or check the JSON Schema of scene files."""

from __future__ import annotations

import sys
from pathlib import Path


def _schema(args) -> int:
    from pframe.schema import schema_text

    path = Path(args.output)
    text = schema_text()
    if args.check:
        current = path.read_text(encoding="utf-8") if path.exists() else None
        if current != text:
            print(f"pframe: {path} is stale or missing; run 'pframe schema' and commit it",
                  file=sys.stderr)
            return 1
        print(f"{path} is up to date")
        return 0
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_text(text, encoding="utf-8")
    print(f"wrote {path}")
    return 0


def register(sub) -> None:
    schema = sub.add_parser("schema", help="write the JSON Schema of scene files")
    schema.add_argument("--check", action="store_true", help="fail if the file is stale")
    schema.add_argument("-o", "--output", default="schemas/model.schema.json")
    schema.set_defaults(run=_schema)
