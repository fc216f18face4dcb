"""``pframe modes`` and ``pframe.modes`` (docs/modes.md) against eigen-solutions written here
on hand-built M and K: a fixed-base shear building, a building on soil, an isolated building
(a bilinear bearing at its post-yield stiffness, a friction pendulum at W / R), buildings in
plan (the closed forms of a symmetric one-storey building, the coupling of an eccentric one),
two buildings coupled by links; effective masses that add up to the total mass; the
participation closed form of a uniform two-storey building; bad input."""

from __future__ import annotations

import math

import numpy as np
import pytest
import scipy.linalg
from conftest import analysis, building

import pframe
from pframe.cli import main
from pframe.laws.registry import GRAVITY

ANALYSIS = analysis(0.01, 0.1)


def _scene(**parts) -> dict:
    return {"analysis": ANALYSIS} | parts


def _reference(K: np.ndarray, M: np.ndarray, iota: np.ndarray):
    """(periods, Gamma) of K phi = w^2 M phi with phi^T M phi = 1 (scipy)."""
    w2, phi = scipy.linalg.eigh(K, M)
    return 2.0 * np.pi / np.sqrt(w2), phi.T @ M @ iota


def _chain(k: list[float]) -> np.ndarray:
    """The stiffness of a shear building with storey stiffnesses ``k`` (bottom up)."""
    n = len(k)
    K = np.zeros((n, n))
    for i, ki in enumerate(k):
        K[i, i] += ki
        if i:
            K[i - 1, i - 1] += ki
            K[i - 1, i] -= ki
            K[i, i - 1] -= ki
    return K


def _row(ds, label: str):
    return ds.sel(analysis=label)


def _agrees(row, periods, gamma):
    """The analysis ``row`` has ``periods`` and participation factors ``gamma`` (to sign)."""
    n = len(periods)
    np.testing.assert_allclose(row.period.values[:n], periods, rtol=1e-9)
    np.testing.assert_allclose(np.abs(row.participation_factor.values[:n, 0]), np.abs(gamma),
                               rtol=1e-7, atol=1e-9 * math.sqrt(row.total_mass.values[0]))


MASSES, STIFF = [2.0e4, 1.5e4, 1.0e4], [3.0e7, 2.5e7, 1.5e7]


def test_a_fixed_base_shear_building_and_its_rayleigh_ratios():
    """Periods and participation against scipy on M and K; the Rayleigh ratio of every mode
    against a0 / (2 w) + a1 w / 2 with the textbook coefficients on modes 1 and 2 (Chopra
    2012 eq. 11.4.9); the effective masses add up to the building's mass."""
    story = {"material": "elastic", "stiffness": STIFF}
    ds = pframe.modes(_scene(buildings=[building("A", 3, MASSES, story)],
                             damping={"ratio": 0.04}))
    M = np.diag(MASSES)
    periods, gamma = _reference(_chain(STIFF), M, np.ones(3))
    row = _row(ds, "A: fixed")
    _agrees(row, periods, gamma)
    w = 2.0 * np.pi / periods
    a0, a1 = 2 * 0.04 * w[0] * w[1] / (w[0] + w[1]), 2 * 0.04 / (w[0] + w[1])
    np.testing.assert_allclose(row.damping_ratio.values, a0 / (2 * w) + a1 * w / 2, rtol=1e-9)
    np.testing.assert_allclose(row.effective_mass.sum("mode").values, [sum(MASSES)], rtol=1e-12)
    np.testing.assert_allclose(row.cumulative_mass_ratio.values[-1], [1.0], rtol=1e-12)
    assert list(ds.analysis.values) == ["A: fixed"]  # no soil, no isolator, no links


def test_participation_of_a_uniform_two_storey_building():
    """m, k on each storey: w^2 = (3 -+ sqrt 5) k / (2 m), phi_1 = (1, phi) with phi the
    golden ratio: Gamma_1^2 = m (1 + phi)^2 / (1 + phi^2), 94.7 % of the mass."""
    m, k = 1000.0, 4.0e6
    ds = pframe.modes(_scene(buildings=[building("U", 2, m, {"material": "elastic",
                                                             "stiffness": k})]))
    row = _row(ds, "U: fixed")
    golden = (1 + math.sqrt(5)) / 2
    w = np.sqrt(np.array([(3 - math.sqrt(5)) / 2, (3 + math.sqrt(5)) / 2]) * k / m)
    np.testing.assert_allclose(row.period.values, 2 * np.pi / w, rtol=1e-12)
    first = m * (1 + golden) ** 2 / (1 + golden**2)
    np.testing.assert_allclose(row.effective_mass.values[:, 0], [first, 2 * m - first],
                               rtol=1e-12)
    assert row.effective_mass_ratio.values[0, 0] == pytest.approx(0.9472, abs=1e-4)


def test_a_building_on_soil():
    """Sway and rocking DOFs after the floors: a storey deforms by u_j - u_(j-1) - h theta,
    the first one standing on the sway; the ground's motion moves the floors and the sway,
    not the rocking. Fixed base: the foundation held, the building's own modes."""
    h, kh, kr, mf, jf = 3.0, 5.0e7, 4.0e9, 3.0e4, 2.0e5
    soil = {"sway_stiffness": kh, "sway_damping": 1.0e5, "rocking_stiffness": kr,
            "rocking_damping": 1.0e6, "foundation": {"mass": mf, "rotational_inertia": jf}}
    b = building("S", 3, MASSES, {"material": "elastic", "stiffness": STIFF}) | {
        "height": h, "soil": soil}
    ds = pframe.modes(_scene(buildings=[b]))
    n = 3
    K = np.zeros((n + 2, n + 2))
    sway, rock = n, n + 1
    for j, k in enumerate(STIFF):
        g = np.zeros(n + 2)
        g[j] += 1.0
        g[j - 1 if j else sway] -= 1.0
        g[rock] -= h
        K += k * np.outer(g, g)
    K[sway, sway] += kh
    K[rock, rock] += kr
    M = np.diag(MASSES + [mf, jf])
    iota = np.array([1.0, 1.0, 1.0, 1.0, 0.0])
    periods, gamma = _reference(K, M, iota)
    row = _row(ds, "S: soil")
    _agrees(row, periods, gamma)
    assert row.total_mass.values[0] == pytest.approx(sum(MASSES) + mf, rel=1e-12)
    np.testing.assert_allclose(row.effective_mass.sum("mode").values, row.total_mass.values,
                               rtol=1e-10)
    fixed = _reference(_chain(STIFF), np.diag(MASSES), np.ones(3))
    _agrees(_row(ds, "S: fixed"), *fixed)
    assert row.period.values[0] > fixed[0][0]  # the soil lengthens the first period
    # the soil's dashpots damp the flexible-base modes beyond the storeys' Rayleigh damping
    assert np.all(row.damping_ratio_with_dashpots.values > row.damping_ratio.values)


def _isolated(bearing: dict) -> dict:
    nodes = [{"name": "I/1", "mass": 4.0e4}] + [{"name": f"I/{i + 2}", "mass": m}
                                                for i, m in enumerate(MASSES)]
    stories = [bearing] + [{"nodes": [f"I/{i + 1}", f"I/{i + 2}"], "material": "elastic",
                            "stiffness": k} for i, k in enumerate(STIFF)]
    return _scene(nodes=nodes, stories=stories)


@pytest.mark.parametrize("kind", ["bilinear", "friction_pendulum"])
def test_an_isolated_building(kind):
    """The isolated modes take the bearing at alpha k0 (bilinear) or W / R (a pendulum,
    W the weight above it); the fixed-base modes at its initial stiffness."""
    masses = [4.0e4] + MASSES
    if kind == "bilinear":
        k0, alpha = 4.0e7, 0.05
        bearing = {"name": "bearing", "nodes": ["ground", "I/1"], "material": "bilinear",
                   "stiffness": k0, "yield_drift": 0.01, "alpha": alpha, "isolator": True}
        k_iso, rule = alpha * k0, "alpha k"
    else:
        radius, k0 = 2.5, 1.0e9
        bearing = {"name": "bearing", "nodes": ["ground", "I/1"],
                   "material": "friction_pendulum", "radius": radius, "mu": 0.05,
                   "k_init": k0}
        k_iso, rule = GRAVITY * sum(masses) / radius, "W / R"
    ds = pframe.modes(_isolated(bearing))
    M = np.diag(masses)
    _agrees(_row(ds, "I: isolated"), *_reference(_chain([k_iso] + STIFF), M, np.ones(4)))
    _agrees(_row(ds, "I: fixed"), *_reference(_chain([k0] + STIFF), M, np.ones(4)))
    said = str(_row(ds, "I: isolated").stiffness.values)
    assert f"bearing ({kind}) at {k_iso:.4g} N/m = {rule}" in said
    if kind == "friction_pendulum":  # a rigid block on a pendulum: 2 pi sqrt(R / g)
        assert _row(ds, "I: isolated").period.values[0] == pytest.approx(
            2 * math.pi * math.sqrt(radius / GRAVITY), rel=0.02)


def _plan_building(centre, lines, mass=2.0e5, size=(12.0, 8.0), floors=1):
    return {"name": "P", "floors": floors, "mass": mass, "height": 3.0,
            "plan": {"size": list(size)}, "centre_of_mass": list(centre), "lines": lines}


def _line(name, position, direction, k):
    return {"name": name, "position": list(position), "direction": direction,
            "material": "elastic", "stiffness": k}


def test_a_symmetric_one_storey_building_in_plan():
    """Translations 2 pi sqrt(m / k) along x and y, torsion 2 pi sqrt(J / k_theta) with
    J = m (L_x^2 + L_y^2) / 12 and k_theta = sum k d^2 about the centre of mass; each mode
    wholly in its direction, its whole mass effective along it."""
    m, (lx, ly), kx, ky = 2.0e5, (12.0, 8.0), 3.0e7, 2.0e7
    lines = [_line("S", (0, 0), "x", kx), _line("N", (0, ly), "x", kx),
             _line("W", (0, 0), "y", ky), _line("E", (lx, 0), "y", ky)]
    ds = pframe.modes(_scene(buildings=[_plan_building((lx / 2, ly / 2), lines, m,
                                                       (lx, ly))]))
    row = _row(ds, "P: fixed")
    J = m * (lx**2 + ly**2) / 12
    k_theta = 2 * kx * (ly / 2) ** 2 + 2 * ky * (lx / 2) ** 2
    expected = {"x": 2 * np.pi * math.sqrt(m / (2 * kx)), "y": 2 * np.pi * math.sqrt(
        m / (2 * ky)), "torsion": 2 * np.pi * math.sqrt(J / k_theta)}
    got = dict(zip(row.mode_direction.values, row.period.values))
    assert got == pytest.approx(expected, rel=1e-12)
    for mode, direction in enumerate(row.mode_direction.values):
        share = row.share.sel(component=str(direction)).values[mode]
        assert share == pytest.approx(1.0, abs=1e-12)
    np.testing.assert_allclose(row.effective_mass.sum("mode").values, [m, m], rtol=1e-12)


def test_an_eccentric_building_in_plan_couples_translation_and_torsion():
    """Two storeys, the centre of mass 1.5 m east of the plan's centre: K = sum k g g^T with
    g = (n_x, n_y, (P - c) x n) of each line and storey, M = diag(m, m, J) per floor; the
    y modes twist (a torsion share well above 0) and the x modes do not."""
    m, (lx, ly), ex = 2.0e5, (12.0, 8.0), 1.5
    lines = [_line("S", (0, 0), "x", 3.0e7), _line("N", (0, ly), "x", 3.0e7),
             _line("W", (0, 0), "y", 4.0e7), _line("E", (lx, 0), "y", 1.0e7)]
    centre = (lx / 2 + ex, ly / 2)
    ds = pframe.modes(_scene(buildings=[_plan_building(centre, lines, m, (lx, ly), 2)]))
    J = m * (lx**2 + ly**2) / 12
    K = np.zeros((6, 6))
    for line in lines:
        n = np.array([1.0, 0.0]) if line["direction"] == "x" else np.array([0.0, 1.0])
        r = np.array(line["position"]) - np.array(centre)
        a = np.array([n[0], n[1], r[0] * n[1] - r[1] * n[0]])
        for storey in range(2):
            g = np.zeros(6)
            g[3 * storey:3 * storey + 3] += a
            if storey:
                g[:3] -= a
            K += line["stiffness"] * np.outer(g, g)
    M = np.diag([m, m, J] * 2)
    iota_y = np.array([0.0, 1.0, 0.0] * 2)
    periods, gamma_y = _reference(K, M, iota_y)
    row = _row(ds, "P: fixed")
    np.testing.assert_allclose(row.period.values, periods, rtol=1e-9)
    np.testing.assert_allclose(np.abs(row.participation_factor.sel(direction="y").values),
                               np.abs(gamma_y), rtol=1e-7, atol=1e-6)
    first_y = int(np.flatnonzero(row.mode_direction.values == "y")[0])
    first_x = int(np.flatnonzero(row.mode_direction.values == "x")[0])
    assert row.share.sel(component="torsion").values[first_y] > 0.05
    assert row.share.sel(component="torsion").values[first_x] < 1e-12
    np.testing.assert_allclose(row.effective_mass.sum("mode").values, [2 * m, 2 * m],
                               rtol=1e-12)


def test_buildings_coupled_by_links():
    """A link's spring couples two buildings (the scene's analysis: its stiffness between
    their roofs); a dashpot adds none and enters the ratio with dashpots only."""
    k_link, c_link = 5.0e6, 2.0e5
    a = building("A", 2, 1.0e4, {"material": "elastic", "stiffness": 2.0e7})
    b = building("B", 2, 1.5e4, {"material": "elastic", "stiffness": 4.0e7})
    links = [{"name": "spring", "nodes": ["A/2", "B/2"], "material": "elastic",
              "stiffness": k_link},
             {"name": "damper", "nodes": ["A/1", "B/1"], "material": "viscous",
              "damping": c_link}]
    ds = pframe.modes(_scene(buildings=[a, b], links=links))
    K = scipy.linalg.block_diag(_chain([2.0e7] * 2), _chain([4.0e7] * 2))
    g = np.array([0, 1.0, 0, -1.0])
    K += k_link * np.outer(g, g)
    M = np.diag([1.0e4] * 2 + [1.5e4] * 2)
    periods, gamma = _reference(K, M, np.ones(4))
    row = _row(ds, "scene: fixed")
    _agrees(row, periods, gamma)
    assert "links spring, damper" in str(row.stiffness.values)
    assert np.all(row.damping_ratio_with_dashpots.values >= row.damping_ratio.values)
    # each building alone: the links left out
    _agrees(_row(ds, "A: fixed"), *_reference(_chain([2.0e7] * 2), np.diag([1.0e4] * 2),
                                              np.ones(2)))


def test_validate_and_modes_give_the_same_periods(capsys):
    """The fixed-base and isolated periods validate prints are the modes' (two ways of
    taking the same matrices)."""
    from pframe.api import loaded_scene
    from pframe.assemble import modes

    loaded = loaded_scene(_isolated({"name": "bearing", "nodes": ["ground", "I/1"],
                                     "material": "bilinear", "stiffness": 4.0e7,
                                     "yield_drift": 0.01, "alpha": 0.05,
                                     "isolator": True}))
    ds = pframe.modes(loaded)
    ex = loaded.expanded
    k0, k_post = modes.storey_stiffness(ex)
    iso = modes.isolation(ex, k0, k_post).isolator
    for label, k in (("I: fixed", k0), ("I: isolated", modes.isolated_stiffness(k0, k_post,
                                                                               iso))):
        omega = modes.lowest_modes(ex, 0, k)
        np.testing.assert_allclose(ds.period.sel(analysis=label).values, 2 * np.pi / omega,
                                   rtol=1e-9)


def test_validate_prints_the_modes_periods_with_p_delta(tmp_path, capsys):
    """With P-delta on, the periods validate prints are pframe modes' (k - P / h) and it says
    so; its damping line says the Rayleigh fit is on the periods without P-delta."""
    import yaml

    story = {"material": "elastic", "stiffness": [k / 10 for k in STIFF]}  # P / h is 5 % of k
    b = building("A", 3, MASSES, story) | {"height": 3.0, "p_delta": True}
    path = tmp_path / "scene.yaml"
    path.write_text(yaml.safe_dump(_scene(buildings=[b])))
    assert main(["validate", str(path)]) == 0
    out = capsys.readouterr().out
    with_p_delta = pframe.modes(str(path)).period.sel(analysis="A: fixed").values
    without = _reference(_chain(story["stiffness"]), np.diag(MASSES), np.ones(3))[0]

    def shown(periods):
        return ", ".join(f"{t:#.3g}" for t in periods)

    assert shown(with_p_delta) != shown(without)
    assert (f"periods {shown(with_p_delta)} s (fixed base, initial stiffness less P-delta's "
            "P / h)") in out, out
    damping = next(line for line in out.splitlines() if "damping of A" in line)
    assert f"1 ({without[0]:#.3g} s)" in damping and "without P-delta's P / h" in damping


def test_the_cli_prints_the_tables_and_refuses_bad_input(tmp_path, capsys):
    path = tmp_path / "scene.yaml"
    path.write_text("buildings:\n  - {name: A, floors: 2, mass: 1000.0, story: {material: "
                    "elastic, stiffness: 4.0e6}}\nanalysis: {dt: 0.01, duration: 0.1}\n")
    assert main(["modes", str(path)]) == 0
    out = capsys.readouterr().out
    assert "building A, fixed base" in out and "94.7" in out
    assert main(["modes", str(path), "--count", "0"]) == 2
    assert "--count=0: give at least 1" in capsys.readouterr().err
    assert main(["modes", str(tmp_path / "missing.yaml")]) == 2
    assert "no such" in capsys.readouterr().err
    path.write_text("buildings:\n  - {name: A, floors: 2, mass: -1.0}\nanalysis: {dt: 0.01, "
                    "duration: 0.1}\n")
    assert main(["modes", str(path)]) == 2
    err = capsys.readouterr().err
    assert "line 2" in err and "Traceback" not in err
    with pytest.raises(pframe.InputError):
        pframe.modes(str(tmp_path / "missing.yaml"))
    with pytest.raises(pframe.InputError, match="count"):
        pframe.modes(str(path), count=0)


def test_modal_damping_gives_each_mode_its_ratio():
    ratios = [0.02, 0.03, 0.05]
    story = {"material": "elastic", "stiffness": STIFF}
    ds = pframe.modes(_scene(buildings=[building("A", 3, MASSES, story)],
                             damping={"kind": "modal", "ratio": ratios}))
    np.testing.assert_allclose(ds.damping_ratio.sel(analysis="A: fixed").values, ratios,
                               rtol=1e-9)


def test_a_scene_on_supports_has_the_modes_of_one_ground():
    """Two buildings on two supports under a wave passage: each building's modes are those
    of its storeys on a fixed base (the supports do not enter the modes)."""
    sine = {"kind": "sine", "amplitude": 1.0, "frequency": 6.0}
    scene = _scene(
        supports=[{"name": "west", "position": [0, 0]}, {"name": "east", "position": [60, 0]}],
        buildings=[building("A", 3, MASSES, {"material": "elastic", "stiffness": STIFF})
                   | {"support": "west"},
                   building("B", 2, 1.0e4, {"material": "elastic", "stiffness": 3.0e7})
                   | {"support": "east"}],
        excitation={"kind": "wave_passage", "velocity": 300.0, "direction": 0,
                    "motion": sine})
    ds = pframe.modes(scene)
    _agrees(_row(ds, "A: fixed"), *_reference(_chain(STIFF), np.diag(MASSES), np.ones(3)))
    _agrees(_row(ds, "B: fixed"), *_reference(_chain([3.0e7] * 2), np.diag([1.0e4] * 2),
                                              np.ones(2)))


def test_p_delta_softens_the_storeys():
    """With P-delta each storey takes k - P / h, P the weight of the floors above it (the
    kernel's storey force is net of P drift / h)."""
    h = 3.0
    b = building("A", 3, MASSES, {"material": "elastic", "stiffness": STIFF}) | {
        "height": h, "p_delta": True}
    ds = pframe.modes(_scene(buildings=[b]))
    weights = GRAVITY * np.cumsum(MASSES[::-1])[::-1]
    softened = [k - p / h for k, p in zip(STIFF, weights)]
    _agrees(_row(ds, "A: fixed"), *_reference(_chain(softened), np.diag(MASSES), np.ones(3)))
    assert "less P-delta's P / h" in str(_row(ds, "A: fixed").stiffness.values)
