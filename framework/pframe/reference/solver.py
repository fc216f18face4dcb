"""The event-driven integration: smooth segments with a scipy ODE solver, regime changes at
the roots of the event functions, outputs from the solver's dense output.

One segment runs from a restart to the next event or ground breakpoint. After every accepted
step the event functions of all elements (one vectorised evaluation) are compared with their
values at the start of the step; where one fell to zero its root is located on the step's
dense output, the integration stops there, the element's law commits its state at that point
(as the kernel commits an accepted step), its regime changes and a new segment starts. The
solver objects of ``scipy.integrate`` (the classes behind ``solve_ivp``) are driven directly,
so that event detection is one vectorised evaluation per step and a restart costs no more
than constructing a solver.
"""

from __future__ import annotations

import time as clock

import numpy as np
from scipy import integrate, optimize

from pframe.errors import InputError
from pframe.reference.ground import Ground, sampled
from pframe.reference.result import Event, Impact, ReferenceResult
from pframe.reference.system import System

METHODS = {"DOP853": integrate.DOP853, "RK45": integrate.RK45, "Radau": integrate.Radau,
           "BDF": integrate.BDF, "LSODA": integrate.LSODA}
IMPLICIT = ("Radau", "BDF", "LSODA")
#: regime changes allowed at one instant before the run is declared to chatter
MAX_CASCADE = 1000
#: an event found within this fraction of a step from its end is taken from that step;
#: farther, the step is taken again up to just past the event
EVENT_MARGIN = 1e-9
#: times a step may be taken again towards one event
MAX_RETAKES = 8
_EPS = np.finfo(float).eps


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


class _Run:
    """One integration of one batch member, filling the outputs as it goes."""

    def __init__(self, system: System, times, rtol, atol, method, max_step):
        self.system = system
        self.times = times
        self.rtol = rtol
        self.atol = atol
        self.method = method
        self.max_step = max_step
        k, n = len(times), system.n
        s, c = system.n_story, system.n_contact
        self.out = {
            "displacement": np.full((k, n), np.nan), "velocity": np.full((k, n), np.nan),
            "acceleration": np.full((k, n), np.nan), "ground_acceleration": np.full(k, np.nan),
            "story_drift": np.full((k, s), np.nan), "story_force": np.full((k, s), np.nan),
            "contact_force": np.full((k, c), np.nan),
            "contact_penetration": np.full((k, c), np.nan),
        }
        self.next_sample = 0
        self.impacts = np.zeros(c, dtype=np.int64)
        self.open_episode: dict[int, Impact] = {}
        self.episodes: list[Impact] = []
        self.events: list[Event] = []
        self.steps = 0
        self.evaluations = 0
        self.segments = 0

    # ------------------------------------------------------------------------------------
    # outputs
    # ------------------------------------------------------------------------------------

    def _store(self, rows, s):
        out = self.out
        out["displacement"][rows] = s.u
        out["velocity"][rows] = s.v
        out["acceleration"][rows] = s.acceleration
        out["ground_acceleration"][rows] = s.ground
        out["story_drift"][rows] = s.drift
        out["story_force"][rows] = s.story_force
        out["contact_force"][rows] = s.contact_force
        out["contact_penetration"][rows] = np.maximum(s.penetration, 0.0)

    def _samples(self, t_stop, step, t_end, y_end):
        """Store the samples in (previous stop, t_stop] from the step's dense output (exact
        at the step's end t_end)."""
        first = self.next_sample
        last = int(np.searchsorted(self.times, t_stop, side="right"))
        if last <= first:
            return
        ts = self.times[first:last]
        if ts.size == 1 and ts[0] == t_end:
            ys = y_end[None, :].copy()
        else:
            ys = step.dense(ts).T
            ys[ts == t_end] = y_end
        n = self.system.n
        s = self.system.evaluate(ts, ys[:, :n], ys[:, n:])
        self._store(slice(first, last), s)
        self.next_sample = last
        for c in np.flatnonzero(self.system.contact_closed()):
            if c in self.open_episode:
                j = int(np.argmax(s.contact_force[:, c]))
                self._candidate(c, ts[j], s.contact_force[j, c],
                                float(s.penetration[:, c].max()))

    # ------------------------------------------------------------------------------------
    # contact episodes
    # ------------------------------------------------------------------------------------

    def _candidate(self, c, t, force, penetration):
        episode = self.open_episode.get(c)
        if episode is None:
            return
        if force > episode.peak_force:
            episode.peak_force = float(force)
            episode.peak_time = float(t)
        episode.max_penetration = max(episode.max_penetration, float(penetration))

    def _boundary(self, t, s):
        """Peak candidates at a step end or restart (where a force may jump)."""
        for c in self.open_episode:
            self._candidate(c, t, s.contact_force[c], s.penetration[c])

    def _watch(self, s):
        """Functions whose falling zeros are local maxima: dP/dt of loaded contacts and the
        penetration rate of closed ones. (2, c); +inf where not watched."""
        system = self.system
        c = system.n_contact
        out = np.full((2, c), np.inf)
        if not c:
            return out
        rate_of_rate = system.contact_incidence @ s.acceleration
        loaded = system.contact_loaded()
        closed = system.contact_closed()
        dpdt = s.contact_tangent * s.penetration_rate + s.contact_rate_tangent * rate_of_rate
        out[0] = np.where(loaded, dpdt, np.inf)
        out[1] = np.where(closed, s.penetration_rate, np.inf)
        return out

    def _maxima(self, t0, w0, t1, w1, state_at):
        """Locate local maxima of contact force and penetration in [t0, t1]."""
        falling = (w0 > 0) & (w0 < np.inf) & (w1 <= 0)
        for which, c in zip(*np.nonzero(falling)):
            def g(t, which=which, c=c):
                return self._watch(state_at(t))[which, c]

            root = _root(g, t0, t1)
            s = state_at(root)
            if which == 0:
                self._candidate(c, root, s.contact_force[c], s.penetration[c])
            else:
                self._candidate(c, root, 0.0, s.penetration[c])

    # ------------------------------------------------------------------------------------
    # regime changes
    # ------------------------------------------------------------------------------------

    def _transition(self, i, t, s, counted=True):
        system = self.system
        kind, gi, j, k = system.event_owner[i]
        group = system.group(kind, gi)
        new, side, what = group.branches.after(int(group.regime[j]), k)
        group.regime[j] = new
        e = int(group.index[j])
        if kind == "story":
            d, r = s.drift[e], s.drift_rate[e]
        else:
            d, r = s.penetration[e], s.penetration_rate[e]
        if side > 0:
            d = max(d, np.finfo(float).tiny)
        elif side < 0:
            d = min(d, 0.0)
        group.elements.commit(j, d, r)
        self.system.refresh_events()
        self.events.append(Event(float(t), kind, e, what))
        if kind == "contact" and what == "onset":
            counted = counted or not d > np.finfo(float).tiny  # closing from the gap itself
            if counted:
                self.impacts[e] += 1
            episode = Impact(e, float(t), float(r), counted=counted)
            self.open_episode[e] = episode
            self.episodes.append(episode)
        elif kind == "contact" and what == "separation":
            episode = self.open_episode.pop(e, None)
            if episode is not None:
                episode.separation = float(t)
                episode.separation_rate = float(r)

    def _settle(self, t, y, counted=True):
        """Apply every regime change due at (t, y) (simultaneous events; the state is a root
        of an event function, where others may vanish too) and return the state under the
        final regimes with its event values.

        An event function is taken as crossed when it is negative beyond its rounding
        error, or within it and decreasing. Then each segment adds the rounding error of its
        start to its event functions: a function that is zero at the start (as the new
        regime's function at the point of a yield or unloading) starts positive, and an
        event is where it falls below minus its rounding error.
        """
        system = self.system
        n = system.n
        system.shift[:] = 0.0
        for _ in range(MAX_CASCADE):
            s = system.evaluate(t, y[:n], y[n:])
            values, rates, error = system.events(s, roundoff=True)
            crossed = np.flatnonzero((values < -error) | ((values <= error) & (rates < 0.0)))
            if not crossed.size:
                system.shift[:] = error
                return s, values + error
            self._transition(int(crossed[0]), t, s, counted)
            system.shift[:] = 0.0
        raise RuntimeError(f"regimes do not settle at t = {t!r} s (chattering contact or "
                           "storey); the reference cannot continue")

    def _crossings(self, step, values, rates, values_new, rates_new):
        """(time, component) of every event function that reaches zero in the step: a sign
        change between the step's ends, or a graze, a dip below zero between two positive
        ends, found at the minimum (where the derivative changes sign from - to +)."""
        system = self.system
        t0, t1 = step.t0, step.t1
        out = []
        fired = ((values > 0) & (values_new <= 0)) | ((values == 0) & (values_new < 0))
        for i in np.flatnonzero(fired):
            out.append((_crossing(_component(system, step, i), t0, t1), int(i)))
        dips = (values > 0) & (values_new > 0) & (rates < 0) & (rates_new > 0)
        for i in np.flatnonzero(dips):
            lowest = _root(lambda x, i=i: -_component(system, step, i, 1)(x), t0, t1)
            if _component(system, step, i)(lowest) <= 0.0:
                out.append((_crossing(_component(system, step, i), t0, lowest), int(i)))
        return out

    def _solver(self, t, y, t_bound, first_step):
        system = self.system
        options = {"rtol": self.rtol, "atol": self.atol, "max_step": self.max_step}
        if first_step is not None:
            options["first_step"] = min(first_step, t_bound - t)
        if self.method in IMPLICIT:
            options["jac"] = system.jacobian
        return METHODS[self.method](system.rhs, t, y, t_bound, **options)

    def _start(self, y0):
        """The kernel's first state: every law evaluated at (u0, v0) and committed; regimes
        follow (a contact closed at t = 0 is not an impact)."""
        system = self.system
        n = system.n
        s = system.evaluate(0.0, y0[:n], y0[n:])
        for kind, g in system.groups():
            d = s.drift if kind == "story" else s.penetration
            r = s.drift_rate if kind == "story" else s.penetration_rate
            for j, e in enumerate(g.index):
                g.elements.commit(j, d[e], r[e])
        s, values = self._settle(0.0, y0, counted=False)
        if self.times[0] == 0.0:
            self._store(0, s)
            self.next_sample = 1
        return s, values

    def run(self, y0, breakpoints):
        t_end = float(self.times[-1])
        t, y = 0.0, y0.copy()
        s, values = self._start(y)
        breaks = np.unique(np.asarray(breakpoints, dtype=float))
        breaks = np.append(breaks[(breaks > 0.0) & (breaks < t_end)], t_end)
        first_step = None
        progress_at, stalled = t, 0
        while t < t_end:
            bound = float(breaks[np.searchsorted(breaks, t, side="right")])
            t, y, s, values, first_step = self._segment(t, y, s, values, bound, first_step)
            if t > progress_at:
                progress_at, stalled = t, 0
            else:
                stalled += 1
                if stalled > MAX_CASCADE:
                    raise RuntimeError(f"events repeat without progress at t = {t!r} s")

    def _segment(self, t, y, s, values, bound, first_step):
        """Integrate from (t, y) until the first event or ``bound``; apply the event.
        Returns the state to restart from, its event values and the next step size.

        A step in which an event is found has had its later stages evaluated past the kink
        (on the law's other branch), which spoils its dense output before the event too. Unless
        the event lies within a hair (``EVENT_MARGIN`` of the step) of the step's end, the
        step is discarded and taken again up to just past the estimated event, so that the
        state at the event comes from stages on the old branch only.
        """
        system = self.system
        n = system.n
        solver = self._solver(t, y, bound, first_step)
        self.segments += 1
        self._boundary(t, s)
        watch = self._watch(s)
        rates = system.events(s)[1]
        retakes = 0
        while solver.status == "running":
            message = solver.step()
            if solver.status == "failed":
                raise RuntimeError(f"{self.method} failed at t = {solver.t!r} s: {message}")
            self.steps += 1
            t_new, y_new = float(solver.t), solver.y.copy()
            s_new = system.evaluate(t_new, y_new[:n], y_new[n:])
            values_new, rates_new = system.events(s_new)
            step = _StepStates(system, solver, t, s, t_new, s_new)
            crossings = self._crossings(step, values, rates, values_new, rates_new)
            if crossings:
                t_stop, event = min(crossings)
                hair = EVENT_MARGIN * (t_new - t) + 8.0 * _EPS * abs(t_new)
                # an event within a hair of the step's start needs no retake: the dense
                # output is exact at the start
                if min(t_new - t_stop, t_stop - t) > hair and retakes < MAX_RETAKES:
                    retakes += 1
                    self.evaluations += solver.nfev
                    end = min(bound, t_stop + 0.1 * EVENT_MARGIN * (t_stop - t)
                              + 4.0 * _EPS * abs(t_stop))
                    solver = self._solver(t, y, end, end - t)
                    continue
                s_stop = step(t_stop)
            else:
                t_stop, s_stop = t_new, s_new
            watch_stop = self._watch(s_stop)
            self._samples(t_stop, step, t_new, y_new)
            self._maxima(t, watch, t_stop, watch_stop, step)
            self._boundary(t_stop, s_stop)
            if not retakes:
                first_step = getattr(solver, "h_abs", None) or solver.step_size
            if crossings:
                self.evaluations += solver.nfev
                self._transition(event, t_stop, s_stop)
                y_stop = np.concatenate((s_stop.u, s_stop.v))
                s_stop, values_stop = self._settle(t_stop, y_stop)
                return t_stop, y_stop, s_stop, values_stop, first_step
            t, y, s, values, rates, watch = t_new, y_new, s_new, values_new, rates_new, watch_stop
        self.evaluations += solver.nfev
        return t, y, s, values, first_step


def _component(system, step, i, which=0):
    """Event function i (which = 0) or its time derivative (which = 1) along the step."""
    def g(x):
        return system.events(step(x))[which][i]

    return g


class _StepStates:
    """The state anywhere in the last step: exact at its ends, else from the dense output
    (built on first use: DOP853 spends three more evaluations on it)."""

    def __init__(self, system, solver, t0, s0, t1, s1):
        self.system, self.solver = system, solver
        self.t0, self.s0, self.t1, self.s1 = t0, s0, t1, s1
        self._dense = None

    def dense(self, t):
        if self._dense is None:
            self._dense = self.solver.dense_output()
        return self._dense(t)

    def __call__(self, t):
        if t == self.t0:
            return self.s0
        if t == self.t1:
            return self.s1
        y = self.dense(t)
        n = self.system.n
        return self.system.evaluate(t, y[:n], y[n:])


def _root(g, a, b):
    """A zero of g in [a, b] where g(a) >= 0 >= g(b) (Brent's method, to a few ulps of t)."""
    ga, gb = g(a), g(b)
    if ga <= 0.0:
        return a
    if gb >= 0.0:
        return b
    xtol = 4.0 * _EPS * max(abs(a), abs(b))
    return optimize.brentq(g, a, b, xtol=xtol, rtol=4.0 * _EPS, maxiter=200)


def _crossing(g, a, b):
    """The first time in (a, b] at which g, positive (or zero) at a, has become negative or
    zero: Brent's root, then moved forward by a few ulps until g is strictly negative (so
    that the new regime starts strictly on its side), or b."""
    root = _root(g, a, b)
    if root == a:
        root = min(b, a + 4.0 * _EPS * max(abs(a), abs(b)))
    step = 4.0 * _EPS * max(abs(root), abs(b - a))
    x = root
    for _ in range(60):
        if g(x) < 0.0:
            return x
        x = min(b, root + step)
        if x == b:
            break
        step *= 2.0
    return b


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
    run = _Run(system, times, rtol, atol, method, max_step)
    y0 = np.concatenate((plan.initial_displacement[member], plan.initial_velocity[member]))
    run.run(np.asarray(y0, dtype=float), ground.breakpoints)

    peak = np.zeros(system.n_contact)
    peak_time = np.full(system.n_contact, np.nan)
    for episode in run.episodes:
        if episode.peak_force > peak[episode.contact]:
            peak[episode.contact] = episode.peak_force
            peak_time[episode.contact] = episode.peak_time
    out = run.out
    return ReferenceResult(
        plan=plan, member=member, times=times, impacts=run.impacts,
        peak_contact_force=peak, peak_contact_force_time=peak_time,
        episodes=run.episodes, events=run.events, steps=run.steps,
        evaluations=run.evaluations, segments=run.segments,
        seconds=clock.perf_counter() - start, method=method, rtol=rtol, atol=atol,
        ground=ground.description, **out,
    )
