"""The plan: everything the kernel needs as numpy arrays, and what it may leave out.

Arrays that differ between variants of a sweep carry a leading batch axis ``B``; the topology
(which DOFs a storey or contact joins, which law it uses) is shared by the batch.
"""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass

import numpy as np

from pframe.assemble import damping, grounds, incidence, modes, stability, timescales
from pframe.assemble.incidence import Sides
from pframe.assemble.ordering import (
    bandwidth,
    place_last,
    reverse_cuthill_mckee,
    sorted_unique,
)
from pframe.errors import InputError
from pframe.kernel.state import DampingStiffness
from pframe.model.expand import Expanded
from pframe.model.rows import column, column_array

#: the scene's ``damping.stiffness`` -> the kernel's slot
DAMPING_STIFFNESS = {mode.name.lower(): mode for mode in DampingStiffness}


# eq=False, repr=False: it holds numpy arrays: a generated __eq__ and __hash__ could only
# raise (== is elementwise), a __repr__ would print every array, and each generated
# function is compiled at every start
@dataclass(frozen=True, eq=False, repr=False)
class LawGroup:
    """Elements of one law: their indices, packed parameters and initial state."""

    law: type
    index: np.ndarray  # (g,) element indices
    params: np.ndarray  # (B, g, n_params)
    state: np.ndarray  # (B, g, n_state)


# eq=False, repr=False: a plan holds numpy arrays, whose == is elementwise, so a generated
# __eq__ (and the __hash__ of its fields) could only raise, and a __repr__ would print every
# array; without them a plan compares and hashes by identity, and the start of every run
# compiles three functions of 67 fields less
@dataclass(frozen=True, eq=False, repr=False)
class Plan:
    """A scene as flat arrays, DOFs numbered for a narrow band. See ``docs/theory.md``."""

    node_names: tuple[str, ...]  # in declaration order (as written in the YAML)
    node_dof: np.ndarray  # (n,) DOF number of each declared node
    story_names: tuple[str, ...]
    contact_names: tuple[str, ...]
    buildings: tuple[str, ...]
    steps: int
    bandwidth: int
    integrator: object  # pframe.integrators.Coefficients
    integrator_name: str
    tolerance: float
    absolute_tolerance: float
    max_iterations: int
    dt: np.ndarray  # (B,)
    mass: np.ndarray  # (B, n) kg
    mass_damping: np.ndarray  # (B, n) a0 m (N s/m)
    # the spring elements, s of them: the storeys, then the links (link_names; no Rayleigh
    # damping, a1 = 0)
    story_dofs: np.ndarray  # (s, 2), -1 = ground
    story_k0: np.ndarray  # (B, s) initial stiffness (N/m)
    story_beta: np.ndarray  # (B, s) stiffness-proportional damping coefficient a1 (s)
    story_damping_stiffness: np.ndarray  # (s,) DampingStiffness slots (kernel.state)
    story_groups: tuple[LawGroup, ...]
    contact_dofs: np.ndarray  # (c, 2) [left, right]
    contact_gap: np.ndarray  # (B, c) m
    contact_groups: tuple[LawGroup, ...]
    ground_acceleration: np.ndarray  # (B, steps + 1) m/s^2 along the first channel (x)
    initial_displacement: np.ndarray  # (B, n)
    initial_velocity: np.ndarray  # (B, n)
    history: tuple[tuple[str, int], ...]  # (quantity, every)
    envelope: tuple[str, ...]
    cd_parts: np.ndarray = None  # (B,) central-difference sub-steps per step
    event_parts: np.ndarray = None  # (B,) event-aware sub-steps per step while in contact
    warnings: tuple[str, ...] = ()
    link_names: tuple[str, ...] = ()  # the last len(link_names) spring elements
    story_height: np.ndarray = None  # (B, s) storey heights (m), NaN: not given (and links)
    story_kg: np.ndarray = None  # (B, s) P-delta's geometric stiffness P / h (N/m), 0: none
    contact_capacity: np.ndarray = None  # (c,) a struck column's shear capacity (N), NaN: none
    #: (B, c, 2) floor-to-column contacts: the weight psi of each side's named node (1: a
    #: floor; a column point is psi u_upper + (1 - psi) u_lower, held in contact_sides)
    contact_share: np.ndarray = None
    #: soil (docs/soil.md): the buildings whose foundations sway and rock, their (F, 2) sway
    #: and rocking DOFs; the soil's springs are the last 2 F spring elements (after the
    #: links), sway then rocking per foundation; their work is booked with the links'. A
    #: storey on soil deforms by u_upper - u_lower - h theta (its sides hold the lever h).
    foundations: tuple[str, ...] = ()
    foundation_dofs: np.ndarray = None
    #: what each foundation's soil is (FoundationSoil.describe), for the summary and the file
    foundation_soil: tuple[str, ...] = ()
    #: the elements that are not plain (pframe.assemble.incidence): lines of resistance in
    #: plan, contacts at points, floor-to-column contacts, storeys on soil
    story_sides: Sides = None
    contact_sides: Sides = None
    #: the ground motion's channels (the site's axes 'x', 'y' it loads), their motions (B, C,
    #: steps + 1) m/s^2 (None: the first channel alone, ground_acceleration) and each DOF's
    #: channel (-1: none, a rotation)
    channels: tuple[str, ...] = ("x",)
    more_channels: np.ndarray = None
    dof_channel: np.ndarray = None
    #: each DOF's node (declaration order; foundations' DOFs: -1) and component (0 u_x, 1 u_y,
    #: 2 theta): the file's layout of a scene in plan
    dof_node: np.ndarray = None
    dof_component: np.ndarray = None
    #: the scene moves its floors along x only (one DOF per node, today's layout)
    planar: bool = True
    #: the named plan points of the floors ('<node>:<point>') and their gauges (the kernel's
    #: Model.gauge_*): point g's displacement along its building's x, y (gauges 2g, 2g + 1),
    #: then its drifts (2P + 2g, 2P + 2g + 1)
    point_names: tuple[str, ...] = ()
    #: (n,) the extent of each node's floor plan (m; NaN: no plan): the small-rotation check
    node_extent: np.ndarray = None
    #: modal damping (docs/theory.md#damping): the DOFs of each building damped so, one block
    #: after another (q,), where each block starts (blocks + 1,), and the blocks' dense
    #: matrices (B, sum of n_b^2), row-major in the order of their DOFs (N s/m)
    modal_dofs: np.ndarray = None
    modal_start: np.ndarray = None
    modal_matrix: np.ndarray = None
    #: what validate tells besides the warnings (storeys taken as isolators) and each
    #: building's damping as applied, one line per building (validate, the result file)
    notes: tuple[str, ...] = ()
    damping_text: tuple[str, ...] = ()
    #: (B, s) each spring's stiffness in its building's isolated modes (N/m): an isolator's
    #: post-yield or sliding stiffness, every other spring's initial stiffness
    story_isolated: np.ndarray = None
    #: elements across supports (docs/supports.md, pframe.assemble.grounds): each spring's
    #: and contact's ground terms (start (E + 1,), channel (T,), coefficient (B, T)) and the
    #: channels' displacements then velocities (B, 2 C, steps + 1); None: no such element
    story_ground_start: np.ndarray = None
    story_ground_channel: np.ndarray = None
    story_ground_coef: np.ndarray = None
    contact_ground_start: np.ndarray = None
    contact_ground_channel: np.ndarray = None
    contact_ground_coef: np.ndarray = None
    ground_motion: np.ndarray = None
    #: the supports (names; empty: one ground) and each node's (empty: one support)
    supports: tuple[str, ...] = ()
    node_support: tuple = ()
    gauge_start: np.ndarray = None  # (4 P + 1,)
    gauge_dof: np.ndarray = None  # (T,)
    gauge_coef: np.ndarray = None  # (B, T)

    @property
    def n_springs(self) -> int:
        """Spring elements in the kernel: the storeys, then the links, then the soil's."""
        return len(self.story_names) + len(self.link_names) + 2 * len(self.foundations)

    @property
    def ground_channels(self) -> np.ndarray:
        """(B, C, steps + 1): the ground motion along each channel (m/s^2)."""
        if self.more_channels is not None:
            return self.more_channels
        return self.ground_acceleration[:, None, :]

    @property
    def batch(self) -> int:
        return self.mass.shape[0]

    @property
    def n_dof(self) -> int:
        return self.mass.shape[1]

    @property
    def linear(self) -> bool:
        """No contacts, only linear storeys and constant damping: one solve per step."""
        return (
            not self.contact_groups
            and all(g.law.linear for g in self.story_groups)
            and np.all(self.story_damping_stiffness == DampingStiffness.INITIAL)
        )

    @property
    def times(self) -> np.ndarray:
        return np.arange(self.steps + 1) * self.dt[0]

    def modal_damping(self, member: int = 0) -> np.ndarray:
        """The modal damping of batch member ``member`` as one dense n x n matrix over the
        DOFs (N s/m): its blocks where they are, zeros elsewhere (and without any)."""
        out = np.zeros((self.n_dof, self.n_dof))
        if self.modal_start is None:
            return out
        at = 0
        for k in range(len(self.modal_start) - 1):
            dofs = self.modal_dofs[self.modal_start[k]:self.modal_start[k + 1]]
            size = len(dofs)
            out[np.ix_(dofs, dofs)] += self.modal_matrix[member, at:at + size * size].reshape(
                size, size)
            at += size * size
        return out



def _groups(elements, n_batch_values):
    """Group elements by law; params stacked over the batch from ``n_batch_values``."""
    every = column(elements, "law")
    laws: dict[type, list[int]] = dict.fromkeys(every)
    if len(laws) == 1:  # (a tall pair's storeys, its contacts)
        laws[every[0]] = list(range(len(every)))
    else:
        laws = {}
        for i, law in enumerate(every):
            laws.setdefault(law, []).append(i)
    groups = []
    for law, index in laws.items():
        params = np.array([_rows(values, index) for values in n_batch_values], dtype=float)
        state = np.zeros((params.shape[0], len(index), len(law.state_names)))
        state[:] = np.asarray(law.initial_state(), dtype=float)
        groups.append(LawGroup(law, np.array(index, dtype=np.int64), params, state))
    return tuple(groups)


def _rows(values: list, index: list) -> np.ndarray:
    """(len(index), n) the rows ``values[i]`` (tuples of n numbers), each distinct tuple
    (by identity: a tall building's storeys share theirs) converted once."""
    picked = values if len(index) == len(values) else [values[i] for i in index]
    width = len(picked[0]) if picked else 0
    ids = list(map(id, picked))
    of_id = dict(zip(ids, picked))  # (every tuple of an id is that one tuple)
    if len(of_id) == len(picked):
        return np.array(picked, dtype=float).reshape(len(picked), width)
    number = {i: k for k, i in enumerate(of_id)}
    table = np.array(list(of_id.values()), dtype=float).reshape(len(of_id), width)
    return table[list(map(number.__getitem__, ids))]


def _spring_values(ex: Expanded, field: str, fill: float) -> np.ndarray:
    """A per-storey array of the scene, padded with ``fill`` for the links (and for the
    storeys of a scene expanded without it)."""
    values = getattr(ex, field, None)
    if values is None or len(values) != len(ex.stories):
        values = np.full(len(ex.stories), fill)
    return np.concatenate([np.asarray(values, dtype=float), np.full(len(ex.links), fill)])


def _geometric_stiffness(ex: Expanded) -> np.ndarray:
    """P / h of every spring (N/m): the storeys with a gravity load
    (:func:`pframe.assemble.modes.geometric_stiffness`), 0 elsewhere."""
    from pframe.assemble.modes import geometric_stiffness

    return np.concatenate([geometric_stiffness(ex), np.zeros(len(ex.links))])


def _p_delta_warnings(plan: Plan) -> tuple[str, ...]:
    """Storeys that P-delta softens to no lateral stiffness: at once (elastic buckling under
    their own weight) or once they yield (negative post-yield stiffness)."""
    if plan.story_kg is None or not np.any(plan.story_kg):
        return ()
    out = []
    for group in plan.story_groups:
        for j, e in enumerate(group.index):
            kg = float(np.max(plan.story_kg[:, e]))
            if kg == 0.0:
                continue
            k0 = float(np.min(plan.story_k0[:, e]))
            after = group.law.post_yield_stiffness(group.params[0, j])
            name = plan.story_names[e]
            if k0 - kg <= 0.0:
                out.append(f"storey {name}: P/h = {kg:.4g} N/m is at least its stiffness "
                           f"{k0:.4g} N/m: it buckles under its gravity load (P-delta) and the "
                           "run will diverge; check the masses, height and stiffness")
            elif after is not None and after - kg < 0.0:
                out.append(f"storey {name}: its post-yield stiffness {after:.4g} N/m is below "
                           f"P/h = {kg:.4g} N/m: once it yields it loses lateral strength as it "
                           "drifts (negative tangent, P-delta); Newton handles it, but the "
                           "storey may ratchet towards collapse: watch its drift ratio")
    return tuple(out)


def _material_warnings(plan: Plan) -> tuple[str, ...]:
    """Each spring's law's own warnings on its parameters (Law.parameter_warnings), once per
    storey or link and message."""
    ns = len(plan.story_names)
    nl = ns + len(plan.link_names)
    out = []
    for group in plan.story_groups:
        said: dict = {}  # the law's warnings on a row of parameters, once per distinct row
        if not any(group.law.parameter_warnings(row) for row in _distinct_rows(group.params)):
            continue  # (a tall building's storeys share a few rows: none says anything)
        for j, e in enumerate(group.index):
            if e >= nl:  # the soil's springs: their values are checked as the scene's
                continue
            name = (f"storey {plan.story_names[e]}" if e < ns
                    else f"link {plan.link_names[e - ns]}")
            messages = []
            for b in range(group.params.shape[0]):
                row = group.params[b, j]
                key = row.tobytes()
                if key not in said:
                    said[key] = list(group.law.parameter_warnings(row))
                messages += said[key]
            for message in dict.fromkeys(messages):
                out.append(f"{name}: {message}")
    return tuple(out)


def _distinct_rows(params: np.ndarray) -> np.ndarray:
    """The distinct rows of ``params`` (..., n), bit for bit (-0.0 is not 0.0)."""
    rows = np.ascontiguousarray(params).reshape(-1, params.shape[-1])
    if not rows.size:  # no rows, or rows of no numbers (one, empty, stands for them)
        return rows[:1]
    whole = np.dtype((np.void, rows.dtype.itemsize * rows.shape[1]))
    # np.unique's own would import numpy.ma (numpy 2.3 on), about 7 ms of a short run
    return sorted_unique(rows.view(whole)).view(rows.dtype).reshape(-1, rows.shape[1])


class _Soil:
    """The foundations on soil of a scene (docs/soil.md): foundation f's sway DOF is the
    extra node ``nodes + 2 f``, its rocking DOF ``nodes + 2 f + 1`` (each one component)."""

    def __init__(self, ex: Expanded, nodes: int):
        self.nodes = nodes
        self.sway = {f.building: nodes + 2 * i for i, f in enumerate(ex.foundations)}
        self.count = len(ex.foundations)

    def keys(self) -> list[tuple[int, int]]:
        return [(self.nodes + i, 0) for i in range(2 * self.count)]

    def channel(self, ex: Expanded, key_node: int) -> int:
        """The channel of a foundation's DOF: its sway is loaded along x by its building's
        support (its rocking by none)."""
        f = key_node - self.nodes
        if f < 0 or f % 2:
            return -1
        building = ex.foundations[f // 2].building
        node = int(np.flatnonzero(ex.node_building == building)[0])
        return grounds.channel_index(ex, node, 0)

    def stories(self, ex: Expanded) -> tuple:
        """The storeys; a storey on soil deforms by u_upper - u_lower - h theta (its lower
        side holds the rocking's lever h) and a first storey stands on the sway DOF."""
        if not self.count:
            return ex.stories
        out = []
        for e, b, h in zip(ex.stories, ex.story_building, ex.story_height):
            if int(b) in self.sway:
                sway = self.sway[int(b)]
                lower, upper = e.side_terms()
                nodes = e.nodes
                if e.nodes[0] < 0:
                    lower, nodes = ((sway, 0, 1.0),), (sway, e.nodes[1])
                e = dataclasses.replace(e, nodes=nodes,
                                        sides=(lower + ((sway + 1, 0, float(h)),), upper))
            out.append(e)
        return tuple(out)

    def springs(self, ex: Expanded) -> tuple:
        """The soil's Kelvin-Voigt springs to the ground: sway, then rocking, per foundation
        (the law's module imported for a scene on soil only)."""
        if not ex.foundations:
            return ()
        from pframe.laws import get_law
        from pframe.model.expand import Element

        law = get_law("material", "kelvin_voigt")
        out = []
        for f in ex.foundations:
            sway = self.sway[f.building]
            name = ex.buildings[f.building]
            out.append(Element(f"{name}/soil_sway", (-1, sway), law,
                               (f.sway_stiffness, f.sway_damping, 1.0, 1e-5)))
            out.append(Element(f"{name}/soil_rocking", (-1, sway + 1), law,
                               (f.rocking_stiffness, f.rocking_damping, 1.0, 1e-5)))
        return tuple(out)

    def masses(self, ex: Expanded) -> np.ndarray:
        """Every DOF's mass: the nodes' degrees of freedom, then m_f and I_f of each
        foundation."""
        extra = [x for f in ex.foundations for x in (f.mass, f.rotational_inertia)]
        own = ex.dof_mass if ex.dof_mass is not None else ex.masses
        return np.concatenate([np.asarray(own, dtype=float), np.array(extra, dtype=float)])

    def pad(self, values: np.ndarray, fill: float) -> np.ndarray:
        return np.concatenate([values, np.full(2 * self.count, fill)])

    def rocking_groups(self, ex: Expanded, springs, key_index) -> dict:
        """rocking DOF -> the DOFs its storeys join (its building's floors and sway DOF)."""
        groups = {key_index[(sway + 1, 0)]: {key_index[(sway, 0)]}
                  for sway in self.sway.values()}
        for e, b in zip(springs, ex.story_building):  # the storeys come first in springs
            if int(b) in self.sway:
                rock = key_index[(self.sway[int(b)] + 1, 0)]
                groups[rock].update(key_index[(i, 0)] for i in e.nodes if i >= 0)
        return groups

    def plan_fields(self, ex: Expanded, dof_of) -> dict:
        if not self.count:
            return {}
        dofs = np.array([[dof_of(s, 0), dof_of(s + 1, 0)] for s in self.sway.values()],
                        dtype=np.int64)
        return dict(foundations=tuple(ex.buildings[f.building] for f in ex.foundations),
                    foundation_dofs=dofs,
                    foundation_soil=tuple(f.describe() for f in ex.foundations))


def batch_key(ex: Expanded) -> tuple:
    """What the variants of one batch must share (:func:`assemble_batch`): topology, laws,
    steps, integrator, recorders, the Rayleigh stiffness choice and the Newton settings (one
    plan holds one tolerance and one iteration limit). Variants with equal keys differ in
    numbers only (masses, stiffnesses, gaps, law parameters, excitation, dt)."""
    return (
        ex.node_names,
        *(tuple(zip(*(column(elements, f) for f in fields))) for elements, fields in (
            (ex.stories, ("name", "nodes", "law")),
            (ex.contacts, ("name", "nodes", "law", "lower")),
            (ex.links, ("name", "nodes", "law")))),
        ex.channels,
        ex.point_names,
        ex.steps,
        ex.integrator,
        ex.recorders,
        tuple((d.kind, getattr(d, "stiffness", None)) for d in ex.damping),
        (ex.tolerance, ex.absolute_tolerance, ex.max_iterations),
        tuple(f.building for f in ex.foundations),
    )


def _dof_keys(variants) -> list[tuple[int, int]]:
    """The degrees of freedom of a batch: those any member moves ((node, component), in node
    then component order); a member that leaves one at rest keeps it at rest (no element of
    it acts on it, nothing loads it)."""
    nodes = len(variants[0].node_names)
    if all(ex.dofs is None for ex in variants):
        return [(i, 0) for i in range(nodes)]
    return sorted({key for ex in variants for key in ex.dofs or [(i, 0) for i in range(nodes)]})


def _per_key(ex: Expanded, keys, values: np.ndarray, fallback=dict,
             planar: bool = False) -> np.ndarray:
    """A member's per-DOF values on the batch's DOFs: its own where it has them, else
    ``fallback()``'s (a dict; a mass: another member's) or 0. ``planar``: the batch's DOFs
    are u_x of every node (:func:`_dof_keys`), a planar member's own."""
    if planar and ex.dofs is None:
        return np.array(values, dtype=float)
    own = ex.dofs or [(i, 0) for i in range(len(ex.node_names))]
    if len(own) == len(keys) and list(own) == list(keys):  # its own DOFs: its own values
        return np.array(values, dtype=float)
    mine = dict(zip(own, np.asarray(values, dtype=float)))
    other = fallback()
    return np.array([mine.get(key, other.get(key, 0.0)) for key in keys])


def assemble(expanded: Expanded) -> Plan:
    """A plan for one scene (a batch of one)."""
    return assemble_batch([expanded])


#: the fields of an Expanded scene that its ground motion sets (Expanded.with_ground and
#: with_supports change these alone)
_MOTION_FIELDS = frozenset({"steps", "ground_acceleration", "ground_acceleration_y",
                            "support_samples", "ground_given"})


def assemble_batch(variants: list[Expanded]) -> Plan:
    """A plan for variants of one scene that differ only in numbers (masses, stiffnesses,
    gaps, law parameters, excitation, dt), not in topology, laws, steps or recorders.
    Members that differ in their ground motion alone (one scene under many records, as a
    risk study's) are assembled once: :func:`_broadcast`."""
    if len(variants) > 2 and _motions_only(variants):
        return _broadcast(variants)
    plan, fit_warnings = _assembled(variants)
    return _checked(plan, variants, fit_warnings)


def _motions_only(variants: list[Expanded]) -> bool:
    """Whether every member is the first but for its ground motion: each other field the
    very object of the first's (members :func:`pframe.gap.runs.under` made of one scene)."""
    first = variants[0]
    names = [f.name for f in dataclasses.fields(first) if f.name not in _MOTION_FIELDS]
    return all(ex.steps == first.steps and all(getattr(ex, n) is getattr(first, n)
                                               for n in names) for ex in variants[1:])


def _broadcast(variants: list[Expanded]) -> Plan:
    """:func:`assemble_batch` of members that differ in their ground motion alone: the
    plan of the first, each field that has a row per member (those whose shape a plan of two
    members changes) repeated for every member, the ground motions each member's; then the
    checks of the whole batch, as for any batch. The assembly is a function of each member's
    numbers, the same in every member, so the plan is the one member by member, to the bit.
    Not for members whose ground displacements the plan carries (several supports, ground
    displacements recorded): those are assembled member by member."""
    one, fit_warnings = _assembled(variants[:1])
    if one.ground_motion is not None:
        plan, fit_warnings = _assembled(variants)
        return _checked(plan, variants, fit_warnings)
    two, _ = _assembled(variants[:2])
    changes = _per_member(one, two, len(variants), skip=("ground_acceleration",
                                                         "more_channels"))
    changes["ground_acceleration"] = np.array([_channels(ex)[0] for ex in variants])
    if one.more_channels is not None:
        changes["more_channels"] = np.array([_channels(ex) for ex in variants])
    return _checked(dataclasses.replace(one, **changes), variants, fit_warnings,
                    motions_only=True)


def _per_member(one, two, count: int, skip=()) -> dict:
    """The fields of the dataclass ``one`` (of a plan of one member) that have a row per
    member, each repeated ``count`` times: the arrays whose shape ``two`` (the same of two
    members) changes, within fields that are dataclasses (a law group, the sides' terms) and
    tuples of them too; not the fields named in ``skip``."""
    changes = {}
    for field in dataclasses.fields(one):
        if field.name in skip:
            continue
        a, b = getattr(one, field.name), getattr(two, field.name)
        if isinstance(a, np.ndarray):
            if a.shape != b.shape:
                changes[field.name] = np.repeat(a, count, axis=0)
        elif _instance(a):
            inner = _per_member(a, b, count)
            if inner:  # (a dataclass rebuilt unchanged could recompute its derived fields)
                changes[field.name] = dataclasses.replace(a, **inner)
        elif isinstance(a, tuple) and a and _instance(a[0]):
            inner = [_per_member(x, y, count) for x, y in zip(a, b)]
            if any(inner):
                changes[field.name] = tuple(dataclasses.replace(x, **c) if c else x
                                            for x, c in zip(a, inner))
    return changes


def _instance(value) -> bool:
    return dataclasses.is_dataclass(value) and not isinstance(value, type)


def _checked(plan: Plan, variants: list[Expanded], fit_warnings: tuple,
             motions_only: bool = False) -> Plan:
    """``plan`` with its sub-steps and the warnings of its checks (stability, P-delta, the
    laws' parameters, the time scales), after the scene's and the damping fit's;
    ``motions_only``: members that differ in their ground motion alone (:func:`_broadcast`)."""
    first = variants[0]
    cd_parts, event_parts, warnings = stability.check(plan, first.integrator)
    warnings = (warnings + fit_warnings + _p_delta_warnings(plan)
                + _material_warnings(plan))
    plan = dataclasses.replace(plan, cd_parts=cd_parts, event_parts=event_parts)
    return dataclasses.replace(plan, warnings=first.warnings + warnings
                               + timescales.check(plan, variants, motions_only))


def _assembled(variants: list[Expanded]) -> tuple[Plan, tuple]:
    """The plan of ``variants`` before its checks (:func:`_checked`), and the damping
    fit's warnings."""
    first = variants[0]
    key = batch_key(first) if len(variants) > 1 else None
    for i, ex in enumerate(variants[1:], start=1):
        if batch_key(ex) != key:
            raise InputError(f"variant {i} differs from variant 0 in topology, laws, kinds of "
                             "damping, steps, recorders or Newton settings; a batch may vary "
                             "numbers only")
    nodes = len(first.node_names)
    soil = _Soil(first, nodes)
    # the degrees of freedom: the nodes' (u_x of each in a planar scene), then each
    # foundation's sway and rocking
    keys = _dof_keys(variants) + soil.keys()
    key_index = {key: i for i, key in enumerate(keys)}
    key_array = np.array(keys, dtype=np.int64).reshape(-1, 2)  # (node, component) each
    n = len(keys)
    # the kernel's spring elements: storeys (a first storey on soil stands on its foundation's
    # sway DOF), then links, then the soil's springs
    spring_sets = [soil.stories(ex) + ex.links + soil.springs(ex) for ex in variants]
    springs = spring_sets[0]
    raw = (incidence.build(spring_sets, lambda node, c: key_index[(node, c)]),
           incidence.build([ex.contacts for ex in variants],
                           lambda node, c: key_index[(node, c)]))
    principal = _principal(key_array[:, 0], nodes + 2 * len(first.foundations))

    def node_dofs(elements):  # each side's node's first DOF (the plain element's DOFs)
        ends = column_array(elements, "nodes", np.int64).reshape(len(elements), 2)
        return np.where(ends >= 0, principal[np.maximum(ends, 0)], -1)

    packed = [column(ex.stories + ex.links + soil.springs(ex), "packed") for ex in variants]
    # each member's laws are the first's (batch_key)
    k0 = np.array([modes.per_law(ex.stories + ex.links + soil.springs(ex),
                                 modes.initial_tangent) for ex in variants])
    k0 = k0.reshape(len(variants), len(springs))
    fitted = damping.BatchDamping(variants, k0[:, :len(first.stories)])
    rocking = {key_index[(sway + 1, 0)] for sway in soil.sway.values()}
    edges = np.concatenate([incidence.edges(node_dofs(springs), raw[0]),
                            incidence.edges(node_dofs(first.contacts), raw[1])])
    if rocking:
        edges = edges[~np.isin(edges, sorted(rocking)).any(axis=1)]
    # a building's modal damping couples all its DOFs
    modal = [(key_index[a], key_index[c]) for block in fitted.modal_keys
             for i, a in enumerate(block) for c in block[i + 1:]]
    order = _node_order(key_array[:, 0], np.concatenate([edges, np.array(modal, dtype=np.int64)
                                              .reshape(-1, 2)]))
    if first.foundations:  # each rocking DOF couples to every floor of its building: last in it
        order = place_last(order, soil.rocking_groups(first, springs, key_index))
    dof_of_key = np.empty(n, dtype=np.int64)
    dof_of_key[order] = np.arange(n)
    story_sides, contact_sides = (_renumbered(x, dof_of_key) for x in raw)
    story_dofs = _renumbered_dofs(node_dofs(springs), dof_of_key)
    contact_dofs = _renumbered_dofs(node_dofs(first.contacts), dof_of_key)
    all_edges = np.concatenate([incidence.edges(story_dofs, story_sides),
                                incidence.edges(contact_dofs, contact_sides),
                                dof_of_key[np.array(modal, dtype=np.int64).reshape(-1, 2)]])
    node_keys = keys[:len(keys) - 2 * len(first.foundations)]
    planar = all(ex.dofs is None for ex in variants)
    masses = _masses(variants, node_keys, soil, planar)
    node_of_key = np.where(key_array[:, 0] < nodes, key_array[:, 0], -1)
    # a0 m on every DOF of a building's floors (translations and rotations alike), none on a
    # foundation's (the soil's dashpots damp them)
    mass_damping = [(np.where(node_of_key >= 0, f.a0[np.clip(node_of_key, 0, None)], 0.0)
                     * masses[b])[order] for b, f in enumerate(fitted.fits)]
    story_beta = [np.concatenate([f.a1, np.zeros(len(springs) - len(first.stories))])
                  for f in fitted.fits]

    history, envelope = _recorded(first, planar)

    by_building = np.array([DAMPING_STIFFNESS[getattr(d, "stiffness", "initial")]
                            for d in first.damping], dtype=np.int64).reshape(-1)
    damping_codes = np.concatenate([
        by_building[np.asarray(first.story_building, dtype=np.int64)],
        np.full(len(springs) - len(first.stories), DampingStiffness.INITIAL,
                dtype=np.int64)])  # links, soil: no Rayleigh term (a1 = 0)
    pad = np.zeros(2 * len(first.foundations))
    plan = Plan(
        node_names=first.node_names,
        node_dof=dof_of_key[principal[:nodes]],
        story_names=tuple(column(first.stories, "name")),
        contact_names=tuple(column(first.contacts, "name")),
        buildings=first.buildings,
        steps=first.steps,
        bandwidth=int(bandwidth(all_edges, np.arange(n))),
        integrator=first.integrator.coefficients(),
        integrator_name=first.integrator.describe(),
        tolerance=first.tolerance,
        absolute_tolerance=first.absolute_tolerance,
        max_iterations=first.max_iterations,
        dt=np.array([ex.dt for ex in variants]),
        mass=np.array([m[order] for m in masses]),
        mass_damping=np.array(mass_damping),
        story_dofs=story_dofs,
        story_k0=k0,
        story_isolated=np.concatenate([fitted.isolated, k0[:, len(first.stories):]], axis=1),
        story_beta=np.array(story_beta).reshape(len(variants), len(springs)),
        story_damping_stiffness=damping_codes,
        story_groups=_groups(springs, packed),
        contact_dofs=contact_dofs,
        contact_gap=np.array([column(ex.contacts, "gap") for ex in variants]).reshape(
            len(variants), len(first.contacts)),
        contact_groups=_groups(first.contacts,
                               [column(ex.contacts, "packed") for ex in variants]),
        ground_acceleration=np.array([_channels(ex)[0] for ex in variants]),
        more_channels=(np.array([_channels(ex) for ex in variants])
                       if len(first.channels) > 1 else None),
        initial_displacement=np.array([np.concatenate([_per_key(
            ex, node_keys, ex.initial_displacement, planar=planar), pad])[order] for ex in variants]),
        initial_velocity=np.array([np.concatenate([_per_key(
            ex, node_keys, ex.initial_velocity, planar=planar), pad])[order] for ex in variants]),
        history=tuple(history.items()),
        envelope=tuple(envelope),
        link_names=tuple(column(first.links, "name")),
        story_height=np.array([soil.pad(_spring_values(ex, "story_height", np.nan), np.nan)
                               for ex in variants]),
        story_kg=np.array([soil.pad(_geometric_stiffness(ex), 0.0) for ex in variants]),
        contact_share=np.array([column(ex.contacts, "share") for ex in variants],
                               dtype=float).reshape(len(variants), len(first.contacts), 2),
        contact_capacity=np.array([np.nan if c is None else c for c in
                                   column(first.contacts, "shear_capacity")], dtype=float),
        **soil.plan_fields(first, lambda node, c: int(dof_of_key[key_index[(node, c)]])),
        story_sides=story_sides,
        contact_sides=contact_sides,
        channels=first.channels,
        dof_channel=_dof_channels(first, key_array, nodes, soil)[order],
        supports=first.supports,
        node_support=first.node_support,
        **grounds.ground_fields(variants, spring_sets, set(history) | set(envelope)),
        dof_node=node_of_key[order],
        dof_component=key_array[:, 1][order],
        planar=planar,
        node_extent=first.node_extent,
        **_gauges(variants, key_index, dof_of_key),
        **fitted.plan_fields(lambda key: int(dof_of_key[key_index[key]])),
    )
    return plan, fitted.warnings


def _recorded(first: Expanded, planar: bool) -> tuple[dict[str, int], list[str]]:
    """The quantities the kernel records: histories (quantity -> every how many steps) and
    envelopes, the recorders' and those the checks and the file need, none of a kind of
    element the scene has not."""
    history: dict[str, int] = {}
    envelope: list[str] = []
    for rec in first.recorders:
        for q in rec.quantities:
            if rec.kind == "history":
                if q in history and history[q] != rec.every:
                    raise InputError(f"{q} is recorded twice with different 'every' "
                                     f"({history[q]} and {rec.every})")
                history[q] = rec.every
            elif q not in envelope:
                envelope.append(q)
    struck = ~np.isnan(column_array(first.contacts, "at", float).reshape(-1, 2)).all(axis=1)
    if struck.any() and "contact_force" not in envelope:  # (Element.column_side)
        # the struck columns' shear: written (peak_column_shear) and checked on its peak
        envelope.append("contact_force")
    if first.point_names and not planar and "point_drift" not in envelope:
        envelope.append("point_drift")  # the storeys' torsional irregularity is read off it
    if not planar and "displacement" not in envelope:
        envelope.append("displacement")  # the floors' rotations: the small-rotation check
    for kind, elements in (("contact_", first.contacts), ("link_", first.links),
                           ("foundation_", first.foundations), ("point_", first.point_names)):
        if not elements:
            history = {q: k for q, k in history.items() if not q.startswith(kind)}
            envelope = [q for q in envelope if not q.startswith(kind)]
    return history, envelope


def _masses(variants: list[Expanded], node_keys: list, soil,
            planar: bool = False) -> list[np.ndarray]:
    """Each variant's mass (or inertia) on each DOF key: the nodes', a DOF a variant lacks
    taking another's (a batch's union of DOFs), then the foundations'."""
    nodes = len(variants[0].node_names)

    def known() -> dict:
        return {key: m for ex in variants for key, m in zip(
            ex.dofs or [(i, 0) for i in range(nodes)],
            ex.dof_mass if ex.dof_mass is not None else ex.masses)}

    return [np.concatenate([_per_key(ex, node_keys, ex.dof_mass if ex.dof_mass is not None
                                     else ex.masses, known, planar),
                            soil.masses(ex)[-2 * soil.count:]
                            if soil.count else np.zeros(0)]) for ex in variants]


def _dof_channels(first: Expanded, keys: np.ndarray, nodes: int, soil) -> np.ndarray:
    """The ground-motion channel that loads each DOF key ((node, component) rows; -1: none):
    a node's u_x and u_y their support's along their site axis (pframe.assemble.grounds), a
    foundation's sway its building's support's along x, a rotation or rocking none."""
    node, component = keys[:, 0], keys[:, 1]
    support = (np.asarray(first.node_support, dtype=np.int64)[np.minimum(node, nodes - 1)]
               if first.node_support else np.zeros(len(node), dtype=np.int64))
    # each (support, translation)'s channel, asked once of grounds.channel_index
    table = {}
    for s, c in set(zip(support[(node < nodes) & (component < 2)].tolist(),
                        component[(node < nodes) & (component < 2)].tolist())):
        at = int(np.flatnonzero((node < nodes) & (component == c) & (support == s))[0])
        table[(s, c)] = grounds.channel_index(first, int(node[at]), c)
    out = np.full(len(node), -1, dtype=np.int64)
    for (s, c), channel in table.items():
        out[(node < nodes) & (component == c) & (support == s)] = channel
    for at in np.flatnonzero(node >= nodes).tolist():
        out[at] = soil.channel(first, int(node[at]))
    return out


def _node_order(node_of: np.ndarray, edges) -> np.ndarray:
    """The DOFs' order (new -> old key index): the nodes in reverse Cuthill-McKee order of the
    graph of nodes the elements join, each node's DOFs together (u_x, u_y, theta). A floor in
    plan then widens the band by its three DOFs, not by how far apart a DOF-level numbering
    may scatter them (the DOF graph's own RCM gave half-bandwidth 12 where this gives 8 on a
    pair of buildings in plan). A planar scene (one DOF per node) is numbered as it was.
    ``node_of``: each DOF key's node."""
    nodes, local = np.unique(node_of, return_inverse=True)  # key -> its node's number
    pairs = np.array(edges, dtype=np.int64).reshape(-1, 2)
    node_order = reverse_cuthill_mckee(len(nodes), local[pairs[(pairs >= 0).all(axis=1)]])
    rank = np.empty(len(nodes), dtype=np.int64)
    rank[node_order] = np.arange(len(nodes))
    # each node's DOFs together, in key order within it (a stable sort)
    return np.argsort(rank[local.reshape(-1)], kind="stable").astype(np.int64)


def _principal(key_nodes: np.ndarray, nodes: int) -> np.ndarray:
    """(nodes,) each node's first DOF (its u_x in a planar scene) by key index (-1: none),
    from each key's node."""
    out = np.full(nodes, -1, dtype=np.int64)
    found, first = np.unique(key_nodes, return_index=True)
    out[found] = first
    return out


def _renumbered(sides: Sides, dof_of_key: np.ndarray) -> Sides:
    return dataclasses.replace(sides, dof=dof_of_key[sides.dof] if sides.dof.size
                               else sides.dof)


def _renumbered_dofs(dofs: np.ndarray, dof_of_key: np.ndarray) -> np.ndarray:
    out = dofs.copy()
    out[dofs >= 0] = dof_of_key[dofs[dofs >= 0]]
    return out


def _gauges(variants, key_index, dof_of_key) -> dict:
    """The plan's gauge arrays (Plan.gauge_*) of the named plan points."""
    start, dof, coefs = [0], [], [[] for _ in variants]
    for g in range(len(variants[0].gauges)):  # each gauge's terms: those of any member
        members = [{(node, c): a for node, c, a in ex.gauges[g]} for ex in variants]
        terms = incidence.merged(list(mine) for mine in members)
        dof += [int(dof_of_key[key_index[key]]) for key in terms]
        for b, mine in enumerate(members):
            coefs[b] += [mine.get(key, 0.0) for key in terms]
        start.append(len(dof))
    return dict(point_names=variants[0].point_names,
                gauge_start=np.array(start, dtype=np.int64),
                gauge_dof=np.array(dof, dtype=np.int64),
                gauge_coef=np.array(coefs, dtype=float).reshape(len(variants), len(dof)))


def _channels(ex: Expanded) -> np.ndarray:
    """(C, steps + 1): the ground motion along each of the scene's channels."""
    if ex.support_samples is not None:
        return np.asarray(ex.support_samples, dtype=float)
    rows = {"x": ex.ground_acceleration, "y": ex.ground_acceleration_y}
    return np.array([rows[c] for c in ex.channels], dtype=float)
