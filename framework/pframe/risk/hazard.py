"""Hazard curves and mean annual frequencies.

A hazard curve lambda_IM(x), the annual frequency with which the intensity measure exceeds x,
is read from a table in one of the forms hazard tools write:

- two columns, IM then annual frequency of exceedance (a header line is allowed; ``#``
  lines are comments): the USGS Unified Hazard Tool's "download" of one curve;
- one header row of IM values and one row of frequencies after any site columns
  (``lon,lat,0.005,0.007,...``): the USGS NSHMP hazard codes' curve files;
- OpenQuake's ``hazard_curve-*.csv``: a first comment line holding ``investigation_time=T``,
  then ``lon,lat,depth,poe-0.005,poe-0.007,...`` with probabilities of exceedance in T
  years, turned into frequencies by lambda = -ln(1 - poe) / T (Poisson).

Between points the curve is interpolated linearly in log-log; outside the table it is not
extrapolated (see :func:`mean_annual_frequency`).

The mean annual frequency of a limit state of fragility P(LS | x):

    lambda_LS = integral P(LS | x) |d lambda_IM(x)|

over the table's range, plus P(LS | x_max) lambda_IM(x_max) for the intensities above it
(a fragility grows with x, so this lower-bounds their share, which is reported).
For a lognormal fragility (theta, beta) and a power law lambda_IM = k0 x^-k the integral over
all x is k0 theta^-k exp(k^2 beta^2 / 2) (Cornell, Jalayer, Hamburger & Foutch 2002).
"""

from __future__ import annotations

import csv
import dataclasses
import math
import re
from pathlib import Path

import numpy as np

from pframe.errors import InputError


@dataclasses.dataclass(frozen=True)
class HazardCurve:
    """IM values (ascending, > 0) and their annual frequencies of exceedance (> 0)."""

    im: np.ndarray
    frequency: np.ndarray
    source: str = ""
    units: str = "g"

    def __post_init__(self):
        im, lam = np.asarray(self.im, float), np.asarray(self.frequency, float)
        where = self.source or "the hazard curve"
        if im.ndim != 1 or im.size < 2 or im.shape != lam.shape:
            raise InputError(f"{where}: a hazard curve needs at least two (IM, annual "
                             "frequency) points")
        keep = lam > 0  # a frequency of 0 (past the model's reach) has no logarithm
        im, lam = im[keep], lam[keep]
        if im.size < 2 or not (np.all(np.isfinite(im)) and np.all(im > 0)
                               and np.all(np.isfinite(lam))):
            raise InputError(f"{where}: IM values must be positive numbers and at least two "
                             "annual frequencies positive")
        order = np.argsort(im)
        im, lam = im[order], lam[order]
        if np.any(np.diff(im) <= 0) or np.any(np.diff(lam) > 0):
            raise InputError(f"{where}: the IM values must differ and the annual frequency of "
                             "exceedance must not grow with the IM (is a column a "
                             "probability of non-exceedance, or are columns swapped?)")
        object.__setattr__(self, "im", im)
        object.__setattr__(self, "frequency", lam)

    @classmethod
    def power_law(cls, k0: float, k: float, low: float = 1e-4, high: float = 1e2,
                  points: int = 400) -> HazardCurve:
        """lambda = k0 x^-k tabulated on a log grid (exact under log-log interpolation)."""
        x = np.geomspace(low, high, points)
        return cls(x, k0 * x ** -k, source=f"power law {k0:g} IM^-{k:g}")

    def rate(self, x):
        """lambda_IM(x), log-log interpolated; NaN outside the table."""
        x = np.asarray(x, float)
        with np.errstate(divide="ignore", invalid="ignore"):
            out = np.exp(np.interp(np.log(x), np.log(self.im), np.log(self.frequency),
                                   left=np.nan, right=np.nan))
        return out

    def intensity(self, frequency: float) -> float:
        """The IM exceeded with ``frequency`` per year (NaN outside the table)."""
        lf = np.log(self.frequency[::-1])
        lx = np.log(self.im[::-1])
        f = math.log(frequency)
        if f < lf[0] or f > lf[-1]:
            return math.nan
        return float(np.exp(np.interp(f, lf, lx)))


def _numbers(row) -> list[float] | None:
    try:
        return [float(v) for v in row]
    except ValueError:
        return None


def read_hazard(path: str | Path) -> HazardCurve:
    """A hazard curve from a CSV table (see the module's docstring for the forms)."""
    path = Path(path)
    try:
        text = path.read_text()
    except OSError as exc:
        raise InputError(f"{path}: cannot read the hazard curve ({exc.strerror or exc})") \
            from None
    lines = text.splitlines()
    investigation = None
    for line in lines[:3]:
        found = re.search(r"investigation_time\s*=\s*'?([0-9.eE+-]+)", line)
        if found:
            investigation = float(found.group(1))
    rows = [r for r in csv.reader(ln for ln in lines if ln.strip() and not ln.startswith("#"))
            if any(c.strip() for c in r)]
    rows = [[c.strip() for c in r] for r in rows]
    expected = ("expected two columns (IM, annual frequency of exceedance), a row of IM "
                "values over a row of frequencies (USGS), or OpenQuake's poe-IM columns")
    if not rows:
        raise InputError(f"{path}: the hazard table is empty; {expected}")
    head = rows[0]
    poe = [i for i, h in enumerate(head) if h.lower().startswith("poe-")]
    if poe:  # OpenQuake
        if investigation is None:
            raise InputError(f"{path}: OpenQuake poe- columns but no investigation_time= in "
                             "the first line: the probabilities cannot become frequencies")
        if len(rows) < 2:
            raise InputError(f"{path}: OpenQuake header without a row of values")
        im = [float(head[i][4:]) for i in poe]
        values = _numbers([rows[1][i] for i in poe])
        if values is None or any(not 0 <= p < 1 for p in values):
            raise InputError(f"{path}, line 2: probabilities of exceedance in [0, 1) expected")
        lam = [-math.log1p(-p) / investigation for p in values]
        return HazardCurve(np.array(im), np.array(lam), source=str(path))
    if len(head) == 2:  # two columns, with or without a header line
        skip = 0 if _numbers(head) is not None else 1
        pairs = []
        for k, r in enumerate(rows[skip:]):
            got = _numbers(r) if len(r) == 2 else None
            if got is None:
                raise InputError(f"{path}: data row {k + 1} ({', '.join(r)}) is not two "
                                 f"numbers; {expected}")
            pairs.append(got)
        arr = np.array(pairs).reshape(-1, 2)
        return HazardCurve(arr[:, 0], arr[:, 1], source=str(path))
    if len(rows) == 2:  # a row of IMs over a row of frequencies, after site columns
        ims = [(i, float(h)) for i, h in enumerate(head) if _numbers([h]) is not None]
        values = _numbers([rows[1][i] for i, _ in ims]) if len(rows[1]) == len(head) else None
        if ims and values is not None:
            return HazardCurve(np.array([x for _, x in ims]), np.array(values),
                               source=str(path))
    raise InputError(f"{path}: not a hazard table pframe reads; {expected}")


def mean_annual_frequency(probability, curve: HazardCurve, points: int = 4000) \
        -> tuple[float, float]:
    """(lambda_LS, the share of it from above the table) for a fragility ``probability(x)``
    (vectorised). The integral runs over the table's IM range on a log grid (midpoint rule
    in |d lambda|), plus P(x_max) lambda(x_max) for the intensities above the table."""
    x = np.geomspace(curve.im[0], curve.im[-1], points)
    lam = curve.rate(x)
    mid = np.sqrt(x[1:] * x[:-1])
    p = np.nan_to_num(np.asarray(probability(mid), float))
    inside = float(np.sum(p * (lam[:-1] - lam[1:])))
    above = float(np.nan_to_num(probability(np.array([x[-1]]))[0]) * lam[-1])
    total = inside + above
    return total, (above / total if total > 0 else 0.0)


def closed_form_maf(median: float, dispersion: float, k0: float, k: float) -> float:
    """Cornell et al. (2002): k0 theta^-k exp(k^2 beta^2 / 2)."""
    return k0 * median ** -k * math.exp(0.5 * k * k * dispersion * dispersion)
