"""Demand quantities of fragility and loss work: absolute floor acceleration, residual drift,
ductility, impact-induced storey shear, the per-impact table and the Park-Ang damage index."""

from __future__ import annotations

import numpy as np
import pytest
from conftest import run_text, scene_text

MASS, STIFFNESS = 1000.0, 4.0e5


def _sdof(integrator: dict, dt: float, duration: float, recorders: list, amplitude=3.0,
          frequency=9.0, story=None, zeta=0.0, extra=None) -> tuple:
    story = story or {"material": "elastic", "stiffness": STIFFNESS}
    scene = {"buildings": [{"name": "A", "floors": 1, "mass": MASS, "story": story}],
             "damping": {"ratio": zeta, "modes": [1, 1]} if zeta else {"ratio": 0.0},
             "excitation": {"kind": "sine", "amplitude": amplitude, "frequency": frequency},
             "analysis": {"integrator": integrator, "dt": dt, "duration": duration},
             "recorders": recorders}
    scene |= extra or {}
    plan, result = run_text(scene_text(**scene))
    assert result.completed(0), result.describe_failure(0)
    return plan, result


# ---------------------------------------------------------------------------------------------
# absolute acceleration
# ---------------------------------------------------------------------------------------------

def test_absolute_acceleration_is_the_inertia_of_the_storey_force():
    """An undamped elastic SDOF: m (u'' + a_g) = -k u at every committed state (Newmark
    imposes equilibrium at the step end), so the absolute acceleration is -k u / m, whatever
    the ground does."""
    plan, result = _sdof({"type": "newmark", "gamma": 0.5, "beta": 0.25}, 1e-3, 2.0,
                         [{"kind": "history", "quantities": ["displacement",
                                                             "absolute_acceleration"]}])
    u = result.history["displacement"][0, :, 0]
    a = result.history["absolute_acceleration"][0, :, 0]
    assert np.abs(a).max() > 1.0
    np.testing.assert_allclose(a, -STIFFNESS / MASS * u, rtol=0, atol=1e-9 * np.abs(a).max())


def test_absolute_acceleration_envelope_sees_substeps_with_their_ground():
    """Central difference in sub-steps: each committed sub-step is in equilibrium,
    m a_abs = -k u, with the ground interpolated to the sub-step. The envelope of the absolute
    acceleration is k/m times the displacement's envelope (both gathered at every sub-step);
    with the step end's ground acceleration at the sub-steps it was not."""
    plan, result = _sdof({"type": "central_difference", "substeps": "auto", "safety": 0.05},
                         0.02, 1.0,
                         [{"kind": "envelope", "quantities": ["displacement",
                                                              "absolute_acceleration"]}],
                         amplitude=10.0, frequency=30.0)
    assert plan.cd_parts[0] > 1
    peak_u = result.envelope["displacement"][0, 0]
    peak_a = result.envelope["absolute_acceleration"][0, 0]
    assert peak_a == pytest.approx(STIFFNESS / MASS * peak_u, rel=1e-9)
