"""The impact QP of one time step: projection of the free velocity onto the compatible cone.

In the kinetic metric ``M``, the end-of-step velocity is

    v+ = argmin 1/2 (v - v_free)^T M (v - v_free)   s.t.  (H v)_i >= 0 (opening rates, i in N),
                                                          (H v)_i  = 0 (sliding rates, i in T),

the impact QP of ``fembeam impact`` with the operators of the current configuration.  It is solved
in its dual form, the mixed linear complementarity problem in the impulses ``P`` (N s/m)

    w = W P + c,  W = H M^-1 H^T,  c = H v_free;   w_T = 0;   0 <= P_N  _|_  w_N >= 0,

with ``v+ = v_free + M^-1 H^T P``, warm-started from the previous step's working set: a few block
principal pivots (Judice and Pires: all infeasible rows change sides at once; one or two solves
in a smooth phase); if they have not converged, Mehrotra's predictor-corrector interior point
(about 13 iterations, each one factorisation of ``W + diag`` on the same band), which does not care
that the impulses are not unique (closed joints between two abutments: ``W`` singular, the
self-stress states) nor that many rows are degenerate (``P = w = 0``: the locked joints at rest of
an impact), the two things on which the pivots cycle; as a last resort a primal active-set method
on ``P`` whose objective decreases at every solve.  Rows that are not constraints this step (open
corners) keep their place as identity rows of the banded ``W``, so every linear solve has the same
banded pattern (LAPACK ``pbsv``/``pbtrf``/``pbtrs``).  ``reg`` (1e-12 of the largest diagonal
entry) makes ``W`` definite when the closed joints are statically indeterminate; it changes the
velocities by about ``reg |P|``.  Every solution's KKT residuals are checked on the
unregularised problem (``w = W P + c``): SolverError otherwise, never a wrong velocity.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy.linalg.lapack import dpbsv

from ..analysis.banded_ipm import interior_point
from ..errors import SolverError
from .constants import BAND, BLOCK_PIVOTS, IPM_ITERATIONS, KKT_TOL, MAX_PIVOTS, REG
from .contacts import Contacts

__all__ = ["MLCPSolution", "solve_mlcp", "banded_solve", "REG", "KKT_TOL", "MAX_PIVOTS"]



def banded_solve(ab: np.ndarray, b: np.ndarray) -> np.ndarray:
    """``x`` with ``A x = b``, ``A`` symmetric positive definite in upper banded storage (LAPACK
    ``dpbsv``, called directly: the small systems of a step cost microseconds)."""
    _, x, info = dpbsv(ab, b)
    if info != 0:
        raise SolverError(f"the step's Delassus matrix is not positive definite (LAPACK info {info})")
    return x


@dataclass
class MLCPSolution:
    """The solution of :func:`solve_mlcp`: the impulses of one step's projection.

    Attributes
    ----------
    P : ndarray
        The impulses (N s/m) on the ``3 J`` rows (two corners and the sliding row of each
        joint), zero on rows that are no constraint.
    w : ndarray
        ``W P + c``: the end-of-step rates ``H v+`` (m/s).
    working : ndarray
        The rows solved as equalities (bool, ``3 J``): the warm start of the next step.
    pivots : int
        The banded solves and interior-point iterations it took.
    kkt : float
        The largest relative KKT residual.
    ab : ndarray or None
        ``W`` (upper banded storage) of the solve.

    Examples
    --------
    A block of 0.5 m x 2 m (2000 kg/m) falling at 1 m/s onto the ground, both corners of its
    base closed and sticking: the projection stops it, each corner taking half of the
    momentum (N s/m) and no corner a rate:

    >>> import numpy as np
    >>> import fembeam
    >>> from fembeam.simulation import Bodies, Contacts, solve_mlcp
    >>> con = Contacts(Bodies.from_curve(fembeam.StraightMember(height=2.0, width=0.5), 1))
    >>> rows = con.evaluate(con.bodies.rest_state()).rows
    >>> v_free = np.array([[0.0, -1.0, 0.0], [0.0, 0.0, 0.0]])   # the block, the ground
    >>> nonneg = np.array([True, True, False])                  # the two corners
    >>> sol = solve_mlcp(con, con.delassus(rows), con.apply(rows, v_free), ~nonneg, nonneg)
    >>> print("P =", sol.P.round(3) + 0.0, "N s/m")
    P = [1000. 1000.    0.] N s/m
    >>> print(bool(np.all(np.abs(sol.w) < 1e-9)), sol.kkt < 1e-9)
    True True
    """

    P: np.ndarray            # impulses (3 J,), zero on rows that are no constraint
    w: np.ndarray            # W P + c: the end-of-step rates H v+ (m/s)
    working: np.ndarray      # rows solved as equalities (bool, 3 J)
    pivots: int
    kkt: float               # largest relative KKT residual
    ab: np.ndarray | None = None   # W (upper banded storage) of the solve


def solve_mlcp(contacts: Contacts, ab: np.ndarray, c: np.ndarray, free: np.ndarray, nonneg: np.ndarray,
               start: np.ndarray | None = None, vscale: float = 1.0, block_pivots: int = BLOCK_PIVOTS) -> MLCPSolution:
    """Solve the MLCP above: ``ab`` is ``W`` in upper banded storage, ``free`` the equality rows
    (``T``), ``nonneg`` the unilateral rows (``N``); the others carry no impulse.  ``start``: the
    previous working set.  ``vscale`` (m/s): the velocity scale of the tolerances.
    ``block_pivots``: block principal pivots tried before the interior point (0: straight to it).
    ``pivots`` of the solution counts the banded solves and the interior point's iterations.

    Last resort, a primal active-set method on the dual (Lawson and Hanson's, for bounds): ``P`` stays feasible;
    each iteration minimises on the working set ``F`` (one banded solve); an infeasible minimiser
    is approached up to the first bound that blocks (those bounds leave ``F``); a feasible one whose
    rates ``w`` are negative on rows outside ``F`` adds them.  The dual objective decreases
    strictly, so no working set comes back: the method ends.  SolverError if it needs more than
    :data:`MAX_PIVOTS` solves or the KKT residuals exceed :data:`KKT_TOL`."""
    m = c.size
    dmax = float(np.max(ab[BAND], initial=0.0))
    if not free.any() and not nonneg.any():
        return MLCPSolution(np.zeros(m), c.copy(), np.zeros(m, bool), 0, 0.0)
    reg = REG * dmax
    F = free | (nonneg & (start if start is not None else True))
    wtol = 1e-12 * vscale
    pscale0 = vscale / max(dmax, 1e-300)
    for k in range(block_pivots):            # block principal pivoting: fast when it converges
        P = banded_solve(contacts.restrict(ab, F, reg), np.where(F, -c, 0.0))
        w = contacts.banded_matvec(ab, P) + reg * P + c
        ztol = 1e-12 * max(float(np.max(np.abs(P), initial=0.0)), pscale0)
        bad = nonneg & ((F & (P < -ztol)) | (~F & (w < -wtol)))
        if not bad.any():
            P[nonneg & (P < 0)] = 0.0
            return _checked(P, contacts.banded_matvec(ab, P) + c, F, free, nonneg, k + 1, vscale, dmax)
        F = F ^ bad
    try:                                     # degenerate or redundant contacts: interior point
        P, its = _interior_point(contacts, ab, c, free, nonneg, reg, vscale)
    except SolverError:
        pass
    else:
        w = contacts.banded_matvec(ab, P) + c           # the rows whose impulse is below their rate
        F = free | (nonneg & (P * vscale > np.maximum(w, 0.0) * max(float(np.max(np.abs(P))), pscale0)))
        Z = np.where(F, P, 0.0)                          # (relative to the scales) carry none
        try:
            return _checked(Z, contacts.banded_matvec(ab, Z) + c, F, free, nonneg, block_pivots + its, vscale, dmax)
        except SolverError:                              # unless their small impulses matter
            return _checked(P, w, F, free, nonneg, block_pivots + its, vscale, dmax)
    F = free | (nonneg & (start if start is not None else True))
    P = np.zeros(m)
    for pivots in range(block_pivots + 1, MAX_PIVOTS + 1):
        z = banded_solve(contacts.restrict(ab, F, reg), np.where(F, -c, 0.0))
        ztol = 1e-12 * max(float(np.max(np.abs(z), initial=0.0)), vscale / max(dmax, 1e-300))
        neg = nonneg & F & (z < -ztol)
        if neg.any():                        # step towards z up to the first blocking bound
            i = np.flatnonzero(neg)
            ratio = P[i] / (P[i] - z[i])
            alpha = float(np.min(ratio))
            P = P + alpha * (z - P)
            block = np.zeros(m, bool)
            block[i[ratio <= alpha * (1 + 1e-12) + 1e-300]] = True
            F &= ~block
            P[~F] = 0.0
            continue
        P = np.where(F, z, 0.0)
        P[nonneg & (P < 0)] = 0.0
        w = contacts.banded_matvec(ab, P) + c
        add = nonneg & ~F & (w < -wtol)
        if not add.any():
            break
        F |= add
    else:
        raise SolverError(f"the step's impact QP did not converge in {MAX_PIVOTS} solves")
    return _checked(P, w, F, free, nonneg, pivots, vscale, dmax)


def _checked(P, w, F, free, nonneg, pivots, vscale, dmax) -> MLCPSolution:
    """The solution, after the check of its KKT residuals (SolverError above :data:`KKT_TOL`)."""
    pscale = max(float(np.max(np.abs(P), initial=0.0)), vscale / max(dmax, 1e-300))
    wn = np.where(nonneg, w, 0.0)
    res = max(float(np.max(np.abs(np.where(free, w, 0.0)), initial=0.0)) / vscale,   # sticking
              float(max(0.0, -np.min(wn, initial=0.0))) / vscale,                      # primal: opening >= 0
              float(max(0.0, -np.min(np.where(nonneg, P, 0.0), initial=0.0))) / pscale,  # dual: P_N >= 0
              float(np.max(np.abs(P * wn), initial=0.0)) / (pscale * vscale))       # complementarity
    if not res <= KKT_TOL:
        raise SolverError(f"the step's impact QP failed its KKT check (residual {res:.3g})")
    return MLCPSolution(P, w, F, pivots, res)


def _interior_point(contacts: Contacts, ab, c, free, nonneg, reg, vscale):
    """Mehrotra's predictor-corrector (:func:`~fembeam.analysis.banded_ipm.interior_point`) on the
    MLCP as the QP ``min 1/2 P^T (W + reg) P + c^T P, P_N >= 0`` (the rows of neither ``T`` nor ``N``
    identity rows with ``c = 0``: ``P = 0``; each iteration one banded factorisation of
    ``W + reg + diag(w_N / P_N)`` and two solves): ``(P, iterations)``, with ``P_N > 0`` and the
    rates ``w_N = (W P + c)_N > 0`` complementary to ``1e-13`` of the scales.  Unlike the pivoting
    methods it is indifferent to redundant closed joints (``W`` singular: the impulses are not
    unique, it converges to the centre of the optimal face) and to degenerate rows (``P = w = 0``).
    SolverError if it has not converged in :data:`IPM_ITERATIONS`."""
    act = free | nonneg
    ps = vscale / max(float(np.max(ab[BAND])), 1e-300)
    tol = 1e-11

    def converged(P: np.ndarray, rd: np.ndarray, mu: float) -> bool:
        pscale = max(float(np.max(np.abs(P))), ps)
        return float(np.max(np.abs(rd))) <= tol * vscale and mu <= 1e-2 * tol * vscale * pscale

    iN = np.flatnonzero(nonneg)
    out = interior_point(lambda P: (contacts.banded_matvec(ab, P) + reg * P + c) * act,
                         contacts.restrict(ab, act, reg), iN, np.where(nonneg, ps, 0.0), np.full(iN.size, vscale),
                         converged, lower=False, max_iter=IPM_ITERATIONS, joint_affine_step=False)
    if out is None:
        raise SolverError("the interior point did not converge")
    return out[0], out[2] + 1
