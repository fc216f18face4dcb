"""Natural frequencies of a building in plan: its floors' translations and rotations coupled
by its lines of resistance (lateral-torsional modes; Chopra, Dynamics of Structures, ch. 9).

The stiffness is K = sum k a a^T over the building's storey springs, a the weights of a
spring's sides (pframe.model.elements), the mass diagonal (m, m and J of each floor)."""

from __future__ import annotations

import numpy as np

#: buildings of up to this many degrees of freedom are solved as a dense matrix; larger ones
#: by a sparse shift-invert solver for their lowest modes
DENSE_DOFS = 768


def stiffness_triplets(springs, k0, local: dict, building_springs) -> tuple[list, list, list]:
    """(rows, cols, values) of sum k a a^T over the springs ``building_springs`` (indices
    into ``springs``, with initial stiffness ``k0``), in the local numbering ``local`` of
    (node, component) keys; terms off the building (another building's floor) are left out."""
    rows, cols, values = [], [], []
    for s in building_springs:
        lower, upper = springs[s].side_terms()
        g = {}
        for sign, side in ((-1.0, lower), (1.0, upper)):
            for node, c, a in side:
                key = (node, c)
                if key in local:
                    g[local[key]] = g.get(local[key], 0.0) + sign * a
        items = list(g.items())
        for i, a in items:
            for j, b in items:
                rows.append(i)
                cols.append(j)
                values.append(k0[s] * a * b)
    return rows, cols, values


def lowest_frequencies(keys, masses, springs, k0, building_springs, count: int) -> np.ndarray:
    """The lowest ``count`` circular frequencies (rad/s) of the building whose degrees of
    freedom are ``keys`` ((node, component), masses ``masses``); all of them for a building
    of up to :data:`DENSE_DOFS` degrees of freedom."""
    local = {key: i for i, key in enumerate(keys)}
    n = len(keys)
    rows, cols, values = stiffness_triplets(springs, k0, local, building_springs)
    scale = 1.0 / np.sqrt(np.asarray(masses, dtype=float))
    if n <= DENSE_DOFS:
        K = np.zeros((n, n))
        np.add.at(K, (rows, cols), values)
        return np.sqrt(np.clip(np.linalg.eigvalsh(K * np.outer(scale, scale)), 0, None))
    from scipy.sparse import coo_matrix
    from scipy.sparse.linalg import eigsh

    K = coo_matrix((np.array(values) * scale[rows] * scale[cols], (rows, cols)),
                   shape=(n, n)).tocsc()
    found = eigsh(K, k=min(count, n - 1), sigma=0, which="LM", return_eigenvectors=False)
    return np.sqrt(np.clip(np.sort(found), 0, None))


def modes_and_shares(keys, masses, springs, k0, building_springs, count: int = 60):
    """Circular frequencies (rad/s, ascending) and the share of the building's mass each mode
    carries, both horizontal directions together: (p_x^2 + p_y^2) / (M_x + M_y) with p_d =
    phi^T M iota_d for phi normalised on the mass (the shares of all modes add up to 1); all
    modes up to :data:`DENSE_DOFS` degrees of freedom, else the lowest ``count``."""
    local = {key: i for i, key in enumerate(keys)}
    n = len(keys)
    masses = np.asarray(masses, dtype=float)
    rows, cols, values = stiffness_triplets(springs, k0, local, building_springs)
    root = np.sqrt(masses)
    scale = 1.0 / root
    if n <= DENSE_DOFS:
        K = np.zeros((n, n))
        np.add.at(K, (rows, cols), values)
        omega2, vectors = np.linalg.eigh(K * np.outer(scale, scale))
    else:
        from scipy.sparse import coo_matrix
        from scipy.sparse.linalg import eigsh

        K = coo_matrix((np.array(values) * scale[rows] * scale[cols], (rows, cols)),
                       shape=(n, n)).tocsc()
        omega2, vectors = eigsh(K, k=min(count, n - 1), sigma=0, which="LM")
        order = np.argsort(omega2)
        omega2, vectors = omega2[order], vectors[:, order]
    translation = np.array([[1.0 if c == d else 0.0 for _, c in keys] for d in (0, 1)])
    participation = (vectors.T @ (root * translation).T) ** 2  # (modes, 2)
    total = float(np.sum(masses * translation))
    return np.sqrt(np.clip(omega2, 0.0, None)), participation.sum(axis=1) / max(total, 1e-300)
