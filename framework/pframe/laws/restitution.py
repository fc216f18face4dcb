"""The restitution of the damped contact laws, and the damping that gives a requested one.

Every function here works on the dimensionless two-body impact, in which a damped law's
restitution depends on one damping number alone (``chi`` or ``zeta``), for any stiffness,
masses and approach velocity (see ``docs/restitution.md``):

- Hunt-Crossley family, ``P = k delta^n (1 + chi delta' / v0)`` (``improved_kelvin``, n = 1;
  ``hertzdamp``, n = 3/2): ``chi (1 + e) = ln((1 + chi) / (1 - chi e))``, for any n;
- ``kelvin`` with tension, ``P = k delta + c delta'``: ``e = exp(-zeta pi / sqrt(1 - zeta^2))``
  (Anagnostopoulos 1988; 0 for zeta >= 1);
- ``kelvin`` clipped at zero: the floors separate when the force reaches zero, at the
  inflexion of the free decay, so ``e = exp(-2 zeta g(zeta))`` with
  ``g = arccos(zeta) / sqrt(1 - zeta^2)`` (``arccosh(zeta) / sqrt(zeta^2 - 1)`` above 1,
  ``g(1) = 1``);
- ``jankowski``, ``P = beta delta^1.5 + c delta'`` while approaching: in units where the
  approach velocity, ``m_eff`` and ``beta`` are 1 the impact is
  ``x'' = -x^1.5 - 2 zeta x^(1/4) x'`` up to the maximum penetration ``x_m`` and elastic after
  it, so ``e = sqrt(4/5) x_m^(5/4)``; ``x_m`` is found by integrating the compression.

The inverse functions (damping for a requested ``e``) are what ``calibration: exact`` packs.
scipy is imported inside the functions that need it, so that reading a scene stays light;
the numerical inverses are cached, so each runs once per value of ``e``.
"""

from __future__ import annotations

import math
from functools import lru_cache

#: Smallest restitution a damped law accepts. As e -> 0 the damping of the Hunt-Crossley laws
#: (chi ~ 1/e), of Jankowski's law (zeta ~ 0.55/e) and of the clipped Kelvin law calibrated
#: exactly (zeta ~ 1/(2 sqrt(e))) grows without bound: the impact tends to a perfectly
#: plastic one that no finite time step resolves. e = 0.01 already dissipates 99.99 % of the
#: impact energy.
E_MIN = 0.01

_EPS = 2.0**-52

#: How far the restitution a published damping formula rebounds with may be from the requested
#: one before ``pframe validate`` and ``pframe solve`` say so.
TOLERANCE = 0.02


def published_rebound(law, params) -> float | None:
    """The restitution a contact rebounds with in a two-body impact when its law uses the
    published damping formula (``calibration: published``) and that restitution is more than
    :data:`TOLERANCE` from the requested one; None otherwise (``calibration: exact``, a law
    without restitution, a plug-in law without a ``rebound`` method, or close enough)."""
    rebound = getattr(law, "rebound", None)
    if rebound is None or getattr(params, "calibration", None) != "published":
        return None
    obtained = float(rebound(params))
    return obtained if abs(obtained - params.restitution) > TOLERANCE else None


def check_restitution(e: float) -> float:
    """``e`` if a damped law accepts it, else ValueError (pydantic reports it at the field)."""
    if e < E_MIN:
        raise ValueError(
            f"restitution {e!r} is below {E_MIN}: as e -> 0 the damping of this law grows "
            "without bound (the impact becomes perfectly plastic, which no finite time step "
            f"resolves); give e >= {E_MIN}, which already dissipates 99.99 % of the impact "
            "energy (see docs/restitution.md)"
        )
    return e


# ---------------------------------------------------------------------------------------------
# Hunt-Crossley family
# ---------------------------------------------------------------------------------------------

def hunt_crossley_restitution(chi: float) -> float:
    """The restitution e in (0, 1] of ``k delta^n (1 + chi delta' / v0)``: the root of
    ``chi (1 + e) = ln((1 + chi) / (1 - chi e))`` in (0, 1/chi); 1 for chi = 0."""
    if chi <= 0.0:
        return 1.0

    def g(e):
        return chi * (1.0 + e) - math.log1p(chi) + math.log1p(-chi * e)

    # g(0) = chi - ln(1 + chi) > 0 and g -> -inf as e -> 1/chi; g is concave in e. Bisection
    # to the last bit (no scipy: pframe validate calls this for every published damping, and
    # importing scipy.optimize would cost it half a second)
    upper = min(1.0, (1.0 - _EPS) / chi)
    if g(upper) >= 0.0:  # chi so small that e rounds to 1
        return upper
    lo, hi = 0.0, upper
    for _ in range(200):
        mid = 0.5 * (lo + hi)
        if mid in (lo, hi):
            break
        if g(mid) > 0.0:
            lo = mid
        else:
            hi = mid
    return 0.5 * (lo + hi)


def _hc_series(chi: float, e: float) -> float:
    """[chi (1 + e) - ln((1 + chi) / (1 - chi e))] / chi^2 as its power series in chi
    (needs chi <= 1/4): (1 - e^2)/2 - sum_{k>=3} ((-1)^(k+1) + e^k) chi^(k-2) / k."""
    total = 0.5 * (1.0 - e) * (1.0 + e)
    power, ek = 1.0, e * e
    for k in range(3, 60):
        power *= chi
        ek *= e
        total -= ((1.0 if k % 2 else -1.0) + ek) * power / k
        if power < 1e-18:
            break
    return total


@lru_cache(maxsize=256)
def hunt_crossley_chi(e: float) -> float:
    """The chi whose two-body impact rebounds with exactly ``e``: the root in (0, 1/e) of
    ``chi (1 + e) = ln((1 + chi) / (1 - chi e))``; 0 for e = 1.

    For e >= 0.9 (chi < 0.2) the equation divided by chi^2 is solved as a power series,
    which avoids the cancellation of its terms. Otherwise the unknown is
    ``s = -ln(1 - chi e)``, ``chi = (1 - exp(-s)) / e``: as e -> 0 the root approaches 1/e
    closer than double precision resolves chi e (1 - chi e ~ exp(-1/e) / e), but s stays a
    well-scaled number, so chi is found to full precision for any e in (0, 1).
    """
    e = float(e)
    if not 0.0 < e <= 1.0:
        raise ValueError(f"restitution must be in (0, 1], got {e!r}")
    if e == 1.0:
        return 0.0
    from scipy.optimize import brentq

    if e >= 0.9:
        # h(0) = (1 - e^2)/2 > 0; h(1/4) < 0 for e >= 0.9
        return brentq(lambda chi: _hc_series(chi, e), 0.0, 0.25, xtol=1e-17,
                      rtol=4.0 * _EPS, maxiter=200)

    def g(s):
        chi = -math.expm1(-s) / e
        return chi * (1.0 + e) - math.log1p(chi) - s

    # g(chi) = chi (1 + e) - ln(1 + chi) + ln(1 - chi e) starts at 0 with zero slope, is
    # convex up to chi = (1 - e) / (2 e) (so positive there) and falls to -inf at 1/e, where
    # g < (1 + e)/e - ln(1 + 1/e) - s: one root in between.
    s_lo = -math.log(0.5 * (1.0 + e))
    s_hi = (1.0 + e) / e + 1.0
    s = brentq(g, s_lo, s_hi, xtol=1e-15, rtol=4.0 * _EPS, maxiter=200)
    return -math.expm1(-s) / e


# ---------------------------------------------------------------------------------------------
# Kelvin
# ---------------------------------------------------------------------------------------------

def kelvin_tension_restitution(zeta: float) -> float:
    """Restitution of ``k delta + c delta'`` kept in tension: exp(-zeta pi / sqrt(1 - zeta^2)),
    0 for zeta >= 1 (the overdamped decay never returns to delta = 0)."""
    if zeta >= 1.0:
        return 0.0
    return math.exp(-zeta * math.pi / math.sqrt(1.0 - zeta * zeta))


def _arccos_ratio(zeta: float) -> float:
    """arccos(zeta) / sqrt(1 - zeta^2), continued as arccosh(zeta) / sqrt(zeta^2 - 1)."""
    d = (1.0 - zeta) * (1.0 + zeta)
    if abs(d) < 1e-8:  # series about zeta = 1: 1 - (zeta - 1)/3 + 2 (zeta - 1)^2 / 15
        x = zeta - 1.0
        return 1.0 - x / 3.0 + 2.0 * x * x / 15.0
    if d > 0.0:
        return math.acos(zeta) / math.sqrt(d)
    return math.acosh(zeta) / math.sqrt(-d)


def kelvin_clipped_restitution(zeta: float) -> float:
    """Restitution of ``max(0, k delta + c delta')``: the force reaches zero where the free
    decay x = exp(-zeta t) sin(w t) / w (w = sqrt(1 - zeta^2), unit frequency and approach
    velocity) has its inflexion, w t = 2 arccos(zeta), and the velocity there is
    -exp(-2 zeta arccos(zeta) / w); the floors then separate at that velocity."""
    if zeta <= 0.0:
        return 1.0
    return math.exp(-2.0 * zeta * _arccos_ratio(zeta))


@lru_cache(maxsize=256)
def kelvin_clipped_zeta(e: float) -> float:
    """The damping ratio with which the clipped Kelvin law rebounds with exactly ``e``."""
    e = float(e)
    if e >= 1.0:
        return 0.0
    from scipy.optimize import brentq

    target = -math.log(e)
    # -ln e(zeta) = 2 zeta g(zeta) increases from 0; above zeta = 1 it exceeds 2 ln(2 zeta),
    # so zeta = max(1, 1 / sqrt(e)) brackets the root
    hi = max(1.0, 1.0 / math.sqrt(e))
    return brentq(lambda z: 2.0 * z * _arccos_ratio(z) - target, 0.0, hi, xtol=1e-15,
                  rtol=4.0 * _EPS, maxiter=200)


# ---------------------------------------------------------------------------------------------
# Jankowski
# ---------------------------------------------------------------------------------------------

@lru_cache(maxsize=1024)
def jankowski_restitution(zeta: float) -> float:
    """Restitution of Jankowski's law for damping ratio ``zeta``.

    Integrates the compression x'' = -x^1.5 - 2 zeta x^(1/4) x' from x = 0, x' = 1 to the
    maximum penetration x_m (x' = 0) with DOP853 (rtol 1e-12, accurate to ~1e-11 in e); the
    restitution is elastic, so e = sqrt(4/5) x_m^(5/4)."""
    if zeta <= 0.0:
        return 1.0
    from scipy.integrate import solve_ivp

    def rhs(t, y):
        x = y[0] if y[0] > 0.0 else 0.0
        return [y[1], -x * math.sqrt(x) - 2.0 * zeta * math.sqrt(math.sqrt(x)) * y[1]]

    def stopped(t, y):
        return y[1]

    stopped.terminal, stopped.direction = True, -1
    # the undamped compression lasts 1.47 (units of the approach); damping shortens it
    sol = solve_ivp(rhs, (0.0, 10.0), [0.0, 1.0], method="DOP853", rtol=1e-12, atol=1e-15,
                    events=stopped)
    if sol.status != 1:  # pragma: no cover - the compression always ends
        raise RuntimeError(f"Jankowski compression did not end (zeta = {zeta})")
    x_max = float(sol.y_events[0][0][0])
    return math.sqrt(0.8) * x_max**1.25


@lru_cache(maxsize=256)
def jankowski_zeta_exact(e: float) -> float:
    """The damping ratio with which Jankowski's law rebounds with exactly ``e`` (to ~1e-10)."""
    e = float(e)
    if e >= 1.0:
        return 0.0
    from scipy.optimize import brentq

    # e(zeta) falls from 1 at zeta = 0, as ~0.55 / zeta for large zeta: 1/e brackets the root
    hi = 1.0 / e
    while jankowski_restitution(hi) >= e:  # pragma: no cover - a safeguard
        hi *= 2.0
    return brentq(lambda z: jankowski_restitution(z) - e, 0.0, hi, xtol=1e-13, rtol=1e-13,
                  maxiter=200)
