"""Regimes of the laws and the events that end them.

Within a regime a law's force is a smooth function of (deformation, rate) for its committed
state; the regime ends where the law would switch branch. Each class here describes one family
of laws by

- ``coefficients(regime, params, committed)``: every event function of an element is affine
  in its deformation d and rate r, ``g = A d + B r + C``, positive while the regime holds; an
  event fires where one reaches zero. Being affine, its time derivative is
  ``A r + B r'``, which lets the integrator find a dip below zero inside a step whose ends
  are both positive (a graze);
- ``after(regime, event)``: the next regime, the side of the kink on which the law commits
  its state (``+1`` just inside contact, ``-1`` just outside, ``0`` at the point), and a label
  for the event log.

The force itself always comes from the law's ``force``; these classes only know where its
branches meet (e.g. the bounding lines of the bilinear storey), they never replace it.
"""

from __future__ import annotations

import numpy as np

from pframe.errors import InputError

#: contact regimes
OPEN, CLOSED, RELEASED = 0, 1, 2
#: Jankowski: closed and approaching / closed and in restitution
APPROACH, RESTITUTION = 1, 2
#: bilinear storey regimes
ELASTIC, YIELD_UP, YIELD_DOWN = 0, 1, 2


def _inactive(size, events):
    """Coefficients of event functions that cannot fire: g = 1."""
    return np.zeros((size, events)), np.zeros((size, events)), np.ones((size, events))


class Smooth:
    """A law without branches (elastic storeys, stateless plug-in materials)."""

    n_events = 0

    def initial(self, size):
        return np.zeros(size, dtype=np.int64)

    def coefficients(self, regime, params, committed):
        return _inactive(len(regime), self.n_events)

    def closed(self, regime):
        return np.zeros(len(regime), dtype=bool)

    def loaded(self, regime):
        return self.closed(regime)


class Gap(Smooth):
    """A compression-only contact whose force is smooth while closed (linear, Hertz, plug-in
    laws without state): events at onset (delta = 0 rising) and separation (falling)."""

    n_events = 1

    def coefficients(self, regime, params, committed):
        a, b, c = _inactive(len(regime), self.n_events)
        a[:, 0] = np.where(regime == OPEN, -1.0, 1.0)  # -delta while open, delta while closed
        c[:, 0] = 0.0
        return a, b, c

    def after(self, regime, event):
        if regime == OPEN:
            return CLOSED, +1, "onset"
        return OPEN, -1, "separation"

    def closed(self, regime):
        return regime != OPEN

    def loaded(self, regime):
        """Closed and carrying the law's force (not released)."""
        return regime == CLOSED


class _Releasing(Gap):
    """A contact whose force is clipped at zero while still closed: the second event function
    is the unclipped expression A delta + B delta' + C, positive while it pushes."""

    n_events = 2

    def unclipped(self, params, committed):  # pragma: no cover - interface
        """(A, B, C, clips) of the unclipped force expression, per element."""
        raise NotImplementedError

    def coefficients(self, regime, params, committed):
        a, b, c = super().coefficients(regime, params, committed)  # n_events columns
        ua, ub, uc, clips = self.unclipped(params, committed)
        sign = np.where(regime == CLOSED, 1.0, -1.0)
        watched = clips & (regime != OPEN)
        a[:, 1] = np.where(watched, sign * ua, 0.0)
        b[:, 1] = np.where(watched, sign * ub, 0.0)
        c[:, 1] = np.where(watched, sign * uc, 1.0)
        return a, b, c

    def after(self, regime, event):
        if event == 0:
            return super().after(regime, event)
        if regime == CLOSED:
            return RELEASED, 0, "release"
        return CLOSED, 0, "re-engage"


class Kelvin(_Releasing):
    """Kelvin, params (k, c, keep_tension): clipped where k delta + c delta' falls to 0."""

    def unclipped(self, params, committed):
        zero = np.zeros(len(params))
        return params[:, 0], params[:, 1], zero, params[:, 2] == 0.0


class HuntCrossley(_Releasing):
    """k delta^n (1 + chi delta'/v0), params (k, n, chi), state (v0, in_contact): the force
    drops to zero (the law never pulls) where 1 + chi delta'/v0 reaches 0; v0 is committed
    at onset (the rate there)."""

    def unclipped(self, params, committed):
        v0 = committed[:, 0]
        chi = params[:, 2]
        damped = (v0 > 0.0) & (chi != 0.0)
        zero = np.zeros(len(params))
        return zero, np.where(damped, chi / np.where(damped, v0, 1.0), 0.0), zero + 1.0, damped


#: bumper regimes beyond the Hunt-Crossley ones: past the crush depth, and released there
CRUSHED, CRUSHED_RELEASED = 3, 4


class Bumper(HuntCrossley):
    """The bumper: the Hunt-Crossley regimes, each also past the crush depth delta_c
    (params[:, 5]), where the hard term's tangent has a sqrt kink: a third event at
    delta = delta_c, so that no integration step straddles it."""

    n_events = 3
    _RELEASE = {CLOSED: RELEASED, RELEASED: CLOSED, CRUSHED: CRUSHED_RELEASED,
                CRUSHED_RELEASED: CRUSHED}
    _CRUSH = {CLOSED: CRUSHED, CRUSHED: CLOSED, RELEASED: CRUSHED_RELEASED,
              CRUSHED_RELEASED: RELEASED}

    def coefficients(self, regime, params, committed):
        base = np.where(regime >= CRUSHED, regime - 2, regime)  # CLOSED / RELEASED alike
        a, b, c = super().coefficients(base, params, committed)  # n_events columns
        depth = params[:, 5]
        crushed = regime >= CRUSHED
        # delta_c - delta while short of the crush depth, delta - delta_c past it
        a[:, 2] = np.where(regime == OPEN, 0.0, np.where(crushed, 1.0, -1.0))
        c[:, 2] = np.where(regime == OPEN, 1.0, np.where(crushed, -depth, depth))
        return a, b, c

    def after(self, regime, event):
        if event == 0:
            return super().after(regime, event)
        if event == 1:
            return self._RELEASE[regime], 0, "release" if regime in (CLOSED, CRUSHED) \
                else "re-engage"
        return self._CRUSH[regime], 0, "crush" if regime in (CLOSED, RELEASED) else "uncrush"

    def loaded(self, regime):
        return (regime == CLOSED) | (regime == CRUSHED)


class Jankowski(Gap):
    """Jankowski: the dashpot acts only while approaching, so delta' = 0 in contact is a
    branch point (approach -> restitution and back)."""

    n_events = 2

    def coefficients(self, regime, params, committed):
        a, b, c = super().coefficients(regime, params, committed)  # n_events columns
        b[:, 1] = np.where(regime == APPROACH, 1.0, np.where(regime == RESTITUTION, -1.0, 0.0))
        c[:, 1] = np.where(regime == OPEN, 1.0, 0.0)
        return a, b, c

    def after(self, regime, event):
        if event == 0:
            if regime == OPEN:
                return APPROACH, +1, "onset"
            return OPEN, -1, "separation"
        if regime == APPROACH:
            return RESTITUTION, 0, "rebound"
        return APPROACH, 0, "approach"

    def loaded(self, regime):
        return regime != OPEN


class Bilinear(Smooth):
    """Bilinear kinematic hardening, params (k, f_y, alpha), state (drift, force): elastic
    until the trial force V_c + k (d - d_c) reaches a bounding line
    alpha k d +- (1 - alpha) f_y (yield), then on that line until the drift rate changes
    sign (unloading)."""

    n_events = 2

    def coefficients(self, regime, params, committed):
        k, fy, alpha = params[:, 0], params[:, 1], params[:, 2]
        reach = (1.0 - alpha) * fy
        offset = committed[:, 1] - k * committed[:, 0]  # trial = k d + offset
        elastic = (regime == ELASTIC) & (reach > 0.0)
        a, b, c = _inactive(len(regime), self.n_events)
        # upper line - trial = (alpha - 1) k d + reach - offset
        a[:, 0] = np.where(elastic, (alpha - 1.0) * k, 0.0)
        c[:, 0] = np.where(elastic, reach - offset, np.where(regime == ELASTIC, 1.0, 0.0))
        b[:, 0] = np.where(regime == YIELD_UP, 1.0, np.where(regime == YIELD_DOWN, -1.0, 0.0))
        # trial - lower line = (1 - alpha) k d + offset + reach
        a[:, 1] = np.where(elastic, (1.0 - alpha) * k, 0.0)
        c[:, 1] = np.where(elastic, offset + reach, 1.0)
        return a, b, c

    def after(self, regime, event):
        if regime == ELASTIC:
            return (YIELD_UP, 0, "yield") if event == 0 else (YIELD_DOWN, 0, "yield")
        return ELASTIC, 0, "unload"


#: the regime models a law names in its ``branches`` attribute (pframe.laws.Law)
BRANCHES = {"gap": Gap, "kelvin": Kelvin, "hunt_crossley": HuntCrossley, "bumper": Bumper,
            "jankowski": Jankowski, "smooth": Smooth, "bilinear": Bilinear}


def branches_for(law) -> Smooth:
    """The regime description of a law: the model its ``branches`` attribute names."""
    if law.branches is not None:
        if law.branches not in BRANCHES:
            raise InputError(f"the {law.kind} law {law.name!r} names the reference branches "
                             f"{law.branches!r}; pframe knows {', '.join(BRANCHES)}")
        return BRANCHES[law.branches]()
    if not law.state_names:
        # a stateless plug-in: the only branch point pframe knows of is the gap itself; kinks
        # inside the law are left to the step-size control
        return Gap() if law.kind == "contact" else Smooth()
    raise InputError(
        f"the reference solution does not know the branches of the {law.kind} law "
        f"{law.name!r} ({law.__module__}.{law.__qualname__}): it has state "
        f"{list(law.state_names)}, and where that state changes must be described in "
        "pframe.reference.branches"
    )
