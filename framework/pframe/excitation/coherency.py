"""Coherency of ground motion between supports, site transfer functions and wave passage: the
pieces of the cross-spectral density matrix of the motions at several supports
(docs/stochastic-motions.md#motions-at-several-supports).

The cross-spectral density of the accelerations at supports j and k is

    S_jk(w) = sqrt(S_jj(w) S_kk(w)) gamma_jk(w),
    gamma_jk(w) = |gamma(w, d_jk)| exp(-i w tau_jk) exp(i theta_jk(w)),

with |gamma| the lagged coherency (loss of coherence with distance d_jk and frequency), tau_jk
= tau_j - tau_k the difference of the waves' arrival times (wave passage) and theta_jk the
phase of H_j H_k^* when supports stand on soil columns with transfer functions H (Der
Kiureghian 1996, "A coherency model for spatially varying ground motions", EESD 25:99-111).
With the firm-ground spectrum S_g and S_jj = |H_j|^2 S_g this is

    S_jk(w) = S_g(w) H_j(w) H_k(w)^* |gamma(w, d_jk)| exp(-i w tau_jk).

Convention: X(w) = int x(t) exp(-i w t) dt, S_jk = E[X_j X_k^*] / T (so that a motion at k
that is the motion at j arriving tau later, x_k(t) = x_j(t - tau), has S_jk = S exp(+i w tau):
tau_jk = tau_j - tau_k = -tau). Frequencies w are in rad/s, distances in m, times in s.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np


@dataclass(frozen=True)
class LucoWong:
    """The lagged coherency of Luco & Wong (1986, "Response of a rigid foundation to a
    spatially random ground motion", EESD 14:891-908):

        |gamma(w, d)| = exp(-(alpha w d / v_s)^2),

    ``incoherence`` alpha (dimensionless; Luco & Wong's mu (r_e / R)^(1/2), of the order of
    0.1 to 0.5) and ``shear_velocity`` v_s (m/s) of the medium; only alpha / v_s counts (2e-4
    to 3e-4 s/m fit the SMART-1 array)."""

    incoherence: float
    shear_velocity: float

    def __post_init__(self):
        _check_positive("Luco-Wong coherency: incoherence", self.incoherence, zero=True)
        _check_positive("Luco-Wong coherency: shear_velocity", self.shear_velocity)

    def __call__(self, omega, distance) -> np.ndarray:
        """|gamma| at the frequencies ``omega`` (rad/s) and distances ``distance`` (m),
        broadcast together."""
        x = self.incoherence * np.asarray(omega, float) * np.asarray(distance, float)
        return np.exp(-(x / self.shear_velocity) ** 2)


@dataclass(frozen=True)
class HarichandranVanmarcke:
    """The lagged coherency of Harichandran & Vanmarcke (1986, "Stochastic variation of
    earthquake ground motion in space and time", J. Eng. Mech. 112(2):154-174):

        |gamma(w, d)| = A exp(-2 d (1 - A + alpha A) / (alpha theta(f)))
                        + (1 - A) exp(-2 d (1 - A + alpha A) / theta(f)),
        theta(f) = k (1 + (f / f0)^b)^(-1/2),      f = w / (2 pi),

    a sum of two exponentials in the distance d whose scale of fluctuation, theta(f), falls
    with frequency; |gamma| -> A exp(-2 d (1 - A + alpha A) / (alpha k)) + ... as f -> 0, below
    1 for d > 0. The defaults are the published fit to event 20 of the SMART-1 array (Lotung,
    Taiwan): A = 0.736, alpha = 0.147, k = 5210 m, f0 = 1.09 Hz, b = 2.78."""

    amplitude: float = 0.736  # A
    alpha: float = 0.147
    k: float = 5210.0  # m
    f0: float = 1.09  # Hz
    b: float = 2.78

    def __post_init__(self):
        if not 0.0 <= self.amplitude <= 1.0:
            raise ValueError(f"Harichandran-Vanmarcke coherency: amplitude A must be in [0, 1], "
                             f"got {self.amplitude!r}")
        for name in ("alpha", "k", "f0", "b"):
            _check_positive(f"Harichandran-Vanmarcke coherency: {name}", getattr(self, name))

    def __call__(self, omega, distance) -> np.ndarray:
        """|gamma| at the frequencies ``omega`` (rad/s) and distances ``distance`` (m),
        broadcast together."""
        f = np.abs(np.asarray(omega, float)) / (2.0 * math.pi)
        theta = self.k / np.sqrt(1.0 + (f / self.f0) ** self.b)
        a = self.amplitude
        scaled = 2.0 * np.asarray(distance, float) * (1.0 - a + self.alpha * a) / theta
        return a * np.exp(-scaled / self.alpha) + (1.0 - a) * np.exp(-scaled)


@dataclass(frozen=True)
class SoilColumn:
    """The transfer function H(w) from the firm-ground (rock) acceleration to the surface
    acceleration of a soil column of fundamental frequency ``frequency`` f_s (Hz) and damping
    ratio ``damping`` zeta_s:

    - ``kind="sdof"`` (Der Kiureghian 1996, the filter of Kanai-Tajimi):
      H = (w_s^2 + 2 i zeta_s w_s w) / (w_s^2 - w^2 + 2 i zeta_s w_s w), w_s = 2 pi f_s;
    - ``kind="layer"`` (a uniform damped layer on rigid rock, Kramer 1996, *Geotechnical
      Earthquake Engineering*, section 7.2.1): H = 1 / cos(w h / v_s*), v_s* = v_s
      sqrt(1 + 2 i zeta_s) (complex shear modulus G (1 + 2 i zeta_s)); with f_s = v_s / (4 h),
      w h / v_s* = (pi / 2) (w / w_s) / sqrt(1 + 2 i zeta_s). Its resonances are at the odd
      multiples of f_s. Damping independent of frequency (hysteretic, as in equivalent-linear
      site response) is not causal: a pulse through the layer has a small precursor (0.2 % of
      the response's peak at zeta_s = 0.1); the SDOF column is causal.

    Both are 1 at w = 0 (the static motion passes unchanged)."""

    frequency: float
    damping: float
    kind: str = "sdof"

    def __post_init__(self):
        _check_positive("soil column: frequency", self.frequency)
        _check_positive("soil column: damping", self.damping)
        if self.kind not in ("sdof", "layer"):
            raise ValueError(f"soil column: kind must be 'sdof' or 'layer', got {self.kind!r}")

    def __call__(self, omega) -> np.ndarray:
        """H at the frequencies ``omega`` (rad/s), complex."""
        w = np.asarray(omega, float)
        ws = 2.0 * math.pi * self.frequency
        if self.kind == "sdof":
            damping = 2j * self.damping * ws * w
            return (ws * ws + damping) / (ws * ws - w * w + damping)
        return 1.0 / np.cos(0.5 * math.pi * (w / ws) / np.sqrt(1.0 + 2j * self.damping))

    def decay_time(self) -> float:
        """The time (s) over which the column's free vibration decays by e^-1 (its slowest
        mode): 1 / (zeta_s w_s)."""
        return 1.0 / (self.damping * 2.0 * math.pi * self.frequency)


@dataclass(frozen=True)
class WavePassage:
    """A plane wave crossing the site at the apparent velocity ``velocity`` (m/s, > 0) in the
    direction ``direction`` (degrees from the site's x axis, counter-clockwise)."""

    velocity: float
    direction: float = 0.0

    def __post_init__(self):
        _check_positive("wave passage: apparent velocity", self.velocity)
        if not math.isfinite(self.direction):
            raise ValueError(f"wave passage: direction must be a finite angle in degrees, got "
                             f"{self.direction!r}")

    def arrivals(self, positions) -> np.ndarray:
        """When the wave reaches each of ``positions`` (n, 2) (s), relative to the site's
        origin: tau_s = (x_s, y_s) . (cos phi, sin phi) / v_app."""
        phi = math.radians(self.direction)
        return support_positions(positions) @ np.array([math.cos(phi), math.sin(phi)]) / self.velocity


def support_positions(positions) -> np.ndarray:
    """``positions`` as a float array (n, 2) of plan coordinates (m), checked."""
    p = np.asarray(positions, dtype=float)
    if p.ndim == 1 and p.size == 2:
        p = p[None, :]
    if p.ndim != 2 or p.shape[1] != 2 or p.shape[0] < 1:
        raise ValueError(f"support positions must be a list of (x, y) pairs in m, got an array "
                         f"of shape {p.shape}")
    if not np.all(np.isfinite(p)):
        raise ValueError("support positions must be finite numbers (m)")
    return p


def separations(positions) -> np.ndarray:
    """The distances d_jk (m) between the supports at ``positions`` (n, 2): (n, n)."""
    p = support_positions(positions)
    return np.hypot(p[:, None, 0] - p[None, :, 0], p[:, None, 1] - p[None, :, 1])


def site_transfers(omega, sites, count: int) -> np.ndarray:
    """H_j(w) of each of ``count`` supports (``sites``: one SoilColumn or None per support, or
    None for all on firm ground): complex (count, len(omega))."""
    omega = np.asarray(omega, float)
    out = np.ones((count, omega.size), dtype=complex)
    if sites is None:
        return out
    if len(sites) != count:
        raise ValueError(f"{len(sites)} site transfer functions for {count} supports: give one "
                         "per support (None for a support on firm ground)")
    for j, site in enumerate(sites):
        if site is not None:
            out[j] = site(omega)
    return out


def lagged_matrix(omega, positions, coherency, sites=None) -> np.ndarray:
    """The normalised cross-spectral matrix without wave passage,

        G_jk(w) = H_j(w) H_k(w)^* |gamma(w, d_jk)|,

    at each frequency: complex (len(omega), n, n), Hermitian and positive semi-definite
    (|gamma| of both models is a positive-definite function of the distance). S_jk = S_g
    G_jk exp(-i w tau_jk). ``coherency`` None: full coherence (|gamma| = 1)."""
    omega = np.atleast_1d(np.asarray(omega, float))
    d = separations(positions)
    n = d.shape[0]
    if coherency is None:
        modulus = np.ones((omega.size, n, n))
    else:
        modulus = np.asarray(coherency(omega[:, None, None], d[None, :, :]), float)
    h = site_transfers(omega, sites, n).T  # (F, n)
    return modulus * h[:, :, None] * np.conj(h[:, None, :])


def cholesky_lower(matrix, tolerance: float = 1e-12) -> np.ndarray:
    """The lower-triangular L with L L^* = ``matrix`` for a stack (F, n, n) of Hermitian
    positive semi-definite matrices: Cholesky, where a pivot at or below ``tolerance`` times
    its diagonal entry (a support fully coherent with earlier ones, or with no motion) gives a
    zero column instead of a division by zero. Dropping such a pivot changes the matrix by at
    most about sqrt(tolerance) of its diagonal."""
    a = np.asarray(matrix, dtype=complex)
    n = a.shape[-1]
    lower = np.zeros_like(a)
    for j in range(n):
        pivot = a[..., j, j].real - np.sum(np.abs(lower[..., j, :j]) ** 2, axis=-1)
        keep = pivot > tolerance * np.maximum(a[..., j, j].real, 0.0)
        root = np.sqrt(np.where(keep, pivot, 0.0))
        lower[..., j, j] = root
        safe = np.where(keep, root, 1.0)
        for i in range(j + 1, n):
            value = a[..., i, j] - np.sum(lower[..., i, :j] * np.conj(lower[..., j, :j]), axis=-1)
            lower[..., i, j] = np.where(keep, value / safe, 0.0)
    return lower


def _check_positive(name: str, value, zero: bool = False) -> None:
    ok = (isinstance(value, (int, float, np.floating, np.integer)) and not isinstance(value, bool)
          and math.isfinite(value) and (value >= 0 if zero else value > 0))
    if not ok:
        raise ValueError(f"{name} must be a finite number {'>= 0' if zero else '> 0'}, got "
                         f"{value!r}")
