"""Shared pydantic base of the integrators' parameters."""

from pydantic import Field

from pframe.objects import Frozen


class IntegratorParams(Frozen):
    """An integrator's parameters: frozen, unknown fields refused, misuse an InputError."""


class Implicit(IntegratorParams):
    events: bool = Field(
        False,
        description="Event-aware stepping: split a step at contact onset and separation, so "
        "the onset velocity v0 is taken at the crossing (see docs/theory.md).",
    )
