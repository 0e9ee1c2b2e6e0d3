"""Minimum thickness: the smallest factor of the thickness law at which the member stands.

"Stands" is decided by the margin LP (:func:`~fembeam.analysis.rows.stand_lp`: a thrust line
under gravity alone inside every section), on the arch actually analysed: the joints of
the mesh (voussoirs, or a mesh with hinges at joints only) or, for the continuous member,
every section (:func:`~fembeam.analysis.continuum.continuum_stands`).  The mid-curve and
the mesh stay fixed; the thickness law is scaled by a factor ``k`` (the operators of every
factor from two assemblies: :class:`~fembeam.fem.rigid.ThicknessFamily`).  The bracket
``[lower, scale]`` (``lower`` does not stand, ``scale`` does), found by at most ~60
doublings or halvings, is shrunk until ``scale - lower <= tol * scale`` by regula falsi
on the margin (Anderson-Bjorck variant: superlinear, ~4-6 solves at ``tol = 1e-6`` instead
of ~20 for a bisection), whose every point keeps the bracket; every step that does not halve
the bracket counts, and after four of them bisection takes over: at most ``log2(1/tol) + 5``
solves follow.

With a Coulomb coefficient ``friction`` the joint forces must also lie in the friction
cone ``|S| <= mu (N+ + N-)`` (:mod:`~fembeam.analysis.friction`): checked at the joints of
the mesh (the fibre forces of the continuous member still at every section), so that the
continuous member's value is approached as the mesh is refined.  Friction can only make
the minimum thickness larger, and below some ``mu`` no thickness stands (``inf``).  The flow
of these rows is associative (dilatant sliding): for joints that slide without dilatancy the
thickness found is a lower bound (a thinner arch has no equilibrium state at all, a thicker
one may still collapse; docs/friction.md, section 3).
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..errors import InputError, SolverError
from ..fem import Discretization, discretize, uniform_nodes
from ..fem.rigid import ThicknessFamily
from ..geometry import MidCurve
from .continuum import continuum_stands, margin_search
from .rows import STAND_TOL, check_friction, joint_rows, solve_unboxed, stand_lp
from .sizes import DEFAULT_ELEMENTS, MIN_ELEMENTS, MIN_VOUSSOIRS, check_count
from .statics import statics

__all__ = ["MinimumThickness", "minimum_thickness", "thickness_on", "stands_on", "shrink_bracket"]

MAX_DOUBLINGS_SCALE = 2.0 ** 40   # a member that does not stand 10^12 times thicker never does


@dataclass(frozen=True)
class MinimumThickness:
    """Outcome of :func:`minimum_thickness`.

    Attributes
    ----------
    curve : MidCurve
        The member whose thickness is scaled.
    scale : float
        Smallest thickness factor that stands (``0`` if every factor down to the shape's
        thinnest admitted section stands, ``inf`` if none up to its limit does).
    lower : float
        A factor that does not stand (``scale - lower <= tol scale``).
    solves : int
        Margin LPs used.
    continuum : bool
        Every section checked (continuous member) or the joints only.
    friction : float or None
        Coulomb coefficient of the joints (None: no sliding).

    Examples
    --------
    :func:`minimum_thickness` returns it: the smallest factor of the thickness that
    stands and the thickness (m) and ``t/R`` it gives:

    >>> import fembeam
    >>> arch = fembeam.CircularArch(radius=1.0, thickness=0.15, embrace_deg=157.5)
    >>> mt = fembeam.minimum_thickness(arch, voussoirs=12)
    >>> print(mt.outcome, f"scale = {mt.scale:.4f}")
    ok scale = 0.4267
    >>> print(f"t_min = {mt.scale * arch.thickness:.4f} m, t_min/R = {mt.t_over_R:.4f}")
    t_min = 0.0640 m, t_min/R = 0.0640
    """

    curve: MidCurve
    scale: float
    lower: float
    solves: int
    continuum: bool
    friction: float | None = None

    @property
    def t_over_R(self) -> float | None:
        """Minimum t/R of a circular arch (None for other shapes)."""
        tr = getattr(self.curve, "t_over_r", None)
        return None if tr is None else self.scale * tr

    @property
    def outcome(self) -> str:
        if self.scale == 0.0:
            return "stands_at_any_thickness"
        return "never_stands" if math.isinf(self.scale) else "ok"

    def to_dict(self) -> dict:
        fin = (lambda x: float(x) if math.isfinite(x) else None)  # noqa: E731
        return {"outcome": self.outcome, "thickness_scale": fin(self.scale), "lower": fin(self.lower),
                "t_min_over_R": None if self.t_over_R is None else fin(self.t_over_R), "solves": self.solves,
                "continuum": self.continuum, "friction": self.friction}


def _margin(disc: Discretization, continuum: bool, friction: float | None = None) -> float:
    """Standing margin under gravity (units of weight): the member stands exactly when it is
    ``>= -STAND_TOL``.  The continuum's is converged to 1e-10 on both sides of zero, so that
    it is continuous in the thickness factor near the root (the root finder's function)."""
    if continuum and friction is None:
        return float(continuum_stands(disc, converge=True)[1])
    st = statics(disc)
    R = joint_rows(st, 1, friction)
    if continuum:    # fibre rows between the joints too, friction rows at the joints
        stand, margin, *_ = margin_search(st, 1, R, np.empty(0), np.empty(0, int), 1e-10, 50, converge=True)
        return float(min(stand.value, margin))
    return float(solve_unboxed(stand_lp, R, st.k).value)


def stands_on(curve: MidCurve, nodes: np.ndarray, continuum: bool, friction: float | None = None) -> bool:
    """Whether ``curve`` stands on the mesh ``nodes`` (arc lengths, m), from its own assembly;
    ``continuum``: every section checked, else the joints only; ``friction`` as
    :func:`minimum_thickness`."""
    return _margin(discretize(curve, nodes), continuum, friction) >= -STAND_TOL


def shrink_bracket(g, lo: float, glo: float, hi: float, ghi: float, tol: float,
                   max_slow: int = 4) -> tuple[float, float]:
    """Shrink ``[lo, hi]`` with ``g(lo) < 0 <= g(hi)`` until ``hi - lo <= tol * hi`` and return
    it: every evaluated point replaces the end of its sign, so the bracket always holds.

    Points by regula falsi with the Anderson-Bjorck modification (the value of an end kept
    twice in a row is scaled by ``1 - g_new / g_old`` of the other end, or halved: superlinear,
    like the Illinois variant but exact for a linear ``g``), moved by ``tol * hi / 4`` towards the end
    the last step kept (once the estimate is that accurate the next point lands on that
    side, and the bracket closes within ``tol * hi / 2`` of the root).  After ``max_slow``
    steps that did not halve the bracket (a margin with kinks or noise), bisection only."""
    kept = 0           # +1: the last step kept lo (hi moved), -1: it kept hi
    slow = 0
    while hi - lo > tol * hi:
        w, eps = hi - lo, 0.5 * tol * hi
        if slow >= max_slow:
            k = 0.5 * (lo + hi)
        else:
            k = hi - ghi * (w / (ghi - glo)) - 0.5 * eps * kept
            k = min(max(k, lo + 0.5 * eps), hi - 0.5 * eps)
        gk = g(k)
        if not math.isfinite(gk):
            raise SolverError(f"minimum thickness: the standing margin at factor {k:g} is {gk}")
        if gk >= 0.0:
            if kept == 1:
                m = 1.0 - gk / ghi if ghi > 0.0 else 0.5
                glo *= m if m > 0.0 else 0.5
            hi, ghi, kept = k, gk, 1
        else:
            if kept == -1:
                m = 1.0 - gk / glo if glo < 0.0 else 0.5
                ghi *= m if m > 0.0 else 0.5
            lo, glo, kept = k, gk, -1
        slow += hi - lo > 0.5 * w
    return lo, hi


def minimum_thickness(curve: MidCurve, elements: int | None = None, voussoirs: int | None = None,
                      tol: float = 1e-6, friction: float | None = None) -> MinimumThickness:
    """Smallest thickness factor at which a member stands under its own weight.

    The member's thickness is scaled (every section alike) and the smallest factor with
    an admissible thrust line under gravity is found by bisection on the standing
    margin.

    Parameters
    ----------
    curve : MidCurve
        The member (lengths in m).
    elements : int, optional
        Rigid elements of a continuous member (default 200), every section checked.
        Not with ``voussoirs``.
    voussoirs : int, optional
        Voussoirs of a discrete arch (its joints checked only).
    tol : float, optional
        Relative tolerance of the factor, in [1e-12, 0.1].
    friction : float, optional
        Coulomb coefficient ``mu >= 0`` of the joints (None, the default: no sliding).

    Returns
    -------
    MinimumThickness
        ``scale`` (the factor; ``0`` if the member stands down to its thinnest admitted
        section, ``inf`` if it never stands), ``lower`` (a factor that does not stand)
        and, for a circular arch, ``t_over_R``.

    Raises
    ------
    InputError
        ``elements`` with ``voussoirs``, or a count or ``tol`` out of range.

    Examples
    --------
    >>> import fembeam
    >>> arch = fembeam.CircularArch(radius=1.0, thickness=0.15, embrace_deg=157.5)
    >>> mt = fembeam.minimum_thickness(arch)
    >>> print(mt.outcome, f"scale = {mt.scale:.4f}, t_min/R = {mt.t_over_R:.4f}")
    ok scale = 0.4310, t_min/R = 0.0647
    """
    if elements is not None and voussoirs is not None:
        raise InputError("give either elements (continuous arch) or voussoirs (discrete arch), not both")
    if voussoirs is not None:
        return thickness_on(curve, uniform_nodes(curve, check_count(voussoirs, "voussoirs", MIN_VOUSSOIRS)), False,
                            tol, friction)
    n = check_count(DEFAULT_ELEMENTS if elements is None else elements, "elements", MIN_ELEMENTS)
    return thickness_on(curve, uniform_nodes(curve, n), True, tol, friction)


def thickness_on(curve: MidCurve, nodes: np.ndarray, continuum: bool, tol: float = 1e-6,
                 friction: float | None = None) -> MinimumThickness:
    """:func:`minimum_thickness` on the mesh ``nodes`` (arc lengths, m); ``continuum``:
    every section checked, else the joints only; ``friction`` as there."""
    if not isinstance(tol, (int, float)) or not 1e-12 <= tol <= 0.1:
        raise InputError(f"the minimum-thickness tolerance must be in [1e-12, 0.1], got {tol!r}")
    mu = check_friction(friction)
    cap = curve.max_thickness_scale * (1 - 1e-9)
    solves = 0
    family = ThicknessFamily.of(curve, nodes)    # every factor's operators without an assembly

    def g(k: float) -> float:
        """Margin at factor ``k`` shifted by the standing tolerance: ``>= 0`` stands."""
        nonlocal solves
        solves += 1
        return _margin(family.at(k), continuum, mu) + STAND_TOL

    floor = curve.min_thickness_scale
    g1 = g(1.0)
    if g1 >= 0.0:
        hi, ghi = 1.0, g1
        lo = max(0.5, floor)
        glo = g(lo)
        while glo >= 0.0:
            if lo <= floor:   # stands down to the thinnest section the shape admits
                return MinimumThickness(curve, 0.0, 0.0, solves, continuum, mu)
            hi, ghi = lo, glo
            lo = max(0.5 * lo, floor)
            glo = g(lo)
    else:
        lo, glo = 1.0, g1
        hi = min(2.0, cap)
        ghi = g(hi)
        while ghi < 0.0:
            if hi >= cap or hi >= MAX_DOUBLINGS_SCALE:
                return MinimumThickness(curve, math.inf, hi, solves, continuum, mu)
            lo, glo = hi, ghi
            hi = min(2.0 * hi, cap)
            ghi = g(hi)
    lo, hi = shrink_bracket(g, lo, glo, hi, ghi, tol)
    return MinimumThickness(curve, hi, lo, solves, continuum, mu)
