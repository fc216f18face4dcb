"""The summary table of a run (pframe.summary, pframe summary, pframe solve --summary) and the
export of histories as CSV (pframe export): the numbers are the result's own (peaks of the
histories, the paper's eight impacts per level, a closed energy balance, ductility against
the scene's yield drift in the file's units)."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pandas as pd
import pytest

import pframe
from pframe.cli import main

MODELS = Path(__file__).resolve().parents[1] / "models"
L_E = 9.81 / (2 * math.pi) ** 2  # the paper's length scale a_p / w_p^2


@pytest.fixture(scope="module")
def run(tmp_path_factory):
    out = tmp_path_factory.mktemp("summary") / "eq14.nc"
    assert main(["solve", str(MODELS / "wu2021-eq14.yaml"), "-o", str(out), "-q",
                 "--summary", str(out.with_suffix(".md"))]) == 0
    return out


def _value(table, part, name, quantity):
    row = table[(table.part == part) & (table.name == name) & (table.quantity == quantity)]
    assert len(row) == 1, (part, name, quantity)
    return row.value.iloc[0]


@pytest.mark.slow
def test_peaks_impacts_energy_and_ductility_are_the_runs(run):
    table = pframe.summary(run)
    with pframe.open(run) as ds:
        displacement = abs(ds.displacement).max("t")
        drift = abs(ds.story_drift).max("t")
        for node in ds.node.values:
            assert _value(table, "node", node, "peak displacement") == pytest.approx(
                float(displacement.sel(node=node)), rel=1e-12)
        for contact in ds.contact.values:  # the paper's example: 8 impacts at each level
            assert _value(table, "contact", contact, "impacts") == 8
            assert _value(table, "contact", contact, "peak contact force") == pytest.approx(
                float(abs(ds.contact_force.sel(contact=contact)).max()), rel=1e-12)
    # yield drifts of the scene (u_ya = 0.1 l_e, u_yb = 0.06 l_e): ductility = peak / yield
    for story, yield_drift in (("A/1", 0.1 * L_E), ("B/2", 0.06 * L_E)):
        assert _value(table, "story", story, "yield drift") == pytest.approx(yield_drift, rel=1e-12)
        assert _value(table, "story", story, "ductility (peak drift / yield drift)") == \
            pytest.approx(float(drift.sel(story=story)) / yield_drift, rel=1e-12)
    # the energy balance closes: input = kinetic + damping + storeys + contacts + algorithmic
    energy = table[table.part == "energy"].set_index("quantity").value.astype(float)
    parts = energy[["kinetic", "damping", "storeys", "contacts", "algorithmic"]].sum()
    assert parts - energy["initial kinetic"] == pytest.approx(energy["input"], rel=1e-9)
    assert _value(table, "run", "", "accuracy (energy verdict)") == "trusted"
    assert set(table[table.part == "energy"].units) == {"J"}


@pytest.mark.slow
def test_markdown_and_csv_hold_the_table(run, tmp_path):
    table = pframe.summary(run, tmp_path / "s.csv")
    back = pd.read_csv(tmp_path / "s.csv", keep_default_na=False)
    assert back.quantity.tolist() == table.quantity.tolist()
    numbers = pd.to_numeric(back.value, errors="coerce")
    mine = pd.to_numeric(table.value, errors="coerce")
    assert np.allclose(numbers.dropna(), mine.dropna(), rtol=1e-12)
    text = run.with_suffix(".md").read_text(encoding="utf-8")  # pframe solve --summary
    force = _value(table, "contact", "floor-3", "peak contact force")
    impacts = _value(table, "contact", "floor-3", "impacts")
    assert f"\n| floor-3 | {force:.6g} | {impacts} |\n" in text  # a row per contact
    assert text.count("\n| A/") == 6 and text.count("\n| B/") == 6  # a row per node, storey
    # the only warning: the sine drives the buildings to the end, so the final drifts are not
    # permanent ones
    warnings = text.split("## Warnings\n\n")[1].strip().splitlines()
    assert len(warnings) == 1 and "the run ends while storeys still swing" in warnings[0]


@pytest.mark.slow
def test_a_dimensionless_result_gives_ductility_in_its_units(tmp_path):
    out = tmp_path / "pi.nc"
    assert main(["solve", str(MODELS / "wu2021-eq14-pi.yaml"), "-o", str(out), "-q"]) == 0
    table = pframe.summary(out)
    assert _value(table, "story", "A/1", "yield drift") == pytest.approx(0.1, rel=1e-9)
    assert _value(table, "story", "B/1", "yield drift") == pytest.approx(0.06, rel=1e-9)
    assert set(table[table.part == "energy"].units) == {"1"}


@pytest.mark.slow
def test_export_writes_each_history_with_names_and_units(run, tmp_path, capsys):
    assert main(["export", str(run), "--csv", str(tmp_path / "csv")]) == 0
    frame = pd.read_csv(tmp_path / "csv" / "displacement.csv")
    assert frame.columns.tolist() == ["t [s]"] + [f"{n} [m]" for n in
                                                  ("A/1", "A/2", "A/3", "B/1", "B/2", "B/3")]
    with pframe.open(run) as ds:
        assert np.allclose(frame["A/3 [m]"], ds.displacement.sel(node="A/3"), rtol=1e-9,
                           atol=1e-15)
        assert np.allclose(frame["t [s]"], ds.t, rtol=1e-9)
    assert sorted(p.name for p in (tmp_path / "csv").iterdir()) == sorted(
        f"{n}.csv" for n in ("displacement", "velocity", "story_force", "story_drift",
                             "contact_force", "impacts"))
    impacts = pd.read_csv(tmp_path / "csv" / "impacts.csv")  # the paper's 8 at each level
    assert impacts.contact.value_counts().to_dict() == {f"floor-{i}": 8 for i in (1, 2, 3)}


def test_a_bad_summary_path_is_refused_before_the_run(tmp_path, capsys):
    out = tmp_path / "run.nc"
    assert main(["solve", str(MODELS / "wu2021-eq14-linear.yaml"), "-o", str(out),
                 "--summary", str(tmp_path / "s.txt")]) == 2
    assert "a summary is written as .csv or .md" in capsys.readouterr().err
    assert not list(tmp_path.iterdir())


@pytest.mark.slow
def test_a_sweep_has_no_one_run_summary(tmp_path, capsys):
    out = tmp_path / "sweep.nc"
    text = (MODELS / "sweeps" / "wu2021-pi-d.yaml").read_text(encoding="utf-8")
    (tmp_path / "sweep.yaml").write_text(
        text.replace("base: ../wu2021-eq14-pi.yaml", f"base: {MODELS / 'wu2021-eq14-pi.yaml'}")
        .replace("linspace: [0, 2, 41]", "linspace: [0, 2, 2]"), encoding="utf-8")
    assert main(["sweep", str(tmp_path / "sweep.yaml"), "-o", str(out), "-q"]) == 0
    assert main(["summary", str(out)]) == 2
    said = capsys.readouterr()
    assert not said.out and said.err.count("\n") == 1, said  # one line, nothing else
    assert "a sweep's file holds a run per variant" in said.err
    with pytest.raises(pframe.InputError, match="this is a sweep's result"):
        pframe.summary(out)


@pytest.mark.slow
def test_a_risk_study_and_a_gap_audit_print_what_their_command_prints(tmp_path, capsys):
    """pframe summary of a risk study's file prints its title, what it ran (measure,
    levels), what pframe risk printed at its end and every warning it holds; of a gap
    audit's, what pframe gap printed; a table of either with -o is refused, writing
    nothing; pframe.summary refuses them as not one run."""
    import xarray as xr
    from test_risk import pulse_study

    from pframe.commands.gap import table
    from pframe.risk.output import summary as risk_summary

    risk, gap = tmp_path / "risk.nc", tmp_path / "gap.nc"
    assert main(["risk", str(pulse_study(tmp_path)), "-o", str(risk), "-q"]) == 0
    assert main(["gap", str(MODELS / "wu2021-pulse.yaml"), "--levels", "0.2,0.4", "--gap",
                 "0.1", "-o", str(gap), "-q"]) == 0
    capsys.readouterr()
    for path, printed in ((risk, risk_summary), (gap, table)):
        assert main(["summary", str(path)]) == 0
        out = capsys.readouterr().out
        ds = pframe.open(path)
        assert out.startswith(ds.attrs["title"] + "\n")
        assert printed(ds) in out
        warnings = ds.attrs["warnings"].splitlines()
        assert all(f"  {line}\n" in out for line in warnings) and (warnings or "none" in out)
        with pytest.raises(pframe.InputError, match="summary table is of one run"):
            pframe.summary(path)
        ds.close()
    with xr.open_dataset(risk) as ds:
        assert ("msa design over 1 record; intensity measure PGA; levels 0.2, 0.3, 0.4, 0.5, "
                "0.6, 0.8, 1 g") in risk_summary(ds)
        assert ds.attrs["warnings"]  # the pulse's all-or-nothing stripes
        assert "90% median" in risk_summary(ds) and "90% beta" in risk_summary(ds)
    out = tmp_path / "risk.md"
    assert main(["summary", str(risk), "-o", str(out)]) == 2
    assert "-o" in capsys.readouterr().err and not out.exists()


@pytest.mark.slow
def test_solve_replaces_its_summary_file_with_overwrite(tmp_path, capsys):
    """--overwrite replaces an existing --summary file as it does the result; without it,
    the run is refused before it starts, naming --summary (the option that gave the file)."""
    out, table = tmp_path / "run.nc", tmp_path / "run.md"
    table.write_text("an earlier summary\n")
    argv = ["solve", str(MODELS / "wu2021-eq14-linear.yaml"), "-o", str(out), "-q",
            "--summary", str(table)]
    assert main(argv) == 2
    assert "choose another name with --summary" in capsys.readouterr().err
    assert not out.exists() and table.read_text() == "an earlier summary\n"
    assert main([*argv, "--overwrite"]) == 0
    assert table.read_text().startswith("# Summary: ")
