"""Which code rules an audit or a study applies, with which factors, and their values over its
runs (docs/gap-audit.md#code-rules).

The selection is written as ``--codes`` text (``asce7,tbdy2018:R=6:I=1.2,gb50011:intensity=8``;
``R.B=6`` for building B alone; ``all``), as a list or mapping in Python, or in YAML (the
``codes:`` of a study file, or a file given to ``--codes``)::

    codes:
      rules:
        - asce7
        - {code: tbdy2018, R: 6, I: 1.2}
        - {code: is1893, R: 5, buildings: {B: {R: 4}}}
        - {name: NZS_7_4, text: "the clause's words", combination: srss,
           amplification: 1.0, minimum: 0.0, aligned_factor: 1.0}
      aligned: true               # instead of the decision from the storey heights
      floor_tolerance: 0.05       # m
"""

from __future__ import annotations

import dataclasses
import math
from pathlib import Path

import numpy as np

from pframe.errors import InputError
from pframe.gap.codes import CODES, Factor, Rule, separation_from_peaks
from pframe.gap.floors import FLOOR_TOLERANCE

USER_FIELDS = ("name", "text", "clause", "amplification", "combination", "minimum",
               "aligned_factor")
CONFIG_FIELDS = ("rules", "aligned", "floor_tolerance")


@dataclasses.dataclass(frozen=True)
class Chosen:
    """A rule with its factors: for both buildings, and per building name."""

    rule: Rule
    factors: dict
    buildings: dict

    def factors_of(self, building: str) -> dict:
        return {**self.factors, **self.buildings.get(building, {})}


@dataclasses.dataclass(frozen=True)
class Selection:
    """The chosen rules, the aligned-floor override (None: from the storey heights) and the
    floor tolerance (m)."""

    chosen: tuple[Chosen, ...] = ()
    aligned: bool | None = None
    tolerance: float = FLOOR_TOLERANCE

    @property
    def names(self) -> list[str]:
        return [c.rule.name for c in self.chosen]


def user_rule(spec: dict, where: str = "codes") -> Rule:
    """A rule the user writes (docs/gap-audit.md#a-rule-of-your-own): ``name``, ``text`` (the
    clause's words or where its factors come from: written to the result file), ``clause``,
    ``amplification`` (on each building's simulated elastic peak), ``combination`` (sum,
    srss or cqc), ``minimum`` (m) and ``aligned_factor`` (on the combination where the
    floors align)."""
    from pframe.gap.codes import RULES_BY_NAME

    unknown = sorted(set(spec) - set(USER_FIELDS))
    if unknown:
        raise InputError(f"{where}: {', '.join(unknown)} {'is' if len(unknown) == 1 else 'are'}"
                         f" not a field of a rule of your own; its fields are "
                         f"{', '.join(USER_FIELDS)}")
    name = spec.get("name")
    if not isinstance(name, str) or not name.replace("_", "").replace("-", "").isalnum():
        raise InputError(f"{where}: a rule of your own needs a name (letters, digits, _ or -)")
    if name in RULES_BY_NAME or name.lower() in CODES or name in ("ABS", "SRSS", "DDC",
                                                                 "simulated"):
        raise InputError(f"{where}: {name!r} is a built-in rule's name; give yours another")
    text = spec.get("text")
    if not isinstance(text, str) or not text.strip():
        raise InputError(f"{where} ({name}): give text, the clause's words or where its "
                         "factors come from (it is written to the result file)")
    combination = spec.get("combination")
    if combination not in ("sum", "srss", "cqc"):
        raise InputError(f"{where} ({name}): combination is sum, srss or cqc, not "
                         f"{combination!r}")
    numbers = {}
    for key, default in (("minimum", 0.0), ("aligned_factor", 1.0)):
        value = spec.get(key, default)
        if not (isinstance(value, (int, float)) and not isinstance(value, bool)
                and math.isfinite(value) and value >= 0):
            raise InputError(f"{where} ({name}): {key} = {value!r} must be a number >= 0")
        numbers[key] = float(value)
    if numbers["aligned_factor"] <= 0:
        raise InputError(f"{where} ({name}): aligned_factor must be > 0")
    floor, factor = numbers["minimum"], numbers["aligned_factor"]
    return Rule(name, "user rule", str(spec.get("clause", "")), text.strip(),
                f"{combination} of the amplified displacements"
                + (f", x {factor:g} where floors align" if factor != 1 else "")
                + (f"; at least {1000 * floor:g} mm" if floor else ""),
                (("amplification", Factor(1.0, "on the building's simulated elastic peak")),),
                amplify=(("amplification",), ()), combination=combination,
                aligned_factor=factor, aligned_note=f"x {factor:g}",
                minimum=(_constant(floor) if floor else None),
                minimum_note=f"{1000 * floor:g} mm" if floor else "", text=text.strip())


def _constant(value: float):
    def minimum(level, heights, fa, fb):
        return np.full(np.shape(level), value)
    return minimum


def _number(text: str):
    try:
        return float(text)
    except ValueError:
        return text


def _from_text(text: str) -> list:
    """``--codes`` text to the list form: ``name[:key=value[:key.BUILDING=value]]``."""
    out = []
    for item in (t.strip() for t in text.split(",") if t.strip()):
        name, *pairs = item.split(":")
        if name.strip().lower() == "all" and not pairs:
            out.extend(CODES)
            continue
        spec: dict = {"code": name.strip()}
        for pair in pairs:
            key, sep, value = pair.partition("=")
            if not sep or not key.strip():
                raise InputError(f"--codes {text}: {pair!r} is not key=value (e.g. "
                                 "tbdy2018:R=6:I=1.2, or R.B=6 for building B)")
            key, _, building = key.strip().partition(".")
            target = spec.setdefault("buildings", {}).setdefault(building, {}) if building \
                else spec
            target[key] = _number(value.strip())
        out.append(spec)
    return out


def _chosen(item, where: str) -> list[Chosen]:
    if isinstance(item, str):
        item = {"code": item}
    if not isinstance(item, dict):
        raise InputError(f"{where}: a rule is a code's name, {{code: NAME, factors...}} or a "
                         "rule of your own {name, text, combination, ...}")
    if "name" in item and "code" not in item:
        spec = dict(item)
        amplification = spec.pop("amplification", 1.0)
        rule = user_rule({**spec}, where)
        per = amplification if isinstance(amplification, dict) else {}
        both = {} if per else {"amplification": amplification}
        for given in [both, *({"amplification": v} for v in per.values())]:
            rule.resolved(given)
        return [Chosen(rule, both, {str(b): {"amplification": v} for b, v in per.items()})]
    spec = dict(item)
    code = str(spec.pop("code", "")).lower()
    if code not in CODES:
        raise InputError(f"{where}: code rule {code!r}: pframe knows {', '.join(CODES)}, or "
                         "a rule of your own (name, text, combination, ...)")
    buildings = spec.pop("buildings", {}) or {}
    if not isinstance(buildings, dict):
        raise InputError(f"{where} ({code}): buildings maps a building's name to its factors")
    out = []
    for rule in CODES[code]:
        rule.resolved(spec)
        for given in buildings.values():
            rule.resolved({**spec, **(given or {})})
        out.append(Chosen(rule, dict(spec), {str(b): dict(g or {}) for b, g in
                                             buildings.items()}))
    return out


def selection(codes=None, *, aligned: bool | None = None,
              tolerance: float | None = None, where: str = "codes") -> Selection:
    """The :class:`Selection` of ``codes``: ``--codes`` text (or a YAML file's path), a list,
    a mapping ``{code: factors}``, a mapping with ``rules`` / ``aligned`` /
    ``floor_tolerance``, or a Selection; ``aligned`` and ``tolerance`` replace the ones it
    gives."""
    if isinstance(codes, Selection):
        found = codes
    else:
        config: dict = {}
        if isinstance(codes, (str, Path)) and str(codes).lower().endswith((".yaml", ".yml")):
            codes, where = _read(Path(codes)), f"{codes}, at codes"
        if isinstance(codes, str):
            config["rules"] = _from_text(codes)
            where = f"--codes {codes}" if where == "codes" else where
        elif isinstance(codes, dict) and set(codes) <= set(CONFIG_FIELDS) and codes:
            config = dict(codes)
        elif isinstance(codes, dict):
            config["rules"] = [{"code": k, **(v or {})} for k, v in codes.items()]
        elif codes:
            config["rules"] = list(codes)
        rules = config.get("rules") or []
        if isinstance(rules, (str, dict)):
            rules = _from_text(rules) if isinstance(rules, str) else [rules]
        chosen = []
        for i, item in enumerate(rules):
            item_where = where if where.startswith("--codes") else f"{where}[{i}]"
            try:
                chosen.extend(_chosen(item, item_where))
            except InputError as exc:
                text = str(exc)
                raise InputError(text if text.startswith(item_where) else
                                 f"{item_where}: {text}") from None
        names = [c.rule.name for c in chosen]
        twice = sorted({n for n in names if names.count(n) > 1})
        if twice:
            raise InputError(f"{where}: {', '.join(twice)} chosen twice; choose each rule once")
        found = Selection(tuple(chosen), _aligned(config.get("aligned"), where),
                          _tolerance(config.get("floor_tolerance"), where))
    if aligned is not None:
        found = dataclasses.replace(found, aligned=_aligned(aligned, "aligned"))
    if tolerance is not None:
        found = dataclasses.replace(found, tolerance=_tolerance(tolerance, "floor_tolerance"))
    return found


def _aligned(value, where):
    if value is None or isinstance(value, bool):
        return value
    text = str(value).strip().lower()
    if text in ("yes", "true", "1"):
        return True
    if text in ("no", "false", "0"):
        return False
    raise InputError(f"{where}: aligned is yes or no (true, false), not {value!r}")


def _tolerance(value, where):
    if value is None:
        return FLOOR_TOLERANCE
    if not (isinstance(value, (int, float)) and not isinstance(value, bool)
            and math.isfinite(value) and value >= 0):
        raise InputError(f"{where}: floor_tolerance is a distance >= 0 (m), not {value!r}")
    return float(value)


def _read(path: Path):
    import yaml

    try:
        text = path.read_text()
    except OSError as exc:
        raise InputError(f"--codes {path}: cannot read it ({exc.strerror})") from None
    try:
        data = yaml.safe_load(text)
    except yaml.YAMLError as exc:
        mark = getattr(exc, "problem_mark", None)
        line = f", line {mark.line + 1}" if mark is not None else ""
        raise InputError(f"{path}{line}: not valid YAML ({getattr(exc, 'problem', exc)})") \
            from None
    if isinstance(data, dict) and set(data) == {"codes"}:
        data = data["codes"]
    if not data:
        raise InputError(f"{path}: no rules (write codes: {{rules: [...]}})")
    return data


def evaluate(chosen: Chosen, u_left, u_right, geometry, left_buildings, right_buildings,
             rho) -> np.ndarray:
    """One rule's separations (m) over an audit's runs: ``u_left``, ``u_right`` (..., C)
    the simulated elastic peaks at each contact's two nodes; ``geometry`` the contacts'
    :class:`~pframe.gap.floors.Geometry`; the contacts' buildings on each side; rho (C,)."""
    u_left, u_right = np.asarray(u_left, float), np.asarray(u_right, float)
    out = np.empty(np.broadcast(u_left, u_right).shape)
    for c in range(out.shape[-1]):
        out[..., c] = separation_from_peaks(
            chosen.rule, u_left[..., c], u_right[..., c],
            factors_a=chosen.factors_of(left_buildings[c]),
            factors_b=chosen.factors_of(right_buildings[c]),
            aligned=geometry.aligned[c], level=geometry.level_left[c],
            level_b=geometry.level_right[c],
            heights=(geometry.height_left[c], geometry.height_right[c]),
            same_height=geometry.same_height[c], rho=rho[c])
    return out


def describe(found: Selection, buildings) -> str:
    """The chosen rules as the result file states them: each rule's code, clause, formula,
    aligned-floor treatment, factors by building and the source of its text (a rule of your
    own: the text you gave)."""
    lines = []
    for c in found.chosen:
        r = c.rule
        factors = "; ".join(f"{b}: " + ", ".join(f"{k} = {v:g}" if isinstance(v, float)
                                                  else f"{k} = {v}"
                                                  for k, v in r.resolved(c.factors_of(b)).items())
                            for b in buildings)
        lines.append(f"{r.name}: {r.code} {r.clause}".rstrip() + f"; {r.formula}; aligned "
                     f"floors: {r.aligned_note}; factors {factors or 'none'}; "
                     + (f"text given: {r.text}" if r.text else f"source: {r.source}"))
    return "\n".join(lines)


def warnings_for(found: Selection, geometry, materials) -> list[str]:
    """What the chosen rules cannot do as the codes mean on this audit's scene."""
    out = []
    if not found.chosen:
        return out
    names = ", ".join(found.names)
    if set(materials) - {"elastic"}:
        out.append(f"the code rules ({names}) take the buildings' elastic peak displacements, "
                   f"but their storeys are {', '.join(sorted(materials))}: the peaks of these "
                   "runs are inelastic and the code separations built on them are not the "
                   "codes' (run an elastic copy of the scene for them)")
    reducing = [c.rule.name for c in found.chosen
                if c.rule.aligned_factor != c.rule.unaligned_factor]
    if reducing and np.isnan(geometry.aligned).any():
        out.append(f"floor levels unknown (storey heights not given) at some contacts: "
                   f"{', '.join(reducing)} take their floors as not aligned there; give the "
                   "storey heights (height) or say aligned: yes")
    heights = [c.rule.name for c in found.chosen if not c.rule.text
               and (c.rule.minimum is not None or c.rule.each is not None)]
    missing = np.isnan(geometry.level_left) | np.isnan(geometry.level_right) | \
        np.isnan(geometry.height_left) | np.isnan(geometry.height_right)
    if heights and missing.any():
        out.append(f"{', '.join(heights)} need the heights of the levels (storey heights: "
                   "height) and are NaN where they are unknown")
    return out


def contact_correlation(inputs) -> np.ndarray:
    """rho (C,) of each contact: the CQC correlation of the first modes of its two
    buildings (:func:`pframe.gap.rules.cqc_correlation`)."""
    from pframe.gap.rules import cqc_correlation

    buildings = list(inputs.loaded.expanded.buildings)
    bl = np.array([buildings.index(n.split("/")[0]) for n in inputs.pairs.left])
    br = np.array([buildings.index(n.split("/")[0]) for n in inputs.pairs.right])
    return cqc_correlation(inputs.periods[bl], inputs.periods[br], inputs.damping[bl],
                           inputs.damping[br])


def rules_over_runs(inputs, found: Selection, geometry, u_left, u_right,
                    en_coincident: bool = False) -> dict[str, np.ndarray]:
    """ABS, SRSS, DDC (and SRSS_EN_0.7), then the chosen code rules, over an audit's or a
    study's runs: ``u_left``, ``u_right`` (..., C) the peaks at each contact's two nodes; rho
    from the first modes of each contact's two buildings."""
    from pframe.gap.rules import separations

    left_b = [n.split("/")[0] for n in inputs.pairs.left]
    right_b = [n.split("/")[0] for n in inputs.pairs.right]
    rho = contact_correlation(inputs)
    out = separations(u_left, u_right, rho, en_coincident)
    for chosen in found.chosen:
        out[chosen.rule.name] = evaluate(chosen, u_left, u_right, geometry, left_b, right_b,
                                         rho)
    return out
