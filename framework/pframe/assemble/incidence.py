"""How elements see the degrees of freedom: each element's two sides as terms of a plan.

A plain element (a planar storey, a contact between two floors' u_x) joins its two DOFs with
coefficient 1 and keeps only ``dofs`` (its two DOFs, -1 the ground); any other element (a
line of resistance in plan, a contact at a corner, a floor-to-column contact, a storey on
soil) also has its sides as terms: side ``s`` of element ``e`` is the sum of ``coef[b, t] *
u[dof[t]]`` for ``t`` in ``start[2e + s] .. start[2e + s + 1]`` (see pframe.model.elements).
:func:`incidence` gives the matrix G of the deformations, d = G u (a storey, a link: second
side less the first; a contact: first less second, before its gap).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from pframe.model.rows import column


# eq=False, repr=False: it holds numpy arrays: a generated __eq__ and __hash__ could only
# raise (== is elementwise), a __repr__ would print every array, and each generated
# function is compiled at every start
@dataclass(frozen=True, eq=False, repr=False)
class Sides:
    """The terms of the sides of a kind of element (see the module); empty when every
    element of the kind is plain."""

    start: np.ndarray  # (2 E + 1,) int64
    dof: np.ndarray  # (T,) int64
    coef: np.ndarray  # (B, T) float

    @property
    def count(self) -> int:
        return len(self.start) // 2

    def general(self) -> np.ndarray:
        """(E,) True where an element has terms (is not plain); found once (callers ask
        element by element)."""
        found = self.__dict__.get("_general")
        if found is None:
            found = self.start[2::2] > self.start[:-1:2]
            found.setflags(write=False)
            object.__setattr__(self, "_general", found)
        return found

    def side(self, e: int, s: int, member: int = 0) -> list[tuple[int, float]]:
        """Side ``s`` of element ``e`` as (DOF, coefficient) pairs."""
        lo, hi = self.start[2 * e + s], self.start[2 * e + s + 1]
        return list(zip(self.dof[lo:hi].tolist(), self.coef[member, lo:hi].tolist()))


def empty(count: int, batch: int) -> Sides:
    return Sides(np.zeros(2 * count + 1, dtype=np.int64), np.zeros(0, dtype=np.int64),
                 np.zeros((batch, 0)))


def build(elements_of_members, dof_of) -> Sides:
    """The sides of the elements of every batch member (one list of elements per member, the
    same elements); ``dof_of(node, component)`` numbers a degree of freedom. An element plain
    in every member gets no terms; otherwise each side holds the union of its members' terms
    (in the order first met), a coefficient 0 where a member has none (a line through one
    member's centre of mass does not turn that member's floor, but turns the others')."""
    first = elements_of_members[0]
    sides = [column(elements, "sides") for elements in elements_of_members]
    if all(of_member.count(None) == len(of_member) for of_member in sides):
        return empty(len(first), len(elements_of_members))  # all plain: no terms at all
    start, dofs = [0], []
    coefs = [[] for _ in elements_of_members]
    for e in range(len(first)):
        sided = any(of_member[e] is not None for of_member in sides)
        for s in range(2):
            if sided:
                members = [dict(((node, c), a) for node, c, a in elements[e].side_terms()[s])
                           for elements in elements_of_members]
                keys = merged(list(terms) for terms in members)
                dofs += [dof_of(*key) for key in keys]
                for b, terms in enumerate(members):
                    coefs[b] += [terms.get(key, 0.0) for key in keys]
            start.append(len(dofs))
    return Sides(np.array(start, dtype=np.int64), np.array(dofs, dtype=np.int64),
                 np.array(coefs, dtype=float).reshape(len(elements_of_members), len(dofs)))


def merged(orders) -> list:
    """The union of the keys of several sequences, each sequence's order kept: a key one
    member has and another lacks goes where it stands among its neighbours (the terms of a
    line along x, (u_x, theta), and of the same line turned, (u_x, u_y, theta), give
    (u_x, u_y, theta)). A member's side then sums its terms in its own run's order, with
    zeros between them, and a batch gives each member's bits (adding 0 changes none)."""
    keys: list = []
    for order in orders:
        at = 0
        for key in order:
            if key in keys:
                at = keys.index(key) + 1
            else:
                keys.insert(at, key)
                at += 1
    return keys


def incidence(dofs: np.ndarray, sides: Sides, member: int, n: int, contact: bool = False):
    """G (E x n, scipy.sparse CSR) with the elements' deformations d = G u: second side less
    the first, or the first less the second for contacts (``contact``; before the gap)."""
    from scipy.sparse import csr_matrix

    rows, cols, values = [], [], []
    general = sides.general() if len(sides.start) > 1 else np.zeros(len(dofs), dtype=bool)
    signs = (1.0, -1.0) if contact else (-1.0, 1.0)
    if not general.any():  # every element plain: its two DOFs, in the same order as below
        dofs = np.asarray(dofs, dtype=np.int64).reshape(-1, 2)
        keep = (dofs >= 0).ravel()
        rows = np.repeat(np.arange(len(dofs)), 2)[keep]
        values = np.tile(np.array(signs), len(dofs))[keep]
        return csr_matrix((values, (rows, dofs.ravel()[keep])), shape=(len(dofs), n))
    for e in range(len(dofs)):
        for s in range(2):
            if general[e]:
                terms = sides.side(e, s, member)
            else:
                terms = [(int(dofs[e, s]), 1.0)] if dofs[e, s] >= 0 else []
            for d, c in terms:
                rows.append(e)
                cols.append(d)
                values.append(signs[s] * c)
    return csr_matrix((values, (rows, cols)), shape=(len(dofs), n))


def side_mobility(dofs: np.ndarray, sides: Sides, member: int, mass: np.ndarray, e: int,
                  s: int) -> float:
    """sum(a^2 / m) over side ``s`` of element ``e`` (1/kg): the inverse of the mass the side
    presents along the element; 0 for the ground."""
    general = len(sides.start) > 1 and sides.general()[e]
    if general:
        return float(sum(c * c / mass[d] for d, c in sides.side(e, s, member)))
    d = int(dofs[e, s])
    return 1.0 / float(mass[d]) if d >= 0 else 0.0


def edges(dofs: np.ndarray, sides: Sides) -> np.ndarray:
    """(m, 2) the pairs of DOFs that the elements couple (the band's off-diagonal entries),
    element by element: a plain element's two DOFs, each pair of the DOFs an element with
    sides touches."""
    plain = np.asarray(dofs, dtype=np.int64).reshape(-1, 2)
    if len(sides.start) <= 1 or not np.any(general := sides.general()):
        return plain
    out, rows = [], plain.tolist()
    for e in range(len(rows)):
        if general[e]:
            lo, hi = sides.start[2 * e], sides.start[2 * e + 2]
            touched = sorted(set(sides.dof[lo:hi].tolist()))
            out += [(a, c) for i, a in enumerate(touched) for c in touched[i + 1:]]
        else:
            out.append(rows[e])
    return np.array(out, dtype=np.int64).reshape(-1, 2)
