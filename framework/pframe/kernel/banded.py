"""Symmetric banded LDL^T factorisation and solve (no pivoting), compiled by numba.

The effective stiffness M / (beta dt^2) + gamma / (beta dt) C + K_T of a pounding scene is
symmetric and, with its mass term, positive definite; DOFs are numbered by reverse
Cuthill-McKee so that the half-bandwidth stays small (one building per row of floors: about
the number of buildings), and the cost per solve is O(n bw^2) instead of O(n^3).

Storage: ``band[i, d]`` holds K[i, i - d] for d = 0..bw (lower band, diagonal first).
"""

from __future__ import annotations

from pframe.kernel.cache import inline


@inline
def ldl_factor(band, bw):
    """Overwrite ``band`` with L (unit lower, off-diagonals) and D (diagonal); False if a
    pivot is not positive (the effective stiffness lost definiteness)."""
    n = band.shape[0]
    for j in range(n):
        d = band[j, 0]
        for k in range(max(0, j - bw), j):
            ljk = band[j, j - k]
            d -= ljk * ljk * band[k, 0]
        if not d > 0.0:
            return False
        band[j, 0] = d
        for i in range(j + 1, min(n, j + bw + 1)):
            s = band[i, i - j]
            for k in range(max(0, i - bw), j):
                s -= band[i, i - k] * band[j, j - k] * band[k, 0]
            band[i, i - j] = s / d
    return True


@inline
def ldl_solve(band, bw, x):
    """Solve in place with a factor from :func:`ldl_factor`."""
    n = band.shape[0]
    for i in range(n):
        s = x[i]
        for k in range(max(0, i - bw), i):
            s -= band[i, i - k] * x[k]
        x[i] = s
    for i in range(n):
        x[i] /= band[i, 0]
    for i in range(n - 1, -1, -1):
        s = x[i]
        for k in range(i + 1, min(n, i + bw + 1)):
            s -= band[k, k - i] * x[k]
        x[i] = s
