"""Drift and acceleration limits (docs/modes.md#limits): the margins in the file, the Dataset,
the summary and the terminal against peaks computed here from the run's own histories;
ASCE/SEI 7-22 Table 12.12-1 as printed; a limit exceeded flagged; a storey without a height
given a reason, never a number."""

from __future__ import annotations

import json

import numpy as np
import pytest
import xarray as xr

import pframe
from pframe.cli import main
from pframe.limits import G, code_ratio

HEIGHT = 3.0


def _scene(limits: dict, heights=True) -> dict:
    a = {"name": "A", "floors": 3, "mass": 1000.0,
         "story": {"material": "elastic", "stiffness": 2.0e6}}
    if heights:
        a["height"] = HEIGHT
    return {"buildings": [a], "excitation": {"kind": "sine", "amplitude": 3.0,
                                             "frequency": 10.0},
            "analysis": {"dt": 0.002, "duration": 2.0},
            "recorders": [{"kind": "history", "quantities": ["story_drift",
                                                             "absolute_acceleration"]}],
            "limits": limits}


def _run(tmp_path, scene: dict, capsys):
    path = tmp_path / "scene.yaml"
    path.write_text(json.dumps(scene), encoding="utf-8")
    out = tmp_path / "run.nc"
    assert main(["solve", str(path), "-o", str(out)]) == 0
    printed = capsys.readouterr().out
    return xr.load_dataset(out), printed


@pytest.mark.slow
@pytest.mark.parametrize("drift, acceleration_g", [(0.01, 2.0), (0.001, 0.3)])
def test_margins_are_the_limits_less_the_peaks_of_the_histories(tmp_path, capsys, drift,
                                                                acceleration_g):
    """margin = limit - max |drift| / h and utilisation = peak / limit, the peaks taken from
    the recorded histories; a limit the run exceeds is flagged in the file and the terminal,
    one it stays within is not."""
    ds, printed = _run(tmp_path, _scene({"drift_ratio": drift,
                                         "acceleration_g": acceleration_g}), capsys)
    ratio = np.max(np.abs(ds.story_drift.values), axis=0) / HEIGHT
    acceleration = np.max(np.abs(ds.absolute_acceleration.values), axis=0)
    np.testing.assert_allclose(ds.story_drift_ratio_margin.values, drift - ratio, rtol=1e-12)
    np.testing.assert_allclose(ds.story_drift_ratio_utilisation.values, ratio / drift,
                               rtol=1e-12)
    limit = acceleration_g * G
    np.testing.assert_allclose(ds.floor_acceleration_margin.values, limit - acceleration,
                               rtol=1e-12)
    np.testing.assert_allclose(ds.floor_acceleration_utilisation.values, acceleration / limit,
                               rtol=1e-12)
    exceeded = ds.attrs["limits_exceeded"]
    over = (ratio > drift).sum() + (acceleration > limit).sum()
    assert len([line for line in exceeded.splitlines() if line]) == over
    if drift == 0.01:  # well within both
        assert over == 0 and np.all(ds.story_drift_ratio_margin.values > 0)
        assert "LIMIT EXCEEDED" not in printed
    else:  # beyond both at some storey and floor
        assert np.any(ds.story_drift_ratio_margin.values < 0)
        assert np.any(ds.floor_acceleration_margin.values < 0)
        assert "LIMIT EXCEEDED: storey A/1" in printed and "storey A/1" in exceeded
        table = pframe.summary(ds)
        flagged = table[(table.part == "warning") & (table.quantity == "limit exceeded")]
        assert len(flagged) == over


def test_a_storey_without_a_height_has_a_reason_not_a_margin(tmp_path, capsys):
    ds, printed = _run(tmp_path, _scene({"drift_ratio": 0.02}, heights=False), capsys)
    assert np.all(np.isnan(ds.story_drift_ratio_margin.values))
    assert np.all(np.isnan(ds.story_drift_ratio_utilisation.values))
    assert "no height was given" in ds.story_drift_ratio_margin.attrs["comment"]
    assert "drift ratio limit not checked at A/1, A/2, A/3: no height" in printed
    assert ds.attrs["limits_exceeded"] == ""
    table = pframe.summary(ds)
    margins = table[table.quantity == "drift ratio margin"].value
    assert margins.isna().all()  # NaN, never 0


def test_the_code_table_as_printed():
    """ASCE/SEI 7-22 Table 12.12-1: Delta_a / h_sx by structure and risk category; the
    low-rise row stops at 4 storeys and has no limit for one (footnote c); rho divides
    (12.12.1.1)."""
    printed = {"low_rise": (0.025, 0.020, 0.015), "masonry_cantilever": (0.010,) * 3,
               "masonry_other": (0.007,) * 3, "other": (0.020, 0.015, 0.010)}
    for structure, row in printed.items():
        for category, value in zip(("II", "III", "IV"), row):
            assert code_ratio(structure, category, 3)[0] == value
        assert code_ratio(structure, "I", 3)[0] == row[0]
    ratio, why = code_ratio("low_rise", "III", 5)
    assert ratio == 0.015 and "low-rise row stops at 4 storeys" in why
    ratio, why = code_ratio("low_rise", "II", 1)
    assert np.isnan(ratio) and "footnote c" in why
    assert code_ratio("other", "II", 8, redundancy=1.3)[0] == pytest.approx(0.020 / 1.3)
    assert code_ratio("other", "II", 8, factor=2.0)[0] == pytest.approx(0.040)


def test_a_code_limit_per_building(tmp_path, capsys):
    """Risk category IV, all other structures: 0.010 h_sx at every storey, its source in the
    file and a note that the code limits the design story drift."""
    ds, printed = _run(tmp_path, _scene({"code": {"risk_category": "IV"}}), capsys)
    np.testing.assert_array_equal(ds.story_drift_ratio_limit.values, [0.010] * 3)
    assert "Table 12.12-1" in ds.story_drift_ratio_limit.attrs["comment"]
    assert "design story drift" in printed
    assert "floor_acceleration_margin" not in ds  # no acceleration limit given


@pytest.mark.parametrize("limits, words", [
    ({"drift_ratio": 0.02, "code": {"risk_category": "II"}}, "not both"),
    ({"acceleration": 3.0, "acceleration_g": 0.3}, "not both"),
    ({}, "give drift_ratio or code"),
    ({"code": {"risk_category": "V"}}, "risk_category"),
    ({"drift_ratio": 0.0}, "drift_ratio"),
])
def test_bad_limits_are_refused(tmp_path, capsys, limits, words):
    path = tmp_path / "scene.yaml"
    path.write_text(json.dumps(_scene(limits)), encoding="utf-8")
    assert main(["validate", str(path)]) == 2
    err = capsys.readouterr().err
    assert "limits" in err and words in err and "Traceback" not in err
