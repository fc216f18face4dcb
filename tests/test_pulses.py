"""Pulse excitations: the cycloidal pulses of Makris & Black (2004) and the Ricker wavelet.

Their velocity and displacement histories are checked against the published expressions
(written here in the papers' own form, with V_p) and against the numerical integrals of the
acceleration; a pulse in a scene is sampled on the analysis grid like the sine.
"""

import math
from pathlib import Path

import numpy as np
import pytest
from scipy.integrate import cumulative_trapezoid

from pframe.errors import InputError
from pframe.excitation.pulses import cycloidal_phase, pulse_end, pulse_motion
from pframe.model.scene import Cycloidal, Ricker
from pframe.reader import parse_scene

AP, TP = 3.0, 0.8
WP = 2 * math.pi / TP


def _pulse(**fields):
    kind = fields.pop("kind", "cycloidal")
    return (Ricker if kind == "ricker" else Cycloidal)(kind=kind, amplitude=AP, period=TP,
                                                        **fields)


def test_published_phase_of_type_c_pulses():
    """Makris & Black (2004): phi = 0.0697 pi (C_1) and 0.0410 pi (C_2)."""
    assert cycloidal_phase(1) / math.pi == pytest.approx(0.0697, abs=5e-5)
    assert cycloidal_phase(2) / math.pi == pytest.approx(0.0410, abs=5e-5)


def _published(kind: str, t, n=1):
    """Makris & Black (2004), eqs. 1-3, in V_p: the ground velocity and displacement."""
    if kind == "A":
        vp = 2 * AP / WP  # a_p = w_p V_p / 2
        return vp / 2 - vp / 2 * np.cos(WP * t), vp / 2 * t - vp / (2 * WP) * np.sin(WP * t)
    if kind == "B":
        vp = AP / WP  # a_p = w_p V_p
        return vp * np.sin(WP * t), vp / WP - vp / WP * np.cos(WP * t)
    phi = cycloidal_phase(n)
    vp = AP / WP
    return (vp * np.sin(WP * t + phi) - vp * math.sin(phi),
            -vp / WP * np.cos(WP * t + phi) + vp / WP * math.cos(phi) - vp * math.sin(phi) * t)


@pytest.mark.parametrize("kind, n", [("A", 1), ("B", 1), ("C", 1), ("C", 2), ("C", 3)])
def test_cycloidal_velocity_and_displacement_are_the_published_ones(kind, n):
    pulse = _pulse(type=kind, n=n)
    t = np.linspace(0.0, pulse_end(pulse), 2001)
    _, v, u = pulse_motion(pulse, t)
    v_pub, u_pub = _published(kind, t, n)
    scale_v, scale_u = AP / WP, AP / WP**2
    assert np.max(np.abs(v - v_pub)) < 1e-13 * scale_v
    assert np.max(np.abs(u - u_pub)) < 1e-12 * scale_u


@pytest.mark.parametrize("fields", [{"type": "A"}, {"type": "B"}, {"type": "C", "n": 1},
                                    {"type": "C", "n": 2}, {"kind": "ricker"},
                                    {"kind": "ricker", "center": 2.0}])
def test_velocity_and_displacement_are_integrals_of_the_acceleration(fields):
    """Trapezoidal integrals on a fine grid over the pulse converge to the closed forms (error
    O(h^2)); what follows the pulse is checked in test_pulse_end_states."""
    pulse = _pulse(**fields)
    t = np.linspace(0.0, pulse_end(pulse), 200001)
    a, v, u = pulse_motion(pulse, t)
    v_num = cumulative_trapezoid(a, t, initial=0.0)
    u_num = cumulative_trapezoid(v, t, initial=0.0)
    assert np.max(np.abs(v_num - v)) < 1e-6 * AP / WP
    assert np.max(np.abs(u_num - u)) < 1e-6 * AP / WP**2


def test_pulse_end_states():
    """Type A leaves the ground displaced by V_p T_p / 2 at rest; B and C_n bring it back to
    its start at rest (the phase of C_n is chosen so); the Ricker wavelet leaves it at rest
    where it started."""  # noqa: D205
    for fields, offset in [({"type": "A"}, (2 * AP / WP) * TP / 2), ({"type": "B"}, 0.0),
                           ({"type": "C", "n": 1}, 0.0), ({"type": "C", "n": 2}, 0.0),
                           ({"kind": "ricker"}, 0.0)]:
        pulse = _pulse(**fields)
        _, v, u = pulse_motion(pulse, np.array([pulse_end(pulse), pulse_end(pulse) + 5.0]))
        assert np.all(np.abs(v) < 1e-8 * AP / WP), fields
        # (the Ricker wavelet, cut at 2 t_0, keeps a velocity of 2 a_p t_0 e^{-pi^2 t_0^2/T_p^2},
        # 2e-9 m/s here: 1e-8 m of drift in the 5 s after it)
        assert u == pytest.approx([offset, offset], abs=1e-6 * AP / WP**2), fields


def test_ricker_published_form():
    """a(t) = a_p (1 - 2 pi^2 f^2 s^2) exp(-pi^2 f^2 s^2), f = 1/T_p: its peak a_p at t_0,
    its zero crossings at s = +-T_p / (pi sqrt 2), its ground displacement
    -a_p T_p^2 / (2 pi^2) at t_0 (the Gaussian's integral)."""
    pulse = _pulse(kind="ricker")
    t0 = 1.5 * TP
    a, _, u = pulse_motion(pulse, np.array([t0, t0 + TP / (math.pi * math.sqrt(2)), t0]))
    assert a[0] == pytest.approx(AP, rel=1e-14)
    assert abs(a[1]) < 1e-14 * AP
    assert u[2] == pytest.approx(-AP * TP**2 / (2 * math.pi**2), rel=1e-7)


def test_characteristic_scales_for_pi_numbers():
    pulse = _pulse(type="B")
    assert pulse.characteristic_acceleration == AP
    assert pulse.characteristic_frequency == pytest.approx(2 * math.pi / TP)
    assert pulse.frequency == pulse.characteristic_frequency


SCENE = """
buildings:
  - {{name: A, floors: 1, mass: 1000.0, story: {{material: elastic, stiffness: 4.0e5}}}}
excitation: {excitation}
analysis: {{dt: 0.002, duration: 3.0}}
"""


def test_pulse_in_a_scene_is_sampled_on_the_grid():
    loaded = parse_scene(SCENE.format(excitation="{kind: cycloidal, type: C, n: 2, "
                                                 "amplitude: 3.0, period: 0.8}"))
    t = np.arange(loaded.expanded.steps + 1) * 0.002
    expected = pulse_motion(loaded.scene.excitation, t)[0]
    assert np.array_equal(loaded.expanded.ground_acceleration, expected)
    assert np.all(expected[t > pulse_end(loaded.scene.excitation) + 1e-9] == 0.0)


@pytest.mark.parametrize("excitation, message", [
    ("{kind: cycloidal, type: A, n: 2, amplitude: 3.0, period: 0.8}", "type C only"),
    ("{kind: cycloidal, type: D, amplitude: 3.0, period: 0.8}", "type"),
    ("{kind: ricker, amplitude: 3.0, period: 0.0}", "period"),
    ("{kind: ricker, amplitude: 3.0, period: 0.8, cycles: 2}", "cycles"),
])
def test_bad_pulses_are_refused_naming_the_field(excitation, message):
    with pytest.raises(InputError, match=message) as info:
        parse_scene(SCENE.format(excitation=excitation), source="pulse.yaml")
    assert "pulse.yaml, line 4, excitation" in str(info.value)  # the excitation line


@pytest.mark.slow
@pytest.mark.parametrize("excitation", [
    {"kind": "cycloidal", "type": "C", "n": 2},
    {"kind": "ricker", "center": 1.2},
], ids=["cycloidal-C2", "ricker"])
def test_pi_form_scenes_take_pulses(excitation, tmp_path):
    """A Pi-form scene under a pulse: ``expand`` then ``pframe pi`` gives back the numbers
    written (a_p and w_p are the pulse's), and two unrelated sets of scales give the same
    dimensionless response."""
    import xarray as xr
    import yaml

    from pframe.cli import main
    from pframe.nondim import scene_pi

    repo = Path(__file__).resolve().parents[1]
    data = yaml.safe_load((repo / "models" / "wu2021-eq14-pi.yaml").read_text())
    data["excitation"] = excitation
    data["analysis"]["tau"] = 15
    data["pi"]["Pi_d"] = 0.05  # a gap the pulses close
    data["recorders"] = [{"kind": "history", "quantities": ["displacement", "contact_force"]}]
    runs = []
    for i, scales in enumerate(({"m_b": 1000.0, "a_p": 9.81, "w_p": 6.283185307179586},
                                {"m_b": 3.0, "a_p": 0.2, "w_p": 40.0})):
        scene = tmp_path / f"pulse-{i}.yaml"
        scene.write_text(yaml.safe_dump(data | {"scales": scales}))
        expanded = parse_scene(scene.read_text(), source=str(scene), base_dir=tmp_path)
        assert expanded.scene.excitation.kind == excitation["kind"]
        assert expanded.scene.excitation.period == pytest.approx(2 * math.pi / scales["w_p"])
        report = scene_pi(expanded.scene, expanded.expanded)
        for name, value in data["pi"].items():
            assert report.values[name] == pytest.approx(value, rel=1e-12), name
        out = tmp_path / f"pulse-{i}.nc"
        assert main(["solve", str(scene), "-o", str(out), "-q"]) == 0
        with xr.open_dataset(out, engine="h5netcdf") as ds:
            runs.append((ds.displacement.values, ds.contact_force.values,
                         ds.impact_count.values))
    (u0, f0, n0), (u1, f1, n1) = runs
    assert np.array_equal(n0, n1) and n0.sum() > 0
    assert np.max(np.abs(u0 - u1)) <= 1e-9 * np.max(np.abs(u0))
    assert np.max(np.abs(f0 - f1)) <= 1e-8 * np.max(np.abs(f0))
