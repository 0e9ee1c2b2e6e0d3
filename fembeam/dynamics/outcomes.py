"""What a motion ends as, and the figures every motion reports: one vocabulary for ``fembeam rock``
(one mechanism at a time) and ``fembeam simulate`` (every piece a rigid body).

* **Outcomes** (:data:`OUTCOMES`): ``rest`` (at rest at the end), ``survived`` (still moving at the
  end), ``overturned`` (the overturning rule below), ``collapsed_by_sliding`` (``fembeam simulate``:
  a joint's faces no longer overlap, or the member reached the overturning level with its joints
  slid more than opened: :func:`fembeam.simulation.kernel.collapse`), ``cannot_stand`` (the member
  cannot carry its own weight).
* **Overturning rule** (:func:`overturn_level`): the member has overturned at the first time its
  potential energy ``V`` (J/m, 0 at rest) falls below ``-OVERTURN_DROP m g t``, i.e.
  its centroid is :data:`OVERTURN_DROP` of the mean thickness ``t`` below its height at rest.  Along
  any rocking mechanism ``V`` rises from rest to the unstable equilibrium and falls below rest
  only beyond it, so a member past that level is falling.  The level is far above the errors of a
  contact model: a corner overlapping its face by ``1e-5 t`` changes ``V`` by about ``1e-5 m g t``.
* **Where a mechanism overturns** (:func:`overturning`): the rotation at which ``V`` falls to that
  level along the mechanism, and the energy barrier on the way (the one-mechanism model).
* **Friction demand** (:func:`friction_demand`): the largest ratio of tangential to normal force
  (or percussion at an impact) over the joints or sections of the motion, with its time and
  place; ``sliding_risk`` when a friction coefficient is given and the ratio exceeds it.
"""
from __future__ import annotations

import math

import numpy as np

from ..errors import SolverError
from .events import brentq

__all__ = ["OUTCOMES", "OVERTURN_DROP", "overturn_level", "mean_thickness", "friction_demand",
           "overturning"]

OUTCOMES = ("rest", "survived", "overturned", "collapsed_by_sliding", "cannot_stand")
OVERTURN_DROP = 0.1     # overturned: centroid this fraction of the mean thickness below rest


def mean_thickness(curve) -> float:
    """Mean thickness (m) of a member over its arc length (101 evenly spaced sections)."""
    s = np.linspace(0.0, curve.length, 101)
    return float(np.mean(np.broadcast_to(np.asarray(curve.thickness_at(s), float), s.shape)))


def overturn_level(curve, mass: float, g: float) -> float:
    """``V`` (J/m) below which the member of ``mass`` (kg/m) has
    overturned: ``-OVERTURN_DROP m g t`` with ``t`` the mean thickness."""
    return -OVERTURN_DROP * mass * g * mean_thickness(curve)


def friction_demand(ratio: float, t: float | None, s: float | None, at: str | None,
                    mu: float | None) -> dict:
    """The JSON block ``friction_demand``: the largest ``|S|/N`` (or ``|P_t|/P_n``) ``max_ratio``, its
    time ``t`` (s), the arc length ``s`` (m from the left springing) of its joint or section, ``at``
    (``"motion"``: a force during the motion, ``"impact"``: a percussion), the friction coefficient
    ``mu`` given (None: unlimited) and ``sliding_risk`` (``max_ratio > mu``; None without ``mu``)."""
    def num(x):
        return None if x is None or not math.isfinite(x) else float(x)

    return {"max_ratio": num(ratio) if ratio is not None else 0.0, "t": num(t), "s": num(s), "at": at,
            "mu": num(mu), "sliding_risk": None if mu is None else bool(ratio is not None and ratio > mu)}


OVERTURN_GRID = 256     # steps from the unstable equilibrium to the lock (or pi) scanning for the level


def overturning(eq: "EquationOfMotion", level: float) -> tuple[float, str, float]:
    """Where mechanism ``eq`` has overturned under the rule above ( ``V`` below
    ``level`` < 0): ``(top, event, barrier)`` with ``top`` the smallest ``sign * theta`` at which
    ``V = level`` (``event`` ``"overturn"``), or just before the four-bar locks if it locks
    first (``"locked"``); ``barrier`` the largest ``V`` on ``[0, top]``.

    ``V`` rises from 0 to the unstable equilibrium ``theta_unstable`` (the first ``V' = 0``), so the
    level is looked for beyond it: on ``OVERTURN_GRID`` steps up to the lock (or pi), the first
    step that ends below it is bisected (``brentq``).  ``V`` past the unstable equilibrium is
    scanned on the same steps for a higher hump; one found is maximised (bounded Brent)."""
    sg = eq.sign
    lock = eq.theta_lock * (1 - 1e-9)

    def V(x):
        return eq.potential(sg * x)

    xu = eq.theta_unstable
    if not math.isfinite(xu):                       # V rises all the way to the lock
        if not math.isfinite(lock):
            raise SolverError("gravity restores the mechanism at every rotation: it cannot overturn")
        return lock, "locked", V(lock)
    barrier, hump = V(xu), None
    hi = min(lock, math.pi)
    prev, v_prev = xu, barrier
    for i in range(1, OVERTURN_GRID + 1):
        x = xu + (hi - xu) * i / OVERTURN_GRID
        v = V(x)
        if v <= level:
            top = brentq(lambda y: V(y) - level, prev, x, xtol=1e-15, rtol=1e-14)
            break
        if v > barrier and (hump is None or v > hump[1]):
            hump = (x, v)
        prev, v_prev = x, v
    else:
        if hi < lock:
            raise SolverError(f"the mechanism neither falls to the overturning level nor locks up to a rotation "
                              f"of pi (V = {v_prev:g} J/m at pi, level {level:g} J/m)")
        top = lock
    if hump is not None:                            # a higher hump past the unstable equilibrium
        from scipy.optimize import minimize_scalar

        step = (hi - xu) / OVERTURN_GRID
        r = minimize_scalar(lambda y: -V(y), bounds=(max(xu, hump[0] - step), min(top, hump[0] + step)),
                            method="bounded", options={"xatol": 1e-12})
        barrier = max(hump[1], -float(r.fun))
    return float(top), ("overturn" if top < lock else "locked"), float(barrier)

