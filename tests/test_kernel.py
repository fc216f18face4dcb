"""The generated kernel: only what a scene needs, and chunked runs equal whole runs."""

from pathlib import Path

import numpy as np

from pframe.assemble import assemble
from pframe.kernel import simulate
from pframe.kernel.codegen import Structure, generate
from pframe.model import load_scene, parse_scene

ELASTIC = """
buildings:
  - {name: A, floors: 3, mass: 1000.0, story: {material: elastic, stiffness: 2.0e6}}
excitation: {kind: sine, amplitude: 2.0, frequency: 6.0}
analysis: {dt: 0.005, duration: 2.0}
recorders: [{kind: envelope, quantities: [displacement]}]
"""


def _source(text):
    plan = assemble(parse_scene(text).expanded)
    return plan, generate(Structure.of(plan))


def test_linear_scene_has_no_newton_and_no_contacts():
    plan, source = _source(ELASTIC)
    assert plan.linear
    assert "claw" not in source and "contact_dofs[e" not in source
    assert "norm_du" not in source  # no Newton convergence test
    assert source.count("ldl_factor(band, bw)") == 1  # factored once, before the steps
    assert "h_velocity" not in source and "e_story_drift" not in source  # nothing unasked


def test_nonlinear_scene_has_what_it_records_only():
    plan = assemble(load_scene("models/wu2021-eq14.yaml").expanded)
    source = generate(Structure.of(plan))
    assert not plan.linear
    assert "claw0" in source and "norm_du" in source
    for q in ("displacement", "velocity", "story_force", "story_drift", "contact_force"):
        assert f"h_{q}[b" in source
    assert "h_acceleration" not in source and "h_contact_penetration" not in source


def test_chunked_run_equals_single_run():
    """The progress-bar path (many kernel calls) gives bit-identical results."""
    plan = assemble(load_scene("models/wu2021-eq14.yaml").expanded)
    whole = simulate(plan)
    calls = []
    chunked = simulate(plan, progress=lambda done, total: calls.append(done), chunk_seconds=1e-4)
    assert len(calls) > 5 and calls[-1] == plan.steps + 1
    for q in whole.history:
        assert np.array_equal(whole.history[q], chunked.history[q])
    for q in whole.envelope:
        assert np.array_equal(whole.envelope[q], chunked.envelope[q])
    assert np.array_equal(whole.impacts, chunked.impacts)
    assert np.array_equal(whole.energy, chunked.energy)


def test_one_newton_solve_per_step_while_laws_keep_their_branch():
    """The constant-acceleration predictor meets a storey that keeps yielding on its yield
    branch: the paper's example (every storey of A yields, 24 impacts) needs a second solve
    only in the steps where a storey yields or unloads or a contact is closed. With the
    predictor u = x_n it needed one in four steps of five (88,091 solves)."""
    plan = assemble(load_scene("models/wu2021-eq14.yaml").expanded)
    result = simulate(plan)
    assert result.completed(0)
    assert result.impacts.sum() == 24
    assert result.iterations[0] / plan.steps < 1.03  # 50,716 solves for 50,000 steps


def test_reusing_the_factorisation_changes_no_bit(tmp_path, monkeypatch):
    """The kernel refactors the effective stiffness only when an element tangent or the
    (sub-)step changed. A kernel edited to refactor at every solve gives the same bits, so no
    change of tangent is missed (a missed one would still converge, to different bits)."""
    import importlib

    from pframe.kernel import run as run_module

    text = (Path(__file__).parent.parent / "models" / "wu2021-eq14.yaml").read_text()
    plan = assemble(parse_scene(text.replace("duration: 7.957747154594767", "duration: 3.0"))
                    .expanded)
    structure = Structure.of(plan)
    source = generate(structure)
    assert source.count("if stale or hs != h_factored:") == 1
    (tmp_path / "always_refactor.py").write_text(
        source.replace("if stale or hs != h_factored:", "if True:"), encoding="utf-8")
    monkeypatch.syspath_prepend(str(tmp_path))
    always = importlib.import_module("always_refactor").kernel
    reused = simulate(plan)
    monkeypatch.setattr("pframe.kernel.build.kernel_for", lambda st: always)
    refactored = run_module.simulate(plan)
    assert reused.impacts.sum() > 0 and reused.substeps.sum() >= 0
    for q in reused.history:
        assert np.array_equal(reused.history[q], refactored.history[q]), q
    assert np.array_equal(reused.energy, refactored.energy)
    assert np.array_equal(reused.iterations, refactored.iterations)
