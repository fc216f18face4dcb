"""The governing variables of any scene, read from its definitions.

Wu et al. (2021), eq. (10), lists 13 variables for two uniform buildings under a sine:
``m_a, m_b, K_a, mu, u_ya, u_yb, xi, alpha, w_bar, e, d, a_p, w_p``. pframe lists the same
kind of variables for any scene:

- per building (tag ``a``, ``b``, ``c``, ... in the order of the YAML: the paper's left ``a``
  and right ``b``): floor masses ``m``, storey stiffnesses ``K``, and the material's other
  parameters (bilinear: yield drift ``u_y``, post-yield ratio ``alpha``); the Rayleigh
  damping ratio ``xi``;
- per contact: the contact frequency ``w_bar = sqrt(k (m1 + m2) / (m1 m2))`` of a linear
  spring (or the stiffness ``k_h`` in N/m^1.5 of a Hertz-type law), restitution ``e`` and gap
  ``d``;
- the excitation: a sine's amplitude ``a_p`` and circular frequency ``w_p`` (and its duration
  ``t_p`` when limited in time); for a record its PGA and ``2 pi / T`` with ``T`` its stated
  characteristic period (:func:`pframe.excitation.characteristic.characteristic`);
- non-zero initial displacements ``u0`` and velocities ``v0``.

Values that are equal are one variable: within a building when every storey has the same
value (``K_a`` rather than ``K_a1, K_a2, K_a3``), and across the scene for the ratios and
contact properties (one ``alpha``, ``xi``, ``w_bar``, ``e``, ``d`` when all agree). Masses,
stiffnesses and yield drifts stay per building, as in the paper, even when two buildings
agree (the HUST frames have ``Pi_m = Pi_mu = 1``).

Storey counts, contact levels, laws, damping modes and the analysis settings are discrete or
numerical parameters: :func:`pframe.nondim.scene_pi.scene_pi` reports them beside the groups.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

from pframe.errors import InputError
from pframe.excitation.characteristic import characteristic
from pframe.laws import ContactContext
from pframe.nondim.buckingham import Variable
from pframe.nondim.dimensions import QUANTITY, Dimension
from pframe.nondim.fields import check_declared, dimension_of

_SI = {QUANTITY[q]: u for q, u in (
    ("dimensionless", "1"), ("mass", "kg"), ("length", "m"), ("time", "s"),
    ("frequency", "rad/s"), ("velocity", "m/s"), ("acceleration", "m/s^2"), ("force", "N"),
    ("stiffness", "N/m"), ("hertz_stiffness", "N/m^1.5"))}


def si_units(dimension: Dimension) -> str:
    if dimension in _SI:
        return _SI[dimension]
    return " ".join(f"{u}^{x}" if x != 1 else u
                    for u, x in zip(("kg", "m", "s"), dimension.exponents) if x)


def building_tag(index: int) -> str:
    """The paper's building letters: a (left), b (right), then c, d, ..."""
    return chr(ord("a") + index) if index < 26 else f"x{index + 1}_"


def join_suffix(root: str, suffix: str) -> str:
    if not suffix:
        return root
    return f"{root}{suffix}" if "_" in root or suffix.startswith("[") else f"{root}_{suffix}"


def _same(values) -> bool:
    first = values[0]
    return all(math.isclose(v, first, rel_tol=1e-12, abs_tol=0.0) for v in values)


# ---------------------------------------------------------------------------------------------
# raw values per element
# ---------------------------------------------------------------------------------------------

def _material_values(law, packed) -> dict[str, tuple[Dimension, float]]:
    """root -> (dimension, value) of one storey, as its law names them (``Law.governing``)."""
    check_declared(law)
    return {root: (dimension_of(what, "material", law.name, root), value)
            for root, (what, value) in law.governing(packed).items()}


def _contact_values(contact, element, masses) -> dict[str, tuple[Dimension, float]]:
    law = element.law
    check_declared(law)
    left, right = element.nodes  # -1: a wall (the ground), of infinite mass
    m_eff = ContactContext(masses[left] if left >= 0 else math.inf,
                           masses[right] if right >= 0 else math.inf).effective_mass
    out = {root: (dimension_of(what, "contact", law.name, root), value)
           for root, (what, value) in law.governing(element.packed, m_eff).items()}
    if getattr(contact, "restitution", None) is not None:
        out["e"] = (QUANTITY["dimensionless"], float(contact.restitution))
    out["d"] = (QUANTITY["length"], element.gap)
    return out


# ---------------------------------------------------------------------------------------------
# variables
# ---------------------------------------------------------------------------------------------

@dataclass
class _Collector:
    """Variables in order, with the group naming role of each."""

    variables: list = field(default_factory=list)
    roles: dict = field(default_factory=dict)  # variable name -> (root, suffix)

    def add(self, root: str, suffix: str, dimension: Dimension, value: float, what: str):
        name = join_suffix(root, suffix)
        self.variables.append(Variable(name, dimension, float(value), what, si_units(dimension)))
        self.roles[name] = (root, suffix)


_RANK = {"m": 0, "K": 1, "u_y": 2, "xi": 3, "alpha": 4, "w_bar": 6, "k_h": 6, "e": 7, "d": 8,
         "a_p": 9, "w_p": 9, "t_p": 9, "u0": 10, "v0": 10}
_PER_BUILDING = ("m", "K", "u_y")  # kept per building even when buildings agree
_WHAT = {"m": "floor mass", "K": "storey stiffness", "u_y": "yield drift",
         "alpha": "post-yield stiffness ratio", "xi": "Rayleigh damping ratio",
         "w_bar": "contact frequency sqrt(k (m1 + m2) / (m1 m2))",
         "k_h": "Hertz contact stiffness", "e": "coefficient of restitution", "d": "gap",
         "c": "dashpot coefficient of F = c |v|^alpha_v sign v",
         "alpha_v": "velocity exponent of a dashpot"}


def _add_per_building(out: _Collector, root, per_building, buildings, scene_wide: bool):
    """``per_building[b]`` = list of (label, (dimension, value)) for building b's storeys."""
    present = [b for b, values in enumerate(per_building) if values]
    if not present:
        return
    every = [v for b in present for _, (_, v) in per_building[b]]
    dimension = per_building[present[0]][0][1][0]
    what = _WHAT.get(root, root)
    if scene_wide and _same(every):
        scope = "every building" if root == "xi" else "every storey"
        if len(present) < len(per_building):  # the others have no such parameter
            scope += " of " + ", ".join(buildings[b] for b in present)
        out.add(root, "", dimension, every[0], f"{what} ({scope})")
        return
    for b in present:
        values = per_building[b]
        if _same([v for _, (_, v) in values]):
            out.add(root, building_tag(b), dimension, values[0][1][1], f"{what} of {buildings[b]}")
        else:
            for label, (dim, v) in values:
                out.add(root, f"{building_tag(b)}{label}", dim, v, f"{what} of {buildings[b]}/{label}")


def scene_variables(scene, expanded) -> tuple[list[Variable], dict]:
    """The governing variables of a validated scene and their naming roles.

    Parameters
    ----------
    scene, expanded
        ``LoadedScene.scene`` and ``LoadedScene.expanded``.

    Returns
    -------
    variables : list of Variable
    roles : dict
        variable name -> (root, suffix), used to name the Pi groups.
    """
    if getattr(expanded, "links", ()):
        raise InputError("the Pi form does not cover links yet: their dampers' coefficients "
                         "are in N (s/m)^alpha, a dimension that depends on alpha, and a "
                         "tuned mass adds its own groups; take the links out to see the "
                         "buildings' Pi numbers, or scale the scene by its similitude ratios "
                         "(pframe scale) where the links' units allow")
    out = _Collector()
    names = expanded.buildings
    n_b = len(names)
    masses = [[] for _ in range(n_b)]
    for i, b in enumerate(expanded.node_building):
        masses[b].append((str(len(masses[b]) + 1), (QUANTITY["mass"], expanded.masses[i])))
    _add_per_building(out, "m", masses, names, scene_wide=False)

    storeys: dict[str, list] = {}
    counts = [0] * n_b
    for element, b in zip(expanded.stories, expanded.story_building):
        counts[b] += 1
        for root, value in _material_values(element.law, element.packed).items():
            storeys.setdefault(root, [[] for _ in range(n_b)])[b].append((str(counts[b]), value))
    for root, per_building in storeys.items():
        _add_per_building(out, root, per_building, names, scene_wide=root not in _PER_BUILDING)

    for b, d in enumerate(expanded.damping):
        if isinstance(d.ratio, list) and len(set(d.ratio)) > 1:
            raise InputError(f"building {names[b]}: its modal damping gives each mode its own "
                             "ratio, which is no single damping ratio xi for the Pi groups: "
                             "give one ratio (ratio: 0.05)")
    ratios = [[("", (QUANTITY["dimensionless"],
                     float(d.ratio[0] if isinstance(d.ratio, list) else d.ratio)))]
              for d in expanded.damping]
    _add_per_building(out, "xi", ratios, names, scene_wide=True)

    contacts: dict[str, list] = {}
    for contact, element in zip(scene.contacts, expanded.contacts):
        for root, value in _contact_values(contact, element, expanded.masses).items():
            contacts.setdefault(root, []).append((element.name, value))
    for root, values in contacts.items():
        if _same([v for _, (_, v) in values]):
            dim, v = values[0][1]
            out.add(root, "", dim, v, f"{_WHAT.get(root, root)} (every contact)")
        else:
            for name, (dim, v) in values:
                out.add(root, f"[{name}]", dim, v, f"{_WHAT.get(root, root)} of {name}")

    excitation = characteristic(scene.excitation, expanded.record)
    if excitation is not None:
        out.add("a_p", "", QUANTITY["acceleration"], excitation.amplitude, excitation.amplitude_is)
        out.add("w_p", "", QUANTITY["frequency"], excitation.frequency, excitation.frequency_is)
        if scene.excitation.kind == "sine" and scene.excitation.duration is not None:
            out.add("t_p", "", QUANTITY["time"], scene.excitation.duration, "sine duration")
    for key, root, dim in (("displacement", "u0", "length"), ("velocity", "v0", "velocity")):
        for node, value in getattr(scene.initial_conditions, key).items():
            if value:
                out.add(root, f"[{node}]", QUANTITY[dim], value, f"initial {key} of {node}")
    # the order of the paper's eq. (10); a stable sort keeps buildings and contacts in order
    variables = sorted(out.variables, key=lambda v: _RANK.get(out.roles[v.name][0], 5))
    return variables, out.roles
