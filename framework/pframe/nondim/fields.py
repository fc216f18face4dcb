"""The dimension of every number a scene file may hold, by where it stands.

Used to scale a scene (:mod:`pframe.nondim.similitude`) and to list its governing variables
(:mod:`pframe.nondim.scene_variables`). Every law, built-in or plug-in, declares its fields
with the class attribute ``dimensions = {"field": "stiffness" | "N/m" | ...}`` (a quantity of
:data:`pframe.nondim.dimensions.QUANTITY` or a unit string as
:func:`pframe.nondim.dimensions.parse_units` reads it). A numeric field whose dimension is
unknown is an error rather than a guess: scaling it wrongly would silently break similarity.
"""

from __future__ import annotations

from typing import ForwardRef, get_args

from pframe.errors import InputError
from pframe.nondim.dimensions import QUANTITY, Dimension, parse_units

#: fields that hold no number (selectors, flags, names, choices)
NON_NUMERIC = frozenset({"law", "material", "keep_tension", "formula", "name", "nodes",
                         "calibration"})


def law_field_dimension(kind: str, law: str, field: str, given: dict | None = None
                        ) -> Dimension | None:
    """Dimension of ``field`` of a storey material or contact law; None if not numeric.
    ``given``: the law's fields as a scene writes them, for a field whose dimension depends
    on another's value (a law's ``dimensions_given``); None refuses such a field.

    Raises
    ------
    InputError
        For a numeric field of a law that declares no dimension for it.
    """
    from pframe.laws import get_law

    return field_dimension(get_law(kind, law), field, given)


def field_dimension(cls, field: str, given: dict | None = None) -> Dimension | None:
    """:func:`law_field_dimension` of the law class ``cls``."""
    if field in NON_NUMERIC:
        return None
    declared = getattr(cls, "dimensions", None) or {}
    if field in declared:
        return dimension_of(declared[field], cls.kind, cls.name, field)
    what = "material" if cls.kind == "material" else "contact law"
    reason = (getattr(cls, "undimensioned", None) or {}).get(field)
    by_value = getattr(cls, "dimensions_given", None)
    if reason and given is not None and by_value is not None:
        units = by_value(given).get(field)
        if units is not None:
            return dimension_of(units, cls.kind, cls.name, field)
    if reason:  # a field whose dimension depends on another field's value (the law says why)
        raise InputError(f"field {field!r} of {what} {cls.name!r} has no fixed dimension: "
                         f"{reason}")
    raise InputError(
        f"the dimension of field {field!r} of {what} {cls.name!r} is unknown; a law declares "
        f"it with a class attribute dimensions = {{{field!r}: 'N/m', ...}} (a quantity such as "
        "'stiffness' or 'length', or a unit string such as 'N/m', 'm', 'rad/s', '1'; "
        "docs/contact-laws.md)")


def check_declared(cls) -> None:
    """Refuse a law with a numeric field that declares neither a dimension nor why it has
    none (``undimensioned``): its governing variables cannot be listed in full, and a Pi
    form without one of them is incomplete (``pframe pi``). A law with the default
    ``governing``, which lists every packed parameter under its own name, needs a dimension
    for each of them (an ``undimensioned`` one is refused with its reason: the law must
    list it in a form of fixed dimension, in its own ``governing``).

    Raises
    ------
    InputError
        Naming the law, the field and the declaration it needs.
    """
    from pframe.laws import Law

    for name, info in cls.Params.model_fields.items():
        if name not in (getattr(cls, "undimensioned", None) or {}) and _numeric(info.annotation):
            field_dimension(cls, name)
    if getattr(cls.governing, "__func__", None) is Law.governing.__func__:
        for name in cls.param_names:
            field_dimension(cls, name)


def _numeric(annotation) -> bool:
    """Whether a field's annotation admits a number (a float or int, bare, in a union or in
    ``Annotated``; not a bool, not a ``Literal`` choice). One not yet resolved (a forward
    reference) may: it counts as numeric rather than pass unchecked."""
    if annotation is bool:
        return False
    if annotation in (float, int) or isinstance(annotation, (str, ForwardRef)):
        return True
    return any(_numeric(a) for a in get_args(annotation) if isinstance(a, type) or get_args(a))


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
    ("excitation", "baseline", "degree"): "dimensionless",  # a record's baseline correction
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
    # limits (pframe.limits): a drift ratio and a code's factors are numbers; an acceleration
    # in g is an acceleration in a fixed unit, scaled as one
    ("limits", "drift_ratio"): "dimensionless",
    ("limits", "code", "redundancy"): "dimensionless",
    ("limits", "code", "factor"): "dimensionless",
    ("limits", "acceleration"): "acceleration",
    ("limits", "acceleration_g"): "acceleration",
    # buildings in plan (docs/plan.md): coordinates and sizes are lengths, directions and
    # angles are numbers, a polar inertia is kg m^2
    ("buildings", "*", "origin"): "length",
    ("buildings", "*", "angle"): "dimensionless",
    ("buildings", "*", "plan", "size"): "length",
    ("buildings", "*", "plan", "outline"): "length",
    ("buildings", "*", "centre_of_mass"): "length",
    ("buildings", "*", "polar_inertia"): "inertia",
    ("buildings", "*", "points", "*"): "length",
    ("buildings", "*", "lines", "*", "position"): "length",
    ("buildings", "*", "lines", "*", "direction"): "dimensionless",
    ("buildings", "*", "lines", "*", "storeys"): "dimensionless",
    ("nodes", "*", "centre_of_mass"): "length",
    ("nodes", "*", "polar_inertia"): "inertia",
    ("stories", "*", "position"): "length",
    ("stories", "*", "direction"): "dimensionless",
    ("contacts", "*", "points"): "length",
    ("contacts", "*", "normal"): "dimensionless",
    ("links", "*", "points"): "length",
    ("links", "*", "direction"): "dimensionless",
    ("excitation", "angle"): "dimensionless",
}
# each of two components is a motion of its own, with a motion's fields
SCENE_FIELDS.update({("excitation", axis) + pattern[1:]: quantity
                     for axis in ("x", "y") for pattern, quantity in list(SCENE_FIELDS.items())
                     if pattern[0] == "excitation" and pattern != ("excitation", "angle")})
# a support's own motion and the motion a wave passage carries are motions too
_MOTION_FIELDS = [(pattern[1:], quantity) for pattern, quantity in SCENE_FIELDS.items()
                  if pattern[0] == "excitation"]
SCENE_FIELDS.update({("supports", "*", "excitation") + rest: q for rest, q in _MOTION_FIELDS})
SCENE_FIELDS.update({("excitation", "motion") + rest: q for rest, q in _MOTION_FIELDS})
SCENE_FIELDS.update({("excitation", "record") + rest: q for rest, q in _MOTION_FIELDS})
SCENE_FIELDS.update({
    ("supports", "*", "position"): "length",
    ("supports", "*", "site", "frequency"): "frequency",
    ("supports", "*", "site", "damping"): "dimensionless",
    ("excitation", "seed"): "dimensionless",  # a coherent simulation's
    ("excitation", "coherency", "incoherence"): "dimensionless",
    ("excitation", "coherency", "shear_velocity"): "velocity",
    ("excitation", "coherency", "amplitude"): "dimensionless",
    ("excitation", "coherency", "alpha"): "dimensionless",
    ("excitation", "coherency", "k"): "length",
    ("excitation", "coherency", "f0"): "frequency",
    ("excitation", "coherency", "b"): "dimensionless",
    ("excitation", "velocity"): "velocity",  # a wave passage's apparent velocity
    ("excitation", "direction"): "dimensionless",
})


def scene_field_dimension(path: tuple) -> Dimension | None:
    """Dimension of the number at ``path`` of a scene outside the law parameters, or None."""
    for pattern, quantity in SCENE_FIELDS.items():
        if len(pattern) == len(path) and all(p in ("*", k) for p, k in zip(pattern, path)):
            return QUANTITY[quantity]
    return None

