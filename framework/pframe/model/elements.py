"""Storeys, links and contacts resolved to node indices, packed numbers and sides.

Every element acts along a direction at a point of each of its two sides (docs/plan.md): a
side is a linear combination of its floors' degrees of freedom, ``((node, component,
coefficient), ...)`` with component 0, 1, 2 the floor's u_x, u_y and theta (site axes; -1 or
no term at all: the ground). A storey or link deforms by ``side(second) - side(first)``, a
contact penetrates by ``side(left) - side(right) - gap``. The planar element of today (u_x of
each node, coefficient 1) is the special case :attr:`Element.plain`; the kernel runs it as it
always has.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from pframe.errors import InputError
from pframe.laws import ContactContext, StoreyContext, get_law
from pframe.laws.restitution import published_rebound
from pframe.model.load import ModelError
from pframe.model.plan import coefficients, normalised
from pframe.model.rows import Rows, Run, column, like
from pframe.model.scene import contact_levels, default_link_name

#: a side: ((node index, component, coefficient), ...); () is the ground
Side = tuple


@dataclass(frozen=True)
class Element:
    """A storey, link or contact resolved to node indices (-1 = ground) and packed numbers.

    ``sides`` (None: the plain element, u_x of each node with coefficient 1) is the linear
    combination of degrees of freedom each side moves with along the element."""

    name: str
    nodes: tuple[int, int]
    law: type
    packed: tuple[float, ...]
    gap: float = 0.0
    #: a floor-to-column contact: the struck storey's lower floor on each side (-1: none or
    #: the ground) and the weight psi of the named node (1: a floor)
    lower: tuple[int, int] = (-1, -1)
    share: tuple[float, float] = (1.0, 1.0)
    shear_capacity: float | None = None
    sides: tuple[Side, Side] | None = None
    #: a floor-to-column contact: where its column is struck on each side (the fraction of
    #: the storey's height; NaN: a floor)
    at: tuple[float, float] = (math.nan, math.nan)
    #: the ground displacements' part of its deformation across supports: ((support,
    #: axis component, coefficient), ...); empty on one support (pframe.model.supports)
    ground: tuple = ()

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

    def side_terms(self) -> tuple[Side, Side]:
        """Both sides as terms, the plain element's included."""
        if self.sides is not None:
            return self.sides
        return tuple(((i, 0, 1.0),) if i >= 0 else () for i in self.nodes)


#: the plain element with every field but its name, nodes, law and numbers at its default
#: (a planar storey, a contact between floors' centres), which tall scenes copy
PLAIN = Element("", (-1, -1), type, ())


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


def plain_sides(sides, nodes) -> bool:
    """Whether sides are the plain element's: u_x of each node (or the ground), coefficient 1."""
    for terms, i in zip(sides, nodes):
        if i < 0:
            if terms:
                return False
        elif len(terms) != 1 or terms[0] != (i, 0, 1.0):
            return False
    return True


def element(name, nodes, law, packed, sides, **more) -> Element:
    """An :class:`Element`, its sides left out (None) when they are the plain element's."""
    return Element(name, nodes, law, packed, sides=None if plain_sides(sides, nodes) else sides,
                   **more)


def finite(packed, path) -> tuple[float, ...]:
    """A law's packed parameters, which must be finite numbers."""
    out = tuple(map(float, packed))
    if not all(np.isfinite(out)):
        raise ModelError(path, "these values give the law a parameter that is not a finite "
                               f"number ({', '.join(f'{v:.4g}' for v in out)}); they are too "
                               "small or too large for each other: check the units")
    return out


def side(node: int, floor, point, direction, weight: float = 1.0) -> Side:
    """The terms of a floor's ``point`` (site coordinates) moving along ``direction``, times
    ``weight``; zero coefficients left out (a line through the centre of mass does not turn
    the floor, a line along x does not move it along y)."""
    if node < 0:
        return ()
    if direction == (1.0, 0.0) and point == floor.centre:  # the planar side: its u_x
        return ((node, 0, weight * 1.0),)
    return tuple((node, c, weight * a) for c, a in
                 enumerate(coefficients(point, floor.centre, direction)) if a != 0.0)


def side_mass(terms: Side, dof_mass) -> float:
    """The mass a side presents to an impact along its direction (kg): 1 / sum(a^2 / m) over
    its terms (m the mass or polar inertia of each degree of freedom); the node's own mass for
    a plain side, infinite for the ground (a wall)."""
    if not terms:
        return math.inf
    if len(terms) == 1 and terms[0][2] == 1.0:
        return float(dof_mass(terms[0][0], terms[0][1]))
    return 1.0 / sum(a * a / dof_mass(i, c) for i, c, a in terms)


class Resolver:
    """Names to indices and sides, with the messages that name the YAML path."""

    def __init__(self, floors):
        self.floors = floors
        self.names = names = column(floors.nodes, "name")  # of each node, in order
        self.index = dict(zip(names, range(len(names))))
        if len(self.index) != len(names):
            seen = set()
            for name, path in zip(names, column(floors.nodes, "path")):
                if name in seen:
                    raise ModelError(path, f"node {name!r} is defined twice (building "
                                           "shorthand and nodes, or twice in nodes)")
                seen.add(name)
        self.building_of = [name.split("/")[0] for name in names]  # Floor.building
        self.buildings = tuple(dict.fromkeys(self.building_of))
        self._centres = None
        self._with_ground = None

    def indices(self, names) -> list:
        """Each name's node index (-1: the ground; None: no such node), as :meth:`node`
        resolves them, at a dictionary's pace (a run of storeys or contact levels)."""
        if self._with_ground is None:
            self._with_ground = {**self.index, "ground": -1}
        return list(map(self._with_ground.get, names))

    def centres(self) -> list:
        """Each floor's centre of mass (site, m): the floors' column, read once."""
        if self._centres is None:
            self._centres = column(self.floors.nodes, "centre")
        return self._centres

    def node(self, name, path) -> int:
        if name == "ground":
            return -1
        if name not in self.index:
            names = list(self.index)
            raise ModelError(path, f"no node named {name!r}; nodes are {', '.join(names[:12])}"
                                   f"{' ...' if len(names) > 12 else ''}")
        return self.index[name]

    def node_at(self, name, path, *field) -> int:
        """:meth:`node` with the path ``path + field``, joined only for its error (a tall
        scene resolves hundreds of thousands of names)."""
        if name == "ground":
            return -1
        i = self.index.get(name)
        return i if i is not None else self.node(name, path + field)

    def floor(self, i: int):
        return self.floors.nodes[i] if i >= 0 else None

    def point(self, i: int, ref, path):
        """A point of node i's floor (site coordinates); the ground takes none."""
        if i < 0:
            if ref is not None:
                raise ModelError(path, "the ground's side (a wall, an anchor) has no point of "
                                       "a floor: give null")
            return None
        return self.floor(i).point(ref, path)


def storey_elements(floors, resolver) -> tuple[Rows, list[int], dict]:
    """The storey springs as elements, each one's building index, and the names seen. A run
    of storeys (a building of the shorthand) is resolved as one (:func:`_storey_run`)."""
    from pframe.model.floors import masses_above

    carried: dict = {}
    masses = column(floors.nodes, "mass")

    def mass_above(upper: str) -> float:  # computed for every storey at the first request
        if not carried:
            carried.update(masses_above(floors.stories, resolver.index, masses))
        return carried[upper]

    parts, building, seen = [], [], {}
    shared: dict = {}  # (law, parameters) -> packed, for laws that do not ask the mass above
    number = {name: i for i, name in enumerate(resolver.buildings)}
    for part in floors.stories.parts:
        run = (_storey_run(part, resolver, seen, shared, mass_above)
               if isinstance(part, Run) else None)
        if run is not None:
            parts.append(run)
            building += [number[resolver.building_of[up]] for _, up in run.fields["nodes"]]
            continue
        out = []
        for spec in part:
            element = _storey(spec, resolver, seen, shared, mass_above)
            out.append(element)
            building.append(number[resolver.building_of[element.nodes[1]]])
        parts.append(tuple(out))
    laws = column(floors.stories, "law")
    free = {law for law in set(laws) if getattr(law, "stiffness_free", False)}
    for i, law in enumerate(laws if free else ()):
        if law in free:
            spec = floors.stories[i]
            raise ModelError(spec.path + ("material",), f"storey {spec.name!r}: a "
                             f"{spec.law.name} has no stiffness and cannot carry a storey; "
                             "put it in links (a damper across the storey: nodes [lower, "
                             "upper])")
    return Rows(parts), building, seen


def _storey_packed(spec, params, upper: str, shared, mass_above):
    """The numbers of storey ``spec``'s law with ``params`` under the floor ``upper``: once
    per (law, parameters) for laws that do not ask the mass above; and whether they are
    those (False: the storey's own, from its mass above)."""
    key = (spec.law, id(params))
    packed = shared.get(key)
    if packed is not None:
        return packed, True
    context = StoreyContext(lambda u=upper: mass_above(u))
    try:
        packed = finite(spec.law.pack(params, context), spec.path)
    except InputError as exc:
        raise ModelError(spec.path, str(exc)) from None
    if callable(context._mass_above):  # not asked: the same for equal parameters
        shared[key] = packed
        return packed, True
    return packed, False


def _storey(spec, resolver, seen, shared, mass_above) -> Element:
    """One storey spring resolved to its nodes, numbers and sides."""
    lower, upper = spec.nodes
    up = resolver.node_at(upper, spec.path, "nodes", 1)
    low = resolver.node_at(lower, spec.path, "nodes", 0)
    if low >= 0 and resolver.building_of[low] != resolver.building_of[up]:
        raise ModelError(spec.path + ("nodes",), f"a storey joins floors of one building; "
                                                 f"{lower!r} and {upper!r} are in two")
    if low == up:
        raise ModelError(spec.path + ("nodes",), "a storey needs two different nodes")
    if spec.name in seen:
        raise ModelError(spec.path, f"storey name {spec.name!r} is used twice")
    seen[spec.name] = True
    packed, _ = _storey_packed(spec, spec.params, upper, shared, mass_above)
    centre = resolver.centres()[up]
    if (spec.position is None and spec.direction == (1.0, 0.0)
            and (low < 0 or resolver.centres()[low] == centre)):
        # the planar storey (u_x of both floors: what side() and element() conclude),
        # without building its sides: a tall building has tens of thousands
        return like(PLAIN, name=spec.name, nodes=(low, up), law=spec.law, packed=packed)
    point = spec.position if spec.position is not None else centre
    sides = (side(low, resolver.floor(low), point, spec.direction),
             side(up, resolver.floor(up), point, spec.direction))
    return element(spec.name, (low, up), spec.law, packed, sides)


def _storey_run(run: Run, resolver, seen, shared, mass_above) -> Run | None:
    """A run of storeys (one storey description repeated up a building) resolved as one run
    of planar elements: what :func:`_storey` gives each, its checks made on the run's
    columns. None when the run is not that simple (a storey off the centres of mass or out
    of x, a law that asks each storey's mass above, a name or node to refuse): then each
    storey is resolved on its own, and refused where it is."""
    spec = run.template
    if spec.position is not None or spec.direction != (1.0, 0.0) or "law" in run.fields:
        return None
    building_of = resolver.building_of
    names = run.column("name")
    ends = run.column("nodes")
    lowers, uppers = [a for a, _ in ends], [b for _, b in ends]  # (not zip(*): 30,000 args)
    up, low = resolver.indices(uppers), resolver.indices(lowers)
    if None in up or None in low or -1 in up or len(set(names)) != len(names) or any(
            n in seen for n in names):
        return None
    centre = resolver.centres()
    if any(i == j or (i >= 0 and (building_of[i] != building_of[j] or centre[i] != centre[j]))
           for i, j in zip(low, up)):
        return None
    params = run.column("params")
    ids = list(map(id, params))
    # parameters' object -> its first storey (the last written, going down)
    first = dict(zip(reversed(ids), range(len(ids) - 1, -1, -1)))
    known = {}  # parameters' object -> packed, packed at its first storey, in their order
    for i, k in sorted(first.items(), key=lambda item: item[1]):
        known[i], same = _storey_packed(spec, params[k], uppers[k], shared, mass_above)
        if not same:  # each storey's own numbers (its mass above): one by one
            return None
    packed = list(map(known.__getitem__, ids))
    seen.update(dict.fromkeys(names, True))
    nodes = list(zip(low, up))
    return Run(like(PLAIN, name=names[0], nodes=nodes[0], law=spec.law, packed=packed[0]),
               len(names), dict(name=names, nodes=nodes, packed=packed))


def p_delta_elements(floors, resolver, seen) -> list[tuple[Element, float, float, int]]:
    """The P-delta of the storeys of buildings in plan: three springs of no stiffness of
    their own per storey, along x and y through the centre of the gravity loads above and a
    twist of lever r (r^2 = J / m of the loads above), each softened by P / h (its geometric
    stiffness); returns (element, P, h, building index) per spring."""
    if not floors.gravity_centres:
        return []  # the elastic law's module is not loaded for a scene without P-delta in plan
    law = get_law("material", "elastic")
    out = []
    for storey, (lower, load, centre, r2, height, path) in floors.gravity_centres.items():
        up = resolver.node(storey, path)
        low = resolver.node(lower, path)
        building = resolver.buildings.index(resolver.building_of[up])
        for axis, direction in (("x", (1.0, 0.0)), ("y", (0.0, 1.0))):
            sides = (side(low, resolver.floor(low), centre, direction),
                     side(up, resolver.floor(up), centre, direction))
            name = f"{storey}/P-delta-{axis}"
            seen[name] = True
            out.append((element(name, (low, up), law, (0.0,), sides), load, height, building))
        lever = math.sqrt(max(r2, 0.0))
        if lever > 0.0:
            sides = (((low, 2, lever),) if low >= 0 else (), ((up, 2, lever),))
            name = f"{storey}/P-delta-rz"
            seen[name] = True
            out.append((Element(name, (low, up), law, (0.0,), sides=sides), load, height,
                        building))
    return out


def link_elements(scene, resolver, seen) -> list[Element]:
    out = []
    for i, link in enumerate(scene.links):
        path = ("links", i)
        if link.nodes[0] == "ground" and link.nodes[1] == "ground":
            raise ModelError(path + ("nodes",), "a link needs a node on at least one side")
        first, second = (resolver.node(node, path + ("nodes", j))
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
        sides = _sides(resolver, (first, second), link.points, link.direction, path,
                       "direction")
        out.append(element(name, (first, second), law, finite(packed, path), sides))
    return out


def _sides(resolver, nodes, points, direction, path, field) -> tuple[Side, Side]:
    """The sides of a link or contact between ``nodes`` at ``points`` along ``direction``
    (the YAML field ``field``)."""
    try:
        unit = normalised(direction)
    except ValueError as exc:
        raise ModelError(path + (field,), str(exc)) from None
    refs = points if points is not None else (None, None)
    out = []
    for j, i in enumerate(nodes):
        where = path + ("points", j)
        point = resolver.point(i, refs[j], where)
        out.append(side(i, resolver.floor(i), point, unit) if i >= 0 else ())
    return tuple(out)


# eq=False: nothing compares two (the scene's contact would not hash); each generated function
# is compiled at every start
@dataclass(frozen=True, eq=False)
class ContactGeometry:
    """A contact resolved but not packed: what its law's numbers wait for are the masses its
    sides move (the degrees of freedom of the whole scene)."""

    path: tuple
    contact: object  # the scene's contact definition
    #: packed () until pack_contacts; a Run of plain elements: further levels of a contact at
    #: every level
    element: Element | Run


def contact_sides(scene, resolver, stories, heights) -> list[ContactGeometry]:
    """The contacts of a scene resolved to nodes and sides (see the module); ``stories`` the
    storey elements (node indices) and ``heights`` their heights (m, NaN: not given), for
    the floor-to-column contacts."""
    out, seen, level = [], {}, None
    for c, contact in enumerate(scene.contacts):
        path = ("contacts", c)
        if contact.nodes[0] == "ground" and contact.nodes[1] == "ground":
            raise ModelError(path + ("nodes",), "a contact needs a node on at least one side; "
                                                "'ground' on one side is a wall")
        levels = _levels(contact, resolver, path)
        law = get_law("contact", contact.law)
        try:
            unit = normalised(contact.normal)
        except ValueError:  # refused where its sides are resolved, at its YAML path
            unit = None
        first = None
        for k, (nodes, name) in enumerate(levels):
            if first is not None and _plain(contact, unit):
                # the further levels of a contact at every level between floors' centres: its
                # buildings checked at the first, the first's element with their names and
                # nodes, as one run
                run = _level_run(first, levels[k:], resolver, seen)
                if run is not None:
                    out.append(run)
                    break
                _claim(seen, name, path)
                out.append(like(first, element=like(first.element, name=name, nodes=(
                    resolver.node_at(nodes[0], path, "nodes", 0),
                    resolver.node_at(nodes[1], path, "nodes", 1)))))
                continue
            geometry, level = _contact(contact, nodes, name, law, path, resolver, seen,
                                       stories, heights, level, unit)
            out.append(geometry)
            first = first or geometry
    return out


def _level_run(first: ContactGeometry, levels, resolver, seen) -> ContactGeometry | None:
    """The further ``levels`` ((nodes, name) each) of a plain contact at every level as one
    geometry whose element is a :class:`Run` like ``first``'s; None when a name is taken or
    a node unknown (each level is then resolved, and refused, on its own)."""
    names = [name for _, name in levels]
    left = resolver.indices([pair[0] for pair, _ in levels])
    right = resolver.indices([pair[1] for pair, _ in levels])
    if (len(set(names)) != len(names) or any(n in seen for n in names)
            or None in left or None in right):
        return None
    seen.update(dict.fromkeys(names, True))
    return like(first, element=Run(first.element, len(names), dict(
        name=names, nodes=list(zip(left, right)))))


def _plain(contact, unit) -> bool:
    """Whether each level of a contact is the plain element: between its floors' centres
    along x, floor to floor."""
    return (unit == (1.0, 0.0) and contact.points is None and contact.column is None
            and contact.at is None and contact.shear_capacity is None)


def _claim(seen: dict, name: str, path) -> None:
    """Mark a contact's name as used (refused if it already is)."""
    if name in seen:
        raise ModelError(path + ("name",), f"contact name {name!r} is used twice")
    seen[name] = True


def _levels(contact, resolver, path) -> list[tuple[tuple[str, str], str]]:
    """The contacts a scene's contact stands for (scene.contact_levels), or why not."""
    ends = [end for end in contact.nodes if end != "ground"]
    shorthand = [end for end in ends if "/" not in end]
    if not shorthand:
        return contact_levels(contact, resolver.index.__contains__)
    if len(shorthand) != len(ends):
        raise ModelError(path + ("nodes",), "a contact at every level names two buildings (or "
                         "a building and 'ground'), not a building and a node: "
                         f"{list(contact.nodes)}")
    for i, end in enumerate(contact.nodes):
        if end != "ground" and end not in resolver.buildings:
            raise ModelError(path + ("nodes", i), f"no building named {end!r}; the buildings "
                             f"are {', '.join(resolver.buildings)}")
    if contact.column is not None:
        raise ModelError(path + ("column",), "a contact at every level joins floors to floors "
                         "(or a wall); a floor-to-column contact names its two nodes")
    levels = contact_levels(contact, resolver.index.__contains__)
    if not levels:
        raise ModelError(path + ("nodes",), f"{contact.nodes[0]} and {contact.nodes[1]} have "
                         "no floor level in common (floor 1 of each)")
    return levels


def _contact(contact, nodes, name, law, path, resolver, seen, stories, heights, level,
             unit=None):
    """One contact of the scene (or one level of a contact at every level) resolved to its
    nodes and sides, and the floors' elevations (computed once, for the struck columns);
    ``unit`` its normal normalised (None: not computed, or no direction)."""
    left, right = (resolver.node_at(nodes[0], path, "nodes", 0),
                   resolver.node_at(nodes[1], path, "nodes", 1))
    if left >= 0 and right >= 0:
        if resolver.building_of[left] == resolver.building_of[right]:
            raise ModelError(path + ("nodes",), "a contact joins nodes of two different "
                             f"buildings (or a node and a wall: 'ground'); both nodes are "
                             f"in {resolver.building_of[left]!r}")
    if left >= 0 and right >= 0 and "normal" not in contact.model_fields_set:
        # along the row (the default normal): the row's order decides left and right; a
        # normal given says the geometry itself
        _check_row_order(name, resolver.buildings, resolver.building_of[left],
                         resolver.building_of[right], nodes, path + ("nodes",))
    _claim(seen, name, path)
    if _plain(contact, unit):
        # floors' centres along x: the plain element (what _sides and element() conclude),
        # without building its sides: a contact at every level of a tall pair has
        # tens of thousands
        return ContactGeometry(path, contact, like(PLAIN, name=name, nodes=(left, right),
                                                   law=law, gap=float(contact.gap))), level
    sides = list(_sides(resolver, (left, right), contact.points, contact.normal, path,
                        "normal"))
    lower, share, at = [-1, -1], [1.0, 1.0], [math.nan, math.nan]
    if contact.column is None and contact.at is not None:
        raise ModelError(path + ("at",), "at is where a column is struck: give column "
                                         "(the side whose node names the struck storey)")
    if contact.column is None and contact.shear_capacity is not None:
        raise ModelError(path + ("shear_capacity",), "shear_capacity is a struck "
                         "column's: give column (a floor-to-column contact); a "
                         "floor-to-floor contact loads no column between floors")
    if contact.column is not None:
        if level is None:
            level = elevations(stories, heights)
        side_, lower[side_], at[side_] = _struck_column(contact, path, (left, right),
                                                        stories, level, resolver.index)
        upper = (left, right)[side_]
        share[side_] = column_share(at[side_])
        refs = contact.points if contact.points is not None else (None, None)
        point = resolver.point(upper, refs[side_], path + ("points", side_))
        normal = normalised(contact.normal)
        sides[side_] = (side(upper, resolver.floor(upper), point, normal, share[side_])
                        + side(lower[side_], resolver.floor(lower[side_]), point, normal,
                               1.0 - share[side_]))
    return ContactGeometry(path, contact, element(
        name, (left, right), law, (), tuple(sides), gap=float(contact.gap),
        lower=tuple(lower), share=tuple(share), shear_capacity=contact.shear_capacity,
        at=tuple(at))), level


def pack_contacts(geometries, dof_mass, excitation_frequency, node_mass=None):
    """The contacts (:class:`Rows`) with their laws' numbers, from the masses their sides
    move (``dof_mass(node, component)``; ``node_mass``, each node's u_x mass, for the levels
    of a contact at every level, at once), and the contacts a published damping formula
    rebounds differently from their restitution (key -> names)."""
    parts, rebounds, validated, packs = [], {}, {}, {}
    for g in geometries:
        e, contact = g.element, g.contact
        law = (e.template if isinstance(e, Run) else e).law
        params = validated.get(id(contact))
        if params is None:  # once per contact of the scene, whatever its levels
            params = validated[id(contact)] = law.Params.model_validate(
                contact.model_dump(include=set(law.Params.model_fields)))
        if isinstance(e, Run):  # levels of plain elements: their nodes' own masses
            names = e.column("name")
            masses, level = _distinct_masses(e.column("nodes"), dof_mass, node_mass)
        else:
            # a wall is the ground: of infinite mass, the impact's effective mass is the
            # floor's; a point of a floor or a column has the mass its displacement's
            # weights give it
            names, level = [e.name], [0]
            if e.sides is None:  # the plain element's sides: its nodes' own masses
                masses = [(tuple(float(dof_mass(i, 0)) if i >= 0 else math.inf
                                 for i in e.nodes), 0)]
            else:
                masses = [((side_mass(e.sides[0], dof_mass),
                            side_mass(e.sides[1], dof_mass)), 0)]
        # once per contact of the scene and masses (the levels alike share their numbers),
        # in the order of the levels (a refusal names the first level of those masses)
        found = []
        for pair, first in masses:
            key = (id(contact), pair)
            if key not in packs:
                packs[key] = _packed_contact(law, params, contact, g.path, names[first], pair,
                                             excitation_frequency)
            found.append(packs[key])
        if any(published is not None for _, published in found):
            for name, k in zip(names, level):
                if found[k][1] is not None:
                    rebounds.setdefault(found[k][1], []).append(name)
        numbers = [found[k][0] for k in level]
        if isinstance(e, Run):
            parts.append(Run(like(e.template, packed=numbers[0]), len(e),
                             dict(e.fields, packed=numbers)))
        else:
            parts.append((like(e, packed=numbers[0]),))
    return Rows(parts), rebounds


def _distinct_masses(ends, dof_mass, node_mass):
    """The distinct masses (kg) of the pairs of nodes ``ends`` along x (the ground: inf),
    each with the first pair that has them, in the pairs' order, and each pair's (an index
    into them): ``node_mass`` (each node's) at once, or else ``dof_mass(node, 0)``."""
    if node_mass is None:
        pairs = [tuple(float(dof_mass(i, 0)) if i >= 0 else math.inf for i in pair)
                 for pair in ends]
        number = {}
        level = [number.setdefault(pair, len(number)) for pair in pairs]
        first = {}
        for i, k in enumerate(level):
            first.setdefault(k, i)
        return [(pair, first[k]) for pair, k in number.items()], level
    ends = np.array(ends, dtype=np.int64).reshape(-1, 2)
    masses = np.ascontiguousarray(np.where(
        ends >= 0, np.asarray(node_mass, dtype=float)[np.maximum(ends, 0)], math.inf))
    # equal masses are equal doubles (no NaN, and a zero is refused before it matters)
    _, first, inverse = np.unique(masses.view(np.dtype((np.void, 16))).ravel(),
                                  return_index=True, return_inverse=True)
    by_first = np.argsort(first, kind="stable")  # distinct masses in the levels' order
    rank = np.empty(len(first), dtype=np.int64)
    rank[by_first] = np.arange(len(first))
    distinct = [(tuple(masses[i].tolist()), int(i)) for i in first[by_first].tolist()]
    return distinct, rank[inverse.ravel()].tolist()


def _packed_contact(law, params, contact, path, name, masses, excitation_frequency):
    """A contact's law's numbers for the masses its sides present, and what a published
    damping formula rebounds with (the key of pack_contacts' rebounds; None: its
    restitution)."""
    context = ContactContext(masses[0], masses[1], excitation_frequency)
    try:
        effective = context.effective_mass
    except ArithmeticError:  # both sides of no mass (underflowed)
        effective = 0.0
    if not (effective > 0.0 and math.isfinite(effective)):
        raise ModelError(path, f"contact {name!r}: the masses its sides present to an "
                         f"impact ({masses[0]:.4g} and {masses[1]:.4g} kg) give an impact "
                         f"mass of {effective:.4g} kg: the masses span more than floating "
                         "point carries (check the units of the masses)")
    try:
        with np.errstate(all="ignore"):
            packed = finite(law.pack(params, context), path)
    except InputError as exc:
        raise ModelError(path, str(exc)) from None
    obtained = published_rebound(law, params)
    published = None
    if obtained is not None:
        chosen = "calibration" in contact.model_fields_set
        published = (chosen, contact.law, law.published_source(params), params.restitution,
                     obtained)
    return packed, published


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


def gauges(floors, resolver, active) -> tuple[tuple[str, ...], tuple, tuple]:
    """The named plan points of the floors (their buildings' corners and points) and their
    gauges: the displacement of each point along its building's x and y axes, then the drift
    at each (the point less the same plan point of the floor below; the ground below the
    first floor), each a tuple of (node, component, coefficient) over the degrees of freedom
    in ``active`` (a DOF the scene does not move adds nothing); and each point's position in
    its building's axes (m)."""
    names, moves, drifts, positions = [], [], [], []
    for i, points in enumerate(column(floors.nodes, "points")):
        if not points:
            continue
        floor = floors.nodes[i]
        storey, level = floor.name.rsplit("/", 1)
        below = resolver.index.get(f"{storey}/{int(level) - 1}", -1) if level.isdigit() else -1
        axes = (floor.placement.vector((1.0, 0.0)), floor.placement.vector((0.0, 1.0)))
        for label, local in floor.points.items():
            point = floor.placement.point(local)
            names.append(f"{floor.name}:{label}")
            positions.append((float(local[0]), float(local[1])))
            for axis in axes:
                up = tuple(t for t in side(i, floor, point, axis) if (t[0], t[1]) in active)
                low = tuple((n, c, -a) for n, c, a in side(below, resolver.floor(below), point,
                                                             axis) if (n, c) in active)
                moves.append(up)
                drifts.append(up + low)
    return tuple(names), tuple(moves + drifts), tuple(positions)
