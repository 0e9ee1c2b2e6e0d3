"""A small swing inside one integration step of ``rock`` (fembeam/dynamics/episode.py, events.py).

When a swing fits inside one step of the integrator, ``theta`` may cross 0 and come back (two
turning points between), so that neither ``theta`` nor the rate changes sign from one end of the
step to the other.  The events are then found on the step's interpolant, cut at its extrema.
Independent references: Housner's equation of the rocking block integrated by SciPy's
``solve_ivp`` (``max_step`` 1e-4 s, an event at ``theta = 0``), the arch's equation integrated the
same way, the roots of a polynomial, and, where no swing hides, the values that the check of the
step's ends alone gave.
"""
from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.integrate import solve_ivp

from fembeam import CircularArch, StraightMember
from fembeam.dynamics import GroundMotion, Rocker
from fembeam.dynamics.dop853 import poly as _poly
from fembeam.dynamics.episode import Signal as _Signal, episode as _episode
from fembeam.dynamics.events import step_events as _step_events
from fembeam.dynamics.result import Track as _Track

G = 9.81


def _housner(width, height, ground, side):
    """Housner's equation of a block ``width`` x ``height`` rocking on its left corner (``side =
    +1``: ``theta > 0``, opened by ``a_g > 0``) or its right corner (``side = -1``, ``theta < 0``):
    with ``phi = side * theta``, ``phi'' = -p^2 (sin(alpha - phi) - side a_g cos(alpha - phi))``,
    ``p^2 = 3 g / (4 R)``, ``tan alpha = width / height``, ``R`` the half-diagonal."""
    alpha, R = math.atan(width / height), 0.5 * math.hypot(width, height)
    p2 = 3 * G / (4 * R)
    at = ground.scalar()

    def f(t, y):
        phi = side * y[0]
        return [y[1], -side * p2 * (math.sin(alpha - phi) - side * at(t) * math.cos(alpha - phi))]
    return f


def _reference(f, sign, t0, y0, t_stop, breaks=(), top=None):
    """``solve_ivp`` (DOP853, rtol 1e-12, ``max_step`` 1e-4 s) from ``(t0, y0)``, restarted at the
    ``breaks`` (the kinks of a record), to the first time ``sign * theta`` falls to 0 (or rises to
    ``top``): ``(that time or None, [(ta, tb, dense solution)])``."""
    def hit(t, y):
        return sign * y[0]
    hit.terminal, hit.direction = True, -1

    def over(t, y):
        return sign * y[0] - top
    over.terminal, over.direction = True, 1
    edges = [t0, *[b for b in breaks if t0 < b < t_stop], t_stop]
    y, pieces = list(y0), []
    for ta, tb in zip(edges[:-1], edges[1:]):
        s = solve_ivp(f, (ta, tb), y, method="DOP853", rtol=1e-12, atol=1e-16, max_step=1e-4,
                      dense_output=True, events=[hit] if top is None else [hit, over])
        pieces.append((ta, s.t[-1], s.sol))
        if s.status == 1:
            return float(s.t[-1]), pieces
        y = s.y[:, -1]
    return None, pieces


# --------------------------------------------------------------------------- a constructed swing
WIDTH, HEIGHT = 0.2, 2.0                      # tan alpha = 0.1: A_L = 0.1 g
TAN = WIDTH / HEIGHT


def _swing_ground():
    """The ground holds the block at its threshold (``a_g = tan alpha``) for 0.3 s, drops to 0 in
    10 us, then rises to ``tan alpha + 0.6`` g over 0.04 s: the block, creeping out, turns back,
    crosses ``theta = 0`` at 0.3034 s and would be pushed back out by 0.3166 s; one step of the
    integrator spans all of it."""
    t = np.array([0.0, 0.3, 0.30001, 0.34001, 0.84001])
    return GroundMotion(t, np.array([TAN, TAN, 0.0, TAN + 0.6, TAN]), "a swing inside one step")


@pytest.mark.parametrize("keep", [True, False])
def test_a_swing_inside_one_step_is_an_impact(keep):
    """The episode from ``theta = 0`` at 1e-5 rad/s on the left corner: the impact at the first
    crossing of ``theta = 0`` found by Housner's equation (solve_ivp), 0.30341030614 s, to 1e-10 s,
    with the same incoming rate; the step that holds it starts and ends with ``theta > 0`` and the
    rate > 0 (the reference has both turning points and both crossings inside it), so a check of
    the step's ends sees nothing (and the block, followed on its mechanism, would be pushed over
    to the overturning level at 0.74 s); the turning point before the impact is reported, and
    ``theta`` never takes the closed side beyond round-off.  ``keep``: the interpolant made at
    every step (the history or the thrust-line check need it) or only where the accelerations at
    the stages say an event may be there."""
    ground = _swing_ground()
    rk = Rocker(StraightMember(height=HEIGHT, width=WIDTH), voussoirs=1, qp=False)
    k = rk.index(rk.start[-1])            # opened by a_g > 0: the left corner, theta > 0
    eq = rk.equations[k]
    assert eq.sign == 1
    track = _Track(np.empty(0), keep)
    ev, t_hit, theta, rate, err, _ = _episode(eq, k, _Signal(ground), 0.0, 2.0, 0.0, 1e-5, track,
                                              rk.tops[k], rk.events[k])
    f = _housner(WIDTH, HEIGHT, ground, 1)
    t_ref, pieces = _reference(f, 1, 0.0, (0.0, 1e-5), 1.0, ground.t)
    assert ev == "impact" and theta == 0.0
    assert t_ref == pytest.approx(0.30341030614, abs=1e-10)
    assert t_hit == pytest.approx(t_ref, abs=1e-10)
    rate_ref = next(p[2] for p in pieces if p[0] <= t_ref <= p[1])(t_ref)[1]
    assert rate == pytest.approx(rate_ref, rel=1e-8) and rate < 0
    assert err < 1e-8
    # the turning point before the impact (the creeping block turns back)
    t_turn = [t for t, kk, th in track.peaks]
    assert len(t_turn) == 1
    sol_ref = next(p[2] for p in pieces if p[0] <= t_turn[0] <= p[1])
    assert abs(sol_ref(t_turn[0])[1]) < 1e-9 * abs(rate_ref)
    if not keep:
        return
    (_, _, _, sol), = track.pieces
    t0, h, y0, F = next(s for s in sol.steps if s[0] <= t_hit <= s[0] + s[1])
    y1 = [u + _poly(c, 1.0) for u, c in zip(y0, F)]
    assert h > 0.015 and y0[0] > 0 and y1[0] > 0 and y0[1] > 0 and y1[1] > 0
    # the reference over that step, past the impact: two turning points, two crossings of 0
    free = solve_ivp(f, (0.0, t0 + h), [0.0, 1e-5], method="DOP853", rtol=1e-12, atol=1e-16, max_step=1e-4,
                     dense_output=True)
    th_ref, w_ref = free.sol(np.linspace(t0, t0 + h, 20001))
    assert np.count_nonzero(np.diff(np.sign(w_ref))) == 2 and np.count_nonzero(np.diff(np.sign(th_ref))) == 2
    assert th_ref.min() < -1e-5
    # theta on the episode's interpolant, up to the impact: never on the closed side
    tt = np.linspace(0.0, t_hit, 200001)
    th = np.array([sol(x)[0] for x in tt])
    assert th.min() >= -1e-15 * th.max()


# --------------------------------------------------------------------------- on shipped records
def test_swings_inside_one_step_on_a_record_block():
    """A 0.2 m x 2 m block under the Chopra El Centro record x 4.75 rocks with rates of 1e-4 to
    1e-3 rad/s while the ground hovers about its A_L = 0.1 g, then overturns: all 24 impacts at
    the times Housner's equation gives from the onset and from each impact's outgoing rate (to
    1e-9 s; among them the impacts at 0.5488340 s and 0.5492599 s of a swing inside one step),
    each outgoing rate Housner's ``(1 - 1.5 sin^2 alpha)`` of the incoming one, the overturning
    where the centroid is a tenth of the width below rest (``R cos(theta - alpha) = h/2 - 0.1
    w``) at 1.5276591 s, and the history never on the closed side of the mechanism."""
    width, height = 0.2, 2.0
    ground = GroundMotion.record("elcentro_chopra").scaled(4.75)
    rk = Rocker(StraightMember(height=height, width=width), voussoirs=1, qp=False)
    res = rk.run(ground, t_end=2.0, dt_out=1e-4, thrust_check=False)
    (t_on, k_on), = res.onsets
    assert res.outcome == "overturned" and res.overturn_reason == "below_rest" and len(res.impacts) == 24
    assert [e.t for e in res.impacts if 0.548 < e.t < 0.55] == pytest.approx([0.548833959, 0.549259937], abs=1e-9)
    alpha, R = math.atan(width / height), 0.5 * math.hypot(width, height)
    top = alpha + math.acos((0.5 * height - 0.1 * width) / R)
    starts = [(t_on, k_on, 0.0)] + [(e.t, e.after, e.rate_out) for e in res.impacts]
    ends = [e.t for e in res.impacts] + [res.t_overturn]
    for (t0, k, rate0), t1 in zip(starts, ends):
        side = rk.equations[k].sign
        t_ref, _ = _reference(_housner(width, height, ground, side), side, t0, (0.0, rate0), t1 + 0.02, ground.t,
                              top=top)
        assert t_ref == pytest.approx(t1, abs=1e-9), (t0, k)
    assert res.t_overturn == pytest.approx(1.5276591, abs=1e-7)
    for e in res.impacts:
        assert not e.at_rest and abs(e.rate_out) == pytest.approx(abs(e.rate_in) * (1 - 1.5 * math.sin(alpha) ** 2),
                                                                  rel=1e-12)
    h = res.history
    moving = h["mechanism"] >= 0
    signs = np.array([eq.sign for eq in rk.equations])[h["mechanism"][moving].astype(int)]
    assert (signs * h["theta"][moving]).min() >= -1e-15 * alpha


def test_swings_inside_one_step_on_a_record_arch():
    """The paper's arch in 7 voussoirs (R = 5 m) under El Centro x 2 rocks with rates down to
    1e-5 rad/s near 4.5 s, where the ground stays near A_L: every impact from 4.50 s to the end
    of the decay, at the time the arch's equation integrated by solve_ivp gives from the outgoing
    rate of the impact before (to 1e-9 s; among them 4.526174756 s and 4.526192722 s, of a swing
    inside one step), and the history (every 2e-4 s) never on the closed side."""
    rk = Rocker(CircularArch.from_ratio(157.5, 0.15, radius=5.0), voussoirs=7, qp=False)
    ground = GroundMotion.record("elcentro").scaled(2.0)
    res = rk.run(ground, t_end=5.0, dt_out=2e-4, thrust_check=False)
    at = ground.scalar()
    window = [(a, b) for a, b in zip(res.impacts, res.impacts[1:]) if 4.5 < a.t < 4.6]
    assert len(window) >= 15
    assert [b.t for a, b in window if 4.526 < b.t < 4.527] == pytest.approx([4.526174756, 4.526192722], abs=1e-9)
    for a, b in window:
        eq = rk.equations[a.after]

        def f(t, y, eq=eq):
            Lam, dLam, dV, Q = eq.coefficients(y[0])
            return [y[1], -(0.5 * dLam * y[1] ** 2 + dV + at(t) * Q) / Lam]
        t_ref, _ = _reference(f, eq.sign, a.t, (0.0, a.rate_out), b.t + 0.02, ground.t)
        assert t_ref == pytest.approx(b.t, abs=1e-9), a.t
    h = res.history
    moving = h["mechanism"] >= 0
    signs = np.array([eq.sign for eq in rk.equations])[h["mechanism"][moving].astype(int)]
    assert (signs * h["theta"][moving]).min() >= -1e-15


# --------------------------------------------------------------------------- one step, by hand
def _cubic_step(coef, scale, h):
    """Interpolants (``_poly``'s form) of ``theta(x) = scale * (c1 x + c2 x^2 + c3 x^3)`` on a step
    ``h`` and of its rate ``theta'(x) / h``: ``theta = F0 x + F1 x u + F2 x^2 u`` (``u = 1 - x``)
    with ``F2 = -c3``, ``F1 = -c2 - c3``, ``F0 = c1 + c2 + c3``."""
    c1, c2, c3 = (scale * c for c in coef)
    d1, d2 = 2 * c2 / h, 3 * c3 / h
    return ((c1 + c2 + c3, -c2 - c3, -c3, 0.0, 0.0, 0.0, 0.0),
            (d1 + d2, -d2, 0.0, 0.0, 0.0, 0.0, 0.0)), c1 / h


@pytest.mark.parametrize("event", ["overturn", "locked", "impact"])
def test_a_crossing_and_back_with_two_turning_points_within_one_step(event):
    """One step whose ``theta`` goes past ``top`` (or below 0) and back with two turning points
    between, the rate of the same sign at both ends: ``p(x) = 1.5 x - 4.25 x^2 + 2.8 x^3`` rises
    to 0.154 at ``x = 0.228`` and falls to -0.087 at ``x = 0.784``, ``p(1) = 0.05``.  The rotation
    opening the mechanism is ``sg theta = top (0.9 + p(x))`` (the overturning level, or where
    the four-bar locks: the same event) or ``theta0 (0.1 - p(x))`` with ``sg = -1`` (an impact):
    the event at the first root of ``p(x) = 0.1`` (numpy.roots), before the first turning point
    and the second, both reported."""
    coef, h, ta = (1.5, -4.25, 2.8), 0.01, 3.0
    top = 0.4
    x_cross = min(r.real for r in np.roots([coef[2], coef[1], coef[0], -0.1]) if abs(r.imag) < 1e-12 and r.real > 0)
    x_turns = sorted(np.roots([3 * coef[2], 2 * coef[1], coef[0]]).real)
    if event == "impact":
        sg, theta0 = -1.0, 1e-6
        F, w0 = _cubic_step(coef, theta0, h)                 # theta = -theta0 (0.1 - p)
        ya = (-0.1 * theta0, w0)
        g = lambda x: theta0 * (0.1 - np.polyval([coef[2], coef[1], coef[0], 0.0], x))  # noqa: E731
    else:
        sg = 1.0
        F, w0 = _cubic_step(coef, top, h)
        ya = (0.9 * top, w0)
        g = lambda x: top * (0.9 + np.polyval([coef[2], coef[1], coef[0], 0.0], x))   # noqa: E731
    w1 = ya[1] + _poly(F[1], 1.0)
    ga = (g(0.0), g(0.0) - top, ya[1])
    gb = (g(1.0), g(1.0) - top, w1)
    assert ga[2] * gb[2] > 0 and 0 < min(ga[0], gb[0]) and max(ga[1], gb[1]) < 0   # the ends show nothing
    events = _step_events(ya, F, ta, ta + h, ga, gb, sg, top, "overturn" if event == "impact" else event)
    found = dict((name, t) for t, name in events if name is not None)
    turns = sorted(t for t, name in events if name is None)
    assert list(found) == [event]
    assert found[event] == pytest.approx(ta + x_cross * h, abs=1e-14)
    assert turns == pytest.approx([ta + x * h for x in x_turns], abs=1e-14)


# --------------------------------------------------------------------------- where nothing hides
CASES = {
    # member, voussoirs, ground, t_end: outcome, impacts, turning points, t_overturn, peak
    # rotation, three impact times (first, middle, last), as found by the check of the step's ends
    "El Centro 0.8 g, 7 voussoirs": (
        "arch", 7, ("elcentro", "pga", 0.8), 30.0,
        ("rest", 230, 232, None, 0.07527850440699466, (2.421733559882841, 9.65116673928223, 26.416600752306653))),
    "El Centro 1.0 g, 7 voussoirs": (
        "arch", 7, ("elcentro", "pga", 1.0), None,
        ("rest", 386, 390, None, 0.1197519285780056, (1.9434457472918933, 14.805534336727593, 26.74127801729767))),
    "Loma Prieta 0.8 g, 7 voussoirs": (
        "arch", 7, ("lomaprieta", "pga", 0.8), 30.0,
        ("rest", 65, 65, None, 0.025837170396761696, (2.649310961203049, 7.7452352521729635, 7.767666864361089))),
    "block 0.5 x 2, sine 0.5 g 0.5 s": (
        (0.5, 2.0), 1, ("sine", 0.5, 0.5), 6.0,
        ("survived", 9, 9, None, 0.1507573228446999, (0.42173357174732057, 3.967898415445288, 5.8778635643092))),
    "block 0.4 x 1.6, El Centro x 3": (
        (0.4, 1.6), 1, ("elcentro", "scale", 3.0), 30.0,
        ("overturned", 1, 5, 3.491776874851574, 0.6435011087932839, (2.089929722113498,) * 3)),
}


@pytest.mark.parametrize("name", list(CASES))
def test_results_unchanged_where_no_swing_hides(name):
    """Runs where no swing hides inside a step: the same outcome, impacts, turning points,
    overturning time and peak rotation as the check of the step's ends alone gave (impact times
    to 1e-8 s: the hinges are now placed at their canonical positions, rounded to 1e-12 of the
    length, which moves the impacts of a long motion by about 1e-9 s)."""
    member, voussoirs, (gname, how, amount, *period), t_end, expected = CASES[name]
    outcome, n_impacts, n_peaks, t_over, peak, times = expected
    curve = CircularArch.from_ratio(157.5, 0.15, radius=5.0) if member == "arch" else \
        StraightMember(height=member[1], width=member[0])
    if gname == "sine":
        ground = GroundMotion.sine(how, amount)
    else:
        ground = GroundMotion.record(gname)
        ground = ground.to_pga(amount) if how == "pga" else ground.scaled(amount)
    res = Rocker(curve, voussoirs=voussoirs, qp=False).run(ground, t_end=t_end, thrust_check=False, history=False)
    ts = [e.t for e in res.impacts]
    assert (res.outcome, len(ts), len(res.peaks)) == (outcome, n_impacts, n_peaks)
    assert [ts[0], ts[len(ts) // 2], ts[-1]] == pytest.approx(list(times), abs=1e-8)
    assert res.peak_rotation == pytest.approx(peak, rel=1e-9)
    if t_over is None:
        assert res.t_overturn is None
    else:
        assert res.t_overturn == pytest.approx(t_over, abs=1e-9)


# --------------------------------------------------------------------------- the bounds, and random steps
def _basis():
    """The terms of the interpolant (``_poly``'s form), ``x^a (1 - x)^b``, as power series."""
    from numpy.polynomial import polynomial as P
    return [P.polymul(P.polypow([0, 1], a), P.polypow([1, -1], b))
            for a, b in [(1, 0), (1, 1), (2, 1), (2, 2), (3, 2), (3, 3), (4, 3)]]


def test_the_bounds_of_the_interpolant_terms():
    """The constants of the bounds on the interpolant: the largest ``|term|`` of each term beyond
    the chord, and the largest ``|d/dx|``, ``|d^2/dx^2|`` of the terms from ``x^2 (1 - x)^2`` on,
    over [0, 1] (a grid of 10^6 + 1 points): bounds, tight to 1e-6."""
    from numpy.polynomial import polynomial as P

    from fembeam.dynamics.events import BOUNDS as _BOUNDS, CURVES as _CURVES, SLOPES as _SLOPES
    x = np.linspace(0.0, 1.0, 1_000_001)
    terms = _basis()
    for c, bound in zip(terms[1:], _BOUNDS):
        assert bound * (1 - 1e-6) <= np.abs(P.polyval(x, c)).max() <= bound * (1 + 1e-12)
    for c, slope, curve in zip(terms[3:], _SLOPES, _CURVES):
        for d, bound in ((1, slope), (2, curve)):
            assert bound * (1 - 1e-6) <= np.abs(P.polyval(x, P.polyder(c, d))).max() <= bound


def test_random_steps_against_a_fine_sampling():
    """1000 random interpolants of degree 7 (the rate's: the derivative of theta's over the step),
    shifted so that ``sg theta`` comes near 0 or near ``top``: ``_step_events`` finds the first
    fall of ``sg theta`` to 0 (impact) and the first rise to ``top`` (overturning) where a
    sampling of 5 * 10^4 points does (refined by ``brentq`` on the sampled bracket; to 1e-12 of
    the step), and every sign change of the rate (cases within 1e-6 of grazing, or starting past
    a level, left out); among them crossings that the step's ends do not show."""
    from numpy.polynomial import polynomial as P
    from scipy.optimize import brentq

    rng = np.random.default_rng(20240611)
    M = np.zeros((8, 7))
    for j, c in enumerate(_basis()):
        M[:c.size, j] = c
    x = np.linspace(0.0, 1.0, 50_001)
    h, ta, top = 0.02, 1.0, 1.0
    checked = crossings = hidden = 0
    for case in range(1000):
        Ft = rng.normal(size=7) * np.array([1.0, 1.0, 0.5, 0.3, 0.2, 0.1, 0.05])
        pt = M @ Ft                                   # theta - theta(0), power series
        dt = P.polyder(pt) / h                        # the rate, exactly: w0 + _poly(Fw, x)
        w0 = dt[0]
        Fw = np.linalg.solve(M[1:], np.concatenate([dt[1:], [0.0]]))
        sg = rng.choice([-1.0, 1.0])
        th = P.polyval(x, pt)
        if case % 3 == 2:     # sg theta's largest value near top
            ya0 = sg * (top - (sg * th).max() + rng.uniform(-0.2, 0.2))
        else:                 # its smallest near 0
            ya0 = sg * (-(sg * th).min() + rng.uniform(-0.2, 0.2))
        g = sg * (ya0 + th)
        if np.abs(g).min() < 1e-6 or np.abs(g - top).min() < 1e-6 or not 0 < g[0] < top:
            continue
        expected = {}
        for name, level, past in (("impact", 0.0, g <= 0), ("overturn", top, g >= top)):
            if past.any():
                i = int(np.argmax(past))
                xc = brentq(lambda s: sg * (ya0 + P.polyval(s, pt)) - level, x[i - 1], x[i], xtol=1e-15)
                expected[name] = ta + xc * h
        rate = P.polyval(x, dt)
        ga = (sg * ya0, sg * ya0 - top, w0)
        gb = (g[-1], g[-1] - top, rate[-1])
        events = _step_events((ya0, w0), (tuple(Ft), tuple(Fw)), ta, ta + h, ga, gb, sg, top, "overturn")
        found = {name: t for t, name in events if name is not None}
        assert sorted(found) == sorted(expected), case
        for name, t in expected.items():
            assert found[name] == pytest.approx(t, abs=1e-12 * h), (case, name)
        turns = np.flatnonzero(np.diff(np.sign(rate)) != 0)
        tw = sorted(t for t, name in events if name is None)
        assert len(tw) == turns.size, case
        for t, j in zip(tw, turns):
            assert x[j] - 1e-9 <= (t - ta) / h <= x[j + 1] + 1e-9, case
        checked += 1
        crossings += bool(expected)
        hidden += ("impact" in expected and g[-1] > 0) + ("overturn" in expected and g[-1] < top)
    assert checked > 500 and crossings > 200 and hidden > 30
