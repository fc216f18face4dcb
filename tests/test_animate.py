"""``pframe animate``: one self-contained HTML page whose drawing is the file's: every floor
displaced by its recorded displacement at the page's one scale, a contact lit exactly while
its force is positive, and then drawn touching (penetration > 0 on the page too). The
geometry is evaluated with node (outside a browser); the rendering in headless Chromium."""

from __future__ import annotations

import base64
import json
import re
import shutil
import subprocess
from pathlib import Path

import numpy as np
import pytest
from conftest import page_layout

import pframe
from pframe.cli import main

MODELS = Path(__file__).resolve().parents[1] / "models"


@pytest.fixture(scope="module")
def page(tmp_path_factory):
    folder = tmp_path_factory.mktemp("animate")
    run = folder / "eq14.nc"
    assert main(["solve", str(MODELS / "wu2021-eq14.yaml"), "-o", str(run), "-q"]) == 0
    assert main(["animate", str(run), "-q"]) == 0
    assert main(["animate", str(run), "-q"]) == 2  # an existing page: --overwrite replaces it
    assert main(["animate", str(run), "-q", "--overwrite"]) == 0
    return run, run.with_suffix(".html")


def _data(text: str) -> dict:
    found = re.search(r'<script id="pframe-data" type="application/json">(.*?)</script>',
                      text, re.S)
    return json.loads(found.group(1))


@pytest.mark.slow
def test_the_page_is_self_contained_and_holds_the_run(page):
    run, html = page
    text = html.read_text(encoding="utf-8")
    assert not re.search(r'(src|href)="(https?:)?//', text)  # nothing loaded from elsewhere
    for control in ('id="play"', 'id="slider"', 'id="speed"', "<canvas"):
        assert control in text
    data = _data(text)
    with pframe.open(run) as ds:
        assert len(data["time"]) <= 2000 and data["time"][0] == 0.0
        assert data["time"][-1] == pytest.approx(float(ds.t[-1]), rel=1e-12)
        assert [f["node"] for f in data["floors"]] == ds.node.values.tolist()
        assert [f["height"] for f in data["floors"]] == [1, 2, 3, 1, 2, 3]
        # building B stands beside A at the smallest contact gap, at the page's scale
        assert data["buildings"][1]["base"] == pytest.approx(
            1.0 + data["scale"] * float(ds.contact_gap.min()), rel=1e-12)


def _layout(html, frames):
    return page_layout(html, frames)


@pytest.mark.slow
def test_the_drawing_is_the_files_displacements_and_contacts(page):
    run, html = page
    data = _data(html.read_text(encoding="utf-8"))
    times = np.array(data["time"])
    frames = list(range(0, len(times), 7))
    drawn = _layout(html, frames)
    with pframe.open(run) as ds:
        t = ds.t.values
        u = ds.displacement.values
        force = ds.contact_force.values
        gap = ds.contact_gap.values
        left = [ds.node.values.tolist().index(n) for n in ds.contact_left.values]
        right = [ds.node.values.tolist().index(n) for n in ds.contact_right.values]
    closed_frames = 0
    for k, g in zip(frames, drawn):
        row = int(np.searchsorted(t, times[k]))
        assert t[row] == times[k]
        for f, floor in zip(data["floors"], g["floors"]):
            assert floor["left"] == pytest.approx(f["base"] + data["scale"] * u[row, f["index"]],
                                                  rel=1e-5, abs=1e-9)
        for c, contact in enumerate(g["contacts"]):
            assert contact["closed"] == bool(force[row, c] > 0)
            if contact["closed"]:  # the floors overlap on the page as they penetrate in the run
                closed_frames += 1
                penetration = u[row, left[c]] - u[row, right[c]] - gap[c]
                assert penetration > 0
                # (the page keeps 6 digits of each displacement)
                assert contact["from"]["right"] - contact["to"]["left"] == pytest.approx(
                    data["scale"] * penetration, abs=data["scale"] * 2e-6)
    assert closed_frames > 0  # the paper's run pounds: the page shows it


def _chromium() -> str:
    for name in ("chromium", "chromium-browser", "google-chrome", "chrome"):
        found = shutil.which(name)
        if found:
            return found
    pytest.skip("no Chromium: the page is not rendered (apt-get install chromium)")


@pytest.mark.slow
def test_headless_chromium_draws_the_floors_where_the_file_says(page, tmp_path):
    """The page opened at a known time (``#t=...``) in headless Chromium: the canvas it drew
    has building A's colour at the middle of the A/3 slab where the file puts it, and not
    where the floor stands at rest."""
    from PIL import Image

    run, html = page
    data = _data(html.read_text(encoding="utf-8"))
    with pframe.open(run) as ds:
        u_top = ds.displacement.sel(node="A/3")
        k = int(np.argmax(np.abs(np.interp(data["time"], ds.t.values, u_top.values))))
        at = data["time"][k]
        u = float(u_top.sel(t=at))
    done = subprocess.run([_chromium(), "--headless", "--no-sandbox", "--disable-gpu",
                           "--allow-file-access-from-files", f"--user-data-dir={tmp_path}",
                           "--dump-dom", f"{html.as_uri()}#t={at!r}&frame"],
                          capture_output=True, text=True, timeout=120)
    found = re.search(r'id="pframe-frame" src="data:image/png;base64,([^"]+)"', done.stdout)
    assert found, done.stderr[-2000:]
    png = tmp_path / "frame.png"
    png.write_bytes(base64.b64decode(found.group(1)))
    image = np.asarray(Image.open(png).convert("RGB")).astype(int)
    height, width = image.shape[:2]
    bases = [b["base"] for b in data["buildings"]]
    xmin, xmax = min(bases) - 1.0, max(bases) + data["width"] + 1.0
    highest = max(f["height"] for f in data["floors"])
    sx, sy = width / (xmax - xmin), (height - 60) / (highest + 0.6)

    def pixel(x, y):
        return image[int(round(height - 30 - y * sy)), int(round((x - xmin) * sx))]

    blue = np.array([0x1F, 0x77, 0xB4])
    middle = data["width"] / 2
    assert np.abs(pixel(middle + data["scale"] * u, 3) - blue).max() < 40
    assert data["scale"] * abs(u) > 0.2  # far enough from rest to tell the two apart
    assert np.abs(pixel(middle + data["scale"] * u + np.sign(u) * 0.6, 3) - blue).max() > 60


# --- a scene in plan: the plan view --------------------------------------------------------

from test_plot_plan import (  # noqa: E402
    ENVELOPES_ONLY,
    GAP,
    SCENE,
    WITHOUT_PLAN,
    small_rotation_closing,
)


@pytest.fixture(scope="module")
def plan_page(tmp_path_factory):
    folder = tmp_path_factory.mktemp("animate-plan")
    scene = folder / "plan.yaml"
    scene.write_text(SCENE, encoding="utf-8")
    run = folder / "plan.nc"
    assert main(["solve", str(scene), "-o", str(run), "-q"]) == 0
    assert main(["animate", str(run), "-q"]) == 0
    return run, run.with_suffix(".html")


def _evaluate(html, expression: str):
    """``expression`` evaluated in node with the page's data and geometry (``data``,
    ``planLayout``, ``planView``): what the page draws, read without a browser."""
    node = shutil.which("node")
    if node is None:
        pytest.skip("node is not installed: the page's geometry is checked with node")
    script = ("const fs = require('fs'); const t = fs.readFileSync(process.argv[1], 'utf8');"
              "const data = JSON.parse(/<script id=\"pframe-data\" type=\"application\\/json\">"
              "([\\s\\S]*?)<\\/script>/.exec(t)[1]);"
              "eval(/<script id=\"pframe-geometry\">([\\s\\S]*?)<\\/script>/.exec(t)[1]);"
              f"console.log(JSON.stringify({expression}));")
    done = subprocess.run([node, "-e", script, str(html)], capture_output=True, text=True,
                          timeout=60)
    assert done.returncode == 0, done.stderr
    return json.loads(done.stdout)


@pytest.mark.slow
def test_a_result_in_plan_gets_a_plan_view_with_its_controls(plan_page):
    """Before: TypeError (a displacement per direction formatted as a number)."""
    run, html = plan_page
    text = html.read_text(encoding="utf-8")
    assert not re.search(r'(src|href)="(https?:)?//', text)
    for control in ('id="play"', 'id="slider"', 'id="speed"', 'id="level"', 'id="magnify"',
                    "<canvas"):
        assert control in text
    data = _data(text)
    assert data["levels"] == ["1", "2", "3"] and data["level"] == "2"  # top level that pounds
    assert [f["node"] for f in data["floors"]] == ["A/1", "A/2", "A/3", "B/1", "B/2"]
    # the default magnification draws the largest motion of a corner about 8 % of the site
    assert data["magnify"] in (1, 2, 5, 10, 20, 50, 100, 200, 500)
    assert f"default {data['magnify']:g} times" in text


@pytest.mark.slow
def test_the_plan_view_moves_each_floor_as_its_recorded_motion(plan_page):
    """Each outline is its floor's plan moved as a rigid body by M (u_x, u_y) and turned by
    M theta about its centre of mass; at M = 1 the contact's two points close along the
    normal by what the run's contact closed (its gap is their distance at rest), to the
    small-rotation error; a contact is lit exactly while its force is positive."""
    run, html = plan_page
    data = _data(html.read_text(encoding="utf-8"))
    frames = list(range(0, len(data["time"]), 9))
    layouts = {m: _evaluate(html, f"{json.dumps(frames)}.map(k => planLayout(data, k, '2', "
                                  f"{m}))") for m in (1.0, data["magnify"])}
    with pframe.open(run) as ds:
        t = ds.t.values
        u = ds.displacement.sel(node=["A/2", "B/2"]).values
        theta = ds.displacement_rz.sel(node=["A/2", "B/2"]).values
        force = ds.contact_force.sel(contact="c2").values
        centres = np.stack([ds.node_x.sel(node=["A/2", "B/2"]).values,
                            ds.node_y.sel(node=["A/2", "B/2"]).values], axis=1)
        closing = small_rotation_closing(ds, "A/2", "B/2")
    rest = {f["node"]: np.array(f["outline"]) for f in data["floors"]}
    closed_frames = 0
    for m, layouts_m in layouts.items():
        for k, g in zip(frames, layouts_m):
            row = int(np.searchsorted(t, data["time"][k]))
            assert t[row] == data["time"][k]
            assert [f["node"] for f in g["floors"]] == ["A/2", "B/2"]
            for j, floor in enumerate(g["floors"]):
                np.testing.assert_allclose(floor["centre"], centres[j] + m * u[row, j],
                                           rtol=0, atol=m * 1e-6 * (1 + abs(u[row, j]).max()))
                a = m * theta[row, j]
                turn = np.array([[np.cos(a), -np.sin(a)], [np.sin(a), np.cos(a)]])
                expected = centres[j] + m * u[row, j] + (rest[floor["node"]] - centres[j]) @ turn.T
                np.testing.assert_allclose(floor["outline"], expected, atol=1e-5 * m + 1e-9)
            (contact,) = g["contacts"]
            assert contact["name"] == "c2"
            assert contact["closed"] == bool(force[row] > 0)
            if m == 1.0:  # along n = (1, 0): A's point less B's, -GAP at rest
                drawn = contact["points"][0][0] - contact["points"][1][0]
                assert drawn == pytest.approx(closing[row] - GAP, abs=2e-5)
                closed_frames += contact["closed"]
    assert closed_frames > 0  # the scene pounds at level 2: the page shows it


@pytest.mark.slow
def test_headless_chromium_lights_the_contact_at_an_impact(plan_page, tmp_path):
    """The page opened at the strongest impact of c2, level 2, in headless Chromium: the
    canvas is red where the page puts the contact's point; at rest it is not."""
    from PIL import Image

    run, html = plan_page
    data = _data(html.read_text(encoding="utf-8"))
    with pframe.open(run) as ds:
        force = np.interp(data["time"], ds.t.values, ds.contact_force.sel(contact="c2").values)
    k = int(np.argmax(force))
    red = np.array([0xD6, 0x27, 0x28])
    for frame, lit in ((k, True), (0, False)):
        at = data["time"][frame]
        where = _evaluate(html, f"(() => {{ const v = planView(data, 900, 640); const g = "
                                f"planLayout(data, {frame}, '2', data.magnify); return g."
                                "contacts[0].points.map(p => [v.x(p[0]), v.y(p[1])]); })()")
        done = subprocess.run([_chromium(), "--headless", "--no-sandbox", "--disable-gpu",
                               "--allow-file-access-from-files", f"--user-data-dir={tmp_path}",
                               "--dump-dom", f"{html.as_uri()}#t={at!r}&level=2&frame"],
                              capture_output=True, text=True, timeout=120)
        found = re.search(r'id="pframe-frame" src="data:image/png;base64,([^"]+)"', done.stdout)
        assert found, done.stderr[-2000:]
        png = tmp_path / f"frame-{frame}.png"
        png.write_bytes(base64.b64decode(found.group(1)))
        image = np.asarray(Image.open(png).convert("RGB")).astype(int)
        assert image.shape[:2] == (640, 900)
        for x, y in where:
            colour = image[int(round(y)), int(round(x))]
            assert (np.abs(colour - red).max() < 40) == lit, (frame, colour)


@pytest.mark.slow
@pytest.mark.parametrize(("text", "message"), [
    (ENVELOPES_ONLY, "the result holds no displacement history to animate; add displacement "
     "to a 'kind: history' recorder"),
    (WITHOUT_PLAN, "the plan view draws each floor's outline, and no building of the scene "
     "has a plan"),
], ids=["no-history", "no-plan"])
def test_a_result_in_plan_the_view_cannot_draw_is_refused(tmp_path, capsys, text, message):
    scene = tmp_path / "lacking.yaml"
    scene.write_text(text, encoding="utf-8")
    run = tmp_path / "lacking.nc"
    assert main(["solve", str(scene), "-o", str(run), "-q"]) == 0
    assert main(["animate", str(run)]) == 2
    err = capsys.readouterr().err
    assert err.startswith(f"pframe: {run}: ") and message in err
    assert "Traceback" not in err and not run.with_suffix(".html").exists()
