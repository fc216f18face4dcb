"""A contact's episodes in its recorded force history: the runs of samples with a positive
force (the impact table of :mod:`pframe.demands`, the impacts on struck columns the result
file keeps, :mod:`pframe.record.hdf5`)."""

from __future__ import annotations

import numpy as np


def positive_runs(f) -> list[tuple[int, int]]:
    """``(first, last)`` sample of each run of positive values of ``f``: a contact's episodes
    in its force history (an impact shorter than the recording stride is not seen)."""
    active = np.asarray(f) > 0.0
    if not active.any():
        return []
    edges = np.diff(active.astype(np.int8))
    starts = list(np.flatnonzero(edges == 1) + 1)
    ends = list(np.flatnonzero(edges == -1))
    if active[0]:
        starts.insert(0, 0)
    if active[-1]:
        ends.append(len(f) - 1)
    return list(zip(starts, ends))
