"""A scene's ground motion as the kernel takes it: samples at the analysis steps along the
site's axes it loads, the records as applied, and what to tell the run about them.

One motion acts along the site's x axis (today's scene). Two components (``kind:
components``) are each any motion, turned by the angle of incidence onto the site's axes:
a_x = cos(a) a_1 - sin(a) a_2, a_y = sin(a) a_1 + cos(a) a_2 (docs/plan.md). A pair of PEER
records is checked to be one recording's two components.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from pframe.errors import InputError
from pframe.excitation import ground_acceleration, read_record
from pframe.excitation.characteristic import apply_record
from pframe.excitation.describe import applied_motion, motion_warnings
from pframe.excitation.records import RecordUnitsError
from pframe.excitation.stochastic import stochastic_record, stochastic_warnings
from pframe.model.load import ModelError


@dataclass(frozen=True)
class GroundMotion:
    """``samples``: site axis ('x', 'y') -> a_g at t_n = n dt, n = 0..steps (m/s^2), the
    axes the motion loads; ``record`` the applied record of a one-record scene (else None),
    ``records`` (component axis, applied record) of each record read; ``warnings``."""

    samples: dict
    record: object = None
    records: tuple = ()
    warnings: tuple[str, ...] = ()

    @property
    def channels(self) -> tuple[str, ...]:
        return tuple(self.samples)


_SAMPLES: dict = {}  # (excitation as JSON, steps, dt) -> its samples, read-only


def _function_samples(excitation, steps: int, dt: float) -> np.ndarray:
    """a_g at t_n = n dt, n = 0..steps, of a motion given as a function of time, computed
    once for the expansions that ask for the same samples (the variants of a sweep); the
    array is shared, hence read-only."""
    if excitation is None:
        return ground_acceleration(None, np.arange(steps + 1) * dt)
    key = (excitation.model_dump_json(), steps, dt)
    samples = _SAMPLES.get(key)
    if samples is None:
        samples = ground_acceleration(excitation, np.arange(steps + 1) * dt)
        samples.setflags(write=False)
        if len(_SAMPLES) >= 8:  # a few motions at a time: memory stays bounded
            _SAMPLES.pop(next(iter(_SAMPLES)), None)
        _SAMPLES[key] = samples
    return samples


def _record(excitation, base_dir, path):
    """The applied record of a record or stochastic motion (None for a function of time)."""
    if excitation is None:
        return None
    if excitation.kind == "record":
        file = Path(base_dir) / excitation.file
        try:
            record = read_record(file, excitation.format, excitation.units, within=base_dir)
        except FileNotFoundError:
            raise ModelError(path + ("file",), f"record file {str(file)!r} not found") from None
        except RecordUnitsError as exc:  # the header and the scene disagree on the units
            where = "units" if excitation.units is not None else "file"
            raise ModelError(path + (where,), str(exc)) from None
        except (ValueError, OSError) as exc:
            raise ModelError(path + ("file",), f"malformed record: {exc}") from None
        try:
            return apply_record(excitation, *record)
        except InputError as exc:
            raise ModelError(path + ("file",), str(exc)) from None
    if excitation.kind == "stochastic":
        try:
            return stochastic_record(excitation)
        except ValueError as exc:
            raise ModelError(path, f"cannot simulate the motion: {exc}") from None
    return None


def _samples(excitation, record, steps: int, dt: float) -> np.ndarray:
    if record is None:  # a function of time (a sine, a pulse): shared by a sweep's variants
        return _function_samples(excitation, steps, dt)
    return ground_acceleration(excitation, np.arange(steps + 1) * dt,
                               (record.times, record.acceleration))


def turn(angle: float) -> tuple[float, float]:
    """cos and sin of an angle in degrees, exact at multiples of 90 degrees."""
    quarter = angle / 90.0
    if quarter == round(quarter):
        return ((1.0, 0.0), (0.0, 1.0), (-1.0, 0.0), (0.0, -1.0))[int(round(quarter)) % 4]
    return math.cos(math.radians(angle)), math.sin(math.radians(angle))


def ground_motion(excitation, base_dir, steps: int, dt: float,
                  path: tuple = ("excitation",)) -> GroundMotion:
    """The ground motion of a scene's ``excitation`` at its analysis steps (see the module);
    ``path`` where the scene gives it (messages)."""
    duration = steps * dt
    if excitation is None or excitation.kind != "components":
        record = _record(excitation, base_dir, path)
        warnings = (tuple(motion_warnings(applied_motion(excitation, record, duration)))
                    + tuple(stochastic_warnings(excitation)))
        return GroundMotion({"x": _samples(excitation, record, steps, dt)}, record,
                            (("x", record),) if record is not None else (), warnings)
    cos, sin = turn(excitation.angle)
    samples: dict = {}
    records, warnings = [], []
    for axis, motion in excitation.motions():
        record = _record(motion, base_dir, path + (axis,))
        if record is not None:
            records.append((axis, record))
        values = _samples(motion, record, steps, dt)
        warnings += [f"component {axis}: {w}" for w in
                     motion_warnings(applied_motion(motion, record, duration))]
        warnings += [f"component {axis}: {w}" for w in stochastic_warnings(motion)]
        # component x acts along (cos, sin), component y along (-sin, cos)
        along = (cos, sin) if axis == "x" else (-sin, cos)
        for site, weight in zip(("x", "y"), along):
            if weight != 0.0:
                part = weight * values if weight != 1.0 else values
                samples[site] = part if site not in samples else samples[site] + part
    warnings += _pair_warnings(excitation, base_dir)
    # a motion in two components loads both of the site's axes, whatever its angle (a sweep
    # over the incidence keeps one layout: zero along an axis at some angles)
    zero = np.zeros(steps + 1)
    return GroundMotion({k: samples.get(k, zero) for k in ("x", "y")}, None, tuple(records),
                        tuple(warnings))


def _pair_warnings(excitation, base_dir) -> list[str]:
    """What says two PEER records given as components are not one recording's pair: another
    event or station, another time step or length (the shorter is zero after its end)."""
    motions = dict(excitation.motions())
    if len(motions) < 2 or any(m.kind != "record" for m in motions.values()):
        return []
    heads = {}
    for axis, m in motions.items():
        file = Path(base_dir) / m.file
        try:
            lines = file.read_text(encoding="utf-8", errors="replace").splitlines()[:4]
        except OSError:
            return []
        if len(lines) < 4 or not file.suffix.lower() == ".at2":
            return []
        heads[axis] = lines
    (x1, x2), (y1, y2) = (heads["x"][1], heads["x"][3]), (heads["y"][1], heads["y"][3])
    out = []
    station_x, station_y = x1.rsplit(",", 1)[0].strip(), y1.rsplit(",", 1)[0].strip()
    if station_x != station_y:
        out.append(f"components x and y are not the two components of one recording: their "
                   f"headers name {station_x!r} and {station_y!r} (PEER line 2, without the "
                   "component)")
    if x2.split() != y2.split():
        out.append(f"components x and y differ in time step or length ({x2.strip()!r} and "
                   f"{y2.strip()!r}); the shorter is zero after its end")
    return out
