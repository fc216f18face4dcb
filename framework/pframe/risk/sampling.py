"""Random scene parameters and small probabilities.

- :class:`Uncertain`: a scene path (as sweeps name them, ``contacts.*.gap``) with a
  distribution: normal (mean, sd), lognormal (median, dispersion = sd of ln) or uniform
  (low, high). Each maps a standard normal u to its value, x = F^-1(Phi(u)), so Latin
  hypercube samples and subset simulation work in one standard normal space.
- :func:`latin_hypercube`: n samples, each variable's n equiprobable strata hit once, in a
  random pairing (McKay, Beckman & Conover 1979).
- :func:`crude_monte_carlo`: P(g <= 0) from n independent samples, with the Clopper-Pearson
  interval.
- :func:`subset_simulation`: Au & Beck (2001), "Estimation of small failure probabilities in
  high dimensions by subset simulation", Prob. Eng. Mech. 16(4): P(g <= 0) as a product of
  conditional probabilities p0 of nested intermediate events, sampled by the modified
  Metropolis algorithm; its coefficient of variation from their eqs. 26-29 (the chains'
  correlation included).

``g`` takes an (n, dim) array of standard normals and returns n values: one batch of runs.
"""

from __future__ import annotations

import dataclasses
import math

import numpy as np
from scipy.stats import beta as beta_dist
from scipy.stats import norm

from pframe.errors import InputError

DISTRIBUTIONS = {"normal": ("mean", "sd"), "lognormal": ("median", "dispersion"),
                 "uniform": ("low", "high")}


@dataclasses.dataclass(frozen=True)
class Uncertain:
    """One uncertain scene value."""

    path: str
    distribution: str
    a: float
    b: float

    def __post_init__(self):
        if self.distribution not in DISTRIBUTIONS:
            raise InputError(f"{self.path}: distribution {self.distribution!r}; expected one "
                             f"of {', '.join(DISTRIBUTIONS)}")
        first, second = DISTRIBUTIONS[self.distribution]
        ok = {"normal": self.b > 0, "lognormal": self.a > 0 and self.b > 0,
              "uniform": self.b > self.a}[self.distribution]
        if not (ok and math.isfinite(self.a) and math.isfinite(self.b)):
            raise InputError(f"{self.path}: a {self.distribution} distribution needs "
                             f"{first} and {second} with "
                             + {"normal": "sd > 0", "lognormal": "median > 0 and dispersion > 0",
                                "uniform": "high > low"}[self.distribution]
                             + f" (got {self.a!r}, {self.b!r})")

    def value(self, u):
        """The value at standard normal ``u``."""
        u = np.asarray(u, float)
        if self.distribution == "normal":
            return self.a + self.b * u
        if self.distribution == "lognormal":
            return self.a * np.exp(self.b * u)
        return self.a + (self.b - self.a) * norm.cdf(u)


def latin_hypercube(n: int, dim: int, rng: np.random.Generator) -> np.ndarray:
    """(n, dim) standard normals of a Latin hypercube: column j takes one point in each of
    the n equiprobable strata of N(0, 1), at a uniform place inside it, in random order."""
    strata = np.stack([rng.permutation(n) for _ in range(dim)], axis=1)
    return norm.ppf((strata + rng.random((n, dim))) / n)


@dataclasses.dataclass(frozen=True)
class Estimate:
    """A probability with its confidence interval, and how it was found."""

    probability: float
    low: float
    high: float
    cov: float  # coefficient of variation of the estimator
    evaluations: int
    method: str
    levels: tuple = ()  # subset simulation: the intermediate thresholds


def crude_monte_carlo(g, dim: int, n: int, rng: np.random.Generator,
                      confidence: float = 0.95, batch: int = 100_000) -> Estimate:
    failures = 0
    done = 0
    while done < n:
        size = min(batch, n - done)
        failures += int(np.sum(np.asarray(g(rng.standard_normal((size, dim)))) <= 0))
        done += size
    p = failures / n
    alpha = 1 - confidence
    low = beta_dist.ppf(alpha / 2, failures, n - failures + 1) if failures else 0.0
    high = beta_dist.ppf(1 - alpha / 2, failures + 1, n - failures) if failures < n else 1.0
    cov = math.sqrt((1 - p) / (p * n)) if p > 0 else math.inf
    return Estimate(p, float(low), float(high), cov, n, "crude Monte Carlo")


def _chain_correlation(indicator: np.ndarray, p: float) -> float:
    """gamma of Au & Beck's eq. 27 from the (chains, length) failure indicators of a level."""
    chains, length = indicator.shape
    if length < 2 or p <= 0 or p >= 1:
        return 0.0
    n = chains * length
    var = p * (1 - p)
    gamma = 0.0
    for k in range(1, length):
        r = np.sum(indicator[:, :length - k] * indicator[:, k:]) / (n - k * chains) - p * p
        gamma += 2 * (1 - k / length) * r / var
    return max(gamma, 0.0)


def subset_simulation(g, dim: int, n: int, rng: np.random.Generator, p0: float = 0.1,
                      spread: float = 1.0, max_levels: int = 20,
                      confidence: float = 0.95, floor: float = 0.0) -> Estimate:
    """P(g(U) <= 0), U standard normal in ``dim`` dimensions, with ``n`` samples per level.

    ``floor``: once the estimate of P(g <= the level's threshold), which bounds P(g <= 0), is
    below it, stop there (no chains run) and return probability 0 with that estimate as the
    interval's upper end (method "... stopped below the floor"): a term too small to matter
    in a sum is not chased down to its own probability."""
    seeds = int(round(n * p0))
    if seeds < 1 or n % seeds:
        raise InputError(f"subset simulation: n * p0 = {n} * {p0} must be a whole number of "
                         "chains that divides n")
    length = n // seeds
    u = rng.standard_normal((n, dim))
    y = np.asarray(g(u), float)
    evaluations = n
    probability = 1.0
    cov2 = 0.0
    thresholds = []
    indicator = None
    for level in range(max_levels):
        order = np.argsort(y)
        threshold = float(y[order[seeds - 1]])
        if threshold <= 0:  # the last level: the fraction that fails outright
            fails = y <= 0
            pf = float(fails.mean())
            if level == 0:
                delta2 = (1 - pf) / (pf * n)
            else:
                gamma = _chain_correlation(indicator_of(fails, seeds, length), pf)
                delta2 = (1 - pf) / (pf * n) * (1 + gamma)
            probability *= pf
            cov2 += delta2
            thresholds.append(0.0)
            break
        thresholds.append(threshold)
        if level == 0:
            cov2 += (1 - p0) / (p0 * n)
        else:
            gamma = _chain_correlation(indicator, p0)
            cov2 += (1 - p0) / (p0 * n) * (1 + gamma)
        probability *= p0
        if probability < floor:
            return Estimate(0.0, 0.0, probability, 0.0, evaluations,
                            "subset simulation stopped below the floor", tuple(thresholds))
        # modified Metropolis from the seeds: chains of `length` states each
        cur_u, cur_y = u[order[:seeds]].copy(), y[order[:seeds]].copy()
        chain_u = np.empty((seeds, length, dim))
        chain_y = np.empty((seeds, length))
        chain_u[:, 0], chain_y[:, 0] = cur_u, cur_y
        for step in range(1, length):
            cand = cur_u + spread * rng.standard_normal(cur_u.shape)
            ratio = np.exp(-0.5 * (cand ** 2 - cur_u ** 2))
            accept = rng.random(cur_u.shape) < np.minimum(1.0, ratio)
            trial = np.where(accept, cand, cur_u)
            moved = np.any(accept, axis=1)
            trial_y = cur_y.copy()
            if moved.any():
                trial_y[moved] = np.asarray(g(trial[moved]), float)
                evaluations += int(moved.sum())
            inside = trial_y <= threshold
            cur_u = np.where(inside[:, None], trial, cur_u)
            cur_y = np.where(inside, trial_y, cur_y)
            chain_u[:, step], chain_y[:, step] = cur_u, cur_y
        u, y = chain_u.reshape(n, dim), chain_y.reshape(n)
        next_threshold = float(np.sort(y)[seeds - 1])
        indicator = (chain_y <= max(next_threshold, 0.0)).astype(float)
    else:
        raise InputError(f"subset simulation: no failure after {max_levels} levels (the "
                         f"probability is below {p0 ** max_levels:.1e}, or g never reaches 0)")
    cov = math.sqrt(cov2)
    z = norm.ppf(0.5 + confidence / 2)
    # the estimator is close to lognormal (a product of level probabilities)
    spread_log = math.sqrt(math.log1p(cov2))
    return Estimate(probability, probability * math.exp(-z * spread_log),
                    probability * math.exp(z * spread_log), cov, evaluations,
                    "subset simulation", tuple(thresholds))


def indicator_of(fails: np.ndarray, chains: int, length: int) -> np.ndarray:
    return fails.reshape(chains, length).astype(float)
