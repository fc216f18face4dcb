"""The player of ``pframe animate``'s page: one self-contained HTML page (no script, font or
file loaded from elsewhere) with play, pause, a time slider, a speed choice, ``#t=<time>`` to
open at a time and ``&frame`` to put the drawn frame in the page as a PNG (headless browsers
dump the DOM), around a view: a script that defines ``draw(k)`` (the elevation view of
:mod:`pframe.plot.animate`, the plan view of :mod:`pframe.plot.plan_view`)."""

from __future__ import annotations

import html
import json

PAGE = """<!DOCTYPE html>
<html lang="en"><head><meta charset="utf-8">
<title>{title}</title>
<style>
body {{ font-family: sans-serif; margin: 1em; }}
#controls {{ display: flex; gap: 0.8em; align-items: center; margin: 0.5em 0; }}
#slider {{ flex: 1; }}
canvas {{ border: 1px solid #ccc; max-width: 100%; }}
.note {{ color: #555; font-size: small; }}
</style></head>
<body>
<h2>{heading}</h2>
<div class="note">{note}</div>
<div id="controls">
<button id="play" type="button">Play</button>
<input id="slider" type="range" min="0" max="{last}" value="0" step="1" aria-label="time">
<span id="clock"></span>
<label>speed <select id="speed">
<option value="0.1">0.1 x</option><option value="0.25">0.25 x</option>
<option value="0.5">0.5 x</option><option value="1" selected>1 x</option>
<option value="2">2 x</option><option value="5">5 x</option></select></label>{controls}
</div>
<canvas id="view" width="900" height="{height}"></canvas>
<script id="pframe-data" type="application/json">{data}</script>
<script id="pframe-geometry">{geometry}</script>
<script>
const data = JSON.parse(document.getElementById("pframe-data").textContent);
const canvas = document.getElementById("view"), ctx = canvas.getContext("2d");
const slider = document.getElementById("slider"), clock = document.getElementById("clock");
const button = document.getElementById("play"), speed = document.getElementById("speed");
let frame = 0, playing = false, last = null;
{view}
function tick(now) {{
  if (!playing) return;
  if (last !== null) {{
    const target = data.time[frame] + (now - last) / 1000 * parseFloat(speed.value);
    let k = frame;
    while (k < data.time.length - 1 && data.time[k + 1] <= target) k++;
    if (k === data.time.length - 1) {{ playing = false; button.textContent = "Play"; }}
    if (k !== frame) {{ draw(k); last = now; }}
  }} else {{ last = now; }}
  requestAnimationFrame(tick);
}}
button.onclick = () => {{
  playing = !playing; button.textContent = playing ? "Pause" : "Play"; last = null;
  if (playing && frame === data.time.length - 1) draw(0);
  if (playing) requestAnimationFrame(tick);
}};
slider.oninput = () => draw(parseInt(slider.value));
// a page opened with #t=<time> shows that time (tests and links)
const asked = /t=([0-9.eE+-]+)/.exec(location.hash);
let start = 0;
if (asked) {{ const t = parseFloat(asked[1]);
  while (start < data.time.length - 1 && data.time[start + 1] <= t) start++; }}
draw(start);
// #t=<time>&frame: the drawn frame as a PNG in the page (headless browsers dump the DOM)
if (/frame/.test(location.hash)) {{
  const img = document.createElement("img"); img.id = "pframe-frame";
  img.src = canvas.toDataURL("image/png"); document.body.appendChild(img);
}}
</script>
</body></html>
"""


def page(data: dict, title: str, note: str, geometry: str, view: str, controls: str = "",
         height: int = 560) -> str:
    """The page's HTML: its player (play, pause, time slider, speed, ``#t=<time>`` and
    ``&frame``) around a view, the script that defines ``draw(k)`` with the page's pure
    ``geometry``; ``controls`` are the view's own (HTML)."""
    text = json.dumps(data, separators=(",", ":")).replace("</", "<\\/")
    return PAGE.format(title=html.escape(f"pframe animate: {title}"),
                       heading=html.escape(title), note=html.escape(note),
                       last=len(data["time"]) - 1, data=text, geometry=geometry,
                       view=view, controls=controls, height=height)
