"""Uncertain scene values and subset simulation inside a study file: the probability of
pounding of two elastic SDOFs with a lognormal gap under stationary Clough-Penzien noise,
by subset simulation over the gap and the noise, against conditional Monte Carlo over the
noise alone (the critical gap does not depend on the gap: P = E[F_gap(critical gap)]);
Latin hypercube samples reach the runs of an msa study; bad input named."""

from __future__ import annotations

import json
import math
from pathlib import Path

import numpy as np
import pytest
import yaml
from scipy.optimize import brentq
from scipy.stats import norm

from pframe.cli import main

MOTION = {"model": "clough_penzien", "intensity": 0.01, "ground_frequency": 15.6,
          "ground_damping": 0.6, "filter_frequency": 1.5, "filter_damping": 0.6,
          "duration": 5.0, "step": 0.01}


def _pair(folder: Path) -> Path:
    mass = 1000.0
    scene = {"title": "two elastic SDOFs",
             "buildings": [{"name": n, "floors": 1, "mass": mass,
                            "story": {"material": "elastic",
                                      "stiffness": mass * (2 * math.pi / p) ** 2}}
                           for n, p in (("A", 0.5), ("B", 1.0))],
             "contacts": [{"name": "roof", "nodes": ["A/1", "B/1"], "gap": 0.2,
                           "law": "linear", "stiffness": 1.0e7}],
             "damping": {"ratio": 0.05}, "analysis": {"dt": 0.01, "duration": 8.0}}
    path = folder / "pair.yaml"
    path.write_text(json.dumps(scene))
    return path


def _study(folder: Path, **fields) -> Path:
    study = {"scene": str(_pair(folder)), "stochastic": MOTION, "duration": 8.0, "dt": 0.01,
             "design": {"kind": "subset", "probability_level": 0.1, "samples": 300},
             "uncertain": {"gap": {"distribution": "lognormal", "median": 0.2,
                                   "dispersion": 0.2}}, "seed": 1}
    study.update(fields)
    path = folder / "study.yaml"
    path.write_text(yaml.safe_dump(study))
    return path


@pytest.fixture(scope="module")
def subset_run(tmp_path_factory):
    """The subset study run whole, uninterrupted: (its folder, its file)."""
    folder = tmp_path_factory.mktemp("subset")
    out = folder / "subset.nc"
    assert main(["risk", str(_study(folder)), "-o", str(out), "-q", "--threads", "2"]) == 0
    return folder, out


@pytest.mark.slow
def test_subset_study_agrees_with_conditional_monte_carlo(subset_run):
    import xarray as xr

    from pframe.reader import load_scene
    from pframe.risk.uncertain import SubsetProblem

    tmp_path, out = subset_run
    ds = xr.open_dataset(out)
    p, lo, hi = (float(ds[k]) for k in ("pounding_probability", "pounding_probability_low",
                                         "pounding_probability_high"))
    assert 1e-4 < p < 3e-2 and 0 < float(ds.pounding_probability_cov) < 0.6
    assert int(ds.evaluations) < 2000 and list(ds.variable_name.values) == ["contacts.*.gap"]
    # conditional Monte Carlo: the noise alone, the gap integrated exactly
    problem = SubsetProblem(load_scene(tmp_path / "pair.yaml"), [], MOTION, 800, 0.01, 2)
    rng = np.random.default_rng(11)
    n = 6000
    g = np.concatenate([problem(rng.standard_normal((1000, problem.dim)))
                        for _ in range(n // 1000)])
    critical = 0.2 - g  # g = gap - critical gap with the scene's gap 0.2
    f = norm.cdf(np.log(np.maximum(critical, 1e-300) / 0.2) / 0.2)
    mean, se = f.mean(), f.std() / math.sqrt(n)
    assert lo <= mean + 1.96 * se and mean - 1.96 * se <= hi, (p, lo, hi, mean, se)


@pytest.mark.slow
def test_a_stopped_subset_study_resumes_to_the_same_numbers(subset_run, tmp_path, monkeypatch):
    """Stopped after five batches (two of the first level, three of its chains), the study
    runs only the other batches the second time and gives the uninterrupted run's numbers,
    bit for bit: the seed draws the same u, the saved batches give the same g."""
    import xarray as xr

    import pframe.risk.runs
    from pframe.risk import risk

    whole = xr.open_dataset(subset_run[1])
    study = _study(tmp_path)
    out = tmp_path / "stopped.nc"
    seen = []

    def stop(done, total):
        seen.append(done)
        if len(seen) == 5:
            raise KeyboardInterrupt

    with pytest.raises(KeyboardInterrupt):
        risk(study, output=out, progress=stop)
    assert not out.exists()
    assert len(list((tmp_path / "stopped.nc.parts").glob("chunk-*"))) == 5
    batches = []
    real = pframe.risk.runs.run_batch
    monkeypatch.setattr(pframe.risk.runs, "run_batch",
                        lambda *a, **k: batches.append(len(a[2])) or real(*a, **k))
    risk(study, output=out)
    again = xr.open_dataset(out)
    assert not (tmp_path / "stopped.nc.parts").exists()
    assert sum(batches) == int(whole.evaluations) - seen[-1]  # only the runs not saved
    for name in ("pounding_probability", "pounding_probability_low",
                 "pounding_probability_high", "pounding_probability_cov", "evaluations"):
        assert float(again[name]) == float(whole[name]), name
    assert np.array_equal(again.threshold.values, whole.threshold.values)


@pytest.mark.parametrize("fields, says", [
    ({"design": {"kind": "subset", "samples": 305}}, "design.samples"),
    ({"stochastic": {**MOTION, "model": "rezaeian2010"}}, "at stochastic"),
    ({"uncertain": {"gap": {"distribution": "lognormal", "median": 0.2}}}, "uncertain.gap"),
    ({"uncertain": {"buildings.C.story.stiffness": {"distribution": "normal", "mean": 1.0,
                                                    "sd": 0.1}}}, "buildings.C"),
    ({"hazard": {"power_law": {"k0": 1e-4, "k": 2.5}}}, "at design"),
    ({"design": {"kind": "subset", "samples": 300, "floor": 1e-4}}, "design.floor"),
])
def test_bad_subset_studies_exit_2_naming_the_place(tmp_path, capsys, fields, says):
    path = _study(tmp_path, **fields)
    assert main(["risk", str(path), "-o", str(tmp_path / "out.nc"), "-q"]) == 2
    err = capsys.readouterr().err
    assert str(path) in err and says in err and "Traceback" not in err
    assert not (tmp_path / "out.nc").exists()


def test_latin_hypercube_gaps_reach_the_runs_of_an_msa_study(tmp_path):
    """Uncertain gap, uniform 0.1-0.3 m, one Latin hypercube sample per run: every run's
    pounding (critical gap > its own gap) is the study's pounding fragility's data, and the
    gaps fill the strata."""
    from pframe.risk import risk

    path = _study(tmp_path, stochastic={**MOTION, "realisations": 4, "seed": 2},
                  design={"kind": "msa", "levels": [0.1, 0.2, 0.3, 0.5]}, measure="pga",
                  pounding_runs=False,
                  uncertain={"gap": {"distribution": "uniform", "low": 0.1, "high": 0.3}})
    rows = {}
    import pframe.risk.study as study

    real = study.run_variants

    def keep(*a, **k):
        rows.update(real(*a, **k))
        return rows

    import warnings
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        try:
            study.run_variants = keep
            risk(path)
        finally:
            study.run_variants = real
    gaps = rows["free_gap"]
    assert gaps.size == 16 and gaps.min() >= 0.1 and gaps.max() <= 0.3
    assert sorted(np.floor((gaps - 0.1) / 0.2 * 16).astype(int)) == list(range(16))


def _records_study(folder: Path, median: float, levels=(0.3,), **fields) -> Path:
    from conftest import record_file

    for name in ("elCentro.AT2", "A-ELC180.AT2"):
        record_file(name)  # skips, saying why, when the shared records are absent
    from conftest import RECORDS

    (folder / "suite.yaml").write_text(yaml.safe_dump({
        "records": ["elCentro.AT2", "A-ELC180.AT2"]}))
    study = {"scene": str(_pair(folder)), "suite": str(folder / "suite.yaml"),
             "records_folder": str(RECORDS), "duration": 8.0, "dt": 0.01,
             "design": {"kind": "subset", "levels": list(levels), "probability_level": 0.1,
                        "samples": 300},
             "uncertain": {"gap": {"distribution": "lognormal", "median": median,
                                   "dispersion": 0.2},
                           "buildings.A.story.stiffness": {
                               "distribution": "lognormal", "median": STIFFNESS_A,
                               "dispersion": 0.15}},
             "seed": 3, **fields}
    path = folder / "records-study.yaml"
    path.write_text(yaml.safe_dump(study))
    return path


STIFFNESS_A = 1000.0 * (2 * math.pi / 0.5) ** 2


@pytest.mark.slow
def test_subset_over_records_agrees_with_monte_carlo_at_stripes_and_over_the_hazard(tmp_path):
    """Two real records scaled to two stripes; uncertain gap and storey stiffness; a power-law
    hazard. Subset simulation per record and stripe, averaged over the records, and the
    annual frequency over the hazard, against Monte Carlo over the stiffness with the records
    enumerated and the gap integrated exactly (P(gap < critical gap) is a lognormal CDF;
    without contacts the pair is linear, so the critical gap at a stripe is the one at 0.3 g
    scaled by the level), combined with the same stripe weights (checked on their own
    above): each within the other's 95 % interval."""
    import xarray as xr

    from pframe.gap.audit import prepare
    from pframe.risk import HazardCurve
    from pframe.risk.uncertain import RecordSubsetProblem, parse, stripe_weights

    levels = np.array([0.22, 0.3])
    probe = _records_study(tmp_path, 0.2)
    spec = yaml.safe_load(probe.read_text())
    inputs = prepare(tmp_path / "pair.yaml", tmp_path / "suite.yaml", levels=[0.3],
                     duration=8.0, dt=0.01, records_folder=Path(spec["records_folder"]))
    params = parse(spec["uncertain"], "uncertain")
    rng = np.random.default_rng(7)
    n = 400
    z = rng.standard_normal(n)
    u = np.zeros((n, 2))  # the gap at its median 0.2, the stiffness sampled
    u[:, [p.path for p in params].index("buildings.A.story.stiffness")] = z
    critical = np.array([0.2 - RecordSubsetProblem(inputs, params, r, 0, 2)(u)
                         for r in range(2)])  # g = gap - critical gap
    assert np.all(critical > 0)

    def chance(median, level):  # per stiffness sample, the mean over the records
        return norm.cdf(np.log(critical * level / 0.3 / median) / 0.2).mean(axis=0)

    # the gap median that makes pounding a rare event at the upper stripe: 1e-2
    median = brentq(lambda m: chance(m, 0.3).mean() - 1e-2, 0.01, 10.0)
    f = np.array([chance(median, x) for x in levels])  # (stripes, samples)
    mean, se = f.mean(axis=1), f.std(axis=1) / math.sqrt(n)
    curve = HazardCurve.power_law(1e-4, 2.5)
    c, _ = stripe_weights(levels, curve)
    maf = c @ f
    maf_mean, maf_se = maf.mean(), maf.std() / math.sqrt(n)

    study = _records_study(tmp_path, median, levels=levels.tolist(),
                           hazard={"power_law": {"k0": 1e-4, "k": 2.5}})
    data = yaml.safe_load(study.read_text())
    data["design"].update(samples=400, floor=1e-5)
    study.write_text(yaml.safe_dump(data))
    out = tmp_path / "records.nc"
    assert main(["risk", str(study), "-o", str(out), "-q", "--threads", "2"]) == 0
    ds = xr.open_dataset(out)
    assert ds.sizes["record"] == 2 and list(ds.level.values) == levels.tolist()
    assert "pounding_probability" not in ds  # one probability per stripe
    for k in range(2):
        p, lo, hi = (float(ds[v][k]) for v in ("level_probability", "level_probability_low",
                                                "level_probability_high"))
        assert p == pytest.approx(float(ds.record_probability[:, k].mean()), rel=1e-12)
        assert lo <= mean[k] + 1.96 * se[k] and mean[k] - 1.96 * se[k] <= hi, (
            k, p, lo, hi, mean[k], se[k])
    lam, lo, hi = (float(ds[v]) for v in ("annual_frequency", "annual_frequency_low",
                                           "annual_frequency_high"))
    assert lam == pytest.approx(float(c @ ds.level_probability.values), rel=1e-9)
    assert lo <= maf_mean + 1.96 * maf_se and maf_mean - 1.96 * maf_se <= hi, (
        lam, lo, hi, maf_mean, maf_se)
    assert 0 < float(ds.annual_frequency_cov) < 0.6
    # a record far weaker than the other may be stopped below the floor (1e-5): it counts 0,
    # and the warnings say so
    stopped = (ds.record_probability.values == 0).sum(axis=0)
    assert np.all(stopped < 2)
    for k in range(2):
        if stopped[k]:
            assert (f"{stopped[k]} of 2 records stopped below the floor 1.0e-05 (probability "
                    f"of pounding under each below it) and count 0; the interval's upper end "
                    f"adds their bound at {levels[k]:g} g") in ds.attrs["warnings"]
    print(f"subset over records: stripes {ds.level_probability.values} "
          f"({ds.level_probability_low.values}-{ds.level_probability_high.values}), "
          f"MAF {lam:.3e} ({lo:.3e}-{hi:.3e}), {int(ds.evaluations)} runs; Monte Carlo "
          f"{mean} +- {1.96 * se}, MAF {maf_mean:.3e} +- {1.96 * maf_se:.1e}; per record "
          f"{ds.record_probability.values.tolist()}")


def test_a_subset_design_over_records_needs_uncertain_values(tmp_path, capsys):
    study = _records_study(tmp_path, 0.2)
    data = yaml.safe_load(study.read_text())
    del data["uncertain"]
    study.write_text(yaml.safe_dump(data))
    assert main(["risk", str(study), "-q"]) == 2
    err = capsys.readouterr().err
    assert "at uncertain" in err and "suite of records" in err and "Traceback" not in err


def test_member_scenes_are_the_variants_and_are_validated_whole(tmp_path):
    """The batch's member scenes (YAML composed once, no text) are the scenes variant()
    makes one by one, and a sample outside what a scene allows (a negative stiffness from a
    normal distribution) is still refused, naming the scene file."""
    from pframe.errors import InputError
    from pframe.reader import load_scene, variant
    from pframe.risk.uncertain import parse, scenes
    from pframe.sweep.paths import put, resolve

    loaded = load_scene(_pair(tmp_path))
    params = parse({"gap": {"distribution": "lognormal", "median": 0.2, "dispersion": 0.3},
                    "buildings.A.story.stiffness": {"distribution": "normal",
                                                    "mean": STIFFNESS_A,
                                                    "sd": 0.1 * STIFFNESS_A}}, "uncertain")
    u = np.random.default_rng(4).standard_normal((6, 2))
    fast = scenes(loaded, params, u)
    for row, member in zip(u, fast):
        def change(data, row=row):
            for p, x in zip(params, row):
                for path in resolve(data, tuple(p.path.split("."))):
                    put(data, path, float(p.value(x)))

        one = variant(loaded, change)
        assert member.scene == one.scene
        assert member.expanded.contacts[0].gap == one.expanded.contacts[0].gap
    with pytest.raises(InputError, match="pair.yaml"):
        scenes(loaded, params, np.array([[0.0, -20.0]]))  # stiffness mean - 20 sd < 0


@pytest.mark.parametrize("theta, beta", [(0.6, 0.4), (1.5, 0.25)])
def test_stripe_weights_integrate_a_fragility_over_the_hazard(theta, beta):
    """The mean annual frequency from probabilities at stripes, sum_k c_k P(x_k), tends to
    Cornell et al.'s closed form k0 theta^-k exp(k^2 beta^2 / 2) for a lognormal P(x) as
    the stripes fill the intensities; with few stripes it is near it, and the notes on the
    shares below the first stripe and above the last appear when those shares matter."""
    from pframe.risk import HazardCurve, closed_form_maf
    from pframe.risk.sampling import Estimate
    from pframe.risk.uncertain import maf_from_stripes, stripe_weights

    k0, k = 1e-4, 2.5
    curve = HazardCurve.power_law(k0, k)
    exact = closed_form_maf(theta, beta, k0, k)
    dense = np.geomspace(0.01, 50.0, 400)
    c, _ = stripe_weights(dense, curve)
    p = norm.cdf(np.log(dense / theta) / beta)
    assert float(np.dot(c, p)) == pytest.approx(exact, rel=2e-3)
    few = theta * np.exp(beta * np.array([-2.5, -1.5, -0.75, 0.0, 0.75, 1.5, 2.5]))
    estimates = [Estimate(float(q), float(q), float(q), 0.1, 1, "known")
                 for q in norm.cdf(np.log(few / theta) / beta)]
    lam, lo, hi, cov, notes = maf_from_stripes(few, estimates, curve)
    assert lam == pytest.approx(exact, rel=0.1) and lo < lam < hi and notes == []
    assert cov == pytest.approx(np.sqrt(np.sum((stripe_weights(few, curve)[0] * 0.1 * np.array(
        [e.probability for e in estimates])) ** 2)) / lam, rel=1e-12)
    # stripes starting at the median: half the frequency lies below them, and it is said
    lam2, *_, notes2 = maf_from_stripes(few[3:], estimates[3:], curve)
    assert lam2 < 0.8 * exact and any("below it" in n for n in notes2)
    # stripes ending at the median: the higher intensities' share is said likewise
    lam3, *_, notes3 = maf_from_stripes(few[:4], estimates[:4], curve)
    assert lam3 < 0.95 * exact and any("above the last stripe" in n for n in notes3)


@pytest.mark.parametrize("design, fields, says", [
    ({"levels": [0.3, 0.2]}, {}, "positive and increasing"),
    ({"levels": [0.3]}, {"hazard": {"power_law": {"k0": 1e-4, "k": 2.5}}}, "two or more"),
    ({}, {"hazard": {"power_law": {"k0": 1e-4, "k": 2.5}}}, "two or more"),
    ({"levels": [0.2, 0.3]}, {"hazard": {"power_law": {"k0": 1e-4, "k": 2.5}},
                              "target": {"return_period": 475}}, "at target"),
    ({"floor": 1.5}, {}, "design.floor"),
])
def test_bad_subset_studies_over_records_exit_2_naming_the_place(tmp_path, capsys, design,
                                                                 fields, says):
    """Checked before any record is read."""
    (tmp_path / "suite.yaml").write_text(yaml.safe_dump({"records": ["elCentro.AT2"]}))
    study = {"scene": str(_pair(tmp_path)), "suite": "suite.yaml",
             "design": {"kind": "subset", "samples": 100, **design},
             "uncertain": {"gap": {"distribution": "lognormal", "median": 0.2,
                                   "dispersion": 0.2}}, **fields}
    path = tmp_path / "study.yaml"
    path.write_text(yaml.safe_dump(study))
    assert main(["risk", str(path), "-o", str(tmp_path / "out.nc"), "-q"]) == 2
    err = capsys.readouterr().err
    assert str(path) in err and says in err and "Traceback" not in err
    assert not (tmp_path / "out.nc").exists()


@pytest.mark.slow
def test_a_subset_study_over_records_killed_resumes_to_the_same_file(tmp_path):
    """Two records at two stripes (one record chased through its levels, the other stopped
    at the floor): SIGKILLed twice part way, the same command continues from the saved
    batches across records and stripes, and writes the very file of an uninterrupted run."""
    import subprocess
    import sys

    from conftest import assert_same_result_file, kill_after

    study = _records_study(tmp_path, 0.2, levels=[0.22, 0.3])
    data = yaml.safe_load(study.read_text())
    data["design"].update(samples=100, floor=1e-4)
    study.write_text(yaml.safe_dump(data))

    def command(out):
        return [sys.executable, "-c", "import sys; from pframe.cli import main; "
                "sys.exit(main())", "risk", study.name, "-o", out, "--threads", "1", "-q"]

    whole = subprocess.run(command("whole.nc"), cwd=tmp_path, capture_output=True, text=True,
                           timeout=900)
    assert whole.returncode == 0, whole.stderr
    parts = tmp_path / "resumed.nc.parts"
    first = kill_after(command("resumed.nc"), tmp_path, parts, 8)
    assert first >= 8 and not (tmp_path / "resumed.nc").exists()
    second = kill_after(command("resumed.nc"), tmp_path, parts, first + 10)
    assert second > first and not (tmp_path / "resumed.nc").exists()
    again = subprocess.run(command("resumed.nc"), cwd=tmp_path, capture_output=True,
                           text=True, timeout=900)
    assert again.returncode == 0, again.stderr
    assert not parts.exists()
    assert_same_result_file(tmp_path / "resumed.nc", tmp_path / "whole.nc")
    import xarray as xr

    ds = xr.open_dataset(tmp_path / "whole.nc")
    total = int(ds.evaluations)
    assert second < total / 20  # killed part way (most batches are a chain step of 20 runs)
    assert (ds.record_probability.values > 0).any() and (ds.record_probability.values == 0).any()


@pytest.mark.slow
def test_a_stripe_where_no_record_pounds_says_so_with_its_upper_end(tmp_path):
    """A gap far above every critical gap and a coarse floor: both records stop below it, the
    probability is 0 as estimated, and the file and the warnings give the upper end (the
    floor's bound) instead of an infinite c.o.v. or an error."""
    import warnings

    from pframe.risk import risk

    study = _records_study(tmp_path, 5.0)
    data = yaml.safe_load(study.read_text())
    data["design"].update(samples=100, floor=1e-2)
    study.write_text(yaml.safe_dump(data))
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        ds = risk(study)
    assert float(ds.pounding_probability) == 0.0
    assert 0.0 < float(ds.pounding_probability_high) <= 1e-2
    assert np.all(ds.record_probability.values == 0)
    said = [str(w.message) for w in caught]
    assert any("2 of 2 records stopped below the floor" in m for m in said)
    assert any("no record pounds" in m and "upper end" in m for m in said)
    assert not any("coefficient of variation" in m for m in said)
    assert "no record pounds" in ds.attrs["warnings"]


@pytest.mark.slow
def test_a_subset_file_writes_its_units_and_measure_as_every_study_file_does(tmp_path):
    """A subset study over records with a hazard and an msa study: every annual frequency
    of both files in the one unit (a reader comparing units as text finds them equal), one
    year^-1 to UDUNITS, and both files name their intensity measure."""
    cf_units = pytest.importorskip("cf_units", reason="cf_units parses the units")
    from test_risk import pulse_study

    from pframe.risk import risk

    subset = tmp_path / "subset"
    subset.mkdir()
    study = _records_study(subset, 5.0, levels=(0.2, 0.3),
                           hazard={"power_law": {"k0": 1e-4, "k": 2.5}})
    data = yaml.safe_load(study.read_text())
    data["design"].update(samples=100, floor=1e-2)  # no record pounds: a short study
    study.write_text(yaml.safe_dump(data))
    msa = tmp_path / "msa"
    msa.mkdir()
    with pytest.warns(UserWarning):
        files = {"subset": risk(study), "msa": risk(pulse_study(msa))}
    units = {(kind, name): var.attrs["units"] for kind, ds in files.items()
             for name, var in ds.variables.items()
             if "frequency" in name and not name.endswith("_cov")}
    assert {("subset", "annual_frequency"), ("subset", "hazard_frequency"),
            ("msa", "hazard_frequency"), ("msa", "target_annual_frequency")} <= set(units)
    assert len(set(units.values())) == 1, units
    year = cf_units.Unit(next(iter(units.values())))
    assert year.convert(1.0, cf_units.Unit("day-1")) == pytest.approx(1 / 365.242198781)
    for kind, ds in files.items():
        assert ds.attrs["measure"] == "PGA", kind


def test_a_subset_estimate_of_zero_says_why_it_has_no_cov():
    """No run pounded: the probability is 0 and its c.o.v. undefined; the summary says so in
    words, never 'c.o.v. inf' or 'c.o.v. nan' as if they were measured."""
    import xarray as xr

    from pframe.risk.output import _results

    ds = xr.Dataset({"pounding_probability": 0.0, "pounding_probability_cov": np.inf,
                     "pounding_probability_low": 0.0, "pounding_probability_high": 3e-3,
                     "evaluations": 1000}, attrs={"duration": 10.0})
    text = _results(ds)
    assert "c.o.v. undefined: no run pounded" in text
    assert "inf" not in text and "nan" not in text
    ds["pounding_probability"], ds["pounding_probability_cov"] = 1e-3, 0.25
    assert "c.o.v. 0.25" in _results(ds)
