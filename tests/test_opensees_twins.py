"""Every element kind of ``pframe opensees`` against its OpenSees twin (pframe.peers.twins).

Where the twin is pframe's model, both programs integrate the same discrete equations, and
each test asks of one scene, run by both:

* every degree of freedom's displacement (floors, foundations) to 1e-9 of its peak, the
  issue's figure, over a run where the element acts (yields, pounds, slides, rocks);
* for a contact, OpenSees' own contact forces against pframe's law evaluated on OpenSees'
  own kinematics (its penetration and closing rate, the law's state carried from step to
  step as pframe's kernel carries it): the twin is the law, to the round-off of the
  penetration recomputed from the floors' displacements;
* for the Hunt-Crossley family, that the run is one where OpenSees' Hertzdamp is pframe's law:
  no contact closes slower than its energy velocity (pframe's floor, which OpenSees lacks)
  and none rebounds so fast that its damping outweighs its spring (where pframe's force stays
  at 0 and OpenSees' pulls). pframe.peers.twins names both differences; the script says
  where a contact pulled (``test_the_script_says_where_a_contact_pulled``).

Timing belongs to ``benchmarks/opensees_speed.py``, not here.
"""

from __future__ import annotations

import json
from pathlib import Path
from types import SimpleNamespace

import numpy as np
import pytest
import yaml
from conftest import require_opensees

require_opensees()

from pframe.assemble import assemble  # noqa: E402
from pframe.kernel import simulate  # noqa: E402
from pframe.laws.registry import builtin_laws, get_law  # noqa: E402
from pframe.peers import twins  # noqa: E402
from pframe.peers.from_plan import peer_scene  # noqa: E402
from pframe.peers.opensees import run  # noqa: E402
from pframe.reader import parse_scene  # noqa: E402

REPO = Path(__file__).resolve().parents[1]
MODELS = REPO / "models"
#: max over DOFs and times of |pframe - OpenSees| over max |OpenSees|
PEAK_RTOL = 1e-9
HISTORIES = ["displacement", "velocity", "story_force", "story_drift", "contact_force",
             "contact_penetration", "link_force"]


def paper_pair(**changes) -> dict:
    """models/wu2021-eq14-linear.yaml (the paper's yielding pair, linear contacts, Newton to
    round-off) as data, recording every history, with ``changes`` merged into it."""
    data = yaml.safe_load((MODELS / "wu2021-eq14-linear.yaml").read_text(encoding="utf-8"))
    data["recorders"] = [{"kind": "history", "quantities": HISTORIES}]
    for key, value in changes.items():
        data[key] = value
    return data


def with_contacts(data: dict, law: dict) -> dict:
    """The scene's contacts with ``law`` (its fields) instead of theirs."""
    data["contacts"] = [{"name": c["name"], "nodes": c["nodes"], "gap": c["gap"]} | law
                        for c in data["contacts"]]
    return data


def solve_both(data: dict, base_dir: Path = MODELS) -> SimpleNamespace:
    """pframe and OpenSeesPy on one scene."""
    plan = assemble(parse_scene(json.dumps(data), base_dir=base_dir).expanded)
    result = simulate(plan)
    assert result.completed(), result.describe_failure()
    peer = peer_scene(plan)
    return SimpleNamespace(plan=plan, result=result, peer=peer, opensees=run(peer))


def relative_difference(ours: np.ndarray, theirs: np.ndarray) -> float:
    assert ours.shape == theirs.shape
    return float(np.max(np.abs(ours - theirs)) / np.max(np.abs(theirs)))


def assert_displacements_agree(both: SimpleNamespace) -> float:
    """Every DOF's displacement to PEAK_RTOL of the peak; returns the difference."""
    difference = relative_difference(both.result.history["displacement"][0],
                                     both.opensees["displacement"])
    assert difference <= PEAK_RTOL, f"displacement: {difference:.3e}"
    return difference


def kinematics(plan, u: np.ndarray, v: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(steps + 1, c) each contact's penetration u_left - u_right - gap and its rate, from
    the DOFs' displacements and velocities (a planar scene's plain contacts; -1: a wall)."""
    def side(values, dofs):
        return np.where(dofs >= 0, values[:, np.clip(dofs, 0, None)], 0.0)

    left, right = plan.contact_dofs[:, 0], plan.contact_dofs[:, 1]
    penetration = side(u, left) - side(u, right) - plan.contact_gap[0]
    return penetration, side(v, left) - side(v, right)


def law_forces(plan, penetration: np.ndarray, rate: np.ndarray) -> np.ndarray:
    """(steps + 1, c) pframe's contact law along the given kinematics, its state committed
    from step to step as the kernel commits it."""
    forces = np.zeros_like(penetration)
    for group in plan.contact_groups:
        for j, c in enumerate(group.index):
            params = group.params[0, j]
            committed = list(group.state[0, j])
            for k in range(penetration.shape[0]):
                trial = list(committed)
                forces[k, c] = group.law.force(params, committed, trial, penetration[k, c],
                                               rate[k, c])[0]
                committed = trial
    return forces


def assert_contacts_are_the_law(both: SimpleNamespace) -> float:
    """OpenSees' contact forces are pframe's law on OpenSees' own kinematics, to 1e-9 of the
    peak force (the penetration, a difference of displacements ~1e2 times larger, carries
    their round-off; measured 1e-13 and below)."""
    penetration, rate = kinematics(both.plan, both.opensees["displacement"],
                                   both.opensees["velocity"])
    theirs = both.opensees["contact_force"]
    assert np.all(theirs >= 0.0), "OpenSees' contact pulled"
    difference = relative_difference(law_forces(both.plan, penetration, rate), theirs)
    assert difference <= PEAK_RTOL, f"contact force against the law: {difference:.3e}"
    return difference


def assert_hunt_crossley_is_hertzdamp(both: SimpleNamespace) -> None:
    """On this run pframe's Hunt-Crossley law is OpenSees' Hertzdamp: at every step of every
    contact the onset velocity v0 is positive and at least the energy velocity
    v_e = sqrt(2 k delta^(n+1) / ((n + 1) m_eff)), and 1 + chi delta' / v0 > 0."""
    plan, result = both.plan, both.result
    penetration = result.history["contact_penetration"][0]
    _, rate = kinematics(plan, result.history["displacement"][0],
                         result.history["velocity"][0])
    impacts = 0
    for group in plan.contact_groups:
        for j, c in enumerate(group.index):
            k, n, chi, inverse_mass = group.params[0, j, :4]
            closed = penetration[:, c] > 0.0
            onset = np.flatnonzero(closed[1:] & ~closed[:-1]) + 1
            impacts += len(onset)
            for start in onset:
                end = start + int(np.argmin(closed[start:])) if not closed[-1] else len(closed)
                delta, speed, v0 = penetration[start:end, c], rate[start:end, c], rate[start, c]
                energy = 2.0 * k * delta ** (n + 1.0) * inverse_mass / (n + 1.0)
                assert v0 > 0.0 and np.all(v0 * v0 >= energy), (group.law.name, c, start)
                assert np.all(1.0 + chi * speed / v0 > 0.0), (group.law.name, c, start)
    assert impacts >= 3, impacts


# ---------------------------------------------------------------------------------------------
# the twins' list
# ---------------------------------------------------------------------------------------------


def test_every_law_names_its_twin():
    """A built-in law's ``opensees`` is the OpenSees material its twin is written with
    (pframe.peers.twins), or None for a law OpenSees has no twin of, refused with the
    reason."""
    laws = [("contact", law) for law in builtin_laws("contact")] + [
        ("material", law) for law in builtin_laws("material")]
    named = {}
    for kind, law in laws:
        table = twins.CONTACTS if kind == "contact" else twins.MATERIALS
        if law.opensees is None:
            assert law.name not in table and law.name in twins.NO_TWIN, law.name
            continue
        assert law.name in table, law.name
        named[law.name] = law.opensees
    # each twin kind the table writes is the material the law names
    examples = {"linear": (1e7,), "hertz": (1e9,), "hertzdamp": (1e9, 1.5, 0.3, 1e-3),
                "improved_kelvin": (1e7, 1.0, 0.9, 1e-3), "hunt_crossley": (1e9, 1.3, 0.5, 0.0),
                "jankowski": (1e9, 0.3, 200.0), "bumper": (1e8, 1.5, 0.3, 0.0, 1e9, 0.004),
                "elastic": (1e6,), "bilinear": (1e6, 1e4, 0.1),
                "viscous": (2e3, 0.5, 1e-5), "kelvin_voigt": (1e5, 2e3, 1.0, 1e-5),
                "friction_pendulum": (5e4, 0.5, 1e6, 0.08, 0.08, 0.0)}
    for name, packed in examples.items():
        kind = "contact" if name in twins.CONTACTS else "material"
        law = next(law for _, law in laws if law.name == name)
        made = twins.twin(kind, law, packed)
        assert twins.OPENSEES_NAMES[made.material[0]] == named[name], name
    with pytest.raises(twins.NoTwin, match="velocity-dependent friction"):
        twins.twin("material", get_law("material", "friction_pendulum"),
                   (5e4, 0.5, 1e6, 0.05, 0.1, 30.0))


# ---------------------------------------------------------------------------------------------
# contacts: the paper's yielding pair pounding with each law
# ---------------------------------------------------------------------------------------------

#: each contact law on the paper's pair (Hertz stiffnesses of the order of the linear
#: contacts' at a millimetre; the bumper thick enough never to be crushed)
CONTACTS = {
    "hertz": {"law": "hertz", "stiffness": 1.0e9},
    "hertzdamp": {"law": "hertzdamp", "stiffness": 1.0e9, "restitution": 0.6},
    "hunt_crossley": {"law": "hunt_crossley", "stiffness": 3.0e8, "exponent": 1.3,
                      "restitution": 0.5},
    "jankowski": {"law": "jankowski", "stiffness": 1.0e9, "restitution": 0.5},
    "bumper": {"law": "bumper", "stiffness": 1.0e8, "hard_stiffness": 1.0e9, "thickness": 0.05,
               "restitution": 0.6},
}


@pytest.mark.slow
def test_improved_kelvin_is_hertzdamp_on_the_papers_scene():
    """models/wu2021-eq14.yaml itself (improved Kelvin contacts, Rayleigh damping on the
    current stiffness: OpenSees' betaK), its Newton at round-off: Hertzdamp with n = 1."""
    data = yaml.safe_load((MODELS / "wu2021-eq14.yaml").read_text(encoding="utf-8"))
    data["recorders"] = [{"kind": "history", "quantities": HISTORIES}]
    data["analysis"]["newton"] = {"tolerance": 1.0e-14, "absolute_tolerance": 1.0e-15}
    both = solve_both(data)
    assert both.peer.rayleigh[0][4] == "current" and both.peer.contact_materials[0] == (
        "hertzdamp", *both.plan.contact_groups[0].params[0, 0, [0, 2, 1]])
    assert_hunt_crossley_is_hertzdamp(both)
    assert_displacements_agree(both)
    assert_contacts_are_the_law(both)


@pytest.mark.slow
@pytest.mark.parametrize("law", sorted(CONTACTS))
def test_contact_law_agrees_with_its_twin(law):
    """Each law on the paper's pair. Jankowski's damping c ~ delta^(1/4) has an infinite
    slope at onset, which amplifies a difference of round-off some 3 to 15 times at each
    impact (measured: 6e-14 before the first, 2e-9 after the eighth, while its forces are
    the law's on OpenSees' kinematics to 2e-16): its run stops after five impacts a contact
    (36,000 of the 50,000 steps), at 2e-10."""
    data = with_contacts(paper_pair(), CONTACTS[law])
    if law == "jankowski":
        data["analysis"]["duration"] = 36_000 * data["analysis"]["dt"]
    both = solve_both(data)
    assert np.all(both.result.impacts[0] > 0)
    if law == "bumper":  # the rubber alone: the hard contact is never reached
        depth = both.plan.contact_groups[0].params[0, :, 5]
        assert np.max(both.result.history["contact_penetration"][0]) < np.min(depth)
    if law in ("hertzdamp", "hunt_crossley", "bumper"):
        assert_hunt_crossley_is_hertzdamp(both)
    assert_displacements_agree(both)
    assert_contacts_are_the_law(both)


# ---------------------------------------------------------------------------------------------
# storeys, links, tuned masses, P-delta, soil, damping
# ---------------------------------------------------------------------------------------------


def isolated(first: dict, **more) -> dict:
    """A base slab and two floors on an isolation storey ``first`` (generic nodes and
    storeys), under a resonant sine."""
    return {
        "nodes": [{"name": "A/1", "mass": 2.0e5}, {"name": "A/2", "mass": 1.5e5},
                  {"name": "A/3", "mass": 1.5e5}],
        "stories": [{"name": "iso", "nodes": ["ground", "A/1"]} | first,
                    {"nodes": ["A/1", "A/2"], "material": "elastic", "stiffness": 3.0e8},
                    {"nodes": ["A/2", "A/3"], "material": "elastic", "stiffness": 3.0e8}],
        "damping": {"ratio": 0.02, "modes": [1, 2]},
        "excitation": {"kind": "sine", "amplitude": 3.0, "frequency": 0.6, "cycles": 3},
        "analysis": {"dt": 0.002, "duration": 8.0,
                     "newton": {"tolerance": 1e-14, "absolute_tolerance": 1e-15}},
        "recorders": [{"kind": "history", "quantities": HISTORIES}],
    } | more


@pytest.mark.slow
@pytest.mark.parametrize("radius", [2.0, None])
def test_friction_pendulum_with_coulomb_friction_agrees(radius):
    """A friction pendulum with a constant mu (and a flat slider) is a Parallel of Steel01
    (b = 0: the friction, elastic-perfectly plastic at mu W from k_init - W / R) and Elastic
    W / R: the building slides back and forth, and its histories agree to round-off. (The
    flat slider's building is undamped: its isolated mode has no frequency to fit Rayleigh
    damping to.)"""
    bearing = {"material": "friction_pendulum", "mu": 0.06, "k_init": 2.0e8}
    if radius:
        bearing["radius"] = radius
    both = solve_both(isolated(bearing) if radius else isolated(bearing, damping={"ratio": 0.0}))
    assert both.peer.story_materials[0][0] == "coulomb_pendulum"
    drift = both.result.history["story_drift"][0][:, 0]
    weight = both.plan.story_groups[0].params[0, 0, 0]
    assert np.max(np.abs(drift)) > 20 * 0.06 * weight / 2.0e8  # far past the stick drift
    assert_displacements_agree(both)
    force = relative_difference(both.result.history["story_force"][0],
                                both.opensees["story_force"])
    assert force <= PEAK_RTOL, f"{force:.3e}"


@pytest.mark.slow
def test_tuned_mass_and_links_of_every_material_agree():
    """The paper's pair (linear contacts) with a tuned mass on A's roof (a Kelvin-Voigt link),
    a yielding bilinear link and an elastic one between the buildings' second floors, and a
    nonlinear damper (alpha = 0.5) from B's first floor to the ground, its linear branch
    below 1e-11 m/s (OpenSees' Viscous keeps the power law there: the export says so)."""
    data = paper_pair()
    data["nodes"] = [{"name": "TMD/1", "mass": 40.0}]
    data["links"] = [
        {"name": "tmd", "nodes": ["A/3", "TMD/1"], "material": "kelvin_voigt",
         "stiffness": 4.0e3, "damping": 150.0},
        {"name": "brace", "nodes": ["A/2", "B/2"], "material": "bilinear", "stiffness": 2.0e4,
         "yield_force": 300.0, "alpha": 0.2},
        {"name": "spring", "nodes": ["A/1", "B/1"], "material": "elastic", "stiffness": 5.0e3},
        {"name": "damper", "nodes": ["ground", "B/1"], "material": "viscous", "damping": 300.0,
         "exponent": 0.5, "linear_below": 1e-11}]
    data["analysis"]["newton"] = {"tolerance": 1e-12, "absolute_tolerance": 1e-12,
                                  "max_iterations": 200}
    both = solve_both(data)
    assert [m[0] for m in both.peer.link_materials] == ["kelvin_voigt", "bilinear", "elastic",
                                                        "viscous"]
    assert any("linear_below" in d for d in both.peer.differences)
    assert np.all(both.result.impacts[0] > 0)
    assert_displacements_agree(both)


@pytest.mark.slow
def test_p_delta_agrees():
    """P-delta (p_delta: true, storeys 3 m high): OpenSees' undamped zeroLength of
    Elastic(-P / h) beside each storey; the storey force (the material's less P d / h, as
    pframe records it) agrees too."""
    data = paper_pair()
    for building in data["buildings"]:
        building |= {"height": 3.0, "p_delta": True}
    both = solve_both(data)
    assert np.all(both.plan.story_kg[0] > 0) and np.all(both.peer.story_geometric > 0)
    assert_displacements_agree(both)
    force = relative_difference(both.result.history["story_force"][0],
                                both.opensees["story_force"])
    assert force <= PEAK_RTOL, f"{force:.3e}"


@pytest.mark.slow
def test_soil_agrees():
    """models/ssi-pair.yaml (the paper's pair on sway and rocking springs and dashpots,
    improved Kelvin contacts, damping on the current stiffness): a 2-D model in the vertical
    plane, twoNodeLink storeys deforming by u_upper - u_lower - h theta; every DOF, the
    foundations' sway and rocking among them, agrees."""
    data = yaml.safe_load((MODELS / "ssi-pair.yaml").read_text(encoding="utf-8"))
    data["recorders"] = [{"kind": "history", "quantities": HISTORIES}]
    data["analysis"]["newton"] = {"tolerance": 1.0e-14, "absolute_tolerance": 1.0e-15}
    data["analysis"]["duration"] = 4.0  # 25,000 steps: the first impacts and their rocking
    both = solve_both(data)
    assert np.all(both.result.impacts[0] > 0)
    soil = both.peer.foundations
    assert soil is not None and np.all(soil.story_foundation >= 0)
    rocking = both.result.history["displacement"][0][:, soil.rocking]
    assert np.max(np.abs(rocking)) > 0.0
    assert_hunt_crossley_is_hertzdamp(both)
    assert_displacements_agree(both)
    for dofs in (soil.sway, soil.rocking):  # each to its own peak
        difference = relative_difference(both.result.history["displacement"][0][:, dofs],
                                         both.opensees["displacement"][:, dofs])
        assert difference <= PEAK_RTOL, f"{difference:.3e}"


@pytest.mark.slow
def test_damping_on_the_committed_stiffness_agrees():
    """damping: stiffness: committed is OpenSees' betaKcomm (the tangent at the last commit)."""
    data = paper_pair()
    data["damping"]["stiffness"] = "committed"
    both = solve_both(data)
    assert {r[4] for r in both.peer.rayleigh if len(r[3])} == {"committed"}
    assert_displacements_agree(both)


# ---------------------------------------------------------------------------------------------
# ground motions, Pi-form scenes, integrators, events
# ---------------------------------------------------------------------------------------------


@pytest.mark.slow
@pytest.mark.parametrize("model", ["wu2021-pulse.yaml", "wu2021-eq14-pi.yaml"])
def test_pulse_and_pi_form_scenes_agree(model):
    """A cycloidal pulse (sampled at the steps, as pframe applies it) and a Pi-form scene
    (exported after its expansion to the dimensional scene), both with improved Kelvin
    contacts and damping on the current stiffness."""
    text = (MODELS / model).read_text(encoding="utf-8")
    loaded = parse_scene(text, base_dir=MODELS)
    plan = assemble(loaded.expanded)
    result = simulate(plan)
    assert result.completed(), result.describe_failure()
    both = SimpleNamespace(plan=plan, result=result, peer=peer_scene(plan))
    both.opensees = run(both.peer)
    assert np.all(result.impacts[0] > 0)
    every = dict(plan.history)["displacement"]  # the scene's recorded steps
    difference = relative_difference(result.history["displacement"][0],
                                     both.opensees["displacement"][::every])
    assert difference <= PEAK_RTOL, f"{difference:.3e}"


@pytest.mark.slow
def test_stochastic_motion_agrees():
    """A stochastic ground motion (Rezaeian & Der Kiureghian's model, one seed) is the
    script's sampled series: the paper's pair, pounding under it, agrees to round-off."""
    data = paper_pair(excitation={
        "kind": "stochastic", "model": "rezaeian2010", "seed": 7,
        "parameters": {"arias": 3.0, "d595": 5.0, "tmid": 3.0, "frequency": 1.2,
                       "slope": -0.05, "damping": 0.3}})
    for contact in data["contacts"]:  # frequency_ratio is a sine's: its stiffness
        contact.pop("frequency_ratio")
        contact |= {"gap": 0.02, "stiffness": (65.0 * 2 * np.pi) ** 2 * 250.0 * 1000.0 / 1250.0}
    both = solve_both(data)
    assert np.sum(both.result.impacts[0]) >= 3
    assert_displacements_agree(both)


@pytest.mark.slow
def test_central_difference_without_velocity_forces_is_newmark_explicit():
    """Central difference (pframe: u + h v + h^2 a / 2, a from the forces there, the
    trapezoidal velocity) is OpenSees' NewmarkExplicit with gamma = 1/2 where no force
    depends on velocity: the paper's yielding, pounding pair without damping agrees to
    round-off, and the script names no difference."""
    data = paper_pair(damping={"ratio": 0.0})
    data["analysis"]["integrator"] = {"type": "central_difference"}
    both = solve_both(data)
    assert both.peer.integrator == ("central_difference",) and not both.peer.differences
    assert np.all(both.result.impacts[0] > 0)
    assert_displacements_agree(both)


def test_central_difference_names_its_difference_where_forces_depend_on_velocity():
    """With Rayleigh damping the two formulations part (pframe takes the damping force at a
    predicted velocity, OpenSees solves for the step end's): the export says so."""
    data = paper_pair()
    data["analysis"]["integrator"] = {"type": "central_difference"}
    data["analysis"]["duration"] = 0.01
    peer = peer_scene(assemble(parse_scene(json.dumps(data), base_dir=MODELS).expanded))
    assert len(peer.differences) == 1 and peer.differences[0].startswith("central_difference")


def test_events_are_stepped_over_and_said_so():
    """OpenSees has no event location: the script of a scene with events: true is the
    script of the same scene with events: false, but for the difference it names."""
    from pframe.peers.from_plan import EVENTS_DIFFERENCE
    from pframe.peers.opensees import script_text

    scripts = {}
    for events in (False, True):
        data = paper_pair()
        data["analysis"]["integrator"]["events"] = events
        data["analysis"]["duration"] = 0.01
        peer = peer_scene(assemble(parse_scene(json.dumps(data), base_dir=MODELS).expanded))
        scripts[events] = (script_text(peer), peer.differences)
    assert scripts[False][1] == () and scripts[True][1] == (EVENTS_DIFFERENCE,)
    assert "OpenSees steps over them" in scripts[True][0]

    def model(text):  # the script after its docstring, without its DIFFERENCES
        text = text[text.index("import base64"):]
        return text[:text.index("DIFFERENCES = ")] + text[text.index("OUT_NPZ = "):]

    assert model(scripts[True][0]) == model(scripts[False][0])


@pytest.mark.slow
def test_the_script_says_where_a_contact_pulled(capsys):
    """models/hust-4x3.yaml (0.3 s of it): the floors' second impact rebounds so fast that
    OpenSees' Hertzdamp pulls (1 + chi delta' / v0 < 0) where pframe's force is 0; the
    script says which contact, when, and that the two differ from then on."""
    data = yaml.safe_load((MODELS / "hust-4x3.yaml").read_text(encoding="utf-8"))
    data["analysis"]["duration"] = 0.3
    run(peer_scene(assemble(parse_scene(json.dumps(data), base_dir=MODELS).expanded)))
    err = capsys.readouterr().err
    assert "contact 'floor-2' pulled at t = 0.24" in err and "differ from then on" in err


# ---------------------------------------------------------------------------------------------
# every shipped model
# ---------------------------------------------------------------------------------------------

#: shipped models OpenSees cannot model, and the reason the refusal must give
REFUSED = {"floor-to-column.yaml": "a floor-to-column contact"}


@pytest.mark.slow
@pytest.mark.parametrize("name", sorted(p.name for p in MODELS.glob("*.yaml")))
def test_every_shipped_model_exports_and_its_script_runs(name, tmp_path, capsys):
    """``pframe opensees`` writes each of models/*.yaml (a record it names is linked from the
    records folder), saying on the terminal each way the script's model is not pframe's,
    and the script runs to the end with OpenSees; a model it cannot write is refused with
    the reason. The script is run as ``run`` runs one (its text, executed)."""
    from conftest import runnable_model

    from pframe.cli import main

    model = runnable_model(MODELS / name, tmp_path)
    script = tmp_path / "model_ops.py"
    code = main(["opensees", str(model), "-o", str(script)])
    err = capsys.readouterr().err
    if name in REFUSED:
        assert code == 2 and REFUSED[name] in err and not script.exists()
        return
    assert code == 0, err
    text = script.read_text(encoding="utf-8")
    namespace = {"__name__": "shipped_model", "__file__": str(script)}
    exec(compile(text, str(script), "exec"), namespace)
    assert err.count("model is not pframe's") == len(namespace["DIFFERENCES"])
    result = namespace["simulate"](str(tmp_path))
    steps = namespace["STEPS"]
    assert result["displacement"].shape[0] == steps + 1
    assert np.all(np.isfinite(result["displacement"]))
    assert np.max(np.abs(result["displacement"])) > 0.0


@pytest.mark.slow
def test_central_difference_with_damping_is_each_programs_own_recurrence():
    """Where a force depends on velocity the two central differences are two recurrences,
    each taken here in closed form for a damped oscillator (m, c, k) under a sine: pframe's
    (u1 = u + h v + h^2 a / 2; the force at the predicted velocity v + h a gives a
    corrector, whose velocity v + h (a + a1') / 2 gives a1; v1 = v + h (a + a1) / 2) and
    OpenSees' NewmarkExplicit (the same u1; (m + h c / 2) a1 = F1 - k u1 - c (v + h a / 2);
    v1 = v + h (a + a1) / 2). Each program follows its own to round-off, and the two part by
    O(h^3) (their damping forces by h^2 a step; measured 2.7e-7 and 3.3e-8 of the peak at
    h = 2 and 1 ms): halving the step divides the difference by 8 (the export names it)."""
    def scene(dt):
        return {"nodes": [{"name": "A/1", "mass": 1.0e3}],
                "stories": [{"nodes": ["ground", "A/1"], "material": "elastic",
                             "stiffness": 4.0e5}],
                "damping": {"ratio": 0.1},
                "excitation": {"kind": "sine", "amplitude": 2.0, "frequency": 5.0},
                "analysis": {"integrator": {"type": "central_difference"}, "dt": dt,
                             "duration": 2.0},
                "recorders": [{"kind": "history", "quantities": ["displacement"]}]}

    def recurrence(plan, own: bool) -> np.ndarray:
        m, k = plan.mass[0, 0], plan.story_k0[0, 0]
        c = plan.mass_damping[0, 0] + plan.story_beta[0, 0] * k
        h, load = plan.dt[0], -m * plan.ground_acceleration[0]
        u, v, a = 0.0, 0.0, load[0] / m
        out = [u]
        for f in load[1:]:
            u = u + h * v + 0.5 * h * h * a
            if own:
                a1 = (f - k * u - c * (v + h * a)) / m
                a1 = (f - k * u - c * (v + 0.5 * h * (a + a1))) / m
            else:
                a1 = (f - k * u - c * (v + 0.5 * h * a)) / (m + 0.5 * h * c)
            v, a = v + 0.5 * h * (a + a1), a1
            out.append(u)
        return np.array(out)

    gaps = []
    for dt in (2e-3, 1e-3):
        both = solve_both(scene(dt))
        ours, theirs = both.result.history["displacement"][0][:, 0], both.opensees[
            "displacement"][:, 0]
        assert relative_difference(ours, recurrence(both.plan, True)) <= 1e-12
        assert relative_difference(theirs, recurrence(both.plan, False)) <= 1e-12
        gaps.append(relative_difference(ours, theirs))
    assert 7.0 < gaps[0] / gaps[1] < 9.0, gaps
