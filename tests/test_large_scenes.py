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


@pytest.mark.slow
def test_an_implicit_scene_is_checked_without_its_highest_frequency(monkeypatch):
    """The highest frequency with the contacts closed bounds central difference's step only:
    an implicit scene's stability check takes its contact periods (their effective masses
    and stiffnesses) and no eigenvalue, which for up to 2,000 degrees of freedom was a dense
    one (seconds at 2 x 1,000 floors, more than the whole set-up of 2 x 10,000). An explicit
    scene still has its w_max."""
    import numpy as np

    from pframe.assemble import assemble
    from pframe.reader import parse_scene

    def refused(*args, **kwargs):
        raise AssertionError("an eigenvalue was computed")

    text = _scene_text(20)
    plan = assemble(parse_scene(text).expanded)
    monkeypatch.setattr(np.linalg, "eigvalsh", refused)
    from pframe.assemble.stability import check

    _, parts, _ = check(plan, plan.integrator)
    assert parts.tolist() == [1]
    explicit = parse_scene(text.replace("type: newmark, gamma: 0.5, beta: 0.25",
                                        "type: central_difference"))
    with pytest.raises(AssertionError, match="an eigenvalue"):
        assemble(explicit.expanded)


def _scene_text(floors: int) -> str:
    data = load(WU2021.read_text(encoding="utf-8"), str(WU2021))
    for building in data["buildings"]:
        building["floors"] = floors
    data["contacts"] = [{**data["contacts"][0], "name": None, "nodes": ["A", "B"]}]
    del data["contacts"][0]["name"]
    data["analysis"]["duration"] = 10 * data["analysis"]["dt"]
    return yaml.safe_dump(data, sort_keys=False)
