"""A law's ``force`` compiled by numba, with the helper functions it calls.

A law's ``force`` may call plain module-level helper functions (the C translator turns each
into a static C function, ``pframe.kernel.translate``). numba compiles only functions it was
given, so :func:`njit` compiles the helpers too: a copy of each function whose module globals
name numba-compiled copies of its helpers, so that the law's own module is untouched. numba is
imported only when :func:`njit` is called (the ``plugins`` extra).
"""

from __future__ import annotations

import inspect
import types


def helpers(function) -> tuple:
    """The module-level Python functions ``function`` calls, directly or through one another,
    in the order first met (its own module's globals and those it imported)."""
    found: dict = {}

    def visit(f):
        for name in f.__code__.co_names:
            value = f.__globals__.get(name)
            if inspect.isfunction(value) and value is not function and value not in found:
                found[value] = None
                visit(value)

    visit(function)
    return tuple(found)


def source(function) -> str:
    """The source of ``function`` and of every helper it calls (what a compiled copy of it
    depends on: a cache key)."""
    texts = []
    for f in (function, *helpers(function)):
        try:
            texts.append(inspect.getsource(f))
        except (OSError, TypeError):
            texts.append(repr(f))
    return "\n".join(texts)


def njit(function, **options):
    """``numba.njit(**options)`` of ``function``, its helper functions compiled as well
    (with numba's defaults but ``error_model``, which they share with ``function``)."""
    import numba

    inner = {k: v for k, v in options.items() if k == "error_model"}
    done: dict = {}

    def compiled(f, top: bool):
        if f in done:
            return done[f]
        scope = dict(f.__globals__)
        copy = types.FunctionType(f.__code__, scope, f.__name__, f.__defaults__, f.__closure__)
        copy.__qualname__, copy.__module__ = f.__qualname__, f.__module__
        done[f] = numba.njit(**(options if top else inner))(copy)
        for name in f.__code__.co_names:
            value = f.__globals__.get(name)
            if inspect.isfunction(value):
                scope[name] = compiled(value, False)
        return done[f]

    return compiled(function, True)
