"""Lognormal collapse fragility: maximum-likelihood fit, bootstrap intervals, margin at a design level.

``P(collapse | IM = x) = Phi(ln(x / theta) / beta)``: ``theta`` the median collapse intensity,
``beta`` the dispersion (standard deviation of ``ln IM`` at collapse).  Each record-sign gives the
intensity at which it collapses, ``x_i``, or, when it did not collapse up to the largest factor
run, a lower bound ``c_j`` (right-censored).  With ``y = ln x``, ``mu = ln theta`` and
``z = (y - mu) / beta`` the log-likelihood is

    l(mu, beta) = sum_i [-z_i^2 / 2 - ln beta] + sum_j ln(1 - Phi(z_j))     (constants dropped).

Without censored samples its maximum is closed-form: ``mu = mean(y)``, ``beta^2 = mean((y - mu)^2)``
(the 1/n variance: maximum likelihood, not the unbiased 1/(n-1)).  With them it is found by
Newton's method from the closed-form fit of the collapsed samples, in Olsen's parameters where it
is concave, until its gradient vanishes.  The maximum exists when at least two collapsed
intensities differ.

Confidence intervals come from a bootstrap (Efron's percentile intervals): ``n`` resamples, each
drawing the groups (the components of one recording, with both signs) with replacement, so that
correlated samples leave or enter together; the seed fixes them.  The collapse margin ratio at a
design intensity ``x_d`` is ``theta / x_d`` and the probability of collapse there
``Phi(ln(x_d / theta) / beta)``; their intervals are the percentiles of the same resamples.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..errors import InputError, SolverError

__all__ = ["LognormalFit", "fit", "fit_censored", "bootstrap", "probability", "empirical", "NEWTON_STEPS"]

NEWTON_STEPS = 100


@dataclass(frozen=True)
class LognormalFit:
    """``theta`` (median, the unit of the intensity), ``beta`` (dispersion), the numbers of
    collapsed and censored samples, and ``method`` (``closed_form`` or ``newton``)."""

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
    y = np.asarray(values, dtype=float).ravel()
    if y.size and not (np.all(np.isfinite(y)) and np.all(y > 0)):
        raise InputError(f"the {name} intensities must be positive finite numbers")
    return np.log(y)


def fit(collapsed, censored=()) -> LognormalFit:
    """Maximum-likelihood fit of the module docstring; :class:`InputError` when it does not
    exist (fewer than two different collapsed intensities)."""
    y, c = _logs(collapsed, "collapse"), _logs(censored, "censored")
    if y.size < 2 or np.ptp(y) <= 1e-12 * max(1.0, float(np.max(np.abs(y)))):
        raise InputError(f"a lognormal fit needs at least two different collapse intensities, got {y.size} "
                         f"collapsed sample(s){' (all equal)' if y.size >= 2 else ''}")
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


def bootstrap(samples: list[tuple[str, float, bool]], n: int = 1000, seed: int = 0, level: float = 0.9,
              design: float | None = None) -> dict:
    """Percentile intervals at ``level`` of ``theta``, ``beta`` and, given a ``design``
    intensity, of the margin ``theta / design`` and of the probability of collapse at it, from
    ``n`` resamples of the groups of ``samples`` ``(group, intensity, censored)``.  Resamples
    without a fit (fewer than two different collapse intensities) are left out and counted."""
    if isinstance(n, bool) or not isinstance(n, int) or not 10 <= n <= 100_000:
        raise InputError(f"the bootstrap needs 10 to 100000 resamples, got {n!r}")
    if not (0.5 <= level < 1):
        raise InputError(f"the confidence level must be in [0.5, 1), got {level!r}")
    groups: dict[str, list[tuple[float, bool]]] = {}
    for g, x, cens in samples:
        groups.setdefault(g, []).append((float(x), bool(cens)))
    keys = sorted(groups)
    rng = np.random.default_rng(seed)
    draws = rng.integers(0, len(keys), size=(n, len(keys)))
    thetas, betas, failed = [], [], 0
    for row in draws:
        pick = [s for k in row for s in groups[keys[k]]]
        try:
            f = fit([x for x, cens in pick if not cens], [x for x, cens in pick if cens])
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
