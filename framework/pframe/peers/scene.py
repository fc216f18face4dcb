"""A plain description of one scene for peer programs, free of pframe's own data structures.

``pframe.peers.from_plan.peer_scene(plan)`` fills it from an assembled plan (batch member 0); the
peer modules turn it into their own input. A planar scene has one degree of freedom per
floor (DOF ``i`` is node ``i``); a scene in plan adds :class:`FloorsInPlan`: its floors are
rigid diaphragms and its elements act along a direction at points of them.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np


@dataclass(frozen=True)
class FloorsInPlan:
    """The floors of a scene in plan and where its elements act on them (site axes, m).

    A floor moves by (u_x, u_y, theta) of its centre of mass; its point P moves by
    (u_x - theta (P_y - c_y), u_y + theta (P_x - c_x)) (small rotations, docs/plan.md), so an
    element along the unit direction n at P sees a . (u_x, u_y, theta) with
    a = (n_x, n_y, (P - c) x n). Each element end is a point on the element's line of action;
    an end on the ground stands where the element's other end is.

    Attributes
    ----------
    names : list of str
        The floors (node ``f`` of the element arrays of :class:`PeerScene`).
    centres : (f, 2) float
        Each floor's centre of mass (m).
    masses : (f, 3) float
        m, m and the polar inertia J of each floor (kg, kg, kg m^2); 0 for a component
        the scene does not move.
    moves : (f, 3) bool
        The components (u_x, u_y, theta) the scene moves; the others stay at 0.
    dofs : (n, 2) int
        ``[floor, component]`` of each degree of freedom of the scene (the order of
        ``PeerScene.masses`` and of the histories).
    story_points, contact_points, link_points : (e, 2, 2) float
        The point ``[x, y]`` of each end of each storey (lower, upper), contact (left,
        right) and link (first, second).
    story_directions, contact_directions, link_directions : (e, 2) float
        The unit direction each element acts along (a contact's normal, from its left side
        to its right); (0, 0) for an element on the floors' rotations alone.
    story_levers, link_levers : (e,) float
        The lever r of an element on the floors' rotations alone (its deformation is
        r (theta_second - theta_first): P-delta's torsion), 0 for every other element (m).
    """

    names: list
    centres: np.ndarray
    masses: np.ndarray
    moves: np.ndarray
    dofs: np.ndarray
    story_points: np.ndarray
    story_directions: np.ndarray
    contact_points: np.ndarray
    contact_directions: np.ndarray
    link_points: np.ndarray
    link_directions: np.ndarray
    story_levers: np.ndarray = None
    link_levers: np.ndarray = None


@dataclass(frozen=True)
class Foundations:
    """The buildings on soil of a planar scene (docs/soil.md): each foundation sways (u_f) and
    rocks (theta) on springs and dashpots to the ground, and a storey of its building deforms
    by u_upper - u_lower - h theta.

    Attributes
    ----------
    sway, rocking : (F,) int
        The DOF of each foundation's sway and of its rocking (whose mass is the foundation's
        rotational inertia, kg m^2).
    sway_materials, rocking_materials : list of tuple
        The twins of its soil springs (:mod:`pframe.peers.twins`; N/m, N s/m and N m/rad,
        N m s/rad).
    story_foundation : (s,) int
        The foundation whose rocking each storey's lower side holds (-1: none).
    story_lever : (s,) float
        That lever h, the storey's height (m; 0: none).
    heights : (n,) float
        The height of each DOF's floor above its foundation (m; 0 for a rocking DOF and for
        a building on a fixed base).
    grounds : (F,) int, optional
        The support whose ground each foundation's soil springs stand on (None: the one
        ground).
    """

    sway: np.ndarray
    rocking: np.ndarray
    sway_materials: list
    rocking_materials: list
    story_foundation: np.ndarray
    story_lever: np.ndarray
    heights: np.ndarray
    grounds: np.ndarray = None


@dataclass(frozen=True)
class Supports:
    """The supports of a scene on several (docs/supports.md), which the script models in
    total coordinates: a ground node per support (in plan, per ground end), its motion imposed
    by OpenSees' ``MultipleSupport`` pattern (:mod:`pframe.peers.supports`). The element
    arrays of :class:`PeerScene` name support ``s``'s ground as node ``-1 - s``.

    Attributes
    ----------
    names : list of str
        The supports.
    channels : list of tuple
        ``(support, axis)`` of each row of the ground motion ('x' or 'y').
    displacement, velocity : (C, steps + 1) float
        Each channel's displacement (m) and velocity (m/s), the trapezoid rule twice from rest
        over its accelerations (``PeerScene.ground_acceleration``): pframe's own.
    dof_channel : (n,) int
        The channel each DOF's motion is relative to (-1: none, a rotation).
    dof_support : (n,) int
        The support each DOF is relative to (a rotation's: its node's).
    damping : (n,) float
        The mass-proportional damping coefficient of each DOF (N s/m, N m s/rad), which acts
        on its motion relative to its support: a dashpot from its support's ground, not
        OpenSees' Rayleigh mass term, which acts on total velocities.
    """

    names: list
    channels: list
    displacement: np.ndarray
    velocity: np.ndarray
    dof_channel: np.ndarray
    dof_support: np.ndarray
    damping: np.ndarray


@dataclass(frozen=True)
class PeerScene:
    """One scene in SI units, DOF ``i`` being node ``i`` (a planar scene) or the degree of
    freedom ``floors.dofs[i]`` of a floor (a scene in plan: ``floors`` given, and the nodes
    of the element arrays and of ``rayleigh`` are floors).

    Attributes
    ----------
    node_names : list of str
        ``"A/1"`` style names, one per DOF.
    masses : (n,) float, kg
    story_nodes : (s, 2) int
        ``[lower, upper]`` DOF of each storey; ``lower == -1`` is the ground (on supports,
        ``-1 - s`` is support s's ground).
    story_names : list of str
    story_materials : list of tuple
        Each storey's OpenSees twin (:mod:`pframe.peers.twins`): ``("elastic", k)``,
        ``("bilinear", k, fy, alpha)`` with k in N/m and fy in N (kinematic hardening, OpenSees
        Steel01 with b = alpha and no isotropic hardening), ``("imk_peak", *packed)`` (the
        law's 23 numbers, ModIMKPeakOriented's arguments), ``("bouc_wen", ...)``,
        ``("bwbn", ...)``, ``("viscous", c, alpha)``, ``("kelvin_voigt", k, c, alpha)`` or
        ``("coulomb_pendulum", k0, q_yield, k2)``.
    contact_nodes : (c, 2) int
        ``[left, right]`` DOF; penetration = u_left - u_right - gap.
    contact_names : list of str
    contact_gaps : (c,) float, m (>= 0)
    contact_materials : list of tuple
        Each contact's OpenSees twin (:mod:`pframe.peers.twins`): ``("linear", k)``
        (``ElasticPPGap``), ``("hertzdamp", k, xi_norm, n)``, ``("jankowski", beta, zeta,
        m_eff)`` or ``("bumper", k, chi, n, k_hard, crush_depth)``.
    rayleigh : list of tuple
        ``(alpha_m, beta_k, node_dofs, story_indices, stiffness)``: mass-proportional
        coefficient on the nodes, stiffness-proportional coefficient on the storeys' initial,
        current or committed stiffness (``stiffness``: ``"initial"``, ``"current"`` or
        ``"committed"``, OpenSees' ``betaKinit``, ``betaK``, ``betaKcomm``); one tuple per
        building and stiffness.
    story_geometric : (s,) float
        P-delta's geometric stiffness P / h of each storey (N/m, 0: none): the storey resists
        its material's force less (P / h) d, undamped.
    ground_acceleration : (steps + 1,) float, m/s^2 at t_n = n dt (relative formulation:
        load on DOF i is -m_i a_g(t)); a scene in plan or on supports: (len(channels),
        steps + 1), one row per site axis the motion loads (on supports, per support and
        axis).
    dt : float, s
    steps : int
    tolerance : float
        Newton test NormDispIncr tolerance (m).
    max_iterations : int
    link_nodes : (l, 2) int
        ``[first, second]`` DOF of each link (-1: the ground); deformation u_second - u_first.
    link_materials : list of tuple
        Each link's twin, as ``story_materials``.
    modal : list of float, optional
        Modal damping instead of Rayleigh's: the ratio of each mode of the whole scene's
        storeys on their initial stiffness, in ascending frequency (OpenSees' ``eigen`` then
        ``modalDamping``); None: Rayleigh damping.
    integrator : tuple
        ``("newmark", gamma, beta)``, ``("hht", alpha, gamma, beta)`` with alpha the weight of
        the step's start (pframe's convention), ``("generalized_alpha", alpha_m, alpha_f,
        gamma, beta)`` (Chung & Hulbert's weights of the step's start), ``("wilson_theta",
        theta)``, ``("trbdf2",)``: Bathe's composite method with gamma = 1/2, whose two
        sub-steps are two analysis steps of OpenSees' TRBDF2, or ``("central_difference",)``.
        Each integrator says which it is (its coefficients' ``opensees``).
    substeps : int
        Analysis steps per step of pframe's (central difference's sub-steps).
    channels : tuple of str
        The site's axes ('x', 'y') the rows of a scene in plan's ground motion load.
    floors : FloorsInPlan, optional
        The floors of a scene in plan (None: a planar scene).
    foundations : Foundations, optional
        The foundations of a planar scene's buildings on soil (None: fixed bases).
    differences : tuple of str
        Where the OpenSees model is not pframe's (empty: the same model).
    supports : Supports, optional
        The supports of a scene on several (None: one ground, the relative formulation).
    """

    node_names: list
    masses: np.ndarray
    story_nodes: np.ndarray
    story_names: list
    story_materials: list
    contact_nodes: np.ndarray
    contact_names: list
    contact_gaps: np.ndarray
    contact_materials: list
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
    channels: tuple = ("x",)
    floors: FloorsInPlan = None
    story_geometric: np.ndarray = None
    substeps: int = 1
    foundations: Foundations = None
    differences: tuple = ()
    supports: Supports = None
