"""pframe: earthquake-induced pounding between adjacent inelastic buildings.

A scene flows one way: YAML -> definition (:mod:`pframe.model`) -> plan (:mod:`pframe.assemble`)
-> compiled kernel (:mod:`pframe.kernel`) -> recorders and HDF5 (:mod:`pframe.record`).
"""

__version__ = "0.1.0"

from pframe.errors import EnvironmentFailure, InputError, PframeError  # noqa: E402

__all__ = ["EnvironmentFailure", "InputError", "PframeError", "__version__"]
