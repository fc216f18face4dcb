"""What a user is told: the restitution a published damping formula really gives (and the one
line that gets the requested one), how each record file was read, what kind of input file
``pframe validate`` was given.

The restitution warning is checked against the kernel: the value it announces is the rebound
that two free masses run through pframe actually show. The record facts are checked against
an independent reading of the file (header and values parsed here, SHA-256 by hashlib).
"""

from __future__ import annotations

import hashlib
import json
import re
import shutil
from pathlib import Path

import h5py
import numpy as np
import pytest
from conftest import node_history, run_text, two_free_masses_text

from pframe.cli import main
from pframe.excitation.describe import describe_line, describe_record
from pframe.reader import parse_scene

REPO = Path(__file__).resolve().parents[1]
MODELS = REPO / "models"
RECORDS = REPO.parent / "shared" / "records"  # beside the clone, as conftest.RECORDS
G = 9.80665
M_LEFT, M_RIGHT, V_IMPACT = 1000.0, 3000.0, 0.5
REBOUND = re.compile(r"rebounds with ([0-9.]+)")

#: (contact, dt, duration): cases whose published formula misses e by more than 0.02
MISSED = {
    "hertzdamp-muthukumar": ({"law": "hertzdamp", "stiffness": 1.0e9, "restitution": 0.65},
                             1.0e-5, 0.03),
    "hertzdamp-ye": ({"law": "hertzdamp", "stiffness": 1.0e9, "restitution": 0.3,
                      "formula": "ye"}, 1.0e-5, 0.03),
    "improved_kelvin": ({"law": "improved_kelvin", "stiffness": 1.0e7, "restitution": 0.2},
                        2.0e-5, 0.04),
    "kelvin-clipped": ({"law": "kelvin", "stiffness": 1.0e7, "restitution": 0.4},
                       2.0e-5, 0.04),
}


def _impact(contact: dict, dt: float, duration: float) -> str:
    return two_free_masses_text(M_LEFT, M_RIGHT, contact, V_IMPACT, 0.0, dt, duration)


@pytest.mark.parametrize("case", list(MISSED))
def test_the_warning_announces_the_rebound_the_kernel_gives(case):
    """Default calibration, a restitution the published formula misses: one warning naming
    the contact, the law, the source, the value it rebounds with and `calibration: exact`;
    the announced value is what two free masses run through the kernel rebound with."""
    contact, dt, duration = MISSED[case]
    plan, result = run_text(_impact(contact, dt, duration))
    warned = [w for w in plan.warnings if "calibration" in w]
    assert len(warned) == 1, plan.warnings
    assert warned[0].startswith(f"contact c ({contact['law']}): restitution "
                                f"{contact['restitution']:g} is asked for")
    assert "add 'calibration: exact' to the contact" in warned[0]
    announced = float(REBOUND.search(warned[0]).group(1))
    assert abs(announced - contact["restitution"]) > 0.02
    v_left = node_history(plan, result, "velocity", "L/1")
    v_right = node_history(plan, result, "velocity", "R/1")
    assert result.impacts[0, 0] == 1
    kernel = -(v_left[-1] - v_right[-1]) / V_IMPACT
    assert kernel == pytest.approx(announced, abs=2e-3), (kernel, announced)


@pytest.mark.parametrize("contact", [
    {"law": "jankowski", "stiffness": 1.0e9, "restitution": 0.4},  # 0.393: within 0.02
    {"law": "improved_kelvin", "stiffness": 1.0e7, "restitution": 0.6},  # 0.594
    {"law": "kelvin", "stiffness": 1.0e7, "restitution": 0.4, "keep_tension": True},  # exact
    {"law": "hertzdamp", "stiffness": 1.0e9, "restitution": 0.65, "calibration": "exact"},
    {"law": "linear", "stiffness": 1.0e7},
])
def test_no_warning_where_the_requested_restitution_is_obtained(contact):
    ex = parse_scene(_impact(contact, 1e-4, 0.01)).expanded
    assert ex.warnings == () and ex.notes == ()


def test_a_written_published_calibration_is_a_note_not_a_warning():
    contact = {"law": "hertzdamp", "stiffness": 1.0e9, "restitution": 0.65,
               "calibration": "published"}
    ex = parse_scene(_impact(contact, 1e-4, 0.01)).expanded
    assert ex.warnings == ()
    assert len(ex.notes) == 1
    assert "calibration: published, Muthukumar & DesRoches 2006" in ex.notes[0]
    assert float(REBOUND.search(ex.notes[0]).group(1)) == pytest.approx(0.775, abs=1e-3)


def test_validate_and_solve_say_so_and_the_file_keeps_it(tmp_path, capsys):
    contact, dt, duration = MISSED["hertzdamp-muthukumar"]
    scene = tmp_path / "impact.yaml"
    scene.write_text(_impact(contact, dt, duration), encoding="utf-8")
    assert main(["validate", str(scene)]) == 0
    err = capsys.readouterr().err
    assert f"pframe: warning: {scene}: contact c (hertzdamp): restitution 0.65" in err
    assert "add 'calibration: exact'" in err
    out = tmp_path / "impact.h5"
    assert main(["solve", str(scene), "-o", str(out)]) == 0
    assert "rebounds with 0.775" in capsys.readouterr().err
    with h5py.File(out, "r") as f:
        stored = f.attrs["warnings"]
    stored = stored.decode() if isinstance(stored, bytes) else str(stored)
    assert "contact c (hertzdamp): restitution 0.65 is asked for" in stored
    assert "rebounds with 0.775" in stored


def test_the_paper_scene_chooses_the_published_formula_in_writing(capsys):
    """models/wu2021-eq14.yaml says calibration: published (the paper's formula): validate
    notes what it rebounds with and warns of nothing about restitution."""
    assert main(["validate", str(MODELS / "wu2021-eq14.yaml")]) == 0
    captured = capsys.readouterr()
    assert "calibration" not in captured.err
    assert ("note: contacts floor-1, floor-2, floor-3 (improved_kelvin, calibration: "
            "published, Ye, Li & Zhu 2009): restitution 0.4 rebounds with 0.380") in captured.out


# ---------------------------------------------------------------------------------------------
# how records were read
# ---------------------------------------------------------------------------------------------

AT2 = """PEER NGA STRONG MOTION DATABASE RECORD
Test record, component 000
ACCELERATION TIME SERIES IN UNITS OF G
NPTS=   7, DT=   .0200 SEC
  .0010  -.0200   .1500  -.2500   .0500
  .0000  -.0100
"""


@pytest.mark.parametrize("suffix", [".AT2", ".at2", ".At2"])
def test_record_facts_of_a_peer_file_in_any_case(tmp_path, suffix):
    path = tmp_path / f"test{suffix}"
    path.write_text(AT2, encoding="utf-8")
    facts = describe_record(path, scale=2.0)
    assert facts["format"] == "at2" and facts["units"] == "g"
    assert facts["points"] == 7 and facts["uniform"]
    assert facts["step"] == pytest.approx(0.02) and facts["duration"] == pytest.approx(0.12)
    assert facts["pga"] == pytest.approx(2.0 * 0.25 * G)
    assert facts["pga_g"] == pytest.approx(0.5)
    assert facts["pga_time"] == pytest.approx(0.06)
    assert facts["sha256"] == hashlib.sha256(path.read_bytes()).hexdigest()
    line = describe_line(facts, duration=1.0)
    assert "PEER NGA .AT2 in g, 7 points, dt = 0.02 s, 0.12 s; PGA x 2 4.903 m/s^2 (0.5 g)" in line
    assert "the ground is at rest after 0.12 s of the 1 s analysed" in line


def test_record_facts_of_a_two_column_file(tmp_path):
    path = tmp_path / "motion.txt"
    path.write_text("# t a\n0.0 0.0\n0.01 1.5\n0.03 -2.5\n0.04 0.5\n", encoding="utf-8")
    facts = describe_record(path)
    assert facts["format"] == "columns" and facts["units"] == "m/s2"
    assert facts["points"] == 4 and not facts["uniform"]
    assert facts["pga"] == pytest.approx(2.5) and facts["pga_time"] == pytest.approx(0.03)
    assert "uneven steps (mean 0.0133333 s)" in describe_line(facts)


def _independent_at2(path: Path) -> tuple[int, float, np.ndarray]:
    lines = path.read_text(encoding="utf-8", errors="replace").splitlines()
    numbers = re.findall(r"[-+]?(?:\d+\.?\d*|\.\d+)(?:[eE][-+]?\d+)?", lines[3])
    n, dt = int(float(numbers[0])), float(numbers[1])
    values = np.array(" ".join(lines[4:]).split(), dtype=float)[:n]
    return n, dt, values


@pytest.mark.skipif(not RECORDS.is_dir(), reason=f"the PEER records folder {RECORDS} is absent")
@pytest.mark.parametrize("name", ["elCentro.AT2", "ARL360.at2"])
def test_record_facts_of_real_peer_records(name):
    path = RECORDS / name
    n, dt, values = _independent_at2(path)
    facts = describe_record(path)
    assert facts["format"] == "at2"  # the lower-case .at2 too
    assert facts["points"] == n and facts["step"] == pytest.approx(dt, rel=1e-9)
    assert facts["duration"] == pytest.approx((n - 1) * dt, rel=1e-9)
    assert facts["pga_g"] == pytest.approx(np.max(np.abs(values)), rel=1e-12)
    assert facts["sha256"] == hashlib.sha256(path.read_bytes()).hexdigest()


def test_validate_and_solve_print_how_the_record_was_read(tmp_path, capsys):
    (tmp_path / "quake.at2").write_text(AT2, encoding="utf-8")
    scene = tmp_path / "scene.yaml"
    scene.write_text(json.dumps({
        "buildings": [{"name": "A", "floors": 1, "mass": 1000.0,
                       "story": {"material": "elastic", "stiffness": 1.0e6}}],
        "excitation": {"kind": "record", "file": "quake.at2"},
        "analysis": {"dt": 0.01, "duration": 0.1},
    }), encoding="utf-8")
    assert main(["validate", str(scene)]) == 0
    out = capsys.readouterr().out
    expected = ("record " + str(tmp_path / "quake.at2") + ": PEER NGA .AT2 in g, 7 points, "
                "dt = 0.02 s, 0.12 s; PGA 2.452 m/s^2 (0.25 g) at t = 0.06 s")
    assert expected in out
    assert "the analysis (0.1 s) stops before the record ends" in out
    assert main(["solve", str(scene), "-o", str(tmp_path / "out.h5")]) == 0
    assert expected in capsys.readouterr().out


# ---------------------------------------------------------------------------------------------
# validate recognises each kind of input file
# ---------------------------------------------------------------------------------------------

@pytest.mark.slow
def test_validate_recognises_scenes_pi_scenes_and_sweeps(capsys):
    assert main(["validate", str(MODELS / "wu2021-eq14-pi.yaml")]) == 0
    assert "valid; a scene in Pi numbers: 6 nodes" in capsys.readouterr().out
    assert main(["validate", str(MODELS / "sweeps" / "wu2021-pi-d.yaml")]) == 0
    out = capsys.readouterr().out
    assert "valid; a sweep of 41 variants (product of Pi_d: 41) of the base scene" in out


def test_validate_reports_a_sweep_mistake_in_the_sweep_file(tmp_path, capsys):
    shutil.copy(MODELS / "wu2021-eq14-pi.yaml", tmp_path / "base.yaml")
    sweep = tmp_path / "sweep.yaml"
    sweep.write_text("base: base.yaml\naxes:\n  - {name: Pi_d, path: pi.Pi_d, linspace: [0, 1]}\n",
                     encoding="utf-8")
    assert main(["validate", str(sweep)]) == 2
    err = capsys.readouterr().err
    assert f"{sweep}, line 3, axes[0].linspace" in err
    assert "unknown field" not in err


# ---------------------------------------------------------------------------------------------
# pframe plot: what the docs say it answers, it answers
# ---------------------------------------------------------------------------------------------

TRANSCRIPT = re.compile(r"```text\n(.*?)```", re.S)


def _plot_transcripts() -> list[tuple[str, list[str], str]]:
    """(page, command arguments, expected stderr) of every ``$ pframe plot`` line in a text
    block of docs/*.md, with the lines after it up to the next ``$``."""
    out = []
    for page in sorted((REPO / "docs").glob("*.md")):
        for block in TRANSCRIPT.findall(page.read_text(encoding="utf-8")):
            command, expected = None, []
            for line in block.splitlines() + ["$ end"]:
                if line.startswith("$ "):
                    if command and command[:2] == ["pframe", "plot"]:
                        out.append((page.name, command[1:], "\n".join(expected)))
                    command, expected = line[2:].split(), []
                elif command:
                    expected.append(line)
    return out


@pytest.fixture(scope="module")
def pi_d_sweep(tmp_path_factory):
    """docs/sweeps.md's pi-d.h5 in small: the shipped Pi_d sweep over 3 values of Pi_d and
    tau = 0 .. 5 (the same dimensions and responses, so the same messages)."""
    folder = tmp_path_factory.mktemp("pi-d")
    base = (MODELS / "wu2021-eq14-pi.yaml").read_text(encoding="utf-8")
    (folder / "base.yaml").write_text(base.replace("\n  tau: 50\n", "\n  tau: 5\n"),
                                      encoding="utf-8")
    sweep = (MODELS / "sweeps" / "wu2021-pi-d.yaml").read_text(encoding="utf-8")
    sweep = sweep.replace("base: ../wu2021-eq14-pi.yaml", "base: base.yaml")
    sweep = sweep.replace("linspace: [0, 2, 41]", "linspace: [0, 2, 3]")
    (folder / "pi-d.yaml").write_text(sweep, encoding="utf-8")
    assert main(["sweep", str(folder / "pi-d.yaml"), "-o", str(folder / "pi-d.h5"), "-q"]) == 0
    return folder


PLOT_TRANSCRIPTS = _plot_transcripts()


def test_the_docs_hold_plot_transcripts():
    assert len(PLOT_TRANSCRIPTS) >= 7, PLOT_TRANSCRIPTS


@pytest.mark.parametrize("page, args, expected", PLOT_TRANSCRIPTS,
                         ids=[" ".join(t[1]) for t in PLOT_TRANSCRIPTS])
def test_plot_answers_as_the_docs_say(pi_d_sweep, monkeypatch, capsys, page, args, expected):
    monkeypatch.chdir(pi_d_sweep)
    code = main(args)
    captured = capsys.readouterr()
    assert captured.err.strip() == expected.strip(), page
    assert code == 2 and not list(pi_d_sweep.glob("*.pdf")) and not list(pi_d_sweep.glob("*.png"))


@pytest.mark.slow
def test_every_choice_list_of_plot_names_choices(pi_d_sweep, monkeypatch, capsys):
    """No message ends in an empty 'choose one of' / 'takes' list, whatever is asked."""
    monkeypatch.chdir(pi_d_sweep)
    asks = [["--curves", "node"], ["--curves", "Pi_d"], ["--curves", "building", "--at",
            "building=A"], ["--at", "story=A/1"], ["--at", "Pi_d=1", "--response", "impact_count"],
            ["--response", "impact_count", "--at", "contact=floor-1", "--curves", "contact"]]
    for ask in asks:
        assert main(["plot", "pi-d.h5", *ask]) == 2
        err = capsys.readouterr().err
        assert not re.search(r"(one of|takes|fixes|axes are)\s*($|[;(])", err), err


def test_a_sweep_option_on_the_file_of_one_run_is_an_error(tmp_path, capsys):
    scene = tmp_path / "impact.yaml"
    scene.write_text(_impact(MISSED["improved_kelvin"][0], 1e-4, 0.02), encoding="utf-8")
    assert main(["solve", str(scene), "-o", str(tmp_path / "run.h5"), "-q"]) == 0
    capsys.readouterr()
    assert main(["plot", str(tmp_path / "run.h5"), "--response", "peak_contact_force"]) == 2
    err = capsys.readouterr().err
    assert "--response does not apply: the file is the result of one run (pframe solve)" in err
    assert "its options are --kind, --story, --time-range, --dimensionless" in err


def test_numbers_are_read_as_yaml_1_2_reads_them(tmp_path):
    """1.0e10 and 1e-3 are numbers (YAML 1.1, PyYAML's default, reads them as text): in a
    scene and as the target of a sweep axis."""
    text = _impact({"law": "hertz", "stiffness": "STIFFNESS"}, 1e-5, 0.001)
    text = text.replace('"STIFFNESS"', "1.0e9").replace('"dt": 1e-05', '"dt": 1e-5')
    from pframe.model.load import _compose

    data, _ = _compose(text, "scene")
    assert data["contacts"][0]["stiffness"] == 1.0e9 and data["analysis"]["dt"] == 1e-5
    (tmp_path / "base.yaml").write_text(text, encoding="utf-8")
    (tmp_path / "sweep.yaml").write_text(
        "base: base.yaml\naxes:\n  - {name: k, path: contacts.c.stiffness, values: [1e9, 2e9]}\n",
        encoding="utf-8")
    assert main(["validate", str(tmp_path / "sweep.yaml")]) == 0


def test_merge_keys_write_repeated_contacts_once(tmp_path):
    """<<: *anchor merges a mapping (keys beside it win); a key written twice is still an error,
    named at its line."""
    text = """\
nodes: [{name: A/1, mass: 1000.0}, {name: A/2, mass: 1000.0},
        {name: B/1, mass: 3000.0}, {name: B/2, mass: 3000.0}]
contacts:
  - &hd {name: c1, nodes: [A/1, B/1], gap: 0.01, law: hertzdamp, stiffness: 1.0e9,
         restitution: 0.6, calibration: exact}
  - {<<: *hd, name: c2, nodes: [A/2, B/2], restitution: 0.8}
analysis: {dt: 0.001, duration: 0.01}
"""
    contacts = parse_scene(text).scene.contacts
    assert [(c.name, c.nodes, c.restitution, c.calibration) for c in contacts] == [
        ("c1", ("A/1", "B/1"), 0.6, "exact"), ("c2", ("A/2", "B/2"), 0.8, "exact")]
    from pframe.errors import InputError

    with pytest.raises(InputError, match=r"line 6: the key 'gap' appears twice"):
        parse_scene(text.replace("restitution: 0.8}", "restitution: 0.8, gap: 0.1, gap: 0.2}"))


def test_validate_prints_the_periods_of_each_building(tmp_path, capsys):
    """A uniform n-storey shear building has w_j = 2 sqrt(k/m) sin((2j - 1) pi / (2 (2n + 1))):
    the periods validate prints are those."""
    import math

    n, m, k = 5, 4.0e5, 7.8e8
    scene = tmp_path / "b.yaml"
    scene.write_text(json.dumps({
        "buildings": [{"name": "B", "floors": n, "mass": m,
                       "story": {"material": "elastic", "stiffness": k}}],
        "analysis": {"dt": 0.01, "duration": 0.1}}), encoding="utf-8")
    assert main(["validate", str(scene)]) == 0
    line = next(x for x in capsys.readouterr().out.splitlines() if "building B" in x)
    printed = [float(v) for v in re.search(r"periods (.*) s \(", line).group(1).split(", ")]
    exact = [2 * math.pi / (2 * math.sqrt(k / m) * math.sin((2 * j - 1) * math.pi / (2 * (2 * n + 1))))
             for j in (1, 2, 3)]
    assert printed == pytest.approx(exact, rel=5e-3)  # 3 significant digits
    assert "building B: 5 floors, periods 0.500, 0.171, 0.109 s" in line
