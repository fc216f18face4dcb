"""What a sweep file may say: a base scene, the axes to vary, how to combine them, what to keep.

A sweep file is YAML, validated by frozen pydantic models that reject unknown fields; errors
name the sweep file, line and field as the scene loader's do (docs/sweeps.md)::

    base: ../wu2021-eq14-pi.yaml      # or an inline `scene:`
    axes:
      - {name: Pi_d, path: pi.Pi_d, linspace: [0, 2, 41]}
    combine: product                  # or zip
    keep: {envelopes: [building_peak_displacement, peak_contact_force]}
    chunk: 64
"""

from __future__ import annotations

import math
from typing import Annotated, Any, Literal

import numpy as np
from pydantic import Field, model_validator

from pframe.errors import InputError
from pframe.model.load import validated
from pframe.model.scene import Base
from pframe.quantities import QUANTITIES
from pframe.resources import MAX_AXIS_VALUES, MAX_VARIANTS, product
from pframe.yamltext import compose

#: dimension names a sweep file may not take for an axis (they are the file's own)
RESERVED = ("node", "story", "contact", "building", "time", "variant", "t", "link",
            "foundation", "direction", "point", "axis")

#: what a sweep keeps per variant -> the entity it runs along (besides the sweep axes)
RESPONSES = {
    "peak_displacement": "node",
    "peak_story_drift": "story",
    "ductility": "story",
    "peak_contact_force": "contact",
    "impact_count": "contact",
    "building_peak_displacement": "building",
    "building_peak_story_drift": "building",
    "building_peak_ductility": "building",
} | {f"peak_{q}": dim for q, (dim, _, _) in QUANTITIES.items()
     if f"peak_{q}" not in ("peak_displacement", "peak_story_drift", "peak_contact_force")}

#: kept when ``keep.envelopes`` is not given
DEFAULT_RESPONSES = ("peak_displacement", "peak_story_drift", "ductility", "peak_contact_force",
                     "impact_count")

Name = Annotated[str, Field(pattern=r"^[A-Za-z_][A-Za-z0-9_]*$",
                            description="Dimension name in the result file (a letter or _, "
                                        "then letters, digits or _).")]
Count = Annotated[int, Field(ge=1, le=MAX_AXIS_VALUES)]
Finite = Annotated[float, Field(allow_inf_nan=False)]


class Axis(Base):
    """One swept value: where it goes in the base scene and the values it takes."""

    name: Name
    path: str | list[str | int] = Field(
        description="Where the value goes in the base scene: dotted keys, list items by name "
                    "(contacts.floor-1.gap, buildings.A.story.yield_drift), * for every item "
                    "(contacts.*.gap), pi.Pi_d in a Pi-form scene; or the same as a list.")
    values: list[Any] | None = Field(
        None, description="The values, in order (numbers; file names for excitation.file).")
    linspace: tuple[Finite, Finite, Count] | None = Field(
        None, description="[start, stop, num]: num values evenly spaced (numpy.linspace).")
    logspace: tuple[Finite, Finite, Count] | None = Field(
        None, description="[start, stop, num]: 10**start .. 10**stop, num values evenly spaced "
                          "in the exponent (numpy.logspace: start and stop are decades).")
    geomspace: tuple[Finite, Finite, Count] | None = Field(
        None, description="[start, stop, num]: start .. stop, num values in geometric "
                          "progression (numpy.geomspace: start and stop are values).")
    units: str | None = Field(None, description="Units of the values, copied into the file.")

    @model_validator(mode="after")
    def _one_source(self):
        given = [k for k in ("values", "linspace", "logspace", "geomspace")
                 if getattr(self, k) is not None]
        if len(given) != 1:
            raise ValueError("give exactly one of values, linspace, logspace or geomspace; got "
                             + (", ".join(given) or "none"))
        if self.name in RESERVED:
            raise ValueError(f"the axis name {self.name!r} is taken by the result file's own "
                             f"dimensions ({', '.join(RESERVED)}); choose another")
        if self.values is not None:
            if not self.values:
                raise ValueError("values is empty; give at least one value")
            for v in self.values:  # text is checked where the path tells what it sets
                if not (isinstance(v, str) or (isinstance(v, (int, float))
                                               and not isinstance(v, bool) and math.isfinite(v))):
                    raise ValueError(f"{v!r} is neither a finite number nor a file name")
        if self.geomspace is not None and (self.geomspace[0] <= 0 or self.geomspace[1] <= 0):
            raise ValueError("geomspace needs positive start and stop (they are values; "
                             "logspace takes decades)")
        return self

    @property
    def segments(self) -> tuple:
        """The path as a tuple of keys, names and indices."""
        if isinstance(self.path, str):
            return tuple(self.path.split("."))
        return tuple(self.path)

    @property
    def is_file(self) -> bool:
        """Whether this axis sets a record file (``excitation.file``)."""
        return self.segments[-2:] == ("excitation", "file")

    @property
    def count(self) -> int:
        """How many values the axis takes (without making them)."""
        if self.values is not None:
            return len(self.values)
        return int((self.linspace or self.logspace or self.geomspace)[2])

    def points(self) -> list:
        """The values the axis takes, as Python numbers or strings."""
        if self.values is not None:
            return list(self.values)
        if self.linspace is not None:
            return np.linspace(*self.linspace[:2], self.linspace[2]).tolist()
        if self.logspace is not None:
            return np.logspace(*self.logspace[:2], self.logspace[2]).tolist()
        return np.geomspace(*self.geomspace[:2], self.geomspace[2]).tolist()


class Keep(Base):
    """What is kept per variant: envelope responses always, histories only when asked."""

    envelopes: list[Literal[tuple(RESPONSES)]] = Field(
        list(DEFAULT_RESPONSES), min_length=1,
        description="Responses per variant (peak values, ductility, impact counts).")
    histories: list[Literal[tuple(QUANTITIES)]] = Field(
        default_factory=list, description="Full histories per variant (large).")
    every: int = Field(1, ge=1, description="Keep every k-th step of the histories (and t = 0).")


class SweepFile(Base):
    """A parametric study: variants of one scene that differ in numbers only."""

    title: str = Field("", description="A title copied into the result file.")
    base: str | None = Field(None, description="The base scene file, relative to this file.")
    scene: dict | None = Field(None, description="The base scene written inline.")
    axes: list[Axis] = Field(min_length=1, description="The swept values.")
    combine: Literal["product", "zip"] = Field(
        "product", description="product: every combination (one dimension per axis); zip: "
                               "the i-th values together (axes of equal length, one dimension "
                               "'variant').")
    keep: Keep = Field(Keep(), description="What to keep per variant.")
    chunk: int = Field(64, ge=1, description="Variants per chunk (run together, saved together).")

    @model_validator(mode="after")
    def _check(self):
        if (self.base is None) == (self.scene is None):
            raise ValueError("give exactly one of base (a scene file) or scene (inline)")
        counts = [a.count for a in self.axes]
        count = counts[0] if self.combine == "zip" else product(counts)
        if count > MAX_VARIANTS:
            raise ValueError(
                f"{' x '.join(f'{c:,}' for c in counts)} = {count:,} variants; a sweep has at "
                f"most {MAX_VARIANTS:,}: use fewer values per axis, or split the study")
        return self


def validated_sweep(text: str, source: str) -> tuple[SweepFile, dict]:
    """The sweep file's model and the line of every value, or an InputError at its line."""
    data, lines = compose(text, source)
    if not isinstance(data, dict):
        raise InputError(f"{source}: a sweep file is a YAML mapping (base or scene, axes, "
                         "combine, keep, chunk)")
    return validated(SweepFile, data, lines, source), lines
