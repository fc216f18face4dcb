"""Code separation rules beside ABS/SRSS/DDC (pframe.gap.rules, docs/gap-audit.md#code-rules),
each against a worked example derived by hand from the clause text."""

from __future__ import annotations

import math
from pathlib import Path

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


# --- the table of code rules (pframe.gap.codes): each clause against a worked example -------

def test_tbdy2018_4_9_3_printed_example():
    """TBDY 2018 4.9.3.1-4.9.3.2, the printed example: u = 18 mm and 24 mm, R = 8, I = 1,
    H = 12 m. sqrt(18^2 + 24^2) = 30 mm; every floor aligned alpha = 0.25 x 8 = 2: 60 mm;
    otherwise alpha = 0.5 x 8 = 4: 120 mm; the geometric minimum 30 + 2 x 10 = 50 mm (two
    steps of 3 m above 6 m) is smaller. With u = 5 mm and 5 mm the minimum governs: 50 mm."""
    from pframe.gap.codes import separation

    kw = {"level": 12.0, "factors": {"R": 8, "I": 1}}
    assert separation("TBDY2018", 0.018, 0.024, aligned=True, **kw) == pytest.approx(0.060)
    assert separation("TBDY2018", 0.018, 0.024, aligned=False, **kw) == pytest.approx(0.120)
    assert separation("TBDY2018", 0.005, 0.005, aligned=True, **kw) == pytest.approx(0.050)
    # from the simulated elastic peaks: u_i(X) = u I / R, so alpha R/I cancels the R/I
    from pframe.gap.codes import separation_from_peaks
    assert separation_from_peaks("TBDY2018", 0.144, 0.192, aligned=True, **kw) == \
        pytest.approx(0.060)


@pytest.mark.parametrize("convention, expected", [("started", 0.060), ("completed", 0.050),
                                                  ("linear", 0.030 + 0.010 * 7.0 / 3.0)])
def test_tbdy2018_minimum_step_conventions(convention, expected):
    """4.9.3.2 at 13 m (7 m above 6 m, 2 1/3 steps of 3 m): every step begun counts 30 + 30 =
    60 mm; completed steps 30 + 20 = 50 mm; linear 30 + 23.3 = 53.3 mm."""
    from pframe.gap.codes import separation

    assert separation("TBDY2018", 0.0, 0.0, level=13.0, factors={"steps": convention}) == \
        pytest.approx(expected)


def test_nbc_4_1_8_14_worked_example():
    """NBC 4.1.8.14 (1) with 4.1.8.13 (2): linear-analysis deflections 10 mm and 20 mm,
    R_d = 3, R_o = 1.5, I_E = 1.3: realistic deflections 10 x 4.5 / 1.3 = 34.615 mm and
    69.231 mm; separation sqrt(34.615^2 + 69.231^2) = 77.40 mm, floors aligned or not."""
    from pframe.gap.codes import separation

    f = {"Rd": 3.0, "Ro": 1.5, "IE": 1.3}
    expected = 4.5 / 1.3 * math.hypot(0.010, 0.020)
    assert expected == pytest.approx(0.07740, abs=1e-5)
    for aligned in (True, False):
        assert separation("NBCC", 0.010, 0.020, aligned=aligned, factors=f) == \
            pytest.approx(expected, rel=1e-12)


def test_ntc_ds_1_10_worked_example():
    """NTC-DS 1.10, zone II (0.003), a level 10 m above the ground: computed displacements
    30 mm and 20 mm give 30 + 30 = 60 mm and 20 + 30 = 50 mm from each boundary, 110 mm
    between the two; one half, 55 mm, only with the same height, the same structure and
    aligned slabs. Zone I, 5 mm each: 5 + 10 = 15 mm < 50 mm, so 50 + 50 = 100 mm."""
    from pframe.gap.codes import separation

    kw = {"level": 10.0, "heights": (10.0, 10.0), "factors": {"zone": "II"}}
    assert separation("NTC_DS", 0.030, 0.020, **kw) == pytest.approx(0.110)
    assert separation("NTC_DS", 0.030, 0.020, aligned=True, **kw) == pytest.approx(0.110)
    same = {**kw, "factors": {"zone": "II", "same_structure": 1}}
    assert separation("NTC_DS", 0.030, 0.020, aligned=True, **same) == pytest.approx(0.055)
    taller = {**same, "heights": (10.0, 13.0)}
    assert separation("NTC_DS", 0.030, 0.020, aligned=True, **taller) == pytest.approx(0.110)
    assert separation("NTC_DS", 0.005, 0.005, level=10.0, factors={"zone": "I"}) == \
        pytest.approx(0.100)


def test_gb50011_6_1_4_published_example():
    """A published exam question on GB 50011-2010 6.1.4 (tihaiku.com/jzgc/1079987.html): a
    21 m frame podium beside a 120 m frame-shear wall tower at intensity 8; item 3) takes
    the system needing the wider joint (frame) and the lower height (21 m): 100 + 20 x
    (21 - 15) / 3 = 140 mm, the answer given (C). Frame-shear wall buildings of 21 m:
    0.7 x 140 = 98 mm, raised to 100 mm."""
    from pframe.gap.codes import separation

    f = {"intensity": 8}
    assert separation("GB50011", 0.0, 0.0, heights=(21.0, 120.0), factors=f,
                      factors_b={"system": "frame-wall"}) == pytest.approx(0.140)
    assert separation("GB50011", 0.0, 0.0, heights=(21.0, 21.0),
                      factors={"intensity": 8, "system": "frame-wall"}) == pytest.approx(0.100)


@pytest.mark.parametrize("convention, expected", [("started", 0.140), ("completed", 0.120),
                                                  ("linear", 0.100 + 0.020 * 5.0 / 3.0)])
def test_gb50011_step_conventions(convention, expected):
    """A 20 m frame at intensity 8 is 5 m above 15 m, 1 2/3 steps of 3 m: 140, 120 or
    133.3 mm by the step convention (pframe's default counts every step begun: 140 mm)."""
    from pframe.gap.codes import separation

    assert separation("GB50011", 0.0, 0.0, heights=(20.0, 25.0),
                      factors={"intensity": 8, "steps": convention}) == pytest.approx(expected)


def test_en1998_worked_example():
    """EN 1998-1 (pframe's rule): d_e = 10 mm and 20 mm, q = q_d = 3: d_s = 30 and 60 mm,
    SRSS sqrt(30^2 + 60^2) = 67.08 mm; 0.7 x 67.08 = 46.96 mm where the floors align."""
    from pframe.gap.codes import separation

    f = {"q": 3.0, "qd": 3.0}
    assert separation("EN1998", 0.010, 0.020, factors=f) == pytest.approx(math.sqrt(0.0045))
    assert separation("EN1998", 0.010, 0.020, aligned=True, factors=f) == \
        pytest.approx(0.7 * math.sqrt(0.0045))


def test_asce7_has_no_aligned_floor_rule_and_is1893_halves():
    """ASCE 7 12.12.2 writes no reduction for aligned floors; IS 1893 7.11.3 replaces R by
    R / 2 (the earlier example: 160 mm, 80 mm where the floors align)."""
    from pframe.gap.codes import separation

    for aligned in (True, False):
        assert separation("ASCE7_same_property", 0.050, 0.030, aligned=aligned,
                          factors_b={"Cd": 4.0, "Ie": 1.25}) == pytest.approx(0.29127, abs=1e-5)
    assert separation("IS1893", 0.020, 0.012, aligned=True) == pytest.approx(0.080)
    assert separation("IS1893", 0.020, 0.012, aligned=False) == pytest.approx(0.160)


def test_rules_take_arrays_of_displacements():
    """Per-building displacements as arrays (records x levels x critical locations): the
    rule is the formula elementwise."""
    from pframe.gap.codes import separation

    rng = np.random.default_rng(3)
    a, b = rng.uniform(0, 0.05, (4, 3, 2)), rng.uniform(0, 0.05, (4, 3, 2))
    out = separation("TBDY2018", a, b, aligned=True, level=3.0)
    assert out.shape == (4, 3, 2)
    assert np.allclose(out, np.maximum(2.0 * np.hypot(a, b), 0.030))


def test_bad_factors_are_refused():
    from pframe.errors import InputError
    from pframe.gap.codes import separation

    with pytest.raises(InputError, match="zone"):
        separation("NTC_DS", 0.01, 0.01, factors={"zone": "IV"})
    with pytest.raises(InputError, match="intensity"):
        separation("GB50011", 0, 0, factors={"intensity": 10})
    with pytest.raises(InputError, match="not one of"):
        separation("TBDY2018", 0.01, 0.01, factors={"Cd": 5})
    with pytest.raises(InputError, match="knows"):
        separation("NZS1170", 0.01, 0.01)


# --- aligned floors from the storey heights ---------------------------------------------------

def test_aligned_floors_from_levels():
    """Floors align when, up to the lower roof, each floor of one building has one of the
    other within the tolerance; the taller building's floors above the lower roof cannot
    meet and do not count; unknown levels give None."""
    from pframe.gap.floors import aligned

    a = {"A/1": 3.0, "A/2": 6.0, "A/3": 9.0, "A/4": 12.0}
    assert aligned(a, {"B/1": 3.0, "B/2": 6.0, "B/3": 9.0}) is True
    assert aligned(a, {"B/1": 3.04, "B/2": 6.03, "B/3": 8.97}) is True
    assert aligned(a, {"B/1": 3.1, "B/2": 6.0, "B/3": 9.0}) is False
    assert aligned(a, {"B/1": 3.1, "B/2": 6.0, "B/3": 9.0}, tolerance=0.15) is True
    assert aligned(a, {"B/1": 4.5, "B/2": 9.0}) is False  # B's floor at 4.5 m meets a column
    assert aligned(a, {"B/1": 3.0, "B/2": 6.0, "B/3": 9.0, "B/4": 10.5}) is False
    assert aligned(a, None) is None


def _two(heights_a, heights_b, contacts=(("c2", "A/2", "B/2"),)):
    from conftest import scene_text

    def b(name, heights):
        out = {"name": name, "floors": 3 if heights is None else len(heights), "mass": 1.0e4,
               "story": {"material": "elastic", "stiffness": 4.0e7}}
        if heights is not None:
            out["height"] = list(heights)
        return out

    return scene_text(
        buildings=[b("A", heights_a), b("B", heights_b)],
        contacts=[{"name": n, "nodes": [x, y], "gap": 0.05, "law": "hertz",
                   "stiffness": 1e9} for n, x, y in contacts],
        damping={"ratio": 0.05, "modes": [1, 1]},
        excitation={"kind": "ricker", "amplitude": 2.0, "period": 0.4},
        analysis={"dt": 0.005, "duration": 2.0})


@pytest.mark.parametrize("heights_b, expected", [([3.0, 3.0, 3.0], 1.0),
                                                  ([3.0, 3.5, 3.0], 0.0),
                                                  (None, math.nan)])
def test_contact_geometry_from_the_scene(tmp_path, heights_b, expected):
    """A 4-storey building of 3 m storeys beside a 3-storey one: 3 m storeys align (the
    fourth floor of A, above B's roof, cannot meet); a 3.5 m second storey puts B's floors
    2 and 3 at 6.5 and 9.5 m, not aligned; no heights: unknown."""
    from pframe.gap.floors import contact_geometry
    from pframe.reader import load_scene

    path = tmp_path / "s.yaml"
    path.write_text(_two([3.0] * 4, heights_b))
    ex = load_scene(path).expanded
    g = contact_geometry(ex, ("A/2",), ("B/2",))
    assert np.array_equal(g.aligned, [expected], equal_nan=True)
    assert g.level_left[0] == pytest.approx(6.0)
    assert g.height_left[0] == pytest.approx(12.0)
    forced = contact_geometry(ex, ("A/2",), ("B/2",), override=True)
    assert forced.aligned[0] == 1.0 and "given" in forced.decided


# --- the selection: --codes text, YAML, rules of your own ---------------------------------------

def test_codes_text_with_factors_and_buildings():
    from pframe.gap.selection import selection

    found = selection("asce7:R=6,tbdy2018:R=4:I=1.5:R.B=3,gb50011:intensity=7:system=wall")
    assert found.names == ["ASCE7_same_property", "ASCE7_property_line", "TBDY2018", "GB50011"]
    tbdy = found.chosen[2]
    assert tbdy.factors_of("A") == {"R": 4.0, "I": 1.5}
    assert tbdy.factors_of("B") == {"R": 3.0, "I": 1.5}
    assert selection("all").names[-1] == "GB50011"


def test_codes_text_refused_with_the_reason():
    from pframe.errors import InputError
    from pframe.gap.selection import selection

    with pytest.raises(InputError, match="key=value"):
        selection("tbdy2018:R6")
    with pytest.raises(InputError, match="twice"):
        selection("asce7,asce7")
    with pytest.raises(InputError, match="must be a number"):
        selection("asce7:R=-1")


def test_a_rule_of_your_own_in_the_audit_file(tmp_path):
    """A rule the user writes (here as NZS 1170.5 would be applied, its factors taken from the
    clause by the engineer): amplification 1.5 on A and 2 on B, SRSS, at least 30 mm, x 0.5
    where the floors align (they do: equal 3 m storeys); its text is written to the file."""
    import pframe.gap

    (tmp_path / "s.yaml").write_text(_two([3.0] * 3, [3.0] * 3))
    text = "NZS 1170.5 7.4.2 as read by the engineer: SRSS of the amplified displacements"
    (tmp_path / "rules.yaml").write_text(
        "codes:\n  rules:\n    - tbdy2018\n    - {name: NZS_own, clause: '7.4.2', text: '"
        + text + "', combination: srss, amplification: {A: 1.5, B: 2.0}, minimum: 0.03,"
        " aligned_factor: 0.5}\n")
    ds = pframe.gap.audit(tmp_path / "s.yaml", codes=tmp_path / "rules.yaml")
    ul = ds.peak_displacement_left.isel(level=0, contact=0).values
    ur = ds.peak_displacement_right.isel(level=0, contact=0).values
    own = ds.gap_required.sel(rule_name="NZS_own").isel(level=0, contact=0).values
    assert np.allclose(own, np.maximum(0.5 * np.hypot(1.5 * ul, 2.0 * ur), 0.03))
    tbdy = ds.gap_required.sel(rule_name="TBDY2018").isel(level=0, contact=0).values
    assert np.allclose(tbdy, np.maximum(0.25 * np.hypot(ul, ur), 0.030))  # aligned, 6 m
    assert text in ds.attrs["code_rules"]
    assert float(ds.floors_aligned[0]) == 1.0


def test_a_rule_of_your_own_needs_its_text():
    from pframe.errors import InputError
    from pframe.gap.selection import selection

    with pytest.raises(InputError, match="text"):
        selection([{"name": "mine", "combination": "srss"}])
    with pytest.raises(InputError, match="combination"):
        selection([{"name": "mine", "text": "x", "combination": "max"}])
    with pytest.raises(InputError, match="built-in"):
        selection([{"name": "SRSS", "text": "x", "combination": "srss"}])


# --- every rule of the table is documented ------------------------------------------------------

def test_docs_and_help_list_every_rule_with_its_clause():
    """docs/gap-audit.md holds the table derived from pframe.gap.codes.CODES, and pframe gap
    --help names every code with its clause."""
    from pathlib import Path

    from pframe.gap.codes import CODES, docs_table

    docs = (Path(__file__).parents[1] / "docs" / "gap-audit.md").read_text()
    start, end = "<!-- BEGIN code-rules -->\n", "\n<!-- END code-rules -->"
    assert start in docs and end in docs
    assert docs.split(start)[1].split(end)[0] == docs_table()
    from pframe.cli import parser

    out = parser("gap")._subparsers._group_actions[0].choices["gap"].format_help()
    flat = " ".join(out.split())
    for name, rules in CODES.items():
        assert f"{name} ({rules[0].code} {rules[0].clause}" in flat


# --- where the rules appear: the command line and pframe risk -----------------------------------

@pytest.mark.slow
def test_pframe_gap_codes_from_a_rules_file_and_bad_ones_exit_2(tmp_path, capsys):
    """--codes takes a rules file; a bad one exits 2 naming the file and the rule, writing
    nothing; --aligned replaces the decision from the heights (file variable 1)."""
    import xarray as xr

    from pframe.cli import main

    (tmp_path / "s.yaml").write_text(_two([3.0, 3.5, 3.0], [3.0] * 3))
    rules = tmp_path / "rules.yaml"
    rules.write_text("codes:\n  rules: [is1893, {code: tbdy2018, R: 4}]\n")
    out = tmp_path / "a.nc"
    assert main(["gap", str(tmp_path / "s.yaml"), "--codes", str(rules), "-o", str(out),
                 "-q"]) == 0
    with xr.open_dataset(out) as ds:
        assert list(ds.rule_name.values) == ["ABS", "SRSS", "DDC", "IS1893", "TBDY2018",
                                             "simulated"]
        assert float(ds.floors_aligned[0]) == 0.0  # A's 3.5 m storey: 6.5 m against 6 m
        g = ds.gap_required.isel(level=0, contact=0)
        assert np.allclose(g.sel(rule_name="IS1893"), g.sel(rule_name="ABS"))  # I u, not / 2
    forced = tmp_path / "b.nc"
    assert main(["gap", str(tmp_path / "s.yaml"), "--codes", str(rules), "--aligned", "yes",
                 "-o", str(forced), "-q"]) == 0
    with xr.open_dataset(forced) as ds:
        g = ds.gap_required.isel(level=0, contact=0)
        assert float(ds.floors_aligned[0]) == 1.0
        assert np.allclose(g.sel(rule_name="IS1893"), 0.5 * g.sel(rule_name="ABS"))
    rules.write_text("codes:\n  rules: [{name: mine, combination: srss}]\n")
    bad = tmp_path / "c.nc"
    assert main(["gap", str(tmp_path / "s.yaml"), "--codes", str(rules), "-o", str(bad)]) == 2
    err = capsys.readouterr().err
    assert str(rules) in err and "text" in err and "Traceback" not in err
    assert not bad.exists()


@pytest.mark.slow
def test_pframe_risk_shows_the_study_codes_beside_the_gap_at_target(tmp_path):
    """A study's codes: NBC on the simulated peaks is the SRSS of the peaks (R_d R_o / I_E
    cancels), so at the target's intensity it equals the SRSS rule; the file describes it."""
    import xarray as xr
    import yaml

    from pframe.cli import main

    repo = Path(__file__).resolve().parents[1]
    study = {"scene": str(repo / "models" / "wu2021-pulse.yaml"), "measure": "pga",
             "design": {"kind": "msa", "levels": [0.2, 0.4, 0.6, 0.8, 1.0]},
             "hazard": {"power_law": {"k0": 1e-4, "k": 2.5}}, "target": {"return_period": 475},
             "bootstrap": 0, "pounding_runs": False, "codes": ["nbcc"]}
    path = tmp_path / "study.yaml"
    path.write_text(yaml.safe_dump(study))
    out = tmp_path / "r.nc"
    assert main(["risk", str(path), "-o", str(out), "-q", "--threads", "2"]) == 0
    with xr.open_dataset(out) as ds:
        at = dict(zip(ds.rule_name.values, ds.rule_separation_at_target.values))
        assert at["NBCC"] == pytest.approx(at["SRSS"], rel=1e-12)
        assert "NBC of Canada 4.1.8.14" in ds.attrs["code_rules"]


def test_a_study_with_a_bad_code_exits_2_naming_the_place(tmp_path, capsys):
    import yaml

    from pframe.cli import main

    repo = Path(__file__).resolve().parents[1]
    path = tmp_path / "study.yaml"
    path.write_text(yaml.safe_dump({"scene": str(repo / "models" / "wu2021-pulse.yaml"),
                                    "design": {"kind": "msa", "levels": [0.2, 0.4]},
                                    "codes": [{"code": "tbdy2018", "Q": 3}]}))
    assert main(["risk", str(path), "-o", str(tmp_path / "r.nc"), "-q"]) == 2
    err = capsys.readouterr().err
    assert str(path) in err and "at codes" in err and "Q" in err
