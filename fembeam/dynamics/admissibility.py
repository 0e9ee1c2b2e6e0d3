"""Whether the one-mechanism motion is admissible: the dynamic thrust line inside every
section along the motion (:func:`thrust_scan`), and the friction the joints need, during the
motion and at the impacts (:func:`impact_friction`)."""
from __future__ import annotations

import math

import numpy as np

from ..errors import SolverError
from .equation import EquationOfMotion
from .ground import GroundMotion
from .thrust import friction_ratio, impact_impulses, section_forces_many, uniform_sections

__all__ = ["motion_sections", "thrust_scan", "impact_friction", "THRUST_TOL", "SECTIONS"]

THRUST_TOL = 1e-6       # thrust line outside the section by more than this fraction of t: exit
SECTIONS = 50           # continuous member: sections checked per moving piece (and one next to each hinge)


def motion_sections(eq: EquationOfMotion, joints: np.ndarray | None) -> np.ndarray:
    """The sections checked on mechanism ``eq``: a voussoir arch's joints in its moving pieces
    (the voussoirs are monolithic), not a free end (it carries nothing); otherwise
    :func:`~fembeam.dynamics.thrust.uniform_sections` (``SECTIONS`` per moving piece and one next to
    each hinge)."""
    m = eq.mechanism
    if joints is None:
        return uniform_sections(m, SECTIONS)
    br = m.breaks[np.flatnonzero(m.moving)[[0, -1]] + [0, 1]]
    keep = (joints >= br[0]) & (joints <= br[1])
    for end, s_end in zip(m.curve.ends, (0.0, m.curve.length)):
        keep &= ~((end == "free") & (joints == s_end))
    return joints[keep]


def thrust_scan(pieces, eqs: list[EquationOfMotion], ground: GroundMotion, dt: float,
                joints: np.ndarray | None = None, tol: float = THRUST_TOL, mu: float | None = None,
                refine: bool = True):
    """The dynamic thrust line along the motion (``pieces``: ``(ta, tb, mechanism, dense
    solution)``) at the sections of :func:`motion_sections`: ``(exit, (ratio, t, s), slide)``.

    ``exit``: the first time (s) at which it leaves the section by more than ``tol`` of the
    thickness anywhere (from then on other hinges would open); None if it never does.
    ``(ratio, t, s)``: the largest ``|S| / N`` over the sections in compression (S the shear, N
    the normal force) and its time and section (m); ``(0, None, None)`` without motion.
    ``slide``: given a friction coefficient ``mu``, the first time that ratio exceeds ``mu`` in a
    section in compression (located as the exit), else None.

    Each piece of motion is evaluated every ``dt`` (at least 5, at most 400 instants; all the
    instants of a mechanism at once: :func:`~fembeam.dynamics.thrust.section_forces_many`); the first exit is located
    (:func:`_first`) to 2^-32 of a scan interval, the largest ratio refined by bounded Brent on the
    scan intervals either side of its best instant (``refine=False``: the best scanned instant)."""
    cuts: dict[int, np.ndarray] = {}
    at = ground.scalar()

    def state(k, instants):
        """The forces on mechanism ``k`` at the ``(dense solution, t)`` pairs ``instants``."""
        y = np.array([sol(tt)[:2] for sol, tt in instants]).reshape(-1, 2)
        a = np.array([at(tt) for _, tt in instants])
        acc = np.array([eqs[k].acceleration(th, w, x) for (th, w), x in zip(y.tolist(), a.tolist())])
        return section_forces_many(eqs[k], y[:, 0], y[:, 1], acc, a, cuts[k])

    def margins_at(k, sol, ts):
        return state(k, [(sol, tt) for tt in ts.tolist()]).margin + tol

    def ratios_at(k, sol, ts):
        return friction_ratio(state(k, [(sol, tt) for tt in ts.tolist()]))[1]

    def ratio(k, sol, tt):
        _, best, i = friction_ratio(state(k, [(sol, tt)]))
        return float(best[0]), (float(cuts[k][i[0]]) if i[0] >= 0 else None)

    grids = [np.linspace(ta, tb, int(np.clip(np.ceil((tb - ta) / dt), 5, 400))) for ta, tb, _, _ in pieces]
    results: list = [None] * len(pieces)
    for k in sorted({p[2] for p in pieces}):     # every instant of a mechanism in one evaluation
        cuts[k] = motion_sections(eqs[k], joints)
        idx = [i for i, p in enumerate(pieces) if p[2] == k]
        f = state(k, [(pieces[i][3], tt) for i in idx for tt in grids[i].tolist()])
        _, best, _ = friction_ratio(f)
        ends = np.cumsum([0] + [grids[i].size for i in idx])
        for i, lo, hi in zip(idx, ends[:-1], ends[1:]):
            results[i] = (f.margin[lo:hi], best[lo:hi])
    exit_at, slide_at, top = None, None, (0.0, None, None, None)       # top: ratio, time, piece, scan interval
    for (ta, tb, k, sol), ts, (margins, best) in zip(pieces, grids, results):
        if mu is not None and slide_at is None:
            over = np.flatnonzero(best > mu)
            if over.size:
                i = int(over[0])
                if i == 0:
                    slide_at = float(ta)
                else:
                    slide_at = _first(lambda x_: mu - ratios_at(k, sol, x_), ts[i - 1], ts[i])
        if exit_at is None:
            out = np.flatnonzero(margins + tol < 0)
            if out.size:
                i = int(out[0])
                if i == 0:
                    exit_at = float(ta)
                else:
                    exit_at = _first(lambda x_: margins_at(k, sol, x_), ts[i - 1], ts[i])
        i = int(np.argmax(best))
        if best[i] > top[0]:
            top = (float(best[i]), float(ts[i]), (k, sol), (ts[max(i - 1, 0)], ts[min(i + 1, ts.size - 1)]))
    if top[1] is None:
        return exit_at, (0.0, None, None), slide_at
    value, t_best, (k, sol), (lo, hi) = top
    s_best = ratio(k, sol, t_best)[1]
    if hi > lo and refine:
        from scipy.optimize import minimize_scalar

        r = minimize_scalar(lambda x: -ratio(k, sol, x)[0], bounds=(lo, hi), method="bounded",
                            options={"xatol": 1e-10 * (hi - lo)})
        if -r.fun > value:
            value, t_best = float(-r.fun), float(r.x)
            s_best = ratio(k, sol, t_best)[1]
    return exit_at, (value, t_best, s_best), slide_at


def _first(fun, lo: float, hi: float, rel: float = 2.0 ** -32, points: int = 31) -> float:
    """The first time in ``(lo, hi]`` where ``fun`` (vectorised over times) is negative, given
    ``fun(lo) >= 0 > fun(hi)``, to ``rel`` of ``hi - lo``, on the negative side: ``points``
    instants a round in one evaluation, the bracket shrinking 32-fold a round (7 rounds)."""
    xtol = (hi - lo) * rel
    while hi - lo > xtol:
        xs = np.linspace(lo, hi, points + 2)[1:-1]
        neg = np.flatnonzero(fun(xs) < 0)
        if neg.size:
            j = int(neg[0])
            lo, hi = (xs[j - 1] if j else lo), xs[j]
        else:
            lo = xs[-1]
    return float(hi)


def impact_friction(eq: EquationOfMotion, eq2: EquationOfMotion, alpha_ratio: float, rate_in: float,
                   joints: np.ndarray | None) -> tuple[float, float | None]:
    """The largest ``|P_t| / P_n`` of the percussions (:func:`~fembeam.dynamics.thrust.impact_impulses`)
    over the sections in compression (:func:`motion_sections` of the mechanism after) of an impact
    from mechanism ``eq`` to ``eq2`` (post-impact rate ``alpha_ratio`` per unit incoming rate;
    ``rate_in``: its sign only, the ratios do not depend on its size), and its section (m)."""
    cuts = motion_sections(eq2, joints)
    f = impact_impulses(eq, eq2, math.copysign(1.0, rate_in), alpha_ratio, cuts)
    if not f.residual < 1e-8:
        raise SolverError(f"the impulses of an impact do not balance (relative residual {f.residual:.1e})")
    _, best, i = friction_ratio(f)
    return float(best[0]), float(cuts[i[0]]) if i[0] >= 0 else None
