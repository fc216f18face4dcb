"""The kernel's grouped arrays and the names of their slots.

A run is four groups of arrays, each a named tuple so that compiled code reads ``m.mass`` and
``st.energy[b, KINETIC]`` rather than positional arguments and bare numbers:

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

# status[b, STATUS_CODE]: why a member stopped
OK, NOT_CONVERGED, NOT_FINITE, NOT_DEFINITE, NOT_STABLE, STOPPED = 0, 1, 2, 3, 4, 5
# status columns: code, the committed state count where it stopped, element kind and index
STATUS_CODE, STATUS_STEP, STATUS_KIND, STATUS_INDEX = 0, 1, 2, 3
STATUS_SLOTS = 4
# element kinds in status[b, STATUS_KIND]
NODE, STORY, CONTACT = 0, 1, 2

# energy[b, slot] (J): work of the ground motion, kinetic energy now, work of damping, of the
# storeys, of the contacts, kinetic energy at t = 0, the ground motion's work counted in
# absolute value, the mechanical energy at t = 0 (the last two bound runaway growth), and the
# energy the integrator's own relations remove (algorithmic dissipation: HHT, generalised
# alpha, Newmark with gamma > 1/2; see kernel/c/energy.c)
INPUT, KINETIC, DAMPING, STOREYS, CONTACTS, KINETIC_0, INPUT_ABS, START, ALGORITHMIC = range(9)
ENERGY_SLOTS = 9

# counters[b, slot]: linear solves, factorisations of the effective stiffness, evaluations of
# the residual (each evaluates every element once), steps split into sub-steps, and values
# gathered by recorders
SOLVES, FACTORISATIONS, EVALUATIONS, SPLIT_STEPS, GATHERS = range(5)
COUNTER_SLOTS = 5
COUNTER_NAMES = ("solves", "factorisations", "evaluations", "split_steps", "gathers")

# recordable quantities, in the order of Recording.history and Recording.envelope
DISPLACEMENT, VELOCITY, ACCELERATION, STORY_DRIFT, STORY_FORCE, CONTACT_FORCE, \
    CONTACT_PENETRATION, GROUND_ACCELERATION = range(8)
RECORDABLE = ("displacement", "velocity", "acceleration", "story_drift", "story_force",
              "contact_force", "contact_penetration", "ground_acceleration")
RECORDABLE_COUNT = len(RECORDABLE)

Model = namedtuple("Model", [
    "mass",             # (B, n) kg, DOFs in band order
    "mass_damping",     # (B, n) a0 m (N s/m)
    "story_dofs",       # (s, 2) lower and upper DOF; -1 is the ground
    "story_order",      # (s,) storeys in evaluation order (grouped by law)
    "story_law",        # (s,) material id (the registry order: kernel/c/laws.c)
    "story_params",     # (B, s, P) the material's packed parameters
    "story_k0",         # (B, s) initial stiffness (N/m)
    "story_beta",       # (B, s) stiffness-proportional damping a1 (s)
    "story_damping",    # (s,) damping on the 0 initial, 1 current, 2 committed stiffness
    "contact_dofs",     # (c, 2) left and right DOF
    "contact_order",    # (c,) contacts in evaluation order (grouped by law)
    "contact_law",      # (c,) contact law id
    "contact_params",   # (B, c, Q) the law's packed parameters
    "gap",              # (B, c) m
    "ground",           # (B, steps + 1) ground acceleration (m/s^2)
    "dt",               # (B,) s
    "cd_parts",         # (B,) central-difference sub-steps per step
    "event_parts",      # (B,) sub-steps per step while a contact is closed (events)
    "stop",             # (1,) set to 1 by the driver (Ctrl-C): seen at every evaluation
])

Settings = namedtuple("Settings", [
    "gamma", "beta", "alpha_m", "alpha_f",  # generalised-alpha coefficients
    "tolerance", "absolute_tolerance",      # Newton: |du| <= tolerance |u| + absolute_tolerance
    "max_iterations",                       # Newton iterations per (sub-)step
    "bandwidth",                            # half-bandwidth of the effective stiffness
    "max_split",                            # a failed step is retried in up to 2^max_split parts
    "linear",     # constant effective stiffness: factor once, one solve per step
    "explicit",   # central difference: no solve
    "events",     # locate contact onset and separation inside steps
    "alpha",      # equilibrium off the step end (HHT, generalised-alpha)
    "always_refactor",  # refactor before every solve (a test's check that reuse changes no bit)
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
    "energy",                               # (B, ENERGY_SLOTS)
    "status",                               # (B, STATUS_SLOTS)
    "counters",                             # (B, COUNTER_SLOTS)
    "material_calls", "contact_calls",      # (B, law ids) evaluations of each law
])

Recording = namedtuple("Recording", [
    "history",     # 8 arrays (B, rows, width), one per RECORDABLE; (B, 0, 0) if unrecorded
    "every",       # (8,) record every k-th step; 0 if unrecorded
    "first_row",   # (8,) the row of the whole history held in row 0 of this call's buffer
    "envelope",    # 8 arrays (B, width), one per RECORDABLE; (B, 0) if unrecorded
    "enveloped",   # (8,) 1 where the envelope is recorded
])

Work = namedtuple("Work", [
    "u", "v", "a",            # (n,) trial state at the step end
    "ue", "ve", "ae",         # (n,) the evaluation point (the same arrays for Newmark)
    "R",                      # (n,) residual, then the solution of one solve
    "band",                   # (n, bandwidth + 1) effective stiffness, then its factor
    "drift", "story_force", "story_damping_force", "story_tangent",  # (s,) trial
    "contact_force", "penetration",                                  # (c,) trial
    "story_kk", "contact_kk",  # element tangents in the current factorisation
    "scalars",                 # (SCALAR_SLOTS,) see H_FACTORED, STALE, MASS_MIN
])
# w.scalars: the step length of the current factorisation (0 before the first), 1.0 when an
# element tangent changed since, the smallest mass of the member, the contact held on one
# branch while an event is located (-1: none) and that branch (1.0 closed, 0.0 open; see
# kernel/c/events.c), the work of the non-inertial forces at the alpha point over the whole
# (sub-)step (kernel/c/energy.c), and 1.0 when a step's coefficient divided by zero (a step
# length or Newmark beta that underflows): the kernel stops and the driver raises
# ZeroDivisionError, as Python would
H_FACTORED, STALE, MASS_MIN, HELD, HELD_CLOSED, ALPHA_WORK, ZERO_DIVISION = range(7)
SCALAR_SLOTS = 7

#: the sizes the C kernel needs besides the arrays (appended to its Model struct)
SIZES = ("batch", "dofs", "stories", "contacts", "story_width", "story_states",
         "contact_width", "contact_states", "ground_width", "materials", "contact_laws")

#: C types of the fields that are not arrays of doubles (``double *``); Recording's per-quantity
#: arrays are C arrays of RECORDABLE length (pframe.kernel.translate writes the structs)
C_TYPES = {
    "Model": {"story_dofs": "int64_t *", "story_order": "int64_t *", "story_law": "int64_t *",
              "story_damping": "int64_t *", "contact_dofs": "int64_t *",
              "contact_order": "int64_t *", "contact_law": "int64_t *",
              "cd_parts": "int64_t *", "event_parts": "int64_t *", "stop": "int64_t *",
              **{name: "int64_t" for name in SIZES}},
    "Settings": {"gamma": "double", "beta": "double", "alpha_m": "double", "alpha_f": "double",
                 "tolerance": "double", "absolute_tolerance": "double",
                 "max_iterations": "int64_t", "bandwidth": "int64_t", "max_split": "int64_t",
                 "linear": "int64_t", "explicit": "int64_t", "events": "int64_t",
                 "alpha": "int64_t", "always_refactor": "int64_t",
                 "material_plugins": "LawFunction *", "contact_plugins": "LawFunction *"},
    "State": {"impacts": "int64_t *", "status": "int64_t *", "counters": "int64_t *",
              "material_calls": "int64_t *", "contact_calls": "int64_t *"},
    "Recording": {"history": "double *[RECORDABLE_COUNT]", "every": "int64_t *",
                  "first_row": "int64_t *", "envelope": "double *[RECORDABLE_COUNT]",
                  "enveloped": "int64_t *", "history_rows": "int64_t[RECORDABLE_COUNT]",
                  "history_width": "int64_t[RECORDABLE_COUNT]",
                  "envelope_width": "int64_t[RECORDABLE_COUNT]"},
    "Work": {},
    "Saved": {"impacts": "int64_t *"},
}
#: Recording's sizes (C only: the Python group holds the arrays, which carry their shapes)
RECORDING_SIZES = ("history_rows", "history_width", "envelope_width")

#: the named slot constants written into c/state.h, by group
C_CONSTANTS = {
    "status codes": ("OK", "NOT_CONVERGED", "NOT_FINITE", "NOT_DEFINITE", "NOT_STABLE",
                     "STOPPED"),
    "status columns": ("STATUS_CODE", "STATUS_STEP", "STATUS_KIND", "STATUS_INDEX",
                       "STATUS_SLOTS"),
    "element kinds": ("NODE", "STORY", "CONTACT"),
    "energy slots": ("INPUT", "KINETIC", "DAMPING", "STOREYS", "CONTACTS", "KINETIC_0",
                     "INPUT_ABS", "START", "ALGORITHMIC", "ENERGY_SLOTS"),
    "counters": ("SOLVES", "FACTORISATIONS", "EVALUATIONS", "SPLIT_STEPS", "GATHERS",
                 "COUNTER_SLOTS"),
    "recordable quantities": ("DISPLACEMENT", "VELOCITY", "ACCELERATION", "STORY_DRIFT",
                              "STORY_FORCE", "CONTACT_FORCE", "CONTACT_PENETRATION",
                              "GROUND_ACCELERATION", "RECORDABLE_COUNT"),
    "work scalars": ("H_FACTORED", "STALE", "MASS_MIN", "HELD", "HELD_CLOSED", "ALPHA_WORK",
                     "ZERO_DIVISION", "SCALAR_SLOTS"),
}

#: copies of one member's committed arrays of State, which a failed attempt at a step restores
Saved = namedtuple("Saved", [
    "U", "V", "A", "drift", "story_force", "story_damping_force", "story_tangent",
    "story_committed", "contact_force", "penetration", "contact_committed", "impacts", "energy",
])
