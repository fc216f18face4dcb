"""Hostile input to the risk chain: every case ends in bounded time with one paragraph naming
the file, the line and the field, exit 2 and nothing written; no input a study reads (the
hazard table included) is ever replaced; ``pframe validate`` refuses what ``pframe risk``
refuses; hazard tables with what no curve can be (NaN or negative frequencies, a malformed
OpenQuake header) are refused, never read as another curve."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest

from pframe.cli import main
from pframe.errors import InputError
from pframe.risk import read_hazard

REPO = Path(__file__).resolve().parents[1]
HAZARD = (REPO / "models" / "risk" / "hazard-power.csv").read_text()


def _study(folder: Path, text: str = "", hazard: str | None = HAZARD) -> Path:
    """The paper's pair under its own pulse (no records needed), a hazard table beside it."""
    if hazard is not None:
        (folder / "hazard.csv").write_text(hazard)
    path = folder / "study.yaml"
    path.write_text(f"scene: {REPO / 'models' / 'wu2021-pulse.yaml'}\n"
                    "measure: pga\n"
                    "design: {kind: msa, levels: [0.2, 0.4, 0.6]}\n"
                    "hazard: {file: hazard.csv}\n"
                    "target: {return_period: 475}\n"
                    "bootstrap: 0\n" + text)
    return path


def _refused(capsys, argv, *says):
    assert main(argv) == 2
    err = capsys.readouterr().err
    assert "Traceback" not in err and err.count("\n") == 1, err
    for s in says:
        assert s in err, err
    return err


@pytest.mark.parametrize("target", ["hazard.csv", "study.yaml"])
def test_an_output_never_replaces_a_file_the_study_reads(tmp_path, capsys, target):
    study = _study(tmp_path)
    before = (tmp_path / target).read_bytes()
    _refused(capsys, ["risk", str(study), "-o", str(tmp_path / target), "--overwrite", "-q"],
             "one of this run's inputs")
    assert (tmp_path / target).read_bytes() == before


def test_a_key_given_twice_is_refused_with_its_line(tmp_path, capsys):
    study = _study(tmp_path, "bootstrap: 5\n")
    for command in (["risk", str(study), "-q"], ["validate", str(study)]):
        _refused(capsys, command, str(study), "line 7", "bootstrap")
    assert not (tmp_path / "study.risk.nc").exists()


@pytest.mark.parametrize("edit, says", [
    ("measure: sa:Z\n", ["line 2", "at measure", "'Z'"]),
    ("measure: sb:1\n", ["line 2", "at measure"]),
    ("measure: sa:-1\n", ["line 2", "at measure"]),
    ("hazard: {file: nowhere.csv}\n", ["line 4", "hazard.file", "nowhere.csv"]),
    ("limits: {drift: {LS: -1}}\n", ["line 7", "limits.drift.LS"]),
])
def test_validate_refuses_what_risk_refuses_naming_the_study_line(tmp_path, capsys, edit,
                                                                    says):
    key = edit.split(":")[0]
    lines = [ln for ln in _study(tmp_path).read_text().splitlines(keepends=True)
             if not ln.startswith(key + ":")]
    study = tmp_path / "study.yaml"
    keep = {"measure": 1, "hazard": 3}.get(key, len(lines))
    study.write_text("".join(lines[:keep]) + edit + "".join(lines[keep:]))
    for command in (["validate", str(study)], ["risk", str(study), "-q"]):
        _refused(capsys, command, str(study), *says)
    assert not (tmp_path / "study.risk.nc").exists()


def test_validate_refuses_a_malformed_hazard_table(tmp_path, capsys):
    study = _study(tmp_path, hazard="IM,AFE\n0.1,0.01\n0.2,nan\n0.3,0.001\n")
    for command in (["validate", str(study)], ["risk", str(study), "-q"]):
        _refused(capsys, command, "hazard.csv, line 3", "nan")


@pytest.mark.parametrize("edit, field", [
    ("dt: 1.0e-9\n", "at dt"),
    ("chunk: 1\nduration: 1.0e+8\n", "at duration"),
    ("duration: 1.0e+6\n", "at duration"),
])
def test_absurd_sizes_are_refused_naming_the_field_that_sets_them(tmp_path, capsys, edit,
                                                                   field):
    study = _stochastic(tmp_path, ", realisations: 2", "{kind: msa, levels: [0.2, 0.4]}")
    study.write_text(study.read_text() + edit)
    err = _refused(capsys, ["risk", str(study), "-q"], str(study), field)
    assert "every k-th" not in err and "envelope" not in err  # a study records nothing


@pytest.mark.parametrize("edit, field", [("dt: 0.001\n", "at dt"),
                                         ("duration: 5.0\n", "at duration")])
def test_a_step_or_duration_the_scene_s_own_excitation_ignores_is_refused(tmp_path, capsys,
                                                                          edit, field):
    _refused(capsys, ["risk", str(_study(tmp_path, edit)), "-q"], "line 7", field)


def _stochastic(folder: Path, motion: str, design: str) -> Path:
    path = folder / "study.yaml"
    path.write_text(f"scene: {REPO / 'models' / 'wu2021-eq14.yaml'}\n"
                    "stochastic: {model: clough_penzien, intensity: 0.02, ground_frequency: "
                    f"15.0, ground_damping: 0.6, duration: 8.0, step: 0.01{motion}}}\n"
                    f"design: {design}\npounding_runs: false\n")
    return path


@pytest.mark.parametrize("motion, design, field", [
    (", realisations: 100000000", "{kind: msa, levels: [0.2, 0.4]}",
     "stochastic.realisations"),
    ("", "{kind: subset, samples: 1000000000}", "design.samples"),
])
def test_absurd_counts_are_refused_at_once(tmp_path, capsys, motion, design, field):
    study = _stochastic(tmp_path, motion, design)
    _refused(capsys, ["risk", str(study), "-q", "-o", str(tmp_path / "out.nc")], field)
    assert not (tmp_path / "out.nc").exists()


def test_subset_stripes_above_the_hazard_table_are_refused(tmp_path, capsys):
    (tmp_path / "hazard.csv").write_text("0.01,0.1\n0.1,0.001\n")
    study = tmp_path / "study.yaml"
    study.write_text(f"scene: {REPO / 'models' / 'wu2021-pulse.yaml'}\n"
                     f"suite: {REPO / 'models' / 'suites' / 'peer-records.yaml'}\n"
                     "uncertain: {gap: {distribution: lognormal, median: 0.05, "
                     "dispersion: 0.3}}\n"
                     "design: {kind: subset, levels: [0.2, 0.4]}\n"
                     "hazard: {file: hazard.csv}\n")
    _refused(capsys, ["risk", str(study), "-q"], "line 4", "design.levels", "above")


# --------------------------------------------------------------------------------------------
# hazard tables
# --------------------------------------------------------------------------------------------

def _oq(time: str, head: str, values: str) -> str:
    return (f'#,,,,"generated_by=\'OpenQuake engine\', investigation_time={time}"\n'
            f"lon,lat,depth,{head}\n-118.2,34.05,0.0,{values}\n")


@pytest.mark.parametrize("text, says", [
    ("IM,AFE\n0.1,0.01\n0.2,nan\n0.3,0.001\n", "line 3"),
    ("IM,AFE\n0.1,0.01\n0.2,-0.002\n0.3,0.001\n", "line 3"),
    ("0.1,0.01\n-0.2,0.005\n0.3,0.001\n", "line 2"),
    ("0.1,0.01\n0.1,0.005\n0.3,0.001\n", "given twice"),
    ("lon,lat,0.1,0.2\n1,2,0.01,nan\n", "line 2, column 4"),
    (_oq("0", "poe-0.1,poe-0.2", "0.1,0.05"), "investigation_time"),
    (_oq("-50", "poe-0.1,poe-0.2", "0.1,0.05"), "investigation_time"),
    (_oq("abc", "poe-0.1,poe-0.2", "0.1,0.05"), "investigation_time"),
    (_oq("50", "poe-0.1,poe-x", "0.1,0.05"), "'poe-x'"),
    (_oq("50", "poe-0.1,poe-0.2", "0.1,abc"), "'abc'"),
    (_oq("50", "poe-0.1,poe-0.2", "0.1,1.0"), "[0, 1)"),
    (_oq("50", "poe-0.1,poe-0.2", "0.1"), "values under"),
])
def test_malformed_hazard_tables_are_refused_naming_the_place(tmp_path, text, says):
    path = tmp_path / "hazard.csv"
    path.write_text(text)
    with pytest.raises(InputError, match=None) as info:
        read_hazard(path)
    assert str(path) in str(info.value) and says in str(info.value)


def test_hostile_hazard_rows_generated_are_refused_or_read_exactly(tmp_path):
    """Rows of a good table with one value replaced by something no curve can be (generated
    over every row and column): refused, naming the line; the good table reads exactly."""
    x = np.geomspace(0.05, 3.0, 8)
    lam = 2e-4 * x ** -2.2
    good = tmp_path / "good.csv"
    good.write_text("".join(f"{float(a)!r},{float(b)!r}\n" for a, b in zip(x, lam)))
    assert read_hazard(good).frequency == pytest.approx(lam, rel=1e-15)
    for row in range(8):
        for col in range(2):
            for bad in ("nan", "-1", "inf", "x", ""):
                cells = [[repr(float(a)), repr(float(b))] for a, b in zip(x, lam)]
                cells[row][col] = bad
                path = tmp_path / "bad.csv"
                path.write_text("".join(",".join(c) + "\n" for c in cells))
                with pytest.raises(InputError) as info:
                    read_hazard(path)
                assert f"line {row + 1}" in str(info.value), (row, col, bad, info.value)


def test_zeros_at_the_top_of_a_table_end_the_curve(tmp_path):
    path = tmp_path / "hazard.csv"
    path.write_text("0.1,0.01\n0.2,0.001\n0.4,0\n0.8,0\n")
    curve = read_hazard(path)
    assert list(curve.im) == [0.1, 0.2] and math.isnan(float(curve.rate(0.3)))
