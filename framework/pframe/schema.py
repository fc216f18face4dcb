"""The JSON Schemas of scene files (built-in laws): ``schemas/model.schema.json`` for
dimensional scenes and ``schemas/pi-scene.schema.json`` for scenes in Pi numbers."""

from __future__ import annotations

import json


def schema_text() -> str:
    from pframe.model.scene import Scene

    schema = Scene.model_json_schema()
    schema["$schema"] = "https://json-schema.org/draft/2020-12/schema"
    schema["title"] = "pframe scene"
    return json.dumps(schema, indent=2, sort_keys=True) + "\n"


def pi_schema_text() -> str:
    from pframe.nondim.pi_form import PiScene

    schema = PiScene.model_json_schema()
    schema["$schema"] = "https://json-schema.org/draft/2020-12/schema"
    schema["title"] = "pframe scene in Pi numbers"
    return json.dumps(schema, indent=2, sort_keys=True) + "\n"
