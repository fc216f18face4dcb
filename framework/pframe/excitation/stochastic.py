"""Stochastic ground motions: seeded, reproducible accelerograms that a scene applies like a
record (``excitation: {kind: stochastic, ...}``; docs/stochastic-motions.md).

Two models:

- ``rezaeian2010``: the site-based model of Rezaeian & Der Kiureghian (2008, EESD 37; 2010,
  EESD 39). A modulated filtered white noise with a time-varying filter,

      a(t) = q(t) sum_i h[t - t_i, omega_f(t_i)] u_i / sigma_h(t),
      h(tau, w) = w / sqrt(1 - zeta^2) exp(-zeta w tau) sin(w sqrt(1 - zeta^2) tau),
      omega_f(t) = 2 pi [f_mid + f' (t - t_mid)],

  u_i standard normal at t_i = i dt, sigma_h(t)^2 = sum_i h^2 (unit variance before q), q the
  gamma-form modulating function alpha_1 t^(alpha_2 - 1) exp(-alpha_3 t) whose (alpha_1,
  alpha_2, alpha_3) give the expected Arias intensity I_a, the significant duration D5-95 and
  the time t_mid at which 45 % of I_a is reached; then a critically damped high-pass
  post-filter (f_c = 0.2 Hz), run on until it has come to rest (10 / w_c = 7.96 s of zeros
  after the modulated motion), which leaves no residual velocity or displacement. The six parameters (I_a,
  D5-95, t_mid, f_mid, f', zeta_f) are given directly or sampled per realisation from the
  earthquake and site (magnitude, R_rup, Vs30, mechanism) by predictive relations: normal
  variables nu_i = mean_i(F, M, R, V) + correlated error, mapped to each parameter's marginal
  distribution (:data:`MARGINALS`, :data:`RELATIONS`).
- ``clough_penzien``: stationary Clough-Penzien filtered white noise (the Kanai-Tajimi filter
  followed by a high-pass second filter; ``filter_frequency: 0`` leaves Kanai-Tajimi), times a
  modulating function (Jennings, gamma form, or none), parameters given directly.

Everything is a function of the excitation's fields and its seed (numpy's PCG64): the same
definition gives the same motion bit for bit on every run.
"""

from __future__ import annotations

import functools
import json
import math
from dataclasses import dataclass, field

import numpy as np

from pframe.excitation.records import G

#: the high-pass post-filter's corner frequency (Hz) of Rezaeian & Der Kiureghian (2008)
HIGHPASS_HZ = 0.2
#: the high-pass filter is run on this many 1 / w_c of zeros after the modulated motion
#: (7.96 s at 0.2 Hz), for it to come to rest: its velocity and displacement there, the
#: motion's residual ones, are its free decay from the motion's end (:func:`settling`)
HIGHPASS_SETTLE = 10.0
#: the filter frequency omega_f(t)/2pi is kept above this (Hz): f_mid + f'(t - t_mid) may fall
#: below zero late in a long motion with a steep negative slope; the facts say when it does
FILTER_FLOOR_HZ = 0.3
#: the modulated motion lasts until the modulating function has delivered this part of I_a
#: (rezaeian2010: then the high-pass filter settles, :data:`HIGHPASS_SETTLE`)
ENERGY_COVERED = 0.9995

# Marginal distributions of the six parameters (Rezaeian & Der Kiureghian 2010, fitted to
# NGA records): ln I_a (I_a in s g) normal; D5-95 (s) beta on [5, 45]; t_mid (s) beta on
# [0.5, 40]; f_mid (Hz) gamma; f' (Hz/s) two-sided exponential on [-2, 0.5]; zeta_f beta on
# [0.02, 1].
MARGINALS = {
    "ln_arias": ("normal", -4.8255, 1.4318),
    "d595": ("beta", 1.1314, 2.4474, 5.0, 45.0),
    "tmid": ("beta", 1.5792, 3.6405, 0.5, 40.0),
    "frequency": ("gamma", 4.0982, 1.4330),
    "slope": ("two_sided_exponential", 17.095, 6.7729, 4.8512, -2.0, 0.5),
    "damping": ("beta", 1.4250, 5.7208, 0.02, 1.0),
}

# Predictive relations of the normal-space means nu_i = b0 + b1 m + b2 F + b3 r + b4 v, with
# F = 0 strike-slip, 1 reverse; for I_a m = M/7, r = ln(R_rup/25 km), v = ln(Vs30/750 m/s),
# for the others m = M, r = R_rup (km), v = Vs30 (m/s); total error standard deviations
# sqrt(sigma^2 + tau^2) (within- and between-event) and the correlation matrix of the total
# errors. Coefficients as published with the SCEC Broadband Platform's implementation of the
# predictive equations for this model's six parameters (Rezaeian, Zhong, Hartzell & Zareian
# 2015, BSSA 105(6), fitted to NGA-West2 records) -- see docs/stochastic-motions.md.
RELATIONS = {
    "names": ("ln_arias", "d595", "tmid", "frequency", "slope", "damping"),
    "beta": np.array([
        [-2.2962, 2.9440, -0.0707, -1.3564, -0.2654],
        [-6.1946, 0.9703, -0.7034, 0.0087, -0.0007],
        [-5.0105, 0.6625, -0.3450, 0.0139, -0.0002],
        [2.2525, -0.2586, -0.0808, -0.0084, 0.0000],
        [-2.4886, 0.3440, 0.0441, 0.0026, -0.0001],
        [-0.2583, 0.1293, -0.4772, -0.0115, 0.0004]]),
    "sigma": np.array([0.5937, 0.5688, 0.4145, 0.7228, 0.9529, 0.7601]),
    "tau": np.array([0.2738, 0.4574, 0.5114, 0.6918, 0.1286, 0.6815]),
    "correlation": np.array([
        [1.0000, -0.3555, 0.0066, -0.1545, 0.1341, -0.0078],
        [-0.3555, 1.0000, 0.6729, -0.1303, -0.1576, -0.1958],
        [0.0066, 0.6729, 1.0000, -0.2761, -0.1977, -0.2188],
        [-0.1545, -0.1303, -0.2761, 1.0000, -0.2034, 0.2814],
        [0.1341, -0.1576, -0.1977, -0.2034, 1.0000, -0.0137],
        [-0.0078, -0.1958, -0.2188, 0.2814, -0.0137, 1.0000]]),
}
#: the range of the records behind the relations that pframe checks a site against (outside
#: it a warning says the relations are extrapolated)
SITE_RANGE = {"magnitude": (5.5, 7.9), "distance": (1.0, 200.0), "vs30": (150.0, 1500.0)}
MECHANISMS = {"strike_slip": 0.0, "reverse": 1.0}


# ----------------------------------------------------------------------------------------
# Parameters and the predictive relations


@dataclass(frozen=True)
class RezaeianParameters:
    """The six parameters of one realisation: I_a (m/s; s g times g), D5-95 (s), t_mid (s),
    f_mid (Hz), f' (Hz/s), zeta_f."""

    arias: float
    d595: float
    tmid: float
    frequency: float
    slope: float
    damping: float

    def as_dict(self) -> dict:
        return {"arias": self.arias, "d595": self.d595, "tmid": self.tmid,
                "frequency": self.frequency, "slope": self.slope, "damping": self.damping}


def relation_means(magnitude: float, distance: float, vs30: float, mechanism: str) -> np.ndarray:
    """The six normal-space means nu_i of the predictive relations (:data:`RELATIONS`)."""
    f = MECHANISMS[mechanism]
    b = RELATIONS["beta"]
    first = b[0] @ [1.0, magnitude / 7.0, f, math.log(distance / 25.0), math.log(vs30 / 750.0)]
    rest = b[1:] @ np.array([1.0, magnitude, f, distance, vs30])
    return np.concatenate([[first], rest])


def relation_covariance() -> np.ndarray:
    """The covariance of the total errors of the six normal-space variables."""
    std = np.hypot(RELATIONS["sigma"], RELATIONS["tau"])
    return RELATIONS["correlation"] * np.outer(std, std)


def from_normal(nu) -> RezaeianParameters:
    """The parameters whose normal-space values are ``nu`` (six): theta_i = F_i^-1(Phi(nu_i))."""
    values = from_normal_batch(np.asarray(nu, dtype=float)[None, :])
    return RezaeianParameters(*(float(v[0]) for v in values))


def from_normal_batch(nu: np.ndarray) -> tuple[np.ndarray, ...]:
    """:func:`from_normal` of each row of ``nu`` (B, 6), vectorised: the six parameters as
    arrays (arias, d595, tmid, frequency, slope, damping), in the order of
    :class:`RezaeianParameters`."""
    from scipy import special

    nu = np.asarray(nu, dtype=float)
    p = special.ndtr(nu)
    values = {}
    for j, name in enumerate(RELATIONS["names"]):
        kind, *args = MARGINALS[name]
        if kind == "normal":
            values[name] = args[0] + args[1] * nu[:, j]  # exact, not through Phi
        elif kind == "beta":
            a, b, lo, hi = args
            values[name] = lo + (hi - lo) * special.betaincinv(a, b, p[:, j])
        elif kind == "gamma":
            values[name] = special.gammaincinv(args[0], p[:, j]) * args[1]
        else:
            values[name] = _two_sided_exponential_ppf(p[:, j], *args)
    return (np.exp(values["ln_arias"]) * G, values["d595"], values["tmid"], values["frequency"],
            values["slope"], values["damping"])


def _two_sided_exponential_ppf(p, a, b, c, lo, hi) -> np.ndarray:
    p = np.asarray(p, dtype=float)
    at_zero = (c / b) * (1.0 - math.exp(b * lo))
    with np.errstate(divide="ignore", invalid="ignore"):
        left = np.log(p * b / c + math.exp(b * lo)) / b
        right = -np.log(np.maximum(1.0 - (p - at_zero) * a / c, 1e-300)) / a
    return np.clip(np.where(p < at_zero, left, right), lo, hi)


def two_sided_exponential_ppf(p: float, a: float, b: float, c: float, lo: float,
                              hi: float) -> float:
    """Inverse of the CDF of the density c e^(b x) on [lo, 0), c e^(-a x) on [0, hi]."""
    return float(_two_sided_exponential_ppf(np.array([p]), a, b, c, lo, hi)[0])


def sample_parameters(magnitude, distance, vs30, mechanism, rng, tries: int = 1000):
    """One realisation's parameters from the site: (parameters, nu, rejected), where
    ``rejected`` counts the draws refused because no gamma-form modulating function has their
    D5-95 and t_mid (D5-95 / t_mid above that of alpha_2 = 1); they are drawn again."""
    values, nu, rejected = sample_parameters_batch(magnitude, distance, vs30, mechanism, [rng],
                                                   tries)
    return RezaeianParameters(*(float(v[0]) for v in values)), nu[0], int(rejected[0])


def sample_parameters_batch(magnitude, distance, vs30, mechanism, rngs, tries: int = 1000):
    """:func:`sample_parameters` for each generator of ``rngs`` (each draws from its own
    stream, as one realisation alone would), vectorised: (the six parameters as arrays, nu
    (B, 6), rejected (B,))."""
    mean = relation_means(magnitude, distance, vs30, mechanism)
    chol = np.linalg.cholesky(relation_covariance())
    count = len(rngs)
    nu = np.empty((count, 6))
    values = [np.empty(count) for _ in range(6)]
    rejected = np.zeros(count, dtype=np.int64)
    todo = np.arange(count)
    for _ in range(tries):
        z = np.array([rngs[b].standard_normal(6) for b in todo]).reshape(len(todo), 6)
        # a sum per row, not a matrix product: the same bits whatever the batch's size
        nu[todo] = mean + np.sum(z[:, None, :] * chol[None, :, :], axis=2)
        drawn = from_normal_batch(nu[todo])
        for v, d in zip(values, drawn):
            v[todo] = d
        bad = ~envelope_feasible_batch(values[1][todo], values[2][todo])
        rejected[todo[bad]] += 1
        todo = todo[bad]
        if not todo.size:
            return tuple(values), nu, rejected
    raise ValueError(f"no feasible modulating function in {tries} draws")


# ----------------------------------------------------------------------------------------
# The gamma-form modulating function


def _gamma_quantiles(shape, probs=(0.05, 0.45, 0.95)) -> np.ndarray:
    """The quantiles ``probs`` of the unit gamma law of each ``shape``: (..., len(probs))."""
    from scipy import special

    return special.gammaincinv(np.asarray(shape, float)[..., None], np.asarray(probs))


def _duration_ratio(shape):
    q = _gamma_quantiles(shape)
    ratio = (q[..., 2] - q[..., 0]) / q[..., 1]
    return float(ratio) if np.ndim(ratio) == 0 else ratio


def envelope_feasible(d595: float, tmid: float) -> bool:
    """Whether a gamma-form q (alpha_2 > 1: q(0) = 0) has this D5-95 and t_mid."""
    return bool(envelope_feasible_batch(np.array([d595]), np.array([tmid]))[0])


def envelope_feasible_batch(d595, tmid) -> np.ndarray:
    """:func:`envelope_feasible` elementwise."""
    ratio = np.asarray(d595, float) / np.asarray(tmid, float)
    return (ratio > 0.0) & (ratio < _duration_ratio(1.0) * (1.0 - 1e-9))


@dataclass(frozen=True)
class GammaEnvelope:
    """q(t) = alpha_1 t^(alpha_2 - 1) exp(-alpha_3 t) (SI: q in m/s^2)."""

    alpha1: float
    alpha2: float
    alpha3: float

    def __call__(self, t):
        t = np.asarray(t, dtype=float)
        with np.errstate(divide="ignore", invalid="ignore"):
            log = (math.log(self.alpha1) + (self.alpha2 - 1.0) * np.log(t) - self.alpha3 * t)
        return np.where(t > 0.0, np.exp(log), 0.0)

    def energy_time(self, fraction: float) -> float:
        """When the expected cumulative Arias intensity reaches ``fraction`` of its total (s)."""
        from scipy import stats

        return float(stats.gamma.ppf(fraction, 2.0 * self.alpha2 - 1.0,
                                     scale=1.0 / (2.0 * self.alpha3)))

    def arias(self) -> float:
        """The expected Arias intensity pi / (2 g) int q^2 dt (m/s) of a unit-variance process."""
        k, rate = 2.0 * self.alpha2 - 1.0, 2.0 * self.alpha3
        return math.pi / (2.0 * G) * math.exp(2.0 * math.log(self.alpha1) + math.lgamma(k)
                                              - k * math.log(rate))


def gamma_envelope(arias: float, d595: float, tmid: float) -> GammaEnvelope:
    """The gamma-form q of expected Arias intensity ``arias`` (m/s), D5-95 ``d595`` (s) and
    t_mid ``tmid`` (s): q^2 is a gamma density of shape k = 2 alpha_2 - 1 and rate 2 alpha_3
    scaled; k solves D5-95 / t_mid = (Q95 - Q5) / Q45 of the gamma(k) quantiles, the rate
    follows from t_mid, alpha_1 from I_a."""
    if not envelope_feasible(d595, tmid):
        raise ValueError(f"no gamma-form modulating function has D5-95 = {d595:g} s and "
                         f"t_mid = {tmid:g} s (D5-95 / t_mid must be below "
                         f"{_duration_ratio(1.0):.4g})")
    a1, a2, a3 = gamma_envelopes(np.array([arias]), np.array([d595]), np.array([tmid]))
    return GammaEnvelope(float(a1[0]), float(a2[0]), float(a3[0]))


def gamma_envelopes(arias, d595, tmid) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(alpha_1, alpha_2, alpha_3) of :func:`gamma_envelope` for arrays of feasible
    parameters: the shape k solved for all at once (bracketed by doubling, then the Illinois
    variant of regula falsi to 1e-13 of k)."""
    arias, d595, tmid = (np.asarray(x, float) for x in (arias, d595, tmid))
    target = d595 / tmid
    lo, hi = np.ones_like(target), np.full_like(target, 2.0)
    f_hi = _duration_ratio(hi) - target
    while np.any(f_hi > 0):
        grow = f_hi > 0
        lo[grow], hi[grow] = hi[grow], 2.0 * hi[grow]
        f_hi[grow] = _duration_ratio(hi[grow]) - target[grow]
    f_lo = _duration_ratio(lo) - target
    k = hi.copy()
    side = np.zeros(target.shape, dtype=np.int8)
    for _ in range(200):
        active = (hi - lo > 1e-13 * hi) & (f_lo != 0) & (f_hi != 0)
        if not np.any(active):
            break
        a = np.flatnonzero(active)
        k[a] = (lo[a] * f_hi[a] - hi[a] * f_lo[a]) / (f_hi[a] - f_lo[a])
        k[a] = np.clip(k[a], lo[a], hi[a])
        f = _duration_ratio(k[a]) - target[a]
        up = f > 0  # the root is above k
        lo[a[up]], f_lo[a[up]] = k[a[up]], f[up]
        hi[a[~up]], f_hi[a[~up]] = k[a[~up]], f[~up]
        # Illinois: halve the value at the end that stayed twice in a row
        f_hi[a[up & (side[a] == 1)]] *= 0.5
        f_lo[a[~up & (side[a] == -1)]] *= 0.5
        side[a] = np.where(up, 1, -1)
    k = np.where(f_lo == 0, lo, np.where(f_hi == 0, hi, k))
    from scipy import special

    rate = _gamma_quantiles(k, (0.45,))[..., 0] / tmid
    log_a1 = 0.5 * (np.log(2.0 * G * arias / math.pi) + k * np.log(rate) - special.gammaln(k))
    return np.exp(log_a1), 0.5 * (k + 1.0), 0.5 * rate


# ----------------------------------------------------------------------------------------
# Simulation


def filter_frequencies(params: RezaeianParameters, times: np.ndarray):
    """omega_f(t) (rad/s) and whether the floor of :data:`FILTER_FLOOR_HZ` was reached."""
    f = params.frequency + params.slope * (np.asarray(times, float) - params.tmid)
    floored = bool(np.any(f < FILTER_FLOOR_HZ))
    return 2.0 * math.pi * np.maximum(f, FILTER_FLOOR_HZ), floored


#: a pulse's filter response is summed until it has decayed by e^-FILTER_CUTOFF (below
#: roundoff of the sum)
FILTER_CUTOFF = 40.0


def rezaeian_unfiltered(params: RezaeianParameters, step: float, rng):
    """(times, a before the post-filter, envelope, floored) of one realisation."""
    env = gamma_envelope(params.arias, params.d595, params.tmid)
    end = env.energy_time(ENERGY_COVERED)
    n = int(math.ceil(end / step)) + 1
    times = np.arange(n) * step
    omega, floored = filter_frequencies(params, times)
    u = rng.standard_normal(n)
    return times, env(times) * filtered_unit(omega, u, params.damping, step), env, floored


def filtered_unit(omega: np.ndarray, u: np.ndarray, zeta: float, step: float) -> np.ndarray:
    """sum_i h[t_k - t_i, omega(t_i)] u_i / sigma_h(t_k) at every sample: the unit-variance
    process before the modulating function (compiled; :func:`filtered_unit_numpy` when the
    extension is not built). ``omega`` (rad/s) must be monotonic, as
    :func:`filter_frequencies` gives it."""
    library = _filter_library()
    if library is None:
        return filtered_unit_numpy(omega, u, zeta, step)
    import ctypes

    n = len(omega)
    omega = np.ascontiguousarray(omega, dtype=float)
    u = np.ascontiguousarray(u, dtype=float)
    total, norm, work = np.empty(n), np.empty(n), np.empty(4 * n)
    library.pframe_rezaeian_filter(n, ctypes.c_double(step), ctypes.c_double(zeta),
                                   ctypes.c_double(FILTER_CUTOFF), omega.ctypes.data,
                                   u.ctypes.data, total.ctypes.data, norm.ctypes.data,
                                   work.ctypes.data)
    return np.divide(total, np.sqrt(norm), out=np.zeros(n), where=norm > 0)


def filtered_unit_numpy(omega: np.ndarray, u: np.ndarray, zeta: float, step: float) -> np.ndarray:
    """:func:`filtered_unit` in numpy, lag by lag with h from exp and sin (the reference the
    compiled filter is tested against; about a hundred times slower)."""
    n = len(omega)
    root = math.sqrt(1.0 - zeta * zeta)
    total = np.zeros(n)
    norm = np.zeros(n)
    decay = zeta * float(np.min(omega)) * step
    for m in range(1, n):  # lag m: the pulses of t_i = t_k - m dt
        if decay * m > FILTER_CUTOFF:  # every later lag is below roundoff
            break
        w = omega[: n - m]
        tau = m * step
        h = w / root * np.exp(-zeta * w * tau) * np.sin(w * root * tau)
        total[m:] += h * u[: n - m]
        norm[m:] += h * h
    return np.divide(total, np.sqrt(norm), out=np.zeros(n), where=norm > 0)


@functools.lru_cache(maxsize=1)
def _filter_library():
    """The compiled filter (extension pframe.excitation._cstochastic, loaded with ctypes,
    whose calls release the GIL), or None when it is not built."""
    import ctypes
    import importlib.util

    spec = importlib.util.find_spec("pframe.excitation._cstochastic")
    if spec is None or not spec.origin:
        return None
    library = ctypes.CDLL(spec.origin)
    library.pframe_rezaeian_filter.restype = ctypes.c_int64
    library.pframe_rezaeian_filter.argtypes = [ctypes.c_int64, ctypes.c_double, ctypes.c_double,
                                               ctypes.c_double] + [ctypes.c_void_p] * 5
    return library


def rezaeian_batch(seeds, step: float, site: dict | None = None,
                   parameters: RezaeianParameters | None = None,
                   highpass_filter: bool = True, until=None) -> list[StochasticMotion]:
    """Realisations of the rezaeian2010 model, one per seed, each what
    ``generate(Stochastic(model="rezaeian2010", seed=seed, ...))`` gives (the same bits: that
    is this function with one seed): parameters sampled from ``site`` (magnitude, distance,
    vs30, mechanism) or ``parameters`` given. Parameters and modulating functions are
    computed for all seeds at once; each motion's filter is the compiled one.

    With ``highpass_filter`` the motion runs :func:`settling_samples` past the modulated
    part, over which the high-pass filter comes to rest.

    ``until`` (s, or a function of a realisation's :class:`RezaeianParameters` giving seconds)
    keeps only the motion up to that time: the same samples as the whole motion's (every
    filter is causal), at a part of the cost."""
    rngs = [np.random.Generator(np.random.PCG64(int(seed))) for seed in seeds]
    count = len(rngs)
    warnings = []
    if parameters is None:
        from types import SimpleNamespace

        warnings = _site_warnings(SimpleNamespace(**site))
        values, _, _ = sample_parameters_batch(site["magnitude"], site["distance"], site["vs30"],
                                               site.get("mechanism", "strike_slip"), rngs)
    else:
        values = tuple(np.full(count, float(v)) for v in parameters.as_dict().values())
    a1, a2, a3 = gamma_envelopes(values[0], values[1], values[2])
    from scipy import special

    ends = special.gammaincinv(2.0 * a2 - 1.0, ENERGY_COVERED) / (2.0 * a3)
    motions = []
    for b, rng in enumerate(rngs):
        params = RezaeianParameters(*(float(v[b]) for v in values))
        env = GammaEnvelope(float(a1[b]), float(a2[b]), float(a3[b]))
        n = int(math.ceil(float(ends[b]) / step)) + 1  # the modulated motion
        total = n + (settling_samples(step) if highpass_filter else 0)
        if until is not None:
            stop = until(params) if callable(until) else until
            total = max(2, min(total, int(math.floor(float(stop) / step + 1e-9)) + 1))
        n = min(n, total)
        times = np.arange(total) * step
        omega, floored = filter_frequencies(params, times[:n])
        u = rng.standard_normal(n)
        acc = env(times[:n]) * filtered_unit(omega, u, params.damping, step)
        if highpass_filter:
            acc = highpass(np.concatenate([acc, np.zeros(total - n)]), step)
        notes = list(warnings)
        if floored:
            notes.append(f"stochastic motion: the filter frequency f_mid + f' (t - t_mid) "
                         f"falls below {FILTER_FLOOR_HZ:g} Hz within the motion and is held "
                         "there")
        acc.setflags(write=False)
        times.setflags(write=False)
        motions.append(StochasticMotion(times, acc, "rezaeian2010", int(seeds[b]),
                                        params.as_dict(), parameters is None, tuple(notes)))
    return motions


def highpass(acceleration: np.ndarray, step: float, corner_hz: float = HIGHPASS_HZ) -> np.ndarray:
    """The critically damped high-pass of Rezaeian & Der Kiureghian (2008): the relative
    acceleration z'' of z'' + 2 w_c z' + w_c^2 z = a(t) from rest, i.e. a - 2 w_c z' - w_c^2 z
    (transfer s^2 / (s + w_c)^2), exact for a linear between samples."""
    from scipy import signal

    num, den = _highpass_coefficients(float(step), float(corner_hz))
    return signal.lfilter(num, den, acceleration)


def settling_samples(step: float, corner_hz: float = HIGHPASS_HZ) -> int:
    """The zeros after a rezaeian2010 motion over which its high-pass filter comes to rest:
    :data:`HIGHPASS_SETTLE` / w_c, in steps (rounded up).

    The filter's state at the modulated motion's end, its velocity v_0 = z'(T) and
    displacement d_0 = z(T) (those of the filtered motion: z'' is it, from rest), then decays
    freely, critically damped (:func:`settling`): after s = w_c t_s the residual velocity is
    at most ((s - 1) |v_0| + s w_c |d_0|) e^-s, the displacement at most ((1 + s) |d_0| +
    s |v_0| / w_c) e^-s; s = 10: 4.5e-4 of (|v_0| + w_c |d_0|). Without it, the motion would
    stop with the residual velocity v_0 (up to a fifth of the peak velocity).
    """
    return int(math.ceil(HIGHPASS_SETTLE / (2.0 * math.pi * corner_hz) / step - 1e-9))


def settling(velocity: float, displacement: float, t, corner_hz: float = HIGHPASS_HZ):
    """(z'(t), z(t)) of the high-pass filter's free decay z'' + 2 w_c z' + w_c^2 z = 0 from
    z'(0) = ``velocity``, z(0) = ``displacement``: z = (d_0 + (v_0 + w_c d_0) t) e^(-w_c t)."""
    wc = 2.0 * math.pi * corner_hz
    t = np.asarray(t, float)
    decay = np.exp(-wc * t)
    slope = velocity + wc * displacement
    return ((velocity - wc * slope * t) * decay, (displacement + slope * t) * decay)


@functools.lru_cache(maxsize=16)
def _highpass_coefficients(step: float, corner_hz: float):
    from scipy import signal

    wc = 2.0 * math.pi * corner_hz
    num, den, _ = signal.cont2discrete(([1.0, 0.0, 0.0], [1.0, 2.0 * wc, wc * wc]), step,
                                       method="foh")
    return np.ravel(num), den


def clough_penzien_psd(omega, intensity, ground_frequency, ground_damping,
                       filter_frequency=0.0, filter_damping=0.0):
    """The two-sided Clough-Penzien PSD S(omega) ((m/s^2)^2 / (rad/s)) of ground
    acceleration, white-noise intensity ``intensity`` S_0 (m^2/s^3):

        S = S_0 (w_g^4 + 4 z_g^2 w_g^2 w^2) / ((w_g^2 - w^2)^2 + 4 z_g^2 w_g^2 w^2)
                * w^4 / ((w_f^2 - w^2)^2 + 4 z_f^2 w_f^2 w^2),

    the second factor 1 for ``filter_frequency`` 0 (Kanai-Tajimi)."""
    w2 = np.asarray(omega, dtype=float) ** 2
    wg2 = ground_frequency**2
    kt = (wg2 * wg2 + 4.0 * ground_damping**2 * wg2 * w2) / (
        (wg2 - w2) ** 2 + 4.0 * ground_damping**2 * wg2 * w2)
    if filter_frequency == 0.0:
        return intensity * kt
    wf2 = filter_frequency**2
    with np.errstate(invalid="ignore", divide="ignore"):
        cp = w2 * w2 / ((wf2 - w2) ** 2 + 4.0 * filter_damping**2 * wf2 * w2)
    return intensity * kt * np.nan_to_num(cp)


@functools.lru_cache(maxsize=16)
def clough_penzien_filter(step: float, wg: float, zg: float, wf: float = 0.0,
                          zf: float = 0.0) -> tuple[np.ndarray, np.ndarray]:
    """The zero-order-hold discretisation (b, a) on ``step`` (s) of the Clough-Penzien filters,
    from white noise to ground acceleration: H(s) = (2 z_g w_g s + w_g^2) / (s^2 + 2 z_g w_g s
    + w_g^2), times s^2 / (s^2 + 2 z_f w_f s + w_f^2) when ``wf`` > 0. Computed once per motion
    model (``scipy.signal.cont2discrete``, a matrix exponential), however many realisations
    are filtered with it; the arrays are read-only."""
    from scipy import signal

    num, den = np.array([2.0 * zg * wg, wg * wg]), np.array([1.0, 2.0 * zg * wg, wg * wg])
    if wf > 0.0:
        num = np.convolve(num, [1.0, 0.0, 0.0])
        den = np.convolve(den, [1.0, 2.0 * zf * wf, wf * wf])
    dnum, dden, _ = signal.cont2discrete((num, den), step, method="zoh")
    b, a = np.ravel(dnum), np.asarray(dden, float)
    b.setflags(write=False)
    a.setflags(write=False)
    return b, a


def clough_penzien_warmup(step: float, wg: float, zg: float, wf: float = 0.0,
                          zf: float = 0.0) -> int:
    """Samples filtered before a stationary Clough-Penzien process is kept: 30 time constants
    of its slowest filter, over which the filters forget their rest."""
    slow = min(zg * wg, zf * wf if wf > 0 else math.inf)
    return int(math.ceil(30.0 / max(slow, 1e-3) / step))


def clough_penzien_stationary(n: int, step: float, intensity, wg, zg, wf=0.0, zf=0.0,
                              rng=None) -> np.ndarray:
    """n samples (step s) of a stationary Clough-Penzien process: white noise of variance
    2 pi S_0 / dt held over each step, through the exact (zero-order-hold) discretisation of
    the filters (:func:`clough_penzien_filter`), after a warm-up that forgets the filters'
    rest (its PSD is S(omega) sinc^2(omega dt / 2) below the Nyquist frequency)."""
    from scipy import signal

    b, a = clough_penzien_filter(float(step), float(wg), float(zg), float(wf), float(zf))
    warm = clough_penzien_warmup(step, wg, zg, wf, zf)
    noise = rng.standard_normal(n + warm) * math.sqrt(2.0 * math.pi * intensity / step)
    return signal.lfilter(b, a, noise)[warm:]


def jennings(t, rise: float, plateau: float, decay: float):
    """Jennings, Housner & Tsai (1968): (t/t_1)^2 up to t_1 = ``rise``, 1 up to t_2 =
    ``plateau``, then exp(-c (t - t_2)), c = ``decay`` (1/s)."""
    t = np.asarray(t, dtype=float)
    return np.where(t < rise, (t / rise) ** 2,
                    np.where(t <= plateau, 1.0, np.exp(-decay * (t - plateau))))


# ----------------------------------------------------------------------------------------
# Measures of a motion


def arias_intensity(acceleration, step: float) -> float:
    """I_a = pi / (2 g) int a^2 dt (m/s), trapezoidal."""
    a2 = np.asarray(acceleration, float) ** 2
    return math.pi / (2.0 * G) * float(np.sum(a2[1:] + a2[:-1]) * 0.5 * step)


def husid(acceleration, step: float) -> np.ndarray:
    """The normalised cumulative Arias intensity (Husid curve) at every sample."""
    a2 = np.asarray(acceleration, float) ** 2
    cum = np.concatenate([[0.0], np.cumsum(0.5 * (a2[1:] + a2[:-1]) * step)])
    return cum / cum[-1] if cum[-1] > 0 else cum


def energy_times(cumulative, step: float, fractions=(0.05, 0.45, 0.95)) -> np.ndarray:
    """Times (s) at which a Husid curve reaches ``fractions`` (linear between samples)."""
    times = np.arange(len(cumulative)) * step
    return np.interp(fractions, cumulative, times)


def zero_crossings(acceleration, start: int = 0, stop: int | None = None) -> int:
    """The number of sign changes of the samples in [start, stop)."""
    a = np.asarray(acceleration, float)[start:stop]
    s = np.sign(a[a != 0.0])
    return int(np.count_nonzero(s[1:] != s[:-1]))


# ----------------------------------------------------------------------------------------
# A scene's stochastic excitation


@dataclass(frozen=True)
class StochasticMotion:
    """One realisation (before the excitation's ``scale``, which :func:`motion` applies)."""

    times: np.ndarray
    acceleration: np.ndarray
    model: str
    seed: int
    parameters: dict  # the model's parameters as used (sampled or given), SI and Hz
    sampled: bool  # the parameters were drawn from the site's predictive relations
    warnings: tuple = field(default=())

    @property
    def pga(self) -> float:
        return float(np.max(np.abs(self.acceleration))) if self.acceleration.size else 0.0

    @property
    def arias(self) -> float:
        return arias_intensity(self.acceleration, float(self.times[1] - self.times[0]))

    def description(self) -> str:
        """The model and its parameters, one line."""
        p = self.parameters
        if self.model == "rezaeian2010":
            how = "sampled from the site" if self.sampled else "given"
            return (f"stochastic rezaeian2010, seed {self.seed}, parameters {how}: I_a = "
                    f"{p['arias']:.4g} m/s, D5-95 = {p['d595']:.4g} s, t_mid = {p['tmid']:.4g} s,"
                    f" f_mid = {p['frequency']:.4g} Hz, f' = {p['slope']:.4g} Hz/s, zeta_f = "
                    f"{p['damping']:.4g}")
        text = (f"stochastic clough_penzien, seed {self.seed}: S_0 = {p['intensity']:.4g} "
                f"m^2/s^3, w_g = {p['ground_frequency']:.4g} rad/s, zeta_g = "
                f"{p['ground_damping']:.4g}")
        if p["filter_frequency"] > 0:
            text += (f", w_f = {p['filter_frequency']:.4g} rad/s, zeta_f = "
                     f"{p['filter_damping']:.4g}")
        return text + f", envelope {p['envelope']}"


def _site_warnings(excitation) -> list[str]:
    out = []
    for name, (lo, hi) in SITE_RANGE.items():
        value = getattr(excitation, name)
        if not lo <= value <= hi:
            out.append(f"stochastic motion: {name} {value:g} is outside {lo:g}-{hi:g}, the "
                       "range pframe accepts the predictive relations over without this "
                       "warning: the sampled parameters are extrapolated")
    return out


def generate(excitation) -> StochasticMotion:
    """The realisation of a scene's ``Stochastic`` excitation (cached on its fields; ``scale``
    is not applied)."""
    data = excitation.model_dump(mode="json")
    data.pop("scale", None)
    return _generate(json.dumps(data, sort_keys=True))


def generate_seeds(excitation, seeds) -> list[StochasticMotion]:
    """The realisations of a ``Stochastic`` excitation for each of ``seeds`` (its own seed is
    not used), each what :func:`generate` gives for that seed, bit for bit, without the cache
    (a suite or a study draws thousands once each): rezaeian2010's in one
    :func:`rezaeian_batch` (parameters and modulating functions computed for all at once),
    clough_penzien's one by one through the model's one discretised filter."""
    data = excitation.model_dump(mode="json")
    data.pop("scale", None)
    if data["model"] != "rezaeian2010":
        return [_generate.__wrapped__(json.dumps({**data, "seed": int(s)}, sort_keys=True))
                for s in seeds]
    given = data.get("parameters")
    site = {k: data[k] for k in ("magnitude", "distance", "vs30", "mechanism")}
    return rezaeian_batch([int(s) for s in seeds], float(data["step"]), None if given else site,
                          RezaeianParameters(**given) if given else None, data["highpass"])


def stochastic_record(excitation):
    """The realisation as an :class:`~pframe.excitation.characteristic.AppliedRecord` (what a
    record excitation gives the rest of pframe): its characteristic period is its mean period
    T_m, as a record's by default."""
    from pframe.excitation.characteristic import AppliedRecord, record_period

    m = generate(excitation)
    period, period_is = record_period("mean", m.times, m.acceleration)
    return AppliedRecord(m.times, m.acceleration, 1.0, 1.0, abs(float(excitation.scale)) * m.pga,
                         period, period_is)


def stochastic_warnings(excitation) -> list[str]:
    """What may make a scene's stochastic motion not the model's (site outside the range
    checked, filter frequency held at its floor); none for other excitations."""
    if excitation is None or excitation.kind != "stochastic":
        return []
    return list(generate(excitation).warnings)


@functools.lru_cache(maxsize=64)
def _generate(key: str) -> StochasticMotion:
    d = json.loads(key)
    rng = np.random.Generator(np.random.PCG64(int(d["seed"])))
    step, warnings = float(d["step"]), []
    if d["model"] == "rezaeian2010":
        given = d.get("parameters")
        site = {k: d[k] for k in ("magnitude", "distance", "vs30", "mechanism")}
        return rezaeian_batch([int(d["seed"])], step, None if given else site,
                              RezaeianParameters(**given) if given else None, d["highpass"])[0]
    else:
        env = d["envelope"] or {"kind": "none"}
        if env["kind"] == "jennings":
            duration = env["plateau"] - math.log(1e-3) / env["decay"]
        elif env["kind"] == "gamma":
            genv = gamma_envelope(1.0, env["d595"], env["tmid"])
            duration = genv.energy_time(ENERGY_COVERED)
        else:
            duration = float(d["duration"])
        n = int(math.ceil(duration / step)) + 1
        times = np.arange(n) * step
        x = clough_penzien_stationary(n, step, d["intensity"], d["ground_frequency"],
                                      d["ground_damping"], d["filter_frequency"],
                                      d["filter_damping"], rng)
        if env["kind"] == "jennings":
            q = jennings(times, env["rise"], env["plateau"], env["decay"])
        elif env["kind"] == "gamma":
            q = genv(times)
            q = q / np.max(q)
        else:
            q = np.ones(n)
        acc = q * x
        parameters = {k: d[k] for k in ("intensity", "ground_frequency", "ground_damping",
                                        "filter_frequency", "filter_damping")}
        parameters["envelope"] = env["kind"]
        sampled = False
    acc.setflags(write=False)
    times.setflags(write=False)
    return StochasticMotion(times, acc, d["model"], int(d["seed"]), parameters, sampled,
                            tuple(warnings))
