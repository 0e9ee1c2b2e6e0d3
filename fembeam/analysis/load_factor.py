"""The load factor of live point loads: the multiple at which the arch collapses.

The dead loads (self weight, fill, point masses) keep their values and the live loads
(:class:`~fembeam.analysis.loads.PointLoads`) grow by the factor ``lambda``; the load factor is
the largest ``lambda`` with a thrust line inside the arch (the static LP of
:mod:`~fembeam.analysis.limit` with ``lambda`` on the live loads), certified like ``A_L``:
a compatible mechanism whose virtual work gives the same factor (duality gap), equilibrium
by two routes.  On the continuous arch the weakest sections between the joints are added
(:mod:`~fembeam.analysis.continuum`), the factor bracketed between a mechanism and an
admissible thrust line, and the mesh has nodes at the loads (the internal force jumps
there).  Outcomes: ``"ok"``, ``"no_mechanism"`` (no multiple of the loads collapses the
arch: an admissible ray of thrust states), ``"cannot_stand"`` (not even the dead loads).
"""
from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from ..errors import InputError, SolverError
from ..fem import discretize, nodes_through, uniform_nodes
from ..geometry import MidCurve
from ..units import kN
from .continuum import continuum_limit
from .limit import LimitResult, limit_analysis
from .loads import PointLoads
from .verification import check
from .sizes import DEFAULT_ELEMENTS, MIN_ELEMENTS, MIN_VOUSSOIRS, check_count

__all__ = ["LoadFactor", "load_factor", "mass_nodes"]


@dataclass
class LoadFactor:
    """Load factor of ``loads`` (``value``: multiple of the live loads; ``lower``: the
    continuum's admissible lower bound), its mechanism and thrust line (``limit`` on the final
    mesh) and the figures checked."""

    status: str
    value: float
    loads: PointLoads
    limit: LimitResult
    lower: float = float("nan")
    verification: dict = field(default_factory=dict)

    @property
    def hinges(self):
        return self.limit.hinges if self.status == "ok" else []

    @property
    def collapse_loads_kN(self) -> list[float]:
        """The live loads at collapse (kN/m): ``value`` times each."""
        return [float(self.value * p) for p in self.loads.pairs[:, 1]] if self.status == "ok" else []

    def thrust_line(self) -> dict:
        lim = self.limit
        if lim.N is None:
            return {}
        return {"angle_deg": lim.disc.joint_angle_deg.tolist(), "N_kN": kN(lim.N[0] + lim.N[1]).tolist(),
                "eccentricity": [None if not np.isfinite(e) else float(e) for e in lim.eccentricity]}


def mass_nodes(curve: MidCurve) -> tuple:
    """Arc lengths (m) of the point masses of ``curve`` (a continuous mesh puts nodes there)."""
    b = getattr(curve, "_built", None)           # (the nearest section: none inside a crown wedge)
    return tuple(curve.nearest_section(b["s_m"]).tolist()) if b is not None else ()


def load_factor(curve: MidCurve, loads, elements: int | None = None, voussoirs: int | None = None,
                continuum: bool | None = None, verify: bool = True, nodes: np.ndarray | None = None,
                disc=None) -> LoadFactor:
    """Load factor of the downward point ``loads`` ``[(x, P), ...]`` (m from the left springing,
    kN per metre of width) on ``curve`` (with its fill and masses), on ``elements`` rigid
    elements (continuous arch, default 200; ``continuum`` True by default) or ``voussoirs``;
    ``nodes``: the mesh instead (arc lengths, m); ``disc``: its discretisation, used when its
    nodes are those of the analysis (loads moved over one mesh, or a mesh with nodes at the
    loads already, share its factorised statics)."""
    live = PointLoads.of(curve, loads)
    if live is None:
        raise InputError("the load factor needs at least one live load (x in m, P > 0 in kN/m)")
    if elements is not None and voussoirs is not None:
        raise InputError("give either elements (continuous arch) or voussoirs (discrete arch), not both")
    if continuum is None:
        continuum = voussoirs is None
    keep = tuple(curve.fixed_nodes)
    if nodes is None:
        n = (check_count(voussoirs, "voussoirs", MIN_VOUSSOIRS) if voussoirs is not None
             else check_count(DEFAULT_ELEMENTS if elements is None else elements, "elements", MIN_ELEMENTS))
        nodes = uniform_nodes(curve, n)
        if continuum and mass_nodes(curve):
            nodes = nodes_through(nodes, np.array(mass_nodes(curve)), keep=keep)
    if continuum:
        keep = keep + mass_nodes(curve)
        at = curve.nearest_section(live.s)      # a load over a crown wedge: the wedge's section
        nodes = nodes_through(nodes, at, keep=keep)
        keep = keep + tuple(at.tolist())
    if disc is None or disc.curve is not curve or not np.array_equal(disc.nodes_s, nodes):
        disc = discretize(curve, nodes, like=disc if disc is not None and disc.curve is curve else None)
    lim = limit_analysis(disc, 1, verify=verify, live=live)
    out = LoadFactor(lim.status, lim.A_L if lim.status == "ok" else float("nan"), live, lim,
                     verification={"limit_mesh": lim.verification})
    if not continuum or lim.status == "no_mechanism":
        return out
    cont = continuum_limit(disc, 1, lim=lim, live=live)
    if cont.status == "ok":
        out.value, out.lower = cont.A_L, cont.A_L_lower
        out.verification["continuum_violation"] = cont.violation
        out.verification["continuum_gap"] = cont.gap
    if cont.status == "no_mechanism":
        out.status, out.value = "no_mechanism", float("nan")
        return out
    if cont.status == "cannot_stand" or cont.exact_hinges:
        disc = discretize(curve, nodes_through(nodes, cont.hinge_s, keep=keep), like=disc)
        lim = limit_analysis(disc, 1, verify=verify, live=live)
        if lim.status != cont.status:
            raise SolverError(f"load factor: the continuum says {cont.status}, the mesh through its hinges "
                              f"says {lim.status}")
        if cont.status == "ok":
            out.verification["hinge_refinement_gap"] = abs(lim.A_L - cont.A_L) / cont.A_L
    out.status, out.limit = cont.status, lim
    if cont.status != "ok":
        out.value = float("nan")
    out.verification["limit"] = lim.verification
    if verify:
        check(out.verification, "load factor of the live loads")
    return out
