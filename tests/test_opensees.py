"""pframe against OpenSeesPy: the same scenes built from stock OpenSees components.

The peer (:mod:`pframe.peers.opensees`) models a scene with ``zeroLength`` storeys
(``Elastic``/``Steel01``), ``ElasticPPGap`` contacts, Rayleigh regions, a ``Path`` ground motion,
Newmark average acceleration and Newton iterations. Both programs integrate the same discrete
equations, so their histories agree to round-off that the dynamics (yielding, impacts) amplify,
not to a discretisation error. The tolerances below say how much, and why.

Timing belongs to ``benchmarks/opensees_speed.py``, not here.
"""

from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path
from types import SimpleNamespace

import numpy as np
import pytest
from conftest import require_opensees

require_opensees()

from pframe.assemble import assemble  # noqa: E402
from pframe.kernel import simulate  # noqa: E402
from pframe.peers.from_plan import peer_scene  # noqa: E402
from pframe.peers.opensees import run, script_text  # noqa: E402
from pframe.reader import load_scene, parse_scene  # noqa: E402

REPO = Path(__file__).resolve().parents[1]
WU2021_LINEAR = REPO / "models" / "wu2021-eq14-linear.yaml"

#: max over nodes and times of |u_pframe - u_opensees|, over max |u|: the paper scene
DISPLACEMENT_RTOL = 1e-9
#: the same for the elastic scenes without contacts (no yielding, no impacts to amplify)
ELASTIC_RTOL = 1e-10


def max_relative_difference(a: np.ndarray, b: np.ndarray) -> float:
    """max |a - b| over max |b|, over every column and time."""
    assert a.shape == b.shape
    return float(np.max(np.abs(a - b)) / np.max(np.abs(b)))


def highest_frequency(plan) -> float:
    """Highest circular frequency (rad/s) of the scene at its initial stiffness with every
    contact closed: no part of a difference between two runs oscillates faster."""
    n = plan.n_dof
    k = np.zeros((n, n))

    def spring(i, j, value):
        k[j, j] += value
        if i >= 0:
            k[i, i] += value
            k[i, j] -= value
            k[j, i] -= value

    for (low, up), k0 in zip(plan.story_dofs, plan.story_k0[0]):
        spring(low, up, k0)
    for group in plan.contact_groups:
        for j, e in enumerate(group.index):
            left, right = plan.contact_dofs[e]
            spring(left, right, group.params[0, j, 0])
    scale = 1.0 / np.sqrt(plan.mass[0])
    return float(np.sqrt(np.linalg.eigvalsh(k * np.outer(scale, scale)).max()))


def onsets(contact_force: np.ndarray) -> np.ndarray:
    """Impacts per contact in a force history: steps where the force turns positive."""
    return np.sum((contact_force[:-1] <= 0.0) & (contact_force[1:] > 0.0), axis=0)


# ---------------------------------------------------------------------------------------------
# (a) the paper's scene with linear contacts: bilinear storeys yield, floors pound
# ---------------------------------------------------------------------------------------------


@pytest.fixture(scope="module")
def wu_linear():
    """pframe and OpenSeesPy on models/wu2021-eq14-linear.yaml (50,000 steps)."""
    plan = assemble(load_scene(WU2021_LINEAR).expanded)
    result = simulate(plan)
    assert result.completed(), result.describe_failure()
    peer = peer_scene(plan)
    return SimpleNamespace(plan=plan, result=result, peer=peer, opensees=run(peer))


@pytest.mark.slow
def test_scene_is_the_hard_case(wu_linear):
    """The comparison means something only if storeys yield, floors pound, and Rayleigh
    damping (on the initial stiffness) and a tight Newton tolerance are in play."""
    plan, result = wu_linear.plan, wu_linear.result
    assert plan.steps == 50_000
    assert len(plan.contact_names) == 3
    assert {g.law.name for g in plan.contact_groups} == {"linear"}
    assert {g.law.name for g in plan.story_groups} == {"bilinear"}
    assert np.all(result.impacts[0] > 0), f"no impacts: {result.impacts[0]}"
    assert np.all(plan.story_damping_stiffness == 0)  # initial
    assert np.all(plan.mass_damping[0] > 0) and np.all(plan.story_beta[0] > 0)
    # bilinear storeys leave the elastic line: force != k0 drift somewhere
    drift = result.history["story_drift"][0]
    force = result.history["story_force"][0]
    plastic = np.max(np.abs(force - plan.story_k0[0] * drift), axis=0)
    assert np.count_nonzero(plastic > 1e-3 * np.max(np.abs(force))) >= 2, plastic
    # Newton stops at the same point in both programs (and far below round-off effects)
    assert plan.tolerance <= 1e-14 and plan.absolute_tolerance <= 1e-15
    assert wu_linear.peer.tolerance == plan.absolute_tolerance


@pytest.mark.slow
def test_displacement_agrees_to_1e9_of_peak(wu_linear):
    u = wu_linear.result.history["displacement"][0]
    u_os = wu_linear.opensees["displacement"]
    assert u.shape == u_os.shape == (wu_linear.plan.steps + 1, wu_linear.plan.n_dof)
    assert np.all(u[0] == 0.0) and np.all(u_os[0] == 0.0)
    # OpenSees accumulates t_n = t_(n-1) + dt; it may drift from n dt by rounding only
    np.testing.assert_allclose(wu_linear.opensees["time"], wu_linear.plan.times, rtol=0,
                               atol=1e-9)
    difference = max_relative_difference(u, u_os)
    assert difference <= DISPLACEMENT_RTOL, f"max relative difference {difference:.3e}"


@pytest.mark.slow
def test_impacts_agree(wu_linear):
    """Both programs see every impact: pframe counts onsets, OpenSees' forces show them."""
    counted = onsets(wu_linear.opensees["contact_force"])
    np.testing.assert_array_equal(counted, wu_linear.result.impacts[0])
    np.testing.assert_array_equal(onsets(wu_linear.result.history["contact_force"][0]),
                                  wu_linear.result.impacts[0])


@pytest.mark.slow
def test_velocity_and_forces_agree(wu_linear):
    """Tolerances that follow from the displacement one, du = 1e-9 max |u|:

    * velocity: a difference between the runs oscillates at most at the scene's highest
      frequency w_max (all contacts closed), so |dv| <= w_max du;
    * storey force: a bilinear storey is an elastic spring (alpha k) beside an elastic-plastic
      one ((1 - alpha) k, the 'stop' operator, Lipschitz 2 in the sup norm of its drift), so
      |dF| <= 2 k0 |d drift| <= 4 k0 du;
    * contact force: a linear spring on the penetration, |dF| <= k_c |d pen| <= 2 k_c du.
    """
    plan, result, opensees = wu_linear.plan, wu_linear.result, wu_linear.opensees
    u_peak = np.max(np.abs(opensees["displacement"]))
    du = DISPLACEMENT_RTOL * u_peak
    contact_k = np.concatenate([g.params[0, :, 0] for g in plan.contact_groups])
    bounds = {
        "velocity": highest_frequency(plan) * du,
        "story_force": 4.0 * np.max(plan.story_k0[0]) * du,
        "contact_force": 2.0 * np.max(contact_k) * du,
    }
    report = {}
    for quantity, bound in bounds.items():
        ours, theirs = result.history[quantity][0], opensees[quantity]
        rtol = bound / np.max(np.abs(theirs))
        report[quantity] = (max_relative_difference(ours, theirs), rtol)
    failed = {q: v for q, v in report.items() if v[0] > v[1]}
    assert not failed, "max relative difference > tolerance: " + ", ".join(
        f"{q} {d:.3e} > {t:.3e}" for q, (d, t) in failed.items())


@pytest.mark.slow
def test_newton_tolerance_is_tight(wu_linear):
    """Tightening pframe's Newton tolerance to round-off changes the result by far less than
    the comparison tolerance, so the agreement is not limited by where Newton stops.

    (pframe accepts a state when the bound |R| / (c0 min m) on the next increment meets the
    tolerance, without applying that increment, so its histories move with the tolerance: on
    this scene 1e-12 relative moves them by ~7e-10 of the peak. At round-off the spread left
    is ~5e-12, the amplified round-off floor of the scene.)"""
    text = WU2021_LINEAR.read_text(encoding="utf-8")
    line = "newton: {tolerance: 1.0e-14, absolute_tolerance: 1.0e-15}"
    assert line in text
    tighter = text.replace(line, "newton: {tolerance: 1.0e-16, absolute_tolerance: 1.0e-16}")
    plan = assemble(parse_scene(tighter, base_dir=WU2021_LINEAR.parent).expanded)
    result = simulate(plan)
    assert result.completed(), result.describe_failure()
    difference = max_relative_difference(wu_linear.result.history["displacement"][0],
                                         result.history["displacement"][0])
    assert difference <= DISPLACEMENT_RTOL / 10, f"{difference:.3e}"


# ---------------------------------------------------------------------------------------------
# (b) elastic buildings, no contacts: the linear kernel (factor once, no Newton)
# ---------------------------------------------------------------------------------------------

#: Two buildings of different heights and damping (L by the building shorthand with its own
#: Rayleigh fit on modes 1 and 3, R by explicit nodes and storeys with the scene's damping).
ELASTIC = {
    "title": "two elastic shear buildings, no contacts",
    "buildings": [{
        "name": "L", "mass": [300.0, 300.0, 250.0],
        "story": {"material": "elastic", "stiffness": 4.0e5},
        "damping": {"ratio": 0.03, "modes": [1, 3]},
    }],
    "nodes": [{"name": "R/1", "mass": 800.0}, {"name": "R/2", "mass": 600.0}],
    "stories": [
        {"nodes": ["ground", "R/1"], "material": "elastic", "stiffness": 2.0e6},
        {"nodes": ["R/1", "R/2"], "material": "elastic", "stiffness": 1.5e6},
    ],
    "damping": {"ratio": 0.05, "modes": [1, 2], "stiffness": "initial"},
    "excitation": {"kind": "sine", "amplitude": 3.0, "frequency": 9.0, "cycles": 8},
    "analysis": {"dt": 0.001, "duration": 10.0},
    "recorders": [{"kind": "history", "quantities": ["displacement", "velocity", "story_force"]}],
}


def _elastic_pair(scene: dict, base_dir: Path | None = None):
    plan = assemble(parse_scene(json.dumps(scene), base_dir=base_dir).expanded)
    result = simulate(plan)
    assert result.completed(), result.describe_failure()
    return plan, result, run(peer_scene(plan))


def _assert_elastic_agreement(plan, result, opensees):
    assert plan.linear and not plan.contact_names
    assert len(plan.buildings) == 2
    for quantity in ("displacement", "velocity", "story_force"):
        difference = max_relative_difference(result.history[quantity][0], opensees[quantity])
        assert difference <= ELASTIC_RTOL, f"{quantity}: {difference:.3e}"


@pytest.mark.slow
def test_elastic_buildings_agree():
    plan, result, opensees = _elastic_pair(ELASTIC)
    assert plan.ground_acceleration[0, 0] == 0.0
    _assert_elastic_agreement(plan, result, opensees)


def test_elastic_buildings_agree_when_the_ground_starts_accelerated(tmp_path):
    """A record with a_g(0) != 0: both programs start from equilibrium at rest, a(0) = -a_g(0)
    (the peer sets it with setNodeAccel; OpenSees would otherwise start from a = 0)."""
    dt = 0.001
    t = np.arange(4001) * dt
    a = 2.5 * np.cos(7.0 * t) * np.exp(-0.3 * t) + 0.8 * np.sin(23.0 * t)
    record = tmp_path / "ground.txt"
    record.write_text("".join(f"{ti!r} {ai!r}\n" for ti, ai in zip(t.tolist(), a.tolist())),
                      encoding="utf-8")
    scene = ELASTIC | {
        "excitation": {"kind": "record", "file": record.name, "units": "m/s2"},
        "analysis": {"dt": dt, "duration": 5.0},
    }
    plan, result, opensees = _elastic_pair(scene, base_dir=tmp_path)
    assert plan.ground_acceleration[0, 0] == 2.5
    _assert_elastic_agreement(plan, result, opensees)


@pytest.mark.slow
def test_standalone_script_equals_run(tmp_path):
    """The script written by script_text, run on its own, reproduces run() bit for bit."""
    plan = assemble(parse_scene(json.dumps(ELASTIC)).expanded)
    peer = peer_scene(plan)
    in_process = run(peer)
    script = tmp_path / "peer.py"
    out = tmp_path / "peer.npz"
    script.write_text(script_text(peer, str(out)), encoding="utf-8")
    text = script.read_text(encoding="utf-8")
    assert "import pframe" not in text and "from pframe" not in text  # stands alone
    completed = subprocess.run([sys.executable, str(script)], capture_output=True, text=True,
                               timeout=300, cwd=tmp_path)
    assert completed.returncode == 0, completed.stderr
    saved = np.load(out)
    for quantity in ("time", "displacement", "velocity", "story_force", "contact_force"):
        np.testing.assert_array_equal(saved[quantity], in_process[quantity], err_msg=quantity)


# ---------------------------------------------------------------------------------------------
# Other integrators: the export writes the scene's own (OpenSees' HHT and WilsonTheta)


def _paper_linear_with(integrator: dict, excitation: dict | None = None,
                       base_dir: Path | None = None):
    import yaml

    scene = yaml.safe_load(WU2021_LINEAR.read_text(encoding="utf-8"))
    scene["analysis"]["integrator"] = integrator
    if excitation is not None:
        scene["excitation"] = excitation
        for contact in scene["contacts"]:  # frequency_ratio needs the sine: its stiffness,
            contact.pop("frequency_ratio")  # (65 w_p)^2 m_a m_b / (m_a + m_b)
            contact["stiffness"] = (65.0 * 2 * np.pi) ** 2 * 250.0 * 1000.0 / 1250.0
    plan = assemble(parse_scene(json.dumps(scene), base_dir=base_dir).expanded)
    result = simulate(plan)
    assert result.completed(), result.describe_failure()
    assert np.all(result.impacts[0] > 0) and len(plan.contact_names) == 3
    return plan, result, run(peer_scene(plan))


@pytest.mark.slow
def test_hht_agrees():
    """HHT (pframe's alpha 0.1, OpenSees' 0.9) on the paper's pounding scene."""
    plan, result, opensees = _paper_linear_with({"type": "hht", "alpha": 0.1})
    difference = max_relative_difference(result.history["displacement"][0],
                                         opensees["displacement"])
    assert difference <= DISPLACEMENT_RTOL, f"{difference:.3e}"


@pytest.mark.slow
def test_wilson_theta_agrees_under_a_ground_motion_linear_in_time(tmp_path):
    """Wilson-theta (theta 1.4) on the paper's yielding, pounding pair. OpenSees reads the
    ground motion at t + theta dt from the record where the method extrapolates the step's
    own samples: under a ramp both are the same numbers, and the histories agree to
    round-off; under the paper's sine they differ by the extrapolation's O(dt^2) only."""
    import yaml

    dt = yaml.safe_load(WU2021_LINEAR.read_text(encoding="utf-8"))["analysis"]["dt"]
    t = np.arange(50_001) * dt
    record = tmp_path / "ramp.txt"
    record.write_text("".join(f"{ti!r} {-2.5 * ti!r}\n" for ti in t.tolist()), encoding="utf-8")
    wilson = {"type": "wilson_theta", "theta": 1.4}
    plan, result, opensees = _paper_linear_with(
        wilson, {"kind": "record", "file": record.name, "units": "m/s2"}, base_dir=tmp_path)
    drift, force = result.history["story_drift"][0], result.history["story_force"][0]
    assert np.max(np.abs(force - plan.story_k0[0] * drift)) > 1e-3 * np.max(np.abs(force))
    difference = max_relative_difference(result.history["displacement"][0],
                                         opensees["displacement"])
    assert difference <= DISPLACEMENT_RTOL, f"{difference:.3e}"
    _, sine, opensees_sine = _paper_linear_with(wilson)
    difference = max_relative_difference(sine.history["displacement"][0],
                                         opensees_sine["displacement"])
    assert 1e-9 < difference < 1e-4, f"{difference:.3e}"


@pytest.mark.slow
def test_bathe_agrees_with_trbdf2():
    """Bathe's composite method with gamma = 1/2 (pframe: two stages of one tableau) is
    OpenSees' TRBDF2 (alternate trapezoidal and backward analysis steps of dt / 2, the ground
    sampled between as pframe interpolates it): on the paper's yielding, pounding pair the
    histories agree to round-off (measured 2.1e-13)."""
    plan, result, opensees = _paper_linear_with({"type": "bathe", "gamma": 0.5})
    drift, force = result.history["story_drift"][0], result.history["story_force"][0]
    assert np.max(np.abs(force - plan.story_k0[0] * drift)) > 1e-3 * np.max(np.abs(force))
    difference = max_relative_difference(result.history["displacement"][0],
                                         opensees["displacement"])
    assert difference <= DISPLACEMENT_RTOL, f"{difference:.3e}"


def test_bathe_exports_only_as_trbdf2():
    """OpenSees' TRBDF2 is Bathe's method at gamma = 1/2: another gamma is refused, naming it."""
    import dataclasses

    from pframe.errors import InputError
    from pframe.integrators import Bathe

    plan = assemble(load_scene(WU2021_LINEAR).expanded)
    plan = dataclasses.replace(plan, integrator=Bathe().coefficients())
    with pytest.raises(InputError, match="TRBDF2 is Bathe's method with gamma = 0.5, not 0.58"):
        peer_scene(plan)


@pytest.mark.slow
def test_generalised_alpha_agrees_with_hht_generalized():
    """pframe's generalised-alpha (Chung & Hulbert, rho_inf = 0.6: alpha_m and alpha_f both
    non-zero) is OpenSees' HHTGeneralized with alpha_I = 1 - alpha_m, alpha_F = 1 - alpha_f:
    its predictor, its Newton update (displacement, velocity and acceleration at the
    weighted points), its tangent (alpha_F K + alpha_F c2 C + alpha_I c3 M) and its commit at
    the step end are the method's (SRC/analysis/integrator/HHTGeneralized.cpp). On the
    paper's yielding, pounding pair the histories agree to round-off. (OpenSees'
    GeneralizedAlpha is not the method: its update sets the nodes' accelerations to a(n+1)
    where its tangent has a(n+1-alpha_m).)"""
    plan, result, opensees = _paper_linear_with({"type": "generalized_alpha",
                                                 "rho_infinity": 0.6})
    assert plan.integrator.alpha_m != 0.0 and plan.integrator.alpha_f != 0.0
    drift, force = result.history["story_drift"][0], result.history["story_force"][0]
    assert np.max(np.abs(force - plan.story_k0[0] * drift)) > 1e-3 * np.max(np.abs(force))
    difference = max_relative_difference(result.history["displacement"][0],
                                         opensees["displacement"])
    assert difference <= DISPLACEMENT_RTOL, f"{difference:.3e}"


@pytest.mark.slow
def test_walls_agree():
    """Walls (contacts to the ground, OpenSees: zeroLength to the fixed node) on both sides of
    a yielding building under a sine: both programs to round-off."""
    scene = {
        "title": "walls",
        "buildings": [{"name": "A", "floors": 2, "mass": 1000.0,
                       "story": {"material": "bilinear", "stiffness": 4.0e5,
                                 "yield_drift": 0.01, "alpha": 0.1}}],
        "contacts": [
            {"name": "east", "nodes": ["A/1", "ground"], "gap": 0.01, "law": "linear",
             "stiffness": 1.0e8},
            {"name": "west", "nodes": ["ground", "A/2"], "gap": 0.02, "law": "linear",
             "stiffness": 1.0e8}],
        "damping": {"ratio": 0.05, "stiffness": "initial"},
        "excitation": {"kind": "sine", "amplitude": 4.0, "frequency": 9.0},
        "analysis": {"dt": 0.0002, "duration": 3.0,
                     "newton": {"tolerance": 1.0e-14, "absolute_tolerance": 1.0e-15}},
        "recorders": [{"kind": "history", "quantities": ["displacement", "contact_force"]}],
    }
    plan = assemble(parse_scene(json.dumps(scene)).expanded)
    result = simulate(plan)
    assert result.completed(), result.describe_failure()
    assert np.all(result.impacts[0] > 2)
    opensees = run(peer_scene(plan))
    for quantity in ("displacement", "contact_force"):
        difference = max_relative_difference(result.history[quantity][0], opensees[quantity])
        assert difference <= DISPLACEMENT_RTOL, f"{quantity}: {difference:.3e}"


@pytest.mark.slow
@pytest.mark.parametrize("material", ["viscous", "kelvin_voigt"])
@pytest.mark.parametrize("alpha", [1.0, 0.5])
def test_links_agree(material, alpha):
    """The paper's pair linked floor to floor by dampers (OpenSees: zeroLength with Viscous,
    or a Parallel of Elastic and Viscous). Linear dampers: round-off. alpha = 0.5: the force
    c |v|^0.5 has an infinite slope at v = 0, so both stop Newton at 1e-12 m and the
    displacements agree to 1e-9 of their peak; the forces, which amplify a velocity
    difference dv near v = 0 to c sqrt(dv), to 1e-3. (pframe's dashpot is linear below
    linear_below, 1e-11 m/s here: OpenSees keeps the power law there.)"""
    import yaml

    scene = yaml.safe_load(WU2021_LINEAR.read_text(encoding="utf-8"))
    scene["recorders"][0]["quantities"].append("link_force")
    if alpha != 1.0:
        scene["analysis"]["newton"] = {"tolerance": 1e-12, "absolute_tolerance": 1e-12,
                                       "max_iterations": 200}
    extra = {"stiffness": 2.0e4} if material == "kelvin_voigt" else {}
    scene["links"] = [{"name": f"damper-{i}", "nodes": [f"A/{i}", f"B/{i}"],
                       "material": material, "damping": 3000.0, "exponent": alpha,
                       "linear_below": 1e-11} | extra
                      for i in (1, 2, 3)]
    plan = assemble(parse_scene(json.dumps(scene)).expanded)
    result = simulate(plan)
    assert result.completed(), result.describe_failure()
    opensees = run(peer_scene(plan))
    displacement = max_relative_difference(result.history["displacement"][0],
                                           opensees["displacement"])
    force = max_relative_difference(result.history["link_force"][0], opensees["link_force"])
    assert displacement <= (1e-12 if alpha == 1.0 else 1e-9), f"{displacement:.3e}"
    assert force <= (1e-12 if alpha == 1.0 else 1e-3), f"{force:.3e}"
