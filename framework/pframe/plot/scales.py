"""Axis labels, and the paper's dimensionless variables for ``--dimensionless``.

Wu et al. (2021), eq. (6) and (8c), with the reference scales of the right structure's floor
mass ``m_b`` and the sine excitation ``a_p sin(w_p t)`` (chosen as for dimensionless result
files, see :func:`reference_scales`):

    tau = w_p t,   x = X / l_e  with  l_e = a_p / w_p^2,   x' = dx/dtau = V w_p / a_p,
    x'' = A / a_p,   forces F / (m_b a_p).

A value is converted by its ``units`` attribute (s, m, m/s, m/s^2, N; a rotation in rad is
already dimensionless, an angular velocity in rad/s becomes d theta / d tau), so every variable
of a result file has its scale without a table of variables.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from pframe.errors import InputError

#: quantity -> (SI axis label without units, dimensionless symbol in mathtext)
LABELS = {
    "time": ("time", r"$\tau = \omega_p t$"),
    "displacement": ("displacement", r"$x = X / l_e$"),
    "velocity": ("velocity", r"$\dot{x} = \mathrm{d}x / \mathrm{d}\tau$"),
    "acceleration": ("acceleration", r"$\ddot{x} = \ddot{X} / a_p$"),
    "contact_force": ("pounding force", r"$F_p / (m_b a_p)$"),
    "contact_penetration": ("penetration", r"$\delta / l_e$"),
    "story_drift": ("storey drift", r"$\Delta x = \Delta X / l_e$"),
    "story_force": ("storey shear", r"$F_s / (m_b a_p)$"),
    "displacement_rz": ("floor rotation", r"$\theta$"),
    "velocity_rz": ("floor angular velocity", r"$\mathrm{d}\theta / \mathrm{d}\tau$"),
}

#: the ``units`` attribute of a dimensionless variable
DIMENSIONLESS = "1"


def axis_label(quantity: str, units: str) -> str:
    """The label of an axis showing ``quantity`` in ``units`` (``"1"``: the paper's symbol)."""
    words, symbol = LABELS.get(quantity, (quantity.replace("_", " "), quantity))
    if units == DIMENSIONLESS:
        return symbol
    return f"{words} ({units})" if units else words


@dataclass(frozen=True)
class Reference:
    """The scales of the paper's dimensionless variables.

    Attributes
    ----------
    amplitude : float
        a_p (m/s^2), the sine excitation's amplitude.
    frequency : float
        w_p (rad/s), its circular frequency.
    mass : float
        m_b (kg), the reference floor mass.
    origin : str
        Where the scales come from, for the figure's footnote.
    """

    amplitude: float
    frequency: float
    mass: float
    origin: str

    @property
    def length(self) -> float:
        """l_e = a_p / w_p^2 (m), the excitation's length scale."""
        return self.amplitude / self.frequency**2

    def factor(self, units: str) -> float | None:
        """Multiplier from ``units`` to the dimensionless value; None for units without one."""
        a_p, w_p = self.amplitude, self.frequency
        return {"s": w_p, "m": 1.0 / self.length, "m/s": w_p / a_p, "m/s^2": 1.0 / a_p,
                "N": 1.0 / (self.mass * a_p), "rad": 1.0, "rad/s": 1.0 / w_p}.get(units)

    def describe(self) -> str:
        return (f"m_b = {self.mass:g} kg, a_p = {self.amplitude:g} m/s^2, "
                f"w_p = {self.frequency:g} rad/s, l_e = {self.length:.6g} m ({self.origin})")


def stored_scales(attributes: dict) -> Reference | None:
    """The reference scales a result file stores (``reference_m_b``, ``reference_a_p``,
    ``reference_w_p``: written by pframe from the scene as for dimensionless files), or None."""
    keys = ("reference_a_p", "reference_w_p", "reference_m_b")
    if not all(k in attributes for k in keys):
        return None
    a_p, w_p, m_b = (float(attributes[k]) for k in keys)
    return Reference(a_p, w_p, m_b, "the reference scales stored in the result")


def reference_scales(input_yaml: str | None, source: str) -> Reference:
    """The reference scales of the scene a result file holds (its ``input_yaml``).

    The scene's ``output.scales`` ``{m_b, a_p, w_p}`` when it gives them; otherwise, as for
    dimensionless result files, ``m_b`` is the first floor mass of the second building (of the
    only one, if there is one) -- the paper's right structure -- and ``a_p``, ``w_p`` are the
    amplitude and circular frequency of the sine excitation.

    Raises
    ------
    InputError
        The file holds no scene, or the scene gives no scales and its excitation is not a sine.
    """
    from pframe.errors import InputError as _Unreadable
    from pframe.yamltext import load

    try:
        raw = load(input_yaml) if input_yaml else None
    except _Unreadable:
        raw = None
    output = raw.get("output") if isinstance(raw, dict) else None
    given = output.get("scales") if isinstance(output, dict) else None
    if isinstance(given, dict) and {"m_b", "a_p", "w_p"} <= given.keys():
        return Reference(float(given["a_p"]), float(given["w_p"]), float(given["m_b"]),
                         "output.scales of the scene")
    excitation = raw.get("excitation") if isinstance(raw, dict) else None
    if not isinstance(excitation, dict) or excitation.get("kind") != "sine":
        raise InputError(
            f"{source}: --dimensionless scales by the sine excitation a_p sin(w_p t) of the "
            "scene (or its output.scales), and this file's scene (its input_yaml attribute) has "
            + ("no scene" if raw is None else "no sine excitation and no output.scales")
            + "; plot it without --dimensionless")

    from pframe.reader import parse_scene

    expanded = parse_scene(input_yaml, source=f"{source} (input_yaml)").expanded
    building = 1 if len(expanded.buildings) > 1 else 0
    first = int(np.flatnonzero(expanded.node_building == building)[0])
    return Reference(abs(float(excitation["amplitude"])), float(excitation["frequency"]),
                     float(expanded.masses[first]),
                     f"m_b of {expanded.node_names[first]}, a_p and w_p of the sine")
