"""The scene of one batch member of a plan as peer programs read it (:class:`PeerScene`), every
reason the OpenSees peer cannot model it, and where its model is not pframe's.

Each element's law becomes its OpenSees twin (:mod:`pframe.peers.twins`); a law without one,
and a scene the script cannot build (initial conditions, floor-to-column contacts, an
integrator OpenSees has no counterpart of), are refused with every reason at once. Where the
twin or the script's stepping is the same model but in conditions (a grazing contact, event
location, central difference's damping), the scene says so in ``differences``. A scene on
several supports is written in total coordinates (:mod:`pframe.peers.supports`).
"""

from __future__ import annotations

import dataclasses

import numpy as np

from pframe.assemble import incidence
from pframe.assemble.incidence import Sides
from pframe.assemble.plan import Plan
from pframe.errors import InputError
from pframe.kernel.state import DampingStiffness
from pframe.model.plan import COMPONENTS
from pframe.peers import supports, twins
from pframe.peers.geometry import floors_in_plan, foundations
from pframe.peers.scene import PeerScene, Supports

#: the kernel's slot of a storey's damping stiffness -> the script's name of it
STIFFNESS = {DampingStiffness.INITIAL: "initial", DampingStiffness.CURRENT: "current",
             DampingStiffness.COMMITTED: "committed"}

EVENTS_DIFFERENCE = (
    "events: pframe locates each contact's onset and separation inside a step and resolves "
    "a closed contact in sub-steps (events: true); OpenSees steps over them at dt, as pframe "
    "does with events: false: from the first impact on the two differ by the step's error")
WILSON_DIFFERENCE = (
    "wilson_theta: OpenSees' WilsonTheta reads the ground motion at t + theta dt from the "
    "record, where pframe extrapolates the step's own samples linearly: the two agree under a "
    "ground motion linear in time and differ by O(dt^2) under others")
SUPPORTS_DIFFERENCE = (
    "supports: the script integrates total displacements with the supports' motion imposed, "
    "pframe the motion relative to the supports; the two are one model under Newmark's "
    "average acceleration (gamma = 1/2, beta = 1/4), whose relations the supports' "
    "displacement, velocity and acceleration keep; under {name} the two integrate the "
    "supports' motion differently and part by O(dt^2)")
CENTRAL_DIFFERENCE = (
    "central_difference: pframe takes the velocity-dependent forces (damping, dashpots, "
    "damped contacts) at the velocity of one predictor-corrector pass; OpenSees' "
    "NewmarkExplicit (gamma = 1/2) solves for the step end's velocity with the damping "
    "tangent: where forces depend on velocity the two differ (by O(dt^3) on a damped "
    "oscillator)")


def _scene_refusals(plan: Plan, member: int) -> list[str]:
    """Every reason the script cannot model the scene, whatever its laws."""
    problems = []
    if np.any(plan.initial_displacement[member]) or np.any(plan.initial_velocity[member]):
        problems.append("it starts from rest: remove initial_conditions")
    if plan.contact_share is not None and np.any(plan.contact_share[member] != 1.0):
        problems.append("OpenSees has no element or constraint that puts a contact at a point "
                        "of a column moving as psi u_upper + (1 - psi) u_lower (a "
                        "floor-to-column contact: a multi-point constraint with two retained "
                        "nodes, which OpenSees' rigidLink and equalDOF are not)")
    if isinstance(plan.integrator.opensees, str):  # the integrator's own reason
        problems.append(plan.integrator.opensees)
    if plan.foundations and not plan.planar:
        problems.append("its buildings in plan stand on soil, which the script models for "
                        "planar scenes only")
    return problems


def _twins(plan: Plan, member: int, kind: str, names, problems: list,
           differences: list) -> list:
    """Each element's twin material (a spring's, ``kind`` "material", or a contact's), in
    element order; the elements without one go to ``problems``, each law's differences to
    ``differences``."""
    groups = plan.story_groups if kind == "material" else plan.contact_groups
    out: list = [None] * sum(len(g.index) for g in groups)
    for group in groups:
        refused = {}
        for j, e in enumerate(group.index):
            try:
                made = twins.twin(kind, group.law, group.params[member, j])
            except twins.NoTwin as why:
                refused.setdefault(str(why), []).append(names[e])
                continue
            out[e] = made.material
            differences.extend(d for d in made.differences if d not in differences)
        for why, elements in refused.items():
            problems.append(f"{', '.join(elements)} ({group.law.name}): {why}")
    return out


def _spring_names(plan: Plan) -> list[str]:
    """Each spring element's name: the storeys, the links, then the soil's springs."""
    return [*plan.story_names, *plan.link_names,
            *(f"{b}/soil_{what}" for b in plan.foundations for what in ("sway", "rocking"))]


def _bouc_wen_damping(plan: Plan, member: int, problems: list) -> None:
    """OpenSees damps on its initial tangent k0 (alpha + (1 - alpha) A0), pframe on the
    tangent at zero drift, k0: the same only when A0 = 1."""
    for group in plan.story_groups:
        if group.law.name != "bouc_wen":
            continue
        damped = plan.story_beta[member, group.index] != 0.0
        if np.any(damped & (group.params[member, :, 5] != 1.0)):
            problems.append("it damps Bouc-Wen storeys on OpenSees' initial tangent, which "
                            "differs from pframe's when Ao != 1: give Ao = 1 or damping "
                            "without a stiffness part")


def _velocity_dependent(plan: Plan, member: int, contacts: list, springs: list) -> bool:
    """Whether any force of the scene depends on a velocity (damping, dashpots, damped
    contacts): where central difference's two formulations part."""
    damped_contact = any(m[0] == "jankowski" or (m[0] in ("hertzdamp", "bumper") and m[2])
                         for m in contacts)
    dashpot = any(m is not None and m[0] in ("viscous", "kelvin_voigt") for m in springs)
    return bool(np.any(plan.mass_damping[member]) or np.any(plan.story_beta[member])
                or (plan.modal_start is not None and len(plan.modal_start) > 1)
                or damped_contact or dashpot)


def _integrator(plan: Plan, member: int, contacts: list, springs: list,
                differences: list) -> tuple[tuple, int]:
    """The script's integrator and its analysis steps per step of pframe's."""
    c = plan.integrator
    if c.events and plan.contact_names:
        differences.append(EVENTS_DIFFERENCE)
    if plan.node_support and tuple(c.opensees) != ("newmark", 0.5, 0.25):
        differences.append(SUPPORTS_DIFFERENCE.format(name=plan.integrator_name))
    if c.opensees[0] == "wilson_theta":
        differences.append(WILSON_DIFFERENCE)
    if c.opensees[0] == "central_difference":
        if _velocity_dependent(plan, member, contacts, springs):
            differences.append(CENTRAL_DIFFERENCE)
        return c.opensees, int(plan.cd_parts[member]) if plan.cd_parts is not None else 1
    return c.opensees, 2 if c.opensees[0] == "trbdf2" else 1


def _peer_modal(plan: Plan, member: int, problems: list) -> list | None:
    """The ratio of each mode of the whole scene (its storeys on their initial stiffness) that
    OpenSees' global ``modalDamping`` needs to reproduce the plan's modal damping, or None
    for Rayleigh damping; what it cannot reproduce goes to ``problems``."""
    if plan.modal_start is None or len(plan.modal_start) < 2:
        return None
    ns = len(plan.story_names)
    damping_matrix = plan.modal_damping(member)
    if plan.link_names or np.any(plan.mass_damping[member]) or np.any(plan.story_beta[member]):
        problems.append("OpenSees' modalDamping damps the modes of the whole model: every "
                        "building needs modal damping, and no links may join them")
        return None
    if plan.foundations:
        problems.append("OpenSees' modalDamping damps the modes of the whole model, the soil's "
                        "included: give a building on soil Rayleigh damping")
        return None
    if plan.node_support:
        problems.append("OpenSees' modalDamping damps the total velocities of a model on "
                        "several supports, pframe's modal damping the motion relative to them "
                        "(it would damp the supports' rigid motion): give Rayleigh damping")
        return None
    G = incidence.incidence(plan.story_dofs[:ns], _first_sides(plan.story_sides, ns), member,
                            plan.n_dof).toarray()
    mass = plan.mass[member]
    scale = 1.0 / np.sqrt(mass)
    K = G.T @ (plan.story_k0[member, :ns, None] * G)
    values, vectors = np.linalg.eigh(K * np.outer(scale, scale))
    omega = np.sqrt(np.clip(values, 0.0, None))
    phi = vectors * scale[:, None]
    ratios = np.array([p @ damping_matrix @ p / (2.0 * w) if w > 0.0 else 0.0
                       for p, w in zip(phi.T, omega)])
    mphi = mass[:, None] * phi
    again = mphi @ np.diag(2.0 * ratios * omega) @ mphi.T
    if not np.allclose(again, damping_matrix, rtol=1e-9,
                       atol=1e-9 * np.max(np.abs(damping_matrix))):
        problems.append("OpenSees' modalDamping takes the modes of the initial stiffness, with "
                        "one ratio per mode of the whole model: give every building the same "
                        "ratio for all its modes, fitted on the initial stiffness (fit: "
                        "initial, or no isolators)")
        return None
    return [float(r) for r in ratios]


def _first_sides(sides: Sides, count: int) -> Sides:
    """The sides of the first ``count`` elements (the storeys, without the links)."""
    end = int(sides.start[2 * count])
    return dataclasses.replace(sides, start=sides.start[:2 * count + 1], dof=sides.dof[:end],
                               coef=sides.coef[:, :end])


def _rayleigh(plan: Plan, member: int, building_of_dof: np.ndarray, node_of_dof: np.ndarray,
              story_building: np.ndarray, problems: list) -> list:
    """One ``(alpha_m, beta_k, nodes, storeys, stiffness)`` per building and damping stiffness:
    alpha_m on the nodes of the building's DOFs that take it (not a foundation's), beta_k on
    its storeys with the stiffness term (not its isolators, by default). On supports alpha_m
    is 0: the mass term acts on the motion relative to the supports, and the script writes it
    as dashpots (:class:`pframe.peers.scene.Supports`)."""
    out = []
    mass_damping = 0.0 if plan.node_support else plan.mass_damping[member]
    for b, building in enumerate(plan.buildings):
        own = np.flatnonzero((building_of_dof == b) & (mass_damping != 0.0))
        ratios = plan.mass_damping[member, own] / plan.mass[member, own]
        # a0 m / m is a0 to the last bit or two: one a0 per building is the same damping
        if len(own) and not np.allclose(ratios, ratios[0], rtol=1e-12, atol=0.0):
            problems.append(f"building {building!r}: OpenSees' Rayleigh regions take one "
                            "mass-proportional coefficient per building")
        alpha, nodes = (float(ratios[0]) if len(own) else 0.0), np.unique(node_of_dof[own])
        groups: dict[tuple, list] = {}
        for e in np.flatnonzero(story_building == b):
            if plan.story_beta[member, e] != 0.0:
                mode = DampingStiffness(int(plan.story_damping_stiffness[e]))
                groups.setdefault((float(plan.story_beta[member, e]), STIFFNESS[mode]),
                                  []).append(e)
        if not groups:
            groups[(0.0, "initial")] = []
        for i, ((beta, stiffness), stories) in enumerate(sorted(groups.items())):
            # the nodes' alpha_m once, with the first group
            out.append((alpha if i == 0 else 0.0, beta, nodes if i == 0 else nodes[:0],
                        np.array(stories, dtype=np.int64), stiffness))
    return out


def _floors(plan: Plan, member: int, centres, springs: list, problems: list):
    """The floors of a scene in plan; an element on their rotations alone (P-delta's torsion)
    must be linear, its stiffness then r^2 times the law's about the rotation."""
    try:
        floors = floors_in_plan(plan, member, centres)
    except ValueError as why:
        problems.append(f"its elements in plan: {why}")
        return None
    levers = np.concatenate([floors.story_levers, floors.link_levers])
    for e in np.flatnonzero(levers):
        if springs[e][0] != "elastic":
            problems.append(f"{_spring_names(plan)[e]} acts on the floors' rotations alone, "
                            "which the script models for elastic springs only")
    return floors


def _supports(plan: Plan, member: int, problems: list):
    """A scene on several supports: the support of each spring's and contact's ground end
    (-1: none) and its :class:`pframe.peers.scene.Supports`; (None, None, None) on one
    ground."""
    if not plan.node_support:
        return None, None, None
    try:
        springs = supports.ground_ends(plan, member, "spring")
        contacts = supports.ground_ends(plan, member, "contact")
    except ValueError as why:
        problems.append(f"its elements across supports: {why}")
        return None, None, None
    count = len(plan.channels)
    motion = plan.ground_motion[member]  # displacements, then velocities
    return springs, contacts, Supports(
        names=list(plan.supports), channels=supports.channels(plan),
        displacement=motion[:count].copy(), velocity=motion[count:].copy(),
        dof_channel=plan.dof_channel.copy(), dof_support=supports.dof_supports(plan),
        damping=plan.mass_damping[member].copy())


def peer_scene(plan: Plan, member: int = 0, centres=None) -> PeerScene:
    """The scene of one batch member for peer programs: each element's law as its OpenSees
    twin, the scene's damping and integrator, starting at rest.

    A scene in plan draws its floors at ``centres`` ((nodes, 2), the site coordinates of
    their centres of mass in m: ``Expanded.node_centre``); without them every floor's centre
    is at the origin, the same model drawn elsewhere (an element acts through the arms of its
    ends about its floor's centre, which its sides hold).

    Raises
    ------
    InputError
        With every reason the OpenSees peer cannot model the scene, at once."""
    problems = _scene_refusals(plan, member)
    differences: list[str] = []
    springs = _twins(plan, member, "material", _spring_names(plan), problems, differences)
    contacts = _twins(plan, member, "contact", list(plan.contact_names), problems,
                      differences)
    _bouc_wen_damping(plan, member, problems)
    modal = _peer_modal(plan, member, problems)
    ns, nl = len(plan.story_names), len(plan.link_names)
    soil = None
    if plan.foundations and plan.planar:
        try:
            soil = foundations(plan, member, springs[ns + nl::2], springs[ns + nl + 1::2])
        except ValueError as why:
            problems.append(str(why))
    integrator, substeps = ((None, 1) if isinstance(plan.integrator.opensees, str) else
                            _integrator(plan, member, contacts, springs, differences))
    floors = None if plan.planar else _floors(plan, member, centres, springs, problems)
    spring_grounds, contact_grounds, on_supports = _supports(plan, member, problems)
    if problems:
        raise InputError("the OpenSees peer cannot model this scene: " + "; ".join(problems))
    building_of_node = np.array([plan.buildings.index(n.split("/")[0])
                                 for n in plan.node_names])
    if floors is None:  # a planar scene: its nodes are its DOFs
        names = [""] * plan.n_dof
        for name, dof in zip(plan.node_names, plan.node_dof):
            names[dof] = name
        building_of_dof = np.full(plan.n_dof, -1)
        building_of_dof[plan.node_dof] = building_of_node
        for b, dofs in zip(plan.foundations, plan.foundation_dofs
                           if plan.foundations else []):
            building_of_dof[dofs] = plan.buildings.index(b)
            names[dofs[0]], names[dofs[1]] = f"{b}/foundation:sway", f"{b}/foundation:rocking"
        node_of_dof = np.arange(plan.n_dof)

        def nodes(dofs):
            return dofs.copy()
    else:  # its nodes are its floors
        names = [f"{plan.node_names[f]}:{COMPONENTS[k]}" for f, k in floors.dofs]
        node_of_dof = plan.dof_node
        building_of_dof = building_of_node[node_of_dof]

        def nodes(dofs):
            return np.where(dofs >= 0, plan.dof_node[np.clip(dofs, 0, None)], -1)
    story_nodes, link_nodes = nodes(plan.story_dofs[:ns]), nodes(plan.story_dofs[ns:ns + nl])
    contact_nodes = nodes(plan.contact_dofs)
    if on_supports is not None:  # each ground end on its support's ground: -1 - s
        story_nodes = supports.with_grounds(story_nodes, spring_grounds[:ns])
        link_nodes = supports.with_grounds(link_nodes, spring_grounds[ns:ns + nl])
        contact_nodes = supports.with_grounds(contact_nodes, contact_grounds)
        if soil is not None:  # a foundation's springs stand on its sway spring's ground
            soil = dataclasses.replace(soil, grounds=np.maximum(spring_grounds[ns + nl::2], 0))
    rayleigh = _rayleigh(plan, member, building_of_dof, node_of_dof,
                         building_of_dof[plan.story_dofs[:ns, 1]], problems)
    if problems:
        raise InputError("the OpenSees peer cannot model this scene: " + "; ".join(problems))
    return PeerScene(
        node_names=names,
        masses=plan.mass[member].copy(),
        story_nodes=story_nodes,
        story_names=list(plan.story_names),
        story_materials=springs[:ns],
        contact_nodes=contact_nodes,
        contact_names=list(plan.contact_names),
        contact_gaps=plan.contact_gap[member].copy(),
        contact_materials=contacts,
        rayleigh=rayleigh,
        ground_acceleration=(plan.ground_acceleration[member].copy()
                             if floors is None and on_supports is None
                             else plan.ground_channels[member].copy()),
        dt=float(plan.dt[member]),
        steps=plan.steps,
        tolerance=plan.absolute_tolerance or 1e-12,
        max_iterations=plan.max_iterations,
        link_nodes=link_nodes,
        link_materials=springs[ns:ns + nl],
        modal=modal,
        integrator=integrator,
        channels=tuple(plan.channels),
        floors=floors,
        story_geometric=(np.zeros(ns) if plan.story_kg is None
                         else plan.story_kg[member, :ns].copy()),
        substeps=substeps,
        foundations=soil,
        differences=tuple(differences),
        supports=on_supports,
    )
