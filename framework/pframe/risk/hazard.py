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


def check_points(im, lam, where: str, label=lambda k: f"point {k + 1}"):
    """(IM, annual frequency) points as a hazard curve takes them: IMs finite and > 0, every
    frequency a finite number >= 0, not growing with the IM; zeros only at the top (past the
    model's reach: the curve ends at the last positive one). Returns them sorted by IM, the
    zeros dropped; InputError naming ``where`` and the point (``label(k)``) otherwise."""
    im, lam = np.asarray(im, float), np.asarray(lam, float)
    if im.ndim != 1 or im.shape != lam.shape or im.size < 2:
        raise InputError(f"{where}: a hazard curve needs at least two (IM, annual frequency) "
                         "points")
    for k in range(im.size):
        if not (math.isfinite(im[k]) and im[k] > 0):
            raise InputError(f"{where}, {label(k)}: the IM {im[k]:g} is not a number > 0 "
                             "(g; the curve is interpolated in log-log)")
        if not (math.isfinite(lam[k]) and lam[k] >= 0):
            raise InputError(f"{where}, {label(k)}: the annual frequency of exceedance "
                             f"{lam[k]:g} is not a number >= 0 (per year)")
    order = np.argsort(im, kind="stable")
    im, lam, rank = im[order], lam[order], order
    same = np.flatnonzero(np.diff(im) <= 0)
    if same.size:
        raise InputError(f"{where}, {label(rank[same[0] + 1])}: the IM {im[same[0]]:g} is given "
                         "twice")
    grows = np.flatnonzero(np.diff(lam) > 0)
    if grows.size:
        k = rank[grows[0] + 1]
        raise InputError(f"{where}, {label(k)}: the annual frequency of exceedance must not "
                         f"grow with the IM (it rises to {lam[grows[0] + 1]:g} at "
                         f"{im[grows[0] + 1]:g} g): is a column a probability of "
                         "non-exceedance, or are columns swapped?")
    keep = lam > 0  # zeros at the top only (the order holds): no logarithm, the curve ends
    if keep.sum() < 2:
        raise InputError(f"{where}: at least two annual frequencies must be > 0")
    return im[keep], lam[keep]


@dataclasses.dataclass(frozen=True)
class HazardCurve:
    """IM values (ascending, > 0) and their annual frequencies of exceedance (> 0; zeros at
    the top of a table, past the model's reach, end the curve)."""

    im: np.ndarray
    frequency: np.ndarray
    source: str = ""
    units: str = "g"

    def __post_init__(self):
        im, lam = check_points(self.im, self.frequency, self.source or "the hazard curve")
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
        if not (isinstance(frequency, (int, float, np.number)) and frequency > 0):
            raise InputError(f"{self.source or 'hazard curve'}: an annual frequency is a number "
                             f"> 0 (got {frequency!r})")
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


def _openquake(path: Path, lines: list[str], rows: list, poe: list[int]) -> HazardCurve:
    """OpenQuake's hazard_curve CSV: ``investigation_time=T`` in the first line, ``poe-IM``
    columns, one site's row of probabilities of exceedance in T years."""
    found = None
    for line in lines[:3]:
        found = found or re.search(r"investigation_time\s*=\s*'?([^,'\"\s]*)", line)
    if found is None:
        raise InputError(f"{path}: OpenQuake poe- columns but no investigation_time= in "
                         "the first line: the probabilities cannot become frequencies")
    try:
        investigation = float(found.group(1))
    except ValueError:
        investigation = math.nan
    if not (math.isfinite(investigation) and investigation > 0):
        raise InputError(f"{path}, line 1: investigation_time={found.group(1)!r} is not a "
                         "number of years > 0")
    (head_line, head), data = rows[0], rows[1:]
    if len(data) != 1:
        raise InputError(f"{path}: {len(data)} rows of probabilities under the header (line "
                         f"{head_line}); pframe reads one site's curve: keep that site's row")
    line, values = data[0]
    im = []
    for i in poe:
        x = _numbers([head[i][4:]])
        if x is None:
            raise InputError(f"{path}, line {head_line}, column {i + 1}: {head[i]!r} is not "
                             "poe- followed by an intensity (poe-0.1)")
        im.append(x[0])
    if len(values) != len(head):
        raise InputError(f"{path}, line {line}: {len(values)} values under {len(head)} "
                         "columns")
    p = []
    for i in poe:
        got = _numbers([values[i]])
        if got is None or not 0 <= got[0] < 1:
            raise InputError(f"{path}, line {line}, column {i + 1} ({head[i]}): "
                             f"{values[i]!r} is not a probability of exceedance in [0, 1)")
        p.append(got[0])
    lam = [-math.log1p(-q) / investigation for q in p]
    points = check_points(im, lam, str(path), lambda k: f"column {head[poe[k]]}")
    return HazardCurve(*points, source=str(path))


def read_hazard(path: str | Path) -> HazardCurve:
    """A hazard curve from a CSV table (see the module's docstring for the forms). Raises
    InputError naming the file and the line of anything malformed (a NaN or negative
    frequency, an IM that is not a number > 0, a frequency that grows with the IM)."""
    from pframe.yamltext import read_bounded

    path = Path(path)
    try:
        text = read_bounded(path, "hazard table")
    except FileNotFoundError:
        raise InputError(f"{path}: no such hazard table") from None
    lines = text.splitlines()
    rows = [(n, [c.strip() for c in r]) for n, r in (
        (n, next(csv.reader([ln]), [])) for n, ln in enumerate(lines, 1)
        if ln.strip() and not ln.lstrip().startswith("#")) if any(c.strip() for c in r)]
    expected = ("expected two columns (IM, annual frequency of exceedance), a row of IM "
                "values over a row of frequencies (USGS), or OpenQuake's poe-IM columns")
    if not rows:
        raise InputError(f"{path}: the hazard table is empty; {expected}")
    head = rows[0][1]
    poe = [i for i, h in enumerate(head) if h.lower().startswith("poe-")]
    if poe:
        return _openquake(path, lines, rows, poe)
    if len(head) == 2:  # two columns, with or without a header line
        # a header names the columns: a first row with a number in it is data
        skip = 1 if all(_numbers([c]) is None for c in head) else 0
        pairs, where = [], []
        for k, (n, r) in enumerate(rows[skip:]):
            got = _numbers(r) if len(r) == 2 else None
            if got is None:
                raise InputError(f"{path}, line {n}: data row {k + 1} ({', '.join(r)}) is not "
                                 f"two numbers; {expected}")
            pairs.append(got)
            where.append(n)
        arr = np.array(pairs, float).reshape(-1, 2)
        points = check_points(arr[:, 0], arr[:, 1], str(path),
                              lambda k: f"line {where[k]}" if k < len(where) else "")
        return HazardCurve(*points, source=str(path))
    if len(rows) == 2:  # a row of IMs over a row of frequencies, after site columns
        ims = [(i, float(h)) for i, h in enumerate(head) if _numbers([h]) is not None]
        line, second = rows[1]
        values = _numbers([second[i] for i, _ in ims]) if len(second) == len(head) else None
        if ims and values is not None:
            points = check_points([x for _, x in ims], values, str(path),
                                  lambda k: f"line {line}, column {ims[k][0] + 1}")
            return HazardCurve(*points, source=str(path))
    raise InputError(f"{path}: not a hazard table pframe reads; {expected}")


def mean_annual_frequency(probability, curve: HazardCurve, points: int = 4000) \
        -> tuple[float, float]:
    """(lambda_LS, the share of it from above the table) for a fragility ``probability(x)``
    (vectorised). The integral runs over the table's IM range on a log grid (midpoint rule
    in |d lambda|), plus P(x_max) lambda(x_max) for the intensities above the table."""
    if not isinstance(curve, HazardCurve):
        raise InputError(f"mean_annual_frequency: curve must be a HazardCurve (read_hazard, "
                         f"HazardCurve.power_law), got {type(curve).__name__}")
    if not (isinstance(points, (int, np.integer)) and points >= 2):
        raise InputError(f"mean_annual_frequency: points={points!r}: a whole number >= 2")
    x = np.geomspace(curve.im[0], curve.im[-1], points)
    lam = curve.rate(x)
    mid = np.sqrt(x[1:] * x[:-1])
    p = np.nan_to_num(np.asarray(probability(mid), float))
    inside = float(np.sum(p * (lam[:-1] - lam[1:])))
    above = float(np.nan_to_num(probability(np.array([x[-1]]))[0]) * lam[-1])
    total = inside + above
    return total, (above / total if total > 0 else 0.0)


def closed_form_maf(median: float, dispersion: float, k0: float, k: float) -> float:
    """Cornell et al. (2002): k0 theta^-k exp(k^2 beta^2 / 2); theta, k0, k > 0, beta >= 0."""
    for name, value, low in (("median", median, 0), ("k0", k0, 0), ("k", k, 0)):
        if not (isinstance(value, (int, float, np.number)) and math.isfinite(value)
                and value > low):
            raise InputError(f"closed_form_maf: {name}={value!r}: a number > 0")
    if not (isinstance(dispersion, (int, float, np.number)) and math.isfinite(dispersion)
            and dispersion >= 0):
        raise InputError(f"closed_form_maf: dispersion={dispersion!r}: a number >= 0")
    return k0 * median ** -k * math.exp(0.5 * k * k * dispersion * dispersion)


#: the design life (years) a limit state's probability is given over unless a study says
DESIGN_LIFE = 50.0


def probability_in_years(rate, years: float = DESIGN_LIFE):
    """The probability that a limit state of mean annual frequency ``rate`` (1/yr) happens at
    least once in ``years``: ``1 - exp(-rate years)``, its occurrences taken as a Poisson
    process (independent events at a constant mean rate; Cornell 1968, the assumption behind
    every "10 % in 50 years" of a hazard map). NaN where the rate is NaN. Monotone in the
    rate, so a range of rates maps to the range of probabilities."""
    if not (isinstance(years, (int, float, np.number)) and math.isfinite(years) and years > 0):
        raise InputError(f"probability_in_years: years={years!r}: a number > 0")
    rate = np.asarray(rate, float)
    if np.any(rate < 0):
        raise InputError("probability_in_years: an annual frequency is negative; rates are "
                         ">= 0 (per year)")
    return -np.expm1(-rate * float(years))
