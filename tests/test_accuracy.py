"""pframe accuracy: integrators x time steps against the reference solution."""

import csv

import numpy as np
import pytest

from pframe import accuracy
from pframe.cli import main
from pframe.reader import parse_scene

SCENE = """
buildings:
  - name: A
    floors: 2
    mass: 500.0
    story: {material: bilinear, stiffness: 2.0e5, yield_drift: 0.03, alpha: 0.1}
  - {name: B, floors: 2, mass: 1000.0, story: {material: elastic, stiffness: 2.0e6}}
contacts:
  - {nodes: [A/2, B/2], gap: 0.05, law: improved_kelvin, frequency_ratio: 40, restitution: 0.5}
excitation: {kind: sine, amplitude: 6.0, frequency: 6.0}
analysis: {dt: 0.0005, duration: 3.0}
"""


@pytest.fixture(scope="module")
def rows():
    loaded = parse_scene(SCENE)
    integrators = {k: accuracy.INTEGRATORS[k] for k in ("newmark", "newmark+events", "hht")}
    return accuracy.study(loaded, integrators, factors=(4.0, 2.0, 1.0), repeats=1)


def test_errors_fall_with_dt_and_impacts_match(rows):
    table, reference = rows
    assert reference.impacts.sum() >= 2
    for name in ("newmark", "newmark+events", "hht"):
        errors = [r.displacement_error for r in table if r.integrator == name]
        assert len(errors) == 3 and errors[0] > errors[1] > errors[2]
        assert errors[-1] < 1e-2
    events = [r for r in table if r.integrator == "newmark+events"]
    assert all(r.impacts == r.reference_impacts for r in events)
    assert all(r.energy_balance_error < 1e-9 for r in events)  # average acceleration


def test_recommendation_is_the_fastest_run_within_tolerance(rows):
    table, _ = rows
    for tol, pick in accuracy.recommend(table, (1e-2, 1e-9)):
        fit = [r for r in table if r.displacement_error <= tol and r.impacts == r.reference_impacts]
        if tol == 1e-9:
            assert pick is None
        else:
            assert pick is min(fit, key=lambda r: r.solve_seconds)


def test_command_writes_table_csv_and_plot(tmp_path, capsys):
    model = tmp_path / "scene.yaml"
    model.write_text(SCENE)
    out = tmp_path / "acc"
    code = main(["accuracy", str(model), "--integrators", "newmark,central_difference",
                 "--factors", "2,1", "--repeats", "1", "-o", str(out)])
    assert code == 0
    printed = capsys.readouterr().out
    assert "displacement error <= 0.01" in printed
    with open(out / "accuracy.csv") as handle:
        rows = list(csv.DictReader(handle))
    assert [r["integrator"] for r in rows] == ["newmark"] * 2 + ["central_difference"] * 2
    assert all(np.isfinite(float(r["displacement_error"])) for r in rows)
    pytest.importorskip("matplotlib")
    assert (out / "work-precision.png").read_bytes()[:4] == b"\x89PNG"


def test_unknown_integrator_is_bad_input(tmp_path, capsys):
    model = tmp_path / "scene.yaml"
    model.write_text(SCENE)
    assert main(["accuracy", str(model), "--integrators", "rk4"]) == 2
    assert "unknown integrator 'rk4'" in capsys.readouterr().err
