"""Accuracy against run time: every integrator on a ladder of time steps, measured against the
reference solution (:mod:`pframe.reference`), as ``pframe accuracy`` prints and plots it."""

from __future__ import annotations

import csv
import math
from dataclasses import asdict, dataclass
from pathlib import Path

import numpy as np

from pframe.errors import InputError
from pframe.integrators import TABLE

#: integrators compared by default: every integrator of pframe.integrators' table at its
#: defaults, and Newmark with event location: name -> the YAML ``analysis.integrator`` mapping
INTEGRATORS = {"newmark": {"type": "newmark"}, "newmark+events": {"type": "newmark", "events": True},
               **{name: {"type": name} for name in TABLE if name != "newmark"}}
FACTORS = (4.0, 2.0, 1.0, 0.5, 0.25)
TOLERANCES = (1e-2, 1e-3, 1e-4)


@dataclass
class Row:
    """One run: errors relative to the reference's peaks; NaN where it did not complete."""

    integrator: str
    dt: float
    steps: int
    solve_seconds: float
    displacement_error: float
    peak_contact_force_error: float
    impacts: int
    reference_impacts: int
    energy_balance_error: float
    status: str


def _variant(loaded, integrator: dict, dt: float):
    from pframe.reader import variant

    def change(data):
        data["analysis"]["integrator"] = integrator
        data["analysis"]["dt"] = dt
        data["recorders"] = [{"kind": "history", "quantities": ["displacement"]},
                             {"kind": "envelope", "quantities": ["contact_force"]}]

    return variant(loaded, change)


def check_factors(factors, loaded) -> None:
    """Factors must be positive powers of two, the largest dividing the scene's steps."""
    for f in factors:
        if not (math.isfinite(f) and f > 0) or abs(math.log2(f) - round(math.log2(f))) > 1e-12:
            raise InputError(f"dt factors must be powers of two, got {f:g}")
    steps0 = loaded.expanded.steps
    if steps0 % round(max(factors)) != 0:
        raise InputError(f"the scene's {steps0} steps are not divisible by the largest dt "
                         f"factor {max(factors):g}")


def study(loaded, integrators: dict | None = None, factors=FACTORS, repeats: int = 3,
          progress=None):
    """Rows for every integrator and dt = factor * the scene's dt, and the reference.

    Errors are taken on the grid of the coarsest step (factors must be powers of two and the
    scene's step count divisible by the largest): displacement error is the largest
    |u - u_ref| over nodes and those times over the peak |u_ref|; the peak contact force error
    compares each contact's recorded peak with the reference's located one.
    """
    from pframe.assemble import assemble
    from pframe.kernel import simulate
    from pframe.reference import of_scene, solve

    integrators = integrators or INTEGRATORS
    base = assemble(loaded.expanded)
    dt0, steps0 = float(base.dt[0]), base.steps
    coarsest = max(factors)
    check_factors(factors, loaded)
    grid = np.arange(steps0 // round(coarsest) + 1) * dt0 * coarsest
    ground = of_scene(loaded)  # the function whose samples every plan below applies
    _check_same_motion(ground, base)
    reference = solve(base, ground=ground, times=grid)
    u_ref = reference.displacement
    u_scale = np.max(np.abs(u_ref))
    f_ref = reference.peak_contact_force
    rows = []
    for name, integrator in integrators.items():
        for f in factors:
            dt = dt0 * f
            try:
                plan = assemble(_variant(loaded, integrator, dt).expanded)
            except InputError as exc:
                rows.append(Row(name, dt, round(steps0 / f), math.nan, math.nan, math.nan, 0,
                                int(reference.impacts.sum()), math.nan,
                                f"refused: {str(exc).split(':', 2)[-1].strip()[:80]}"))
                continue
            _check_same_motion(ground, plan)
            best = math.inf
            for _ in range(repeats):
                result = simulate(plan)
                best = min(best, result.solve_seconds)
            stride = round(coarsest / f)
            status = "completed" if result.completed(0) else result.describe_failure(0)
            if result.completed(0):
                u = result.history["displacement"][0][::stride]
                disp = float(np.max(np.abs(u - u_ref)) / u_scale)
                peaks = result.envelope["contact_force"][0] if f_ref.size else np.zeros(0)
                force = (float(np.max(np.abs(peaks - f_ref)) / np.max(f_ref))
                         if f_ref.size and np.max(f_ref) > 0 else 0.0)
            else:
                disp = force = math.nan
            rows.append(Row(name, dt, plan.steps, best, disp, force, int(result.impacts[0].sum()),
                            int(reference.impacts.sum()), result.energy_error(0), status))
            if progress is not None:
                progress(rows[-1])
    return rows, reference


def _check_same_motion(ground, plan) -> None:
    """The reference integrates the motion the run applies: the plan's samples are the
    reference's ground at the plan's times (one definition, pframe.excitation.sample.motion);
    anything else is a bug of pframe, not of the scene."""
    times = np.arange(plan.steps + 1) * float(plan.dt[0])
    applied = plan.ground_acceleration[0]
    scale = max(float(np.max(np.abs(applied), initial=0.0)), 1e-300)
    gap = float(np.max(np.abs(np.asarray(ground(times)) - applied), initial=0.0))
    if gap > 1e-12 * scale:
        raise RuntimeError(f"the reference's ground motion ({ground.description}) differs "
                           f"from the run's by {gap / scale:.2e} of its peak: the accuracy "
                           "study would measure the wrong problem")


def recommend(rows, tolerances=TOLERANCES) -> list[tuple[float, Row | None]]:
    """For each tolerance on the displacement error, the fastest run that meets it with the
    reference's impact count (None when no run does)."""
    out = []
    for tol in tolerances:
        fit = [r for r in rows if r.displacement_error <= tol and r.impacts == r.reference_impacts]
        out.append((tol, min(fit, key=lambda r: r.solve_seconds) if fit else None))
    return out


def write_csv(rows, path) -> None:
    from pframe import outputs

    with outputs.replacing(path) as tmp, open(tmp, "w", newline="") as handle:
        writer = csv.DictWriter(handle, fieldnames=list(asdict(rows[0])))
        writer.writeheader()
        for row in rows:
            writer.writerow(asdict(row))


def table(rows) -> str:
    lines = [f"{'integrator':<20} {'dt (s)':>10} {'solve (s)':>10} {'disp err':>9} "
             f"{'peak F err':>10} {'impacts':>8} {'energy err':>10}  status"]
    for r in rows:
        lines.append(f"{r.integrator:<20} {r.dt:>10.4g} {r.solve_seconds:>10.4f} "
                     f"{r.displacement_error:>9.2e} {r.peak_contact_force_error:>10.2e} "
                     f"{f'{r.impacts}/{r.reference_impacts}':>8} {r.energy_balance_error:>10.2e}"
                     f"  {r.status}")
    return "\n".join(lines)


def plot(rows, path, title: str = "") -> None:
    """Work-precision diagram: displacement error against solve time, log-log."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(7, 5), dpi=110)
    for name in dict.fromkeys(r.integrator for r in rows):
        pts = [r for r in rows if r.integrator == name and np.isfinite(r.displacement_error)]
        if not pts:
            continue
        ax.loglog([r.solve_seconds for r in pts], [r.displacement_error for r in pts], "o-",
                  label=name)
        for r in pts:
            ax.annotate(f"{r.dt:.2g}", (r.solve_seconds, r.displacement_error), fontsize=7,
                        textcoords="offset points", xytext=(3, 3))
    ax.set_xlabel("kernel solve time (s)")
    ax.set_ylabel("displacement error / peak displacement")
    ax.set_title(title or "work-precision (labels: dt in s)")
    ax.grid(True, which="both", alpha=0.3)
    ax.legend()
    fig.tight_layout()
    from pframe import outputs

    with outputs.replacing(path) as tmp:
        fig.savefig(tmp, format=Path(path).suffix.lstrip(".") or "png")
    plt.close(fig)
