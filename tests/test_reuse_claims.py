"""What a risk study's reuse of the runs without contacts trusts of a contact law
(pframe.risk.runs.reusable, docs/risk.md "Runs with contacts that never close"): a law's
``free_when_open`` speaks for the ``force`` it was declared beside. A plug-in law that
subclasses a built-in one and replaces its force inherits the built-in's claim without
making it: a study must then integrate every run with its contacts."""

from __future__ import annotations

from typing import Literal

import pytest
import yaml
from conftest import WU2021

import pframe.laws.registry as registry
import pframe.risk.runs as runs
from pframe.laws.contact.improved_kelvin import ImprovedKelvin
from pframe.reader import load_scene

#: how far before the gap closes the law below takes hold (m)
EARLY = 0.05


class EarlyKelvin(ImprovedKelvin):
    """A plug-in law as a third party might write one: pframe's improved Kelvin law with its
    force replaced by a spring that takes hold EARLY before the gap closes (a bumper
    standing proud of the face the gap is measured to). It declares nothing of its own."""

    class Params(ImprovedKelvin.Params):
        law: Literal["early_kelvin_test"]

    @staticmethod
    def force(params, committed, trial, deformation, rate):
        reach = deformation + EARLY
        if reach <= 0.0:
            return 0.0, 0.0, 0.0
        return params[0] * reach, params[0], 0.0


@pytest.fixture
def early_scene(tmp_path, monkeypatch):
    """The paper's pair with its contacts of the law above, installed as a plug-in is (an
    entry point's name; the class registered under it)."""
    monkeypatch.setitem(registry._registered["contact"], "early_kelvin_test", EarlyKelvin)
    monkeypatch.setattr(EarlyKelvin, "kind", "contact", raising=False)
    monkeypatch.setattr(EarlyKelvin, "name", "early_kelvin_test", raising=False)
    found = registry._entry_points

    def entry_points(kind):
        return {**found(kind), **({"early_kelvin_test": None} if kind == "contact" else {})}

    monkeypatch.setattr(registry, "_entry_points", entry_points)
    scene = yaml.safe_load(WU2021.read_text(encoding="utf-8"))
    for contact in scene["contacts"]:
        contact["law"] = "early_kelvin_test"
    path = tmp_path / "early.yaml"
    path.write_text(yaml.safe_dump(scene, sort_keys=False), encoding="utf-8")
    return load_scene(path)


def test_the_law_acts_before_its_gap_closes():
    """The premise: at an open gap (penetration -EARLY / 2) the law pushes, though it
    inherits the claim that it does not."""
    packed = (1.0e6, 0.0, 0.0)
    force, tangent, _ = EarlyKelvin.force(packed, None, None, -EARLY / 2, 0.0)
    assert force > 0.0 and tangent > 0.0
    assert EarlyKelvin.free_when_open  # inherited from ImprovedKelvin


def test_a_plug_in_that_replaces_a_built_in_force_is_not_reused(early_scene):
    assert not EarlyKelvin.claims_free_when_open()
    assert not runs.reusable(early_scene, (1500, 0.001), 1500, 0.001)


def test_every_built_in_contact_law_and_a_plain_subclass_keep_their_claim():
    """The rule refuses only a replaced force: a subclass that keeps the force (or declares
    the claim again beside its own force) still claims it, and every built-in law does."""
    laws = registry.all_contact_laws()
    assert laws and all(law.claims_free_when_open() for law in laws)

    class Renamed(ImprovedKelvin):
        pass

    class OwnForce(ImprovedKelvin):  # its own force, free while open, and its own claim
        free_when_open = True

        @staticmethod
        def force(params, committed, trial, deformation, rate):
            return ImprovedKelvin.force(params, committed, trial, deformation, rate)

    assert Renamed.claims_free_when_open() and OwnForce.claims_free_when_open()
