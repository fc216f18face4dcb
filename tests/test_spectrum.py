"""The elastic response spectrum (exact piecewise-linear recurrence, Nigam & Jennings 1969)
against a closed form (the steady state under a sine) and against SDOFs integrated by the
kernel."""

import json
import math

import numpy as np
import pytest

from pframe.assemble import assemble_batch
from pframe.excitation.spectrum import response_spectrum, sdof_response, spectral_acceleration
from pframe.kernel import simulate
from pframe.reader import parse_scene


def _steady(a, big_w, period, xi):
    """Complex amplitude U of u = Im(U e^{i W t}) for u'' + 2 xi w u' + w^2 u = -a sin(W t)."""
    w = 2 * math.pi / period
    return -a / (w * w - big_w * big_w + 2j * xi * w * big_w)


@pytest.mark.parametrize("period, xi", [(0.3, 0.05), (0.7, 0.05), (0.7, 0.0), (2.0, 0.2)])
def test_sine_record_from_its_steady_state_stays_on_it(period, xi):
    """Started on the closed-form steady state, the recurrence follows it: the sine sampled at
    dt differs from its piecewise-linear interpolation by O(dt^2), and so does the response."""
    a, big_w, dt = 3.0, 2 * math.pi / 0.7 * 1.03, 0.001
    t = np.arange(0, 20.0, dt)
    u_amp = _steady(a, big_w, period, xi)
    u, v = sdof_response(a * np.sin(big_w * t), dt, period, xi, u_amp.imag,
                         (1j * big_w * u_amp).imag)
    exact = (u_amp * np.exp(1j * big_w * t)).imag
    assert np.max(np.abs(u - exact)) < 1e-4 * abs(u_amp)
    assert np.max(np.abs(u)) == pytest.approx(abs(u_amp), rel=1e-4)


def test_recurrence_is_exact_for_piecewise_linear_motion():
    """A coarse record and the same record refined by linear interpolation give the same
    response at the coarse samples to round-off: the recurrence has no time-step error."""
    rng = np.random.default_rng(3)
    coarse = rng.normal(size=400)
    dt = 0.02
    fine = np.interp(np.arange(0, 399 * dt + 1e-9, dt / 8), np.arange(400) * dt, coarse)
    for period in (0.05, 0.5, 3.0):
        u_coarse, _ = sdof_response(coarse, dt, period, 0.05)
        u_fine, _ = sdof_response(fine, dt / 8, period, 0.05)
        assert np.max(np.abs(u_fine[::8] - u_coarse)) < 1e-10 * np.max(np.abs(u_coarse))


def test_zero_period_is_the_pga_and_pseudo_quantities():
    acc = np.sin(np.linspace(0, 30, 3001)) * np.linspace(1, 0, 3001) * 4.0
    spec = response_spectrum(acc, 0.01, [0.0, 0.5, 1.0])
    assert spec["PSa"][0] == np.max(np.abs(acc))
    w = 2 * np.pi / np.array([0.5, 1.0])
    assert spec["PSa"][1:] == pytest.approx(w**2 * spec["Sd"][1:], rel=1e-15)
    assert spec["PSv"][1:] == pytest.approx(w * spec["Sd"][1:], rel=1e-15)


def test_peaks_equal_sdofs_integrated_by_the_kernel(tmp_path):
    """SDOF buildings of the same periods and 5 % damping (one batch of the kernel, Newmark at
    a twentieth of the record's step) reach the spectrum's peaks."""
    rng = np.random.default_rng(11)
    dt_record = 0.01
    t = np.arange(0, 20.0, dt_record)
    acc = np.convolve(rng.normal(size=t.size), np.ones(8) / 8, mode="same")
    acc *= 2.5 * np.exp(-((t - 6) / 5) ** 2)
    np.savetxt(tmp_path / "rec.txt", np.column_stack([t, acc]), fmt="%.17g")
    periods = np.array([0.3, 0.6, 1.2, 2.5])
    mass = 1000.0
    variants = []
    for period in periods:
        k = mass * (2 * math.pi / period) ** 2
        scene = {"buildings": [{"name": "S", "floors": 1, "mass": mass,
                                "story": {"material": "elastic", "stiffness": k}}],
                 "damping": {"ratio": 0.05},
                 "excitation": {"kind": "record", "file": "rec.txt"},
                 "analysis": {"dt": dt_record / 20, "duration": 24.0},
                 "recorders": [{"kind": "envelope", "quantities": ["displacement"]}]}
        variants.append(parse_scene(json.dumps(scene), base_dir=tmp_path).expanded)
    result = simulate(assemble_batch(variants))
    peaks = result.envelope["displacement"][:, 0]
    padded = np.concatenate([acc, np.zeros(int(4.0 / dt_record))])  # the kernel's free tail
    sd = response_spectrum(padded, dt_record, periods, 0.05)["Sd"]
    assert peaks == pytest.approx(sd, rel=2e-3)
    assert spectral_acceleration(padded, dt_record, 1.2) == pytest.approx(
        (2 * math.pi / 1.2) ** 2 * sd[2], rel=1e-14)
