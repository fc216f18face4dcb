"""The ground motion's channels as the kernel takes them, with the supports' displacements
where elements across supports need them (docs/supports.md).

A channel is one support's motion along one axis. Every DOF that translates is loaded by its
node's support's channel along its axis (-1: a rotation, a foundation's rocking). An element
across supports adds the ground displacements' part of its deformation, the terms
(channel, coefficient) of :attr:`pframe.model.elements.Element.ground`; the kernel reads the
displacement of channel c as ground series C + c and its velocity as series 2 C + c, after the
C accelerations, each sampled at the steps and linear between them as the accelerations are.
"""

from __future__ import annotations

import numpy as np

from pframe.model.plan import COMPONENTS
from pframe.model.support_motion import GROUND_QUANTITIES, kinematics


def channel_index(ex, node: int, component: int) -> int:
    """The channel of a node's translation ``component`` (0 x, 1 y): its support's motion
    along that axis; -1 when the motion does not load that axis."""
    axis = COMPONENTS[component]
    if ex.node_support:
        name = f"{ex.supports[ex.node_support[node]]}:{axis}"
    else:
        name = axis
    return ex.channels.index(name) if name in ex.channels else -1


def _term_channel(ex, support: int, component: int) -> int:
    return ex.channels.index(f"{ex.supports[support]}:{COMPONENTS[component]}")


def _terms(elements_of_members, ex_of_members) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(start (E + 1,), channel (T,), coef (B, T)) of the ground terms of each element, the
    union of the members' terms (a member without one has it at 0)."""
    count = len(elements_of_members[0])
    start, channel, coefs = [0], [], [[] for _ in elements_of_members]
    for e in range(count):
        members = [{_term_channel(ex, s, c): a for s, c, a in elements[e].ground}
                   for elements, ex in zip(elements_of_members, ex_of_members)]
        keys = sorted(set().union(*members))
        channel += keys
        for b, mine in enumerate(members):
            coefs[b] += [mine.get(k, 0.0) for k in keys]
        start.append(len(channel))
    return (np.array(start, dtype=np.int64), np.array(channel, dtype=np.int64),
            np.array(coefs, dtype=float).reshape(len(elements_of_members), len(channel)))




def ground_fields(variants, spring_sets, recorded) -> dict:
    """The Plan's fields of the elements across supports (see the module): their ground
    terms for the springs (storeys, links, soil) and the contacts, and the channels'
    displacements and velocities (B, 2 C, steps + 1); empty on one ground whose displacement
    no recorder asks for (``recorded``: the quantities recorded)."""
    first = variants[0]
    if not (first.node_support or any(q in recorded for q in GROUND_QUANTITIES)):
        return {}
    story = _terms(spring_sets, variants)
    contact = _terms([ex.contacts for ex in variants], variants)
    motion = []
    for ex in variants:  # a record's files where given, else integrated from rest
        displacement, velocity, _ = kinematics(ex)
        motion.append(np.concatenate([np.array(displacement), np.array(velocity)]))
    return dict(story_ground_start=story[0], story_ground_channel=story[1],
                story_ground_coef=story[2], contact_ground_start=contact[0],
                contact_ground_channel=contact[1], contact_ground_coef=contact[2],
                ground_motion=np.array(motion))
