"""Whole-kernel physics: linear dynamics against closed forms, Newmark's order of accuracy,
the energy balance, bilinear hysteresis and the pounding example of Wu et al. (2021)."""

from __future__ import annotations

import math

import numpy as np
import pytest
from conftest import (
    WU2021,
    analysis,
    building,
    element_history,
    fit_sine,
    node_history,
    observed_order,
    run_text,
    scene_text,
    sdof_text,
)

# ---------------------------------------------------------------------------------------------
# linear SDOF: steady state under sine ground acceleration
# ---------------------------------------------------------------------------------------------

SDOF_M = 1000.0  # kg
SDOF_WN = 4.0 * math.pi  # rad/s (2 Hz)
SDOF_K = SDOF_M * SDOF_WN**2
SDOF_ZETA = 0.05
SDOF_AP = 2.0  # m/s^2
SDOF_DT = 1.0e-3  # s
SDOF_T = 30.0  # s; the free transient decays as exp(-zeta wn t) = 2e-8 by t = 28 s


@pytest.mark.parametrize("ratio", [0.5, 1.0, 2.0])
def test_sdof_steady_state_matches_closed_form(ratio):
    """m u'' + c u' + k u = -m a_p sin(w t) with c = 2 zeta sqrt(k m) (Rayleigh on modes [1, 1]
    of an SDOF): after the transient the response is Im(H e^{iwt}),
    H = -m a_p / (k - m w^2 + i c w), below, at and above resonance.

    Newmark's average acceleration is the trapezoidal rule, whose steady state is exactly
    H(w') with w' = (2/dt) tan(w dt / 2): that is checked to 1e-6 (the transient remnant
    ~2e-8), and the error against the continuous H, |dlnH/dlnw| (w dt)^2 / 12 <= 1.4e-4 in
    amplitude and 2.6e-4 rad in phase (at resonance dphi/dlnw = 1/zeta) here, to 1e-3."""
    w = ratio * SDOF_WN
    text = sdof_text(SDOF_M, SDOF_K, SDOF_ZETA,
                     {"kind": "sine", "amplitude": SDOF_AP, "frequency": w}, SDOF_DT, SDOF_T)
    plan, result = run_text(text)
    assert result.completed(0)
    t = plan.times
    u = node_history(plan, result, "displacement", "A/1")
    last = t >= SDOF_T - 2.0 - 1e-9  # the last 2 s: an integer number of cycles (2, 4, 8)
    measured = fit_sine(t[last], u[last], w)

    c = 2.0 * SDOF_ZETA * math.sqrt(SDOF_K * SDOF_M)

    def h(freq):
        return -SDOF_M * SDOF_AP / (SDOF_K - SDOF_M * freq**2 + 1j * c * freq)

    exact = h(w)
    amplitude = SDOF_M * SDOF_AP / math.hypot(SDOF_K - SDOF_M * w**2, c * w)
    assert abs(exact) == pytest.approx(amplitude, rel=1e-14)
    assert abs(measured) == pytest.approx(amplitude, rel=1e-3)
    assert abs(np.angle(measured / exact)) < 1e-3
    discrete = h(2.0 / SDOF_DT * math.tan(w * SDOF_DT / 2.0))
    assert abs(measured - discrete) <= 1e-6 * abs(exact)


# ---------------------------------------------------------------------------------------------
# free vibration of a 3-storey building: modal solution and second-order convergence
# ---------------------------------------------------------------------------------------------

FREE_M = 1000.0
FREE_K = 1.0e6
FREE_U0 = np.array([0.01, 0.02, 0.03])
FREE_T = 2.0  # s, 4.5 fundamental periods


def _free_vibration(dt):
    text = scene_text(
        buildings=[building("A", 3, FREE_M, {"material": "elastic", "stiffness": FREE_K})],
        damping={"ratio": 0.0},
        initial_conditions={"displacement": {f"A/{i + 1}": u for i, u in enumerate(FREE_U0)}},
        analysis=analysis(dt, FREE_T),
    )
    plan, result = run_text(text)
    assert result.completed(0)
    u = np.array([node_history(plan, result, "displacement", f"A/{i}") for i in (1, 2, 3)])
    return plan.times, u


def _modes():
    """Eigenpairs of K phi = w^2 M phi (mass-normalised phi) of the fixed-base building."""
    stiffness = FREE_K * np.array([[2.0, -1.0, 0.0], [-1.0, 2.0, -1.0], [0.0, -1.0, 1.0]])
    mass = FREE_M * np.eye(3)
    scale = 1.0 / np.sqrt(np.diag(mass))
    w2, psi = np.linalg.eigh(stiffness * np.outer(scale, scale))
    phi = psi * scale[:, None]
    return np.sqrt(w2), phi, mass


def test_free_vibration_matches_modal_solution_and_newmark_is_second_order():
    """Undamped free vibration from initial displacements: u(t) = sum phi_j q_j cos(w_j t),
    q = phi^T M u0. Newmark's average acceleration has no amplitude error and a period
    elongation w -> (2/dt) atan(w dt / 2): the kernel reproduces that discrete solution to
    roundoff (1e-12 m over 4000 steps), and its error against the exact modal solution
    (compared on the common 2 ms grid) falls as dt^2: observed orders within 0.1 of 2."""
    w, phi, mass = _modes()
    q0 = phi.T @ mass @ FREE_U0
    errors = []
    for dt in (2e-3, 1e-3, 5e-4):  # w_3 dt <= 0.11: in the asymptotic range
        t, u = _free_vibration(dt)
        exact = (phi * q0) @ np.cos(np.outer(w, t))
        discrete = (phi * q0) @ np.cos(np.outer(2.0 / dt * np.arctan(w * dt / 2.0), t))
        assert np.max(np.abs(u - discrete)) <= 1e-12
        stride = int(round(2e-3 / dt))
        errors.append(np.max(np.abs(u[:, ::stride] - exact[:, ::stride])))
        # mode j lags by (w_j - w'_j) t <= w_j^3 dt^2 t / 12, so |u_i - exact_i| is at most
        # sum_j |phi_ij q_j| (w_j - w'_j) T, and (checking the measure) of that order
        lag = np.abs(phi * q0) @ ((w - 2.0 / dt * np.arctan(w * dt / 2.0)) * FREE_T)
        assert np.all(np.max(np.abs(u - exact), axis=1) <= lag + 1e-12)
        assert errors[-1] > 0.2 * np.max(lag)
    orders = observed_order(errors)
    print(f"free vibration errors {errors}, observed orders {orders}")
    assert np.all(np.abs(orders - 2.0) < 0.1)


# ---------------------------------------------------------------------------------------------
# energy balance
# ---------------------------------------------------------------------------------------------


def _two_buildings(material_a, material_b, contact, gap, dt, duration, ratio=0.05):
    return scene_text(
        buildings=[building("A", 3, 250.0, material_a), building("B", 3, 1000.0, material_b)],
        contacts=[{"name": f"floor-{i}", "nodes": [f"A/{i}", f"B/{i}"], "gap": gap} | contact
                  for i in (1, 2, 3)],
        damping={"ratio": ratio, "modes": [1, 2]},
        excitation={"kind": "sine", "amplitude": 9.81, "frequency": 2.0 * math.pi},
        analysis=analysis(dt, duration),
    )


ELASTIC_A = {"material": "elastic", "stiffness": 197392.088}
ELASTIC_B = {"material": "elastic", "stiffness": 1973920.88}


def test_energy_balance_elastic_with_linear_contact():
    """Two elastic buildings pounding through linear contacts with Rayleigh damping: the work
    of the ground equals kinetic energy + damping + storey + contact work. With Newmark
    gamma = 1/2, beta = 1/4 and trapezoidal work sums this is an identity of the discrete
    equations, exact up to the Newton out-of-balance (|du| <= 1e-12 |u|) and roundoff over
    40000 steps: < 1e-9 of the largest term."""
    text = _two_buildings(ELASTIC_A, ELASTIC_B, {"law": "linear", "stiffness": 5.0e6},
                          gap=0.02, dt=1.0e-4, duration=4.0)
    plan, result = run_text(text)
    assert result.completed(0)
    assert np.all(result.impacts[0] >= 2)  # it does pound, at every floor
    energy = result.energy_terms(0)
    assert energy["damping"] > 0.1 * energy["input"]  # the damping term matters in the balance
    print(f"energy error (elastic, linear contact): {result.energy_error(0):.2e}")
    assert result.energy_error(0) < 1e-9


def test_energy_balance_bilinear_with_improved_kelvin(wu2021_run):
    """The paper's example (bilinear storeys, improved Kelvin contacts): the same identity
    with hysteretic and impact dissipation, < 1e-8 (50000 Newton-solved steps)."""
    _, plan, result = wu2021_run
    assert result.completed(0)
    energy = result.energy_terms(0)
    assert energy["contacts"] > 0.05 * energy["input"]  # impacts dissipate
    # yielding dissipates (elastic storeys store ~ nothing at rest)
    assert energy["storeys"] > 0.5 * energy["input"]
    print(f"energy error (bilinear, improved Kelvin): {result.energy_error(0):.2e}")
    assert result.energy_error(0) < 1e-8


# ---------------------------------------------------------------------------------------------
# bilinear hysteresis
# ---------------------------------------------------------------------------------------------

BI_M, BI_K, BI_UY = 1000.0, 1.0e5, 0.01  # wn = 10 rad/s, f_y = 1000 N


def _bilinear_sdof(alpha):
    story = {"material": "bilinear", "stiffness": BI_K, "yield_drift": BI_UY, "alpha": alpha}
    # a_p = 3 m/s^2 at w = 5 rad/s: an elastic response of 0.04 m, i.e. 4 u_y (more once
    # yielding softens the storey towards resonance)
    text = sdof_text(BI_M, BI_K, 0.02, {"kind": "sine", "amplitude": 3.0, "frequency": 5.0},
                     1.0e-3, 10.0, story=story)
    plan, result = run_text(text)
    assert result.completed(0), result.describe_failure(0)
    drift = element_history(plan, result, "story_drift", "A/1")
    force = element_history(plan, result, "story_force", "A/1")
    return result, drift, force


@pytest.mark.parametrize("alpha", [0.1, 0.0])
def test_bilinear_hysteresis_stays_between_bounding_lines(alpha):
    """A bilinear SDOF driven far past yield: the storey force always lies between
    alpha k u +- (1 - alpha) f_y (to roundoff, 1e-12 f_y), it reaches those lines, and each
    committed step follows the kinematic-hardening rule f_{n+1} = clip(f_n + k du) of the
    previous *committed* state (Newton iterations must not move the state). With alpha = 0
    (elastic-perfectly plastic) |f| <= f_y and the run completes."""
    result, drift, force = _bilinear_sdof(alpha)
    fy = BI_K * BI_UY
    centre, reach = alpha * BI_K * drift, (1.0 - alpha) * fy
    assert np.max(np.abs(drift)) > 3.0 * BI_UY  # driven hard
    assert np.all(np.abs(force - centre) <= reach * (1.0 + 1e-12))
    assert np.max(np.abs(force - centre)) == pytest.approx(reach, rel=1e-12)  # yields
    if alpha == 0.0:
        assert np.max(np.abs(force)) <= fy * (1.0 + 1e-12)
    trial = force[:-1] + BI_K * np.diff(drift)
    rule = np.clip(trial, centre[1:] - reach, centre[1:] + reach)
    assert np.max(np.abs(force[1:] - rule)) <= 1e-9 * fy
    assert np.sum(np.abs(force[1:] - trial) > 1e-6 * fy) > 50  # many plastic steps
    print(f"bilinear alpha={alpha}: peak drift {np.max(np.abs(drift)) / BI_UY:.2f} u_y, "
          f"energy error {result.energy_error(0):.1e}")
    assert result.energy_error(0) < 1e-9


# ---------------------------------------------------------------------------------------------
# Wu et al. (2021), eq. 14: the paper's pounding example
# ---------------------------------------------------------------------------------------------



def _wu2021_variant(text, law):
    variant = text.replace("law: improved_kelvin, frequency_ratio: 65, restitution: 0.4",
                           f"law: {law}, frequency_ratio: 65, restitution: 0.4")
    assert variant.count(f"law: {law},") == 3
    return run_text(variant, base_dir=WU2021.parent)


def _check_paper(plan, result):
    """What Wu et al. (2021) report for eq. 14 over tau = 0..50."""
    assert result.completed(0), result.describe_failure(0)
    assert plan.contact_names == ("floor-1", "floor-2", "floor-3")
    assert result.impacts[0].tolist() == [8, 8, 8]
    uy_a, uy_b = 0.02484902028828334, 0.014909412172970003
    drift = dict(zip(plan.story_names, result.envelope["story_drift"][0]))
    # "the first and the second story of both structures are entering the plastic stage;
    # ... the third story ... is already in the elastic stage" (section 3)
    assert drift["A/1"] > uy_a and drift["A/2"] > uy_a
    assert drift["B/1"] > uy_b and drift["B/2"] > uy_b
    assert drift["A/3"] < uy_a and drift["B/3"] < uy_b
    # the envelope is the peak of the history
    history = np.abs(result.history["story_drift"][0]).max(axis=0)
    assert np.array_equal(history, result.envelope["story_drift"][0])


def test_wu2021_improved_kelvin(wu2021_run):
    """The shipped example (improved Kelvin, e = 0.4, Pi_wcon = 65, Rayleigh damping on the
    current stiffness as eq. 5b writes it): 8 impacts at each floor, storeys 1 and 2 of both
    buildings yield and storey 3 stays elastic, and the improved Kelvin force is never
    tensile (it vanishes with the penetration and is clipped in fast rebound)."""
    loaded, plan, result = wu2021_run
    assert plan.steps == 50000  # tau = 0..50 with dtau = 0.001
    _check_paper(plan, result)
    force = result.history["contact_force"][0]
    assert np.min(force) >= 0.0
    assert np.max(force) > 0.0
    print("wu2021 improved Kelvin: peak drifts", result.envelope["story_drift"][0])


def test_wu2021_kelvin(wu2021_text):
    """The same example with the (clipped) Kelvin law: 8 impacts at each floor, storeys 1 and
    2 of both buildings yield, storey 3 elastic, and the clipped force is never negative."""
    plan, result = _wu2021_variant(wu2021_text, "kelvin")
    _check_paper(plan, result)
    assert np.min(result.history["contact_force"][0]) >= 0.0


def test_wu2021_kelvin_keep_tension_pulls(wu2021_text):
    """Kelvin with keep_tension: the force turns tensile before separation (the drawback the
    paper shows in its Figure 6), by more than 1% of its peak compression."""
    text = wu2021_text.replace("calibration: published}", "calibration: published, "
                               "keep_tension: true}")
    assert text.count("keep_tension: true") == 3
    plan, result = _wu2021_variant(text, "kelvin")
    assert result.completed(0), result.describe_failure(0)
    force = result.history["contact_force"][0]
    assert np.min(force) < -0.01 * np.max(force)
