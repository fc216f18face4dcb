"""The runs of a risk study: one batch of the compiled kernel per chunk of variants (record x
intensity level), twice: the scene without its contacts (on the study's step: the critical
gap, the buildings' peak displacements and demands without pounding) and, optionally, the
scene with its contacts at their gaps (on the scene's step: impacts and demands with
pounding). The kernel keeps the peaks (envelopes); a sink keeps the running maximum of
u_left - u_right over the streamed displacements, so memory stays bounded whatever the steps.

Demands per variant: peak |storey drift| over each building's storeys (m), peak absolute floor
acceleration |a_rel + a_g| over each building's floors (m/s^2), the number of impacts; for a
planar scene also each storey's peak |drift ratio|, each floor's peak absolute acceleration
and the peak ground acceleration (the demand table pelicun reads, pframe.risk.pelicun).
"""

from __future__ import annotations

import dataclasses

import numpy as np

from pframe.gap.runs import (
    GapSink,
    Pairs,
    axes_of,
    contact_pairs,
    for_runs,
    on_channels,
    under,
)
from pframe.model.scene import Envelope, History


def _owners(plan) -> tuple[np.ndarray, np.ndarray]:
    """Building index of each floor's translation along the site's x or y (-1: a rotation,
    a foundation's DOF) and of each storey (its upper floor's)."""
    node_building = np.array([plan.buildings.index(name.split("/")[0])
                              for name in plan.node_names], dtype=np.int64)
    of_dof = np.full(plan.n_dof, -1, dtype=np.int64)
    moves = (plan.dof_node >= 0) & (plan.dof_component < 2)
    of_dof[moves] = node_building[plan.dof_node[moves]]
    upper = plan.dof_node[plan.story_dofs[:len(plan.story_names), 1]]  # storeys, not links
    return of_dof, node_building[upper]


def _per_building(values: np.ndarray, owner: np.ndarray, count: int) -> np.ndarray:
    out = np.full((values.shape[0], count), np.nan)
    for b in range(count):
        if np.any(owner == b):
            out[:, b] = np.max(values[:, owner == b], axis=1)
    return out


def run_batch(loaded, pairs: Pairs, accelerations: np.ndarray, steps: int, dt: float,
              contacts: bool, threads: int | None = None, axes=None) -> dict[str, np.ndarray]:
    """One batch: a member per ground motion of ``accelerations`` (m/s^2; (B, steps + 1)
    along x, or (B, C, steps + 1) along the site's x and y, or at each support along
    ``axes``: pframe.gap.runs.axes_of)."""
    from pframe.assemble import assemble_batch
    from pframe.kernel import simulate

    # ``loaded``: one scene, or one per member (uncertain parameters, docs/risk.md)
    members = list(loaded) if isinstance(loaded, (list, tuple)) else [loaded]
    # the kernel keeps the peaks (the absolute acceleration's with the ground at every
    # sub-step); only the displacements stream out, for the critical gap's running maximum
    recorders = (Envelope(kind="envelope", quantities=["displacement", "story_drift",
                                                       "story_drift_ratio",
                                                       "absolute_acceleration"]),
                 History(kind="history", quantities=["displacement"]))
    accelerations = on_channels(accelerations)
    channels = axes_of(accelerations, axes)
    bases = [dataclasses.replace(for_runs(m, channels, contacts), steps=int(steps),
                                 recorders=recorders, dt=float(dt)) for m in members]
    plan = assemble_batch([under(bases[k if len(bases) > 1 else 0], a[None])[0]
                           for k, a in enumerate(accelerations)])
    gaps = np.array([min(c.gap for c in m.expanded.contacts) for m in members])
    # members of their own geometry (uncertain values): each its own contacts' sides
    sink = GapSink(plan, [contact_pairs(m) for m in members] if len(members) > 1 else pairs)
    result = simulate(plan, threads=threads, sink=sink)
    of_dof, of_story = _owners(plan)
    nb = len(plan.buildings)
    drift = np.abs(result.envelope["story_drift"])
    left, right = sink.peaks(result.envelope["displacement"])
    out = {
        "g_req": sink.gap,
        "peak_left": left, "peak_right": right,
        "drift": _per_building(drift, of_story, nb),
        # NaN for a building without storey heights (a drift-ratio limit needs them)
        "drift_ratio": _per_building(np.abs(result.envelope["story_drift_ratio"]), of_story, nb),
        "acceleration": _per_building(result.envelope["absolute_acceleration"], of_dof, nb),
        # each storey and floor of a planar scene (pframe.risk.pelicun's demand table): a
        # scene in plan has lines of resistance and three DOFs per floor instead
        **({"drift_ratio_each": np.abs(result.envelope["story_drift_ratio"]),
            "acceleration_each": result.envelope["absolute_acceleration"][:, plan.node_dof],
            "ground_acceleration": np.max(np.abs(accelerations[:, 0]), axis=-1)}
           if plan.planar else {}),
        "impacts": (result.impacts.astype(np.int32) if contacts and result.impacts is not None
                    else np.zeros((plan.batch, len(pairs.names)), np.int32)),
        "complete": np.array([result.completed(b) for b in range(plan.batch)], dtype=np.int8),
        "gap": np.broadcast_to(gaps, (plan.batch,)).copy(),  # the member's smallest gap
        "solve_seconds": np.float64(result.solve_seconds),
    }
    return out
