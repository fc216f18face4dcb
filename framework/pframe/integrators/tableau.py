"""A step as data: the stages of an implicit integrator and their relations.

A step of length h advances the committed state (u_0, v_0, a_0) at t through S implicit
stages. Stage s (1 ... S) ends at t + c_s h, with the state (u_s, v_s, a_s) whose acceleration
a_s is its unknown, and imposes equilibrium of the equation of motion

    M a_e + C v_e + F(u_e) = P(t + e_s h)

at its evaluation point (u_e, v_e, a_e). Each of the five relations (u_s, v_s, u_e, v_e, a_e)
is a linear combination of the points before it -- the step start (point 0) and the ends of the
earlier stages -- and of the stage's own a_s, with coefficients scaled by powers of h so that
they are numbers independent of the step:

    x = sum_j (c_ju u_j + c_jv h v_j + c_ja h^2 a_j) / h^p  +  c_s h^2 a_s / h^p,

p the order of x (0 for a displacement, 1 a velocity, 2 an acceleration). The step ends at the
last stage. Newton then solves each stage for a_s with the effective stiffness
K + (c_ve / (c_ue h)) C + (c_ae / (c_ue h^2)) M per unit of u_e (c_ue, c_ve, c_ae the own
coefficients of u_e, v_e, a_e): ``kernel/c/integrator.c``.

The form holds every implicit integrator pframe has: Newmark and the generalised-alpha family
(one stage, evaluated at the weighted point t(n+1-alpha)), Wilson-theta (one stage evaluated
at t + theta h, past its end) and Bathe's composite method (two stages evaluated at their ends:
the trapezoidal rule to t + gamma h, the three-point backward difference to t + h). Its
amplification matrix (:meth:`Tableau.amplification`) follows from the data, for the dt checks
(:mod:`pframe.assemble.timescales`) and the tests.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

#: the relations of a stage, in the kernel's order (pframe.kernel.state.Relation), and the
#: power of h each is divided by
RELATIONS = {"u": 0, "v": 1, "ue": 0, "ve": 1, "ae": 2}


def _own(value: float, points: int) -> tuple:
    """A relation that is ``value`` times the stage's own acceleration (scaled) alone."""
    return ((0.0, 0.0, 0.0),) * points + ((0.0, 0.0, value),)


@dataclass(frozen=True)
class Stage:
    """One implicit stage: where it ends and is evaluated (fractions of the step), and its
    relations, each a tuple of ``(c_u, c_v, c_a)`` per point (the step start, then the earlier
    stages' ends) followed by the stage's own ``(0, 0, c_a)``. ``ue``, ``ve``, ``ae`` left out:
    equilibrium at the stage's end (``at`` = ``end``)."""

    end: float
    u: tuple
    v: tuple
    at: float | None = None
    ue: tuple | None = None
    ve: tuple | None = None
    ae: tuple | None = None
    evaluated_at_end: bool = field(init=False)

    def __post_init__(self):
        points = len(self.u) - 1
        ends = self.ue is None and self.ve is None and self.ae is None
        object.__setattr__(self, "evaluated_at_end", ends)
        defaults = {"at": self.end, "ue": self.u, "ve": self.v, "ae": _own(1.0, points)}
        for name, value in defaults.items():
            if getattr(self, name) is None:
                object.__setattr__(self, name, value)
        for name in RELATIONS:
            rows = getattr(self, name)
            if len(rows) != points + 1 or rows[-1][0] != 0.0 or rows[-1][1] != 0.0:
                raise ValueError(f"stage relation {name} needs a (c_u, c_v, c_a) per point and "
                                 "only an acceleration term of its own stage")
        if not self.ae[-1][2] > 0.0:
            raise ValueError("a stage's evaluated acceleration must grow with its own")

    def relation(self, name: str) -> tuple:
        return getattr(self, name)

    @property
    def implicit(self) -> bool:
        """Its end and evaluated displacements depend on its own acceleration (an equation to
        solve; central difference, Newmark's beta = 0, has none)."""
        return self.u[-1][2] > 0.0 and self.ue[-1][2] > 0.0

    @property
    def stiffness(self) -> tuple[float, float, float, float]:
        """What the stage's effective stiffness depends on (its own coefficients of u, u_e,
        v_e, a_e): stages with equal ones share one factorisation in the kernel."""
        return (self.u[-1][2], self.ue[-1][2], self.ve[-1][2], self.ae[-1][2])


@dataclass(frozen=True)
class Tableau:
    """The stages of a step, and the weight ``kinetic_weight`` (times h^2) of
    ``(1/2) a M a`` in the kinetic energy the balance counts (Newmark's beta - 1/4: the
    quadratic form a Newmark step conserves; 0 for a method that has none)."""

    stages: tuple[Stage, ...]
    kinetic_weight: float = 0.0

    def __post_init__(self):
        for s, stage in enumerate(self.stages):
            if len(stage.u) != s + 2:
                raise ValueError(f"stage {s + 1} has {len(stage.u) - 1} points before it, not "
                                 f"{s + 1} (the step start and the earlier stages)")
        if self.stages[-1].end != 1.0:
            raise ValueError("the last stage ends the step (end = 1)")

    @property
    def off_end(self) -> bool:
        """Some stage imposes equilibrium elsewhere than at its end."""
        return not all(stage.evaluated_at_end for stage in self.stages)

    @property
    def beyond(self) -> bool:
        """Some stage is evaluated past its end (Wilson-theta): with located events, contacts
        keep the branch they have at the (sub-)step's start there (kernel/c/assembly.c)."""
        return any(stage.at > stage.end for stage in self.stages)

    def stiffness_classes(self) -> tuple[int, ...]:
        """Each stage's effective-stiffness class: stages of one class share a factorisation
        (the kernel refactors when the class or the step length changes)."""
        keys: dict = {}
        return tuple(keys.setdefault(stage.stiffness, len(keys)) for stage in self.stages)

    def amplification(self, w_h: float) -> np.ndarray:
        """The amplification matrix of an undamped vibration of circular frequency w integrated
        with step h (``w_h`` = w h): ``x(n+1) = A x(n)`` for ``x = (u, h v, h^2 a)``, stage by
        stage from the relations, each stage's a from its equilibrium ``a_e + w^2 u_e = 0``."""
        W = w_h * w_h
        points = [np.eye(3)]  # each point's x as a matrix acting on the step start's x
        for stage in self.stages:
            def row(name, stage=stage):
                rows = stage.relation(name)
                return sum(np.asarray(c) @ x for c, x in zip(rows[:-1], points)), rows[-1][2]
            ue, ue_own = row("ue")
            ae, ae_own = row("ae")
            a = -(ae + W * ue) / (ae_own + W * ue_own)
            u, u_own = row("u")
            v, v_own = row("v")
            points.append(np.array([u + u_own * a, v + v_own * a, a]))
        return points[-1]

    def spectral_radius(self, w_h: float) -> float:
        """The largest modulus of the amplification matrix's eigenvalues at ``w_h`` = w h."""
        return float(np.max(np.abs(np.linalg.eigvals(self.amplification(w_h)))))


def newmark(gamma: float, beta: float, alpha_m: float = 0.0, alpha_f: float = 0.0) -> Tableau:
    """Newmark's relations with equilibrium at t(n+1-alpha): the generalised-alpha family
    (Chung & Hulbert 1993), x_e = (1 - alpha) x(n+1) + alpha x(n), alpha_f for u, v and the
    load, alpha_m for a."""
    u = ((1.0, 1.0, 0.5 - beta), (0.0, 0.0, beta))
    v = ((0.0, 1.0, 1.0 - gamma), (0.0, 0.0, gamma))
    if alpha_m == 0.0 and alpha_f == 0.0:
        return Tableau((Stage(1.0, u, v),), beta - 0.25)
    wf = 1.0 - alpha_f
    stage = Stage(1.0, u, v, at=wf,
                  ue=((1.0, wf, wf * (0.5 - beta)), (0.0, 0.0, wf * beta)),
                  ve=((0.0, 1.0, wf * (1.0 - gamma)), (0.0, 0.0, wf * gamma)),
                  ae=((0.0, 0.0, alpha_m), (0.0, 0.0, 1.0 - alpha_m)))
    return Tableau((stage,), beta - 0.25)


def wilson(theta: float, gamma: float = 0.5, beta: float = 1.0 / 6.0) -> Tableau:
    """Wilson's theta method (Wilson, Farhoomand & Bathe 1973): Newmark's relations over the
    extended step theta h, equilibrium at its end t + theta h, the step end at h on the same
    (linear) acceleration: a_e = (1 - theta) a(n) + theta a(n+1)."""
    th = theta
    stage = Stage(1.0, ((1.0, 1.0, 0.5 - beta), (0.0, 0.0, beta)),
                  ((0.0, 1.0, 1.0 - gamma), (0.0, 0.0, gamma)), at=th,
                  ue=((1.0, th, th * th * (0.5 - beta * th)), (0.0, 0.0, beta * th ** 3)),
                  ve=((0.0, 1.0, th * (1.0 - gamma * th)), (0.0, 0.0, gamma * th * th)),
                  ae=((0.0, 0.0, 1.0 - th), (0.0, 0.0, th)))
    return Tableau((stage,), beta - 0.25)
