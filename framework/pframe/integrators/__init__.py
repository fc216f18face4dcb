"""Time integrators, one small module each, listed once in :data:`TABLE`.

An integrator module holds the YAML parameters (a pydantic model tagged by ``type``), the
facts it declares (:class:`~pframe.integrators._base.Facts`: its order, the stepping paths it
runs on, the tolerances its tests hold it to) and ``coefficients()``, the step the kernel runs
(:class:`~pframe.integrators.coefficients.Coefficients`). The step is data: a
:class:`~pframe.integrators.tableau.Tableau` of implicit stages, each imposing equilibrium at
a point written as linear combinations of the step start, the earlier stages and its own
acceleration, run by the kernel's one generic stage loop on every stepping path. Newmark and
the generalised-alpha family (Newmark: alpha_m = alpha_f = 0; HHT: alpha_m = 0), with
equilibrium

    M a(n+1-alpha_m) + C v(n+1-alpha_f) + F(u(n+1-alpha_f)) = P(t(n+1-alpha_f)),
    x(n+1-alpha) = (1 - alpha) x(n+1) + alpha x(n),

and Wilson-theta (equilibrium at t + theta h, past the step end) are one stage with a fast
path in the kernel; Bathe's composite method is two. Central difference is explicit (no
solve: the mass matrix is diagonal). The amplification matrix follows from the tableau, and
the dt checks take each integrator's period error from it.

:data:`TABLE` is the one list, with :data:`SCHEME` (the kernel's scheme of each, which each
class reads as its ``scheme``): :data:`ALL_INTEGRATORS`, :data:`SCHEMES` (and from them the
kernel's ``Scheme``), the scene's integrator union, the schemas, the classes ``pframe``
exports and the integrators the tests run all follow from it. It names modules, classes and
schemes only, so that ``import pframe`` and the kernel's tables read it without loading them
(each loads on first use: a scene loads the module of the integrator it names).
"""

import importlib

#: the integrators: the YAML ``type`` (the module ``pframe.integrators.<type>``) -> its class
TABLE = {
    "newmark": "Newmark",
    "hht": "HHT",
    "generalized_alpha": "GeneralizedAlpha",
    "wilson_theta": "WilsonTheta",
    "central_difference": "CentralDifference",
    "bathe": "Bathe",
}

#: the kernel's scheme that runs each integrator of :data:`TABLE` (None: explicit, no scheme);
#: each class's ``scheme`` is read from here, so the kernel's schemes are listed without
#: loading the integrators' modules
SCHEME = {
    "newmark": "alpha_family",
    "hht": "alpha_family",
    "generalized_alpha": "alpha_family",
    "wilson_theta": "wilson_theta",
    "central_difference": None,
    "bathe": "tableau",
}

#: names of this package defined in its modules (loaded on first use)
_MODULES = {"Coefficients": "coefficients", "Tableau": "tableau", "Stage": "tableau",
            "Facts": "_base", "PATHS": "_base",
            **{cls: module for module, cls in TABLE.items()}}


def _all_integrators() -> tuple:
    return tuple(__getattr__(cls) for cls in TABLE.values())


def _schemes() -> tuple:
    """The kernel's implicit schemes, in the order of their first integrator in the table."""
    return tuple(dict.fromkeys(SCHEME[name] for name in TABLE if SCHEME[name] is not None))


def __getattr__(name: str):
    if name == "ALL_INTEGRATORS":
        value = _all_integrators()
    elif name == "SCHEMES":
        value = _schemes()
    elif name in _MODULES:
        module = importlib.import_module(f"pframe.integrators.{_MODULES[name]}")
        value = getattr(module, name)
    else:
        raise AttributeError(f"module 'pframe.integrators' has no attribute {name!r}")
    globals()[name] = value
    return value


__all__ = ["ALL_INTEGRATORS", "PATHS", "SCHEMES", "TABLE", "Coefficients", "Facts", "Stage",
           "Tableau", *TABLE.values()]
