"""Buildings drawn at their heights (``pframe animate``): floors at the elevations the scene's
storey heights give, floor-to-column contacts at their point on the struck column, and the old
layout (floor numbers) when a storey has no height. The page's geometry is evaluated with node
(outside a browser), as tests/test_animate.py does."""

from __future__ import annotations

import json
import re

import numpy as np
import pytest
from conftest import page_layout

import pframe
from pframe.cli import main
from pframe.plot.animate import animation_data

A_HEIGHTS = [3.0] * 5
B_HEIGHTS = [5.1, 3.0, 3.0, 3.0]
AT = 0.3
#: where each side's columns are struck: B's floors stand 0.7 up A's storeys, A's 0.3 up B's
AT_OF = {"right": AT, "left": 1.0 - AT}


def _scene(heights: bool = True) -> str:
    """models/floor-to-column.yaml's pair, with B's floors raised to 0.7 of A's storeys (A's
    at 0.3 of B's) under a sine: each contact struck at AT_OF its column side (as its
    heights give it: a contradicting at is refused)."""
    story = {"material": "elastic", "stiffness": 3.0e7}
    a = {"name": "A", "floors": 5, "mass": 3.0e4, "story": story}
    b = {"name": "B", "floors": 4, "mass": 3.0e4, "story": story}
    if heights:
        a["height"], b["height"] = A_HEIGHTS, B_HEIGHTS
    contacts = [{"name": f"A{i}-column-B{i}", "nodes": [f"A/{i}", f"B/{i}"], "gap": 0.002,
                 "law": "linear", "stiffness": 1.0e9, "column": "right", "at": AT_OF["right"]}
                for i in (2, 3, 4)]
    contacts += [{"name": f"B{i}-column-A{i + 1}", "nodes": [f"A/{i + 1}", f"B/{i}"],
                  "gap": 0.002, "law": "linear", "stiffness": 1.0e9, "column": "left",
                  "at": AT_OF["left"]} for i in (1, 2, 3)]
    return json.dumps({
        "buildings": [a, b], "contacts": contacts, "damping": {"ratio": 0.05},
        "excitation": {"kind": "sine", "amplitude": 4.0, "frequency": 1.5, "cycles": 3},
        "analysis": {"dt": 0.002, "duration": 2.0},
        "recorders": [{"kind": "history", "quantities": ["displacement", "contact_force"]}]})


@pytest.fixture(scope="module")
def run(tmp_path_factory):
    folder = tmp_path_factory.mktemp("heights")
    out = {}
    for heights in (True, False):
        scene = folder / f"ftc-{heights}.yaml"
        scene.write_text(_scene(heights), encoding="utf-8")
        result = folder / f"ftc-{heights}.nc"
        assert main(["solve", str(scene), "-o", str(result), "-q"]) == 0
        assert main(["animate", str(result), "-q"]) == 0
        out[heights] = result
    return out


def _elevations():
    return {**{f"A/{i + 1}": z for i, z in enumerate(np.cumsum(A_HEIGHTS))},
            **{f"B/{i + 1}": z for i, z in enumerate(np.cumsum(B_HEIGHTS))}}


@pytest.mark.slow
def test_floors_stand_at_their_elevations_and_contacts_at_their_column_point(run):
    """Each floor's drawn height is the sum of the storey heights below it; each
    floor-to-column contact's column end is its at of the way up the struck storey, the
    striking floor's own elevation."""
    with pframe.open(run[True]) as ds:
        data = animation_data(ds)
    elevation = _elevations()
    assert {f["node"]: f["height"] for f in data["floors"]} == pytest.approx(elevation)
    assert data["elevations"] and "elevations" in data["placement"]
    floors = [f["node"] for f in data["floors"]]
    for c in data["contacts"]:
        striking, struck = re.match(r"([AB])(\d)-column-([AB])(\d)", c["name"]).group(1, 3)
        upper = c["name"].split("-")[-1]
        upper = f"{upper[0]}/{upper[1]}"
        lower = f"{upper[0]}/{int(upper[2]) - 1}"
        bottom = elevation.get(lower, 0.0)
        at = AT_OF[c["column"]["side"]]
        assert c["column"]["y"] == pytest.approx(bottom + at * (elevation[upper] - bottom))
        assert c["column"]["y"] == pytest.approx(elevation[f"{striking}/{c['name'][1]}"])
        assert c["column"]["side"] == ("right" if struck == "B" else "left")
        assert c["column"]["lower"] == (floors.index(lower) if lower in floors else -1)
        assert c["column"]["share"] == pytest.approx(at * at * (3 - 2 * at))
        assert striking != struck


def _layout(html, frames):
    return page_layout(html, frames)


@pytest.mark.slow
def test_the_page_draws_contacts_from_the_floor_to_the_column_point(run):
    """The page's geometry (node): a contact's floor end is the floor, its column end at the
    point's elevation, shifted by the run's displacement of that point (the struck storey's
    floors weighted as the contact weighs them)."""
    html = run[True].with_suffix(".html")
    data = json.loads(re.search(r'<script id="pframe-data" type="application/json">(.*?)'
                                r'</script>', html.read_text(encoding="utf-8"), re.S).group(1))
    frames = list(range(0, len(data["time"]), 97))
    drawn = _layout(html, frames)
    elevation = _elevations()
    with pframe.open(run[True]) as ds:
        t = ds.t.values
        u = ds.displacement.values
        nodes = ds.node.values.tolist()
    for k, g in zip(frames, drawn):
        row = int(np.searchsorted(t, data["time"][k]))
        for c, contact in zip(data["contacts"], g["contacts"]):
            column = contact["to"] if c["column"]["side"] == "right" else contact["from"]
            floor = contact["from"] if c["column"]["side"] == "right" else contact["to"]
            upper = column["node"]
            lower = f"{upper[0]}/{int(upper[2:]) - 1}"
            low = u[row, nodes.index(lower)] if lower in nodes else 0.0
            base = next(b["base"] for b in data["buildings"] if b["name"] == upper[0])
            at = AT_OF[c["column"]["side"]]
            share = at * at * (3 - 2 * at)
            point = share * u[row, nodes.index(upper)] + (1 - share) * low
            assert column["left"] == pytest.approx(base + data["scale"] * point,
                                                   rel=1e-5, abs=1e-6)
            bottom = elevation.get(lower, 0.0)
            assert column["y"] == pytest.approx(bottom + at * (elevation[upper] - bottom))
            assert floor["y"] == pytest.approx(elevation[floor["node"]])


@pytest.mark.slow
def test_without_heights_floors_stand_at_their_numbers(run):
    """A scene without storey heights: the old layout (floor numbers), and the page says why;
    contacts join their floors."""
    with pframe.open(run[False]) as ds:
        data = animation_data(ds)
    assert [f["height"] for f in data["floors"]] == [1, 2, 3, 4, 5, 1, 2, 3, 4]
    assert not data["elevations"] and "floor numbers" in data["placement"]
    assert all("column" not in c for c in data["contacts"])
    assert "floor numbers" in run[False].with_suffix(".html").read_text(encoding="utf-8")
