"""Uncertain scene parameters of a study, and subset simulation of a small probability of
pounding (docs/risk.md).

``uncertain:`` maps a scene path (as sweeps name them: ``contacts.*.gap``,
``buildings.A.story.stiffness``; ``gap`` is short for ``contacts.*.gap``) to a distribution
(:class:`pframe.risk.sampling.Uncertain`): every value the path names takes the same sample
(a path with ``*`` is one variable, fully correlated over its items). Each run of an msa,
grid-ida or cloud design gets its own Latin hypercube sample.

``design: {kind: subset, probability_level, samples, ...}`` estimates P(pounding) under the
study's stationary Clough-Penzien motion by subset simulation (Au & Beck 2001) over the
uncertain parameters and the motion's white noise: ``u`` is the standard normal vector of
both, ``g(u) = gap - max_t (u_left - u_right)`` from a run without contacts (pounding is
``g <= 0``: a run with contacts pounds exactly then), one batch of the kernel per call.
"""

from __future__ import annotations

import math

import numpy as np

from pframe.errors import InputError
from pframe.risk.sampling import DISTRIBUTIONS, Uncertain

SHORT = {"gap": "contacts.*.gap"}


def parse(uncertain: dict, where: str) -> list[Uncertain]:
    """The study's ``uncertain`` mapping as :class:`Uncertain` variables."""
    out = []
    for path, spec in uncertain.items():
        at = f"{where}.{path}"
        if not isinstance(spec, dict) or spec.get("distribution") not in DISTRIBUTIONS:
            raise InputError(f"{at}: give distribution (one of {', '.join(DISTRIBUTIONS)}) "
                             "and its two parameters, e.g. {distribution: lognormal, median: "
                             "0.05, dispersion: 0.3}")
        first, second = DISTRIBUTIONS[spec["distribution"]]
        extra = set(spec) - {"distribution", first, second}
        if extra or first not in spec or second not in spec:
            raise InputError(f"{at}: a {spec['distribution']} distribution takes {first} and "
                             f"{second}" + (f" (not {', '.join(sorted(extra))})" if extra else ""))
        try:
            a, b = float(spec[first]), float(spec[second])
        except (TypeError, ValueError):
            raise InputError(f"{at}: {first} and {second} are numbers") from None
        try:
            out.append(Uncertain(SHORT.get(path, path), spec["distribution"], a, b))
        except InputError as exc:
            raise InputError(f"{where}: {exc}") from None
    return out


def check_paths(loaded, params: list[Uncertain], where: str) -> None:
    """Every path names numbers the scene gives."""
    from pframe.sweep.paths import check_targets, resolve
    from pframe.yamltext import compose

    data, _ = compose(loaded.text, loaded.source)
    for p in params:
        try:
            check_targets(data, resolve(data, tuple(p.path.split("."))), files=False)
        except InputError as exc:
            raise InputError(f"{where}.{p.path}: {exc} (in the scene {loaded.source})") from None


def scenes(loaded, params: list[Uncertain], u: np.ndarray) -> list:
    """One scene per row of the standard normals ``u`` (n, len(params)), each validated
    whole as a file is; the scene's YAML is composed once, and the members, which are run
    and never written, keep no text of their own."""
    from pframe.reader import variant
    from pframe.sweep.paths import put, resolve
    from pframe.yamltext import compose

    composed = compose(loaded.text, loaded.source)
    out = []
    for row in np.atleast_2d(u):
        values = [float(p.value(x)) for p, x in zip(params, row)]

        def change(data, values=values):
            for p, v in zip(params, values):
                for path in resolve(data, tuple(p.path.split("."))):
                    put(data, path, v)

        out.append(variant(loaded, change, composed, text=False))
    return out


def cp_filter(step: float, wg: float, zg: float, wf: float = 0.0, zf: float = 0.0):
    """The zero-order-hold discretisation (b, a) of the Clough-Penzien filters, from white
    noise to ground acceleration (the process of clough_penzien_stationary)."""
    from scipy import signal

    num, den = np.array([2.0 * zg * wg, wg * wg]), np.array([1.0, 2.0 * zg * wg, wg * wg])
    if wf > 0.0:
        num = np.convolve(num, [1.0, 0.0, 0.0])
        den = np.convolve(den, [1.0, 2.0 * zf * wf, wf * wf])
    dnum, dden, _ = signal.cont2discrete((num, den), step, method="zoh")
    return np.ravel(dnum), dden


class SubsetProblem:
    """g(u) of a subset study: runs without contacts of the scenes and motions ``u`` names."""

    def __init__(self, loaded, params: list[Uncertain], motion: dict, steps: int, dt: float,
                 threads=None):
        from pframe.gap.runs import contact_pairs

        self.loaded, self.params, self.threads = loaded, params, threads
        self.pairs = contact_pairs(loaded)
        self.steps, self.dt = steps, dt
        self.step = float(motion.get("step", 0.01))
        self.noise = int(math.ceil(float(motion["duration"]) / self.step)) + 1
        self.scale = math.sqrt(2.0 * math.pi * float(motion["intensity"]) / self.step)
        self.filter = cp_filter(self.step, float(motion["ground_frequency"]),
                                float(motion["ground_damping"]),
                                float(motion.get("filter_frequency", 0.0)),
                                float(motion.get("filter_damping", 0.6)))
        self.runs = 0

    @property
    def dim(self) -> int:
        return len(self.params) + self.noise

    def accelerations(self, u: np.ndarray) -> np.ndarray:
        from scipy import signal

        a = signal.lfilter(*self.filter, u[:, len(self.params):] * self.scale, axis=1)
        times = np.arange(self.steps + 1) * self.dt
        grid = np.arange(self.noise) * self.step
        return np.stack([np.interp(times, grid, row, right=0.0) for row in a])

    def __call__(self, u: np.ndarray) -> np.ndarray:
        from pframe.risk.runs import run_batch

        u = np.atleast_2d(u)
        members = (scenes(self.loaded, self.params, u[:, :len(self.params)]) if self.params
                   else self.loaded)
        out = run_batch(members, self.pairs, self.accelerations(u), self.steps, self.dt,
                        contacts=False, threads=self.threads)
        self.runs += len(u)
        g = out["gap"] - np.max(out["g_req"], axis=1)
        return np.where(out["complete"] == 1, g, -np.inf)  # a failed run counts as pounding


class RecordSubsetProblem:
    """g(u) of a subset study over a suite of records, conditional on record ``record`` scaled
    to level ``column``: runs without contacts of the scenes the uncertain values ``u`` name
    (standard normals, one per value), all under that record."""

    def __init__(self, inputs, params: list[Uncertain], record: int, column: int,
                 threads=None):
        self.inputs, self.params, self.threads = inputs, params, threads
        self.ground = inputs.accelerations([record * inputs.factors.shape[1] + column])[0]
        self.runs = 0

    @property
    def dim(self) -> int:
        return len(self.params)

    def __call__(self, u: np.ndarray) -> np.ndarray:
        from pframe.risk.runs import run_batch

        u = np.atleast_2d(u)
        i = self.inputs
        out = run_batch(scenes(i.loaded, self.params, u), i.pairs,
                        np.tile(self.ground, (len(u), 1)), i.steps, i.dt, contacts=False,
                        threads=self.threads)
        self.runs += len(u)
        g = out["gap"] - np.max(out["g_req"], axis=1)
        return np.where(out["complete"] == 1, g, -np.inf)


def over_records(g_of, records: int, dim: int, n: int, seed: int, p0: float,
                 confidence: float = 0.95):
    """P(pounding) = (1 / R) sum_r P(pounding | record r), each term by subset simulation over
    the uncertain values with its own generator (seeded by (seed, r)); the terms are
    independent, so var(P) = sum_r (cov_r p_r)^2 / R^2. A record under which the chains find
    no pounding in subset_simulation's levels contributes 0 (its probability is below
    p0^max_levels). Returns (the combined Estimate, the per-record estimates, notes)."""
    from scipy.stats import norm

    from pframe.risk.sampling import Estimate, subset_simulation

    terms, notes = [], []
    for r in range(records):
        try:
            terms.append(subset_simulation(g_of(r), dim, n, np.random.default_rng([seed, r]),
                                           p0=p0))
        except InputError as exc:
            if "no failure" not in str(exc):
                raise
            terms.append(Estimate(0.0, 0.0, 0.0, 0.0, 0, "subset simulation", ()))
            notes.append(f"record {r + 1}: no pounding found ({exc}); counted as 0")
    p = np.array([t.probability for t in terms])
    sd = np.array([t.cov * t.probability for t in terms])
    probability = float(p.mean())
    evaluations = int(sum(t.evaluations for t in terms))
    if probability <= 0.0:
        raise InputError("subset simulation over the records: no pounding under any record "
                         "within the levels searched (the probability is below "
                         f"{p0 ** 20:.1e} for every record)")
    cov2 = float(np.sum(sd ** 2)) / records ** 2 / probability ** 2
    z = norm.ppf(0.5 + confidence / 2)
    spread_log = math.sqrt(math.log1p(cov2))
    combined = Estimate(probability, probability * math.exp(-z * spread_log),
                        probability * math.exp(z * spread_log), math.sqrt(cov2), evaluations,
                        "subset simulation over the records", ())
    return combined, terms, notes


#: runs per saved batch of a subset study (a level's first sample is cut into such batches)
PIECE = 250
#: batches a subset study may save (levels x chain steps, far above what max_levels allows)
MAX_CALLS = 99_999


class _Runs:
    """The run count of a subset study over records (its problems are one per record)."""

    runs = 0


class SavedCalls:
    """g(u) of a subset study, each batch of runs saved beside the output as it finishes
    (batch c of the study's sequence, with the SHA-256 of its u), so that a stopped study run
    again replays the saved batches (the same seed draws the same u, hence the same chains)
    and runs only the rest: the same numbers, bit for bit, as an uninterrupted run. Members
    of a batch are independent, so cutting a call into batches changes no bit either."""

    def __init__(self, problem: SubsetProblem, parts=None, saved: dict | None = None,
                 progress=None):
        self.problem, self.parts, self.progress = problem, parts, progress
        self.saved = {} if saved is None else saved  # filled by the caller as it loads
        self.calls = 0
        self.replayed = 0
        self.runs = 0  # over every problem it served

    def __call__(self, u: np.ndarray) -> np.ndarray:
        import hashlib

        u = np.atleast_2d(u)
        out = []
        for lo in range(0, len(u), PIECE):
            piece = np.ascontiguousarray(u[lo:lo + PIECE])
            c, self.calls = self.calls, self.calls + 1
            key = np.frombuffer(hashlib.sha256(piece.tobytes()).digest(), np.uint8)
            hit = self.saved.get(c)
            if hit is not None and np.array_equal(hit.get("u_sha256"), key):
                y = np.asarray(hit["g"], float)
                self.problem.runs += len(piece)
                self.replayed += 1
            else:
                y = np.asarray(self.problem(piece), float)
                if self.parts is not None:
                    self.parts.save(c, {"g": y, "u_sha256": key})
            out.append(y)
            self.runs += len(piece)
            if self.progress is not None:
                self.progress(self.runs, None)
        return np.concatenate(out)


def run_subset(spec, text: str, study, scene, suite, output, overwrite: bool, threads,
               timings, start: float, progress=None, records_folder=None):
    """A subset study: the probability of pounding, its c.o.v. and confidence interval. With
    ``output``, its batches are saved beside it until the file is written, so that a stopped
    study resumes (:class:`SavedCalls`)."""
    import hashlib
    import shutil
    import time
    import warnings
    from pathlib import Path

    from pframe.gap.audit import prepare
    from pframe.risk.output import subset_dataset
    from pframe.risk.sampling import subset_simulation

    on_records = spec.stochastic is None
    inputs = prepare(scene, suite, levels=(spec.design.levels or None) if on_records else None,
                     measure=spec.measure, duration=spec.duration, dt=spec.dt,
                     records_folder=records_folder)
    params = parse(spec.uncertain or {}, f"{study}, at uncertain")
    check_paths(inputs.loaded, params, f"{study}, at uncertain")
    if output is not None:
        from pframe import outputs
        from pframe.api import run_inputs

        output = outputs.check_output(output, inputs=[r for r in (
            *run_inputs(inputs.loaded), str(study)) if r], overwrite=overwrite,
            what="risk file")
    d = spec.design
    if on_records:
        problem = _Runs()
    else:
        problem = SubsetProblem(inputs.loaded, params, spec.stochastic, inputs.steps, inputs.dt,
                                threads)
    parts, saved = None, {}
    if output is not None:
        from pframe.risk.ida import _Store
        from pframe.sweep.store import Parts

        digest = inputs.digest("risk subset " + hashlib.sha256(text.encode()).hexdigest())
        parts = Parts(Path(output), _Store(digest, inputs.loaded.source, 1),
                      _Store(count=MAX_CALLS, chunks=MAX_CALLS))
    g = SavedCalls(problem, parts, saved, progress)
    try:
        if parts is not None:
            saved.update(parts.load_finished(overwrite, "scene, study file"))
        terms, notes = None, list(inputs.warnings)
        if on_records:
            def g_of(r):
                g.problem = RecordSubsetProblem(inputs, params, r, 0, threads)
                return g

            estimate, terms, more = over_records(g_of, len(inputs.suite.motions), len(params),
                                                 d.samples, spec.seed, d.probability_level)
            notes += more
            problem.runs = estimate.evaluations
        else:
            estimate = subset_simulation(g, problem.dim, d.samples,
                                         np.random.default_rng(spec.seed),
                                         p0=d.probability_level)
    finally:
        if parts is not None:
            parts.close()
    if estimate.cov > 0.3:
        notes.append(f"the probability's coefficient of variation is {estimate.cov:.2f}: "
                     "raise design.samples for a tighter estimate")
    for line in notes:
        warnings.warn(f"{study}: {line}", stacklevel=3)
    ds = subset_dataset(spec, inputs, params, estimate, problem, text, str(study), notes,
                        terms)
    if output is not None:
        from pframe.record.netcdf import write_dataset
        from pframe.sweep.store import parts_folder

        write_dataset(ds, output)
        shutil.rmtree(parts_folder(Path(output)), ignore_errors=True)
    if timings is not None:
        timings.update(wall_seconds=time.perf_counter() - start, variants=problem.runs,
                       solve_seconds=math.nan)
    return ds
