"""What writing the results costs, side by side in one run: the kernel's time against the file
(plain and deflated), the in-memory Dataset of ``pframe.solve``, and the whole ``pframe solve``
command, for the paper's example (50,000 steps, five histories).

    python benchmarks/result_files.py [--repeat 5]

Prints medians and ratios. With ``--against PATH`` (a checkout of another pframe version, its
``framework`` folder) the whole command is also timed with that version, interleaved with this
one, so both see the same machine load.
"""

from __future__ import annotations

import argparse
import os
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
SCENE = ROOT / "models" / "wu2021-eq14.yaml"


def _median(times: list[float]) -> float:
    return statistics.median(times)


def in_process(repeat: int, folder: Path) -> dict[str, float]:
    import pframe
    from pframe.api import loaded_scene
    from pframe.assemble import assemble
    from pframe.kernel import simulate
    from pframe.record import write_result

    loaded = loaded_scene(SCENE)
    plan = assemble(loaded.expanded)
    simulate(plan)  # load the kernel
    out: dict[str, list[float]] = {"kernel": [], "file": [], "file, --compress": [],
                                   "pframe.solve (Dataset in memory)": []}
    sizes = {}
    for i in range(repeat):
        start = time.perf_counter()
        result = simulate(plan)
        out["kernel"].append(time.perf_counter() - start)
        for key, compress in (("file", False), ("file, --compress", True)):
            path = folder / f"{i}-{compress}.nc"
            start = time.perf_counter()
            write_result(path, result, loaded, compress=compress)
            out[key].append(time.perf_counter() - start)
            sizes[key] = path.stat().st_size
            path.unlink()
        start = time.perf_counter()
        pframe.solve(loaded, progress=False)
        out["pframe.solve (Dataset in memory)"].append(time.perf_counter() - start)
    medians = {k: _median(v) for k, v in out.items()}
    kernel = medians["kernel"]
    print(f"paper's example, {plan.steps} steps, median of {repeat}:")
    for key, value in medians.items():
        size = f", {sizes[key] / 1e6:.1f} MB" if key in sizes else ""
        print(f"  {key:36s} {value * 1e3:8.1f} ms  ({value / kernel:5.2f} x the kernel){size}")
    return medians


def whole_command(repeat: int, folder: Path, against: Path | None) -> None:
    script = Path(sys.executable).with_name("pframe")
    versions = {"this version": None} | ({f"{against}": against} if against else {})
    times: dict[str, list[float]] = {name: [] for name in versions}
    for i in range(repeat):
        for name, framework in versions.items():  # interleaved: the same load for both
            env = dict(os.environ)
            if framework is not None:
                env["PYTHONPATH"] = str(framework)
            out = folder / f"cmd-{i}.{'nc' if framework is None else 'h5'}"
            start = time.perf_counter()
            subprocess.run([str(script), "solve", str(SCENE), "-o", str(out), "-q"],
                           check=True, env=env)
            times[name].append(time.perf_counter() - start)
            out.unlink()
    base = _median(times["this version"])
    print(f"whole `pframe solve` command (process start to exit), median of {repeat}:")
    for name, values in times.items():
        print(f"  {name:36s} {_median(values):8.3f} s  ({_median(values) / base:5.2f} x this "
              "version)")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeat", type=int, default=5)
    parser.add_argument("--against", type=Path, help="another version's framework folder")
    args = parser.parse_args()
    with tempfile.TemporaryDirectory() as folder:
        in_process(args.repeat, Path(folder))
        whole_command(args.repeat, Path(folder), args.against)


if __name__ == "__main__":
    main()
