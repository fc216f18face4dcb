"""Bad input met while reviewing the tall-scene work: each must end in a one-paragraph
InputError naming the place, never a traceback. Both predate that work (the code before it
fails the same way); they are kept here, expected to fail, until they are fixed where they
arise."""

from __future__ import annotations

import json
import subprocess
import sys

import pytest
from conftest import REPO

from pframe.errors import InputError
from pframe.reader import parse_scene


@pytest.mark.xfail(strict=True, raises=IndexError, reason="a building of the shorthand "
                   "whose per-floor lists are all empty has 0 floors: _storey_count returns "
                   "0 and the floors' geometry indexes an empty list (IndexError)")
def test_a_building_whose_per_floor_lists_are_empty_is_refused_where_it_is():
    scene = {"buildings": [{"name": "A", "mass": [],
                            "story": {"material": "elastic", "stiffness": 1.0e7}}],
             "analysis": {"dt": 0.01, "duration": 0.1}}
    with pytest.raises(InputError, match=r"buildings\[0\]"):
        parse_scene(json.dumps(scene), "empty.yaml")


@pytest.mark.slow
@pytest.mark.xfail(strict=True, reason="pframe schema -o . calls Path('.').with_name(...), "
                   "whose ValueError reaches the terminal as a traceback")
def test_schema_into_a_folder_name_without_a_file_name_is_refused(tmp_path):
    done = subprocess.run([sys.executable, "-m", "pframe.cli", "schema", "-o", "."],
                          capture_output=True, text=True, cwd=tmp_path, timeout=120,
                          env={"PYTHONPATH": str(REPO / "framework"), "PATH": ""})
    assert done.returncode == 2 and "Traceback" not in done.stderr, done.stderr
