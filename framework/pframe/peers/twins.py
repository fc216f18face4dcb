"""The OpenSees twin of each law: the stock uniaxial material the script writes for it, made
from the law's packed parameters, and how the twin's model differs from the law, where it does.

A law has a twin here when OpenSees has a material whose equations are the law's, or the law's
but for conditions the twin names (its ``differences``: the script says them in its
docstring, ``pframe opensees`` and :func:`pframe.to_opensees` warn of them). A law without one
is refused with the reason (:data:`NO_TWIN`). The law declares the name of its twin
(``Law.opensees``); ``tests/test_opensees_twins.py`` holds the two lists together.

The twins were read in OpenSees' sources (OpenSees 3.7.1, ``SRC/material/uniaxial``):

* ``Hertzdamp`` (Hughes, after Muthukumar & DesRoches 2006 and Ye, Li & Zhu 2009):
  ``F = (K_h + xi delta') delta^n`` while closed, ``xi = xi_norm K_h / v0`` with ``v0`` the
  rate at the onset trial (a trial closing the gap after a committed open one): pframe's
  Hunt-Crossley family ``k delta^n (1 + chi delta' / v0)`` with ``xi_norm = chi``, the same
  ``v0`` (the rate at the end of the onset step) and, in the onset step, the same force
  ``k (1 + chi) delta^n``;
* ``JankowskiImpact``: ``beta delta^1.5 + 2 xi sqrt(beta delta^(1/2) m_eff) delta'`` while
  approaching, ``beta delta^1.5`` in restitution: Jankowski's law (``xi = zeta``) itself;
* ``Viscous``: ``C |v|^alpha sign v`` at every speed (``minVel`` caps only its damping tangent);
* ``Steel01`` with ``b = 0`` for a friction pendulum's Coulomb friction (elastic-perfectly
  plastic at ``mu W``, initial stiffness ``k_init - W / R``) in parallel with ``Elastic``
  ``W / R``: pframe's ``friction_pendulum`` with a constant ``mu``.
"""

from __future__ import annotations

from dataclasses import dataclass

#: the Hunt-Crossley family as OpenSees' Hertzdamp has it, and where pframe's law is another
HUNT_CROSSLEY_DIFFERENCES = (
    "{law}: OpenSees' Hertzdamp has no energy-velocity floor: where a contact closes slower "
    "than the elastic energy it holds would give (a grazing or lasting contact, "
    "docs/restitution.md), pframe damps it less than OpenSees",
    "{law}: OpenSees' Hertzdamp pulls when its damping outweighs its spring in rebound "
    "(1 + chi delta' / v0 < 0), where pframe's force stays at 0",
    "{law}: OpenSees' Hertzdamp loses its damping for the rest of a contact when a Newton "
    "trial of a step opens it and a later trial of that step closes it again",
)
#: pframe's dashpot below linear_below, where OpenSees' Viscous keeps the power law
DASHPOT_DIFFERENCE = (
    "{law}: below linear_below pframe's dashpot is linear, c v0^(alpha - 1) v, where OpenSees' "
    "Viscous keeps c |v|^alpha: their forces differ there by up to c v0^alpha")

#: laws OpenSees has no twin of, and why
NO_TWIN = {
    "kelvin": "OpenSees has no uniaxial material of a spring and dashpot that act only while a "
              "gap is closed (a Parallel of ElasticPPGap and Viscous would damp the open gap)",
    "friction_pendulum": "OpenSees' velocity-dependent friction (flatSliderBearing, "
                         "singleFPBearing) is an element's, which needs an axial load on a "
                         "vertical degree of freedom the script's model does not have; a "
                         "constant mu (Coulomb friction) is written",
}


@dataclass(frozen=True)
class Twin:
    """A law's OpenSees twin in one scene.

    Attributes
    ----------
    material : tuple
        The script's material: its kind, then its numbers (the script's ``material`` or
        ``contact_material`` writes it).
    differences : tuple of str
        Where OpenSees' model is not the law's (empty: the same model).
    """

    material: tuple
    differences: tuple = ()


class NoTwin(ValueError):
    """A law (or its parameters) OpenSees has no twin of; the message says why."""


def _floats(values) -> tuple:
    return tuple(float(v) for v in values)


def _dashpot(law: str, alpha: float) -> tuple:
    return () if alpha == 1.0 else (DASHPOT_DIFFERENCE.format(law=law),)


def _bwbn(p) -> Twin:
    if tuple(p[5:9]) != (1.0, 0.0, 0.0, 0.0):
        # OpenSees' BWBN has pinching only: no A, nu or eta degradation, z_u with A = 1
        raise NoTwin("OpenSees' BWBN has no strength or stiffness degradation: its bwbn "
                     "storeys need Ao = 1 and deltaA = deltaNu = deltaEta = 0")
    # OpenSees' 12 numbers, then the tolerance and the iterations
    return Twin(("bwbn", *_floats(p[:6]), *_floats(p[9:16]), int(p[16])))


def _friction_pendulum(p) -> Twin:
    weight, inverse_radius, k_init, slow, fast, rate = (float(v) for v in p)
    if slow != fast and rate != 0.0:
        raise NoTwin(NO_TWIN["friction_pendulum"])
    k2 = weight * inverse_radius
    return Twin(("coulomb_pendulum", k_init - k2, fast * weight, k2))


#: storey and link laws: packed parameters -> their twin
MATERIALS = {
    "elastic": lambda p: Twin(("elastic", float(p[0]))),
    "bilinear": lambda p: Twin(("bilinear", *_floats(p[:3]))),
    # the 9 parameters, the tolerance, the iterations
    "bouc_wen": lambda p: Twin(("bouc_wen", *_floats(p[:10]), int(p[10]))),
    "imk_peak": lambda p: Twin(("imk_peak", *_floats(p))),  # ModIMKPeakOriented's 23
    "bwbn": _bwbn,
    "viscous": lambda p: Twin(("viscous", *_floats(p[:2])), _dashpot("viscous", p[1])),
    "kelvin_voigt": lambda p: Twin(("kelvin_voigt", *_floats(p[:3])),
                                   _dashpot("kelvin_voigt", p[2])),
    "friction_pendulum": _friction_pendulum,
}


def _hunt_crossley(law: str):
    def twin(p) -> Twin:  # (k, n, chi, 1 / m_eff): Hertzdamp(k, chi, gap, n)
        return Twin(("hertzdamp", float(p[0]), float(p[2]), float(p[1])),
                    tuple(text.format(law=law) for text in HUNT_CROSSLEY_DIFFERENCES)
                    if p[2] != 0.0 else ())
    return twin


def _bumper(p) -> Twin:
    """A Hertzdamp for the rubber and one for the hard contact behind it, in parallel."""
    k, n, chi, _, hard, depth = (float(v) for v in p)
    return Twin(("bumper", k, chi, n, hard, depth), (
        *(text.format(law="bumper") for text in HUNT_CROSSLEY_DIFFERENCES),
        "bumper: OpenSees' hard stage is a Hertzdamp of its own, whose damping is scaled by "
        "the closing rate when the rubber is crushed, where pframe's scales both stages by "
        "the rate at onset: once crushed, OpenSees damps the hard stage more"))


#: contact laws: packed parameters -> their twin (the gap is the contact's)
CONTACTS = {
    "linear": lambda p: Twin(("linear", float(p[0]))),
    "hertz": lambda p: Twin(("hertzdamp", float(p[0]), 0.0, 1.5)),
    "improved_kelvin": _hunt_crossley("improved_kelvin"),
    "hertzdamp": _hunt_crossley("hertzdamp"),
    "hunt_crossley": _hunt_crossley("hunt_crossley"),
    "jankowski": lambda p: Twin(("jankowski", *_floats(p[:3]))),  # beta, zeta, m_eff
    "bumper": _bumper,
}

#: the OpenSees material(s) each kind of twin is written with: the laws' ``opensees``
OPENSEES_NAMES = {
    "elastic": "Elastic", "bilinear": "Steel01", "bouc_wen": "BoucWen",
    "imk_peak": "ModIMKPeakOriented", "bwbn": "BWBN", "viscous": "Viscous",
    "kelvin_voigt": "Parallel(Elastic, Viscous)",
    "coulomb_pendulum": "Parallel(Steel01, Elastic)", "linear": "ElasticPPGap",
    "hertzdamp": "Hertzdamp", "jankowski": "JankowskiImpact",
    "bumper": "Parallel(Hertzdamp, Hertzdamp)",
}


def twin(kind: str, law, packed) -> Twin:
    """The twin of ``law`` (a material, ``kind`` "material", or a contact law) with the packed
    parameters ``packed``; raises :class:`NoTwin` saying why there is none."""
    table = MATERIALS if kind == "material" else CONTACTS
    make = table.get(law.name)
    if make is None or law.opensees is None:
        raise NoTwin(NO_TWIN.get(law.name) or f"{law.name!r} has no OpenSees counterpart in "
                     "pframe's script (a law without a stock OpenSees material of its "
                     "equations)")
    return make(packed)
