"""Soil under a building: frequency-independent sway and rocking springs and dashpots.

Wolf's cone model of a rigid disk on the surface of a homogeneous half-space (J. P. Wolf,
*Foundation Vibration Analysis Using Simple Physical Models*, Prentice Hall 1994, Table 2-3A;
docs/soil.md), with G = rho V_s^2:

- sway:    K_h = 8 G r_h / (2 - nu),          C_h = rho V_s pi r_h^2
- rocking: K_r = 8 G r_r^3 / (3 (1 - nu)),    C_r = rho V_p pi r_r^4 / 4

V_p = V_s sqrt(2 (1 - nu) / (1 - 2 nu)), replaced by 2 V_s for 1/3 < nu <= 1/2, where a
trapped soil mass moment of inertia Delta I = 0.3 pi (nu - 1/3) rho r_r^5 moves with the
foundation. A rectangular foundation of width b (along the shaking) and length l is the disk
of equal area for sway, r_h = sqrt(b l / pi), and of equal second moment of area about the
rocking axis for rocking, r_r = (l b^3 / (3 pi))^(1/4). Pure arithmetic: no pydantic, numpy.
"""

from __future__ import annotations

import math
from dataclasses import dataclass


@dataclass(frozen=True)
class Cone:
    """The cone model's springs, dashpots and trapped mass of one foundation (SI units)."""

    sway_stiffness: float      # K_h (N/m)
    sway_damping: float        # C_h (N s/m)
    rocking_stiffness: float   # K_r (N m/rad)
    rocking_damping: float     # C_r (N m s/rad)
    trapped_inertia: float     # Delta I (kg m^2), 0 for nu <= 1/3
    sway_radius: float         # r_h (m)
    rocking_radius: float      # r_r (m)
    p_wave_velocity: float     # the V_p of the rocking dashpot (m/s), capped at 2 V_s


def equivalent_radii(width: float, length: float) -> tuple[float, float]:
    """(r_h, r_r) of a rectangle b x l: equal area, and equal second moment l b^3 / 12 about
    the rocking axis (across the shaking) as pi r^4 / 4."""
    return math.sqrt(width * length / math.pi), (length * width**3 / (3.0 * math.pi)) ** 0.25


def cone(shear_wave_velocity: float, poisson: float, density: float, sway_radius: float,
         rocking_radius: float) -> Cone:
    """Wolf's cone springs and dashpots of a surface disk (radii r_h and r_r; equal for a
    circular foundation)."""
    vs, nu, rho = shear_wave_velocity, poisson, density
    g = rho * vs * vs
    if nu > 1.0 / 3.0:
        vp = 2.0 * vs
        trapped = 0.3 * math.pi * (nu - 1.0 / 3.0) * rho * rocking_radius**5
    else:
        vp = vs * math.sqrt(2.0 * (1.0 - nu) / (1.0 - 2.0 * nu))
        trapped = 0.0
    return Cone(
        sway_stiffness=8.0 * g * sway_radius / (2.0 - nu),
        sway_damping=rho * vs * math.pi * sway_radius**2,
        rocking_stiffness=8.0 * g * rocking_radius**3 / (3.0 * (1.0 - nu)),
        rocking_damping=rho * vp * math.pi * rocking_radius**4 / 4.0,
        trapped_inertia=trapped,
        sway_radius=sway_radius,
        rocking_radius=rocking_radius,
        p_wave_velocity=vp,
    )
