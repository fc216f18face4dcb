"""The no-contact runs of a gap audit: one batch of the compiled kernel over records x levels.

Each variant is the scene without its contacts under one record scaled to one level. The
kernel records the floor displacements of every step; a sink keeps, per contact level, the
running maximum of u_left - u_right (the gap the two floors need) and nothing else, so memory
stays bounded whatever the number of steps and variants.
"""

from __future__ import annotations

import dataclasses
import math

import numpy as np

from pframe.errors import InputError
from pframe.model.scene import Envelope, History

#: free vibration after the longest record, in the longest first period of the buildings
TAIL_PERIODS = 3.0


@dataclasses.dataclass(frozen=True)
class Pairs:
    """The contact levels of a scene: names, node names, DOF-order independent node indices.

    ``sides``: each contact's two sides as terms ((node, component, coefficient), ...) of the
    scene's degrees of freedom (pframe.model.elements): the displacement of the point of each
    side along the contact's normal, a = (n_x, n_y, (P - c) x n) (docs/plan.md); a planar
    contact's side is its node's u_x. The contact closes by side 0 less side 1."""

    names: tuple[str, ...]
    left: tuple[str, ...]
    right: tuple[str, ...]
    gaps: np.ndarray  # the scene's gaps (m)
    sides: tuple = ()
    #: each contact's ground displacements' part across supports (docs/supports.md):
    #: ((support name, axis, coefficient), ...); () on one support
    grounds: tuple = ()


def contact_pairs(loaded) -> Pairs:
    ex = loaded.expanded
    if not ex.contacts:
        raise InputError(f"{loaded.source}: the scene has no contacts; a gap audit needs the "
                         "levels where the buildings may touch (contacts: [...])")
    walls = [c.name for c in ex.contacts if min(c.nodes) < 0]
    if walls:
        raise InputError(f"{loaded.source}: contact{'s' if len(walls) > 1 else ''} "
                         f"{', '.join(walls)} stand{'' if len(walls) > 1 else 's'} against a "
                         "wall (the ground); the gap audit sets separations between "
                         "buildings and does not audit walls yet: audit a scene without them, "
                         "or run a sweep over the wall's gap (docs/sweeps.md)")
    return Pairs(tuple(c.name for c in ex.contacts),
                 tuple(ex.node_names[c.nodes[0]] for c in ex.contacts),
                 tuple(ex.node_names[c.nodes[1]] for c in ex.contacts),
                 np.array([c.gap for c in ex.contacts]),
                 tuple(c.side_terms() for c in ex.contacts),
                 _pair_grounds(ex))


def _pair_grounds(ex) -> tuple:
    """Each contact's ground terms along both of the site's axes (the runs may load y where
    the scene does not), by support name."""
    from pframe.model.plan import COMPONENTS
    from pframe.model.supports import ground_terms

    if not ex.node_support:
        return ()
    return tuple(tuple((ex.supports[s], COMPONENTS[c], a) for s, c, a in
                       ground_terms(contact, ex.node_support, None, ("x", "y"),
                                    first_positive=True))
                 for contact in ex.contacts)


def for_runs(loaded, channels: tuple[str, ...] = ("x",), contacts: bool = False):
    """The scene's Expanded form to run under other ground motions (``Expanded.with_ground``)
    along the site's axes ``channels``: without its contacts (or with them, ``contacts``),
    and without its own excitation. With 'y' among the channels, a scene is expanded under a
    motion in two components (zero until replaced), so that it moves the degrees of freedom
    the y axis loads; a scene whose storeys cannot resist motion along y is refused."""
    from pframe.model.expand import expand
    from pframe.model.load import ModelError
    from pframe.model.scene import Components, Sine

    zero = Components(x=Sine(amplitude=0.0, frequency=1.0)) if "y" in channels else None
    update = {"excitation": zero}
    if loaded.scene.supports:
        update.update(_at_supports(loaded, zero))
    elif contacts and ("y" not in channels or "y" in loaded.expanded.axes):
        return loaded.expanded
    if not contacts:
        update["contacts"] = []
    try:
        return expand(loaded.scene.model_copy(update=update), loaded.base_dir)
    except ModelError as exc:
        why = ""
        if "y" in channels and "y" not in loaded.expanded.axes:
            why = (" (the runs' ground motions move the site's y axis: pairs of records or "
                   "records at an angle, which a scene along x alone cannot take)")
        raise InputError(f"{loaded.where(exc.path)}: {exc.message}{why}") from None


def _at_supports(loaded, motion) -> dict:
    """The scene's changes to run it on its supports under a suite's motions
    (docs/supports.md): a wave passage keeps its delays (a motion given along the site's
    axes alone reaches each support with its delay, :meth:`Expanded.with_ground`); any other
    scene stands under the same zero motion at every support, its supports' own motions
    left out, each member replacing every support's motion (:meth:`Expanded.with_supports`,
    pframe.gap.members)."""
    from pframe.model.scene import Sine, WavePassage

    scene = loaded.scene
    motion = motion or Sine(amplitude=0.0, frequency=1.0)
    passage = scene.excitation
    if passage is not None and passage.kind == "wave_passage":
        return {"excitation": WavePassage(motion=motion, velocity=passage.velocity,
                                          direction=passage.direction)}
    return {"excitation": motion,
            "supports": [s.model_copy(update={"excitation": None}) for s in scene.supports]}


def axes_of(accelerations, axes=None) -> tuple[str, ...]:
    """The site's axes the runs load: ``axes`` when the caller knows them (rows at each of
    a scene's supports, pframe.gap.members), else those of ``accelerations``' rows (B, C,
    steps + 1), along x (and y)."""
    return tuple(axes) if axes is not None else ("x", "y")[:on_channels(accelerations).shape[1]]


def first_modes(plan, member: int = 0) -> tuple[np.ndarray, np.ndarray]:
    """First period (s) and its damping ratio of each building of a plan: the eigen-analysis
    of the building's masses and storeys (each at its stiffness in the isolated modes: an
    isolator at its post-yield or sliding stiffness, any other storey at its initial one;
    docs/theory.md#damping), and the ratio the plan's damping gives that mode,
    xi_1 = phi^T C phi / (2 w_1) with phi normalised on the masses (Rayleigh's
    a0 / (2 w_1) + a1 w_1 / 2 when every storey takes the stiffness term). A building on soil
    (docs/soil.md) is analysed with its foundation's sway and rocking DOFs and springs: its
    flexible-base period (Veletsos & Meek lengthening), with the ratio of its storeys'
    damping (the soil's dashpots left out); a building in plan with its floors' three DOFs
    (its first lateral-torsional mode). A storey under P-delta is at k0 - P / h, the
    stiffness the runs integrate at rest. Springs between buildings (links) are left out."""
    from pframe.assemble.incidence import incidence

    owner = np.full(plan.n_dof, -1)
    nodes = plan.dof_node if plan.dof_node is not None else np.full(plan.n_dof, -1)
    if plan.dof_node is None:
        nodes[plan.node_dof] = np.arange(len(plan.node_names))
    building_of_node = [plan.buildings.index(n.split("/")[0]) for n in plan.node_names]
    owner[nodes >= 0] = np.array(building_of_node, dtype=int)[nodes[nodes >= 0]] \
        if len(building_of_node) else []
    for building, dofs in zip(plan.foundations, plan.foundation_dofs
                              if plan.foundations else ()):
        owner[dofs] = plan.buildings.index(building)
    stiffness = plan.story_isolated if plan.story_isolated is not None else plan.story_k0
    if plan.story_kg is not None and np.any(plan.story_kg):
        # the storeys at rest as the runs integrate them: k0 less P-delta's P / h, as
        # pframe validate and pframe modes give the periods
        stiffness = stiffness - plan.story_kg
    G = incidence(plan.story_dofs, plan.story_sides, member, plan.n_dof).tocsr()
    damping = _damping_matrix(plan, member, G)
    periods, ratios = [], []
    for b in range(len(plan.buildings)):
        dofs = np.flatnonzero(owner == b)
        k = np.zeros((dofs.size, dofs.size))
        for s in range(plan.n_springs):
            row = G.getrow(s)
            if row.nnz == 0 or np.any(owner[row.indices] != b):
                continue  # a link to another building, or a spring of another building
            g = np.zeros(plan.n_dof)
            g[row.indices] = row.data
            g = g[dofs]
            k += stiffness[member, s] * np.outer(g, g)
        scale = 1.0 / np.sqrt(plan.mass[member, dofs])
        w2, shapes = np.linalg.eigh(k * np.outer(scale, scale))
        w1 = math.sqrt(max(w2[0], 0.0))
        phi = shapes[:, 0] * scale
        c = float(phi @ damping[np.ix_(dofs, dofs)] @ phi)
        periods.append(2.0 * math.pi / w1 if w1 > 0 else math.inf)
        ratios.append(c / (2.0 * w1) if w1 > 0 else math.nan)
    return np.array(periods), np.array(ratios)


def _damping_matrix(plan, member: int, G) -> np.ndarray:
    """The plan's damping matrix C (n x n, N s/m) of its storeys and masses: a0 m on the
    diagonal, a1 k_0 g g^T of each storey with the stiffness term (g its row of the
    deformations G), the modal blocks (the soil's dashpots and the links' left out)."""
    n, ns = plan.n_dof, len(plan.story_names)
    out = np.diag(np.asarray(plan.mass_damping[member], dtype=float))
    for s in np.flatnonzero(plan.story_beta[member, :ns]):
        row = G.getrow(s)
        g = np.zeros(n)
        g[row.indices] = row.data
        out += plan.story_beta[member, s] * plan.story_k0[member, s] * np.outer(g, g)
    return out + plan.modal_damping(member)


def base_plan(loaded, channels: tuple[str, ...] = ("x",)):
    """A one-member plan of the scene without contacts (for its periods and damping)."""
    from pframe.assemble import assemble

    ex = for_runs(loaded, channels)
    ex = ex.first_steps(1, recorders=())
    return assemble(ex)


def on_channels(accelerations: np.ndarray) -> np.ndarray:
    """(B, C, steps + 1) from ground motions given along x alone (B, steps + 1) or along
    the channels already."""
    accelerations = np.asarray(accelerations, dtype=float)
    return accelerations[:, None, :] if accelerations.ndim == 2 else accelerations


def under(base, accelerations) -> list:
    """``base`` (an Expanded scene) under each ground motion of ``accelerations`` (B, C,
    steps + 1) or (B, steps + 1): along its x axis, and its y axis when C is 2; on several
    supports, C a row per channel (support and axis) replaces every support's motion."""
    several = base.support_samples is not None
    return [base.with_supports(a) if several and len(a) == len(base.channels)
            and len(base.channels) > len(base.axes)
            else base.with_ground(a[0], a[1] if len(a) > 1 else None)
            for a in on_channels(accelerations)]


def batch_plan(loaded, accelerations: np.ndarray, steps: int, contacts_gaps=None,
               dt: float | None = None, axes=None):
    """The batch plan: one member per motion of ``accelerations`` ((B, steps + 1) along x, or
    (B, C, steps + 1) along the site's x and y) on the scene's time step; without contacts,
    or (for checks) with the scene's contacts at ``contacts_gaps`` (B, c); ``dt`` (s)
    replaces the scene's step; ``axes``: see :func:`axes_of`."""
    from pframe.assemble import assemble_batch

    channels = axes_of(accelerations, axes)
    if contacts_gaps is None:
        ex = for_runs(loaded, channels)
        recorders = (Envelope(kind="envelope", quantities=["displacement"]),
                     History(kind="history", quantities=["displacement"]))
    else:
        ex = for_runs(loaded, channels, contacts=True)
        recorders = (Envelope(kind="envelope", quantities=["displacement"]),)
    base = dataclasses.replace(ex, steps=int(steps), recorders=recorders,
                               dt=float(dt if dt is not None else ex.dt))
    variants = under(base, accelerations)
    if contacts_gaps is not None:
        variants = [dataclasses.replace(member, contacts=tuple(
            dataclasses.replace(c, gap=float(g)) for c, g in zip(ex.contacts, contacts_gaps[b])))
            for b, member in enumerate(variants)]
    return assemble_batch(variants)


def _contact_grounds(plan, members):
    """(B, c, steps + 1) the ground displacements' part of each contact's closing at every
    step (docs/supports.md: the contacts of ``members``, each a :class:`Pairs`, in a run of
    ``plan``), or None on one ground."""
    if plan.ground_motion is None or not any(m.grounds for m in members):
        return None
    out = np.zeros((plan.batch, len(members[0].names), plan.steps + 1))
    for b, pairs in enumerate(members):
        for c, terms in enumerate(pairs.grounds):
            for support, axis, a in terms:
                name = f"{support}:{axis}"
                if name in plan.channels:  # an axis the runs do not load does not move
                    series = plan.ground_motion[b, plan.channels.index(name)]
                    out[b, c] += a * series[:plan.steps + 1]
    return out


class GapSink:
    """Running max over the steps (from row ``start`` on) of the closing of each contact:
    its first side less its second (:class:`Pairs`), u_left - u_right of a planar contact,
    the closing of its two points along its normal in plan; and the running peak of each
    side's displacement, |a . u| (the displacement of the contact's point along its normal,
    ``peak_side``), where a side is not its node's u_x (a planar contact's peaks are the
    kernel's envelope of the displacement).

    A side's term on a degree of freedom the runs do not move (a rotation only the contact
    would cause) is left out: that DOF stays at rest. ``pairs``: the contacts of the scene,
    or of each batch member (a list, one per member: members whose geometry differs, the
    uncertain values of a risk study), their terms' union taken with a coefficient 0 where a
    member has none."""

    def __init__(self, plan, pairs, start: int = 0):
        from pframe.assemble.incidence import merged

        members = list(pairs) if isinstance(pairs, (list, tuple)) else [pairs] * plan.batch
        where = {(int(n), int(c)): d for d, (n, c) in enumerate(zip(plan.dof_node,
                                                                    plan.dof_component))}
        self.terms = []  # per contact, per side: [(DOF, coefficients (B,)), ...]
        for c in range(len(members[0].names)):
            sides = []
            for s in range(2):
                own = [{(n, k): a for n, k, a in m.sides[c][s] if (n, k) in where}
                       for m in members]
                sides.append([(where[key], np.array([mine.get(key, 0.0) for mine in own]))
                              for key in merged(list(mine) for mine in own)])
            self.terms.append(sides)
        self.start = int(start)
        self.ground = _contact_grounds(plan, members)
        self.gap = np.full((plan.batch, len(members[0].names)), -np.inf)
        self.peak_side = np.zeros((plan.batch, len(members[0].names), 2))
        # the sides whose peak is the kernel's envelope (peaks): no running peak of their own
        self.tracked = [[s for s in range(2) if self.plain(c, s) is None]
                        for c in range(len(self.terms))]

    def plain(self, c: int, s: int) -> int | None:
        """The DOF of side ``s`` of contact ``c`` when that side is its node's u_x alone."""
        terms = self.terms[c][s]
        return (terms[0][0] if len(terms) == 1 and np.all(terms[0][1] == 1.0) else None)

    def closing_dofs(self) -> np.ndarray | None:
        """(c, 2) each contact's left and right DOF where every contact closes by one DOF's
        u less another's (each side its node's u_x alone, on one ground, from the first
        step): the kernel can keep the running maxima itself (:meth:`run`); else None."""
        pairs = [[self.plain(c, s) for s in range(2)] for c in range(len(self.terms))]
        if self.start or self.ground is not None or any(None in pair for pair in pairs):
            return None
        return np.array(pairs, dtype=np.int64).reshape(-1, 2)

    def run(self, plan, **options):
        """``simulate(plan, **options)`` into this sink. Where :meth:`closing_dofs` allows,
        the kernel keeps each contact's running maximum (simulate's ``closing``: the same
        subtraction of the same doubles and the same maximum) and the displacements' history,
        recorded for this sink alone, is neither recorded nor streamed (about a quarter of
        the kernel's time on the risk study's runs without contacts, and the sink's own).
        A member that fails keeps the maximum over the steps it completed."""
        from pframe.kernel import simulate

        dofs = self.closing_dofs()
        if dofs is None:
            return simulate(plan, sink=self, **options)
        plan = dataclasses.replace(plan, history=tuple(
            (q, every) for q, every in plan.history if q != "displacement"))
        result = simulate(plan, sink=self if plan.history else None, closing=dofs, **options)
        np.fmax(self.gap, result.closing, out=self.gap)
        return result

    @staticmethod
    def _side(rows, terms):
        out = None
        for dof, a in terms:
            part = rows[:, :, dof] if np.all(a == 1.0) else a[:, None] * rows[:, :, dof]
            out = part if out is None else out + part
        return np.zeros(rows.shape[:2]) if out is None else out

    def __call__(self, quantity, first_row, rows):
        skip = max(0, self.start - first_row)
        if quantity != "displacement" or rows.shape[1] <= skip:
            return
        rows = rows[:, skip:]
        steps = slice(first_row + skip, first_row + skip + rows.shape[1])
        for c, (left, right) in enumerate(self.terms):
            sides = self._side(rows, left), self._side(rows, right)
            closing = sides[0] - sides[1]
            if self.ground is not None:  # across supports: the ground displacements' part
                closing = closing + self.ground[:, c, steps]
            # a member that failed inside these rows has NaN after the failure: fmax keeps
            # what came before (its results are discarded anyway)
            block = np.max(closing, axis=1)
            np.fmax(self.gap[:, c], block, out=self.gap[:, c])
            for s in self.tracked[c]:
                np.fmax(self.peak_side[:, c, s], np.max(np.abs(sides[s]), axis=1),
                        out=self.peak_side[:, c, s])

    def peaks(self, envelope: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """(B, C) each contact's peak |u| of its left and of its right side: the kernel's
        ``envelope`` of the displacement (B, n_dof) where a side is its node's u_x, the
        running peak along the normal otherwise."""
        out = self.peak_side.copy()
        for c in range(len(self.terms)):
            for s in range(2):
                dof = self.plain(c, s)
                if dof is not None:
                    out[:, c, s] = envelope[:, dof]
        return out[:, :, 0], out[:, :, 1]


def run_batch(loaded, pairs: Pairs, accelerations: np.ndarray, steps: int, dt: float,
              threads: int | None = None, progress=None, axes=None) -> dict[str, np.ndarray]:
    """Run the no-contact batch; per member: peak |u| of the left and right floor of each
    contact level, g_req = max_t (u_left - u_right) (not clipped), and the run's status;
    ``axes``: see :func:`axes_of`."""
    plan = batch_plan(loaded, accelerations, steps, dt=dt, axes=axes)
    sink = GapSink(plan, pairs)
    result = sink.run(plan, threads=threads, progress=(lambda done, total: progress(done, total))
                      if progress else None)
    left, right = sink.peaks(result.envelope["displacement"])
    complete = np.array([result.completed(b) for b in range(plan.batch)], dtype=np.int8)
    status = np.array([result.describe_failure(b) for b in range(plan.batch)], dtype=str)
    return {"peak_left": left, "peak_right": right,
            "g_req": sink.gap, "complete": complete, "status": status,
            "solve_seconds": np.float64(result.solve_seconds)}
