"""Shared pydantic base of the integrators' parameters, and the facts each declares."""

from __future__ import annotations

from dataclasses import dataclass, fields
from typing import ClassVar

from pydantic import Field, model_validator

from pframe.objects import Frozen

#: the stepping paths beyond the whole step that an implicit integrator may support: contact
#: events located inside steps (``events: true``), and a failed step retried in 2, 4, ...
#: sub-steps
PATHS = ("events", "retry")


@dataclass(frozen=True)
class Facts:
    """What an integrator declares about itself. The generic tests read these facts instead
    of keeping tables by name, and fail naming an integrator that has left one out (None).

    order : int
        Convergence order on smooth motion (tests/test_integrators.py).
    paths : frozenset of str
        The paths of :data:`PATHS` the integrator runs on; the others refuse (``events: true``
        at validation; a failed step stops the run instead of being retried).
    examples : dict
        label -> a configuration (the YAML ``analysis.integrator`` mapping) the tests run;
        the first is the integrator's reference configuration.
    restitution_tolerance, impact_balance_tolerance : float
        On the free two-body impact at 400 steps per contact without events: the largest
        error in the coefficient of restitution against its formula, and in the energy balance
        (tests/test_contact_matrix.py, with the reasons measured there).
    balance : dict
        label -> (configuration, (low, high)): on the paper's scene at 1 and 4 times its step,
        the algorithmic dissipation relative to the largest energy term lies in (low, high)
        (tests/test_verdict.py).
    balance_tolerance : float
        The energy balance error on the paper's scene (tests/test_verdict.py).
    spectral_decay : tuple of dict
        Configurations whose free-vibration dissipation is checked against the spectral radius
        of their amplification matrix (empty: the integrator dissipates nothing).
    """

    order: int | None = None
    paths: frozenset | None = None
    examples: dict | None = None
    restitution_tolerance: float | None = None
    impact_balance_tolerance: float | None = None
    balance: dict | None = None
    balance_tolerance: float | None = None
    spectral_decay: tuple | None = None

    def missing(self) -> list[str]:
        """The facts not declared."""
        return [f.name for f in fields(self) if getattr(self, f.name) is None]


class IntegratorParams(Frozen):
    """An integrator's parameters: frozen, unknown fields refused, misuse an InputError."""

    #: the kernel's scheme that runs it (pframe.integrators.SCHEME, by its type); None:
    #: explicit
    scheme: ClassVar[str | None] = None
    #: what the generic tests check (see Facts)
    facts: ClassVar[Facts] = Facts()

    @classmethod
    def type_name(cls) -> str:
        """The YAML ``type`` (the tag of the scene's integrator union)."""
        return cls.model_fields["type"].default

    @classmethod
    def __pydantic_init_subclass__(cls, **kwargs):
        super().__pydantic_init_subclass__(**kwargs)
        from pframe.integrators import SCHEME

        field = cls.model_fields.get("type")
        if field is not None and field.default in SCHEME:  # an integrator of the table
            cls.scheme = SCHEME[field.default]


class Implicit(IntegratorParams):
    events: bool = Field(
        False,
        description="Event-aware stepping: split a step at contact onset and separation, so "
        "the onset velocity v0 is taken at the crossing (see docs/theory.md).",
    )

    @model_validator(mode="after")
    def _events_supported(self):
        if self.events and "events" not in (self.facts.paths or ()):
            raise ValueError(f"the {self.type_name()} integrator does not locate contact "
                             "events inside its steps: set events: false")
        return self

    def runs_on(self) -> dict:
        """The Coefficients arguments that say which paths it runs on."""
        return {"events": self.events, "retry": "retry" in (self.facts.paths or ())}
