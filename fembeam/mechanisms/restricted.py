"""The paper's restricted problem (16)-(17): the best compatible four-hinge mechanism
after the impact.

* Discrete arch (hinges only at the joints ``joint_s``): exhaustive search over all
  ``C(J, 4) x 2^4`` placements and sides, vectorised with prefix sums of the voussoir
  inertia, so every candidate costs O(1) whatever the number of voussoirs:
  ``Lambda' = sum_k a_k^T Q[k] a_k`` and ``Gamma = sum_k a_k . (Q b)[k]`` over the three
  moving pieces ``k`` (``Q`` = 3x3 inertia matrix of a piece, ``a_k`` its motion
  ``(V_x, V_y, Omega)``, ``b`` the pre-impact field).
* Continuous arch: maximise ``r`` of (17) (exact integrals, :func:`~fembeam.mechanisms.energy.post_impact`)
  over the four hinge positions with the sides fixed, by a bounded quasi-Newton search
  started from the exhaustive optimum on a fine joint grid.
"""
from __future__ import annotations

from dataclasses import dataclass, field
from itertools import chain, combinations, islice, product as iproduct
from math import comb

import numpy as np

from ..errors import InputError, SolverError
from ..fem import uniform_nodes
from ..geometry import MidCurve
from .energy import post_impact, product as momentum_product
from .hinge import ROCKING_SIDES, opening_signs, pivot_fractions
from .mechanism import Mechanism

__all__ = ["RestrictedResult", "ExhaustiveGeometry", "best_four_hinge_discrete", "best_four_hinge_continuous",
           "refine_four_hinge", "qp_with_hinges_only_at", "exhaustive_candidates", "MAX_EXHAUSTIVE_JOINTS"]

MAX_EXHAUSTIVE_JOINTS = 81   # 80 voussoirs: 16 C(81, 4) = 26.6 million candidates, ~30 s


@dataclass
class RestrictedResult:
    """Best four-hinge mechanism ``after`` with its ``r`` (17); ``ranking``: the next
    best candidates as ``(r, Mechanism)``; ``candidates``/``compatible``: counts.

    Examples
    --------
    :func:`best_four_hinge_discrete` returns it; of the four-hinge mechanisms on the 13
    joints of the paper's arch of 12 voussoirs, the best after the paper's one closes
    (hinges in deg):

    >>> from fembeam.mechanisms.restricted import best_four_hinge_discrete
    >>> import fembeam
    >>> arch = fembeam.CircularArch(radius=1.0, thickness=0.15, embrace_deg=157.5)
    >>> sides = ["intrados", "extrados", "intrados", "extrados"]
    >>> before = fembeam.Mechanism.from_angles(arch, [0.0, 52.5, 118.125, 157.5], sides)
    >>> res = best_four_hinge_discrete(fembeam.uniform_nodes(arch, 12), before)
    >>> print([f"{a:g}" for a in res.after.angles_deg()], f"r = {res.r:.4f}")
    ['0', '52.5', '105', '157.5'] r = 0.6071
    >>> print(res.candidates, "candidates,", res.compatible, "compatible")
    11440 candidates, 547 compatible
    """

    after: Mechanism | None
    r: float
    ranking: list = field(default_factory=list)
    candidates: int = 0
    compatible: int = 0
    method: str = ""


def _prefix(x: np.ndarray) -> np.ndarray:
    """Prefix sums over the voussoirs along the last axis, starting at 0 (J,)."""
    return np.concatenate([np.zeros(x.shape[:-1] + (1,)), np.cumsum(x, -1)], -1)


def _inertia_sums(curve: MidCurve, joint_s: np.ndarray) -> np.ndarray:
    """Prefix sums over the voussoirs of ``(m, S_x, S_y, J)`` (4, J)."""
    m, S, J = curve.segment_inertia(joint_s[:-1], joint_s[1:])
    return _prefix(np.array([m, S[0], S[1], J]))


def _pairing_sums(curve: MidCurve, joint_s: np.ndarray, before: Mechanism):
    """Prefix sums over the voussoirs of the pre-impact momentum pairing ``G = Q b`` (3, J),
    and ``Lambda = b^T Q b`` of the field ``before``."""
    m, S, J = curve.segment_inertia(joint_s[:-1], joint_s[1:])
    b = before.motion_at(0.5 * (joint_s[:-1] + joint_s[1:])).T     # (3, N): V_x, V_y, Omega
    G = np.array([m * b[0] - S[1] * b[2], m * b[1] + S[0] * b[2], -S[1] * b[0] + S[0] * b[1] + J * b[2]])
    return _prefix(G), float(np.sum(G * b))


def _geometry(P: np.ndarray, sides_sign: np.ndarray, inertia: list):
    """What of ``r`` depends on the geometry alone: ``P`` (n, 4, 2) hinge points,
    ``sides_sign`` (4,); for each moving piece (I, III, II) its ``(m, S_x, S_y, J)``,
    ``inertia[k]`` (4, n).  Returns ``(n, sel, sgn, lam_a, vel)``: the candidates ``sel`` whose
    linkage moves with ``Lambda' > 0`` and hinges that open together (the others have r = 0
    whatever the pre-impact field), the sign ``sgn`` of the rate that opens them, ``Lambda' =
    sum_k a_k^T Q_k a_k`` and the motions ``vel[k] = (V_x, V_y, Omega)`` of the pieces at unit
    rate (``a_k``: motion of piece ``k``, ``Q_k`` its 3x3 inertia matrix), all on ``sel``."""
    C1, C13, C23, C2 = (P[:, i].T for i in range(4))
    d1, d2 = C13 - C1, C23 - C2
    det = -d1[0] * d2[1] + d1[1] * d2[0]
    with np.errstate(all="ignore"):
        a = (-(C2 - C1)[0] * d2[1] + (C2 - C1)[1] * d2[0]) / det
        C3 = C1 + a * d1
        e3 = C13 - C3
        om3 = np.sum((C13 - C1) * e3, 0) / np.sum(e3 * e3, 0)
        om2 = om3 * np.sum((C23 - C3) * (C23 - C2), 0) / np.sum((C23 - C2) ** 2, 0)
        valid = (np.abs(det) > 1e-12 * np.sum(d1 * d1, 0)) & np.isfinite(om3) & np.isfinite(om2)
        jumps = np.array([np.ones_like(om3), om3 - 1.0, om2 - om3, -om2]) * sides_sign[:, None]
        sgn = np.where(np.all(jumps >= 0, 0), 1.0, np.where(np.all(jumps <= 0, 0), -1.0, 0.0)) * valid
        lam_a = np.zeros(om3.shape)
        vel = []
        for w, c, (m, Sx, Sy, J) in zip((np.ones_like(om3), om3, om2), (C1, C3, C2), inertia):
            vx, vy = w * c[1], -w * c[0]                               # rotation w about c
            lam_a += m * (vx * vx + vy * vy) + 2.0 * w * (Sx * vy - Sy * vx) + J * w * w
            vel.append((vx, vy, w))
        sel = np.flatnonzero(valid & (sgn != 0) & (lam_a > 0))
    return om3.size, sel, sgn[sel], lam_a[sel], [(vx[sel], vy[sel], w[sel]) for vx, vy, w in vel]


def _restitution(geometry, pairing: list, lam: float) -> np.ndarray:
    """r of every candidate of ``geometry`` (:func:`_geometry`) for the pre-impact field whose
    pairing with each moving piece is ``pairing[k]`` (3, len(sel)) and ``Lambda = lam``:
    ``Gamma = sum_k a_k . G_k``, ``r = Gamma^2 / (Lambda Lambda')`` where the rate of sign
    ``Gamma`` opens every hinge, else 0."""
    n, sel, sgn, lam_a, vel = geometry
    gam = np.zeros(sel.shape)
    for (vx, vy, w), G in zip(vel, pairing):
        gam += vx * G[0] + vy * G[1] + w * G[2]
    ok = gam * sgn > 0
    r = np.zeros(n)
    with np.errstate(all="ignore"):
        r[sel[ok]] = gam[ok] ** 2 / (lam * lam_a[ok])
    return r


def _quadruples(n: int, chunk: int):
    """All ``C(n, 4)`` increasing index quadruples of ``range(n)``, lexicographic, in
    (k, 4) blocks of at most ``chunk`` rows (never all in memory at once)."""
    it = combinations(range(n), 4)
    while True:
        block = np.fromiter(chain.from_iterable(islice(it, chunk)), dtype=np.int64)
        if block.size == 0:
            return
        yield block.reshape(-1, 4)


def exhaustive_candidates(joints: int) -> int:
    """Candidates of the exhaustive search on ``joints`` joints: ``16 C(joints, 4)``."""
    return 16 * comb(int(joints), 4)


class ExhaustiveGeometry:
    """The part of the exhaustive search on the joints ``joint_s`` of ``curve`` that depends on
    the geometry alone (:func:`_geometry` of every placement and choice of sides), computed once
    and reused by every :func:`best_four_hinge_discrete` on these joints: only the pairing with
    the pre-impact field is left to each search (a small part of the work), with the same
    numbers.  It keeps the candidates whose hinges can open together (about a tenth of them),
    some 100 bytes each: 7 MB on the 32 joints of :func:`best_four_hinge_continuous`' grid,
    20 MB on 41."""

    def __init__(self, curve: MidCurve, joint_s, chunk: int = 200_000):
        js = np.asarray(joint_s, float)
        _check_joints(js.size)
        self.curve, self.joint_s = curve, js
        self.blocks = list(_blocks(curve, js, chunk))

    def matches(self, curve: MidCurve, joint_s) -> bool:
        """Whether this is the geometry of ``joint_s`` on ``curve`` (the same object)."""
        js = np.asarray(joint_s, float)
        return curve is self.curve and js.shape == self.joint_s.shape and bool(np.all(js == self.joint_s))


def _check_joints(J: int):
    if J < 4:
        raise InputError("a four-hinge mechanism needs at least four joints")
    if J > MAX_EXHAUSTIVE_JOINTS:
        raise InputError(f"the exhaustive four-hinge search takes at most {MAX_EXHAUSTIVE_JOINTS} joints "
                         f"({MAX_EXHAUSTIVE_JOINTS - 1} voussoirs; its time grows as the 4th power), got {J}")


def _blocks(curve: MidCurve, js: np.ndarray, chunk: int):
    """Per block of quadruples ``idx`` (:func:`_quadruples`): ``(idx, [(sides, geometry)])`` for
    the 16 choices of sides (:func:`_geometry`), generated one block at a time."""
    cI = _inertia_sums(curve, js)
    X, n, t = curve.position(js), curve.normal(js), curve.thickness_at(js)
    for idx in _quadruples(js.size, chunk):
        inertia = [cI[:, idx[:, k + 1]] - cI[:, idx[:, k]] for k in range(3)]
        geo = []
        for sides in iproduct(ROCKING_SIDES, repeat=4):
            y = pivot_fractions(sides)
            P = (X[:, idx] + y[None, :] * t[idx] * n[:, idx]).transpose(1, 2, 0)   # (k, 4, 2)
            geo.append((sides, _geometry(P, opening_signs(sides), inertia)))
        yield idx, geo


def best_four_hinge_discrete(joint_s, before: Mechanism, keep: int = 5,
                             chunk: int = 200_000, geometry: ExhaustiveGeometry | None = None) -> RestrictedResult:
    """Exhaustive restricted problem on the joints ``joint_s`` (m, increasing, the
    springings included) for the pre-impact field ``before`` (rigid on each voussoir).

    Every placement and choice of sides is tried: ``16 C(J, 4)`` candidates for ``J``
    joints, O(J^4) time (about 1 us per candidate on one core) in memory O(``chunk``);
    at most :data:`MAX_EXHAUSTIVE_JOINTS` joints (InputError beyond).  ``geometry``: the
    :class:`ExhaustiveGeometry` of these joints, when computed before (the same answer, about
    ten times faster)."""
    curve = before.curve
    js = np.asarray(joint_s, float)
    J = js.size
    _check_joints(J)
    if geometry is not None and not geometry.matches(curve, js):
        raise InputError("the precomputed geometry of the exhaustive search is not that of these joints")
    cG, lam = _pairing_sums(curve, js, before)
    best: list[tuple[float, tuple[int, ...], tuple[str, ...]]] = []
    n_compat = 0
    for idx, geo in (geometry.blocks if geometry is not None else _blocks(curve, js, chunk)):
        for sides, g in geo:
            sel = idx[g[1]]
            r = _restitution(g, [cG[:, sel[:, k + 1]] - cG[:, sel[:, k]] for k in range(3)], lam)
            n_compat += int(np.count_nonzero(r > 0))
            top = np.argpartition(r, -keep)[-keep:] if r.size > keep else np.arange(r.size)
            best += [(float(r[i]), tuple(int(j) for j in idx[i]), sides) for i in top if r[i] > 0]
            best = sorted(best, key=lambda z: -z[0])[:keep]
    total = exhaustive_candidates(J)
    if not best:
        return RestrictedResult(None, 0.0, [], total, 0, "exhaustive")
    rank = [(r, Mechanism(curve, tuple(js[list(i)]), s)) for r, i, s in best]
    return RestrictedResult(rank[0][1], rank[0][0], rank[1:], total, n_compat, "exhaustive")


def refine_four_hinge(before: Mechanism, start: Mechanism) -> tuple[float, Mechanism]:
    """Maximise the exact ``r`` (17) over the four hinge positions of ``start`` (sides
    fixed) by L-BFGS-B; returns ``(r, mechanism)``, never worse than ``start``."""
    curve, L, sides = before.curve, before.curve.length, start.sides
    lam = momentum_product(before, before)

    def f(x):
        s = curve.nearest_section(np.sort(np.clip(x, 0.0, 1.0)) * L)    # no hinge inside a crown wedge
        try:
            return -post_impact(before, Mechanism(curve, tuple(s), sides), lam).r
        except SolverError:      # a degenerate linkage met by the line search (parallel lines): no motion
            return 0.0

    x0 = np.asarray(start.s) / L
    from scipy.optimize import minimize   # imported here: scipy.optimize takes 0.2 s to import

    res = minimize(f, x0, method="L-BFGS-B", bounds=[(0.0, 1.0)] * 4,
                   options={"ftol": 1e-15, "gtol": 1e-12, "eps": 1e-9, "maxiter": 1000})
    x = res.x if res.fun <= f(x0) else x0
    return -f(x), Mechanism(curve, tuple(curve.nearest_section(np.sort(np.clip(x, 0, 1)) * L)), sides)


def best_four_hinge_continuous(before: Mechanism, grid: int = 31,
                               starts: list[Mechanism] | None = None,
                               geometry: ExhaustiveGeometry | None = None) -> RestrictedResult:
    """Restricted problem on a continuous arch: exhaustive search on ``grid`` uniform
    voussoirs (:func:`~fembeam.fem.uniform_nodes`) for the sides and a start, then maximise
    the exact ``r`` over the four hinge positions (L-BFGS-B, sides fixed; none inside a
    crown wedge) from it and from ``starts``.  ``geometry``: the :class:`ExhaustiveGeometry`
    of that grid, when several searches on the member share it."""
    curve = before.curve
    coarse = best_four_hinge_discrete(uniform_nodes(curve, grid), before, keep=2, geometry=geometry)
    cands = [m for m in [coarse.after] + [h for _, h in coarse.ranking] + list(starts or []) if m is not None]
    results = sorted((refine_four_hinge(before, start) for start in cands), key=lambda z: -z[0])
    if not results:
        return RestrictedResult(None, 0.0, [], coarse.candidates, 0, "exhaustive")
    return RestrictedResult(results[0][1], results[0][0], results[1:], coarse.candidates, coarse.compatible,
                            f"exhaustive on {grid} voussoirs, then L-BFGS-B on the exact r")


def qp_with_hinges_only_at(disc, d0: np.ndarray, open_joints, backend: str = "clarabel") -> tuple[float, np.ndarray]:
    """The impact QP of :mod:`fembeam.analysis.impact` with every joint except ``open_joints``
    locked (both fibre openings = 0): ``(r, d')``.  With four joints it is the
    restricted problem on those sections, solved by the FE machinery: a cross-check
    of the closed form, and the tool that shows what extra open joints buy."""
    import scipy.sparse as sp

    from ..analysis.qp import solve_qp
    from ..fem import dof_scaling

    J = disc.n_joints
    free = np.zeros(J, bool)
    free[np.asarray(open_joints, int)] = True
    rows = np.concatenate([np.arange(J), J + np.arange(J)])
    free2 = np.concatenate([free, free])
    D = dof_scaling(disc)
    M = disc.M
    two_k = float(d0 @ M @ d0)
    m = float(disc.rigid(V=(1.0, 0.0)) @ M @ disc.rigid(V=(1.0, 0.0)))
    sigma = np.sqrt(two_k / m)
    Bo = disc.B_open[rows]
    A_eq = sp.vstack([disc.B_slide, Bo[~free2]]).tocsr() @ D
    A_in = Bo[free2] @ D
    sol = solve_qp((D @ M @ D / m).tocsc(), -(D @ (M @ d0)) / (m * sigma), A_eq, A_in, backend=backend)
    d = sigma * (D @ sol.x)
    return float(d @ M @ d) / two_k, d
