"""Shared helpers for the physics tests: scene builders (YAML text) and run shortcuts.

Scenes are written as JSON, which is valid YAML and prints floats with ``repr`` (exact
round trip), so every number a test uses is the number the kernel sees.

Kernels are compiled once per *structure* (laws in use and recorded quantities) and cached on
disk, so the builders share a few recorder sets (:data:`RECORDERS`, :data:`FREE_RECORDERS`)
to keep the number of distinct kernels, and the test time, small.
"""

from __future__ import annotations

import json
import math
import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
import pytest

from pframe.assemble import assemble, assemble_batch
from pframe.kernel import simulate
from pframe.reader import load_scene, parse_scene

REPO = Path(__file__).resolve().parents[1]
WU2021 = REPO / "models" / "wu2021-eq14.yaml"
#: real PEER records, kept beside the repository (shared/records), never copied into it
RECORDS = REPO.parent / "shared" / "records"


def assert_names(found, expected, what: str, extra: bool = True) -> None:
    """A list derived from a registry holds exactly the names of ``expected`` (``extra`` False:
    at least them): fail naming each one missing and each one not expected, whole, never a
    set difference cut short."""
    found, expected = set(found), set(expected)
    missing = sorted(map(str, expected - found))
    beyond = sorted(map(str, found - expected)) if extra else []
    parts = ([f"missing {', '.join(missing)}"] if missing else []) + (
        [f"not expected {', '.join(beyond)}"] if beyond else [])
    assert not parts, f"{what}: {'; '.join(parts)}"


def fact(cls, name: str):
    """An integrator's declared fact (pframe.integrators' Facts): the generic tests ask the
    integrator what to check. One left out fails here, naming the integrator and the fact."""
    value = getattr(cls.facts, name, None)
    if value is None:
        pytest.fail(f"the integrator {cls.__name__} ({cls.__module__}) has not declared its "
                    f"fact {name!r} (Facts.{name} in its class's facts)")
    return value


def integrator_class(config: dict):
    """The integrator class of a configuration (the YAML ``analysis.integrator`` mapping)."""
    from pframe.integrators import ALL_INTEGRATORS

    return {cls.type_name(): cls for cls in ALL_INTEGRATORS}[config.get("type", "newmark")]


def integrator_examples() -> list[tuple[str, type, dict]]:
    """(label, class, configuration) of every example every integrator declares (an
    integrator that declares none has none here; test_integrators fails it by name)."""
    from pframe.integrators import ALL_INTEGRATORS

    return [(label, cls, config) for cls in ALL_INTEGRATORS
            for label, config in (cls.facts.examples or {}).items()]


def integrator_cases() -> list:
    """pytest parameters (configuration, facts) of every example every integrator declares,
    and each again with ``events: true`` where the integrator runs on that path."""
    out = []
    for label, cls, config in integrator_examples():
        out.append(pytest.param(config, cls.facts, id=label))
        if "events" in (cls.facts.paths or ()):
            out.append(pytest.param({**config, "events": True}, cls.facts, id=f"{label}-events"))
    return out


def integrator_configurations() -> dict[str, dict]:
    """Every integrator in its reference configuration (its first example) by its type, and
    with ``events: true`` (``<type>+events``) where it runs on that path."""
    from pframe.integrators import ALL_INTEGRATORS

    out = {}
    for cls in ALL_INTEGRATORS:
        config = next(iter((cls.facts.examples or {}).values()), {"type": cls.type_name()})
        out[cls.type_name()] = config
        if "events" in (cls.facts.paths or ()):
            out[f"{cls.type_name()}+events"] = config | {"events": True}
    return out


def record_file(name: str) -> Path:
    """A record of :data:`RECORDS`; the test is skipped, saying why, when it is absent."""
    path = RECORDS / name
    if not path.is_file():
        pytest.skip(f"the PEER record {name} is not in {RECORDS} (models/ names it by file; "
                    "the PEER NGA-West2 database has it)")
    return path


def require_opensees() -> None:
    """Skip the calling test module, saying why, when OpenSeesPy cannot be imported (a
    missing liblapack surfaces as ImportError or OSError: either skips)."""
    try:
        import openseespy.opensees  # noqa: F401
    except Exception as exc:  # pragma: no cover - depends on the machine
        pytest.skip(
            f"OpenSeesPy is not importable ({type(exc).__name__}: {exc}); install it with "
            'pip install -e ".[peers]" and the system libblas3/liblapack3',
            allow_module_level=True,
        )


def runnable_model(model: Path, folder: Path) -> Path:
    """``model`` itself, or, when it names a record that is not beside it, a copy of it in
    ``folder`` beside a link to the record of :data:`RECORDS` (skipped when absent there)."""
    import yaml

    data = yaml.safe_load(model.read_text(encoding="utf-8")) or {}

    def records(node):  # every record file of the scene's motions, wherever it stands
        if isinstance(node, dict):
            found = [node["file"]] if node.get("kind") == "record" else []
            return found + [f for v in node.values() for f in records(v)]
        if isinstance(node, list):
            return [f for v in node for f in records(v)]
        return []

    files = records([data.get("excitation"), data.get("supports")])
    if all((model.parent / file).is_file() for file in files):
        return model
    for file in files:
        record = record_file(Path(file).name)
        if not (folder / record.name).exists():  # another model of the folder reads it too
            (folder / record.name).symlink_to(record)
    copy = folder / model.name
    copy.write_text(model.read_text(encoding="utf-8"), encoding="utf-8")
    return copy

#: The recorders of models/wu2021-eq14.yaml: scenes recording these share its kernels.
RECORDERS = [
    {"kind": "history",
     "quantities": ["displacement", "velocity", "story_force", "story_drift", "contact_force"]},
    {"kind": "envelope", "quantities": ["displacement", "story_drift", "contact_force"]},
]
#: For scenes of free masses (no storeys): velocities and the contact force.
FREE_RECORDERS = [
    {"kind": "history", "quantities": ["displacement", "velocity", "contact_force"]},
]


def scene_text(**scene) -> str:
    """YAML text (JSON flavour) of a scene given as keyword arguments."""
    scene.setdefault("recorders", RECORDERS)
    return json.dumps(scene)


def analysis(dt: float, duration: float, **newton) -> dict:
    """Newmark average acceleration (gamma 1/2, beta 1/4) with a tight Newton tolerance."""
    out = {"integrator": {"type": "newmark", "gamma": 0.5, "beta": 0.25},
           "dt": dt, "duration": duration}
    if newton:
        out["newton"] = newton
    return out


def building(name: str, floors: int, mass, story: dict, damping: dict | None = None) -> dict:
    out = {"name": name, "floors": floors, "mass": mass, "story": story}
    if damping is not None:
        out["damping"] = damping
    return out


def sdof_text(mass: float, stiffness: float, zeta: float, excitation: dict | None,
              dt: float, duration: float, story: dict | None = None) -> str:
    """One building, one storey: m u'' + c u' + f(u) = -m a_g (relative coordinates)."""
    story = story or {"material": "elastic", "stiffness": stiffness}
    scene = {
        "buildings": [building("A", 1, mass, story)],
        "damping": {"ratio": zeta, "modes": [1, 1]},
        "analysis": analysis(dt, duration),
    }
    if excitation is not None:
        scene["excitation"] = excitation
    return scene_text(**scene)


def two_free_masses_text(m1: float, m2: float, contact: dict, v1: float, v2: float,
                         dt: float, duration: float, gap: float = 0.0) -> str:
    """Two storey-less masses L/1 and R/1 joined by one contact (by default of gap 0, so
    touching at t = 0), no damping, no excitation: a pure impact, u_L = u_R = 0 and
    v_L = v1, v_R = v2 at t = 0."""
    contact = {"name": "c", "nodes": ["L/1", "R/1"], "gap": gap} | contact
    return scene_text(
        nodes=[{"name": "L/1", "mass": m1}, {"name": "R/1", "mass": m2}],
        contacts=[contact],
        damping={"ratio": 0.0},
        initial_conditions={"velocity": {"L/1": v1, "R/1": v2}},
        analysis=analysis(dt, duration),
        recorders=FREE_RECORDERS,
    )


def run_text(text: str, base_dir: Path | None = None):
    """Parse, assemble (batch of one) and simulate: (plan, result)."""
    loaded = parse_scene(text, base_dir=base_dir)
    plan = assemble(loaded.expanded)
    return plan, simulate(plan)


def run_batch(texts: list[str]):
    plan = assemble_batch([parse_scene(t).expanded for t in texts])
    return plan, simulate(plan)


def node_history(plan, result, quantity: str, node: str, member: int = 0) -> np.ndarray:
    """History of a node quantity (node columns are in DOF order: plan.node_dof maps)."""
    column = plan.node_dof[plan.node_names.index(node)]
    return result.history[quantity][member, :, column]


def element_history(plan, result, quantity: str, name: str, member: int = 0) -> np.ndarray:
    """History of a storey or contact quantity (columns in declaration order)."""
    names = plan.contact_names if quantity.startswith("contact_") else plan.story_names
    return result.history[quantity][member, :, names.index(name)]


def fit_sine(t: np.ndarray, u: np.ndarray, w: float) -> complex:
    """Least-squares a, b of u = a sin(w t) + b cos(w t) (plus a constant), as a + i b, so that
    u = Im((a + i b) e^{i w t})."""
    design = np.column_stack([np.sin(w * t), np.cos(w * t), np.ones_like(t)])
    (a, b, _), *_ = np.linalg.lstsq(design, u, rcond=None)
    return complex(a, b)


def observed_order(errors) -> np.ndarray:
    """log2 of the ratio of errors at successive halvings of dt."""
    errors = np.asarray(errors, dtype=float)
    return np.log2(errors[:-1] / errors[1:])


def hunt_crossley_restitution(chi: float) -> float:
    """The exact restitution of F = k delta^n (1 + chi delta'/v0): the root e of
    chi (1 + e) = ln((1 + chi) / (1 - chi e)) in (0, 1] (any exponent n; from
    m w dw / (1 + chi w / v0) = -k delta^n d delta integrated over one contact)."""
    from scipy.optimize import brentq

    def g(e):
        return chi * (1.0 + e) - math.log((1.0 + chi) / (1.0 - chi * e))

    upper = min(1.0, (1.0 / chi) * (1.0 - 1e-15)) if chi > 0 else 1.0
    return brentq(g, 1e-9, upper, xtol=1e-15, rtol=4 * np.finfo(float).eps)


# ---------------------------------------------------------------------------------------------
# the free two-body impact (test_restitution.py, test_contact_matrix.py)
# ---------------------------------------------------------------------------------------------

M_LEFT, M_RIGHT = 1000.0, 3000.0
M_EFF = M_LEFT * M_RIGHT / (M_LEFT + M_RIGHT)
V_IMPACT = 0.5  # m/s, L/1 moving right into R/1 at rest
K_LINEAR = 1.0e7  # N/m
K_HERTZ = 1.0e9  # N/m^1.5

def _impact_variants(damped: bool) -> dict:
    """case -> (law, extra YAML keys, label) of every built-in contact law's declared impacts
    (``Law.impacts``, pframe.laws.facts.Impact), the damped laws' or the others'."""
    from pframe.laws.registry import builtin_laws

    out = {}
    for law in builtin_laws("contact"):
        if ("restitution" in law.Params.model_fields) == damped:
            for case, impact in (getattr(law, "impacts", None) or {}).items():
                out[case] = (law.name, impact.params, impact.label)
    return out


#: The damped laws, one variant per row of docs/restitution.md's tables (their declared
#: impacts): (law, extra YAML keys, label).
IMPACT_VARIANTS = _impact_variants(damped=True)
#: The laws without damping (e = 1): (law, extra YAML keys, label).
UNDAMPED_VARIANTS = _impact_variants(damped=False)


def _variant(case: str):
    return IMPACT_VARIANTS.get(case) or UNDAMPED_VARIANTS[case]


def contact_context():
    from pframe.laws import ContactContext

    return ContactContext(M_LEFT, M_RIGHT)


CONTEXT = contact_context()


def impact_law(case: str):
    """The law class of ``case``."""
    from pframe.laws import get_law

    return get_law("contact", _variant(case)[0])


def impact_contact(case: str, e: float | None = None, calibration: str | None = None) -> dict:
    """The contact's YAML keys (law, stiffness, restitution, calibration, ...) of ``case``."""
    law, extra, _ = _variant(case)
    if case in UNDAMPED_VARIANTS:
        return {"law": law} | extra
    return {"law": law, "restitution": e, "calibration": calibration} | extra


def impact_params(case: str, e: float | None = None, calibration: str | None = None):
    """The law's parameters (its pydantic ``Params``) for ``case``."""
    return impact_law(case).Params(**impact_contact(case, e, calibration))


def impact_packed(case: str, e: float | None = None,
                  calibration: str | None = None) -> tuple[float, ...]:
    """The numbers the law packs for ``case`` (pframe's own calibration)."""
    return impact_law(case).pack(impact_params(case, e, calibration), CONTEXT)


def impact_force(case: str, e: float | None = None, calibration: str | None = None):
    """F(delta, delta') of ``case`` for a free impact at V_IMPACT: the law's reference force,
    written from its paper (``Law.reference_force``, never pframe's force function)."""
    from pframe.laws import facts

    law = impact_law(case)
    reference = facts.declared(law, "reference_force")
    return reference(impact_params(case, e, calibration), CONTEXT, V_IMPACT)


def impact_ode(force, m_eff: float, v: float):
    """Integrate m_eff delta'' = -F(delta, delta') from delta = 0, delta' = v with DOP853
    (rtol 1e-12) to the separation delta = 0: (restitution, contact duration)."""
    from scipy.integrate import solve_ivp

    def rhs(t, y):
        x = y[0]
        return [y[1], -force(x, y[1]) / m_eff if x > 0 else 0.0]

    def separated(t, y):
        return y[0]

    separated.terminal, separated.direction = True, -1
    sol = solve_ivp(rhs, (0.0, 10.0), [0.0, v], method="DOP853", rtol=1e-12, atol=1e-16,
                    events=separated, first_step=1e-9)
    assert sol.status == 1, "the reference impact did not separate"
    return -sol.y_events[0][0][1] / v, sol.t_events[0][0]


def reference_impact(case: str, e: float | None = None, calibration: str | None = None):
    """(restitution, contact duration) of the two-mass impact of ``case``, from the ODE of its
    reference force."""
    return impact_ode(impact_force(case, e, calibration), M_EFF, V_IMPACT)


@pytest.fixture(scope="session")
def wu2021_text() -> str:
    return WU2021.read_text(encoding="utf-8")


@pytest.fixture(scope="session")
def wu2021_run():
    """The paper's example as shipped (improved Kelvin contacts): (loaded, plan, result)."""
    loaded = load_scene(WU2021)
    plan = assemble(loaded.expanded)
    return loaded, plan, simulate(plan)


#: global attributes that say when and by which command a file was written
PROVENANCE = ("date_created", "history")


def assert_same_result_file(a: Path, b: Path) -> None:
    """Two result files hold the same thing: every variable bit for bit (names, dimensions,
    order), every attribute, apart from when and by which command each was written."""
    import h5py

    def contents(path):
        with h5py.File(path, "r") as f:
            attrs = {k: np.asarray(v).tolist() for k, v in f.attrs.items()
                     if k not in PROVENANCE}
            data = {}

            def visit(name, obj):
                if isinstance(obj, h5py.Dataset):
                    data[name] = (obj.dtype.str, obj.shape, obj[()].tobytes(),
                                  sorted(k for k in obj.attrs
                                         if k not in ("DIMENSION_LIST", "REFERENCE_LIST")))

            f.visititems(visit)
            return list(f), attrs, data

    names_a, attrs_a, data_a = contents(a)
    names_b, attrs_b, data_b = contents(b)
    assert names_a == names_b
    assert attrs_a == attrs_b
    assert data_a.keys() == data_b.keys()
    for name in data_a:
        assert data_a[name] == data_b[name], name


def page_layout(html, frames: list[int]) -> list[dict]:
    """The animation page's own geometry (its `layout` function, run in node) at frames:
    what the page draws, read without a browser. Skips where node is absent."""
    import shutil
    import subprocess

    node = shutil.which("node")
    if node is None:
        pytest.skip("node is not installed: the page's geometry is checked with node")
    script = ("const fs = require('fs'); const t = fs.readFileSync(process.argv[1], 'utf8');"
              "const data = JSON.parse(/<script id=\"pframe-data\" type=\"application\\/json\">"
              "([\\s\\S]*?)<\\/script>/.exec(t)[1]);"
              "eval(/<script id=\"pframe-geometry\">([\\s\\S]*?)<\\/script>/.exec(t)[1]);"
              "console.log(JSON.stringify(JSON.parse(process.argv[2]).map(k => layout(data, k))));")
    done = subprocess.run([node, "-e", script, str(html), json.dumps(frames)],
                          capture_output=True, text=True, timeout=60)
    assert done.returncode == 0, done.stderr
    return json.loads(done.stdout)


def drive_material(law, packed, drifts):
    """A storey material driven through a drift history, each step committed: its force,
    tangent and committed state after each drift."""
    committed = np.zeros(len(law.state_names))
    trial = committed.copy()
    forces, tangents, states = [], [], []
    for d in drifts:
        f, k, _ = law.force(packed, committed, trial, float(d), 0.0)
        committed = trial.copy()
        forces.append(f)
        tangents.append(k)
        states.append(committed)
    return np.array(forces), np.array(tangents), np.array(states)


def kill_after(command: list[str], cwd: Path, parts: Path, chunks: int) -> int:
    """Start ``command`` in its own session, SIGKILL it as soon as the folder ``parts`` holds
    ``chunks`` saved chunk files (``chunk-*.npz``: a sweep's chunks, a study's batches);
    return how many it holds then. Fails the test if the command ends first."""
    process = subprocess.Popen(command, cwd=cwd, stdout=subprocess.DEVNULL,
                               stderr=subprocess.PIPE, start_new_session=True)
    try:
        deadline = time.monotonic() + 600
        while time.monotonic() < deadline:
            if parts.is_dir() and len(list(parts.glob("chunk-*.npz"))) >= chunks:
                break
            if process.poll() is not None:
                pytest.fail("the command ended before it could be killed: "
                            f"{process.stderr.read().decode()}")
            time.sleep(0.002)
        os.killpg(process.pid, signal.SIGKILL)
        process.wait()
    finally:
        if process.poll() is None:
            os.killpg(process.pid, signal.SIGKILL)
            process.wait()
    assert process.returncode == -signal.SIGKILL
    return len(list(parts.glob("chunk-*.npz")))


def pytest_collection_modifyitems(items):
    """Tests on the Dask :func:`cluster` run last, one after the other: the cluster starts
    once for all of them and stops at once (idle, its three processes still cost CPU)."""
    items.sort(key=lambda item: "cluster" in getattr(item, "fixturenames", ()))


def _dask(*args, cwd) -> subprocess.Popen:
    return subprocess.Popen([sys.executable, "-m", "dask", *args], cwd=cwd,
                            stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL,
                            start_new_session=True)


@pytest.fixture(scope="session")
def cluster(tmp_path_factory):
    """The address of a real ``dask scheduler`` on a free loopback port with two one-thread
    ``dask worker`` processes, shared by the modules that run on Dask (started once: each
    process costs seconds of imports)."""
    folder = tmp_path_factory.mktemp("dask")
    file = folder / "scheduler.json"
    processes = [_dask("scheduler", "--host", "127.0.0.1", "--port", "0", "--no-dashboard",
                       "--scheduler-file", str(file), cwd=folder)]
    try:
        deadline = time.monotonic() + 120
        while not file.exists() and time.monotonic() < deadline:
            time.sleep(0.1)
        assert file.exists(), "the dask scheduler did not start"
        address = json.loads(file.read_text())["address"]
        for _ in range(2):
            processes.append(_dask("worker", address, "--nthreads", "1", "--nworkers", "1",
                                   "--host", "127.0.0.1", "--no-dashboard",
                                   "--local-directory", str(folder), cwd=folder))
        from distributed import Client

        with Client(address, timeout="60s") as client:
            client.wait_for_workers(2, timeout=120)
        yield address
    finally:
        for process in reversed(processes):
            if process.poll() is None:
                os.killpg(process.pid, signal.SIGTERM)
        for process in processes:
            try:
                process.wait(timeout=30)
            except subprocess.TimeoutExpired:
                os.killpg(process.pid, signal.SIGKILL)
                process.wait()
