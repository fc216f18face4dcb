"""The unit systems a scene may be written in (``units:``, docs/units.md): pure data.

Each system is *consistent*: its force unit is its mass unit times its length unit per second
squared, so F = m a, k = F / u and every equation of the kernel hold in it as written. Time is
in seconds in every system. A scene is converted to SI (N, m, kg, s) when it is read and its
results are converted back when they are written (:class:`pframe.nondim.output.OutputUnits`):
the kernel always integrates in SI, so a scene in kN-m-t gives the SI scene's physics to
round-off.

The factors are exact rationals (``Fraction``): one inch is 0.0254 m and one pound-force
4.4482216152605 N by definition (NIST SP 811, appendix B), so a number is converted with one
rounding. The symbols are UDUNITS-2's (a result file's ``units`` attributes): ``t`` is the
tonne, ``kip`` 1000 lbf, ``in`` the inch.
"""

from __future__ import annotations

import functools
from dataclasses import dataclass
from fractions import Fraction

#: one inch in metres and one pound-force in newtons, exactly (NIST SP 811, appendix B)
INCH = Fraction("0.0254")
POUND_FORCE = Fraction("4.4482216152605")
#: standard gravity, m/s^2 (CGPM 1901; NIST SP 811): what "in g" means (PEER records, a PGA)
STANDARD_GRAVITY = 9.80665


@dataclass(frozen=True)
class UnitSystem:
    """A consistent set of units: ``force``, ``length`` and ``mass`` symbols (UDUNITS), and
    how many kilograms and metres one mass and one length unit are."""

    name: str
    force: str
    length: str
    mass: str
    kilograms: Fraction
    metres: Fraction
    #: a mass written with its own symbol (kg, t), or as force s^2 / length (kip s^2/in)
    named_mass: bool = True

    @property
    def si(self) -> bool:
        return self.kilograms == 1 and self.metres == 1

    @property
    def newtons(self) -> Fraction:
        """One force unit in newtons: mass unit x length unit / s^2 (consistency)."""
        return self.kilograms * self.metres

    def factor(self, mass, length, time=0) -> float:
        """The SI value of one unit of dimension ``M^mass L^length T^time`` of this system
        (time is in seconds in every system, so ``time`` does not matter): exact, rounded
        once, for integer exponents; a power of the exact factors for fractional ones (a
        Hertz stiffness, N/m^1.5)."""
        return _factor(self.kilograms, self.metres, Fraction(mass), Fraction(length))

    def symbol(self, mass, length, time) -> str:
        """The unit of dimension ``M^mass L^length T^time`` in this system, UDUNITS-2
        syntax: a mass (and a density, an inertia) in the mass unit where it has a name,
        anything with time in it through the force unit (``kN/m``, ``kN s/m``, ``kN m``)."""
        mass, length, time = Fraction(mass), Fraction(length), Fraction(time)
        if mass and (time or not self.named_mass):  # M = F L^-1 s^2
            factors = [(self.force, mass), (self.length, length - mass), ("s", time + 2 * mass)]
        else:
            factors = [(self.mass, mass), (self.length, length), ("s", time)]
        top = [_power(s, x) for s, x in factors if x > 0]
        bottom = [_power(s, -x) for s, x in factors if x < 0]
        text = " ".join(top) or "1"
        return text + "".join(f"/{b}" for b in bottom)


@functools.lru_cache(maxsize=256)  # every number of a scene asks for one of a few
def _factor(kilograms: Fraction, metres: Fraction, mass: Fraction, length: Fraction) -> float:
    if mass.denominator == 1 and length.denominator == 1:
        return float(kilograms ** int(mass) * metres ** int(length))
    return float(kilograms) ** float(mass) * float(metres) ** float(length)


def _power(symbol: str, exponent: Fraction) -> str:
    if exponent == 1:
        return symbol
    return f"{symbol}^{exponent.numerator}" if exponent.denominator == 1 else \
        f"{symbol}^{float(exponent):g}"


#: the unit systems, by the name a scene gives (force-length-mass, or force-length-time
#: where the mass unit has no name of its own); the first is the default
SYSTEMS: dict[str, UnitSystem] = {s.name: s for s in (
    UnitSystem("N-m-kg", "N", "m", "kg", Fraction(1), Fraction(1)),
    UnitSystem("kN-m-t", "kN", "m", "t", Fraction(1000), Fraction(1)),
    UnitSystem("N-mm-t", "N", "mm", "t", Fraction(1000), Fraction(1, 1000)),
    UnitSystem("kip-in-s", "kip", "in", "kip s^2/in", 1000 * POUND_FORCE / INCH, INCH,
               named_mass=False),
    UnitSystem("lbf-in-s", "lbf", "in", "lbf s^2/in", POUND_FORCE / INCH, INCH,
               named_mass=False),
)}
SI = SYSTEMS["N-m-kg"]
#: the names a scene's ``units`` accepts, the default first
NAMES = tuple(SYSTEMS)


def describe(system: UnitSystem) -> str:
    """``force kN, length m, mass t (1000 kg), time s`` -- the file's ``units_system_description``."""
    mass = system.mass if system.named_mass else f"{system.mass} ({float(system.kilograms):.12g} kg)"
    if system.named_mass and system.kilograms != 1:
        mass += f" ({float(system.kilograms):g} kg)"
    return f"force {system.force}, length {system.length}, mass {mass}, time s"
