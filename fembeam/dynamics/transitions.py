"""The impact model at every impact: which mechanism follows, and with what rate.

When the member returns to its undeformed shape along a mechanism, every hinge closes at
once.  The mechanism after the impact is the best compatible one-parameter mechanism of the
restricted problem (the largest ``r = Gamma^2 / (Lambda Lambda')`` among compatible
mechanisms, closed-form integrals, :mod:`fembeam.mechanisms.restricted`), with
``alpha' = (Gamma / Lambda') alpha``.  Both scale linearly with the incoming rate, so a
:class:`Transition` is computed once per mechanism (for a unit closing rate) and reused.
Beside it the general impact QP on the finite-element mesh gives ``r_qp``, the upper bound
over all compatible fields (hinges anywhere).
"""
from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from ..analysis import impact
from ..errors import InputError
from ..fem import discretize, nodes_through, uniform_nodes
from ..geometry import MidCurve
from ..mechanisms import ROCKING_SIDES, Mechanism, merge_adjacent, post_impact
from ..mechanisms.restricted import ExhaustiveGeometry, best_four_hinge_continuous, best_four_hinge_discrete

__all__ = ["Transition", "ImpactModel", "HINGE_GRID"]

HINGE_GRID = 100_000  # continuous member: hinge positions after an impact on L / HINGE_GRID
SEARCH_GRID = 31      # continuous member: voussoirs of the exhaustive search that starts the local one
KEEP_GEOMETRY = 40    # discrete arch: the exhaustive search's geometry kept up to this many voussoirs (~20 MB)


@dataclass(frozen=True)
class Transition:
    """The impact of a mechanism closing at unit rate (:class:`ImpactModel`).

    Attributes
    ----------
    before : Mechanism
        The mechanism before the impact.
    after : Mechanism or None
        The mechanism after it (None: the member is arrested).
    r : float
        ``K'/K`` of the impact.
    alpha_ratio : float
        Post-impact rate of ``after`` per unit incoming rate, with the sign that opens
        ``after``.
    r_qp : float or None
        ``K'/K`` of the general impact QP (None unless asked for).
    hinges_qp : list of Hinge
        The hinges of the general QP's post-impact field.

    Examples
    --------
    An :class:`ImpactModel` called with a mechanism returns it: the paper's mechanism
    closes on the one of hinges at 0, 52.5, 105 and 157.5 deg, keeping a fraction ``r``
    of its kinetic energy:

    >>> import fembeam
    >>> from fembeam.dynamics import ImpactModel
    >>> arch = fembeam.CircularArch(radius=1.0, thickness=0.15, embrace_deg=157.5)
    >>> sides = ["intrados", "extrados", "intrados", "extrados"]
    >>> mech = fembeam.Mechanism.from_angles(arch, [0.0, 52.5, 118.125, 157.5], sides)
    >>> tr = ImpactModel(arch, voussoirs=12)(mech)
    >>> print(f"r = {tr.r:.4f} (QP: {tr.r_qp:.4f}), rate ratio {tr.alpha_ratio:.4f}")
    r = 0.6071 (QP: 0.6137), rate ratio 1.3298
    >>> print([f"{a:g}" for a in tr.after.angles_deg()])
    ['0', '52.5', '105', '157.5']
    """

    before: Mechanism
    after: Mechanism | None
    r: float
    alpha_ratio: float
    r_qp: float | None = None
    hinges_qp: list = field(default_factory=list)


class ImpactModel:
    """The impact transitions of a member: calling it with a mechanism gives its
    :class:`Transition` (solved once per mechanism, then cached).

    Parameters
    ----------
    curve : MidCurve
        The member.
    voussoirs : int, optional
        Discrete arch of this many voussoirs (hinges only at their joints).
    elements : int, optional
        Otherwise the continuous member (hinges anywhere), with this many rigid elements
        for the general QP (default 200).
    backend : str, optional
        Solver of the general impact QP.
    qp : bool, optional
        Also solve the general impact QP (``r_qp``).

    Examples
    --------
    >>> import fembeam
    >>> from fembeam.dynamics import ImpactModel
    >>> arch = fembeam.CircularArch(radius=1.0, thickness=0.15, embrace_deg=157.5)
    >>> model = ImpactModel(arch, voussoirs=12)
    >>> sides = ["intrados", "extrados", "intrados", "extrados"]
    >>> mech = fembeam.Mechanism.from_angles(arch, [0.0, 52.5, 118.125, 157.5], sides)
    >>> print(f"r = {model(mech).r:.4f};", model.solved, "mechanism solved")
    r = 0.6071; 1 mechanism solved
    """

    def __init__(self, curve: MidCurve, voussoirs: int | None = None, elements: int = 200,
                 backend: str = "clarabel", qp: bool = True):
        self.curve, self.voussoirs, self.elements = curve, voussoirs, int(elements)
        self.backend, self.qp = backend, qp
        self._cache: dict[tuple, Transition] = {}
        self._geometry: ExhaustiveGeometry | None = None   # of the exhaustive search, once for all

    def _exhaustive(self, joints) -> ExhaustiveGeometry:
        """The geometry of the exhaustive search on ``joints`` (the same for every mechanism
        of the member), computed on first use."""
        if self._geometry is None:
            self._geometry = ExhaustiveGeometry(self.curve, joints)
        return self._geometry

    def __call__(self, before: Mechanism) -> Transition:
        key = before.key
        if key not in self._cache:
            self._cache[key] = self._solve(before.canonical())
        return self._cache[key]

    @property
    def solved(self) -> int:
        """Number of distinct mechanisms whose impact was solved."""
        return len(self._cache)

    def _general_qp(self, pre: Mechanism):
        if not self.qp:
            return None, []
        if self.voussoirs is not None:
            disc = discretize(self.curve, uniform_nodes(self.curve, self.voussoirs))
        else:
            disc = discretize(self.curve, nodes_through(uniform_nodes(self.curve, self.elements), pre.s,
                                                        keep=self.curve.fixed_nodes))
        res = impact(disc, pre.dofs(disc), backend=self.backend)
        hinges = res.hinges if self.voussoirs is not None else merge_adjacent(disc, res.hinges)
        return float(res.r), hinges

    def _continuous(self, pre: Mechanism, hinges_qp) -> list[Mechanism]:
        """Continuous member: the restricted optimum, snapped to ``HINGE_GRID`` positions.

        The search (:func:`best_four_hinge_continuous`: exhaustive on a grid, then local from
        its best candidates and from the general QP's hinges) depends on ``before`` alone, never
        on the mechanisms solved earlier: a transition is a function of the mechanism's key
        (:attr:`~fembeam.mechanisms.Mechanism.key`), whatever the order in which a motion meets
        them.  Snapping makes the set of mechanisms finite, so that a long motion reuses its
        transitions; ``r`` is stationary at the optimum, so the snap changes it by
        O((L / HINGE_GRID)^2)."""
        curve, L = self.curve, self.curve.length
        starts = [Mechanism.from_hinges(curve, hinges_qp)] if len(hinges_qp) == 4 and all(
            h.side in ROCKING_SIDES for h in hinges_qp) else []
        grid = uniform_nodes(curve, SEARCH_GRID)
        rr = best_four_hinge_continuous(pre, grid=SEARCH_GRID, starts=starts, geometry=self._exhaustive(grid))
        found = [rr.after] if rr.after is not None else []
        return [Mechanism(curve, tuple(np.round(np.asarray(m.s) / L * HINGE_GRID) * L / HINGE_GRID), m.sides)
                for m in found]

    def _solve(self, before: Mechanism) -> Transition:
        sgn = before.compatible_sign()
        if sgn == 0:
            raise InputError("the mechanism before the impact is not compatible")
        pre = before.with_alpha(-sgn)            # closing at unit rate
        r_qp, hinges_qp = self._general_qp(pre)
        curve = self.curve
        if before.n_hinges == 1:                 # a block: the other corners of the base
            cands = [Mechanism(curve, before.s, (k,)) for k in ROCKING_SIDES]
        elif self.voussoirs is not None:
            joints = uniform_nodes(curve, self.voussoirs)
            rr = best_four_hinge_discrete(joints, pre, geometry=self._exhaustive(joints)
                                          if self.voussoirs <= KEEP_GEOMETRY else None)
            cands = [rr.after] if rr.after is not None else []
        else:
            cands = self._continuous(pre, hinges_qp)
        best = None
        for c in cands:
            fig = post_impact(pre, c)
            if fig.compatible and (best is None or fig.r > best[1].r):
                best = (c, fig)
        if best is None:
            return Transition(before, None, 0.0, 0.0, r_qp, hinges_qp)
        after, fig = best
        return Transition(before, after.with_alpha(1.0), float(fig.r), float(fig.alpha_ratio), r_qp, hinges_qp)
