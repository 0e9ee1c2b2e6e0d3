"""Compiled (numba) contact operators and banded linear algebra of one time step.

The same operators as :mod:`.contacts` and :mod:`.projection`, written as loops over the joints
for the compiled stepper (:mod:`.kernel`): the joint geometry and the rows of ``H``, ``H v``,
``H^T P``, the Delassus operator ``W = H M^-1 H^T`` in LAPACK's upper band storage
(``W[i, k]`` at ``ab[BAND + i - k, k]``, ``i <= k``, half-bandwidth :data:`BAND`), and a banded
Cholesky factorisation of ``W`` restricted to a set of rows (the others identity rows) plus a
diagonal.  Conventions of :mod:`.contacts`: joint ``j`` has the reference side ``A[j]`` and the
other side ``B[j]`` (body ``n`` is the ground), rows ``3 j + 0, 1`` the opening rates of its
intrados and extrados corners and ``3 j + 2`` the sliding rate at its ``contact`` corner.
"""
from __future__ import annotations

import math

import numpy as np
from numba import njit

BAND = 5


@njit(cache=True, error_model="numpy")
def geometry(q, A, B, ra, rb, nu0, tau0, gap, slip, rows, contact):
    """Gaps and slips ``(J, 2)`` (m), the rows of ``H`` ``(J, 3, 2, 3)`` and the contact corners at
    positions ``q`` ``(n + 1, 3)``; ``ra``, ``rb`` ``(J, 2, 2)`` the corners relative to the
    centroids of the two sides at rest, ``nu0``, ``tau0`` ``(J, 2)`` the reference face's normal and
    tangent at rest."""
    for j in range(A.size):
        a, b = A[j], B[j]
        ca, sa = math.cos(q[a, 2]), math.sin(q[a, 2])
        cb, sb = math.cos(q[b, 2]), math.sin(q[b, 2])
        nux, nuy = ca * nu0[j, 0] - sa * nu0[j, 1], sa * nu0[j, 0] + ca * nu0[j, 1]
        tx, ty = ca * tau0[j, 0] - sa * tau0[j, 1], sa * tau0[j, 0] + ca * tau0[j, 1]
        px0 = q[b, 0] + cb * rb[j, 0, 0] - sb * rb[j, 0, 1]
        py0 = q[b, 1] + sb * rb[j, 0, 0] + cb * rb[j, 0, 1]
        px1 = q[b, 0] + cb * rb[j, 1, 0] - sb * rb[j, 1, 1]
        py1 = q[b, 1] + sb * rb[j, 1, 0] + cb * rb[j, 1, 1]
        for c in range(2):
            px, py = (px0, py0) if c == 0 else (px1, py1)
            dx = px - (q[a, 0] + ca * ra[j, c, 0] - sa * ra[j, c, 1])
            dy = py - (q[a, 1] + sa * ra[j, c, 0] + ca * ra[j, c, 1])
            gap[j, c] = dx * nux + dy * nuy
            slip[j, c] = dx * tx + dy * ty
        k = 1 if gap[j, 1] < gap[j, 0] else 0
        contact[j] = k
        for r in range(3):
            dx, dy = (nux, nuy) if r < 2 else (tx, ty)
            c = r if r < 2 else k
            x, y = (px0, py0) if c == 0 else (px1, py1)
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
    """``out = H^T P`` ``(n + 1, 3)`` (impulses on the bodies; the ground's row zero)."""
    out[:] = 0.0
    for j in range(sides.shape[0]):
        for s in range(2):
            i = sides[j, s]
            for d in range(3):
                out[i, d] += rows[j, 0, s, d] * P[3 * j] + rows[j, 1, s, d] * P[3 * j + 1] \
                    + rows[j, 2, s, d] * P[3 * j + 2]
    out[out.shape[0] - 1, :] = 0.0


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
    """``out = W x`` from the upper band storage."""
    m = x.size
    for i in range(m):
        out[i] = ab[BAND, i] * x[i]
    for d in range(1, BAND + 1):
        for k in range(d, m):
            a = ab[BAND - d, k]          # W[k - d, k]
            out[k - d] += a * x[k]
            out[k] += a * x[k - d]


@njit(cache=True, error_model="numpy")
def factor(ab, keep, reg, extra, U) -> bool:
    """Cholesky ``U^T U`` of ``W`` restricted to the rows ``keep`` (the others identity rows) plus
    ``reg + extra`` on the kept diagonal; ``U[j, d]`` = ``U[j, j + d]`` for ``d > 0`` and ``U[j, 0]``
    the inverse of the diagonal entry ``1 / U[j, j]``.  False if not positive definite."""
    m = keep.size
    for j in range(m):
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
