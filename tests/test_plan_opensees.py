"""pframe against OpenSeesPy on buildings in plan (docs/plan.md).

The OpenSees model (:mod:`pframe.peers.opensees`) is built from the scene's geometry with stock
components: a node per floor at its centre of mass with (m, m, J), a node per element end tied
to its floor by ``rigidLink beam``, ``zeroLength`` elements oriented along each line of
resistance, contact normal or link, Rayleigh regions, the same Newmark. Both programs then
integrate the same discrete equations, so their histories agree to round-off that yielding and
impacts amplify, not to a discretisation error: to 1e-9 of their peaks (the issue's figure).

The energy balance is checked twice: pframe's own (kernel/c/energy.c), and the same balance
recomputed from OpenSees' histories alone (its velocities, element forces and deformations,
the trapezoidal works of average acceleration), term by term against pframe's.
"""

from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path
from types import SimpleNamespace

import numpy as np
import pytest
from conftest import require_opensees

require_opensees()

from pframe.assemble import assemble  # noqa: E402
from pframe.assemble.incidence import incidence  # noqa: E402
from pframe.errors import InputError  # noqa: E402
from pframe.kernel import simulate  # noqa: E402
from pframe.peers.from_plan import peer_scene  # noqa: E402
from pframe.peers.opensees import run, script_text  # noqa: E402
from pframe.reader import parse_scene  # noqa: E402

#: max over DOFs (elements) and times of |pframe - OpenSees| over max |OpenSees|
PEAK_RTOL = 1e-9
#: the energy balance and each of its terms, over the largest term of the run
ENERGY_RTOL = 1e-9
#: Newton stops where both programs' round-off does (the comparison is not limited by it)
NEWTON = {"tolerance": 1.0e-14, "absolute_tolerance": 1.0e-15}
HISTORIES = ["displacement", "velocity", "story_drift", "story_force", "contact_force",
             "contact_penetration", "link_force", "link_deformation"]
MASS = 1.2e5
SIZE = (12.0, 8.0)  # plan (m)


def lines(material: str, stiffness=(4.0e7, 2.5e7, 3.0e7, 5.0e7, 2.0e7)) -> list[dict]:
    """Four frames along the plan's edges and a brace at its NE corner at 135 degrees, of
    unequal stiffness (N/m): the centre of rigidity is off the plan's centre; ``bilinear``
    yields at a drift of 4 mm."""
    law = ({"material": "elastic"} if material == "elastic" else
           {"material": "bilinear", "yield_drift": 0.004, "alpha": 0.05})
    where = [("X1", [0, 0], "x"), ("X2", [0, SIZE[1]], "x"), ("Y1", [0, 0], "y"),
             ("Y2", [SIZE[0], 0], "y"), ("D", list(SIZE), 135.0)]
    return [{"name": name, "position": p, "direction": d, "stiffness": k} | law
            for (name, p, d), k in zip(where, stiffness)]


def building(name: str, floors: int, material: str, centre=(7.5, 3.2), **more) -> dict:
    """A building of ``floors`` storeys on :func:`lines`, its mass off the plan's centre."""
    return {"name": name, "floors": floors, "mass": MASS, "height": 3.0,
            "plan": {"size": list(SIZE)}, "centre_of_mass": list(centre),
            "lines": lines(material)} | more


def scene(buildings: list[dict], dt: float = 0.002, duration: float = 3.0, **more) -> dict:
    return {
        "buildings": buildings,
        "damping": {"ratio": 0.05, "modes": [1, 3]},
        "excitation": {"kind": "sine", "amplitude": 3.0, "frequency": 2.0, "cycles": 3},
        "analysis": {"integrator": {"type": "newmark", "gamma": 0.5, "beta": 0.25},
                     "dt": dt, "duration": duration, "newton": NEWTON},
        "recorders": [{"kind": "history", "quantities": HISTORIES}],
    } | more


def solve_both(data: dict, base_dir: Path | None = None) -> SimpleNamespace:
    """pframe and OpenSeesPy on one scene in plan."""
    loaded = parse_scene(json.dumps(data), base_dir=base_dir)
    plan = assemble(loaded.expanded)
    assert not plan.planar
    result = simulate(plan)
    assert result.completed(), result.describe_failure()
    peer = peer_scene(plan, centres=loaded.expanded.node_centre)
    return SimpleNamespace(plan=plan, result=result, peer=peer, opensees=run(peer))


def relative_difference(ours: np.ndarray, theirs: np.ndarray) -> float:
    assert ours.shape == theirs.shape
    return float(np.max(np.abs(ours - theirs)) / np.max(np.abs(theirs)))


def assert_agreement(both: SimpleNamespace) -> dict:
    """Every history both record, to PEAK_RTOL of its peak; returns the differences."""
    differences = {}
    for quantity in HISTORIES:
        ours = both.result.history.get(quantity)
        if ours is None or ours.shape[2] == 0:
            continue
        differences[quantity] = relative_difference(ours[0], both.opensees[quantity])
    failed = {q: d for q, d in differences.items() if not d <= PEAK_RTOL}
    assert not failed, ", ".join(f"{q}: {d:.3e}" for q, d in failed.items())
    return differences


def penetration(peer, u: np.ndarray) -> np.ndarray:
    """(steps + 1, c) each contact's n . (u_left - u_right) - gap from the floors' motions u
    (negative while open), by the rigid-diaphragm map of the script's own geometry: a point P
    of a floor moves along n by n_x u_x + n_y u_y + ((P - c) x n) theta."""
    floors = peer.floors
    column = {(int(f), int(k)): i for i, (f, k) in enumerate(floors.dofs)}
    out = np.zeros((u.shape[0], len(peer.contact_gaps))) - np.asarray(peer.contact_gaps)
    for e, (nodes, points, n) in enumerate(zip(peer.contact_nodes, floors.contact_points,
                                              floors.contact_directions)):
        for f, p, sign in zip(nodes, points, (1.0, -1.0)):
            if f < 0:
                continue
            r = p - floors.centres[f]
            for k, a in enumerate((n[0], n[1], r[0] * n[1] - r[1] * n[0])):
                if (f, k) in column:
                    out[:, e] += sign * a * u[:, column[(f, k)]]
    return out


def opensees_energy(peer, opensees: dict) -> dict:
    """The works of average acceleration's balance from OpenSees' histories alone (J): input
    -sum 1/2 (a_g,n + a_g,n+1) m du along each channel, the kinetic energy 1/2 v M v at the
    end, damping (alpha_m M v on the floors, beta k0 on each storey's deformation rate,
    whose step sum is 2 dd / dt under average acceleration), and the trapezoidal works of the
    storeys', contacts' and links' forces on their deformations (kernel/c/energy.c; a
    contact's on its penetration, negative while open, as pframe counts it)."""
    u, v = opensees["displacement"], opensees["velocity"]
    du = np.diff(u, axis=0)
    dofs, m = peer.floors.dofs, np.asarray(peer.masses)
    ag = np.atleast_2d(peer.ground_acceleration)
    work_in = 0.0
    for row, axis in zip(ag, peer.channels):
        loaded = dofs[:, 1] == {"x": 0, "y": 1}[axis]
        work_in -= np.sum(0.5 * (row[:-1] + row[1:]) * (du[:, loaded] @ m[loaded]))
    alpha = np.zeros(len(m))
    beta = np.zeros(len(peer.story_materials))
    for alpha_m, beta_k, floors, stories, stiffness in peer.rayleigh:
        assert stiffness == "initial" or not len(stories)  # beta_k on k0, as below
        alpha[np.isin(dofs[:, 0], floors)] += alpha_m
        beta[np.asarray(stories, dtype=int)] = beta_k
    k0 = np.array([mat[1] for mat in peer.story_materials])
    drift = np.diff(opensees["story_drift"], axis=0)
    damping = (np.sum(0.5 * (v[:-1] + v[1:]) * du * alpha * m)
               + np.sum(beta * k0 * drift**2) / peer.dt)

    def work(force, deformation):
        return float(np.sum(0.5 * (force[:-1] + force[1:]) * np.diff(deformation, axis=0)))

    return {"input": float(work_in), "kinetic": float(0.5 * np.sum(m * v[-1] ** 2)),
            "damping": float(damping),
            "storeys": work(opensees["story_force"], opensees["story_drift"]),
            "contacts": work(opensees["contact_force"], penetration(peer, u)),
            "links": work(opensees["link_force"], opensees["link_deformation"])}


def assert_energy_closes(both: SimpleNamespace) -> float:
    """pframe's balance closes, OpenSees' closes, and each term is the same in both;
    returns the largest term difference over the scale."""
    result = both.result
    scale = result.energy_scale()
    assert result.energy_error() <= ENERGY_RTOL, result.energy_error()
    ours = result.energy_terms()
    theirs = opensees_energy(both.peer, both.opensees)
    balance = theirs["input"] - sum(w for name, w in theirs.items() if name != "input")
    assert abs(balance) <= ENERGY_RTOL * scale, f"OpenSees' balance {balance / scale:.3e}"
    # average acceleration does not damp: its dissipation is round-off
    assert abs(ours["algorithmic"]) <= ENERGY_RTOL * scale and ours["initial_kinetic"] == 0.0
    differences = {name: abs(ours[name] - w) / scale for name, w in theirs.items()}
    failed = {q: d for q, d in differences.items() if not d <= ENERGY_RTOL}
    assert not failed, ", ".join(f"{q}: {d:.3e}" for q, d in failed.items())
    return max(differences.values())


def floor_rotation(both: SimpleNamespace, node: str, source: str = "pframe") -> np.ndarray:
    """theta (rad) of a floor over time."""
    plan = both.plan
    f = plan.node_names.index(node)
    column = int(np.flatnonzero((plan.dof_node == f) & (plan.dof_component == 2))[0])
    u = (both.result.history["displacement"][0] if source == "pframe"
         else both.opensees["displacement"])
    return u[:, column]


# ---------------------------------------------------------------------------------------------
# (a) eccentric elastic buildings, (b) the same with bilinear lines, (d) the energy in each
# ---------------------------------------------------------------------------------------------


@pytest.mark.slow
def test_one_storey_eccentric_building_under_a_record_starting_accelerated(tmp_path):
    """One storey, its mass off the centre of rigidity, turned 20 degrees on the site, under a
    record with a_g(0) != 0 along x: it sways along both axes and twists, and both programs
    start from equilibrium at rest, a(0) = -a_g(0) on every floor's u_x (OpenSees would
    otherwise start from a = 0, which changes a whole history)."""
    dt = 0.002
    t = np.arange(1501) * dt
    a = 2.5 * np.cos(9.0 * t) * np.exp(-0.4 * t) + 0.8 * np.sin(31.0 * t)
    record = tmp_path / "ground.txt"
    record.write_text("".join(f"{ti!r} {ai!r}\n" for ti, ai in zip(t.tolist(), a.tolist())),
                      encoding="utf-8")
    data = scene([building("A", 1, "elastic", angle=20.0, origin=[3.0, -2.0])],
                 excitation={"kind": "record", "file": record.name, "units": "m/s2"})
    both = solve_both(data, base_dir=tmp_path)
    assert both.plan.ground_acceleration[0, 0] == 2.5
    assert both.plan.n_dof == 3 and both.plan.linear
    theta = floor_rotation(both, "A/1")
    assert np.max(np.abs(theta)) * SIZE[0] > 0.05 * np.max(np.abs(
        both.result.history["displacement"][0]))  # it twists
    assert_agreement(both)
    assert_energy_closes(both)


@pytest.mark.slow
@pytest.mark.parametrize("material", ["elastic", "bilinear"])
def test_multi_storey_eccentric_building(material):
    """Three storeys turned 20 degrees, x excitation near the first mode: elastic (the linear
    kernel, one factorisation) and bilinear lines that yield (Newton, Steel01)."""
    data = scene([building("A", 3, material, angle=20.0)])
    both = solve_both(data)
    assert both.plan.n_dof == 9
    if material == "bilinear":
        drift = both.result.history["story_drift"][0]
        force = both.result.history["story_force"][0]
        k0 = both.plan.story_k0[0]
        plastic = np.max(np.abs(force - k0 * drift), axis=0) > 1e-3 * np.max(np.abs(force))
        assert np.count_nonzero(plastic) >= 5, "the lines must yield"
    assert_agreement(both)
    assert_energy_closes(both)


@pytest.mark.slow
def test_one_storey_bilinear_building():
    data = scene([building("A", 1, "bilinear", angle=-35.0)],
                 excitation={"kind": "sine", "amplitude": 5.0, "frequency": 3.0, "cycles": 3})
    both = solve_both(data)
    force, drift = (both.result.history[q][0] for q in ("story_force", "story_drift"))
    assert np.max(np.abs(force - both.plan.story_k0[0] * drift)) > 1e-2 * np.max(np.abs(force))
    assert_agreement(both)
    assert_energy_closes(both)


@pytest.mark.slow
def test_p_delta_in_plan():
    """P-delta in plan: pframe's P-delta springs of each storey, along x and y at the
    gravity loads' centre and on the floors' rotation (lever r, the loads' spread: a
    zeroLength about z of r^2 times its stiffness, Elastic(-r^2 P / h) beside it, undamped),
    of two buildings pounding at a corner: every history agrees, each spring's force with
    its P-delta part (measured 3e-15 of the peak in displacement)."""
    data = corner_scene(dt=0.002)
    for b in data["buildings"]:
        b["p_delta"] = True
    both = solve_both(data)
    names = both.plan.story_names
    p_delta = np.array(["P-delta" in name for name in names])
    assert np.all(both.peer.story_geometric[p_delta] > 0) and not np.any(
        both.peer.story_geometric[~p_delta])
    turning = np.array([name.endswith("P-delta-rz") for name in names])
    assert np.all(both.peer.floors.story_levers[turning] > 0)
    assert np.all(both.result.impacts[0] > 0)
    assert_agreement(both)


# ---------------------------------------------------------------------------------------------
# (c) two buildings pounding at a corner
# ---------------------------------------------------------------------------------------------

#: B: a symmetric building (its centre of mass on its centre of rigidity) east of A, its west
#: edge 5 cm from A's east edge; its point [0, 6] faces A's NE corner [12, 8] across x
SYMMETRIC = [{"name": n, "position": p, "direction": d, "material": "elastic", "stiffness": k}
             for n, p, d, k in (("X1", [0, 0], "x", 6.0e7), ("X2", [0, 8], "x", 6.0e7),
                                ("Y1", [0, 0], "y", 6.0e7), ("Y2", [12, 0], "y", 6.0e7))]


def corner_scene(dt: float) -> dict:
    b = {"name": "B", "floors": 2, "mass": 0.8 * MASS, "height": 3.0, "plan": {"size": list(SIZE)},
         "origin": [12.05, 2.0], "lines": SYMMETRIC}
    contacts = [{"name": f"corner-{i}", "nodes": [f"A/{i}", f"B/{i}"], "points": ["NE", [0, 6]],
                 "normal": [1, 0], "gap": 0.01, "law": "linear", "stiffness": 1.0e9}
                for i in (1, 2)]
    return scene([building("A", 2, "bilinear"), b], dt=dt, duration=4.0, contacts=contacts,
                 excitation={"kind": "sine", "amplitude": 4.0, "frequency": 1.5, "cycles": 4})


@pytest.mark.slow
def test_corner_impact_twists_both_buildings_and_agrees():
    """A yielding eccentric building strikes a symmetric one at a corner (a linear contact, a
    point off both centres of mass): B only twists once struck. The contact is resolved in
    time (some 40 steps per contact period), so the two programs follow the same impacts and
    agree point by point."""
    both = solve_both(corner_scene(dt=0.001))
    plan, result = both.plan, both.result
    assert not plan.warnings, plan.warnings
    impacts = result.impacts[0]
    assert np.all(impacts > 0), impacts
    force = result.history["contact_force"][0]
    first = int(np.argmax(np.any(force > 0.0, axis=1)))
    for floor in ("B/1", "B/2"):
        theta = floor_rotation(both, floor)
        # symmetric: no twist before the first impact (but the round-off of its arms)
        assert np.max(np.abs(theta[:first])) < 1e-12 * np.max(np.abs(theta))
        assert np.max(np.abs(theta)) > 1e-4  # rad: struck at an arm of 2 m
    assert np.max(np.abs(floor_rotation(both, "A/1"))) > 1e-4
    # the contact period at its effective mass (1 / sum a^2 / m of both sides)
    mobility = sum(a * a / plan.mass[0, d] for s in range(2)
                   for d, a in plan.contact_sides.side(0, s))
    period = 2 * np.pi / np.sqrt(1.0e9 * mobility)
    assert period / plan.dt[0] > 30
    counted = np.sum((both.opensees["contact_force"][:-1] <= 0.0)
                     & (both.opensees["contact_force"][1:] > 0.0), axis=0)
    np.testing.assert_array_equal(counted, impacts)
    assert_agreement(both)
    assert_energy_closes(both)


@pytest.mark.slow
def test_links_and_a_wall_in_plan():
    """A Kelvin-Voigt link along [3, 2] between the two buildings' points, and a wall (a
    contact to the ground) west of A at its SW corner: the ground's end of the wall and the
    link's ends are points of the floors like any other."""
    data = corner_scene(dt=0.001)
    data["links"] = [{"name": "damper", "nodes": ["A/2", "B/2"], "points": [[12, 2], [0, 1]],
                      "direction": [3.0, 2.0], "material": "kelvin_voigt", "stiffness": 1.0e6,
                      "damping": 2.0e5}]
    data["contacts"].append({"name": "wall", "nodes": ["ground", "A/1"], "points": [None, "SW"],
                             "normal": [1, 0], "gap": 0.02, "law": "linear",
                             "stiffness": 1.0e9})
    both = solve_both(data)
    assert np.all(both.result.impacts[0] > 0), both.result.impacts[0]
    assert np.max(np.abs(both.result.history["link_force"][0])) > 0
    assert_agreement(both)
    assert_energy_closes(both)


# ---------------------------------------------------------------------------------------------
# Ground motion along y, and in two components
# ---------------------------------------------------------------------------------------------


@pytest.mark.slow
def test_motion_along_y():
    data = scene([building("A", 2, "bilinear", angle=20.0)], excitation={
        "kind": "components", "y": {"kind": "sine", "amplitude": 4.0, "frequency": 2.0,
                                    "cycles": 3}})
    both = solve_both(data)
    # a motion in components loads both site axes (one layout whatever its angle): x is 0
    assert both.plan.channels == ("x", "y") == tuple(both.peer.channels)
    assert np.all(both.plan.ground_channels[0, 0] == 0.0)
    assert np.max(np.abs(both.plan.ground_channels[0, 1])) > 0.0
    assert_agreement(both)
    assert_energy_closes(both)


@pytest.mark.slow
def test_two_components_agree_and_superpose():
    """Both components at once (the script writes a UniformExcitation per channel): pframe
    agrees with OpenSees; and on an elastic building (turned on the site) the response to both
    is the sum of the responses to each, pframe's x run plus its y run."""
    x = {"kind": "sine", "amplitude": 3.0, "frequency": 2.0, "cycles": 3}
    y = {"kind": "sine", "amplitude": 2.0, "frequency": 3.0, "cycles": 4}
    pair = scene([building("A", 2, "elastic", angle=20.0)], excitation={
        "kind": "components", "x": x, "y": y})
    both = solve_both(pair)
    assert_agreement(both)
    assert_energy_closes(both)
    plan, opensees = both.plan, both.opensees
    assert plan.channels == ("x", "y")
    total = 0.0
    for alone in ({"x": x}, {"y": y}):
        part = scene(pair["buildings"], excitation={"kind": "components"} | alone)
        one = assemble(parse_scene(json.dumps(part)).expanded)
        assert one.n_dof == plan.n_dof
        np.testing.assert_array_equal(one.dof_node, plan.dof_node)
        np.testing.assert_array_equal(one.dof_component, plan.dof_component)
        result = simulate(one)
        assert result.completed()
        total = total + result.history["displacement"][0]
    assert relative_difference(total, opensees["displacement"]) <= 1e-12
    assert relative_difference(total, both.result.history["displacement"][0]) <= 1e-12


# ---------------------------------------------------------------------------------------------
# The geometry the script is written from, the script on its own, and refusals
# ---------------------------------------------------------------------------------------------


def test_ends_reproduce_the_sides():
    """Each element end's point and direction give back its side's coefficients a = (n_x,
    n_y, (P - c) x n): the deformations OpenSees' rigid links and zeroLength compute from
    them are pframe's, d = G u, whatever the site's coordinates (with or without the
    centres); a storey's two ends coincide."""
    data = corner_scene(dt=0.001)
    data["buildings"][1]["angle"] = 25.0
    data["links"] = [{"name": "damper", "nodes": ["A/2", "B/2"], "points": [[12, 2], [0, 1]],
                      "direction": [3.0, 2.0], "material": "elastic", "stiffness": 1.0e6}]
    loaded = parse_scene(json.dumps(data))
    plan = assemble(loaded.expanded)
    ns = len(plan.story_names)
    for centres in (loaded.expanded.node_centre, None):
        floors = peer_scene(plan, centres=centres).floors
        c = floors.centres
        for kind, dofs, sides, points, directions, contact in (
                ("story", plan.story_dofs, plan.story_sides,
                 np.concatenate([floors.story_points, floors.link_points]),
                 np.concatenate([floors.story_directions, floors.link_directions]), False),
                ("contact", plan.contact_dofs, plan.contact_sides, floors.contact_points,
                 floors.contact_directions, True)):
            nodes = np.where(dofs >= 0, plan.dof_node[np.clip(dofs, 0, None)], -1)
            g = np.zeros((len(dofs), plan.n_dof))
            for e in range(len(dofs)):
                n = directions[e]
                assert abs(np.hypot(*n) - 1.0) < 1e-15
                for s, sign in enumerate((1.0, -1.0) if contact else (-1.0, 1.0)):
                    f = nodes[e, s]
                    if f < 0:
                        continue
                    r = points[e, s] - c[f]
                    for k, a in enumerate((n[0], n[1], r[0] * n[1] - r[1] * n[0])):
                        hit = np.flatnonzero((plan.dof_node == f) & (plan.dof_component == k))
                        if hit.size:
                            g[e, hit[0]] += sign * a
                        else:  # a component the scene does not move: no part of it
                            assert abs(a) < 1e-12, (kind, e, s, k)
            expected = incidence(dofs, sides, 0, plan.n_dof, contact=contact).toarray()
            np.testing.assert_allclose(g, expected, rtol=0, atol=1e-13)
            if kind == "story":
                np.testing.assert_allclose(points[:ns, 0], points[:ns, 1], rtol=0, atol=1e-13)


@pytest.mark.slow
def test_exported_script_runs_without_pframe(tmp_path):
    """``pframe opensees`` on a scene in plan: the script runs in a Python where pframe cannot
    be imported, and saves exactly what :func:`run` returns in process."""
    from pframe.cli import main

    data = corner_scene(dt=0.002)
    data["analysis"]["duration"] = 1.5
    model = tmp_path / "corner.yaml"
    model.write_text(json.dumps(data), encoding="utf-8")
    script = tmp_path / "corner_ops.py"
    assert main(["opensees", str(model), "-o", str(script)]) == 0
    text = script.read_text(encoding="utf-8")
    assert "rigidLink" in text and '"-ndm", 2, "-ndf", 3' in text
    out = tmp_path / "out.npz"
    script.write_text(text.replace("OUT_NPZ = None", f"OUT_NPZ = {str(out)!r}"),
                      encoding="utf-8")
    blocked = ("import runpy, sys; sys.modules['pframe'] = None; "  # import pframe fails
               f"runpy.run_path({str(script)!r}, run_name='__main__')")
    done = subprocess.run([sys.executable, "-c", blocked], capture_output=True, text=True,
                          timeout=600, cwd=tmp_path)
    assert done.returncode == 0, done.stderr
    saved = np.load(out)
    loaded = parse_scene(json.dumps(data))
    in_process = run(peer_scene(assemble(loaded.expanded), centres=loaded.expanded.node_centre))
    for quantity in HISTORIES + ["time"]:
        np.testing.assert_array_equal(saved[quantity], in_process[quantity], err_msg=quantity)


def test_refusals_in_plan_name_each_reason():
    """A scene in plan the script cannot model is refused with every reason: here initial
    conditions and a Kelvin contact, which has no OpenSees twin (the planar refusal of scenes
    in plan is gone)."""
    data = corner_scene(dt=0.002)
    data["contacts"][0] = {key: value for key, value in data["contacts"][0].items()
                           if key not in ("law", "stiffness")} | {
        "law": "kelvin", "stiffness": 1.0e9, "restitution": 0.6}
    data["initial_conditions"] = {"displacement": {"A/1": [0.0, 0.01, 0.0]}}
    plan = assemble(parse_scene(json.dumps(data)).expanded)
    with pytest.raises(InputError) as caught:
        peer_scene(plan)
    message = str(caught.value)
    assert "initial_conditions" in message
    assert f"{data['contacts'][0]['name']} (kelvin): OpenSees has no uniaxial material" in message
    assert "planar" not in message


def test_to_opensees_writes_a_scene_in_plan():
    """pframe.to_opensees draws each floor at its centre of mass on the site (A's given, B's
    the centroid of its plan from its origin); peer_scene without the centres draws them at
    the origin."""
    import pframe

    data = corner_scene(dt=0.002)
    text = pframe.to_opensees(data)
    assert "FLOOR_NAMES = ['A/1', 'A/2', 'B/1', 'B/2']" in text
    assert "CENTRES = [[7.5, 3.2], [7.5, 3.2], [18.05, 6.0], [18.05, 6.0]]" in text
    bare = script_text(peer_scene(assemble(parse_scene(json.dumps(data)).expanded)))
    assert "CENTRES = [[0.0, 0.0], [0.0, 0.0], [0.0, 0.0], [0.0, 0.0]]" in bare
