"""Every ``pframe`` command that reads or writes a file, given hostile paths: each input
missing, a folder, a device, a FIFO, empty, binary, a too-long name, a path through a file,
a symbolic-link loop; each output a folder, a device, a FIFO, one of the command's inputs,
an existing file (without ``--overwrite``), in a missing folder, through a file, a too-long
name, empty. Generated: every command x every argument x every kind.

Each case answers in bounded time (a FIFO is never opened for reading or writing) with exit
2 (bad input) or 3 (the environment), one paragraph naming the path, no traceback; nothing is
written, and no input, device or other file is changed. Runs in-process (``pframe.cli.main``)
under an alarm, so a case that would block fails instead of hanging."""

from __future__ import annotations

import hashlib
import os
import re
import signal
import stat
from pathlib import Path

import numpy as np
import pytest
import yaml

from pframe.cli import main

SCENE = {
    "buildings": [
        {"name": "A", "floors": 1, "mass": 1000.0, "story": {"material": "elastic",
                                                             "stiffness": 1.0e6}},
        {"name": "B", "floors": 1, "mass": 1000.0, "story": {"material": "elastic",
                                                             "stiffness": 2.0e6}}],
    "contacts": [{"nodes": ["A/1", "B/1"], "gap": 0.01, "law": "linear", "stiffness": 1.0e7}],
    "excitation": {"kind": "sine", "amplitude": 3.0, "frequency": 6.0},
    "analysis": {"dt": 0.002, "duration": 0.05},
    "recorders": [{"kind": "history", "quantities": ["displacement", "velocity",
                                                     "contact_force"]}],
}

#: each command: its arguments with a valid value ({name} of a fixture file), the argument
#: that is an input or an output, and what else it needs
COMMANDS = {
    "solve": (["{scene}", "-o", "{out}/run.nc", "--summary", "{out}/summary.md", "-q"],
              {"inputs": [0], "outputs": [2, 4]}),
    "validate": (["{scene}"], {"inputs": [0], "outputs": []}),
    "pi": (["{scene}"], {"inputs": [0], "outputs": []}),
    "expand": (["{scene}", "-o", "{out}/expanded.yaml"], {"inputs": [0], "outputs": [2]}),
    "scale": (["{scene}", "--length", "1/2", "--modulus", "1", "--acceleration", "1", "-o",
               "{out}/scaled.yaml"], {"inputs": [0], "outputs": [8]}),
    "opensees": (["{scene}", "-o", "{out}/model_ops.py"], {"inputs": [0], "outputs": [2]}),
    "accuracy": (["{scene}", "--factors", "1", "--repeats", "1", "-o", "{out}/study"],
                 {"inputs": [0], "outputs": [6], "folder": True}),
    "summary": (["{result}", "-o", "{out}/summary.md"], {"inputs": [0], "outputs": [2]}),
    "plot": (["{result}", "-o", "{out}/figure.png", "-q"], {"inputs": [0], "outputs": [2]}),
    "animate": (["{result}", "-o", "{out}/page.html", "-q"], {"inputs": [0], "outputs": [2]}),
    "export": (["{result}", "--csv", "{out}/csv"], {"inputs": [0], "outputs": [2],
                                                     "folder": True}),
    "export --pelicun": (["{result}", "--pelicun", "{out}/edp.csv"],
                         {"inputs": [0], "outputs": [2]}),
    "sweep": (["{sweep}", "-o", "{out}/sweep.nc", "-q"], {"inputs": [0], "outputs": [2]}),
    "gap": (["{scene}", "--suite", "{suite}", "--levels", "1.0", "-o", "{out}/gap.nc", "-q"],
            {"inputs": [0, 2], "outputs": [6]}),
    "schema": (["-o", "{out}/schema.json"], {"inputs": [], "outputs": [1],
                                               "makes": "missing-folder"}),
}
#: the options that name an output file or folder, in one command or another
OUTPUT_OPTIONS = ("-o", "--summary", "--pelicun", "--csv")
#: hostile inputs (made by _hostile)
INPUTS = ["missing", "folder", "devnull", "devzero", "fifo", "empty", "binary", "long-name",
          "through-a-file", "link-loop"]
#: hostile outputs
OUTPUTS = ["folder", "devnull", "fifo", "the-input", "existing", "missing-folder",
           "through-a-file", "long-name", "empty-name"]
#: seconds a case may take before it counts as blocked
SECONDS = 60


@pytest.fixture(scope="module")
def files(tmp_path_factory):
    """Valid inputs: a scene, its result, a sweep of it, a suite of one record."""
    folder = tmp_path_factory.mktemp("valid")
    (folder / "scene.yaml").write_text(yaml.safe_dump(SCENE), encoding="utf-8")
    assert main(["solve", str(folder / "scene.yaml"), "-o", str(folder / "run.nc"), "-q"]) in (0,)
    (folder / "sweep.yaml").write_text(
        "base: scene.yaml\naxes:\n  - {name: gap, path: contacts.*.gap, values: [0.01]}\n",
        encoding="utf-8")
    t = np.arange(0.0, 0.05, 0.002)
    np.savetxt(folder / "rec.txt", np.column_stack([t, 3.0 * np.sin(6.0 * t)]))
    (folder / "suite.yaml").write_text("records: [rec.txt]\n", encoding="utf-8")
    return folder


def _digest(path: Path) -> str | None:
    try:
        if not stat.S_ISREG(os.stat(path).st_mode):
            return "special"
        return hashlib.sha256(path.read_bytes()).hexdigest()
    except OSError:
        return None


def _state(folder: Path) -> dict:
    return {str(p.relative_to(folder)): _digest(p) for p in sorted(folder.rglob("*"))
            if not p.is_symlink()}


def _hostile(kind: str, work: Path, valid: Path) -> str:
    """A hostile path of ``kind`` (made in ``work``); ``valid`` is the argument's valid file
    (the input of an output case)."""
    if kind == "missing":
        return str(work / "missing.yaml")
    if kind == "folder":
        (work / "a-folder").mkdir()
        return str(work / "a-folder")
    if kind == "devnull":
        return "/dev/null"
    if kind == "devzero":
        return "/dev/zero"
    if kind == "fifo":
        os.mkfifo(work / "a-fifo")
        return str(work / "a-fifo")
    if kind == "empty":
        (work / "empty.yaml").write_bytes(b"")
        return str(work / "empty.yaml")
    if kind == "binary":
        (work / "binary.yaml").write_bytes(bytes(range(256)) * 8)
        return str(work / "binary.yaml")
    if kind == "long-name":
        return str(work / ("x" * 300 + valid.suffix))
    if kind == "through-a-file":
        (work / "plain").write_text("x", encoding="utf-8")
        return str(work / "plain" / valid.name)
    if kind == "link-loop":
        os.symlink(work / "loop-b", work / "loop-a")
        os.symlink(work / "loop-a", work / "loop-b")
        return str(work / "loop-a")
    if kind == "the-input":
        return "{input}"
    if kind == "existing":
        (work / valid.name).write_bytes(b"an existing file\n")
        return str(work / valid.name)
    if kind == "missing-folder":
        return str(work / "no-such-folder" / valid.name)
    if kind == "empty-name":
        return ""
    raise AssertionError(kind)


def _cases():
    for command, (_, roles) in COMMANDS.items():
        for i in roles["inputs"]:
            for kind in INPUTS:
                yield pytest.param(command, "input", i, kind, id=f"{command}-in{i}-{kind}")
        for i in roles["outputs"]:
            for kind in OUTPUTS:
                if kind == "the-input" and not roles["inputs"]:
                    continue
                if (kind == "folder" and roles.get("folder")) or kind == roles.get("makes"):
                    continue  # an output folder may exist; schema makes its folder
                yield pytest.param(command, "output", i, kind, id=f"{command}-out-{kind}")


class _Late(Exception):
    pass


def _alarm(signum, frame):
    raise _Late


@pytest.mark.slow
@pytest.mark.parametrize("command, role, index, kind", list(_cases()))
def test_a_hostile_path_is_refused_cleanly(files, tmp_path, capsys, command, role, index,
                                           kind):
    work = tmp_path / "work"
    out = tmp_path / "out"
    work.mkdir()
    out.mkdir()
    args, roles = COMMANDS[command]
    names = {"scene": files / "scene.yaml", "result": files / "run.nc",
             "sweep": files / "sweep.yaml", "suite": files / "suite.yaml", "out": out}
    argv = [a.format(**{k: str(v) for k, v in names.items()}) for a in args]
    first_input = argv[roles["inputs"][0]] if roles["inputs"] else None
    argv[index] = _hostile(kind, work, Path(argv[index])).replace("{input}", first_input or "")
    before = {"valid": _state(files), "work": _state(work)}
    previous = signal.signal(signal.SIGALRM, _alarm)
    signal.alarm(SECONDS)
    try:
        code = main([command.split()[0], *argv])
    except _Late:
        pytest.fail(f"pframe {command} {' '.join(argv)}: no answer in {SECONDS} s")
    finally:
        signal.alarm(0)
        signal.signal(signal.SIGALRM, previous)
    err = capsys.readouterr().err
    assert code in (2, 3), (code, err)
    lines = [line for line in err.strip().splitlines() if not line.startswith("pframe: warning")]
    assert len(lines) == 1 and lines[0].startswith("pframe: "), err
    assert "Traceback" not in err
    assert _state(files) == before["valid"]  # no input changed, nothing written beside them
    assert _state(work) == before["work"]  # no hostile target changed
    assert not any(out.iterdir()), sorted(p.name for p in out.iterdir())
    if role == "output":  # advice names the option this output was given with, no other
        given = argv[index - 1]
        named = {o for o in OUTPUT_OPTIONS if re.search(rf"(?<![\w-]){o}(?![\w-])", lines[0])}
        assert named <= {given}, (given, lines[0])
        if kind == "existing" and not roles.get("folder"):
            assert given in named, lines[0]


@pytest.mark.slow
def test_a_python_caller_is_told_the_keyword_that_names_its_output(tmp_path):
    """From Python, a refused output names the keyword of the function called (the pelicun
    table's ``path``, the CSV export's ``folder``), not the ``pframe`` command's option."""
    from pframe.errors import InputError
    from pframe.risk import export_pelicun
    from pframe.tables import export_csv

    result, existing = tmp_path / "risk.nc", tmp_path / "edp.csv"
    result.write_bytes(b"never read: the output is refused first")
    existing.write_text("mine\n")
    with pytest.raises(InputError, match=r"overwrite=True .* another name with path=\.\.\.$"):
        export_pelicun(result, existing)
    with pytest.raises(InputError, match=r"^folder=''"):
        export_csv(result, "")
    assert existing.read_text() == "mine\n"
