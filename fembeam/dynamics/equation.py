"""Equation of motion of a one-parameter mechanism of rigid pieces, at finite rotation.

The mechanism (:class:`~fembeam.mechanisms.Mechanism`) moves with one coordinate
``theta`` (rad, counter-clockwise): the rotation of its first moving piece about its
first hinge.  Lagrange's equation with a horizontal ground acceleration ``a_g(t) g``
(``a_g`` in g, positive along +x; its inertia load is ``-a_g g`` per unit mass)::

    Lambda(theta) theta'' + 0.5 Lambda'(theta) theta'^2 + V'(theta) + a_g(t) Q(theta) = 0

* ``Lambda = 2K / theta'^2`` (kg m^2/m): ``sum_k int |v|^2 dm`` over the
  pieces for ``theta' = 1``;
* ``V = g sum_k m_k y_Gk`` (J/m, relative to ``theta = 0``);
* ``Q = g d/dtheta sum_k m_k x_Gk`` (the work of a unit horizontal acceleration).

Four hinges C1, C13, C23, C2 make a four-bar linkage: crank I (C1-C13) turns by ``theta``
about C1, coupler III (C13-C23), rocker II (C23-C2) about C2; the angular rates
``w3 = dpsi3/dtheta``, ``w2 = dpsi2/dtheta`` and their derivatives come from the loop
closure ``B' + w3 k x (D - B) = w2 k x (D - C2)`` (``B``, ``D``: C13 and C23 moved) and its
derivative, so ``Lambda'`` is exact (no differencing).  One hinge: a single piece turning
about it (a rocking block), ``Lambda`` constant.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..errors import SolverError
from ..mechanisms import Mechanism

__all__ = ["EquationOfMotion", "GRAVITY"]

from ..units import GRAVITY   # m/s^2 (one constant: fembeam.units)


def _cross(a, b) -> float:
    return float(a[0] * b[1] - a[1] * b[0])


def _about(m: float, S: np.ndarray, J: float, C: np.ndarray) -> float:
    """Polar moment about point ``C`` from ``m``, first moment ``S`` and ``J`` about the origin."""
    return float(J - 2.0 * (C @ S) + m * (C @ C))


@dataclass(frozen=True)
class _Piece:
    m: float             # mass per metre of width (kg/m)
    G0: np.ndarray       # centroid at theta = 0 (m)
    J: float             # polar moment about the piece's reference point (see EquationOfMotion)


class EquationOfMotion:
    """Lagrange's equation of motion of a mechanism at finite rotation.

    Parameters
    ----------
    mechanism : Mechanism
        The mechanism (hinges and sides; its rate is ignored).
    g : float, optional
        Acceleration of gravity (m/s^2).

    Attributes
    ----------
    sign : {1, -1}
        The sense of ``theta`` (rad, the rotation of the first moving piece) that opens
        every hinge.

    Raises
    ------
    SolverError
        No sense of motion opens all the hinges.

    Examples
    --------
    The paper's four-hinge mechanism at rest: a ground acceleration of 0.3 g towards
    ``-x`` (below ``A_L = 0.359 g``) cannot open it, one of 0.5 g does (rad/s^2):

    >>> import fembeam
    >>> from fembeam.dynamics import EquationOfMotion
    >>> arch = fembeam.CircularArch(radius=1.0, thickness=0.15, embrace_deg=157.5)
    >>> sides = ["intrados", "extrados", "intrados", "extrados"]
    >>> mech = fembeam.Mechanism.from_angles(arch, [0.0, 52.5, 118.125, 157.5], sides)
    >>> eq = EquationOfMotion(mech)
    >>> for a_g in (-0.3, -0.5):
    ...     print(f"{a_g} g: {eq.sign * eq.acceleration(0.0, 0.0, a_g):.2f} rad/s^2")
    -0.3 g: -0.51 rad/s^2
    -0.5 g: 1.22 rad/s^2
    >>> print(f"unstable at {eq.theta_unstable:.3f} rad, V = {eq.potential(-0.01):.2f} J/m")
    unstable at 0.118 rad, V = 17.28 J/m
    """

    def __init__(self, mechanism: Mechanism, g: float = GRAVITY):
        self.mechanism = mechanism.with_alpha(1.0)
        self.g = float(g)
        self.sign = mechanism.compatible_sign()
        if self.sign == 0:
            raise SolverError("the mechanism is not compatible: no sense of motion opens all its hinges")
        br = mechanism.breaks
        moving = np.flatnonzero(mechanism.moving)
        m, S, J = mechanism.curve.segment_inertia(br[moving], br[moving + 1])
        P = mechanism.points()
        self.points0 = P
        if mechanism.n_hinges == 1:
            C = P[:, 0]
            self.pieces = (_Piece(float(m[0]), S[:, 0] / m[0], _about(m[0], S[:, 0], J[0], C)),)
            self.C = C
            p = self.pieces[0]
            self._block = (p.J, p.m, tuple(map(float, p.G0 - C)))
        else:
            C1, C13, C23, C2 = P.T
            refs = (C1, C13, C2)   # crank about C1, coupler about the material point C13, rocker about C2
            self.pieces = tuple(_Piece(float(m[i]), S[:, i] / m[i], _about(m[i], S[:, i], J[i], refs[i]))
                                for i in range(3))
            self.C1, self.C13, self.C23, self.C2 = C1, C13, C23, C2
            self.l1 = float(np.linalg.norm(C13 - C1))
            self.l2 = float(np.linalg.norm(C23 - C2))
            self.l3 = float(np.linalg.norm(C23 - C13))
            self.branch = 1.0 if _cross(C13 - C2, C23 - C2) >= 0 else -1.0
            # plain floats for the hot path
            self._c = (float(C1[0]), float(C1[1]), float(C2[0]), float(C2[1]))
            self._r = (float((C13 - C1)[0]), float((C13 - C1)[1]))
            self._k = (*map(float, C23 - C13), *map(float, C23 - C2))
            self._pc = tuple((p.m, p.J, *map(float, p.G0 - ref)) for p, ref in zip(self.pieces, refs))
            self._l1s, self._l2s, self._l3s = self.l1 ** 2, self.l2 ** 2, self.l3 ** 2
        self._one = mechanism.n_hinges == 1
        self.mass = float(sum(p.m for p in self.pieces))
        self._Y0 = self._height(0.0)
        self.theta_lock = self._lock_angle()
        self.theta_unstable = self._unstable_angle()

    # ------------------------------------------------------------------ kinematics
    def _closure(self, c: float, s: float):
        """The loop closure of the four-bar at ``theta`` (``c, s``: its cosine and sine), in plain
        floats (this runs at every stage of the integrator): ``(ax, ay, ux, uy, wx, wy, w2, w3,
        dw2, dw3)`` with ``a = B - C1``, ``u = D - B``, ``w = D - C2`` (m) and the rates
        ``w3 = dpsi3/dtheta``, ``w2 = dpsi2/dtheta`` and their derivatives; None when the loop
        cannot close (``D``: the circle of radius ``l2`` about C2 met by that of radius ``l3``
        about ``B``, on the branch of rest)."""
        c1x, c1y, c2x, c2y = self._c
        rx, ry = self._r
        l2s, l3s = self._l2s, self._l3s
        ax, ay = c * rx - s * ry, s * rx + c * ry                   # B - C1
        dx, dy = c1x + ax - c2x, c1y + ay - c2y                     # B - C2
        d2 = dx * dx + dy * dy
        d = math.sqrt(d2)
        a = (l2s - l3s + d2) / (2 * d)
        h2 = l2s - a * a
        if h2 < 0.0:
            return None
        h = self.branch * math.sqrt(h2)
        ex, ey = dx / d, dy / d
        wx, wy = a * ex - h * ey, a * ey + h * ex                   # D - C2
        ux, uy = wx - dx, wy - dy                                   # D - B
        det = ux * wy - uy * wx                                     # cross(u, w); 0 at the lock
        if abs(det) <= 1e-14 * (ux * ux + uy * uy + wx * wx + wy * wy):
            return None
        # w2 k x w - w3 k x u = B' = k x (B - C1) (Cramer's rule), and its derivative
        w2, w3 = (ay * ux - uy * ax) / det, (-wy * ax + ay * wx) / det
        qx, qy = -ax - w3 * w3 * ux + w2 * w2 * wx, -ay - w3 * w3 * uy + w2 * w2 * wy
        dw2, dw3 = (-qx * ux - uy * qy) / det, (-wy * qy - qx * wx) / det
        return ax, ay, ux, uy, wx, wy, w2, w3, dw2, dw3

    def _scalars(self, theta: float):
        """The four-bar at ``theta`` (:meth:`_closure`): ``B, D`` (tuples, m), ``psi3, psi2``
        (rad), ``w3, w2, dw3, dw2``; None when the loop cannot close."""
        k = self._closure(math.cos(theta), math.sin(theta))
        if k is None:
            return None
        ax, ay, ux, uy, wx, wy, w2, w3, dw2, dw3 = k
        c1x, c1y, c2x, c2y = self._c
        k3x, k3y, k2x, k2y = self._k
        psi3 = math.atan2(k3x * uy - k3y * ux, k3x * ux + k3y * uy)
        psi2 = math.atan2(k2x * wy - k2y * wx, k2x * wx + k2y * wy)
        return (c1x + ax, c1y + ay), (c2x + wx, c2y + wy), psi3, psi2, w3, w2, dw3, dw2

    def _linkage(self, theta: float):
        """Positions, rates and rate derivatives of the four-bar at ``theta``:
        ``B, D`` (arrays, m), ``psi3, psi2`` (rad), ``w3, w2, dw3, dw2``; None when the loop
        cannot close."""
        k = self._scalars(theta)
        return None if k is None else (np.array(k[0]), np.array(k[1]), *k[2:])

    @staticmethod
    def _rot(phi: float, v: np.ndarray) -> np.ndarray:
        c, s = math.cos(phi), math.sin(phi)
        return np.array([c * v[0] - s * v[1], s * v[0] + c * v[1]])

    def coefficients(self, theta: float) -> tuple[float, float, float, float]:
        """``(Lambda, Lambda', V', Q)`` at ``theta`` (SI units per metre of width);
        SolverError when the linkage cannot reach ``theta``.  The integrator's right-hand
        side: the loop closure of :meth:`_closure`, the rotations of coupler and rocker as
        cosines and sines (their sides keep their lengths ``l3``, ``l2``)."""
        g = self.g
        c, s = math.cos(theta), math.sin(theta)
        if self._one:
            J, m, (x0, y0) = self._block
            return J, 0.0, g * m * (c * x0 - s * y0), -g * m * (s * x0 + c * y0)
        k = self._closure(c, s)
        if k is None:
            raise SolverError(f"the four-bar linkage cannot reach theta = {theta:g} rad (locked)")
        ax, ay, ux, uy, wx, wy, w2, w3, dw2, dw3 = k
        l2s, l3s = self._l2s, self._l3s
        k3x, k3y, k2x, k2y = self._k
        c3, s3 = (k3x * ux + k3y * uy) / l3s, (k3x * uy - k3y * ux) / l3s
        c2, s2 = (k2x * wx + k2y * wy) / l2s, (k2x * wy - k2y * wx) / l2s
        (m1, J1, x1, y1), (m3, J3, x3, y3), (m2, J2, x2, y2) = self._pc
        r1x, r1y = c * x1 - s * y1, s * x1 + c * y1                 # G1 - C1
        r2x, r2y = c2 * x2 - s2 * y2, s2 * x2 + c2 * y2             # G2 - C2
        g3x, g3y = c3 * x3 - s3 * y3, s3 * x3 + c3 * y3             # G3 - B
        ag = ax * g3x + ay * g3y
        Lam = J1 + w2 * w2 * J2 + m3 * self._l1s + 2 * w3 * m3 * ag + w3 * w3 * J3
        # B' = k x a = (-ay, ax); g3' = w3 k x g3 = w3 (-g3y, g3x); d(a.g3) = B'.g3 + a.g3'
        dag = (-ay * g3x + ax * g3y) + w3 * (-ax * g3y + ay * g3x)
        dLam = 2 * w2 * dw2 * J2 + 2 * m3 * (dw3 * ag + w3 * dag) + 2 * w3 * dw3 * J3
        # velocities of the centroids for theta' = 1 (k x r = (-r_y, r_x)), weighted by mass
        vx = -m1 * r1y - m2 * w2 * r2y + m3 * (-ay - w3 * g3y)
        vy = m1 * r1x + m2 * w2 * r2x + m3 * (ax + w3 * g3x)
        return Lam, dLam, g * vy, g * vx

    def piece_rotations(self, theta: float) -> tuple[float, ...]:
        """Rotations (rad, counter-clockwise) of the moving pieces at ``theta``, left to
        right: ``(theta,)`` for one hinge, ``(theta, psi3, psi2)`` for the four-bar."""
        if self.mechanism.n_hinges == 1:
            return (float(theta),)
        k = self._scalars(theta)
        if k is None:
            raise SolverError(f"the four-bar linkage cannot reach theta = {theta:g} rad (locked)")
        return float(theta), k[2], k[3]

    def _moments(self, theta: float) -> np.ndarray:
        """``sum_k m_k G_k`` (kg m/m) at ``theta``."""
        if self.mechanism.n_hinges == 1:
            p = self.pieces[0]
            return p.m * (self.C + self._rot(theta, p.G0 - self.C))
        k = self._linkage(theta)
        if k is None:
            raise SolverError(f"the four-bar linkage cannot reach theta = {theta:g} rad (locked)")
        B, D, psi3, psi2 = k[:4]
        p1, p3, p2 = self.pieces
        return (p1.m * (self.C1 + self._rot(theta, p1.G0 - self.C1)) + p2.m * (self.C2 + self._rot(psi2, p2.G0 - self.C2))
                + p3.m * (B + self._rot(psi3, p3.G0 - self.C13)))

    def _height(self, theta: float) -> float:
        """``sum_k m_k y_Gk`` (kg m/m) at ``theta``, in plain floats."""
        c, s = math.cos(theta), math.sin(theta)
        if self._one:
            m, y = self.pieces[0].m, float(self.C[1])
            x0, y0 = self._block[2]
            return m * (y + s * x0 + c * y0)
        k = self._scalars(theta)
        if k is None:
            raise SolverError(f"the four-bar linkage cannot reach theta = {theta:g} rad (locked)")
        (m1, _, x1, y1), (m3, _, x3, y3), (m2, _, x2, y2) = self._pc
        psi3, psi2 = k[2], k[3]
        return (m1 * (self._c[1] + s * x1 + c * y1) + m2 * (self._c[3] + math.sin(psi2) * x2 + math.cos(psi2) * y2)
                + m3 * (k[0][1] + math.sin(psi3) * x3 + math.cos(psi3) * y3))

    def potential(self, theta: float) -> float:
        """``V(theta) - V(0)`` (J/m)."""
        return self.g * (self._height(theta) - self._Y0)

    def horizontal_moment(self, theta: float) -> float:
        """``sum_k m_k x_Gk`` (kg m): ``Q = g d/dtheta`` of it."""
        return float(self._moments(theta)[0])

    def energy(self, theta: float, rate: float) -> float:
        """``0.5 Lambda theta'^2 + V`` (J/m), gravity only."""
        return 0.5 * self.coefficients(theta)[0] * rate * rate + self.potential(theta)

    def acceleration(self, theta: float, rate: float, a_g: float) -> float:
        """``theta''`` (rad/s^2) for ground acceleration ``a_g`` (g)."""
        Lam, dLam, dV, Q = self.coefficients(theta)
        return -(0.5 * dLam * rate * rate + dV + a_g * Q) / Lam

    # ------------------------------------------------------------------ special angles
    def _lock_angle(self) -> float:
        """``sign * theta`` at which the four-bar locks (inf for one hinge or none before pi)."""
        if self.mechanism.n_hinges == 1:
            return math.inf
        ok = lambda x: self._linkage(self.sign * x) is not None  # noqa: E731
        grid = np.linspace(0.0, math.pi, 721)[1:]
        bad = [x for x in grid if not ok(x)]
        if not bad:
            return math.inf
        hi = bad[0]
        lo = hi - grid[0]
        for _ in range(80):
            mid = 0.5 * (lo + hi)
            lo, hi = (mid, hi) if ok(mid) else (lo, mid)
        return lo

    def _unstable_angle(self) -> float:
        """Smallest ``sign * theta > 0`` where gravity stops restoring (``V' = 0``): the
        unstable equilibrium of the mechanism; inf when the linkage locks first."""
        f = lambda x: self.sign * self.coefficients(self.sign * x)[2]  # noqa: E731
        if f(0.0) <= 0:
            raise SolverError("gravity does not restore the mechanism at rest: the arch cannot stand on it")
        top = min(self.theta_lock * (1 - 1e-9), math.pi)
        grid = np.linspace(0.0, top, 2001)[1:]
        prev = 0.0
        for x in grid:
            if f(x) <= 0:
                from scipy.optimize import brentq   # here: scipy.optimize takes 0.2 s to import

                return brentq(f, prev, x, xtol=1e-15, rtol=1e-14)
            prev = x
        return math.inf
