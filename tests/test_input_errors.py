"""Bad input: exit code 2, one paragraph naming the file, the line and the field, no traceback,
and no output file created or overwritten.

Every case runs in-process through ``pframe.cli.main`` three ways: ``validate``, ``solve`` to
a new output path (which must not appear) and ``solve --overwrite`` onto an existing file
(which must stay byte for byte as it was).
"""

from __future__ import annotations

from dataclasses import dataclass, field

import h5py
import pytest

from pframe.cli import main

#: A valid scene, one key per line so that every field has a line of its own. Its structure
#: (bilinear storeys, improved Kelvin contacts, these recorders) is that of
#: models/wu2021-eq14.yaml, so the one run below reuses that scene's compiled kernel.
BASE = """\
title: input error checks
buildings:
  - name: A
    floors: 2
    mass: 1000.0
    story:
      material: bilinear
      stiffness: 4.0e5
      yield_drift: 0.02
      alpha: 0.1
  - name: B
    floors: 2
    mass: 2000.0
    story:
      material: bilinear
      stiffness: 8.0e6
      yield_drift: 0.03
      alpha: 0.1
contacts:
  - name: c1
    nodes: [A/2, B/2]
    gap: 0.001
    law: improved_kelvin
    stiffness: 1.0e7
    restitution: 0.5
excitation:
  kind: sine
  amplitude: 3.0
  frequency: 6.0
analysis:
  dt: 0.001
  duration: 0.2
recorders:
  - kind: history
    quantities: [displacement, velocity, story_force, story_drift, contact_force]
  - kind: envelope
    quantities: [displacement, story_drift, contact_force]
"""

SINE = "excitation:\n  kind: sine\n  amplitude: 3.0\n  frequency: 6.0\n"
RECORD = "excitation:\n  kind: record\n  file: rec.txt\n"
AT2 = "excitation:\n  kind: record\n  file: rec.AT2\n"
AT2_HEAD = "PEER NGA STRONG MOTION DATABASE RECORD\nTEST 1999\nACCELERATION TIME SERIES IN UNITS OF G\n"
GOOD_RECORD = "0.0 0.0\n0.01 0.5\n0.02 -0.3\n"

GENERIC_NODES = """\
nodes:
  - {name: L/1, mass: 1.0}
  - {name: R/1, mass: 2.0}
  - {name: L/1, mass: 3.0}
analysis: {dt: 0.001, duration: 0.01}
"""


def takers(kind: str, name: str) -> str:
    """The built-in laws of ``kind`` whose parameters include ``name``, as the message lists
    them (registry order)."""
    from pframe.laws.registry import builtin_laws

    return ", ".join(law.name for law in builtin_laws(kind) if name in law.Params.model_fields)


def edit(old: str, new: str, text: str = BASE) -> str:
    assert text.count(old) == 1, f"{old!r} is not unique in the base scene"
    return text.replace(old, new)


@dataclass
class Case:
    """``at``: text of the line the message must name (``occurrence`` picks among equal lines);
    ``where``: what follows 'line N' in the message (the field, or ': ...' / ', column')."""

    text: str
    at: str
    where: str
    contains: tuple[str, ...] = ()
    files: dict = field(default_factory=dict)
    occurrence: int = 1


def line_of(text: str, needle: str, occurrence: int = 1) -> int:
    hits = [i for i, line in enumerate(text.splitlines(), start=1) if needle in line]
    assert len(hits) >= occurrence, f"{needle!r} not in the scene"
    return hits[occurrence - 1]


CASES = {
    "yaml-syntax": Case(edit("    gap: 0.001\n", "    gap: 0.001: 2\n"), "gap: 0.001: 2",
                        ", column", ("not valid YAML",)),
    "yaml-tab": Case(edit("    gap: 0.001\n", "\tgap: 0.001\n"), "gap: 0.001", ", column",
                     ("not valid YAML",)),
    "unknown-law": Case(edit("law: improved_kelvin", "law: improved_kelvn"), "law:",
                        ", contacts[0].law",
                        ("unknown contact law 'improved_kelvn'", "known: ", "hertz",
                         "improved_kelvin", "jankowski", "kelvin", "linear")),
    "unknown-material": Case(edit("material: bilinear\n      stiffness: 4.0e5",
                                  "material: bilinar\n      stiffness: 4.0e5"),
                             "bilinar", ", buildings[0].story.material",
                             ("unknown material 'bilinar'", "known: ", "elastic")),
    # YAML booleans in number fields (pydantic alone would read them as 1 and 0)
    "gap-boolean": Case(edit("gap: 0.001", "gap: on"), "gap: on", ", contacts[0].gap",
                        ("expected a number, got the boolean true",)),
    "mass-list-boolean": Case(edit("mass: 1000.0", "mass: [1000.0, yes]"), "mass: [",
                              ", buildings[0].mass[1]", ("got the boolean true",)),
    "iterations-boolean": Case(edit("  duration: 0.2\n", "  duration: 0.2\n  newton:\n"
                                    "    max_iterations: true\n"), "max_iterations: true",
                               ", analysis.newton.max_iterations", ("got the boolean true",)),
    "mass-zero": Case(edit("mass: 1000.0", "mass: 0.0"), "mass: 0.0", ", buildings[0].mass",
                      ("greater than 0",)),
    "mass-negative": Case(edit("mass: 2000.0", "mass: -2000.0"), "mass: -2000.0",
                          ", buildings[1].mass", ("greater than 0",)),
    "mass-list-zero": Case(edit("mass: 1000.0", "mass: [1000.0, 0.0]"), "mass: [",
                           ", buildings[0].mass[1]", ("greater than 0",)),
    "node-mass-zero": Case(GENERIC_NODES.replace("mass: 2.0", "mass: 0"), "R/1",
                           ", nodes[1].mass", ("greater than 0",)),
    "story-stiffness-zero": Case(edit("stiffness: 4.0e5", "stiffness: 0.0"), "stiffness: 0.0",
                                 ", buildings[0].story.stiffness", ("greater than 0",)),
    "story-stiffness-negative": Case(edit("stiffness: 8.0e6", "stiffness: -8.0e6"),
                                     "stiffness: -8.0e6", ", buildings[1].story.stiffness",
                                     ("greater than 0",)),
    "contact-stiffness-zero": Case(edit("stiffness: 1.0e7", "stiffness: 0"), "stiffness: 0",
                                   ", contacts[0].stiffness", ("greater than 0",)),
    "contact-stiffness-negative": Case(edit("stiffness: 1.0e7", "stiffness: -1.0e7"),
                                       "stiffness: -1.0e7", ", contacts[0].stiffness",
                                       ("greater than 0",)),
    "restitution-zero": Case(edit("restitution: 0.5", "restitution: 0"), "restitution",
                             ", contacts[0].restitution", ("greater than 0",)),
    "restitution-negative": Case(edit("restitution: 0.5", "restitution: -0.1"), "restitution",
                                 ", contacts[0].restitution", ("greater than 0",)),
    "restitution-above-one": Case(edit("restitution: 0.5", "restitution: 1.5"), "restitution",
                                  ", contacts[0].restitution", ("less than or equal to 1",)),
    "contact-within-one-building": Case(edit("nodes: [A/2, B/2]", "nodes: [A/1, A/2]"),
                                        "nodes: [A/1", ", contacts[0].nodes", ("'A'",)),
    "contact-to-missing-node": Case(edit("nodes: [A/2, B/2]", "nodes: [A/2, B/9]"),
                                    "nodes: [A/2", ", contacts[0].nodes[1]",
                                    ("no node named 'B/9'",)),
    "negative-gap": Case(edit("gap: 0.001", "gap: -0.001"), "gap:", ", contacts[0].gap",
                         ("greater than or equal to 0",)),
    "duplicate-building": Case(edit("  - name: B\n", "  - name: A\n"), "- name: A",
                               ", buildings[1].name", ("building 'A' is defined twice",),
                               occurrence=2),
    "duplicate-node": Case(GENERIC_NODES, "L/1", ", nodes[2].name",
                           ("node 'L/1' is defined twice",), occurrence=2),
    "duplicate-node-shorthand": Case(BASE + "nodes:\n  - {name: B/2, mass: 5.0}\n",
                                     "{name: B/2", ", nodes[0].name",
                                     ("node 'B/2' is defined twice",)),
    "duplicate-contact": Case(edit("    restitution: 0.5\n", "    restitution: 0.5\n"
                                   "  - {name: c1, nodes: [A/1, B/1], gap: 0.001,\n"
                                   "     law: linear, stiffness: 1.0e6}\n"),
                              "{name: c1", ", contacts[1].name",
                              ("contact name 'c1' is used twice",)),
    "duplicate-default-contact-name": Case(
        edit("  - name: c1\n", "  - {nodes: [A/2, B/2], gap: 0.002, law: linear, "
                               "stiffness: 1.0e6}\n  - name: A/2-B/2\n"),
        "- name: A/2-B/2", ", contacts[1].name", ("contact name 'A/2-B/2' is used twice",)),
    "duplicate-yaml-key": Case(edit("    gap: 0.001\n", "    gap: 0.001\n    gap: 0.002\n"),
                               "gap: 0.002", ": the key 'gap' appears twice",
                               ("contacts[0]",)),
    "dt-zero": Case(edit("dt: 0.001", "dt: 0"), "dt: 0", ", analysis.dt", ("greater than 0",)),
    "dt-negative": Case(edit("dt: 0.001", "dt: -0.001"), "dt:", ", analysis.dt",
                        ("greater than 0",)),
    "record-missing": Case(edit(SINE, RECORD), "file: rec.txt", ", excitation.file",
                           ("rec.txt", "not found")),
    "record-bad-number": Case(edit(SINE, RECORD), "file: rec.txt", ", excitation.file",
                              ("rec.txt, line 3", "'0.02 abc'"),
                              files={"rec.txt": "0.0 0.0\n0.01 0.5\n0.02 abc\n"}),
    "record-one-column": Case(edit(SINE, RECORD), "file: rec.txt", ", excitation.file",
                              ("rec.txt, line 2", "two columns"),
                              files={"rec.txt": "0.0 0.0\n0.01\n0.02 0.5\n"}),
    "record-time-not-increasing": Case(edit(SINE, RECORD), "file: rec.txt", ", excitation.file",
                                       ("rec.txt", "increase"),
                                       files={"rec.txt": "0.0 0.0\n0.02 0.5\n0.01 0.3\n"}),
    "record-repeated-time": Case(edit(SINE, RECORD), "file: rec.txt", ", excitation.file",
                                 ("rec.txt", "increase"),
                                 files={"rec.txt": "0.0 0.0\n0.01 0.5\n0.01 0.3\n"}),
    "at2-header-without-npts-dt": Case(edit(SINE, AT2), "file: rec.AT2", ", excitation.file",
                                       ("rec.AT2, line 4", "NPTS"),
                                       files={"rec.AT2": AT2_HEAD + "4000 POINTS\n0.1 0.2\n"}),
    "at2-fewer-values-than-npts": Case(edit(SINE, AT2), "file: rec.AT2", ", excitation.file",
                                       ("rec.AT2", "NPTS=4000"),
                                       files={"rec.AT2": AT2_HEAD
                                              + "NPTS=  4000, DT=   .0050 SEC\n0.1 0.2 0.3\n"}),
    "frequency-ratio-with-record": Case(edit("stiffness: 1.0e7", "frequency_ratio: 65",
                                             edit(SINE, RECORD)),
                                        "- name: c1", ", contacts[0]",
                                        ("frequency_ratio", "sine"),
                                        files={"rec.txt": GOOD_RECORD}),
    "unknown-field": Case(edit("restitution: 0.5", "restitusion: 0.5"), "restitusion",
                          ", contacts[0].restitusion", ("unknown field",)),
    "unknown-top-level-field": Case(BASE + "dampng: {ratio: 0.02}\n", "dampng",
                                    ", dampng", ("unknown field",)),
    # a line left behind when the law was changed: said so, not "check the spelling"
    "field-of-another-law": Case(
        edit("law: improved_kelvin\n    stiffness: 1.0e7\n    restitution: 0.5",
             "law: linear\n    stiffness: 1.0e7\n    calibration: published"), "calibration",
        ", contacts[0].calibration",
        ("the contact law linear takes no 'calibration' (it takes stiffness, frequency, "
         f"frequency_ratio); {takers('contact', 'calibration')} take it",)),
    "field-of-another-material": Case(
        edit("yield_drift: 0.02\n      alpha: 0.1", "yield_drift: 0.02\n      alpha: 0.1\n"
             "      restitution: 0.5"), "restitution", ", buildings[0].story.restitution",
        ("unknown field",)),  # no material takes it: the spelling may be the mistake
    "field-of-another-material-taken": Case(
        edit("yield_drift: 0.02\n      alpha: 0.1", "yield_drift: 0.02\n      alpha: 0.1\n"
             "      damping: 5.0e3"), "damping", ", buildings[0].story.damping",
        ("the material bilinear takes no 'damping' (it takes stiffness, yield_drift, "
         f"yield_force, alpha); {takers('material', 'damping')} take it",)),
    "duration-below-dt": Case(edit("duration: 0.2", "duration: 0.0001"), "duration:",
                              ", analysis.duration", ("shorter than one step",)),
}

CASES.update({
    "at2-header-without-dt": Case(
        edit(SINE, AT2), "file: rec.AT2", ", excitation.file", ("rec.AT2, line 4",),
        files={"rec.AT2": AT2_HEAD + "NPTS= 4000, TIME STEP MISSING\n0.1 0.2\n"}),
    "per-storey-stiffness-list-with-zero": Case(
        edit("stiffness: 4.0e5", "stiffness: [4.0e5, 0.0]"), "stiffness: [",
        ", buildings[0].story.stiffness", ("greater than 0",)),
})

SENTINEL = b"an existing output file\x00\x01\x02 that bad input must not touch\n"


def _reject(tmp_path, capsys, mode: str, case: Case):
    model = tmp_path / "scene.yaml"
    model.write_text(case.text, encoding="utf-8")
    for name, content in case.files.items():
        (tmp_path / name).write_text(content, encoding="utf-8")
    existing = tmp_path / "existing.h5"
    existing.write_bytes(SENTINEL)
    new = tmp_path / "new.h5"
    before = sorted(p.name for p in tmp_path.iterdir())
    argv = {"validate": ["validate", str(model)],
            "solve": ["solve", str(model), "-o", str(new)],
            "solve-overwrite": ["solve", str(model), "-o", str(existing), "--overwrite"]}[mode]
    code = main(argv)
    out, err = capsys.readouterr()
    assert code == 2, (out, err)
    assert "Traceback" not in err
    assert err.startswith("pframe: ") and err.endswith("\n")
    assert "\n" not in err.rstrip("\n"), "the message is one paragraph"
    line = line_of(case.text, case.at, case.occurrence)
    assert f"{model}, line {line}{case.where}" in err
    for expected in case.contains:
        assert expected in err
    assert sorted(p.name for p in tmp_path.iterdir()) == before  # no output, no temp file
    assert existing.read_bytes() == SENTINEL
    return err


@pytest.mark.parametrize("mode", ["validate", "solve", "solve-overwrite"])
@pytest.mark.parametrize("name", list(CASES))
def test_bad_input_is_reported_at_its_line(tmp_path, capsys, name, mode):
    _reject(tmp_path, capsys, mode, CASES[name])


@pytest.mark.parametrize("old, new", [
    ("stiffness: 4.0e5", "stiffness: [4.0e5, 3.0e5]"),
    ("yield_drift: 0.03", "yield_drift: [0.03, 0.04]"),
    ("yield_drift: 0.02\n      alpha: 0.1", "yield_drift: 0.02\n      alpha: [0.1, 0.2]"),
], ids=["stiffness", "yield_drift", "alpha"])
def test_per_storey_lists_are_accepted(tmp_path, capsys, old, new):
    model = tmp_path / "scene.yaml"
    model.write_text(edit(old, new), encoding="utf-8")
    assert main(["validate", str(model)]) == 0


@pytest.mark.parametrize("text", [
    edit("restitution: 0.5", "restitution: 1.0"),
    edit("restitution: 0.5", "restitution: 1"),
    edit("gap: 0.001", "gap: 0.0"),
    edit(SINE, RECORD),
])
def test_edge_values_are_valid(tmp_path, capsys, text):
    (tmp_path / "rec.txt").write_text(GOOD_RECORD, encoding="utf-8")
    model = tmp_path / "scene.yaml"
    model.write_text(text, encoding="utf-8")
    assert main(["validate", str(model)]) == 0
    out, err = capsys.readouterr()
    assert err == "" and "valid" in out


def test_missing_model_file(tmp_path, capsys):
    missing = tmp_path / "nothere.yaml"
    assert main(["solve", str(missing), "-o", str(tmp_path / "out.h5")]) == 2
    err = capsys.readouterr().err
    assert str(missing) in err and "no such model file" in err and "Traceback" not in err
    assert list(tmp_path.iterdir()) == []


@pytest.mark.parametrize("text, what", [
    ("", "holds nothing"),
    ("- 1\n- 2\n", "holds list"),
])
def test_scene_must_be_a_mapping(tmp_path, capsys, text, what):
    model = tmp_path / "scene.yaml"
    model.write_text(text, encoding="utf-8")
    assert main(["validate", str(model)]) == 2
    err = capsys.readouterr().err
    assert str(model) in err and what in err and "Traceback" not in err


def test_output_folder_must_exist(tmp_path, capsys):
    model = tmp_path / "scene.yaml"
    model.write_text(BASE, encoding="utf-8")
    out = tmp_path / "no" / "such" / "folder" / "out.h5"
    assert main(["solve", str(model), "-o", str(out)]) == 2
    err = capsys.readouterr().err
    assert "does not exist" in err and str(out) in err and "Traceback" not in err
    assert sorted(p.name for p in tmp_path.iterdir()) == ["scene.yaml"]


def test_existing_output_needs_overwrite(tmp_path, capsys):
    model = tmp_path / "scene.yaml"
    model.write_text(BASE, encoding="utf-8")
    out = tmp_path / "out.h5"
    out.write_bytes(SENTINEL)
    assert main(["solve", str(model), "-o", str(out)]) == 2
    err = capsys.readouterr().err
    assert str(out) in err and "--overwrite" in err and "Traceback" not in err
    assert "\n" not in err.rstrip("\n")
    assert out.read_bytes() == SENTINEL
    assert sorted(p.name for p in tmp_path.iterdir()) == ["out.h5", "scene.yaml"]

    assert main(["solve", str(model), "-o", str(out), "--overwrite", "-q"]) == 0
    captured = capsys.readouterr()
    assert captured.out == "" and captured.err == ""
    with h5py.File(out, "r") as f:
        assert f.attrs["complete"] == 1
        assert f.attrs["input_yaml"].decode() == BASE  # NC_CHAR: bytes in h5py
    assert sorted(p.name for p in tmp_path.iterdir()) == ["out.h5", "scene.yaml"]


@pytest.mark.parametrize("name, expected", [
    ("mass-zero", "line 5, buildings[0].mass"),
    ("story-stiffness-zero", "line 8, buildings[0].story.stiffness"),
    ("restitution-above-one", "line 25, contacts[0].restitution"),
    ("contact-to-missing-node", "line 21, contacts[0].nodes[1]"),
    ("frequency-ratio-with-record", "line 20, contacts[0]"),
    ("duplicate-building", "line 11, buildings[1].name"),
    ("dt-zero", "line 31, analysis.dt"),
])
def test_line_numbers_by_hand(tmp_path, capsys, name, expected):
    """The line arithmetic checked against numbers counted by hand in BASE."""
    err = _reject(tmp_path, capsys, "validate", CASES[name])
    assert f"scene.yaml, {expected}" in err
