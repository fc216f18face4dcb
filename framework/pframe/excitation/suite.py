"""Ground-motion suites: lists or folders of records, each with a scale factor, and the
scaling of a suite to intensity levels (a target PGA or a target Sa(T, 5 %)).

A suite file is YAML (docs/gap-audit.md#suites)::

    records:                                  # file names relative to this file
      - RSN6_IMPVALL.I_I-ELC180.AT2
      - {file: RSN1063_NORTHR_RRS228.AT2, scale: 1.2}
      - {file: kobe.txt, units: m/s2}         # two columns: time (s), acceleration
    folder: more-records/                     # and/or every .AT2 file of a folder
    stochastic:                               # and/or simulated motions, one per seed
      - {model: rezaeian2010, magnitude: 7, distance: 20, vs30: 400, seeds: [1, 2, 3]}
    measure: {kind: sa, period: A, damping: 0.05}   # or {kind: pga}; period in s or a building
    levels: [0.1, 0.2, 0.3]                   # target intensities (g); omit: scales as given

For a scene in plan (docs/plan.md) an entry may say how it stands on the site: a pair of
records, the two horizontal components of one recording, turned by an angle (or several, one
motion each) as a scene's ``kind: components`` is, or one record along a direction::

    records:
      - {x: RSN6_IMPVALL.I_I-ELC180.AT2, y: RSN6_IMPVALL.I_I-ELC270.AT2, angles: [0, 90]}
      - {file: RSN1063_NORTHR_RRS228.AT2, angle: 30}
    stochastic:
      - {x: {model: rezaeian2010, ...}, y: {model: rezaeian2010, ...}, angle: 30,
         seeds: [[11, 12], [13, 14]]}

For a scene on supports an entry may give a record per support, and the suite simulations
of the scene's coherent motions (docs/supports.md#suites-of-a-motion-per-support;
:mod:`pframe.gap.members` resolves them on the scene)::

    records:
      - {supports: {west: RSN6_IMPVALL.I_I-ELC180.AT2, east: RSN6_IMPVALL.I_I-E06230.AT2}}
    coherent: {realisations: 20}

The intensity of a pair is its maximum-direction value (RotD100: the peak of the horizontal
vector of the two, of the ground accelerations for the PGA and of the oscillators'
displacements for Sa), which ASCE 7-22 (11.4, 16.2) defines its spectra in; both
components take one scale factor.
"""

from __future__ import annotations

import dataclasses
import math
import os
from dataclasses import dataclass
from pathlib import Path
from typing import Annotated, Literal

import numpy as np
from pydantic import BaseModel, ConfigDict, Field, model_validator

from pframe.errors import InputError
from pframe.excitation.records import G, read_record
from pframe.model.motion import turn

RECORD_SUFFIXES = (".at2",)


class _Base(BaseModel):
    model_config = ConfigDict(extra="forbid", frozen=True)


class RecordEntry(_Base):
    """One record of a suite, or a pair of records (x, y) of one recording."""

    file: str | None = Field(None, description="A PEER NGA .AT2 file or two columns (time s, "
                             "acceleration).")
    x: str | None = Field(None, description="A pair's component along its x axis (a file, "
                          "as file); give y with it, and no file.")
    y: str | None = Field(None, description="A pair's component along its y axis (at its "
                          "angle + 90 degrees).")
    angle: float | None = Field(None, allow_inf_nan=False, description="Where the motion "
                                "stands on the site of a scene in plan: the direction of the "
                                "record, or of a pair's x axis (degrees from the site's x, "
                                "counter-clockwise; docs/gap-audit.md#suites-in-plan).")
    angles: list[Annotated[float, Field(allow_inf_nan=False)]] | None = Field(
        None, min_length=1, description="Several angles instead of angle: one motion each.")
    supports: dict[str, str] | None = Field(
        None, min_length=1, description="A record per support of a scene on supports "
        "(support name -> file, docs/supports.md#suites-of-a-motion-per-support): one member "
        "whose intensity is its first support's; give no file, x or y with it.")

    @model_validator(mode="after")
    def _one_form(self):
        if self.supports is not None:
            if self.file is not None or self.x is not None or self.y is not None:
                raise ValueError("give supports (a record per support) or file, or x and y, "
                                 "not both")
            return self
        pair = self.x is not None or self.y is not None
        if pair and self.file is not None:
            raise ValueError("give file (one record) or x and y (a pair), not both")
        if pair and (self.x is None or self.y is None):
            raise ValueError("a pair gives both x and y (the two components of one "
                             "recording); one record along a direction is {file, angle}")
        if not pair and self.file is None:
            raise ValueError("give file (one record), or x and y (a pair)")
        if self.angle is not None and self.angles is not None:
            raise ValueError("give angle or angles, not both")
        return self

    @property
    def files(self) -> tuple[str, ...]:
        """The record files the entry reads (one, a pair's two, or one per support)."""
        if self.supports is not None:
            return tuple(self.supports.values())
        return (self.file,) if self.file is not None else (self.x, self.y)
    scale: float = Field(1.0, gt=0, allow_inf_nan=False, description="Factor on the record "
                         "(used when the suite is not scaled to levels).")
    format: Literal["auto", "columns", "at2"] = Field("auto", description="File format.")
    units: Literal["g", "m/s2", "cm/s2", "gal", "mm/s2", "in/s2", "ft/s2"] | None = Field(
        None, description="Default: the units the file's header states, else g for .AT2 and "
        "m/s2 otherwise; units that contradict the header are refused.")


class Measure(_Base):
    """The intensity measure the levels are given in (g)."""

    kind: Literal["pga", "sa"] = Field("pga", description="Peak ground acceleration or "
                                       "pseudo-spectral acceleration Sa(T, damping).")
    period: float | str | None = Field(None, description="Sa's period: seconds, or a "
                                       "building's name (its first period).")
    damping: float = Field(0.05, ge=0, lt=1, description="Sa's damping ratio.")


class CoherentEntry(_Base):
    """Simulations of a scene's coherent motions (``excitation: {kind: coherent}``), one
    member each."""

    realisations: int = Field(ge=1, le=100000, description="How many: member i (its place "
                              "in the suite, from 0) is the scene's simulation with seed "
                              "seed + i.")


class SuiteFile(_Base):
    """A suite of ground motions."""

    records: list[str | RecordEntry] = Field(default_factory=list, description="Record files.")
    folder: str | None = Field(None, description="A folder whose .AT2 files are added.")
    stochastic: list[dict] = Field(default_factory=list, description="Stochastic motions: "
                                   "the fields of a scene's stochastic excitation (without "
                                   "kind) and seeds (a list of seeds, one motion each).")
    coherent: CoherentEntry | None = Field(None, description="Members simulated as a scene "
                                           "on supports with a coherent excitation says "
                                           "(docs/supports.md#suites-of-a-motion-per-support).")
    measure: Measure = Field(Measure(), description="Intensity measure of the levels.")
    levels: list[Annotated[float, Field(gt=0, allow_inf_nan=False)]] | None = Field(
        None, description="Target intensities (g); each record is scaled to each level.")


@dataclass(frozen=True)
class Extent:
    """What a motion kept only as far as the runs read it knew of its whole (a stochastic
    study given its duration keeps no more of each realisation: docs/risk.md#speed): its
    duration (s), the time of its peak ground acceleration (s) and that peak (m/s^2; of the
    horizontal vector of a pair)."""

    duration: float
    peak_time: float
    peak: float


@dataclass(frozen=True)
class GroundMotion:
    """A record of a suite: its name, samples (m/s^2, scale applied) and step; for a scene in
    plan, where it stands on the site (the module's docstring)."""

    name: str
    time: np.ndarray
    acceleration: np.ndarray
    source: str
    #: a pair's second component on ``time`` (m/s^2), along ``angle`` + 90 degrees; None:
    #: one component
    second: np.ndarray | None = None
    #: the direction of the (first) component on the site, degrees from its x axis
    angle: float = 0.0
    #: the suite said where the motion stands (a pair, or an angle): a scene whose own motion
    #: has two components takes no other
    directed: bool = False
    #: the second component's file
    second_source: str = ""
    #: the whole motion's extent, when ``time`` holds only its beginning (:meth:`cut`)
    extent: Extent | None = None
    #: a motion per support ((support name, GroundMotion), ...; docs/supports.md): the
    #: member's own samples are its first support's (its intensity); empty: one motion
    at_supports: tuple = ()
    #: where the suite gives it (file, line, field), for messages
    where: str = ""
    #: a simulation of the scene's coherent motions still to be made (its place in the
    #: suite says its seed; pframe.gap.members)
    coherent: bool = False

    @property
    def dt(self) -> float:
        return float(self.time[1] - self.time[0])

    @property
    def duration(self) -> float:
        """The whole motion's duration (s): its own, or its supports' longest."""
        own = self.extent.duration if self.extent is not None else float(self.time[-1])
        return max([own] + [m.duration for _, m in self.at_supports])

    @property
    def peak(self) -> float:
        """The whole motion's peak ground acceleration (m/s^2; of a pair, its horizontal
        vector's)."""
        return self.extent.peak if self.extent is not None else float(np.max(self.magnitude))

    @property
    def peak_time(self) -> float:
        """When the whole motion's peak ground acceleration comes (s)."""
        if self.extent is not None:
            return self.extent.peak_time
        return float(self.time[int(self.magnitude.argmax())])

    def cut(self, until: float) -> GroundMotion:
        """The motion kept only as far as times up to ``until`` (s) read it (on_grid and
        on_site give the same numbers there), with its whole extent. (A motion per support
        keeps its supports' whole.)"""
        keep = int(np.searchsorted(self.time, until, side="left")) + 1
        if keep >= self.time.size:
            return self
        own = self.extent.duration if self.extent is not None else float(self.time[-1])
        extent = Extent(own, self.peak_time, self.peak)
        return dataclasses.replace(
            self, time=self.time[:keep].copy(), acceleration=self.acceleration[:keep].copy(),
            second=None if self.second is None else self.second[:keep].copy(), extent=extent)

    @property
    def sources(self) -> tuple[str, ...]:
        """The files it reads."""
        return tuple(f for m in (self,) + tuple(m for _, m in self.at_supports)
                     for f in (m.source, m.second_source) if f)

    @property
    def loads_y(self) -> bool:
        """Whether the motion moves the ground along the site's y axis."""
        return self.second is not None or turn(self.angle)[1] != 0.0

    @property
    def magnitude(self) -> np.ndarray:
        """|a_g| on ``time``: of the horizontal vector of a pair."""
        if self.second is None:
            return np.abs(self.acceleration)
        return np.hypot(self.acceleration, self.second)

    def on_grid(self, times: np.ndarray) -> np.ndarray:
        """Linearly interpolated on ``times`` (s), zero after the record ends: the first
        component, along its own direction."""
        return np.interp(times, self.time, self.acceleration, left=0.0, right=0.0)

    def on_site(self, times: np.ndarray, channels=("x",)) -> np.ndarray:
        """(len(channels), len(times)): the motion along the site's axes ``channels`` ('x',
        'y') at ``times``, each component turned onto them as a scene's ``kind:
        components`` is (docs/plan.md): a_x = cos(a) a_1 - sin(a) a_2, a_y = sin(a) a_1 +
        cos(a) a_2. A motion along x alone gives ``on_grid`` itself along x."""
        cos, sin = turn(self.angle)
        parts = [((cos, sin), self.on_grid(times))]
        if self.second is not None:
            parts.append(((-sin, cos), np.interp(times, self.time, self.second, left=0.0,
                                                 right=0.0)))
        if self.loads_y and "y" not in channels:
            raise ValueError(f"motion {self.name} loads the site's y axis, which the runs "
                             "do not take")
        out = np.zeros((len(channels), len(times)))
        for row, axis in enumerate(channels):
            total = None
            for along, values in parts:
                weight = along["xy".index(axis)]
                if weight != 0.0:
                    part = values if weight == 1.0 else weight * values
                    total = part if total is None else total + part
            if total is not None:
                out[row] = total
        return out

    def evenly_spaced(self) -> tuple[np.ndarray, float]:
        """Samples on an even step (the smallest step of the file) for the spectrum."""
        steps = np.diff(self.time)
        if np.allclose(steps, steps[0], rtol=1e-6, atol=0):
            return self.acceleration, float(steps[0])
        dt = float(np.min(steps))
        grid = np.arange(0.0, self.time[-1] + 0.5 * dt, dt)
        return self.on_grid(grid), dt

    def components_evenly_spaced(self) -> tuple[list[np.ndarray], float]:
        """Each component's samples on one even step (a pair's two, on the first's)."""
        first, dt = self.evenly_spaced()
        if self.second is None:
            return [first], dt
        grid = np.arange(len(first)) * dt
        return [first, np.interp(grid, self.time, self.second, left=0.0, right=0.0)], dt


@dataclass(frozen=True)
class Suite:
    """Ground motions with the intensity measure and levels they are scaled to."""

    motions: tuple[GroundMotion, ...]
    measure: Measure = Measure()
    levels: tuple[float, ...] | None = None
    source: str = ""

    @property
    def names(self) -> list[str]:
        return [m.name for m in self.motions]


def _read(file: str, entry: RecordEntry, folder: Path, where: str):
    path = folder / file
    try:
        t, a = read_record(path, entry.format, entry.units, within=folder)
    except FileNotFoundError:
        raise InputError(f"{where}: record file {str(path)!r} not found") from None
    except (ValueError, OSError) as exc:
        raise InputError(f"{where}: malformed record: {exc}") from None
    return t, a * entry.scale, str(path)


def _entry_motion(entry: RecordEntry, folder: Path, where: str) -> GroundMotion:
    t, a, path = _read(entry.file, entry, folder, where)
    return GroundMotion(Path(entry.file).name, t, a, path)


def _on_one_grid(t1, a1, t2, a2):
    """Two components on one time grid: the first's when they share it, else the finer
    step over the longer of the two (each zero after its end)."""
    if len(t1) == len(t2) and np.allclose(t1, t2, rtol=0, atol=1e-9 * max(t1[-1], 1.0)):
        return t1, a1, a2
    dt = min(float(np.min(np.diff(t1))), float(np.min(np.diff(t2))))
    grid = np.arange(0.0, max(t1[-1], t2[-1]) + 0.5 * dt, dt)
    return (grid, np.interp(grid, t1, a1, left=0.0, right=0.0),
            np.interp(grid, t2, a2, left=0.0, right=0.0))


def _angles(item, where: str) -> tuple[list[float], bool]:
    """The angles an entry (a RecordEntry or a stochastic entry's dict) gives, one motion
    each ([0] when it gives none), and whether it gave any."""
    angle, angles = (getattr(item, "angle", None), getattr(item, "angles", None)) \
        if not isinstance(item, dict) else (item.get("angle"), item.get("angles"))
    if angle is not None and angles is not None:
        raise InputError(f"{where}: give angle or angles, not both")
    values = angles if angles is not None else [angle] if angle is not None else [0.0]
    for v in values:
        if isinstance(v, bool) or not isinstance(v, (int, float)) or not np.isfinite(v):
            raise InputError(f"{where}: an angle is a number of degrees, not {v!r}")
    return [float(v) for v in values], angle is not None or angles is not None


def _turned(motion: GroundMotion, angles: list[float], given: bool) -> list[GroundMotion]:
    """The motion at each angle; named ``<name>@<angle>`` where the entry gave angles."""
    return [dataclasses.replace(motion, angle=a, directed=motion.directed or given,
                                name=f"{motion.name}@{a:g}" if given else motion.name)
            for a in angles]


def _support_motion(entry: RecordEntry, folder: Path, where) -> GroundMotion:
    """A member with a record per support (``entry.supports``; ``where(*path)`` the place of
    a field in the suite): each support's record read as a suite's record is, all on one
    step; the member's own samples are its first support's."""
    parts, step = [], None
    for name, file in entry.supports.items():
        at = where("supports", name)
        t, a, path = _read(file, entry, folder, at)
        motion = GroundMotion(Path(file).name, t, a, path, where=at)
        steps = np.diff(t)
        if not np.allclose(steps, steps[0], rtol=1e-6, atol=0):
            raise InputError(f"{at}: {file} is not sampled on an even step; the records of a "
                             "motion per support share one step")
        if step is None:
            step, first = float(steps[0]), name
        elif not math.isclose(float(steps[0]), step, rel_tol=1e-6):
            raise InputError(f"{at}: {file} is sampled every {float(steps[0]):g} s and "
                             f"{first}'s record every {step:g} s; the records of a motion per "
                             "support share one step (resample one of them)")
        parts.append((name, motion))
    head = parts[0][1]
    name = "+".join(f"{s}={m.name}" for s, m in parts)
    return GroundMotion(name, head.time, head.acceleration, head.source,
                        at_supports=tuple(parts), where=where())


def _entry_motions(entry: RecordEntry, folder: Path, where: str, at=None) -> list[GroundMotion]:
    """The motions of a suite's record entry: one record, or a pair, at each of its angles;
    or a record per support (``at(*path)``: where a field of the entry is)."""
    if entry.supports is not None:
        if entry.angle is not None or entry.angles is not None:
            raise InputError(f"{where}: a record per support moves the ground along the "
                             "site's x axis; angle and angles are for one record or a pair")
        return [_support_motion(entry, folder, at or (lambda *p: where))]
    angles, given = _angles(entry, where)
    if entry.file is not None:
        return _turned(_entry_motion(entry, folder, where), angles, given)
    t1, a1, path1 = _read(entry.x, entry, folder, f"{where}.x")
    t2, a2, path2 = _read(entry.y, entry, folder, f"{where}.y")
    time, first, second = _on_one_grid(t1, a1, t2, a2)
    motion = GroundMotion(f"{Path(entry.x).name}+{Path(entry.y).name}", time, first, path1,
                          second=second, directed=True, second_source=path2)
    return _turned(motion, angles, given)


def _unique(motions: list[GroundMotion]) -> tuple[GroundMotion, ...]:
    seen: dict[str, int] = {}
    out = []
    for m in motions:
        count = seen.get(m.name, 0)
        seen[m.name] = count + 1
        out.append(m if not count else dataclasses.replace(m, name=f"{m.name}#{count + 1}"))
    return tuple(out)


def folder_records(folder: Path) -> list[Path]:
    """The record files of a folder (.AT2 in any case), sorted by name."""
    return sorted(p for p in folder.iterdir() if p.suffix.lower() in RECORD_SUFFIXES)


def load_suite(path: str | Path, records_folder: str | Path | None = None) -> Suite:
    """A suite from a suite file (YAML), a folder of .AT2 files, or one record file.

    A suite file's record names are relative to ``records_folder`` when given (where the user
    keeps the downloaded records), else to the suite file's folder."""
    from pframe.model.load import read_input, validated
    from pframe.yamltext import compose as _compose
    from pframe.yamltext import where as _where

    path = Path(path)
    if path.is_dir():
        return suite_from_files(folder_records(path), source=str(path))
    if path.suffix.lower() not in (".yaml", ".yml"):
        return suite_from_files([path], source=str(path))
    text = read_input(path, "suite")
    data, lines = _compose(text, str(path))
    if not isinstance(data, dict):
        raise InputError(f"{path}: a suite file is a YAML mapping (records, folder, measure, "
                         "levels)")
    model = validated(SuiteFile, data, lines, str(path))
    base = Path(records_folder) if records_folder is not None else path.parent
    if not base.is_dir():
        from pframe.outputs import not_regular

        raise InputError(f"{base}: the records folder " + (
            f"is {not_regular(base) or 'a file'}, not a folder" if base.exists()
            else "does not exist"))
    motions = []
    for i, item in enumerate(model.records):
        entry = RecordEntry(file=item) if isinstance(item, str) else item
        where = _where(str(path), lines, ("records", i))
        motions += [m if m.where else dataclasses.replace(m, where=where) for m in
                    _entry_motions(entry, base, where, lambda *p, i=i: _where(
                        str(path), lines, ("records", i) + p))]
    if model.folder is not None:
        folder = base / model.folder
        if not folder.is_dir():
            raise InputError(f"{_where(str(path), lines, ('folder',))}: {str(folder)!r} is not "
                             "a folder")
        for file in folder_records(folder):
            motions.append(_entry_motion(RecordEntry(file=str(file.relative_to(base))),
                                         base, _where(str(path), lines, ("folder",))))
    for i, item in enumerate(model.stochastic):
        where = _where(str(path), lines, ("stochastic", i))
        motions += [dataclasses.replace(m, where=where) for m in stochastic_motions(item, where)]
    if model.coherent is not None:
        at = _where(str(path), lines, ("coherent",))
        motions += [GroundMotion(f"coherent#{k + 1}", np.zeros(2), np.zeros(2), "", where=at,
                                 coherent=True)
                    for k in range(model.coherent.realisations)]
    if not motions:
        raise InputError(f"{path}: the suite names no records (give records or a folder of "
                         ".AT2 files)")
    levels = tuple(model.levels) if model.levels else None
    return Suite(_unique(motions), model.measure, levels, str(path))


def _simulated(item: dict, seeds: list[int], where: str,
               until: float | None = None) -> list[tuple[str, np.ndarray, np.ndarray]]:
    """Stochastic motions, one per seed: names, times and samples (m/s^2, scale applied),
    each generated whole, then (``until``) kept up to that time, with its whole extent
    (:meth:`GroundMotion.cut`). Blocks of seeds are generated on one thread per CPU (the
    filter releases the GIL): a block's whole motions at a time."""
    from pydantic import ValidationError

    from pframe.excitation.stochastic import generate_seeds
    from pframe.model.scene import Stochastic

    try:
        excitation = Stochastic.model_validate({**item, "seed": seeds[0]})
    except ValidationError as exc:
        problems = "; ".join(f"{'.'.join(map(str, e['loc'])) or 'entry'}: {e['msg']}"
                             for e in exc.errors())
        raise InputError(f"{where}: {problems}") from None
    scale = excitation.scale

    def block(chunk):
        out = []
        for seed, m in zip(chunk, generate_seeds(excitation, chunk)):
            motion = GroundMotion(f"{excitation.model}-seed{seed}", np.asarray(m.times),
                                  np.asarray(m.acceleration) * scale, "")
            out.append(motion if until is None else motion.cut(until))
        return out

    size = 32
    chunks = [seeds[k:k + size] for k in range(0, len(seeds), size)]
    if len(chunks) == 1:
        return block(chunks[0])
    from concurrent.futures import ThreadPoolExecutor

    with ThreadPoolExecutor(min(len(chunks), os.cpu_count() or 1)) as pool:
        return [m for part in pool.map(block, chunks) for m in part]


def _seed(value) -> bool:
    return isinstance(value, int) and not isinstance(value, bool) and value >= 0


def stochastic_motions(item: dict, where: str, until: float | None = None) -> list[GroundMotion]:
    """The motions of a suite's stochastic entry: one per seed of ``seeds`` (at each of its
    angles); a pair ``{x: {...}, y: {...}}`` takes a pair of seeds for each motion. With
    ``until`` (s), each is kept only up to that time (:meth:`GroundMotion.cut`): memory for
    the runs, not for the whole motions."""
    item = dict(item)
    seeds = item.pop("seeds", None)
    item.pop("kind", None)
    angles, given = _angles(item, where)
    item.pop("angle", None)
    item.pop("angles", None)
    pair = "x" in item or "y" in item
    if pair:
        unknown = sorted(set(item) - {"x", "y"})
        if unknown or not all(isinstance(item.get(k), dict) for k in ("x", "y")):
            raise InputError(f"{where}: a stochastic pair gives x and y, each the fields of a "
                             "stochastic motion (model, ...), then angle or angles and seeds"
                             + (f"; {', '.join(unknown)} belong in x and y" if unknown
                                else ""))
        if not (isinstance(seeds, list) and seeds and all(
                isinstance(s, list) and len(s) == 2 and all(_seed(v) for v in s)
                for s in seeds)):
            raise InputError(f"{where}: a stochastic pair needs seeds, a list of pairs of "
                             "integers >= 0 (the two components' seeds, one motion each), "
                             "e.g. seeds: [[1, 2], [3, 4]]")
    elif not (isinstance(seeds, list) and seeds and all(_seed(s) for s in seeds)):
        raise InputError(f"{where}: a stochastic entry needs seeds, a list of integers >= 0 "
                         "(one motion each), e.g. seeds: [1, 2, 3]")
    if not pair:  # no file: nothing an output could overwrite
        return [turned for m in _simulated(item, seeds, where, until)
                for turned in _turned(m, angles, given)]
    # a pair: each component generated whole (its extent is the pair's), then cut
    firsts, seconds = (_simulated(item[k], [s[i] for s in seeds], f"{where}.{k}")
                       for i, k in enumerate(("x", "y")))
    out = []
    for m1, m2 in zip(firsts, seconds):
        time, first, second = _on_one_grid(m1.time, m1.acceleration, m2.time, m2.acceleration)
        pair = GroundMotion(f"{m1.name}+{m2.name}", time, first, "", second=second,
                            directed=True)
        out += _turned(pair if until is None else pair.cut(until), angles, given)
    return out


def suite_from_files(files, source: str = "", scale: float = 1.0) -> Suite:
    """A suite of record files given by name (format by suffix)."""
    files = [Path(f) for f in files]
    if not files:
        raise InputError(f"{source or 'the suite'}: no record files (.AT2) found")
    motions = [_entry_motion(RecordEntry(file=f.name, scale=scale), f.parent, str(f))
               for f in files]
    return Suite(_unique(motions), source=source)


def intensity(motion: GroundMotion, measure: Measure, period: float | None = None) -> float:
    """The motion's intensity in g: PGA, or Sa(period, damping) by the exact recurrence; of
    a pair, its maximum-direction value (RotD100): the peak of the horizontal vector of the
    two accelerations, or w^2 times the peak of the vector of the two oscillators'
    displacements (the oscillator's response to a motion along any direction is the same
    combination of its responses to the two)."""
    if measure.kind == "pga":
        return motion.peak / G
    if motion.extent is not None:
        raise ValueError(f"motion {motion.name} is cut: its spectrum needs the whole motion")
    from pframe.excitation.spectrum import sdof_response, spectral_acceleration

    if motion.second is None:
        acc, dt = motion.evenly_spaced()
        return spectral_acceleration(acc, dt, period, measure.damping) / G
    components, dt = motion.components_evenly_spaced()
    u = [sdof_response(a, dt, period, measure.damping)[0] for a in components]
    return float((2.0 * np.pi / period) ** 2 * np.max(np.hypot(*u))) / G


def scale_factors(suite: Suite, periods_by_building: dict[str, float] | None = None,
                  levels=None) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(level values, factors (record, level), intensities (record) in g) of a suite.

    With levels (argument, else the suite's), record i at level j is scaled by
    ``level_j / IM_i`` (its own scale factor cancels); without, each keeps its factor and the
    single level is 1 (the records as given)."""
    period = None
    if suite.measure.kind == "sa":
        p = suite.measure.period
        if p is None:
            raise InputError(f"{suite.source or 'suite'}: measure sa needs a period (seconds "
                             "or a building's name)")
        if isinstance(p, str):
            try:
                p = float(p)
            except ValueError:
                if not periods_by_building or p not in periods_by_building:
                    known = ", ".join(periods_by_building or {}) or "none"
                    raise InputError(f"{suite.source or 'suite'}: measure period {p!r} is "
                                     f"neither seconds nor a building of the scene ({known})"
                                     ) from None
                p = periods_by_building[p]
        if not p > 0:
            raise InputError(f"{suite.source or 'suite'}: the measure's period must be > 0 s")
        period = float(p)
    ims = np.array([intensity(m, suite.measure, period) for m in suite.motions])
    levels = levels if levels is not None else suite.levels
    if levels is None:
        return np.array([1.0]), np.ones((len(suite.motions), 1)), ims
    levels = np.asarray(levels, dtype=float)
    if np.any(ims <= 0):
        zero = [m.name for m, x in zip(suite.motions, ims) if x <= 0]
        raise InputError(f"records with zero intensity cannot be scaled to a level: {zero}")
    return levels, levels[None, :] / ims[:, None], ims
