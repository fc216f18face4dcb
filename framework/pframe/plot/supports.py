"""The supports' figure (``pframe plot --kind supports``, docs/plotting.md#supports-figures):
what moved each support and what it did to the contacts across them.

Three panels on one time axis, each drawn where the file holds its history:

- (a) each support's ground acceleration (``ground_acceleration``), along x (solid) and y
  (dashed) for a scene in plan;
- (b) each support's ground displacement (``ground_displacement``);
- (c) each contact's relative ground displacement, the ground displacements' part of its
  closing (``contact_ground_displacement``: the left side's support's less the right
  side's, along the contact's normal).
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from pframe.errors import InputError
from pframe.plot.style import BUILDING_COLOURS, CONTACT_COLOURS, matplotlib_figure, tidy

#: (letter, quantity, title) of the panels, top to bottom
PANELS = (("a", "ground_acceleration", "ground acceleration of each support"),
          ("b", "ground_displacement", "ground displacement of each support"),
          ("c", "contact_ground_displacement", "relative ground displacement at each contact"))


def _lines(ax, variable, names, colours, label):
    """One line per name (and per direction: x solid, y dashed) of ``variable`` (t, name[,
    direction]) on ``ax``."""
    time = variable.dims[0]
    t = variable[time].values
    directions = [d for d in variable.dims if d not in (time, variable.dims[1])]
    for i, name in enumerate(names):
        column = variable.isel({variable.dims[1]: i})
        colour = colours[i % len(colours)]
        if directions:
            for j, direction in enumerate(column[directions[0]].values):
                ax.plot(t, column.isel({directions[0]: j}).values, color=colour,
                        linestyle=("-", "--")[j % 2], linewidth=0.9,
                        label=f"{label} {name} ({direction})")
        else:
            ax.plot(t, column.values, color=colour, linewidth=0.9, label=f"{label} {name}")


def support_figures(path: str | Path, *, time_range=None) -> dict:
    """``{"supports": Figure}``: the panels of the module of a result file, each where the
    file holds its history; an InputError naming what to record when it holds none."""
    from pframe.api import open as open_result

    Figure = matplotlib_figure()
    ds = open_result(path)
    if "support" not in ds.dims or ds.sizes["support"] < 2:
        raise InputError(f"{path}: the scene stands on one ground: --kind supports draws the "
                         "motions of a scene's several supports (docs/supports.md)")
    found = [(letter, q, title) for letter, q, title in PANELS if q in ds]
    if not found:
        raise InputError(f"{path}: the file has no history of ground_acceleration, "
                         "ground_displacement or contact_ground_displacement: list them in a "
                         "recorder of kind history and solve again")
    fig = Figure(figsize=(9.0, 2.3 * len(found) + 1.0), layout="constrained")
    axes = fig.subplots(len(found), 1, squeeze=False, sharex=True)[:, 0]
    for ax, (letter, quantity, title) in zip(axes, found):
        variable = ds[quantity]
        time = variable.dims[0]
        if time_range is not None:
            variable = variable.sel({time: slice(*time_range)})
        if quantity == "contact_ground_displacement":
            names, colours, label = ([str(n) for n in ds["contact"].values], CONTACT_COLOURS,
                                     "contact")
        else:
            names, colours, label = ([str(n) for n in ds["support"].values],
                                     BUILDING_COLOURS, "support")
        _lines(ax, variable, names, colours, label)
        if quantity == "contact_ground_displacement":
            ax.axhline(0.0, color="0.5", linewidth=0.6)
        ax.set_title(f"({letter}) {title}", loc="left", fontsize="medium")
        ax.set_ylabel(f"{quantity.replace('_', ' ')}\n({variable.attrs.get('units', '')})",
                      fontsize="small")
        ax.set_gid(quantity)
        ax.legend(fontsize="x-small", loc="upper right", ncols=min(len(names), 4))
        tidy(ax)
        if np.all(np.isnan(variable.values)):
            ax.text(0.5, 0.5, "not computed", transform=ax.transAxes, ha="center")
    time = ds[found[0][1]].dims[0]
    axes[-1].set_xlabel(f"time ({ds[time].attrs.get('units', 's')})", fontsize="small")
    said = ds.attrs.get("ground_displacement_method", "")
    missing = [f"({letter}) {q}" for letter, q, _ in PANELS if q not in ds]
    if missing:  # a panel left out is said, with what would draw it
        said = (f"not drawn: {', '.join(missing)}, which the file does not record (list "
                f"{' and '.join(q.split(' ')[1] for q in missing)} in a recorder of kind "
                "history to draw them)" + ("; " + said if said else ""))
    heading = f"{ds.attrs.get('title', '')}: the supports' motions".lstrip(": ")
    fig.suptitle(heading, fontsize="medium")
    if said:  # what is left out; how the displacements were had (a file, or integrated)
        from pframe.plot.style import fitted

        fig.supxlabel(fitted(said, fig.get_figwidth(), "x-small"), fontsize="x-small")
    return {"supports": fig}
