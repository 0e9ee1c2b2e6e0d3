"""Compiled (numba) solvers of one step's contact problem.

**Without friction** (sticking joints) the problem is the MLCP of :mod:`.projection`

    w = W P + c;   w_T = 0 (sliding rows);   0 <= P_N  _|_  w_N >= 0 (opening rows),

solved as there: block principal pivots warm-started from the previous working set, then
Mehrotra's interior point on the same band, then a primal active-set method; every solution's
KKT residuals checked on the unregularised ``W``.

**With Coulomb friction** ``mu`` each joint with a closed corner carries the normal percussions
``P_n0, P_n1 >= 0`` of its corners and one tangential percussion ``P_t`` along its face, with

    |P_t| <= mu N  (N = P_n0 + P_n1);   |P_t| < mu N  =>  w_t = 0;   w_t != 0  =>  P_t = -mu N sign(w_t)

(sliding without dilatancy: the normal rates are not affected by sliding).  The sticking solution
is computed first; if every joint satisfies ``|P_t| <= mu N`` it is the answer.  Otherwise the
Tresca fixed point (Panagiotopoulos; Siconos' ``TFP`` solver): with the bounds ``mu N^k`` frozen
the problem is the convex QP ``min 1/2 P^T W P + c^T P`` with ``P_N >= 0`` and ``|P_t| <= mu N^k``,
solved by block principal pivoting on the box (a row is free, at its lower or at its upper bound;
every solve is the symmetric band of ``W`` on the free rows) or, failing that, by projected
Gauss-Seidel; ``N^{k+1}`` is its normal percussion, until the solution satisfies Coulomb's law
with its own normal percussions (:func:`coulomb_residual`, relative to the scales of the
percussions and rates, below ``COULOMB_TOL`` times the KKT tolerance).

Status codes: 0 solved, 1 did not converge, 2 the KKT (or Coulomb) check failed, 3 not positive
definite.
"""
from __future__ import annotations

import math

import numpy as np
from numba import njit

from .kernel_linalg import BAND, factor, matvec, solve

REG = 1e-12          # as projection.REG
KKT_TOL = 1e-8       # as projection.KKT_TOL (the default of the kkt_tol arguments)
MAX_PIVOTS = 1000
IPM_ITERATIONS = 80
BOX_PIVOTS = 100     # box pivots per Tresca problem
PGS_SWEEPS = 2000   # projected Gauss-Seidel sweeps (fallback)
FIXED_POINT = 60     # Tresca fixed-point iterations
RELAX_FROM = 10      # fixed-point iterations before the update of N is relaxed
COULOMB_TOL = 1e-5   # Coulomb residual admitted (relative to the scales of percussions and rates)
REG_FRICTION = 1e-9  # regularisation of the Tresca problems (relative to the largest diagonal entry of W):
                     # the self-stress states of redundant closed joints are otherwise decided by
                     # round-off at a condition number of 1e12, and the pivots cycle on them
NSGS_SWEEPS = 2000   # non-smooth Gauss-Seidel sweeps (the last resort of the frictional problem)
PGS_TOL = 1e-9       # projected gradient that ends the projected Gauss-Seidel, relative to the rates


@njit(cache=True, error_model="numpy")
def _maxabs(x):
    out = 0.0
    for i in range(x.size):
        a = abs(x[i])
        if a > out:
            out = a
    return out


@njit(cache=True, error_model="numpy")
def kkt_residual(P, w, free, nonneg, vscale, dmax):
    """Largest relative KKT residual of the sticking MLCP (as ``projection._checked``)."""
    pscale = max(_maxabs(P), vscale / max(dmax, 1e-300))
    res = 0.0
    for i in range(P.size):
        if free[i]:
            res = max(res, abs(w[i]) / vscale)
        if nonneg[i]:
            res = max(res, max(0.0, -w[i]) / vscale, max(0.0, -P[i]) / pscale,
                      abs(P[i] * w[i]) / (pscale * vscale))
    return res


@njit(cache=True, error_model="numpy")
def _rates(ab, P, c, reg, w):
    matvec(ab, P, w)
    for i in range(P.size):
        w[i] += reg * P[i] + c[i]


@njit(cache=True, error_model="numpy")
def _ipm(ab, c, free, nonneg, reg, vscale, U, out):
    """Mehrotra's predictor-corrector on ``min 1/2 P^T (W + reg) P + c^T P, P_N >= 0`` (the port of
    :func:`fembeam.analysis.banded_ipm.interior_point` as :mod:`.projection` calls it: separate
    steps to the boundary for ``P`` and ``z``).  ``out`` the solution; returns the iterations, -1 on
    failure."""
    m = c.size
    act = free | nonneg
    I = np.flatnonzero(nonneg)
    nI = max(I.size, 1)
    ps = vscale / max(_maxabs(ab[BAND]), 1e-300)
    tol = 1e-11
    g = np.zeros(m)
    for i in I:
        g[i] = ps
    z = np.full(I.size, vscale)
    r = np.empty(m)
    extra = np.zeros(m)
    rhs = np.empty(m)
    dg = np.empty(m)
    dz = np.empty(I.size)
    rc = np.empty(I.size)
    for it in range(IPM_ITERATIONS):
        _rates(ab, g, c, reg, r)
        for i in range(m):
            if not act[i]:
                r[i] = 0.0
        mu = 0.0
        for k in range(I.size):
            r[I[k]] -= z[k]
            mu += g[I[k]] * z[k]
        mu /= nI
        pscale = max(_maxabs(g), ps)
        if _maxabs(r) <= tol * vscale and mu <= 1e-2 * tol * vscale * pscale:
            out[:] = g
            return it + 1
        extra[:] = 0.0
        for k in range(I.size):
            extra[I[k]] = z[k] / g[I[k]]
        if not factor(ab, act, reg, extra, U):
            return -1
        # predictor: rc = g z
        for i in range(m):
            rhs[i] = -r[i]
        for k in range(I.size):
            rhs[I[k]] -= z[k]           # rc / g = z
        solve(U, rhs, dg)
        ag, az = 1.0, 1.0
        for k in range(I.size):
            i = I[k]
            dz[k] = (-g[i] * z[k] - z[k] * dg[i]) / g[i]
            if dg[i] < 0:
                ag = min(ag, g[i] / -dg[i])
            if dz[k] < 0:
                az = min(az, z[k] / -dz[k])
        mu_aff = 0.0
        for k in range(I.size):
            i = I[k]
            mu_aff += (g[i] + ag * dg[i]) * (z[k] + az * dz[k])
        mu_aff /= nI
        sigma = (mu_aff / mu) ** 3 if mu > 0 else 0.0
        for k in range(I.size):
            i = I[k]
            rc[k] = g[i] * z[k] + dg[i] * dz[k] - sigma * mu
        for i in range(m):
            rhs[i] = -r[i]
        for k in range(I.size):
            rhs[I[k]] -= rc[k] / g[I[k]]
        solve(U, rhs, dg)
        a = 1.0
        for k in range(I.size):
            i = I[k]
            dz[k] = (-rc[k] - z[k] * dg[i]) / g[i]
            if dg[i] < 0:
                a = min(a, g[i] / -dg[i])
            if dz[k] < 0:
                a = min(a, z[k] / -dz[k])
        a *= 0.995
        finite = 0.0
        for i in range(m):
            g[i] += a * dg[i]
            finite += 0.0 * g[i]
        for k in range(I.size):
            z[k] += a * dz[k]
            finite += 0.0 * z[k]
        if finite != 0.0:                # a NaN or an infinity
            return -1
    return -1


@njit(cache=True, error_model="numpy")
def solve_mlcp(ab, c, free, nonneg, F, warm, vscale, block_pivots, U, P, w, kkt_tol):
    """The sticking MLCP (port of :func:`.projection.solve_mlcp`).  ``F`` (in: the previous working
    set if ``warm``; out: the new one), ``P`` and ``w = W P + c`` the solution.  Returns
    ``(status, pivots, kkt)``."""
    m = c.size
    dmax = 0.0
    for i in range(m):
        dmax = max(dmax, ab[BAND, i])
    if not (free.any() or nonneg.any()):
        P[:] = 0.0
        w[:] = c
        F[:] = False
        return 0, 0, 0.0
    reg = REG * dmax
    for i in range(m):
        F[i] = free[i] or (nonneg[i] and (F[i] if warm else True))
    wtol = 1e-12 * vscale
    pscale0 = vscale / max(dmax, 1e-300)
    zero = np.zeros(m)
    rhs = np.empty(m)
    for k in range(block_pivots):
        if not factor(ab, F, reg, zero, U):
            return 3, k, 0.0
        for i in range(m):
            rhs[i] = -c[i] if F[i] else 0.0
        solve(U, rhs, P)
        _rates(ab, P, c, reg, w)
        ztol = 1e-12 * max(_maxabs(P), pscale0)
        nbad = 0
        for i in range(m):
            if nonneg[i] and ((F[i] and P[i] < -ztol) or (not F[i] and w[i] < -wtol)):
                nbad += 1
        if nbad == 0:
            for i in range(m):
                if nonneg[i] and P[i] < 0:
                    P[i] = 0.0
            matvec(ab, P, w)
            w += c
            res = kkt_residual(P, w, free, nonneg, vscale, dmax)
            return (0 if res <= kkt_tol else 2), k + 1, res
        for i in range(m):
            if nonneg[i] and ((F[i] and P[i] < -ztol) or (not F[i] and w[i] < -wtol)):
                F[i] = not F[i]
    its = _ipm(ab, c, free, nonneg, reg, vscale, U, P)
    if its >= 0:
        matvec(ab, P, w)
        w += c
        pmax = max(_maxabs(P), pscale0)
        Z = np.empty(m)
        for i in range(m):
            F[i] = free[i] or (nonneg[i] and P[i] * vscale > max(w[i], 0.0) * pmax)
            Z[i] = P[i] if F[i] else 0.0
        wz = np.empty(m)
        matvec(ab, Z, wz)
        wz += c
        res = kkt_residual(Z, wz, free, nonneg, vscale, dmax)
        if res <= kkt_tol:
            P[:] = Z
            w[:] = wz
            return 0, block_pivots + its, res
        res = kkt_residual(P, w, free, nonneg, vscale, dmax)
        return (0 if res <= kkt_tol else 2), block_pivots + its, res
    # last resort: Lawson-Hanson primal active set on the dual
    for i in range(m):
        F[i] = free[i] or (nonneg[i] and (F[i] if warm else True))
    P[:] = 0.0
    z = np.empty(m)
    for pivots in range(block_pivots + 1, MAX_PIVOTS + 1):
        if not factor(ab, F, reg, zero, U):
            return 3, pivots, 0.0
        for i in range(m):
            rhs[i] = -c[i] if F[i] else 0.0
        solve(U, rhs, z)
        ztol = 1e-12 * max(_maxabs(z), vscale / max(dmax, 1e-300))
        alpha = np.inf
        for i in range(m):
            if nonneg[i] and F[i] and z[i] < -ztol:
                alpha = min(alpha, P[i] / (P[i] - z[i]))
        if alpha < np.inf:
            for i in range(m):
                blocked = nonneg[i] and F[i] and z[i] < -ztol and P[i] / (P[i] - z[i]) <= alpha * (1 + 1e-12) + 1e-300
                P[i] = P[i] + alpha * (z[i] - P[i])
                if blocked:
                    F[i] = False
                if not F[i]:
                    P[i] = 0.0
            continue
        for i in range(m):
            P[i] = z[i] if F[i] else 0.0
            if nonneg[i] and P[i] < 0:
                P[i] = 0.0
        matvec(ab, P, w)
        w += c
        nadd = 0
        for i in range(m):
            if nonneg[i] and not F[i] and w[i] < -wtol:
                F[i] = True
                nadd += 1
        if nadd == 0:
            res = kkt_residual(P, w, free, nonneg, vscale, dmax)
            return (0 if res <= kkt_tol else 2), pivots, res
    return 1, MAX_PIVOTS, 0.0


# ------------------------------------------------------------------------------------- friction
@njit(cache=True, error_model="numpy")
def coulomb_residual(P, w, closed_joint, nonneg, mu, vscale, pscale):
    """Largest relative residual of the frictional contact law: normal complementarity, the cone
    ``|P_t| <= mu N``, sticking (``w_t = 0``) inside it and sliding against ``P_t`` on it."""
    res = 0.0
    for j in range(closed_joint.size):
        for r in range(2):
            i = 3 * j + r
            if nonneg[i]:
                res = max(res, max(0.0, -w[i]) / vscale, max(0.0, -P[i]) / pscale,
                          abs(P[i] * w[i]) / (pscale * vscale))
        if not closed_joint[j]:
            continue
        N = P[3 * j] + P[3 * j + 1]
        Pt, wt = P[3 * j + 2], w[3 * j + 2]
        excess = abs(Pt) - mu * N
        res = max(res, max(0.0, excess) / pscale)
        # inside the cone: no sliding; sliding: opposed to P_t with |P_t| = mu N
        slack = max(0.0, -excess) / pscale
        res = max(res, min(slack, abs(wt) / vscale))
        res = max(res, max(0.0, Pt * wt) / (pscale * vscale))
    return res


@njit(cache=True, error_model="numpy")
def _box_pivots(ab, c, lo, hi, state, reg, vscale, U, P, w):
    """``min 1/2 P^T (W + reg) P + c^T P`` with ``lo <= P <= hi`` (rows with ``lo = hi`` fixed) by block
    principal pivoting: ``state`` 0 free, 1 at ``lo``, 2 at ``hi`` (in: a start; out: the optimum's).
    True when converged."""
    m = c.size
    dmax = 0.0
    for i in range(m):
        dmax = max(dmax, ab[BAND, i])
    wtol = 1e-12 * vscale
    zero = np.zeros(m)
    PB = np.empty(m)
    rhs = np.empty(m)
    F = np.empty(m, np.bool_)
    for i in range(m):
        if hi[i] <= lo[i]:
            state[i] = 1
    for k in range(BOX_PIVOTS):
        for i in range(m):
            F[i] = state[i] == 0
            PB[i] = 0.0 if F[i] else (lo[i] if state[i] == 1 else hi[i])
        matvec(ab, PB, rhs)
        for i in range(m):
            rhs[i] = -(rhs[i] + reg * PB[i] + c[i]) if F[i] else PB[i]
        if not factor(ab, F, reg, zero, U):
            return False
        solve(U, rhs, P)
        _rates(ab, P, c, reg, w)
        ztol = 1e-12 * max(_maxabs(P), vscale / max(dmax, 1e-300))
        changed = 0
        for i in range(m):
            if hi[i] <= lo[i]:
                continue
            s = state[i]
            if s == 0 and P[i] < lo[i] - ztol:
                state[i] = 1
            elif s == 0 and P[i] > hi[i] + ztol:
                state[i] = 2
            elif s == 1 and w[i] < -wtol:
                state[i] = 0
            elif s == 2 and w[i] > wtol:
                state[i] = 0
            if state[i] != s:
                changed += 1
        if changed == 0:
            for i in range(m):
                P[i] = min(max(P[i], lo[i]), hi[i])
            return True
    return False


@njit(cache=True, error_model="numpy")
def _pgs(ab, c, lo, hi, reg, vscale, P, w):
    """Projected Gauss-Seidel on the same box QP (exact minimisation along each row, then the
    clamp): the fallback of :func:`_box_pivots`.  True when the projected gradient is below
    ``1e-12 vscale``."""
    m = c.size
    for i in range(m):
        P[i] = min(max(P[i], lo[i]), hi[i])
    for sweep in range(PGS_SWEEPS):
        matvec(ab, P, w)
        for i in range(m):
            w[i] += reg * P[i] + c[i]
        worst = 0.0
        for i in range(m):
            if hi[i] <= lo[i]:
                continue
            g = w[i]
            if (P[i] <= lo[i] and g > 0) or (P[i] >= hi[i] and g < 0):
                continue
            worst = max(worst, abs(g))
        if worst <= PGS_TOL * vscale:
            return True
        for i in range(m):               # one sweep, rates updated row by row
            if hi[i] <= lo[i]:
                continue
            d = ab[BAND, i] + reg
            gi = reg * P[i] + c[i] + ab[BAND, i] * P[i]
            for k in range(max(0, i - BAND), i):
                gi += ab[BAND + k - i, i] * P[k]
            for k in range(i + 1, min(m, i + BAND + 1)):
                gi += ab[BAND + i - k, k] * P[k]
            P[i] = min(max(P[i] - gi / d, lo[i]), hi[i])
    return False


@njit(cache=True, error_model="numpy")
def solve_friction(ab, c, nonneg, closed_joint, mu, vscale, state, U, P, w, tol):
    """The frictional problem from the sticking solution ``P`` (in; out: the solution, or the
    iterate of smallest residual) by the Tresca fixed point; ``state`` the box statuses (warm
    start; out: the solution's).  The bounds follow ``N`` (relaxed by 1/2 from iteration
    :data:`RELAX_FROM` on: a joint whose normal percussion vanishes when it slides and returns
    when it sticks makes the plain iteration a 2-cycle).  Returns ``(status, solves, residual)``:
    0 when :func:`coulomb_residual` is below ``tol``."""
    m = c.size
    J = closed_joint.size
    dmax = 0.0
    for i in range(m):
        dmax = max(dmax, ab[BAND, i])
    reg = REG_FRICTION * dmax
    lo = np.zeros(m)
    hi = np.zeros(m)
    N = np.empty(J)
    best = np.inf
    Pbest = P.copy()
    for j in range(J):
        N[j] = max(P[3 * j], 0.0) + max(P[3 * j + 1], 0.0)
    solves = 0
    for it in range(FIXED_POINT):
        for j in range(J):
            for r in range(2):
                i = 3 * j + r
                hi[i] = np.inf if nonneg[i] else 0.0
            i = 3 * j + 2
            b = mu * N[j] if closed_joint[j] else 0.0
            lo[i], hi[i] = -b, b
        ok = _box_pivots(ab, c, lo, hi, state, reg, vscale, U, P, w)
        solves += 1
        if not ok:
            ok = _pgs(ab, c, lo, hi, reg, vscale, P, w)
            solves += 1
            if not ok:
                break
        # Coulomb's law with the new normal percussions (the bounds used were the previous ones)
        matvec(ab, P, w)
        w += c
        pscale = max(_maxabs(P), vscale / max(dmax, 1e-300))
        res = coulomb_residual(P, w, closed_joint, nonneg, mu, vscale, pscale)
        if res < best:
            best = res
            Pbest[:] = P
        if res <= tol:
            return 0, solves, res
        omega = 0.5 if it >= RELAX_FROM else 1.0
        for j in range(J):
            N[j] += omega * (P[3 * j] + P[3 * j + 1] - N[j])
    P[:] = Pbest
    matvec(ab, P, w)
    w += c
    return 1, solves, best


@njit(cache=True, error_model="numpy")
def _local(Wl, q, mu, active0, active1, Pl):
    """Exact solution of one joint's frictional problem ``w = Wl P + q`` (``P = (P_n0, P_n1, P_t)``,
    ``active0/1``: the corner is closed) by enumeration of its cases: which corners carry a
    percussion, and sticking or sliding either way.  ``Pl`` the solution; False if no case is
    consistent (round-off), in which case ``Pl`` is the case with the smallest violation."""
    best, bestP0, bestP1, bestPt = np.inf, 0.0, 0.0, 0.0
    d = max(Wl[0, 0], Wl[1, 1], Wl[2, 2])          # percussions times d: rates (violations in m/s)
    tol = 1e-10 * (abs(q[0]) + abs(q[1]) + abs(q[2]) + 1e-300)
    for corners in range(4):                       # 0: none, 1: corner 0, 2: corner 1, 3: both
        a0, a1 = corners & 1 == 1, corners & 2 == 2
        if (a0 and not active0) or (a1 and not active1):
            continue
        for s in (0, 1, -1):                       # stick, P_t = +mu N, P_t = -mu N
            if corners == 0 and s != 0:
                continue
            # unknowns x = (P_n0, P_n1, P_t) with the inactive ones zero; equations w_i = 0 on the
            # active normal rows and, when sticking, on the tangential row; when sliding
            # P_t = s mu (P_n0 + P_n1) is substituted.
            A = np.zeros((3, 3))
            b = np.zeros(3)
            idx = np.zeros(3, np.int64)
            k = 0
            if a0:
                idx[k] = 0
                k += 1
            if a1:
                idx[k] = 1
                k += 1
            nn = k
            if s == 0 and corners != 0:
                idx[k] = 2
                k += 1
            for r in range(k):
                row = idx[r]
                b[r] = -q[row]
                for cc in range(k):
                    col = idx[cc]
                    A[r, cc] = Wl[row, col]
                    if s != 0 and col < 2:
                        A[r, cc] += Wl[row, 2] * s * mu
            x = np.zeros(3)
            if k > 0:
                sol = np.linalg.solve(A[:k, :k] + 0.0, b[:k])
                for r in range(k):
                    x[idx[r]] = sol[r]
            N = x[0] + x[1]
            if s != 0:
                x[2] = s * mu * N
            w0 = Wl[0, 0] * x[0] + Wl[0, 1] * x[1] + Wl[0, 2] * x[2] + q[0]
            w1 = Wl[1, 0] * x[0] + Wl[1, 1] * x[1] + Wl[1, 2] * x[2] + q[1]
            wt = Wl[2, 0] * x[0] + Wl[2, 1] * x[1] + Wl[2, 2] * x[2] + q[2]
            viol = max(0.0, -x[0] * d, -x[1] * d)
            if active0 and not a0:
                viol = max(viol, -w0)
            if active1 and not a1:
                viol = max(viol, -w1)
            if s == 0:
                viol = max(viol, (abs(x[2]) - mu * N) * d)
            else:
                viol = max(viol, s * wt)
            if viol < best:
                best, bestP0, bestP1, bestPt = viol, x[0], x[1], x[2]
            if viol <= tol:
                Pl[0], Pl[1], Pl[2] = x[0], x[1], x[2]
                return True
    Pl[0], Pl[1], Pl[2] = bestP0, bestP1, bestPt
    return False


@njit(cache=True, error_model="numpy")
def nsgs(ab, c, nonneg, closed_joint, mu, vscale, reg, tol, P, w):
    """Non-smooth Gauss-Seidel (Jean and Moreau; the solver of LMGC90 and Siconos): sweeps over
    the joints, each solved exactly (:func:`_local`) with the others' percussions frozen, from
    the ``P`` given, until :func:`coulomb_residual` is below ``tol``.  Returns
    ``(converged, sweeps, residual)``."""
    m = c.size
    J = closed_joint.size
    dmax = 0.0
    for i in range(m):
        dmax = max(dmax, ab[BAND, i])
    Wl = np.zeros((3, 3))
    ql = np.zeros(3)
    Pl = np.zeros(3)
    res = np.inf
    for j in range(J):
        if not closed_joint[j]:
            P[3 * j] = P[3 * j + 1] = P[3 * j + 2] = 0.0
    for sweep in range(NSGS_SWEEPS):
        matvec(ab, P, w)
        for i in range(m):
            w[i] += c[i]
        pscale = max(_maxabs(P), vscale / max(dmax, 1e-300))
        res = coulomb_residual(P, w, closed_joint, nonneg, mu, vscale, pscale)
        if res <= tol:
            return True, sweep, res
        for j in range(J):
            if not closed_joint[j]:
                continue
            base = 3 * j
            for r in range(3):               # the joint's block of W and its free rates
                for cc in range(3):
                    i, k = base + r, base + cc
                    lo_, hi_ = min(i, k), max(i, k)
                    Wl[r, cc] = ab[BAND + lo_ - hi_, hi_]
                Wl[r, r] += reg
            for r in range(3):
                i = base + r
                acc = c[i] + ab[BAND, i] * P[i]
                for k in range(max(0, i - BAND), i):
                    acc += ab[BAND + k - i, i] * P[k]
                for k in range(i + 1, min(m, i + BAND + 1)):
                    acc += ab[BAND + i - k, k] * P[k]
                ql[r] = acc
            for r in range(3):
                for cc in range(3):
                    ql[r] -= (Wl[r, cc] - (reg if r == cc else 0.0)) * P[base + cc]
            _local(Wl, ql, mu, nonneg[base], nonneg[base + 1], Pl)
            P[base], P[base + 1], P[base + 2] = Pl[0], Pl[1], Pl[2]
    return False, NSGS_SWEEPS, res
