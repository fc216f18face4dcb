"""A scene in another unit system (``units:``, docs/units.md): the same physics as in SI, its
results in its own units, stated.

The scenes below are written once in SI and converted here by hand (mass / M, length / L,
force / (M L), a dashpot's c / (F L^-alpha), a Hertz stiffness / (F L^-1.5)), with the unit
factors written out in this file, not taken from pframe's table; the results are converted
back by the factor UDUNITS gives for each variable's ``units`` attribute (cf_units). The
kernel integrates in SI, so the only difference is the round-off of converting the inputs
(one rounding each) and the outputs, which the run carries through two impacts: measured
below 3e-16 of each variable's peak in kN-m-t, N-mm-t and kip-in-s, 5e-14 in lbf-in-s;
asserted to 1e-12.
"""

from __future__ import annotations

import copy
import math

import numpy as np
import pytest
import xarray as xr
import yaml
from conftest import REPO, record_file

from pframe.errors import InputError
from pframe.reader import parse_scene

INCH, POUND_FORCE = 0.0254, 4.4482216152605
#: name -> (kilograms per mass unit, metres per length unit); force = M L / s^2
SYSTEMS = {
    "N-m-kg": (1.0, 1.0),
    "kN-m-t": (1000.0, 1.0),
    "N-mm-t": (1000.0, 1e-3),
    "kip-in-s": (1000.0 * POUND_FORCE / INCH, INCH),
    "lbf-in-s": (POUND_FORCE / INCH, INCH),
}
#: the force and length symbols each system's files use
SYMBOLS = {"N-m-kg": ("N", "m"), "kN-m-t": ("kN", "m"), "N-mm-t": ("N", "mm"),
           "kip-in-s": ("kip", "in"), "lbf-in-s": ("lbf", "in")}
TOLERANCE = 1e-12

QUANTITIES = ["displacement", "velocity", "acceleration", "absolute_acceleration",
              "story_drift", "story_force", "contact_force", "contact_penetration",
              "link_force", "link_deformation", "ground_acceleration"]

SI = {
    "title": "units",
    "buildings": [
        {"name": "A", "floors": 2, "mass": 250.0, "height": [3.5, 3.0],
         "story": {"material": "bilinear", "stiffness": 200000.0, "yield_drift": 0.004,
                   "alpha": 0.1}},
        {"name": "B", "floors": 2, "mass": 1000.0, "height": 3.0,
         "story": {"material": "elastic", "stiffness": 2000000.0}}],
    "contacts": [{"nodes": ["A/2", "B/2"], "gap": 0.004, "law": "hertz",
                  "stiffness": 1.0e9},
                 {"nodes": ["A/1", "B/1"], "gap": 0.004, "law": "linear",
                  "stiffness": 5.0e7}],
    "links": [{"nodes": ["A/1", "B/1"], "material": "viscous", "damping": 3000.0,
               "exponent": 0.5}],
    "excitation": {"kind": "sine", "amplitude": 4.0, "frequency": 6.0},
    "initial_conditions": {"velocity": {"B/2": 0.05}},
    "analysis": {"dt": 0.0003, "duration": 1.0,
                 "newton": {"absolute_tolerance": 1e-15}},
    "recorders": [{"kind": "history", "quantities": QUANTITIES},
                  {"kind": "envelope", "quantities": ["displacement", "contact_force"]}],
}


def written_in(name: str, scene: dict = SI) -> dict:
    """``scene`` (in SI) as an engineer writes it in system ``name``."""
    mass, length = SYSTEMS[name]
    force = mass * length
    out = copy.deepcopy(scene)
    out["units"] = name
    for b in out["buildings"]:
        b["mass"] /= mass
        b["height"] = ([h / length for h in b["height"]] if isinstance(b["height"], list)
                       else b["height"] / length)
        b["story"]["stiffness"] /= force / length
        if "yield_drift" in b["story"]:
            b["story"]["yield_drift"] /= length
    for contact in out["contacts"]:
        contact["gap"] /= length
        contact["stiffness"] /= force / length ** (1.5 if contact["law"] == "hertz" else 1.0)
    for link in out.get("links", []):
        link["damping"] /= force * length ** -link["exponent"]
    excitation = out["excitation"]
    if excitation["kind"] == "sine":
        excitation["amplitude"] /= length
    else:
        excitation["pga"] /= length
    for node in out.get("initial_conditions", {}).get("velocity", {}):
        out["initial_conditions"]["velocity"][node] /= length
    out["analysis"]["newton"]["absolute_tolerance"] /= length
    return out


def _solve(data: dict, folder) -> xr.Dataset:
    import pframe

    return pframe.solve(parse_scene(yaml.safe_dump(data, sort_keys=False), "scene.yaml",
                                    folder))


def _in_si(ds: xr.Dataset, name: str) -> np.ndarray:
    """A variable of a result file in SI, by the factor UDUNITS gives for its units."""
    cf_units = pytest.importorskip("cf_units", reason="cf_units reads the units")
    unit = cf_units.Unit(ds[name].attrs["units"])
    return unit.convert(np.asarray(ds[name].values, float), _si(unit))


def _si(unit):
    import cf_units

    return cf_units.Unit(unit.definition.split(" ", 1)[-1] if " " in unit.definition
                         else unit.definition)


def _agree(a: np.ndarray, b: np.ndarray) -> float:
    return float(np.max(np.abs(a - b)) / max(np.max(np.abs(a)), 1e-300))


@pytest.fixture(scope="module")
def results(tmp_path_factory):
    folder = tmp_path_factory.mktemp("units")
    return {name: _solve(written_in(name), folder) for name in SYSTEMS}


@pytest.mark.slow
@pytest.mark.parametrize("name", list(SYSTEMS)[1:])
def test_the_same_scene_in_any_system_gives_the_same_physics(results, name):
    si, other = results["N-m-kg"], results[name]
    assert int(si["impact_count"].sum()) >= 2  # the contacts pound: the test is not idle
    for q in QUANTITIES + ["peak_displacement", "peak_contact_force"]:
        assert _agree(np.asarray(si[q].values, float), _in_si(other, q)) < TOLERANCE, q
    np.testing.assert_array_equal(si["impact_count"], other["impact_count"])
    energies = [k for k in si.attrs if si.attrs.get(f"{k}_units") == "J"]
    assert "energy_input" in energies
    cf_units = pytest.importorskip("cf_units")
    scale = cf_units.Unit(other.attrs["energy_input_units"]).convert(1.0, cf_units.Unit("J"))
    peak = max(abs(si.attrs[k]) for k in energies)
    for k in energies:
        assert abs(si.attrs[k] - other.attrs[k] * scale) <= TOLERANCE * peak, k


@pytest.mark.slow
@pytest.mark.parametrize("name", list(SYSTEMS))
def test_a_file_states_its_units(results, name):
    ds = results[name]
    force, length = SYMBOLS[name]
    assert ds.attrs["units_system"] == name
    assert f"force {force}, length {length}" in ds.attrs["units_system_description"]
    expected = {"displacement": length, "velocity": f"{length}/s",
                "acceleration": f"{length}/s^2", "story_force": force,
                "contact_force": force, "link_force": force,
                "peak_displacement": length, "contact_gap": length}
    for variable, units in expected.items():
        assert ds[variable].attrs["units"] == units, variable
    assert ds.attrs["energy_input_units"] == ("J" if name == "N-m-kg" else f"{force} {length}")
    assert ds["t"].attrs["units"] == "s"


def test_the_si_file_is_todays_to_the_bit(tmp_path):
    """N-m-kg is the default: a scene that says so is the scene that does not."""
    said = _solve({**SI, "analysis": {**SI["analysis"], "duration": 0.05},
                   "units": "N-m-kg"}, tmp_path)
    unsaid = _solve({**SI, "analysis": {**SI["analysis"], "duration": 0.05}}, tmp_path)
    for q in QUANTITIES:
        np.testing.assert_array_equal(said[q].values, unsaid[q].values)
    assert unsaid.attrs["units_system"] == "N-m-kg"


@pytest.mark.slow
@pytest.mark.parametrize("name", ["kN-m-t", "N-mm-t", "kip-in-s"])
def test_a_record_in_g_scaled_to_a_pga_in_the_scenes_units(tmp_path, name):
    """A PEER record is in g whatever the scene's units; its pga is in the scene's units."""
    (tmp_path / "elCentro.AT2").symlink_to(record_file("elCentro.AT2"))
    scene = {**SI, "excitation": {"kind": "record", "file": "elCentro.AT2", "pga": 3.0},
             "analysis": {**SI["analysis"], "duration": 2.1}}
    si = _solve(scene, tmp_path)
    other = _solve(written_in(name, scene), tmp_path)
    length = SYMBOLS[name][1]
    assert other.attrs["excitation_pga"] == pytest.approx(3.0 / SYSTEMS[name][1], rel=1e-14)
    assert other.attrs["excitation_pga_units"] == f"{length}/s^2"
    assert other.attrs["excitation_pga_g"] == pytest.approx(3.0 / 9.80665, rel=1e-14)
    for q in QUANTITIES:
        assert _agree(np.asarray(si[q].values, float), _in_si(other, q)) < TOLERANCE, q


@pytest.mark.slow
@pytest.mark.parametrize("name", ["N-mm-t", "kip-in-s"])
def test_soil_and_a_stochastic_motion_convert_too(tmp_path, name):
    """A building on soil (the cone model: V_s, density, a foundation's radius and mass) under
    a seeded Clough-Penzien motion (S_0 in m^2/s^3): the same physics in any system."""
    mass, length = SYSTEMS[name]
    scene = {k: v for k, v in SI.items() if k != "initial_conditions"}
    scene = copy.deepcopy(scene)
    scene["buildings"][1]["soil"] = {"shear_wave_velocity": 250.0, "poisson": 0.3,
                                     "density": 1900.0,
                                     "foundation": {"radius": 3.0, "mass": 2000.0}}
    scene["excitation"] = {"kind": "stochastic", "model": "clough_penzien", "seed": 3,
                           "intensity": 0.02, "ground_frequency": 15.0,
                           "ground_damping": 0.6, "envelope": {"kind": "gamma", "d595": 2.0,
                                                              "tmid": 1.0}}
    scene["analysis"] = {**scene["analysis"], "duration": 0.9}
    on_soil = QUANTITIES + ["foundation_sway", "foundation_rocking"]
    scene["recorders"] = [{"kind": "history", "quantities": on_soil}]
    other = written_in(name, {**scene, "excitation": {"kind": "sine", "amplitude": 1.0,
                                                      "frequency": 1.0}})
    soil = other["buildings"][1]["soil"]
    soil["shear_wave_velocity"] /= length
    soil["density"] /= mass / length**3
    soil["foundation"] = {"radius": 3.0 / length, "mass": 2000.0 / mass}
    other["excitation"] = {**scene["excitation"], "intensity": 0.02 / length**2}
    si, converted = _solve(scene, tmp_path), _solve(other, tmp_path)
    assert np.max(np.abs(si["foundation_rocking"].values)) > 0  # the soil moves
    for q in on_soil:
        assert _agree(np.asarray(si[q].values, float), _in_si(converted, q)) < TOLERANCE, q
    cf_units = pytest.importorskip("cf_units")
    for key in ("soil_sway_stiffness", "soil_sway_damping", "soil_rocking_stiffness",
                "soil_rocking_damping"):  # the springs applied, in the file's units
        unit = cf_units.Unit(converted.attrs[f"{key}_units"])
        value = unit.convert(np.asarray(converted.attrs[key]),
                             cf_units.Unit(si.attrs[f"{key}_units"]))
        np.testing.assert_allclose(value, si.attrs[key], rtol=1e-12, err_msg=key)


def test_an_unknown_unit_system_names_the_file_line_and_the_accepted(tmp_path):
    text = yaml.safe_dump({**SI, "units": "kN-mm-t"}, sort_keys=False)
    with pytest.raises(InputError) as caught:
        parse_scene(text, "scene.yaml", tmp_path)
    message = str(caught.value)
    line = 1 + text.splitlines().index("units: kN-mm-t")
    assert message.startswith(f"scene.yaml, line {line}, units: unknown unit system 'kN-mm-t'")
    assert "accepted: N-m-kg, kN-m-t, N-mm-t, kip-in-s, lbf-in-s" in message


def test_a_law_field_without_a_dimension_is_refused_in_another_system(tmp_path, monkeypatch):
    """A law (a plug-in, say) that declares no dimension for a field cannot be converted:
    refused naming the field, never read as SI."""
    from pframe.laws import get_law

    monkeypatch.setattr(get_law("material", "elastic"), "dimensions", {})
    text = yaml.safe_dump(written_in("kN-m-t"), sort_keys=False)
    with pytest.raises(InputError) as caught:
        parse_scene(text, "scene.yaml", tmp_path)
    message = str(caught.value)
    assert "buildings[1].story.stiffness: cannot convert this value from kN-m-t to SI" \
        in message
    assert "the dimension of field 'stiffness' of material 'elastic' is unknown" in message
    parse_scene(yaml.safe_dump(SI), "scene.yaml", tmp_path)  # SI needs no dimension


def test_defaults_keep_their_si_meaning(tmp_path):
    """A default is SI: applied after the conversion (a dashpot's linear_below 1e-5 m/s is
    1e-2 mm/s in N-mm-t)."""
    si = parse_scene(yaml.safe_dump(SI), "s.yaml", tmp_path).expanded
    mm = parse_scene(yaml.safe_dump(written_in("N-mm-t")), "s.yaml", tmp_path).expanded
    assert np.allclose(mm.links[0].packed, si.links[0].packed, rtol=1e-15, atol=0)
    assert mm.links[0].packed[2] == si.links[0].packed[2] == 1e-5


def test_a_validated_scene_is_in_si_and_says_so(tmp_path):
    loaded = parse_scene(yaml.safe_dump(written_in("kN-m-t")), "s.yaml", tmp_path)
    assert loaded.scene.units == "N-m-kg" and loaded.system.name == "kN-m-t"
    assert loaded.scene.buildings[0].mass == 250.0  # kg: the kernel's units
    assert loaded.given["units"] == "kN-m-t" and loaded.given["buildings"][0]["mass"] == 0.25
    assert math.isclose(loaded.scene.contacts[0].stiffness, 1.0e9, rel_tol=1e-15)


def test_output_si_asks_for_an_si_file(tmp_path):
    data = written_in("kN-m-t")
    data["analysis"] = {**data["analysis"], "duration": 0.01}
    ds = _solve({**data, "output": {"units": "SI"}}, tmp_path)
    assert ds.attrs["units_system"] == "N-m-kg" and ds["story_force"].attrs["units"] == "N"


# ---------------------------------------------------------------------------------------------
# every number has a dimension
# ---------------------------------------------------------------------------------------------

def _numeric_paths(cls, path=(), out=None) -> list:
    """Every path to a number in a scene's data (0 for a list index, 'A/1' for a mapping
    key), outside the recorders (kept as they are), law parameters included."""
    from test_scale_fields import _models, _numeric

    out = [] if out is None else out
    for name, field in cls.model_fields.items():
        if name == "recorders":
            continue
        here = path + (name,)
        annotation = field.annotation
        if _numeric(annotation):
            out.append(here + (("A/1",) if "dict" in str(annotation) else ()))
        listed = "list" in str(annotation) or "dict" in str(annotation)
        for model in _models(annotation):
            _numeric_paths(model, here + ((0,) if listed else ()), out)
    return out


def _without_dimension(cls) -> list:
    """The numeric paths of scene class ``cls`` a conversion of units cannot convert."""
    from test_scale_fields import _is_law_parameter

    from pframe.nondim.scene_units import unit_field_dimension

    return [p for p in _numeric_paths(cls)
            if not _is_law_parameter(p) and unit_field_dimension(p) is None]


def test_every_number_of_a_scene_has_a_dimension_to_convert():
    """Soil, stochastic motions, supports, coherency, plan geometry: every field."""
    from pframe.model.scene import scene_class

    paths = _numeric_paths(scene_class())
    for reached in [("buildings", 0, "soil", "foundation", "rotational_inertia"),
                    ("excitation", "intensity"), ("supports", 0, "excitation", "pga")]:
        assert reached in paths  # the walk reaches them
    assert not _without_dimension(scene_class())


def test_a_new_field_without_a_dimension_fails_the_check():
    from pydantic import create_model

    from pframe.model.scene import scene_class

    grown = create_model("Grown", __base__=scene_class(), crane_load=(float, 0.0))
    assert _without_dimension(grown) == [("crane_load",)]


def test_every_law_parameter_has_a_dimension_to_convert():
    """Every numeric parameter of every built-in law has a declared dimension, or one its
    law gives for its other fields (``dimensions_given``) in each of the law's examples."""
    from pframe.laws.registry import builtin_laws
    from pframe.nondim.fields import _numeric, field_dimension

    for kind in ("contact", "material"):
        for law in builtin_laws(kind):
            numeric = [n for n, f in law.Params.model_fields.items() if _numeric(f.annotation)]
            for example in law.examples:
                for name in numeric:
                    field_dimension(law, name, example)  # raises, naming law and field


def test_bouc_wen_gamma_and_beta_are_converted_for_their_n(tmp_path):
    """gamma and beta in m^-n: in N-mm-t they are in mm^-n."""
    story = {"material": "bouc_wen", "alpha": 0.1, "ko": 2.0e5, "n": 1.5, "gamma": 4000.0,
             "beta": 4000.0}
    si = {"buildings": [{"name": "A", "floors": 1, "mass": 250.0, "story": story}],
          "analysis": {"dt": 0.01, "duration": 0.1}}
    mm = copy.deepcopy(si)
    mm["units"] = "N-mm-t"
    mm["buildings"][0]["mass"] = 0.25
    mm["buildings"][0]["story"] |= {"ko": 200.0, "gamma": 4000.0 * 1e-3**1.5,
                                    "beta": 4000.0 * 1e-3**1.5}
    a = parse_scene(yaml.safe_dump(si), "a.yaml", tmp_path).expanded.stories[0].packed
    b = parse_scene(yaml.safe_dump(mm), "b.yaml", tmp_path).expanded.stories[0].packed
    np.testing.assert_allclose(b, a, rtol=1e-14, atol=0)


# ---------------------------------------------------------------------------------------------
# the commands around a run
# ---------------------------------------------------------------------------------------------

def _written(tmp_path, name: str, scene: dict = SI) -> str:
    path = tmp_path / f"{name}.yaml"
    path.write_text(yaml.safe_dump(written_in(name, scene), sort_keys=False), encoding="utf-8")
    return str(path)


def test_expand_writes_a_scene_of_another_system_in_si(tmp_path, capsys):
    from pframe.cli import main

    path = _written(tmp_path, "kip-in-s")
    assert main(["expand", path, "-o", str(tmp_path / "si.yaml")]) == 0
    text = (tmp_path / "si.yaml").read_text(encoding="utf-8")
    assert "(units: kip-in-s) to SI" in text and "\nunits:" not in text
    expanded = parse_scene(text, "si.yaml", tmp_path).expanded
    original = parse_scene(yaml.safe_dump(SI), "o.yaml", tmp_path).expanded
    np.testing.assert_allclose(expanded.masses, original.masses, rtol=1e-14, atol=0)
    for a, b in zip(expanded.contacts, original.contacts):
        np.testing.assert_allclose(a.packed, b.packed, rtol=1e-14, atol=0)
    capsys.readouterr()


def test_pi_prints_the_governing_variables_in_the_scenes_units(tmp_path, capsys):
    """The Pi numbers are the same in any system; the variables are printed in its units."""
    from pframe.cli import main

    scene = {k: v for k, v in SI.items() if k not in ("links", "initial_conditions")}
    scene["contacts"] = scene["contacts"][:1]  # pi: one contact law
    outputs = {}
    for name in ("N-m-kg", "kN-m-t"):
        assert main(["pi", _written(tmp_path, name, scene)]) == 0
        outputs[name] = capsys.readouterr().out
    si, kn = (outputs[n].splitlines() for n in ("N-m-kg", "kN-m-t"))
    groups = [line for line in si if line.startswith("  Pi_")]
    assert groups and groups == [line for line in kn if line.startswith("  Pi_")]
    assert any(line.split()[:3] == ["m_a", "0.25", "t"] for line in kn)
    assert any(line.split()[:3] == ["K_a", "200", "kN/m"] for line in kn)


def test_a_pi_form_scene_takes_no_units(tmp_path):
    from pframe.reader import load_scene

    text = (REPO / "models" / "hust-4x3-pi.yaml").read_text(encoding="utf-8")
    (tmp_path / "pi.yaml").write_text(text + "units: kN-m-t\n", encoding="utf-8")
    with pytest.raises(InputError, match=r"units: a Pi-form scene is written in Pi numbers"):
        load_scene(tmp_path / "pi.yaml")


def test_validate_names_the_system(tmp_path, capsys):
    from pframe.cli import main

    assert main(["validate", _written(tmp_path, "N-mm-t")]) == 0
    assert "  units: N-mm-t (force N, length mm, mass t (1000 kg), time s)" in \
        capsys.readouterr().out


@pytest.mark.slow
@pytest.mark.parametrize("command", [["gap"], ["plot", "--dimensionless"]])
def test_what_reads_si_only_refuses_another_system(tmp_path, capsys, command):
    """A gap audit's code rules and suites are SI: refused, naming the file and units."""
    from pframe.cli import main

    path = _written(tmp_path, "kN-m-t")
    if command[0] == "plot":
        data = written_in("kN-m-t")
        data["analysis"] = {**data["analysis"], "duration": 0.01}
        (tmp_path / "short.yaml").write_text(yaml.safe_dump(data), encoding="utf-8")
        assert main(["solve", str(tmp_path / "short.yaml"), "-q", "-o",
                     str(tmp_path / "short.nc")]) == 0
        path = str(tmp_path / "short.nc")
    out = tmp_path / ("out.png" if command[0] == "plot" else "out.nc")
    assert main([command[0], path, *command[1:], "-o", str(out)]) == 2
    err = capsys.readouterr().err
    assert "kN-m-t" in err and "units" in err and "Traceback" not in err
    assert not out.exists()


@pytest.mark.slow
def test_the_summary_of_a_file_in_mm_is_the_si_files_converted(tmp_path, capsys):
    """Ductility, residual drift, hysteretic energy and the Park-Ang index mix the file's
    histories with the scene's yield and ultimate drifts: in the file's units, the same; so
    are the impacts."""
    from pframe.tables import summary

    scene = copy.deepcopy(SI)
    scene["buildings"][0]["park_ang"] = {"ultimate_drift": 0.05, "beta": 0.1}
    tables = {}
    for name in ("N-m-kg", "N-mm-t"):
        data = written_in(name, scene)
        data["buildings"][0]["park_ang"]["ultimate_drift"] /= SYSTEMS[name][1]
        tables[name] = summary(_solve(data, tmp_path))
    si, mm = tables["N-m-kg"], tables["N-mm-t"]
    parts = ("story", "impact")
    rows = si[si.part.isin(parts)]
    assert {"Park-Ang damage index", "approach velocity"} <= set(rows.quantity)
    cf_units = pytest.importorskip("cf_units")
    for (_, a), (_, b) in zip(rows.iterrows(), mm[mm.part.isin(parts)].iterrows()):
        assert (a["name"], a["quantity"]) == (b["name"], b["quantity"])
        scale = cf_units.Unit(b["units"] or "1").convert(1.0, cf_units.Unit(a["units"] or "1"))
        assert b["value"] * scale == pytest.approx(a["value"], rel=1e-9, abs=1e-12), \
            a["quantity"]


@pytest.mark.slow
@pytest.mark.filterwarnings("ignore:.*the OpenSees script's model is not pframe's")
def test_the_opensees_script_is_in_si_and_says_so(tmp_path):
    import pframe

    scene = {k: v for k, v in SI.items() if k != "initial_conditions"}  # OpenSees: from rest
    si = pframe.to_opensees(parse_scene(yaml.safe_dump(scene), "s.yaml", tmp_path))
    other = pframe.to_opensees(parse_scene(yaml.safe_dump(written_in("kip-in-s", scene)),
                                           "s.yaml", tmp_path))
    assert "Its numbers are in SI units (N, m, kg, s)." in si
    assert "the scene, written in kip-in-s, converted." in other
    namespaces = []
    for text in (si, other):
        namespace = {"__name__": "units_script"}
        exec(compile(text, "script.py", "exec"), namespace)  # the data block only
        namespaces.append(namespace)
    np.testing.assert_allclose(namespaces[1]["MASSES"], namespaces[0]["MASSES"], rtol=1e-14)
    np.testing.assert_allclose(namespaces[1]["CONTACT_GAPS"], namespaces[0]["CONTACT_GAPS"],
                               rtol=1e-14)


@pytest.mark.slow
def test_a_sweep_of_a_scene_in_mm_is_the_si_sweep_in_mm(tmp_path, capsys):
    """The swept values are in the scene's units, and so are the sweep file's responses."""
    from pframe.cli import main

    files = {}
    for name, gaps in (("N-m-kg", [0.002, 0.004]), ("N-mm-t", [2.0, 4.0])):
        base = _written(tmp_path, name)
        sweep = tmp_path / f"sweep-{name}.yaml"
        sweep.write_text(yaml.safe_dump({
            "base": base, "axes": [{"name": "gap", "path": "contacts.0.gap", "values": gaps}],
            "keep": {"envelopes": ["peak_displacement", "peak_contact_force",
                                   "impact_count"]}}), encoding="utf-8")
        files[name] = tmp_path / f"sweep-{name}.nc"
        assert main(["sweep", str(sweep), "-o", str(files[name])]) == 0
    capsys.readouterr()
    si, mm = (xr.open_dataset(files[n]) for n in ("N-m-kg", "N-mm-t"))
    assert mm.attrs["units_system"] == "N-mm-t"
    assert mm["peak_displacement"].attrs["units"] == "mm"
    assert _agree(si["peak_displacement"].values, _in_si(mm, "peak_displacement")) < TOLERANCE
    assert _agree(si["peak_contact_force"].values, _in_si(mm, "peak_contact_force")) < TOLERANCE
    np.testing.assert_array_equal(si["impact_count"].values, mm["impact_count"].values)
    assert si["impact_count"].values.sum() > 0


def test_a_bad_number_is_quoted_as_written(tmp_path):
    """The validation's message quotes the scene's number (-0.25 t), not its SI value."""
    data = written_in("kN-m-t")
    data["buildings"][0]["mass"] = -0.25
    with pytest.raises(InputError) as caught:
        parse_scene(yaml.safe_dump(data, sort_keys=False), "scene.yaml", tmp_path)
    assert "buildings[0].mass: Input should be greater than 0 (got -0.25)" in str(caught.value)


@pytest.mark.slow
def test_figures_label_their_axes_in_the_files_units(tmp_path):
    import pframe
    from pframe.plot.figure import figures

    data = written_in("N-mm-t")
    data["analysis"] = {**data["analysis"], "duration": 0.3}
    data["recorders"] = [{"kind": "history", "quantities": ["displacement", "velocity",
                                                            "acceleration", "story_drift",
                                                            "story_force", "contact_force"]}]
    (tmp_path / "mm.yaml").write_text(yaml.safe_dump(data), encoding="utf-8")
    pframe.solve(tmp_path / "mm.yaml", output=tmp_path / "mm.nc", progress=False)
    axes = [ax for fig in figures(tmp_path / "mm.nc").values() for ax in fig.axes]
    labels = {ax.get_ylabel() for ax in axes} | {ax.get_xlabel() for ax in axes}
    assert any(label.endswith("(mm)") for label in labels), labels
    assert any(label.endswith("(N)") for label in labels), labels
    assert not any(label.endswith("(m)") for label in labels), labels


@pytest.mark.slow
def test_a_dimensionless_file_is_the_same_in_any_system(tmp_path):
    """Pi numbers have no units: output.units dimensionless gives the SI scene's file."""
    files = {}
    for name in ("N-m-kg", "kip-in-s"):
        data = written_in(name)
        data["analysis"] = {**data["analysis"], "duration": 0.1}
        data["output"] = {"units": "dimensionless"}
        files[name] = _solve(data, tmp_path)
    si, kip = files["N-m-kg"], files["kip-in-s"]
    assert kip.attrs["units_system"] == "dimensionless"
    for q in QUANTITIES:
        assert kip[q].attrs["units"] == "1", q
        assert _agree(si[q].values, kip[q].values) < TOLERANCE, q
    assert kip.attrs["scale_m_b"] == pytest.approx(si.attrs["scale_m_b"], rel=1e-14)


def test_a_number_too_large_once_in_si_says_it_is_quoted_in_si(tmp_path):
    """5e99 kip s^2/in is 8.8e104 kg, beyond the 1e100 pframe computes with: the message
    quotes the SI number and says so."""
    data = written_in("kip-in-s")
    data["buildings"][0]["mass"] = 5.0e99
    with pytest.raises(InputError) as caught:
        parse_scene(yaml.safe_dump(data, sort_keys=False), "scene.yaml", tmp_path)
    message = str(caught.value)
    assert "buildings[0].mass: 8.756e+104 is larger than the 1e+100" in message
    assert message.endswith("(the numbers quoted are the scene's in SI: N, m, kg)")


def test_a_law_named_by_a_list_is_refused_by_the_validation(tmp_path):
    """Found by the generated hostile input: ``material: [1.0, 2.0]`` in a scene in kN-m-t
    was looked up as a law's name (a TypeError); it is the validation's error now."""
    data = written_in("kN-m-t")
    data["buildings"][0]["story"]["material"] = [1.0, 2.0]
    with pytest.raises(InputError, match=r"buildings\[0\]\.story"):
        parse_scene(yaml.safe_dump(data, sort_keys=False), "scene.yaml", tmp_path)
