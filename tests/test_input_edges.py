"""Input met while reviewing the tall-scene work that ended in a traceback (both predate
that work): a building whose per-floor lists are all empty is refused where it stands, and
``pframe schema -o`` takes a folder."""

from __future__ import annotations

import json
import subprocess
import sys

import pytest
from conftest import REPO

from pframe.errors import InputError
from pframe.reader import parse_scene


def test_a_building_whose_per_floor_lists_are_empty_is_refused_where_it_is():
    scene = {"buildings": [{"name": "A", "mass": [],
                            "story": {"material": "elastic", "stiffness": 1.0e7}}],
             "analysis": {"dt": 0.01, "duration": 0.1}}
    with pytest.raises(InputError, match=r"buildings\[0\]"):
        parse_scene(json.dumps(scene), "empty.yaml")


@pytest.mark.slow
@pytest.mark.parametrize("output", [".", "new/", "out"])
def test_schema_into_a_folder_writes_the_schemas_in_it(tmp_path, output):
    """-o names the scene schema's file or, as a folder (one that exists, or a name ending in
    a slash, made if need be), the folder the schemas go into; '.' ended in a traceback from
    Path('.').with_name()."""
    (tmp_path / "out").mkdir()
    done = subprocess.run([sys.executable, "-m", "pframe.cli", "schema", "-o", output],
                          capture_output=True, text=True, cwd=tmp_path, timeout=120,
                          env={"PYTHONPATH": str(REPO / "framework"), "PATH": ""})
    assert done.returncode == 0 and "Traceback" not in done.stderr, done.stderr
    folder = tmp_path / output
    for name in ("model", "pi-scene", "sweep", "suite", "risk"):
        data = json.loads((folder / f"{name}.schema.json").read_text(encoding="utf-8"))
        assert data["$id"] == f"urn:pframe:schema:{name}"
