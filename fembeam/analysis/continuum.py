"""The thrust line between the joints: where does a static solution leave the section?

A limit LP on a mesh constrains the fibre forces at the joints only, so its optimum is
the load factor of a mechanism with hinges at joints: an upper bound of the continuous
member's ``A_L``.  Between the joints the same forces follow from the equilibrium of
the part left of each section (:func:`~fembeam.analysis.statics.section_forces`); this
module finds, in every element, the sections where a fibre force is smallest: samples
inside every element, then a bracketed golden-section search (vectorised over the
elements) around the smallest sample of those that come close to zero.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..errors import InputError
from .statics import Statics, section_force_rows, statics

__all__ = ["weakest_sections", "ContinuumLimit", "continuum_limit"]

SAMPLES = 4          # interior samples per element
GOLDEN_STEPS = 60    # at most; the bracket shrinks by 0.618 a step, down to 1e-7 of the length
SCREEN_ELEMENTS = 1000  # meshes finer than this are screened by the forces at the nodes first
NEAR = 0.05          # elements whose sampled fibre force is below this (units of weight) are searched


def _fibres(st: Statics, s: np.ndarray, z: np.ndarray) -> np.ndarray:
    return (section_force_rows(st, s)[1:] @ z)            # (2, ns): N+, N-


def weakest_sections(st: Statics, z: np.ndarray, level: float = 0.0) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Local minima of the fibre forces inside the elements for ``z = (x, lambda, 1)``.

    Returns ``(s, fibre, value)`` for every (element, fibre) whose sampled minimum is
    within ``min(NEAR, 50 (h/L)^2)`` of ``level`` (units of weight): section (m), fibre
    index (0 intrados, 1 extrados) and the minimum force there.  Between samples a
    fibre force can dip by at most ~f'' h^2 / 32 (f'' is a few weights per L^2), so the
    elements left out cannot reach ``level``.
    """
    nodes = st.disc.nodes_s
    L = nodes[-1] - nodes[0]
    h_all = np.diff(nodes)
    # on fine meshes, screening by the values at the nodes: inside an element a fibre force
    # dips below the chord of its end values by at most f'' h^2 / 8 (f'' grows with the load
    # factor); elements next to a kink (whose end value is that of the bisector cut) or
    # across a break of the densities are kept
    cand = np.ones(h_all.size, bool)
    if h_all.size > SCREEN_ELEMENTS:
        fn = _fibres(st, nodes, z)
        ends = np.minimum(fn[:, :-1], fn[:, 1:]).min(0)
        load = 1.0 + abs(float(z[st.k]))
        cand = ends < level + load * np.minimum(NEAR, 200.0 * (h_all / L) ** 2)
        cand |= _irregular(st.disc.curve, nodes)
    cand = np.flatnonzero(cand)
    if cand.size == 0:
        return np.empty(0), np.empty(0, int), np.empty(0)
    q = (np.arange(1, SAMPLES + 1) / (SAMPLES + 1))
    s = (nodes[cand, None] + h_all[cand, None] * q[None, :]).ravel()
    f = _fibres(st, s, z).reshape(2, cand.size, SAMPLES)
    fmin = f.min(2)
    fib, i = np.nonzero(fmin < level + np.minimum(NEAR, 50.0 * (h_all[cand] / L) ** 2))
    if i.size == 0:
        return np.empty(0), np.empty(0, int), np.empty(0)
    el = cand[i]
    k = np.argmin(f[fib, i], 1)
    h = h_all[el]
    a = nodes[el] + h * np.where(k == 0, 0.0, q[np.maximum(k - 1, 0)])
    b = nodes[el] + h * np.where(k == SAMPLES - 1, 1.0, q[np.minimum(k + 1, SAMPLES - 1)])
    g = 0.5 * (np.sqrt(5.0) - 1.0)
    c, d = b - g * (b - a), a + g * (b - a)

    def val(x):
        return _fibres(st, x, z)[fib, np.arange(fib.size)]

    fc, fd = val(c), val(d)
    width = 1e-7 * (nodes[-1] - nodes[0])   # f(s* +- ds) - f(s*) ~ f'' ds^2: 1e-14 of the weight
    for _ in range(GOLDEN_STEPS):
        if np.max(b - a) <= width:
            break
        left = fc < fd                       # the minimum lies in [a, d]: drop (d, b]
        b = np.where(left, d, b)
        a = np.where(left, a, c)
        x = np.where(left, b - g * (b - a), a + g * (b - a))
        fx = val(x)
        c, d, fd, fc = (np.where(left, x, d), np.where(left, c, x),
                        np.where(left, fc, fx), np.where(left, fx, fd))
    sm, vm = np.where(fc < fd, c, d), np.minimum(fc, fd)
    kinks = np.asarray(getattr(st.disc.curve, "kinks", ()), float)
    if kinks.size:
        sm, vm = _one_sided(kinks, nodes, el, sm, vm, val, 2.0 * width)
    return sm, fib, vm


def _irregular(curve, nodes: np.ndarray) -> np.ndarray:
    """Elements with a kink at an end or a break of the densities inside or at an end."""
    out = np.zeros(nodes.size - 1, bool)
    pts = np.unique(np.concatenate([np.asarray(getattr(curve, "kinks", ()), float),
                                    np.asarray(getattr(curve, "breaks", ()), float)]))
    if pts.size:
        tol = 1e-13 * (nodes[-1] - nodes[0])
        out |= np.any((pts[None, :] >= nodes[:-1, None] - tol) & (pts[None, :] <= nodes[1:, None] + tol), 1)
    return out


def _one_sided(kinks, nodes, el, sm, vm, val, near):
    """At a kink (a node) the fibre force of the element's own normal cuts tends to a limit
    that differs from its value on the kink's cut (the bisector): a minimum there lies at
    the end of the element, where the golden search stops ``near`` short of it, a first-
    order error.  Searches that ended that close to a kink are evaluated at the kink's
    one-sided section (one ulp inside the element: the element's own tangent) instead,
    when it is weaker."""
    j = np.argmin(np.abs(sm[:, None] - kinks[None, :]), 1)
    k = kinks[j]
    at = np.abs(sm - k) <= near
    if not at.any():
        return sm, vm
    inside = np.where(nodes[el] < k, np.nextafter(k, -np.inf), np.nextafter(k, np.inf))
    s_alt = np.where(at, inside, sm)
    v_alt = val(s_alt)
    better = at & (v_alt < vm)
    return np.where(better, s_alt, sm), np.where(better, v_alt, vm)


@dataclass
class ContinuumLimit:
    """The continuous member's limit state, bracketed: ``A_L`` (upper bound: a mechanism
    with hinges at ``hinge_s``) and ``A_L_lower`` (lower bound: an admissible thrust line
    everywhere); ``status`` as :class:`~fembeam.analysis.limit.LimitResult`.

    ``exact_hinges``: the hinge positions solve the optimality conditions to round-off.
    It is False when the optimum is degenerate, e.g. two hinges of one edge merging
    (thick arches: the thrust line touches the edge with a contact of fourth order), where
    the positions are determined only to about the square root of the tolerance."""

    status: str
    A_L: float
    A_L_lower: float
    margin: float                 # standing margin (units of weight), lower bound on the continuum
    hinge_s: np.ndarray           # sections (m) of the mechanism's hinges (joints or cuts)
    cuts: np.ndarray              # sections between the joints added as constraints (m)
    violation: float              # thrust line outside between the joints at A_L (units of weight)
    rounds: int
    exact_hinges: bool = False    # hinge positions solved to round-off (Newton); False: degenerate

    @property
    def gap(self) -> float:
        return (self.A_L - self.A_L_lower) / self.A_L if self.A_L > 0 else 0.0


def _rows(st: Statics, direction: int, R: np.ndarray, cuts: np.ndarray, fib: np.ndarray) -> np.ndarray:
    if cuts.size == 0:
        return R
    C = section_force_rows(st, cuts)                      # (3, nc, k + 2)
    C = C[1 + fib, np.arange(cuts.size)]
    C[:, st.k] *= direction
    return np.concatenate([R, C])


def continuum_limit(disc, direction: int = 1, tol: float = 1e-10, max_rounds: int = 50) -> ContinuumLimit:
    """Limit analysis of the continuous member meshed by ``disc``: the joints of ``disc``
    plus, round after round, the weakest sections between them (the exchange method of
    semi-infinite linear programming), until the thrust line at the optimum lies inside
    the section everywhere to ``tol`` (units of weight).  The bounds bracket ``A_L``:
    the convex combination ``theta z* + (1 - theta) z_c`` of the optimum and of the
    most central state under gravity ``z_c`` (margin ``m_c > 0``) is admissible for
    ``theta = m_c / (m_c + violation)``, so ``A_L >= theta A_L*``."""
    from .limit import STAND_TOL, _check_direction, _unboxed, joint_rows, main_lp

    if getattr(disc, "element", None) != "rigid":
        raise InputError("the continuum analysis needs rigid elements (fembeam.discretize): its sections "
                         "between joints are cut from rigid pieces")
    direction = _check_direction(direction)

    st = statics(disc)
    k, J = st.k, disc.n_joints
    R = joint_rows(st, direction)
    stand, margin, cuts, fib, rounds = _stand(st, direction, R, np.empty(0), np.empty(0, int), tol, max_rounds)
    if stand.value < -STAND_TOL:
        return ContinuumLimit("cannot_stand", float("nan"), float("nan"), stand.value,
                              _support(disc, cuts, stand.y, J), cuts, float("nan"), rounds)
    for _ in range(max_rounds):
        rounds += 1
        main = _unboxed(main_lp, _rows(st, direction, R, cuts, fib), k)
        if main.at_bound[k]:
            return ContinuumLimit("no_mechanism", float("inf"), float("inf"), margin, np.empty(0), cuts, 0.0, rounds)
        s_new, f_new, v = weakest_sections(st, np.r_[main.z[:k], direction * main.z[k], 1.0])
        violation = max(0.0, -float(np.min(v, initial=0.0)))
        keep = v < -tol
        if not keep.any():
            break
        cuts, fib = np.concatenate([cuts, s_new[keep]]), np.concatenate([fib, f_new[keep]])
    lam = float(main.z[k])
    hinge_s = _support(disc, cuts, main.y, J)
    exact = False
    clusters = _clusters(disc, cuts, fib, main.y, J)
    # the LP's clusters, then (curves with breaks) those near a break moved onto it
    for cand in [clusters] + _at_breaks(disc, *clusters):
        polished = _polish(st, direction, *cand, main.z[:k], lam)
        if polished is None:
            continue
        x_p, lam_p, s_p, scale = polished
        s_new, f_new, v = weakest_sections(st, np.r_[x_p, direction * lam_p, 1.0])
        joints = joint_rows(st, direction) @ np.r_[x_p, lam_p, 1.0]
        v_p = max(0.0, -float(np.min(v, initial=0.0)), -float(np.min(joints)))
        if v_p <= tol * scale and lam_p <= lam * (1 + 1e-9):
            lam, violation, hinge_s, exact = lam_p, v_p, s_p, True
            break
    lower = lam * margin / (margin + violation) if margin > 0 else 0.0
    return ContinuumLimit("ok", lam, min(lam, lower), margin, hinge_s, cuts, violation, rounds, exact)


def _clusters(disc, cuts, fib, y, J):
    """The LP's hinges: supporting sections (positive duals) of one fibre closer than two
    elements merge into one, at their dual-weighted mean; ``(s, fibre, fixed)``, where a
    hinge at a springing stays fixed there."""
    s_all = np.concatenate([disc.joint_s, disc.joint_s, cuts])
    f_all = np.concatenate([np.zeros(J, int), np.ones(J, int), fib])
    w = np.abs(y)
    on = w > 1e-6 * max(np.max(w), 1e-300)
    order = np.lexsort((s_all[on], f_all[on]))
    s, f, w = s_all[on][order], f_all[on][order], w[on][order]
    gap = 2.0 * np.max(np.diff(disc.nodes_s))
    new = np.concatenate([[True], (np.diff(s) > gap) | (np.diff(f) != 0)])
    grp = np.cumsum(new) - 1
    wsum = np.bincount(grp, w)
    sc = np.bincount(grp, w * s) / wsum
    fc = f[new]
    L = disc.nodes_s[-1]
    ends = np.bincount(grp, (s == 0.0) | (s == L)) > 0
    sc = np.where(ends, np.where(sc < 0.5 * L, 0.0, L), sc)
    order = np.argsort(sc)
    return sc[order], fc[order], ends[order]


def _at_breaks(disc, s, fib, fixed) -> list:
    """Candidate clusters with each free one lying within two elements of one of the
    curve's :attr:`~fembeam.geometry.MidCurve.breaks` (a kink, the crown of a thickness
    law) moved onto it and fixed there: the fibre force has a corner at a break, so a
    hinge there is a minimum without a vanishing slope, which :func:`_polish` cannot find
    as a free unknown.  At a kink the hinge may be on the kink's own cut or on either
    one-sided cut (one ulp off the kink: the normal cut of that side's branch), three
    candidates each.  Empty when no cluster moves."""
    import itertools

    br = np.asarray(getattr(disc.curve, "breaks", ()), float)
    if br.size == 0 or s.size == 0:
        return []
    kinks = set(getattr(disc.curve, "kinks", ()))
    near = 2.0 * np.max(np.diff(disc.nodes_s))
    d = np.abs(s[:, None] - br[None, :])
    j = np.argmin(d, 1)
    move = np.flatnonzero(~fixed & (d[np.arange(s.size), j] <= near))
    if move.size == 0:
        return []
    options = [[b] + ([np.nextafter(b, -np.inf), np.nextafter(b, np.inf)] if b in kinks else [])
               for b in br[j[move]]]
    out = []
    for choice in itertools.product(*options):
        s2 = s.copy()
        s2[move] = choice
        f2 = fixed.copy()
        f2[move] = True
        out.append((s2, fib, f2))
    return out


def _polish(st: Statics, direction: int, s0, fib, fixed, x0, lam0):
    """Newton on the optimality conditions of the continuum LP with its hinges known:
    the fibre force vanishes at every hinge, and so does its derivative along the member
    at an interior hinge (the thrust line touches the edge).  Unknowns: the redundants,
    the load factor and the interior hinge positions; as many equations when the
    mechanism is not degenerate (``k + 1`` hinges).  Returns ``(x, lambda, s)`` or None."""
    from scipy.optimize import root

    k = st.k
    L = st.disc.nodes_s[-1]
    # k + 1 distinct hinges (the LP's clusters are known to ~sqrt(tol) only, so the spacing
    # test that decides degeneracy is made on the solved positions below)
    if s0.size != k + 1 or np.min(np.diff(s0), initial=np.inf) <= 0:
        return None
    free = ~fixed
    ds = 1e-5 * L

    def fibre(s, z):
        return np.einsum("nj,j->n", section_force_rows(st, s)[1 + fib, np.arange(s.size)], z)

    def unpack(p):
        s = s0.copy()
        s[free] = p[k + 1:] * L
        return p[:k], p[k], s

    def F(p):
        x, lam, s = unpack(p)
        z = np.r_[x, direction * lam, 1.0]
        slope = (fibre(np.clip(s + ds, 0, L), z) - fibre(np.clip(s - ds, 0, L), z)) / (2 * ds) * L
        return np.r_[fibre(s, z), slope[free]]

    p0 = np.r_[x0, lam0, s0[free] / L]
    sol = root(F, p0, method="hybr", options={"xtol": 1e-14})
    x, lam, s = unpack(sol.x)
    res = F(sol.x)
    # the residuals' round-off floor grows with the size of the terms that cancel in a fibre
    # force (~1/t for thin sections): thresholds relative to that size, not absolute
    z = np.r_[x, direction * lam, 1.0]
    scale = max(1.0, float(np.max(np.abs(section_force_rows(st, s)[1 + fib, np.arange(s.size)]) @ np.abs(z))))
    # judged by the residual (MINPACK may stop at the noise floor and call it slow progress):
    # fibre forces and slopes ~1e-11 (the noise of the central difference, eps / ds)
    if (np.max(np.abs(res[:k + 1])) > 1e-10 * scale or np.max(np.abs(res[k + 1:]), initial=0) > 1e-8 * scale
            or s[0] < 0 or s[-1] > L
            # at least two elements apart: otherwise the optimum is degenerate (hinges merging,
            # e.g. at a springing) and the positions are ill-conditioned
            or np.min(np.diff(s), initial=np.inf) < 2.0 * np.max(np.diff(st.disc.nodes_s))):
        return None
    return x, float(lam), s, scale


def _stand(st: Statics, direction: int, R, cuts, fib, tol: float, max_rounds: int):
    """Largest margin under gravity on the continuum: the LP's value bounds it from above,
    the smallest fibre force of the LP's state along the whole member from below."""
    from .limit import STAND_TOL, _unboxed, stand_lp

    k = st.k
    for rounds in range(1, max_rounds + 1):
        stand = _unboxed(stand_lp, _rows(st, direction, R, cuts, fib), k)
        z_c = np.r_[stand.z[:k], 0.0, 1.0]
        s_new, f_new, v = weakest_sections(st, z_c, stand.value)
        margin = min(stand.value, float(np.min(v, initial=np.inf)))
        keep = v < stand.value - tol
        if margin >= -STAND_TOL or stand.value < -STAND_TOL or not keep.any():
            break
        cuts, fib = np.concatenate([cuts, s_new[keep]]), np.concatenate([fib, f_new[keep]])
    return stand, margin, cuts, fib, rounds


def continuum_stands(disc, tol: float = 1e-10, max_rounds: int = 50) -> tuple[bool, float]:
    """Whether the continuous member meshed by ``disc`` stands under gravity, and the
    margin (units of weight; a lower bound when it stands, the LP's bound when not)."""
    from .limit import STAND_TOL, joint_rows

    st = statics(disc)
    stand, margin, *_ = _stand(st, 1, joint_rows(st, 1), np.empty(0), np.empty(0, int), tol, max_rounds)
    if stand.value < -STAND_TOL:
        return False, stand.value
    return margin >= -STAND_TOL, margin


def _support(disc, cuts: np.ndarray, y: np.ndarray, J: int) -> np.ndarray:
    """Sections carrying the LP's duals (the hinges): joints and cuts, sorted."""
    s_all = np.concatenate([disc.joint_s, disc.joint_s, cuts])
    w = np.abs(y)
    return np.unique(s_all[w > 1e-6 * max(np.max(w), 1e-300)])
