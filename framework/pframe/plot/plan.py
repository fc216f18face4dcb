"""Figures of a scene in plan (floors that move along x and y and turn; docs/plotting.md).

One figure per floor level, its history panels two to a row on one time axis, x beside y:

- the floors' centres of mass along the site's x and y (``displacement``, ``velocity``);
- the named plan points (corners) along their building's own axes (``point_displacement``,
  ``point_drift``), when the recorders kept their histories;
- the floors' rotations, the pounding force of each contact at the level, and the drift of
  every line of resistance of each building's storey below the level;
- ``kind="hysteresis"`` (and ``"all"``, below the histories): each line's force against its
  drift, a row per building.

``kind="torsion"`` draws one figure of the whole scene: each storey's torsional irregularity
ratio along its building's x and y, with the limits 1.2 (type 1a) and 1.4 (type 1b) of ASCE
7-22 Table 12.3-1. The gap-closing figure (``kind="pounding"``) is
:func:`pframe.plot.figure.draw_pounding`, which draws a contact in plan along its normal at
its points.
"""

from __future__ import annotations

import numpy as np

from pframe.errors import InputError
from pframe.irregularity import TORSIONAL_IRREGULARITY
from pframe.plot.data import Result
from pframe.plot.scales import DIMENSIONLESS, LABELS, axis_label
from pframe.plot.style import (
    CONTACT_COLOURS,
    building_colour,
    headed,
    matplotlib_figure,
    on_common_time,
)

#: rows of x and y panels: (quantity, title) along x, then along y
PAIRS = ((("displacement_x", "floor displacement along the site's x"),
          ("displacement_y", "floor displacement along the site's y")),
         (("velocity_x", "floor velocity along the site's x"),
          ("velocity_y", "floor velocity along the site's y")),
         (("point_displacement_x", "point displacement along its building's x"),
          ("point_displacement_y", "point displacement along its building's y")),
         (("point_drift_x", "point drift along its building's x"),
          ("point_drift_y", "point drift along its building's y")))
#: panels of their own, after the pairs, two to a row
SINGLES = (("displacement_rz", "floor rotation"), ("velocity_rz", "floor angular velocity"),
           ("contact_force", "pounding force"))
#: axis words of the components (the units come from the file)
WORDS = {"displacement": "displacement", "velocity": "velocity",
         "point_displacement": "point displacement", "point_drift": "point drift"}
#: line styles of the named points of one floor (their colour is their building's)
POINT_STYLES = ("-", "--", ":", "-.")
#: the torsion figure's two series: along the building's x, along its y
AXIS_STYLES = ({"marker": "o", "label": "along the building's x"},
               {"marker": "s", "linestyle": ":", "markerfacecolor": "white",
                "label": "along the building's y"})
#: what a panel's values are compared with to tell a response from round-off: the figure's
#: panels of the same kind (a rotation as the displacement it makes one length unit from the
#: centre of mass: the figure's length unit, or l_e in a dimensionless file)
KINDS = {"displacement_x": "displacement", "displacement_y": "displacement",
         "displacement_rz": "displacement", "point_displacement_x": "displacement",
         "point_displacement_y": "displacement", "velocity_x": "velocity",
         "velocity_y": "velocity", "velocity_rz": "velocity", "point_drift_x": "drift",
         "point_drift_y": "drift", "story_drift": "drift"}
#: a panel whose peak is at most this fraction of the largest peak of its kind in the figure
#: is zero to round-off (double precision is 1.1e-16; a symmetric scene shaken along x gives
#: y and rotation near 1e-18 of x, an eccentricity of 1e-9 of the plan far more than 1e-12)
ROUND_OFF = 1e-12
#: legend entries that fit beside a panel's title, and in a row of their own under it
BESIDE_TITLE, LEGEND_ROW = 4, 8
#: height of a row of panels (inches)
ROW = 2.05


def _names_at(result: Result, level: str, quantity: str) -> list[str]:
    """The names a panel of ``quantity`` draws at ``level``: its floors, points or contacts."""
    history = result.histories.get(quantity)
    if history is None:
        return []
    if quantity == "contact_force":
        wanted = result.levels.contacts.get(level, [])
    elif quantity.startswith("point_"):
        floors = set(result.levels.nodes.get(level, {}).values())
        wanted = [p for p in history.names if p.rsplit(":", 1)[0] in floors]
    else:
        wanted = list(result.levels.nodes.get(level, {}).values())
    return [n for n in wanted if n in history.names]


def plan_panels(result: Result, level: str, kind: str):
    """``(rows, loops)`` of one level: rows of up to two history panels, each
    ``(quantity, title, names)`` (``story_drift`` panels name one building's lines), and
    rows of loop panels, a building's lines each."""
    rows = []
    if kind in ("all", "histories"):
        for pair in PAIRS:
            row = [(q, title, _names_at(result, level, q)) for q, title in pair]
            row = [panel for panel in row if panel[2]]
            if row:
                rows.append(row)
        singles = [(q, title, _names_at(result, level, q)) for q, title in SINGLES]
        singles = [panel for panel in singles if panel[2]]
        if "story_drift" in result.histories:
            for building, lines in result.levels.lines.get(level, {}).items():
                singles.append(("story_drift", f"storey drift of each line, storey "
                                f"{building}/{level}", lines))
        rows += [singles[i:i + 2] for i in range(0, len(singles), 2)]
    loops = []
    if kind in ("all", "hysteresis") and {"story_drift", "story_force"} <= result.histories.keys():
        loops = list(result.levels.lines.get(level, {}).values())
    return rows, loops


def _ylabel(quantity: str, units: str, power: int = 0) -> str:
    """``displacement along x (m)``, ``floor rotation (mrad)``, ``drift along the line (m)``;
    the paper's symbol and the component when dimensionless. ``power``: the values are shown
    divided by 10^power (:func:`_scale`), in a prefixed unit when there is one."""
    if power and units in PREFIXED and power in PREFIXES:
        units, power = PREFIXES[power] + units, 0
    base, _, component = quantity.rpartition("_")
    if base in WORDS and component in ("x", "y"):
        words, symbol = f"{WORDS[base]} along {component}", f"{axis_label(base, units)} " \
            f"along {component}"
    elif quantity == "story_drift":
        words, symbol = "drift along the line", axis_label("story_drift", units)
    else:
        words, symbol = LABELS.get(quantity, (quantity,))[0], axis_label(quantity, units)
    multiplier = f"$10^{{{power}}}$" if power else ""
    if units == DIMENSIONLESS:
        return f"{symbol} ({multiplier})" if multiplier else symbol
    return axis_label(words, " ".join(filter(None, (multiplier, units))))


#: SI units that take a prefix, and the prefixes of powers of 1000
PREFIXED = ("m", "m/s", "m/s^2", "N", "rad", "rad/s", "rad/s^2")
PREFIXES = {-9: "n", -6: "\N{MICRO SIGN}", -3: "m", 3: "k", 6: "M", 9: "G"}


def _scale(ax, axis: str = "y") -> int:
    """Tick labels without a multiplier over the axis (it would push the panel's title above
    its neighbour's): beyond 1e-3 .. 1e4 the values are shown divided by a power of 1000,
    which the axis label names (:func:`_ylabel`). Returns that power (0: none)."""
    from matplotlib.ticker import FuncFormatter

    data = [np.asarray(line.get_xdata() if axis == "x" else line.get_ydata(), dtype=float)
            for line in ax.get_lines()]
    peak = max((float(np.nanmax(np.abs(d))) for d in data if np.isfinite(d).any()),
               default=0.0)
    magnitude = int(np.floor(np.log10(peak))) if peak > 0 else 0
    if -3 < magnitude < 4:
        ax.ticklabel_format(axis=axis, style="plain", useOffset=False)
        return 0
    power = 3 * int(round(magnitude / 3))
    (ax.xaxis if axis == "x" else ax.yaxis).set_major_formatter(
        FuncFormatter(lambda value, _: f"{value / 10.0**power:.6g}"))
    return power


def _entries(panel) -> int:
    """How many entries the legend of a history panel has (a point's style names it on
    every floor)."""
    quantity, _, names = panel
    if quantity.startswith("point_"):
        return len({name.rsplit(":", 1)[-1] for name in names})
    return len(names)


def _peak(result: Result, panel) -> float:
    """The largest magnitude a history panel draws (0 when none is finite)."""
    history = result.histories[panel[0]]
    values = np.abs(np.stack([history.column(name) for name in panel[2]]))
    return float(np.nanmax(values)) if np.isfinite(values).any() else 0.0


def round_off_notes(result: Result, panels, letters) -> list:
    """For each of ``panels`` (lettered ``letters``), None, or the note it shows in place of
    its values when they are zero to round-off: at most :data:`ROUND_OFF` of the largest
    peak of their kind (:data:`KINDS`) in the figure (a panel of exact zeros draws them)."""
    peaks = [_peak(result, panel) for panel in panels]
    largest: dict[str, tuple[float, int]] = {}
    for k, (panel, peak) in enumerate(zip(panels, peaks)):
        kind = KINDS.get(panel[0], panel[0])
        if peak > largest.get(kind, (0.0, -1))[0]:
            largest[kind] = (peak, k)
    notes = []
    for panel, peak in zip(panels, peaks):
        reference, of = largest.get(KINDS.get(panel[0], panel[0]), (0.0, -1))
        if not 0.0 < peak <= ROUND_OFF * reference:
            notes.append(None)
            continue
        units = result.histories[panel[0]].units
        text = f"0 to round-off: |peak| {peak:.1e}" + (
            f" {units}" if units not in ("", DIMENSIONLESS) else "") + "\n"
        if panel[0].endswith("_rz"):  # compared as the translation it makes 1 unit away
            length = result.histories[panels[of][0]].units.split("/")[0]
            text += (f"times 1 {length} from the centre of mass, "
                     if length not in ("", DIMENSIONLESS) else "times l_e, ")
        notes.append(f"{text}below {ROUND_OFF:.0e} of panel ({letters[of]})'s peak")
    return notes


def _history_panel(ax, result: Result, panel, letter: str, legend: bool, band: int,
                   round_off: str | None = None):
    """One history panel; ``band``: rows of legend under the title (0: the legend beside
    it); ``round_off``: the values are zero to round-off (:func:`round_off_notes`), drawn
    as zero with this note instead of their noise magnified to fill the axis."""
    quantity, title, names = panel
    history = result.histories[quantity]
    styles = {}
    for name in names:
        if quantity == "contact_force":
            colour = CONTACT_COLOURS[names.index(name) % len(CONTACT_COLOURS)]
            style, label = "-", name
        elif quantity == "story_drift":
            colour = f"C{names.index(name) % 10}"
            style, label = "-", name.rsplit("/", 1)[-1]
        else:
            building = name.split("/", 1)[0]
            colour = building_colour(result, building)
            if quantity.startswith("point_"):
                point = name.rsplit(":", 1)[-1]
                style = styles.setdefault(point, POINT_STYLES[len(styles) % len(POINT_STYLES)])
            else:
                style = "-"
            label = name
        values = history.column(name)
        ax.plot(history.time, np.zeros_like(values) if round_off else values, label=label,
                linewidth=0.8, color=colour, linestyle=style)
    if round_off:
        ax.set_ylim(-1.0, 1.0)
        ax.set_yticks([0.0])
        ax.text(0.5, 0.72, round_off, transform=ax.transAxes, ha="center", va="center",
                fontsize="x-small", color="0.3")
    ax.set_label(quantity if quantity != "story_drift" else f"story_drift {names[0]}")
    points = quantity.startswith("point_")
    # a long legend has a band of its own under the title (the row's titles stay level)
    ax.set_title(f"({letter}) {title}", loc="left", fontsize="medium",
                 pad=6.0 + 14.0 * band if band else None)
    if legend:
        handles = None
        if points:  # their colour is their building's; a line style names each point
            from matplotlib.lines import Line2D

            handles = [Line2D([], [], color="0.25", linewidth=0.8, linestyle=style, label=p)
                       for p, style in styles.items()]
        # above the axes beside the title: inside, it would hide the peaks it is about
        ax.legend(handles=handles, fontsize="x-small", loc="lower right",
                  bbox_to_anchor=(1.0, 1.0), ncols=min(_entries(panel), LEGEND_ROW if band
                                                       else BESIDE_TITLE),
                  frameon=False, borderaxespad=0.1, handlelength=2.2 if points else 1.5,
                  columnspacing=1.0)
    ax.grid(True, alpha=0.3, linewidth=0.6)
    ax.tick_params(labelsize=8)
    ax.set_ylabel(_ylabel(quantity, history.units, _scale(ax)), fontsize="small")


def draw_plan_level(result: Result, level: str, kind: str = "all", fig=None):
    """The figure of one floor level of a scene in plan (see the module), or None when it has
    nothing of ``kind`` to draw; drawn into ``fig`` when given. Each axes is labelled with its
    quantity (``displacement_x``, ``contact_force``, ...; ``story_drift <first line>``,
    ``hysteresis <line>``) and each line with its floor, point, contact or line name."""
    Figure = matplotlib_figure()
    rows, loops = plan_panels(result, level, kind)
    if not rows and not loops:
        return None
    columns = max(2, max((len(lines) for lines in loops), default=0))
    height = ROW * len(rows) + 2.3 * len(loops) + 1.0
    if fig is None:
        fig = Figure(figsize=(11.0 if columns <= 4 else 2.7 * columns, height),
                     layout="constrained")
    if rows and loops:
        top, bottom = fig.subfigures(2, 1, height_ratios=(ROW * len(rows), 2.3 * len(loops)))
    else:
        top, bottom = (fig, None) if rows else (None, fig)
    letter = ord("a")
    if rows:
        panels = [panel for row in rows for panel in row]
        noise = iter(round_off_notes(result, panels,
                                     [chr(letter + k) for k in range(len(panels))]))
        grid = top.add_gridspec(len(rows), 2)
        first = None
        for r, row in enumerate(rows):
            for c, panel in enumerate(row):
                # a panel alone in its row spans it
                ax = top.add_subplot(grid[r, c] if len(row) == 2 else grid[r, :], sharex=first)
                first = first or ax
                # a pair draws the same floors or points: one legend, on its y panel
                paired = len(row) == 2 and row[0][2] == row[1][2]
                longest = max(_entries(p) for p in row)
                # the points' titles are long: their legend never fits beside them
                beside = longest <= BESIDE_TITLE and not row[0][0].startswith("point_")
                band = 0 if beside else -(-longest // LEGEND_ROW)
                _history_panel(ax, result, panel, chr(letter), not paired or c == 1, band,
                               next(noise))
                letter += 1
                if r < len(rows) - 1:
                    ax.tick_params(labelbottom=False)
                else:
                    ax.set_xlabel(axis_label("time", result.histories[panel[0]].time_units),
                                  fontsize="small")
    if loops:
        _draw_loops(bottom, result, loops, letter)
    return headed(fig, result, f"{result.title}: level {level}")


def _draw_loops(fig, result: Result, loops, letter: int):
    """A row of hysteresis loops (line force against line drift) per building."""
    drift, force = result.histories["story_drift"], result.histories["story_force"]
    columns = max(len(lines) for lines in loops)
    grid = fig.add_gridspec(len(loops), columns)
    for r, lines in enumerate(loops):
        building = lines[0].split("/", 1)[0]
        for c, line in enumerate(lines):
            ax = fig.add_subplot(grid[r, c])
            x, y = on_common_time(drift, force, line)
            ax.plot(x, y, linewidth=0.7, label=line, color=building_colour(result, building))
            ax.set_label(f"hysteresis {line}")
            ax.set_title(f"({chr(letter)}) line {line}", loc="left", fontsize="medium")
            letter += 1
            ax.grid(True, alpha=0.3, linewidth=0.6)
            ax.tick_params(labelsize=8)
            ax.locator_params(axis="x", nbins=4)
            ax.set_xlabel(_ylabel("story_drift", drift.units, _scale(ax, "x")),
                          fontsize="small")
            ax.set_ylabel(_ylabel("story_force", force.units, _scale(ax)), fontsize="small")


def storeys_by_building(result: Result) -> dict:
    """``building -> [(floor, (ratio along x, ratio along y)), ...]`` bottom to top."""
    out: dict[str, list] = {}
    for floor, ratios in result.torsion.items():
        out.setdefault(floor.split("/", 1)[0], []).append((floor, ratios))
    return out


def draw_torsion(result: Result, fig=None):
    """The torsional irregularity ratio of every storey along its building's x and y, one
    panel per building, against the limits of ASCE 7-22 Table 12.3-1 (1.2: type 1a, 1.4:
    type 1b). Axes labelled ``torsion <building>``, their lines ``x`` and ``y``."""
    Figure = matplotlib_figure()
    buildings = storeys_by_building(result)
    if not buildings or all(np.isnan(r).all() for s in buildings.values() for _, r in s):
        return None
    tallest = max(len(storeys) for storeys in buildings.values())
    if fig is None:
        fig = Figure(figsize=(max(5.0, 3.4 * len(buildings) + 0.8), 0.45 * tallest + 2.6),
                     layout="constrained")
    axes = fig.subplots(1, len(buildings), sharex=True, squeeze=False)[0]
    finite = [v for s in buildings.values() for _, r in s for v in r if np.isfinite(v)]
    high = max([*finite, TORSIONAL_IRREGULARITY[1]]) * 1.08
    for k, (ax, (building, storeys)) in enumerate(zip(axes, buildings.items())):
        level = np.arange(1, len(storeys) + 1)
        ratios = np.array([r for _, r in storeys], dtype=float)
        colour = building_colour(result, building)
        ax.axvspan(TORSIONAL_IRREGULARITY[0], TORSIONAL_IRREGULARITY[1], color="C1", alpha=0.12,
                   linewidth=0, label="_1a")
        ax.axvspan(TORSIONAL_IRREGULARITY[1], high, color="C3", alpha=0.12, linewidth=0,
                   label="_1b")
        ax.axvline(TORSIONAL_IRREGULARITY[0], color="C1", linestyle="--", linewidth=1.0,
                   label="1.2: type 1a (torsional irregularity)")
        ax.axvline(TORSIONAL_IRREGULARITY[1], color="C3", linestyle="--", linewidth=1.0,
                   label="1.4: type 1b (extreme torsional irregularity)")
        for axis, style in zip((0, 1), AXIS_STYLES):
            ax.plot(ratios[:, axis], level, color=colour, linewidth=1.0, **style)
        for i, (_, ratio) in enumerate(storeys):
            missing = [axis for axis, v in zip("xy", ratio) if np.isnan(v)]
            twist = [axis for axis, v in zip("xy", ratio) if np.isinf(v)]
            notes = ([f"{' and '.join(missing)}: no drift"] if missing else []) + (
                [f"{' and '.join(twist)}: twists only (ratio inf)"] if twist else [])
            if notes:
                ax.annotate("; ".join(notes), (1.0, i + 1), xytext=(4, 0),
                            textcoords="offset points", va="center", fontsize="x-small",
                            color="C3" if twist else "0.35")
        ax.set_label(f"torsion {building}")
        ax.set_title(f"({chr(ord('a') + k)}) building {building}", loc="left",
                     fontsize="medium")
        ax.set_yticks(level, [f"{floor.split('/', 1)[1]}" for floor, _ in storeys])
        ax.set_ylim(0.5, len(storeys) + 0.5)
        ax.set_xlim(min([*finite, 1.0]) - 0.04, high)
        ax.set_xlabel(r"$\delta_{max} / \delta_{avg}$ (dimensionless)", fontsize="small")
        if k == 0:
            ax.set_ylabel("storey (the floor above it)", fontsize="small")
        ax.grid(True, alpha=0.3, linewidth=0.6)
        ax.tick_params(labelsize=8)
    from matplotlib.lines import Line2D

    # the limits as drawn, the two axes in grey (each building has its colour)
    handles = [h for h in axes[0].get_lines() if h.get_linestyle() == "--"]
    handles += [Line2D([], [], color="0.3", linewidth=1.0, **style) for style in AXIS_STYLES]
    fig.legend(handles, [h.get_label() for h in handles], loc="outside lower center", ncols=2,
               fontsize="x-small", frameon=False)
    # (non-breaking spaces: a wrapped heading keeps the code's name on one line)
    return headed(fig, result, f"{result.title}: torsional irregularity per storey "
                  "(ASCE\u00a07-22\u00a0Table\u00a012.3-1)")


def plan_notes(result: Result, kind: str) -> list[str]:
    """Why panels of ``kind`` are left out of the figures of a scene in plan."""
    out = []
    have = result.histories
    if kind in ("all", "histories"):
        if "displacement_x" not in have:
            out.append("the file has no displacement history: no floor displacement and "
                       "rotation panels")
        if result.has_contacts and "contact_force" not in have:
            out.append("the file has no contact_force history: no pounding force panels")
        if result.has_stories and "story_drift" not in have:
            out.append("the file has no story_drift history: no panels of the lines' drifts")
    if kind in ("all", "hysteresis"):
        lacking = [q for q in ("story_drift", "story_force") if q not in have]
        if result.has_stories and lacking:
            out.append(f"the file has no {' and no '.join(lacking)} history: no hysteresis "
                       "loops of the lines")
    if kind in ("all", "torsion") and not result.torsion:
        out.append(TORSION_MISSING)
    return out


#: why a result of a scene in plan has no torsion figure, and what gives it one
TORSION_MISSING = ("the file has no torsional_irregularity: pframe solve writes it from the "
                   "peak point_drift at each floor's named points, which a building has when "
                   "it has a plan (plan: {size: [L_x, L_y]} or plan: {outline: ...}) or "
                   "points; give them and solve again")


def torsion_figures(result: Result, kind: str, fig=None) -> dict:
    """``{"torsion": Figure}`` of a result in plan, drawn into ``fig`` when given (empty when
    it has no ratio; ``kind`` ``"torsion"`` then refuses it, naming what to record)."""
    fig = draw_torsion(result, fig) if result.torsion else None
    if fig is None and kind == "torsion":
        why = TORSION_MISSING if not result.torsion else (
            "no storey has a torsional irregularity ratio (no storey drifts at its plan's "
            "ends)")
        raise InputError(f"{result.path}: nothing to plot for --kind torsion: {why}")
    return {} if fig is None else {"torsion": fig}
