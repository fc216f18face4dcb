"""A motion for every support (docs/supports.md): identical supports are today's scene; a
delayed copy of one motion moves the second building later by the delay; an element across
supports sees the ground displacements' difference; the kernel's relative formulation is the
total-coordinate integration of the same scene with the supports' motion imposed."""

from __future__ import annotations

import functools
import json

import numpy as np
import pytest
from conftest import analysis, building, integrator_cases, node_history, record_file, run_text

from pframe.errors import InputError
from pframe.reader import parse_scene

MASS, K = 2.0e5, 1.0e8


def pair(supports=None, excitation=None, links=(), contacts=(), dt=0.005, duration=4.0,
         quantities=("displacement",), **more) -> dict:
    """Two three-storey frames A and B (their first floors 3 m apart on the site), on
    supports west and east when ``supports`` says so."""
    scene = {
        "buildings": [building("A", 3, MASS, {"material": "elastic", "stiffness": K}),
                      building("B", 3, MASS, {"material": "elastic", "stiffness": 2 * K})],
        "links": list(links), "contacts": list(contacts),
        "excitation": excitation or {"kind": "sine", "amplitude": 3.0, "frequency": 9.0},
        "damping": {"ratio": 0.05},
        "analysis": analysis(dt, duration),
        "recorders": [{"kind": "history", "quantities": list(quantities)}],
    } | more
    if supports:
        scene["supports"] = supports
        scene["buildings"][0]["support"] = "west"
        scene["buildings"][1]["support"] = "east"
    return scene


SUPPORTS = [{"name": "west", "position": [0.0, 0.0]}, {"name": "east", "position": [40.0, 0.0]}]


def _run(scene: dict):
    return run_text(json.dumps(scene))


def test_identical_supports_are_todays_scene():
    """Two supports under one motion, a contact and a link across them: the same bits as the
    scene on one ground (the ground displacements' difference, d_west - d_east, is 0 to the
    bit)."""
    contacts = [{"nodes": ["A/3", "B/3"], "gap": 0.005, "law": "linear", "stiffness": 1e9}]
    links = [{"nodes": ["A/2", "B/2"], "material": "viscous", "damping": 1e5}]
    today = _run(pair(links=links, contacts=contacts,
                      quantities=("displacement", "contact_force", "link_force")))[1]
    plan, both = _run(pair(SUPPORTS, links=links, contacts=contacts,
                           quantities=("displacement", "contact_force", "link_force")))
    assert plan.channels == ("west:x", "east:x")
    assert plan.contact_ground_start.tolist() == [0, 2]  # the contact is across the supports
    assert int(today.impacts.sum()) > 0
    for q in ("displacement", "contact_force", "link_force"):
        np.testing.assert_array_equal(both.history[q], today.history[q])
    np.testing.assert_array_equal(both.energy, today.energy)


def test_a_delayed_copy_moves_the_second_building_later():
    """A wave passage at 400 m/s over 10 m, a delay of 25 steps, of a sine that starts from
    zero (a(0) = 0: A starts from rest as B does when the waves reach it): B (as A) responds
    0.025 s later, u_B(t) = u_A(t - 0.025), to the bit; and a contact between them (1 N/m,
    gap 0, a force too small to matter) closes by their relative motion plus the ground
    displacements' difference d(t) - d(t - tau), the sine integrated twice by the trapezoid
    rule, to 1e-6 of its peak (what its force changes)."""
    supports = [{"name": "west", "position": [0.0, 0.0]},
                {"name": "east", "position": [10.0, 0.0]}]
    scene = pair(supports, {"kind": "wave_passage", "velocity": 400.0,
                            "motion": {"kind": "sine", "amplitude": 3.0, "frequency": 9.0,
                                       "cycles": 6}},
                 dt=0.001, duration=6.0, quantities=("displacement", "contact_penetration"))
    scene["buildings"][1]["story"]["stiffness"] = K  # B as A
    plan, result = _run(scene)
    k = 25
    a = node_history(plan, result, "displacement", "A/1")
    b = node_history(plan, result, "displacement", "B/1")
    assert np.max(np.abs(a)) > 0.005
    np.testing.assert_array_equal(b[:k], 0.0)
    np.testing.assert_array_equal(b[k:], a[:-k])
    scene["contacts"] = [{"nodes": ["A/1", "B/1"], "gap": 0.0, "law": "linear",
                          "stiffness": 1.0}]
    plan, result = _run(scene)
    a = node_history(plan, result, "displacement", "A/1")
    b = node_history(plan, result, "displacement", "B/1")
    from pframe.model.support_motion import integrated

    ground = plan.ground_channels[0]
    np.testing.assert_array_equal(ground[1][k:], ground[0][:-k])
    _, d_west = integrated(ground[0], 0.001)
    _, d_east = integrated(ground[1], 0.001)
    closing = (a + d_west) - (b + d_east)
    penetration = result.history["contact_penetration"][0][:, 0]
    np.testing.assert_allclose(penetration, np.maximum(closing, 0.0), rtol=0,
                               atol=1e-9 * np.max(np.abs(closing)))
    assert np.max(np.abs(d_west - d_east)) > 0.3 * np.max(np.abs(closing))


def _total_newmark(plan, k_a: float, k_b: float, k_link: float) -> np.ndarray:
    """The pair with an elastic link between A/2 and B/2 integrated in total coordinates, an
    implementation independent of pframe's (its relative coordinates and ground terms):
    Newmark's average acceleration on the floors' total displacements x,

        M x'' + a0 M (x' - v_s) + sum_storeys (k d + a1 k d') + k_link (x_B2 - x_A2) = 0,

    each storey's deformation d = x_upper - x_lower with the ground end at its support's
    displacement d_s (west under A, east under B), the supports' displacements and velocities
    the trapezoid rule twice over their accelerations. Returns x (steps + 1, 6) in the order
    A/1..3, B/1..3. a0 and a1 are the plan's (the damping's fit is not what is checked)."""
    from pframe.model.support_motion import integrated

    dt, steps = float(plan.dt[0]), plan.steps
    (v_w, d_w), (v_e, d_e) = (integrated(g, dt) for g in plan.ground_channels[0])
    order = [plan.node_dof[plan.node_names.index(f"{b}/{i}")] for b in "AB" for i in (1, 2, 3)]
    m = plan.mass[0][order]
    a0 = (plan.mass_damping[0] / plan.mass[0])[order]
    a1 = plan.story_beta[0][:6]  # the storeys A/1..3, B/1..3 in declaration order
    K, C = np.zeros((6, 6)), np.diag(a0 * m)
    # storey spring s between floors (lower, upper), -1 the ground
    storeys = [(-1, 0), (0, 1), (1, 2), (-1, 3), (3, 4), (4, 5)]
    stiff = [k_a] * 3 + [k_b] * 3
    for (lo, up), k, b in zip(storeys, stiff, a1):
        g = np.zeros(6)
        g[up] = 1.0
        if lo >= 0:
            g[lo] = -1.0
        K += k * np.outer(g, g)
        C += b * k * np.outer(g, g)
    g = np.zeros(6)
    g[4], g[1] = 1.0, -1.0
    K += k_link * np.outer(g, g)

    def force(n):  # what the moving supports put into the floors at step n
        f = a0 * m * np.r_[[v_w[n]] * 3, [v_e[n]] * 3]
        f[0] += stiff[0] * d_w[n] + a1[0] * stiff[0] * v_w[n]
        f[3] += stiff[3] * d_e[n] + a1[3] * stiff[3] * v_e[n]
        return f

    M = np.diag(m)
    x, v = np.zeros(6), np.zeros(6)
    acc = np.linalg.solve(M, force(0) - C @ v - K @ x)
    out = np.zeros((steps + 1, 6))
    effective = M + 0.5 * dt * C + 0.25 * dt * dt * K
    for n in range(steps):
        x_pred = x + dt * v + 0.25 * dt * dt * acc
        v_pred = v + 0.5 * dt * acc
        acc = np.linalg.solve(effective, force(n + 1) - C @ v_pred - K @ x_pred)
        x = x_pred + 0.25 * dt * dt * acc
        v = v_pred + 0.5 * dt * acc
        out[n + 1] = x
    return out, d_w, d_e


def test_the_relative_formulation_is_the_total_one():
    """Two frames on two supports with different motions (a record at west, a sine at east),
    an elastic link across: pframe's floors relative to their supports, plus their supports'
    displacements, are the total displacements of an independent total-coordinate Newmark
    integration (_total_newmark), to 1e-10 of the peak; the energy balance closes."""
    record = record_file("elCentro.AT2")
    supports = [{"name": "west", "position": [0.0, 0.0],
                 "excitation": {"kind": "record", "file": str(record)}},
                {"name": "east", "position": [30.0, 0.0],
                 "excitation": {"kind": "sine", "amplitude": 2.0, "frequency": 7.0}}]
    k_link = 3e7
    scene = pair(supports, links=[{"nodes": ["A/2", "B/2"], "material": "elastic",
                                   "stiffness": k_link}], dt=0.002, duration=8.0)
    scene.pop("excitation")
    plan, result = _run(scene)
    assert plan.story_ground_start is not None  # the link is across the supports
    total, d_w, d_e = _total_newmark(plan, K, 2 * K, k_link)
    order = [plan.node_dof[plan.node_names.index(f"{b}/{i}")] for b in "AB" for i in (1, 2, 3)]
    relative = result.history["displacement"][0][:, order]
    ours = relative + np.c_[np.repeat(d_w[:, None], 3, 1), np.repeat(d_e[:, None], 3, 1)]
    scale = np.max(np.abs(total))
    assert scale > 0.01
    np.testing.assert_allclose(ours, total, rtol=0, atol=1e-10 * scale)
    assert result.energy_error(0) < 1e-12


def test_supports_are_checked():
    """A building on an undeclared support, a support nothing stands on, a wall without its
    support in a scene of several, a wave passage without supports, an apparent velocity of
    zero: each refused, naming the place."""
    def refused(scene, match):
        with pytest.raises(InputError, match=match):
            parse_scene(json.dumps(scene))

    scene = pair(SUPPORTS)
    scene["buildings"][1]["support"] = "north"
    refused(scene, r"buildings\[1\]\.support.*support 'north', which the scene does not "
                   r"declare; its supports are west, east")
    scene = pair(SUPPORTS + [{"name": "north"}])
    refused(scene, r"support 'north': nothing stands on it")
    scene = pair(SUPPORTS, contacts=[{"nodes": ["B/1", "ground"], "gap": 0.1,
                                      "law": "linear", "stiffness": 1e9}])
    refused(scene, r"contacts\[0\].*several supports \(west, east\): say which with "
                   r"support: <name>")
    scene = pair(excitation={"kind": "wave_passage", "velocity": 300.0,
                             "motion": {"kind": "sine", "amplitude": 1.0, "frequency": 5.0}})
    refused(scene, "declare them")
    scene = pair(SUPPORTS, excitation={"kind": "wave_passage", "velocity": 0.0,
                                       "motion": {"kind": "sine", "amplitude": 1.0,
                                                  "frequency": 5.0}})
    refused(scene, r"excitation.velocity.*greater than 0")


def _across(integrator: dict, dt: float):
    """A and B on supports 10 m apart under a wave passage (200 m/s) of a sine, pounding at
    their third floors across the supports (Hertz-damped)."""
    supports = [{"name": "west", "position": [0.0, 0.0]},
                {"name": "east", "position": [10.0, 0.0]}]
    scene = pair(supports, {"kind": "wave_passage", "velocity": 200.0,
                            "motion": {"kind": "sine", "amplitude": 5.0, "frequency": 8.0}},
                 contacts=[{"nodes": ["A/3", "B/3"], "gap": 0.004, "law": "hertzdamp",
                            "stiffness": 5e9, "restitution": 0.7}],
                 dt=dt, duration=2.0, quantities=())
    scene["analysis"]["integrator"] = integrator
    scene["recorders"] = [{"kind": "envelope", "quantities": ["displacement",
                                                              "contact_force"]}]
    return _run(scene)[1]



@functools.cache
def _across_reference():
    return _across({"type": "newmark", "events": True}, 1.25e-4)


@pytest.mark.parametrize("integrator, facts", integrator_cases())
def test_every_integrator_pounds_across_supports(integrator, facts):
    """Every integrator (its declared examples, with located events where it has them) on
    impacts between buildings on two supports under a wave passage: the same impacts, peaks
    within 1 % of Newmark's with events at a quarter of the step, and the energy balance,
    the supports' work on the contact included, closed to the integrator's declared
    tolerance."""
    reference = _across_reference()
    result = _across(integrator, 5e-4)
    assert result.completed(0), result.describe_failure()
    assert int(result.impacts[0].sum()) > 0
    assert result.impacts[0].tolist() == reference.impacts[0].tolist()
    assert result.energy_error(0) <= max(facts.balance_tolerance, 1e-9)
    np.testing.assert_allclose(result.envelope["displacement"][0],
                               reference.envelope["displacement"][0], rtol=1e-2)
    assert result.envelope["contact_force"][0][0] == pytest.approx(
        reference.envelope["contact_force"][0][0], rel=3e-2)


def test_a_result_on_supports_reproduces_from_the_file_alone(tmp_path):
    """Each support's own record is kept in the result under its name (record_east_file,
    its text and checksum, excitation_east_pga with its unit) and pframe.load of the file,
    the records gone, runs the same bits again."""
    import hashlib
    import shutil

    import pframe

    sources = {"west": record_file("elCentro.AT2"), "east": record_file("A-ELC180.AT2")}
    folder = tmp_path / "project"
    (folder / "records").mkdir(parents=True)
    for source in sources.values():
        shutil.copy(source, folder / "records" / source.name)
    supports = [{"name": name, "position": [40.0 * i, 0.0],
                 "excitation": {"kind": "record", "file": f"records/{source.name}"}}
                for i, (name, source) in enumerate(sources.items())]
    scene = pair(supports, contacts=[{"nodes": ["A/3", "B/3"], "gap": 0.002, "law": "linear",
                                      "stiffness": 1e9}],
                 dt=0.005, duration=4.0, quantities=("displacement", "ground_displacement",
                                                     "contact_ground_displacement"))
    scene.pop("excitation")
    path = folder / "scene.yaml"
    path.write_text(json.dumps(scene), encoding="utf-8")
    first = pframe.solve(path, output=tmp_path / "run.nc", progress=False).load()
    for name, source in sources.items():
        assert first.attrs[f"record_{name}_sha256"] == hashlib.sha256(
            source.read_bytes()).hexdigest()
    assert first.attrs["excitation_west_pga_g"] == pytest.approx(0.3188, abs=5e-5)
    assert first.attrs["excitation_west_pga_units"] == "m/s^2"
    assert first.ground_displacement.dims == ("t", "support")
    assert float(np.abs(first.contact_ground_displacement).max()) > 0.0
    shutil.rmtree(folder)
    again = pframe.solve(pframe.load(tmp_path / "run.nc"), progress=False)
    np.testing.assert_array_equal(again.displacement.values, first.displacement.values)


def test_the_gap_audit_closes_gaps_across_supports(tmp_path):
    """pframe.gap.audit of two buildings on supports 60 m apart under a wave passage: the
    simulated critical gap is the peak of their relative motion plus the ground
    displacements' difference (a run with the contact's gap out of reach, its
    contact_ground_displacement recorded), where the ground's part is most of it; the code
    rules stay the buildings' peaks relative to their own supports (ABS)."""
    import pframe.gap

    supports = [{"name": "west", "position": [0.0, 0.0]},
                {"name": "east", "position": [60.0, 0.0]}]
    motion = {"kind": "sine", "amplitude": 2.0, "frequency": 4.0, "cycles": 3}
    scene = pair(supports, {"kind": "wave_passage", "velocity": 150.0, "motion": motion},
                 contacts=[{"nodes": ["A/3", "B/3"], "gap": 10.0, "law": "linear",
                            "stiffness": 1e9}], dt=0.002, duration=5.0,
                 quantities=("displacement", "contact_ground_displacement"))
    for b in scene["buildings"]:
        b["height"] = 3.5
    plan, result = _run(scene)
    assert int(result.impacts.sum()) == 0
    a = node_history(plan, result, "displacement", "A/3")
    b = node_history(plan, result, "displacement", "B/3")
    ground = result.history["contact_ground_displacement"][0][:, 0]
    expected = np.max(a - b + ground)
    assert np.max(np.abs(ground)) > 0.5 * expected
    path = tmp_path / "scene.yaml"
    path.write_text(json.dumps(scene), encoding="utf-8")
    ds = pframe.gap.audit(path)
    simulated = float(ds.gap_required.sel(rule="simulated").values.ravel()[0])
    assert simulated == pytest.approx(expected, rel=1e-9)
    absolute = float(ds.gap_required.sel(rule="ABS").values.ravel()[0])
    assert absolute == pytest.approx(np.max(np.abs(a)) + np.max(np.abs(b)), rel=1e-9)


def test_a_sweep_over_the_apparent_velocity_is_its_single_runs(tmp_path):
    """A sweep of two buildings on supports under a wave passage of a record (its file
    carried by the sweep as every record is) over the apparent velocity: each variant's
    impacts and peak contact force are those of the scene run alone at that velocity, to the
    bit; slower waves (more incoherence between the supports) pound more."""
    import shutil

    import pframe

    record = record_file("elCentro.AT2")
    shutil.copy(record, tmp_path / record.name)
    supports = [{"name": "west", "position": [0.0, 0.0]},
                {"name": "east", "position": [60.0, 0.0]}]
    scene = pair(supports, {"kind": "wave_passage", "velocity": 300.0,
                            "motion": {"kind": "record", "file": record.name}},
                 contacts=[{"nodes": ["A/3", "B/3"], "gap": 0.05, "law": "linear",
                            "stiffness": 1e9}], dt=0.005, duration=10.0, quantities=())
    scene["recorders"] = [{"kind": "envelope", "quantities": ["contact_force"]}]
    (tmp_path / "base.yaml").write_text(json.dumps(scene), encoding="utf-8")
    (tmp_path / "sweep.yaml").write_text(json.dumps({
        "base": "base.yaml",
        "axes": [{"name": "velocity", "path": "excitation.velocity",
                  "values": [150.0, 600.0]}],
        "keep": {"envelopes": ["peak_contact_force", "impact_count"]}}), encoding="utf-8")
    swept = pframe.sweep(tmp_path / "sweep.yaml", progress=False)
    counts = []
    for i, velocity in enumerate((150.0, 600.0)):
        scene["excitation"]["velocity"] = velocity
        (tmp_path / "one.yaml").write_text(json.dumps(scene), encoding="utf-8")
        one = pframe.solve(tmp_path / "one.yaml", progress=False)
        assert swept.impact_count.values[i, 0] == one.impact_count.values[0]
        assert swept.peak_contact_force.values[i, 0] == one.peak_contact_force.values[0]
        counts.append(int(one.impact_count.values[0]))
    assert counts[0] > counts[1] > 0


def _plan_pair() -> dict:
    import yaml
    from conftest import REPO

    data = yaml.safe_load((REPO / "models" / "plan-asymmetric-pair.yaml").read_text())
    data["analysis"]["duration"] = 14.0
    data["recorders"] = [{"kind": "history", "quantities": ["displacement", "contact_force",
                                                            "contact_ground_displacement"]}]
    return data


@pytest.mark.slow
def test_buildings_in_plan_on_supports():
    """The asymmetric pair in plan (two components, corner contacts): on two supports under
    the same motion, the same bits as on one ground; under a wave passage along the row,
    each corner contact's ground part is the supports' displacement difference along its
    normal (x), the energy balance closes, and the corners pound differently."""
    data = _plan_pair()
    today = _run(data)[1]
    supports = [{"name": "west", "position": [12.0, 8.0]},
                {"name": "east", "position": [32.0, 8.0]}]
    on = json.loads(json.dumps(data)) | {"supports": supports}
    on["buildings"][0]["support"], on["buildings"][1]["support"] = "west", "east"
    plan, same = _run(on)
    for q in ("displacement", "contact_force"):
        np.testing.assert_array_equal(same.history[q], today.history[q])
    np.testing.assert_array_equal(same.history["contact_ground_displacement"], 0.0)
    on["excitation"] = {"kind": "wave_passage", "velocity": 250.0, "motion": data["excitation"]}
    plan, passed = _run(on)
    assert passed.completed(0) and passed.energy_error(0) < 1e-12
    from pframe.model.support_motion import integrated

    channels = plan.channels
    assert channels == ("west:x", "west:y", "east:x", "east:y")
    d = {c: integrated(g, float(plan.dt[0]))[1] for c, g in zip(channels,
                                                               plan.ground_channels[0])}
    ground = passed.history["contact_ground_displacement"][0]
    np.testing.assert_allclose(ground, (d["west:x"] - d["east:x"])[:, None] * np.ones(6),
                               rtol=0, atol=1e-12 * np.max(np.abs(d["west:x"])))
    assert passed.impacts[0].tolist() != today.impacts[0].tolist()


def _coherent(excitation: dict, sites=(None, None)) -> dict:
    supports = [{"name": "west", "position": [0.0, 0.0]},
                {"name": "east", "position": [50.0, 0.0]}]
    for support, site in zip(supports, sites):
        if site:
            support["site"] = site
    scene = pair(supports, excitation, dt=0.005, duration=12.0,
                 contacts=[{"nodes": ["A/3", "B/3"], "gap": 0.05, "law": "linear",
                            "stiffness": 1e9}],
                 quantities=("ground_acceleration", "contact_ground_displacement"))
    return scene


CP = {"kind": "stochastic", "model": "clough_penzien", "intensity": 0.02,
      "ground_frequency": 15.0, "ground_damping": 0.6,
      "envelope": {"kind": "jennings", "rise": 1.0, "plateau": 4.0, "decay": 0.5}}


def test_coherent_motions_at_the_supports():
    """kind: coherent: fully coherent without delay or soil, the supports move alike (to
    round-off, and no ground part at the contact); the same seed gives the same motions bit for bit, another
    seed others; incoherence (Harichandran-Vanmarcke) and a soft column under east make them
    differ, and the contact then sees a ground part."""
    alike = _run(_coherent({"kind": "coherent", "seed": 3, "motion": CP}))[1]
    g = alike.history["ground_acceleration"][0]
    assert np.max(np.abs(g)) > 0.5
    np.testing.assert_allclose(g[:, 0], g[:, 1], rtol=0, atol=1e-12 * np.max(np.abs(g)))
    assert np.max(np.abs(alike.history["contact_ground_displacement"][0])) < 1e-9  # m
    differing = {"kind": "coherent", "seed": 3, "motion": CP, "velocity": 500.0,
                 "coherency": {"model": "harichandran_vanmarcke"}}
    site = {"frequency": 1.2, "damping": 0.25}
    one = _run(_coherent(differing, (None, site)))[1]
    again = _run(_coherent(differing, (None, site)))[1]
    other = _run(_coherent(differing | {"seed": 4}, (None, site)))[1]
    h = one.history["ground_acceleration"][0]
    np.testing.assert_array_equal(h, again.history["ground_acceleration"][0])
    assert not np.array_equal(h, other.history["ground_acceleration"][0])
    assert np.max(np.abs(h[:, 0] - h[:, 1])) > 0.2 * np.max(np.abs(h))
    assert np.max(np.abs(one.history["contact_ground_displacement"][0])) > 1e-3


def test_coherent_motions_conditioned_on_a_record():
    """Conditioned on a record at west (Konakli & Der Kiureghian 2012): west's motion is the
    record as applied at the analysis step, sample for sample, from the delay the scene
    states for west on; east's is simulated."""
    record = record_file("elCentro.AT2")
    plain = pair(excitation={"kind": "record", "file": str(record)}, dt=0.005,
                 duration=12.0, quantities=("ground_acceleration",))
    applied = _run(plain)[1].history["ground_acceleration"][0]
    scene = _coherent({"kind": "coherent", "seed": 1, "motion": CP,
                       "coherency": {"model": "luco_wong", "incoherence": 0.3,
                                     "shear_velocity": 400.0},
                       "record": {"kind": "record", "file": str(record)}, "at": "west"})
    g = _run(scene)[1].history["ground_acceleration"][0]
    # the simulated motions start before the record (the conditional mean's precursor and a
    # sample at rest): the record stands at west from its delay on, sample for sample
    delay = parse_scene(json.dumps(scene)).expanded.support_delays[0]
    k = int(round(delay / 0.005))
    assert k > 0
    np.testing.assert_array_equal(g[:k, 0], 0.0)
    np.testing.assert_array_equal(g[k:, 0], applied[:-k])
    assert 0.0 < np.max(np.abs(g[:, 0] - g[:, 1]))


def test_records_of_different_steps_or_lengths_at_two_supports_are_said(tmp_path):
    """Supports with records of their own that differ in time step or in length are
    interpolated onto the analysis step and at rest after their ends: the run says so,
    naming each support's excitation, its step and its end; records sampled alike are
    not warned of."""
    t1, t2 = np.arange(0.0, 4.0 + 1e-9, 0.01), np.arange(0.0, 3.0 + 1e-9, 0.02)
    for name, t in (("a.txt", t1), ("b.txt", t2), ("c.txt", t1)):
        np.savetxt(tmp_path / name, np.column_stack([t, np.sin(7.0 * t)]))

    def warnings_of(first, second):
        supports = [dict(SUPPORTS[0], excitation={"kind": "record", "file": first}),
                    dict(SUPPORTS[1], excitation={"kind": "record", "file": second})]
        scene = pair(supports, duration=2.0)
        scene.pop("excitation")
        return parse_scene(json.dumps(scene), "s.yaml", tmp_path).expanded.warnings

    said = [w for w in warnings_of("a.txt", "b.txt") if "differ in time step" in w]
    assert len(said) == 1
    assert "supports[0].excitation (west, x): dt = 0.01 s, ends at 4 s" in said[0]
    assert "supports[1].excitation (east, x): dt = 0.02 s, ends at 3 s" in said[0]
    assert not [w for w in warnings_of("a.txt", "c.txt") if "differ in time step" in w]
