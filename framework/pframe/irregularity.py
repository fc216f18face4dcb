"""The torsional irregularity of a storey in plan from the peak drifts at its named points
(ASCE 7-22 Table 12.3-1), a pure function of the result's arrays."""

from __future__ import annotations

import numpy as np

#: ASCE 7-22 Table 12.3-1: a storey is torsionally irregular (type 1a) when its largest drift
#: at one end exceeds this many times the mean of the drifts at its two ends, extremely so
#: (type 1b) above the second
TORSIONAL_IRREGULARITY = (1.2, 1.4)
#: a drift at most this fraction of a larger one of the same storey is round-off of it
ROUND_OFF = 1e-12
#: what a file's ``torsional_irregularity`` (node, axis) holds
LONG_NAME = ("torsional irregularity ratio of the storey below the floor (ASCE 7-22 Table "
             "12.3-1): the larger peak drift at the plan's two ends across the axis over the "
             "peak of their mean (the drift at the plan's centre point); inf for a storey that "
             "twists without translating; NaN where it does not drift along the axis (to "
             "round-off of its drift along the other); type 1a above 1.2, 1b above 1.4")


def torsional_irregularity(point_names, positions, peak_drift, floors) -> np.ndarray:
    """(floors, 2) the torsional irregularity ratio of the storey below each floor along its
    building's x and y axes: the larger of the peak drifts at the plan's two ends across the
    axis (the points of least and greatest y for drift along x, of x along y) over the peak of
    their mean, which on a rigid diaphragm is the drift at the middle between them (the
    floor's ``centre`` point, :data:`pframe.model.floors.CENTRE`). ASCE 7-22 Table 12.3-1
    (types 1a and 1b) compares the largest drift at an end with the mean of the drifts at the
    two ends under one load; in a response history the mean is taken at each instant, so a
    storey that twists without translating (its ends drift equal and opposite) has a ratio of
    inf, not the 1.0 that the mean of the two peaks would give. NaN for a floor without named
    points, or whose storey does not drift along the axis: not at all, or by round-off of its
    drift along the other (a symmetric storey shaken along x drifts along y by 1e-18 of x,
    whose ratio would be that of two round-off numbers).

    ``point_names`` '<floor>:<point>', ``positions`` (P, 2) each point in its building's axes
    (m), ``peak_drift`` (P, 2) its peak drift along those axes, ``floors`` the floor names."""
    from pframe.model.floors import CENTRE

    out = np.full((len(floors), 2), np.nan)
    index = {name: i for i, name in enumerate(floors)}
    groups: dict[str, list[int]] = {}
    centres: dict[str, int] = {}
    for p, name in enumerate(point_names):
        floor, label = name.rsplit(":", 1)
        if label == CENTRE:
            centres[floor] = p
        else:
            groups.setdefault(floor, []).append(p)
    positions, peak_drift = np.asarray(positions, float), np.asarray(peak_drift, float)
    for floor, points in groups.items():
        if floor not in index or floor not in centres:
            continue
        storey = float(np.max(peak_drift[points + [centres[floor]]]))
        for axis in (0, 1):
            across = positions[points, 1 - axis]  # drift along x varies across y
            if across.max() - across.min() <= 0.0:
                continue
            ends = [points[int(np.argmin(across))], points[int(np.argmax(across))]]
            largest = float(np.max(peak_drift[ends, axis]))
            middle = float(peak_drift[centres[floor], axis])
            if largest <= ROUND_OFF * storey:
                continue
            # the middle's drift is round-off of the ends' when the storey only twists
            out[index[floor], axis] = largest / middle if middle > ROUND_OFF * largest else np.inf
    return out
