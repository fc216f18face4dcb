"""Record files and ground-motion suites: every shared PEER record read with its header's NPTS
and DT, malformed headers named by file and line, suites scaled to PGA and Sa levels."""

import math
import re
from pathlib import Path

import numpy as np
import pytest

from pframe.errors import InputError
from pframe.excitation import read_record
from pframe.excitation.records import G
from pframe.excitation.spectrum import spectral_acceleration
from pframe.excitation.suite import Measure, load_suite, scale_factors, suite_from_files

REPO = Path(__file__).resolve().parents[1]
RECORDS = (REPO / ".." / "shared" / "records").resolve()
needs_records = pytest.mark.skipif(
    not RECORDS.is_dir(), reason=f"the PEER records folder {RECORDS} (../shared/records "
    "beside the repository) is absent; the records are not part of the project")


def _header(path: Path) -> tuple[int, float, list[float]]:
    """NPTS, DT and the values of an AT2 file, read independently of pframe's reader."""
    lines = path.read_text().splitlines()
    npts = int(re.search(r"NPTS\s*=\s*(\d+)", lines[3]).group(1))
    dt = float(re.search(r"DT\s*=\s*([0-9.Ee+-]+)", lines[3]).group(1))
    return npts, dt, [float(x) for x in " ".join(lines[4:]).split()]


@needs_records
def test_every_shared_record_is_read_with_its_header():
    files = sorted(p for p in RECORDS.iterdir() if p.suffix.lower() == ".at2")
    assert len(files) >= 4
    for path in files:
        npts, dt, values = _header(path)
        t, a = read_record(path)
        assert t.size == npts == len(values), path.name
        assert t[1] - t[0] == pytest.approx(dt, rel=1e-12) and t[-1] == pytest.approx((npts - 1) * dt)
        assert a[-1] == pytest.approx(values[-1] * G, rel=1e-15), path.name  # no value lost


HEAD = "PEER NGA STRONG MOTION DATABASE RECORD\nEVENT, STATION\nACCELERATION TIME SERIES IN UNITS OF G\n"


@pytest.mark.parametrize("body, where, what", [
    ("NPTS= 3, DT= .0100 SEC\n0.1 0.2\n", "line 4", "NPTS=3 but 2 values"),
    ("NPTS= 2, DT= .0100 SEC\n0.1 0.2 0.3\n", "line 4", "NPTS=2 but 3 values"),
    ("NPTS= 3, DT= -.0100 SEC\n0.1 0.2 0.3\n", "line 4", "DT > 0"),
    ("THE STEP IS 0.01 SEC\n0.1 0.2 0.3\n", "line 4", "NPTS"),
    ("NPTS= 3, DT= .0100 SEC\n0.1 0.2\n0.3x\n", "line 6", "'0.3x' is not a number"),
])
def test_malformed_at2_names_file_and_line(tmp_path, body, where, what):
    path = tmp_path / "bad.AT2"
    path.write_text(HEAD + body)
    with pytest.raises(ValueError) as info:
        read_record(path)
    assert f"bad.AT2, {where}" in str(info.value) and what in str(info.value)


def _write_at2(path: Path, acc_g, dt=0.01):
    with open(path, "w") as f:
        f.write(HEAD + f"NPTS= {len(acc_g)}, DT= {dt:.4f} SEC\n")
        for chunk in np.array_split(np.asarray(acc_g), max(1, len(acc_g) // 5)):
            f.write(" ".join(f"{x:.10E}" for x in chunk) + "\n")


def test_suite_file_scales_and_levels(tmp_path):
    t = np.arange(0, 10, 0.01)
    _write_at2(tmp_path / "one.AT2", 0.2 * np.sin(2 * np.pi * t) * np.exp(-t / 3))
    np.savetxt(tmp_path / "two.txt", np.column_stack([t, 3.0 * np.sin(5 * t) * np.exp(-t / 2)]))
    (tmp_path / "suite.yaml").write_text(
        "records:\n  - one.AT2\n  - {file: two.txt, scale: 2.0}\nmeasure: {kind: pga}\n")
    suite = load_suite(tmp_path / "suite.yaml")
    assert suite.names == ["one.AT2", "two.txt"]
    levels, factors, ims = scale_factors(suite)
    assert levels.tolist() == [1.0] and factors.tolist() == [[1.0], [1.0]]
    pga_two = np.max(np.abs(3.0 * np.sin(5 * t) * np.exp(-t / 2))) * 2.0 / G
    assert ims[1] == pytest.approx(pga_two, rel=1e-12)
    levels, factors, ims = scale_factors(suite, levels=[0.1, 0.4])
    for r in range(2):  # each record scaled to each level's PGA
        for j, level in enumerate(levels):
            scaled = suite.motions[r].acceleration * factors[r, j]
            assert np.max(np.abs(scaled)) / G == pytest.approx(level, rel=1e-12)


def test_sa_scaling_at_a_named_period_and_at_a_buildings_period(tmp_path):
    t = np.arange(0, 10, 0.01)
    _write_at2(tmp_path / "one.AT2", 0.2 * np.sin(2 * np.pi * t) * np.exp(-t / 3))
    suite = suite_from_files([tmp_path / "one.AT2"])
    for period, by_building in ((0.5, None), ("B", {"A": 0.3, "B": 0.8})):
        chosen = Measure(kind="sa", period=period, damping=0.05)
        import dataclasses

        levels, factors, _ = scale_factors(dataclasses.replace(suite, measure=chosen),
                                           by_building, levels=[0.3])
        motion = suite.motions[0]
        t_sa = 0.8 if period == "B" else 0.5
        sa = spectral_acceleration(motion.acceleration * factors[0, 0], motion.dt, t_sa, 0.05)
        assert sa / G == pytest.approx(0.3, rel=1e-12)
    with pytest.raises(InputError, match="neither seconds nor a building"):
        scale_factors(dataclasses.replace(suite, measure=Measure(kind="sa", period="C")),
                      {"A": 0.3}, levels=[0.3])


def test_suite_errors_name_file_and_line(tmp_path):
    (tmp_path / "suite.yaml").write_text("records:\n  - missing.AT2\n")
    with pytest.raises(InputError, match=r"suite.yaml, line 2, records\[0\]: record file"):
        load_suite(tmp_path / "suite.yaml")
    (tmp_path / "suite.yaml").write_text("records: [a.AT2]\nlevels: [0.1, -0.2]\n")
    with pytest.raises(InputError, match=r"suite.yaml, line 2, levels\[1\]"):
        load_suite(tmp_path / "suite.yaml")
    (tmp_path / "bad.AT2").write_text(HEAD + "NPTS= 3, DT= .01 SEC\n0.1 0.2\n")
    (tmp_path / "suite.yaml").write_text("records: [bad.AT2]\n")
    with pytest.raises(InputError, match=r"suite.yaml, line 1, records\[0\]: malformed record: "
                                         r".*bad.AT2, line 4"):
        load_suite(tmp_path / "suite.yaml")


@needs_records
def test_folder_suite_reads_every_shared_record():
    suite = load_suite(RECORDS)
    assert len(suite.motions) == len([p for p in RECORDS.iterdir() if p.suffix.lower() == ".at2"])
    assert all(math.isclose(m.dt, _header(Path(m.source))[1]) for m in suite.motions)


@needs_records
def test_validate_reads_a_suite_file(tmp_path, capsys):
    """pframe validate recognises a suite file: its structure, then each record read as the
    audit reads it, or named when it is not beside the suite."""
    from pframe.cli import main

    suite = tmp_path / "suite.yaml"
    suite.write_text("records: [elCentro.AT2, {file: missing.AT2, scale: 2.0}]\n"
                     "measure: {kind: sa, period: 0.5}\n")
    (tmp_path / "elCentro.AT2").symlink_to(RECORDS / "elCentro.AT2")
    assert main(["validate", str(suite)]) == 0
    out = capsys.readouterr().out
    assert "valid; a ground-motion suite of 2 records, levels in sa" in out
    assert "1559 points, dt = 0.02 s" in out and "missing.AT2: not beside the suite" in out
    suite.write_text("records: [elCentro.AT2]\nmeasure: {kind: pgv}\n")
    assert main(["validate", str(suite)]) == 2
    assert "line 2, measure.kind" in capsys.readouterr().err
