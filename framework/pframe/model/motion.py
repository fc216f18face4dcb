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
from pframe.excitation.describe import applied_motion, motion_warnings
from pframe.excitation.sample import ground_acceleration
from pframe.model.load import ModelError


# eq=False, repr=False: it holds numpy arrays: a generated __eq__ and __hash__ could only
# raise (== is elementwise), a __repr__ would print every array, and each generated
# function is compiled at every start
@dataclass(frozen=True, eq=False, repr=False)
class GroundMotion:
    """``samples``: site axis ('x', 'y') -> a_g at t_n = n dt, n = 0..steps (m/s^2), the
    axes the motion loads; ``record`` the applied record of a one-record scene (else None),
    ``records`` (component axis, applied record) of each record read; ``warnings``."""

    samples: dict
    record: object = None
    records: tuple = ()
    warnings: tuple[str, ...] = ()
    #: how its displacement is had, by site axis: (axis, displacement or None, velocity or
    #: None, words): a record's files (m, m/s at the steps) or its baseline correction;
    #: an axis not here is integrated from rest (pframe.model.support_motion.integrated)
    given: tuple = ()

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
        # the reading of records imported for a record only (a function of time reads none)
        from pframe.excitation.characteristic import apply_record
        from pframe.excitation.records import RecordUnitsError, read_record

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
        if excitation.baseline is not None:
            record = _corrected(excitation, record, path)
        try:
            return apply_record(excitation, *record)
        except InputError as exc:
            raise ModelError(path + ("file",), str(exc)) from None
    if excitation.kind == "stochastic":
        from pframe.excitation.stochastic import stochastic_record

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


def _stochastic_warnings(excitation) -> list[str]:
    """:func:`pframe.excitation.stochastic.stochastic_warnings`, its module imported for a
    stochastic motion only (with json and its models, a few ms of every other run)."""
    if excitation is None or excitation.kind != "stochastic":
        return []
    from pframe.excitation.stochastic import stochastic_warnings

    return stochastic_warnings(excitation)


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
                    + tuple(_stochastic_warnings(excitation)))
        samples = _samples(excitation, record, steps, dt)
        given, more = _given(excitation, record, base_dir, path, samples, dt)
        return GroundMotion({"x": samples}, record,
                            (("x", record),) if record is not None else (), warnings + more,
                            given)
    cos, sin = turn(excitation.angle)
    samples: dict = {}
    records, warnings = [], []
    for axis, motion in excitation.motions():
        if motion.kind == "record" and (motion.displacement is not None
                                        or motion.baseline is not None):
            field = "displacement" if motion.displacement is not None else "baseline"
            raise ModelError(path + (axis, field), "a record's displacement file or baseline "
                             "correction is read for a motion along one axis; not yet for "
                             "either component of two (leave it out: the displacement is "
                             "then the acceleration integrated twice, as the run states)")
        record = _record(motion, base_dir, path + (axis,))
        if record is not None:
            records.append((axis, record))
        values = _samples(motion, record, steps, dt)
        warnings += [f"component {axis}: {w}" for w in
                     motion_warnings(applied_motion(motion, record, duration))]
        warnings += [f"component {axis}: {w}" for w in _stochastic_warnings(motion)]
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


#: how far a record's displacement file may stray from its acceleration integrated twice
#: from rest (the trapezoid rule, as the kernel steps), as a part of the file's peak over the
#: analysis, before the run warns that the two may not be one record's
DISPLACEMENT_TOLERANCE = 0.05


def _corrected(excitation, record, path) -> tuple:
    """A record file's (times, acceleration) with the scene's baseline correction
    (pframe.excitation.kinematics.baseline_correct) on its own step."""
    from pframe.excitation.kinematics import baseline_correct

    times, acceleration = record
    steps = np.diff(times)
    if not np.allclose(steps, steps[0], rtol=1e-6, atol=0):
        raise ModelError(path + ("baseline",), "a baseline correction is made on the record's "
                         "own step, and this record's samples are not evenly spaced")
    try:
        done = baseline_correct(acceleration, float(steps[0]), excitation.baseline.fit,
                                excitation.baseline.degree)
    except ValueError as exc:
        raise ModelError(path + ("baseline",), str(exc)) from None
    return times, done.acceleration


def _series(excitation, base_dir, path, quantity: str):
    from pframe.excitation.records import read_series

    name = getattr(excitation, quantity)
    file = Path(base_dir) / name
    try:
        return read_series(file, quantity, within=base_dir)
    except FileNotFoundError:
        raise ModelError(path + (quantity,), f"{quantity} file {str(file)!r} not found") \
            from None
    except (ValueError, OSError) as exc:
        raise ModelError(path + (quantity,), f"malformed {quantity} file: {exc}") from None


def _given(excitation, record, base_dir, path, samples, dt) -> tuple[tuple, tuple]:
    """(GroundMotion.given, warnings) of a motion along x: a record's displacement (and
    velocity) files at the analysis steps, scaled and stretched as its acceleration is
    (d(t) = f T^2 d_file(t / T), v(t) = f T v_file(t / T): f its amplitude factor and scale,
    T its time factor), each checked against the acceleration integrated from rest
    (:data:`DISPLACEMENT_TOLERANCE`); or its baseline correction in words."""
    if excitation is None or excitation.kind != "record":
        return (), ()
    if excitation.displacement is None:
        if excitation.baseline is None:
            return (), ()
        b = excitation.baseline
        return (("x", None, None, f"the record's acceleration baseline-corrected (fit {b.fit}, "
                 f"degree {b.degree})"),), ()
    from pframe.excitation.kinematics import integrate

    factor, stretch = excitation.scale * record.amplitude_factor, record.time_factor
    times = np.arange(samples.size) * dt
    velocity, displacement = integrate(samples, dt)
    found, words, warnings = {}, [], []
    for quantity, power, integral in (("displacement", 2, displacement),
                                      ("velocity", 1, velocity)):
        if getattr(excitation, quantity) is None:
            continue
        t, values, units = _series(excitation, base_dir, path, quantity)
        series = factor * stretch**power * np.interp(times / stretch, t, values)
        found[quantity] = series
        peak = float(np.max(np.abs(series)))
        gap = np.abs(series - integral)
        worst = int(np.argmax(gap))
        part = float(gap[worst]) / peak if peak > 0 else (0.0 if gap[worst] == 0 else np.inf)
        unit = "m" if quantity == "displacement" else "m/s"
        words.append(f"{quantity} from {getattr(excitation, quantity)} ({units}), within "
                     f"{100 * part:.3g} % of its peak of the acceleration integrated "
                     f"{'twice' if power == 2 else 'once'} from rest")
        if part > DISPLACEMENT_TOLERANCE:
            warnings.append(
                f"record {excitation.file}: its {quantity} file {getattr(excitation, quantity)} "
                f"and its acceleration integrated {'twice' if power == 2 else 'once'} from rest "
                f"differ by up to {float(gap[worst]):.4g} {unit} at t = {times[worst]:.4g} s, "
                f"{100 * part:.3g} % of the file's peak {peak:.4g} {unit} (more than "
                f"{100 * DISPLACEMENT_TOLERANCE:g} %): the supports move by the file's "
                f"{quantity}, which may not be this record's (another processing, units or "
                f"step); check the files, or leave {quantity} out to integrate the acceleration")
    if "velocity" not in found:
        words.append("velocity the acceleration integrated once from rest")
    return (("x", found["displacement"], found.get("velocity"), "; ".join(words)),), \
        tuple(warnings)
