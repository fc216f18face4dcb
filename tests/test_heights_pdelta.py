"""Storey heights, drift ratios and P-delta.

P-delta against closed forms: the reduced stiffness k - P/h of a storey under its gravity load
(the period of a one-storey frame, the modes of a three-storey one), the elastic buckling
load P = k h (an unstable storey's exponential departure), and the energy balance with
yielding storeys whose post-yield stiffness P-delta makes negative.
"""

from __future__ import annotations

import json
import math

import numpy as np
import pytest
from conftest import run_text

from pframe.errors import InputError

G = 9.80665


def _newmark(w: float, dt: float) -> float:
    """The frequency average-acceleration Newmark gives a free vibration of frequency w:
    (2 / dt) atan(w dt / 2) (no amplitude error)."""
    return 2.0 / dt * math.atan(w * dt / 2.0)


def _building(floors, mass, k, height, p_delta=True, material="elastic", extra=None,
              u0=0.01, duration=4.0, dt=1e-3, excitation=None):
    story = {"material": material, "stiffness": k} | (extra or {})
    scene = {
        "buildings": [{"name": "A", "floors": floors, "mass": mass, "height": height,
                       "p_delta": p_delta, "story": story}],
        "damping": {"ratio": 0.0},
        "analysis": {"dt": dt, "duration": duration},
        "recorders": [{"kind": "history", "quantities": [
            "displacement", "story_drift", "story_force", "story_drift_ratio"]}],
    }
    if excitation is None:
        scene["initial_conditions"] = {"displacement": {f"A/{floors}": u0}}
    else:
        scene["excitation"] = excitation
        scene["damping"] = {"ratio": 0.05}
    return json.dumps(scene)


def test_one_storey_period_with_p_delta():
    """m u'' + (k - m g / h) u = 0: the period lengthens to 2 pi sqrt(m / (k - m g / h))."""
    m, k, h = 1000.0, 1.0e4, 3.0
    plan, result = run_text(_building(1, m, k, h))
    assert result.completed(0)
    w = _newmark(math.sqrt((k - m * G / h) / m), 1e-3)
    u = result.history["displacement"][0, :, 0]
    assert np.max(np.abs(u - 0.01 * np.cos(w * plan.times))) < 1e-11
    # without P-delta the period is the storey's own: P-delta is what changed it
    _, plain = run_text(_building(1, m, k, h, p_delta=False))
    u_plain = plain.history["displacement"][0, :, 0]
    w_plain = _newmark(math.sqrt(k / m), 1e-3)
    assert np.max(np.abs(u_plain - 0.01 * np.cos(w_plain * plan.times))) < 1e-11


def test_three_storey_modes_with_p_delta():
    """The three modes of a shear building with P-delta are those of K - K_G, with storey i
    carrying the weight of the floors i..n: the free vibration from a mode shape stays in it
    at that mode's reduced frequency."""
    m, k, h = 2.0e4, 3.0e6, 3.5
    n = 3
    K = np.zeros((n, n))
    for i in range(n):
        ki = k - G * m * (n - i) / h  # storey i below floor i + 1
        K[i, i] += ki
        if i > 0:
            K[i - 1, i - 1] += ki
            K[i - 1, i] -= ki
            K[i, i - 1] -= ki
    w2, phi = np.linalg.eigh(K / m)
    shape = phi[:, 0] / phi[-1, 0] * 0.02
    scene = json.loads(_building(n, m, k, h))
    scene["initial_conditions"] = {"displacement": {f"A/{i + 1}": float(shape[i])
                                                    for i in range(n)}}
    plan, result = run_text(json.dumps(scene))
    u = result.history["displacement"][0][:, plan.node_dof]
    exact = np.outer(np.cos(_newmark(math.sqrt(w2[0]), 1e-3) * plan.times), shape)
    assert np.max(np.abs(u - exact)) < 1e-9 * 0.02


def test_the_gap_audits_first_period_is_the_one_the_runs_integrate():
    """The gap audit's first period (its Sa(T1) measure and DDC's rho) of a building under
    P-delta is the first mode of K - K_G, the stiffness its runs integrate at rest, not of K
    alone."""
    from pframe.assemble import assemble
    from pframe.gap.runs import first_modes
    from pframe.reader import parse_scene

    m, k, h, n = 2.0e4, 3.0e6, 3.5, 3
    K = np.zeros((n, n))
    for i in range(n):
        ki = k - G * m * (n - i) / h
        K[i, i] += ki
        if i > 0:
            K[i - 1, i - 1] += ki
            K[i - 1, i] -= ki
            K[i, i - 1] -= ki
    w1 = math.sqrt(np.linalg.eigvalsh(K / m)[0])
    plan = assemble(parse_scene(_building(n, m, k, h)).expanded)
    periods, _ = first_modes(plan)
    assert periods[0] == pytest.approx(2.0 * math.pi / w1, rel=1e-12)


def test_a_storey_above_its_buckling_load_departs_exponentially():
    """P / h > k: u'' = ((P / h - k) / m) u grows as cosh; pframe warns before the run."""
    m, k, h = 1000.0, 2.0e3, 3.0  # m g / h = 3269 N/m > k
    text = _building(1, m, k, h, u0=1e-4, duration=1.0)
    plan, result = run_text(text)
    assert any("buckles" in w for w in plan.warnings)
    s = math.sqrt((m * G / h - k) / m)
    u = result.history["displacement"][0, :, 0]
    exact = 1e-4 * np.cosh(s * plan.times)
    done = np.isfinite(u)
    np.testing.assert_allclose(u[done], exact[done], rtol=1e-5)


def test_a_collapse_under_gravity_is_named_as_one():
    """Left to run, the unstable storey runs away; the failure says it is a P-delta collapse,
    not numerics creating energy."""
    _, result = run_text(_building(1, 1000.0, 2.0e3, 3.0, u0=1e-4, duration=10.0))
    assert not result.completed(0)
    why = result.describe_failure(0)
    assert "collapsing under gravity" in why and "node A/1" in why


def test_negative_post_yield_stiffness_is_warned_and_handled():
    """A bilinear storey with alpha k < P / h: warned; the run completes (Newton with a
    negative tangent), the storey's net force falls as it drifts past yield, and the energy
    balance (the gravity loads' work included) closes."""
    m, k, h, alpha = 2.0e4, 2.0e7, 3.5, 0.002
    text = _building(3, m, k, h, material="bilinear",
                     extra={"yield_drift": 0.01, "alpha": alpha},
                     excitation={"kind": "sine", "amplitude": 6.0, "frequency": 9.0,
                                 "cycles": 5}, duration=8.0, dt=1e-3)
    plan, result = run_text(text)
    assert any("post-yield stiffness" in w for w in plan.warnings)
    assert result.completed(0), result.describe_failure(0)
    assert result.energy_error(0) < 1e-10
    d = result.history["story_drift"][0, :, 0]
    f = result.history["story_force"][0, :, 0]
    # the net shear in the direction of the drift never passes the backbone
    # (1 - alpha) f_y + (alpha k - P/h) |d|, which falls with |d|, and reaches it past yield
    kg = float(plan.story_kg[0, 0])
    assert kg == pytest.approx(3 * m * G / h)
    fy = k * 0.01
    backbone = (1 - alpha) * fy + (alpha * k - kg) * np.abs(d)
    along = np.sign(d) * f
    assert np.all(along <= backbone + 1e-9 * fy)
    far = np.abs(d) > 0.03
    assert far.any() and np.max(along[far] - backbone[far]) > -1e-3 * fy


def test_drift_ratio_is_drift_over_height():
    plan, result = run_text(_building(3, 1000.0, 1e5, [4.0, 3.0, 3.0], p_delta=False))
    drift = result.history["story_drift"][0]
    np.testing.assert_allclose(result.history["story_drift_ratio"][0],
                               drift / np.array([4.0, 3.0, 3.0]), rtol=1e-15)


def test_p_delta_needs_heights():
    from pframe.reader import parse_scene

    scene = json.loads(_building(2, 1000.0, 1e5, 3.0))
    del scene["buildings"][0]["height"]
    with pytest.raises(InputError, match="P-delta needs the storey heights"):
        _ = parse_scene(json.dumps(scene)).expanded


def test_a_scene_without_p_delta_is_bit_for_bit_unchanged():
    """Heights alone change nothing in the motion: P-delta off gives the same bits as a scene
    without heights."""
    _, with_heights = run_text(_building(3, 1000.0, 1e5, 3.0, p_delta=False))
    scene = json.loads(_building(3, 1000.0, 1e5, 3.0, p_delta=False))
    del scene["buildings"][0]["height"]
    scene["recorders"][0]["quantities"].remove("story_drift_ratio")
    _, without = run_text(json.dumps(scene))
    np.testing.assert_array_equal(with_heights.history["displacement"],
                                  without.history["displacement"])


@pytest.mark.slow
def test_a_storey_without_a_height_has_no_drift_ratio(tmp_path, capsys):
    """A storey without a height (an isolator, typically) has no drift ratio: NaN in the
    history, the envelope, the file, the Dataset and the summary, with the reason, never 0
    (which passes any drift limit); the storeys with a height keep d / h."""
    import pframe
    from pframe.cli import main

    scene = {
        "nodes": [{"name": "I/1", "mass": 4.0e4}, {"name": "I/2", "mass": 3.0e4},
                  {"name": "I/3", "mass": 3.0e4}],
        "stories": [{"name": "bearing", "nodes": ["ground", "I/1"], "material": "bilinear",
                     "stiffness": 4.0e6, "yield_drift": 0.01, "alpha": 0.1},
                    {"nodes": ["I/1", "I/2"], "material": "elastic", "stiffness": 1.2e8,
                     "height": 3.2},
                    {"nodes": ["I/2", "I/3"], "material": "elastic", "stiffness": 1.0e8,
                     "height": 3.2}],
        "excitation": {"kind": "sine", "amplitude": 2.0, "frequency": 3.0},
        "analysis": {"dt": 0.01, "duration": 2.0},
        "recorders": [{"kind": "history", "quantities": ["story_drift_ratio"]},
                      {"kind": "envelope", "quantities": ["story_drift", "story_drift_ratio"]}],
    }
    path = tmp_path / "scene.yaml"
    path.write_text(json.dumps(scene))
    assert main(["solve", str(path), "-o", str(tmp_path / "out.nc")]) == 0
    assert "; not defined at bearing (no height)" in capsys.readouterr().out
    ds = pframe.open(tmp_path / "out.nc")
    peak = ds.peak_story_drift_ratio.values
    assert np.isnan(peak[0]) and np.all(peak[1:] > 0.0)
    np.testing.assert_allclose(peak[1:], ds.peak_story_drift.values[1:] / 3.2, rtol=1e-12)
    assert np.all(np.isnan(ds.story_drift_ratio.values[:, 0]))
    for variable in (ds.peak_story_drift_ratio, ds.story_drift_ratio):
        assert variable.attrs["comment"].startswith("NaN at bearing: no height was given")
    table = pframe.summary(ds)
    row = table[(table.name == "bearing") & (table.quantity == "peak story drift ratio")]
    assert np.isnan(row.value.iloc[0])
    assert "NaN at bearing" in table[table.quantity == "drift ratio not defined"].value.iloc[0]
