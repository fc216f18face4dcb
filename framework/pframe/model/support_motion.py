"""The ground motion of every support of a scene (docs/supports.md), as the kernel takes it.

Each support moves with its own motion (``supports[].excitation``), or with the scene's:
the same motion under every support, or the wave passage's, a(t - tau_s) with
tau_s = (p_s - p_first) . e / v_app counted from the support the waves reach first. Its
displacement and velocity, where an element across supports needs them, are its acceleration
integrated by the trapezoid rule twice from rest, the relation Newmark's average
acceleration keeps between the three (v_{n+1} = v_n + h (a_n + a_{n+1}) / 2 and
d_{n+1} = d_n + h (v_n + v_{n+1}) / 2), so that a structure's motion relative to its
support plus that support's displacement is its total motion as an integration in total
coordinates gives it.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from pframe.model.load import ModelError
from pframe.model.motion import GroundMotion, ground_motion


# eq=False, repr=False: it holds numpy arrays: a generated __eq__ and __hash__ could only
# raise (== is elementwise), a __repr__ would print every array, and each generated
# function is compiled at every start
@dataclass(frozen=True, eq=False, repr=False)
class SupportMotion:
    """``samples`` channel name -> a_g at the steps (m/s^2): one channel per support and axis
    of the motion ('<support>:x', ...); ``axes`` the axes the motions load; ``delays`` each
    support's wave-passage delay (s; zeros without one); ``motions`` each support's
    :class:`GroundMotion`; ``warnings`` what to tell the run."""

    samples: dict
    axes: tuple[str, ...]
    delays: tuple[float, ...]
    motions: tuple[GroundMotion, ...]
    warnings: tuple[str, ...]
    #: what the run is told besides (a coherent simulation's notes) and how it was made
    notes: tuple[str, ...] = ()
    description: str = ""
    #: how each channel's displacement is had where not integrated from rest: (channel,
    #: displacement or None, velocity or None, words), as GroundMotion.given, delayed
    given: tuple = ()

    @property
    def channels(self) -> tuple[str, ...]:
        return tuple(self.samples)

    #: the one applied record of a one-record scene (none here: each support has its own)
    record = None
    records: tuple = ()


def delays(positions, velocity: float, direction: float) -> np.ndarray:
    """tau_s (s) of each support at ``positions`` (site, m) for waves travelling along
    ``direction`` (degrees from x) at the apparent ``velocity`` (m/s), from the first reached."""
    e = np.array([math.cos(math.radians(direction)), math.sin(math.radians(direction))])
    arrival = np.asarray(positions, dtype=float) @ e / float(velocity)
    return arrival - arrival.min()


def delayed(samples: np.ndarray, delay: float, dt: float) -> np.ndarray:
    """a(t - delay) at the same sample times, zero before the motion arrives: a whole number
    of steps shifts the samples (exact); a fraction of a step shifts them by a linear phase
    of their Fourier transform, zero-padded so that nothing wraps round (exact for a motion
    band-limited below the Nyquist frequency)."""
    samples = np.asarray(samples, dtype=float)
    if delay == 0.0:
        return samples
    whole = delay / dt
    if abs(whole - round(whole)) <= 1e-9 * max(1.0, whole):  # a whole number of steps (to
        k = int(round(whole))                                 # the round-off of delay / dt)
        return np.concatenate([np.zeros(min(k, samples.size)), samples[:max(samples.size - k, 0)]])
    n = samples.size
    size = 1 << int(math.ceil(math.log2(2 * n + int(math.ceil(whole)) + 2)))
    spectrum = np.fft.rfft(samples, size)
    frequency = np.fft.rfftfreq(size, dt)
    shifted = np.fft.irfft(spectrum * np.exp(-2j * np.pi * frequency * delay), size)[:n]
    shifted[: int(math.floor(whole))] = 0.0
    return shifted


def integrated(acceleration: np.ndarray, dt: float) -> tuple[np.ndarray, np.ndarray]:
    """(velocity, displacement) of ``acceleration`` samples, the trapezoid rule twice from rest
    (see the module): :func:`pframe.excitation.kinematics.integrate`, the one place it is
    written."""
    from pframe.excitation.kinematics import integrate

    return integrate(acceleration, dt)


def support_motion(scene, supports, base_dir, steps: int, dt: float) -> SupportMotion:
    """The motion of each of ``supports`` (:class:`pframe.model.supports.Supports`) at the
    analysis steps (see the module)."""
    excitation = scene.excitation
    if excitation is not None and excitation.kind == "coherent":
        return _coherent(scene, supports, base_dir, steps, dt)
    passage = excitation is not None and excitation.kind == "wave_passage"
    if passage:
        tau = delays(supports.positions, excitation.velocity, excitation.direction)
        common = excitation.motion
        common_path = ("excitation", "motion")
    else:
        tau = np.zeros(len(supports.names))
        common, common_path = excitation, ("excitation",)
    shared = None
    motions, warnings = [], []
    for s, support in enumerate(scene.supports):
        if support.excitation is not None:
            if passage:
                raise ModelError(("supports", s, "excitation"), f"support {support.name!r} has "
                                 "its own motion and the scene's is a wave passage, which "
                                 "gives every support its motion: give one or the other")
            motion = ground_motion(support.excitation, base_dir, steps, dt,
                                   ("supports", s, "excitation"))
            warnings += [f"support {support.name}: {w}" for w in motion.warnings]
        else:
            if shared is None:
                shared = ground_motion(common, base_dir, steps, dt, common_path)
                warnings += list(shared.warnings)
            motion = shared
        motions.append(motion)
    warnings += _mismatched_records(scene, motions)
    axes = tuple(a for a in ("x", "y") if any(a in m.samples for m in motions)) or ("x",)
    samples, given = {}, []
    for s, (name, motion) in enumerate(zip(supports.names, motions)):
        for axis, d, v, words in motion.given:
            given.append((f"{name}:{axis}", *(None if row is None else
                                               delayed(row, float(tau[s]), dt)
                                               for row in (d, v)), words))
        for axis in axes:
            values = motion.samples.get(axis, np.zeros(steps + 1))
            samples[f"{name}:{axis}"] = delayed(values, float(tau[s]), dt)
            peak, kept = float(np.max(np.abs(values))), float(np.max(np.abs(
                samples[f"{name}:{axis}"])))
            if tau[s] > 0.0 and kept < 0.999 * peak:
                warnings.append(f"support {name}: the waves reach it {float(tau[s]):.4g} s "
                                "after the first, and the analysis stops before the motion's "
                                f"peak arrives there: it applies at most {kept:.4g} m/s^2 of "
                                f"{peak:.4g} along {axis}; lengthen analysis.duration by "
                                f"{float(tau[s]):.4g} s")
    return SupportMotion(samples, axes, tuple(map(float, tau)), tuple(motions),
                         tuple(warnings), given=tuple(given))


def _mismatched_records(scene, motions) -> list[str]:
    """What says the records of supports with motions of their own differ in time step or
    length: each is interpolated onto the analysis step and is at rest after its end, so the
    supports' motions are not one array's recordings sampled alike."""
    own = [(s, support.name, axis, record.times) for s, (support, motion)
           in enumerate(zip(scene.supports, motions)) if support.excitation is not None
           for axis, record in motion.records if len(record.times) > 1]
    if len(own) < 2:
        return []
    steps = {round(float(t[1] - t[0]), 9) for *_, t in own}
    ends = [float(t[-1]) for *_, t in own]
    if len(steps) == 1 and max(ends) - min(ends) <= min(steps):
        return []
    listed = "; ".join(f"supports[{s}].excitation ({name}, {axis}): dt = {t[1] - t[0]:.4g} s, "
                       f"ends at {t[-1]:.4g} s" for s, name, axis, t in own)
    return [f"the supports' records differ in time step or length ({listed}): each is "
            "interpolated onto the analysis step and is at rest after its end, so their "
            "difference is not one array's recordings sampled alike; check that they are the "
            "records meant"]


def kinematics(ex) -> tuple[list, list, list]:
    """(displacements, velocities, words) of each of the scene's channels (m, m/s at the
    steps; docs/supports.md#displacements-from-a-record): a record's files where it gives
    them, else its acceleration integrated from rest (:func:`integrated`); words say how,
    and, where nothing corrects it, how far it drifts by the end of the analysis."""
    rows = (ex.support_samples if ex.support_samples is not None else
            [{"x": ex.ground_acceleration, "y": ex.ground_acceleration_y}[c]
             for c in ex.channels])
    given = {channel: (d, v, words) for channel, d, v, words in ex.ground_given}
    out_d, out_v, out_words = [], [], []
    for channel, row in zip(ex.channels, rows):
        d, v, words = given.get(channel, (None, None, None))
        if d is None or v is None:
            v_int, d_int = integrated(row, ex.dt)
            v = v_int if v is None else v
            if d is None:
                d = d_int
                words = (f"{words or 'no baseline correction'}: displacement the acceleration "
                         "integrated twice from rest (the trapezoid rule); at t = "
                         f"{ex.steps * ex.dt:.4g} s its velocity is {v[-1]:.4g} m/s and its "
                         f"displacement {d[-1]:.4g} m (peak {float(np.max(np.abs(d))):.4g} m)")
        support, _, axis = channel.rpartition(":")
        out_d.append(d)
        out_v.append(v)
        out_words.append(f"{'support ' + support if support else 'the ground'} along {axis}: "
                         f"{words}")
    return out_d, out_v, out_words


def _coherent(scene, supports, base_dir, steps: int, dt: float) -> SupportMotion:
    """The supports' motions of a coherent simulation (:mod:`pframe.model.coherent`)."""
    from pframe.model.coherent import coherent_motions

    own = [i for i, s in enumerate(scene.supports) if s.excitation is not None]
    if own:
        raise ModelError(("supports", own[0], "excitation"), f"support "
                         f"{scene.supports[own[0]].name!r} has its own motion and the scene's "
                         "is a coherent simulation, which gives every support its motion: "
                         "give one or the other")
    acceleration, tau, notes, description, _ = coherent_motions(scene, supports, base_dir,
                                                                steps, dt)
    samples = {f"{name}:x": row for name, row in zip(supports.names, acceleration)}
    motions = tuple(GroundMotion({"x": row}) for row in acceleration)
    return SupportMotion(samples, ("x",), tau, motions, (), notes, description)


#: what a recorder reads of the ground's displacements
GROUND_QUANTITIES = ("ground_displacement", "contact_ground_displacement")


def displacement_lines(ex) -> list[str]:
    """How each channel's displacement is had (:func:`kinematics`' words), where a run uses
    it: on several supports (elements across them), or a recorder of the ground's
    displacement; none otherwise."""
    recorded = {q for r in ex.recorders for q in getattr(r, "quantities", ())}
    if not (ex.node_support or recorded & set(GROUND_QUANTITIES)):
        return []
    return kinematics(ex)[2]
