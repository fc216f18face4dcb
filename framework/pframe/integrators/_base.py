"""Shared pydantic base of the integrators' parameters."""

from pydantic import BaseModel, ConfigDict, Field


class IntegratorParams(BaseModel):
    model_config = ConfigDict(extra="forbid", frozen=True)


class Implicit(IntegratorParams):
    events: bool = Field(
        False,
        description="Event-aware stepping: split a step at contact onset and separation, so "
        "the onset velocity v0 is taken at the crossing (see docs/theory.md).",
    )
