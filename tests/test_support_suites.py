"""Gap audits and risk studies over suites whose members give a motion per support
(docs/supports.md#suites-of-a-motion-per-support): the same record at every support is one
ground; a delayed copy per support is the wave passage; a coherent simulation per member is
the scene run alone with that record and seed."""

from __future__ import annotations

import json

import numpy as np
import pytest
from conftest import node_history, record_file, run_text
from test_supports import pair

import pframe.gap
from pframe.errors import InputError

SUPPORTS = [{"name": "west", "position": [0.0, 0.0]}, {"name": "east", "position": [60.0, 0.0]}]
CONTACT = [{"nodes": ["A/3", "B/3"], "gap": 10.0, "law": "linear", "stiffness": 1e9}]
RULES = ("simulated", "ABS", "SRSS", "DDC")


def _scene(tmp_path, name, supports=None, excitation=None, duration=6.0, dt=0.01,
           quantities=("displacement",), gap=10.0) -> tuple:
    scene = pair(supports, excitation, contacts=[CONTACT[0] | {"gap": gap}], dt=dt,
                 duration=duration, quantities=quantities)
    for b in scene["buildings"]:
        b["height"] = 3.5
    path = tmp_path / f"{name}.yaml"
    path.write_text(json.dumps(scene), encoding="utf-8")
    return path, scene


def _suite(tmp_path, name, records, **more):
    path = tmp_path / f"{name}.suite.yaml"
    path.write_text(json.dumps({"records": records} | more), encoding="utf-8")
    return path


def _gaps(ds) -> np.ndarray:
    return np.array([ds.gap_required.sel(rule=r).values for r in RULES])


def _copy(tmp_path, name, shift: int = 0) -> str:
    """elCentro as two columns (s, m/s^2) beside the suite, ``shift`` steps later (zeros
    before): the bits of the record as a suite reads it."""
    from pframe.excitation.records import read_record

    t, a = read_record(record_file("elCentro.AT2"))
    a = np.concatenate([np.zeros(shift), a])
    t = np.arange(a.size) * (t[1] - t[0])
    path = tmp_path / name
    path.write_text("".join(f"{float(x)!r} {float(y)!r}\n" for x, y in zip(t, a)),
                    encoding="utf-8")
    return name


@pytest.mark.slow
def test_the_same_record_at_every_support_is_one_ground(tmp_path):
    """A member naming elCentro at both supports: every rule and the simulated gap of the
    one-ground audit under elCentro, at two PGA levels, to 1e-9 (the intensity measured at
    the first support named, every support scaled by its factor, as the file says)."""
    record = _copy(tmp_path, "elcentro.txt")
    one, _ = _scene(tmp_path, "one")
    two, _ = _scene(tmp_path, "two", SUPPORTS)
    levels = {"levels": [0.2, 0.5]}
    plain = pframe.gap.audit(one, _suite(tmp_path, "plain", [record], **levels), duration=6.0)
    per = pframe.gap.audit(two, _suite(tmp_path, "per", [{"supports": {
        "east": record, "west": record}}], **levels), duration=6.0)
    assert np.max(_gaps(plain)) > 1e-3
    np.testing.assert_allclose(_gaps(per), _gaps(plain), rtol=1e-9, atol=0)
    np.testing.assert_allclose(per.intensity.values, plain.intensity.values, rtol=1e-12)
    assert list(per.record_intensity_support.values) == ["east"]  # the first named
    assert "reference support" in per.level.attrs["long_name"]


@pytest.mark.slow
def test_a_delayed_copy_per_support_is_the_wave_passage(tmp_path):
    """Supports 60 m apart, waves at 150 m/s along x: east is reached 0.4 s (40 steps)
    later. A member giving west elCentro and east elCentro 0.4 s (20 of its samples) later is the wave
    passage's audit of elCentro, rule for rule and level for level, to 1e-9; the delay
    widens the simulated gap by more than 30 % over the same record at both supports."""
    passage = {"kind": "wave_passage", "velocity": 150.0,
               "motion": {"kind": "sine", "amplitude": 1.0, "frequency": 1.0}}
    carried, _ = _scene(tmp_path, "passage", SUPPORTS, passage)
    per, _ = _scene(tmp_path, "per", SUPPORTS)
    levels = {"levels": [0.3, 0.6]}
    # from rest (a zero first): a delay of a motion that starts with a jump is the jump
    # delayed, which a record read between samples is not
    one = _suite(tmp_path, "one", [_copy(tmp_path, "a.txt", 1)], **levels)
    expected = pframe.gap.audit(carried, one, duration=6.0)
    found = pframe.gap.audit(per, _suite(tmp_path, "two", [{"supports": {
        "west": "a.txt", "east": _copy(tmp_path, "b.txt", 21)}}], **levels), duration=6.0)
    np.testing.assert_allclose(_gaps(found), _gaps(expected), rtol=1e-9, atol=0)
    ground = pframe.gap.audit(per, _suite(tmp_path, "same", [{"supports": {
        "west": "a.txt", "east": "a.txt"}}], **levels), duration=6.0)
    simulated = lambda ds: ds.gap_required.sel(rule="simulated").values  # noqa: E731
    assert np.all(simulated(found) > 1.3 * simulated(ground))


def _coherent_scene(tmp_path, name, excitation, duration=6.0):
    excitation = {"kind": "coherent", "seed": 7, "velocity": 400.0,
                  "coherency": {"model": "luco_wong", "incoherence": 0.3,
                                "shear_velocity": 400.0},
                  "motion": {"kind": "stochastic", "model": "clough_penzien",
                             "intensity": 0.01, "ground_frequency": 15.0,
                             "ground_damping": 0.6, "duration": 4.0}} | excitation
    return _scene(tmp_path, name, SUPPORTS, excitation, duration=duration,
                  quantities=("displacement", "contact_ground_displacement"))


def _alone(scene: dict) -> float:
    """The scene's own run: its contact's critical gap, max (u_A - u_B + ground part)."""
    plan, result = run_text(json.dumps(scene))
    a = node_history(plan, result, "displacement", "A/3")
    b = node_history(plan, result, "displacement", "B/3")
    return float(np.max(a - b + result.history["contact_ground_displacement"][0][:, 0]))


@pytest.mark.slow
def test_a_coherent_simulation_per_member_is_the_scene_alone(tmp_path):
    """A coherent scene conditioned at west, under a suite of two records: member i is the
    scene run alone with that record and seed 7 + i (its critical gap to 1e-9), the
    audit again gives the same bits; unconditioned realisations likewise."""
    records = [_copy(tmp_path, "a.txt"), _copy(tmp_path, "b.txt", 30)]
    path, scene = _coherent_scene(tmp_path, "coherent", {
        "record": {"kind": "record", "file": records[0]}, "at": "west"})
    suite = _suite(tmp_path, "records", records)
    ds = pframe.gap.audit(path, suite, duration=6.0)
    again = pframe.gap.audit(path, suite, duration=6.0)
    np.testing.assert_array_equal(ds.gap_required.values, again.gap_required.values)
    simulated = ds.gap_required.sel(rule="simulated").values.reshape(2)
    for i, file in enumerate(records):
        alone = json.loads(json.dumps(scene))
        alone["excitation"] |= {"record": {"kind": "record", "file": str(tmp_path / file)},
                                "seed": 7 + i}
        assert simulated[i] == pytest.approx(_alone(alone), rel=1e-9)
    assert list(ds.record_name.values) == ["a.txt@west-seed7", "b.txt@west-seed8"]
    assert list(ds.record_intensity_support.values) == ["west", "west"]  # at
    path, scene = _coherent_scene(tmp_path, "free", {})
    suite = _suite(tmp_path, "free", [], coherent={"realisations": 2})
    simulated = pframe.gap.audit(path, suite, duration=6.0).gap_required.sel(
        rule="simulated").values.reshape(2)
    for i in range(2):
        assert simulated[i] == pytest.approx(_alone(scene | {"excitation": scene[
            "excitation"] | {"seed": 7 + i}}), rel=1e-9)


def test_an_own_wave_passage_is_its_single_run(tmp_path):
    """The audit of a wave passage's own motion (no suite) whose first support is not the
    first the waves reach: each support takes the motion with its delay once (it was
    delayed twice, the first support's delayed samples taken for the motion)."""
    supports = [{"name": "east", "position": [60.0, 0.0]},
                {"name": "west", "position": [0.0, 0.0]}]
    passage = {"kind": "wave_passage", "velocity": 150.0,
               "motion": {"kind": "ricker", "amplitude": 5.0, "period": 0.5, "center": 0.75}}
    path, scene = _scene(tmp_path, "own", supports, passage, duration=1.3, dt=0.005,
                         quantities=("displacement", "contact_ground_displacement"))
    found = float(pframe.gap.audit(path).gap_required.sel(rule="simulated").values.ravel()[0])
    expected = _alone(scene)
    assert expected > 0.01  # m
    assert found == pytest.approx(expected, rel=1e-9)


def test_members_the_scene_cannot_take_are_refused(tmp_path):
    """A member without a motion for a support, a support the scene does not have, records
    of different steps, a motion per support on one ground, one motion for supports with
    motions of their own: InputError at the suite's file, line and field."""
    path, _ = _scene(tmp_path, "two", SUPPORTS)
    one, _ = _scene(tmp_path, "one")
    a = _copy(tmp_path, "a.txt")
    coarse = tmp_path / "coarse.txt"
    coarse.write_text("0 0\n0.05 1\n0.1 0\n", encoding="utf-8")

    def refused(scene, records, match):
        suite = _suite(tmp_path, "bad", records)
        with pytest.raises(InputError, match=match):
            pframe.gap.audit(scene, suite, duration=1.0)

    refused(path, [{"supports": {"west": a}}],
            r"bad\.suite\.yaml, line 1, records\[0\]\.supports: no motion for support east")
    refused(path, [{"supports": {"west": a, "east": a, "north": a}}],
            r"bad\.suite\.yaml, line 1, records\[0\]\.supports\.north: the scene .* has no "
            r"support 'north'; its supports are west, east")
    refused(path, [{"supports": {"west": a, "east": "coarse.txt"}}],
            r"records\[0\]\.supports\.east: coarse\.txt is sampled every 0\.05 s and west's "
            r"record every 0\.02 s")
    refused(one, [{"supports": {"west": a, "east": a}}],
            r"records\[0\]: a motion per support, and the scene .* stands on one ground")
    own = SUPPORTS[:1] + [SUPPORTS[1] | {"excitation": {"kind": "sine", "amplitude": 1.0,
                                                          "frequency": 2.0}}]
    scene, _ = _scene(tmp_path, "own", own)
    refused(scene, [a], r"records\[0\]: a\.txt is one motion, and the supports east .* "
                        r"have motions of their own")


@pytest.mark.slow
@pytest.mark.parametrize("design", [
    {"kind": "msa", "levels": [0.3, 0.6]},
    {"kind": "ida", "hunt": {"start": 0.1, "step": 0.1}, "resolution": 0.05, "limit": "LS",
     "max_level": 1.5}], ids=["msa", "ida"])
def test_a_risk_study_over_a_record_per_support(tmp_path, design):
    """A study (runs without and with the contacts; stripes, or IDA's hunt and fill) of the
    pair on two supports whose member gives both elCentro: the intensities, critical gaps,
    drifts and impacts of the study of the pair on one ground under elCentro, to 1e-9."""
    import xarray as xr
    import yaml

    from pframe.cli import main

    record = _copy(tmp_path, "a.txt", 1)
    found = {}
    for name, supports, records in (("one", None, [record]),
                                    ("two", SUPPORTS, [{"supports": {"west": record,
                                                                     "east": record}}])):
        scene, _ = _scene(tmp_path, name, supports, duration=3.0, dt=0.005, gap=0.12)
        study = {"scene": scene.name, "suite": _suite(tmp_path, name, records).name,
                 "measure": "pga", "duration": 3.0,
                 "design": design, "limits": {"drift": {"LS": 0.05}}, "bootstrap": 0}
        path = tmp_path / f"{name}.study.yaml"
        path.write_text(yaml.safe_dump(study), encoding="utf-8")
        out = tmp_path / f"{name}.nc"
        assert main(["risk", str(path), "-o", str(out), "-q"]) == 0
        found[name] = xr.open_dataset(out)
    one, two = found["one"], found["two"]
    assert float(one.critical_gap.max()) > 1e-3
    assert int(one.impact_count.sum()) > 0  # the runs with contacts pound
    for variable in ("intensity", "critical_gap", "peak_story_drift",
                     "peak_floor_acceleration"):
        np.testing.assert_allclose(two[variable].values, one[variable].values, rtol=1e-9,
                                   atol=0)
    np.testing.assert_array_equal(two.impact_count.values, one.impact_count.values)


@pytest.mark.slow
def test_a_conditioned_simulation_scales_with_its_record():
    """Scaling a conditioned member's motions to a level is conditioning on the scaled
    record: the simulation is linear in its record at a seed (its mean a filter of the
    record, its residual's spectrum the record's own), to round-off."""
    from pframe.excitation.coherency import LucoWong, WavePassage
    from pframe.excitation.conditioned import conditioned
    from pframe.excitation.records import read_record

    _, a = read_record(record_file("elCentro.AT2"))
    made = [conditioned(k * a, 0.02, [(0.0, 0.0), (60.0, 0.0)], LucoWong(0.3, 400.0),
                        recorded=0, seed=3, wave=WavePassage(400.0, 0.0)).acceleration
            for k in (1.0, 2.5)]
    assert np.max(np.abs(made[0][1] - made[0][0])) > 0.1  # the other support differs
    np.testing.assert_allclose(made[1], 2.5 * made[0], rtol=0,
                               atol=1e-13 * np.max(np.abs(made[1])))


def test_a_subset_design_on_supports_needs_a_wave_passage(tmp_path, capsys):
    """A subset design over a stochastic motion draws one motion per run, which a scene on
    supports takes through its wave passage: one without (the same sine under both
    supports) is refused with what to write, exit 2 and nothing written (it failed inside
    the runs, a traceback)."""
    import yaml
    from test_risk_subset import MOTION

    from pframe.cli import main

    scene, _ = _scene(tmp_path, "same", SUPPORTS, duration=8.0, gap=0.2)
    study = {"scene": scene.name, "stochastic": MOTION, "duration": 8.0, "dt": 0.01,
             "design": {"kind": "subset", "probability_level": 0.1, "samples": 100},
             "uncertain": {"gap": {"distribution": "lognormal", "median": 0.2,
                                   "dispersion": 0.2}}, "seed": 1}
    path = tmp_path / "study.yaml"
    path.write_text(yaml.safe_dump(study), encoding="utf-8")
    assert main(["risk", str(path), "-o", str(tmp_path / "out.nc"), "-q"]) == 2
    assert "a subset design draws one stochastic motion per run" in capsys.readouterr().err
    assert not (tmp_path / "out.nc").exists()
