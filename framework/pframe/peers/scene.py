"""A plain description of one scene for peer programs, free of pframe's own data structures.

``pframe.assemble.peer_scene(plan)`` fills it from an assembled plan (batch member 0); the
peer modules turn it into their own input.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np


@dataclass(frozen=True)
class PeerScene:
    """One scene in SI units, DOF ``i`` being node ``i``.

    Attributes
    ----------
    node_names : list of str
        ``"A/1"`` style names, one per DOF.
    masses : (n,) float, kg
    story_nodes : (s, 2) int
        ``[lower, upper]`` DOF of each storey; ``lower == -1`` is the ground.
    story_names : list of str
    story_materials : list of tuple
        ``("elastic", k)`` or ``("bilinear", k, fy, alpha)`` with k in N/m and fy in N
        (kinematic hardening, OpenSees Steel01 with b = alpha and no isotropic hardening), or
        ``("imk_peak", *packed)``: the law's 23 numbers, ModIMKPeakOriented's arguments.
    contact_nodes : (c, 2) int
        ``[left, right]`` DOF; penetration = u_left - u_right - gap.
    contact_names : list of str
    contact_gaps : (c,) float, m (>= 0)
    contact_stiffness : (c,) float, N/m (linear, compression only, no damping)
    rayleigh : list of tuple
        Per building ``(alpha_m, beta_k, node_dofs, story_indices)``: mass-proportional
        coefficient on the building's nodes, stiffness-proportional coefficient on the
        *initial* stiffness of its storeys.
    ground_acceleration : (steps + 1,) float, m/s^2 at t_n = n dt (relative formulation:
        load on DOF i is -m_i a_g(t)).
    dt : float, s
    steps : int
    tolerance : float
        Newton test NormDispIncr tolerance (m).
    max_iterations : int
    link_nodes : (l, 2) int
        ``[first, second]`` DOF of each link (-1: the ground); deformation u_second - u_first.
    link_materials : list of tuple
        ``("elastic", k)``, ``("bilinear", k, fy, alpha)``, ``("viscous", c, alpha)`` or
        ``("kelvin_voigt", k, c, alpha)``.
    modal : list of float, optional
        Modal damping instead of Rayleigh's: the ratio of each mode of the whole scene's
        storeys on their initial stiffness, in ascending frequency (OpenSees' ``eigen`` then
        ``modalDamping``); None: Rayleigh damping.
    integrator : tuple
        ``("newmark", gamma, beta)``, ``("hht", alpha, gamma, beta)`` with alpha the weight of
        the step's start (pframe's convention), ``("wilson_theta", theta)``, or
        ``("trbdf2",)``: Bathe's composite method with gamma = 1/2, whose two sub-steps are two
        analysis steps of OpenSees' TRBDF2. Each integrator says which it is (its
        coefficients' ``opensees``).
    """

    node_names: list
    masses: np.ndarray
    story_nodes: np.ndarray
    story_names: list
    story_materials: list
    contact_nodes: np.ndarray
    contact_names: list
    contact_gaps: np.ndarray
    contact_stiffness: np.ndarray
    rayleigh: list
    ground_acceleration: np.ndarray
    dt: float
    steps: int
    tolerance: float = 1e-12
    max_iterations: int = 50
    integrator: tuple = ("newmark", 0.5, 0.25)
    link_nodes: np.ndarray = None
    link_materials: list = None
    modal: list = None
