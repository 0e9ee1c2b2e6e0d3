"""Rigid curved-beam elements on a scikit-fem mesh of the mid-curve.

Each element ``e`` of a 1D mesh (``MeshLine1`` in the arc length ``s``) carries the
three fields of Appendix B as constants: the tangential and normal velocity
``(w_e, v_e)`` of its mid-curve midpoint ``P_e`` (components on ``t_e``, ``n_e``)
and its angular velocity ``omega_e`` (rad/s, counter-clockwise); inside the element
the field is the rigid motion ``vel(X) = w_e t_e + v_e n_e + omega_e k x (X - P_e)``.
Every rigid motion is therefore represented exactly and has no strain.

The strain measures (B.1)-(B.5) of such a field are measures concentrated at the
nodes (the **joints**): with ``[.]`` the jump right minus left of a node,

* ``eps_pm = [vel(X_j + y_pm n_j)] . t_j`` with ``y_+ = +t/2`` (intrados) and
  ``y_- = -t/2`` (extrados): the opening rates of the two edge fibres, i.e.
  ``[w] + y_pm [omega]`` = ``eps0 + chi y``;
* ``gamma = [vel(X_j)] . n_j``: the sliding rate.

A springing joint is the same jump against an abutment at rest. The operators are a
facet form tested with the P1 nodal functions (row ``i`` belongs to node ``i``), whose
facets are points: its rows are the point evaluations of the form (:func:`_joint_rows`,
equal to scikit-fem's facet assembly); the kinetic energy ``2K = d^T M d`` with the
exact annular-sector densities of :meth:`MidCurve.inertia_densities` is a scikit-fem
cell form on the ``MeshLine1`` of the elements.
"""
from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np
import scipy.sparse as sp
from skfem import CellBasis, ElementLineP0, Functional, MeshLine1

from ..errors import InputError, SolverError
from ..geometry import MidCurve
from .mesh import check_nodes

__all__ = ["Discretization", "discretize", "ThicknessFamily", "rigid_dofs", "dof_scaling", "block_diagonal",
           "diagonal_blocks", "NDOF"]

NDOF = 3  # (w, v, omega) per element


@dataclass(frozen=True)
class Discretization:
    """Assembled operators of a rigid-element mesh of a member (:func:`discretize`).

    A velocity field ``d`` (length ``3 n``) stores ``(w, v, omega)`` at each of the
    ``n`` DOF points (the element midpoints): velocities along the tangent and the
    normal (m/s) and the angular velocity (rad/s, counter-clockwise).

    Attributes
    ----------
    curve : MidCurve
        The member.
    mesh : skfem.MeshLine1
        The mesh, nodes at the arc lengths :attr:`nodes_s` (m).
    M : scipy.sparse.csr_matrix
        Kinetic-energy (mass) matrix, ``K = 1/2 d^T M d`` (J/m for ``d`` in m/s and
        rad/s; masses per metre of width).
    B_open : scipy.sparse.csr_matrix
        ``2 J`` rows: the opening rates (m/s) of the intrados fibre at the ``J`` joints,
        then of the extrados fibre; a joint opens where its rate is > 0.
    B_slide : scipy.sparse.csr_matrix
        ``J`` rows: the sliding rates (m/s) at the joints.
    joint_s : ndarray
        Arc lengths of the joints (m), left to right.
    frames : dict
        Arc length ``s``, position ``P``, tangent ``t`` and normal ``n`` of the DOF
        points.
    element : {"rigid", "p1"}
        Kind of element.
    intorder : int
        Gauss order of the mass form.

    Examples
    --------
    >>> import fembeam
    >>> arch = fembeam.CircularArch(radius=1.0, thickness=0.15, embrace_deg=157.5)
    >>> disc = fembeam.discretize(arch, fembeam.uniform_nodes(arch, 6))
    >>> print(disc.n_elements, "elements,", disc.n_joints, "joints, M", disc.M.shape)
    6 elements, 7 joints, M (18, 18)
    >>> print(disc.joint_angle_deg)
    [  0.    26.25  52.5   78.75 105.   131.25 157.5 ]
    """

    curve: MidCurve
    mesh: MeshLine1
    M: sp.csr_matrix
    B_open: sp.csr_matrix
    B_slide: sp.csr_matrix
    joint_s: np.ndarray
    frames: dict = field(repr=False)
    element: str = "rigid"       # "rigid" (this module) or "p1" (fembeam.fem.p1)
    intorder: int = 0            # Gauss order of the mass form (rigid elements)

    @property
    def n_elements(self) -> int:
        return self.mesh.t.shape[1]

    @property
    def n_joints(self) -> int:
        return self.joint_s.size

    @property
    def nodes_s(self) -> np.ndarray:
        return self.mesh.p[0]

    @property
    def joint_angle_deg(self) -> np.ndarray:
        return self.curve.angle_deg(self.joint_s)

    @property
    def joint_thickness(self) -> np.ndarray:
        return self.curve.thickness_at(self.joint_s)

    @property
    def B(self) -> sp.csr_matrix:
        """All constraint rows: sliding (= 0) first, then openings (>= 0)."""
        return sp.vstack([self.B_slide, self.B_open]).tocsr()

    def rigid(self, V=(0.0, 0.0), omega: float = 0.0, about=(0.0, 0.0)) -> np.ndarray:
        return rigid_dofs(self, V, omega, about)

    def load_vectors(self) -> tuple[np.ndarray, np.ndarray]:
        """``(f_x, f_y)``: ``f . d`` is the integral of rho times the x (y) velocity,
        i.e. the power of a unit horizontal (upward) acceleration field."""
        return self.M @ self.rigid(V=(1.0, 0.0)), self.M @ self.rigid(V=(0.0, 1.0))


def rigid_dofs(disc: Discretization, V=(0.0, 0.0), omega: float = 0.0, about=(0.0, 0.0)) -> np.ndarray:
    """Element DOFs of the rigid motion with velocity ``V`` at ``about`` and angular
    velocity ``omega``."""
    P, te, ne = disc.frames["P"], disc.frames["t"], disc.frames["n"]
    vx = V[0] - omega * (P[1] - about[1])
    vy = V[1] + omega * (P[0] - about[0])
    d = np.empty((P.shape[1], NDOF))
    d[:, 0] = vx * te[0] + vy * te[1]
    d[:, 1] = vx * ne[0] + vy * ne[1]
    d[:, 2] = omega
    return d.ravel()


def dof_scaling(disc: Discretization) -> sp.dia_matrix:
    """Diagonal ``D`` with ``d = D d~``: the rotation DOFs of ``d~`` are velocities
    (multiplied by the member length), so that every column of ``B D`` and ``M`` is of
    one physical dimension and the solvers see numbers independent of the units."""
    s = np.tile([1.0, 1.0, 1.0 / disc.curve.length], disc.M.shape[0] // 3)
    return sp.diags(s)


def _element_frames(curve: MidCurve, a: np.ndarray, b: np.ndarray) -> dict:
    """Frames of the elements ``[a, b]`` at their midpoints."""
    sm = 0.5 * (a + b)
    return {"s": sm, "P": curve.position(sm), "t": curve.tangent(sm), "n": curve.normal(sm)}


def _break_elements(curve: MidCurve, a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """Elements ``[a, b]`` containing one of ``curve.breaks`` (a kink, a crown of a thickness
    law, a spline knot) inside them: the densities are not smooth there and a Gauss rule
    over the element would span it; and elements holding part of a solid span (a pointed
    arch's crown wedge: :meth:`MidCurve.segment_inertia` integrates it on its own rule)."""
    br = np.asarray(getattr(curve, "breaks", ()), float)
    out = np.zeros(a.size, bool)
    if br.size:
        tol = 1e-13 * curve.length
        out |= np.any((br[None, :] > a[:, None] + tol) & (br[None, :] < b[:, None] - tol), 1)
    for lo, hi in getattr(curve, "solid_spans", ()):
        out |= (a < hi) & (b > lo)
    return np.flatnonzero(out)


def _mass_blocks(m: np.ndarray, S0: np.ndarray, J0: np.ndarray, fr: dict) -> np.ndarray:
    """The 3x3 blocks ``(n, 3, 3)`` of ``M`` from each element's mass ``m``, first moment
    ``S0`` (2, n) and polar moment ``J0`` about the origin.  About the element's midpoint
    ``P``: ``S = S0 - m P``, ``J = J0 - 2 P . S0 + m |P|^2`` and
    ``2K = m |V|^2 + 2 omega V . (k x S) + J omega^2`` with ``V = w t + v n``."""
    P, te, ne = fr["P"], fr["t"], fr["n"]
    S = S0 - m * P
    J = J0 - 2 * np.sum(P * S0, 0) + m * np.sum(P * P, 0)
    kS = np.array([-S[1], S[0]])
    blocks = np.zeros((m.size, NDOF, NDOF))
    blocks[:, 0, 0] = blocks[:, 1, 1] = m
    blocks[:, 0, 2] = blocks[:, 2, 0] = np.sum(te * kS, 0)
    blocks[:, 1, 2] = blocks[:, 2, 1] = np.sum(ne * kS, 0)
    blocks[:, 2, 2] = J
    return blocks


def diagonal_blocks(M: sp.spmatrix) -> np.ndarray:
    """The 3x3 diagonal blocks ``(n, 3, 3)`` of a block-diagonal ``M`` (inverse of
    :func:`block_diagonal`)."""
    C = M.tocoo()
    blocks = np.zeros((M.shape[0] // NDOF, NDOF, NDOF))
    blocks[C.row // NDOF, C.row % NDOF, C.col % NDOF] = C.data
    return blocks


def block_diagonal(blocks: np.ndarray) -> sp.csr_matrix:
    """The block-diagonal sparse matrix of the 3x3 ``blocks`` ``(n, 3, 3)``."""
    n = blocks.shape[0]
    dof = NDOF * np.arange(n)[:, None] + np.arange(NDOF)
    rows = np.repeat(dof, NDOF, axis=1).ravel()
    cols = np.tile(dof, NDOF).ravel()
    return sp.csr_matrix((blocks.ravel(), (rows, cols)), shape=(NDOF * n,) * 2)


def _default_order(curve: MidCurve, nodes_s: np.ndarray) -> int:
    """Gauss order of the mass form for the largest turning of an element (sampled)."""
    q = np.linspace(0.0, 1.0, 5)
    s = nodes_s[:-1, None] + np.diff(nodes_s)[:, None] * q[None, :]
    # inside a solid span (a crown wedge) the turning is that of a fan of cuts, not of the
    # mid-curve: those elements are integrated by segment_inertia
    kap = np.where(curve.admissible(s), np.abs(curve.curvature(s.ravel())).reshape(s.shape), 0.0)
    kh = float(np.max(kap.max(1) * np.diff(nodes_s)))
    if getattr(curve, "fill", None) is not None and nodes_s.size <= 101:
        return 40      # a coarse mesh of a filled arch: the columns vary faster than the ring
    if kh <= 0.03:      # fine meshes: 3 or 4 points reach round-off (measured on flat ellipses too)
        return 5 if kh <= 0.005 else 7
    return 12 if kh <= 2.0 else (24 if kh <= 4.0 else 40)


def _mass(curve: MidCurve, mesh: MeshLine1, a: np.ndarray, b: np.ndarray, fr: dict, intorder: int,
          power: int | None = None) -> np.ndarray:
    """Mass blocks ``(n, 3, 3)`` of the elements ``[a, b]`` of ``mesh`` (``power``: the terms
    in ``t`` or ``t^3`` of the densities only)."""
    # kinetic energy 2K = d^T M d: each element's mass and moments (exact annular-sector
    # densities) by the cell quadrature; an element across a break by its smooth parts
    cb = CellBasis(mesh, ElementLineP0(), intorder=intorder)
    s = np.asarray(cb.default_parameters()["x"])[0]
    mu0, mu1, mu2 = curve.inertia_densities(s) if power is None else curve.inertia_densities(s, power)
    integral = Functional(lambda w: w.f)
    m = integral.elemental(cb, f=mu0)
    S0 = np.array([integral.elemental(cb, f=mu1[0]), integral.elemental(cb, f=mu1[1])])
    J0 = integral.elemental(cb, f=mu2)
    e = _break_elements(curve, a, b)
    if e.size:
        m[e], S0[:, e], J0[e] = (curve.segment_inertia(a[e], b[e]) if power is None
                                 else curve.segment_inertia(a[e], b[e], power=power))
    pts = curve.point_inertia(a, b)       # masses at points (fembeam.geometry.asbuilt)
    if pts is not None:                   # (segment_inertia has them already on the elements e)
        w = np.ones(a.size)
        w[e] = 0.0
        m, S0, J0 = m + w * pts[0], S0 + w * pts[1], J0 + w * pts[2]
    return _mass_blocks(m, S0, J0, fr)


def _elements(curve: MidCurve, a: np.ndarray, b: np.ndarray, ends: np.ndarray, intorder: int):
    """Assemble the elements ``[a_e, b_e]`` (increasing; runs of consecutive elements,
    possibly several) with scikit-fem: the mesh of these elements, their frames, their
    mass blocks ``(n, 3, 3)`` and, on the points of the mesh, the joint rows
    ``(B_open+, B_open-, B_slide)`` as CSR matrices (rows: points, columns: the DOFs of
    these elements).  Rows are assembled at the points shared by two elements and at the
    points ``ends`` (springings against an abutment)."""
    if np.array_equal(a[1:], b[:-1]):                 # one run: the points in order
        p, i = np.append(a, b[-1]), np.arange(a.size)
        mesh = MeshLine1(p[None, :], np.array([i, i + 1]))
    else:
        p = np.unique(np.concatenate([a, b]))
        mesh = MeshLine1(p[None, :], np.array([np.searchsorted(p, a), np.searchsorted(p, b)]))
    fr = _element_frames(curve, a, b)
    blocks = _mass(curve, mesh, a, b, fr, intorder)
    return mesh, fr, blocks, _joint_rows(curve, mesh, fr, np.asarray(ends, int))


def _joint_rows(curve: MidCurve, mesh: MeshLine1, fr: dict, ends: np.ndarray) -> list[sp.csr_matrix]:
    """``(B_open+, B_open-, B_slide)`` on the points of ``mesh`` (CSR, rows: points, columns:
    the DOFs of its elements), rows at the points shared by two elements and at ``ends``.

    A joint's rows are the jump of the rigid fields across it, a measure concentrated at
    the point: the facet form ``sum_sides sign (a0 w + a1 v + a2 omega) q`` tested with the
    P1 nodal function ``q`` of the point is the evaluation of its coefficients there, so
    the rows are written directly (the same operators as scikit-fem's facet assembly of
    that form, to round-off: tested).  For the side element ``e`` of the joint at ``X``
    with normal ``n_j``, the rate of the fibre ``X + y n_j`` along ``d`` (``t_j`` for the
    openings with ``y = +-t/2``, ``n_j`` for sliding with ``y = 0``) is
    ``(t_e . d) w + (n_e . d) v + ((X + y n_j - P_e) x d) omega``, signed ``-1`` on the
    element left of the joint and ``+1`` on the right (jump right minus left)."""
    p, t = mesh.p[0], mesh.t
    n = t.shape[1]
    rowed = np.bincount(t.ravel(), minlength=p.size) == 2
    rowed[ends] = True
    el = np.tile(np.arange(n), 2)
    pt = t.ravel()                                         # each element's left, then right point
    sign = np.repeat([1.0, -1.0], n)
    keep = rowed[pt]
    el, pt, sign = el[keep], pt[keep], sign[keep]
    u, inv = np.unique(pt, return_inverse=True)            # the curve evaluated once per joint
    s = p[u]
    X, tj, nj = curve.position(s)[:, inv], curve.tangent(s)[:, inv], curve.normal(s)[:, inv]
    h = np.broadcast_to(np.asarray(curve.thickness_at(s), float), s.shape)[inv]
    P, te, ne = fr["P"][:, el], fr["t"][:, el], fr["n"][:, el]
    rows = np.repeat(pt, NDOF)
    cols = (NDOF * el[:, None] + np.arange(NDOF)).ravel()

    def rows_along(d: np.ndarray, y_sign: float) -> sp.csr_matrix:
        Q = X + 0.5 * y_sign * h * nj - P                  # fibre point - P_e
        vals = sign * np.array([te[0] * d[0] + te[1] * d[1], ne[0] * d[0] + ne[1] * d[1], Q[0] * d[1] - Q[1] * d[0]])
        return sp.csr_matrix((vals.T.ravel(), (rows, cols)), shape=(p.size, NDOF * n))

    return [rows_along(tj, +1.0), rows_along(tj, -1.0), rows_along(nj, 0.0)]


def _joint_nodes(curve: MidCurve, n_elements: int) -> tuple[list[int], np.ndarray]:
    """The nodes at the springings that are joints (against an abutment), and every joint's
    node (the interior nodes and those), in order."""
    bnd = [f for f, end in zip((0, n_elements), curve.ends) if end == "joint"]
    return bnd, np.sort(np.concatenate([np.arange(1, n_elements), np.array(bnd, dtype=int)]))


def discretize(curve: MidCurve, nodes_s: np.ndarray, intorder: int | None = None,
               like: Discretization | None = None) -> Discretization:
    """Rigid-element mesh of a member: the mass matrix and the joints' constraint rows.

    Parameters
    ----------
    curve : MidCurve
        The member.
    nodes_s : array_like
        Arc lengths of the nodes (m), strictly increasing from 0 to ``curve.length``
        (e.g. :func:`~fembeam.fem.mesh.uniform_nodes`); every node is a joint.
    intorder : int, optional
        Gauss order of the mass form (default: from the turning of the elements, see
        Notes).
    like : Discretization, optional
        A discretisation of the same curve on a mesh sharing most elements: only the
        new elements and their joints are assembled (meshes of 1500 elements or more).

    Returns
    -------
    Discretization
        ``M``, ``B_open``, ``B_slide`` and the joints.

    Raises
    ------
    InputError
        Nodes not strictly increasing, not spanning the member, or inside one of its
        :attr:`~fembeam.geometry.MidCurve.solid_spans`.

    Notes
    -----
    ``intorder`` is the Gauss order of the mass form; by default chosen from the largest
    turning ``kappa h`` of an element: 5 up to 0.005 rad, 7 up to 0.03 rad, 12 up to 2 rad
    (round-off accuracy for a single element spanning 120 degrees of a circle), 24 up to
    4 rad, 40 beyond (coarse voussoirs on strongly curved shapes, e.g. the springings of
    a flat ellipse); an element containing one of the curve's
    :attr:`~fembeam.geometry.MidCurve.breaks` gets its exact block instead.  At a kink
    (a node, when the mesh comes from :func:`~fembeam.fem.uniform_nodes`) the joint is
    the section the curve defines there: position, tangent (the bisector), normal and
    thickness at the kink; nothing else here assumes a smooth mid-curve.

    ``like``: a discretisation of the same curve on a mesh sharing most elements with
    ``nodes_s`` (e.g. the mesh before a few nodes were moved onto hinges): only the
    elements not in it and the joints next to them are assembled, the rest is copied
    (meshes of 1500 elements or more; smaller ones are assembled in full, which is quicker).
    The operators are those of the full assembly (to round-off).

    Examples
    --------
    >>> import fembeam
    >>> arch = fembeam.CircularArch(radius=1.0, thickness=0.15, embrace_deg=157.5)
    >>> disc = fembeam.discretize(arch, fembeam.uniform_nodes(arch, 12))
    >>> print(disc.n_elements, "elements:", disc.M.shape, "mass matrix,",
    ...       disc.B_open.shape, "opening rows")
    12 elements: (36, 36) mass matrix, (26, 36) opening rows
    """
    nodes_s = check_nodes(curve, nodes_s)
    if intorder is None:
        intorder = _default_order(curve, nodes_s)
    if isinstance(intorder, bool) or not isinstance(intorder, (int, np.integer)) or not 1 <= intorder <= 40:
        raise InputError(f"intorder must be an integer from 1 to 40 (Gauss order of the mass form), got {intorder!r}")
    if like is not None:
        out = _update(like, curve, nodes_s, int(intorder))
        if out is not None:
            return out
    n = nodes_s.size - 1
    bnd, joint_nodes = _joint_nodes(curve, n)
    mesh, fr, blocks, rows = _elements(curve, nodes_s[:-1], nodes_s[1:], np.array(bnd, int), intorder)
    B_open = sp.vstack([rows[0][joint_nodes], rows[1][joint_nodes]]).tocsr()
    B_slide = rows[2][joint_nodes].tocsr()
    for A in (B_open, B_slide):
        A.eliminate_zeros()
    return Discretization(curve, mesh, block_diagonal(blocks), B_open, B_slide, nodes_s[joint_nodes], fr,
                          intorder=int(intorder))


UPDATE_FRACTION = 0.125   # a local update when at most this fraction of the elements is new
UPDATE_MIN_ELEMENTS = 1500   # and the mesh has at least this many (below, the full assembly is quicker:
                             # 2.6 against 4.2 ms at 200 elements, 6.9 against 5.5 ms at 2000)


def _update(old: Discretization, curve: MidCurve, x: np.ndarray, intorder: int) -> Discretization | None:
    """:func:`discretize` on the nodes ``x`` from ``old``: the elements of ``x`` that are
    elements of ``old`` (same end nodes) keep their mass blocks and frames, the joints
    between two of them their rows (columns renumbered); the new elements and their
    neighbours are assembled as a mesh of their own (:func:`_elements`).  None when
    ``old`` is not of this curve and order, most elements are new or the mesh is small
    (``UPDATE_MIN_ELEMENTS``)."""
    if (not isinstance(old, Discretization) or old.curve is not curve or old.element != "rigid"
            or old.intorder != intorder):
        return None
    y, n = old.nodes_s, x.size - 1
    oi = np.minimum(np.searchsorted(y, x[:-1]), y.size - 2)          # old element starting at x[e]
    same = (y[oi] == x[:-1]) & (y[oi + 1] == x[1:])
    new = np.flatnonzero(~same)
    if new.size == 0:
        return old                                                         # the same mesh
    if new.size > UPDATE_FRACTION * n or n < UPDATE_MIN_ELEMENTS:
        return None
    # the new elements and their neighbours, assembled alone: rows at the joints next to new elements
    touched = np.unique(np.concatenate([new, new + 1]))                    # nodes
    win = np.unique(np.clip(np.concatenate([new - 1, new, new + 1]), 0, n - 1))
    bnd, joint_nodes = _joint_nodes(curve, n)
    pts_w = np.unique(np.concatenate([x[win], x[win + 1]]))                # the window's points
    ends_w = np.searchsorted(pts_w, x[[j for j in bnd if j in touched]])
    _, fr_w, blocks_w, rows_w = _elements(curve, x[win], x[win + 1], ends_w, intorder)
    pos = np.searchsorted(win, new)                                        # new elements in the window
    # elements: old blocks and frames, the new ones from the window
    blocks = diagonal_blocks(old.M)[oi]
    blocks[new] = blocks_w[pos]
    fr = {k: v[..., oi].copy() for k, v in old.frames.items()}
    for k in fr:
        fr[k][..., new] = fr_w[k][..., pos]
    # joints: new numbering (interior nodes and abutment joints), each either copied or assembled
    J, Jo = joint_nodes.size, old.n_joints
    old_node = np.searchsorted(y, x[joint_nodes])                          # exact where copied
    copied = ~np.isin(joint_nodes, touched)
    old_joint = np.searchsorted(np.searchsorted(y, old.joint_s), old_node)  # its index among old's joints
    new_of_old_el = np.full(y.size - 1, -1)
    new_of_old_el[oi[same]] = np.flatnonzero(same)
    w_joint = np.flatnonzero(~copied)
    w_row = np.searchsorted(pts_w, x[joint_nodes[w_joint]])

    col_of_old = (NDOF * new_of_old_el[:, None] + np.arange(NDOF)).ravel()   # old column -> new column

    def splice(A_old: sp.csr_matrix, parts: list[sp.csr_matrix]) -> sp.csr_matrix:
        """Rows of ``A_old`` (fibres x old joints) at the copied joints, in the new numbering
        (order kept: both numberings follow the arc length), plus the window's rows."""
        f = len(parts)
        A = A_old.tocsr()
        target = (np.arange(f)[:, None] * J + np.flatnonzero(copied)).ravel()
        source = (np.arange(f)[:, None] * Jo + old_joint[copied]).ravel()
        counts = np.zeros(f * J, A.indptr.dtype)
        counts[target] = np.diff(A.indptr)[source]
        S = A[source]                                  # the copied rows, in order
        kept = sp.csr_matrix((S.data, col_of_old[S.indices], np.r_[0, np.cumsum(counts)]), shape=(f * J, NDOF * n))
        W = sp.vstack([Aw[w_row] for Aw in parts]).tocoo()
        wr = (W.row // w_row.size) * J + w_joint[W.row % w_row.size]
        win_part = sp.csr_matrix((W.data, (wr, NDOF * win[W.col // NDOF] + W.col % NDOF)), shape=(f * J, NDOF * n))
        out = (kept + win_part).tocsr()
        out.eliminate_zeros()
        return out

    mesh = MeshLine1.init_tensor(x)
    return Discretization(curve, mesh, block_diagonal(blocks), splice(old.B_open, rows_w[:2]),
                          splice(old.B_slide, rows_w[2:]), x[joint_nodes], fr, intorder=intorder)


@dataclass(frozen=True)
class ThicknessFamily:
    """The discretisations of one mesh of ``curve`` with its thickness law scaled by a
    factor ``k`` (the mid-curve fixed), without assembling each: the operators are
    polynomials in ``k``.  The fibres sit at ``y = +-k h / 2``, so
    ``B_open(k) = [B_mid + k B_half; B_mid - k B_half]``, ``B_slide`` does not change; the
    densities are ``rho t`` and ``rho t^3 / 12`` terms, so ``M(k) = k M_1 + k^3 M_3``.
    ``B_mid`` and ``B_half`` come from the assembly at ``k = 1``, ``M_1`` and ``M_3`` from
    the terms in ``t`` and ``t^3`` of the densities (each to round-off: no differences).

    A curve whose sections move with its thickness
    (:attr:`~fembeam.geometry.MidCurve.polynomial_in_thickness` False: the crown joint and
    wedges of a pointed arch) is assembled at every ``k`` instead, on the nodes of
    ``nodes_s`` that are sections of the scaled curve (a node a thicker crown wedge
    swallows is left out)."""

    base: Discretization
    M1: np.ndarray | None   # entries of M_1 and M_3 in the pattern of base.M (None: assembled at every k)
    M3: np.ndarray | None
    B_mid: sp.csr_matrix | None
    B_half: sp.csr_matrix | None
    nodes: np.ndarray | None = None     # the mesh of every k (assembled at every k only)

    @classmethod
    def of(cls, curve: MidCurve, nodes_s: np.ndarray) -> "ThicknessFamily":
        if not curve.polynomial_in_thickness:
            nodes = np.asarray(nodes_s, float)
            return cls(discretize(curve, nodes), None, None, None, None, nodes)
        one = discretize(curve, nodes_s)
        a, b = one.nodes_s[:-1], one.nodes_s[1:]
        M1, M3 = (block_diagonal(_mass(curve, one.mesh, a, b, one.frames, one.intorder, p)) for p in (1, 3))
        probe = np.linspace(0.0, curve.length, 7)
        parts = zip(curve.inertia_densities(probe, 1), curve.inertia_densities(probe, 3), curve.inertia_densities(probe))
        if not (all(np.array_equal(one.M.indptr, M.indptr) and np.array_equal(one.M.indices, M.indices)
                    for M in (M1, M3))
                and all(np.allclose(p1 + p3, p, rtol=0, atol=1e-12 * np.max(np.abs(p))) for p1, p3, p in parts)):
            raise SolverError(f"thickness family: the t and t^3 terms of {type(curve).__name__}'s densities "
                              f"do not add up to its mass matrix (inertia_densities(s, power))")
        J = one.n_joints
        plus, minus = one.B_open[:J], one.B_open[J:]
        return cls(one, M1.data, M3.data, ((plus + minus) * 0.5).tocsr(), ((plus - minus) * 0.5).tocsr())

    def at(self, k: float) -> Discretization:
        """The discretisation of ``base.curve.with_thickness_scaled(k)`` on the same mesh."""
        b = self.base
        if self.M1 is None:
            curve = b.curve.with_thickness_scaled(k)
            return discretize(curve, self.nodes[curve.admissible(self.nodes)])
        B_open = sp.vstack([self.B_mid + k * self.B_half, self.B_mid - k * self.B_half]).tocsr()
        B_open.eliminate_zeros()
        M = sp.csr_matrix((k * self.M1 + k**3 * self.M3, b.M.indices, b.M.indptr), shape=b.M.shape)
        return Discretization(b.curve.with_thickness_scaled(k), b.mesh, M, B_open, b.B_slide, b.joint_s, b.frames,
                              intorder=b.intorder)
