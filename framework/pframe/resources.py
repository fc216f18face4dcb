"""What a run will need, estimated before anything is allocated, and the limits it must meet.

A unit mistake (a duration in milliseconds typed as seconds, a dt in microseconds) or a hostile
file can ask for 10^12 steps or a 200,000-floor building. :func:`check_steps` refuses, while
the scene is being resolved and before the time axis exists, a step count whose ground-motion
arrays alone cannot fit; :func:`estimate` adds up the memory of the recorders (streamed to the
file in blocks of at most 32 MiB by ``pframe solve``, held whole by sweeps), the kernel's work
arrays and the scene's own objects, the size of the result file and the run time, and
:func:`check` refuses (exit 2, one paragraph with the numbers and how to reduce them) what
does not fit, or warns about a run that fits but is very large.

The memory limit is 80 % of the machine's physical memory, or ``PFRAME_MEMORY_LIMIT`` (bytes,
or a number with KiB, MiB, GiB, TiB) when set: a service that runs scene files from others
sets it lower.
"""

from __future__ import annotations

import math
import os
import re
from dataclasses import dataclass

#: the most time steps a run may have (a year of ground motion at dt = 0.03 s; 10^9 steps of
#: the smallest scene take about ten minutes)
MAX_STEPS = 10**9
#: the most variants a sweep may have
MAX_VARIANTS = 10**6
#: values along one axis of a sweep
MAX_AXIS_VALUES = 10**6
#: a run estimated to take longer than this, or to write more than WARN_FILE_BYTES, is warned
#: about (it still runs)
WARN_SECONDS = 600.0
WARN_FILE_BYTES = 4 * 2**30
#: bytes of the streamed history blocks (pframe.kernel.run.STREAM_BYTES) and the copies the
#: writer makes of one block (columns in node order, unit conversion)
STREAM_BYTES = 32 * 2**20
_STREAM_COPIES = 3
#: the interpreter, numpy, numba and the loaded kernel
_BASE_BYTES = 200 * 2**20
#: Python objects per floor, storey or contact while a scene is read and resolved (the YAML
#: values, the validated models, the resolved elements)
_OBJECT_BYTES = 2048
#: float arrays of the kernel's state and work per degree of freedom, storey and contact
_ARRAYS_PER_DOF, _ARRAYS_PER_ELEMENT, _BAND = 40, 30, 8
#: copies of the ground motion while the scene is resolved and assembled (time axis, samples,
#: the plan's copy, the stability check's velocity)
_GROUND_COPIES = 4
#: kernel time per step: a constant and a part per degree of freedom, storey or contact
#: (measured on a 2-core machine: 0.6 us a step for the paper's 6-floor pair, 8 s for 100
#: steps of a 400,000-floor pair; see docs/getting-started.md)
_STEP_SECONDS, _ELEMENT_SECONDS = 0.3e-6, 0.1e-6
#: time to read, resolve and assemble a scene, per floor, storey or contact (measured on the
#: 2-core machine: 11 s for a pair of 100,000-floor buildings, 4 s of it resolving; the kernel
#: then takes 0.17 us a floor and step)
_SETUP_SECONDS = 55e-6
#: floors, storeys and contacts a scene may have without PFRAME_MAX_FLOORS: about 11 s and
#: 1 GiB of setting up before the first step, and 35 ms a step; the tallest buildings have
#: about 160 floors, a city block of them a few thousand
MAX_FLOORS = 100_000

_SUFFIX = {"": 1, "b": 1, "k": 2**10, "kb": 10**3, "kib": 2**10, "m": 2**20, "mb": 10**6,
           "mib": 2**20, "g": 2**30, "gb": 10**9, "gib": 2**30, "t": 2**40, "tb": 10**12,
           "tib": 2**40}


def size(text: str) -> int:
    """Bytes of ``'512MiB'``, ``'4 GiB'``, ``'1e9'``."""
    match = re.fullmatch(r"\s*([0-9.eE+]+)\s*([A-Za-z]*)\s*", str(text))
    if not match or match.group(2).lower() not in _SUFFIX:
        raise ValueError(f"{text!r} is not a size (bytes, or a number with KiB, MiB, GiB, TiB)")
    try:
        value = float(match.group(1)) * _SUFFIX[match.group(2).lower()]
    except ValueError:
        raise ValueError(f"{text!r} is not a size (bytes, or a number with KiB, MiB, GiB, "
                         "TiB)") from None
    if not (math.isfinite(value) and 0 < value <= 2**60):
        raise ValueError(f"{text!r} is not a size a machine has (bytes, at most 1 EiB)")
    return int(value)


def physical_memory() -> int:
    try:
        return os.sysconf("SC_PAGE_SIZE") * os.sysconf("SC_PHYS_PAGES")
    except (ValueError, OSError, AttributeError):
        return 8 * 2**30


def memory_limit() -> int:
    """Bytes a run may use: ``PFRAME_MEMORY_LIMIT``, else 80 % of the physical memory."""
    given = os.environ.get("PFRAME_MEMORY_LIMIT")
    if given:
        from pframe.errors import InputError

        try:
            return size(given)
        except ValueError as exc:
            raise InputError(f"PFRAME_MEMORY_LIMIT: {exc}") from None
    return int(0.8 * physical_memory())


def human(count: float) -> str:
    """``1.5 GiB`` for a byte count."""
    for unit in ("bytes", "KiB", "MiB", "GiB", "TiB", "PiB", "EiB"):
        if abs(count) < 1024 or unit == "EiB":
            return f"{count:.0f} {unit}" if unit == "bytes" else f"{count:.3g} {unit}"
        count /= 1024
    return f"{count:.3g} EiB"


def duration(seconds: float) -> str:
    if seconds < 120:
        return f"{seconds:.3g} s"
    if seconds < 7200:
        return f"{seconds / 60:.3g} min"
    if seconds < 2 * 86400:
        return f"{seconds / 3600:.3g} h"
    if seconds < 2 * 365 * 86400:
        return f"{seconds / 86400:.3g} days"
    return f"{seconds / (365 * 86400):.3g} years"


#: what reduces each part of a run's memory (and its file, and its time)
_FEWER_STEPS = ("check the units of analysis.duration and analysis.dt (seconds), or use a "
                "shorter duration or a larger dt")
_LESS_RECORDED = ("record histories every k-th step (every: k), fewer quantities, or envelopes "
                  "only (kind: envelope)")


def check_steps(steps: float, dt: float, duration_: float) -> str | None:
    """Why ``duration_ / dt`` steps cannot run (None if they can): too many steps, or ground
    motion arrays larger than the memory limit. Called before the time axis is built."""
    limit = memory_limit()
    ground = _GROUND_COPIES * 8.0 * (steps + 1)
    if steps <= MAX_STEPS and ground + _BASE_BYTES <= limit:
        return None
    return (f"duration {duration_:g} s / dt {dt:g} s is {steps:.4g} steps: "
            + (f"more than the {MAX_STEPS:.0e} steps pframe runs" if steps > MAX_STEPS else
               f"their ground-motion arrays alone need {human(ground)}, more than the "
               f"{human(limit)} this machine allows")
            + f" (at about {duration(steps * _STEP_SECONDS)} of computing); "
            f"{_FEWER_STEPS}")


def max_floors() -> int:
    """Floors, storeys and contacts a scene may have: ``PFRAME_MAX_FLOORS`` (the opt-in to a
    larger scene), else :data:`MAX_FLOORS`."""
    given = os.environ.get("PFRAME_MAX_FLOORS")
    if not given:
        return MAX_FLOORS
    try:
        value = float(given.replace("_", "").replace(",", ""))
    except ValueError:
        value = math.nan
    if not (1 <= value <= 1e12) or value != int(value):
        from pframe.errors import InputError

        raise InputError(f"PFRAME_MAX_FLOORS: {given!r} is not a whole number of floors "
                         "between 1 and 1e12 (for example 2000000)")
    return int(value)


def check_floors(floors: int, elements: int | None = None, steps: float | None = None
                 ) -> str | None:
    """Why a scene of ``floors`` floors (``elements`` floors, storeys and contacts in all, run
    for ``steps`` steps) cannot be resolved on this machine, or needs the opt-in
    ``PFRAME_MAX_FLOORS`` (None if it can): called before the floors are built, so the answer
    comes at once."""
    elements = floors if elements is None else elements
    limit = memory_limit()
    per_element = 2 * _OBJECT_BYTES + 8 * (_ARRAYS_PER_DOF + _BAND + 1)
    need = _BASE_BYTES + elements * per_element
    if need > limit:
        return (f"{floors:,} floors would need about {human(need)} of memory to set up, more "
                f"than the {human(limit)} this machine allows; use fewer floors")
    allowed = max_floors()
    if elements <= allowed:
        return None
    run = "" if steps is None else (
        f", and the {steps:,.0f} steps about "
        f"{duration(steps * (_STEP_SECONDS + _ELEMENT_SECONDS * elements))}")
    return (f"{floors:,} floors ({elements:,} floors, storeys and contacts in all): setting "
            f"the scene up would take about {duration(elements * _SETUP_SECONDS)} and "
            f"{human(need)} of memory before the first step{run}; that is more than the "
            f"{allowed:,} pframe sets up unasked (an extra zero typed is the usual cause). Use "
            f"fewer floors or contacts, or set PFRAME_MAX_FLOORS={elements} to run it")


# eq=False: estimates are read, never compared or hashed; each generated function is compiled
# at every start
@dataclass(frozen=True, eq=False)
class Estimate:
    """What a run needs: memory (bytes, at the peak), result file (bytes), time (s)."""

    steps: int
    dofs: int
    elements: int  # storeys + contacts
    variants: int
    batch: int  # variants run at once (one chunk of a sweep)
    memory: int
    file: int
    seconds: float
    streaming: bool
    #: bytes of memory by part: the histories held, the ground motion (its step count), the
    #: scene's arrays and objects, the per-variant responses of a sweep
    parts: tuple = ()

    def describe(self) -> str:
        what = (f"{self.steps:,} steps of {self.dofs:,} floors and {self.elements:,} storeys "
                "and contacts" + (f", {self.variants:,} variants" if self.variants > 1 else ""))
        return (f"{what}: about {human(self.memory)} of memory, a {human(self.file)} result "
                f"file and {duration(self.seconds)} of computing")

    def cause(self, limit: int) -> str:
        """What to reduce so that the memory fits ``limit``: the histories recorded if the
        run fits without them, else the largest of the other parts. In words, with how."""
        parts = dict(self.parts)
        held = parts.pop("histories", 0)
        sweep = self.variants > 1
        if self.memory - held <= limit and held:
            return (f"the histories recorded need {human(held)} of it"
                    + (f" ({self.batch:,} variants of a chunk at once)" if sweep else "")
                    + f": {_LESS_RECORDED}" + (", or a smaller chunk" if sweep else ""))
        largest = max(parts, key=parts.get) if parts else "ground"
        if largest == "ground":
            return (f"its {self.steps:,} time steps need {human(parts[largest])} for the ground "
                    f"motion alone" + (f" ({self.batch:,} variants at once)" if sweep else "")
                    + f": {_FEWER_STEPS}" + (", or a smaller chunk" if sweep else ""))
        if largest == "scene":
            return (f"its {self.dofs:,} floors and {self.elements:,} storeys and contacts need "
                    f"{human(parts[largest])}" + (" per chunk" if sweep else "")
                    + ": use fewer floors or contacts" + (", or a smaller chunk" if sweep else ""))
        return (f"the responses of its {self.variants:,} variants need "
                f"{human(parts[largest])}: use fewer values per axis, or split the study")

    def file_cause(self) -> str:
        """What makes the result file large, and how to make it smaller."""
        if dict(self.parts).get("histories", 0):
            return (f"the histories of its {self.steps:,} steps"
                    + (f" and {self.variants:,} variants" if self.variants > 1 else "")
                    + f": {_LESS_RECORDED}, or fewer steps ({_FEWER_STEPS})")
        return f"the responses of its {self.variants:,} variants: fewer variants"

    def time_cause(self) -> str:
        return (f"{self.steps:,} steps of {self.dofs + self.elements:,} floors, storeys and "
                "contacts" + (f" for {self.variants:,} variants" if self.variants > 1 else "")
                + f": {_FEWER_STEPS}" + (", or fewer variants" if self.variants > 1 else ""))


def _widths(dofs: int, stories: int, contacts: int, links: int = 0, points: int = 0) -> dict:
    return {"node": dofs, "story": stories, "contact": contacts, None: 1, "link": links,
            "foundation": 2,  # at most a pair's (docs/soil.md): small either way
            "point": 2 * points}


def history_bytes(recorders, steps: int, dofs: int, stories: int, contacts: int,
                  links: int = 0, points: int = 0) -> int:
    """Bytes of the histories of one run, at their full length (``dofs``: the values of a
    node quantity per step: a node's 1, or 3 in plan; ``points``: named plan points)."""
    from pframe.quantities import QUANTITIES

    widths = _widths(dofs, stories, contacts, links, points)
    total = 0
    for rec in recorders:
        if rec.kind != "history":
            continue
        rows = steps // rec.every + 1
        for q in dict.fromkeys(rec.quantities):
            kind = QUANTITIES[q][0]
            if (kind == "contact" and not contacts) or (kind == "link" and not links) or (
                    kind == "point" and not points):
                continue
            total += 8 * rows * (widths[kind] + 1)  # the values and their time coordinate
    return total


def estimate(steps: int, dofs: int, stories: int, contacts: int, recorders, *,
             streaming: bool = True, variants: int = 1, batch: int = 1,
             threads: int | None = None, links: int = 0, points: int = 0) -> Estimate:
    """The resources of ``variants`` runs of one scene, ``batch`` of them at once."""
    threads = max(1, min(batch, threads or os.cpu_count() or 1))
    elements = stories + contacts + links
    histories = history_bytes(recorders, steps, dofs, stories, contacts, links, points)
    if streaming:
        held = min(histories, _STREAM_COPIES * STREAM_BYTES)
    else:
        held = 2 * batch * histories  # the buffers, and the chunk's copy for the file
    kernel = 8 * (batch * (_ARRAYS_PER_DOF * dofs + _ARRAYS_PER_ELEMENT * elements)
                  + threads * dofs * (_BAND + 1))
    ground = _GROUND_COPIES * 8 * batch * (steps + 1)
    objects = _OBJECT_BYTES * (dofs + elements) * (2 if batch > 1 else 1)
    small = 64 * variants * (dofs + elements + 16)  # per-variant responses of a sweep
    memory = _BASE_BYTES + held + kernel + ground + objects + small
    file = (histories * variants + small + 64 * (dofs + elements) + 2**16)
    seconds = variants * steps * (_STEP_SECONDS + _ELEMENT_SECONDS * (dofs + elements)) / threads
    parts = (("histories", int(held)), ("ground", int(ground)),
             ("scene", int(kernel + objects)), ("responses", int(small)))
    return Estimate(int(steps), int(dofs), int(elements), int(variants), int(batch),
                    int(memory), int(file), float(seconds), streaming, parts)


def check(est: Estimate, where: str, *, free_disk: int | None = None) -> list[str]:
    """Raise :class:`InputError` when the run cannot fit (memory, steps, variants) and
    :class:`EnvironmentFailure` when its file cannot fit on the disk (``free_disk``); return
    warnings for a run that fits but is very large."""
    from pframe.errors import EnvironmentFailure, InputError, option

    limit = memory_limit()
    if est.steps > MAX_STEPS:
        raise InputError(f"{where}: {est.describe()}; pframe runs at most {MAX_STEPS:.0e} steps: "
                         f"{_FEWER_STEPS}")
    if est.variants > MAX_VARIANTS:
        raise InputError(f"{where}: {est.describe()}; a sweep has at most {MAX_VARIANTS:,} "
                         "variants: use fewer values per axis, or split the study")
    if est.memory > limit:
        source = ("PFRAME_MEMORY_LIMIT" if os.environ.get("PFRAME_MEMORY_LIMIT")
                  else "80 % of this machine's memory")
        raise InputError(f"{where}: {est.describe()}; that is more memory than the "
                         f"{human(limit)} allowed ({source}); {est.cause(limit)}")
    if free_disk is not None and est.file > free_disk:
        raise EnvironmentFailure(
            f"{where}: {est.describe()}; the result file would not fit in the "
            f"{human(free_disk)} free on its disk. Free space or write elsewhere "
            f"({option('output')}); the file holds {est.file_cause()}")
    warnings = []
    if est.seconds > WARN_SECONDS or est.file > WARN_FILE_BYTES:
        why = (f"its file holds {est.file_cause()}" if est.file > WARN_FILE_BYTES
               and est.seconds <= WARN_SECONDS else f"its time is {est.time_cause()}")
        warnings.append(f"a large run: {est.describe()}; Ctrl-C stops it (nothing is "
                        f"written); {why}")
    return warnings


def of_expanded(expanded, *, streaming: bool = True, variants: int = 1, batch: int = 1,
                recorders=None) -> Estimate:
    """:func:`estimate` for a resolved scene (``pframe.model.expand.Expanded``)."""
    nodes = len(expanded.node_names)
    planar = getattr(expanded, "dofs", None) is None
    return estimate(expanded.steps, nodes if planar else 3 * nodes, len(expanded.stories),
                    len(expanded.contacts),
                    expanded.recorders if recorders is None else recorders,
                    streaming=streaming, variants=variants, batch=batch,
                    links=len(getattr(expanded, "links", ())),
                    points=len(getattr(expanded, "point_names", ())))


def product(counts) -> int:
    out = 1
    for c in counts:
        out *= int(c)
    return out


def steps_of(duration_: float, dt: float) -> float:
    """``duration / dt`` as a float (inf when it overflows), before any rounding to int."""
    try:
        return duration_ / dt
    except (OverflowError, ZeroDivisionError):
        return math.inf
