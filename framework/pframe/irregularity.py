"""The torsional irregularity of a storey in plan from the peak drifts at its named points
(ASCE 7-22 Table 12.3-1), a pure function of the result's arrays."""

from __future__ import annotations

import numpy as np

#: ASCE 7-22 Table 12.3-1: a storey is torsionally irregular (type 1a) when its largest drift
#: at one end exceeds this many times the mean of the drifts at its two ends, extremely so
#: (type 1b) above the second
TORSIONAL_IRREGULARITY = (1.2, 1.4)


def torsional_irregularity(point_names, positions, peak_drift, floors) -> np.ndarray:
    """(floors, 2) the torsional irregularity ratio of the storey below each floor along its
    building's x and y axes: the larger of the peak drifts at the plan's two ends across the
    axis (the points of least and greatest y for drift along x, of x along y) over their mean
    (ASCE 7-22 Table 12.3-1, types 1a and 1b, with the peak drifts of the response history;
    on a rigid diaphragm the drift along an axis varies linearly across it, so its ends hold
    the extremes). NaN for a floor without named points, or whose storey does not drift.

    ``point_names`` '<floor>:<point>', ``positions`` (P, 2) each point in its building's axes
    (m), ``peak_drift`` (P, 2) its peak drift along those axes, ``floors`` the floor names."""
    out = np.full((len(floors), 2), np.nan)
    index = {name: i for i, name in enumerate(floors)}
    groups: dict[str, list[int]] = {}
    for p, name in enumerate(point_names):
        groups.setdefault(name.rsplit(":", 1)[0], []).append(p)
    positions, peak_drift = np.asarray(positions, float), np.asarray(peak_drift, float)
    for floor, points in groups.items():
        for axis in (0, 1):
            across = positions[points, 1 - axis]  # drift along x varies across y
            ends = [points[int(np.argmin(across))], points[int(np.argmax(across))]]
            if across.max() - across.min() <= 0.0:
                continue
            drifts = peak_drift[ends, axis]
            mean = 0.5 * float(drifts.sum())
            if mean > 0.0 and floor in index:
                out[index[floor], axis] = float(drifts.max()) / mean
    return out
