"""Writes the source of a time-stepping kernel that holds only what one scene needs.

The kernel is an implicit member of the generalised-alpha family (Newmark, HHT,
Chung-Hulbert) with full Newton iterations, or explicit central difference. From the plan's
*structure*
(laws in use, contacts or none, linear or not, quantities recorded) this module writes a
Python module whose ``kernel`` function numba compiles and caches on disk. A linear scene gets
a kernel with a factor-once solve and no Newton loop; a scene without contacts gets no contact
code; a quantity nobody records is never gathered. Law ``force`` functions, built-in or from a
plug-in, are called directly, so numba inlines them like built-in code.

Kernel arguments are listed by :func:`argument_names`; state arrays are updated in place, so a
run can proceed chunk by chunk (for a progress bar) with identical results.
"""

from __future__ import annotations

import hashlib
import inspect
from dataclasses import dataclass

from pframe.assemble.plan import Plan

FORMAT_VERSION = "3"

#: status codes written by the kernel into status[b, 0]
OK, NOT_CONVERGED, NOT_FINITE, NOT_DEFINITE, NOT_STABLE = 0, 1, 2, 3, 4
#: element kinds written into status[b, 2]
NODE, STORY, CONTACT = 0, 1, 2

_GATHER = {
    "displacement": ("n", "u[i]"),
    "velocity": ("n", "v[i]"),
    "acceleration": ("n", "a[i]"),
    "story_drift": ("s", "drift_c[b, i]"),
    "story_force": ("s", "sforce_c[b, i]"),
    "contact_force": ("c", "cforce_c[b, i]"),
    "contact_penetration": ("c", "max(cpen_c[b, i], 0.0)"),
    "ground_acceleration": (None, "ag[b, k]"),
}


@dataclass(frozen=True)
class Structure:
    """What decides the kernel's code (numbers do not)."""

    story_laws: tuple[type, ...]
    contact_laws: tuple[type, ...]
    linear: bool
    damping_modes: tuple[int, ...]  # distinct codes in use
    history: tuple[str, ...]
    envelope: tuple[str, ...]
    alpha: bool = False  # equilibrium off the step end (HHT, generalised-alpha)
    explicit: bool = False  # central difference
    events: bool = False  # locate contact onset and separation inside steps

    @classmethod
    def of(cls, plan: Plan) -> Structure:
        c = plan.integrator
        return cls(
            story_laws=tuple(g.law for g in plan.story_groups),
            contact_laws=tuple(g.law for g in plan.contact_groups),
            linear=plan.linear,
            damping_modes=tuple(sorted(set(int(c) for c in plan.story_damping_stiffness))),
            history=tuple(q for q, _ in plan.history),
            envelope=plan.envelope,
            alpha=c.alpha,
            explicit=c.explicit,
            events=c.events and bool(plan.contact_groups),
        )

    def key(self) -> str:
        """A hash of the structure and of the source of everything the kernel calls."""
        from pframe import __version__
        from pframe.kernel import banded

        parts = [FORMAT_VERSION, __version__, repr(self.linear), repr(self.damping_modes),
                 repr(self.history), repr(self.envelope), repr((self.alpha, self.explicit,
                                                                self.events))]
        for law in self.story_laws + self.contact_laws:
            parts.append(f"{law.__module__}.{law.__qualname__}")
            parts.append(inspect.getsource(law.force))
        parts += [inspect.getsource(banded), inspect.getsource(inspect.getmodule(generate))]
        return hashlib.sha256("\n".join(parts).encode()).hexdigest()[:20]


def argument_names(structure: Structure) -> list[str]:
    names = ["begin", "end", "dt", "gamma", "beta", "alpha_m", "alpha_f", "tol", "atol",
             "max_iter", "bw", "mass", "mdamp", "story_dofs", "k0", "sbeta", "dmode"]
    for g in range(len(structure.story_laws)):
        names += [f"sp{g}", f"sx{g}", f"sc{g}", f"st{g}"]
    names += ["contact_dofs", "gap"]
    for g in range(len(structure.contact_laws)):
        names += [f"cp{g}", f"cx{g}", f"cc{g}", f"ct{g}"]
    names += ["ag", "U", "V", "A", "drift_c", "sforce_c", "sdamp_c", "stan_c",
              "cforce_c", "cpen_c", "impacts", "energy", "status", "iterations",
              "substeps", "max_split", "cd_parts", "event_parts"]
    for q in structure.history:
        names += [f"h_{q}", f"every_{q}"]
    names += [f"e_{q}" for q in structure.envelope]
    return names


class _Writer:
    def __init__(self):
        self.lines: list[str] = []
        self.depth = 0

    def __call__(self, *lines: str):
        for line in lines:
            self.lines.append("    " * self.depth + line if line else "")
        return self

    def indent(self):
        self.depth += 1
        return self

    def dedent(self):
        self.depth -= 1
        return self


def _law_imports(w: _Writer, laws, prefix: str):
    for g, law in enumerate(laws):
        w(f"from {law.__module__} import {law.__qualname__.split('.')[0]} as _{prefix}{g}")
        w(f"{prefix}{g} = numba.njit(inline='always')(_{prefix}{g}.force)")


def _evaluate(w: _Writer, st: Structure, tangent: bool):
    """Forces, residual R and (with ``tangent``) each element's effective tangent at the
    evaluation point (ue, ve, ae, age): the step end for Newmark, the alpha point for HHT and
    generalised-alpha. Tangent weights: wm on the mass term, wf on the others. A tangent that
    differs from the one in the current factorisation (skk, ckk) marks it stale."""
    w("for i in range(n):")
    w("    R[i] = -mass[b, i] * (age + ae[i]) - mdamp[b, i] * ve[i]")
    for g, _ in enumerate(st.story_laws):
        w(f"for j in range(sx{g}.shape[0]):").indent()
        w(f"e = sx{g}[j]", "lo = story_dofs[e, 0]", "up = story_dofs[e, 1]",
          "d = ue[up]", "r = ve[up]", "if lo >= 0:",
          "    d -= ue[lo]", "    r -= ve[lo]",
          f"f, kt, kr = slaw{g}(sp{g}b[j], sc{g}b[j], st{g}b[j], d, r)")
        if st.damping_modes == (0,):
            w("kd = k0[b, e]")
        else:
            w("kd = k0[b, e]", "if dmode[e] == 1:", "    kd = kt",
              "elif dmode[e] == 2:", "    kd = stan_c[b, e]")
        w("fd = sbeta[b, e] * kd * r", "drift_t[e] = d", "sforce_t[e] = f", "sdamp_t[e] = fd",
          "stan_t[e] = kt", "R[up] -= f + fd", "if lo >= 0:", "    R[lo] += f + fd")
        if tangent:
            w("kk = (kt + c1 * (kr + sbeta[b, e] * kd)) * wf", "if kk != skk[e]:",
              "    skk[e] = kk", "    stale = True")
        w().dedent()
    for g, _ in enumerate(st.contact_laws):
        w(f"for j in range(cx{g}.shape[0]):").indent()
        w(f"e = cx{g}[j]", "lft = contact_dofs[e, 0]", "rgt = contact_dofs[e, 1]",
          "d = ue[lft] - ue[rgt] - gap[b, e]", "r = ve[lft] - ve[rgt]",
          f"f, kd_, kr = claw{g}(cp{g}b[j], cc{g}b[j], ct{g}b[j], d, r)",
          "cforce_t[e] = f", "cpen_t[e] = d", "R[lft] -= f", "R[rgt] += f")
        if tangent:
            w("kk = (kd_ + c1 * kr) * wf", "if kk != ckk[e]:", "    ckk[e] = kk",
              "    stale = True")
        w().dedent()


def _assemble_band(w: _Writer, st: Structure):
    """The effective tangent band from the element tangents of the last evaluation."""
    w("for i in range(n):", "    for d in range(1, bw + 1):", "        band[i, d] = 0.0",
      "    band[i, 0] = mass[b, i] * c0 * wm + mdamp[b, i] * c1 * wf")
    if st.story_laws:
        w("for e in range(ns):", "    kk = skk[e]", "    lo = story_dofs[e, 0]",
          "    up = story_dofs[e, 1]", "    band[up, 0] += kk", "    if lo >= 0:",
          "        band[lo, 0] += kk", "        band[max(lo, up), abs(lo - up)] -= kk")
    if st.contact_laws:
        w("for e in range(nc):", "    kk = ckk[e]", "    lft = contact_dofs[e, 0]",
          "    rgt = contact_dofs[e, 1]", "    band[lft, 0] += kk", "    band[rgt, 0] += kk",
          "    band[max(lft, rgt), abs(lft - rgt)] -= kk")


def _fail(w: _Writer, code: str, kind: str, index: str, leave: bool = True):
    w(f"status[b, 0] = {code}", "status[b, 1] = k", f"status[b, 2] = {kind}",
      f"status[b, 3] = {index}", "failed = True")
    if leave:
        w("break")


def _finite_check(w: _Writer, st: Structure):
    w("total = 0.0", "for i in range(n):", "    total += R[i]",
      "if not np.isfinite(total):").indent()
    w(f"kind = {NODE}", "where = 0")
    if st.story_laws:
        w("for e in range(ns):", "    if not np.isfinite(sforce_t[e] + sdamp_t[e]):",
          f"        kind = {STORY}", "        where = e", "        break")
    if st.contact_laws:
        w("for e in range(nc):", "    if not np.isfinite(cforce_t[e]):",
          f"        kind = {CONTACT}", "        where = e", "        break")
    _fail(w, str(NOT_FINITE), "kind", "where")
    w().dedent()


def _at_end_point(w: _Writer, st: Structure):
    """Make the evaluation point the step end (a no-op for Newmark, whose ue is u_new)."""
    if st.alpha:
        w("for i in range(n):", "    ue[i] = u_new[i]", "    ve[i] = v_new[i]",
          "    ae[i] = a_new[i]")
    w("age = ag_new")


def _at_alpha_point(w: _Writer, st: Structure):
    if st.alpha:
        w("for i in range(n):", "    ue[i] = wf * u_new[i] + alpha_f * U[b, i]",
          "    ve[i] = wf * v_new[i] + alpha_f * V[b, i]",
          "    ae[i] = wm * a_new[i] + alpha_m * A[b, i]",
          "age = wf * ag_new + alpha_f * ag_old")
    else:
        w("age = ag_new")


def _commit(w: _Writer, st: Structure):
    """Energy increments (trapezoidal work), impact counts, state copy; runaway check."""
    w("if k > 0:").indent()
    w("work_in = 0.0", "work_damp = 0.0", "for i in range(n):",
      "    du = u_new[i] - U[b, i]",
      "    work_in -= 0.5 * (ag_old + ag_new) * mass[b, i] * du",
      "    work_damp += 0.5 * mdamp[b, i] * (V[b, i] + v_new[i]) * du",
      "work_story = 0.0", "for e in range(ns):",
      "    dd = drift_t[e] - drift_c[b, e]",
      "    work_story += 0.5 * (sforce_c[b, e] + sforce_t[e]) * dd",
      "    work_damp += 0.5 * (sdamp_c[b, e] + sdamp_t[e]) * dd",
      "energy[b, 0] += work_in", "energy[b, 2] += work_damp", "energy[b, 3] += work_story")
    if st.contact_laws:
        w("work_contact = 0.0", "for e in range(nc):",
          "    work_contact += 0.5 * (cforce_c[b, e] + cforce_t[e]) * (cpen_t[e] - cpen_c[b, e])",
          "    if cpen_c[b, e] <= 0.0 and cpen_t[e] > 0.0:", "        impacts[b, e] += 1",
          "energy[b, 4] += work_contact")
    w().dedent()
    # Newmark's relations make (1/2) v M v + (beta - 1/4) (h^2 / 2) a M a the kinetic energy
    # whose increments the trapezoidal inertia work equals exactly (beta = 1/4: no term;
    # central difference: beta = 0), so the balance also closes for explicit steps.
    w("shadow = (beta - 0.25) * hs * hs", "kinetic = 0.0", "raw = 0.0", "for i in range(n):",
      "    U[b, i] = u_new[i]", "    V[b, i] = v_new[i]", "    A[b, i] = a_new[i]",
      "    raw += 0.5 * mass[b, i] * v_new[i] * v_new[i]",
      "    kinetic += 0.5 * mass[b, i] * (v_new[i] * v_new[i] + shadow * a_new[i] * a_new[i])",
      "energy[b, 1] = kinetic", "if k == 0:", "    energy[b, 5] = kinetic",
      "for e in range(ns):", "    drift_c[b, e] = drift_t[e]", "    sforce_c[b, e] = sforce_t[e]",
      "    sdamp_c[b, e] = sdamp_t[e]", "    stan_c[b, e] = stan_t[e]")
    if st.contact_laws:
        w("for e in range(nc):", "    cforce_c[b, e] = cforce_t[e]", "    cpen_c[b, e] = cpen_t[e]")
    for g, law in enumerate(st.story_laws):
        if law.state_names:
            w(f"sc{g}[b] = st{g}[b]")
    for g, law in enumerate(st.contact_laws):
        if law.state_names:
            w(f"cc{g}[b] = ct{g}[b]")
    # Divergence: the kinetic energy cannot exceed what came in (initial energy plus the
    # input work, counted in absolute value) but by the integrator's own small excess; ten
    # times that means the numbers are running away (an energy test on the balance would not
    # do: Newmark with gamma = 1/2 conserves its modified energy even when unstable).
    w("if k == 0:").indent()
    w("start = raw", "for e in range(ns):", "    start += 0.5 * sforce_t[e] * drift_t[e]")
    if st.contact_laws:
        w("for e in range(nc):", "    start += 0.5 * cforce_t[e] * max(cpen_t[e], 0.0)")
    w("energy[b, 7] = abs(start)").dedent()
    w("else:", "    energy[b, 6] += abs(work_in)",
      "budget = energy[b, 6] + energy[b, 7] + (hs * (abs(ag_old) + abs(ag_new))) ** 2 * mmin",
      "if not raw <= 10.0 * budget:").indent()
    w("worst = 0", "for i in range(n):", "    if abs(U[b, i]) > abs(U[b, worst]):",
      "        worst = i")
    _fail(w, str(NOT_STABLE), str(NODE), "worst", leave=False)
    w().dedent()


def _record(w: _Writer, st: Structure):
    sizes = {"n": "n", "s": "ns", "c": "nc"}
    for q in st.history:
        size, value = _GATHER[q]
        value = value.replace("u[i]", "U[b, i]").replace("v[i]", "V[b, i]").replace("a[i]", "A[b, i]")
        w(f"if k % every_{q} == 0:").indent()
        if size is None:
            w(f"h_{q}[b, k // every_{q}] = {value}")
        else:
            w(f"for i in range({sizes[size]}):", f"    h_{q}[b, k // every_{q}, i] = {value}")
        w().dedent()
    for q in st.envelope:
        size, value = _GATHER[q]
        value = value.replace("u[i]", "U[b, i]").replace("v[i]", "V[b, i]").replace("a[i]", "A[b, i]")
        if size is None:
            w(f"e_{q}[b] = max(e_{q}[b], abs({value}))")
        else:
            w(f"for i in range({sizes[size]}):",
              f"    e_{q}[b, i] = max(e_{q}[b, i], abs({value}))")


def _committed_arrays(st: Structure) -> list[str]:
    """Per-member committed arrays: what a failed attempt at a step must restore."""
    names = ["U", "V", "A", "drift_c", "sforce_c", "sdamp_c", "stan_c", "energy"]
    if st.contact_laws:
        names += ["cforce_c", "cpen_c", "impacts"]
    names += [f"sc{g}" for g, law in enumerate(st.story_laws) if law.state_names]
    names += [f"cc{g}" for g, law in enumerate(st.contact_laws) if law.state_names]
    return names


def _constants(w: _Writer, h: str):
    w(f"c0 = 1.0 / (beta * {h} * {h})", f"c1 = gamma / (beta * {h})", f"c2 = 1.0 / (beta * {h})",
      f"c4 = {h} * (1.0 - gamma)", f"c5 = {h} * gamma",
      "inv_c0_mmin = 1.0 / (c0 * wm * mmin)")


def _interpolate_ground(w: _Writer, start: str, stop: str):
    w(f"ag_old = ag[b, k - 1] + (ag[b, k] - ag[b, k - 1]) * {start}",
      f"ag_new = ag[b, k - 1] + (ag[b, k] - ag[b, k - 1]) * {stop}")


def _newton(w: _Writer, st: Structure):
    """Iterate one (sub-)step from the committed state to equilibrium at ag_new."""
    # Predictor of a nonlinear scene: constant acceleration (a_new = A, v_new = V + hs A).
    # A storey that keeps yielding or a contact that stays closed is then met on its current
    # branch with the tangent of the direction it moves in, and one solve ends the step. The
    # old predictor u_new = U (v_new = -V with average acceleration) evaluated every law at
    # its committed point, where a yielding storey reports its elastic slope: four steps in
    # five of the paper's example took a second solve. A linear scene's single solve is
    # exact from any predictor.
    w("for i in range(n):",
      "    u_new[i] = U[b, i]" if st.linear
      else "    u_new[i] = U[b, i] + hs * V[b, i] + 0.5 * hs * hs * A[b, i]",
      "converged = False")
    w("for it in range(max_iter + 1):").indent()
    w("for i in range(n):",
      "    a_new[i] = c0 * (u_new[i] - U[b, i]) - c2 * V[b, i] - c3 * A[b, i]",
      "    v_new[i] = V[b, i] + c4 * A[b, i] + c5 * a_new[i]")
    _at_alpha_point(w, st)
    _evaluate(w, st, tangent=not st.linear)
    _finite_check(w, st)
    if not st.linear:
        # The next increment du = K^-1 R is bounded by |R| / (c0 wm min m) while the tangents
        # are not negative. When that bound is a thousandth of the tolerance the correction
        # is negligible (a step whose laws stayed on one branch: R is round-off), so skip it;
        # otherwise iterate, so that results do not depend on the tolerance.
        w("if it > 0 and not converged:", "    norm_r = 0.0", "    for i in range(n):",
          "        norm_r += R[i] * R[i]",
          "    converged = np.sqrt(norm_r) * inv_c0_mmin <= 1e-3 * (tol * np.sqrt(norm_u) + atol)")
    w("if converged:", "    break")
    w("if it == max_iter:").indent()
    w("worst = 0", "for i in range(n):", "    if abs(R[i]) > abs(R[worst]):", "        worst = i")
    _fail(w, str(NOT_CONVERGED), str(NODE), "worst")
    w().dedent()
    if not st.linear:
        # Refactor only when a tangent or the (sub-)step changed: a storey that stays elastic
        # or keeps yielding and an open contact keep theirs, so most steps reuse the factor
        # (bit for bit what refactoring would give).
        w("if stale or hs != h_factored:").indent()
        _assemble_band(w, st)
        w("stale = False", "h_factored = hs", "if not ldl_factor(band, bw):").indent()
        _fail(w, str(NOT_DEFINITE), str(NODE), "0")
        w().dedent().dedent()
    w("ldl_solve(band, bw, R)", "iterations[b] += 1")
    if st.linear:
        w("for i in range(n):", "    u_new[i] += R[i]", "converged = True")
    else:
        w("norm_du = 0.0", "norm_u = 0.0", "for i in range(n):", "    u_new[i] += R[i]",
          "    norm_du += R[i] * R[i]", "    norm_u += u_new[i] * u_new[i]",
          "converged = np.sqrt(norm_du) <= tol * np.sqrt(norm_u) + atol")
    w().dedent()  # Newton loop
    if st.alpha:
        # commit the laws' state and forces at the step end, not at the alpha point
        w("if not failed:").indent()
        _at_end_point(w, st)
        _evaluate(w, st, tangent=False)
        w().dedent()


def _initial_state(w: _Writer, st: Structure):
    """t = 0: accelerations from equilibrium with the initial displacements and velocities."""
    w("ag_old = 0.0", "ag_new = ag[b, 0]", "for i in range(n):", "    u_new[i] = U[b, i]",
      "    v_new[i] = V[b, i]", "    a_new[i] = 0.0")
    _at_end_point(w, st)
    w("for once in range(1):").indent()  # a loop for _fail's break
    _evaluate(w, st, tangent=False)
    _finite_check(w, st)
    w().dedent()
    w("if failed:", "    break", "for i in range(n):", "    a_new[i] = R[i] / mass[b, i]")
    _commit(w, st)
    _record(w, st)


def _header(w: _Writer, st: Structure):
    w('"""Generated by pframe.kernel.codegen; do not edit (regenerated when pframe changes)."""',
      "import numba", "import numpy as np",
      "from pframe.kernel.banded import ldl_factor, ldl_solve")
    _law_imports(w, st.story_laws, "slaw")
    _law_imports(w, st.contact_laws, "claw")
    w("", "", "@numba.njit(cache=True, parallel=False, nogil=True)",
      f"def kernel({', '.join(argument_names(st))}):").indent()
    w("nb = mass.shape[0]", "n = mass.shape[1]", "ns = story_dofs.shape[0]",
      "nc = contact_dofs.shape[0]", "wm = 1.0 - alpha_m", "wf = 1.0 - alpha_f",
      "c3 = 0.5 / beta - 1.0" if not st.explicit else "c3 = 0.0",
      "for b in range(nb):").indent()
    w("if status[b, 0] != 0:", "    continue", "h = dt[b]", "mmin = mass[b].min()",
      "u_new = np.empty(n)", "v_new = np.empty(n)", "a_new = np.empty(n)", "R = np.empty(n)",
      "band = np.zeros((n, bw + 1))",
      "drift_t = np.zeros(ns)", "sforce_t = np.zeros(ns)", "sdamp_t = np.zeros(ns)",
      "stan_t = np.zeros(ns)", "cforce_t = np.zeros(nc)", "cpen_t = np.zeros(nc)",
      "norm_u = 0.0", "failed = False", "hs = h / cd_parts[b]" if st.explicit else "hs = h")
    if not st.linear and not st.explicit:
        # element tangents in the current factorisation of the effective stiffness
        w("skk = np.full(ns, np.nan)", "ckk = np.full(nc, np.nan)", "stale = True",
          "h_factored = 0.0")
    # this member's law parameters and states, taken once (not per element call)
    for prefix, laws in (("s", st.story_laws), ("c", st.contact_laws)):
        for g in range(len(laws)):
            w(*(f"{prefix}{kind}{g}b = {prefix}{kind}{g}[b]" for kind in "pct"))
    if st.alpha:
        w("ue = np.empty(n)", "ve = np.empty(n)", "ae = np.empty(n)")
    elif st.explicit:
        w("ue = u_new", "ve = v_new", "ae = np.zeros(n)")
    else:
        w("ue = u_new", "ve = v_new", "ae = a_new")


def _linear_body(w: _Writer, st: Structure):
    """Linear scene: the effective stiffness is constant; factor it once, one solve a step."""
    _constants(w, "h")
    w("for i in range(n):", "    band[i, 0] = mass[b, i] * c0 * wm + mdamp[b, i] * c1 * wf",
      "for e in range(ns):",
      "    lo = story_dofs[e, 0]", "    up = story_dofs[e, 1]",
      "    kk = k0[b, e] * (1.0 + c1 * sbeta[b, e]) * wf", "    band[up, 0] += kk",
      "    if lo >= 0:", "        band[lo, 0] += kk",
      "        band[max(lo, up), abs(lo - up)] -= kk",
      "if not ldl_factor(band, bw):", f"    status[b, 0] = {NOT_DEFINITE}",
      "    status[b, 1] = begin", "    continue",
      "for k in range(begin, end):").indent()
    w("if k == 0:").indent()
    _initial_state(w, st)
    w("continue").dedent()
    _interpolate_ground(w, "0.0", "1.0")
    _newton(w, st)
    w("if failed:", "    break")
    _commit(w, st)
    w("if failed:", "    break")
    _record(w, st)


def _explicit_body(w: _Writer, st: Structure):
    """Central difference: predict with the old acceleration, correct the velocity once."""
    w("for k in range(begin, end):").indent()
    w("if k == 0:").indent()
    _initial_state(w, st)
    w("continue").dedent()
    w("parts = cd_parts[b]", "hs = h / parts", "for part in range(parts):").indent()
    _interpolate_ground(w, "part / parts", "(part + 1) / parts")
    w("age = ag_new", "for i in range(n):",
      "    u_new[i] = U[b, i] + hs * V[b, i] + 0.5 * hs * hs * A[b, i]",
      "    v_new[i] = V[b, i] + hs * A[b, i]")
    for _ in range(2):  # predictor, then one corrector of the velocity-dependent forces
        _evaluate(w, st, tangent=False)
        _finite_check(w, st)
        w("for i in range(n):", "    a_new[i] = R[i] / mass[b, i]",
          "    v_new[i] = V[b, i] + 0.5 * hs * (A[b, i] + a_new[i])")
    w("iterations[b] += 1")
    _commit(w, st)
    w("if failed:", "    break")
    w().dedent()  # parts
    w("if failed:", "    break")
    _record(w, st)


def _event_location(w: _Writer, st: Structure):
    """After a converged sub-step from pos to f_try: if a contact opened or closed inside it,
    shorten it (regula falsi on the fraction) so that it ends just past the crossing, where
    the onset velocity is taken; the rest of the step follows as further sub-steps."""
    w("first = -1", "s_best = 2.0", "for e in range(nc):",
      "    d0 = cpen_c[b, e]", "    d1 = cpen_t[e]",
      "    if d0 != 0.0 and ((d0 < 0.0 < d1) or (d0 > 0.0 >= d1)):",
      "        s = d0 / (d0 - d1)", "        if s < s_best:", "            s_best = s",
      "            first = e")
    w("if first >= 0:").indent()
    w("d0 = cpen_c[b, first]", "d1 = cpen_t[first]",
      "target = 1e-7 * abs(d1 - d0) * (1.0 if d1 > 0.0 else -1.0)",
      "lo_s = 0.0", "lo_d = d0", "hi_s = 1.0", "hi_d = d1", "span = f_try - pos",
      "for rep in range(8):").indent()
    w("s = lo_s + (target - lo_d) * (hi_s - lo_s) / (hi_d - lo_d)",
      "s = min(max(s, lo_s + 1e-6 * (hi_s - lo_s)), hi_s - 1e-6 * (hi_s - lo_s))",
      "f_try = pos + s * span", "hs = (f_try - pos) * h")
    _constants(w, "hs")
    _interpolate_ground(w, "pos", "f_try")
    _newton(w, st)
    w("if failed:", "    break",
      "d = cpen_t[first]",
      "if (target > 0.0 and 0.0 < d <= 2.0 * target) or (target < 0.0 and 2.0 * target <= d <= 0.0):",
      "    break",
      "if (d - target) * (lo_d - target) > 0.0:", "    lo_s = s", "    lo_d = d",
      "else:", "    hi_s = s", "    hi_d = d")
    w().dedent().dedent()


def _nonlinear_body(w: _Writer, st: Structure):
    """Newton steps; a step without a root (a law with a jump or infinite slope at contact
    onset) is retried as 2, 4, ... 2^max_split sub-steps from its start, with the ground
    acceleration interpolated linearly; recording stays on the step grid."""
    saved = _committed_arrays(st)
    for name in saved:
        w(f"save_{name} = {name}[b].copy()")
    w("for k in range(begin, end):").indent()
    w("if k == 0:").indent()
    _initial_state(w, st)
    w("continue").dedent()
    if st.events:  # several sub-steps may be committed before a failure: save every step
        for name in saved:
            w(f"save_{name}[:] = {name}[b]")
    w("split = 0", "while True:").indent()
    w("parts = 1 << split", "failed = False", "for part in range(parts):").indent()
    if st.events:
        w("pos = part / parts", "stop = (part + 1) / parts", "while pos < stop:").indent()
        # while a contact is closed, sub-steps of 1 / event_parts of the step (a sliver
        # left before the step end joins the last one)
        w("f_try = stop", "for e in range(nc):", "    if cpen_c[b, e] > 0.0:",
          "        piece = 1.0 / (parts * event_parts[b])",
          "        if pos + 1.01 * piece < stop:", "            f_try = pos + piece", "        break")
    else:
        w("pos = part / parts", "f_try = (part + 1) / parts")
    w("hs = (f_try - pos) * h")
    _constants(w, "hs")
    _interpolate_ground(w, "pos", "f_try")
    _newton(w, st)
    w("if failed:", "    break")
    if st.events:
        _event_location(w, st)
        w("if failed:", "    break")
    _commit(w, st)
    w("if failed:", "    break")
    if st.events:
        w("pos = f_try").dedent()  # while pos < stop
        w("if failed:", "    break")
    w().dedent()  # parts
    w(f"if not failed or status[b, 0] == {NOT_FINITE} or status[b, 0] == {NOT_STABLE} "
      "or split == max_split:").indent()
    w("if failed and (split > 0 or " + ("True" if st.events else "False") + "):").indent()
    for name in saved:
        w(f"{name}[b] = save_{name}")
    w().dedent()
    w("break").dedent()
    w("if split == 0:").indent()
    w("substeps[b] += 1")
    if not st.events:
        for name in saved:
            w(f"save_{name}[:] = {name}[b]")
    w().dedent()
    if st.events:
        w("if True:").indent()
    else:
        w("else:").indent()
    for name in saved:
        w(f"{name}[b] = save_{name}")
    w().dedent()
    w("for i in range(4):", "    status[b, i] = 0", "split += 1")
    w().dedent()  # while
    w("if failed:", "    break")
    _record(w, st)


def generate(st: Structure) -> str:
    """The source text of the kernel module for this structure."""
    w = _Writer()
    _header(w, st)
    if st.explicit:
        _explicit_body(w, st)
    elif st.linear:
        _linear_body(w, st)
    else:
        _nonlinear_body(w, st)
    return "\n".join(w.lines) + "\n"
