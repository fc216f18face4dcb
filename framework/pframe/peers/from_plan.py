"""The scene of one batch member of a plan as peer programs read it (:class:`PeerScene`), and
every reason the OpenSees peer cannot model it."""

from __future__ import annotations

import dataclasses

import numpy as np

from pframe.assemble import incidence
from pframe.assemble.incidence import Sides
from pframe.assemble.plan import Plan
from pframe.errors import InputError
from pframe.kernel.state import DampingStiffness
from pframe.model.plan import COMPONENTS
from pframe.peers.scene import FloorsInPlan, PeerScene


def _peer_refusals(plan: Plan, member: int) -> list[str]:
    """Every reason the OpenSees peer cannot model a plan's member (none: it can)."""
    problems = []
    if np.any(plan.initial_displacement[member]) or np.any(plan.initial_velocity[member]):
        problems.append("it starts from rest: remove initial_conditions")
    c = plan.integrator
    if plan.contact_share is not None and np.any(plan.contact_share[member] != 1.0):
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
    return problems


def _peer_materials(plan: Plan, member: int) -> tuple[list, list]:
    """The storeys' and the links' materials of a :class:`PeerScene`, in element order."""
    ns = len(plan.story_names)
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
    links = sorted((i, ("elastic", p[0]) if group.law.name == "elastic"
                    else ("bilinear", p[0], p[1], p[2]) if group.law.name == "bilinear"
                    else ("viscous", p[0], p[1]) if group.law.name == "viscous"
                    else ("kelvin_voigt", p[0], p[1], p[2]))
                   for group in plan.story_groups
                   for i, p in zip(group.index, group.params[member]) if i >= ns)
    return [m for _, m in sorted(materials, key=lambda t: t[0])], [m for _, m in links]


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


def peer_scene(plan: Plan, member: int = 0, centres=None) -> PeerScene:
    """The scene of one batch member for peer programs: linear contacts, start at rest,
    Rayleigh on the initial stiffness (what the OpenSees peer models).

    A scene in plan draws its floors at ``centres`` ((nodes, 2), the site coordinates of
    their centres of mass in m: ``Expanded.node_centre``); without them every floor's centre
    is at the origin, the same model drawn elsewhere (an element acts through the arms of its
    ends about its floor's centre, which its sides hold)."""
    problems = _peer_refusals(plan, member)  # every reason at once
    modal = _peer_modal(plan, member, problems)
    if problems:
        raise InputError("the OpenSees peer cannot model this scene: " + "; ".join(problems))
    c = plan.integrator
    ns = len(plan.story_names)
    materials, link_materials = _peer_materials(plan, member)
    stiffness = np.zeros(len(plan.contact_names))
    for group in plan.contact_groups:
        stiffness[group.index] = group.params[member, :, 0]
    floors = None if plan.planar else _floors_in_plan(plan, member, centres)
    if floors is None:  # a planar scene: its nodes are its DOFs
        names = [""] * plan.n_dof
        for name, dof in zip(plan.node_names, plan.node_dof):
            names[dof] = name
        node_names, node_of_dof = names, np.arange(plan.n_dof)

        def nodes(dofs):
            return dofs.copy()
    else:  # its nodes are its floors
        node_names, node_of_dof = list(plan.node_names), plan.dof_node
        names = [f"{plan.node_names[f]}:{COMPONENTS[k]}" for f, k in floors.dofs]

        def nodes(dofs):
            return np.where(dofs >= 0, plan.dof_node[np.clip(dofs, 0, None)], -1)
    rayleigh = []
    building_of_node = np.array([plan.buildings.index(n.split("/")[0]) for n in node_names])
    story_nodes = nodes(plan.story_dofs[:ns])
    story_building = building_of_node[story_nodes[:, 1]]
    dof_building = building_of_node[node_of_dof]
    for b in range(len(plan.buildings)):
        own = np.flatnonzero(dof_building == b)  # every DOF of a building has one alpha_m
        stories = np.flatnonzero(story_building == b)
        # the storeys with the stiffness term (not the isolators, by default): one a1 for all
        damped = stories[plan.story_beta[member, stories] != 0.0]
        alpha = float(plan.mass_damping[member, own[0]] / plan.mass[member, own[0]])
        beta = float(plan.story_beta[member, damped[0]]) if len(damped) else 0.0
        rayleigh.append((alpha, beta, np.flatnonzero(building_of_node == b), damped))
    return PeerScene(
        node_names=names,
        masses=plan.mass[member].copy(),
        story_nodes=story_nodes,
        story_names=list(plan.story_names),
        story_materials=materials,
        contact_nodes=nodes(plan.contact_dofs),
        contact_names=list(plan.contact_names),
        contact_gaps=plan.contact_gap[member].copy(),
        contact_stiffness=stiffness,
        rayleigh=rayleigh,
        ground_acceleration=(plan.ground_acceleration[member].copy() if floors is None
                             else plan.ground_channels[member].copy()),
        dt=float(plan.dt[member]),
        steps=plan.steps,
        tolerance=plan.absolute_tolerance or 1e-12,
        max_iterations=plan.max_iterations,
        link_nodes=nodes(plan.story_dofs[ns:]),
        link_materials=link_materials,
        modal=modal,
        integrator=c.opensees,
        channels=tuple(plan.channels),
        floors=floors,
    )


def _floors_in_plan(plan: Plan, member: int, centres):
    """The :class:`pframe.peers.scene.FloorsInPlan` of a scene in plan (see peer_scene)."""
    count = len(plan.node_names)
    centres = (np.zeros((count, 2)) if centres is None
               else np.array(centres, dtype=float).reshape(count, 2))
    masses, moves = np.zeros((count, 3)), np.zeros((count, 3), dtype=bool)
    masses[plan.dof_node, plan.dof_component] = plan.mass[member]
    moves[plan.dof_node, plan.dof_component] = True
    ns, nl = len(plan.story_names), len(plan.link_names)
    ends = {kind: _element_ends(plan, dofs, sides, elements, member, centres)
            for kind, dofs, sides, elements in (
                ("story", plan.story_dofs, plan.story_sides, range(ns)),
                ("link", plan.story_dofs, plan.story_sides, range(ns, ns + nl)),
                ("contact", plan.contact_dofs, plan.contact_sides,
                 range(len(plan.contact_names))))}
    return FloorsInPlan(
        names=list(plan.node_names), centres=centres, masses=masses, moves=moves,
        dofs=np.stack([plan.dof_node, plan.dof_component], axis=1),
        story_points=ends["story"][0], story_directions=ends["story"][1],
        contact_points=ends["contact"][0], contact_directions=ends["contact"][1],
        link_points=ends["link"][0], link_directions=ends["link"][1])


def _element_ends(plan: Plan, dofs, sides: Sides, elements, member: int, centres):
    """(e, 2, 2) a point of each end of each element and (e, 2) its direction, from its sides.

    A floor's side along the unit n at P is a = (n_x, n_y, (P - c) x n) (pframe.model.plan;
    a zero coefficient left out), so n = (a_x, a_y), and P = c + a_theta (n_y, -n_x) is the
    point of the line of action nearest the centre c ((P - c) x n = a_theta |n|^2). Both ends
    are then slid along n to one station, so that ends on one line coincide (a storey's
    floors, a contact along its normal); an end on the ground stands at the other end."""
    general = (sides.general() if sides is not None and len(sides.start) > 1
               else np.zeros(len(dofs), dtype=bool))
    points, directions = np.zeros((len(elements), 2, 2)), np.zeros((len(elements), 2))
    for k, e in enumerate(elements):
        coefficient = np.zeros((2, 3))
        floor = [-1, -1]
        for s in range(2):
            terms = (sides.side(e, s, member) if general[e] else
                     [(int(dofs[e, s]), 1.0)] if dofs[e, s] >= 0 else [])
            for d, a in terms:
                floor[s] = int(plan.dof_node[d])
                coefficient[s, plan.dof_component[d]] += a
        on = [s for s in range(2) if floor[s] >= 0]
        n = coefficient[on[0], :2]
        if any(not np.array_equal(coefficient[s, :2], n) for s in on):
            raise ValueError(f"element {e}: its sides act along two directions")
        across = np.array([n[1], -n[0]])
        for s in on:
            points[k, s] = centres[floor[s]] + coefficient[s, 2] * across
        station = np.mean([points[k, s] @ n for s in on])
        for s in on:
            points[k, s] += (station - points[k, s] @ n) * n
        for s in range(2):
            if floor[s] < 0:
                points[k, s] = points[k, on[0]]
        directions[k] = n
    return points, directions
