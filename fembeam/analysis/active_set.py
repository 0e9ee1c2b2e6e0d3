"""The impact QP of a chain of rigid elements through its banded dual, O(N) per iteration.

The impact projection (:mod:`~fembeam.analysis.impact`)::

    minimise 1/2 (d - d0)^T M (d - d0)  s.t.  B_slide d = 0,  B_open d >= 0

has the dual (``g``: the joint impulses, rows ``S, N+, N-`` of every joint)::

    minimise 1/2 g^T Q g + g^T B d0   s.t.  N+, N- >= 0,     Q = B M^-1 B^T,

with ``d = d0 + M^-1 B^T g`` and ``z = Q g + B d0 = B d`` the opening and sliding rates.
``M`` is block diagonal (one 3x3 block per element) and every joint touches two elements,
so, numbered joint by joint, ``Q`` is banded (bandwidth 5; summed element by element,
:func:`_chain_q`): a bound-constrained QP with a banded Hessian.  It is solved in two stages:

1. **interior point** (Mehrotra's predictor-corrector): every Newton matrix
   ``Q + diag(z/g)`` keeps the band (LAPACK band Cholesky, O(N)); about 20 iterations,
   independent of N, locate the open rows;
2. **active set** (primal-dual, a semismooth Newton method on ``min(N, z) = 0``): with the
   open rows ``O`` (impulse zero) the others are solved as equalities and
   ``O = {rows with g < z}`` (impulses and rates in the units of the problem's scale)
   until it repeats: first with ``Q`` (cheap), then with the primal-dual system
   ``[[M, -B_F^T], [-B_F, 0]]`` numbered joint, element, joint, ... (banded LU), which
   gives ``d`` and ``g`` to round-off where ``Q``'s explicit product loses digits with N.
   (The answer on ``Q`` alone, judged through ``d = d0 + M^-1 B^T g``, was measured at
   10^5 elements with a work ``g.z`` of 4e-7 of the kinetic energy: not certifiable.)

On a continuous arch the post-impact hinges are zones of many open joints; the interior
point finds them at once, where an active set alone moves a zone's end by one joint per
step.  On fine meshes (``MULTILEVEL_ELEMENTS``) the interior point runs on a chain of
the elements glued in groups (:func:`_glued`, exactly the chain of a coarser mesh), and
active-set steps carry its open rows through chains 4, 16, ... times finer down to the
mesh (:func:`_coarse_open`): a few steps per level instead of ~20 factorisations of
the whole chain.  The result is checked like any other solve (dual and primal feasibility and
complementarity to 1e-8); ``None`` means "no certified answer" (no convergence, or a
singular system, as for an arch arrested by the impact) and the caller then solves the
primal QP with an interior-point solver.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import scipy.sparse as sp
from scipy.linalg import blas, lapack

from ..errors import InputError
from ..fem import Discretization, dof_scaling
from ..fem.rigid import block_diagonal, diagonal_blocks
from .banded_ipm import interior_point
from .statics import inverse3

__all__ = ["ChainProjection", "project_chain", "MAX_STEPS"]

MAX_STEPS = 50          # active-set steps before giving up (then: the interior-point QP)
Q_STEPS = 10            # steps on Q at most: beyond ~10^6 elements its round-off moves rows at random
Q_JOINTS = 600_000      # chains with more joints take no steps on Q (its rates' round-off ~1e-3 at 10^6)
GUESS_Q_JOINTS = 200_000  # glued chains with more joints take primal-dual steps: an exact guess
RATIO = 4               # glued chains: groups RATIO times smaller from one level to the next
MULTILEVEL_ELEMENTS = 16384   # from this size the open rows are guessed on glued chains
COARSE_ELEMENTS = 1024  # pieces of the coarsest glued chain: at least this many
IPM_TOL = 1e-9          # the interior point only finds the open rows: the active set ends it
KKT_TOL = 1e-11         # relative violation of the sign conditions accepted as optimal
REFINE = 1              # refinement steps of each active-set solve


@dataclass
class ChainProjection:
    d: np.ndarray          # projected field (element DOFs)
    mu: np.ndarray         # (2, J) fibre impulses (>= 0): intrados, extrados
    lam: np.ndarray        # (J,) sliding multipliers
    open: np.ndarray       # (2, J) bool: the fibre rows left open (impulse zero)
    steps: int             # interior-point iterations plus active-set steps
    kkt: dict              # dual_infeasibility, primal_infeasibility, complementarity (relative)


class _Dual:
    """The scaled dual of ``disc``'s impact QP: ``Q`` (LAPACK lower band storage
    ``lower``, bandwidth ``bw``) and ``c``."""

    def __init__(self, disc: Discretization, d0: np.ndarray):
        J = self.J = disc.n_joints
        M = disc.M.tocsr()
        if isinstance(disc, _Glued):
            self.B, self.blocks = disc.B, disc.blocks
        else:
            self.B = _joint_major(disc)
            self.blocks = _chain_blocks(self.B, M)               # None: not a chain
        self.m = float(np.sum(M.diagonal()[0::3]))               # total mass
        self.sigma = np.sqrt(float(d0 @ (M @ d0)) / self.m)      # mean velocity of d0
        self.c = self.B @ d0 / self.sigma                         # scaled: g in m sigma, z in sigma
        self.lower = (_product_q(self.B, M, self.m) if self.blocks is None
                      else _chain_q(*self.blocks, J, self.m))
        self.bw = self.lower.shape[0] - 1
        self.fibre = np.ones(3 * J, bool)
        self.fibre[0::3] = False
        self.iterations = 0

    def rates(self, g: np.ndarray) -> np.ndarray:
        """``Q g + c`` (BLAS symmetric band product)."""
        return blas.dsbmv(self.bw, 1.0, self.lower, g, lower=1) + self.c

    @property
    def Q(self) -> sp.csr_matrix:
        """``Q`` as a sparse matrix (for inspection)."""
        n = self.lower.shape[1]
        low = sp.diags([self.lower[k, :n - k] for k in range(self.bw + 1)], -np.arange(self.bw + 1), (n, n))
        return (low + sp.triu(low.T, 1)).tocsr()

    def factor(self, open_: np.ndarray | None = None):
        """Cholesky factor (LAPACK band, lower) of ``Q`` with the ``open_`` rows and
        columns replaced by those of the identity; None if not positive definite."""
        ab = self.lower.copy(order="F")
        if open_ is not None:
            o = np.flatnonzero(open_)
            n = ab.shape[1]
            for k in range(self.bw + 1):
                ab[k, o] = 0.0                                   # column o: entries (o + k, o)
                ab[k, np.clip(o - k, 0, n - 1)[o >= k]] = 0.0    # row o: entries (o, o - k)
            ab[0, o] = 1.0
        L, info = lapack.dpbtrf(ab, lower=1, overwrite_ab=1)
        return L if info == 0 else None

    def solve(self, L, rhs: np.ndarray) -> np.ndarray | None:
        x, info = lapack.dpbtrs(L, rhs, lower=1)
        return x if info == 0 and np.all(np.isfinite(x)) else None

    def interior_point(self, tol: float | None = None, max_iter: int = 80) -> np.ndarray | None:
        """Mehrotra's predictor-corrector (:func:`.banded_ipm.interior_point`) on
        ``min 1/2 g^T Q g + c^T g, g_I >= 0`` (``I``: the fibre rows), from ``g_I = z = 1``,
        until ``|r| <= tol s`` and ``mu <= tol^2 s`` (``s = max(1, |c|)``); the Newton steps
        in :attr:`iterations`; None without convergence."""
        tol = IPM_TOL if tol is None else tol
        scale = max(1.0, float(np.max(np.abs(self.c))))
        I = np.flatnonzero(self.fibre)
        out = interior_point(self.rates, self.lower, I, self.fibre.astype(float), np.ones(I.size),
                             lambda g, r, mu: np.max(np.abs(r)) <= tol * scale and mu <= tol * tol * scale,
                             lower=True, max_iter=max_iter)
        if out is None:
            return None
        g, _, self.iterations = out
        return g


def project_chain(disc: Discretization, d0: np.ndarray, start_open: np.ndarray | None = None,
                  max_steps: int = MAX_STEPS) -> ChainProjection | None:
    """Projection of ``d0`` onto the compatible cone of ``disc``: the open rows from
    ``start_open`` (a (2, J) mask), else from the glued chains (meshes of at least
    ``MULTILEVEL_ELEMENTS`` elements; when that guess leads to no certified answer, the
    interior point is tried), else from the interior point; the active-set steps give the
    exact solution; None when there is no certified answer (module docstring)."""
    if disc.n_joints < disc.n_elements:    # no abutment: its rigid motions are free, no projection is defined
        raise InputError(f"the member must rest on one abutment with a free end, or on two abutments "
                         f"({disc.n_joints} joints for {disc.n_elements} elements)")
    P = _Dual(disc, d0)
    if start_open is not None:
        open_ = np.zeros((P.J, 3), bool)
        open_[:, 1:] = np.asarray(start_open, bool).T
        return _finish(disc, d0, P, open_.ravel(), max_steps, 0)
    if disc.n_elements >= MULTILEVEL_ELEMENTS and disc.n_joints == disc.n_elements + 1:   # joint j at node j
        guess, coarse_steps = _coarse_open(disc, d0, max_steps, blocks=P.blocks)
        out = None if guess is None else _finish(disc, d0, P, guess, max_steps, coarse_steps)
        if out is not None:
            return out                                           # else: the interior point decides
    g = P.interior_point()
    if g is None:
        return None
    return _finish(disc, d0, P, P.fibre & (g < P.rates(g)), max_steps, P.iterations)


def _finish(disc, d0, P: "_Dual", open_: np.ndarray, max_steps: int, spent: int) -> ChainProjection | None:
    """Active-set steps on ``Q`` (cheap, O(N) banded Cholesky) from the open rows ``open_``
    until they repeat, then on the primal-dual system (accurate) until they repeat there
    too; the answer if its KKT conditions hold to 1e-8 (``spent``: steps already taken)."""
    steps, optimal, used = 0, False, open_
    new = open_
    if P.J <= Q_JOINTS:
        out = _active_set(P, open_, min(Q_STEPS, max_steps), partial=True)
        if out is None:
            return None
        used, new, _, g, z, steps, optimal = out
    out = _active_set(P, used if optimal else new, max_steps - steps, _KKT(disc, d0, P))
    if out is None:
        return None
    open_, _, d, g, z, more, _ = out
    kkt = _kkt(g, z, P.fibre)
    if max(kkt.values()) > 1e-8:
        return None
    J = P.J
    gj = (g * P.m * P.sigma).reshape(J, 3).T
    return ChainProjection(d, gj[1:], gj[0], open_.reshape(J, 3).T[1:].copy(), spent + steps + more, kkt)


def _active_set(P: _Dual, open_: np.ndarray, max_steps: int, kkt_system: "_KKT | None" = None,
                partial: bool = False):
    """Active-set steps from the open rows ``open_`` (joint-major mask), on ``Q`` or, with
    ``kkt_system``, on the primal-dual system, until the open rows repeat (or cycle) or
    the solution satisfies the KKT sign conditions to ``KKT_TOL`` (rows with ``g`` and
    ``z`` both at round-off flip without changing it).  Returns ``(open rows used, next
    open rows, d (None on Q), g, z, steps, optimal)``, None when a system is singular
    (no mechanism left) or the steps run out (with ``partial``: the last step's)."""
    fibre, c = P.fibre, P.c
    seen = set()
    for step in range(1, max_steps + 1):
        if kkt_system is None:
            L = P.factor(open_=open_)                            # Q_FF, the open rows decoupled
            g = None if L is None else P.solve(L, np.where(open_, 0.0, -c))
            if g is None:
                return None
            g[open_] = 0.0
            d, z = None, P.rates(g)
        else:
            out = kkt_system.solve(open_)
            if out is None:
                return None
            d, g, z = out
        new = fibre & (g < z)
        scale = max(np.max(np.abs(g)), np.max(np.abs(z[fibre])), 1e-300)
        optimal = max(-np.min(g[fibre]), -np.min(z[fibre])) <= KKT_TOL * scale
        key = new.tobytes()
        if optimal or np.array_equal(new, open_) or key in seen:
            return open_, new, d, g, z, step, optimal
        seen.add(key)
        open_ = new
    return (open_, new, d, g, z, max_steps, False) if partial and max_steps > 0 else None


@dataclass
class _Glued:
    """The chain of ``disc`` with the elements glued in groups of ``K`` (a rigid piece
    each), as :class:`_Dual` and :class:`_KKT` read it: ``M``, the joint-major ``B`` and
    their blocks (:func:`_chain_blocks`); ``joints``: the joints of ``disc`` left between
    the pieces; ``frames``: those of each piece's first element (its DOFs'), so that a
    glued chain can be glued again."""

    M: sp.csr_matrix
    B: sp.csr_matrix
    blocks: tuple
    curve: object
    joints: np.ndarray
    frames: dict

    @property
    def n_joints(self) -> int:
        return self.joints.size

    @property
    def n_elements(self) -> int:
        return self.M.shape[0] // 3


def _glued(disc: Discretization | _Glued, d0: np.ndarray, K: int,
           blocks: tuple | None = None) -> tuple[_Glued, np.ndarray]:
    """Groups of ``K`` consecutive elements moving as rigid pieces: ``d = T q`` with ``q``
    the velocity of each group's first element (its own frame), so the pieces' operators
    are ``T^T M T`` and the rows of ``B`` at the joints between groups times ``T``, and
    the pre-impact field is ``d0``'s projection ``(T^T M T)^-1 T^T M d0`` (the same
    momentum).  Exact: the glued chain is the mesh of the group boundaries (and gluing
    a glued chain in groups of ``K'`` is gluing ``disc`` in groups of ``K K'``).  A chain
    between two abutments (``J = n + 1``); ``blocks``: ``disc``'s, if known.  Computed
    block by block: ``T`` has one 3x3 block per element."""
    n, J = disc.n_elements, disc.n_joints
    if blocks is None:
        blocks = disc.blocks if isinstance(disc, _Glued) else _chain_blocks(_joint_major(disc), disc.M.tocsr())
    b, Mb = blocks
    lead = np.arange(0, n, K)
    first = np.arange(n) // K * K
    Pm, te, ne = disc.frames["P"], disc.frames["t"], disc.frames["n"]
    r = Pm - Pm[:, first]
    rp = np.stack([-r[1], r[0]])                      # k x r: velocity per unit rotation
    tl, nl = te[:, first], ne[:, first]
    T = np.zeros((3, 3, n))                           # T[:, :, e]: element e's DOFs from its piece's
    T[0] = [np.sum(tl * te, 0), np.sum(nl * te, 0), np.sum(rp * te, 0)]
    T[1] = [np.sum(tl * ne, 0), np.sum(nl * ne, 0), np.sum(rp * ne, 0)]
    T[2, 2] = 1.0
    MT = np.einsum("ije,jke->ike", Mb, T)
    Mg = np.add.reduceat(np.einsum("jie,jke->ike", T, MT), lead, axis=2)
    p = np.add.reduceat(np.einsum("jie,je->ie", MT, d0.reshape(n, 3).T), lead, axis=1)     # T^T M d0
    last = np.minimum(lead + K, n) - 1                # a piece's last element (T = I for its first)
    bl, Tl = (np.ascontiguousarray(x[:, :, last]) for x in (b[3:], T))   # C order: einsum is slow
    bg = np.empty((6, 3, lead.size))                  # on others (fancy indexing's)
    bg[:3] = b[:3, :, lead]
    bg[3:] = np.einsum("aje,jke->ake", bl, Tl)
    kept = np.unique(np.r_[np.arange(0, J, K), J - 1])
    joints = disc.joints[kept] if isinstance(disc, _Glued) else kept
    frames = {k: disc.frames[k][:, ::K] for k in ("P", "t", "n")}
    chain = _Glued(_from_blocks(Mg, lead.size), _from_blocks(bg, kept.size), (bg, Mg), disc.curve, joints,
                   frames)
    return chain, np.einsum("ije,je->ei", inverse3(Mg)[0], p).ravel()


def _from_blocks(blocks: np.ndarray, rows: int) -> sp.csr_matrix:
    """The CSR matrix (``rows`` block rows of 3) of a chain's blocks ``blocks[:, :, e]``
    (:func:`_chain_blocks`): ``M`` (3x3 at block row and column ``e``) or the joint-major
    ``B`` (6x3: block rows ``e`` and ``e + 1``, column ``e``), through BSR storage."""
    n, h = blocks.shape[2], blocks.shape[0] // 3
    full = np.zeros((rows + 1, h, 3, 3))                   # block row j, columns j - h + 1 ... j
    for k in range(h):
        full[k:n + k, h - 1 - k] = blocks[3 * k:3 * k + 3].transpose(2, 0, 1)
    col = np.arange(rows)[:, None] - np.arange(h)[::-1]
    keep = (col >= 0) & (col < n)
    indptr = np.concatenate([[0], np.cumsum(keep.sum(1))])
    return sp.bsr_matrix((full[:rows][keep], col[keep], indptr), shape=(3 * rows, 3 * n)).tocsr()


def _prolong(open_: np.ndarray, coarse: np.ndarray, fine: np.ndarray) -> np.ndarray:
    """Open rows (joint-major mask) on the joints ``fine`` from those on ``coarse`` (a
    subset): a joint of both keeps its rows; one between two coarse joints is open in
    a fibre where both are."""
    o = open_.reshape(-1, 3)
    i = np.searchsorted(coarse, fine)
    at = coarse[np.minimum(i, coarse.size - 1)] == fine
    lo, hi = np.maximum(i - 1, 0), np.minimum(i, coarse.size - 1)
    out = np.where(at[:, None], o[np.minimum(i, coarse.size - 1)], o[lo] & o[hi])
    out[:, 0] = False
    return out.ravel()


def _coarse_open(disc: Discretization, d0: np.ndarray, max_steps: int = MAX_STEPS,
                 blocks: tuple | None = None) -> tuple[np.ndarray | None, int]:
    """The open rows of ``disc``'s projection guessed from glued chains (:func:`_glued`)
    of ``COARSE_ELEMENTS`` to ``4 COARSE_ELEMENTS`` pieces, then 4, 16, ... times finer:
    the interior point on the coarsest, active-set steps from the rows of the level
    below on the others.  Returns the guess on ``disc``'s joints (None if a level fails)
    and the steps spent (interior-point iterations and ``max_steps`` at most per level);
    ``blocks``: ``disc``'s (:func:`_chain_blocks`), if known."""
    K = 1
    while disc.n_elements // (RATIO * K) >= COARSE_ELEMENTS:
        K *= RATIO
    if K == 1:
        return None, 0                                   # too few elements for a coarser chain
    if blocks is None:
        blocks = _chain_blocks(_joint_major(disc), disc.M.tocsr())
    if blocks is None:
        return None, 0                                   # not a chain of rigid elements
    levels = [_glued(disc, d0, RATIO, blocks)]           # glued again and again: O(N) in all
    while K > RATIO:
        levels.append(_glued(*levels[-1], RATIO))
        K //= RATIO
    open_, joints, steps = None, None, 0
    for chain, q0 in levels[::-1]:                       # coarsest first
        P = _Dual(chain, q0)
        if open_ is None:
            g = P.interior_point()
            if g is None:
                return None, steps
            start = P.fibre & (g < P.rates(g))
            steps += P.iterations
        else:
            start = _prolong(open_, joints, chain.joints)
        accurate = _KKT(chain, q0, P) if P.J > GUESS_Q_JOINTS else None
        out = _active_set(P, start, max_steps, accurate, partial=True)
        if out is None:
            return None, steps
        open_, joints, steps = out[0], chain.joints, steps + out[5]
    return _prolong(open_, joints, np.arange(disc.n_joints)), steps


class _KKT:
    """The equality-constrained projection with the rows ``F`` closed, in the primal and
    the dual at once (well conditioned, unlike ``Q``): with ``D`` the DOF scaling,
    ``[[Ms, -Bs_F^T], [-Bs_F, 0]] [d~; g~] = [Ms d0~; 0]``, ``Ms = D M D / m``,
    ``Bs = B D``; numbered joint, element, joint, ... it is banded (banded LU, O(N))."""

    def __init__(self, disc: Discretization, d0: np.ndarray, P: "_Dual"):
        self.D = dof_scaling(disc)
        s = self.D.diagonal()
        self.P, self.J, n = P, disc.n_joints, disc.M.shape[0]
        self.Ms = _scaled(disc.M.tocsr(), s, s / P.m)
        self.Bs = _scaled(P.B, s)
        self.d0 = d0 / (s * P.sigma)
        self.rhs = np.concatenate([self.Ms @ self.d0, np.zeros(3 * self.J)])
        # numbering: joint j rows at 6 j + (0, 1, 2), element e DOFs at 6 e + 3 + (0, 1, 2)
        self.perm = np.concatenate([6 * np.arange(n // 3)[:, None] + 3 + np.arange(3),
                                    6 * np.arange(self.J)[:, None] + np.arange(3)], axis=None)
        self.n = n
        # the matrix with every row closed and a zero diagonal in the joint rows is put in
        # band storage by each solve (one band array in memory): a chain's from its blocks
        # (scaled: -Bs, Ms), any other from its entries' positions in the band
        self.N, self.chain, self.entries = n + 3 * self.J, None, None
        if P.blocks is not None:
            (b, Mb), se = P.blocks, s.reshape(-1, 3).T          # se[j, e]: scale of element e's DOF j
            self.chain, self.l, self.u = (-b * se, Mb * se[:, None] * se / P.m), 5, 5
        else:
            Mc, Bc = self.Ms.tocoo(), self.Bs.tocoo()
            row = self.perm[np.concatenate([Mc.row, Bc.col, n + Bc.row])]
            col = self.perm[np.concatenate([Mc.col, n + Bc.row, Bc.col])]
            self.l, self.u = int(max(np.max(row - col), 0)), int(max(np.max(col - row), 0))
            self.entries = (self.l + self.u + row - col + (2 * self.l + self.u + 1) * col,   # flat positions
                            np.concatenate([Mc.data, -Bc.data, -Bc.data]))

    def band(self) -> np.ndarray:
        """The matrix with every row closed (zero diagonal in the joint rows) in LAPACK
        gbtrf band storage (Fortran order)."""
        if self.chain is not None:
            return _chain_kkt_band(*self.chain, self.N)
        ab = np.zeros((2 * self.l + self.u + 1, self.N), order="F")
        ab.reshape(-1, order="F")[self.entries[0]] = self.entries[1]
        return ab

    def solve(self, open_: np.ndarray):
        ab, l, u = self.band(), self.l, self.u
        rows = self.perm[self.n + np.flatnonzero(open_)]        # open rows: B's entries and the
        ab[:, rows] = 0.0                                        # diagonal in their columns and rows,
        for k in range(-u, l + 1):                               # then a diagonal 1
            c = rows - k
            ab[l + u + k, c[(c >= 0) & (c < ab.shape[1])]] = 0.0
        ab[l + u, rows] = 1.0
        lu, piv, info = lapack.dgbtrf(ab, l, u, overwrite_ab=1)
        if info != 0:                                            # singular: no mechanism left
            return None
        keep, p = (~open_).astype(float), self.perm

        def lu_solve(r):
            return lapack.dgbtrs(lu, l, u, _permute(r, p), piv)[0][p]

        def residual(x):
            dt, g = x[:self.n], x[self.n:]
            return self.rhs - np.concatenate([self.Ms @ dt - self.Bs.T @ (keep * g), -keep * (self.Bs @ dt) + open_ * g])

        x = lu_solve(self.rhs)
        for _ in range(REFINE):                                  # iterative refinement
            x += lu_solve(residual(x))
        if not np.all(np.isfinite(x)):
            return None
        dt, g = x[:self.n], x[self.n:]
        g[open_] = 0.0
        return self.D @ dt * self.P.sigma, g, self.Bs @ dt


def _kkt(g: np.ndarray, z: np.ndarray, fibre: np.ndarray) -> dict:
    """Relative KKT figures of impulses ``g`` and rates ``z`` (fibre rows: ``g, z >= 0``,
    ``g z = 0``; sliding rows: ``z = 0``)."""
    scale = max(np.max(np.abs(g)), np.max(np.abs(z[fibre])), 1e-300)
    return {"dual_infeasibility": float(max(0.0, -np.min(g[fibre])) / scale),
            "primal_infeasibility": float(max(0.0, -np.min(z[fibre]), np.max(np.abs(z[~fibre]))) / scale),
            "complementarity": float(np.max(np.abs(g[fibre] * z[fibre])) / scale**2)}


def _permute(v: np.ndarray, p: np.ndarray) -> np.ndarray:
    """``w`` with ``w[p[i]] = v[i]``."""
    w = np.empty_like(v)
    w[p] = v
    return w


def _block_inverse(M: sp.csr_matrix) -> sp.csr_matrix:
    """Inverse of a block-diagonal matrix of 3x3 blocks."""
    return block_diagonal(inverse3(diagonal_blocks(M).transpose(1, 2, 0))[0].transpose(2, 0, 1))


def _joint_major(disc: Discretization) -> sp.csr_matrix:
    """``B`` with the rows ``S, N+, N-`` of every joint together (banded for a chain)."""
    J = disc.n_joints
    return sp.vstack([disc.B_slide, disc.B_open]).tocsr()[np.arange(3 * J).reshape(3, J).T.ravel()]


def _chain_blocks(B: sp.csr_matrix, M: sp.csr_matrix) -> tuple[np.ndarray, np.ndarray] | None:
    """``(b, Mb)``: the columns of every element ``e`` in ``B`` (joint-major rows) as a
    6x3 block ``b[:, :, e]`` (the rows of joints ``e`` and ``e + 1``) and ``M``'s 3x3
    diagonal blocks ``Mb[:, :, e]`` (element index last: array arithmetic runs along it);
    None when the pattern is not a chain's (element ``e`` touching joints ``e`` and
    ``e + 1`` only, ``J = n`` or ``n + 1``; ``M`` block diagonal; no duplicate entries)."""
    n = M.shape[0] // 3
    Br, Mr = (np.repeat(np.arange(A.shape[0], dtype=A.indices.dtype), np.diff(A.indptr)) for A in (B, M))
    e = B.indices // 3                                           # element of every entry of B
    r = Br - 3 * e                                               # its row in the element's block
    if (B.shape[0] // 3 - n not in (0, 1) or B.nnz == 0 or not (B.has_canonical_format and M.has_canonical_format)
            or r.min() < 0 or r.max() > 5 or np.any(M.indices // 3 != Mr // 3)):
        return None
    b = np.zeros((n, 6, 3))
    b.reshape(-1)[3 * Br + B.indices + 6 * e] = B.data           # b[e, r, i] = B[3 e + r, 3 e + i]
    Mb = np.zeros((n, 3, 3))
    Mb.reshape(-1)[3 * Mr + M.indices % 3] = M.data
    return b.transpose(1, 2, 0).copy(), Mb.transpose(1, 2, 0).copy()


def _chain_q(b: np.ndarray, Mb: np.ndarray, J: int, m: float) -> np.ndarray:
    """``m B M^-1 B^T`` of a chain (blocks of :func:`_chain_blocks`) summed element by
    element (block tridiagonal, 3x3 blocks joint by joint) in LAPACK lower band storage
    (``(6, 3 J)``, Fortran order)."""
    n = b.shape[2]
    W = np.einsum("aie,ije->aje", b, inverse3(Mb)[0] * m)          # b M^-1, then times b^T:
    strip = np.zeros((6, 3, n + 1))                              # strip[r, c, j] = Q[3 j + r, 3 j + c]
    strip[:, :, :n] = np.einsum("aje,bje->abe", W, b[:3])        # element e at joint e and (e + 1, e)
    strip[:3, :, 1:] += np.einsum("aje,bje->abe", W[3:], b[3:])  # element e at joint e + 1
    band = np.zeros((J, 3, 6))                                   # band[j, c, k] = Q[3 j + c + k, 3 j + c]
    for c in range(3):
        band[:, c, :6 - c] = strip[c:, c, :J].T
    return band.reshape(3 * J, 6).T[:min(6, 3 * J)]


def _product_q(B: sp.csr_matrix, M: sp.csr_matrix, m: float) -> np.ndarray:
    """``m B M^-1 B^T`` by sparse products (any pattern) in LAPACK lower band storage
    (Fortran order, the bandwidth of the pattern)."""
    Q = (B @ _block_inverse(M) @ B.T).tocoo() * m
    low = Q.row >= Q.col
    lower = np.zeros((int(np.max(Q.row - Q.col)) + 1, Q.shape[0]), order="F")
    lower[Q.row[low] - Q.col[low], Q.col[low]] = Q.data[low]
    return lower


def _scaled(A: sp.csr_matrix, right: np.ndarray, left: np.ndarray | None = None) -> sp.csr_matrix:
    """``diag(left) A diag(right)`` (same pattern)."""
    A = A.copy()
    A.data *= right[A.indices]
    if left is not None:
        A.data *= np.repeat(left, np.diff(A.indptr))
    return A


def _chain_kkt_band(nbs: np.ndarray, Ms: np.ndarray, N: int) -> np.ndarray:
    """:meth:`_KKT.band` of a chain from its scaled blocks ``-bs`` (``nbs``, 6x3 per
    element, :func:`_chain_blocks`) and ``Ms`` (bandwidths 5 and 5; ``T[q, t, k]`` is
    band row ``k`` of column ``6 q + t``): column ``6 e + 3 + j`` (element ``e``) holds
    ``-bs[:3, j, e], Ms[:, j, e], -bs[3:, j, e]`` in band rows ``7 - j ... 15 - j``,
    column ``6 q + a`` (joint ``q``) ``-bs[3 + a, :, q - 1]`` above the diagonal (band
    row 10) and ``-bs[a, :, q]`` below."""
    n = nbs.shape[2]
    T = np.zeros((n + 1, 6, 16))
    for j in range(3):
        T[:n, 3 + j, 7 - j:10 - j] = nbs[:3, j].T
        T[:n, 3 + j, 10 - j:13 - j] = Ms[:, j].T
        T[:n, 3 + j, 13 - j:16 - j] = nbs[3:, j].T
        T[1:, j, 7 - j:10 - j] = nbs[3 + j].T
        T[:n, j, 13 - j:16 - j] = nbs[j].T
    return T.reshape(-1, 16)[:N].T
