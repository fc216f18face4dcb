"""The dimension of every number a scene file may hold, by where it stands.

Used to scale a scene (:mod:`pframe.nondim.similitude`) and to list its governing variables
(:mod:`pframe.nondim.scene_variables`). Built-in laws are listed here; a plug-in law declares
its fields with a class attribute ``dimensions = {"field": "N/m", ...}`` (unit strings as
:func:`pframe.nondim.dimensions.parse_units` reads them). A numeric field whose dimension is
unknown is an error rather than a guess: scaling it wrongly would silently break similarity.
"""

from __future__ import annotations

from pframe.errors import InputError
from pframe.nondim.dimensions import QUANTITY, Dimension, parse_units

#: fields that hold no number (selectors, flags, names, choices)
NON_NUMERIC = frozenset({"law", "material", "keep_tension", "formula", "name", "nodes"})

_STIFFNESS_FORM = {"stiffness": "stiffness", "frequency": "frequency",
                   "frequency_ratio": "dimensionless", "restitution": "dimensionless"}
_HERTZ_FORM = {"stiffness": "hertz_stiffness", "restitution": "dimensionless"}

#: (kind, law) -> field -> quantity name of :data:`pframe.nondim.dimensions.QUANTITY`
LAW_FIELDS = {
    ("material", "elastic"): {"stiffness": "stiffness"},
    ("material", "bilinear"): {"stiffness": "stiffness", "yield_drift": "length",
                               "yield_force": "force", "alpha": "dimensionless"},
    ("contact", "linear"): _STIFFNESS_FORM,
    ("contact", "kelvin"): _STIFFNESS_FORM,
    ("contact", "improved_kelvin"): _STIFFNESS_FORM,
    ("contact", "hertz"): _HERTZ_FORM,
    ("contact", "hertzdamp"): _HERTZ_FORM,
    ("contact", "jankowski"): _HERTZ_FORM,
}


def law_field_dimension(kind: str, law: str, field: str) -> Dimension | None:
    """Dimension of ``field`` of a storey material or contact law; None if not numeric.

    Raises
    ------
    InputError
        For a numeric field of a law that declares no dimension for it.
    """
    if field in NON_NUMERIC:
        return None
    table = LAW_FIELDS.get((kind, law))
    if table is not None and field in table:
        return QUANTITY[table[field]]
    from pframe.laws import get_law

    declared = getattr(get_law(kind, law), "dimensions", None) or {}
    if field in declared:
        try:
            return parse_units(declared[field])
        except ValueError as exc:
            raise InputError(f"{kind} law {law!r} declares field {field!r} as {exc}") from None
    what = "material" if kind == "material" else "contact law"
    raise InputError(
        f"the dimension of field {field!r} of {what} {law!r} is unknown; a plug-in law declares "
        f"it with a class attribute dimensions = {{{field!r}: 'N/m', ...}} (unit strings such "
        "as 'N/m', 'm', 'rad/s', '1')")


#: fields outside the laws: path pattern (``*`` any key or index) -> quantity name
SCENE_FIELDS = {
    ("buildings", "*", "mass"): "mass",
    ("buildings", "*", "floors"): "dimensionless",
    ("damping", "modes"): "dimensionless",
    ("buildings", "*", "damping", "modes"): "dimensionless",
    ("nodes", "*", "mass"): "mass",
    ("contacts", "*", "gap"): "length",
    ("damping", "ratio"): "dimensionless",
    ("buildings", "*", "damping", "ratio"): "dimensionless",
    ("excitation", "amplitude"): "acceleration",
    ("excitation", "frequency"): "frequency",
    ("excitation", "cycles"): "dimensionless",
    ("excitation", "duration"): "time",
    ("excitation", "scale"): "acceleration",  # a factor on the record's accelerations
    ("excitation", "pga"): "acceleration",
    ("excitation", "period"): "time",  # a record's is of its file's time axis: kept there
    ("initial_conditions", "displacement", "*"): "length",
    ("initial_conditions", "velocity", "*"): "velocity",
    ("analysis", "dt"): "time",
    ("analysis", "duration"): "time",
    ("analysis", "newton", "tolerance"): "dimensionless",
    ("analysis", "newton", "absolute_tolerance"): "length",
    ("analysis", "newton", "max_iterations"): "dimensionless",
    ("analysis", "integrator", "*"): "dimensionless",  # Newmark, HHT, alpha coefficients
    ("output", "scales", "m_b"): "mass",
    ("output", "scales", "a_p"): "acceleration",
    ("output", "scales", "w_p"): "frequency",
}


def scene_field_dimension(path: tuple) -> Dimension | None:
    """Dimension of the number at ``path`` of a scene outside the law parameters, or None."""
    for pattern, quantity in SCENE_FIELDS.items():
        if len(pattern) == len(path) and all(p in ("*", k) for p, k in zip(pattern, path)):
            return QUANTITY[quantity]
    return None

