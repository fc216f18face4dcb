"""A scene of more floors, storeys and contacts than pframe sets up unasked (100,000; the
opt-in is PFRAME_MAX_FLOORS) is refused at once, before anything is built, with the estimated
set-up time, memory and run time (docs/getting-started.md#limits)."""

from __future__ import annotations

import tracemalloc
from pathlib import Path

import pytest
import yaml

from pframe.cli import main
from pframe.yamltext import load

WU2021 = Path(__file__).resolve().parents[1] / "models" / "wu2021-eq14.yaml"


def _scene(folder: Path, floors: int | None = None) -> Path:
    data = load(WU2021.read_text(encoding="utf-8"), str(WU2021))
    if floors is not None:
        for building in data["buildings"]:
            building["floors"] = floors
    path = folder / "scene.yaml"
    path.write_text(yaml.safe_dump(data, sort_keys=False), encoding="utf-8")
    return path


@pytest.mark.parametrize("command", ["validate", "solve"])
def test_a_million_floors_is_refused_at_once_with_its_estimate(tmp_path, capsys, monkeypatch,
                                                               command):
    monkeypatch.delenv("PFRAME_MAX_FLOORS", raising=False)
    monkeypatch.setenv("PFRAME_MEMORY_LIMIT", "1TiB")  # memory is not what refuses it
    scene = _scene(tmp_path, 1_000_000)
    tracemalloc.start()
    try:
        code = main([command, str(scene), "-o", str(tmp_path / "out.nc")][
            :None if command == "solve" else 2])
        _, peak = tracemalloc.get_traced_memory()
    finally:
        tracemalloc.stop()
    err = capsys.readouterr().err
    assert code == 2, err
    assert err.startswith("pframe: ") and "Traceback" not in err
    assert "2,000,000 floors" in err and "PFRAME_MAX_FLOORS=4000003" in err
    assert "the 50,000 steps about" in err and "before the first step" in err
    assert peak < 64 * 2**20  # nothing was built
    assert sorted(p.name for p in tmp_path.iterdir()) == ["scene.yaml"]


def test_the_opt_in_counts_floors_storeys_and_contacts(tmp_path, capsys, monkeypatch):
    """The paper's pair: 6 floors, 6 storeys and 3 contacts."""
    scene = _scene(tmp_path)
    monkeypatch.setenv("PFRAME_MAX_FLOORS", "14")
    assert main(["validate", str(scene)]) == 2
    assert "PFRAME_MAX_FLOORS=15" in capsys.readouterr().err
    monkeypatch.setenv("PFRAME_MAX_FLOORS", "15")
    assert main(["validate", str(scene)]) == 0


@pytest.mark.parametrize("value", ["lots", "0", "1e400", "2.5"])
def test_an_unreadable_opt_in_is_bad_input(tmp_path, capsys, monkeypatch, value):
    monkeypatch.setenv("PFRAME_MAX_FLOORS", value)
    assert main(["validate", str(_scene(tmp_path))]) == 2
    err = capsys.readouterr().err
    assert err.startswith("pframe: PFRAME_MAX_FLOORS: ") and "Traceback" not in err
