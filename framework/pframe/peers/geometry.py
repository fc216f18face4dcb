"""Where the elements of a scene act, as the OpenSees script draws them: the floors of a scene
in plan (:func:`floors_in_plan`) and the foundations of a planar scene on soil
(:func:`foundations`)."""

from __future__ import annotations

import numpy as np

from pframe.assemble.incidence import Sides
from pframe.assemble.plan import Plan
from pframe.peers.scene import FloorsInPlan, Foundations


def floors_in_plan(plan: Plan, member: int, centres):
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
    if np.any(ends["contact"][2]):
        raise ValueError("a contact acts on the floors' rotations alone")
    return FloorsInPlan(
        names=list(plan.node_names), centres=centres, masses=masses, moves=moves,
        dofs=np.stack([plan.dof_node, plan.dof_component], axis=1),
        story_points=ends["story"][0], story_directions=ends["story"][1],
        contact_points=ends["contact"][0], contact_directions=ends["contact"][1],
        link_points=ends["link"][0], link_directions=ends["link"][1],
        story_levers=ends["story"][2], link_levers=ends["link"][2])


def _element_ends(plan: Plan, dofs, sides: Sides, elements, member: int, centres):
    """(e, 2, 2) a point of each end of each element and (e, 2) its direction, from its sides.

    A floor's side along the unit n at P is a = (n_x, n_y, (P - c) x n) (pframe.model.plan;
    a zero coefficient left out), so n = (a_x, a_y), and P = c + a_theta (n_y, -n_x) is the
    point of the line of action nearest the centre c ((P - c) x n = a_theta |n|^2). Both ends
    are then slid along n to one station, so that ends on one line coincide (a storey's
    floors, a contact along its normal); an end on the ground stands at the other end.

    An element on the floors' rotations alone (P-delta's torsion: a lever r on theta, no
    translation) gets the direction (0, 0), its ends at the floors' centres and its lever r
    in the third array ((e,), 0 for every other element): the script turns it into a
    rotational spring of r^2 times its stiffness."""
    general = (sides.general() if sides is not None and len(sides.start) > 1
               else np.zeros(len(dofs), dtype=bool))
    points, directions = np.zeros((len(elements), 2, 2)), np.zeros((len(elements), 2))
    levers = np.zeros(len(elements))
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
        if not np.any(coefficient[on, :2]):  # the rotations alone, by one lever
            if any(coefficient[s, 2] != coefficient[on[0], 2] for s in on):
                raise ValueError(f"element {e}: its sides turn by two levers")
            levers[k] = coefficient[on[0], 2]
            for s in range(2):
                points[k, s] = centres[floor[s] if floor[s] >= 0 else floor[on[0]]]
            continue
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
    return points, directions, levers


def foundations(plan: Plan, member: int, sway_materials: list,
                rocking_materials: list) -> Foundations:
    """The :class:`pframe.peers.scene.Foundations` of a planar scene on soil: which storey's
    lower side holds which foundation's rocking, with what lever, and each floor's height
    above its foundation (its storeys' heights summed from the ground or the foundation up;
    0 where no height is given).

    Raises ValueError naming a storey whose sides are not a storey's on soil (u_upper less
    u_lower and h theta of one foundation)."""
    ns = len(plan.story_names)
    sides = plan.story_sides
    general = (sides.general()[:ns] if sides is not None and len(sides.start) > 1
               else np.zeros(ns, dtype=bool))
    rocking_of = {int(r): f for f, r in enumerate(plan.foundation_dofs[:, 1])}
    story_foundation, lever = np.full(ns, -1, dtype=np.int64), np.zeros(ns)
    lower_dof = plan.story_dofs[:ns, 0].copy()
    for e in np.flatnonzero(general):
        lower = dict(sides.side(e, 0, member))
        rocks = [d for d in lower if d in rocking_of]
        rest = [(d, a) for d, a in lower.items() if d not in rocking_of]
        if (len(rocks) != 1 or len(rest) != 1 or rest[0][1] != 1.0
                or sides.side(e, 1, member) != [(int(plan.story_dofs[e, 1]), 1.0)]):
            raise ValueError(f"storey {plan.story_names[e]!r} is neither plain nor a storey "
                             "on soil")
        story_foundation[e] = rocking_of[rocks[0]]
        lever[e] = lower[rocks[0]]
        lower_dof[e] = rest[0][0]
    height = np.where(np.isfinite(plan.story_height[member, :ns]),
                      plan.story_height[member, :ns], 0.0)
    heights = np.zeros(plan.n_dof)
    for _ in range(ns):  # floors above floors: at most ns passes, each fixing one more level
        before = heights.copy()
        for e in range(ns):
            base = heights[lower_dof[e]] if lower_dof[e] >= 0 else 0.0
            heights[plan.story_dofs[e, 1]] = base + height[e]
        if np.array_equal(before, heights):
            break
    return Foundations(sway=plan.foundation_dofs[:, 0].copy(),
                       rocking=plan.foundation_dofs[:, 1].copy(),
                       sway_materials=sway_materials, rocking_materials=rocking_materials,
                       story_foundation=story_foundation, story_lever=lever,
                       heights=heights)
