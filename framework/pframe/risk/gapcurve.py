"""The annual frequency of pounding against a uniform gap, and the gap at a target frequency
(docs/risk.md, "The gap at the target").

A run pounds at the gap ``g`` exactly when its critical gap (the run without contacts) exceeds
``g``, so the fraction of runs that pound at each intensity can only fall as ``g`` grows, and
so must the annual frequency of pounding ``lambda(g)``. The design's fragility refitted at
each gap from those outcomes does not keep that order: its median and its dispersion move
together, and the integral over the hazard can rise from one gap to a wider one (a stripe
that loses a pounding run can widen the fitted dispersion, and a wider dispersion weighs the
frequent low intensities more). That refitted curve is kept as the *raw* estimate; the curve
used is its upper envelope from the right,

    lambda_env(g) = max over g' >= g of lambda_raw(g'),

the smallest non-increasing curve that is nowhere below the raw one: at every gap, the
frequency that any wider gap was estimated to pound with. Its root is the largest crossing
of the raw curve: every gap at or above the one reported pounds, by the raw estimate, no
more often than the target (conservative), and a non-monotone raw curve is reported.

With msa the raw curve is a step function of ``g`` (the fit sees ``g`` only through how many
runs of each stripe pound), constant between consecutive critical gaps: evaluated at each
distinct critical gap it is known exactly, and the envelope with it. IDA and cloud fits move
continuously with ``g``; their curve is evaluated on a log grid over the critical gaps (a
rise narrower than its spacing, about a tenth of the gap, can be missed there).
"""

from __future__ import annotations

import math

import numpy as np
from scipy.optimize import brentq

#: points of the log grid of an ida or cloud curve (between half the smallest critical gap
#: and the largest; the crossing is then refined by Brent's method)
GRID = 48
#: a curve computed at once is searched for the gap at a target from its widest gap down,
#: in blocks of SCAN gaps or a SCANS-th of its grid, whichever is more; above a gap it is
#: told the crossing is likely below (``near``), in blocks of WIDE gaps (the cost of a fit
#: falls with the rows fitted together, and all of those are needed)
SCAN, SCANS, WIDE = 512, 16, 4096


class GapCurve:
    """``lambda_raw(g)`` from ``rate_at(g)`` (the design's fit at the uniform gap ``g``,
    integrated over the hazard), its envelope from the right, and the largest crossing of a
    target. ``g_req``: the critical gaps of the runs that count (m); ``step``: the raw curve
    is constant between consecutive critical gaps (msa). ``many(grid)``: the numbers of
    ``rate_at`` at every gap of ``grid``, at once; ``many(grid, target)`` may put in place
    of a value any number on the same side of ``target`` (above, or at or below), which is
    all the search for the gap at ``target`` reads of a curve not otherwise used. ``near``:
    a gap near which the crossing is expected (a bootstrap resample's: the whole sample's
    gap), which sizes the search's blocks, not what it finds."""

    def __init__(self, rate_at, g_req: np.ndarray, step: bool, many=None,
                 near: float | None = None):
        self.rate_at, self.step, self.many, self.near = rate_at, step, many, near
        g = np.unique(g_req[np.isfinite(g_req) & (g_req > 0)])
        self.grid = g if step or g.size < 2 else np.geomspace(g[0] * 0.5, g[-1], GRID)
        self._values = self._right = None

    @property
    def values(self) -> np.ndarray:
        """lambda_raw at every gap of the grid (computed when first asked for)."""
        if self._values is None:  # ``many(grid)``: the numbers of rate_at, at once
            self._values = (np.asarray(self.many(self.grid), float) if self.many is not None
                            else np.array([self.raw(x) for x in self.grid], dtype=float))
        return self._values

    @property
    def right(self) -> np.ndarray:
        """The envelope at each grid point: the largest raw value at or to its right."""
        if self._right is None:
            finite = np.where(np.isfinite(self.values), self.values, -np.inf)
            self._right = np.maximum.accumulate(finite[::-1])[::-1]
        return self._right

    def raw(self, g: float) -> float:
        return float(self.rate_at(g))

    def envelope(self, g: float) -> float:
        """lambda_env(g): max(lambda_raw(g), the raw values at the grid's gaps above g)."""
        later = np.searchsorted(self.grid, g, side="right")
        best = self.right[later] if later < self.grid.size else -np.inf
        here = self.raw(g)
        out = max(best, here if math.isfinite(here) else -np.inf)
        return float(out) if out > -np.inf else math.nan

    def crossings(self, target: float) -> list[float]:
        """The grid's gaps where the raw curve passes from above the target to at or below it
        (going up in g): one for a monotone curve."""
        v = self.values
        keep = np.flatnonzero(np.isfinite(v))
        return [float(self.grid[b]) for a, b in zip(keep[:-1], keep[1:])
                if v[a] > target >= v[b]]

    def gap(self, target: float) -> float:
        """The smallest gap whose envelope is at or below ``target``: the largest crossing of
        the raw curve (NaN when no gap between the critical gaps reaches the target)."""
        if not self.grid.size:
            return math.nan
        i, later = self._last_above(target)
        if i < 0:  # every critical gap meets it: below the smallest, all runs pound
            low = self.raw(0.5 * self.grid[0])
            if not (math.isfinite(low) and low > target):
                return math.nan
            return float(self.grid[0]) if self.step else self._root(0.5 * self.grid[0],
                                                                     self.grid[0], target)
        if later < 0:
            return math.nan
        if self.step:  # constant on [grid[i], grid[i + 1]): the step is the root
            return float(self.grid[later])
        return self._root(self.grid[i], self.grid[later], target)

    def _last_above(self, target: float) -> tuple[int, int]:
        """The last grid point whose raw value is above ``target`` and the first after it
        with a value (-1 where there is none). A curve computed at once whose values are
        not known yet is computed from its widest gap down, a block at a time, only as far
        as that point (a bootstrap resample asks for nothing else: where the curve crosses
        the target, it is far from its widest gap)."""
        if self._values is None and self.many is not None:
            end, known = self.grid.size, np.empty(0)
            size = max(SCAN, -(-end // SCANS))
            wide = (int(np.searchsorted(self.grid, self.near)) if self.near is not None
                    and math.isfinite(self.near) else end)
            while end > 0:
                lo = max(wide, end - max(size, WIDE)) if end > wide else max(0, end - size)
                known = np.concatenate([np.asarray(self.many(self.grid[lo:end], target),
                                                   float), known])
                if self._last(known, target)[0] >= 0:
                    break
                end = lo
            i, later = self._last(known, target)
            return (lo + i if i >= 0 else -1), (lo + later if later >= 0 else -1)
        return self._last(self.values, target)

    @staticmethod
    def _last(values: np.ndarray, target: float) -> tuple[int, int]:
        above = np.flatnonzero(np.isfinite(values) & (values > target))
        if not above.size:
            return -1, -1
        i = int(above[-1])
        later = np.flatnonzero(np.isfinite(values[i + 1:]))
        return i, (i + 1 + int(later[0]) if later.size else -1)

    def _root(self, a: float, b: float, target: float) -> float:
        def f(x):
            value = self.raw(x)
            return math.log(max(value, 1e-300)) - math.log(target) if value == value else -1.0

        try:
            return float(brentq(f, a, b, xtol=1e-6 * a))
        except ValueError:  # a NaN end: the bracket's right end meets the target
            return float(b)

    def rise(self) -> tuple[float, float, float, float] | None:
        """Where the raw curve rises most with the gap, relative to its value: (g1, lambda1,
        g2, lambda2) with g1 < g2 and lambda1 < lambda2, or None for a non-increasing one."""
        v = self.values
        keep = np.flatnonzero(np.isfinite(v) & (v > 0))
        if keep.size < 2:
            return None
        later = np.maximum.accumulate(v[keep][::-1])[::-1]  # max at or right of each point
        ratio = later / v[keep]
        k = int(np.argmax(ratio))
        if ratio[k] <= 1 + 1e-6:  # below: the optimisers' own tolerance, not a rise
            return None
        j = keep[k:][int(np.argmax(v[keep[k:]]))]
        return (float(self.grid[keep[k]]), float(v[keep[k]]), float(self.grid[j]), float(v[j]))
