"""The ``pframe`` command: solve (complete and stopped-early runs), validate, schema --check.

The HDF5 file is read back with xarray (engine h5netcdf), as a user would. The scene has the
structure of models/wu2021-eq14.yaml (bilinear storeys, improved Kelvin contacts, the same
recorders), so it reuses that scene's compiled kernel.
"""

from __future__ import annotations

import re
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
import pytest
import xarray as xr

import pframe
from pframe.cli import main

REPO = Path(__file__).resolve().parents[1]
SCHEMA = REPO / "schemas" / "model.schema.json"

SCENE = """\
title: two 2-storey buildings pounding at the top
buildings:
  - name: A
    floors: 2
    mass: 1000.0
    story: {material: bilinear, stiffness: 4.0e5, yield_drift: 0.02, alpha: 0.1}
  - name: B
    floors: 2
    mass: 2000.0
    story: {material: bilinear, stiffness: 8.0e6, yield_drift: 0.03, alpha: 0.1}
contacts:
  - {name: top, nodes: [A/2, B/2], gap: 0.001, law: improved_kelvin, stiffness: 1.0e7,
     restitution: 0.5}
excitation: {kind: sine, amplitude: 3.0, frequency: 6.0}
analysis:
  dt: 0.001
  duration: 1.0
recorders:
  - kind: history
    quantities: [displacement, velocity, story_force, story_drift, contact_force]
  - kind: envelope
    quantities: [displacement, story_drift, contact_force]
"""
#: Newton cannot meet a tolerance below round-off: the run stops in its first step.
FAILING = SCENE.replace("  duration: 1.0\n", "  duration: 1.0\n  newton: {tolerance: 1.0e-18}\n")
NODES = ["A/1", "A/2", "B/1", "B/2"]
UNITS = {"displacement": "m", "velocity": "m/s", "story_force": "N", "story_drift": "m",
         "contact_force": "N"}
STATUS = re.compile(r"at t = ([0-9.e+-]+) s \(step (\d+)\) at (node|storey|contact) ([^\s;]+)")


@pytest.fixture
def scene_file(tmp_path):
    path = tmp_path / "scene.yaml"
    path.write_text(SCENE, encoding="utf-8")
    return path


@pytest.mark.slow
def test_solve_writes_a_netcdf_readable_file(tmp_path, scene_file, capsys):
    out = tmp_path / "result.h5"
    start = time.perf_counter()
    assert main(["solve", str(scene_file), "-o", str(out)]) == 0
    wall = time.perf_counter() - start
    captured = capsys.readouterr()
    assert captured.err == ""
    assert "status: completed" in captured.out and str(out) in captured.out
    with pframe.open(out) as ds:
        assert list(ds["node_name"].values) == NODES
        assert list(ds["story_name"].values) == NODES
        assert list(ds["contact_name"].values) == ["top"]
        assert ds.sizes["t"] == 1001
        np.testing.assert_allclose(ds["t"].values, np.arange(1001) * 0.001, rtol=1e-12)
        assert ds["t"].attrs["units"] == "s"
        for name, units in UNITS.items():
            dim = {"displacement": "node", "velocity": "node",
                   "contact_force": "contact"}.get(name, "story")
            assert ds[name].dims == ("t", dim)
            assert ds[name].attrs["units"] == units
            assert ds[name].attrs["long_name"]
            assert np.all(np.isfinite(ds[name].values))
        for name in ("displacement", "story_drift", "contact_force"):
            peak = ds[f"peak_{name}"]
            assert peak.dims == (ds[name].dims[1],)
            assert peak.attrs["units"] == UNITS[name]
            np.testing.assert_allclose(peak.values, np.abs(ds[name]).max("t").values,
                                       rtol=1e-14)
        assert ds["impact_count"].dims == ("contact",)
        assert int(ds["impact_count"].sel(contact_name="top")) >= 1
        assert float(ds["contact_force"].max()) > 0.0

        attrs = ds.attrs
        assert attrs["input_yaml"] == SCENE
        assert attrs["pframe_version"] == pframe.__version__
        assert attrs["dt"] == 0.001
        assert attrs["steps"] == 1000
        assert attrs["steps_completed"] == 1000
        assert isinstance(attrs["solve_seconds"], (float, np.floating))
        assert 0.0 < attrs["solve_seconds"] < wall  # the kernel's part of the whole command
        assert attrs["status"] == "completed"
        assert attrs["complete"] == 1
        assert 0.0 <= attrs["energy_balance_error"] < 1e-9


@pytest.mark.slow
def test_run_that_stops_early_is_written_and_marked(tmp_path, capsys):
    model = tmp_path / "failing.yaml"
    model.write_text(FAILING, encoding="utf-8")
    out = tmp_path / "failing.h5"
    assert main(["solve", str(model), "-o", str(out)]) == 1
    err = capsys.readouterr().err
    assert "Traceback" not in err
    assert "stopped early" in err and "marked incomplete" in err and str(out) in err
    match = STATUS.search(err)
    assert match, err
    t, step, kind, element = float(match[1]), int(match[2]), match[3], match[4]
    assert 0 < step < 1000
    assert t == pytest.approx(step * 0.001)
    assert element in {"node": NODES, "storey": NODES, "contact": ["top"]}[kind]

    with xr.open_dataset(out, engine="h5netcdf") as ds:
        attrs = ds.attrs
        assert attrs["complete"] == 0
        assert "Newton did not converge" in attrs["status"]
        assert match[0] in attrs["status"]  # the same time, step and element as on stderr
        assert attrs["steps"] == 1000
        assert attrs["steps_completed"] == step - 1
        assert attrs["input_yaml"] == FAILING
        assert ds.sizes["t"] == step  # states t = 0 .. (step - 1) dt
        for name in UNITS:
            assert np.all(np.isfinite(ds[name].values))


def test_validate_prints_valid(scene_file, capsys):
    assert main(["validate", str(scene_file)]) == 0
    captured = capsys.readouterr()
    assert captured.err == ""
    assert captured.out.startswith(f"{scene_file}: valid;")
    assert "4 nodes in 2 buildings, 4 storeys, 1 contacts, 1000 steps" in captured.out


@pytest.mark.slow
def test_console_script_runs(scene_file):
    script = Path(sys.executable).with_name("pframe")
    command = [str(script)] if script.exists() else [sys.executable, "-m", "pframe.cli"]
    version = subprocess.run(command + ["--version"], capture_output=True, text=True,
                             timeout=120)
    assert version.returncode == 0 and version.stdout.strip() == f"pframe {pframe.__version__}"
    run = subprocess.run(command + ["validate", str(scene_file)], capture_output=True,
                         text=True, timeout=120)
    assert run.returncode == 0 and ": valid;" in run.stdout


#: the ``pframe`` command with its work replaced by printing what it runs in: the value of
#: the environment variable named first on the command line (repr), and whether the module named
#: second is imported (before the command's work)
ENVIRONMENT_PROBE = """
import os, sys
from pframe import cli
variable, module = sys.argv[1:3]
def probe(argv=None):
    print(repr(os.environ.get(variable)), module in sys.modules)
    return 0
cli.main = probe
sys.argv = ["pframe", *sys.argv[3:]]
sys.exit(cli.console_main())
"""


def _probe(variable: str, module: str, command: str, given: str | None) -> str:
    """What :data:`ENVIRONMENT_PROBE` prints for ``pframe COMMAND scene.yaml`` run with
    ``variable`` set to ``given`` (None: unset)."""
    import os

    env = {k: v for k, v in os.environ.items() if k != variable}
    if given is not None:
        env[variable] = given
    done = subprocess.run([sys.executable, "-c", ENVIRONMENT_PROBE, variable, module, command,
                           "scene.yaml"], capture_output=True, text=True, timeout=60,
                          env=env | {"PYTHONPATH": str(REPO / "framework")})
    assert done.returncode == 0, done.stderr
    return done.stdout.strip()


@pytest.mark.parametrize(("command", "given", "runs_with"), [
    ("solve", None, "'4' False"), ("validate", None, "'4' False"),
    ("solve", "28", "'28' False"),
    ("sweep", None, "None False"), ("plot", None, "None False")])
def test_a_short_command_puts_idle_blas_threads_to_sleep_unless_told(command, given,
                                                                     runs_with):
    """numpy's OpenBLAS threads spin about 0.1 s before they sleep (about 30 ms of CPU of
    numpy's import): a short command has them sleep at once, set before numpy is imported;
    a value the user set, or a long command (a sweep), keeps the library's own."""
    assert _probe("OPENBLAS_THREAD_TIMEOUT", "numpy", command, given) == runs_with


@pytest.mark.parametrize(("command", "given", "runs_with"), [
    ("solve", None, "'__all__' False"), ("validate", None, "'__all__' False"),
    ("solve", "", "'' False"), ("solve", "logfire", "'logfire' False"),
    ("sweep", None, "None False")])
def test_a_short_command_skips_pydantic_plugins_unless_told(command, given, runs_with):
    """Pydantic reads every installed package's entry points for plug-ins at its first
    validator (about 5 ms of a short command): a short command turns them off before pydantic
    is imported; a value the user set (empty: every plug-in) or a long command keeps them."""
    assert _probe("PYDANTIC_DISABLE_PLUGINS", "pydantic", command, given) == runs_with


def test_schema_check_passes_on_the_committed_schema(monkeypatch, capsys):
    monkeypatch.chdir(REPO)
    assert main(["schema", "--check"]) == 0, capsys.readouterr().err
    assert "up to date" in capsys.readouterr().out


@pytest.mark.slow
def test_schema_check_fails_on_a_stale_or_missing_copy(tmp_path, capsys):
    fresh = tmp_path / "fresh.json"
    assert main(["schema", "-o", str(fresh)]) == 0
    assert fresh.read_bytes() == SCHEMA.read_bytes()
    assert main(["schema", "--check", "-o", str(fresh)]) == 0
    capsys.readouterr()

    stale = tmp_path / "stale.json"
    stale.write_text(SCHEMA.read_text(encoding="utf-8").replace(
        '"title": "pframe scene"', '"title": "pframe scene (old)"'), encoding="utf-8")
    assert stale.read_bytes() != SCHEMA.read_bytes()
    before = stale.read_bytes()
    assert main(["schema", "--check", "-o", str(stale)]) == 1
    err = capsys.readouterr().err
    assert "stale" in err and str(stale) in err
    assert stale.read_bytes() == before  # --check never writes

    missing = tmp_path / "missing.json"
    assert main(["schema", "--check", "-o", str(missing)]) == 1
    assert not missing.exists()


def test_help_lists_every_command_and_each_parses_alone(capsys):
    """``pframe --help`` lists every sub-command; ``pframe CMD`` builds only CMD's parser
    (all of them cost 14 ms a call), which reads the arguments as the whole parser does."""
    from pframe.cli import parser
    from pframe.commands import COMMANDS

    with pytest.raises(SystemExit) as stop:
        main(["--help"])
    assert stop.value.code == 0
    listed = capsys.readouterr().out
    assert all(name in listed for name in COMMANDS)
    argv = ["solve", "scene.yaml", "-o", "out.nc", "--overwrite", "-q", "--strict"]
    alone, whole = parser("solve").parse_args(argv), parser().parse_args(argv)
    assert {k: v for k, v in vars(alone).items() if k != "run"} == {
        k: v for k, v in vars(whole).items() if k != "run"}
    for name in COMMANDS:
        sub = parser(name)
        assert [a.choices for a in sub._subparsers._group_actions][0].keys() == {name}
        with pytest.raises(SystemExit) as stop:
            sub.parse_args([name, "--help"])
        assert stop.value.code == 0 and f"usage: pframe {name}" in capsys.readouterr().out


def test_each_interrupted_command_says_so(monkeypatch, capsys):
    """The "interrupted" line is said once per command, not once per process: main() called
    again in the same process (the Python API, a notebook, these tests) says it again."""
    import pframe.commands.validate as validate

    def stopped(args):
        raise KeyboardInterrupt

    monkeypatch.setattr(validate, "_validate", stopped)
    for _ in range(2):
        assert main(["validate", "scene.yaml"]) == 130
        assert capsys.readouterr().err == "pframe: interrupted; no output written\n"
