"""Lognormal fragility functions by maximum likelihood, with their confidence (Baker 2015,
"Efficient analytical fragility function fitting using dynamic structural analysis data",
Earthquake Spectra 31(1)):

    P(limit state | IM = x) = Phi(ln(x / theta) / beta).

- multiple-stripe analysis: z_j of n_j runs at level x_j exceed the limit; binomial
  likelihood sum_j [z_j ln Phi_j + (n_j - z_j) ln(1 - Phi_j)] (Baker's eq. 11);
- incremental dynamic analysis: each record's capacity (the IM at which it first exceeds the
  limit) is one lognormal sample; a record that never exceeds it up to the highest IM run is
  right-censored there;
- cloud analysis: ln D = a + b ln IM + e, e ~ N(0, s^2), fitted by maximum likelihood with the
  runs above ``censor`` (collapse, or a demand the runs cannot measure) right-censored, so
  P(D > d | x) = Phi((a + b ln x - ln d) / s): theta = exp((ln d - a) / b), beta = s / b.

Each fit returns a :class:`Fragility` whose covariance of (ln theta, ln beta) is the inverse
of the observed Fisher information (the negative log-likelihood's Hessian at the optimum,
by central differences); confidence bounds are mu +- z sd on the log scale.
"""

from __future__ import annotations

import dataclasses
import math

import numpy as np
from scipy.optimize import minimize
from scipy.special import log_ndtr, ndtr
from scipy.stats import norm

_LOG_SQRT_2PI = 0.5 * math.log(2 * math.pi)

#: the confidence of the bounds every fit reports
CONFIDENCE = 0.90


@dataclasses.dataclass(frozen=True)
class Fragility:
    """A lognormal fragility; ``cov``: covariance of (ln median, ln dispersion)."""

    median: float
    dispersion: float
    cov: np.ndarray = dataclasses.field(default_factory=lambda: np.full((2, 2), np.nan))
    method: str = "msa"
    note: str = ""  # why the fit is absent, when it is

    @property
    def fitted(self) -> bool:
        return math.isfinite(self.median) and math.isfinite(self.dispersion)

    def probability(self, x):
        x = np.asarray(x, float)
        if not self.fitted:
            return np.full(x.shape, np.nan)
        with np.errstate(divide="ignore"):
            return _cdf(np.log(x / self.median) / self.dispersion)

    def bounds(self, confidence: float = CONFIDENCE) -> tuple[tuple, tuple]:
        """((median low, high), (dispersion low, high)) at ``confidence``."""
        z = norm.ppf(0.5 + confidence / 2)
        sd = np.sqrt(np.diag(self.cov)) if np.all(np.isfinite(self.cov)) else np.full(2, np.nan)
        with np.errstate(over="ignore"):  # a fit the data hardly fix: unbounded
            return ((float(self.median * np.exp(-z * sd[0])),
                     float(self.median * np.exp(z * sd[0]))),
                    (float(self.dispersion * np.exp(-z * sd[1])),
                     float(self.dispersion * np.exp(z * sd[1]))))


def _absent(method: str, note: str) -> Fragility:
    return Fragility(math.nan, math.nan, method=method, note=note)


#: the largest standard deviation of ln theta or ln beta of a fit the data fix: above it the
#: 90 % bounds span more than a factor exp(2 x 1.645 x 2) ~ 700 (the MAF's range is not
#: sampled either, pframe.risk.analysis)
MAX_SD = 2.0


def unfixed(f: Fragility) -> str:
    """Why the data do not fix the fitted ``f``, or '' when they do: the covariance of
    (ln theta, ln beta) (the inverse observed information) is not finite and positive
    definite (the likelihood is flat, or its maximum lies at a boundary: beta -> 0 or a
    median beyond the data), or a standard deviation is above :data:`MAX_SD`."""
    if not f.fitted:
        return ""
    cov = np.asarray(f.cov, float)
    if not np.all(np.isfinite(cov)) or np.min(np.linalg.eigvalsh(cov)) <= 0:
        return ("the likelihood has no curvature at its maximum (flat, or its maximum at a "
                "limit: a dispersion going to 0 or a median beyond the data)")
    sd = np.sqrt(np.diag(cov))
    k = int(np.argmax(sd))
    if sd[k] > MAX_SD:
        z = norm.ppf(0.5 + CONFIDENCE / 2)
        return (f"the standard deviation of ln {('theta', 'beta')[k]} is {sd[k]:.3g}: its "
                f"{100 * CONFIDENCE:g} % bounds would span a factor of "
                f"{math.exp(min(2 * z * sd[k], 700.0)):.3g}")
    return ""


def checked(f: Fragility) -> Fragility:
    """``f``, or an absent fit (NaN) with the reason when the data do not fix it."""
    why = unfixed(f)
    if not why:
        return f
    return _absent(f.method, f"the data do not fix the fit: {why} (add runs or levels where "
                   "the limit is passed)")


def _numbers(name: str, values, where: str = "") -> np.ndarray:
    """A 1-D float array of finite numbers, or InputError naming the argument."""
    from pframe.errors import InputError

    try:
        out = np.asarray(values, dtype=float)
    except (TypeError, ValueError):
        raise InputError(f"{where}{name}: expected a list of numbers, got {values!r:.80}") \
            from None
    if out.ndim != 1 or out.size == 0:
        raise InputError(f"{where}{name}: expected a non-empty list of numbers (one per "
                         f"{'level' if 'level' in name else 'value'}), got shape {out.shape}")
    bad = np.flatnonzero(~np.isfinite(out))
    if bad.size:
        raise InputError(f"{where}{name}[{bad[0]}] is {out[bad[0]]}: expected a finite number")
    return out


def _same_length(**arrays) -> None:
    from pframe.errors import InputError

    sizes = {k: v.size for k, v in arrays.items()}
    if len(set(sizes.values())) > 1:
        raise InputError("expected one value per level (or run) in each of "
                         + ", ".join(f"{k} ({n})" for k, n in sizes.items()))


def _positive(name: str, values: np.ndarray, what: str) -> None:
    from pframe.errors import InputError

    bad = np.flatnonzero(values <= 0)
    if bad.size:
        raise InputError(f"{name}[{bad[0]}] is {values[bad[0]]:g}: {what} must be > 0 (the "
                         "lognormal fragility takes its logarithm)")


def _hessian(f, p: np.ndarray, h: float = 1e-4) -> np.ndarray:
    n = p.size
    out = np.empty((n, n))
    for i in range(n):
        for j in range(n):
            e_i, e_j = np.eye(n)[i] * h, np.eye(n)[j] * h
            out[i, j] = (f(p + e_i + e_j) - f(p + e_i - e_j) - f(p - e_i + e_j)
                         + f(p - e_i - e_j)) / (4 * h * h)
    return out


def _covariance(nll, p: np.ndarray, transform=None) -> np.ndarray:
    """Inverse observed information of ``nll`` at ``p``; ``transform(p) -> (J, value)`` maps
    the parameters to (ln theta, ln beta) (delta method)."""
    hess = _hessian(nll, p)
    try:
        cov = np.linalg.inv(hess)
    except np.linalg.LinAlgError:
        return np.full((2, 2), np.nan)
    if not np.all(np.isfinite(cov)) or np.any(np.diag(cov) < 0):
        return np.full((2, 2), np.nan)
    if transform is not None:
        jac = transform(p)
        cov = jac @ cov @ jac.T
    return cov


def _best(nll, starts) -> object:
    best = None
    for guess in starts:  # fatol relative to the likelihood's size: a sum over many runs
        res = minimize(nll, guess, method="Nelder-Mead",
                       options={"xatol": 1e-9, "fatol": 1e-12 * max(1.0, abs(nll(guess))),
                                "maxiter": 4000})
        if best is None or res.fun < best.fun:
            best = res
    return best


def fit_msa(levels, trials, exceeded) -> Fragility:
    """Baker's binomial MLE over stripes: ``trials[j]`` runs at ``levels[j]`` (> 0, g),
    ``exceeded[j]`` of them (0 to ``trials[j]``) exceed the limit. Absent (NaN, with the
    reason in ``note``) when the data cannot fix both parameters: fewer than two levels with
    runs, no exceedance at all, every level all or nothing (a perfect separation), none
    exceeding below a level and all above it (:func:`separated`: no finite maximum), or a
    likelihood too flat at its maximum (:func:`unfixed`). Raises
    :class:`~pframe.errors.InputError` for arguments that are not stripes."""
    from pframe.errors import InputError

    x = _numbers("levels", levels)
    n = _numbers("trials", trials)
    z = _numbers("exceeded", exceeded)
    _same_length(levels=x, trials=n, exceeded=z)
    _positive("levels", x, "an intensity level")
    for j in range(x.size):
        if not 0 <= z[j] <= n[j]:
            raise InputError(f"exceeded[{j}] is {z[j]:g} of trials[{j}] = {n[j]:g} runs: the "
                             "runs that exceed the limit are between 0 and the runs at the "
                             "level")
    return checked(msa_fit(x, n, z))


def msa_fit(x, n, z) -> Fragility:
    """:func:`fit_msa` on checked arrays, keeping a fit the data hardly fix (the gap at a
    target refits at every gap, where the likelihood's limits are meaningful)."""
    x, n, z = (np.asarray(a, float) for a in (x, n, z))
    keep = n > 0
    x, n, z = x[keep], n[keep], z[keep]
    if x.size < 2:
        return _absent("msa", "fewer than two intensity levels with runs")
    if z.sum() == 0:
        return _absent("msa", "no run exceeds the limit at any level")
    if np.all((z == 0) | (z == n)):
        return _absent("msa", "every level is all-or-nothing: the median lies between two "
                       "levels and the dispersion is not determined (add levels there)")
    if separated(np.log(x), n, z):
        return _absent("msa", SEPARATED)
    return _probit(np.log(x), n, z)


#: why a fit of data :func:`separated` is absent
SEPARATED = ("the data do not fix the fit: the likelihood has no interior maximum (no run "
             "exceeds the limit below one level and every run above it does: the median is at "
             "that level and the dispersion goes to 0; add levels around it)")


def separated(lx, n, z) -> np.ndarray:
    """Whether the binomial data (``z`` (L,) or (m, L) exceedances of the ``n`` runs at the
    levels ``lx``) are separated along the intensity: every level with a run that does not
    exceed lies at or below every level with one that does. Then the probit likelihood has no
    maximum at a finite slope (it rises towards c1 -> infinity, where the curve becomes a
    step at that level: quasi-complete separation, Albert & Anderson 1984), and a scoring
    stops wherever it grows too slowly to go on."""
    lx, n, z = np.asarray(lx, float), np.asarray(n, float), np.asarray(z, float)
    below = np.where((z < n) & (n > 0), lx, -np.inf).max(axis=-1)  # the highest non-exceedance
    above = np.where(z > 0, lx, np.inf).min(axis=-1)  # the lowest exceedance
    return below <= above


# The normal distribution's functions as scipy.stats.norm computes them (the same special
# functions, so the same bits), without its argument checks, which cost 30 times the work in
# the probit fit that a gap-at-target search repeats thousands of times.
def _cdf(x):
    return ndtr(x)


def _sf(x):
    return ndtr(-x)


def _pdf(x):
    return np.exp(-x**2 / 2.0) / _PDF_C


_PDF_C = np.sqrt(2 * np.pi)


def _loglik(c, lx, n, z) -> float:
    eta = c[0] + c[1] * lx
    return float(np.sum(z * log_ndtr(eta) + (n - z) * log_ndtr(-eta)))


def _probit(lx, n, z) -> Fragility:
    """Binomial probit regression P = Phi(c0 + c1 ln x) by Fisher scoring with step halving
    (each step solves a 2 x 2 system: fast enough to refit for every gap of a root search);
    theta = exp(-c0 / c1), beta = 1 / c1."""
    fractions = z / n
    mid = int(np.argmin(np.abs(fractions - 0.5)))
    beta0 = max(float(np.std(lx)), 0.3)
    c = np.array([-lx[mid] / beta0, 1.0 / beta0])
    design = np.stack([np.ones_like(lx), lx], axis=1)
    current = _loglik(c, lx, n, z)
    info = None
    for _ in range(200):
        eta = design @ c
        p = np.clip(_cdf(eta), 1e-300, 1 - 1e-16)
        q = np.clip(_sf(eta), 1e-300, 1 - 1e-16)
        phi = _pdf(eta)
        score = design.T @ ((z - n * p) * phi / (p * q))
        info = (design * (n * phi * phi / (p * q))[:, None]).T @ design
        try:
            step = np.linalg.solve(info, score)
        except np.linalg.LinAlgError:
            break
        scale = 1.0
        while scale > 1e-6:
            trial = c + scale * step
            value = _loglik(trial, lx, n, z)
            if value >= current - 1e-12:
                break
            scale *= 0.5
        c, moved = trial, abs(value - current)
        current = value
        if np.max(np.abs(scale * step)) < 1e-10 or moved < 1e-13:
            break
        if c[1] > 1e3:
            break
    if not (1e-2 < c[1] < 1e3) or not np.isfinite(current):
        return _absent("msa", "the likelihood has no interior maximum (the data separate "
                       "perfectly, or exceedance falls with the intensity)")
    eta = design @ c
    p = np.clip(_cdf(eta), 1e-300, 1 - 1e-16)
    q = np.clip(_sf(eta), 1e-300, 1 - 1e-16)
    phi = _pdf(eta)
    info = (design * (n * phi * phi / (p * q))[:, None]).T @ design
    try:
        cov_c = np.linalg.inv(info)
    except np.linalg.LinAlgError:
        cov_c = np.full((2, 2), np.nan)
    jac = np.array([[-1 / c[1], c[0] / c[1] ** 2], [0.0, -1 / c[1]]])
    return Fragility(math.exp(-c[0] / c[1]), float(1.0 / c[1]), jac @ cov_c @ jac.T, "msa")


#: |eta| beyond which :func:`probit_rows` takes log Phi(+-eta) from log_ndtr rather than the
#: log of Phi (which is then within 3e-7 of 0 or 1: its log would lose digits)
_FAR = 5.0

#: the last Newton step (in c) below which :func:`probit_rows` asks whether a row is settled:
#: the steps left move c by about its square (quadratic convergence), 1e-8 here
SETTLING = 1e-3

#: the steepest start :func:`probit_rows` takes (c1 = 1 / beta: a dispersion of 0.05): a
#: steeper fit is one the data nearly separate, whose likelihood is flat towards c1 -> inf,
#: and where its scoring stops then depends on where it starts
STEEP = 20.0


def probit_rows(lx, n, z, start=None, settled=None) -> tuple[np.ndarray, np.ndarray]:
    """:func:`_probit` for many rows of counts at once: ``z`` (m, L) exceedances of the
    ``n`` (L,) runs at the levels ``lx`` (L,, log); the same Fisher scoring with step halving,
    row by row in lockstep (the gap's curve fits one row per gap). Returns the coefficients
    ``c`` (m, 2) of P = Phi(c0 + c1 ln x) and whether each is an interior maximum (the rows
    :func:`_probit` would fit; the others it reports absent). ``start`` (m, 2): where finite
    with c1 > 0, the coefficients a row's scoring starts from instead of :func:`_probit`'s
    start (a fit of nearby counts: a bootstrap resample's from the whole sample's at the
    same gap). The log-likelihood is concave in c (log Phi is, Pratt 1981), so the scoring
    reaches the same maximum from any start, to its stopping tolerance (a step below 1e-10
    or a change of the log-likelihood below 1e-13): fewer steps, not another answer.
    ``settled(c)``: for rows of a warm start whose last Newton step was below
    :data:`SETTLING` (the steps left then move c by about its square), whether the caller
    has all it needs of them at ``c`` (a bootstrap resample's rate clearly on one side of
    the target): those stop there."""
    z = np.atleast_2d(np.asarray(z, float))
    m = z.shape[0]
    lost = n - z  # the runs that do not exceed

    def loglik(c, rows):
        """The log-likelihood of rows ``rows`` at ``c``, and Phi(eta), Phi(-eta) there
        (the next step's p and q when the step is taken)."""
        eta = c[:, :1] + c[:, 1:] * lx
        p, q = _cdf(eta), _sf(eta)
        with np.errstate(divide="ignore"):
            log_p, log_q = np.log(p), np.log(q)
        far = np.abs(eta) > _FAR  # where Phi is too near 0 or 1 for its log
        if far.any():
            log_p[far], log_q[far] = log_ndtr(eta[far]), log_ndtr(-eta[far])
        return np.sum(z[rows] * log_p + lost[rows] * log_q, axis=1), p, q

    mid = np.argmin(np.abs(z / n - 0.5), axis=1)
    beta0 = max(float(np.std(lx)), 0.3)
    c = np.stack([-lx[mid] / beta0, np.full(m, 1.0 / beta0)], axis=1)
    warm = np.zeros(m, bool)
    if start is not None:
        warm = np.isfinite(start).all(axis=1) & (start[:, 1] > 1e-2) & (start[:, 1] < STEEP)
        c[warm] = start[warm]
    current, at_p, at_q = loglik(c, np.arange(m))
    apart = separated(lx, n, z)  # no maximum to find: not scored, not fitted
    active = ~apart
    for _ in range(200):
        rows = np.flatnonzero(active)
        if not rows.size:
            break
        eta = c[rows, :1] + c[rows, 1:] * lx
        p = np.clip(at_p[rows], 1e-300, 1 - 1e-16)
        q = np.clip(at_q[rows], 1e-300, 1 - 1e-16)
        phi = _pdf(eta)
        zr, pq = z[rows], p * q
        w = (zr - n * p) * phi / pq
        score = np.stack([w.sum(axis=1), (w * lx).sum(axis=1)], axis=1)
        near = warm[rows]
        # the observed information (Newton's method) from a near start (fewer steps),
        # Fisher's expected one from the default start
        if near.all():
            ratio_p, ratio_q = phi / p, phi / q
            weight = zr * ratio_p * (eta + ratio_p) + lost[rows] * ratio_q * (ratio_q - eta)
        else:
            weight = n * phi * phi / pq
            if near.any():
                ratio_p, ratio_q, zn, e = phi[near] / p[near], phi[near] / q[near], zr[near], eta[near]
                weight[near] = zn * ratio_p * (e + ratio_p) + (n - zn) * ratio_q * (ratio_q - e)
        a, b, d = weight.sum(axis=1), (weight * lx).sum(axis=1), (weight * lx * lx).sum(axis=1)
        det = a * d - b * b
        solvable = np.isfinite(det) & (np.abs(det) > 1e-300)
        active[rows[~solvable]] = False  # a singular system: _probit stops there too
        rows, score, a, b, d, det = (v[solvable] for v in (rows, score, a, b, d, det))
        step = np.stack([d * score[:, 0] - b * score[:, 1],
                         a * score[:, 1] - b * score[:, 0]], axis=1) / det[:, None]
        scale = np.ones(rows.size)
        trial = c[rows] + step
        value, trial_p, trial_q = loglik(trial, rows)
        worse = value < current[rows] - 1e-12
        # from a warm start, a step already below the stopping tolerance is not halved: at
        # the maximum the log-likelihood's rounding can make any step look worse
        near = warm[rows]
        worse &= ~(near & (np.max(np.abs(step), axis=1) < 1e-10))
        while worse.any():  # halve the step of the rows it made worse, down to 1e-6
            scale[worse] *= 0.5
            worse &= scale > 1e-6
            worse &= ~near | (np.max(np.abs(scale[:, None] * step), axis=1) >= 1e-10)
            trial[worse] = c[rows[worse]] + scale[worse, None] * step[worse]
            value[worse], trial_p[worse], trial_q[worse] = loglik(trial[worse], rows[worse])
            worse &= value < current[rows] - 1e-12
        moved = np.abs(value - current[rows])
        c[rows], current[rows], at_p[rows], at_q[rows] = trial, value, trial_p, trial_q
        taken = np.max(np.abs(scale[:, None] * step), axis=1)
        done = (taken < 1e-10) | (moved < 1e-13) | (trial[:, 1] > 1e3)
        active[rows[done]] = False
        if settled is not None:
            ask = rows[~done & near & (taken < SETTLING)]
            if ask.size:
                active[ask[settled(c[ask])]] = False
    return c, (c[:, 1] > 1e-2) & (c[:, 1] < 1e3) & np.isfinite(current) & ~apart


def fit_capacities(capacities, censored=None) -> Fragility:
    """Lognormal MLE of IM capacities (IDA; > 0, g); ``censored[i]``: record i never exceeded
    the limit, its capacity is above ``capacities[i]`` (the highest IM run). Absent (NaN, with
    the reason) when the data do not fix it; :class:`~pframe.errors.InputError` for arguments
    that are not capacities."""
    c = _numbers("capacities", capacities)
    _positive("capacities", c, "a capacity")
    if censored is not None:
        flags = _numbers("censored", censored)
        _same_length(capacities=c, censored=flags)
        if not np.all((flags == 0) | (flags == 1)):
            from pframe.errors import InputError

            raise InputError("censored: expected true/false (or 1/0) per capacity")
    return checked(capacity_fit(c, censored))


def capacity_fit(capacities, censored=None) -> Fragility:
    """:func:`fit_capacities` on checked arrays, keeping a fit the data hardly fix."""
    c = np.asarray(capacities, float)
    cens = np.zeros(c.shape, bool) if censored is None else np.asarray(censored, bool)
    keep = np.isfinite(c) & (c > 0)
    c, cens = c[keep], cens[keep]
    if (~cens).sum() < 2:
        return _absent("ida", "fewer than two records reach the limit")
    lc = np.log(c)
    if np.ptp(lc[~cens]) < 1e-9 * max(1.0, float(np.max(np.abs(lc)))):
        return _absent("ida", "every record reaching the limit does so at the same IM (the "
                       "lowest run, or one level): the dispersion is not determined")

    exact, above = lc[~cens], lc[cens]

    def nll(p):  # scipy.special directly: norm.logpdf's checks cost 30 times the sum
        mu, log_beta = p
        inv = math.exp(-log_beta)
        t = (exact - mu) * inv
        return -(np.sum(-0.5 * t * t - _LOG_SQRT_2PI - log_beta)
                 + np.sum(log_ndtr((mu - above) * inv)))

    start = np.array([lc[~cens].mean(), math.log(max(lc[~cens].std(), 0.05))])
    if not cens.any() and lc.std() > 0:  # the closed form: the mean and sd of ln c
        best = type("Best", (), {"x": np.array([lc.mean(), math.log(lc.std())])})
    else:
        best = minimize(nll, start, method="Nelder-Mead",
                        options={"xatol": 1e-8, "fatol": 1e-12 * max(1.0, abs(nll(start))),
                                 "maxiter": 4000})
    return Fragility(math.exp(best.x[0]), math.exp(best.x[1]), _covariance(nll, best.x),
                     "ida")


@dataclasses.dataclass(frozen=True)
class Regression:
    """ln D = a + b ln IM + N(0, s^2), with the covariance of (a, b, ln s)."""

    a: float
    b: float
    s: float
    cov: np.ndarray
    note: str = ""  # why the regression is absent, when it is

    def fragility(self, limit: float, check: bool = True) -> Fragility:
        """P(D > limit | IM) as a lognormal fragility in IM (b > 0); absent (NaN, with the
        reason) when the data do not fix it (``check``)."""
        if self.note:
            return _absent("cloud", self.note)
        if not (self.b > 0 and math.isfinite(self.s)):
            return _absent("cloud", "the demand does not grow with the intensity (b <= 0)")
        ll = math.log(limit)
        p = np.array([self.a, self.b, math.log(self.s)])

        def jac(_):  # d(ln theta, ln beta) / d(a, b, ln s)
            lt = (ll - self.a) / self.b
            return np.array([[-1 / self.b, -lt / self.b, 0.0], [0.0, -1 / self.b, 1.0]])

        cov = jac(p) @ self.cov @ jac(p).T if np.all(np.isfinite(self.cov)) else \
            np.full((2, 2), np.nan)
        out = Fragility(math.exp((ll - self.a) / self.b), self.s / self.b, cov, "cloud")
        return checked(out) if check else out


def fit_cloud(intensities, demands, censor: float | None = None) -> Regression:
    """Maximum-likelihood regression of ln demand on ln IM (intensities > 0, demands >= 0; a
    demand of 0 has no logarithm and is left out); demands >= ``censor`` are right-censored
    there (their ln D is only known to be above ln censor). :class:`~pframe.errors.InputError`
    for arguments that are not such runs."""
    from pframe.errors import InputError

    im = _numbers("intensities", intensities)
    d = _numbers("demands", demands)
    _same_length(intensities=im, demands=d)
    _positive("intensities", im, "an intensity")
    if np.any(d < 0):
        k = int(np.argmax(d < 0))
        raise InputError(f"demands[{k}] is {d[k]:g}: a demand is >= 0")
    if censor is not None and not (math.isfinite(censor) and censor > 0):
        raise InputError(f"censor={censor!r}: the censoring demand is a number > 0")
    x = np.log(im)
    keep = d > 0
    x, d = x[keep], d[keep]
    cens = np.zeros(d.shape, bool) if censor is None else d >= censor
    y = np.log(np.where(cens, censor if censor else 1.0, d))
    if (~cens).sum() < 3:
        return Regression(math.nan, math.nan, math.nan, np.full((3, 3), np.nan),
                          f"{int((~cens).sum())} run(s) with a positive demand below the "
                          "censoring: the regression needs three or more")
    b0, a0 = np.polyfit(x[~cens], y[~cens], 1)
    s0 = max(float(np.std(y[~cens] - a0 - b0 * x[~cens])), 1e-3)

    def nll(p):
        a, b, log_s = p
        s = math.exp(log_s)
        t = (y - a - b * x) / s
        return -(np.sum(norm.logpdf(t[~cens]) - log_s) + np.sum(norm.logsf(t[cens])))

    if cens.any():
        p = _best(nll, (np.array([a0, b0, math.log(s0)]),)).x
    else:  # ordinary least squares is the MLE (its s divides by n)
        resid = y - a0 - b0 * x
        p = np.array([a0, b0, math.log(max(math.sqrt(np.mean(resid ** 2)), 1e-12))])
    hess = _hessian(nll, p)
    try:
        cov = np.linalg.inv(hess)
    except np.linalg.LinAlgError:
        cov = np.full((3, 3), np.nan)
    return Regression(float(p[0]), float(p[1]), math.exp(p[2]), cov)
