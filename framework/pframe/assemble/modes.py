"""The modes of a scene's buildings, and which storeys are isolators.

A building's modes are those of its masses and storeys alone on a fixed base (links to other
buildings and contacts left out), on a stiffness chosen per storey:

- **fixed base, initial stiffness**: every storey at its initial tangent (the elastic modes);
- **isolated**: each isolator storey at its post-yield or sliding stiffness (the law's
  ``post_yield_stiffness``: W / R of a friction pendulum, alpha k0 of a Bouc-Wen or bilinear
  bearing), every other storey at its initial tangent: the modes that govern a base-isolated
  building once its bearings yield or slide, which its damping is fitted on
  (:mod:`pframe.assemble.damping`; Ryan & Polanco 2008);
- **flexible base**: a building on soil with its foundation's sway and rocking springs
  (docs/soil.md).

A storey is an isolator when the scene says so (``isolator``), when its law is a bearing by
nature (``Law.isolator``: friction_pendulum), or when its post-yield stiffness is at most
1 / :data:`ISOLATION_RATIO` of that of every storey above it: the building then rides on it
as a nearly rigid block (two equal masses on a storey ten times softer than the one above
put 95 % of the top's displacement of the first mode into it), which is what isolation is.
A frame whose storeys all yield alike is not an isolator (its storeys soften together).
"""

from __future__ import annotations

import contextlib
import functools
import math
import weakref
from dataclasses import dataclass

import numpy as np

from pframe.assemble.ordering import sorted_unique
from pframe.model.rows import Rows, Run, column, column_array

#: a storey whose post-yield stiffness is at most this many times below that of every storey
#: above it is an isolator (see the module's docstring)
ISOLATION_RATIO = 10.0
#: buildings of up to this many floors are analysed as a dense matrix; taller ones in banded
#: form (a shear building is tridiagonal): memory and time grow with n, not n^2 or n^3
DENSE_FLOORS = 256
#: the periods shown per building (validate, a loaded scene's repr)
SHOWN_MODES = 3


def initial_tangent(law, packed) -> float:
    """The tangent of a law at zero deformation from rest (N/m); found once per law and
    parameters (the storeys of a tall building share theirs)."""
    params = np.asarray(packed, dtype=float)
    return _initial_tangent(law, params.tobytes())


@functools.lru_cache(maxsize=4096)
def _initial_tangent(law, packed: bytes) -> float:
    params = np.frombuffer(packed, dtype=float).copy()
    state = np.zeros(len(law.state_names))
    return float(law.force(params, state.copy(), state, 0.0, 0.0)[1])


def per_law(elements, function) -> list:
    """``function(law, packed)`` of each element, computed once per law and packed numbers
    (the storeys of a tall building share theirs)."""
    known: dict = {}
    out = []
    for part in elements.parts if isinstance(elements, Rows) else (elements,):
        if isinstance(part, Run) and "law" not in part.fields:  # one law: by the numbers' id
            law, packed = part.template.law, part.column("packed")
            ids = list(map(id, packed))
            value = {i: known.setdefault((law, i), (function(law, p), p))[0]
                     for i, p in dict(zip(ids, packed)).items()}
            out += map(value.__getitem__, ids)
            continue
        for law, packed in zip(column(part, "law"), column(part, "packed")):
            key = (law, id(packed))
            if key not in known:
                known[key] = (function(law, packed), packed)  # (the numbers kept: id unique)
            out.append(known[key][0])
    return out


def post_yield(ex, k0: np.ndarray) -> np.ndarray:
    """(s,) the post-yield or sliding stiffness each storey's law declares (N/m): its initial
    tangent ``k0`` where the law declares none, and never above it."""
    post = per_law(ex.stories, lambda law, packed: law.post_yield_stiffness(
        np.asarray(packed, dtype=float)))
    if None not in post:  # min(p, k) of each: p unless k is below it (a NaN compares false)
        post, k0 = np.array(post, dtype=float), np.asarray(k0, dtype=float)
        return np.where(k0 < post, k0, post)
    return np.array([k if p is None else min(float(p), k)
                     for k, p in zip(np.asarray(k0, dtype=float).tolist(), post)], dtype=float)


def storey_stiffness(ex) -> tuple[np.ndarray, np.ndarray]:
    """(k0, k_post) of every storey of an Expanded scene (N/m): the initial tangent and the
    post-yield or sliding stiffness (:func:`post_yield`)."""
    k0 = np.array(per_law(ex.stories, initial_tangent), dtype=float)
    return k0, post_yield(ex, k0)


def geometric_stiffness(ex) -> np.ndarray:
    """P / h of every storey of an Expanded scene (N/m): P-delta's geometric stiffness where
    a storey carries a gravity load (``p_delta``), 0 elsewhere. The kernel's storey force is
    net of P drift / h, so the storey's lateral stiffness at rest is k0 - P / h."""
    n = len(ex.stories)
    gravity, height = getattr(ex, "story_gravity", None), getattr(ex, "story_height", None)
    out = np.zeros(n)
    if gravity is None or len(gravity) != n:
        return out
    gravity = np.asarray(gravity, dtype=float)
    loaded = gravity > 0.0
    out[loaded] = gravity[loaded] / np.asarray(height, dtype=float)[loaded]
    return out


def spring_matrix(springs, n: int) -> np.ndarray:
    """The dense n x n stiffness of springs ``(i, j, k)`` between DOFs i and j (i = -1: the
    ground), for the small scenes where a dense matrix is the simplest form."""
    K = np.zeros((n, n))
    for i, j, k in springs:
        K[j, j] += k
        if i >= 0:
            K[i, i] += k
            K[i, j] -= k
            K[j, i] -= k
    return K


def scaled_triplets(springs, scale):
    """(values, (rows, cols)) of M^-1/2 K M^-1/2 (``scale`` = M^-1/2) from springs
    ``(i, j, k)`` between DOFs i and j (i = -1: the ground), for a sparse matrix."""
    rows, cols, vals = [], [], []
    for il, iu, k in springs:
        rows.append(iu), cols.append(iu), vals.append(k * scale[iu] ** 2)
        if il >= 0:
            off = -k * scale[il] * scale[iu]
            rows += [il, il, iu]
            cols += [il, iu, il]
            vals += [k * scale[il] ** 2, off, off]
    return vals, (rows, cols)


def sparse_lowest(matrix, count: int) -> tuple[np.ndarray, np.ndarray]:
    """The ``count`` lowest eigenpairs (w^2 ascending, vectors) of a symmetric sparse matrix,
    by ARPACK's shift-invert about 0, from a fixed start vector: ARPACK's own start is random
    and advances from call to call, so the same matrix would give modes (and the Rayleigh
    coefficients fitted on them) that differ in their last bits from run to run."""
    from scipy.sparse.linalg import eigsh

    n = matrix.shape[0]
    start = np.random.default_rng(0).standard_normal(n)  # generic: no mode left out of it
    values, vectors = eigsh(matrix, k=min(count, n - 1), sigma=0, which="LM", v0=start)
    order = np.argsort(values)
    return values[order], vectors[:, order]


def scaled_band(ends: np.ndarray, stiffness: np.ndarray, scale: np.ndarray,
                width: int) -> np.ndarray:
    """(width + 1, n) the lower band of M^-1/2 K M^-1/2 (``scale`` = M^-1/2, n of them),
    band[d, j] = A[j + d, j], from springs between DOFs ``ends`` (m, 2) (i, j; i = -1: the
    ground) of ``stiffness`` (m,). Each entry sums its springs' terms in the springs' order,
    as a loop over them would (np.add.at accumulates index by index, in order): the same
    bits, at numpy's pace (a tall building has tens of thousands of storeys)."""
    n = len(scale)
    band = np.zeros((width + 1) * n)
    if not len(ends):
        return band.reshape(width + 1, n)
    il, iu = ends[:, 0].astype(np.int64), ends[:, 1].astype(np.int64)
    k = np.asarray(stiffness, dtype=float)
    # numpy's pow on each scalar, as before (inf, not OverflowError, if huge)
    square = np.array([float(v ** 2) for v in scale], dtype=float)
    grounded = il < 0
    at = np.column_stack([iu, np.where(grounded, -1, il)]).ravel()
    terms = np.column_stack([k * square[iu], k * square[np.maximum(il, 0)]]).ravel()
    keep = at >= 0
    np.add.at(band, at[keep], terms[keep])
    both = ~grounded
    lo, hi = np.minimum(il, iu)[both], np.maximum(il, iu)[both]
    np.add.at(band, (hi - lo) * n + lo, -(k[both] * scale[il[both]] * scale[iu[both]]))
    return band.reshape(width + 1, n)


def building_dofs(ex, b: int) -> int:
    """How many degrees of freedom building b's floors have (:func:`building_keys`)."""
    if ex.dofs is None:
        return int(np.count_nonzero(ex.node_building == b))
    return len(building_keys(ex, b)[0])


def building_keys(ex, b: int) -> tuple[list, np.ndarray]:
    """The degrees of freedom of building b's floors, (node, component) in the scene's order,
    and their masses (kg; kg m^2 for a rotation): u_x of each floor in a planar scene, every
    DOF the scene moves in plan."""
    if ex.dofs is None:
        nodes = np.flatnonzero(ex.node_building == b)
        return (list(zip(nodes.tolist(), [0] * len(nodes))),
                np.asarray(ex.masses, dtype=float)[nodes])
    mine = [p for p, (node, _) in enumerate(ex.dofs) if ex.node_building[node] == b]
    return [ex.dofs[p] for p in mine], np.asarray(ex.dof_mass, dtype=float)[mine]


def _plan_rows(ex, b: int, local: dict) -> list[tuple[int, dict]]:
    """(storey, {local DOF: weight}) of each storey spring of building b in plan: its
    deformation's weights on the building's DOFs (upper side less lower side)."""
    out = []
    for s in np.flatnonzero(ex.story_building == b):
        lower, upper = ex.stories[s].side_terms()
        g: dict[int, float] = {}
        for sign, side in ((-1.0, lower), (1.0, upper)):
            for node, c, a in side:
                if (node, c) in local:
                    g[local[(node, c)]] = g.get(local[(node, c)], 0.0) + sign * a
        out.append((int(s), g))
    return out


def _plan_modes(ex, b: int, k: np.ndarray, count: int | None, vectors: bool):
    """:func:`lowest_modes` of a building in plan: its lateral-torsional modes over its
    floors' DOFs (K = sum k g g^T of its storey springs, M diagonal)."""
    keys, masses = building_keys(ex, b)
    local = {key: i for i, key in enumerate(keys)}
    n = len(keys)
    rows, cols, values = [], [], []
    for s, g in _plan_rows(ex, b, local):
        for i, a in g.items():
            for j, c in g.items():
                rows.append(i)
                cols.append(j)
                values.append(float(k[s]) * a * c)
    scale = 1.0 / np.sqrt(masses)
    if count is None or n <= 3 * DENSE_FLOORS:
        K = np.zeros((n, n))
        np.add.at(K, (rows, cols), values)
        K *= np.outer(scale, scale)
        if not vectors:
            return np.sqrt(np.clip(np.linalg.eigvalsh(K), 0, None))
        w2, shapes = np.linalg.eigh(K)
        return np.sqrt(np.clip(w2, 0, None)), shapes * scale[:, None]
    from scipy.sparse import coo_matrix

    values = np.array(values) * scale[rows] * scale[cols]
    matrix = coo_matrix((values, (rows, cols)), shape=(n, n)).tocsc()
    w2, shapes = sparse_lowest(matrix, count)
    omega = np.sqrt(np.clip(w2, 0, None))
    return (omega, shapes * scale[:, None]) if vectors else omega


def directions(ex, b: int, phi: np.ndarray) -> list[str]:
    """The direction each mode of building b in plan mostly moves in (x, y or torsion): the
    largest of its participation along the site's x and y and in twist, each over its total
    (p_d^2 / sum m_d with p_d = phi^T M iota_d, phi normalised on the masses)."""
    keys, masses = building_keys(ex, b)
    return direction_names(np.array([k[1] for k in keys]), masses, phi)


def direction_names(components: np.ndarray, masses: np.ndarray, phi: np.ndarray) -> list[str]:
    """:func:`directions` of modes ``phi`` (columns) over DOFs of ``components`` (0 u_x,
    1 u_y, 2 theta; any other: none of the three) and ``masses``."""
    out = []
    for mode in np.asarray(phi).T:
        shares = []
        for c in range(3):
            on = components == c
            total = float(np.sum(masses[on]))
            shares.append((float(mode[on] @ masses[on]) ** 2 / total) if total > 0 else 0.0)
        out.append(("x", "y", "torsion")[int(np.argmax(shares))])
    return out


def building_spring_arrays(ex, b: int, k: np.ndarray):
    """(nodes of building b, (m, 2) its springs' ends local to it (-1: the ground), (m,)
    their stiffnesses taken from ``k``, one per storey of the scene)."""
    nodes = np.flatnonzero(ex.node_building == b)
    local = np.full(len(ex.node_building) + 1, -1, dtype=np.int64)  # [-1]: the ground
    local[nodes] = np.arange(len(nodes))
    mine = np.flatnonzero(ex.story_building == b)
    ends = local[column_array(ex.stories, "nodes", np.int64).reshape(-1, 2)[mine]]
    return nodes, ends, np.asarray(k, dtype=float)[mine]


def spring_list(ends: np.ndarray, stiffness: np.ndarray) -> list:
    """Springs ``(i, j, k)`` (Python numbers) of ``ends`` (m, 2) and ``stiffness`` (m,)."""
    return list(zip(ends[:, 0].tolist(), ends[:, 1].tolist(), stiffness.tolist()))


def band_width(ends: np.ndarray) -> int:
    """The half-bandwidth max |i - j| of springs between ``ends`` (m, 2) (a spring to the
    ground, i = -1, adds none)."""
    joined = ends[ends[:, 0] >= 0]
    return int(np.max(np.abs(joined[:, 0] - joined[:, 1]))) if len(joined) else 0


def stiffness_form(ex, b: int, k: np.ndarray, phi: np.ndarray) -> np.ndarray:
    """phi^T K phi of building b's storeys with stiffnesses ``k`` (one per storey of the
    scene; 0 leaves a storey out) for each column of ``phi`` (its floors, in declaration
    order; in plan its DOFs, :func:`building_keys`): sum over the storeys of k d^2, d the
    storey's deformation (phi_upper - phi_lower), without an n x n matrix."""
    if ex.dofs is not None:
        keys, _ = building_keys(ex, b)
        local = {key: i for i, key in enumerate(keys)}
        phi = np.asarray(phi, dtype=float).reshape(len(keys), -1)
        total = np.zeros(phi.shape[1])
        for s, g in _plan_rows(ex, b, local):
            d = sum(a * phi[i] for i, a in g.items()) if g else np.zeros(phi.shape[1])
            total += float(k[s]) * d * d
        return total
    nodes = np.flatnonzero(ex.node_building == b)
    local = np.full(len(ex.node_names), -1)
    local[nodes] = np.arange(len(nodes))
    mine = np.flatnonzero(ex.story_building == b)
    ends = column_array(ex.stories, "nodes", np.int64).reshape(-1, 2)[mine]
    upper = local[ends[:, 1]]
    lower = np.where(ends[:, 0] >= 0, local[np.maximum(ends[:, 0], 0)], -1)
    phi = np.asarray(phi, dtype=float).reshape(len(nodes), -1)
    drift = phi[upper] - np.where(lower[:, None] >= 0, phi[np.maximum(lower, 0)], 0.0)
    return np.asarray(k, dtype=float)[mine] @ (drift * drift)


@contextlib.contextmanager
def one_blas_thread():
    """BLAS on one thread while a tall building's mode shapes are computed: LAPACK's inverse
    iteration (stein, behind eigh_tridiagonal's selected vectors) calls vector operations of
    the building's length, which a threaded BLAS splits over its threads, and those threads
    then spin more than they compute (at 30,000 floors on two busy cores, ten times the CPU
    of one thread). The frequencies (bisection) do not depend on it; the shapes differ only
    in the last bits (another order of the threads' partial sums)."""
    from threadpoolctl import threadpool_limits

    with threadpool_limits(limits=1, user_api="blas"):
        yield


#: the last few frequencies :func:`lowest_modes` computed: (scene, its arguments and masses,
#: frequencies); the damping's fit and its description ask a tall building's same modes twice
_SOLVED: list = []


def lowest_modes(ex, b: int, k: np.ndarray, count: int | None = None,
                 vectors: bool = False):
    """The circular frequencies (rad/s, ascending) of building ``b`` with storey stiffnesses
    ``k``, and with ``vectors`` its mode shapes (columns, normalised on the masses:
    phi^T M phi = 1): all its modes up to :data:`DENSE_FLOORS` floors (or ``count`` None),
    else (at least) the lowest ``count``. In plan: its lateral-torsional modes over its
    floors' DOFs (:func:`building_keys`). The frequencies alone of the same scene (the same
    object, its masses unchanged) and arguments as one of the last few are not solved again:
    they are copied."""
    if vectors:
        return _lowest_modes(ex, b, k, count, vectors)
    key = (b, np.asarray(k, dtype=float).tobytes(), count, np.asarray(ex.masses).tobytes(),
           None if ex.dof_mass is None else np.asarray(ex.dof_mass).tobytes())
    for scene, asked, omega in _SOLVED:
        if scene() is ex and asked == key:
            return np.copy(omega)
    omega = _lowest_modes(ex, b, k, count, vectors)
    _SOLVED.insert(0, (weakref.ref(ex), key, np.copy(omega)))
    del _SOLVED[8:]
    return omega


def _lowest_modes(ex, b: int, k: np.ndarray, count: int | None, vectors: bool):
    if ex.dofs is not None:
        return _plan_modes(ex, b, k, count, vectors)
    nodes, ends, stiffness = building_spring_arrays(ex, b, k)
    n = len(nodes)
    scale = 1.0 / np.sqrt(ex.masses[nodes])
    width = band_width(ends)
    if count is None or n <= DENSE_FLOORS or width > 64:
        springs = spring_list(ends, stiffness)
        if count is not None and n > 4 * DENSE_FLOORS and width > 64:
            return _sparse_lowest(springs, scale, n, count, vectors)
        stiffness = spring_matrix(springs, n) * np.outer(scale, scale)
        if not vectors:
            return np.sqrt(np.clip(np.linalg.eigvalsh(stiffness), 0, None))
        values, shapes = np.linalg.eigh(stiffness)
        return np.sqrt(np.clip(values, 0, None)), shapes * scale[:, None]
    from scipy.linalg import eig_banded, eigh_tridiagonal

    band = scaled_band(ends, stiffness, scale, width)
    last = min(count, n) - 1
    with one_blas_thread() if vectors else contextlib.nullcontext():
        if width <= 1:
            out = eigh_tridiagonal(band[0], band[1][:-1] if width else np.zeros(n - 1),
                                   eigvals_only=not vectors, select="i", select_range=(0, last))
        else:
            out = eig_banded(band, lower=True, eigvals_only=not vectors, select="i",
                             select_range=(0, last))
    if not vectors:
        return np.sqrt(np.clip(out, 0, None))
    return np.sqrt(np.clip(out[0], 0, None)), out[1] * scale[:, None]


def _sparse_lowest(springs, scale, n: int, count: int, vectors: bool):
    """Lowest ``count`` modes of a large building that is not banded (sparse solver)."""
    from scipy.sparse import coo_matrix

    matrix = coo_matrix(scaled_triplets(springs, scale), shape=(n, n)).tocsc()
    values, shapes = sparse_lowest(matrix, count)
    omega = np.sqrt(np.clip(values, 0, None))
    return (omega, shapes * scale[:, None]) if vectors else omega


# eq=False, repr=False: it holds numpy arrays: a generated __eq__ and __hash__ could only
# raise (== is elementwise), a __repr__ would print every array, and each generated
# function is compiled at every start
@dataclass(frozen=True, eq=False, repr=False)
class Isolation:
    """Which storeys of a scene are isolators, and why."""

    isolator: np.ndarray  # (s,) bool: treated as an isolator
    looks: np.ndarray  # (s,) bool: an isolator by its law or its stiffness (whatever is said)
    notes: tuple[str, ...]  # why a storey the scene did not name is taken as one


def _min_above(ex, k_post: np.ndarray) -> np.ndarray:
    """For each storey, the smallest post-yield stiffness of the storeys above it (those
    reached upward from its upper node; inf: none), in one pass however tall."""
    chains = _chains_min_above(ex, k_post)
    if chains is not None:
        return chains
    ends = column(ex.stories, "nodes")
    upper = [u for _, u in ends]
    k_post = k_post.tolist()
    starting: dict[int, list[int]] = {}
    for s, (lower, _) in enumerate(ends):
        starting.setdefault(lower, []).append(s)
    below_top: dict[int, float] = {}  # node -> smallest k_post of the storeys above it
    if all(t > s for s, u in enumerate(upper) for t in starting.get(u, ())):
        # every storey declared after the storeys below it (a building of the shorthand):
        # one pass from the last down gives each node its value once those above have theirs
        for u in reversed(upper):
            above = starting.get(u, ())
            if len(above) == 1:  # a chain of storeys: the same min(), without its lists
                t = above[0]
                below_top[u] = min(math.inf, min(k_post[t], below_top.get(upper[t], math.inf)))
                continue
            below_top[u] = min([math.inf] + [min(k_post[t], below_top.get(upper[t], math.inf))
                                             for t in above])
        return np.array([below_top.get(u, math.inf) for u in upper], dtype=float)
    for start in set(upper):
        if start in below_top:
            continue
        todo, open_ = [(start, False)], set()
        while todo:  # post-order; a loop of storeys (refused elsewhere) is cut where it closes
            node, done = todo.pop()
            if done:
                open_.discard(node)
                below_top[node] = min([math.inf] + [
                    min(k_post[s], below_top.get(upper[s], math.inf))
                    for s in starting.get(node, ()) if upper[s] not in open_])
                continue
            if node in below_top or node in open_:
                continue
            open_.add(node)
            todo.append((node, True))
            todo += [(upper[s], False) for s in starting.get(node, ())]
    return np.array([below_top.get(u, math.inf) for u in upper], dtype=float)


def _chains_min_above(ex, k_post: np.ndarray) -> np.ndarray | None:
    """:func:`_min_above` of storeys that stand in chains declared bottom up (each storey's
    upper node the lower node of the next storey only, or of none: a building of the
    shorthand), as a running minimum down each chain; None for any other layout, or a NaN
    stiffness (whose min() depends on its place)."""
    k_post = np.asarray(k_post, dtype=float)
    ends = column_array(ex.stories, "nodes", np.int64).reshape(-1, 2)
    n = len(ends)
    if not n or np.isnan(k_post).any():
        return None
    lower, upper = ends[:, 0], ends[:, 1]
    starts = lower[lower >= 0]
    if len(sorted_unique(starts)) != len(starts):
        return None  # a node that several storeys stand on: a tree, not a chain
    first = np.full(max(int(ends.max()) + 1, 1), -1, dtype=np.int64)
    first[starts] = np.flatnonzero(lower >= 0)
    following = first[upper]  # the storey standing on each storey's upper node (-1: none)
    if not np.all((following == np.arange(n) + 1) | (following < 0)):
        return None
    out = np.full(n, math.inf)
    start = 0
    for last in np.flatnonzero(following < 0).tolist():  # each chain: start .. last
        # above storey s: the storeys s + 1 .. last; min() of exact floats, in any order
        out[start:last] = np.minimum.accumulate(k_post[last:start:-1])[::-1]
        start = last + 1
    return out


def isolation(ex, k0: np.ndarray, k_post: np.ndarray) -> Isolation:
    """The isolators of a scene (see the module's docstring), with a note for each storey
    taken as one without the scene saying so."""
    said = ex.story_isolator or (None,) * len(ex.stories)
    # a spring of no stiffness of its own (P-delta's in plan) is neither an isolator nor the
    # storey above one
    stiff = k0 > 0.0
    above = _min_above(ex, np.where(stiff, k_post, math.inf))
    laws = column(ex.stories, "law")
    bearing = {law: bool(law.isolator) for law in set(laws)}
    k_post = np.asarray(k_post, dtype=float)
    # the comparisons of IEEE doubles, element by element (a NaN compares false)
    with np.errstate(invalid="ignore", over="ignore"):
        looks = stiff & (np.fromiter(map(bearing.__getitem__, laws), dtype=bool,
                                     count=len(laws))
                         | (np.isfinite(above) & (above > 0.0)
                            & (k_post * ISOLATION_RATIO <= above)))
    isolator = (looks.copy() if not ex.story_isolator else
                np.array([look if says is None else bool(says)
                          for look, says in zip(looks.tolist(), said)], dtype=bool))
    notes = []
    for s in np.flatnonzero(looks & np.array([x is None for x in said], dtype=bool)):
        e = ex.stories[s]
        why = (f"a {e.law.name} is a bearing" if e.law.isolator else
               f"its post-yield stiffness {k_post[s]:.4g} N/m is 1/{above[s] / k_post[s]:.3g} "
               "of that of the storeys above it")
        notes.append(f"storey {e.name} is taken as an isolator ({why}): no stiffness-"
                     "proportional damping on it, and its building's damping is fitted on its "
                     "isolated modes; write isolator: false on it to damp it as a frame "
                     "storey")
    return Isolation(isolator, looks, tuple(notes))


def isolated_stiffness(k0: np.ndarray, k_post: np.ndarray, isolator: np.ndarray) -> np.ndarray:
    """Every storey's stiffness in the isolated modes: the isolators' post-yield stiffness,
    the others' initial tangent."""
    return np.where(isolator, k_post, k0)


def _soil_frequencies(ex, b: int, k0: np.ndarray) -> np.ndarray | None:
    """The circular frequencies of building b on its soil (sway and rocking DOFs after its
    floors; a storey deforms by u_upper - u_lower - h theta), or None on a fixed base."""
    soil = [f for f in ex.foundations if f.building == b]
    if not soil:
        return None
    f = soil[0]
    nodes = np.flatnonzero(ex.node_building == b)
    n = len(nodes)
    local = {node: i for i, node in enumerate(nodes)}
    sway, rock = n, n + 1
    stiffness = np.zeros((n + 2, n + 2))
    for s in np.flatnonzero(ex.story_building == b):
        low, up = ex.stories[s].nodes
        g = np.zeros(n + 2)
        g[local[up]] += 1.0
        g[local[low] if low >= 0 else sway] -= 1.0
        g[rock] -= ex.story_height[s]
        stiffness += k0[s] * np.outer(g, g)
    stiffness[sway, sway] += f.sway_stiffness
    stiffness[rock, rock] += f.rocking_stiffness
    scale = 1.0 / np.sqrt(np.concatenate([ex.masses[nodes], [f.mass, f.rotational_inertia]]))
    values = np.linalg.eigvalsh(stiffness * np.outer(scale, scale))
    return np.sqrt(np.clip(values, 0, None))


def _periods(omega) -> str:
    shown = [2.0 * math.pi / w if w > 0 else math.inf for w in omega[:SHOWN_MODES]]
    return ", ".join("inf" if math.isinf(t) else f"{t:#.3g}" for t in shown)


def period_lines(ex) -> list[str]:
    """The periods that matter of each building, as lines: fixed base on the initial
    stiffness; isolated (a building with isolators); flexible base (a building on soil);
    each less P-delta's P / h where a storey carries a gravity load, as ``pframe modes``
    takes them (the damping's fit does not: :func:`pframe.assemble.damping.describe`)."""
    k0, k_post = storey_stiffness(ex)
    iso = isolation(ex, k0, k_post)
    kg = geometric_stiffness(ex)
    net = k0 - kg
    lines = []
    for b, name in enumerate(ex.buildings):
        nodes = np.flatnonzero(ex.node_building == b)
        mine = ex.story_building == b
        if not np.any(mine):
            lines.append(f"building {name}: {len(nodes)} floor{'s' if len(nodes) > 1 else ''}"
                         " without storeys (held by links)")
            continue
        if len(nodes) > 2000:  # a dense eigen-solve of n^2 values: not for a tall building
            lines.append(f"building {name}: {len(nodes)} floors (periods not computed above "
                         "2,000 floors)")
            continue
        parts = []
        initial = ("initial stiffness less P-delta's P / h" if np.any(kg[mine]) else
                   "initial stiffness")
        isolators = np.flatnonzero(mine & iso.isolator)
        if isolators.size:
            omega = lowest_modes(ex, b, isolated_stiffness(k0, k_post, iso.isolator) - kg,
                                 SHOWN_MODES)
            which = ", ".join(f"{ex.stories[s].name} at {k_post[s]:.4g} N/m"
                              for s in isolators[:3]) + (" ..." if isolators.size > 3 else "")
            parts.append(f"periods {_periods(omega)} s (isolated: {which})")
        if ex.dofs is not None:  # in plan: each period with the direction it mostly moves in
            fixed, shapes = lowest_modes(ex, b, net, SHOWN_MODES, vectors=True)
            shown = [f"{2.0 * math.pi / w:#.3g} s ({d})" if w > 0 else f"inf ({d})"
                     for w, d in zip(fixed[:SHOWN_MODES], directions(ex, b, shapes))]
            parts.append(f"periods {', '.join(shown)} (fixed base, {initial}, "
                         "lateral-torsional)")
        else:
            fixed = lowest_modes(ex, b, net, SHOWN_MODES)
            parts.append(f"periods {_periods(fixed)} s (fixed base, {initial})")
        soil = _soil_frequencies(ex, b, net)
        if soil is not None:
            parts.append(f"periods {_periods(soil)} s (on its soil, {initial})")
        lines.append(f"building {name}: {len(nodes)} floor{'s' if len(nodes) > 1 else ''}, "
                     + "; ".join(parts))
    return lines


def modes_and_shares(ex, b: int, k0: np.ndarray, count: int = 60):
    """Circular frequencies (rad/s, ascending) of building b in plan and the share of its mass
    each mode carries, both horizontal directions together: (p_x^2 + p_y^2) / (M_x + M_y)
    with p_d = phi^T M iota_d (the shares of all modes add up to 1); all modes up to
    3 x :data:`DENSE_FLOORS` degrees of freedom, else the lowest ``count``."""
    keys, masses = building_keys(ex, b)
    omega, phi = _plan_modes(ex, b, k0, count, vectors=True)
    translation = np.array([[1.0 if c == d else 0.0 for _, c in keys] for d in (0, 1)])
    participation = ((phi.T * masses) @ translation.T) ** 2
    total = float(np.sum(masses * translation))
    return omega, participation.sum(axis=1) / max(total, 1e-300)
