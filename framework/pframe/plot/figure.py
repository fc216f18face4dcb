"""One figure per floor level, as in Figures 3 to 5 of Wu et al. (2021).

Panels, lettered as in the paper so that a figure and its caption can be read side by side:

- (a) displacement histories of every building's floor at the level;
- (b) pounding force histories of the contacts at the level;
- (c) velocity histories of the floors;
- (d), (e), ... hysteresis loops (storey shear against storey drift) of each building's storey
  below the level, left to right.

``kind="pounding"`` draws instead, per contact of the level, the gap closing: the relative
displacement of the contact's two nodes against its gap (the gap a dashed line, the times the
gap is closed shaded), the impacts marked on the time axis, and the contact's force below.

Histories are stacked on the left with one time axis, the loops on the right. A panel whose
history the file lacks is left out (:func:`notes` says which); the letters of the others stay.
Figures are :class:`matplotlib.figure.Figure` objects made without pyplot, so they need no
display and hold no global state.
"""

from __future__ import annotations

from collections.abc import Callable
from pathlib import Path

import numpy as np

from pframe.errors import InputError
from pframe.plot.data import Result, read_result
from pframe.plot.scales import DIMENSIONLESS, axis_label, reference_scales, stored_scales
from pframe.plot.style import CONTACT_COLOURS, matplotlib_figure
from pframe.plot.style import building_colour as _building_colour
from pframe.plot.style import headed as _headed
from pframe.plot.style import on_common_time as _on_common_time
from pframe.plot.style import tidy as _tidy

KINDS = ("all", "histories", "hysteresis", "pounding", "links", "torsion", "supports")
#: (letter, quantity, title) of the history panels, top to bottom
HISTORY_PANELS = (("a", "displacement", "displacement histories"),
                  ("b", "contact_force", "pounding force histories"),
                  ("c", "velocity", "velocity histories"))


def _uses(kind: str, quantity: str) -> bool:
    if kind == "pounding":
        return quantity in ("displacement", "contact_force")
    hysteresis = quantity in ("story_drift", "story_force")
    return kind == "all" or (kind == "hysteresis") == hysteresis


def notes(result: Result, kind: str = "all") -> list[str]:
    """Why panels of ``kind`` are left out, and other things a reader of the figures should
    know (an incomplete run, storeys or contacts without a level)."""
    if result.plan:
        from pframe.plot.plan import plan_notes

        return plan_notes(result, kind) + _shared_notes(result, kind)
    out = []
    missing = [q for q in ("displacement", "contact_force", "velocity")
               if _uses(kind, q) and q not in result.histories]
    for letter, quantity, _ in HISTORY_PANELS:
        if quantity not in missing:
            continue
        if kind == "pounding":
            if quantity == "contact_force" and not result.has_contacts:
                out.append("the scene has no contacts: nothing pounds")
            elif result.has_contacts:
                out.append(f"the file has no {quantity} history: "
                           + ("no gap-closing panels" if quantity == "displacement"
                              else "no force panels"))
            continue
        if quantity == "contact_force" and not result.has_contacts:
            out.append("the scene has no contacts: no pounding force panel (b)")
        else:
            out.append(f"the file has no {quantity} history: panel ({letter}) left out")
    if _uses(kind, "story_force"):
        lacking = [q for q in ("story_drift", "story_force") if q not in result.histories]
        if not result.has_stories:
            out.append("the scene has no storeys: no hysteresis panels")
        elif lacking:
            out.append(f"the file has no {' and no '.join(lacking)} history: hysteresis "
                       "panels (d), (e) left out")
    return out + _shared_notes(result, kind)


def _shared_notes(result: Result, kind: str) -> list[str]:
    """The notes of planar figures and figures in plan alike."""
    out = []
    if kind == "pounding" and result.has_contacts and not result.gaps:
        out.append("the file has no contact_gap: no gap-closing panels")
    if kind == "pounding" and result.plan and result.has_contacts and \
            "displacement_x" not in result.histories:
        out.append("the file has no displacement history: no gap-closing panels")
    out.extend(result.dropped)
    for name in result.levels.unplaced:
        out.append(f"{name!r}: its floor level is not known (see docs/plotting.md), not drawn")
    if not result.complete:
        out.append(f"the run stopped early ({result.status}); the figures show what was computed")
    return out


def _level_content(result: Result, level: str, kind: str):
    """The history panels ``[(letter, quantity, title, names)]`` and loop panels
    ``[(letter, building, storey)]`` of one level."""
    levels = result.levels
    histories = []
    if kind != "hysteresis":
        for letter, quantity, title in HISTORY_PANELS:
            if quantity not in result.histories:
                continue
            if quantity == "contact_force":
                names = levels.contacts.get(level, [])
            else:
                names = list(levels.nodes.get(level, {}).values())
            if names:
                histories.append((letter, quantity, title, names))
    loops = []
    if kind != "histories" and {"story_drift", "story_force"} <= result.histories.keys():
        stories = levels.stories.get(level, {})
        for building in levels.buildings:
            if building in stories:
                loops.append((chr(ord("d") + len(loops)), building, stories[building]))
    return histories, loops


def gap_closing(result: Result, contact: str):
    """``(time, relative, gap, onsets)`` of one contact: the relative displacement
    ``u_left - u_right`` of its two points, its gap, and the times the gap closes (each
    impact: the relative displacement rises past the gap; a run that starts closed counts
    an impact at its first time, as the kernel does). A point is a node, or, on the column
    side of a floor-to-column contact, the struck point of the column, psi u_upper +
    (1 - psi) u_lower, as the kernel's contact sees it. None when the file lacks the
    displacements of the nodes or the gap."""
    history = result.histories.get("displacement")
    pair = result.contacts.get(contact)
    if result.plan:  # a contact in plan closes along its normal at its points
        from pframe.plot.plan_data import gap_closing_in_plan

        return gap_closing_in_plan(result, contact)
    if history is None or pair is None or contact not in result.gaps:
        return None
    column = result.columns.get(contact)
    lower = [] if column is None or column[1] == "ground" else [column[1]]
    if any(node not in history.names for node in (*pair, *lower)):
        return None
    points = [history.column(node) for node in pair]
    if column is not None:  # displacements are relative to the ground: 0 at a column's foot
        side, _, psi, _ = column
        points[side] = psi * points[side] + (1.0 - psi) * (
            history.column(lower[0]) if lower else 0.0)
    relative = points[0] - points[1]
    gap = result.gaps[contact]
    closed = relative > gap
    onsets = np.flatnonzero(closed & ~np.concatenate(([False], closed[:-1])))
    return history.time, relative, gap, history.time[onsets]


def _mark_impacts(ax, onsets):
    """The impacts as triangles on the time axis: x in data, y at the axis (they never hide
    the curve). Unclipped, they may sit on the axis line; a contact without impacts keeps an
    empty, clipped line (for the legend), since an empty unclipped one would claim the whole
    figure's corner and collapse the layout."""
    ax.plot(onsets, np.zeros_like(onsets), linestyle="none", marker="^", markersize=6,
            color="C3", clip_on=onsets.size == 0, transform=ax.get_xaxis_transform(),
            label="impacts")


def draw_pounding(result: Result, level: str, fig=None):
    """The gap-closing figure of one level (None when no contact of it can be drawn): per
    contact, (a) the relative displacement of its nodes against its gap, closing shaded and
    impacts marked on the time axis, and (b) its force when the file has it.

    Axes labels for programs reading the figure: ``gap <contact>`` and ``force <contact>``;
    the lines are labelled ``relative``, ``gap`` and ``impacts``, the shading ``closed``."""
    Figure = matplotlib_figure()
    drawn = [(c, gap_closing(result, c)) for c in result.levels.contacts.get(level, [])]
    drawn = [(c, data) for c, data in drawn if data is not None]
    if not drawn:
        return None
    force = result.histories.get("contact_force")
    rows = sum(1 + (force is not None and c in force.names) for c, _ in drawn)
    if fig is None:
        fig = Figure(figsize=(8.0, 2.3 * rows + 0.9), layout="constrained")
    grid = fig.add_gridspec(rows, 1)
    closing = result.histories.get("contact_closing") or result.histories["displacement"]
    units = closing.units
    row, first, letter = 0, None, ord("a")
    for contact, (time, relative, gap, onsets) in drawn:
        left, right = result.contacts[contact]
        ax = fig.add_subplot(grid[row, 0], sharex=first)
        first = first or ax
        row += 1
        ax.plot(time, relative, linewidth=0.8, color="C0", label="relative")
        ax.axhline(gap, linestyle="--", linewidth=0.9, color="k", label="gap")
        ax.fill_between(time, gap, relative, where=relative > gap, interpolate=True,
                        color="C3", alpha=0.35, linewidth=0, label="closed")
        # the closed stretches are short and shallow next to the swing: drawn over in red
        ax.plot(time, np.where(relative > gap, relative, np.nan), linewidth=2.2, color="C3",
                solid_capstyle="butt", label="_closed")
        _mark_impacts(ax, onsets)
        ax.set_label(f"gap {contact}")
        count = len(onsets)
        title = f"({chr(letter)}) gap closing, {contact}: {count} impact{'s' if count != 1 else ''}"
        counted = result.impacts.get(contact)
        if counted is not None and counted != count:  # a coarse history misses short impacts
            title += f" seen in the history; the run counted {counted}"
        ax.set_title(title, loc="left", fontsize="medium")
        letter += 1
        ax.set_ylabel(axis_label("relative displacement", units), fontsize="small")
        handles = [h for h in ax.get_lines() + ax.collections
                   if not h.get_label().startswith("_")]
        order = {"relative": 0, "gap": 1, "closed": 2, "impacts": 3}
        handles.sort(key=lambda h: order[h.get_label()])
        gap_text = f"{gap:.4g}" + ("" if units == DIMENSIONLESS else f" {units}")
        ends = [left, right]
        column = result.columns.get(contact)
        if column is not None:  # the struck point of the column, as the kernel's contact
            ends[column[0]] += f" column at {column[3]:.3g}"
        ax.legend(handles, [" - ".join(ends), f"gap {gap_text}", "closed", "impacts"],
                  fontsize="x-small", loc="lower right", bbox_to_anchor=(1.0, 1.0), ncols=4,
                  frameon=False, borderaxespad=0.1, handlelength=1.5)
        _tidy(ax)
        ax.tick_params(labelbottom=False)
        if force is not None and contact in force.names:
            ax = fig.add_subplot(grid[row, 0], sharex=first)
            row += 1
            ax.plot(force.time, force.column(contact), linewidth=0.8, color="k", label=contact)
            _mark_impacts(ax, onsets)
            ax.set_label(f"force {contact}")
            ax.set_title(f"({chr(letter)}) pounding force, contact {contact}", loc="left",
                         fontsize="medium")
            letter += 1
            ax.set_ylabel(axis_label("contact_force", force.units), fontsize="small")
            _tidy(ax)
            ax.tick_params(labelbottom=False)
    ax.tick_params(labelbottom=True)
    ax.set_xlabel(axis_label("time", closing.time_units), fontsize="small")
    return _headed(fig, result, f"{result.title}: pounding at level {level}")


def draw_level(result: Result, level: str, kind: str = "all", fig=None):
    """The figure of one floor level, or None when it has nothing of ``kind`` to show;
    drawn into ``fig`` (a matplotlib Figure, e.g. ``plt.figure()``) when given. Font sizes
    are relative ("small", "medium"), so they follow the user's ``font.size``.

    Each axes carries a label for programs reading the figure: the quantity of a history
    panel (``displacement``, ``contact_force``, ``velocity``) or ``hysteresis <storey>``;
    each line is labelled with its node, contact or storey name.
    """
    if kind == "pounding":
        return draw_pounding(result, level, fig)
    if result.plan:
        from pframe.plot.plan import draw_plan_level

        return draw_plan_level(result, level, kind, fig)
    Figure = matplotlib_figure()
    histories, loops = _level_content(result, level, kind)
    if not histories and not loops:
        return None
    rows = max(len(histories), len(loops))
    if not histories:
        size = (3.6 * len(loops) + 0.6, 3.6)
    elif not loops:
        size = (8.0, 2.3 * rows + 0.9)
    else:
        size = (10.5, 2.3 * rows + 0.9)
    if fig is None:
        fig = Figure(figsize=size, layout="constrained")
    if histories and loops:
        outer = fig.add_gridspec(1, 2, width_ratios=(1.75, 1.0))
        left = outer[0].subgridspec(len(histories), 1)
        right = outer[1].subgridspec(len(loops), 1)
    elif histories:
        left, right = fig.add_gridspec(len(histories), 1), None
    else:
        left, right = None, fig.add_gridspec(1, len(loops))

    first = None
    for i, (letter, quantity, title, names) in enumerate(histories):
        ax = fig.add_subplot(left[i, 0], sharex=first)
        first = first or ax
        history = result.histories[quantity]
        for j, name in enumerate(names):
            colour = (CONTACT_COLOURS[j % len(CONTACT_COLOURS)] if quantity == "contact_force"
                      else _building_colour(result, name.split("/", 1)[0]))
            ax.plot(history.time, history.column(name), label=name, linewidth=0.8, color=colour)
        ax.set_label(quantity)
        ax.set_title(f"({letter}) {title}", loc="left", fontsize="medium")
        ax.set_ylabel(axis_label(quantity, history.units), fontsize="small")
        # above the axes, beside the title: inside, it would hide the peaks it is about
        ax.legend(fontsize="x-small", loc="lower right", bbox_to_anchor=(1.0, 1.0), ncols=len(names),
                  frameon=False, borderaxespad=0.1, handlelength=1.5)
        _tidy(ax)
        if i == len(histories) - 1:
            ax.set_xlabel(axis_label("time", history.time_units), fontsize="small")
        else:
            ax.tick_params(labelbottom=False)

    drift, force = result.histories.get("story_drift"), result.histories.get("story_force")
    for i, (letter, building, story) in enumerate(loops):
        ax = fig.add_subplot(right[i, 0] if histories else right[0, i])
        x, y = _on_common_time(drift, force, story)
        ax.plot(x, y, linewidth=0.7, label=story, color=_building_colour(result, building))
        ax.set_label(f"hysteresis {story}")
        ax.set_title(f"({letter}) hysteresis, storey {story} (building {building})",
                     loc="left", fontsize="medium")
        ax.set_xlabel(axis_label("story_drift", drift.units), fontsize="small")
        ax.set_ylabel(axis_label("story_force", force.units), fontsize="small")
        _tidy(ax)
        # a loop panel is narrow: the default ticks of a drift in m run into each other
        ax.locator_params(axis="x", nbins=5)

    return _headed(fig, result, f"{result.title}: level {level}")


def prepare(source: str | Path | Result, *, time_range: tuple[float, float] | None = None,
            dimensionless: bool = False) -> Result:
    """Read a result file and apply ``dimensionless`` then ``time_range`` (in the units of the
    time axis drawn: s, or tau when dimensionless)."""
    result = source if isinstance(source, Result) else read_result(source)
    if dimensionless and not result.is_dimensionless:
        system = result.attributes.get("units_system", "N-m-kg")
        system = system.decode() if isinstance(system, bytes) else str(system)
        if system != "N-m-kg":  # the scales below read the scene's numbers as SI
            raise InputError(f"{result.path}: --dimensionless draws a result in SI units, and "
                             f"this one is in {system} (docs/units.md); solve the scene with "
                             "output: {units: SI}, or {units: dimensionless}")
        reference = stored_scales(result.attributes) or reference_scales(result.input_yaml,
                                                                         str(result.path))
        result = result.dimensionless(reference)
    if time_range is not None:
        result = result.window(*time_range)
    return result


def figures(source: str | Path | Result, *, kind: str = "all", levels=None,
            time_range: tuple[float, float] | None = None, dimensionless: bool = False,
            report: Callable[[str], None] | None = None, units=None) -> dict:
    """The paper's figures of a result file, one per floor level.

    Parameters
    ----------
    source : str, Path or Result
        A result file of ``pframe solve`` (or one already read with :func:`prepare`).
    kind : {"all", "histories", "hysteresis", "pounding", "links", "torsion", "supports"}
        All panels, the histories (a)-(c) only, the hysteresis loops only, the gap
        closing of each contact (:func:`draw_pounding`; levels with contacts only), or every
        link's force history and force-deformation loop (one figure, ``"links"``). A scene in
        plan is drawn by :mod:`pframe.plot.plan`: its levels along x and y, and with ``"all"``
        (every level) or ``"torsion"`` the torsional irregularity of its storeys (one figure,
        ``"torsion"``); ``"supports"``: each support's ground acceleration and displacement
        and each contact's relative ground displacement (one figure,
        :mod:`pframe.plot.supports`).
    levels : sequence of str or int, optional
        The floor levels to draw (default: every level with something to draw).
    time_range : (float, float), optional
        Draw ``start <= t <= stop`` only, in the units of the time axis drawn.
    dimensionless : bool
        Draw the paper's dimensionless variables (tau, x = X / l_e, ...), scaled by the
        scene's sine excitation; a file written dimensionless is drawn so in any case.
    report : callable, optional
        Called with each note on panels left out (see :func:`notes`).
    units : str or dict, optional
        ``"engineering"`` (mm, mm/s, kN), a string such as ``"mm,kN"`` or a mapping
        ``{"m": "mm", "N": "kN"}`` (not with ``dimensionless``).

    Returns
    -------
    dict
        ``level -> matplotlib.figure.Figure``, in level order (then ``"torsion"``).

    Raises
    ------
    InputError
        Unreadable file, unknown level or kind, or nothing to plot.
    """
    if kind not in KINDS:
        raise InputError(f"unknown kind {kind!r}; choose one of {', '.join(KINDS)}")
    matplotlib_figure()
    if kind == "links":  # one figure of every link (pframe.plot.links)
        if dimensionless or units is not None or levels is not None:
            raise InputError("--kind links draws in the file's units, every link: leave out "
                             "dimensionless, units and levels")
        return link_figures(source if not isinstance(source, Result) else source.path,
                            time_range=time_range)
    if kind == "supports":  # one figure of the supports' motions (pframe.plot.supports)
        from pframe.plot.supports import support_figures

        if dimensionless or units is not None or levels is not None:
            raise InputError("--kind supports draws in the file's units, every support: leave "
                             "out dimensionless, units and levels")
        return support_figures(source if not isinstance(source, Result) else source.path,
                               time_range=time_range)
    result = prepare(source, time_range=time_range, dimensionless=dimensionless)
    if units is not None:
        if dimensionless:
            raise InputError("give units or dimensionless, not both")
        result = result.in_units(units)
    if kind == "torsion" and not result.plan:
        raise InputError(f"{result.path}: --kind torsion draws the storeys of buildings in "
                         "plan, and this result's scene is planar (its floors move along x "
                         "only): it has no torsion")
    if kind == "torsion" and levels is not None:
        raise InputError("--kind torsion draws every storey of every building in one figure: "
                         "leave out --story")
    found = notes(result, kind)
    order = result.levels.order
    if levels is not None:
        levels = [str(level) for level in levels]
        unknown = [level for level in levels if level not in order]
        if unknown:
            raise InputError(f"{result.path}: no floor level {', '.join(unknown)}; "
                             f"the levels are {', '.join(order)}")
    figs = {}
    for level in (levels if levels is not None else order) if kind != "torsion" else ():
        fig = draw_level(result, level, kind)
        if fig is not None:
            figs[level] = fig
    if result.plan and (kind == "torsion" or (kind == "all" and levels is None)):
        from pframe.plot.plan import torsion_figures

        figs.update(torsion_figures(result, kind))
    if not figs:
        where = f" at level {', '.join(levels)}" if levels is not None else ""
        why = "; ".join(found) or "no history of a node, storey or contact"
        raise InputError(
            f"{result.path}: nothing to plot for --kind {kind}{where}: {why}. The figures draw "
            "the histories of displacement, velocity, contact_force, story_drift and "
            "story_force" + (" (and of a scene in plan point_displacement and point_drift)"
                             if result.plan else "")
            + ": list them in a recorder of kind history and solve again.")
    if report is not None:
        for note in found:
            report(note)
    return figs


# ---------------------------------------------------------------------------------------------
# the links' figure (``kind="links"``): for each link (damper, coupling, tuned mass spring)
# its force history and its force against its deformation, the loop whose area is what it
# dissipated


def link_figures(path: str | Path, *, time_range=None) -> dict:
    """``{"links": Figure}``: one row per link, its force history (left) and its force
    against its deformation (right). Needs the ``link_force`` and ``link_deformation``
    histories."""
    from pframe.api import open as open_result

    Figure = matplotlib_figure()
    ds = open_result(path)
    missing = [q for q in ("link_force", "link_deformation") if q not in ds]
    if "link" not in ds.dims:
        raise InputError(f"{path}: the scene has no links: nothing to plot for --kind links")
    if missing:
        raise InputError(f"{path}: the file has no {' and no '.join(missing)} history: list "
                         "link_force and link_deformation in a recorder of kind history and "
                         "solve again")
    force, stretch = ds["link_force"], ds["link_deformation"]
    time = force.dims[0]
    if time_range is not None:
        start, stop = time_range
        force = force.sel({time: slice(start, stop)})
        stretch = stretch.sel({time: slice(start, stop)})
    names = [str(n) for n in ds["link"].values]
    rows = len(names)
    fig = Figure(figsize=(10.0, 2.4 * rows + 0.8), layout="constrained")
    axes = fig.subplots(rows, 2, squeeze=False, width_ratios=(1.8, 1.0))
    t = force[time].values
    for i, name in enumerate(names):
        f = force.isel(link=i).values
        d = stretch.isel(link=i).values
        left, right = axes[i]
        left.plot(t, f, color="C0", linewidth=0.9, label=name)
        left.set_title(f"({chr(97 + 2 * i)}) link {name}: force history", loc="left",
                       fontsize="medium")
        left.set_ylabel(f"force ({force.attrs.get('units', 'N')})", fontsize="small")
        left.set_gid("link_force " + name)
        right.plot(d, f, color="C3", linewidth=0.8, label=name)
        right.set_title(f"({chr(98 + 2 * i)}) force against deformation", loc="left",
                        fontsize="medium")
        right.set_xlabel(f"deformation ({stretch.attrs.get('units', 'm')})", fontsize="small")
        right.set_gid("link_loop " + name)
        for ax in (left, right):
            ax.grid(True, alpha=0.3, linewidth=0.6)
            ax.tick_params(labelsize=8)
        if np.all(np.isnan(f)):
            left.text(0.5, 0.5, "not computed", transform=left.transAxes, ha="center")
    axes[-1][0].set_xlabel(f"time ({force[time].attrs.get('units', 's')})", fontsize="small")
    fig.suptitle(f"{ds.attrs.get('title', '')}: links", fontsize="medium")
    return {"links": fig}
