"""The modes of a scene (``pframe modes``, :func:`pframe.modes`): periods, directions,
participation factors, effective modal masses and the damping ratio each mode gets, for each
building on a fixed base, on its soil and isolated, and for the scene its links couple.

The matrices are the plan's (:mod:`pframe.assemble`), the ones the kernel integrates: the
masses of its degrees of freedom (the floors' u_x, or u_x, u_y and theta in plan; a
foundation's sway and rocking), and the stiffness ``K = G^T diag(k) G`` of its spring
elements, G their deformations (:func:`pframe.assemble.incidence.incidence`: a line of
resistance in plan by its sides' weights, a storey on soil less ``h theta``). What each
analysis takes (every analysis says it in its ``stiffness`` text):

- storeys and links at their initial tangent ``k0``, less P-delta's geometric stiffness
  ``P / h`` where a storey carries a gravity load (the kernel's storey force is net of it);
  a dashpot has none, a Kelvin-Voigt link its spring;
- **isolated**: the isolators at their post-yield or sliding stiffness (the law's
  ``post_yield_stiffness``: alpha k0 of a bilinear or Bouc-Wen bearing, W / R of a friction
  pendulum; :mod:`pframe.assemble.modes` decides which storeys are isolators), as the
  building's damping is fitted;
- **fixed base**: a foundation's sway and rocking held (the building as if on rock);
  **on its soil**: with them and the soil's springs (docs/soil.md);
- contacts open (their gaps), so none of them; the supports (docs/supports.md) fixed, so a
  scene on several supports has the modes of one ground.

With ``phi`` normalised on the masses (``phi^T M phi = 1``) and ``iota_d`` the ground's rigid
motion along the site's axis d (1 on the translations along d and on a foundation's sway
along x; 0 on rotations and rocking), Chopra (2012) sections 13.2 and 13.3:

- participation factor ``Gamma_nd = phi_n^T M iota_d`` (kg^1/2 with this normalisation; the
  ``L_n / M_n`` of a mode normalised otherwise), effective modal mass ``M*_nd = Gamma_nd^2``
  (kg), summing over all modes to the total mass along d, ``iota_d^T M iota_d``;
- the direction shares of a mode: the parts of ``phi_n^T M phi_n = 1`` on the DOFs of each
  component (x, y, torsion, rocking), its kinetic energy's shares; the direction named is
  the one :func:`pframe.assemble.modes.directions` names (the largest ``Gamma_d^2 / M_d``,
  as damping's ``modes: [x1, torsion1]`` count them);
- damping ratio ``xi_n = phi_n^T C phi_n / (2 w_n)`` of the scene's damping (Rayleigh's
  ``a0 M + a1 K_d``, or the modal matrix), and ``xi_n`` with the elements' own dashpots too
  (links, the soil, viscous storey laws: their rate tangents at rest), the diagonal terms of
  ``Phi^T C Phi`` (a non-classical damping's off-diagonal terms are left out).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from pframe.errors import InputError

#: analyses of up to this many degrees of freedom get all their modes (a dense eigen-solve);
#: larger ones their lowest ``count`` (a sparse one)
DENSE_DOFS = 2000
#: the lowest modes kept of an analysis larger than :data:`DENSE_DOFS`
SPARSE_MODES = 30
#: the parts of a mode's kinetic energy the output names
SHARES = ("x", "y", "torsion", "rocking")


@dataclass(frozen=True)
class Analysis:
    """One eigen-analysis: a system (a building, or the scene its links couple) on one base
    and stiffness."""

    system: str  # a building's name, or "scene" (the buildings its links couple)
    case: str  # "fixed", "soil" or "isolated"
    dofs: np.ndarray  # the plan's DOFs it moves
    springs: np.ndarray  # the plan's spring elements it holds
    stiffness: np.ndarray  # (springs,) N/m, P-delta's P / h subtracted
    text: str  # what stiffness and base it takes, for people


def _owner(plan, ex) -> np.ndarray:
    """(n,) the building of each DOF of a plan (a foundation's: its building's)."""
    owner = np.full(plan.n_dof, -1)
    nodes = (plan.dof_node if plan.dof_node is not None else None)
    if nodes is None:
        owner[plan.node_dof] = ex.node_building
    else:
        moving = nodes >= 0
        owner[moving] = np.asarray(ex.node_building)[nodes[moving]]
    for name, dofs in zip(plan.foundations, plan.foundation_dofs if plan.foundations else ()):
        owner[dofs] = plan.buildings.index(name)
    return owner


def _components(plan) -> np.ndarray:
    """(n,) the share each DOF counts in (an index into :data:`SHARES`)."""
    out = (np.zeros(plan.n_dof, dtype=int) if plan.dof_component is None
           else np.asarray(plan.dof_component, dtype=int).copy())
    if plan.foundations:
        out[plan.foundation_dofs[:, 0]] = 0
        out[plan.foundation_dofs[:, 1]] = 3
    return out


def _foundation_dofs(plan) -> np.ndarray:
    return (plan.foundation_dofs.ravel() if plan.foundations else np.zeros(0, dtype=int))


def _rate_tangents(plan, member: int) -> np.ndarray:
    """(springs,) each spring's rate tangent at rest (N s/m): a dashpot's coefficient."""
    out = np.zeros(plan.n_springs)
    for group in plan.story_groups:
        for j, e in enumerate(group.index):
            state = np.asarray(group.state[member, j], dtype=float)
            out[e] = float(group.law.force(np.asarray(group.params[member, j], dtype=float),
                                           state.copy(), state.copy(), 0.0, 0.0)[2])
    return out


def _isolators(ex, plan) -> tuple[np.ndarray, str]:
    """(s,) the storeys taken as isolators, and what stiffness each is taken at."""
    from pframe.assemble import modes

    k0, k_post = modes.storey_stiffness(ex)
    iso = modes.isolation(ex, k0, k_post).isolator
    said = []
    for s in np.flatnonzero(iso)[:4]:
        e = ex.stories[s]
        rule = (e.law.post_yield_stiffness.__doc__ or "").split(":")[0].strip()
        said.append(f"{e.name} ({e.law.name}) at {k_post[s]:.4g} N/m"
                    + (f" = {rule}" if rule else ""))
    more = " ..." if iso.sum() > 4 else ""
    return iso, ", ".join(said) + more


def analyses(plan, ex, member: int = 0) -> list[Analysis]:
    """The analyses of a plan's member: each building on a fixed base, on its soil (if it
    has one) and isolated (if it has isolators); then the scene its links couple (if links
    join buildings), likewise. See the module's docstring for what each takes."""
    from pframe.assemble.incidence import incidence

    G = incidence(plan.story_dofs, plan.story_sides, member, plan.n_dof).tocsr()
    owner = _owner(plan, ex)
    ns = len(plan.story_names)
    kg = plan.story_kg[member] if plan.story_kg is not None else np.zeros(plan.n_springs)
    initial = plan.story_k0[member] - kg
    isolator, which = _isolators(ex, plan)
    isolated = plan.story_isolated[member] - kg if plan.story_isolated is not None else initial
    spring_owner = []
    for s in range(plan.n_springs):
        cols = G.indices[G.indptr[s]:G.indptr[s + 1]]
        owners = set(owner[cols].tolist())
        spring_owner.append(owners.pop() if len(owners) == 1 else -1)
    spring_owner = np.array(spring_owner)
    foundation = _foundation_dofs(plan)
    links = ns + len(plan.link_names)
    coupling = [plan.link_names[s - ns] for s in range(ns, links) if spring_owner[s] == -1
                and G.indptr[s + 1] > G.indptr[s]]
    pdelta = " less P-delta's P / h" if np.any(kg) else ""
    base = (f"storeys and links at their initial tangent{pdelta} (a dashpot has none); "
            "contacts open")
    systems = [(name, np.flatnonzero(owner == b), np.flatnonzero(spring_owner == b))
               for b, name in enumerate(plan.buildings)]
    if coupling:
        systems.append(("scene", np.arange(plan.n_dof), np.arange(plan.n_springs)))
    out = []
    for name, dofs, springs in systems:
        mine = springs[springs < ns]
        if not springs.size:
            continue  # no storeys of its own (a tuned mass): see the coupled scene
        on_soil = np.intersect1d(dofs, foundation)
        fixed = np.setdiff1d(dofs, foundation)
        out.append(Analysis(name, "fixed", fixed, springs, initial[springs],
                            f"fixed base{' (its foundation held)' if on_soil.size else ''}; "
                            f"{base}"))
        if on_soil.size:
            out.append(Analysis(name, "soil", dofs, springs, initial[springs],
                                f"on its soil (the foundation's sway and rocking springs); "
                                f"{base}"))
        if np.any(isolator[mine]):
            out.append(Analysis(name, "isolated", dofs, springs, isolated[springs],
                                f"isolated: {which}; the other storeys and links at their "
                                f"initial tangent{pdelta}; "
                                f"{'on its soil' if on_soil.size else 'fixed base'}; "
                                "contacts open"))
    if coupling:
        out = [a if a.system != "scene" else Analysis(
            a.system, a.case, a.dofs, a.springs, a.stiffness,
            f"the buildings coupled by links {', '.join(coupling[:4])}"
            f"{' ...' if len(coupling) > 4 else ''}; " + a.text) for a in out]
    return out


@dataclass(frozen=True)
class Solved:
    """The modes of one :class:`Analysis` (mode shapes normalised on the masses)."""

    omega: np.ndarray  # (m,) rad/s, ascending
    shapes: np.ndarray  # (dofs, m)
    participation: np.ndarray  # (m, directions) phi^T M iota_d (kg^1/2)
    total_mass: np.ndarray  # (directions,) iota_d^T M iota_d (kg)
    shares: np.ndarray  # (m, SHARES) parts of phi^T M phi = 1 on each component
    direction: list  # (m,) x, y or torsion
    damping: np.ndarray  # (m,) the scene's damping model's ratio
    dashpots: np.ndarray  # (m,) with the elements' dashpots too


def _eigen(K, masses: np.ndarray, count: int | None):
    """(omega, phi) of K phi = w^2 M phi, M = diag(masses), phi^T M phi = 1; all modes up
    to :data:`DENSE_DOFS`, else the lowest ``count``."""
    scale = 1.0 / np.sqrt(masses)
    n = len(masses)
    with np.errstate(all="ignore"):
        if n <= DENSE_DOFS:
            w2, shapes = np.linalg.eigh(K.toarray() * np.outer(scale, scale))
        else:
            from scipy.sparse import diags

            from pframe.assemble.modes import sparse_lowest

            scaled = (diags(scale) @ K @ diags(scale)).tocsc()
            w2, shapes = sparse_lowest(scaled, count or SPARSE_MODES)
    phi = shapes * scale[:, None]
    # a mode's sign is arbitrary: its largest component positive, so that outputs repeat
    big = np.argmax(np.abs(phi), axis=0)
    phi *= np.where(phi[big, np.arange(phi.shape[1])] < 0, -1.0, 1.0)
    return np.sqrt(np.clip(w2, 0.0, None)), phi


def solve(plan, ex, analysis: Analysis, member: int = 0, count: int | None = None,
          axes: tuple[str, ...] = ("x",)) -> Solved:
    """The modes of ``analysis`` (see the module's docstring for what is computed)."""
    from scipy.sparse import diags

    from pframe.assemble import modes
    from pframe.assemble.incidence import incidence
    from pframe.kernel.state import DampingStiffness

    dofs = analysis.dofs
    G = incidence(plan.story_dofs, plan.story_sides, member, plan.n_dof).tocsr()
    g = G[analysis.springs][:, dofs]
    K = (g.T @ diags(analysis.stiffness) @ g).tocsr()
    masses = np.asarray(plan.mass[member], dtype=float)[dofs]
    if not np.all(masses > 0.0) or not np.all(np.isfinite(K.data)):
        raise InputError(f"{analysis.system}: its modes cannot be computed: a degree of "
                         "freedom without mass, or a stiffness that is not finite")
    omega, phi = _eigen(K, masses, count)
    if not np.all(np.isfinite(omega)):
        raise InputError(f"{analysis.system}: its natural frequencies span more than floating "
                         "point carries (check the units of its masses and stiffnesses)")
    components = _components(plan)[dofs]
    foundation = _foundation_dofs(plan)
    iota = np.zeros((len(axes), len(dofs)))
    for d, axis in enumerate(axes):
        c = ("x", "y").index(axis)
        iota[d] = components == c
    iota[:, np.isin(dofs, foundation[1::2])] = 0.0  # rocking: not moved by a translation
    participation = (phi.T * masses) @ iota.T
    shares = np.stack([np.sum(masses[components == c, None] * phi[components == c] ** 2, axis=0)
                       for c in range(len(SHARES))], axis=1)
    deformation = g @ phi  # each spring's deformation in each mode
    beta = plan.story_beta[member][analysis.springs]
    initial = plan.story_damping_stiffness[analysis.springs] == DampingStiffness.INITIAL
    kg = plan.story_kg[member][analysis.springs] if plan.story_kg is not None else 0.0
    k_d = np.where(initial, plan.story_k0[member][analysis.springs], analysis.stiffness + kg)
    c = (np.asarray(plan.mass_damping[member], dtype=float)[dofs] @ phi ** 2
         + (beta * k_d) @ deformation ** 2)
    if plan.modal_start is not None and len(plan.modal_start) > 1:
        block = plan.modal_damping(member)[np.ix_(dofs, dofs)]
        c = c + np.einsum("im,ij,jm->m", phi, block, phi)
    viscous = _rate_tangents(plan, member)[analysis.springs] @ deformation ** 2
    with np.errstate(divide="ignore", invalid="ignore"):
        ratio = np.where(omega > 0.0, c / (2.0 * omega), np.nan)
        dashpots = np.where(omega > 0.0, (c + viscous) / (2.0 * omega), np.nan)
    return Solved(omega, phi, participation, iota @ masses, shares,
                  modes.direction_names(components, masses, phi), ratio, dashpots)


def _dof_labels(plan, ex) -> list[str]:
    """'<node>:<component>' of each DOF of the plan; '<building>/foundation:sway|rocking'."""
    from pframe.model.plan import COMPONENTS

    labels = [""] * plan.n_dof
    nodes = plan.dof_node
    for d in range(plan.n_dof):
        if nodes is None:
            continue
        if nodes[d] >= 0:
            labels[d] = f"{ex.node_names[nodes[d]]}:{COMPONENTS[plan.dof_component[d]]}"
    if nodes is None:
        for i, d in enumerate(plan.node_dof):
            labels[d] = f"{ex.node_names[i]}:x"
    for name, (sway, rock) in zip(plan.foundations,
                                  plan.foundation_dofs if plan.foundations else ()):
        labels[sway], labels[rock] = f"{name}/foundation:sway", f"{name}/foundation:rocking"
    return labels


#: the Dataset's description of its variables (Chopra 2012, sections 13.2 and 13.3)
COMMENT = ("modes normalised on the masses (phi^T M phi = 1); participation_factor = phi^T M "
           "iota_d, effective_mass = its square (summing over all modes to total_mass along "
           "d); share: the parts of phi^T M phi on each component (x, y, torsion, rocking); "
           "damping_ratio = phi^T C phi / (2 w) of the scene's damping (Rayleigh or modal), "
           "damping_ratio_with_dashpots with the links', the soil's and viscous storeys' "
           "dashpots too (the diagonal of Phi^T C Phi); NaN beyond an analysis's modes; each "
           "analysis's stiffness says what it takes")


def dataset(loaded, member: int = 0, count: int | None = None):
    """The modes of a loaded scene (:class:`pframe.reader.LoadedScene`) as an xarray
    Dataset: one ``analysis`` per building and base (and the coupled scene), modes along
    ``mode`` (see the module's docstring and :data:`COMMENT`)."""
    import xarray as xr

    from pframe.assemble import assemble

    ex = loaded.expanded
    plan = assemble(ex)
    axes = ("x",) if plan.planar else ("x", "y")
    chosen = analyses(plan, ex, member)
    if not chosen:
        raise InputError(f"{loaded.source}: no building has storeys or links, so it has no "
                         "modes")
    solved = [solve(plan, ex, a, member, count, axes) for a in chosen]
    used = [s for i, s in enumerate(SHARES)
            if any(np.any(x.shares[:, i] > 0.0) for x in solved)]
    modes = max(len(s.omega) for s in solved)
    if count is not None:
        modes = min(modes, count)
    A = len(chosen)

    period = np.full((A, modes), np.nan)
    fields = {name: np.full((A, modes), np.nan) for name in ("damping", "dashpots")}
    gamma = np.full((A, modes, len(axes)), np.nan)
    share = np.full((A, modes, len(used)), np.nan)
    shape = np.full((A, modes, plan.n_dof), np.nan)
    direction = np.full((A, modes), "", dtype=object)
    total = np.zeros((A, len(axes)))
    for a, (an, s) in enumerate(zip(chosen, solved)):
        k = min(len(s.omega), modes)
        with np.errstate(divide="ignore"):
            period[a, :k] = np.where(s.omega[:k] > 0.0, 2.0 * math.pi / s.omega[:k], np.inf)
        fields["damping"][a, :k] = s.damping[:k]
        fields["dashpots"][a, :k] = s.dashpots[:k]
        gamma[a, :k] = s.participation[:k]
        share[a, :k] = s.shares[:k][:, [SHARES.index(u) for u in used]]
        shape[a, :k][:, an.dofs] = s.shapes[:, :k].T
        direction[a, :k] = s.direction[:k]
        total[a] = s.total_mass
    effective = gamma ** 2
    with np.errstate(invalid="ignore", divide="ignore"):
        ratio = effective / total[:, None, :]
    cumulative = np.cumsum(np.nan_to_num(ratio), axis=1)
    cumulative[np.isnan(ratio)] = np.nan
    dims, dir3 = ("analysis", "mode"), ("analysis", "mode", "direction")
    ds = xr.Dataset(
        {
            "period": (dims, period, {"units": "s", "long_name": "natural period (inf: a "
                                      "mode of no stiffness, a block sliding)"}),
            "frequency": (dims, 1.0 / period, {"units": "Hz", "long_name":
                                             "natural frequency"}),
            "mode_direction": (dims, direction.astype(str), {"long_name": "the direction the mode "
                          "mostly moves in (as damping's modes: [x1, torsion1] count them)"}),
            "share": (("analysis", "mode", "component"), share, {
                "units": "1", "long_name": "share of the mode's kinetic energy on each "
                "component"}),
            "participation_factor": (dir3, gamma, {"units": "kg^0.5", "long_name":
                                     "modal participation factor phi^T M iota"}),
            "effective_mass": (dir3, effective, {"units": "kg", "long_name":
                               "effective modal mass (phi^T M iota)^2"}),
            "effective_mass_ratio": (dir3, ratio, {"units": "1", "long_name":
                                     "effective modal mass over the total mass"}),
            "cumulative_mass_ratio": (dir3, cumulative, {"units": "1", "long_name":
                                      "effective modal mass of this mode and the lower ones "
                                      "over the total mass"}),
            "total_mass": (("analysis", "direction"), total, {
                "units": "kg", "long_name": "mass the ground's rigid motion along the "
                "direction moves (iota^T M iota)"}),
            "damping_ratio": (dims, fields["damping"], {
                "units": "1", "long_name": "damping ratio of the scene's damping (Rayleigh or "
                "modal)"}),
            "damping_ratio_with_dashpots": (dims, fields["dashpots"], {
                "units": "1", "long_name": "damping ratio with the elements' dashpots too "
                "(links, soil, viscous storeys; diagonal of Phi^T C Phi)"}),
            "shape": (("analysis", "mode", "dof"), shape, {
                "units": "kg^-0.5", "long_name": "mode shape normalised on the masses (NaN: a "
                "DOF the analysis holds or does not have)"}),
        },
        coords={
            "analysis": [f"{a.system}: {a.case}" for a in chosen],
            "mode": np.arange(1, modes + 1),
            "direction": list(axes),
            "component": used,
            "dof": _dof_labels(plan, ex),
            "system": ("analysis", [a.system for a in chosen]),
            "case": ("analysis", [a.case for a in chosen]),
            "stiffness": ("analysis", [a.text for a in chosen]),
        },
        attrs={"title": ex_title(loaded), "source": str(loaded.source), "comment": COMMENT,
               "damping": "\n".join(plan.damping_text)},
    )
    if isinstance(loaded.given, dict) and "pi" in loaded.given:
        ds.attrs["units_note"] = PI_NOTE
    return ds


#: what the numbers of a scene in Pi numbers are (as pframe validate shows them)
PI_NOTE = ("a scene in Pi numbers: its masses, times and frequencies are its dimensionless "
           "numbers (masses over m_b, times over 1 / w_p), not the kg, s and Hz the units say")


def ex_title(loaded) -> str:
    return str(getattr(loaded.scene, "title", "") or "")


def modes(scene, *, count: int | None = None, base_dir=None):
    """The modes of a scene (anything :func:`pframe.load` takes) as an xarray Dataset:
    periods, directions, participation factors, effective modal masses and damping ratios of
    each building on a fixed base, on its soil and isolated, and of the scene its links
    couple (docs/modes.md). ``count``: at most this many modes per analysis."""
    from pframe.api import count_argument, loaded_scene

    count = count_argument(count, "count", "pframe.modes")
    return dataset(loaded_scene(scene, base_dir), count=count)


def _cell(value: float, scale: float = 1.0, digits: str = "#.4g") -> str:
    if value != value:
        return "-"
    if math.isinf(value):
        return "inf"
    return format(value * scale, digits)


def table_lines(ds, shown: int) -> list[str]:
    """The modes of :func:`dataset` as text tables, one per analysis, its first ``shown``
    modes (``pframe modes``)."""
    axes = [str(d) for d in ds.direction.values]
    components = [str(c) for c in ds.component.values]
    head = (["mode", "T (s)", "f (Hz)", "direction"] + [f"{c} %" for c in components]
            + [h for d in axes for h in (f"Gamma_{d}", f"M*_{d} (kg)", f"M*_{d} %",
                                         f"sum {d} %")]
            + ["xi %", "xi+dashpots %"])
    out = [f"{ds.attrs['source']}: modes normalised on the masses; Gamma = phi^T M iota "
           "(kg^0.5), M* = Gamma^2, share: of the mode's kinetic energy; xi of the scene's "
           "damping, and with the elements' dashpots too (docs/modes.md)"]
    if ds.attrs.get("units_note"):
        out.append(f"note: {ds.attrs['units_note']}")
    for a in range(ds.sizes["analysis"]):
        period = ds.period.values[a]
        count = int(np.sum(~np.isnan(period)))
        rows = []
        for m in range(min(count, shown)):
            row = [str(m + 1), _cell(period[m]), _cell(ds.frequency.values[a, m]),
                   str(ds.mode_direction.values[a, m])]
            row += [_cell(ds.share.values[a, m, c], 100, ".1f") for c in range(len(components))]
            for d in range(len(axes)):
                # round-off of a mode that does not move along d: shown as 0, not 1e-13
                gamma = ds.participation_factor.values[a, m, d]
                if abs(gamma) < 1e-9 * math.sqrt(ds.total_mass.values[a, d]):
                    gamma = 0.0
                row += [_cell(gamma),
                        _cell(gamma ** 2),
                        _cell(ds.effective_mass_ratio.values[a, m, d], 100, ".1f"),
                        _cell(ds.cumulative_mass_ratio.values[a, m, d], 100, ".1f")]
            row += [_cell(ds.damping_ratio.values[a, m], 100, ".3g"),
                    _cell(ds.damping_ratio_with_dashpots.values[a, m], 100, ".3g")]
            rows.append(row)
        widths = [max(len(r[i]) for r in [head] + rows) for i in range(len(head))]
        totals = ", ".join(f"{d} {ds.total_mass.values[a, i]:.4g} kg"
                           for i, d in enumerate(axes))
        system = str(ds.system.values[a])
        who = "the coupled scene" if system == "scene" else f"building {system}"
        out += ["", f"{who}, {ds.stiffness.values[a]}", f"  total mass {totals}; "
                f"{count} mode{'s' if count != 1 else ''}"]
        out += ["  " + "  ".join(c.rjust(w) for c, w in zip(r, widths)) for r in [head] + rows]
        if count > shown:
            last = [f"{d} {100 * ds.cumulative_mass_ratio.values[a, shown - 1, i]:.1f} %"
                    for i, d in enumerate(axes)]
            out.append(f"  ... {count - shown} more (--count {count} shows them); the modes "
                       f"shown carry {', '.join(last)} of the mass")
    if ds.attrs.get("damping"):
        out += ["", "damping:"] + [f"  {line}" for line in ds.attrs["damping"].splitlines()]
    return out
