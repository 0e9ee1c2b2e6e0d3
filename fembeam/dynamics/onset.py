"""Onset of rocking: when the ground's inertia load first exceeds the limit load ``A_L`` of one
direction, located exactly on the piecewise-linear signal (and on a pulse's formula)."""
from __future__ import annotations

import numpy as np

from ..mechanisms.energy import load_factor
from .events import EPS, brentq
from .ground import GroundMotion

__all__ = ["onset_time", "below_time", "onset_load", "ONSET_REL_TOL"]

ONSET_REL_TOL = 1e-9    # a mechanism's own load factor this far (relative) above A_L is A_L


def onset_load(mechanism, direction: int, A_L: float) -> float:
    """The inertia load (g) at which ``mechanism`` starts to move along ``direction`` x.

    Parameters
    ----------
    mechanism : Mechanism
        The mechanism the motion starts on (the limit analysis's hinges).
    direction : int
        +1 or -1, the sense of the inertia load.
    A_L : float
        The limit analysis's load factor (g).

    Returns
    -------
    float
        ``A_L`` when the mechanism's own load factor (virtual work of gravity over that of a
        unit horizontal inertia load, :func:`~fembeam.mechanisms.energy.load_factor`, g) agrees
        with it to :data:`ONSET_REL_TOL`, else that load factor.  The two differ when the
        limit analysis knows the continuum's ``A_L`` but not its hinges (a degenerate
        optimum: the hinges stay at the joints of the mesh, whose mechanism needs a larger
        load, e.g. 1.70262 g against 1.70253 g for a semicircle with t/R = 1 on 200 elements).
        Started at ``A_L``, such a mechanism would close again at once (gravity still wins)
        and the load would pass with the member at rest.
    """
    own = float(load_factor(mechanism, direction))
    return own if own > A_L * (1.0 + ONSET_REL_TOL) else float(A_L)


def onset_time(ground: GroundMotion, t0: float, t1: float, A_plus: float, A_minus: float):
    """First time in ``[t0, t1]`` at which ``-a_g > A_plus`` (returns ``(t, +1)``) or
    ``a_g > A_minus`` (``(t, -1)``), exact on the piecewise-linear signal (zero outside its
    samples), refined on the formula of a pulse; None if the ground stays below both
    thresholds."""
    t, a = ground.t, ground.a
    # the signal on [t0, t1]: its samples inside, with the values at t0 and t1
    inside = (t > t0) & (t < t1)
    ts = np.concatenate([[t0], t[inside], [t1]])
    av = np.concatenate([[float(ground(t0))], a[inside], [float(ground(t1))]])
    if t0 < t[0] < t1:      # the jump from zero to the first sample
        k = np.searchsorted(ts, t[0])
        ts, av = np.insert(ts, k, t[0]), np.insert(av, k, 0.0)
    best = None
    for d, f in ((1, -av - A_plus), (-1, av - A_minus)):
        if not np.isfinite(f).all() or not np.any(f > 0):
            continue
        i = int(np.argmax(f > 0))
        if i == 0:
            tc = ts[0]
        else:
            f0, f1 = f[i - 1], f[i]
            tc = ts[i - 1] + (ts[i] - ts[i - 1]) * (-f0) / (f1 - f0)
            tc = min(max(tc, ts[i - 1]), ts[i])
            if ground.exact is not None:     # the crossing of the pulse's formula in this interval
                ex = (lambda x: -ground.exact.at(x) - A_plus) if d == 1 else (lambda x: ground.exact.at(x) - A_minus)
                if ex(ts[i - 1]) <= 0 < ex(ts[i]):
                    tc = brentq(ex, ts[i - 1], ts[i], xtol=1e-15, rtol=8 * EPS)
                    while ex(tc) <= 0 and tc < ts[i]:    # just inside the exceedance
                        tc = np.nextafter(tc, np.inf)
        if best is None or tc < best[0]:
            best = (float(tc), d)
    return best


def below_time(ground: GroundMotion, t0: float, t1: float, A_plus: float, A_minus: float, eps: float):
    """First sample time in ``(t0, t1]`` where the ground is within both thresholds
    (``-a_g <= A_plus`` and ``a_g <= A_minus``), or just after the last sample (where the
    signal is zero); None if there is none before ``t1``."""
    t, a = ground.t, ground.a
    ok = np.flatnonzero((t > t0) & (t <= t1) & (-a <= A_plus) & (a <= A_minus))
    if ok.size:
        return float(t[ok[0]])
    after = max(float(t[-1]), t0) + eps
    return after if after <= t1 else None

