"""The parts of a scene that most scenes leave out: soil under a building (its foundation),
the Park-Ang damage index of its storeys, the limits a run is checked against.

Apart from :mod:`pframe.model.scene` so that a scene without them does not make their
models: the fields that hold them are made on demand (:func:`pframe.model.tagged.lazy_model`),
and this module is imported when a scene first gives one. Their names are also
:mod:`pframe.model.scene`'s.
"""

from typing import Literal

from pydantic import Field, model_validator

from pframe.model.parts import Base, Positive


class ParkAng(Base):
    """The Park-Ang damage index of a building's storeys, DI = d_max / d_u + beta E_h /
    (F_y d_u) (Park & Ang 1985; pframe summary): d_max the peak storey drift, E_h the storey's
    hysteretic energy, F_y its yield force (from its material)."""

    ultimate_drift: Positive | list[Positive] = Field(
        description="d_u: the storey's ultimate drift under monotonic loading (m), one for all "
        "storeys or one per storey, bottom up.")
    beta: float = Field(ge=0, allow_inf_nan=False, description="beta: the weight of the "
                        "hysteretic energy (Park & Ang 1985 give 0.05 as a typical value for "
                        "reinforced concrete members).")


class Foundation(Base):
    """A building's rigid foundation on soil: its size, mass and rotational inertia."""

    width: Positive | None = Field(None, description="Width b (m) along the shaking (the "
                                   "row of buildings).")
    length: Positive | None = Field(None, description="Length l (m) across the shaking "
                                    "(default: the width).")
    radius: Positive | None = Field(None, description="Radius (m) of a circular foundation "
                                    "(instead of width and length).")
    mass: Positive = Field(description="Foundation mass m_f (kg): the sway DOF's mass.")
    rotational_inertia: Positive | None = Field(
        None, description="Mass moment of inertia I_f (kg m^2) about the rocking axis (default: "
        "a thin slab's, m_f b^2 / 12, or m_f r^2 / 4 for a disk); add the floors' own "
        "rotational inertias here if they matter (the floors' translation with the rocking is "
        "already in their masses).")

    @model_validator(mode="after")
    def _size(self):
        if self.radius is not None and (self.width is not None or self.length is not None):
            raise ValueError("give radius (a circular foundation) or width and length, not both")
        if self.length is not None and self.width is None:
            raise ValueError("length needs width (the size along the shaking)")
        if self.rotational_inertia is None and self.radius is None and self.width is None:
            raise ValueError("give rotational_inertia (kg m^2), or the foundation's size "
                             "(width, or radius) to take a slab's")
        return self


#: the soil given by its properties (Wolf's cone model) or by its four springs and dashpots
SOIL_PROPERTIES = ("shear_wave_velocity", "poisson", "density")
SOIL_VALUES = ("sway_stiffness", "sway_damping", "rocking_stiffness", "rocking_damping")


class Soil(Base):
    """Soil under a building: sway and rocking springs and dashpots under its foundation, from
    the soil's properties (Wolf's cone model of a surface disk; docs/soil.md) or given."""

    shear_wave_velocity: Positive | None = Field(None, description="V_s (m/s).")
    poisson: float | None = Field(None, ge=0, le=0.5, description="Poisson's ratio nu "
                                  "(0 .. 0.5).")
    density: Positive | None = Field(None, description="rho (kg/m^3).")
    sway_stiffness: Positive | None = Field(None, description="K_h (N/m), instead of the "
                                            "soil's properties.")
    sway_damping: float | None = Field(None, ge=0, allow_inf_nan=False,
                                       description="C_h (N s/m).")
    rocking_stiffness: Positive | None = Field(None, description="K_r (N m/rad).")
    rocking_damping: float | None = Field(None, ge=0, allow_inf_nan=False,
                                          description="C_r (N m s/rad).")
    foundation: Foundation = Field(description="The foundation.")

    @model_validator(mode="after")
    def _one_way(self):
        props = [getattr(self, k) is not None for k in SOIL_PROPERTIES]
        values = [getattr(self, k) is not None for k in SOIL_VALUES]
        if any(props) and any(values):
            raise ValueError("give the soil's properties (shear_wave_velocity, poisson, "
                             "density) or its springs and dashpots (sway_stiffness, "
                             "sway_damping, rocking_stiffness, rocking_damping), not both")
        if any(props) and not all(props):
            missing = [k for k, on in zip(SOIL_PROPERTIES, props) if not on]
            raise ValueError(f"the cone model needs {', '.join(missing)} as well")
        if any(values) and not all(values):
            missing = [k for k, on in zip(SOIL_VALUES, values) if not on]
            raise ValueError(f"give {', '.join(missing)} as well (all four values)")
        if not any(props) and not any(values):
            raise ValueError("give the soil's properties (shear_wave_velocity, poisson, "
                             "density) or its four springs and dashpots (sway_stiffness, "
                             "sway_damping, rocking_stiffness, rocking_damping)")
        if all(props) and self.foundation.radius is None and self.foundation.width is None:
            raise ValueError("the cone model needs the foundation's size: width (and length) "
                             "or radius")
        return self


class CodeDriftLimit(Base):
    """A building code's allowable storey drift: ASCE/SEI 7-22 Table 12.12-1 (section
    12.12.1), by risk category and structure (pframe.limits)."""

    code: Literal["asce7-22"] = Field("asce7-22", description="The code (ASCE/SEI 7-22).")
    risk_category: Literal["I", "II", "III", "IV"] = Field(
        description="Risk category (ASCE 7-22 Table 1.5-1): I or II 0.020 h_sx, III 0.015, "
        "IV 0.010 for all other structures.")
    structure: Literal["low_rise", "masonry_cantilever", "masonry_other", "other"] = Field(
        "other", description="The table's row: low_rise (other than masonry shear wall, 4 "
        "storeys or less, walls and partitions designed to accommodate the drifts: 0.025, "
        "0.020, 0.015 h_sx; a taller building takes 'other'), masonry_cantilever (0.010), "
        "masonry_other (0.007) or other (all other structures).")
    redundancy: float = Field(1.0, ge=1.0, allow_inf_nan=False, description="rho: the "
                              "limit is divided by it for moment frames in Seismic Design "
                              "Categories D to F (12.12.1.1).")
    factor: Positive = Field(1.0, description="A multiple of the table's limit (ASCE 7's "
                             "nonlinear response history procedure, chapter 16, holds the mean "
                             "over a suite to a multiple of it).")


class Limits(Base):
    """Limits on each storey's peak drift ratio and each floor's peak absolute acceleration:
    the summary, the result file and the Dataset give each demand's margin and utilisation
    (docs/modes.md#limits)."""

    drift_ratio: float | None = Field(None, gt=0, le=1, allow_inf_nan=False, description=
                                      "Allowed peak storey drift ratio (drift over the "
                                      "storey's height; 0.02 is 2 %); needs heights.")
    code: CodeDriftLimit | None = Field(None, description="A code's allowable storey drift "
                                        "instead of drift_ratio.")
    acceleration: Positive | None = Field(None, description="Allowed peak absolute floor "
                                          "acceleration (m/s^2).")
    acceleration_g: Positive | None = Field(None, description="The same in g (9.80665 "
                                            "m/s^2), instead of acceleration.")

    @model_validator(mode="after")
    def _one_of_each(self):
        if self.drift_ratio is not None and self.code is not None:
            raise ValueError("give drift_ratio or code, not both")
        if self.acceleration is not None and self.acceleration_g is not None:
            raise ValueError("give acceleration (m/s^2) or acceleration_g (g), not both")
        if all(v is None for v in (self.drift_ratio, self.code, self.acceleration,
                                   self.acceleration_g)):
            raise ValueError("give drift_ratio or code, acceleration or acceleration_g")
        return self
