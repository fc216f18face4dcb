"""The Python API (docs/python.md): scenes from objects, results as Datasets equal to the files
of the command line, YAML round trips, results that reproduce their runs."""

from __future__ import annotations

import math
import re
import subprocess
import sys
import warnings
from pathlib import Path

import numpy as np
import pytest
import yaml
from conftest import assert_names, runnable_model

import pframe

ROOT = Path(__file__).resolve().parents[1]
MODELS = ROOT / "models"
RECORDS = ROOT.parent / "shared" / "records"
#: attributes that say when and how a file was made, not what it holds
RUN_FACTS = ("date_created", "history", "solve_seconds", "source")
LABELS = ["node_name", "story_name", "contact_name"]


def _pframe() -> list[str]:
    script = Path(sys.executable).with_name("pframe")
    return [str(script)] if script.exists() else [sys.executable, "-m", "pframe.cli"]


def _as_in_the_file(ds):
    """A Dataset of pframe as xarray reads its file: without the names as coordinate values
    of their dimensions and the indexes on the labels (``pframe.indexed``)."""
    ds = ds.drop_vars([d for d in ds.dims if d in ds.coords and ds[d].dtype == object])
    return ds.drop_indexes([n for n in ds.indexes if n.endswith("_name")])


def _without_run_facts(ds):
    ds = ds.copy()
    for key in RUN_FACTS:
        ds.attrs.pop(key, None)
    return ds


def paper_scene():
    """Wu et al. (2021), eq. (14), dimensional: models/wu2021-eq14.yaml built from objects."""
    w_p, a_p = 2 * math.pi, 9.81
    l_e = a_p / w_p**2
    contacts = [pframe.Contact(name=f"floor-{i}", nodes=(f"A/{i}", f"B/{i}"), gap=0.5 * l_e,
                               law="improved_kelvin", frequency_ratio=65, restitution=0.4,
                               calibration="published")
                for i in (1, 2, 3)]
    return pframe.Scene(
        title="Wu et al. 2021, eq. 14 (improved Kelvin), dimensional",
        buildings=[
            pframe.Building(name="A", floors=3, mass=250.0, story=pframe.StoryProperties(
                material="bilinear", stiffness=5 * 1000.0 * w_p**2, yield_drift=0.1 * l_e,
                alpha=0.1)),
            pframe.Building(name="B", floors=3, mass=1000.0, story=pframe.StoryProperties(
                material="bilinear", stiffness=50 * 1000.0 * w_p**2, yield_drift=0.06 * l_e,
                alpha=0.1)),
        ],
        contacts=contacts,
        damping=pframe.Rayleigh(ratio=0.05, modes=(1, 2), stiffness="current"),
        excitation=pframe.Sine(amplitude=a_p, frequency=w_p),
        analysis=pframe.Analysis(integrator=pframe.Newmark(gamma=0.5, beta=0.25),
                                 dt=0.001 / w_p, duration=50 / w_p),
        recorders=[
            pframe.History(quantities=["displacement", "velocity", "story_force",
                                       "story_drift", "contact_force"]),
            pframe.Envelope(quantities=["displacement", "story_drift", "contact_force"]),
        ],
    )


@pytest.fixture(scope="module")
def cli_file(tmp_path_factory) -> Path:
    out = tmp_path_factory.mktemp("cli") / "eq14.nc"
    done = subprocess.run(_pframe() + ["solve", str(MODELS / "wu2021-eq14.yaml"), "-o", str(out),
                                       "-q"], capture_output=True, text=True, timeout=600)
    assert done.returncode == 0, done.stderr
    return out


def test_import_is_light():
    """``import pframe`` loads neither the kernel nor numpy, xarray or matplotlib."""
    code = ("import sys, pframe; heavy = [m for m in ('numpy', 'numba', 'xarray', 'h5py', "
            "'matplotlib', 'pframe.kernel') if m in sys.modules]; print(heavy)")
    done = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True)
    assert done.stdout.strip() == "[]", done.stdout + done.stderr


def test_the_api_is_listed_once():
    assert_names(pframe.__all__, {"InputError", "EnvironmentFailure", "PframeError",
                                  "__version__", *pframe._API}, "pframe.__all__")
    for name in pframe.__all__:
        assert getattr(pframe, name) is not None


def test_scene_from_objects_is_the_paper_scene():
    assert paper_scene() == pframe.load(MODELS / "wu2021-eq14.yaml")


@pytest.mark.slow
def test_solve_equals_the_cli_file(cli_file):
    """The paper's scene built without YAML gives the file ``pframe solve`` writes: every
    variable, coordinate and attribute, value for value (the in-memory Dataset differs only
    by its name indexes and the facts of when and how it was made)."""
    import xarray as xr

    ds = pframe.solve(paper_scene(), progress=False)
    with xr.open_dataset(cli_file, engine="h5netcdf") as cli:
        cli = _without_run_facts(cli.load())
    mine = _without_run_facts(_as_in_the_file(ds))
    # the scene text differs (the file's comments): the scene it describes does not
    assert pframe.load(yaml.safe_load(mine.attrs.pop("input_yaml"))) == paper_scene()
    cli.attrs.pop("input_yaml")
    xr.testing.assert_identical(cli, mine)
    # and the numbers are the paper's run: eight impacts at each level (docs/validation.md)
    assert ds.impact_count.values.tolist() == [8, 8, 8]
    assert ds.attrs["complete"] == 1 and ds.attrs["energy_balance_error"] < 1e-9
    # a name selects, as in the docs
    top = ds.displacement.sel(node_name="A/3")
    assert top.dims == ("t",) and float(abs(top).max()) == pytest.approx(
        float(ds.peak_displacement.sel(node_name="A/3")), rel=0, abs=0)


@pytest.mark.slow
def test_names_are_the_coordinates_of_their_dimensions(tmp_path):
    """pandas, xarray's legends and ``.sel`` show and take the names of nodes, storeys and
    contacts (in memory and read back from the file), and the file keeps labels only."""
    import h5py
    import matplotlib

    matplotlib.use("Agg")
    nodes = ["A/1", "A/2", "A/3", "B/1", "B/2", "B/3"]
    out = tmp_path / "linear.nc"
    memory = pframe.solve(MODELS / "wu2021-eq14-linear.yaml", progress=False)
    with pframe.solve(MODELS / "wu2021-eq14-linear.yaml", output=out, progress=False) as read:
        for ds in (memory, read):
            series = ds.peak_displacement.to_series()
            assert series.index.name == "node" and series.index.tolist() == nodes
            assert series["A/3"] == float(ds.peak_displacement.isel(node=2))
            frame = ds[["peak_contact_force", "impact_count"]].to_dataframe()
            assert frame.index.tolist() == ["floor-1", "floor-2", "floor-3"]
            assert ds.story_drift.sel(story="B/2").equals(ds.story_drift.isel(story=4))
            assert ds.displacement.sel(node_name="A/3").equals(ds.displacement.sel(node="A/3"))
            lines = ds.displacement.isel(t=slice(0, 5)).plot.line(x="t")
            legend = lines[0].axes.get_legend()
            assert [text.get_text() for text in legend.get_texts()] == nodes
            matplotlib.pyplot.close("all")
    with h5py.File(out, "r") as f:  # CF: no string coordinate variables
        assert "node" not in f or f["node"].dtype.kind == "f"
        assert b"".join(f["node_name"][2]).decode() == "A/3"


@pytest.mark.slow
def test_open_equals_solve_to_file(tmp_path, cli_file):
    import xarray as xr

    out = tmp_path / "api.nc"
    with pframe.solve(MODELS / "wu2021-eq14.yaml", output=out, progress=False) as ds:
        with pframe.open(cli_file) as cli:
            xr.testing.assert_identical(_without_run_facts(ds.load()),
                                        _without_run_facts(cli.load()))
    with pytest.raises(pframe.InputError, match="exists"):
        pframe.solve(MODELS / "wu2021-eq14.yaml", output=out)


@pytest.mark.parametrize("model", sorted(p.name for p in MODELS.glob("*.yaml")))
def test_yaml_round_trip(model, tmp_path):
    """YAML -> objects -> YAML -> objects: equal scenes, and the same text the second time."""
    path = runnable_model(MODELS / model, tmp_path)  # a model naming a record: beside it
    scene = pframe.load(path)
    text = scene.to_yaml()
    again = pframe.load(yaml.safe_load(text), base_dir=path.parent)
    assert again == scene
    assert again.to_yaml() == text


def test_round_trip_keeps_tags_left_at_defaults():
    """A tag left at its default in Python (``kind``, ``type``) is still written: without it
    the YAML would read as another kind of object."""
    scene = paper_scene().model_copy(update={
        "analysis": pframe.Analysis(dt=1e-3, duration=1.0, integrator=pframe.HHT(alpha=0.1))})
    data = yaml.safe_load(scene.to_yaml())
    assert data["analysis"]["integrator"] == {"type": "hht", "alpha": 0.1}
    assert data["excitation"]["kind"] == "sine"
    assert pframe.load(data) == scene


def _calls_during(watched: set, work) -> dict:
    """How often each (module, function) of ``watched`` is entered while ``work()`` runs."""
    counts = dict.fromkeys(watched, 0)

    def profile(frame, event, arg):
        if event == "call":
            key = (frame.f_globals.get("__name__"), frame.f_code.co_name)
            if key in counts:
                counts[key] += 1

    sys.setprofile(profile)
    try:
        work()
    finally:
        sys.setprofile(None)
    return counts


@pytest.mark.parametrize("given", ["objects", "dict"])
def test_a_python_scene_flows_one_way(given, tmp_path):
    """pframe.solve of a scene built in Python validates its data once and expands it once,
    writes no YAML text to read it again (the text is written once, for the file's
    input_yaml), finds its reference scales once (a dimensionless scene used to find them
    three times), and opens the file it wrote without checking it as one of unknown origin."""
    scene = paper_scene().model_copy(update={
        "analysis": pframe.Analysis(dt=5e-4, duration=0.05),
        "output": pframe.Output(units="dimensionless")})
    source = scene if given == "objects" else yaml.safe_load(scene.to_yaml())
    out = tmp_path / "run.nc"
    counts = _calls_during({("pframe.model.load", "validated"), ("pframe.model.expand", "expand"),
                            ("pframe.yamltext", "compose"), ("yaml", "dump_all"),
                            ("pframe.nondim.reference", "reference_scales"),
                            ("pframe.record.check", "check_file")},
                           lambda: pframe.solve(source, output=out).close())
    assert counts == {("pframe.model.load", "validated"): 1, ("pframe.model.expand", "expand"): 1,
                      ("pframe.yamltext", "compose"): 0, ("yaml", "dump_all"): 1,
                      ("pframe.nondim.reference", "reference_scales"): 1,
                      ("pframe.record.check", "check_file"): 0}
    with pframe.open(out) as ds:
        assert ds.attrs["input_yaml"] == scene.to_yaml()
        assert ds.attrs["source"] == ("pframe.Scene" if given == "objects" else "pframe.load(dict)")
    assert pframe.load(out) == scene


def test_a_scene_objects_problem_names_its_field():
    """A problem found when a scene object is used names the field, as a dict's does (not a
    line of a YAML text the user never saw)."""
    scene = paper_scene()
    bad = scene.model_copy(update={"contacts": [pframe.Contact(
        law="linear", nodes=("A/3", "C/3"), gap=0.05, stiffness=1e7)]})
    with pytest.raises(pframe.InputError, match=r"^pframe\.Scene, contacts\[0\]\.nodes\[1\]: "
                       "no node named 'C/3'"):
        pframe.load(bad)
    huge = scene.model_copy(update={"buildings": [
        scene.buildings[0].model_copy(update={"mass": 1e200}), scene.buildings[1]]})
    with pytest.raises(pframe.InputError, match=r"^pframe\.Scene, buildings\[0\]\.mass: 1e\+200 "
                       "is larger than"):
        pframe.load(huge)


def test_bad_objects_raise_input_error():
    with pytest.raises(pframe.InputError, match="restitution"):
        pframe.Contact(law="kelvin", nodes=("A/1", "B/1"), gap=0.0, stiffness=1e6,
                       restitution=1.5)
    with pytest.raises(pframe.InputError, match=r"pframe\.load\(dict\), buildings\[0\]\.mass"):
        pframe.load({"buildings": [{"name": "A", "floors": 2, "mass": -1.0,
                                    "story": {"material": "elastic", "stiffness": 1e6}}],
                     "analysis": {"dt": 0.01, "duration": 1.0}})


def test_incomplete_run_warns_and_returns_what_was_computed():
    """A run that cannot go on (Newton asked for a tolerance below round-off cannot converge
    once a storey yields) returns its computed states, marked incomplete, with a warning."""
    scene = pframe.load({
        "buildings": [{"name": "A", "floors": 1, "mass": 1.0,
                       "story": {"material": "bilinear", "stiffness": 100.0,
                                 "yield_drift": 0.001, "alpha": 0.1}}],
        "excitation": {"kind": "sine", "amplitude": 10.0, "frequency": 3.0},
        "analysis": {"dt": 0.01, "duration": 5.0, "newton": {"tolerance": 1.0e-18}},
        "recorders": [{"kind": "history", "quantities": ["displacement"]}],
    })
    with pytest.warns(pframe.IncompleteRun, match="stopped early"):
        ds = pframe.solve(scene, progress=False)
    assert ds.attrs["complete"] == 0
    assert ds.sizes["t"] == ds.attrs["steps_completed"] + 1 < 501


@pytest.mark.slow
@pytest.mark.skipif(not RECORDS.is_dir(), reason=f"the shared PEER records ({RECORDS}) are absent")
def test_record_run_reproduces_from_the_file_alone(tmp_path):
    """A record-driven result holds the record's text and checksum: loading the result file
    (the scene folder and record gone) rebuilds the scene and its run, bit for bit."""
    import hashlib
    import shutil

    folder = tmp_path / "project"
    (folder / "records").mkdir(parents=True)
    shutil.copy(RECORDS / "elCentro.AT2", folder / "records" / "elCentro.AT2")
    scene_file = folder / "scene.yaml"
    scene_file.write_text(yaml.safe_dump({
        "buildings": [{"name": "A", "floors": 2, "mass": 1000.0,
                       "story": {"material": "bilinear", "stiffness": 4e5,
                                 "yield_drift": 0.01, "alpha": 0.1}},
                      {"name": "B", "floors": 2, "mass": 2000.0,
                       "story": {"material": "elastic", "stiffness": 2e6}}],
        "contacts": [{"nodes": ["A/2", "B/2"], "gap": 0.01, "law": "linear",
                      "stiffness": 1e7}],
        "excitation": {"kind": "record", "file": "records/elCentro.AT2"},
        "analysis": {"dt": 0.002, "duration": 10.0},
        "recorders": [{"kind": "history", "quantities": ["displacement", "contact_force"]}],
    }, sort_keys=False))
    out = tmp_path / "run.nc"
    first = pframe.solve(scene_file, output=out, progress=False).load()
    digest = hashlib.sha256((RECORDS / "elCentro.AT2").read_bytes()).hexdigest()
    assert first.attrs["record_sha256"] == digest
    assert first.attrs["record_read_as"].startswith("PEER NGA .AT2 in g, 1559 points, "
                                                     "dt = 0.02 s")
    shutil.rmtree(folder)
    again = pframe.solve(pframe.load(out), progress=False)
    np.testing.assert_array_equal(again.displacement.values, first.displacement.values)
    np.testing.assert_array_equal(again.contact_force.values, first.contact_force.values)
    assert int(first.impact_count.sum()) > 0


def test_copies_and_variants_keep_their_record(tmp_path, monkeypatch):
    """A loaded scene copied (model_copy, with or without update) or varied (reader.variant)
    reads the record it was loaded with, from any current folder, not a same-named file
    there (a decoy: another earthquake under the same name)."""
    import hashlib
    import shutil

    from conftest import record_file

    from pframe.api import loaded_scene
    from pframe.reader import variant

    # the decoy is another earthquake (Borrego Mountain 1968) under the real one's name
    real, decoy = record_file("elCentro.AT2"), record_file("A-ELC180.AT2")
    project, elsewhere = tmp_path / "project", tmp_path / "elsewhere"
    for folder, record in ((project, real), (elsewhere, decoy)):
        (folder / "records").mkdir(parents=True)
        shutil.copy(record, folder / "records" / "elCentro.AT2")
    (project / "scene.yaml").write_text(yaml.safe_dump({
        "buildings": [{"name": "A", "floors": 2, "mass": 1000.0,
                       "story": {"material": "bilinear", "stiffness": 4e5,
                                 "yield_drift": 0.01, "alpha": 0.1}},
                      {"name": "B", "floors": 2, "mass": 2000.0,
                       "story": {"material": "elastic", "stiffness": 2e6}}],
        "contacts": [{"nodes": ["A/2", "B/2"], "gap": 0.01, "law": "linear",
                      "stiffness": 1e7}],
        "excitation": {"kind": "record", "file": "records/elCentro.AT2"},
        "analysis": {"dt": 0.002, "duration": 8.0},
    }, sort_keys=False))
    digest = hashlib.sha256(real.read_bytes()).hexdigest()
    monkeypatch.chdir(tmp_path)
    scene = pframe.load("project/scene.yaml")  # a relative path, then another cwd
    loaded = loaded_scene("project/scene.yaml")
    reference = pframe.solve(scene, progress=False)
    monkeypatch.chdir(elsewhere)
    copies = {
        "model_copy": scene.model_copy(),
        "model_copy(update=title)": scene.model_copy(update={"title": "a copy"}),
        "model_copy(deep)": scene.model_copy(deep=True),
        "model_copy(update=excitation)": scene.model_copy(update={
            "excitation": scene.excitation.model_copy(update={"scale": 1.0})}),
        "variant": variant(loaded, lambda data: data.update(title="a variant")),
    }
    for how, copy in copies.items():
        ds = pframe.solve(copy, progress=False)
        assert ds.attrs["record_sha256"] == digest, how
        np.testing.assert_array_equal(ds.peak_displacement.values,
                                      reference.peak_displacement.values, err_msg=how)
    assert scene.model_copy() == scene  # the folder is no part of the scene's value
    assert scene.excitation == pframe.Record(file="records/elCentro.AT2")


@pytest.mark.slow
def test_to_opensees_script_runs_and_agrees(tmp_path):
    """The script of ``pframe.to_opensees(scene)`` runs on its own and gives pframe's
    histories."""
    pytest.importorskip("openseespy.opensees", reason="OpenSeesPy (peers extra) is absent",
                        exc_type=ImportError)
    scene = pframe.load(MODELS / "wu2021-eq14-linear.yaml")
    script = tmp_path / "model_ops.py"
    script.write_text(pframe.to_opensees(scene).replace(
        "OUT_NPZ = None", f"OUT_NPZ = {str(tmp_path / 'o.npz')!r}"))
    done = subprocess.run([sys.executable, str(script)], capture_output=True, text=True,
                          timeout=600, cwd=tmp_path)
    assert done.returncode == 0, done.stderr
    from pframe.api import loaded_scene
    from pframe.assemble import assemble

    dof = assemble(loaded_scene(scene).expanded).node_dof  # the script's columns are DOFs
    peer = np.load(tmp_path / "o.npz")
    ds = pframe.solve(scene, progress=False)
    u = ds.displacement.values
    assert np.max(np.abs(peer["displacement"][:, dof] - u)) <= 1e-9 * np.max(np.abs(u))


def test_opensees_refuses_laws_it_cannot_model():
    """The paper's scene with Kelvin contacts: OpenSees has no twin of the law; the refusal
    names the contacts, the law and why."""
    import yaml

    data = yaml.safe_load((MODELS / "wu2021-eq14.yaml").read_text(encoding="utf-8"))
    for contact in data["contacts"]:
        contact["law"] = "kelvin"
    with pytest.raises(pframe.InputError, match=r"floor-1, floor-2, floor-3 \(kelvin\): "
                                                "OpenSees has no uniaxial material"):
        pframe.to_opensees(data, base_dir=MODELS)


def test_to_opensees_warns_where_its_model_is_not_pframes():
    """The paper's improved Kelvin contacts are OpenSees' Hertzdamp but for conditions
    (pframe.peers.twins): to_opensees warns of each, and the script says them."""
    with pytest.warns(UserWarning, match="the OpenSees script's model is not pframe's") as caught:
        text = pframe.to_opensees(pframe.load(MODELS / "wu2021-eq14.yaml"))
    messages = [str(w.message) for w in caught]
    assert len(messages) == 3 and all("improved_kelvin: OpenSees' Hertzdamp" in m
                                      for m in messages)
    assert "Where this model is not pframe's" in text and "energy-velocity floor" in text


@pytest.mark.slow
def test_sweep_returns_the_file_dataset(tmp_path):
    import xarray as xr

    definition = MODELS / "sweeps" / "wu2021-pi-d.yaml"
    ds = pframe.sweep(definition, progress=False, chunk=64)
    out = tmp_path / "sw.nc"
    done = subprocess.run(_pframe() + ["sweep", str(definition), "-o", str(out), "-q"],
                          capture_output=True, text=True, timeout=900)
    assert done.returncode == 0, done.stderr
    with xr.open_dataset(out, engine="h5netcdf") as cli:
        xr.testing.assert_identical(
            _without_run_facts(cli.load()),
            _without_run_facts(_as_in_the_file(ds)))
    assert ds.building_peak_displacement.dims == ("Pi_d", "building")
    assert ds.building_peak_displacement.to_series().unstack().columns.tolist() == ["A", "B"]


def test_progress_is_silent_when_not_interactive(capfd):
    pframe.solve(MODELS / "wu2021-eq14-linear.yaml")
    captured = capfd.readouterr()
    assert captured.err == "" and captured.out == ""


@pytest.mark.slow
def test_plot_takes_a_dataset_and_the_users_axes():
    matplotlib = pytest.importorskip("matplotlib", reason="the plot extra is absent")
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    ds = pframe.solve(MODELS / "wu2021-eq14.yaml", progress=False)
    fig, ax = plt.subplots()
    with plt.rc_context({"font.size": 20}):
        drawn = pframe.plot(ds, "contact_force", names="floor-3", units="kN", ax=ax)
        assert drawn is ax
        assert ax.get_ylabel() == "pounding force (kN)"
        (line,) = ax.get_lines()
        peak = float(ds.peak_contact_force.sel(contact_name="floor-3"))
        assert np.max(line.get_ydata()) == pytest.approx(peak / 1000.0, rel=1e-12)
        figure = pframe.plot(ds, level=3, units="engineering")
        sizes = {t.get_fontsize() for a in figure.axes for t in [a.title, a.xaxis.label]
                 if t.get_text()}
        assert min(sizes) > 12  # relative sizes follow the user's font.size (20 here)
    plt.close("all")
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        with pytest.raises(pframe.InputError, match="choose from A/1"):
            pframe.plot(ds, "displacement", names=["A/9"])


@pytest.mark.slow
def test_python_page_runs_as_a_notebook_would(tmp_path):
    """Every Python block of docs/python.md, run in order as one script (the way a notebook
    runs its cells): load, solve from a file and from objects, sweep, plot."""
    pytest.importorskip("matplotlib", reason="the plot extra is absent")
    page = (ROOT / "docs" / "python.md").read_text(encoding="utf-8")
    blocks = re.findall(r"^```python\n(.*?)^```", page, flags=re.S | re.M)
    assert len(blocks) >= 4
    script = tmp_path / "notebook.py"
    script.write_text("import matplotlib\nmatplotlib.use('Agg')\n" + "\n".join(blocks)
                      + "\nprint('done', sorted(ds.data_vars)[:2])\n", encoding="utf-8")
    (tmp_path / "models").symlink_to(MODELS)
    done = subprocess.run([sys.executable, str(script)], capture_output=True, text=True,
                          cwd=tmp_path, timeout=900)
    assert done.returncode == 0, done.stderr[-3000:]
    assert "done" in done.stdout
    assert (tmp_path / "eq14.nc").exists()  # ds.to_netcdf of the first block


def test_a_scene_prints_as_the_calls_that_build_it():
    """``repr`` of a scene: a line per building, contact and setting, public names only
    (``Contact``, not ``Contact_improved_kelvin``), which evaluates to an equal scene."""
    scene = pframe.load({
        "title": "two towers",
        "buildings": [{"name": "A", "floors": 3, "mass": 250.0,
                       "story": {"material": "bilinear", "stiffness": 2.0e5, "yield_drift": 0.025,
                                 "alpha": 0.1}},
                      {"name": "B", "floors": 2, "mass": [1000.0, 900.0],
                       "story": {"material": "elastic", "stiffness": 2.0e6}}],
        "contacts": [{"name": f"floor-{i}", "nodes": [f"A/{i}", f"B/{i}"], "gap": 0.125,
                      "law": "improved_kelvin", "frequency_ratio": 65, "restitution": 0.4,
                      "calibration": "published"} for i in (1, 2)],
        "excitation": {"kind": "sine", "amplitude": 9.81, "frequency": 6.25},
        "analysis": {"dt": 0.0005, "duration": 2.0},
    })
    text = repr(scene)
    lines = [line for line in text.splitlines() if not line.startswith("# ")]
    assert "Contact_" not in text and "Storeys(" not in text and str(scene) == text
    assert [line.strip()[:9] for line in lines if line.startswith("    ")] == [
        "Building(", "Building(", "Contact(l", "Contact(l"]
    assert len(lines) == 13 and max(map(len, lines)) < 160
    # then, as comments, what loading found: the periods of each building (A: 2 pi / w_r,
    # w_r = 2 sqrt(k / m) sin((2r - 1) pi / 14); B: its 2 x 2 eigenproblem)
    assert text.splitlines()[13:] == [
        "# building A: 3 floors, periods 0.499, 0.178, 0.123 s (fixed base, initial stiffness)",
        "# building B: 2 floors, periods 0.219, 0.0855 s (fixed base, initial stiffness)"]
    namespace = {name: getattr(pframe, name) for name in pframe._API}
    assert eval(text, namespace) == scene  # noqa: S307 - the test of a repr
    assert eval(repr(scene.contacts[1]), namespace) == scene.contacts[1]  # noqa: S307
    html = scene._repr_html_()
    assert html.count("<tr>") == 5 and "Contact(law=&#x27;improved_kelvin&#x27;" in html
    many = pframe.Building(name="C", floors=20, mass=[100.0 + i for i in range(20)],
                           story=pframe.StoryProperties(material="elastic", stiffness=1e6))
    assert "mass=[100, 101, 102, ... 15 more ..., 118, 119]" in repr(many)
