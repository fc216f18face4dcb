"""A risk study reuses a run without contacts as the run with them where no contact can close
(pframe.risk.runs.with_contacts, docs/risk.md): the study's outputs are those of integrating
every run with its contacts, to the bit; a run that comes within a hair of a gap, or closes
it, is integrated; different steps, or a law that may act while open, turn the reuse off."""

from __future__ import annotations

import warnings
from pathlib import Path

import numpy as np
import pytest
import yaml
from conftest import integrator_cases

import pframe.risk.runs as runs
from pframe.gap.runs import contact_pairs
from pframe.reader import load_scene

REPO = Path(__file__).resolve().parents[1]
PAIR = REPO / "models" / "wu2021-eq14.yaml"
DT = 0.002


def _study(folder: Path, study_dt: float = DT, chunk: int | None = None,
           design: dict | None = None) -> Path:
    """The paper's pair on a 2 ms step under 6 Clough-Penzien motions at four PGA stripes:
    the weaker stripes never close a gap, the stronger pound."""
    scene = yaml.safe_load(PAIR.read_text(encoding="utf-8"))
    scene["analysis"].update(dt=DT, duration=4.0)
    (folder / "scene.yaml").write_text(yaml.safe_dump(scene, sort_keys=False), encoding="utf-8")
    study = {"scene": "scene.yaml", "measure": "pga",
             "stochastic": {"model": "clough_penzien", "intensity": 0.02,
                            "ground_frequency": 15.0, "ground_damping": 0.6, "duration": 4.0,
                            "step": 0.01, "realisations": 6, "seed": 3},
             "design": design or {"kind": "msa", "levels": [0.1, 0.3, 0.6, 1.2]},
             "dt": study_dt, "duration": 4.0, "pounding_runs": True,
             "limits": {"drift": {"LS": 0.05}, "acceleration": {"A": 1.0}},
             "hazard": {"power_law": {"k0": 1.0e-4, "k": 2.5}},
             "target": {"return_period": 475}, "bootstrap": 20}
    if chunk is not None:
        study["chunk"] = chunk
    path = folder / f"study-{chunk}-{(design or {}).get('kind', 'msa')}.yaml"
    path.write_text(yaml.safe_dump(study, sort_keys=False), encoding="utf-8")
    return path


def _risk(path: Path, reuse: bool, monkeypatch):
    from pframe.risk.study import risk

    monkeypatch.setattr(runs, "_REUSE_OPEN", reuse)
    timings: dict = {}
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # the small study's fits warn of their few runs
        ds = risk(path, threads=1, timings=timings)
    return ds, timings


@pytest.mark.slow
def test_a_study_reusing_open_runs_is_the_study_integrating_every_run(tmp_path, monkeypatch):
    """Every variable of the study's Dataset (runs, fragilities, MAFs, the gap at target and
    its bootstrap) equals, to the bit, that of the study with every run with contacts
    integrated; and the reuse did happen (some runs reused, some integrated). The first
    runs in chunks of 7 variants (each assembled while the one before runs), the second in
    one batch."""
    reused, t_on = _risk(_study(tmp_path, chunk=7), True, monkeypatch)
    whole, t_off = _risk(_study(tmp_path), False, monkeypatch)
    count = t_on["variants"]
    assert t_off["contact_runs"] == count
    assert 0 < t_on["contact_runs"] < count
    assert int((whole["impact_count"].values.sum(axis=-1) > 0).sum()) > 0  # some pound
    assert sorted(reused.variables) == sorted(whole.variables)
    for name in whole.variables:
        a, b = reused[name].values, whole[name].values
        same = (np.array_equal(a, b, equal_nan=True) if a.dtype.kind in "fc"
                else np.array_equal(a, b))
        assert same, name


@pytest.mark.slow
def test_an_ida_hunt_reusing_open_runs_is_the_hunt_integrating_every_run(tmp_path,
                                                                         monkeypatch):
    """A hunt and fill up to pounding in the runs with contacts: the same rounds, runs and
    Dataset to the bit with the reuse and without it."""
    design = {"kind": "ida", "hunt": {"start": 0.1, "step": 0.2, "growth": 1.5},
              "resolution": 0.1, "limit": "pounding", "condition": "with_pounding",
              "max_level": 2.0}
    path = _study(tmp_path, design=design)
    reused, t_on = _risk(path, True, monkeypatch)
    whole, t_off = _risk(path, False, monkeypatch)
    assert t_on["variants"] == t_off["variants"] == t_off["contact_runs"] > t_on["contact_runs"]
    assert int((whole["impact_count"].values.sum(axis=-1) > 0).sum()) > 0  # some pound
    for name in whole.variables:
        assert np.array_equal(reused[name].values, whole[name].values,
                              equal_nan=reused[name].dtype.kind in "fc"), name


@pytest.mark.slow
def test_different_steps_turn_the_reuse_off(tmp_path, monkeypatch):
    """The runs without contacts on 1 ms, those with contacts on the scene's 2 ms: every run
    with contacts is integrated."""
    _, timings = _risk(_study(tmp_path, study_dt=DT / 2), True, monkeypatch)
    assert timings["contact_runs"] == timings["variants"]


def test_reuse_needs_the_same_steps_and_laws_free_while_open(monkeypatch):
    from pframe.laws.contact.improved_kelvin import ImprovedKelvin

    loaded = load_scene(PAIR)
    assert runs.reusable(loaded, (4000, 0.001), 4000, 0.001)
    assert not runs.reusable(loaded, (4000, 0.001), 4001, 0.001)
    assert not runs.reusable(loaded, (4000, 0.002), 4000, 0.001)
    monkeypatch.setattr(ImprovedKelvin, "free_when_open", False)  # as a plug-in law
    assert not runs.reusable(loaded, (4000, 0.001), 4000, 0.001)


@pytest.mark.slow
def test_a_run_within_a_hair_of_a_gap_is_integrated_with_its_contacts():
    """Motions scaled (by bisection) so that the peak closing ends a hair below the gap
    (1e-12 m and less) or a hair above it: each run is integrated with its contacts, and the
    result is that of integrating it (a Newton iterate of such a run may cross the gap that
    the committed steps never reach); a weak motion's run beside them is reused."""
    loaded = load_scene(PAIR)
    pairs = contact_pairs(loaded)
    gap = float(pairs.gaps.min())
    steps, dt = 1500, 0.001
    t = np.arange(steps + 1) * dt
    rng = np.random.default_rng(3)
    f, phase = rng.uniform(0.5, 3.0, 6), rng.uniform(0.0, 6.0, 6)
    shape = np.sin(2 * np.pi * f[:, None] * t + phase[:, None]) * np.exp(-t)
    shape = np.concatenate([shape, shape, shape[:1]])

    def free(amplitude):
        return runs.run_batch(loaded, pairs, amplitude[:, None] * shape, steps, dt,
                              contacts=False, reach=True)

    lo, hi = np.zeros(6), np.full(6, 40.0)
    for _ in range(60):
        mid = 0.5 * (lo + hi)
        below = runs.run_batch(loaded, pairs, mid[:, None] * shape[:6], steps, dt,
                               contacts=False)["g_req"].max(axis=1) < gap
        lo, hi = np.where(below, mid, lo), np.where(below, hi, mid)
    amplitude = np.concatenate([lo, hi, [0.1 * lo[0]]])  # a hair below, above; far below
    out = free(amplitude)
    closing = out["g_req"].max(axis=1)
    assert np.all(closing[:6] < gap) and np.all(gap - closing[:6] < 1e-12)
    assert np.all(closing[6:12] >= gap) and closing[12] < 0.5 * gap
    motions = amplitude[:, None] * shape
    hit = runs.with_contacts(loaded, pairs, out, (steps, dt), lambda i: motions[i], steps, dt)
    assert hit["integrated"].tolist() == [1] * 12 + [0]
    direct = runs.run_batch(loaded, pairs, motions, steps, dt, contacts=True)
    for key, value in direct.items():
        if key != "solve_seconds":
            assert np.array_equal(hit[key], value, equal_nan=True), key


@pytest.mark.slow
@pytest.mark.parametrize("integrator, facts", integrator_cases())
def test_an_open_run_is_its_run_with_contacts_under_every_integrator(integrator, facts,
                                                                    tmp_path):
    """Under every integrator the reuse allows (each example, and on the event-aware path),
    the runs of a batch whose contacts cannot close (reach below every gap) are their runs
    with contacts to the bit: peaks, drifts, accelerations, the critical gap."""
    scene = yaml.safe_load(PAIR.read_text(encoding="utf-8"))
    scene["analysis"]["integrator"] = integrator
    path = tmp_path / "scene.yaml"
    path.write_text(yaml.safe_dump(scene, sort_keys=False), encoding="utf-8")
    loaded = load_scene(path)
    pairs = contact_pairs(loaded)
    steps, dt = 1500, 0.001
    if not runs.reusable(loaded, (steps, dt), steps, dt):
        # refused here for an explicit integrator only: it may take sub-steps for the
        # contacts' stiffness, so its runs with contacts step differently
        from pframe.assemble import assemble

        assert assemble(loaded.expanded).integrator.explicit, integrator
        return
    t = np.arange(steps + 1) * dt
    rng = np.random.default_rng(5)
    amplitude, f = rng.uniform(1.0, 14.0, 12), rng.uniform(0.5, 3.0, 12)
    motions = amplitude[:, None] * np.sin(2 * np.pi * f[:, None] * t) * np.exp(-t)
    free = runs.run_batch(loaded, pairs, motions, steps, dt, contacts=False, reach=True)
    hit = runs.run_batch(loaded, pairs, motions, steps, dt, contacts=True)
    open_ = np.all(free["reach"] < pairs.gaps, axis=1)
    assert open_.any() and not open_.all()
    for key, value in free.items():
        if key not in ("solve_seconds", "reach"):
            assert np.array_equal(value[open_], hit[key][open_], equal_nan=True), key
