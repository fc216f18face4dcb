"""The Pi groups of a scene, named as in Wu et al. (2021), and the report ``pframe pi`` prints.

With the paper's repeating variables ``(m_b, a_p, w_p)`` the groups are the canonical
Buckingham groups of :func:`pframe.nondim.buckingham.pi_groups`, renamed after the paper
(``Pi_m``, ``Pi_k``, ``Pi_uya``, ``Pi_wcon``, ...), except that every storey stiffness after
the first is expressed relative to it: ``Pi_mu = K_b / K_a`` rather than ``K_b / (m_b w_p^2)``
(eq. 11 uses the ratio ``mu``). Both are complete Pi sets; :func:`check_groups` confirms it.
"""

from __future__ import annotations

from dataclasses import dataclass
from fractions import Fraction

import numpy as np

from pframe.errors import InputError
from pframe.nondim.buckingham import Group, Variable, check_groups, pi_groups
from pframe.nondim.reference import reference_building
from pframe.nondim.scene_variables import building_tag, join_suffix, scene_variables


def _group_name(root: str, suffix: str) -> str:
    short = {"u_y": "uy", "w_bar": "wcon", "k_h": "kh", "K": "k"}.get(root, root)
    return "Pi_" + join_suffix(short, suffix) if short != "uy" else f"Pi_uy{suffix}"


def paper_groups(variables: list[Variable], roles: dict, repeating: list[str]) -> list[Group]:
    """The Pi groups named as in Wu et al. (2021): canonical Buckingham groups on
    ``(m_b, a_p, w_p)``, except that every storey stiffness after the first is expressed
    relative to it (``Pi_mu = K_b / K_a``) rather than to ``m_b w_p^2``."""
    canonical = pi_groups(variables, repeating)
    by_var = {g.exponents[0][0]: g for g in canonical}
    stiffness = [v.name for v in variables if roles[v.name][0] == "K"]
    masses = [v.name for v in variables if roles[v.name][0] == "m" and v.name not in repeating]
    others = stiffness[1:]
    groups = []
    for v in variables:
        if v.name in repeating:
            continue
        root, suffix = roles[v.name]
        g = by_var[v.name]
        description = f"{v.description}: {v.name}"
        if root == "K" and v.name != stiffness[0]:
            name = "Pi_mu" if len(others) == 1 else join_suffix("Pi_mu", suffix)
            g = Group(name, ((v.name, Fraction(1)), (stiffness[0], Fraction(-1))), description)
        elif root == "K":
            g = Group("Pi_k", g.exponents, description)
        elif root == "m":
            g = Group("Pi_m" if len(masses) == 1 else join_suffix("Pi_m", suffix), g.exponents,
                      description)
        else:
            g = Group(_group_name(root, suffix), g.exponents, description)
        groups.append(g)
    return groups


@dataclass(frozen=True)
class PiReport:
    """The Pi analysis of one scene (what ``pframe pi`` prints)."""

    variables: tuple[Variable, ...]
    repeating: tuple[str, ...]
    groups: tuple[Group, ...]
    values: dict
    discrete: tuple[str, ...]
    numerics: dict
    notes: tuple[str, ...]

    def as_dict(self) -> dict:
        return {
            "dimensions": ["M", "L", "T"],
            "variables": [{"name": v.name, "dimension": str(v.dimension), "units": v.units,
                           "value": v.value, "description": v.description}
                          for v in self.variables],
            "repeating": list(self.repeating),
            "groups": [{"name": g.name, "formula": g.formula(), "value": self.values[g.name],
                        "exponents": {n: str(x) for n, x in g.exponents},
                        "description": g.description} for g in self.groups],
            "discrete": list(self.discrete),
            "numerics": self.numerics,
            "notes": list(self.notes),
        }


def _discrete(scene, expanded) -> list[str]:
    out = []
    for b, name in enumerate(expanded.buildings):
        laws = sorted({e.law.name for e, sb in zip(expanded.stories, expanded.story_building)
                       if sb == b})
        floors = int(np.sum(expanded.node_building == b))
        out.append(f"building {building_tag(b)} = {name}: {floors} floors, "
                   f"{sum(1 for sb in expanded.story_building if sb == b)} storeys "
                   f"({', '.join(laws) or 'none'})")
    for contact, element in zip(scene.contacts, expanded.contacts):
        left, right = (expanded.node_names[i] for i in element.nodes)
        extra = ", keep_tension" if getattr(contact, "keep_tension", False) else ""
        out.append(f"contact {element.name}: {left} - {right} ({element.law.name}{extra})")
    rayleigh = [d for d in expanded.damping if d.kind == "rayleigh"]
    if rayleigh:
        modes = {tuple(d.modes) for d in rayleigh}
        stiff = {d.stiffness for d in rayleigh}
        out.append(f"Rayleigh damping on modes "
                   f"{'; '.join(' and '.join(map(str, m)) for m in sorted(modes))}"
                   f" ({', '.join(sorted(stiff))} stiffness)")
    if len(rayleigh) < len(expanded.damping):
        out.append("modal damping")
    if scene.excitation is not None and scene.excitation.kind == "sine":
        cycles = scene.excitation.cycles
        out.append("sine excitation" + (f", {cycles:g} cycles" if cycles else ""))
    elif scene.excitation is not None and scene.excitation.kind == "record":
        e = scene.excitation
        targets = "".join(f", {k} {getattr(e, k):.6g}" for k in ("pga", "frequency")
                          if getattr(e, k) is not None)
        period = e.period if isinstance(e.period, str) else f"{e.period:g} s"
        out.append(f"record excitation {e.file} (period: {period}{targets})")
    elif scene.excitation is not None:
        out.append(f"{scene.excitation.kind} pulse excitation")
    return out


def default_repeating(variables: list[Variable], roles: dict, expanded) -> list[str]:
    """The paper's repeating variables: the reference building's first floor-mass variable,
    ``a_p`` and ``w_p``."""
    tag = building_tag(reference_building(expanded))
    mass = next(v.name for v in variables
                if roles[v.name][0] == "m" and roles[v.name][1].startswith(tag))
    return [mass, "a_p", "w_p"]


def _in_plan(scene) -> bool:
    """Whether a scene says anything of plan: lines of resistance, points, normals, a motion
    in components (even when its elements happen to act along x through the centres)."""
    if any(b.lines is not None for b in scene.buildings):
        return True
    if scene.excitation is not None and scene.excitation.kind == "components":
        return True
    return any("points" in c.model_fields_set or "normal" in c.model_fields_set
               for c in scene.contacts)


def scene_pi(scene, expanded, repeating: list[str] | None = None) -> PiReport:
    """Variables, Pi groups (names, formulas, values) and discrete parameters of a scene.

    With the default repeating variables (the reference floor mass ``m_b``, ``a_p``,
    ``w_p``) the groups carry the paper's names (:func:`paper_groups`); with others they are
    the canonical Buckingham groups ``Pi_<variable>``.

    Raises
    ------
    InputError
        For a scene without excitation and no repeating variables given, or repeating
        variables that cannot serve (:class:`~pframe.nondim.buckingham.DimensionalAnalysisError`).
    """
    if getattr(expanded, "foundations", ()):
        raise InputError("the Pi form has no soil yet (docs/soil.md): the sway and rocking "
                         "springs' groups are not derived; remove soil to see the fixed "
                         "pair's groups")
    if getattr(expanded, "dofs", None) is not None or _in_plan(scene):
        raise InputError("the Pi form has no buildings in plan yet (docs/plan.md): the groups "
                         "of their eccentricities, plan sizes, polar inertias, angles and a "
                         "motion's incidence are not derived, and the paper's groups alone "
                         "would describe another scene; write the scene's storeys along x "
                         "through the centres of mass (a planar scene) to see its groups")
    if getattr(scene, "supports", None):
        raise InputError("the Pi form has no supports yet (docs/supports.md): the groups of "
                         "their distances, the apparent velocity and their motions' "
                         "coherence are not derived, and the paper's groups alone would "
                         "describe another scene; remove supports to see the groups of the "
                         "pair on one ground")
    variables, roles = scene_variables(scene, expanded)
    by_name = {v.name: v for v in variables}
    default = repeating is None
    if default:
        if "a_p" not in by_name:
            raise InputError("the scene has no excitation, so there is no default a_p, w_p; "
                             "choose repeating variables among " + ", ".join(by_name))
        repeating = default_repeating(variables, roles, expanded)
    groups = (paper_groups(variables, roles, repeating) if default
              else pi_groups(variables, repeating))
    check_groups(variables, groups)
    values = {g.name: g.value({v.name: v.value for v in variables}) for g in groups}
    numerics = {"dt": expanded.dt, "duration": expanded.dt * expanded.steps}
    notes = []
    if "w_p" in by_name:
        w = by_name["w_p"].value
        numerics |= {"dtau": w * expanded.dt, "tau": w * expanded.dt * expanded.steps}
        if scene.excitation.kind == "record":
            record = expanded.record
            notes.append(f"record: a_p = PGA = {by_name['a_p'].value:.6g} m/s^2, w_p = 2 pi / T "
                         f"= {w:.6g} rad/s (T = {record.period:.4g} s, the {record.period_is}"
                         + (f", times x {record.time_factor:.6g}" if record.time_factor != 1
                            else "") + ")")
    return PiReport(tuple(variables), tuple(repeating), tuple(groups), values,
                    tuple(_discrete(scene, expanded)), numerics, tuple(notes))
