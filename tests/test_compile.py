"""Nothing is compiled at run time for built-in laws: the kernel is C, compiled when pframe is
installed.

A fresh process with an empty cache runs the paper's scene and a scene using every part of
the kernel (every built-in law, HHT with event location, envelopes): it never imports numba,
writes nothing in the cache, and the terminal says nothing about compiling. ``pframe
compile`` says that nothing needs compiling. The generated C (the laws translated from their
Python ``force``, the structs from ``pframe.kernel.state``) is current.
"""

from __future__ import annotations

import json
import os
import subprocess
import sys
from pathlib import Path

import pytest

from pframe.kernel import translate

REPO = Path(__file__).resolve().parents[1]

EDITED = {
    "buildings": [
        {"name": "A", "floors": 2, "mass": 1000.0,
         "story": {"material": "bilinear", "stiffness": 4.0e5, "yield_drift": 0.02, "alpha": 0.1}},
        {"name": "B", "floors": 2, "mass": 2000.0,
         "story": {"material": "elastic", "stiffness": 8.0e6}},
        {"name": "C", "floors": 3, "mass": 500.0,
         "story": {"material": "bilinear", "stiffness": 2.0e6, "yield_force": 4.0e4,
                   "alpha": 0.05}}],
    "contacts": [
        {"name": "ab", "nodes": ["A/1", "B/1"], "gap": 0.002, "law": "kelvin",
         "stiffness": 1.0e7, "restitution": 0.6},
        {"name": "bc", "nodes": ["B/2", "C/2"], "gap": 0.002, "law": "hertzdamp",
         "stiffness": 1.0e9, "restitution": 0.6}],
    "excitation": {"kind": "sine", "amplitude": 3.0, "frequency": 6.0},
    "analysis": {"dt": 0.001, "duration": 0.5,
                 "integrator": {"type": "hht", "alpha": 0.1, "events": True}},
    "recorders": [
        {"kind": "history", "quantities": ["acceleration", "contact_penetration",
                                           "ground_acceleration"], "every": 3},
        {"kind": "envelope", "quantities": ["story_force", "contact_force"]}],
}

#: solve two scenes through the API in a fresh interpreter; report what was imported
_PROBE = """
import json, sys
import pframe
first = pframe.solve(sys.argv[1], output=sys.argv[3])
second = pframe.solve(sys.argv[2], output=sys.argv[4])
print(json.dumps({"numba": "numba" in sys.modules,
                  "llvmlite": "llvmlite" in sys.modules,
                  "complete": [bool(first.attrs["complete"]), bool(second.attrs["complete"])]}))
"""


@pytest.mark.slow
def test_a_built_in_scene_neither_imports_numba_nor_compiles(tmp_path):
    cache = tmp_path / "cache"
    env = dict(os.environ, PFRAME_CACHE_DIR=str(cache))
    edited = tmp_path / "edited.yaml"
    edited.write_text(json.dumps(EDITED), encoding="utf-8")
    done = subprocess.run(
        [sys.executable, "-c", _PROBE, str(REPO / "models" / "wu2021-eq14.yaml"), str(edited),
         str(tmp_path / "a.nc"), str(tmp_path / "b.nc")],
        capture_output=True, text=True, env=env, timeout=600)
    assert done.returncode == 0, done.stderr
    report = json.loads(done.stdout.strip().splitlines()[-1])
    assert report == {"numba": False, "llvmlite": False, "complete": [True, True]}
    assert "compil" not in done.stderr
    assert not cache.exists() or not any(p.is_file() for p in cache.rglob("*"))


@pytest.mark.slow
def test_pframe_solve_of_an_ordinary_scene_imports_no_scipy_sparse(tmp_path):
    """scipy.sparse (about 0.1 s to import) is for tall scenes and explicit stability
    checks: the paper's scene solved from the command line never imports it."""
    probe = ("import sys\nfrom pframe.cli import main\n"
             "code = main(['solve', sys.argv[1], '-o', sys.argv[2], '-q'])\n"
             "print(code, 'scipy.sparse' in sys.modules)")
    done = subprocess.run(
        [sys.executable, "-c", probe, str(REPO / "models" / "wu2021-eq14.yaml"),
         str(tmp_path / "a.nc")], capture_output=True, text=True, timeout=600)
    assert done.stdout.split() == ["0", "False"], done.stderr


def _pframe() -> list[str]:
    script = Path(sys.executable).with_name("pframe")
    return [str(script)] if script.exists() else [sys.executable, "-m", "pframe.cli"]


@pytest.mark.slow
def test_pframe_compile_says_nothing_needs_compiling(tmp_path):
    env = dict(os.environ, PFRAME_CACHE_DIR=str(tmp_path / "cache"))
    done = subprocess.run(_pframe() + ["compile"], capture_output=True, text=True, env=env,
                          timeout=600)
    assert done.returncode == 0, done.stderr
    assert "nothing to compile" in done.stdout


def test_the_generated_c_is_current():
    """c/laws.c and c/state.h are what the laws and state.py give: `python -m
    pframe.kernel.translate` rewrites them (and the compiled kernel refuses stale sources)."""
    assert translate.stale() == [], "run: python -m pframe.kernel.translate"
    assert translate.main(["--check"]) == 0


def test_the_compiled_kernel_matches_its_sources_and_structs():
    import ctypes

    from pframe.kernel import ckernel

    library = ckernel.library()
    assert library.pframe_source_hash().decode() == ckernel.source_hash()
    sizes = (ctypes.c_int64 * len(ckernel.STRUCTS))()
    library.pframe_layout(sizes)
    assert list(sizes) == [ctypes.sizeof(s) for s in ckernel.STRUCTS]


def test_a_stale_kernel_is_refused(tmp_path, monkeypatch):
    """Sources edited after the build (a changed hash) stop the run with what to do, instead
    of running an old kernel."""
    from pframe.errors import EnvironmentFailure
    from pframe.kernel import ckernel

    copy = tmp_path / "c"
    copy.mkdir()
    for path in ckernel.C_FOLDER.iterdir():
        if path.suffix in (".c", ".h"):
            (copy / path.name).write_bytes(path.read_bytes())
    (copy / "newton.c").write_text((copy / "newton.c").read_text() + "\n/* edited */\n")
    monkeypatch.setattr(ckernel, "C_FOLDER", copy)
    with pytest.raises(EnvironmentFailure, match="stale build"):
        ckernel._load()
