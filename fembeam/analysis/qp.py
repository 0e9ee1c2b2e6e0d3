"""Sparse convex QP backends with one result type.

Problem (all backends)::

    minimise   1/2 x^T P x + q^T x
    subject to A_eq x = b_eq (default 0),  A_in x >= 0

KKT convention returned: ``P x + q = A_eq^T lam + A_in^T mu`` with ``mu >= 0``
(for the impact QP ``mu`` are the internal impulses).  Every solve is checked: a
status other than solved raises :class:`SolverError`.
"""
from __future__ import annotations

import time
from dataclasses import dataclass

import numpy as np
import scipy.sparse as sp

from ..errors import InputError, SolverError

__all__ = ["QPSolution", "solve_qp", "BACKENDS"]

BACKENDS = ("clarabel", "osqp")


@dataclass
class QPSolution:
    """The solution of :func:`solve_qp`, whichever the backend.

    Attributes
    ----------
    x : ndarray
        The minimiser.
    lam : ndarray
        The multipliers of ``A_eq x = b_eq``.
    mu : ndarray
        The multipliers (``>= 0``) of ``A_in x >= 0``: ``P x + q = A_eq^T lam + A_in^T mu``.
    status : str
        The backend's status (``"Solved"``, ``"solved"``, ``"solved (unpolished)"``).
    iterations : int
        The backend's iterations.
    solve_time : float
        The backend's own time (s).
    backend : {"clarabel", "osqp"}
        The backend that solved it.
    infeasible : bool
        No feasible point with the required normalisation.

    Examples
    --------
    The projection of ``(1, 3)`` onto the segment ``x1 + x2 = 1``, ``x >= 0`` (minimise
    ``1/2 |x|^2 - x1 - 3 x2``) is its end ``(0, 1)``; of the bounds, only ``x1 >= 0`` carries
    a multiplier:

    >>> import numpy as np
    >>> import scipy.sparse as sp
    >>> from fembeam.analysis.qp import solve_qp
    >>> sol = solve_qp(sp.eye(2, format="csc"), np.array([-1.0, -3.0]),
    ...                sp.csc_matrix([[1.0, 1.0]]), sp.eye(2, format="csc"), b_eq=[1.0])
    >>> print(sol.backend, sol.status)
    clarabel Solved
    >>> print("x =", sol.x.round(6) + 0.0, "lam =", sol.lam.round(6) + 0.0,
    ...       "mu =", sol.mu.round(6) + 0.0)
    x = [0. 1.] lam = [-2.] mu = [1. 0.]
    """

    x: np.ndarray
    lam: np.ndarray          # multipliers of A_eq x = 0
    mu: np.ndarray           # multipliers of A_in x >= 0 (>= 0)
    status: str
    iterations: int
    solve_time: float        # s, the solver's own time
    backend: str
    infeasible: bool = False  # no feasible point with the required normalisation


def _osqp(P, q, A_eq, A_in, b_eq, tol):
    """ADMM to a loose tolerance, then polishing (an active-set solve) gives the accurate
    primal and dual; if polishing fails, ADMM continues warm-started to ``tol``."""
    import osqp

    A = sp.vstack([A_eq, A_in]).tocsc()
    l = np.concatenate([b_eq, np.zeros(A_in.shape[0])])
    u = np.concatenate([b_eq, np.full(A_in.shape[0], np.inf)])
    solver = osqp.OSQP()
    solver.setup(sp.triu(P).tocsc(), q, A, l, u, eps_abs=max(tol, 1e-6), eps_rel=max(tol, 1e-6),
                 max_iter=400000, polishing=True, polish_refine_iter=20, verbose=False,
                 adaptive_rho_interval=25)
    t0 = time.perf_counter()
    res = solver.solve(raise_error=False)
    iters = res.info.iter
    if res.info.status == "solved" and res.info.status_polish != 1 and tol < 1e-6:
        solver.update_settings(eps_abs=tol, eps_rel=tol)
        res = solver.solve(raise_error=False)
        iters += res.info.iter
    dt = time.perf_counter() - t0
    status = res.info.status
    if status != "solved":
        raise SolverError(f"OSQP did not solve the QP (status: {status!r}, {iters} iterations)")
    if res.info.status_polish != 1:
        status = "solved (unpolished)"  # accuracy is then decided by the verification figures
    y = -res.y
    neq = A_eq.shape[0]
    return QPSolution(res.x, y[:neq], y[neq:], status, int(iters), dt, "osqp")


def _clarabel(P, q, A_eq, A_in, b_eq, tol):
    import clarabel

    A = sp.vstack([A_eq, -A_in]).tocsc()
    b = np.concatenate([b_eq, np.zeros(A_in.shape[0])])
    cones = [clarabel.ZeroConeT(A_eq.shape[0]), clarabel.NonnegativeConeT(A_in.shape[0])]
    s = clarabel.DefaultSettings()
    s.verbose = False
    s.tol_gap_abs = s.tol_gap_rel = s.tol_feas = tol
    s.tol_ktratio = 1e-8
    s.max_iter = 200
    t0 = time.perf_counter()
    sol = clarabel.DefaultSolver(sp.triu(P).tocsc(), q, A, b, cones, s).solve()
    dt = time.perf_counter() - t0
    status = str(sol.status)
    if status != "Solved":
        raise SolverError(f"Clarabel did not solve the QP (status: {status}, {sol.iterations} iterations)")
    z = np.asarray(sol.z)
    neq = A_eq.shape[0]
    return QPSolution(np.asarray(sol.x), -z[:neq], z[neq:], status, int(sol.iterations), dt, "clarabel")


def solve_qp(P, q, A_eq, A_in, backend: str = "clarabel", tol: float = 1e-10, b_eq=None) -> QPSolution:
    """Solve the QP with ``backend`` (``"clarabel"`` interior point, ``"osqp"`` ADMM
    with solution polishing); ``tol`` is passed as the absolute/relative tolerance."""
    b_eq = np.zeros(A_eq.shape[0]) if b_eq is None else np.asarray(b_eq, float)
    if backend == "clarabel":
        return _clarabel(P, q, A_eq, A_in, b_eq, tol)
    if backend == "osqp":
        return _osqp(P, q, A_eq, A_in, b_eq, tol)
    raise InputError(f"unknown QP backend {backend!r}; allowed: {', '.join(BACKENDS)}")
