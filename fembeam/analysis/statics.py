"""Statics of a chain of rigid elements: every joint force is affine in the redundants.

The joint forces ``g = (S_j, N+_j, N-_j)`` (shear, intrados and extrados fibre forces,
compression positive; the force on the element right of joint ``j`` is
``(N+ + N-) t_j + S n_j`` with moment ``t_j/2 (N+ - N-)`` about the mid-curve point)
balance the body forces of every element::

    B^T g = p,   B = [B_slide; B_open],   p = f_y - lambda f_x   (per unit g)

(``f_x``, ``f_y``: :meth:`Discretization.load_vectors`; ``lambda`` is the horizontal
acceleration in g, positive along +x; gravity acts along -y).  ``B^T`` has ``3 n``
rows and ``3 J`` columns: between two abutments ``J = n + 1`` and the chain is
statically indeterminate to degree three, with a free end ``J = n`` and determinate.
Taking the forces of the first joint as the redundants ``x``, the remaining columns
form a square block-bidiagonal matrix ``K`` (element ``e`` touches joints ``e`` and
``e + 1``), factorised once by sparse LU in O(N)::

    g(x, lambda) = G0 + lambda G_lambda + G_x x,   G_x = [I; -K^{-1} B_red^T]

The columns of ``G_x`` span the null space of ``B^T``: the self-stress states.  The
same factorisation maps opening rates back to the element velocities of a mechanism
(``K^T u = jumps``).  Forces are normalised by the total mass ``m`` (units of its
weight) and the rotation DOFs by the member length, so that every number here is
independent of the units of length and of the density.

:func:`section_forces` gives the same forces at any section ``s`` from the equilibrium
of the part of the member left of ``s`` (prefix integrals of the body force): an
independent route used to check the joint forces and to search the continuum between
the joints.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import scipy.sparse as sp
import scipy.sparse.linalg as spla

from ..errors import InputError, SolverError
from ..fem import Discretization, dof_scaling

__all__ = ["Statics", "statics", "section_forces", "section_force_rows"]


@dataclass(frozen=True)
class Statics:
    """Affine joint forces of ``disc``: arrays ``(3, J)`` (rows ``S, N+, N-``) in units of
    the total weight ``m g``; ``G_x`` is ``(3, J, k)`` for ``k`` redundants (0 or 3)."""

    disc: Discretization
    mass: float
    G0: np.ndarray
    G_lambda: np.ndarray
    G_x: np.ndarray
    lu: object
    K: sp.csc_matrix
    prefix: tuple            # mass and first moment of the member on [0, node_i], Gauss order

    def solve(self, rhs: np.ndarray, trans: str = "N") -> np.ndarray:
        """``K^{-1} rhs`` (``K^{-T}`` with ``trans="T"``), refined once if the residual is
        above 1e-13 of the right-hand side."""
        return _refined(self.lu, self.K if trans == "N" else self.K.T, rhs, trans)

    @property
    def k(self) -> int:
        return self.G_x.shape[2]

    def forces(self, x: np.ndarray, lam: float) -> np.ndarray:
        """Joint forces ``(3, J)`` (units of weight) for redundants ``x`` and load ``lam``."""
        return self.G0 + lam * self.G_lambda + self.G_x @ np.asarray(x, float).reshape(self.k)

    def particular(self, p: np.ndarray) -> np.ndarray:
        """Joint forces ``(3, J)`` with ``B^T g = p`` (generalised forces ``p`` in the units
        of ``M``-products, i.e. mass x velocity) and zero redundants, divided by ``m``."""
        D = dof_scaling(self.disc)
        sol = self.solve(D @ np.asarray(p, float) / self.mass)
        return np.concatenate([np.zeros(self.k), sol]).reshape(-1, 3).T

    def mechanism(self, eps: np.ndarray) -> tuple[np.ndarray, float]:
        """Element velocities ``u`` whose opening rates are ``eps`` (2, J) (sliding zero),
        and the closure residual: the relative misfit of the ``k`` rows of the first joint
        (zero when ``eps`` is compatible, e.g. the duals of a limit LP)."""
        disc = self.disc
        J = disc.n_joints
        c = np.zeros((J, 3))
        c[:, 1], c[:, 2] = eps[0], eps[1]
        c = c.ravel()
        ut = self.solve(c[self.k:], trans="T")
        u = dof_scaling(disc) @ ut
        jumps = np.concatenate([disc.B_slide @ u, disc.B_open @ u])
        want = np.concatenate([np.zeros(J), eps[0], eps[1]])
        scale = max(np.max(np.abs(eps)), 1e-300)
        return u, float(np.max(np.abs(jumps - want)) / scale)


def statics(disc: Discretization) -> Statics:
    """Factorise the equilibrium operator of ``disc`` (O(N): banded LU of a block-bidiagonal
    matrix); computed once per discretisation (kept on it: the limit analysis, the
    continuum search and the impact's verification share it)."""
    st = disc.__dict__.get("_statics")
    if st is None:
        st = _statics(disc)
        object.__setattr__(disc, "_statics", st)   # a cache, not a field of the frozen dataclass
    return st


def _statics(disc: Discretization) -> Statics:
    J = disc.n_joints
    n3 = disc.M.shape[0]
    k = 3 * J - n3
    if k not in (0, 3):
        raise InputError(f"the member must rest on one abutment with a free end, or on two abutments "
                         f"({J} joints for {n3 // 3} elements)")
    if k == 3 and disc.joint_s[0] != 0.0:
        raise InputError("with two abutments the first joint must be the left springing")
    D = dof_scaling(disc)
    perm = np.arange(3 * J).reshape(3, J).T.ravel()          # joint-major rows (S, N+, N-)
    B = (sp.vstack([disc.B_slide, disc.B_open]).tocsr()[perm] @ D).tocsr()
    fx, fy = disc.load_vectors()
    m = float(fx @ disc.rigid(V=(1.0, 0.0)))
    K = B[k:].T.tocsc()
    lu = _factorise(K)
    rhs = np.column_stack([D @ fy / m, -(D @ fx) / m, -(B[:k].T.toarray())])
    sol = _refined(lu, K, rhs, "N")
    if not np.all(np.isfinite(sol)):
        raise SolverError("the equilibrium operator is numerically singular")

    def joints(col):
        return np.concatenate([np.zeros((k,) + col.shape[1:]), col]).reshape((J, 3) + col.shape[1:])

    G0 = joints(sol[:, 0]).T
    Gl = joints(sol[:, 1]).T
    Gx = np.concatenate([np.eye(k), sol[:, 2:]]).reshape(J, 3, k).transpose(1, 0, 2)
    return Statics(disc, m, G0, Gl, Gx, lu, K, _cumulative_inertia(disc))


class _Banded:
    """LU with partial pivoting of a banded matrix (LAPACK gbtrf/gbtrs), with the
    ``solve(rhs, trans)`` interface of SuperLU.  A chain numbered element by element is
    banded (element ``e`` touches joints ``e`` and ``e + 1``: bandwidths 5 and 2), so the
    factorisation costs O(N) with a small constant."""

    def __init__(self, K: sp.spmatrix):
        C = K.tocoo()
        self._factor(C.row, C.col, C.data, K.shape[0])

    @classmethod
    def from_entries(cls, row: np.ndarray, col: np.ndarray, data: np.ndarray, n: int) -> "_Banded":
        """Factor the ``n x n`` matrix of the entries (no duplicates; the bandwidths are
        those of the pattern, zeros included), without building a sparse matrix."""
        lu = cls.__new__(cls)
        lu._factor(row, col, data, n)
        return lu

    def _factor(self, row, col, data, n: int) -> None:
        from scipy.linalg import get_lapack_funcs

        self.n = n
        self.l, self.u = int(np.max(row - col)), int(np.max(col - row))
        ab = np.zeros((2 * self.l + self.u + 1, self.n))
        ab[self.l + self.u + row - col, col] = data
        self.gbtrf, self.gbtrs = get_lapack_funcs(("gbtrf", "gbtrs"), (ab,))
        self.lu, self.piv, info = self.gbtrf(ab, self.l, self.u)
        if info != 0:
            raise SolverError(f"the equilibrium operator is singular (LAPACK gbtrf info {info})")

    def solve(self, rhs: np.ndarray, trans: str = "N") -> np.ndarray:
        x, info = self.gbtrs(self.lu, self.l, self.u, rhs, self.piv, trans=0 if trans == "N" else 1)
        if info != 0:
            raise SolverError(f"banded solve failed (LAPACK gbtrs info {info})")
        return x


def _factorise(K: sp.spmatrix):
    """Banded LU when the numbering makes ``K`` banded (any chain of elements), else SuperLU."""
    C = K.tocoo()
    if C.nnz and np.max(C.row - C.col) + np.max(C.col - C.row) <= 16:
        return _Banded(K)
    try:
        return spla.splu(K.tocsc())   # COLAMD + partial pivoting
    except RuntimeError as err:       # exactly singular: a mechanism with every joint locked
        raise SolverError(f"the equilibrium operator is singular ({err})") from None


def _refined(lu, A, rhs, trans):
    x = lu.solve(rhs, trans=trans)
    r = rhs - A @ x
    if np.max(np.abs(r)) > 1e-13 * np.max(np.abs(rhs)):
        x = x + lu.solve(r, trans=trans)
    return x


def _order(disc: Discretization) -> int:
    """Gauss points per element for round-off accuracy: the integrands vary on the scale
    of the curvature radius, and the n-point rule errs by ~(kappa h)^(2n) / (2n)!."""
    h = np.diff(disc.nodes_s)
    kh = float(np.max(np.abs(disc.curve.curvature(0.5 * (disc.nodes_s[:-1] + disc.nodes_s[1:]))) * h))
    return 3 if kh < 0.02 else (5 if kh < 0.2 else (10 if kh < 1.0 else 24))


def _cumulative_inertia(disc: Discretization):
    order = _order(disc)
    m_el, S_el, _ = disc.curve.segment_inertia(disc.nodes_s[:-1], disc.nodes_s[1:], order=order)
    return np.concatenate([[0.0], np.cumsum(m_el)]), np.concatenate([np.zeros((2, 1)), np.cumsum(S_el, 1)], 1), order


def _prefix_inertia(st: "Statics", s: np.ndarray):
    """Mass and first moment (about the origin) of the member on ``[0, s]``."""
    nodes = st.disc.nodes_s
    cm, cS, order = st.prefix
    e = np.clip(np.searchsorted(nodes, s, side="right") - 1, 0, nodes.size - 2)
    m, S = cm[e].copy(), cS[:, e].copy()
    inside = s != nodes[e]
    if inside.any():
        m_p, S_p, _ = st.disc.curve.segment_inertia(nodes[e[inside]], s[inside], order=order)
        m[inside] += m_p
        S[:, inside] += S_p
    return m, S


def _abutment(st: Statics) -> tuple[np.ndarray, np.ndarray]:
    """Force ``F0`` (2, k + 2) and moment about the origin ``M0`` (k + 2) of the abutment
    on the member at ``s = 0``, per unit vector of ``(x, lambda, 1)`` (units of weight,
    and weight x m); computed once per ``st`` (kept on it)."""
    out = st.__dict__.get("_abutment")
    if out is None:
        curve, k = st.disc.curve, st.k
        g0 = np.zeros((3, k + 2))
        g0[:, :k] = st.G_x[:, 0, :]
        g0[:, k] = st.G_lambda[:, 0]
        g0[:, k + 1] = st.G0[:, 0]
        t0, n0, X0 = curve.tangent(0.0), curve.normal(0.0), curve.position(0.0)
        h0 = float(curve.thickness_at(0.0))
        F0 = np.outer(t0, g0[1] + g0[2]) + np.outer(n0, g0[0])            # (2, k+2)
        M0 = X0[0] * F0[1] - X0[1] * F0[0] + 0.5 * h0 * (g0[1] - g0[2])    # about the origin
        out = (F0, M0)
        object.__setattr__(st, "_abutment", out)   # a cache, not a field of the frozen dataclass
    return out


def section_force_rows(st: Statics, s: np.ndarray) -> np.ndarray:
    """Coefficients ``C`` (3, ns, k + 2) with forces ``(S, N+, N-)`` at sections ``s``
    equal to ``C @ (x, lambda, 1)``, from the equilibrium of the part left of ``s``.

    For ``k = 0`` (free left end is not supported; the free end is on the right) the
    part left of ``s`` is loaded by the body forces and the abutment force, which is
    then itself determinate: it is taken from the joint forces of ``st``.
    """
    curve = st.disc.curve
    s = np.atleast_1d(np.asarray(s, float))
    ns, k = s.size, st.k
    F0, M0 = _abutment(st)
    mu, S1 = _prefix_inertia(st, s)
    mu, S1 = mu / st.mass, S1 / st.mass
    F = np.repeat(F0[:, None, :], ns, 1)
    M = np.repeat(M0[None, :], ns, 0)
    # body force per unit mass (lambda, -1): lambda column and constant column
    F[0, :, k] += mu
    F[1, :, k + 1] -= mu
    M[:, k] += -S1[1]          # moment of (1, 0) per unit mass: X x (1, 0) = -y
    M[:, k + 1] += -S1[0]      # moment of (0, -1): X x (0, -1) = -x
    t, n, X = curve.tangent(s), curve.normal(s), curve.position(s)
    h = curve.thickness_at(s)
    N = t[0][:, None] * F[0] + t[1][:, None] * F[1]
    Sh = n[0][:, None] * F[0] + n[1][:, None] * F[1]
    MX = M - (X[0][:, None] * F[1] - X[1][:, None] * F[0])
    return np.array([Sh, 0.5 * N + MX / h[:, None], 0.5 * N - MX / h[:, None]])


def section_forces(st: Statics, s: np.ndarray, x: np.ndarray, lam: float) -> np.ndarray:
    """Forces ``(3, ns)`` (``S, N+, N-``, units of weight) at sections ``s`` (m)."""
    z = np.concatenate([np.asarray(x, float).reshape(st.k), [lam, 1.0]])
    return section_force_rows(st, s) @ z
