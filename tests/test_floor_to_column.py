"""Floor-to-column contacts: a floor striking a neighbour's column between two of its floors.

The struck point's displacement is psi u_upper + (1 - psi) u_lower with the fixed-fixed
column's shape psi = 3 at^2 - 2 at^3, and the contact force is shared between the two floors
with the same weights. A hand-derived case: a mass striking the mid-height of a column joining
two free masses is an elastic impact of two bodies, the struck point's mass being
1 / (psi^2 / m_upper + (1 - psi)^2 / m_lower); the impulse goes to the two floors as psi and
1 - psi.
"""

from __future__ import annotations

import json
import math
import re
import warnings

import numpy as np
import pytest
from conftest import REPO, record_file, run_text, runnable_model

from pframe.errors import InputError


def _psi(at):
    return at * at * (3.0 - 2.0 * at)


def _scene(at: float, m_a=500.0, m1=1000.0, m2=2000.0, k_c=1e8, v0=0.5, capacity=None,
           law=None, duration=0.01):
    contact = {"name": "f2c", "nodes": ["A/1", "B/2"], "gap": 0.0, "column": "right",
               "at": at} | (law or {"law": "linear", "stiffness": k_c})
    if capacity is not None:
        contact["shear_capacity"] = capacity
    return json.dumps({
        "buildings": [{"name": "A", "floors": 1, "mass": m_a,
                       "story": {"material": "elastic", "stiffness": 1e-3}},
                      {"name": "B", "floors": 2, "mass": [m1, m2],
                       "story": {"material": "elastic", "stiffness": 1e-3}}],
        "contacts": [contact],
        "damping": {"ratio": 0.0},
        "initial_conditions": {"velocity": {"A/1": v0}},
        "analysis": {"dt": 2e-6, "duration": duration,
                     "integrator": {"type": "newmark", "events": True}},
        "recorders": [{"kind": "history", "quantities": ["velocity", "contact_force"]}],
    })


@pytest.mark.parametrize("at", [0.5, 0.25, 0.8])
def test_an_impact_on_a_column_is_a_two_body_impact(at):
    m_a, m1, m2, k_c, v0 = 500.0, 1000.0, 2000.0, 1e8, 0.5
    psi = at * at * (3.0 - 2.0 * at)
    plan, result = run_text(_scene(at))
    assert result.completed(0) and int(result.impacts[0, 0]) == 1
    v = result.history["velocity"][0][:, plan.node_dof]
    m_point = 1.0 / (psi**2 / m2 + (1.0 - psi) ** 2 / m1)
    m_eff = m_a * m_point / (m_a + m_point)
    impulse = 2.0 * m_eff * v0
    np.testing.assert_allclose(v[-1], [v0 * (m_a - m_point) / (m_a + m_point),
                                       (1.0 - psi) * impulse / m1, psi * impulse / m2],
                               rtol=1e-8, atol=1e-10)
    force = result.history["contact_force"][0, :, 0]
    duration = np.count_nonzero(force > 0) * 2e-6
    assert duration == pytest.approx(math.pi * math.sqrt(m_eff / k_c), abs=4e-6)
    assert result.energy_error(0) < 1e-12
    # the struck column's local shear: the larger segment, max(psi, 1 - psi) F
    np.testing.assert_allclose(result.column_shear(0),
                               [max(psi, 1 - psi) * np.max(force)], rtol=1e-12)


@pytest.mark.filterwarnings("ignore:.*its first period")  # free masses: no storeys to speak of
def test_the_impact_table_and_the_dataset_give_each_impacts_column_shear():
    """The two-body impact at 0.25 of the storey: one impact whose column shear is
    max(psi, 1 - psi) times its peak force, in the impact table (pframe.impacts, the
    summary) and in the Dataset (impact_column_shear, peak_column_shear), in N."""
    import pframe

    psi = _psi(0.25)
    ds = pframe.solve(pframe.load(json.loads(_scene(0.25))))
    table = pframe.impacts(ds)
    assert len(table) == 1
    shear = max(psi, 1 - psi) * table.peak_force[0]
    assert table.column_shear[0] == pytest.approx(shear, rel=1e-15)
    peak = float(ds.contact_force.max())
    assert float(ds.impact_column_shear[0]) == pytest.approx(max(psi, 1 - psi) * peak, rel=1e-15)
    assert float(ds.peak_column_shear[0]) == pytest.approx(max(psi, 1 - psi) * peak, rel=1e-15)
    summary = pframe.summary(ds)
    row = summary[(summary.part == "impact") & (summary.quantity == "column shear")]
    assert list(row.value) == [table.column_shear[0]] and list(row.units) == ["N"]


def test_the_calibrated_restitution_uses_the_struck_points_mass():
    """exact calibration for the effective mass of the floor and the column point: the
    relative velocity of the two points rebounds with e."""
    at, e = 0.5, 0.6
    psi = at * at * (3.0 - 2.0 * at)
    plan, result = run_text(_scene(at, law={"law": "hertzdamp", "stiffness": 1e9,
                                           "restitution": e, "calibration": "exact"},
                                   duration=0.05))
    force = result.history["contact_force"][0, :, 0]
    assert force[-1] == 0.0 and int(result.impacts[0, 0]) == 1  # separated
    v = result.history["velocity"][0][:, plan.node_dof]
    point = psi * v[:, 2] + (1 - psi) * v[:, 1]
    assert -(v[-1, 0] - point[-1]) / 0.5 == pytest.approx(e, abs=2e-4)


def test_the_capacity_check_warns_everywhere(tmp_path):
    import pframe

    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        ds = pframe.solve(pframe.load(json.loads(_scene(0.5, capacity=1e4))),
                          output=tmp_path / "run.nc")
    assert any("exceeds the column's shear capacity" in str(w.message) for w in caught)
    assert "exceeds the column's shear capacity" in ds.attrs["warnings"]
    _, quiet = run_text(_scene(0.5, capacity=1e9))
    assert quiet.column_shear(0)[0] < 1e9


def test_floor_to_column_errors_are_clear():
    from pframe.reader import parse_scene

    data = json.loads(_scene(0.5))
    del data["contacts"][0]["at"]
    with pytest.raises(InputError, match="needs at, where the column is struck"):
        _ = parse_scene(json.dumps(data)).expanded
    data = json.loads(_scene(0.5))
    data["contacts"][0]["column"] = "left"  # A/1 tops a storey, B/2 is the node: fine
    _ = parse_scene(json.dumps(data)).expanded
    data["contacts"][0]["nodes"] = ["ground", "B/2"]
    with pytest.raises(InputError, match="tops no storey"):
        _ = parse_scene(json.dumps(data)).expanded


def _offset_pair(contact: dict) -> str:
    """A (storeys of 3 m: floors at 3, 6, 9 m) beside B (storeys of 4.5 m: 4.5, 9 m)."""
    return json.dumps({
        "buildings": [{"name": "A", "floors": 3, "mass": 1000.0, "height": 3.0,
                       "story": {"material": "elastic", "stiffness": 1e6}},
                      {"name": "B", "floors": 2, "mass": 1000.0, "height": 4.5,
                       "story": {"material": "elastic", "stiffness": 1e6}}],
        "contacts": [{"name": "c", "gap": 0.01, "law": "linear", "stiffness": 1e8} | contact],
        "excitation": {"kind": "sine", "amplitude": 1.0, "frequency": 5.0},
        "analysis": {"dt": 1e-3, "duration": 0.01}})


def test_at_follows_the_storey_heights():
    """With both buildings' heights, at = (z_floor - z_lower) / (z_upper - z_lower): A/2 at
    6 m strikes B's storey from 4.5 to 9 m at 1/3 of it, whether at is left out or given
    within 0.001; a contradicting at (the 0.9 once accepted) is refused, naming the value the
    heights give."""
    from pframe.reader import parse_scene

    computed = parse_scene(_offset_pair({"nodes": ["A/2", "B/2"], "column": "right"}))
    c = computed.expanded.contacts[0]
    psi = (1 / 3) ** 2 * (3 - 2 / 3)
    assert c.at[1] == pytest.approx(1 / 3, rel=1e-15) and c.share[1] == pytest.approx(psi)
    names = computed.expanded.node_names
    assert names[c.lower[1]] == "B/1" and c.share[0] == 1.0 and math.isnan(c.at[0])
    close = parse_scene(_offset_pair({"nodes": ["A/2", "B/2"], "column": "right", "at": 0.333}))
    assert close.expanded.contacts[0].at[1] == c.at[1]
    with pytest.raises(InputError, match=r"contacts\[0\]\.at: at 0\.9 contradicts the storey "
                                         r"heights: floor A/2 at 6 m .* from 4\.5 to 9 m put "
                                         r"the struck point at 0\.333333"):
        _ = parse_scene(_offset_pair({"nodes": ["A/2", "B/2"], "column": "right",
                                      "at": 0.9})).expanded


@pytest.mark.parametrize("contact, says", [
    # A/1 at 3 m is below B's second storey (4.5 to 9 m)
    ({"nodes": ["A/1", "B/2"], "column": "right"}, "cannot strike that storey (it is below"),
    # A/3 at 9 m is level with B/2: a floor-to-floor contact
    ({"nodes": ["A/3", "B/2"], "column": "right"}, "level with B/2, a floor-to-floor contact"),
    # B/1 at 4.5 m is above A's first storey (0 to 3 m), even with an at
    ({"nodes": ["A/1", "B/1"], "column": "left", "at": 0.5}, "(it is above it)"),
    ({"nodes": ["A/2", "B/2"], "at": 0.5}, "at is where a column is struck: give column"),
    ({"nodes": ["A/2", "B/2"], "shear_capacity": 1e5}, "shear_capacity is a struck column's"),
])
def test_impossible_floor_to_column_pairings_are_refused(contact, says):
    from pframe.reader import parse_scene

    with pytest.raises(InputError, match=re.escape(says)):
        _ = parse_scene(_offset_pair(contact)).expanded


def test_the_example(tmp_path):
    """models/floor-to-column.yaml: floors and columns pound, the balance closes, its columns
    hold (no warning: the example solves cleanly), and with columns half as strong those the
    impacts overload are named."""
    from pframe.assemble import assemble
    from pframe.kernel import simulate
    from pframe.reader import load_scene
    from pframe.verdict import of_result

    record_file("elCentro.AT2")
    loaded = load_scene(runnable_model(REPO / "models" / "floor-to-column.yaml", tmp_path))
    plan = assemble(loaded.expanded)
    result = simulate(plan)
    assert result.completed(0) and result.energy_error(0) < 1e-10
    assert int(result.impacts[0].sum()) >= 5
    shear = result.column_shear(0)
    assert np.all(shear[np.isfinite(shear)] < plan.contact_capacity[np.isfinite(shear)])
    assert not [w for w in of_result(result).warnings if "shear capacity" in w]
    # columns half as strong: those the impacts overload are named, and only those
    import dataclasses

    weaker = dataclasses.replace(result, plan=dataclasses.replace(
        plan, contact_capacity=plan.contact_capacity / 2))
    over = [w for w in of_result(weaker).warnings if "shear capacity" in w]
    assert len(over) == int(np.sum(shear > plan.contact_capacity / 2)) >= 1


@pytest.fixture(scope="module")
def example_file(tmp_path_factory):
    """models/floor-to-column.yaml solved to a file (displacement and contact_force
    histories at every step)."""
    from pframe.cli import main

    folder = tmp_path_factory.mktemp("f2c")
    record_file("elCentro.AT2")
    out = folder / "f2c.nc"
    model = runnable_model(REPO / "models" / "floor-to-column.yaml", folder)
    assert main(["solve", str(model), "-o", str(out), "-q"]) == 0
    return out


@pytest.mark.slow
def test_the_file_holds_each_impacts_column_shear(example_file):
    """The file (as the Dataset) holds where each column is struck and its shear: per
    contact the peak over the run, max(psi, 1 - psi) times the peak contact force, and per
    impact the same of that impact's peak (every impact the run counted, read back from the
    force history independently here); the summary lists both."""
    import pframe

    with pframe.open(example_file) as ds:
        ds = ds.load()
    side = {c: str(v) for c, v in zip(ds.contact.values, ds.contact_column.values)}
    assert side["A2-column-B2"] == "right" and side["B1-column-A2"] == "left"
    assert str(ds.contact_column_lower.sel(contact="B1-column-A2").values) == "A/1"
    np.testing.assert_array_equal(ds.contact_at.values, 0.5)  # from the storey heights
    weight = max(_psi(0.5), 1 - _psi(0.5))
    np.testing.assert_allclose(ds.peak_column_shear.values,
                               weight * ds.peak_contact_force.values, rtol=1e-15)
    assert ds.peak_column_shear.attrs["units"] == "N" and ds.impact_column_shear.attrs["units"] == "N"
    expected = []
    for contact in ds.contact.values:
        force = ds.contact_force.sel(contact=contact).values
        closed = np.flatnonzero(force > 0)
        for run in np.split(closed, np.flatnonzero(np.diff(closed) > 1) + 1) if closed.size else []:
            k = run[np.argmax(force[run])]
            expected.append((float(ds.t[k]), str(contact), weight * force[k]))
    expected.sort()
    assert len(expected) == int(ds.impact_count.sum()) == ds.sizes["impact"] == 13
    assert [str(c) for c in ds.impact_contact.values] == [c for _, c, _ in expected]
    np.testing.assert_array_equal(ds.impact_time.values, [t for t, _, _ in expected])
    np.testing.assert_allclose(ds.impact_column_shear.values, [v for *_, v in expected],
                               rtol=1e-15)
    table = pframe.summary(example_file)
    peak = table[(table.part == "contact") & (table.quantity == "peak column shear")]
    assert len(peak) == 7 and peak.value.max() == pytest.approx(ds.peak_column_shear.max())
    shears = table[(table.part == "impact") & (table.quantity == "column shear")]
    assert sorted(shears.value) == pytest.approx(sorted(v for *_, v in expected), rel=1e-12)


@pytest.mark.slow
def test_the_pounding_figure_follows_the_struck_point(example_file):
    """The gap closing of a floor-to-column contact is that of the floor and the struck point
    of the column, psi u_upper + (1 - psi) u_lower: its impacts are the run's (the named
    nodes' closing counted 3 where the run counted 0 at B2-column-A3, and 8 where it counted
    7 at B4-column-A5)."""
    import pframe
    from pframe.plot import figures

    with pframe.open(example_file) as ds:
        ds = ds.load()
    drawn = set()
    for fig in figures(example_file, kind="pounding").values():
        for ax in fig.axes:
            if not ax.get_label().startswith("gap "):
                continue
            contact = ax.get_label()[len("gap "):]
            c = ds.sel(contact=contact)
            floor, upper, lower = (str(c.contact_left.values), str(c.contact_right.values),
                                   str(c.contact_column_lower.values))
            if str(c.contact_column.values) == "left":
                floor, upper = upper, floor
            psi = _psi(float(c.contact_at))
            point = psi * ds.displacement.sel(node=upper) + (1 - psi) * (
                ds.displacement.sel(node=lower) if lower != "ground" else 0.0)
            sign = 1.0 if str(c.contact_column.values) == "right" else -1.0
            expected = sign * (ds.displacement.sel(node=floor) - point).values
            line = next(ln for ln in ax.get_lines() if ln.get_label() == "relative")
            np.testing.assert_allclose(line.get_ydata(), expected, rtol=1e-12, atol=1e-15)
            impacts = next(ln for ln in ax.get_lines() if ln.get_label() == "impacts")
            assert len(impacts.get_xdata()) == int(c.impact_count)
            assert "the run counted" not in ax.get_title(loc="left")
            drawn.add(contact)
    assert len(drawn) == 7  # each at both its levels
