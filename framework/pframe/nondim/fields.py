"""The dimension of every number a scene file may hold, by where it stands.

Used to scale a scene (:mod:`pframe.nondim.similitude`) and to list its governing variables
(:mod:`pframe.nondim.scene_variables`). Every law, built-in or plug-in, declares its fields
with the class attribute ``dimensions = {"field": "stiffness" | "N/m" | ...}`` (a quantity of
:data:`pframe.nondim.dimensions.QUANTITY` or a unit string as
:func:`pframe.nondim.dimensions.parse_units` reads it). A numeric field whose dimension is
unknown is an error rather than a guess: scaling it wrongly would silently break similarity.
"""

from __future__ import annotations

from pframe.errors import InputError
from pframe.nondim.dimensions import QUANTITY, Dimension, parse_units

#: fields that hold no number (selectors, flags, names, choices)
NON_NUMERIC = frozenset({"law", "material", "keep_tension", "formula", "name", "nodes",
                         "calibration"})


def law_field_dimension(kind: str, law: str, field: str) -> Dimension | None:
    """Dimension of ``field`` of a storey material or contact law; None if not numeric.

    Raises
    ------
    InputError
        For a numeric field of a law that declares no dimension for it.
    """
    if field in NON_NUMERIC:
        return None
    from pframe.laws import get_law

    cls = get_law(kind, law)
    declared = getattr(cls, "dimensions", None) or {}
    if field in declared:
        return dimension_of(declared[field], kind, law, field)
    what = "material" if kind == "material" else "contact law"
    reason = (getattr(cls, "undimensioned", None) or {}).get(field)
    if reason:  # a field whose dimension depends on another field's value (the law says why)
        raise InputError(f"field {field!r} of {what} {law!r} has no fixed dimension: {reason}")
    raise InputError(
        f"the dimension of field {field!r} of {what} {law!r} is unknown; a law declares it "
        f"with a class attribute dimensions = {{{field!r}: 'N/m', ...}} (a quantity such as "
        "'stiffness' or 'length', or a unit string such as 'N/m', 'm', 'rad/s', '1'; "
        "docs/contact-laws.md)")


def dimension_of(declared: str, kind: str = "", law: str = "", field: str = "") -> Dimension:
    """The dimension a law declares for a field or variable: a quantity name of
    :data:`QUANTITY` or a unit string."""
    if declared in QUANTITY:
        return QUANTITY[declared]
    try:
        return parse_units(declared)
    except ValueError as exc:
        raise InputError(f"{kind} law {law!r} declares {field!r} as {exc}") from None


#: fields outside the laws: path pattern (``*`` any key or index) -> quantity name
SCENE_FIELDS = {
    ("buildings", "*", "mass"): "mass",
    ("buildings", "*", "floors"): "dimensionless",
    ("damping", "modes"): "dimensionless",
    ("buildings", "*", "damping", "modes"): "dimensionless",
    ("buildings", "*", "height"): "length",  # one for all storeys, or each (a list)
    ("buildings", "*", "park_ang", "ultimate_drift"): "length",
    ("buildings", "*", "park_ang", "beta"): "dimensionless",
    ("nodes", "*", "mass"): "mass",
    ("stories", "*", "height"): "length",
    ("stories", "*", "gravity_load"): "force",
    ("stories", "*", "park_ang", "ultimate_drift"): "length",
    ("stories", "*", "park_ang", "beta"): "dimensionless",
    ("contacts", "*", "gap"): "length",
    ("contacts", "*", "at"): "dimensionless",  # a fraction of the struck storey's height
    ("contacts", "*", "shear_capacity"): "force",
    ("damping", "ratio"): "dimensionless",
    ("buildings", "*", "damping", "ratio"): "dimensionless",
    ("excitation", "amplitude"): "acceleration",
    ("excitation", "frequency"): "frequency",
    ("excitation", "cycles"): "dimensionless",
    ("excitation", "duration"): "time",
    ("excitation", "scale"): "acceleration",  # a factor on the record's accelerations
    ("excitation", "pga"): "acceleration",
    ("excitation", "period"): "time",  # a record's is of its file's time axis: kept there
    ("excitation", "n"): "dimensionless",  # a cycloidal pulse's cycles
    ("excitation", "center"): "time",  # a Ricker wavelet's peak
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

