"""Repeated storeys, floors and contact levels held as runs (pframe.model.rows): read as the
tuples they stand for, expanded and assembled as the same elements written out one by one,
and the array shortcuts of the assembly equal to the loops they replace, to the bit."""

from __future__ import annotations

import dataclasses
import importlib
import pickle

import numpy as np
import pytest

from pframe.assemble import assemble, modes
from pframe.model.rows import Rows, Run, column, column_array
from pframe.reader import parse_scene


@dataclasses.dataclass(frozen=True)
class _Item:
    name: str
    nodes: tuple
    law: str = "elastic"


def _rows_and_tuple():
    names = [f"A/{k}" for k in range(1, 6)]
    nodes = [(k - 1, k) for k in range(5)]
    run = Run(_Item(names[0], nodes[0]), 5, dict(name=names, nodes=nodes))
    extra = (_Item("wall", (4, -1), law="linear"),)
    written = tuple(_Item(n, e) for n, e in zip(names, nodes)) + extra
    return Rows((run, extra)), written


def test_rows_read_as_the_tuple_they_stand_for():
    rows, written = _rows_and_tuple()
    assert len(rows) == len(written) == 6
    assert [rows[i] for i in range(6)] == list(written)
    assert rows[-1] == written[-1] and rows[-6] == written[0]
    assert rows[1:4] == written[1:4] and rows[::-2] == written[::-2]
    assert rows == written and written == rows and rows != written[:-1]
    assert tuple(rows) == written and list(rows) == list(written)  # twice: from the cache
    assert rows + ("x",) == written + ("x",) and ("x",) + rows == ("x",) + written
    assert isinstance(rows + (), Rows) and isinstance(() + rows, Rows)
    assert column(rows, "law") == column(written, "law") == ["elastic"] * 5 + ["linear"]
    ends = column_array(rows, "nodes", np.int64)
    assert ends.tolist() == [list(e) for e in column(written, "nodes")]
    assert not ends.flags.writeable and column_array(rows, "nodes", np.int64) is ends
    assert pickle.loads(pickle.dumps(rows)) == written
    with pytest.raises(IndexError):
        rows[6]
    with pytest.raises(ValueError, match="3 values for 5 rows"):
        Run(written[0], 5, dict(name=["a", "b", "c"]))


BUILDING = """\
buildings:
  - {name: A, floors: 5, mass: [300.0, 280.0, 260.0, 240.0, 220.0],
     story: {material: bilinear, stiffness: [4.0e5, 3.5e5, 3.5e5, 3.0e5, 2.0e5],
             yield_drift: 0.02, alpha: 0.1}}
"""
WRITTEN = "nodes:\n" + "".join(
    f"  - {{name: A/{k}, mass: {m}}}\n"
    for k, m in zip(range(1, 6), (300.0, 280.0, 260.0, 240.0, 220.0))) + "stories:\n" + "".join(
    f"  - {{nodes: [{'ground' if k == 1 else f'A/{k - 1}'}, A/{k}], material: bilinear, "
    f"stiffness: {s}, yield_drift: 0.02, alpha: 0.1}}\n"
    for k, s in zip(range(1, 6), (4.0e5, 3.5e5, 3.5e5, 3.0e5, 2.0e5)))
REST = """\
damping: {ratio: 0.05, modes: [1, 2]}
excitation: {kind: sine, amplitude: 2.0, frequency: 6.0}
analysis: {dt: 0.001, duration: 0.01}
"""


def _plan_arrays(plan) -> dict:
    return {f.name: getattr(plan, f.name) for f in dataclasses.fields(plan)
            if isinstance(getattr(plan, f.name), np.ndarray)}


def test_a_building_of_the_shorthand_is_its_storeys_written_out():
    """A building's storeys resolved as one run are the elements, numbers and plan of the
    same floors and storeys written out as generic nodes and storeys (resolved one by
    one), to the bit."""
    short = parse_scene(BUILDING + REST).expanded
    long = parse_scene(WRITTEN + REST).expanded
    assert isinstance(short.stories, Rows) and any(isinstance(p, Run)
                                                   for p in short.stories.parts)
    assert not any(isinstance(p, Run) for p in long.stories.parts)
    assert short.stories == long.stories and short.node_names == long.node_names
    assert short.stories[1].packed == short.stories[2].packed  # equal storeys, one packing
    a, b = _plan_arrays(assemble(short)), _plan_arrays(assemble(long))
    assert a.keys() == b.keys()
    for name in a:
        assert a[name].tobytes() == b[name].tobytes(), name


def test_storeys_asking_their_mass_above_are_packed_one_by_one():
    """A friction pendulum carries the weight above it: a run of them is resolved storey by
    storey, each with its own weight (g times the masses above it), as written out."""
    pendulum = ("story: {material: friction_pendulum, radius: 2.0, mu: 0.05, "
                "k_init: 1.0e8}")
    short = parse_scene(BUILDING.replace(
        "story: {material: bilinear, stiffness: [4.0e5, 3.5e5, 3.5e5, 3.0e5, 2.0e5],\n"
        "             yield_drift: 0.02, alpha: 0.1}", pendulum) + REST).expanded
    weights = [s.packed[0] for s in short.stories]
    above = np.cumsum([220.0, 240.0, 260.0, 280.0, 300.0])[::-1]
    np.testing.assert_allclose(weights, 9.80665 * above, rtol=1e-15)
    assert len(set(weights)) == 5


def test_a_storey_name_used_twice_is_refused_where_it_is():
    text = BUILDING + "stories:\n  - {name: A/2, nodes: [A/1, A/3], material: elastic, " \
                      "stiffness: 1.0e5}\n" + REST
    with pytest.raises(Exception, match="stories\\[0\\].*storey name 'A/2' is used twice"):
        parse_scene(text, source="scene.yaml")


def _loop_band(springs, scale, width):
    """The band as a loop over the springs (the form scaled_band replaces)."""
    n = len(scale)
    band, root = [[0.0] * n for _ in range(width + 1)], scale.tolist()
    square = [float(v ** 2) for v in scale]
    for il, iu, kk in springs:
        band[0][iu] += kk * square[iu]
        if il >= 0:
            band[0][il] += kk * square[il]
            lo, hi = min(il, iu), max(il, iu)
            band[hi - lo][lo] -= kk * root[il] * root[iu]
    return np.array(band, dtype=float).reshape(width + 1, n)


@pytest.mark.parametrize("seed", [1, 2, 3])
def test_the_scaled_band_sums_as_the_loop_over_the_springs(seed):
    """Springs of a chain, a tree and walls, several on one DOF, in a shuffled order: each
    entry of the band is the loop's sum, bit for bit."""
    rng = np.random.default_rng(seed)
    n = 40
    springs = [(i - 1, i, float(k)) for i, k in enumerate(rng.uniform(1e5, 1e7, n))]
    springs += [(int(i), int(i) + int(d), float(k)) for i, d, k in zip(
        rng.integers(0, n - 3, 30), rng.integers(1, 4, 30), rng.uniform(1e3, 1e9, 30))]
    springs += [(-1, int(i), float(k)) for i, k in zip(rng.integers(0, n, 5),
                                                        rng.uniform(1e4, 1e6, 5))]
    springs = [springs[i] for i in rng.permutation(len(springs))]
    scale = 1.0 / np.sqrt(rng.uniform(10.0, 1e5, n))
    width = max(abs(i - j) for i, j, _ in springs if i >= 0)
    ends = np.array([(i, j) for i, j, _ in springs], dtype=np.int64)
    stiffness = np.array([k for *_, k in springs])
    assert modes.band_width(ends) == width
    assert modes.scaled_band(ends, stiffness, scale, width).tobytes() == \
        _loop_band(springs, scale, width).tobytes()


@pytest.mark.parametrize("scene", ["tall", "plan"])
def test_the_storeys_above_an_isolator_are_found_alike_down_chains(scene, monkeypatch):
    """The smallest post-yield stiffness above each storey: the running minimum down the
    chains of a building of the shorthand equals the walk over the storeys, for any
    stiffnesses; storeys in plan (several lines on a floor) take the walk."""
    text = BUILDING + WRITTEN.replace("A/", "B/") + REST  # a run, then storeys one by one
    if scene == "plan":
        text = (BUILDING + REST).replace(
            "story: {material: bilinear, stiffness: [4.0e5, 3.5e5, 3.5e5, 3.0e5, 2.0e5],\n"
            "             yield_drift: 0.02, alpha: 0.1}",
            "plan: {size: [10.0, 8.0]},\n     lines: [{name: X1, position: [0, 0], "
            "direction: x, material: elastic, stiffness: 2.0e5}, {name: X2, position: "
            "[0, 8], direction: x, material: elastic, stiffness: 2.0e5}, "
            "{name: Y1, position: [5, 0], direction: y, material: elastic, "
            "stiffness: 2.0e5}]")
    ex = parse_scene(text).expanded
    rng = np.random.default_rng(5)
    walk = importlib.import_module("pframe.assemble.modes")
    for _ in range(4):
        k = rng.choice([1e3, 1e5, 2e5, 3e5, np.inf], size=len(ex.stories))
        chains = walk._chains_min_above(ex, k)
        assert (chains is None) == (scene == "plan")
        found = walk._min_above(ex, k)
        monkeypatch.setattr(walk, "_chains_min_above", lambda ex, k: None)
        assert found.tobytes() == walk._min_above(ex, k).tobytes()
        monkeypatch.undo()


def test_the_sorted_unique_of_the_ordering_is_numpys():
    from pframe.assemble.ordering import sorted_unique

    rng = np.random.default_rng(11)
    for size in (0, 1, 7, 500):
        values = rng.integers(-3, 40, size)
        assert sorted_unique(values).tobytes() == np.unique(values).tobytes()


def test_the_contact_periods_found_once_per_distinct_row_are_each_contacts(monkeypatch):
    """The stability check's contact stiffnesses and periods, found once per distinct
    numbers and effective mass, are those of the loop over the contacts, bit for bit (levels
    of several masses, a wall, a power law)."""
    stability = importlib.import_module("pframe.assemble.stability")
    text = BUILDING + """\
  - {name: B, floors: 4, mass: [500.0, 500.0, 450.0, 500.0],
     story: {material: elastic, stiffness: 1.0e6}}
contacts:
  - {nodes: [A, B], gap: 0.01, law: hertzdamp, stiffness: 2.0e9, restitution: 0.6}
  - {name: wall, nodes: [B, ground], gap: 0.02, law: linear, stiffness: 1.0e7}
""" + REST
    plan = assemble(parse_scene(text).expanded)
    assert len(plan.contact_names) == 8
    found = stability.highest_frequency(plan)
    monkeypatch.setattr(stability, "_plain_mobility", lambda *args: None)
    looped = stability.highest_frequency(plan)
    assert found[0] == looped[0] and found[1].tobytes() == looped[1].tobytes()


def test_place_last_moves_each_key_just_after_its_groups_last_vertex():
    """The linear ``place_last`` against the list search it replaced, on random orders and
    groups (groups sharing their last vertex, groups naming keys placed before them)."""
    from pframe.assemble.ordering import place_last

    def searched(order, groups):  # the definition, one list search per member
        rest = [int(v) for v in order if int(v) not in groups]
        for vertex, members in groups.items():
            rest.insert(max(rest.index(v) for v in members) + 1, vertex)
        return rest

    rng = np.random.default_rng(5)
    for n in (3, 8, 40, 200):
        for _ in range(30):
            order = rng.permutation(n)
            keys = rng.choice(n, size=rng.integers(1, max(2, n // 4)), replace=False).tolist()
            others = [v for v in range(n) if v not in keys]
            groups = {}
            for i, key in enumerate(keys):
                pool = others + keys[:i]
                groups[key] = set(rng.choice(pool, size=rng.integers(1, len(pool) + 1),
                                             replace=False).tolist())
            assert place_last(order, groups).tolist() == searched(order, groups)
    with pytest.raises(ValueError):
        place_last(np.arange(4), {3: {2}, 2: {0}})  # 3's group names key 2, not yet placed
