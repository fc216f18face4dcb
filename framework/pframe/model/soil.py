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


@dataclass(frozen=True)
class FoundationSoil:
    """A building's foundation on soil (docs/soil.md): its two DOFs' masses, the springs and
    dashpots to the ground, and where they came from."""

    building: int  # index into Expanded.buildings
    sway_stiffness: float  # K_h (N/m)
    sway_damping: float  # C_h (N s/m)
    rocking_stiffness: float  # K_r (N m/rad)
    rocking_damping: float  # C_r (N m s/rad)
    mass: float  # m_f (kg)
    rotational_inertia: float  # I_f (kg m^2), with the cone's trapped soil
    trapped_inertia: float = 0.0  # the cone's trapped soil (kg m^2), included above
    source: str = "given"  # "cone" (Wolf's cone model) or "given"

    def describe(self) -> str:
        """What was applied, in one line (the run summary, the result's attributes)."""
        trapped = (f" (with {self.trapped_inertia:.4g} kg m^2 of trapped soil)"
                   if self.trapped_inertia else "")
        how = "Wolf's cone model" if self.source == "cone" else "given"
        return (f"K_h = {self.sway_stiffness:.4g} N/m, C_h = {self.sway_damping:.4g} N s/m, "
                f"K_r = {self.rocking_stiffness:.4g} N m/rad, C_r = "
                f"{self.rocking_damping:.4g} N m s/rad ({how}); m_f = {self.mass:.4g} kg, "
                f"I_f = {self.rotational_inertia:.4g} kg m^2{trapped}")


def foundation_soil(soil, building: int) -> FoundationSoil:
    """The springs, dashpots and inertias of a scene's ``soil`` (pframe.model.scene.Soil)."""
    f = soil.foundation
    if f.radius is not None:
        r_h = r_r = f.radius
        slab = f.mass * f.radius**2 / 4.0
    elif f.width is not None:
        length = f.length if f.length is not None else f.width
        r_h, r_r = equivalent_radii(f.width, length)
        slab = f.mass * f.width**2 / 12.0
    else:
        slab = None
    inertia = f.rotational_inertia if f.rotational_inertia is not None else slab
    if soil.shear_wave_velocity is None:
        return FoundationSoil(building, soil.sway_stiffness, soil.sway_damping,
                              soil.rocking_stiffness, soil.rocking_damping, f.mass, inertia)
    c = cone(soil.shear_wave_velocity, soil.poisson, soil.density, r_h, r_r)
    return FoundationSoil(building, c.sway_stiffness, c.sway_damping, c.rocking_stiffness,
                          c.rocking_damping, f.mass, inertia + c.trapped_inertia,
                          c.trapped_inertia, "cone")
