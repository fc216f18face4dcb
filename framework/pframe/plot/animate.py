"""An animation of a run as one self-contained HTML page (``pframe animate RUN.nc``).

The buildings stand side by side, their floors at their elevations (the sums of the storey
heights of the scene the result holds; at their floor numbers when a storey has no height),
each floor displaced sideways by its recorded displacement, drawn at one scale for the whole
page: displacements and gaps are multiplied by the same factor, so two floors touch on the
page when they touch in the run. A contact is drawn between its floors, red while its force
is positive (closed), grey when open; a floor-to-column contact ends on the struck column at
its point (``at`` of the way up the storey), displaced as the run displaces that point (the
storey's floors weighted as the contact weighs them). Play, pause, a time slider and a speed
choice; no file, script or font is loaded from elsewhere.

The page's geometry is one pure function (``layout(data, frame)`` in the page's script), so
a test can evaluate it outside a browser and compare it with the file. A scene in plan is
drawn from above instead (:mod:`pframe.plot.plan_view`), in the same player (:func:`page`).
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from pframe.errors import InputError
from pframe.plot.player import page

#: frames kept in the page at most (the histories are sampled evenly down to this)
MAX_FRAMES = 2000
#: drawing units: a floor is 1 high; a building is this wide
WIDTH = 1.0
#: the largest displacement is drawn this wide (in drawing units), gaps at the same scale
SWAY = 0.6


def _floor_of(name: str, index_in_building: int) -> float:
    tail = name.split("/", 1)[1] if "/" in name else ""
    return float(tail) if tail.isdigit() else float(index_in_building + 1)


def elevations(ds, nodes: list[str]):
    """The floors' elevations (m) and the floor-to-column contacts' points from the scene the
    result holds: ``({node: elevation}, {contact: (column side, lower floor or None, weight
    of the upper floor, elevation)}, typical storey height)``, or None with the reason when a
    drawn floor's elevation is not known (no scene, a storey without height, a floor on no
    storey)."""
    if "input_yaml" not in ds.attrs:
        return None, "the result holds no scene"
    from pframe.api import scene_of_attributes
    from pframe.model.expand import elevations

    try:
        loaded = scene_of_attributes(dict(ds.attrs), "the result", Path("."))
    except InputError as exc:
        return None, f"its scene cannot be read ({exc})"
    expanded = loaded.expanded
    names = expanded.node_names
    heights = np.asarray(expanded.story_height, dtype=float)
    level = elevations(expanded.stories, heights)
    missing = [n for n in nodes if n not in names or names.index(n) not in level]
    if missing:
        return None, f"{missing[0]} stands on a storey without height"
    floor = {n: level[names.index(n)] for n in nodes}
    points = {}
    for c in expanded.contacts:
        for side in (0, 1):
            if c.share[side] != 1.0 or c.lower[side] >= 0:
                upper, lower = c.nodes[side], c.lower[side]
                bottom = level[lower]
                points[c.name] = ("left" if side == 0 else "right",
                                  None if lower < 0 else names[lower], c.share[side],
                                  bottom + c.at[side] * (level[upper] - bottom))
    drawn = [h for h in heights if np.isfinite(h)]
    return (floor, points, float(np.mean(drawn)) if drawn else 1.0), ""


def animation_data(ds, max_frames: int = MAX_FRAMES) -> dict:
    """What the page draws, from a result Dataset with a displacement history: times, the
    floors of each building (name, height, displacement per frame), the contacts (floors
    joined, closed per frame), and the drawing scale."""
    if "displacement" not in ds:
        raise InputError("the result holds no displacement history to animate; add "
                         "displacement to a 'kind: history' recorder and solve again")
    u = ds.displacement
    time_dim = u.dims[0]
    steps = ds.sizes[time_dim]
    pick = np.unique(np.linspace(0, steps - 1, min(steps, max_frames)).round().astype(int))
    t = np.asarray(ds[time_dim].values)[pick]
    disp = np.asarray(u.values)[pick]
    nodes = [str(n) for n in u[u.dims[1]].values]
    buildings: dict[str, list[int]] = {}
    for i, name in enumerate(nodes):
        buildings.setdefault(name.split("/", 1)[0], []).append(i)

    contacts = []
    gaps_between: dict[tuple[str, str], float] = {}
    if "contact_left" in ds.coords and "contact" in ds.dims:
        force = None
        if "contact_force" in ds and ds.contact_force.dims[0] == time_dim:
            force = np.asarray(ds.contact_force.values)[pick]
        for c, name in enumerate(str(n) for n in ds.contact.values):
            left, right = str(ds.contact_left.values[c]), str(ds.contact_right.values[c])
            if left not in nodes or right not in nodes:
                continue
            gap = float(ds.contact_gap.values[c]) if "contact_gap" in ds.coords else 0.0
            pair = (left.split("/", 1)[0], right.split("/", 1)[0])
            gaps_between[pair] = min(gap, gaps_between.get(pair, np.inf))
            contacts.append({"name": name, "left": nodes.index(left),
                             "right": nodes.index(right), "gap": gap,
                             "closed": (None if force is None else
                                        [int(v) for v in (force[:, c] > 0)])})
    peak = float(np.nanmax(np.abs(disp))) if disp.size else 0.0
    scale = SWAY / peak if peak > 0 else 1.0
    # the bases: each building WIDTH wide; the space to the next is its smallest contact gap
    # at the page's scale (a pair without contacts: half a width)
    names = list(buildings)
    base, x = {}, 0.0
    for k, b in enumerate(names):
        base[b] = x
        if k + 1 < len(names):
            gap = gaps_between.get((b, names[k + 1]), gaps_between.get((names[k + 1], b)))
            x += WIDTH + (gap * scale if gap is not None and np.isfinite(gap) else 0.5 * WIDTH)
    placed, why = elevations(ds, nodes)
    floors = []
    for b, indices in buildings.items():
        for k, i in enumerate(indices):
            height = _floor_of(nodes[i], k) if placed is None else placed[0][nodes[i]]
            floors.append({"node": nodes[i], "building": b, "height": height,
                           "base": base[b], "index": i})
    for contact in contacts:
        point = None if placed is None else placed[1].get(contact["name"])
        if point is not None:
            side, lower, share, y = point
            contact["column"] = {"side": side, "share": share, "y": y,
                                 "lower": -1 if lower is None else nodes.index(lower)}
    units = str(u.attrs.get("units", ""))
    return {
        "title": str(ds.attrs.get("title", "")), "source": str(ds.attrs.get("source", "")),
        "time": [float(v) for v in t], "time_units": str(ds[time_dim].attrs.get("units", "")),
        "units": units, "scale": scale, "width": WIDTH,
        "displacement": [[float(f"{v:.6g}") for v in row] for row in disp],
        "floors": floors, "contacts": contacts,
        "buildings": [{"name": b, "base": base[b]} for b in names],
        "elevations": placed is not None, "storey": 1.0 if placed is None else placed[2],
        "placement": ("floors at their elevations (m)" if placed is not None else
                      f"floors at their floor numbers ({why})"),
    }


GEOMETRY = r"""
// floor positions of one frame, in drawing units (pure: tests evaluate it outside a browser)
function layout(data, frame) {
  const row = data.displacement[frame];
  const floors = data.floors.map(f => ({
    node: f.node, building: f.building, y: f.height,
    left: f.base + data.scale * row[f.index], right: f.base + data.width + data.scale * row[f.index]}));
  const byIndex = {};
  data.floors.forEach((f, k) => { byIndex[f.index] = floors[k]; });
  // a floor-to-column contact's column end: its point, displaced as the run weighs its floors
  const point = (c, upper) => {
    const f = data.floors.find(g => g.index === upper);
    const low = c.column.lower < 0 ? 0 : row[c.column.lower];
    const x = f.base + data.scale * (c.column.share * row[upper] + (1 - c.column.share) * low);
    return {node: f.node, building: f.building, y: c.column.y, left: x, right: x + data.width};
  };
  const contacts = data.contacts.map(c => ({
    name: c.name, closed: c.closed ? c.closed[frame] === 1 : false,
    from: c.column && c.column.side === "left" ? point(c, c.left) : byIndex[c.left],
    to: c.column && c.column.side === "right" ? point(c, c.right) : byIndex[c.right]}));
  return {floors: floors, contacts: contacts};
}
"""

#: the elevation view of a planar scene: ``draw(k)`` of the page's player
ELEVATION = """
const colours = ["#1f77b4", "#ff7f0e", "#2ca02c", "#9467bd", "#8c564b", "#17becf"];
const highest = Math.max(1, ...data.floors.map(f => f.height));
const xs = data.buildings.map(b => b.base);
const xmin = Math.min(...xs) - 1.0, xmax = Math.max(...xs) + data.width + 1.0;
const sx = canvas.width / (xmax - xmin), sy = (canvas.height - 60) / (highest + 0.6 * data.storey);
const px = x => (x - xmin) * sx, py = y => canvas.height - 30 - y * sy;
function draw(k) {
  frame = k; slider.value = k;
  const g = layout(data, k);
  ctx.clearRect(0, 0, canvas.width, canvas.height);
  ctx.strokeStyle = "#444"; ctx.lineWidth = 2;
  ctx.beginPath(); ctx.moveTo(0, py(0)); ctx.lineTo(canvas.width, py(0)); ctx.stroke();
  data.buildings.forEach((b, n) => {
    const mine = g.floors.filter(f => f.building === b.name).sort((p, q) => p.y - q.y);
    ctx.strokeStyle = colours[n % colours.length]; ctx.lineWidth = 3;
    for (const side of ["left", "right"]) {
      ctx.beginPath(); ctx.moveTo(px(side === "left" ? b.base : b.base + data.width), py(0));
      mine.forEach(f => ctx.lineTo(px(f[side]), py(f.y))); ctx.stroke();
    }
    ctx.lineWidth = 5;
    mine.forEach(f => { ctx.beginPath(); ctx.moveTo(px(f.left), py(f.y));
      ctx.lineTo(px(f.right), py(f.y)); ctx.stroke(); });
    ctx.fillStyle = "#222"; ctx.font = "14px sans-serif";
    ctx.fillText(b.name, px(b.base + data.width / 2) - 4, py(0) + 20);
  });
  g.contacts.forEach(c => {
    ctx.strokeStyle = c.closed ? "#d62728" : "#bbbbbb"; ctx.lineWidth = c.closed ? 6 : 1.5;
    const a = c.from.right <= c.to.left ? [c.from.right, c.to.left] : [c.from.left, c.to.right];
    ctx.beginPath(); ctx.arc(px(a[0]), py(c.from.y), c.closed ? 7 : 3, 0, 2 * Math.PI);
    ctx.moveTo(px(a[0]), py(c.from.y)); ctx.lineTo(px(a[1]), py(c.to.y)); ctx.stroke();
  });
  clock.textContent = "t = " + data.time[k].toFixed(3) + " " + data.time_units;
}
"""


def animation_html(ds, max_frames: int = MAX_FRAMES) -> str:
    """The page (see the module docstring) of a result Dataset; the plan view
    (:mod:`pframe.plot.plan_view`) for a scene in plan (a ``direction`` dimension)."""
    if "direction" in ds.dims:
        from pframe.plot.plan_view import plan_animation_html

        return plan_animation_html(ds, max_frames)
    data = animation_data(ds, max_frames)
    title = data["title"] or data["source"] or "pframe run"
    note = (f"{len(data['time'])} frames; displacements and gaps drawn "
            f"{data['scale']:.3g} times their size ({data['units']}); {data['placement']}; "
            "a contact is red while it is closed.")
    return page(data, title, note, GEOMETRY, ELEVATION)


def write_animation(result, output: str | Path, overwrite: bool = True) -> Path:
    """Write the page of ``result`` (a Dataset or a result file) to ``output`` (.html)."""
    from pframe import outputs
    from pframe.tables import result_dataset

    path = Path(output)
    if path.suffix.lower() not in (".html", ".htm"):
        raise InputError(f"{path}: the animation is an HTML page; give a name ending in .html")
    path = outputs.check_output(path, overwrite=overwrite, what="animation")
    ds = result_dataset(result)
    try:
        text = animation_html(ds)
    except InputError as exc:  # the message names the file drawn
        name = result if isinstance(result, (str, Path)) else ds.attrs.get("source", "")
        raise InputError(f"{name}: {exc}" if name else str(exc)) from None
    with outputs.replacing(path) as tmp:
        tmp.write_text(text, encoding="utf-8")
    return path
