"""Minimum thickness: the smallest factor of the thickness law at which the member stands.

"Stands" is decided by the margin LP of :mod:`~fembeam.analysis.limit` (a thrust line
under gravity alone inside every section), on the arch actually analysed: the joints of
the mesh (voussoirs, or a mesh with hinges at joints only) or, for the continuous member,
every section (:func:`~fembeam.analysis.continuum.continuum_stands`).  The mid-curve and
the mesh stay fixed; the thickness law is scaled by a factor ``k``.  The bracket
``[lower, scale]`` (``lower`` does not stand, ``scale`` does) is halved until
``scale - lower <= tol * scale``: at most ``log2(1/tol)`` solves after the bracket is
found, which itself takes at most ~60 doublings or halvings.

With a Coulomb coefficient ``friction`` the joint forces must also lie in the friction
cone ``|S| <= mu (N+ + N-)`` (:mod:`~fembeam.analysis.friction`): checked at the joints of
the mesh (the fibre forces of the continuous member still at every section), so that the
continuous member's value is approached as the mesh is refined.  Friction can only make
the minimum thickness larger, and below some ``mu`` no thickness stands (``inf``).
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..errors import InputError
from ..fem import discretize, uniform_nodes
from ..geometry import MidCurve
from .continuum import _stand, continuum_stands
from .friction import check_friction
from .limit import STAND_TOL, _unboxed, joint_rows, stand_lp
from .statics import statics

__all__ = ["MinimumThickness", "minimum_thickness", "thickness_on"]

MAX_DOUBLINGS_SCALE = 2.0 ** 40   # a member that does not stand 10^12 times thicker never does


@dataclass(frozen=True)
class MinimumThickness:
    """``scale``: smallest thickness factor that stands (``0`` if every factor down to the
    shape's thinnest admitted section stands, ``inf`` if none up to its limit does); ``lower``: a factor that
    does not stand (``scale - lower <= tol scale``); ``solves``: margin LPs used."""

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


def _stands(curve: MidCurve, nodes: np.ndarray, continuum: bool, friction: float | None = None) -> bool:
    disc = discretize(curve, nodes)
    if continuum and friction is None:
        return continuum_stands(disc)[0]
    st = statics(disc)
    R = joint_rows(st, 1, friction)
    if continuum:    # fibre rows between the joints too, friction rows at the joints
        stand, margin, *_ = _stand(st, 1, R, np.empty(0), np.empty(0, int), 1e-10, 50)
        return stand.value >= -STAND_TOL and margin >= -STAND_TOL
    return _unboxed(stand_lp, R, st.k).value >= -STAND_TOL


def minimum_thickness(curve: MidCurve, elements: int | None = None, voussoirs: int | None = None,
                      tol: float = 1e-6, friction: float | None = None) -> MinimumThickness:
    """Smallest thickness factor at which ``curve`` stands under its own weight: the
    continuous member meshed by ``elements`` (default 200) rigid elements, every section
    checked, or the discrete arch of ``voussoirs``; ``tol`` relative, in [1e-12, 0.1];
    ``friction``: Coulomb coefficient ``mu >= 0`` of the joints (None: no sliding)."""
    from .pipeline import DEFAULT_ELEMENTS, _count

    if elements is not None and voussoirs is not None:
        raise InputError("give either elements (continuous arch) or voussoirs (discrete arch), not both")
    if voussoirs is not None:
        return thickness_on(curve, uniform_nodes(curve, _count(voussoirs, "voussoirs", 1)), False, tol, friction)
    n = _count(DEFAULT_ELEMENTS if elements is None else elements, "elements", 4)
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

    def stands(k: float) -> bool:
        nonlocal solves
        solves += 1
        return _stands(curve.with_thickness_scaled(k), nodes, continuum, mu)

    floor = curve.min_thickness_scale
    if stands(1.0):
        lo, hi = max(0.5, floor), 1.0
        while stands(lo):
            if lo <= floor:   # stands down to the thinnest section the shape admits
                return MinimumThickness(curve, 0.0, 0.0, solves, continuum, mu)
            lo, hi = max(0.5 * lo, floor), lo
    else:
        lo, hi = 1.0, min(2.0, cap)
        while not stands(hi):
            if hi >= cap or hi >= MAX_DOUBLINGS_SCALE:
                return MinimumThickness(curve, math.inf, hi, solves, continuum, mu)
            lo, hi = hi, min(2.0 * hi, cap)
    while hi - lo > tol * hi:
        mid = 0.5 * (lo + hi)
        lo, hi = (lo, mid) if stands(mid) else (mid, hi)
    return MinimumThickness(curve, hi, lo, solves, continuum, mu)
