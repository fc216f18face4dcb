"""A risk study: a scene, a record suite and an analysis design, run in resumable batches;
then fragilities, the hazard, mean annual frequencies and the gap at a target frequency
(docs/risk.md).

A study file (YAML; paths relative to it)::

    scene: ../wu2021-eq14.yaml
    suite: ../suites/peer-records.yaml
    measure: sa:A                  # pga, sa:SECONDS or sa:BUILDING (its first period)
    design: {kind: msa, levels: [0.25, 0.5, 0.75, 1.0]}   # or ida (same grid), cloud
    dt: 0.002                      # step of the runs without contacts (default: the scene's)
    pounding_runs: true            # also run with the contacts (scene's step): demands with pounding
    limits:
      drift: {IO: 0.02, LS: 0.04}          # peak storey drift (m), any storey of a building
      drift_ratio: {CP: 0.025}             # peak storey drift ratio (needs storey heights)
      acceleration: {A: 1.0}               # peak absolute floor acceleration (g)
    hazard: {file: hazard.csv}     # or {power_law: {k0: 1.0e-4, k: 2.5}}
    target: {return_period: 475}   # or {annual_frequency: 2.1e-3}
    design_life: 50                # years: P(at least once) = 1 - exp(-MAF years)
    codes: [asce7, {code: tbdy2018, R: 6}]   # code rules beside the gap at target
"""

from __future__ import annotations

import dataclasses
import math
import time
import warnings
from pathlib import Path
from typing import Literal

import numpy as np
from pydantic import BaseModel, ConfigDict, Field

from pframe.errors import InputError

G = 9.80665
#: bytes per step of a run's ground motion while a batch runs (the copies the kernel and
#: its caller hold, as pframe.resources counts them, and the two of the next batch, which
#: is assembled meanwhile: _here)
GROUND_BYTES = 6 * 8.0
#: the ground motions a batch of runs holds at most when the study gives no chunk (bytes):
#: memory bounded whatever the number of variants
BATCH_BYTES = 256 * 2**20


class _Base(BaseModel):
    model_config = ConfigDict(extra="forbid")


class Hunt(_Base):
    """The hunt of an IDA by hunt and fill: levels start, start + step, then steps growing
    by ``growth`` each time, until the limit is passed."""

    start: float = Field(gt=0, allow_inf_nan=False, description="The first level (g).")
    step: float = Field(gt=0, allow_inf_nan=False, description="The first step up (g).")
    growth: float = Field(1.5, ge=1, allow_inf_nan=False, description="Each step is the "
                          "last times this (1: equal steps).")


class Design(_Base):
    """Records scaled to levels (msa, ida) or as given (cloud); IDA by hunt and fill."""

    kind: Literal["msa", "ida", "cloud", "subset"] = Field(
        description="multiple-stripe (records scaled to levels), incremental dynamic analysis "
        "(on a grid of levels, or by hunt and fill), cloud (unscaled), or subset simulation "
        "of the probability of pounding (stationary Clough-Penzien motion, or a suite of records "
        "with uncertain values)")
    levels: list[float] | None = Field(None, description="intensity levels (g) of msa/ida; "
                                       "the stripes a subset design over records scales "
                                       "them to (two or more with a hazard: its annual "
                                       "frequency of pounding)")
    hunt: Hunt | None = Field(None, description="ida by hunt and fill (instead of levels): "
                              "each record hunted up to the limit, then bisected")
    resolution: float | None = Field(None, gt=0, allow_inf_nan=False, description="ida hunt: "
                                     "bisect until the levels bracketing each capacity are "
                                     "this close (g)")
    limit: str = Field("pounding", description="ida hunt: the limit hunted (pounding, or a "
                       "name of limits); a failed run (collapse, non-convergence) passes it")
    condition: Literal["with_pounding", "without_pounding"] | None = Field(
        None, description="ida hunt: the runs whose demand is hunted (default: with pounding "
        "when pounding_runs, else without)")
    probability_level: float = Field(0.1, gt=0, lt=1, description="subset: the conditional "
                                     "probability p0 of each intermediate level")
    samples: int = Field(1000, ge=10, description="subset: runs per level")
    floor: float = Field(1e-6, ge=0, lt=1, description="subset over records: a record whose "
                         "probability of pounding is found below this is stopped there and "
                         "counts 0 (its bound widens the interval's upper end)")
    max_level: float = Field(5.0, gt=0, allow_inf_nan=False, description="ida hunt: the "
                             "highest level run; a record that has not passed the limit there "
                             "is right-censored (g)")


class PowerLaw(_Base):
    """A power-law hazard curve lambda = k0 IM^-k."""

    k0: float = Field(gt=0, description="Annual frequency of exceeding IM = 1 g.")
    k: float = Field(gt=0, description="The log-log slope of the hazard curve.")


class Hazard(_Base):
    """The hazard curve of the study's intensity measure: a table or a power law."""

    file: str | None = Field(None, description="A CSV hazard table (two columns, USGS or "
                             "OpenQuake form), relative to the study file.")
    power_law: PowerLaw | None = Field(None, description="A power law instead of a table.")


class Target(_Base):
    """The target annual frequency of pounding the gap is solved for."""

    annual_frequency: float | None = Field(None, gt=0, lt=1, description="Per year.")
    return_period: float | None = Field(None, gt=1, description="Years (its inverse is the "
                                        "annual frequency).")


class Limits(_Base):
    """Demand limits, by name."""

    drift: dict[str, float] = Field(default_factory=dict, description="name: drift (m)")
    drift_ratio: dict[str, float] = Field(
        default_factory=dict, description="name: storey drift ratio (drift over the storey's "
        "height; 0.01 is 1 %); needs storey heights (height) in the scene")
    acceleration: dict[str, float] = Field(default_factory=dict,
                                           description="name: absolute acceleration (g)")


class StudyFile(_Base):
    """A risk study of ``pframe risk`` (docs/risk.md)."""

    scene: str = Field(description="The scene file, relative to the study file.")
    suite: str | None = Field(None, description="A suite file, relative to the study file "
                              "(default: the scene's own excitation).")
    stochastic: dict | None = Field(None, description="Stochastic motions instead of a "
                                    "suite: the fields of a scene's stochastic excitation "
                                    "(model, its parameters; without kind and seed), "
                                    "realisations (how many) and seed (of the first; the "
                                    "others follow it).")
    uncertain: dict[str, dict] | None = Field(None, description="Uncertain scene values: "
                                              "a path (as sweeps name them; gap: every "
                                              "contact's gap) to {distribution: normal|"
                                              "lognormal|uniform, and mean/sd, median/"
                                              "dispersion or low/high}; sampled by Latin "
                                              "hypercube, one sample per run.")
    records_folder: str | None = Field(None, description="Where the suite's records are "
                                       "(default: beside the suite).")
    measure: str | None = Field(None, description="pga, sa:SECONDS or sa:BUILDING "
                                "(default: the suite's measure).")
    design: Design = Field(description="The analysis design.")
    dt: float | None = Field(None, gt=0, description="Step of the runs without contacts (s; "
                             "default: the scene's).")
    duration: float | None = Field(None, gt=0, description="Analysed time (s; default: the "
                                   "longest record plus three first periods).")
    pounding_runs: bool = Field(True, description="Also run with the contacts at the scene's "
                                "gaps and step, for demands with pounding.")
    limits: Limits = Field(default_factory=Limits, description="Demand limits.")
    hazard: Hazard | None = Field(None, description="The hazard curve.")
    target: Target | None = Field(None, description="The target annual frequency of "
                                  "pounding.")
    design_life: float = Field(50.0, gt=0, allow_inf_nan=False, description="Years over "
                               "which each limit state's probability of happening at least "
                               "once is given: 1 - exp(-annual frequency x years), occurrences "
                               "taken as a Poisson process.")
    codes: list | dict | str | None = Field(None, description="Building codes' separation "
                                           "rules shown beside the gap at target: names "
                                           "(asce7, tbdy2018, ...), {code: NAME, factors}, "
                                           "rules of your own, or {rules: [...], aligned, "
                                           "floor_tolerance} (docs/gap-audit.md#code-rules).")
    bootstrap: int = Field(200, ge=0, description="record resamples for the gap's interval")
    seed: int = Field(0, description="Seed of the bootstrap and of the MAF's range.")
    chunk: int | None = Field(None, ge=1, description="Variants per saved batch (a stopped "
                              "study resumes from them).")


class _At:
    """``FILE, line N, at FIELD`` for the messages about a study's fields."""

    def __init__(self, path, lines: dict):
        self.path, self.lines = path, lines

    def __call__(self, field: str) -> str:
        parts = tuple(int(p) if p.isdigit() else p for p in field.split("."))
        for cut in range(len(parts), 0, -1):
            if parts[:cut] in self.lines:
                return f"{self.path}, line {self.lines[parts[:cut]]}, at {field}"
        return f"{self.path}, at {field}"


def read_study(path) -> tuple[StudyFile, Path, str]:
    """The study file checked (its YAML as strictly as a scene's: a key given twice, YAML 1.2
    numbers, line numbers in every message) and its folder and text; InputError otherwise."""
    study, base, text, _ = _read(path)
    return study, base, text


def _read(path):
    from pframe.model.load import read_input, validated
    from pframe.yamltext import compose

    path = Path(path)
    text = read_input(path, "study")
    data, lines = compose(text, str(path))
    if not isinstance(data, dict):
        raise InputError(f"{path}: a risk study is a mapping (scene:, suite:, design:, ...)")
    study = validated(StudyFile, data, lines, str(path))
    at = _At(path, lines)
    design = study.design
    if study.codes is not None:
        from pframe.gap.selection import selection

        selection(study.codes, where=f"{path}, at codes")
    if study.uncertain is not None:
        from pframe.risk.uncertain import parse

        parse(study.uncertain, at("uncertain"))
        if design.hunt is not None:
            raise InputError(f"{at('uncertain')}: an ida by hunt and fill follows each "
                             "record with one scene; uncertain values go with msa, a grid "
                             "ida, cloud or subset")
    if design.kind == "subset":
        _check_subset(study, at)
    elif design.hunt is not None or design.resolution is not None:
        _check_hunt(study, at)
    elif design.kind in ("msa", "ida") and (not design.levels or len(design.levels) < 2
                                          or any(not (x > 0 and math.isfinite(x))
                                                 for x in design.levels)):
        raise InputError(f"{at('design.levels')}: a {design.kind} design needs at least two "
                         "positive intensity levels (g)")
    if design.kind == "cloud" and design.levels:
        raise InputError(f"{at('design.levels')}: a cloud analysis runs the records "
                         "unscaled; remove the levels (or use kind: msa)")
    if study.stochastic is not None:
        _check_stochastic(study, at)
    if study.hazard is not None and (study.hazard.file is None) == (study.hazard.power_law
                                                                    is None):
        raise InputError(f"{at('hazard')}: give either file: TABLE.csv or power_law: "
                         "{k0: ..., k: ...}")
    if study.target is not None and (study.target.annual_frequency is None) == (
            study.target.return_period is None):
        raise InputError(f"{at('target')}: give either annual_frequency or return_period")
    for kind, values in (("drift", study.limits.drift),
                         ("drift_ratio", study.limits.drift_ratio),
                         ("acceleration", study.limits.acceleration)):
        for name, v in values.items():
            if not (v > 0 and math.isfinite(v)):
                raise InputError(f"{at(f'limits.{kind}.{name}')}: a limit is a number > 0")
    if study.measure is not None:
        from pframe.gap.audit import parse_measure

        try:
            parse_measure(study.measure)
        except InputError:
            raise InputError(f"{at('measure')}: {study.measure!r} is not an intensity "
                             "measure; write pga, or sa:PERIOD with PERIOD in seconds or a "
                             "building's name (sa:0.5, sa:A)") from None
    return study, path.parent, text, lines


def _check_stochastic(study, at) -> None:
    if study.suite is not None:
        raise InputError(f"{at('stochastic')}: give a suite or stochastic motions, not both")
    n = study.stochastic.get("realisations", 1 if study.design.kind == "subset" else None)
    seed = study.stochastic.get("seed", 0)
    if not (isinstance(n, int) and not isinstance(n, bool) and n >= 1):
        raise InputError(f"{at('stochastic.realisations')}: the number of motions, an "
                         f"integer >= 1 (got {n!r})")
    if not (isinstance(seed, int) and not isinstance(seed, bool) and seed >= 0):
        raise InputError(f"{at('stochastic.seed')}: an integer >= 0 (got {seed!r})")


def _check_measure(spec, at, buildings) -> None:
    """The study's ``sa:PERIOD``: seconds > 0 or a building of the scene (named at the
    study's line, not the suite's)."""
    if spec.measure is None:
        return
    from pframe.gap.audit import parse_measure

    chosen = parse_measure(spec.measure)
    if chosen.kind != "sa":
        return
    try:
        period = float(chosen.period)
    except ValueError:
        if chosen.period not in buildings:
            raise InputError(f"{at('measure')}: {chosen.period!r} is neither a period in "
                             "seconds nor a building of the scene (" + ", ".join(buildings)
                             + ")") from None
        return
    if not (period > 0 and math.isfinite(period)):
        raise InputError(f"{at('measure')}: the spectral period must be a number > 0 s (got "
                         f"{chosen.period})")


def _check_subset(study, at) -> None:
    if study.suite is not None:
        _check_subset_records(study, at)
        return
    m = study.stochastic or {}
    if (m.get("model") != "clough_penzien" or m.get("envelope") is not None
            or m.get("duration") is None):
        raise InputError(f"{at('stochastic')}: a subset design runs over the white noise "
                         "of a stationary motion: give stochastic: {model: clough_penzien, "
                         "intensity, ground_frequency, ground_damping, duration, ...} without "
                         "an envelope (realisations are not needed), or give a suite of "
                         "records and uncertain values to run over")
    if "floor" in study.design.model_fields_set:
        raise InputError(f"{at('design.floor')}: the floor stops the weaker records of a "
                         "subset design over a suite; over a stochastic motion the one "
                         "probability is followed to its end (leave floor out)")
    if study.design.levels or study.hazard is not None or study.target is not None:
        raise InputError(f"{at('design')}: a subset design estimates the probability of "
                         "pounding under the study's motion; levels, hazard and target belong "
                         "to msa, ida and cloud")
    _check_chains(study, at)


def _check_subset_records(study, at) -> None:
    """A subset design over a suite: the uncertain values are its random space."""
    if not study.uncertain:
        raise InputError(f"{at('uncertain')}: a subset design over a suite of records runs "
                         "over the uncertain scene values (each record's probability of "
                         "pounding given those values); give uncertain: {gap: {distribution: "
                         "lognormal, median: ..., dispersion: ...}, ...}")
    levels = study.design.levels
    if levels is not None and (not levels or any(not (x > 0 and math.isfinite(x))
                                                 for x in levels)
                               or list(levels) != sorted(set(levels))):
        raise InputError(f"{at('design.levels')}: a subset design over records takes "
                         "intensity levels (g) to scale them to, positive and increasing, or "
                         "none (as recorded)")
    if study.hazard is not None and (levels is None or len(levels) < 2):
        raise InputError(f"{at('design.levels')}: the annual frequency of pounding over the "
                         "hazard integrates the probability at stripes of intensity: give two "
                         "or more levels (g) spanning the intensities that matter")
    if study.target is not None:
        raise InputError(f"{at('target')}: a subset design estimates the probability (and "
                         "with a hazard, the annual frequency) of pounding at the scene's gap "
                         "distribution; the gap at a target belongs to msa, ida and cloud")
    _check_chains(study, at)


def _check_chains(study, at) -> None:
    n, p0 = study.design.samples, study.design.probability_level
    seeds = n * p0
    if abs(seeds - round(seeds)) > 1e-9 or round(seeds) < 1 or n % round(seeds):
        raise InputError(f"{at('design.samples')}: samples x probability_level = {n} x "
                         f"{p0:g} must be a whole number of chains that divides samples")


def _check_hunt(study, at) -> None:
    design = study.design
    if design.kind != "ida" or design.levels:
        raise InputError(f"{at('design')}: hunt and resolution belong to an ida design "
                         "without levels (kind: ida, hunt: {start, step, growth}, "
                         "resolution: ...); a grid of levels is the other form")
    if design.hunt is None or design.resolution is None:
        raise InputError(f"{at('design.hunt' if design.hunt is None else 'design.resolution')}"
                         ": an ida by hunt and fill needs both hunt: {start: G, step: G, "
                         "growth: X} and resolution: G")
    if design.max_level <= design.hunt.start:
        raise InputError(f"{at('design.max_level')}: {design.max_level:g} g is not above "
                         f"the hunt's start ({design.hunt.start:g} g)")
    known = ["pounding", *study.limits.drift, *study.limits.drift_ratio,
             *study.limits.acceleration]
    if design.limit not in known:
        raise InputError(f"{at('design.limit')}: {design.limit!r} is not a limit of the "
                         f"study (known: {', '.join(known)})")
    if design.condition == "with_pounding" and not study.pounding_runs:
        raise InputError(f"{at('design.condition')}: with_pounding needs pounding_runs: "
                         "true")


def stochastic_suite(item: dict, where: str, until: float | None = None):
    """A suite of ``realisations`` motions of a stochastic model, seeds ``seed``, ``seed + 1``,
    ... (the scene's stochastic excitation, generated by pframe.excitation.stochastic). A
    pair of components (``x: {...}, y: {...}``, turned by ``angle``) draws two seeds a
    motion: ``seed + 2k`` for x and ``seed + 2k + 1`` for y, so that no two components share
    one. With ``until`` (s), each motion is kept only as far as the runs read it."""
    from pframe.excitation.suite import Suite, stochastic_motions

    item = dict(item)
    n, seed = item.pop("realisations", 1), item.pop("seed", 0)
    seeds = ([[seed + 2 * k, seed + 2 * k + 1] for k in range(n)] if "x" in item or "y" in item
             else list(range(seed, seed + n)))
    return Suite(tuple(stochastic_motions({**item, "seeds": seeds}, where, until)),
                 source=where.split(",")[0])


class _Definition:
    def __init__(self, digest: str, source: str, chunk: int):
        self.digest, self.source, self.chunk = digest, source, chunk


class _Spec:
    def __init__(self, count: int, chunk: int):
        self.count, self.chunks = count, -(-count // chunk)


def free_batch(inputs, variants, uncertain=None) -> tuple:
    """The scenes of ``variants`` (one per variant with ``uncertain``) and their batch
    without contacts, assembled (pframe.risk.runs.prepare): the first half of
    :func:`run_chunk`, which :func:`run_variants` prepares in a thread while the kernel runs
    the chunk before."""
    from pframe.risk.runs import prepare

    scenes = inputs.loaded
    if uncertain is not None:
        from pframe.risk.uncertain import scenes as variants_of

        scenes = variants_of(inputs.loaded, uncertain[0], uncertain[1])
    return scenes, prepare(scenes, inputs.pairs, inputs.accelerations(variants), inputs.steps,
                           inputs.dt, contacts=False, axes=inputs.channels)


def run_chunk(inputs, pounding_runs: bool, variants, uncertain=None, threads=None,
              prepared=None) -> dict:
    """One batch of variants (without contacts, and with them with ``pounding_runs``);
    ``uncertain``: (variables, their standard normals per variant); ``prepared``: what
    :func:`free_batch` gives of them, if it ran already. A pure function of its arguments:
    on a Dask cluster, a task."""
    from pframe.risk.runs import run_batch, with_contacts

    scene_dt = float(inputs.loaded.expanded.dt)
    contact_steps = int(math.ceil(inputs.steps * inputs.dt / scene_dt - 1e-9))
    scenes, batch = prepared or free_batch(inputs, variants, uncertain)
    ground = batch.accelerations
    free = run_batch(scenes, inputs.pairs, ground, inputs.steps, inputs.dt, contacts=False,
                     threads=threads, axes=inputs.channels, reach=pounding_runs, batch=batch)
    del batch, prepared  # its plan: the runs with contacts assemble their own
    if pounding_runs:
        if (contact_steps, scene_dt) != (inputs.steps, inputs.dt):
            ground = None  # the runs with contacts read their motions on their own steps

        def motions(index):
            if ground is None:
                return inputs.accelerations(variants[index], contact_steps, scene_dt)
            return ground if len(index) == len(ground) else ground[index]

        hit = with_contacts(scenes, inputs.pairs, free, (inputs.steps, inputs.dt), motions,
                            contact_steps, scene_dt, threads=threads, axes=inputs.channels)
    arrays = {f"free_{k}": v for k, v in free.items()}
    if pounding_runs:
        arrays.update({f"contact_{k}": v for k, v in hit.items()})
    return arrays


def _on_cluster(address: str, inputs, pounding_runs, todo, chunk, uncertain, finish):
    """The chunks ``todo`` as tasks on the Dask scheduler at ``address`` (as sweeps)."""
    from pframe.sweep.runner import dask_client

    client = dask_client(address, "runs")
    from distributed import as_completed

    with client:
        remote = client.scatter(inputs, broadcast=True)
        futures = {}
        for c in todo:
            variants = np.arange(c * chunk, min(inputs.count, (c + 1) * chunk))
            part = None if uncertain is None else (uncertain[0], uncertain[1][variants])
            futures[client.submit(run_chunk, remote, pounding_runs, variants, part, 1,
                                  retries=2, pure=False)] = c
        for future in as_completed(list(futures)):
            finish(futures[future], future.result())


def _here(inputs, pounding_runs, chunks, chunk, uncertain, threads, finish) -> None:
    """The ``chunks`` on this machine, in order: each chunk's batch without contacts is
    assembled in a thread while the kernel runs the chunk before (the assembly holds the
    interpreter, the kernel does not), so a CPU no longer waits for it between chunks; two
    chunks' batches are held at most."""
    from concurrent.futures import ThreadPoolExecutor

    def part(c):
        variants = np.arange(c * chunk, min(inputs.count, (c + 1) * chunk))
        return variants, None if uncertain is None else (uncertain[0], uncertain[1][variants])

    with ThreadPoolExecutor(1) as pool:
        coming = pool.submit(free_batch, inputs, *part(chunks[0])) if chunks else None
        for k, c in enumerate(chunks):
            prepared = coming.result()
            coming = (pool.submit(free_batch, inputs, *part(chunks[k + 1]))
                      if k + 1 < len(chunks) else None)
            finish(c, run_chunk(inputs, pounding_runs, *part(c), threads, prepared))
            prepared = None


def run_variants(inputs, pounding_runs: bool, chunk: int, output, threads, restart: bool,
                 progress=None, uncertain=None, identity: str = "",
                 scheduler: str | None = None) -> dict:
    """Every variant's arrays; chunks saved beside ``output`` so a stopped study resumes;
    with ``scheduler``, chunks run on that Dask cluster."""
    count = inputs.count
    spec = _Spec(count, chunk)
    parts = None
    if output is not None:
        from pframe.sweep.store import Parts

        digest = inputs.digest(f"risk chunk={chunk} pounding={pounding_runs}{identity}")
        parts = Parts(Path(output), _Definition(digest, inputs.loaded.source, chunk), spec)
    done: dict[int, dict] = {}

    def finish(c, arrays):
        if parts is not None:
            parts.save(c, arrays)
        done[c] = arrays
        if progress is not None:
            progress(sum(len(np.atleast_1d(a["free_complete"])) for a in done.values()), count)

    try:
        if parts is not None:
            done.update(parts.load_finished(restart,
                                            "scene, suite, levels, step, chunk size"))
        todo = [c for c in range(spec.chunks) if c not in done]
        if scheduler and todo:
            _on_cluster(scheduler, inputs, pounding_runs, todo, chunk, uncertain, finish)
        _here(inputs, pounding_runs, [c for c in todo if c not in done], chunk, uncertain,
              threads, finish)
    finally:
        if parts is not None:
            parts.close()
    ordered = [done[c] for c in range(spec.chunks)]
    return {k: (np.concatenate([o[k] for o in ordered]) if np.ndim(ordered[0][k]) else
                sum(float(o[k]) for o in ordered)) for k in ordered[0]}


@dataclasses.dataclass
class Opened:
    """A study read and checked against its scene, suite and hazard, ready to run."""

    spec: StudyFile
    text: str
    hazard: object  # HazardCurve or None
    inputs: object  # pframe.gap.audit.AuditInputs
    params: list  # the uncertain values (pframe.risk.sampling.Uncertain)
    reads: list  # every file the study reads: never an output


def open_study(study, records_folder=None) -> Opened:
    """Read the study file, its hazard table, scene and suite (with its records), and check
    everything ``pframe risk`` would refuse before it runs (``pframe validate`` runs this).
    Raises :class:`InputError` naming the file, the line and the field."""
    from pframe.gap.audit import prepare
    from pframe.reader import load_scene, require_si

    spec, base, text, lines = _read(study)
    at = _At(study, lines)
    scene = (base / spec.scene).resolve()
    suite = None if spec.suite is None else (base / spec.suite).resolve()
    loaded = None
    if spec.stochastic is not None:
        _check_motions(spec, at)
        loaded = load_scene(scene)
        suite = stochastic_suite(spec.stochastic, at("stochastic"),
                                 _runs_end(spec, float(loaded.expanded.dt)))
    folder = records_folder or (None if spec.records_folder is None
                                else (base / spec.records_folder).resolve())
    hazard, table = None, None
    if spec.hazard is not None:
        from pframe.risk.hazard import HazardCurve, read_hazard

        if spec.hazard.file:
            table = base / spec.hazard.file
            if not table.exists():
                raise InputError(f"{at('hazard.file')}: no hazard table {table} (the path is "
                                 "relative to the study file)")
            hazard = read_hazard(table)
        else:
            hazard = HazardCurve.power_law(spec.hazard.power_law.k0, spec.hazard.power_law.k)
    if hazard is not None and d_levels_above(spec, hazard):
        raise InputError(f"{at('design.levels')}: every stripe is above the hazard table's "
                         f"last intensity ({hazard.im[-1]:g} g): the table says nothing of how "
                         "often they are exceeded, so no annual frequency can be given; "
                         "extend the table up to the stripes, or lower them")
    loaded = loaded or load_scene(scene)
    require_si(loaded, "a risk study")  # its hazard, stripes and gaps are in SI
    _check_measure(spec, at, list(loaded.expanded.buildings))
    if suite is None:  # the scene's own excitation runs as the scene says
        for field, value, own in (("dt", spec.dt, loaded.expanded.dt),
                                  ("duration", spec.duration, None)):
            if value is not None and value != own:
                raise InputError(f"{at(field)}: the study runs the scene's own excitation, "
                                 f"on the scene's step and for its analysis.duration ({scene});"
                                 f" {field} applies to a suite of records or stochastic "
                                 "motions (remove it, or change the scene)")
    d = spec.design
    if d.kind == "subset":
        levels = (d.levels or None) if spec.stochastic is None else None
    else:
        levels = [d.hunt.start] if d.hunt is not None else d.levels
    inputs = prepare(loaded, suite, levels=levels, measure=spec.measure,
                     duration=spec.duration, dt=spec.dt, records_folder=folder)
    _check_runs(spec, at, inputs)
    heights = np.asarray(inputs.loaded.expanded.story_height, float)
    if spec.limits.drift_ratio and not np.all(np.isfinite(heights)):
        raise InputError(f"{at('limits.drift_ratio')}: a drift-ratio limit needs every "
                         f"storey's height, and the scene {scene} gives none for some storeys "
                         "(give height on its buildings), or give the limit as a drift in "
                         "metres under limits.drift")
    params = []
    if spec.uncertain:
        from pframe.risk.uncertain import check_paths, parse

        params = parse(spec.uncertain, at("uncertain"))
        check_paths(inputs.loaded, params, at("uncertain"))
    return Opened(spec, text, hazard, inputs, params, study_reads(study, inputs, table))


def _runs_end(spec, scene_dt: float) -> float | None:
    """The last time a study's runs read of its stochastic motions (s): that of the runs
    without contacts (the study's duration on its step) or with them (as long, on the
    scene's step), or None when each motion is needed whole: no duration given (the runs
    last as long as the longest motion), or an intensity measure that is a spectral value
    (it takes the whole motion)."""
    from pframe.gap.audit import parse_measure

    measure = parse_measure(spec.measure)
    if spec.duration is None or (measure is not None and measure.kind != "pga"):
        return None
    dt = float(spec.dt or scene_dt)
    free = math.ceil(spec.duration / dt - 1e-9) * dt
    return max(free, math.ceil(free / scene_dt - 1e-9) * scene_dt)


def _check_motions(spec, at) -> None:
    """Stochastic motions that could not be held (each is kept whole, on its own step), or
    more runs than a study takes: refused before one is generated, naming the count."""
    from pframe import resources

    m, design = spec.stochastic, spec.design
    n = m.get("realisations", 1)
    levels = len(design.levels or [1]) if design.kind in ("msa", "ida", "subset") else 1
    if n * levels > resources.MAX_VARIANTS:
        raise InputError(f"{at('stochastic.realisations')}: {n:,} motions x {levels} levels is "
                         f"{n * levels:,} runs; a study runs at most "
                         f"{resources.MAX_VARIANTS:,} (an extra zero typed is the usual cause)")
    try:
        points = float(m.get("duration", 0.0)) / float(m.get("step", 0.01)) + 1
    except (TypeError, ValueError, ZeroDivisionError):
        return  # the motion's own checks name it
    need = 16.0 * n * points  # times and accelerations of every motion
    if need > resources.memory_limit():
        raise InputError(f"{at('stochastic.realisations')}: {n:,} motions of {points:,.0f} "
                         f"points each need about {resources.human(need)} of memory, more than "
                         f"the {resources.human(resources.memory_limit())} this machine allows; "
                         "use fewer realisations (or a longer step)")


def _check_runs(spec, at, inputs) -> None:
    """Steps, batches and subset samples that could not run on this machine, refused before
    anything runs, naming the study's field that sets them (not what a run records)."""
    from pframe import resources

    field = "dt" if spec.dt is not None else "duration"
    if resources.check_steps(inputs.steps, inputs.dt, inputs.steps * inputs.dt):
        raise InputError(f"{at(field)}: {inputs.steps * inputs.dt:g} s analysed on a step of "
                         f"{inputs.dt:g} s is {inputs.steps:,} steps per run, more than "
                         f"pframe runs ({resources.MAX_STEPS:.0e} steps, or what this machine's "
                         "memory holds); check the units (seconds) and give a larger dt or a "
                         "shorter duration")
    limit = resources.memory_limit()
    if spec.design.kind == "subset":
        dim = len(spec.uncertain or {}) + (0 if spec.stochastic is None else int(
            math.ceil(float(spec.stochastic["duration"])
                      / float(spec.stochastic.get("step", 0.01)))) + 1)
        need = 3 * 8.0 * spec.design.samples * dim  # the samples, their proposals, a level's
        if need > limit:
            raise InputError(f"{at('design.samples')}: {spec.design.samples:,} samples of "
                             f"{dim:,} standard normals each need about {resources.human(need)} "
                             f"of memory, more than the {resources.human(limit)} this machine "
                             "allows; use fewer samples per level")
        return
    batch = min(spec.chunk or default_chunk(inputs), inputs.count)
    need = GROUND_BYTES * batch * (inputs.steps + 1)
    if need > limit:
        raise InputError(f"{at('chunk' if spec.chunk else field)}: {batch:,} runs of "
                         f"{inputs.steps + 1:,} steps in one batch need about "
                         f"{resources.human(need)} of memory for their ground motions, more than "
                         f"the {resources.human(limit)} this machine allows; give chunk: N (runs "
                         "per batch) or a larger dt")


def default_chunk(inputs) -> int:
    """Variants per batch when the study gives no chunk: as many as hold :data:`BATCH_BYTES`
    of ground motion in their longer runs (those with contacts run on the scene's step),
    at most all of them. The batches are saved beside the output as they finish, as given
    chunks are."""
    scene_dt = float(inputs.loaded.expanded.dt)
    steps = max(inputs.steps, math.ceil(inputs.steps * inputs.dt / scene_dt - 1e-9))
    per_run = GROUND_BYTES * (steps + 1) * len(inputs.channels)
    return max(1, min(inputs.count, int(BATCH_BYTES // per_run)))


def d_levels_above(spec, hazard) -> bool:
    """A subset design over stripes whose every stripe lies above the hazard table (its
    annual frequency would rest on the table's lower bound above its last IM only)."""
    levels = spec.design.levels
    return (spec.design.kind == "subset" and bool(levels)
            and min(levels) > float(hazard.im[-1]))


def study_reads(study, inputs, table=None) -> list[str]:
    """Every file a study reads (the study, its scene and the scene's record, the suite and
    its records, the hazard table): the inputs an output must never replace."""
    from pframe.api import run_inputs

    reads = [*run_inputs(inputs.loaded), inputs.suite.source, str(study),
             *(f for m in inputs.suite.motions for f in m.sources), table]
    return [str(r) for r in reads if r]


def risk(study, *, output: str | Path | None = None, overwrite: bool = False,
         records_folder=None, threads: int | None = None, progress=None,
         timings: dict | None = None, scheduler: str | None = None):
    """Run a risk study (a study file, see :mod:`pframe.risk.study`) and return its
    ``xarray.Dataset``: the runs (record x level), fragilities of pounding and of each
    demand limit with and without pounding (maximum likelihood, 90 % confidence bounds),
    mean annual frequencies, and the gap at the target annual frequency beside the code
    rules. With ``output``, writes it (netCDF-4, CF-1.8), keeping finished batches beside it
    until then so that a stopped study resumes. Warnings (runs cut short, a hazard table too
    short for the fragilities, runs that failed) go in ``warnings`` and the file's
    ``warnings`` attribute. ``threads``: the kernel's threads, and the processes the gap's
    bootstrap resamples are shared among (default: one per CPU). With ``scheduler``
    (tcp://HOST:PORT), the batches of an msa, grid ida or cloud design run on that Dask
    cluster (the ``cluster`` extra), saved as they come back. Raises :class:`InputError` for bad input."""
    from pframe.risk.analysis import analyse
    from pframe.risk.output import build_dataset

    start = time.perf_counter()
    opened = open_study(study, records_folder)
    spec, text, hazard, inputs = opened.spec, opened.text, opened.hazard, opened.inputs
    if scheduler and (spec.design.kind == "subset" or spec.design.hunt is not None):
        raise InputError(f"--scheduler {scheduler}: {study} is a "
                         + ("subset simulation" if spec.design.kind == "subset" else
                            "hunt and fill") + ", whose rounds depend on each other; "
                         "pframe runs it on this machine (leave out --scheduler)")
    if output is not None:
        from pframe import outputs

        output = outputs.check_output(output, inputs=opened.reads, overwrite=overwrite,
                                      what="risk file")
    if spec.design.kind == "subset":
        from pframe.risk.uncertain import run_subset

        return run_subset(spec, text, study, inputs, opened.params, output, overwrite,
                          threads, timings, start, progress, hazard)
    hunt = spec.design.hunt is not None
    chunk = spec.chunk or default_chunk(inputs)
    search = None
    if hunt:
        from pframe.risk.ida import run_hunt

        rows, inputs, search = run_hunt(inputs, spec, output, threads, overwrite, progress)
    else:
        uncertain, identity = None, ""
        if spec.uncertain:
            import json

            from pframe.risk.sampling import latin_hypercube

            params = opened.params
            u = latin_hypercube(inputs.count, len(params), np.random.default_rng(spec.seed))
            uncertain = (params, u)
            identity = f" uncertain={json.dumps(spec.uncertain, sort_keys=True)} seed={spec.seed}"
        rows = run_variants(inputs, spec.pounding_runs, chunk, output, threads, overwrite,
                            progress, uncertain, identity, scheduler)
    result = analyse(spec, inputs, rows, hazard, threads)
    for line in result.warnings:
        warnings.warn(f"{study}: {line}", stacklevel=2)
    ds = build_dataset(spec, inputs, rows, result, text, str(study), hazard, search)
    if output is not None:
        import shutil

        from pframe.record.netcdf import write_dataset
        from pframe.sweep.store import parts_folder

        write_dataset(ds, output)
        shutil.rmtree(parts_folder(Path(output)), ignore_errors=True)
    if timings is not None:
        timings.update(wall_seconds=time.perf_counter() - start,
                       variants=search.runs if search is not None else inputs.count,
                       solve_seconds=float(rows["free_solve_seconds"])
                       + float(rows.get("contact_solve_seconds", 0.0)),
                       # runs with contacts integrated (the others reused the runs without)
                       contact_runs=int(np.sum(rows.get("contact_integrated", 0))))
    return ds


