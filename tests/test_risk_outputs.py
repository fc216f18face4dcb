"""What comes after a risk study (docs/risk.md): each limit state's probability over a design
life, and the demands handed to pelicun (FEMA P-58 losses).

The probability in T years of a Poisson process of rate lambda, 1 - exp(-lambda T), against
the hazard maps' "10 % in 50 years" (the 475-year return period); the file's storey-by-storey
demands against its per-building peaks; pelicun's demand table against the file it came
from, and, where pelicun is installed (in this Python, in .venv/pelicun or in the Python
``PELICUN_PYTHON`` names: pelicun pins its own pandas and scipy, so the README and CI keep it
in a venv of its own), against what pelicun reads back from it."""

from __future__ import annotations

import math
import os
import shutil
import subprocess
from pathlib import Path

import numpy as np
import pytest

from pframe.cli import main
from pframe.errors import InputError
from pframe.risk import demand_table, export_pelicun, probability_in_years

REPO = Path(__file__).resolve().parents[1]


def test_ten_percent_in_fifty_years_is_the_475_year_return_period():
    """A hazard map's 10 % in 50 years is the return period -50 / ln(0.9) = 474.6 years."""
    assert probability_in_years(1 / 474.56, 50) == pytest.approx(0.10, rel=1e-4)
    assert probability_in_years(1 / 2475, 50) == pytest.approx(0.0200, rel=1e-3)  # 2 % in 50
    rates = np.array([0.0, 1e-9, 1e-3, 1.0, np.nan])
    p = probability_in_years(rates, 50)
    assert p[0] == 0 and p[1] == pytest.approx(5e-8, rel=1e-8)  # no cancellation at 1e-9
    assert p[3] == pytest.approx(1 - math.exp(-50)) and math.isnan(p[4])
    for years in (0, -1, math.inf, "50"):
        with pytest.raises(InputError, match="years"):
            probability_in_years(1e-3, years)
    with pytest.raises(InputError, match="negative"):
        probability_in_years(-1e-3, 50)


def _study(folder: Path, **extra) -> Path:
    """The paper's pair under a pulse, its storeys 3 m high, over eight stochastic motions at
    six levels of PGA (runs with and without contacts)."""
    import yaml

    text = (REPO / "models" / "wu2021-pulse.yaml").read_text()
    scene = folder / "pair-heights.yaml"
    scene.write_text(text.replace("    floors: 3\n", "    floors: 3\n    height: 3.0\n"))
    assert scene.read_text().count("height: 3.0") == 2
    study = {"scene": str(scene), "measure": "pga",
             "stochastic": {"model": "clough_penzien", "intensity": 0.02,
                            "ground_frequency": 15.0, "ground_damping": 0.6, "duration": 4.0,
                            "step": 0.01, "realisations": 8, "seed": 3},
             "design": {"kind": "msa", "levels": [0.2, 0.4, 0.6, 0.8, 1.0, 1.3]},
             "dt": 0.002, "bootstrap": 0,
             "limits": {"drift_ratio": {"IO": 0.005, "LS": 0.01}},
             "hazard": {"power_law": {"k0": 1e-4, "k": 2.5}}, **extra}
    path = folder / "study.yaml"
    path.write_text(yaml.safe_dump(study))
    return path


@pytest.fixture(scope="module")
def study(tmp_path_factory):
    import pframe

    folder = tmp_path_factory.mktemp("outputs")
    out = folder / "risk.nc"
    assert main(["risk", str(_study(folder)), "-o", str(out), "-q", "--threads", "2"]) == 0
    with pframe.open(out) as opened:
        return opened.load(), folder


@pytest.mark.slow
def test_each_limit_state_has_its_probability_over_the_design_life(study, capsys):
    from pframe.risk.output import summary

    ds, _ = study
    assert float(ds.attrs["design_life"]) == 50.0
    assert np.isfinite(ds.annual_frequency.sel(limit="LS").values).all()  # fitted; not all are
    for end in ("", "_low", "_high"):
        np.testing.assert_allclose(ds[f"probability_in_design_life{end}"].values,
                                   1 - np.exp(-50 * ds[f"annual_frequency{end}"].values),
                                   rtol=1e-12)
    assert ds.probability_in_design_life.attrs["units"] == "1"
    text = summary(ds)
    assert "P 50 yr" in text and "Poisson" in text
    ls = float(ds.probability_in_design_life.sel(limit="LS", condition="with_pounding"))
    assert f"{100 * ls:.3g} %" in text


@pytest.mark.slow
def test_a_study_sets_its_own_design_life(tmp_path):
    out = tmp_path / "risk.nc"
    path = _study(tmp_path, design_life=100, pounding_runs=False)
    assert main(["risk", str(path), "-o", str(out), "-q", "--threads", "2"]) == 0
    import pframe

    with pframe.open(out) as ds:
        assert float(ds.attrs["design_life"]) == 100.0
        assert np.isfinite(float(ds.probability_in_design_life.sel(
            limit="LS", condition="without_pounding")))
        np.testing.assert_allclose(ds.probability_in_design_life.values,
                                   -np.expm1(-100 * ds.annual_frequency.values), rtol=1e-12)
    path = _study(tmp_path, design_life=0)
    assert main(["risk", str(path), "-o", str(tmp_path / "no.nc"), "-q"]) == 2
    assert not (tmp_path / "no.nc").exists()


@pytest.mark.slow
def test_storey_demands_are_the_building_peaks_storey_by_storey(study):
    """The largest of a building's storey drift ratios is its peak drift ratio; the largest
    of its floors' accelerations its peak floor acceleration; the ground's peak is the level
    (PGA scaled on the motion's own samples: the runs without contacts on a step that
    divides the motion's, those with contacts resampled on the scene's finer step)."""
    ds, _ = study
    for b in ds.building.values:
        stories = ds.story_building.values == b
        floors = ds.node_building.values == b
        np.testing.assert_allclose(
            ds.story_peak_drift_ratio.isel(story=stories).max("story").values,
            ds.peak_story_drift_ratio.sel(building=b).values, rtol=1e-12)
        np.testing.assert_allclose(
            ds.node_peak_absolute_acceleration.isel(node=floors).max("node").values,
            ds.peak_floor_acceleration.sel(building=b).values, rtol=1e-12)
    assert list(ds.story_location.values) == [1, 2, 3, 1, 2, 3]
    level = np.broadcast_to(ds.level.values, ds.intensity.shape)
    free = ds.peak_ground_acceleration.sel(condition="without_pounding").values
    np.testing.assert_allclose(free, level, rtol=1e-9)
    hit = ds.peak_ground_acceleration.sel(condition="with_pounding").values
    assert np.all(hit <= level * (1 + 1e-9)) and np.all(hit > 0.98 * level)


@pytest.mark.slow
def test_pelicun_table_holds_the_file_demands(study):
    ds, folder = study
    table, units = demand_table(folder / "risk.nc", building="B")
    assert list(table.columns) == ["1-PFA-0-1", "1-PFA-1-1", "1-PFA-2-1", "1-PFA-3-1",
                                   "1-PID-1-1", "1-PID-2-1", "1-PID-3-1", "1-ERROR"]
    assert units["1-PFA-2-1"] == "g" and units["1-PID-3-1"] == "rad"
    runs = ds.sel(condition="with_pounding")
    assert len(table) == runs.complete.size == 48
    # row k is record k // 6 at level k % 6 (record-major)
    np.testing.assert_array_equal(
        table["1-PID-2-1"].values, runs.story_peak_drift_ratio.sel(story="B/2").values.ravel())
    np.testing.assert_array_equal(
        table["1-PFA-3-1"].values,
        runs.node_peak_absolute_acceleration.sel(node="B/3").values.ravel())
    assert (table["1-ERROR"] == 0).all()
    stripe, _ = demand_table(ds, building="B", condition="without_pounding", level=0.6)
    assert len(stripe) == 8
    np.testing.assert_allclose(stripe["1-PFA-0-1"].values, 0.6, rtol=1e-9)
    failed = ds.copy(deep=True)
    failed["complete"].loc[dict(condition="with_pounding")] = np.where(
        np.arange(48).reshape(8, 6) == 7, 0, 1)  # record 2 at level 2 failed
    with pytest.warns(UserWarning, match="1 of 48 runs failed"):
        table, _ = demand_table(failed, building="B")
    assert list(np.flatnonzero(table["1-ERROR"].values)) == [7]
    assert table.iloc[7, :-1].isna().all() and not table.iloc[6, :-1].isna().any()
    bare = ds.copy(deep=True)
    bare["story_peak_drift_ratio"][:] = np.nan  # a scene without storey heights
    with pytest.raises(InputError, match="no height"):
        demand_table(bare, building="A")
    for kwargs, says in (({}, "name the one"), ({"building": "C"}, "no building 'C'"),
                         ({"building": "A", "level": 0.5}, "has the levels"),
                         ({"building": "A", "condition": "wet"}, "with_pounding or")):
        with pytest.raises(InputError, match=says):
            demand_table(ds, **kwargs)


@pytest.mark.slow
def test_pframe_export_pelicun_never_replaces_a_file_unasked(study, tmp_path, capsys):
    _, folder = study
    result = str(folder / "risk.nc")
    edp = tmp_path / "edp.csv"
    assert main(["export", result, "--pelicun", str(edp), "--building", "A"]) == 0
    lines = edp.read_text().splitlines()
    assert lines[0].startswith(",1-PFA-0-1,") and lines[1].startswith("Units,g,")
    assert len(lines) == 2 + 48
    edp.write_text("mine\n")
    capsys.readouterr()
    assert main(["export", result, "--pelicun", str(edp), "--building", "A"]) == 2
    err = capsys.readouterr().err
    assert "--overwrite" in err and "-o" not in err.split("--overwrite")[1]
    assert edp.read_text() == "mine\n"
    assert main(["export", result, "--pelicun", str(edp), "--building", "A",
                 "--overwrite"]) == 0
    assert edp.read_text().startswith(",1-PFA-0-1")
    assert main(["export", result, "--pelicun", result, "--building", "A",
                 "--overwrite"]) == 2  # never the result itself
    assert main(["export", result, "--csv", str(tmp_path), "--building", "A"]) == 2
    assert main(["export", result]) == 2
    with pytest.raises(InputError, match="overwrite=True"):
        export_pelicun(result, edp, building="A")


#: where the README and .ci/run put pelicun's own environment
PELICUN_VENV = REPO / ".venv" / "pelicun" / "bin" / "python"


def _pelicun_python() -> str | None:
    """A Python that imports pelicun: this one, the one ``PELICUN_PYTHON`` names, or
    :data:`PELICUN_VENV`'s."""
    import importlib.util
    import sys

    if importlib.util.find_spec("pelicun") is not None:
        return sys.executable
    for other in (os.environ.get("PELICUN_PYTHON"), str(PELICUN_VENV)):
        if other and shutil.which(other) and subprocess.run(
                [other, "-c", "import importlib.util, sys; "
                 "sys.exit(importlib.util.find_spec('pelicun') is None)"],
                capture_output=True).returncode == 0:
            return other
    return None


_READ_BACK = """
import sys
from pelicun.assessment import Assessment
a = Assessment({"PrintLog": False, "Seed": 1})
a.demand.load_sample(sys.argv[1])
a.demand.save_sample(sys.argv[2])
"""


@pytest.mark.slow
@pytest.mark.skipif(_pelicun_python() is None, reason="pelicun is not installed here, nor "
                    "in .venv/pelicun, and PELICUN_PYTHON names no Python that has it (python3 "
                    "-m venv .venv/pelicun && .venv/pelicun/bin/pip install pelicun, as the "
                    "README and .ci/run do)")
def test_pelicun_reads_the_table_back(study, tmp_path):
    """pelicun's DemandModel loads the table and saves the same demands in the same units,
    columns (type, location, direction) as FEMA P-58 numbers them."""
    import pandas as pd

    _, folder = study
    edp = export_pelicun(folder / "risk.nc", tmp_path / "edp.csv", building="A", level=0.8)
    back = tmp_path / "back.csv"
    subprocess.run([_pelicun_python(), "-c", _READ_BACK, str(edp), str(back)], check=True,
                   timeout=300)
    read = pd.read_csv(back, index_col=0)
    assert read.loc["Units"].to_dict() == {f"{t}-{k}-1": u for t, u, ks in
                                           (("PFA", "g", range(4)), ("PID", "rad", (1, 2, 3)))
                                           for k in ks}
    mine, _ = demand_table(folder / "risk.nc", building="A", level=0.8)
    values = read.drop(index="Units").astype(float)
    for column in values.columns:
        np.testing.assert_allclose(values[column].values, mine[f"1-{column}"].values,
                                   rtol=1e-9)

