"""Every integrator: convergence order, stability limits, event-aware contact stepping."""

import math

import numpy as np
import pytest

from pframe.assemble import assemble
from pframe.errors import InputError
from pframe.kernel import simulate
from pframe.kernel.state import Status, StatusColumn
from pframe.reader import load_scene, parse_scene

MASS, STIFFNESS = 1000.0, 4.0e6
FREE = """
buildings:
  - {{name: A, floors: 3, mass: {m}, story: {{material: elastic, stiffness: {k}}}}}
damping: {{ratio: 0.0}}
initial_conditions: {{displacement: {{A/1: 0.01, A/2: 0.02, A/3: 0.025}}}}
analysis: {{integrator: {integrator}, dt: {dt!r}, duration: {duration!r}}}
recorders: [{{kind: history, quantities: [displacement]}}]
"""
INTEGRATORS = {
    "average_acceleration": "{type: newmark}",
    "linear_acceleration": "{type: newmark, variant: linear_acceleration}",
    "hht": "{type: hht, alpha: 0.1}",
    "generalized_alpha": "{type: generalized_alpha, rho_infinity: 0.6}",
    "wilson_theta": "{type: wilson_theta, theta: 1.4}",
    "central_difference": "{type: central_difference}",
}


def test_every_integrator_is_tested():
    """The cases above cover every integrator pframe offers: a new one fails here until it
    has its convergence case."""
    import yaml

    from pframe.integrators import ALL_INTEGRATORS

    tested = {yaml.safe_load(text)["type"] for text in INTEGRATORS.values()}
    assert tested == {cls.model_fields["type"].default for cls in ALL_INTEGRATORS}


def _modal_free_vibration(times):
    """Exact u(t) of the undamped 3-storey shear building from rest at the initial shape."""
    k, m = STIFFNESS, MASS
    K = k * np.array([[2, -1, 0], [-1, 2, -1], [0, -1, 1]], dtype=float)
    w2, phi = np.linalg.eigh(K / m)
    q0 = phi.T @ np.array([0.01, 0.02, 0.025])
    return (phi @ (q0[:, None] * np.cos(np.sqrt(w2)[:, None] * times[None, :]))).T


@pytest.mark.parametrize("name", list(INTEGRATORS))
def test_second_order_on_free_vibration(name):
    """Errors against the modal solution fall four-fold per halving of dt (order 2 within
    0.1) for every integrator, explicit included (below its stability limit)."""
    w_max = math.sqrt(STIFFNESS / MASS * (2 + 2 * math.cos(2 * math.pi / 7)))
    duration = 0.5
    errors = []
    for dt in (0.4 / w_max, 0.2 / w_max, 0.1 / w_max):
        dt = duration / round(duration / dt)
        text = FREE.format(m=MASS, k=STIFFNESS, integrator=INTEGRATORS[name], dt=dt,
                           duration=duration)
        plan = assemble(parse_scene(text).expanded)
        result = simulate(plan)
        assert result.completed(0), result.describe_failure(0)
        u = result.history["displacement"][0][:, plan.node_dof]
        exact = _modal_free_vibration(plan.times)
        errors.append(np.max(np.abs(u - exact)) / np.max(np.abs(exact)))
    orders = np.log2(np.array(errors[:-1]) / np.array(errors[1:]))
    assert np.all(np.abs(orders - 2.0) < 0.1), (errors, orders)


def _wu2021(dt: float, steps: int, events: bool):
    """The paper's example, shortened to two impacts per floor, at a given dt."""
    text = load_scene("models/wu2021-eq14.yaml").text
    text = text.replace("integrator: {type: newmark, gamma: 0.5, beta: 0.25}",
                        f"integrator: {{type: newmark, events: {str(events).lower()}}}")
    text = text.replace("dt: 0.00015915494309189535", f"dt: {dt!r}")
    text = text.replace("duration: 7.957747154594767", f"duration: {dt * steps!r}")
    text = text.replace("[displacement, velocity, story_force, story_drift, contact_force]",
                        "[displacement]")
    plan = assemble(parse_scene(text).expanded)
    result = simulate(plan)
    assert result.completed(0), result.describe_failure(0)
    return result.history["displacement"][0], result.impacts[0]


@pytest.mark.slow
def test_event_aware_stepping_is_second_order_through_impacts():
    """With events, improved-Kelvin pounding converges at second order (the onset velocity is
    taken at the crossing). Measured: orders 1.93, 1.99, 1.99 with events; without, the
    error depends on where in a step each impact begins: orders 2.28, 0.79, 1.83."""
    dt0 = 2 * 0.00015915494309189535
    steps = 7800
    reference, impacts = _wu2021(dt0 / 32, steps * 32, True)
    assert list(impacts) == [2, 2, 2]
    errors = []
    for refine in (1, 2, 4):
        u, _ = _wu2021(dt0 / refine, steps * refine, True)
        errors.append(np.max(np.abs(u - reference[:: 32 // refine])) / np.max(np.abs(reference)))
    orders = np.log2(np.array(errors[:-1]) / np.array(errors[1:]))
    assert np.all(orders > 1.8), (errors, orders)


def test_explicit_step_above_the_limit_is_refused_or_substepped():
    # the initial-stiffness twin: with damping on the tangent (the paper's K(t)) central
    # difference at 2 sub-steps of 0.005 s diverges, and says so, after 5 impacts
    text = load_scene("models/wu2021-eq14-initial.yaml").text
    text = text.replace("integrator: {type: newmark, gamma: 0.5, beta: 0.25}",
                        "integrator: {type: central_difference}")
    coarse = text.replace("dt: 0.00015915494309189535", "dt: 0.005")
    with pytest.raises(InputError, match=r"stability limit .* = 0\.004\d+ s \(w_max = 412"):
        assemble(parse_scene(coarse).expanded)
    auto = coarse.replace("type: central_difference}", "type: central_difference, substeps: auto}")
    plan = assemble(parse_scene(auto).expanded)
    assert plan.cd_parts[0] == 2
    result = simulate(plan)
    assert result.completed(0)
    assert list(result.impacts[0]) == [8, 8, 8]


def test_contact_resolution_warning():
    text = load_scene("models/wu2021-eq14.yaml").text
    plan = assemble(parse_scene(text.replace("dt: 0.00015915494309189535", "dt: 0.005")).expanded)
    assert len(plan.warnings) == 1 and "3.1 steps, fewer than 20" in plan.warnings[0]
    assert not assemble(parse_scene(text).expanded).warnings  # 97 steps per contact period


def test_divergence_stops_with_time_step_and_node():
    """Linear acceleration above its limit sqrt(12) / w_max diverges; the run stops with the
    time, step and node, and what it recorded holds no NaN."""
    w_max = math.sqrt(STIFFNESS / MASS * (2 + 2 * math.cos(2 * math.pi / 7)))
    dt = 2.0 * math.sqrt(12.0) / w_max
    text = FREE.format(m=MASS, k=STIFFNESS, integrator=INTEGRATORS["linear_acceleration"],
                       dt=dt, duration=400 * dt)
    plan = assemble(parse_scene(text).expanded)
    result = simulate(plan)
    assert result.status[0, StatusColumn.CODE] in (Status.NOT_STABLE, Status.NOT_FINITE)
    message = result.describe_failure(0)
    assert "diverged" in message and "step" in message and "node A/" in message
    done = result.states_done(0)
    assert 1 < done < 400
    assert np.all(np.isfinite(result.history["displacement"][0][:done]))


# ---------------------------------------------------------------------------------------------
# The integrator as one unit: the kernel's scheme against the method's own recurrence


def _oscillator(integrator: str, stiffness: float, dt: float, steps: int, floors: int = 1,
                extra: str = ""):
    """pframe on a shear building of unit masses from u = 1 m on every floor, at rest."""
    start = ", ".join(f"A/{i + 1}: 1.0" for i in range(floors))
    text = f"""
buildings:
  - {{name: A, floors: {floors}, mass: 1.0, story: {{material: elastic, stiffness: {stiffness!r}}}}}
initial_conditions: {{displacement: {{{start}}}}}
analysis: {{integrator: {integrator}, dt: {dt!r}, duration: {dt * steps!r}}}
recorders: [{{kind: history, quantities: [displacement, velocity, acceleration]}}]
{extra or "damping: {ratio: 0.0}"}
"""
    plan = assemble(parse_scene(text).expanded)
    result = simulate(plan)
    assert result.completed(0), result.describe_failure(0)
    return plan, result


def _matrices(plan):
    """M, C, K of member 0 in DOF order (storey springs, Rayleigh on the initial stiffness)."""
    n = plan.n_dof
    M = np.diag(plan.mass[0])
    K, C = np.zeros((n, n)), np.diag(plan.mass_damping[0])
    for (low, up), k0, beta in zip(plan.story_dofs, plan.story_k0[0], plan.story_beta[0]):
        for matrix, value in ((K, k0), (C, beta * k0)):
            matrix[up, up] += value
            if low >= 0:
                matrix[low, low] += value
                matrix[low, up] -= value
                matrix[up, low] -= value
    return M, C, K


def _wilson_bathe(M, C, K, u0, theta: float, dt: float, steps: int, load):
    """Wilson-theta for M u'' + C u' + K u = p(t), from u0 at rest, step by step as Bathe
    gives it (Finite Element Procedures, 1996, Table 9.3): the effective stiffness, the
    effective load at t + theta dt with the load extrapolated linearly, then the step end.
    Independent of pframe's code."""
    tau = theta * dt
    a0, a1 = 6.0 / tau**2, 3.0 / tau
    a2, a3 = 2.0 * a1, tau / 2.0
    a4, a5 = a0 / theta, -a2 / theta
    a6, a7 = 1.0 - 3.0 / theta, dt / 2.0
    a8 = dt**2 / 6.0
    u, v = np.array(u0, dtype=float), np.zeros(len(u0))
    a = np.linalg.solve(M, load(0.0) - C @ v - K @ u)
    out = [u]
    k_hat = K + a0 * M + a1 * C
    for n in range(steps):
        t = n * dt
        r_hat = (load(t) + theta * (load(t + dt) - load(t))
                 + M @ (a0 * u + a2 * v + 2.0 * a) + C @ (a1 * u + 2.0 * v + a3 * a))
        u_tau = np.linalg.solve(k_hat, r_hat)
        a_new = a4 * (u_tau - u) + a5 * v + a6 * a
        v_new = v + a7 * (a_new + a)
        u_new = u + dt * v + a8 * (a_new + 2.0 * a)
        u, v, a = u_new, v_new, a_new
        out.append(u)
    return np.array(out)


@pytest.mark.parametrize("w_dt", [0.05, 0.5, 5.0])
def test_wilson_theta_is_wilsons_method(w_dt):
    """The kernel's Wilson-theta step equals Bathe's tabulated algorithm on a damped, forced
    two-storey building, to round-off, from w_1 dt = 0.05 (accurate) to 5 (stiff modes it
    damps)."""
    k, theta, omega_g = 400.0, 1.4, 7.0
    w1 = math.sqrt(k * (3.0 - math.sqrt(5.0)) / 2.0)  # first mode of two unit masses
    dt = w_dt / w1
    extra = (f"damping: {{ratio: 0.03}}\n"
             f"excitation: {{kind: sine, amplitude: 2.0, frequency: {omega_g!r}}}")
    plan, result = _oscillator(f"{{type: wilson_theta, theta: {theta}}}", k, dt, 60, floors=2,
                               extra=extra)
    M, C, K = _matrices(plan)
    assert C[0, 0] > 0  # the test means something only with damping
    # pframe's relative formulation: p(t) = -M 1 a_g(t)
    ones = np.ones(plan.n_dof)
    exact = _wilson_bathe(M, C, K, ones, theta, dt, 60,
                          lambda t: -M @ ones * 2.0 * math.sin(omega_g * t))
    u = result.history["displacement"][0]
    assert np.max(np.abs(u - exact)) <= 1e-12 * np.max(np.abs(exact)), np.abs(u - exact).max()


@pytest.mark.parametrize("name,w_dt", [
    (name, w_dt) for name in ("average_acceleration", "linear_acceleration", "hht",
                              "generalized_alpha", "wilson_theta")
    for w_dt in (0.3, 3.0)
    if not (name == "linear_acceleration" and w_dt > 2.0)])  # unstable above sqrt(12)
def test_kernel_steps_with_its_amplification_matrix(name, w_dt):
    """Free vibration in the kernel is x(n+1) = A x(n) of the integrator's amplification
    matrix (pframe.integrators, which the dt checks use) for x = (u, h v, h^2 a): the kernel's
    scheme and the Python description of it are one method."""
    import yaml

    from pframe.model.scene import Analysis

    w = 20.0
    dt = w_dt / w
    steps = 40
    config = yaml.safe_load(INTEGRATORS[name])
    coefficients = Analysis(integrator=config, dt=dt, duration=1.0).integrator.coefficients()
    _, result = _oscillator(INTEGRATORS[name], w * w, dt, steps)
    x = np.array([1.0, 0.0, -w * w * dt * dt])
    matrix = coefficients.amplification(w_dt)
    expected = [x[0]]
    for _ in range(steps):
        x = matrix @ x
        expected.append(x[0])
    u = result.history["displacement"][0][:, 0]
    assert np.max(np.abs(u - np.array(expected))) <= 1e-12, np.abs(u - expected).max()


def test_wilson_theta_stability_bound():
    """Wilson-theta is unconditionally stable from theta = (1 + sqrt 3) / 2 = 1.366 (Hilber &
    Hughes 1978): spectral radius <= 1 at every w dt for the smallest theta pframe accepts,
    above 1 at large w dt below the bound (which is why pframe refuses theta < 1.37)."""
    from pframe.integrators import WilsonTheta

    w_dt = np.logspace(-2, 6, 200)
    stable = WilsonTheta(theta=1.37).coefficients()
    assert max(stable.spectral_radius(x) for x in w_dt) <= 1.0 + 1e-12
    below = WilsonTheta.model_construct(theta=1.35, events=False).coefficients()
    assert below.spectral_radius(1e4) > 1.0
    with pytest.raises(InputError, match=r"theta: Input should be greater than or equal to 1.37"):
        WilsonTheta(theta=1.3)


def test_wilson_theta_dissipation_is_counted():
    """Wilson-theta damps a free vibration (as its amplification matrix says); the energy it
    takes is the ALGORITHMIC term, so the balance closes to round-off."""
    from pframe.kernel.state import Energy

    w, dt, steps = 20.0, 0.02, 400  # w dt = 0.4: 15.7 steps per period
    _, result = _oscillator("{type: wilson_theta, theta: 1.4}", w * w, dt, steps)
    energy = result.energy[0]
    u = result.history["displacement"][0][:, 0]
    v = result.history["velocity"][0][:, 0]
    start = 0.5 * w * w * 1.0**2
    mechanical = 0.5 * w * w * u[-1] ** 2 + 0.5 * v[-1] ** 2
    assert mechanical < 0.8 * start  # damped by the integrator alone (no damping here)
    # W_storeys is the rise of the spring's energy; the balance closes with the modified
    # kinetic energy and the algorithmic term
    assert energy[Energy.STOREYS] == pytest.approx(0.5 * w * w * (u[-1] ** 2 - 1.0), rel=1e-12)
    balance = (energy[Energy.KINETIC] - energy[Energy.KINETIC_0] + energy[Energy.STOREYS]
               + energy[Energy.ALGORITHMIC])
    assert abs(balance) <= 1e-12 * start, balance
    assert energy[Energy.ALGORITHMIC] > 0.2 * start
