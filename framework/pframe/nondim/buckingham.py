"""Buckingham Pi groups from a dimension matrix, in exact rational arithmetic.

With ``n`` variables whose dimension matrix ``D`` (rows M, L, T; one column per variable) has
rank ``r``, every dimensionless product ``prod_j q_j^{x_j}`` is a vector ``x`` with
``D x = 0``: the null space of ``D``, of dimension ``n - r`` (Buckingham's Pi theorem). Choosing
``r`` repeating variables ``R`` whose columns are independent gives one group per other
variable ``q``:

    Pi_q = q * prod_i R_i^{a_i},      D_R a = -d_q

which is solvable exactly because the columns of ``D_R`` span those of ``D``. The groups are
independent (each holds its own variable with exponent 1) and complete (there are
``n - r``). Gauss-Jordan elimination on :class:`fractions.Fraction` entries keeps every
exponent exact (1/2, -3, ...), where a floating-point null space (SVD) would return a rotated,
scaled basis with roundoff.
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from fractions import Fraction

from pframe.errors import InputError
from pframe.nondim.dimensions import BASE, Dimension


class DimensionalAnalysisError(InputError):
    """Repeating variables that cannot serve, or groups that are not a valid Pi set."""


@dataclass(frozen=True)
class Variable:
    """A governing variable: name, dimension and (optionally) its value in SI units."""

    name: str
    dimension: Dimension
    value: float | None = None
    description: str = ""
    units: str = ""


@dataclass(frozen=True)
class Group:
    """A dimensionless product ``prod q^x`` of variables, with exact exponents."""

    name: str
    exponents: tuple[tuple[str, Fraction], ...]
    description: str = ""

    @property
    def powers(self) -> dict[str, Fraction]:
        return dict(self.exponents)

    def dimension(self, variables: Mapping[str, Variable]) -> Dimension:
        out = Dimension()
        for name, exponent in self.exponents:
            out = out * variables[name].dimension ** exponent
        return out

    def value(self, values: Mapping[str, float]) -> float:
        """The group's number for the given variable values (positive powers over negative
        ones, so that a ratio of equal values is exactly 1)."""
        top, bottom = 1.0, 1.0
        for name, exponent in self.exponents:
            power = abs(int(exponent) if exponent.denominator == 1 else float(exponent))
            if exponent > 0:
                top *= float(values[name]) ** power
            else:
                bottom *= float(values[name]) ** power
        return top / bottom

    def formula(self) -> str:
        """``K_a / (m_b w_p^2)``-style text of the product."""
        return format_product(self.exponents)


def _power(name: str, exponent: Fraction) -> str:
    if exponent == 1:
        return name
    if exponent.denominator == 1:
        return f"{name}^{exponent}"
    return f"{name}^({exponent})"


def format_product(exponents) -> str:
    """Text of ``prod name^x``: positive powers over negative ones."""
    top = [_power(n, x) for n, x in exponents if x > 0]
    bottom = [_power(n, -x) for n, x in exponents if x < 0]
    numerator = " ".join(top) or "1"
    if not bottom:
        return numerator
    denominator = bottom[0] if len(bottom) == 1 else f"({' '.join(bottom)})"
    return f"{numerator} / {denominator}"


# ---------------------------------------------------------------------------------------------
# exact linear algebra
# ---------------------------------------------------------------------------------------------

def rref(matrix: Sequence[Sequence]) -> tuple[list[list[Fraction]], list[int]]:
    """Reduced row echelon form of ``matrix`` (copied to Fractions) and its pivot columns."""
    rows = [[Fraction(x) for x in row] for row in matrix]
    pivots: list[int] = []
    if not rows:
        return rows, pivots
    top = 0
    for col in range(len(rows[0])):
        pivot = next((i for i in range(top, len(rows)) if rows[i][col] != 0), None)
        if pivot is None:
            continue
        rows[top], rows[pivot] = rows[pivot], rows[top]
        lead = rows[top][col]
        rows[top] = [x / lead for x in rows[top]]
        for i in range(len(rows)):
            if i != top and rows[i][col] != 0:
                factor = rows[i][col]
                rows[i] = [a - factor * b for a, b in zip(rows[i], rows[top])]
        pivots.append(col)
        top += 1
        if top == len(rows):
            break
    return rows, pivots


def rank(matrix: Sequence[Sequence]) -> int:
    return len(rref(matrix)[1])


def null_space(matrix: Sequence[Sequence]) -> list[list[Fraction]]:
    """A basis of ``{x : matrix x = 0}``, one vector per free column (exact)."""
    rows, pivots = rref(matrix)
    width = len(matrix[0]) if matrix else 0
    basis = []
    for free in (c for c in range(width) if c not in pivots):
        x = [Fraction(0)] * width
        x[free] = Fraction(1)
        for row, col in enumerate(pivots):
            x[col] = -rows[row][free]
        basis.append(x)
    return basis


def _integral(vector: Sequence[Fraction]) -> list[Fraction]:
    """The vector scaled to coprime integers, its first non-zero entry positive."""
    scale = math.lcm(*(x.denominator for x in vector))
    ints = [int(x * scale) for x in vector]
    divisor = math.gcd(*ints) or 1
    sign = next((1 if x > 0 else -1 for x in ints if x), 1)
    return [Fraction(sign * x, divisor) for x in ints]


def dimension_matrix(variables: Sequence[Variable]) -> list[list[Fraction]]:
    """Rows M, L, T; one column per variable."""
    return [[v.dimension.exponents[i] for v in variables] for i in range(len(BASE))]


# ---------------------------------------------------------------------------------------------
# Pi groups
# ---------------------------------------------------------------------------------------------

def pi_groups(variables: Sequence[Variable], repeating: Sequence[str],
              names: Mapping[str, str] | None = None) -> list[Group]:
    """One Pi group per non-repeating variable, made dimensionless by the repeating ones.

    Parameters
    ----------
    variables : sequence of Variable
        The governing variables (distinct names).
    repeating : sequence of str
        Names of the repeating (reference) variables, as many as the rank of the dimension
        matrix and with independent dimensions, e.g. the paper's ``("m_b", "a_p", "w_p")``.
    names : mapping, optional
        Group name for a variable's group; default ``"Pi_" + variable``.

    Returns
    -------
    list of Group
        In the order of ``variables``, ``Pi_q = q prod_i R_i^{a_i}`` with ``D_R a = -d_q``.

    Raises
    ------
    DimensionalAnalysisError
        When a repeating variable is unknown or repeated, when the repeating variables are
        not independent (the message gives the dimensionless product they form), or when
        they are too few to make every variable dimensionless.
    """
    by_name = {v.name: v for v in variables}
    if len(by_name) != len(variables):
        raise DimensionalAnalysisError("two governing variables have the same name")
    unknown = [r for r in repeating if r not in by_name]
    if unknown:
        raise DimensionalAnalysisError(
            f"unknown repeating variable(s) {', '.join(unknown)}; the variables are "
            f"{', '.join(by_name)}")
    if len(set(repeating)) != len(repeating):
        raise DimensionalAnalysisError(f"a repeating variable is named twice: {', '.join(repeating)}")
    chosen = [by_name[r] for r in repeating]
    needed = rank(dimension_matrix(variables))
    d_rep = dimension_matrix(chosen)
    dependence = null_space(d_rep) if chosen else []
    if dependence:
        product = format_product([(r, x) for r, x in zip(repeating, _integral(dependence[0]))
                                  if x])
        raise DimensionalAnalysisError(
            f"the repeating variables {', '.join(repeating)} are not independent: "
            f"{product} is dimensionless; choose {needed} variables whose dimensions are "
            f"independent ({', '.join(f'{r}: {by_name[r].dimension}' for r in repeating)})")
    groups = []
    for v in variables:
        if v.name in repeating:
            continue
        augmented = [row + [-v.dimension.exponents[i]] for i, row in enumerate(d_rep)]
        rows, pivots = rref(augmented)
        if len(chosen) in pivots:
            raise DimensionalAnalysisError(
                f"the repeating variables {', '.join(repeating)} cannot make {v.name} "
                f"({v.dimension}) dimensionless; the scene's dimension matrix has rank "
                f"{needed}, so choose {needed} independent repeating variables")
        exponents = [(v.name, Fraction(1))]
        exponents += [(repeating[col], rows[row][-1]) for row, col in enumerate(pivots)
                      if rows[row][-1] != 0]
        name = (names or {}).get(v.name, f"Pi_{v.name}")
        groups.append(Group(name, tuple(exponents), v.description))
    return groups


def check_groups(variables: Sequence[Variable], groups: Sequence[Group]) -> None:
    """Raise :class:`DimensionalAnalysisError` unless ``groups`` is a complete Pi set.

    A complete set has every group dimensionless, the groups' exponent vectors linearly
    independent, and ``n - r`` groups (``n`` variables, ``r`` the rank of their dimension
    matrix), so that every dimensionless product of the variables is a product of powers of
    the groups.
    """
    by_name = {v.name: v for v in variables}
    for g in groups:
        dim = g.dimension(by_name)
        if not dim.dimensionless:
            raise DimensionalAnalysisError(f"{g.name} = {g.formula()} has dimension {dim}")
    order = list(by_name)
    exponents = [[g.powers.get(name, Fraction(0)) for name in order] for g in groups]
    if groups and rank(exponents) < len(groups):
        raise DimensionalAnalysisError(
            "the groups are not independent: one is a product of powers of the others")
    expected = len(variables) - rank(dimension_matrix(variables))
    if len(groups) != expected:
        raise DimensionalAnalysisError(
            f"{len(groups)} groups for {len(variables)} variables of dimension rank "
            f"{len(variables) - expected}: a complete set has {expected}")
