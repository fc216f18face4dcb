"""The generated kernel: only what a scene needs, and chunked runs equal whole runs."""

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
