"""Physical dimensions as exact exponents of mass M, length L and time T.

A :class:`Dimension` is the vector ``(a, b, c)`` of ``M^a L^b T^c`` with
:class:`fractions.Fraction` entries, so that quantities such as a Hertz contact stiffness
(N/m^1.5 = M L^-1/2 T^-2) are represented exactly and products, quotients and powers of
dimensions never accumulate floating-point error.

:data:`QUANTITY` lists the physical quantities pframe uses, and :func:`parse_units` reads the
small unit strings of the YAML reference (``"N/m^1.5"``, ``"rad/s"``, ``"kg"``, ``"1"``).
"""

from __future__ import annotations

import re
from dataclasses import dataclass
from fractions import Fraction

#: the base dimensions, in the order of a :class:`Dimension`'s exponents
BASE = ("M", "L", "T")


def _fraction(value) -> Fraction:
    return value if isinstance(value, Fraction) else Fraction(value)


@dataclass(frozen=True)
class Dimension:
    """``M^mass L^length T^time`` with exact rational exponents."""

    mass: Fraction = Fraction(0)
    length: Fraction = Fraction(0)
    time: Fraction = Fraction(0)

    def __post_init__(self):
        for name in ("mass", "length", "time"):
            object.__setattr__(self, name, _fraction(getattr(self, name)))

    @property
    def exponents(self) -> tuple[Fraction, Fraction, Fraction]:
        return (self.mass, self.length, self.time)

    @classmethod
    def of(cls, exponents) -> Dimension:
        return cls(*exponents)

    def __mul__(self, other: Dimension) -> Dimension:
        return Dimension.of(a + b for a, b in zip(self.exponents, other.exponents))

    def __truediv__(self, other: Dimension) -> Dimension:
        return Dimension.of(a - b for a, b in zip(self.exponents, other.exponents))

    def __pow__(self, power) -> Dimension:
        power = _fraction(power)
        return Dimension.of(a * power for a in self.exponents)

    @property
    def dimensionless(self) -> bool:
        return not any(self.exponents)

    def __str__(self) -> str:
        """``M L^-1 T^-2`` style; ``1`` for a dimensionless quantity."""
        parts = []
        for base, exponent in zip(BASE, self.exponents):
            if exponent == 1:
                parts.append(base)
            elif exponent and exponent.denominator == 1:
                parts.append(f"{base}^{exponent}")
            elif exponent:
                parts.append(f"{base}^({exponent})")
        return " ".join(parts) or "1"


DIMENSIONLESS = Dimension()
MASS = Dimension(mass=1)
LENGTH = Dimension(length=1)
TIME = Dimension(time=1)

#: the physical quantities pframe uses, by name
QUANTITY: dict[str, Dimension] = {
    "dimensionless": DIMENSIONLESS,
    "mass": MASS,
    "length": LENGTH,
    "displacement": LENGTH,
    "time": TIME,
    "frequency": TIME**-1,
    "velocity": LENGTH / TIME,
    "acceleration": LENGTH / TIME**2,
    "force": MASS * LENGTH / TIME**2,
    "stiffness": MASS / TIME**2,  # N/m: storey and linear contact springs
    "hertz_stiffness": MASS * LENGTH ** Fraction(-1, 2) / TIME**2,  # N/m^1.5
    "damping_coefficient": MASS / TIME,  # N s/m
    "modulus": MASS / LENGTH / TIME**2,  # Pa: elastic modulus, stress
    "density": MASS / LENGTH**3,
    "energy": MASS * LENGTH**2 / TIME**2,
    "inertia": MASS * LENGTH**2,  # kg m^2: a floor's polar moment of inertia
}

#: unit symbols pframe's YAML uses, as dimensions (SI, so no conversion factors arise)
_UNIT = {
    "1": DIMENSIONLESS,
    "rad": DIMENSIONLESS,
    "kg": MASS,
    "t": MASS,  # accepted for reading only; pframe's files are in kg
    "m": LENGTH,
    "s": TIME,
    "Hz": TIME**-1,
    "N": QUANTITY["force"],
    "Pa": QUANTITY["modulus"],
    "J": QUANTITY["energy"],
}
_FACTOR = re.compile(r"\s*([A-Za-z1]+)(?:\^\(?([+-]?\d+(?:/\d+|\.\d+)?)\)?)?\s*")


def parse_units(text: str) -> Dimension:
    """The dimension of a unit string such as ``"N/m^1.5"``, ``"m/s^2"``, ``"kg m^-3"``.

    Factors are separated by spaces, ``*`` or ``/`` (everything after a ``/`` up to the next
    ``/`` divides); exponents follow ``^`` as integers, decimals or fractions (``m^(1/2)``).

    Raises
    ------
    ValueError
        For a unit symbol not in pframe's table (SI base and derived units only).
    """
    result = DIMENSIONLESS
    for i, group in enumerate(re.split(r"/(?![^(]*\))", text)):  # not the / of m^(1/2)
        for factor in filter(None, re.split(r"[\s*]+", group.strip())):
            match = _FACTOR.fullmatch(factor)
            if not match or match.group(1) not in _UNIT:
                raise ValueError(f"unknown unit {factor!r} in {text!r}; known: "
                                 f"{', '.join(_UNIT)}")
            dim = _UNIT[match.group(1)] ** Fraction(match.group(2) or 1)
            result = result / dim if i > 0 else result * dim
    return result
