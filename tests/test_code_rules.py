"""Code separation rules beside ABS/SRSS/DDC (pframe.gap.rules, docs/gap-audit.md#code-rules),
each against a worked example derived by hand from the clause text."""

from __future__ import annotations

import math

import numpy as np
import pytest

from pframe.gap.rules import (
    asce7_separation,
    code_separations,
    design_displacement,
    is1893_separation,
)


def test_asce7_22_12_12_2_worked_example():
    """ASCE 7-22 12.12.2: delta_M = C_d delta_max / I_e (12.12-1); same property delta_MT =
    sqrt(delta_M1^2 + delta_M2^2) (12.12-2); at a property line each is set back delta_M.

    Building 1: special RC moment frame, C_d = 5.5, I_e = 1.0, delta_max = 50 mm:
    delta_M1 = 5.5 x 50 / 1.0 = 275 mm. Building 2: C_d = 4.0, I_e = 1.25, delta_max = 30 mm:
    delta_M2 = 4.0 x 30 / 1.25 = 96 mm. delta_MT = sqrt(275^2 + 96^2) = sqrt(75625 + 9216) =
    sqrt(84841) = 291.27 mm; across a property line 275 + 96 = 371 mm."""
    out = asce7_separation(0.050, 0.030, 5.5, 4.0, 1.0, 1.25)
    assert out["ASCE7_same_property"] == pytest.approx(math.sqrt(84841) / 1000, rel=1e-12)
    assert out["ASCE7_same_property"] == pytest.approx(0.29127, abs=1e-5)
    assert out["ASCE7_property_line"] == pytest.approx(0.371, rel=1e-12)


def test_is1893_2016_7_11_3_worked_example():
    """IS 1893 (Part 1):2016 7.11.3: R times the sum of the storey displacements under the
    design lateral force (7.11.1); R / 2 where the floor levels coincide.

    Two SMRF buildings (R = 5), design displacements 20 mm and 12 mm at the level:
    5 x (20 + 12) = 160 mm; at coincident floor levels 2.5 x 32 = 80 mm."""
    out = is1893_separation(0.020, 0.012, 5.0, 5.0)
    assert out["IS1893"] == pytest.approx(0.160, rel=1e-12)
    assert out["IS1893_same_levels"] == pytest.approx(0.080, rel=1e-12)


def test_design_displacements_from_the_simulated_elastic_peaks():
    """The design forces are the motion's elastic forces divided by R / I, so an elastic
    building's design displacement is u I / R: ASCE 7 gives (C_d / R) u per building, IS 1893
    I u. With the defaults (ASCE R 8, C_d 5.5, I_e 1; IS R 5, I 1) and u = 0.4 m, 0.2 m:
    ASCE same property (5.5 / 8) sqrt(0.4^2 + 0.2^2) = 0.6875 x 0.44721 = 0.30746 m,
    property line 0.6875 x 0.6 = 0.4125 m; IS 1893 0.4 + 0.2 = 0.6 m, at the same levels 0.3 m."""
    assert design_displacement(-0.4, 8.0, 1.0) == pytest.approx(0.05)
    out = code_separations(np.array([0.4]), np.array([0.2]), ["asce7", "is1893"])
    assert out["ASCE7_same_property"][0] == pytest.approx(0.6875 * math.sqrt(0.2), rel=1e-12)
    assert out["ASCE7_property_line"][0] == pytest.approx(0.4125, rel=1e-12)
    assert out["IS1893"][0] == pytest.approx(0.6, rel=1e-12)
    assert out["IS1893_same_levels"][0] == pytest.approx(0.3, rel=1e-12)
    other = code_separations(0.4, 0.2, ["asce7"], {"R": 4.0}, {"Cd": 4.0})
    # building a: (5.5 / 4) 0.4 = 0.55; b: (4 / 8) 0.2 = 0.1
    assert other["ASCE7_property_line"] == pytest.approx(0.65, rel=1e-12)


def test_gap_audit_adds_code_rules_under_a_stochastic_suite(tmp_path):
    """pframe.gap.audit with codes over a suite of stochastic motions (one per seed): the code
    rules are the rules' formulas on the runs' peak displacements, one motion per seed."""
    from conftest import building, scene_text

    import pframe.gap

    scene = scene_text(
        buildings=[building("A", 1, 1000.0, {"material": "elastic", "stiffness": 4e5}),
                   building("B", 1, 1000.0, {"material": "elastic", "stiffness": 9e5})],
        contacts=[{"name": "c", "nodes": ["A/1", "B/1"], "gap": 0.01, "law": "hertz",
                   "stiffness": 1e9}],
        damping={"ratio": 0.05, "modes": [1, 1]},
        analysis={"dt": 0.01, "duration": 5.0})
    (tmp_path / "s.yaml").write_text(scene)
    (tmp_path / "suite.yaml").write_text(
        "stochastic:\n  - {model: clough_penzien, intensity: 0.01, ground_frequency: 15,"
        " ground_damping: 0.6, envelope: {kind: jennings, rise: 1, plateau: 3, decay: 1},"
        " seeds: [1, 2]}\n")
    ds = pframe.gap.audit(tmp_path / "s.yaml", tmp_path / "suite.yaml",
                          codes={"asce7": {"R": 6.0}, "is1893": {}})
    assert list(ds.record_name.values) == ["clough_penzien-seed1", "clough_penzien-seed2"]
    g = ds.gap_required.isel(level=0, contact=0)
    ul = ds.peak_displacement_left.isel(level=0, contact=0).values
    ur = ds.peak_displacement_right.isel(level=0, contact=0).values
    assert ul[0] != ul[1]
    rules = list(ds.rule_name.values)
    assert np.allclose(g.isel(rule=rules.index("ASCE7_same_property")),
                       5.5 / 6.0 * np.hypot(ul, ur))
    assert np.allclose(g.isel(rule=rules.index("IS1893")), ul + ur)
    assert "asce7: R = 6" in ds.attrs["code_factors"]
