"""A run that loses definiteness names the element that made it so: the storey whose P-delta
load P / h exceeds its stiffness (its tangent k - P / h is negative beyond what the mass term
M / (beta dt^2) holds), wherever it stands in the scene and in the band order, not the node of
whichever pivot failed first (generated: each storey of a row of buildings in turn)."""

from __future__ import annotations

import pytest

from pframe.assemble import assemble
from pframe.kernel import simulate
from pframe.kernel.state import Kind, Status, StatusColumn
from pframe.reader import parse_scene

BUILDINGS = {"A": 3, "B": 2, "C": 3}
STOREYS = [f"{b}/{i}" for b, n in BUILDINGS.items() for i in range(1, n + 1)]


def _scene(weak: str) -> str:
    nodes, stories = [], []
    for building, floors in BUILDINGS.items():
        for i in range(1, floors + 1):
            name = f"{building}/{i}"
            lower = "ground" if i == 1 else f"{building}/{i - 1}"
            nodes.append(f"  - {{name: {name}, mass: 1000.0}}")
            # P / h = 1e12 N/m against k = 1e6 N/m and M / (beta dt^2) = 4e7 N/m
            load = ", height: 1.0, gravity_load: 1.0e12" if name == weak else ""
            stories.append(f"  - {{nodes: [{lower}, {name}], material: elastic, "
                           f"stiffness: 1.0e6{load}}}")
    return "\n".join([
        "nodes:", *nodes, "stories:", *stories,
        "links:", "  - {nodes: [A/3, C/1], material: elastic, stiffness: 1.0e5}",
        "excitation: {kind: sine, amplitude: 1.0, frequency: 6.0}",
        "analysis: {dt: 0.01, duration: 0.1}"])


@pytest.mark.parametrize("weak", STOREYS)
def test_the_storey_with_a_negative_tangent_is_named(weak):
    plan = assemble(parse_scene(_scene(weak)).expanded)
    result = simulate(plan)
    status = result.status[0]
    assert status[StatusColumn.CODE] == Status.NOT_DEFINITE
    assert status[StatusColumn.KIND] == Kind.STORY
    assert plan.story_names[status[StatusColumn.INDEX]] == weak
    assert result.describe_failure().endswith(f"at storey {weak}")
    assert "negative tangent" in result.describe_failure()
