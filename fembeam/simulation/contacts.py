"""Contact geometry of the joints in a moved configuration, and the constraint operators.

For joint ``j`` with reference side ``a`` and other side ``b`` (:class:`~.bodies.Bodies`), corner
``c`` (0: intrados, 1: extrados: the order of :data:`~fembeam.mechanisms.hinge.EDGES`) of ``b``'s
face is at ``p_b = x_b + R(phi_b) (X_c - G0_b)`` and the corresponding corner of ``a``'s face at
``p_a = x_a + R(phi_a) (X_c - G0_a)`` (they coincide at rest); ``a``'s face has the normal
``nu_a = R(phi_a) nu0`` (into ``b``) and tangent ``tau_a = R(phi_a) tau0``, ``b``'s face
``nu_b = R(phi_b) nu0``, ``tau_b = R(phi_b) tau0``.  The two faces are segments of the joint's
depth ``h`` (m): they touch, if at all, at the two ends of their overlap, so each end ``c`` of the
joint is represented by the corner that lies on the other face:

* ``b``'s corner over ``a``'s face (``-h <= u <= EDGE_TOL h``, with ``u = +-(p_b - p_a) . tau_a``
  the offset of ``b``'s corner beyond ``a``'s, outwards: ``+`` at corner 0, ``-`` at corner 1):
  the contact point ``p_b``, the face ``a``'s: ``gap = (p_b - p_a) . nu_a``,
  ``slip = (p_b - p_a) . tau_a`` (also at a hinge, where the two corners coincide);
* ``b``'s corner beyond ``a``'s face (``u > EDGE_TOL h``, ``b`` slid outwards): ``a``'s corner
  is the end, over ``b``'s face if ``u_b = +-(p_b - p_a) . tau_b <= h`` (its distance from ``b``'s
  corner along ``b``'s face), the contact point ``p_a``, the face ``b``'s:
  ``gap = (p_b - p_a) . nu_b``, ``slip = (p_b - p_a) . tau_b`` (so an overhanging corner of ``b``
  is no pivot: ``a``'s face ends at ``p_a``);
* ``u < -h`` or ``u_b > h``: the faces no longer overlap at that end (nor, then, at the other):
  no contact, the gap :data:`OFF_FACE` and zero rows.

``gap`` (m, >= 0 open) is the distance of the contact point from the face's line and ``slip``
(m) the tangential offset of the two corners; both are continuous where ``u`` changes sign
(there ``p_b - p_a`` is normal to both faces up to the gap times their relative rotation).
The opening rate ``d gap/dt = (v_b(p) - v_a(p)) . nu`` at the contact point ``p`` along the
face's normal ``nu``, exactly (the face moves rigidly with its body), and the sliding rate
``(v_b(p) - v_a(p)) . tau``: rows of ``H`` acting on the body velocities ``(vx, vy, omega)``
(centroid velocity, m/s; angular velocity, rad/s, counter-clockwise) with coefficients
``(d_x, d_y, (p - x) x d)`` on ``b`` and their opposite on ``a``.

Every joint owns three rows of ``H``, always in this order: the opening rates of its ends 0
(intrados) and 1 (extrados) and one sliding rate, at the end given by ``contact`` (the one with
the smaller gap).  Joints are ordered along the member and consecutive joints share one body, so the Delassus
operator ``W = H M^-1 H^T`` is banded (half-bandwidth 5): it is assembled straight into LAPACK's
upper banded storage through index arrays fixed at set-up (the sparsity pattern never changes).
"""
from __future__ import annotations

import copy
from dataclasses import dataclass

import numpy as np
from scipy.linalg.blas import dsbmv

from .bodies import Bodies
from .constants import BAND, OFF_FACE

__all__ = ["Contacts", "Geometry", "OFF_FACE", "EDGE_TOL"]

EDGE_TOL = 1e-7    # relative to the depth: a corner beyond the other face's end by less is still over
                   # it (the closing tolerance of a gap; at a hinge the two corners coincide to round-off)


@dataclass
class Geometry:
    """The joints in one configuration: ``gap``, ``slip`` ``(J, 2)`` (m) and the rows of ``H``
    ``(J, 3, 2, 3)`` (joint, row, side ``a``/``b``, body DOF), ``contact`` ``(J,)`` the corner of the
    sliding row."""

    gap: np.ndarray
    slip: np.ndarray
    rows: np.ndarray
    contact: np.ndarray


class Contacts:
    """Contact operators of ``bodies``, vectorised over the joints.  Internally the two column
    blocks of a joint's rows are its reference side ``a`` (slot 0) and other side ``b`` (slot 1);
    positions and directions are complex numbers ``x + i y`` (a rotation is a product)."""

    def __init__(self, bodies: Bodies):
        b = bodies
        self.bodies = b
        n, J = b.n, b.n_joints
        self.J = J
        self.a, self.b = b.ref, b.oth
        self.sides = np.stack([b.ref, b.oth], axis=1)                    # (J, 2) body of each slot
        right_end = b.joint_s == b.nodes[-1]
        left = np.where(right_end, b.oth, b.ref)
        right = np.where(right_end, b.ref, b.oth)
        # consecutive joints share one body: the right body of j, the left body of j + 1
        self.chain = bool(J < 2 or np.all(right[:-1] == left[1:]))
        self._slot_r = np.where(right_end, 0, 1)[:-1]                    # slot of j's right body
        self._slot_l = np.where(right_end, 1, 0)[1:]                     # slot of (j + 1)'s left body
        G0 = np.hstack([b.G0, np.zeros((2, 1))])
        G0c = G0[0] + 1j * G0[1]
        X = b.corners[..., 0] + 1j * b.corners[..., 1]                    # (J, 2)
        self.r_b = X - G0c[self.b][:, None]                               # corners in b's frame
        self.r_a = X - G0c[self.a][:, None]
        self.nu0 = b.nu[:, 0] + 1j * b.nu[:, 1]
        self.tau0 = b.tau[:, 0] + 1j * b.tau[:, 1]
        # the outward sense of each end along tau0 (+1 at corner 0, -1 at corner 1) and the depth
        out = np.sign(((X[:, 0] - X[:, 1]) * self.tau0.conj()).real)
        self.outward = np.stack([out, -out], axis=1)                      # (J, 2)
        self.depth = np.asarray(b.thickness, float).copy()                # (J,) m
        self.edge = EDGE_TOL * self.depth                                  # (J,) m
        self.minv = b.inverse_mass()
        self._mi = self.minv[self.sides].reshape(J, 1, 6)                 # per slot, DOF
        # scatter of slot contributions to the bodies: each body is a side of at most two joints
        pairs = [[] for _ in range(n + 1)]
        for j in range(J):
            for k in range(2):
                pairs[self.sides[j, k]].append(2 * j + k)
        if any(len(p) > 2 for p in pairs[:-1]):
            raise ValueError("a body is a side of more than two joints")
        pad = 2 * J                                                      # index of a zero row
        self._gather = np.array([(p + [pad, pad])[:2] for p in pairs[:-1]] + [[pad, pad]], int)
        # banded storage of W: entry (i, k), i <= k, at ab[BAND + i - k, k]
        m = 3 * J
        self.m = m
        rr, cc = np.meshgrid(np.arange(3), np.arange(3), indexing="ij")
        diag_i = (3 * np.arange(J)[:, None, None] + rr).ravel()
        diag_k = (3 * np.arange(J)[:, None, None] + cc).ravel()
        off_i = (3 * np.arange(J - 1)[:, None, None] + rr).ravel()
        off_k = (3 * np.arange(1, J)[:, None, None] + cc).ravel()
        self._upper_d = diag_i <= diag_k
        self._flat_d = ((BAND + diag_i - diag_k) * m + diag_k)[self._upper_d]
        self._flat_o = (BAND + off_i - off_k) * m + off_k
        d_, k_ = np.divmod(np.arange((BAND + 1) * m), m)                 # banded slot -> (d, k)
        i_of = k_ + d_ - BAND
        self._i_of = np.clip(i_of, 0, m - 1).reshape(BAND + 1, m)
        self._valid = (i_of >= 0).reshape(BAND + 1, m)
        self._jj = np.arange(J)
        self._right_end = right_end
        self.split = False

    def split_supports(self) -> "Contacts":
        """A copy whose right springing rests on a second support body, row ``n + 1`` (the left
        one keeps row ``n``): both are kinematic (no inverse mass), so each may move at its own
        prescribed velocity.  Positions and velocities are then ``(n + 2, 3)`` and :meth:`apply_t`
        gives the impulses on the two supports in the last two rows."""
        out = copy.copy(self)
        n = self.bodies.n
        out.a = np.where(self._right_end & (self.a == n), n + 1, self.a)
        out.sides = np.stack([out.a, self.b], axis=1)
        out.minv = np.vstack([self.minv, np.zeros((1, 3))])
        out._mi = out.minv[out.sides].reshape(self.J, 1, 6)
        pairs = [[] for _ in range(n + 2)]
        for j in range(self.J):
            for k in range(2):
                pairs[out.sides[j, k]].append(2 * j + k)
        pad = 2 * self.J
        out._gather = np.array([(p + [pad, pad])[:2] for p in pairs], int)
        out.split = True
        return out

    # ------------------------------------------------------------------ geometry
    def evaluate(self, q: np.ndarray) -> Geometry:
        """Gaps, slips and the rows of ``H`` at positions ``q`` ``(n + 1, 3)`` (``x, y`` of the centroids,
        m; ``phi``, rad; last row the ground, zero)."""
        z = q[:, 0] + 1j * q[:, 1]
        e = np.exp(1j * q[:, 2])
        a, b = self.a, self.b
        za, zb, ea, eb = z[a], z[b], e[a], e[b]
        pb = zb[:, None] + eb[:, None] * self.r_b                        # corners of b (J, 2)
        pa = za[:, None] + ea[:, None] * self.r_a                        # corners of a
        d = pb - pa
        nu_a, tau_a = (ea * self.nu0)[:, None], (ea * self.tau0)[:, None]
        nu_b, tau_b = (eb * self.nu0)[:, None], (eb * self.tau0)[:, None]
        u = self.outward * (d * tau_a.conj()).real                        # b's corner beyond a's, outwards
        h = self.depth[:, None]
        over_b = u > self.edge[:, None]                                  # a's corner the end (on b's face?)
        u_b = self.outward * (d * tau_b.conj()).real                      # a's corner within b's face, inwards
        touch = np.where(over_b, u_b <= h, u >= -h)                       # the faces overlap at this end
        p = np.where(over_b, pa, pb)                                     # contact points (J, 2)
        nu = np.where(over_b, nu_b, nu_a)
        tau = np.where(over_b, tau_b, tau_a)
        gap = np.where(touch, (d * nu.conj()).real, OFF_FACE)
        slip = (d * tau.conj()).real
        contact = (gap[:, 1] < gap[:, 0]).astype(int)
        jj = self._jj
        dirs = np.stack([nu[:, 0], nu[:, 1], tau[jj, contact]], axis=1)    # (J, 3)
        dirs = dirs * np.stack([touch[:, 0], touch[:, 1], touch[jj, contact]], axis=1)   # no contact: zero rows
        pts = np.concatenate([p, p[jj, contact][:, None]], axis=1)          # (J, 3)
        J = self.J
        rows = np.empty((J, 3, 2, 3))
        rows[:, :, 1, 0], rows[:, :, 1, 1] = dirs.real, dirs.imag
        rows[:, :, 0, 0], rows[:, :, 0, 1] = -dirs.real, -dirs.imag
        rows[:, :, 1, 2] = ((pts - zb[:, None]).conj() * dirs).imag
        rows[:, :, 0, 2] = -((pts - za[:, None]).conj() * dirs).imag
        return Geometry(gap, slip, rows, contact)

    # ------------------------------------------------------------------ operators
    def apply(self, rows: np.ndarray, v: np.ndarray) -> np.ndarray:
        """``H v`` ``(3 J,)`` for body velocities (or displacements) ``v`` ``(n + 1, 3)``."""
        J = self.J
        return (rows.reshape(J, 3, 6) @ v[self.sides].reshape(J, 6, 1)).ravel()

    def apply_t(self, rows: np.ndarray, P: np.ndarray) -> np.ndarray:
        """``H^T P`` ``(n + 1, 3)`` (generalised forces or impulses on the bodies; the ground's row
        zero), or ``(n + 2, 3)`` with the impulses on the two supports (:meth:`split_supports`)."""
        J = self.J
        c = (P.reshape(J, 1, 3) @ rows.reshape(J, 3, 6)).reshape(2 * J, 3)
        c = np.vstack([c, np.zeros((1, 3))])
        g = self._gather
        out = c[g[:, 0]] + c[g[:, 1]]
        if not self.split:
            out[-1] = 0.0
        return out

    def delassus(self, rows: np.ndarray) -> np.ndarray:
        """``W = H M^-1 H^T`` in upper banded storage ``(BAND + 1, 3 J)``."""
        J = self.J
        R = rows.reshape(J, 3, 6)
        RM = R * self._mi
        D = RM @ R.transpose(0, 2, 1)
        ab = np.zeros((BAND + 1) * self.m)
        ab[self._flat_d] = D.ravel()[self._upper_d]
        if J > 1:
            jj = self._jj[:-1]
            A = rows[jj, :, self._slot_r, :] * self.minv[self.sides[jj, self._slot_r]][:, None, :]
            B = rows[jj + 1, :, self._slot_l, :]
            ab[self._flat_o] = (A @ B.transpose(0, 2, 1)).ravel()
        return ab.reshape(BAND + 1, self.m)

    def banded_matvec(self, ab: np.ndarray, x: np.ndarray) -> np.ndarray:
        """``W x`` from the upper banded storage (BLAS ``dsbmv``)."""
        return dsbmv(BAND, 1.0, ab, x)

    def restrict(self, ab: np.ndarray, keep: np.ndarray, reg: float) -> np.ndarray:
        """``W`` with the rows and columns outside ``keep`` replaced by the identity, plus ``reg`` on
        the kept diagonal (the same banded pattern for every working set)."""
        if keep.all():
            out = ab.copy()
            out[BAND] += reg
            return out
        f = keep.astype(float)
        out = ab * f[self._i_of]
        out *= f
        out[BAND] += (1.0 - f) + reg * f
        return out
