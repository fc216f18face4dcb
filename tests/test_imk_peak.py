"""The imk_peak storey material: OpenSees' ModIMKPeakOriented (modified Ibarra-Medina-
Krawinkler, peak-oriented, with cyclic deterioration).

Against OpenSeesPy (the peers extra) under the same prescribed drift histories, to round-off:
a cyclic history of growing amplitude that crosses every branch (elastic, hardening, capping,
residual, fracture) with every deterioration mode on, and noisy histories with small
reversals, over random parameter sets. Through the kernel: the hysteretic work the balance
books is the loops' area of the recorded force and drift, and the balance closes.
"""

from __future__ import annotations

import json
import math

import numpy as np
import pytest
from conftest import REPO, drive_material, record_file, run_text, runnable_model

from pframe.laws.material.imk_peak import ImkPeak

#: a storey of 3 m: K0 40 MN/m, yield at 100 kN (drift 2.5 mm), capping 20 mm later, fracture
#: at 0.15 m; every deterioration on
BASE = dict(k0=4.0e7, as_plus=0.03, as_neg=0.04, my_plus=1.0e5, my_neg=1.2e5, lamda_s=0.6,
            lamda_c=0.6, lamda_a=0.6, lamda_k=0.6, c_s=1.0, c_c=1.0, c_a=1.0, c_k=1.0,
            theta_p_plus=0.02, theta_p_neg=0.025, theta_pc_plus=0.06, theta_pc_neg=0.08,
            res_plus=0.3, res_neg=0.25, theta_u_plus=0.15, theta_u_neg=0.17, d_plus=1.0,
            d_neg=0.9)


def _packed(**changes):
    return ImkPeak.pack(ImkPeak.Params(material="imk_peak", **(BASE | changes)))


def _pframe(packed, drifts):
    return drive_material(ImkPeak, packed, drifts)


_TAG = [0]


def _opensees(packed, drifts):
    ops = pytest.importorskip("openseespy.opensees", reason="OpenSeesPy (the peers extra) "
                              "is not installed")
    _TAG[0] += 1
    ops.wipe()
    ops.uniaxialMaterial("ModIMKPeakOriented", _TAG[0], *packed)
    ops.testUniaxialMaterial(_TAG[0])
    out, tangents = [], []
    for d in drifts:
        ops.setStrain(float(d))
        out.append(ops.getStress())
        tangents.append(ops.getTangent())
    return np.array(out), np.array(tangents)


def _growing_cycles(amplitude, cycles=12, n=4000, noise=0.0, seed=0):
    t = np.linspace(0.0, cycles, n)
    d = amplitude * (t / cycles) ** 1.5 * np.sin(2 * np.pi * t)
    if noise:
        d = d + noise * np.random.default_rng(seed).standard_normal(n)
    return d[1:]


def test_agrees_with_opensees_across_every_branch():
    """Growing cycles to fracture: OpenSees' forces and tangents to round-off, and the history
    does cross the hardening, capping (negative tangent) and residual branches, deteriorates
    (yield force, hardening and unloading stiffness fall) and fractures."""
    packed = _packed()
    drifts = _growing_cycles(0.16)
    f, k, s = _pframe(packed, drifts)
    f_os, k_os = _opensees(packed, drifts)
    scale = np.max(np.abs(f_os))
    assert np.max(np.abs(f - f_os)) <= 1e-9 * scale
    assert np.max(np.abs(k - k_os)) <= 1e-9 * packed[0]
    names = ImkPeak.state_names
    fy_pos = s[:, names.index("fyPos")]
    assert np.any(k < 0.0)                                   # capping
    assert np.any(k == 1.0e-7)                               # residual plateau
    assert np.any(np.isclose(k, 0.03 * 4.0e7, rtol=1e-12))   # hardening before deterioration
    assert fy_pos.min() < 0.9 * 1.0e5                        # basic strength deteriorated
    assert s[:, names.index("ekunload")].min() < 0.95 * 4.0e7  # unloading stiffness too
    assert s[-1, names.index("flagStop")] == 1.0 and f[-1] == 0.0  # fractured
    # and the cap was passed before fracture: a force above the yield force was reached
    assert scale > 1.0e5


@pytest.mark.parametrize("seed", range(6))
def test_agrees_with_opensees_on_random_storeys_and_small_reversals(seed):
    """Random parameters (each deterioration on or off, exponents 1 or 2) under growing cycles
    with small reversals superposed: OpenSees' forces to round-off."""
    rng = np.random.default_rng(seed)
    params = {k: float(v * rng.uniform(0.5, 1.5)) for k, v in BASE.items()}
    for name in ("lamda_s", "lamda_c", "lamda_a", "lamda_k"):
        params[name] *= float(rng.choice([0.0, 1.0]))
    for name in ("c_s", "c_c", "c_a", "c_k"):
        params[name] = float(rng.choice([1.0, 2.0]))
    for name in ("res_plus", "res_neg", "d_plus", "d_neg"):
        params[name] = min(params[name], 1.0)
    packed = ImkPeak.pack(ImkPeak.Params(material="imk_peak", **params))
    drifts = _growing_cycles(0.2, noise=0.002 * (seed % 2), seed=seed)
    f, _, _ = _pframe(packed, drifts)
    f_os, _ = _opensees(packed, drifts)
    assert np.max(np.abs(f - f_os)) <= 1e-9 * np.max(np.abs(f_os))


def test_a_non_integer_exponent_stays_finite_where_opensees_does_not():
    """At an elastic reversal the energy ratio of the unloading-stiffness rule is round-off,
    sometimes negative; OpenSees' pow of it is NaN for a non-integer c_K, and its storey then
    unloads along the backbone (or returns NaN). pframe counts it as no deterioration: finite,
    and on unloading from past yield it unloads with (nearly) K0."""
    packed = _packed(c_k=1.3, lamda_s=0.0, lamda_c=0.0, lamda_a=0.0)
    drifts = _growing_cycles(0.05, cycles=6, noise=0.0005, seed=3)
    f, k, s = _pframe(packed, drifts)
    assert np.all(np.isfinite(f)) and np.all(np.isfinite(s))
    ekunload = s[:, ImkPeak.state_names.index("ekunload")]
    assert np.all(ekunload <= 4.0e7) and ekunload.min() > 0.5 * 4.0e7


def _one_storey(excitation, duration, p_delta=False, **changes):
    story = {"material": "imk_peak"} | BASE | changes
    scene = {
        "buildings": [{"name": "A", "floors": 1, "mass": 4.0e4, "height": 3.0,
                       "p_delta": p_delta, "story": story}],
        "damping": {"ratio": 0.02},
        "excitation": excitation,
        "analysis": {"dt": 0.002, "duration": duration},
        "recorders": [{"kind": "history", "quantities": ["story_drift", "story_force"]}],
    }
    return json.dumps(scene)


@pytest.mark.parametrize("p_delta, amplitude", [(False, 2.9), (True, 2.8)])
def test_the_kernel_books_the_loops_area_and_the_balance_closes(p_delta, amplitude):
    """A one-storey frame shaken into deteriorating cycles: the storeys' work the balance books
    equals the area of the recorded force-drift loops (trapezoids), and the balance closes
    (with P-delta too)."""
    w = math.sqrt(4.0e7 / 4.0e4)
    plan, result = run_text(_one_storey({"kind": "sine", "amplitude": amplitude,
                                         "frequency": 0.6 * w / (2 * math.pi), "cycles": 8},
                                        6.0, p_delta=p_delta))
    assert result.completed(0), result.describe_failure(0)
    assert result.energy_error(0) < 1e-10
    d = result.history["story_drift"][0, :, 0]
    f = result.history["story_force"][0, :, 0]
    assert np.max(np.abs(d)) > 3 * 0.0025  # well past yield
    if not p_delta:
        area = float(np.sum(0.5 * (f[1:] + f[:-1]) * np.diff(d)))
        booked = result.energy_terms(0)["storeys"]
        assert booked == pytest.approx(area, rel=1e-9)


def test_the_example_softens_a_storey(tmp_path):
    """models/degrading-frames.yaml: El Centro x 1.5 drives A's first storey past its cap;
    its drift ratio passes 2.5 %, the secant stiffness of its late loops (the material's
    force: the recorded net force plus P drift / h) falls far below K0, its strength
    deteriorates, the frames pound, and the balance (gravity's work included) closes."""
    from pframe.assemble import assemble
    from pframe.kernel import simulate
    from pframe.reader import load_scene

    record_file("elCentro.AT2")
    loaded = load_scene(runnable_model(REPO / "models" / "degrading-frames.yaml", tmp_path))
    plan = assemble(loaded.expanded)
    result = simulate(plan)
    assert result.completed(0), result.describe_failure(0)
    assert result.energy_error(0) < 1e-10
    assert int(result.impacts[0].sum()) >= 1
    e = plan.story_names.index("A/1")
    ratio = result.history["story_drift_ratio"][0, :, e]
    assert np.max(np.abs(ratio)) > 0.025
    d = result.history["story_drift"][0, :, e]
    f = result.history["story_force"][0, :, e] + plan.story_kg[0, e] * d
    k0, my = 4.0e7, 3.0e5
    late = slice(len(d) // 2, None)
    hi, lo = np.argmax(d[late]), np.argmin(d[late])
    secant = (f[late][hi] - f[late][lo]) / (d[late][hi] - d[late][lo])
    assert 0.0 < secant < 0.25 * k0
    assert np.max(np.abs(f[late])) < 0.9 * my < np.max(np.abs(f))


def test_a_scene_of_imk_peak_storeys_agrees_with_its_opensees_export():
    """Two frames of imk_peak storeys (asymmetric, every deterioration on) pounding under a
    sine, exported to OpenSees (zeroLength storeys of ModIMKPeakOriented): the displacements
    and storey forces agree to 1e-12 of their peak (round-off), through yielding, capping and
    deterioration."""
    pytest.importorskip("openseespy.opensees", reason="OpenSeesPy (the peers extra) is not "
                        "installed")
    from pframe.assemble import assemble
    from pframe.kernel import simulate
    from pframe.peers.from_plan import peer_scene
    from pframe.peers.opensees import run
    from pframe.reader import parse_scene

    story = {"material": "imk_peak"} | BASE | {"k0": 4.0e6, "my_plus": 2.5e4, "my_neg": 3.0e4,
                                               "theta_pc_plus": 0.3, "theta_pc_neg": 0.3}
    scene = {
        "buildings": [{"name": "A", "floors": 3, "mass": 4000.0, "story": story},
                      {"name": "B", "floors": 2, "mass": 5000.0,
                       "story": story | {"k0": 6.0e6}}],
        "contacts": [{"name": f"c{i}", "nodes": [f"A/{i}", f"B/{i}"], "gap": 0.005,
                      "law": "linear", "stiffness": 1.0e8} for i in (1, 2)],
        "damping": {"ratio": 0.05, "stiffness": "initial"},
        "excitation": {"kind": "sine", "amplitude": 2.5, "frequency": 2.5, "cycles": 6},
        "analysis": {"dt": 0.001, "duration": 5.0,
                     "newton": {"tolerance": 1.0e-14, "absolute_tolerance": 1.0e-15}},
        "recorders": [{"kind": "history", "quantities": ["displacement", "story_drift",
                                                         "story_force"]}],
    }
    plan = assemble(parse_scene(json.dumps(scene)).expanded)
    result = simulate(plan)
    assert result.completed(), result.describe_failure()
    drift = result.history["story_drift"][0]
    e = plan.story_names.index("A/1")
    assert np.max(np.abs(drift[:, e])) > 2.5e4 / 4.0e6 + 0.02  # A's first storey passed its cap
    assert int(result.impacts[0].sum()) >= 2
    opensees = run(peer_scene(plan))
    u = result.history["displacement"][0]
    assert np.max(np.abs(u - opensees["displacement"])) <= 1e-12 * np.max(np.abs(u))
    f = result.history["story_force"][0]
    assert np.max(np.abs(f - opensees["story_force"])) <= 1e-12 * np.max(np.abs(f))


def test_the_reference_solver_refuses_it_rather_than_miss_its_kinks():
    """pframe accuracy's reference solution locates each law's kinks from a regime
    description; imk_peak has none, so it is refused by name (never integrated across
    unlocated branch changes)."""
    from pframe.errors import InputError
    from pframe.reference.branches import branches_for

    with pytest.raises(InputError, match="material law 'imk_peak'"):
        branches_for(ImkPeak)


def test_a_scaled_scene_is_similar():
    """Similitude (pframe scale, lengths x 1/4, accelerations x 1, masses x 1/16): every
    imk_peak parameter carries its dimension (Lamda and the drifts are lengths, My a force,
    K0 a stiffness), so the scaled storey's drift is the prototype's x 1/4 at the scaled times,
    through yielding, capping and deterioration, and its Pi groups are the prototype's."""
    from pframe.nondim import scale_scene, scene_pi, similitude
    from pframe.reader import parse_scene

    w = math.sqrt(4.0e7 / 4.0e4)
    data = json.loads(_one_storey({"kind": "sine", "amplitude": 2.9,
                                   "frequency": 0.6 * w / (2 * math.pi), "cycles": 8}, 6.0))
    del data["buildings"][0]["height"], data["buildings"][0]["p_delta"]
    factors = similitude({"length": "1/4", "acceleration": 1, "mass": "1/16"})
    scaled = scale_scene(data, factors, "model")
    assert scaled["buildings"][0]["story"]["lamda_s"] == pytest.approx(0.6 / 4)
    prototype, model = parse_scene(json.dumps(data)), parse_scene(json.dumps(scaled))
    before = scene_pi(prototype.scene, prototype.expanded).values
    after = scene_pi(model.scene, model.expanded).values
    for name, value in before.items():
        assert after[name] == pytest.approx(value, rel=1e-12, abs=1e-300), name
    _, big = run_text(json.dumps(data))
    _, small = run_text(json.dumps(scaled))
    d_big = big.history["story_drift"][0, :, 0]
    d_small = small.history["story_drift"][0, :, 0]
    assert np.max(np.abs(d_big)) > 0.0025 + 0.02
    assert np.max(np.abs(d_small - d_big / 4)) <= 1e-9 * np.max(np.abs(d_small))


def test_lamda_c_zero_is_warned_because_it_drops_the_cap():
    """OpenSees' algorithm (followed to the bit) takes lamda_c = 0 as 'the cap's capacity is
    exhausted': the cap's reference force drops by D at the first half cycle past yield, and
    the storey keeps almost no strength past it. A user reading 0 as 'off' would get a
    collapsing storey silently: pframe warns before the run (plan.warnings, which solve
    prints, writes and raises as a Python warning), and not for lamda_c > 0."""
    from pframe.assemble import assemble
    from pframe.reader import parse_scene

    drifts = _growing_cycles(0.1)
    zero, _, _ = _pframe(_packed(lamda_c=0.0, lamda_s=0.0, lamda_a=0.0, lamda_k=0.0), drifts)
    large, _, _ = _pframe(_packed(lamda_c=1e6, lamda_s=0.0, lamda_a=0.0, lamda_k=0.0), drifts)
    late = slice(len(drifts) // 2, None)
    assert np.max(np.abs(zero[late])) < 0.05 * np.max(np.abs(large[late]))

    def warnings(**changes):
        text = _one_storey({"kind": "sine", "amplitude": 1.0, "frequency": 1.0}, 0.1,
                           **changes)
        return [w for w in assemble(parse_scene(text).expanded).warnings if "lamda_c" in w]

    warned = warnings(lamda_c=0.0)
    assert len(warned) == 2 and all(w.startswith("storey A/1: imk_peak with lamda_c = 0")
                                    for w in warned)
    assert "drops by 90%" in warned[1]  # d_neg = 0.9
    assert warnings() == []
