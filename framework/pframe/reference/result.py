"""What a reference solution holds."""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np


@dataclass
class Impact:
    """One contact episode, from onset (gap closing) to separation (gap opening).

    Times in s, rates (penetration rate delta') in m/s, force in N, penetration in m. An
    episode already closed at t = 0 is listed with ``counted = False`` (as the kernel, the
    impact count ignores it); one still closed at the end has ``separation = nan``.
    """

    contact: int
    onset: float
    approach_rate: float
    peak_force: float = 0.0
    peak_time: float = float("nan")
    max_penetration: float = 0.0
    separation: float = float("nan")
    separation_rate: float = float("nan")
    counted: bool = True

    @property
    def restitution(self) -> float:
        """-delta'(separation) / delta'(onset): the coefficient of restitution of a two-body
        impact without other forces."""
        return -self.separation_rate / self.approach_rate


@dataclass
class Event:
    """A regime change: at ``time`` element ``index`` (a storey or contact, declaration
    order) went through ``what`` (onset, separation, release, re-engage, rebound, approach,
    yield, unload)."""

    time: float
    kind: str  # "story" or "contact"
    index: int
    what: str


@dataclass
class ReferenceResult:
    """Histories at ``times`` (batch member ``member`` of ``plan``); node columns in DOF order
    like the kernel's ``Result.history`` (``plan.node_dof`` maps declared nodes), storey and
    contact columns in declaration order. Units: m, m/s, m/s^2, N."""

    plan: object
    member: int
    times: np.ndarray
    displacement: np.ndarray  # (K, n)
    velocity: np.ndarray
    acceleration: np.ndarray  # relative to the ground
    ground_acceleration: np.ndarray  # (K,)
    story_drift: np.ndarray  # (K, s)
    story_force: np.ndarray  # material force (damping excluded)
    contact_force: np.ndarray  # (K, c), compression positive
    contact_penetration: np.ndarray  # max(delta, 0)
    impacts: np.ndarray  # (c,) contact onsets at t > 0 (or at 0 from an open gap)
    peak_contact_force: np.ndarray  # (c,) located between samples
    peak_contact_force_time: np.ndarray  # (c,)
    episodes: list = field(default_factory=list)  # Impact, in time order
    events: list = field(default_factory=list)  # Event, in time order
    steps: int = 0  # accepted integrator steps
    evaluations: int = 0  # right-hand side evaluations by the integrator
    segments: int = 0  # integrator restarts (events and ground breakpoints)
    seconds: float = 0.0
    method: str = ""
    rtol: float = 0.0
    atol: np.ndarray = None
    ground: str = ""
    story_drift_ratio: np.ndarray = None  # (K, s) drift / height (NaN without heights)
    link_deformation: np.ndarray = None  # (K, l) u_second - u_first
    link_force: np.ndarray = None  # (K, l)
    foundation_sway: np.ndarray = None  # (K, F) a foundation's sway (m)
    foundation_rocking: np.ndarray = None  # (K, F) its rocking (rad)
    absolute_acceleration: np.ndarray = None  # (K, n) acceleration + ground acceleration
    point_displacement: np.ndarray = None  # (K, 2 P) named plan points along x, y of each
    point_drift: np.ndarray = None  # (K, 2 P) their drifts
    #: (K,) the ground acceleration at ``times`` integrated twice by the trapezoid rule
    #: from rest (the kernel's relation; exact as the samples get dense), and (K, c) each
    #: contact's part of it: 0, the reference takes one ground
    ground_displacement: np.ndarray = None
    contact_ground_displacement: np.ndarray = None

    def __post_init__(self):
        if self.ground_displacement is None or np.all(np.isnan(self.ground_displacement)):
            t, a = self.times, self.ground_acceleration
            v = np.concatenate([[0.0], np.cumsum(0.5 * np.diff(t) * (a[1:] + a[:-1]))])
            self.ground_displacement = np.concatenate(
                [[0.0], np.cumsum(0.5 * np.diff(t) * (v[1:] + v[:-1]))])

    def history(self, quantity: str) -> np.ndarray:
        """A history by its recorder name (``displacement``, ``story_force``, ...)."""
        return getattr(self, quantity)

    def node(self, quantity: str, name: str) -> np.ndarray:
        """History of a node quantity for the node named ``name`` (e.g. ``A/3``)."""
        plan = self.plan
        return getattr(self, quantity)[:, plan.node_dof[plan.node_names.index(name)]]

    def element(self, quantity: str, name: str) -> np.ndarray:
        """History of a storey or contact quantity for the element named ``name``."""
        names = (self.plan.contact_names if quantity.startswith("contact_")
                 else self.plan.story_names)
        return getattr(self, quantity)[:, names.index(name)]
