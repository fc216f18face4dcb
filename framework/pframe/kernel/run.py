"""Running a plan through its kernel, chunk by chunk."""

from __future__ import annotations

import os
import time
from concurrent.futures import ThreadPoolExecutor
from dataclasses import dataclass, field

import numpy as np

from pframe.kernel.codegen import (
    CONTACT,
    NOT_CONVERGED,
    NOT_DEFINITE,
    NOT_FINITE,
    NOT_STABLE,
    STORY,
    Structure,
    argument_names,
)
from pframe.quantities import QUANTITIES

_WIDTH = {q: {"node": "n", "story": "s", "contact": "c", None: None}[dim]
          for q, (dim, _, _) in QUANTITIES.items()}


#: kernel arguments without a batch axis (topology shared by all variants)
_SHARED = {"story_dofs", "dmode", "contact_dofs"}

#: a step whose Newton iteration fails is retried in up to 2^MAX_SPLIT sub-steps
MAX_SPLIT = 10


@dataclass
class Result:
    """What a run produced, batch axis first. Node columns are in DOF order."""

    plan: object
    history: dict = field(default_factory=dict)  # quantity -> (B, rows, width)
    envelope: dict = field(default_factory=dict)  # quantity -> (B, width)
    impacts: np.ndarray = None  # (B, c)
    energy: np.ndarray = None  # (B, 8) input, kinetic, damping, story, contact, kinetic0,
    # |input| accumulated, initial mechanical energy
    status: np.ndarray = None  # (B, 4) code, state index, element kind, element index
    iterations: np.ndarray = None  # (B,) Newton solves
    substeps: np.ndarray = None  # (B,) steps that had to be split into sub-steps
    solve_seconds: float = 0.0
    compile_seconds: float = 0.0

    def states_done(self, b: int = 0) -> int:
        """Number of committed states (t = 0 included)."""
        return int(self.status[b, 1]) if self.status[b, 0] else self.plan.steps + 1

    def completed(self, b: int = 0) -> bool:
        return self.status[b, 0] == 0

    def energy_error(self, b: int = 0) -> float:
        """|W_input - (dE_kinetic + W_damping + W_storeys + W_contacts)| relative to the
        largest energy term of the run."""
        w_in, kin, damp, story, contact, kin0 = self.energy[b, :6]
        scale = max(abs(w_in), kin + kin0 + abs(damp) + abs(story) + abs(contact), 1e-300)
        return abs(w_in - (kin - kin0 + damp + story + contact)) / scale

    def describe_failure(self, b: int = 0) -> str:
        code, state, kind, index = (int(x) for x in self.status[b])
        if code == 0:
            return "completed"
        plan = self.plan
        t = state * float(plan.dt[b])
        if kind == STORY:
            where = f"storey {plan.story_names[index]}"
        elif kind == CONTACT:
            where = f"contact {plan.contact_names[index]}"
        else:
            dof_names = {int(d): nm for nm, d in zip(plan.node_names, plan.node_dof)}
            where = f"node {dof_names.get(index, index)}"
        why = {NOT_CONVERGED: f"Newton did not converge in {plan.max_iterations} iterations "
                              f"(nor in 2^{MAX_SPLIT} sub-steps)",
               NOT_FINITE: "a force became NaN or infinite",
               NOT_DEFINITE: "the effective stiffness is not positive definite",
               NOT_STABLE: "the run diverged (the numerics created more energy than the "
                           "excitation put in)"}[code]
        return f"{why} at t = {t:.6g} s (step {state}) at {where}"


def _arrays(plan, structure: Structure):
    B, n = plan.mass.shape
    s, c = len(plan.story_names), len(plan.contact_names)
    sizes = {"n": n, "s": s, "c": c}
    a = {
        "dt": plan.dt, "gamma": plan.integrator.gamma, "beta": plan.integrator.beta,
        "alpha_m": plan.integrator.alpha_m, "alpha_f": plan.integrator.alpha_f,
        "tol": plan.tolerance,
        "atol": plan.absolute_tolerance, "max_iter": plan.max_iterations, "bw": plan.bandwidth,
        "mass": plan.mass, "mdamp": plan.mass_damping, "story_dofs": plan.story_dofs,
        "k0": plan.story_k0, "sbeta": plan.story_beta, "dmode": plan.story_damping_stiffness,
        "contact_dofs": plan.contact_dofs, "gap": plan.contact_gap,
        "ag": plan.ground_acceleration,
        "U": plan.initial_displacement.copy(), "V": plan.initial_velocity.copy(),
        "A": np.zeros((B, n)), "drift_c": np.zeros((B, s)), "sforce_c": np.zeros((B, s)),
        "sdamp_c": np.zeros((B, s)), "stan_c": plan.story_k0.copy(),
        "cforce_c": np.zeros((B, c)), "cpen_c": np.full((B, c), -1.0),
        "impacts": np.zeros((B, c), dtype=np.int64), "energy": np.zeros((B, 8)),
        "status": np.zeros((B, 4), dtype=np.int64), "iterations": np.zeros(B, dtype=np.int64),
        "substeps": np.zeros(B, dtype=np.int64), "max_split": MAX_SPLIT,
        "cd_parts": plan.cd_parts if plan.cd_parts is not None else np.ones(B, dtype=np.int64),
        "event_parts": (plan.event_parts if plan.event_parts is not None
                        else np.ones(B, dtype=np.int64)),
    }
    for prefix, groups in (("s", plan.story_groups), ("c", plan.contact_groups)):
        for g, group in enumerate(groups):
            a[f"{prefix}p{g}"] = np.ascontiguousarray(group.params)
            a[f"{prefix}x{g}"] = group.index
            a[f"{prefix}c{g}"] = group.state.copy()
            a[f"{prefix}t{g}"] = group.state.copy()
    for q, every in plan.history:
        width = _WIDTH[q]
        rows = plan.steps // every + 1
        shape = (B, rows) if width is None else (B, rows, sizes[width])
        a[f"h_{q}"] = np.full(shape, np.nan)
        a[f"every_{q}"] = every
    for q in structure.envelope:
        width = _WIDTH[q]
        a[f"e_{q}"] = np.zeros(B) if width is None else np.zeros((B, sizes[width]))
    return a


def _pieces(batch: int, threads: int | None) -> list[tuple[int, int]]:
    """Contiguous slices of the batch for the threads: several per thread, for balance."""
    threads = threads or os.cpu_count() or 1
    count = min(batch, 1 if threads == 1 else 4 * threads)
    edges = np.linspace(0, batch, count + 1).round().astype(int)
    return [(int(a), int(b)) for a, b in zip(edges[:-1], edges[1:]) if b > a]


def simulate(plan, progress=None, chunk_seconds: float = 0.25, threads: int | None = None) -> Result:
    """Integrate every member of the plan's batch over all its steps.

    ``progress(done, total)`` is called between chunks when given; without it the whole run
    is one kernel call after the first state (which also compiles or loads the kernel).
    A batch runs in ``threads`` threads (default: one per CPU).
    """
    from pframe.kernel.build import diagnose, kernel_for

    structure = Structure.of(plan)
    kernel = kernel_for(structure)
    arrays = _arrays(plan, structure)
    names = argument_names(structure)
    batched = {name for name in names
               if isinstance(arrays.get(name), np.ndarray) and arrays[name].ndim >= 1
               and name not in _SHARED and not name.startswith(("sx", "cx"))}

    pieces = _pieces(plan.batch, threads)
    pool = ThreadPoolExecutor(len(pieces)) if len(pieces) > 1 else None

    def call(begin, end):
        arrays["begin"], arrays["end"] = begin, end
        if pool is None:
            kernel(*[arrays[name] for name in names])
            return
        # The kernel releases the GIL (nogil): contiguous slices of the batch run in threads,
        # each variant on its own, so one slow variant never holds up the others' iterations.
        futures = [pool.submit(kernel, *[arrays[name][lo:hi] if name in batched else arrays[name]
                                         for name in names]) for lo, hi in pieces]
        for future in futures:
            future.result()

    total = plan.steps + 1
    start = time.perf_counter()
    try:
        call(0, 1)  # state t = 0; compiles or loads the kernel
    except Exception as exc:
        if type(exc).__module__.startswith("numba"):
            raise diagnose(structure, exc) from None
        raise
    compile_seconds = time.perf_counter() - start
    solve = 0.0
    done = 1
    size = total - 1 if progress is None else min(total - 1, 500)
    while done < total:
        end = min(total, done + size)
        tick = time.perf_counter()
        call(done, end)
        elapsed = time.perf_counter() - tick
        solve += elapsed
        if progress is not None:
            progress(end, total)
            size = max(1, int((end - done) * chunk_seconds / max(elapsed, 1e-6)))
        done = end
        if np.all(arrays["status"][:, 0] != 0):
            break
    if pool is not None:
        pool.shutdown()
    return Result(
        plan=plan,
        history={q: arrays[f"h_{q}"] for q, _ in plan.history},
        envelope={q: arrays[f"e_{q}"] for q in structure.envelope},
        impacts=arrays["impacts"],
        energy=arrays["energy"],
        status=arrays["status"],
        iterations=arrays["iterations"],
        substeps=arrays["substeps"],
        solve_seconds=solve,
        compile_seconds=compile_seconds,
    )
