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
