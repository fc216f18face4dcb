"""A record path that leaves the folder of the file naming it (``../secret.txt``, an absolute
path) never makes pframe print that file's text: a malformed record outside the folder is
told by file and line only, from a scene, a sweep's axis and a suite alike; inside the folder
the message quotes the offending text, as it helps there. Generated over the ways a record can
be malformed (each puts a marker in the text a message would quote) and the ways a path can
leave its folder."""

from __future__ import annotations

from pathlib import Path

import pytest
import yaml

from pframe.cli import main

MARKER = "SECRETMARKER"  # no digits: a header reads numbers out of its text
#: malformed records, each with the marker where a message would quote it
MALFORMED = {
    "columns-line": f"0 0\n0.01 1\n{MARKER} here\n",
    "columns-three": f"0 0\n0.01 1 {MARKER}\n",
    "at2-header": f"a\nb\nc\n{MARKER} no numbers\n1 2 3\n",
    "at2-token": f"a\nb\nc\nNPTS= 3, DT= 0.01\n0.1 {MARKER} 0.3\n",
    "units-header": f"# units: {MARKER}/s2\n0 0\n0.01 1\n0.02 0\n",
}
SCENE = {
    "buildings": [{"name": "A", "floors": 1, "mass": 1000.0,
                   "story": {"material": "elastic", "stiffness": 1.0e6}}],
    "analysis": {"dt": 0.01, "duration": 0.02},
}


def _layout(tmp_path: Path, kind: str, how: str) -> tuple[Path, str]:
    """The record (with suffix .AT2 for the AT2 kinds) outside ``tmp_path/work`` and the name
    the work folder's files give it: relative (``../``), deep (``../../x/..``) or absolute."""
    work = tmp_path / "deep" / "work"
    work.mkdir(parents=True)
    suffix = ".AT2" if kind.startswith("at2") else ".txt"
    record = tmp_path / "deep" / f"record{suffix}"
    record.write_text(MALFORMED[kind], encoding="utf-8")
    name = {"relative": f"../record{suffix}", "deep": f"../../deep/record{suffix}",
            "absolute": str(record)}[how]
    return work, name


def _check(code: int, err: str, shown: bool):
    assert code == 2 and "Traceback" not in err and len(err.strip().splitlines()) == 1
    assert (MARKER in err) == shown, err
    if not shown:
        assert "its text is not shown" in err or "line" in err


@pytest.mark.parametrize("how", ["relative", "deep", "absolute"])
@pytest.mark.parametrize("kind", sorted(MALFORMED))
def test_a_scene_never_prints_a_record_outside_its_folder(tmp_path, capsys, kind, how):
    work, name = _layout(tmp_path, kind, how)
    scene = {**SCENE, "excitation": {"kind": "record", "file": name}}
    (work / "scene.yaml").write_text(yaml.safe_dump(scene), encoding="utf-8")
    code = main(["validate", str(work / "scene.yaml")])
    _check(code, capsys.readouterr().err, shown=False)


@pytest.mark.parametrize("kind", sorted(MALFORMED))
def test_a_record_in_the_scene_folder_is_quoted(tmp_path, capsys, kind):
    suffix = ".AT2" if kind.startswith("at2") else ".txt"
    (tmp_path / f"record{suffix}").write_text(MALFORMED[kind], encoding="utf-8")
    scene = {**SCENE, "excitation": {"kind": "record", "file": f"record{suffix}"}}
    (tmp_path / "scene.yaml").write_text(yaml.safe_dump(scene), encoding="utf-8")
    code = main(["validate", str(tmp_path / "scene.yaml")])
    _check(code, capsys.readouterr().err, shown=True)


@pytest.mark.parametrize("how", ["relative", "absolute"])
@pytest.mark.parametrize("kind", ["columns-line", "at2-token"])
def test_a_sweep_axis_never_prints_a_record_outside_its_folder(tmp_path, capsys, kind, how):
    work, name = _layout(tmp_path, kind, how)
    (work / "ok.txt").write_text("0 0\n0.01 1\n0.02 0\n", encoding="utf-8")
    scene = {**SCENE, "excitation": {"kind": "record", "file": "ok.txt"}}
    (work / "base.yaml").write_text(yaml.safe_dump(scene), encoding="utf-8")
    (work / "sweep.yaml").write_text(yaml.safe_dump({"base": "base.yaml", "axes": [
        {"name": "record", "path": "excitation.file", "values": ["ok.txt", name]}]}),
        encoding="utf-8")
    code = main(["sweep", str(work / "sweep.yaml"), "-o", str(work / "out.nc"), "-q"])
    _check(code, capsys.readouterr().err, shown=False)
    assert not (work / "out.nc").exists()


def test_a_suite_never_prints_a_record_outside_its_folder(tmp_path, capsys):
    from pframe.errors import InputError
    from pframe.excitation.suite import load_suite

    work, name = _layout(tmp_path, "columns-line", "relative")
    (work / "suite.yaml").write_text(yaml.safe_dump({"records": [name]}), encoding="utf-8")
    with pytest.raises(InputError) as info:
        load_suite(work / "suite.yaml")
    assert MARKER not in str(info.value) and "its text is not shown" in str(info.value)
