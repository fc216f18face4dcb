"""``pframe.plot``: figures of a result from Python (a Dataset or a file), on the user's axes.

Figures follow the user's matplotlib style (``plt.style.use``, ``rcParams``): font sizes are
relative, colours are the style's cycle (``C0``, ``C1``, ...). Without ``ax``/``fig`` the
figure is made with pyplot, so a notebook shows it.
"""

from __future__ import annotations

from pframe.errors import InputError


def _names(names):
    """``names`` as None or a list of text; an InputError otherwise."""
    from pframe.api import describe

    if names is None or isinstance(names, str):
        return names
    try:
        out = list(names)
    except TypeError:
        out = None
    if out is None or not all(isinstance(n, str) for n in out):
        raise InputError(f"pframe.plot: names is {describe(names)}; give a name or a list of names "
                         "(of nodes, storeys or contacts), as text")
    return out


def _drawing_area(ax, fig) -> None:
    """Refuse an ``ax`` that is not matplotlib's Axes, a ``fig`` that is not its Figure."""
    from matplotlib.axes import Axes
    from matplotlib.figure import Figure, SubFigure

    from pframe.api import describe

    if ax is not None and not isinstance(ax, Axes):
        raise InputError(f"pframe.plot: ax is {describe(ax)}; give matplotlib Axes (fig, ax = "
                         "plt.subplots()), or leave it out")
    if fig is not None and not isinstance(fig, (Figure, SubFigure)):
        raise InputError(f"pframe.plot: fig is {describe(fig)}; give a matplotlib Figure, or leave "
                         "it out")


def _time_range(value):
    """``(start, stop)`` as two finite numbers, or None; an InputError for anything else."""
    import math

    from pframe.api import describe

    if value is None:
        return None
    try:
        start, stop = (float(v) for v in value)
    except (TypeError, ValueError):
        raise InputError(f"pframe.plot: time_range is {describe(value)}; give (start, stop), "
                         "two numbers in the units of the time axis drawn") from None
    if not (math.isfinite(start) and math.isfinite(stop)):
        raise InputError(f"pframe.plot: time_range={value!r}: give two finite numbers")
    return start, stop


def plot(result, quantity: str | None = None, *, names=None, level=None, kind: str = "all",
         units=None, dimensionless: bool = False, time_range=None, ax=None, fig=None):
    """Draw a result of ``pframe.solve``/``pframe.open`` (or a result file's path).

    Two forms:

    - ``quantity`` given (``displacement``, ``velocity``, ``contact_force``, ``story_drift``,
      ``story_force``): its histories against time on ``ax`` (default: new axes), one line
      per name in ``names`` (default: every node, storey or contact); returns the axes;
    - otherwise the paper's figure of one floor ``level`` (default: the top level with a
      contact, else the top level) drawn into ``fig``; returns the figure. A scene in plan
      draws its floors along x and y, their rotations and the lines' drifts
      (:mod:`pframe.plot.plan`); ``kind="torsion"`` its storeys' torsional irregularity.

    A scene in plan's histories are named per component: ``displacement_x``,
    ``displacement_y``, ``displacement_rz``, ``point_drift_x``, ...

    ``units``: ``"engineering"`` (mm, mm/s, kN), a string such as ``"mm,kN"``, or a mapping
    ``{"m": "mm", "N": "kN"}``; ``dimensionless``: the paper's variables (tau, X / l_e, ...);
    ``time_range``: ``(start, stop)`` in the units of the time axis drawn.
    """
    from pframe.api import describe, flag_argument
    from pframe.plot.figure import draw_level, matplotlib_figure, prepare
    from pframe.plot.scales import axis_label

    matplotlib_figure()  # a clear message when matplotlib is missing
    dimensionless = flag_argument(dimensionless, "dimensionless", "pframe.plot")
    time_range = _time_range(time_range)
    for name, value in (("quantity", quantity), ("kind", kind)):
        if value is not None and not isinstance(value, str):
            raise InputError(f"pframe.plot: {name} is {describe(value)}: give its name, as text")
    names = _names(names)
    _drawing_area(ax, fig)
    data = prepare(result, time_range=time_range, dimensionless=dimensionless)
    if units is not None:
        if dimensionless:
            raise InputError("plot: give units or dimensionless, not both")
        data = data.in_units(units)
    if quantity is not None:
        history = data.histories.get(quantity)
        if history is None:
            recorded = ", ".join(data.histories) or "none"
            raise InputError(f"plot: {quantity!r} is not a recorded history of this result "
                             f"(recorded: {recorded}); add it to a history recorder")
        chosen = list(history.names) if names is None else (
            [names] if isinstance(names, str) else list(names))
        unknown = [n for n in chosen if n not in history.names]
        if unknown:
            raise InputError(f"plot: no {', '.join(unknown)} in {quantity}; choose from "
                             f"{', '.join(history.names)}")
        if ax is None:
            import matplotlib.pyplot as plt

            _, ax = plt.subplots(layout="constrained")
        for name in chosen:
            ax.plot(history.time, history.column(name), label=name)
        ax.set_xlabel(axis_label("time", history.time_units))
        ax.set_ylabel(axis_label(quantity, history.units))
        ax.ticklabel_format(axis="y", useOffset=False)
        ax.legend()
        return ax
    if kind == "torsion":  # one figure of every storey (a scene in plan)
        from pframe.plot.plan import torsion_figures

        if not data.plan:
            raise InputError("plot: kind 'torsion' draws buildings in plan; this result's "
                             "scene is planar")
        if fig is None:
            import matplotlib.pyplot as plt

            fig = plt.figure(layout="constrained", figsize=(8.0, 5.0))
        return torsion_figures(data, kind, fig=fig)["torsion"]
    order = data.levels.order
    if not order:
        raise InputError("plot: the result has no floor levels to draw")
    if level is None:
        with_contacts = [lv for lv in order if data.levels.contacts.get(lv)]
        level = (with_contacts or list(order))[-1]
    level = str(level)
    if level not in order:
        raise InputError(f"plot: no floor level {level}; the levels are {', '.join(order)}")
    if fig is None:
        import matplotlib.pyplot as plt

        fig = plt.figure(layout="constrained", figsize=(10.5, 7.8))
    drawn = draw_level(data, level, kind, fig=fig)
    if drawn is None:
        raise InputError(f"plot: nothing of kind {kind!r} to draw at level {level}")
    return drawn
