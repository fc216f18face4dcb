"""The plan: everything the kernel needs as numpy arrays, and what it may leave out.

Arrays that differ between variants of a sweep carry a leading batch axis ``B``; the topology
(which DOFs a storey or contact joins, which law it uses) is shared by the batch.
"""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np

from pframe.assemble import damping, modes, stability, timescales
from pframe.assemble.ordering import bandwidth, place_last, reverse_cuthill_mckee
from pframe.errors import InputError
from pframe.kernel.state import DampingStiffness
from pframe.model.expand import Expanded

if TYPE_CHECKING:
    from pframe.peers.scene import PeerScene

#: the scene's ``damping.stiffness`` -> the kernel's slot
DAMPING_STIFFNESS = {mode.name.lower(): mode for mode in DampingStiffness}


@dataclass(frozen=True)
class LawGroup:
    """Elements of one law: their indices, packed parameters and initial state."""

    law: type
    index: np.ndarray  # (g,) element indices
    params: np.ndarray  # (B, g, n_params)
    state: np.ndarray  # (B, g, n_state)


@dataclass(frozen=True)
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
    ground_acceleration: np.ndarray  # (B, steps + 1) m/s^2
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
    #: floor-to-column contacts: (c, 2) the struck storey's lower floor DOF on each side (-1:
    #: none or the ground) and (B, c, 2) the weight psi of each side's node (1: a floor)
    contact_lower: np.ndarray = None
    contact_share: np.ndarray = None
    contact_capacity: np.ndarray = None  # (c,) a struck column's shear capacity (N), NaN: none
    #: soil (docs/soil.md): the buildings whose foundations sway and rock, their (F, 2) sway
    #: and rocking DOFs, each spring's rocking DOF (s,) (-1: none; the lever is its height),
    #: and the ground load's influence (n,): 1 on a translational DOF, 0 on a rocking one
    #: (the ground load is -m influence a_g; an absolute acceleration is a + influence a_g).
    #: The soil's springs are the last 2 F spring elements (after the links), sway then
    #: rocking per foundation; their work is booked with the links'.
    foundations: tuple[str, ...] = ()
    foundation_dofs: np.ndarray = None
    story_theta: np.ndarray = None
    ground_influence: np.ndarray = None
    #: what each foundation's soil is (FoundationSoil.describe), for the summary and the file
    foundation_soil: tuple[str, ...] = ()
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

    @property
    def n_springs(self) -> int:
        """Spring elements in the kernel: the storeys, then the links, then the soil's."""
        return len(self.story_names) + len(self.link_names) + 2 * len(self.foundations)

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
    laws: dict[type, list[int]] = {}
    for i, element in enumerate(elements):
        laws.setdefault(element.law, []).append(i)
    groups = []
    for law, index in laws.items():
        params = np.array([[values[i] for i in index] for values in n_batch_values], dtype=float)
        state = np.zeros((params.shape[0], len(index), len(law.state_names)))
        state[:] = np.asarray(law.initial_state(), dtype=float)
        groups.append(LawGroup(law, np.array(index, dtype=np.int64), params, state))
    return tuple(groups)


def _spring_values(ex: Expanded, field: str, fill: float) -> np.ndarray:
    """A per-storey array of the scene, padded with ``fill`` for the links (and for the
    storeys of a scene expanded without it)."""
    values = getattr(ex, field, None)
    if values is None or len(values) != len(ex.stories):
        values = np.full(len(ex.stories), fill)
    return np.concatenate([np.asarray(values, dtype=float), np.full(len(ex.links), fill)])


def _geometric_stiffness(ex: Expanded) -> np.ndarray:
    """P / h of every spring (N/m): the storeys with a gravity load, 0 elsewhere."""
    gravity = _spring_values(ex, "story_gravity", 0.0)
    height = _spring_values(ex, "story_height", np.nan)
    out = np.zeros(len(gravity))
    loaded = gravity > 0.0
    out[loaded] = gravity[loaded] / height[loaded]
    return out


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
        for j, e in enumerate(group.index):
            if e >= nl:  # the soil's springs: their values are checked as the scene's
                continue
            name = (f"storey {plan.story_names[e]}" if e < ns
                    else f"link {plan.link_names[e - ns]}")
            for message in dict.fromkeys(m for b in range(group.params.shape[0])
                                         for m in group.law.parameter_warnings(
                                             group.params[b, j])):
                out.append(f"{name}: {message}")
    return tuple(out)


class _Soil:
    """The foundations on soil of a scene (docs/soil.md): foundation f's sway DOF is the
    extra node ``nodes + 2 f``, its rocking DOF ``nodes + 2 f + 1``."""

    def __init__(self, ex: Expanded, nodes: int):
        self.nodes = nodes
        self.sway = {f.building: nodes + 2 * i for i, f in enumerate(ex.foundations)}
        self.count = len(ex.foundations)

    def stories(self, ex: Expanded) -> tuple:
        """The storeys, a first storey on soil standing on its foundation's sway DOF."""
        if not self.count:
            return ex.stories
        out = []
        for e, b in zip(ex.stories, ex.story_building):
            if e.nodes[0] < 0 and int(b) in self.sway:
                e = dataclasses.replace(e, nodes=(self.sway[int(b)], e.nodes[1]))
            out.append(e)
        return tuple(out)

    def springs(self, ex: Expanded) -> tuple:
        """The soil's Kelvin-Voigt springs to the ground: sway, then rocking, per foundation."""
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
        """Every DOF's mass: the nodes', then m_f and I_f of each foundation."""
        extra = [x for f in ex.foundations for x in (f.mass, f.rotational_inertia)]
        return np.concatenate([np.asarray(ex.masses, dtype=float), np.array(extra, dtype=float)])

    def pad(self, values: np.ndarray, fill: float) -> np.ndarray:
        return np.concatenate([values, np.full(2 * self.count, fill)])

    def rocking_groups(self, ex: Expanded, springs) -> dict:
        """rocking DOF -> the DOFs its storeys join (its building's floors and sway DOF)."""
        groups = {sway + 1: {sway} for sway in self.sway.values()}
        for e, b in zip(springs, ex.story_building):  # the storeys come first in springs
            if int(b) in self.sway:
                groups[self.sway[int(b)] + 1].update(i for i in e.nodes if i >= 0)
        return groups

    def rocking_edges(self, ex: Expanded, springs) -> list:
        return [(th, i) for th, group in self.rocking_groups(ex, springs).items()
                for i in group]

    def story_theta(self, ex: Expanded, springs, dof_of_node) -> np.ndarray:
        out = np.full(len(springs), -1, dtype=np.int64)
        for s, b in enumerate(ex.story_building):
            if int(b) in self.sway:
                if not np.isfinite(ex.story_height[s]):
                    raise InputError(f"storey {ex.stories[s].name!r} of a building on soil has "
                                     "no height (the rocking's lever): give height")
                out[s] = dof_of_node[self.sway[int(b)] + 1]
        return out

    def plan_fields(self, ex: Expanded, springs, dof_of_node) -> dict:
        if not self.count:
            return {}
        influence = np.ones(len(dof_of_node))
        dofs = np.array([[dof_of_node[s], dof_of_node[s + 1]] for s in self.sway.values()],
                        dtype=np.int64)
        influence[dofs[:, 1]] = 0.0  # the ground load acts on translations only
        return dict(foundations=tuple(ex.buildings[f.building] for f in ex.foundations),
                    foundation_dofs=dofs,
                    story_theta=self.story_theta(ex, springs, dof_of_node),
                    ground_influence=influence,
                    foundation_soil=tuple(f.describe() for f in ex.foundations))


def batch_key(ex: Expanded) -> tuple:
    """What the variants of one batch must share (:func:`assemble_batch`): topology, laws,
    steps, integrator, recorders, each building's kind of damping and Rayleigh's stiffness
    choice, and the Newton settings (one plan holds one tolerance and one iteration limit).
    Variants with equal keys differ in numbers only (masses, stiffnesses, gaps, law
    parameters, excitation, dt)."""
    return (
        ex.node_names,
        tuple((e.name, e.nodes, e.law) for e in ex.stories),
        tuple((e.name, e.nodes, e.law, e.lower) for e in ex.contacts),
        tuple((e.name, e.nodes, e.law) for e in ex.links),
        ex.steps,
        ex.integrator,
        ex.recorders,
        tuple((d.kind, getattr(d, "stiffness", None)) for d in ex.damping),
        (ex.tolerance, ex.absolute_tolerance, ex.max_iterations),
        tuple(f.building for f in ex.foundations),
    )


def assemble(expanded: Expanded) -> Plan:
    """A plan for one scene (a batch of one)."""
    return assemble_batch([expanded])


def assemble_batch(variants: list[Expanded]) -> Plan:
    """A plan for variants of one scene that differ only in numbers (masses, stiffnesses,
    gaps, law parameters, excitation, dt), not in topology, laws, steps or recorders."""
    first = variants[0]
    key = batch_key(first)
    for i, ex in enumerate(variants[1:], start=1):
        if batch_key(ex) != key:
            raise InputError(f"variant {i} differs from variant 0 in topology, laws, kinds of "
                             "damping, steps, recorders or Newton settings; a batch may vary "
                             "numbers only")
    nodes = len(first.node_names)
    soil = _Soil(first, nodes)
    n = nodes + 2 * len(first.foundations)  # a foundation's sway and rocking DOFs after the nodes
    # the kernel's spring elements: storeys (a first storey on soil stands on its foundation's
    # sway DOF), then links, then the soil's springs
    springs = soil.stories(first) + first.links + soil.springs(first)
    edges = [e.nodes for e in springs] + [e.nodes for e in first.contacts]
    for e in first.contacts:  # a floor-to-column contact couples up to four nodes
        if max(e.lower) >= 0:
            ends = [i for i in (e.nodes[0], e.lower[0], e.nodes[1], e.lower[1]) if i >= 0]
            edges += [(a, c) for a in ends for c in ends if a < c]

    def dofs(elements):
        out = np.array([[dof_of_node[i] if i >= 0 else -1 for i in e.nodes] for e in elements],
                       dtype=np.int64)
        return out.reshape(len(elements), 2)

    packed = [[e.packed for e in ex.stories + ex.links + soil.springs(ex)] for ex in variants]
    k0 = np.array([[modes.initial_tangent(e.law, p) for e, p in zip(springs, row)]
                   for row in packed])
    k0 = k0.reshape(len(variants), len(springs))
    masses = [soil.masses(ex) for ex in variants]
    fitted = damping.BatchDamping(variants, k0[:, :len(first.stories)])
    if fitted.modal_nodes:  # a building's modal damping couples all its floors
        edges += [(a, c) for block in fitted.modal_nodes for a in block for c in block if a < c]
    order = reverse_cuthill_mckee(n, edges)
    if first.foundations:  # each rocking DOF couples to every floor of its building: last in it
        order = place_last(order, soil.rocking_groups(first, springs))
        edges += soil.rocking_edges(first, springs)
    dof_of_node = np.empty(n, dtype=np.int64)
    dof_of_node[order] = np.arange(n)
    pad_dofs = np.zeros(n - nodes)
    mass_damping = [np.concatenate([f.a0, pad_dofs]) * masses[b]  # foundations: a0 = 0
                    for b, f in enumerate(fitted.fits)]
    mass_damping = [m[order] for m in mass_damping]
    story_beta = [np.concatenate([f.a1, np.zeros(len(springs) - len(first.stories))])
                  for f in fitted.fits]

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
    if any(e.column_side is not None for e in first.contacts) and \
            "contact_force" not in envelope:
        # the struck columns' shear: written (peak_column_shear) and checked on its peak
        envelope.append("contact_force")
    for kind, elements in (("contact_", first.contacts), ("link_", first.links),
                           ("foundation_", first.foundations)):
        if not elements:
            history = {q: k for q, k in history.items() if not q.startswith(kind)}
            envelope = [q for q in envelope if not q.startswith(kind)]

    damping_codes = np.array(
        [DAMPING_STIFFNESS[getattr(first.damping[b], 'stiffness', 'initial')]
         for b in first.story_building]
        + [DampingStiffness.INITIAL] * (len(springs) - len(first.stories)),  # links, soil:
        dtype=np.int64,  # no Rayleigh term (a1 = 0)
    )
    pad = np.zeros(n - nodes)
    plan = Plan(
        node_names=first.node_names,
        node_dof=dof_of_node[:nodes],
        story_names=tuple(e.name for e in first.stories),
        contact_names=tuple(e.name for e in first.contacts),
        buildings=first.buildings,
        steps=first.steps,
        bandwidth=int(bandwidth(edges, dof_of_node)),
        integrator=first.integrator.coefficients(),
        integrator_name=first.integrator.describe(),
        tolerance=first.tolerance,
        absolute_tolerance=first.absolute_tolerance,
        max_iterations=first.max_iterations,
        dt=np.array([ex.dt for ex in variants]),
        mass=np.array([m[order] for m in masses]),
        mass_damping=np.array(mass_damping),
        story_dofs=dofs(springs),
        story_k0=k0,
        story_isolated=np.concatenate([fitted.isolated, k0[:, len(first.stories):]], axis=1),
        story_beta=np.array(story_beta).reshape(len(variants), len(springs)),
        story_damping_stiffness=damping_codes,
        story_groups=_groups(springs, packed),
        contact_dofs=dofs(first.contacts),
        contact_gap=np.array([[e.gap for e in ex.contacts] for ex in variants]).reshape(
            len(variants), len(first.contacts)),
        contact_groups=_groups(first.contacts,
                               [[e.packed for e in ex.contacts] for ex in variants]),
        ground_acceleration=np.array([ex.ground_acceleration for ex in variants]),
        initial_displacement=np.array([np.concatenate([ex.initial_displacement, pad])[order]
                                       for ex in variants]),
        initial_velocity=np.array([np.concatenate([ex.initial_velocity, pad])[order]
                                   for ex in variants]),
        history=tuple(history.items()),
        envelope=tuple(envelope),
        link_names=tuple(e.name for e in first.links),
        story_height=np.array([soil.pad(_spring_values(ex, "story_height", np.nan), np.nan)
                               for ex in variants]),
        story_kg=np.array([soil.pad(_geometric_stiffness(ex), 0.0) for ex in variants]),
        contact_lower=np.array([[dof_of_node[i] if i >= 0 else -1 for i in e.lower]
                                for e in first.contacts], dtype=np.int64).reshape(-1, 2),
        contact_share=np.array([[e.share for e in ex.contacts] for ex in variants],
                               dtype=float).reshape(len(variants), len(first.contacts), 2),
        contact_capacity=np.array([np.nan if e.shear_capacity is None else e.shear_capacity
                                   for e in first.contacts], dtype=float),
        **soil.plan_fields(first, springs, dof_of_node),
        **fitted.plan_fields(dof_of_node),
    )
    cd_parts, event_parts, warnings = stability.check(plan, first.integrator)
    warnings = (warnings + fitted.warnings + _p_delta_warnings(plan)
                + _material_warnings(plan))
    plan = dataclasses.replace(plan, cd_parts=cd_parts, event_parts=event_parts)
    return dataclasses.replace(plan, warnings=first.warnings + warnings
                               + timescales.check(plan, variants))


def _peer_modal(plan: Plan, member: int, problems: list) -> list | None:
    """The ratio of each mode of the whole scene (its storeys on their initial stiffness) that
    OpenSees' global ``modalDamping`` needs to reproduce the plan's modal damping, or None
    for Rayleigh damping; what it cannot reproduce goes to ``problems``."""
    if plan.modal_start is None or len(plan.modal_start) < 2:
        return None
    n, ns = plan.n_dof, len(plan.story_names)
    damping = plan.modal_damping(member)
    if plan.link_names or np.any(plan.mass_damping[member]) or np.any(plan.story_beta[member]):
        problems.append("OpenSees' modalDamping damps the modes of the whole model: every "
                        "building needs modal damping, and no links may join them")
        return None
    springs = [(int(lo), int(up), float(plan.story_k0[member, e]))
               for e, (lo, up) in enumerate(plan.story_dofs[:ns])]
    mass = plan.mass[member]
    scale = 1.0 / np.sqrt(mass)
    values, vectors = np.linalg.eigh(modes.spring_matrix(springs, n) * np.outer(scale, scale))
    omega = np.sqrt(np.clip(values, 0.0, None))
    phi = vectors * scale[:, None]
    ratios = np.array([p @ damping @ p / (2.0 * w) if w > 0.0 else 0.0
                       for p, w in zip(phi.T, omega)])
    mphi = mass[:, None] * phi
    again = mphi @ np.diag(2.0 * ratios * omega) @ mphi.T
    if not np.allclose(again, damping, rtol=1e-9, atol=1e-9 * np.max(np.abs(damping))):
        problems.append("OpenSees' modalDamping takes the modes of the initial stiffness, with "
                        "one ratio per mode of the whole model: give every building the same "
                        "ratio for all its modes, fitted on the initial stiffness (fit: "
                        "initial, or no isolators)")
        return None
    return [float(r) for r in ratios]


def peer_scene(plan: Plan, member: int = 0) -> PeerScene:
    """The scene of one batch member for peer programs: linear contacts, start at rest,
    Rayleigh on the initial stiffness (what the OpenSees peer models)."""
    from pframe.peers.scene import PeerScene

    problems = []  # every reason at once
    if np.any(plan.initial_displacement[member]) or np.any(plan.initial_velocity[member]):
        problems.append("it starts from rest: remove initial_conditions")
    c = plan.integrator
    if plan.contact_lower is not None and np.any(plan.contact_lower >= 0) or (
            plan.contact_share is not None and np.any(plan.contact_share[member] != 1.0)):
        problems.append("its contacts join floors (floor-to-column contacts need a "
                        "multi-point constraint the script does not write)")
    if plan.story_kg is not None and np.any(plan.story_kg[member]):
        problems.append("OpenSees' zeroLength storeys have no P-delta: remove p_delta and "
                        "gravity_load")
    if isinstance(c.opensees, str):  # the integrator's own reason (pframe.integrators)
        problems.append(c.opensees)
    if c.events and plan.contact_names:
        problems.append("OpenSees has no event-aware stepping: set 'events: false' on the "
                        "integrator")
    if np.any(plan.story_damping_stiffness != DampingStiffness.INITIAL):
        problems.append("it damps on the initial stiffness only (damping.stiffness: initial)")
    modal = _peer_modal(plan, member, problems)
    ns = len(plan.story_names)
    for group in plan.story_groups:
        if np.any(group.index >= ns) and group.law.name not in (
                "elastic", "bilinear", "viscous", "kelvin_voigt"):
            problems.append(f"it models links with Elastic, Steel01, Viscous or a Parallel of "
                            f"Elastic and Viscous; the scene's links use {group.law.name!r}")
        if not np.any(group.index < ns):
            continue
        storeys = group.index < ns
        if group.law.opensees not in ("Elastic", "Steel01", "BoucWen", "ModIMKPeakOriented",
                                      "BWBN"):
            problems.append(f"it models storeys with Elastic, Steel01, BoucWen, "
                            f"ModIMKPeakOriented or BWBN (the laws elastic, bilinear, bouc_wen, "
                            f"imk_peak and bwbn); the scene's storeys use "
                            f"{group.law.name!r}, which has no OpenSees uniaxialMaterial "
                            "counterpart")
        elif group.law.opensees == "BoucWen" and np.any(
                group.params[member, storeys, 5] != 1.0) and np.any(
                plan.story_beta[member, group.index[storeys]]):
            # OpenSees damps on its initial tangent k0 (alpha + (1 - alpha) A0), pframe on
            # the tangent at zero drift, k0
            problems.append("it damps Bouc-Wen storeys on OpenSees' initial tangent, which "
                            "differs from pframe's when Ao != 1: give Ao = 1 or damping "
                            "without a stiffness part")
        elif group.law.opensees == "BWBN" and np.any(
                group.params[member, storeys, 5:9] != (1.0, 0.0, 0.0, 0.0)):
            # OpenSees' BWBN has pinching only: no A, nu or eta degradation, z_u with A = 1
            problems.append("OpenSees' BWBN has no strength or stiffness degradation: its "
                            "bwbn storeys need Ao = 1 and deltaA = deltaNu = deltaEta = 0")
    for group in plan.contact_groups:
        if group.law.opensees != "ElasticPPGap":
            problems.append(f"it models contacts with ElasticPPGap (the law linear); the "
                            f"scene's contacts use {group.law.name!r}, which has no OpenSees "
                            "counterpart in pframe's script")
    if plan.foundations:
        problems.append("its bases are fixed: the script has no soil (a foundation's rocking "
                        "needs a rigid-link constraint it does not write); remove soil")
    if problems:
        raise InputError("the OpenSees peer cannot model this scene: " + "; ".join(problems))
    materials = []
    for group in plan.story_groups:
        for j, i in enumerate(group.index):
            if i >= ns:
                continue
            p = group.params[member, j]
            if group.law.opensees == "Elastic":
                materials.append((i, ("elastic", p[0])))
            elif group.law.opensees == "BoucWen":
                materials.append((i, ("bouc_wen", *p[:11])))
            elif group.law.name == "imk_peak":
                materials.append((i, ("imk_peak", *p)))
            elif group.law.opensees == "BWBN":  # OpenSees' 12 numbers, tolerance, iterations
                materials.append((i, ("bwbn", *p[:6], *p[9:17])))
            else:
                materials.append((i, ("bilinear", p[0], p[1], p[2])))
    materials = [m for _, m in sorted(materials, key=lambda t: t[0])]
    ns = len(plan.story_names)
    links = sorted((i, ("elastic", p[0]) if group.law.name == "elastic"
                    else ("bilinear", p[0], p[1], p[2]) if group.law.name == "bilinear"
                    else ("viscous", p[0], p[1]) if group.law.name == "viscous"
                    else ("kelvin_voigt", p[0], p[1], p[2]))
                   for group in plan.story_groups
                   for i, p in zip(group.index, group.params[member]) if i >= ns)
    link_materials = [m for _, m in links]
    stiffness = np.zeros(len(plan.contact_names))
    for group in plan.contact_groups:
        stiffness[group.index] = group.params[member, :, 0]
    rayleigh = []
    names = [""] * plan.n_dof
    for name, dof in zip(plan.node_names, plan.node_dof):
        names[dof] = name
    building_of_node = np.array([plan.buildings.index(n.split("/")[0]) for n in names])
    story_building = building_of_node[plan.story_dofs[:ns, 1]]
    for b in range(len(plan.buildings)):
        nodes = np.flatnonzero(building_of_node == b)
        stories = np.flatnonzero(story_building == b)
        # the storeys with the stiffness term (not the isolators, by default): one a1 for all
        damped = stories[plan.story_beta[member, stories] != 0.0]
        alpha = float(plan.mass_damping[member, nodes[0]] / plan.mass[member, nodes[0]])
        beta = float(plan.story_beta[member, damped[0]]) if len(damped) else 0.0
        rayleigh.append((alpha, beta, nodes, damped))
    return PeerScene(
        node_names=names,
        masses=plan.mass[member].copy(),
        story_nodes=plan.story_dofs[:ns].copy(),
        story_names=list(plan.story_names),
        story_materials=materials,
        contact_nodes=plan.contact_dofs.copy(),
        contact_names=list(plan.contact_names),
        contact_gaps=plan.contact_gap[member].copy(),
        contact_stiffness=stiffness,
        rayleigh=rayleigh,
        ground_acceleration=plan.ground_acceleration[member].copy(),
        dt=float(plan.dt[member]),
        steps=plan.steps,
        tolerance=plan.absolute_tolerance or 1e-12,
        max_iterations=plan.max_iterations,
        link_nodes=plan.story_dofs[ns:].copy(),
        link_materials=link_materials,
        modal=modal,
        integrator=c.opensees,
    )
