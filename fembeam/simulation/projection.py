"""The impact QP of one time step: projection of the free velocity onto the compatible cone.

In the kinetic metric ``M``, the end-of-step velocity is

    v+ = argmin 1/2 (v - v_free)^T M (v - v_free)   s.t.  (H v)_i >= 0 (opening rates, i in N),
                                                          (H v)_i  = 0 (sliding rates, i in T),

the impact QP of ``fembeam impact`` with the operators of the current configuration.  It is solved
in its dual form, the mixed linear complementarity problem in the impulses ``P`` (N s per unit depth)

    w = W P + c,  W = H M^-1 H^T,  c = H v_free;   w_T = 0;   0 <= P_N  _|_  w_N >= 0,

with ``v+ = v_free + M^-1 H^T P``, warm-started from the previous step's working set: a few block
principal pivots (Judice and Pires: all infeasible rows change sides at once; one or two solves
in a smooth phase), then, if they have not converged, a primal active-set method on ``P`` whose
objective decreases at every solve (finite, :func:`solve_mlcp`).  Rows
that are not constraints this step (open corners) keep their place as identity rows of the banded
``W``, so every linear solve has the same banded pattern (LAPACK ``pbtrf``/``pbtrs`` through
:func:`scipy.linalg.solveh_banded`).  ``reg`` (1e-12 of the largest diagonal entry) makes ``W``
definite when the closed joints are statically indeterminate (an arch at rest); it changes the
velocities by about ``reg |P|``.  Every solution's KKT residuals are checked.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy.linalg.lapack import dpbsv

from ..errors import SolverError
from .contacts import BAND, Contacts

__all__ = ["MLCPSolution", "solve_mlcp", "banded_solve", "REG", "KKT_TOL", "MAX_PIVOTS"]

REG = 1e-12          # regularisation, relative to the largest diagonal entry of W
KKT_TOL = 1e-8       # KKT residuals, relative to the scales of velocities and impulses
MAX_PIVOTS = 1000    # linear solves of one projection
BLOCK_PIVOTS = 8     # block principal pivots tried first


def banded_solve(ab: np.ndarray, b: np.ndarray) -> np.ndarray:
    """``x`` with ``A x = b``, ``A`` symmetric positive definite in upper banded storage (LAPACK
    ``dpbsv``, called directly: the small systems of a step cost microseconds)."""
    _, x, info = dpbsv(ab, b)
    if info != 0:
        raise SolverError(f"the step's Delassus matrix is not positive definite (LAPACK info {info})")
    return x


@dataclass
class MLCPSolution:
    P: np.ndarray            # impulses (3 J,), zero on rows that are no constraint
    w: np.ndarray            # W P + c: the end-of-step rates H v+ (m/s)
    working: np.ndarray      # rows solved as equalities (bool, 3 J)
    pivots: int
    kkt: float               # largest relative KKT residual
    ab: np.ndarray | None = None   # W (upper banded storage) of the solve


def solve_mlcp(contacts: Contacts, ab: np.ndarray, c: np.ndarray, free: np.ndarray, nonneg: np.ndarray,
               start: np.ndarray | None = None, vscale: float = 1.0) -> MLCPSolution:
    """Solve the MLCP above: ``ab`` is ``W`` in upper banded storage, ``free`` the equality rows
    (``T``), ``nonneg`` the unilateral rows (``N``); the others carry no impulse.  ``start``: the
    previous working set.  ``vscale`` (m/s): the velocity scale of the tolerances.

    A primal active-set method on the dual (Lawson and Hanson's, for bounds): ``P`` stays feasible;
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
    for k in range(BLOCK_PIVOTS):            # block principal pivoting: fast when it converges
        P = banded_solve(contacts.restrict(ab, F, reg), np.where(F, -c, 0.0))
        w = contacts.banded_matvec(ab, P) + reg * P + c
        ztol = 1e-12 * max(float(np.max(np.abs(P), initial=0.0)), pscale0)
        bad = nonneg & ((F & (P < -ztol)) | (~F & (w < -wtol)))
        if not bad.any():
            P[nonneg & (P < 0)] = 0.0
            return _checked(P, w, F, free, nonneg, k + 1, vscale, dmax)
        F = F ^ bad
    F = free | (nonneg & (start if start is not None else True))
    P = np.zeros(m)
    for pivots in range(BLOCK_PIVOTS + 1, MAX_PIVOTS + 1):
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
        w = contacts.banded_matvec(ab, P) + reg * P + c
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
