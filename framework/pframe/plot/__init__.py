"""Figures of result files in the manner of Wu et al. (2021), Figures 3 to 5 (the ``plot``
extra: matplotlib).

One figure per floor level: displacement, pounding force and velocity histories of both
buildings' floors at that level, and the hysteresis loops of the storeys below them::

    from pframe.plot import figures, save

    figs = figures("eq14.nc", levels=[3])          # {"3": matplotlib Figure}
    save(figs, "eq14-level3.png")

``pframe.plot`` itself is callable (:func:`pframe.plot.api.plot`): ``pframe.plot(ds)`` draws
a Dataset or a file on the user's axes.

:mod:`~pframe.plot.data`, :mod:`~pframe.plot.levels` and :mod:`~pframe.plot.scales` need no
matplotlib; it is imported when a figure is drawn or saved.
"""

from pframe._callable import make_callable
from pframe.plot.data import History, Result, read_result
from pframe.plot.figure import KINDS, draw_level, figures, notes, prepare
from pframe.plot.levels import Levels, group_by_level
from pframe.plot.output import output_paths, save
from pframe.plot.scales import Reference, reference_scales

__all__ = ["KINDS", "History", "Levels", "Reference", "Result", "draw_level", "figures",
           "group_by_level", "notes", "output_paths", "prepare", "read_result",
           "reference_scales", "save"]


make_callable(__name__, "pframe.plot.api", "plot")  # pframe.plot(...) draws
