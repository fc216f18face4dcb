"""The scene: buildings (or generic nodes and storeys), contacts, excitation, analysis, recorders.

Every model is frozen and rejects unknown fields. Storeys and contacts are tagged unions on
``material`` and ``law``; the union is built from the law registry, so a law from a plug-in
package is validated exactly like a built-in one (:func:`scene_class`).
"""


import functools
import os
from typing import Annotated, Literal, Union, get_args

from pydantic import (
    BaseModel,
    ConfigDict,
    Field,
    create_model,
    model_validator,
)

from pframe import integrators
from pframe.errors import InputError
from pframe.integrators import Newmark
from pframe.integrators._base import IntegratorParams
from pframe.laws import get_law
from pframe.laws.registry import builtin_names
from pframe.model.parts import (
    TAGS,
    Base,
    BuildingName,
    NodeName,
    Positive,
    Sine,
    SupportName,
    brief,
    public_name,
    shown_fields,
    shown_items,
)
from pframe.model.plan import Direction, FloorPlan, Point
from pframe.model.tagged import lazy_model, on_demand, tagged
from pframe.objects import Frozen, describe, dotted
from pframe.quantities import QUANTITIES as _QUANTITIES
from pframe.units import NAMES

QUANTITIES = tuple(_QUANTITIES)
Quantity = Literal[QUANTITIES]


def _no_items() -> list:
    """``[]``: the default of the Scene's lists. Pydantic reads a default factory's signature
    when it builds the validator; ``list``'s is text, parsed with tokenize, whose patterns
    compile on first use (about 2 ms of every ``pframe solve``)."""
    return []


def _scene_lines(scene) -> list[tuple[str, list[str]]]:
    """(field, one line per item) of the fields a scene was given, in the model's order."""
    out = []
    for name in shown_fields(scene):
        value = getattr(scene, name)
        if isinstance(value, list):
            out.append((name, shown_items(value, brief)))
        else:
            out.append((name, [brief(value)]))
    return out


#: id(scene) -> (weak reference to it, a function giving the facts its repr ends with: the
#: periods of its buildings, which only its expanded form knows; pframe.load sets it)
_FACTS: dict[int, tuple] = {}


def attach_facts(scene, facts) -> None:
    """Make ``facts()`` (lines) the end of ``scene``'s repr, as comments (``# ...``), while
    the scene lives; computed when the repr is asked for."""
    import weakref

    key = id(scene)
    _FACTS[key] = (weakref.ref(scene, lambda _, key=key: _FACTS.pop(key, None)), facts)


def _facts(scene) -> list[str]:
    entry = _FACTS.get(id(scene))
    if entry is None or entry[0]() is not scene:
        return []
    return list(entry[1]())


def scene_text(scene) -> str:
    """A scene in a few lines: its title, then one line per building, storey, contact and
    setting (the repr of a scene), then what pframe.load found of it as comments (the
    periods of its buildings)."""
    lines = [f"{type(scene).__name__}("]
    for name, items in _scene_lines(scene):
        if name == "title" or len(items) == 1 and not isinstance(getattr(scene, name), list):
            lines.append(f"  {name}={items[0]},")
        elif not items:
            lines.append(f"  {name}=[],")
        else:
            lines.append(f"  {name}=[")
            lines += [f"    {item}," for item in items]
            lines.append("  ],")
    return "\n".join(lines + [")"] + [f"# {fact}" for fact in _facts(scene)])


def scene_html(scene) -> str:
    """The HTML form of a scene for notebooks: a table of its fields, one item per line."""
    from html import escape

    rows = "".join(
        f"<tr><th style='text-align:left;vertical-align:top'>{escape(name)}</th>"
        f"<td style='text-align:left'><code>{'<br>'.join(escape(i) for i in items) or '[]'}"
        f"</code></td></tr>" for name, items in _scene_lines(scene))
    facts = "".join(f"<li>{escape(fact)}</li>" for fact in _facts(scene))
    return (f"<div><strong>pframe Scene</strong><table>{rows}</table>"
            + (f"<ul>{facts}</ul>" if facts else "") + "</div>")


class Node(Base):
    """A floor: a rigid diaphragm with a lumped mass at its centre of mass, which moves along
    the site's x and y and turns about the vertical (docs/plan.md); a scene whose elements
    all act along x through the centres of mass moves it along x only."""

    name: NodeName
    mass: Positive = Field(description="Lumped floor mass (kg).")
    free: bool = Field(False, description="A free body: no storey, link with a stiffness or "
                       "soil holds it to the ground. Such a node is refused in a building that "
                       "has storeys (a storey left out?) and warned about under a ground "
                       "motion, unless it says free: true.")
    centre_of_mass: Point = Field((0.0, 0.0), description="[x, y]: where the floor's mass is "
                                  "in the site's plan (m); its motion is that point's.")
    polar_inertia: Positive | None = Field(
        None, description="J: the floor's mass moment of inertia about the vertical through "
        "its centre of mass (kg m^2); needed once the floor turns (an element off its centre "
        "of mass).")


#: a point of a floor: a named point of its building (a corner: SW, SE, NE, NW of a
#: rectangular plan) or [x, y] in its building's plan axes (m)
PointRef = Annotated[str | Point, Field(description="A named point of the floor's building "
                                        "(its plan's corners SW, SE, NE, NW, or one of its "
                                        "points) or [x, y] in the building's plan axes (m).")]


#: a node's name, or the ground (a storey's base, a wall's side of a contact, a link's anchor)
NodeOrGround = Annotated[
    str,
    Field(pattern=r"^(ground|[A-Za-z0-9_.-]+/[A-Za-z0-9_.-]+)$",
          description="A node name '<building>/<floor>', or 'ground'."),
]
#: a contact's side: a node, 'ground', or a building (a contact at each of its floors)
ContactEnd = Annotated[
    str,
    Field(pattern=r"^(ground|[A-Za-z0-9_.-]+(/[A-Za-z0-9_.-]+)?)$",
          description="A node name '<building>/<floor>', 'ground', or a building's name (a "
                      "contact at every floor level)."),
]


#: every name pframe.model.scene_options defines that this module gives too
_OPTION_NAMES = frozenset({"ParkAng", "Foundation", "Soil", "CodeDriftLimit", "Limits",
                           "SOIL_PROPERTIES", "SOIL_VALUES"})


def _option(name: str):
    """A field holding the model ``name`` of pframe.model.scene_options, made (and the module
    imported) when a scene first gives one (:func:`pframe.model.tagged.lazy_model`)."""
    def make():
        from pframe.model import scene_options

        return getattr(scene_options, name)

    return lazy_model(make, Base)


_PARK_ANG, _SOIL, _LIMITS = _option("ParkAng"), _option("Soil"), _option("Limits")


def _deferred(model: type):
    """A field of ``model`` (made already) whose validator is built at the field's first
    value, not with the scene's: generic nodes, supports, a floor plan and output scales
    are left out of most scenes (:func:`pframe.model.tagged.lazy_model`)."""
    return lazy_model(lambda: model, model)


class StoryBase(Base):
    """A storey shear spring between two nodes, or a node and the ground."""

    nodes: tuple[str, NodeName] = Field(
        description="[lower, upper]: 'ground' or a node name, then the node above it."
    )
    name: str | None = Field(None, description="Defaults to the upper node's name.")
    height: Positive | None = Field(None, description="Storey height h (m): drift ratio, "
                                    "P-delta.")
    gravity_load: float | None = Field(None, ge=0, allow_inf_nan=False,
                                       description="Axial (gravity) load P the storey carries "
                                       "(N): P-delta, a geometric stiffness -P/h (needs height).")
    park_ang: _PARK_ANG | None = Field(
        None, description="Ultimate drift (one value) and beta of the storey's Park-Ang "
        "damage index (pframe summary); none: no damage index.")
    position: Point | None = Field(
        None, description="[x, y]: a point of the storey's line of resistance in the site's "
        "plan (m); default: the upper floor's centre of mass.")
    direction: Direction = Field("x", description="The line's direction: x, y or an angle "
                                 "(degrees from the site's x axis); its drift is the relative "
                                 "motion of its point along it.")
    isolator: bool | None = Field(
        None, description="An isolation storey (bearings): no stiffness-proportional Rayleigh "
        "damping on it, and its building's isolated modes take its post-yield or sliding "
        "stiffness. Default: its material says (friction_pendulum: yes); any other storey is "
        "one when its post-yield stiffness is at most a tenth of that of every storey above it "
        "(docs/theory.md#damping).")
    stiffness_damping: bool | None = Field(
        None, description="Whether its building's Rayleigh damping adds the stiffness-"
        "proportional term a1 k to this storey (default: yes, but not on an isolator).")

    support: SupportName | None = Field(
        None, description="The support its lower end stands on when it is 'ground' "
        "(docs/supports.md); default: the scene's only support.")


class LinkBase(Base):
    """A link: a material element between any two nodes, or a node and the ground, acting in
    tension and compression with no gap (dampers and springs between buildings, the spring
    and dashpot of a tuned mass, a device to the ground)."""

    name: str | None = Field(None, description="Defaults to '<first>~<second>'.")
    nodes: tuple[NodeOrGround, NodeOrGround] = Field(
        description="[first, second]: deformation = u_second - u_first (a storey's drift when "
        "first is below second); 'ground' on one side anchors the link to the ground."
    )
    points: tuple[PointRef | None, PointRef | None] | None = Field(
        None, description="[first, second]: where the link is attached on each floor (null: "
        "its centre of mass, the default).")
    direction: Point = Field((1.0, 0.0), description="[x, y]: the direction the link acts "
                             "along, in the site's axes (default [1, 0]: the row's axis).")
    support: SupportName | None = Field(
        None, description="The support a side of it that is 'ground' stands on "
        "(docs/supports.md); default: the scene's only support.")


def default_link_name(nodes) -> str:
    """The name of a link the scene does not name: ``<first>~<second>``."""
    return f"{nodes[0]}~{nodes[1]}"


def default_contact_name(nodes) -> str:
    """The name of a contact the scene does not name: ``<left>-<right>`` (the one rule;
    result files, sweeps and figures use it)."""
    return f"{nodes[0]}-{nodes[1]}"


def contact_levels(contact, has_node) -> list[tuple[tuple[str, str], str]]:
    """The contacts a scene's contact stands for, as (nodes, name): itself, or, when its
    nodes name buildings (the shorthand), one at each floor level k = 1, 2, ... that both
    sides have (``has_node(name)``; 'ground' has every level), named
    ``<name>/<k>`` or by the default rule of its nodes."""
    left, right = contact.nodes
    if all(end == "ground" or "/" in end for end in (left, right)):
        return [(tuple(contact.nodes), contact.name or default_contact_name(contact.nodes))]
    out = []
    k = 1
    while True:
        nodes = tuple(end if end == "ground" or "/" in end else f"{end}/{k}"
                      for end in (left, right))
        if not all(end == "ground" or has_node(end) for end in nodes):
            return out
        out.append((nodes, f"{contact.name}/{k}" if contact.name
                    else default_contact_name(nodes)))
        k += 1


def default_story_name(nodes) -> str:
    """The name of a storey the scene does not name: its upper node's."""
    return str(nodes[1])


class ContactBase(Base):
    """A compression-only contact element across the gap between two buildings, or between a
    floor and a wall (the ground)."""

    name: str | None = Field(None, description="Defaults to '<left>-<right>'; a contact at "
                             "every level is named '<name>/<floor>' (default "
                             "'<left>/<floor>-<right>/<floor>', as written out).")
    nodes: tuple[ContactEnd, ContactEnd] = Field(
        description="[left, right]: penetration = u_left - u_right - gap. The buildings "
        "stand from left to right in the order the scene declares them; the left node's "
        "building must come first (a contact written the other way round is refused). "
        "'ground' on one side is a wall moving with the ground (a moat or retaining wall, a "
        "stop): [A/1, ground] stands right of A/1, [ground, A/1] left of it. Two buildings' "
        "names ([A, B]) are a contact at every floor level both have (A/1 with B/1, A/2 with "
        "B/2, ...), each with these fields: the shorthand of a tall pair (a building and "
        "'ground': a wall at each of its floors)."
    )
    gap: float = Field(ge=0, allow_inf_nan=False, description="Initial gap d (m).")
    column: Literal["left", "right"] | None = Field(
        None, description="Floor-to-column pounding: the side whose node names a storey (by "
        "its upper floor) struck at a point of its column, 'at' of the way up from its lower "
        "floor (floors at different heights).")
    at: float | None = Field(None, gt=0, lt=1, allow_inf_nan=False,
                             description="Where the column is struck: the fraction of the "
                             "storey's height above its lower floor (0 < at < 1). With both "
                             "buildings' storey heights it is computed from them (leave it "
                             "out; one that differs by more than 0.001 is refused); without "
                             "them it is required.")
    shear_capacity: float | None = Field(
        None, gt=0, allow_inf_nan=False, description="The struck column's shear capacity (N) "
        "of a floor-to-column contact: the local shear the impact puts into it is checked "
        "against it.")
    points: tuple[PointRef | None, PointRef | None] | None = Field(
        None, description="[left, right]: the point of each floor that strikes (a corner, a "
        "point of an edge; null: its centre of mass, the default). A wall's side takes null.")
    normal: Point = Field((1.0, 0.0), description="[x, y]: the direction from the left point "
                          "to the right one along which they close, in the site's axes "
                          "(default [1, 0]: the row's axis); penetration = normal . (u_left - "
                          "u_right) - gap.")
    support: SupportName | None = Field(
        None, description="The support its wall (a side that is 'ground') stands on "
        "(docs/supports.md); default: the scene's only support.")


class LineBase(Base):
    """A line of resistance of a building in plan (a frame, a wall, an isolator): a storey
    spring at a plan point along a direction, in every storey of the building (or those of
    ``storeys``); its material's values are one for all storeys or one per storey, bottom up."""

    name: Annotated[str, Field(pattern=r"^[A-Za-z0-9_.-]+$")] = Field(
        description="The line's name; its storey elements are '<building>/<storey>/<name>'.")
    position: Point = Field(description="[x, y]: a point of the line in the building's plan "
                            "axes (m).")
    direction: Direction = Field("x", description="x, y, or an angle (degrees from the "
                                 "building's x axis): the direction the line resists along.")
    storeys: tuple[Annotated[int, Field(ge=1)], Annotated[int, Field(ge=1)]] | None = Field(
        None, description="[first, last]: the storeys the line stands in (1-based, "
        "inclusive); default: all.")
    isolator: bool | None = Field(
        None, description="A line of isolation bearings: no stiffness-proportional Rayleigh "
        "damping on it, and its building's isolated modes take its post-yield or sliding "
        "stiffness (as a storey's isolator).")
    stiffness_damping: bool | None = Field(
        None, description="Whether its building's Rayleigh damping adds the stiffness-"
        "proportional term a1 k to this line (default: yes, but not on an isolator).")

    @model_validator(mode="after")
    def _storey_range(self):
        if self.storeys is not None and self.storeys[1] < self.storeys[0]:
            raise ValueError("storeys: [first, last] with first <= last")
        return self


#: the stiffness a building's damping is fitted on (Rayleigh's and modal damping's ``fit``)
FIT_DESCRIPTION = (
    "The stiffness of the modes the damping is fitted on: isolated (each isolator storey at its "
    "post-yield or sliding stiffness, every other storey at its initial stiffness: the modes "
    "that govern an isolated building; for a building without isolators the same as initial) "
    "or initial (every storey at its initial stiffness).")


RayleighMode = Union[Annotated[int, Field(ge=1)],  # noqa: UP007
                     Annotated[str, Field(pattern=r"^(x|y|torsion)[1-9][0-9]*$")]]


class Rayleigh(Base):
    """Rayleigh damping of one building, C = a0 M + a1 K, fitted on that building alone (a
    fixed base) so that the two modes named get the ratio asked; the a1 K term acts on its
    storeys but not on its isolators (docs/theory.md#damping)."""

    kind: Literal["rayleigh"] = "rayleigh"
    ratio: float = Field(0.05, ge=0, lt=1, description="Damping ratio on both fitted modes.")
    modes: tuple[RayleighMode, RayleighMode] = Field(
        (1, 2), description="The two modes the ratio is fitted to: 1-based numbers in the "
        "building's order of frequency, or in plan a direction and its number (x1, y2, "
        "torsion1: the first mode moving mostly in twist, as validate lists them)."
    )
    stiffness: Literal["initial", "current", "committed"] = Field(
        "initial", description="Stiffness of the beta K term (as OpenSees betaKinit/K/Kcomm)."
    )
    fit: Literal["isolated", "initial"] = Field("isolated", description=FIT_DESCRIPTION)


class Modal(Base):
    """Modal damping of one building: each of its modes (fixed base, on the stiffness ``fit``
    names) gets its own ratio, C = M Phi diag(2 xi_i w_i) Phi^T M with Phi normalised on the
    masses (docs/theory.md#damping). A dense term over the building's floors."""

    # YAML without a kind is Rayleigh's: the schema asks a modal damping for its kind (Python
    # objects know their class)
    model_config = Frozen.model_config | ConfigDict(json_schema_extra={"required": ["kind"]})

    kind: Literal["modal"] = "modal"
    ratio: (Annotated[float, Field(ge=0, lt=1, allow_inf_nan=False)]
            | list[Annotated[float, Field(ge=0, lt=1, allow_inf_nan=False)]]) = Field(
        0.05, description="The damping ratio of every mode, or one per mode from the first "
        "(the modes after the list take its last ratio).")
    fit: Literal["isolated", "initial"] = Field("isolated", description=FIT_DESCRIPTION)

    @model_validator(mode="after")
    def _some_ratio(self):
        if isinstance(self.ratio, list) and not self.ratio:
            raise ValueError("give at least one ratio (one for every mode, or one per mode)")
        return self


#: the motions of pframe.model.scene_motions: kind -> class name (the module is imported
#: when a scene first names one of them; a sine, the common case, is this module's)
_MOTIONS = {"record": "Record", "cycloidal": "Cycloidal", "ricker": "Ricker",
            "stochastic": "Stochastic", "components": "Components",
            "wave_passage": "WavePassage", "coherent": "Coherent"}
#: every name pframe.model.scene_motions defines that this module gives too
_MOTION_NAMES = frozenset({*_MOTIONS.values(), "Baseline", "StochasticParameters", "Jennings",
                           "GammaShape", "Coherency", "Motion"})


def _motion_model(kind: str) -> type:
    if kind == "sine":
        return Sine
    from pframe.model import scene_motions

    return getattr(scene_motions, _MOTIONS[kind])


def motions(*kinds: str):
    """The tagged union (on ``kind``) of the motions of ``kinds``, in that order: each model
    made, and pframe.model.scene_motions imported, when a value first names its kind
    (:func:`pframe.model.tagged.on_demand`; a reader of the fields unfolds it)."""
    return on_demand(kinds, _motion_model, "kind", Base)


#: one motion along one direction, or two components (a support's own motion)
_SUPPORT_MOTION = motions("sine", "record", "cycloidal", "ricker", "stochastic", "components")
#: a scene's excitation
_SCENE_MOTION = motions("sine", "record", "cycloidal", "ricker", "stochastic", "components",
                        "wave_passage", "coherent")


class SiteColumn(Base):
    """The soil column under a support (its site response, docs/supports.md): a filter of the
    firm-ground motion of fundamental frequency ``frequency`` and damping ``damping``."""

    frequency: Positive = Field(description="The column's fundamental frequency f_s (Hz).")
    damping: float = Field(gt=0, lt=1, allow_inf_nan=False, description="Its damping ratio.")
    kind: Literal["sdof", "layer"] = Field("sdof", description="sdof (a single-mode filter, "
                                           "causal) or layer (a uniform damped layer on rock, "
                                           "Kramer 1996).")


class Support(Base):
    """A piece of ground that moves as one (docs/supports.md): what buildings, walls and the
    ground ends of storeys and links stand on, with its own motion."""

    name: SupportName = Field(description="Its name (buildings and elements name it).")
    position: Point = Field((0.0, 0.0), description="[x, y]: where it is on the site (m): the "
                            "wave passage's delays.")
    excitation: _SUPPORT_MOTION | None = Field(
        None, description="Its own motion; none: the scene's excitation (the same motion, or "
        "the wave passage's at this support).")
    site: SiteColumn | None = Field(None, description="The soil column under it, which "
                                    "filters a coherent simulation's motion here (kind: "
                                    "coherent); none: firm ground.")


def plain_motions(excitation) -> tuple:
    """The plain motions (a sine, a pulse, a record, a stochastic motion) an excitation is
    made of: itself, each of two components, the motion a wave passage carries."""
    if excitation is None:
        return ()
    if excitation.kind == "components":
        return tuple(m for _, m in excitation.motions())
    if excitation.kind == "wave_passage":
        return plain_motions(excitation.motion)
    if excitation.kind == "coherent":
        return (excitation.motion,) + ((excitation.record,) if excitation.record else ())
    return (excitation,)


def scene_motions(scene) -> tuple:
    """Every plain motion of a scene: its excitation's, then each support's own."""
    out = plain_motions(scene.excitation)
    for support in getattr(scene, "supports", ()) or ():
        out += plain_motions(support.excitation)
    return out


def records_of(excitation) -> tuple:
    """The record definitions an excitation reads (a record, the records among the
    components of a pair or in a wave passage)."""
    return tuple(m for m in plain_motions(excitation) if m.kind == "record")


def tag_reader(key: str, default: str):
    """The discriminator of a union whose tag ``key`` may be left out (``default``): reads it
    from YAML data (a dict) or from an object built in Python."""
    def tag(value):
        if isinstance(value, dict):
            return value.get(key, default)
        return getattr(value, key, None)

    return tag


_integrator_tag = tag_reader("type", "newmark")


def _integrator_model(name: str) -> type:
    return getattr(integrators, integrators.TABLE[name])


#: the scene's integrator: one of pframe.integrators' table, tagged by its ``type``, each
#: model made (its module imported) when a scene first names it
Integrator = on_demand(integrators.TABLE, _integrator_model, _integrator_tag, IntegratorParams)
_INTEGRATOR_TYPES = list(integrators.TABLE)


Damping = tagged({"rayleigh": Rayleigh, "modal": Modal}, tag_reader("kind", "rayleigh"))


class Newton(Base):
    """Full Newton-Raphson iterations (skipped for a linear scene)."""

    tolerance: float = Field(
        1e-12, gt=0, description="Converged when |du| <= tolerance |u| + absolute_tolerance."
    )
    absolute_tolerance: float = Field(0.0, ge=0, description="(m)")
    max_iterations: int = Field(50, ge=1, description="Newton iterations before a step is split.")


class Analysis(Base):
    """Time integration: integrator, step, duration and Newton settings."""

    integrator: Integrator = Field(Newmark(), description="The time integrator (type: "
                                   + ", ".join(_INTEGRATOR_TYPES[:-1]) + " or "
                                   + _INTEGRATOR_TYPES[-1] + ").")
    dt: Positive = Field(description="Time step (s).")
    duration: Positive = Field(description="Analysed time (s).")
    newton: Newton = Field(Newton(), description="Newton-Raphson settings (nonlinear scenes).")


class History(Base):
    """Record quantities at every ``every``-th step (and at t = 0)."""

    kind: Literal["history"] = "history"
    quantities: list[Quantity] = Field(min_length=1, description="What to record.")
    every: int = Field(1, ge=1, description="Record every k-th step (and t = 0).")


class Envelope(Base):
    """Record only the peak absolute value of each quantity over the run."""

    kind: Literal["envelope"] = "envelope"
    quantities: list[Quantity] = Field(min_length=1, description="What to record peaks of.")


class InitialConditions(Base):
    """Displacements and velocities relative to the ground at t = 0 (default: at rest)."""

    displacement: dict[NodeName, float | tuple[float, float, float]] = Field(
        default_factory=dict, description="(m) along x, or [u_x (m), u_y (m), theta (rad)] of "
        "a floor in plan.")
    velocity: dict[NodeName, float | tuple[float, float, float]] = Field(
        default_factory=dict, description="(m/s) along x, or [v_x (m/s), v_y (m/s), "
        "theta' (rad/s)] of a floor in plan.")


class OutputScales(Base):
    """Reference scales of dimensionless output (Wu et al. 2021, eq. 6)."""

    m_b: Positive = Field(description="Reference mass m_b (kg).")
    a_p: Positive = Field(description="Reference acceleration a_p (m/s^2).")
    w_p: Positive = Field(description="Reference circular frequency w_p (rad/s).")


class Output(Base):
    """Units of the result file: SI, or dimensionless (tau = w_p t, x = X / l_e, l_e = a_p /
    w_p^2, force / (m_b a_p); see docs/dimensional-analysis.md)."""

    units: Literal["SI", "dimensionless"] = Field(
        "SI", description="SI or dimensionless. Left out, a dimensional file is in the "
        "scene's units (docs/units.md); SI given writes a scene of another unit system's "
        "results in SI.")
    scales: _deferred(OutputScales) | None = Field(
        None, description="m_b, a_p, w_p of dimensionless output; default: the first floor mass "
        "of the second building and the excitation's amplitude and frequency.")
    reference: BuildingName | None = Field(
        None, description="The building whose first floor mass is the mass scale m_b of the Pi "
        "groups (pframe pi) and of dimensionless output; default: the second building, or the "
        "only one.")


#: the defaults of a scene's initial conditions and output: the models' own defaults, made
#: without their validators (model_construct), which a scene that gives neither (most do)
#: never builds (their fields are deferred; neither model has a validator of its own)
_AT_REST = InitialConditions.model_construct()
_SI_OUTPUT = Output.model_construct()


#: fields that say which kind of object a mapping is: written even when left at their default


def given_fields(value, where: str | None = None, path: tuple = ()):
    """The data of a scene, a part of one, or Python data holding parts, as YAML gives it:
    of a model the fields that were set, plus the tags that select a model of a union
    (``kind``, ``type``, ``law``, ``material``); numpy numbers and arrays as Python numbers
    and lists, tuples as lists, paths as text. Anything else (a set, a function, an object of
    another library, which ``model_construct`` or ``model_copy`` may have let in) is an
    :class:`InputError` naming ``where`` (the call; default: the object's public name) and
    its key."""
    if where is None:
        where = f"pframe.{public_name(type(value))}" if isinstance(value, BaseModel) \
            else "the scene"
    if type(value).__module__ == "numpy":  # before float: numpy's float64 is one
        kind = value.dtype.kind if hasattr(value, "dtype") else ""
        if getattr(value, "shape", None) == () and kind and kind in "biufU":
            return value.item()  # YAML writes Python's numbers only
        if getattr(value, "shape", ()) and kind and kind in "biuf":
            return value.tolist()
    if value is None or isinstance(value, (bool, int, float, str)):
        return value
    if isinstance(value, BaseModel):
        return {name: given_fields(getattr(value, name), where, path + (name,))
                for name in type(value).model_fields
                if name in value.model_fields_set or name in TAGS}
    if isinstance(value, dict):
        out = {}
        for key, item in value.items():
            if not isinstance(key, str):
                raise InputError(f"{where}: {dotted(path) or 'the dict'}: the key {key!r} is "
                                 f"{describe(key)}; a scene's keys are the field names, as text")
            out[key] = given_fields(item, where, path + (key,))
        return out
    if isinstance(value, (list, tuple)):
        return [given_fields(item, where, path + (i,)) for i, item in enumerate(value)]
    if isinstance(value, os.PathLike):
        return os.fspath(value)
    raise InputError(f"{where}: {dotted(path) or 'the value'} is {describe(value)}; a scene holds "
                     "numbers, text, True/False, None, and lists and dicts of them (numpy "
                     "numbers and arrays are taken as numbers and lists)")


def _broadcast(params_model: type[BaseModel], discriminator: str) -> type[BaseModel]:
    """A variant of a material's Params whose numeric fields also take one value per storey.

    Each value keeps its own constraints (a list item is checked like a scalar); the model
    validators of the material (such as 'yield_drift or yield_force') run per storey later.
    """
    fields = {}
    for name, info in params_model.model_fields.items():
        if name == discriminator or info.annotation in (bool, str):
            fields[name] = (info.annotation, info)
            continue
        item = Annotated[(info.annotation, *info.metadata)] if info.metadata else info.annotation
        default = ... if info.is_required() else info.default
        fields[name] = (Union[item, list[item]], Field(default, description=info.description))  # noqa: UP007
    tag = get_args(params_model.model_fields[discriminator].annotation)[0]
    return create_model(
        f"{params_model.__qualname__.split('.')[0]}Storeys",
        __base__=Base,
        __doc__=f"Storey properties ({discriminator}: {tag}); a list gives one value per storey, "
        "bottom up.",
        **fields,
    )




@functools.cache
def _storeys_model(material: str):
    """The storey properties of a material, each field a value or one per storey (made once
    per material; at module level, not cached inside the scene class's factory, so that
    cloudpickle can ship a scene by value to Dask's workers)."""
    return _broadcast(get_law("material", material).Params, "material")


def scene_class(contact_laws: tuple[str, ...] = (), materials: tuple[str, ...] = ()):
    """The Scene model for the built-in laws plus the named plug-in laws (one class per set
    of laws, however they are passed: scenes of the same laws compare equal)."""
    return _scene_class(tuple(sorted(contact_laws)), tuple(sorted(materials)))


#: the names a scene's ``units`` accepts (pframe.units.SYSTEMS), the default first
UNIT_SYSTEMS = NAMES


@functools.cache
def _scene_class(contact_laws: tuple[str, ...], materials: tuple[str, ...]):
    material_names = sorted(set(builtin_names("material")) | set(materials))
    contact_names = sorted(set(builtin_names("contact")) | set(contact_laws))

    # one model per law and place, made when a scene first names the law (on_demand): the
    # laws' modules are imported then too
    def params(kind: str):
        return lambda name: get_law(kind, name).Params

    material_params, contact_params = params("material"), params("contact")
    storeys = _storeys_model  # module level: a scene pickles (Dask ships it to workers)
    story_type = on_demand(material_names, lambda n: create_model(
        f"Story_{n}", __base__=(StoryBase, material_params(n))), "material", StoryBase)
    contact_type = on_demand(contact_names, lambda n: create_model(
        f"Contact_{n}", __base__=(ContactBase, contact_params(n))), "law", ContactBase)
    link_type = on_demand(material_names, lambda n: create_model(
        f"Link_{n}", __base__=(LinkBase, material_params(n))), "material", LinkBase)
    storeys_type = on_demand(material_names, storeys, "material", Base)
    line_type = on_demand(material_names, lambda n: create_model(
        f"Line_{n}", __base__=(LineBase, storeys(n))), "material", LineBase)

    class Building(Base):
        """Shorthand for one shear building: floors 1..n above ground, storey i below floor i."""

        name: BuildingName = Field(description="The building's name: its floors are the nodes "
                                                "'<name>/1' .. '<name>/<floors>'.")
        floors: int | None = Field(None, ge=1, description="Number of floors (storeys).")
        mass: Positive | list[Positive] = Field(description="Floor masses (kg), bottom up.")
        story: storeys_type | None = Field(
            None, description="Storey properties: one storey spring along x through the "
            "floors' centres of mass (a planar building); or give lines.")
        lines: list[line_type] | None = Field(
            None, min_length=1, description="Lines of resistance (frames, walls, isolators) "
            "of every storey, each at a plan point along a direction with its material "
            "(docs/plan.md); instead of story.")
        origin: Point = Field((0.0, 0.0), description="[x, y]: where the building's plan "
                              "origin stands on the site (m).")
        angle: float = Field(0.0, allow_inf_nan=False, description="The angle of the "
                             "building's x axis from the site's x axis (degrees, "
                             "counter-clockwise).")
        plan: _deferred(FloorPlan) | None = Field(None, description="The floors' plan (size or outline, "
                                       "building axes): the default centre of mass and polar "
                                       "inertia, the named corners, where contact points may "
                                       "be.")
        centre_of_mass: Point | list[Point] | None = Field(
            None, description="[x, y] of the floors' centre of mass in the building's axes "
            "(m), one for all floors or one per floor; default: the plan's centroid, else the "
            "origin.")
        polar_inertia: Positive | list[Positive] | None = Field(
            None, description="J: each floor's mass moment of inertia about the vertical "
            "through its centre of mass (kg m^2), one for all or one per floor; default: a "
            "uniform slab of the plan, m (L_x^2 + L_y^2) / 12 for a rectangle.")
        points: dict[Annotated[str, Field(pattern=r"^[A-Za-z0-9_.-]+$")], Point] = Field(
            default_factory=dict, description="Named plan points [x, y] (building axes, m): "
            "where contacts strike and outputs are taken, besides the plan's corners.")
        damping: Damping | None = Field(None, description="Rayleigh (kind: rayleigh, the "
                                        "default) or modal damping (kind: modal); defaults to "
                                        "the scene's damping.")
        height: Positive | list[Positive] | None = Field(
            None, description="Storey heights (m), bottom up, one for all or one per storey: "
            "drift ratios, P-delta, floor levels in the figures.")
        p_delta: bool = Field(
            False, description="P-delta: each storey carries the weight of the floors above "
            "it (g = 9.80665 m/s^2 times their masses), whose geometric stiffness -P/h "
            "softens it (needs height).")
        support: SupportName | None = Field(
            None, description="The support the building stands on (docs/supports.md); "
            "default: the scene's only support.")
        soil: _SOIL | None = Field(
            None, description="Soil under the building (default: a fixed base): a foundation "
            "that sways and rocks on springs and dashpots (needs height; docs/soil.md).")
        park_ang: _PARK_ANG | None = Field(
            None, description="Ultimate drift and beta of the Park-Ang damage index of its "
            "storeys (pframe summary); none: no damage index.")

        @model_validator(mode="after")
        def _story_or_lines(self):
            if (self.story is None) == (self.lines is None):
                raise ValueError("give story (one storey spring per storey, a planar "
                                 "building) or lines (lines of resistance in plan), not both "
                                 "and not neither")
            return self

    class Scene(Base):
        """A scene of adjacent buildings that may pound into each other."""

        title: str = Field("", description="A title copied into the result file.")
        units: Literal[UNIT_SYSTEMS] = Field(
            UNIT_SYSTEMS[0], description="The unit system every number of the scene is "
            "written in, and its results are written in (docs/units.md): " + ", ".join(
                UNIT_SYSTEMS) + ". Each is consistent (F = m a); time is in seconds in all. "
            "The units the fields below name are N-m-kg's; in another system read the same "
            "quantity in that system's units (a stiffness N/m is kN/m in kN-m-t).")
        buildings: list[Building] = Field(default_factory=_no_items, description="Shear buildings, "
                                          "from left to right.")
        nodes: list[_deferred(Node)] = Field(
            default_factory=_no_items, description="Generic floor nodes (their buildings "
            "stand right of the shorthand's, in the order first named).")
        stories: list[story_type] = Field(
            default_factory=_no_items, description="Generic storeys between nodes.")
        contacts: list[contact_type] = Field(
            default_factory=_no_items, description="Contact elements between buildings.")
        links: list[link_type] = Field(
            default_factory=_no_items, description="Links: a material (viscous, kelvin_voigt, "
            "elastic, bilinear, ...) between two nodes or a node and the ground, in tension and "
            "compression (dampers, couplings, tuned masses).")
        damping: Damping = Field(Rayleigh(), description="Default damping of every building: "
                                 "Rayleigh (kind: rayleigh, the default) or modal (kind: "
                                 "modal).")
        supports: list[_deferred(Support)] = Field(
            default_factory=_no_items, description="The pieces of ground structures stand on, each "
            "with its own motion (docs/supports.md); none: one ground under everything.")
        excitation: _SCENE_MOTION | None = Field(
            None, description="Ground motion along the site's x axis, or in two components "
            "(kind: components), or as the waves pass the supports (kind: wave_passage), or "
            "simulated at every support (kind: coherent); none: free vibration from initial "
            "conditions.")
        initial_conditions: _deferred(InitialConditions) = Field(
            _AT_REST, description="State at t = 0 (default: at rest).")
        analysis: Analysis = Field(description="Time integration: integrator, step dt (s), "
                                   "duration (s), Newton settings.")
        recorders: list[tagged([History, Envelope], "kind")] = Field(
            default_factory=lambda: [
                Envelope(kind="envelope", quantities=["displacement", "story_drift", "contact_force"])
            ],
            description="What the result file keeps: histories (kind: history) and peaks (kind: "
                        "envelope); default: the peaks of displacement, story_drift and "
                        "contact_force.")
        output: _deferred(Output) = Field(_SI_OUTPUT, description="Units of the result file.")
        limits: _LIMITS | None = Field(None, description="Limits on the peak storey drift "
                                      "ratio and floor acceleration, checked after the run "
                                      "(docs/modes.md#limits).")

        def __repr__(self) -> str:
            return scene_text(self)

        __str__ = __repr__

        def _repr_html_(self) -> str:
            return scene_html(self)

        def to_yaml(self) -> str:
            """The scene as YAML: the fields that were given (defaults left out), in the
            order of the reference; ``pframe.load`` of it gives an equal scene."""
            from pframe.yamltext import dump

            return dump(given_fields(self))

    return Scene


def __getattr__(name: str):
    # ``Scene`` (the built-in laws) is built on first use (PEP 562), not on import: reading a
    # scene file builds the class it needs through scene_class(contact_laws, materials)
    if name == "Scene":
        return scene_class()
    if name in _MOTION_NAMES:  # made apart (pframe.model.scene_motions)
        from pframe.model import scene_motions

        return getattr(scene_motions, name)
    if name in _OPTION_NAMES:  # made apart (pframe.model.scene_options)
        from pframe.model import scene_options

        return getattr(scene_options, name)
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")


def __dir__() -> list[str]:
    return sorted(set(globals()) | {"Scene"} | _MOTION_NAMES | _OPTION_NAMES)
