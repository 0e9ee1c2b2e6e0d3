"""The rows of the static limit LPs and the three LPs on them, shared by the limit analysis of
the joints (:mod:`~fembeam.analysis.limit`), of the continuous member
(:mod:`~fembeam.analysis.continuum`), with friction (:mod:`~fembeam.analysis.friction`) and of
the minimum thickness (:mod:`~fembeam.analysis.thickness`).

A row is an affine function of the redundants ``x`` (``k`` of them, units of the weight) and
of the load factor ``lambda`` (g, positive along ``direction``): an array ``(k + 2,)`` acting on
``(x, lambda, 1)``, in units of the total weight ``m g``, admissible when ``>= 0``.  The rows are
the joint forces of :class:`~fembeam.analysis.statics.Statics` (``g = (S, N+, N-)``: shear, and
intrados and extrados fibre forces, compression positive):

* fibre rows ``N+ >= 0``, ``N- >= 0`` of every joint (:func:`joint_rows`) and of any section
  between the joints (:func:`append_section_rows`): the thrust line inside the section;
* with a Coulomb coefficient ``mu`` the friction rows ``(mu (N+ + N-) -+ S) / (1 + mu) >= 0``
  (:func:`friction_rows`), divided by ``1 + mu`` so that they tend to the normal force, not to
  infinity, for large ``mu``.

The duals ``y >= 0`` of the rows are the jumps of a velocity field at the joints
(:func:`jumps`): opening rates of the intrados and extrados fibres and, with friction, the
sliding rate with its associative dilatancy (docs/friction.md).

The LPs (:func:`stand_lp`, :func:`main_lp`, :func:`ray_lp`) box the redundants so that HiGHS
always has a bounded problem; :func:`solve_unboxed` enlarges the box until it no longer binds,
so that their duals are those of the unboxed problems.
"""
from __future__ import annotations

import math
from typing import Callable

import numpy as np

from ..errors import InputError, SolverError
from .lp import SmallLP, maximise
from .statics import Statics, section_force_rows

__all__ = ["BOX", "XBOX", "STAND_TOL", "MAX_FRICTION", "check_direction", "check_friction", "joint_rows",
           "friction_rows", "append_section_rows", "jumps", "stand_lp", "main_lp", "ray_lp", "solve_unboxed"]

BOX = 1e6            # bound on lambda (g): beyond it, look for a no-mechanism certificate
XBOX = 1e3           # bound on the redundants (units of weight), enlarged by solve_unboxed
STAND_TOL = 1e-12    # margin (units of weight) below which the member does not stand
MAX_FRICTION = 1000.0   # beyond it the rows' round-off (times mu) exceeds the certificate's tolerance


def check_direction(direction) -> int:
    """``direction`` of the horizontal acceleration as the int ``+1`` (+x) or ``-1``; InputError
    otherwise."""
    if isinstance(direction, bool) or direction not in (1, -1):
        raise InputError(f"direction must be +1 or -1, got {direction!r}")
    return int(direction)


def check_friction(mu) -> float | None:
    """``None`` (no sliding) or a Coulomb coefficient ``0 <= mu <= MAX_FRICTION``; InputError
    otherwise (joints that never slide: no coefficient at all)."""
    if mu is None:
        return None
    if isinstance(mu, bool) or not isinstance(mu, (int, float, np.integer, np.floating)) \
            or not math.isfinite(mu) or not 0 <= mu <= MAX_FRICTION:
        raise InputError(f"the friction coefficient must be a number in [0, {MAX_FRICTION:g}] (no coefficient: "
                         f"joints that never slide), got {mu!r}")
    return float(mu)


def _force_rows(st: Statics, direction: int, i: int) -> np.ndarray:
    """``(J, k + 2)``: joint force ``i`` (0: ``S``, 1: ``N+``, 2: ``N-``) of every joint as rows."""
    return np.concatenate([st.G_x[i], direction * st.G_lambda[i][:, None], st.G0[i][:, None]], 1)


def joint_rows(st: Statics, direction: int, friction: float | None = None) -> np.ndarray:
    """``(2 J, k + 2)``: fibre forces ``N+`` of every joint, then ``N-``, as rows on
    ``(x, lambda, 1)`` (units of weight; ``lambda`` along ``direction``, +1 or -1); with a
    coefficient ``friction`` ``(4 J, k + 2)``: then the rows of :func:`friction_rows`."""
    R = np.concatenate([_force_rows(st, direction, i) for i in (1, 2)])
    return R if friction is None else np.concatenate([R, friction_rows(st, direction, friction)])


def friction_rows(st: Statics, direction: int, mu: float) -> np.ndarray:
    """``(2 J, k + 2)``: rows ``(mu N -+ S) / (1 + mu)`` (``N = N+ + N-``) of every joint
    acting on ``(x, lambda, 1)``, ``-S`` rows first (units of weight)."""
    N, S = _force_rows(st, direction, 1) + _force_rows(st, direction, 2), _force_rows(st, direction, 0)
    return np.concatenate([mu * N - S, mu * N + S]) / (1.0 + mu)


def append_section_rows(R: np.ndarray, st: Statics, direction: int, cuts: np.ndarray,
                        fib: np.ndarray) -> np.ndarray:
    """``R`` followed by one fibre row per section: fibre ``fib[i]`` (0: ``N+``, 1: ``N-``) at
    arc length ``cuts[i]`` (m), from the equilibrium of the part left of the section
    (:func:`~fembeam.analysis.statics.section_force_rows`); ``R`` itself when there is none."""
    if cuts.size == 0:
        return R
    C = section_force_rows(st, cuts)                      # (3, nc, k + 2)
    C = C[1 + fib, np.arange(cuts.size)]
    C[:, st.k] *= direction
    return np.concatenate([R, C])


def jumps(y: np.ndarray, J: int, mu: float | None) -> np.ndarray:
    """Jumps ``(3, J)`` at the joints (rows: sliding rate ``gamma``, intrados and extrados
    opening rates ``eps+``, ``eps-``) conjugate to the duals ``y`` of :func:`joint_rows` (fibre
    rows ``N+``, ``N-``, then with ``mu`` the friction rows ``-S``, ``+S``): with the duals
    ``a``, ``b`` of the friction rows ``gamma = (b - a) / (1 + mu)`` and both openings grow by
    ``mu (a + b) / (1 + mu)`` (associative dilatancy)."""
    y = np.asarray(y, float).reshape(-1, J)
    c = np.zeros((3, J))
    c[1:] = y[:2]
    if mu is not None:
        a, b = y[2], y[3]
        c[0] = (b - a) / (1.0 + mu)
        c[1:] += mu * (a + b) / (1.0 + mu)
    return c


def stand_lp(R: np.ndarray, k: int, xbox: float = XBOX) -> SmallLP:
    """Largest margin under gravity alone: ``max tau s.t. rows(x, 0) >= tau`` (``tau``: units
    of weight, at most 1; ``|x| <= xbox``)."""
    A = np.column_stack([R[:, :k], -np.ones(R.shape[0])])
    return maximise(np.r_[np.zeros(k), 1.0], A, R[:, k + 1], [(-xbox, xbox)] * k + [(None, 1.0)],
                    seq=R.shape[0] // 2)


def main_lp(R: np.ndarray, k: int, xbox: float = XBOX) -> SmallLP:
    """The limit LP: ``max lambda s.t. rows(x, lambda) >= 0`` (``lambda <= BOX``, ``|x| <= xbox``)."""
    return maximise(np.r_[np.zeros(k), 1.0], R[:, :k + 1], R[:, k + 1], [(-xbox, xbox)] * k + [(None, BOX)],
                    seq=R.shape[0] // 2)


def ray_lp(R: np.ndarray, k: int, xbox: float = XBOX) -> SmallLP:
    """``max tau s.t. rows_x dx + rows_lambda >= tau``: ``tau >= 0`` is an admissible ray of
    self-stress and load (no horizontal acceleration makes a mechanism)."""
    A = np.column_stack([R[:, :k], -np.ones(R.shape[0])])
    return maximise(np.r_[np.zeros(k), 1.0], A, R[:, k], [(-xbox, xbox)] * k + [(None, 1.0)], seq=R.shape[0] // 2)


def solve_unboxed(lp: Callable[..., SmallLP], R: np.ndarray, k: int) -> SmallLP:
    """Solve ``lp(R, k, xbox)`` with the redundants boxed, enlarging the box while it binds (a
    thrust of more than 1e3 weights: very flat or very thin members); the box never binds at
    the end, so the duals are those of the unboxed problem.  SolverError when it still binds
    at 1e15 weights."""
    for xbox in (XBOX, 1e6 * XBOX, 1e12 * XBOX):
        sol = lp(R, k, xbox)
        if not sol.at_bound[:k].any():
            return sol
    raise SolverError(f"limit LP: the redundants exceed {1e12 * XBOX:g} weights (no finite thrust state)")
