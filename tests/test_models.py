"""Every shipped scene in models/ names the schema for editors, validates, and runs to the end."""

from __future__ import annotations

from pathlib import Path

import h5py
import pytest
import yaml
from conftest import runnable_model

from pframe.cli import main
from pframe.reader import load_scene

REPO = Path(__file__).resolve().parents[1]
MODELS = sorted((REPO / "models").glob("*.yaml"))
SCHEMA_LINE = "# yaml-language-server: $schema="


def test_there_are_models():
    assert MODELS, "models/ holds no *.yaml scene"


@pytest.mark.parametrize("model", MODELS, ids=[m.name for m in MODELS])
def test_model_names_the_schema_and_validates(model, tmp_path):
    text = model.read_text(encoding="utf-8")
    first = text.splitlines()[0]
    assert first.startswith(SCHEMA_LINE), f"{model.name} must open with '{SCHEMA_LINE}...'"
    schema = (model.parent / first[len(SCHEMA_LINE):].strip()).resolve()
    # a scene in Pi numbers (top-level 'pi:') has its own schema
    expected = "pi-scene" if "pi" in (yaml.safe_load(text) or {}) else "model"
    assert schema == (REPO / "schemas" / f"{expected}.schema.json").resolve()
    assert schema.is_file()
    loaded = load_scene(runnable_model(model, tmp_path))
    assert loaded.expanded.steps >= 1
    assert loaded.expanded.node_names


@pytest.mark.slow
@pytest.mark.parametrize("model", MODELS, ids=[m.name for m in MODELS])
def test_model_solves(model, tmp_path, capsys):
    model = runnable_model(model, tmp_path)
    out = tmp_path / f"{model.stem}.h5"
    assert main(["solve", str(model), "-o", str(out), "-q"]) == 0, capsys.readouterr().err
    assert capsys.readouterr().err == ""
    with h5py.File(out, "r") as f:
        attrs = f.attrs
        assert attrs["complete"] == 1
        assert attrs["status"] == b"completed"  # NC_CHAR: bytes in h5py
        assert attrs["steps_completed"] == attrs["steps"] == load_scene(model).expanded.steps
        assert attrs["input_yaml"].decode() == model.read_text(encoding="utf-8")
        assert 0.0 <= attrs["energy_balance_error"] < 1e-8
