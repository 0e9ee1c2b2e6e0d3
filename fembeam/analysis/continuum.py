"""The thrust line between the joints: where does a static solution leave the section?

A limit LP on a mesh constrains the fibre forces at the joints only, so its optimum is
the load factor of a mechanism with hinges at joints: an upper bound of the continuous
member's ``A_L``.  Between the joints the same forces follow from the equilibrium of
the part left of each section (:func:`~fembeam.analysis.statics.section_forces`); this
module finds, in every element, the sections where a fibre force is smallest: samples
inside every element, then a bracketed Brent search (parabolic steps safeguarded by
golden-section steps, vectorised over the elements) around the smallest sample of those
that come close to zero.
"""
from __future__ import annotations

import itertools
from dataclasses import dataclass

import numpy as np

from ..errors import InputError, SolverError
from ..geometry.asbuilt import point_sections
from .lp import SmallLP
from .rows import STAND_TOL, append_section_rows, check_direction, joint_rows, main_lp, solve_unboxed, stand_lp
from .statics import Statics, section_force_rows, section_forces, statics

__all__ = ["weakest_sections", "brent_minimise", "ContinuumLimit", "continuum_limit", "margin_search",
           "continuum_stands"]

SAMPLES = 4          # interior samples per element
SEARCH_STEPS = 100   # at most; Brent's bracket shrinks down to 1e-7 of the length (~6-10 steps)
SCREEN_ELEMENTS = 1000  # meshes finer than this are screened by the forces at the nodes first
NEAR = 0.05          # elements whose sampled fibre force is below this (units of weight) are searched


def _fibres(st: Statics, s: np.ndarray, z: np.ndarray) -> np.ndarray:
    return section_forces(st, s, z[:st.k], z[st.k])[1:]  # (2, ns): N+, N- of z = (x, lambda, 1)


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
    curve = st.disc.curve
    start, stop, points = _search_intervals(curve, nodes)
    h_all = stop - start
    # on fine meshes, screening by the values at the ends: inside an element a fibre force
    # dips below the chord of its end values by at most f'' h^2 / 8 (f'' grows with the load
    # factor); elements next to a kink (whose end value is that of the bisector cut) or
    # across a break of the densities are kept
    cand = np.ones(h_all.size, bool)
    if nodes.size - 1 > SCREEN_ELEMENTS:
        u, inv = np.unique(np.concatenate([start, stop]), return_inverse=True)
        ends = np.minimum(*np.split(_fibres(st, u, z)[:, inv], 2, axis=1)).min(0)
        load = 1.0 + abs(float(z[st.k]))
        cand = ends < level + load * np.minimum(NEAR, 200.0 * (h_all / L) ** 2)
        cand |= _irregular(curve, start, stop)
    cand = np.flatnonzero(cand)
    out_s, out_f, out_v = _at_points(st, points, z, level)
    if cand.size == 0:
        return out_s, out_f, out_v
    q = (np.arange(1, SAMPLES + 1) / (SAMPLES + 1))
    s = (start[cand, None] + h_all[cand, None] * q[None, :]).ravel()
    f = _fibres(st, s, z).reshape(2, cand.size, SAMPLES)
    fmin = f.min(2)
    fib, i = np.nonzero(fmin < level + np.minimum(NEAR, 50.0 * (h_all[cand] / L) ** 2))
    if i.size == 0:
        return out_s, out_f, out_v
    el = cand[i]
    k = np.argmin(f[fib, i], 1)
    h = h_all[el]
    a = start[el] + h * np.where(k == 0, 0.0, q[np.maximum(k - 1, 0)])
    b = np.where(k == SAMPLES - 1, stop[el], start[el] + h * q[np.minimum(k + 1, SAMPLES - 1)])
    # the interpolation points of the first (parabolic) step: the two samples nearest the
    # smallest one (both neighbours inside, else the next two towards the inside)
    jw = np.where(k == 0, 1, k - 1)
    jv = np.where(k == 0, 2, np.where(k == SAMPLES - 1, SAMPLES - 3, k + 1))
    rows = np.arange(fib.size)
    fs = f[fib, i]

    def val(x, sel=slice(None)):
        return _fibres(st, x, z)[fib[sel], np.arange(x.size)]

    width = 1e-7 * (nodes[-1] - nodes[0])   # f(s* +- ds) - f(s*) ~ f'' ds^2: 1e-14 of the weight
    x, fx = start[el] + h * q[k], fs[rows, k]
    w, fw, v, fv = start[el] + h * q[jw], fs[rows, jw], start[el] + h * q[jv], fs[rows, jv]
    # smallest sample next to a node: the minimum is often the node itself, where a search
    # of the bracket would creep up to it by golden steps; two probes at 1/4 and 3/4 of
    # ``width`` from the node settle it (for a unimodal f, f(u1) <= f(u2) puts the minimum
    # in [node, u2]), else the bracket starts at u1
    end = np.where(k == 0, a, np.where(k == SAMPLES - 1, b, np.nan))
    probe = np.flatnonzero(np.isfinite(end))
    at_node = np.zeros(fib.size, bool)
    if probe.size:
        inward = np.where(k[probe] == 0, 1.0, -1.0)
        u = np.concatenate([end[probe] + 0.25 * width * inward, end[probe] + 0.75 * width * inward])
        fu = val(u, np.tile(probe, 2))
        u1, u2, f1, f2 = u[:probe.size], u[probe.size:], fu[:probe.size], fu[probe.size:]
        settled = f1 <= f2
        at_node[probe[settled]] = True
        x[probe[settled]], fx[probe[settled]] = u1[settled], f1[settled]
        go = probe[~settled]
        gl = inward[~settled] > 0
        a[go], b[go] = np.where(gl, u1[~settled], a[go]), np.where(gl, b[go], u1[~settled])
        better = f2[~settled] < fx[go]   # u2 replaces the worst interpolation point (or becomes x)
        v[go], fv[go] = np.where(better, w[go], u2[~settled]), np.where(better, fw[go], f2[~settled])
        w[go], fw[go] = np.where(better, x[go], w[go]), np.where(better, fx[go], fw[go])
        x[go], fx[go] = np.where(better, u2[~settled], x[go]), np.where(better, f2[~settled], fx[go])
    sm, vm = x.copy(), fx.copy()
    todo = np.flatnonzero(~at_node)
    if todo.size:
        sm[todo], vm[todo] = brent_minimise(lambda s, sel: val(s, todo[sel]), a[todo], b[todo], x[todo], fx[todo],
                                            w[todo], fw[todo], v[todo], fv[todo], width)
    kinks = np.asarray(getattr(curve, "kinks", ()), float)
    if kinks.size:
        sm, vm = _one_sided(kinks, start, el, sm, vm, val, 2.0 * width)
    sm = np.clip(sm, start[el], stop[el])            # never past an end (a wedge's edge)
    return np.concatenate([sm, out_s]), np.concatenate([fib, out_f]), np.concatenate([vm, out_v])


def _search_intervals(curve, nodes: np.ndarray):
    """Where sections are searched: each element ``[nodes[e], nodes[e + 1]]`` less the
    curve's :attr:`~fembeam.geometry.MidCurve.solid_spans` (no section inside them).
    Returns ``(start, stop, points)``: the stretches of positive length, and the sections
    checked on their own: the ends of the stretches that are not nodes (the edges of the
    wedges, e.g. the last radial section of a pointed arch's arc: a search inside its
    stretch stops ``width`` short of an end) and the isolated sections (e.g. a crown joint
    inside an element whose ends lie beyond the wedges)."""
    lo, hi = nodes[:-1].copy(), nodes[1:].copy()
    for a, b in getattr(curve, "solid_spans", ()):
        over = (lo < b) & (hi > a)
        if not over.any():
            continue
        left, right = over & (lo <= a), over & (hi >= b)
        lo = np.concatenate([lo[~over], lo[left], np.full(int(right.sum()), b)])
        hi = np.concatenate([hi[~over], np.full(int(left.sum()), a), hi[right]])
    order = np.argsort(lo, kind="stable")
    lo, hi = lo[order], hi[order]
    point = hi <= lo
    ends = np.concatenate([lo, hi])
    points = np.unique(ends[~np.isin(ends, nodes)])
    return lo[~point], hi[~point], points


def _at_points(st: Statics, points: np.ndarray, z: np.ndarray, level: float):
    """:func:`weakest_sections` at isolated sections: both fibres of each, those within
    ``NEAR`` of ``level``."""
    if points.size == 0:
        return np.empty(0), np.empty(0, int), np.empty(0)
    f = _fibres(st, points, z)
    fib, i = np.nonzero(f < level + NEAR)
    return points[i], fib, f[fib, i]


def brent_minimise(f, a, b, x, fx, w, fw, v, fv, width: float, max_steps: int = SEARCH_STEPS):
    """Brent's minimisation (parabolic interpolation safeguarded by golden-section steps,
    as in ``scipy.optimize.fminbound``), vectorised over independent searches.

    ``f(u, sel)`` evaluates the searches ``sel`` (an index array) at ``u``; each search
    starts from its bracket ``[a, b]`` around a minimum, the best point ``x`` and two more
    points ``w``, ``v`` (with values; they may lie outside the bracket and may coincide,
    which only makes the first step a golden one).  A search stops when ``b - a <= width``
    with ``x`` inside (Brent's test ``|x - (a+b)/2| <= 2 tol - (b-a)/2``, ``tol = width/4``;
    steps are at least ``tol``): for a unimodal ``f`` the minimiser is within ``width``
    of ``x``, as for a golden-section search to that width; searches still wider after
    ``max_steps`` are finished by golden sections.  Returns ``(x, f(x))``."""
    cg = 0.5 * (3.0 - np.sqrt(5.0))
    tol1 = 0.25 * width
    tol2 = 2.0 * tol1
    a, b, x, fx, w, fw, v, fv = (np.array(y, float) for y in (a, b, x, fx, w, fw, v, fv))
    d = np.zeros_like(x)
    e = b - a            # the "step before last": the whole bracket, so that the first step may be parabolic
    for _ in range(max_steps):
        xm = 0.5 * (a + b)
        act = np.flatnonzero(np.abs(x - xm) > tol2 - 0.5 * (b - a))
        if act.size == 0:
            break
        A, B, X, W, V, FX, FW, FV, D, E, XM = (y[act] for y in (a, b, x, w, v, fx, fw, fv, d, e, xm))
        r = (X - W) * (FX - FV)
        qq = (X - V) * (FX - FW)
        p = (X - V) * qq - (X - W) * r
        qq = 2.0 * (qq - r)
        p = np.where(qq > 0.0, -p, p)
        qq = np.abs(qq)
        # parabolic step: shorter than half the step before last, and inside the bracket
        para = (np.abs(E) > tol1) & (np.abs(p) < np.abs(0.5 * qq * E)) & (p > qq * (A - X)) & (p < qq * (B - X))
        with np.errstate(divide="ignore", invalid="ignore"):
            dp = np.where(para, p / qq, 0.0)
        U = X + dp
        dp = np.where(para & ((U - A < tol2) | (B - U < tol2)), np.where(XM >= X, tol1, -tol1), dp)
        eg = np.where(X >= XM, A - X, B - X)
        E = np.where(para, D, eg)
        D = np.where(para, dp, cg * eg)
        U = np.where(np.abs(D) >= tol1, X + D, X + np.where(D >= 0.0, tol1, -tol1))
        FU = f(U, act)
        better = FU <= FX
        # bracket: the best point's other side moves in
        A = np.where(better, np.where(U >= X, X, A), np.where(U < X, U, A))
        B = np.where(better, np.where(U >= X, B, X), np.where(U < X, B, U))
        # interpolation points: best x, second best w, third v
        second = ~better & ((FU <= FW) | (W == X))
        third = ~better & ~second & ((FU <= FV) | (V == X) | (V == W))
        shift = better | second
        V, FV = np.where(shift, W, np.where(third, U, V)), np.where(shift, FW, np.where(third, FU, FV))
        W, FW = np.where(better, X, np.where(second, U, W)), np.where(better, FX, np.where(second, FU, FW))
        X, FX = np.where(better, U, X), np.where(better, FU, FX)
        for y, Y in ((a, A), (b, B), (x, X), (w, W), (v, V), (fx, FX), (fw, FW), (fv, FV), (d, D), (e, E)):
            y[act] = Y
    act = np.flatnonzero(b - a > width)
    if act.size:       # steps ran out (very flat minima, |s - m|^16): golden sections finish them
        g = 0.5 * (np.sqrt(5.0) - 1.0)
        A, B = a[act], b[act]
        C, D = B - g * (B - A), A + g * (B - A)
        FC, FD = f(C, act), f(D, act)
        while np.max(B - A) > width:
            left = FC < FD                       # the minimum lies in [A, D]: drop (D, B]
            B, A = np.where(left, D, B), np.where(left, A, C)
            U = np.where(left, B - g * (B - A), A + g * (B - A))
            FU = f(U, act)
            C, D, FD, FC = (np.where(left, U, D), np.where(left, C, U),
                            np.where(left, FC, FU), np.where(left, FU, FD))
        XU, FXU = np.where(FC < FD, C, D), np.minimum(FC, FD)
        better = FXU < fx[act]
        x[act], fx[act] = np.where(better, XU, x[act]), np.where(better, FXU, fx[act])
    return x, fx


def _irregular(curve, lo: np.ndarray, hi: np.ndarray) -> np.ndarray:
    """Stretches ``[lo, hi]`` with a kink at an end or a break of the densities inside or at an end."""
    out = np.zeros(lo.size, bool)
    pts = np.unique(np.concatenate([np.asarray(getattr(curve, "kinks", ()), float),
                                    np.asarray(getattr(curve, "breaks", ()), float)]))
    if pts.size:
        tol = 1e-13 * float(curve.length)
        out |= np.any((pts[None, :] >= lo[:, None] - tol) & (pts[None, :] <= hi[:, None] + tol), 1)
    return out


def _one_sided(kinks, start, el, sm, vm, val, near):
    """At a kink (a node) the fibre force of the element's own normal cuts tends to a limit
    that differs from its value on the kink's cut (the bisector): a minimum there lies at
    the end of the element, where the search stops ``near`` short of it, a first-
    order error.  Searches that ended that close to a kink are evaluated at the kink's
    one-sided section (one ulp inside the element: the element's own tangent) instead,
    when it is weaker."""
    j = np.argmin(np.abs(sm[:, None] - kinks[None, :]), 1)
    k = kinks[j]
    at = np.abs(sm - k) <= near
    if not at.any():
        return sm, vm
    inside = np.where(start[el] < k, np.nextafter(k, -np.inf), np.nextafter(k, np.inf))
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
    the positions are determined only to about the square root of the tolerance.

    Examples
    --------
    :func:`~fembeam.analyze` of a continuous arch reports it as ``continuum``: the
    bracket of ``A_L`` (g) and the hinges (arc lengths in m from the left springing):

    >>> import fembeam
    >>> arch = fembeam.CircularArch(radius=1.0, thickness=0.15, embrace_deg=157.5)
    >>> c = fembeam.analyze(arch, elements=60).continuum
    >>> print(c.status, f"A_L in [{c.A_L_lower:.4f}, {c.A_L:.4f}] g")
    ok A_L in [0.3534, 0.3534] g
    >>> print([f"{s:.3f}" for s in c.hinge_s])
    ['0.026', '1.035', '2.043', '2.749']
    """

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


def continuum_limit(disc, direction: int = 1, tol: float = 1e-10, max_rounds: int = 50,
                    lim=None, live=None) -> ContinuumLimit:
    """Limit analysis of the continuous member meshed by ``disc``: the joints of ``disc``
    plus, round after round, the weakest sections between them (the exchange method of
    semi-infinite linear programming), until the thrust line at the optimum lies inside
    the section everywhere to ``tol`` (units of weight).  ``lim``: the limit analysis of
    ``disc`` along ``direction`` without friction, if done: its LPs on the joints are the
    first round's.  The bounds bracket ``A_L``:
    the convex combination ``theta z* + (1 - theta) z_c`` of the optimum and of the
    most central state under gravity ``z_c`` (margin ``m_c > 0``) is admissible for
    ``theta = m_c / (m_c + violation)``, so ``A_L >= theta A_L*``.  ``live``: point loads
    (:class:`~fembeam.analysis.loads.PointLoads`) whose load factor is sought instead."""
    if getattr(disc, "element", None) != "rigid":
        raise InputError("the continuum analysis needs rigid elements (fembeam.discretize): its sections "
                         "between joints are cut from rigid pieces")
    direction = check_direction(direction)

    st = statics(disc, live)
    k, J = st.k, disc.n_joints
    R = joint_rows(st, direction)
    first = (lim.lps if lim is not None and lim.disc is disc and lim.direction == direction and lim.friction is None
             and getattr(lim, "live", None) is live else (None, None))
    stand, margin, cuts, fib, rounds = margin_search(st, direction, R, np.empty(0), np.empty(0, int), tol,
                                                     max_rounds, first=first[0])
    if stand.value < -STAND_TOL:
        return ContinuumLimit("cannot_stand", float("nan"), float("nan"), stand.value,
                              _support(disc, cuts, stand.y, J), cuts, float("nan"), rounds)
    for _ in range(max_rounds):
        rounds += 1
        main = (first[1] if cuts.size == 0 and first[1] is not None
                else solve_unboxed(main_lp, append_section_rows(R, st, direction, cuts, fib), k))
        if main.at_bound[k]:
            return ContinuumLimit("no_mechanism", float("inf"), float("inf"), margin, np.empty(0), cuts, 0.0, rounds)
        s_new, f_new, v = weakest_sections(st, np.r_[main.z[:k], direction * main.z[k], 1.0])
        violation = max(0.0, -float(np.min(v, initial=0.0)))
        keep = v < -tol
        if not keep.any():
            break
        cuts, fib = np.concatenate([cuts, s_new[keep]]), np.concatenate([fib, f_new[keep]])
    else:
        raise SolverError(f"continuum limit analysis: sections still outside the thrust line by {violation:.2e} "
                          f"(units of weight) after {max_rounds} rounds")
    lam = float(main.z[k])
    hinge_s = _support(disc, cuts, main.y, J)
    exact = False
    clusters = _clusters(disc, cuts, fib, main.y, J)
    # the LP's clusters, then (curves with breaks) those near a break moved onto it
    corners = np.concatenate([point_sections(disc.curve), live.s if live is not None else []])
    for cand in [clusters] + _at_breaks(disc, *clusters, corners=corners):
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
    """The LP's hinges: supporting sections (positive duals) of one fibre closer than
    :func:`_cluster_gap` merge into one, at their dual-weighted mean; ``(s, fibre, fixed)``, where a
    hinge at a springing stays fixed there."""
    s_all = np.concatenate([disc.joint_s, disc.joint_s, cuts])
    f_all = np.concatenate([np.zeros(J, int), np.ones(J, int), fib])
    w = np.abs(y)
    on = w > 1e-6 * max(np.max(w), 1e-300)
    order = np.lexsort((s_all[on], f_all[on]))
    s, f, w = s_all[on][order], f_all[on][order], w[on][order]
    gap = _cluster_gap(disc.nodes_s)
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


CLUSTER_FRACTION = 0.25  # supports of one fibre within this part of the length (or two elements) are one hinge


def _cluster_gap(nodes: np.ndarray) -> float:
    """The distance (m) within which supporting sections of one fibre are one hinge: two
    elements of the mesh with nodes at ``nodes`` (m), at most :data:`CLUSTER_FRACTION` of the
    length.  A hinge's supports lie within an element of it; the cap matters below 8 elements,
    where two elements would merge distinct hinges of one edge (on 4 elements, 0.48 to 0.50 of
    the length apart in the arches of 120 deg with t/R = 0.4 and 157.5 deg with t/R = 0.6)."""
    return min(2.0 * float(np.max(np.diff(nodes))), CLUSTER_FRACTION * float(nodes[-1] - nodes[0]))


def _at_breaks(disc, s, fib, fixed, corners=()) -> list:
    """Candidate clusters with each free one lying within two elements of one of the
    curve's :attr:`~fembeam.geometry.MidCurve.breaks` (a kink, the crown of a thickness
    law) moved onto it and fixed there: the fibre force has a corner at a break, so a
    hinge there is a minimum without a vanishing slope, which :func:`_polish` cannot find
    as a free unknown.  At a kink the hinge may be on the kink's own cut or on either
    one-sided cut (one ulp off the kink: the normal cut of that side's branch), three
    candidates each.  ``corners``: other sections where the fibre forces have a corner (point
    masses, live loads).  Empty when no cluster moves."""
    br = np.unique(np.concatenate([np.asarray(getattr(disc.curve, "breaks", ()), float),
                                   np.asarray(corners, float)]))
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
    k = st.k
    L = st.disc.nodes_s[-1]
    curve = st.disc.curve
    # k + 1 distinct hinges (the LP's clusters are known to ~sqrt(tol) only, so the spacing
    # test that decides degeneracy is made on the solved positions below)
    if s0.size != k + 1 or np.min(np.diff(s0), initial=np.inf) <= 0:
        return None
    free = ~fixed
    ds = 1e-5 * L

    def unpack(p):
        s = s0.copy()
        s[free] = p[k + 1:] * L
        return p[:k], p[k], s

    fib3 = np.tile(fib, 3)
    fi = np.flatnonzero(free)
    nf = fi.size

    def FJ(p):
        """Residuals and their Jacobian: the fibre forces are linear in (x, lambda), their
        slopes and curvatures along the member by central differences (step ``ds``)."""
        x, lam, s = unpack(p)
        # the hinges and their neighbours +- ds in one evaluation
        s3 = np.concatenate([s, np.clip(s + ds, 0, L), np.clip(s - ds, 0, L)])
        C3 = section_force_rows(st, s3)[1 + fib3, np.arange(s3.size)]
        C3[:, k] *= direction
        C, Cp, Cm = np.split(C3, 3)
        y = np.r_[x, lam, 1.0]
        f, fp, fm = C @ y, Cp @ y, Cm @ y
        slope = (fp - fm) / (2 * ds) * L
        J = np.zeros((k + 1 + nf, k + 1 + nf))
        J[:k + 1, :k + 1] = C[:, :k + 1]
        J[fi, k + 1 + np.arange(nf)] = slope[fi]
        J[k + 1:, :k + 1] = ((Cp - Cm)[:, :k + 1] / (2 * ds) * L)[fi]
        J[k + 1 + np.arange(nf), k + 1 + np.arange(nf)] = ((fp - 2 * f + fm) / ds**2 * L * L)[fi]
        return np.r_[f, slope[fi]], J

    def F(p):
        return FJ(p)[0]

    def judged(p_sol):
        # the fibre forces are linear in (x, lambda): at the solved hinges they are made to
        # vanish to round-off by one linear solve (the solvers stop where the slopes'
        # central-difference noise, ~1e-11, hides the fibre residual; the correction moves
        # the slopes by as little) (kept when the fibre residuals are no worse: an
        # ill-conditioned system, degenerate hinges, could spoil them; the slopes are judged
        # below with the rest)
        x, lam, s = unpack(p_sol)
        if not np.all(np.isfinite(p_sol)) or s[0] < 0 or s[-1] > L or not np.all(curve.admissible(s)):
            return None
        C = section_force_rows(st, s)[1 + fib, np.arange(s.size)]
        C[:, k] *= direction
        p, res = p_sol, F(p_sol)
        try:
            p_lin = np.r_[np.linalg.solve(C[:, :k + 1], -C[:, k + 1]), p_sol[k + 1:]]
            res_lin = F(p_lin)
            if np.max(np.abs(res_lin[:k + 1])) <= np.max(np.abs(res[:k + 1])):
                p, res = p_lin, res_lin
        except np.linalg.LinAlgError:
            pass
        x, lam, s = unpack(p)
        # the residuals' round-off floor grows with the size of the terms that cancel in a fibre
        # force (~1/t for thin sections): thresholds relative to that size, not absolute
        z = np.r_[x, direction * lam, 1.0]
        scale = max(1.0, float(np.max(np.abs(C) @ np.abs(z))))
        # judged by the residual (a solver may stop at the noise floor and call it slow
        # progress): fibre forces and slopes ~1e-11 (the noise of the central difference, eps / ds)
        if (np.max(np.abs(res[:k + 1])) > 1e-10 * scale or np.max(np.abs(res[k + 1:]), initial=0) > 1e-8 * scale
                # apart by two elements or 1 % of the length (_merging): otherwise the optimum is
                # degenerate (hinges merging, e.g. at a springing) and the positions ill-conditioned
                or _merging(s, st.disc.nodes_s)):
            return None
        return x, float(lam), s, scale

    p0 = np.r_[x0, lam0, s0[free] / L]
    out = judged(_newton(FJ, p0, lambda p: (np.all(p[k + 1:] >= 0) and np.all(p[k + 1:] <= 1)
                                            and np.all(curve.admissible(p[k + 1:] * L)))))
    if out is None:      # Newton did not converge from the LP's hinges: MINPACK's trust region
        from scipy.optimize import root

        out = judged(root(FJ, p0, jac=True, method="hybr", options={"xtol": 1e-14}).x)
    return out


MERGE_FRACTION = 0.01   # solved hinges closer than this part of the length (or two elements) are merging


def _merging(s: np.ndarray, nodes: np.ndarray) -> bool:
    """Whether two of the solved hinges at ``s`` (m) are closer than two elements of the
    mesh with nodes at ``nodes`` (m) or than :data:`MERGE_FRACTION` of the member's length,
    whichever is shorter: a degenerate optimum, whose positions are ill-conditioned.

    The length cap keeps the test a property of the mechanism on coarse meshes: on 4 to 7
    elements two elements are 29 to 50 % of the length, which rejected the well-separated
    hinges of the semicircular-type arches (the paper arch's closest pair is 26 % of the
    length apart) and left the mechanism on the uniform mesh, with a load factor 5 to 12 %
    above ``A_L``."""
    L = float(nodes[-1] - nodes[0])
    gap = min(2.0 * float(np.max(np.diff(nodes))), MERGE_FRACTION * L)
    return bool(np.min(np.diff(s), initial=np.inf) < gap)


NEWTON_STEPS = 30   # Newton steps at most (two or three from the LP's hinges)
HALVINGS = 6        # halvings of a step that does not decrease the residual
STEP_TOL = 1e-12    # a step this small (relative to the unknowns) ends the iteration


def _newton(FJ, p0: np.ndarray, inside, max_steps: int = NEWTON_STEPS) -> np.ndarray:
    """Newton's method on ``FJ(p) = (F, dF/dp)`` from ``p0``, each step halved (at most
    ``HALVINGS`` times) until the residual decreases and ``inside(p)`` holds; stops when a
    step is below ``STEP_TOL`` (relative), none decreases the residual or a full step
    decreases it less than tenfold (the noise floor of the central differences, reached
    one or two steps after the LP's hinges).  The caller judges the result."""
    p = p0.copy()
    f, J = FJ(p)
    nf = np.linalg.norm(f)
    for _ in range(max_steps):
        try:
            dp = np.linalg.solve(J, -f)
        except np.linalg.LinAlgError:
            return p
        if np.max(np.abs(dp)) <= STEP_TOL * max(1.0, np.max(np.abs(p))):
            return p
        t = 1.0
        for _ in range(HALVINGS):
            q = p + t * dp
            if inside(q):
                fq, Jq = FJ(q)
                nq = np.linalg.norm(fq)
                if nq < nf:
                    break
            t *= 0.5
        else:
            return p
        slow = t == 1.0 and nq > 0.1 * nf      # a full step without quadratic decrease: noise
        p, f, J, nf = q, fq, Jq, nq
        if slow:
            return p
    return p


def margin_search(st: Statics, direction: int, R: np.ndarray, cuts: np.ndarray, fib: np.ndarray, tol: float,
                  max_rounds: int, converge: bool = False,
                  first: SmallLP | None = None) -> tuple[SmallLP, float, np.ndarray, np.ndarray, int]:
    """Largest margin under gravity on the continuum (units of weight), by the exchange method
    from the rows ``R`` (:func:`~fembeam.analysis.rows.joint_rows` along ``direction``) and the
    fibre rows ``fib`` at the sections ``cuts`` (m): the LP's value bounds it from above, the
    smallest fibre force of the LP's state along the whole member from below.  The rounds stop
    as soon as that state stands, or with ``converge`` only when the bounds agree to ``tol``
    (or the joints alone cannot stand).  ``first``: the LP on the rows ``R`` alone, already
    solved.  Returns ``(stand, margin, cuts, fib, rounds)``: the last stand LP (its value the
    upper bound), the lower bound, the sections of that LP and the rounds used."""
    k = st.k
    if isinstance(max_rounds, bool) or not isinstance(max_rounds, (int, np.integer)) or max_rounds < 1:
        raise InputError(f"max_rounds must be a positive integer, got {max_rounds!r}")
    for rounds in range(1, max_rounds + 1):
        stand = (first if first is not None and cuts.size == 0
                 else solve_unboxed(stand_lp, append_section_rows(R, st, direction, cuts, fib), k))
        z_c = np.r_[stand.z[:k], 0.0, 1.0]
        s_new, f_new, v = weakest_sections(st, z_c, stand.value)
        margin = min(stand.value, float(np.min(v, initial=np.inf)))
        keep = v < stand.value - tol
        if (margin >= -STAND_TOL and not converge) or stand.value < -STAND_TOL or not keep.any():
            break
        if rounds == max_rounds:                    # the cuts returned are those of the last LP
            if margin < -STAND_TOL:
                raise SolverError(f"whether the member stands is undecided after {max_rounds} rounds: the joints "
                                  f"stand, a section between them does not yet")
            break
        cuts, fib = np.concatenate([cuts, s_new[keep]]), np.concatenate([fib, f_new[keep]])
    return stand, margin, cuts, fib, rounds


def continuum_stands(disc, tol: float = 1e-10, max_rounds: int = 50, converge: bool = False) -> tuple[bool, float]:
    """Whether the continuous member meshed by ``disc`` stands under gravity, and the
    margin (units of weight; a lower bound when it stands, the LP's bound when not).
    ``converge``: the margin to ``tol`` also when it stands (more LP rounds), a continuous
    function of the thickness for a root finder (unless the joints alone cannot stand)."""
    st = statics(disc)
    stand, margin, *_ = margin_search(st, 1, joint_rows(st, 1), np.empty(0), np.empty(0, int), tol, max_rounds, converge)
    if stand.value < -STAND_TOL:
        return False, stand.value
    return margin >= -STAND_TOL, margin


def _support(disc, cuts: np.ndarray, y: np.ndarray, J: int) -> np.ndarray:
    """Sections carrying the LP's duals (the hinges): joints and cuts, sorted."""
    s_all = np.concatenate([disc.joint_s, disc.joint_s, cuts])
    w = np.abs(y)
    return np.unique(s_all[w > 1e-6 * max(np.max(w), 1e-300)])
