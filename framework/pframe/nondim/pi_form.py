"""Scenes written in Pi numbers, expanded to dimensional scenes.

A Pi-form scene is recognised by its top-level ``pi:`` mapping. It describes the paper's
configuration (Wu et al. 2021, section 2): a left building ``a`` and a right building ``b``,
each with equal floor masses and equal storeys, contacts between floors of the same level,
and a sine ground motion ``a_p sin(w_p t)``. With the reference scales ``m_b``, ``a_p``,
``w_p`` (``scales:``, each 1 by default) and ``l_e = a_p / w_p^2``:

    m_a = Pi_m m_b                K_a = Pi_k m_b w_p^2        K_b = Pi_mu K_a
    u_ya = Pi_uya l_e             u_yb = Pi_uyb l_e           alpha = Pi_alpha
    xi = Pi_xi                    w_bar = Pi_wcon w_p         e = Pi_e        d = Pi_d l_e
    dt = dtau / w_p               duration = tau / w_p

(``K_b = Pi_mu K_a``: the paper-notes reading of the stiffness ratio, under which eq. 14 gives
the paper's 8 impacts per storey.) A building with ``Pi_uy`` is bilinear, one without it
elastic. :func:`expand_pi` returns the dimensional scene as YAML data, which is then
validated like any scene; the kernel never knows a scene came from Pi numbers.
"""

from __future__ import annotations

import copy
from typing import Literal

from pydantic import Field, create_model

from pframe.laws.params import Restitution
from pframe.model.load import ModelError
from pframe.model.scene import Analysis, Base, BuildingName, Envelope, History, Rayleigh

#: reference scale -> the quantity it is (for similitude)
SCALE_QUANTITY = {"m_b": "mass", "a_p": "acceleration", "w_p": "frequency"}


class PiNumbers(Base):
    """The Pi numbers of Wu et al. (2021), eqs. (11)-(14)."""

    Pi_m: float = Field(gt=0, allow_inf_nan=False, description="m_a / m_b: mass ratio.")
    Pi_k: float = Field(gt=0, allow_inf_nan=False,
                        description="K_a / (m_b w_p^2): storey stiffness of building a.")
    Pi_mu: float = Field(gt=0, allow_inf_nan=False, description="K_b / K_a: stiffness ratio.")
    Pi_uya: float | None = Field(None, gt=0, allow_inf_nan=False,
                                 description="u_ya w_p^2 / a_p: yield drift of a (omit: elastic).")
    Pi_uyb: float | None = Field(None, gt=0, allow_inf_nan=False,
                                 description="u_yb w_p^2 / a_p: yield drift of b (omit: elastic).")
    Pi_xi: float = Field(ge=0, lt=1, description="Rayleigh damping ratio of both buildings.")
    Pi_alpha: float | None = Field(None, ge=0, le=1,
                                   description="Post-yield stiffness ratio (with Pi_uya/Pi_uyb).")
    Pi_wcon: float | None = Field(None, gt=0, allow_inf_nan=False,
                                  description="w_bar / w_p: contact frequency ratio.")
    Pi_e: Restitution | None = Field(None, description="Coefficient of restitution e.")
    Pi_d: float | None = Field(None, ge=0, allow_inf_nan=False, description="d w_p^2 / a_p: gap.")


class PiBuilding(Base):
    """One of the two buildings: its name and number of floors (storeys)."""

    name: BuildingName = Field(description="Building name (node names are '<name>/<floor>').")
    floors: int = Field(ge=1, description="Number of floors (storeys).")


class PiBuildings(Base):
    """The left building a and the right building b (whose floor mass is m_b)."""

    a: PiBuilding
    b: PiBuilding


class PiContacts(Base):
    """Contacts between floors of the same level of a and b."""

    floors: list[int] | None = Field(
        None, description="Levels with a contact (default: every floor both buildings have).")
    law: Literal["improved_kelvin", "kelvin", "linear"] = Field(
        "improved_kelvin", description="Contact law (stiffness from Pi_wcon).")
    keep_tension: bool = Field(False, description="kelvin only: keep the tensile force.")


class Scales(Base):
    """Reference scales that make the scene dimensional (each 1 by default)."""

    m_b: float = Field(1.0, gt=0, allow_inf_nan=False, description="Floor mass of b (kg).")
    a_p: float = Field(1.0, gt=0, allow_inf_nan=False, description="Sine amplitude (m/s^2).")
    w_p: float = Field(1.0, gt=0, allow_inf_nan=False, description="Sine frequency (rad/s).")


class PiExcitation(Base):
    """The sine a_p sin(w_p t), optionally a pulse of some cycles."""

    cycles: float | None = Field(None, gt=0, allow_inf_nan=False,
                                 description="Number of cycles, then zero (default: unlimited).")


class PiOutput(Base):
    """Units of the result file."""

    units: Literal["SI", "dimensionless"] = Field(
        "dimensionless", description="dimensionless (tau, x = X / l_e, ...) or SI.")


def _without(model, drop: set, name: str, doc: str, **extra):
    """A copy of ``model`` without the fields ``drop`` and with ``extra`` fields; following
    the scene model keeps the Pi form in step with new analysis or damping options."""
    fields = {k: (info.annotation, info) for k, info in model.model_fields.items()
              if k not in drop}
    return create_model(name, __base__=Base, __doc__=doc, **extra, **fields)


PiAnalysis = _without(
    Analysis, {"dt", "duration"}, "PiAnalysis",
    "Time integration in dimensionless time tau = w_p t (newton.absolute_tolerance in units "
    "of l_e).",
    dt_tau=(float, Field(gt=0, allow_inf_nan=False, description="Step dtau = w_p dt.")),
    tau=(float, Field(gt=0, allow_inf_nan=False, description="Duration tau = w_p t_end.")))
PiDamping = _without(Rayleigh, {"ratio"}, "PiDamping",
                     "Rayleigh damping settings (the ratio is Pi_xi).")


class PiScene(Base):
    """A scene of two buildings written in the Pi numbers of Wu et al. (2021)."""

    title: str = Field("", description="A title copied into the result file.")
    pi: PiNumbers = Field(description="The Pi numbers.")
    buildings: PiBuildings = Field(description="Names and floor counts of buildings a and b.")
    contacts: PiContacts = Field(PiContacts(), description="Contact levels and law.")
    scales: Scales = Field(Scales(), description="Reference scales m_b, a_p, w_p.")
    excitation: PiExcitation = Field(PiExcitation(), description="Sine pulse length.")
    damping: PiDamping = Field(PiDamping(), description="Rayleigh modes and stiffness.")
    analysis: PiAnalysis = Field(description="Dimensionless time step and duration.")
    recorders: list[History | Envelope] | None = Field(
        None, description="As in a dimensional scene (default: the scene's default).")
    output: PiOutput = Field(PiOutput(), description="Units of the result file.")


def is_pi_form(data) -> bool:
    return isinstance(data, dict) and "pi" in data


def _check(pi: PiScene) -> list[int]:
    """Cross-field rules; returns the contact levels. Raises ModelError at the YAML path."""
    numbers, a, b = pi.pi, pi.buildings.a, pi.buildings.b
    if a.name == b.name:
        raise ModelError(("buildings", "b", "name"), f"buildings a and b are both {a.name!r}")
    common = min(a.floors, b.floors)
    floors = pi.contacts.floors if pi.contacts.floors is not None else list(range(1, common + 1))
    for i, level in enumerate(floors):
        if not 1 <= level <= common or level in floors[:i]:
            raise ModelError(("contacts", "floors", i), f"contact level {level} is not a floor "
                             f"both buildings have (1 .. {common}) or is listed twice")
    needs = {"Pi_wcon": bool(floors), "Pi_d": bool(floors),
             "Pi_e": bool(floors) and pi.contacts.law != "linear",
             "Pi_alpha": numbers.Pi_uya is not None or numbers.Pi_uyb is not None}
    for key, needed in needs.items():
        given = getattr(numbers, key) is not None
        if needed and not given:
            raise ModelError(("pi",), f"{key} is required for this scene")
        if given and not needed:
            why = {"Pi_alpha": "no building yields (no Pi_uya or Pi_uyb)",
                   "Pi_e": "linear contacts are undamped"}.get(key, "the scene has no contacts")
            raise ModelError(("pi", key), f"{key} does not apply: {why}")
    if pi.contacts.keep_tension and pi.contacts.law != "kelvin":
        raise ModelError(("contacts", "keep_tension"), "keep_tension applies to kelvin only")
    return floors


def expand_pi(pi: PiScene, raw: dict) -> dict:
    """The dimensional scene (YAML data) of a validated Pi-form scene.

    Parameters
    ----------
    pi : PiScene
        The validated Pi form.
    raw : dict
        The YAML data it was validated from; recorders and analysis options are copied from
        it as written.

    Raises
    ------
    ModelError
        For rules across fields (contact levels, Pi numbers a scene needs or cannot use).
    """
    floors = _check(pi)
    n, s = pi.pi, pi.scales
    length = s.a_p / s.w_p**2  # l_e, the excitation's length scale
    k_a = n.Pi_k * s.m_b * s.w_p**2
    masses = {"a": n.Pi_m * s.m_b, "b": s.m_b}
    stiffness = {"a": k_a, "b": n.Pi_mu * k_a}
    yields = {"a": n.Pi_uya, "b": n.Pi_uyb}
    buildings = []
    for key in ("a", "b"):
        building = getattr(pi.buildings, key)
        story = {"material": "elastic", "stiffness": stiffness[key]}
        if yields[key] is not None:
            story = {"material": "bilinear", "stiffness": stiffness[key],
                     "yield_drift": yields[key] * length, "alpha": n.Pi_alpha}
        buildings.append({"name": building.name, "floors": building.floors,
                          "mass": masses[key], "story": story})
    a, b = pi.buildings.a.name, pi.buildings.b.name
    contacts = []
    for level in floors:
        contact = {"name": f"floor-{level}", "nodes": [f"{a}/{level}", f"{b}/{level}"],
                   "gap": n.Pi_d * length, "law": pi.contacts.law, "frequency_ratio": n.Pi_wcon}
        if pi.contacts.law != "linear":
            contact["restitution"] = n.Pi_e
        if pi.contacts.keep_tension:
            contact["keep_tension"] = True
        contacts.append(contact)
    excitation = {"kind": "sine", "amplitude": s.a_p, "frequency": s.w_p}
    if pi.excitation.cycles is not None:
        excitation["cycles"] = pi.excitation.cycles
    analysis = {k: copy.deepcopy(v) for k, v in raw["analysis"].items()
                if k not in ("dt_tau", "tau")}
    if "absolute_tolerance" in analysis.get("newton", {}):
        analysis["newton"]["absolute_tolerance"] *= length
    analysis |= {"dt": pi.analysis.dt_tau / s.w_p, "duration": pi.analysis.tau / s.w_p}
    out = {"title": pi.title, "buildings": buildings, "contacts": contacts,
           "damping": {"ratio": n.Pi_xi, **copy.deepcopy(raw.get("damping") or {})},
           "excitation": excitation, "analysis": analysis}
    if pi.recorders is not None:
        out["recorders"] = copy.deepcopy(raw["recorders"])
    out["output"] = {"units": pi.output.units,
                     "scales": {"m_b": s.m_b, "a_p": s.a_p, "w_p": s.w_p}}
    return out


def expand_pi_data(data: dict, lines: dict, source: str) -> dict:
    """Validate Pi-form YAML data and expand it; errors name the file, line and field."""
    from pframe.errors import InputError
    from pframe.model.load import _where, validated

    pi = validated(PiScene, data, lines, source)
    try:
        return expand_pi(pi, data)
    except ModelError as exc:
        raise InputError(f"{_where(source, lines, exc.path)}: {exc.message}") from None
    except ArithmeticError:  # scales whose products leave floating point (w_p = 1e-200)
        raise InputError(f"{_where(source, lines, ('scales',) if 'scales' in data else ('pi',))}: "
                         "the Pi numbers and scales give dimensional values beyond floating "
                         "point arithmetic (a division by zero or an overflow); check them"
                         ) from None
