"""Incremental dynamic analysis by hunt and fill (Vamvatsikos & Cornell 2002, "Incremental
dynamic analysis", EESD 31(3); 2004, "Applied incremental dynamic analysis", Earthquake
Spectra 20(2)), batched across records.

Per record: *hunt* up from ``start`` in steps that grow geometrically (``step``, then
``step * growth``, ``step * growth^2``, ...) until a run passes the limit (its demand / limit
exceeds 1, or the run fails: non-convergence or collapse), or ``max_level`` is run without
passing it (the record is right-censored there); then *fill* by bisection between the last
level that did not pass and the first that did, until they are at most ``resolution`` apart.
Each round runs the next level of every record still searching: one batch of the kernel.

The capacity of a record is then found as on a grid (:func:`pframe.risk.analysis.fit`): the
IM where the demand ratio passes 1, interpolated in log-log between the two bracketing runs
(or the first run that passes, for a yes/no outcome), so it is within ``resolution`` of the
capacity a dense grid finds when the demand grows with the IM.
"""

from __future__ import annotations

import dataclasses

import numpy as np


@dataclasses.dataclass
class _Record:
    level: float  # the last hunted level
    step: float  # the next hunt step
    lo: float = 0.0  # fill: the highest level that did not pass, the lowest that did
    hi: float = np.inf
    done: bool = False
    censored: bool = False


class HuntAndFill:
    """The search state of every record; :meth:`next_round` gives the (record, IM) to run,
    :meth:`report` takes whether each passed the limit."""

    def __init__(self, records: int, start: float, step: float, growth: float,
                 resolution: float, max_level: float):
        self.start, self.growth = float(start), float(growth)
        self.resolution, self.max_level = float(resolution), float(max_level)
        self.state = [_Record(level=0.0, step=float(step)) for _ in range(records)]
        self.rounds = 0
        self.runs = 0

    def next_round(self) -> tuple[np.ndarray, np.ndarray]:
        which, ims = [], []
        for r, s in enumerate(self.state):
            if s.done:
                continue
            if s.hi == np.inf:  # hunting up
                im = self.start if s.level == 0.0 else min(s.level + s.step, self.max_level)
            else:  # filling between lo and hi
                im = 0.5 * (s.lo + s.hi)
            which.append(r)
            ims.append(im)
        return np.array(which, dtype=np.int64), np.array(ims, dtype=float)

    def report(self, which, ims, passed) -> None:
        self.rounds += 1
        self.runs += len(which)
        for r, im, p in zip(which, ims, passed):
            s = self.state[r]
            if s.hi == np.inf:
                if p:
                    s.hi = im
                    s.lo = s.level  # 0 when the first level passes
                else:
                    if s.level > 0.0:
                        s.step *= self.growth
                    s.level = im
                    if im >= self.max_level:
                        s.done = s.censored = True
                        continue
            elif p:
                s.hi = im
            else:
                s.lo = im
            if s.hi < np.inf and s.hi - s.lo <= self.resolution:
                s.done = True

    @property
    def finished(self) -> bool:
        return all(s.done for s in self.state)


def hunt_and_fill(passes, records: int, start: float, step: float, growth: float,
                  resolution: float, max_level: float, max_rounds: int = 200):
    """Run the search with ``passes(which, ims) -> bool array`` (one batch per round);
    returns the :class:`HuntAndFill` with its counts of rounds and runs."""
    search = HuntAndFill(records, start, step, growth, resolution, max_level)
    while not search.finished and search.rounds < max_rounds:
        which, ims = search.next_round()
        search.report(which, ims, np.asarray(passes(which, ims), bool))
    return search


def grid_layout(record: np.ndarray, im: np.ndarray, records: int) -> np.ndarray:
    """(records, L) indices into the runs, each record's runs in order of IM, -1 padded."""
    per = [np.flatnonzero(record == r) for r in range(records)]
    per = [p[np.argsort(im[p], kind="stable")] for p in per]
    width = max(1, max(len(p) for p in per))
    out = np.full((records, width), -1, dtype=np.int64)
    for r, p in enumerate(per):
        out[r, :len(p)] = p
    return out


class _Store:
    """What the chunk store asks of a study (identity, chunking) and of its extent."""

    def __init__(self, digest: str = "", source: str = "", chunk: int = 1, count: int = 0,
                 chunks: int = 0):
        self.digest, self.source, self.chunk = digest, source, chunk
        self.count, self.chunks = count, chunks


def _limit(spec, name: str) -> tuple[str, float | None]:
    if name == "pounding":
        return "pounding", None
    for kind in ("drift", "drift_ratio", "acceleration"):
        values = getattr(spec.limits, kind)
        if name in values:
            return kind, float(values[name])
    raise KeyError(name)


def _pad(done: list[dict], layout: np.ndarray) -> dict:
    """The rounds' arrays concatenated, then laid out (records x slots) record-major with
    the slots not run filled (NaN, 0; complete -1)."""
    rows = {k: (np.concatenate([d[k] for d in done]) if np.ndim(done[0][k]) else
                sum(float(d[k]) for d in done)) for k in done[0]}
    flat = layout.ravel()
    out = {}
    for k, v in rows.items():
        if not np.ndim(v):
            out[k] = v
            continue
        fill = -1 if k.endswith("_complete") else (np.nan if v.dtype.kind == "f" else 0)
        padded = np.full((flat.size, *v.shape[1:]), fill, dtype=v.dtype)
        padded[flat >= 0] = v[flat[flat >= 0]]
        out[k] = padded
    return out


def run_hunt(inputs, spec, output, threads, restart: bool, progress=None):
    """The study's IDA by hunt and fill: every round one batch (with the runs with contacts
    too, with ``pounding_runs``), saved beside ``output`` so that a stopped study resumes.
    Returns (rows laid out records x slots, the inputs with that layout, the search)."""
    import math
    from pathlib import Path

    from pframe.risk.analysis import _ratios
    from pframe.risk.runs import run_batch, with_contacts

    design = spec.design
    hunt = design.hunt
    records = len(inputs.suite.motions)
    kind, value = _limit(spec, design.limit)
    condition = design.condition or ("with_pounding" if spec.pounding_runs else
                                     "without_pounding")
    prefix = "contact" if condition == "with_pounding" else "free"
    gap = float(np.min(inputs.pairs.gaps))
    scene_dt = float(inputs.loaded.expanded.dt)
    contact_steps = int(math.ceil(inputs.steps * inputs.dt / scene_dt - 1e-9))
    max_rounds = 200

    def ground(which, ims, steps, dt):
        times = np.arange(steps + 1) * dt
        return np.stack([im / inputs.intensities[r] * inputs.motion(r, times)
                         for r, im in zip(which, ims)])

    parts = None
    if output is not None:
        from pframe.sweep.store import Parts

        digest = inputs.digest(f"risk ida hunt {design.model_dump_json()} "
                               f"pounding={spec.pounding_runs}")
        parts = Parts(Path(output), _Store(digest, inputs.loaded.source, 1),
                      _Store(count=max_rounds, chunks=max_rounds))
    saved: dict[int, dict] = {}
    done: list[dict] = []
    order_record, order_im = [], []

    def passes(which, ims):
        c = len(done)
        if c in saved and np.array_equal(saved[c]["ida_record"], which):
            arrays = saved[c]
        else:
            free = run_batch(inputs.loaded, inputs.pairs,
                             ground(which, ims, inputs.steps, inputs.dt), inputs.steps,
                             inputs.dt, contacts=False, threads=threads,
                             axes=inputs.channels, reach=spec.pounding_runs)
            hit = None if not spec.pounding_runs else with_contacts(
                inputs.loaded, inputs.pairs, free, (inputs.steps, inputs.dt),
                lambda index: ground(which[index], ims[index], contact_steps, scene_dt),
                contact_steps, scene_dt, threads=threads, axes=inputs.channels)
            arrays = {f"free_{k}": v for k, v in free.items()}
            if hit is not None:
                arrays.update({f"contact_{k}": v for k, v in hit.items()})
            arrays["ida_record"], arrays["ida_im"] = which, ims
            if parts is not None:
                parts.save(c, arrays)
        done.append(arrays)
        order_record.append(which)
        order_im.append(ims)
        if progress is not None:
            progress(sum(len(w) for w in order_record), None)
        ratio = _ratios(arrays, prefix, kind, value, gap)
        return (arrays[f"{prefix}_complete"] == 0) | (ratio > 1)

    try:
        if parts is not None:
            saved.update(parts.load_finished(restart, "scene, suite, design, step"))
        search = hunt_and_fill(passes, records, hunt.start, hunt.step, hunt.growth,
                               design.resolution, design.max_level, max_rounds)
    finally:
        if parts is not None:
            parts.close()
    record = np.concatenate(order_record)
    im = np.concatenate(order_im)
    layout = grid_layout(record, im, records)
    rows = _pad(done, layout)
    rows["ida_im"] = np.where(layout.ravel() >= 0, rows["ida_im"], np.nan)
    factors = rows["ida_im"].reshape(layout.shape) / np.asarray(inputs.intensities)[:, None]
    laid = dataclasses.replace(inputs, levels=np.arange(1.0, layout.shape[1] + 1),
                               factors=factors)
    return rows, laid, search
