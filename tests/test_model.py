"""pframe.model: what a scene file becomes (definitions and their resolution to elements),
and where its mistakes are reported."""

from __future__ import annotations

import pytest

from pframe.errors import InputError
from pframe.model.scene import scene_class
from pframe.reader import parse_scene

SCENE = """\
buildings:
  - name: A
    floors: 3
    mass: [300.0, 200.0, 100.0]
    story: {material: elastic, stiffness: [3.0e5, 2.0e5, 1.0e5]}
  - {name: B, floors: 2, mass: 500.0, story: {material: elastic, stiffness: 1.0e6}}
nodes:
  - {name: C/1, mass: 50.0}
stories:
  - {nodes: [ground, C/1], material: elastic, stiffness: 4.0e4, name: column}
contacts:
  - {nodes: [A/2, B/2], gap: 0.01, law: linear, stiffness: 1.0e7}
  - {name: roof, nodes: [B/2, C/1], gap: 0.02, law: linear, stiffness: 1.0e7}
analysis: {dt: 0.01, duration: 1.0}
"""


def test_building_shorthand_and_generic_elements_resolve_in_declaration_order():
    ex = parse_scene(SCENE).expanded
    assert ex.node_names == ("A/1", "A/2", "A/3", "B/1", "B/2", "C/1")
    assert ex.masses.tolist() == [300.0, 200.0, 100.0, 500.0, 500.0, 50.0]
    names = [s.name for s in ex.stories]
    assert names == ["A/1", "A/2", "A/3", "B/1", "B/2", "column"]
    # storey i of a building joins floor i - 1 (the ground for the first) and floor i
    assert [s.nodes for s in ex.stories] == [(-1, 0), (0, 1), (1, 2), (-1, 3), (3, 4), (-1, 5)]
    assert [s.packed[0] for s in ex.stories[:3]] == [3.0e5, 2.0e5, 1.0e5]
    assert [c.name for c in ex.contacts] == ["A/2-B/2", "roof"]  # default <left>-<right>
    assert [c.nodes for c in ex.contacts] == [(1, 4), (4, 5)]
    assert ex.node_building.tolist() == [0, 0, 0, 1, 1, 2]


@pytest.mark.parametrize(("change", "where", "what"), [
    (("mass: 500.0", "mass: [500.0]"), "line 6, buildings[1].mass",
     "expected one value per storey (2), got 1"),
    (("nodes: [A/2, B/2]", "nodes: [A/2, X/2]"), "line 12, contacts[0]", "X/2"),
    (("{name: B, floors: 2", "{name: A, floors: 2"), "buildings[1].name", "defined twice"),
    (("stiffness: 4.0e4", "stiffness: -4.0e4"), "line 10, stories[0]", "greater than 0"),
], ids=["per-storey-length", "unknown-node", "duplicate-building", "negative-stiffness"])
def test_mistakes_are_reported_at_their_line_and_field(change, where, what):
    text = SCENE.replace(*change)
    assert text != SCENE
    with pytest.raises(InputError) as info:
        parse_scene(text, source="scene.yaml")
    message = str(info.value)
    assert message.startswith("scene.yaml, ") and where in message and what in message


def test_one_scene_class_per_set_of_laws():
    """However the plug-in law names are passed, the same laws give the same class (so the
    scenes of a file and of Python objects compare equal)."""
    assert scene_class() is scene_class((), ()) is scene_class(contact_laws=[])


ROW = """\
buildings:
  - {name: A, floors: 1, mass: 1000.0, story: {material: elastic, stiffness: 1.0e6}}
  - {name: B, floors: 1, mass: 1000.0, story: {material: elastic, stiffness: 2.0e6}}
  - {name: C, floors: 1, mass: 1000.0, story: {material: elastic, stiffness: 4.0e6}}
contacts:
  - {nodes: [A/1, B/1], gap: 0.01, law: linear, stiffness: 1.0e8}
  - {nodes: [B/1, C/1], gap: 0.01, law: linear, stiffness: 1.0e8}
initial_conditions: {velocity: {B/1: 1.0}}
analysis: {dt: 0.001, duration: 0.5}
"""


def test_a_contact_against_the_row_order_is_refused_at_its_line():
    """The buildings stand left to right in the order they are declared; a contact written
    [right, left] would close when its buildings move apart (the issue's row A, B, C with
    [C/1, B/1]: 5 impacts instead of 1), so it is refused, naming it and its line."""
    ex = parse_scene(ROW).expanded
    assert ex.buildings == ("A", "B", "C") and [c.name for c in ex.contacts] == [
        "A/1-B/1", "B/1-C/1"]
    text = ROW.replace("[B/1, C/1]", "[C/1, B/1]")
    with pytest.raises(InputError) as info:
        parse_scene(text, source="row.yaml")
    message = str(info.value)
    assert message.startswith("row.yaml, line 7, contacts[1].nodes: contact 'C/1-B/1'")
    assert "declares them (A, B, C)" in message and "write nodes [B/1, C/1]" in message
    # generic nodes follow the same rule: their buildings come after the shorthand's
    generic = ROW.replace("contacts:", "nodes:\n  - {name: D/1, mass: 10.0}\ncontacts:\n"
                          "  - {nodes: [D/1, C/1], gap: 0.01, law: linear, stiffness: 1.0e8}")
    with pytest.raises(InputError, match="contact 'D/1-C/1' has 'D/1' on the left of 'C/1'"):
        parse_scene(generic)


@pytest.mark.parametrize(("change", "message"), [
    ({"stories": [{"nodes": ["ground", "A/1"], "material": "elastic", "stiffness": 1e6}]},
     r"line \d+, nodes\[1\]\.name: node 'A/2': no storey, link with a stiffness or soil "
     r"holds it to the ground"),
    ({"stories": [{"nodes": ["A/1", "A/2"], "material": "elastic", "stiffness": 1e6}]},
     r"nodes\[0\]\.name: nodes 'A/1', 'A/2' \(joined to each other\): no storey, link with "
     r"a stiffness or soil holds them to the ground .* they would float, with no stiffness to "
     r"return them\. .* on each node if they are meant to be free bodies"),
    ({"links": [{"nodes": ["ground", "A/2"], "material": "viscous", "damping": 1e3}]},
     "nor a dashpot"),
])
def test_a_node_nothing_holds_is_refused(change, message):
    """A floor of a building with storeys that no storey (or stiff link, or soil) joins to
    the ground floats: refused at its line, naming it (it ran to 'completed' before)."""
    scene = {"nodes": [{"name": "A/1", "mass": 1e3}, {"name": "A/2", "mass": 1e3}],
             "stories": [{"nodes": ["ground", "A/1"], "material": "elastic",
                          "stiffness": 1e6}],
             "contacts": [{"nodes": ["A/2", "ground"], "gap": 0.1, "law": "linear",
                           "stiffness": 1e7}],
             "analysis": {"dt": 0.01, "duration": 0.1}} | change
    with pytest.raises(InputError, match=message):
        _load(scene)
    _load(scene | {"nodes": [node | {"free": True} for node in scene["nodes"]]})
    held = {"nodes": [{"name": "A/1", "mass": 1e3}, {"name": "A/2", "mass": 1e3}],
            "links": [{"nodes": ["ground", "A/1"], "material": "elastic", "stiffness": 1e5},
                      {"nodes": ["A/1", "A/2"], "material": "bilinear", "stiffness": 1e5,
                       "yield_drift": 0.01, "alpha": 0.1}],
            "stories": [{"nodes": ["ground", "A/1"], "material": "elastic", "stiffness": 1e6}],
            "analysis": {"dt": 0.01, "duration": 0.1}}
    _load(held)  # links with a stiffness hold a node


def test_free_masses_under_a_ground_motion_are_said_to_be_free():
    """Masses of a building without storeys are free bodies (two masses striking): silent in
    free vibration, warned under a ground motion (the ground moves under them), silent again
    when they say free: true."""
    scene = {"nodes": [{"name": "L/1", "mass": 1e3}, {"name": "R/1", "mass": 1e3}],
             "contacts": [{"nodes": ["L/1", "R/1"], "gap": 0.0, "law": "linear",
                           "stiffness": 1e7}],
             "damping": {"ratio": 0.0}, "analysis": {"dt": 0.01, "duration": 0.1}}
    assert not _load(scene).expanded.warnings
    shaken = scene | {"excitation": {"kind": "sine", "amplitude": 1.0, "frequency": 3.0}}
    warnings = _load(shaken).expanded.warnings
    assert any("nodes L/1, R/1: no storey" in w and "free bodies" in w for w in warnings)
    for node in shaken["nodes"]:
        node["free"] = True
    assert not _load(shaken).expanded.warnings


def _load(scene: dict):
    import json

    return parse_scene(json.dumps(scene))


PAIR = """\
buildings:
  - {name: A, floors: 3, mass: [300.0, 200.0, 100.0], story: {material: elastic, stiffness: 3.0e5}}
  - {name: B, floors: 2, mass: [500.0, 400.0], story: {material: elastic, stiffness: 1.0e6}}
contacts:
CONTACTS
analysis: {dt: 0.01, duration: 1.0}
"""


def _pair(contacts: list[str]) -> str:
    return PAIR.replace("CONTACTS", "\n".join(f"  - {c}" for c in contacts))


def test_a_contact_at_every_level_is_each_level_written_out():
    """[A, B] stands for a contact at every floor level both have (A/1-B/1, A/2-B/2: B has
    two), each with the shorthand's fields and its own impact mass; [A, ground] for a wall at
    each of A's floors; a name names the levels <name>/<k>. The same elements, packed
    numbers, warnings and notes as the contacts written out one by one."""
    law = "law: improved_kelvin, stiffness: 2.0e7, restitution: 0.5"
    short = parse_scene(_pair([f"{{nodes: [A, B], gap: 0.01, {law}}}",
                               f"{{name: moat, nodes: [A, ground], gap: 0.03, {law}}}"]))
    long = parse_scene(_pair(
        [f"{{nodes: [A/{k}, B/{k}], gap: 0.01, {law}}}" for k in (1, 2)]
        + [f"{{name: moat/{k}, nodes: [A/{k}, ground], gap: 0.03, {law}}}" for k in (1, 2, 3)]))
    a, b = short.expanded, long.expanded
    assert [c.name for c in a.contacts] == ["A/1-B/1", "A/2-B/2", "moat/1", "moat/2",
                                            "moat/3"]
    assert a.contacts == b.contacts
    assert a.contacts[0].packed != a.contacts[1].packed  # each level's impact mass
    assert a.warnings == b.warnings and a.notes == b.notes


@pytest.mark.parametrize("contact, says", [
    ("{nodes: [A, B/2], gap: 0.01, law: linear, stiffness: 1.0e7}",
     "names two buildings (or a building and 'ground'), not a building and a node"),
    ("{nodes: [A, C], gap: 0.01, law: linear, stiffness: 1.0e7}", "no building named 'C'"),
    ("{nodes: [A, B], gap: 0.01, law: linear, stiffness: 1.0e7, column: right, at: 0.5}",
     "a floor-to-column contact names its two nodes"),
    ("{nodes: [B, A], gap: 0.01, law: linear, stiffness: 1.0e7}", "on the left of"),
])
def test_a_bad_contact_at_every_level_is_named_at_its_line(contact, says):
    with pytest.raises(InputError, match="line 5, contacts\\[0\\]") as error:
        parse_scene(_pair([contact]), source="pair.yaml")
    assert says in str(error.value)


def test_a_contact_at_every_level_counts_its_levels_before_anything_is_built(monkeypatch):
    """The size check counts one contact per level of the shorter side: a pair of 20,001 and
    20,002 floors with [A, B] is 100,007 floors, storeys and contacts, refused at once
    (without PFRAME_MAX_FLOORS), as the same contacts written out would be."""
    monkeypatch.delenv("PFRAME_MAX_FLOORS", raising=False)
    text = (PAIR.replace("floors: 3, mass: [300.0, 200.0, 100.0]", "floors: 20001, mass: 300.0")
            .replace("floors: 2, mass: [500.0, 400.0]", "floors: 20002, mass: 500.0")
            .replace("CONTACTS", "  - {nodes: [A, B], gap: 0.01, law: linear, stiffness: 1.0e7}"))
    with pytest.raises(InputError, match="100,007 floors, storeys and contacts in all"):
        parse_scene(text)


def test_the_floating_node_check_labels_alike_with_either_graph_method(monkeypatch):
    """Small scenes label the graph of storeys and links by a union-find, large ones by
    scipy's connected components: the same partition of a random graph either way."""
    import importlib

    import numpy as np

    expand = importlib.import_module("pframe.model.expand")  # the module, not its function

    rng = np.random.default_rng(7)
    count = 400
    ends = rng.integers(0, count, size=(300, 2))
    small = expand.components(count, ends)
    monkeypatch.setattr(expand, "_GRAPH_LIBRARY_ABOVE", 0)
    large = expand.components(count, ends)
    pairs = rng.integers(0, count, size=(5000, 2))
    np.testing.assert_array_equal(small[pairs[:, 0]] == small[pairs[:, 1]],
                                  large[pairs[:, 0]] == large[pairs[:, 1]])
    assert len(set(small.tolist())) == len(set(large.tolist())) > 1
