"""The runs of a risk study: one batch of the compiled kernel per chunk of variants (record x
intensity level), twice: the scene without its contacts (on the study's step: the critical
gap, the buildings' peak displacements and demands without pounding) and, optionally, the
scene with its contacts at their gaps (on the scene's step: impacts and demands with
pounding). A sink keeps running maxima only, so memory stays bounded whatever the steps.

Demands per variant: peak |storey drift| over each building's storeys (m), peak absolute floor
acceleration |a_rel + a_g| over each building's floors (m/s^2), the number of impacts.
"""

from __future__ import annotations

import dataclasses

import numpy as np

from pframe.gap.runs import GapSink, Pairs, without_contacts
from pframe.model.scene import Envelope, History


class DemandSink:
    """Running maxima: u_left - u_right per contact (the critical gap) and |a + a_g| per DOF."""

    def __init__(self, plan, pairs: Pairs, ground: np.ndarray):
        self.gaps = GapSink(plan, pairs)
        self.ground = ground  # (B, steps + 1) m/s^2
        self.absolute = np.zeros((plan.batch, plan.n_dof))

    def __call__(self, quantity, first_row, rows):
        if quantity == "displacement":
            self.gaps(quantity, first_row, rows)
        elif quantity == "acceleration" and rows.shape[1]:
            ag = self.ground[:, first_row:first_row + rows.shape[1], None]
            np.fmax(self.absolute, np.max(np.abs(rows + ag), axis=1), out=self.absolute)


def _owners(plan) -> tuple[np.ndarray, np.ndarray]:
    """Building index of each DOF and of each storey."""
    of_dof = np.empty(plan.n_dof, dtype=np.int64)
    for name, dof in zip(plan.node_names, plan.node_dof):
        of_dof[dof] = plan.buildings.index(name.split("/")[0])
    return of_dof, of_dof[plan.story_dofs[:, 1]]


def _per_building(values: np.ndarray, owner: np.ndarray, count: int) -> np.ndarray:
    out = np.full((values.shape[0], count), np.nan)
    for b in range(count):
        if np.any(owner == b):
            out[:, b] = np.max(values[:, owner == b], axis=1)
    return out


def run_batch(loaded, pairs: Pairs, accelerations: np.ndarray, steps: int, dt: float,
              contacts: bool, threads: int | None = None) -> dict[str, np.ndarray]:
    """One batch: a member per row of ``accelerations`` (B, steps + 1) in m/s^2."""
    from pframe.assemble import assemble_batch
    from pframe.kernel import simulate

    # ``loaded``: one scene, or one per member (uncertain parameters, docs/risk.md)
    members = list(loaded) if isinstance(loaded, (list, tuple)) else [loaded]
    recorders = (Envelope(kind="envelope", quantities=["displacement", "story_drift"]),
                 History(kind="history", quantities=["displacement", "acceleration"]))
    bases = [dataclasses.replace(
        m.expanded if contacts else without_contacts(m, keep_excitation=False),
        steps=int(steps), recorders=recorders, dt=float(dt)) for m in members]
    plan = assemble_batch([dataclasses.replace(bases[k if len(bases) > 1 else 0],
                                               ground_acceleration=np.asarray(a, float))
                           for k, a in enumerate(accelerations)])
    gaps = np.array([min(c.gap for c in m.expanded.contacts) for m in members])
    sink = DemandSink(plan, pairs, np.asarray(accelerations, float))
    result = simulate(plan, threads=threads, sink=sink)
    of_dof, of_story = _owners(plan)
    nb = len(plan.buildings)
    drift = np.abs(result.envelope["story_drift"])
    peak = result.envelope["displacement"]
    out = {
        "g_req": sink.gaps.gap,
        "peak_left": peak[:, sink.gaps.left], "peak_right": peak[:, sink.gaps.right],
        "drift": _per_building(drift, of_story, nb),
        "acceleration": _per_building(sink.absolute, of_dof, nb),
        "impacts": (result.impacts.astype(np.int32) if contacts and result.impacts is not None
                    else np.zeros((plan.batch, len(pairs.names)), np.int32)),
        "complete": np.array([result.completed(b) for b in range(plan.batch)], dtype=np.int8),
        "gap": np.broadcast_to(gaps, (plan.batch,)).copy(),  # the member's smallest gap
        "solve_seconds": np.float64(result.solve_seconds),
    }
    return out
