"""Similitude of scale models: derived scale ratios from the ones a test designer chooses.

A scale ratio ``S_q = q_model / q_prototype``. In a mechanical problem every ratio follows from
three independent ones (one per base dimension M, L, T): with ``S_q = S_M^a S_L^b S_T^c``
for ``q`` of dimension ``M^a L^b T^c``, choosing e.g. length, elastic modulus and acceleration
fixes ``S_M, S_L, S_T`` and with them everything else. Wu et al. (2021), Table 1, chooses
``S_l = 1/16``, ``S_E = 1`` (the same steel) and ``S_a = 1`` (gravity); then

    S_T = (S_l / S_a)^(1/2) = 1/4,  S_v = 1/4,  S_k = S_E S_l = 1/16,
    S_F = S_E S_l^2 = 1/256 = S_m S_a,  S_m = 1/256,  S_rho = S_m / S_l^3 = 16,

so the density ratio is 16 (added mass), not the 1 the paper's text states.

Ratios are kept exact: a :class:`Ratio` is a product of primes with rational exponents, so
``(1/15)^(1/2)`` stays exact where a float would not, and ``1/256`` prints as ``1/256``.
"""

from __future__ import annotations

import copy
import math
from collections.abc import Mapping
from dataclasses import dataclass
from fractions import Fraction

from pframe.errors import InputError
from pframe.nondim.buckingham import format_product, rank, rref
from pframe.nondim.dimensions import QUANTITY, Dimension
from pframe.nondim.fields import law_field_dimension, scene_field_dimension

#: quantities a similitude table lists: name -> (symbol, dimension); Table 1's rows first
QUANTITIES: dict[str, tuple[str, Dimension]] = {
    "length": ("S_l", QUANTITY["length"]),
    "modulus": ("S_E", QUANTITY["modulus"]),
    "stiffness": ("S_k", QUANTITY["stiffness"]),
    "acceleration": ("S_a", QUANTITY["acceleration"]),
    "time": ("S_T", QUANTITY["time"]),
    "velocity": ("S_v", QUANTITY["velocity"]),
    "displacement": ("S_x", QUANTITY["displacement"]),
    "mass": ("S_m", QUANTITY["mass"]),
    "density": ("S_rho", QUANTITY["density"]),
    "force": ("S_F", QUANTITY["force"]),
    "frequency": ("S_w", QUANTITY["frequency"]),
    "energy": ("S_W", QUANTITY["energy"]),
}


class SimilitudeError(InputError):
    """Scale factors that do not fix exactly one similitude, or a scene value that cannot be
    scaled (``path``: where in the scene's data, ``reason``: why, without the path)."""

    def __init__(self, message: str, path: tuple | None = None, reason: str | None = None):
        super().__init__(message)
        self.path = path
        self.reason = reason or message


def _prime_factors(n: int) -> dict[int, int]:
    if n > 10**15:
        raise SimilitudeError(f"{n} is too large to factor exactly; give a simpler ratio")
    out: dict[int, int] = {}
    p = 2
    while p * p <= n:
        while n % p == 0:
            out[p] = out.get(p, 0) + 1
            n //= p
        p += 1 if p == 2 else 2
    if n > 1:
        out[n] = out.get(n, 0) + 1
    return out


@dataclass(frozen=True)
class Ratio:
    """A positive number ``prod p^x`` over primes ``p`` with rational exponents ``x``."""

    powers: tuple[tuple[int, Fraction], ...] = ()

    @classmethod
    def of(cls, value) -> Ratio:
        value = Fraction(value)
        if value <= 0:
            raise SimilitudeError(f"a scale ratio is positive; got {value}")
        powers = {p: Fraction(x) for p, x in _prime_factors(value.numerator).items()}
        for p, x in _prime_factors(value.denominator).items():
            powers[p] = powers.get(p, Fraction(0)) - x
        return cls._make(powers)

    @classmethod
    def _make(cls, powers: Mapping[int, Fraction]) -> Ratio:
        return cls(tuple(sorted((p, x) for p, x in powers.items() if x)))

    def __mul__(self, other: Ratio) -> Ratio:
        powers = dict(self.powers)
        for p, x in other.powers:
            powers[p] = powers.get(p, Fraction(0)) + x
        return Ratio._make(powers)

    def __pow__(self, exponent) -> Ratio:
        exponent = Fraction(exponent)
        return Ratio._make({p: x * exponent for p, x in self.powers})

    @property
    def exact(self) -> Fraction | None:
        """The ratio as a Fraction when it is rational, else None."""
        if any(x.denominator != 1 for _, x in self.powers):
            return None
        out = Fraction(1)
        for p, x in self.powers:
            out *= Fraction(p) ** int(x)
        return out

    def __float__(self) -> float:
        exact = self.exact
        if exact is not None:
            return float(exact)
        return math.exp(sum(float(x) * math.log(p) for p, x in self.powers))

    def __str__(self) -> str:
        """``1/256``, or ``(1/15)^(1/2)`` for an irrational ratio."""
        exact = self.exact
        if exact is not None:
            return str(exact)
        root = math.lcm(*(x.denominator for _, x in self.powers))
        return f"({(self ** root).exact})^(1/{root})"


def parse_ratio(text) -> Fraction:
    """``"1/16"``, ``"0.0625"``, ``"16"`` or a number, read exactly (``"1/2.5"`` too)."""
    if isinstance(text, (int, Fraction)):
        return Fraction(text)
    if isinstance(text, float):
        return Fraction(repr(text))
    try:
        top, _, bottom = str(text).partition("/")
        value = Fraction(top.strip()) / (Fraction(bottom.strip()) if bottom else 1)
    except (ValueError, ZeroDivisionError):
        raise SimilitudeError(f"{text!r} is not a ratio (write 1/16, 0.0625 or 16)") from None
    if value <= 0:
        raise SimilitudeError(f"a scale ratio is positive; got {text!r}")
    return value


def _solve(columns: list[Dimension], target: Dimension) -> list[Fraction]:
    """Exponents ``c`` with ``sum_i c_i columns_i = target`` (columns independent, spanning)."""
    augmented = [[col.exponents[i] for col in columns] + [target.exponents[i]] for i in range(3)]
    rows, pivots = rref(augmented)
    out = [Fraction(0)] * len(columns)
    for row, col in enumerate(pivots):
        out[col] = rows[row][-1]
    return out


@dataclass(frozen=True)
class Similitude:
    """The similitude fixed by three independent chosen ratios (and any consistent extras)."""

    chosen: tuple[tuple[str, Fraction], ...]
    basis: tuple[str, ...]

    def exponents(self, what: str | Dimension) -> list[Fraction]:
        dimension = QUANTITIES[what][1] if isinstance(what, str) else what
        return _solve([QUANTITIES[b][1] for b in self.basis], dimension)

    def ratio(self, what: str | Dimension) -> Ratio:
        """``S`` of a quantity name of :data:`QUANTITIES` or of any dimension."""
        chosen = dict(self.chosen)
        out = Ratio()
        for name, exponent in zip(self.basis, self.exponents(what)):
            out = out * Ratio.of(chosen[name]) ** exponent
        return out

    def formula(self, what: str | Dimension) -> str:
        """The ratio in terms of the chosen ones, e.g. ``(S_l / S_a)^(1/2)`` as
        ``S_l^(1/2) / S_a^(1/2)``."""
        return format_product([(QUANTITIES[b][0], x)
                               for b, x in zip(self.basis, self.exponents(what)) if x])

    def rows(self) -> list[dict]:
        """One row per quantity of :data:`QUANTITIES`: symbol, dimension, ratio, whether chosen
        or implied, and the formula from the chosen ratios."""
        chosen = dict(self.chosen)
        out = []
        for name, (symbol, dimension) in QUANTITIES.items():
            ratio = self.ratio(name)
            out.append({
                "quantity": name, "symbol": symbol, "dimension": str(dimension),
                "ratio": str(ratio), "value": float(ratio),
                "status": "chosen" if name in chosen else "implied",
                "formula": "" if name in self.basis else self.formula(name),
            })
        return out

    def notes(self) -> list[str]:
        """What a designer should know about the implied ratios."""
        out = []
        density, modulus = self.ratio("density"), self.ratio("modulus")
        if modulus.exact == 1 and density.exact != 1:
            out.append(
                f"density ratio S_rho = {density} with S_E = 1: a model of the prototype's "
                f"material must carry added mass so that its mass per volume is {density} "
                f"times the prototype's (S_m = S_rho S_l^3 = {self.ratio('mass')}).")
        table1 = {"length": Fraction(1, 16), "modulus": Fraction(1), "acceleration": Fraction(1)}
        if all(self.ratio(q) == Ratio.of(v) for q, v in table1.items()):
            out.append("these are the ratios of Wu et al. (2021), Table 1, whose text states "
                       "S_E = S_rho = 1; its S_m = 1/256 with S_l = 1/16 needs S_rho = 16.")
        return out


def similitude(chosen: Mapping[str, object]) -> Similitude:
    """The similitude fixed by the chosen ratios ``{quantity: ratio}``.

    The first three chosen quantities with independent dimensions form the basis; any further
    chosen ratio must equal what the basis implies.

    Raises
    ------
    SimilitudeError
        For an unknown quantity, fewer than three independent ratios, or a further ratio that
        contradicts the implied one (naming both values).
    """
    values = []
    for name, value in chosen.items():
        if name not in QUANTITIES:
            raise SimilitudeError(f"unknown quantity {name!r}; known: {', '.join(QUANTITIES)}")
        values.append((name, parse_ratio(value)))
    basis: list[str] = []
    for name, _ in values:
        trial = basis + [name]
        if rank([[QUANTITIES[n][1].exponents[i] for n in trial] for i in range(3)]) == len(trial):
            basis = trial
    if len(basis) < 3:
        given = ", ".join(f"{n} ({QUANTITIES[n][1]})" for n, _ in values) or "none"
        raise SimilitudeError(
            f"three scale ratios with independent dimensions are needed (one for each of M, L, "
            f"T); given: {given}. For a shaking-table model: length, modulus and acceleration "
            "(S_a = 1 keeps gravity)")
    result = Similitude(tuple(values), tuple(basis))
    for name, value in values:
        implied = result.ratio(name)
        if name not in basis and implied != Ratio.of(value):
            raise SimilitudeError(
                f"the ratios contradict each other: {', '.join(f'{b} {dict(values)[b]}' for b in basis)} "
                f"imply {name} {implied} ({QUANTITIES[name][0]} = {result.formula(name)}), not "
                f"{value}; give three independent ratios, or further ones that agree")
    return result


# ---------------------------------------------------------------------------------------------
# scaling a scene
# ---------------------------------------------------------------------------------------------

def _law_context(path: tuple, node: dict):
    """(kind, law name, the law's fields as written) of the mapping ``node`` at ``path``, if
    it holds a law's parameters."""
    if len(path) == 2 and path[0] == "contacts":
        return ("contact", node.get("law"), node)
    if (len(path) == 2 and path[0] in ("stories", "links")) or (
            len(path) == 3 and path[0] == "buildings" and path[2] == "story") or (
            len(path) == 4 and path[0] == "buildings" and path[2] == "lines"):
        return ("material", node.get("material"), node)
    return None


#: a floor in plan's initial [u_x, u_y, theta] and [v_x, v_y, theta']: the rotation's
#: dimension is not its translations'
_PLAN_TRIPLE = {"displacement": ("length", "length", "dimensionless"),
                "velocity": ("velocity", "velocity", "frequency")}


def _scale_leaf(value, path: tuple, law, factor_of, dimension_at, by_value: bool = False):
    if isinstance(value, bool) or not isinstance(value, (int, float, list)):
        return value
    if isinstance(value, list):
        if path[:1] == ("initial_conditions",) and len(path) == 3 and len(value) == 3:
            return [v * factor_of(QUANTITY[q]) for v, q in zip(value, _PLAN_TRIPLE[path[1]])]
        return [_scale_leaf(v, path, law, factor_of, dimension_at, by_value) for v in value]
    dimension = dimension_at(path)
    if dimension is None and law is not None and isinstance(law[1], str):
        try:
            dimension = law_field_dimension(law[0], law[1], path[-1],
                                            law[2] if by_value else None)
        except InputError as exc:
            raise _unscalable(path, str(exc)) from None
    if dimension is None:
        raise _unscalable(path, "its dimension is unknown")
    return value if dimension.dimensionless else value * factor_of(dimension)


def _unscalable(path: tuple, reason: str) -> SimilitudeError:
    return SimilitudeError(f"cannot scale {'.'.join(map(str, path))}: {reason}", path,
                           f"cannot scale this value: {reason}")


def walk_scene(node, factor_of, dimension_at=scene_field_dimension, by_value: bool = False,
               path: tuple = (), law=None):
    """``node`` (a scene's data, or a part of it at ``path``) with every number multiplied by
    ``factor_of(dimension)``; the dimension of a number from ``dimension_at(path)`` (default:
    :data:`pframe.nondim.fields.SCENE_FIELDS`) or, for a law's parameter, from the law's
    declarations (:func:`pframe.nondim.fields.law_field_dimension`; ``by_value``: a dimension
    that depends on the law's other fields, a dashpot's on its exponent, is taken from their
    values as written, where a similitude refuses it).

    Raises
    ------
    SimilitudeError
        For a number whose dimension is unknown, with its ``path``.
    """
    if isinstance(node, dict):
        law = _law_context(path, node) or law
        return {k: walk_scene(v, factor_of, dimension_at, by_value, path + (k,), law)
                for k, v in node.items()}
    if isinstance(node, list) and node and all(isinstance(v, dict) for v in node):
        return [walk_scene(v, factor_of, dimension_at, by_value, path + (i,), law)
                for i, v in enumerate(node)]
    return _scale_leaf(node, path, law, factor_of, dimension_at, by_value)


def scale_scene(data: dict, sim: Similitude, to: str = "model") -> dict:
    """A scene (YAML data, dimensional or Pi form) scaled to model or to prototype size.

    Every number is multiplied by ``S`` of its dimension (``to="model"``) or divided by it
    (``to="prototype"``); dimensionless numbers, recorders and the title are kept. A Pi-form
    scene keeps its Pi numbers: only its reference ``scales`` change.

    Raises
    ------
    SimilitudeError
        For a record excitation when ``S_T != 1`` and it gives no ``frequency`` (its time axis
        is then the file's), and for a number whose dimension is unknown.
    """
    if to not in ("model", "prototype"):
        raise SimilitudeError(f"scale to 'model' or 'prototype', not {to!r}")
    sign = 1 if to == "model" else -1

    def factor_of(dimension: Dimension) -> float:
        return float(sim.ratio(dimension) ** sign)

    if "pi" in data:
        from pframe.nondim.pi_form import SCALE_QUANTITY

        scales = dict(data.get("scales") or {})
        record = (data.get("excitation") or {}).get("kind") == "record"
        if record and not {"a_p", "w_p"} <= scales.keys():
            raise SimilitudeError(
                "the Pi-form scene's record is used at its own PGA and characteristic frequency "
                "(no scales.a_p, scales.w_p); write them in scales (pframe expand prints them) "
                "and scale again")
        for key, quantity in SCALE_QUANTITY.items():
            scales[key] = float(scales.get(key, 1.0)) * factor_of(QUANTITY[quantity])
        return {**data, "scales": scales}
    motions = _scene_motions(data)
    for where, motion in motions.items():
        _check_motion(motion, ".".join(map(str, where)), sim)
    kept = {k: data[k] for k in ("title", "recorders") if k in data}
    walked = copy.deepcopy({k: v for k, v in data.items() if k not in kept})
    stochastic = [w for w, m in motions.items() if m.get("kind") == "stochastic"]
    for where in stochastic:  # kept as it is (S_T = S_a = 1, checked)
        _parent(walked, where).pop(where[-1])
    out = walk_scene(walked, factor_of)
    for where in stochastic:
        _parent(out, where, create=True)[where[-1]] = motions[where]
    for where, motion in motions.items():
        if motion.get("kind") == "record" and "period" in motion:  # of the file's time axis
            _parent(out, where)[where[-1]]["period"] = motion["period"]
    return {k: (kept[k] if k in kept else _ordered(out[k], data[k])) for k in data}


def _scene_motions(data: dict) -> dict:
    """Every motion of a scene by its path: the excitation, each of two components, the
    motion a wave passage carries, each support's own."""
    out = {}
    places = [(("excitation",), data.get("excitation"))] + [
        (("supports", i, "excitation"), s.get("excitation"))
        for i, s in enumerate(data.get("supports") or []) if isinstance(s, dict)]
    for where, excitation in places:
        if isinstance(excitation, dict):
            out.update(_motions(excitation, where))
    return out


def _motions(excitation: dict, where: tuple) -> dict:
    """The motions of one excitation by path: itself, each of two components, the motion a
    wave passage carries."""
    if excitation.get("kind") == "components":
        return {where + (axis,): excitation[axis] for axis in ("x", "y")
                if isinstance(excitation.get(axis), dict)}
    if excitation.get("kind") == "wave_passage" and isinstance(excitation.get("motion"), dict):
        return _motions(excitation["motion"], where + ("motion",))
    if excitation.get("kind") == "coherent":  # its stochastic motion and its record
        return {where + (key,): excitation[key] for key in ("motion", "record")
                if isinstance(excitation.get(key), dict)}
    return {where: excitation}


def _parent(data, where: tuple, create: bool = False):
    """The container of ``where`` in nested data (``create``: making the missing mappings)."""
    node = data
    for key in where[:-1]:
        if create and isinstance(node, dict) and key not in node:
            node[key] = {}
        node = node[key]
    return node


def _ordered(value, like):
    """``value`` with the keys of its mappings in ``like``'s order (a motion kept aside and
    put back stands where the scene wrote it)."""
    if isinstance(value, dict) and isinstance(like, dict):
        return {k: _ordered(value[k], like[k]) for k in like if k in value} | {
            k: v for k, v in value.items() if k not in like}
    if isinstance(value, list) and isinstance(like, list) and len(value) == len(like):
        return [_ordered(v, w) for v, w in zip(value, like)]
    return value


def _check_motion(motion: dict, where: str, sim: Similitude) -> None:
    """Refuse a motion similitude cannot scale: a stochastic one unless S_T = S_a = 1, a
    record at another time scale without its characteristic frequency."""
    if motion.get("kind") == "stochastic":
        if sim.ratio("time").exact != 1 or sim.ratio("acceleration").exact != 1:
            raise SimilitudeError(
                f"the scene's {where} is a stochastic motion and S_T = {sim.ratio('time')}, "
                f"S_a = {sim.ratio('acceleration')}: its model describes prototype earthquakes "
                "(a magnitude and distance, or filter frequencies and an intensity), which "
                "similitude does not scale; write the motion as a record file (time x S_T, "
                "acceleration x S_a) and point the excitation at it")
    elif motion.get("kind") == "record" and sim.ratio("time").exact != 1 \
            and "frequency" not in motion:
        raise SimilitudeError(
            f"the scene's {where} is a record and S_T = {sim.ratio('time')}: give "
            f"{where}.frequency (the record's characteristic frequency 2 pi / T, which "
            "pframe pi prints as w_p) so that its time axis is scaled with it, or write the "
            f"scaled record (time x S_T, acceleration x S_a) and point {where}.file at it")
