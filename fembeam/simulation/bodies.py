"""The rigid bodies of a member and the joints between them, in the rest configuration.

A member (arch or block, :class:`~fembeam.geometry.MidCurve`) is cut by normal sections at the
nodes ``s_0 = 0 < s_1 < ... < s_n = L`` (m) into ``n`` rigid bodies: the voussoirs of a discrete
arch, or the rigid elements of a continuous one (the same cuts as ``fembeam rock`` and the impact
QP).  Each body has its exact mass ``m`` (kg/m), centroid ``G0`` (m) and polar moment
``I`` about the centroid (kg m^2/m) from :meth:`MidCurve.segment_inertia` (the
integrals of :class:`~fembeam.dynamics.equation.EquationOfMotion`).

Joints are the nodes whose section is a contact: the interior nodes (between bodies ``i - 1`` and
``i``) and the ends of kind ``"joint"`` (against the ground, fixed in the ground's frame).  A joint
has two corners, in the order of :data:`~fembeam.mechanisms.hinge.EDGES`: the intrados ``X + t/2 n``
(index 0) and the extrados ``X - t/2 n`` (index 1).
Its *reference* side is the body on its left (the ground at a springing) and its *other* side the
body on its right (the body at a springing); the reference face's normal ``nu`` points into the
other side and its tangent is the section's direction ``n``.  The ground is stored as an extra body
(index ``n``) with zero inverse mass, so that every joint has two sides.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..errors import InputError
from ..fem import uniform_nodes
from ..geometry import MidCurve
from ..mechanisms.hinge import EDGES, pivot_fractions

__all__ = ["Bodies"]


@dataclass(frozen=True)
class Bodies:
    """Rigid bodies between ``nodes`` of ``curve`` and their joints (rest configuration, SI units
    per metre of width).  Arrays over bodies have length ``n``; ``G0`` is ``(2, n)``.  Arrays over
    joints (length ``J``, ordered by arc length): ``joint_s``, ``ref``/``oth`` (body indices, ``n`` =
    the ground), ``corners`` ``(J, 2, 2)`` (joint, edge in the order of ``EDGES``, xy), ``nu`` and ``tau``
    ``(J, 2)`` (unit normal of the reference face into the other side, and its tangent), ``thickness``."""

    curve: MidCurve
    nodes: np.ndarray
    m: np.ndarray
    G0: np.ndarray
    I: np.ndarray
    joint_s: np.ndarray
    ref: np.ndarray
    oth: np.ndarray
    corners: np.ndarray
    nu: np.ndarray
    tau: np.ndarray
    thickness: np.ndarray

    @classmethod
    def from_curve(cls, curve: MidCurve, n: int | None = None, nodes=None) -> "Bodies":
        """Bodies of ``n`` equal cuts (:func:`~fembeam.fem.uniform_nodes`) or at ``nodes`` (m)."""
        if not isinstance(curve, MidCurve):
            raise InputError(f"simulate needs a member (e.g. fembeam.CircularArch), got {type(curve).__name__}")
        if nodes is None:
            nodes = uniform_nodes(curve, n)
        nodes = np.asarray(nodes, float)
        k = nodes.size - 1
        m, S, J = curve.segment_inertia(nodes[:-1], nodes[1:])
        G0 = S / m
        I_G = J - m * np.sum(G0 * G0, 0)
        idx = list(range(1, k))
        if curve.ends[0] == "joint":
            idx = [0] + idx
        if curve.ends[1] == "joint":
            idx = idx + [k]
        idx = np.array(idx, int)
        s = nodes[idx]
        X, t, nrm = curve.position(s), curve.tangent(s), curve.normal(s)
        h = np.broadcast_to(np.asarray(curve.thickness_at(s), float), s.shape).copy()
        corners = np.stack([(X + y * h * nrm).T for y in pivot_fractions(EDGES)], axis=1)   # (J, 2, 2)
        ref = np.where(idx == 0, k, idx - 1)                       # left body; the ground at s = 0
        oth = np.where(idx == k, k, idx)                           # right body; at s = L: the ground ...
        right_end = idx == k                                       # ... so there the sides swap:
        ref, oth = np.where(right_end, k, ref), np.where(right_end, k - 1, oth)
        nu = np.where(right_end[:, None], -t.T, t.T)               # into the other side
        return cls(curve, nodes, m, G0, I_G, s, ref, oth, corners, nu, nrm.T.copy(), h)

    @property
    def n(self) -> int:
        return self.m.size

    @property
    def n_joints(self) -> int:
        return self.joint_s.size

    @property
    def mass(self) -> float:
        return float(self.m.sum())

    def inverse_mass(self) -> np.ndarray:
        """``(n + 1, 3)``: ``1/m, 1/m, 1/I`` per body, zeros for the ground."""
        out = np.zeros((self.n + 1, 3))
        out[:-1, 0] = out[:-1, 1] = 1.0 / self.m
        out[:-1, 2] = 1.0 / self.I
        return out

    def rest_state(self) -> np.ndarray:
        """``(n + 1, 3)`` positions ``x, y`` (m, the centroids) and angles ``phi`` (rad, 0 at rest);
        the last row is the ground."""
        q = np.zeros((self.n + 1, 3))
        q[:-1, :2] = self.G0.T
        return q

    def outlines(self, points: int | None = None) -> list[np.ndarray]:
        """Each body's boundary in its own frame (relative to ``G0``), ``(2, k)``: the extrados
        forward, then the intrados back; ``points`` sections per body (default: 2 for a straight
        member, else enough for about 200 over the member, at least 2)."""
        n = self.n
        if points is None:
            straight = not np.any(self.curve.curvature(np.linspace(0, self.curve.length, 9)))
            points = 2 if straight else max(2, int(np.ceil(200 / n)) + 1)
        out = []
        for i in range(n):
            s = np.linspace(self.nodes[i], self.nodes[i + 1], points)
            X, nrm = self.curve.position(s), self.curve.normal(s)
            h = 0.5 * np.asarray(self.curve.thickness_at(s), float)
            poly = np.hstack([X - h * nrm, (X + h * nrm)[:, ::-1]])
            out.append(poly - self.G0[:, i:i + 1])
        return out

    def velocities_from_dofs(self, disc, d: np.ndarray) -> np.ndarray:
        """Body velocities ``(n + 1, 3)`` (``vx, vy`` of the centroid in m/s, ``omega`` in rad/s) of the
        element DOFs ``d`` of :func:`~fembeam.fem.discretize` on the same cuts (``w, v, omega`` at the
        element's mid-curve point ``P`` on its frame ``t, n``)."""
        d = np.asarray(d, float).reshape(-1, 3)
        P, te, ne = disc.frames["P"], disc.frames["t"], disc.frames["n"]
        vP = d[:, 0] * te + d[:, 1] * ne
        w = d[:, 2]
        out = np.zeros((self.n + 1, 3))
        out[:-1, 0] = vP[0] - w * (self.G0[1] - P[1])
        out[:-1, 1] = vP[1] + w * (self.G0[0] - P[0])
        out[:-1, 2] = w
        return out

    def kinetic_energy(self, v: np.ndarray) -> float:
        """``1/2 v^T M v`` (J/m) of body velocities ``(n + 1, 3)``."""
        v = v[:-1]
        return 0.5 * float(self.m @ (v[:, 0] ** 2 + v[:, 1] ** 2) + self.I @ (v[:, 2] ** 2))
