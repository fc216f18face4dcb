"""Demand quantities of a single run, from its result (a Dataset of :func:`pframe.solve` or
:func:`pframe.open`): what fragility and loss studies read (docs/netcdf.md#demand-quantities).

- residual drift per storey: the drift at the end of the run, with a judgement of whether the
  structure still moves strongly then (:func:`residual_drift`);
- yield drift and yield force of a yielding storey, from its material (``governing``:
  ``u_y``, or the Bouc-Wen ``z_y``) (:func:`yield_properties`);
- hysteretic energy per storey from its force and drift histories, and the Park-Ang damage
  index DI = d_max / d_u + beta E_h / (F_y d_u) (Park & Ang 1985) (:func:`park_ang`);
- the storey shear attributable to contact forces (:func:`impact_storey_shear`);
- a table of impacts (:func:`impacts`).

Everything is computed from the recorded histories, in SI units (a file written in another
unit system, docs/units.md, is read back in SI: the scene's yield and ultimate drifts are); what
a quantity needs and the run did not record is named in the error (or the summary's warning).
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from pframe.episodes import positive_runs
from pframe.errors import InputError

#: the final share of a run over which residual drift is judged (see residual_drift)
TAIL_SHARE = 0.1
#: a storey whose drift still swings by more than this share of its peak drift over the tail
#: "still moves strongly": its final drift is not a permanent drift
TAIL_SWING = 0.1


def _text(value) -> str:
    return value.decode("utf-8") if isinstance(value, bytes) else str(value)


def _dimensionless(ds) -> bool:
    return _text(ds.attrs.get("units_system", "")) == "dimensionless"


def _system(ds):
    """The unit system of a result (None: dimensionless)."""
    from pframe.units import SYSTEMS

    name = _text(ds.attrs.get("units_system", "")) or "N-m-kg"
    if name == "dimensionless":
        return None
    if name not in SYSTEMS:
        raise InputError(f"the result is written in units_system {name!r}, which this pframe "
                         f"does not know ({', '.join(SYSTEMS)})")
    return SYSTEMS[name]


def in_file_units(ds, value, si_units: str) -> tuple:
    """(value, units) of an SI value as the result ``ds`` writes its quantities (its unit
    system's; SI in a dimensionless file, whose demands are not computed)."""
    from pframe.nondim.output import OutputUnits
    from pframe.units import SI

    convert = OutputUnits(system=_system(ds) or SI)
    return convert.variable(value, si_units, "")[:2]


def si_factor(ds, si_units: str) -> float:
    """The SI value of one unit of a quantity of SI units ``si_units`` (``"m"``, ``"N"``) as
    the result ``ds`` writes it: 1 in SI and in a dimensionless file, else its unit system's
    (``units_system``; docs/units.md).

    Raises
    ------
    InputError
        For a unit system pframe does not know (a file of a later version).
    """
    from pframe.nondim.dimensions import parse_units

    system = _system(ds)
    return 1.0 if system is None else system.factor(*parse_units(si_units).exponents)


def _history(ds, name: str):
    """(times, values (K, width)) of a recorded history, in SI (:func:`si_factor`), or
    None."""
    if name not in ds.data_vars:
        return None
    var = ds[name]
    if var.ndim != 2 or not var.dims[0].startswith("t"):
        return None
    from pframe.quantities import QUANTITIES

    factor = si_factor(ds, QUANTITIES[name][1]) if name in QUANTITIES else 1.0
    values = np.asarray(var.values, float)
    return (np.asarray(ds[var.dims[0]].values, float),
            values if factor == 1.0 else values * factor)


def _need(ds, names, what: str, where: str):
    missing = [n for n in names if _history(ds, n) is None]
    if missing:
        raise InputError(f"{where}: {what} needs the histories of {', '.join(missing)}; add "
                         f"them to a 'kind: history' recorder (every: 1 for the impacts' "
                         f"onsets, peaks and durations to the step)")


def _dataset(result):
    """The Dataset of ``result`` (a Dataset, or a result file's path, read whole) with the
    names as coordinates."""
    from pframe.api import result_dataset

    return result_dataset(result, "pframe.impacts")


def scene_of(ds, where: str = "the result"):
    """The loaded scene a result holds (its ``input_yaml``)."""
    from pframe.api import scene_of_attributes

    return scene_of_attributes(dict(ds.attrs), where, Path("."))


# ---------------------------------------------------------------------------------------------
# residual drift
# ---------------------------------------------------------------------------------------------

def residual_drift(ds) -> tuple[np.ndarray, np.ndarray] | None:
    """(residual drift per storey, swing over the tail per storey) from the ``story_drift``
    history, or None without it. The residual drift is the last recorded drift; the swing is
    half the range of the drift over the last :data:`TAIL_SHARE` of the run. A swing above
    :data:`TAIL_SWING` of the storey's peak drift means the run ended while the storey still
    moved strongly: its final drift is then not the permanent drift (give the motion a
    free-vibration tail; docs/netcdf.md#demand-quantities)."""
    h = _history(ds, "story_drift")
    if h is None:
        return None
    t, d = h
    finite = np.all(np.isfinite(d), axis=1)
    if not finite.any():
        return None
    t, d = t[finite], d[finite]
    tail = d[t >= t[-1] - TAIL_SHARE * (t[-1] - t[0])]
    return d[-1].copy(), 0.5 * (tail.max(axis=0) - tail.min(axis=0))


def still_moving(residual, swing, peak) -> np.ndarray:
    """(s,) bool: storeys whose drift still swings strongly at the end of the run."""
    return np.asarray(swing) > TAIL_SWING * np.maximum(np.asarray(peak), 1e-300)


# ---------------------------------------------------------------------------------------------
# yielding storeys
# ---------------------------------------------------------------------------------------------

def yield_properties(story) -> tuple[float, float] | None:
    """(yield drift, yield force) of an expanded storey whose material yields (its
    ``governing`` names a yield drift ``u_y``, or the Bouc-Wen ``z_y``), in SI units; None for
    a material that does not yield (elastic, viscous, Kelvin-Voigt, a friction bearing)."""
    governing = getattr(story.law, "governing", None)
    if governing is None:
        return None
    try:
        numbers = governing(story.packed)
    except (TypeError, ValueError, ZeroDivisionError):
        return None
    drift = numbers.get("u_y", numbers.get("z_y"))
    stiffness = numbers.get("K")
    if drift is None or stiffness is None or not np.isfinite(drift[1]):
        return None
    return float(drift[1]), float(stiffness[1] * drift[1])


# ---------------------------------------------------------------------------------------------
# hysteretic energy and the Park-Ang index
# ---------------------------------------------------------------------------------------------

def hysteretic_energy(force, drift, stiffness) -> np.ndarray:
    """E_h of each storey (columns): the work of the storey force along the drift history
    (trapezoid, as the kernel books ``energy_storeys``) less the elastic energy still stored
    at the end, F_end^2 / (2 K) with K the initial stiffness: the energy dissipated by
    yielding. ``force``, ``drift``: (K, s); ``stiffness``: (s,)."""
    force, drift = np.asarray(force, float), np.asarray(drift, float)
    work = np.sum(0.5 * (force[1:] + force[:-1]) * np.diff(drift, axis=0), axis=0)
    return work - force[-1] ** 2 / (2.0 * np.asarray(stiffness, float))


def park_ang_index(peak_drift, ultimate_drift, beta, energy, yield_force) -> np.ndarray:
    """DI = d_max / d_u + beta E_h / (F_y d_u) (Park & Ang 1985)."""
    return (np.asarray(peak_drift) / ultimate_drift
            + beta * np.asarray(energy) / (np.asarray(yield_force) * ultimate_drift))


def park_ang(ds, loaded=None) -> dict[str, dict]:
    """Per storey name: hysteretic energy ``energy`` (J) and, for the storeys of a building
    with ``park_ang``, the damage index ``index`` with its terms; from the ``story_force`` and
    ``story_drift`` histories (recorded at every step: the loops' area is integrated between
    samples). Raises InputError naming what is missing."""
    where = "the Park-Ang damage index"
    if _dimensionless(ds):
        raise InputError(f"{where} is computed on results in SI units, not a dimensionless "
                         "one: run the scene with output.units: si")
    _need(ds, ("story_force", "story_drift"), where, "the result")
    loaded = loaded or scene_of(ds)
    ex = loaded.expanded
    _, force = _history(ds, "story_force")
    _, drift = _history(ds, "story_drift")
    finite = np.all(np.isfinite(force), axis=1) & np.all(np.isfinite(drift), axis=1)
    force, drift = force[finite], drift[finite]
    names = [str(n) for n in ds["story"].values] if "story" in ds.coords else [
        s.name for s in ex.stories]
    by_name = {s.name: (i, s) for i, s in enumerate(ex.stories)}
    stiffness = np.array([_stiffness(by_name[n][1]) for n in names])
    energy = hysteretic_energy(force, drift, stiffness)
    peak = np.max(np.abs(drift), axis=0)
    out = {}
    specs = _park_ang_specs(loaded)
    for col, name in enumerate(names):
        i, story = by_name[name]
        row = {"energy": float(energy[col]), "peak_drift": float(peak[col])}
        spec, du = specs.get(name, (None, None))
        props = yield_properties(story)
        if spec is not None and props is not None:
            row |= {"ultimate_drift": du, "beta": float(spec.beta), "yield_force": props[1],
                    "index": float(park_ang_index(peak[col], du, spec.beta, energy[col],
                                                  props[1]))}
        out[name] = row
    return out


def _park_ang_specs(loaded) -> dict:
    """Storey name -> (its ParkAng, its ultimate drift): a building's (one value, or one per
    storey bottom up) or a generic storey's own."""
    from pframe.model.scene import default_story_name

    out = {}
    names = {story.name for story in loaded.expanded.stories}
    for building in loaded.scene.buildings:
        spec = building.park_ang
        level = 0
        while spec is not None and f"{building.name}/{level + 1}" in names:  # bottom up
            du = spec.ultimate_drift
            out[f"{building.name}/{level + 1}"] = (
                spec, float(du[level] if isinstance(du, list) else du))
            level += 1
    for story in loaded.scene.stories:
        if story.park_ang is not None:
            name = story.name or default_story_name(story.nodes)
            out[name] = (story.park_ang, float(story.park_ang.ultimate_drift))
    return out


def _stiffness(story) -> float:
    governing = getattr(story.law, "governing", None)
    numbers = governing(story.packed) if governing is not None else {}
    k = numbers.get("K")
    return float(k[1]) if k is not None else np.inf  # no K: no stored energy is removed


# ---------------------------------------------------------------------------------------------
# contacts: the storey shear they cause, and the impacts
# ---------------------------------------------------------------------------------------------

def _contact_loads(ex) -> np.ndarray:
    """(c, n): the force on each node of one unit of each contact's force (compression
    positive): the left side pushed back (-), the right side forward (+); a floor-to-column
    side shares it between the floors of the struck storey (psi, 1 - psi); a wall's side is
    the ground."""
    n = len(ex.node_names)
    out = np.zeros((len(ex.contacts), n))
    for e, c in enumerate(ex.contacts):
        for side, sign in ((0, -1.0), (1, 1.0)):
            node, lower, psi = c.nodes[side], c.lower[side], c.share[side]
            if node >= 0:
                out[e, node] += sign * psi
            if psi != 1.0 and lower >= 0:
                out[e, lower] += sign * (1.0 - psi)
    return out


def _above(ex) -> np.ndarray:
    """(s, n) bool: the nodes each storey carries (its upper node and every node reached
    upward from it through storeys)."""
    upward = {}
    for s in ex.stories:
        upward.setdefault(s.nodes[0], []).append(s.nodes[1])
    out = np.zeros((len(ex.stories), len(ex.node_names)), bool)
    for i, s in enumerate(ex.stories):
        todo = [s.nodes[1]]
        while todo:
            node = todo.pop()
            if node >= 0 and not out[i, node]:
                out[i, node] = True
                todo.extend(upward.get(node, []))
    return out


def impact_storey_shear(ds, loaded=None) -> np.ndarray:
    """(K, s) the storey shear attributable to contact forces (storeys in the result's
    order): the resultant of the contact forces on the floors a storey carries,
    V_c,i(t) = sum_{j above i} F_c,j(t). It is the contact term of the storey's
    equilibrium V_i(t) = sum_{j above i} (F_c,j - m_j a_j^abs) (V_i the storey's material
    and damping shear), the inertia term being the other
    (docs/netcdf.md#demand-quantities). Needs the ``contact_force`` history."""
    _need(ds, ("contact_force",), "the impact storey shear", "the result")
    loaded = loaded or scene_of(ds)
    ex = loaded.expanded
    _, force = _history(ds, "contact_force")
    contacts = _order(ds, "contact", [c.name for c in ex.contacts])
    stories = _order(ds, "story", [s.name for s in ex.stories])
    loads = _contact_loads(ex)[contacts]
    return np.nan_to_num(force) @ loads @ _above(ex)[stories].T.astype(float)


def _order(ds, dim: str, declared: list[str]) -> list[int]:
    """The declared elements in the order of the result's ``dim`` (its columns)."""
    if dim not in ds.coords:
        return list(range(len(declared)))
    return [declared.index(str(n)) for n in ds[dim].values]


#: the impact table's columns and units
IMPACT_COLUMNS = (("contact", ""), ("onset", "s"), ("approach_velocity", "m/s"),
                  ("peak_force", "N"), ("duration", "s"), ("impulse", "N s"),
                  ("column_shear", "N"), ("closed_at_start", ""), ("closed_at_end", ""))


def impacts(result):
    """The impacts of a run as a pandas DataFrame, one row per contact episode in time order,
    in SI units whatever the result's (docs/units.md; ``pframe summary`` shows them in the
    result's): ``contact``, ``onset`` (s), ``approach_velocity`` (the penetration rate at onset, m/s),
    ``peak_force`` (N), ``duration`` (onset to separation, s), ``impulse`` (the time integral
    of the contact force, N s), ``column_shear`` (N: the peak shear a floor-to-column
    contact's impact put into the struck column, ``Element.column_weight`` times its peak force;
    NaN for a floor-to-floor contact), and whether the episode was already closed at the first
    sample (``closed_at_start``: no onset, approach velocity NaN) or still closed at the last
    (``closed_at_end``: duration NaN). ``result``: a Dataset or a result file's path.

    From the recorded histories of ``contact_force`` and ``velocity`` (and
    ``contact_penetration`` when recorded, for onsets and separations to second order); an
    episode is a run of samples with a positive contact force. Onset and separation are
    located between samples (from the penetration and its rate when recorded, else from the
    force), so the duration, impulse and approach velocity are exact to O(dt^2) for a
    history recorded at every step; peaks are those of the samples."""
    import pandas as pd

    ds = _dataset(result)
    where = str(result) if isinstance(result, (str, Path)) else "the Dataset"
    if _dimensionless(ds):
        raise InputError(f"{where}: the impact table is computed on results in SI units, not "
                         "a dimensionless one: run the scene with output.units: si")
    if "contact" not in ds.dims:
        return pd.DataFrame(columns=[c for c, _ in IMPACT_COLUMNS])
    _need(ds, ("contact_force", "velocity"), "the impact table", where)
    loaded = scene_of(ds, where)
    ex = loaded.expanded
    t, force = _history(ds, "contact_force")
    tv, velocity = _history(ds, "velocity")
    if tv.shape != t.shape or not np.array_equal(tv, t):
        raise InputError(f"{where}: the impact table needs contact_force and velocity "
                         "recorded at the same steps (one history recorder for both)")
    pen = _history(ds, "contact_penetration")
    pen = pen[1] if pen is not None and np.array_equal(pen[0], t) else None
    loads = _contact_loads(ex)  # the contact point's rate is -(loads @ v) (left - right)
    names = [str(n) for n in ds["contact"].values] if "contact" in ds.coords else [
        c.name for c in ex.contacts]
    by_name = {c.name: e for e, c in enumerate(ex.contacts)}
    rows = []
    for col, name in enumerate(names):
        e = by_name[name]
        rate = -(velocity @ loads[e])
        rows += _episodes(name, t, np.nan_to_num(force[:, col]), rate,
                          None if pen is None else pen[:, col], ex.contacts[e].column_weight)
    table = pd.DataFrame(rows, columns=[c for c, _ in IMPACT_COLUMNS])
    return table.sort_values(["onset", "contact"], kind="stable").reset_index(drop=True)


def _crossing(t0, t1, s0, s1) -> float:
    """Where the linear interpolation of s between (t0, s0) and (t1, s1) is zero."""
    return t0 + (t1 - t0) * s0 / (s0 - s1) if s0 != s1 else 0.5 * (t0 + t1)


def _episodes(name, t, f, rate, pen, weight=None) -> list[tuple]:
    rows = []
    for i, j in positive_runs(f):
        closed_start, closed_end = i == 0, j == len(t) - 1
        if closed_start:
            onset, approach = float(t[0]), float("nan")
        else:
            if pen is not None and pen[i] > 0.0:
                # pen(t_i) = the integral of the rate from the onset: trapezoid between the
                # rate before the onset (r_{i-1}, the free flight's) and r_i
                mean = 0.5 * (rate[i - 1] + rate[i])
                onset = t[i] - pen[i] / mean if mean > 0 else t[i - 1]
            else:
                onset = _crossing(t[i - 1], t[i], 0.0, f[i]) if j == i else (
                    t[i] - f[i] * (t[i + 1] - t[i]) / max(f[i + 1] - f[i], 1e-300))
            onset = float(min(max(onset, t[i - 1]), t[i]))
            approach = float(rate[i - 1])  # the free flight's rate, to O(dt) of its change
            if i >= 2:  # ... extrapolated to the onset
                approach += (onset - t[i - 1]) * (rate[i - 1] - rate[i - 2]) / (t[i - 1] - t[i - 2])
        if closed_end:
            end = float("nan")
        else:
            if pen is not None and pen[j] > 0.0:
                mean = -0.5 * (rate[j] + rate[j + 1])
                end = t[j] + pen[j] / mean if mean > 0 else 0.5 * (t[j] + t[j + 1])
            else:
                end = (t[j] + f[j] * (t[j] - t[j - 1]) / max(f[j - 1] - f[j], 1e-300)
                       if j > i else 0.5 * (t[j] + t[j + 1]))
            end = float(min(max(end, t[j]), t[j + 1]))
        ts = np.concatenate(([onset], t[i:j + 1], [] if closed_end else [end]))
        fs = np.concatenate(([0.0 if not closed_start else f[i]], f[i:j + 1],
                             [] if closed_end else [0.0]))
        impulse = float(np.sum(0.5 * (fs[1:] + fs[:-1]) * np.diff(ts)))
        peak = float(f[i:j + 1].max())
        rows.append((name, onset, approach, peak, end - onset, impulse,
                     float("nan") if weight is None else weight * peak,
                     bool(closed_start), bool(closed_end)))
    return rows

