"""How a ground motion was read and what a run applies: format, samples, step, units (and
where they were read), the PGA after every scaling, when it occurs, and what part of the motion
the analysis covers.

``pframe validate`` and ``pframe solve`` print these facts for the excitation of every scene
(and every record a sweep uses), and the result file keeps them, so that the motion a run
applied can be confirmed before (and after) it::

    from pframe.excitation.describe import describe_record, describe_line, applied_motion

    facts = describe_record("records/A-ELC180.AT2", pga=4.0)
    print(describe_line(facts, duration=40.0))   # A-ELC180.AT2: PEER .AT2, 4000 points, ...
    applied_motion(scene.excitation, expanded.record, duration)   # any kind of excitation
"""

from __future__ import annotations

import hashlib
import math
from pathlib import Path
from types import SimpleNamespace

import numpy as np

from pframe.units import STANDARD_GRAVITY as G
from pframe.yamltext import read_bounded_bytes

#: how the two formats are named in messages
FORMAT_NAMES = {"at2": "PEER NGA .AT2", "columns": "two columns (time, acceleration)"}
#: a motion is "cut before its peak" when the analysis applies less than this part of it
PEAK_COVERED = 0.999


def record_format(path: str | Path, format: str = "auto") -> str:
    """``at2`` or ``columns``: the format a record file is read as. ``auto`` chooses by the
    suffix, in any case (``.AT2``, ``.at2``, ``.At2``): PEER for ``.at2``, else columns."""
    if format != "auto":
        return format
    return "at2" if Path(path).suffix.lower() == ".at2" else "columns"


def _get(excitation, name, default=None):
    if isinstance(excitation, dict):
        return excitation.get(name, default)
    return getattr(excitation, name, default)


def describe_scene_record(excitation, base_dir: str | Path = ".", file=None) -> dict:
    """:func:`describe_record` of a scene's record excitation (a model object or its YAML
    mapping), every scaling it states included; ``file`` replaces its file (a sweep's)."""
    path = Path(file) if file is not None else Path(base_dir) / _get(excitation, "file")
    return describe_record(path, _get(excitation, "format", "auto"),
                           _get(excitation, "units"), _get(excitation, "scale", 1.0),
                           pga=_get(excitation, "pga"), frequency=_get(excitation, "frequency"),
                           period=_get(excitation, "period", "mean"), within=base_dir)


def describe_record(path: str | Path, format: str = "auto", units: str | None = None,
                    scale: float = 1.0, *, pga: float | None = None,
                    frequency: float | None = None, period="mean", within=None) -> dict:
    """The facts of one record file as pframe reads and applies it.

    Parameters
    ----------
    path : str or Path
        The record file.
    format : {"auto", "at2", "columns"}
        As the scene's ``excitation.format``.
    units : str or None
        As the scene's ``excitation.units`` (None: the header's, else g for PEER files and
        m/s^2 otherwise).
    scale, pga, frequency, period :
        The scene's ``excitation.scale``, ``pga`` (target PGA, m/s^2), ``frequency`` (target
        characteristic circular frequency, rad/s) and ``period`` (how that is found).
    within : str or Path, optional
        The folder of the file that names the record: a message quotes the record's text
        only when it lies inside (as :func:`pframe.excitation.records.read_record`).

    Returns
    -------
    dict
        Of the file: ``file`` (str, the path as given), ``sha256`` (hex digest of the file's
        bytes), ``format`` (``"at2"`` or ``"columns"``), ``units`` (the units its values were
        read in, a name of :data:`pframe.excitation.records.UNITS`), ``units_from``
        (``"header, line N"``, ``"scene"`` or ``"default"``), ``units_header`` (the units text
        of the header, or None), ``points`` (int), ``step`` (float s; the mean step when the
        times are uneven), ``uniform`` (bool, every step equals ``step`` to 1e-6 relative),
        ``start`` and ``duration`` (float s: first time and last minus first), ``file_pga``
        (m/s^2) and ``file_pga_time`` (s).
        As applied: ``scale``, ``target_pga`` and ``frequency`` (as given, or None),
        ``amplitude_factor`` and ``time_factor`` (what the file's accelerations, ``scale``
        apart, and times were multiplied by), ``pga`` (float m/s^2, the peak absolute ground
        acceleration after units and every scaling), ``pga_g`` (the same in g, g = 9.80665
        m/s^2), ``pga_time`` (float s, when it occurs on the applied time axis) and ``end``
        (s, when the applied record ends).

    Raises
    ------
    FileNotFoundError, ValueError
        As :func:`pframe.excitation.records.read_record`.
    """
    from pframe.excitation.records import MAX_RECORD_BYTES, read_record_file

    path = Path(path)
    content = read_bounded_bytes(path, "record", MAX_RECORD_BYTES)  # a FIFO is never read
    kind = record_format(path, format)
    read = read_record_file(path, kind, units, within)
    times, acceleration = read.times, np.asarray(read.acceleration, dtype=float)
    steps = np.diff(times)
    step = float(np.mean(steps)) if steps.size else 0.0
    file_peak = int(np.argmax(np.abs(acceleration))) if acceleration.size else 0
    amplitude_factor, time_factor = 1.0, 1.0
    if pga is not None or frequency is not None:
        from pframe.excitation.characteristic import apply_record

        applied = apply_record(SimpleNamespace(pga=pga, frequency=frequency, period=period,
                                               scale=scale), times, acceleration)
        amplitude_factor, time_factor = applied.amplitude_factor, applied.time_factor
    values = acceleration * amplitude_factor * scale
    peak = int(np.argmax(np.abs(values))) if values.size else 0
    peak_value = float(abs(values[peak])) if values.size else 0.0
    return {
        "file": str(path),
        "sha256": hashlib.sha256(content).hexdigest(),
        "format": kind,
        "units": read.units,
        "units_from": read.units_from,
        "units_header": read.header,
        "points": int(times.size),
        "step": step,
        "uniform": bool(steps.size == 0 or np.allclose(steps, step, rtol=1e-6, atol=0.0)),
        "start": float(times[0]) if times.size else 0.0,
        "duration": float(times[-1] - times[0]) if times.size else 0.0,
        "file_pga": float(abs(acceleration[file_peak])) if acceleration.size else 0.0,
        "file_pga_time": float(times[file_peak]) if times.size else 0.0,
        "scale": float(scale),
        "target_pga": None if pga is None else float(pga),
        "frequency": None if frequency is None else float(frequency),
        "amplitude_factor": float(amplitude_factor),
        "time_factor": float(time_factor),
        "pga": peak_value,
        "pga_g": peak_value / G,
        "pga_time": float(times[peak] * time_factor) if times.size else 0.0,
        "end": float(times[-1] * time_factor) if times.size else 0.0,
    }


def _units_clause(facts: dict) -> str:
    from pframe.excitation.records import UNIT_NAMES

    name = UNIT_NAMES.get(facts["units"], facts["units"])
    where = facts.get("units_from", "default")
    if where.startswith("header"):
        return f"units {name} as its header states ({where.removeprefix('header, ')}, " \
               f"{facts['units_header']!r})"
    if where == "scene":
        said = (f"; the header's {facts['units_header']!r} is not a unit pframe reads"
                if facts.get("units_header") else "; the file states none")
        return f"units {name} as the scene states{said}"
    return f"units {name} by default: the file states none (give excitation.units if they " \
           "are not)"


def _g(value: float) -> str:
    return f"{value:.4g} m/s^2 ({value / G:.4g} g)"


def describe_line(facts: dict, duration: float | None = None) -> str:
    """One line of :func:`describe_record`'s facts; with the analysed ``duration`` (s), what
    part of the record the analysis covers."""
    from pframe.excitation.records import UNIT_NAMES

    step = f"dt = {facts['step']:.6g} s" if facts["uniform"] else \
        f"uneven steps (mean {facts['step']:.6g} s)"
    units = "g" if facts["units"] == "g" else UNIT_NAMES.get(facts["units"], facts["units"])
    line = (f"record {facts['file']}: {FORMAT_NAMES[facts['format']]} in {units}, "
            f"{facts['points']} points, {step}, {facts['duration']:.6g} s; ")
    target, frequency = facts.get("target_pga"), facts.get("frequency")
    if target is None and frequency is None:
        scaled = f" x {facts['scale']:g}" if facts["scale"] != 1.0 else ""
        line += f"PGA{scaled} {_g(facts['pga'])} at t = {facts['pga_time']:.4g} s"
    else:
        how = []
        if target is not None:
            how.append(f"scaled to pga {target:g} m/s^2 (x {facts['amplitude_factor']:.4g})")
        if facts["scale"] != 1.0:
            how.append(f"x {facts['scale']:g}")
        if frequency is not None:
            how.append(f"time x {facts['time_factor']:.4g} for frequency {frequency:g} rad/s, "
                       f"the record lasts {facts['end']:.6g} s")
        line += (f"PGA applied {_g(facts['pga'])} at t = {facts['pga_time']:.4g} s "
                 f"({'; '.join(how)}; the file's PGA {_g(facts['file_pga'])} at t = "
                 f"{facts['file_pga_time']:.4g} s)")
    line += f"; {_units_clause(facts)}; sha256 {facts['sha256'][:12]}"
    if duration is not None:
        line += "; " + coverage(facts, duration, "record")
    return line


def coverage(facts: dict, duration: float, what: str) -> str:
    """What part of a motion of ``facts`` (``end``, ``pga``, ``pga_time``) an analysis of
    ``duration`` (s) applies."""
    end = facts["end"]
    if not math.isfinite(end):
        return f"the analysis applies it for {duration:g} s"
    if duration < end - 1e-9:
        text = f"the analysis ({duration:g} s) stops before the {what} ends (at {end:.6g} s)"
        if duration < facts["pga_time"]:
            text += f" and before its PGA (t = {facts['pga_time']:.4g} s)"
        return text
    if duration > end + 1e-9:
        return f"the ground is at rest after {end:.6g} s of the {duration:g} s analysed"
    return f"the analysis ({duration:g} s) covers the whole {what}"


def applied_motion(excitation, record=None, duration: float | None = None) -> dict | None:
    """The ground motion a scene's excitation applies, for every kind; None without one.

    Parameters
    ----------
    excitation : Sine, Record, a pulse or None
        The scene's excitation.
    record : AppliedRecord, optional
        For a record: the record as applied (``Expanded.record``: ``pga`` and ``frequency``
        done; ``scale`` is applied here).
    duration : float, optional
        The analysis duration (s).

    Returns
    -------
    dict
        ``kind``, ``description`` (the motion in words), ``amplitude`` (m/s^2: the sine's or
        pulse's a_p, a record's PGA), ``pga`` (m/s^2, the peak |a_g| of the whole motion),
        ``pga_g``, ``pga_time`` (s, its first time), ``end`` (s, when the ground comes to
        rest for good; inf for a sine without end), ``duration`` (s or None) and, with a
        duration, ``applied_peak`` (m/s^2, the peak |a_g| within the analysis) and
        ``cut_before_peak`` (bool: the analysis applies less than 0.999 of the PGA).
    """
    if excitation is None:
        return None
    if record is None and excitation.kind not in ("record", "stochastic"):
        # a sine or a pulse: a function of its fields and the duration alone, the same for
        # every variant of a sweep that leaves them (its peak search costs milliseconds)
        key = (type(excitation).__name__, excitation.model_dump_json(), duration)
        return dict(_analytic_motion(key, excitation, duration))
    return _applied_motion(excitation, record, duration)


_ANALYTIC: dict = {}


def _analytic_motion(key, excitation, duration):
    facts = _ANALYTIC.get(key)
    if facts is None:
        if len(_ANALYTIC) > 256:
            _ANALYTIC.clear()
        facts = _ANALYTIC[key] = _applied_motion(excitation, None, duration)
    return facts


def _applied_motion(excitation, record, duration):
    from pframe.excitation.sample import motion

    m = motion(excitation, record)
    kind = excitation.kind
    if kind in ("record", "stochastic"):
        times = np.asarray(m.breakpoints, dtype=float)
        values = np.abs(np.asarray(m(times), dtype=float))
        peak = int(np.argmax(values))
        pga, pga_time = float(values[peak]), float(times[peak])
        description = m.description
        if kind == "stochastic":
            from pframe.excitation.stochastic import arias_intensity

            arias = arias_intensity(m(times), float(times[1] - times[0]))
            description += f"; Arias intensity {arias:.4g} m/s"
        amplitude = pga
    else:
        horizon = m.end if math.isfinite(m.end) else 2.0 * math.pi / excitation.frequency
        pga, pga_time = _peak(m, horizon)
        amplitude = abs(float(excitation.amplitude))
        if kind == "sine":
            w = float(excitation.frequency)
            until = "without end" if not math.isfinite(m.end) else f"until t = {m.end:.6g} s"
            description = (f"sine a_p = {_g(float(excitation.amplitude))}, w_p = {w:g} rad/s (T = "
                           f"{2.0 * math.pi / w:.4g} s), {until}")
        else:
            name = "ricker" if kind == "ricker" else f"cycloidal type {excitation.type}" + (
                f"{excitation.n}" if excitation.type == "C" else "")
            description = (f"{name} pulse a_p = {_g(float(excitation.amplitude))}, T_p = "
                           f"{float(excitation.period):g} s, over 0-{m.end:.6g} s")
    facts = {"kind": kind, "description": description, "amplitude": amplitude, "pga": pga,
             "pga_g": pga / G, "pga_time": pga_time, "end": float(m.end), "duration": duration}
    if duration is not None:
        if kind in ("record", "stochastic"):
            inside = times <= duration
            applied = float(np.max(values[inside], initial=0.0))
            applied = max(applied, float(abs(m(float(duration))))) if duration < m.end \
                else applied
        elif duration >= horizon:  # the analysis covers the whole motion: its peak is the PGA
            applied = pga
        else:
            applied = _peak(m, duration)[0]
        facts["applied_peak"] = applied
        facts["cut_before_peak"] = bool(applied < PEAK_COVERED * pga)
    return facts


def _peak(m, horizon: float) -> tuple[float, float]:
    """(peak |a|, first time of it) of a smooth motion over [0, horizon]: on 20001 points and
    the breakpoints, then refined by a golden-section search around the best point."""
    if horizon <= 0.0:
        return float(abs(m(0.0))), 0.0
    grid = np.linspace(0.0, horizon, 20001)
    inside = [b for b in np.asarray(m.breakpoints, float) if 0.0 <= b <= horizon]
    if inside:  # (a sorted, distinct grid without them: union1d would only copy it)
        grid = np.union1d(grid, inside)
    values = np.abs(np.asarray(m(grid), dtype=float))
    finite = np.isfinite(values)
    if not finite.any():  # a motion that is nowhere a number (absurd inputs): no peak
        return float("nan"), 0.0
    values = np.where(finite, values, 0.0)
    hits = np.flatnonzero(values >= np.max(values) * (1.0 - 1e-6))
    k = int(hits[0]) if hits.size else int(np.argmax(values))  # the first peak...
    while k + 1 < values.size and values[k + 1] >= values[k]:  # ...at its top
        k += 1
    lo, hi = grid[max(k - 1, 0)], grid[min(k + 1, grid.size - 1)]
    best_t, best = float(grid[k]), float(values[k])
    ratio = (math.sqrt(5.0) - 1.0) / 2.0
    a, b = lo, hi
    for _ in range(60):
        c, d = b - ratio * (b - a), a + ratio * (b - a)
        if abs(m(c)) >= abs(m(d)):
            b = d
        else:
            a = c
    t = 0.5 * (a + b)
    if abs(m(t)) > best * (1.0 + 1e-12):
        best_t, best = float(t), float(abs(m(t)))
    return best, best_t


def _what(kind: str) -> str:
    """A motion of ``kind`` in words: record, sine, stochastic motion, ricker pulse."""
    if kind == "stochastic":
        return "stochastic motion"
    return kind if kind in ("record", "sine") else f"{kind} pulse"


def motion_line(facts: dict) -> str:
    """One line of :func:`applied_motion`'s facts (a sine, a pulse or a stochastic motion;
    records have :func:`describe_line`)."""
    peak = "PGA" if facts["kind"] == "stochastic" else "peak"
    line = (f"excitation: {facts['description']}; {peak} {_g(facts['pga'])} at t = "
            f"{facts['pga_time']:.4g} s")
    if facts.get("duration") is not None:
        kind = facts["kind"]
        line += "; " + coverage(facts, facts["duration"], _what(kind))
    return line


#: the largest peak ground acceleration a motion may have without a warning (m/s^2): above
#: any recorded (about 4.4 g, the 2008 Iwate-Miyagi earthquake at IWTH25, Aoi et al. 2008), so
#: beyond it the usual cause is a unit or a scale typed wrong (cm/s^2 read as m/s^2, a record
#: in g scaled by 9.81 twice)
PLAUSIBLE_PGA = 5.0 * G


def motion_warnings(facts: dict | None) -> list[str]:
    """Warnings about the motion a run applies: a peak ground acceleration beyond any
    recorded (:data:`PLAUSIBLE_PGA`), and the analysis stopping before the peak of a record
    or a pulse (it applies less than 0.999 of the PGA the scene asks for). A sine is not
    warned of stopping early: it reaches its amplitude every cycle, and a run shorter than a
    quarter of one is a choice."""
    if not facts:
        return []
    out = []
    if facts.get("pga", 0.0) > PLAUSIBLE_PGA:
        out.append(f"the ground motion's peak acceleration is {_g(facts['pga'])}, beyond any "
                   f"recorded earthquake's (about 4.4 g at most): check the units of the "
                   f"{_what(facts['kind'])} (m/s^2, or g for a PEER record) and its scale or "
                   "pga; the results are those of this motion")
    return out + _cut_warnings(facts)


def _cut_warnings(facts: dict) -> list[str]:
    if not facts.get("cut_before_peak") or facts["kind"] == "sine":
        return []
    what = _what(facts["kind"])
    needed = facts["pga_time"]
    return [f"the analysis stops at t = {facts['duration']:g} s, before the {what}'s peak "
            f"ground acceleration {_g(facts['pga'])} at t = {needed:.4g} s: the run applies "
            f"at most {_g(facts['applied_peak'])}. Set analysis.duration to at least "
            f"{needed:.4g} s (the {what} lasts {facts['end']:.6g} s) to apply the motion "
            "asked for"]
