"""One list for each kind of thing, the others derived from it and held together here.

- Recorded quantities: ``pframe.quantities.QUANTITIES`` is the list; the kernel's slots
  (``kernel.state.Recordable``, and through it ``c/state.h``), the scene's recorders, the
  sweep's histories and the reference solver follow it; ``kernel/c/record.c`` gathers each.
- Energy terms: ``kernel.state.Energy`` is the list of slots; ``ENERGY_TERMS`` names those a
  result file carries and the rest are the kernel's bookkeeping.
- Counters, status columns, element kinds, damping stiffness: ``kernel.state`` enumerations.

Outside the C kernel the small arrays are indexed by slot name, never by number (checked on
the source).
"""

from __future__ import annotations

import math
import re
import typing
from pathlib import Path

import numpy as np
import pytest
from conftest import analysis, assert_names, building, run_text, scene_text

from pframe.kernel import state
from pframe.quantities import QUANTITIES

ROOT = Path(__file__).resolve().parents[1]
PACKAGE = ROOT / "framework" / "pframe"


def _c_defines() -> dict[str, int]:
    text = (PACKAGE / "kernel" / "c" / "state.h").read_text(encoding="utf-8")
    return {m[1]: int(m[2]) for m in re.finditer(r"#define (\w+) (-?\d+)\n", text)}


def test_recordable_slots_are_the_quantities_in_order():
    assert state.RECORDABLE == tuple(QUANTITIES)
    assert [s.name.lower() for s in state.Recordable] == list(QUANTITIES)
    defines = _c_defines()
    for name, slot in state.RECORDABLE_SLOT.items():
        assert defines[name.upper()] == slot == list(QUANTITIES).index(name)
    assert defines["RECORDABLE_COUNT"] == len(QUANTITIES)


def test_every_quantity_is_gathered_by_the_kernel_and_known_to_its_users():
    """record.c names each quantity's slot; the scene's recorders, the sweep's histories and
    the reference solver take exactly the quantities of the list."""
    from pframe.model.scene import QUANTITIES as recordable
    from pframe.reference.result import ReferenceResult
    from pframe.sweep.definition import Keep

    record_c = (PACKAGE / "kernel" / "c" / "record.c").read_text(encoding="utf-8")
    for slot in state.Recordable:
        assert re.search(rf"\b{slot.name}\b", record_c), f"record.c never gathers {slot.name}"
    assert recordable == tuple(QUANTITIES)
    histories = typing.get_args(typing.get_args(Keep.model_fields["histories"].annotation)[0])
    assert_names(histories, QUANTITIES, "the sweep's keep.histories choices")
    assert_names(ReferenceResult.__dataclass_fields__, QUANTITIES,
                 "the reference solver's ReferenceResult fields", extra=False)


GAP, CONTACT_STIFFNESS = 0.01, 5.0e6
STOREYS = {"A": 197392.088, "B": 1973920.88}
LINK_K, LINK_C, HEIGHT = 2.0e4, 500.0, 3.0


def _pounding_every_quantity():
    """Two elastic buildings pounding through linear contacts, every quantity of the list
    recorded as a history at every step and as an envelope."""
    text = scene_text(
        buildings=[building("A", 2, 250.0, {"material": "elastic", "stiffness": STOREYS["A"]})
                   | {"height": HEIGHT},
                   building("B", 2, 1000.0, {"material": "elastic", "stiffness": STOREYS["B"]})
                   | {"height": HEIGHT}],
        contacts=[{"name": f"floor-{i}", "nodes": [f"A/{i}", f"B/{i}"], "gap": GAP,
                   "law": "linear", "stiffness": CONTACT_STIFFNESS} for i in (1, 2)],
        links=[{"name": "coupler", "nodes": ["A/2", "B/2"], "material": "kelvin_voigt",
                "stiffness": LINK_K, "damping": LINK_C}],
        damping={"ratio": 0.05, "modes": [1, 2]},
        excitation={"kind": "sine", "amplitude": 9.81, "frequency": 2.0 * math.pi},
        analysis=analysis(2.0e-4, 1.5),
        recorders=[{"kind": "history", "quantities": list(QUANTITIES)},
                   {"kind": "envelope", "quantities": list(QUANTITIES)}],
    )
    return run_text(text)


def test_every_quantity_records_what_it_means():
    """Each quantity of the list is gathered from its own state and shaped by its dimension:
    drifts are floor differences, penetrations the closure beyond the gap, forces the laws'
    (elastic storeys, linear contacts), the ground acceleration the sine; an envelope is the
    peak of the absolute history."""
    plan, result = _pounding_every_quantity()
    assert result.completed(0)
    # a foundation's sway and rocking need soil (tests/test_soil.py checks them), a named
    # plan point a floor plan (tests/test_plan.py)
    on_soil = {q for q, (dim, _, _) in QUANTITIES.items() if dim in ("foundation", "point")}
    assert_names(result.history, set(QUANTITIES) - on_soil, "the quantities recorded as histories")
    assert_names(result.envelope, set(QUANTITIES) - on_soil, "the quantities recorded as envelopes")
    widths = {"node": plan.n_dof, "story": len(plan.story_names),
              "contact": len(plan.contact_names), "link": len(plan.link_names)}
    for q, (dim, _, _) in QUANTITIES.items():
        if q in on_soil:
            continue
        history = result.history[q][0]
        assert history.shape[0] == plan.steps + 1
        assert history.shape[1:] == (() if dim is None else (widths[dim],)), q
        assert np.all(np.isfinite(history)), q
        assert np.array_equal(result.envelope[q][0], np.abs(history).max(axis=0)), q
    h = {q: v[0] for q, v in result.history.items()}
    u = h["displacement"]
    ns = len(plan.story_names)
    lower, upper = plan.story_dofs[:ns, 0], plan.story_dofs[:ns, 1]
    drift = u[:, upper] - np.where(lower >= 0, u[:, np.maximum(lower, 0)], 0.0)
    np.testing.assert_allclose(h["story_drift"], drift, rtol=0, atol=1e-15)
    np.testing.assert_allclose(h["story_drift_ratio"], drift / HEIGHT, rtol=1e-15, atol=0)
    first, second = plan.story_dofs[ns:, 0], plan.story_dofs[ns:, 1]  # the links
    stretch = u[:, second] - u[:, first]
    np.testing.assert_allclose(h["link_deformation"], stretch, rtol=0, atol=1e-15)
    rate = h["velocity"][:, second] - h["velocity"][:, first]
    np.testing.assert_allclose(h["link_force"], LINK_K * stretch + LINK_C * rate,
                               rtol=1e-12, atol=1e-9)
    k = np.array([STOREYS[name.split("/")[0]] for name in plan.story_names])
    np.testing.assert_allclose(h["story_force"], k * drift, rtol=1e-12, atol=1e-9)
    left, right = plan.contact_dofs[:, 0], plan.contact_dofs[:, 1]
    closure = u[:, left] - u[:, right] - plan.contact_gap[0]
    penetration = np.maximum(closure, 0.0)
    assert penetration.max() > 0  # it does pound
    np.testing.assert_allclose(h["contact_penetration"], penetration, rtol=0, atol=1e-15)
    np.testing.assert_allclose(h["contact_force"], CONTACT_STIFFNESS * penetration,
                               rtol=1e-12, atol=1e-6)
    t = np.arange(plan.steps + 1) * plan.dt[0]
    np.testing.assert_allclose(h["ground_acceleration"], 9.81 * np.sin(2.0 * math.pi * t),
                               rtol=0, atol=1e-12)
    velocity = np.concatenate([[0.0], np.cumsum(0.5 * plan.dt[0] * (
        h["ground_acceleration"][1:] + h["ground_acceleration"][:-1]))])
    np.testing.assert_allclose(h["ground_displacement"], np.concatenate([[0.0], np.cumsum(
        0.5 * plan.dt[0] * (velocity[1:] + velocity[:-1]))]), rtol=1e-12, atol=1e-15)
    np.testing.assert_array_equal(h["contact_ground_displacement"], 0.0)  # one ground
    np.testing.assert_allclose(h["absolute_acceleration"],
                               h["acceleration"] + h["ground_acceleration"][:, None],
                               rtol=0, atol=1e-12)
    np.testing.assert_allclose(np.diff(u, axis=0) / plan.dt[0],
                               0.5 * (h["velocity"][1:] + h["velocity"][:-1]),
                               rtol=1e-9, atol=1e-12)  # Newmark average acceleration
    np.testing.assert_allclose(np.diff(h["velocity"], axis=0) / plan.dt[0],
                               0.5 * (h["acceleration"][1:] + h["acceleration"][:-1]),
                               rtol=1e-9, atol=1e-9)


def test_energy_terms_and_bookkeeping_are_the_energy_slots(tmp_path):
    """Every energy slot is a term of the balance that result files carry or the kernel's own
    bookkeeping, not both; the file's energy attributes are the terms, each documented, and
    they close the balance."""
    terms, bookkeeping = set(state.ENERGY_TERMS.values()), set(state.ENERGY_BOOKKEEPING)
    assert not terms & bookkeeping
    assert_names(terms | bookkeeping, state.Energy, "the energy terms and bookkeeping slots")
    assert len(state.ENERGY_TERMS) == len(terms)
    assert _c_defines()["ENERGY_SLOTS"] == len(state.Energy)
    netcdf = (ROOT / "docs" / "netcdf.md").read_text(encoding="utf-8")
    for name in state.ENERGY_TERMS:
        assert f"`energy_{name}`" in netcdf, f"docs/netcdf.md does not describe energy_{name}"

    import pframe

    plan, result = _pounding_every_quantity()
    e = result.energy_terms(0)
    assert list(e) == list(state.ENERGY_TERMS)
    balance = e["input"] - (e["kinetic"] - e["initial_kinetic"] + e["damping"] + e["storeys"]
                            + e["contacts"] + e["links"] + e["algorithmic"])
    assert abs(balance) < 1e-9 * e["input"]
    scene = tmp_path / "scene.yaml"
    scene.write_text(scene_text(
        buildings=[building("A", 1, 100.0, {"material": "elastic", "stiffness": 4.0e4})],
        damping={"ratio": 0.02, "modes": [1, 1]},
        excitation={"kind": "sine", "amplitude": 1.0, "frequency": 3.0},
        analysis=analysis(0.01, 1.0)), encoding="utf-8")
    dataset = pframe.solve(scene)
    written = {k[len("energy_"):] for k in dataset.attrs
               if k.startswith("energy_") and not k.endswith("_units")}
    assert_names(written - {"balance_error"}, state.ENERGY_TERMS, "the file's energy attributes")


def test_counters_are_named_and_written():
    from pframe.record.hdf5 import COUNTER_ATTRIBUTES

    assert state.COUNTER_NAMES == tuple(c.name.lower() for c in state.Counter)
    assert_names({name for name, _ in COUNTER_ATTRIBUTES}, state.COUNTER_NAMES,
                 "record/hdf5.py's COUNTER_ATTRIBUTES")
    assert _c_defines()["COUNTER_SLOTS"] == len(state.Counter)


def test_damping_stiffness_slots_are_the_scenes_choices():
    from pframe.assemble.plan import DAMPING_STIFFNESS
    from pframe.model.scene import Rayleigh

    choices = typing.get_args(Rayleigh.model_fields["stiffness"].annotation)
    assert tuple(DAMPING_STIFFNESS) == choices
    assert [DAMPING_STIFFNESS[c] for c in choices] == list(state.DampingStiffness)
    defines = _c_defines()
    assert [defines[f"DAMPING_{c.upper()}"] for c in choices] == list(range(len(choices)))


#: the kernel's small arrays, indexed by a number instead of a slot name
NUMERIC_SLOT = re.compile(r"\b(energy|status|counters|scalars)\[[^\]\[]*,\s*:?\s*-?\d+\s*[\]:]")


@pytest.mark.parametrize("folder", ["framework", "tests", "benchmarks"])
def test_slots_are_used_by_name(folder):
    """``result.energy[b, 2]`` says nothing and breaks silently when a slot is added; the
    Python side says ``result.energy[b, Energy.DAMPING]`` (or ``result.energy_terms()``)."""
    found = []
    for path in sorted((ROOT / folder).rglob("*.py")):
        if path.name == Path(__file__).name:
            continue
        for number, line in enumerate(path.read_text(encoding="utf-8").splitlines(), 1):
            if NUMERIC_SLOT.search(line):
                found.append(f"{path.relative_to(ROOT)}:{number}: {line.strip()}")
    assert not found, "slots used by number:\n" + "\n".join(found)


def test_the_numeric_slot_check_finds_one():
    assert NUMERIC_SLOT.search("w_in = result.energy[0, :6]")
    assert NUMERIC_SLOT.search("if result.status[b, 0] == 0:")
    assert NUMERIC_SLOT.search("self.counters[:, 3]")
    assert not NUMERIC_SLOT.search("result.energy[b, Energy.DAMPING]")
    assert not NUMERIC_SLOT.search("self.energy[b]")
    assert not NUMERIC_SLOT.search("single.energy[0]")  # a batch member
