"""The plan view of ``pframe animate`` for a scene in plan: the site from above, one floor
level at a time.

Each building's floor at the chosen level is drawn as its plan's outline on the site (its
``origin`` and ``angle``), moved as a rigid body by its floor's recorded motion: translated
by M (u_x, u_y) and turned by M theta about its centre of mass, M the page's displacement
magnification (the page states it; the reader may change it). The outline at rest is drawn
dashed beneath it. A contact is drawn at its point on each floor, moving with its floor, red
while its force is positive (closed). The site's axes, a scale bar and the outlines are at
true size and equal scale on both axes; only the motion is magnified, so two outlines drawn
overlapping are not in contact unless their contact is red.

The drawing is the pure function ``planLayout(data, frame, level, magnify)`` and the pixel
transform ``planView(data, width, height)`` in the page's script, which tests evaluate
outside a browser.
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np

from pframe.errors import InputError

#: the default magnification draws the largest motion of a floor's outline this fraction of
#: the site's extent (rounded down to 1, 2 or 5 times a power of ten)
MOTION = 0.08


def _nice(value: float) -> float:
    """The largest of 1, 2, 5 times a power of ten not above ``value`` (1 for none)."""
    if not value > 0 or not math.isfinite(value):
        return 1.0
    power = 10.0 ** math.floor(math.log10(value))
    return max(m * power for m in (1.0, 2.0, 5.0) if m * power <= value * (1 + 1e-12))


def _scene(ds):
    """The scene the result holds, its floors placed (pframe.model.floors): the outlines,
    placements and contact points are the scene's, not the file's."""
    from pframe.api import scene_of_attributes
    from pframe.model.floors import floors

    if "input_yaml" not in ds.attrs:
        raise InputError("the result holds no scene (no input_yaml attribute): the plan view "
                         "draws the floors' outlines from it; animate the file pframe solve "
                         "wrote, which holds its scene")
    try:
        loaded = scene_of_attributes(dict(ds.attrs), "the result", Path("."))
    except InputError as exc:
        raise InputError(f"the plan view draws the floors' outlines from the scene the result "
                         f"holds, and it cannot be read: {exc}") from None
    return loaded.scene, floors(loaded.scene)


def _contacts(scene, placed, nodes, names, force, pick) -> list[dict]:
    """Each contact of the file: the floors it joins (node index, -1 for the ground), its
    point on each (site, m) and whether it is closed at each frame (None: no force history)."""
    from pframe.model.scene import contact_levels

    by_name = {f.name: f for f in placed.nodes}
    defined = {name: (ends, c) for c in scene.contacts
               for ends, name in contact_levels(c, by_name.__contains__)}
    out = []
    for j, name in enumerate(names):
        if name not in defined:
            continue
        ends, contact = defined[name]
        refs = contact.points if contact.points is not None else (None, None)
        sides = []
        for node, ref in zip(ends, refs):
            if node == "ground" or node not in nodes:
                sides.append(None)
                continue
            point = by_name[node].point(ref, ("contacts", j, "points"))
            sides.append({"index": nodes.index(node), "point": [float(point[0]),
                                                                 float(point[1])]})
        out.append({"name": name, "sides": sides,
                    "closed": None if force is None else
                    [int(v) for v in (force[pick, j] > 0)]})
    return out


def plan_animation_data(ds, max_frames: int) -> dict:
    """What the plan view draws, from a result Dataset of a scene in plan (a ``direction``
    dimension): times, each floor's outline, centre of mass and level, its motion (u_x, u_y,
    theta) per frame, the contacts' points and closed frames, the levels and the default
    magnification."""
    if "displacement" not in ds or "displacement_rz" not in ds:
        raise InputError("the result holds no displacement history to animate; add "
                         "displacement to a 'kind: history' recorder and solve again (a scene "
                         "in plan writes the floors' rotations with it)")
    u, rz = ds["displacement"], ds["displacement_rz"]
    time_dim = u.dims[0]
    steps = ds.sizes[time_dim]
    pick = np.unique(np.linspace(0, steps - 1, min(steps, max_frames)).round().astype(int))
    nodes = [str(n) for n in ds["node_name"].values]
    motion = np.concatenate([np.asarray(u.values)[pick],
                             np.asarray(rz.values)[pick][:, :, None]], axis=2)
    scene, placed = _scene(ds)
    floors, missing = [], []
    for f in placed.nodes:
        if f.name not in nodes:
            continue
        level = f.name.split("/", 1)[1] if "/" in f.name else f.name
        outline = None if f.plan is None else [
            [float(v) for v in f.placement.point(p)] for p in f.plan.corners()]
        if outline is None:
            missing.append(f.building)
        floors.append({"node": f.name, "building": f.building, "level": level,
                       "index": nodes.index(f.name),
                       "centre": [float(f.centre[0]), float(f.centre[1])],
                       "outline": outline})
    if len(missing) == len(floors):
        raise InputError("the plan view draws each floor's outline, and no building of the "
                         "scene has a plan: give each a plan (plan: {size: [L_x, L_y]} or "
                         "plan: {outline: [[x, y], ...]}) and solve again")
    force = None
    if "contact_force" in ds and ds["contact_force"].dims[0] == time_dim:
        force = np.asarray(ds["contact_force"].values)
    names = [str(n) for n in ds["contact_name"].values] if "contact_name" in ds else []
    contacts = _contacts(scene, placed, nodes, names, force, pick)
    # the default magnification: the largest motion of an outline's corner (or centre)
    corners = [(f, np.asarray(f["outline"] or [f["centre"]])) for f in floors]
    peak = 0.0
    for f, points in corners:
        ux, uy, theta = (motion[:, f["index"], k][:, None] for k in range(3))
        arm = points - np.asarray(f["centre"])
        moved = np.hypot(ux - theta * arm[:, 1], uy + theta * arm[:, 0])
        peak = max(peak, float(np.nanmax(moved)) if moved.size else 0.0)
    every = np.concatenate([points for _, points in corners])
    extent = float(np.hypot(*(every.max(axis=0) - every.min(axis=0)))) or 1.0
    levels = list(dict.fromkeys(sorted((f["level"] for f in floors),
                                       key=lambda v: (not v.isdigit(), int(v) if v.isdigit()
                                                      else 0, v))))
    level_of = {f["index"]: f["level"] for f in floors}
    with_contacts = [lv for lv in levels if any(
        side is not None and level_of[side["index"]] == lv
        for c in contacts for side in c["sides"])]
    return {
        "title": str(ds.attrs.get("title", "")), "source": str(ds.attrs.get("source", "")),
        "time": [float(v) for v in np.asarray(ds[time_dim].values)[pick]],
        "time_units": str(ds[time_dim].attrs.get("units", "")),
        "units": str(u.attrs.get("units", "")),
        "motion": [[[float(f"{v:.6g}") for v in node] for node in row] for row in motion],
        "floors": floors, "contacts": contacts, "levels": levels,
        "level": (with_contacts or levels)[-1],
        "buildings": list(dict.fromkeys(f["building"] for f in floors)),
        "magnify": _nice(MOTION * extent / peak) if peak > 0 else 1.0,
        "extent": extent, "without_plan": list(dict.fromkeys(missing)),
        "lit": force is not None,
    }


GEOMETRY = r"""
// a floor's points moved as a rigid body: translated by m (u_x, u_y), turned by m theta about
// its centre of mass (pure: tests evaluate it outside a browser)
function planMove(data, frame, f, magnify) {
  const [ux, uy, rz] = data.motion[frame][f.index];
  const a = magnify * rz, c = Math.cos(a), s = Math.sin(a);
  const [cx, cy] = f.centre;
  return p => [cx + magnify * ux + c * (p[0] - cx) - s * (p[1] - cy),
               cy + magnify * uy + s * (p[0] - cx) + c * (p[1] - cy)];
}
// the floors at one level and the contacts that strike them, in site coordinates (m)
function planLayout(data, frame, level, magnify) {
  const byIndex = {};
  data.floors.forEach(f => { byIndex[f.index] = f; });
  const floors = data.floors.filter(f => f.level === level).map(f => {
    const move = planMove(data, frame, f, magnify);
    return {node: f.node, building: f.building, centre: move(f.centre),
            outline: f.outline ? f.outline.map(move) : null, rest: f.outline};
  });
  const contacts = data.contacts.filter(c => c.sides.some(
      s => s && byIndex[s.index].level === level)).map(c => ({
    name: c.name, closed: c.closed ? c.closed[frame] === 1 : false,
    points: c.sides.map(s => s ? planMove(data, frame, byIndex[s.index], magnify)(s.point)
                                 : null)}));
  return {floors: floors, contacts: contacts};
}
// site coordinates (m) -> canvas pixels: every outline at rest fits, one scale on both axes
function planView(data, width, height) {
  const all = [];
  data.floors.forEach(f => (f.outline || [f.centre]).forEach(p => all.push(p)));
  const xs = all.map(p => p[0]), ys = all.map(p => p[1]);
  const margin = 0.12 * data.extent;
  const x0 = Math.min(...xs) - margin, x1 = Math.max(...xs) + margin;
  const y0 = Math.min(...ys) - margin, y1 = Math.max(...ys) + margin;
  const scale = Math.min(width / (x1 - x0), (height - 40) / (y1 - y0));
  const left = (width - scale * (x1 - x0)) / 2, bottom = height - 40 - (height - 40 - scale * (y1 - y0)) / 2;
  return {scale: scale, x: x => left + (x - x0) * scale, y: y => bottom - (y - y0) * scale};
}
"""

VIEW = r"""
// the elevation view's colours: none is the red of a closed contact
const colours = ["#1f77b4", "#ff7f0e", "#2ca02c", "#9467bd", "#8c564b", "#17becf"];
const levelChoice = document.getElementById("level"), magnifyChoice = document.getElementById("magnify");
const askedLevel = /level=([^&]+)/.exec(location.hash);
const askedMagnify = /magnify=([0-9.eE+-]+)/.exec(location.hash);
levelChoice.value = askedLevel ? decodeURIComponent(askedLevel[1]) : data.level;
magnifyChoice.value = askedMagnify ? parseFloat(askedMagnify[1]) : data.magnify;
const view = planView(data, canvas.width, canvas.height);
const note = document.getElementById("magnified");
function path(points) {
  ctx.beginPath(); ctx.moveTo(view.x(points[0][0]), view.y(points[0][1]));
  points.slice(1).forEach(p => ctx.lineTo(view.x(p[0]), view.y(p[1]))); ctx.closePath();
}
function draw(k) {
  frame = k; slider.value = k;
  const level = levelChoice.value, m = Math.max(0, parseFloat(magnifyChoice.value) || 0);
  note.textContent = "motion drawn " + m + " times its size";
  const g = planLayout(data, k, level, m);
  ctx.clearRect(0, 0, canvas.width, canvas.height);
  // the buildings without a floor at this level: their plan at rest, faint
  const here = new Set(g.floors.map(f => f.building));
  ctx.setLineDash([2, 4]); ctx.strokeStyle = "#cccccc"; ctx.lineWidth = 1;
  data.floors.filter(f => !here.has(f.building) && f.outline).forEach(f => {
    path(f.outline); ctx.stroke(); });
  g.floors.forEach(f => {
    const colour = colours[data.buildings.indexOf(f.building) % colours.length];
    if (f.outline) {
      ctx.setLineDash([5, 4]); ctx.strokeStyle = "#999999"; ctx.lineWidth = 1;
      path(f.rest); ctx.stroke();
      ctx.setLineDash([]); ctx.strokeStyle = colour; ctx.lineWidth = 2.5;
      ctx.globalAlpha = 0.18; ctx.fillStyle = colour; path(f.outline); ctx.fill();
      ctx.globalAlpha = 1.0; path(f.outline); ctx.stroke();
    }
    ctx.setLineDash([]); ctx.fillStyle = colour;
    ctx.beginPath(); ctx.arc(view.x(f.centre[0]), view.y(f.centre[1]), 4, 0, 2 * Math.PI); ctx.fill();
    ctx.fillStyle = "#222"; ctx.font = "14px sans-serif";
    ctx.fillText(f.node, view.x(f.centre[0]) + 7, view.y(f.centre[1]) - 7);
  });
  g.contacts.forEach(c => {
    const points = c.points.filter(p => p);
    ctx.setLineDash([]);
    ctx.strokeStyle = c.closed ? "#d62728" : "#777777"; ctx.fillStyle = "#d62728";
    ctx.lineWidth = c.closed ? 3 : 1.5;
    if (points.length === 2) { ctx.beginPath(); ctx.moveTo(view.x(points[0][0]), view.y(points[0][1]));
      ctx.lineTo(view.x(points[1][0]), view.y(points[1][1])); ctx.stroke(); }
    points.forEach(p => { ctx.beginPath();
      ctx.arc(view.x(p[0]), view.y(p[1]), c.closed ? 9 : 4, 0, 2 * Math.PI);
      if (c.closed) ctx.fill(); ctx.stroke(); });
    ctx.fillStyle = c.closed ? "#d62728" : "#555555"; ctx.font = "12px sans-serif";
    ctx.fillText(c.name, view.x(points[0][0]) + 11, view.y(points[0][1]) + 16);
  });
  // the site's axes and a scale bar, at true size
  const bar = Math.pow(10, Math.floor(Math.log10(data.extent / 4)));
  const ox = 20, oy = canvas.height - 12;
  ctx.strokeStyle = "#222"; ctx.fillStyle = "#222"; ctx.lineWidth = 2; ctx.setLineDash([]);
  ctx.beginPath(); ctx.moveTo(ox, oy); ctx.lineTo(ox + bar * view.scale, oy); ctx.stroke();
  ctx.font = "12px sans-serif"; ctx.fillText(bar + " m", ox + bar * view.scale + 6, oy + 4);
  const ax = canvas.width - 60, ay = canvas.height - 12;
  ctx.beginPath(); ctx.moveTo(ax, ay); ctx.lineTo(ax + 30, ay); ctx.moveTo(ax, ay);
  ctx.lineTo(ax, ay - 30); ctx.stroke();
  ctx.beginPath(); ctx.moveTo(ax + 34, ay); ctx.lineTo(ax + 27, ay - 4); ctx.lineTo(ax + 27, ay + 4);
  ctx.moveTo(ax, ay - 34); ctx.lineTo(ax - 4, ay - 27); ctx.lineTo(ax + 4, ay - 27); ctx.fill();
  ctx.fillText("x", ax + 38, ay + 4); ctx.fillText("y", ax - 3, ay - 38);
  clock.textContent = "t = " + data.time[k].toFixed(3) + " " + data.time_units + ", level " + level;
}
levelChoice.onchange = () => draw(frame);
magnifyChoice.oninput = () => draw(frame);
"""


def plan_animation_html(ds, max_frames: int) -> str:
    """The page of a result of a scene in plan (see the module)."""
    import html

    from pframe.plot.player import page

    data = plan_animation_data(ds, max_frames)
    title = data["title"] or data["source"] or "pframe run"
    note = (f"{len(data['time'])} frames; the site from above (x east, y north), the "
            "floors' outlines and the gaps at true size, their motion magnified (default "
            f"{data['magnify']:g} times; change it below): outlines drawn overlapping are not "
            "in contact unless their contact is red, as it is while closed."
            + ("" if data["lit"] or not data["contacts"] else " The file has no "
               "contact_force history: contacts are never lit.")
            + (f" Without a plan (plan: size or outline), {', '.join(data['without_plan'])} "
               "is drawn as its centres of mass only." if data["without_plan"] else ""))
    options = "".join(f'<option value="{html.escape(lv)}">{html.escape(lv)}</option>'
                      for lv in data["levels"])
    controls = (f'\n<label>level <select id="level">{options}</select></label>'
                '\n<label>magnification <input id="magnify" type="number" min="0" step="any" '
                'style="width: 5em"></label> <span id="magnified" class="note"></span>')
    return page(data, title, note, GEOMETRY, VIEW, controls=controls, height=640)
