"""From the runs of a study to fragilities, mean annual frequencies and the gap at a target
annual frequency (docs/risk.md)."""

from __future__ import annotations

import dataclasses
import math

import numpy as np
from scipy.optimize import brentq

from pframe.risk.fragility import Fragility, fit_capacities, fit_cloud, fit_msa
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
    gap_rates: np.ndarray = None
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
        binary: bool = False, used: np.ndarray | None = None) -> Fragility:
    """The design's fragility of ``ratio > 1``: binomial over stripes (msa), capacities
    (ida: the IM where the ratio first passes 1, log-interpolated between the record's runs
    in order of IM), or the censored regression of ln ratio on ln IM (cloud; a binary
    outcome: probit over runs). ``used`` (ida by hunt and fill, runs record-major, each
    record's in order of IM): the slots run; there a failed run passes every limit."""
    exceed = (ratio > 1) & ok
    if kind == "msa" or (kind == "cloud" and binary):
        if kind == "msa":
            lv = np.asarray(levels)
            n = ok.reshape(records, -1).sum(axis=0)
            z = exceed.reshape(records, -1).sum(axis=0)
            return fit_msa(lv, n, z)
        return fit_msa(im[ok], np.ones(ok.sum()), exceed[ok].astype(float))
    if kind == "cloud":
        return fit_cloud(im[ok], ratio[ok]).fragility(1.0)
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
    return fit_capacities(capacities, censored)


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


def _gap_solver(kind, im, g_req, ok, levels, records, hazard, target, used=None):
    """lambda(g) of pounding at a uniform gap g, and the root of lambda(g) = target."""
    known: dict = {}  # msa: lambda by the stripes' counts of pounding runs

    def rate(g):
        if kind != "msa":
            return rate_at(g)
        # an msa fit sees g only through how many runs of each stripe pound: lambda(g) is a
        # step function, and a root search meets each step many times (the same numbers)
        key = ((g_req / g > 1) & ok).reshape(records, -1).sum(axis=0).tobytes()
        if key not in known:
            known[key] = rate_at(g)
        return known[key]

    def rate_at(g):
        frag = fit(kind, im, g_req / g, ok, levels, records, used=used)
        if frag.fitted:
            return mean_annual_frequency(frag.probability, hazard, points=800)[0]
        exceed = (g_req > g) & ok
        if not exceed.any():
            return 0.0
        if kind == "msa":  # all-or-nothing stripes: the likelihood's limit beta -> 0, a step
            # between the highest level where none pound and the lowest where all do
            z = exceed.reshape(records, -1).sum(axis=0)
            lv = np.asarray(levels, float)
            first = int(np.argmax(z > 0))
            step = lv[0] if first == 0 else math.sqrt(lv[first - 1] * lv[first])
            value = hazard.rate(step)
            return float(value) if np.isfinite(value) else math.nan
        return math.nan

    return rate, _root(rate, g_req[ok], target)


def _root(rate, g_values, target) -> float:
    g = np.sort(g_values[g_values > 0])
    if g.size < 2:
        return math.nan
    lo, hi = g[0] * 0.5, g[-1]
    f = lambda x: math.log(max(rate(x), 1e-300)) - math.log(target)  # noqa: E731
    grid = np.geomspace(lo, hi, 24)
    values = [f(x) for x in grid]
    for a, b, fa, fb in zip(grid[:-1], grid[1:], values[:-1], values[1:]):
        if math.isfinite(fa) and math.isfinite(fb) and fa > 0 >= fb:
            return float(brentq(f, a, b, xtol=1e-6 * a))
    return math.nan


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


def analyse(spec, inputs, rows, hazard: HazardCurve | None) -> Analysis:
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
    if spec.target is None or hazard is None:
        return out
    target = (spec.target.annual_frequency if spec.target.annual_frequency is not None
              else 1.0 / spec.target.return_period)
    out.target = target
    out.im_at_target = hazard.intensity(target)
    g_req = np.max(rows["free_g_req"], axis=1)
    ok = rows["free_complete"] == 1
    used = (rows["free_complete"] >= 0) if hunted else None
    rate, out.gap = _gap_solver(kind, im, g_req, ok, inputs.levels, R, hazard, target, used)
    g_req = np.where(ok, g_req, np.nan)  # failed or not run
    positive = g_req[ok & (g_req > 0)]
    if positive.size:
        out.gap_grid = np.geomspace(positive.min() * 0.5, positive.max(), 40)
        out.gap_rates = np.array([rate(g) for g in out.gap_grid])
    reg = fit_cloud(im[ok], g_req[ok])
    out.gap_regression = _root(lambda g: mean_annual_frequency(
        reg.fragility(g).probability, hazard, points=800)[0], g_req[ok], target)
    if spec.bootstrap and kind != "cloud":
        found = []
        for _ in range(spec.bootstrap):
            pick = rng.integers(0, R, R)
            idx = (pick[:, None] * L + np.arange(L)[None, :]).ravel()
            found.append(_gap_solver(kind, im[idx], g_req[idx], ok[idx], inputs.levels, R,
                                     hazard, target, None if used is None else used[idx])[1])
        found = np.array(found)
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
    # the code rules at the intensity of the target's frequency (median over the records,
    # interpolated in ln IM between levels)
    if kind != "cloud" and math.isfinite(out.im_at_target):
        from pframe.gap.audit import code_rules
        from pframe.gap.selection import rules_over_runs

        found, geometry, extra = code_rules(spec.codes, inputs)
        out.warnings.extend(extra)
        rules = rules_over_runs(inputs, found, geometry, rows["free_peak_left"],
                                rows["free_peak_right"])
        rules["simulated"] = rows["free_g_req"]
        for rule, v in rules.items():
            if hunted:  # each record's runs in order of IM, interpolated, then the median
                vr = np.where(ok[:, None], v, np.nan).max(axis=1).reshape(R, L)
                x = out.im_at_target
                at = [np.interp(x, im.reshape(R, L)[r][ok.reshape(R, L)[r]],
                                vr[r][ok.reshape(R, L)[r]], left=np.nan, right=np.nan)
                      for r in range(R) if ok.reshape(R, L)[r].sum() >= 2]
                if at and np.isfinite(at).any():
                    out.rules_at_target[rule] = float(np.nanmedian(at))
                continue
            per_level = np.nanmedian(np.where(ok[:, None], v, np.nan).max(axis=1)
                                     .reshape(R, L), axis=0)
            x = math.log(out.im_at_target)
            lv = np.log(inputs.levels)
            if lv[0] <= x <= lv[-1]:
                out.rules_at_target[rule] = float(np.interp(x, lv, per_level))
        if not out.rules_at_target:
            out.warnings.append(f"the intensity at the target frequency "
                                f"({out.im_at_target:.3g} g) is outside the levels run: the "
                                "code rules there are left out")

    return out
