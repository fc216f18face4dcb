"""The first-order system y = [u, v] of one batch member, with the laws' regimes.

Equation of motion (``docs/theory.md``), node columns in DOF order as in the plan::

    m a = -m a_g - a0 m v - G_s^T (f_s + a1 k0 d') - G_c^T P

with storey drifts d = G_s u (G_s: +1 upper node, -1 lower node), contact penetrations
delta = G_c u - gap (G_c: +1 left node, -1 right node), f_s and P from the laws' ``force``
at their committed states. Assembly is vectorised: incidence matrices for the gathers and
scatters, one compiled loop per law group for the forces.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from pframe.assemble.incidence import incidence
from pframe.errors import InputError
from pframe.kernel.state import DampingStiffness
from pframe.reference.branches import branches_for
from pframe.reference.evaluate import LawElements

#: rounding error of an event function, relative to the magnitudes it is computed from
ROUNDOFF = 1e3 * np.finfo(float).eps


def _selector(index: np.ndarray):
    """A slice when the indices are consecutive (cheaper than fancy indexing)."""
    if len(index) and np.array_equal(index, np.arange(index[0], index[0] + len(index))):
        return slice(int(index[0]), int(index[0]) + len(index))
    return index


@dataclass
class Group:
    """One law's elements with their regime description and current regimes."""

    elements: LawElements
    branches: object
    regime: np.ndarray  # (g,) int
    offset: int  # position of the group's event functions in the flat event vector

    @property
    def index(self) -> np.ndarray:
        return self.elements.index


@dataclass
class State:
    """Everything derived from (t, u, v) at one time or at many (leading axis = samples)."""

    u: np.ndarray
    v: np.ndarray
    ground: np.ndarray
    drift: np.ndarray
    drift_rate: np.ndarray
    story_force: np.ndarray
    story_tangent: np.ndarray
    story_rate_tangent: np.ndarray
    penetration: np.ndarray
    penetration_rate: np.ndarray
    contact_force: np.ndarray
    contact_tangent: np.ndarray
    contact_rate_tangent: np.ndarray
    acceleration: np.ndarray


class System:
    """The equations of motion of batch member ``member`` of ``plan``."""

    def __init__(self, plan, member: int, ground, jit: bool = True):
        if np.any(plan.story_damping_stiffness != DampingStiffness.INITIAL):
            raise InputError(
                "the reference solution supports Rayleigh damping on the initial stiffness "
                "only (damping.stiffness: initial); 'current' and 'committed' tie the damping "
                "to the tangent of the time-stepping scheme")
        if plan.contact_share is not None and np.any(plan.contact_share != 1.0):
            raise InputError("the reference solution does not model floor-to-column contacts "
                             "yet (their force is shared between two floors)")
        if len(plan.channels) > 1:
            raise InputError("the reference solution takes a ground motion along one axis; "
                             "this scene's has two components")
        self.plan = plan
        self.member = member
        self.ground = ground
        n = plan.n_dof
        self.n = n
        self.mass = np.array(plan.mass[member], dtype=float)
        self.mass_damping = np.array(plan.mass_damping[member], dtype=float) / self.mass
        # d = G u of every element (pframe.assemble.incidence): a storey on soil deforms less
        # h theta, a line in plan by its sides' weights; the ground load acts on the DOFs of
        # its channel only (not a rotation, nor a foundation's rocking)
        self.story_incidence = incidence(plan.story_dofs, plan.story_sides, member,
                                         n).toarray()
        self.influence = (np.ones(n) if plan.dof_channel is None
                          else (plan.dof_channel >= 0).astype(float))
        self.contact_incidence = incidence(plan.contact_dofs, plan.contact_sides, member, n,
                                           contact=True).toarray()
        self.story_damping = np.array(plan.story_beta[member] * plan.story_k0[member])
        # modal damping (docs/theory.md#damping): the dense blocks over one n x n, scaled by 1/m
        self.modal = None
        if plan.modal_start is not None and len(plan.modal_start) > 1:
            self.modal = plan.modal_damping(member) / self.mass[:, None]
        self.gap = np.array(plan.contact_gap[member], dtype=float)
        self.n_story = plan.n_springs  # the storeys, then the links
        self.n_contact = len(plan.contact_names)
        self.story_groups = self._groups(plan.story_groups, jit, 0)
        offset = sum(g.branches.n_events * len(g.elements) for g in self.story_groups)
        self.contact_groups = self._groups(plan.contact_groups, jit, offset)
        self.n_events = offset + sum(g.branches.n_events * len(g.elements)
                                     for g in self.contact_groups)
        # scatter matrices scaled by 1/m: the force terms of the acceleration
        self._story_scatter = np.ascontiguousarray(self.story_incidence.T / self.mass[:, None])
        self._contact_scatter = np.ascontiguousarray(self.contact_incidence.T
                                                     / self.mass[:, None])
        self._story_gather = np.ascontiguousarray(self.story_incidence)
        self._contact_gather = np.ascontiguousarray(self.contact_incidence)
        self._story_calls = [(_selector(g.index), g.elements.force_only)
                             for g in self.story_groups]
        self._contact_calls = [(_selector(g.index), g.elements.force_only)
                               for g in self.contact_groups]
        self.event_owner = self._event_owners()
        self._event_element = np.array(
            [(0 if kind == "story" else self.n_story) + int(self.group(kind, gi).index[j])
             for kind, gi, j, _ in self.event_owner], dtype=np.int64)
        self._a = np.zeros(self.n_events)
        self._b = np.zeros(self.n_events)
        self._c = np.ones(self.n_events)
        #: added to the event functions of a segment: the rounding margin of its start
        self.shift = np.zeros(self.n_events)
        self.refresh_events()

    def _groups(self, groups, jit, offset):
        out = []
        for g in groups:
            elements = LawElements(g.law, g.index, g.params[self.member], g.state[self.member],
                                   jit=jit)
            branches = branches_for(g.law)
            out.append(Group(elements, branches, branches.initial(len(elements)), offset))
            offset += branches.n_events * len(elements)
        return out

    def _event_owners(self):
        """(kind, group, element in group, event) of each entry of the flat event vector,
        which runs group by group, element by element."""
        return [(kind, gi, j, k)
                for kind, groups in (("story", self.story_groups),
                                     ("contact", self.contact_groups))
                for gi, g in enumerate(groups)
                for j in range(len(g.elements))
                for k in range(g.branches.n_events)]

    # ------------------------------------------------------------------------------------
    # forces
    # ------------------------------------------------------------------------------------

    def _law_forces(self, groups, size, deformation, rate):
        lead = deformation.shape[:-1]
        out = np.zeros((3,) + lead + (size,))
        for g in groups:
            out[..., g.index] = g.elements.forces(deformation[..., g.index], rate[..., g.index])
        return out

    def evaluate(self, t, u, v) -> State:
        """Forces and accelerations at time(s) ``t``; u, v of shape (n,) or (K, n)."""
        ag = self.ground(t)
        drift = u @ self.story_incidence.T
        drift_rate = v @ self.story_incidence.T
        story = self._law_forces(self.story_groups, self.n_story, drift, drift_rate)
        penetration = u @ self.contact_incidence.T - self.gap
        penetration_rate = v @ self.contact_incidence.T
        contact = self._law_forces(self.contact_groups, self.n_contact, penetration,
                                   penetration_rate)
        shear = story[0] + self.story_damping * drift_rate
        acc = (-np.asarray(ag)[..., None] * self.influence - self.mass_damping * v
               - shear @ self._story_scatter.T - contact[0] @ self._contact_scatter.T)
        if self.modal is not None:
            acc = acc - v @ self.modal.T
        return State(u, v, ag, drift, drift_rate, story[0], story[1], story[2], penetration,
                     penetration_rate, contact[0], contact[1], contact[2], acc)

    def rhs(self, t, y):
        """dy/dt = [v, a]: the hot path of the integration, kept to a few numpy calls."""
        n = self.n
        u, v = y[:n], y[n:]
        drift = self._story_gather.dot(u)
        drift_rate = self._story_gather.dot(v)
        shear = self.story_damping * drift_rate
        for where, force in self._story_calls:
            shear[where] += force(drift[where], drift_rate[where])
        push = self._story_scatter.dot(shear)
        push += self.mass_damping * v
        if self.modal is not None:
            push += self.modal.dot(v)
        if self.n_contact:
            penetration = self._contact_gather.dot(u)
            penetration -= self.gap
            rate = self._contact_gather.dot(v)
            contact = np.empty(self.n_contact)
            for where, force in self._contact_calls:
                contact[where] = force(penetration[where], rate[where])
            push += self._contact_scatter.dot(contact)
        out = np.empty(2 * n)
        out[:n] = v
        np.negative(push, out=out[n:])
        out[n:] -= self.ground(t) * self.influence
        return out

    def jacobian(self, t, y):
        """d rhs / d y from the laws' tangents (for the implicit methods)."""
        n = self.n
        s = self.evaluate(t, y[:n], y[n:])
        gs, gc = self.story_incidence, self.contact_incidence
        ks = gs.T @ (s.story_tangent[:, None] * gs)
        cs = gs.T @ ((s.story_rate_tangent + self.story_damping)[:, None] * gs)
        kc = gc.T @ (s.contact_tangent[:, None] * gc)
        cc = gc.T @ (s.contact_rate_tangent[:, None] * gc)
        jac = np.zeros((2 * n, 2 * n))
        jac[:n, n:] = np.eye(n)
        jac[n:, :n] = -(ks + kc) / self.mass[:, None]
        jac[n:, n:] = -(cs + cc) / self.mass[:, None] - np.diag(self.mass_damping)
        if self.modal is not None:
            jac[n:, n:] -= self.modal
        return jac

    # ------------------------------------------------------------------------------------
    # regimes and events
    # ------------------------------------------------------------------------------------

    def groups(self):
        for kind, groups in (("story", self.story_groups), ("contact", self.contact_groups)):
            for g in groups:
                yield kind, g

    def refresh_events(self):
        """Recompute the event coefficients from the regimes and committed states (after a
        regime change; they are constant within a segment)."""
        for _, g in self.groups():
            size = g.branches.n_events * len(g.elements)
            if not size:
                continue
            a, b, c = g.branches.coefficients(g.regime, g.elements.params, g.elements.committed)
            where = slice(g.offset, g.offset + size)
            self._a[where], self._b[where], self._c[where] = (
                a.reshape(-1), b.reshape(-1), c.reshape(-1))

    def events(self, s: State, roundoff: bool = False):
        """Event functions g = A d + B r + C + shift (positive while the regimes hold) and
        their time derivatives A r + B r', as flat vectors, at one state; with
        ``roundoff``, also the rounding error of g (a few ulps of its largest term)."""
        deformation = np.concatenate((s.drift, s.penetration))[self._event_element]
        rate = np.concatenate((s.drift_rate, s.penetration_rate))[self._event_element]
        rate_of_rate = np.concatenate((self.story_incidence @ s.acceleration,
                                       self.contact_incidence @ s.acceleration))
        rate_of_rate = rate_of_rate[self._event_element]
        values = self._a * deformation + self._b * rate + self._c + self.shift
        rates = self._a * rate + self._b * rate_of_rate
        if not roundoff:
            return values, rates
        # a deformation is a difference of displacements (less the gap): its rounding error
        # scales with those, not with the (possibly tiny) difference
        u, v = np.abs(s.u), np.abs(s.v)
        size = np.concatenate((np.abs(self.story_incidence) @ u,
                               np.abs(self.contact_incidence) @ u + np.abs(self.gap)))
        size_rate = np.concatenate((np.abs(self.story_incidence) @ v,
                                    np.abs(self.contact_incidence) @ v))
        error = ROUNDOFF * (np.abs(self._a) * size[self._event_element]
                            + np.abs(self._b) * size_rate[self._event_element]
                            + np.abs(self._c))
        return values, rates, error

    def contact_closed(self) -> np.ndarray:
        """(c,) True where a contact's regime is closed."""
        out = np.zeros(self.n_contact, dtype=bool)
        for g in self.contact_groups:
            out[g.index] = g.branches.closed(g.regime)
        return out

    def contact_loaded(self) -> np.ndarray:
        """(c,) True where a contact is closed and its force acts (not released)."""
        out = np.zeros(self.n_contact, dtype=bool)
        for g in self.contact_groups:
            out[g.index] = g.branches.loaded(g.regime)
        return out

    def group(self, kind: str, gi: int) -> Group:
        return (self.story_groups if kind == "story" else self.contact_groups)[gi]
