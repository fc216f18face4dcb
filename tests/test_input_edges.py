"""Input met while reviewing the tall-scene work that ended in a traceback (both predate
that work): a building whose per-floor lists are all empty is refused where it stands, and
``pframe schema -o .`` is refused as any output folder is."""

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
def test_schema_into_a_folder_is_refused_as_every_output_folder_is(tmp_path):
    """-o . ended in a traceback from Path('.').with_name(); a folder is refused as an
    output, in one line, as every command refuses one (tests/test_hostile_paths.py)."""
    done = subprocess.run([sys.executable, "-m", "pframe.cli", "schema", "-o", "."],
                          capture_output=True, text=True, cwd=tmp_path, timeout=120,
                          env={"PYTHONPATH": str(REPO / "framework"), "PATH": ""})
    assert done.returncode == 2 and "Traceback" not in done.stderr, done.stderr
    assert done.stderr.strip().splitlines() == [
        "pframe: .: is a folder; give a file name for the schema file (-o)"]
    assert not list(tmp_path.iterdir())  # nothing written beside it
