"""The compiled (numba) time stepping of :mod:`.stepper`, in three layers, as in a non-smooth
contact dynamics code (the mechanical model, the one-step problem, its solvers):

1. **Operators**: the joint geometry and the rows of ``H`` (:mod:`.contacts`, as loops over the
   joints), ``H v``, ``H^T P``, the Delassus operator ``W = H M^-1 H^T`` in LAPACK's upper band
   storage (``W[i, k]`` at ``ab[BAND + i - k, k]``, ``i <= k``) and a banded Cholesky
   factorisation of ``W`` restricted to a set of rows (the others identity rows) plus a diagonal.
   Joint ``j`` has the reference side ``A[j]`` and the other side ``B[j]`` (body ``n``: the
   ground); rows ``3 j``, ``3 j + 1`` are the opening rates of its intrados and extrados corners
   (corner index ``c`` 0 and 1, the order of :data:`~fembeam.mechanisms.hinge.EDGES`) and
   ``3 j + 2`` the sliding rate at its ``contact`` corner.

2. **One step's contact problem.**  Without friction (sticking joints) it is the MLCP of
   :mod:`.projection`, ``w = W P + c``, ``w_T = 0`` (sliding rows), ``0 <= P_N _|_ w_N >= 0``,
   solved as there (:func:`solve_mlcp`: block principal pivots warm-started from the previous
   working set, Mehrotra's interior point, a primal active-set method; KKT residuals checked).
   With Coulomb friction ``mu`` a joint with a closed corner has normal percussions
   ``P_n0, P_n1 >= 0`` and one tangential percussion ``P_t`` along its face::

       |P_t| <= mu N  (N = P_n0 + P_n1);   |P_t| < mu N => w_t = 0;   w_t != 0 => P_t = -mu N sign(w_t)

   (sliding without dilatancy).  In order, until one satisfies Coulomb's law to the tolerance
   (:func:`coulomb_residual`):

   a. the sticking solution, if ``|P_t| <= mu N`` at every joint;
   b. the same velocities with a self-stress of the redundant closed joints added
      (:func:`self_stress`, :func:`redistribute`): between two abutments the percussions are
      determined up to three self-stress states, and one of them may lie in the cone;
   c. the semi-smooth Newton method on Alart and Curnier's equations (:func:`semismooth_newton`,
      damped on their squared residual, banded, and polished by one full step with the cases of
      its answer): from the sticking solution it settles most steps in a few iterations;
   d. the Tresca fixed point (:func:`solve_friction`; Siconos' ``TFP``): with the bounds
      ``mu N^k`` frozen, the convex QP ``min 1/2 P^T W P + c^T P``, ``P_N >= 0``,
      ``|P_t| <= mu N^k`` by block principal pivoting on the box (projected Gauss-Seidel as
      fallback), then ``N^{k+1}`` from its solution (relaxed after some iterations); where it
      stalls near the solution, Newton (c) from its best iterate (one step and the polish);
   e. non-smooth Gauss-Seidel with an exact solver per joint (:func:`nsgs`; LMGC90's and
      Siconos' solver), from the sticking solution, then from the best iterate of (d);
   f. Lemke's complementary pivoting on the problem written as a linear complementarity
      problem (:func:`lemke_friction`, Stewart and Trinkle's form, exact in the plane): a finite
      sequence of pivots where (c)-(e) iterate on the coupling of the joints, which grows with
      ``mu`` (a 7-voussoir arch under twice El Centro at ``mu = 10``: the fixed point cycled at a
      residual of 1.4e-2, Newton stalled at 1.9e-2, Gauss-Seidel at 7.9e-3 after 2000 sweeps,
      on a problem whose exact solution has two joints sliding).
   g. Newton again from the best answer of (c)-(f) (with ``mu = 1000`` every stage stalls from the
      sticking solution, and Newton converges from near the solution).

3. **The loop** (:func:`advance`) runs the steps of :mod:`.stepper` from the state it is given
   until the end of the run, an overturning (when asked to stop there), or a budget of steps or
   output rows is used (the caller then reports progress and calls again).  Its arguments are
   four named tuples of arrays owned by the caller: :class:`Model` (the bodies and joints),
   :class:`State` (positions ``q`` and velocities ``v`` ``(n + 2, 3)``, the last two rows the
   left and the right support, kinematic: moved at their own velocity; the joint geometry of the
   last configuration, the warm starts of the solvers, the scalars ``fs``, floats at indices
   ``F_*``, and ``ist``, integers at indices ``I_*``), :class:`Run` (the settings) and
   :class:`Buffers` (the outputs); its scratch arrays are a fifth, :class:`Work`.  A run's first
   call evaluates the geometry of the initial state (:func:`_start`); then each step is six
   phases:

   a. :func:`_observe`: the energies and their balance, the peak rotation, the collapse;
   b. :func:`_record`: a history row and the positions, at the output times;
   c. :func:`_events`: the closed corners, the impacts (:func:`_impact`), the landings that cut
      the step (:func:`_landings`), the step's length;
   d. :func:`_contact_step`: the midpoint, the contact problem of the smooth step, the new
      velocities and positions, the slip and the friction's work (:func:`_slip`);
   e. :func:`_correct`: the position projection onto the closed corners;
   f. :func:`_commit`: the ground's work, the state and the clocks at the step's end.

Solver status codes: 0 solved, 1 did not converge, 2 KKT check failed, 3 not positive definite,
4 the frictional problem unsolved.  One module, so that numba's on-disk cache (keyed on this
file) is never stale for a part of it.
"""
from __future__ import annotations

import math
from collections import namedtuple

import numpy as np
from numba import njit

from .constants import BAND, COULOMB_TOL, IPM_ITERATIONS, KKT_TOL, LOOSE, MAX_PIVOTS, OFF_FACE, OPEN_TOL, REG

# ================================================================================================= operators


@njit(cache=True, error_model="numpy")
def geometry(q, A, B, ra, rb, nu0, tau0, outward, depth, edge, gap, slip, rows, contact):
    """Gaps and slips ``(J, 2)`` (m), the rows of ``H`` ``(J, 3, 2, 3)`` and the contact ends at
    positions ``q`` ``(n + 1, 3)`` (:mod:`.contacts`: each end of a joint is the corner lying on
    the other body's face, ``b``'s or ``a``'s; none, gap ``OFF_FACE`` and zero rows, where the
    faces no longer overlap); ``ra``, ``rb`` ``(J, 2, 2)`` the corners relative to the centroids
    of the two sides at rest, ``nu0``, ``tau0`` ``(J, 2)`` the reference face's normal and tangent
    at rest, ``outward`` ``(J, 2)`` the outward sense of each end along ``tau0`` (+-1), ``depth``
    ``(J,)`` the joint's depth (m), ``edge`` ``(J,)`` (m) how far beyond ``a``'s face a corner of
    ``b`` still counts as over it (``contacts.EDGE_TOL`` times the depth)."""
    px = np.empty(2)
    py = np.empty(2)
    nx = np.empty(2)
    ny = np.empty(2)
    tx = np.empty(2)
    ty = np.empty(2)
    on = np.empty(2, np.bool_)
    for j in range(A.size):
        a, b = A[j], B[j]
        ca, sa = math.cos(q[a, 2]), math.sin(q[a, 2])
        cb, sb = math.cos(q[b, 2]), math.sin(q[b, 2])
        nax, nay = ca * nu0[j, 0] - sa * nu0[j, 1], sa * nu0[j, 0] + ca * nu0[j, 1]
        tax, tay = ca * tau0[j, 0] - sa * tau0[j, 1], sa * tau0[j, 0] + ca * tau0[j, 1]
        nbx, nby = cb * nu0[j, 0] - sb * nu0[j, 1], sb * nu0[j, 0] + cb * nu0[j, 1]
        tbx, tby = cb * tau0[j, 0] - sb * tau0[j, 1], sb * tau0[j, 0] + cb * tau0[j, 1]
        for c in range(2):
            pbx = q[b, 0] + cb * rb[j, c, 0] - sb * rb[j, c, 1]
            pby = q[b, 1] + sb * rb[j, c, 0] + cb * rb[j, c, 1]
            pax = q[a, 0] + ca * ra[j, c, 0] - sa * ra[j, c, 1]
            pay = q[a, 1] + sa * ra[j, c, 0] + ca * ra[j, c, 1]
            dx, dy = pbx - pax, pby - pay
            u = outward[j, c] * (dx * tax + dy * tay)
            if u > edge[j]:                       # b's corner beyond a's face: a's corner on b's face?
                px[c], py[c], nx[c], ny[c], tx[c], ty[c] = pax, pay, nbx, nby, tbx, tby
                on[c] = outward[j, c] * (dx * tbx + dy * tby) <= depth[j]
            else:                                 # b's corner on a's face?
                px[c], py[c], nx[c], ny[c], tx[c], ty[c] = pbx, pby, nax, nay, tax, tay
                on[c] = u >= -depth[j]
            gap[j, c] = dx * nx[c] + dy * ny[c] if on[c] else OFF_FACE
            slip[j, c] = dx * tx[c] + dy * ty[c]
        k = 1 if gap[j, 1] < gap[j, 0] else 0
        contact[j] = k
        for r in range(3):
            c = r if r < 2 else k
            dx, dy = (nx[c], ny[c]) if r < 2 else (tx[c], ty[c])
            if not on[c]:
                dx, dy = 0.0, 0.0
            x, y = px[c], py[c]
            rows[j, r, 1, 0] = dx
            rows[j, r, 1, 1] = dy
            rows[j, r, 1, 2] = (x - q[b, 0]) * dy - (y - q[b, 1]) * dx
            rows[j, r, 0, 0] = -dx
            rows[j, r, 0, 1] = -dy
            rows[j, r, 0, 2] = -((x - q[a, 0]) * dy - (y - q[a, 1]) * dx)


@njit(cache=True, error_model="numpy")
def apply_h(rows, sides, v, out):
    """``out = H v`` ``(3 J,)`` for body velocities ``v`` ``(n + 1, 3)``."""
    for j in range(sides.shape[0]):
        for r in range(3):
            acc = 0.0
            for s in range(2):
                i = sides[j, s]
                acc += rows[j, r, s, 0] * v[i, 0] + rows[j, r, s, 1] * v[i, 1] + rows[j, r, s, 2] * v[i, 2]
            out[3 * j + r] = acc


@njit(cache=True, error_model="numpy")
def apply_ht(rows, sides, P, out):
    """``out = H^T P`` (impulses on the bodies, ``(n + 2, 3)``; the last two rows: on the left and
    the right support, N s/m, which have no inverse mass)."""
    out[:] = 0.0
    for j in range(sides.shape[0]):
        for s in range(2):
            i = sides[j, s]
            for d in range(3):
                out[i, d] += rows[j, 0, s, d] * P[3 * j] + rows[j, 1, s, d] * P[3 * j + 1] \
                    + rows[j, 2, s, d] * P[3 * j + 2]


@njit(cache=True, error_model="numpy")
def delassus(rows, sides, minv, ab):
    """``ab`` = ``W = H M^-1 H^T`` in upper band storage ``(BAND + 1, 3 J)``: the blocks of a joint
    with itself and with the next joint (through the body they share)."""
    ab[:] = 0.0
    J = sides.shape[0]
    for j in range(J):
        for j2 in range(j, min(j + 2, J)):
            for s in range(2):
                body = sides[j, s]
                for s2 in range(2):
                    if sides[j2, s2] != body:
                        continue
                    for r in range(3):
                        for r2 in range(3):
                            i, k = 3 * j + r, 3 * j2 + r2
                            if i > k:
                                continue
                            ab[BAND + i - k, k] += rows[j, r, s, 0] * minv[body, 0] * rows[j2, r2, s2, 0] \
                                + rows[j, r, s, 1] * minv[body, 1] * rows[j2, r2, s2, 1] \
                                + rows[j, r, s, 2] * minv[body, 2] * rows[j2, r2, s2, 2]


@njit(cache=True, error_model="numpy")
def matvec(ab, x, out):
    """``out = W x`` from the upper band storage: row ``i`` sums ``W[i, i] x[i]``, then
    ``W[i, i - d] x[i - d]`` and ``W[i, i + d] x[i + d]`` for ``d = 1 .. BAND`` (the order of the
    sum by the band's columns it was), one pass over the rows per term: no pass carries a
    dependence from one row to the next (the passes by columns updated two rows each, 3.0 -> 2.3 us
    at 603 rows)."""
    m = x.size
    for i in range(m):
        out[i] = ab[BAND, i] * x[i]
    for d in range(1, BAND + 1):
        band = ab[BAND - d]              # W[k - d, k] at band[k]
        for i in range(d, m):
            out[i] += band[i] * x[i - d]
        for i in range(m - d):
            out[i] += band[i + d] * x[i + d]


@njit(cache=True, error_model="numpy")
def factor(ab, keep, reg, extra, U, j0=0) -> bool:
    """Cholesky ``U^T U`` of ``W`` restricted to the rows ``keep`` (the others identity rows) plus
    ``reg + extra`` on the kept diagonal; ``U[j, d]`` = ``U[j, j + d]`` for ``d > 0`` and ``U[j, 0]``
    the inverse of the diagonal entry ``1 / U[j, j]``.  From row ``j0`` on, the rows before it
    kept (row ``j`` depends on ``keep[j:j + BAND + 1]`` and the rows above: ``U`` of a ``keep``
    whose first change is at row ``r`` is resumed at ``r - BAND``).  False if not positive
    definite."""
    m = keep.size
    for j in range(j0, m):
        if not keep[j]:                  # an identity row: U's row and column j are e_j
            U[j, 0] = 1.0
            for d in range(1, BAND + 1):
                U[j, d] = 0.0
            continue
        a = ab[BAND, j] + reg + extra[j]
        for i in range(max(0, j - BAND), j):
            u = U[i, j - i]
            a -= u * u
        if not a > 0.0:
            return False
        inv = 1.0 / math.sqrt(a)
        U[j, 0] = inv
        for d in range(1, BAND + 1):
            k = j + d
            if k >= m or not keep[k]:
                U[j, d] = 0.0
                continue
            a = ab[BAND - d, k]
            for i in range(max(0, k - BAND), j):     # rows i < j of U[i, j] U[i, k]
                a -= U[i, j - i] * U[i, k - i]
            U[j, d] = a * inv
    return True


@njit(cache=True, error_model="numpy")
def solve(U, b, x):
    """``x`` with ``U^T U x = b`` (``U`` from :func:`factor`)."""
    m = b.size
    for j in range(m):                   # U^T y = b
        acc = b[j]
        for i in range(max(0, j - BAND), j):
            acc -= U[i, j - i] * x[i]
        x[j] = acc * U[j, 0]
    for j in range(m - 1, -1, -1):       # U x = y
        acc = x[j]
        for d in range(1, min(BAND, m - 1 - j) + 1):
            acc -= U[j, d] * x[j + d]
        x[j] = acc * U[j, 0]


# =========================================================================================== contact solvers
BOX_PIVOTS = 100     # box pivots per Tresca problem
PGS_SWEEPS = 2000   # projected Gauss-Seidel sweeps (fallback)
FIXED_POINT = 60     # Tresca fixed-point iterations
RELAX_FROM = 10      # fixed-point iterations before the update of N is relaxed
REG_FRICTION = 1e-9  # regularisation of the Tresca problems (relative to the largest diagonal entry of W):
                     # the self-stress states of redundant closed joints are otherwise decided by
                     # round-off at a condition number of 1e12, and the pivots cycle on them
SSN_ITERATIONS = 50   # semi-smooth Newton iterations
NSGS_SWEEPS = 2000   # non-smooth Gauss-Seidel sweeps (the last resort of the frictional problem)
PGS_TOL = 1e-9       # projected gradient that ends the projected Gauss-Seidel, relative to the rates
PIVOT_RATIO = 10.0         # Newton's banded elimination keeps the diagonal pivot unless a row below is this
                           # many times larger (1: partial pivoting)
CHECKPOINT = 16            # ... and saves the rows it is eliminating every this many columns: a Newton
                           # iteration whose cases differ from the last one's from row r on resumes there
                           # (8: Newton 3-5 % slower, its saves costing more than the columns it spared; 32: 5 %)
SELF_STRESS_PIVOT = 1e-4   # a factor's pivot below this x W's largest diagonal entry: self-stress states sought


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


@njit(cache=True)
def compiled_constants():
    """The values of :mod:`.constants` this compiled code was built with (numba freezes module
    globals at compilation; the cache is keyed on this file only), in the order of
    :func:`.constants.values`."""
    return (BAND, OFF_FACE, REG, KKT_TOL, MAX_PIVOTS, IPM_ITERATIONS, COULOMB_TOL, LOOSE, OPEN_TOL)


# ------------------------------------------------------------------------------------- friction
@njit(cache=True, error_model="numpy")
def coulomb_residual(P, w, closed_joint, nonneg, mu, vscale, pscale):
    """Largest relative residual of the frictional contact law: normal complementarity, the cone
    ``|P_t| <= mu N``, sticking (``w_t = 0``) inside it and sliding against ``P_t`` on it.  The
    terms of one scale are compared before their division by it (a correctly rounded division by
    a positive number is monotone: the same result as dividing each)."""
    rv = 0.0                             # rates, percussions, their products; then the sticking term
    rp = 0.0
    rpv = 0.0
    stick = 0.0
    for j in range(closed_joint.size):
        for r in range(2):
            i = 3 * j + r
            if nonneg[i]:
                rv = max(rv, -w[i])
                rp = max(rp, -P[i])
                rpv = max(rpv, abs(P[i] * w[i]))
        if not closed_joint[j]:
            continue
        N = P[3 * j] + P[3 * j + 1]
        Pt, wt = P[3 * j + 2], w[3 * j + 2]
        excess = abs(Pt) - mu * N
        rp = max(rp, excess)
        # inside the cone: no sliding; sliding: opposed to P_t with |P_t| = mu N
        if excess < 0.0 and wt != 0.0:
            stick = max(stick, min(-excess / pscale, abs(wt) / vscale))
        rpv = max(rpv, Pt * wt)
    return max(0.0, rv / vscale, rp / pscale, rpv / (pscale * vscale), stick)


@njit(cache=True, error_model="numpy")
def _box_pivots(ab, c, lo, hi, state, reg, vscale, U, built, P, w):
    """``min 1/2 P^T (W + reg) P + c^T P`` with ``lo <= P <= hi`` (rows with ``lo = hi`` fixed) by block
    principal pivoting: ``state`` 0 free, 1 at ``lo``, 2 at ``hi`` (in: a start; out: the optimum's).
    ``U`` the factor (:func:`factor`, at ``reg``) of the free rows ``built`` (1 free, 0 not, -1
    unknown; in and out: each pivot's factorisation resumes the last one).  True when converged."""
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
        first = 0                        # U resumed where F first differs from the rows it has
        while first < m and built[first] == F[first]:
            first += 1
        if first < m:
            if not factor(ab, F, reg, zero, U, max(first - BAND, 0)):
                built[:] = -1
                return False
            for i in range(first, m):
                built[i] = F[i]
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
    built = np.full(m, -1, np.int64)     # the free rows U was factored on (_box_pivots)
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
        ok = _box_pivots(ab, c, lo, hi, state, reg, vscale, U, built, P, w)
        solves += 1
        if not ok:                       # the pivots from all rows free, then Gauss-Seidel
            state[:] = 0
            ok = _box_pivots(ab, c, lo, hi, state, reg, vscale, U, built, P, w)
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
def _small_solve(A, b, k, x) -> bool:
    """``x[:k]`` with ``A[:k, :k] x = b[:k]`` (``k <= 3``; ``A``, ``b`` overwritten) by Gaussian
    elimination with partial pivoting, as LAPACK's ``dgesv`` on the copy :func:`_local` used to
    allocate.  False if a pivot vanishes (singular)."""
    for j in range(k):
        p = j
        big = abs(A[j, j])
        for i in range(j + 1, k):
            if abs(A[i, j]) > big:
                big, p = abs(A[i, j]), i
        if big == 0.0:
            return False
        if p != j:
            for cc in range(k):
                A[j, cc], A[p, cc] = A[p, cc], A[j, cc]
            b[j], b[p] = b[p], b[j]
        for i in range(j + 1, k):
            f = A[i, j] / A[j, j]
            for cc in range(j + 1, k):
                A[i, cc] -= f * A[j, cc]
            b[i] -= f * b[j]
    for i in range(k - 1, -1, -1):
        acc = b[i]
        for cc in range(i + 1, k):
            acc -= A[i, cc] * x[cc]
        x[i] = acc / A[i, i]
    return True


@njit(cache=True, error_model="numpy")
def _local(Wl, q, mu, active0, active1, Pl, A, b, sol):
    """Exact solution of one joint's frictional problem ``w = Wl P + q`` (``P = (P_n0, P_n1, P_t)``,
    ``active0/1``: the corner is closed) by enumeration of its cases: which corners carry a
    percussion, and sticking or sliding either way.  ``Pl`` the solution; False if no case is
    consistent (round-off), in which case ``Pl`` is the case with the smallest violation.  ``A``
    ``(3, 3)``, ``b``, ``sol`` ``(3,)``: scratch (no allocation per case: this runs once per joint
    and sweep of :func:`nsgs`, thousands of sweeps on a hard step)."""
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
            i0, i1, i2 = 0, 0, 0                   # the unknowns' indices, in order
            k = 0
            if a0:
                i0 = 0
                k += 1
            if a1:
                if k == 0:
                    i0 = 1
                else:
                    i1 = 1
                k += 1
            if s == 0 and corners != 0:
                if k == 0:
                    i0 = 2
                elif k == 1:
                    i1 = 2
                else:
                    i2 = 2
                k += 1
            for r in range(k):
                row = i0 if r == 0 else (i1 if r == 1 else i2)
                b[r] = -q[row]
                for cc in range(k):
                    col = i0 if cc == 0 else (i1 if cc == 1 else i2)
                    A[r, cc] = Wl[row, col]
                    if s != 0 and col < 2:
                        A[r, cc] += Wl[row, 2] * s * mu
            x0, x1, x2 = 0.0, 0.0, 0.0
            if k > 0:
                if not _small_solve(A, b, k, sol):
                    continue
                for r in range(k):
                    col = i0 if r == 0 else (i1 if r == 1 else i2)
                    if col == 0:
                        x0 = sol[r]
                    elif col == 1:
                        x1 = sol[r]
                    else:
                        x2 = sol[r]
            N = x0 + x1
            if s != 0:
                x2 = s * mu * N
            w0 = Wl[0, 0] * x0 + Wl[0, 1] * x1 + Wl[0, 2] * x2 + q[0]
            w1 = Wl[1, 0] * x0 + Wl[1, 1] * x1 + Wl[1, 2] * x2 + q[1]
            wt = Wl[2, 0] * x0 + Wl[2, 1] * x1 + Wl[2, 2] * x2 + q[2]
            viol = max(0.0, -x0 * d, -x1 * d)
            if active0 and not a0:
                viol = max(viol, -w0)
            if active1 and not a1:
                viol = max(viol, -w1)
            if s == 0:
                viol = max(viol, (abs(x2) - mu * N) * d)
            else:
                viol = max(viol, s * wt)
            if viol < best:
                best, bestP0, bestP1, bestPt = viol, x0, x1, x2
            if viol <= tol:
                Pl[0], Pl[1], Pl[2] = x0, x1, x2
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
    As = np.zeros((3, 3))
    bs = np.zeros(3)
    xs = np.zeros(3)
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
            _local(Wl, ql, mu, nonneg[base], nonneg[base + 1], Pl, As, bs, xs)
            P[base], P[base + 1], P[base + 2] = Pl[0], Pl[1], Pl[2]
    return False, NSGS_SWEEPS, res


@njit(cache=True, error_model="numpy")
def _lemke(M, q, z, max_pivots):
    """Lemke's complementary pivoting for ``w = M z + q``, ``0 <= z _|_ w >= 0`` (covering vector
    of ones; lexicographic ratio test, so degenerate rows do not cycle): True with ``z`` the
    solution, False on a secondary ray or after ``max_pivots`` pivots."""
    n = q.size
    if n == 0 or np.min(q) >= 0.0:
        z[:] = 0.0
        return True
    T = np.zeros((n, 2 * n + 2))          # columns: w (n), z (n), z0, right-hand side
    for i in range(n):
        T[i, i] = 1.0
        for k in range(n):
            T[i, n + k] = -M[i, k]
        T[i, 2 * n] = -1.0
        T[i, 2 * n + 1] = q[i]
    basis = np.arange(n)
    r = int(np.argmin(q))
    enter = 2 * n
    for it in range(max_pivots):
        if it > 0:                        # the ratio test on the entering column
            scale = 0.0
            for i in range(n):
                scale = max(scale, abs(T[i, enter]))
            r = -1
            for i in range(n):
                if T[i, enter] <= 1e-11 * scale:
                    continue
                if r < 0:
                    r = i
                    continue
                a = T[i, 2 * n + 1] / T[i, enter]
                b = T[r, 2 * n + 1] / T[r, enter]
                if a < b - 1e-13 * (abs(a) + abs(b)):
                    r = i
                elif a <= b + 1e-13 * (abs(a) + abs(b)):       # a tie: z0 leaves first, else lexicographic
                    if basis[r] == 2 * n:
                        continue
                    if basis[i] == 2 * n:
                        r = i
                        continue
                    for k in range(n):
                        x, y = T[i, k] / T[i, enter], T[r, k] / T[r, enter]
                        if x < y:
                            r = i
                            break
                        if x > y:
                            break
            if r < 0:
                return False
        piv = T[r, enter]
        for k in range(2 * n + 2):
            T[r, k] /= piv
        for i in range(n):
            if i != r and T[i, enter] != 0.0:
                f = T[i, enter]
                for k in range(2 * n + 2):
                    T[i, k] -= f * T[r, k]
        leaving = basis[r]
        basis[r] = enter
        if leaving == 2 * n:
            z[:] = 0.0
            for i in range(n):
                if basis[i] >= n and basis[i] < 2 * n:
                    z[basis[i] - n] = max(T[i, 2 * n + 1], 0.0)
            return True
        enter = leaving + n if leaving < n else leaving - n
    return False


@njit(cache=True, error_model="numpy")
def lemke_friction(ab, c, nonneg, closed_joint, mu, vscale, reg, P, w):
    """The frictional problem as the linear complementarity problem of Stewart and Trinkle (exact
    for a planar joint: the cone has two edges), solved by Lemke's method (:func:`_lemke`): per
    closed joint the normal percussions ``P_n >= 0`` of its closed corners, ``P_t = b+ - b-``
    with ``b+-`` >= 0 and the sliding speed ``l >= 0``:

        w_n >= 0 _|_ P_n;  l + w_t >= 0 _|_ b+;  l - w_t >= 0 _|_ b-;  mu N - b+ - b- >= 0 _|_ l.

    Unlike the fixed point, Newton and Gauss-Seidel it does not iterate on the coupling of the
    joints, which ``mu`` scales: a finite sequence of pivots (``4 n`` at most, ``n`` unknowns;
    about ``n`` in practice, each ``O(n^2)``).  ``P``, ``w`` the solution; returns
    ``(converged, pivots, residual)`` (:func:`coulomb_residual`)."""
    m = c.size
    J = closed_joint.size
    rows_n = np.empty(m, np.int64)
    nN = 0
    for i in range(m):
        if nonneg[i]:
            rows_n[nN] = i
            nN += 1
    joints = np.empty(J, np.int64)
    nT = 0
    for j in range(J):
        if closed_joint[j]:
            joints[nT] = j
            nT += 1
    n = nN + 3 * nT
    M = np.zeros((n, n))
    q = np.zeros(n)
    idx = np.empty(nN + nT, np.int64)           # the MLCP's rows: the normal ones, then the tangential
    for a in range(nN):
        idx[a] = rows_n[a]
    for b in range(nT):
        idx[nN + b] = 3 * joints[b] + 2
    for a in range(nN + nT):
        for b in range(nN + nT):
            i, k = idx[a], idx[b]
            lo, hi = min(i, k), max(i, k)
            Wik = ab[BAND + lo - hi, hi] if hi - lo <= BAND else 0.0
            if a == b:
                Wik += reg
            # the columns of P_n and b+ take W, those of b- take -W
            if a < nN:
                if b < nN:
                    M[a, b] = Wik
                else:
                    M[a, b] = Wik
                    M[a, b + nT] = -Wik
            else:
                ra = a + 0                          # w_t row (for b+) and -w_t row (for b-)
                if b < nN:
                    M[ra, b] = Wik
                    M[ra + nT, b] = -Wik
                else:
                    M[ra, b] = Wik
                    M[ra, b + nT] = -Wik
                    M[ra + nT, b] = -Wik
                    M[ra + nT, b + nT] = Wik
    for a in range(nN):
        q[a] = c[rows_n[a]]
    for b in range(nT):
        q[nN + b] = c[3 * joints[b] + 2]
        q[nN + nT + b] = -c[3 * joints[b] + 2]
        M[nN + b, nN + 2 * nT + b] = 1.0            # + l
        M[nN + nT + b, nN + 2 * nT + b] = 1.0
        M[nN + 2 * nT + b, nN + b] = -1.0           # mu N - b+ - b-
        M[nN + 2 * nT + b, nN + nT + b] = -1.0
    for a in range(nN):
        j = rows_n[a] // 3
        for b in range(nT):
            if joints[b] == j:
                M[nN + 2 * nT + b, a] = mu
    z = np.zeros(n)
    ok = _lemke(M, q, z, 4 * n + 10)
    P[:] = 0.0
    for a in range(nN):
        P[rows_n[a]] = z[a]
    for b in range(nT):
        P[3 * joints[b] + 2] = z[nN + b] - z[nN + nT + b]
    matvec(ab, P, w)
    for i in range(m):
        w[i] += c[i]
    dmax = 0.0
    for i in range(m):
        dmax = max(dmax, ab[BAND, i])
    pscale = max(_maxabs(P), vscale / max(dmax, 1e-300))
    res = coulomb_residual(P, w, closed_joint, nonneg, mu, vscale, pscale)
    return ok, n, res


@njit(cache=True, error_model="numpy")
def self_stress(ab, F, reg, U, Z):
    """:func:`self_stress_of` with ``W_FF + reg`` factorised here."""
    return self_stress_of(ab, F, reg, U, Z, False)


@njit(cache=True, error_model="numpy")
def self_stress_of(ab, F, reg, U, Z, factored):
    """The self-stress states of the rows ``F``: an orthonormal basis of the null space of ``W``
    restricted to them (its columns ``Z[:, :k]``; returns ``k``; at most ``Z.shape[1]``), by three
    inverse iterations on ``W_FF + reg`` from fixed starting vectors and a Rayleigh-Ritz step
    (kept: Ritz values below ``1e-7`` of ``W``'s largest diagonal entry).  The percussions of a
    redundant set of closed joints are determined up to these states; the velocities are not
    affected by them (``W Z = 0``)."""
    m = F.size
    q = Z.shape[1]
    dmax = 0.0
    for i in range(m):
        dmax = max(dmax, ab[BAND, i])
    if not factored:                     # (factored: U is already that factor, the sticking solve's)
        zero = np.zeros(m)
        if not factor(ab, F, reg, zero, U):
            return 0
    # a null vector z of W_FF whose last entry is at row p makes W's leading block up to p singular:
    # the factor's pivot there (1 / U[p, 0]^2) is at most reg |z|^2 / z_p^2.  With every pivot
    # above SELF_STRESS_PIVOT of W's diagonal there is none unless its entries span four orders of
    # magnitude (a self-stress of the joints of a member spans the ratio of its lengths); so on most
    # steps the inverse iterations, the Rayleigh-Ritz step and their checks (more than a frictional
    # step's Newton iterations) are skipped
    small = False
    for i in range(m):
        if F[i] and U[i, 0] * U[i, 0] * SELF_STRESS_PIVOT * dmax >= 1.0:
            small = True
            break
    if not small:
        return 0
    X = np.zeros((m, q))
    for i in range(m):                   # deterministic, generic starting vectors on F
        if F[i]:
            for k in range(q):
                X[i, k] = math.sin(1.0 + 0.7 * i + 1.3 * k * i + 0.5 * k)
    col = np.empty(m)
    out = np.empty(m)
    for it in range(3):
        for k in range(q):
            col[:] = X[:, k]
            solve(U, col, out)
            for i in range(m):
                X[i, k] = out[i] if F[i] else 0.0
        for k in range(q):               # modified Gram-Schmidt
            for l in range(k):
                d = 0.0
                for i in range(m):
                    d += X[i, k] * X[i, l]
                for i in range(m):
                    X[i, k] -= d * X[i, l]
            nrm = 0.0
            for i in range(m):
                nrm += X[i, k] * X[i, k]
            nrm = math.sqrt(nrm)
            for i in range(m):           # a dependent vector (fewer rows than vectors) is dropped
                X[i, k] = X[i, k] / nrm if nrm > 1e-8 else 0.0
    WX = np.empty((m, q))
    for k in range(q):
        col[:] = X[:, k]
        matvec(ab, col, out)
        for i in range(m):
            WX[i, k] = out[i] if F[i] else 0.0
    R = X.T @ WX
    R = 0.5 * (R + R.T)
    lam, V = np.linalg.eigh(R)
    Y = X @ V
    k = 0
    for l in range(q):                   # kept: unit vectors on F whose rates W y vanish
        nrm = 0.0
        for i in range(m):
            col[i] = Y[i, l] if F[i] else 0.0
            nrm += col[i] * col[i]
        if not (lam[l] <= 1e-7 * dmax and abs(math.sqrt(nrm) - 1.0) < 1e-6):
            continue
        matvec(ab, col, out)
        wn = 0.0
        for i in range(m):
            if F[i]:
                wn = max(wn, abs(out[i]))
        if wn <= 1e-7 * dmax:
            Z[:, k] = col
            k += 1
    return k


@njit(cache=True, error_model="numpy")
def redistribute(P, Z, k, nonneg, F, closed_joint, mu, margin):
    """Percussions ``P + Z s`` in the cone (``P_n >= 0`` on the rows of ``F``,
    ``|P_t| <= mu N - margin``, to ``margin / 2``) for some combination ``s`` of the self-stress states ``Z[:, :k]``:
    the squared violations minimised by Newton's method on their piecewise-quadratic sum (a few
    ``k x k`` solves).  ``P`` is replaced and True returned when the violations vanish."""
    if k == 0:
        return False
    J = closed_joint.size
    # the constraints a . s <= b, one per row: -P_n <= -margin; P_t - mu N <= -margin; -P_t - mu N <= -margin
    nc = 0
    A = np.zeros((4 * J, k))             # two corners and the two sides of the cone per joint
    b = np.zeros(4 * J)
    for j in range(J):
        for r in range(2):
            i = 3 * j + r
            if nonneg[i] and F[i]:
                for l in range(k):
                    A[nc, l] = -Z[i, l]
                b[nc] = P[i]
                nc += 1
        if closed_joint[j]:
            for sgn in (1.0, -1.0):
                for l in range(k):
                    A[nc, l] = sgn * Z[3 * j + 2, l] - mu * (Z[3 * j, l] + Z[3 * j + 1, l])
                b[nc] = -sgn * P[3 * j + 2] + mu * (P[3 * j] + P[3 * j + 1]) - margin
                nc += 1
    s = np.zeros(k)
    for it in range(50):
        H = np.zeros((k, k))
        g = np.zeros(k)
        worst = 0.0
        for c in range(nc):
            r = -b[c]
            for l in range(k):
                r += A[c, l] * s[l]
            if r > 0:
                worst = max(worst, r)
                for l in range(k):
                    g[l] += A[c, l] * r
                    for l2 in range(k):
                        H[l, l2] += A[c, l] * A[c, l2]
        if worst <= 0.5 * margin:
            for i in range(P.size):
                for l in range(k):
                    P[i] += Z[i, l] * s[l]
            return True
        for l in range(k):
            H[l, l] += 1e-14 * (H[l, l] + 1e-300)
        step = np.linalg.solve(H, g)
        # backtracking on the sum of squared violations
        f0 = 0.0
        for c in range(nc):
            r = -b[c]
            for l in range(k):
                r += A[c, l] * s[l]
            if r > 0:
                f0 += r * r
        alpha = 1.0
        for ls in range(30):
            f1 = 0.0
            for c in range(nc):
                r = -b[c]
                for l in range(k):
                    r += A[c, l] * (s[l] - alpha * step[l])
                if r > 0:
                    f1 += r * r
            if f1 < f0:
                break
            alpha *= 0.5
        for l in range(k):
            s[l] -= alpha * step[l]
    return False


@njit(cache=True, error_model="numpy")
def _ac_merit(ab, c, nonneg, closed_joint, mu, rho, P, w):
    """``|Phi(P)|^2`` of the Alart-Curnier equations (percussion units), ``w`` filled."""
    m = c.size
    matvec(ab, P, w)
    for i in range(m):
        w[i] += c[i]
    out = 0.0
    for j in range(closed_joint.size):
        for r in range(2):
            i = 3 * j + r
            f = P[i] - max(0.0, P[i] - rho[i] * w[i]) if nonneg[i] else P[i]
            out += f * f
        i = 3 * j + 2
        if closed_joint[j]:
            b = mu * (max(P[3 * j], 0.0) + max(P[3 * j + 1], 0.0))
            f = P[i] - min(max(P[i] - rho[i] * w[i], -b), b)
        else:
            f = P[i]
        out += f * f
    return out


@njit(cache=True, error_model="numpy")
def _band_factor(A, b, kl, j0, last, saved, saved_last) -> bool:
    """Forward elimination of ``A x = b`` in place, for a square matrix whose entries vanish outside
    ``-kl <= k - i <= kl``, stored by rows as ``A[i, kl + k - i]`` (``m x (3 kl + 1)``: pivoting
    moves a row's entries up to ``2 kl`` to the right of the diagonal): Gaussian elimination
    restricted to the band (LAPACK's ``dgbsv`` order: ``O(m kl^2)`` operations and ``O(m kl)``
    storage; a dense ``m x m`` matrix cost ``O(m^2)`` per Newton iteration only to be cleared),
    leaving ``U`` in ``A`` and ``L^-1 b`` in ``b`` (:func:`_band_back` then solves).  Threshold
    pivoting: the diagonal is kept unless a row below has an entry :data:`PIVOT_RATIO` times larger
    (partial pivoting swapped three rows in four of ``W``'s, whose tangential and normal rows
    differ in scale, and each swap doubles the row's length); each row's last nonzero column
    tracked (``last[i]``: one past it, as given, then as filled), and the updates stop there.

    From column ``j0`` (a multiple of :data:`CHECKPOINT`): every :data:`CHECKPOINT` columns the
    rows the elimination has begun but not finished (``j .. j + kl - 1``: ``A``'s, then ``b``'s in
    the last column of ``saved[j // CHECKPOINT]``) and their ``last`` (``saved_last``) are saved; a
    call with ``j0 > 0`` restores them and keeps the columns before ``j0`` of the last elimination
    (valid when the rows ``< j0 + kl`` of ``A`` and ``b`` are those it eliminated: the rows from
    ``j0 + kl`` on are the caller's, as assembled, with their ``last``).  The
    same operations in the same order as an elimination from column 0.  False if a pivot
    vanishes (singular)."""
    m, width = A.shape
    for j in range(j0, m):
        if j % CHECKPOINT == 0:
            s = j // CHECKPOINT
            restore = j == j0 and j0 > 0
            for i in range(j, min(m, j + kl)):
                row, keep_row = A[i], saved[s, i - j]
                if restore:
                    last[i] = saved_last[s, i - j]
                    for k in range(width):
                        row[k] = keep_row[k]
                    b[i] = keep_row[width]
                else:
                    saved_last[s, i - j] = last[i]
                    for k in range(width):
                        keep_row[k] = row[k]
                    keep_row[width] = b[i]
        p = j
        big = abs(A[j, kl])
        keep = PIVOT_RATIO * big
        for i in range(j + 1, min(m, j + kl + 1)):
            v = abs(A[i, kl + j - i])
            if v > big:
                big, p = v, i
        if big == 0.0:
            return False
        if big <= keep:
            p = j
        if p != j:
            top = max(last[j], last[p])
            rj, rp = A[j], A[p]
            dp = kl + j - p
            for o in range(top - j):
                t = rj[kl + o]
                rj[kl + o] = rp[dp + o]
                rp[dp + o] = t
            b[j], b[p] = b[p], b[j]
            last[j], last[p] = last[p], last[j]
        rj = A[j]
        pivot = rj[kl]
        n = last[j] - j
        bj = b[j]
        for i in range(j + 1, min(m, j + kl + 1)):
            ri = A[i]
            di = kl + j - i
            f = ri[di] / pivot
            if f != 0.0:
                for o in range(1, n):
                    ri[di + o] -= f * rj[kl + o]
                b[i] -= f * bj
                if last[j] > last[i]:
                    last[i] = last[j]
            ri[di] = 0.0
    return True


@njit(cache=True, error_model="numpy")
def _band_back(A, kl, last, b, x):
    """``x`` from the elimination of :func:`_band_factor` (back substitution; ``b`` kept)."""
    for i in range(b.size - 1, -1, -1):
        ri = A[i]
        acc = b[i]
        for o in range(1, last[i] - i):
            acc -= ri[kl + o] * x[i + o]
        x[i] = acc / ri[kl]


@njit(cache=True, error_model="numpy")
def _band_solve(A, b, kl, x):
    """``x`` with ``A x = b`` (:func:`_band_factor` from column 0, then :func:`_band_back`; ``A``
    and ``b`` overwritten).  False if a pivot vanishes (singular)."""
    m = b.size
    last = np.empty(m, np.int64)
    for i in range(m):
        last[i] = min(m, i + kl + 1)
    checkpoints = m // CHECKPOINT + 1
    if not _band_factor(A, b, kl, 0, last, np.empty((checkpoints, kl, A.shape[1] + 1)),
                        np.empty((checkpoints, kl), np.int64)):
        return False
    _band_back(A, kl, last, b, x)
    return True


@njit(cache=True, error_model="numpy")
def semismooth_newton(ab, c, nonneg, closed_joint, mu, vscale, reg, tol, P, w):
    """Coulomb's law as the equations of Alart and Curnier, ``P_n = max(0, P_n - rho w_n)`` and
    ``P_t = proj[-mu N, mu N](P_t - rho w_t)`` (``rho = 1 / W_ii``), solved by the semi-smooth
    Newton method: the cases those projections pick (a corner pressed or free, a joint sticking
    or sliding either way) fix a linear system in ``P`` (sliding: ``P_t = -+ mu N``, a
    non-symmetric row, within the band of ``W``), solved by banded elimination in band storage
    (:func:`_band_factor`, resumed where the cases first differ from the last system's: an
    iteration changes a few of them); the step damped by halving until ``|Phi|^2`` decreases (the merit and
    the rates of the accepted step are those of the next iteration).  The polish (one more step
    with the cases of the answer) reuses the last solution when its cases are the answer's and
    the step to it was full (the same system).
    From the ``P`` given; returns ``(converged, iterations, residual)``."""
    m = c.size
    J = closed_joint.size
    dmax = 0.0
    for i in range(m):
        dmax = max(dmax, ab[BAND, i])
    rho = np.empty(m)
    for i in range(m):
        rho[i] = 1.0 / max(ab[BAND, i], 1e-300)
    Pt = np.empty(m)
    wt = np.empty(m)
    case = np.zeros(m, np.int64)
    width = 3 * BAND + 1
    A = np.zeros((m, width))
    built = np.full(m, -1, np.int64)     # the cases of the system factored in A
    rowend = np.empty(m, np.int64)       # and its elimination (_band_factor)
    saved = np.empty((m // CHECKPOINT + 1, BAND, width + 1))
    saved_last = np.empty((m // CHECKPOINT + 1, BAND), np.int64)
    rhs = np.zeros(m)
    d = np.zeros(m)
    res = np.inf
    f0 = _ac_merit(ab, c, nonneg, closed_joint, mu, rho, P, w)       # and w = W P + c
    polish = False
    res0 = 0.0
    P0 = np.empty(m)
    w0 = np.empty(m)
    last = np.full(m, -1, np.int64)      # the cases of the last system solved, its solution, and
    dfull = np.empty(m)                  # whether the step to it was full
    full = False
    for it in range(SSN_ITERATIONS + 2):
        pscale = max(_maxabs(P), vscale / max(dmax, 1e-300))
        res = coulomb_residual(P, w, closed_joint, nonneg, mu, vscale, pscale)
        if polish:                        # the polished iterate, if it is no worse
            if res <= res0:
                return True, it, res
            P[:] = P0
            w[:] = w0
            return True, it, res0
        if res <= tol:
            # one more full step with the cases of the solution: their linear system's solution is
            # the exact one (the tolerance alone would leave rates of 1e-5 of the scale at pressed
            # corners, which turn the voussoirs of an arch that slides without rocking)
            polish = True
            res0 = res
            P0[:] = P
            w0[:] = w
        elif it >= SSN_ITERATIONS:
            break
        for j in range(J):
            for r in range(2):
                i = 3 * j + r
                case[i] = 1 if nonneg[i] and P[i] - w[i] * rho[i] > 0 else 0
            i = 3 * j + 2
            N = max(P[3 * j], 0.0) + max(P[3 * j + 1], 0.0)
            y = P[i] - w[i] * rho[i]
            if not closed_joint[j]:
                case[i] = 0
            elif abs(y) <= mu * N:
                case[i] = 1
            else:
                case[i] = 2 if y > 0 else 3
        if polish and full:
            same = True
            for i in range(m):
                if case[i] != last[i]:
                    same = False
                    break
            if same:                      # the polish's system is the last one solved: its solution
                P[:] = dfull
                matvec(ab, P, w)
                w += c
                continue
        first = 0                         # the system differs from the one factored from row first on
        while first < m and case[first] == built[first]:
            first += 1
        if first < m:                     # its factorisation resumed at the checkpoint before first - BAND
            j0 = max(first - BAND, 0) // CHECKPOINT * CHECKPOINT
            for i in range(j0, m):
                for k in range(width):
                    A[i, k] = 0.0
                rhs[i] = -c[i] if case[i] == 1 else 0.0
                rowend[i] = i + 1             # one past the row's last nonzero (the elimination's work)
                if case[i] == 1:              # w_i = 0: row i of W (W[k, i] at ab[BAND + k - i, i], k <= i)
                    A[i, BAND] = ab[BAND, i] + reg
                    for o in range(1, min(BAND, i) + 1):
                        A[i, BAND - o] = ab[BAND - o, i]
                    for o in range(1, min(BAND, m - 1 - i) + 1):
                        A[i, BAND + o] = ab[BAND - o, i + o]
                        if A[i, BAND + o] != 0.0:
                            rowend[i] = i + o + 1
                elif case[i] == 0:            # P_i = 0
                    A[i, BAND] = 1.0
                else:                         # P_t -+ mu (P_n0 + P_n1) = 0
                    s = 1.0 if case[i] == 2 else -1.0
                    A[i, BAND] = 1.0
                    A[i, BAND - 1] = -s * mu
                    A[i, BAND - 2] = -s * mu
                built[i] = case[i]
            if not _band_factor(A, rhs, BAND, j0, rowend, saved, saved_last):
                return polish, it, res
        _band_back(A, BAND, rowend, rhs, d)
        if polish:
            P[:] = d
            matvec(ab, P, w)
            w += c
            continue
        for i in range(m):                # the Newton step, damped on the merit |Phi|^2
            dfull[i] = d[i]
            last[i] = case[i]
            d[i] -= P[i]
        alpha = 1.0
        f1 = f0
        descent = False
        for ls in range(20):
            for i in range(m):
                Pt[i] = P[i] + alpha * d[i]
            f1 = _ac_merit(ab, c, nonneg, closed_joint, mu, rho, Pt, wt)
            if f1 < (1.0 - 1e-4 * alpha) * f0:
                descent = True
                break
            alpha *= 0.5
        if not descent:
            # the line search found no decrease in 20 halvings: stalled (the iterations after it
            # only repeat steps of 1e-6, each a banded elimination and 20 merits; the later
            # stages start from the sticking solution). P and w stay at the iterate whose
            # residual res is, so that a caller keeping the best answer keeps a measured one
            return False, it + 1, res
        P[:] = Pt
        w[:] = wt
        f0 = f1
        full = alpha == 1.0
    return False, SSN_ITERATIONS, res


# ==================================================================================================== the loop
# float state
F_T, F_W_GROUND, F_D, F_DRIFT, F_BAL, F_ESEEN, F_PEAK, F_TPEAK, F_NEXT, F_E0, F_TOVER, F_RATIO, F_TRATIO, \
    F_SLIP, F_TSLIP, F_VMIN, F_KKT, F_FRICTION, F_COULOMB, F_VSCALE = range(20)
N_FLOAT = 20
# integer state
I_STEPS, I_CUTS, I_PIVOTS, I_OUTCOME, I_HASW, I_HASWI, I_STALE, I_JRATIO, I_ATRATIO, I_JSLIP, I_STATUS, \
    I_SLIDING, I_REDIST, I_LOOSE, I_BY_FP, I_BY_SSN, I_BY_NSGS, I_BY_LEMKE, I_START = range(19)
N_INT = 19
# ist[I_START] before the first call: the run starts from rest (the joints carry no slip) or from a
# given state (they carry the state's); advance() first evaluates the geometry (_start)
FROM_REST, FROM_STATE = 1, 2
# outcomes while running (0: none yet)
OVERTURNED, SLID_OUT = 1, 2
# statuses of advance()
RUNNING, FINISHED, STOPPED = 0, 1, 2
SOLVER_FAILED = 3       # the contact problem of a step failed (ist[I_STATUS] the solver's code)
HISTORY_COLUMNS = 13     # and the mean forces of the arch on the supports (x, y, left then right; N/m)

# the arguments of advance(), named tuples of arrays and scalars (numba types each field; one
# compiled advance() as long as the fields keep their dtypes, dimensions and C layout)
Model = namedtuple("Model", "A B ra rb nu0 tau0 outward depth edge sides minv m mv y0 thick gap_tol")
"""The bodies and joints, fixed during a run: the joint data of :func:`geometry` (the first nine
fields), ``sides`` ``(J, 2)``,
the inverse masses ``minv`` and the masses ``mv`` ``(n + 2, 3)`` (the supports': zero), the
masses ``m`` ``(n,)``, the centroids' heights at rest ``y0``, the joints' thicknesses ``thick`` and
the gaps at which their corners count as closed ``gap_tol`` ``(J,)`` (m)."""
State = namedtuple("State", "q v gap slip rows contact was_closed working working_imp box box_imp s_ref fs ist sup")
"""What a run carries from step to step and from call to call: positions, velocities, the
geometry of ``q``, the corners closed at the last step, the warm starts of the solvers (smooth
steps and impacts), the slip the joints carry ``s_ref``, the scalars ``fs`` (``F_*``) and ``ist``
(``I_*``) and the supports' accumulators ``sup`` (6,)."""
Run = namedtuple("Run", "dt t0 dt_out g h_min V_over mu stop kind amp period ts av impact_pivots block_pivots "
                 "kkt_tol coulomb_tol")
"""The settings of a run: time step, start, history step (s), ``g``, shortest step (s), the
overturning level of ``V`` (J/m), ``mu`` (inf: no sliding), whether to stop at a collapse, the
ground motion (:func:`ground_at`), the block pivots of impacts and smooth steps, the tolerances."""
Buffers = namedtuple("Buffers", "hist pos imp dump_ab dump_c dump_P dump_closed")
"""The outputs of one call: history rows, positions, impacts ``(t, K-, K+)``; the frictional
problem of a failed step (``W`` banded, ``c``, the sticking ``P``, the closed corners)."""
Work = namedtuple("Work", "acc ab U Z P w c Hv Ha imp_v closed hit gm_gap gm_slip gm_rows gm_contact qm v_free "
                  "v_new q_new dq on rhs lam zero Hdq")
"""The scratch arrays of :func:`advance` (:func:`_workspace`)."""


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
def collapse(V, V_over, gap, s_ref):
    """The collapse decided in a configuration (0: none): :data:`SLID_OUT` when a joint has no
    contact region left (its faces no longer overlap: both ends' gaps ``OFF_FACE``); when the
    potential energy ``V`` (J/m) is below the overturning level ``V_over``, :data:`SLID_OUT` if
    the largest slip a joint carries (``|s_ref|``, m) exceeds the largest opening of a joint's end
    (its gap, m: the two relative displacements of the faces, tangential and normal), else
    :data:`OVERTURNED`."""
    slid, opened = 0.0, 0.0
    for j in range(gap.shape[0]):
        if gap[j, 0] >= OFF_FACE and gap[j, 1] >= OFF_FACE:
            return SLID_OUT
        slid = max(slid, abs(s_ref[j]))
        for k in range(2):
            if gap[j, k] < OFF_FACE:
                opened = max(opened, gap[j, k])
    if V < V_over:
        return SLID_OUT if slid > opened else OVERTURNED
    return 0


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
def _project(rows, sides, minv, v_free, closed, F, warm, box, mu, floor, block_pivots, ab, U, P, w, c, Z, dump_ab, dump_c, dump_P, dump_closed,
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
            # the stick solution violates the cone: the same velocities with other percussions
            # (a self-stress of redundant joints added) if they can lie in the cone ...
            pmax, dmax = 0.0, 0.0
            for i in range(m):
                pmax = max(pmax, abs(P[i]))
                dmax = max(dmax, ab[BAND, i])
            # (U is the factor of W on F at REG when the block pivots solved the sticking problem:
            # their last factorisation, of the working set they returned)
            k = self_stress_of(ab, F, REG * dmax, U, Z, 1 <= piv <= block_pivots)
            Pstick = P.copy()
            if redistribute(P, Z, k, nonneg, F, cj, mu, 1e-9 * max(pmax, vscale / max(dmax, 1e-300))):
                matvec(ab, P, w)             # the velocities must not have changed
                w += c
                if kkt_residual(P, w, free, nonneg, vscale, dmax) <= kkt_tol:
                    slide = False
                    ist[I_REDIST] += 1
                else:
                    P[:] = Pstick
        if slide:
            # ... else the semi-smooth Newton method from it (a few banded eliminations on most
            # steps), then the Tresca fixed point, non-smooth Gauss-Seidel and Lemke's pivots
            Pstick = P.copy()
            ok, its, res = semismooth_newton(ab, c, nonneg, cj, mu, vscale, REG_FRICTION * dmax, coulomb_tol, P, w)
            ist[I_PIVOTS] += its
            if ok:
                ist[I_BY_SSN] += 1
            else:
                best = res
                Pbest = P.copy()
                P[:] = Pstick
                for j in range(J):          # start: the stick solution's working set, the violated bounds
                    for r in range(2):
                        box[3 * j + r] = 0 if F[3 * j + r] else 1
                    N = P[3 * j] + P[3 * j + 1]
                    box[3 * j + 2] = 2 if P[3 * j + 2] > mu * N else (1 if P[3 * j + 2] < -mu * N else 0)
                status, piv, res = solve_friction(ab, c, nonneg, cj, mu, vscale, box, U, P, w, coulomb_tol)
                ist[I_PIVOTS] += piv
                ok = status == 0
                if ok:
                    ist[I_BY_FP] += 1
                else:
                    # Newton from the fixed point's best iterate (near the solution it converges in
                    # one step and its polish: where the fixed point stalls within a few times the
                    # tolerance, Gauss-Seidel from the sticking solution took 500-2000 sweeps), then
                    # non-smooth Gauss-Seidel from the stick solution, then from the fixed point's
                    # best iterate, then Lemke's pivots on the linear complementarity problem; a
                    # stalled step accepted at the best of them up to LOOSE x the tolerance
                    P0 = P.copy()
                    if res < best:
                        best = res
                        Pbest[:] = P
                    ok, its, res = semismooth_newton(ab, c, nonneg, cj, mu, vscale, REG_FRICTION * dmax, coulomb_tol,
                                                     P, w)
                    ist[I_PIVOTS] += its
                    if ok:
                        ist[I_BY_SSN] += 1
                    elif res < best:
                        best = res
                        Pbest[:] = P
                    for stage in range(3):
                        if ok:
                            break
                        P[:] = P0 if stage == 1 else Pstick
                        if stage < 2:
                            ok, its, res = nsgs(ab, c, nonneg, cj, mu, vscale, REG * dmax, coulomb_tol, P, w)
                        else:
                            ok, its, res = lemke_friction(ab, c, nonneg, cj, mu, vscale, REG * dmax, P, w)
                            ok = ok and res <= coulomb_tol
                        ist[I_PIVOTS] += its
                        if ok:
                            ist[I_BY_NSGS if stage < 2 else I_BY_LEMKE] += 1
                            break
                        if res < best:
                            best = res
                            Pbest[:] = P
                    if not ok:
                        # Newton again from the best answer so far: with a large mu (1000) the
                        # coupling of the joints stalls every stage from the sticking solution,
                        # and Newton converges from near the solution
                        P[:] = Pbest
                        ok, its, res = semismooth_newton(ab, c, nonneg, cj, mu, vscale, REG_FRICTION * dmax,
                                                         coulomb_tol, P, w)
                        ist[I_PIVOTS] += its
                        if ok:
                            ist[I_BY_SSN] += 1
                        elif res < best:
                            best = res
                            Pbest[:] = P
                if not ok and best <= LOOSE * coulomb_tol:    # accepted, counted and reported
                    ok = True
                    res = best
                    P[:] = Pbest
                    matvec(ab, P, w)
                    w += c
                    ist[I_LOOSE] += 1
                if not ok:
                    fs[F_KKT] = best
                    dump_ab[:, :] = ab              # the failing problem, for the error report
                    dump_c[:] = c
                    dump_P[:] = Pstick
                    dump_closed[:, :] = closed
                    fs[F_VSCALE] = vscale
                    return 4
            fs[F_COULOMB] = max(fs[F_COULOMB], res)
            # the working set as the interior point's (solve_mlcp): a corner is pressed when its
            # percussion, relative to the percussions' scale, exceeds its opening rate, relative to
            # the rates'.  Not by the sign of P alone: the frictional solvers leave a round-off
            # percussion (+-1e-17 of the scale) at a corner that opens, and a corner counted as
            # pressed is pulled back to its face by the position projection (energy created: the
            # balance of the 7-voussoir test went from 3.3e-4 to 1.9e-3 or 6.0e-3 by that sign)
            pscale = max(_maxabs(P), vscale / max(dmax, 1e-300))
            for i in range(m):
                F[i] = free[i] or (nonneg[i] and P[i] * vscale > max(w[i], 0.0) * pscale)
            ist[I_SLIDING] += 1
    # friction demand: |P_t| / N at the joints whose normal percussion is at least 1e-2 of the
    # percussion scale of the step's tolerances (the largest, or the rates' scale over W's
    # diagonal): a lighter joint's ratio is not resolved by them.  A joint that slides (its
    # sliding rate above the tolerance) needed more than mu to stick: its demand is at least mu
    pmax, dmax = 0.0, 0.0
    for i in range(m):
        pmax = max(pmax, abs(P[i]))
        dmax = max(dmax, ab[BAND, i])
    pscale = max(pmax, vscale / max(dmax, 1e-300))
    for j in range(J):
        N = P[3 * j] + P[3 * j + 1]
        if cj[j] and N > 1e-2 * pscale:
            ratio = abs(P[3 * j + 2]) / N
            if mu < np.inf and abs(w[3 * j + 2]) > coulomb_tol * vscale:
                ratio = max(ratio, mu)
            if ratio > fs[F_RATIO]:
                fs[F_RATIO] = ratio
                fs[F_TRATIO] = t
                ist[I_JRATIO] = j
                ist[I_ATRATIO] = at_impact
    return 0


@njit(cache=True, error_model="numpy")
def _on_supports(imp_v, v, n, sup):
    """Adds the impulses ``imp_v`` (N s/m) on the supports (rows ``n``, ``n + 1``) to ``sup``;
    returns their work on the arch (J/m): minus their work on the supports moving at ``v``."""
    work = 0.0
    for k in range(2):
        for d in range(2):
            sup[2 * k + d] += imp_v[n + k, d]
            work -= imp_v[n + k, d] * v[n + k, d]
    sup[5] += work
    return work


@njit(cache=True, error_model="numpy", inline="always")
def _copy(src, dst, rows):
    """``dst[:rows] = src[:rows]`` (two-dimensional; a loop: numba's slice assignment compiles to
    far more code, its shape checks and their messages)."""
    for i in range(rows):
        for d in range(src.shape[1]):
            dst[i, d] = src[i, d]


@njit(cache=True, error_model="numpy", inline="always")
def _start(mod, st):
    """Phase 0, before the first step of a run (``ist[I_START]`` set): the geometry of ``q``, the
    corners closed there, and the slip the joints carry (none from rest, the state's otherwise)."""
    geometry(st.q, mod.A, mod.B, mod.ra, mod.rb, mod.nu0, mod.tau0, mod.outward, mod.depth, mod.edge,
             st.gap, st.slip, st.rows, st.contact)
    for j in range(mod.A.size):
        for k in range(2):
            st.was_closed[j, k] = st.gap[j, k] <= mod.gap_tol[j]
        st.s_ref[j] = st.slip[j, st.contact[j]] if st.ist[I_START] == FROM_STATE else 0.0
    st.ist[I_START] = 0


@njit(cache=True, error_model="numpy", inline="always")
def _workspace(mod, g):
    """The scratch arrays of :func:`advance` (:class:`Work`), the loads' array ``acc`` with its
    weight column set."""
    n, nb, J = mod.m.size, mod.minv.shape[0], mod.A.size
    M3 = 3 * J
    acc = np.zeros((nb, 3))
    for i in range(n):
        acc[i, 1] = -g
    return Work(acc, np.zeros((BAND + 1, M3)), np.zeros((M3, BAND + 1)), np.zeros((M3, 4)), np.zeros(M3),
                np.zeros(M3), np.zeros(M3), np.zeros(M3), np.zeros(M3), np.zeros((nb, 3)),
                np.zeros((J, 2), np.bool_), np.zeros((J, 2), np.bool_), np.zeros((J, 2)), np.zeros((J, 2)),
                np.zeros((J, 3, 2, 3)), np.zeros(J, np.int64), np.zeros((nb, 3)), np.zeros((nb, 3)),
                np.zeros((nb, 3)), np.zeros((nb, 3)), np.zeros((nb, 3)), np.zeros(M3, np.bool_), np.zeros(M3),
                np.zeros(M3), np.zeros(M3), np.zeros(M3))


@njit(cache=True, error_model="numpy", inline="always")
def _observe(mod, st, run, t, t_end):
    """Phase 1, the configuration at ``t``: the energies, their balance, the peak rotation, and
    the collapse (decided once, on ``V - sup[5]``: ``V`` less the supports' work on the arch).
    Returns ``(K, V, largest rotation, done)``: ``done`` at the end of the run (a remainder shorter
    than a landing cut is not stepped) or at an outcome when the run stops there (also one
    decided by an earlier call that returned for its buffers before it could stop)."""
    fs, ist = st.fs, st.ist
    K = _kinetic(mod.mv, st.v)
    V = _potential(mod.m, mod.y0, run.g, st.q)
    fs[F_ESEEN] = max(fs[F_ESEEN], K + abs(V), abs(fs[F_W_GROUND]), fs[F_D])
    fs[F_BAL] = max(fs[F_BAL], abs(K + V - fs[F_E0] - fs[F_W_GROUND] + fs[F_D]) / fs[F_ESEEN])
    fs[F_VMIN] = min(fs[F_VMIN], V)
    rot, q = 0.0, st.q
    for i in range(mod.m.size):
        rot = max(rot, abs(q[i, 2]))
    if rot > fs[F_PEAK]:
        fs[F_PEAK], fs[F_TPEAK] = rot, t
    done = t >= t_end - run.h_min or (run.stop and ist[I_OUTCOME] != 0)
    if ist[I_OUTCOME] == 0:
        code = collapse(V - st.sup[5], run.V_over, st.gap, st.s_ref)
        if code != 0:
            ist[I_OUTCOME] = code
            fs[F_TOVER] = t
            done = done or run.stop
    return K, V, rot, done


@njit(cache=True, error_model="numpy", inline="always")
def _record(mod, st, run, out, nh, t, K, V, rot):
    """Phase 2: history row ``nh`` (:data:`HISTORY_COLUMNS`) and the positions at ``t``; the mean
    forces on the supports since the last row, and the time of the next row."""
    n, sup, hist, fs, gap, thick = mod.m.size, st.sup, out.hist, st.fs, st.gap, mod.thick
    hinges, separated = 0, 0
    for j in range(mod.A.size):
        k = int(gap[j, 0] > OPEN_TOL * thick[j]) + int(gap[j, 1] > OPEN_TOL * thick[j])
        hinges += k == 1
        separated += k == 2
    hist[nh, 0] = t
    hist[nh, 1] = K
    hist[nh, 2] = V
    hist[nh, 3] = fs[F_W_GROUND]
    hist[nh, 4] = fs[F_D]
    hist[nh, 5] = ground_at(run.kind, run.amp, run.period, run.ts, run.av, t)
    hist[nh, 6] = hinges
    hist[nh, 7] = separated
    hist[nh, 8] = rot
    for d in range(4):
        hist[nh, 9 + d] = sup[d] / sup[4] if sup[4] > 0 else 0.0
        sup[d] = 0.0
    sup[4] = 0.0
    _copy(st.q, out.pos[nh], n)
    fs[F_NEXT] = run.t0 + run.dt_out * (math.floor((t - run.t0) / run.dt_out + 1e-9) + 1)


@njit(cache=True, error_model="numpy", inline="always")
def _loads(run, acc, n, time):
    """The ground acceleration ``a_g`` (g) at ``time``, and the inertia forces per unit mass of the
    bodies in ``acc``."""
    a_g = ground_at(run.kind, run.amp, run.period, run.ts, run.av, time)
    for i in range(n):
        acc[i, 0] = -a_g * run.g
    return a_g


@njit(cache=True, error_model="numpy", inline="always")
def _impact(mod, st, run, out, wk, t, h):
    """The impact at ``t`` (in phase 3): the velocities projected onto the cone of the closed
    corners ``wk.closed`` (the geometry of ``q`` refreshed first if a position projection left it
    stale); the supports' work counts as the ground's and as dissipated.  Returns the solver's
    status (0: solved)."""
    fs, ist, v, minv, imp_v = st.fs, st.ist, st.v, mod.minv, wk.imp_v
    if ist[I_STALE]:
        geometry(st.q, mod.A, mod.B, mod.ra, mod.rb, mod.nu0, mod.tau0, mod.outward, mod.depth, mod.edge,
                 st.gap, st.slip, st.rows, st.contact)
        ist[I_STALE] = 0
    status = _project(st.rows, mod.sides, minv, v, wk.closed, st.working_imp, ist[I_HASWI] == 1, st.box_imp,
                      run.mu, run.g * h, run.impact_pivots, wk.ab, wk.U, wk.P, wk.w, wk.c, wk.Z, out.dump_ab,
                      out.dump_c, out.dump_P, out.dump_closed, fs, ist, t, np.int64(1), run.kkt_tol,
                      run.coulomb_tol)       # (np.int64: one compiled _project for both calls, not one per literal)
    if status != 0:
        return status
    ist[I_HASWI] = 1
    apply_ht(st.rows, mod.sides, wk.P, imp_v)
    w_sup = _on_supports(imp_v, v, mod.m.size, st.sup)
    fs[F_W_GROUND] += w_sup
    fs[F_D] += w_sup
    for i in range(v.shape[0]):
        for d in range(3):
            v[i, d] += minv[i, d] * imp_v[i, d]
    _copy(wk.closed, wk.hit, mod.A.size)
    return 0


@njit(cache=True, error_model="numpy", inline="always")
def _landings(mod, st, run, wk):
    """The open corners' predicted landings (``gap + s v_n + s^2/2 a_n = 0``, phase 3): a corner
    landing within ``h_min`` is closed now.  Returns ``(a corner closed now, the first landing s)``."""
    closed, gap, Hv, Ha, h_min = wk.closed, st.gap, wk.Hv, wk.Ha, run.h_min
    apply_h(st.rows, mod.sides, st.v, Hv)
    apply_h(st.rows, mod.sides, wk.acc, Ha)
    soon = False
    s_cut = np.inf
    for j in range(mod.A.size):
        for k in range(2):
            if closed[j, k]:
                continue
            s = _roots(gap[j, k], Hv[3 * j + k], Ha[3 * j + k])
            if s < h_min:
                soon = True
                closed[j, k] = True
            s_cut = min(s_cut, s)
    return soon, s_cut


@njit(cache=True, error_model="numpy", inline="always")
def _events(mod, st, run, out, wk, t, t_end, ni):
    """Phase 3, the events at ``t``: the corners closed, an impact when one closed since the last
    step (again after a landing within ``h_min`` closes another), the impact recorded in
    ``out.imp[ni]``, and the step's length ``h`` (``dt``, all of a remainder shorter than
    ``dt + h_min``, or cut at the first landing).  Returns ``(status, h, a_g, impacts written)``."""
    closed, was_closed, hit, gap, gap_tol, J = wk.closed, st.was_closed, wk.hit, st.gap, mod.gap_tol, mod.A.size
    h = t_end - t if t_end - t < run.dt + run.h_min else run.dt    # no sliver of a step left at the end
    for j in range(J):
        for k in range(2):
            closed[j, k] = gap[j, k] <= gap_tol[j]
    a_g = _loads(run, wk.acc, mod.m.size, t + 0.5 * h)
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
                K_in = _kinetic(mod.mv, st.v)
            status = _impact(mod, st, run, out, wk, t, h)
            if status != 0:
                return status, h, a_g, ni
            have_hit = True
        if all_closed:
            s_cut = np.inf
            break
        soon, s_cut = _landings(mod, st, run, wk)
        if not soon:
            break
    if K_in >= 0:
        K_out = _kinetic(mod.mv, st.v)
        st.fs[F_D] += K_in - K_out
        out.imp[ni, 0] = t
        out.imp[ni, 1] = K_in
        out.imp[ni, 2] = K_out
        ni += 1
    if s_cut < h:
        h = s_cut
        st.ist[I_CUTS] += 1
        a_g = _loads(run, wk.acc, mod.m.size, t + 0.5 * h)
    return 0, h, a_g, ni


@njit(cache=True, error_model="numpy", inline="always")
def _contact_step(mod, st, run, out, wk, t, h):
    """Phase 4, the smooth step: the midpoint ``q_m``, the free velocity, the contact problem of
    the closed corners at ``q_m`` (its impulses on the supports: their work), ``v_{k+1}``,
    ``q_{k+1}`` (in ``wk``) and its geometry, then the slip and the friction's work
    (:func:`_slip`).  Returns ``(status, a corner closed)``."""
    q, v, minv, nb, fs, ist = st.q, st.v, mod.minv, st.q.shape[0], st.fs, st.ist
    qm, v_free, v_new, q_new, acc, closed, imp_v = wk.qm, wk.v_free, wk.v_new, wk.q_new, wk.acc, wk.closed, wk.imp_v
    for i in range(nb):
        for d in range(3):
            qm[i, d] = q[i, d] + 0.5 * h * v[i, d]
            v_free[i, d] = v[i, d] + h * acc[i, d]
    any_closed = False
    for j in range(mod.A.size):
        if closed[j, 0] or closed[j, 1]:
            any_closed = True
    if any_closed:
        geometry(wk.qm, mod.A, mod.B, mod.ra, mod.rb, mod.nu0, mod.tau0, mod.outward, mod.depth, mod.edge,
                 wk.gm_gap, wk.gm_slip, wk.gm_rows, wk.gm_contact)
        if run.mu < np.inf:
            apply_h(wk.gm_rows, mod.sides, v, wk.Hv)      # the rates at the start of the step
        status = _project(wk.gm_rows, mod.sides, minv, wk.v_free, wk.closed, st.working, ist[I_HASW] == 1, st.box,
                          run.mu, run.g * h, run.block_pivots, wk.ab, wk.U, wk.P, wk.w, wk.c, wk.Z, out.dump_ab,
                          out.dump_c, out.dump_P, out.dump_closed, fs, ist, t, np.int64(0), run.kkt_tol,
                          run.coulomb_tol)
        if status != 0:
            return status, any_closed
        ist[I_HASW] = 1
        apply_ht(wk.gm_rows, mod.sides, wk.P, imp_v)
        fs[F_W_GROUND] += _on_supports(imp_v, v, mod.m.size, st.sup)
        for i in range(nb):
            for d in range(3):
                v_new[i, d] = v_free[i, d] + minv[i, d] * imp_v[i, d]
    else:
        _copy(v_free, v_new, nb)
        ist[I_HASW] = 0
    _copy(closed, st.was_closed, mod.A.size)
    for i in range(nb):
        for d in range(3):
            q_new[i, d] = qm[i, d] + 0.5 * h * v_new[i, d]
    geometry(q_new, mod.A, mod.B, mod.ra, mod.rb, mod.nu0, mod.tau0, mod.outward, mod.depth, mod.edge,
             st.gap, st.slip, st.rows, st.contact)
    ist[I_STALE] = 0
    _slip(st, run, wk, t, h)
    return 0, any_closed


@njit(cache=True, error_model="numpy", inline="always")
def _slip(st, run, wk, t, h):
    """The slip carried by the joints (whatever ``mu``: an open joint's follows the bodies, so a
    landing keeps its offset; a closed joint's moves only by sliding, never with ``mu = inf``)
    and the work of friction (phase 4)."""
    mu, fs, s_ref, P, closed, Hv, w, slip, contact = run.mu, st.fs, st.s_ref, wk.P, wk.closed, wk.Hv, wk.w, \
        st.slip, st.contact
    for j in range(s_ref.size):
        if closed[j, 0] or closed[j, 1]:
            if mu < np.inf:
                # the slip and the work of P_t over the step: positions move by h/2 (v_k + v_k+1)
                rate = 0.5 * (Hv[3 * j + 2] + w[3 * j + 2])
                s_ref[j] += h * rate
                work = -P[3 * j + 2] * rate              # P_t opposes the sliding rate
                fs[F_FRICTION] += work
                fs[F_D] += work
        else:
            s_ref[j] = slip[j, contact[j]]
        if mu < np.inf and abs(s_ref[j]) > fs[F_SLIP]:
            fs[F_SLIP] = abs(s_ref[j])
            fs[F_TSLIP] = t + h
            st.ist[I_JSLIP] = j


@njit(cache=True, error_model="numpy", inline="always")
def _correct(mod, st, run, wk, a_g):
    """Phase 5, the position projection of ``q_{k+1}`` (``wk.q_new``): ``M``-orthogonally (one
    Gauss-Newton step, velocities untouched) onto zero gap at the closed corners that carried a
    percussion (or overlap) and the carried slip at their joints, with the rows of the midpoint;
    the gaps updated to first order (the geometry then stale) and the loads' work on the
    correction counted as drift.  Returns the status (3: ``W`` not positive definite)."""
    J, n, gap, slip, on, rhs, minv, dq = mod.A.size, mod.m.size, st.gap, st.slip, wk.on, wk.rhs, mod.minv, wk.dq
    closed, P, working, contact, s_ref, ab, q_new, Hdq, m = wk.closed, wk.P, st.working, st.contact, st.s_ref, \
        wk.ab, wk.q_new, wk.Hdq, mod.m
    nload = 0
    for j in range(J):
        lj = False
        for k in range(2):
            lk = closed[j, k] and gap[j, k] < OFF_FACE and ((P[3 * j + k] > 0 and working[3 * j + k])
                                                            or gap[j, k] < 0)
            on[3 * j + k] = lk
            lj = lj or lk
        on[3 * j + 2] = lj
        nload += lj
    if nload == 0:
        return 0
    for j in range(J):
        for k in range(2):
            rhs[3 * j + k] = -gap[j, k] if on[3 * j + k] else 0.0
        rhs[3 * j + 2] = -(slip[j, contact[j]] - s_ref[j]) if on[3 * j + 2] else 0.0
    dmax = 0.0
    for i in range(3 * J):
        dmax = max(dmax, ab[BAND, i])
    if not factor(ab, on, REG * dmax, wk.zero, wk.U):
        return 3
    solve(wk.U, rhs, wk.lam)
    apply_ht(wk.gm_rows, mod.sides, wk.lam, dq)
    for i in range(dq.shape[0]):
        for d in range(3):
            dq[i, d] *= minv[i, d]
            q_new[i, d] += dq[i, d]
    apply_h(st.rows, mod.sides, dq, Hdq)
    for j in range(J):
        gap[j, 0] += Hdq[3 * j]
        gap[j, 1] += Hdq[3 * j + 1]
    st.ist[I_STALE] = 1
    dy, dx = 0.0, 0.0
    for i in range(n):
        dy += m[i] * dq[i, 1]
        dx += m[i] * dq[i, 0]
    st.fs[F_DRIFT] += run.g * dy + a_g * run.g * dx
    return 0


@njit(cache=True, error_model="numpy", inline="always")
def _commit(mod, st, run, wk, t, h, a_g):
    """Phase 6: the ground's work over the step, ``(q, v)`` set to the step's end, the clocks.
    Returns the new time."""
    q, fs, m, q_new = st.q, st.fs, mod.m, wk.q_new
    wx = 0.0
    for i in range(m.size):
        wx += m[i] * (q_new[i, 0] - q[i, 0])
    fs[F_W_GROUND] += -a_g * run.g * wx
    _copy(q_new, q, q.shape[0])
    _copy(wk.v_new, st.v, q.shape[0])
    t = t + h
    st.sup[4] += h
    fs[F_T] = t
    st.ist[I_STEPS] += 1
    return t


@njit(cache=True, error_model="numpy")
def advance(mod, st, run, out, t_end, max_steps):
    """Steps from the state ``st`` (:class:`State`) of the bodies ``mod`` (:class:`Model`) with the
    settings ``run`` (:class:`Run`) until ``t_end``, a stop, ``max_steps`` steps, or the buffers of
    ``out`` (:class:`Buffers`: ``hist`` ``(rows, 13)``, ``pos`` ``(rows, n, 3)``, ``imp``
    ``(rows, 3)``) are full.  Returns ``(status, history rows written, impacts written)``.  The
    supports (rows ``n``, ``n + 1`` of ``q``, ``v``) move at their velocities; ``st.sup`` (6,)
    accumulates the impulses of the arch on them (x, y left, x, y right; N s/m) and the time (s)
    since the last history row, whose columns 9-12 are their means (N/m), and (``sup[5]``) their
    work on the arch (J/m), which also counts as the ground's.  A run's first call starts with
    :func:`_start`; each step: :func:`_observe`, :func:`_record`, :func:`_events`,
    :func:`_contact_step`, :func:`_correct`, :func:`_commit`."""
    wk = _workspace(mod, run.g)
    fs, ist = st.fs, st.ist
    if ist[I_START]:
        _start(mod, st)
    nh, ni = np.int64(0), np.int64(0)     # (not the literal 0: one compiled _record and _events)
    t = fs[F_T]
    for count in range(max_steps + 1):
        K, V, rot, done = _observe(mod, st, run, t, t_end)
        if t >= fs[F_NEXT] or done:
            if nh == out.hist.shape[0]:
                return RUNNING, nh, ni
            _record(mod, st, run, out, nh, t, K, V, rot)
            nh += 1
        if done:
            return STOPPED if t < t_end - run.h_min else FINISHED, nh, ni
        if count == max_steps or ni == out.imp.shape[0]:
            return RUNNING, nh, ni
        status, h, a_g, ni = _events(mod, st, run, out, wk, t, t_end, ni)
        if status == 0:
            status, any_closed = _contact_step(mod, st, run, out, wk, t, h)
            if status == 0 and any_closed:
                status = _correct(mod, st, run, wk, a_g)
        if status != 0:
            ist[I_STATUS] = status
            fs[F_T] = t
            return SOLVER_FAILED, nh, ni
        t = _commit(mod, st, run, wk, t, h, a_g)
    return RUNNING, nh, ni
