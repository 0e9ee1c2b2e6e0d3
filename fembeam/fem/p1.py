"""Continuous P1 curved-beam elements: the alternative to the rigid elements of :mod:`.fem`.

The fields ``(w, v, omega)`` of Appendix B are continuous and piecewise linear in the
arc length ``s``: ``d[3i:3i+3]`` are their values at node ``i``, ``w`` and ``v`` being
the components on the tangent ``t_i`` and normal ``n_i`` of that node (so rigid motions
are set by :func:`fembeam.fem.rigid_dofs` with the node frames).  Inside an element the
*intrinsic components* are interpolated, so a rigid motion (whose ``w``, ``v`` vary like
``cos``/``sin`` of the angle) is reproduced only to ``O(h^2)``.

Constraint sections ("joints", in the order of ``joint_s``, left to right):

* the left springing: a joint against the abutment at rest (opening ``w + omega y >= 0``
  at ``y = +-t/2``, sliding ``v = 0``);
* each element midpoint: the strain rates of (B.1)-(B.5),
  ``eps_pm = eps0 +- chi t/2`` with ``eps0 = w' - kappa v``, ``chi = omega'`` and
  ``gamma = v' + kappa w + omega``, integrated over the element with the one-point
  (midpoint) rule, i.e. P1 trial / P0 test functions.  A row is then the element's
  total opening (m/s), commensurate with a joint jump, and its multiplier is the
  element value of the fibre (or shear) force/impulse, as at a rigid-element joint;
* the right springing: ``-(w + omega y) >= 0``, ``-v = 0`` (jump abutment minus arch).

The kinetic energy uses the exact annular-sector densities of
:meth:`MidCurve.inertia_densities` (same as the rigid elements) on the interpolated field.
"""
from __future__ import annotations

import numpy as np
import scipy.sparse as sp
from skfem import (BilinearForm, CellBasis, ElementLineP0, ElementLineP1, ElementVector,
                   FacetBasis, MeshLine1, asm)

from ..errors import InputError
from ..geometry import MidCurve
from .mesh import check_nodes
from .rigid import NDOF, Discretization

__all__ = ["discretize_p1"]


def _node_frames(curve: MidCurve, sn: np.ndarray) -> dict:
    return {"s": sn, "P": curve.position(sn), "t": curve.tangent(sn), "n": curve.normal(sn)}


def discretize_p1(curve: MidCurve, nodes_s: np.ndarray, intorder: int = 1,
                  mass_intorder: int = 6, components: str = "intrinsic") -> Discretization:
    """Assemble ``M``, ``B_open``, ``B_slide`` for continuous P1 fields on the mesh
    with nodes ``nodes_s`` (arc lengths, m).

    ``intorder`` is the Gauss order of the strain rows (1: the midpoint rule, one row per
    element and fibre); ``mass_intorder`` that of the kinetic-energy form (P1 x P1 times
    smooth densities: order 6 is exact to round-off for elements below ~30 degrees).

    ``components`` selects what is interpolated linearly between the nodes:
    ``"intrinsic"`` (default) the components ``(w, v)`` on the local frame, or
    ``"cartesian"`` the velocity vector ``(v_x, v_y)`` (then ``w = V . t(s)``,
    ``v = V . n(s)`` and ``eps0 = V' . t``, ``gamma = V' . n + omega``): translations are
    exact and, on a circle, rigid motions have no fibre strain at the midpoints (the
    chord is parallel to the midpoint tangent); only ``gamma`` keeps an ``O(h^2)``
    residual.  The DOFs are intrinsic nodal components in both cases.
    """
    nodes_s = check_nodes(curve, nodes_s)
    if components not in ("intrinsic", "cartesian"):
        raise InputError(f"components must be 'intrinsic' or 'cartesian', got {components!r}")
    cart = components == "cartesian"
    if getattr(curve, "kinks", ()):
        raise InputError("continuous P1 fields are not defined across a kink of the mid-curve (the tangent "
                         "jumps there); use the rigid elements (fembeam.discretize)")
    if getattr(curve, "solid_spans", ()):
        raise InputError("continuous P1 fields are not defined across a crown joint and its wedges (parts "
                         "of the member with no section); use the rigid elements (fembeam.discretize)")
    if curve.point_inertia(np.array([0.0]), np.array([curve.length])) is not None:
        raise InputError("continuous P1 fields take distributed masses only; point masses need the rigid "
                         "elements (fembeam.discretize)")
    if intorder > 1:
        raise InputError("P1 strain rows use the midpoint rule (intorder=1): a higher order "
                         "would need one row per quadrature point")
    mesh = MeshLine1.init_tensor(nodes_s)
    E = ElementVector(ElementLineP1(), NDOF)

    @BilinearForm
    def mass(u, v, w):
        s = w.x[0]
        X, t, n = curve.position(s), curve.tangent(s), curve.normal(s)
        mu0, mu1, mu2 = curve.inertia_densities(s)
        Sx, Sy = mu1[0] - mu0 * X[0], mu1[1] - mu0 * X[1]        # first moment about X(s)
        J = mu2 - 2 * (X[0] * mu1[0] + X[1] * mu1[1]) + mu0 * (X[0]**2 + X[1]**2)
        if cart:
            Vu, Vv = (u[0], u[1]), (v[0], v[1])
        else:
            Vu = (u[0] * t[0] + u[1] * n[0], u[0] * t[1] + u[1] * n[1])
            Vv = (v[0] * t[0] + v[1] * n[0], v[0] * t[1] + v[1] * n[1])
        kS = (-Sy, Sx)                                            # k x S
        return (mu0 * (Vu[0] * Vv[0] + Vu[1] * Vv[1])
                + u[2] * (Vv[0] * kS[0] + Vv[1] * kS[1])
                + v[2] * (Vu[0] * kS[0] + Vu[1] * kS[1])
                + J * u[2] * v[2])

    M = asm(mass, CellBasis(mesh, E, intorder=mass_intorder))

    # interior strain rates, integrated over each element (rows: P0 test functions)
    def strain_form(kind: str, y_sign: float):
        @BilinearForm
        def form(u, v, w):
            s = w.x[0]
            y = 0.5 * y_sign * curve.thickness_at(s)
            if cart:
                t, n = curve.tangent(s), curve.normal(s)
                dV = (u.grad[0][0], u.grad[1][0])
                if kind == "slide":
                    return (dV[0] * n[0] + dV[1] * n[1] + u[2]) * v
                return (dV[0] * t[0] + dV[1] * t[1] + y * u.grad[2][0]) * v
            kap = curve.curvature(s)
            if kind == "slide":
                return (u.grad[1][0] + kap * u[0] + u[2]) * v
            return (u.grad[0][0] - kap * u[1] + y * u.grad[2][0]) * v
        return form

    trial, test = CellBasis(mesh, E, intorder=intorder), CellBasis(mesh, ElementLineP0(), intorder=intorder)

    # springing joints: jump (abutment at rest) = -(outward normal) x (end value)
    ends = [node for node, end in zip((0, mesh.p.shape[1] - 1), curve.ends) if end == "joint"]
    if ends:
        facets = np.array([np.flatnonzero(mesh.facets[0] == node)[0] for node in ends])
        fb, fb1 = FacetBasis(mesh, E, facets=facets), FacetBasis(mesh, ElementLineP1(), facets=facets)

    def end_form(kind: str, y_sign: float):
        @BilinearForm
        def form(u, v, w):
            s = w.x[0]
            if cart:
                t, n = curve.tangent(s), curve.normal(s)
                wv = (u[0] * t[0] + u[1] * t[1], u[0] * n[0] + u[1] * n[1])
            else:
                wv = (u[0], u[1])
            if kind == "slide":
                return -w.n[0] * wv[1] * v
            y = 0.5 * y_sign * curve.thickness_at(s)
            return -w.n[0] * (wv[0] + y * u[2]) * v
        return form

    left = [0] if ends and ends[0] == 0 else []
    right = [mesh.p.shape[1] - 1] if ends and ends[-1] == mesh.p.shape[1] - 1 else []

    def rows(kind: str, y_sign: float) -> sp.csr_matrix:
        inner = asm(strain_form(kind, y_sign), trial, test).tocsr()
        if not ends:
            return inner
        A = asm(end_form(kind, y_sign), fb, fb1).tocsr()   # rows indexed by node
        return sp.vstack([A[left], inner, A[right]]).tocsr()

    B_open = sp.vstack([rows("open", +1.0), rows("open", -1.0)]).tocsr()
    B_slide = rows("slide", 0.0)
    frames = _node_frames(curve, nodes_s)
    if cart:   # nodal (v_x, v_y, omega) = T (w, v, omega)
        T = _frame_rotation(frames)
        M, B_open, B_slide = (T.T @ M @ T), (B_open @ T).tocsr(), (B_slide @ T).tocsr()
    for A in (B_open, B_slide):
        A.eliminate_zeros()
    mid = 0.5 * (nodes_s[:-1] + nodes_s[1:])
    joint_s = np.concatenate([nodes_s[left], mid, nodes_s[right]])
    return Discretization(curve, mesh, M.tocsr(), B_open, B_slide, joint_s, frames, element="p1")


def _frame_rotation(frames: dict) -> sp.csr_matrix:
    """Block-diagonal ``T`` with ``(v_x, v_y, omega)_i = T_i (w, v, omega)_i``."""
    t, n = frames["t"], frames["n"]
    k = t.shape[1]
    blocks = np.zeros((k, NDOF, NDOF))
    blocks[:, 0, 0], blocks[:, 0, 1], blocks[:, 1, 0], blocks[:, 1, 1] = t[0], n[0], t[1], n[1]
    blocks[:, 2, 2] = 1.0
    return sp.block_diag(list(blocks), format="csr")


def midpoints_through(nodes_s: np.ndarray, points_s) -> np.ndarray:
    """Copy of ``nodes_s`` with, for each interior point of ``points_s``, the element
    containing it shifted (same length, or shortened next to a springing) so that its
    midpoint is exactly there: a P1 hinge sits at an element midpoint (its strain row).
    Points at the ends are left alone (the springings are joints of their own)."""
    out = np.array(nodes_s, float)
    L0, L1 = out[0], out[-1]
    tol = 1e-12 * (L1 - L0)
    for p in np.atleast_1d(points_s):
        if p <= L0 + tol or p >= L1 - tol:
            continue
        k = int(np.clip(np.searchsorted(out, p) - 1, 0, out.size - 2))
        if k == 0:
            lo, hi = L0, 2 * p - L0
        elif k == out.size - 2:
            lo, hi = 2 * p - L1, L1
        else:
            half = 0.5 * (out[k + 1] - out[k])
            lo, hi = p - half, p + half
        ok_lo = k == 0 or out[k - 1] < lo
        ok_hi = k + 2 >= out.size or hi < out[k + 2]
        if ok_lo and ok_hi:
            out[k], out[k + 1] = lo, hi
    return out
