"""IDA by hunt and fill (Vamvatsikos & Cornell 2004): the capacities it finds equal a dense
grid's to the requested resolution, with far fewer runs, and the censored fit uses them;
studies on stochastic motions (no record files needed); bad hunts named."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest
import yaml

from pframe.cli import main
from pframe.excitation.records import G
from pframe.risk import fit_capacities
from pframe.risk.ida import hunt_and_fill

REPO = Path(__file__).resolve().parents[1]


def test_hunt_and_fill_brackets_every_capacity_within_the_resolution():
    """Demand / limit = (IM / c_r)^1.3: each record passes the limit at c_r exactly. The
    search brackets every c_r below max_level within 0.02 g, censors the others at
    max_level, and needs a fraction of the runs of a 0.02 g grid."""
    rng = np.random.default_rng(7)
    caps = 0.7 * np.exp(0.5 * rng.standard_normal(300))
    seen = []

    def passes(which, ims):
        seen.append(len(which))
        return (ims / caps[which]) ** 1.3 > 1

    search = hunt_and_fill(passes, caps.size, start=0.1, step=0.1, growth=1.5,
                           resolution=0.02, max_level=3.0)
    assert search.finished and search.runs == sum(seen) and search.rounds == len(seen)
    for c, s in zip(caps, search.state):
        if c > 3.0:
            assert s.censored
            continue
        assert not s.censored and s.lo < c <= s.hi and s.hi - s.lo <= 0.02 + 1e-12
    grid_runs = caps.size * len(np.arange(0.02, 3.0 + 1e-9, 0.02))
    assert search.runs < grid_runs / 10
    assert search.rounds <= 20  # every round one batch across the records


def _capacity(im, ratio):
    """The IM where ratio first passes 1 over runs in order of IM, log-log interpolated
    (censored at the top run when it never does)."""
    keep = np.isfinite(im)
    im, ratio = im[keep], ratio[keep]
    above = np.flatnonzero(ratio > 1)
    if not above.size:
        return im[-1], True
    j = above[0]
    if j == 0:
        return im[0], False
    a, b = np.log(ratio[j - 1]), np.log(ratio[j])
    return math.exp(np.log(im[j - 1]) + (-a / (b - a)) * np.log(im[j] / im[j - 1])), False


def _study(folder: Path, name: str, design: dict, **extra) -> Path:
    study = {"scene": str(REPO / "models" / "wu2021-eq14.yaml"), "measure": "pga",
             "stochastic": {"model": "clough_penzien", "intensity": 0.02,
                            "ground_frequency": 15.0, "ground_damping": 0.6, "duration": 8.0,
                            "step": 0.01, "realisations": 5, "seed": 1},
             "design": design, "dt": 0.002, "pounding_runs": False,
             "limits": {"drift": {"LS": 0.05}}, "bootstrap": 0}
    study.update(extra)
    path = folder / f"{name}.yaml"
    path.write_text(yaml.safe_dump(study))
    return path


@pytest.fixture(scope="module")
def hunted(tmp_path_factory):
    import xarray as xr

    folder = tmp_path_factory.mktemp("ida")
    hunt = {"kind": "ida", "hunt": {"start": 0.1, "step": 0.1, "growth": 1.5},
            "resolution": 0.02, "limit": "LS", "max_level": 2.0}
    grid = {"kind": "ida", "levels": [round(0.01 * k, 3) for k in range(1, 201)]}
    out = {}
    for name, design in (("hunt", hunt), ("grid", grid)):
        path = _study(folder, name, design)
        assert main(["risk", str(path), "-o", str(folder / f"{name}.nc"), "-q",
                     "--threads", "2"]) == 0
        out[name] = xr.open_dataset(folder / f"{name}.nc")
    return out, folder


@pytest.mark.slow
def test_hunt_finds_the_dense_grids_capacities_with_far_fewer_runs(hunted):
    """Five Clough-Penzien motions on the paper's pair (bilinear storeys), drift limit
    0.05 m: every record's capacity by hunt and fill is within the 0.02 g resolution of the
    capacity on a 0.01 g grid of 200 levels; the hunt runs a tenth of the grid's runs."""
    ds, grid = hunted[0]["hunt"], hunted[0]["grid"]
    found = [_capacity(ds.intensity.values[r], ds.peak_story_drift.isel(
        condition=0).values[r].max(axis=-1) / 0.05) for r in range(ds.sizes["record"])]
    dense = [_capacity(grid.intensity.values[r], grid.peak_story_drift.isel(
        condition=0).values[r].max(axis=-1) / 0.05) for r in range(grid.sizes["record"])]
    assert sum(not c for _, c in dense) >= 4  # most records reach the limit below 2 g
    for (h, hc), (g, gc) in zip(found, dense):
        assert hc == gc
        if not hc:
            assert abs(h - g) <= 0.02
    runs = int(ds.attrs["ida_runs"])
    assert runs == int((ds.complete.isel(condition=0) >= 0).sum())
    assert runs * 10 < grid.sizes["record"] * grid.sizes["level"]
    # the censored fit of the file is the fit of these capacities
    f = fit_capacities([c for c, _ in found], [x for _, x in found])
    sel = {"limit_name": "LS", "condition_name": "without_pounding"}
    assert float(ds.fragility_median.sel(sel)) == pytest.approx(f.median, rel=1e-6)
    assert float(ds.fragility_dispersion.sel(sel)) == pytest.approx(f.dispersion, rel=1e-6)
    assert ds.attrs["ida_limit"] == "LS" and ds.attrs["Conventions"] == "CF-1.8"


@pytest.mark.parametrize("design, says", [
    ({"kind": "ida", "hunt": {"start": 0.1, "step": 0.1}}, "design.resolution"),
    ({"kind": "msa", "hunt": {"start": 0.1, "step": 0.1}, "resolution": 0.02}, "at design"),
    ({"kind": "ida", "hunt": {"start": 0.1, "step": 0.1}, "resolution": 0.02,
      "limit": "IO"}, "design.limit"),
    ({"kind": "ida", "hunt": {"start": 0.1, "step": 0.1, "growth": 0.5},
      "resolution": 0.02}, "design.hunt.growth"),
])
def test_bad_hunts_exit_2_naming_the_place(tmp_path, capsys, design, says):
    path = _study(tmp_path, "bad", design)
    assert main(["risk", str(path), "-o", str(tmp_path / "out.nc"), "-q"]) == 2
    err = capsys.readouterr().err
    assert str(path) in err and says in err and "Traceback" not in err


def test_capacities_all_equal_give_no_fit():
    """Every record passing at the first run (the gap solver's small gaps) left Nelder-Mead
    chasing a dispersion of 0 for 4,000 iterations and reported it as a fit."""
    f = fit_capacities([0.1, 0.1, 0.1, 0.2], [False, False, False, True])
    assert not f.fitted and "same IM" in f.note


def test_a_studys_stochastic_motions_are_the_scenes_realisations_of_those_seeds():
    from pframe.excitation.stochastic import generate
    from pframe.model.scene import Stochastic
    from pframe.risk.study import stochastic_suite

    fields = {"model": "clough_penzien", "intensity": 0.02, "ground_frequency": 15.0,
              "ground_damping": 0.6, "duration": 4.0, "step": 0.01}
    suite = stochastic_suite({**fields, "realisations": 3, "seed": 5}, "study.yaml")
    assert len(suite.motions) == 3
    for k, m in enumerate(suite.motions):
        scene = generate(Stochastic(kind="stochastic", seed=5 + k, **fields))
        assert np.array_equal(m.acceleration, scene.acceleration)
    assert not np.array_equal(suite.motions[0].acceleration, suite.motions[1].acceleration)


@pytest.mark.slow
def test_a_study_keeps_of_each_motion_what_its_runs_read(tmp_path):
    """A stochastic study given its duration (and measured in PGA) keeps each realisation only
    as far as its runs read it, generated in blocks on threads: the same realisations, scale
    factors, warnings and ground motions of the runs (with and without contacts) as from the
    whole motions, and each knows its whole duration and peak."""
    from pframe.risk.study import open_study, stochastic_suite

    motion = {"model": "rezaeian2010", "magnitude": 6.5, "distance": 20.0, "vs30": 400.0,
              "realisations": 40, "seed": 3}
    study = _study(tmp_path, "cut", {"kind": "msa", "levels": [0.2, 0.4]}, stochastic=motion,
                   duration=3.0, pounding_runs=True)
    inputs = open_study(study).inputs
    whole = stochastic_suite(motion, "whole").motions
    kept = inputs.suite.motions
    assert [m.name for m in kept] == [m.name for m in whole]
    for cut, full in zip(kept, whole):
        assert cut.time[-1] < 3.0 + 0.01 + 1e-9 < full.time[-1]
        assert (cut.duration, cut.peak, cut.peak_time) == (full.duration, full.peak,
                                                           full.peak_time)
    scene_dt = inputs.loaded.expanded.dt
    for steps, dt in ((inputs.steps, inputs.dt),
                      (math.ceil(inputs.steps * inputs.dt / scene_dt - 1e-9), scene_dt)):
        times = np.arange(steps + 1) * dt
        for r in (0, 39):
            assert np.array_equal(kept[r].on_site(times), whole[r].on_site(times))
    ims = np.array([m.peak for m in whole]) / G
    assert np.array_equal(inputs.factors, np.array([[0.2, 0.4]]) / ims[:, None])
    # each motion's cut warning from its whole extent: ten named, thirty counted
    assert len(inputs.warnings) == 11 and "runs to" in inputs.warnings[0]
    assert inputs.warnings[-1].startswith("30 more records: the runs stop at 3 s")


@pytest.mark.parametrize("stochastic, says", [
    ({"model": "clough_penzien", "intensity": 0.02, "ground_frequency": 15.0,
      "ground_damping": 0.6, "duration": 4.0}, "stochastic.realisations"),
    ({"model": "clough_penzien", "intensity": 0.02, "ground_frequency": 15.0,
      "ground_damping": 0.6, "duration": 4.0, "realisations": 2, "seed": -1}, "stochastic.seed"),
    ({"model": "clough_penzien", "intensity": 0.02, "realisations": 2}, "ground_frequency"),
])
def test_bad_stochastic_motions_exit_2_naming_the_place(tmp_path, capsys, stochastic, says):
    path = _study(tmp_path, "bad", {"kind": "msa", "levels": [0.1, 0.2]},
                  stochastic=stochastic)
    assert main(["risk", str(path), "-o", str(tmp_path / "out.nc"), "-q"]) == 2
    err = capsys.readouterr().err
    assert str(path) in err and says in err and "Traceback" not in err


@pytest.mark.slow
def test_a_stopped_hunt_resumes_from_its_saved_rounds(tmp_path, hunted, monkeypatch):
    """Stopped after three rounds, the study runs only the later rounds the second time and
    gives the file of an uninterrupted run."""
    import xarray as xr

    import pframe.risk.runs
    from pframe.risk import risk

    whole = hunted[0]["hunt"]
    study = _study(tmp_path, "hunt", {"kind": "ida", "hunt": {"start": 0.1, "step": 0.1,
                                      "growth": 1.5}, "resolution": 0.02, "limit": "LS",
                                      "max_level": 2.0})
    out = tmp_path / "stopped.nc"
    calls = []

    def stop(done, total):
        calls.append(done)
        if len(calls) == 3:
            raise KeyboardInterrupt

    with pytest.raises(KeyboardInterrupt):
        risk(study, output=out, progress=stop)
    assert not out.exists() and len(list((tmp_path / "stopped.nc.parts").glob("chunk-*"))) == 3
    batches = []
    real = pframe.risk.runs.run_batch
    monkeypatch.setattr(pframe.risk.runs, "run_batch",
                        lambda *a, **k: batches.append(1) or real(*a, **k))
    risk(study, output=out)
    assert len(batches) == int(whole.attrs["ida_rounds"]) - 3
    again = xr.open_dataset(out)
    assert np.array_equal(again.intensity.values, whole.intensity.values, equal_nan=True)
    assert np.array_equal(again.peak_story_drift.values, whole.peak_story_drift.values,
                          equal_nan=True)
    assert int(again.attrs["ida_runs"]) == int(whole.attrs["ida_runs"])
