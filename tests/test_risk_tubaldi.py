"""The mean annual frequency of pounding of two elastic SDOFs under a stationary Gaussian
ground acceleration, as a first-passage problem (Tubaldi, Barbato & Ghazizadeh 2012):
the spectral moments of the relative displacement against the white-noise closed form,
Vanmarcke's first-passage probability against pframe's runs within their Monte Carlo
confidence plus the approximation's known bias, then the mean annual frequency over a
hazard curve; docs/risk.md shows the numbers this recomputes."""

from __future__ import annotations

import math
import re
from pathlib import Path

import numpy as np
import pytest

from pframe.gap.rules import cqc_correlation
from pframe.risk.firstpassage import (
    Moments,
    check_text,
    relative_moments,
    rice,
    tubaldi_check,
    vanmarcke,
)

REPO = Path(__file__).resolve().parents[1]
#: Vanmarcke's approximation errs on the conservative side at moderate barriers (6-11 % of
#: P_f here at eta 2-3, q = 0.3). 12 % still tells the one-sided barrier's clump factor,
#: exp(-sqrt(2 pi) q^1.2 eta), from the two-sided one's, exp(-sqrt(pi / 2) q^1.2 eta)
BIAS = 0.12


@pytest.mark.parametrize("ta, tb, za, zb", [(0.5, 1.0, 0.05, 0.05), (0.3, 0.45, 0.02, 0.07)])
def test_relative_displacement_variance_under_white_noise_is_the_cqc_closed_form(ta, tb, za, zb):
    """White noise S_0: sigma_j^2 = pi S_0 / (2 z_j w_j^3), and the correlation of the two
    displacements is Der Kiureghian's CQC coefficient (exact for white noise), so
    sigma_r^2 = sigma_A^2 + sigma_B^2 - 2 rho sigma_A sigma_B."""
    s0 = 0.02
    m = relative_moments(lambda w: s0 + 0 * np.asarray(w), (ta, tb), (za, zb))
    sa, sb = (math.sqrt(math.pi * s0 / (2 * z * (2 * math.pi / t) ** 3))
              for t, z in ((ta, za), (tb, zb)))
    rho = cqc_correlation(ta, tb, za, zb)
    assert m.l0 == pytest.approx(sa * sa + sb * sb - 2 * rho * sa * sb, rel=1e-7)
    assert 0 < m.bandwidth < 1 and m.rate > 0


def test_vanmarcke_rate_lies_below_rices_and_tends_to_it_in_the_tail():
    """Above two sigma, Vanmarcke's decay rate (a clump of crossings counts once) is below
    Rice's Poisson rate nu_0 exp(-eta^2 / 2), and it meets it at high barriers, where
    crossings are rare and independent. (Below, its clump factor exceeds 1.)"""
    from scipy.stats import norm

    m = Moments(1.0, 1.0 / 0.9, 1.0 / 0.9 ** 2 * 1.2)  # q about 0.4
    eta = np.array([2.0, 3.0, 4.0, 5.0, 6.0])
    t = 30.0
    rate = -np.log((1 - vanmarcke(eta, m, t)) / norm.cdf(eta)) / t
    poisson = m.rate * np.exp(-eta ** 2 / 2)
    assert np.all(rate < poisson) and rate[-1] / poisson[-1] == pytest.approx(1.0, rel=0.01)
    assert np.all(np.diff(vanmarcke(eta, m, t)) < 0)
    assert -np.expm1(-poisson * t) == pytest.approx(rice(eta, m, t), rel=1e-12)


@pytest.fixture(scope="module")
def check():
    return tubaldi_check(threads=2)


@pytest.mark.slow
def test_first_passage_probability_against_pframes_runs(check):
    """1,000 runs of 10 s (after 10 s that forget the rest) under stationary
    Clough-Penzien input: the share whose u_A - u_B passes b = eta sigma equals Vanmarcke's
    P_f within the 99 % Monte Carlo interval plus the approximation's bias."""
    n = check.realisations
    for eta, s, v in zip(check.eta, check.simulated, check.vanmarcke):
        half = 2.58 * math.sqrt(max(s * (1 - s), 1.0 / n) / n)
        assert abs(v - s) <= half + BIAS * v, (eta, s, v)
    assert 0.05 < check.simulated[3] < 0.5  # the range of barriers says something


@pytest.mark.slow
def test_mean_annual_frequency_of_pounding_against_pframes_runs(check):
    """The MAF over lambda = 1e-5 IM^-3 from Vanmarcke's fragility equals the one from the
    runs' maxima (each scaled with the IM: the pair is linear) within the runs' 95 %
    bootstrap interval widened by the approximation's bias."""
    lo, hi = check.maf_simulated_range
    assert lo / (1 + BIAS) <= check.maf_vanmarcke <= hi * (1 + BIAS)
    assert lo <= check.maf_simulated <= hi


@pytest.mark.slow
def test_docs_show_the_check_as_it_runs(check):
    text = (REPO / "docs" / "risk.md").read_text()
    block = re.search(r"<!-- BEGIN tubaldi -->\n```text\n(.*?)```\n<!-- END tubaldi -->",
                      text, re.S)
    assert block, "docs/risk.md lacks the first-passage block"
    assert block.group(1).strip() == check_text(check).strip()
