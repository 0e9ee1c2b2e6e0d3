"""The main job: equivalent static analysis, then the impact, every result checked.

``analyze`` runs, on a mesh of ``elements`` rigid elements (continuous arch) or of
``voussoirs`` rigid voussoirs (discrete arch):

1. the limit LP on the uniform mesh (``A_L_mesh``: hinges at joints only);
2. continuous arch: the limit analysis of the continuum (joints plus the weakest
   sections between them, :mod:`~fembeam.analysis.continuum`), which brackets ``A_L``
   between a mechanism and an admissible thrust line; the mesh then gets nodes at the
   hinges and the limit LP on it must reproduce ``A_L`` (``hinge_refinement_gap``);
3. the impact QP with ``d0 = -u``: ``r``, post-impact field, impulses, hinges.

Physical outcomes are reported in ``outcome``, not raised: ``"rocking"`` (r > 0),
``"arrested"`` (r = 0, the arch stops dead), ``"cannot_stand"`` (no thrust line under
gravity fits: the minimum thickness of the analysed arch is reported) and
``"no_mechanism"`` (no horizontal acceleration turns the arch into a mechanism).

With a Coulomb coefficient ``friction`` the limit analysis keeps every joint force inside
the friction cone (:mod:`~fembeam.analysis.friction`; on the continuous arch the fibre
rows are checked between the joints, the friction rows at the joints of the mesh refined
through the hinges and slides).  Its flow is associative (dilatant sliding), so ``A_L`` is
then an UPPER bound of the collapse load of joints that slide without dilatancy; the same
analysis with frictionless joints on the same mesh gives the safe LOWER bound
(:func:`~fembeam.analysis.friction.lower_bound`), both in :attr:`AnalysisResult.friction_bounds`.
When its mechanism slides the outcome is ``"sliding"`` and no impact follows (the impact
model is of a rocking, frictionless arch).  Every result reports the friction coefficient
the joints need, at the limit state and at the impact (:meth:`AnalysisResult.required_friction`).
"""
from __future__ import annotations

import time
from dataclasses import dataclass, field

import numpy as np

from ..errors import InputError, SolverError
from ..fem import discretize, nodes_through, uniform_nodes
from ..geometry import MidCurve
from ..geometry.asbuilt import build
from ..mechanisms.hinge import merge_adjacent
from ..units import kN
from .continuum import ContinuumLimit, continuum_limit
from .friction import bound_of, bounds, continuum_support, lower_bound, required_friction
from .impact import ImpactResult, impact
from .limit import LimitResult, limit_analysis
from .load_factor import LoadFactor, load_factor, mass_nodes
from .loads import PointLoads
from .rows import check_direction, check_friction
from .sizes import DEFAULT_ELEMENTS, MAX_ELEMENTS, MIN_ELEMENTS, MIN_VOUSSOIRS, check_count
from .thickness import MinimumThickness, thickness_on
from .thrust_range import ThrustRange, thrust_range
from .verification import THRESHOLDS, check

# units of the impulse line (impulses and their moment per metre of width) for the normalised
# mechanism: a mean horizontal speed of 1 m/s before the impact (docs/visualisation.md)
IMPULSE_UNIT = "N s/m (for a mean horizontal speed of 1 m/s before the impact)"
IMPULSE_MOMENT_UNIT = "N m s/m (for a mean horizontal speed of 1 m/s before the impact)"

__all__ = ["AnalysisResult", "analyze"]


@dataclass
class AnalysisResult:
    """Everything :func:`analyze` (and ``fembeam analyze``) reports.

    :meth:`to_dict` is its JSON. Forces, masses and energies are per metre of barrel
    width.

    Attributes
    ----------
    geometry : dict
        The member's description (its ``describe()``: shape and dimensions in m).
    mode : {"continuous", "voussoirs"}
        A continuous arch of rigid elements or a discrete arch of voussoirs.
    n : int
        Pieces of the uniform mesh: elements or voussoirs (also :attr:`elements`).
    direction : {1, -1}
        Direction of the inertia load (+1: along ``+x``, a ground acceleration towards
        ``-x``).
    backend : str
        Solver of the impact QP asked for.
    outcome : {"rocking", "arrested", "sliding", "cannot_stand", "no_mechanism"}
        What happens (:func:`analyze`).
    limit : LimitResult or None
        The limit analysis on the final mesh.
    impact : ImpactResult or None
        The impact of the mechanism (outcomes ``"rocking"`` and ``"arrested"``).
    A_L_mesh : float
        Load factor (g) of the limit analysis on the uniform mesh, hinges at its joints.
    A_L : float
        Incipient rocking acceleration (g); NaN without a mechanism.
    A_L_lower : float
        Continuous arch: the load factor (g) of an admissible thrust line, a lower bound
        of ``A_L``.
    thickness : MinimumThickness or None
        The minimum thickness, when the arch cannot stand.
    continuum : ContinuumLimit or None
        The limit analysis of the continuum (continuous arch).
    verification : dict
        Every checked figure (residuals, duality gaps), by group.
    timings : dict
        Wall time of each step (s).
    friction : float or None
        Coulomb coefficient of the joints (None: no sliding).
    friction_lower : tuple or None
        With ``friction``: ``(status, A_L)`` of the frictionless analysis on the same
        mesh, the safe lower bound.
    loads : PointLoads or None
        The live point loads (kN/m).
    load : LoadFactor or None
        Their load factor (:attr:`load_factor`).
    thrust : ThrustRange or None
        ``H_min, H_max`` (kN/m) under the dead loads.
    mass : float
        Mass of the arch, fill and point masses (kg/m).
    r : float
        Restitution coefficient ``K'/K`` of the impact (0 when arrested, NaN without
        impact).

    Examples
    --------
    :func:`analyze` returns it; the paper's arch of 12 voussoirs rocks from
    ``A_L`` (g), weighs ``mass`` (kg/m) and stands in a range of thrust (kN/m):

    >>> import fembeam
    >>> arch = fembeam.CircularArch(radius=1.0, thickness=0.15, embrace_deg=157.5)
    >>> res = fembeam.analyze(arch, voussoirs=12)
    >>> print(res.outcome, f"A_L = {res.A_L:.4f} g, mass {res.mass:.1f} kg/m")
    rocking A_L = 0.3593 g, mass 824.7 kg/m
    >>> print(f"H in [{res.thrust.H_min:.3f}, {res.thrust.H_max:.3f}] kN/m")
    H in [1.612, 2.643] kN/m
    """

    geometry: dict
    mode: str                       # "continuous" or "voussoirs"
    n: int                          # pieces of the uniform mesh: elements ("continuous") or voussoirs
    direction: int
    backend: str
    outcome: str
    limit: LimitResult | None = None
    impact: ImpactResult | None = None
    A_L_mesh: float = float("nan")  # LP on the uniform mesh (hinges at its joints only)
    A_L: float = float("nan")
    A_L_lower: float = float("nan")  # continuum: admissible thrust line (lower bound)
    thickness: MinimumThickness | None = None
    continuum: ContinuumLimit | None = None
    verification: dict = field(default_factory=dict)
    timings: dict = field(default_factory=dict)
    friction: float | None = None   # Coulomb coefficient of the limit analysis (None: no sliding)
    # with friction: (status, A_L) of the frictionless analysis on the same mesh (the safe lower bound)
    friction_lower: tuple | None = None
    loads: PointLoads | None = None        # live point loads (kN/m)
    load: LoadFactor | None = None         # their load factor
    thrust: ThrustRange | None = None      # H_min, H_max under the dead loads (kN/m)
    mass: float = float("nan")             # kg per metre of width: masonry, fill and point masses

    @property
    def load_factor(self) -> float | None:
        """Multiple of the live loads at collapse (None without loads or when none collapses)."""
        return None if self.load is None or self.load.status != "ok" else float(self.load.value)

    @property
    def elements(self) -> int:
        """:attr:`n` under its JSON key (a voussoir count in mode ``"voussoirs"``)."""
        return self.n

    @property
    def t_min_over_R(self) -> float | None:
        """Minimum t/R of a circular arch that cannot stand (None otherwise)."""
        return None if self.thickness is None else self.thickness.t_over_R

    @property
    def r(self) -> float:
        """Restitution coefficient ``K'/K`` (0 when arrested, NaN without an impact)."""
        if self.outcome == "rocking":
            return self.impact.r
        return 0.0 if self.outcome == "arrested" else float("nan")

    @property
    def hinges_before(self):
        """Hinges of the incipient mechanism (none unless the arch rocks or is arrested)."""
        return self.limit.hinges if self.outcome in ("rocking", "arrested", "sliding") else []

    def required_friction(self, mu: float | None = None) -> dict:
        """Friction coefficient the joints need: ``"limit"``: ``|S| / N`` of the limit state,
        ``"impact"``: ``|I_n| / |I_t|`` of the impulses (shear over normal at each joint);
        each ``{"max", "at_deg", "at_s", "joint"}`` (None with a ``reason`` where undefined)
        and, with :attr:`friction` (or ``mu``), the joints needing more (``above``)."""
        mu = self.friction if mu is None else mu
        lim, imp = self.limit, self.impact
        if lim is not None and lim.status == "ok":
            d = lim.disc
            limit = required_friction(d.joint_angle_deg, d.joint_s, lim.S, lim.N[0] + lim.N[1], mu, "force")
        else:
            limit = {"max": None, "reason": f"no limit state (outcome {self.outcome})"}
        if imp is not None:
            d = imp.disc
            impact = required_friction(d.joint_angle_deg, d.joint_s, imp.I_n, -imp.I_t, mu, "impulse")
        else:
            impact = {"max": None, "reason": f"no impact (outcome {self.outcome})"}
        return {"limit": limit, "impact": impact}

    @property
    def sliding_risk(self) -> bool | None:
        """With :attr:`friction`: whether a joint slides in the mechanism or needs more
        friction than it has, at the limit state or at the impact (None without friction)."""
        if self.friction is None:
            return None
        rf = self.required_friction()
        return bool(self.outcome == "sliding" or any(rf[k].get("above") for k in rf))

    @property
    def friction_bounds(self) -> dict | None:
        """With :attr:`friction`: the associative load factor with ``mu`` (an upper bound of
        the collapse load of joints that slide without dilatancy) and with frictionless joints
        (a lower bound), and what is known between them
        (:func:`~fembeam.analysis.friction.bounds`); None without friction."""
        if self.friction is None or self.friction_lower is None:
            return None
        return bounds(self.friction, (self.limit.status, self.A_L), self.friction_lower,
                      statics_determinate(self.limit.disc))

    @property
    def hinges_after(self):
        """Hinges of the post-impact mechanism (adjacent joints merged on a continuous
        arch); none without an impact."""
        if self.impact is None:
            return []
        h = self.impact.hinges
        return merge_adjacent(self.impact.disc, h) if self.mode == "continuous" else h

    def to_dict(self, fields: bool = False) -> dict:
        """The JSON of ``fembeam analyze`` (no NaN or infinity: null where undefined);
        ``hinges_exact`` is False when the continuum optimum is degenerate and the
        mechanism was taken from the uniform mesh (docs/theory.md, section 4)."""
        def num(x):
            return None if x is None or not np.isfinite(x) else float(x)

        out = {
            "outcome": self.outcome,
            "A_L": num(self.A_L),
            "r": num(self.r),
            "elements": self.n,
            "mode": self.mode,
            "direction": self.direction,
            "geometry": self.geometry,
            "hinges_before": [h.to_dict() for h in self.hinges_before],
            "hinges_after": [h.to_dict() for h in self.hinges_after],
            "hinge_joints_after": [h.to_dict() for h in (self.impact.hinges if self.impact else [])],
            "A_L_uniform_mesh": num(self.A_L_mesh),
            "A_L_lower_bound": num(self.A_L_lower),
            "hinges_exact": (bool(self.continuum.exact_hinges)
                             if self.continuum is not None and self.outcome in ("rocking", "arrested") else None),
            "t_min_over_R": num(self.t_min_over_R),
            "minimum_thickness": self.thickness.to_dict() if self.thickness is not None else None,
            "friction": self.friction,
            "bound": bound_of(self.friction),
            "friction_bounds": self.friction_bounds,
            "required_friction": self.required_friction(),
            "sliding_risk": self.sliding_risk,
            "sliding_before": list(self.limit.slides) if self.limit is not None else [],
            "backend": self.backend,
            "solver_iterations": self.impact.iterations if self.impact else None,
            # the impact's figures at the top level, and by group
            "verification": {**self.verification.get("impact", {}), **self.verification},
            "timings_s": {k: round(v, 4) for k, v in self.timings.items()},
        }
        out["geometry"] = {**self.geometry, "fill": self.geometry.get("fill")}
        out["masses"] = list(self.geometry.get("masses", []))
        out["loads"] = self.loads.to_list() if self.loads is not None else []
        out["mass_kg_per_m"] = num(self.mass)
        out["weight_kN_per_m"] = num(kN(self.mass))
        out["load_factor"] = self.load_factor
        out["load_outcome"] = (self.load.status if self.load is not None
                               else "cannot_stand" if self.loads is not None and self.outcome == "cannot_stand"
                               else None)
        out["load_factor_lower_bound"] = (num(self.load.lower) if self.load is not None and self.load.status == "ok"
                                          else None)
        out["load_mechanism"] = [h.to_dict() for h in self.load.hinges] if self.load is not None else []
        out["collapse_loads_kN_per_m"] = self.load.collapse_loads_kN if self.load is not None else []
        out["thrust_range"] = None if self.thrust is None else self.thrust.to_dict()
        if self.load is not None:
            out["verification"]["load_factor"] = self.load.verification
            if fields:
                out["load_thrust_line"] = self.load.thrust_line()
        out["units"] = {"A_L": "g", "density": "kg/m^3", "radius": "m", "thickness": "m",
                        "impulse_line.I_t": IMPULSE_UNIT, "impulse_line.I_n": IMPULSE_UNIT,
                        "impulse_line.moment": IMPULSE_MOMENT_UNIT, "impulse_line.eccentricity": "m",
                        "thrust_line.N": "kN/m", "thrust_line.eccentricity": "m", "angle_deg": "deg",
                        "load_factor": "multiple of the live loads", "loads.P": "kN/m", "masses.M": "kg/m",
                        "loads.x": "m from the left springing", "masses.x": "m from the left springing",
                        "thrust_range": "kN/m", "geometry.fill.density": "kg/m^3", "geometry.fill.depth": "m",
                        "mass_kg_per_m": "kg/m", "weight_kN_per_m": "kN/m", "collapse_loads_kN_per_m": "kN/m"}
        if fields and self.impact is not None:
            imp = self.impact
            out["impulse_line"] = {
                "angle_deg": imp.disc.joint_angle_deg.tolist(),
                "I_t": imp.I_t.tolist(), "I_n": imp.I_n.tolist(),
                "moment": imp.moment.tolist(),
                "eccentricity": [None if not np.isfinite(e) else float(e) for e in imp.eccentricity],
            }
        if fields and self.limit is not None and self.limit.N is not None:
            lim = self.limit
            out["thrust_line"] = {"angle_deg": lim.disc.joint_angle_deg.tolist(),
                                  "N": kN(lim.N[0] + lim.N[1]).tolist(),
                                  "eccentricity": [None if not np.isfinite(e) else float(e) for e in lim.eccentricity]}
        return out


def statics_determinate(disc) -> bool:
    """Whether the joint forces of ``disc`` follow from equilibrium alone (no redundants: a
    member with a free end, e.g. a block or a stack of blocks on its base)."""
    return 3 * disc.n_joints == disc.M.shape[0]    # k = 3 J - (DOFs) redundants (statics.py)


def analyze(curve: MidCurve, elements: int | None = None, voussoirs: int | None = None,
            direction: int = 1, backend: str = "auto", refine_hinges: bool = True,
            verify: bool = True, tmin_tol: float = 1e-6, friction: float | None = None, *,
            density: float | None = None, fill_density: float | None = None, fill_depth: float | None = None,
            loads=(), masses=(), thrust: bool = True) -> AnalysisResult:
    """Limit analysis and impact of a member, every result checked.

    On a uniform mesh of rigid elements (continuous arch) or voussoirs (discrete arch):
    the limit analysis gives the incipient rocking acceleration ``A_L`` and its
    mechanism; on a continuous arch the hinges are then located between the joints
    (limit analysis of the continuum) and the mesh refined through them; the impact
    of the mechanism's velocity field ``d0 = -u`` gives the restitution coefficient
    ``r`` and the impulse line.

    Parameters
    ----------
    curve : MidCurve
        The member, e.g. a :class:`~fembeam.geometry.circular.CircularArch` (lengths in
        m, density in kg/m^3).
    elements : int, optional
        Rigid elements of the uniform mesh of a continuous arch (default
        :data:`~fembeam.analysis.sizes.DEFAULT_ELEMENTS`). Not with ``voussoirs``.
    voussoirs : int, optional
        Voussoirs of a discrete arch (hinges at its joints only). Not with
        ``elements``.
    direction : {1, -1}, optional
        Direction of the horizontal inertia load ``direction * A_L g``: ``+1`` along
        ``+x`` (a ground acceleration towards ``-x``), ``-1`` the mirror.
    backend : {"auto", "clarabel", "osqp", "active-set"}, optional
        Solver of the impact QP (:func:`~fembeam.analysis.impact.impact`).
    refine_hinges : bool, optional
        Continuous arch: locate the hinges between the joints and refine the mesh
        through them (default True); False keeps the uniform mesh.
    verify : bool, optional
        Check every certificate (duality gaps, residuals) against
        :data:`~fembeam.analysis.verification.THRESHOLDS`.
    tmin_tol : float, optional
        Relative tolerance of the minimum thickness reported when the arch cannot
        stand, in [1e-12, 0.1].
    friction : float, optional
        Coulomb coefficient ``mu >= 0`` of the joints in the limit analysis (None, the
        default: the joints do not slide). Then ``A_L`` is an upper bound for joints
        that slide without dilatancy; the lower one is in
        :attr:`AnalysisResult.friction_bounds`.
    density : float, optional
        Density of the masonry in kg/m^3, replacing the member's.
    fill_density : float, optional
        Density of the fill above the arch in kg/m^3 (with ``fill_depth``).
    fill_depth : float, optional
        Depth of the fill (road) above the crown's extrados in m.
    loads : sequence of (float, float), optional
        Live point loads ``(x, P)``: ``x`` in m from the left springing, ``P`` in kN/m
        (downwards); their load factor is reported (:attr:`AnalysisResult.load_factor`).
        Not with ``friction``.
    masses : sequence of (float, float), optional
        Point masses ``(x, M)``: ``x`` in m from the left springing, ``M`` in kg/m.
    thrust : bool, optional
        Also the range of horizontal thrust ``H_min, H_max`` (kN/m) under the dead
        loads (default True).

    Returns
    -------
    AnalysisResult
        ``outcome`` is ``"rocking"`` (``r > 0``), ``"arrested"`` (``r = 0``),
        ``"sliding"`` (with ``friction``: the mechanism slides, no impact follows),
        ``"cannot_stand"`` (no thrust line fits under gravity: the minimum thickness
        is reported) or ``"no_mechanism"``; physical outcomes are reported, not raised.

    Raises
    ------
    InputError
        An input out of its range, ``elements`` with ``voussoirs``, or ``loads`` with
        ``friction``.
    SolverError
        A solve failed or a certificate failed its check (``verify``).

    See Also
    --------
    limit_analysis, impact, minimum_thickness

    Examples
    --------
    The paper's arch (embrace 157.5 deg, t/R = 0.15) of 12 voussoirs:

    >>> import fembeam
    >>> arch = fembeam.CircularArch(radius=1.0, thickness=0.15, embrace_deg=157.5)
    >>> res = fembeam.analyze(arch, voussoirs=12)
    >>> print(res.outcome, f"A_L = {res.A_L:.4f} g, r = {res.r:.4f}")
    rocking A_L = 0.3593 g, r = 0.6137
    >>> for h in res.hinges_before:
    ...     print(f"{h.angle_deg:6.1f} deg  {h.side}")
       0.0 deg  intrados
      52.5 deg  extrados
     118.1 deg  intrados
     157.5 deg  extrados
    """
    if not isinstance(curve, MidCurve):
        raise InputError(f"analyze needs a member (e.g. fembeam.CircularArch), got {type(curve).__name__}")
    curve = build(curve, density, fill_density, fill_depth, masses)
    live = PointLoads.of(curve, loads)
    if live is not None and friction is not None:
        raise InputError("the load factor is computed for joints that do not slide: give live loads or a "
                         "friction coefficient, not both")
    if elements is not None and voussoirs is not None:
        raise InputError("give either elements (continuous arch) or voussoirs (discrete arch), not both")
    direction = check_direction(direction)
    mu = check_friction(friction)
    mode = "voussoirs" if voussoirs is not None else "continuous"
    n = (check_count(voussoirs, "voussoirs", MIN_VOUSSOIRS) if mode == "voussoirs"
         else check_count(DEFAULT_ELEMENTS if elements is None else elements, "elements", MIN_ELEMENTS))
    continuum = mode == "continuous" and refine_hinges
    desc = curve.describe() if hasattr(curve, "describe") else {}
    res = AnalysisResult(desc, mode, n, direction, backend, "rocking", friction=mu, loads=live)
    res.mass = float(curve.segment_inertia(0.0, curve.length)[0][0])
    clock = time.perf_counter()

    nodes = uniform_nodes(curve, n)
    if continuum and mass_nodes(curve):     # the internal forces jump at a point mass: a node there
        nodes = nodes_through(nodes, np.array(mass_nodes(curve)), keep=curve.fixed_nodes)
    if continuum and live is not None:      # and at a live load (one mesh for A_L and the load factor)
        nodes = nodes_through(nodes, curve.nearest_section(live.s), keep=curve.fixed_nodes + mass_nodes(curve))
    disc = disc0 = discretize(curve, nodes)
    res.timings["assembly"] = time.perf_counter() - clock
    t0 = time.perf_counter()
    lim = limit_analysis(disc, direction, verify=verify, friction=mu)
    res.A_L_mesh = lim.A_L
    res.verification["limit_uniform_mesh"] = lim.verification
    res.timings["limit"] = time.perf_counter() - t0
    if continuum and lim.status != "no_mechanism" and mu is not None:
        t0 = time.perf_counter()
        status, lam, support = continuum_support(disc, direction, mu)
        disc = discretize(curve, nodes_through(nodes, support, keep=curve.fixed_nodes + mass_nodes(curve)), like=disc)
        lim = limit_analysis(disc, direction, verify=verify, friction=mu)
        if lim.status != status:
            raise SolverError(f"limit analysis with friction: the continuum says {status}, the mesh through its "
                              f"hinges says {lim.status}")
        if status == "ok":   # reported, not checked: friction is imposed at the joints only
            res.verification["friction_refinement_gap"] = abs(lim.A_L - lam) / max(abs(lam), 1e-300)
        res.timings["continuum"] = time.perf_counter() - t0
    elif continuum and lim.status != "no_mechanism":
        t0 = time.perf_counter()
        cont = continuum_limit(disc, direction, lim=lim)
        res.continuum = cont
        if cont.status == "ok":
            res.verification["continuum_violation"] = cont.violation
            res.verification["continuum_gap"] = cont.gap
            res.A_L_lower = cont.A_L_lower
        if cont.status == "cannot_stand" or cont.exact_hinges:
            # the mechanism (or the collapse certificate) on a mesh with nodes at its hinges
            disc = discretize(curve, nodes_through(nodes, cont.hinge_s, keep=curve.fixed_nodes + mass_nodes(curve)), like=disc)
            lim = limit_analysis(disc, direction, verify=verify)
            if lim.status != cont.status:
                raise SolverError(f"limit analysis: the continuum says {cont.status}, the mesh through its "
                                  f"hinges says {lim.status}")
            if cont.status == "ok":
                res.verification["hinge_refinement_gap"] = abs(lim.A_L - cont.A_L) / cont.A_L
        # else: degenerate optimum (hinges known to ~sqrt(tol) only): the mechanism and the
        # impact stay on the uniform mesh, whose LP optimum is a well-posed vertex
        res.timings["continuum"] = time.perf_counter() - t0
    res.limit = lim
    res.A_L = float("nan") if lim.status != "ok" else (res.continuum.A_L if res.continuum else lim.A_L)
    if mu is not None:   # the safe side: frictionless joints on the same mesh (Radenkovic's second theorem)
        t0 = time.perf_counter()
        # no admissible state with mu: none with frictionless joints either
        res.friction_lower = (("cannot_stand", float("nan")) if lim.status == "cannot_stand" else
                              lower_bound(disc, direction, continuum, verify))
        res.timings["lower_bound"] = time.perf_counter() - t0
    res.verification["limit"] = lim.verification
    if verify:
        check(res.verification, "limit analysis of the continuum")
    if lim.status != "cannot_stand":
        t0 = time.perf_counter()
        if thrust and statics_determinate(disc) is False:
            res.thrust = thrust_range(disc, continuum=continuum)
        if live is not None:
            res.load = load_factor(curve, live, nodes=nodes, continuum=continuum, verify=verify, disc=disc0)
        res.timings["loads_and_thrust"] = time.perf_counter() - t0
    if lim.status == "ok" and lim.slides:
        res.outcome = "sliding"    # the arch starts to slide: no rocking impact follows
        res.timings["total"] = time.perf_counter() - clock
        return res
    if lim.status != "ok":
        res.outcome = lim.status
        if lim.status == "cannot_stand":
            res.thickness = thickness_on(curve, nodes, continuum, tmin_tol, friction=mu)
        res.timings["total"] = time.perf_counter() - clock
        return res

    t0 = time.perf_counter()
    imp = impact(disc, -lim.u, backend=backend, verify=verify)
    res.timings["impact"] = time.perf_counter() - t0
    res.timings["impact_solver"] = imp.solve_time
    res.impact = imp
    res.verification["impact"] = imp.verification
    res.verification["thresholds"] = THRESHOLDS
    if imp.arrested:
        res.outcome = "arrested"
    res.timings["total"] = time.perf_counter() - clock
    return res
