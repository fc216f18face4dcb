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
    to every storey of its building) then widens the band by the group's span only.

    The keys are placed one after another in the dict's order, each just after the last of
    its members where the vertices stand by then (a member may be a key placed before it).
    Linear in the vertices: a position is (the place of a vertex that is no key, the slot in
    the keys placed just after it; 0 for the vertex itself), so no list is searched."""
    order = np.asarray(order, dtype=np.int64)
    keys = np.fromiter(groups, dtype=np.int64, count=len(groups))
    rest = order[~np.isin(order, keys)]
    place = np.full(int(max(order.max(initial=-1), keys.max(initial=-1))) + 1, -1,
                    dtype=np.int64)
    place[rest] = np.arange(len(rest))
    after: dict[int, list[int]] = {}  # place in rest -> the keys just after it, in order
    slot: dict[int, tuple[int, int]] = {}  # a key placed -> (place in rest, slot >= 1)
    for vertex, members in groups.items():
        members = np.fromiter(members, dtype=np.int64, count=len(members))
        placed = [slot[m] for m in members.tolist() if m in slot]
        plain = members[~np.isin(members, list(slot))]
        found = place[plain[plain < len(place)]] if plain.size else plain
        if not members.size or (plain.size and (found.size < plain.size or found.min() < 0)):
            raise ValueError(f"vertex {vertex}'s group names a vertex not in the order")
        anchor = max(placed + ([(int(found.max()), 0)] if plain.size else []))
        row = after.setdefault(anchor[0], [])
        row.insert(anchor[1], int(vertex))
        for s, key in enumerate(row):
            slot[key] = (anchor[0], s + 1)
    pieces, start = [], 0
    for at in sorted(after):
        pieces += [rest[start:at + 1], np.array(after[at], dtype=np.int64)]
        start = at + 1
    return np.concatenate(pieces + [rest[start:]])
