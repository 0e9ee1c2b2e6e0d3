"""Arches on moving supports: a support movement followed to collapse, quasi-statically, with
finite displacements of rigid pieces (docs/supports.md).

The member is a chain of ``n`` rigid pieces (voussoirs, or the elements of the continuous arch)
between two abutments, joined at ``J = n + 1`` joints; no sliding, no crushing, no tension.  One
abutment (or both) moves by ``delta`` times a fixed direction: ``spread`` (each support moves
outward by ``delta / 2``), ``settle`` (the right support moves down by ``delta``) or ``move`` (the
right or the left support moves by ``delta`` along a unit vector).

**Kinematics.**  A joint ``j`` is closed, or open by a finite rotation ``theta_j`` (rad,
counter-clockwise, right piece relative to the left one) about its pivot ``p_j``: the intrados
point when ``theta_j < 0``, the extrados point when ``theta_j > 0`` (the fibre on the other side
opens).  Piece ``e`` (between joints ``e`` and ``e + 1``) is placed by the composition of exact
rigid rotations ``g_e = T(u_L) o rho_0 o ... o rho_e``, ``rho_j(X) = R(theta_j)(X - p_j) + p_j``:
``g_e(X) = R(phi_e) X + c_e`` with ``phi_e = sum_{j<=e} theta_j`` and
``c_e = u_L + sum_{j<=e} (R(phi_{j-1}) - R(phi_j)) p_j``.  The right abutment is ``g_n``: the
closure ``phi_n = 0``, ``c_n = u_R`` (three equations) ties the hinge rotations to the support
positions.  With three hinges the closure fixes them (one degree of freedom, driven by
``delta``); it is solved by Newton's method to round-off at every increment (predictor: the
secant of the last two increments).

**Statics on the deformed geometry.**  The unknowns are the force ``(H, V_L)`` and the moment
``M_0`` (about the origin) of the left abutment on the arch; the force across joint ``j`` is
``(H, V_L - W_{<j})`` and its moment ``M_0 - sum_{e<j} W_e x_e``, with the weights ``W_e`` (self
weight, fill, point masses: vertical, at the current centroids ``x_e`` of the pieces that carry
them).  On the current face of joint ``j`` (intrados point ``I``, extrados point ``E``, thickness
``h``) the fibre forces are ``N+ = (M_j - E x F_j) / h`` and ``N- = -(M_j - I x F_j) / h``.  A
closed joint needs ``N+ >= 0`` and ``N- >= 0``; an open one carries its force at the pivot: the
other fibre's force is zero and the normal force at the pivot is ``>= 0``.

**The state compatible with the movement.**  With ``v_L``, ``v_R`` the support velocities per
unit ``delta`` and ``R_L``, ``R_R`` the support reactions on the arch, the virtual work of any
statically admissible state on the actual mechanism ``u`` is
``W . u + R_L . v_L + R_R . v_R = -sum N eps <= 0``, zero for the actual state (its line of
thrust at the pivots of the opening hinges).  So the actual state maximises
``R_L . v_L + R_R . v_R = (v_L - v_R) . (H, V_L) + const`` over the admissible states, a linear
programme in ``(H, V_L, M_0)`` (for spreading: the minimum thrust); its duals are the opening
rates of the mechanism.  At the start (every joint closed) this picks the hinges; afterwards
the open hinges are equality rows and the LP checks the state and certifies it (margin LP:
``max tau`` with every inequality row ``>= tau``; ``tau < 0`` is a certificate that the
deformed arch cannot stand in this hinge configuration).

**Events.**  Along the three-hinge path the line of thrust moves; when it reaches an edge of a
closed joint (the margin of that row is zero, located by root finding in the increment) a
fourth hinge forms.  The four-hinge chain has one degree of freedom with the supports held;
its equilibrium is stationary (the line of thrust through the four pivots) and its stability
is the sign of the second derivative of the potential energy along it: negative, the pieces
form a mechanism under gravity alone, the arch collapses (the edge reached last is reported);
positive, the path goes on with four hinges (equilibrium through the four pivots imposed by
Newton's method on closure plus stationarity) until one of the older hinges closes: the hinge
has migrated; negative, the new hinge takes the rotation of an older one when that three-hinge
state is admissible and lower in energy (a snap-through migration), else the arch collapses;
rows at their edge at the same displacement (the mirror image of the new hinge on a symmetric
arch) are events of their own, handled next, not a bar to the snap.  On the continuous arch a hinge reaching the joint next to it on the same side rolls onto it
(the element between them stands for a thin slice of the continuum).  A hinge that closes
hands the choice back to the LP on the deformed geometry.  An open hinge whose pivot force reaches zero, and three collinear pivots (the
thrust becomes unbounded), are collapses too.
"""
from __future__ import annotations

import math
import time
from dataclasses import dataclass, field

import highspy
import numpy as np

from ..errors import InputError, SolverError
from ..fem import nodes_through, uniform_nodes
from ..geometry import MidCurve
from ..units import GRAVITY, kN
from .load_factor import mass_nodes
from .lp import HIGHS_OPTIONS, first_highs
from .sizes import MAX_ELEMENTS, MIN_ELEMENTS, check_count
from .snaps import dynamic_snap

__all__ = ["Movement", "SupportsResult", "Chain", "supports", "MOVEMENTS", "SNAP_MODELS", "DEFAULT_STEPS",
           "MAX_STEPS"]

MOVEMENTS = ("spread", "settle", "move")
SNAP_MODELS = ("dynamic", "static")     # where a snap-through ends: the simulated pieces at rest, or the next joint
DEFAULT_STEPS = 200
MAX_STEPS = 100_000
MIN_VOUSSOIRS_SUPPORTS = 2     # a single block cannot follow a support movement on two pivots
DEFAULT_REACH = 0.5            # without --up-to: followed up to this fraction of the span
NEWTON_TOL = 1e-13             # closure residual (rad, and m / span)
ROW_TOL = 1e-9                 # margin (units of the total weight) below which a row is at its edge
EVENT_TOL = 1e-12              # displacement tolerance of the events (fraction of the span)


@dataclass(frozen=True)
class Movement:
    """A support movement per unit displacement ``delta`` (m): the velocities ``v_L``, ``v_R``
    (2,) of the left and right abutments; ``kind`` (``spread``, ``settle``, ``move``),
    ``direction`` (unit vector of the moving support; spreading: the right support's) and
    ``left`` (the left support moves)."""

    kind: str
    direction: tuple
    left: bool = False

    @classmethod
    def of(cls, kind: str, vector=None, left: bool = False) -> "Movement":
        """``kind`` ``"spread"``, ``"settle"`` or ``"move"`` (with ``vector`` ``(dx, dy)``, any
        length > 0: only its direction is used); InputError otherwise."""
        if kind not in MOVEMENTS:
            raise InputError(f"unknown movement {kind!r}: expected one of {', '.join(MOVEMENTS)}")
        if kind == "spread":
            if left:
                raise InputError("spreading moves both supports apart symmetrically: --left does not apply")
            if vector is not None:
                raise InputError("spreading has a fixed direction: no vector")
            return cls("spread", (1.0, 0.0), False)
        if kind == "settle":
            if vector is not None:
                raise InputError("settlement has a fixed direction (down): no vector")
            return cls("settle", (0.0, -1.0), bool(left))
        try:
            dx, dy = (float(v) for v in vector)
        except (TypeError, ValueError):
            raise InputError(f"a movement needs a vector DX,DY (m), got {vector!r}") from None
        if not (math.isfinite(dx) and math.isfinite(dy)):
            raise InputError(f"the movement DX,DY must be finite, got {dx!r},{dy!r}")
        size = math.hypot(dx, dy)
        if not size > 0 or not math.isfinite(size):
            raise InputError(f"the movement DX,DY must have a non-zero finite length, got {dx!r},{dy!r}")
        return cls("move", (dx / size, dy / size), bool(left))

    @property
    def velocities(self) -> tuple[np.ndarray, np.ndarray]:
        d = np.array(self.direction, float)
        if self.kind == "spread":
            return -0.5 * d, 0.5 * d
        return (d, np.zeros(2)) if self.left else (np.zeros(2), d)

    @property
    def moving(self) -> str:
        return "left" if self.left else "right"

    def describe(self) -> dict:
        what = {"spread": "span increase (each support moves outward by half of it)",
                "settle": f"settlement of the {self.moving} support",
                "move": f"length of the {self.moving} support's displacement along ({self.direction[0]:.6g}, "
                        f"{self.direction[1]:.6g})"}[self.kind]
        return {"kind": self.kind, "direction": list(self.direction), "moving_support": "both" if self.kind == "spread"
                else self.moving, "displacement_means": what}


def _rot(phi: np.ndarray) -> np.ndarray:
    """Rotation matrices ``(2, 2, k)`` of the angles ``phi`` (k,)."""
    c, s = np.cos(phi), np.sin(phi)
    return np.array([[c, -s], [s, c]])


def _apply(R: np.ndarray, X: np.ndarray) -> np.ndarray:
    """``R[:, :, k] @ X[:, k]`` for every ``k``."""
    return np.einsum("ijk,jk->ik", R, X)


class Chain:
    """The reference geometry of the pieces of ``curve`` between the nodes ``nodes`` (m): joint
    points ``X``, tangents ``t``, normals ``n``, thicknesses ``h``, intrados and extrados points
    ``I``, ``E`` (2, J), the weights ``W`` (kg/m: per unit g) and centroids ``C`` (2, n) of the
    pieces, and the length scale ``L`` (the span, m)."""

    def __init__(self, curve: MidCurve, nodes: np.ndarray):
        self.curve, self.nodes = curve, np.asarray(nodes, float)
        s = self.nodes
        self.X, self.t, self.n = curve.position(s), curve.tangent(s), curve.normal(s)
        self.h = np.broadcast_to(np.asarray(curve.thickness_at(s), float), s.shape).copy()
        self.I = self.X + 0.5 * self.h * self.n
        self.E = self.X - 0.5 * self.h * self.n
        m, S, _ = curve.segment_inertia(s[:-1], s[1:])
        if not np.all(m > 0):
            raise InputError("every piece must have a positive mass")
        self.W = np.asarray(m, float)
        self.C = np.asarray(S, float) / self.W
        self.Wtot = float(self.W.sum())
        self.Wc = np.concatenate([[0.0], np.cumsum(self.W)])     # weight left of each joint
        self.L = float(abs(self.X[0, -1] - self.X[0, 0])) or float(curve.length)
        self.J = s.size

    @property
    def span(self) -> float:
        """Horizontal distance between the springings' mid-curve points (m)."""
        return float(abs(self.X[0, -1] - self.X[0, 0]))

    # ------------------------------------------------------------------ kinematics
    def pivots(self, side: np.ndarray) -> np.ndarray:
        """Reference pivot points (2, J): intrados where ``side > 0``, extrados where ``< 0``
        (:attr:`~fembeam.mechanisms.hinge.Side.code`), the mid-curve point elsewhere."""
        return np.where(side > 0, self.I, np.where(side < 0, self.E, self.X))

    def place(self, theta: np.ndarray, side: np.ndarray, uL: np.ndarray):
        """Placements ``(phi, c)`` of the pieces right of every joint (``J`` of them: the last is
        the right abutment): ``g_j(X) = R(phi_j) X + c_j``; and the current pivots (2, J)."""
        p = self.pivots(side)
        phi = np.cumsum(theta)
        Rj = _rot(phi)
        Rprev = _rot(np.concatenate([[0.0], phi[:-1]]))
        terms = _apply(Rprev, p) - _apply(Rj, p)
        c = uL[:, None] + np.cumsum(terms, axis=1)
        P = _apply(Rj, p) + c
        return phi, c, Rj, P

    def closure(self, theta, side, uL, uR) -> np.ndarray:
        """``(phi_n, (c_n - u_R) / L)``: zero when the chain meets the right abutment."""
        phi, c, _, _ = self.place(theta, side, uL)
        return np.array([phi[-1], (c[0, -1] - uR[0]) / self.L, (c[1, -1] - uR[1]) / self.L])

    def closure_jacobian(self, theta, side, uL, hinges: np.ndarray) -> np.ndarray:
        """``d closure / d theta_j`` (3, m) for the hinge joints ``hinges``: a rotation at joint
        ``j`` turns everything right of it about its current pivot."""
        phi, c, _, P = self.place(theta, side, uL)
        d = c[:, -1:] - P[:, hinges]
        return np.vstack([np.ones(hinges.size), -d[1] / self.L, d[0] / self.L])

    def centroids(self, theta, side, uL) -> np.ndarray:
        """Current centroids (2, n) of the pieces (m)."""
        phi, c, Rj, _ = self.place(theta, side, uL)
        return _apply(Rj[:, :, :-1], self.C) + c[:, :-1]

    def potential(self, theta, side, uL) -> float:
        """``sum W_e y_e`` (kg m / m per unit g)."""
        return float(self.W @ self.centroids(theta, side, uL)[1])

    def gravity_gradient(self, theta, side, uL, hinges: np.ndarray) -> np.ndarray:
        """``dV / d theta_j`` for the hinge joints, in units of ``W_tot L``: a rotation at joint
        ``j`` lifts piece ``e >= j`` by ``x_e - x_pivot``."""
        phi, c, Rj, P = self.place(theta, side, uL)
        x = _apply(Rj[:, :, :-1], self.C)[0] + c[0, :-1]
        Wx = np.concatenate([np.cumsum((self.W * x)[::-1])[::-1], [0.0]])   # sum over e >= j
        Wr = np.concatenate([np.cumsum(self.W[::-1])[::-1], [0.0]])
        return (Wx[hinges] - Wr[hinges] * P[0, hinges]) / (self.Wtot * self.L)

    # ------------------------------------------------------------------ statics
    def rows(self, theta, side, uL) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Fibre rows on the deformed geometry: ``A`` (2 J, 3), ``b`` (2 J) with ``N+ / W_tot``
        of every joint, then ``N- / W_tot``, equal to ``A z + b`` for
        ``z = (H / W_tot, V_L / W_tot, M_0 / (W_tot L))``; and the normal rows ``(J, 4)``
        (``A`` then ``b``) of the force across each joint along its current tangent."""
        phi, c, Rj, _ = self.place(theta, side, uL)
        I = _apply(Rj, self.I) + c
        E = _apply(Rj, self.E) + c
        t = _apply(Rj, self.t)
        x = _apply(Rj[:, :, :-1], self.C)[0] + c[0, :-1]
        Mw = np.concatenate([[0.0], np.cumsum(self.W * x)]) / self.Wtot          # (J,)  moment of the weights left
        Wc = self.Wc / self.Wtot
        L, h = self.L, self.h
        Ap = np.column_stack([E[1], -E[0], np.full(self.J, L)]) / h[:, None]
        bp = (-Mw + E[0] * Wc) / h
        Am = -np.column_stack([I[1], -I[0], np.full(self.J, L)]) / h[:, None]
        bm = -(-Mw + I[0] * Wc) / h
        normal = np.column_stack([t[0], t[1], np.zeros(self.J), -t[1] * Wc])
        return np.vstack([Ap, Am]), np.concatenate([bp, bm]), normal

    def section_rows(self, theta, side, uL, s: np.ndarray, piece: np.ndarray):
        """Fibre rows ``(A, b)`` (2 k, 3), (2 k) of the sections at the reference arc lengths
        ``s`` (m) inside the pieces ``piece`` (moved with them), ``N+`` then ``N-`` as in
        :meth:`rows`: from the equilibrium of the part left of each section (the weight of the
        piece left of it at the centroid of that part)."""
        phi, c, Rj, _ = self.place(theta, side, uL)
        s, piece = np.asarray(s, float), np.asarray(piece, int)
        curve = self.curve
        R, cc = Rj[:, :, piece], c[:, piece]
        hs = np.broadcast_to(np.asarray(curve.thickness_at(s), float), s.shape)
        I = _apply(R, curve.point(s, 0.5 * hs)) + cc
        E = _apply(R, curve.point(s, -0.5 * hs)) + cc
        m, S, _ = curve.segment_inertia(self.nodes[piece], s)
        x = _apply(Rj[:, :, :-1], self.C)[0] + c[0, :-1]
        Mw_e = np.concatenate([[0.0], np.cumsum(self.W * x)])[piece]
        Mw = (Mw_e + _apply(R, S)[0] + m * cc[0]) / self.Wtot
        Wc = (self.Wc[piece] + m) / self.Wtot
        L, k = self.L, s.size
        Ap = np.column_stack([E[1], -E[0], np.full(k, L)]) / hs[:, None]
        bp = (-Mw + E[0] * Wc) / hs
        Am = -np.column_stack([I[1], -I[0], np.full(k, L)]) / hs[:, None]
        bm = -(-Mw + I[0] * Wc) / hs
        return np.vstack([Ap, Am]), np.concatenate([bp, bm])


# ---------------------------------------------------------------------- the LP
@dataclass
class _LP:
    status: str            # "optimal" or "infeasible"
    z: np.ndarray
    y: np.ndarray          # duals of the inequality rows (>= 0), of the equality rows (free)
    margin: float          # max tau: every inequality row >= tau (units of the total weight)
    residual: float = 0.0


def _highs(nv: int, lo, up, cost) -> "highspy.Highs":
    first_highs()
    h = highspy.Highs()
    for k, v in HIGHS_OPTIONS.items():
        h.setOptionValue(k, v)
    h.addVars(nv, np.asarray(lo, float), np.asarray(up, float))
    h.changeColsCost(nv, np.arange(nv, dtype=np.int32), -np.asarray(cost, float))     # HiGHS minimises
    return h


def _add(h, A, lo, up) -> None:
    n, nv = A.shape
    if n == 0:
        return
    if not (np.all(np.isfinite(A)) and np.all(np.isfinite(lo))):
        raise SolverError("supports LP: a row is not finite")
    h.addRows(n, np.asarray(lo, float), np.asarray(up, float), n * nv, np.arange(0, n * nv, nv, dtype=np.int32),
              np.tile(np.arange(nv, dtype=np.int32), n), np.ascontiguousarray(A, float).ravel())


ZBOX = 1e7   # bound on the normalised unknowns (a thrust of 1e7 weights: an arch flattened to a line)


def _run(h, what: str):
    h.run()
    st = h.getModelStatus()
    if st != highspy.HighsModelStatus.kOptimal:
        raise SolverError(f"supports LP ({what}): HiGHS returned {h.modelStatusToString(st)}")
    sol = h.getSolution()
    return np.array(sol.col_value), np.array(sol.row_dual)


def solve_state(c: np.ndarray, A: np.ndarray, b: np.ndarray, eq: np.ndarray) -> _LP:
    """``max c.z`` s.t. ``A z + b >= 0`` on the rows not in ``eq`` and ``= 0`` on those in ``eq``
    (bool mask), after the margin LP ``max tau`` s.t. ``A z + b >= tau`` (inequalities),
    ``A z + b = 0`` (equalities), ``tau <= 1``: with ``tau < 0`` the rows admit no state
    (status ``"infeasible"``, the margin LP's duals are the certificate: a mechanism under
    gravity alone).  Checked: status, the rows at the solution, dual residual and gap."""
    ineq = ~eq
    nv = A.shape[1]
    scale = max(1.0, float(np.max(np.abs(A))))
    if eq.sum() >= nv and np.linalg.matrix_rank(A[eq], tol=1e-10 * scale) == nv:
        # the equality rows fix the state (three open hinges or more): the LP's feasible set is at
        # most one point, computed directly (HiGHS's tolerances would judge a vertex at the edge)
        z, *_ = np.linalg.lstsq(A[eq], -b[eq], rcond=None)
        eq_res = float(np.max(np.abs(A[eq] @ z + b[eq])))
        if eq_res > 1e-9 * max(1.0, float(np.max(np.abs(z)))):
            return _LP("infeasible", z, np.zeros(A.shape[0]), -eq_res)
        r = A[ineq] @ z + b[ineq]
        tau = float(np.min(r, initial=1.0))
        y = np.zeros(A.shape[0])
        ye, *_ = np.linalg.lstsq(A[eq].T, -c, rcond=None)    # opening rates of the mechanism (A^T y = -c)
        y[np.flatnonzero(eq)] = ye
        if tau < -ROW_TOL:
            return _LP("infeasible", z, y, tau)
        return _LP("optimal", z, y, tau, float(np.max(np.abs(A[eq].T @ ye + c))))
    h = _highs(nv + 1, [-ZBOX] * nv + [-ZBOX], [ZBOX] * nv + [1.0], np.r_[np.zeros(nv), 1.0])
    _add(h, np.column_stack([A[ineq], -np.ones(ineq.sum())]), -b[ineq], np.full(ineq.sum(), highspy.kHighsInf))
    _add(h, np.column_stack([A[eq], np.zeros(eq.sum())]), -b[eq], -b[eq])
    zt, yt = _run(h, "margin")
    # the margin at HiGHS's state (its own tau carries the solver's absolute tolerances)
    tau = max(float(zt[-1]), float(np.min(A[ineq] @ zt[:nv] + b[ineq], initial=1.0)))
    if np.any(np.abs(zt[:nv]) > 0.5 * ZBOX):
        raise SolverError("supports LP: the state exceeds 1e6 weights (collinear pivots?)")
    if tau < -ROW_TOL:
        y = np.zeros(A.shape[0])
        y[np.flatnonzero(ineq)] = yt[:ineq.sum()]
        y[np.flatnonzero(eq)] = yt[ineq.sum():]
        return _LP("infeasible", zt[:nv], np.abs(y) * np.sign(y), tau)
    h = _highs(nv, [-ZBOX] * nv, [ZBOX] * nv, c)
    slack = min(tau, 0.0) - 1e-12        # a state at the edge (an event located to round-off) stays feasible
    _add(h, A[ineq], -b[ineq] + slack, np.full(ineq.sum(), highspy.kHighsInf))
    _add(h, A[eq], -b[eq], -b[eq])
    z, yd = _run(h, "state")
    y = np.zeros(A.shape[0])
    y[np.flatnonzero(ineq)] = yd[:ineq.sum()]
    y[np.flatnonzero(eq)] = yd[ineq.sum():]
    r = A @ z + b
    worst = max(-float(np.min(r[ineq], initial=np.inf)) + slack, float(np.max(np.abs(r[eq]), initial=0.0)))
    if worst > 1e-7 * max(1.0, float(np.max(np.abs(z)))):
        raise SolverError(f"supports LP: the state violates a row by {worst:.2e} weights")
    # duals: HiGHS minimises -c.z with rows A z >= -b: A^T y = -c on the optimum
    dual_res = float(np.max(np.abs(A.T @ y + c))) / max(1.0, float(np.max(np.abs(c))))
    if dual_res > 1e-7 * scale:
        raise SolverError(f"supports LP: dual residual {dual_res:.2e}")
    return _LP("optimal", z, y, tau, dual_res)


# ---------------------------------------------------------------------- the path
@dataclass
class SupportsResult:
    """A support movement followed to collapse (see the module docstring); lengths in m,
    forces in kN per metre of width.

    ``outcome``: ``"collapsed"`` (the arch became a mechanism under gravity), ``"reached_up_to"``
    (it stood up to the requested displacement) or ``"cannot_stand"`` (not even at rest).
    ``capacity``: the displacement at collapse (None unless collapsed).  ``path``: rows
    ``(delta, H, V_left, V_right)``; ``hinges``: the hinges at the start (joint, side, angle);
    ``migrations``: hinges that formed on the way without collapsing it (joint, side, the
    displacement, and the joint whose hinge closed, when it did); ``last_edge``: the joint and
    side reached at collapse.  ``snaps``: the snap-throughs followed by the dynamics
    (``snap_model`` ``"dynamic"``): the displacement, the hinges ``opened``, how it ``ended``
    (``"rest"`` or ``"collapse"``), its duration ``time`` (s), the energy ``dissipated`` by its
    impacts and the ``potential_drop`` from start to rest (J/m, equal up to the simulation's
    energy error), and the ``hinges_after``.  ``frames``: the rotations of the joints at each
    row of ``path`` (for the pictures).

    Examples
    --------
    :func:`supports` returns it; spreading the supports of the paper's arch of 12
    voussoirs, from the passive thrust ``H_min`` (kN/m) to collapse at a displacement
    ``capacity`` (m):

    >>> import fembeam
    >>> from fembeam.analysis.supports import Movement, supports
    >>> arch = fembeam.CircularArch(radius=1.0, thickness=0.15, embrace_deg=157.5)
    >>> res = supports(arch, Movement.of("spread"), voussoirs=12)
    >>> share = res.capacity_over_span
    >>> print(res.outcome, f"at {res.capacity:.4f} m, {share:.2%} of the span")
    collapsed at 0.1965 m, 10.02% of the span
    >>> print(f"H_min = {res.H_min:.3f} kN/m;", [h["angle_deg"] for h in res.hinges])
    H_min = 1.612 kN/m; [26.25, 78.75, 131.25]
    """

    geometry: dict
    movement: Movement
    mode: str
    n: int
    steps: int
    up_to: float | None
    span: float
    outcome: str = "collapsed"
    capacity: float | None = None
    hinges: list = field(default_factory=list)
    migrations: list = field(default_factory=list)
    last_edge: dict | None = None
    collapse: dict = field(default_factory=dict)
    path: list = field(default_factory=list)
    frames: list = field(default_factory=list)
    verification: dict = field(default_factory=dict)
    timings: dict = field(default_factory=dict)
    chain: Chain | None = None
    H_min: float | None = None
    snaps: list = field(default_factory=list)
    snap_model: str = "dynamic"

    @property
    def capacity_over_span(self) -> float | None:
        return None if self.capacity is None else self.capacity / self.span

    def to_dict(self) -> dict:
        def num(v):
            return None if v is None or not math.isfinite(v) else float(v)
        return {
            "outcome": self.outcome,
            "capacity": num(self.capacity),
            "capacity_over_span": num(self.capacity_over_span),
            "hinges": self.hinges,
            "migrations": self.migrations,
            "snaps": self.snaps,
            "last_edge": self.last_edge,
            "collapse": self.collapse,
            "path": [{"displacement": num(d), "H": num(H), "V": num(Vr if not self.movement.left else Vl),
                      "V_left": num(Vl), "V_right": num(Vr)} for d, H, Vl, Vr in self.path],
            "units": {"capacity": "m", "displacement": "m", "H": "kN/m", "V": "kN/m", "V_left": "kN/m",
                      "V_right": "kN/m", "span": "m", "angle_deg": "deg", "H_min": "kN/m", "snaps.time": "s",
                      "snaps.dissipated": "J/m", "snaps.potential_drop": "J/m"},
            "span": self.span,
            "H_min": num(self.H_min),
            "settings": {"movement": self.movement.describe(), "mode": self.mode,
                         ("voussoirs" if self.mode == "voussoirs" else "elements"): self.n,
                         "steps": self.steps, "up_to": num(self.up_to), "snaps": self.snap_model,
                         "geometry": self.geometry},
            "verification": {k: float(v) for k, v in self.verification.items()},
        }

    def csv_rows(self) -> list[dict]:
        return [{"displacement_m": d, "H_kN_per_m": H, "V_left_kN_per_m": Vl, "V_right_kN_per_m": Vr,
                 "hinges": f[2]} for (d, H, Vl, Vr), f in zip(self.path, self.frames)]

    def placed(self, i: int, samples: int = 6) -> list[np.ndarray]:
        """Outlines ``(2, k)`` (m) of the pieces at the row ``i`` of the path (extrados then
        intrados back), each moved rigidly with its piece."""
        ch = self.chain
        d, th, _, side, _ = self.frames[i]
        uL, _ = self.movement_supports(d)
        phi, c, Rj, _ = ch.place(th, side, uL)
        curve = ch.curve
        out = []
        for e in range(ch.J - 1):
            s = np.linspace(ch.nodes[e], ch.nodes[e + 1], samples)
            h = curve.thickness_at(s)
            pts = np.hstack([curve.point(s, -0.5 * h), curve.point(s[::-1], 0.5 * h[::-1])])
            out.append(Rj[:, :, e] @ pts + c[:, e:e + 1])
        return out

    def movement_supports(self, d: float):
        vL, vR = self.movement.velocities
        return vL * d, vR * d

    def thrust_points(self, i: int) -> np.ndarray:
        """Points (2, J) (m) where the line of thrust crosses the joints at the row ``i`` (the
        centre of the fibre forces on each current face)."""
        ch = self.chain
        d, th, _, side, z = self.frames[i]
        uL, _ = self.movement_supports(d)
        A, b, _ = ch.rows(th, side, uL)
        N = A @ z + b
        Np, Nm = N[:ch.J], N[ch.J:]
        phi, c, Rj, _ = ch.place(th, side, uL)
        I = np.einsum("ijk,jk->ik", Rj, ch.I) + c
        E = np.einsum("ijk,jk->ik", Rj, ch.E) + c
        tot = np.where(np.abs(Np + Nm) > 1e-300, Np + Nm, 1.0)
        return (Np * I + Nm * E) / tot


class _Path:
    """The state followed along the displacement: rotations ``theta`` (J,), pivot sides
    ``side`` (J,: +1 intrados, -1 extrados, 0 closed) and the hinge joints."""

    def __init__(self, chain: Chain, mv: Movement, continuous: bool = False):
        self.ch, self.mv = chain, mv
        self.continuous = continuous
        self.vL, self.vR = mv.velocities
        self.c = np.r_[self.vL - self.vR, 0.0]          # objective on (H, V_L, M_0) (normalised)
        self.theta = np.zeros(chain.J)
        self.side = np.zeros(chain.J, int)
        self.lam = np.zeros(3)
        self.snaps = "static"

    def supports_at(self, d: float):
        return self.vL * d, self.vR * d

    @property
    def hinges(self) -> np.ndarray:
        return np.flatnonzero(self.side != 0)

    # -------------------------------------------------------------- kinematics at a displacement
    def solve(self, d: float, theta0: np.ndarray, side: np.ndarray, lam0=None):
        """Rotations (and, with more than three hinges, the multipliers of the closure) at the
        displacement ``d`` for the pivot sides ``side``, from the guess ``theta0``: Newton on the
        closure (three hinges) or on closure and stationarity of the potential energy (more);
        None when it does not converge (a singular configuration)."""
        ch = self.ch
        uL, uR = self.supports_at(d)
        hs = np.flatnonzero(side != 0)
        m = hs.size
        th = theta0.copy()
        lam = np.zeros(3) if lam0 is None else lam0.copy()
        for _ in range(40):
            r1 = ch.closure(th, side, uL, uR)
            Jc = ch.closure_jacobian(th, side, uL, hs)
            if m == 3:
                try:
                    dx = np.linalg.solve(Jc, -r1)
                except np.linalg.LinAlgError:
                    return None
                if np.linalg.cond(Jc) > 1e12:
                    return None
                th[hs] += dx
                if np.max(np.abs(dx)) < NEWTON_TOL and np.max(np.abs(r1)) < 1e3 * NEWTON_TOL:
                    r1 = ch.closure(th, side, uL, uR)
                    if np.max(np.abs(r1)) < 1e-12:
                        g = ch.gravity_gradient(th, side, uL, hs)
                        lam = np.linalg.solve(Jc.T, g)
                        return th, lam
            else:
                r2 = ch.gravity_gradient(th, side, uL, hs) - Jc.T @ lam
                K = self._hessian(th, side, uL, hs, lam)
                Mx = np.block([[Jc, np.zeros((3, 3))], [K, -Jc.T]])
                rhs = -np.r_[r1, r2]
                try:
                    dx = np.linalg.solve(Mx, rhs)
                except np.linalg.LinAlgError:
                    return None
                if not np.all(np.isfinite(dx)) or np.linalg.cond(Mx) > 1e13:
                    return None
                th[hs] += dx[:m]
                lam += dx[m:]
                if np.max(np.abs(dx)) < NEWTON_TOL and np.max(np.abs(np.r_[r1, r2])) < 1e-11:
                    return th, lam
        return None

    def _hessian(self, th, side, uL, hs, lam, eps=1e-7) -> np.ndarray:
        """Hessian (m, m) of the Lagrangian ``V - lam . closure`` in the hinge rotations (central
        differences of its gradient)."""
        ch = self.ch
        m = hs.size
        K = np.empty((m, m))
        for i, j in enumerate(hs):
            tp, tm = th.copy(), th.copy()
            tp[j] += eps
            tm[j] -= eps
            gp = ch.gravity_gradient(tp, side, uL, hs) - ch.closure_jacobian(tp, side, uL, hs).T @ lam
            gm = ch.gravity_gradient(tm, side, uL, hs) - ch.closure_jacobian(tm, side, uL, hs).T @ lam
            K[:, i] = (gp - gm) / (2 * eps)
        return 0.5 * (K + K.T)

    def reduced_hessian(self, d: float, th: np.ndarray, side: np.ndarray, lam: np.ndarray) -> np.ndarray:
        """Eigenvalues of the Hessian of the potential energy along the free modes (the null space
        of the closure Jacobian): units of ``W_tot L`` per rad^2."""
        ch = self.ch
        uL, _ = self.supports_at(d)
        hs = np.flatnonzero(side != 0)
        Jc = ch.closure_jacobian(th, side, uL, hs)
        _, sv, Vt = np.linalg.svd(Jc)
        Z = Vt[3:].T
        if Z.shape[1] == 0:
            return np.zeros(0)
        K = self._hessian(th, side, uL, hs, lam)
        return np.linalg.eigvalsh(Z.T @ K @ Z)

    # -------------------------------------------------------------- statics at a configuration
    def rows(self, d, th, side):
        uL, _ = self.supports_at(d)
        A, b, normal = self.ch.rows(th, side, uL)
        J = self.ch.J
        eq = np.zeros(2 * J, bool)
        hs = np.flatnonzero(side != 0)
        # an open joint carries its force at the pivot: the other fibre's force is zero
        eq[np.where(side[hs] > 0, J + hs, hs)] = True
        # ... and the normal force at the pivot is >= 0 (its fibre row, in place of the
        # fibre row of the pivot: the same force, N = N+ + N-)
        piv = np.where(side[hs] > 0, hs, J + hs)
        A = A.copy()
        b = b.copy()
        A[piv] = normal[hs, :3]
        b[piv] = normal[hs, 3]
        return A, b, eq

    def margins(self, d, th, side):
        """Margin of every inequality row of the determinate state (three hinges or more: the
        state from the multipliers of the Newton solve is the line through the pivots);
        returned with the state ``z``."""
        A, b, eq = self.rows(d, th, side)
        # the state through the pivots: least squares on the equality rows (exact for 3)
        z, *_ = np.linalg.lstsq(A[eq], -b[eq], rcond=None)
        r = A @ z + b
        r[eq] = np.inf
        return r, z

    def state(self, d, th, side) -> _LP:
        A, b, eq = self.rows(d, th, side)
        return solve_state(self.c, A, b, eq)


def _hinge_dict(ch: Chain, j: int, side: int) -> dict:
    return {"joint": int(j), "side": "intrados" if side > 0 else "extrados",
            "angle_deg": float(ch.curve.angle_deg(ch.nodes[j])), "s": float(ch.nodes[j])}


def _row_joint(ch: Chain, row: int) -> tuple[int, int]:
    """(joint, side of the line of thrust: +1 intrados, -1 extrados) of a fibre row: ``N+ = 0``
    puts the line at the extrados, ``N- = 0`` at the intrados."""
    J = ch.J
    return (row, -1) if row < J else (row - J, +1)


def supports(curve: MidCurve, movement: Movement, elements: int | None = None, voussoirs: int | None = None,
             up_to: float | None = None, steps: int = DEFAULT_STEPS, refine: bool = True,
             snaps: str | None = None) -> SupportsResult:
    """Follow ``movement`` of the supports of ``curve`` (an arch on two abutments, as built: fill
    and masses are dead loads moving with their pieces) from rest to collapse, or to ``up_to``
    (m); see the module docstring.

    Parameters
    ----------
    curve : MidCurve
        The arch (any shape; :func:`~fembeam.geometry.asbuilt.build` for fill and masses).
    movement : Movement
        :meth:`Movement.of` ``("spread")``, ``("settle")`` or ``("move", (dx, dy))``.
    elements, voussoirs : int, optional
        Rigid elements of the continuous arch (hinges at their joints only; default 200) or
        voussoirs of a discrete arch (exact).
    up_to : float, optional
        Stop at this displacement (m) if the arch stands until then; default: follow it to
        collapse (at most half the span).
    steps : int
        Increments up to ``up_to`` (or to half the span): the rows of the path; every event in
        between (a hinge forming, closing, the collapse) is located by root finding.
    refine : bool
        Locate the events inside the increments (default); False: an event is put at the end
        of the increment where it is first seen (the first-order variant of the convergence
        study).
    snaps : {"dynamic", "static"}, optional
        Where a snap-through (an unstable hinge configuration with the supports held) ends:
        ``"dynamic"`` (default for voussoirs), where the rigid-body simulation of the pieces, the
        supports held, comes to rest (:mod:`.snaps`); ``"static"`` (default for the continuous
        arch, whose elements are not pieces), the admissible three-hinge state at the same
        displacement in which the new hinge has taken the rotation of the nearest older one.

    Returns
    -------
    SupportsResult
        Capacity (m and fraction of the span), hinges, migrations, the path of ``H`` and ``V``
        (kN/m), the collapse.
    """
    if not isinstance(curve, MidCurve):
        raise InputError(f"supports needs an arch (e.g. fembeam.CircularArch), got {type(curve).__name__}")
    if not isinstance(movement, Movement):
        raise InputError("movement must be a fembeam.analysis.supports.Movement (Movement.of)")
    if tuple(curve.ends) != ("joint", "joint"):
        raise InputError("a support movement needs an arch on two abutments")
    if elements is not None and voussoirs is not None:
        raise InputError("give either elements (continuous arch) or voussoirs (discrete arch), not both")
    if snaps is not None and snaps not in SNAP_MODELS:
        raise InputError(f"snaps must be one of {', '.join(SNAP_MODELS)}, got {snaps!r}")
    mode = "voussoirs" if voussoirs is not None else "continuous"
    snaps = snaps or ("dynamic" if mode == "voussoirs" else "static")
    n = (check_count(voussoirs, "voussoirs", MIN_VOUSSOIRS_SUPPORTS) if mode == "voussoirs"
         else check_count(200 if elements is None else elements, "elements", MIN_ELEMENTS))
    if isinstance(steps, bool) or not isinstance(steps, (int, np.integer)) or not 1 <= steps <= MAX_STEPS:
        raise InputError(f"the number of steps must be an integer in [1, {MAX_STEPS}], got {steps!r}")
    clock = time.perf_counter()
    nodes = uniform_nodes(curve, n)
    if mode == "continuous" and mass_nodes(curve):
        nodes = nodes_through(nodes, np.array(mass_nodes(curve)), keep=curve.fixed_nodes)
    if mode == "continuous":
        nodes = _continuum_rest_nodes(curve, nodes, movement)
    ch = Chain(curve, nodes)
    span = ch.span
    if up_to is not None:
        up_to = float(up_to)
        if not math.isfinite(up_to) or up_to <= 0:
            raise InputError(f"--up-to must be a positive finite displacement (m), got {up_to!r}")
    reach = up_to if up_to is not None else DEFAULT_REACH * span
    desc = curve.describe() if hasattr(curve, "describe") else {}
    res = SupportsResult(desc, movement, mode, int(nodes.size - 1), int(steps), up_to, span, chain=ch)
    P = _Path(ch, movement, continuous=mode == "continuous")
    P.snaps = res.snap_model = snaps

    # ---------------------------------------------------------------- at rest: the hinges
    A, b, eq = P.rows(0.0, P.theta, P.side)
    lp = solve_state(P.c, A, b, eq)
    if lp.status == "infeasible":
        res.outcome = "cannot_stand"
        res.collapse = {"reason": "the arch cannot stand at rest: no line of thrust fits inside it",
                        "margin_weights": lp.margin}
        res.timings["total"] = time.perf_counter() - clock
        return res
    res.H_min = kN(lp.z[0] * ch.Wtot) if movement.kind == "spread" else None
    side = _candidates(P, 0.0, P.theta, P.side, lp, A, b)
    if np.count_nonzero(side) < 3:
        raise SolverError("supports: fewer than three hinges at rest: the movement cannot be followed "
                          f"({np.count_nonzero(side)} edges reached by the line of thrust)")
    side = _select_hinges(P, 0.0, P.theta, side, reach / steps)
    if side is None:
        raise SolverError("supports: no hinge configuration at rest follows the movement")
    P.side = side
    res.hinges = [_hinge_dict(ch, j, side[j]) for j in P.hinges]
    _record(res, P, 0.0, lp.z)
    res.verification["rest_dual_residual"] = lp.residual

    # ---------------------------------------------------------------- the path
    dstep = reach / steps
    d, th, lam = 0.0, P.theta.copy(), np.zeros(3)
    prev = None
    k = 0
    same = 0               # events in a row at one displacement (the two halves of a symmetric arch)
    while True:
        target = min(reach, (k + 1) * dstep)
        guess = th if prev is None else th + (th - prev[1]) * (target - d) / max(d - prev[0], 1e-300)
        sol = P.solve(target, guess, P.side, lam)
        if sol is None:
            sol = P.solve(target, th, P.side, lam)
        event = None
        if sol is not None:
            th_new, lam_new = sol
            event = _first_event(P, target, th_new, P.side)
        if sol is None or event is not None:
            dn, thn, lamn, what = _locate(P, d, target, th, lam, refine)
            if what is None:       # nothing located inside (the step failed at its end only)
                what = ("singular", None)
            outcome = _handle(res, P, dn, thn, lamn, what)
            if outcome == "collapsed":
                res.outcome = "collapsed"
                res.capacity = dn
                _record(res, P, dn, P.margins(dn, thn, P.side)[1], thn)
                break
            same = same + 1 if dn <= d + EVENT_TOL * span else 0
            if same > 4 * ch.J:
                raise SolverError(f"supports: the events at {dn:.6g} m do not end ({same} in a row)")
            d, th, lam, prev = dn, P.theta.copy(), P.lam.copy(), None
            continue
        prev = (d, th)
        d, th, lam = target, th_new, lam_new
        P.theta, P.lam = th, lam
        k += 1
        st = P.state(d, th, P.side)
        if st.status != "optimal":
            raise SolverError(f"supports: the deformed arch at {d:.6g} m has no admissible state though no edge "
                              f"was reached (margin {st.margin:.2e})")
        _record(res, P, d, st.z, th)
        if d >= reach * (1 - 1e-12):
            res.outcome = "reached_up_to" if up_to is not None else "standing"
            break
    if res.outcome == "standing":
        res.outcome = "reached_up_to"
        res.up_to = reach
    res.timings["total"] = time.perf_counter() - clock
    return res


SNAP = 1e-4            # continuous arch at rest: a hinge this fraction of an element from a node is at the node
SUBSECTIONS = 16        # continuous arch at rest: sections checked per element between the joints


def _continuum_rest_nodes(curve: MidCurve, nodes: np.ndarray, mv: Movement) -> np.ndarray:
    """The mesh ``nodes`` with a node at each hinge of the continuous arch at rest: the state of
    the movement's LP with every section admissible (the rows of the weakest sections between
    the joints added round after round, then each touching section located by a bounded
    scalar minimisation of its margin), so that the hinges at rest are not shifted to the
    nearest joint of the uniform mesh.  The mesh unchanged when the arch cannot stand."""
    from scipy.optimize import minimize_scalar

    ch = Chain(curve, nodes)
    P = _Path(ch, mv)
    th, side, u0 = np.zeros(ch.J), np.zeros(ch.J, int), np.zeros(2)
    A0, b0, eq0 = P.rows(0.0, th, side)
    ne = ch.J - 1
    ell = np.diff(nodes)
    frac = np.arange(1, SUBSECTIONS) / SUBSECTIONS
    sub = (nodes[:-1, None] + ell[:, None] * frac[None, :]).ravel()
    piece = np.repeat(np.arange(ne), frac.size)
    ok = curve.admissible(sub)
    sub, piece = sub[ok], piece[ok]
    As, bs = ch.section_rows(th, side, u0, sub, piece)
    k = sub.size
    extra_s, extra_f = [], []

    def solve():
        if extra_s:
            pc = np.clip(np.searchsorted(nodes, extra_s, side="right") - 1, 0, ne - 1)
            Ae, be = ch.section_rows(th, side, u0, np.array(extra_s), pc)
            m = len(extra_s)
            pick = np.array(extra_f) * m + np.arange(m)
            A, b = np.vstack([A0, Ae[pick]]), np.concatenate([b0, be[pick]])
        else:
            A, b = A0, b0
        return solve_state(P.c, A, b, np.zeros(A.shape[0], bool)), A, b

    for _ in range(30):
        lp, A, b = solve()
        if lp.status != "optimal":
            return nodes
        r = As @ lp.z + bs
        bad = np.flatnonzero(r < -ROW_TOL)
        if bad.size == 0:
            break
        for f in (0, 1):                       # the most violated section of each element and fibre
            rows = bad[(bad >= f * k) & (bad < (f + 1) * k)]
            if rows.size == 0:
                continue
            pcs = piece[rows - f * k]
            for e in np.unique(pcs):
                i = rows[pcs == e][np.argmin(r[rows[pcs == e]])]
                extra_s.append(float(sub[i - f * k]))
                extra_f.append(f)
    else:
        return nodes
    refined = set()
    for _ in range(3):                         # the touching sections located, the LP solved again
        lp, A, b = solve()
        if lp.status != "optimal":
            return nodes
        scale = max(1.0, float(np.max(np.abs(lp.z))))
        r = As @ lp.z + bs
        touching = np.flatnonzero(r <= 1e-7 * scale)
        new_s, new_f = [], []
        for i in touching:
            f, q = divmod(int(i), k)
            e = piece[q]
            lo, hi = max(nodes[e], sub[q] - ell[e] / SUBSECTIONS), min(nodes[e + 1], sub[q] + ell[e] / SUBSECTIONS)

            def margin(x, e=e, f=f):
                Ax, bx = ch.section_rows(th, side, u0, np.array([x]), np.array([e]))
                return float(Ax[f] @ lp.z + bx[f])
            opt = minimize_scalar(margin, bounds=(lo, hi), method="bounded", options={"xatol": 1e-12 * ch.L})
            x = float(opt.x)
            at_bound = min(x - lo, hi - x) <= 1e-6 * ell[e] and not np.any(np.abs(nodes - x) <= 1e-6 * ell[e])
            if at_bound:              # the minimum lies beyond this sub-section's bracket: another row has it
                continue
            new_s.append(x)
            new_f.append(f)
        if not new_s:
            break
        refined.update(range(len(extra_s), len(extra_s) + len(new_s)))
        extra_s += new_s
        extra_f += new_f
    lp, A, b = solve()
    if lp.status != "optimal":
        return nodes
    r = (A @ lp.z + b)[A0.shape[0]:]
    hinge_s = [x for i, (x, v) in enumerate(zip(extra_s, r))
               if i in refined and v <= 1e-7 * max(1.0, float(np.max(np.abs(lp.z))))]
    if not hinge_s:
        return nodes
    pts = np.sort(np.array(hinge_s))
    groups = np.concatenate([[0], np.cumsum(np.diff(pts) > SNAP * np.min(ell))])
    pts = np.array([pts[groups == g].mean() for g in np.unique(groups)])     # one section touched twice
    pts = pts[(pts > 1e-6 * ch.L) & (pts < curve.length * (1 - 1e-6))]
    pts = curve.nearest_section(pts)
    # a touching section is located to ~1e-8 of the length (the margin is quadratic about it):
    # one within SNAP of an element from a node is that node (the key joint of a symmetric arch)
    near = np.abs(pts[:, None] - nodes[None, :]) <= SNAP * np.min(ell)
    pts = np.where(near.any(1), nodes[np.argmax(near, 1)], pts)
    return nodes_through(nodes, pts, keep=tuple(curve.fixed_nodes) + tuple(mass_nodes(curve)))


def _select_hinges(P: _Path, d0: float, th0: np.ndarray, side: np.ndarray, dstep: float) -> np.ndarray | None:
    """The hinge configuration that follows the movement from ``(d0, th0)``: ``side`` holds the
    open hinges (``theta != 0``, kept) and the edges the line of thrust reaches at closed joints
    (``theta = 0``, candidates).  With more than three, the whole set is kept when its free
    modes are stable (e.g. both joints of a symmetric arch's key stone), else the sets of three
    holding every open hinge are tried: the first whose trial step keeps the rotations' signs and
    every row admissible is returned (None: none is)."""
    from itertools import combinations

    hs = np.flatnonzero(side)
    must = [j for j in hs if th0[j] != 0.0]
    d = d0 + min(dstep, 1e-6 * P.ch.span)

    def admissible(sd, full=False):
        h = np.flatnonzero(sd)
        sol = P.solve(d, th0, sd)
        if sol is None:
            return False
        th, lam = sol
        if np.any(th[h] * sd[h] > 1e-15):
            return False
        if full:
            ev = P.reduced_hessian(d, th, sd, lam)
            if not (ev.size and ev.min() > 0):
                return False
        r, _ = P.margins(d, th, sd)
        return r.min() >= -ROW_TOL

    if hs.size == 3:
        return side if admissible(side) else None
    if hs.size > 3 and admissible(side, full=True):
        return side
    free = [j for j in hs if j not in must]
    for extra in combinations(free, 3 - len(must)) if len(must) <= 3 else ():
        s3 = np.zeros_like(side)
        pick = list(must) + list(extra)
        s3[pick] = side[pick]
        if admissible(s3):
            return s3
    return None


def _candidates(P: _Path, d: float, th: np.ndarray, side: np.ndarray, lp: _LP, A, b) -> np.ndarray:
    """``side`` with the edges the line of thrust of the LP state ``lp`` reaches at closed joints
    added (the duals' hinges when the optimum is not degenerate)."""
    ch = P.ch
    J = ch.J
    r = (A @ lp.z + b)[:2 * J]
    scale = max(1.0, float(np.max(np.abs(lp.z))))
    out = side.copy()
    closed = np.concatenate([side == 0, side == 0])
    active = np.flatnonzero((r <= 1e-9 * scale) & closed)
    y = lp.y[:2 * J]
    dual = np.flatnonzero((np.abs(y) > 1e-7 * max(1e-300, float(np.max(np.abs(y))))) & closed)
    for row in (active if active.size + np.count_nonzero(side) > 3 else np.union1d(active, dual)):
        j, sd = _row_joint(ch, row)
        if out[j] == 0:
            out[j] = sd
    return out


def _first_event(P: _Path, d, th, side):
    """What went wrong at ``(d, th)``: a row below its edge (``("row", index)``), a hinge
    closing (``("close", joint)``), or None."""
    r, _ = P.margins(d, th, side)
    if r.min() < -ROW_TOL:
        return ("row", int(np.argmin(r)))
    hs = np.flatnonzero(side)
    wrong = hs[th[hs] * side[hs] > 0]          # rotation past zero: the hinge has closed
    if wrong.size:
        return ("close", int(wrong[0]))
    return None


def _event_value(P: _Path, d, th, side, what):
    if what[0] == "row":
        r, _ = P.margins(d, th, side)
        return float(r.min())
    hs = np.flatnonzero(side)
    return float(np.min(-th[hs] * side[hs]))


def _locate(P: _Path, d0, d1, th0, lam0, refine: bool):
    """The first event in ``(d0, d1]``: bisection on the smallest margin (rows, and hinge
    rotations); returns ``(d, theta, lam, what)`` at the event (``what`` None if no event is
    found before the kinematics fails)."""
    side = P.side

    def at(d, guess, lg):
        sol = P.solve(d, guess, side, lg)
        if sol is None:
            return None
        th, lam = sol
        return th, lam, _first_event(P, d, th, side)

    lo, hi = d0, d1
    th_lo, lam_lo = th0, lam0
    hi_what = None
    tol = EVENT_TOL * P.ch.span
    if not refine:
        got = at(d1, th0, lam0)
        if got is None:
            return d0, th0, lam0, None
        return d1, got[0], got[1], got[2]
    while hi - lo > tol:
        mid = 0.5 * (lo + hi)
        got = at(mid, th_lo, lam_lo)
        if got is None or got[2] is not None:
            hi = mid
            hi_what = None if got is None else got[2]
        else:
            lo, th_lo, lam_lo = mid, got[0], got[1]
    if hi_what is None:
        got = at(hi, th_lo, lam_lo)
        hi_what = None if got is None else got[2]
    if hi_what is None:
        return lo, th_lo, lam_lo, ("singular", None)
    return lo, th_lo, lam_lo, hi_what


def _handle(res: SupportsResult, P: _Path, d, th, lam, what) -> str:
    """Act on an event at ``d``: ``"collapsed"`` or ``"go"`` (the hinge set changed)."""
    ch = P.ch
    kind, idx = what
    P.theta, P.lam = th, lam
    if kind == "singular":
        res.last_edge = None
        res.collapse = {"reason": "the pivots of the mechanism became collinear (the thrust grows without bound)",
                        "displacement": d}
        return "collapsed"
    if kind == "close":
        j = idx
        P.side = P.side.copy()
        P.side[j] = 0
        th = th.copy()
        th[j] = 0.0
        P.theta = th
        opened = [m for m in res.migrations if m.get("closed_joint") is None]
        if opened:                        # a hinge that formed earlier took over from this one
            opened[-1]["closed_joint"] = int(j)
            opened[-1]["closed_at"] = float(d)
            sol = P.solve(d, th, P.side, None)
            if sol is not None and np.count_nonzero(P.side) >= 3:
                P.theta, P.lam = sol
                return "go"
        # the joint has closed: the LP on this geometry (the other hinges at their pivots) picks
        # the state, and the edges its line of thrust reaches the new hinges (a migration)
        A, b, eq = P.rows(d, th, P.side)
        st = solve_state(P.c, A, b, eq)
        if st.status != "optimal":
            res.collapse = {"reason": "after a hinge closed the deformed arch admits no state (margin "
                                      f"{st.margin:.3g} weights)", "displacement": d}
            return "collapsed"
        cand = _candidates(P, d, th, P.side, st, A, b)
        new = _select_hinges(P, d, th, cand, 1e-6 * ch.span)
        if new is None:
            res.collapse = {"reason": f"after the hinge of joint {j} closed no hinge configuration follows the "
                                      "movement", "displacement": d}
            return "collapsed"
        for i in np.flatnonzero((new != 0) & (P.side == 0)):
            res.migrations.append({**_hinge_dict(ch, int(i), int(new[i])), "displacement": float(d),
                                   "closed_joint": int(j), "closed_at": float(d)})
        P.side = new
        return "go"
    # a row reached its edge
    J = ch.J
    row = idx
    j, s = _row_joint(ch, row)
    beside = [a for a in (j - 1, j + 1) if 0 <= a < J and P.side[a] == s]
    if P.continuous and beside:
        # continuous arch: the line of thrust leaves the edge next to an open hinge on the same
        # side; the hinge rolls onto this joint (the rotation passes from the old joint to the
        # new one: the element between them stands for a thin slice of the continuum, compressed
        # between two pivots on one face, which turns over at once at no cost of energy)
        a = beside[0]
        new, th2 = P.side.copy(), th.copy()
        new[j], new[a] = s, 0
        th2[j], th2[a] = th[a], 0.0
        sol = P.solve(d, th2, new, None)
        if sol is not None:
            P.side, (P.theta, P.lam) = new, sol
            res.migrations.append({**_hinge_dict(ch, j, s), "displacement": float(d), "closed_joint": int(a),
                                   "closed_at": float(d), "rolled": True})
            return "go"
    new = P.side.copy()
    new[j] = s
    # stability of the configuration with the new hinge: the free mode with the supports held
    sol = P.solve(d, th, new, None)
    edge = _hinge_dict(ch, j, s)
    if sol is None:
        res.last_edge = edge
        res.collapse = {"reason": "a new hinge formed and the hinge configuration is singular", "displacement": d}
        return "collapsed"
    th2, lam2 = sol
    ev = P.reduced_hessian(d, th2, new, lam2)
    curv = float(ev.min()) if ev.size else 0.0
    if curv <= 0.0:
        # unstable: with the supports held the pieces turn along the free mode, downhill, until an
        # older hinge closes; when that three-hinge state is admissible and lower in energy the
        # hinge has jumped (a snap-through migration: on the continuous arch a hinge rolling over
        # one element), else the arch collapses
        if P.snaps == "dynamic":
            return _dynamic(res, P, d, th, new, j, edge, curv * ch.Wtot * ch.L * GRAVITY / 1000.0)
        snap = _snap(P, d, th, new, j)
        if snap is not None:
            a, side3, th3, lam3 = snap
            P.side, P.theta, P.lam = side3, th3, lam3
            res.migrations.append({**edge, "displacement": float(d), "closed_joint": int(a), "closed_at": float(d),
                                   "snap": True})
            return "go"
        res.last_edge = edge
        res.collapse = {"reason": f"a hinge formed at joint {j} ({edge['side']}, {edge['angle_deg']:.2f} deg): with "
                                  f"the supports held the pieces form a mechanism on which gravity does positive work",
                        "displacement": d, "hinges": [_hinge_dict(ch, i, new[i]) for i in np.flatnonzero(new)],
                        "energy_curvature": curv * ch.Wtot * ch.L * GRAVITY / 1000.0,
                        "energy_curvature_unit": "kJ/m per rad^2 along the free mode"}
        return "collapsed"
    P.side, P.theta, P.lam = new, th2, lam2
    res.migrations.append({**edge, "displacement": float(d), "closed_joint": None, "closed_at": None,
                           "energy_curvature": curv * ch.Wtot * ch.L * GRAVITY / 1000.0})
    return "go"


def _dynamic(res: SupportsResult, P: _Path, d: float, th: np.ndarray, new: np.ndarray, j: int, edge: dict,
             curvature: float) -> str:
    """The snap from the hinge sides ``new`` at ``d`` followed by the rigid-body dynamics with
    the supports held (:mod:`.snaps`): the state where the arch comes to rest (``"go"``), or
    its collapse; ``curvature`` (kJ/m per rad^2) of the potential energy along the free mode."""
    ch = P.ch
    # the other rows at their edge at this displacement (the mirror image of the new hinge on a
    # symmetric arch) open with it
    r0, _ = P.margins(d, th, P.side)
    new = new.copy()
    for a, s in (_row_joint(ch, int(r)) for r in np.flatnonzero(r0 <= ROW_TOL)):
        if new[a] == 0:
            new[a] = s
    opened = [int(a) for a in np.flatnonzero((new != 0) & (P.side == 0))]
    uL, _ = P.supports_at(d)
    end = dynamic_snap(P, d, th, new, opened)
    record = {"displacement": float(d), "opened": [_hinge_dict(ch, a, new[a]) for a in opened],
              "ended": "collapse" if end.collapsed else "rest", "time": end.time, "dissipated": end.dissipated,
              "potential_drop": None, "hinges_after": None}
    res.snaps.append(record)
    if end.collapsed:
        res.last_edge = edge
        res.collapse = {"reason": f"a hinge formed at joint {j} ({edge['side']}, {edge['angle_deg']:.2f} deg) and "
                                  f"the pieces snapped through with the supports held: {end.reason}",
                        "displacement": d, "hinges": [_hinge_dict(ch, i, new[i]) for i in np.flatnonzero(new)],
                        "energy_curvature": curvature, "energy_curvature_unit": "kJ/m per rad^2 along the free mode"}
        return "collapsed"
    side = sol = None
    for side, theta in end.readings:          # the hinges at rest: an admissible state, not the one before
        h = np.flatnonzero(side)
        if h.size < 3 or np.array_equal(side, P.side):
            continue
        sol = P.solve(d, theta, side, None)
        if sol is not None and not np.any(sol[0][h] * side[h] > 0) \
                and np.min(P.margins(d, sol[0], side)[0]) >= -ROW_TOL:
            break
        sol = None
    if sol is None:
        raise SolverError(f"supports: the snap-through at {d:.6g} m came to rest in the simulation in a state that "
                          "is not an admissible hinge configuration of the path (hinges at joints "
                          f"{', '.join(map(str, np.flatnonzero(end.readings[0][0])))}); --snaps static follows "
                          "it without the simulation")
    record["hinges_after"] = [_hinge_dict(ch, i, side[i]) for i in np.flatnonzero(side)]
    record["potential_drop"] = GRAVITY * (ch.potential(th, P.side, uL) - ch.potential(sol[0], side, uL))
    old = np.flatnonzero((P.side != 0) & (side == 0))
    for i in np.flatnonzero((side != 0) & (P.side == 0)):
        same = old[P.side[old] == side[i]]               # the closed hinge of the same side nearest to it
        closed = int(same[np.argmin(np.abs(same - i))]) if same.size else None
        res.migrations.append({**_hinge_dict(ch, int(i), int(side[i])), "displacement": float(d),
                               "closed_joint": closed, "closed_at": None if closed is None else float(d),
                               "snap": True})
    P.side, (P.theta, P.lam) = side, sol
    return "go"


def _snap(P: _Path, d: float, th: np.ndarray, new: np.ndarray, j: int):
    """The three-hinge state at ``d`` where the new hinge ``j`` has taken the rotation of an older
    one (tried in order of distance from ``j``): admissible, the rotations of the right signs
    and the potential energy not above the current one; ``(closed joint, side, theta, lam)`` or
    None."""
    uL, _ = P.supports_at(d)
    V0 = P.ch.potential(th, P.side, uL)
    # rows at their edge before the snap: events at this displacement too (the mirror image of
    # the new hinge on a symmetric arch); the snap may pass them, they are handled next
    r0, _ = P.margins(d, th, P.side)
    edge = r0 <= ROW_TOL
    for a in sorted((i for i in np.flatnonzero(P.side)), key=lambda i: abs(i - j)):
        side3, guess = new.copy(), th.copy()
        side3[a] = 0
        guess[j], guess[a] = (th[a], 0.0) if new[j] == P.side[a] else (0.0, 0.0)
        sol = P.solve(d, guess, side3, None)
        if sol is None:
            continue
        th3, lam3 = sol
        h = np.flatnonzero(side3)
        if np.any(th3[h] * side3[h] > 0) or th3[j] == 0.0:
            continue
        if P.ch.potential(th3, side3, uL) > V0 + 1e-12 * P.ch.Wtot * P.ch.L:
            continue
        r, _ = P.margins(d, th3, side3)
        if np.all((r >= -ROW_TOL) | edge):
            return a, side3, th3, lam3
    return None


def _record(res: SupportsResult, P: _Path, d: float, z: np.ndarray, th=None) -> None:
    ch = P.ch
    W = ch.Wtot
    H, Vl = kN(z[0] * W), kN(z[1] * W)
    Vr = kN(W) - Vl
    res.path.append((float(d), float(H), float(Vl), float(Vr)))
    res.frames.append((float(d), (P.theta if th is None else th).copy(), int(np.count_nonzero(P.side)),
                       P.side.copy(), np.asarray(z, float).copy()))
