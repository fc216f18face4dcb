"""DOF numbering that keeps the effective stiffness narrow-banded (reverse Cuthill-McKee)."""

from __future__ import annotations

import numpy as np


def reverse_cuthill_mckee(n: int, edges) -> np.ndarray:
    """A permutation ``order`` (new -> old) of ``n`` vertices joined by ``edges`` (pairs;
    a negative vertex or a loop joins nothing): breadth-first from each unvisited vertex of
    least degree, each vertex's neighbours visited by degree then number, reversed."""
    pairs = _pairs(edges)
    pairs = pairs[pairs[:, 0] != pairs[:, 1]]
    # each vertex's neighbours once (both directions), sorted by vertex, degree, number
    joined = sorted_unique(np.concatenate([pairs[:, 0] * n + pairs[:, 1],
                                           pairs[:, 1] * n + pairs[:, 0]]))
    first, other = np.divmod(joined, max(n, 1))
    degree = np.bincount(first, minlength=n)
    by = np.lexsort((other, degree[other], first))
    neighbours = other[by].tolist()
    start_of = np.searchsorted(first[by], np.arange(n + 1)).tolist()
    seen = [False] * n
    order: list[int] = []  # the visited vertices, in the order they join the queue
    for start in np.lexsort((np.arange(n), degree)).tolist():
        if seen[start]:
            continue
        seen[start] = True
        order.append(start)
        head = len(order) - 1  # the queue: order[head:] (first in, first out)
        while head < len(order):
            v = order[head]
            head += 1
            for w in neighbours[start_of[v]:start_of[v + 1]]:
                if not seen[w]:
                    seen[w] = True
                    order.append(w)
    return np.array(order[::-1], dtype=np.int64)


def sorted_unique(values: np.ndarray) -> np.ndarray:
    """np.unique(values) of a 1-D array, by a sort: numpy's own takes a hash table for
    integers (numpy 2.3 on), many times slower on the 10^5 distinct keys of a tall scene."""
    values = np.sort(np.asarray(values).ravel())
    return values[np.concatenate([[True], values[1:] != values[:-1]])] if values.size else values


def _pairs(edges) -> np.ndarray:
    """(m, 2) the edges joining two vertices (a negative one, none: left out)."""
    pairs = np.asarray(edges, dtype=np.int64).reshape(-1, 2)
    return pairs[(pairs >= 0).all(axis=1)]


def bandwidth(edges, position: np.ndarray) -> int:
    """Half-bandwidth of the matrix with these off-diagonal entries in the new numbering."""
    pairs = _pairs(edges)
    if not len(pairs):
        return 0
    return int(np.max(np.abs(np.asarray(position)[pairs[:, 0]]
                             - np.asarray(position)[pairs[:, 1]])))


def place_last(order: np.ndarray, groups: dict[int, set[int]]) -> np.ndarray:
    """``order`` (new -> old) with each key of ``groups`` moved just after the last of its
    group's vertices: a vertex coupled to a whole group (a foundation's rocking DOF, coupled
    to every storey of its building) then widens the band by the group's span only."""
    rest = [int(v) for v in order if int(v) not in groups]
    for vertex, members in groups.items():
        last = max(rest.index(v) for v in members)
        rest.insert(last + 1, vertex)
    return np.array(rest, dtype=np.int64)
