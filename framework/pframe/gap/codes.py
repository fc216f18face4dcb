"""The building codes' separation rules as data (docs/gap-audit.md#code-rules).

One table, :data:`CODES`, holds every built-in rule: its code and clause, the source its text
was read in, its factors with their defaults, how a building's displacement is amplified, how
the two buildings' displacements combine, its minimum and what aligned floors change. The
``--codes`` choices, ``pframe gap --help``, the docs table and the result file's description of
the rules are derived from it; a rule the user writes (:func:`user_rule`) has the same fields.

Two displacements per rule, both per building and arrays (records x levels x contacts, or
anything that broadcasts, so that displacements at the critical locations of buildings in plan
can be fed later):

- d, the displacement the clause starts from (ASCE 7's delta_max, IS 1893's Delta, TBDY's
  reduced u_i, NBC's linear-analysis deflection, EN 1998's d_e): :func:`separation` takes it;
- u, the peak displacement pframe simulates under the motion, elastic and without contact:
  :func:`separation_from_peaks` takes it, with d = u x ``design`` (the codes' design forces are
  the motion's elastic forces divided by their force reduction, so an elastic building's d is
  its u times I / R).
"""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Callable

import numpy as np

from pframe.errors import InputError

#: how a height is counted in steps of a minimum that grows by a step per so many metres
STEP_CONVENTIONS = ("started", "completed", "linear")


@dataclasses.dataclass(frozen=True)
class Factor:
    """A factor a rule takes: its default, its meaning, the values it may take (strings, or
    numbers for a choice such as the intensity); numbers are otherwise > 0."""

    default: float | str
    meaning: str
    choices: tuple = ()


@dataclasses.dataclass(frozen=True)
class Rule:
    """A separation rule (module docstring). ``design`` and ``amplify`` are pairs (factors
    multiplied, factors divided): d = u prod(design[0]) / prod(design[1]); the displacement
    the clause combines is d prod(amplify[0]) / prod(amplify[1])."""

    name: str
    code: str
    clause: str
    source: str
    formula: str
    factors: tuple[tuple[str, Factor], ...] = ()
    design: tuple[tuple[str, ...], tuple[str, ...]] = ((), ())
    amplify: tuple[tuple[str, ...], tuple[str, ...]] = ((), ())
    combination: str = "srss"  # sum | srss | cqc | none
    aligned_factor: float = 1.0
    unaligned_factor: float = 1.0
    aligned_note: str = "aligned floors change nothing"
    #: (level height m, building heights (a, b) m, factors a, b) -> minimum separation (m)
    minimum: Callable | None = None
    minimum_note: str = ""
    #: per building, before the combination: (displacement, level height, factors) -> m
    each: Callable | None = None
    #: the aligned-floor factor also needs the same roof height and this factor set to 1
    needs_same_height: bool = False
    same_structure: str | None = None
    #: what the user gave (a user rule's text), for the result file
    text: str = ""

    def resolved(self, given: dict | None = None) -> dict:
        """The factors with their defaults, ``given`` (name -> value) checked and applied."""
        known = dict(self.factors)
        out = {k: f.default for k, f in known.items()}
        for key, value in (given or {}).items():
            if key not in known:
                raise InputError(f"code rule {self.name}: factor {key!r} is not one of "
                                 f"{', '.join(known) or 'its factors (it has none)'}")
            choices = known[key].choices
            if choices:
                if isinstance(value, str) or not isinstance(value, (int, float)):
                    ok = str(value) in [str(c) for c in choices]
                    value = next((c for c in choices if str(c) == str(value)), value)
                else:
                    ok = value in choices
                if not ok:
                    raise InputError(f"code rule {self.name}: factor {key} = {value!r} must "
                                     f"be one of {', '.join(str(c) for c in choices)}")
            elif not (isinstance(value, (int, float)) and not isinstance(value, bool)
                      and math.isfinite(value) and value > 0):
                raise InputError(f"code rule {self.name}: factor {key} = {value!r} must be a "
                                 "number > 0")
            out[key] = value
        return out


def _ratio(pair, factors: dict) -> float:
    num, den = pair
    return math.prod(float(factors[k]) for k in num) / math.prod(float(factors[k]) for k in den)


def steps(excess, step: float, convention: str) -> np.ndarray:
    """How many steps of ``step`` metres a height ``excess`` m above the threshold counts:
    ``started`` (every step begun counts: ceil), ``completed`` (floor) or ``linear``
    (excess / step); 0 below the threshold, NaN for an unknown height."""
    x = np.maximum(np.asarray(excess, float) / step, 0.0)
    if convention == "started":
        return np.ceil(x - 1e-9)
    if convention == "completed":
        return np.floor(x + 1e-9)
    return x


# --- the clauses' minima (functions of heights), each from its source ---------------------

def _tbdy_minimum(level, heights, fa, fb):
    """TBDY 2018 4.9.3.2: at least 30 mm up to 6 m of height, and at least 10 mm more for
    each 3 m above 6 m; at the contact's level (the higher of its two nodes)."""
    return 0.030 + 0.010 * steps(np.asarray(level, float) - 6.0, 3.0, fa["steps"])


#: GB 50011-2010 6.1.4 1) 1): metres of height per 20 mm of width above 15 m, by intensity
GB_STEP = {6: 5.0, 7: 4.0, 8: 3.0, 9: 2.0}
#: 6.1.4 1) 2): fraction of the frame's width by structural system
GB_SYSTEM = {"frame": 1.0, "frame-wall": 0.7, "wall": 0.5}


def _gb_width(level, heights, fa, fb):
    """GB 50011-2010 6.1.4 1): a frame 100 mm up to 15 m, then 20 mm more per 5, 4, 3, 2 m
    at intensity 6, 7, 8, 9; frame-wall 70 %, wall 50 % of it, neither below 100 mm; two
    systems: the one needing the wider joint and the lower building's height (item 3))."""
    system = max((fa["system"], fb["system"]), key=lambda s: GB_SYSTEM[s])
    height = np.minimum(np.asarray(heights[0], float), np.asarray(heights[1], float))
    frame = 0.100 + 0.020 * steps(height - 15.0, GB_STEP[int(fa["intensity"])], fa["steps"])
    return np.maximum(GB_SYSTEM[system] * frame, 0.100)


#: NTC-DS 2004 1.10: the height coefficient by zone
NTC_ZONE = {"I": 0.001, "II": 0.003, "III": 0.006}


def _ntc_each(d, level, factors):
    """NTC-DS 1.10: each building's separation from its boundary, at least 50 mm and at least
    its computed displacement plus 0.001, 0.003 or 0.006 times the level's height (zone I,
    II, III)."""
    return np.maximum(0.050, d + NTC_ZONE[factors["zone"]] * np.asarray(level, float))


_R = Factor(8.0, "response modification coefficient R")
_STEPS = Factor("started", "how a height counts in the minimum's steps: started (every "
                "step begun), completed or linear", STEP_CONVENTIONS)

#: the built-in code rules by the name ``--codes`` takes (a name may give several rules)
CODES: dict[str, tuple[Rule, ...]] = {
    "asce7": (
        Rule("ASCE7_same_property", "ASCE/SEI 7-16", "12.12.3",
             "ASCE/SEI 7-16 12.12.3 (Structural Separation), read in a copy of its page "
             "(scribd.com/document/408979656): delta_M = C_d delta_max / I_e (eq. 12.12-1) at "
             "critical locations, delta_max the maximum elastic displacement; adjacent "
             "structures on the same property at least delta_MT = sqrt(delta_M1^2 + "
             "delta_M2^2) (eq. 12.12-2); no provision for aligned floors. ASCE 7-22 keeps "
             "the equations; its section's number could not be read here, so the clause "
             "cited is the 2016 edition's",
             "sqrt(delta_M1^2 + delta_M2^2), delta_M = C_d delta_max / I_e",
             (("R", _R), ("Cd", Factor(5.5, "deflection amplification factor C_d")),
              ("Ie", Factor(1.0, "importance factor I_e"))),
             design=(("Ie",), ("R",)), amplify=(("Cd",), ("Ie",)), combination="srss"),
        Rule("ASCE7_property_line", "ASCE/SEI 7-16", "12.12.3",
             "as ASCE7_same_property: a structure adjoining a property line not common to a "
             "public way is set back from it by at least its delta_M, so two buildings on "
             "either side of the line stand delta_M1 + delta_M2 apart",
             "delta_M1 + delta_M2",
             (("R", _R), ("Cd", Factor(5.5, "deflection amplification factor C_d")),
              ("Ie", Factor(1.0, "importance factor I_e"))),
             design=(("Ie",), ("R",)), amplify=(("Cd",), ("Ie",)), combination="sum"),
    ),
    "is1893": (
        Rule("IS1893", "IS 1893 (Part 1):2016", "7.11.3",
             "the standard's text could not be read while this was written; the rule is "
             "pframe's earlier one, as an open IS 1893 design checker states clause 7.11.3 "
             "with Amendment 1: R1 Delta1 + R2 Delta2, halved where the floor levels match, "
             "Delta the storey displacement under the design lateral force (7.11.1)",
             "R_A Delta_A + R_B Delta_B; (R_A Delta_A + R_B Delta_B) / 2 where floors align",
             (("R", Factor(5.0, "response reduction factor R")),
              ("I", Factor(1.0, "importance factor I"))),
             design=(("I",), ("R",)), amplify=(("R",), ()), combination="sum",
             aligned_factor=0.5, aligned_note="x 1/2 (R replaced by R/2)"),
    ),
    "en1998": (
        Rule("EN1998", "EN 1998-1:2004", "4.4.2.7",
             "4.3.4: d_s = q_d d_e, d_e from the linear analysis under the design spectrum, "
             "q_d = q unless otherwise specified (FEM-Design theory manual, Seismic analysis, "
             "Displacement calculation; civiloutline.blogspot.com/2020/01). The text of "
             "4.4.2.7 itself could not be read while this was written: the rule is pframe's "
             "earlier one (the SRSS of the two d_s at the level, 0.7 of it where the floor "
             "levels coincide)",
             "sqrt(d_sA^2 + d_sB^2), d_s = q_d d_e; x 0.7 where floors align",
             (("q", Factor(1.0, "behaviour factor q")),
              ("qd", Factor(1.0, "displacement behaviour factor q_d (give q and q_d; the "
                            "clause takes q_d = q unless specified)"))),
             design=((), ("q",)), amplify=(("qd",), ()), combination="srss",
             aligned_factor=0.7, aligned_note="x 0.7"),
    ),
    "nbcc": (
        Rule("NBCC", "NBC of Canada", "4.1.8.14",
             "4.1.8.14 (1) and 4.1.8.13 (2), wording read in the Ontario Building Code, "
             "Division B, which reproduces them (buildingcode.online/707.html and /706.html): "
             "adjacent structures separated by the square root of the sum of the squares of "
             "their deflections, the linear-analysis deflections multiplied by R_d R_o / I_E; "
             "the 2020 edition's own text was not read",
             "sqrt(dA^2 + dB^2), d = R_d R_o delta / I_E",
             (("Rd", Factor(1.0, "ductility-related force modification factor R_d")),
              ("Ro", Factor(1.0, "overstrength-related force modification factor R_o")),
              ("IE", Factor(1.0, "earthquake importance factor I_E"))),
             design=(("IE",), ("Rd", "Ro")), amplify=(("Rd", "Ro"), ("IE",)),
             combination="srss"),
    ),
    "tbdy2018": (
        Rule("TBDY2018", "TBDY 2018", "4.9.3",
             "4.9.3.1 and 4.9.3.2, Turkish text read in a transcription of the regulation "
             "(GitHub nubufi/GeoBot, src/data/markdowns/section4.md): at each storey alpha "
             "times the SRSS of the two blocks' reduced displacements u_i(X) (storey "
             "averages), alpha = 0.25 R/I when the floors of the two are at the same level "
             "on every storey, 0.5 R/I for the whole building when they differ on any; not "
             "less than 30 mm up to 6 m of height plus 10 mm for each 3 m above 6 m",
             "alpha sqrt(u_A^2 + u_B^2), alpha = 0.25 R/I (floors aligned) or 0.5 R/I; at "
             "least 30 mm + 10 mm per 3 m above 6 m",
             (("R", Factor(8.0, "structural system behaviour factor R")),
              ("I", Factor(1.0, "building importance factor I")), ("steps", _STEPS)),
             design=(("I",), ("R",)), amplify=(("R",), ("I",)), combination="srss",
             aligned_factor=0.25, unaligned_factor=0.5,
             aligned_note="alpha = 0.25 R/I; 0.5 R/I otherwise (twice)",
             minimum=_tbdy_minimum,
             minimum_note="30 mm up to 6 m, + 10 mm per 3 m above, at the contact's level"),
    ),
    "ntc": (
        Rule("NTC_DS", "NTC Diseno por Sismo (Mexico City, 2004)", "1.10",
             "1.10 Separacion de edificios colindantes, text read at "
             "es.scribd.com/document/671909992: each building at least 50 mm from its "
             "boundary and at least its computed displacement at the level plus 0.001, 0.003 "
             "or 0.006 times the level's height (zones I, II, III); between adjacent "
             "buildings the sum of the two; one half of it if both have the same height and "
             "structure and their slabs coincide at every level. The computed displacement is "
             "defined in 1.8, whose text was not read: the factor 'amplification' takes it "
             "from the simulated peak",
             "s_A + s_B, s = max(50 mm, d + k h), k = 0.001, 0.003, 0.006 (zones I, II, III); "
             "x 1/2 for the same height and structure with aligned slabs",
             (("zone", Factor("III", "zone I, II or III", ("I", "II", "III"))),
              ("amplification", Factor(1.0, "the computed displacement over the simulated "
                                            "elastic peak (1: the peak itself)")),
              ("same_structure", Factor(0, "1 when both have the same structure "
                                           "(estructuracion)", (0, 1)))),
             design=(("amplification",), ()), combination="sum",
             aligned_factor=0.5,
             aligned_note="x 1/2 only with the same height, same_structure = 1 and aligned slabs",
             each=_ntc_each, needs_same_height=True, same_structure="same_structure"),
    ),
    "gb50011": (
        Rule("GB50011", "GB 50011-2010", "6.1.4",
             "6.1.4 item 1, text quoted at kaowang.cn/shiti/2364995.html and "
             "v5tt.cn/wenda/460817.html: frame buildings 100 mm up to 15 m, then 20 mm more "
             "per 5, 4, 3 or 2 m of height at intensity 6, 7, 8 or 9; frame-shear wall 70 %, "
             "shear wall 50 % of it, neither below 100 mm; different systems on the two "
             "sides: the one needing the wider joint and the lower building's height",
             "100 mm + 20 mm per 5/4/3/2 m above 15 m (frame); x 0.7 frame-wall, x 0.5 wall, "
             ">= 100 mm",
             (("intensity", Factor(9, "seismic fortification intensity 6 to 9", (6, 7, 8, 9))),
              ("system", Factor("frame", "frame, frame-wall or wall", tuple(GB_SYSTEM))),
              ("steps", _STEPS)),
             combination="none", aligned_note="no aligned-floor provision",
             minimum=_gb_width, minimum_note="the width itself (no displacement)"),
    ),
}

#: every built-in rule by its result name
RULES_BY_NAME: dict[str, Rule] = {r.name: r for rules in CODES.values() for r in rules}


def lookup(rule) -> Rule:
    """A :class:`Rule`, or a built-in rule's name (its result name, or its ``--codes`` name
    when that gives one rule)."""
    if isinstance(rule, Rule):
        return rule
    text = str(rule)
    if text in RULES_BY_NAME:
        return RULES_BY_NAME[text]
    if text.lower() in CODES and len(CODES[text.lower()]) == 1:
        return CODES[text.lower()][0]
    raise InputError(f"code rule {text!r}: pframe knows "
                     f"{', '.join(sorted(RULES_BY_NAME))} (--codes {', '.join(CODES)})")


def _combine(rule: Rule, a, b, rho):
    if rule.combination == "sum":
        return a + b
    if rule.combination == "srss":
        return np.sqrt(a * a + b * b)
    if rule.combination == "cqc":
        if rho is None:
            raise InputError(f"code rule {rule.name}: the cqc combination needs the "
                             "correlation rho of the two buildings' first modes")
        return np.sqrt(np.maximum(a * a + b * b - 2.0 * np.asarray(rho) * a * b, 0.0))
    return np.zeros(np.broadcast(a, b).shape)


def separation(rule, d_a, d_b, *, aligned=False, level=math.nan, level_b=None,
               heights=(math.nan, math.nan), same_height=None, rho=None,
               factors=None, factors_a=None, factors_b=None) -> np.ndarray:
    """The separation (m) a rule asks for between buildings A and B at one level.

    ``d_a``, ``d_b``: each building's displacement as the clause defines it (m; see the
    module docstring and docs/gap-audit.md), arrays that broadcast. ``aligned``: whether the
    floors align (bool, or an array of 1/0; NaN counts as not aligned). ``level`` (and
    ``level_b`` when B's floor stands elsewhere): the level's height above the ground (m);
    ``heights``: the two buildings' heights (m); ``same_height``: whether their roofs stand
    at the same height (default: ``heights`` equal). ``rho``: the correlation of the two
    buildings' first modes (cqc only). ``factors`` apply to both buildings, ``factors_a`` /
    ``factors_b`` to one (over ``factors``).
    """
    rule = lookup(rule)
    fa = rule.resolved({**(factors or {}), **(factors_a or {})})
    fb = rule.resolved({**(factors or {}), **(factors_b or {})})
    level_a = np.asarray(level, float)
    level_b = level_a if level_b is None else np.asarray(level_b, float)
    a = np.abs(np.asarray(d_a, float)) * _ratio(rule.amplify, fa)
    b = np.abs(np.asarray(d_b, float)) * _ratio(rule.amplify, fb)
    if rule.each is not None:
        a, b = rule.each(a, level_a, fa), rule.each(b, level_b, fb)
    together = np.asarray(aligned, float) == 1.0
    if rule.needs_same_height:
        same = (np.asarray(same_height, float) == 1.0 if same_height is not None
                else np.isclose(np.asarray(heights[0], float), np.asarray(heights[1], float)))
        together = together & same
    if rule.same_structure is not None:
        together = together & (float(fa[rule.same_structure]) == 1.0) \
            & (float(fb[rule.same_structure]) == 1.0)
    out = np.where(together, rule.aligned_factor, rule.unaligned_factor) * \
        _combine(rule, a, b, rho)
    if rule.minimum is not None:
        out = np.maximum(out, rule.minimum(np.maximum(level_a, level_b), heights, fa, fb))
    return out


def design_ratio(rule, factors: dict | None = None) -> float:
    """d / u of a rule: the clause's displacement over the simulated elastic peak."""
    rule = lookup(rule)
    return _ratio(rule.design, rule.resolved(factors))


def separation_from_peaks(rule, u_a, u_b, *, factors=None, factors_a=None, factors_b=None,
                          **context) -> np.ndarray:
    """:func:`separation` from the simulated elastic peak displacements u (m) of the two
    buildings: each d = u x :func:`design_ratio` with its own factors."""
    rule = lookup(rule)
    ga = {**(factors or {}), **(factors_a or {})}
    gb = {**(factors or {}), **(factors_b or {})}
    return separation(rule, np.abs(np.asarray(u_a, float)) * design_ratio(rule, ga),
                      np.abs(np.asarray(u_b, float)) * design_ratio(rule, gb),
                      factors_a=ga, factors_b=gb, **context)


def codes_help() -> str:
    """The ``--codes`` choices as ``pframe gap --help`` lists them: each name, its code and
    clause, its factors with their defaults."""
    parts = []
    for name, rules in CODES.items():
        rule = rules[0]
        factors = ", ".join(f"{k} {f.default}" for k, f in rule.factors)
        parts.append(f"{name} ({rule.code} {rule.clause}"
                     + (f"; {factors}" if factors else "") + ")")
    return "; ".join(parts)


def docs_table() -> str:
    """The docs' table of the built-in code rules (docs/gap-audit.md#code-rules), derived
    from :data:`CODES`; ``tests/test_code_rules.py`` checks the docs hold it."""
    rows = ["| `--codes` | Rule | Code, clause | Separation | Aligned floors | Factors (default) "
            "| Where the text was read |", "|---|---|---|---|---|---|---|"]
    for name, rules in CODES.items():
        for rule in rules:
            factors = ", ".join(f"{k} ({f.default})" for k, f in rule.factors) or "none"
            rows.append(f"| `{name}` | `{rule.name}` | {rule.code} {rule.clause} | "
                        f"{rule.formula} | {rule.aligned_note} | {factors} | {rule.source} |")
    return "\n".join(rows)
