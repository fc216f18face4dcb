"""``solve``: the reference solution of one batch member of a plan."""

from __future__ import annotations

import time as clock

import numpy as np

from pframe.errors import InputError
from pframe.reference.ground import Ground, sampled
from pframe.reference.result import ReferenceResult
from pframe.reference.stepping import METHODS, Integration
from pframe.reference.system import System


def default_atol(plan, member: int, rtol: float) -> np.ndarray:
    """rtol times a displacement scale (for u) and a velocity scale (for v).

    The scales come from the scene: the initial conditions, the gaps and the response of the
    lowest storey mode w_1 to the peak ground acceleration (a_max / w_1^2, with velocity
    w_1 times the displacement scale). Without storeys they come from the initial velocities
    and the duration.
    """
    n = plan.n_dof
    u0 = np.abs(plan.initial_displacement[member]).max(initial=0.0)
    v0 = np.abs(plan.initial_velocity[member]).max(initial=0.0)
    a_max = np.abs(plan.ground_acceleration[member]).max(initial=0.0)
    gap = np.abs(plan.contact_gap[member]).max(initial=0.0)
    duration = plan.steps * float(plan.dt[member])
    stiffness = np.zeros((n, n))
    for (low, up), k in zip(plan.story_dofs, plan.story_k0[member]):
        stiffness[up, up] += k
        if low >= 0:
            stiffness[low, low] += k
            stiffness[low, up] -= k
            stiffness[up, low] -= k
    scale = 1.0 / np.sqrt(plan.mass[member])
    w2 = np.linalg.eigvalsh(stiffness * np.outer(scale, scale))
    w2 = w2[w2 > 1e-9 * max(w2.max(initial=0.0), 1e-300)]
    if w2.size:
        w1 = float(np.sqrt(w2.min()))
        u_ref = max(u0, v0 / w1, a_max / w1**2, gap)
        v_ref = max(v0, w1 * u_ref)
    else:
        v_ref = max(v0, a_max * duration)
        u_ref = max(u0, gap, v_ref * duration)
    u_ref = u_ref or 1.0
    v_ref = v_ref or 1.0
    return rtol * np.concatenate((np.full(n, u_ref), np.full(n, v_ref)))


def solve(plan, member: int = 0, rtol: float = 1e-12, atol=None, method: str = "DOP853",
          times=None, ground=None, jit: bool = True, max_step: float = np.inf) -> ReferenceResult:
    """A reference solution of one batch member of a plan, independent of the kernel.

    Integrates the first-order form of the equations of motion (``docs/theory.md``) with a
    scipy ODE solver at tight tolerances, restarting at every regime change of a law
    (contact onset and separation, release of a clipped contact force, yield and unloading of
    a bilinear storey, Jankowski's switch at zero penetration rate) located as a root on the
    dense output, and at every breakpoint of the ground motion. See
    ``docs/reference-solution.md``.

    Parameters
    ----------
    plan : Plan
        An assembled scene; only ``damping.stiffness: initial`` is supported.
    member : int
        Batch member.
    rtol : float
        Relative tolerance of the ODE solver.
    atol : float or (2n,) array, optional
        Absolute tolerance (m for displacements, m/s for velocities); by default ``rtol``
        times the scales of :func:`default_atol`.
    method : str
        ``DOP853`` (default, explicit order 8), ``RK45``, ``Radau``, ``BDF`` or ``LSODA``
        (implicit ones get the Jacobian from the laws' tangents).
    times : array, optional
        Output times (s), increasing from 0; default the plan's step times ``n dt``. The
        integration ends at the last one.
    ground : callable or Ground, optional
        a_g(t) (m/s^2) for scalar or array t. Default: the plan's samples interpolated
        linearly, with a restart at every sample (slow: one segment per step). For a sine or
        a record pass :func:`pframe.reference.ground.of_scene` (exact, continuous time).
        A plain callable is taken as smooth; wrap it in ``Ground(f, breakpoints)`` if not.
    jit : bool
        Compile the laws' ``force`` with numba (default) or call them from Python.
    max_step : float
        Largest step of the ODE solver (s).

    Returns
    -------
    ReferenceResult
    """
    if method not in METHODS:
        raise InputError(f"unknown method {method!r}; choose one of {', '.join(METHODS)}")
    start = clock.perf_counter()
    steps = np.arange(plan.steps + 1) * float(plan.dt[member])
    if ground is None:
        ground = sampled(steps, plan.ground_acceleration[member])
    elif not isinstance(ground, Ground):
        ground = Ground(ground, np.empty(0))
    if times is None:
        times = steps
    times = np.asarray(times, dtype=float)
    if times.ndim != 1 or times.size == 0 or times[0] < 0 or np.any(np.diff(times) <= 0):
        raise InputError("times must be a non-empty increasing sequence of times >= 0")
    if atol is None:
        atol = default_atol(plan, member, rtol)
    atol = np.broadcast_to(np.asarray(atol, dtype=float), (2 * plan.n_dof,)).copy()
    system = System(plan, member, ground, jit=jit)
    run = Integration(system, times, rtol, atol, method, max_step)
    y0 = np.concatenate((plan.initial_displacement[member], plan.initial_velocity[member]))
    run.run(np.asarray(y0, dtype=float), ground.breakpoints)

    peak, peak_time = run.episodes.peaks()
    return ReferenceResult(
        plan=plan, member=member, times=times, impacts=run.episodes.impacts,
        peak_contact_force=peak, peak_contact_force_time=peak_time,
        episodes=run.episodes.all, events=run.events, steps=run.steps,
        evaluations=run.evaluations, segments=run.segments,
        seconds=clock.perf_counter() - start, method=method, rtol=rtol, atol=atol,
        ground=ground.description, **run.out,
    )
