"""Contact episodes: impact counts, and the peak force and penetration of each contact,
located between output samples.

A local maximum of the contact force P is where dP/dt = (dP/d delta) delta' +
(dP/d delta') delta'' falls through zero (both derivatives from the law, delta'' from the
equations of motion); one of the penetration is where delta' does. Their roots are found on
the integrator's dense output; steps' ends and restarts are candidates too (a force may jump
at an event, as the Kelvin dashpot's at onset).
"""

from __future__ import annotations

import numpy as np

from pframe.reference.result import Impact
from pframe.reference.roots import root


class Episodes:
    """Impact counts and the episodes of the contacts of one run."""

    def __init__(self, system):
        self.system = system
        self.impacts = np.zeros(system.n_contact, dtype=np.int64)
        self.open: dict[int, Impact] = {}
        self.all: list[Impact] = []

    def onset(self, contact: int, t: float, rate: float, counted: bool):
        if counted:
            self.impacts[contact] += 1
        episode = Impact(contact, float(t), float(rate), counted=counted)
        self.open[contact] = episode
        self.all.append(episode)

    def separation(self, contact: int, t: float, rate: float):
        episode = self.open.pop(contact, None)
        if episode is not None:
            episode.separation = float(t)
            episode.separation_rate = float(rate)

    def _candidate(self, c, t, force, penetration):
        episode = self.open.get(c)
        if episode is None:
            return
        if force > episode.peak_force:
            episode.peak_force = float(force)
            episode.peak_time = float(t)
        episode.max_penetration = max(episode.max_penetration, float(penetration))

    def boundary(self, t, s):
        """Candidates at a step's end or a restart."""
        for c in self.open:
            self._candidate(c, t, s.contact_force[c], s.penetration[c])

    def samples(self, ts, force, penetration):
        """Candidates at output samples: force and penetration of shape (len(ts), c)."""
        for c in self.open:
            j = int(np.argmax(force[:, c]))
            self._candidate(c, ts[j], force[j, c], float(penetration[:, c].max()))

    def watch(self, s):
        """(2, c): dP/dt of loaded contacts and delta' of closed ones; +inf elsewhere."""
        system = self.system
        out = np.full((2, system.n_contact), np.inf)
        if not system.n_contact:
            return out
        rate_of_rate = system.contact_incidence @ s.acceleration
        dpdt = s.contact_tangent * s.penetration_rate + s.contact_rate_tangent * rate_of_rate
        out[0] = np.where(system.contact_loaded(), dpdt, np.inf)
        out[1] = np.where(system.contact_closed(), s.penetration_rate, np.inf)
        return out

    def maxima(self, t0, w0, t1, w1, step):
        """Local maxima of force and penetration in [t0, t1]: falling zeros of ``watch``."""
        falling = (w0 > 0) & (w0 < np.inf) & (w1 <= 0)
        for which, c in zip(*np.nonzero(falling)):
            def g(t, which=which, c=c):
                return self.watch(step(t))[which, c]

            at = root(g, t0, t1)
            s = step(at)
            force = s.contact_force[c] if which == 0 else 0.0
            self._candidate(c, at, force, s.penetration[c])

    def peaks(self):
        """(c,) largest force over the episodes and its time."""
        peak = np.zeros(self.system.n_contact)
        when = np.full(self.system.n_contact, np.nan)
        for episode in self.all:
            if episode.peak_force > peak[episode.contact]:
                peak[episode.contact] = episode.peak_force
                when[episode.contact] = episode.peak_time
        return peak, when
