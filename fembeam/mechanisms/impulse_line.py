"""The impulse line of a four-hinge impact (Sects. 2-4, eqs. (3)-(4), (8)-(11)).

For a pre-impact field ``before`` and a post-impact mechanism of prescribed shape
``after`` (``alpha' x`` its unit field; both are
:class:`~fembeam.mechanisms.mechanism.Mechanism`), the momentum balances (3) of the arch
portions leave four scalar unknowns: ``alpha'`` and the internal linear and angular
impulse at one section.  Requiring the line to pass through four points (one per
section ``s_a < s_b < s_c < s_d``) fixes them; with the points at the new hinges
this is the paper's system (8)-(11) (impulses ``I_C'1``, ``I_C'2`` applied at
``C'1``, ``C'2``; zero moment about ``C'13`` and ``C'23``), and ``alpha'`` must then
equal ``Gamma / Lambda'`` of (15) (checked).  With the points opposite the closing
hinges it is the classical model (:mod:`fembeam.mechanisms.classical`).

Conventions (as :class:`~fembeam.analysis.impact.ImpactResult`): ``I(s)`` is the impulse
exerted on the part left of ``s`` by the part on its right, so (3) reads
``I(s) = I(s_a) + int_{s_a}^{s} (dp' - dp)`` and compression is ``I_t < 0``;
``M`` is the moment of the impulses about the mid-curve point ``X(s)`` and the
eccentricity ``e = M / I_t`` (m) is measured from the mid-curve along ``n`` (+ to
the intrados).  The paper's ``lambda`` of (4) is measured from the centroid ``G``,
which lies ``kappa t^2 / 12`` outward: ``lambda = e + kappa t^2 / 12``.
"""
from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from ..errors import SolverError
from ..geometry import MidCurve
from .energy import momenta, post_impact
from .mechanism import Mechanism

__all__ = ["ImpulseLine", "impulse_line_through", "four_hinge_impulse_line", "sections_union",
           "ADMISSIBILITY_TOL"]

# relative tolerances of the admissibility report (of t for distances, of max|I_t|
# for forces): the linear algebra is exact to ~1e-13
ADMISSIBILITY_TOL = 1e-9


def sections_union(curve: MidCurve, *arrays) -> np.ndarray:
    """Sorted union of section arrays (m), merging points closer than 1e-9 L."""
    s = np.sort(np.concatenate([np.atleast_1d(np.asarray(a, float)) for a in arrays]))
    keep = np.concatenate([[True], np.diff(s) > 1e-9 * curve.length])
    return s[keep]


def _cross(a, b):
    return a[0] * b[1] - a[1] * b[0]


@dataclass
class ImpulseLine:
    """Internal impulses at the sections ``s`` (m) for post-impact field ``alpha' x after``.

    ``I`` (2, n): impulse on the left part by the right part (N s/m);
    ``M``: its moment about the mid-curve point (N m s/m); ``thickness`` (m).
    """

    curve: MidCurve
    s: np.ndarray
    I: np.ndarray
    M: np.ndarray
    alpha_ratio: float                     # alpha'/alpha of the solved system
    through: np.ndarray                    # (2, 4): sections s and offsets y (m) imposed
    after: Mechanism
    extra: dict = field(default_factory=dict)

    @property
    def angle_deg(self) -> np.ndarray:
        return np.asarray(self.curve.angle_deg(self.s), float)

    @property
    def thickness(self) -> np.ndarray:
        return self.curve.thickness_at(self.s)

    @property
    def I_t(self) -> np.ndarray:
        t = self.curve.tangent(self.s)
        return self.I[0] * t[0] + self.I[1] * t[1]

    @property
    def I_n(self) -> np.ndarray:
        n = self.curve.normal(self.s)
        return self.I[0] * n[0] + self.I[1] * n[1]

    @property
    def eccentricity(self) -> np.ndarray:
        """``e = M / I_t`` (m, from the mid-curve, + to the intrados); NaN where ``I_t = 0``."""
        It = self.I_t
        with np.errstate(invalid="ignore", divide="ignore"):
            return np.where(np.abs(It) > 1e-12 * np.max(np.abs(It), initial=0.0), self.M / It, np.nan)

    def at(self, s) -> np.ndarray:
        """Eccentricity at sections ``s`` that are among ``self.s`` (nearest match)."""
        idx = np.abs(self.s[None, :] - np.atleast_1d(s)[:, None]).argmin(1)
        return self.eccentricity[idx]

    def admissibility(self, tol: float = ADMISSIBILITY_TOL) -> dict:
        """Kinematic (through the new hinges) and static (compressive, inside the
        thickness) admissibility at the evaluated sections; ``failures`` lists where
        each check fails: for the hinges one entry per missed hinge, for the static checks
        one entry per run of consecutive failing sections (``from_deg``-``to_deg``,
        worst section ``angle_deg`` and its ``value``)."""
        curve, t = self.curve, self.thickness
        It, e = self.I_t, self.eccentricity
        scale = max(np.max(np.abs(It)), 1e-300)
        carried = np.abs(It) > 1e-9 * scale
        fails = []
        # kinematic: through the four new hinges
        hs = np.asarray(self.after.s, float)
        yh = self.after.pivot_y()
        eh = self.at(hs)
        miss = np.abs(eh - yh) / curve.thickness_at(hs)
        miss = np.where(np.isfinite(miss), miss, np.inf)
        for s_, m_, e_, t_, k in zip(hs, miss, eh, curve.thickness_at(hs), self.after.sides):
            if m_ > tol:
                fails.append({"angle_deg": float(curve.angle_deg(s_)), "check": "through_hinge",
                              "hinge_side": k, "value": None if not np.isfinite(e_) else float(e_ / t_)})
        # static: compressive (I_t <= 0), and inside the thickness (|e| <= t/2)
        tens = It / scale
        out = np.where(carried, (np.abs(np.nan_to_num(e)) - 0.5 * t) / t, -np.inf)
        fails += self._zones(tens > tol, tens, "compressive", tens)
        fails += self._zones(out > tol, out, "inside_thickness", e / t)
        return {
            "passes_through_hinges": bool(np.all(miss <= tol)),
            "inside_thickness": bool(np.all(out <= tol)),
            "compressive": bool(np.all(tens <= tol)),
            "max_miss_at_hinges": float(np.max(miss)),            # |e - y_hinge| / t
            "max_outside": float(max(0.0, np.max(out, initial=0.0))),   # (|e| - t/2) / t
            "max_tension": float(max(0.0, np.max(tens, initial=0.0))),   # I_t / max|I_t|
            "sections": int(self.s.size),
            "failures": fails,
        }

    def _zones(self, bad: np.ndarray, severity: np.ndarray, check: str, value: np.ndarray) -> list[dict]:
        """Runs of consecutive failing sections: extent and worst section (``value``:
        e/t for the thickness check, I_t/max|I_t| for the compression check)."""
        idx = np.flatnonzero(bad)
        out = []
        for run in np.split(idx, np.flatnonzero(np.diff(idx) > 1) + 1) if idx.size else []:
            w = run[np.argmax(severity[run])]
            out.append({"check": check, "angle_deg": float(self.angle_deg[w]), "value": float(value[w]),
                        "from_deg": float(self.angle_deg[run[0]]), "to_deg": float(self.angle_deg[run[-1]]),
                        "sections": int(run.size)})
        return out

    def to_dict(self) -> dict:
        e = self.eccentricity
        return {"angle_deg": self.angle_deg.tolist(), "I_t": self.I_t.tolist(), "I_n": self.I_n.tolist(),
                "moment": self.M.tolist(),
                "eccentricity": [None if not np.isfinite(x) else float(x) for x in e]}


def impulse_line_through(before: Mechanism, after: Mechanism, points_s, points_y,
                         sections) -> ImpulseLine:
    """Impulse line for the post-impact field ``alpha' x after`` (unit rate) passing
    through the points at sections ``points_s`` (4, increasing, m) offset ``points_y``
    (m, along ``n``); evaluated at ``sections`` (m).  Solves for ``alpha'`` and
    ``I(points_s[0])``."""
    curve = after.curve
    ps = np.asarray(points_s, float)
    pts = curve.point(ps, points_y)
    unit = after.with_alpha(1.0)
    sec = np.asarray(sections, float)
    br = sections_union(curve, ps, sec, [0.0, curve.length], before.breaks, unit.breaks)
    zero = np.zeros((3, 1))
    cb = np.concatenate([zero, np.cumsum(momenta(before, br), 1)], 1)   # int_0^s of (p, L_O)
    ca = np.concatenate([zero, np.cumsum(momenta(unit, br), 1)], 1)

    def cum(c, s):   # value at the break nearest to each s (s are among the breaks up to 1e-9 L)
        i = np.clip(np.searchsorted(br, s), 1, br.size - 1)
        i = np.where(np.abs(br[i - 1] - s) < np.abs(br[i] - s), i - 1, i)
        return c[:, i]

    Pa, Pk = pts[:, 0], pts[:, 1:]
    dA = cum(ca, ps[1:]) - cum(ca, ps[:1])   # (3, 3): unit after field, from s_a to s_k
    dB = cum(cb, ps[1:]) - cum(cb, ps[:1])
    # moment about P_k of the impulse at s_k vanishes:
    # (P_a - P_k) x I_a + alpha' (dL_a - P_k x dp_a) = dL_b - P_k x dp_b
    A = np.empty((3, 3))
    A[:, 0] = dA[2] - _cross(Pk, dA[:2])
    rel = Pa[:, None] - Pk
    A[:, 1] = -rel[1]          # d/dI_x of rel x I = rel_x I_y - rel_y I_x
    A[:, 2] = rel[0]
    b = dB[2] - _cross(Pk, dB[:2])
    with np.errstate(divide="ignore"):
        D = 1.0 / np.max(np.abs(A), axis=0)   # columns of one unit each (alpha': rho R^4, I: R)
    if not np.all(np.isfinite(D)) or np.linalg.cond(A * D) > 1e12:
        raise SolverError("the impulse line through these four points is not unique (degenerate points)")
    alpha, Ix, Iy = D * np.linalg.solve(A * D, b)
    Ia = np.array([Ix, Iy])
    Ma = _cross(Pa, Ia)   # about the origin: the impulse acts at P_a
    d = alpha * (cum(ca, sec) - cum(ca, ps[:1])) - (cum(cb, sec) - cum(cb, ps[:1]))
    I = Ia[:, None] + d[:2]
    MO = Ma + d[2]
    X = curve.position(sec)
    M = MO - _cross(X, I)
    return ImpulseLine(curve, sec, I, M, float(alpha), np.array([ps, np.asarray(points_y, float)]), after)


def four_hinge_impulse_line(before: Mechanism, after: Mechanism, sections) -> ImpulseLine:
    """The equilibrated, kinematically admissible impulse line of the four-hinge
    mechanism ``after`` (through its hinges, eqs. (8)-(11)); ``extra`` carries the
    closed-form figures of (15), (17) and the gap between the two ``alpha'``."""
    hs = np.asarray(after.s, float)
    sec = sections_union(after.curve, hs, sections)
    line = impulse_line_through(before, after, hs, after.pivot_y(), sec)
    fig = post_impact(before, after)
    line.extra = {"Gamma": fig.Gamma, "Lambda": fig.Lambda, "Lambda_after": fig.Lambda_after,
                  "alpha_ratio_15": fig.alpha_ratio, "r": fig.r, "compatible": fig.compatible,
                  "alpha_gap": abs(line.alpha_ratio - fig.alpha_ratio) / max(abs(fig.alpha_ratio), 1e-300)}
    return line
