"""The event-driven integration: smooth segments with a scipy ODE solver, regime changes at
the roots of the event functions, outputs from the solver's dense output.

One segment runs from a restart to the next event or ground breakpoint. After every accepted
step the event functions of all elements (one vectorised evaluation) are compared with their
values at the start of the step; where one reached zero (or dipped below it inside the step)
its root is located on the step's dense output, the step is taken again up to just past it
(so that no stage of it lies on the law's other branch), the element's law commits its state
there (as the kernel commits an accepted step), its regime changes and a new segment starts.
The solver objects of ``scipy.integrate`` (the classes behind ``solve_ivp``) are driven
directly, so that event detection is one vectorised evaluation per step and a restart costs
no more than constructing a solver.
"""

from __future__ import annotations

import numpy as np
from scipy import integrate

from pframe.quantities import QUANTITIES
from pframe.reference.episodes import Episodes
from pframe.reference.result import Event
from pframe.reference.roots import EPS, crossing, root
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


class Integration:
    """One integration of one batch member, filling the outputs as it goes."""

    def __init__(self, system: System, times, rtol, atol, method, max_step):
        self.system = system
        self.times = times
        self.rtol = rtol
        self.atol = atol
        self.method = method
        self.max_step = max_step
        k, n = len(times), system.n
        c = system.n_contact
        plan = system.plan
        s = len(plan.story_names)  # the storeys; the links are the springs after them
        self.storeys = s
        self.heights = (plan.story_height[system.member, :s] if plan.story_height is not None
                        else np.full(s, np.nan))
        self.links = len(plan.link_names)
        self.foundations = (plan.foundation_dofs if plan.foundation_dofs is not None
                            else np.zeros((0, 2), dtype=np.int64))
        points = len(plan.point_names)
        width = {"node": (n,), "story": (s,), "contact": (c,), None: (),
                 "link": (self.links,), "foundation": (len(self.foundations),),
                 "point": (2 * points,)}
        # the named plan points' gauges (Plan.gauge_*) as a matrix on the DOFs
        self.gauges = np.zeros((4 * points, n))
        for g in range(4 * points):
            for t in range(plan.gauge_start[g], plan.gauge_start[g + 1]):
                self.gauges[g, plan.gauge_dof[t]] += plan.gauge_coef[system.member, t]
        self.out = {q: np.full((k, *width[dim]), np.nan) for q, (dim, _, _) in QUANTITIES.items()}
        self.next_sample = 0
        self.episodes = Episodes(system)
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
        out["absolute_acceleration"][rows] = (s.acceleration + np.asarray(s.ground)[..., None]
                                              * self.system.influence)
        ns = self.storeys
        out["story_drift"][rows] = s.drift[..., :ns]
        out["story_force"][rows] = s.story_force[..., :ns]
        out["story_drift_ratio"][rows] = s.drift[..., :ns] / self.heights
        nl = ns + self.links  # the soil's springs follow the links
        out["link_deformation"][rows] = s.drift[..., ns:nl]
        out["link_force"][rows] = s.story_force[..., ns:nl]
        out["foundation_sway"][rows] = s.u[..., self.foundations[:, 0]]
        out["foundation_rocking"][rows] = s.u[..., self.foundations[:, 1]]
        out["contact_force"][rows] = s.contact_force
        out["contact_penetration"][rows] = np.maximum(s.penetration, 0.0)
        gauged = s.u @ self.gauges.T
        half = self.gauges.shape[0] // 2
        out["point_displacement"][rows] = gauged[..., :half]
        out["point_drift"][rows] = gauged[..., half:]
        out["contact_ground_displacement"][rows] = 0.0  # one ground (supports are refused)

    def _samples(self, t_stop, step):
        """Store the samples in (previous stop, t_stop] from the step (its dense output,
        exact at its ends)."""
        first = self.next_sample
        last = int(np.searchsorted(self.times, t_stop, side="right"))
        if last <= first:
            return
        ts = self.times[first:last]
        if ts.size == 1:  # most often the step's end, whose state is known
            s = step(float(ts[0]))
            self._store(first, s)
            self.episodes.samples(ts, s.contact_force[None, :], s.penetration[None, :])
        else:
            ys = step.dense(ts).T
            ys[ts == step.t1] = np.concatenate((step.s1.u, step.s1.v))
            n = self.system.n
            s = self.system.evaluate(ts, ys[:, :n], ys[:, n:])
            self._store(slice(first, last), s)
            self.episodes.samples(ts, s.contact_force, s.penetration)
        self.next_sample = last

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
            # a contact closed at t = 0 is not an impact, one closing from the gap itself is
            self.episodes.onset(e, t, r, counted or not d > np.finfo(float).tiny)
        elif kind == "contact" and what == "separation":
            self.episodes.separation(e, t, r)

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
            out.append((crossing(_component(system, step, i), t0, t1), int(i)))
        dips = (values > 0) & (values_new > 0) & (rates < 0) & (rates_new > 0)
        for i in np.flatnonzero(dips):
            lowest = root(lambda x, i=i: -_component(system, step, i, 1)(x), t0, t1)
            if _component(system, step, i)(lowest) <= 0.0:
                out.append((crossing(_component(system, step, i), t0, lowest), int(i)))
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
        self.episodes.boundary(t, s)
        watch = self.episodes.watch(s)
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
            step = StepStates(system, solver, t, s, t_new, s_new)
            crossings = self._crossings(step, values, rates, values_new, rates_new)
            if crossings:
                t_stop, event = min(crossings)
                hair = EVENT_MARGIN * (t_new - t) + 8.0 * EPS * abs(t_new)
                # an event within a hair of the step's start needs no retake: the dense
                # output is exact at the start
                if min(t_new - t_stop, t_stop - t) > hair and retakes < MAX_RETAKES:
                    retakes += 1
                    self.evaluations += solver.nfev
                    end = min(bound, t_stop + 0.1 * EVENT_MARGIN * (t_stop - t)
                              + 4.0 * EPS * abs(t_stop))
                    solver = self._solver(t, y, end, end - t)
                    continue
                s_stop = step(t_stop)
            else:
                t_stop, s_stop = t_new, s_new
            watch_stop = self.episodes.watch(s_stop)
            self._samples(t_stop, step)
            self.episodes.maxima(t, watch, t_stop, watch_stop, step)
            self.episodes.boundary(t_stop, s_stop)
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


class StepStates:
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
