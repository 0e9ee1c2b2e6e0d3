"""Equivalent static analysis: the incipient rocking acceleration ``A_L`` (in g) and
its mechanism, on the joints of a discretisation, with certificates.

Static (lower-bound) linear programme in the ``k`` redundants ``x`` of the chain
(:mod:`~fembeam.analysis.statics`) and the load factor ``lambda``::

    maximise lambda   s.t.  N+_j(x, lambda) >= 0,  N-_j(x, lambda) >= 0   (every joint)

with the horizontal acceleration ``direction * lambda g``: both fibre forces of every
joint compressive (the thrust line inside the section), the shear free (no sliding).
``k + 1 <= 4`` unknowns and ``2 J`` rows (:mod:`~fembeam.analysis.rows`), solved by
constraint generation in O(J) (:mod:`~fembeam.analysis.lp`).  Its duals are the opening
rates of the joints: the mechanism ``u`` (element velocities from
:meth:`Statics.velocities`), whose kinematic load factor ``f_y.u / (direction f_x.u)``
must equal the static one (duality gap).

Outcomes, each with its certificate, checked before it is returned:

* ``"ok"``: forces admissible at ``A_L`` and a compatible mechanism with the same load
  factor (static and kinematic theorems agree);
* ``"cannot_stand"``: no admissible state under gravity alone (largest margin
  ``max_x min_j N(x, 0) < 0``); certificate: a compatible mechanism on which gravity
  does positive work (the duals of the margin LP);
* ``"no_mechanism"``: an admissible state under gravity and an admissible ray of
  self-stress plus horizontal load (``N(x0 + lambda dx, lambda) >= 0`` for every
  ``lambda >= 0``): no horizontal acceleration turns the member into a mechanism.

With a finite Coulomb coefficient ``friction = mu`` every joint also gets the rows
``mu (N+ + N-) -+ S >= 0`` (:mod:`~fembeam.analysis.rows`, the theory in
:mod:`~fembeam.analysis.friction`); the duals then give a mechanism that may slide, with
the associative dilatancy ``mu |gamma|`` at both fibres, and the same certificates hold
(the jumps lie in the dual cone of the admissible forces).
Joints that slide without dilatancy may collapse below that ``A_L``: it is an upper bound
for them, and ``friction=0`` gives the lower one (docs/friction.md, section 3).

Forces are per unit g, in kg per metre of width (:func:`fembeam.units.kN` gives kN/m).
"""
from __future__ import annotations

import time
from dataclasses import dataclass, field

import numpy as np

from ..errors import CannotStandError, InputError, SolverError
from ..fem import Discretization
from ..mechanisms.hinge import Hinge, hinges_and_slides
from .lp import FEAS_TOL
from .rows import (BOX, STAND_TOL, XBOX, check_direction, check_friction, joint_rows, jumps, main_lp, ray_lp,
                   solve_unboxed, stand_lp)
from .statics import Statics, section_forces, statics
from .verification import check

__all__ = ["LimitResult", "limit_analysis", "FRICTION_TOL"]

FRICTION_TOL = 1e-6  # friction_excess above which a result with friction fails its check


@dataclass
class LimitResult:
    """Outcome of :func:`limit_analysis`, with its certificate.

    Forces are per unit g, in kg per metre of width (:func:`fembeam.units.kN` gives
    kN/m); fibre forces and shears act at the joints, left to right.

    Attributes
    ----------
    status : {"ok", "cannot_stand", "no_mechanism"}
        ``"ok"``: admissible forces at ``A_L`` and a compatible mechanism with the same
        load factor; ``"cannot_stand"``: no admissible state under gravity alone (the
        mechanism ``u`` is one on which gravity does positive work);
        ``"no_mechanism"``: no horizontal acceleration turns the member into a
        mechanism.
    disc : Discretization
        The mesh analysed.
    direction : {1, -1}
        Direction of the inertia load (+1: along ``+x``).
    A_L : float
        Incipient rocking acceleration (g); NaN unless ``status == "ok"``.
    u : ndarray or None
        The mechanism's element velocities, normalised by its horizontal momentum.
    N : ndarray or None
        ``(2, J)`` fibre forces at the intrados and extrados (kg/m per g, >= 0 in
        compression).
    S : ndarray or None
        ``(J,)`` shear forces (kg/m per g).
    hinges : list of Hinge
        The mechanism's hinges, left to right.
    friction : float or None
        Coulomb coefficient of the joints (None: no sliding).
    slides : list of dict
        Sliding joints of the mechanism (with ``friction`` only).
    margin : float
        ``max_x min_j N(x, 0) / (m g)``: > 0 when the member stands under gravity.
    verification : dict
        The checked figures of the certificate (duality gap, residuals).
    solve_time : float
        Time of the LP solves (s).
    lp_rounds : int
        Rounds of constraint generation.

    Examples
    --------
    :func:`limit_analysis` of a mesh returns it: the load factor ``A_L`` (g), the
    standing margin and the joint forces, in kN/m through :func:`fembeam.units.kN`:

    >>> import fembeam
    >>> from fembeam.units import kN
    >>> arch = fembeam.CircularArch(radius=1.0, thickness=0.15, embrace_deg=157.5)
    >>> disc = fembeam.discretize(arch, fembeam.uniform_nodes(arch, 12))
    >>> lim = fembeam.limit_analysis(disc)
    >>> print(lim.status, f"A_L = {lim.A_L:.4f} g, margin {lim.margin:.4f}")
    ok A_L = 0.3593 g, margin 0.1110
    >>> N = kN(lim.N[0] + lim.N[1])    # normal force at each joint, at A_L
    >>> print(f"{N[0]:.3f} kN/m at the left springing")
    3.639 kN/m at the left springing
    """

    status: str
    disc: Discretization
    direction: int
    A_L: float = float("nan")              # units of g
    u: np.ndarray | None = None            # mechanism: -direction f_load.u = m ("ok"), f_y.u = -m ("cannot_stand")
    N: np.ndarray | None = None            # (2, J) fibre forces intrados/extrados, per g (>= 0: compression)
    S: np.ndarray | None = None            # (J,) shear forces, per g
    hinges: list[Hinge] = field(default_factory=list)
    friction: float | None = None          # Coulomb coefficient of the joints (None: no sliding)
    slides: list[dict] = field(default_factory=list)   # sliding joints of the mechanism (friction only)
    margin: float = float("nan")           # max_x min_j N(x, 0) / (m g): > 0 stands under gravity
    verification: dict = field(default_factory=dict)
    solve_time: float = 0.0
    lp_rounds: int = 0
    # the LP solutions on the joints' rows (stand, main or None): the continuum search's
    # first round solves the same LPs and takes them from here
    lps: tuple = field(default=(None, None), repr=False, compare=False)
    live: object = field(default=None, repr=False, compare=False)   # PointLoads of a load factor

    @property
    def eccentricity(self) -> np.ndarray:
        """Thrust-line eccentricity at the joints (m, from the mid-curve, + to intrados);
        NaN where the joint carries no force."""
        t, Nt = self.disc.joint_thickness, self.N[0] + self.N[1]
        with np.errstate(invalid="ignore", divide="ignore"):
            return np.where(Nt > 1e-12 * np.max(Nt), 0.5 * t * (self.N[0] - self.N[1]) / Nt, np.nan)


def limit_analysis(disc: Discretization, direction: int = 1, strict: bool = False,
                   verify: bool = True, friction: float | None = None, live=None) -> LimitResult:
    """Incipient rocking acceleration ``A_L`` and its mechanism, on the joints of a mesh.

    Static (lower-bound) linear programme: the largest horizontal acceleration
    ``direction * lambda g`` under which both fibre forces of every joint stay
    compressive (the thrust line inside the section, no sliding); its duals give the
    mechanism, whose kinematic load factor must equal the static one.

    Parameters
    ----------
    disc : Discretization
        The mesh (:func:`~fembeam.fem.rigid.discretize`).
    direction : {1, -1}, optional
        Direction of the inertia load: ``+1`` along ``+x`` (a ground acceleration
        towards ``-x``).
    strict : bool, optional
        Raise :class:`~fembeam.errors.CannotStandError` instead of returning
        ``status == "cannot_stand"``.
    verify : bool, optional
        Check the certificate (duality gap, residuals).
    friction : float, optional
        Coulomb coefficient ``mu >= 0`` of every joint (None, the default: no sliding);
        with associative (dilatant) sliding, so ``A_L`` is an upper bound for joints
        that slide without dilatancy.
    live : PointLoads, optional
        Live point loads (kN/m): ``A_L`` is then their load factor (the multiple at
        collapse, the dead loads at their values; ``direction`` +1).

    Returns
    -------
    LimitResult
        ``status``, ``A_L`` (g), the mechanism ``u`` and its hinges, the joint forces.

    Raises
    ------
    InputError
        ``disc`` is no :class:`~fembeam.fem.rigid.Discretization`, or ``direction`` or
        ``friction`` out of range.
    CannotStandError
        With ``strict``, when the member cannot stand under its own weight.
    SolverError
        A solve failed or the certificate failed its check (``verify``).

    Examples
    --------
    >>> import fembeam
    >>> arch = fembeam.CircularArch(radius=1.0, thickness=0.15, embrace_deg=157.5)
    >>> disc = fembeam.discretize(arch, fembeam.uniform_nodes(arch, 12))
    >>> lim = fembeam.limit_analysis(disc)
    >>> print(lim.status, f"A_L = {lim.A_L:.4f} g", len(lim.hinges), "hinges")
    ok A_L = 0.3593 g 4 hinges
    """
    if not isinstance(disc, Discretization):
        raise InputError(f"limit_analysis needs a Discretization (fembeam.discretize), got {type(disc).__name__}")
    direction = check_direction(direction)
    mu = check_friction(friction)
    t0 = time.perf_counter()
    if live is not None and direction != 1:
        raise InputError("live loads act downward: their load factor takes direction +1")
    st = statics(disc, live)
    k = st.k
    R = joint_rows(st, direction, mu)
    stand = solve_unboxed(stand_lp, R, k)
    margin = stand.value
    if margin < -STAND_TOL:
        res = _cannot_stand(st, direction, stand, R, mu)
    else:
        main = solve_unboxed(main_lp, R, k)
        if main.at_bound[k]:      # lambda held by its bound: look for the no-mechanism certificate
            res = _no_mechanism(st, direction, stand, R, mu)
        else:
            res = _ok(st, direction, main, R, mu)
        res.lp_rounds = stand.rounds + main.rounds
    res.lps = (stand, None if margin < -STAND_TOL else main)
    res.margin = margin
    res.friction = mu
    res.live = live
    res.solve_time = time.perf_counter() - t0
    if verify:
        check(res.verification, f"limit analysis ({res.status})")
        excess = res.verification.get("friction_excess", 0.0)
        if not excess <= FRICTION_TOL:
            raise SolverError(f"limit analysis ({res.status}): solution failed verification "
                              f"(friction_excess = {excess:.2e} > {FRICTION_TOL:.0e})")
    if strict and res.status == "cannot_stand":
        raise CannotStandError("the member cannot stand under its own weight: no thrust line fits inside it "
                               "(see fembeam.minimum_thickness)")
    return res


def _duals(y: np.ndarray, R: np.ndarray, k: int) -> np.ndarray:
    """The row duals ``y`` made exactly compatible: on their support (the hinges and
    slides) the closure conditions ``R_x^T y = 0`` are solved to round-off (null space by
    SVD) instead of to the LP's dual tolerance, which matters for very thin members whose
    rows are large."""
    y = np.asarray(y, float)
    S = np.flatnonzero(y > 1e-9 * np.max(y))
    if k == 0 or S.size <= k:
        return y
    _, sv, Vt = np.linalg.svd(R[S, :k].T)
    null = Vt[-(S.size - k):] if S.size - k > 0 else Vt[-1:]
    e = null.T @ (null @ y[S])                              # projection of y[S] on the null space
    if np.all(e > 0):
        out = np.zeros_like(y)
        out[S] = e
        return out
    return y


def _incompatibility(disc, u, closure, mu: float | None = None) -> float:
    """Closure misfit and distance of the jumps of ``u`` from the compatible cone
    ``eps+- >= mu |gamma|`` (``gamma = 0`` without friction), relative to the largest jump."""
    e, g = disc.B_open @ u, disc.B_slide @ u
    scale = max(np.max(np.abs(e)), np.max(np.abs(g)) if mu is not None else 0.0, 1e-300)
    if mu is None:
        return float(max(closure, -np.min(e) / scale, np.max(np.abs(g)) / scale))
    return float(max(closure, -np.min(e - mu * np.tile(np.abs(g), 2)) / scale))


def _kinematics(st: Statics, y: np.ndarray, R: np.ndarray, mu: float | None):
    """Mechanism of the row duals ``y``: jumps ``c`` (3, J), velocities ``u``, closure."""
    yc = _duals(y, R, st.k)
    c = jumps(yc, st.disc.n_joints, mu)
    u, closure = st.velocities(c)
    return yc, c, u, closure


def _ok(st: Statics, direction: int, lp, R: np.ndarray, mu: float | None = None) -> LimitResult:
    disc, m, k = st.disc, st.mass, st.k
    x, lam = lp.z[:k], float(lp.z[k])
    if -1e-9 < lam < 0:   # a member at its minimum thickness: A_L = 0 to the LP's tolerance
        lam = 0.0
    y, c, u, closure = _kinematics(st, lp.y, R, mu)
    fy, fl = st.f_dead, st.f_load
    power = -direction * float(fl @ u)
    if not power > 0:
        raise SolverError("limit LP: the dual mechanism does no work against the load")
    u *= m / power
    g = st.forces(x, direction * lam)
    hinges, slides = hinges_and_slides(disc, u, mu)
    out = LimitResult("ok", disc, direction, lam, u, m * g[1:], m * g[0], hinges, slides=slides)
    lam_k = float(fy @ u) / m
    out.verification = _static_figures(st, x, direction * lam, g, fy + direction * lam * fl, mu)
    rows = R @ np.r_[x, lam, 1.0]          # every row at the optimum (>= 0), units of weight
    out.verification.update({
        "duality_gap": abs(lam_k - lam) / (1.0 + abs(lam)),
        # each row times its dual (the work of that row's force on its jump), relative
        "complementarity": float(np.max(np.abs(rows * y)) / (np.max(np.abs(g)) * max(np.max(np.abs(y)), 1e-300))),
        "incompatibility": _incompatibility(disc, u, closure, mu),
        "max_shear_ratio": _shear_ratio(g),
    })
    return out


def _static_figures(st: Statics, x, lam_signed, g, p, mu: float | None = None) -> dict:
    """Equilibrium with the sparse operators, the joint forces recomputed from the
    equilibrium of the part left of each joint, and the thrust line from the latter."""
    disc, m = st.disc, st.mass
    B = disc.B_open.T @ g[1:].ravel() + disc.B_slide.T @ g[0]
    eq = float(np.linalg.norm(m * B - p) / np.linalg.norm(p))
    gmax = np.max(np.abs(g))
    # rigid elements: the part left of a joint is a union of exact rigid pieces, so its
    # equilibrium gives the joint forces independently (P1 elements have no such pieces)
    gs = section_forces(st, disc.joint_s, x, lam_signed) if disc.element == "rigid" else g
    Ns = gs[1] + gs[2]
    carried = Ns > 1e-9 * gmax
    outside = -np.minimum(gs[1], gs[2])[carried] / Ns[carried]
    out = {
        "equilibrium_residual": eq,
        "statics_mismatch": float(np.max(np.abs(gs - g)) / gmax),
        "thrust_line_outside": float(max(0.0, np.max(outside, initial=0.0))),
        "max_tensile_force": float(max(0.0, -np.min(g[1:])) / np.max(g[1:])),
    }
    if disc.element != "rigid":   # no second route: say so rather than report a zero
        del out["statics_mismatch"]
    if mu is not None:            # shear beyond the Coulomb cone, from the same forces
        out["friction_excess"] = float(max(0.0, np.max(np.abs(gs[0]) - mu * Ns)) / gmax)
    return out


def _shear_ratio(g) -> float:
    Nt = g[1] + g[2]
    carried = Nt > 1e-9 * np.max(Nt)
    return float(np.max(np.abs(g[0][carried]) / Nt[carried], initial=0.0))


def _cannot_stand(st: Statics, direction: int, lp, R: np.ndarray, mu: float | None = None) -> LimitResult:
    """Certificate: the margin LP's duals, a compatible mechanism that gravity drives."""
    disc, m = st.disc, st.mass
    _, _, u, closure = _kinematics(st, lp.y, R, mu)
    fy = st.f_dead
    lift = float(fy @ u)
    if not lift < 0:
        raise SolverError("cannot-stand certificate failed: gravity does no work on the margin LP's mechanism")
    u *= m / -lift
    hinges, slides = hinges_and_slides(disc, u, mu)
    out = LimitResult("cannot_stand", disc, direction, u=u, hinges=hinges, slides=slides)
    rms = np.sqrt(float(u @ disc.M @ u) / m)
    out.verification = {"incompatibility": _incompatibility(disc, u, closure, mu),
                        "gravity_power": float(fy @ u) / (m * rms)}   # < 0: the weight descends along u
    return out


def _no_mechanism(st: Statics, direction: int, stand, R, mu: float | None = None) -> LimitResult:
    """Certificate: an admissible state at lambda = 0 and an admissible ray of
    (self-stress, horizontal load)."""
    disc, m, k = st.disc, st.mass, st.k
    ray = solve_unboxed(ray_lp, R, k)
    if ray.value < -FEAS_TOL:
        raise SolverError(f"limit LP: A_L exceeds {BOX:g} g but no admissible ray exists")
    dx = ray.z[:k]
    g0 = st.forces(stand.z[:k], 0.0)
    gr = st.forces(dx, direction * 1.0) - st.forces(np.zeros(k), 0.0)   # forces per unit lambda
    fy, fl = st.f_dead, st.f_load
    B = disc.B_open.T @ gr[1:].ravel() + disc.B_slide.T @ gr[0]
    out = LimitResult("no_mechanism", disc, direction, A_L=float("inf"), N=m * g0[1:], S=m * g0[0])
    out.verification = _static_figures(st, stand.z[:k], 0.0, g0, fy, mu)
    ray_rows = R[:, :k] @ dx + R[:, k]      # fibre (and friction) rows of the ray, >= 0
    out.verification["ray_residual"] = float(max(np.linalg.norm(m * B - direction * fl) / np.linalg.norm(fl),
                                                 max(0.0, -np.min(ray_rows)) / max(np.max(np.abs(gr)), 1e-300)))
    return out
