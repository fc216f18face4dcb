"""pframe: earthquake-induced pounding between adjacent inelastic buildings.

A scene flows one way: YAML or Python objects -> scene (:mod:`pframe.model`) -> plan
(:mod:`pframe.assemble`) -> compiled kernel (:mod:`pframe.kernel`) -> result file or
xarray Dataset (:mod:`pframe.record`). The public Python API (docs/python.md) is listed here,
once; its names load on first use, so ``import pframe`` stays light::

    import pframe
    scene = pframe.load("models/wu2021-eq14.yaml")      # or pframe.Scene(...) from objects
    ds = pframe.solve(scene)                            # xarray.Dataset, the file's layout
    ds.peak_displacement.to_series()
"""

__version__ = "0.1.0"

from pframe.errors import EnvironmentFailure, InputError, PframeError  # noqa: E402
from pframe.integrators import TABLE as _INTEGRATORS  # noqa: E402

#: public name -> module that defines it
_API = {
    # reading, running, results
    "load": "pframe.api", "solve": "pframe.api", "sweep": "pframe.sweep", "open": "pframe.api",
    "to_opensees": "pframe.api", "risk": "pframe.risk",
    "IncompleteRun": "pframe.api", "AccuracyWarning": "pframe.verdict",
    "summary": "pframe.tables", "impacts": "pframe.demands", "modes": "pframe.modal",
    # figures (matplotlib: pip install "pframe[plot]"); pframe.plot and pframe.sweep are also
    # packages, made callable (pframe._callable)
    "plot": "pframe.plot",
    # a scene from objects, with the names and fields of the YAML
    "Scene": "pframe.api", "Building": "pframe.api", "StoryProperties": "pframe.api",
    "Story": "pframe.api", "Contact": "pframe.api",
    "Node": "pframe.model.scene", "Rayleigh": "pframe.model.scene",
    "Modal": "pframe.model.scene",
    "Sine": "pframe.model.scene", "Record": "pframe.model.scene",
    "Cycloidal": "pframe.model.scene", "Ricker": "pframe.model.scene",
    "Stochastic": "pframe.model.scene",
    "Analysis": "pframe.model.scene", "Newton": "pframe.model.scene",
    "History": "pframe.model.scene", "Envelope": "pframe.model.scene",
    "InitialConditions": "pframe.model.scene", "Output": "pframe.model.scene",
    "OutputScales": "pframe.model.scene",
    # every integrator of pframe.integrators' table (which names them without loading them)
    **{cls: "pframe.integrators" for cls in _INTEGRATORS.values()},
}

__all__ = ["AccuracyWarning", "Analysis", "Building", "Contact", "Cycloidal", "Envelope",
           "EnvironmentFailure", "History", "IncompleteRun", "InitialConditions", "InputError",
           "Modal", "Newton", "Node", "Output", "OutputScales", "PframeError", "Rayleigh", "Record",
           "Ricker", "Scene", "Sine", "Stochastic", "Story", "StoryProperties", "__version__",
           "impacts", "load", "modes", "open", "plot", "risk", "solve", "summary", "sweep", "to_opensees"]
__all__ += list(_INTEGRATORS.values())


def __getattr__(name: str):
    module = _API.get(name)
    if module is None:
        raise AttributeError(f"module 'pframe' has no attribute {name!r}")
    import importlib

    imported = importlib.import_module(module)
    value = imported if module == f"pframe.{name}" else getattr(imported, name)
    globals()[name] = value
    return value


def __dir__() -> list[str]:
    return sorted(set(globals()) | set(__all__))
