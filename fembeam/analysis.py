"""The main job: equivalent static analysis, then the impact, with every check.

``analyze`` runs, on a mesh of ``elements`` rigid elements (continuous arch) or of
``voussoirs`` rigid voussoirs (discrete arch):

1. the limit-analysis LP on the uniform mesh (A_L, mechanism ``u``, thrust line);
2. continuous arch only: the four hinges of ``u`` are moved off the mesh to their
   optimal continuous positions (``A_L`` is smooth in them, THEORY §8) and mesh nodes
   are put there; the LP on that mesh must reproduce the optimised ``A_L``;
3. the impact QP with ``d0 = -u``: ``r``, post-impact field, impulses, hinges.

Physical outcomes are reported in ``outcome``, not raised: ``"rocking"`` (r > 0),
``"arrested"`` (r = 0, the arch stops dead), ``"cannot_stand"`` (A_L <= 0) and
``"no_mechanism"`` (no horizontal acceleration turns the arch into a mechanism).
"""
from __future__ import annotations

import time
from dataclasses import dataclass, field

import numpy as np

from .errors import InputError, SolverError
from .fem import discretize, nodes_through, uniform_nodes
from .fourhinge import FourHinge, optimise_load_factor
from .geometry import CircularArch, MidCurve
from .hinges import merge_adjacent
from .impact import ImpactResult, impact
from .limit import LimitResult, limit_analysis

__all__ = ["AnalysisResult", "analyze", "minimum_thickness", "THRESHOLDS", "DEFAULT_ELEMENTS"]

DEFAULT_ELEMENTS = 200
MIN_ELEMENTS = 4

# Verification thresholds (dimensionless, see docs/verification.md): residuals of
# linear algebra at ~1e-14 and solver tolerances of 1e-10 leave ample margin.  The
# LP's duals come from simplex basis solves on a chain whose condition number grows
# like N^2: their equilibrium residual reaches 7e-8 at 3200 elements, hence 1e-6.
THRESHOLDS = {
    "equilibrium_residual": 1e-6,
    "impulse_line_outside": 1e-6,
    "thrust_line_outside": 1e-6,
    "max_tensile_impulse": 1e-6,
    "max_tensile_force": 1e-6,
    "impulse_work": 1e-7,
    "complementarity": 1e-7,
    "incompatibility": 1e-6,
    "virtual_work_gap": 1e-7,
    "hinge_refinement_gap": 1e-7,
}


@dataclass
class AnalysisResult:
    """Everything ``fembeam analyze`` reports; :meth:`to_dict` is its JSON."""

    geometry: dict
    mode: str                       # "continuous" or "voussoirs"
    elements: int
    direction: int
    backend: str
    outcome: str
    limit: LimitResult | None = None
    impact: ImpactResult | None = None
    A_L_mesh: float = float("nan")  # LP on the uniform mesh, before hinge refinement
    A_L: float = float("nan")
    t_min_over_R: float | None = None
    verification: dict = field(default_factory=dict)
    timings: dict = field(default_factory=dict)

    @property
    def r(self) -> float:
        if self.outcome == "rocking":
            return self.impact.r
        return 0.0 if self.outcome == "arrested" else float("nan")

    @property
    def hinges_before(self):
        return self.limit.hinges if self.limit is not None else []

    @property
    def hinges_after(self):
        if self.impact is None:
            return []
        h = self.impact.hinges
        return merge_adjacent(self.impact.disc, h) if self.mode == "continuous" else h

    def to_dict(self, fields: bool = False) -> dict:
        def num(x):
            return None if x is None or not np.isfinite(x) else float(x)

        out = {
            "outcome": self.outcome,
            "A_L": num(self.A_L),
            "r": num(self.r),
            "elements": self.elements,
            "mode": self.mode,
            "direction": self.direction,
            "geometry": self.geometry,
            "hinges_before": [h.to_dict() for h in self.hinges_before],
            "hinges_after": [h.to_dict() for h in self.hinges_after],
            "hinge_joints_after": [h.to_dict() for h in (self.impact.hinges if self.impact else [])],
            "A_L_uniform_mesh": num(self.A_L_mesh),
            "t_min_over_R": num(self.t_min_over_R),
            "backend": self.backend,
            "solver_iterations": self.impact.iterations if self.impact else None,
            # the impact's figures (issue item 5) at the top level, and by group
            "verification": {**self.verification.get("impact", {}), **self.verification},
            "timings_s": {k: round(v, 4) for k, v in self.timings.items()},
        }
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
                                  "N": (lim.N[0] + lim.N[1]).tolist(), "eccentricity": lim.eccentricity.tolist()}
        return out


def _check(figures: dict, where: str) -> None:
    bad = {k: v for k, v in figures.items() if k in THRESHOLDS and not v <= THRESHOLDS[k]}
    if bad:
        txt = ", ".join(f"{k} = {v:.2e} > {THRESHOLDS[k]:.0e}" for k, v in bad.items())
        raise SolverError(f"{where}: solution failed verification ({txt})")


def analyze(curve: MidCurve, elements: int | None = None, voussoirs: int | None = None,
            direction: int = 1, backend: str = "clarabel", refine_hinges: bool = True,
            verify: bool = True) -> AnalysisResult:
    """Limit analysis and impact of ``curve`` (see the module docstring)."""
    if elements is not None and voussoirs is not None:
        raise InputError("give either elements (continuous arch) or voussoirs (discrete arch), not both")
    if direction not in (1, -1):
        raise InputError(f"direction must be +1 or -1, got {direction!r}")
    mode = "voussoirs" if voussoirs is not None else "continuous"
    n = voussoirs if voussoirs is not None else (DEFAULT_ELEMENTS if elements is None else elements)
    lowest = 1 if mode == "voussoirs" else MIN_ELEMENTS
    if not isinstance(n, (int, np.integer)) or isinstance(n, bool) or n < lowest:
        raise InputError(f"the number of {'voussoirs' if mode == 'voussoirs' else 'elements'} must be an "
                         f"integer >= {lowest}, got {n!r}")
    desc = curve.describe() if hasattr(curve, "describe") else {}
    res = AnalysisResult(desc, mode, int(n), direction, backend, "rocking")
    clock = time.perf_counter()

    nodes = uniform_nodes(curve, n)
    disc = discretize(curve, nodes)
    lim = limit_analysis(disc, direction)
    res.timings["limit"] = time.perf_counter() - clock
    res.A_L_mesh = lim.A_L
    if lim.status != "ok":
        res.outcome, res.limit = lim.status, None
        if lim.status == "cannot_stand" and isinstance(curve, CircularArch):
            res.t_min_over_R = minimum_thickness(curve.embrace_deg)
        res.A_L = lim.A_L if np.isfinite(lim.A_L) else float("nan")
        return res
    if verify:
        _check(lim.verification, "limit analysis")
    res.A_L = lim.A_L

    if mode == "continuous" and refine_hinges and len(lim.hinges) == 4 and \
            all(h.side != "separated" for h in lim.hinges):
        t0 = time.perf_counter()
        start = FourHinge(tuple(h.s for h in lim.hinges), tuple(h.side for h in lim.hinges))
        best, lam = optimise_load_factor(curve, start, direction)
        disc2 = discretize(curve, nodes_through(nodes, best.s))
        lim2 = limit_analysis(disc2, direction)
        gap = float(abs(lim2.A_L - lam) / lam) if lim2.status == "ok" else float("inf")
        # accepted only if the LP through the moved nodes reproduces the optimum (the
        # mechanism kept its four hinges); otherwise the uniform mesh is kept
        if gap <= THRESHOLDS["hinge_refinement_gap"]:
            if verify:
                _check(lim2.verification, "limit analysis (refined mesh)")
            disc, lim, res.A_L = disc2, lim2, lam
            res.verification["hinge_refinement_gap"] = gap
        else:
            res.verification["hinge_refinement"] = f"rejected: LP gap {gap:.2e} (mechanism is not four-hinge)"
        res.timings["hinge_refinement"] = time.perf_counter() - t0
    res.limit = lim
    res.verification["limit"] = lim.verification

    t0 = time.perf_counter()
    imp = impact(disc, -lim.u, backend=backend)
    res.timings["impact"] = time.perf_counter() - t0
    res.timings["impact_solver"] = imp.solve_time
    if verify:
        _check(imp.verification, "impact QP")
    res.impact = imp
    res.verification["impact"] = imp.verification
    res.verification["thresholds"] = THRESHOLDS
    if imp.arrested:
        res.outcome = "arrested"
    res.timings["total"] = time.perf_counter() - clock
    return res


def minimum_thickness(embrace_deg: float, elements: int = 200, tol: float = 1e-5) -> float:
    """Smallest t/R at which a circular arch of embrace ``embrace_deg`` stands under
    its own weight (bisection on the sign of the LP's A_L; semicircle: 0.1075); ``inf``
    if no t/R below 2 does (embrace beyond about 305 degrees)."""
    def stands(tr: float) -> bool:
        c = CircularArch.from_ratio(embrace_deg, tr)
        lim = limit_analysis(discretize(c, uniform_nodes(c, elements)))
        return lim.status in ("ok", "no_mechanism")

    lo, hi = 1e-4, 0.05
    while not stands(hi):
        if hi >= 1.99:
            return float("inf")   # no thickness below 2R lets this arch stand (rings near 360 deg)
        lo, hi = hi, min(2 * hi, 1.99)
    while hi - lo > tol:
        mid = 0.5 * (lo + hi)
        lo, hi = (lo, mid) if stands(mid) else (mid, hi)
    return hi
