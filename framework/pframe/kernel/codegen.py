"""Writes the source of a time-stepping kernel that holds only what one scene needs.

The kernel is Newmark's method with full Newton iterations. From the plan's *structure*
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

FORMAT_VERSION = "2"

#: status codes written by the kernel into status[b, 0]
OK, NOT_CONVERGED, NOT_FINITE, NOT_DEFINITE = 0, 1, 2, 3
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

    @classmethod
    def of(cls, plan: Plan) -> Structure:
        return cls(
            story_laws=tuple(g.law for g in plan.story_groups),
            contact_laws=tuple(g.law for g in plan.contact_groups),
            linear=plan.linear,
            damping_modes=tuple(sorted(set(int(c) for c in plan.story_damping_stiffness))),
            history=tuple(q for q, _ in plan.history),
            envelope=plan.envelope,
        )

    def key(self) -> str:
        """A hash of the structure and of the source of every law it calls."""
        parts = [FORMAT_VERSION, repr(self.linear), repr(self.damping_modes),
                 repr(self.history), repr(self.envelope)]
        for law in self.story_laws + self.contact_laws:
            parts.append(f"{law.__module__}.{law.__qualname__}")
            parts.append(inspect.getsource(law.force))
        from pframe import __version__
        from pframe.kernel import banded

        parts += [__version__, inspect.getsource(banded), inspect.getsource(inspect.getmodule(generate))]
        return hashlib.sha256("\n".join(parts).encode()).hexdigest()[:20]


def argument_names(structure: Structure) -> list[str]:
    names = ["begin", "end", "dt", "gamma", "beta", "tol", "atol", "max_iter", "bw",
             "mass", "mdamp", "story_dofs", "k0", "sbeta", "dmode"]
    for g in range(len(structure.story_laws)):
        names += [f"sp{g}", f"sx{g}", f"sc{g}", f"st{g}"]
    names += ["contact_dofs", "gap"]
    for g in range(len(structure.contact_laws)):
        names += [f"cp{g}", f"cx{g}", f"cc{g}", f"ct{g}"]
    names += ["ag", "U", "V", "A", "drift_c", "sforce_c", "sdamp_c", "stan_c",
              "cforce_c", "cpen_c", "impacts", "energy", "status", "iterations",
              "substeps", "max_split"]
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


def _evaluate(w: _Writer, st: Structure):
    """Forces, residual R and (nonlinear) tangent band at (u_new, v_new, a_new)."""
    nonlinear = not st.linear
    w("for i in range(n):")
    w("    R[i] = -mass[b, i] * (ag_new + a_new[i]) - mdamp[b, i] * v_new[i]")
    if nonlinear:
        w("    for d in range(bw + 1):", "        band[i, d] = 0.0",
          "    band[i, 0] = mass[b, i] * c0 + mdamp[b, i] * c1")
    for g, _ in enumerate(st.story_laws):
        w(f"for j in range(sx{g}.shape[0]):").indent()
        w(f"e = sx{g}[j]", "lo = story_dofs[e, 0]", "up = story_dofs[e, 1]",
          "d = u_new[up]", "r = v_new[up]", "if lo >= 0:",
          "    d -= u_new[lo]", "    r -= v_new[lo]",
          f"f, kt, kr = slaw{g}(sp{g}[b, j], sc{g}[b, j], st{g}[b, j], d, r)")
        if st.damping_modes == (0,):
            w("kd = k0[b, e]")
        else:
            w("kd = k0[b, e]", "if dmode[e] == 1:", "    kd = kt",
              "elif dmode[e] == 2:", "    kd = stan_c[b, e]")
        w("fd = sbeta[b, e] * kd * r", "drift_t[e] = d", "sforce_t[e] = f", "sdamp_t[e] = fd",
          "stan_t[e] = kt", "R[up] -= f + fd", "if lo >= 0:", "    R[lo] += f + fd")
        if nonlinear:
            w("kk = kt + c1 * (kr + sbeta[b, e] * kd)", "band[up, 0] += kk", "if lo >= 0:",
              "    band[lo, 0] += kk", "    band[max(lo, up), abs(lo - up)] -= kk")
        w().dedent()
    for g, _ in enumerate(st.contact_laws):
        w(f"for j in range(cx{g}.shape[0]):").indent()
        w(f"e = cx{g}[j]", "lft = contact_dofs[e, 0]", "rgt = contact_dofs[e, 1]",
          "d = u_new[lft] - u_new[rgt] - gap[b, e]", "r = v_new[lft] - v_new[rgt]",
          f"f, kd_, kr = claw{g}(cp{g}[b, j], cc{g}[b, j], ct{g}[b, j], d, r)",
          "cforce_t[e] = f", "cpen_t[e] = d", "R[lft] -= f", "R[rgt] += f",
          "kk = kd_ + c1 * kr", "band[lft, 0] += kk", "band[rgt, 0] += kk",
          "band[max(lft, rgt), abs(lft - rgt)] -= kk")
        w().dedent()


def _fail(w: _Writer, code: str, kind: str, index: str):
    w(f"status[b, 0] = {code}", "status[b, 1] = k", f"status[b, 2] = {kind}",
      f"status[b, 3] = {index}", "failed = True", "break")


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


def _commit(w: _Writer, st: Structure):
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
    w("kinetic = 0.0", "for i in range(n):", "    U[b, i] = u_new[i]", "    V[b, i] = v_new[i]",
      "    A[b, i] = a_new[i]", "    kinetic += 0.5 * mass[b, i] * v_new[i] * v_new[i]",
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
      f"c4 = {h} * (1.0 - gamma)", f"c5 = {h} * gamma", "inv_c0_mmin = 1.0 / (c0 * mass[b].min())")


def _newton(w: _Writer, st: Structure):
    """Iterate one (sub-)step to equilibrium at load ag_new; on failure set failed/break."""
    w("for i in range(n):", "    u_new[i] = U[b, i]", "converged = False")
    w("for it in range(max_iter + 1):").indent()
    w("if k == 0:", "    for i in range(n):", "        v_new[i] = V[b, i]", "        a_new[i] = 0.0",
      "else:", "    for i in range(n):",
      "        a_new[i] = c0 * (u_new[i] - U[b, i]) - c2 * V[b, i] - c3 * A[b, i]",
      "        v_new[i] = V[b, i] + c4 * A[b, i] + c5 * a_new[i]")
    _evaluate(w, st)
    _finite_check(w, st)
    w("if k == 0:", "    for i in range(n):", "        a_new[i] = R[i] / mass[b, i]", "    break")
    if not st.linear:
        # The next increment du = K^-1 R is bounded by |R| / (c0 min m) while the tangents are
        # not negative. When that bound is a thousandth of the tolerance the correction is
        # negligible (a step whose laws stayed on one branch: R is round-off), so skip it;
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
        w("if not ldl_factor(band, bw):").indent()
        _fail(w, str(NOT_DEFINITE), str(NODE), "0")
        w().dedent()
    w("ldl_solve(band, bw, R)", "iterations[b] += 1")
    if st.linear:
        w("for i in range(n):", "    u_new[i] += R[i]", "converged = True")
    else:
        w("norm_du = 0.0", "norm_u = 0.0", "for i in range(n):", "    u_new[i] += R[i]",
          "    norm_du += R[i] * R[i]", "    norm_u += u_new[i] * u_new[i]",
          "converged = np.sqrt(norm_du) <= tol * np.sqrt(norm_u) + atol")
    w().dedent()  # Newton loop


def generate(st: Structure) -> str:
    """The source text of the kernel module for this structure."""
    w = _Writer()
    w('"""Generated by pframe.kernel.codegen; do not edit (regenerated when pframe changes)."""',
      "import numba", "import numpy as np",
      "from pframe.kernel.banded import ldl_factor, ldl_solve")
    _law_imports(w, st.story_laws, "slaw")
    _law_imports(w, st.contact_laws, "claw")
    w("", "", "@numba.njit(cache=True, parallel=False, nogil=True)",
      f"def kernel({', '.join(argument_names(st))}):").indent()
    w("nb = mass.shape[0]", "n = mass.shape[1]", "ns = story_dofs.shape[0]",
      "nc = contact_dofs.shape[0]", "c3 = 0.5 / beta - 1.0",
      "for b in range(nb):").indent()
    w("if status[b, 0] != 0:", "    continue", "h = dt[b]")
    _constants(w, "h")
    w("norm_u = 0.0",
      "u_new = np.empty(n)", "v_new = np.empty(n)", "a_new = np.empty(n)", "R = np.empty(n)",
      "band = np.zeros((n, bw + 1))",
      "drift_t = np.zeros(ns)", "sforce_t = np.zeros(ns)", "sdamp_t = np.zeros(ns)",
      "stan_t = np.zeros(ns)", "cforce_t = np.zeros(nc)", "cpen_t = np.zeros(nc)")
    if st.linear:
        w("# linear scene: the effective stiffness is constant, factor it once",
          "for i in range(n):", "    band[i, 0] = mass[b, i] * c0 + mdamp[b, i] * c1",
          "for e in range(ns):",
          "    lo = story_dofs[e, 0]", "    up = story_dofs[e, 1]",
          "    kk = k0[b, e] * (1.0 + c1 * sbeta[b, e])", "    band[up, 0] += kk",
          "    if lo >= 0:", "        band[lo, 0] += kk",
          "        band[max(lo, up), abs(lo - up)] -= kk",
          "if not ldl_factor(band, bw):", f"    status[b, 0] = {NOT_DEFINITE}",
          "    status[b, 1] = begin", "    continue",
          "failed = False", "for k in range(begin, end):").indent()
        w("ag_old = ag[b, k - 1] if k > 0 else 0.0", "ag_new = ag[b, k]")
        _newton(w, st)
        w("if failed:", "    break")
        _commit(w, st)
        _record(w, st)
        w().dedent().dedent().dedent()
        return "\n".join(w.lines) + "\n"

    # Nonlinear scene: a step whose Newton iteration fails (a contact law with a jump or an
    # infinite slope at onset can leave the discrete step without a root) is retried as 2, 4,
    # ... 2^max_split sub-steps from the state at the start of the step, with the ground
    # acceleration interpolated linearly. Recording stays on the step grid.
    saved = _committed_arrays(st)
    for name in saved:
        w(f"save_{name} = {name}[b].copy()")
    w("failed = False", "for k in range(begin, end):").indent()
    w("split = 0", "while True:").indent()
    w("parts = 1 << split", "hs = h / parts")
    w("if split > 0:").indent()
    _constants(w, "hs")
    w().dedent()
    w("failed = False", "for part in range(parts):").indent()
    w("if k == 0:", "    ag_old = 0.0", "    ag_new = ag[b, 0]", "else:",
      "    ag_old = ag[b, k - 1] + (ag[b, k] - ag[b, k - 1]) * part / parts",
      "    ag_new = ag[b, k - 1] + (ag[b, k] - ag[b, k - 1]) * (part + 1) / parts")
    _newton(w, st)
    w("if failed:", "    break")
    _commit(w, st)
    w().dedent()  # parts
    w(f"if not failed or status[b, 0] == {NOT_FINITE} or split == max_split or k == 0:").indent()
    w("if failed and split > 0:").indent()  # leave the state of the last completed step
    for name in saved:
        w(f"{name}[b] = save_{name}")
    w().dedent()
    w("break").dedent()
    w("if split == 0:").indent()
    w("substeps[b] += 1")
    for name in saved:
        w(f"save_{name}[:] = {name}[b]")
    w().dedent()
    w("else:").indent()
    for name in saved:
        w(f"{name}[b] = save_{name}")
    w().dedent()
    w("for i in range(4):", "    status[b, i] = 0", "split += 1")
    w().dedent()  # while
    w("if split > 0:").indent()
    _constants(w, "h")
    w().dedent()
    w("if failed:", "    break")
    _record(w, st)
    w().dedent().dedent().dedent()
    return "\n".join(w.lines) + "\n"
