"""A scene's coherent motions at its supports (``excitation: {kind: coherent}``,
docs/supports.md): the scene's numbers handed to the generators of
:mod:`pframe.excitation.simulated` and :mod:`pframe.excitation.conditioned`, and their
motions cut to the analysis."""

from __future__ import annotations

import math
from typing import NamedTuple

import numpy as np

from pframe.model.load import ModelError


def _coherency(given):
    from pframe.excitation.coherency import HarichandranVanmarcke, LucoWong

    if given is None:
        return None
    if given.model == "luco_wong":
        return LucoWong(given.incoherence, given.shear_velocity)
    return HarichandranVanmarcke(given.amplitude, given.alpha, given.k, given.f0, given.b)


def shared_spectrum(motion, path):
    """(spectrum, modulating function q(t) or None, duration (s)) of the stochastic motion
    every support shares."""
    from pframe.excitation import stochastic
    from pframe.excitation.simulated import CloughPenzienSpectrum, rezaeian_mid_time

    if motion.model == "rezaeian2010":
        if motion.parameters is not None:
            parameters = stochastic.RezaeianParameters(**motion.parameters.model_dump())
        else:
            rng = np.random.Generator(np.random.PCG64(int(motion.seed)))
            parameters = stochastic.sample_parameters(motion.magnitude, motion.distance,
                                                      motion.vs30, motion.mechanism, rng)[0]
        return rezaeian_mid_time(parameters)
    spectrum = CloughPenzienSpectrum(motion.intensity, motion.ground_frequency,
                                     motion.ground_damping, motion.filter_frequency,
                                     motion.filter_damping)
    envelope = motion.envelope
    if envelope is None:
        if motion.duration is None:
            raise ModelError(path + ("duration",), "a clough_penzien motion needs an envelope "
                                                   "or a duration")
        return spectrum, None, float(motion.duration)
    if envelope.kind == "jennings":
        return (spectrum, lambda t: stochastic.jennings(t, envelope.rise, envelope.plateau,
                                                        envelope.decay),
                envelope.plateau - math.log(1e-3) / envelope.decay)
    shape = stochastic.gamma_envelope(1.0, envelope.d595, envelope.tmid)
    peak = float(np.max(shape(np.linspace(0.0, 4.0 * envelope.tmid, 4001))))
    return (spectrum, lambda t: shape(t) / peak,
            shape.energy_time(stochastic.ENERGY_COVERED))


class CoherentMotions(NamedTuple):
    """What :func:`coherent_motions` gives."""

    acceleration: np.ndarray  # (S, steps + 1) m/s^2
    delays: tuple
    notes: tuple
    description: str
    lasts: float  # how long the simulated motions last (s), the analysis or not


def coherent_motions(scene, supports, base_dir, steps: int, dt: float, record=None,
                     seed: int | None = None):
    """Each support's acceleration at the analysis steps (m/s^2), its delay (s) and the
    generators' notes (:class:`CoherentMotions`). ``record`` (m/s^2 at the analysis steps)
    replaces the excitation's record at its support ``at``, and ``seed`` its seed: a suite's
    member run on the scene (pframe.gap.members)."""
    from pframe.excitation.coherency import SoilColumn, WavePassage
    from pframe.excitation.conditioned import conditioned
    from pframe.excitation.simulated import simulate
    from pframe.model.motion import ground_motion

    excitation = scene.excitation
    path = ("excitation",)
    coherency = _coherency(excitation.coherency)
    wave = (WavePassage(excitation.velocity, excitation.direction)
            if excitation.velocity is not None else None)
    sites = [None if s.site is None else SoilColumn(s.site.frequency, s.site.damping,
                                                    s.site.kind) for s in scene.supports]
    positions = [tuple(p) for p in supports.positions]
    seed = excitation.seed if seed is None else int(seed)
    try:
        if excitation.record is not None or record is not None:
            if excitation.at not in supports.names:
                raise ModelError(path + ("at",), f"no support named {excitation.at!r}; the "
                                 f"supports are {', '.join(supports.names)}")
            if record is None:
                if excitation.record.displacement is not None:
                    raise ModelError(path + ("record", "displacement"), "the supports of a "
                                     "coherent simulation move by their simulated "
                                     "accelerations integrated from rest; a record's "
                                     "displacement file is not read here (leave it out)")
                record = ground_motion(excitation.record, base_dir, steps, dt,
                                       path + ("record",)).samples["x"]
            found = conditioned(record, dt, positions, coherency,
                                recorded=supports.names.index(excitation.at),
                                seed=seed, wave=wave, sites=sites,
                                highpass=excitation.motion.highpass)
        else:
            spectrum, envelope, duration = shared_spectrum(excitation.motion, path + ("motion",))
            found = simulate(positions, dt, duration, spectrum, coherency,
                             seed=seed, envelope=envelope, wave=wave, sites=sites,
                             highpass=excitation.motion.highpass)
    except ValueError as exc:
        raise ModelError(path, f"cannot simulate the supports' motions: {exc}") from None
    acceleration = np.zeros((len(supports.names), steps + 1))
    count = min(steps + 1, found.acceleration.shape[1])
    acceleration[:, :count] = found.acceleration[:, :count]
    notes = list(found.notes)
    lasts = (found.acceleration.shape[1] - 1) * dt
    if found.acceleration.shape[1] > steps + 1:
        notes.append(f"the simulated motions last {lasts:.4g} s and the analysis "
                     f"{steps * dt:.4g} s: the rest is not applied")
    return CoherentMotions(acceleration, tuple(map(float, found.delays)), tuple(notes),
                           found.description, lasts)
