"""The supports a scene's structures stand on, and what their motions do to its elements.

A support is a piece of ground that moves as one, with its own acceleration a_s, velocity
v_s and displacement d_s (docs/supports.md). Every node is written relative to one support,
its structure's (the building's ``support``, or the support of the ground end of the storeys
that carry a generic node): it is loaded by -m a_s. An element sees the total motion of its
two sides, so its deformation is the relative one plus the ground displacements' part,

    d_e = G u + sum_t c_t d_{s_t, axis_t}(t),

which vanishes for an element whose two sides stand on one support (a storey to its own
ground, a contact between two buildings on one support) and is the difference of the
ground displacements for a contact across supports (Clough & Penzien, Dynamics of
Structures, multiple-support excitation; OpenSees' ``MultipleSupport`` pattern imposes the
same total motion). A scene that declares no support stands on one ground, as it always has.
"""

from __future__ import annotations

from dataclasses import dataclass

from pframe.model.load import ModelError
from pframe.model.plan import COMPONENTS

#: the name of the one ground of a scene that declares no supports
GROUND = "ground"


@dataclass(frozen=True)
class Supports:
    """``names`` of the supports (the scene's, or the one ground), each node's support
    (``node_support``, an index into ``names``), where each stands (site, m) and whether the
    scene declared them."""

    names: tuple[str, ...]
    node_support: tuple[int, ...]
    positions: tuple[tuple[float, float], ...]
    declared: bool

    @property
    def several(self) -> bool:
        return len(self.names) > 1

    def channel_names(self, axes: tuple[str, ...]) -> tuple[str, ...]:
        """The ground motion's channels: each support's axes ('x', 'y'), named '<support>:<axis>'
        when there are several supports (the axis alone for one, as a scene has always had)."""
        if not self.several:
            return tuple(axes)
        return tuple(f"{name}:{axis}" for name in self.names for axis in axes)


def _index(names, name, path, what) -> int:
    if name not in names:
        raise ModelError(path, f"{what} stands on support {name!r}, which the scene does not "
                               f"declare; its supports are {', '.join(names)}")
    return names.index(name)


def _default(names, declared, path, what) -> int:
    if len(names) > 1:
        raise ModelError(path, f"{what} stands on the ground, and the scene has several "
                               f"supports ({', '.join(names)}): say which with support: "
                               "<name>")
    return 0


def resolve(scene, floors, resolver) -> Supports:
    """Each node's support (see the module): a building's nodes stand on its support; a
    generic node on the support of the ground end of the storey (or, failing one, the link)
    that carries it, and so does every node above it; a node that nothing carries, on the
    first support."""
    declared = bool(scene.supports)
    names = tuple(s.name for s in scene.supports) or (GROUND,)
    if len(set(names)) != len(names):
        seen = set()
        for i, s in enumerate(scene.supports):
            if s.name in seen:
                raise ModelError(("supports", i, "name"), f"support {s.name!r} is declared twice")
            seen.add(s.name)
    positions = tuple(tuple(map(float, s.position)) for s in scene.supports) or ((0.0, 0.0),)
    support: dict[int, int] = {}
    for b, building in enumerate(scene.buildings):
        path = ("buildings", b)
        if building.story is not None and getattr(building.story, "support", None) is not None:
            raise ModelError(path + ("story", "support"), "a building's storeys stand on the "
                             "building's support: give support on the building")
        s = (_index(names, building.support, path + ("support",), f"building {building.name!r}")
             if building.support is not None
             else _default(names, declared, path, f"building {building.name!r}"))
        for i, name in enumerate(resolver.building_of):  # each floor's building
            if name == building.name:
                support[i] = s
    _carried(scene, resolver, names, declared, support)
    node_support = tuple(support.get(i, 0) for i in range(len(floors.nodes)))
    used = set(node_support) | set(_ground_sides(scene, names, declared).values())
    for s, name in enumerate(names):
        if declared and s not in used:
            raise ModelError(("supports", s), f"support {name!r}: nothing stands on it (no "
                             "building names it, no storey, link or wall); remove it or put "
                             "something on it")
    return Supports(names, node_support, positions, declared)


def _carried(scene, resolver, names, declared, support) -> None:
    """The supports of generic nodes: from the ground ends of their storeys upward, then
    across links to nodes still without one."""
    upward: dict[str, list[str]] = {}
    for i, story in enumerate(scene.stories):
        lower, upper = story.nodes
        if lower == "ground":
            what = f"storey {story.name or upper!r}"
            s = (_index(names, story.support, ("stories", i, "support"), what)
                 if story.support is not None
                 else _default(names, declared, ("stories", i), what))
            node = resolver.index.get(upper)
            if node is not None:
                support.setdefault(node, s)
        else:
            if story.support is not None:
                raise ModelError(("stories", i, "support"), "support names what a storey's "
                                 "ground end stands on; this storey's lower end is a node")
            upward.setdefault(lower, []).append(upper)
    todo = [resolver.names[i] for i in support]
    while todo:
        name = todo.pop()
        for upper in upward.get(name, ()):
            node = resolver.index.get(upper)
            if node is not None and node not in support:
                support[node] = support[resolver.index[name]]
                todo.append(upper)
    changed = True
    while changed:  # a tuned mass, a node held by links only: its partner's support
        changed = False
        for link in scene.links:
            ends = [resolver.index.get(n) for n in link.nodes]
            if None in ends or -1 in ends:
                continue
            a, b = ends
            if (a in support) != (b in support):
                support[b if a in support else a] = support[a if a in support else b]
                changed = True


def _ground_sides(scene, names, declared) -> dict:
    """(kind, index) -> the support index of the ground side of each storey, link and
    contact that has one (the wall of a contact, the anchor of a link)."""
    out = {}
    for kind in ("stories", "links", "contacts"):
        for i, item in enumerate(getattr(scene, kind)):
            grounded = "ground" in item.nodes
            given = getattr(item, "support", None)
            path = (kind, i)
            if given is not None and not grounded:
                raise ModelError(path + ("support",), "support names what a side of it that "
                                 "is 'ground' stands on; neither of its sides is")
            if grounded:
                what = {"stories": "storey", "links": "link", "contacts": "contact"}[kind]
                out[(kind, i)] = (_index(names, given, path + ("support",), f"this {what}")
                                  if given is not None
                                  else _default(names, declared, path, f"this {what}'s ground "
                                                "side"))
    return out


def ground_supports(scene, supports: Supports) -> dict:
    """Element name -> the support of its ground side, for the scene's generic storeys, links
    and contacts that have one (a building's storeys stand on its own support: not here)."""
    from pframe.model.scene import (
        default_contact_name,
        default_link_name,
        default_story_name,
    )

    names = {"stories": default_story_name, "links": default_link_name,
             "contacts": default_contact_name}
    out = {}
    for (kind, i), s in _ground_sides(scene, supports.names, supports.declared).items():
        item = getattr(scene, kind)[i]
        out[(kind, item.name or names[kind](item.nodes))] = s
    return out


def ground_terms(element, node_support, ground_side_support: int | None, axes,
                 first_positive: bool = False) -> tuple:
    """The ground displacements' part of an element's deformation (see the module):
    ((support, axis component, coefficient), ...), the total motion of its second side less
    its first's (a storey, a link), or of its first less its second's (``first_positive``: a
    contact's left less right). Empty when both sides stand on one support."""
    sides = element.side_terms()
    totals: dict[tuple[int, int], float] = {}
    scale = 0.0
    signs = ((0, 1.0), (1, -1.0)) if first_positive else ((0, -1.0), (1, 1.0))
    for k, sign in signs:
        terms = sides[k]
        if terms:
            for node, component, a in terms:
                if component < 2:
                    key = (node_support[node], component)
                    totals[key] = totals.get(key, 0.0) + sign * a
                    scale = max(scale, abs(a))
        else:  # the ground: it moves along the element's direction at the other side
            other = sides[1 - k]
            direction = [sum(a for _, c, a in other if c == comp) for comp in (0, 1)]
            for component, a in enumerate(direction):
                if a != 0.0:
                    key = (ground_side_support, component)
                    totals[key] = totals.get(key, 0.0) + sign * a
                    scale = max(scale, abs(a))
    # a side spread over floors (a struck column: psi and 1 - psi) sums to its direction only
    # to round-off: what is left of a difference on one support is that, not a motion
    out = tuple((s, c, v) for (s, c), v in sorted(totals.items())
                if abs(v) > 1e-12 * scale and COMPONENTS[c] in axes)
    return out
