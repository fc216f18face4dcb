"""The JSON Schemas of the input files: one per kind of file, shipped in the package, each with
an ``$id``; every example in models/ (sweeps included) passes the schema its ``$schema`` line
names under an independent validator (check-jsonschema), seeded mistakes fail it, the schemas
pass ajv's strict mode (when node and ajv are installed), and every key a user hovers over in
an editor has a description."""

from __future__ import annotations

import json
import os
import shutil
import subprocess
import sys
from pathlib import Path

import pytest
import yaml
from conftest import assert_names

from pframe.commands.validate import input_kind
from pframe.schema import FILES, packaged, texts

REPO = Path(__file__).resolve().parents[1]
SCHEMAS = REPO / "schemas"
EXAMPLES = sorted((REPO / "models").rglob("*.yaml"))
SCHEMA_LINE = "# yaml-language-server: $schema="
#: the schema file of each kind of input file
FOR_KIND = {"scene": "model.schema.json", "pi-scene": "pi-scene.schema.json",
            "sweep": "sweep.schema.json", "suite": "suite.schema.json",
            "risk": "risk.schema.json"}


def _check_jsonschema():
    exe = shutil.which("check-jsonschema")
    if exe is None:
        pytest.skip("check-jsonschema is not installed (pip install -e \".[test]\")")
    return exe


def _validate(schema: Path, *instances: Path) -> dict[Path, list[dict]]:
    """check-jsonschema's verdict on each instance, from one run over all of them (a run
    costs a second of start-up; one per file made this the suite's slowest module): the
    errors it reports for each file, empty for a file that passes."""
    result = subprocess.run([_check_jsonschema(), "-o", "json", "--schemafile", str(schema),
                             *map(str, instances)], capture_output=True, text=True)
    report = json.loads(result.stdout)
    found = {Path(i).resolve(): [] for i in instances}
    for error in report["errors"] + report.get("parse_errors", []):
        found[Path(error["filename"]).resolve()].append(error)
    assert (result.returncode == 0) == (not any(found.values())), result.stdout + result.stderr
    return found


def test_the_schema_files_are_current_in_the_repository_and_the_package():
    for name, text in texts().items():
        assert (SCHEMAS / name).read_text(encoding="utf-8") == text, f"schemas/{name} is stale"
        assert (packaged() / name).read_text(encoding="utf-8") == text, \
            f"framework/pframe/schemas/{name} is stale"


def test_the_package_ships_the_schemas():
    """pyproject's package data takes the three files into the wheel (and sdist)."""
    if sys.version_info < (3, 11):
        pytest.skip("tomllib needs Python 3.11")
    import tomllib

    config = tomllib.loads((REPO / "pyproject.toml").read_text(encoding="utf-8"))
    patterns = config["tool"]["setuptools"]["package-data"]["pframe"]
    shipped = {p.name for pattern in patterns for p in packaged().parent.glob(pattern)}
    assert_names(shipped, FILES, f"the schemas pyproject's package data ({patterns}) ships",
                 extra=False)


def test_each_schema_has_its_id_and_title():
    ids = set()
    for name, (title, schema_id) in FILES.items():
        schema = json.loads((packaged() / name).read_text(encoding="utf-8"))
        assert schema["$id"] == schema_id and schema["title"] == title
        assert schema["$schema"] == "https://json-schema.org/draft/2020-12/schema"
        ids.add(schema["$id"])
    assert len(ids) == len(FILES)


@pytest.fixture(scope="module")
def example_verdicts():
    """check-jsonschema over every example, one run per schema its ``$schema`` line names."""
    by_schema: dict[Path, list[Path]] = {}
    for example in EXAMPLES:
        first = example.read_text(encoding="utf-8").splitlines()[0]
        if first.startswith(SCHEMA_LINE):
            schema = (example.parent / first[len(SCHEMA_LINE):].strip()).resolve()
            by_schema.setdefault(schema, []).append(example)
    verdicts = {}
    for schema, examples in by_schema.items():
        verdicts.update(_validate(schema, *examples))
    return verdicts


@pytest.mark.slow
@pytest.mark.parametrize("example", EXAMPLES, ids=[e.relative_to(REPO).as_posix() for e in EXAMPLES])
def test_every_example_names_its_schema_and_passes_it(example, example_verdicts):
    text = example.read_text(encoding="utf-8")
    first = text.splitlines()[0]
    assert first.startswith(SCHEMA_LINE), f"{example.name} must open with '{SCHEMA_LINE}...'"
    schema = (example.parent / first[len(SCHEMA_LINE):].strip()).resolve()
    assert schema == (SCHEMAS / FOR_KIND[input_kind(yaml.safe_load(text))]).resolve()
    assert example_verdicts[example.resolve()] == [], example_verdicts[example.resolve()]


#: (schema, a valid example, the mistake: (old text, new text), what the validator names)
MISTAKES = [
    ("model.schema.json", "wu2021-eq14.yaml", ("law: improved_kelvin", "law: improved_kelvn"),
     "contacts"),
    ("model.schema.json", "wu2021-eq14.yaml", ("restitution: 0.4", "restitution: 1.4"),
     "contacts"),
    ("model.schema.json", "wu2021-eq14.yaml", ("gap: 0.1242451014414167", "gapp: 0.12"),
     "contacts"),
    ("model.schema.json", "wu2021-eq14.yaml", ("material: bilinear", "material: steel"),
     "buildings"),
    ("model.schema.json", "wu2021-eq14.yaml", ("kind: sine", "kind: sinus"), "excitation"),
    ("model.schema.json", "wu2021-eq14.yaml", ("type: newmark", "type: newmarc"), "analysis"),
    ("model.schema.json", "wu2021-eq14.yaml", ("  dt: ", "  dtt: "), "analysis"),
    # (the names of Pi numbers depend on the scene, so the schema cannot list them; the
    # loader names a wrong one)
    ("pi-scene.schema.json", "wu2021-eq14-pi.yaml", ("  tau: 50", "  tau: -50"), "analysis"),
    ("pi-scene.schema.json", "wu2021-eq14-pi.yaml", ("law: improved_kelvin", "law: kelvn"),
     "contacts"),
    ("sweep.schema.json", "sweeps/wu2021-pi-d.yaml", ("linspace: [0, 2, 41]", "linspace: [0, 2]"),
     "axes"),
    ("sweep.schema.json", "sweeps/wu2021-pi-d.yaml", ("    path: pi.Pi_d", "    paht: pi.Pi_d"),
     "axes"),
    ("sweep.schema.json", "sweeps/wu2021-pi-d.yaml", ("keep:", "combine: both\nkeep:"),
     "combine"),
    ("sweep.schema.json", "sweeps/wu2021-pi-d.yaml", ("impact_count]", "impact_counts]"),
     "keep"),
    ("suite.schema.json", "suites/peer-records.yaml", ("measure: {kind: pga}",
                                                       "measure: {kind: pgv}"), "measure"),
    ("suite.schema.json", "suites/peer-records.yaml", ("  - ARL360.at2", "  - {file: ARL360.at2, "
                                                       "scale: -1}"), "records"),
]


@pytest.fixture(scope="module")
def mistake_verdicts(tmp_path_factory):
    """check-jsonschema over every seeded mistake (each in its own file), one run per schema."""
    folder = tmp_path_factory.mktemp("mistakes")
    by_schema: dict[str, list[Path]] = {}
    files = []
    for number, (schema, example, mistake, _) in enumerate(MISTAKES):
        text = (REPO / "models" / example).read_text(encoding="utf-8")
        assert mistake[0] in text, (example, mistake)
        broken = folder / f"{number}-{Path(example).name}"
        broken.write_text(text.replace(mistake[0], mistake[1], 1), encoding="utf-8")
        by_schema.setdefault(schema, []).append(broken)
        files.append(broken)
    verdicts = {}
    for schema, broken in by_schema.items():
        verdicts.update(_validate(SCHEMAS / schema, *broken))
    return [verdicts[f.resolve()] for f in files]


@pytest.mark.slow
@pytest.mark.parametrize("number, where", [(n, m[3]) for n, m in enumerate(MISTAKES)],
                         ids=[f"{m[1]}:{m[2][1].strip()}" for m in MISTAKES])
def test_seeded_mistakes_fail_the_schema(mistake_verdicts, number, where):
    errors = mistake_verdicts[number]
    assert errors, f"{MISTAKES[number]} passed the schema"
    assert f"$.{where}" in json.dumps(errors), errors  # the place it names


def _properties(schema: dict):
    for name, model in [("(top level)", schema), *schema.get("$defs", {}).items()]:
        for key, prop in model.get("properties", {}).items():
            yield name, key, prop


@pytest.mark.parametrize("name", list(FILES))
def test_every_key_has_a_description(name):
    schema = json.loads((packaged() / name).read_text(encoding="utf-8"))
    missing = [f"{model}.{key}" for model, key, prop in _properties(schema)
               if not prop.get("description")]
    assert not missing, f"{name}: keys without a description: {missing}"
    tags = [(model, key, prop) for model, key, prop in _properties(schema)
            if key in ("law", "material", "kind", "type") and "const" in prop]
    for model, key, prop in tags:  # the tag names what it picks, and says what that is
        assert f"'{prop['const']}': " in prop["description"], (model, key, prop)


def test_no_openapi_keywords_are_left():
    for name in FILES:
        assert '"discriminator"' not in (packaged() / name).read_text(encoding="utf-8")


AJV = """
const Ajv2020 = require("ajv/dist/2020");
const fs = require("fs");
let failed = 0;
for (const file of process.argv.slice(1)) {
  const ajv = new Ajv2020({strictTypes: true, strictTuples: true});  // strict: throw, not log
  try { ajv.compile(JSON.parse(fs.readFileSync(file, "utf8"))); }
  catch (e) { console.log(file + ": " + e.message); failed = 1; }
}
process.exit(failed);
"""


def test_ajv_strict_mode_compiles_every_schema():
    """ajv's default strict mode rejects unknown keywords (pydantic's discriminator) and
    ambiguous types; node and the npm package ajv are not Python things, so CI skips this."""
    node = shutil.which("node")
    if node is None:
        pytest.skip("node is not installed: the ajv strict-mode check needs node and npm's ajv")
    # where the README and .ci/run install it (npm install --prefix .venv/node ajv@8)
    env = dict(os.environ, NODE_PATH=os.pathsep.join(
        p for p in (os.environ.get("NODE_PATH"), str(REPO / ".venv" / "node" / "node_modules"))
        if p))
    probe = subprocess.run([node, "-e", "require.resolve('ajv/dist/2020')"], capture_output=True,
                           env=env)
    if probe.returncode != 0:
        pytest.skip("node cannot find the npm package ajv (npm install --prefix .venv/node "
                    "ajv@8, or set NODE_PATH to a node_modules folder that holds it)")
    files = [str(packaged() / name) for name in FILES]
    result = subprocess.run([node, "-e", AJV, *files], capture_output=True, text=True, env=env)
    assert result.returncode == 0, result.stdout + result.stderr


@pytest.mark.slow
def test_a_named_pi_number_is_checked_by_its_own_rule_only(tmp_path):
    """A Pi number named in the schema (Pi_alpha: 0 to 1) is not also held to the rule of
    the other Pi numbers (a number > 0): Pi_alpha = 0, which pframe accepts, passes the
    schema (it failed when the pattern matched the named properties too), a made-up
    Pi_foo = 0 still fails, and pframe agrees on both."""
    from pframe.api import load
    from pframe.errors import InputError

    text = (REPO / "models" / "wu2021-eq14-pi.yaml").read_text(encoding="utf-8")
    assert "  Pi_alpha: 0.1" in text
    elastic = tmp_path / "pi-alpha-0.yaml"
    elastic.write_text(text.replace("  Pi_alpha: 0.1", "  Pi_alpha: 0"), encoding="utf-8")
    unknown = tmp_path / "pi-foo-0.yaml"
    unknown.write_text(text.replace("  Pi_alpha: 0.1", "  Pi_alpha: 0.1\n  Pi_foo: 0"),
                       encoding="utf-8")
    verdicts = _validate(SCHEMAS / "pi-scene.schema.json", elastic, unknown)
    assert verdicts[elastic.resolve()] == [], verdicts
    load(elastic)  # pframe accepts it too
    assert verdicts[unknown.resolve()] and "Pi_foo" in json.dumps(verdicts[unknown.resolve()])
    with pytest.raises(InputError):
        load(unknown)
