"""Parametric sweeps: thousands of variants of one scene run as batches of the compiled kernel.

A sweep file names a base scene and the numbers to vary (docs/sweeps.md)::

    from pframe.sweep import load_sweep, run_sweep

    definition = load_sweep("models/sweeps/wu2021-pi-d.yaml")
    run_sweep(definition, "pi-d.nc")          # pframe.open("pi-d.nc")

``pframe.sweep(...)`` itself runs a sweep and returns its Dataset (:func:`pframe.api.sweep`).

Chunks of variants are saved as they finish and the result file is written from them, so a
sweep killed at any moment continues where it stopped; ``scheduler="tcp://HOST:PORT"`` sends
the chunks to a Dask cluster (the ``cluster`` extra).
"""

from pframe._callable import make_callable
from pframe.sweep.chunk import run_chunk
from pframe.sweep.definition import DEFAULT_RESPONSES, RESPONSES, SweepFile
from pframe.sweep.grid import parse
from pframe.sweep.reading import load_sweep, parse_sweep
from pframe.sweep.runner import SweepRun, run_sweep
from pframe.sweep.spec import SweepDefinition

__all__ = ["DEFAULT_RESPONSES", "RESPONSES", "SweepDefinition", "SweepFile", "SweepRun",
           "load_sweep", "parse", "parse_sweep", "run_chunk", "run_sweep"]


make_callable(__name__, "pframe.api", "sweep")  # pframe.sweep(...) runs a sweep
