"""Pi-parameters: dimensions, Buckingham Pi groups, Pi-form scenes and similitude.

This package reads scene definitions and returns definitions or numbers; it never touches
the kernel, which does not know whether a scene came from Pi numbers (and it imports neither
numba nor h5py).

- :mod:`~pframe.nondim.dimensions`: exact M, L, T exponents; the quantities pframe uses.
- :mod:`~pframe.nondim.buckingham`: Pi groups from a dimension matrix (exact Gauss-Jordan).
- :mod:`~pframe.nondim.scene_variables`: the governing variables of any scene.
- :mod:`~pframe.nondim.reference`: its reference scales (m_b, a_p, w_p).
- :mod:`~pframe.nondim.scene_pi`: their Pi groups with the paper's names (``pframe pi``).
- :mod:`~pframe.nondim.pi_form`: scenes written in Pi numbers, expanded to dimensional ones.
- :mod:`~pframe.nondim.similitude`: scale ratios of scale models; scaling a scene.
- :mod:`~pframe.nondim.output`: dimensionless result files.
"""

import importlib
import sys
import types
from typing import TYPE_CHECKING

if TYPE_CHECKING:  # what the names below are, for type checkers and editors
    from pframe.nondim.buckingham import (
        DimensionalAnalysisError,
        Group,
        Variable,
        check_groups,
        null_space,
        pi_groups,
    )
    from pframe.nondim.dimensions import QUANTITY, Dimension, parse_units
    from pframe.nondim.output import OutputUnits, output_units
    from pframe.nondim.pi_form import PiScene, expand_pi, is_pi_form
    from pframe.nondim.reference import reference_scales
    from pframe.nondim.scene_pi import PiReport, scene_pi
    from pframe.nondim.scene_variables import scene_variables
    from pframe.nondim.similitude import Ratio, Similitude, SimilitudeError, scale_scene, similitude

#: public name -> the submodule defining it, imported when the name is first used (PEP 562),
#: so that one submodule (a result file needs only ``output``) does not import them all
_SOURCES = {
    "DimensionalAnalysisError": "buckingham",
    "Group": "buckingham",
    "Variable": "buckingham",
    "check_groups": "buckingham",
    "null_space": "buckingham",
    "pi_groups": "buckingham",
    "QUANTITY": "dimensions",
    "Dimension": "dimensions",
    "parse_units": "dimensions",
    "OutputUnits": "output",
    "output_units": "output",
    "PiScene": "pi_form",
    "expand_pi": "pi_form",
    "is_pi_form": "pi_form",
    "PiReport": "scene_pi",
    "scene_pi": "scene_pi",
    "reference_scales": "reference",
    "scene_variables": "scene_variables",
    "Ratio": "similitude",
    "Similitude": "similitude",
    "SimilitudeError": "similitude",
    "scale_scene": "similitude",
    "similitude": "similitude",
}

__all__ = [
    "QUANTITY",
    "Dimension",
    "DimensionalAnalysisError",
    "Group",
    "OutputUnits",
    "PiReport",
    "PiScene",
    "Ratio",
    "Similitude",
    "SimilitudeError",
    "Variable",
    "check_groups",
    "expand_pi",
    "is_pi_form",
    "null_space",
    "output_units",
    "parse_units",
    "pi_groups",
    "reference_scales",
    "scale_scene",
    "scene_pi",
    "scene_variables",
    "similitude",
]


#: the submodules, also reachable as attributes (``pframe.nondim.buckingham``) without an import
_SUBMODULES = frozenset(("buckingham", "dimensions", "emit", "fields", "output", "pi_form", "reference",
                         "scene_pi", "scene_variables", "similitude"))


def __getattr__(name: str):
    if name in _SOURCES:
        value = getattr(importlib.import_module(f"{__name__}.{_SOURCES[name]}"), name)
    elif name in _SUBMODULES:
        value = importlib.import_module(f"{__name__}.{name}")
    else:
        raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
    globals()[name] = value
    return value


def __dir__() -> list[str]:
    return sorted(set(globals()) | set(__all__) | _SUBMODULES)


class _Package(types.ModuleType):
    """Keeps ``pframe.nondim.similitude`` (and ``scene_pi``, ``scene_variables``) the function
    of that name, as ``from pframe.nondim import similitude`` gives, when the submodule of the
    same name is imported directly (the import system then sets the attribute to the module)."""

    def __setattr__(self, name, value):
        if isinstance(value, types.ModuleType) and _SOURCES.get(name) == name:
            value = getattr(value, name)
        super().__setattr__(name, value)


sys.modules[__name__].__class__ = _Package
