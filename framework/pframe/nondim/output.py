"""Dimensionless result files (Wu et al. 2021, eq. 6).

With the reference scales ``m_b``, ``a_p``, ``w_p`` and ``l_e = a_p / w_p^2``, a result
written with ``output: {units: dimensionless}`` holds

    tau = w_p t,   x = X / l_e,   v = V w_p / a_p,   a = A / a_p,   f = F / (m_b a_p)

and energies divided by ``m_b a_p l_e``. Two similar scenes (the same Pi numbers) then give
the same file, whatever their masses, frequencies and amplitudes. The conversion happens when
the file is written; the kernel always integrates in SI units.

A dimensional file is written in the scene's unit system (``units: kN-m-t``, docs/units.md):
each SI value divided by the SI value of one unit of its dimension, its ``units`` attribute
that system's (``kN``, ``kN m``, ``mm/s^2``).
"""

from __future__ import annotations

from dataclasses import dataclass, field

from pframe.units import SI, UnitSystem, describe

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
    """How results are written: in a unit system (``scales`` None; SI by default) or divided
    by the reference scales."""

    scales: dict | None = None
    system: UnitSystem = field(default=SI)

    @property
    def dimensionless(self) -> bool:
        return self.scales is not None

    @property
    def energy_units(self) -> str:
        """The units of the file's energies (``energy_*`` attributes)."""
        return "1" if self.dimensionless else self.units("J")

    def units(self, si_units: str) -> str:
        """The units a quantity of SI units ``si_units`` is written in, in a dimensional
        file (``si_units`` itself in SI, or for a quantity without mass or length)."""
        return self._system(si_units)[0]

    def _system(self, si_units: str) -> tuple[str, float]:
        """(units, SI value of one of them) of a quantity of SI units ``si_units``."""
        if self.system.si:
            return si_units, 1.0
        # the parser of units (pframe.nondim.dimensions) imported by a file in another system
        from pframe.nondim.dimensions import parse_units

        mass, length, time = parse_units(si_units).exponents
        if not mass and not length:
            return si_units, 1.0
        return self.system.symbol(mass, length, time), self.system.factor(mass, length)

    def _divisor(self, units: str):
        if self.scales is None or units not in _DIVISOR:
            return None, 1.0
        symbol, divisor = _DIVISOR[units]
        return symbol, divisor(self.scales["m_b"], self.scales["a_p"], self.scales["w_p"])

    def variable(self, data, units: str, long_name: str):
        """``(data, units, long_name)`` as written; quantities of other units stay SI."""
        if self.scales is None:
            written, factor = self._system(units)
            return (data if factor == 1.0 else data / factor), written, long_name
        symbol, divisor = self._divisor(units)
        if symbol is None:
            return data, units, long_name
        return data / divisor, "1", f"{long_name} (dimensionless, {symbol})"

    def restated(self, attrs: dict) -> dict:
        """Global attributes with their ``<name>_units`` (:func:`pframe.record.netcdf.
        with_units`) in this system: SI values of SI units converted (an acceleration in g
        stays in g; energies are converted already, :meth:`energy`)."""
        if self.scales is not None or self.system.si:
            return attrs
        out = dict(attrs)
        for name, value in attrs.items():
            units = attrs.get(f"{name}_units")
            if units is None or name.startswith("energy_") or isinstance(value, (str, bytes)):
                continue
            try:
                written, factor = self._system(units)
            except ValueError:  # "9.80665 m/s^2": a value in g
                continue
            out[name], out[f"{name}_units"] = value / factor, written
        return out

    def show(self, value: float, si_units: str, spec: str = ".4g") -> str:
        """An SI value as a message prints it in this system: ``0.021 m``, ``3.356 kN``."""
        written, factor = self._system(si_units)
        return f"{value / factor:{spec}} {written}"

    def time(self, seconds):
        """``(values, units, long_name)`` of a time coordinate."""
        if self.scales is None:
            return seconds, "s", "time since the start of the analysis"
        return seconds * self.scales["w_p"], "1", "dimensionless time tau = w_p t"

    def energy(self, joules: float) -> float:
        if self.scales is None:
            factor = self._system("J")[1]
            return joules if factor == 1.0 else joules / factor
        return joules / self._divisor("J")[1]

    def attributes(self, dt: float) -> dict:
        """Global attributes naming the unit system (``units_system``: N-m-kg, kN-m-t, ...,
        and what its units are), or describing the scales of a dimensionless file."""
        if self.scales is None:
            return {"units_system": self.system.name,
                    "units_system_description": describe(self.system)}
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
    from pframe.nondim.reference import reference_scales

    return OutputUnits(reference_scales(scene, expanded))
