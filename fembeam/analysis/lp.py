"""Linear programmes in a few unknowns with very many inequality rows.

``maximise c . z  subject to  A z + b >= 0`` with ``A`` of shape ``(rows, nv)``, ``nv``
at most five (the redundants, the load factor, a margin) and up to millions of rows
(two per joint).  Constraint generation: HiGHS solves the problem on a small working
set of rows; every row is then evaluated (one matrix-vector product, O(rows)); the most
violated row of each run of violated rows joins the working set; stop when none is
violated.  An optimum of the working set that satisfies every row is an optimum of the
whole problem, and its duals (zero outside the working set) are the whole problem's
duals: the certificate is checked, not assumed.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy.optimize import linprog

from ..errors import SolverError

__all__ = ["SmallLP", "maximise"]

FEAS_TOL = 1e-10      # row violation accepted (rows are in units of the total weight)
HIGHS_OPTIONS = {"primal_feasibility_tolerance": 1e-10, "dual_feasibility_tolerance": 1e-10}


@dataclass
class SmallLP:
    """Solution: ``z``, objective ``value``, row duals ``y >= 0`` (``A^T y = -c`` on
    the optimum, sign convention of ``max c.z s.t. A z + b >= 0``), rounds, rows used."""

    z: np.ndarray
    value: float
    y: np.ndarray
    rounds: int
    working_rows: int
    min_row: float          # min over all rows of A z + b (>= -FEAS_TOL)
    at_bound: np.ndarray    # bool per variable: a box bound holds the optimum (binding, non-zero reduced cost)


def _runs_argmin(r: np.ndarray, bad: np.ndarray, seq: int) -> np.ndarray:
    """Most violated row of every run of consecutive violated rows (rows grouped in
    sequences of length ``seq``, e.g. one fibre along the member)."""
    idx = np.flatnonzero(bad)
    brk = np.flatnonzero((np.diff(idx) != 1) | (np.diff(idx // seq) != 0)) + 1
    starts = np.concatenate([[0], brk])
    ends = np.concatenate([brk, [idx.size]])
    vals = r[idx]
    run = np.repeat(np.arange(starts.size), ends - starts)
    first = np.flatnonzero(vals == np.minimum.reduceat(vals, starts)[run])
    _, pick = np.unique(run[first], return_index=True)
    return idx[first[pick]]


def maximise(c: np.ndarray, A: np.ndarray, b: np.ndarray, bounds, seq: int | None = None,
             start: np.ndarray | None = None, initial: int = 64, max_rounds: int = 100,
             per_round: int = 256) -> SmallLP:
    """Solve ``max c.z s.t. A z + b >= 0`` (see the module docstring); ``bounds`` as for
    :func:`scipy.optimize.linprog`; rows come in sequences of ``seq`` ordered along the
    member (default: one sequence); ``start``: rows to put in the working set first."""
    A, b, c = np.asarray(A, float), np.asarray(b, float), np.asarray(c, float)
    nr = A.shape[0]
    seq = nr if seq is None else seq
    work = np.unique(np.concatenate([np.linspace(0, nr - 1, min(nr, initial * max(1, nr // seq))).astype(np.int64),
                                     np.asarray([] if start is None else start, dtype=np.int64)]))
    for rnd in range(1, max_rounds + 1):
        res = linprog(-c, A_ub=-A[work], b_ub=b[work], bounds=bounds, method="highs", options=HIGHS_OPTIONS)
        if res.status != 0:
            raise SolverError(f"HiGHS failed on a {work.size}-row working set (status {res.status}: {res.message})")
        z = res.x
        r = A @ z + b
        bad = r < -FEAS_TOL
        bad[work] = False   # rows of the working set hold to HiGHS's own tolerance
        if not bad.any():
            break
        add = _runs_argmin(r, bad, seq)
        if add.size > per_round:
            add = add[np.argsort(r[add])[:per_round]]
        work = np.union1d(work, add)
    else:
        raise SolverError(f"constraint generation did not converge in {max_rounds} rounds")
    y = np.zeros(nr)
    y[work] = -np.asarray(res.ineqlin.marginals)
    # a bound binds when it is active and its reduced cost is not zero: a free self-stress
    # parked at its bound by the simplex does not hold the optimum
    reduced = np.abs(np.asarray(res.lower.marginals)) + np.abs(np.asarray(res.upper.marginals))
    at_bound = reduced > 1e-9 * max(1.0, float(np.max(np.abs(c))))
    return SmallLP(z, float(c @ z), y, rnd, int(work.size), float(np.min(r)), at_bound)


def _bounds_list(bounds, n):
    if isinstance(bounds, tuple) and len(bounds) == 2 and not isinstance(bounds[0], (tuple, list)):
        return [bounds] * n
    return list(bounds)
