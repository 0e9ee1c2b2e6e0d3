"""The reference (pure NumPy) implementation of the time stepping of :mod:`.stepper`, without
friction: the same algorithm as the compiled loop (:mod:`.kernel`), one step at a time with the
solvers of :mod:`.projection` (LAPACK band solves).  ``Simulator.run(..., engine="reference")``; the
tests compare the two."""
from __future__ import annotations

import math
import time

import numpy as np

from ..dynamics.ground import GroundMotion
from ..dynamics.outcomes import overturn_level
from .constants import BAND, BLOCK_PIVOTS, GAP_TOL, IMPACT_PIVOTS, OFF_FACE, REG, REST_KINETIC
from .contacts import Contacts
from .projection import banded_solve, solve_mlcp
from .result import SimulationResult
from .stepper import MIN_STEP, checked_run, start_heights, support_history, supported


def _roots(gap, vn, an):
    """Smallest ``s`` in ``(0, inf)`` with ``gap + s vn + s^2/2 an = 0`` (``gap > 0``), inf if none."""
    a2, a1 = 0.5 * an, vn
    disc = a1 * a1 - 4.0 * a2 * gap
    den = -a1 + np.sqrt(np.maximum(disc, 0.0))
    with np.errstate(divide="ignore", invalid="ignore"):
        s = np.where((disc >= 0) & (den > 0), 2.0 * gap / den, np.inf)
    return s


def run_reference(sim, ground: GroundMotion, dt, t_end, dt_out, q0, v0, stop_at_overturn, progress,
                  motion=None):
    """The time history of :meth:`.stepper.Simulator.run` in NumPy (no friction); the supports
    are rows ``n`` and ``n + 1`` of the positions and velocities, moved by ``motion``."""
    clock = time.perf_counter()
    t0, t_end, dt, dt_out, q, v = checked_run(sim, ground, dt, t_end, dt_out, q0, v0)
    bodies, g = sim.bodies, sim.g
    con, q, v = supported(sim, q, v, motion)
    t_hold = t0 + motion.hold_after if motion is not None and motion.hold_after > 0 else math.inf
    sup, sup_t, F_rows, W_sup = np.zeros(4), 0.0, [], 0.0
    V_over = overturn_level(sim.curve, bodies.mass, g)
    L = sim.curve.length
    n = bodies.n
    minv = con.minv
    m = bodies.m
    mass = bodies.mass
    y0 = start_heights(bodies, q, motion)
    E_unit = mass * g * L
    thick = bodies.thickness[:, None]
    gap_tol = GAP_TOL * thick
    at = ground.scalar()
    J = con.J

    def potential(q_):
        return g * float(m @ (q_[:n, 1] - y0))

    geo = con.evaluate(q)
    res = SimulationResult(sim.curve, ground, bodies, mode=sim.mode, dt=dt)
    mv = np.concatenate([np.repeat(m, 2).reshape(-1, 2), bodies.I[:, None], np.zeros((n, 0))], axis=1)
    mv = np.vstack([mv, np.zeros((2, 3))]).ravel()             # (vx, vy, omega) weights of 2K

    def kinetic(v_):
        return 0.5 * float(mv @ (v_.ravel() ** 2))

    E0 = kinetic(v) + potential(q)
    W_ground = D = drift = 0.0
    working = working_imp = None      # warm starts of the smooth projections and of the impacts
    t = t0
    steps = cuts = pivots = 0
    next_out = t0
    peak, t_peak = 0.0, None
    balance = 0.0
    E_seen = max(abs(E0), 1e-9 * E_unit)
    outcome, t_over = None, None
    h_min = MIN_STEP * dt
    rec = res.record
    acc = np.zeros((n + 2, 3))
    acc[:n, 1] = -g
    nonneg = np.zeros((J, 3), bool)
    free = np.zeros((J, 3), bool)
    jj = np.arange(J)
    was_closed = geo.gap <= gap_tol
    stale = False
    # the slip each joint carries (m): none from rest, a given state's own (q0); an open joint's
    # follows the bodies, a closed joint's holds (no sliding): the position projection keeps it
    s_ref = np.zeros(J) if q0 is None else geo.slip[jj, geo.contact].copy()
    while True:
        K = kinetic(v)
        V = potential(q)
        E_seen = max(E_seen, K + abs(V), abs(W_ground), D)
        balance = max(balance, abs(K + V - E0 - W_ground + D) / E_seen)
        rot = float(np.max(np.abs(q[:n, 2])))
        if rot > peak:
            peak, t_peak = rot, t
        done = t >= t_end - h_min                # (a remainder shorter than a landing cut is not stepped)
        if outcome is None:
            outcome = collapse(V - W_sup, V_over, geo.gap, s_ref)     # V less the supports' work on the arch
            if outcome is not None:
                t_over = t
                done = done or stop_at_overturn
        if t >= next_out or done:
            rec(t, q[:-1], v[:-1], K, V, W_ground, D, float(at(t)), geo.gap, thick)
            F_rows.append(sup / sup_t if sup_t > 0 else np.zeros(4))
            sup, sup_t = np.zeros(4), 0.0
            next_out = t0 + dt_out * (math.floor((t - t0) / dt_out + 1e-9) + 1)
            if progress is not None:
                progress(t)
        if done:
            break
        if t >= t_hold - h_min:                  # the supports held from here on
            v[-2:] = q[-2:] = 0.0
            q[-2:, :2] = motion.up_to * np.array([motion.left, motion.right])
            t_hold = math.inf
        t_stop = min(t_end, t_hold)
        h = t_stop - t if t_stop - t < dt + h_min else dt    # no sliver of a step left at the end
        # 1. impact: a corner closes at t (it landed at the end of the last step, or its predicted
        #    landing is within MIN_STEP of t): the projection of v alone, in this configuration
        #    (no force acts during an impact); then 2. the landings within the step, predicted
        #    with the velocity after the impact, cut it there
        closed = geo.gap <= gap_tol
        a_g = at(t + 0.5 * h)
        acc[:n, 0] = -a_g * g
        K_in, hit, s = None, None, None
        while True:
            if (closed & ~was_closed).any() and (hit is None or (closed & ~hit).any()):
                if K_in is None:
                    K_in = kinetic(v)
                if stale:
                    geo, stale = con.evaluate(q), False
                sol, working_imp = _project(con, geo.rows, v, closed, working_imp, nonneg, free, g * h, IMPACT_PIVOTS)
                pivots += sol.pivots
                imp_v = con.apply_t(geo.rows, sol.P)
                v = v + minv * imp_v
                sup += imp_v[-2:, :2].ravel()
                w_sup = -float(np.sum(imp_v[-2:, :2] * v[-2:, :2]))      # the supports' work on the arch
                W_ground += w_sup
                W_sup += w_sup
                D += w_sup
                hit = closed.copy()
            if closed.all():
                s = None
                break
            vn = con.apply(geo.rows, v).reshape(J, 3)[:, :2]
            an = con.apply(geo.rows, acc).reshape(J, 3)[:, :2]
            s = np.where(closed, np.inf, _roots(geo.gap, vn, an))
            soon = s < h_min
            if not soon.any():
                break
            closed |= soon
        if K_in is not None:
            K_out = kinetic(v)
            D += K_in - K_out
            res.impacts.append((t, K_in, K_out))
        if s is not None:
            s_cut = float(np.min(s))
            if s_cut < h:
                h = s_cut
                cuts += 1
                a_g = at(t + 0.5 * h)
                acc[:n, 0] = -a_g * g
        # 3. midpoint, free velocity
        qm = q + 0.5 * h * v
        v_free = v + h * acc
        # 4. projection onto the compatible cone
        P = None
        if closed.any():
            gm = con.evaluate(qm)
            sol, working = _project(con, gm.rows, v_free, closed, working, nonneg, free, g * h)
            pivots += sol.pivots
            imp_v = con.apply_t(gm.rows, sol.P)
            v_new = v_free + minv * imp_v
            sup += imp_v[-2:, :2].ravel()
            w_sup = -float(np.sum(imp_v[-2:, :2] * v[-2:, :2]))
            W_ground += w_sup
            W_sup += w_sup
            P = sol.P.reshape(J, 3)
            ab = sol.ab
        else:
            v_new = v_free
            working = None
        was_closed = closed
        # 5. positions, projected onto the loaded contacts (velocities untouched)
        q_new = qm + 0.5 * h * v_new
        geo = con.evaluate(q_new)
        stale = False
        open_ = ~closed.any(axis=1)
        s_ref[open_] = geo.slip[jj, geo.contact][open_]
        if P is not None:
            loaded = closed & (geo.gap < OFF_FACE) & (((P[:, :2] > 0) & working.reshape(J, 3)[:, :2]) | (geo.gap < 0))
            if loaded.any():
                on = np.zeros((J, 3), bool)
                on[:, :2] = loaded
                on[:, 2] = loaded.any(axis=1)
                resid = np.concatenate([geo.gap, (geo.slip[jj, geo.contact] - s_ref)[:, None]], axis=1)
                on = on.ravel()
                lam = _solve_eq(con, ab, on, -np.where(on, resid.ravel(), 0.0))
                dq = minv * con.apply_t(gm.rows, lam)
                q_new = q_new + dq
                geo.gap = geo.gap + con.apply(geo.rows, dq).reshape(J, 3)[:, :2]   # to O(|dq|^2)
                stale = True                 # rows, slips: of q_new before dq (re-evaluated at an impact)
                drift += g * float(m @ dq[:n, 1]) + a_g * g * float(m @ dq[:n, 0])
        W_ground += float(-a_g * g * (m @ (q_new[:n, 0] - q[:n, 0])))
        q, v = q_new, v_new
        t = t + h
        sup_t += h
        steps += 1
    if outcome is None:
        outcome = "rest" if kinetic(v) < REST_KINETIC * E_unit else "survived"
    res.finish(outcome=outcome, t_end=t, t_overturn=t_over, peak_rotation=peak, t_peak=t_peak,
               energy_balance_error=balance, dissipated=D, ground_work=W_ground, projection_drift=drift, steps=steps,
               cut_steps=cuts, pivots=pivots, time=time.perf_counter() - clock)
    if motion is not None:
        support_history(res, motion, t0, F_rows)
        res.support_q_end = q[-2:, :2].copy()
    return res


def collapse(V: float, V_over: float, gap: np.ndarray, s_ref: np.ndarray) -> str | None:
    """The collapse decided in a configuration (None: none), as :func:`.kernel.collapse`:
    ``"collapsed_by_sliding"`` when a joint's faces no longer overlap (both ends' gaps
    :data:`~.contacts.OFF_FACE`); when ``V`` (J/m) is below the overturning level ``V_over``,
    ``"collapsed_by_sliding"`` if the largest slip a joint carries (m) exceeds the largest opening
    of a joint's end (m), else ``"overturned"``."""
    off = gap >= OFF_FACE
    if off.all(axis=1).any():
        return "collapsed_by_sliding"
    if V < V_over:
        opened = float(np.max(np.where(off, 0.0, gap), initial=0.0))
        return "collapsed_by_sliding" if float(np.max(np.abs(s_ref), initial=0.0)) > opened else "overturned"
    return None


def _project(con: Contacts, rows, v_free, closed, working, nonneg, free, floor, block_pivots=BLOCK_PIVOTS):
    """The MLCP of the projection of ``v_free`` with the closed corners ``closed`` ``(J, 2)``;
    returns the solution (with its banded ``W`` as ``ab``) and the new working set."""
    nonneg[:, :2] = closed
    free[:, 2] = closed.any(axis=1)
    ab = con.delassus(rows)
    c = con.apply(rows, v_free)
    vscale = max(float(np.max(np.abs(c))), floor, 1e-300)
    sol = solve_mlcp(con, ab, c, free.ravel(), nonneg.ravel(), working, vscale, block_pivots)
    sol.ab = ab
    return sol, sol.working


def _solve_eq(con: Contacts, ab: np.ndarray, on: np.ndarray, rhs: np.ndarray) -> np.ndarray:
    """``(W + reg I)_on lam = rhs`` on the rows ``on`` (zero elsewhere)."""
    return banded_solve(con.restrict(ab, on, REG * float(np.max(ab[BAND]))), rhs)
