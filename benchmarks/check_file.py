"""What the damage check before reading a result costs (``pframe.record.check.check_file``,
run by ``pframe.open`` and ``pframe plot``), side by side in one run: the check against
xarray's lazy open of the same file and against reading its histories, for the paper's
example (50,000 steps) and the same scene run 40 times longer (2,000,000 steps, streamed).

    python benchmarks/check_file.py [--repeat 5]

Prints medians and ratios; nothing is asserted.
"""

from __future__ import annotations

import argparse
import statistics
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(Path(__file__).resolve().parent))

from _common import print_header, scene_copy  # noqa: E402

SCENE = ROOT / "models" / "wu2021-eq14.yaml"


def _timed(action, repeat: int) -> float:
    times = []
    for _ in range(repeat):
        start = time.perf_counter()
        action()
        times.append(time.perf_counter() - start)
    return statistics.median(times)


def measure(path: Path, repeat: int) -> dict[str, float]:
    import xarray as xr

    from pframe.record.check import check_file

    def lazy():
        xr.open_dataset(path, engine="h5netcdf").close()

    def histories():
        with xr.open_dataset(path, engine="h5netcdf") as ds:
            ds["displacement"].values  # noqa: B018 - the read is the point

    return {"check_file": _timed(lambda: check_file(path), repeat),
            "xarray lazy open": _timed(lazy, repeat),
            "read displacement": _timed(histories, repeat)}


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeat", type=int, default=5)
    args = parser.parse_args()
    print_header()
    from pframe.cli import main as pframe

    with tempfile.TemporaryDirectory() as folder:
        folder = Path(folder)
        short = folder / "eq14.nc"
        assert pframe(["solve", str(SCENE), "-o", str(short), "-q"]) == 0
        scene = scene_copy(SCENE, folder, steps=2_000_000)
        long = folder / "long.nc"
        assert pframe(["solve", str(scene), "-o", str(long), "-q"]) == 0
        for name, path in (("50,000 steps", short), ("2,000,000 steps", long)):
            times = measure(path, args.repeat)
            size = path.stat().st_size / 2**20
            print(f"{name} ({size:.0f} MiB), median of {args.repeat}:")
            base = times["xarray lazy open"]
            for key, value in times.items():
                print(f"  {key:<20} {value * 1e3:9.2f} ms   {value / base:6.2f} x the lazy open")


if __name__ == "__main__":
    main()
