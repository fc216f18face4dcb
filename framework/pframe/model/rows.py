"""A tuple of frozen dataclass instances held by column where they repeat a template.

A tall building's floors, its storeys and a contact at every level of a tall pair are tens of
thousands of instances that differ from the first in a few fields (a name, the nodes, a
mass). :class:`Rows` holds such a run as the first instance (the template) and one sequence
per field that varies, so that expanding and assembling it are operations on those
sequences (:func:`column`), not a loop building one object per storey. To every other reader
it is the tuple it stands for: ``len``, indexing, slices, iteration, ``+`` with a tuple and
``==`` with a tuple behave as the tuple's, and an instance is built (by :func:`like`) only
when it is read.
"""

from __future__ import annotations

import operator
from bisect import bisect_right
from collections.abc import Sequence
from itertools import chain, repeat

import numpy as np


def like(prototype, **changes):
    """A copy of the frozen dataclass instance ``prototype`` with ``changes`` to its fields:
    ``dataclasses.replace`` without the per-field ``__init__`` (a fraction of its cost: what
    every storey of a tall building repeats is built tens of thousands of times). Only for
    classes without ``__post_init__``; ``changes`` must name their fields."""
    out = object.__new__(type(prototype))
    out.__dict__.update(prototype.__dict__, **changes)
    return out


class Run:
    """``length`` instances like ``template`` but for the fields in ``fields`` (field name ->
    a sequence of ``length`` values)."""

    __slots__ = ("template", "length", "fields")

    def __init__(self, template, length: int, fields: dict):
        for name, values in fields.items():
            if len(values) != length:
                raise ValueError(f"field {name!r} has {len(values)} values for {length} rows")
        self.template, self.length, self.fields = template, int(length), dict(fields)

    def __len__(self) -> int:
        return self.length

    def __getitem__(self, i: int):
        return like(self.template, **{k: v[i] for k, v in self.fields.items()})

    def __iter__(self):
        kind, base, keys = type(self.template), self.template.__dict__, tuple(self.fields)
        for values in zip(*self.fields.values()):
            out = object.__new__(kind)
            out.__dict__.update(base)
            out.__dict__.update(zip(keys, values))
            yield out

    def column(self, name: str) -> list:
        values = self.fields.get(name)
        if values is None:
            return [getattr(self.template, name)] * self.length
        return list(values)

    def array(self, name: str, dtype) -> np.ndarray:
        """:meth:`column` as an array: one value repeated (the template's, or one object
        in every row) converted once."""
        values = self.fields.get(name)
        if values is not None and not one_object(values):
            return np.array(values, dtype=dtype)
        one = np.asarray(getattr(self.template, name) if values is None else values[0],
                         dtype=dtype)
        return np.broadcast_to(one, (self.length,) + one.shape).copy()

    def __getstate__(self):
        return self.template, self.length, self.fields

    def __setstate__(self, state):
        self.template, self.length, self.fields = state


class Rows(Sequence):
    """A tuple of instances held as parts: runs (:class:`Run`) and tuples of instances, in
    order (see the module)."""

    def __init__(self, parts=()):
        flat = []
        for part in parts:
            if isinstance(part, Rows):
                flat += part.parts
            elif isinstance(part, Run):
                flat.append(part)
            elif len(part):
                flat.append(tuple(part))
        self.parts = tuple(p for p in flat if len(p))
        self._starts = [0]
        for part in self.parts:
            self._starts.append(self._starts[-1] + len(part))
        self._items = None  # the instances, once iterated: read again at a tuple's cost
        self._arrays: dict = {}  # (field, dtype) -> its column as an array (array())

    def __len__(self) -> int:
        return self._starts[-1]

    def __getitem__(self, i):
        if self._items is not None:
            return self._items[i]
        if isinstance(i, slice):
            return tuple(self)[i]
        n = len(self)
        if i < 0:
            i += n
        if not 0 <= i < n:
            raise IndexError("Rows index out of range")
        p = bisect_right(self._starts, i) - 1
        return self.parts[p][i - self._starts[p]]

    def __iter__(self):
        if self._items is None:
            self._items = tuple(chain.from_iterable(self.parts))
        return iter(self._items)

    def __add__(self, other):
        if isinstance(other, (tuple, Rows)):
            return Rows((self, other))
        return NotImplemented

    def __radd__(self, other):
        if isinstance(other, tuple):
            return Rows((other, self))
        return NotImplemented

    def __eq__(self, other):
        if isinstance(other, (tuple, Rows)):
            return tuple(self) == tuple(other)
        return NotImplemented

    __hash__ = None

    def __repr__(self) -> str:
        return f"Rows({tuple(self)!r})"

    def column(self, name: str) -> list:
        """Every instance's field ``name``, in order, without building the instances."""
        if self._items is not None:
            return [getattr(x, name) for x in self._items]
        out = []
        for part in self.parts:
            out += (part.column(name) if isinstance(part, Run)
                    else [getattr(x, name) for x in part])
        return out

    def array(self, name: str, dtype) -> np.ndarray:
        """:meth:`column` as a read-only array, made once (the instances do not change)."""
        key = (name, np.dtype(dtype))
        found = self._arrays.get(key)
        if found is None:
            parts = [part.array(name, dtype) if isinstance(part, Run)
                     else np.array([getattr(x, name) for x in part], dtype=dtype)
                     for part in self.parts]
            if parts and len({p.shape[1:] for p in parts}) == 1:
                found = np.concatenate(parts)
            else:  # none, or of several shapes: numpy's word on the whole column
                found = np.array(self.column(name), dtype=dtype)
            found.setflags(write=False)
            self._arrays[key] = found
        return found

    def __getstate__(self):
        return self.parts

    def __setstate__(self, parts):
        self.__init__(parts)


def one_object(values) -> bool:
    """Whether every item of ``values`` is its first (one object repeated: a value given once
    for every storey), at C's pace."""
    return not len(values) or all(map(operator.is_, values, repeat(values[0])))


def column(items, name: str) -> list:
    """Field ``name`` of each instance of ``items`` (a tuple, a list or :class:`Rows`)."""
    if isinstance(items, Rows):
        return items.column(name)
    return [getattr(x, name) for x in items]


def column_array(items, name: str, dtype) -> np.ndarray:
    """:func:`column` as an array (read-only: of :class:`Rows`, made once)."""
    if isinstance(items, Rows):
        return items.array(name, dtype)
    return np.array(column(items, name), dtype=dtype)
