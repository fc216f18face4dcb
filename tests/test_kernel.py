"""The kernel: one compiled kernel for every scene, and only what a scene needs at run time.

What a scene does not use is shown by the counters the kernel reports (solves,
factorisations, residual evaluations, evaluations of each law, gathered values), not by
reading code: the kernel is the same for every scene.
"""

import json
import sys

import numpy as np
import pytest
import yaml
from conftest import RECORDERS, WU2021, integrator_configurations, scene_text

from pframe.assemble import assemble
from pframe.kernel import simulate
from pframe.reader import load_scene, parse_scene

ELASTIC = """
buildings:
  - {name: A, floors: 3, mass: 1000.0, story: {material: elastic, stiffness: 2.0e6}}
excitation: {kind: sine, amplitude: 2.0, frequency: 6.0}
analysis: {dt: 0.005, duration: 2.0}
recorders: [{kind: envelope, quantities: [displacement]}]
"""


def test_linear_scene_factors_once_and_solves_once_a_step():
    plan = assemble(parse_scene(ELASTIC).expanded)
    result = simulate(plan)
    assert plan.linear and result.completed()
    assert result.counter("factorisations") == 1
    assert result.counter("solves") == plan.steps
    # no Newton iteration: the residual at the start, the forces at the end of each step
    assert result.counter("evaluations") == 2 * plan.steps + 1
    assert result.counter("split_steps") == 0
    assert result.law_calls == {"elastic": 3 * result.counter("evaluations")}
    # one envelope of 3 nodes, gathered once per state; no history
    assert result.counter("gathers") == 3 * (plan.steps + 1)
    assert result.history == {}


def test_scene_without_contacts_evaluates_no_contact_law():
    data = json.loads(scene_text(
        buildings=[{"name": "A", "floors": 3, "mass": 1000.0,
                    "story": {"material": "bilinear", "stiffness": 2.0e6, "yield_drift": 0.01,
                              "alpha": 0.1}}],
        excitation={"kind": "sine", "amplitude": 4.0, "frequency": 6.0},
        analysis={"dt": 0.005, "duration": 2.0}))
    plan = assemble(parse_scene(json.dumps(data)).expanded)
    result = simulate(plan)
    assert not plan.linear and result.completed()
    assert set(result.law_calls) == {"bilinear"}
    assert result.law_calls["bilinear"][0] == 3 * result.counter("evaluations")
    # histories of the recorders of conftest.RECORDERS that apply: 3 nodes x 2, 3 storeys x 2;
    # envelopes: 3 nodes, 3 storeys; contact quantities are dropped without contacts
    assert result.counter("gathers") == (12 + 6) * (plan.steps + 1)


def test_nonlinear_scene_gathers_what_it_records_only():
    plan = assemble(load_scene(WU2021).expanded)
    result = simulate(plan)
    assert set(result.history) == {"displacement", "velocity", "story_force", "story_drift",
                                   "contact_force"}
    assert set(result.envelope) == {"displacement", "story_drift", "contact_force"}
    per_state = (6 + 6 + 6 + 6 + 3) + (6 + 6 + 3)
    assert result.counter("gathers") == per_state * (plan.steps + 1)
    assert result.law_calls["improved_kelvin"][0] == 3 * result.counter("evaluations")
    assert result.law_calls["bilinear"][0] == 6 * result.counter("evaluations")


@pytest.mark.slow
def test_chunked_run_equals_single_run():
    """The progress-bar path (many kernel calls) gives bit-identical results. The paper's
    scene over its first 2.5 s (about 15,700 steps): two impacts at each contact, which the
    chunks cut through as the whole run does not."""
    text = WU2021.read_text(encoding="utf-8").replace("duration: 7.957747154594767",
                                                      "duration: 2.5")
    plan = assemble(parse_scene(text).expanded)
    whole = simulate(plan)
    assert np.all(whole.impacts >= 2)
    calls = []
    chunked = simulate(plan, progress=lambda done, total: calls.append(done), chunk_seconds=1e-4)
    assert len(calls) > 5 and calls[-1] == plan.steps + 1
    for q in whole.history:
        assert np.array_equal(whole.history[q], chunked.history[q])
    for q in whole.envelope:
        assert np.array_equal(whole.envelope[q], chunked.envelope[q])
    assert np.array_equal(whole.impacts, chunked.impacts)
    assert np.array_equal(whole.energy, chunked.energy)
    # the same work, but for a factorisation at the start of each call
    for name in ("solves", "evaluations", "split_steps", "gathers"):
        assert whole.counter(name) == chunked.counter(name)


def test_streamed_histories_equal_held_ones(monkeypatch):
    """A sink receives every history row exactly once, in chunks of bounded size."""
    from pframe.kernel import run as run_module

    plan = assemble(load_scene(WU2021).expanded)
    whole = simulate(plan)
    monkeypatch.setattr(run_module, "STREAM_BYTES", 40_000)  # many small chunks
    received: dict[str, list] = {}

    def sink(quantity, first_row, rows):
        parts = received.setdefault(quantity, [])
        assert first_row == sum(p.shape[1] for p in parts)
        assert rows.nbytes <= 40_000
        parts.append(rows.copy())

    streamed = simulate(plan, sink=sink)
    assert streamed.history == {}
    assert len(received["displacement"]) > 10
    for q, rows in whole.history.items():
        assert np.array_equal(np.concatenate(received[q], axis=1), rows), q
    assert np.array_equal(whole.energy, streamed.energy)


def test_one_newton_solve_per_step_while_laws_keep_their_branch():
    """The constant-acceleration predictor meets a storey that keeps yielding on its yield
    branch: the paper's example (every storey of A yields, 24 impacts) needs a second solve
    only in the steps where a storey yields or unloads or a contact is closed. With the
    predictor u = x_n it needed one in four steps of five (88,091 solves)."""
    plan = assemble(load_scene(WU2021).expanded)
    result = simulate(plan)
    assert result.completed(0)
    assert result.impacts.sum() == 24
    assert result.iterations[0] / plan.steps < 1.03  # 50,716 solves for 50,000 steps
    assert result.counter("factorisations") < 0.05 * plan.steps


def test_reusing_the_factorisation_changes_no_bit(monkeypatch):
    """The kernel refactors the effective stiffness only when an element tangent or the
    (sub-)step changed. The kernel made to refactor at every solve gives the same bits, so no
    change of tangent is missed (a missed one would still converge, to different bits)."""
    from pframe.kernel import run as run_module

    data = yaml.safe_load(WU2021.read_text(encoding="utf-8"))
    data["analysis"]["duration"] = 3.0
    plan = assemble(parse_scene(json.dumps(data)).expanded)
    reused = simulate(plan)
    monkeypatch.setattr(run_module, "ALWAYS_REFACTOR", True)
    refactored = simulate(plan)
    assert reused.impacts.sum() > 0
    assert refactored.counter("factorisations") > 10 * reused.counter("factorisations")
    for q in reused.history:
        assert np.array_equal(reused.history[q], refactored.history[q]), q
    assert np.array_equal(reused.energy, refactored.energy)
    assert np.array_equal(reused.iterations, refactored.iterations)


@pytest.mark.slow
def test_every_law_and_integrator_share_one_compiled_kernel():
    """Every built-in material (storeys and links) and contact law under every integrator
    (with and without event location), P-delta, every recordable quantity, record and sine
    excitation: one process, one
    compiled kernel (loaded once), and nothing compiled at run time (numba never imported)."""
    from pframe.kernel import ckernel
    from pframe.laws import all_contact_laws, all_materials, facts

    numba_before = "numba" in sys.modules

    def first(law, tag):  # the law's first example
        return {tag: law.name} | facts.declared(law, "examples")[0]

    # a material without stiffness of its own is a link's
    contact = {law.name: first(law, "law") for law in all_contact_laws()}
    story = {law.name: first(law, "material") for law in all_materials()
             if not getattr(law, "stiffness_free", False)}
    links = {law.name: first(law, "material") for law in all_materials()
             if getattr(law, "stiffness_free", False)}
    integrators = [{"type": "newmark"}, {"type": "newmark", "events": True},
                   {"type": "hht", "alpha": 0.1}, {"type": "generalized_alpha", "events": True},
                   {"type": "wilson_theta", "events": True},
                   {"type": "central_difference", "substeps": "auto"}]
    # and every other integrator of the table, with event location where it has it
    configurations = integrator_configurations()
    integrators += [configurations.get(f"{name}+events", configurations[name])
                    for name in configurations if "+" not in name
                    and name not in {config["type"] for config in integrators}]
    from pframe.kernel.state import RECORDABLE

    every = list(RECORDABLE)
    runs = completed = 0
    for i, integrator in enumerate(integrators):
        for j, (law, params) in enumerate(contact.items()):
            material = list(story)[(i + j) % len(story)]
            link = list(links)[(i + j) % len(links)]
            scene = {
                "buildings": [{"name": "A", "floors": 2, "mass": 1000.0, "story": story[material],
                               "height": 3.0, "p_delta": bool(j % 2)},
                              {"name": "B", "floors": 3, "mass": 800.0, "story": story["elastic"],
                               "height": 3.0}],
                "contacts": [{"name": f"c{f}", "nodes": [f"A/{f}", f"B/{f}"], "gap": 0.002,
                              **params} for f in (1, 2)],
                "links": [{"name": "l", "nodes": ["A/2", "B/3"], **links[link]}],
                "excitation": {"kind": "sine", "amplitude": 3.0, "frequency": 8.0},
                "analysis": {"dt": 0.001, "duration": 0.6, "integrator": integrator},
                "recorders": [{"kind": "history", "quantities": every[: 2 + (i + j) % 10],
                               "every": 1 + j % 3},
                              {"kind": "envelope", "quantities": every[(i + j) % 11:]}],
            }
            result = simulate(assemble(parse_scene(json.dumps(scene)).expanded))
            # clipped Kelvin with event location can stall at a separation (as it did before
            # the kernel was compiled once): such a run stops, late, and says why
            assert result.completed() or result.states_done() > 200, result.describe_failure()
            assert set(result.law_calls) == {law, material, "elastic", link}
            runs += 1
            completed += result.completed()
    assert runs == len(integrators) * len(contact) and completed >= runs - 2
    assert ckernel.library() is ckernel._library
    assert ("numba" in sys.modules) == numba_before


def test_a_baseline_kernel_stands_in_for_the_installed_one_and_gives_it_back():
    """ckernel.baseline (benchmarks/kernel_limit.py --baseline) runs a process's simulations
    with another build of the kernel's library, checked for its interface and structs, and
    restores the installed one after, also when the block raises."""
    import importlib.util

    from pframe.kernel import ckernel

    installed = ckernel.library()
    plan = assemble(parse_scene(scene_text(
        buildings=[{"name": "A", "floors": 2, "mass": 1000.0,
                    "story": {"material": "bilinear", "stiffness": 1e6, "yield_force": 3e3,
                              "alpha": 0.05}}],
        excitation={"kind": "sine", "amplitude": 3.0, "frequency": 2.0},
        analysis={"dt": 0.01, "duration": 1.0}, recorders=RECORDERS)).expanded)
    own = simulate(plan)
    path = importlib.util.find_spec("pframe.kernel._ckernel").origin
    with pytest.raises(KeyError):
        with ckernel.baseline(path):
            assert ckernel.library() is not installed
            other = simulate(plan)
            raise KeyError("out of the block")
    assert ckernel.library() is installed
    for q, rows in own.history.items():
        assert np.array_equal(other.history[q], rows), q


def test_batches_and_single_runs_share_the_kernel():
    """A batch run in threads (a sweep's chunk) calls the same compiled kernel as single
    runs, and each member gives the bits of its single run."""
    from pframe.assemble import assemble_batch

    texts = [scene_text(buildings=[{"name": "A", "floors": 1, "mass": m,
                                    "story": {"material": "elastic", "stiffness": 1e6}}],
                        excitation={"kind": "sine", "amplitude": 1.0, "frequency": 5.0},
                        analysis={"dt": 0.01, "duration": 1.0}, recorders=RECORDERS)
             for m in (500.0, 1000.0, 2000.0)]
    batch = simulate(assemble_batch([parse_scene(t).expanded for t in texts]), threads=2)
    for b, text in enumerate(texts):
        single = simulate(assemble(parse_scene(text).expanded))
        for q, rows in single.history.items():
            assert np.array_equal(batch.history[q][b], rows[0]), q


def _c_force(kind: str, law_id: int, params, committed, deformation: float, rate: float):
    import ctypes

    from pframe.kernel import ckernel

    trial = np.full(max(1, len(committed)), np.nan)
    out = np.zeros(3)
    pointer = ctypes.c_void_p
    ckernel.library().pframe_law_force(
        ctypes.c_int64(0 if kind == "material" else 1), ctypes.c_int64(law_id),
        pointer(params.ctypes.data), pointer(committed.ctypes.data), pointer(trial.ctypes.data),
        ctypes.c_double(deformation), ctypes.c_double(rate), pointer(out.ctypes.data))
    return out, trial


def _imk_peak_sample(law, rng):
    """Parameters, a committed state reached by driving the law along a random cyclic drift
    history of growing amplitude (hardening, capping, residual, deterioration, fracture), and
    a next drift near it (or a repeat of it, or a first step from rest)."""
    base = dict(k0=2.0e7, as_plus=0.03, as_neg=0.04, my_plus=1.0e5, my_neg=1.2e5,
                lamda_s=0.4, lamda_c=0.4, lamda_a=0.4, lamda_k=0.4, c_s=1.0, c_c=1.0,
                c_a=1.0, c_k=1.0, theta_p_plus=0.02, theta_p_neg=0.025, theta_pc_plus=0.06,
                theta_pc_neg=0.08, res_plus=0.3, res_neg=0.25, theta_u_plus=0.15,
                theta_u_neg=0.17, d_plus=1.0, d_neg=0.9)
    values = {k: v * rng.uniform(0.7, 1.3) for k, v in base.items()}
    for name in ("lamda_s", "lamda_c", "lamda_a", "lamda_k"):
        values[name] *= rng.choice([0.0, 1.0])
    for name in ("c_s", "c_c", "c_a", "c_k"):
        values[name] = float(rng.choice([1.0, 1.7, 2.0]))
    for name in ("res_plus", "res_neg", "d_plus", "d_neg"):
        values[name] = min(values[name], 1.0)
    params = np.array(law.pack(law.Params(material="imk_peak", **values)))
    committed = np.zeros(len(law.state_names))
    trial = committed.copy()
    steps = int(rng.integers(0, 400))
    t = np.linspace(0.0, 8.0, 400)
    drifts = 0.2 * (t / 8.0) ** 1.5 * np.sin(2 * np.pi * t) + 0.001 * rng.standard_normal(400)
    for d in drifts[:steps]:
        law.force(params, committed, trial, float(d), 0.0)
        committed = trial.copy()
    d = float(drifts[steps - 1]) if steps else 0.0
    deformation = float(rng.choice([d, d + rng.uniform(-0.01, 0.01), d + 1e-20]))
    return params, committed, deformation


@pytest.mark.slow
def test_every_built_in_law_in_c_is_its_python_force_bit_for_bit():
    """A law is written once, in Python: the kernel's C is translated from it
    (pframe.kernel.translate). Over deformations and rates on both sides of every branch
    (open and closed, loading and unloading, onset and ongoing contact, yielding both ways),
    the compiled C gives the Python function's force, tangents and trial state, bit for bit."""
    from pframe.laws.registry import builtin_laws

    rng = np.random.default_rng(19)
    checked = 0
    for kind in ("material", "contact"):
        for law_id, law in enumerate(builtin_laws(kind)):
            width, states = len(law.param_names), len(law.state_names)
            for _ in range(400):
                params = rng.uniform(0.05, 2.0, max(1, width)) * np.array(
                    [1e6] + [1.0] * (max(1, width) - 1))
                if law.name in ("improved_kelvin", "hertzdamp"):
                    params[1] = rng.choice([1.0, 1.5])  # the exponent n
                    params[2] = rng.choice([0.0, rng.uniform(0.1, 2.0)])  # chi
                if law.name == "kelvin":
                    params[2] = rng.choice([0.0, 1.0])  # keep_tension
                if law.name in ("viscous", "kelvin_voigt"):  # both dashpot branches
                    params[-1] = rng.choice([1e-5, 0.5, 5.0])  # linear_below
                if law.name == "bilinear":
                    params[1] = rng.uniform(1e3, 1e5)  # yield force
                    params[2] = rng.choice([0.0, 0.1, 1.0])  # alpha
                if law.name == "bouc_wen":  # OpenSees' BoucWen, with and without degradation
                    zy = rng.uniform(0.005, 0.05)
                    n = rng.choice([1.0, 2.0, 5.5])
                    params[:] = (rng.choice([0.0, 0.1]), 1e6 * rng.uniform(0.5, 2.0), n,
                                 rng.uniform(0.2, 0.8) / zy**n, rng.uniform(0.2, 0.8) / zy**n,
                                 1.0, rng.choice([0.0, 1e-4]), rng.choice([0.0, 1e-4]),
                                 rng.choice([0.0, 1e-4]), 1e-8, rng.choice([3.0, 20.0]))
                if law.name == "bwbn":  # pinched or not, degrading or not
                    zy = rng.uniform(0.005, 0.05)
                    n = rng.choice([1.0, 2.0, 5.5])
                    params[:] = (rng.choice([0.0, 0.1]), 1e6 * rng.uniform(0.5, 2.0), n,
                                 rng.uniform(0.2, 0.8) / zy**n, rng.uniform(0.2, 0.8) / zy**n,
                                 1.0, rng.choice([0.0, 1e-4]), rng.choice([0.0, 1e-4]),
                                 rng.choice([0.0, 1e-4]), rng.uniform(0.0, 0.3),
                                 rng.choice([0.0, 0.8]), rng.uniform(0.0, 1e-3),
                                 zy * rng.uniform(0.1, 1.0), rng.choice([0.0, 1e-6]),
                                 rng.uniform(0.1, 1.0), 1e-8, rng.choice([3.0, 20.0]))
                if law.name == "friction_pendulum":  # Coulomb or velocity dependent, flat or not
                    w = rng.uniform(1e4, 1e6)
                    params[:] = (w, rng.choice([0.0, 1.0 / rng.uniform(0.5, 4.0)]), 1e3 * w,
                                 0.05, rng.choice([0.05, 0.1]), rng.choice([0.0, 30.0]))
                if law.name == "bumper":  # crushed or not
                    params[1] = 1.5
                    params[2] = rng.choice([0.0, rng.uniform(0.1, 2.0)])
                    params[5] = rng.uniform(0.0, 0.02)
                committed = rng.uniform(-0.01, 0.01, max(1, states)) * rng.choice([0.0, 1.0])
                if states and law.name in ("bouc_wen", "bwbn", "friction_pendulum"):
                    committed[:] = rng.uniform(-0.03, 0.03, states) * rng.choice([0.0, 1.0])
                    if law.name in ("bouc_wen", "bwbn"):
                        committed[2] = rng.uniform(0.0, 1e3)  # the hysteretic energy
                elif states and law.name != "bilinear":
                    committed[-1] = rng.choice([0.0, 1.0])  # in contact or not
                    committed[0] = rng.uniform(-1.0, 1.0)  # the onset velocity
                deformation = float(rng.choice([-1.0, 1.0]) * rng.uniform(0, 0.02))
                if law.name == "imk_peak":  # a state the law reaches on a cyclic history
                    params, committed, deformation = _imk_peak_sample(law, rng)
                rate = float(rng.uniform(-2.0, 2.0))
                trial = np.full(max(1, states), np.nan)
                expected = law.force(params, committed.copy(), trial, deformation, rate)
                got, c_trial = _c_force(kind, law_id, params, committed, deformation, rate)
                assert [float(x) for x in expected] == got.tolist(), (law.name, params, deformation)
                assert np.array_equal(trial[:states], c_trial[:states], equal_nan=True), law.name
                checked += 1
    assert checked == 400 * (len(builtin_laws("material")) + len(builtin_laws("contact")))


def test_the_translator_refuses_what_it_cannot_translate():
    """A built-in law's force outside the translated subset is refused with the law, the line
    and the construct (never C that computes something else)."""
    import re

    import pytest

    from pframe.kernel.translate import TranslationError, translate

    class Looping:
        kind, name, __qualname__ = "contact", "looping", "Looping"

        @staticmethod
        def force(params, committed, trial, deformation, rate):
            total = 0.0
            while total < deformation:
                total += deformation
            return total, 0.0, 0.0

    class Unbounded:  # a loop's bound must be a constant
        kind, name, __qualname__ = "contact", "unbounded", "Unbounded"

        @staticmethod
        def force(params, committed, trial, deformation, rate):
            total = 0.0
            for _ in range(params[0]):
                total += deformation
            return total, 0.0, 0.0

    class Counting:  # the C counter is an int: the law keeps a float count of its own
        kind, name, __qualname__ = "contact", "counting", "Counting"

        @staticmethod
        def force(params, committed, trial, deformation, rate):
            total = 0.0
            for i in range(3):
                total += i
            return total, 0.0, 0.0

    class Calling:
        kind, name, __qualname__ = "contact", "calling", "Calling"

        @staticmethod
        def force(params, committed, trial, deformation, rate):
            return float(round(deformation)), 0.0, 0.0

    class Writing:
        kind, name, __qualname__ = "contact", "writing", "Writing"

        @staticmethod
        def force(params, committed, trial, deformation, rate):
            committed[0] = deformation
            return 0.0, 0.0, 0.0

    for law, what in ((Looping, "While statements"), (Calling, "the call"),
                      (Writing, "only trial[i] may be written"),
                      (Unbounded, "a loop must be `for NAME in range(N):`"),
                      (Counting, "the loop counter 'i' is read")):
        with pytest.raises(TranslationError, match=re.escape(what)) as error:
            translate(law, "c_name")
        assert f"'{law.name}'" in str(error.value) and "line" in str(error.value)


def test_the_translator_takes_a_bounded_loop_with_break():
    """for NAME in range(N) (N constant) with break: the C loop computes the Python loop's
    bits (here a Newton solve of x^3 = deformation, as Bouc-Wen's for z)."""
    import numpy as np

    from pframe.kernel.translate import translate

    class Cubic:
        kind, name, __qualname__ = "contact", "cubic", "Cubic"

        @staticmethod
        def force(params, committed, trial, deformation, rate):
            x = 1.0
            count = 0.0
            for _ in range(50):
                step = (x * x * x - deformation) / (3.0 * x * x)
                x = x - step
                count = count + 1.0
                if abs(step) <= 1e-15 * abs(x):
                    break
            trial[0] = count
            return x, 0.0, 0.0

    source = translate(Cubic, "contact_cubic")
    assert "for (loop0_ = 0; loop0_ < 50; loop0_++) {" in source and "break;" in source
    assert "int64_t loop0_;" in source
    trial = np.zeros(1)
    assert Cubic.force(None, None, trial, 8.0, 0.0)[0] == 2.0 and 3 < trial[0] < 50


# --- helper functions: module-level functions a law's force calls ----------------------------

#: a module-level number a law reads (translated as its value)
_SLOT = 1


def _spring(k, x):
    """A number from numbers."""
    return k * x * (1.0 + 0.25 * x)


def _spring_and_slope(k, x):
    """A tuple, unpacked by the caller."""
    return _spring(k, x), k * (1.0 + 0.5 * x)


def _remember(state, x):
    """Writes the array it is given (the law's trial)."""
    state[0] = x
    state[_SLOT] = x * x


def _three(params, x, r):
    """Returned as the force's three numbers."""
    f, kd = _spring_and_slope(params[0], x)
    return f + params[1] * r, kd, params[1]


def _countdown(x):
    return _countdown(x - 1.0)


class _Helped:
    kind, name, __qualname__ = "contact", "helped", "_Helped"

    @staticmethod
    def force(params, committed, trial, deformation, rate):
        if deformation <= 0.0:
            return 0.0, 0.0, 0.0
        _remember(trial, deformation + committed[0])
        if rate < 0.0:
            return _three(params, deformation, rate)
        f, kd = _spring_and_slope(params[0], deformation)
        return f + _spring(params[1], rate), kd, params[1] * (1.0 + 0.5 * rate)


def test_the_translator_takes_helper_functions():
    """A module-level function a force calls becomes one static C function: numbers and
    arrays in, a number or a tuple out (written through pointers), a read-only array const, a
    written one not; a module-level number is its value."""
    from pframe.kernel.translate import translate

    source = " ".join(translate(_Helped, "contact_helped").split())  # unwrapped
    assert "static PFRAME_INLINE double test_kernel__spring(double k_, double x_)" in source
    assert ("static PFRAME_INLINE void test_kernel__spring_and_slope(double k_, double x_, "
            "double *ret0, double *ret1)") in source
    assert "static PFRAME_INLINE void test_kernel__remember(double *state_, double x_)" in source
    assert "state_[1] = (x_ * x_);" in source
    assert ("static PFRAME_INLINE void test_kernel__three(const double *params_, double x_, "
            "double r_,") in source
    assert "test_kernel__spring_and_slope(params[0], deformation, &f_, &kd_);" in source
    assert "test_kernel__three(params, deformation, rate, &out[0], &out[1], &out[2]);" in source
    assert source.count("static PFRAME_INLINE double test_kernel__spring(") == 1
    # each helper before its first caller, the force last
    assert source.index("test_kernel__spring(double") < source.index(
        "test_kernel__spring_and_slope(double") < source.index("static PFRAME_INLINE void contact_helped(")


def test_the_translator_refuses_helpers_it_cannot_translate():
    """Recursion, a read-only array written through a helper, an array passed where a number
    was, a dropped result and a tuple of the wrong length are refused, naming the law, the
    line and what."""
    import re

    from pframe.kernel.translate import TranslationError, translate

    class Recursing:
        kind, name, __qualname__ = "contact", "recursing", "Recursing"

        @staticmethod
        def force(params, committed, trial, deformation, rate):
            return _countdown(deformation), 0.0, 0.0

    class WritingParams:
        kind, name, __qualname__ = "contact", "writing_params", "WritingParams"

        @staticmethod
        def force(params, committed, trial, deformation, rate):
            _remember(params, deformation)
            return 0.0, 0.0, 0.0

    class Mixed:
        kind, name, __qualname__ = "contact", "mixed", "Mixed"

        @staticmethod
        def force(params, committed, trial, deformation, rate):
            _remember(trial, deformation)
            _remember(deformation, deformation)
            return 0.0, 0.0, 0.0

    class Dropping:
        kind, name, __qualname__ = "contact", "dropping", "Dropping"

        @staticmethod
        def force(params, committed, trial, deformation, rate):
            _spring(1.0, deformation)
            return 0.0, 0.0, 0.0

    class Unpacking:
        kind, name, __qualname__ = "contact", "unpacking", "Unpacking"

        @staticmethod
        def force(params, committed, trial, deformation, rate):
            a, b, c = _spring_and_slope(1.0, deformation)
            return a, b, c

    for law, what in ((Recursing, "calls itself"),
                      (WritingParams, "only trial[i] may be written"),
                      (Mixed, "called with arrays in other places than before"),
                      (Dropping, "the result of test_kernel._spring is dropped"),
                      (Unpacking, "returns 2, not a tuple of 3 numbers")):
        with pytest.raises(TranslationError, match=re.escape(what)) as error:
            translate(law, "c_name")
        assert f"'{law.name}'" in str(error.value) and "line" in str(error.value)


@pytest.mark.slow
def test_a_law_with_helpers_gives_its_python_bits_in_c_and_numba(tmp_path):
    """The C of a force with helpers, compiled with the kernel's flags, and its numba copy
    (pframe.laws.compiled, as plug-ins and the reference solver compile laws) give the
    Python function's force, tangents and trial state bit for bit."""
    import ctypes
    import shutil
    import subprocess

    from pframe.kernel.translate import translate
    from pframe.laws.compiled import njit

    compiler = shutil.which("cc") or shutil.which("gcc")
    if compiler is None:
        pytest.skip("no C compiler")
    prelude = ("#include <math.h>\n#include <stdint.h>\n#define PFRAME_INLINE inline\n"
               "static inline double py_min(double a, double b) { return b < a ? b : a; }\n"
               "static inline double py_max(double a, double b) { return b > a ? b : a; }\n")
    source = prelude + translate(_Helped, "contact_helped").replace(
        "static PFRAME_INLINE void contact_helped", "void contact_helped")
    (tmp_path / "helped.c").write_text(source, encoding="utf-8")
    library = tmp_path / "helped.so"
    subprocess.run([compiler, "-std=c99", "-O2", "-ffp-contract=off", "-fno-fast-math",
                    "-shared", "-fPIC", "-o", str(library), str(tmp_path / "helped.c")],
                   check=True)
    c_force = ctypes.CDLL(str(library)).contact_helped
    c_force.restype = None
    pointer = ctypes.c_void_p
    numba_force = njit(_Helped.force, error_model="numpy")
    rng = np.random.default_rng(3)
    for _ in range(200):
        params, committed = rng.uniform(0.1, 3.0, 2), rng.uniform(-1.0, 1.0, 2)
        x, r = float(rng.uniform(-0.5, 2.0)), float(rng.uniform(-2.0, 2.0))
        trial, c_trial, n_trial = np.zeros(2), np.zeros(2), np.zeros(2)
        out = np.zeros(3)
        expected = _Helped.force(params, committed, trial, x, r)
        c_force(pointer(params.ctypes.data), pointer(committed.ctypes.data),
                pointer(c_trial.ctypes.data), ctypes.c_double(x), ctypes.c_double(r),
                pointer(out.ctypes.data))
        assert out.tolist() == [float(v) for v in expected]
        assert numba_force(params, committed, n_trial, x, r) == expected
        assert c_trial.tolist() == trial.tolist() == n_trial.tolist()
