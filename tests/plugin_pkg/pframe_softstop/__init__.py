"""A third-party contact law for pframe, used by tests/test_plugin.py.

``SoftStop`` is a cubic-stiffening compression-only spring,
F = k delta (1 + (delta / delta_ref)^2) for delta > 0. ``Broken`` is a law whose force()
numba cannot compile (it formats a string), to check the error message.
``ImprovedKelvinCopy`` is pframe's improved Kelvin law as a plug-in (``improved_kelvin_copy``).
"""

from __future__ import annotations

from typing import Literal

from pydantic import Field

from pframe.laws import Law
from pframe.laws.contact._hunt_crossley import hunt_crossley_force
from pframe.laws.contact.improved_kelvin import ImprovedKelvin
from pframe.laws.params import LawParams, Positive


class SoftStop(Law):
    """F = k delta (1 + (delta / delta_ref)^2) for delta > 0, zero otherwise."""

    class Params(LawParams):
        law: Literal["softstop"]
        stiffness: Positive = Field(description="Initial contact stiffness k (N/m).")
        reference_penetration: Positive = Field(
            description="Penetration delta_ref (m) at which the stiffness has doubled."
        )

    param_names = ("stiffness", "reference_penetration")
    # what pframe needs to know of the law besides its force (docs/contact-laws.md)
    dimensions = {"stiffness": "N/m", "reference_penetration": "m"}
    exponent = 1.0  # sized by k at small penetration (the cubic term stiffens it further)
    branches = None  # stateless: the gap is its only kink
    opensees = None

    @classmethod
    def pack(cls, params, context=None):
        return (float(params.stiffness), float(params.reference_penetration))

    @staticmethod
    def force(params, committed, trial, deformation, rate):
        if deformation <= 0.0:
            return 0.0, 0.0, 0.0
        k = params[0]
        x = deformation / params[1]
        return k * deformation * (1.0 + x * x), k * (1.0 + 3.0 * x * x), 0.0


class Broken(Law):
    """A law numba cannot compile: force() formats a Python string."""

    class Params(LawParams):
        law: Literal["broken"]
        stiffness: Positive = Field(description="Contact stiffness k (N/m).")

    param_names = ("stiffness",)

    @classmethod
    def pack(cls, params, context=None):
        return (float(params.stiffness),)

    @staticmethod
    def force(params, committed, trial, deformation, rate):
        label = "penetration %s m" % deformation  # noqa: UP031 - numba cannot compile this
        if deformation <= 0.0 or not label:
            return 0.0, 0.0, 0.0
        return params[0] * deformation, params[0], 0.0


class ImprovedKelvinCopy(ImprovedKelvin):
    """pframe's improved Kelvin law under another name, as a plug-in: its force is compiled by
    numba into a C function the kernel calls through a pointer, where the built-in one is in
    the compiled kernel (the same results, bit for bit; benchmarks/plugin_speed.py compares
    their speed)."""

    class Params(ImprovedKelvin.Params):
        law: Literal["improved_kelvin_copy"]

    force = staticmethod(hunt_crossley_force)  # the same Python function as the built-in's
