"""The compiled (numba) loop of the Moreau-Jean time stepping of :mod:`.stepper`.

:func:`advance` runs the steps of :mod:`.stepper`'s docstring from the state it is given until the
end of the run, an overturning (when asked to stop there), or a budget of steps or output rows is
used (the caller then reports progress, checks for interrupts and calls again).  The state lives
in arrays owned by the caller: positions ``q`` and velocities ``v`` ``(n + 1, 3)``, the joint
geometry of the last configuration, the warm starts of the contact solvers, the scalars ``fs``
(floats, indices ``F_*``) and ``ist`` (integers, indices ``I_*``).
"""
from __future__ import annotations

import math

import numpy as np
from numba import njit

from .kernel_linalg import BAND, apply_h, apply_ht, delassus, factor, geometry, solve
from .kernel_solve import REG, nsgs, solve_friction, solve_mlcp

# float state
F_T, F_W, F_D, F_DRIFT, F_BAL, F_ESEEN, F_PEAK, F_TPEAK, F_NEXT, F_E0, F_TOVER, F_RATIO, F_TRATIO, \
    F_SLIP, F_TSLIP, F_VMIN, F_KKT, F_FRICTION, F_COULOMB = range(19)
N_FLOAT = 19
# integer state
I_STEPS, I_CUTS, I_PIVOTS, I_OUTCOME, I_HASW, I_HASWI, I_STALE, I_JRATIO, I_ATRATIO, I_JSLIP, I_STATUS, \
    I_SLIDING = range(12)
N_INT = 12
# outcomes while running (0: none yet)
OVERTURNED, SLID_OUT = 1, 2
# statuses of advance()
RUNNING, FINISHED, STOPPED = 0, 1, 2
SOLVER_FAILED = 3       # the contact problem of a step failed (ist[I_STATUS] the solver's code)
HISTORY_COLUMNS = 9


@njit(cache=True, error_model="numpy")
def ground_at(kind, amp, period, ts, av, time):
    """``a_g`` (g): a pulse's formula (``kind`` 1 rectangular, 2 one-sine, 3 Ricker) or the
    piecewise-linear signal ``ts``, ``av`` (kind 0), zero outside it (as ``GroundMotion.scalar``)."""
    if kind == 0:
        n = ts.size
        if time < ts[0] or time > ts[n - 1]:
            return 0.0
        i = min(np.searchsorted(ts, time, side="right"), n - 1)
        return av[i - 1] + (av[i] - av[i - 1]) * (time - ts[i - 1]) / (ts[i] - ts[i - 1])
    end = 3.0 * period if kind == 3 else period
    if time < 0.0 or time > end or (kind == 1 and time >= period):
        return 0.0
    if kind == 1:
        return amp
    if kind == 2:
        return amp * math.sin(2.0 * math.pi * time / period)
    u2 = (math.pi * (time - 1.5 * period) / period) ** 2
    return amp * (1.0 - 2.0 * u2) * math.exp(-u2)


@njit(cache=True, error_model="numpy")
def _kinetic(mv, v):
    n = mv.shape[0]
    out = 0.0
    for i in range(n):
        out += mv[i, 0] * v[i, 0] ** 2 + mv[i, 1] * v[i, 1] ** 2 + mv[i, 2] * v[i, 2] ** 2
    return 0.5 * out


@njit(cache=True, error_model="numpy")
def _potential(m, y0, g, q):
    out = 0.0
    for i in range(m.size):
        out += m[i] * (q[i, 1] - y0[i])
    return g * out


@njit(cache=True, error_model="numpy")
def _roots(gap, vn, an):
    """Smallest ``s > 0`` with ``gap + s vn + s^2/2 an = 0`` (``gap > 0``), inf if none."""
    a2 = 0.5 * an
    disc = vn * vn - 4.0 * a2 * gap
    den = -vn + math.sqrt(max(disc, 0.0))
    if disc >= 0 and den > 0:
        return 2.0 * gap / den
    return np.inf


@njit(cache=True, error_model="numpy")
def _project(rows, sides, minv, v_free, closed, F, warm, box, mu, floor, block_pivots, ab, U, P, w, c,
             fs, ist, t, at_impact, kkt_tol, coulomb_tol):
    """The contact problem of ``v_free`` with the closed corners ``closed`` ``(J, 2)``: ``P``, ``w``,
    ``ab`` (W) filled, ``F`` the new working set.  Returns the solver's status (0: solved) and
    tracks the friction demand in ``fs``/``ist``."""
    J = closed.shape[0]
    m = 3 * J
    nonneg = np.zeros(m, np.bool_)
    free = np.zeros(m, np.bool_)
    cj = np.zeros(J, np.bool_)
    for j in range(J):
        nonneg[3 * j] = closed[j, 0]
        nonneg[3 * j + 1] = closed[j, 1]
        cj[j] = closed[j, 0] or closed[j, 1]
        free[3 * j + 2] = cj[j]
    delassus(rows, sides, minv, ab)
    apply_h(rows, sides, v_free, c)
    vscale = 1e-300
    for i in range(m):
        vscale = max(vscale, abs(c[i]))
    vscale = max(vscale, floor)
    status, piv, res = solve_mlcp(ab, c, free, nonneg, F, warm, vscale, block_pivots, U, P, w, kkt_tol)
    ist[I_PIVOTS] += piv
    if status != 0:
        fs[F_KKT] = res
        return status
    if mu < np.inf:
        slide = False
        for j in range(J):
            if cj[j] and abs(P[3 * j + 2]) > mu * (P[3 * j] + P[3 * j + 1]) + 1e-12 * vscale / max(ab[BAND, 3 * j + 2], 1e-300):
                slide = True
                break
        if slide:
            # the stick solution violates the cone: the Tresca fixed point from it, then
            # non-smooth Gauss-Seidel
            for j in range(J):              # start: the stick solution's working set, the violated bounds
                for r in range(2):
                    box[3 * j + r] = 0 if F[3 * j + r] else 1
                N = P[3 * j] + P[3 * j + 1]
                box[3 * j + 2] = 2 if P[3 * j + 2] > mu * N else (1 if P[3 * j + 2] < -mu * N else 0)
            status, piv, res = solve_friction(ab, c, nonneg, cj, mu, vscale, box, U, P, w, coulomb_tol)
            ist[I_PIVOTS] += piv
            if status != 0:                 # non-smooth Gauss-Seidel from the best iterate
                dmax = 0.0
                for i in range(m):
                    dmax = max(dmax, ab[BAND, i])
                ok, sweeps, res = nsgs(ab, c, nonneg, cj, mu, vscale, REG * dmax, coulomb_tol, P, w)
                ist[I_PIVOTS] += sweeps
                if not ok:
                    fs[F_KKT] = res
                    return 4
            fs[F_COULOMB] = max(fs[F_COULOMB], res)
            for i in range(m):
                F[i] = free[i] or (nonneg[i] and P[i] > 0)
            ist[I_SLIDING] += 1
    # friction demand: |P_t| / N at the joints whose normal percussion is at least 1e-3 of the
    # percussion scale of the step's tolerances (the largest, or the rates' scale over W's
    # diagonal): a lighter joint's ratio is not resolved by them
    pmax, dmax = 0.0, 0.0
    for i in range(m):
        pmax = max(pmax, abs(P[i]))
        dmax = max(dmax, ab[BAND, i])
    pscale = max(pmax, vscale / max(dmax, 1e-300))
    for j in range(J):
        N = P[3 * j] + P[3 * j + 1]
        if cj[j] and N > 1e-3 * pscale:
            ratio = abs(P[3 * j + 2]) / N
            if ratio > fs[F_RATIO]:
                fs[F_RATIO] = ratio
                fs[F_TRATIO] = t
                ist[I_JRATIO] = j
                ist[I_ATRATIO] = at_impact
    return 0


@njit(cache=True, error_model="numpy")
def advance(q, v, A, B, sides, ra, rb, nu0, tau0, minv, m, mv, y0, thick, joint_thick,
            gap, slip, rows, contact, was_closed, working, working_imp, box, box_imp, s_ref,
            fs, ist, dt, t_end, t0, dt_out, g, h_min, gap_tol, V_over, slide_out, mu, stop,
            kind, amp, period, ts, av, impact_pivots, block_pivots,
            hist, pos, imp, max_steps, kkt_tol, coulomb_tol):
    """Steps from the state given until the end, a stop, ``max_steps`` steps, or the buffers
    ``hist`` ``(rows, 9)`` / ``pos`` ``(rows, n, 3)`` / ``imp`` ``(rows, 3)`` are full.  Returns
    ``(status, history rows written, impacts written)``."""
    n = m.size
    J = A.size
    M3 = 3 * J
    nh = 0
    ni = 0
    acc = np.zeros((n + 1, 3))
    for i in range(n):
        acc[i, 1] = -g
    ab = np.zeros((BAND + 1, M3))
    U = np.zeros((M3, BAND + 1))
    P = np.zeros(M3)
    w = np.zeros(M3)
    c = np.zeros(M3)
    Hv = np.zeros(M3)
    Ha = np.zeros(M3)
    imp_v = np.zeros((n + 1, 3))
    closed = np.zeros((J, 2), np.bool_)
    hit = np.zeros((J, 2), np.bool_)
    s_land = np.zeros((J, 2))
    gm_gap = np.zeros((J, 2))
    gm_slip = np.zeros((J, 2))
    gm_rows = np.zeros((J, 3, 2, 3))
    gm_contact = np.zeros(J, np.int64)
    qm = np.zeros((n + 1, 3))
    v_free = np.zeros((n + 1, 3))
    v_new = np.zeros((n + 1, 3))
    q_new = np.zeros((n + 1, 3))
    dq = np.zeros((n + 1, 3))
    on = np.zeros(M3, np.bool_)
    rhs = np.zeros(M3)
    lam = np.zeros(M3)
    zero = np.zeros(M3)
    Hdq = np.zeros(M3)
    t = fs[F_T]
    for count in range(max_steps + 1):
        K = _kinetic(mv, v)
        V = _potential(m, y0, g, q)
        fs[F_ESEEN] = max(fs[F_ESEEN], K + abs(V), abs(fs[F_W]), fs[F_D])
        fs[F_BAL] = max(fs[F_BAL], abs(K + V - fs[F_E0] - fs[F_W] + fs[F_D]) / fs[F_ESEEN])
        fs[F_VMIN] = min(fs[F_VMIN], V)
        rot = 0.0
        for i in range(n):
            rot = max(rot, abs(q[i, 2]))
        if rot > fs[F_PEAK]:
            fs[F_PEAK], fs[F_TPEAK] = rot, t
        done = t >= t_end - 1e-12 * dt
        if ist[I_OUTCOME] == 0 and V < V_over:
            ist[I_OUTCOME] = OVERTURNED
            fs[F_TOVER] = t
            done = done or stop
        if ist[I_OUTCOME] == 0 and mu < np.inf:
            for j in range(J):
                if abs(s_ref[j]) > slide_out * joint_thick[j]:
                    ist[I_OUTCOME] = SLID_OUT
                    fs[F_TOVER] = t
                    done = done or stop
                    break
        if t >= fs[F_NEXT] or done:
            if nh == hist.shape[0]:
                return RUNNING, nh, ni
            hinges, separated = 0, 0
            for j in range(J):
                k = int(gap[j, 0] > 1e-6 * thick[j]) + int(gap[j, 1] > 1e-6 * thick[j])
                hinges += k == 1
                separated += k == 2
            hist[nh, 0] = t
            hist[nh, 1] = K
            hist[nh, 2] = V
            hist[nh, 3] = fs[F_W]
            hist[nh, 4] = fs[F_D]
            hist[nh, 5] = ground_at(kind, amp, period, ts, av, t)
            hist[nh, 6] = hinges
            hist[nh, 7] = separated
            hist[nh, 8] = rot
            pos[nh] = q[:n]
            nh += 1
            fs[F_NEXT] = t0 + dt_out * (math.floor((t - t0) / dt_out + 1e-9) + 1)
        if done:
            return STOPPED if t < t_end - 1e-12 * dt else FINISHED, nh, ni
        if count == max_steps or ni == imp.shape[0]:
            return RUNNING, nh, ni
        h = min(dt, t_end - t)
        for j in range(J):
            for k in range(2):
                closed[j, k] = gap[j, k] <= gap_tol[j]
        a_g = ground_at(kind, amp, period, ts, av, t + 0.5 * h)
        for i in range(n):
            acc[i, 0] = -a_g * g
        K_in = -1.0
        have_hit = False
        s_cut = np.inf
        while True:
            newly = False
            beyond_hit = not have_hit
            all_closed = True
            for j in range(J):
                for k in range(2):
                    if closed[j, k] and not was_closed[j, k]:
                        newly = True
                    if have_hit and closed[j, k] and not hit[j, k]:
                        beyond_hit = True
                    if not closed[j, k]:
                        all_closed = False
            if newly and beyond_hit:
                if K_in < 0:
                    K_in = _kinetic(mv, v)
                if ist[I_STALE]:
                    geometry(q, A, B, ra, rb, nu0, tau0, gap, slip, rows, contact)
                    ist[I_STALE] = 0
                st = _project(rows, sides, minv, v, closed, working_imp, ist[I_HASWI] == 1, box_imp, mu, g * h,
                              impact_pivots, ab, U, P, w, c, fs, ist, t, 1, kkt_tol, coulomb_tol)
                if st != 0:
                    ist[I_STATUS] = st
                    fs[F_T] = t
                    return SOLVER_FAILED, nh, ni
                ist[I_HASWI] = 1
                apply_ht(rows, sides, P, imp_v)
                for i in range(n + 1):
                    for d in range(3):
                        v[i, d] += minv[i, d] * imp_v[i, d]
                hit[:, :] = closed
                have_hit = True
            if all_closed:
                s_cut = np.inf
                break
            apply_h(rows, sides, v, Hv)
            apply_h(rows, sides, acc, Ha)
            soon = False
            s_cut = np.inf
            for j in range(J):
                for k in range(2):
                    if closed[j, k]:
                        continue
                    s = _roots(gap[j, k], Hv[3 * j + k], Ha[3 * j + k])
                    if s < h_min:
                        soon = True
                        closed[j, k] = True
                    s_cut = min(s_cut, s)
            if not soon:
                break
        if K_in >= 0:
            K_out = _kinetic(mv, v)
            fs[F_D] += K_in - K_out
            imp[ni, 0] = t
            imp[ni, 1] = K_in
            imp[ni, 2] = K_out
            ni += 1
        if s_cut < h:
            h = s_cut
            ist[I_CUTS] += 1
            a_g = ground_at(kind, amp, period, ts, av, t + 0.5 * h)
            for i in range(n):
                acc[i, 0] = -a_g * g
        for i in range(n + 1):
            for d in range(3):
                qm[i, d] = q[i, d] + 0.5 * h * v[i, d]
                v_free[i, d] = v[i, d] + h * acc[i, d]
        any_closed = False
        for j in range(J):
            if closed[j, 0] or closed[j, 1]:
                any_closed = True
        if any_closed:
            geometry(qm, A, B, ra, rb, nu0, tau0, gm_gap, gm_slip, gm_rows, gm_contact)
            if mu < np.inf:
                apply_h(gm_rows, sides, v, Hv)      # the rates at the start of the step
            st = _project(gm_rows, sides, minv, v_free, closed, working, ist[I_HASW] == 1, box, mu, g * h,
                          block_pivots, ab, U, P, w, c, fs, ist, t, 0, kkt_tol, coulomb_tol)
            if st != 0:
                ist[I_STATUS] = st
                fs[F_T] = t
                return SOLVER_FAILED, nh, ni
            ist[I_HASW] = 1
            apply_ht(gm_rows, sides, P, imp_v)
            for i in range(n + 1):
                for d in range(3):
                    v_new[i, d] = v_free[i, d] + minv[i, d] * imp_v[i, d]
        else:
            v_new[:, :] = v_free
            ist[I_HASW] = 0
        was_closed[:, :] = closed
        for i in range(n + 1):
            for d in range(3):
                q_new[i, d] = qm[i, d] + 0.5 * h * v_new[i, d]
        geometry(q_new, A, B, ra, rb, nu0, tau0, gap, slip, rows, contact)
        ist[I_STALE] = 0
        if mu < np.inf:                   # the slip carried by the joints, the work of friction
            for j in range(J):
                if closed[j, 0] or closed[j, 1]:
                    # the slip and the work of P_t over the step: positions move by h/2 (v_k + v_k+1)
                    rate = 0.5 * (Hv[3 * j + 2] + w[3 * j + 2])
                    s_ref[j] += h * rate
                    work = -P[3 * j + 2] * rate              # P_t opposes the sliding rate
                    fs[F_FRICTION] += work
                    fs[F_D] += work
                else:
                    s_ref[j] = slip[j, contact[j]]
                if abs(s_ref[j]) > fs[F_SLIP]:
                    fs[F_SLIP] = abs(s_ref[j])
                    fs[F_TSLIP] = t + h
                    ist[I_JSLIP] = j
        if any_closed:
            nload = 0
            for j in range(J):
                lj = False
                for k in range(2):
                    lk = closed[j, k] and ((P[3 * j + k] > 0 and working[3 * j + k]) or gap[j, k] < 0)
                    on[3 * j + k] = lk
                    lj = lj or lk
                on[3 * j + 2] = lj
                nload += lj
            if nload > 0:
                for j in range(J):
                    for k in range(2):
                        rhs[3 * j + k] = -gap[j, k] if on[3 * j + k] else 0.0
                    rhs[3 * j + 2] = -(slip[j, contact[j]] - s_ref[j]) if on[3 * j + 2] else 0.0
                dmax = 0.0
                for i in range(M3):
                    dmax = max(dmax, ab[BAND, i])
                if not factor(ab, on, REG * dmax, zero, U):
                    ist[I_STATUS] = 3
                    fs[F_T] = t
                    return SOLVER_FAILED, nh, ni
                solve(U, rhs, lam)
                apply_ht(gm_rows, sides, lam, dq)
                for i in range(n + 1):
                    for d in range(3):
                        dq[i, d] *= minv[i, d]
                        q_new[i, d] += dq[i, d]
                apply_h(rows, sides, dq, Hdq)
                for j in range(J):
                    gap[j, 0] += Hdq[3 * j]
                    gap[j, 1] += Hdq[3 * j + 1]
                ist[I_STALE] = 1
                dy, dx = 0.0, 0.0
                for i in range(n):
                    dy += m[i] * dq[i, 1]
                    dx += m[i] * dq[i, 0]
                fs[F_DRIFT] += g * dy + a_g * g * dx
        wx = 0.0
        for i in range(n):
            wx += m[i] * (q_new[i, 0] - q[i, 0])
        fs[F_W] += -a_g * g * wx
        q[:, :] = q_new
        v[:, :] = v_new
        t = t + h
        fs[F_T] = t
        ist[I_STEPS] += 1
    return RUNNING, nh, ni
