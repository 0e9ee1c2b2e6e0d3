"""Statics of a chain of rigid elements: every joint force is affine in the redundants.

The joint forces ``g = (S_j, N+_j, N-_j)`` (shear, intrados and extrados fibre forces,
compression positive; the force on the element right of joint ``j`` is
``(N+ + N-) t_j + S n_j`` with moment ``t_j/2 (N+ - N-)`` about the mid-curve point)
balance the body forces of every element::

    B^T g = p,   B = [B_slide; B_open],   p = f_y - lambda f_x   (per unit g)

(``f_x``, ``f_y``: :meth:`Discretization.load_vectors`; ``lambda`` is the horizontal
acceleration in g, positive along +x; gravity acts along -y).  With live point loads
(:class:`~fembeam.analysis.loads.PointLoads`) ``lambda`` is instead their multiple, the load
factor: ``p = f_y + lambda f_P``, the dead loads at their values.  ``B^T`` has ``3 n``
rows and ``3 J`` columns: between two abutments ``J = n + 1`` and the chain is
statically indeterminate to degree three, with a free end ``J = n`` and determinate.
Taking the forces of the first joint as the redundants ``x``, the remaining columns
form a square block-bidiagonal matrix ``K`` (element ``e`` touches joints ``e`` and
``e + 1``), factorised once in O(N) (inverses of its 3x3 diagonal blocks and a banded
triangular solve)::

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
from scipy.linalg import get_lapack_funcs

from ..errors import InputError, SolverError
from ..fem import Discretization, dof_scaling

__all__ = ["Statics", "statics", "section_forces", "section_force_rows", "abutment_rows", "inverse3"]


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
    K: sp.coo_matrix
    prefix: tuple            # mass and first moment of the member on [0, node_i], Gauss order
    live: object = None      # PointLoads: lambda multiplies them (None: the horizontal acceleration)

    def solve(self, rhs: np.ndarray, trans: str = "N") -> np.ndarray:
        """``K^{-1} rhs`` (``K^{-T}`` with ``trans="T"``), refined once."""
        return _refined(self.lu, self.K if trans == "N" else self.K.T, rhs, trans)

    @property
    def k(self) -> int:
        return self.G_x.shape[2]

    @property
    def f_dead(self) -> np.ndarray:
        """``p`` at ``lambda = 0``: ``f_y`` (mass units: the weights per unit g)."""
        return self.disc.load_vectors()[1]

    @property
    def f_load(self) -> np.ndarray:
        """``dp / dlambda``: ``-f_x`` for the horizontal acceleration, ``f_P`` for live loads."""
        return -self.disc.load_vectors()[0] if self.live is None else self.live.vector(self.disc)

    def forces(self, x: np.ndarray, lam: float) -> np.ndarray:
        """Joint forces ``(3, J)`` (units of weight) for redundants ``x`` and load ``lam``."""
        return self.G0 + lam * self.G_lambda + self.G_x @ np.asarray(x, float).reshape(self.k)

    def particular(self, p: np.ndarray) -> np.ndarray:
        """Joint forces ``(3, J)`` with ``B^T g = p`` (generalised forces ``p`` in the units
        of ``M``-products, i.e. mass x velocity) and zero redundants, divided by ``m``."""
        D = dof_scaling(self.disc)
        sol = self.solve(D @ np.asarray(p, float) / self.mass)
        return np.concatenate([np.zeros(self.k), sol]).reshape(-1, 3).T

    def velocities(self, c: np.ndarray) -> tuple[np.ndarray, float]:
        """Element velocities ``u`` whose jumps at the joints are ``c`` (3, J) (rows: sliding
        rate ``B_slide u``, intrados and extrados opening rates ``B_open u``): ``K^T u = c`` on
        all joints but the first ``k`` rows; and the closure misfit of those rows relative to
        ``max |c|`` (zero when ``c`` is compatible, e.g. from the duals of a limit LP)."""
        disc = self.disc
        cj = np.asarray(c, float).T.ravel()                   # joint-major (S, N+, N-)
        u = dof_scaling(disc) @ self.solve(cj[self.k:], trans="T")
        got = np.concatenate([disc.B_slide @ u, disc.B_open @ u])
        want = np.concatenate([c[0], c[1], c[2]])
        return u, float(np.max(np.abs(got - want)) / max(np.max(np.abs(c)), 1e-300))

    def mechanism(self, eps: np.ndarray) -> tuple[np.ndarray, float]:
        """:meth:`velocities` of the opening rates ``eps`` (2, J) without sliding."""
        eps = np.asarray(eps, float)
        return self.velocities(np.concatenate([np.zeros((1, eps.shape[1])), eps]))


def statics(disc: Discretization, live=None) -> Statics:
    """Factorise the equilibrium operator of ``disc`` (O(N): banded LU of a block-bidiagonal
    matrix); computed once per discretisation (kept on it: the limit analysis, the
    continuum search and the impact's verification share it).  ``live``: point loads
    (:class:`~fembeam.analysis.loads.PointLoads`) whose multiple is ``lambda`` (None: the
    horizontal acceleration); the factorisation is shared."""
    st = disc.__dict__.get("_statics")
    if st is None:
        st = _statics(disc)
        object.__setattr__(disc, "_statics", st)   # a cache, not a field of the frozen dataclass
    if live is None:
        return st
    cache = disc.__dict__.setdefault("_statics_live", {})
    out = cache.get(live.key)
    if out is None:
        rhs = dof_scaling(disc).diagonal() * live.vector(disc) / st.mass
        col = _refined(st.lu, st.K, rhs, "N")
        if not np.all(np.isfinite(col)):
            raise SolverError("the equilibrium operator is numerically singular")
        Gl = np.concatenate([np.zeros(st.k), col]).reshape(-1, 3).T
        out = Statics(disc, st.mass, st.G0, Gl, st.G_x, st.lu, st.K, st.prefix, live)
        cache[live.key] = out
    return out


def _statics(disc: Discretization) -> Statics:
    J = disc.n_joints
    n3 = disc.M.shape[0]
    k = 3 * J - n3
    if k not in (0, 3):
        raise InputError(f"the member must rest on one abutment with a free end, or on two abutments "
                         f"({J} joints for {n3 // 3} elements)")
    if k == 3 and disc.joint_s[0] != 0.0:
        raise InputError("with two abutments the first joint must be the left springing")
    scale = dof_scaling(disc).diagonal()
    r, dof, val = _joint_entries(disc, scale, k // 3, J)      # K = (B D)^T without the first k rows
    K = sp.coo_matrix((val, (dof, r - k)), shape=(n3, n3))
    lu = _factorise(K.row, K.col, K.data, n3)
    fx, fy = disc.load_vectors()
    m = float(fx @ disc.rigid(V=(1.0, 0.0)))
    rhs = np.zeros((n3, k + 2), order="F")
    rhs[:, 0] = scale * fy / m
    rhs[:, 1] = -(scale * fx) / m
    r, dof, val = _joint_entries(disc, scale, 0, k // 3)     # the rows of the redundants
    np.add.at(rhs, (dof, 2 + r), -val)
    sol = _refined(lu, K, rhs, "N")
    if not np.all(np.isfinite(sol)):
        raise SolverError("the equilibrium operator is numerically singular")

    def joints(col):
        return np.concatenate([np.zeros((k,) + col.shape[1:]), col]).reshape((J, 3) + col.shape[1:])

    G0 = joints(sol[:, 0]).T
    Gl = joints(sol[:, 1]).T
    Gx = np.concatenate([np.eye(k), sol[:, 2:]]).reshape(J, 3, k).transpose(1, 0, 2)
    return Statics(disc, m, G0, Gl, Gx, lu, K, _cumulative_inertia(disc))


def _joint_entries(disc: Discretization, scale: np.ndarray, first: int, last: int):
    """Entries ``(r, dof, value)`` of ``B D`` (``D = diag(scale)``) in the rows of the joints
    ``first <= j < last``, numbered joint-major: ``r = 3 j + (0, 1, 2)`` for ``S, N+, N-``."""
    J = disc.n_joints
    rows, cols, vals = [], [], []
    for c, (A, r0) in enumerate([(disc.B_slide, 0), (disc.B_open, 0), (disc.B_open, J)]):
        A = A.tocsr()
        ptr = A.indptr[r0 + first:r0 + last + 1]                # rows r0 + j of A
        rows.append(np.repeat(3 * np.arange(first, last, dtype=A.indices.dtype) + c, np.diff(ptr)))
        cols.append(A.indices[ptr[0]:ptr[-1]])
        vals.append(A.data[ptr[0]:ptr[-1]])
    dof = np.concatenate(cols)
    return np.concatenate(rows), dof, np.concatenate(vals) * scale[dof]


class _BlockBidiagonal:
    """LU of a matrix of 3x3 blocks, nonzero on the diagonal (``A_e``) and on one
    off-diagonal (``C_e``, left or right of it): the equilibrium operator of a chain of
    rigid elements (the rows of element ``e`` touch joints ``e`` and ``e + 1``).
    ``K = diag(A) (I + N)`` with ``N = diag(A)^-1 C`` strictly block-triangular, so a solve
    is a product by the block-diagonal inverse and one banded triangular solve (LAPACK
    tbtrs): O(N), with the ``solve(rhs, trans)`` interface of SuperLU."""

    @classmethod
    def from_entries(cls, row: np.ndarray, col: np.ndarray, data: np.ndarray, n: int) -> "_BlockBidiagonal | None":
        """Factor the ``n x n`` matrix of the entries (duplicates summed), or None if its
        pattern is not block-bidiagonal."""
        if n % 3 or row.size == 0:
            return None
        nb = n // 3
        b = row // 3                       # block row
        c = col - 3 * b                    # column from the diagonal block's: -3..-1 left, 0..2, 3..5 right
        lo, hi = int(c.min()), int(c.max())
        if lo < -3 or hi > 5 or (lo < 0 and hi > 2):
            return None
        lu = cls.__new__(cls)
        lu.lower = hi < 3
        # (row, column, block) of the left and diagonal (lower) or diagonal and right blocks, duplicates summed
        at = (6 * (row - 3 * b) + c + (3 if lu.lower else 0)) * nb + b
        blocks = np.bincount(at, weights=data, minlength=6 * n).reshape(3, 6, nb)
        A, C = (blocks[:, 3:], blocks[:, :3]) if lu.lower else (blocks[:, :3], blocks[:, 3:])
        Ainv, det = inverse3(A)
        if not np.all(det != 0):
            raise SolverError("the equilibrium operator is singular (a singular 3x3 block)")
        N = np.einsum("ijb,jkb->bik", Ainv, C)
        # band storage of the unit triangular I + N (diagonal not referenced): column
        # 3 b' + j of row 3 b + i (b' = b -+ 1) at band row 3 + i - j (lower), 2 + i - j (upper)
        ab = np.zeros((nb, 3, 6))                               # its transpose is (6, n), Fortran order
        i, j = np.indices((3, 3))
        if lu.lower:
            ab[:-1, j, 3 + i - j] = N[1:]
        else:
            ab[1:, j, 2 + i - j] = N[:-1]
        lu.ab = ab.reshape(n, 6).T
        lu.Ainv = np.ascontiguousarray(Ainv.transpose(2, 0, 1))   # (block, row, column)
        lu.tbtrs, = get_lapack_funcs(("tbtrs",), (lu.ab,))
        return lu

    def solve(self, rhs: np.ndarray, trans: str = "N") -> np.ndarray:
        uplo = "L" if self.lower else "U"
        if trans == "N":
            x, info = self.tbtrs(self.ab, _block_product(self.Ainv, rhs), uplo=uplo, trans="N", diag="U")
        else:
            y, info = self.tbtrs(self.ab, rhs, uplo=uplo, trans="T", diag="U")
            x = _block_product(self.Ainv.transpose(0, 2, 1), y)
        if info != 0:
            raise SolverError(f"banded triangular solve failed (LAPACK tbtrs info {info})")
        return x


def inverse3(a: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Inverses and determinants of 3x3 matrices ``a`` (3, 3, nb), by cofactors (array
    arithmetic along the last axis: many times faster than ``np.linalg.inv`` on small
    matrices)."""
    i1, i2 = [1, 2, 0], [2, 0, 1]                          # i + 1, i + 2 (mod 3)
    r = lambda u, v: a[np.ix_(u, v)]                      # noqa: E731  r(i1, i2)[i, j] = a[i + 1, j + 2]
    cof = r(i1, i1) * r(i2, i2) - r(i1, i2) * r(i2, i1)
    det = np.sum(a[0] * cof[0], axis=0)
    with np.errstate(divide="ignore", invalid="ignore"):    # a singular block: the caller checks det
        return cof.transpose(1, 0, 2) / det, det


def _block_product(Ab: np.ndarray, x: np.ndarray) -> np.ndarray:
    """``diag(Ab) x`` for blocks ``Ab`` (nb, 3, 3) and ``x`` (3 nb,) or (3 nb, m)."""
    x = np.asarray(x, float)
    if x.ndim == 1:                        # einsum is the faster for one column, matmul for several
        return np.einsum("bij,bj->bi", Ab, x.reshape(-1, 3)).reshape(x.shape)
    return (Ab @ x.reshape(Ab.shape[0], 3, -1)).reshape(x.shape)


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
        self.n = n
        self.l, self.u = int(np.max(row - col)), int(np.max(col - row))
        ld = 2 * self.l + self.u + 1
        ab = np.zeros((n, ld))                      # its transpose: the band storage, Fortran order
        ab.ravel()[ld * col + (self.l + self.u) + row - col] = data
        ab = ab.T
        self.gbtrf, self.gbtrs = get_lapack_funcs(("gbtrf", "gbtrs"), (ab,))
        self.lu, self.piv, info = self.gbtrf(ab, self.l, self.u, overwrite_ab=1)
        if info != 0:
            raise SolverError(f"the equilibrium operator is singular (LAPACK gbtrf info {info})")

    def solve(self, rhs: np.ndarray, trans: str = "N") -> np.ndarray:
        x, info = self.gbtrs(self.lu, self.l, self.u, rhs, self.piv, trans=0 if trans == "N" else 1)
        if info != 0:
            raise SolverError(f"banded solve failed (LAPACK gbtrs info {info})")
        return x


def _factorise(row: np.ndarray, col: np.ndarray, data: np.ndarray, n: int):
    """LU of the ``n x n`` matrix of the entries: block-bidiagonal for a chain of rigid
    elements, banded when the numbering makes it banded, else SuperLU."""
    lu = _BlockBidiagonal.from_entries(row, col, data, n)
    if lu is not None:
        return lu
    d = row - col
    if d.size and np.max(d) - np.min(d) <= 16:
        return _Banded.from_entries(row, col, data, n)
    try:
        return spla.splu(sp.csc_matrix((data, (row, col)), shape=(n, n)))   # COLAMD + partial pivoting
    except RuntimeError as err:       # exactly singular: a mechanism with every joint locked
        raise SolverError(f"the equilibrium operator is singular ({err})") from None


def _refined(lu, A, rhs, trans):
    """``A^{-1} rhs`` with one step of iterative refinement: the solve is backward stable,
    but along a long chain its forward error grows like ``N eps`` even when the residual is
    at round-off; one step brings it back to a few ``eps``."""
    x = lu.solve(rhs, trans=trans)
    return x + lu.solve(rhs - A @ x, trans=trans)


def _order(disc: Discretization) -> int:
    """Gauss points per element for round-off accuracy: the integrands vary on the scale
    of the curvature radius, and the n-point rule errs by ~(kappa h)^(2n) / (2n)!."""
    h = np.diff(disc.nodes_s)
    mid = 0.5 * (disc.nodes_s[:-1] + disc.nodes_s[1:])
    # a crown wedge's fan turns fast, but segment_inertia integrates it on its own rule
    kh = float(np.max(np.where(disc.curve.admissible(mid), np.abs(disc.curve.curvature(mid)), 0.0) * h))
    if getattr(disc.curve, "fill", None) is not None and h.size <= 100:
        return 24      # a coarse mesh of a filled arch: the columns vary faster than the ring
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


def abutment_rows(st: Statics) -> tuple[np.ndarray, np.ndarray]:
    """Force ``F0`` (2, k + 2) and moment about the origin ``M0`` (k + 2) of the left abutment
    on the member, as rows acting on ``(x, lambda, 1)`` (units of weight, and weight x m)."""
    return _abutment(st)


def section_force_rows(st: Statics, s: np.ndarray) -> np.ndarray:
    """Coefficients ``C`` (3, ns, k + 2) with forces ``(S, N+, N-)`` at sections ``s``
    equal to ``C @ (x, lambda, 1)``, from the equilibrium of the part left of ``s``.

    For ``k = 0`` (free left end is not supported; the free end is on the right) the
    part left of ``s`` is loaded by the body forces and the abutment force, which is
    then itself determinate: it is taken from the joint forces of ``st``.
    """
    return _section_forces(st, s, np.eye(st.k + 2))


def section_forces(st: Statics, s: np.ndarray, x: np.ndarray, lam: float) -> np.ndarray:
    """Forces ``(3, ns)`` (``S, N+, N-``, units of weight) at sections ``s`` (m)."""
    z = np.concatenate([np.asarray(x, float).reshape(st.k), [lam, 1.0]])
    return _section_forces(st, s, z[:, None])[..., 0]


def _section_forces(st: Statics, s: np.ndarray, z: np.ndarray) -> np.ndarray:
    """Forces (3, ns, m) at sections ``s`` for the columns ``z`` (k + 2, m) of ``(x, lambda, 1)``."""
    curve, k = st.disc.curve, st.k
    s = np.atleast_1d(np.asarray(s, float))
    F0, M0 = _abutment(st)
    mu, S1 = _prefix_inertia(st, s)
    mu, S1 = mu[:, None] / st.mass, S1[:, :, None] / st.mass
    # abutment force, plus the body force (lambda, -1) per unit mass of the part left of s
    Fx = F0[0] @ z
    Fy = F0[1] @ z - mu * z[k + 1]
    M = M0 @ z - S1[0] * z[k + 1]                   # moment of (0, -1) per unit mass: -x
    if st.live is None:
        Fx = Fx + mu * z[k]
        M = M - S1[1] * z[k]                        # moment of (1, 0) per unit mass: -y
    else:                                           # live loads left of s, downward, times lambda
        W, Wx = st.live.prefix(s)
        Fy = Fy - (W / st.mass)[:, None] * z[k]
        M = M - (Wx / st.mass)[:, None] * z[k]
    t, n, X = curve.tangent(s), curve.normal(s), curve.position(s)
    h = curve.thickness_at(s)
    N = t[0][:, None] * Fx + t[1][:, None] * Fy
    Sh = n[0][:, None] * Fx + n[1][:, None] * Fy
    MX = M - (X[0][:, None] * Fy - X[1][:, None] * Fx)
    return np.array([Sh, 0.5 * N + MX / h[:, None], 0.5 * N - MX / h[:, None]])
