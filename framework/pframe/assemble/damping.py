"""Each building's damping: Rayleigh's coefficients or a modal damping matrix, fitted on the
modes that govern it, and the checks of what a building's modes really get.

Rayleigh damping (``kind: rayleigh``) is ``C = a0 M + a1 K_d``, where ``K_d`` holds the storeys
that take the stiffness-proportional term (every storey but the isolators by default; a storey
says otherwise with ``stiffness_damping``). ``a0`` and ``a1`` are fitted so that the two modes
named (of the stiffness ``fit`` names: isolated by default, :mod:`pframe.assemble.modes`) get
the ratio asked,

    phi_i^T C phi_i = 2 xi w_i        (phi normalised on the masses),

that is ``a0 + a1 s_i = 2 xi w_i`` with ``s_i = phi_i^T K_d phi_i``. Where ``K_d`` is the
whole stiffness the modes are computed on, ``s_i = w_i^2`` and this is the textbook
``a0 = 2 xi w_i w_j / (w_i + w_j)``, ``a1 = 2 xi / (w_i + w_j)`` (Chopra 2012, eq. 11.4.9),
which pframe then computes as such. Modal damping (``kind: modal``) gives every mode its own
ratio, ``C = M Phi diag(2 xi_n w_n) Phi^T M`` (Chopra 2012, eq. 11.4.22), a dense matrix over
the building's floors.

Fitting a base-isolated building's damping on its initial stiffness (a friction pendulum's
stick stiffness, a lead-rubber bearing's elastic one) damps its isolated mode far above the
ratio asked (Ryan & Polanco 2008): :func:`fit` fits the isolated modes, and :func:`checks`
warns when what the isolated mode gets is far from what was asked.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from pframe.assemble import modes
from pframe.errors import InputError

#: a building's modal damping matrix is dense over its floors (n^2 numbers, n^2 operations at
#: every evaluation of the residual and a band as wide as the building): refused above this
MODAL_FLOORS = 400
#: the stiffness term meeting an isolator whose initial stiffness is this many times its
#: post-yield stiffness damps the isolator's own post-yield swaying at least sqrt(4) = 2 times
#: the ratio it has at its initial stiffness: warned about
INITIAL_OVER_POST = 4.0
#: an isolated mode damped this many times the ratio asked, or more, is warned about
OVERDAMPED = 1.5


# eq=False, repr=False: it holds numpy arrays: a generated __eq__ and __hash__ could only
# raise (== is elementwise), a __repr__ would print every array, and each generated
# function is compiled at every start
@dataclass(frozen=True, eq=False, repr=False)
class Fit:
    """The damping of a scene: a0 per node (1/s: on every DOF of the node's floor), a1 per
    storey (s), and the modal blocks (the DOFs of a building, (node, component), and its
    dense matrix, N s/m)."""

    a0: np.ndarray  # (nodes,) in declaration order
    a1: np.ndarray  # (s,)
    modal: tuple[tuple[np.ndarray, np.ndarray], ...] = ()
    warnings: tuple[str, ...] = ()  # a fit that could not give every mode named its ratio


def stiffness_damped(ex, isolator: np.ndarray) -> np.ndarray:
    """(s,) True where the stiffness-proportional term acts: what a storey says
    (``stiffness_damping``), else every storey but the isolators."""
    if not ex.story_stiffness_damping:  # none said: every storey but the isolators
        return ~np.asarray(isolator, dtype=bool)[:len(ex.stories)]
    said = ex.story_stiffness_damping
    return np.array([not isolator[s] if said[s] is None else bool(said[s])
                     for s in range(len(ex.stories))], dtype=bool)


def _ratios(damping, count: int) -> np.ndarray:
    """A modal damping's ratio for each of ``count`` modes (the last given repeated)."""
    given = damping.ratio if isinstance(damping.ratio, list) else [damping.ratio]
    return np.array([given[min(i, len(given) - 1)] for i in range(count)], dtype=float)


def _fit_stiffness(damping, k0, k_post, isolator) -> np.ndarray:
    return (modes.isolated_stiffness(k0, k_post, isolator) if damping.fit == "isolated"
            else k0)


def _frequencies(ex, b, k, count, vectors=False):
    try:
        with np.errstate(all="ignore"):
            out = modes.lowest_modes(ex, b, k, count, vectors=vectors)
    except (np.linalg.LinAlgError, ArithmeticError, ValueError):
        out = None
    omega = out[0] if vectors and out is not None else out
    if out is None or not np.all(np.isfinite(omega)):
        raise InputError(f"building {ex.buildings[b]!r}: its natural frequencies (for its "
                         "damping) cannot be computed from its masses and storey stiffnesses; "
                         "they span more than floating point carries (check the units)")
    return out


def wanted_modes(ex, b: int, damping, k_fit) -> tuple[int, int]:
    """The two modes (1-based, in building b's order of frequency on ``k_fit``) Rayleigh
    damping is fitted to: numbers as given, a direction's (``x1``, ``y2``, ``torsion1``) found
    among the building's modes by :func:`pframe.assemble.modes.directions`; a one-storey
    building's single mode twice for the default (1, 2)."""
    name = ex.buildings[b]
    count = modes.building_dofs(ex, b)  # its modes (in plan: lateral-torsional)
    asked = damping.modes
    if all(isinstance(m, int) for m in asked):
        if max(asked) <= count:
            return tuple(asked)
        if count == 1 and tuple(asked) == (1, 2):
            return (1, 1)  # a one-storey building has one mode: fit the ratio there
        raise InputError(f"building {name!r} has {count} modes; damping modes "
                         f"{list(asked)} cannot be fitted")
    phi = _frequencies(ex, b, k_fit, None, vectors=True)[1]
    seen = modes.directions(ex, b, phi)
    out = []
    for m in asked:
        if isinstance(m, int):
            if m > count:
                raise InputError(f"building {name!r} has {count} modes; damping mode {m} "
                                 "cannot be fitted")
            out.append(m)
            continue
        direction = m.rstrip("0123456789")
        number = int(m[len(direction):])
        found = [i + 1 for i, d in enumerate(seen) if d == direction]
        if number > len(found):
            have = ", ".join(f"{d} {seen.count(d)}" for d in ("x", "y", "torsion")
                             if d in seen)
            raise InputError(f"building {name!r} has {len(found)} mode(s) moving mostly in "
                             f"{direction}, so damping mode {m!r} cannot be fitted (its "
                             f"modes by direction: {have}; pframe validate lists them)")
        out.append(found[number - 1])
    return tuple(out)


def _rayleigh(ex, b: int, damping, k_fit, k_d, damped, warnings: list) -> tuple[float, float]:
    """(a0, a1) of building b: its modes of ``k_fit``, the stiffness term on the storeys
    ``damped`` with stiffness ``k_d``; what the fit cannot give goes to ``warnings``."""
    name = ex.buildings[b]
    mine = np.flatnonzero(ex.story_building == b)
    wanted = wanted_modes(ex, b, damping, k_fit)
    textbook = bool(np.all(damped[mine])) and np.array_equal(k_d[mine], k_fit[mine])
    out = _frequencies(ex, b, k_fit, max(wanted), vectors=not textbook)
    omega = out if textbook else out[0]
    wi, wj = omega[wanted[0] - 1], omega[wanted[1] - 1]
    if min(wi, wj) == 0.0 and wi + wj > 0.0:
        which = wanted[0] if wi == 0.0 else wanted[1]
        raise InputError(f"building {name!r}: its mode {which} has no stiffness (an isolator "
                         "with no post-yield stiffness, a flat slider: the building slides as "
                         "a block); Rayleigh damping cannot give it a ratio: fit it on higher "
                         "modes (damping: {modes: [2, 3]}) or use kind: modal")
    if wi + wj == 0.0:
        raise InputError(f"building {name!r} has no stiffness to fit Rayleigh damping to "
                         "(add storeys or set damping ratio 0)")
    xi = damping.ratio
    if textbook:
        return 2.0 * xi * wi * wj / (wi + wj), 2.0 * xi / (wi + wj)
    s = modes.stiffness_form(ex, b, np.where(damped, k_d, 0.0),
                             out[1][:, [wanted[0] - 1, wanted[1] - 1]])
    if wanted[0] == wanted[1] or math.isclose(s[0], s[1], rel_tol=1e-12, abs_tol=0.0):
        if wanted[0] != wanted[1] and not math.isclose(wi, wj, rel_tol=1e-12):
            # no stiffness term (or one that damps both modes alike): the mass term alone
            # cannot give two modes one ratio; it gives the first its ratio
            warnings.append(f"building {name}: no storey takes Rayleigh's stiffness term (or "
                            f"it damps modes {wanted[0]} and {wanted[1]} alike), so the mass "
                            f"term alone gives mode {wanted[0]} its {100 * xi:.3g} % and mode "
                            f"{wanted[1]} {100 * xi * wi / wj:.3g} %; use kind: modal for "
                            "both")
            return 2.0 * xi * wi, 0.0
        if s[0] == 0.0:
            return 2.0 * xi * wi, 0.0
        return xi * wi, xi * wi / s[0]  # one mode: half of it from each term
    a1 = 2.0 * xi * (wj - wi) / (s[1] - s[0])
    a0 = 2.0 * xi * wi - a1 * s[0]
    if a0 < 0.0 or a1 < 0.0:
        raise InputError(f"building {name!r}: Rayleigh damping fitted on modes "
                         f"{list(damping.modes)} needs a negative coefficient (a0 = {a0:.4g} "
                         f"1/s, a1 = {a1:.4g} s): the storeys with the stiffness term (every "
                         "storey but the isolators, or as their stiffness_damping says) deform "
                         f"more in mode {wanted[0]}, relative to its frequency, than in mode "
                         f"{wanted[1]}; fit other modes, choose other storeys for the "
                         "stiffness term (stiffness_damping), or use kind: modal")
    return a0, a1


def _modal(ex, b: int, damping, k_fit) -> np.ndarray:
    """C = M Phi diag(2 xi_n w_n) Phi^T M of building b (over its DOFs,
    :func:`pframe.assemble.modes.building_keys`)."""
    keys, masses = modes.building_keys(ex, b)
    floors = len({node for node, _ in keys})
    if floors > MODAL_FLOORS:
        raise InputError(f"building {ex.buildings[b]!r}: modal damping is a dense matrix over "
                         f"its {floors} floors (n^2 operations a step); it is offered up "
                         f"to {MODAL_FLOORS} floors: use kind: rayleigh")
    omega, phi = _frequencies(ex, b, k_fit, None, vectors=True)
    mphi = masses[:, None] * phi
    matrix = mphi @ np.diag(2.0 * _ratios(damping, len(omega)) * omega) @ mphi.T
    return 0.5 * (matrix + matrix.T)


def fit(ex, k0: np.ndarray, k_post: np.ndarray, isolator: np.ndarray) -> Fit:
    """The damping of every building of an Expanded scene (see the module's docstring)."""
    a0 = np.zeros(len(ex.node_names))
    a1 = np.zeros(len(ex.stories))
    blocks, warnings = [], []
    damped = stiffness_damped(ex, isolator)
    for b, name in enumerate(ex.buildings):
        damping = ex.damping[b]
        mine = np.flatnonzero(ex.story_building == b)
        if damping.kind == "modal":
            forced = [ex.stories[s].name for s in mine
                      if (ex.story_stiffness_damping or (None,) * len(ex.stories))[s]]
            if forced:
                raise InputError(f"building {name!r} has modal damping, which has no "
                                 "stiffness-proportional term: storey "
                                 f"{forced[0]} says stiffness_damping: true")
            if not mine.size:
                continue
            if any(f.building == b for f in ex.foundations):
                raise InputError(f"building {name!r}: modal damping of a building on soil is "
                                 "not modelled (its modes include the foundation's sway and "
                                 "rocking, which the soil's dashpots damp): use kind: rayleigh")
            matrix = _modal(ex, b, damping, _fit_stiffness(damping, k0, k_post, isolator))
            blocks.append((modes.building_keys(ex, b)[0], matrix))
            continue
        if damping.ratio == 0.0 or not mine.size:
            continue  # no storeys: masses carried by links only (a tuned mass) are damped by
            # their links, not by a Rayleigh fit
        k_fit = _fit_stiffness(damping, k0, k_post, isolator)
        k_d = k0 if damping.stiffness == "initial" else k_fit
        b0, b1 = _rayleigh(ex, b, damping, k_fit, k_d, damped, warnings)
        a0[ex.node_building == b] = b0
        a1[mine] = np.where(damped[mine], b1, 0.0)
    return Fit(a0, a1, tuple(blocks), tuple(warnings))


def isolated_ratio(ex, b: int, result: Fit, k0, k_post, isolator, damped) -> tuple | None:
    """(period T (s), damping ratio) of building b's first isolated mode under the damping
    ``result`` (the stiffness term on each storey's initial stiffness where the building's
    damping says initial, else on its isolated stiffness); None when the mode has no
    period (a flat slider) or the building is too tall for a dense check."""
    keys, masses = modes.building_keys(ex, b)
    if len(keys) > modes.DENSE_FLOORS:
        return None
    k_iso = modes.isolated_stiffness(k0, k_post, isolator)
    omega, phi = modes.lowest_modes(ex, b, k_iso, vectors=True)
    if omega[0] <= 0.0:
        return None
    p = phi[:, 0]
    damping = ex.damping[b]
    k_d = k0 if getattr(damping, "stiffness", "initial") == "initial" else k_iso
    a0 = result.a0[[node for node, _ in keys]]
    c = float(np.sum(a0 * masses * p * p)
              + modes.stiffness_form(ex, b, np.where(damped, result.a1 * k_d, 0.0), p)[0])
    for block_keys, matrix in result.modal:
        if list(block_keys) == list(keys):
            c += float(p @ matrix @ p)
    return 2.0 * math.pi / omega[0], c / (2.0 * omega[0])


def checks(ex, result: Fit, k0, k_post, iso) -> tuple[str, ...]:
    """Warnings: a building whose isolated mode 1 gets far more damping than asked, and why
    (the stiffness term on an isolator's initial stiffness, a fit on the initial stiffness);
    Ryan & Polanco (2008)."""
    damped = stiffness_damped(ex, iso.isolator)
    suspect = iso.isolator | iso.looks
    out = []
    for b, name in enumerate(ex.buildings):
        mine = np.flatnonzero((ex.story_building == b) & suspect)
        damping = ex.damping[b]
        asked = (_ratios(damping, 1)[0] if damping.kind == "modal" else damping.ratio)
        if not mine.size or asked == 0.0:
            continue
        causes = []
        initial = getattr(damping, "stiffness", "initial") == "initial"
        said = ex.story_isolator or (None,) * len(ex.stories)
        for s in mine:
            if damped[s] and result.a1[s] > 0.0 and initial \
                    and k0[s] >= INITIAL_OVER_POST * k_post[s]:
                ratio = "far" if k_post[s] == 0.0 else f"{k0[s] / k_post[s]:.3g} times"
                remedy = ("it says isolator: false; an isolator gets no stiffness term"
                          if said[s] is False else "leave out its stiffness_damping: an "
                          "isolator gets none by default")
                causes.append(f"Rayleigh's stiffness term acts on storey {ex.stories[s].name}'s "
                              f"initial stiffness {k0[s]:.4g} N/m, {ratio} above its post-"
                              f"yield or sliding stiffness ({remedy})")
        if damping.fit == "initial":
            causes.append("the damping is fitted on the initial stiffness (fit: initial; the "
                          "default, fit: isolated, fits the isolated modes)")
        found = isolated_ratio(ex, b, result, k0, k_post, suspect, damped)
        over = found is not None and found[1] >= OVERDAMPED * asked
        if not causes or not (over or any("stiffness term" in c for c in causes)):
            continue
        got = (f"is damped at {100 * found[1]:.3g} % of critical, not the {100 * asked:.3g} % "
               f"asked" if found is not None else "is damped far from the ratio asked")
        period = f" (T = {found[0]:.3g} s)" if found is not None else ""
        out.append(f"building {name}: its isolated mode 1{period} {got}: " + "; ".join(causes)
                   + " (Ryan & Polanco 2008; docs/theory.md#damping)")
    return tuple(out)


def describe(ex, result: Fit, k0, k_post, isolator) -> tuple[str, ...]:
    """Each building's damping as applied, one line per building (validate, the file):
    ``building A: Rayleigh 5 % on modes 1 (0.502 s) and 2 (0.179 s) of the fixed base:
    a0 = 0.9216 1/s, a1 = 0.002103 s on the initial stiffness``."""
    out = []
    damped = stiffness_damped(ex, isolator)
    p_delta = modes.geometric_stiffness(ex) > 0.0
    for b, name in enumerate(ex.buildings):
        damping = ex.damping[b]
        mine = np.flatnonzero(ex.story_building == b)
        isolated = damping.fit == "isolated" and bool(np.any(isolator[mine]))
        on = "the isolated building" if isolated else "the fixed base"
        if not mine.size:
            out.append(f"building {name}: none of its own (no storeys; its links damp it)")
            continue
        if damping.kind == "modal":
            given = damping.ratio if isinstance(damping.ratio, list) else [damping.ratio]
            ratios = (f"{100 * given[0]:.3g} % on every mode" if len(given) == 1 else
                      ", ".join(f"{100 * r:.3g} %" for r in given) + " on modes 1, 2, ... "
                      "(the last on the modes after)")
            out.append(f"building {name}: modal, {ratios} of {on}")
            continue
        if damping.ratio == 0.0:
            out.append(f"building {name}: none (ratio 0)")
            continue
        k_fit = _fit_stiffness(damping, k0, k_post, isolator)
        wanted = wanted_modes(ex, b, damping, k_fit)
        omega = modes.lowest_modes(ex, b, k_fit, max(wanted))
        named = dict(zip(wanted, damping.modes))
        periods = [f"{m} ({named[m] + ', ' if isinstance(named.get(m), str) else ''}"
                   + (f"{2 * math.pi / omega[m - 1]:#.3g} s)" if omega[m - 1] > 0.0 else
                      "no period: the building slides as a block)")
                   for m in dict.fromkeys(wanted)]
        a0 = float(result.a0[ex.node_building == b][0])
        a1 = float(np.max(result.a1[mine]))
        skipped = [ex.stories[s].name for s in mine[~damped[mine]].tolist()]
        without = (", not on " + ", ".join(skipped[:4]) + (" ..." if len(skipped) > 4 else "")
                   if skipped and a1 else "")
        out.append(f"building {name}: Rayleigh {100 * damping.ratio:.3g} % on mode"
                   f"{'s' if len(periods) > 1 else ''} {' and '.join(periods)} of {on}: a0 = "
                   f"{a0:.4g} 1/s, a1 = {a1:.4g} s on the {damping.stiffness} stiffness"
                   f"{without}" + ("; modes and stiffness without P-delta's P / h (its "
                                   "periods with it are longer; docs/theory.md#damping)"
                                   if np.any(p_delta[mine]) else ""))
    return tuple(out)


class BatchDamping:
    """The damping of the members of a batch (:func:`pframe.assemble.assemble_batch`): the
    isolators decided on member 0 for all (a batch shares its topology), each member's fit
    (members of equal masses, stiffnesses and damping share one), the warnings, and the plan's
    modal arrays."""

    def __init__(self, variants, k0: np.ndarray):
        first = variants[0]
        k_post = [modes.post_yield(ex, k0[b]) for b, ex in enumerate(variants)]
        self.isolation = iso = modes.isolation(first, k0[0], k_post[0])
        cache: dict = {}
        self.fits = []
        differ = []
        for b, ex in enumerate(variants):
            if b and not np.array_equal(modes.isolation(ex, k0[b], k_post[b]).isolator,
                                        iso.isolator):
                differ.append(b)
            key = (ex.masses.tobytes(), getattr(ex.dof_mass, "tobytes", lambda: b"")(),
                   k0[b].tobytes(), k_post[b].tobytes(), id(ex.damping))
            if key not in cache:
                cache[key] = fit(ex, k0[b], k_post[b], iso.isolator)
            self.fits.append(cache[key])
        warnings = list(self.fits[0].warnings) + list(
            checks(first, self.fits[0], k0[0], k_post[0], iso))
        if differ:
            names = [first.stories[s].name for s in np.flatnonzero(iso.isolator)] or ["none"]
            warnings.append(f"the storeys taken as isolators differ between the members of this "
                            f"batch (member {differ[0]} and {len(differ) - 1} more): every "
                            f"member is damped as member 0, whose isolators are "
                            f"{', '.join(names)}; write isolator: true or false on the storeys "
                            "to choose")
        self.warnings = tuple(warnings)
        self.notes = iso.notes
        self.text = describe(first, self.fits[0], k0[0], k_post[0], iso.isolator)
        self.modal_keys = [list(keys) for keys, _ in self.fits[0].modal]
        self.isolated = np.array([modes.isolated_stiffness(k0[b], k_post[b], iso.isolator)
                                  for b in range(len(variants))]).reshape(k0.shape)

    def plan_fields(self, dof_of) -> dict:
        """The plan's modal arrays, ``dof_of((node, component))`` numbering a DOF."""
        blocks = self.modal_keys
        sizes = [len(keys) for keys in blocks]
        return dict(
            modal_dofs=np.array([dof_of(key) for keys in blocks for key in keys],
                                dtype=np.int64),
            modal_start=np.concatenate([[0], np.cumsum(sizes)]).astype(np.int64),
            modal_matrix=np.array([np.concatenate([m.ravel() for _, m in f.modal] or
                                                  [np.zeros(0)]) for f in self.fits]),
            notes=self.notes, damping_text=self.text)
