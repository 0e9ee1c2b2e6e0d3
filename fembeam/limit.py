"""Equivalent static analysis: incipient rocking acceleration and mechanism (THEORY §3).

Kinematic linear programme over compatible rigid-element fields ``u``::

    minimise  f_y . u            (power of gravity lifting the weight, per g)
    subject to  direction * f_x . u = m   (unit mean horizontal velocity)
                B_slide u = 0,  B_open u >= 0

The optimum over ``m`` is ``lambda_L = A_L / g``.  HiGHS' duals are the joint forces of
the thrust line: fibre forces ``N_pm >= 0`` (compression) and shear ``S``, in
equilibrium with weight and inertia: ``f_y - lambda_L direction f_x = B_open^T N + B_slide^T S``.
Forces are reported per unit g (multiply by g for newtons per unit depth).
"""
from __future__ import annotations

import time
from dataclasses import dataclass, field

import numpy as np
import scipy.sparse as sp
from scipy.optimize import linprog

from .errors import CannotStandError, SolverError
from .fem import Discretization
from .hinges import Hinge, find_hinges

__all__ = ["LimitResult", "limit_analysis", "dof_scaling"]


def dof_scaling(disc: Discretization) -> sp.dia_matrix:
    """Diagonal ``D`` with ``d = D d~``: makes the rotation DOFs velocities (x length)."""
    s = np.tile([1.0, 1.0, 1.0 / disc.curve.length], disc.M.shape[0] // 3)
    return sp.diags(s)


@dataclass
class LimitResult:
    """Outcome of the limit analysis. ``status`` is ``"ok"``, ``"cannot_stand"``
    (the arch collapses under its own weight) or ``"no_mechanism"`` (no compatible
    mechanism moves in the load direction: no horizontal acceleration can collapse it)."""

    status: str
    disc: Discretization
    direction: int
    A_L: float = float("nan")              # units of g
    u: np.ndarray | None = None            # mechanism, direction * f_x . u = total mass
    N: np.ndarray | None = None            # (2, J) fibre forces intrados/extrados, per g
    S: np.ndarray | None = None            # (J,) shear forces, per g
    hinges: list[Hinge] = field(default_factory=list)
    verification: dict = field(default_factory=dict)
    solve_time: float = 0.0

    @property
    def eccentricity(self) -> np.ndarray:
        """Thrust-line eccentricity at the joints (m, from the mid-curve, + to intrados)."""
        t, Nt = self.disc.joint_thickness, self.N[0] + self.N[1]
        with np.errstate(invalid="ignore", divide="ignore"):
            return np.where(Nt > 1e-12 * np.max(Nt), 0.5 * t * (self.N[0] - self.N[1]) / Nt, np.nan)


def limit_analysis(disc: Discretization, direction: int = 1, strict: bool = False) -> LimitResult:
    """Solve the kinematic LP on ``disc``; the load acts in ``direction`` (+1: +x).

    With ``strict`` an arch that cannot stand raises :class:`CannotStandError` instead of
    returning ``status == "cannot_stand"``."""
    res = _solve(disc, direction)
    if strict and res.status == "cannot_stand":
        raise CannotStandError("the arch cannot stand under its own weight (A_L <= 0): its thickness is "
                               "below the minimum for its embrace angle (see fembeam.minimum_thickness)")
    return res


def _solve(disc: Discretization, direction: int) -> LimitResult:
    D = dof_scaling(disc)
    fx, fy = disc.load_vectors()
    m = float(fx @ disc.rigid(V=(1.0, 0.0)))
    Bs, Bo = disc.B_slide @ D, disc.B_open @ D
    c = D @ fy / m
    A_eq = sp.vstack([Bs, sp.csr_matrix(direction * (D @ fx) / m)]).tocsr()
    b_eq = np.zeros(A_eq.shape[0])
    b_eq[-1] = 1.0
    t0 = time.perf_counter()
    # HiGHS's interior point with crossover (a vertex solution and its duals) is 2-5 times
    # faster than the simplex from 1600 elements on (benchmarks/lp_methods.py). Status 4
    # ("numerical difficulties") was seen on nearly locked arches and on nearly closed
    # rings (where presolve fails and the plain simplex proves unboundedness): retry.
    for method, presolve in (("highs-ipm", True), ("highs-ds", True), ("highs-ds", False)):
        res = linprog(c, A_ub=-Bo, b_ub=np.zeros(Bo.shape[0]), A_eq=A_eq, b_eq=b_eq,
                      bounds=(None, None), method=method, options={"presolve": presolve})
        if res.status != 4:
            break
    dt = time.perf_counter() - t0
    if res.status == 2:
        return LimitResult("no_mechanism", disc, direction, solve_time=dt)
    if res.status == 3:
        return LimitResult("cannot_stand", disc, direction, A_L=-np.inf, solve_time=dt)
    if res.status != 0:
        raise SolverError(f"HiGHS failed on the limit-analysis LP: {res.message}")
    lam = float(res.fun)
    u = D @ res.x
    J = disc.n_joints
    N = -m * np.asarray(res.ineqlin.marginals).reshape(2, J)   # >= 0: compression
    S = m * np.asarray(res.eqlin.marginals)[:-1]
    out = LimitResult("ok" if lam > 0 else "cannot_stand", disc, direction, lam, u, N, S,
                      find_hinges(disc, u), solve_time=dt)
    out.verification = _verify(out, fx, fy, m)
    return out


def _verify(res: LimitResult, fx, fy, m) -> dict:
    disc, u, N, S = res.disc, res.u, res.N, res.S
    eq = fy - res.A_L * res.direction * fx - disc.B_open.T @ N.ravel() - disc.B_slide.T @ S
    eps = disc.B_open @ u
    Nmax = np.max(np.abs(N))
    t = disc.joint_thickness
    e = res.eccentricity
    carried = np.isfinite(e)
    return {
        "equilibrium_residual": float(np.linalg.norm(eq) / np.linalg.norm(fy)),
        "thrust_line_outside": float(max(0.0, np.max((np.abs(e[carried]) - 0.5 * t[carried]) / t[carried]))),
        "max_tensile_force": float(max(0.0, -np.min(N)) / Nmax),
        "complementarity": float(np.max(np.abs(N.ravel() * eps)) / (Nmax * np.max(np.abs(eps)))),
        "incompatibility": float(max(0.0, -np.min(eps), np.max(np.abs(disc.B_slide @ u))) / np.max(eps)),
        "max_shear_ratio": float(np.max(np.abs(S[carried]) / (N[0] + N[1])[carried])),
    }
