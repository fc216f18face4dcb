"""Pounding fragility: P(pounding | IM) as a lognormal distribution fitted by maximum
likelihood to the fraction of records that pound at each intensity level (Baker 2015,
"Efficient analytical fragility function fitting using dynamic structural analysis data",
Earthquake Spectra 31(1), eq. 11):

    P(pound | IM = x) = Phi(ln(x / theta) / beta),
    (theta, beta) = argmax sum_j [ z_j ln Phi_j + (n_j - z_j) ln(1 - Phi_j) ]

with n_j records at level x_j, z_j of which pound.
"""

from __future__ import annotations

import math

import numpy as np
from scipy.optimize import minimize
from scipy.stats import norm


def lognormal_probability(x, median: float, dispersion: float):
    """Phi(ln(x / median) / dispersion)."""
    return norm.cdf(np.log(np.asarray(x, float) / median) / dispersion)


def fit_lognormal(levels, trials, pounded) -> tuple[float, float]:
    """Maximum-likelihood (median, dispersion) of a lognormal fragility; NaN, NaN when the
    data cannot fix both: fewer than two levels, or no level where some but not all records
    pound (then the likelihood grows without bound as the dispersion goes to zero)."""
    x = np.asarray(levels, float)
    n = np.asarray(trials, float)
    z = np.asarray(pounded, float)
    keep = n > 0
    x, n, z = x[keep], n[keep], z[keep]
    if x.size < 2 or np.all((z == 0) | (z == n)):
        return math.nan, math.nan
    lx = np.log(x)

    def nll(p):
        mu, log_beta = p
        q = norm.cdf((lx - mu) / math.exp(log_beta))
        q = np.clip(q, 1e-300, 1.0 - 1e-16)
        return -np.sum(z * np.log(q) + (n - z) * np.log1p(-q))

    fractions = z / n
    mid = np.argmin(np.abs(fractions - 0.5))
    start = np.array([lx[mid], math.log(max(np.std(lx), 0.1))])
    best = None
    for guess in (start, start + [0.0, 1.0], start - [0.0, 1.0]):
        res = minimize(nll, guess, method="Nelder-Mead",
                       options={"xatol": 1e-10, "fatol": 1e-12, "maxiter": 4000})
        if best is None or res.fun < best.fun:
            best = res
    mu, log_beta = best.x
    if not np.isfinite(best.fun) or log_beta > math.log(1e3) or log_beta < math.log(1e-4):
        return math.nan, math.nan
    return float(math.exp(mu)), float(math.exp(log_beta))
