"""A ground motion beyond any recorded earthquake's peak (a unit or a scale typed wrong: a PGA
of 1e50 g) runs, but says so in the terminal, the file and the Python warnings; a strong but
real motion (4 g) does not. Generated over the kinds of motion and their magnitudes."""

from __future__ import annotations

import warnings

import numpy as np
import pytest

import pframe
from pframe.api import loaded_scene
from pframe.excitation.describe import PLAUSIBLE_PGA
from pframe.excitation.records import G

SCENE = {
    "buildings": [{"name": "A", "floors": 1, "mass": 1000.0,
                   "story": {"material": "elastic", "stiffness": 1.0e6}}],
    "analysis": {"dt": 0.005, "duration": 0.5},
}


def _excitation(kind: str, peak: float, folder) -> dict:
    if kind == "sine":
        return {"kind": "sine", "amplitude": peak, "frequency": 6.0}
    if kind == "ricker":
        return {"kind": "ricker", "amplitude": peak, "period": 0.2}
    if kind == "record-scaled":  # a record of 1 m/s^2 scaled up
        t = np.arange(0.0, 0.5, 0.005)
        np.savetxt(folder / "rec.txt", np.column_stack([t, np.sin(12.0 * t)]))
        return {"kind": "record", "file": "rec.txt", "scale": peak / float(np.max(np.abs(
            np.sin(12.0 * t))))}
    t = np.arange(0.0, 0.5, 0.005)  # a record whose values are the peak itself
    np.savetxt(folder / "rec.txt", np.column_stack([t, peak * np.sin(12.0 * t)]))
    return {"kind": "record", "file": "rec.txt", "pga": peak}


@pytest.mark.parametrize("kind", ["sine", "ricker", "record-scaled", "record-pga"])
@pytest.mark.parametrize("peak_g", [0.3, 4.0, 6.0, 1e3, 1e50])
def test_an_implausible_peak_is_said(tmp_path, kind, peak_g):
    scene = {**SCENE, "excitation": _excitation(kind, peak_g * G, tmp_path)}
    expanded = loaded_scene(scene, tmp_path).expanded
    said = [w for w in expanded.warnings if "beyond any recorded earthquake" in w]
    assert bool(said) == (peak_g * G > PLAUSIBLE_PGA), (kind, peak_g, said)
    if said:
        assert f"({peak_g:.4g} g)" in said[0] and "check the units" in said[0]


def test_the_warning_reaches_the_file_and_python(tmp_path):
    scene = {**SCENE, "excitation": {"kind": "sine", "amplitude": 1e50 * G, "frequency": 6.0}}
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        ds = pframe.solve(scene, output=tmp_path / "run.nc")
    assert any("beyond any recorded earthquake" in str(w.message)
               and issubclass(w.category, pframe.AccuracyWarning) for w in caught)
    assert "beyond any recorded earthquake" in str(ds.attrs["warnings"])
