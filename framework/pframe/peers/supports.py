"""A scene on several supports as the OpenSees script draws it: in total coordinates, each
support's motion imposed on its ground nodes by OpenSees' ``MultipleSupport`` pattern
(docs/supports.md).

pframe writes every node relative to its support, U = u + d_s (the node's total displacement
U), and gives an element the ground displacements' part of its deformation as terms,
d_e = G u + sum_t c_t d_{channel_t} (``Plan.story_ground_*``, ``contact_ground_*``). In total
coordinates an element deforms by the difference of its two ends' total motions: a floor's
end moves with its DOFs' totals, a ground end with its support. So the terms must be the
floor sides' supports' displacements, each with its side's sign and coefficient, and the
ground end's support's along the element's direction; :func:`ground_ends` finds that support
from the terms and checks that they are exactly this (Clough & Penzien, *Dynamics of
Structures*, multiple-support excitation).

The supports' displacements and velocities are pframe's own (the trapezoid rule twice from
rest over the sampled accelerations, ``Plan.ground_motion``), given to OpenSees as series of
their own: then the displacement OpenSees imposes is pframe's sample for sample, and the
triple (d, v, a) keeps Newmark's average-acceleration relations, so that the relative
integration plus d_s is the total one (docs/supports.md).
"""

from __future__ import annotations

import numpy as np

from pframe.assemble.plan import Plan

#: the script's OpenSees DOF of each axis a channel moves along
AXIS_DOF = {"x": 1, "y": 2}


def channels(plan: Plan) -> list[tuple[int, str]]:
    """(support index, axis) of each channel '<support>:<axis>' of a scene on supports."""
    out = []
    for name in plan.channels:
        support, axis = name.rsplit(":", 1)
        out.append((plan.supports.index(support), axis))
    return out


def dof_supports(plan: Plan) -> np.ndarray:
    """(n,) the support each DOF's motion is relative to: its channel's, else (a rotation)
    its node's, a foundation's rocking its sway's."""
    support_of = [s for s, _ in channels(plan)]
    out = np.zeros(plan.n_dof, dtype=np.int64)
    for d in range(plan.n_dof):
        c, node = int(plan.dof_channel[d]), int(plan.dof_node[d])
        out[d] = support_of[c] if c >= 0 else plan.node_support[node] if node >= 0 else 0
    for sway, rocking in (plan.foundation_dofs if plan.foundations else []):
        out[rocking] = out[sway]
    return out


def _elements(plan: Plan, kind: str):
    """(names, sides as (DOF, coefficient) lists, each side's sign in the deformation, the
    ground terms' start, channel, coefficient) of the springs (storeys, links, the soil's) or
    the contacts."""
    if kind == "spring":
        names = [*plan.story_names, *plan.link_names,
                 *(f"{b}/soil_{w}" for b in plan.foundations for w in ("sway", "rocking"))]
        return (names, plan.story_dofs, plan.story_sides, (-1.0, 1.0), plan.story_ground_start,
                plan.story_ground_channel, plan.story_ground_coef)
    return (list(plan.contact_names), plan.contact_dofs, plan.contact_sides, (1.0, -1.0),
            plan.contact_ground_start, plan.contact_ground_channel, plan.contact_ground_coef)


def ground_ends(plan: Plan, member: int, kind: str) -> np.ndarray:
    """(E,) the support of each spring's (``kind`` "spring": storeys, links, the soil's) or
    contact's (``kind`` "contact") ground end; -1 for an element with none.

    Raises ValueError naming an element whose ground terms are not the total motion of its
    ends (see the module)."""
    names, dofs, sides, signs, start, channel, coef = _elements(plan, kind)
    general = (sides.general() if sides is not None and len(sides.start) > 1
               else np.zeros(len(names), dtype=bool))
    axis_of = [axis for _, axis in channels(plan)]
    support = dof_supports(plan)
    out = np.full(len(names), -1, dtype=np.int64)
    for e, name in enumerate(names):
        # what the terms hold beyond the floor ends' supports: the ground end's support
        lo, hi = (int(start[e]), int(start[e + 1])) if start is not None else (0, 0)
        left = {int(c): float(a) for c, a in zip(channel[lo:hi], coef[member, lo:hi])}
        direction: dict[str, float] = {}
        ground, floors = [], []
        for s in range(2):
            terms = (sides.side(e, s, member) if general[e] else
                     [(int(dofs[e, s]), 1.0)] if dofs[e, s] >= 0 else [])
            if not terms:
                ground.append(s)
            for d, a in terms:
                floors.append(int(support[d]))
                c = int(plan.dof_channel[d])
                if c >= 0:  # the floor end's support moves it along the channel's axis
                    left[c] = left.get(c, 0.0) - signs[s] * a
                    direction[axis_of[c]] = a  # both ends act along one direction
        scale = max([1.0, *(abs(v) for v in left.values())])
        left = {c: v for c, v in left.items() if abs(v) > 1e-12 * scale}
        if len(ground) > 1 or (not ground and left):
            raise ValueError(f"{name}: its ground terms are not its ends' supports' motions")
        if ground and not left:  # on its floor's support, or along no axis the motion loads
            out[e] = floors[0] if floors else 0
        elif ground:
            out[e] = _support_moving(plan, left, signs[ground[0]], direction, scale, name)
    return out


def _support_moving(plan: Plan, left: dict, sign: float, direction: dict, scale: float,
                    name: str) -> int:
    """The support whose displacement along ``direction`` (with the ground side's ``sign``)
    is the ground terms ``left``."""
    of = {(s, axis): c for c, (s, axis) in enumerate(channels(plan))}
    for g in range(len(plan.supports)):
        expected = {of[(g, axis)]: sign * n for axis, n in direction.items()
                    if (g, axis) in of and n != 0.0}
        if expected.keys() == left.keys() and all(
                abs(expected[c] - left[c]) <= 1e-12 * scale for c in left):
            return g
    raise ValueError(f"{name}: its ground terms are not the motion of one support's ground")


def with_grounds(nodes: np.ndarray, grounds: np.ndarray) -> np.ndarray:
    """An element's ends with its ground end (-1) as -1 - s, s the ground end's support."""
    nodes = np.asarray(nodes, dtype=np.int64).reshape(-1, 2)
    return np.where(nodes < 0, -1 - np.maximum(grounds, 0)[:, None], nodes)
