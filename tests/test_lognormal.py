"""The lognormal fit against samples of a known lognormal, scipy's censored fit and the closed form;
the interval-censored fit against a maximum of the likelihood found here by a generic optimiser and
by scipy's interval-censored fit; the bootstrap's coverage and its groups; bad input refused; the
Kaplan-Meier fractions by hand."""
import math

import numpy as np
import pytest

from fembeam.errors import InputError
from fembeam.studies.lognormal import bootstrap, empirical, fit, fit_censored, fit_interval, probability

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
        b = bootstrap([(str(i // 2), v, v) for i, v in enumerate(x)], n=150, seed=k, level=0.9)
        inside += b["theta"][0] <= THETA <= b["theta"][1]
    assert 0.8 <= inside / 150 <= 0.96


def test_bootstrap_resamples_groups_and_is_reproducible():
    samples = [("a", 0.3, 0.3), ("a", 0.31, 0.31), ("b", 0.5, 0.5), ("b", 0.52, 0.52), ("c", 0.82, math.inf),
               ("c", 0.8, 0.84)]
    one, two = bootstrap(samples, n=300, seed=7, design=0.25), bootstrap(samples, n=300, seed=7, design=0.25)
    assert one == two and one["groups"] == 3 and one["fitted"] + one["left_out"] == 300
    assert one["margin"] == pytest.approx([t / 0.25 for t in one["theta"]], rel=1e-12)
    assert 0 <= one["probability"][0] <= one["probability"][1] <= 1
    # a resample drawing group "c" three times has intervals that share [0.82, 0.84]: no fit, left out
    assert one["left_out"] > 0
    with pytest.raises(InputError):
        bootstrap(samples, n=5)
    # one group: every resample would be the sample itself
    with pytest.raises(InputError, match="at least two groups"):
        bootstrap([("a", 0.3, 0.33), ("a", 0.5, 0.55), ("a", 0.4, math.inf)], n=100)


def test_empirical_fractions():
    x, F = empirical([0.4, 0.1, 0.3, 0.2])
    assert x.tolist() == [0.1, 0.2, 0.3, 0.4] and F.tolist() == [0.25, 0.5, 0.75, 1.0]
    # censored at 0.15 leaves the count at risk after 0.1: S = 3/4, then 3/4 * 1/2, then 0
    x, F = empirical([0.1, 0.2, 0.3], [0.15])
    assert F.tolist() == pytest.approx([0.25, 0.625, 1.0], abs=1e-15)


def independent_interval_mle(lo, up):
    """The interval-censored maximum by Nelder-Mead on ``-sum ln(Phi(z(up)) - Phi(z(lo)))`` in
    ``(mu, ln beta)``, written without fembeam's code (scipy's normal distribution)."""
    from scipy import optimize, stats
    llo, lup = np.log(lo), np.log(up)

    def nll(p):
        mu, beta = p[0], math.exp(p[1])
        pr = stats.norm.cdf((lup - mu) / beta) - stats.norm.cdf((llo - mu) / beta)
        return -float(np.sum(np.log(np.maximum(pr, 1e-300))))
    mid = np.where(np.isfinite(lup), 0.5 * (llo + lup), llo)
    best = None
    for start in ([mid.mean(), math.log(mid.std())], [mid.mean() + 0.3, 0.0]):
        r = optimize.minimize(nll, start, method="Nelder-Mead",
                              options={"xatol": 1e-11, "fatol": 1e-13, "maxiter": 20000, "maxfev": 40000})
        best = r if best is None or r.fun < best.fun else best
    return math.exp(best.x[0]), math.exp(best.x[1]), -best.fun


def brackets(seed, n=30, ratio=1.05, cap=None):
    """Brackets of a collapse search: the true intensities of a known lognormal, each known only
    between a safe intensity and a collapse ``ratio`` above it placed at random around it;
    above ``cap`` right-censored at ``cap``."""
    rng = np.random.default_rng(seed)
    x = np.exp(rng.normal(math.log(THETA), BETA, n))
    lo = x / ratio ** rng.uniform(0.0, 1.0, n)
    up = lo * ratio
    if cap is not None:
        out = x > cap
        lo[out], up[out] = cap, math.inf
    return lo, up


@pytest.mark.parametrize("seed, ratio, cap", [(1, 1.05, None), (2, 1.05, 0.7), (3, 1.3, 0.6), (4, 1.01, None)])
def test_interval_fit_is_the_maximum_of_the_interval_likelihood(seed, ratio, cap):
    from scipy import stats
    lo, up = brackets(seed, ratio=ratio, cap=cap)
    f = fit_interval(lo, up)
    th, be, best = independent_interval_mle(lo, up)
    assert f.method == "interval_censored" and f.n_collapsed + f.n_censored == lo.size
    assert f.n_censored == int(np.sum(np.isinf(up)))
    assert f.theta == pytest.approx(th, rel=1e-6) and f.beta == pytest.approx(be, rel=1e-5)
    # scipy's own interval-censored fit (a third route)
    fin = np.isfinite(up)
    data = stats.CensoredData(interval=np.log(np.c_[lo[fin], up[fin]]), right=np.log(lo[~fin]))
    mu, sd = stats.norm.fit(data)
    assert math.log(f.theta) == pytest.approx(mu, abs=1e-3) and f.beta == pytest.approx(sd, abs=1e-3)
    # and the likelihood there is at least as high as the optimiser's
    ll = float(np.sum(np.log(stats.norm.cdf((np.log(up) - math.log(f.theta)) / f.beta)
                             - stats.norm.cdf((np.log(lo) - math.log(f.theta)) / f.beta))))
    assert ll >= best - 1e-9


def test_interval_fit_of_narrow_brackets_and_exact_samples_is_the_closed_form():
    x = np.exp(np.random.default_rng(5).normal(math.log(THETA), BETA, 50))
    exact = fit(x)
    same = fit_interval(x, x)                          # lower = upper: exactly known
    assert same.theta == pytest.approx(exact.theta, rel=1e-12) and same.beta == pytest.approx(exact.beta, rel=1e-10)
    narrow = fit_interval(x / 1.000001, x)
    assert narrow.theta == pytest.approx(exact.theta, rel=1e-6) and narrow.beta == pytest.approx(exact.beta, rel=1e-5)


def test_upper_ends_as_exact_bias_the_median_upward():
    """Brackets 5 % wide fitted as if their upper ends were exact put the median about half a
    bracket (2.5 %) above the interval fit; the interval fit is within the sampling error of the
    truth (2000 samples: standard error of ln theta 0.9 %)."""
    lo, up = brackets(6, n=2000)
    upper_as_exact, interval = fit(up), fit_interval(lo, up)
    assert upper_as_exact.theta / interval.theta - 1 == pytest.approx(0.5 * math.log(1.05), abs=2e-3)
    assert abs(math.log(interval.theta / THETA)) < 4 * BETA / math.sqrt(2000)


@pytest.mark.parametrize("lower, upper, match", [
    ([], [], "at least one sample"),
    ([0.3, 0.4], [0.33], "lower bounds but"),
    ([0.3, math.nan], [0.33, 0.5], "positive finite"),
    ([0.3, math.inf], [0.33, math.inf], "positive finite"),
    ([0.3, -0.4], [0.33, 0.5], "positive finite"),
    ([0.3, 0.0], [0.33, 0.5], "positive finite"),
    ([0.3, 0.4], [0.33, math.nan], "upper intensities"),
    ([0.3, 0.4], [0.33, -1.0], "upper intensities"),
    ([0.3, 0.5], [0.33, 0.45], "upper intensity is below"),
    ([0.3, "x"], [0.33, 0.5], "must be numbers"),
    ([0.3], [0.33], "two different"),
    ([0.3, 0.31, 0.2], [0.33, 0.34, math.inf], "two different"),      # all share [0.31, 0.33]
    ([0.3, 0.33], [0.33, 0.36], "two different"),                       # share one point
])
def test_interval_fit_refuses_bad_input(lower, upper, match):
    with pytest.raises(InputError, match=match):
        fit_interval(lower, upper)


@pytest.mark.parametrize("collapsed, censored, match", [
    ([], [], "two different"),
    ([0.3], [], "two different"),
    ([0.3, math.nan], [], "positive finite"),
    ([0.3, 0.4], [math.inf], "positive finite"),
    ([0.3, 0.4], [-1.0], "positive finite"),
    ([0.3, "x"], [], "positive finite"),
])
def test_exact_fits_refuse_bad_input(collapsed, censored, match):
    for f in (fit, fit_censored):
        with pytest.raises(InputError, match=match):
            f(collapsed, censored)


def test_bootstrap_refuses_bad_samples():
    with pytest.raises(InputError, match="upper intensity is below"):
        bootstrap([("a", 0.3, 0.2), ("b", 0.4, 0.5)], n=20)
    with pytest.raises(InputError, match="positive finite"):
        bootstrap([("a", -0.3, 0.2), ("b", 0.4, 0.5)], n=20)
    with pytest.raises(InputError, match="design"):
        bootstrap([("a", 0.3, 0.33), ("b", 0.4, 0.5)], n=20, design=0.0)
