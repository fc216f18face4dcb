"""A suite's members on the supports of a scene (docs/supports.md#suites-of-a-motion-per-support).

A gap audit or risk study runs a scene under each member of a suite. On one ground a member
is one motion. On several supports every support needs one, and a member gives them in one
of three ways:

- **one motion**, which reaches the supports as the scene's excitation says: a wave passage
  delays it to each support (tau_s, :func:`pframe.model.support_motion.delays`); the same
  motion under every support otherwise (a scene whose supports have motions of their own
  takes none: which would it replace?);
- **a record per support** (a suite entry ``{supports: {west: a.AT2, east: b.AT2}}``);
- **a coherent simulation** of the scene (``excitation: {kind: coherent}``): a member's
  record conditions it at the support ``at`` (Konakli & Der Kiureghian 2012), or the suite's
  ``coherent: {realisations: N}`` simulates it unconditioned; member i (its place in the
  suite, from 0) is seeded ``seed + i``, so each member is the scene run alone with that
  record and that seed.

The latter two are resolved here, once, into a motion per support; a member's intensity is
that of its **reference support**: the first support a record-per-support entry names, the
support ``at`` of a conditioned simulation (its record as applied), the scene's first support
of an unconditioned one. Scaled to a level, every support's motion takes the member's one
factor (the relative motions scale with the motions: the conditioned simulation is linear
in its record, its mean a filter of it and its residual's spectrum the record's).
"""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass

import numpy as np

from pframe.errors import InputError
from pframe.excitation.suite import GroundMotion, Suite


@dataclass(frozen=True)
class OnSupports:
    """How the members reach the scene's supports ``names`` along the site's ``axes``: each
    member's rows are its supports' motions (a member of one motion: delayed by ``delays``,
    s, each support's; zeros for the same motion under every support)."""

    names: tuple[str, ...]
    axes: tuple[str, ...]
    delays: tuple[float, ...]

    def rows(self, motion: GroundMotion, times: np.ndarray) -> np.ndarray:
        """(supports x axes, len(times)) the member's motion at each support along each
        axis (m/s^2, support-major as the scene's channels are), on the even ``times``."""
        from pframe.model.support_motion import delayed

        if motion.at_supports:
            given = dict(motion.at_supports)
            return np.concatenate([given[name].on_site(times, self.axes)
                                   for name in self.names])
        site = motion.on_site(times, self.axes)
        dt = float(times[1] - times[0]) if len(times) > 1 else 1.0
        return np.array([delayed(row, tau, dt) for tau in self.delays for row in site])


def reference(motion: GroundMotion) -> str:
    """The support a member's intensity is measured at (see the module; a member of one
    motion has the same at every support)."""
    return motion.at_supports[0][0] if motion.at_supports else "every support"


def several(loaded) -> bool:
    """Whether the scene stands on several supports."""
    return bool(loaded.expanded.node_support)


def duration(loaded, motion: GroundMotion) -> float:
    """How long a member lasts before it is resolved (s): an unconditioned simulation, as
    long as its modulating function (or the motion's duration) says."""
    if not motion.coherent:
        return motion.duration
    from pframe.model.coherent import shared_spectrum

    return float(shared_spectrum(loaded.scene.excitation.motion, ("excitation", "motion"))[2])


def own_member(loaded, name: str) -> GroundMotion:
    """The scene's own motion at its supports, one member (an audit without a suite)."""
    ex = loaded.expanded
    times = np.arange(ex.steps + 1) * ex.dt
    count = len(ex.axes)
    parts = []
    for s, support in enumerate(ex.supports):
        rows = ex.support_samples[s * count:(s + 1) * count]
        x = rows[ex.axes.index("x")] if "x" in ex.axes else np.zeros(times.size)
        y = rows[ex.axes.index("y")] if "y" in ex.axes else None
        parts.append((support, GroundMotion(support, times, x, loaded.source, second=y,
                                            directed=True)))
    head = parts[0][1]
    return GroundMotion(name, times, head.acceleration, loaded.source, second=head.second,
                        directed=True, at_supports=tuple(parts))


def resolve(loaded, suite: Suite, axes: tuple[str, ...], steps: int, dt: float,
            own: bool = False):
    """(suite, :class:`OnSupports` or None on one ground, warnings): the members of
    ``suite`` resolved on the scene's supports (see the module), simulations made on the
    runs' ``steps`` of ``dt``. Refuses (InputError, at the member's place in the suite) a
    member the scene cannot take."""
    if not several(loaded):
        per = next((m for m in suite.motions if m.at_supports or m.coherent), None)
        if per is not None:
            raise InputError(f"{per.where or suite.source}: a motion per support, and the scene "
                             f"{loaded.source} stands on one ground (it declares no supports, "
                             "or one): give one record")
        return suite, None, ()
    ex, scene = loaded.expanded, loaded.scene
    kind = scene.excitation.kind if scene.excitation is not None else None
    delays = (tuple(ex.support_delays) if kind == "wave_passage"
              else (0.0,) * len(ex.supports))
    on = OnSupports(tuple(ex.supports), tuple(axes), delays)
    if own:
        return suite, on, ()
    motions, warnings = [], []
    for index, motion in enumerate(suite.motions):
        if motion.at_supports:
            _check_names(loaded, motion)
            motions.append(motion)
        elif motion.coherent or kind == "coherent":
            found, cut = _simulated(loaded, motion, index, steps, dt)
            motions.append(found)
            warnings += cut
        else:
            _check_one(loaded, motion, suite)
            motions.append(motion)
    return dataclasses.replace(suite, motions=tuple(motions)), on, tuple(warnings)


def _check_names(loaded, motion: GroundMotion) -> None:
    names = loaded.expanded.supports
    for support, part in motion.at_supports:
        if support not in names:
            raise InputError(f"{part.where or motion.where}: the scene {loaded.source} has no "
                             f"support {support!r}; its supports are {', '.join(names)}")
    missing = [s for s in names if s not in dict(motion.at_supports)]
    if missing:
        raise InputError(f"{motion.where}.supports: no motion for support"
                         f"{'s' if len(missing) > 1 else ''} {', '.join(missing)} of the scene "
                         f"{loaded.source}; a member with a record per support gives every "
                         f"support one ({', '.join(names)})")


def _check_one(loaded, motion: GroundMotion, suite: Suite) -> None:
    """One motion for a scene whose supports move with motions of their own: refused."""
    own = [s.name for s in loaded.scene.supports if s.excitation is not None]
    if own:
        raise InputError(
            f"{motion.where or suite.source}: {motion.name} is one motion, and the supports "
            f"{', '.join(own)} of the scene {loaded.source} have motions of their own: it "
            "could stand for any of them. Give each member a record per support, {supports: "
            "{" + ", ".join(f"{s}: FILE" for s in loaded.expanded.supports) + "}}, or the "
            "scene a wave passage (excitation: {kind: wave_passage, velocity: ..., motion: "
            "...}) that carries one motion to every support")


def _simulated(loaded, motion: GroundMotion, index: int, steps: int, dt: float):
    """A member's coherent simulation (a motion per support) and the warning when the runs
    stop before it ends."""
    from pframe.model.coherent import coherent_motions
    from pframe.model.load import ModelError
    from pframe.model.supports import Supports

    ex, excitation = loaded.expanded, loaded.scene.excitation
    where = motion.where or motion.name
    if excitation is None or excitation.kind != "coherent":
        raise InputError(f"{where}: coherent simulations are of the scene's coherent motions, "
                         f"and the scene {loaded.source} has none (excitation: {{kind: "
                         "coherent, ...}})")
    if not motion.coherent and excitation.at is None:
        raise InputError(f"{where}: {motion.name} would condition the scene's coherent "
                         "simulation at the support it was recorded at, and the scene "
                         f"{loaded.source} names none: give its excitation record and at (the "
                         "suite's records stand for its record), or simulate without records "
                         "(the suite's coherent: {realisations: N})")
    if not motion.coherent and (motion.second is not None or motion.angle):
        raise InputError(f"{where}: {motion.name} is along a direction or a pair; a coherent "
                         "simulation is conditioned on one record along the site's x")
    times = np.arange(steps + 1) * dt
    supports = Supports(tuple(ex.supports), tuple(ex.node_support),
                        tuple(ex.support_positions), True)
    seed = int(excitation.seed) + index
    try:
        found = coherent_motions(loaded.scene, supports, loaded.base_dir, steps, dt,
                                 record=None if motion.coherent else motion.on_grid(times),
                                 seed=seed)
    except ModelError as exc:
        raise InputError(f"{loaded.where(exc.path)}: {exc.message}") from None
    reference = ex.supports.index(excitation.at) if not motion.coherent else 0
    parts = [(name, GroundMotion(name, times, row, "", where=where))
             for name, row in zip(ex.supports, found.acceleration)]
    parts = tuple([parts[reference]] + parts[:reference] + parts[reference + 1:])
    name = (f"coherent-seed{seed}" if motion.coherent
            else f"{motion.name}@{excitation.at}-seed{seed}")
    head = found.acceleration[reference]
    member = GroundMotion(name, times, head, motion.source, where=where, at_supports=parts)
    cut = ([] if found.lasts <= steps * dt + 0.5 * dt else
           [f"member {name}: the simulated motions last {found.lasts:.4g} s and the runs "
            f"{steps * dt:.4g} s: the rest is not applied; give a longer duration"])
    return member, cut
