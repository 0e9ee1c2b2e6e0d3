"""One episode of the one-mechanism motion: from a state on a mechanism to its first event.

The mechanism's equation of motion (:class:`~fembeam.dynamics.equation.EquationOfMotion`),
with the ground's work ``W' = -a_g Q theta'`` as a third state, is integrated by DOP853
(:mod:`.dop853`, rtol ``RTOL``) with steps ending on the kinks of the ground signal
(:class:`Signal`), and events located on each step's interpolant (:mod:`.events`): an impact
(``theta`` back to 0), overturning (the rotation reaches its overturning angle,
:func:`~fembeam.dynamics.outcomes.overturning`) or the end of the interval; turning points on
the way are recorded.
"""
from __future__ import annotations

import math
from bisect import bisect_left, bisect_right

from .dop853 import MAX_FACTOR, N_STAGES, Dense, Dop853, poly
from .equation import EquationOfMotion
from .events import EPS, may_cross_stages, step_events
from .ground import GroundMotion
from .result import Track

__all__ = ["Signal", "episode", "motion_rhs", "RTOL"]

RTOL = 1e-10


class Signal:
    """The ground acceleration for the integrator: ``breaks`` (kinks: every sample of a record
    or of a short pulse, the ends of a finely sampled smooth pulse) and, on each interval
    between them, ``a_g(t)`` as a cheap scalar function (a record: the line of that interval)."""

    def __init__(self, ground: GroundMotion):
        self.at = ground.scalar()
        smooth = ground.smooth and ground.t.size > 8
        self.breaks = (ground.t[[0, -1]] if smooth else ground.t).tolist()
        self.linear = ground.exact is None and not smooth     # a_g linear between breaks
        self.values = ground.a.tolist()

    def jumps(self, t: float) -> bool:
        """``a_g`` may jump at the break ``t`` (a record is continuous between its ends)."""
        return not self.linear or t == self.breaks[0] or t == self.breaks[-1]

    def interval(self, t: float):
        """``(tb, a_g)``: the first break after ``t`` (inf: none) and ``a_g`` up to it."""
        br = self.breaks
        i = bisect_right(br, t)
        tb = br[i] if i < len(br) else math.inf
        if not self.linear:
            return tb, self.at
        if i == 0 or i == len(br):
            return tb, lambda x: 0.0
        ta, a0, da = br[i - 1], self.values[i - 1], self.values[i] - self.values[i - 1]
        dt = tb - ta
        return tb, lambda x: a0 + da * (x - ta) / dt



def motion_rhs(coef, ag):
    """The right-hand side ``fun(t, (theta, theta', W)) -> (theta', theta'', W')`` of the equation
    of motion with coefficients ``coef(theta) = (Lambda, Lambda', V', Q)``, and a setter for
    the ground acceleration ``ag(t)`` (g) on the current interval of the signal."""
    box = [ag]

    def fun(t: float, y: tuple) -> tuple:
        w = y[1]
        Lam, dLam, dV, Q = coef(y[0])
        aQ = box[0](t) * Q
        return w, -(0.5 * dLam * w * w + dV + aQ) / Lam, -aQ * w

    def set_ground(a) -> None:
        box[0] = a

    return fun, set_ground


def episode(eq: EquationOfMotion, k: int, sig: Signal, t: float, t_end: float, theta: float,
             rate: float, track: Track, top: float, reason: str):
    """Integrate along ``eq`` from ``(t, theta, rate)`` to the first event.  Returns
    ``(event, t, theta, rate, energy_balance_error, ground_work)`` with event ``"impact"``,
    ``reason`` (the rotation ``sign * theta`` reaches ``top``: ``"overturn"`` or ``"locked"``,
    :func:`overturning`) or ``"end"``; ``ground_work`` (J/m): the ground's work over
    the episode.

    :class:`~.dop853.Dop853` steps never cross a break of the signal (a kink): a step that would is
    shortened to end on it, and the steps left to it are made equal; the step-size control
    carries on across breaks (no restart).  Events are located on the interpolant of the
    step (``brentq``) with the conventions of ``solve_ivp``, inside the step too (a swing with
    two turning points in one step, :func:`~.events.step_events`); the interpolant is made where the
    history or the thrust-line check needs it, or where the stages say that the step may hold an
    event (:func:`~.events.may_cross_stages`)."""
    sg = eq.sign
    # the scales of the tolerances and of the energy error: the unstable equilibrium (or the lock)
    hump = min(eq.theta_unstable, eq.theta_lock * (1 - 1e-9))
    scale_th = max(hump if math.isfinite(hump) else 1.0, 1e-6)
    scale_w = scale_th * math.sqrt(eq.g / eq.mechanism.curve.length)
    E0 = eq.energy(theta, rate)
    E_scale = max(abs(eq.potential(sg * hump)) if math.isfinite(hump) else abs(E0), abs(E0), 1e-300)
    coef, at = eq.coefficients, sig.at
    tb, ag = sig.interval(t)
    fun, set_ground = motion_rhs(coef, ag)
    st = Dop853(fun, (1e-12 * scale_th, 1e-12 * scale_w, 1e-12 * E_scale), RTOL)
    keep = track.keep
    sol = Dense() if keep else None
    grid = track.grid_list
    gi = bisect_left(grid, t)
    y = (theta, rate, 0.0)
    f = fun(t, y)
    bound = min(tb, t_end)
    hp = st.first_step(t, y, f, bound - t) if bound > t else 0.0
    t_start, hit = t, None
    g_prev = (sg * theta, sg * theta - top, rate)
    while t < t_end:
        if t >= bound:                # a break: the signal's next interval
            tb, ag = sig.interval(t)
            set_ground(ag)
            bound = min(tb, t_end)
            if sig.jumps(t):
                f = fun(t, y)
        span = bound - t
        rejected = False
        while True:                   # one accepted step
            h = span if hp >= span else span / math.ceil(span / hp)
            y1, K, err = st.step(t, y, f, h)
            if err < 1.0:
                break
            hp = Dop853.next_step(h, err, True)
            rejected = True
            if hp < 10 * (math.nextafter(t, math.inf) - t):
                raise SolverError(f"time integration failed at t = {t:g} s (step size too small)")
        grow = Dop853.next_step(h, err, rejected)
        hp = max(grow, hp) if grow == h * MAX_FACTOR else grow     # a step cut short at a break: keep hp
        t_old, y_old = t, y
        t, y = (bound if h == span else t_old + h), y1
        f = (K[0][N_STAGES], K[1][N_STAGES], K[2][N_STAGES])
        hh = t - t_old
        g_new = (sg * y[0], sg * y[0] - top, y[1])
        need = keep or (gi < len(grid) and grid[gi] < t)
        F = st.dense(t_old, hh, y_old, y, K) if need or may_cross_stages(g_prev, g_new, hh, K[1]) else None

        def at_(x):
            return tuple(u + poly(c, (x - t_old) / hh) for u, c in zip(y_old, F))

        roots = step_events(y_old, F, t_old, t, g_prev, g_new, sg, top, reason) if F is not None else []
        g_prev = g_new
        stop = min((r for r in roots if r[1] is not None), default=None)
        t_stop = stop[0] if stop is not None else t
        for tr, name in roots:
            if name is None and tr > t_start and (stop is None or tr <= stop[0]):
                yp = at_(tr)
                track.peaks.append((float(tr), k, float(yp[0])))
                track.peak_at(tr, yp[0], eq)
        while gi < len(grid) and grid[gi] < t_stop:
            tt = grid[gi]
            th, w = at_(tt)[:2]
            track.add(tt, k, th, w, 0.5 * coef(th)[0] * w * w, eq.potential(th), at(tt))
            gi += 1
        if keep:
            sol.add(t_old, hh, y_old, F)
        if stop is not None:
            hit = (stop[1], t_stop, at_(t_stop))
            break
    if keep and sol.steps:
        track.pieces.append((t_start, float(hit[1] if hit is not None else t_end), k, sol))
    te, y = (hit[1], hit[2]) if hit is not None else (t_end, y)
    track.peak_at(te, y[0], eq)
    err = abs(eq.energy(y[0], y[1]) - E0 - y[2]) / E_scale
    if hit is None:
        return "end", t_end, float(y[0]), float(y[1]), err, float(y[2])
    Lam = coef(y[0])[0]
    track.add(te, k, y[0], y[1], 0.5 * Lam * y[1] ** 2, eq.potential(y[0]), at(te))
    if hit[0] == "impact":
        return "impact", te, 0.0, float(y[1]), err, float(y[2])
    return hit[0], te, float(y[0]), float(y[1]), err, float(y[2])

