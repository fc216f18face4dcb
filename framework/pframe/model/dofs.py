"""Which degrees of freedom a scene moves, and the checks that they can move as they must.

A floor has three: u_x, u_y and theta (docs/plan.md). The scene keeps those that an element
acts on, the ground motion loads or an initial condition sets; the others stay at rest and
are left out, so a planar scene (every element along x through the centres of mass, a motion
along x) has one degree of freedom per floor, as it always had. A floor that turns needs its
polar inertia; a storey must resist every motion its floor is given (a storey whose lines of
resistance give no torsional stiffness to a floor that an eccentric impact turns is refused,
with what turns it).
"""

from __future__ import annotations

import functools
import math
from dataclasses import dataclass

import numpy as np

from pframe.model.load import ModelError
from pframe.model.plan import COMPONENTS
from pframe.model.rows import Rows, Run, column, column_array

_AXIS_WORDS = {0: "along x", 1: "along y", 2: "in torsion (about the vertical)"}


# eq=False, repr=False: it holds numpy arrays: a generated __eq__ and __hash__ could only
# raise (== is elementwise), a __repr__ would print every array, and each generated
# function is compiled at every start
@dataclass(frozen=True, eq=False, repr=False)
class Dofs:
    """The degrees of freedom of a scene: ``table`` of (node, component) in node order, then
    component order (x, y, theta), and the mass of each (kg; kg m^2 for theta)."""

    table: tuple[tuple[int, int], ...]
    mass: np.ndarray
    #: () -> the reasons (:attr:`reasons`), worded only when a message asks
    explain: object = dict
    #: (d, 2) the table as an array (None: made from it when asked)
    key_array: np.ndarray | None = None

    @functools.cached_property
    def keys(self) -> np.ndarray:
        """(d, 2) the table as an array: each DOF's node and component."""
        if self.key_array is not None:
            return self.key_array
        return np.array(self.table, dtype=np.int64).reshape(-1, 2)

    @property
    def planar(self) -> bool:
        """Only u_x of every node: today's planar scene."""
        return not np.any(self.keys[:, 1])

    def node_mass(self, count: int) -> np.ndarray:
        """(count,) each node's u_x mass (kg; NaN: its u_x does not move)."""
        out = np.full(count, np.nan)
        along = self.keys[:, 1] == 0
        out[self.keys[along, 0]] = self.mass[along]
        return out

    @functools.cached_property
    def reasons(self) -> dict:
        """(node, component) -> why it moves (for the messages)."""
        return self.explain()


def _parts(elements):
    """The parts of a sequence of elements (:class:`Rows`' runs and tuples, or itself)."""
    return elements.parts if isinstance(elements, Rows) else (elements,)


def _plain_run(part) -> bool:
    """Whether ``part`` is a run of plain elements (u_x of each node, pframe.model.elements)."""
    return isinstance(part, Run) and part.template.sides is None and "sides" not in part.fields


def _reasons(elements, channels, initial) -> dict:
    """(node, component) -> why it moves (the first element, load or initial value)."""
    why: dict = {}
    for part in _parts(elements):
        if _plain_run(part):  # u_x of each node (not the ground), read off its columns
            for name, ends in zip(part.column("name"), part.column("nodes")):
                for i in ends:
                    if i >= 0 and (i, 0) not in why:
                        why[(i, 0)] = f"{name} acts on it"
            continue
        for e in part:
            if e.sides is None:  # the plain element: u_x of each node (not the ground)
                keys = [(i, 0) for i in e.nodes if i >= 0]
            else:
                keys = [(node, component) for terms in e.sides for node, component, _ in terms]
            for key in keys:
                if key not in why:  # the first element's reason (worded only then)
                    why[key] = f"{e.name} acts on it"
    return why | {k: v for k, v in initial.items() if k not in why} | {
        k: v for k, v in channels.items() if k not in why}


def _moving(count: int, elements, channels, initial) -> tuple[tuple, np.ndarray | None]:
    """The keys of :func:`_reasons`, sorted (node, then component), without wording them: a
    mask of the nodes' components (a run of plain elements marks its nodes' u_x at once);
    and the same as an array (None: a key outside the floors')."""
    moves = np.zeros((count, len(COMPONENTS)), dtype=bool)
    for axis in channels:
        moves[:, COMPONENTS.index(axis)] = True
    odd = set()  # a key outside the floors' components (kept as the dictionary would)
    for part in _parts(elements):
        if _plain_run(part):
            ends = part.array("nodes", np.int64).ravel()
            moves[ends[ends >= 0], 0] = True
            continue
        for e in part:
            for node, component, *_ in (((i, 0) for i in e.nodes if i >= 0)
                                        if e.sides is None else
                                        (t for terms in e.sides for t in terms)):
                if 0 <= node < count and 0 <= component < len(COMPONENTS):
                    moves[node, component] = True
                else:
                    odd.add((node, component))
    for node, component in initial:
        if 0 <= node < count and 0 <= component < len(COMPONENTS):
            moves[node, component] = True
        else:
            odd.add((node, component))
    nodes, components = np.nonzero(moves)
    table = tuple(zip(nodes.tolist(), components.tolist()))
    if odd:
        return tuple(sorted(set(table) | odd)), None
    return table, np.stack([nodes, components], axis=1).astype(np.int64)


def active(floors, elements, channels: tuple[str, ...], initial: dict) -> Dofs:
    """The scene's degrees of freedom (see the module) from its floors, every element, the
    site's axes the ground motion loads (``channels``: 'x', 'y') and the initial values given
    ((node, component) -> value)."""
    count = len(floors.nodes)

    def explain() -> dict:
        said = [(COMPONENTS.index(axis), f"the ground motion's {axis} component loads it")
                for axis in channels]
        loads = {(i, c): why for i in range(count) for c, why in said}
        given = {key: "an initial condition sets it" for key, value in initial.items()
                 if value}
        return _reasons(elements, loads, given)

    table, keys = _moving(count, elements, channels, {k: v for k, v in initial.items() if v})
    if keys is not None and not keys[:, 1].any():  # u_x of each node: their masses
        return Dofs(table, np.array(column_array(floors.nodes, "mass", float)[keys[:, 0]]),
                    explain, keys)
    masses = []
    mass, inertia = column(floors.nodes, "mass"), column(floors.nodes, "inertia")
    for node, component in table:
        if component < 2:
            masses.append(mass[node])
            continue
        if inertia[node] is None:
            floor = floors.nodes[node]
            raise ModelError(floor.building_path, f"floor {floor.name} turns "
                             f"({explain()[(node, component)]}: it acts off the floor's "
                             "centre of mass) but its polar moment of inertia is unknown: give "
                             "polar_inertia (kg m^2), or the plan (size or outline) for a "
                             "uniform slab's")
        masses.append(inertia[node])
    return Dofs(table, np.array(masses, dtype=float), explain, keys)


def check_storeys(floors, resolver, storeys, dofs: Dofs) -> None:
    """Every storey resists every motion of its upper floor relative to its lower one: the
    directions of its springs (lines of resistance, a planar storey spring, P-delta's own
    aside) span the upper floor's degrees of freedom. A planar scene has nothing to check."""
    if dofs.planar:
        return
    moving: dict[int, list[int]] = {}
    for node, component in dofs.table:
        moving.setdefault(node, []).append(component)
    groups: dict[tuple[int, int], list] = {}
    for e in storeys:
        if "/P-delta-" in e.name:
            continue
        groups.setdefault(e.nodes, []).append(e)
    for (_, upper), lines in groups.items():
        comps = moving.get(upper, [])
        rows = []
        for e in lines:
            a = np.zeros(3)
            for node, component, c in e.side_terms()[1]:
                if node == upper:
                    a[component] = c
            rows.append(a[comps])
        matrix = np.array(rows)
        gram = matrix.T @ matrix
        scale = max(float(np.max(np.abs(gram))), 1e-300)
        values, vectors = np.linalg.eigh(gram / scale)
        if values[0] > 1e-10:
            continue
        loose = np.zeros(3)
        loose[comps] = vectors[:, 0]
        floor = floors.nodes[upper]
        path = next((spec.path for spec in floors.stories if spec.nodes[1] == floor.name),
                    floor.building_path)
        twist = abs(loose[2]) > 1e-9 * max(float(np.max(np.abs(loose))), 1e-300)
        component = 2 if twist else (0 if abs(loose[0]) >= abs(loose[1]) else 1)
        reason = dofs.reasons.get((upper, component)) or _loaded_reason(component)
        if twist:  # a rotation about the point that does not move
            centre = (floor.centre[0] - loose[1] / loose[2], floor.centre[1] + loose[0] / loose[2])
            what = (f"in torsion: it can turn about the point [{centre[0]:.4g}, "
                    f"{centre[1]:.4g}] (site, m)")
        elif len(comps) > 1 and min(abs(loose[0]), abs(loose[1])) > 1e-9:
            angle = math.degrees(math.atan2(loose[1], loose[0]))
            what = f"along the direction at {angle:.4g} degrees from x"
        else:
            what = _AXIS_WORDS[component]
        raise ModelError(path, f"storey {floor.name}: its storey springs give it no stiffness "
                         f"{what}, but its floor moves so ({reason}); "
                         f"{_remedy(2 if twist else component, len(lines))}")


def _loaded_reason(component: int) -> str:
    return ("the ground motion or an initial condition moves it" if component < 2
            else "an element acts off its centre of mass")


def _remedy(component: int, lines: int) -> str:
    if lines == 1:
        return ("a planar storey spring (story) resists along one direction through the "
                "centre of mass only: give the building lines of resistance (lines) at its "
                "frames' plan positions, or keep every element and motion along x through the "
                "centres of mass")
    if component == 2:
        return ("its lines of resistance all pass through one point (or are parallel and "
                "coincide): place them apart in plan to give torsional stiffness")
    return ("no line of resistance acts in that direction: add a line along it, or leave the "
            "motion out")
