"""pframe.nondim: exact Buckingham Pi groups, the Pi groups of any scene, Pi-form scenes,
similitude (Table 1 of Wu et al. 2021) and the ``pframe pi / expand / scale`` commands.

No kernel runs here (see test_similarity.py for the responses).
"""

from __future__ import annotations

import json
import math
from dataclasses import replace
from fractions import Fraction
from pathlib import Path

import pytest
import yaml
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st
from pydantic import Field

from pframe.cli import main
from pframe.errors import InputError
from pframe.laws import Law
from pframe.laws.params import LawParams, Positive
from pframe.nondim import (
    QUANTITY,
    Dimension,
    DimensionalAnalysisError,
    Ratio,
    SimilitudeError,
    Variable,
    check_groups,
    null_space,
    parse_units,
    pi_groups,
    scale_scene,
    scene_pi,
    similitude,
)
from pframe.nondim.buckingham import dimension_matrix, rank
from pframe.reader import load_scene, parse_scene

REPO = Path(__file__).resolve().parents[1]
MODELS = REPO / "models"

#: Wu et al. (2021), eq. (14), in the paper-notes reading Pi_mu = K_b / K_a
EQ14 = {"Pi_m": 0.25, "Pi_k": 5.0, "Pi_mu": 10.0, "Pi_uya": 0.1, "Pi_uyb": 0.06,
        "Pi_xi": 0.05, "Pi_alpha": 0.1, "Pi_wcon": 65.0, "Pi_e": 0.4, "Pi_d": 0.5}
#: section 4.4 of the paper (the HUST test model)
HUST = {"Pi_m": 1.0, "Pi_k": 17.5, "Pi_mu": 1.0, "Pi_xi": 0.05, "Pi_wcon": 65.0,
        "Pi_e": 0.4, "Pi_d": 0.41}

M, L, T = QUANTITY["mass"], QUANTITY["length"], QUANTITY["time"]
ONE = QUANTITY["dimensionless"]


def _paper_variables() -> list[Variable]:
    """The 13 variables of eq. (10), in its order."""
    dims = {"m_a": M, "m_b": M, "K_a": QUANTITY["stiffness"], "mu": ONE, "u_ya": L,
            "u_yb": L, "xi": ONE, "alpha": ONE, "w_bar": T**-1, "e": ONE, "d": L,
            "a_p": QUANTITY["acceleration"], "w_p": T**-1}
    return [Variable(n, d) for n, d in dims.items()]


# ---------------------------------------------------------------------------------------------
# Buckingham
# ---------------------------------------------------------------------------------------------

def test_the_papers_13_variables_give_its_10_groups():
    """Eq. (10) -> eq. (11): 13 variables, 3 dimensions, repeating (m_b, a_p, w_p): the ten
    groups of eq. (11) with exact exponents."""
    variables = _paper_variables()
    assert rank(dimension_matrix(variables)) == 3
    groups = pi_groups(variables, ["m_b", "a_p", "w_p"])
    check_groups(variables, groups)
    formulas = {g.name: g.formula() for g in groups}
    assert formulas == {
        "Pi_m_a": "m_a / m_b", "Pi_K_a": "K_a / (m_b w_p^2)", "Pi_mu": "mu",
        "Pi_u_ya": "u_ya w_p^2 / a_p", "Pi_u_yb": "u_yb w_p^2 / a_p", "Pi_xi": "xi",
        "Pi_alpha": "alpha", "Pi_w_bar": "w_bar / w_p", "Pi_e": "e",
        "Pi_d": "d w_p^2 / a_p"}
    exponents = {g.name: g.powers for g in groups}
    assert exponents["Pi_K_a"] == {"K_a": 1, "m_b": -1, "w_p": -2}
    assert all(isinstance(x, Fraction) for g in groups for _, x in g.exponents)


def test_exponents_are_exact_fractions():
    """A Hertz stiffness (N/m^1.5) needs a_p^(1/2): exact, not 0.49999999."""
    k_h = Variable("k_h", parse_units("N/m^1.5"))
    rest = [Variable("m_b", M), Variable("a_p", QUANTITY["acceleration"]),
            Variable("w_p", T**-1)]
    (group,) = pi_groups([k_h, *rest], ["m_b", "a_p", "w_p"])
    assert group.powers == {"k_h": 1, "a_p": Fraction(1, 2), "m_b": -1, "w_p": -3}
    assert group.formula() == "k_h a_p^(1/2) / (m_b w_p^3)"
    assert group.dimension({v.name: v for v in [k_h, *rest]}).dimensionless


def test_dependent_repeating_variables_are_rejected():
    variables = _paper_variables()
    with pytest.raises(DimensionalAnalysisError) as info:
        pi_groups(variables, ["m_b", "K_a", "w_p"])
    message = str(info.value)
    assert "m_b, K_a, w_p are not independent" in message
    assert "m_b w_p^2 / K_a is dimensionless" in message
    with pytest.raises(DimensionalAnalysisError, match="cannot make .* dimensionless"):
        pi_groups(variables, ["m_b", "a_p"])
    with pytest.raises(DimensionalAnalysisError, match="unknown repeating variable"):
        pi_groups(variables, ["m_b", "a_p", "omega"])


def test_check_groups_rejects_incomplete_dependent_or_dimensional_sets():
    variables = _paper_variables()
    groups = pi_groups(variables, ["m_b", "a_p", "w_p"])
    with pytest.raises(DimensionalAnalysisError, match="a complete set has 10"):
        check_groups(variables, groups[:-1])
    with pytest.raises(DimensionalAnalysisError, match="not independent"):
        check_groups(variables, groups[:-1] + [groups[0]])
    bad = type(groups[0])("Pi_bad", (("m_a", Fraction(1)),))
    with pytest.raises(DimensionalAnalysisError, match="has dimension M"):
        check_groups(variables, groups[:-1] + [bad])


def test_null_space_is_exact():
    matrix = [[1, 2, 3], [2, 4, 7]]
    (vector,) = null_space(matrix)
    assert vector == [Fraction(-2), Fraction(1), Fraction(0)]
    assert all(sum(a * x for a, x in zip(row, vector)) == 0 for row in matrix)


def test_units_parse_to_dimensions():
    assert parse_units("N/m") == QUANTITY["stiffness"]
    assert parse_units("N/m^1.5") == QUANTITY["hertz_stiffness"]
    assert parse_units("kg m^-3") == QUANTITY["density"]
    assert parse_units("rad/s") == T**-1
    assert parse_units("m^(1/2)") == L ** Fraction(1, 2)
    assert str(QUANTITY["hertz_stiffness"]) == "M L^(-1/2) T^-2"
    with pytest.raises(ValueError, match="unknown unit"):
        parse_units("ft")


_EXPONENT = st.sampled_from([Fraction(x, 2) for x in range(-4, 5)])


@st.composite
def _variable_sets(draw):
    n = draw(st.integers(1, 9))
    dims = [Dimension(draw(_EXPONENT), draw(_EXPONENT), draw(_EXPONENT)) for _ in range(n)]
    return [Variable(f"q{i}", d) for i, d in enumerate(dims)]


@pytest.mark.slow
@given(_variable_sets())
@settings(max_examples=200, deadline=None)
def test_groups_of_random_dimension_matrices_are_dimensionless_and_complete(variables):
    """For any variables and any independent repeating set (taken greedily), the groups are
    dimensionless, independent and n - r in number; a dependent set is rejected."""
    repeating = []
    for v in variables:
        if rank(dimension_matrix([*repeating, v])) > len(repeating):
            repeating.append(v)
    names = [v.name for v in repeating]
    groups = pi_groups(variables, names)
    by_name = {v.name: v for v in variables}
    assert all(g.dimension(by_name).dimensionless for g in groups)
    assert len(groups) == len(variables) - rank(dimension_matrix(variables))
    check_groups(variables, groups)
    extra = next((v.name for v in variables if v.name not in names), None)
    if extra is not None and len(names) == 3:
        with pytest.raises(DimensionalAnalysisError, match="not independent"):
            pi_groups(variables, [*names, extra])


# ---------------------------------------------------------------------------------------------
# similitude
# ---------------------------------------------------------------------------------------------

def test_table_1_of_the_paper_exactly_and_its_density_ratio():
    """S_l = 1/16, S_E = 1, S_a = 1 give Table 1 exactly, and a density ratio of 16."""
    sim = similitude({"length": "1/16", "modulus": 1, "acceleration": 1})
    table1 = {"length": Fraction(1, 16), "modulus": 1, "stiffness": Fraction(1, 16),
              "acceleration": 1, "time": Fraction(1, 4), "velocity": Fraction(1, 4),
              "displacement": Fraction(1, 16), "mass": Fraction(1, 256)}
    for quantity, ratio in table1.items():
        assert sim.ratio(quantity).exact == ratio, quantity
    assert sim.ratio("density").exact == 16
    assert sim.ratio("force").exact == Fraction(1, 256)
    rows = {r["quantity"]: r for r in sim.rows()}
    assert [r["quantity"] for r in sim.rows()][:8] == list(table1)  # Table 1's order
    assert rows["time"]["status"] == "implied" and rows["length"]["status"] == "chosen"
    assert rows["time"]["formula"] == "S_l^(1/2) / S_a^(1/2)"
    assert rows["mass"]["ratio"] == "1/256"
    notes = " ".join(sim.notes())
    assert "S_rho = 16" in notes and "added mass" in notes and "Table 1" in notes


def test_the_papers_stated_density_ratio_contradicts_table_1():
    """The text's S_E = S_rho = 1 with S_l = 1/16 and S_a = 1 is over-determined."""
    with pytest.raises(SimilitudeError) as info:
        similitude({"length": "1/16", "modulus": 1, "acceleration": 1, "density": 1})
    assert "imply density 16" in str(info.value) and "not 1" in str(info.value)
    similitude({"length": "1/16", "modulus": 1, "acceleration": 1, "density": 16})  # agrees


def test_irrational_ratios_stay_exact():
    sim = similitude({"length": "1/15", "modulus": "1", "acceleration": "1"})
    time = sim.ratio("time")
    assert time.exact is None and str(time) == "(1/15)^(1/2)"
    assert (time**2).exact == Fraction(1, 15)
    assert float(time) == pytest.approx(15**-0.5, rel=1e-15)
    assert Ratio.of("1/16") ** Fraction(1, 2) == Ratio.of(Fraction(1, 4))


def test_similitude_needs_three_independent_ratios():
    with pytest.raises(SimilitudeError, match="three scale ratios"):
        similitude({"length": "1/16", "displacement": "1/16", "acceleration": 1})
    with pytest.raises(SimilitudeError, match="unknown quantity"):
        similitude({"lenght": "1/16"})
    with pytest.raises(SimilitudeError, match="positive"):
        similitude({"length": "-1/16", "modulus": 1, "acceleration": 1})


# ---------------------------------------------------------------------------------------------
# the Pi groups of scenes
# ---------------------------------------------------------------------------------------------

def _values(report) -> dict[str, float]:
    return {g.name: report.values[g.name] for g in report.groups}


@pytest.mark.parametrize("model", ["wu2021-eq14.yaml", "wu2021-eq14-pi.yaml"])
def test_eq14_gives_the_ten_numbers_of_the_paper(model):
    loaded = load_scene(MODELS / model)
    report = scene_pi(loaded.scene, loaded.expanded)
    assert len(report.variables) == 13 and report.repeating == ("m_b", "a_p", "w_p")
    values = _values(report)
    assert list(values) == list(EQ14)  # the paper's names, in its order
    for name, value in EQ14.items():
        assert values[name] == pytest.approx(value, rel=1e-12, abs=1e-15), name
    assert report.numerics["dtau"] == pytest.approx(0.001, rel=1e-12)
    assert report.numerics["tau"] == pytest.approx(50.0, rel=1e-12)


def test_hust_model_gives_the_numbers_of_section_4_4():
    loaded = load_scene(MODELS / "hust-4x3-pi.yaml")
    values = _values(scene_pi(loaded.scene, loaded.expanded))
    assert values == pytest.approx(HUST, rel=1e-12)
    # the dimensional model keeps the test's 2 mm gap: Pi_d = 0.408, printed as 0.41
    loaded = load_scene(MODELS / "hust-4x3.yaml")
    values = _values(scene_pi(loaded.scene, loaded.expanded))
    assert values["Pi_d"] == pytest.approx(0.002 * 20**2 / (0.2 * 9.80665), rel=1e-12)
    assert round(values["Pi_d"], 2) == 0.41


def test_pi_command_prints_names_formulas_values_and_json(capsys):
    assert main(["pi", str(MODELS / "wu2021-eq14.yaml")]) == 0
    out = capsys.readouterr().out
    assert "13 governing variables, 3 reference dimensions, 10 Pi groups" in out
    assert "Pi_k     = K_a / (m_b w_p^2)  5\n" in out
    assert "Pi_mu    = K_b / K_a          10\n" in out
    assert main(["pi", str(MODELS / "wu2021-eq14.yaml"), "--json"]) == 0
    data = json.loads(capsys.readouterr().out)
    assert [g["name"] for g in data["groups"]] == list(EQ14)
    for g in data["groups"]:
        assert g["value"] == pytest.approx(EQ14[g["name"]], rel=1e-12)
    assert {v["name"]: v["dimension"] for v in data["variables"]}["K_a"] == "M T^-2"
    exponents = {g["name"]: g["exponents"] for g in data["groups"]}
    assert exponents["Pi_uya"] == {"u_ya": "1", "a_p": "-1", "w_p": "2"}


def test_pi_command_takes_other_repeating_variables(capsys):
    model = str(MODELS / "wu2021-eq14.yaml")
    assert main(["pi", model, "--repeating", "m_a,K_a,a_p", "--json"]) == 0
    data = json.loads(capsys.readouterr().out)
    values = {g["name"]: g["value"] for g in data["groups"]}
    assert values["Pi_w_p"] == pytest.approx(1 / math.sqrt(5 / 0.25), rel=1e-12)
    assert main(["pi", model, "--repeating", "m_a,K_a,w_p"]) == 2
    assert "are not independent" in capsys.readouterr().err


def test_a_record_takes_its_pga_and_mean_period(tmp_path):
    """For a record, a_p is the PGA and w_p = 2 pi / T_m; a sampled sine of 2 Hz has
    T_m = 0.5 s (to the spectral leakage of a finite record)."""
    import numpy as np

    t = np.arange(0.0, 20.0, 0.005)
    np.savetxt(tmp_path / "sine.txt", np.column_stack([t, 2.5 * np.sin(4 * np.pi * t)]))
    text = json.dumps({
        "buildings": [{"name": "A", "floors": 1, "mass": 100.0,
                       "story": {"material": "elastic", "stiffness": 1e5}}],
        "excitation": {"kind": "record", "file": "sine.txt"},
        "analysis": {"dt": 0.005, "duration": 19.99}})
    loaded = parse_scene(text, base_dir=tmp_path)
    report = scene_pi(loaded.scene, loaded.expanded)
    by_name = {v.name: v.value for v in report.variables}
    assert by_name["a_p"] == pytest.approx(2.5, rel=1e-6)
    assert by_name["w_p"] == pytest.approx(4 * np.pi, rel=0.02)
    assert "Rathje" in report.notes[0]


def _eq14_with_dashpot_storeys(exponent: float, damping: float = 3000.0):
    data = yaml.safe_load((MODELS / "wu2021-eq14.yaml").read_text(encoding="utf-8"))
    data["buildings"][0]["story"] = {"material": "kelvin_voigt", "stiffness": 197392.0,
                                     "damping": damping, "exponent": exponent}
    return parse_scene(json.dumps(data), base_dir=MODELS)


@pytest.mark.parametrize("exponent", [1.0, 0.5])
def test_a_dashpot_storeys_coefficient_is_a_governing_variable(exponent):
    """A Kelvin-Voigt storey's c of F = k u + c |v|^alpha sign v is in N (s/m)^alpha
    = M L^(1 - alpha) T^(alpha - 2): with m_b, a_p, w_p repeating its group is
    c / (m_b a_p^(1 - alpha) w_p^alpha) (pframe pi once left c out and exited 0, and named
    alpha "post-yield stiffness ratio")."""
    loaded = _eq14_with_dashpot_storeys(exponent)
    report = scene_pi(loaded.scene, loaded.expanded)
    c = {v.name: v for v in report.variables}["c"]
    a = Fraction(exponent)
    assert c.dimension == Dimension(1, 1 - a, a - 2) and c.value == 3000.0
    m_b, a_p, w_p = 1000.0, 9.81, 2 * math.pi
    expected = 3000.0 / (m_b * a_p ** (1 - exponent) * w_p ** exponent)
    assert report.values["Pi_c"] == pytest.approx(expected, rel=1e-12)
    # its exponent is not the bilinear storeys' post-yield ratio, though both are "alpha"
    assert report.values["Pi_alpha_v"] == exponent and report.values["Pi_alpha"] == 0.1


def test_every_numeric_field_of_a_built_in_law_declares_its_dimension():
    """Or why it has none: pframe pi and pframe scale would refuse the law otherwise (the
    dashpots' c, in N (s/m)^alpha, once declared neither)."""
    from pframe.laws.registry import builtin_laws
    from pframe.nondim.fields import check_declared

    for kind in ("material", "contact"):
        for law in builtin_laws(kind):
            check_declared(law)


def test_pi_refuses_a_law_parameter_without_a_declared_dimension():
    """A law field that declares no dimension (nor why it has none) cannot be a governing
    variable: pframe pi refuses the scene, naming the law, the field and the declaration,
    where it once left the field out and exited 0 (the default governing() of a plug-in law
    dropped it; a law with its own governing() never listed it)."""
    class Undeclared(Law):  # a plug-in law as a third party might write it
        class Params(LawParams):
            stiffness: Positive = Field(description="k (N/m)")
            reach: Positive = Field(description="a length (m) whose dimension is not declared")

        kind, name = "material", "undeclared"
        param_names = ("stiffness", "reach")
        dimensions = {"stiffness": "stiffness"}

    class OwnGoverning(Undeclared):
        name = "own_governing"

        @classmethod
        def governing(cls, packed, effective_mass=None):
            return {"K": ("stiffness", packed[0])}

    loaded = load_scene(MODELS / "wu2021-eq14.yaml")
    for law in (Undeclared, OwnGoverning):
        stories = tuple(replace(s, law=law, packed=(s.packed[0], 0.02))
                        for s in loaded.expanded.stories)
        expanded = replace(loaded.expanded, stories=stories)
        with pytest.raises(InputError) as refused:
            scene_pi(loaded.scene, expanded)
        message = str(refused.value)
        assert f"field 'reach' of material {law.name!r}" in message
        assert "dimensions = {'reach':" in message


# ---------------------------------------------------------------------------------------------
# random scenes: groups dimensionless and independent; similar scenes have the same groups
# ---------------------------------------------------------------------------------------------

_POSITIVE = st.floats(0.05, 20.0)
_CONTACT_LAWS = ["linear", "kelvin", "improved_kelvin", "hertz", "hertzdamp", "jankowski"]


@st.composite
def _scenes(draw) -> dict:
    """A random dimensional scene: 1-3 buildings of 1-4 floors, uniform or per-storey values,
    elastic or bilinear storeys, contacts of any built-in law at common floors, a sine."""
    n = draw(st.integers(1, 3))
    floors = [draw(st.integers(1, 4)) for _ in range(n)]
    buildings = []
    for i, f in enumerate(floors):
        def value(scale, f=f):
            if draw(st.booleans()):
                return draw(_POSITIVE) * scale
            return [draw(_POSITIVE) * scale for _ in range(f)]
        story = {"material": draw(st.sampled_from(["elastic", "bilinear"])),
                 "stiffness": value(1e5)}
        if story["material"] == "bilinear":
            story |= {"yield_drift": value(0.01), "alpha": draw(st.sampled_from([0.0, 0.1, 0.3]))}
        building = {"name": "ABC"[i], "floors": f, "mass": value(100.0), "story": story}
        if draw(st.booleans()):
            building["damping"] = {"ratio": draw(st.sampled_from([0.0, 0.02, 0.05]))}
        buildings.append(building)
    contacts = []
    for i in range(n - 1):
        for level in range(1, min(floors[i], floors[i + 1]) + 1):
            if not draw(st.booleans()):
                continue
            law = draw(st.sampled_from(_CONTACT_LAWS))
            contact = {"nodes": [f"{'ABC'[i]}/{level}", f"{'ABC'[i + 1]}/{level}"],
                       "gap": draw(st.sampled_from([0.0, 0.001, 0.02])), "law": law}
            if law in ("linear", "kelvin", "improved_kelvin"):
                form = draw(st.sampled_from(["stiffness", "frequency", "frequency_ratio"]))
                contact[form] = draw(_POSITIVE) * {"stiffness": 1e7, "frequency": 100.0,
                                                   "frequency_ratio": 10.0}[form]
            else:
                contact["stiffness"] = draw(_POSITIVE) * 1e9
            if law != "linear" and law != "hertz":
                contact["restitution"] = draw(st.sampled_from([0.3, 0.5, 0.8]))
            contacts.append(contact)
    excitation = {"kind": "sine", "amplitude": draw(_POSITIVE), "frequency": draw(_POSITIVE)}
    if draw(st.booleans()):
        excitation["duration"] = draw(_POSITIVE)
    return {"buildings": buildings, "contacts": contacts, "excitation": excitation,
            "damping": {"ratio": 0.05}, "analysis": {"dt": 0.01, "duration": 0.1},
            "initial_conditions": {"velocity": {"A/1": draw(st.sampled_from([0.0, 0.3]))}}}


_SIMILITUDE = st.fixed_dictionaries({
    q: st.sampled_from(["1/1000", "1/16", "1/3", "1", "7/2", "10", "1000"])
    for q in ("mass", "length", "time")})


@pytest.mark.slow
@given(_scenes(), _SIMILITUDE)
@settings(max_examples=60, deadline=None, suppress_health_check=[HealthCheck.too_slow])
def test_groups_of_random_scenes_are_dimensionless_independent_and_similarity_invariant(
        data, factors):
    """Any scene's groups are dimensionless, independent and complete (n - 3 of them), and a
    scene scaled by any similitude (mass, length, time ratios 1/1000 .. 1000) has the same
    groups with the same values."""
    loaded = parse_scene(json.dumps(data))
    report = scene_pi(loaded.scene, loaded.expanded)
    variables = {v.name: v for v in report.variables}
    assert all(g.dimension(variables).dimensionless for g in report.groups)
    assert len(report.groups) == len(variables) - 3
    check_groups(list(variables.values()), list(report.groups))

    scaled = scale_scene(data, similitude(factors), "model")
    other = parse_scene(json.dumps(scaled))
    again = scene_pi(other.scene, other.expanded)
    assert [g.name for g in again.groups] == [g.name for g in report.groups]
    for name, value in report.values.items():
        assert again.values[name] == pytest.approx(value, rel=1e-9, abs=1e-300), name
    back = scale_scene(scaled, similitude(factors), "prototype")
    flat = json.dumps(back)
    assert json.loads(flat).keys() == data.keys()


# ---------------------------------------------------------------------------------------------
# Pi-form scenes
# ---------------------------------------------------------------------------------------------

_CONTACT_OPTIONS = {"kelvin": [{}, {"keep_tension": True}, {"calibration": "exact"}],
                    "improved_kelvin": [{}, {"calibration": "exact"}],
                    "hertzdamp": [{}, {"formula": "ye"}, {"calibration": "exact"}],
                    "jankowski": [{}, {"calibration": "exact"}]}
_STIFFNESS_GROUP = {"linear": "Pi_wcon", "kelvin": "Pi_wcon", "improved_kelvin": "Pi_wcon",
                    "hertz": "Pi_kh", "hertzdamp": "Pi_kh", "jankowski": "Pi_kh"}


def _pi_numbers(draw, floors: dict, reference: str, law: str, contacts: bool) -> dict:
    """The Pi numbers of a row of buildings, named as the paper names them: one mass ratio per
    building other than the reference one (``Pi_m`` when there is one), ``Pi_k`` for building
    a's stiffness, ``Pi_mu`` for each other building's relative to a's (suffixed by tag when
    there are several), ``Pi_uy<tag>`` for a yielding building."""
    tags = list(floors)
    others = [t for t in tags if t != reference]
    pi = {("Pi_m" if len(others) == 1 else f"Pi_m{t}"): draw(st.floats(0.1, 10)) for t in others}
    pi["Pi_k"] = draw(st.floats(0.5, 50))
    pi |= {("Pi_mu" if len(tags) == 2 else f"Pi_mu{t}"): draw(st.floats(0.1, 10))
           for t in tags[1:]}
    for t in tags:
        if draw(st.booleans()):
            pi[f"Pi_uy{t}"] = draw(st.floats(0.01, 1.0))
    pi["Pi_xi"] = draw(st.floats(0.0, 0.2))
    if any(k.startswith("Pi_uy") for k in pi):
        pi["Pi_alpha"] = draw(st.floats(0.0, 1.0))
    if contacts:
        pi[_STIFFNESS_GROUP[law]] = draw(st.floats(5, 100))
        pi["Pi_d"] = draw(st.floats(0.0, 2.0))
        if law not in ("linear", "hertz"):
            pi["Pi_e"] = draw(st.floats(0.1, 1.0))
    return pi


@st.composite
def _pi_scenes(draw) -> dict:
    """A Pi-form scene: 1 to 4 buildings of 1 to 4 floors, any reference building, contacts of
    any built-in law (and its options) at chosen levels of each neighbouring pair, a sine."""
    n = draw(st.integers(1, 4))
    tags = "abcd"[:n]
    floors = {t: draw(st.integers(1, 4)) for t in tags}
    pairs = [f"{a}-{b}" for a, b in zip(tags, tags[1:])]
    levels = {p: draw(st.lists(st.integers(1, min(floors[p[0]], floors[p[2]])), unique=True,
                               max_size=4)) for p in pairs}
    law = draw(st.sampled_from(_CONTACT_LAWS))
    reference = draw(st.sampled_from(tags))
    pi = _pi_numbers(draw, floors, reference, law, any(levels.values()))
    scene = {"pi": pi,
             "buildings": {t: {"name": t.upper(), "floors": f} for t, f in floors.items()},
             "contacts": {"floors": levels, "law": law,
                          **draw(st.sampled_from(_CONTACT_OPTIONS.get(law, [{}])))},
             "analysis": {"dt_tau": 0.01, "tau": 1.0}}
    if draw(st.booleans()) or reference != ("b" if n > 1 else "a"):
        scene["reference"] = reference
    if draw(st.booleans()):
        scene["scales"] = {"m_b": draw(st.floats(1e-3, 1e4)), "a_p": draw(st.floats(1e-2, 1e2)),
                           "w_p": draw(st.floats(1e-1, 1e3))}
    return scene


@pytest.mark.slow
@given(_pi_scenes())
@settings(max_examples=100, deadline=None, suppress_health_check=[HealthCheck.too_slow])
def test_expanding_a_pi_scene_then_taking_its_groups_returns_its_numbers(scene):
    loaded = parse_scene(json.dumps(scene))
    report = scene_pi(loaded.scene, loaded.expanded)
    values = _values(report)
    assert set(values) == set(scene["pi"])
    for name, value in scene["pi"].items():
        assert values[name] == pytest.approx(value, rel=1e-12, abs=1e-15), name
    assert report.numerics["dtau"] == pytest.approx(0.01, rel=1e-12)
    reference = scene.get("reference", "b" if len(scene["buildings"]) > 1 else "a")
    assert report.repeating[0] == f"m_{reference}"
    scales = scene.get("scales", {"m_b": 1.0})
    first = list(loaded.expanded.node_building).index("abcd".index(reference))
    assert loaded.expanded.masses[first] == scales["m_b"]


def _sine_record(folder: Path, frequency_hz: float = 2.0, amplitude: float = 2.5) -> str:
    """A two-column record file of a sine (m/s^2), 20 s at 200 samples per second."""
    import numpy as np

    t = np.arange(0.0, 20.0, 0.005)
    np.savetxt(folder / "sine.txt", np.column_stack([t, amplitude * np.sin(2 * np.pi * frequency_hz * t)]))
    return "sine.txt"


def _row_of_three(law: str, record: str, **extra) -> dict:
    stiffness = {"Pi_wcon": 40.0} if _STIFFNESS_GROUP[law] == "Pi_wcon" else {"Pi_kh": 75.0}
    restitution = {} if law in ("linear", "hertz") else {"Pi_e": 0.65}
    return {"pi": {"Pi_ma": 1.2, "Pi_mc": 0.8, "Pi_k": 15.8, "Pi_mub": 0.9, "Pi_muc": 0.81,
                   "Pi_uya": 0.66, "Pi_uyc": 0.5, "Pi_xi": 0.05, "Pi_alpha": 0.1, **stiffness,
                   **restitution, "Pi_d": 0.88},
            "buildings": {"a": {"name": "A", "floors": 8}, "b": {"name": "B", "floors": 5},
                          "c": {"name": "C", "floors": 3}},
            "contacts": {"law": law},
            "excitation": {"kind": "record", "file": record},
            "analysis": {"dt_tau": 0.01, "tau": 20.0}, **extra}


@pytest.mark.parametrize("law", _CONTACT_LAWS)
def test_every_contact_law_has_a_pi_form_under_a_record(law, tmp_path):
    """Three buildings, each built-in law, a record scaled to a_p and w_p: expand, then pi,
    gives the numbers back; a Hertz-type stiffness is k_h a_p^(1/2) / (m_b w_p^3), i.e.
    k_h l_e^(1/2) / (m_b w_p^2)."""
    scene = _row_of_three(law, _sine_record(tmp_path), scales={"m_b": 1.5e5, "a_p": 3.0, "w_p": 20.0})
    loaded = parse_scene(json.dumps(scene), base_dir=tmp_path)
    report = scene_pi(loaded.scene, loaded.expanded)
    assert _values(report) == pytest.approx(scene["pi"], rel=1e-12)
    variables = {v.name: v.value for v in report.variables}
    assert variables["a_p"] == pytest.approx(3.0, rel=1e-15)
    assert variables["w_p"] == pytest.approx(20.0, rel=1e-15)
    group = {g.name: g for g in report.groups}[_STIFFNESS_GROUP[law]]
    if law.startswith(("hertz", "jankowski")):
        assert group.powers == {"k_h": 1, "a_p": Fraction(1, 2), "m_b": -1, "w_p": -3}
        l_e = 3.0 / 20.0**2
        k_h = loaded.expanded.contacts[0].packed[0]
        assert k_h * l_e**0.5 / (1.5e5 * 20.0**2) == pytest.approx(75.0, rel=1e-12)
    else:
        assert group.powers == {"w_bar": 1, "w_p": -1}
    contacts = [c.name for c in loaded.expanded.contacts]
    assert contacts == [f"A/{i}-B/{i}" for i in range(1, 6)] + [f"B/{i}-C/{i}" for i in range(1, 4)]


@pytest.mark.slow
def test_a_record_is_scaled_to_a_p_and_compressed_to_w_p(tmp_path):
    """A 2 Hz sine record of amplitude 2.5 m/s^2 (T_m = 0.5 s) in a Pi form with a_p = 5 and
    w_p = 2 pi 8 rad/s is applied as a sine of 5 m/s^2 at 8 Hz; without scales it is applied as
    recorded, and a stated period of 1 s sets w_p = 2 pi rad/s instead."""
    import numpy as np

    scene = _row_of_three("hertzdamp", _sine_record(tmp_path),
                          scales={"m_b": 1.0, "a_p": 5.0, "w_p": 16 * math.pi})
    expanded = parse_scene(json.dumps(scene), base_dir=tmp_path).expanded
    t = np.arange(expanded.steps + 1) * expanded.dt
    # the mean period of a finite sampled sine is 0.5 s to its spectral leakage
    time_factor = expanded.record.time_factor
    assert time_factor == pytest.approx(0.25, rel=3e-3)
    # linear interpolation between samples 0.00125 s apart: (w h)^2 / 8 of the amplitude, 2.5e-3
    expected = 5.0 * np.sin(4 * math.pi * t / time_factor)
    assert expanded.ground_acceleration == pytest.approx(expected, abs=3e-3)
    assert expanded.dt == pytest.approx(0.01 / (16 * math.pi), rel=1e-15)

    as_recorded = parse_scene(json.dumps(_row_of_three("hertz", "sine.txt")), base_dir=tmp_path)
    variables = {v.name: v.value for v in scene_pi(as_recorded.scene, as_recorded.expanded).variables}
    assert variables["a_p"] == pytest.approx(2.5, rel=1e-12)
    assert variables["w_p"] == pytest.approx(4 * math.pi, rel=3e-3)
    assert as_recorded.expanded.record.time_factor == 1.0

    predominant = _row_of_three("hertz", "sine.txt")
    predominant["excitation"]["period"] = "predominant"
    loaded = parse_scene(json.dumps(predominant), base_dir=tmp_path)
    report = scene_pi(loaded.scene, loaded.expanded)
    assert {v.name: v.value for v in report.variables}["w_p"] == pytest.approx(4 * math.pi, rel=5e-3)
    assert "predominant period T_p" in report.notes[0]

    stated = _row_of_three("hertz", "sine.txt")
    stated["excitation"]["period"] = 1.0
    loaded = parse_scene(json.dumps(stated), base_dir=tmp_path)
    report = scene_pi(loaded.scene, loaded.expanded)
    assert {v.name: v.value for v in report.variables}["w_p"] == pytest.approx(2 * math.pi)
    assert "the period stated in the scene" in report.notes[0]


@pytest.mark.slow
def test_oscillator_steps_are_exact_for_a_piecewise_linear_record():
    """The spectrum recurrence against an adaptive Runge-Kutta integration of the same
    oscillator under the same linearly interpolated record (a chirp from rest), and the
    predominant period of a 2 Hz sine: the resonance, 0.5 s to the damped peak's offset."""
    import numpy as np
    from scipy.integrate import solve_ivp

    from pframe.excitation.characteristic import predominant_period, sdof_peak_displacements

    t = np.arange(0.0, 10.0, 0.02)
    a = 3.0 * np.sin(2 * np.pi * (0.5 + 0.3 * t) * t)
    for period in (0.15, 0.7, 2.5):
        w = 2 * np.pi / period
        def rate(s, z, w=w):
            return [z[1], -w * w * z[0] - 0.1 * w * z[1] - np.interp(s, t, a)]

        solution = solve_ivp(rate, (0, t[-1]), [0.0, 0.0], t_eval=t, max_step=0.005,
                             rtol=1e-11, atol=1e-13)
        exact = np.max(np.abs(solution.y[0]))
        assert sdof_peak_displacements(t, a, [period])[0] == pytest.approx(exact, rel=1e-7)
    sine = 2.5 * np.sin(4 * np.pi * np.arange(0.0, 20.0, 0.005))
    assert predominant_period(np.arange(0.0, 20.0, 0.005), sine) == pytest.approx(0.5, rel=5e-3)


def test_a_record_scene_with_frequency_scales_in_time(tmp_path):
    """A dimensional scene whose record names its characteristic frequency scales with any
    similitude: the same Pi groups (a record without it is refused when S_T != 1)."""
    scene = _row_of_three("jankowski", _sine_record(tmp_path), scales={"a_p": 3.0, "w_p": 20.0})
    from pframe.nondim.pi_form import expand_pi_data

    data = expand_pi_data(scene, {}, "row.yaml", tmp_path)
    before = parse_scene(json.dumps(data), base_dir=tmp_path)
    scaled = scale_scene(data, similitude({"length": "1/16", "modulus": 1, "acceleration": 1}))
    assert scaled["excitation"]["frequency"] == pytest.approx(4 * 20.0)
    after = parse_scene(json.dumps(scaled), base_dir=tmp_path)
    a, b = (scene_pi(x.scene, x.expanded) for x in (before, after))
    assert b.values == pytest.approx(a.values, rel=1e-12)


def test_pi_form_problems_are_named_all_at_once(tmp_path):
    """A level two buildings do not share, an option the law has not, a Pi number that does
    not apply, one that is unknown and one that is missing: one message with all five."""
    scene = _row_of_three("hertz", _sine_record(tmp_path))
    scene["pi"] |= {"Pi_e": 0.5, "Pi_q": 1.0}
    del scene["pi"]["Pi_alpha"]
    scene["contacts"] |= {"floors": {"a-b": [1, 6]}, "keep_tension": True}
    with pytest.raises(InputError) as info:
        parse_scene(json.dumps(scene), source="row.yaml", base_dir=tmp_path)
    message = str(info.value)
    for part in ("contacts.floors.a-b[1]: contact level 6 is not a floor both a and b have",
                 "contacts.keep_tension: keep_tension does not apply to hertz contacts",
                 "pi.Pi_e: Pi_e does not apply: hertz contacts have no restitution",
                 "pi.Pi_q: unknown field", "pi: Pi_alpha is required (alpha)"):
        assert part in message, (part, message)
    assert message.count("row.yaml") == 5


def test_a_record_takes_pga_or_scale_not_both(tmp_path):
    data = {"buildings": [{"name": "A", "floors": 1, "mass": 1.0,
                           "story": {"material": "elastic", "stiffness": 1.0}}],
            "excitation": {"kind": "record", "file": _sine_record(tmp_path), "scale": 2.0,
                           "pga": 3.0},
            "analysis": {"dt": 0.005, "duration": 1}}  # the record's own samples
    with pytest.raises(InputError, match="give scale .a factor. or pga"):
        parse_scene(json.dumps(data), base_dir=tmp_path)
    del data["excitation"]["scale"]
    loaded = parse_scene(json.dumps(data), base_dir=tmp_path)
    assert max(abs(loaded.expanded.ground_acceleration)) == pytest.approx(3.0, rel=1e-9)


def test_expand_command_prints_a_valid_dimensional_scene(tmp_path, capsys):
    source = MODELS / "wu2021-eq14-pi.yaml"
    assert main(["expand", str(source)]) == 0
    text = capsys.readouterr().out
    assert text.startswith("# yaml-language-server: $schema=../schemas/model.schema.json\n")
    data = yaml.safe_load(text)
    assert "pi" not in data and data["buildings"][1]["mass"] == 1.0
    assert data["contacts"][0]["gap"] == 0.5 and data["analysis"]["dt"] == 0.001
    expanded = parse_scene(text).expanded
    direct = load_scene(source).expanded
    assert (expanded.masses == direct.masses).all()
    assert [c.packed for c in expanded.contacts] == [c.packed for c in direct.contacts]
    assert [s.packed for s in expanded.stories] == [s.packed for s in direct.stories]
    out = tmp_path / "eq14.yaml"
    assert main(["expand", str(source), "-o", str(out)]) == 0
    assert out.read_text(encoding="utf-8") == text


def test_pi_scene_scales_are_the_reference_scales(tmp_path):
    """m_b, a_p, w_p of scales: make the paper's dimensional example exactly."""
    data = yaml.safe_load((MODELS / "wu2021-eq14-pi.yaml").read_text(encoding="utf-8"))
    data["scales"] = {"m_b": 1000.0, "a_p": 9.81, "w_p": 2 * math.pi}
    mine = parse_scene(json.dumps(data)).expanded
    shipped = load_scene(MODELS / "wu2021-eq14.yaml").expanded
    assert mine.masses.tolist() == shipped.masses.tolist()
    for a, b in zip(mine.stories + mine.contacts, shipped.stories + shipped.contacts):
        assert a.packed == pytest.approx(b.packed, rel=1e-14)
        assert a.gap == pytest.approx(b.gap, rel=1e-14)
    assert mine.dt == pytest.approx(shipped.dt, rel=1e-15) and mine.steps == shipped.steps


_PI_ERRORS = [
    ("  Pi_e: 0.4        # coefficient of restitution\n",
     "  Pi_e: 0.4\n  Pi_f: 1\n", "line 21, pi.Pi_f: unknown field"),
    ("law: improved_kelvin}", "law: linear}", "line 20, pi.Pi_e: Pi_e does not apply: linear"),
    ("floors: [1, 2, 3]", "floors: [1, 4]", "line 25, contacts.floors[1]: contact level 4"),
    ("  Pi_alpha: 0.1    # post-yield stiffness ratio\n", "",
     "line 11, pi: Pi_alpha is required"),
    ("  b: {name: B, floors: 3}", "  b: {name: A, floors: 3}",
     "line 24, buildings.b.name: buildings a and b are both 'A'"),
    ("  dt_tau: 0.001", "  dt: 0.001", "line 28, analysis.dt: unknown field"),
    ("Pi_k: 5 ", "Pi_k: -5 ", "line 13, pi.Pi_k: Input should be greater than 0"),
    ("Pi_k: 5 ", "Pi_k: yes ", "line 13, pi.Pi_k: expected a number, got the boolean true"),
]


@pytest.mark.parametrize("old, new, message", _PI_ERRORS, ids=[e[2][:40] for e in _PI_ERRORS])
def test_pi_scene_errors_name_the_line(old, new, message):
    text = (MODELS / "wu2021-eq14-pi.yaml").read_text(encoding="utf-8")
    assert old in text
    with pytest.raises(InputError) as info:
        parse_scene(text.replace(old, new, 1), source="eq14-pi.yaml")
    assert f"eq14-pi.yaml, {message}" in str(info.value)


def test_dimensionless_output_needs_scales_without_excitation():
    data = {"nodes": [{"name": "A/1", "mass": 1.0}], "analysis": {"dt": 0.1, "duration": 1},
            "output": {"units": "dimensionless"}}
    with pytest.raises(InputError, match="output: dimensionless output needs reference scales"):
        parse_scene(json.dumps(data))
    data["output"]["scales"] = {"m_b": 1.0, "a_p": 2.0, "w_p": 3.0}
    parse_scene(json.dumps(data))


# ---------------------------------------------------------------------------------------------
# pframe scale
# ---------------------------------------------------------------------------------------------

def test_scale_command_prints_table_1(capsys):
    args = ["scale", "--length", "1/16", "--modulus", "1", "--acceleration", "1"]
    assert main(args) == 0
    out = capsys.readouterr().out
    assert "  time         S_T    T             1/4" in out
    assert "  mass         S_m    M             1/256" in out
    assert "added mass" in out
    assert main([*args, "--json"]) == 0
    rows = {r["quantity"]: r for r in json.loads(capsys.readouterr().out)["rows"]}
    assert {q: rows[q]["ratio"] for q in ("stiffness", "time", "velocity", "mass", "density")} \
        == {"stiffness": "1/16", "time": "1/4", "velocity": "1/4", "mass": "1/256",
            "density": "16"}
    assert rows["length"]["status"] == "chosen" and rows["time"]["status"] == "implied"
    assert main(["scale", "--length", "1/16", "--modulus", "1", "--density", "1",
                 "--acceleration", "1"]) == 2
    assert "imply acceleration 16" in capsys.readouterr().err


def test_scale_command_scales_a_scene_both_ways(tmp_path, capsys):
    source = MODELS / "wu2021-eq14.yaml"
    model = tmp_path / "model.yaml"
    args = ["--length", "1/16", "--modulus", "1", "--acceleration", "1"]
    assert main(["scale", str(source), *args, "-o", str(model)]) == 0
    small = load_scene(model)
    big = load_scene(source)
    assert small.expanded.masses == pytest.approx(big.expanded.masses / 256, rel=1e-15)
    assert small.expanded.dt == pytest.approx(big.expanded.dt / 4, rel=1e-15)
    assert small.expanded.contacts[0].gap == pytest.approx(big.expanded.contacts[0].gap / 16)
    a, b = (scene_pi(x.scene, x.expanded) for x in (small, big))
    assert a.values == pytest.approx(b.values, rel=1e-12)
    back = tmp_path / "back.yaml"
    assert main(["scale", str(model), *args, "--to", "prototype", "-o", str(back)]) == 0
    again = load_scene(back).expanded
    assert again.masses == pytest.approx(big.expanded.masses, rel=1e-15)
    capsys.readouterr()
    assert main(["scale", str(MODELS / "hust-4x3-pi.yaml"), *args]) == 0
    scaled = yaml.safe_load(capsys.readouterr().out)
    assert scaled["pi"] == yaml.safe_load(
        (MODELS / "hust-4x3-pi.yaml").read_text(encoding="utf-8"))["pi"]
    assert scaled["scales"] == pytest.approx({"m_b": 1700 / 256, "a_p": 1.96133, "w_p": 80.0})


def test_scaling_a_record_in_time_is_refused(tmp_path):
    data = {"buildings": [{"name": "A", "floors": 1, "mass": 1.0,
                           "story": {"material": "elastic", "stiffness": 1.0}}],
            "excitation": {"kind": "record", "file": "r.txt", "scale": 2.0},
            "analysis": {"dt": 0.1, "duration": 1}}
    with pytest.raises(SimilitudeError, match="record"):
        scale_scene(data, similitude({"length": "1/16", "modulus": 1, "acceleration": 1}))
    same_time = similitude({"length": "1/16", "time": 1, "mass": "1/2"})
    assert scale_scene(data, same_time)["excitation"]["scale"] == pytest.approx(2 / 16)


# ---------------------------------------------------------------------------------------------
# docs/dimensional-analysis.md
# ---------------------------------------------------------------------------------------------

DOC = REPO / "docs" / "dimensional-analysis.md"


@pytest.mark.parametrize("marker, argv", [
    ("pi-output", ["pi", "models/wu2021-eq14.yaml"]),
    ("scale-output", ["scale", "--length", "1/16", "--modulus", "1", "--acceleration", "1"]),
])
def test_the_page_shows_what_the_commands_print(marker, argv, capsys, monkeypatch):
    monkeypatch.chdir(REPO)
    text = DOC.read_text(encoding="utf-8")
    block = text.split(f"<!-- BEGIN {marker} -->\n")[1].split(f"<!-- END {marker} -->")[0]
    assert main(argv) == 0
    assert block == f"```text\n{capsys.readouterr().out}```\n"


def test_the_page_lists_every_key_of_pi_form_scenes():
    from pframe.nondim.pi_form import PiBuilding, PiContacts, PiNumbers, PiScene, Scales

    text = DOC.read_text(encoding="utf-8")
    for model in (PiScene, PiNumbers, PiBuilding, PiContacts, Scales):
        for field in model.model_fields:
            assert f"`{field}`" in text, f"{model.__name__}.{field} is not documented"
    assert "`dt_tau`" in text and "`tau`" in text


def test_nondim_imports_neither_numba_nor_h5py():
    """pframe.nondim reads definitions and returns definitions: no kernel, no HDF5."""
    import subprocess
    import sys

    code = "import sys, pframe.nondim; print('numba' in sys.modules, 'h5py' in sys.modules)"
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                         timeout=120, check=True).stdout
    assert out.split() == ["False", "False"]
