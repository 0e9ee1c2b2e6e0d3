"""The lognormal fit against samples of a known lognormal, scipy's censored fit and the closed form;
the bootstrap's coverage; the Kaplan-Meier fractions by hand."""
import math

import numpy as np
import pytest

from fembeam.errors import InputError
from fembeam.studies.lognormal import bootstrap, empirical, fit, fit_censored, probability

THETA, BETA = 0.5, 0.4


def loglik(y, c, mu, beta):
    from scipy.stats import norm
    return float(np.sum(norm.logpdf(y, mu, beta)) + np.sum(norm.logsf(c, mu, beta)))


def test_fit_recovers_a_known_lognormal():
    n = 20_000
    x = np.exp(np.random.default_rng(3).normal(math.log(THETA), BETA, n))
    f = fit(x)
    se = BETA / math.sqrt(n)                       # standard error of ln theta; of beta: BETA / sqrt(2 n)
    assert abs(math.log(f.theta / THETA)) < 4 * se and abs(f.beta - BETA) < 4 * BETA / math.sqrt(2 * n)
    assert f.method == "closed_form" and f.n_collapsed == n and f.n_censored == 0
    # the closed form is the maximum: Newton's method on the likelihood lands on it
    g = fit_censored(x, [])
    assert g.theta == pytest.approx(f.theta, rel=1e-12) and g.beta == pytest.approx(f.beta, rel=1e-10)
    assert probability(THETA, THETA, BETA) == pytest.approx(0.5, abs=1e-15)


def test_censored_fit_against_scipy_and_the_truth():
    from scipy import stats
    x = np.exp(np.random.default_rng(4).normal(math.log(THETA), BETA, 2000))
    cap = 0.7                                      # 80 % collapse below it; the rest censored there
    y, c = np.log(x[x <= cap]), np.full(int(np.sum(x > cap)), math.log(cap))
    f = fit(np.exp(y), np.exp(c))
    assert f.method == "newton" and f.n_censored == c.size > 200
    assert abs(math.log(f.theta / THETA)) < 0.03 and abs(f.beta - BETA) < 0.03
    mu, sd = stats.norm.fit(stats.CensoredData(uncensored=y, right=c))      # scipy's generic optimiser
    assert math.log(f.theta) == pytest.approx(mu, abs=1e-3) and f.beta == pytest.approx(sd, abs=1e-3)
    assert loglik(y, c, math.log(f.theta), f.beta) >= loglik(y, c, mu, sd) - 1e-9    # ours is at least as high


def test_fit_needs_two_different_collapses():
    with pytest.raises(InputError, match="two different"):
        fit([0.3], [1.0, 1.0])
    with pytest.raises(InputError, match="all equal"):
        fit([0.3, 0.3])
    with pytest.raises(InputError, match="positive"):
        fit([0.3, -1.0])


def test_bootstrap_interval_covers_the_median():
    """Percentile intervals at 90 % from 40 groups of 2 samples: the true median inside in
    about 87 % of 150 experiments (the percentile interval covers a little less than its level
    with few groups: 87.4 % in 500 experiments, 89.4 % with 150 groups; binomial standard
    deviation 2.7 %)."""
    rng = np.random.default_rng(11)
    inside = 0
    for k in range(150):
        x = np.exp(rng.normal(math.log(THETA), BETA, 80))
        b = bootstrap([(str(i // 2), v, False) for i, v in enumerate(x)], n=150, seed=k, level=0.9)
        inside += b["theta"][0] <= THETA <= b["theta"][1]
    assert 0.8 <= inside / 150 <= 0.96


def test_bootstrap_resamples_groups_and_is_reproducible():
    samples = [("a", 0.3, False), ("a", 0.31, False), ("b", 0.5, False), ("b", 0.52, False), ("c", 0.9, True),
               ("c", 0.8, False)]
    one, two = bootstrap(samples, n=300, seed=7, design=0.25), bootstrap(samples, n=300, seed=7, design=0.25)
    assert one == two and one["groups"] == 3 and one["fitted"] + one["left_out"] == 300
    assert one["margin"] == pytest.approx([t / 0.25 for t in one["theta"]], rel=1e-12)
    assert 0 <= one["probability"][0] <= one["probability"][1] <= 1
    # a resample drawing group "c" three times has one collapse intensity: no fit, left out
    assert one["left_out"] > 0
    with pytest.raises(InputError):
        bootstrap(samples, n=5)


def test_empirical_fractions():
    x, F = empirical([0.4, 0.1, 0.3, 0.2])
    assert x.tolist() == [0.1, 0.2, 0.3, 0.4] and F.tolist() == [0.25, 0.5, 0.75, 1.0]
    # censored at 0.15 leaves the count at risk after 0.1: S = 3/4, then 3/4 * 1/2, then 0
    x, F = empirical([0.1, 0.2, 0.3], [0.15])
    assert F.tolist() == pytest.approx([0.25, 0.625, 1.0], abs=1e-15)
