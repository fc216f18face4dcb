"""The links' figure (``pframe plot --kind links``): for each link (damper, coupling, tuned
mass spring) its force history and its force against its deformation, the loop whose area is
what it dissipated."""

from __future__ import annotations

from pathlib import Path

import numpy as np

from pframe.errors import InputError


def link_figures(path: str | Path, *, time_range=None) -> dict:
    """``{"links": Figure}``: one row per link, its force history (left) and its force
    against its deformation (right). Needs the ``link_force`` and ``link_deformation``
    histories."""
    from pframe.api import open as open_result
    from pframe.plot.figure import matplotlib_figure

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
