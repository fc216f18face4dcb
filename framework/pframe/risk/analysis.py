"""From the runs of a study to fragilities, mean annual frequencies and the gap at a target
annual frequency (docs/risk.md)."""

from __future__ import annotations

import dataclasses
import math
import os

import numpy as np

from pframe.risk import fragility
from pframe.risk.fragility import Fragility, capacity_fit, fit_cloud, msa_fit, unfixed
from pframe.risk.gapcurve import GapCurve
from pframe.risk.hazard import HazardCurve, mean_annual_frequency

G = 9.80665
CONDITIONS = ("without_pounding", "with_pounding")


@dataclasses.dataclass
class Analysis:
    limit_names: list
    limit_kinds: list
    limit_values: list  # m, g, or the scene's gap for pounding
    im: np.ndarray  # (V,) the IM of every variant (g)
    fragilities: dict  # (limit, condition) -> Fragility
    maf: dict  # (limit, condition) -> (lambda, low, high, share above the table)
    target: float = math.nan
    im_at_target: float = math.nan
    gap: float = math.nan  # the gap at the target frequency (m)
    gap_low: float = math.nan
    gap_high: float = math.nan
    gap_regression: float = math.nan
    rules_at_target: dict = dataclasses.field(default_factory=dict)
    gap_grid: np.ndarray = None  # uniform gaps (m) and the annual frequency of pounding at each
    gap_rates: np.ndarray = None  # the envelope from the right of the refitted curve
    gap_rates_raw: np.ndarray = None  # the refitted curve itself
    warnings: list = dataclasses.field(default_factory=list)


def _variant_im(spec, inputs, rows=None) -> np.ndarray:
    if rows is not None and "ida_im" in rows:  # hunt and fill: each run's own level
        return rows["ida_im"]
    R, L = inputs.factors.shape
    if spec.design.kind == "cloud":
        return np.repeat(inputs.intensities, L)
    return np.tile(inputs.levels, R)


def _ratios(rows, prefix: str, kind: str, value: float, gap: float) -> np.ndarray | None:
    """demand / limit per variant (> 1 exceeds), or None without those runs."""
    if f"{prefix}_complete" not in rows:
        return None
    if kind == "pounding":
        if prefix == "contact":
            return np.where(rows["contact_impacts"].sum(axis=1) > 0, 2.0, 0.5)
        return np.max(rows["free_g_req"], axis=1) / rows.get("free_gap", gap)  # each run's
    if kind in ("drift", "drift_ratio"):
        return np.max(rows[f"{prefix}_{kind}"], axis=1) / value
    return np.max(rows[f"{prefix}_acceleration"], axis=1) / (value * G)


def fit(kind: str, im: np.ndarray, ratio: np.ndarray, ok: np.ndarray, levels, records: int,
        binary: bool = False, used: np.ndarray | None = None, checked: bool = True) -> Fragility:
    """The design's fragility of ``ratio > 1``: binomial over stripes (msa), capacities
    (ida: the IM where the ratio first passes 1, log-interpolated between the record's runs
    in order of IM), or the censored regression of ln ratio on ln IM (cloud; a binary
    outcome: probit over runs). ``used`` (ida by hunt and fill, runs record-major, each
    record's in order of IM): the slots run; there a failed run passes every limit.
    ``checked``: a fit the data do not fix is absent, with the reason
    (:func:`pframe.risk.fragility.unfixed`); the gap's curve keeps it (False)."""
    frag = _fit(kind, im, ratio, ok, levels, records, binary, used)
    return fragility.checked(frag) if checked else frag


def _fit(kind, im, ratio, ok, levels, records, binary, used) -> Fragility:
    exceed = (ratio > 1) & ok
    if kind == "msa" or (kind == "cloud" and binary):
        if kind == "msa":
            lv = np.asarray(levels)
            n = ok.reshape(records, -1).sum(axis=0)
            z = exceed.reshape(records, -1).sum(axis=0)
            return msa_fit(lv, n, z)
        return msa_fit(im[ok], np.ones(ok.sum()), exceed[ok].astype(float))
    if kind == "cloud":
        return fit_cloud(im[ok], ratio[ok]).fragility(1.0, check=False)
    ims = np.asarray(im, float).reshape(records, -1)
    r = np.log(np.maximum(ratio.reshape(records, -1), 1e-300))
    good = ok.reshape(records, -1)
    if used is None:  # a grid: a record with a failed run is left out
        keep = good.all(axis=1)
        used = np.ones_like(good)
    else:  # hunt and fill: slots not run are left out, a failed run passes the limit
        used = used.reshape(records, -1)
        keep = used.any(axis=1)
        r = np.where(good, r, np.inf)
    capacities, censored = [], []
    for k in np.flatnonzero(keep):
        lv = np.log(ims[k][used[k]])
        rk = r[k][used[k]]
        above = np.flatnonzero(rk > 0)
        if not above.size:
            capacities.append(math.exp(lv[-1]))
            censored.append(True)
            continue
        j = above[0]
        if j == 0 or binary or not np.isfinite(rk[j]):
            capacities.append(math.exp(lv[j]))
        else:  # ln ratio linear in ln IM between runs j-1 and j
            f = -rk[j - 1] / (rk[j] - rk[j - 1])
            capacities.append(math.exp(lv[j - 1] + f * (lv[j] - lv[j - 1])))
        censored.append(False)
    return capacity_fit(capacities, censored)


def _maf(frag: Fragility, hazard: HazardCurve, rng, draws: int = 200):
    if not frag.fitted or hazard is None:
        return (math.nan, math.nan, math.nan, math.nan)
    value, above = mean_annual_frequency(frag.probability, hazard)
    low = high = math.nan
    if np.all(np.isfinite(frag.cov)) and np.all(np.diag(frag.cov) < 4.0):
        mean = np.log([frag.median, frag.dispersion])
        samples = rng.multivariate_normal(mean, frag.cov, size=draws)
        values = [mean_annual_frequency(
            Fragility(math.exp(a), math.exp(b)).probability, hazard, points=800)[0]
            for a, b in samples]
        low, high = np.percentile(values, [5, 95])
    return (value, float(low), float(high), above)


def _gap_curve(kind, im, g_req, ok, levels, records, hazard, used=None,
               warm=None, near=None) -> GapCurve:
    """lambda(g) of pounding at a uniform gap g, the design's fit refitted at each g
    (:mod:`pframe.risk.gapcurve`: its envelope from the right and the largest crossing);
    ``warm``: the fits an msa curve computed at once starts from (:func:`_warm_fits`);
    ``near``: where its search expects the crossing (GapCurve's)."""
    known: dict = {}  # msa: lambda by the stripes' counts of pounding runs

    def rate(g):
        if kind != "msa":
            return rate_at(g)
        # an msa fit sees g only through how many runs of each stripe pound: lambda(g) is a
        # step function, and the curve meets each step many times (the same numbers)
        key = ((g_req / g > 1) & ok).reshape(records, -1).sum(axis=0).tobytes()
        if key not in known:
            known[key] = rate_at(g)
        return known[key]

    regression = fit_cloud(im[ok], np.maximum(g_req[ok], 0.0)) if kind == "cloud" else None

    def rate_at(g):
        if regression is not None:  # the cloud's regression of ln(g_req / g) on ln IM is
            # that of ln g_req shifted by -ln g: one fit serves every gap (and is monotone)
            frag = regression.fragility(g, check=False)
        else:
            frag = fit(kind, im, g_req / g, ok, levels, records, used=used, checked=False)
        if frag.fitted:
            return mean_annual_frequency(frag.probability, hazard, points=800)[0]
        exceed = (g_req > g) & ok
        if not exceed.any():
            return 0.0
        if kind == "msa":
            return _step_rate(exceed.reshape(records, -1).sum(axis=0),
                              ok.reshape(records, -1).sum(axis=0), levels, hazard)
        return math.nan

    many = None
    if kind == "msa":
        def many(grid, target=None):
            return _msa_rates(grid, g_req, ok, levels, records, hazard, target, warm)
    return GapCurve(rate, np.where(ok, g_req, np.nan), step=(kind == "msa"), many=many,
                    near=near)


#: fits whose integrals over the hazard are taken at once (the hazard's 800 points each)
RATE_ROWS = 4096


def _msa_rates(grid, g_req, ok, levels, records, hazard, target=None, warm=None) \
        -> np.ndarray:
    """lambda(g) of the msa fit at every gap of ``grid`` at once: the numbers of rate_at in
    :func:`_gap_curve` (the same fit, the same integral, its fallbacks), with the probit fits
    of the distinct count rows in one vectorised Fisher scoring (a curve of hundreds of
    gaps, and one per bootstrap resample). With ``target``, a fit whose integral's bounds
    (:func:`_sides`) leave no doubt on which side of it lambda lies has that bound in place
    of lambda: the numbers tell above or below the target, and nothing more. ``warm``: the
    fits the scoring starts from (:func:`_warm_fits`)."""
    from scipy.special import ndtr

    lv = np.asarray(levels, float)
    x = np.geomspace(hazard.im[0], hazard.im[-1], 800)
    lam = hazard.rate(x)
    middle, weight = np.log(np.sqrt(x[1:] * x[:-1])), lam[:-1] - lam[1:]
    sided = target is not None and bool(np.all(weight >= 0))

    def above_table(c):
        return np.nan_to_num(ndtr(c[:, 0] + c[:, 1] * math.log(x[-1]))) * lam[-1]

    def settled(c):  # rows whose side of the target no last step of the scoring can change
        return ~np.isnan(_sides(c, middle, weight, above_table(c), target, SETTLED)[0])

    rows, back, none, tried, c, good = _msa_fits(grid, g_req, ok, levels, records, warm,
                                                 settled if sided and warm is not None else None)
    fitted = np.zeros(len(rows), bool)
    out = np.where(none, 0.0, np.nan)
    if tried.size:
        c = c[good]
        above = above_table(c)
        inside = np.full(len(c), np.nan)
        todo = np.arange(len(c))
        if sided:
            inside, todo = _sides(c, middle, weight, above, target)
        inside[todo] = _integrals(c[todo], middle, weight)
        out[tried[good]] = inside + above
        fitted[tried[good]] = True
    n = ok.reshape(records, -1).sum(axis=0)
    for k in np.flatnonzero(~none & ~fitted):  # the likelihood's limit: a step (rate_at)
        out[k] = _step_rate(rows[k], n, lv, hazard)
    return out[back]


def _step_rate(z, n, levels, hazard) -> float:
    """lambda of msa stripes without a fit, as the likelihood's limit beta -> 0 takes them:
    a step in the intensity from none pounding to all, at the first level where a run pounds
    when some of its runs do not (separated stripes, pframe.risk.fragility.separated: the
    likelihood rises towards that step, the stripe's share at its level), between that level
    and the one below (at the lowest level when it is the first) when all its runs pound
    (all-or-nothing stripes: any step between them has the likelihood 1)."""
    lv = np.asarray(levels, float)
    first = int(np.argmax(np.asarray(z) > 0))
    step = (lv[first] if first == 0 or z[first] < n[first]
            else math.sqrt(lv[first - 1] * lv[first]))
    value = float(hazard.rate(step))
    return value if math.isfinite(value) else math.nan


#: the relative margin by which a bootstrap resample's rate must clear the target, on the
#: bounds of :func:`_sides`, for its probit scoring to stop before its stopping tolerance
#: (:func:`pframe.risk.fragility.probit_rows`' ``settled``)
SETTLED = 1e-3


def _msa_fits(grid, g_req, ok, levels, records, warm=None, settled=None):
    """The probit fits of the msa curve at the gaps of ``grid``, one per distinct row of
    pounding counts: ``rows`` (k, L) those counts, ``back`` (len(grid),) each gap's row,
    ``none`` (k,) the rows where no run pounds, ``tried`` the rows fitted (two levels or more
    with runs, not all-or-nothing), ``c`` (len(tried), 2) their coefficients and ``good``
    which of them are interior maxima (:func:`pframe.risk.fragility.probit_rows`). ``warm``:
    (gaps, coefficients) of fits at those gaps (NaN where none) that the scoring of a row
    starts from, at the first gap of ``grid`` with that row; ``settled``: probit_rows'."""
    from pframe.risk.fragility import probit_rows

    lv = np.asarray(levels, float)
    n = ok.reshape(records, -1).sum(axis=0)
    counts = _pounding_counts(grid, g_req, ok, records)
    rows, back = _distinct(counts, np.asarray(grid, float))
    keep = n > 0
    nn, zz = n[keep].astype(float), rows[:, keep].astype(float)
    none = zz.sum(axis=1) == 0
    if keep.sum() < 2:
        return rows, back, none, np.empty(0, np.int64), np.empty((0, 2)), np.empty(0, bool)
    tried = np.flatnonzero(~none & ~np.all((zz == 0) | (zz == nn), axis=1))
    start = None
    if warm is not None and tried.size:
        first = np.empty(len(rows), np.int64)
        first[back[::-1]] = np.arange(back.size)[::-1]  # each row's first gap
        gaps, fits = warm
        at = np.asarray(grid, float)[first[tried]]
        where = np.minimum(np.searchsorted(gaps, at), max(gaps.size - 1, 0))
        start = np.full((tried.size, 2), np.nan)
        if gaps.size:
            hit = gaps[where] == at
            start[hit] = fits[where[hit]]
    c, good = probit_rows(np.log(lv[keep]), nn, zz[tried], start=start, settled=settled)
    return rows, back, none, tried, c, good


def _distinct(counts: np.ndarray, grid: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The distinct rows of ``counts`` (one per gap of ``grid``) and each gap's row. Over
    increasing gaps every count can only fall, so equal rows are neighbours: a comparison
    with the row before finds them, without np.unique's sort of the rows (each row's fit
    is its own, whatever rows are fitted beside it)."""
    if counts.shape[0] < 2 or not np.all(np.diff(grid) > 0):
        rows, back = np.unique(counts, axis=0, return_inverse=True)
        return rows, back.ravel()
    new = np.ones(counts.shape[0], bool)
    new[1:] = np.any(counts[1:] != counts[:-1], axis=1)
    return counts[new], np.cumsum(new) - 1


def _warm_fits(g_req, ok, levels, records) -> tuple[np.ndarray, np.ndarray]:
    """The msa fits of the whole sample at each of its distinct critical gaps: (gaps,
    coefficients (len(gaps), 2), NaN where there is no interior maximum). A bootstrap
    resample's critical gaps are among them, and its fit at a gap is near the whole
    sample's there: started from it, the scoring takes a few steps instead of a dozen."""
    grid = np.unique(g_req[ok & np.isfinite(g_req) & (g_req > 0)])
    rows, back, _, tried, c, good = _msa_fits(grid, g_req, ok, levels, records)
    by_row = np.full((len(rows), 2), np.nan)
    by_row[tried[good]] = c[good]
    return grid, by_row[back]


def _integrals(c, middle, weight) -> np.ndarray:
    """sum_k Phi(c0 + c1 middle_k) weight_k for each row of ``c`` (m, 2): the midpoint rule
    of :func:`pframe.risk.hazard.mean_annual_frequency` for many probit fits, each row's
    the same bits whatever rows are computed with it."""
    from scipy.special import ndtr

    inside = np.empty(len(c))
    for lo in range(0, len(c), RATE_ROWS):  # bounded memory: a block of rows at a time
        block = c[lo:lo + RATE_ROWS]
        eta = np.multiply(block[:, 1:], middle)
        eta += block[:, :1]
        ndtr(eta, out=eta)
        if not np.isfinite(block).all():  # finite coefficients give a finite Phi
            np.nan_to_num(eta, copy=False)
        eta *= weight  # not a matrix product: BLAS's sum for a row can depend on the rows
        # beside it, and a curve searched a block at a time must find the same numbers
        inside[lo:lo + RATE_ROWS] = eta.sum(axis=1)
    return inside


#: points of the midpoint rule in each block of :func:`_sides`'s bounds, coarse first (the
#: rows the coarse bounds decide, most of a resample's, take no finer ones)
SIDE_BLOCKS = (64, 16)


def _sides(c, middle, weight, above, target: float, margin: float = 1e-9) \
        -> tuple[np.ndarray, np.ndarray]:
    """Bounds of :func:`_integrals` from a point in each block of ``SIDE_BLOCKS`` points:
    with c1 > 0 (a fitted probit) Phi grows along the increasing ``middle``, so with weights
    >= 0 each block's sum lies between its weight times Phi at its first point and at the
    next block's first (the last block's: at its last point). Returns the integrals (the
    lower bound where even it puts lambda = integral + ``above`` above ``target``, the upper
    where even it puts lambda at or below; NaN elsewhere) and the rows left to integrate
    (those the finest bounds do not decide, and any without c1 > 0). The ``margin`` of 1e-9
    covers the rounding of both sums (a relative 1e-13 over 800 terms)."""
    from scipy.special import ndtr

    inside = np.full(len(c), np.nan)
    todo = np.flatnonzero(np.isfinite(c).all(axis=1) & (c[:, 1] > 0))
    for size in SIDE_BLOCKS:
        if not todo.size:
            break
        starts = np.arange(0, middle.size, size)
        w = np.add.reduceat(weight, starts)
        ct = c[todo]
        edges = ndtr(ct[:, :1] + ct[:, 1:] * middle[np.append(starts, middle.size - 1)])
        low, high = edges[:, :-1] @ w, edges[:, 1:] @ w
        over = (low + above[todo]) * (1 - margin) > target
        under = (high + above[todo]) * (1 + margin) <= target
        inside[todo[over]], inside[todo[under]] = low[over], high[under]
        todo = todo[~(over | under)]
    return inside, np.flatnonzero(np.isnan(inside))


def _pounding_counts(grid, g_req, ok, records) -> np.ndarray:
    """(len(grid), levels): how many runs of each stripe pound at each gap g of ``grid``,
    ``g_req / g > 1`` counted over the runs that count (``ok``), as the fit at one gap
    counts them: by sorting each stripe's critical gaps once, not a pass over the runs per
    gap. The test is monotone in g_req (a rounded division is), so the runs that pound at g
    are those after the first whose ratio exceeds 1: past the last g_req <= g, and past the
    few just above g whose ratio rounds to 1."""
    grid = np.asarray(grid, float)
    by_stripe = np.where(ok, g_req, np.nan).reshape(records, -1)
    out = np.empty((grid.size, by_stripe.shape[1]), dtype=np.int64)
    for j in range(by_stripe.shape[1]):
        column = by_stripe[:, j]
        values = np.sort(column[~np.isnan(column)])
        first = np.searchsorted(values, grid, side="right")
        ahead = np.flatnonzero(first < values.size)
        while ahead.size:  # a ratio that rounds to 1 does not pound
            stays = values[first[ahead]] / grid[ahead] <= 1
            ahead = ahead[stays]
            first[ahead] += 1
            ahead = ahead[first[ahead] < values.size]
        out[:, j] = values.size - first
    return out


def _hunt_censoring(out, spec, rows, name, cond, prefix, ratio, R) -> None:
    """IDA by hunt and fill stops each record at its capacity for the hunted limit: another
    limit a record has not passed by then is censored there (below the top level), which
    the censored fit takes but the data then say little above it."""
    design = spec.design
    hunted = design.condition or ("with_pounding" if spec.pounding_runs else
                                  "without_pounding")
    if (name, cond) == (design.limit, hunted):
        return
    complete = rows[f"{prefix}_complete"]
    runs = complete.reshape(R, -1) >= 0
    passed = ((ratio > 1) | (complete == 0)).reshape(R, -1) & runs
    top = np.nanmax(np.where(runs, rows["ida_im"].reshape(R, -1), np.nan), axis=1)
    early = int(np.sum(~passed.any(axis=1) & (top < design.max_level)))
    if early:
        out.warnings.append(
            f"{name} ({cond.replace('_', ' ')}): {early} of {R} records stop (at their "
            f"{design.limit} capacity) before passing it and are right-censored there: the "
            "fit is censored, but hunt that limit (design.limit) for its capacities")


def analyse(spec, inputs, rows, hazard: HazardCurve | None, threads: int | None = None) \
        -> Analysis:
    """The fragilities, mean annual frequencies and gap at target of a study's runs; the
    gap's bootstrap resamples in ``threads`` processes (default: one per CPU)."""
    rng = np.random.default_rng(spec.seed)
    kind = spec.design.kind
    R, L = inputs.factors.shape
    im = _variant_im(spec, inputs, rows)
    hunted = "ida_im" in rows
    gaps = np.asarray(inputs.pairs.gaps, float)
    gap = float(gaps.min())
    names = ["pounding", *spec.limits.drift, *spec.limits.drift_ratio,
             *spec.limits.acceleration]
    kinds = (["pounding"] + ["drift"] * len(spec.limits.drift)
             + ["drift_ratio"] * len(spec.limits.drift_ratio)
             + ["acceleration"] * len(spec.limits.acceleration))
    values = [gap, *spec.limits.drift.values(), *spec.limits.drift_ratio.values(),
              *spec.limits.acceleration.values()]
    out = Analysis(names, kinds, values, im, {}, {})
    failed = {p: (rows[f"{p}_complete"] == 0) for p in ("free", "contact")
              if f"{p}_complete" in rows}
    for p, bad in failed.items():
        if bad.any():
            out.warnings.append(f"{int(bad.sum())} runs {'with' if p == 'contact' else 'without'}"
                                " contacts failed and are " + (
                                    "counted as passing every limit (collapse or "
                                    "non-convergence, as IDA takes them)" if hunted else
                                    "left out of the fits"))
    for name, k, value in zip(names, kinds, values):
        for cond, prefix in zip(CONDITIONS, ("free", "contact")):
            ratio = _ratios(rows, prefix, k, value, gap)
            if ratio is None:
                frag = Fragility(math.nan, math.nan, note="no runs with contacts "
                                 "(pounding_runs: false)")
            else:
                ok = rows[f"{prefix}_complete"] == 1
                frag = fit(kind, im, ratio, ok, inputs.levels, R,
                           binary=(k == "pounding" and prefix == "contact"),
                           used=(rows[f"{prefix}_complete"] >= 0) if hunted else None)
            if hunted and ratio is not None and frag.fitted:
                _hunt_censoring(out, spec, rows, name, cond, prefix, ratio, R)
            out.fragilities[(name, cond)] = frag
            if ratio is not None and not frag.fitted:
                out.warnings.append(f"{name} ({cond.replace('_', ' ')}): no fragility (NaN): "
                                    f"{frag.note}")
            out.maf[(name, cond)] = _maf(frag, hazard, rng)
            share = out.maf[(name, cond)][3]
            if share == share and share > 0.05:
                out.warnings.append(
                    f"{name} ({cond.replace('_', ' ')}): {share:.0%} of its mean annual "
                    "frequency comes from intensities above the hazard table's last value "
                    "(counted at the fragility there: a lower bound); extend the table")
            if hazard is not None and frag.fitted and frag.probability(hazard.im[0]) > 0.01:
                out.warnings.append(
                    f"{name} ({cond.replace('_', ' ')}): the fragility is "
                    f"{float(frag.probability(hazard.im[0])):.0%} at the hazard table's first "
                    "IM, so the frequency from lower intensities is missing (an underestimate);"
                    " extend the table down")
    if spec.target is not None and hazard is not None:
        _at_target(out, spec, inputs, rows, hazard, im, rng, threads)
    return out


def _at_target(out: Analysis, spec, inputs, rows, hazard: HazardCurve, im, rng,
               threads: int | None = None) -> None:
    """The gap at the target annual frequency of pounding (the largest crossing of the
    refitted curve, :mod:`pframe.risk.gapcurve`), its bootstrap interval, the regression's
    estimate and the code rules at the target's intensity."""
    kind = spec.design.kind
    R, L = inputs.factors.shape
    hunted = "ida_im" in rows
    target = (spec.target.annual_frequency if spec.target.annual_frequency is not None
              else 1.0 / spec.target.return_period)
    out.target = target
    out.im_at_target = hazard.intensity(target)
    g_req = np.max(rows["free_g_req"], axis=1)
    ok = rows["free_complete"] == 1
    used = (rows["free_complete"] >= 0) if hunted else None
    curve = _gap_curve(kind, im, g_req, ok, inputs.levels, R, hazard, used)
    g_req = np.where(ok, g_req, np.nan)  # failed or not run
    positive = g_req[ok & (g_req > 0)]
    if positive.size:
        out.gap_grid = np.geomspace(positive.min() * 0.5, positive.max(), 40)
        out.gap_rates = np.array([curve.envelope(g) for g in out.gap_grid])
        out.gap_rates_raw = np.array([curve.raw(g) for g in out.gap_grid])
    outside = _outside_table(hazard, target)
    if outside:
        out.warnings.append(outside + "; the gap at target is left out")
        _rules_at_target(out, kind, inputs, rows, im, ok, hunted, spec)
        return
    out.gap = curve.gap(target)
    _say_not_monotone(out, curve, target)
    reg = fit_cloud(im[ok], g_req[ok])
    out.gap_regression = GapCurve(lambda g: mean_annual_frequency(
        reg.fragility(g, check=False).probability, hazard, points=800)[0], g_req[ok], step=False).gap(target)
    if spec.bootstrap and kind != "cloud":
        picks = [rng.integers(0, R, R) for _ in range(spec.bootstrap)]
        found = np.array(_resampled_gaps((kind, im, g_req, ok, inputs.levels, R, hazard, used,
                                          target), picks, threads, near=out.gap))
        if np.isfinite(found).sum() >= 0.9 * len(found):
            out.gap_low, out.gap_high = (float(v) for v in np.nanpercentile(found, [5, 95]))
        else:
            out.warnings.append("the gap's bootstrap interval is left out: in more than a "
                                "tenth of the record resamples no gap reaches the target")
    if not math.isfinite(out.gap):
        out.warnings.append(
            f"no gap between the runs' critical gaps reaches the target annual frequency "
            f"{target:.3g} (too few levels near it, or a hazard table that does not cover "
            "the fragility); the gap at target is left out")
    else:
        _say_what_the_gap_rests_on(out, kind, im, g_req, ok, inputs.levels, R, hazard, used)
    _rules_at_target(out, kind, inputs, rows, im, ok, hunted, spec)


def _gaps_of(data, picks, near=None) -> list:
    """The gap at target of each resample of the records ``picks`` (record numbers, drawn
    with replacement); ``data``: (kind, im, g_req, ok, levels, records, hazard, used,
    target) of the study, and optionally the whole sample's fits (:func:`_warm_fits`) that
    an msa resample's fits start from; ``near``: the whole sample's gap, near which each
    resample's is expected (its search's blocks are sized by it, GapCurve's)."""
    kind, im, g_req, ok, levels, R, hazard, used, target = data[:9]
    warm = data[9] if len(data) > 9 else None
    L = im.size // R
    out = []
    for pick in picks:
        idx = (pick[:, None] * L + np.arange(L)[None, :]).ravel()
        out.append(_gap_curve(kind, im[idx], g_req[idx], ok[idx], levels, R, hazard,
                              None if used is None else used[idx], warm, near).gap(target))
    return out


def _resampled_gaps(data, picks: list, workers: int | None, near=None) -> list:
    """:func:`_gaps_of` shared among ``workers`` processes (default: one per CPU), each a
    contiguous share of the resamples; the numbers are those of one process, in order (each
    resample's work is its own). Processes, not threads: the fits are many small numpy
    operations, each too short to run while another thread holds the interpreter. One
    process where a process cannot be forked (not on this platform, or inside a daemonic
    worker, as a Dask worker's). An msa study's fits at its own critical gaps are computed
    once, here, for every resample's fits to start from."""
    import multiprocessing

    if data[0] == "msa" and len(data) == 9:
        data = (*data, _warm_fits(data[2], data[3], data[4], data[5]))
    workers = max(1, min(len(picks), workers or os.cpu_count() or 1))
    if (workers == 1 or "fork" not in multiprocessing.get_all_start_methods()
            or multiprocessing.current_process().daemon):
        return _gaps_of(data, picks, near)
    from concurrent.futures import ProcessPoolExecutor
    from functools import partial

    share = -(-len(picks) // workers)
    with ProcessPoolExecutor(workers, mp_context=multiprocessing.get_context("fork")) as pool:
        parts = pool.map(partial(_gaps_of, data, near=near),
                         [picks[lo:lo + share] for lo in range(0, len(picks), share)])
        return [value for part in parts for value in part]


def _outside_table(hazard: HazardCurve, target: float) -> str:
    """Why the hazard table cannot give the gap at ``target``, or ''."""
    low, high = float(hazard.frequency[-1]), float(hazard.frequency[0])
    if target < low:
        return (f"the target annual frequency {target:.3g} is below the hazard table's "
                f"smallest ({low:.3g} /yr at {hazard.im[-1]:.3g} g): the frequency of "
                "pounding there rests on intensities the table does not cover (counted at "
                "the fragility at its last IM, a lower bound that would give too small a "
                "gap); extend the table to intensities exceeded less often than the target")
    if target > high:
        return (f"the target annual frequency {target:.3g} is above the hazard table's "
                f"largest ({high:.3g} /yr at {hazard.im[0]:.3g} g): no gap pounds that often "
                "by the table; extend it down to intensities exceeded more often")
    return ""


def _say_not_monotone(out: Analysis, curve: GapCurve, target: float) -> None:
    rise = curve.rise()
    if rise is None:
        return
    g1, v1, g2, v2 = rise
    crossings = curve.crossings(target)
    several = (f"; the refitted curve crosses the target {len(crossings)} times (at "
               + ", ".join(f"{1000 * g:.1f}" for g in crossings) + " mm) and the gap at "
               "target is the largest crossing" if len(crossings) > 1 else "")
    out.warnings.append(
        "the annual frequency of pounding refitted at each gap is not monotone: it rises "
        f"from {v1:.3g} /yr at {1000 * g1:.1f} mm to {v2:.3g} /yr at {1000 * g2:.1f} mm "
        "(the fit's dispersion moves with the gap); pframe uses its upper envelope from the "
        "right (at each gap, the largest frequency of any wider gap: conservative)" + several)


def _say_what_the_gap_rests_on(out, kind, im, g_req, ok, levels, R, hazard, used) -> None:
    """Warnings when the fit at the gap found (just below it, where pounding is more frequent
    than the target) is one the data do not fix, or rests on intensities above the table."""
    below = out.gap * (1 - 1e-6)
    frag = fit(kind, im, g_req / below, ok, levels, R, used=used, checked=False)
    if not frag.fitted:
        out.warnings.append(
            f"the gap at target ({1000 * out.gap:.1f} mm) rests on stripes that are all or "
            "nothing there, or where none pounds below a level and all do above it (the "
            "likelihood's limit, a step in the intensity): add levels between the stripes "
            "where pounding starts")
        return
    why = unfixed(frag)
    if why:
        out.warnings.append(f"the gap at target ({1000 * out.gap:.1f} mm) rests on a fit the "
                            f"data do not fix ({why}): treat it as indicative; add records "
                            "or levels where pounding starts")
    share = mean_annual_frequency(frag.probability, hazard, points=800)[1]
    if share > 0.05:
        out.warnings.append(
            f"{share:.0%} of the frequency of pounding at the gap at target comes from "
            "intensities above the hazard table's last value (counted at the fragility there, "
            "a lower bound: the gap may be larger); extend the table")


def _interp_loglog(x: float, xs, ys) -> float:
    """y at x, linear in log-log between the points (exact for a power law: an elastic pair's
    displacements scale with the intensity); linear where a value is not positive; NaN
    outside the points or where they are not finite."""
    xs, ys = np.asarray(xs, float), np.asarray(ys, float)
    good = np.isfinite(xs) & np.isfinite(ys) & (xs > 0)
    xs, ys = xs[good], ys[good]
    if xs.size < 1 or not xs[0] <= x <= xs[-1]:
        return math.nan
    j = min(int(np.searchsorted(xs, x, side="right")), xs.size - 1)
    i = max(j - 1, 0)
    if xs[j] == xs[i]:
        return float(ys[j])
    if ys[i] > 0 and ys[j] > 0:
        f = math.log(x / xs[i]) / math.log(xs[j] / xs[i])
        return float(math.exp(math.log(ys[i]) + f * math.log(ys[j] / ys[i])))
    return float(np.interp(x, xs[i:j + 1], ys[i:j + 1]))


def _rules_at_target(out: Analysis, kind: str, inputs, rows, im, ok, hunted: bool,
                     spec) -> None:
    """The code rules (the study's ``codes``) and the simulated critical gap at the intensity
    of the target's frequency: median over the records, interpolated in log-log between
    levels (each record's runs in order of IM, then the median, for a hunt)."""
    if out.im_at_target != out.im_at_target or kind == "cloud":
        return
    R, L = inputs.factors.shape
    if getattr(spec, "codes", None):  # the codes' rules need the scene's floors (aligned?)
        from pframe.gap.audit import code_rules
        from pframe.gap.selection import rules_over_runs

        found, geometry, extra = code_rules(spec.codes, inputs)
        out.warnings.extend(extra)
        rules = rules_over_runs(inputs, found, geometry, rows["free_peak_left"],
                                rows["free_peak_right"])
    else:  # ABS, SRSS and DDC of the pair, its two buildings' first modes correlated
        from pframe.gap.rules import cqc_correlation, separations

        rho = cqc_correlation(inputs.periods[0], inputs.periods[-1], inputs.damping[0],
                              inputs.damping[-1])
        rules = separations(rows["free_peak_left"], rows["free_peak_right"], rho)
    rules["simulated"] = rows["free_g_req"]
    x = out.im_at_target
    for rule, v in rules.items():
        per_run = np.where(ok[:, None], v, np.nan).max(axis=1).reshape(R, L)
        if hunted:
            ims, good = im.reshape(R, L), ok.reshape(R, L)
            at = [_interp_loglog(x, ims[r][good[r]], per_run[r][good[r]])
                  for r in range(R) if good[r].sum() >= 2]
            if at and np.isfinite(at).any():
                out.rules_at_target[rule] = float(np.nanmedian(at))
            continue
        value = _interp_loglog(x, inputs.levels, np.nanmedian(per_run, axis=0))
        if math.isfinite(value):
            out.rules_at_target[rule] = value
    if not out.rules_at_target:
        out.warnings.append(f"the intensity at the target frequency ({x:.3g} g) is outside "
                            "the levels run: the code rules there are left out")
