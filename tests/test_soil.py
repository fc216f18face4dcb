"""Soil under a building (docs/soil.md): sway and rocking springs and dashpots.

Wolf's cone formulas against a worked number; the Veletsos & Meek period of a single storey
on flexible soil; a 1-storey building with a heavy foundation against the exact modal
solution of its three DOFs (u, u_f, theta); the energy balance closing with the soil; a fixed
base as the limit of stiffening soil; the kernel against the reference solver (scipy) on a
2-storey building on soil; bad soil input; a scene without soil paying nothing for it.
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest
from conftest import analysis, building, scene_text

from pframe.assemble import assemble
from pframe.errors import InputError
from pframe.kernel import simulate
from pframe.kernel.state import Energy
from pframe.model.soil import cone, equivalent_radii
from pframe.reader import parse_scene

RECORDERS = [{"kind": "history", "quantities": ["displacement", "story_drift",
                                                "foundation_sway", "foundation_rocking"]}]


def _run(text: str):
    plan = assemble(parse_scene(text).expanded)
    return plan, simulate(plan)


def _on_soil(floors: int, mass, k: float, h: float, soil: dict, **scene) -> str:
    b = building("A", floors, mass, {"material": "elastic", "stiffness": k})
    b |= {"height": h, "soil": soil}
    scene.setdefault("recorders", RECORDERS)
    scene.setdefault("damping", {"ratio": 0.0})
    return scene_text(buildings=[b], **scene)


def _given(kh, kr, mf, If, ch=0.0, cr=0.0) -> dict:
    return {"sway_stiffness": kh, "sway_damping": ch, "rocking_stiffness": kr,
            "rocking_damping": cr, "foundation": {"mass": mf, "rotational_inertia": If}}


def test_cone_model_against_wolfs_expressions():
    """Wolf 1994, Table 2-3A, for a 15 m x 15 m foundation on soil of V_s = 150 m/s, rho =
    1800 kg/m^3: G = 4.05e7 Pa; r_h = sqrt(225 / pi) = 8.4628 m, r_r = (15^4 / (3 pi))^(1/4)
    = 8.5610 m. nu = 0.25 (V_p = V_s sqrt(3) = 259.81 m/s, no trapped mass):
    K_h = 8 G r_h / 1.75 = 1.5668e9 N/m, C_h = rho V_s pi r_h^2 = 6.075e7 N s/m,
    K_r = 8 G r_r^3 / 2.25 = 9.0351e10 N m/rad, C_r = rho V_p pi r_r^4 / 4 = 1.9729e9 N m s/rad.
    nu = 0.4: V_p capped at 2 V_s = 300 m/s in C_r = 2.2781e9, and the trapped mass moment
    0.3 pi (0.4 - 1/3) rho r_r^5 = 5.2008e6 kg m^2; K_h = 8 G r_h / 1.6 = 1.7137e9,
    K_r = 8 G r_r^3 / 1.8 = 1.1294e11."""
    r_h, r_r = equivalent_radii(15.0, 15.0)
    assert r_h == pytest.approx(8.46284, rel=1e-5)
    assert r_r == pytest.approx(8.56098, rel=1e-5)
    low = cone(150.0, 0.25, 1800.0, r_h, r_r)
    assert low.p_wave_velocity == pytest.approx(259.808, rel=1e-5)
    assert low.sway_stiffness == pytest.approx(1.56684e9, rel=1e-4)
    assert low.sway_damping == pytest.approx(6.0750e7, rel=1e-4)
    assert low.rocking_stiffness == pytest.approx(9.0351e10, rel=1e-4)
    assert low.rocking_damping == pytest.approx(1.9729e9, rel=1e-4)
    assert low.trapped_inertia == 0.0
    high = cone(150.0, 0.4, 1800.0, r_h, r_r)
    assert high.p_wave_velocity == 300.0
    assert high.sway_stiffness == pytest.approx(1.71372e9, rel=1e-4)
    assert high.rocking_stiffness == pytest.approx(1.12939e11, rel=1e-4)
    assert high.rocking_damping == pytest.approx(2.2781e9, rel=1e-4)
    assert high.trapped_inertia == pytest.approx(5.2008e6, rel=1e-4)
    # a circle is its own equivalent disk; a long strip rocks on its width cubed
    r_h, r_r = equivalent_radii(10.0, 40.0)
    assert math.pi * r_h**2 == pytest.approx(400.0)
    assert math.pi * r_r**4 / 4.0 == pytest.approx(40.0 * 10.0**3 / 12.0)


def test_the_scene_applies_the_cone_model_and_says_so():
    soil = {"shear_wave_velocity": 150.0, "poisson": 0.4, "density": 1800.0,
            "foundation": {"width": 15.0, "mass": 4.0e5}}
    plan, _ = _run(_on_soil(2, 2.0e5, 2.0e8, 3.0, soil, analysis=analysis(0.01, 0.02)))
    from pframe.record.hdf5 import soil_attributes

    attrs = soil_attributes(plan)
    c = cone(150.0, 0.4, 1800.0, *equivalent_radii(15.0, 15.0))
    assert attrs["soil_sway_stiffness"][0] == c.sway_stiffness
    assert attrs["soil_rocking_damping"][0] == c.rocking_damping
    # the rocking DOF's inertia: a slab's m b^2 / 12 plus the trapped soil
    theta = plan.foundation_dofs[0, 1]
    assert plan.mass[0, theta] == pytest.approx(4.0e5 * 225.0 / 12.0 + c.trapped_inertia)
    assert "Wolf's cone model" in plan.foundation_soil[0]


def _zero_crossing_period(t, u) -> float:
    up = np.flatnonzero((u[:-1] < 0.0) & (u[1:] >= 0.0))
    times = t[up] - u[up] * (t[up + 1] - t[up]) / (u[up + 1] - u[up])
    return float(np.mean(np.diff(times)))


def test_veletsos_meek_period_lengthening():
    """A single storey (m, k, h) on sway and rocking springs with a light foundation:
    T~ / T = sqrt(1 + k / k_h + k h^2 / k_r) (Veletsos & Meek 1974), from its free
    vibration (the light foundation's own modes are orders of magnitude faster; HHT's
    numerical damping removes them, leaving the slow mode's period to O(dt^2))."""
    m, k, h, kh, kr = 1.0e5, 4.0e7, 10.0, 2.0e8, 4.0e10
    text = _on_soil(1, m, k, h, _given(kh, kr, 1.0, 10.0),
                    initial_conditions={"displacement": {"A/1": 0.01}},
                    analysis={"integrator": {"type": "hht", "alpha": 0.1}, "dt": 2.5e-4,
                              "duration": 3.0})
    plan, result = _run(text)
    u = result.history["displacement"][0, :, 0]
    fixed = 2.0 * math.pi * math.sqrt(m / k)
    expected = fixed * math.sqrt(1.0 + k / kh + k * h * h / kr)
    assert expected / fixed > 1.1  # a real lengthening
    assert _zero_crossing_period(plan.times, u) == pytest.approx(expected, rel=2e-3)


def test_heavy_foundation_follows_the_exact_modal_solution():
    """One storey on soil with a foundation as heavy as the floor: three DOFs (u, u_f,
    theta) with M = diag(m, m_f, I_f) and K = k g g^T + diag(0, k_h, k_r), g = (1, -1, -h).
    Released from u = u0, the kernel follows sum_j phi_j q_j cos(w_j t) (undamped) to
    Newmark's period error, which falls as dt^2."""
    m, k, h, kh, kr, mf, If = 1.0e5, 4.0e7, 10.0, 1.0e8, 2.0e10, 1.0e5, 3.0e6
    g = np.array([1.0, -1.0, -h])
    K = k * np.outer(g, g) + np.diag([0.0, kh, kr])
    M = np.diag([m, mf, If])
    w2, phi = np.linalg.eigh(np.linalg.inv(np.sqrt(M)) @ K @ np.linalg.inv(np.sqrt(M)))
    phi = np.linalg.inv(np.sqrt(M)) @ phi
    u0 = np.array([0.01, 0.0, 0.0])
    q0 = phi.T @ M @ u0
    errors = []
    for dt in (4e-4, 2e-4):
        text = _on_soil(1, m, k, h, _given(kh, kr, mf, If),
                        initial_conditions={"displacement": {"A/1": 0.01}},
                        analysis=analysis(dt, 1.0))
        plan, result = _run(text)
        t = plan.times
        exact = (phi * q0) @ np.cos(np.sqrt(w2)[:, None] * t)
        got = np.stack([result.history["displacement"][0, :, plan.node_dof[0]],
                        result.history["foundation_sway"][0, :, 0],
                        result.history["foundation_rocking"][0, :, 0]])
        errors.append([np.max(np.abs(got[i] - exact[i])) / np.max(np.abs(exact[i]))
                       for i in range(3)])
        # the storey deforms by its drift: u - u_f - h theta (without the rigid rotation)
        np.testing.assert_allclose(result.history["story_drift"][0, :, 0],
                                   got[0] - got[1] - h * got[2], atol=1e-15)
    errors = np.array(errors)
    assert np.all(errors[-1] < 5e-3), errors
    assert np.all(errors[0] / errors[1] > 3.5), errors  # second order


def test_foundation_quantities_are_its_dofs_and_their_peaks():
    """foundation_sway and foundation_rocking are the foundation's DOFs, their envelopes
    the peaks of their histories (history and envelope recorded together)."""
    text = _on_soil(2, 1e5, 5e7, 3.0, _given(1e8, 1e10, 5e4, 5e5, 1e6, 1e8),
                    excitation={"kind": "sine", "amplitude": 2.0, "frequency": 10.0},
                    analysis=analysis(1e-3, 0.5),
                    recorders=RECORDERS + [{"kind": "envelope", "quantities": [
                        "foundation_sway", "foundation_rocking"]}])
    plan, result = _run(text)
    sway, theta = plan.foundation_dofs[0]
    assert plan.bandwidth == 3 and theta == plan.n_dof - 1  # the rocking DOF last
    for q, dof in (("foundation_sway", sway), ("foundation_rocking", theta)):
        h = result.history[q][0, :, 0]
        assert np.max(np.abs(h)) > 0.0
        # the kernel's displacement rows hold every DOF (the file keeps the nodes')
        np.testing.assert_array_equal(h, result.history["displacement"][0, :, dof])
        assert result.envelope[q][0, 0] == np.max(np.abs(h))


def _balance(result, b=0):
    e = result.energy[b]
    rest = (e[Energy.KINETIC] - e[Energy.KINETIC_0] + e[Energy.DAMPING] + e[Energy.STOREYS]
            + e[Energy.CONTACTS] + e[Energy.LINKS] + e[Energy.ALGORITHMIC])
    return e[Energy.INPUT], rest


@pytest.mark.parametrize("integrator", [{"type": "newmark", "gamma": 0.5, "beta": 0.25},
                                        {"type": "hht", "alpha": 0.1},
                                        {"type": "central_difference"}])
def test_energy_balance_closes_on_soil(integrator):
    """Under a sine, with Rayleigh damping in the storeys and the soil's dashpots: the
    ground's work (on the translations only) is the kinetic energy, the damping, the
    storeys' work, the soil's (booked with the links) and the integrator's dissipation."""
    soil = {"shear_wave_velocity": 120.0, "poisson": 0.45, "density": 1800.0,
            "foundation": {"width": 12.0, "length": 20.0, "mass": 3.0e5}}
    text = _on_soil(3, 2.0e5, 1.5e8, 3.2, soil, damping={"ratio": 0.05},
                    excitation={"kind": "sine", "amplitude": 3.0, "frequency": 8.0},
                    analysis={"integrator": integrator, "dt": 1e-4, "duration": 2.0})
    _, result = _run(text)
    assert result.completed(0)
    work_in, rest = _balance(result)
    assert result.energy[0, Energy.LINKS] > 0.01 * work_in  # the soil's dashpots take some
    assert abs(work_in - rest) < 1e-9 * result.energy[0, Energy.INPUT_ABS]


def test_stiff_soil_converges_to_the_fixed_base():
    """The same 3-storey building under a sine, on soil stiffened 10^2 .. 10^6 times: its
    floor displacements converge to the fixed-base building's, the error falling with the
    soil's flexibility (about as 1 / stiffness)."""
    common = dict(excitation={"kind": "sine", "amplitude": 2.0, "frequency": 10.0},
                  analysis=analysis(1e-3, 2.0),
                  recorders=[{"kind": "history", "quantities": ["displacement"]}],
                  damping={"ratio": 0.05})
    fixed = scene_text(buildings=[building("A", 3, 2.0e5, {"material": "elastic",
                                                          "stiffness": 1.5e8})
                                  | {"height": 3.2}], **common)
    _, ref = _run(fixed)
    u_fixed = ref.history["displacement"][0]
    errors = []
    for scale in (1e2, 1e4, 1e6):
        text = _on_soil(3, 2.0e5, 1.5e8, 3.2,
                        _given(1.5e8 * scale, 1.5e8 * 100.0 * scale, 1.0e5, 1.0e6,
                               1e6, 1e8), **common)
        plan, result = _run(text)
        u = result.history["displacement"][0][:, plan.node_dof]
        errors.append(np.max(np.abs(u - u_fixed[:, _fixed_dofs(fixed)]))
                      / np.max(np.abs(u_fixed)))
    assert errors[-1] < 1e-5, errors
    assert errors[0] > errors[1] > errors[2], errors
    assert errors[0] / errors[1] > 30 and errors[1] / errors[2] > 30, errors


def _fixed_dofs(text):
    return assemble(parse_scene(text).expanded).node_dof


@pytest.mark.slow
def test_kernel_agrees_with_the_reference_solver_on_soil():
    """A 2-storey building on soil (sway and rocking dashpots, Rayleigh damping on the
    initial stiffness) under a sine: the kernel (Newmark, dt = 2e-4) against the reference
    solver (scipy DOP853 on the same equations of motion, rtol 1e-10), to Newmark's error."""
    from pframe.reference import of_scene, solve

    soil = {"shear_wave_velocity": 100.0, "poisson": 0.3, "density": 1700.0,
            "foundation": {"width": 10.0, "mass": 2.0e5}}
    text = _on_soil(2, 1.5e5, 8.0e7, 3.0, soil, damping={"ratio": 0.05},
                    excitation={"kind": "sine", "amplitude": 2.0, "frequency": 9.0},
                    analysis=analysis(2e-4, 1.5))
    loaded = parse_scene(text)
    plan = assemble(loaded.expanded)
    result = simulate(plan)
    reference = solve(plan, ground=of_scene(loaded), rtol=1e-10)
    for q in ("displacement", "foundation_sway", "foundation_rocking", "story_drift"):
        got, want = result.history[q][0], reference.history(q)
        scale = np.max(np.abs(want))
        assert scale > 0.0
        assert np.max(np.abs(got - want)) < 2e-4 * scale, q


@pytest.mark.parametrize("soil, where, says", [
    ({"sway_stiffness": 1e8, "foundation": {"mass": 1e5, "rotational_inertia": 1e6}},
     "buildings[0].soil", "sway_damping, rocking_stiffness, rocking_damping as well"),
    ({"shear_wave_velocity": 150.0, "poisson": 0.3, "density": 1800.0,
      "foundation": {"mass": 1e5, "rotational_inertia": 1e6}},
     "buildings[0].soil", "the foundation's size"),
    ({"shear_wave_velocity": 150.0, "poisson": 0.6, "density": 1800.0,
      "foundation": {"mass": 1e5, "width": 10.0}},
     "buildings[0].soil.poisson", "0.5"),
])
def test_bad_soil_is_refused_in_one_paragraph(soil, where, says):
    text = _on_soil(1, 1e5, 1e7, 3.0, soil, analysis=analysis(0.01, 0.1))
    with pytest.raises(InputError) as info:
        parse_scene(text)
    message = str(info.value)
    assert where in message and says in message and "\n" not in message.strip()


def test_soil_needs_heights():
    b = building("A", 1, 1e5, {"material": "elastic", "stiffness": 1e7}) | {
        "soil": _given(1e8, 1e10, 1e5, 1e6)}
    with pytest.raises(InputError, match=r"buildings\[0\]\.soil.*give height"):
        parse_scene(scene_text(buildings=[b], analysis=analysis(0.01, 0.1)))


def test_a_scene_without_soil_pays_nothing():
    """No extra DOFs nor springs; every DOF takes the whole ground load."""
    text = scene_text(buildings=[building("A", 3, 1e5, {"material": "elastic",
                                                        "stiffness": 1e8})],
                      analysis=analysis(0.01, 0.1))
    plan = assemble(parse_scene(text).expanded)
    assert plan.n_dof == 3 and plan.n_springs == 3 and plan.foundations == ()
    assert not plan.story_sides.general().any() and np.all(plan.dof_channel == 0)


@pytest.mark.slow
def test_ssi_pair_against_the_fixed_pair():
    """models/ssi-pair.yaml (the paper's pair on soft soil) against models/wu2021-eq14.yaml
    (the same pair fixed): both complete with their balance closed; the soil lengthens the
    buildings' periods, so the pair's response differs (peaks, impact forces) while they still
    pound; the foundations sway and rock."""
    from conftest import REPO

    from pframe.reader import load_scene

    runs = {}
    for name in ("ssi-pair", "wu2021-eq14"):
        loaded = load_scene(REPO / "models" / f"{name}.yaml")
        plan = assemble(loaded.expanded)
        result = simulate(plan)
        assert result.completed(0)
        work_in, rest = _balance(result)
        assert abs(work_in - rest) < 1e-9 * result.energy[0, Energy.INPUT_ABS]
        runs[name] = (plan, result)
    (soil_plan, soil), (fixed_plan, fixed) = runs["ssi-pair"], runs["wu2021-eq14"]
    assert soil_plan.node_names == fixed_plan.node_names
    peak_soil = soil.envelope["displacement"][0][soil_plan.node_dof]
    peak_fixed = fixed.envelope["displacement"][0][fixed_plan.node_dof]
    assert np.max(np.abs(peak_soil / peak_fixed - 1.0)) > 0.02  # the soil matters
    assert np.all(soil.impacts[0] > 0) and np.all(fixed.impacts[0] > 0)  # both still pound
    assert np.all(soil.envelope["foundation_sway"][0] > 0)
    assert np.all(soil.envelope["foundation_rocking"][0] > 0)
    # the soil lengthens each building's first period (Veletsos & Meek), here by 10-40 %
    for b in (0, 1):
        nodes = [i for i, n in enumerate(soil_plan.node_names)
                 if n.split("/")[0] == soil_plan.buildings[b]]
        assert len(nodes) == 3
    lengthening = _first_periods(soil_plan) / _first_periods(fixed_plan)
    assert np.all((lengthening > 1.1) & (lengthening < 1.4)), lengthening


def _first_periods(plan) -> np.ndarray:
    """Each building's first period (s) from its DOFs' undamped K and M (contacts open)."""
    n = plan.n_dof
    K = np.zeros((n, n))
    sided = plan.story_sides.general()
    for e, (lo, up) in enumerate(plan.story_dofs):
        g = np.zeros(n)
        if sided[e]:  # a storey on soil: u_upper - (u_lower + h theta), its sides' terms
            for side, sign in ((0, -1.0), (1, 1.0)):
                for dof, c in plan.story_sides.side(e, side):
                    g[dof] += sign * c
            assert g[plan.foundation_dofs[:, 1]].min() < 0  # the lever -h on the rocking
        else:
            g[up] = 1.0
            if lo >= 0:
                g[lo] = -1.0
        K += plan.story_k0[0, e] * np.outer(g, g)
    M = plan.mass[0]
    building = np.empty(n, dtype=np.int64)
    for name, dof in zip(plan.node_names, plan.node_dof):
        building[dof] = plan.buildings.index(name.split("/")[0])
    if plan.foundation_dofs is not None:
        for f, name in enumerate(plan.foundations):
            building[plan.foundation_dofs[f]] = plan.buildings.index(name)
    out = []
    for b in range(len(plan.buildings)):
        idx = np.flatnonzero(building == b)
        s = 1.0 / np.sqrt(M[idx])
        w2 = np.linalg.eigvalsh(K[np.ix_(idx, idx)] * np.outer(s, s))
        out.append(2.0 * math.pi / math.sqrt(w2[0]))
    return np.array(out)


def test_a_sweep_over_the_soil_equals_each_scene_run_alone(tmp_path):
    """Soil values are sweep parameters like any other: each variant of a sweep over the sway
    stiffness holds, bit for bit, the peaks of its own scene run alone."""
    import h5py
    import yaml

    from pframe.sweep import load_sweep, run_sweep

    soil = _given(2.0e8, 4.0e10, 1.0e3, 1.0e4, ch=1.0e5, cr=1.0e7)
    text = _on_soil(2, 1.0e5, 4.0e7, 3.5, soil,
                    excitation={"kind": "sine", "amplitude": 2.0, "frequency": 9.0,
                                "cycles": 3},
                    analysis={"dt": 1e-3, "duration": 2.0})
    (tmp_path / "base.yaml").write_text(text)
    values = [2.0e7, 2.0e8]
    (tmp_path / "sweep.yaml").write_text(yaml.safe_dump({
        "base": "base.yaml",
        "axes": [{"name": "kh", "path": "buildings.A.soil.sway_stiffness",
                  "values": values, "units": "N/m"}]}))
    out = tmp_path / "out.nc"
    assert run_sweep(load_sweep(tmp_path / "sweep.yaml"), out).completed
    with h5py.File(out, "r") as f:
        peaks = np.asarray(f["peak_displacement"])
    assert not np.allclose(peaks[0], peaks[1])  # the soil matters
    for i, kh in enumerate(values):
        plan, alone = _run(_on_soil(2, 1.0e5, 4.0e7, 3.5, soil | {"sway_stiffness": kh},
                                    excitation={"kind": "sine", "amplitude": 2.0,
                                                "frequency": 9.0, "cycles": 3},
                                    analysis={"dt": 1e-3, "duration": 2.0},
                                    recorders=[{"kind": "envelope",
                                                "quantities": ["displacement"]}]))
        assert np.array_equal(peaks[i], alone.envelope["displacement"][0][plan.node_dof])


def test_the_gap_audit_takes_the_flexible_base_period():
    """The gap audit's first modes (its DDC rule and sa:BUILDING measure) see the soil: a
    single storey on a light foundation has Veletsos & Meek's lengthened period, and the audit
    of the paper's pair on soil runs (it used to stop on the foundation's unnamed DOFs)."""
    from pframe.gap.audit import prepare
    from pframe.gap.runs import first_modes

    m, k, h, kh, kr = 1.0e5, 4.0e7, 10.0, 2.0e8, 4.0e10
    plan, _ = _run(_on_soil(1, m, k, h, _given(kh, kr, 1.0, 10.0),
                            analysis={"dt": 1e-3, "duration": 0.01}))
    periods, _ = first_modes(plan)
    fixed = 2.0 * math.pi * math.sqrt(m / k)
    assert periods[0] == pytest.approx(fixed * math.sqrt(1.0 + k / kh + k * h * h / kr),
                                       rel=1e-4)
    models = Path(__file__).resolve().parents[1] / "models"
    inputs = prepare(models / "ssi-pair.yaml")
    fixed_inputs = prepare(models / "wu2021-eq14.yaml")
    assert np.all(inputs.periods > 1.05 * fixed_inputs.periods)
