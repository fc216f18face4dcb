"""Demand quantities of fragility and loss work: absolute floor acceleration, residual drift,
ductility, impact-induced storey shear, the per-impact table and the Park-Ang damage index."""

from __future__ import annotations

import json
import math

import numpy as np
import pytest
from conftest import run_text, scene_text, two_free_masses_text

import pframe
from pframe.assemble import assemble

MASS, STIFFNESS = 1000.0, 4.0e5


def _sdof(integrator: dict, dt: float, duration: float, recorders: list, amplitude=3.0,
          frequency=9.0, story=None, zeta=0.0, extra=None) -> tuple:
    story = story or {"material": "elastic", "stiffness": STIFFNESS}
    scene = {"buildings": [{"name": "A", "floors": 1, "mass": MASS, "story": story}],
             "damping": {"ratio": zeta, "modes": [1, 1]} if zeta else {"ratio": 0.0},
             "excitation": {"kind": "sine", "amplitude": amplitude, "frequency": frequency},
             "analysis": {"integrator": integrator, "dt": dt, "duration": duration},
             "recorders": recorders}
    scene |= extra or {}
    plan, result = run_text(scene_text(**scene))
    assert result.completed(0), result.describe_failure(0)
    return plan, result


# ---------------------------------------------------------------------------------------------
# absolute acceleration
# ---------------------------------------------------------------------------------------------

def test_absolute_acceleration_is_the_inertia_of_the_storey_force():
    """An undamped elastic SDOF: m (u'' + a_g) = -k u at every committed state (Newmark
    imposes equilibrium at the step end), so the absolute acceleration is -k u / m, whatever
    the ground does."""
    plan, result = _sdof({"type": "newmark", "gamma": 0.5, "beta": 0.25}, 1e-3, 2.0,
                         [{"kind": "history", "quantities": ["displacement",
                                                             "absolute_acceleration"]}])
    u = result.history["displacement"][0, :, 0]
    a = result.history["absolute_acceleration"][0, :, 0]
    assert np.abs(a).max() > 1.0
    np.testing.assert_allclose(a, -STIFFNESS / MASS * u, rtol=0, atol=1e-9 * np.abs(a).max())


def test_absolute_acceleration_envelope_is_the_inertia_of_the_storey_force():
    """The envelope the time loop keeps at each step end (Newmark, whole steps): m a_abs =
    -k u at every committed state of an undamped elastic SDOF, so the peak absolute
    acceleration is k/m times the peak displacement, with the ground of the step's own
    sample (one sample off, the peaks would differ by about the ground's step change)."""
    plan, result = _sdof({"type": "newmark", "gamma": 0.5, "beta": 0.25}, 1e-3, 2.0,
                         [{"kind": "envelope", "quantities": ["displacement",
                                                              "absolute_acceleration"]}])
    peak_u = result.envelope["displacement"][0, 0]
    peak_a = result.envelope["absolute_acceleration"][0, 0]
    assert peak_a > 1.0
    assert peak_a == pytest.approx(STIFFNESS / MASS * peak_u, rel=1e-9)


def test_absolute_acceleration_envelope_sees_substeps_with_their_ground():
    """Central difference in sub-steps: each committed sub-step is in equilibrium,
    m a_abs = -k u, with the ground interpolated to the sub-step. The envelope of the absolute
    acceleration is k/m times the displacement's envelope (both gathered at every sub-step);
    with the step end's ground acceleration at the sub-steps it was not."""
    plan, result = _sdof({"type": "central_difference", "substeps": "auto", "safety": 0.05},
                         0.02, 1.0,
                         [{"kind": "envelope", "quantities": ["displacement",
                                                              "absolute_acceleration"]}],
                         amplitude=10.0, frequency=30.0)
    assert plan.cd_parts[0] > 1
    peak_u = result.envelope["displacement"][0, 0]
    peak_a = result.envelope["absolute_acceleration"][0, 0]
    assert peak_a == pytest.approx(STIFFNESS / MASS * peak_u, rel=1e-9)


# ---------------------------------------------------------------------------------------------
# the impact table
# ---------------------------------------------------------------------------------------------

M1, M2, K_CONTACT, V1 = 1000.0, 2000.0, 1.0e7, 1.2
M_EFF = M1 * M2 / (M1 + M2)
GAP = 0.01


def _two_masses(dt: float, recorders: list, v2: float = 0.0):
    """Two free masses, the left one at V1 towards the right one at v2, a linear contact
    across a gap of 0.01 m: one elastic impact."""
    text = two_free_masses_text(M1, M2, {"law": "linear", "stiffness": K_CONTACT}, V1, v2,
                                dt, 0.05, gap=GAP)
    scene = json.loads(text)
    scene["recorders"] = recorders
    return pframe.solve(scene)


EVERY_STEP = [{"kind": "history", "quantities": ["velocity", "contact_force",
                                                 "contact_penetration"]}]


@pytest.mark.parametrize("v2", [0.0, -0.3])
def test_impact_table_of_one_elastic_impact_is_the_closed_form(v2):
    """A linear contact between free masses: the contact is a half sine of duration
    pi sqrt(m_eff / k), peak v sqrt(k m_eff) and impulse 2 m_eff v, v = v1 - v2 the approach
    velocity, starting when the gap has closed (t = gap / v); the impulse is also the
    momentum each mass gained, m1 (v1_after - v1_before)."""
    ds = _two_masses(1e-5, EVERY_STEP, v2)
    table = pframe.impacts(ds)
    assert len(table) == 1
    row = table.iloc[0]
    v = V1 - v2
    assert row.contact == "c"
    assert row.onset == pytest.approx(GAP / v, rel=1e-6)
    assert row.approach_velocity == pytest.approx(v, rel=1e-6)
    assert row.duration == pytest.approx(math.pi * math.sqrt(M_EFF / K_CONTACT), rel=1e-5)
    assert row.peak_force == pytest.approx(v * math.sqrt(K_CONTACT * M_EFF), rel=1e-5)
    assert row.impulse == pytest.approx(2.0 * M_EFF * v, rel=1e-5)
    left = ds.velocity.sel(node="L/1").values
    assert row.impulse == pytest.approx(-M1 * (left[-1] - left[0]), rel=1e-5)
    assert not row.closed_at_start and not row.closed_at_end


def test_impact_table_converges_at_second_order_without_the_penetration():
    """Without the penetration history the onset and separation come from the force alone:
    still the closed form, its error shrinking with dt."""
    duration = math.pi * math.sqrt(M_EFF / K_CONTACT)
    errors = []
    for dt in (4e-4, 2e-4):
        ds = _two_masses(dt, [{"kind": "history", "quantities": ["velocity", "contact_force"]}])
        errors.append(abs(pframe.impacts(ds).duration.iloc[0] - duration) / duration)
    assert errors[1] < 0.3 * errors[0] and errors[1] < 1e-4  # 4.3 times smaller here


def test_impact_table_names_the_histories_it_needs():
    ds = _two_masses(1e-4, [{"kind": "envelope", "quantities": ["contact_force"]}])
    with pytest.raises(pframe.InputError, match="contact_force, velocity"):
        pframe.impacts(ds)


# ---------------------------------------------------------------------------------------------
# hysteretic energy and the Park-Ang damage index
# ---------------------------------------------------------------------------------------------

K_STOREY, FY, ALPHA = 2.0e6, 1.0e4, 0.1
UY = FY / K_STOREY


def _bilinear_loops(amplitude: float, cycles: int, samples: int = 4000):
    """The bilinear law's own force along a prescribed drift 0 -> D, then ``cycles`` full
    cycles D -> -D -> D (straight lines): (drift, force)."""
    from pframe.laws import get_law

    law = get_law("material", "bilinear")
    params = (K_STOREY, FY, ALPHA)
    path = [np.linspace(0.0, amplitude, samples)]
    for _ in range(cycles):
        path += [np.linspace(amplitude, -amplitude, 2 * samples)[1:],
                 np.linspace(-amplitude, amplitude, 2 * samples)[1:]]
    drift = np.concatenate(path)
    committed, force = [0.0, 0.0], np.empty_like(drift)
    for i, d in enumerate(drift):
        trial = [0.0, 0.0]
        force[i] = law.force(params, committed, trial, float(d), 0.0)[0]
        committed = trial
    return drift, force


@pytest.mark.parametrize("cycles", [1, 3])
def test_hysteretic_energy_is_the_loop_area_of_a_bilinear_storey(cycles):
    """Under cycles of amplitude D the bilinear loop is a parallelogram of area
    4 (1 - alpha) F_y (D - u_y); the first loading 0 -> D dissipates its work less the
    elastic energy F_max^2 / (2 k) it stores. The Park-Ang index follows:
    DI = D / d_u + beta E_h / (F_y d_u)."""
    from pframe.demands import hysteretic_energy, park_ang_index

    amplitude = 5.0 * UY
    drift, force = _bilinear_loops(amplitude, cycles)
    f_max = ALPHA * K_STOREY * amplitude + (1.0 - ALPHA) * FY
    first = 0.5 * FY * UY + 0.5 * (FY + f_max) * (amplitude - UY) - f_max**2 / (2 * K_STOREY)
    loop = 4.0 * (1.0 - ALPHA) * FY * (amplitude - UY)
    expected = first + cycles * loop
    energy = hysteretic_energy(force[:, None], drift[:, None], [K_STOREY])[0]
    assert energy == pytest.approx(expected, rel=1e-6)
    du, beta = 10.0 * UY, 0.05
    index = park_ang_index(np.abs(drift).max(), du, beta, energy, FY)
    assert index == pytest.approx(amplitude / du + beta * expected / (FY * du), rel=1e-6)


BILINEAR = {"material": "bilinear", "stiffness": K_STOREY, "yield_force": FY, "alpha": ALPHA}


def _yielding_building(recorders, park_ang=None, **story):
    scene = {"buildings": [{"name": "A", "floors": 2, "mass": 2000.0,
                            "story": story or BILINEAR}],
             "damping": {"ratio": 0.02, "modes": [1, 2]},
             "excitation": {"kind": "sine", "amplitude": 6.0, "frequency": 12.0},
             "analysis": {"integrator": {"type": "newmark", "gamma": 0.5, "beta": 0.25},
                          "dt": 5e-4, "duration": 3.0},
             "recorders": recorders}
    if park_ang:
        scene["buildings"][0]["park_ang"] = park_ang
    return pframe.solve(scene)


STOREY_HISTORIES = [{"kind": "history", "quantities": ["story_force", "story_drift"]}]


def test_hysteretic_energy_of_a_run_closes_with_the_kernels_storey_work():
    """The storeys' work integrated from their histories (every step) is the kernel's own
    energy_storeys, booked step by step; the summary's hysteretic energy is that work less
    the elastic energy stored at the end, and the damage index its Park-Ang combination."""
    from pframe.demands import park_ang

    ds = _yielding_building(STOREY_HISTORIES, {"ultimate_drift": [0.05, 0.04], "beta": 0.1})
    rows = park_ang(ds)
    force, drift = ds.story_force.values, ds.story_drift.values
    stored = force[-1] ** 2 / (2 * K_STOREY)
    work = sum(rows[n]["energy"] for n in rows) + stored.sum()
    assert work == pytest.approx(float(ds.attrs["energy_storeys"]), rel=1e-9)
    assert np.abs(drift).max() > 2 * UY  # it does yield
    for i, name in enumerate(rows):
        du = (0.05, 0.04)[i]
        peak = np.abs(drift[:, i]).max()
        assert rows[name]["index"] == pytest.approx(
            peak / du + 0.1 * rows[name]["energy"] / (FY * du), rel=1e-12)


def test_ductility_covers_every_yielding_material():
    """The yield drift of the summary's ductility comes from each material's own yield
    drift: bilinear f_y / k, IMK My / K0, Bouc-Wen (A0 / (beta + gamma))^(1/n). Before, only
    the bilinear material had one."""
    from pframe.tables import summary

    bouc_wen = {"material": "bouc_wen", "alpha": 0.1, "ko": K_STOREY, "n": 2.0,
                "gamma": 0.5 / UY**2, "beta": 0.5 / UY**2}
    imk = {"material": "imk_peak", "k0": K_STOREY, "as_plus": 0.05, "as_neg": 0.05,
           "my_plus": FY, "my_neg": FY, "lamda_s": 1e3, "lamda_c": 1e3, "lamda_a": 1e3,
           "lamda_k": 1e3, "c_s": 1.0, "c_c": 1.0, "c_a": 1.0, "c_k": 1.0,
           "theta_p_plus": 0.05, "theta_p_neg": 0.05, "theta_pc_plus": 0.1,
           "theta_pc_neg": 0.1, "res_plus": 0.2, "res_neg": 0.2, "theta_u_plus": 0.4,
           "theta_u_neg": 0.4, "d_plus": 1.0, "d_neg": 1.0}
    for story in (bouc_wen, imk):
        table = summary(_yielding_building(
            [{"kind": "envelope", "quantities": ["story_drift"]}], **story))
        rows = table[(table.part == "story") & (table.quantity == "yield drift")]
        assert len(rows) == 2, story["material"]
        np.testing.assert_allclose(rows.value.astype(float), UY, rtol=1e-12)


# ---------------------------------------------------------------------------------------------
# the storey shear of the contact forces
# ---------------------------------------------------------------------------------------------

def test_impact_storey_shear_closes_each_storeys_equilibrium():
    """Undamped elastic buildings pounding: each storey's shear is the contact forces on the
    floors it carries less their inertia, k d_i = sum_{j above i} (F_c,j - m_j a_j^abs) at
    every step (Newmark imposes equilibrium at the step end), so the impact storey shear is
    k d_i + sum m_j a_j^abs."""
    from pframe.demands import impact_storey_shear

    masses = {"A": 3000.0, "B": 1500.0}
    scene = {"buildings": [{"name": b, "floors": 3, "mass": masses[b],
                            "story": {"material": "elastic", "stiffness": k}}
                           for b, k in (("A", 4.0e6), ("B", 1.0e6))],
             "contacts": [{"name": f"c{i}", "nodes": [f"A/{i}", f"B/{i}"], "gap": 0.005,
                           "law": "linear", "stiffness": 5e7} for i in (2, 3)],
             "damping": {"ratio": 0.0},
             "excitation": {"kind": "sine", "amplitude": 4.0, "frequency": 9.0},
             "analysis": {"integrator": {"type": "newmark", "gamma": 0.5, "beta": 0.25},
                          "dt": 2e-4, "duration": 2.0},
             "recorders": [{"kind": "history", "quantities": [
                 "story_force", "absolute_acceleration", "contact_force"]}]}
    ds = pframe.solve(scene)
    shear = impact_storey_shear(ds)
    assert np.abs(ds.contact_force.values).max() > 0  # it pounds
    for i, name in enumerate(str(s) for s in ds.story.values):
        building, floor = name.split("/")
        above = [f"{building}/{j}" for j in range(int(floor), 4)]
        inertia = sum(masses[building] * ds.absolute_acceleration.sel(node=n).values
                      for n in above)
        expected = ds.story_force.values[:, i] + inertia
        np.testing.assert_allclose(shear[:, i], expected, rtol=0,
                                   atol=1e-6 * np.abs(expected).max())
    assert np.abs(shear).max() > 0


# ---------------------------------------------------------------------------------------------
# residual drift
# ---------------------------------------------------------------------------------------------

K_EPP, FY_EPP, M_EPP = 4.0e5, 4.0e3, 1000.0
UY_EPP = FY_EPP / K_EPP


def _kicked_epp(zeta: float, duration: float):
    """An elastic-perfectly-plastic SDOF kicked by an initial velocity (no ground motion): it
    yields once, to d_max, then swings elastically about d_max - u_y."""
    scene = {"buildings": [{"name": "A", "floors": 1, "mass": M_EPP,
                            "story": {"material": "bilinear", "stiffness": K_EPP,
                                      "yield_force": FY_EPP, "alpha": 0.0}}],
             "damping": {"ratio": zeta, "modes": [1, 1]} if zeta else {"ratio": 0.0},
             "initial_conditions": {"velocity": {"A/1": 0.45}},
             "analysis": {"integrator": {"type": "newmark", "gamma": 0.5, "beta": 0.25},
                          "dt": 1e-3, "duration": duration},
             "recorders": [{"kind": "history", "quantities": ["story_drift"]}]}
    return pframe.solve(scene)


def test_residual_drift_after_a_free_vibration_tail_is_the_permanent_drift():
    """Damped, after 30 periods of free vibration: at rest the storey force is 0, so the
    drift is the peak less the elastic recovery, d_max - u_y; the summary warns of nothing."""
    from pframe.tables import summary

    ds = _kicked_epp(0.05, 10.0)
    peak = float(np.abs(ds.story_drift).max())
    assert peak > 2 * UY_EPP
    table = summary(ds)
    residual = table[(table.part == "story") & (table.quantity == "residual drift")]
    assert float(residual.value.iloc[0]) == pytest.approx(peak - UY_EPP, rel=1e-4)
    assert not (table.part == "warning").any()


def test_a_run_ending_in_motion_warns_that_its_residual_drift_is_not_permanent():
    """Undamped: the storey swings by u_y about d_max - u_y for ever; the end drift is not
    the permanent drift, and the summary says so, naming the storey and its swing."""
    from pframe.demands import residual_drift
    from pframe.tables import summary

    ds = _kicked_epp(0.0, 3.0)
    final, swing = residual_drift(ds)
    assert swing[0] == pytest.approx(UY_EPP, rel=1e-3)
    warnings = summary(ds).query("part == 'warning'").value.tolist()
    assert len(warnings) == 1 and "A/1" in warnings[0] and "free-vibration tail" in warnings[0]


def test_park_ang_ultimate_drifts_are_one_per_storey(tmp_path):
    from pframe.reader import load_scene

    scene = {"buildings": [{"name": "A", "floors": 3, "mass": 1000.0, "story": BILINEAR,
                            "park_ang": {"ultimate_drift": [0.05, 0.04], "beta": 0.05}}],
             "analysis": {"dt": 0.01, "duration": 1.0}}
    path = tmp_path / "scene.yaml"
    path.write_text(json.dumps(scene), encoding="utf-8")
    with pytest.raises(pframe.InputError, match="park_ang.*expected one value per storey"):
        load_scene(path)


def test_solve_prints_the_peak_absolute_floor_acceleration(tmp_path, capsys):
    from pframe.cli import main

    scene = {"buildings": [{"name": "A", "floors": 2, "mass": 2000.0,
                            "story": {"material": "elastic", "stiffness": 4e6}}],
             "damping": {"ratio": 0.05, "modes": [1, 2]},
             "excitation": {"kind": "sine", "amplitude": 3.0, "frequency": 10.0},
             "analysis": {"integrator": {"type": "newmark", "gamma": 0.5, "beta": 0.25},
                          "dt": 1e-3, "duration": 1.0},
             "recorders": [{"kind": "history", "quantities": ["absolute_acceleration"]}]}
    path = tmp_path / "scene.yaml"
    path.write_text(json.dumps(scene), encoding="utf-8")
    assert main(["solve", str(path), "-o", str(tmp_path / "run.nc")]) == 0
    with pframe.open(tmp_path / "run.nc") as ds:
        peak = np.abs(ds.absolute_acceleration.values).max(axis=0)
        top = str(ds.node.values[int(np.argmax(peak))])
    assert f"peak absolute floor acceleration {peak.max():.4g} m/s^2 at {top}" in \
        capsys.readouterr().out


@pytest.mark.slow
def test_impact_table_agrees_with_the_reference_solvers_episodes():
    """Two yielding buildings pounding through linear contacts under a sine: every impact of
    the table (kernel histories at every step) is an episode of the reference solution
    (scipy's DOP853 at tight tolerances, restarted at each onset and separation): the same
    count, the onset to 1e-6 s, and approach velocity, peak force and duration to 1e-4 (about
    1e-5 here; storey A/1 yields to 1.4 times its yield drift)."""
    from pframe.api import loaded_scene
    from pframe.reference import of_scene, solve

    scene = {"buildings": [{"name": "A", "floors": 2, "mass": 1000.0,
                            "story": {"material": "bilinear", "stiffness": 2e6,
                                      "yield_force": 1.5e4, "alpha": 0.1}},
                           {"name": "B", "floors": 2, "mass": 3000.0,
                            "story": {"material": "bilinear", "stiffness": 1.5e7,
                                      "yield_force": 2e5, "alpha": 0.1}}],
             "contacts": [{"name": f"c{i}", "nodes": [f"A/{i}", f"B/{i}"], "gap": 0.01,
                           "law": "linear", "stiffness": 5e7} for i in (1, 2)],
             "damping": {"ratio": 0.05, "modes": [1, 2]},
             "excitation": {"kind": "sine", "amplitude": 4.0, "frequency": 25.0},
             "analysis": {"integrator": {"type": "newmark", "gamma": 0.5, "beta": 0.25},
                          "dt": 5e-5, "duration": 1.0},
             "recorders": EVERY_STEP}
    ds = pframe.solve(scene)
    table = pframe.impacts(ds)
    loaded = loaded_scene(scene)
    plan = assemble(loaded.expanded)
    reference = solve(plan, ground=of_scene(loaded))
    episodes = [e for e in reference.episodes if e.counted and np.isfinite(e.separation)]
    assert len(table) == len(episodes) >= 3
    names = plan.contact_names
    for row, episode in zip(table.itertuples(), sorted(episodes, key=lambda e: e.onset)):
        assert row.contact == names[episode.contact]
        assert row.onset == pytest.approx(episode.onset, abs=1e-6)
        assert row.approach_velocity == pytest.approx(episode.approach_rate, rel=1e-4)
        assert row.peak_force == pytest.approx(episode.peak_force, rel=1e-4)
        assert row.duration == pytest.approx(episode.separation - episode.onset, rel=1e-4)


def test_a_generic_storey_takes_its_own_park_ang():
    """A storey of the generic list (not a building's shorthand) carries its own ultimate
    drift and beta; the index is its Park-Ang combination, the storey without one has none."""
    from pframe.demands import park_ang

    story = BILINEAR | {"park_ang": {"ultimate_drift": 0.04, "beta": 0.2}}
    scene = {"nodes": [{"name": "N/1", "mass": 2000.0}, {"name": "N/2", "mass": 2000.0}],
             "stories": [story | {"nodes": ["ground", "N/1"]},
                         BILINEAR | {"nodes": ["N/1", "N/2"]}],
             "damping": {"ratio": 0.02, "modes": [1, 2]},
             "excitation": {"kind": "sine", "amplitude": 6.0, "frequency": 12.0},
             "analysis": {"integrator": {"type": "newmark", "gamma": 0.5, "beta": 0.25},
                          "dt": 5e-4, "duration": 2.0},
             "recorders": STOREY_HISTORIES}
    rows = park_ang(pframe.solve(scene))
    first, second = rows["N/1"], rows["N/2"]
    assert first["index"] == pytest.approx(
        first["peak_drift"] / 0.04 + 0.2 * first["energy"] / (FY * 0.04), rel=1e-12)
    assert first["energy"] > 0 and "index" not in second
