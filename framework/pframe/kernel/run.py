"""Running a plan through the compiled kernel, chunk by chunk, in threads over the batch.

The plan's arrays are grouped into the kernel's named tuples (:mod:`pframe.kernel.state`),
whose data pointers fill the C kernel's structs (:mod:`pframe.kernel.ckernel`); the kernel
(``pframe_run`` in ``c/loop.c``) is called over consecutive ranges of steps, which gives the
same bits as one call, so that a progress bar can be updated and histories can be handed to a
``sink`` (a file being written) chunk by chunk instead of held whole in memory. The sink takes
a call's rows while the kernel runs the next call.

The kernel always runs in worker threads while the main thread waits, free to receive
Ctrl-C, SIGTERM and SIGHUP; it then sets the model's ``stop`` flag, which the kernel reads at
every evaluation of the residual (``check_finite`` in ``c/assembly.c``), so a run stops within
one Newton iteration or sub-step whatever a step or a call holds (10^9 Newton iterations
allowed, 10^5 sub-steps a step, a large batch), and waits for the calls to return before the
stop goes on.
"""

from __future__ import annotations

import functools
import os
import time
from concurrent.futures import FIRST_EXCEPTION, ThreadPoolExecutor, wait
from dataclasses import dataclass, field

import numpy as np

from pframe.integrators.tableau import RELATIONS
from pframe.kernel.state import (
    ENERGY_TERMS,
    RECORDABLE,
    RECORDABLE_SLOT,
    STAGE_WIDTH,
    Counter,
    Energy,
    Kind,
    Model,
    Recordable,
    Recording,
    Relation,
    Run,
    Saved,
    Scalar,
    Scheme,
    Settings,
    StageColumn,
    StagePoint,
    State,
    Status,
    StatusColumn,
    Value,
    Work,
)
from pframe.outputs import check_stop
from pframe.quantities import QUANTITIES

#: a step whose Newton iteration fails is retried in up to 2^MAX_SPLIT sub-steps
MAX_SPLIT = 10
#: refactor the effective stiffness before every solve (a test shows that reusing the
#: factorisation changes no bit)
ALWAYS_REFACTOR = False
#: take every implicit step of a nonlinear scene through the retry path, in sub-steps (a test
#: shows that each path runs the scene's integrator)
FORCE_SPLIT = False
#: the history rows held while streaming, in bytes: the rows of the call the sink takes and
#: of the call the kernel fills, each at most a third of it
STREAM_BYTES = 32 * 2**20
_HELD_CALLS = 3

_SIZE = {"node": 0, "story": 1, "contact": 2, None: 3, "link": 4, "foundation": 5,
         "point": 6}


# eq=False: it holds numpy arrays (== elementwise), so a generated __eq__ could only raise
# (and would be compiled at every start); results compare by identity
@dataclass(eq=False)
class Result:
    """What a run produced, batch axis first. Node columns are in DOF order."""

    plan: object
    history: dict = field(default_factory=dict)  # quantity -> (B, rows, width); rows streamed
    # to a sink are not held here
    envelope: dict = field(default_factory=dict)  # quantity -> (B, width)
    impacts: np.ndarray = None  # (B, c)
    energy: np.ndarray = None  # (B, len(Energy)), see pframe.kernel.state
    status: np.ndarray = None  # (B, len(StatusColumn)): code, state index, element kind and index
    counters: np.ndarray = None  # (B, len(Counter)): solves, factorisations, evaluations,
    # split steps, gathered values
    law_calls: dict = field(default_factory=dict)  # law name -> (B,) evaluations of that law
    closing: np.ndarray = None  # (B, P) max over the steps of u_i - u_j of each pair asked
    solve_seconds: float = 0.0
    compile_seconds: float = 0.0  # the first call (state t = 0): loading the kernel, and
    # compiling plug-in laws the first time

    @property
    def iterations(self) -> np.ndarray:
        """(B,) linear solves (Newton iterations that solved; central-difference steps)."""
        return self.counters[:, Counter.SOLVES]

    @property
    def substeps(self) -> np.ndarray:
        """(B,) steps that had to be split into sub-steps."""
        return self.counters[:, Counter.SPLIT_STEPS]

    def counter(self, name: str, b: int = 0) -> int:
        """One of :data:`pframe.kernel.state.COUNTER_NAMES` for member ``b``."""
        return int(self.counters[b, Counter[name.upper()]])

    def states_done(self, b: int = 0) -> int:
        """Number of committed states (t = 0 included)."""
        if self.status[b, StatusColumn.CODE] == Status.OK:
            return self.plan.steps + 1
        return int(self.status[b, StatusColumn.STEP])

    def completed(self, b: int = 0) -> bool:
        return self.status[b, StatusColumn.CODE] == Status.OK

    def energy_scale(self, b: int = 0) -> float:
        """The largest energy term of the run (J): what the balance is measured against."""
        e = self.energy[b]
        return max(abs(e[Energy.INPUT]), e[Energy.KINETIC] + e[Energy.KINETIC_0]
                   + abs(e[Energy.DAMPING]) + abs(e[Energy.STOREYS]) + abs(e[Energy.CONTACTS])
                   + abs(e[Energy.LINKS]) + abs(e[Energy.ALGORITHMIC]), 1e-300)

    def energy_error(self, b: int = 0) -> float:
        """|W_input - (dE_kinetic + W_damping + W_storeys + W_contacts + W_links +
        D_algorithmic)|
        relative to the largest energy term of the run: zero but for round-off, Newton's
        tolerance and an inconsistent step (kernel/c/energy.c)."""
        e = self.energy[b]
        balance = e[Energy.INPUT] - (e[Energy.KINETIC] - e[Energy.KINETIC_0] + e[Energy.DAMPING]
                                     + e[Energy.STOREYS] + e[Energy.CONTACTS] + e[Energy.LINKS]
                                     + e[Energy.ALGORITHMIC])
        return abs(balance) / self.energy_scale(b)

    def energy_terms(self, b: int = 0) -> dict[str, float]:
        """The balance's terms of member ``b`` by name (J), in the order of the balance."""
        return {name: float(self.energy[b, slot]) for name, slot in ENERGY_TERMS.items()}

    def column_shear(self, b: int = 0) -> np.ndarray:
        """(c,) the peak local shear each floor-to-column contact put into the struck column
        (N; NaN for a floor-to-floor contact): the larger of the column's two segments,
        max(psi, 1 - psi) times the peak contact force (a fixed-fixed column swaying, loaded
        at the point: its lower floor takes (1 - psi) F, its upper psi F)."""
        plan = self.plan
        out = np.full(len(plan.contact_names), np.nan)
        if plan.contact_share is None or not len(plan.contact_names):
            return out
        if "contact_force" in self.envelope:
            peak = self.envelope["contact_force"][b]
        elif "contact_force" in self.history:
            peak = np.nanmax(np.abs(self.history["contact_force"][b]), axis=0)
        else:
            return out
        share = plan.contact_share[b]
        column = np.any(share != 1.0, axis=1)
        psi = np.where(share[:, 0] != 1.0, share[:, 0], share[:, 1])
        out[column] = (np.maximum(psi, 1.0 - psi) * peak)[column]
        return out

    def algorithmic_dissipation(self, b: int = 0) -> float:
        """The energy the integrator's own relations removed (negative: created), relative to
        the largest energy term of the run."""
        return float(self.energy[b, Energy.ALGORITHMIC]) / self.energy_scale(b)

    def describe_failure(self, b: int = 0) -> str:
        code, state, kind, index = (int(self.status[b, c]) for c in StatusColumn)
        if code == Status.OK:
            return "completed"
        plan = self.plan
        t = state * float(plan.dt[b])
        if kind == Kind.STORY and index >= len(plan.story_names):
            where = f"link {plan.link_names[index - len(plan.story_names)]}"
        elif kind == Kind.STORY:
            where = f"storey {plan.story_names[index]}"
        elif kind == Kind.CONTACT:
            where = f"contact {plan.contact_names[index]}"
        else:
            dof_names = {int(d): nm for nm, d in zip(plan.node_names, plan.node_dof)}
            where = f"node {dof_names.get(index, index)}"
        retried = (f"nor in 2^{MAX_SPLIT} sub-steps" if plan.integrator.retry
                   else "the integrator does not retry a failed step in sub-steps")
        why = {Status.NOT_CONVERGED: f"Newton did not converge in {plan.max_iterations} iterations "
                              f"({retried})",
               Status.NOT_FINITE: "a force became NaN or infinite",
               Status.NOT_DEFINITE: "the effective stiffness is not positive definite",
               Status.NOT_STABLE: "the run diverged (the numerics created more energy than the "
                           "excitation put in)"}[code]
        if code == Status.NOT_DEFINITE and kind != Kind.NODE:  # the element the kernel found
            why = ("the effective stiffness is not positive definite, from a negative tangent "
                   "stiffness")
        if (code == Status.NOT_STABLE and plan.story_kg is not None
                and np.any(plan.story_kg[b])):
            why = ("the run diverged: the kinetic energy outgrew what the excitation put in. "
                   "With P-delta this is most likely a storey collapsing under gravity (its "
                   "geometric stiffness releasing the weight's potential energy), not the "
                   "numerics; the run stops there")
        return f"{why} at t = {t:.6g} s (step {state}) at {where}"


def _law_table(groups, count: int, batch: int, ids: dict) -> tuple:
    """Per-element law ids, evaluation order (grouped by law), and the laws' parameters and
    states padded to the widest law: (batch, count, width) arrays."""
    law = np.zeros(count, dtype=np.int64)
    order = np.array([i for g in groups for i in g.index], dtype=np.int64)
    params = np.zeros((batch, count, max([1] + [g.params.shape[2] for g in groups])))
    state = np.zeros((batch, count, max([1] + [g.state.shape[2] for g in groups])))
    for g in groups:
        law[g.index] = ids[g.law]
        params[:, g.index, :g.params.shape[2]] = g.params
        state[:, g.index, :g.state.shape[2]] = g.state
    return law, order, params, state


def _group_model(plan, ids) -> tuple[Model, np.ndarray, np.ndarray]:
    B = plan.batch
    story_law, story_order, story_params, story_state = _law_table(
        plan.story_groups, plan.n_springs, B, ids)
    contact_law, contact_order, contact_params, contact_state = _law_table(
        plan.contact_groups, len(plan.contact_names), B, ids)
    ones = np.ones(B, dtype=np.int64)
    model = Model(
        mass=plan.mass, mass_damping=plan.mass_damping, story_dofs=plan.story_dofs,
        story_order=story_order, story_law=story_law, story_params=story_params,
        story_k0=plan.story_k0, story_beta=plan.story_beta,
        story_damping=plan.story_damping_stiffness,
        story_height=(plan.story_height if plan.story_height is not None
                      else np.full((B, plan.n_springs), np.nan)),
        story_kg=(plan.story_kg if plan.story_kg is not None
                  else np.zeros((B, plan.n_springs))),
        contact_dofs=plan.contact_dofs,
        contact_order=contact_order, contact_law=contact_law, contact_params=contact_params,
        gap=plan.contact_gap, dt=plan.dt,
        ground=(plan.ground_channels if plan.ground_motion is None
                else np.concatenate([plan.ground_channels, plan.ground_motion], axis=1)),
        cd_parts=plan.cd_parts if plan.cd_parts is not None else ones,
        event_parts=plan.event_parts if plan.event_parts is not None else ones,
        stop=np.zeros(1, dtype=np.int64),
        dof_channel=(plan.dof_channel if plan.dof_channel is not None
                     else np.zeros(plan.n_dof, dtype=np.int64)),
        foundation_dofs=(plan.foundation_dofs if plan.foundation_dofs is not None
                         else np.zeros((0, 2), dtype=np.int64)),
        **_grounds("story", plan.story_ground_start, plan.story_ground_channel,
                   plan.story_ground_coef, plan.n_springs, B),
        **_grounds("contact", plan.contact_ground_start, plan.contact_ground_channel,
                   plan.contact_ground_coef, len(plan.contact_names), B),
        **_sides("story", plan.story_sides, plan.n_springs, B),
        **_sides("contact", plan.contact_sides, len(plan.contact_names), B),
        gauge_start=(plan.gauge_start if plan.gauge_start is not None
                     else np.zeros(1, dtype=np.int64)),
        gauge_dof=plan.gauge_dof if plan.gauge_dof is not None else np.zeros(0, dtype=np.int64),
        gauge_coef=plan.gauge_coef if plan.gauge_coef is not None else np.zeros((B, 0)),
        modal_dofs=(plan.modal_dofs if plan.modal_dofs is not None
                    else np.zeros(0, dtype=np.int64)),
        modal_start=(plan.modal_start if plan.modal_start is not None
                     else np.zeros(1, dtype=np.int64)),
        modal_matrix=(plan.modal_matrix if plan.modal_matrix is not None
                      else np.zeros((B, 0))),
    )
    return _normalised(model), story_state, contact_state


def _sides(kind: str, sides, count: int, batch: int) -> dict:
    """The Model's arrays of the sides of a kind of element (none: every element plain)."""
    if sides is None:
        return {f"{kind}_side_start": np.zeros(2 * count + 1, dtype=np.int64),
                f"{kind}_side_dof": np.zeros(0, dtype=np.int64),
                f"{kind}_side_coef": np.zeros((batch, 0))}
    return {f"{kind}_side_start": sides.start, f"{kind}_side_dof": sides.dof,
            f"{kind}_side_coef": sides.coef}


def _grounds(kind: str, start, channel, coef, count: int, batch: int) -> dict:
    """The Model's arrays of the ground terms of a kind of element (docs/supports.md; none:
    every element on one support)."""
    if start is None:
        return {f"{kind}_ground_start": np.zeros(count + 1, dtype=np.int64),
                f"{kind}_ground_channel": np.zeros(0, dtype=np.int64),
                f"{kind}_ground_coef": np.zeros((batch, 0))}
    return {f"{kind}_ground_start": start, f"{kind}_ground_channel": channel,
            f"{kind}_ground_coef": coef}


def _normalised(group):
    """Every array C-contiguous, writable and of the kernel's dtype (float64 or int64), so
    that every scene calls the one compiled kernel."""
    out = []
    for value in group:
        kind = np.int64 if np.asarray(value).dtype.kind in "iub" else np.float64
        array = np.ascontiguousarray(value, dtype=kind)
        if not array.flags.writeable:
            array = array.copy()
        out.append(array)
    return type(group)(*out)


def tableau_rows(tableau) -> np.ndarray:
    """Settings.tableau: one row of STAGE_WIDTH numbers per stage (pframe.kernel.state's
    StageColumn, then the coefficients [Relation, StagePoint, Value])."""
    if len(tableau.stages) > len(StagePoint) - 1:
        raise ValueError(f"the kernel runs at most {len(StagePoint) - 1} stages a step")
    rows = np.zeros((len(tableau.stages), STAGE_WIDTH))
    for stage, (row, cls) in enumerate(zip(rows, tableau.stiffness_classes())):
        row[StageColumn.END] = tableau.stages[stage].end
        row[StageColumn.AT] = tableau.stages[stage].at
        row[StageColumn.STIFFNESS] = cls
        coefficients = row[len(StageColumn):].reshape(len(Relation), len(StagePoint), len(Value))
        for relation, name in zip(Relation, RELATIONS, strict=True):
            for point, values in enumerate(tableau.stages[stage].relation(name)):
                coefficients[relation, point] = values
    return rows


def _settings(plan, laws) -> Settings:
    c = plan.integrator
    return Settings(
        gamma=float(c.gamma), beta=float(c.beta), alpha_m=float(c.alpha_m),
        alpha_f=float(c.alpha_f), scheme=int(Scheme[c.scheme.upper()]),
        theta=float(c.theta), stages=c.stages, tableau=tableau_rows(c.tableau),
        kinetic_weight=float(c.tableau.kinetic_weight), beyond=bool(c.tableau.beyond),
        tolerance=float(plan.tolerance),
        absolute_tolerance=float(plan.absolute_tolerance),
        max_iterations=int(plan.max_iterations), bandwidth=int(plan.bandwidth),
        max_split=int(MAX_SPLIT if c.retry else 0), linear=bool(plan.linear and not c.explicit),
        explicit=bool(c.explicit), events=bool(c.events and plan.contact_names),
        alpha=bool(c.alpha), always_refactor=bool(ALWAYS_REFACTOR),
        force_split=bool(FORCE_SPLIT),
        material_plugins=laws.address(laws.material_table),
        contact_plugins=laws.address(laws.contact_table),
    )


def _state(plan, story_state, contact_state, n_materials: int, n_contact_laws: int) -> State:
    B, n = plan.mass.shape
    s, c = plan.n_springs, len(plan.contact_names)
    return _normalised(State(
        U=plan.initial_displacement.copy(), V=plan.initial_velocity.copy(), A=np.zeros((B, n)),
        drift=np.zeros((B, s)), story_force=np.zeros((B, s)),
        story_damping_force=np.zeros((B, s)), story_tangent=plan.story_k0.copy(),
        story_committed=story_state, story_trial=story_state.copy(),
        contact_force=np.zeros((B, c)), penetration=np.full((B, c), -1.0),
        contact_committed=contact_state, contact_trial=contact_state.copy(),
        impacts=np.zeros((B, c), dtype=np.int64),
        energy=np.zeros((B, len(Energy))),
        status=np.zeros((B, len(StatusColumn)), dtype=np.int64),
        counters=np.zeros((B, len(Counter)), dtype=np.int64),
        material_calls=np.zeros((B, n_materials), dtype=np.int64),
        contact_calls=np.zeros((B, n_contact_laws), dtype=np.int64),
    ))


class _Recorders:
    """The history buffers of each call (or of the whole run) and the envelopes."""

    def __init__(self, plan, sink, closing=None):
        B = plan.batch
        self.plan, self.sink = plan, sink
        self.closing_dofs = np.ascontiguousarray(
            np.zeros((0, 2)) if closing is None else closing, dtype=np.int64).reshape(-1, 2)
        self.closing = np.full((B, len(self.closing_dofs)), -np.inf)
        sizes = (plan.n_dof, len(plan.story_names), len(plan.contact_names), len(plan.channels),
                 len(plan.link_names), len(plan.foundations), 2 * len(plan.point_names))
        self.widths = [sizes[_SIZE[QUANTITIES[q][0]]] for q in RECORDABLE]
        self.every = np.zeros(len(RECORDABLE), dtype=np.int64)
        for q, every in plan.history:
            self.every[RECORDABLE_SLOT[q]] = every
        self.enveloped = np.array([q in plan.envelope for q in RECORDABLE], dtype=np.int64)
        self.envelope = tuple(np.zeros((B, w if on else 0))
                              for w, on in zip(self.widths, self.enveloped))
        if self.enveloped[Recordable.STORY_DRIFT_RATIO] and plan.story_height is not None:
            # a storey without a height has no drift ratio: its peak stays NaN (the kernel's
            # running maximum keeps a NaN it starts from), never 0, which would pass a limit
            ns = len(plan.story_names)
            self.envelope[Recordable.STORY_DRIFT_RATIO][
                np.isnan(plan.story_height[:, :ns])] = np.nan
        self.whole = None if sink is not None else self._buffers(0, plan.steps + 1)

    def _rows(self, q: int, begin: int, end: int) -> tuple[int, int]:
        every = int(self.every[q])
        return -(-begin // every), -(-end // every)

    def _buffers(self, begin: int, end: int):
        # left unfilled: the kernel writes every row of a member that has not stopped, and
        # those of a stopped member are filled with NaN after the call (unwritten)
        B = self.plan.batch
        out = []
        for q, width in enumerate(self.widths):
            if self.every[q]:
                first, stop = self._rows(q, begin, end)
                out.append(np.empty((B, stop - first, width)))
            else:
                out.append(np.zeros((B, 0, 0)))
        return tuple(out)

    def unwritten(self, rec: Recording, begin: int, end: int, status: np.ndarray) -> None:
        """NaN in the history rows that the kernel left unwritten in a call of states [begin,
        end): those of a member that has stopped (``status``, read while no call runs), from
        the state it stopped at (Result.states_done) on. The whole run's buffers are filled
        to their end in the call the member stops in (no later call writes them)."""
        for b in np.flatnonzero(status[:, StatusColumn.CODE] != Status.OK):
            done = int(status[b, StatusColumn.STEP])
            if self.whole is not None and not begin <= done < end:
                continue
            for q, history in enumerate(rec.history):
                if self.every[q]:
                    first = 0 if self.whole is not None else self._rows(q, begin, end)[0]
                    history[b, self._rows(q, max(begin, done), end)[0] - first:] = np.nan

    def max_steps(self) -> int:
        """Steps per call that keep the streamed buffers under STREAM_BYTES (three calls'
        rows are held at once)."""
        if self.sink is None:
            return 1 << 62
        per_step = sum(8.0 * self.plan.batch * w / e
                       for w, e in zip(self.widths, self.every) if e)
        return max(1, int(STREAM_BYTES / _HELD_CALLS / per_step)) if per_step else 1 << 62

    def for_call(self, begin: int, end: int) -> Recording:
        if self.whole is not None:
            history, first = self.whole, np.zeros(len(RECORDABLE), dtype=np.int64)
        else:
            history = self._buffers(begin, end)
            first = np.array([self._rows(q, begin, end)[0] if e else 0
                              for q, e in enumerate(self.every)], dtype=np.int64)
        return Recording(history, self.every, first, self.envelope, self.enveloped,
                         self.closing_dofs, self.closing)

    def deliver(self, rec: Recording, begin: int, done: int) -> None:
        """Hand the rows of states [begin, done) to the sink."""
        if self.sink is None:
            return
        for q, name in enumerate(RECORDABLE):
            if self.every[q]:
                first, stop = self._rows(q, begin, done)
                if stop > first:
                    self.sink(name, first, self._shaped(name, rec.history[q][:, :stop - first]))

    def _shaped(self, name, array):
        # one value a step: a column per channel of the ground motion, one column for one
        return array[..., 0] if QUANTITIES[name][0] is None and array.shape[-1] == 1 else array

    def histories(self) -> dict:
        if self.whole is None:
            return {}
        return {q: self._shaped(q, self.whole[RECORDABLE_SLOT[q]]) for q, _ in self.plan.history}

    def envelopes(self) -> dict:
        return {q: self._shaped(q, self.envelope[RECORDABLE_SLOT[q]]) for q in self.plan.envelope}


def work_arrays(plan, st: State) -> Work:
    """Scratch arrays of one member at a time: its trial state (for Newmark the evaluation
    point is the step end itself), the band, the tangents in its factorisation, and what the
    stages before the last keep (their ends, and the deformations and law states there)."""
    n, s, c = plan.n_dof, plan.n_springs, len(plan.contact_names)
    stages = plan.integrator.stages
    u, v, a = np.zeros(n), np.zeros(n), np.zeros(n)
    if plan.integrator.alpha:
        ue, ve, ae = np.zeros(n), np.zeros(n), np.zeros(n)
    elif plan.integrator.explicit:
        ue, ve, ae = u, v, np.zeros(n)
    else:
        ue, ve, ae = u, v, a
    work = Work(u, v, a, ue, ve, ae, np.zeros(n), np.zeros((n, plan.bandwidth + 1)),
                *(np.zeros(s) for _ in range(4)), np.zeros(c), np.zeros(c), np.zeros(s),
                np.zeros(c), np.zeros(len(Scalar)),
                np.zeros((stages - 1, len(Value), n)), np.zeros(s), np.zeros(c),
                np.zeros(st.story_committed[0].size), np.zeros(st.contact_committed[0].size),
                *(np.zeros(len(plan.channels) * (1 if plan.ground_motion is None else 3))
                  for _ in range(4)))
    return work


def _saved(st: State) -> Saved:
    """Room for one member's committed arrays (what a failed step attempt restores)."""
    return Saved(*[getattr(st, name)[0].copy() for name in Saved._fields])


def _pieces(batch: int, threads: int | None) -> list[tuple[int, int]]:
    """Contiguous slices of the batch for the threads: several per thread, for balance."""
    threads = threads or os.cpu_count() or 1
    count = min(batch, 1 if threads == 1 else 4 * threads)
    edges = np.linspace(0, batch, count + 1).round().astype(int)
    return [(int(a), int(b)) for a, b in zip(edges[:-1], edges[1:]) if b > a]


#: Model fields shared by the batch (topology), which threads do not slice
_SHARED = {"story_dofs", "story_order", "story_law", "story_damping", "contact_dofs",
           "contact_order", "contact_law", "stop", "dof_channel",
           "foundation_dofs", "story_side_start", "story_side_dof", "contact_side_start",
           "contact_side_dof", "gauge_start", "gauge_dof",
           "story_ground_start", "story_ground_channel", "contact_ground_start",
           "contact_ground_channel", "modal_dofs", "modal_start"}


def _slice(group, lo: int, hi: int):
    return type(group)(*[value if name in _SHARED else value[lo:hi]
                         for name, value in zip(group._fields, group)])


def _slice_recording(rec: Recording, lo: int, hi: int) -> Recording:
    return rec._replace(history=tuple(h[lo:hi] for h in rec.history),
                        envelope=tuple(e[lo:hi] for e in rec.envelope),
                        closing=rec.closing[lo:hi])


#: how often the main thread looks for a stop that a destructor swallowed while it waits (s)
POLL_SECONDS = 0.05


def _wait(futures, stop: np.ndarray, meanwhile=None) -> None:
    """Wait for the kernel's calls, with the main thread free for signals (after running
    ``meanwhile()``, the main thread's own work while the calls run). On a stop (Ctrl-C,
    SIGTERM: raised here by the signal's handler, or found by check_stop) or an error in one
    call or in ``meanwhile``, the kernel is asked to stop (``stop[0] = 1``), which every call
    sees within one evaluation of the residual, and the calls are awaited before the
    exception goes on: no thread writes into the run's arrays after simulate has left."""
    try:
        if meanwhile is not None:
            meanwhile()
        pending = set(futures)
        while pending:
            done, pending = wait(pending, timeout=POLL_SECONDS, return_when=FIRST_EXCEPTION)
            for future in done:
                future.result()  # a call's error
            check_stop()
    except BaseException:
        stop[0] = 1
        while True:
            try:
                wait(futures)
                break
            except BaseException:  # another signal while the calls return: the first one wins
                continue
        raise


def _between(recorders: _Recorders, rec: Recording, begin: int, end: int) -> None:
    """The main thread's work while the kernel runs a call: the rows of states [begin,
    end) of the call before to the sink."""
    recorders.deliver(rec, begin, end)


def simulate(plan, progress=None, chunk_seconds: float = 0.25, threads: int | None = None,
             sink=None, announce=None, closing=None) -> Result:
    """Integrate every member of the plan's batch over all its steps.

    ``progress(done, total)`` is called between chunks when given. ``sink(quantity,
    first_row, rows)``, when given, receives the history rows (batch axis first) as they are
    computed, and the result then holds no histories: memory stays bounded whatever the
    duration. ``announce(message)`` is called before plug-in laws are compiled (once per set
    of plug-in laws; built-in laws are in the compiled kernel). A batch runs in ``threads``
    threads (default: one per CPU). ``closing`` ((P, 2) DOF indices): the result's
    ``closing`` (B, P) holds each pair's running maximum of u_i - u_j over the steps (a
    gap's closing, pframe.gap.runs.GapSink's, with no history streamed for it).
    """
    from pframe.kernel import ckernel
    from pframe.kernel.plugins import law_ids

    start = time.perf_counter()
    laws = law_ids(plan, announce)
    ckernel.library()  # loaded and checked once per process
    ids = laws.ids
    model, story_state, contact_state = _group_model(plan, ids)
    stop = model.stop  # shared by every piece of the batch (_SHARED)
    settings = _settings(plan, laws)
    st = _state(plan, story_state, contact_state, laws.materials, laws.contact_laws)
    recorders = _Recorders(plan, sink, closing)

    pieces = _pieces(plan.batch, threads)
    # always a pool, even of one thread: the main thread waits and receives the signals
    pool = ThreadPoolExecutor(len(pieces))
    scratch = [(work_arrays(plan, st), _saved(st)) for _ in pieces]
    c_settings = ckernel.arrays(ckernel.Settings, settings)
    # the structs of each piece of the batch: the same arrays for every call
    structs = []
    for (lo, hi), (work, saved) in zip(pieces, scratch):
        sliced = _slice(model, lo, hi)
        sizes = dict(batch=hi - lo, dofs=plan.n_dof, stories=plan.n_springs,
                     links=len(plan.link_names) + 2 * len(plan.foundations),  # with the soil
                     contacts=len(plan.contact_names), story_width=model.story_params.shape[2],
                     story_states=st.story_committed.shape[2],
                     contact_width=model.contact_params.shape[2],
                     contact_states=st.contact_committed.shape[2],
                     ground_width=model.ground.shape[2], channels=len(plan.channels),
                     ground_series=model.ground.shape[1],
                     story_ground_terms=model.story_ground_channel.shape[0],
                     contact_ground_terms=model.contact_ground_channel.shape[0],
                     materials=laws.materials,
                     contact_laws=laws.contact_laws, foundations=len(plan.foundations),
                     story_terms=model.story_side_dof.shape[0],
                     contact_terms=model.contact_side_dof.shape[0],
                     points=len(plan.point_names), gauge_terms=model.gauge_dof.shape[0],
                     modal_blocks=len(model.modal_start) - 1,
                     modal_width=model.modal_matrix.shape[1])
        structs.append((ckernel.arrays(ckernel.Model, sliced, **sizes),
                        ckernel.arrays(ckernel.State, _slice(st, lo, hi)),
                        ckernel.arrays(ckernel.Work, work), ckernel.arrays(ckernel.Saved, saved)))

    def kernel(piece, rec, begin, end):
        c_model, c_state, c_work, c_saved = structs[piece]
        code = ckernel.run(c_model, c_settings, c_state, ckernel.recording(rec), c_work,
                           c_saved, begin, end)
        if code == Run.ZERO_DIVISION:
            raise ZeroDivisionError("float division by zero")
        # RUN_STOPPED: the main thread asked for it and is raising the stop (see _wait)

    def call(begin, end, meanwhile=None):
        try:
            return _call(begin, end, meanwhile)
        except (ZeroDivisionError, OverflowError, FloatingPointError) as exc:
            from pframe.errors import InputError

            raise InputError(
                f"the time stepping divided by zero or overflowed ({exc}) before step {end}: "
                "the scene's numbers (masses, stiffnesses, dt, the integrator's coefficients) "
                "are too small or too large for floating point arithmetic; check the units"
            ) from None

    def _call(begin, end, meanwhile):
        rec = recorders.for_call(begin, end)
        # The kernel releases the GIL: contiguous slices of the batch run in threads, each
        # member on its own, so one slow member never holds up the others.
        futures = [pool.submit(kernel, piece, _slice_recording(rec, lo, hi), begin, end)
                   for piece, (lo, hi) in enumerate(pieces)]
        _wait(futures, stop, meanwhile)
        recorders.unwritten(rec, begin, end, st.status)
        return rec

    try:
        total = plan.steps + 1
        rec = call(0, 1)  # state t = 0
        compile_seconds = time.perf_counter() - start
        recorders.deliver(rec, 0, 1)
        solve = 0.0
        done = 1
        limit = recorders.max_steps()
        # Calls last about chunk_seconds whatever the mode (progress shown or not), for the
        # progress bar and the streamed blocks; a stop does not wait for a call's end (_wait).
        size = min(total - 1, 500, limit)
        # the sink takes a call's rows while the kernel runs the next call (the states are
        # the kernel's, the rows a call's own buffers): three calls' rows at most are held
        # (STREAM_BYTES in all)
        last = None  # the last call's rows, first and end states
        while done < total:
            end = min(total, done + size)
            tick = time.perf_counter()
            rec = call(done, end, None if last is None else functools.partial(
                _between, recorders, *last))
            elapsed = time.perf_counter() - tick
            solve += elapsed
            last = rec, done, end
            rec = None  # the next call's buffers replace the last's, not join them
            check_stop()
            if progress is not None:
                progress(end, total)
            grow = chunk_seconds / max(elapsed, 1e-6)
            size = max(1, min(limit, int((end - done) * min(grow, 8.0))))
            done = end
            if np.all(st.status[:, StatusColumn.CODE] != Status.OK):
                break
        if last is not None:
            recorders.deliver(*last)
    finally:
        pool.shutdown()
    law_calls = {}
    for group in plan.story_groups:
        law_calls[group.law.name] = st.material_calls[:, ids[group.law]].copy()
    for group in plan.contact_groups:
        law_calls[group.law.name] = st.contact_calls[:, ids[group.law]].copy()
    return Result(
        plan=plan,
        history=recorders.histories(),
        envelope=recorders.envelopes(),
        impacts=st.impacts,
        energy=st.energy,
        status=st.status,
        counters=st.counters,
        law_calls=law_calls,
        solve_seconds=solve,
        compile_seconds=compile_seconds,
        closing=recorders.closing if closing is not None else None,
    )

