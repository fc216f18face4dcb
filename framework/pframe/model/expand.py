"""From a validated scene to resolved elements: building shorthand expanded, names resolved to
indices, law parameters packed into numbers. Every problem is reported at its YAML path."""

from __future__ import annotations

import math
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from pframe.errors import InputError
from pframe.excitation import ground_acceleration, read_record
from pframe.excitation.characteristic import apply_record
from pframe.excitation.describe import applied_motion, motion_warnings
from pframe.excitation.records import RecordUnitsError
from pframe.excitation.stochastic import stochastic_record, stochastic_warnings
from pframe.laws import ContactContext, StoreyContext, get_law
from pframe.laws.restitution import published_rebound
from pframe.model.load import ModelError
from pframe.model.scene import default_contact_name, default_link_name, default_story_name
from pframe.resources import check_floors, check_steps, steps_of


@dataclass(frozen=True)
class Element:
    """A storey or contact resolved to node indices (-1 = ground) and packed numbers."""

    name: str
    nodes: tuple[int, int]
    law: type
    packed: tuple[float, ...]
    gap: float = 0.0
    #: a floor-to-column contact: the struck storey's lower floor on each side (-1: none or
    #: the ground), the weight psi of the named node (1: a floor) and where the column is
    #: struck (the fraction of the storey's height; NaN: a floor)
    lower: tuple[int, int] = (-1, -1)
    share: tuple[float, float] = (1.0, 1.0)
    shear_capacity: float | None = None
    at: tuple[float, float] = (math.nan, math.nan)

    @property
    def column_side(self) -> int | None:
        """The side (0 left, 1 right) of a floor-to-column contact whose node tops the struck
        storey; None for a contact between floors (or a floor and a wall)."""
        return next((side for side in (0, 1) if not math.isnan(self.at[side])), None)

    @property
    def column_weight(self) -> float | None:
        """The struck column's shear per unit contact force of a floor-to-column contact,
        max(psi, 1 - psi): its segments carry psi F (above the struck point) and
        (1 - psi) F (below it), the end reactions of a member fixed at both floors under a
        point load (:func:`column_share`); None for a contact between floors."""
        side = self.column_side
        return None if side is None else max(self.share[side], 1.0 - self.share[side])


#: a floor-to-column contact's ``at`` may differ from the one its storey heights give by this
#: much (the rounding of a value written with three decimals); more is a contradiction
AT_TOLERANCE = 1e-3


def column_share(at: float) -> float:
    """psi = 3 at^2 - 2 at^3 of a column struck ``at`` of the way up its storey.

    The column is a member fixed at both floors (the floors' rotations neglected, as a shear
    building's): psi is the deflection at ``at`` when its upper end sways by 1 with its lower
    end fixed (the cubic of a fixed-fixed member), and, by reciprocity, the reaction at the
    upper end of a unit load at ``at``, R_upper = a^2 (a + 3 b) / L^3 = psi, R_lower =
    b^2 (3 a + b) / L^3 = 1 - psi (a = at L, b = L - a: AISC Steel Construction Manual,
    Table 3-23, case 16, beam fixed at both ends, concentrated load at any point). So the
    contact force F goes to the upper floor as psi F and to the lower floor as (1 - psi) F,
    and the column's two segments carry those shears.
    """
    return at * at * (3.0 - 2.0 * at)


def elevations(stories, heights) -> dict[int, float]:
    """Node index -> its elevation above the ground (m; -1, the ground, at 0): a storey's
    upper floor stands its height above its lower floor. Floors above a storey without a
    height (NaN) are left out."""
    above: dict[int, list] = {}
    for story, h in zip(stories, heights):
        above.setdefault(story.nodes[0], []).append((story.nodes[1], float(h)))
    level, todo = {-1: 0.0}, [-1]
    while todo:
        node = todo.pop()
        for upper, h in above.get(node, ()):
            if math.isfinite(h) and upper not in level:
                level[upper] = level[node] + h
                todo.append(upper)
    return level


@dataclass(frozen=True)
class FoundationSoil:
    """A building's foundation on soil (docs/soil.md): its two DOFs' masses, the springs and
    dashpots to the ground, and where they came from."""

    building: int  # index into Expanded.buildings
    sway_stiffness: float  # K_h (N/m)
    sway_damping: float  # C_h (N s/m)
    rocking_stiffness: float  # K_r (N m/rad)
    rocking_damping: float  # C_r (N m s/rad)
    mass: float  # m_f (kg)
    rotational_inertia: float  # I_f (kg m^2), with the cone's trapped soil
    trapped_inertia: float = 0.0  # the cone's trapped soil (kg m^2), included above
    source: str = "given"  # "cone" (Wolf's cone model) or "given"

    def describe(self) -> str:
        """What was applied, in one line (the run summary, the result's attributes)."""
        trapped = (f" (with {self.trapped_inertia:.4g} kg m^2 of trapped soil)"
                   if self.trapped_inertia else "")
        how = "Wolf's cone model" if self.source == "cone" else "given"
        return (f"K_h = {self.sway_stiffness:.4g} N/m, C_h = {self.sway_damping:.4g} N s/m, "
                f"K_r = {self.rocking_stiffness:.4g} N m/rad, C_r = "
                f"{self.rocking_damping:.4g} N m s/rad ({how}); m_f = {self.mass:.4g} kg, "
                f"I_f = {self.rotational_inertia:.4g} kg m^2{trapped}")


def foundation_soil(soil, building: int) -> FoundationSoil:
    """The springs, dashpots and inertias of a scene's ``soil`` (pframe.model.scene.Soil)."""
    from pframe.model import soil as cone_model

    f = soil.foundation
    if f.radius is not None:
        r_h = r_r = f.radius
        slab = f.mass * f.radius**2 / 4.0
    elif f.width is not None:
        length = f.length if f.length is not None else f.width
        r_h, r_r = cone_model.equivalent_radii(f.width, length)
        slab = f.mass * f.width**2 / 12.0
    else:
        slab = None
    inertia = f.rotational_inertia if f.rotational_inertia is not None else slab
    if soil.shear_wave_velocity is None:
        return FoundationSoil(building, soil.sway_stiffness, soil.sway_damping,
                              soil.rocking_stiffness, soil.rocking_damping, f.mass, inertia)
    c = cone_model.cone(soil.shear_wave_velocity, soil.poisson, soil.density, r_h, r_r)
    return FoundationSoil(building, c.sway_stiffness, c.sway_damping, c.rocking_stiffness,
                          c.rocking_damping, f.mass, inertia + c.trapped_inertia,
                          c.trapped_inertia, "cone")


@dataclass(frozen=True)
class Expanded:
    """A scene resolved to numbers, in declaration order (no DOF numbering yet)."""

    buildings: tuple[str, ...]
    node_names: tuple[str, ...]
    node_building: np.ndarray  # (n,) index into buildings
    masses: np.ndarray  # (n,) kg
    stories: tuple[Element, ...]
    story_building: np.ndarray  # (s,)
    contacts: tuple[Element, ...]
    links: tuple[Element, ...]  # (first, second): deformation u_second - u_first
    damping: tuple  # Rayleigh definition per building
    ground_acceleration: np.ndarray  # (steps + 1,) m/s^2
    initial_displacement: np.ndarray
    initial_velocity: np.ndarray
    dt: float
    steps: int
    integrator: object  # the integrator's definition (pframe.integrators)
    tolerance: float
    absolute_tolerance: float
    max_iterations: int
    recorders: tuple
    #: the record as applied (pframe.excitation.characteristic.AppliedRecord), for a record
    record: object = None
    #: the excitation's definition (Sine, Record, a pulse or None): its time scales are
    #: checked against dt (pframe.assemble.timescales)
    excitation: object = None
    #: reference scales a Pi-form scene left at 1 ('m_b' kg, 'w_p' rad/s): its masses or
    #: times are then ratios, not a building's, and are not judged as such
    unit_scales: tuple[str, ...] = ()
    #: index of the reference building (its first floor mass is the mass scale m_b)
    reference: int = 0
    #: what the run will be told (pframe solve prints them; the result file keeps them)
    warnings: tuple[str, ...] = ()
    #: (s,) storey heights (m), NaN where the scene gives none; (s,) gravity loads P (N) of
    #: the storeys with P-delta (0: none)
    story_height: np.ndarray = None
    story_gravity: np.ndarray = None
    #: what validate shows besides (facts the scene chose explicitly)
    notes: tuple[str, ...] = ()
    #: the foundations on soil (FoundationSoil), in building order; none: every base fixed
    foundations: tuple = ()
    #: (s,) what each storey's ``isolator`` and ``stiffness_damping`` say: True, False or
    #: None (not said: pframe.assemble.modes decides); empty: none said (every None)
    story_isolator: tuple = ()
    story_stiffness_damping: tuple = ()


#: standard gravity (m/s^2), for the storeys' gravity loads under P-delta
GRAVITY = 9.80665


def _validation_message(exc: Exception) -> str:
    """A storey's parameter error in one line: each pydantic error as ``field: message`` (a
    check across fields has no field), never pydantic's closing link to its documentation."""
    errors = getattr(exc, "errors", None)
    if callable(errors):
        parts = []
        for error in errors():
            text = str(error.get("msg", "")).removeprefix("Value error, ")
            where = ".".join(str(part) for part in error.get("loc", ()))
            parts.append(f"{where}: {text}" if where else text)
        if parts:
            return "; ".join(parts)
    return str(exc)


def _per_storey(value, n: int, path):
    if isinstance(value, list):
        if len(value) != n:
            raise ModelError(path, f"expected one value per storey ({n}), got {len(value)}")
        return value
    return [value] * n


def _building_nodes(scene, nodes, stories, damping, foundations):
    """Expand the building shorthand into (name, mass, path) nodes and storeys, and the
    foundations on soil into (building index, FoundationSoil)."""
    for b, building in enumerate(scene.buildings):
        path = ("buildings", b)
        if building.soil is not None:
            if building.height is None:
                raise ModelError(path + ("soil",), "soil needs the storey heights (the "
                                 "rocking's lever): give height (m, one for all storeys or "
                                 "one per storey)")
            if building.p_delta:
                raise ModelError(path + ("p_delta",), "P-delta on soil is not modelled (the "
                                 "rocking's overturning moment of the gravity loads): remove "
                                 "p_delta or soil")
            foundations.append((b, foundation_soil(building.soil, b)))
        lists = {"mass": building.mass} | {
            k: v for k, v in building.story.model_dump().items() if isinstance(v, list)
        }
        lengths = {k: len(v) for k, v in lists.items() if isinstance(v, list)}
        n = building.floors or (max(lengths.values()) if lengths else None)
        if n is None:
            raise ModelError(path, "give floors (the number of storeys) or per-floor lists")
        masses = _per_storey(building.mass, n, path + ("mass",))
        fields = {
            key: _per_storey(value, n, path + ("story", key)) if key != "material" else value
            for key, value in building.story.model_dump().items()
        }
        law = get_law("material", building.story.material)
        damping[building.name] = building.damping
        heights = (_per_storey(building.height, n, path + ("height",))
                   if building.height is not None else [None] * n)
        if building.park_ang is not None:  # one ultimate drift per storey (pframe.demands)
            _per_storey(building.park_ang.ultimate_drift, n, path + ("park_ang", "ultimate_drift"))
        if building.p_delta and building.height is None:
            raise ModelError(path + ("p_delta",), "P-delta needs the storey heights: give "
                             "height (m, one for all storeys or one per storey)")
        above = np.cumsum(np.asarray(masses, dtype=float)[::-1])[::-1]  # floors i..n
        for i in range(n):
            name = f"{building.name}/{i + 1}"
            nodes.append((name, masses[i], path + ("name",)))
            raw = {k: (v if k == "material" else v[i]) for k, v in fields.items()}
            raw = {k: v for k, v in raw.items() if v is not None}
            try:
                params = law.Params.model_validate(raw)
            except Exception as exc:
                msg = _validation_message(exc)
                raise ModelError(path + ("story",), f"storey {i + 1}: {msg}") from None
            lower = "ground" if i == 0 else f"{building.name}/{i}"
            stories.append((name, (lower, name), law, params, path + ("story",), heights[i],
                            GRAVITY * float(above[i]) if building.p_delta else 0.0))


def _finite(packed, path) -> tuple[float, ...]:
    """A law's packed parameters, which must be finite numbers."""
    out = tuple(map(float, packed))
    if not all(np.isfinite(out)):
        raise ModelError(path, "these values give the law a parameter that is not a finite "
                               f"number ({', '.join(f'{v:.4g}' for v in out)}); they are too "
                               "small or too large for each other: check the units")
    return out


def _check_size(scene) -> None:
    """Refuse, before building them, more floors than the machine can hold, or than pframe
    sets up without the opt-in PFRAME_MAX_FLOORS (resources.MAX_FLOORS)."""
    total = len(scene.nodes)
    for building in scene.buildings:
        lengths = [len(v) for v in [building.mass, *building.story.model_dump().values()]
                   if isinstance(v, list)]
        total += building.floors or max(lengths, default=0)
    # each floor has its storey; generic storeys and contacts are elements of their own
    elements = 2 * total - len(scene.nodes) + len(scene.stories) + len(scene.contacts)
    problem = check_floors(total, elements,
                           steps_of(scene.analysis.duration, scene.analysis.dt))
    if problem:
        raise ModelError(("buildings",), problem)


def _masses_above(stories, index, masses) -> dict:
    """node name -> the mass of that node and of every node above it (kg): the nodes reached
    upward through storeys (lower -> upper), each counted once along each storey (a tree, as
    buildings are). One pass over the storeys, whatever the height. Unknown names are left to
    the caller's check; a storey loop (refused elsewhere) is cut where it closes."""
    upward: dict[str, list[str]] = {}
    for story in stories:  # (name, (lower, upper), law, params, path, ...)
        lower, upper = story[1]
        upward.setdefault(lower, []).append(upper)
    carried: dict[str, float] = {}
    for start in {story[1][1] for story in stories}:
        if start in carried:
            continue
        todo, open_ = [(start, False)], set()
        while todo:  # post-order: a node's total once every node above it has one
            name, done = todo.pop()
            if done:
                open_.discard(name)
                carried[name] = (float(masses[index[name]]) if name in index else 0.0) + sum(
                    carried.get(up, 0.0) for up in upward.get(name, ()) if up not in open_)
                continue
            if name in carried or name in open_:
                continue
            open_.add(name)
            todo.append((name, True))
            todo += [(up, False) for up in upward.get(name, ()) if up not in carried]
    return carried


_SAMPLES: dict = {}  # (excitation as JSON, steps, dt) -> its samples, read-only


def _function_samples(excitation, steps: int, dt: float) -> np.ndarray:
    """a_g at t_n = n dt, n = 0..steps, of a motion given as a function of time, computed
    once for the expansions that ask for the same samples (the variants of a sweep); the
    array is shared, hence read-only."""
    if excitation is None:
        return ground_acceleration(None, np.arange(steps + 1) * dt)
    key = (excitation.model_dump_json(), steps, dt)
    samples = _SAMPLES.get(key)
    if samples is None:
        samples = ground_acceleration(excitation, np.arange(steps + 1) * dt)
        samples.setflags(write=False)
        if len(_SAMPLES) >= 8:  # a few motions at a time: memory stays bounded
            _SAMPLES.pop(next(iter(_SAMPLES)), None)
        _SAMPLES[key] = samples
    return samples


def expand(scene, base_dir: Path | str = ".") -> Expanded:
    """Resolve a validated scene; raises :class:`ModelError` with the YAML path of a problem."""
    nodes: list = []
    stories: list = []
    damping: dict = {}
    if len({b.name for b in scene.buildings}) != len(scene.buildings):
        seen = set()
        for b, building in enumerate(scene.buildings):
            if building.name in seen:
                raise ModelError(("buildings", b, "name"),
                                 f"building {building.name!r} is defined twice")
            seen.add(building.name)
    _check_size(scene)
    shorthand_foundations: list = []
    _building_nodes(scene, nodes, stories, damping, shorthand_foundations)
    for i, node in enumerate(scene.nodes):
        nodes.append((node.name, node.mass, ("nodes", i, "name")))
    if not nodes:
        raise ModelError(("buildings",), "the scene has no floors; give at least one building "
                                         "(name, floors, mass, story), or nodes and stories")
    index: dict[str, int] = {}
    for i, (name, _, path) in enumerate(nodes):
        if name in index:
            raise ModelError(path, f"node {name!r} is defined twice (building shorthand and "
                                   "nodes, or twice in nodes)")
        index[name] = i
    building_of = [name.split("/")[0] for name, _, _ in nodes]
    buildings = tuple(dict.fromkeys(building_of))

    def node_index(name, path):
        if name not in index:
            raise ModelError(path, f"no node named {name!r}; nodes are "
                                   f"{', '.join(list(index)[:12])}{' ...' if len(index) > 12 else ''}")
        return index[name]

    flags = [(None, None)] * len(stories)  # (isolator, stiffness_damping) of each storey
    for s, story in enumerate(scene.stories):
        flags.append((story.isolator, story.stiffness_damping))
        law = get_law("material", story.material)
        params = law.Params.model_validate(story.model_dump(include=set(law.Params.model_fields)))
        if story.gravity_load is not None and story.height is None:
            raise ModelError(("stories", s, "gravity_load"), "P-delta needs the storey's "
                             "height: give height (m)")
        if story.park_ang is not None and isinstance(story.park_ang.ultimate_drift, list):
            raise ModelError(("stories", s, "park_ang", "ultimate_drift"), "one storey has one "
                             "ultimate drift (m), not a list")
        stories.append((story.name or default_story_name(story.nodes), story.nodes, law, params,
                        ("stories", s), story.height, float(story.gravity_load or 0.0)))

    carried: dict = {}

    def mass_above(upper: str) -> float:  # computed for every storey at the first request
        if not carried:
            carried.update(_masses_above(stories, index, [m for _, m, _ in nodes]))
        return carried[upper]

    story_elements, story_building, seen = [], [], {}
    for name, (lower, upper), law, params, path, _, _ in stories:
        up = node_index(upper, path + ("nodes", 1))
        low = -1 if lower == "ground" else node_index(lower, path + ("nodes", 0))
        if low >= 0 and building_of[low] != building_of[up]:
            raise ModelError(path + ("nodes",), f"a storey joins floors of one building; "
                                                f"{lower!r} and {upper!r} are in two")
        if low == up:
            raise ModelError(path + ("nodes",), "a storey needs two different nodes")
        if name in seen:
            raise ModelError(path, f"storey name {name!r} is used twice")
        seen[name] = True
        try:
            packed = law.pack(params, StoreyContext(lambda upper=upper: mass_above(upper)))
        except InputError as exc:
            raise ModelError(path, str(exc)) from None
        story_elements.append(Element(name, (low, up), law, _finite(packed, path)))
        story_building.append(buildings.index(building_of[up]))

    for name, (_, _), law, _, path, _, _ in stories:
        if getattr(law, "stiffness_free", False):
            raise ModelError(path + ("material",), f"storey {name!r}: a {law.name} has no "
                             "stiffness and cannot carry a storey; put it in links (a damper "
                             "across the storey: nodes [lower, upper])")
    link_elements = []
    for i, link in enumerate(scene.links):
        path = ("links", i)
        if link.nodes[0] == "ground" and link.nodes[1] == "ground":
            raise ModelError(path + ("nodes",), "a link needs a node on at least one side")
        first, second = (-1 if node == "ground" else node_index(node, path + ("nodes", j))
                         for j, node in enumerate(link.nodes))
        if first == second:
            raise ModelError(path + ("nodes",), "a link needs two different nodes")
        name = link.name or default_link_name(link.nodes)
        if name in seen:
            raise ModelError(path + ("name",), f"link name {name!r} is used twice (storeys "
                                               "and links share their names)")
        seen[name] = True
        law = get_law("material", link.material)
        params = law.Params.model_validate(link.model_dump(include=set(law.Params.model_fields)))
        try:
            packed = law.pack(params)
        except InputError as exc:  # e.g. a friction pendulum's weight: a link carries none
            raise ModelError(path, f"link {name!r}: {exc}") from None
        link_elements.append(Element(name, (first, second), law, _finite(packed, path)))
    floating = _check_held(scene, nodes, story_elements, link_elements)

    record = None
    if scene.excitation is not None and scene.excitation.kind == "record":
        file = Path(base_dir) / scene.excitation.file
        try:
            record = read_record(file, scene.excitation.format, scene.excitation.units,
                                 within=base_dir)
        except FileNotFoundError:
            raise ModelError(("excitation", "file"), f"record file {str(file)!r} not found") from None
        except RecordUnitsError as exc:  # the header and the scene disagree on the units
            where = "units" if scene.excitation.units is not None else "file"
            raise ModelError(("excitation", where), str(exc)) from None
        except (ValueError, OSError) as exc:
            raise ModelError(("excitation", "file"), f"malformed record: {exc}") from None
        try:
            record = apply_record(scene.excitation, *record)
        except InputError as exc:
            raise ModelError(("excitation", "file"), str(exc)) from None
    if scene.excitation is not None and scene.excitation.kind == "stochastic":
        try:
            record = stochastic_record(scene.excitation)
        except ValueError as exc:
            raise ModelError(("excitation",), f"cannot simulate the motion: {exc}") from None
    excitation_frequency = None  # of frequency_ratio (Pi_wcon = w_bar / w_p): a sine's
    if scene.excitation is not None and scene.excitation.kind == "sine":
        excitation_frequency = scene.excitation.frequency
    masses = np.array([m for _, m, _ in nodes], dtype=float)
    contacts, seen, rebounds = [], {}, {}
    level = None  # the floors' elevations, for the floor-to-column contacts
    for c, contact in enumerate(scene.contacts):
        path = ("contacts", c)
        if contact.nodes[0] == "ground" and contact.nodes[1] == "ground":
            raise ModelError(path + ("nodes",), "a contact needs a node on at least one side; "
                                                "'ground' on one side is a wall")
        left, right = (-1 if node == "ground" else node_index(node, path + ("nodes", i))
                       for i, node in enumerate(contact.nodes))
        name = contact.name or default_contact_name(contact.nodes)
        if left >= 0 and right >= 0:
            if building_of[left] == building_of[right]:
                raise ModelError(path + ("nodes",), "a contact joins nodes of two different "
                                 f"buildings (or a node and a wall: 'ground'); both nodes are "
                                 f"in {building_of[left]!r}")
            _check_row_order(name, buildings, building_of[left], building_of[right],
                             contact.nodes, path + ("nodes",))
        if name in seen:
            raise ModelError(path + ("name",), f"contact name {name!r} is used twice")
        seen[name] = True
        law = get_law("contact", contact.law)
        params = law.Params.model_validate(contact.model_dump(include=set(law.Params.model_fields)))
        lower, share, at = [-1, -1], [1.0, 1.0], [math.nan, math.nan]
        side_mass = [masses[left] if left >= 0 else math.inf,
                     masses[right] if right >= 0 else math.inf]
        if contact.column is None and contact.at is not None:
            raise ModelError(path + ("at",), "at is where a column is struck: give column "
                                             "(the side whose node names the struck storey)")
        if contact.column is None and contact.shear_capacity is not None:
            raise ModelError(path + ("shear_capacity",), "shear_capacity is a struck "
                             "column's: give column (a floor-to-column contact); a "
                             "floor-to-floor contact loads no column between floors")
        if contact.column is not None:
            if level is None:
                level = elevations(story_elements, [math.nan if h is None else h
                                                    for *_, h, _ in stories])
            side, lower[side], at[side] = _struck_column(contact, path, (left, right),
                                                         story_elements, level, index)
            upper = (left, right)[side]
            share[side] = column_share(at[side])
            inverse = share[side] ** 2 / masses[upper] + (
                (1.0 - share[side]) ** 2 / masses[lower[side]] if lower[side] >= 0 else 0.0)
            side_mass[side] = 1.0 / inverse
        # a wall is the ground: of infinite mass, the impact's effective mass is the floor's;
        # a column point has the mass its displacement's weights give it
        context = ContactContext(side_mass[0], side_mass[1], excitation_frequency)
        try:
            with np.errstate(all="ignore"):
                packed = _finite(law.pack(params, context), path)
        except InputError as exc:
            raise ModelError(path, str(exc)) from None
        contacts.append(Element(name, (left, right), law, packed, float(contact.gap),
                                tuple(lower), tuple(share), contact.shear_capacity, tuple(at)))
        obtained = published_rebound(law, params)
        if obtained is not None:
            chosen = "calibration" in contact.model_fields_set
            key = (chosen, contact.law, law.published_source(params), params.restitution, obtained)
            rebounds.setdefault(key, []).append(name)

    analysis = scene.analysis
    count = steps_of(analysis.duration, analysis.dt)
    problem = check_steps(count, analysis.dt, analysis.duration)
    if problem:
        raise ModelError(("analysis", "dt" if analysis.dt < 1e-7 else "duration"), problem)
    steps = int(round(count))
    if steps < 1:
        raise ModelError(("analysis", "duration"), f"duration {analysis.duration} s is shorter "
                                                   f"than one step dt = {analysis.dt} s")
    if record is None:  # a function of time (a sine, a pulse): shared by a sweep's variants
        ag = _function_samples(scene.excitation, steps, analysis.dt)
    else:
        ag = ground_acceleration(scene.excitation, np.arange(steps + 1) * analysis.dt,
                                 (record.times, record.acceleration))

    reference = 1 if len(buildings) > 1 else 0
    chosen = scene.output.reference
    if chosen is not None:
        if chosen not in buildings:
            raise ModelError(("output", "reference"), f"no building named {chosen!r}; the "
                             f"buildings are {', '.join(buildings)}")
        reference = buildings.index(chosen)

    u0, v0 = np.zeros(len(nodes)), np.zeros(len(nodes))
    for field, target in (("displacement", u0), ("velocity", v0)):
        for name, value in getattr(scene.initial_conditions, field).items():
            target[node_index(name, ("initial_conditions", field, name))] = value

    return Expanded(
        buildings=buildings,
        node_names=tuple(name for name, _, _ in nodes),
        node_building=np.array([buildings.index(b) for b in building_of], dtype=np.int64),
        masses=masses,
        stories=tuple(story_elements),
        story_building=np.array(story_building, dtype=np.int64),
        contacts=tuple(contacts),
        links=tuple(link_elements),
        story_height=np.array([np.nan if h is None else float(h) for *_, h, _ in stories]),
        story_gravity=np.array([float(g) for *_, g in stories]),
        damping=tuple(damping.get(b) or scene.damping for b in buildings),
        ground_acceleration=ag,
        initial_displacement=u0,
        initial_velocity=v0,
        dt=float(analysis.dt),
        steps=steps,
        integrator=analysis.integrator,
        tolerance=analysis.newton.tolerance,
        absolute_tolerance=analysis.newton.absolute_tolerance,
        max_iterations=analysis.newton.max_iterations,
        recorders=tuple(scene.recorders),
        record=record,
        excitation=scene.excitation,
        reference=reference,
        warnings=tuple(_rebound_text(key, names) for key, names in rebounds.items() if not key[0])
        + tuple(motion_warnings(applied_motion(scene.excitation, record, steps * analysis.dt)))
        + tuple(stochastic_warnings(scene.excitation)) + floating,
        notes=tuple(_rebound_text(key, names) for key, names in rebounds.items() if key[0]),
        foundations=_foundations(shorthand_foundations, scene, buildings, building_of),
        story_isolator=tuple(f[0] for f in flags) if any(f != (None, None) for f in flags)
        else (),
        story_stiffness_damping=tuple(f[1] for f in flags)
        if any(f != (None, None) for f in flags) else (),
    )


def _struck_column(contact, path, ends, stories, level, index) -> tuple[int, int, float]:
    """``(side, lower floor, at)`` of a floor-to-column contact: the side whose node tops the
    struck storey, that storey's lower floor (-1: the ground) and where it is struck.

    When the elevations of the striking floor and of the struck storey's two floors are known
    (every storey below them has a height), ``at = (z_floor - z_lower) / (z_upper - z_lower)``
    and must lie strictly between 0 and 1: a floor level with one of the storey's floors is a
    floor-to-floor contact, one outside the storey cannot strike it; a given ``at`` that
    differs from it by more than :data:`AT_TOLERANCE` is refused. Otherwise ``at`` is
    required."""
    names = {i: n for n, i in index.items()} | {-1: "ground"}
    side = 0 if contact.column == "left" else 1
    upper, floor = ends[side], ends[1 - side]
    below = [s for s in stories if s.nodes[1] == upper] if upper >= 0 else []
    if not below:
        raise ModelError(path + ("column",), f"the {contact.column} node "
                         f"{contact.nodes[side]!r} tops no storey: a struck column is named "
                         "by the floor above it")
    lower = below[0].nodes[0]
    if floor < 0 or not {floor, lower, upper} <= level.keys():
        if contact.at is None:
            raise ModelError(path + ("at",), "a floor-to-column contact needs at, where the "
                             "column is struck (0 < at < 1 of the storey's height), when the "
                             "heights of the striking floor and of the struck storey are not "
                             "known: give at, or the storey heights (height) of both "
                             "buildings, from which pframe computes it")
        return side, lower, float(contact.at)
    z, bottom, top = level[floor], level[lower], level[upper]
    where = (f"floor {names[floor]} at {z:g} m and the storey below {names[upper]}, from "
             f"{bottom:g} to {top:g} m")
    for end, height in ((lower, bottom), (upper, top)):
        if math.isclose(z, height, rel_tol=1e-9, abs_tol=1e-9):
            raise ModelError(path + ("column",), f"{where}: the floor is level with "
                             f"{names[end]}, a floor-to-floor contact; name those two floors "
                             "in nodes, without column and at")
    at = (z - bottom) / (top - bottom)
    if not 0.0 < at < 1.0:
        raise ModelError(path + ("nodes",), f"{where}: the floor cannot strike that storey "
                         f"(it is {'below' if at < 0 else 'above'} it); name the storey the "
                         f"floor faces, by its upper floor")
    if contact.at is not None and abs(contact.at - at) > AT_TOLERANCE:
        raise ModelError(path + ("at",), f"at {contact.at:g} contradicts the storey heights: "
                         f"{where} put the struck point at {at:.6g} of the storey; leave at "
                         "out (pframe computes it from the heights) or correct the heights")
    return side, lower, at


def _check_held(scene, nodes, stories, links) -> tuple[str, ...]:
    """Refuse a node that nothing holds to the ground in a building that has storeys: no chain
    of storeys, links with a stiffness or (a shorthand building's) soil joins it to the ground,
    and it is not declared ``free``. Such a floor floats (a storey left out, a node
    mistyped): the static stiffness is singular, and a run would complete with the floor
    drifting as a free body. A contact does not hold it (it acts only once closed), nor does a
    dashpot (a stiffness-free link). The nodes of a building without storeys are free bodies
    by design (masses that strike each other or a wall): under a ground motion a warning says
    what they do (the ground moves under them), unless they are declared ``free``."""
    parent = list(range(len(nodes) + 1))  # the last entry is the ground

    def root(i):
        while parent[i] != i:
            parent[i] = parent[parent[i]]
            i = parent[i]
        return i

    ground = len(nodes)
    for element in list(stories) + [e for e in links
                                    if not getattr(e.law, "stiffness_free", False)]:
        a, b = (ground if i < 0 else i for i in element.nodes)
        parent[root(a)] = root(b)
    free = {n.name for n in scene.nodes if n.free}
    with_storeys = {nodes[e.nodes[1]][0].split("/")[0] for e in stories}
    loose = [i for i, (name, _, _) in enumerate(nodes)
             if root(i) != root(ground) and name not in free]
    refused = [i for i in loose if nodes[i][0].split("/")[0] in with_storeys]
    if refused:
        first = refused[0]
        group = [nodes[i][0] for i in loose if root(i) == root(first)]
        what = (f"node {group[0]!r}" if len(group) == 1 else
                f"nodes {', '.join(repr(g) for g in group)} (joined to each other)")
        it = "it" if len(group) == 1 else "them"
        raise ModelError(nodes[first][2], f"{what}: no storey, link with a stiffness or soil "
                         f"holds {it} to the ground (a contact does not, nor a dashpot), though "
                         f"the building has storeys; {it} would float, with no stiffness to "
                         f"return {it}. Give {it} a storey (nodes: [ground or the floor below, "
                         f"{group[0]}]) or a link with a stiffness, or write free: true on "
                         f"{'the node' if len(group) == 1 else 'each node'} if {it} is meant "
                         "to be a free body")
    if not loose or scene.excitation is None:
        return ()
    names = [nodes[i][0] for i in loose]
    return (f"node{'s' if len(names) > 1 else ''} {', '.join(names[:6])}"
            f"{' ...' if len(names) > 6 else ''}: no storey, link with a stiffness or soil "
            "holds them to the ground, so they are free bodies: the ground motion moves under "
            "them (their displacement relative to the ground is -u_g until a contact or a "
            "dashpot acts); write free: true on them if that is meant, or give them storeys",)


def _foundations(shorthand, scene, buildings, building_of) -> tuple:
    """The foundations on soil, re-indexed to ``buildings``; a building on soil has only its
    shorthand floors (a generic node or storey of it has no rocking lever)."""
    out = []
    for b, soil in shorthand:
        name = scene.buildings[b].name
        for i, node in enumerate(scene.nodes):
            if node.name.split("/")[0] == name:
                raise ModelError(("nodes", i, "name"), f"building {name!r} stands on soil; "
                                 "its floors come from the building shorthand only (a generic "
                                 "node of it would not rock with its foundation)")
        out.append(FoundationSoil(**{**soil.__dict__, "building": buildings.index(name)}))
    return tuple(out)


def _check_row_order(name, buildings, left, right, nodes, path) -> None:
    """A contact's nodes are [left, right] in the row the scene declares: the buildings stand
    from left to right in the order they are first declared (``buildings``, then the
    buildings of ``nodes``). A contact written the other way round closes when its buildings
    move apart, so it is refused (docs/yaml-reference.md)."""
    if buildings.index(left) < buildings.index(right):
        return
    raise ModelError(path, f"contact {name!r} has {nodes[0]!r} on the left of {nodes[1]!r}, but "
                           "the buildings stand from left to right in the order the scene "
                           f"declares them ({', '.join(buildings)}), so {left} is right of "
                           f"{right}: a contact's nodes are [left, right] (penetration u_left - "
                           "u_right - gap) and this one would close when the buildings move "
                           f"apart; write nodes [{nodes[1]}, {nodes[0]}], or declare the "
                           "buildings in their left-to-right order")


def _rebound_text(key, names) -> str:
    """What a published damping formula gives instead of the restitution asked for."""
    chosen, law, source, requested, obtained = key
    which = f"contact{'s' if len(names) > 1 else ''} {', '.join(names)}"
    if chosen:
        return (f"{which} ({law}, calibration: published, {source}): restitution {requested:g} "
                f"rebounds with {obtained:.3f} in a two-body impact")
    return (f"{which} ({law}): restitution {requested:g} is asked for, but the default "
            f"calibration: published ({source}) rebounds with {obtained:.3f} in a two-body "
            f"impact; add 'calibration: exact' to the contact to get {requested:g} (or write "
            "'calibration: published' to keep the published formula; docs/restitution.md)")
