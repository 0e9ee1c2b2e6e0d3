"""Internal forces of a moving mechanism: the dynamic thrust line.

At an instant ``(theta, theta', theta'')`` of an :class:`~fembeam.dynamics.equation.EquationOfMotion`
with ground acceleration ``a_g`` (g, positive along +x), every material point of a moving
piece carries, in the frame of the ground, the body force per unit mass::

    b(x) = -g e_y - a_g g e_x - a(x),   a(x) = a_A + alpha k x (x - A) - omega^2 (x - A)

(``A``: the piece's reference point, C1 / C13 moved to ``B`` / C2 for the crank / coupler /
rocker of a four-hinge arch, the hinge of a block; ``omega = w theta'``,
``alpha = w theta'' + w' theta'^2``).  Over a sub-arc ``[sa, sb]`` these loads integrate
exactly from its mass ``m``, first moment and polar moment in the reference configuration
(:meth:`~fembeam.geometry.MidCurve.segment_inertia`) moved rigidly with the piece.

Four hinges: the hinge forces (8 components) follow from the 3 x 3 equations of dynamic
equilibrium of the pieces in least squares; the 9 equations are consistent (relative
residual ~1e-12) only when ``theta''`` satisfies the equation of motion.  A section's
forces then follow from the part of its piece on its left.  One hinge (a block with a
free end): from the part between the section and the free end; the residual is the
moment equation of the whole block about its hinge.

Sections are straight normal cuts moved rigidly with their piece; at a section ``s``
with moved tangent ``t`` and normal ``n`` (``n = (t_y, -t_x)``, towards the intrados) the
action of the part ``[.., s]`` on the part ``[s, ..]`` is the force ``N t + V n`` (N/m of
depth; ``N > 0`` compression) and the moment ``M`` (N m/m) about the section's mid
point; its line of action crosses the section at ``e = M / N`` (m, + towards the intrados).
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..errors import InputError
from .equation import EquationOfMotion

__all__ = ["SectionForces", "section_forces", "thrust_line_margin"]


@dataclass(frozen=True)
class SectionForces:
    """Internal forces at the sections ``s`` (m) of a moving mechanism (per unit depth).

    ``N`` (N, compression > 0), ``V`` (N, along the moved normal), ``M`` (N m, about the
    section's mid point), ``eccentricity = M / N`` (m, + towards the intrados),
    ``thickness`` (m); ``margin = min (t/2 - |e|) / t`` over the sections (< 0: the thrust
    line leaves the section somewhere; a section with ``N <= 0`` counts as ``-inf``);
    ``residual``: relative residual of the equilibrium equations of the pieces (~1e-12
    when ``theta''`` satisfies the equation of motion)."""

    s: np.ndarray
    N: np.ndarray
    V: np.ndarray
    M: np.ndarray
    eccentricity: np.ndarray
    thickness: np.ndarray
    margin: float
    residual: float


def _cross(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    return a[0] * b[1] - a[1] * b[0]


def _rot(phi: float, v: np.ndarray) -> np.ndarray:
    c, s = np.cos(phi), np.sin(phi)
    return np.array([c * v[0] - s * v[1], s * v[0] + c * v[1]])


@dataclass(frozen=True)
class _Kinematics:
    """One moving piece: material point ``X0`` moved to ``A`` (acceleration ``aA``), turned
    by ``phi`` (rad) with angular velocity ``omega`` (rad/s) and acceleration ``alpha`` (rad/s^2)."""

    X0: np.ndarray
    A: np.ndarray
    aA: np.ndarray
    phi: float
    omega: float
    alpha: float

    def loads(self, curve, sa, sb, P: np.ndarray, gvec: np.ndarray):
        """Resultant force (2, n) and moment about the points ``P`` (2, n) of the body forces
        on the arcs ``[sa, sb]`` (gravity, ground inertia ``gvec`` per unit mass and d'Alembert)."""
        m, S, J = curve.segment_inertia(sa, sb)
        X0 = self.X0[:, None]
        s_r = _rot(self.phi, S - m * X0)                            # int (x - A) dm
        j_r = J - 2.0 * np.sum(X0 * S, 0) + m * np.sum(X0 * X0, 0)  # int |x - A|^2 dm
        p = P - self.A[:, None]
        c = (gvec - self.aA)[:, None]
        F = m * c - self.alpha * np.array([-s_r[1], s_r[0]]) + self.omega**2 * s_r
        Mo = (_cross(s_r - m * p, c) - self.alpha * (j_r - np.sum(p * s_r, 0))
              - self.omega**2 * _cross(p, s_r))
        return F, Mo


def _pieces(eq: EquationOfMotion, theta: float, rate: float, accel: float):
    """Kinematics of the moving pieces and the moved hinge points (2, n_hinges)."""
    zero = np.zeros(2)
    if eq.mechanism.n_hinges == 1:
        return [_Kinematics(eq.C, eq.C, zero, theta, rate, accel)], eq.C[:, None]
    k = eq._linkage(theta)
    if k is None:
        raise InputError(f"the four-bar linkage cannot reach theta = {theta:g} rad (locked)")
    B, D, psi3, psi2, w3, w2, dw3, dw2 = k
    r = B - eq.C1
    aB = accel * np.array([-r[1], r[0]]) - rate**2 * r
    kin = [_Kinematics(eq.C1, eq.C1, zero, theta, rate, accel),
           _Kinematics(eq.C13, B, aB, psi3, w3 * rate, w3 * accel + dw3 * rate**2),
           _Kinematics(eq.C2, eq.C2, zero, psi2, w2 * rate, w2 * accel + dw2 * rate**2)]
    return kin, np.column_stack([eq.C1, B, D, eq.C2])


def section_forces(eq: EquationOfMotion, theta: float, rate: float, accel: float, a_g: float,
                   s) -> SectionForces:
    """Internal forces at the sections ``s`` (m, inside the moving pieces) at the instant
    ``theta`` (rad), ``rate = theta'`` (rad/s), ``accel = theta''`` (rad/s^2) under the
    ground acceleration ``a_g`` (g).  ``accel`` is not checked: see ``residual``."""
    mech = eq.mechanism
    curve = mech.curve
    s = np.atleast_1d(np.asarray(s, float))
    nh, moving = mech.n_hinges, np.flatnonzero(mech.moving)
    edges = mech.breaks[np.r_[moving, moving[-1] + 1]]
    tol = 1e-12 * curve.length
    if np.any(s < edges[0] - tol) or np.any(s > edges[-1] + tol):
        raise InputError(f"sections must lie in the moving pieces, s in [{edges[0]:g}, {edges[-1]:g}] m")
    kin, H = _pieces(eq, float(theta), float(rate), float(accel))
    gvec = np.array([-a_g * eq.g, -eq.g])
    # hinges at the ends of every moving piece (breaks index b is hinge b - 1; -1: free end)
    ends = [(p - 1 if p >= 1 else -1, p if p < nh else -1) for p in moving]

    # equilibrium of the pieces: a piece gets +H_j at its left hinge and -H_j at its right
    # one (H_j: action of the part left of hinge j on the part right of it); moment rows / L
    Lc = curve.length
    A = np.zeros((3 * len(kin), 2 * nh))
    b = np.zeros(3 * len(kin))
    for k, (kn, hinges) in enumerate(zip(kin, ends)):
        F, Mo = kn.loads(curve, edges[k], edges[k + 1], kn.A[:, None], gvec)
        for j, sign in zip(hinges, (1.0, -1.0)):
            if j >= 0:
                a = H[:, j] - kn.A
                A[3 * k:3 * k + 2, 2 * j:2 * j + 2] = sign * np.eye(2)
                A[3 * k + 2, 2 * j:2 * j + 2] = sign * np.array([-a[1], a[0]]) / Lc
        b[3 * k:3 * k + 3] = -F[0, 0], -F[1, 0], -Mo[0] / Lc
    h = np.linalg.lstsq(A, b, rcond=None)[0]
    residual = float(np.linalg.norm(A @ h - b) / np.linalg.norm(b))
    Hf = h.reshape(nh, 2).T

    piece = np.clip(np.searchsorted(edges, s, side="right") - 1, 0, len(kin) - 1)
    T, M = np.zeros((2, s.size)), np.zeros(s.size)
    tn, nn = np.zeros((2, s.size)), np.zeros((2, s.size))
    for k, (kn, (left, right)) in enumerate(zip(kin, ends)):
        i = np.flatnonzero(piece == k)
        if i.size == 0:
            continue
        si = s[i]
        P = kn.A[:, None] + _rot(kn.phi, curve.position(si) - kn.X0[:, None])
        tn[:, i], nn[:, i] = _rot(kn.phi, curve.tangent(si)), _rot(kn.phi, curve.normal(si))
        if right < 0 and left >= 0:            # free right end: minus the loads on [s, end]
            F, Mo = kn.loads(curve, si, np.full(si.size, edges[k + 1]), P, gvec)
            T[:, i], M[i] = -F, -Mo
        else:                                  # left hinge force (if any) plus the loads on [start, s]
            F, Mo = kn.loads(curve, np.full(si.size, edges[k]), si, P, gvec)
            T[:, i], M[i] = F, Mo
            if left >= 0:
                T[:, i] += Hf[:, [left]]
                M[i] += _cross(H[:, [left]] - P, Hf[:, [left]])
    N, V = np.sum(T * tn, 0), np.sum(T * nn, 0)
    t = curve.thickness_at(s)
    with np.errstate(divide="ignore", invalid="ignore"):
        e = M / N
        margins = np.where(N > 0, (0.5 * t - np.abs(e)) / t, -np.inf)
    return SectionForces(s, N, V, M, e, t, float(np.min(margins)), residual)


def thrust_line_margin(eq: EquationOfMotion, theta: float, rate: float, accel: float, a_g: float,
                       sections: int = 200, inset: float = 1e-6) -> SectionForces:
    """:func:`section_forces` on ``sections`` uniform sections strictly inside every moving
    piece plus the sections ``inset * L`` inside each of its hinges (at a hinge itself
    ``|e| = t/2`` by construction)."""
    mech = eq.mechanism
    br = mech.breaks
    moving = np.flatnonzero(mech.moving)
    u = np.arange(1, sections + 1) / (sections + 1)
    d = inset * mech.curve.length
    hinge = lambda b: 1 <= b <= mech.n_hinges  # noqa: E731  (breaks index b is a hinge)
    s = [np.concatenate([br[p] + (br[p + 1] - br[p]) * u, [br[p] + d] if hinge(p) else [],
                         [br[p + 1] - d] if hinge(p + 1) else []]) for p in moving]
    return section_forces(eq, theta, rate, accel, a_g, np.sort(np.concatenate(s)))
