"""A scene's reference scales (m_b, a_p, w_p): the result file's ``reference_*`` attributes
and the units of a dimensionless one (:mod:`pframe.nondim.output`).

Apart from :mod:`pframe.nondim.scene_variables`, which lists every governing variable, so
that a run, which needs only these three, does not import what that needs (about 2 ms).
"""

from __future__ import annotations

import numpy as np

from pframe.errors import InputError
from pframe.excitation.characteristic import characteristic


def excitation_scales(scene, expanded) -> dict[str, float] | None:
    """``{"a_p": ..., "w_p": ...}`` of the scene's excitation
    (:func:`pframe.excitation.characteristic.characteristic`); None without one."""
    found = characteristic(scene.excitation, expanded.record)
    return None if found is None else {"a_p": found.amplitude, "w_p": found.frequency}


def reference_building(expanded) -> int:
    """The building whose floor mass is the mass scale: ``output.reference`` when the scene
    names it, else b (the second) if there is one, else the only one."""
    return expanded.reference


def reference_scales(scene, expanded) -> dict[str, float]:
    """``m_b``, ``a_p``, ``w_p`` for dimensionless output: ``output.scales`` if given, else the
    first floor mass of the reference building and the excitation's scales.

    Raises
    ------
    InputError
        For a scene without excitation and without ``output.scales``.
    """
    given = getattr(getattr(scene, "output", None), "scales", None)
    if given is not None:
        return {"m_b": given.m_b, "a_p": given.a_p, "w_p": given.w_p}
    excitation = excitation_scales(scene, expanded)
    if excitation is None or excitation["a_p"] == 0.0:
        raise InputError("dimensionless output needs reference scales: the scene has no "
                         "excitation to take a_p and w_p from; give output.scales "
                         "{m_b, a_p, w_p}")
    first = int(np.flatnonzero(expanded.node_building == reference_building(expanded))[0])
    return {"m_b": float(expanded.masses[first])} | excitation
