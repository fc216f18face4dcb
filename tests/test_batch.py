"""A batch of variants is N independent runs: the same numbers as N single runs."""

from __future__ import annotations

import numpy as np
import pytest
from conftest import run_batch, run_text

from pframe.kernel import simulate

#: A small pounding scene (2 + 2 floors, bilinear storeys, improved Kelvin contacts; the
#: laws and recorders of models/wu2021-eq14.yaml, so it shares that kernel). GAP and
#: STIFFNESS are replaced per variant.
TEMPLATE = """
title: batch variant
buildings:
  - {name: A, floors: 2, mass: 250.0,
     story: {material: bilinear, stiffness: 197392.088, yield_drift: 0.0248, alpha: 0.1}}
  - {name: B, floors: 2, mass: [1000.0, 800.0],
     story: {material: bilinear, stiffness: 1973920.88, yield_drift: 0.0149, alpha: 0.1}}
contacts:
  - {name: floor-1, nodes: [A/1, B/1], gap: GAP, law: improved_kelvin,
     stiffness: STIFFNESS, restitution: 0.4}
  - {name: floor-2, nodes: [A/2, B/2], gap: GAP, law: improved_kelvin,
     stiffness: STIFFNESS, restitution: 0.6}
damping: {ratio: 0.05, modes: [1, 2]}
excitation: {kind: sine, amplitude: 9.81, frequency: 6.283185307179586}
analysis: {dt: 2.0e-4, duration: 3.0}
recorders:
  - kind: history
    quantities: [displacement, velocity, story_force, story_drift, contact_force]
  - kind: envelope
    quantities: [displacement, story_drift, contact_force]
"""
VARIANTS = [(0.005, 2.0e7), (0.01, 2.0e7), (0.005, 5.0e6), (0.015, 1.0e8)]  # (gap m, k N/m)


def _text(gap, stiffness):
    return TEMPLATE.replace("GAP", repr(gap)).replace("STIFFNESS", repr(stiffness))


@pytest.fixture(scope="module")
def batch():
    return run_batch([_text(*v) for v in VARIANTS])


@pytest.fixture(scope="module")
def singles():
    return [run_text(_text(*v)) for v in VARIANTS]


def test_batch_equals_single_runs(batch, singles):
    """Each member of a batch of 4 variants (gaps and contact stiffnesses) gives bit for bit
    the histories, envelopes, impact counts and energies of its own single run: the members
    share code and topology, never numbers."""
    plan, result = batch
    assert plan.batch == len(VARIANTS)
    for b, (single_plan, single) in enumerate(singles):
        assert single.completed(0) and result.completed(b)
        assert np.array_equal(plan.node_dof, single_plan.node_dof)
        assert set(result.history) == set(single.history)
        for q, values in result.history.items():
            assert np.array_equal(values[b], single.history[q][0]), q
        assert set(result.envelope) == set(single.envelope)
        for q, values in result.envelope.items():
            assert np.array_equal(values[b], single.envelope[q][0]), q
        assert np.array_equal(result.impacts[b], single.impacts[0])
        assert np.array_equal(result.energy[b], single.energy[0])


def test_batch_variants_really_differ(batch):
    """The variants pound differently (else the comparison above would prove little)."""
    plan, result = batch
    impacts = result.impacts
    print("impacts per variant:", impacts.tolist())
    assert np.all(impacts.sum(axis=1) > 0)
    assert len({tuple(row) for row in impacts.tolist()}) > 1
    force = result.envelope["contact_force"]
    for i in range(len(VARIANTS)):
        for j in range(i):
            assert not np.array_equal(result.history["displacement"][i],
                                      result.history["displacement"][j])
            assert not np.allclose(force[i], force[j], rtol=1e-3)
    assert np.all(result.envelope["story_drift"][:, 0] > 0.0248)  # A/1 yields in all


@pytest.mark.slow
def test_chunked_run_equals_one_call(batch):
    """Running the batch in chunks (with a progress callback) continues from the state left
    in place and gives the same numbers as one kernel call."""
    plan, result = batch
    calls = []
    # chunks of about 2 ms: some 30 calls here (at 1e-4 s every call is one step, and the
    # calls' overhead, not the steps, takes the test's time)
    chunked = simulate(plan, progress=lambda done, total: calls.append((done, total)),
                       chunk_seconds=2e-3)
    assert len(calls) > 2 and calls[-1] == (plan.steps + 1, plan.steps + 1)
    for q in result.history:
        assert np.array_equal(chunked.history[q], result.history[q]), q
    for q in result.envelope:
        assert np.array_equal(chunked.envelope[q], result.envelope[q]), q
    assert np.array_equal(chunked.impacts, result.impacts)
    assert np.array_equal(chunked.energy, result.energy)


def test_a_batch_refuses_variants_whose_newton_settings_differ():
    """One plan holds one Newton tolerance: variants that ask for another are refused, not
    run with variant 0's (the batch key includes the Newton settings)."""
    from pframe.assemble import assemble_batch, batch_key
    from pframe.errors import InputError
    from pframe.reader import parse_scene

    base = _text(*VARIANTS[0])
    strict = base.replace("analysis: {dt: 2.0e-4, duration: 3.0}",
                          "analysis: {dt: 2.0e-4, duration: 3.0, newton: {tolerance: 1.0e-9}}")
    assert strict != base
    a, b = (parse_scene(t).expanded for t in (base, strict))
    assert batch_key(a) != batch_key(b)
    with pytest.raises(InputError, match="Newton settings"):
        assemble_batch([a, b])
    other = parse_scene(_text(*VARIANTS[1])).expanded  # numbers only: the same key
    assert batch_key(a) == batch_key(other)


def test_members_share_a_modal_fit_only_when_they_share_the_structure():
    """Members with one structure share its Rayleigh fit and dt checks (a risk study's
    records); a member with other masses or stiffnesses gets its own, as it would alone."""
    import dataclasses

    from pframe.assemble import assemble, assemble_batch
    from pframe.reader import parse_scene

    base = parse_scene(_text(0.005, 2.0e7)).expanded
    heavy = dataclasses.replace(base, masses=base.masses * 4.0)
    stiff = parse_scene(TEMPLATE.replace("GAP", "0.005").replace("STIFFNESS", "2e7")
                        .replace("1973920.88", "7895683.52")).expanded
    members = [base, heavy, base, stiff]
    plan = assemble_batch(members)
    for b, ex in enumerate(members):
        alone = assemble(ex)
        assert np.array_equal(plan.mass_damping[b], alone.mass_damping[0])
        assert np.array_equal(plan.story_beta[b], alone.story_beta[0])
    assert not np.array_equal(plan.mass_damping[0], plan.mass_damping[1])
    assert not np.array_equal(plan.story_beta[0], plan.story_beta[3])


@pytest.mark.parametrize("law", ["improved_kelvin", "hertz"])
def test_a_batch_checks_each_members_contacts_as_alone(law):
    """The stability check of a batch finds each member's contact periods and event sub-steps
    as the member's own plan does, whether members share their numbers (found once) or differ
    only in the ground motion, which sets a power law's stiffness (Hertz) and not a linear
    one's (improved Kelvin)."""
    from conftest import parse_scene

    from pframe.assemble import assemble, assemble_batch
    from pframe.assemble.stability import check, highest_frequency

    contact = ("stiffness: 2.0e7, restitution: 0.4" if law == "improved_kelvin" else
               "stiffness: 5.0e9")
    text = (TEMPLATE.replace("law: improved_kelvin,\n     stiffness: STIFFNESS, restitution: 0.4",
                             f"law: {law}, {contact}")
            .replace("law: improved_kelvin,\n     stiffness: STIFFNESS, restitution: 0.6",
                     f"law: {law}, {contact}")
            .replace("GAP", "0.005")
            .replace("analysis: {", "analysis: {integrator: {type: newmark, events: true}, "))
    variants = [parse_scene(text.replace("amplitude: 9.81", f"amplitude: {a!r}")).expanded
                for a in (9.81, 2.0, 9.81, 40.0)]
    plan = assemble_batch(variants)
    periods = [highest_frequency(assemble(ex))[1] for ex in variants]
    assert [np.array_equal(periods[0], p) for p in periods[1:]] == (
        [True] * 3 if law == "improved_kelvin" else [False, True, False])
    batch_parts = check(plan, plan.integrator)[1]
    assert batch_parts.tolist() == [int(assemble(ex).event_parts[0]) for ex in variants]


def _same(a, b) -> bool:
    """Equal to the bit: arrays by dtype, shape and value (NaN where NaN), dataclasses and
    containers field by field."""
    import dataclasses

    if isinstance(a, np.ndarray):
        return (isinstance(b, np.ndarray) and a.dtype == b.dtype and a.shape == b.shape
                and np.array_equal(a, b, equal_nan=a.dtype.kind == "f"))
    if dataclasses.is_dataclass(a) and not isinstance(a, type):
        return type(a) is type(b) and all(_same(getattr(a, f.name), getattr(b, f.name))
                                          for f in dataclasses.fields(a))
    if isinstance(a, (tuple, list)):
        return (type(a) is type(b) and len(a) == len(b)
                and all(_same(x, y) for x, y in zip(a, b)))
    if isinstance(a, dict):
        return a.keys() == b.keys() and all(_same(a[k], b[k]) for k in a)
    if isinstance(a, float) and isinstance(b, float) and a != a:
        return b != b
    return a == b


@pytest.mark.slow
@pytest.mark.parametrize("model", ["wu2021-eq14.yaml", "ssi-pair.yaml", "damper-linked.yaml",
                                   "plan-asymmetric-pair.yaml", "hust-4x3.yaml"])
@pytest.mark.parametrize("contacts", [False, True])
def test_members_under_other_motions_alone_are_assembled_once_to_the_bit(model, contacts):
    """A batch of one scene under several ground motions (a risk study's, a gap audit's) is
    assembled once and its rows repeated: every field of the plan, warnings included, is the
    plan assembled member by member (the same members, each a copy, which the batch cannot
    take for one scene's)."""
    import dataclasses
    from pathlib import Path

    from pframe.assemble import assemble_batch
    from pframe.assemble.plan import Plan, _motions_only
    from pframe.gap.runs import axes_of, for_runs, on_channels, under
    from pframe.reader import load_scene

    loaded = load_scene(Path(__file__).parents[1] / "models" / model)
    ex = loaded.expanded
    rng = np.random.default_rng(3)
    steps = 200
    motions = on_channels(rng.standard_normal((4, len(ex.channels), steps + 1)))
    # a step of 0.1 s: coarse for the buildings' periods, so the time-scale checks warn
    base = dataclasses.replace(for_runs(loaded, axes_of(motions, None), contacts),
                               steps=steps, dt=0.1)
    members = under(base, motions)
    assert _motions_only(members)
    once = assemble_batch(members)
    copies = [dataclasses.replace(m, masses=m.masses.copy()) for m in members]
    assert not _motions_only(copies)
    each = assemble_batch(copies)
    assert once.warnings  # the case checks the warnings' member numbers
    for field in dataclasses.fields(Plan):
        assert _same(getattr(once, field.name), getattr(each, field.name)), field.name
    assert not np.array_equal(once.ground_acceleration[0], once.ground_acceleration[1])
