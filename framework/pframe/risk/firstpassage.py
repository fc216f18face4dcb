"""Pounding of two elastic SDOFs under a stationary Gaussian ground acceleration as a
first-passage problem (Tubaldi, Barbato & Ghazizadeh 2012, "A probabilistic performance-
based risk assessment approach for seismic pounding with efficient application to linear
systems", Structural Safety 36-37; Lin & Hsu 1989 for the relative displacement):

- the relative displacement r = u_A - u_B (A on the left, pounding when r > gap) is a
  zero-mean stationary Gaussian process with one-sided spectral density
  G_r(w) = 2 |H_A(w) - H_B(w)|^2 S(w), H_j(w) = -1 / (w_j^2 - w^2 + 2 i z_j w_j w) the
  relative displacement of SDOF j per unit ground acceleration and S(w) the two-sided PSD
  of the ground acceleration (white noise S_0, or Clough-Penzien);
- its spectral moments lambda_i = int_0^inf w^i G_r(w) dw give sigma = sqrt(lambda_0), the
  rate of up-crossings of zero nu_0 = sqrt(lambda_2 / lambda_0) / (2 pi) and the bandwidth
  q = sqrt(1 - lambda_1^2 / (lambda_0 lambda_2));
- Vanmarcke's (1975) approximation of the probability that r up-crosses b = gap within a
  duration T, for a one-sided barrier (the envelope's qualified crossings, with
  Vanmarcke's empirical q_e = q^1.2):

      P_f = 1 - Phi(eta) exp(-nu_0 T exp(-eta^2 / 2)
                               (1 - exp(-sqrt(2 pi) q_e eta)) / (1 - exp(-eta^2 / 2))),

  eta = b / sigma (the initial factor: r starts below the barrier; at large eta it tends
  to Rice's Poisson rate nu_0 exp(-eta^2 / 2), below it at small eta where crossings
  cluster);
- scaling the input by s scales sigma by s, so P_f(gap | IM) for IM proportional to s, and
  the mean annual frequency of pounding lambda = int P_f(gap | x) |d lambda_IM(x)| over a
  hazard curve (:func:`pframe.risk.hazard.mean_annual_frequency`).

:func:`simulate_maxima` runs the pair in pframe (one batch, no contacts) and returns the
maximum of r over [start, end] of every realisation: the Monte Carlo side of the check
(tests/test_risk_tubaldi.py, docs/risk.md).
"""

from __future__ import annotations

import dataclasses
import json
import math
from pathlib import Path

import numpy as np
from scipy import integrate
from scipy.stats import norm


@dataclasses.dataclass(frozen=True)
class Moments:
    """Spectral moments (lambda_0, lambda_1, lambda_2) of a stationary process."""

    l0: float
    l1: float
    l2: float

    @property
    def sigma(self) -> float:
        return math.sqrt(self.l0)

    @property
    def rate(self) -> float:
        """nu_0: mean rate of up-crossings of zero (1/s)."""
        return math.sqrt(self.l2 / self.l0) / (2 * math.pi)

    @property
    def bandwidth(self) -> float:
        """Vanmarcke's q."""
        return math.sqrt(max(0.0, 1.0 - self.l1 ** 2 / (self.l0 * self.l2)))

    def scaled(self, s: float) -> Moments:
        """The moments of the response to the input times s."""
        return Moments(self.l0 * s * s, self.l1 * s * s, self.l2 * s * s)


def relative_transfer(omega, periods, damping) -> np.ndarray:
    """H_A(w) - H_B(w): relative displacement per unit ground acceleration."""
    w = np.asarray(omega, float)
    out = np.zeros(w.shape, complex)
    for sign, t, z in zip((1.0, -1.0), periods, damping):
        wn = 2 * math.pi / t
        out += sign * -1.0 / (wn * wn - w * w + 2j * z * wn * w)
    return out


def relative_moments(psd, periods, damping) -> Moments:
    """Spectral moments of r = u_A - u_B for the two-sided ground PSD ``psd(w)``."""
    wn = sorted(2 * math.pi / np.asarray(periods, float))
    top = 50.0 * wn[-1]

    def moment(i):
        f = lambda w: 2.0 * w ** i * abs(relative_transfer(w, periods, damping)) ** 2 * psd(w)  # noqa: E731
        body = integrate.quad(f, 0.0, top, points=wn, limit=400, epsabs=0, epsrel=1e-10)[0]
        tail = integrate.quad(f, top, np.inf, limit=200, epsabs=0, epsrel=1e-8)[0]
        return body + tail

    return Moments(moment(0), moment(1), moment(2))


def vanmarcke(barrier, moments: Moments, duration: float) -> np.ndarray:
    """Probability that the process up-crosses ``barrier`` within ``duration`` (s), from a
    stationary start (Vanmarcke 1975, one-sided barrier, q_e = q^1.2)."""
    eta = np.asarray(barrier, float) / moments.sigma
    qe = moments.bandwidth ** 1.2
    with np.errstate(divide="ignore", invalid="ignore", over="ignore"):
        e = np.exp(-0.5 * eta * eta)
        clump = -np.expm1(-math.sqrt(2 * math.pi) * qe * eta) / -np.expm1(-0.5 * eta * eta)
        rate = moments.rate * e * np.where(eta > 0, clump, 1.0)
        survive = norm.cdf(eta) * np.exp(-rate * duration)
    return np.where(eta > 0, 1.0 - survive, 1.0)


def rice(barrier, moments: Moments, duration: float) -> np.ndarray:
    """The Poisson (Rice) approximation 1 - exp(-nu_0 T exp(-eta^2 / 2)), an upper bound at
    small eta where crossings come in clumps."""
    eta = np.asarray(barrier, float) / moments.sigma
    return -np.expm1(-moments.rate * duration * np.exp(-0.5 * eta * eta))


def simulate_maxima(loaded, accelerations: np.ndarray, dt: float, start: float,
                    threads: int | None = None) -> np.ndarray:
    """max over t >= ``start`` of the closing of the scene's first contact (u_left - u_right;
    in plan, of its points along its normal), for every row of ``accelerations`` (B, steps +
    1) m/s^2 on step ``dt``, without contacts."""
    from pframe.gap.runs import GapSink, batch_plan, contact_pairs
    from pframe.kernel import simulate

    pairs = contact_pairs(loaded)
    steps = accelerations.shape[-1] - 1
    plan = batch_plan(loaded, accelerations, steps, dt=dt)
    sink = GapSink(plan, pairs, start=int(round(start / dt)))
    result = simulate(plan, threads=threads, sink=sink)
    failed = [b for b in range(plan.batch) if not result.completed(b)]
    peak = sink.gap[:, 0].copy()
    peak[failed] = np.nan
    return peak


def clough_penzien_batch(count: int, n: int, step: float, intensity: float, wg: float,
                         zg: float, wf: float = 0.0, zf: float = 0.0, rng=None) -> np.ndarray:
    """(count, n) stationary Clough-Penzien ground accelerations in one filtering pass: the
    process of :func:`pframe.excitation.stochastic.clough_penzien_stationary` (white noise of
    variance 2 pi S_0 / dt held over each step through the zero-order-hold discretisation of
    the filters, after a warm-up), generated for many realisations at once. Its PSD is
    ``clough_penzien_psd(w) sinc^2(w dt / 2)`` below the Nyquist frequency."""
    from scipy import signal

    from pframe.excitation.stochastic import clough_penzien_filter, clough_penzien_warmup

    b, a = clough_penzien_filter(float(step), float(wg), float(zg), float(wf), float(zf))
    warm = clough_penzien_warmup(step, wg, zg, wf, zf)
    rng = np.random.default_rng() if rng is None else rng
    noise = rng.standard_normal((count, n + warm)) * math.sqrt(2.0 * math.pi * intensity / step)
    return signal.lfilter(b, a, noise, axis=1)[:, warm:]


def held_psd(psd, step: float):
    """The PSD of a process held over steps of ``step`` (zero-order hold): psd sinc^2."""
    return lambda w: psd(w) * np.sinc(np.asarray(w, float) * step / (2 * math.pi)) ** 2


def pounding_probability(gap: float, moments: Moments, im_ref: float, duration: float):
    """P(pounding within ``duration`` | IM = x) by Vanmarcke, for the moments of the
    response to the input whose IM is ``im_ref`` (the response scales with the IM)."""
    def probability(x):
        x = np.asarray(x, float)
        flat = [float(vanmarcke(gap, moments.scaled(v / im_ref), duration)) if v > 0 else 0.0
                for v in x.ravel()]
        return np.array(flat).reshape(x.shape)
    return probability


@dataclasses.dataclass
class Check:
    """The first-passage check of an elastic SDOF pair under stationary Clough-Penzien
    input: simulated against Vanmarcke, per barrier and for the mean annual frequency."""

    periods: tuple
    damping: float
    duration: float
    realisations: int
    moments: Moments
    im_ref: float  # rms ground acceleration of the reference input (g)
    eta: np.ndarray  # barriers / sigma
    simulated: np.ndarray
    vanmarcke: np.ndarray
    rice: np.ndarray
    gap: float
    maf_vanmarcke: float
    maf_simulated: float
    maf_simulated_range: tuple  # 2.5-97.5 % over realisation resamples


def tubaldi_check(realisations: int = 1000, seed: int = 3, threads: int | None = None,
                  periods=(0.5, 1.0), damping: float = 0.05, duration: float = 10.0,
                  warm: float = 10.0, dt: float = 0.01, hazard=None) -> Check:
    """Two elastic SDOFs (1000 kg, ``periods``, ``damping``) under a stationary
    Clough-Penzien ground acceleration (S_0 = 0.01 m^2/s^3, w_g = 15.6 rad/s, z_g = 0.6,
    w_f = 1.5 rad/s, z_f = 0.6), ``realisations`` runs of ``warm`` + ``duration`` s in one
    batch; the maximum of u_A - u_B over the last ``duration`` s against Vanmarcke's
    first-passage probability at barriers eta sigma, then the mean annual frequency of
    pounding at gap = 7.5 sigma (the reference input's) over the power-law hazard
    lambda = 1e-5 IM^-3 of the rms ground acceleration IM (g)."""
    from scipy import integrate

    from pframe.excitation.stochastic import clough_penzien_psd
    from pframe.reader import parse_scene
    from pframe.risk.hazard import HazardCurve, mean_annual_frequency

    s0, wg, zg, wf, zf = 0.01, 15.6, 0.6, 1.5, 0.6
    mass = 1000.0
    scene = {"title": "two elastic SDOFs (first-passage check)",
             "buildings": [{"name": n, "floors": 1, "mass": mass,
                            "story": {"material": "elastic",
                                      "stiffness": mass * (2 * math.pi / p) ** 2}}
                           for n, p in zip("AB", periods)],
             "contacts": [{"name": "roof", "nodes": ["A/1", "B/1"], "gap": 1.0,
                           "law": "linear", "stiffness": 1.0e7}],
             "damping": {"ratio": damping},
             "analysis": {"dt": dt, "duration": warm + duration}}
    loaded = parse_scene(json.dumps(scene), "first-passage pair", Path("."))
    steps = int(round((warm + duration) / dt))
    rng = np.random.default_rng(seed)
    acc = clough_penzien_batch(realisations, steps + 1, dt, s0, wg, zg, wf, zf, rng)
    peak = simulate_maxima(loaded, acc, dt, warm, threads=threads)
    psd = held_psd(lambda w: clough_penzien_psd(w, s0, wg, zg, wf, zf), dt)
    m = relative_moments(psd, periods, (damping, damping))
    eta = np.array([1.5, 2.0, 2.5, 3.0, 3.5])
    sim = np.array([np.mean(peak > e * m.sigma) for e in eta])
    im_ref = math.sqrt(2 * integrate.quad(psd, 0, np.inf, limit=400)[0]) / 9.80665
    gap = 7.5 * m.sigma
    hazard = hazard or HazardCurve.power_law(1e-5, 3.0, 1e-3, 10.0)
    maf_v = mean_annual_frequency(pounding_probability(gap, m, im_ref, duration), hazard)[0]

    def simulated(sample):
        srt = np.sort(sample)
        return lambda x: 1.0 - np.searchsorted(srt, gap * im_ref / np.asarray(x, float),
                                               side="right") / srt.size

    maf_s = mean_annual_frequency(simulated(peak), hazard, points=800)[0]
    boot = [mean_annual_frequency(simulated(rng.choice(peak, peak.size)), hazard,
                                  points=800)[0] for _ in range(200)]
    return Check(tuple(periods), damping, duration, realisations, m, im_ref, eta, sim,
                 vanmarcke(eta * m.sigma, m, duration), rice(eta * m.sigma, m, duration),
                 gap, float(maf_v), float(maf_s), tuple(np.percentile(boot, [2.5, 97.5])))


def check_text(c: Check) -> str:
    """The check as docs/risk.md shows it."""
    lines = [f"SDOF pair T = {c.periods[0]:g} s / {c.periods[1]:g} s, zeta = {c.damping:g}; "
             f"r = u_A - u_B: sigma = {1000 * c.moments.sigma:.2f} mm, nu_0 = "
             f"{c.moments.rate:.3f} /s, q = {c.moments.bandwidth:.3f}; "
             f"{c.realisations} runs of {c.duration:g} s",
             f"{'eta = b / sigma':>16} {'simulated':>10} {'(95 %)':>8} {'Vanmarcke':>10} "
             f"{'Rice':>7}"]
    for e, s, v, r in zip(c.eta, c.simulated, c.vanmarcke, c.rice):
        half = 1.96 * math.sqrt(s * (1 - s) / c.realisations)
        lines.append(f"{e:>16.1f} {s:>10.3f} {'+-' + format(half, '.3f'):>8} {v:>10.3f} "
                     f"{r:>7.3f}")
    lo, hi = c.maf_simulated_range
    lines.append(f"gap {1000 * c.gap:.1f} mm, hazard 1e-5 IM^-3 (IM: rms ground acceleration, "
                 f"g; reference {c.im_ref:.4f} g): MAF of pounding {c.maf_vanmarcke:.3e} /yr "
                 f"(Vanmarcke), {c.maf_simulated:.3e} /yr simulated (95 %: {lo:.3e}-{hi:.3e})")
    return "\n".join(lines)
