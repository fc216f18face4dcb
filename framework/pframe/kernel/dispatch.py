"""The built-in laws behind one switch on a law id.

Every storey and contact carries the id of its law (:data:`MATERIALS`, :data:`CONTACT_LAWS`);
the kernel calls :func:`material_force` or :func:`contact_force`, which branch to the law's own
``force`` (written in the law's module, see :class:`pframe.laws.Law`). A law no element of a
scene uses is never branched to, so it costs nothing at run time, and one compiled kernel
serves every combination of laws. Plug-in laws get ids after the built-in ones and a switch
of their own that falls back to this one (:mod:`pframe.kernel.plugins`).
"""

from __future__ import annotations

import math

import numba

from pframe.kernel.cache import compiled, inline
from pframe.laws.contact.hertz import Hertz
from pframe.laws.contact.hertzdamp import Hertzdamp
from pframe.laws.contact.improved_kelvin import ImprovedKelvin
from pframe.laws.contact.jankowski import Jankowski
from pframe.laws.contact.kelvin import Kelvin
from pframe.laws.contact.linear import Linear
from pframe.laws.material.bilinear import Bilinear
from pframe.laws.material.elastic import Elastic

#: material ids: the index in this tuple
MATERIALS = (Elastic, Bilinear)
#: contact law ids: the index in this tuple
CONTACT_LAWS = (Linear, Kelvin, ImprovedKelvin, Hertz, Hertzdamp, Jankowski)

# the laws' force functions, inlined into the switches; the storey materials and the linear
# contact are inlined where elements are evaluated, as if written there
_elastic = numba.njit(inline='always')(Elastic.force)
_bilinear = numba.njit(inline='always')(Bilinear.force)
_linear = numba.njit(inline='always')(Linear.force)
_kelvin = numba.njit(inline='always')(Kelvin.force)
_hunt_crossley = numba.njit(inline='always')(ImprovedKelvin.force)  # improved Kelvin and Hertzdamp alike
_hertz = numba.njit(inline='always')(Hertz.force)
_jankowski = numba.njit(inline='always')(Jankowski.force)

assert Hertzdamp.force is ImprovedKelvin.force


@inline
def material_force(law, params, committed, trial, drift, rate):
    """(storey force, d force / d drift, d force / d rate) of material ``law``."""
    if law == 1:
        return _bilinear(params, committed, trial, drift, rate)
    if law == 0:
        return _elastic(params, committed, trial, drift, rate)
    return math.nan, math.nan, math.nan


@compiled
def damped_contact_force(law, params, committed, trial, penetration, rate):
    """The contact laws with damping or a power law, behind a call: their code is compiled
    once, not into every place elements are evaluated (it would add seconds to the one
    compilation for a few nanoseconds a contact)."""
    if law == 2 or law == 4:
        return _hunt_crossley(params, committed, trial, penetration, rate)
    if law == 1:
        return _kelvin(params, committed, trial, penetration, rate)
    if law == 3:
        return _hertz(params, committed, trial, penetration, rate)
    if law == 5:
        return _jankowski(params, committed, trial, penetration, rate)
    return math.nan, math.nan, math.nan


@inline
def contact_force(law, params, committed, trial, penetration, rate):
    """(contact force, d force / d penetration, d force / d rate) of contact law ``law``."""
    if law == 0:
        return _linear(params, committed, trial, penetration, rate)
    return damped_contact_force(law, params, committed, trial, penetration, rate)
