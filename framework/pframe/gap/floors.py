"""Where the floors of two buildings stand: their elevations from the storey heights, whether
they are aligned, and the heights the code rules ask for (docs/gap-audit.md#aligned-floors).

Floors are aligned when, up to the lower building's roof (the floors that can meet), the two
buildings have the same number of floors and each floor of one stands within ``tolerance`` of
a floor of the other. pframe's tolerance, 0.05 m, is a fraction of a slab's thickness (slabs
are 0.15 m to 0.25 m thick): floors closer than that strike slab on slab, the case the codes'
aligned-floor rules are written for; farther apart, a slab may strike a column. A building
whose storey heights are not all given has no known floor levels: the decision is then
unknown (None) and the rules take the floors as not aligned, the conservative side.
"""

from __future__ import annotations

import dataclasses
import math

import numpy as np

#: floor elevations within this distance (m) are at the same level
FLOOR_TOLERANCE = 0.05


def building_levels(expanded) -> dict[str, dict[str, float] | None]:
    """Each building's floor elevations (node name -> m above the ground), from its storey
    heights; None for a building some storey of which has no height."""
    from pframe.model.expand import elevations

    heights = expanded.story_height
    if heights is None:
        heights = np.full(len(expanded.stories), np.nan)
    level = elevations(expanded.stories, heights)
    out: dict[str, dict[str, float] | None] = {}
    for b, name in enumerate(expanded.buildings):
        nodes = [i for i in range(len(expanded.node_names)) if expanded.node_building[i] == b]
        if all(i in level for i in nodes):
            out[name] = {expanded.node_names[i]: level[i] for i in nodes}
        else:
            out[name] = None
    return out


def aligned(levels_a: dict | None, levels_b: dict | None,
            tolerance: float = FLOOR_TOLERANCE) -> bool | None:
    """Whether two buildings' floors align up to the lower roof (module docstring); None
    when either's floor levels are unknown."""
    if levels_a is None or levels_b is None or not levels_a or not levels_b:
        return None
    za, zb = sorted(levels_a.values()), sorted(levels_b.values())
    top = min(za[-1], zb[-1]) + tolerance
    za, zb = [z for z in za if z <= top], [z for z in zb if z <= top]
    return len(za) == len(zb) and all(abs(x - y) <= tolerance for x, y in zip(za, zb))


@dataclasses.dataclass(frozen=True)
class Geometry:
    """Per contact (left, right): the elevations of its two nodes and the heights of their
    buildings (m, NaN unknown), whether the buildings' floors align (1, 0, NaN unknown) and
    whether their roofs stand at the same height (1, 0, NaN)."""

    level_left: np.ndarray
    level_right: np.ndarray
    height_left: np.ndarray
    height_right: np.ndarray
    aligned: np.ndarray
    same_height: np.ndarray
    #: how ``aligned`` was decided, for the result file and the terminal
    decided: str


def contact_geometry(expanded, left: tuple, right: tuple, *, override: bool | None = None,
                     tolerance: float = FLOOR_TOLERANCE) -> Geometry:
    """The :class:`Geometry` of the contacts whose left and right nodes are ``left``,
    ``right`` (node names ``building/floor``); ``override`` (True, False) replaces the
    decision from the storey heights."""
    levels = building_levels(expanded)

    def node_level(node):
        found = levels.get(node.split("/")[0])
        return math.nan if found is None else found.get(node, math.nan)

    def roof(node):
        found = levels.get(node.split("/")[0])
        return max(found.values()) if found else math.nan

    def flag(value):
        return math.nan if value is None else float(value)

    pairs = list(zip(left, right))
    decided = [aligned(levels.get(a.split("/")[0]), levels.get(b.split("/")[0]), tolerance)
               for a, b in pairs]
    same = [math.nan if math.isnan(roof(a)) or math.isnan(roof(b))
            else float(abs(roof(a) - roof(b)) <= tolerance) for a, b in pairs]
    if override is None:
        how = (f"from the storey heights (floor elevations within {tolerance:g} m up to the "
               "lower roof)")
        if any(d is None for d in decided):
            how += "; unknown where a building has no storey heights (taken as not aligned)"
        values = [flag(d) for d in decided]
    else:
        how = f"given: floors {'aligned' if override else 'not aligned'}"
        values = [float(bool(override))] * len(pairs)
    return Geometry(np.array([node_level(a) for a, _ in pairs]),
                    np.array([node_level(b) for _, b in pairs]),
                    np.array([roof(a) for a, _ in pairs]),
                    np.array([roof(b) for _, b in pairs]),
                    np.array(values, dtype=float), np.array(same, dtype=float), how)
