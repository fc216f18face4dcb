"""The JSON Schemas of pframe's input files (built-in laws), shipped inside the package.

Five files, one per kind of input file, each with its ``$id``:

- ``model.schema.json``: a scene (:class:`pframe.model.scene.Scene`);
- ``pi-scene.schema.json``: a scene written in Pi numbers (:class:`pframe.nondim.pi_form.PiScene`);
- ``sweep.schema.json``: a sweep file (:class:`pframe.sweep.definition.SweepFile`);
- ``suite.schema.json``: a ground-motion suite of ``pframe gap``
  (:class:`pframe.excitation.suite.SuiteFile`);
- ``risk.schema.json``: a study of ``pframe risk`` (:class:`pframe.risk.study.StudyFile`).

They are generated from the pydantic models and made to pass a strict validator (ajv's
default strict mode): pydantic's ``discriminator`` keyword, which is OpenAPI's and not JSON
Schema's, is left out (every branch of a tagged union already fixes its tag with ``const``, so
``oneOf`` picks exactly one), and the tags a user hovers over to choose (``law``,
``material``, ``kind``, ``type``) carry a description taken from the law or model they pick.

The package holds the files (:func:`packaged`); ``pframe schema`` writes them for editors
(``schemas/`` of the repository, or any folder) and ``pframe schema --check`` fails when a
copy is stale.
"""

from __future__ import annotations

import inspect
import json
import re
from pathlib import Path

JSON_SCHEMA = "https://json-schema.org/draft/2020-12/schema"
#: file name -> (title, $id)
FILES = {
    "model.schema.json": ("pframe scene", "urn:pframe:schema:model"),
    "pi-scene.schema.json": ("pframe scene in Pi numbers", "urn:pframe:schema:pi-scene"),
    "sweep.schema.json": ("pframe sweep file", "urn:pframe:schema:sweep"),
    "suite.schema.json": ("pframe ground-motion suite", "urn:pframe:schema:suite"),
    "risk.schema.json": ("pframe risk study", "urn:pframe:schema:risk"),
}
#: the properties that pick a branch of a tagged union
SELECTORS = ("law", "material", "kind", "type")


def _first_sentence(text: str) -> str:
    text = " ".join(inspect.cleandoc(text).split("\n\n")[0].split())
    match = re.search(r"(?<! al)(?<! e\.g)(?<! i\.e)\. ", text)
    return text if match is None else text[:match.start() + 1]


def _law_summary(selector: str, value: str) -> str | None:
    kind = {"law": "contact", "material": "material"}.get(selector)
    if kind is None:
        return None
    from pframe.laws import get_law

    try:
        law = get_law(kind, value)
    except Exception:  # not a registered law: leave the schema's own text
        return None
    doc = law.__dict__.get("__doc__") or inspect.getmodule(law).__doc__
    return _first_sentence(doc) if doc else None


def _describe_selectors(schema: dict) -> None:
    """A description on every ``law``/``material``/``kind``/``type`` tag of a union branch."""
    what = {"law": "Contact law", "material": "Storey material", "type": "Integrator"}
    kinds = {"Sine": "Excitation", "Record": "Excitation", "History": "Recorder",
             "Envelope": "Recorder"}
    for name, model in schema.get("$defs", {}).items():
        what["kind"] = f"{kinds.get(name, 'The')} kind"
        for selector in SELECTORS:
            prop = model.get("properties", {}).get(selector)
            if not prop or "const" not in prop or prop.get("description"):
                continue
            value = prop["const"]
            summary = _law_summary(selector, value) or _first_sentence(model.get("description", ""))
            prop["description"] = f"{what[selector]} '{value}': {summary}".rstrip(": ")


def _strict(node) -> None:
    """Drop what a strict JSON Schema validator rejects: OpenAPI's ``discriminator``."""
    if isinstance(node, dict):
        node.pop("discriminator", None)
        for value in node.values():
            _strict(value)
    elif isinstance(node, list):
        for value in node:
            _strict(value)


def _patterns_without_named(node) -> None:
    """A property named in ``properties`` must also satisfy every ``patternProperties``
    pattern that matches its name (JSON Schema), which ajv's strict mode flags: a named
    ``Pi_alpha`` (0 to 1, or null) matched ``^Pi_[A-Za-z0-9_]+$`` (a number > 0), so the
    schema refused the valid ``Pi_alpha: 0``. Each pattern is made to leave the named
    properties out (a negative lookahead, which ECMA-262 regexes have)."""
    if isinstance(node, dict):
        patterns, named = node.get("patternProperties"), node.get("properties")
        if isinstance(patterns, dict) and isinstance(named, dict) and named:
            rewritten = {}
            for pattern, rule in patterns.items():
                matched = sorted(n for n in named if re.search(pattern, n))
                if matched and pattern.startswith("^"):
                    names = "|".join(re.escape(n) for n in matched)
                    pattern = f"^(?!(?:{names})$){pattern[1:]}"
                rewritten[pattern] = rule
            node["patternProperties"] = rewritten
        for value in node.values():
            _patterns_without_named(value)
    elif isinstance(node, list):
        for value in node:
            _patterns_without_named(value)


def _describe_references(schema: dict) -> None:
    """A property that only refers to a model takes that model's first sentence."""
    defs = schema.get("$defs", {})
    for model in [schema, *defs.values()]:
        for prop in model.get("properties", {}).values():
            if prop.get("description") or "$ref" not in prop:
                continue
            target = defs.get(prop["$ref"].split("/")[-1], {})
            if target.get("description"):
                prop["description"] = _first_sentence(target["description"])


def finish(schema: dict, name: str) -> dict:
    """A pydantic JSON Schema made into the file ``name`` (see the module docstring)."""
    title, schema_id = FILES[name]
    _strict(schema)
    _patterns_without_named(schema)
    _describe_selectors(schema)
    _describe_references(schema)
    return {"$schema": JSON_SCHEMA, "$id": schema_id, "title": title,
            **{k: v for k, v in schema.items() if k not in ("$schema", "$id", "title")}}


def scene_schema() -> dict:
    from pframe.model.scene import Scene

    return finish(Scene.model_json_schema(), "model.schema.json")


def pi_schema() -> dict:
    from pframe.nondim.pi_form import PiScene

    return finish(PiScene.model_json_schema(), "pi-scene.schema.json")


def sweep_schema() -> dict:
    from pframe.sweep.definition import SweepFile

    schema = SweepFile.model_json_schema()
    scene = schema.get("properties", {}).get("scene")
    if scene is not None:  # an inline base scene: either kind of scene file, checked by pframe
        scene["description"] = (scene.get("description", "") + " A scene or a scene in Pi "
                                "numbers, as in model.schema.json or pi-scene.schema.json "
                                "(pframe validate checks it).")
    return finish(schema, "sweep.schema.json")


def suite_schema() -> dict:
    from pframe.excitation.suite import SuiteFile

    return finish(SuiteFile.model_json_schema(), "suite.schema.json")


def risk_schema() -> dict:
    from pframe.risk.study import StudyFile

    return finish(StudyFile.model_json_schema(), "risk.schema.json")


def _text(schema: dict) -> str:
    return json.dumps(schema, indent=2, sort_keys=True) + "\n"


def texts() -> dict[str, str]:
    """File name -> text of every schema file."""
    return {"model.schema.json": _text(scene_schema()),
            "pi-scene.schema.json": _text(pi_schema()),
            "sweep.schema.json": _text(sweep_schema()),
            "suite.schema.json": _text(suite_schema()),
            "risk.schema.json": _text(risk_schema())}


def schema_text() -> str:
    """The text of ``model.schema.json``."""
    return _text(scene_schema())


def pi_schema_text() -> str:
    """The text of ``pi-scene.schema.json``."""
    return _text(pi_schema())


def packaged() -> Path:
    """The folder of the schema files shipped inside the package (``pframe/schemas``)."""
    return Path(__file__).parent / "schemas"
