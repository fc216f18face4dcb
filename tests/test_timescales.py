"""dt against every time scale of a scene, and scenes no building has (pframe.assemble.timescales,
docs/accuracy.md#what-pframe-checks-about-dt): each coarse step is warned with numbers that are
checked here against closed forms, an independent eigensolver and pframe's own runs."""

from __future__ import annotations

import json
import math
import re
import warnings
from pathlib import Path

import numpy as np
import pytest
import scipy.linalg
from conftest import RECORDERS, REPO, analysis, node_history, record_file, run_text, scene_text

from pframe.assemble import assemble
from pframe.assemble.timescales import (
    MASS_SHARE,
    STEPS_PER_PERIOD,
    building_modes,
    carrying_modes,
    period_error,
)
from pframe.integrators import HHT, CentralDifference, GeneralizedAlpha, Newmark
from pframe.reader import load_scene, parse_scene

MASS = 1000.0
PERIOD = 0.5  # s: the first period of the one-storey building below
STIFFNESS = MASS * (2.0 * math.pi / PERIOD) ** 2


def one_storey(dt: float, duration: float, excitation: dict | None = None, **extra) -> str:
    scene = {"buildings": [{"name": "A", "floors": 1, "mass": MASS,
                            "story": {"material": "elastic", "stiffness": STIFFNESS}}],
             "damping": {"ratio": 0.0}, "analysis": analysis(dt, duration)} | extra
    if excitation is not None:
        scene["excitation"] = excitation
    return scene_text(**scene)


def warnings_of(text: str, base_dir: Path | None = None) -> tuple[str, ...]:
    return assemble(parse_scene(text, base_dir=base_dir).expanded).warnings


def only(found, word: str) -> str:
    chosen = [w for w in found if word in w]
    assert len(chosen) == 1, found
    return chosen[0]


# -- the integrators' period error ----------------------------------------------------------

@pytest.mark.parametrize("steps", [2.5, 4.0, 10.0, 20.0, 100.0])
def test_period_error_is_the_closed_form_of_newmark_and_central_difference(steps):
    """Average acceleration turns w h into 2 atan(w h / 2), central difference into
    2 asin(w h / 2) (both exact for an undamped oscillator)."""
    x = 2.0 * math.pi / steps
    trapezoidal = period_error(Newmark().coefficients(), steps)
    assert trapezoidal == pytest.approx((x / 2) / math.atan(x / 2) - 1.0, rel=1e-9)
    explicit = period_error(CentralDifference().coefficients(), steps)
    if x < 2.0:
        assert explicit == pytest.approx((x / 2) / math.asin(x / 2) - 1.0, rel=1e-9)
    else:  # beyond its stability limit it carries no vibration
        assert explicit == math.inf
    # the rule of thumb the threshold is chosen by: (w h)^2 / 12
    if steps >= STEPS_PER_PERIOD:
        assert trapezoidal == pytest.approx(x * x / 12.0, rel=0.01)


def test_period_error_of_hht_and_generalized_alpha_is_second_order():
    for integrator in (HHT(), GeneralizedAlpha()):
        c = integrator.coefficients()
        assert period_error(c, 20.0) / period_error(c, 40.0) == pytest.approx(4.0, rel=0.02)
        assert 0.0 < period_error(c, STEPS_PER_PERIOD) < 0.01
    assert period_error(Newmark().coefficients(), 1.9) == math.inf


def test_the_stated_period_error_is_the_one_pframe_runs_with():
    """Free vibration at 5 steps per period: the warning's period error is the elongation
    measured on pframe's own displacement history (u(n+1) + u(n-1) = 2 cos(w' h) u(n))."""
    dt = PERIOD / 5.0
    text = one_storey(dt, 40 * PERIOD, initial_conditions={"displacement": {"A/1": 0.1}})
    warning = only(warnings_of(text), "building A")
    assert "with 5.00 steps, fewer than 20" in warning
    stated = float(re.search(r"makes its period ([0-9.]+)% longer", warning).group(1)) / 100
    plan, result = run_text(text)
    u = node_history(plan, result, "displacement", "A/1")
    cosine = np.dot(u[1:-1], u[2:] + u[:-2]) / (2.0 * np.dot(u[1:-1], u[1:-1]))
    measured = (2.0 * math.pi / 5.0) / math.acos(cosine) - 1.0
    assert measured == pytest.approx(stated, abs=0.0006)  # the warning rounds to 0.1 %
    assert "use dt <= 0.025 s" in warning


# -- buildings ------------------------------------------------------------------------------

def test_dt_above_the_buildings_period_is_not_valid_even_without_contacts():
    """The issue's case: dt = 1 s on a building of first period 0.5 s, no contacts."""
    text = one_storey(1.0, 30.0, initial_conditions={"displacement": {"A/1": 0.1}})
    warning = only(warnings_of(text), "building A")
    assert "dt = 1 s resolves the period 0.5 s" in warning
    assert "0.50 steps" in warning and "result is not valid" in warning
    assert "use dt <= 0.025 s" in warning
    assert not warnings_of(one_storey(0.025, 1.0))  # 20 steps per period: quiet


def test_the_modes_judged_carry_90_percent_of_the_mass():
    """A uniform 20-storey shear building: the modal masses (checked against scipy's
    generalised eigensolver) add up to 1; the modes judged are the fewest lowest ones that
    carry 90 %, and dt is judged on the shortest of them."""
    floors, m, k = 20, 2.0e5, 4.0e8
    text = scene_text(buildings=[{"name": "T", "floors": floors, "mass": m,
                                  "story": {"material": "elastic", "stiffness": k}}],
                      analysis=analysis(0.01, 1.0))
    ex = parse_scene(text).expanded
    omega, shares = building_modes(ex, 0, np.full(floors, k))
    stiffness = np.diag(np.r_[2.0 * np.ones(floors - 1), 1.0] * k) \
        - k * (np.eye(floors, k=1) + np.eye(floors, k=-1))
    values, vectors = scipy.linalg.eigh(stiffness, m * np.eye(floors))
    independent = (vectors.T @ (m * np.ones(floors))) ** 2 / (m * floors)
    np.testing.assert_allclose(omega, np.sqrt(values), rtol=1e-10)
    np.testing.assert_allclose(shares, independent, rtol=1e-8, atol=1e-14)
    assert float(np.sum(shares)) == pytest.approx(1.0, rel=1e-12)
    count = carrying_modes(omega, shares)
    assert np.sum(shares[:count]) >= MASS_SHARE > np.sum(shares[:count - 1])
    shortest = 2.0 * math.pi / omega[count - 1]
    # a step of 15 steps per period of that mode is warned, with the mode named
    dt = float(shortest / 15.0)
    warning = only(warnings_of(text.replace('"dt": 0.01', f'"dt": {dt!r}')), "building T")
    assert f"mode {count}, the shortest of the modes 1-{count}" in warning
    assert "with 15.00 steps" in warning
    # one step per period of it is fine for its first mode alone: the check is on mode `count`
    assert 2.0 * math.pi / omega[0] / dt > STEPS_PER_PERIOD


def test_a_yielding_storey_is_judged_on_its_elastic_period():
    """A bilinear storey: its initial (elastic) stiffness sets the period judged."""
    story = {"material": "bilinear", "stiffness": STIFFNESS, "yield_drift": 0.01, "alpha": 0.1}
    text = scene_text(buildings=[{"name": "A", "floors": 1, "mass": MASS, "story": story}],
                      analysis=analysis(0.1, 1.0))
    warning = only(warnings_of(text), "building A")
    assert "period 0.5 s (elastic: its storeys' initial stiffness)" in warning
    assert "with 5.00 steps" in warning


def test_central_difference_sub_steps_are_reported_and_judged():
    """With substeps: auto the warning says how many sub-steps and why (the limit
    0.9 x 2 / w of one storey), and the building is judged at the sub-step: at 0.9 of its
    limit central difference resolves the highest mode with pi / 0.9 = 3.5 steps."""
    text = one_storey(0.5, 1.0)
    data = json.loads(text)
    data["analysis"]["integrator"] = {"type": "central_difference", "substeps": "auto"}
    found = warnings_of(json.dumps(data))
    limit = 0.9 * 2.0 / (2.0 * math.pi / PERIOD)
    warning = only(found, "central difference")
    parts = math.ceil(0.5 / limit)
    assert f"takes {parts} sub-steps of {0.5 / parts:.4g} s per step" in warning
    assert f"stability limit {limit:.4g} s" in warning
    warning = only(found, "building A")
    assert f"central-difference sub-step h = {0.5 / parts:.4g} s" in warning
    assert f"with {PERIOD / (0.5 / parts):.2f} steps" in warning
    assert "shorter" in warning  # central difference shortens periods


# -- excitations ----------------------------------------------------------------------------

def test_a_sine_above_the_nyquist_frequency_is_an_alias():
    """The issue's case: 477 Hz at dt = 0.002 s (Nyquist 250 Hz) is seen as 500 - 477 = 23 Hz;
    the sampled ground motion is exactly that alias."""
    w = 2.0 * math.pi * 477.0
    text = one_storey(0.002, 0.5, {"kind": "sine", "amplitude": 1.0, "frequency": w})
    loaded = parse_scene(text)
    plan = assemble(loaded.expanded)
    warning = only(plan.warnings, "sine")
    assert "1.05 steps" in warning and "Nyquist frequency 250 Hz" in warning
    assert "alias of 23 Hz" in warning and "result is not valid" in warning
    t = plan.times
    np.testing.assert_allclose(plan.ground_acceleration[0], -np.sin(2 * math.pi * 23.0 * t),
                               atol=1e-9)
    coarse = one_storey(0.01, 1.0, {"kind": "sine", "amplitude": 1.0,
                                    "frequency": 2.0 * math.pi / 0.1})
    warning = only(warnings_of(coarse), "sine")
    assert "with 10.00 steps" in warning
    assert f"{period_error(Newmark().coefficients(), 10.0):.1%} longer" in warning


@pytest.mark.parametrize("pulse", [{"kind": "cycloidal", "type": "A"},
                                   {"kind": "ricker"}])
def test_a_pulse_period_is_checked(pulse):
    text = one_storey(0.01, 1.0, pulse | {"amplitude": 1.0, "period": 0.08})
    warning = only(warnings_of(text), "T_p = 0.08 s")
    assert "with 8.00 steps" in warning and "use dt <= 0.004 s" in warning
    assert not [w for w in warnings_of(one_storey(0.004, 1.0, pulse | {"amplitude": 1.0,
                                                                       "period": 0.08}))]


def _two_tone_record(folder: Path) -> Path:
    """20 s at 0.02 s of equal 0.5 Hz and 10 Hz sines (whole periods: no leakage)."""
    t = np.arange(1000) * 0.02
    a = np.sin(2 * math.pi * 0.5 * t) + np.sin(2 * math.pi * 10.0 * t)
    path = folder / "two-tone.txt"
    path.write_text("\n".join(f"{float(ti)!r} {float(ai)!r}" for ti, ai in zip(t, a)), encoding="utf-8")
    return path


def test_a_step_longer_than_the_records_step_is_warned_with_the_aliased_share(tmp_path):
    """Half the two-tone record's energy is at 10 Hz, above the Nyquist frequency 1 Hz of
    dt = 0.5 s; at dt = 0.04 s (Nyquist 12.5 Hz) none is."""
    _two_tone_record(tmp_path)
    excitation = {"kind": "record", "file": "two-tone.txt"}
    building = {"name": "A", "floors": 1, "mass": MASS,
                "story": {"material": "elastic", "stiffness": MASS * (2 * math.pi / 10) ** 2}}

    def text(dt):
        return scene_text(buildings=[building], excitation=excitation,
                          analysis=analysis(dt, 20.0))

    loaded = parse_scene(text(0.5), base_dir=tmp_path)
    plan = assemble(loaded.expanded)
    warning = only(plan.warnings, "record's own step")
    assert "dt = 0.5 s is 25 times the record's own step 0.02 s" in warning
    assert "50.0% of its energy lies above the step's Nyquist frequency 1 Hz" in warning
    assert "result is not valid" in warning and "use dt <= 0.02 s" in warning
    sampled = float(np.max(np.abs(plan.ground_acceleration[0])))
    assert f"PGA as sampled is {sampled:.4g} m/s^2" in warning
    warning = only(warnings_of(text(0.04), tmp_path), "record's own step")
    assert "2 times" in warning and "0.0% of its energy" in warning
    assert "results may be inaccurate" in warning
    assert not [w for w in warnings_of(text(0.02), tmp_path) + warnings_of(text(0.005), tmp_path)
                if "record" in w]


def test_the_issue_record_case_el_centro_at_half_a_second():
    """El Centro 1940 (step 0.02 s) analysed at dt = 0.5 s: warned, not valid."""
    record = record_file("elCentro.AT2")
    text = scene_text(buildings=[{"name": "A", "floors": 1, "mass": MASS, "story": {
        "material": "elastic", "stiffness": MASS * (2 * math.pi / 2.0) ** 2}}],
        excitation={"kind": "record", "file": record.name}, analysis=analysis(0.5, 30.0))
    found = warnings_of(text, record.parent)
    assert "25 times the record's own step 0.02 s" in only(found, "record's own step")
    assert "result is not valid" in only(found, "record's own step")
    assert "with 4.00 steps" in only(found, "building A")


# -- implausible scenes ---------------------------------------------------------------------

def _uniform_first_period(floors, m, k):
    """First period of a uniform fixed-base shear building (closed form)."""
    return 2 * math.pi / (2 * math.sqrt(k / m) * math.sin(math.pi / (2 * (2 * floors + 1))))


@pytest.mark.parametrize(("mass", "stiffness", "word", "fixed"), [
    (250.0, 197392.088e3, "shorter", 1000 ** 0.5),   # masses in tonnes
    (250.0e3, 197.392088e3, "longer", 1000 ** -0.5),  # stiffnesses in kN/m
])
def test_a_building_off_by_a_factor_1000_is_named(mass, stiffness, word, fixed):
    text = scene_text(buildings=[{"name": "A", "floors": 3, "mass": mass,
                                  "story": {"material": "elastic", "stiffness": stiffness}}],
                      analysis=analysis(1e-4, 0.1))
    first = _uniform_first_period(3, mass, stiffness)
    warning = only(warnings_of(text), "than buildings have")
    assert f"its first period {first:.3g} s is {word}" in warning
    assert f"the first period is {first * fixed:.3g} s" in warning  # 0.502 s, a building's
    assert "check the units (kg, N/m)" in warning


def test_pi_form_scenes_at_unit_scales_are_not_judged_as_buildings(tmp_path):
    """A Pi-form scene at its default scales m_b = 1 kg, w_p = 1 rad/s has ratios, not a
    building's masses and periods: no implausibility warning; with w_p given, its periods are
    seconds and are judged."""
    import yaml

    data = yaml.safe_load((REPO / "models" / "wu2021-eq14-pi.yaml").read_text())
    data["pi"]["Pi_k"] = 5.0e5  # first period 0.0316 / sqrt(... ) s at w_p = 1
    data["analysis"]["dt_tau"] = 1e-5
    data["analysis"]["tau"] = 0.01
    text = yaml.safe_dump(data)
    assert not [w for w in warnings_of(text) if "than buildings have" in w]
    data["scales"] = {"w_p": 1.0}
    warning = only(warnings_of(yaml.safe_dump(data)), "building A: its first period")
    assert "check Pi_k and w_p" in warning


# -- the channels, and quiet scenes ---------------------------------------------------------

def test_the_warning_reaches_python_and_the_result_file():
    import pframe

    text = one_storey(1.0, 3.0, initial_conditions={"displacement": {"A/1": 0.1}},
                      recorders=RECORDERS)
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        ds = pframe.solve(json.loads(text))
    assert any("result is not valid" in str(w.message) for w in caught)
    assert "0.50 steps" in str(ds.attrs["warnings"])


def test_the_shipped_models_are_resolved(tmp_path):
    """Every model of models/ resolves its time scales: no warning from these checks."""
    from conftest import runnable_model

    words = ("steps, fewer than", "record's own step", "than buildings have", "sub-steps")
    for model in sorted((REPO / "models").glob("*.yaml")):
        found = assemble(load_scene(runnable_model(model, tmp_path)).expanded).warnings
        assert not [w for w in found if any(x in w for x in words)], (model.name, found)


def test_a_tall_chain_of_storeys_gets_its_lowest_modes_and_their_masses():
    """1000 uniform floors (beyond the dense limit): the frequencies and modal masses of the
    lowest modes against the closed forms, w_r = 2 sqrt(k/m) sin((2r - 1) pi / (2 (2n + 1)))
    and, for so many floors, the shear beam's 8 / ((2r - 1)^2 pi^2)."""
    n, k, m = 1000, 2.0e7, 3.0e4
    text = scene_text(buildings=[{"name": "A", "floors": n, "mass": m,
                                  "story": {"material": "elastic", "stiffness": k}}],
                      analysis=analysis(0.01, 0.1))
    omega, shares = building_modes(parse_scene(text).expanded, 0, np.full(n, k))
    r = np.arange(1, len(omega) + 1)
    exact = 2 * np.sqrt(k / m) * np.sin((2 * r - 1) * np.pi / (2 * (2 * n + 1)))
    np.testing.assert_allclose(omega, exact, rtol=1e-9)
    np.testing.assert_allclose(shares[:4], 8 / ((2 * r[:4] - 1) ** 2 * np.pi ** 2), rtol=2e-3)
    assert np.sum(shares) >= MASS_SHARE  # computed until they carry 90 %
