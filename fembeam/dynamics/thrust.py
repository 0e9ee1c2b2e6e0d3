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
:func:`section_forces_many` does the same at many instants of one mechanism at once (the
sections' integrals computed once, the pieces' equilibrium solved for all instants together).

**Impulses at an impact** (:func:`impact_impulses`): in the undeformed shape every material
point's velocity jumps from ``v-`` (the mechanism before, closing) to ``v+`` (the mechanism
after, opening); the percussions are the forces above with the body force replaced by the
body impulse ``-(v+ - v-)`` per unit mass and the hinges those of the mechanism after.  The 3 x 3
balances of its pieces are consistent (8 unknowns) exactly when the rate after is the impact
model's ``alpha' = (Gamma / Lambda') alpha`` (the impulse does no work on the mechanism after).
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..errors import InputError
from .equation import EquationOfMotion

__all__ = ["SectionForces", "section_forces", "section_forces_many", "thrust_line_margin", "uniform_sections",
           "impact_impulses", "friction_ratio"]


@dataclass(frozen=True)
class SectionForces:
    """Internal forces at the sections ``s`` (m) of a moving mechanism (per metre of width).

    ``N`` (N/m, compression > 0), ``V`` (N/m, along the moved normal), ``M`` (N m/m, about the
    section's mid point), ``eccentricity = M / N`` (m, + towards the intrados),
    ``thickness`` (m); ``margin = min (t/2 - |e|) / t`` over the sections (< 0: the thrust
    line leaves the section somewhere; a section with ``N <= 0`` counts as ``-inf``);
    ``residual``: relative residual of the equilibrium equations of the pieces (~1e-12
    when ``theta''`` satisfies the equation of motion).  From :func:`section_forces_many`
    the forces are arrays (instants, sections) and ``margin``, ``residual`` one per instant;
    from :func:`impact_impulses` they are percussions (N s/m)."""

    s: np.ndarray
    N: np.ndarray
    V: np.ndarray
    M: np.ndarray
    eccentricity: np.ndarray
    thickness: np.ndarray
    margin: float
    residual: float


def _cross(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """z component of ``a x b`` over axis 0 (2-vectors) or, for ``(n, 2, k)`` stacks, axis 1."""
    if a.ndim == 3 or b.ndim == 3:
        return a[:, 0] * b[:, 1] - a[:, 1] * b[:, 0]
    return a[0] * b[1] - a[1] * b[0]


def _rot(phi, v: np.ndarray) -> np.ndarray:
    """``v`` (2, k) turned by the angles ``phi`` (n,): (n, 2, k)."""
    c, s = np.cos(phi)[:, None], np.sin(phi)[:, None]
    return np.stack([c * v[0] - s * v[1], s * v[0] + c * v[1]], axis=1)


@dataclass(frozen=True)
class _Kinematics:
    """One moving piece at ``n`` instants: material point ``X0`` (2,) moved to ``A`` (n, 2)
    (acceleration ``aA``), turned by ``phi`` (n,) with angular velocity ``omega`` and
    acceleration ``alpha`` (n,)."""

    X0: np.ndarray
    A: np.ndarray
    aA: np.ndarray
    phi: np.ndarray
    omega: np.ndarray
    alpha: np.ndarray

    def loads(self, inertia, P: np.ndarray, gvec: np.ndarray):
        """Resultant force (n, 2, k) and moment (n, k) about the points ``P`` (n, 2, k) of the body
        forces (gravity and ground inertia ``gvec`` (n, 2) per unit mass and d'Alembert) on the arcs
        of ``inertia = (m, S, J)`` (the arcs' mass, first and polar moments about the origin in the
        reference configuration, moved rigidly with the piece)."""
        m, S, J = inertia
        X0 = self.X0[:, None]
        s_r = _rot(self.phi, S - m * X0)                            # int (x - A) dm
        j_r = J - 2.0 * np.sum(X0 * S, 0) + m * np.sum(X0 * X0, 0)  # int |x - A|^2 dm
        p = P - self.A[:, :, None]
        c = (gvec - self.aA)[:, :, None]
        al, om2 = self.alpha[:, None], self.omega[:, None] ** 2
        F = m * c - al[:, None] * np.stack([-s_r[:, 1], s_r[:, 0]], axis=1) + om2[:, None] * s_r
        Mo = _cross(s_r - m * p, c) - al * (j_r - np.sum(p * s_r, 1)) - om2 * _cross(p, s_r)
        return F, Mo

    def frame(self, curve, s: np.ndarray, geometry=None):
        """Moved mid points (n, 2, k), tangents and normals of the sections ``s`` (k,);
        ``geometry``: their position, tangent and normal in the reference configuration, when
        known."""
        X, tg, nm = geometry if geometry is not None else (curve.position(s), curve.tangent(s), curve.normal(s))
        P = self.A[:, :, None] + _rot(self.phi, X - self.X0[:, None])
        return P, _rot(self.phi, tg), _rot(self.phi, nm)


def _pieces(eq: EquationOfMotion, theta, rate, accel):
    """Kinematics of the moving pieces at the instants ``theta``, ``rate``, ``accel`` (n,) and
    the moved hinge points (n, 2, n_hinges)."""
    n = theta.size
    zero = np.zeros((n, 2))
    if eq.mechanism.n_hinges == 1:
        C = np.broadcast_to(eq.C, (n, 2))
        return [_Kinematics(eq.C, C, zero, theta, rate, accel)], C[:, :, None]
    rows = [eq._scalars(x) for x in theta.tolist()]
    if any(k is None for k in rows):
        x = theta[[k is None for k in rows].index(True)]
        raise InputError(f"the four-bar linkage cannot reach theta = {x:g} rad (locked)")
    B, D = np.array([k[0] for k in rows]), np.array([k[1] for k in rows])
    psi3, psi2, w3, w2, dw3, dw2 = np.array([k[2:] for k in rows]).T
    r = B - eq.C1
    aB = accel[:, None] * np.stack([-r[:, 1], r[:, 0]], 1) - (rate ** 2)[:, None] * r
    C1, C2 = np.broadcast_to(eq.C1, (n, 2)), np.broadcast_to(eq.C2, (n, 2))
    kin = [_Kinematics(eq.C1, C1, zero, theta, rate, accel),
           _Kinematics(eq.C13, B, aB, psi3, w3 * rate, w3 * accel + dw3 * rate ** 2),
           _Kinematics(eq.C2, C2, zero, psi2, w2 * rate, w2 * accel + dw2 * rate ** 2)]
    return kin, np.stack([C1, B, D, C2], axis=2)


def _internal(mech, s, refs, H, loads, frame) -> SectionForces:
    """The forces at the sections ``s`` (inside the moving pieces of ``mech``) from the
    equilibrium of its pieces at ``n`` instants.  ``refs[k]`` (n, 2): a point of piece ``k``
    (its moment equation); ``H`` (n, 2, n_hinges): the hinge points; ``loads(k, sa, sb, P)``: the
    resultant (n, 2, j) and moment (n, j) about ``P`` (n, 2, j) of the body loads on the arcs
    ``[sa, sb]`` of piece ``k``; ``frame(k, s)``: the sections' moved mid points, tangents and
    normals (n, 2, j)."""
    curve = mech.curve
    s = np.atleast_1d(np.asarray(s, float))
    nh, moving = mech.n_hinges, np.flatnonzero(mech.moving)
    edges = mech.breaks[np.r_[moving, moving[-1] + 1]]
    tol = 1e-12 * curve.length
    if np.any(s < edges[0] - tol) or np.any(s > edges[-1] + tol):
        raise InputError(f"sections must lie in the moving pieces, s in [{edges[0]:g}, {edges[-1]:g}] m")
    n, K = H.shape[0], len(refs)
    # hinges at the ends of every moving piece (breaks index b is hinge b - 1; -1: free end)
    ends = [(p - 1 if p >= 1 else -1, p if p < nh else -1) for p in moving]

    # equilibrium of the pieces: a piece gets +H_j at its left hinge and -H_j at its right
    # one (H_j: action of the part left of hinge j on the part right of it); moment rows / L
    Lc = curve.length
    A = np.zeros((n, 3 * K, 2 * nh))
    b = np.zeros((n, 3 * K))
    for k, hinges in enumerate(ends):
        F, Mo = loads(k, edges[k:k + 1], edges[k + 1:k + 2], refs[k][:, :, None])
        for j, sign in zip(hinges, (1.0, -1.0)):
            if j >= 0:
                a = H[:, :, j] - refs[k]
                A[:, 3 * k, 2 * j] = A[:, 3 * k + 1, 2 * j + 1] = sign
                A[:, 3 * k + 2, 2 * j], A[:, 3 * k + 2, 2 * j + 1] = -sign * a[:, 1] / Lc, sign * a[:, 0] / Lc
        b[:, 3 * k], b[:, 3 * k + 1], b[:, 3 * k + 2] = -F[:, 0, 0], -F[:, 1, 0], -Mo[:, 0] / Lc
    h = np.einsum("nij,nj->ni", np.linalg.pinv(A), b)
    residual = np.linalg.norm(np.einsum("nij,nj->ni", A, h) - b, axis=1) / np.linalg.norm(b, axis=1)
    Hf = h.reshape(n, nh, 2).transpose(0, 2, 1)                  # (n, 2, nh)

    piece = np.clip(np.searchsorted(edges, s, side="right") - 1, 0, K - 1)
    T, M = np.zeros((n, 2, s.size)), np.zeros((n, s.size))
    tn, nn = np.zeros((n, 2, s.size)), np.zeros((n, 2, s.size))
    for k, (left, right) in enumerate(ends):
        i = np.flatnonzero(piece == k)
        if i.size == 0:
            continue
        si = s[i]
        P, tn[:, :, i], nn[:, :, i] = frame(k, si)
        if right < 0 and left >= 0:            # free right end: minus the loads on [s, end]
            F, Mo = loads(k, si, np.full(si.size, edges[k + 1]), P)
            T[:, :, i], M[:, i] = -F, -Mo
        else:                                  # left hinge force (if any) plus the loads on [start, s]
            F, Mo = loads(k, np.full(si.size, edges[k]), si, P)
            T[:, :, i], M[:, i] = F, Mo
            if left >= 0:
                T[:, :, i] += Hf[:, :, [left]]
                M[:, i] += _cross(H[:, :, [left]] - P, Hf[:, :, [left]])
    N, V = np.sum(T * tn, 1), np.sum(T * nn, 1)
    t = curve.thickness_at(s)
    with np.errstate(divide="ignore", invalid="ignore"):
        e = M / N
        margins = np.where(N > 0, (0.5 * t - np.abs(e)) / t, -np.inf)
    return SectionForces(s, N, V, M, e, np.broadcast_to(t, s.shape), np.min(margins, 1), residual)


def section_forces_many(eq: EquationOfMotion, theta, rate, accel, a_g, s) -> SectionForces:
    """:func:`section_forces` at the instants ``theta``, ``rate``, ``accel``, ``a_g`` (arrays
    of one length n): ``N``, ``V``, ``M``, ``eccentricity`` (n, sections), ``margin`` and
    ``residual`` (n,)."""
    theta, rate, accel, a_g = (np.atleast_1d(np.asarray(x, float)) for x in (theta, rate, accel, a_g))
    kin, H = _pieces(eq, theta, rate, accel)
    curve = eq.mechanism.curve
    gvec = np.stack([-a_g * eq.g, np.full(theta.size, -eq.g)], 1)

    def loads(k, sa, sb, P):
        inertia = _reference(eq, ("inertia", sa.tobytes(), sb.tobytes()), lambda: curve.segment_inertia(sa, sb))
        return kin[k].loads(inertia, P, gvec)

    def frame(k, si):
        geometry = _reference(eq, ("frame", si.tobytes()),
                              lambda: (curve.position(si), curve.tangent(si), curve.normal(si)))
        return kin[k].frame(curve, si, geometry)

    return _internal(eq.mechanism, s, [kn.A for kn in kin], H, loads, frame)


REFERENCE_MEMO = 64   # arcs and sections whose reference geometry an equation of motion keeps


def _reference(eq: EquationOfMotion, key: tuple, compute):
    """What ``compute()`` gives for the reference configuration (the inertia of arcs, the frames
    of sections: arrays that do not depend on the instant), kept on ``eq`` under ``key`` (the
    exact bytes of the arc lengths): the thrust-line scans of a motion ask for the same arcs and
    sections of a mechanism at every step.  The arrays kept are read-only."""
    memo = eq.__dict__.setdefault("_reference_memo", {})
    out = memo.get(key)
    if out is None:
        out = tuple(np.array(a) for a in compute())    # copies: never an array the member keeps
        for a in out:
            a.setflags(write=False)
        if len(memo) >= REFERENCE_MEMO:
            memo.pop(next(iter(memo)))
        memo[key] = out
    return out


def section_forces(eq: EquationOfMotion, theta: float, rate: float, accel: float, a_g: float,
                   s) -> SectionForces:
    """Internal forces at the sections ``s`` (m, inside the moving pieces) at the instant
    ``theta`` (rad), ``rate = theta'`` (rad/s), ``accel = theta''`` (rad/s^2) under the
    ground acceleration ``a_g`` (g).  ``accel`` is not checked: see ``residual``."""
    f = section_forces_many(eq, theta, rate, accel, a_g, s)
    return SectionForces(f.s, f.N[0], f.V[0], f.M[0], f.eccentricity[0], f.thickness, float(f.margin[0]),
                         float(f.residual[0]))


def uniform_sections(mech, sections: int = 200, inset: float = 1e-6) -> np.ndarray:
    """``sections`` uniform sections strictly inside every moving piece of ``mech`` plus the
    sections ``inset * L`` inside each of its hinges (at a hinge itself ``|e| = t/2`` by
    construction), sorted; none inside a crown wedge (no section there), the crown joint
    one of them when a moving piece holds it."""
    br = mech.breaks
    moving = np.flatnonzero(mech.moving)
    u = np.arange(1, sections + 1) / (sections + 1)
    d = inset * mech.curve.length
    hinge = lambda b: 1 <= b <= mech.n_hinges  # noqa: E731  (breaks index b is a hinge)
    s = [np.concatenate([br[p] + (br[p + 1] - br[p]) * u, [br[p] + d] if hinge(p) else [],
                         [br[p + 1] - d] if hinge(p + 1) else []]) for p in moving]
    s = np.sort(np.concatenate(s))
    curve = mech.curve
    if curve.solid_spans:
        inner = [x for x in curve.fixed_nodes if any(br[p] < x < br[p + 1] for p in moving)]
        s = np.union1d(s[curve.admissible(s)], inner)
    return s


def thrust_line_margin(eq: EquationOfMotion, theta: float, rate: float, accel: float, a_g: float,
                       sections: int = 200, inset: float = 1e-6) -> SectionForces:
    """:func:`section_forces` on :func:`uniform_sections` (``sections`` per moving piece and
    ``inset * L`` inside each hinge)."""
    return section_forces(eq, theta, rate, accel, a_g, uniform_sections(eq.mechanism, sections, inset))


def friction_ratio(f: SectionForces):
    """``|V| / N`` at the sections of ``f`` in compression (NaN where ``N <= 0``: nothing to
    carry friction; the thrust-line check reports such a section), and per instant its largest
    value and the index of its section (0 and -1 where no section is in compression)."""
    N, V = np.atleast_2d(f.N), np.atleast_2d(f.V)
    with np.errstate(divide="ignore", invalid="ignore"):
        r = np.where(N > 0, np.abs(V) / N, np.nan)
    ok = np.any(np.isfinite(r), 1)
    i = np.where(ok, np.argmax(np.where(np.isfinite(r), r, -1.0), 1), -1)
    best = np.where(ok, np.take_along_axis(np.nan_to_num(r, nan=-1.0), np.maximum(i, 0)[:, None], 1)[:, 0], 0.0)
    return r, best, i


def _velocity_fields(eq: EquationOfMotion):
    """The mechanism's velocity at unit rate in the undeformed shape, as rigid fields
    ``(sa, sb, vA, A, w)`` on its moving pieces: ``v(x) = vA + w k x (x - A)``."""
    mech = eq.mechanism
    moving = np.flatnonzero(mech.moving)
    br = mech.breaks
    arcs = [(float(br[p]), float(br[p + 1])) for p in moving]
    zero = np.zeros(2)
    if mech.n_hinges == 1:
        return [(*arcs[0], zero, eq.C, 1.0)]
    k = eq._scalars(0.0)
    if k is None:
        raise InputError("the four-bar linkage cannot close at theta = 0")
    w3, w2 = k[4], k[5]
    r = eq.C13 - eq.C1
    return [(*arcs[0], zero, eq.C1, 1.0), (*arcs[1], np.array([-r[1], r[0]]), eq.C13, w3),
            (*arcs[2], zero, eq.C2, w2)]


def _momentum(curve, fields, rate: float, sa, sb, P):
    """Momentum (2, j) and its moment about the points ``P`` (2, j) of the fields (times
    ``rate``) on the arcs ``[sa, sb]`` (j,)."""
    F, Mo = np.zeros((2, sa.size)), np.zeros(sa.size)
    for a, b, vA, A, w in fields:
        lo, hi = np.clip(sa, a, b), np.clip(sb, a, b)
        cut = hi > lo
        if not np.any(cut):
            continue
        m, S, J = curve.segment_inertia(lo[cut], hi[cut])
        Pc = P[:, cut]
        d = S - m * A[:, None]
        F[:, cut] += rate * (m * vA[:, None] + w * np.array([-d[1], d[0]]))
        Mo[cut] += rate * (_cross(S - m * Pc, np.broadcast_to(vA[:, None], S.shape))
                           + w * (J - np.sum((Pc + A[:, None]) * S, 0) + m * np.sum(Pc * A[:, None], 0)))
    return F, Mo


def impact_impulses(before: EquationOfMotion, after: EquationOfMotion, rate_in: float, rate_out: float,
                    s) -> SectionForces:
    """Percussions at the sections ``s`` (m, inside the moving pieces of ``after``) of an impact
    in the undeformed shape from ``before`` at ``theta' = rate_in`` to ``after`` at
    ``theta' = rate_out`` (rad/s): ``N`` (normal, compression > 0), ``V`` (tangential), ``M`` (N s/m
    and N m s/m); ``residual``: that of the balances of the pieces of ``after`` (~1e-12 when
    ``rate_out`` is the impact model's)."""
    curve = after.mechanism.curve
    pre, post = _velocity_fields(before), _velocity_fields(after)

    def loads(k, sa, sb, P):                  # the body impulse -(v+ - v-) on the arcs
        P = P[0]
        sa, sb = np.broadcast_to(sa, (P.shape[1],)), np.broadcast_to(sb, (P.shape[1],))
        Fp, Mp = _momentum(curve, post, rate_out, sa, sb, P)
        Fm, Mm = _momentum(curve, pre, rate_in, sa, sb, P)
        return (Fm - Fp)[None], (Mm - Mp)[None]

    def frame(k, si):
        return curve.position(si)[None], curve.tangent(si)[None], curve.normal(si)[None]

    mech = after.mechanism
    H = mech.points()[None]
    refs = [np.asarray(A, float)[None] for _, _, _, A, _ in post]
    f = _internal(mech, s, refs, H, loads, frame)
    return SectionForces(f.s, f.N[0], f.V[0], f.M[0], f.eccentricity[0], f.thickness, float(f.margin[0]),
                         float(f.residual[0]))
