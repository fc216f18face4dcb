"""Scenes written in Pi numbers, expanded to dimensional scenes.

A Pi-form scene is recognised by its top-level ``pi:`` mapping. It describes a row of shear
buildings ``a``, ``b``, ``c``, ... (left to right), each with equal floor masses and equal
storeys (elastic, or bilinear when it has a yield drift), contacts of one built-in law between
floors of the same level of neighbouring buildings, and a sine or a recorded ground motion.
The reference scales are the floor mass ``m_b`` of the reference building (``reference:``,
default ``b``, or ``a`` alone) and the excitation's characteristic amplitude ``a_p`` and
circular frequency ``w_p`` (:func:`pframe.excitation.characteristic.characteristic`).

The Pi numbers are the groups ``pframe pi`` finds for the scene, by the same code: the
structure of the scene (buildings, storey laws, contacts, excitation) is laid out with
placeholder numbers, :func:`pframe.nondim.scene_variables.scene_variables` lists its governing
variables and :func:`pframe.nondim.scene_pi.paper_groups` gives their groups (Buckingham, on
the repeating variables ``m_b, a_p, w_p``, named as in Wu et al. 2021). Each group then fixes
its variable: ``Pi_q = q prod R^x`` gives ``q = Pi_q / prod R^x``, evaluated as ``Pi_q`` times
``m_b^a l_e^b w_p^-c`` for the dimension ``M^a L^b T^c`` of what is left once the other
(non-repeating) variables of the group are known, ``l_e = a_p / w_p^2``. For two buildings
under a sine this is the paper's expansion:

    m_a = Pi_m m_b                K_a = Pi_k m_b w_p^2        K_b = Pi_mu K_a
    u_ya = Pi_uya l_e             u_yb = Pi_uyb l_e           alpha = Pi_alpha
    xi = Pi_xi                    w_bar = Pi_wcon w_p         e = Pi_e        d = Pi_d l_e
    dt = dtau / w_p               duration = tau / w_p

and a Hertz-type contact gets ``k_h = Pi_kh m_b w_p^2 / l_e^(1/2)``. Expanding a Pi-form scene
and taking the groups of the result (``pframe pi``) returns the numbers written. The kernel
never knows a scene came from Pi numbers.
"""

from __future__ import annotations

import copy
import math
from dataclasses import dataclass
from pathlib import Path
from typing import Annotated, Literal, Union

from pydantic import ConfigDict, Discriminator, Field, Tag, create_model

from pframe.errors import InputError
from pframe.laws import get_law
from pframe.laws.params import Restitution
from pframe.laws.registry import builtin_names
from pframe.model.load import ModelError
from pframe.model.scene import (
    Analysis,
    Base,
    BuildingName,
    Envelope,
    History,
    Rayleigh,
    tag_reader,
)

#: reference scale -> the quantity it is (for similitude)
SCALE_QUANTITY = {"m_b": "mass", "a_p": "acceleration", "w_p": "frequency"}

_POSITIVE = Annotated[float, Field(gt=0, allow_inf_nan=False)]
_PI_NAME = r"^Pi_[A-Za-z0-9_]+$"


class PiNumbers(Base):
    """The Pi numbers: the groups ``pframe pi`` lists for the scene, by name. The paper's
    (Wu et al. 2021, eqs. 11-14) are listed; a scene of more buildings adds ``Pi_m<tag>``
    (``m / m_b`` of each building but the reference one when there are several), ``Pi_mu<tag>``
    (``K / K_a`` of each building after a) and ``Pi_uy<tag>``."""

    model_config = ConfigDict(
        extra="allow", frozen=True,
        json_schema_extra={"patternProperties": {_PI_NAME: {"type": "number",
                                                            "exclusiveMinimum": 0}},
                           "additionalProperties": False})
    __pydantic_extra__: dict[str, _POSITIVE]

    Pi_m: float | None = Field(None, gt=0, allow_inf_nan=False,
                               description="m_a / m_b: mass ratio (two buildings).")
    Pi_k: float | None = Field(None, gt=0, allow_inf_nan=False,
                               description="K_a / (m_b w_p^2): storey stiffness of building a.")
    Pi_mu: float | None = Field(None, gt=0, allow_inf_nan=False,
                                description="K_b / K_a: stiffness ratio (two buildings).")
    Pi_uya: float | None = Field(None, gt=0, allow_inf_nan=False,
                                 description="u_ya w_p^2 / a_p: yield drift of a (omit: elastic).")
    Pi_uyb: float | None = Field(None, gt=0, allow_inf_nan=False,
                                 description="u_yb w_p^2 / a_p: yield drift of b (omit: elastic).")
    Pi_xi: float | None = Field(None, ge=0, lt=1,
                                description="Rayleigh damping ratio of every building.")
    Pi_alpha: float | None = Field(None, ge=0, le=1,
                                   description="Post-yield stiffness ratio (with a Pi_uy).")
    Pi_wcon: float | None = Field(None, gt=0, allow_inf_nan=False,
                                  description="w_bar / w_p: contact frequency ratio (linear, "
                                  "kelvin, improved_kelvin).")
    Pi_kh: float | None = Field(None, gt=0, allow_inf_nan=False,
                                description="k_h a_p^(1/2) / (m_b w_p^3) = k_h l_e^(1/2) / (m_b "
                                "w_p^2): Hertz stiffness (hertz, hertzdamp, jankowski).")
    Pi_e: Restitution | None = Field(None, description="Coefficient of restitution e.")
    Pi_d: float | None = Field(None, ge=0, allow_inf_nan=False, description="d w_p^2 / a_p: gap.")

    def given(self) -> dict[str, float]:
        """Every Pi number written, by name."""
        out = {k: v for k, v in self.model_dump().items() if v is not None}
        return out


class PiBuilding(Base):
    """One building of the row: its name and number of floors (storeys)."""

    name: BuildingName = Field(description="Building name (node names are '<name>/<floor>').")
    floors: int = Field(ge=1, description="Number of floors (storeys).")


_TAG = Annotated[str, Field(pattern=r"^[a-z]$")]
_PAIR = Annotated[str, Field(pattern=r"^[a-z]-[a-z]$")]
CONTACT_LAWS = tuple(sorted(builtin_names("contact")))


class PiContacts(Base):
    """Contacts between floors of the same level of neighbouring buildings, one law for all."""

    floors: list[int] | dict[_PAIR, list[int]] | None = Field(
        None, description="Levels with a contact: one list for every neighbouring pair, or one "
        "per pair ('a-b': [...]; a pair not listed has none). Default: every floor both "
        "buildings of a pair have.")
    law: Literal[CONTACT_LAWS] = Field(
        "improved_kelvin", description="Contact law: linear, kelvin and improved_kelvin take "
        "Pi_wcon; hertz, hertzdamp and jankowski take Pi_kh.")
    keep_tension: bool = Field(False, description="kelvin only: keep the tensile force.")
    formula: Literal["muthukumar", "ye"] | None = Field(
        None, description="hertzdamp only: the published damping formula.")
    calibration: Literal["published", "exact"] | None = Field(
        None, description="Damped laws: published damping formula or exact restitution "
        "(default: the law's).")


class Scales(Base):
    """Reference scales that make the scene dimensional."""

    m_b: float = Field(1.0, gt=0, allow_inf_nan=False,
                       description="Floor mass of the reference building (kg); default 1.")
    a_p: float | None = Field(None, gt=0, allow_inf_nan=False,
                              description="Excitation amplitude (m/s^2): the sine's, or the PGA "
                              "the record is scaled to; default 1 for a sine, the record's own.")
    w_p: float | None = Field(None, gt=0, allow_inf_nan=False,
                              description="Excitation circular frequency (rad/s): the sine's, or "
                              "2 pi / T of the record, its time axis scaled to it; default 1 "
                              "for a sine, the record's own.")


class PiSine(Base):
    """The sine a_p sin(w_p t), optionally a pulse of some cycles."""

    kind: Literal["sine"] = "sine"
    cycles: float | None = Field(None, gt=0, allow_inf_nan=False,
                                 description="Number of cycles, then zero (default: unlimited).")


class PiRecord(Base):
    """A recorded ground motion, scaled to PGA a_p and to characteristic frequency w_p."""

    kind: Literal["record"]
    file: str = Field(description="Two columns (time s, acceleration) or a PEER NGA .AT2 file "
                      "(path relative to the scene file).")
    format: Literal["auto", "columns", "at2"] = Field(
        "auto", description="File format; auto: .AT2 suffix for PEER, else two columns.")
    units: Literal["m/s2", "g"] | None = Field(
        None, description="Acceleration units of the file (default: g for .AT2, m/s2 otherwise).")
    period: Literal["mean", "predominant"] | _POSITIVE = Field(
        "mean", description="The record's characteristic period T, which sets w_p = 2 pi / T of "
        "its Pi groups and dimensionless output: mean (the mean period T_m of Rathje et al. "
        "1998, 2004, over 0.25-20 Hz), predominant (the period T_p of the peak of the 5%-damped "
        "acceleration spectrum) or a period in seconds of the record as in its file.")


class PiCycloidal(Base):
    """A cycloidal pulse of amplitude a_p and period T_p = 2 pi / w_p (docs/gap-audit.md)."""

    kind: Literal["cycloidal"]
    type: Literal["A", "B", "C"] = Field(description="A (forward), B (forward and back) or "
                                         "C (n main cycles).")
    n: int = Field(1, ge=1, description="Main cycles of a type-C pulse (C_n); only for type C.")


class PiRicker(Base):
    """The Ricker wavelet of amplitude a_p and period T_p = 2 pi / w_p (docs/gap-audit.md)."""

    kind: Literal["ricker"]
    center: _POSITIVE | None = Field(None, description="Time of the central peak in pulse "
                                     "periods, t_0 / T_p (default 1.5).")


_excitation_kind = tag_reader("kind", "sine")


PiExcitation = Annotated[
    Union[Annotated[PiSine, Tag("sine")], Annotated[PiRecord, Tag("record")],  # noqa: UP007
          Annotated[PiCycloidal, Tag("cycloidal")], Annotated[PiRicker, Tag("ricker")]],
    Discriminator(_excitation_kind),
]


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
    """A row of shear buildings written in Pi numbers (Wu et al. 2021, generalised)."""

    title: str = Field("", description="A title copied into the result file.")
    pi: PiNumbers = Field(description="The Pi numbers.")
    buildings: dict[_TAG, PiBuilding] = Field(
        min_length=1, description="The buildings from left to right, tagged a, b, c, ...")
    reference: _TAG | None = Field(
        None, description="Tag of the building whose floor mass is m_b (default: b, or a alone).")
    contacts: PiContacts = Field(PiContacts(), description="Contact levels and law.")
    scales: Scales = Field(Scales(), description="Reference scales m_b, a_p, w_p.")
    excitation: PiExcitation = Field(
        PiSine(), description="Sine (default), record, or pulse (cycloidal, ricker).")
    damping: PiDamping = Field(PiDamping(), description="Rayleigh modes and stiffness.")
    analysis: PiAnalysis = Field(description="Dimensionless time step and duration.")
    recorders: list[History | Envelope] | None = Field(
        None, description="As in a dimensional scene (default: the scene's default).")
    output: PiOutput = Field(PiOutput(), description="Units of the result file.")


def is_pi_form(data) -> bool:
    return isinstance(data, dict) and "pi" in data


# ---------------------------------------------------------------------------------------------
# the layout: what does not depend on the numbers
# ---------------------------------------------------------------------------------------------

class _Problems(Exception):
    """Every problem found, each at its path of the Pi-form data."""

    def __init__(self, problems: list[tuple[tuple, str]]):
        super().__init__("; ".join(m for _, m in problems))
        self.problems = problems


def _reference(pi: PiScene) -> str:
    tags = list(pi.buildings)
    return pi.reference or ("b" if len(tags) > 1 else "a")


def _pairs_and_levels(pi: PiScene, problems: list) -> list[tuple[str, str, list[int]]]:
    """(left tag, right tag, levels) of every neighbouring pair with contacts."""
    tags = list(pi.buildings)
    pairs = list(zip(tags, tags[1:]))
    floors = pi.contacts.floors
    if isinstance(floors, dict):
        known = {f"{a}-{b}" for a, b in pairs}
        for key in floors:
            if key not in known:
                problems.append((("contacts", "floors", key), f"{key} is not a pair of "
                                 f"neighbouring buildings; the pairs are {', '.join(known) or 'none'}"))
    out = []
    for a, b in pairs:
        common = min(pi.buildings[a].floors, pi.buildings[b].floors)
        if floors is None:
            levels, path = list(range(1, common + 1)), None
        elif isinstance(floors, dict):
            levels, path = floors.get(f"{a}-{b}", []), ("contacts", "floors", f"{a}-{b}")
        else:
            levels, path = floors, ("contacts", "floors")
        good = []  # the others are reported, and left out so that every problem is found
        for i, level in enumerate(levels):
            if not 1 <= level <= common or level in levels[:i]:
                which = "both buildings have" if len(pairs) == 1 else f"both {a} and {b} have"
                problems.append((path + (i,), f"contact level {level} is not a floor {which} "
                                 f"(1 .. {common}) or is listed twice"))
            else:
                good.append(level)
        if good:
            out.append((a, b, good))
    return out


def _contact_options(pi: PiScene, problems: list) -> dict:
    """The law options written (keep_tension, formula, calibration), checked against the law."""
    c = pi.contacts
    options = {k: v for k, v in (("keep_tension", c.keep_tension), ("formula", c.formula),
                                 ("calibration", c.calibration)) if v not in (None, False)}
    fields = get_law("contact", c.law).Params.model_fields
    for key in options:
        if key not in fields:
            users = [law for law in CONTACT_LAWS
                     if key in get_law("contact", law).Params.model_fields]
            problems.append((("contacts", key), f"{key} does not apply to {c.law} contacts "
                             f"(it applies to {', '.join(users)})"))
    return {k: v for k, v in options.items() if k in fields}


@dataclass(frozen=True)
class _Layout:
    """The Pi-form scene's structure, checked."""

    tags: tuple[str, ...]
    reference: str
    contacts: tuple[tuple[str, str, list[int]], ...]
    options: dict
    yielding: tuple[str, ...]  # tags of bilinear buildings


def _layout(pi: PiScene, problems: list) -> _Layout:
    """The structure of the scene; problems are added to ``problems``, and raised at once
    when the scene cannot be laid out (tags, names, reference)."""
    tags = list(pi.buildings)
    expected = [chr(ord("a") + i) for i in range(len(tags))]
    if tags != expected:
        problems.append((("buildings",), f"the buildings are tagged {', '.join(expected)} in "
                         f"order from the left; got {', '.join(tags)}"))
    names: dict = {}
    for tag, building in pi.buildings.items():
        if building.name in names:
            problems.append((("buildings", tag, "name"), f"buildings {names[building.name]} and "
                             f"{tag} are both {building.name!r}"))
        names.setdefault(building.name, tag)
    reference = _reference(pi)
    if reference not in pi.buildings:
        problems.append((("reference",), f"no building {reference!r}; the buildings are "
                         f"{', '.join(tags)}"))
    if problems:
        raise _Problems(problems)
    contacts = _pairs_and_levels(pi, problems)
    options = _contact_options(pi, problems)
    given = pi.pi.given()
    yielding = tuple(t for t in tags if f"Pi_uy{t}" in given)
    return _Layout(tuple(tags), reference, tuple(contacts), options, yielding)


# ---------------------------------------------------------------------------------------------
# the dimensional scene for given variable values
# ---------------------------------------------------------------------------------------------

_PLACEHOLDER = {"m": 1.0, "K": 1.0, "u_y": 1.0, "alpha": 0.1, "xi": 0.05, "w_bar": 1.0,
                "k_h": 1.0, "e": 0.5, "d": 0.0}


def _contact_numbers(law: str) -> tuple[str, ...]:
    """The variable roots a built-in contact law has (as scene_variables lists them)."""
    fields = get_law("contact", law).Params.model_fields
    roots = ("w_bar",) if "frequency_ratio" in fields else ("k_h",)
    return roots + (("e",) if "restitution" in fields else ()) + ("d",)


def _scene(pi: PiScene, raw: dict, layout: _Layout, value, scales: dict,
           excitation: dict) -> dict:
    """The dimensional scene (YAML data); ``value(root, tag)`` gives each number."""
    buildings = []
    for tag in layout.tags:
        building = pi.buildings[tag]
        story = {"material": "elastic", "stiffness": value("K", tag)}
        if tag in layout.yielding:
            story = {"material": "bilinear", "stiffness": value("K", tag),
                     "yield_drift": value("u_y", tag), "alpha": value("alpha", "")}
        buildings.append({"name": building.name, "floors": building.floors,
                          "mass": value("m", tag), "story": story})
    law = pi.contacts.law
    roots = _contact_numbers(law)
    contacts = []
    for left, right, levels in layout.contacts:
        a, b = pi.buildings[left].name, pi.buildings[right].name
        for level in levels:
            name = f"floor-{level}" if len(layout.tags) == 2 else f"{a}/{level}-{b}/{level}"
            contact = {"name": name, "nodes": [f"{a}/{level}", f"{b}/{level}"],
                       "gap": value("d", ""), "law": law}
            if "w_bar" in roots and pi.excitation.kind == "sine":
                contact["frequency_ratio"] = value("w_bar", "")  # Pi_wcon itself
            elif "w_bar" in roots:  # frequency_ratio is a sine's
                contact["frequency"] = value("w_bar", "")
            else:
                contact["stiffness"] = value("k_h", "")
            if "e" in roots:
                contact["restitution"] = value("e", "")
            contact |= layout.options
            contacts.append(contact)
    analysis = {k: copy.deepcopy(v) for k, v in raw["analysis"].items()
                if k not in ("dt_tau", "tau")}
    length = scales["a_p"] / scales["w_p"] ** 2
    if "absolute_tolerance" in analysis.get("newton", {}):
        analysis["newton"]["absolute_tolerance"] *= length
    analysis |= {"dt": pi.analysis.dt_tau / scales["w_p"],
                 "duration": pi.analysis.tau / scales["w_p"]}
    out = {"title": pi.title, "buildings": buildings, "contacts": contacts,
           "damping": {"ratio": value("xi", ""), **copy.deepcopy(raw.get("damping") or {})},
           "excitation": excitation, "analysis": analysis}
    if pi.recorders is not None:
        out["recorders"] = copy.deepcopy(raw["recorders"])
    out["output"] = {"units": pi.output.units, "scales": dict(scales)}
    if layout.reference != ("b" if len(layout.tags) > 1 else "a"):
        out["output"]["reference"] = pi.buildings[layout.reference].name
    return out


def _excitation(pi: PiScene, scales: dict | None) -> dict:
    """The dimensional excitation; ``scales`` None for the record as in its file."""
    e = pi.excitation
    if e.kind == "sine":
        out = {"kind": "sine", "amplitude": scales["a_p"], "frequency": scales["w_p"]}
        if e.cycles is not None:
            out["cycles"] = e.cycles
        return out
    if e.kind in ("cycloidal", "ricker"):  # a pulse: amplitude a_p, period T_p = 2 pi / w_p
        period = 2.0 * math.pi / scales["w_p"]
        out = {"kind": e.kind, "amplitude": scales["a_p"], "period": period}
        if e.kind == "cycloidal":
            out |= {"type": e.type} | ({"n": e.n} if e.type == "C" else {})
        elif e.center is not None:
            out["center"] = e.center * period
        return out
    out = {"kind": "record", "file": e.file}
    if e.format != "auto":
        out["format"] = e.format
    if e.units is not None:
        out["units"] = e.units
    out["period"] = e.period
    if scales is not None:
        out |= {"pga": scales["a_p"], "frequency": scales["w_p"]}
    return out


# ---------------------------------------------------------------------------------------------
# expansion
# ---------------------------------------------------------------------------------------------

@dataclass(frozen=True)
class Expansion:
    """A Pi-form scene expanded: the dimensional scene, the groups it was built from, and the
    reference scales with what ``a_p`` and ``w_p`` are."""

    data: dict
    groups: tuple
    scales: dict
    excitation: object  # pframe.excitation.characteristic.Characteristic


def _probe(pi: PiScene, raw: dict, layout: _Layout, base_dir, source: str):
    """The scene laid out with placeholder numbers and analysed as ``pframe pi`` does: its
    variables, roles, groups and the excitation's characteristic (record as in its file)."""
    from pframe.excitation.characteristic import characteristic
    from pframe.model.expand import expand
    from pframe.model.load import validated
    from pframe.model.scene import scene_class
    from pframe.nondim.scene_pi import default_repeating, paper_groups
    from pframe.nondim.scene_variables import scene_variables

    given = pi.pi.given()
    sine = {"a_p": pi.scales.a_p or 1.0, "w_p": pi.scales.w_p or 1.0}
    probe_scales = {"m_b": 1.0, **sine}

    def placeholder(root, tag):
        if root in ("alpha", "xi") and f"Pi_{root}" in given:
            return given[f"Pi_{root}"]
        return _PLACEHOLDER[root]

    data = _scene(pi, {**raw, "recorders": None}, layout, placeholder, probe_scales,
                  _excitation(pi, None if pi.excitation.kind == "record" else probe_scales))
    data["analysis"] |= {"dt": 1.0, "duration": 1.0}
    data["output"] = {k: v for k, v in data["output"].items() if k == "reference"}
    data.pop("recorders", None)
    scene = validated(scene_class(), data, {}, source)
    try:
        expanded = expand(scene, base_dir)
    except ModelError as exc:
        raise _Problems([(exc.path, exc.message)]) from None
    variables, roles = scene_variables(scene, expanded)
    repeating = default_repeating(variables, roles, expanded)
    groups = paper_groups(variables, roles, repeating)
    return variables, roles, repeating, groups, characteristic(scene.excitation, expanded.record)


def _why_not(name: str, pi: PiScene, layout: _Layout) -> str:
    """Why a Pi number is not one of the scene's groups."""
    law = pi.contacts.law
    reasons = {
        "Pi_e": f"{law} contacts have no restitution" if layout.contacts
        else "the scene has no contacts",
        "Pi_wcon": f"{law} contacts take Pi_kh (N/m^1.5)" if layout.contacts
        else "the scene has no contacts",
        "Pi_kh": f"{law} contacts take Pi_wcon" if layout.contacts else "the scene has no contacts",
        "Pi_d": "the scene has no contacts",
        "Pi_alpha": "no building yields (no Pi_uy" + "/".join(layout.tags) + ")",
    }
    return f"{name} does not apply: {reasons[name]}" if name in reasons else None


def expand_pi(pi: PiScene, raw: dict, base_dir: Path | str = ".", source: str = "<Pi form>"
              ) -> Expansion:
    """The dimensional scene of a validated Pi-form scene.

    Parameters
    ----------
    pi : PiScene
        The validated Pi form.
    raw : dict
        The YAML data it was validated from; recorders and analysis options are copied from
        it as written.
    base_dir : path
        Where a record's file is found (the scene file's folder).

    Raises
    ------
    _Problems
        Every problem found, each at its path (contact levels, tags, law options, Pi numbers
        missing or not applying, a record that cannot be read).
    """
    problems: list = []
    layout = _layout(pi, problems)
    try:
        variables, roles, repeating, groups, found = _probe(pi, raw, layout, base_dir, source)
    except _Problems as exc:
        raise _Problems(problems + exc.problems) from None
    scales = {"m_b": pi.scales.m_b,
              "a_p": pi.scales.a_p if pi.scales.a_p is not None
              else (found.amplitude if pi.excitation.kind == "record" else 1.0),
              "w_p": pi.scales.w_p if pi.scales.w_p is not None
              else (found.frequency if pi.excitation.kind == "record" else 1.0)}

    given = pi.pi.given()
    expected = {g.name: g for g in groups}
    for name in given:
        if name not in expected:
            why = _why_not(name, pi, layout) or (
                "unknown field: not a Pi group of this scene, whose groups are "
                + ", ".join(expected))
            problems.append((("pi", name), why))
    for name, group in expected.items():
        if name not in given:
            problems.append((("pi",), f"{name} is required ({group.formula()})"))
    if problems:
        raise _Problems(problems)

    dims = {v.name: v.dimension for v in variables}
    length = scales["a_p"] / scales["w_p"] ** 2
    values = {repeating[0]: scales["m_b"], "a_p": scales["a_p"], "w_p": scales["w_p"]}
    pending = list(groups)
    while pending:
        group = next(g for g in pending
                     if all(n in values for n, _ in g.exponents[1:]))
        pending.remove(group)
        (own, _), others = group.exponents[0], group.exponents[1:]
        value, rest = float(given[group.name]), dims[own]
        for name, x in others:
            if name not in repeating:
                value *= values[name] ** float(-x) if x != -1 else values[name]
                rest = rest / dims[name] ** -x
        for scale, exponent in ((scales["m_b"], rest.mass), (length, rest.length),
                                (scales["w_p"], -rest.time)):
            if exponent:
                value *= scale if exponent == 1 else scale ** float(exponent)
        values[own] = value

    by_role = {roles[name]: v for name, v in values.items()}

    def value(root, tag):
        if root == "w_bar" and pi.excitation.kind == "sine":  # frequency_ratio = w_bar / w_p
            return given["Pi_wcon"]
        return by_role[(root, tag)] if (root, tag) in by_role else by_role[(root, "")]

    data = _scene(pi, raw, layout, value, scales, _excitation(pi, scales))
    return Expansion(data, tuple(groups), scales, found)


def pi_expansion(data: dict, lines: dict, source: str, base_dir: Path | str = ".") -> Expansion:
    """Validate Pi-form YAML data and expand it; errors name the file, line and field of every
    problem at once."""
    from pframe.model.load import validated
    from pframe.yamltext import where as _where

    pi = validated(PiScene, data, lines, source)
    try:
        return expand_pi(pi, data, base_dir, source)
    except _Problems as exc:
        raise InputError("; ".join(f"{_where(source, lines, path)}: {message}"
                                   for path, message in exc.problems)) from None
    except ArithmeticError:  # scales whose products leave floating point (w_p = 1e-200)
        raise InputError(f"{_where(source, lines, ('scales',) if 'scales' in data else ('pi',))}: "
                         "the Pi numbers and scales give dimensional values beyond floating "
                         "point arithmetic (a division by zero or an overflow); check them"
                         ) from None


def expand_pi_data(data: dict, lines: dict, source: str, base_dir: Path | str = ".") -> dict:
    """The dimensional scene (YAML data) of Pi-form YAML data; see :func:`pi_expansion`."""
    return pi_expansion(data, lines, source, base_dir).data
