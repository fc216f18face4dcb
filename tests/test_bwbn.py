"""The bwbn storey material: Bouc-Wen-Baber-Noori (degradation and pinching).

- Against OpenSeesPy's ``BWBN`` (the peers extra) under prescribed drift histories: the same
  forces to round-off, pinched or not (OpenSees' BWBN has no A, nu, eta degradation).
- Its tangent against central differences of its force, pinched and degrading (where
  OpenSees' BWBN tangent is not the derivative of its force).
- Without pinching it is ``bouc_wen``: the same forces and states bit for bit, degrading or not.
- Published cyclic behaviour (Baber & Noori 1986, Foliente 1995): pinched loops are soft near
  zero force on reloading, more so as energy is dissipated; strength and stiffness degrade
  with the dissipated energy under cycles of constant amplitude.
- Through the kernel, a building of bwbn storeys under El Centro 1940: the storeys' work is
  the area of the recorded force-drift loops and the energy balance closes; and a pinched
  building agrees with its OpenSees export.
"""

from __future__ import annotations

import json

import numpy as np
import pytest
from conftest import drive_material, record_file, run_text

from pframe.laws.registry import get_law

BWBN = get_law("material", "bwbn")
BOUC_WEN = get_law("material", "bouc_wen")

Z_U = 0.01  # m: the ultimate hysteretic displacement of the storeys below
K0 = 2.0e7
SHAPE = dict(alpha=0.05, ko=K0, n=2.0, gamma=0.5 / Z_U**2, beta=0.5 / Z_U**2)
PINCHING = dict(q=0.1, zetas=0.9, p=2.0e-4, psi=0.004, deltaPsi=1.0e-7, lamda=0.5)
DEGRADING = dict(deltaA=1.0e-6, deltaNu=2.0e-6, deltaEta=1.0e-6)


def _packed(**fields):
    return BWBN.pack(BWBN.Params(material="bwbn", **(SHAPE | fields)))


_run = drive_material


_TAG = [0]


def _opensees(packed, drifts):
    ops = pytest.importorskip("openseespy.opensees", reason="OpenSeesPy (the peers extra) "
                              "is not installed")
    _TAG[0] += 1
    ops.wipe()
    # alpha ko n gamma beta Ao | q zetas p Shi deltaShi lamda | tolerance maxNumIter
    ops.uniaxialMaterial("BWBN", _TAG[0], *packed[:6], *packed[9:16], int(packed[16]))
    ops.testUniaxialMaterial(_TAG[0])
    forces, tangents = [], []
    for d in drifts:
        ops.setStrain(float(d))
        forces.append(ops.getStress())
        tangents.append(ops.getTangent())
    return np.array(forces), np.array(tangents)


def _cycles(amplitude, cycles=6, n=3000, growing=True, noise=0.0, seed=0):
    t = np.linspace(0.0, cycles, n + 1)
    envelope = t / cycles if growing else np.minimum(1.0, 4.0 * t)
    d = amplitude * envelope * np.sin(2 * np.pi * t)
    if noise:
        d = d + noise * np.random.default_rng(seed).standard_normal(d.size)
    return d[1:]


def _central_differences(packed, drifts, every=37, h=1e-8):
    """(tangent, central difference of the force) at every ``every``-th step of the history,
    each from that step's committed state."""
    committed = np.zeros(3)
    trial = committed.copy()
    out = []
    for i, d in enumerate(drifts):
        _, k, _ = BWBN.force(packed, committed, trial, float(d), 0.0)
        following = trial.copy()
        if i % every == 5 % every:
            up = BWBN.force(packed, committed, trial.copy(), float(d) + h, 0.0)[0]
            down = BWBN.force(packed, committed, trial.copy(), float(d) - h, 0.0)[0]
            out.append((k, (up - down) / (2 * h)))
        committed = following
    return np.array(out)


@pytest.mark.parametrize("pinched", [False, True])
def test_agrees_with_opensees_bwbn(pinched):
    """Growing cycles to 5 z_u: OpenSees' BWBN forces to round-off (the same Newton for z from
    0.01); where pinching is off its tangent too."""
    packed = _packed(**(PINCHING if pinched else {}))
    drifts = _cycles(0.05)
    f, k, _ = _run(BWBN, packed, drifts)
    f_os, k_os = _opensees(packed, drifts)
    assert np.max(np.abs(f - f_os)) <= 1e-12 * np.max(np.abs(f_os))
    if not pinched:
        assert np.max(np.abs(k - k_os)) <= 1e-12 * K0


@pytest.mark.parametrize("seed", range(4))
def test_agrees_with_opensees_on_random_pinched_storeys(seed):
    """Random shapes (n from 1 to 4, beta / (beta + gamma) from 0.3 to 0.8) and pinching
    parameters under growing cycles with small reversals: OpenSees' forces to round-off."""
    rng = np.random.default_rng(seed)
    total = 1.0 / Z_U ** (n := float(rng.choice([1.0, 2.0, 3.5])))
    share = rng.uniform(0.3, 0.8)
    packed = _packed(n=n, beta=share * total, gamma=(1 - share) * total,
                     alpha=rng.uniform(0.0, 0.2), q=rng.uniform(0.0, 0.4),
                     zetas=rng.uniform(0.5, 0.95), p=rng.uniform(1e-5, 1e-3),
                     psi=Z_U * rng.uniform(0.1, 0.6), deltaPsi=rng.uniform(0.0, 1e-6),
                     lamda=rng.uniform(0.1, 1.0))
    drifts = _cycles(0.06, noise=0.0005 * (seed % 2), seed=seed)
    f, _, _ = _run(BWBN, packed, drifts)
    f_os, _ = _opensees(packed, drifts)
    assert np.max(np.abs(f - f_os)) <= 1e-12 * np.max(np.abs(f_os))


@pytest.mark.slow
def test_tangent_is_the_derivative_of_the_force():
    """Pinched and degrading, along a cyclic history: the tangent is dF/du of the step's
    update (central differences, 1e-8 of k0). OpenSees' BWBN tangent is not, where the
    pinching acts (its numerator misses the drift increment's factor)."""
    for fields in (PINCHING | DEGRADING, PINCHING, DEGRADING):
        pairs = _central_differences(_packed(**fields), _cycles(0.05))
        assert len(pairs) > 50
        assert np.max(np.abs(pairs[:, 0] - pairs[:, 1])) <= 1e-8 * K0, fields
    pytest.importorskip("openseespy.opensees", reason="OpenSeesPy (the peers extra) is not "
                        "installed")
    packed = _packed(**PINCHING)
    drifts = _cycles(0.05)
    _, k_os = _opensees(packed, drifts)
    differences = _central_differences(packed, drifts, every=1)[:, 1]
    assert np.max(np.abs(k_os - differences)) > 0.5 * K0


@pytest.mark.parametrize("degrading", [False, True])
def test_without_pinching_it_is_bouc_wen(degrading):
    """zetas = 0: the force and the state (drift, z, e) of bouc_wen bit for bit (the pinching
    factor is exactly 1), the tangent to round-off (the same derivative, summed in another
    order), along cycles with reversals, degrading or not."""
    extra = DEGRADING if degrading else {}
    bw = BOUC_WEN.pack(BOUC_WEN.Params(material="bouc_wen", **SHAPE, **extra))
    drifts = _cycles(0.05, noise=0.0005)
    f_bw, k_bw, s_bw = _run(BOUC_WEN, bw, drifts)
    # the pinching's other parameters are inert without zetas
    f, k, s = _run(BWBN, _packed(**extra, q=0.3, p=1e-3, psi=0.002, lamda=0.4), drifts)
    assert np.array_equal(f, f_bw) and np.array_equal(s, s_bw)
    assert np.max(np.abs(k - k_bw)) <= 1e-12 * K0


def _zero_crossings(f, k, d):
    """The tangents where the force changes sign while the drift grows in that direction
    (reloading through zero force), in order."""
    out = []
    for i in range(1, len(f)):
        if f[i - 1] * f[i] < 0 and (d[i] - d[i - 1]) * f[i] > 0:
            out.append(k[i])
    return np.array(out)


@pytest.mark.slow
def test_loops_pinch_and_more_as_energy_is_dissipated():
    """Baber & Noori's pinching: on reloading through zero force the pinched storey's tangent
    is far below the virgin tangent k0 and below the unpinched storey's there, and it falls
    from cycle to cycle as zeta1 = zetas (1 - exp(-p e)) grows with the dissipated energy.
    The unpinched loop reloads through zero force stiffer than half of k0."""
    drifts = _cycles(0.04, cycles=8, n=8000, growing=False)
    f, k, _ = _run(BWBN, _packed(**PINCHING), drifts)
    f0, k0, _ = _run(BWBN, _packed(), drifts)
    pinched, plain = _zero_crossings(f, k, drifts), _zero_crossings(f0, k0, drifts)
    assert len(pinched) >= 12 and len(plain) >= 12
    assert np.all(plain[2:] > 0.5 * K0)
    assert np.all(pinched[2:] < 0.5 * plain[2:])
    assert pinched[-1] < 0.2 * K0
    assert pinched[-1] < pinched[2]
    # the pinched loop encloses less area (dissipates less) per cycle
    area = float(np.sum(0.5 * (f[1:] + f[:-1]) * np.diff(drifts)))
    area0 = float(np.sum(0.5 * (f0[1:] + f0[:-1]) * np.diff(drifts)))
    assert 0.0 < area < area0


def _peaks(f, d):
    """The largest force of each positive excursion (between upward zero crossings of d)."""
    up = np.flatnonzero((d[:-1] <= 0) & (d[1:] > 0))
    return np.array([f[a:b].max() for a, b in zip(up[:-1], up[1:])])


@pytest.mark.slow
def test_strength_and_stiffness_degrade_with_dissipated_energy():
    """Cycles of constant amplitude (4 z_u): without degradation the peak force and the
    unloading tangent stay constant; with deltaNu (strength) the peak force falls every cycle;
    with deltaEta (stiffness) the unloading tangent, k0 (alpha + (1 - alpha) A / eta) at a
    peak, falls every cycle; as the hysteretic energy e (the third state variable) grows."""
    drifts = _cycles(0.04, cycles=10, n=10000, growing=False)
    unloading = np.flatnonzero((drifts[1:-1] > drifts[:-2]) & (drifts[1:-1] >= drifts[2:])) + 2
    f0, k0, s0 = _run(BWBN, _packed(), drifts)
    steady = _peaks(f0, drifts)
    assert np.max(np.abs(np.diff(steady))) <= 1e-9 * steady[-1]
    assert np.all(k0[unloading] == K0)
    assert np.all(np.diff(s0[:, 2][::500]) > 0)  # the energy grows every half cycle
    f, _, _ = _run(BWBN, _packed(deltaNu=5e-6), drifts)
    weaker = _peaks(f, drifts)
    assert np.all(np.diff(weaker) < 0) and weaker[-1] < 0.85 * steady[-1]
    _, k, _ = _run(BWBN, _packed(deltaEta=5e-6), drifts)
    assert np.all(np.diff(k[unloading]) < 0) and k[unloading][-1] < 0.6 * K0


def _scene(story, excitation, duration, dt=0.005, floors=3):
    return json.dumps({
        "buildings": [{"name": "A", "floors": floors, "mass": 2.0e5, "height": 3.0,
                       "story": {"material": "bwbn"} | story}],
        "damping": {"ratio": 0.05, "stiffness": "initial"},
        "excitation": excitation,
        "analysis": {"dt": dt, "duration": duration,
                     "newton": {"tolerance": 1.0e-14, "absolute_tolerance": 1.0e-15}},
        "recorders": [{"kind": "history", "quantities": ["displacement", "story_drift",
                                                         "story_force"]}],
    })


@pytest.mark.slow
def test_a_building_under_el_centro_balances_its_energy():
    """Three pinched, degrading storeys under El Centro 1940 x 2: they yield (drift past
    z_u), the storeys' work the balance books is the area of the recorded force-drift loops,
    and the balance closes."""
    record = record_file("elCentro.AT2")
    story = SHAPE | PINCHING | DEGRADING
    plan, result = run_text(_scene(story, {"kind": "record", "file": str(record),
                                           "scale": 2.0}, 12.0))
    assert result.completed(0), result.describe_failure(0)
    assert result.energy_error(0) < 1e-10
    d = result.history["story_drift"][0]
    f = result.history["story_force"][0]
    assert np.max(np.abs(d[:, 0])) > 2 * Z_U
    area = float(np.sum(0.5 * (f[1:] + f[:-1]) * np.diff(d, axis=0)))
    assert result.energy_terms(0)["storeys"] == pytest.approx(area, rel=1e-9)


def test_a_pinched_building_agrees_with_its_opensees_export():
    """A 3-storey building of pinched storeys (no degradation: what OpenSees' BWBN models)
    under a sine, exported to OpenSees (zeroLength + BWBN): displacements and storey forces
    agree to 1e-9 of their peak. Not to round-off: the two Newton solves use different
    tangents (OpenSees' is not the derivative where the pinching acts), so they agree to
    their convergence tolerance."""
    pytest.importorskip("openseespy.opensees", reason="OpenSeesPy (the peers extra) is not "
                        "installed")
    from pframe.assemble import assemble
    from pframe.kernel import simulate
    from pframe.peers.from_plan import peer_scene
    from pframe.peers.opensees import run
    from pframe.reader import parse_scene

    plan = assemble(parse_scene(_scene(SHAPE | PINCHING, {"kind": "sine", "amplitude": 4.0,
                                                          "frequency": 1.2, "cycles": 4},
                                       4.0, dt=0.002)).expanded)
    result = simulate(plan)
    assert result.completed(), result.describe_failure()
    assert np.max(np.abs(result.history["story_drift"][0][:, 0])) > 2 * Z_U
    opensees = run(peer_scene(plan))
    u = result.history["displacement"][0]
    assert np.max(np.abs(u - opensees["displacement"])) <= 1e-9 * np.max(np.abs(u))
    f = result.history["story_force"][0]
    assert np.max(np.abs(f - opensees["story_force"])) <= 1e-9 * np.max(np.abs(f))


def test_opensees_export_writes_bwbn_and_refuses_degradation(tmp_path):
    """pframe opensees writes a bwbn storey as BWBN; with A, nu or eta degradation (which
    OpenSees' BWBN lacks) it refuses, saying why."""
    import pframe
    from pframe.errors import InputError

    path = tmp_path / "bwbn.yaml"
    sine = {"kind": "sine", "amplitude": 1.0, "frequency": 3.0}
    path.write_text(_scene(SHAPE | PINCHING, sine, 0.1), encoding="utf-8")
    script = pframe.to_opensees(path)
    assert '"BWBN"' in script and "'bwbn'" in script
    path.write_text(_scene(SHAPE | PINCHING | {"deltaNu": 1e-6}, sine, 0.1), encoding="utf-8")
    with pytest.raises(InputError, match="BWBN has no strength or stiffness degradation"):
        pframe.to_opensees(path)


def test_input_errors_name_the_field():
    """Pinching without its spread, or a severity of 1 or more, is refused naming the
    storey and the field."""
    from pframe.errors import InputError
    from pframe.reader import parse_scene

    sine = {"kind": "sine", "amplitude": 1.0, "frequency": 3.0}
    for bad, message in (({"zetas": 0.5}, "needs psi and lamda"),
                         ({"zetas": 0.5, "psi": 0.004}, "needs lamda"),
                         ({"zetas": 1.0, "psi": 0.004, "lamda": 0.5}, "zetas: Input should be "
                                                                      "less than 1"),
                         ({"q": -0.1}, "q: Input should be greater than or equal to 0")):
        with pytest.raises(InputError, match=r"buildings\[0\]") as error:
            parse_scene(_scene(SHAPE | bad, sine, 0.1))
        assert message in str(error.value)
