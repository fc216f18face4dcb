"""Pi-parameters: dimensions, Buckingham Pi groups, Pi-form scenes and similitude.

This package reads scene definitions and returns definitions or numbers; it never touches
the kernel, which does not know whether a scene came from Pi numbers (and it imports neither
numba nor h5py).

- :mod:`~pframe.nondim.dimensions`: exact M, L, T exponents; the quantities pframe uses.
- :mod:`~pframe.nondim.buckingham`: Pi groups from a dimension matrix (exact Gauss-Jordan).
- :mod:`~pframe.nondim.scene_variables`: the governing variables of any scene.
- :mod:`~pframe.nondim.scene_pi`: their Pi groups with the paper's names (``pframe pi``).
- :mod:`~pframe.nondim.pi_form`: scenes written in Pi numbers, expanded to dimensional ones.
- :mod:`~pframe.nondim.similitude`: scale ratios of scale models; scaling a scene.
- :mod:`~pframe.nondim.output`: dimensionless result files.
"""

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
from pframe.nondim.scene_pi import PiReport, scene_pi
from pframe.nondim.scene_variables import reference_scales, scene_variables
from pframe.nondim.similitude import Ratio, Similitude, SimilitudeError, scale_scene, similitude

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
