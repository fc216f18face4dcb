"""From a validated scene to resolved elements: building shorthand expanded, names resolved to
indices, law parameters packed into numbers. Every problem is reported at its YAML path."""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass, replace
from pathlib import Path

import numpy as np

from pframe.model import dofs as dof_table
from pframe.model import supports as support_table
from pframe.model.elements import (
    AT_TOLERANCE,
    Element,
    Resolver,
    column_share,
    contact_sides,
    elevations,
    gauges,
    link_elements,
    p_delta_elements,
    pack_contacts,
    storey_elements,
)
from pframe.model.floors import floors as collect_floors
from pframe.model.load import ModelError
from pframe.model.motion import GroundMotion, ground_motion
from pframe.model.rows import Rows, Run, column, column_array
from pframe.model.scene import scene_motions
from pframe.model.support_motion import support_motion
from pframe.resources import check_floors, check_steps, steps_of

__all__ = ["AT_TOLERANCE", "Element", "Expanded", "column_share", "elevations", "expand"]


# eq=False, repr=False: as pframe.assemble.plan.Plan, it holds numpy arrays (== elementwise):
# a generated __eq__ and __hash__ could only raise, a __repr__ would print every array, and
# each costs compiling at every start
@dataclass(frozen=True, eq=False, repr=False)
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
    #: the degrees of freedom (node, component: 0 u_x, 1 u_y, 2 theta) the scene moves, in
    #: node order (pframe.model.dofs); None: u_x of every node (a planar scene). The initial
    #: displacement and velocity are per degree of freedom, in this order.
    dofs: tuple | None = None
    #: (d,) the mass of each degree of freedom (kg; kg m^2 for theta); None: ``masses``
    dof_mass: np.ndarray = None
    #: the site's axes the ground motion loads ('x', 'y') and, besides ``ground_acceleration``
    #: (along x, zero if the motion has no x part), the samples along y (m/s^2) or None
    channels: tuple[str, ...] = ("x",)
    ground_acceleration_y: np.ndarray = None
    #: (n, 2) each node's centre of mass on the site (m) and (n,) the extent of its floor's
    #: plan (m, NaN: not given): the small-rotation check
    node_centre: np.ndarray = None
    node_extent: np.ndarray = None
    #: (component axis, applied record) of each record a two-component motion reads
    component_records: tuple = ()
    #: the named plan points of the floors ('<node>:<point>') and their gauges: the point's
    #: displacement along its building's x and y, then its drift, each ((node, component,
    #: coefficient), ...) (pframe.model.elements.gauges)
    point_names: tuple[str, ...] = ()
    gauges: tuple = ()
    #: each named point's position in its building's axes (m)
    point_positions: tuple = ()
    #: (s,) what each storey's ``isolator`` and ``stiffness_damping`` say: True, False or
    #: None (not said: pframe.assemble.modes decides); empty: none said (every None)
    story_isolator: tuple = ()
    story_stiffness_damping: tuple = ()

    #: the supports the scene declares (docs/supports.md; empty: one ground), where each
    #: stands (site, m), each node's support (empty: one support), the motion of every
    #: channel (support and axis; None: one support) and each support's wave-passage delay
    supports: tuple[str, ...] = ()
    support_positions: tuple = ()
    node_support: tuple = ()
    support_samples: np.ndarray = None
    support_delays: tuple = ()
    #: the site's axes the ground motion loads ('x', or 'x' and 'y')
    axes: tuple[str, ...] = ("x",)
    #: every plain motion of the scene (its excitation's, each support's own): the time
    #: scales checked against dt; empty: the excitation's
    motions: tuple = ()
    #: each declared support's motion as applied (pframe.model.motion.GroundMotion: its
    #: record, its components' records), before any wave-passage delay
    support_motions: tuple = ()
    #: how a channel's displacement is had where it is not its acceleration integrated from
    #: rest: (channel, displacement, velocity, words) (pframe.model.support_motion.kinematics)
    ground_given: tuple = ()

    def with_ground(self, x, y=None, steps: int | None = None, **changes) -> Expanded:
        """This scene under another ground motion: ``x`` along the site's x axis and ``y``
        along its y axis (m/s^2 at t_n = n dt, n = 0..steps; ``steps`` default: this scene's),
        with any other field ``changes``. A scene whose motion loads the y axis (two
        components) keeps that channel, zero when ``y`` is None; one whose motion does not
        cannot take a ``y`` (its degrees of freedom were chosen without it: expand the scene
        with a motion in two components instead)."""
        steps = self.steps if steps is None else int(steps)
        x = np.asarray(x, dtype=float)
        if x.shape != (steps + 1,) or (y is not None and np.shape(y) != (steps + 1,)):
            raise ValueError(f"a ground motion of {steps} steps has {steps + 1} samples per "
                             f"axis, not {x.shape} and {np.shape(y) if y is not None else ''}")
        if "y" in self.axes:
            y = np.zeros(steps + 1) if y is None else np.asarray(y, dtype=float)
        elif y is not None:
            raise ValueError("the scene's motion does not load its y axis: expand it with a "
                             "motion in two components (kind: components) to apply one")
        if self.support_samples is not None:
            changes["support_samples"] = self._carried(x, y, steps)
        return dataclasses.replace(self, steps=steps, ground_acceleration=x,
                                   ground_acceleration_y=y, ground_given=(), **changes)

    def with_supports(self, samples, steps: int | None = None, **changes) -> Expanded:
        """This scene on its several supports under other motions: ``samples`` (C, steps +
        1), every channel's (support and axis, in ``channels`` order; m/s^2 at t_n = n dt),
        each support's motion replaced (a suite's member, pframe.gap.members)."""
        steps = self.steps if steps is None else int(steps)
        samples = np.asarray(samples, dtype=float)
        if self.support_samples is None or samples.shape != (len(self.channels), steps + 1):
            raise ValueError(f"the motions of {len(self.channels)} channels over {steps} steps "
                             f"are ({len(self.channels)}, {steps + 1}) samples, not "
                             f"{samples.shape}")
        rows = dict(zip(self.channels, samples))
        first = self.channels[0][:-1]
        return dataclasses.replace(self, steps=steps, support_samples=samples,
                                   ground_acceleration=rows.get(first + "x",
                                                                np.zeros(steps + 1)),
                                   ground_acceleration_y=rows.get(first + "y"),
                                   ground_given=(), **changes)

    def first_steps(self, steps: int, **changes) -> Expanded:
        """This scene cut to its first ``steps`` steps (a warm-up, a plan for its periods),
        every ground motion with it."""
        cut = slice(0, steps + 1)
        return dataclasses.replace(
            self, steps=steps, ground_acceleration=self.ground_acceleration[cut],
            ground_acceleration_y=(None if self.ground_acceleration_y is None
                                   else self.ground_acceleration_y[cut]),
            support_samples=(None if self.support_samples is None
                             else self.support_samples[:, cut]),
            ground_given=tuple((c, *(None if r is None else r[cut] for r in (d, v)), w)
                               for c, d, v, w in self.ground_given), **changes)

    def _carried(self, x, y, steps: int) -> np.ndarray:
        """Each support's samples of a motion the scene's wave passage carries (docs/
        supports.md): x and y delayed by each support's delay. A scene whose supports have
        motions of their own takes no single motion."""
        from pframe.model.scene import WavePassage
        from pframe.model.support_motion import delayed

        if not isinstance(self.excitation, WavePassage):  # (with_supports replaces them all)
            raise ValueError("the scene's supports move with motions of their own: one motion "
                             "cannot stand for them (give the scene a wave passage, whose "
                             "motion each support takes with its delay)")
        return np.array([delayed(x if axis == "x" else y, tau, self.dt)
                         for tau in self.support_delays for axis in self.axes])


def _check_size(scene) -> None:
    """Refuse, before building them, more floors than the machine can hold, or than pframe
    sets up without the opt-in PFRAME_MAX_FLOORS (resources.MAX_FLOORS)."""
    total, lines, counts = len(scene.nodes), 0, {}
    for building in scene.buildings:
        values = [building.mass, *(building.story.model_dump().values() if building.story
                                   else ())]
        for line in building.lines or ():
            values += list(line.model_dump().values())
        floors = building.floors or max((len(v) for v in values if isinstance(v, list)),
                                        default=0)
        counts[building.name] = floors
        total += floors
        lines += floors * (len(building.lines) - 1 if building.lines else 0)
    # a contact at every level counts one per level of its shorter side
    contacts = sum(min([counts.get(end, 0) for end in c.nodes if end != "ground"] or [1])
                   if any(end != "ground" and "/" not in end for end in c.nodes) else 1
                   for c in scene.contacts)
    # each floor has its storey (or its lines); generic storeys and contacts are elements of
    # their own
    elements = 2 * total - len(scene.nodes) + lines + len(scene.stories) + contacts
    problem = check_floors(total, elements,
                           steps_of(scene.analysis.duration, scene.analysis.dt))
    if problem:
        raise ModelError(("buildings",), problem)


def expand(scene, base_dir: Path | str = ".") -> Expanded:
    """Resolve a validated scene; raises :class:`ModelError` with the YAML path of a problem."""
    _check_names(scene)
    _check_size(scene)
    floors = collect_floors(scene)
    if not floors.nodes:
        raise ModelError(("buildings",), "the scene has no floors; give at least one building "
                                         "(name, floors, mass, story), or nodes and stories")
    resolver = Resolver(floors)
    stories, story_building, seen = storey_elements(floors, resolver)
    p_delta = p_delta_elements(floors, resolver, seen)
    links = link_elements(scene, resolver, seen)
    floating = _check_held(scene, floors.nodes, stories, links)
    analysis = scene.analysis
    steps = _steps(analysis)
    supports = support_table.resolve(scene, floors, resolver)
    motion = _motion(scene, supports, base_dir, steps, analysis.dt)
    excitation_frequency = None  # of frequency_ratio (Pi_wcon = w_bar / w_p): a sine's
    if scene.excitation is not None and scene.excitation.kind == "sine":
        excitation_frequency = scene.excitation.frequency
    initial = _initial_conditions(scene, resolver)
    geometries = contact_sides(scene, resolver, stories,
                               [math.nan if h is None else h
                                for h in column(floors.stories, "height")])
    springs = stories + tuple(e for e, *_ in p_delta)
    dofs = dof_table.active(floors, Rows([g.element if isinstance(g.element, Run)
                                          else (g.element,) for g in geometries]
                                         + [tuple(links), springs]), motion.axes, initial)
    dof_table.check_storeys(floors, resolver, springs, dofs)
    position = {key: i for i, key in enumerate(dofs.table)}
    contacts, rebounds = pack_contacts(geometries,
                                       lambda node, c: dofs.mass[position[(node, c)]],
                                       excitation_frequency,
                                       dofs.node_mass(len(floors.nodes)))
    if supports.several:
        springs, links, contacts = _across(scene, supports, motion.axes, springs, links,
                                           contacts)
    reference = _reference(scene, resolver.buildings)
    point_names, point_gauges, point_positions = gauges(floors, resolver, position)
    heights = column(floors.stories, "height") + [h for *_, h, _ in p_delta]
    gravity = column(floors.stories, "gravity") + [g for _, g, *_ in p_delta]
    number = {name: b for b, name in enumerate(resolver.buildings)}
    plans = column(floors.nodes, "plan")
    extents = {id(p): p.extent() for p in plans if p is not None}  # once per plan
    return Expanded(
        buildings=resolver.buildings,
        node_names=tuple(column(floors.nodes, "name")),
        node_building=np.array([number[b] for b in resolver.building_of], dtype=np.int64),
        masses=column_array(floors.nodes, "mass", float).copy(),
        stories=Rows((springs,)),
        story_building=np.array(story_building + [b for *_, b in p_delta], dtype=np.int64),
        contacts=Rows((contacts,)),
        links=tuple(links),
        story_height=np.array([np.nan if h is None else float(h) for h in heights]),
        story_gravity=np.array([float(g) for g in gravity]),
        damping=tuple(floors.damping.get(b) or scene.damping for b in resolver.buildings),
        ground_acceleration=motion.samples[motion.channels[0]] if "x" in motion.axes
        else np.zeros(steps + 1),
        ground_acceleration_y=motion.samples.get(motion.channels[0][:-1] + "y"),
        channels=motion.channels,
        supports=supports.names if supports.declared else (),
        support_positions=supports.positions if supports.declared else (),
        node_support=supports.node_support if supports.several else (),
        support_samples=(np.array([motion.samples[c] for c in motion.channels])
                         if supports.several else None),
        support_delays=getattr(motion, "delays", ()),
        axes=motion.axes,
        motions=scene_motions(scene),
        support_motions=getattr(motion, "motions", ()),
        ground_given=tuple(motion.given),
        initial_displacement=_initial(initial, dofs.table, 0),
        initial_velocity=_initial(initial, dofs.table, 1),
        dt=float(analysis.dt),
        steps=steps,
        integrator=analysis.integrator,
        tolerance=analysis.newton.tolerance,
        absolute_tolerance=analysis.newton.absolute_tolerance,
        max_iterations=analysis.newton.max_iterations,
        recorders=tuple(scene.recorders) + _limit_recorders(scene),
        record=motion.record,
        component_records=motion.records if scene.excitation is not None
        and scene.excitation.kind == "components" else (),
        excitation=scene.excitation,
        reference=reference,
        warnings=tuple(_rebound_text(key, names) for key, names in rebounds.items() if not key[0])
        + motion.warnings + floating,
        notes=tuple(_rebound_text(key, names) for key, names in rebounds.items() if key[0])
        + tuple(getattr(motion, "notes", ())),
        foundations=_foundations(floors.foundations, scene, resolver.buildings,
                                 resolver.building_of),
        dofs=None if dofs.planar and len(dofs.table) == len(floors.nodes) else dofs.table,
        dof_mass=dofs.mass,
        node_centre=column_array(floors.nodes, "centre", float).reshape(-1, 2).copy(),
        node_extent=np.array([extents[id(p)] if p is not None else np.nan for p in plans]),
        point_names=point_names,
        gauges=point_gauges,
        point_positions=point_positions,
        **_storey_flags(floors.stories, len(p_delta)),
    )


def _limit_recorders(scene) -> tuple:
    """The envelopes the scene's limits are checked on (pframe.limits), recorded with its
    own recorders (pframe.limits imported for a scene with limits only)."""
    limits = getattr(scene, "limits", None)
    if limits is None:
        return ()
    from pframe.limits import recorded
    from pframe.model.scene import Envelope

    needed = recorded(limits)
    return (Envelope(kind="envelope", quantities=list(needed)),) if needed else ()


def _motion(scene, supports, base_dir, steps: int, dt: float):
    """The scene's ground motion: one ground's (:func:`ground_motion`, its channels the axes
    it loads) or each support's (:func:`support_motion`, a channel per support and axis)."""
    if not supports.declared:
        if scene.excitation is not None and scene.excitation.kind == "wave_passage":
            raise ModelError(("excitation", "kind"), "a wave passage moves the scene's "
                             "supports one after the other: declare them (supports: with "
                             "their names and positions) and put the buildings on them")
        motion = ground_motion(scene.excitation, base_dir, steps, dt)
        return _OneGround(motion)
    found = support_motion(scene, supports, base_dir, steps, dt)
    if not supports.several:  # one declared support: today's channels, named by axis
        samples = {axis: found.samples[f"{supports.names[0]}:{axis}"] for axis in found.axes}
        given = tuple((c.rpartition(":")[2], d, v, w) for c, d, v, w in found.given)
        return _OneGround(GroundMotion(samples, found.motions[0].record,
                                       found.motions[0].records, found.warnings, given),
                          found.delays, found.motions)
    return found


class _OneGround:
    """A one-ground motion seen as a support motion (its axes are its channels)."""

    def __init__(self, motion, delays=(), motions=()):
        self.motion, self.delays, self.motions = motion, delays, motions
        self.samples, self.warnings, self.given = motion.samples, motion.warnings, motion.given
        self.record, self.records = motion.record, motion.records
        self.channels = self.axes = motion.channels


def _across(scene, supports, axes, springs, links, contacts):
    """The elements with the ground displacements' part of their deformation (elements
    across supports, :func:`pframe.model.supports.ground_terms`)."""
    grounds = support_table.ground_supports(scene, supports)
    node_support = supports.node_support

    def with_ground(kind, element, first_positive=False):
        other = [n for n in element.nodes if n >= 0]
        side = grounds.get((kind, element.name),
                           node_support[other[0]] if other else None)
        terms = support_table.ground_terms(element, node_support, side, axes, first_positive)
        return replace(element, ground=terms) if terms else element

    return ([with_ground("stories", e) for e in springs],
            [with_ground("links", e) for e in links],
            [with_ground("contacts", e, True) for e in contacts])


def _initial(initial: dict, table, slot: int) -> np.ndarray:
    """The initial displacement (``slot`` 0) or velocity (1) of each degree of freedom of
    ``table`` ((node, component) -> (displacement, velocity) given, 0 elsewhere)."""
    if not initial:
        return np.zeros(len(table))
    return np.array([initial.get(k, (0.0, 0.0))[slot] for k in table])


def _storey_flags(specs, extra: int) -> dict:
    """Expanded.story_isolator and story_stiffness_damping: what each storey spring says
    (the P-delta springs of buildings in plan, ``extra``, say nothing); empty when none
    says anything."""
    isolator, stiffness_damping = column(specs, "isolator"), column(specs, "stiffness_damping")
    if isolator.count(None) == len(isolator) == stiffness_damping.count(None):
        return {}  # (at C's pace: a tall building says nothing)
    flags = list(zip(isolator, stiffness_damping)) + [(None, None)] * extra
    if all(f == (None, None) for f in flags):
        return {}
    return dict(story_isolator=tuple(f[0] for f in flags),
                story_stiffness_damping=tuple(f[1] for f in flags))


#: vertices above which the floating-node check labels the graph with scipy's connected
#: components (its import, about 0.1 s, then pays for itself); below, a union-find in Python
#: keeps scipy.sparse off the path of every ordinary pframe solve
_GRAPH_LIBRARY_ABOVE = 5000


def components(count: int, ends: np.ndarray) -> np.ndarray:
    """A label per vertex of the undirected graph of ``count`` vertices and edges ``ends``
    ((m, 2) vertex pairs): equal labels, joined by a chain of edges."""
    if count > _GRAPH_LIBRARY_ABOVE:
        from scipy.sparse import coo_matrix
        from scipy.sparse.csgraph import connected_components

        joined = coo_matrix((np.ones(len(ends)), (ends[:, 0], ends[:, 1])),
                            shape=(count, count))
        return connected_components(joined, directed=False)[1]
    parent = list(range(count))

    def root(i):
        while parent[i] != i:
            parent[i] = parent[parent[i]]
            i = parent[i]
        return i

    for a, b in ends.tolist():
        parent[root(a)] = root(b)
    return np.array([root(i) for i in range(count)])


def _check_held(scene, nodes, stories, links) -> tuple[str, ...]:
    """Refuse a node that nothing holds to the ground in a building that has storeys: no chain
    of storeys, links with a stiffness or (a shorthand building's) soil joins it to the ground,
    and it is not declared ``free``. Such a floor floats (a storey left out, a node
    mistyped): the static stiffness is singular, and a run would complete with the floor
    drifting as a free body. A contact does not hold it (it acts only once closed), nor does a
    dashpot (a stiffness-free link). The nodes of a building without storeys are free bodies
    by design (masses that strike each other or a wall): under a ground motion a warning says
    what they do (the ground moves under them), unless they are declared ``free``."""
    ground = len(nodes)  # the ground: the graph's last vertex
    ends = np.concatenate([column_array(stories, "nodes", np.int64).reshape(-1, 2), np.array(
        [e.nodes for e in links if not getattr(e.law, "stiffness_free", False)],
        dtype=np.int64).reshape(-1, 2)])
    ends[ends < 0] = ground
    label = components(ground + 1, ends)  # the same label: joined
    free = {n.name for n in scene.nodes if n.free}
    loose = [i for i in np.flatnonzero(label[:ground] != label[ground]).tolist()
             if nodes[i].name not in free]
    with_storeys = {nodes[e.nodes[1]].building for e in stories} if loose else set()
    refused = [i for i in loose if nodes[i].building in with_storeys]
    if refused:
        first = refused[0]
        group = [nodes[i].name for i in loose if label[i] == label[first]]
        what = (f"node {group[0]!r}" if len(group) == 1 else
                f"nodes {', '.join(repr(g) for g in group)} (joined to each other)")
        one = len(group) == 1
        it, they = ("it", "it") if one else ("them", "they")
        raise ModelError(nodes[first].path, f"{what}: no storey, link with a stiffness or soil "
                         f"holds {it} to the ground (a contact does not, nor a dashpot), though "
                         f"the building has storeys; {they} would float, with no stiffness to "
                         f"return {it}. Give {it} a storey (nodes: [ground or the floor below, "
                         f"{group[0]}]) or a link with a stiffness, or write free: true on "
                         f"{'the node' if one else 'each node'} if {they} "
                         f"{'is' if one else 'are'} meant to be "
                         f"{'a free body' if one else 'free bodies'}")
    if not loose or scene.excitation is None:
        return ()
    names = [nodes[i].name for i in loose]
    return (f"node{'s' if len(names) > 1 else ''} {', '.join(names[:6])}"
            f"{' ...' if len(names) > 6 else ''}: no storey, link with a stiffness or soil "
            "holds them to the ground, so they are free bodies: the ground motion moves under "
            "them (their displacement relative to the ground is -u_g until a contact or a "
            "dashpot acts); write free: true on them if that is meant, or give them storeys",)


def _check_names(scene) -> None:
    if len({b.name for b in scene.buildings}) != len(scene.buildings):
        seen = set()
        for b, building in enumerate(scene.buildings):
            if building.name in seen:
                raise ModelError(("buildings", b, "name"),
                                 f"building {building.name!r} is defined twice")
            seen.add(building.name)


def _steps(analysis) -> int:
    count = steps_of(analysis.duration, analysis.dt)
    problem = check_steps(count, analysis.dt, analysis.duration)
    if problem:
        raise ModelError(("analysis", "dt" if analysis.dt < 1e-7 else "duration"), problem)
    steps = int(round(count))
    if steps < 1:
        raise ModelError(("analysis", "duration"), f"duration {analysis.duration} s is shorter "
                                                   f"than one step dt = {analysis.dt} s")
    return steps


def _reference(scene, buildings) -> int:
    reference = 1 if len(buildings) > 1 else 0
    chosen = scene.output.reference
    if chosen is not None:
        if chosen not in buildings:
            raise ModelError(("output", "reference"), f"no building named {chosen!r}; the "
                             f"buildings are {', '.join(buildings)}")
        reference = buildings.index(chosen)
    return reference


def _initial_conditions(scene, resolver) -> dict:
    """(node, component) -> (displacement, velocity) given at t = 0."""
    out: dict = {}
    for slot, field in enumerate(("displacement", "velocity")):
        for name, value in getattr(scene.initial_conditions, field).items():
            node = resolver.node(name, ("initial_conditions", field, name))
            values = (value,) if isinstance(value, (int, float)) else value
            for component, v in enumerate(values):
                pair = list(out.get((node, component), (0.0, 0.0)))
                pair[slot] = float(v)
                out[(node, component)] = tuple(pair)
    return out


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
        out.append(dataclasses.replace(soil, building=buildings.index(name)))
    return tuple(out)


def _rebound_text(key, names) -> str:
    """What a published damping formula gives instead of the restitution asked for."""
    chosen, law, source, requested, obtained = key
    listed = (", ".join(names) if len(names) <= 6 else
              f"{', '.join(names[:3])}, ... {names[-1]} ({len(names)} contacts)")
    which = f"contact{'s' if len(names) > 1 else ''} {listed}"
    if chosen:
        return (f"{which} ({law}, calibration: published, {source}): restitution {requested:g} "
                f"rebounds with {obtained:.3f} in a two-body impact")
    return (f"{which} ({law}): restitution {requested:g} is asked for, but the default "
            f"calibration: published ({source}) rebounds with {obtained:.3f} in a two-body "
            f"impact; add 'calibration: exact' to the contact to get {requested:g} (or write "
            "'calibration: published' to keep the published formula; docs/restitution.md)")
