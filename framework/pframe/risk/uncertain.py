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

    data = loaded.given
    for p in params:
        try:
            check_targets(data, resolve(data, tuple(p.path.split("."))), files=False)
        except InputError as exc:
            raise InputError(f"{where}.{p.path}: {exc} (in the scene {loaded.source})") from None


def scenes(loaded, params: list[Uncertain], u: np.ndarray) -> list:
    """One scene per row of the standard normals ``u`` (n, len(params)), each validated
    whole as a file is, from the scene's data (no text is made of the members, which are run
    and never written)."""
    from pframe.reader import variant
    from pframe.sweep.paths import put, resolve

    out = []
    for row in np.atleast_2d(u):
        values = [float(p.value(x)) for p, x in zip(params, row)]

        def change(data, values=values):
            for p, v in zip(params, values):
                for path in resolve(data, tuple(p.path.split("."))):
                    put(data, path, v)

        out.append(variant(loaded, change))
    return out


class SubsetProblem:
    """g(u) of a subset study: runs without contacts of the scenes and motions ``u`` names."""

    def __init__(self, loaded, params: list[Uncertain], motion: dict, steps: int, dt: float,
                 threads=None, channels: tuple[str, ...] = ("x",)):
        from pframe.excitation.stochastic import clough_penzien_filter
        from pframe.gap.runs import contact_pairs

        excitation = loaded.scene.excitation
        if loaded.expanded.node_support and (excitation is None
                                             or excitation.kind != "wave_passage"):
            raise InputError(f"{loaded.source}: a subset design draws one stochastic motion "
                             "per run, which reaches a scene's supports as its wave passage "
                             "carries it; this scene on supports has none (excitation: {kind: "
                             "wave_passage, ...}), or run it under a suite of records "
                             "(docs/supports.md#suites-of-a-motion-per-support)")
        self.loaded, self.params, self.threads = loaded, params, threads
        # the motion's direction on the site (its angle, degrees from the site's x)
        self.channels, self.angle = channels, float(motion.get("angle", 0.0))
        self.pairs = contact_pairs(loaded)
        self.steps, self.dt = steps, dt
        self.step = float(motion.get("step", 0.01))
        self.noise = int(math.ceil(float(motion["duration"]) / self.step)) + 1
        self.scale = math.sqrt(2.0 * math.pi * float(motion["intensity"]) / self.step)
        self.filter = clough_penzien_filter(self.step, float(motion["ground_frequency"]),
                                            float(motion["ground_damping"]),
                                            float(motion.get("filter_frequency", 0.0)),
                                            float(motion.get("filter_damping", 0.6)))
        self.runs = 0

    @property
    def dim(self) -> int:
        return len(self.params) + self.noise

    def accelerations(self, u: np.ndarray) -> np.ndarray:
        """(B, C, steps + 1) the motions of the standard normals ``u`` along the channels."""
        from scipy import signal

        from pframe.excitation.suite import GroundMotion

        a = signal.lfilter(*self.filter, u[:, len(self.params):] * self.scale, axis=1)
        times = np.arange(self.steps + 1) * self.dt
        grid = np.arange(self.noise) * self.step
        return np.stack([GroundMotion("", grid, row, "", angle=self.angle).on_site(
            times, self.channels) for row in a])

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
                        np.repeat(self.ground[None], len(u), axis=0), i.steps, i.dt,
                        contacts=False, threads=self.threads, axes=i.channels)
        self.runs += len(u)
        g = out["gap"] - np.max(out["g_req"], axis=1)
        return np.where(out["complete"] == 1, g, -np.inf)


def over_records(g_of, records: int, dim: int, n: int, seed: int, p0: float,
                 confidence: float = 0.95, floor: float = 0.0, column: int = 0):
    """P(pounding) = (1 / R) sum_r P(pounding | record r), each term by subset simulation over
    the uncertain values with its own generator (seeded by (seed, r), and the stripe
    ``column`` after the first); the terms are independent, so var(P) = sum_r (cov_r p_r)^2
    / R^2. A record whose levels fall below ``floor`` before it pounds is stopped there and
    counts 0, its level's probability (which bounds its term) added to the interval's upper
    end / R; one under which the chains find no pounding in subset_simulation's levels
    counts 0 too (its probability is below p0^max_levels). Returns (the combined Estimate,
    the per-record estimates, notes)."""
    from scipy.stats import norm

    from pframe.risk.sampling import Estimate, subset_simulation

    terms, notes = [], []
    bound = 0.0  # what the terms counted 0 may add, at most
    for r in range(records):
        rng = np.random.default_rng([seed, r] if column == 0 else [seed, r, column])
        try:
            term = subset_simulation(g_of(r), dim, n, rng, p0=p0, floor=floor)
        except InputError as exc:
            if "no failure" not in str(exc):
                raise
            term = Estimate(0.0, 0.0, p0 ** 20, 0.0, 0, "subset simulation", ())
            notes.append(f"record {r + 1}: no pounding found ({exc}); counted as 0")
        if term.probability == 0.0:
            bound += term.high
        terms.append(term)
    p = np.array([t.probability for t in terms])
    sd = np.array([t.cov * t.probability for t in terms])
    probability = float(p.mean())
    evaluations = int(sum(t.evaluations for t in terms))
    stopped = sum(t.method.endswith("floor") for t in terms)
    if stopped:
        notes.append(f"{stopped} of {records} records stopped below the floor "
                     f"{floor:.1e} (probability of pounding under each below it) and count 0; "
                     "the interval's upper end adds their bound")
    if probability <= 0.0:
        return (Estimate(0.0, 0.0, bound / records, math.inf, evaluations,
                         "subset simulation over the records", ()), terms, notes)
    cov2 = float(np.sum(sd ** 2)) / records ** 2 / probability ** 2
    z = norm.ppf(0.5 + confidence / 2)
    spread_log = math.sqrt(math.log1p(cov2))
    combined = Estimate(probability, probability * math.exp(-z * spread_log),
                        probability * math.exp(z * spread_log) + bound / records,
                        math.sqrt(cov2), evaluations, "subset simulation over the records", ())
    return combined, terms, notes


def stripe_weights(levels, hazard) -> tuple[np.ndarray, float]:
    """The weights c_k of the mean annual frequency lambda = sum_k c_k P_k of pounding from
    the probabilities P_k at the stripes ``levels`` (g, increasing): P(pounding | IM = x)
    taken linear in ln x between stripes, 0 below the first and P_K above the last, and
    integrated over the hazard curve as every fragility is (hazard.mean_annual_frequency:
    lambda is linear in P, so c_k is the integral of the k-th hat function). Also the rate
    of exceeding the first stripe, lambda_IM(x_1), for the note on what lies below it."""
    from pframe.risk.hazard import mean_annual_frequency

    lx = np.log(np.asarray(levels, float))

    def hat(k):
        def h(x):
            x = np.log(np.asarray(x, float))
            e = np.zeros(len(lx))
            e[k] = 1.0
            out = np.interp(x, lx, e)
            return np.where(x < lx[0], 0.0, out)
        return h

    c = np.array([mean_annual_frequency(hat(k), hazard)[0] for k in range(len(lx))])
    return c, float(hazard.rate(np.array([levels[0]]))[0])


def maf_from_stripes(levels, estimates, hazard, confidence: float = 0.95):
    """(lambda, low, high, cov, notes): the mean annual frequency of pounding from the stripes'
    estimates (independent: var = sum_k c_k^2 sd_k^2; the interval lognormal, the upper end
    raised by the stripes' floor bounds), and what it leaves out."""
    from scipy.stats import norm

    c, _ = stripe_weights(levels, hazard)
    p = np.array([e.probability for e in estimates])
    sd = np.array([e.cov * e.probability if e.probability > 0 else 0.0 for e in estimates])
    bound = np.array([e.high if e.probability == 0 else 0.0 for e in estimates])
    lam = float(np.dot(c, p))
    notes = []
    from pframe.risk.hazard import mean_annual_frequency

    below = 0.0
    if p[0] > 0:  # below the first stripe, counted 0: estimated on P's power law there
        x1 = float(levels[0])
        slope = math.log(p[1] / p[0]) / math.log(levels[1] / x1) if p[1] > 0 else 0.0
        below = mean_annual_frequency(
            lambda x: np.where(x < x1, p[0] * (np.asarray(x) / x1) ** max(slope, 0.0), 0.0),
            hazard)[0]
    if lam > 0 and below > 0.05 * lam:
        notes.append(f"the probability of pounding at the first stripe ({levels[0]:g} g) is "
                     f"{p[0]:.2e}: the intensities below it, counted 0, would add about "
                     f"{below:.2e} /yr ({below / lam:.0%} of the annual frequency) on the "
                     "power law of the first two stripes; add a lower stripe")
    # above the last stripe P is counted at P_K: what P's power law of the last two stripes
    # (capped at 1) adds there
    top = 0.0
    if p[-1] > 0 and p[-2] > 0:
        xk = float(levels[-1])
        slope = max(math.log(p[-1] / p[-2]) / math.log(xk / levels[-2]), 0.0)
        top = mean_annual_frequency(
            lambda x: np.where(x > xk, np.minimum(1.0, p[-1] * (np.asarray(x) / xk) ** slope)
                               - p[-1], 0.0), hazard)[0]
    if lam > 0 and top > 0.05 * lam:
        notes.append(f"the intensities above the last stripe ({levels[-1]:g} g) are counted at "
                     f"its probability {p[-1]:.2e}; on the power law of the last two stripes "
                     f"(capped at 1) they would add about {top:.2e} /yr ({top / lam:.0%} of the "
                     "annual frequency); add a higher stripe")
    above = _share_above(levels, p, hazard, lam)
    if above > 0.05:
        notes.append(f"{above:.0%} of the annual frequency comes from intensities above the "
                     f"hazard table's last value ({hazard.im[-1]:g} g), counted at the "
                     "probability there (a lower bound); extend the table up")
    if lam <= 0:  # no stripe pounds: 0 as estimated, its c.o.v. undefined
        return 0.0, 0.0, float(np.dot(c, bound)), math.nan, notes
    cov2 = float(np.sum((c * sd) ** 2)) / lam ** 2
    z = norm.ppf(0.5 + confidence / 2)
    spread_log = math.sqrt(math.log1p(cov2))
    return (lam, lam * math.exp(-z * spread_log),
            lam * math.exp(z * spread_log) + float(np.dot(c, bound)), math.sqrt(cov2), notes)


def _share_above(levels, p, hazard, lam: float) -> float:
    """The share of ``lam`` that the stripes' probabilities (linear in ln x between them)
    contribute through the intensities above the hazard table (counted at its last IM)."""
    if not lam > 0:
        return 0.0
    x = float(hazard.im[-1])
    lx = np.log(np.asarray(levels, float))
    at = 0.0 if math.log(x) < lx[0] else float(np.interp(math.log(x), lx, p))
    return at * float(hazard.frequency[-1]) / lam


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


def run_subset(spec, text: str, study, inputs, params, output, overwrite: bool, threads,
               timings, start: float, progress=None, hazard=None):
    """A subset study (``inputs``: the study opened, :func:`pframe.risk.study.open_study`;
    ``output`` checked): the probability of pounding, its c.o.v. and confidence interval.
    With ``output``, its batches are saved beside it until the file is written, so that a
    stopped study resumes (:class:`SavedCalls`)."""
    import hashlib
    import shutil
    import time
    import warnings
    from pathlib import Path

    from pframe.risk.output import subset_dataset
    from pframe.risk.sampling import subset_simulation

    on_records = spec.stochastic is None
    d = spec.design
    if on_records:
        problem = _Runs()
    else:
        problem = SubsetProblem(inputs.loaded, params, spec.stochastic, inputs.steps, inputs.dt,
                                threads, inputs.channels)
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
        terms, notes, stripes, maf = None, list(inputs.warnings), None, None
        if on_records:
            stripes, terms = [], []
            for column in range(inputs.factors.shape[1]):
                def g_of(r, column=column):
                    g.problem = RecordSubsetProblem(inputs, params, r, column, threads)
                    return g

                estimate, per_record, more = over_records(
                    g_of, len(inputs.suite.motions), len(params), d.samples, spec.seed,
                    d.probability_level, floor=d.floor, column=column)
                stripes.append(estimate)
                terms.append(per_record)
                at = f" at {float(inputs.levels[column]):g} g" if len(inputs.levels) > 1 else ""
                notes += [line + at for line in more]
            problem.runs = sum(e.evaluations for e in stripes)
            estimate = stripes[0]
            if hazard is not None:
                maf = maf_from_stripes(inputs.levels, stripes, hazard)
                notes += maf[4]
        else:
            estimate = subset_simulation(g, problem.dim, d.samples,
                                         np.random.default_rng(spec.seed),
                                         p0=d.probability_level)
    finally:
        if parts is not None:
            parts.close()
    for k, e in enumerate(stripes or [estimate]):
        at = f" at {float(inputs.levels[k]):g} g" if stripes and len(stripes) > 1 else ""
        if e.probability == 0.0:
            notes.append(f"no record pounds{at} within the levels searched: the probability "
                         f"is 0 as estimated, below about {e.high:.1e} (the upper end)")
        elif e.cov > 0.3:
            notes.append(f"the probability's coefficient of variation is {e.cov:.2f}{at}: "
                         "raise design.samples for a tighter estimate")
    for line in notes:
        warnings.warn(f"{study}: {line}", stacklevel=3)
    ds = subset_dataset(spec, inputs, params, estimate, problem, text, str(study), notes,
                        terms, stripes, maf, hazard)
    if output is not None:
        from pframe.record.netcdf import write_dataset
        from pframe.sweep.store import parts_folder

        write_dataset(ds, output)
        shutil.rmtree(parts_folder(Path(output)), ignore_errors=True)
    if timings is not None:
        timings.update(wall_seconds=time.perf_counter() - start, variants=problem.runs,
                       solve_seconds=math.nan)
    return ds
