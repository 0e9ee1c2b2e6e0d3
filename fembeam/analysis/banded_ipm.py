"""Mehrotra's predictor-corrector interior point for a bound-constrained QP with a banded Hessian::

    minimise 1/2 g^T Q g + c^T g   subject to   g_I >= 0,

``Q`` symmetric positive (semi)definite in LAPACK band storage (upper or lower).  With the
multipliers ``z >= 0`` of the bounds the optimality conditions are

    r = Q g + c - E_I z = 0,    g_I z = 0,    g_I, z >= 0      (E_I: the columns I of the identity).

Every iteration factors the Newton matrix ``Q + diag(z / g)`` (on ``I``; the band is kept, LAPACK
``pbtrf``, O(n)) once and solves it twice for the step of a complementarity target ``rc``::

    (Q + diag(z / g)) dg = -r - rc / g  (rc / g on I only),    dz = -(rc + z dg_I) / g:

the predictor (affine scaling, ``rc = g z``), the complementarity ``mu_aff`` after its step to the
boundary, ``sigma = (mu_aff / mu)^3`` with ``mu = g.z / |I|``, the corrector
``rc = g z + dg_aff dz_aff - sigma mu``, and 0.995 of the step to the boundary (at most 1).
Used by the impact QP's banded dual (:mod:`.active_set`) and the time stepping's impact QP
(:mod:`fembeam.simulation.projection`); each brings its own start, stopping test and scaling.
"""
from __future__ import annotations

from typing import Callable

import numpy as np
from scipy.linalg.lapack import dpbtrf, dpbtrs

__all__ = ["interior_point", "Converged"]

Converged = Callable[[np.ndarray, np.ndarray, float], bool]   # (g, r, mu) -> stop


def _to_boundary(x: np.ndarray, dx: np.ndarray) -> float:
    """The longest step ``a <= 1`` keeping ``x + a dx >= 0`` (``x > 0``)."""
    ratio = np.divide(x, -dx, out=np.full(x.shape, np.inf), where=dx < 0)
    return min(1.0, float(np.min(ratio, initial=np.inf)))


def interior_point(rates: Callable[[np.ndarray], np.ndarray], ab: np.ndarray, I: np.ndarray, g: np.ndarray,
                   z: np.ndarray, converged: Converged, *, lower: bool, max_iter: int = 80,
                   joint_affine_step: bool = True) -> tuple[np.ndarray, np.ndarray, int] | None:
    """Mehrotra's predictor-corrector on the QP above (module docstring): ``rates(g)`` is
    ``Q g + c``, ``ab`` is ``Q`` in LAPACK band storage (``lower`` or upper), ``I`` the indices of
    the bounded rows, ``g`` (``g_I > 0``) and ``z > 0`` (one per row of ``I``) the start.  Before
    every Newton step ``converged(g, r, mu)`` decides on the residual ``r`` and ``mu``.
    ``joint_affine_step``: ``mu_aff`` after one step for ``g`` and ``z`` (else the longest step
    for each).  Returns ``(g, z, Newton steps)``; None if ``Q + diag(z / g)`` is not positive
    definite, an iterate is not finite or ``max_iter`` steps have not converged.  Rows outside
    ``I`` whose row of ``Q`` is the identity's and whose rate is zero stay at ``g = 0`` (a caller's
    rows that are no constraint)."""
    g, z = np.array(g, float), np.array(z, float)
    diag = 0 if lower else ab.shape[0] - 1
    n_I = max(z.size, 1)
    for it in range(max_iter):
        r = rates(g)
        r[I] -= z
        gI = g[I]
        mu = float(gI @ z) / n_I
        if converged(g, r, mu):
            return g, z, it
        newton = ab.copy(order="F")
        newton[diag, I] += z / gI
        L, info = dpbtrf(newton, lower=lower, overwrite_ab=1)
        if info != 0:
            return None

        def step(rc: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
            """``(dg, dg_I, dz)`` for the complementarity target ``rc``."""
            rhs = -r
            rhs[I] -= rc / gI
            dg = dpbtrs(L, rhs, lower=lower)[0]
            dgI = dg[I]
            return dg, dgI, (-rc - z * dgI) / gI

        gz = gI * z
        dg, dgI, dz = step(gz)                                          # predictor: rc = g z
        ag, az = _to_boundary(gI, dgI), _to_boundary(z, dz)
        if joint_affine_step:
            ag = az = min(ag, az)
        mu_aff = float((gI + ag * dgI) @ (z + az * dz)) / n_I
        sigma = (mu_aff / mu) ** 3 if mu > 0 else 0.0
        dg, dgI, dz = step(gz + dgI * dz - sigma * mu)                  # corrector
        a = 0.995 * min(_to_boundary(gI, dgI), _to_boundary(z, dz))
        g += a * dg
        z += a * dz
        if not (np.all(np.isfinite(g)) and np.all(np.isfinite(z))):
            return None
    return None
