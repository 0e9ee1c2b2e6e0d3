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

import threading

import highspy
import numpy as np

from ..errors import SolverError

__all__ = ["SmallLP", "maximise", "first_highs"]

FEAS_TOL = 1e-10      # row violation accepted (rows are in units of the total weight)
HIGHS_OPTIONS = {"output_flag": False, "primal_feasibility_tolerance": 1e-10, "dual_feasibility_tolerance": 1e-10}


@dataclass
class SmallLP:
    """Solution: ``z``, objective ``value``, row duals ``y >= 0`` (``A^T y = -c`` on
    the optimum, sign convention of ``max c.z s.t. A z + b >= 0``), rounds, rows used."""

    z: np.ndarray
    value: float
    y: np.ndarray
    rounds: int
    working_rows: int
    min_row: float          # min over all rows of A z + b (>= -FEAS_TOL; rows scaled when retried equilibrated)
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
             start: np.ndarray | None = None, initial: int = 16, max_rounds: int = 100,
             per_round: int = 256) -> SmallLP:
    """Solve ``max c.z s.t. A z + b >= 0`` (see the module docstring); ``bounds``: one
    ``(lower, upper)`` per unknown (None: unbounded); rows come in sequences of ``seq``
    ordered along the member (default: one sequence); ``start``: rows to put in the
    working set first.  One HiGHS model (the ``highspy`` API) takes the rows of every
    round, so each round's simplex starts from the last optimal basis."""
    A, b, c = np.asarray(A, float), np.asarray(b, float), np.asarray(c, float)
    nr, nv = A.shape
    seq = nr if seq is None else seq
    work = np.unique(np.concatenate([np.linspace(0, nr - 1, min(nr, initial * max(1, nr // seq))).astype(np.int64),
                                     np.asarray([] if start is None else start, dtype=np.int64)]))
    try:
        return _generate(c, A, b, bounds, seq, work, max_rounds, per_round, None)
    except _Unsolved:
        # rows of very different sizes (a very thin section: entries ~1/t) can leave HiGHS's
        # absolute tolerances out of reach: the same rows equilibrated by powers of two (exact)
        big = np.maximum(np.max(np.abs(A), axis=1, initial=0.0), np.abs(b))
        scale = np.ldexp(1.0, -np.frexp(np.where(big > 0, big, 1.0))[1])
        try:
            return _generate(c, A, b, bounds, seq, work, max_rounds, per_round, scale)
        except _Unsolved as e:
            raise SolverError(str(e)) from None


_OUTCOMES = (highspy.HighsModelStatus.kInfeasible, highspy.HighsModelStatus.kUnbounded,
             highspy.HighsModelStatus.kUnboundedOrInfeasible)


class _Unsolved(SolverError):
    """HiGHS found no optimum of a working set."""


def _generate(c, A, b, bounds, seq, work, max_rounds, per_round, scale) -> SmallLP:
    """The rounds of :func:`maximise` (rows multiplied by ``scale`` for HiGHS, if given)."""
    nr, nv = A.shape
    h = _highs(c, _bounds_list(bounds, nv))
    rows = work
    for rnd in range(1, max_rounds + 1):
        if scale is None:                   # the rows joining the working set (a warm start after the first)
            _add_rows(h, A[rows], b[rows])
        else:
            _add_rows(h, A[rows] * scale[rows, None], b[rows] * scale[rows])
        ran = h.run()
        status = h.getModelStatus()
        if status in _OUTCOMES:              # a genuine outcome of the working set: no retry
            raise SolverError(f"HiGHS: the {work.size}-row working set is {h.modelStatusToString(status)}")
        if ran == highspy.HighsStatus.kError or status != highspy.HighsModelStatus.kOptimal:
            raise _Unsolved(f"HiGHS failed on a {work.size}-row working set ({h.modelStatusToString(status)})")
        sol = h.getSolution()
        if len(sol.row_dual) != work.size:
            raise SolverError(f"HiGHS holds {len(sol.row_dual)} rows of the {work.size}-row working set")
        z = np.array(sol.col_value)
        r = A @ z + b
        if scale is not None:                # the retry's rows: judged as HiGHS saw them
            r *= scale
        bad = r < -FEAS_TOL
        bad[work] = False   # rows of the working set hold to HiGHS's own tolerance
        if not bad.any():
            break
        rows = _runs_argmin(r, bad, seq)
        if rows.size > per_round:
            rows = rows[np.argsort(r[rows])[:per_round]]
        work = np.concatenate([work, rows])  # in the order of the model's rows
    else:
        raise SolverError(f"constraint generation did not converge in {max_rounds} rounds")
    y = np.zeros(nr)
    y[work] = np.array(sol.row_dual) * (1.0 if scale is None else scale[work])   # >= 0 (min -c.z, rows A z >= -b)
    # a bound binds when it is active and its reduced cost is not zero: a free self-stress
    # parked at its bound by the simplex does not hold the optimum
    at_bound = np.abs(np.array(sol.col_dual)) > 1e-9 * max(1.0, float(np.max(np.abs(c))))
    return SmallLP(z, float(c @ z), y, rnd, int(work.size), float(np.min(r)), at_bound)


_BANNER_DONE = False   # the first construction in this process is done (HiGHS >= 1.16 prints a banner there)
_LOCK = threading.Lock()


def first_highs() -> None:
    """Construct a first HiGHS object with the C-level stdout sent to /dev/null: HiGHS >= 1.16
    prints its banner on the first construction in a process, before any option can be
    set, and the commands' stdout must stay pure (JSON)."""
    global _BANNER_DONE
    if _BANNER_DONE:
        return
    import ctypes
    import os
    import sys

    with _LOCK:                      # threads of one process (a Dask worker) redirect once
        if _BANNER_DONE:
            return
        try:                         # best effort: without a usable fd 1 there is nothing to protect
            if sys.stdout is not None:
                sys.stdout.flush()
            libc = ctypes.CDLL(None)
            libc.fflush(None)
            saved = os.dup(1)
        except (OSError, TypeError, AttributeError, ValueError):
            highspy.Highs()
            _BANNER_DONE = True
            return
        try:
            null = os.open(os.devnull, os.O_WRONLY)
            try:
                os.dup2(null, 1)
                highspy.Highs()
                libc.fflush(None)
            finally:
                os.dup2(saved, 1)
                os.close(null)
        finally:
            os.close(saved)
        _BANNER_DONE = True


def _highs(c: np.ndarray, bounds: list) -> "highspy.Highs":
    """A HiGHS model ``min -c.z`` over the box ``bounds`` (None: infinite), no rows yet."""
    first_highs()
    h = highspy.Highs()
    for k, v in HIGHS_OPTIONS.items():
        h.setOptionValue(k, v)
    inf = highspy.kHighsInf
    lo = np.array([-inf if lb is None else lb for lb, _ in bounds], float)
    up = np.array([inf if ub is None else ub for _, ub in bounds], float)
    h.addVars(c.size, lo, up)
    h.changeColsCost(c.size, np.arange(c.size, dtype=np.int32), -c)
    return h


def _add_rows(h: "highspy.Highs", A: np.ndarray, b: np.ndarray) -> None:
    """Rows ``A z >= -b`` (dense ``A``, a few columns)."""
    n, nv = A.shape
    if not (np.all(np.isfinite(A)) and np.all(np.isfinite(b))):
        raise SolverError("limit LP: a constraint row is not finite")
    added = h.addRows(n, -b, np.full(n, highspy.kHighsInf), n * nv, np.arange(0, n * nv, nv, dtype=np.int32),
              np.tile(np.arange(nv, dtype=np.int32), n), np.ascontiguousarray(A, float).ravel())
    if added == highspy.HighsStatus.kError:   # e.g. an entry of 1e15 or more: HiGHS rejects the rows
        raise _Unsolved(f"HiGHS rejected {n} constraint rows (entries too large?)")


def _bounds_list(bounds, n):
    if isinstance(bounds, tuple) and len(bounds) == 2 and not isinstance(bounds[0], (tuple, list)):
        return [bounds] * n
    return list(bounds)
