"""The kernel's grouped arrays and the names of their slots.

A run is four groups of arrays, each a named tuple so that compiled code reads ``m.mass`` and
``st.energy[b, Energy.KINETIC]`` rather than positional arguments and bare numbers:

- :class:`Model`: what the scene is (masses, connectivity, law ids and parameters, ground
  motion); read only. Arrays of shape ``(B, ...)`` have one row per batch member; topology
  (which DOFs an element joins, which law it uses, the order elements are evaluated in) is
  shared by the batch.
- :class:`Settings`: the integrator's coefficients, Newton's tolerances and the switches that
  decide which parts of the algorithm run (linear, explicit, events, alpha).
- :class:`State`: the committed state of every member, updated in place step by step, with
  its energy terms, status and counters.
- :class:`Recording`: where recorded quantities go, for the steps of one call.

Every array is C-contiguous and of a fixed dtype and rank, whatever the scene, so one compiled
kernel serves every scene.

This module is the one list of the kernel's data: the C kernel's header ``c/state.h`` (its
structs and slot names) is generated from it by ``python -m pframe.kernel.translate``, and the
driver's ctypes mirror of the structs (:mod:`pframe.kernel.ckernel`) is built from it at
import. A test fails when the header is stale.
"""

from __future__ import annotations

from collections import namedtuple
from enum import IntEnum, auto

from pframe.integrators import SCHEMES
from pframe.quantities import QUANTITIES


class Slots(IntEnum):
    """Named slots of one of the kernel's small arrays (or named codes), numbered from 0 in
    the order they are written. Each kind is defined once, here: its C constants
    (``c/state.h``), its count and the names result files use follow from it."""

    @staticmethod
    def _generate_next_value_(name, start, count, last_values):
        return count


class Status(Slots):
    """status[b, StatusColumn.CODE]: why a member stopped."""

    OK = auto()
    NOT_CONVERGED = auto()
    NOT_FINITE = auto()
    NOT_DEFINITE = auto()
    NOT_STABLE = auto()
    STOPPED = auto()  # the driver asked the kernel to stop (Ctrl-C, SIGTERM: Model.stop)


class StatusColumn(Slots):
    """status[b, column]: the code, the committed state count where it stopped, the element
    kind and index (C: ``STATUS_CODE``, ...)."""

    CODE = auto()
    STEP = auto()
    KIND = auto()
    INDEX = auto()


class Kind(Slots):
    """Element kinds in status[b, StatusColumn.KIND]."""

    NODE = auto()
    STORY = auto()
    CONTACT = auto()


class Energy(Slots):
    """energy[b, slot] (J)."""

    INPUT = auto()        # work of the ground motion
    KINETIC = auto()      # kinetic energy now
    DAMPING = auto()      # work of damping
    STOREYS = auto()      # work of the storeys
    CONTACTS = auto()     # work of the contacts
    KINETIC_0 = auto()    # kinetic energy at t = 0
    INPUT_ABS = auto()    # the ground motion's work counted in absolute value, and
    START = auto()        # the mechanical energy at t = 0: these two bound runaway growth
    ALGORITHMIC = auto()  # energy the integrator's own relations remove (HHT, generalised
    # alpha, Wilson-theta, Newmark with gamma > 1/2; see kernel/c/energy.c)
    LINKS = auto()        # work of the links (dampers, couplings, tuned masses)


#: the energy balance's terms as result files name them (``energy_<name>``), in the order of
#: the balance W_input = dE_kinetic + W_damping + W_storeys + W_contacts + W_links + D_alg
ENERGY_TERMS = {"input": Energy.INPUT, "kinetic": Energy.KINETIC, "damping": Energy.DAMPING,
                "storeys": Energy.STOREYS, "contacts": Energy.CONTACTS, "links": Energy.LINKS,
                "initial_kinetic": Energy.KINETIC_0, "algorithmic": Energy.ALGORITHMIC}
#: the energy slots that are the kernel's own bookkeeping (the runaway bound), not written
ENERGY_BOOKKEEPING = (Energy.INPUT_ABS, Energy.START)


class Counter(Slots):
    """counters[b, slot]: linear solves, factorisations of the effective stiffness,
    evaluations of the residual (each evaluates every element once), steps split into
    sub-steps, values gathered by recorders, and contact events located inside steps.
    ``Counter[name.upper()]`` of a name of :data:`COUNTER_NAMES`."""

    SOLVES = auto()
    FACTORISATIONS = auto()
    EVALUATIONS = auto()
    SPLIT_STEPS = auto()
    GATHERS = auto()
    EVENTS = auto()  # sub-steps ended at a located contact event (kernel/c/events.c)


#: the counters' names (``Result.counter(name)``), in slot order
COUNTER_NAMES = tuple(c.name.lower() for c in Counter)

#: recordable quantities: those of :data:`pframe.quantities.QUANTITIES` (the one list), in its
#: order, which is that of Recording.history and Recording.envelope (C: ``DISPLACEMENT``, ...)
Recordable = Slots("Recordable", [q.upper() for q in QUANTITIES])
RECORDABLE = tuple(QUANTITIES)
#: a quantity's slot by its name
RECORDABLE_SLOT = {q: Recordable[q.upper()] for q in RECORDABLE}


#: Settings.scheme: how the kernel runs the implicit integrator (kernel/c/integrator.c): the
#: schemes of :data:`pframe.integrators.SCHEMES`, which follow from the integrators' table (C:
#: ``ALPHA_FAMILY``, ``WILSON_THETA``, ``TABLEAU``: the fast paths of one Newmark stage and the
#: generic stage loop)
Scheme = Slots("Scheme", [scheme.upper() for scheme in SCHEMES])


class StagePoint(Slots):
    """The points a stage's relations combine: the step start, then the ends of the stages
    (at most ``STAGE_POINTS - 1`` stages a step; see pframe.integrators.tableau; C:
    ``POINT_START``, ...)."""

    START = auto()
    STAGE_1 = auto()
    STAGE_2 = auto()
    STAGE_3 = auto()


class Relation(Slots):
    """A stage's relations: its end displacement and velocity, and the displacement, velocity
    and acceleration of its evaluation point (C: ``U_END``, ...)."""

    U_END = auto()
    V_END = auto()
    U_EVAL = auto()
    V_EVAL = auto()
    A_EVAL = auto()


class StageColumn(Slots):
    """Settings.tableau[stage, column]: where the stage ends and where it is evaluated
    (fractions of the step), its effective-stiffness class (stages of one class share a
    factorisation), then the relations' coefficients from ``STAGE_HEAD`` on:
    ``[relation, point, value]`` (C: ``STAGE_END``, ...)."""

    END = auto()
    AT = auto()
    STIFFNESS = auto()


class Value(Slots):
    """The values of a point a relation weighs: u, h v and h^2 a (C: ``VALUE_U``, ...)."""

    U = auto()
    V = auto()
    A = auto()


#: the width of one stage's row of Settings.tableau
STAGE_WIDTH = len(StageColumn) + len(Relation) * len(StagePoint) * len(Value)


class DampingStiffness(Slots):
    """Model.story_damping[e]: the stiffness a storey's beta K damping is proportional to
    (the scene's ``damping.stiffness``; C: ``DAMPING_INITIAL``, ...)."""

    INITIAL = auto()
    CURRENT = auto()
    COMMITTED = auto()


class Scalar(Slots):
    """w.scalars[slot]: the step length of the current factorisation (0 before the first),
    1.0 when an element tangent changed since, the smallest mass of the member, the contact
    held on one branch while an event is located (-1: none) and that branch (1.0 closed, 0.0
    open; see kernel/c/events.c), the work of the non-inertial forces at the alpha point over
    the whole (sub-)step (kernel/c/energy.c), and 1.0 when a step's coefficient divided by
    zero (a step length or Newmark beta that underflows): the kernel stops and the driver
    raises ZeroDivisionError, as Python would. The generic stage loop (kernel/c/newton.c) adds
    the effective-stiffness class of the factorisation in hand, the work of the inertia at the
    stages' evaluation points over the step (kernel/c/energy.c), and 1.0 while a stage after
    the first is solved (the laws start from the previous stage's state, Work.story_stage)."""

    H_FACTORED = auto()
    STALE = auto()
    MASS_MIN = auto()
    HELD = auto()
    HELD_CLOSED = auto()
    ALPHA_WORK = auto()
    ZERO_DIVISION = auto()
    STIFFNESS_FACTORED = auto()
    INERTIAL_WORK = auto()
    LAWS_FROM_STAGE = auto()


class Run(Slots):
    """What one call of the kernel (``pframe_run``) returns: it ran, or a step's coefficients
    divided by zero, or it was asked to stop (C: ``RUN_OK``, ``RUN_ZERO_DIVISION``,
    ``RUN_STOPPED``)."""

    OK = auto()
    ZERO_DIVISION = auto()
    STOPPED = auto()


#: the slot kinds written into c/state.h: title, kind, the C names' prefix, and the name of the
#: count (None: no count)
C_CONSTANTS = (
    ("status codes", Status, "", None),
    ("status columns", StatusColumn, "STATUS_", "STATUS_SLOTS"),
    ("element kinds", Kind, "", None),
    ("energy slots", Energy, "", "ENERGY_SLOTS"),
    ("counters", Counter, "", "COUNTER_SLOTS"),
    ("recordable quantities", Recordable, "", "RECORDABLE_COUNT"),
    ("damping stiffness", DampingStiffness, "DAMPING_", None),
    ("integrator schemes", Scheme, "", None),
    ("stage points", StagePoint, "POINT_", "STAGE_POINTS"),
    ("stage relations", Relation, "", "RELATIONS"),
    ("stage columns", StageColumn, "STAGE_", "STAGE_HEAD"),
    ("point values", Value, "VALUE_", "VALUE_SLOTS"),
    ("work scalars", Scalar, "", "SCALAR_SLOTS"),
    ("pframe_run's return values", Run, "RUN_", None),
)
#: the counts c/state.h defines (``RECORDABLE_COUNT``, ...), by their C name
C_COUNTS = {count: len(kind) for _, kind, _, count in C_CONSTANTS if count}

Model = namedtuple("Model", [
    "mass",             # (B, n) kg, DOFs in band order
    "mass_damping",     # (B, n) a0 m (N s/m)
    # the spring elements: the storeys, then the links (the last `links` of them; a link is a
    # spring between any two DOFs, without Rayleigh damping: kernel/c/energy.c books its work
    # apart), s in all
    "story_dofs",       # (s, 2) lower and upper DOF; -1 is the ground
    "story_order",      # (s,) storeys in evaluation order (grouped by law)
    "story_law",        # (s,) material id (the registry order: kernel/c/laws.c)
    "story_params",     # (B, s, P) the material's packed parameters
    "story_k0",         # (B, s) initial stiffness (N/m)
    "story_beta",       # (B, s) stiffness-proportional damping a1 (s)
    "story_damping",    # (s,) DampingStiffness of the beta K damping
    "story_height",     # (B, s) storey height (m; NaN: not given), for drift ratios
    "story_kg",         # (B, s) P-delta's geometric stiffness P / h (N/m; 0: none)
    "contact_dofs",     # (c, 2) left and right DOF (-1: the ground, a wall)
    "contact_order",    # (c,) contacts in evaluation order (grouped by law)
    "contact_law",      # (c,) contact law id
    "contact_params",   # (B, c, Q) the law's packed parameters
    "gap",              # (B, c) m
    "ground",           # (B, G, steps + 1) the ground's series (pframe.assemble.grounds):
                        # the acceleration along each of the C channels (m/s^2), the site's
                        # axes the motion loads at each support (pframe.assemble.Plan.channels),
                        # then, with elements across supports, their displacements (m) and
                        # velocities (m/s): G = C or 3 C
    "dt",               # (B,) s
    "cd_parts",         # (B,) central-difference sub-steps per step
    "event_parts",      # (B,) sub-steps per step while a contact is closed (events)
    "stop",             # (1,) set to 1 by the driver (Ctrl-C): seen at every evaluation
    "dof_channel",      # (n,) the channel whose ground motion loads a DOF (-m a_g): -1 for a
                        # rotation or a foundation's rocking (an absolute acceleration is
                        # a + a_g of its channel)
    "foundation_dofs",  # (F, 2) sway and rocking DOF of each foundation on soil
    # the sides of the elements that are not plain (pframe.assemble.incidence): side s of
    # element e is sum coef[b, t] x[dof[t]] over t in start[2 e + s] .. start[2 e + s + 1];
    # a plain element (no terms) joins its two DOFs of *_dofs with coefficient 1
    "story_side_start",    # (2 s + 1,)
    "story_side_dof",      # (Ts,)
    "story_side_coef",     # (B, Ts)
    "contact_side_start",  # (2 c + 1,)
    "contact_side_dof",    # (Tc,)
    "contact_side_coef",   # (B, Tc)
    # the named plan points of the floors (point_displacement, point_drift): gauge g is
    # sum gauge_coef[b, t] U[gauge_dof[t]], t in gauge_start[g] .. gauge_start[g + 1]; the
    # displacements along the building's x and y of each point, then its drifts
    "gauge_start",         # (4 P + 1,)
    "gauge_dof",           # (Tg,)
    "gauge_coef",          # (B, Tg)
    # elements across supports (docs/supports.md): the ground displacements' part of spring
    # e's deformation, sum coef[b, t] x[C + channel[t]] over t in start[e] .. start[e + 1]
    # with x the ground's series at the evaluation point (its rate: x[2 C + channel[t]])
    "story_ground_start",    # (s + 1,)
    "story_ground_channel",  # (Tgs,)
    "story_ground_coef",     # (B, Tgs)
    "contact_ground_start",    # (c + 1,)
    "contact_ground_channel",  # (Tgc,)
    "contact_ground_coef",     # (B, Tgc)
    # modal damping (docs/theory.md#damping): a dense block over each such building's DOFs
    "modal_dofs",       # (q,) the DOFs of the blocks, one block after another
    "modal_start",      # (blocks + 1,) where each block starts in modal_dofs
    "modal_matrix",     # (B, sum of n_b^2) each block's matrix, row-major (N s/m)
])

Settings = namedtuple("Settings", [
    "gamma", "beta", "alpha_m", "alpha_f",  # Newmark's gamma and beta, the inertia and force
                                            # weights of the previous step (alpha family)
    "scheme", "theta",                      # Scheme, and Wilson's theta
    "stages", "tableau",  # the step's implicit stages, and their rows (stages, STAGE_WIDTH)
    "kinetic_weight",     # the kinetic energy's (1/2) a M a weight, times h^2 (beta - 1/4)
    "beyond",     # some stage is evaluated past its end (Wilson-theta): see assembly.c
    "tolerance", "absolute_tolerance",      # Newton: |du| <= tolerance |u| + absolute_tolerance
    "max_iterations",                       # Newton iterations per (sub-)step
    "bandwidth",                            # half-bandwidth of the effective stiffness
    "max_split",                            # a failed step is retried in up to 2^max_split parts
    "linear",     # constant effective stiffness: factor once, one solve per step
    "explicit",   # central difference: no solve
    "events",     # locate contact onset and separation inside steps
    "alpha",      # equilibrium off the step end (HHT, generalised-alpha, Wilson-theta)
    "always_refactor",  # refactor before every solve (a test's check that reuse changes no bit)
    "force_split",  # take every implicit step in sub-steps, as a failed one is retried (a
                    # test's check that the retry path runs the integrator)
    "material_plugins", "contact_plugins",  # function pointers of plug-in laws (ids after
                                            # the built-in ones; see pframe.kernel.plugins)
])

State = namedtuple("State", [
    "U", "V", "A",                          # (B, n) committed displacement, velocity, accel.
    "drift", "story_force", "story_damping_force", "story_tangent",  # (B, s) committed
    "story_committed", "story_trial",       # (B, s, S) law state variables
    "contact_force", "penetration",         # (B, c) committed
    "contact_committed", "contact_trial",   # (B, c, T) law state variables
    "impacts",                              # (B, c) contact onsets
    "energy",                               # (B, len(Energy))
    "status",                               # (B, len(StatusColumn))
    "counters",                             # (B, len(Counter))
    "material_calls", "contact_calls",      # (B, law ids) evaluations of each law
])

Recording = namedtuple("Recording", [
    "history",     # arrays (B, rows, width), one per Recordable slot; (B, 0, 0) if unrecorded
    "every",       # (len(Recordable),) record every k-th step; 0 if unrecorded
    "first_row",   # (len(Recordable),) the row of the whole history held in row 0 of this call's buffer
    "envelope",    # arrays (B, width), one per Recordable slot; (B, 0) if unrecorded
    "enveloped",   # (len(Recordable),) 1 where the envelope is recorded
    # the running maximum of u[i] - u[j] over the committed steps (a gap's closing, signed:
    # pframe.gap.runs.GapSink's without a history streamed) of each pair (i, j):
    "closing_dofs",  # (P, 2) the DOFs of each pair
    "closing",       # (B, P) the running maxima (-inf before the first step)
])

Work = namedtuple("Work", [
    "u", "v", "a",            # (n,) trial state at the step end
    "ue", "ve", "ae",         # (n,) the evaluation point (the same arrays for Newmark)
    "R",                      # (n,) residual, then the solution of one solve
    "band",                   # (n, bandwidth + 1) effective stiffness, then its factor
    "drift", "story_force", "story_damping_force", "story_tangent",  # (s,) trial
    "contact_force", "penetration",                                  # (c,) trial
    "story_kk", "contact_kk",  # element tangents in the current factorisation
    "scalars",                 # (len(Scalar),) see Scalar
    # the generic stage loop: the ends of the stages before the last, (stages - 1, 3, n) u, v
    # and a, the deformations and law states at the previous stage's end, the laws start from
    "stage_values", "stage_drift", "stage_penetration", "story_stage", "contact_stage",
    # (G,) the ground's series at a (sub-)step's start and end and at its evaluation point,
    # and at the end of the stage before (the generic stage loop)
    "ag_old", "ag_new", "age", "ag_stage",
])

#: the sizes the C kernel needs besides the arrays (appended to its Model struct)
SIZES = ("batch", "dofs", "stories", "contacts", "links", "story_width", "story_states",
         "contact_width", "contact_states", "ground_width", "channels", "ground_series",
         "materials", "contact_laws", "foundations", "story_terms", "contact_terms", "points",
         "gauge_terms", "story_ground_terms", "contact_ground_terms", "modal_blocks",
         "modal_width")

#: C types of the fields that are not arrays of doubles (``double *``); Recording's per-quantity
#: arrays are C arrays of RECORDABLE length (pframe.kernel.translate writes the structs)
C_TYPES = {
    "Model": {"story_dofs": "int64_t *", "story_order": "int64_t *", "story_law": "int64_t *",
              "story_damping": "int64_t *", "contact_dofs": "int64_t *",
              "foundation_dofs": "int64_t *", "dof_channel": "int64_t *",
              "story_side_start": "int64_t *", "story_side_dof": "int64_t *",
              "contact_side_start": "int64_t *", "contact_side_dof": "int64_t *",
              "gauge_start": "int64_t *", "gauge_dof": "int64_t *",
              "story_ground_start": "int64_t *", "story_ground_channel": "int64_t *",
              "contact_ground_start": "int64_t *", "contact_ground_channel": "int64_t *",
              "modal_dofs": "int64_t *", "modal_start": "int64_t *",
              "contact_order": "int64_t *", "contact_law": "int64_t *",
              "cd_parts": "int64_t *", "event_parts": "int64_t *", "stop": "int64_t *",
              **{name: "int64_t" for name in SIZES}},
    "Settings": {"gamma": "double", "beta": "double", "alpha_m": "double", "alpha_f": "double",
                 "scheme": "int64_t", "theta": "double", "stages": "int64_t",
                 "kinetic_weight": "double", "beyond": "int64_t", "force_split": "int64_t",
                 "tolerance": "double", "absolute_tolerance": "double",
                 "max_iterations": "int64_t", "bandwidth": "int64_t", "max_split": "int64_t",
                 "linear": "int64_t", "explicit": "int64_t", "events": "int64_t",
                 "alpha": "int64_t", "always_refactor": "int64_t",
                 "material_plugins": "LawFunction *", "contact_plugins": "LawFunction *"},
    "State": {"impacts": "int64_t *", "status": "int64_t *", "counters": "int64_t *",
              "material_calls": "int64_t *", "contact_calls": "int64_t *"},
    "Recording": {"history": "double *[RECORDABLE_COUNT]", "every": "int64_t *",
                  "first_row": "int64_t *", "envelope": "double *[RECORDABLE_COUNT]",
                  "enveloped": "int64_t *", "closing_dofs": "int64_t *",
                  "closings": "int64_t", "history_rows": "int64_t[RECORDABLE_COUNT]",
                  "history_width": "int64_t[RECORDABLE_COUNT]",
                  "envelope_width": "int64_t[RECORDABLE_COUNT]",
                  "envelope_count": "int64_t", "envelope_list": "int64_t[RECORDABLE_COUNT]"},
    "Work": {"loops": "void *"},
    "Saved": {"impacts": "int64_t *"},
}
#: Work's C-only field: each member's evaluation loops, prepared once per call (kernel/c/loop.c;
#: assembly.c's Loops); the driver leaves it NULL
WORK_PREPARED = ("loops",)
#: Recording's sizes (C only: the Python group holds the arrays, which carry their shapes),
#: and the enveloped quantities listed (their count, then their slots in order: the kernel
#: updates the envelopes every step and sub-step, without a pass over every quantity), and the
#: number of pairs of closing_dofs
RECORDING_SIZES = ("history_rows", "history_width", "envelope_width", "envelope_count",
                   "envelope_list", "closings")

#: copies of one member's committed arrays of State, which a failed attempt at a step restores
Saved = namedtuple("Saved", [
    "U", "V", "A", "drift", "story_force", "story_damping_force", "story_tangent",
    "story_committed", "contact_force", "penetration", "contact_committed", "impacts", "energy",
])
