"""Compiling once per installation, as a user sees it: a fresh process, an empty cache.

The first ``pframe solve`` on a terminal says that the kernel is being compiled; ``pframe
compile`` then finds it compiled; a scene edited in every way the kernel could care about
(laws, integrator, events, recorders, size) runs without compiling anything: no line, and no
new file in the cache.
"""

from __future__ import annotations

import json
import os
import pty
import subprocess
import sys
from pathlib import Path

import pytest

ANNOUNCE = "compiling pframe's kernel once for this installation"

FIRST = {
    "buildings": [
        {"name": "A", "floors": 2, "mass": 1000.0,
         "story": {"material": "bilinear", "stiffness": 4.0e5, "yield_drift": 0.02, "alpha": 0.1}},
        {"name": "B", "floors": 2, "mass": 2000.0,
         "story": {"material": "elastic", "stiffness": 8.0e6}}],
    "contacts": [{"name": "top", "nodes": ["A/2", "B/2"], "gap": 0.001, "law": "improved_kelvin",
                  "stiffness": 1.0e7, "restitution": 0.5}],
    "excitation": {"kind": "sine", "amplitude": 3.0, "frequency": 6.0},
    "analysis": {"dt": 0.001, "duration": 0.5},
    "recorders": [{"kind": "history", "quantities": ["displacement"]}],
}


def _edited() -> dict:
    scene = json.loads(json.dumps(FIRST))
    scene["buildings"].append({"name": "C", "floors": 3, "mass": 500.0,
                               "story": {"material": "bilinear", "stiffness": 2.0e6,
                                         "yield_force": 4.0e4, "alpha": 0.05}})
    scene["contacts"] = [
        {"name": "ab", "nodes": ["A/1", "B/1"], "gap": 0.002, "law": "kelvin",
         "stiffness": 1.0e7, "restitution": 0.6},
        {"name": "bc", "nodes": ["B/2", "C/2"], "gap": 0.002, "law": "hertzdamp",
         "stiffness": 1.0e9, "restitution": 0.6}]
    scene["analysis"]["integrator"] = {"type": "hht", "alpha": 0.1, "events": True}
    scene["recorders"] = [
        {"kind": "history", "quantities": ["acceleration", "contact_penetration",
                                           "ground_acceleration"], "every": 3},
        {"kind": "envelope", "quantities": ["story_force", "contact_force"]}]
    return scene


def _pframe() -> list[str]:
    script = Path(sys.executable).with_name("pframe")
    return [str(script)] if script.exists() else [sys.executable, "-m", "pframe.cli"]


def _on_terminal(args: list[str], env: dict) -> tuple[int, str]:
    """Run ``pframe ARGS`` with a terminal for standard error; (exit code, what it wrote)."""
    leader, follower = pty.openpty()
    try:
        done = subprocess.run(_pframe() + args, stdout=subprocess.PIPE, stderr=follower,
                              env=env, timeout=600)
        os.close(follower)
        follower = -1
        chunks = []
        while True:
            try:
                chunk = os.read(leader, 65536)
            except OSError:  # the terminal is closed once everything was read
                break
            if not chunk:
                break
            chunks.append(chunk)
        return done.returncode, b"".join(chunks).decode() + done.stdout.decode()
    finally:
        os.close(leader)
        if follower >= 0:
            os.close(follower)


def _cache_files(root: Path) -> set[str]:
    return {str(p.relative_to(root)) for p in root.rglob("*") if p.is_file()}


@pytest.mark.skipif(not hasattr(pty, "openpty"), reason="needs a pseudo-terminal (POSIX)")
def test_first_run_compiles_once_and_edits_compile_nothing(tmp_path):
    env = dict(os.environ, PFRAME_CACHE_DIR=str(tmp_path / "cache"))
    first, edited = tmp_path / "first.yaml", tmp_path / "edited.yaml"
    first.write_text(json.dumps(FIRST), encoding="utf-8")
    edited.write_text(json.dumps(_edited()), encoding="utf-8")

    code, output = _on_terminal(["solve", str(first), "-o", str(tmp_path / "a.h5")], env)
    assert code == 0, output
    assert output.count(ANNOUNCE) == 1

    compiled = _cache_files(tmp_path / "cache")
    done = subprocess.run(_pframe() + ["compile"], capture_output=True, text=True, env=env,
                          timeout=600)
    assert done.returncode == 0 and "already compiled" in done.stdout, done.stderr

    code, output = _on_terminal(["solve", str(edited), "-o", str(tmp_path / "b.h5")], env)
    assert code == 0, output
    assert ANNOUNCE not in output and "impacts" in output
    assert _cache_files(tmp_path / "cache") == compiled  # nothing new was compiled
