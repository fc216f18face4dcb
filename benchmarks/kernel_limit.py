"""pframe's kernel against the limit: a hand-written C program of the same algorithm
(benchmarks/kernel_limit.c) on the paper's pair, per step, peaks only.

    python benchmarks/kernel_limit.py [--scene models/wu2021-eq14.yaml] [--repeats 7]
                                      [--rounds 5] [--baseline FOLDER]

The scene is models/wu2021-eq14.yaml (Wu et al. 2021 eq. 14: two 3-storey bilinear
buildings, 3 improved Kelvin contacts, Rayleigh damping on the current stiffness, Newmark's
average acceleration, 50,000 steps) with its recorders replaced by the envelopes of the
floor displacements, storey drifts and contact forces (peaks only). Its plan's numbers (the
DOF order, masses, damping, packed law parameters, ground samples, Newton's tolerances) are
written for the C program, which is compiled here with the flags ``setup.py`` gives the kernel
(``-std=c99 -O2 -ffp-contract=off -fno-fast-math``). The C program does what the kernel does
for this scene and nothing else (no energy, histories, finiteness or stability checks, batch,
sub-steps, law dispatch); its peaks must agree with the kernel's to 1e-9 (relative), checked
and printed.

Timing, side by side in one run: ``--rounds`` rounds, each the C program (best of
``--repeats`` runs in its process) then pframe's kernel (``simulate`` of the plan, one thread,
its ``solve_seconds``, best of ``--repeats``); per step, and the ratio kernel / C per round,
then its median, and the ratio of the two sides' best times over all rounds (goal: at most
1.3). On a shared machine another job slows either side at random, and only ever slows it:
the best of many runs is the side's own cost, so the ratio of the bests is the figure to
read when the per-round ratios scatter (the load average is printed with each round).

``--baseline FOLDER``: a folder of the kernel's C sources from another revision (for example
``git archive main framework/pframe/kernel/c | tar -x -C /tmp/main``, then
``--baseline /tmp/main/framework/pframe/kernel/c``), compiled here with the same flags and run
as a third side of each round (pframe.kernel.ckernel.baseline: the same interface and structs
are required), so that a change to the kernel is measured against what it changes in one
process, under the same load; its peaks are compared with the kernel's, bit for bit.
Nothing is asserted.
"""

from __future__ import annotations

import argparse
import statistics
import subprocess
import sys
import sysconfig
import tempfile
from pathlib import Path

import numpy as np
from _common import KELVIN, load_average, print_header

HERE = Path(__file__).resolve().parent
PEAKS = [{"kind": "envelope", "quantities": ["displacement", "story_drift", "contact_force"]}]
#: the flags setup.py compiles the kernel with (gcc and clang)
FLAGS = ["-std=c99", "-O2", "-ffp-contract=off", "-fno-fast-math"]


def peaks_plan(scene: Path):
    """The scene with its recorders replaced by the peaks, as a plan of one member."""
    import yaml

    from pframe.assemble import assemble
    from pframe.reader import parse_scene

    data = yaml.safe_load(scene.read_text(encoding="utf-8"))
    data["recorders"] = PEAKS
    loaded = parse_scene(yaml.safe_dump(data, sort_keys=False), base_dir=scene.parent)
    return assemble(loaded.expanded)


def write_input(plan, path: Path) -> None:
    """The numbers kernel_limit.c reads (its header says the layout), in the kernel's DOF
    order and its elements' evaluation order."""
    from pframe.kernel.plugins import law_ids
    from pframe.kernel.run import _group_model

    model, _, _ = _group_model(plan, law_ids(plan).ids)
    laws = {g.law.name for g in plan.story_groups} | {g.law.name for g in plan.contact_groups}
    if laws != {"bilinear", "improved_kelvin"} or plan.batch != 1:
        raise SystemExit(f"the C program runs bilinear storeys and improved Kelvin contacts, "
                         f"one member; the scene has {sorted(laws)}")
    c = plan.integrator
    if (c.scheme, float(c.gamma), float(c.beta), float(c.alpha_f)) != ("alpha_family", 0.5,
                                                                      0.25, 0.0):
        raise SystemExit("the C program runs Newmark's average acceleration")
    if plan.story_sides is not None and plan.story_sides.dof.size:
        raise SystemExit("the C program runs plain (planar) elements")
    s_order, c_order = model.story_order, model.contact_order
    story = model.story_params[0][s_order]
    contact = model.contact_params[0][c_order]
    with open(path, "wb") as f:
        np.array([plan.n_dof, len(s_order), len(c_order), plan.steps, plan.bandwidth,
                  plan.max_iterations], dtype=np.int64).tofile(f)
        np.array([plan.dt[0], c.gamma, c.beta, plan.tolerance, plan.absolute_tolerance],
                 dtype=float).tofile(f)
        model.mass[0].tofile(f)
        model.mass_damping[0].tofile(f)
        model.story_dofs[s_order, 0].tofile(f)
        model.story_dofs[s_order, 1].tofile(f)
        for column in range(3):  # k, yield force, alpha
            np.ascontiguousarray(story[:, column]).tofile(f)
        np.ascontiguousarray(model.story_beta[0][s_order]).tofile(f)
        model.contact_dofs[c_order, 0].tofile(f)
        model.contact_dofs[c_order, 1].tofile(f)
        np.ascontiguousarray(model.gap[0][c_order]).tofile(f)
        for column in (0, 2, 3):  # k, chi, 1 / m_eff (the exponent is 1)
            np.ascontiguousarray(contact[:, column]).tofile(f)
        np.ascontiguousarray(model.ground[0, 0, :plan.steps + 1]).tofile(f)
    return s_order, c_order


def compile_limit(folder: Path) -> Path:
    compiler = (sysconfig.get_config_var("CC") or "cc").split()[0]
    binary = folder / "kernel_limit"
    subprocess.run([compiler, *FLAGS, "-o", str(binary), str(HERE / "kernel_limit.c"), "-lm"],
                   check=True)
    return binary


def run_limit(binary: Path, data: Path, repeats: int) -> tuple[float, int, np.ndarray]:
    out = subprocess.run([str(binary), str(data), str(repeats)], check=True,
                         capture_output=True, text=True).stdout.split()
    return float(out[0]), int(out[1]), np.array([float(v) for v in out[2:]])


def compile_baseline(sources: Path, folder: Path) -> Path:
    """The kernel library of the C sources in ``sources`` (kernel.c and what it includes),
    compiled as pip compiles the installed one: Python's flags, then setup.py's."""
    compiler = (sysconfig.get_config_var("CC") or "cc").split()[0]
    python_flags = [*(sysconfig.get_config_var("CFLAGS") or "").split(),
                    *(sysconfig.get_config_var("CCSHARED") or "-fPIC").split()]
    library = folder / "baseline_kernel.so"
    subprocess.run([compiler, *python_flags, *FLAGS, "-fvisibility=hidden", "-shared", "-o",
                    str(library), str(sources / "kernel.c"), "-lm"], check=True)
    return library


def run_kernel(plan, repeats: int) -> tuple[float, object]:
    from pframe.kernel import simulate

    best, result = np.inf, None
    for _ in range(repeats):
        result = simulate(plan, threads=1)
        best = min(best, result.solve_seconds)
    return best / plan.steps * 1e9, result


def run_baseline(plan, library: Path, repeats: int) -> tuple[float, object]:
    from pframe.kernel import ckernel

    with ckernel.baseline(library):
        return run_kernel(plan, repeats)


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--scene", type=Path, default=KELVIN)
    parser.add_argument("--repeats", type=int, default=7)
    parser.add_argument("--rounds", type=int, default=5)
    parser.add_argument("--baseline", type=Path, default=None,
                        help="a folder of the kernel's C sources to run as a third side")
    args = parser.parse_args(argv)
    print_header()
    plan = peaks_plan(args.scene)
    with tempfile.TemporaryDirectory(prefix="pframe-limit-") as tmp:
        data = Path(tmp) / "scene.bin"
        s_order, c_order = write_input(plan, data)
        binary = compile_limit(Path(tmp))
        baseline = (None if args.baseline is None
                    else compile_baseline(args.baseline, Path(tmp)))
        run_kernel(plan, 1)  # the kernel loaded before the clock
        ratios, best_c, best_kernel, best_base = [], np.inf, np.inf, np.inf
        for k in range(args.rounds):
            c_ns, c_solves, c_peaks = run_limit(binary, data, args.repeats)
            k_ns, result = run_kernel(plan, args.repeats)
            ratios.append(k_ns / c_ns)
            best_c, best_kernel = min(best_c, c_ns), min(best_kernel, k_ns)
            line = (f"round {k + 1}: C {c_ns:.1f} ns/step, kernel {k_ns:.1f} ns/step, "
                    f"kernel / C {k_ns / c_ns:.2f}")
            if baseline is not None:
                base_ns, base_result = run_baseline(plan, baseline, args.repeats)
                best_base = min(best_base, base_ns)
                line += f", baseline {base_ns:.1f} ns/step"
            print(f"{line}; load average {load_average()}", flush=True)
    env = result.envelope
    ours = np.concatenate([env["displacement"][0], env["story_drift"][0][s_order],
                           env["contact_force"][0][c_order]])
    worst = float(np.max(np.abs(ours - c_peaks) / np.maximum(np.abs(c_peaks), 1e-300)))
    solves = int(result.counter("solves"))
    print(f"peaks (6 displacements, 6 drifts, 3 contact forces): largest relative difference "
          f"{worst:.2e} ({'within' if worst <= 1e-9 else 'NOT within'} 1e-9); Newton solves: "
          f"C {c_solves}, kernel {solves}")
    print(f"kernel / C per step, median of {args.rounds} rounds: "
          f"{statistics.median(ratios):.2f}; best of all rounds: kernel {best_kernel:.1f} "
          f"ns/step, C {best_c:.1f} ns/step, ratio {best_kernel / best_c:.2f} (goal: at most "
          f"1.3); {plan.steps} steps, {plan.n_dof} DOFs, {len(s_order)} storeys, "
          f"{len(c_order)} contacts")
    if baseline is not None:
        same = all(np.array_equal(env[q], base_result.envelope[q]) for q in env)
        print(f"baseline ({args.baseline}): best {best_base:.1f} ns/step, baseline / C "
              f"{best_base / best_c:.2f}, kernel / baseline {best_kernel / best_base:.3f}; "
              f"peaks {'identical' if same else 'DIFFERENT'} to the bit")
    return 0


if __name__ == "__main__":
    sys.exit(main())
