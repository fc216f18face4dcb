"""The gap audit: code minimum separations beside the simulated no-pounding gap, over a suite
of ground motions scaled to intensity levels (docs/gap-audit.md)."""

from __future__ import annotations

import dataclasses
import hashlib
import math
import time
import warnings
from pathlib import Path

import numpy as np

from pframe.errors import InputError, given, option
from pframe.excitation.suite import GroundMotion, Measure, Suite, load_suite, scale_factors, suite_from_files
from pframe.gap import members, runs


@dataclasses.dataclass(frozen=True)
class AuditInputs:
    """What the batch runs: the variants' ground motions and the bookkeeping around them."""

    loaded: object
    pairs: runs.Pairs
    suite: Suite
    levels: np.ndarray  # (L,) target intensities (g), or [1.0] for the records as given
    factors: np.ndarray  # (R, L)
    intensities: np.ndarray  # (R,) of each record as given (g)
    steps: int
    dt: float
    periods: np.ndarray  # (buildings,)
    damping: np.ndarray
    scaled: bool
    warnings: tuple = ()  # what the runs leave out (records cut by the duration)
    #: the site's axes the runs' ground motions load ('x', and 'y' for a scene in plan
    #: under two components or a motion at an angle)
    channels: tuple[str, ...] = ("x",)
    #: how the members reach a scene's supports (pframe.gap.members); None: one ground
    supports: object = None

    def motion(self, record: int, times: np.ndarray) -> np.ndarray:
        """(C, len(times)) record ``record`` as given (unscaled) on ``times`` (s): along the
        runs' ``channels``, or at each support along each (pframe.gap.members)."""
        motion = self.suite.motions[record]
        if self.supports is not None:
            return self.supports.rows(motion, times)
        return motion.on_site(times, self.channels)

    @property
    def count(self) -> int:
        return self.factors.size

    def accelerations(self, variants, steps: int | None = None,
                      dt: float | None = None) -> np.ndarray:
        """Ground accelerations (len(variants), C, steps + 1) of variants (record-major)
        along the runs' ``channels``, on this audit's step (or ``steps`` of ``dt``)."""
        steps = self.steps if steps is None else int(steps)
        times = np.arange(steps + 1) * (self.dt if dt is None else dt)
        levels = self.factors.shape[1]
        out = None
        cache: dict[int, np.ndarray] = {}
        for k, v in enumerate(variants):
            r, j = divmod(int(v), levels)
            if r not in cache:
                cache = {r: self.motion(r, times)}
            if out is None:
                out = np.empty((len(variants),) + cache[r].shape)
            out[k] = self.factors[r, j] * cache[r]
        return out if out is not None else np.empty((0, len(self.channels), steps + 1))

    def digest(self, options: str) -> str:
        from pframe.sweep.spec import code_fingerprint

        h = hashlib.sha256()
        h.update(self.loaded.text.encode())
        for m in (n for member in self.suite.motions
                  for n in (member, *(p for _, p in member.at_supports))):
            h.update(m.name.encode())
            h.update(np.ascontiguousarray(m.time).tobytes())
            h.update(np.ascontiguousarray(m.acceleration).tobytes())
            if m.second is not None or m.angle:  # a pair, or a direction: its own runs
                h.update(f"{m.angle!r}".encode())
                h.update(np.ascontiguousarray(m.second if m.second is not None else
                                              np.zeros(0)).tobytes())
        h.update(self.factors.tobytes())
        h.update(f"{self.steps} {self.dt!r} {options} {code_fingerprint()}".encode())
        return h.hexdigest()[:32]


def parse_measure(measure) -> Measure | None:
    """A suite's intensity measure from ``pga``, ``sa:SECONDS``, ``sa:BUILDING`` (or a dict,
    or a Measure); None stays None. InputError for anything else."""
    if measure is None or isinstance(measure, Measure):
        return measure
    if isinstance(measure, dict):
        return Measure(**measure)
    text = str(measure).strip()
    kind, _, period = text.partition(":")
    kind = kind.strip().lower()
    if kind not in ("pga", "sa") or (kind == "sa" and not period) or (kind == "pga" and period):
        raise InputError(f"--measure {text}: write pga, or sa:PERIOD with PERIOD in seconds or "
                         "a building's name (sa:0.5, sa:A)")
    return Measure(kind=kind, period=period.strip() or None)


def _scene_motion(loaded) -> GroundMotion:
    ex = loaded.expanded
    moved = members.several(loaded) and any(s.excitation is not None
                                            for s in loaded.scene.supports)
    if loaded.scene.excitation is None and not moved:
        raise InputError(f"{loaded.source}: the scene has no excitation; give a suite of "
                         "records (--suite) or an excitation in the scene")
    excitation = loaded.scene.excitation
    kind = excitation.kind if excitation is not None else "supports"
    name = Path(excitation.file).name if kind == "record" else kind
    if kind in ("stochastic", "coherent"):
        name = (f"{excitation.model}-seed{excitation.seed}" if kind == "stochastic"
                else f"coherent-seed{excitation.seed}")
    if members.several(loaded):  # each support's motion as the scene gives it
        return members.own_member(loaded, name)
    times = np.arange(ex.steps + 1) * ex.dt
    # two components: the scene's samples along the site's x and y (already turned)
    second = None if ex.ground_acceleration_y is None else ex.ground_acceleration_y.copy()
    return GroundMotion(name, times, ex.ground_acceleration.copy(), loaded.source,
                        second=second, directed=True)


#: what a suite entry for a scene whose motion has two components writes
DIRECTED = ("write each record as a pair, the two components of one recording, {x: FILE, y: "
            "FILE, angle: DEGREES} (or angles: [...], one run each), or as one record along "
            "a direction, {file: FILE, angle: DEGREES} (angle 0: along the site's x); and "
            "each stochastic motion as a pair, {x: {model: ...}, y: {model: ...}, angle: "
            "DEGREES}, or with the angle it acts along; docs/gap-audit.md#suites-in-plan")


def run_channels(loaded, suite: Suite, own: bool) -> tuple[str, ...]:
    """The site's axes the runs load: x, and y when the scene's motion has two components or
    a motion of the suite moves the ground along y. Under a scene whose motion has two
    components, a motion the suite does not place on the site (a plain record, a folder's
    files, a stochastic entry without an angle) is refused: it could mean either axis, or
    the pair it came from."""
    if not own and "y" in loaded.expanded.axes:
        loose = [m.name for m in suite.motions if not m.directed]
        if loose:
            raise InputError(
                f"{suite.source or 'the suite'}: {', '.join(loose[:4])}"
                f"{' ...' if len(loose) > 4 else ''}: the scene {loaded.source} is shaken in "
                "two components, and these motions do not say how they stand on the site (they "
                f"could mean either axis, or half of a pair); {DIRECTED}")
    if "y" in loaded.expanded.axes or any(m.loads_y for m in suite.motions):
        return ("x", "y")
    return ("x",)


def _record_extent(loaded, suite: Suite, own: bool) -> tuple[np.ndarray, np.ndarray]:
    """End time and time of the peak (s) of each record as it is applied; for the scene's
    own record, of the whole record (the scene's duration may stop before its end)."""
    if own and loaded.expanded.record is not None:
        record = loaded.expanded.record
        return (np.array([record.times[-1]]),
                np.array([record.times[int(np.abs(record.acceleration).argmax())]]))
    ends = np.array([m.duration for m in suite.motions])
    peaks = np.array([m.peak_time for m in suite.motions])
    return ends, peaks


#: records named one by one in the warnings of the runs that stop before their end; the
#: others are counted in one more (a study of 10^4 stochastic motions is not 10^4 lines)
CUT_NAMED = 10


def cut_warnings(names, ends, peaks, analysed: float, dt: float, remedy: str) -> list[str]:
    """One warning per record the analysed time stops before the end of (the first
    :data:`CUT_NAMED`; then one counting the others, and how many of them have their peak
    ground acceleration past the end)."""
    out, others, missing = [], 0, 0
    for name, end, peak in zip(names, ends, peaks):
        if end <= analysed + 0.5 * dt:
            continue
        if len(out) == CUT_NAMED:
            others += 1
            missing += peak > analysed
            continue
        missed = (f"its peak ground acceleration (t = {peak:.4g} s) is past the end, so the "
                  "response to it is missing" if peak > analysed else
                  "its peak ground acceleration is inside")
        out.append(f"record {name}: the runs stop at {analysed:.4g} s, but the record runs to "
                   f"{end:.4g} s ({missed}); {remedy}")
    if others:
        out.append(f"{others} more records: the runs stop at {analysed:.4g} s, before each "
                   f"record's end; {missing} of them have their peak ground acceleration past "
                   f"it (the response to it is missing); {remedy}")
    return out


def prepare(scene, suite=None, *, levels=None, measure=None, duration: float | None = None,
            dt: float | None = None, records_folder=None) -> AuditInputs:
    """Read the scene and the suite, find the buildings' first modes and every record's
    scale factor at every level."""
    from pframe.reader import load_scene, require_si

    loaded = load_scene(scene) if isinstance(scene, (str, Path)) else scene
    require_si(loaded, "a gap audit")  # its rules, suites and files are in SI
    pairs = runs.contact_pairs(loaded)
    own = suite is None
    if own:
        suite = Suite((_scene_motion(loaded),), source=loaded.source)
    elif isinstance(suite, (str, Path)):
        suite = load_suite(suite, records_folder)
    elif not isinstance(suite, Suite):
        files = [Path(f) for f in suite]
        suite = (load_suite(files[0], records_folder) if len(files) == 1
                 else suite_from_files(files, source=", ".join(map(str, files))))
    channels = run_channels(loaded, suite, own)
    plan = runs.base_plan(loaded, channels)
    periods, damping = runs.first_modes(plan)
    chosen = parse_measure(measure)
    if chosen is not None:
        suite = dataclasses.replace(suite, measure=chosen)
    if levels is not None:
        levels = [float(x) for x in levels]
        if not levels or any(not (x > 0 and math.isfinite(x)) for x in levels):
            raise InputError(f"--levels {levels}: intensity levels are positive numbers (g)")
    if dt is not None and not (dt > 0 and math.isfinite(dt)):
        raise InputError(f"--dt {dt}: the time step is a number > 0 (s)")
    if own and dt is not None and dt != loaded.expanded.dt:
        raise InputError(f"--dt {dt}: the scene's own excitation runs on the scene's step "
                         f"({loaded.expanded.dt:g} s); --dt applies to a suite of records")
    dt = float(dt or loaded.expanded.dt)
    if own:
        steps = loaded.expanded.steps
        remedy = ("lengthen the scene's analysis.duration to at least its record's length "
                  "to audit the whole record")
    else:
        if duration is not None and not (duration > 0 and math.isfinite(duration)):
            raise InputError(f"--duration {duration}: the analysed time is a number > 0 (s)")
        remedy = ("leave out --duration (the default runs the longest record plus three "
                  "first periods) or give at least the record's length")
        if duration is None:
            longest = max(members.duration(loaded, m) for m in suite.motions)
            duration = longest + runs.TAIL_PERIODS * float(np.max(periods[np.isfinite(periods)]))
        steps = int(math.ceil(duration / dt - 1e-9))
    # a motion per support, simulations made: the intensities are the reference supports'
    suite, on_supports, simulated = members.resolve(loaded, suite, channels, steps, dt, own)
    by_building = dict(zip(plan.buildings, periods))
    level_values, factors, ims = scale_factors(suite, by_building, levels)
    ends, peaks = _record_extent(loaded, suite, own)
    warnings = cut_warnings(suite.names, ends, peaks, steps * dt, dt, remedy) + list(simulated)
    return AuditInputs(loaded, pairs, suite, np.asarray(level_values, float), factors, ims,
                       steps, dt, periods, damping, levels is not None or suite.levels is not None,
                       tuple(warnings), channels, on_supports)


class _Definition:
    """What the chunk store needs to know of the audit (its identity and chunking)."""

    def __init__(self, digest: str, source: str, chunk: int):
        self.digest, self.source, self.chunk = digest, source, chunk


class _Spec:
    def __init__(self, count: int, chunk: int):
        self.count = count
        self.chunks = -(-count // chunk)


def code_rules(codes, inputs, aligned=None):
    """The :class:`~pframe.gap.selection.Selection` of ``codes`` (anything
    :func:`~pframe.gap.selection.selection` takes), the contacts' floor geometry and the
    warnings: the buildings not elastic (code rules take elastic peaks), floor levels or
    heights unknown."""
    from pframe.gap.floors import contact_geometry
    from pframe.gap.selection import selection, warnings_for

    found = selection(codes, aligned=aligned)
    geometry = contact_geometry(inputs.loaded.expanded, inputs.pairs.left, inputs.pairs.right,
                                override=found.aligned, tolerance=found.tolerance)
    materials = {s.law.name for s in inputs.loaded.expanded.stories}
    return found, geometry, warnings_for(found, geometry, materials)


def audit(scene, suite=None, *, gap: float | None = None, levels=None, measure=None,
          en_coincident: bool = False, codes=None, aligned: bool | None = None,
          duration: float | None = None, dt: float | None = None, records_folder=None,
          output: str | Path | None = None, overwrite: bool = False, chunk: int | None = None,
          threads: int | None = None, progress=None, timings: dict | None = None):
    """Gap audit of a scene: for each contact level and record (x intensity level), the ABS,
    SRSS and DDC separations of the two buildings' peak displacements run without contact,
    and the simulated critical gap g_req = max_t (u_left - u_right); with ``gap``, the
    fraction of records that pound and a lognormal fragility over the levels.

    ``suite``: a suite file (YAML), a folder of .AT2 files, a list of record files, a
    :class:`~pframe.excitation.suite.Suite`, or None for the scene's own excitation. ``levels``
    (g) scale every record to each intensity in ``measure`` (``"pga"``, ``"sa:0.5"``,
    ``"sa:A"`` for building A's first period, or a Measure). Returns an ``xarray.Dataset``
    (records x levels x contacts x rules); with ``output``, also writes it (netCDF4/HDF5),
    saving the batch in chunks of ``chunk`` variants beside it so that a stopped audit
    resumes. ``dt`` (s) replaces the scene's step for the records (the runs have no contact
    to resolve); ``records_folder`` is where a suite file's records are (default: beside
    it). ``codes`` adds code rules (``"asce7,tbdy2018:R=6"``, a list, ``{"asce7": {"R": 6}}``,
    a YAML file; :func:`pframe.gap.selection.selection`); ``aligned`` (True, False) replaces
    the aligned-floor decision from the storey heights. ``timings``, a dict, receives the
    wall and kernel seconds. Raises
    :class:`InputError` for bad input.
    """
    from pframe.gap.output import build_dataset, write_dataset

    start = time.perf_counter()
    if gap is not None and not (gap >= 0 and math.isfinite(gap)):
        raise InputError(f"--gap {gap}: the provided gap is a number >= 0 (m)")
    inputs = prepare(scene, suite, levels=levels, measure=measure, duration=duration, dt=dt,
                     records_folder=records_folder)
    codes, geometry, extra = code_rules(codes, inputs, aligned)
    if extra:
        inputs = dataclasses.replace(inputs, warnings=tuple(inputs.warnings) + tuple(extra))
    for text in inputs.warnings:  # also in the result's `warnings` attribute
        warnings.warn(f"{inputs.loaded.source}: {text}", stacklevel=2)
    if output is not None:  # never a device, the scene, the suite or a record it reads
        from pframe import outputs
        from pframe.api import run_inputs

        reads = [*run_inputs(inputs.loaded), inputs.suite.source,
                 *(f for m in inputs.suite.motions for f in m.sources)]
        output = outputs.check_output(output, inputs=[r for r in reads if r],
                                      overwrite=overwrite, what="audit file")
    count = inputs.count
    chunk = count if chunk is None else int(chunk)
    if chunk < 1:
        raise InputError(f"{given('chunk', chunk)}: a chunk holds at least one variant")
    rows = _run_chunks(inputs, chunk, output, threads, progress, overwrite)
    ds = build_dataset(inputs, rows, gap=gap, en_coincident=en_coincident, codes=codes,
                       geometry=geometry)
    if output is not None:
        import shutil

        from pframe.sweep.store import parts_folder

        write_dataset(ds, output)
        shutil.rmtree(parts_folder(output), ignore_errors=True)
    if timings is not None:  # printed by the command, never written to the file
        timings.update(wall_seconds=time.perf_counter() - start,
                       solve_seconds=float(rows["solve_seconds"]), variants=inputs.count,
                       steps=inputs.steps)
    return ds


def _run_chunks(inputs: AuditInputs, chunk: int, output, threads, progress,
                overwrite: bool = False) -> dict:
    """Run the batches not yet saved beside ``output`` (all, without one); return every
    variant's rows in order. Batches of the same audit found there are taken up, even with
    ``overwrite``; batches of another audit are discarded only with it."""
    count = inputs.count
    spec = _Spec(count, chunk)
    parts = None
    if output is not None:
        from pframe.sweep.store import Parts

        definition = _Definition(inputs.digest(f"chunk={chunk}"), inputs.loaded.source, chunk)
        parts = Parts(Path(output), definition, spec)
    done: dict[int, dict] = {}
    try:
        if parts is not None:
            try:
                finished = parts.open(restart=overwrite)
            except InputError as exc:
                if "holds" not in str(exc):
                    raise
                raise InputError(
                    f"{parts.folder}: holds batches of another audit (another scene, suite, "
                    f"levels, step, chunk size or pframe code); pass {option('overwrite')} to "
                    "discard them and start again, or choose another output name with "
                    f"{option('output')}") from None
            for c in finished:
                done[c] = parts.load(c)
        finished = sum(min(chunk, count - c * chunk) for c in done)
        for c in range(spec.chunks):
            if c in done:
                continue
            variants = np.arange(c * chunk, min(count, (c + 1) * chunk))
            acc = inputs.accelerations(variants)
            offset = finished

            def report(step, total, offset=offset, size=variants.size):
                if progress is not None:
                    progress(offset + size * step / total, count)

            arrays = runs.run_batch(inputs.loaded, inputs.pairs, acc, inputs.steps, inputs.dt,
                                    threads, report if progress else None, inputs.channels)
            if parts is not None:
                parts.save(c, arrays)
            done[c] = arrays
            finished += variants.size
    finally:
        if parts is not None:
            parts.close()
    ordered = [done[c] for c in range(spec.chunks)]
    out = {key: np.concatenate([o[key] for o in ordered]) for key in
           ("peak_left", "peak_right", "g_req", "complete", "status")}
    out["solve_seconds"] = sum(float(o["solve_seconds"]) for o in ordered)
    return out
