"""DOF numbering that keeps the effective stiffness narrow-banded (reverse Cuthill-McKee)."""

from __future__ import annotations

from collections import deque

import numpy as np


def reverse_cuthill_mckee(n: int, edges: list[tuple[int, int]]) -> np.ndarray:
    """A permutation ``order`` (new -> old) of ``n`` vertices joined by ``edges``."""
    neighbours: list[set[int]] = [set() for _ in range(n)]
    for i, j in edges:
        if i >= 0 and j >= 0 and i != j:
            neighbours[i].add(j)
            neighbours[j].add(i)
    degree = [len(s) for s in neighbours]
    seen = [False] * n
    order: list[int] = []
    for start in sorted(range(n), key=lambda v: (degree[v], v)):
        if seen[start]:
            continue
        seen[start] = True
        queue = deque([start])
        while queue:
            v = queue.popleft()
            order.append(v)
            for w in sorted(neighbours[v], key=lambda u: (degree[u], u)):
                if not seen[w]:
                    seen[w] = True
                    queue.append(w)
    return np.array(order[::-1], dtype=np.int64)


def bandwidth(edges: list[tuple[int, int]], position: np.ndarray) -> int:
    """Half-bandwidth of the matrix with these off-diagonal entries in the new numbering."""
    return max((abs(position[i] - position[j]) for i, j in edges if i >= 0 and j >= 0),
               default=0)


def place_last(order: np.ndarray, groups: dict[int, set[int]]) -> np.ndarray:
    """``order`` (new -> old) with each key of ``groups`` moved just after the last of its
    group's vertices: a vertex coupled to a whole group (a foundation's rocking DOF, coupled
    to every storey of its building) then widens the band by the group's span only."""
    rest = [int(v) for v in order if int(v) not in groups]
    for vertex, members in groups.items():
        last = max(rest.index(v) for v in members)
        rest.insert(last + 1, vertex)
    return np.array(rest, dtype=np.int64)
