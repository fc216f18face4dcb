"""Accuracy studies: the reference against itself (self-convergence in the tolerance) and the
kernel against the reference (convergence in dt).

``python -m pframe.reference MODEL.yaml`` prints both for a scene (the numbers quoted in
``docs/reference-solution.md``).
"""

from __future__ import annotations

import time
from dataclasses import dataclass

import numpy as np

from pframe.reference.ground import of_scene
from pframe.reference.solver import solve

#: quantities compared, with their units
COMPARED = (("displacement", "m"), ("velocity", "m/s"), ("story_force", "N"),
            ("contact_force", "N"))


@dataclass
class Difference:
    """Largest differences between two runs on common output times."""

    displacement: float
    velocity: float
    story_force: float
    contact_force: float
    peak_contact_force: float

    @classmethod
    def between(cls, a, b, stride: int = 1) -> Difference:
        """a sampled every ``stride`` rows (a finer kernel run) against b."""
        def largest(x, y):
            return float(np.max(np.abs(np.asarray(x) - y), initial=0.0))

        peak_a = getattr(a, "peak_contact_force", None)
        return cls(*(largest(getattr(a, q)[::stride], getattr(b, q)) for q, _ in COMPARED),
                   largest(peak_a, b.peak_contact_force) if peak_a is not None else np.nan)


def self_convergence(plan, ground, rtols=(1e-6, 1e-8, 1e-10, 1e-12), finest: float = 1e-13,
                     method: str = "DOP853"):
    """Runs at each tolerance and at ``finest``: [(rtol, seconds, result, Difference to the
    finest run)]. Compile the laws beforehand for honest timings (the first run compiles)."""
    best = solve(plan, rtol=finest, ground=ground, method=method)
    rows = []
    for rtol in rtols:
        result = solve(plan, rtol=rtol, ground=ground, method=method)
        rows.append((rtol, result.seconds, result, Difference.between(result, best)))
    rows.append((finest, best.seconds, best, Difference.between(best, best)))
    return rows


class _KernelRun:
    """The kernel's histories as attributes, with its peak contact force (largest sample)."""

    def __init__(self, plan, result):
        self.plan = plan
        for q, _ in COMPARED:
            if q in result.history:
                setattr(self, q, result.history[q][0])
        if "contact_force" in result.history:
            self.peak_contact_force = np.max(result.history["contact_force"][0], axis=0)
        self.impacts = result.impacts[0]
        self.solve_seconds = result.solve_seconds


def with_dt(text: str, factor: int) -> str:
    """A scene's YAML text with its time step divided by ``factor`` (``analysis.dt``, or
    ``analysis.dt_tau`` of a Pi-form scene), changed on its data, not its text."""
    import yaml

    from pframe.yamltext import load

    data = load(text, "scene")
    key = "dt_tau" if "pi" in data else "dt"
    data["analysis"][key] = data["analysis"][key] / factor
    return yaml.safe_dump(data, sort_keys=False, allow_unicode=True)


def kernel_convergence(text: str, reference, factors=(1, 2, 4, 8), base_dir=None):
    """The kernel at dt / factor against the reference (run at the scene's own dt grid):
    [(factor, kernel run, Difference)]."""
    from pframe.assemble import assemble
    from pframe.kernel import simulate
    from pframe.reader import parse_scene

    rows = []
    for factor in factors:
        plan = assemble(parse_scene(with_dt(text, factor), base_dir=base_dir).expanded)
        kernel = _KernelRun(plan, simulate(plan))
        rows.append((factor, kernel, Difference.between(kernel, reference, stride=factor)))
    return rows


def main(argv=None) -> int:
    import argparse

    from pframe.assemble import assemble
    from pframe.reader import load_scene

    parser = argparse.ArgumentParser(
        prog="python -m pframe.reference",
        description="Reference solution of a scene: self-convergence in the tolerance and "
                    "the kernel's convergence in dt towards it.")
    parser.add_argument("model", help="scene YAML file")
    parser.add_argument("--factors", default="1,2,4,8",
                        help="kernel runs at dt / factor (comma separated; empty: none)")
    parser.add_argument("--methods", action="store_true",
                        help="also compare Radau, LSODA and RK45 at rtol 1e-10 with DOP853")
    args = parser.parse_args(argv)

    loaded = load_scene(args.model)
    plan = assemble(loaded.expanded)
    ground = of_scene(loaded)
    tick = time.perf_counter()
    solve(plan, rtol=1e-6, ground=ground, times=plan.times[:2])  # compile the laws
    print(f"{args.model}: {plan.n_dof} DOFs, {len(plan.story_names)} storeys, "
          f"{len(plan.contact_names)} contacts, {plan.steps} output steps; ground "
          f"{ground.description}; law compilation {time.perf_counter() - tick:.1f} s\n")

    rows = self_convergence(plan, ground)
    best = rows[-1][2]
    print(f"self-convergence (DOP853; differences to rtol {rows[-1][0]:g}):")
    print(f"{'rtol':>8} {'seconds':>8} {'steps':>6} {'events':>6} {'u (m)':>9} {'v (m/s)':>9} "
          f"{'story (N)':>9} {'contact (N)':>11} {'peak P (N)':>10}")
    for rtol, seconds, result, diff in rows:
        print(f"{rtol:8.0e} {seconds:8.1f} {result.steps:6d} {len(result.events):6d} "
              f"{diff.displacement:9.1e} {diff.velocity:9.1e} {diff.story_force:9.1e} "
              f"{diff.contact_force:11.1e} {diff.peak_contact_force:10.1e}")
    print(f"\nimpacts {best.impacts.tolist()}, peak contact force "
          f"{np.round(best.peak_contact_force, 3).tolist()} N at "
          f"{np.round(best.peak_contact_force_time, 6).tolist()} s; peak |u| "
          f"{np.abs(best.displacement).max():.6g} m")

    if args.methods:
        print("\nother methods at rtol 1e-10 against DOP853 at rtol 1e-13:")
        for method in ("Radau", "LSODA", "RK45"):
            result = solve(plan, rtol=1e-10, ground=ground, method=method)
            diff = Difference.between(result, best)
            print(f"{method:>8} {result.seconds:6.1f} s  u {diff.displacement:.1e} m  "
                  f"v {diff.velocity:.1e} m/s  peak P {diff.peak_contact_force:.1e} N")

    factors = [int(f) for f in args.factors.split(",") if f.strip()]
    if factors:
        reference = solve(plan, rtol=1e-12, ground=ground)
        print("\nkernel at dt / factor against the reference (rtol 1e-12):")
        print(f"{'factor':>6} {'u (m)':>9} {'ratio':>6} {'v (m/s)':>9} {'peak P (N)':>10} "
              f"{'impacts':>10}")
        previous = None
        for factor, kernel, diff in kernel_convergence(loaded.text, reference, factors,
                                                       loaded.base_dir):
            ratio = f"{previous / diff.displacement:6.2f}" if previous else " " * 6
            print(f"{factor:6d} {diff.displacement:9.2e} {ratio} {diff.velocity:9.2e} "
                  f"{diff.peak_contact_force:10.2e} {str(kernel.impacts.tolist()):>10}")
            previous = diff.displacement
    return 0
