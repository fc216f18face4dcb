"""What a law declares for its generic tests: one table of facts per law, on the law.

The tests of every law (``tests/test_laws.py``, ``tests/test_restitution.py``,
``tests/test_kernel.py``, ``tests/test_reference.py``; the impact matrix through
``tests/conftest.py``) loop over the registry and read from each law:

- ``examples``: parameter sets, as a scene writes them (without ``law:`` / ``material:``);
  the first is the one a scene of the tests runs (the every-law kernel run);
- ``tangent_states(packed)``: :class:`TangentState` rows at which the tangents are checked
  against finite differences of ``force`` (and against a closed form where one is given);
- contact laws: ``impacts``, the free two-body impacts of the tests (:class:`Impact`:
  1000 kg at 0.5 m/s into 3000 kg at rest), ``reference_force(params, context, v0)``, the
  force F(delta, delta') written from the law's paper (the oracle an impact ODE is integrated
  with: it never calls ``force`` or ``pack``), and ``rebound(params)``, the restitution of a
  two-body impact in closed form (None where there is none: the ODE is the reference then).

A built-in law that lacks one fails the tests with one message naming the law and the fact
(:func:`declared`). Plug-in laws need none of them.
"""

from __future__ import annotations

from dataclasses import dataclass, field

#: the contact tests' approach velocity of a running contact (m/s): the committed onset
#: velocity of the Hunt-Crossley family's running contacts
V0 = 0.5


@dataclass(frozen=True)
class TangentState:
    """A state at which a law's tangents are checked.

    Attributes
    ----------
    committed : tuple of float
        The committed state (as many numbers as the law's ``state_names``).
    deformation, rate : float
        The trial deformation (m) and its rate (m/s), away from any kink of the law (the
        test checks that the one-sided differences agree).
    scale : (float, float)
        The natural scales of deformation and rate: the finite-difference steps are 1e-6 of
        them, the absolute floors of the comparison |f| / scale.
    tangent, rate_tangent : float or None
        The closed-form d force / d deformation and d force / d rate there, if known.
    tolerance : (float, float)
        Relative tolerances on ``tangent`` and ``rate_tangent`` (0: equal to the bit).
    """

    committed: tuple
    deformation: float
    rate: float
    scale: tuple = (0.01, 0.1)
    tangent: float | None = None
    rate_tangent: float | None = None
    tolerance: tuple = (1e-14, 1e-14)


def contact_states(onset: tuple, running: tuple) -> list[TangentState]:
    """The contact tests' five states, none within 10% of a kink of a built-in law: the
    first step of a contact (committed ``onset``) approaching, then a contact that began at
    :data:`V0` (committed ``running``) approaching, near its maximum penetration, rebounding
    and rebounding near separation. The scales are the state's own deformation and rate."""
    rows = [(onset, 1.0e-3, 0.4), (running, 1.0e-3, 0.4), (running, 3.0e-3, 0.05),
            (running, 2.0e-3, -0.1), (running, 4.0e-4, -0.05)]
    return [TangentState(c, x, r, (x, abs(r))) for c, x, r in rows]


@dataclass(frozen=True)
class Impact:
    """A free two-body impact of a contact law in the tests: 1000 kg at 0.5 m/s into 3000 kg
    at rest, gap 0, no damping (``tests/conftest.py``).

    Attributes
    ----------
    params : dict
        The contact's fields but ``law``, ``restitution`` and ``calibration`` (which the tests
        vary): a stiffness that suits those masses.
    label : str
        How docs/restitution.md's tables name the case.
    tolerance : float
        The kernel's error in e at 4000 steps per contact that the test allows (say why in a
        comment: the force's smoothness at onset and separation sets the order).
    calibrations : tuple of str
        The rows of docs/restitution.md's tables (damped laws).
    descriptions : dict
        calibration -> the table's text of its damping, where not "published (source)" or
        "exact".
    exact_label : str or None
        The label of the exact row, where not ``label``.
    """

    params: dict
    label: str
    tolerance: float = 1e-5
    calibrations: tuple = ("published", "exact")
    descriptions: dict = field(default_factory=dict)
    exact_label: str | None = None


class NotDeclared(AssertionError):
    """A built-in law lacks a fact its generic tests need."""


#: what each fact is, for the message that names a missing one
FACTS = {
    "examples": "parameter sets, as a scene writes them",
    "tangent_states": "the states at which its tangents are checked (pframe.laws.facts."
                      "TangentState)",
    "impacts": "its free two-body impacts in the tests (pframe.laws.facts.Impact)",
    "reference_force": "its force F(delta, delta') written from its paper, the oracle of the "
                       "impact tests",
    "rebound": "the restitution of a two-body impact in closed form, or None where there is "
               "none",
}


def declared(law, fact: str):
    """``law``'s declaration of ``fact``; :class:`NotDeclared` naming the law and the fact
    when it has none (an attribute the law never set, or left empty)."""
    value = getattr(law, fact, None)
    if value is None and fact == "rebound" and "rebound" in vars(law):
        return None  # declared: no closed form
    if value is None or (fact in ("examples", "impacts") and not value):
        raise NotDeclared(
            f"{law.kind} law {law.name!r} ({law.__module__}) declares no {fact}: "
            f"{FACTS[fact]} (docs/architecture.md, 'A law carries its facts')")
    return value


def tangent_states(law, packed) -> list[TangentState]:
    """``law.tangent_states(packed)``; :class:`NotDeclared` where the law declares none."""
    states = law.tangent_states(packed)
    if not states:
        raise NotDeclared(
            f"{law.kind} law {law.name!r} ({law.__module__}) declares no tangent_states: "
            f"{FACTS['tangent_states']} (docs/architecture.md, 'A law carries its facts')")
    return states
