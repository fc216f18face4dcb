"""A scene written in another unit system (``units: kN-m-t``, docs/units.md), converted to SI
when it is read.

Every number is multiplied by the SI value of one unit of its dimension
(:meth:`pframe.units.UnitSystem.factor`): the dimension of a scene field from
:data:`UNIT_FIELDS` (:data:`pframe.nondim.fields.SCENE_FIELDS` and the fields a similitude
leaves alone: soil, stochastic motions), of a law's parameter from the law's declarations
(``dimensions``; ``dimensions_given`` for one whose dimension depends on another field's
value). A number of unknown dimension is refused: it would otherwise be read as SI.
"""

from __future__ import annotations

import functools

from pframe.nondim.dimensions import DIMENSIONLESS, QUANTITY, Dimension, parse_units
from pframe.nondim.fields import SCENE_FIELDS
from pframe.nondim.similitude import walk_scene
from pframe.units import UnitSystem

#: numbers whose unit a field names whatever the scene's system: kept as written (the
#: stochastic model's predictive equations take R_rup in km and Vs30 in m/s)
FIXED_UNITS = {"distance": "km", "vs30": "m/s"}

_STOCHASTIC = {
    "seed": "dimensionless", "magnitude": "dimensionless", "scale": "dimensionless",
    "intensity": "m^2/s^3", "ground_frequency": "frequency", "ground_damping": "dimensionless",
    "filter_frequency": "frequency", "filter_damping": "dimensionless", "duration": "time",
    "step": "time",
    ("parameters", "arias"): "velocity", ("parameters", "d595"): "time",
    ("parameters", "tmid"): "time", ("parameters", "frequency"): "frequency",
    ("parameters", "slope"): "1/s^2", ("parameters", "damping"): "dimensionless",
    ("envelope", "rise"): "time", ("envelope", "plateau"): "time",
    ("envelope", "decay"): "frequency", ("envelope", "d595"): "time",
    ("envelope", "tmid"): "time",
}
_SOIL = {
    "shear_wave_velocity": "velocity", "poisson": "dimensionless", "density": "density",
    "sway_stiffness": "stiffness", "sway_damping": "damping_coefficient",
    "rocking_stiffness": "energy",  # N m/rad
    "rocking_damping": "kg m^2/s",  # N m s/rad
    ("foundation", "width"): "length", ("foundation", "length"): "length",
    ("foundation", "radius"): "length", ("foundation", "mass"): "mass",
    ("foundation", "rotational_inertia"): "inertia",
}


def _motion_places() -> list[tuple]:
    """Every place a plain motion stands in a scene (the patterns of SCENE_FIELDS' motions)."""
    places = {pattern[:-1] for pattern in SCENE_FIELDS
              if pattern[-1] == "amplitude" and "coherency" not in pattern}
    return sorted(places | {("excitation", "motion"), ("excitation", "record")}, key=len)


def _unit_fields() -> dict:
    out = dict(SCENE_FIELDS)
    for place in _motion_places():
        # a record's (and a stochastic motion's) scale is a factor on the motion: its
        # accelerations are in the units of the file (a similitude scales the factor instead)
        out[place + ("scale",)] = "dimensionless"
        for key, quantity in _STOCHASTIC.items():
            out[place + (key if isinstance(key, tuple) else (key,))] = quantity
        for key in FIXED_UNITS:
            out[place + (key,)] = "fixed"
    for key, quantity in _SOIL.items():
        out[("buildings", "*", "soil") + (key if isinstance(key, tuple) else (key,))] = quantity
    return out


#: the dimension of every number of a scene outside the laws' parameters, by path: a
#: quantity of :data:`pframe.nondim.dimensions.QUANTITY`, a unit string, or ``fixed``
UNIT_FIELDS = _unit_fields()


@functools.lru_cache(maxsize=4096)  # a sweep converts the same paths for every variant
def unit_field_dimension(path: tuple) -> Dimension | None:
    """The dimension of the number at ``path`` for a conversion of units (a ``fixed`` one
    is dimensionless there: it is not converted); None where unknown."""
    for pattern, quantity in UNIT_FIELDS.items():
        if len(pattern) == len(path) and all(p in ("*", k) for p, k in zip(pattern, path)):
            if quantity == "fixed":
                return DIMENSIONLESS
            return QUANTITY[quantity] if quantity in QUANTITY else parse_units(quantity)
    return None


#: top-level keys that hold no number to convert
_KEPT = ("title", "recorders", "units")


def to_si(data: dict, system: UnitSystem) -> dict:
    """A scene's data written in ``system``, in SI: every number times the SI value of one
    unit of its dimension. The data of an SI scene is returned as it is (not copied).

    Raises
    ------
    SimilitudeError
        For a number whose dimension is unknown, with its ``path``.
    """
    if system.si:
        return data

    def factor_of(dimension: Dimension) -> float:
        return system.factor(*dimension.exponents)

    out = walk_scene({k: v for k, v in data.items() if k not in _KEPT}, factor_of,
                     unit_field_dimension, by_value=True)
    return {k: (data[k] if k in _KEPT else out[k]) for k in data}
