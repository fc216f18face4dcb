"""The floors of a scene and the storey springs between them, before they are resolved to
indices: the building shorthand expanded (a planar storey per storey, or the building's lines
of resistance in every storey), the generic nodes and storeys added, each floor placed on the
site (docs/plan.md). Every problem is reported at its YAML path (:class:`ModelError`)."""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from pframe.laws import get_law
from pframe.model.load import ModelError
from pframe.model.plan import Placement, unit
from pframe.model.rows import Rows, Run, column, one_object
from pframe.model.scene import default_story_name

#: standard gravity (m/s^2), for the storeys' gravity loads under P-delta
GRAVITY = 9.80665


@dataclass(frozen=True)
class Floor:
    """A node: a floor (a rigid diaphragm) with its mass at its centre of mass.

    ``centre`` is in site coordinates (m); ``inertia`` its polar moment J (kg m^2) or None
    when the scene gives no way to know it; ``points`` its building's named plan points
    (building axes); ``placement`` where its building stands."""

    name: str
    mass: float
    path: tuple
    centre: tuple[float, float] = (0.0, 0.0)
    inertia: float | None = None
    placement: Placement = field(default_factory=Placement)
    plan: object = None  # pframe.model.plan.FloorPlan, or None
    points: dict = field(default_factory=dict)
    building_path: tuple = ()

    @property
    def building(self) -> str:
        return self.name.split("/")[0]

    def point(self, ref, path) -> tuple[float, float]:
        """A point of this floor in site coordinates: ``ref`` a named point of its building,
        [x, y] in its building's axes, or None (its centre of mass)."""
        if ref is None:
            return self.centre
        if isinstance(ref, str):
            if ref not in self.points:
                known = ", ".join(self.points) or "none (give the building a plan or points)"
                raise ModelError(path, f"building {self.building!r} has no point named {ref!r};"
                                       f" its points are {known}")
            ref = self.points[ref]
        local = (float(ref[0]), float(ref[1]))
        if self.plan is not None:
            extent = self.plan.extent()
            if not self.plan.contains(local, 1e-6 * extent):
                raise ModelError(path, f"the point [{local[0]:g}, {local[1]:g}] is outside "
                                       f"the plan of {self.name}'s floor (building axes, m); "
                                       "a contact or link acts at a point of the floor")
        return self.placement.point(local)


@dataclass(frozen=True)
class StoreySpec:
    """A storey spring (a planar storey, a line of resistance, a generic storey) between two
    floors by name, with its law, validated parameters and line: ``position`` in site
    coordinates (None: through the upper floor's centre of mass) and ``direction`` a unit
    vector of the site."""

    name: str
    nodes: tuple[str, str]
    law: type
    params: object
    path: tuple
    height: float | None
    gravity: float
    position: tuple[float, float] | None = None
    direction: tuple[float, float] = (1.0, 0.0)
    #: the storey (its upper floor's name) the spring belongs to: the lines of one storey
    storey: str = ""
    #: what the storey or line says of itself: an isolator, Rayleigh's stiffness term on it
    #: (None: not said)
    isolator: bool | None = None
    stiffness_damping: bool | None = None


@dataclass(frozen=True)
class Floors:
    """What :func:`floors` collects, in declaration order."""

    nodes: Rows  # of Floor (a run per building of the shorthand: pframe.model.rows)
    stories: Rows  # of StoreySpec
    damping: dict  # building name -> its damping definition (or None)
    foundations: tuple  # (building index in scene.buildings, FoundationSoil)
    #: storey (its upper floor) -> (its lower floor, the gravity load P (N), the load's
    #: centre (site, m), r^2 = J / m of the load (m^2), the height h (m), the YAML path) of
    #: each storey of a building in plan with P-delta (pframe.model.elements)
    gravity_centres: dict = field(default_factory=dict)


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


def per_storey(value, n: int, path):
    """``value`` as one item per storey: a list of n, or one value for all."""
    if isinstance(value, list):
        if len(value) != n:
            raise ModelError(path, f"expected one value per storey ({n}), got {len(value)}")
        return value
    return [value] * n


def _storey_params(law, fields: dict, i: int, path, validated: dict | None = None):
    """The validated parameters of storey ``i`` from fields that are one value or a list;
    storeys of the same values share one validation (``validated``: values -> parameters,
    the building's: a tall building's storeys are validated once, not one by one)."""
    raw = {k: (v if k == "material" else v[i]) for k, v in fields.items()}
    raw = {k: v for k, v in raw.items() if v is not None}
    key = tuple(raw.items())
    try:
        known = validated.get(key) if validated is not None else None
    except TypeError:  # a value that is not hashable: validated on its own
        known, validated = None, None
    if known is not None:
        return known
    try:
        params = law.Params.model_validate(raw)
    except Exception as exc:
        raise ModelError(path, f"storey {i + 1}: {_validation_message(exc)}") from None
    if validated is not None:
        validated[key] = params
    return params


def _one_for_all(law, fields: dict, path):
    """The parameters every storey shares when no field varies over them (each list one value
    repeated, the shorthand's usual case: validated once, not once per storey), else None."""
    if all(k == "material" or one_object(v) for k, v in fields.items()):
        return _storey_params(law, fields, 0, path)
    return None


def _material_fields(properties, n: int, path) -> tuple[type, dict]:
    """A material's law and its fields (one list per field, of n storeys) from a storey
    definition of the shorthand (``story`` or a line)."""
    fields = {}
    own = properties.model_dump()
    for key, value in own.items():
        if key == "material":
            fields[key] = value
        elif key in get_law("material", own["material"]).Params.model_fields:
            fields[key] = per_storey(value, n, path + (key,))
    return get_law("material", own["material"]), fields


def _storey_count(building, path) -> int:
    sources = [building.mass, *(building.story.model_dump().values() if building.story else ())]
    for line in building.lines or ():
        sources += [v for k, v in line.model_dump().items()
                    if k not in ("position", "storeys") and isinstance(v, list)]
    lengths = [len(v) for v in sources if isinstance(v, list)]
    n = building.floors or (max(lengths) if lengths else None)
    if n is None:
        raise ModelError(path, "give floors (the number of storeys) or per-floor lists")
    if n == 0:  # floors is at least 1: every per-floor list given is empty
        raise ModelError(path, "its per-floor lists are empty: give floors (the number of "
                               "storeys) or a value for each floor in them")
    return n


#: the automatic named point in the middle of a floor's named points' extent: its drift along
#: x (along y) is the mean of the drifts at the extent's two ends across y (across x), which
#: the torsional irregularity divides by (pframe.irregularity)
CENTRE = "centre"


def _add_centre(points: dict, building, path) -> None:
    """Add :data:`CENTRE` to a building's named points (two or more), the middle of their
    extent in its axes; a point of the user's of that name elsewhere is refused."""
    if len(points) < 2:
        return
    xs, ys = [p[0] for p in points.values()], [p[1] for p in points.values()]
    centre = (0.5 * (min(xs) + max(xs)), 0.5 * (min(ys) + max(ys)))
    given = points.get(CENTRE)
    if given is not None and not all(abs(a - b) <= 1e-9 * (1.0 + abs(b))
                                     for a, b in zip(given, centre)):
        raise ModelError(path + ("points", CENTRE),
                         f"the point name {CENTRE!r} is pframe's own: the middle of the floor's "
                         f"named points, here at [{centre[0]:.6g}, {centre[1]:.6g}] m (the "
                         "torsional irregularity reads its drift); name this point otherwise")
    points[CENTRE] = centre


def _building_geometry(building, n: int, path):
    """Placement, plan, named points, centres of mass (building axes) and polar inertias (or
    None) of a building's n floors."""
    placement = Placement(building.origin, building.angle)
    plan = building.plan
    points = dict(plan.corner_names()) if plan is not None else {}
    points.update({k: (float(x), float(y)) for k, (x, y) in building.points.items()})
    _add_centre(points, building, path)
    default = plan.centroid() if plan is not None else (0.0, 0.0)
    centres = building.centre_of_mass
    if centres is None:
        centres = [default] * n
    elif isinstance(centres, list):
        centres = per_storey(centres, n, path + ("centre_of_mass",))
    else:
        centres = [centres] * n
    masses = per_storey(building.mass, n, path + ("mass",))
    if building.polar_inertia is not None:
        inertias = per_storey(building.polar_inertia, n, path + ("polar_inertia",))
    elif plan is not None:
        radius2 = plan.polar_radius2()
        inertias = [m * radius2 for m in masses]
    else:
        inertias = [None] * n
    if one_object(centres):  # one centre for every floor (the usual case)
        return placement, plan, points, [tuple(map(float, centres[0]))] * n, inertias
    as_floats, last = [], None
    for c in centres:  # one tuple for a run of floors given one centre (placed once)
        as_floats.append(as_floats[-1] if as_floats and c is last else tuple(map(float, c)))
        last = c
    return placement, plan, points, as_floats, inertias


def _shorthand(scene, b, building, nodes, stories, gravity_centres) -> None:
    """One building of the shorthand: its floors, and its storeys (a planar storey spring, or
    its lines of resistance in every storey)."""
    path = ("buildings", b)
    n = _storey_count(building, path)
    masses = per_storey(building.mass, n, path + ("mass",))
    placement, plan, points, centres, inertias = _building_geometry(building, n, path)
    heights = (per_storey(building.height, n, path + ("height",))
               if building.height is not None else [None] * n)
    if building.park_ang is not None:  # one ultimate drift per storey (pframe.demands)
        per_storey(building.park_ang.ultimate_drift, n, path + ("park_ang", "ultimate_drift"))
    if building.p_delta and building.height is None:
        raise ModelError(path + ("p_delta",), "P-delta needs the storey heights: give "
                         "height (m, one for all storeys or one per storey)")
    above = np.cumsum(np.asarray(masses, dtype=float)[::-1])[::-1]  # floors i..n
    if one_object(centres):  # one centre for every floor: placed once
        placed = [placement.point(centres[0])] * n if n else []
    else:
        placed, given, centre = [], None, None
        for c in centres:  # placed once for a run of floors given one centre
            if c is not given:
                given, centre = c, placement.point(c)
            placed.append(centre)
    names = [f"{building.name}/{i + 1}" for i in range(n)]
    if n:  # one run: the first floor's placement, plan and points shared by every floor
        nodes.append(Run(Floor(names[0], masses[0], path + ("name",), placed[0], inertias[0],
                               placement, plan, points, path), n,
                         dict(name=names, mass=masses, centre=placed, inertia=inertias)))
    gravity = ([GRAVITY * float(above[i]) for i in range(n)] if building.p_delta
               else [0.0] * n)
    if building.story is not None:
        if n:
            law, fields = _material_fields(building.story, n, path + ("story",))
            same, validated = _one_for_all(law, fields, path + ("story",)), {}
            params = ([same] * n if same is not None else
                      [_storey_params(law, fields, i, path + ("story",), validated)
                       for i in range(n)])
            lowers = ["ground", *names[:-1]]
            # one run: the first storey's law, path and direction shared by every storey
            stories.append(Run(StoreySpec(names[0], (lowers[0], names[0]), law, params[0],
                                          path + ("story",), heights[0], gravity[0],
                                          direction=placement.vector((1.0, 0.0)),
                                          storey=names[0]), n,
                               dict(name=names, nodes=list(zip(lowers, names)), params=params,
                                    height=heights, gravity=gravity, storey=names)))
        return
    for j, line in enumerate(building.lines):
        lpath = path + ("lines", j)
        law, fields = _material_fields(line, n, lpath)
        same, validated = _one_for_all(law, fields, lpath), {}
        first, last = line.storeys or (1, n)
        if last > n:
            raise ModelError(lpath + ("storeys",), f"building {building.name!r} has {n} "
                             f"storeys; the line cannot stand in storey {last}")
        direction = placement.vector(unit(line.direction))
        position = placement.point(line.position)
        for i in range(first - 1, last):
            storey = f"{building.name}/{i + 1}"
            lower = "ground" if i == 0 else f"{building.name}/{i}"
            stories.append((StoreySpec(f"{storey}/{line.name}", (lower, storey), law,
                                       same or _storey_params(law, fields, i, lpath,
                                                              validated),
                                       lpath, heights[i], 0.0, position, direction, storey,
                                       line.isolator, line.stiffness_damping),))
    if building.p_delta:
        # the gravity loads P of each storey stand at the centre of mass of the floors above
        # it, spread over their plan (r^2 = J / m): the P-delta elements of the storey
        centre = np.array([placement.point(c) for c in centres])
        inertia = np.array([np.nan if j is None else j for j in inertias], dtype=float)
        weights = np.asarray(masses, dtype=float)
        for i in range(n):
            w = weights[i:]
            c = (w[:, None] * centre[i:]).sum(axis=0) / w.sum()
            spread = inertia[i:] + w * ((centre[i:] - c) ** 2).sum(axis=1)
            gravity_centres[f"{building.name}/{i + 1}"] = (
                "ground" if i == 0 else f"{building.name}/{i}", gravity[i],
                (float(c[0]), float(c[1])), float(spread.sum() / w.sum()), heights[i],
                path + ("p_delta",))


def floors(scene) -> Floors:
    """The floors and storey springs of a scene, in declaration order (the building shorthand
    first, then the generic nodes and storeys); the foundations on soil."""
    nodes: list = []  # parts of Rows: a run per building of the shorthand, else one by one
    stories: list = []
    damping: dict = {}
    foundations: list = []
    gravity_centres: dict = {}
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
            if building.lines is not None:
                raise ModelError(path + ("soil",), "soil under a building in plan (sway in "
                                 "two directions and torsion of its foundation) is not "
                                 "modelled yet: give the building's storeys as story (a "
                                 "planar building) or leave out the soil")
            from pframe.model.soil import foundation_soil  # only a scene with soil

            foundations.append((b, foundation_soil(building.soil, b)))
        damping[building.name] = building.damping
        _shorthand(scene, b, building, nodes, stories, gravity_centres)
    for i, node in enumerate(scene.nodes):
        nodes.append((Floor(node.name, node.mass, ("nodes", i, "name"),
                           tuple(map(float, node.centre_of_mass)), node.polar_inertia,
                           building_path=("nodes", i)),))
    for s, story in enumerate(scene.stories):
        law = get_law("material", story.material)
        params = law.Params.model_validate(story.model_dump(include=set(law.Params.model_fields)))
        if story.gravity_load is not None and story.height is None:
            raise ModelError(("stories", s, "gravity_load"), "P-delta needs the storey's "
                             "height: give height (m)")
        if story.park_ang is not None and isinstance(story.park_ang.ultimate_drift, list):
            raise ModelError(("stories", s, "park_ang", "ultimate_drift"), "one storey has one "
                             "ultimate drift (m), not a list")
        position = None if story.position is None else tuple(map(float, story.position))
        name = story.name or default_story_name(story.nodes)
        stories.append((StoreySpec(name, story.nodes, law, params, ("stories", s),
                                   story.height, float(story.gravity_load or 0.0), position,
                                   unit(story.direction), story.nodes[1], story.isolator,
                                   story.stiffness_damping),))
    return Floors(Rows(nodes), Rows(stories), damping, tuple(foundations), gravity_centres)


def masses_above(stories, index, masses) -> dict:
    """node name -> the mass of that node and of every node above it (kg): the nodes reached
    upward through storeys (lower -> upper), each counted once along each storey (a tree, as
    buildings are). One pass over the storeys, whatever the height. Unknown names are left to
    the caller's check; a storey loop (refused elsewhere) is cut where it closes."""
    upward: dict[str, list[str]] = {}
    ends = column(stories, "nodes")
    for lower, upper in ends:
        if upper not in upward.get(lower, ()):  # the lines of one storey: one way up
            upward.setdefault(lower, []).append(upper)
    carried: dict[str, float] = {}
    for start in {upper for _, upper in ends}:
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
