"""The JSON Schema of scene files (built-in laws), written to ``schemas/model.schema.json``."""

from __future__ import annotations

import json


def schema_text() -> str:
    from pframe.model.scene import Scene

    schema = Scene.model_json_schema()
    schema["$schema"] = "https://json-schema.org/draft/2020-12/schema"
    schema["title"] = "pframe scene"
    return json.dumps(schema, indent=2, sort_keys=True) + "\n"
