"""The runs of a risk study: one batch of the compiled kernel per chunk of variants (record x
intensity level), twice: the scene without its contacts (on the study's step: the critical
gap, the buildings' peak displacements and demands without pounding) and, optionally, the
scene with its contacts at their gaps (on the scene's step: impacts and demands with
pounding). The kernel keeps the peaks (envelopes) and, for contacts between floors (each side
one DOF), the running maximum of u_left - u_right; a sink keeps it over the streamed
displacements otherwise (pframe.gap.runs.GapSink.run), so memory stays bounded whatever the
steps.

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


def _peak(values: np.ndarray) -> np.ndarray:
    """max |values| along the last axis, without a copy of |values|."""
    return np.maximum(np.max(values, axis=-1), -np.min(values, axis=-1))


def _per_building(values: np.ndarray, owner: np.ndarray, count: int) -> np.ndarray:
    out = np.full((values.shape[0], count), np.nan)
    for b in range(count):
        if np.any(owner == b):
            out[:, b] = np.max(values[:, owner == b], axis=1)
    return out


@dataclasses.dataclass
class Batch:
    """A batch assembled, ready to run (:func:`prepare`): its plan, the sink of its
    displacements, its ground motions (B, C, steps + 1) and whether it has contacts."""

    plan: object
    sink: GapSink
    accelerations: np.ndarray
    contacts: bool
    gaps: np.ndarray  # (B,) each member's smallest gap


def prepare(loaded, pairs: Pairs, accelerations: np.ndarray, steps: int, dt: float,
            contacts: bool, axes=None) -> Batch:
    """The batch of :func:`run_batch`, assembled (a thread may prepare the next batch while
    the kernel runs one: pframe.risk.study.run_variants)."""
    from pframe.assemble import assemble_batch

    # ``loaded``: one scene, or one per member (uncertain parameters, docs/risk.md)
    members = list(loaded) if isinstance(loaded, (list, tuple)) else [loaded]
    # the kernel keeps the peaks (the absolute acceleration's with the ground at every
    # sub-step); the displacements are recorded for the critical gap's running maximum
    # alone, which the kernel keeps itself where it can (GapSink.run: no history then).
    # A storey without a height has no drift ratio (its peak is NaN): where no storey of any
    # member has one, the kernel is not asked for them (run_batch gives the NaN)
    ratios = any(np.isfinite(np.asarray(m.expanded.story_height, float)).any() for m in members)
    recorders = (Envelope(kind="envelope", quantities=[
        "displacement", "story_drift", *(["story_drift_ratio"] if ratios else []),
        "absolute_acceleration"]), History(kind="history", quantities=["displacement"]))
    accelerations = on_channels(accelerations)
    channels = axes_of(accelerations, axes)
    bases = [dataclasses.replace(for_runs(m, channels, contacts), steps=int(steps),
                                 recorders=recorders, dt=float(dt)) for m in members]
    plan = assemble_batch([under(bases[k if len(bases) > 1 else 0], a[None])[0]
                           for k, a in enumerate(accelerations)])
    gaps = np.array([min(c.gap for c in m.expanded.contacts) for m in members])
    # members of their own geometry (uncertain values): each its own contacts' sides
    sink = GapSink(plan, [contact_pairs(m) for m in members]
                   if isinstance(loaded, (list, tuple)) else pairs)
    return Batch(plan, sink, accelerations, bool(contacts),
                 np.broadcast_to(gaps, (plan.batch,)).copy())


def run_batch(loaded, pairs: Pairs, accelerations: np.ndarray, steps: int, dt: float,
              contacts: bool, threads: int | None = None, axes=None,
              reach: bool = False, batch: Batch | None = None) -> dict[str, np.ndarray]:
    """One batch: a member per ground motion of ``accelerations`` (m/s^2; (B, steps + 1)
    along x, or (B, C, steps + 1) along the site's x and y, or at each support along
    ``axes``: pframe.gap.runs.axes_of), or the ``batch`` :func:`prepare` assembled of them.
    With ``reach`` (runs without contacts), also ``reach``: each contact's bound on its
    closing at every point the run with contacts would evaluate (:func:`_reach`)."""
    if batch is None:
        batch = prepare(loaded, pairs, accelerations, steps, dt, contacts, axes)
    plan, sink, accelerations = batch.plan, batch.sink, batch.accelerations
    result = sink.run(plan, threads=threads)
    of_dof, of_story = _owners(plan)
    nb = len(plan.buildings)
    drift = np.abs(result.envelope["story_drift"])
    ratio = np.abs(result.envelope["story_drift_ratio"]) if "story_drift_ratio" in \
        result.envelope else np.full(drift.shape[:1] + (len(plan.story_names),), np.nan)
    left, right = sink.peaks(result.envelope["displacement"])
    out = {
        "g_req": sink.gap,
        "peak_left": left, "peak_right": right,
        "drift": _per_building(drift, of_story, nb),
        # NaN for a building without storey heights (a drift-ratio limit needs them)
        "drift_ratio": _per_building(ratio, of_story, nb),
        "acceleration": _per_building(result.envelope["absolute_acceleration"], of_dof, nb),
        # each storey and floor of a planar scene (pframe.risk.pelicun's demand table): a
        # scene in plan has lines of resistance and three DOFs per floor instead
        **({"drift_ratio_each": ratio,
            "acceleration_each": result.envelope["absolute_acceleration"][:, plan.node_dof],
            "ground_acceleration": _peak(accelerations[:, 0])}
           if plan.planar else {}),
        "impacts": (result.impacts.astype(np.int32) if batch.contacts and result.impacts is not None
                    else np.zeros((plan.batch, len(pairs.names)), np.int32)),
        "complete": np.array([result.completed(b) for b in range(plan.batch)], dtype=np.int8),
        "gap": batch.gaps,  # the member's smallest gap
        "solve_seconds": np.float64(result.solve_seconds),
    }
    if reach:
        out["reach"] = _reach(plan, sink, result, accelerations, pairs)
    return out


#: the bound of :func:`_reach` in h^2 times the accelerations (s^2 x m/s^2): the
#: constant-acceleration predictor strays beta h^2 |a_end - a_start| <= h^2 (|a_l| + |a_r|)
#: from a step's end, a point inside a step (a stage of a tableau) less than h^2 / 8 of them
#: from the chord; twice that for the Newton iterates in between
REACH_FACTOR = 2.0


def _reach(plan, sink: GapSink, result, accelerations: np.ndarray, pairs: Pairs) -> np.ndarray:
    """(B, c) a bound on each contact's closing at every point a run with its contacts would
    evaluate: the running maximum over the steps (``sink.gap``) plus REACH_FACTOR h^2 (|a_l|
    + |a_r|), a_l and a_r the peak relative accelerations of its two floors (their peak
    absolute ones plus the ground's). +inf (no bound) for a member that failed or split a
    step (its sub-steps are evaluated, not streamed), and for a scene in plan, on supports
    or with contacts between points (their closing is not one floor's u_x less another's)."""
    out = np.full(sink.gap.shape, np.inf)
    plain = all(sink.plain(c, s) is not None for c in range(len(sink.terms)) for s in range(2))
    if not plan.planar or sink.ground is not None or not plain:
        return out
    dof = dict(zip(plan.node_names, plan.node_dof))
    peak = result.envelope["absolute_acceleration"]
    ground = np.max(_peak(accelerations), axis=1)
    h = np.asarray(plan.dt, dtype=float)
    for c, (left, right) in enumerate(zip(pairs.left, pairs.right)):
        a = peak[:, dof[left]] + peak[:, dof[right]] + 2.0 * ground
        out[:, c] = sink.gap[:, c] + REACH_FACTOR * h * h * a
    ok = np.array([result.completed(b) for b in range(plan.batch)])
    ok &= result.substeps == 0
    out[~ok] = np.inf
    return out


#: reuse a run without contacts as the run with them where no contact closes (docs/risk.md,
#: "Runs with contacts that never close"); off only in the test that proves the equality
_REUSE_OPEN = True


def reusable(loaded, free: tuple[int, float], steps: int, dt: float) -> bool:
    """Whether a run without contacts of ``loaded`` (``free``: its steps and step, s) is the
    run with its contacts (``steps`` of ``dt``) of any member whose contacts stay open at
    every point the kernel evaluates. That needs the same steps, step and motions, contact
    laws that exert no force and no tangent while open (their ``free_when_open``,
    declared beside their force: ``Law.claims_free_when_open``), a scene
    that does not step differently for having contacts (an explicit integrator may take
    sub-steps for their stiffness; a linear scene without them takes one solve a step, with
    them Newton's), and the same order of every DOF within each group the storeys and links
    join (the factorisation then takes the same operations: the contacts' band entries are
    zeros). A planar scene on one support only (the bound of :func:`_reach`)."""
    from pframe.assemble import assemble
    from pframe.gap.runs import for_runs

    ex = loaded.expanded
    if (not _REUSE_OPEN or (int(free[0]), float(free[1])) != (int(steps), float(dt))
            or ex.dofs is not None or loaded.scene.supports or not ex.contacts
            or not all(c.law.claims_free_when_open() for c in ex.contacts)):
        return False
    plans = [assemble(for_runs(loaded, ("x",), contacts).first_steps(1, recorders=()))
             for contacts in (False, True)]
    if plans[0].integrator.explicit or plans[0].linear:
        return False
    orders = []
    for plan in plans:
        names = np.empty(plan.n_dof, dtype=object)
        names[plan.node_dof] = plan.node_names
        orders.append(names)
    return all(
        [n for n in orders[1] if n in group] == [n for n in orders[0] if n in group]
        for group in _joined(plans[0], orders[0]))


def _joined(plan, names) -> list[set]:
    """The groups of node names the plan's storeys and links join (its buildings, or
    buildings a link joins)."""
    from pframe.assemble.incidence import edges
    from pframe.model.expand import components

    pairs = np.asarray(plan.story_dofs if plan.story_sides is None
                       else edges(plan.story_dofs, plan.story_sides)).reshape(-1, 2)
    labels = components(plan.n_dof, pairs[(pairs >= 0).all(axis=1)])
    groups: dict[int, set] = {}
    for i, label in enumerate(labels.tolist()):
        groups.setdefault(label, set()).add(names[i])
    return list(groups.values())


def with_contacts(scenes, pairs: Pairs, free: dict, free_run: tuple[int, float], motions,
                  steps: int, dt: float, threads: int | None = None,
                  axes=None) -> dict[str, np.ndarray]:
    """The runs with contacts of a batch whose runs without them are ``free`` (run_batch
    with ``reach``; its ``reach`` is taken out): a member none of whose contacts can close
    (each contact's reach below its gap, strictly) when :func:`reusable` holds takes its run
    without contacts, the others are integrated with them. ``free_run``: the steps and step
    (s) of the runs without contacts; ``scenes``: the batch's scene or
    one per member; ``motions(index)``: the ground motions of those members, ``steps`` of
    ``dt``. Adds ``integrated`` (1 where the member ran with its contacts)."""
    reach = free.pop("reach")
    several = isinstance(scenes, (list, tuple))
    count = len(free["complete"])
    skip = np.zeros(count, dtype=bool)
    if reusable(scenes[0] if several else scenes, free_run, steps, dt):
        gaps = (np.array([[c.gap for c in m.expanded.contacts] for m in scenes]) if several
                else np.broadcast_to(pairs.gaps, reach.shape))
        skip = np.all(reach < gaps, axis=1)
    run = np.flatnonzero(~skip)
    if run.size == count:
        out = run_batch(scenes, pairs, motions(run), steps, dt, contacts=True,
                        threads=threads, axes=axes)
    else:
        out = {k: (v.copy() if np.ndim(v) else np.float64(0.0)) for k, v in free.items()}
        out["impacts"] = np.zeros_like(free["impacts"])
        if run.size:
            hit = run_batch([scenes[i] for i in run] if several else scenes, pairs,
                            motions(run), steps, dt, contacts=True, threads=threads, axes=axes)
            for k, v in hit.items():
                if np.ndim(v):
                    out[k][run] = v
                else:
                    out[k] = v
    out["integrated"] = (~skip).astype(np.int8)
    return out
