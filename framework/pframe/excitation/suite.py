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
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path
from typing import Annotated, Literal

import numpy as np
from pydantic import BaseModel, ConfigDict, Field

from pframe.errors import InputError
from pframe.excitation.records import G, read_record

RECORD_SUFFIXES = (".at2",)


class _Base(BaseModel):
    model_config = ConfigDict(extra="forbid", frozen=True)


class RecordEntry(_Base):
    """One record of a suite."""

    file: str = Field(description="A PEER NGA .AT2 file or two columns (time s, acceleration).")
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


class SuiteFile(_Base):
    """A suite of ground motions."""

    records: list[str | RecordEntry] = Field(default_factory=list, description="Record files.")
    folder: str | None = Field(None, description="A folder whose .AT2 files are added.")
    stochastic: list[dict] = Field(default_factory=list, description="Stochastic motions: "
                                   "the fields of a scene's stochastic excitation (without "
                                   "kind) and seeds (a list of seeds, one motion each).")
    measure: Measure = Field(Measure(), description="Intensity measure of the levels.")
    levels: list[Annotated[float, Field(gt=0, allow_inf_nan=False)]] | None = Field(
        None, description="Target intensities (g); each record is scaled to each level.")


@dataclass(frozen=True)
class GroundMotion:
    """A record of a suite: its name, samples (m/s^2, scale applied) and step."""

    name: str
    time: np.ndarray
    acceleration: np.ndarray
    source: str

    @property
    def dt(self) -> float:
        return float(self.time[1] - self.time[0])

    @property
    def duration(self) -> float:
        return float(self.time[-1])

    def on_grid(self, times: np.ndarray) -> np.ndarray:
        """Linearly interpolated on ``times`` (s), zero after the record ends."""
        return np.interp(times, self.time, self.acceleration, left=0.0, right=0.0)

    def evenly_spaced(self) -> tuple[np.ndarray, float]:
        """Samples on an even step (the smallest step of the file) for the spectrum."""
        steps = np.diff(self.time)
        if np.allclose(steps, steps[0], rtol=1e-6, atol=0):
            return self.acceleration, float(steps[0])
        dt = float(np.min(steps))
        grid = np.arange(0.0, self.time[-1] + 0.5 * dt, dt)
        return self.on_grid(grid), dt


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


def _entry_motion(entry: RecordEntry, folder: Path, where: str) -> GroundMotion:
    path = folder / entry.file
    try:
        t, a = read_record(path, entry.format, entry.units, within=folder)
    except FileNotFoundError:
        raise InputError(f"{where}: record file {str(path)!r} not found") from None
    except (ValueError, OSError) as exc:
        raise InputError(f"{where}: malformed record: {exc}") from None
    return GroundMotion(Path(entry.file).name, t, a * entry.scale, str(path))


def _unique(motions: list[GroundMotion]) -> tuple[GroundMotion, ...]:
    seen: dict[str, int] = {}
    out = []
    for m in motions:
        count = seen.get(m.name, 0)
        seen[m.name] = count + 1
        out.append(m if not count else GroundMotion(f"{m.name}#{count + 1}", m.time,
                                                    m.acceleration, m.source))
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
        motions.append(_entry_motion(entry, base, _where(str(path), lines, ("records", i))))
    if model.folder is not None:
        folder = base / model.folder
        if not folder.is_dir():
            raise InputError(f"{_where(str(path), lines, ('folder',))}: {str(folder)!r} is not "
                             "a folder")
        for file in folder_records(folder):
            motions.append(_entry_motion(RecordEntry(file=str(file.relative_to(base))),
                                         base, _where(str(path), lines, ("folder",))))
    for i, item in enumerate(model.stochastic):
        motions += stochastic_motions(item, _where(str(path), lines, ("stochastic", i)))
    if not motions:
        raise InputError(f"{path}: the suite names no records (give records or a folder of "
                         ".AT2 files)")
    levels = tuple(model.levels) if model.levels else None
    return Suite(_unique(motions), model.measure, levels, str(path))


def stochastic_motions(item: dict, where: str) -> list[GroundMotion]:
    """The motions of a suite's stochastic entry: one per seed of ``seeds``."""
    from pydantic import ValidationError

    from pframe.excitation.stochastic import generate
    from pframe.model.scene import Stochastic

    item = dict(item)
    seeds = item.pop("seeds", None)
    item.pop("kind", None)
    if not (isinstance(seeds, list) and seeds and all(isinstance(s, int) and
                                                      not isinstance(s, bool) and s >= 0
                                                      for s in seeds)):
        raise InputError(f"{where}: a stochastic entry needs seeds, a list of integers >= 0 "
                         "(one motion each), e.g. seeds: [1, 2, 3]")
    out = []
    for seed in seeds:
        try:
            excitation = Stochastic.model_validate({**item, "seed": seed})
        except ValidationError as exc:
            problems = "; ".join(f"{'.'.join(map(str, e['loc'])) or 'entry'}: {e['msg']}"
                                 for e in exc.errors())
            raise InputError(f"{where}: {problems}") from None
        m = generate(excitation)
        acc = np.asarray(m.acceleration) * excitation.scale
        out.append(GroundMotion(f"{excitation.model}-seed{seed}", np.asarray(m.times), acc,
                                ""))  # no file: nothing an output could overwrite
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
    """The motion's intensity in g: PGA, or Sa(period, damping) by the exact recurrence."""
    if measure.kind == "pga":
        return float(np.max(np.abs(motion.acceleration))) / G
    from pframe.excitation.spectrum import spectral_acceleration

    acc, dt = motion.evenly_spaced()
    return spectral_acceleration(acc, dt, period, measure.damping) / G


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
