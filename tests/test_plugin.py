"""A third-party contact law arrives through an entry point and runs inside the kernel.

The package ``tests/plugin_pkg`` (distribution ``pframe-softstop``) registers two contact
laws in the group ``pframe.contact_laws``: ``softstop``, a cubic-stiffening spring
F = k delta (1 + (delta / delta_ref)^2), ``broken``, whose force() numba cannot compile, and
``improved_kelvin_copy``, pframe's improved Kelvin law as a plug-in. numba compiles a plug-in's
force into a C function the C kernel calls through a pointer (pframe.kernel.plugins).

pip installs it into a private folder (``--target``) that only the ``pframe`` subprocesses
of these tests see (on their PYTHONPATH): the environment is never changed, so neither other
tests nor a concurrent test run can see the extra laws or lose them half way. Every check
runs ``pframe`` in a fresh interpreter, which reads the entry points anew.
"""

from __future__ import annotations

import json
import os
import shutil
import subprocess
import sys
from pathlib import Path

import h5py
import numpy as np
import pytest

PLUGIN_SOURCE = Path(__file__).resolve().parent / "plugin_pkg"

STIFFNESS = 1.0e4  # N/m
REFERENCE_PENETRATION = 0.005  # m

#: pip output that means "cannot build here" (no wheel/setuptools) ...
_CANNOT_BUILD = ("bdist_wheel", "no module named", "setuptools")
#: ... and "cannot fetch the build requirements" (no network / no index)
_NO_NETWORK = ("could not find a version", "no matching distribution", "connection",
               "network", "temporary failure", "max retries", "proxyerror", "name resolution")


def _pip(*args: str) -> subprocess.CompletedProcess:
    return subprocess.run([sys.executable, "-m", "pip", "--disable-pip-version-check",
                           "--no-input", *args], capture_output=True, text=True, timeout=600)


@pytest.fixture(scope="session")
def softstop_site(tmp_path_factory) -> Path:
    """A folder holding the installed plug-in (package and dist-info with its entry points).

    The package is copied first so that no build files land in the source tree.
    """
    root = tmp_path_factory.mktemp("plugin")
    source, site = root / "plugin_pkg", root / "site"
    shutil.copytree(PLUGIN_SOURCE, source, ignore=shutil.ignore_patterns(
        "build", "*.egg-info", "__pycache__"))
    offline = _pip("install", "--no-deps", "--no-build-isolation", "--target", str(site),
                   str(source))
    if offline.returncode != 0:
        shutil.rmtree(site, ignore_errors=True)
        online = _pip("install", "--no-deps", "--target", str(site), str(source))
        if online.returncode != 0:
            first, second = offline.stdout + offline.stderr, online.stdout + online.stderr
            if (any(s in first.lower() for s in _CANNOT_BUILD)
                    and any(s in second.lower() for s in _NO_NETWORK)):
                pytest.skip("cannot install the test plug-in: building it without isolation "
                            "needs the 'wheel' package (absent), and the package index that "
                            "would provide it is unreachable")
            pytest.fail(f"pip could not install {source}:\n--- without build isolation:\n"
                        f"{first[-3000:]}\n--- with build isolation:\n{second[-3000:]}")
    assert (site / "pframe_softstop" / "__init__.py").is_file()
    yield site
    shutil.rmtree(site, ignore_errors=True)  # the only trace of the install


@pytest.fixture
def run_pframe(softstop_site):
    """``pframe ARGS`` in a fresh interpreter that sees the plug-in."""
    script = Path(sys.executable).with_name("pframe")
    command = [str(script)] if script.exists() else [sys.executable, "-m", "pframe.cli"]
    env = dict(os.environ)
    env["PYTHONPATH"] = os.pathsep.join(
        [str(softstop_site)] + ([env["PYTHONPATH"]] if env.get("PYTHONPATH") else []))

    def run(*args: str, cwd: Path, cache: Path | None = None) -> subprocess.CompletedProcess:
        here = env if cache is None else dict(env, PFRAME_CACHE_DIR=str(cache))
        return subprocess.run(command + list(args), cwd=cwd, env=here, capture_output=True,
                              text=True, timeout=600)

    run.site = [softstop_site]
    return run


def _two_masses(contact: dict) -> str:
    """Two storey-less masses touching at t = 0 and approaching at 1.5 m/s."""
    scene = {
        "title": "two free masses hitting through a plug-in contact law",
        "nodes": [{"name": "L/1", "mass": 1.0}, {"name": "R/1", "mass": 2.0}],
        "contacts": [{"name": "c", "nodes": ["L/1", "R/1"], "gap": 0.0} | contact],
        "damping": {"ratio": 0.0},
        "initial_conditions": {"velocity": {"L/1": 1.0, "R/1": -0.5}},
        "analysis": {"dt": 1.0e-4, "duration": 0.05},
        "recorders": [{"kind": "history",
                       "quantities": ["displacement", "contact_force", "contact_penetration"]}],
    }
    return json.dumps(scene, indent=1)  # JSON is YAML; one key per line


SOFTSTOP = {"law": "softstop", "stiffness": STIFFNESS,
            "reference_penetration": REFERENCE_PENETRATION}


@pytest.mark.slow
def test_plugin_law_runs_inside_the_kernel(run_pframe, tmp_path):
    model = tmp_path / "soft.yaml"
    model.write_text(_two_masses(SOFTSTOP), encoding="utf-8")
    run = run_pframe("solve", str(model), "-o", str(tmp_path / "soft.h5"), "-q", cwd=tmp_path)
    assert run.returncode == 0, run.stderr
    with h5py.File(tmp_path / "soft.h5", "r") as f:
        assert f.attrs["complete"] == 1
        assert [b"".join(row).decode() for row in f["contact_name"][:]] == ["c"]
        delta = f["contact_penetration"][:, 0]
        force = f["contact_force"][:, 0]
    closed = delta > 0.0
    assert closed.sum() > 50  # the impact lasts many steps
    expected = STIFFNESS * delta * (1.0 + (delta / REFERENCE_PENETRATION) ** 2)
    np.testing.assert_allclose(force[closed], expected[closed], rtol=1e-12, atol=0.0)
    assert np.all(force[~closed] == 0.0)
    # the cubic term matters: the peak force is far above the linear spring's k delta
    peak = np.argmax(delta)
    assert delta[peak] > 0.7 * REFERENCE_PENETRATION
    assert force[peak] > 1.4 * STIFFNESS * delta[peak]


@pytest.mark.slow
def test_plugin_params_are_validated_with_lines(run_pframe, tmp_path):
    contact = dict(SOFTSTOP)
    del contact["reference_penetration"]
    contact["stiffness"] = -1.0
    text = _two_masses(contact)
    model = tmp_path / "bad.yaml"
    model.write_text(text, encoding="utf-8")
    run = run_pframe("validate", str(model), cwd=tmp_path)
    assert run.returncode == 2
    assert "Traceback" not in run.stderr
    lines = text.splitlines()
    stiffness_line = next(i for i, s in enumerate(lines, 1) if '"stiffness"' in s)
    assert f"line {stiffness_line}, contacts[0].stiffness" in run.stderr
    assert "contacts[0].reference_penetration: this field is required" in run.stderr


@pytest.mark.slow
def test_uncompilable_plugin_law_is_named(run_pframe, tmp_path):
    model = tmp_path / "broken.yaml"
    model.write_text(_two_masses({"law": "broken", "stiffness": STIFFNESS}), encoding="utf-8")
    out = tmp_path / "broken.h5"
    run = run_pframe("solve", str(model), "-o", str(out), cwd=tmp_path)
    assert run.returncode != 0
    assert "Traceback" not in run.stderr
    assert "'broken'" in run.stderr
    assert "cannot be compiled" in run.stderr
    assert not out.exists()


@pytest.mark.slow
def test_pi_refuses_a_plugin_law_without_declared_dimensions(run_pframe, tmp_path):
    """``broken`` declares no dimension for its stiffness: pframe pi cannot list it as a
    governing variable and says which law, which field and what to declare, exit 2 (it once
    left the stiffness out of the groups and exited 0)."""
    scene = json.loads(_two_masses({"law": "broken", "stiffness": STIFFNESS}))
    scene["excitation"] = {"kind": "sine", "amplitude": 1.0, "frequency": 6.0}
    model = tmp_path / "broken.yaml"
    model.write_text(json.dumps(scene), encoding="utf-8")
    run = run_pframe("pi", str(model), cwd=tmp_path)
    assert run.returncode == 2, run.stdout
    assert "Traceback" not in run.stderr and run.stdout == ""
    assert "field 'stiffness' of contact law 'broken'" in run.stderr
    assert "dimensions = {'stiffness':" in run.stderr


@pytest.mark.slow
def test_unknown_law_lists_plugin_laws(run_pframe, tmp_path):
    model = tmp_path / "typo.yaml"
    model.write_text(_two_masses(SOFTSTOP | {"law": "softstp"}), encoding="utf-8")
    run = run_pframe("validate", str(model), cwd=tmp_path)
    assert run.returncode == 2
    assert "Traceback" not in run.stderr
    assert "unknown contact law 'softstp'" in run.stderr
    known = run.stderr.split("known:", 1)[1]
    for name in ("softstop", "broken", "linear", "hertz", "kelvin", "improved_kelvin"):
        assert name in known


@pytest.mark.slow
def test_plugin_law_is_known_everywhere_a_built_in_law_is(run_pframe, tmp_path):
    """What a law declares (dimensions, exponent, branches, OpenSees counterpart) is all that
    ``pframe pi``, ``pframe scale``, the steps-per-contact check, the reference solver and
    the OpenSees script need: the plug-in law is known to each of them as a built-in one."""
    scene = json.loads(_two_masses(SOFTSTOP))
    scene["analysis"]["dt"] = 5.0e-3  # too coarse for the contact: the check says so
    model = tmp_path / "soft.yaml"
    model.write_text(json.dumps(scene), encoding="utf-8")

    pi = run_pframe("pi", str(model), "--json", "--repeating",
                    "m_b,stiffness,reference_penetration", cwd=tmp_path)
    assert pi.returncode == 0, pi.stderr
    variables = {v["name"]: v for v in json.loads(pi.stdout)["variables"]}
    assert variables["stiffness"]["value"] == STIFFNESS
    assert variables["reference_penetration"]["value"] == REFERENCE_PENETRATION

    scaled = tmp_path / "half.yaml"
    scale = run_pframe("scale", str(model), "--length", "1/2", "--modulus", "1",
                       "--acceleration", "1", "-o", str(scaled), cwd=tmp_path)
    assert scale.returncode == 0, scale.stderr
    import yaml

    contact = yaml.safe_load(scaled.read_text())["contacts"][0]
    # length 1/2, modulus 1, acceleration 1: force ~ L^2, so N/m ~ L: stiffness halves
    assert contact["stiffness"] == pytest.approx(STIFFNESS / 2, rel=1e-12)
    assert contact["reference_penetration"] == pytest.approx(REFERENCE_PENETRATION / 2,
                                                             rel=1e-12)

    validate = run_pframe("validate", str(model), cwd=tmp_path)
    assert validate.returncode == 0, validate.stderr
    assert "steps" in validate.stderr and "contact period" in validate.stderr

    code = ("from pframe.laws import get_law; from pframe.reference.branches import "
            "branches_for; law = get_law('contact', 'softstop'); "
            "print(type(branches_for(law)).__name__, law.exponent, law.opensees)")
    probe = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                           env={**os.environ, "PYTHONPATH": os.pathsep.join(
                               [str(p) for p in run_pframe.site] + sys.path)}, timeout=300)
    assert probe.returncode == 0, probe.stderr
    assert probe.stdout.split() == ["Gap", "1.0", "None"]

    peer = run_pframe("opensees", str(model), cwd=tmp_path)
    assert peer.returncode == 2 and "softstop" in peer.stderr
    assert "no OpenSees counterpart" in peer.stderr


@pytest.mark.slow
def test_a_plugin_copy_of_a_built_in_law_gives_its_results(run_pframe, tmp_path):
    """The paper's scene with its improved Kelvin contacts as the built-in law (C, in the
    kernel) and as a plug-in copy (numba cfunc, called through a pointer): the same numbers,
    bit for bit, and the plug-in compiled once (a second run finds it cached).
    benchmarks/plugin_speed.py compares their speed."""
    import yaml

    models = Path(__file__).resolve().parents[1] / "models"
    data = yaml.safe_load((models / "wu2021-eq14.yaml").read_text(encoding="utf-8"))
    data["analysis"]["duration"] = 3.0  # the first impacts at every floor
    builtin = tmp_path / "builtin.yaml"
    builtin.write_text(json.dumps(data), encoding="utf-8")
    for contact in data["contacts"]:
        contact["law"] = "improved_kelvin_copy"
    plugin = tmp_path / "plugin.yaml"
    plugin.write_text(json.dumps(data), encoding="utf-8")
    env_cache = tmp_path / "cache"
    results, files = {}, {}
    for name, model in (("builtin", builtin), ("plugin", plugin), ("again", plugin)):
        run = run_pframe("solve", str(model), "-o", str(tmp_path / f"{name}.h5"), "-q",
                         cwd=tmp_path, cache=env_cache)
        assert run.returncode == 0, run.stderr
        files[name] = {p for p in env_cache.rglob("*") if p.is_file()}
        with h5py.File(tmp_path / f"{name}.h5", "r") as f:
            results[name] = {q: f[q][:] for q in ("displacement", "contact_force", "story_force")}
    assert files["builtin"] == set()  # the built-in law compiled nothing
    assert any(p.name == "compiled" for p in files["plugin"])  # the plug-in, once ...
    assert files["again"] == files["plugin"]  # ... and the next run found it in the cache
    assert results["builtin"]["contact_force"].max() > 0  # the contacts did close
    for q, values in results["builtin"].items():
        assert np.array_equal(values, results["plugin"][q]), q
        assert np.array_equal(values, results["again"][q]), q
