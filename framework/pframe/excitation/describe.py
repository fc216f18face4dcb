"""How a ground-motion record was read: format, samples, step, duration, peak and units.

``pframe validate`` and ``pframe solve`` print these facts for every record a scene or sweep
uses, so that a record can be confirmed before (and after) a run::

    from pframe.excitation.describe import describe_record, describe_line

    facts = describe_record("records/A-ELC180.AT2")
    print(describe_line(facts))   # A-ELC180.AT2: PEER .AT2, 4000 points, dt = 0.01 s, ...
"""

from __future__ import annotations

import hashlib
from pathlib import Path

import numpy as np

from pframe.excitation.records import G, read_record

#: how the two formats are named in messages
FORMAT_NAMES = {"at2": "PEER NGA .AT2", "columns": "two columns (time, acceleration)"}


def record_format(path: str | Path, format: str = "auto") -> str:
    """``at2`` or ``columns``: the format a record file is read as. ``auto`` chooses by the
    suffix, in any case (``.AT2``, ``.at2``, ``.At2``): PEER for ``.at2``, else columns."""
    if format != "auto":
        return format
    return "at2" if Path(path).suffix.lower() == ".at2" else "columns"


def describe_record(path: str | Path, format: str = "auto", units: str | None = None,
                    scale: float = 1.0) -> dict:
    """The facts of one record file as pframe reads it.

    Parameters
    ----------
    path : str or Path
        The record file.
    format : {"auto", "at2", "columns"}
        As the scene's ``excitation.format``.
    units : {"g", "m/s2"} or None
        As the scene's ``excitation.units`` (None: g for PEER files, m/s^2 otherwise).
    scale : float
        The scene's ``excitation.scale``, applied to the peak.

    Returns
    -------
    dict
        ``file`` (str, the path as given), ``sha256`` (hex digest of the file's bytes),
        ``format`` (``"at2"`` or ``"columns"``), ``units`` (the file's acceleration units,
        ``"g"`` or ``"m/s2"``), ``points`` (int, samples read), ``step`` (float s, the sample
        step; the mean step when the times are uneven), ``uniform`` (bool, whether every step
        equals ``step`` to 1e-6 relative), ``start`` and ``duration`` (float s: first time and
        last minus first), ``scale`` (float), ``pga`` (float m/s^2, the peak absolute ground
        acceleration after units and scale), ``pga_g`` (the same in g, g = 9.80665 m/s^2) and
        ``pga_time`` (float s, when it occurs).

    Raises
    ------
    FileNotFoundError, ValueError
        As :func:`pframe.excitation.records.read_record`.
    """
    path = Path(path)
    content = path.read_bytes()
    kind = record_format(path, format)
    times, acceleration = read_record(path, kind, units)
    acceleration = np.asarray(acceleration, dtype=float) * scale
    steps = np.diff(times)
    step = float(np.mean(steps)) if steps.size else 0.0
    peak = int(np.argmax(np.abs(acceleration))) if acceleration.size else 0
    pga = float(abs(acceleration[peak])) if acceleration.size else 0.0
    return {
        "file": str(path),
        "sha256": hashlib.sha256(content).hexdigest(),
        "format": kind,
        "units": units or ("g" if kind == "at2" else "m/s2"),
        "points": int(times.size),
        "step": step,
        "uniform": bool(steps.size == 0 or np.allclose(steps, step, rtol=1e-6, atol=0.0)),
        "start": float(times[0]) if times.size else 0.0,
        "duration": float(times[-1] - times[0]) if times.size else 0.0,
        "scale": float(scale),
        "pga": pga,
        "pga_g": pga / G,
        "pga_time": float(times[peak]) if times.size else 0.0,
    }


def describe_line(facts: dict, duration: float | None = None) -> str:
    """One line of :func:`describe_record`'s facts; with the analysed ``duration`` (s), what
    part of the record the analysis covers."""
    step = f"dt = {facts['step']:.6g} s" if facts["uniform"] else \
        f"uneven steps (mean {facts['step']:.6g} s)"
    scaled = f" x {facts['scale']:g}" if facts["scale"] != 1.0 else ""
    line = (f"record {facts['file']}: {FORMAT_NAMES[facts['format']]} in "
            f"{'g' if facts['units'] == 'g' else 'm/s^2'}, {facts['points']} points, {step}, "
            f"{facts['duration']:.6g} s; PGA{scaled} {facts['pga']:.4g} m/s^2 "
            f"({facts['pga_g']:.4g} g) at t = {facts['pga_time']:.4g} s; "
            f"sha256 {facts['sha256'][:12]}")
    if duration is not None:
        end = facts["start"] + facts["duration"]
        if duration < end - 1e-9:
            line += f"; the analysis ({duration:g} s) stops before the record ends"
            if duration < facts["pga_time"]:
                line += " and before its PGA"
        elif duration > end + 1e-9:
            line += f"; the ground is at rest after {end:.6g} s of the {duration:g} s analysed"
    return line
