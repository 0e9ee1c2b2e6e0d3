"""Coulomb friction at the joints: the theory of the friction rows of the static problem and
of their duals (sliding with associative dilatancy), the limit LP of the continuous member
with friction, the two bounds of the collapse load and the friction each joint requires.
The rows and the jumps of their duals are built in :mod:`~fembeam.analysis.rows`
(:func:`~fembeam.analysis.rows.friction_rows`, :func:`~fembeam.analysis.rows.jumps`), the
hinges and slides of a field in :mod:`~fembeam.mechanisms.hinge`.

Joint forces ``g_j = (S_j, N+_j, N-_j)`` (:mod:`~fembeam.analysis.statics`; shear and
fibre forces, compression positive, units of the total weight).  With a finite
coefficient ``mu`` the admissible forces of a joint form the cone

    N+ >= 0,   N- >= 0,   |S| <= mu (N+ + N-),

written as the fibre rows and two friction rows ``(mu (N+ + N-) -+ S) / (1 + mu)``
(divided by ``1 + mu`` so that they tend to the normal force, not to infinity, for
large ``mu``).  A row ``r`` is ``l_r . g_j``; the duals ``y_r >= 0`` of the rows give
the jump of the velocity field at the joint, ``c_j = sum_r y_r l_r``, i.e. with the duals
``a, b`` of the friction rows::

    sliding  gamma = B_slide u = (b - a) / (1 + mu)
    openings eps+- = B_open u  = y+- + mu (a + b) / (1 + mu)   (>= mu |gamma|)

the associative flow rule: a joint that slides at rate ``gamma`` opens by ``mu |gamma|``
at both fibres (dilatancy).  These jumps lie in the dual cone ``eps+- >= mu |gamma|``
of the admissible forces, on which every admissible force does non-negative work, so
the kinematic theorem holds and the static and kinematic load factors of the optimum
must agree (the duality check of :mod:`~fembeam.analysis.limit`).

Real masonry joints slide without dilatancy: the flow rule is non-associated, the static
theorem does not hold for it, and the associative load factor with ``mu`` is an UPPER bound
of the collapse load of such joints (every collapse state of theirs is an admissible state
of the LP).  A LOWER bound follows from Radenkovic's second theorem: the associative analysis
with a reduced law whose normals contain the real flow; for a cohesionless joint that slides
without dilatancy the reduced coefficient is ``mu* = 0`` (frictionless joints, still
no-tension), :data:`REDUCED_FRICTION` and :func:`lower_bound` (docs/friction.md, section 3).
"""
from __future__ import annotations

import copy

import numpy as np

from ..errors import SolverError
from ..fem import Discretization
from ..geometry import MidCurve
from ..mechanisms.hinge import hinges_and_slides
from .continuum import margin_search, weakest_sections
from .limit import limit_analysis
from .rows import (MAX_FRICTION, STAND_TOL, append_section_rows, check_friction, friction_rows, joint_rows, jumps,
                   main_lp, solve_unboxed)
from .statics import Statics, statics

__all__ = ["mechanism", "required_friction",
           "mass_on_midcurve", "continuum_support", "REDUCED_FRICTION", "UPPER_BOUND", "LOWER_BOUND",
           "EXACT_WITHOUT_FRICTION", "THICKNESS_BOUND", "bound_of", "lower_bound", "bounds"]

# Radenkovic's reduced coefficient of a cohesionless Coulomb joint that slides without
# dilatancy, whatever its mu: the largest cone {|S| <= mu* N} whose normals contain every
# non-dilatant flow (a joint may slide at any N >= 0, N = 0 included) is mu* = 0.
REDUCED_FRICTION = 0.0
UPPER_BOUND = "upper (associative flow; sliding without dilatancy can collapse below it)"
LOWER_BOUND = ("lower (Radenkovic's second theorem: associative analysis with the reduced coefficient mu* = 0 "
               "of a cohesionless joint that slides without dilatancy, i.e. frictionless no-tension joints)")
EXACT_WITHOUT_FRICTION = ("exact (mu = 0: frictionless joints slide without dilatancy in the associative analysis "
                          "too, so both bounds are this analysis and its load factor is the collapse load)")

THICKNESS_BOUND = ("lower (associative flow: a thinner arch has no equilibrium state and collapses whatever the "
                   "flow rule; joints that slide without dilatancy may need a thicker one)")


def bound_of(mu: float | None) -> str | None:
    """What ``A_L`` of a limit analysis with coefficient ``mu`` is for joints that slide
    without dilatancy (None: joints that never slide)."""
    return None if mu is None else (EXACT_WITHOUT_FRICTION if mu == REDUCED_FRICTION else UPPER_BOUND)


def mechanism(st: Statics, c: np.ndarray) -> tuple[np.ndarray, float]:
    """Element velocities with jumps ``c`` (3, J) at the joints and their closure misfit:
    :meth:`~fembeam.analysis.statics.Statics.velocities`."""
    return st.velocities(c)


def required_friction(angle_deg: np.ndarray, s: np.ndarray, shear: np.ndarray, normal: np.ndarray,
                      mu: float | None = None, what: str = "force") -> dict:
    """The friction coefficient each joint (section) needs, ``|shear| / normal``
    (``normal``: the compressive normal force or impulse, >= 0), over the joints carrying
    more than 1e-9 of the largest: its ``max`` and where (``at_deg``: reporting angle,
    ``at_s``: arc length, m; ``joint``: index), and with ``mu`` the joints needing more
    (``above``).  ``max`` is None, with a ``reason``, when no joint carries a ``what``."""
    shear, normal = np.asarray(shear, float), np.asarray(normal, float)
    angle_deg, s = np.asarray(angle_deg, float), np.asarray(s, float)
    carried = normal > 1e-9 * max(np.max(np.abs(normal), initial=0.0), 1e-300)
    out: dict = {"max": None, "at_deg": None, "at_s": None, "joint": None}
    if not carried.any():
        out["reason"] = f"no joint carries a compressive normal {what}"
    else:
        ratio = np.full(normal.shape, -np.inf)
        ratio[carried] = np.abs(shear[carried]) / normal[carried]
        j = int(np.argmax(ratio))
        out.update({"max": float(ratio[j]), "at_deg": round(float(angle_deg[j]), 6), "at_s": float(s[j]),
                    "joint": j})
    if mu is not None:
        above = np.flatnonzero(carried & (np.abs(shear) > mu * (1 + 1e-9) * normal))
        out["above"] = [{"angle_deg": round(float(angle_deg[k]), 6), "s": float(s[k]),
                         "ratio": float(abs(shear[k]) / normal[k])} for k in above]
    return out


def mass_on_midcurve(curve: MidCurve) -> MidCurve:
    """A copy of ``curve`` whose weight acts on the mid-curve (the first moment of every
    slice is ``rho t X`` instead of ``rho (t X - kappa t^3/12 n)``): the simplification
    of Heyman and of much of the literature on minimum thickness, for comparisons.  The
    mass per unit length and the rotary inertia are unchanged; the copy keeps the load
    model when its thickness is scaled."""
    base = type(curve)

    def inertia_densities(self, s, power=None):
        mu0, _, mu2 = base.inertia_densities(self, s, power)
        t = self.thickness_at(s) if power in (None, 1) else np.zeros(np.shape(s))
        return mu0, self.density * t * self.position(s), mu2

    cls = type(f"{base.__name__}MassOnMidCurve", (base,), {"inertia_densities": inertia_densities,
                                                            "__module__": __name__})
    out = copy.copy(curve)
    object.__setattr__(out, "__class__", cls)   # frozen dataclasses: bypass their __setattr__
    return out


def continuum_support(disc: Discretization, direction: int, mu: float, tol: float = 1e-10,
                      max_rounds: int = 50) -> tuple[str, float, np.ndarray]:
    """Limit LP of the continuous member meshed by ``disc`` with friction ``mu``: the fibre
    rows at the joints and, round after round, at the weakest sections between them
    (:func:`~fembeam.analysis.continuum.weakest_sections`), the friction rows at the joints.
    Returns the status (as :class:`~fembeam.analysis.limit.LimitResult`), the load factor
    (g; NaN unless ``"ok"``) and the sections (m) carrying the duals: the hinges and
    slides, where the mesh needs nodes."""
    st = statics(disc)
    k, J = st.k, disc.n_joints
    R = joint_rows(st, direction, mu)
    stand, margin, cuts, fib, _ = margin_search(st, direction, R, np.empty(0), np.empty(0, int), tol, max_rounds)
    lp, status, lam = stand, "cannot_stand", float("nan")
    if stand.value >= -STAND_TOL:
        for _ in range(max_rounds):
            lp = solve_unboxed(main_lp, append_section_rows(R, st, direction, cuts, fib), k)
            if lp.at_bound[k]:
                return "no_mechanism", float("inf"), np.empty(0)
            s_new, f_new, v = weakest_sections(st, np.r_[lp.z[:k], direction * lp.z[k], 1.0])
            keep = v < -tol
            if not keep.any():
                break
            cuts, fib = np.concatenate([cuts, s_new[keep]]), np.concatenate([fib, f_new[keep]])
        else:
            raise SolverError(f"limit analysis with friction: the sections between the joints still need "
                              f"cuts after {max_rounds} rounds")
        status, lam = "ok", float(lp.z[k])
    s_all = np.concatenate([np.tile(disc.joint_s, R.shape[0] // J), cuts])
    w = np.abs(lp.y)
    return status, lam, np.unique(s_all[w > 1e-6 * max(np.max(w), 1e-300)])


def lower_bound(disc: Discretization, direction: int, continuum: bool, verify: bool = True) -> tuple[str, float]:
    """Safe load factor of ``disc`` whose joints slide without dilatancy, whatever their
    coefficient: the associative limit analysis with :data:`REDUCED_FRICTION` (frictionless,
    no-tension joints; Radenkovic's second theorem, docs/friction.md section 3).  Returns the
    status (``"ok"``, ``"cannot_stand"``: no safe load follows, ``"no_mechanism"``: no
    horizontal acceleration collapses it) and the load factor (g; NaN unless ``"ok"``, and
    never below 0).  ``continuum``: the fibre rows are checked between the joints as well
    (:func:`continuum_support`); the shear vanishes at the joints of ``disc`` only."""
    if continuum:
        status, lam, _ = continuum_support(disc, direction, REDUCED_FRICTION)
    else:
        lim = limit_analysis(disc, direction, verify=verify, friction=REDUCED_FRICTION)
        status, lam = lim.status, lim.A_L
    return status, (max(float(lam), 0.0) + 0.0 if status == "ok" else float("nan"))   # + 0.0: no -0.0


def bounds(mu: float, upper: tuple[str, float], lower: tuple[str, float], determinate: bool) -> dict:
    """The JSON ``friction_bounds``: the associative load factor with ``mu`` (``upper``) and
    with :data:`REDUCED_FRICTION` (``lower``), each ``(status, A_L)``, and what is known of
    the collapse load of joints that slide without dilatancy between them."""
    def entry(what, coefficient, status, lam, bound):
        d = {"A_L": float(lam) + 0.0 if status == "ok" else None, "outcome": status, "friction": coefficient,
             "bound": bound}
        if status == "cannot_stand":
            d["reason"] = (f"with {what} the arch cannot stand: " + (
                "no equilibrium state fits, so it collapses under its own weight whatever the flow rule"
                if what == "this coefficient" else "no safe load factor follows from the theorem"))
        elif status == "no_mechanism":
            d["reason"] = (f"with {what} no horizontal acceleration turns the arch into a mechanism"
                           + (": no collapse whatever the flow rule" if coefficient == REDUCED_FRICTION else
                              " with dilatant sliding; joints that slide without dilatancy may still collapse"))
        return d

    out = {"upper": entry("this coefficient", mu, *upper, bound_of(mu)),
           "lower": entry("frictionless joints", REDUCED_FRICTION, *lower, LOWER_BOUND),
           "determinate": bool(determinate)}
    if mu == REDUCED_FRICTION:
        out["known"] = EXACT_WITHOUT_FRICTION
    elif determinate:
        out["known"] = ("statically determinate (no redundants): the joint forces follow from equilibrium alone, "
                        "so the collapse load equals the upper value whatever the flow rule")
    else:
        out["known"] = ("the collapse load of joints that slide without dilatancy lies between lower and upper, "
                        "and no theorem places it closer: it may reach upper or fall well below it; the smallest "
                        "collapse load solves a non-convex problem (a mathematical programme with complementarity "
                        "constraints, docs/friction.md section 3)")
    return out
