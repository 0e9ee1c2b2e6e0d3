"""One table of verification thresholds and the check every result runs on itself.

Every figure is dimensionless and small when the solution is right; each is recomputed
from the solution by a route other than the one that produced it (docs/verification.md
gives the formula of each).  A figure above its threshold, or one that is not a finite
number, fails the result: :func:`check` raises :class:`~fembeam.errors.SolverError`,
which the command line turns into exit code 3.

Why these values: residuals of linear algebra on these operators are ~1e-14; the QP is
solved to 1e-10 and the LPs' rows to 1e-11 (units of the total weight); the limit LP's
forces come from a sparse LU of a chain whose condition number grows like N^2 (1e-9 at
10^5 elements was measured), hence 1e-6 for the force residuals.
"""
from __future__ import annotations

import math

from ..errors import SolverError

__all__ = ["THRESHOLDS", "check", "failures"]

THRESHOLDS: dict[str, float] = {
    # limit analysis
    "equilibrium_residual": 1e-6,    # |B^T g - p| / |p| with the sparse operators
    "statics_mismatch": 1e-6,        # joint forces vs equilibrium of the part left of each joint
    "thrust_line_outside": 1e-6,     # (|e| - t/2) / t, e from that equilibrium, not from the LP
    "max_tensile_force": 1e-6,       # -min(N) / max(N)
    "duality_gap": 1e-7,             # |A_L(static) - A_L(mechanism)| / (1 + A_L)
    "complementarity": 1e-7,         # max N eps / (max N max eps)
    "incompatibility": 1e-6,         # negative openings, sliding, closure misfit / max opening
    "continuum_violation": 1e-8,     # thrust line outside between the joints (continuum), units of weight
    "hinge_refinement_gap": 1e-7,    # mesh LP through the hinges vs the continuum A_L
    "ray_residual": 1e-6,            # no-mechanism certificate: equilibrium and admissibility of the ray
    # impact
    "impulse_line_outside": 1e-6,    # impulses recomputed from the momentum balance of the elements
    "impulse_mismatch": 1e-6,        # those impulses vs the QP's multipliers
    "max_tensile_impulse": 1e-6,
    "impulse_work": 1e-7,
    "virtual_work_gap": 1e-7,
}


def failures(figures: dict) -> dict:
    """The figures of ``figures`` that have a threshold and do not meet it."""
    return {k: v for k, v in figures.items()
            if k in THRESHOLDS and not (isinstance(v, (int, float)) and math.isfinite(v) and v <= THRESHOLDS[k])}


def check(figures: dict, where: str) -> None:
    """Raise :class:`SolverError` naming every figure above its threshold."""
    bad = failures(figures)
    if bad:
        txt = ", ".join(f"{k} = {v:.2e} > {THRESHOLDS[k]:.0e}" for k, v in bad.items())
        raise SolverError(f"{where}: solution failed verification ({txt})")
