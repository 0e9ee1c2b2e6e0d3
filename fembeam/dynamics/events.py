"""Events of the one-mechanism motion on a DOP853 step: where the rotation ``theta`` of the
mechanism returns to 0 (an impact), reaches its overturning angle, or turns (the rate vanishes).

A small swing may fit inside one step: ``theta`` can cross 0 and come back with two turning
points between, so that nothing changes sign from one end of the step to the other.  So each
step's interpolant (:func:`~fembeam.dynamics.dop853.poly`, a polynomial of degree 7 in the
step's fraction ``x``) is bounded first (:func:`deviation`, :func:`monotone`,
:func:`one_extremum`); where an event is possible the step is cut at the interpolant's extrema
(:func:`extrema`), between which it is monotone, and the first crossing is located by
``brentq`` with the endpoint conventions of ``solve_ivp`` (:func:`step_events`).
"""
from __future__ import annotations

from operator import mul

import numpy as np

from .dop853 import poly

__all__ = ["step_events", "may_cross_stages", "crosses", "deviation", "monotone", "one_extremum", "extrema",
           "brentq", "EPS"]

EPS = float(np.finfo(float).eps)


def brentq(*args, **kwargs) -> float:
    """``scipy.optimize.brentq``, imported on first use (0.2 s: ``fembeam rock --help`` need not)."""
    from scipy.optimize import brentq as _brentq

    return _brentq(*args, **kwargs)


# the interpolant's terms beyond the chord, x u, x^2 u, x^2 u^2, x^3 u^2, x^3 u^3, x^4 u^3 (u = 1 - x),
# are at most a^a b^b / (a + b)^(a + b) on [0, 1] for x^a u^b
BOUNDS = (1 / 4, 4 / 27, 1 / 16, 108 / 3125, 1 / 64, 6912 / 823543)
# the largest |d/dx| and |d^2/dx^2| on [0, 1] of the terms from x^2 u^2 on (at the ends or where the next
# derivative vanishes), rounded up
SLOPES = (0.19245009, 0.13557551, 0.05366564, 0.03358307)
CURVES = (2.0, 2.0, 0.37500001, 0.2425993)
DERIV = None     # 7 x 7: the power coefficients (x^0 .. x^6, rows) of the derivative of each term of poly


def deviation(F) -> float:
    """A bound on ``|poly(F, x) - x F[0]|`` for ``x`` in [0, 1]: how far the interpolant may
    stray from the chord of its step (the terms of :data:`BOUNDS`, written out: this runs at
    every step)."""
    _, f1, f2, f3, f4, f5, f6 = F
    b1, b2, b3, b4, b5, b6 = BOUNDS
    return b1 * abs(f1) + b2 * abs(f2) + b3 * abs(f3) + b4 * abs(f4) + b5 * abs(f5) + b6 * abs(f6)


def monotone(F) -> bool:
    """Whether ``poly(F, x)`` is monotone for ``x`` in [0, 1]: its slope is that of the first three
    terms, ``F0 + F1 (1 - 2x) + F2 (2x - 3x^2)`` (a quadratic: its range on [0, 1] is that of its
    ends and vertex), give or take the slopes of the others (at most :data:`SLOPES`)."""
    f0, f1, f2, f3, f4, f5, f6 = F
    s3, s4, s5, s6 = SLOPES
    r = s3 * abs(f3) + s4 * abs(f4) + s5 * abs(f5) + s6 * abs(f6)
    a, b = f0 + f1, f0 - f1 - f2
    lo, hi = (a, b) if a < b else (b, a)
    if f2 != 0.0:
        x = (f2 - f1) / (3.0 * f2)
        if 0.0 < x < 1.0:
            q = f0 + f1 * (1.0 - 2.0 * x) + f2 * x * (2.0 - 3.0 * x)
            lo, hi = min(lo, q), max(hi, q)
    return lo > r or hi < -r


def one_extremum(F) -> bool:
    """Whether the slope of ``poly(F, x)`` is monotone for ``x`` in [0, 1] (at most one extremum):
    its second derivative is ``-2 F1 + F2 (2 - 6x)`` give or take that of the terms from ``x^2
    u^2`` on (at most :data:`CURVES`)."""
    _, f1, f2, f3, f4, f5, f6 = F
    c3, c4, c5, c6 = CURVES
    r = c3 * abs(f3) + c4 * abs(f4) + c5 * abs(f5) + c6 * abs(f6)
    a, b = 2.0 * (f2 - f1), -2.0 * (f1 + 2.0 * f2)
    return (a > r and b > r) or (a < -r and b < -r)


def extrema(F) -> list[float]:
    """The points ``x`` in (0, 1) where ``d/dx poly(F, x)`` may vanish, sorted: the real roots
    of this polynomial of degree 6 (eigenvalues of its companion matrix), and the real parts of
    nearly real ones (an extra point is harmless: between two consecutive points, and the ends,
    the interpolant is monotone)."""
    global DERIV
    if DERIV is None:
        from numpy.polynomial import polynomial as P

        terms = [(1, 0), (1, 1), (2, 1), (2, 2), (3, 2), (3, 3), (4, 3)]     # x^a (1 - x)^b
        rows = [np.pad(P.polyder(P.polymul(P.polypow([0, 1], a), P.polypow([1, -1], b))), (0, 7))[:7]
                for a, b in terms]
        DERIV = np.array(rows).T.tolist()
    c = [sum(map(mul, F, col)) for col in DERIV]
    n = 6
    while n and c[n] == 0.0:
        n -= 1
    if n == 0:
        return []
    A = np.eye(n, k=-1)          # the companion matrix of c[0] + c[1] x + ... + c[n] x^n
    A[0] = c[n - 1::-1]
    A[0] /= -c[n]
    return sorted(z.real for z in np.linalg.eigvals(A).tolist() if abs(z.imag) <= 1e-6 and 0.0 < z.real < 1.0)



DIRECTIONS = (False, True, None)     # impact: falling; overturning: rising; turning point: either


def crosses(g0: float, g1: float, up: bool | None) -> bool:
    """``g`` reaches 0 from ``g0`` to ``g1`` rising (``up``), falling (False) or either (None),
    as ``solve_ivp`` finds events."""
    if g0 == g1:
        return False
    rise, fall = g0 <= 0 <= g1, g0 >= 0 >= g1
    return rise if up else fall if up is False else rise or fall


def step_events(ya: tuple, F: tuple, ta: float, tb: float, ga: tuple, gb: tuple, sg: float, top: float,
                 reason: str) -> list:
    """Events in the step ``[ta, tb]`` (``ya``, ``F``: its start and interpolant; ``ga``, ``gb``: the event
    functions ``sg theta``, ``sg theta - top``, ``rate`` at its ends): ``(t, name)`` with name
    ``"impact"`` (``sg theta`` falls to 0), ``reason`` (it rises to ``top``) or None (a turning
    point, ``rate = 0``).

    A small swing may fit inside one step: ``theta`` can cross 0 (or ``top``) and come back, with
    two turning points between, so that neither ``theta`` nor the rate changes sign from one end
    of the step to the other.  So the interpolants are bounded first (:func:`deviation`: how far
    from the chord of the step; :func:`monotone`, :func:`one_extremum`: whether monotone, whether the
    slope is): a step where ``theta`` cannot reach 0 or ``top`` and the rate cannot vanish holds
    no event.  Where ``theta`` may reach 0 or ``top``, the step is cut at every extremum of its
    interpolant (none where it is monotone; where its slope is monotone, at most one: at the
    turning point; otherwise the real roots of its derivative, :func:`extrema`): between two
    cuts ``theta`` is monotone, so the first piece whose ends show a crossing holds the first
    crossing, located by ``brentq`` (the endpoint conventions of ``solve_ivp``).  An extremum
    within round-off of 0 (or of ``top``) is no crossing (a member starting from rest at ``theta =
    0`` must not hit it).  The turning points are the sign changes of the rate's interpolant: at
    most one where it is monotone, otherwise bracketed between the midpoints of the extrema of
    ``theta``."""
    Ft, Fw = F[0], F[1]
    w0, w1 = ga[2], gb[2]
    dev = deviation(Ft) * (1 + 1e-12) + 16 * EPS * (abs(ga[0]) + abs(ga[1]))
    near = min(ga[0], gb[0]) <= dev or max(ga[1], gb[1]) >= -dev       # theta may reach 0 or top
    turn = w0 * w1 <= 0.0 or min(abs(w0), abs(w1)) <= deviation(Fw) * (1 + 1e-12) + 16 * EPS * abs(w0)
    if not (near or turn):
        return []
    h = tb - ta

    def theta(x):
        return ya[0] + poly(Ft, (x - ta) / h)

    def rate(x):
        return ya[1] + poly(Fw, (x - ta) / h)

    def root(fun, t0, t1, g0, g1):
        if g1 == 0 or g0 == 0:
            return t1 if g1 == 0 else t0
        f0, f1 = fun(t0), fun(t1)
        if f0 * f1 > 0.0:       # the interpolant differs from the step's end values in the last bits
            return t1 if abs(f1) < abs(f0) else t0
        return brentq(fun, t0, t1, xtol=4 * EPS * abs(tb))

    out, ext, turns = [], None, []
    if turn:
        points = [(ta, w0), (tb, w1)]
        if not monotone(Fw):                     # the rate may not be monotone
            ext = extrema(Ft)
            points[1:1] = [(tm, rate(tm)) for tm in (ta + 0.5 * h * (x0 + x1) for x0, x1 in zip(ext, ext[1:]))]
        for (t0, g0), (t1, g1) in zip(points, points[1:]):
            if crosses(g0, g1, None):
                turns.append(root(rate, t0, t1, g0, g1))
        out += [(tw, None) for tw in turns]
    if near:
        if monotone(Ft):                         # theta monotone: no cut
            cuts = []
        elif ext is None and one_extremum(Ft) and (
                (Ft[0] + Ft[1]) * (Ft[0] - Ft[1] - Ft[2]) > 0 or len(turns) == 1):
            # its slope monotone: no extremum where the slopes at the ends (h theta') agree,
            # otherwise one, at the turning point
            cuts = turns if (Ft[0] + Ft[1]) * (Ft[0] - Ft[1] - Ft[2]) <= 0 else []
        else:
            ext = extrema(Ft) if ext is None else ext
            cuts = [ta + x * h for x in ext]
        inner = [(tc, sg * theta(tc)) for tc in cuts]
        tol = 8 * EPS * (abs(ya[0]) + sum(map(abs, Ft)))       # round-off of theta on the interpolant
        for i, name, c in ((0, "impact", 0.0), (1, reason, top)):
            pts = [(ta, ga[i]), *((tc, v - c) for tc, v in inner if abs(v - c) > tol + 4 * EPS * c), (tb, gb[i])]
            for (t0, g0), (t1, g1) in zip(pts, pts[1:]):
                if crosses(g0, g1, DIRECTIONS[i]):
                    out.append((root(lambda x: sg * theta(x) - c, t0, t1, g0, g1), name))
                    break
    return out


def may_cross_stages(ga: tuple, gb: tuple, h: float, Kw: list) -> bool:
    """Whether a step may hold an event (:func:`step_events`), asked before its interpolant is
    made (three more evaluations of the equation of motion) from the accelerations ``Kw`` at its
    stages (both ends among them).  Yes where an event function changes sign from one end of the
    step to the other.  Otherwise an event needs two turning points inside the step (a crossing
    of 0 or ``top`` and back around one turning point changes the sign of the rate): ``theta''``
    vanishes inside, and so does the rate, which then comes within ``h/2 max |theta''|`` of 0 at
    one end.  Between the stages the acceleration strays from their range by a few per cent of
    it (6 % at most, measured on the shipped records and on sine pulses): ``theta''`` may vanish
    where the stages change sign or come within half their range of 0, the rate where one end is
    within ``h max |Kw|`` of 0."""
    a0, a1, aw = ga
    b0, b1, bw = gb
    if (a0 >= 0.0 >= b0 and a0 != b0) or (a1 <= 0.0 <= b1 and a1 != b1) or \
            (aw != bw and (aw <= 0.0 <= bw or aw >= 0.0 >= bw)):      # crosses, written out
        return True
    lo, hi = min(Kw), max(Kw)
    if lo * hi > 0.0 and min(abs(lo), abs(hi)) > 0.5 * (hi - lo):
        return False
    return min(abs(ga[2]), abs(gb[2])) <= h * max(-lo, hi)

