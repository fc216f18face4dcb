"""docs/first-scene.md runs as written: its files are written from the page's yaml blocks
(a block whose first line is ``# NAME.yaml``), then every ``pframe`` command of its bash blocks
and every python block run in order in one folder, with the record the page names taken from
the PEER records folder. The numbers the page quotes are checked against the run."""

from __future__ import annotations

import contextlib
import io
import re
import shlex
from pathlib import Path

import pytest

import pframe
from pframe.cli import main

REPO = Path(__file__).resolve().parents[1]
PAGE = REPO / "docs" / "first-scene.md"
RECORDS = REPO.parent / "shared" / "records"  # beside the clone, as conftest.RECORDS
FENCE = re.compile(r"^```(\w+)\n(.*?)^```", re.M | re.S)


def _blocks() -> list[tuple[str, str]]:
    return [(m.group(1), m.group(2)) for m in FENCE.finditer(PAGE.read_text(encoding="utf-8"))]


def _quoted(after: str) -> list[str]:
    """The lines of the first text block after the bash block holding ``after``."""
    blocks = _blocks()
    for i, (language, text) in enumerate(blocks):
        if language == "bash" and after in text:
            return next(t for lang, t in blocks[i + 1:] if lang == "text").splitlines()
    raise AssertionError(f"no bash block with {after!r}")


def test_the_page_is_linked_from_readme_and_getting_started():
    for page in (REPO / "README.md", REPO / "docs" / "getting-started.md"):
        assert "first-scene.md" in page.read_text(encoding="utf-8"), page


@pytest.mark.slow
def test_the_page_runs_as_written(tmp_path, monkeypatch):
    record = RECORDS / "ARL360.at2"
    if not record.is_file():
        pytest.skip(f"the PEER record {record} is absent (the page's record, NGA-West2 RSN 949)")
    pytest.importorskip("matplotlib")
    pytest.importorskip("xarray")
    (tmp_path / "records").mkdir()
    (tmp_path / "records" / "ARL360.at2").symlink_to(record)
    monkeypatch.chdir(tmp_path)
    outputs = {}
    commands = 0
    for language, text in _blocks():
        first = text.splitlines()[0] if text else ""
        if language == "yaml" and re.fullmatch(r"# [\w.-]+\.yaml", first):
            (tmp_path / first[2:]).write_text(text, encoding="utf-8")
        elif language == "bash":
            for line in text.splitlines():
                if not line.startswith("pframe "):
                    continue
                out, err = io.StringIO(), io.StringIO()
                with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
                    code = main(shlex.split(line)[1:])
                assert code == 0, f"{line}: exit {code}: {err.getvalue()}"
                outputs[line] = (out.getvalue(), err.getvalue())
                commands += 1
        elif language == "python":
            out = io.StringIO()
            with contextlib.redirect_stdout(out):
                exec(compile(text, f"{PAGE.name} python block", "exec"), {})
    assert commands >= 6
    assert (tmp_path / "frames-level5.png").is_file() and (tmp_path / "stiffness.png").is_file()

    # what the page quotes is what the commands print
    validate_out, validate_err = outputs["pframe validate frames.yaml"]
    assert validate_out.splitlines() == _quoted("pframe validate frames.yaml")
    assert validate_err == ""
    solve_out = outputs["pframe solve frames.yaml -o frames.nc"][0].splitlines()
    quoted = _quoted("pframe solve frames.yaml")
    assert quoted == [line for line in solve_out if line in quoted]
    assert len(quoted) == 9
    sweep_err = outputs["pframe validate stiffness.yaml"][1]
    assert "variant 2 (stiffness=3e+10): dt = 0.002 s" in sweep_err
    assert "with 18.0 steps, fewer than 20" in sweep_err

    with pframe.open(tmp_path / "stiffness.nc") as ds:
        peak_a = ds.building_peak_displacement.sel(building_name="A").values
        force = ds.peak_contact_force.sel(contact_name="floor-5").values
        warnings = ds.attrs["warnings"]
    assert [f"{v:.4f}" for v in peak_a] == ["0.0840", "0.0817", "0.0802"]
    assert [f"{v:.2g}" for v in force] == ["5.5e+06", "9.9e+06", "1.6e+07"]
    assert "with 18.0 steps, fewer than 20" in warnings
    table = _quoted("pframe accuracy frames.yaml")
    printed = outputs[next(k for k in outputs if k.startswith("pframe accuracy"))][0]
    for quoted_row in table[1:]:  # the error columns (not the timings) agree
        name, dt = quoted_row.split()[:2]
        row = next(r for r in printed.splitlines() if r.split()[:2] == [name, dt])
        assert row.split()[3:6] == quoted_row.split()[3:6], (row, quoted_row)


def test_the_warning_the_page_quotes_for_a_coarse_step(tmp_path, monkeypatch, capsys):
    record = RECORDS / "ARL360.at2"
    if not record.is_file():
        pytest.skip(f"the PEER record {record} is absent (the page's record, NGA-West2 RSN 949)")
    (tmp_path / "records").mkdir()
    (tmp_path / "records" / "ARL360.at2").symlink_to(record)
    monkeypatch.chdir(tmp_path)
    scene = next(t for lang, t in _blocks() if lang == "yaml" and t.startswith("# frames.yaml"))
    (tmp_path / "frames.yaml").write_text(scene.replace("dt: 0.002,", "dt: 0.01,"),
                                          encoding="utf-8")
    assert main(["validate", "frames.yaml"]) == 0
    quoted = [line for line in PAGE.read_text(encoding="utf-8").splitlines()
              if line.startswith("pframe: warning: frames.yaml: dt = 0.01 s")]
    assert capsys.readouterr().err.strip().splitlines() == quoted
