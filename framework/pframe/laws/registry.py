"""Registry of material and contact laws.

A law is a small class (see :class:`Law`): a pydantic ``Params`` model for what the YAML says,
``pack`` turning those parameters into a flat tuple of floats, a fixed number of state
variables, and a pure scalar ``force`` function. A built-in law's ``force`` is translated to C
(``pframe.kernel.translate`` writes ``kernel/c/laws.c``); a plug-in's is compiled by numba
into a C function the kernel calls (``pframe.kernel.plugins``). Registering is one decorator
for a built-in law and one entry point for a third-party law; a name registered twice is an
error, never a silent override.

:data:`_BUILTIN_MODULES` is the one ordered list of built-in laws: a law's id in the kernel
is its place in it (:func:`builtin_laws`); a new built-in law is a module added here.
"""

from __future__ import annotations

import importlib
import math
from dataclasses import dataclass
from typing import ClassVar

from pydantic import BaseModel

from pframe.errors import InputError

CONTACT_GROUP = "pframe.contact_laws"
MATERIAL_GROUP = "pframe.materials"

_BUILTIN_MODULES = {
    "contact": (
        "pframe.laws.contact.linear",
        "pframe.laws.contact.kelvin",
        "pframe.laws.contact.improved_kelvin",
        "pframe.laws.contact.hertz",
        "pframe.laws.contact.hertzdamp",
        "pframe.laws.contact.jankowski",
        "pframe.laws.contact.bumper",
        "pframe.laws.contact.hunt_crossley",
    ),
    "material": (
        "pframe.laws.material.elastic",
        "pframe.laws.material.bilinear",
        "pframe.laws.material.viscous",
        "pframe.laws.material.kelvin_voigt",
        "pframe.laws.material.bouc_wen",
        "pframe.laws.material.friction_pendulum",
        "pframe.laws.material.imk_peak",
        "pframe.laws.material.bwbn",
    ),
}
_GROUPS = {"contact": CONTACT_GROUP, "material": MATERIAL_GROUP}
_registered: dict[str, dict[str, type[Law]]] = {"contact": {}, "material": {}}
_builtin_names_by_kind: dict[str, frozenset[str]] = {}


@dataclass(frozen=True)
class ContactContext:
    """What a contact law may need from the scene to turn its parameters into numbers.

    Attributes
    ----------
    mass_left, mass_right : float
        Lumped masses of the two colliding nodes (kg).
    excitation_frequency : float or None
        Circular frequency w_p of a sine excitation (rad/s); None for a record.
    """

    mass_left: float
    mass_right: float
    excitation_frequency: float | None = None

    @property
    def effective_mass(self) -> float:
        """m1 m2 / (m1 + m2) (kg); a wall (the ground: infinite mass) gives the floor's."""
        if math.isinf(self.mass_left) or math.isinf(self.mass_right):
            return min(self.mass_left, self.mass_right)
        return self.mass_left * self.mass_right / (self.mass_left + self.mass_right)


#: standard gravity (m/s^2): the weight a storey carries is g times the masses above it
GRAVITY = 9.80665


class StoreyContext:
    """What a storey material may need from the scene: the mass it carries.

    ``mass_above`` is a number or a function giving it, called the first time a law asks
    (so that a scene whose laws never ask pays nothing for it).

    Attributes
    ----------
    mass_above : float
        The masses of the storey's upper node and of every node above it in its building
        (kg): a base isolator carries the whole superstructure, weight ``GRAVITY * mass_above``.
    """

    def __init__(self, mass_above):
        self._mass_above = mass_above

    @property
    def mass_above(self) -> float:
        if callable(self._mass_above):
            self._mass_above = float(self._mass_above())
        return self._mass_above

    @property
    def weight(self) -> float:
        """g times the masses above (N)."""
        return GRAVITY * self.mass_above


class Law:
    """Base of every material and contact law.

    Subclasses set the class attributes and write ``force`` as plain Python arithmetic on
    floats and 1-D float arrays (numba compiles it; no Python objects, no allocation)::

        force(params, committed, trial, deformation, rate) -> (f, df_ddeformation, df_drate)

    ``params`` holds ``pack``'s numbers, ``committed`` the state of the last accepted step
    (read only), ``trial`` receives the state for this deformation (the kernel copies it to
    ``committed`` when the step is accepted). For a contact, ``deformation`` is the
    penetration u_left - u_right - gap (m, positive when closed) and ``f`` is compression
    positive (N); for a storey material it is the drift (m) and ``f`` the storey shear (N).
    """

    kind: ClassVar[str]
    name: ClassVar[str]
    Params: ClassVar[type[BaseModel]]
    param_names: ClassVar[tuple[str, ...]]
    state_names: ClassVar[tuple[str, ...]] = ()
    #: True when force = params-only constant tangent x deformation (no Newton needed).
    linear: ClassVar[bool] = False
    #: contact laws: True when force and both tangents are exactly 0 at every penetration
    #: <= 0 (an open gap), whatever the state: a run whose contacts never close is then the
    #: run without them, to the bit, and a risk study reuses it (pframe.risk.runs.reusable;
    #: tests/test_laws.py checks the claim of every law that makes it)
    free_when_open: ClassVar[bool] = False

    @classmethod
    def claims_free_when_open(cls) -> bool:
        """``free_when_open`` as a claim about this law's own ``force``: declared by the class
        that defines the force or by one below it. A subclass that replaces a law's force
        (a plug-in written on a built-in law) does not inherit the claim it never made."""
        if not cls.free_when_open:
            return False
        owner = next((c for c in cls.__mro__ if "force" in vars(c)), Law)
        claim = next(c for c in cls.__mro__ if "free_when_open" in vars(c))
        return issubclass(claim, owner)

    # What the rest of pframe needs to know of a law, declared by the law (built-in and
    # plug-in alike; docs/contact-laws.md):
    #: field -> what it measures: a quantity of ``pframe.nondim.dimensions.QUANTITY``
    #: (``stiffness``, ``hertz_stiffness``, ``length``, ``force``, ``frequency``,
    #: ``dimensionless``, ...) or a unit string (``"N/m^1.5"``). ``pframe pi``, ``pframe
    #: scale`` and Pi-form scenes use it; a numeric field without one is refused there.
    dimensions: ClassVar[dict[str, str]] = {}
    #: field -> why it has no fixed dimension (Bouc-Wen's gamma, in m^-n): ``pframe scale``
    #: refuses it with that reason
    undimensioned: ClassVar[dict[str, str]] = {}

    @classmethod
    def dimensions_given(cls, given: dict) -> dict[str, str]:
        """The units of the ``undimensioned`` fields given the law's fields as a scene writes
        them (a dashpot's c in N (s/m)^alpha for its alpha): a scene in another unit system
        converts them so (docs/units.md); a field left out is refused there with its
        ``undimensioned`` reason. None by default."""
        return {}

    #: n of F ~ k delta^n: the stability and steps-per-contact checks size a contact from it
    exponent: ClassVar[float] = 1.0
    #: how the reference solver (``pframe accuracy``) locates the law's kinks: a model of
    #: :data:`pframe.reference.branches.BRANCHES` (``gap``, ``kelvin``, ``hunt_crossley``,
    #: ``jankowski``, ``smooth``, ``bilinear``); None: a stateless law's only kink is the gap
    branches: ClassVar[str | None] = None
    #: a device whose initial stiffness is not a structural stiffness (a sliding bearing's
    #: stick stiffness): a storey of it is an isolator by default (no stiffness-proportional
    #: Rayleigh damping; its building's isolated modes take its post-yield stiffness;
    #: docs/theory.md#damping)
    isolator: ClassVar[bool] = False

    @classmethod
    def post_yield_stiffness(cls, packed) -> float | None:
        """A storey material's smallest tangent after yielding or sliding, from its packed
        parameters (N/m), or None where it has no such bound (its initial tangent then
        stands for it). The P-delta check compares it with P / h; an isolator's is the
        stiffness its building's isolated modes (and their damping fit) take."""
        return None

    @classmethod
    def parameter_warnings(cls, packed) -> tuple[str, ...]:
        """What may surprise in these valid packed parameters: pframe warns of it before a
        run (``plan.warnings``). None by default."""
        return ()

    #: the stock OpenSees material pframe's OpenSees script models the law with, or None
    opensees: ClassVar[str | None] = None

    @classmethod
    def governing(cls, packed, effective_mass: float | None = None) -> dict:
        """The law's governing variables for ``pframe pi``: root name -> (what it measures,
        as in :attr:`dimensions`, value), from its packed numbers. By default every packed
        parameter under its own name; built-in laws name theirs as the paper does (``K``,
        ``u_y``, ``w_bar``, ``k_h``). ``pframe pi`` first refuses a law with a parameter it
        cannot list (:func:`pframe.nondim.fields.check_declared`): one without a declared
        dimension, or one declared ``undimensioned`` that this default would have to list."""
        return {p: (cls.dimensions[p], v) for p, v in zip(cls.param_names, packed)
                if p in cls.dimensions}

    # What the generic tests check, declared by the law (pframe.laws.facts says what each
    # is; a built-in law that lacks one fails its tests with one message naming the fact):
    #: parameter sets as a scene writes them (without ``law:`` / ``material:``), the first
    #: the one the every-law kernel run uses
    examples: ClassVar[tuple[dict, ...]] = ()
    #: contact laws: name -> :class:`pframe.laws.facts.Impact`, the tests' two-body impacts
    impacts: ClassVar[dict | None] = None
    #: contact laws: ``reference_force(params, context, v0)`` -> F(delta, delta'), the force
    #: written from the law's paper (the impact tests' oracle), a classmethod
    reference_force = None

    @classmethod
    def tangent_states(cls, packed) -> list | None:
        """The :class:`pframe.laws.facts.TangentState` rows at which the tests check the
        tangents of ``force`` with these packed parameters. By default, for a contact law
        without state, the contact tests' five states; None (not declared) otherwise."""
        if cls.kind == "contact" and not cls.state_names:
            from pframe.laws.facts import contact_states

            return contact_states((), ())
        return None

    @staticmethod
    def force(params, committed, trial, deformation, rate):  # pragma: no cover - interface
        raise NotImplementedError

    @classmethod
    def pack(cls, params: BaseModel, context: ContactContext | None = None) -> tuple[float, ...]:
        """Numbers for the kernel, in the order of ``param_names``."""
        raise NotImplementedError

    @classmethod
    def initial_state(cls) -> tuple[float, ...]:
        return (0.0,) * len(cls.state_names)


class SpringContact(Law):
    """A contact law whose stiffness is a linear spring's (N/m), given by ``stiffness``,
    ``frequency`` or ``frequency_ratio``: ``pframe pi`` names it by the contact frequency
    w_bar = sqrt(k / m_eff) (Wu et al. 2021)."""

    dimensions = {"stiffness": "stiffness", "frequency": "frequency",
                  "frequency_ratio": "dimensionless", "restitution": "dimensionless"}

    @classmethod
    def governing(cls, packed, effective_mass=None):
        return {"w_bar": ("frequency", math.sqrt(packed[0] / effective_mass))}


class HertzContact(Law):
    """A contact law of the Hertz family, F ~ k delta^1.5 with ``stiffness`` k in N/m^1.5:
    ``pframe pi`` names it k_h."""

    dimensions = {"stiffness": "hertz_stiffness", "restitution": "dimensionless"}
    exponent = 1.5

    @classmethod
    def governing(cls, packed, effective_mass=None):
        return {"k_h": ("hertz_stiffness", packed[0])}


def _register(kind: str, name: str):
    def decorate(cls: type[Law]) -> type[Law]:
        table = _registered[kind]
        if name in table and table[name] is not cls:
            raise ValueError(f"{kind} law {name!r} is registered twice")
        cls.kind = kind
        cls.name = name
        table[name] = cls
        return cls

    return decorate


def contact_law(name: str):
    """Class decorator registering a contact law under ``name`` (the YAML ``law:`` value)."""
    return _register("contact", name)


def material(name: str):
    """Class decorator registering a storey material under ``name`` (YAML ``material:``)."""
    return _register("material", name)


def _load_builtins(kind: str) -> None:
    if kind not in _builtin_names_by_kind:
        for module in _BUILTIN_MODULES[kind]:
            importlib.import_module(module)
        _builtin_names_by_kind[kind] = frozenset(_registered[kind])


def _load_builtin(kind: str, name: str) -> type[Law]:
    """The built-in law ``name``, its module (``name`` is the last part of the module's
    name: :func:`builtin_names`) imported alone: a scene of two laws loads two of the 16."""
    module = _BUILTIN_MODULES[kind][_builtin_index[kind][name]]
    importlib.import_module(module)
    return _registered[kind][name]


def builtin_laws(kind: str) -> tuple[type[Law], ...]:
    """The built-in laws of ``kind`` in the order of :data:`_BUILTIN_MODULES`: a law's kernel
    id is its index (plug-in laws get the ids after these)."""
    _load_builtins(kind)
    by_module = {cls.__module__: cls for cls in _registered[kind].values()}
    return tuple(by_module[module] for module in _BUILTIN_MODULES[kind])


#: kind -> built-in name -> its index in :data:`_BUILTIN_MODULES` (its kernel id): a
#: built-in law's module is named after the law (``pframe.laws.contact.linear`` registers
#: ``linear``; tests/test_registry.py checks every one), so the names are known unloaded
_builtin_index = {kind: {module.rsplit(".", 1)[1]: i for i, module in enumerate(modules)}
                  for kind, modules in _BUILTIN_MODULES.items()}


def builtin_names(kind: str) -> list[str]:
    """The names of the built-in laws of ``kind``, sorted (no law module is imported)."""
    return sorted(_builtin_index[kind])


def builtin_id(law: type[Law]) -> int | None:
    """A built-in law's kernel id (its index in :data:`_BUILTIN_MODULES`); None for a
    plug-in law. Only the law's own module is needed (unlike :func:`builtin_laws`)."""
    kind = getattr(law, "kind", None)
    index = _builtin_index.get(kind, {}).get(getattr(law, "name", None))
    if index is None or _BUILTIN_MODULES[kind][index] != law.__module__:
        return None
    return index


def builtin_count(kind: str) -> int:
    """How many built-in laws of ``kind`` there are (plug-in ids come after them)."""
    return len(_BUILTIN_MODULES[kind])


def _entry_points(kind: str):
    from importlib.metadata import entry_points  # slow to import: only when a plug-in is named

    found = {}
    for ep in entry_points(group=_GROUPS[kind]):
        if ep.name in found or ep.name in builtin_names(kind):
            raise InputError(
                f"{kind} law {ep.name!r} is defined twice (entry point {ep.value!r} in group "
                f"{_GROUPS[kind]} and {'another plug-in' if ep.name in found else 'pframe'}); "
                "uninstall one of them or rename it"
            )
        found[ep.name] = ep
    return found


def available_names(kind: str) -> list[str]:
    """Built-in names and installed plug-in names (without importing the plug-ins)."""
    return sorted(set(builtin_names(kind)) | set(_entry_points(kind)))


def get_law(kind: str, name: str) -> type[Law]:
    """The law class registered as ``name``, loading a plug-in entry point if needed."""
    if name in _builtin_index[kind]:
        return _load_builtin(kind, name)
    _load_builtins(kind)
    table = _registered[kind]
    if name in table:
        return table[name]
    plugins = _entry_points(kind)
    if name not in plugins:
        known = ", ".join(available_names(kind))
        what = "contact law" if kind == "contact" else "material"
        raise InputError(f"unknown {what} {name!r}; known: {known}")
    try:
        cls = plugins[name].load()
    except Exception as exc:  # a broken plug-in is the user's to fix: say which one
        raise InputError(
            f"{kind} law {name!r} from entry point {plugins[name].value!r} "
            f"(group {_GROUPS[kind]}) failed to import: {exc}"
        ) from None
    if not (isinstance(cls, type) and issubclass(cls, Law)):
        raise InputError(
            f"entry point {name!r} in group {_GROUPS[kind]} must name a pframe.laws.Law "
            f"subclass, got {cls!r}"
        )
    return _register(kind, name)(cls)


def all_contact_laws() -> tuple[type[Law], ...]:
    """Every built-in contact law, in registration order (tests run over this tuple)."""
    _load_builtins("contact")
    return tuple(_registered["contact"][n] for n in builtin_names("contact"))


def all_materials() -> tuple[type[Law], ...]:
    """Every built-in storey material."""
    _load_builtins("material")
    return tuple(_registered["material"][n] for n in builtin_names("material"))
