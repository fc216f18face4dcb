"""Velocity and displacement of a ground acceleration, and its baseline correction
(docs/stochastic-motions.md#velocities-and-displacements).

The integration is the trapezoid rule twice from rest, the relations of Newmark's average
acceleration method (gamma = 1/2, beta = 1/4) that pframe's kernel steps with:

    v_{n+1} = v_n + h (a_n + a_{n+1}) / 2,
    d_{n+1} = d_n + h (v_n + v_{n+1}) / 2  (= d_n + h v_n + h^2 (a_n + a_{n+1}) / 4),

so a support's displacement is the one the kernel's own integration of its acceleration gives.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np


def integrate(acceleration, step: float) -> tuple[np.ndarray, np.ndarray]:
    """(velocity, displacement) of ``acceleration`` (m/s^2 every ``step`` s, along the last
    axis) by the trapezoid rule twice from rest (module docstring): v_0 = d_0 = 0."""
    a = np.asarray(acceleration, dtype=float)
    h = float(step)
    zero = np.zeros(a.shape[:-1] + (1,))
    v = np.concatenate([zero, np.cumsum(0.5 * h * (a[..., 1:] + a[..., :-1]), axis=-1)], axis=-1)
    d = np.concatenate([zero, np.cumsum(0.5 * h * (v[..., 1:] + v[..., :-1]), axis=-1)], axis=-1)
    return v, d


@dataclass(frozen=True)
class BaselineCorrection:
    """A baseline-corrected motion: its ``acceleration``, ``velocity`` and ``displacement``
    (the trapezoid rule twice from rest of the corrected acceleration, as :func:`integrate`),
    the ``coefficients`` c_j of the polynomial a_c(t) = sum_j c_j t^j (m/s^(2+j)) removed from
    each row's acceleration, and ``description``: for each row, the correction in words."""

    acceleration: np.ndarray
    velocity: np.ndarray
    displacement: np.ndarray
    coefficients: np.ndarray
    description: tuple[str, ...]


def baseline_correct(acceleration, step: float, fit: str = "velocity",
                     degree: int = 1) -> BaselineCorrection:
    """Remove from ``acceleration`` (m/s^2 every ``step`` s; one row or rows along the last
    axis) the polynomial a_c(t) = c_0 + c_1 t + ... + c_p t^p (p = ``degree``) whose velocity
    v_c and displacement d_c (the trapezoid rule from rest, :func:`integrate`) fit, by least
    squares over all samples, the motion's velocity (``fit="velocity"``) or its displacement
    (``fit="displacement"``), or that bring it to rest (``fit="rest"``: final velocity and
    displacement 0 exactly, degree >= 1; with more than two coefficients, the least-norm ones
    of the scaled polynomial).

    Fitting a low-order polynomial to the velocity and removing its derivative from the
    acceleration is the usual baseline adjustment of strong-motion records (Boore & Bommer
    2005, "Processing of strong-motion accelerograms: needs, options and consequences", Soil
    Dyn. Earthq. Eng. 25:93-115); with ``degree`` 1 the velocity's baseline is a quadratic
    through zero at t = 0. Here the correction is built from rest (v_c(0) = d_c(0) = 0: the
    motion still starts at rest) and integrated by the same trapezoid rule, so the corrected
    acceleration, velocity and displacement keep the relations of :func:`integrate` exactly
    (to round-off): the displacement changes by d_c, not by an analytic t^(j+2) that the
    kernel's integration would not reproduce. Least squares leaves the corrected velocity (or
    displacement) orthogonal to every v_c (d_c) of the family: a drift of that form is
    removed exactly. A least-squares fit does not aim at the end: on a record already
    processed it may leave a larger final velocity or displacement than it had (the
    description says); ``rest`` is pframe's choice for motions whose end matters (a support's
    displacement that does not return to rest changes a gap between supports for good): the
    lowest-order polynomial from rest that ends the motion at rest."""
    a = np.asarray(acceleration, dtype=float)
    if fit not in ("velocity", "displacement", "rest"):
        raise ValueError(f"baseline fit must be 'velocity', 'displacement' or 'rest', got "
                         f"{fit!r}")
    lowest = 1 if fit == "rest" else 0
    if not (isinstance(degree, int) and lowest <= degree <= 5):
        raise ValueError(f"baseline degree must be a whole number from {lowest} to 5 for fit "
                         f"{fit!r}, got {degree!r}")
    if a.shape[-1] < degree + 3:
        raise ValueError(f"{a.shape[-1]} samples are too few for a baseline of degree {degree}")
    rows = a.reshape(-1, a.shape[-1])
    times = np.arange(a.shape[-1]) * float(step)
    span = times[-1]
    basis = np.array([(times / span) ** j for j in range(degree + 1)])  # scaled: well posed
    basis_v, basis_d = integrate(basis, step)
    v, d = integrate(rows, step)
    if fit == "rest":
        design = np.stack([basis_v[:, -1], basis_d[:, -1]], axis=1)  # (degree + 1, 2)
        target = np.stack([v[:, -1], d[:, -1]], axis=1)  # (rows, 2)
    else:
        design, target = (basis_v, v) if fit == "velocity" else (basis_d, d)
    scaled, *_ = np.linalg.lstsq(design.T, target.T, rcond=None)  # (degree + 1, rows)
    corrected = (rows - scaled.T @ basis, v - scaled.T @ basis_v, d - scaled.T @ basis_d)
    coefficients = scaled.T / span ** np.arange(degree + 1)
    words = tuple(_words(c, fit, row_v, row_d, new_v, new_d, row_a, new_a)
                  for c, row_v, row_d, new_v, new_d, row_a, new_a in zip(
                      coefficients, v, d, corrected[1], corrected[2], rows, corrected[0]))
    shape = a.shape
    return BaselineCorrection(corrected[0].reshape(shape), corrected[1].reshape(shape),
                              corrected[2].reshape(shape),
                              coefficients.reshape(shape[:-1] + (degree + 1,)), words)


def _words(coefficients, fit, v, d, new_v, new_d, a, new_a) -> str:
    terms = " + ".join(f"{c:.4g}" + ("" if j == 0 else " t" if j == 1 else f" t^{j}")
                       for j, c in enumerate(coefficients))
    peak = float(np.max(np.abs(a)))
    change = (float(np.max(np.abs(new_a))) - peak) / peak if peak > 0 else math.nan
    how = ("that brings the motion to rest at its end" if fit == "rest" else
           f"whose {fit} best fits the motion's (least squares)")
    return (f"baseline correction: removed a_c(t) = {terms} (m/s^2, t in s) from the "
            f"acceleration, the polynomial from rest {how}; final velocity {v[-1]:.4g} -> "
            f"{new_v[-1]:.4g} m/s, final displacement "
            f"{d[-1]:.4g} -> {new_d[-1]:.4g} m, peak displacement {np.max(np.abs(d)):.4g} -> "
            f"{np.max(np.abs(new_d)):.4g} m, peak acceleration changed by {100 * change:.2g} %")
