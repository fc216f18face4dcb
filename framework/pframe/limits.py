"""Peak storey drift ratios and floor accelerations against limits (docs/modes.md#limits).

The limits are the scene's (``limits:``): a drift ratio and a floor acceleration the user
gives, or the allowable storey drift of a building code, :data:`ASCE7_22`. For each storey the
margin is ``limit - demand`` and the utilisation ``demand / limit``; a storey without a height
has no drift ratio, so its margin is NaN with the reason (never 0).

ASCE/SEI 7-22 section 12.12.1 holds the design story drift Delta of every storey to the
allowable story drift Delta_a of its Table 12.12-1, a multiple of the storey height h_sx by
risk category and structure; 12.12.1.1 divides Delta_a by the redundancy factor rho for
seismic force-resisting systems of moment frames alone in Seismic Design Categories D to F.
The code's Delta is the design story drift (Cd delta_xe / Ie, section 12.8.6, from an elastic
analysis under the design forces); a run's peak drift is that only when the run was made to
stand for it, and the code's nonlinear response-history procedure (chapter 16) compares the
mean over a suite of motions with a multiple of the table's limits (``factor``). pframe
compares the run's peak with the limit as given and says so with every result.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

#: standard gravity (m/s^2), for limits in g
G = 9.80665

#: ASCE/SEI 7-22 Table 12.12-1, allowable story drift Delta_a / h_sx by structure and risk
#: category (I or II, III, IV)
ASCE7_22 = {
    "low_rise": (0.025, 0.020, 0.015),
    "masonry_cantilever": (0.010, 0.010, 0.010),
    "masonry_other": (0.007, 0.007, 0.007),
    "other": (0.020, 0.015, 0.010),
}
#: what each row of :data:`ASCE7_22` is, in the table's words
STRUCTURES = {
    "low_rise": "structures, other than masonry shear wall structures, 4 stories or less "
                "above the base, with interior walls, partitions, ceilings and exterior wall "
                "systems designed to accommodate the story drifts",
    "masonry_cantilever": "masonry cantilever shear wall structures",
    "masonry_other": "other masonry shear wall structures",
    "other": "all other structures",
}
#: the clause cited with every code limit
SOURCE = "ASCE/SEI 7-22 section 12.12.1, Table 12.12-1"
#: the storeys above the base up to which the low-rise row applies (Table 12.12-1)
LOW_RISE_STOREYS = 4
COLUMN = {"I": 0, "II": 0, "III": 1, "IV": 2}


def code_ratio(structure: str, risk_category: str, storeys: int, redundancy: float = 1.0,
               factor: float = 1.0) -> tuple[float, str]:
    """(Delta_a / h_sx, why) of a building of ``storeys`` storeys above its base: the row of
    :data:`ASCE7_22` for ``structure`` (the low-rise row only up to 4 storeys: above, all
    other structures), the column of ``risk_category``, divided by ``redundancy`` (rho,
    12.12.1.1) and times ``factor``; NaN for a single-storey low-rise building, which the
    table's footnote c leaves without a limit."""
    row = structure
    said = f"{SOURCE}, risk category {risk_category}"
    if structure == "low_rise" and storeys > LOW_RISE_STOREYS:
        row = "other"
        said += (f", all other structures (the low-rise row stops at {LOW_RISE_STOREYS} "
                 f"storeys; this building has {storeys})")
    elif structure == "low_rise" and storeys == 1:
        return math.nan, (f"{SOURCE}: no drift limit for a single-storey structure whose "
                          "walls, partitions and ceilings are designed to accommodate the "
                          "story drifts (footnote c)")
    else:
        said += f", {STRUCTURES[row]}"
    ratio = ASCE7_22[row][COLUMN[risk_category]]
    if redundancy != 1.0:
        said += f", divided by rho = {redundancy:g} (12.12.1.1)"
    if factor != 1.0:
        said += f", times {factor:g}"
    return ratio / redundancy * factor, said + f": {ratio:g} h_sx"


@dataclass(frozen=True)
class Check:
    """The limits of a run and its demands against them, per storey and per node."""

    drift_limit: np.ndarray  # (s,) allowed drift ratio, NaN: none
    drift_demand: np.ndarray  # (s,) peak drift ratio, NaN: no height
    drift_why: tuple[str, ...]  # (s,) where each limit comes from, or why there is none
    acceleration_limit: float  # m/s^2, NaN: none
    acceleration_demand: np.ndarray  # (n,) peak absolute floor acceleration (m/s^2)
    acceleration_why: str
    story_names: tuple[str, ...]
    node_names: tuple[str, ...]

    @property
    def drift_margin(self) -> np.ndarray:
        return self.drift_limit - self.drift_demand

    @property
    def drift_utilisation(self) -> np.ndarray:
        with np.errstate(divide="ignore", invalid="ignore"):
            return self.drift_demand / self.drift_limit

    @property
    def acceleration_margin(self) -> np.ndarray:
        return self.acceleration_limit - self.acceleration_demand

    @property
    def acceleration_utilisation(self) -> np.ndarray:
        with np.errstate(divide="ignore", invalid="ignore"):
            return self.acceleration_demand / self.acceleration_limit

    def missing_heights(self) -> list[str]:
        """The storeys with a drift limit but no drift ratio (no height)."""
        return [n for n, lim, d in zip(self.story_names, self.drift_limit, self.drift_demand)
                if np.isfinite(lim) and not np.isfinite(d)]

    def exceeded(self) -> list[str]:
        """One line per storey or floor beyond its limit."""
        out = [f"storey {n}: peak drift ratio {100 * d:.3g} % exceeds its limit "
               f"{100 * lim:.3g} % (margin {100 * (lim - d):.3g} %)"
               for n, lim, d in zip(self.story_names, self.drift_limit, self.drift_demand)
               if d > lim]
        out += [f"floor {n}: peak absolute acceleration {a:.4g} m/s^2 ({a / G:.3g} g) exceeds "
                f"its limit {self.acceleration_limit:.4g} m/s^2 "
                f"({self.acceleration_limit / G:.3g} g)"
                for n, a in zip(self.node_names, self.acceleration_demand)
                if a > self.acceleration_limit]
        return out

    def lines(self) -> list[str]:
        """The terminal's lines: the tightest storey and floor, what is exceeded, what is not
        defined."""
        out = []
        if np.any(np.isfinite(self.drift_limit)):
            u = self.drift_utilisation
            if np.any(np.isfinite(u)):
                s = int(np.nanargmax(u))
                out.append(f"drift ratio limit: the tightest storey is {self.story_names[s]}, "
                           f"{100 * self.drift_demand[s]:.3g} % of {100 * self.drift_limit[s]:.3g}"
                           f" % allowed (margin {100 * self.drift_margin[s]:.3g} %, "
                           f"utilisation {u[s]:.3g}); limit: {self.drift_why[s]}")
            missing = self.missing_heights()
            if missing:
                out.append(f"drift ratio limit not checked at {', '.join(missing[:4])}"
                           f"{' ...' if len(missing) > 4 else ''}: no height (the drift ratio "
                           "is not defined; height on the storey gives it)")
        if np.isfinite(self.acceleration_limit) and self.acceleration_demand.size:
            n = int(np.nanargmax(self.acceleration_demand))
            a = self.acceleration_demand[n]
            out.append(f"floor acceleration limit: the largest is at {self.node_names[n]}, "
                       f"{a:.4g} m/s^2 of {self.acceleration_limit:.4g} m/s^2 allowed "
                       f"(margin {self.acceleration_limit - a:.4g} m/s^2, utilisation "
                       f"{a / self.acceleration_limit:.3g}); limit: {self.acceleration_why}")
        if any(w.startswith(SOURCE) for w in self.drift_why):
            out.append("note: Table 12.12-1 limits the design story drift (Cd delta_xe / Ie, "
                       "12.8.6); this run's peak is that only where the run was made to stand "
                       "for it (docs/modes.md#limits)")
        out += [f"LIMIT EXCEEDED: {line}" for line in self.exceeded()]
        return out


#: what every check says of the demand it compares
BASIS = ("the run's peak storey drift ratio (|drift| / height) and peak absolute floor "
         "acceleration (of a floor in plan, the larger of its centre of mass's peaks along x "
         "and y), against the limits as given")


def storey_limits(ex, limits) -> tuple[np.ndarray, tuple[str, ...]]:
    """(s,) the drift ratio allowed at each storey of an Expanded scene and where it comes
    from (NaN and why where there is none)."""
    count = len(ex.stories)
    if limits.drift_ratio is not None:
        return (np.full(count, float(limits.drift_ratio)),
                (f"given (limits.drift_ratio = {limits.drift_ratio:g})",) * count)
    if limits.code is None:
        return np.full(count, np.nan), ("no drift limit given",) * count
    code = limits.code
    floors = np.bincount(np.asarray(ex.node_building, dtype=int), minlength=len(ex.buildings))
    ratio, why = np.full(count, np.nan), []
    for s in range(count):
        b = int(ex.story_building[s])
        value, text = code_ratio(code.structure, code.risk_category, int(floors[b]),
                                 code.redundancy, code.factor)
        ratio[s] = value
        why.append(text)
    return ratio, tuple(why)


def evaluate(ex, plan, limits, envelope: dict, member: int = 0) -> Check:
    """The limits of ``limits`` (the scene's) against a run's envelopes (quantity -> (B, ...)
    peaks, as :class:`pframe.kernel.Result` holds them)."""
    ns = len(ex.stories)
    drift_limit, why = storey_limits(ex, limits)
    demand = np.full(ns, np.nan)
    if "story_drift_ratio" in envelope:
        demand = np.asarray(envelope["story_drift_ratio"][member], dtype=float)[:ns]
    acceleration = (limits.acceleration if limits.acceleration is not None else
                    limits.acceleration_g * G if limits.acceleration_g is not None else
                    math.nan)
    said = ("given" if limits.acceleration is not None else
            f"given ({limits.acceleration_g:g} g)" if limits.acceleration_g is not None else
            "no acceleration limit given")
    floors = np.full(len(plan.node_names), np.nan)
    if "absolute_acceleration" in envelope:
        peak = np.asarray(envelope["absolute_acceleration"][member], dtype=float)
        if plan.planar:
            floors = peak[plan.node_dof]
        else:
            for d in range(plan.n_dof):
                node, c = int(plan.dof_node[d]), int(plan.dof_component[d])
                if node >= 0 and c < 2:
                    floors[node] = np.fmax(floors[node], peak[d])
    return Check(drift_limit, demand, why, float(acceleration), floors, said,
                 tuple(e.name for e in ex.stories), tuple(plan.node_names))


def recorded(limits) -> tuple[str, ...]:
    """The envelopes a run with ``limits`` needs."""
    if limits is None:
        return ()
    out = []
    if limits.drift_ratio is not None or limits.code is not None:
        out += ["story_drift", "story_drift_ratio"]
    if limits.acceleration is not None or limits.acceleration_g is not None:
        out.append("absolute_acceleration")
    return tuple(out)
