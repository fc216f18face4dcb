"""A run refused for its size says what does not fit and how to reduce that: the step count
(a unit mistake in duration or dt) when the run would not fit even without its histories,
the histories recorded when it would, the floors when the scene's arrays are the cause. An
absurd step count is never blamed on what is recorded (generated over step counts, recorders,
scene sizes and sweeps)."""

from __future__ import annotations

import itertools

import pytest

from pframe import resources
from pframe.errors import InputError
from pframe.model.scene import Envelope, History

LIMIT = 2 * 2**30
HISTORIES = [History(kind="history", quantities=["displacement", "velocity", "story_drift"])]
ENVELOPES = [Envelope(kind="envelope", quantities=["displacement"])]


def _refusal(monkeypatch, *args, **kwargs) -> str | None:
    monkeypatch.setenv("PFRAME_MEMORY_LIMIT", str(LIMIT))
    est = resources.estimate(*args, **kwargs)
    try:
        resources.check(est, "scene.yaml")
    except InputError as exc:
        return str(exc)
    return None


CASES = list(itertools.product(
    [10**5, 10**6, 10**7, 10**8, 5 * 10**8],  # steps
    [(6, 6, 3), (2000, 2000, 1000), (2 * 10**5, 2 * 10**5, 10)],  # floors, storeys, contacts
    [HISTORIES, ENVELOPES],
    [dict(streaming=True), dict(streaming=False, variants=640, batch=64)]))


@pytest.mark.parametrize("steps, sizes, recorders, run", CASES)
def test_the_advice_names_the_part_that_does_not_fit(monkeypatch, steps, sizes, recorders, run):
    message = _refusal(monkeypatch, steps, *sizes, recorders, **run)
    if message is None:
        return
    assert message.startswith("scene.yaml: ") and "\n" not in message
    without = resources.estimate(steps, *sizes, ENVELOPES, **run)
    if without.memory > LIMIT:  # too large even with envelopes only: not the recorders
        assert "every k-th step" not in message and "envelopes only" not in message
        parts = dict(without.parts)
        if max(parts, key=parts.get) == "ground":
            assert f"its {steps:,} time steps" in message
            assert "check the units of analysis.duration and analysis.dt" in message
    else:  # it fits without its histories: they are the cause, and nothing else is blamed
        assert "the histories recorded need" in message and "every k-th step" in message
        assert "check the units" not in message and "fewer floors" not in message


def test_an_absurd_step_count_is_named_as_such(monkeypatch):
    """10^8 steps of the paper's pair with histories (the ground motion alone is 3 GiB):
    the message names the steps and their units, not the recorders."""
    message = _refusal(monkeypatch, 10**8, 6, 6, 3, HISTORIES)
    assert "its 100,000,000 time steps need 2.98 GiB for the ground motion alone" in message
    assert "every k-th step" not in message


def test_histories_that_do_not_fit_are_named_as_such(monkeypatch):
    """A sweep's chunk of 64 variants holding 2 10^5 rows of histories: the recorders (or the
    chunk), not the step count."""
    message = _refusal(monkeypatch, 2 * 10**5, 6, 6, 3, HISTORIES, streaming=False, variants=640,
                       batch=64)
    assert "the histories recorded need" in message and "(64 variants of a chunk at once)" in \
        message and "or a smaller chunk" in message
    assert "check the units" not in message


def test_too_many_steps_to_allocate_says_the_units(monkeypatch):
    monkeypatch.setenv("PFRAME_MEMORY_LIMIT", str(LIMIT))
    message = resources.check_steps(1e9, 1e-7, 100.0)
    assert "check the units of analysis.duration and analysis.dt" in message
    assert "every k-th step" not in message and "envelopes" not in message
