"""Dimensionless result files (Wu et al. 2021, eq. 6).

With the reference scales ``m_b``, ``a_p``, ``w_p`` and ``l_e = a_p / w_p^2``, a result
written with ``output: {units: dimensionless}`` holds

    tau = w_p t,   x = X / l_e,   v = V w_p / a_p,   a = A / a_p,   f = F / (m_b a_p)

and energies divided by ``m_b a_p l_e``. Two similar scenes (the same Pi numbers) then give
the same file, whatever their masses, frequencies and amplitudes. The conversion happens when
the file is written; the kernel always integrates in SI units.
"""

from __future__ import annotations

from dataclasses import dataclass

#: SI units of a recorded quantity -> (symbol of the dimensionless variable, its divisor)
_DIVISOR = {
    "m": ("X / l_e", lambda m, a, w: a / w**2),
    "m/s": ("V w_p / a_p", lambda m, a, w: a / w),
    "m/s^2": ("A / a_p", lambda m, a, w: a),
    "N": ("F / (m_b a_p)", lambda m, a, w: m * a),
    "J": ("E / (m_b a_p l_e)", lambda m, a, w: m * a * a / w**2),
}


@dataclass(frozen=True)
class OutputUnits:
    """How results are written: SI (``scales`` None) or divided by the reference scales."""

    scales: dict | None = None

    @property
    def dimensionless(self) -> bool:
        return self.scales is not None

    def _divisor(self, units: str):
        if self.scales is None or units not in _DIVISOR:
            return None, 1.0
        symbol, divisor = _DIVISOR[units]
        return symbol, divisor(self.scales["m_b"], self.scales["a_p"], self.scales["w_p"])

    def variable(self, data, units: str, long_name: str):
        """``(data, units, long_name)`` as written; quantities of other units stay SI."""
        symbol, divisor = self._divisor(units)
        if symbol is None:
            return data, units, long_name
        return data / divisor, "1", f"{long_name} (dimensionless, {symbol})"

    def time(self, seconds):
        """``(values, units, long_name)`` of a time coordinate."""
        if self.scales is None:
            return seconds, "s", "time since the start of the analysis"
        return seconds * self.scales["w_p"], "1", "dimensionless time tau = w_p t"

    def energy(self, joules: float) -> float:
        return joules / self._divisor("J")[1]

    def attributes(self, dt: float) -> dict:
        """Global attributes describing the scales (none for SI)."""
        if self.scales is None:
            return {}
        m, a, w = self.scales["m_b"], self.scales["a_p"], self.scales["w_p"]
        return {
            "units_system": "dimensionless",
            "nondimensional_scales": (
                "tau = w_p t; x = X / l_e; v = V w_p / a_p; a = A / a_p; f = F / (m_b a_p); "
                f"energies E / (m_b a_p l_e); m_b = {m!r} kg, a_p = {a!r} m/s^2, "
                f"w_p = {w!r} rad/s, l_e = a_p / w_p^2 = {a / w**2!r} m"),
            "scale_m_b": float(m), "scale_a_p": float(a), "scale_w_p": float(w),
            "scale_l_e": float(a / w**2), "dtau": float(dt * w),
        }


def output_units(scene, expanded) -> OutputUnits:
    """The units a scene's result file is written in (``output.units``)."""
    output = getattr(scene, "output", None)
    if output is None or output.units != "dimensionless":
        return OutputUnits()
    from pframe.nondim.scene_variables import reference_scales

    return OutputUnits(reference_scales(scene, expanded))
