"""Pydantic building blocks shared by the laws' ``Params`` models."""

from __future__ import annotations

import math
from fractions import Fraction
from typing import Annotated, Literal

from pydantic import AfterValidator, BaseModel, ConfigDict, Field, model_validator

from pframe.errors import InputError
from pframe.laws.restitution import E_MIN, check_restitution

Positive = Annotated[float, Field(gt=0, allow_inf_nan=False)]
Restitution = Annotated[
    float,
    Field(gt=0, le=1, description="Coefficient of restitution e, in (0, 1]."),
]
#: The restitution of a damped law, whose damping grows without bound as e -> 0: at least
#: :data:`pframe.laws.restitution.E_MIN` (checked by ``pframe validate``).
DampedRestitution = Annotated[
    float,
    Field(gt=0, le=1, description=f"Coefficient of restitution e, in [{E_MIN}, 1]."),
    AfterValidator(check_restitution),
]
#: The stiffness of the Hertz-type laws (hertz, hertzdamp, jankowski), for the schema and the docs.
HERTZ_STIFFNESS = (
    "Hertz stiffness k (N/m^1.5) of F = k delta^1.5. An impact at approach velocity v penetrates "
    "delta_m = (5 m_eff v^2 / (4 k))^(2/5) and lasts about 2.94 delta_m / v (m_eff = m1 m2 / "
    "(m1 + m2)); pframe warns when dt gives fewer than 20 steps per contact period. Published: "
    "2.75e10 N/m^1.5 (25,000 kip/in^1.5, Muthukumar & DesRoches 2006, bridge decks); see "
    "docs/restitution.md#choosing-the-contact-stiffness.")
#: How a damped law turns its restitution into damping (see docs/restitution.md).
Calibration = Annotated[
    Literal["published", "exact"],
    Field(description="published (the default): the damping formula of the law's source, whose "
                      "two-body impact rebounds with a restitution near e (docs/restitution.md "
                      "lists how near; pframe validate and solve warn when it misses e by more "
                      "than 0.02 and calibration was not written); exact: the damping with "
                      "which it rebounds with e itself."),
]


class LawParams(BaseModel):
    """Base of every law's parameters: frozen, unknown fields rejected."""

    model_config = ConfigDict(extra="forbid", frozen=True, defer_build=True)


class ContactStiffness(LawParams):
    """A linear contact spring given by stiffness, contact frequency or frequency ratio.

    The contact frequency is w_bar = sqrt(k (m1 + m2) / (m1 m2)) with m1, m2 the masses of
    the two colliding nodes (Wu et al. 2021, eq. 8); ``frequency_ratio`` is w_bar / w_p, the
    paper's Pi_wcon, and needs a sine excitation.
    """

    stiffness: Positive | None = Field(
        None, description="Contact stiffness k (N/m). The contact frequency is w_bar = "
        "sqrt(k (m1 + m2) / (m1 m2)), the contact period 2 pi / w_bar; pframe warns when dt "
        "gives fewer than 20 steps per period. A stiff spring, many times the storey stiffness "
        "(Wu et al. 2021: w_bar = 65 w_p); see docs/restitution.md#choosing-the-contact-stiffness.")
    frequency: Positive | None = Field(
        None, description="Contact frequency w_bar = sqrt(k (m1+m2)/(m1 m2)) (rad/s)."
    )
    frequency_ratio: Positive | None = Field(
        None, description="w_bar / w_p, the paper's Pi_wcon (needs a sine excitation)."
    )

    @model_validator(mode="after")
    def _exactly_one(self):
        given = [n for n in ("stiffness", "frequency", "frequency_ratio") if getattr(self, n)]
        if len(given) != 1:
            raise ValueError(
                "give exactly one of stiffness (N/m), frequency (rad/s) or frequency_ratio "
                f"(Pi_wcon); got {', '.join(given) or 'none'}"
            )
        return self

    def resolve_stiffness(self, context) -> float:
        """Stiffness k (N/m) from whichever of the three forms was given."""
        if self.stiffness is not None:
            return float(self.stiffness)
        if self.frequency is not None:
            w = self.frequency
        else:
            if context is None or context.excitation_frequency is None:
                raise InputError(
                    "frequency_ratio needs a sine excitation (it is w_bar / w_p); give "
                    "stiffness or frequency instead"
                )
            w = self.frequency_ratio * context.excitation_frequency
        return w * w * context.effective_mass


def kelvin_damping_ratio(e: float) -> float:
    """zeta = -ln e / sqrt(pi^2 + ln^2 e) (Anagnostopoulos 1988); 0 for e = 1."""
    if e >= 1.0:
        return 0.0
    ln_e = math.log(e)
    return -ln_e / math.sqrt(math.pi**2 + ln_e**2)


#: why a dashpot's coefficient c of F = c |v|^alpha sign v has no fixed dimension (the
#: ``undimensioned`` declaration of the laws with a power-law dashpot)
DASHPOT_UNDIMENSIONED = ("c of F = c |v|^alpha sign v is in N (s/m)^alpha, a dimension that "
                         "depends on alpha; scale it by hand (by S_F S_v^-alpha)")


def dashpot_dimensions(cls, given: dict) -> dict[str, str]:
    """A dashpot law's ``dimensions_given``: c of F = c |v|^alpha sign v in N (s/m)^alpha,
    alpha its ``exponent`` as written (the law's default where left out)."""
    alpha = given.get("exponent", cls.Params.model_fields["exponent"].default)
    if isinstance(alpha, bool) or not isinstance(alpha, (int, float)) or not alpha > 0:
        return {}  # validation names the exponent
    return {"damping": dashpot_units(alpha)}


def dashpot_units(alpha: float) -> str:
    """The units of c of F = c |v|^alpha sign v, N (s/m)^alpha = kg m^(1 - alpha)
    s^(alpha - 2), as a unit string :func:`pframe.nondim.dimensions.parse_units` reads.

    alpha is read as the nearest fraction of denominator at most 1000 (1/3 for 0.333...): a
    dimension's exponents are exact rationals, and a velocity exponent is a design value of
    a few digits.
    """
    a = Fraction(alpha).limit_denominator(1000)
    return f"kg m^({1 - a}) s^({a - 2})"
