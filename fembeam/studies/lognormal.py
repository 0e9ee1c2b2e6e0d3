"""Lognormal collapse fragility: maximum-likelihood fit, bootstrap intervals, margin at a design level.

``P(collapse | IM = x) = Phi(ln(x / theta) / beta)``: ``theta`` the median collapse intensity
(the intensity's unit: g, or m/s for PGV), ``beta`` the dispersion (standard deviation of
``ln IM`` at collapse, dimensionless).  With ``mu = ln theta`` and ``z(x) = (ln x - mu) / beta``:

* **Interval-censored samples** (:func:`fit_interval`, what a collapse search gives): sample ``i``
  is known only to lie in ``[l_i, u_i]``: a record-sign's first collapse lies between the
  intensity of the last safe factor run below it and that of the first collapse found;
  ``u_i = inf`` when no collapse was found up to ``l_i`` (right-censored).  The log-likelihood is

      l(mu, beta) = sum_i ln(Phi(z(u_i)) - Phi(z(l_i))),

  with the exactly known samples (``l_i = u_i``), if any, entering as ``-z_i^2 / 2 - ln beta``.
  It is concave in Olsen's parameters ``delta = mu / beta``, ``h = 1 / beta`` and maximised by
  Newton's method.  The maximum exists when the intervals do not all share a point.
* **Exact and right-censored samples** (:func:`fit`, :func:`fit_censored`): the intensities
  ``x_i`` and lower bounds ``c_j``,

      l(mu, beta) = sum_i [-z_i^2 / 2 - ln beta] + sum_j ln(1 - Phi(z_j))     (constants dropped).

  Without censored samples its maximum is closed-form: ``mu = mean(y)``, ``beta^2 = mean((y -
  mu)^2)`` (``y = ln x``; the 1/n variance: maximum likelihood, not the unbiased 1/(n-1)).  With
  them it is found by Newton's method from the closed-form fit of the collapsed samples, in
  Olsen's parameters, until its gradient vanishes.  The maximum exists when at least two
  collapsed intensities differ.  Treating the upper end of a collapse bracket as exact biases the
  median upward by up to one bracket (the search's resolution): :func:`fit_interval` is the fit of
  what a search knows.

Confidence intervals come from a bootstrap (Efron's percentile intervals): ``n`` resamples, each
drawing the groups (the components of one recording, with both signs) with replacement, so that
correlated samples leave or enter together; the seed fixes them.  It needs at least two groups.
The collapse margin ratio at a design intensity ``x_d`` is ``theta / x_d`` and the probability of
collapse there ``Phi(ln(x_d / theta) / beta)``; their intervals are the percentiles of the same
resamples.  Every function refuses bad input (no sample, a non-finite or non-positive
intensity, an upper bound below its lower one) with :class:`~fembeam.errors.InputError`.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..errors import InputError, SolverError

__all__ = ["LognormalFit", "fit", "fit_censored", "fit_interval", "bootstrap", "probability", "empirical",
           "NEWTON_STEPS"]

NEWTON_STEPS = 100


@dataclass(frozen=True)
class LognormalFit:
    """``theta`` (median, the unit of the intensity), ``beta`` (dispersion, dimensionless), the
    numbers of collapsed and right-censored samples, and ``method`` (``closed_form``, ``newton``
    or ``interval_censored``).

    Examples
    --------
    :func:`fit` returns it: the median collapse intensity (here PGA, g), the
    dispersion, and the probability of collapse at an intensity:

    >>> from fembeam.studies.lognormal import fit
    >>> f = fit([0.31, 0.42, 0.55, 0.38], censored=[0.6])
    >>> print(f"theta = {f.theta:.3f} g, beta = {f.beta:.3f};",
    ...       f.n_collapsed, "collapsed,", f.n_censored, "censored")
    theta = 0.453 g, beta = 0.292; 4 collapsed, 1 censored
    >>> print(f"P(collapse at 0.4 g) = {f.probability(0.4):.3f}")
    P(collapse at 0.4 g) = 0.335
    """

    theta: float
    beta: float
    n_collapsed: int
    n_censored: int
    method: str

    def probability(self, x) -> np.ndarray:
        return probability(x, self.theta, self.beta)


def probability(x, theta: float, beta: float):
    """``Phi(ln(x / theta) / beta)``."""
    from scipy.special import ndtr
    return ndtr(np.log(np.asarray(x, dtype=float) / theta) / beta)


def _logs(values, name: str) -> np.ndarray:
    try:
        y = np.asarray(values, dtype=float).ravel()
    except (TypeError, ValueError):
        raise InputError(f"the {name} intensities must be positive finite numbers, got {values!r}") from None
    if y.size and not (np.all(np.isfinite(y)) and np.all(y > 0)):
        raise InputError(f"the {name} intensities must be positive finite numbers")
    return np.log(y)


def _two_different(y: np.ndarray) -> None:
    if y.size < 2 or np.ptp(y) <= 1e-12 * max(1.0, float(np.max(np.abs(y)))):
        raise InputError(f"a lognormal fit needs at least two different collapse intensities, got {y.size} "
                         f"collapsed sample(s){' (all equal)' if y.size >= 2 else ''}")


def fit(collapsed, censored=()) -> LognormalFit:
    """Maximum-likelihood lognormal fit of exact and right-censored collapse intensities.

    ``P(collapse | IM = x) = Phi(ln(x / theta) / beta)``. Without censored samples the
    maximum is closed-form (``ln theta`` the mean of ``ln x``, ``beta`` the 1/n standard
    deviation); with them it is found by Newton's method (:func:`fit_censored`). The
    likelihoods are those of :mod:`fembeam.studies.lognormal`.

    Parameters
    ----------
    collapsed : array_like of float
        Intensities at collapse, known exactly, in the intensity's unit (g, or m/s for
        PGV); positive and finite, at least two different ones.
    censored : array_like of float, optional
        Right-censored samples: intensities (same unit) up to which no collapse was found,
        i.e. lower bounds of the collapse intensity. None by default.

    Returns
    -------
    LognormalFit
        ``theta`` (median collapse intensity, the intensity's unit), ``beta`` (dispersion
        of ``ln IM``, dimensionless), the counts of collapsed and censored samples and the
        ``method`` (``"closed_form"`` or ``"newton"``).

    Raises
    ------
    InputError
        Fewer than two different collapsed intensities (the maximum does not exist), or
        an intensity that is not a positive finite number.
    SolverError
        Newton's method did not converge (censored samples only).

    See Also
    --------
    fit_interval : the fit of interval-censored samples, what a collapse search gives.
    bootstrap : confidence intervals of ``theta`` and ``beta``.

    Examples
    --------
    >>> from fembeam.studies.lognormal import fit
    >>> f = fit([0.31, 0.42, 0.55, 0.38])
    >>> print(f.method, f"theta = {f.theta:.3f} g, beta = {f.beta:.3f}")
    closed_form theta = 0.406 g, beta = 0.206
    >>> print(f"P(collapse at 0.4 g) = {f.probability(0.4):.3f}")
    P(collapse at 0.4 g) = 0.471

    One record that did not collapse up to 0.6 g raises the median:

    >>> f = fit([0.31, 0.42, 0.55, 0.38], censored=[0.6])
    >>> print(f.method, f"theta = {f.theta:.3f} g, beta = {f.beta:.3f}")
    newton theta = 0.453 g, beta = 0.292
    """
    y, c = _logs(collapsed, "collapse"), _logs(censored, "censored")
    _two_different(y)
    if c.size == 0:
        mu = float(np.mean(y))
        return LognormalFit(math.exp(mu), float(np.sqrt(np.mean((y - mu) ** 2))), int(y.size), 0, "closed_form")
    return fit_censored(np.exp(y), np.exp(c))


def fit_censored(collapsed, censored) -> LognormalFit:
    """The likelihood maximised by Newton's method (also without censored samples: a check of
    the closed form).  In Olsen's parameters ``delta = mu / beta``, ``h = 1 / beta``
    (``z = h y - delta``) it is concave, so Newton's steps, halved until the likelihood rises
    (or moves by less than its round-off), reach its maximum; :class:`SolverError` if the gradient is not zero after
    :data:`NEWTON_STEPS` steps."""
    from scipy.special import log_ndtr

    y, c = _logs(collapsed, "collapse"), _logs(censored, "censored")
    _two_different(y)
    n = y.size

    def value(delta: float, h: float) -> float:
        z = h * y - delta
        return n * math.log(h) - 0.5 * float(z @ z) + float(np.sum(log_ndtr(delta - h * c)))

    h = 1.0 / max(float(np.std(y)), 1e-6)
    delta = float(np.mean(y)) * h
    for _ in range(NEWTON_STEPS):
        z, zc = h * y - delta, h * c - delta
        m = np.exp(-0.5 * zc * zc - 0.5 * math.log(2 * math.pi) - log_ndtr(-zc))      # phi / (1 - Phi)
        dm = m * (m - zc)                                                               # m'(z)
        g = np.array([np.sum(z) + np.sum(m), n / h - z @ y - m @ c])
        H = np.array([[-n - np.sum(dm), np.sum(y) + dm @ c], [0.0, -n / h ** 2 - y @ y - dm @ (c * c)]])
        H[1, 0] = H[0, 1]
        if max(abs(g[0]), abs(g[1] * h)) <= 1e-9 * (n + c.size):
            return LognormalFit(math.exp(delta / h), float(1.0 / h), int(n), int(c.size), "newton")
        step = -np.linalg.solve(H, g)
        now, t = value(delta, h), 1.0
        while h + t * step[1] <= 0 or value(delta + t * step[0], h + t * step[1]) < now - 1e-13 * abs(now):
            t *= 0.5
            if t < 1e-12:
                break
        delta, h = delta + t * step[0], h + t * step[1]
    raise SolverError(f"the censored lognormal fit did not converge in {NEWTON_STEPS} Newton steps (gradient {g})")


def _interval_logp(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """``ln(Phi(b) - Phi(a))`` for ``a < b`` (``b`` may be ``+inf``): the difference taken on the
    side of zero where it does not cancel (``Phi(-a) - Phi(-b)`` when ``a > 0``), and in logarithms
    where it would underflow (beyond about 37 standard deviations)."""
    from scipy.special import log_ndtr, ndtr

    up = a > 0
    lo_, hi_ = np.where(up, -b, a), np.where(up, -a, b)
    with np.errstate(divide="ignore", invalid="ignore"):
        out = np.log(ndtr(hi_) - ndtr(lo_))
        tiny = ~(out > -500.0)
        if np.any(tiny):
            lh, ll = log_ndtr(hi_[tiny]), log_ndtr(lo_[tiny])
            out[tiny] = lh + np.log(-np.expm1(np.minimum(ll - lh, -1e-300)))
    return out


def _bounds(lower, upper) -> tuple[np.ndarray, np.ndarray]:
    """``ln`` of the bounds of intervals ``[lower, upper]`` checked (:class:`InputError`): as many
    lower as upper bounds, at least one, the lower ones positive and finite, the upper ones
    positive (``inf`` or None: right-censored), none below its lower bound."""
    try:
        lo = np.asarray(lower, dtype=float).ravel()
        up = np.array([math.inf if v is None else v for v in np.asarray(upper, dtype=object).ravel()], dtype=float)
    except (TypeError, ValueError):
        raise InputError("the intervals' intensities must be numbers (the upper ones inf or None when censored)") \
            from None
    if lo.size == 0:
        raise InputError("a lognormal fit needs at least one sample, got none")
    if lo.size != up.size:
        raise InputError(f"{lo.size} lower bounds but {up.size} upper bounds")
    if not (np.all(np.isfinite(lo)) and np.all(lo > 0)):
        raise InputError("the lower intensities must be positive finite numbers")
    if np.any(np.isnan(up)) or np.any(up <= 0) or np.any(up == -math.inf):
        raise InputError("the upper intensities must be positive numbers (inf: right-censored)")
    if np.any(up < lo):
        i = int(np.argmax(up < lo))
        raise InputError(f"an interval's upper intensity is below its lower one: [{lo[i]:g}, {up[i]:g}]")
    return np.log(lo), np.log(up)


def fit_interval(lower, upper, start: tuple[float, float] | None = None) -> LognormalFit:
    """Maximum-likelihood lognormal of interval-censored intensities: sample ``i`` is known to
    lie in ``[lower_i, upper_i]`` (in the intensity's unit; ``upper_i = inf`` or None: only above
    ``lower_i``, right-censored; ``lower_i = upper_i``: exactly known).  With ``z = (ln x - mu) /
    beta`` the log-likelihood is

        l = sum_exact [-z_i^2 / 2 - ln beta] + sum_other ln(Phi(z(upper_i)) - Phi(z(lower_i))),

    concave in Olsen's parameters ``delta = mu / beta``, ``h = 1 / beta`` (the normal
    probability of an interval is log-concave in its ends, which are affine in them); Newton's
    steps, halved until the likelihood rises, reach its maximum.  It is attained (``beta > 0``
    finite) unless the closed intervals share a point, e.g. a single sample or brackets that all
    overlap: then the likelihood grows without end as ``beta -> 0`` and :class:`InputError` says so,
    as it does for bad input (:func:`_bounds`).  :class:`SolverError` if the gradient is not zero
    after :data:`NEWTON_STEPS` steps.  ``method`` ``"interval_censored"``; ``n_collapsed`` counts
    the samples with a finite upper bound, ``n_censored`` the others.  ``start``: ``(theta,
    beta)`` to start from (a bootstrap starts each resample from the sample's fit)."""
    lo, up = _bounds(lower, upper)
    if np.max(lo) <= np.min(up) + 1e-12:             # logarithms: the closed intervals share a point
        raise InputError(f"a lognormal fit needs at least two different collapse intensities: the intervals of the "
                         f"{lo.size} sample(s) share the intensity {math.exp(np.max(lo)):.6g} (the likelihood grows "
                         "without end as the dispersion goes to 0)")
    return _newton_interval(lo, up, start)


_LOG_SQRT_2PI = 0.5 * math.log(2 * math.pi)


def _newton_interval(lo: np.ndarray, up: np.ndarray, start: tuple[float, float] | None) -> LognormalFit:
    """The Newton iteration of :func:`fit_interval` on checked ``ln`` bounds, from ``start``
    ``(theta, beta)`` or from the moments of the intervals' midpoints."""
    exact = up == lo
    counts = (int(np.sum(np.isfinite(up))), int(np.sum(~np.isfinite(up))))
    y = lo[exact]
    ne = y.size
    if ne == lo.size:                               # every sample exact: the closed form is the maximum
        mu = float(np.mean(y))
        return LognormalFit(math.exp(mu), float(np.sqrt(np.mean((y - mu) ** 2))), *counts, "interval_censored")
    ia, ib = lo[~exact], up[~exact]
    fin = np.isfinite(ib)
    ibf = np.where(fin, ib, 0.0)

    def state(delta: float, h: float):
        a, b = h * ia - delta, h * ib - delta
        logp = _interval_logp(a, b)
        z = h * y - delta
        return ne * math.log(h) - 0.5 * float(z @ z) + float(np.sum(logp)), z, a, b, logp

    if start is None or not all(math.isfinite(v) and v > 0 for v in start):
        mid = np.where(np.isfinite(up), 0.5 * (lo + up), lo)
        sd = max(float(np.std(mid)), 0.25 * float(np.ptp(np.concatenate([lo, up[np.isfinite(up)]]))), 1e-3)
        h, delta = 1.0 / sd, float(np.mean(mid)) / sd
    else:
        h = 1.0 / float(start[1])
        delta = math.log(float(start[0])) * h
    now, z, a, b, logp = state(delta, h)
    g = np.zeros(2)
    for _ in range(NEWTON_STEPS):
        ra = np.exp(-0.5 * a * a - _LOG_SQRT_2PI - logp)
        bf = np.where(fin, b, 0.0)
        rb = np.where(fin, np.exp(-0.5 * bf * bf - _LOG_SQRT_2PI - logp), 0.0)
        laa, lbb, lab = a * ra - ra * ra, -bf * rb - rb * rb, ra * rb
        g = np.array([np.sum(z) + np.sum(ra - rb), ne / h - z @ y + np.sum(rb * ibf - ra * ia)])
        if max(abs(g[0]), abs(g[1] * h)) <= 1e-9 * lo.size:
            return LognormalFit(math.exp(delta / h), float(1.0 / h), *counts, "interval_censored")
        H = np.empty((2, 2))
        H[0, 0] = -ne + np.sum(laa + 2 * lab + lbb)
        H[0, 1] = H[1, 0] = np.sum(y) - np.sum(laa * ia + lab * (ia + ibf) + lbb * ibf)
        H[1, 1] = -ne / h ** 2 - y @ y + np.sum(laa * ia * ia + 2 * lab * ia * ibf + lbb * ibf * ibf)
        try:
            step = -np.linalg.solve(H, g)
        except np.linalg.LinAlgError:
            step = g.copy()
        if step @ g <= 0:                           # not an ascent direction (round-off): the gradient
            step = g / max(1.0, float(np.max(np.abs(g))))
        t = 1.0
        while True:
            d1, h1 = delta + t * step[0], h + t * step[1]
            if h1 > 0:
                trial = state(d1, h1)
                if trial[0] >= now - 1e-13 * abs(now) or t < 1e-12:
                    break
            elif t < 1e-12:
                trial = state(delta, h)
                d1, h1 = delta, h
                break
            t *= 0.5
        delta, h = d1, h1
        now, z, a, b, logp = trial
    raise SolverError(f"the interval-censored lognormal fit did not converge in {NEWTON_STEPS} Newton steps "
                      f"(gradient {g})")


def bootstrap(samples: list[tuple[str, float, float]], n: int = 1000, seed: int = 0, level: float = 0.9,
              design: float | None = None) -> dict:
    """Bootstrap percentile intervals of a lognormal fragility, resampling groups.

    Each of ``n`` resamples draws the groups (e.g. the components of one recording, with
    both signs) with replacement, so that correlated samples leave or enter together, and
    is refitted by :func:`fit_interval`. The intervals are Efron's percentile intervals of
    the refitted values. Resamples without a fit (intervals that all share a point) are
    left out and counted.

    Parameters
    ----------
    samples : sequence of (str, float, float or None)
        ``(group, lower, upper)``: the collapse intensity of each sample lies in
        ``[lower, upper]`` (the intensity's unit: g, or m/s for PGV); ``upper`` inf or
        None: right-censored at ``lower``; ``lower == upper``: known exactly.
    n : int, optional
        Resamples, in [10, 100000] (default 1000).
    seed : int, optional
        Seed of the resampling (default 0): the same seed gives the same intervals.
    level : float, optional
        Confidence level of the intervals, in [0.5, 1) (default 0.9: the 5 % and 95 %
        percentiles).
    design : float, optional
        A design intensity (the intensity's unit, > 0): the intervals of the collapse
        margin ratio ``theta / design`` and of the probability of collapse there are added.

    Returns
    -------
    dict
        ``theta`` and ``beta`` (each ``[low, high]``; ``theta`` in the intensity's unit,
        ``beta`` dimensionless), with ``design`` also ``margin`` and ``probability``;
        ``resamples``, ``fitted`` and ``left_out`` (resamples without a fit), ``level``,
        ``seed`` and ``groups`` (the number of groups).

    Raises
    ------
    InputError
        Fewer than two groups (every resample would be the sample itself), no resample
        with a fit, or bad input (``n``, ``level``, ``design`` or an interval out of range).

    See Also
    --------
    fit_interval : the fit of each resample.

    Examples
    --------
    Three recordings of two components each; one component did not collapse up to 0.48 g:

    >>> from fembeam.studies.lognormal import bootstrap
    >>> samples = [("A", 0.30, 0.33), ("A", 0.35, 0.38), ("B", 0.41, 0.45),
    ...            ("B", 0.48, None), ("C", 0.25, 0.28), ("C", 0.36, 0.40)]
    >>> out = bootstrap(samples, n=200, seed=1, design=0.3)
    >>> print(out["groups"], out["fitted"], "of", out["resamples"], "resamples fitted")
    3 200 of 200 resamples fitted
    >>> lo, hi = out["theta"]
    >>> print(f"theta in [{lo:.3f}, {hi:.3f}] g at 90 %")
    theta in [0.324, 0.431] g at 90 %
    >>> lo, hi = out["probability"]
    >>> print(f"P(collapse at 0.3 g) in [{lo:.3f}, {hi:.3f}]")
    P(collapse at 0.3 g) in [0.037, 0.306]
    """
    if isinstance(n, bool) or not isinstance(n, int) or not 10 <= n <= 100_000:
        raise InputError(f"the bootstrap needs 10 to 100000 resamples, got {n!r}")
    if not (isinstance(level, (int, float)) and 0.5 <= level < 1):
        raise InputError(f"the confidence level must be in [0.5, 1), got {level!r}")
    if design is not None and not (isinstance(design, (int, float)) and math.isfinite(design) and design > 0):
        raise InputError(f"the design intensity must be a positive finite number, got {design!r}")
    groups: dict[str, list[tuple[float, float]]] = {}
    for g, lo, up in samples:
        groups.setdefault(str(g), []).append((lo, up))
    _bounds([s[0] for v in groups.values() for s in v], [s[1] for v in groups.values() for s in v])
    keys = sorted(groups)
    if len(keys) < 2:
        raise InputError(f"a bootstrap over groups needs at least two groups (recordings), got {len(keys)}: every "
                         "resample would be the sample itself")
    try:
        whole = fit_interval([s[0] for v in groups.values() for s in v], [s[1] for v in groups.values() for s in v])
        start = (whole.theta, whole.beta)
    except InputError:
        start = None
    rng = np.random.default_rng(seed)
    draws = rng.integers(0, len(keys), size=(n, len(keys)))
    thetas, betas, failed = [], [], 0
    for row in draws:
        pick = [s for k in row for s in groups[keys[k]]]
        try:
            f = fit_interval([lo for lo, _ in pick], [up for _, up in pick], start)
        except (InputError, SolverError):
            failed += 1
            continue
        thetas.append(f.theta)
        betas.append(f.beta)
    if not thetas:
        raise InputError("no bootstrap resample has two different collapse intensities: no interval")
    th, be = np.array(thetas), np.array(betas)
    q = [50 * (1 - level), 50 * (1 + level)]
    out = {"resamples": int(n), "fitted": int(th.size), "left_out": failed, "level": float(level),
           "seed": int(seed), "groups": len(keys),
           "theta": [float(v) for v in np.percentile(th, q)], "beta": [float(v) for v in np.percentile(be, q)]}
    if design is not None:
        out["margin"] = [float(v) for v in np.percentile(th / design, q)]
        out["probability"] = [float(v) for v in np.percentile(probability(design, th, be), q)]
    return out


def empirical(collapsed, censored=()) -> tuple[np.ndarray, np.ndarray]:
    """The collapse intensities sorted and the fraction collapsed at each (Kaplan-Meier: the
    samples censored below an intensity leave the count at risk; ``i / n`` without them)."""
    x = np.sort(np.asarray(collapsed, dtype=float))
    c = np.asarray(censored, dtype=float)
    at_risk = (x.size - np.arange(x.size)) + np.sum(c[None, :] >= x[:, None], axis=1)
    return x, 1.0 - np.cumprod(1.0 - 1.0 / at_risk)
