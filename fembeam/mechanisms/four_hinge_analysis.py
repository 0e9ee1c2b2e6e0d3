"""Four-hinge impact analysis of an arch (Sects. 3-5, Appendix A), start to finish.

:func:`four_hinge_impact` runs the general analysis (limit LP and impact QP, for
``r_max`` and the incipient mechanism), takes the hinges before the impact (default:
the incipient mechanism), chooses the hinges after it (``model``: ``"prescribed"``,
``"restricted"``: best compatible four-hinge mechanism of (16)-(17), or
``"classical"``: mirrored hinges, impulses through the points opposite the closing
hinges) and computes ``r``, ``alpha'`` and the impulse line with its admissibility.
:meth:`FourHingeImpact.picture_fields` gives the rigid-element fields for the VTK
export and the pictures of :mod:`fembeam.output`.
"""
from __future__ import annotations

import time
from dataclasses import dataclass, field
from typing import Callable

import numpy as np

from ..analysis import AnalysisResult, analyze
from ..errors import InputError
from ..fem import discretize, nodes_through, uniform_nodes
from ..geometry import MidCurve
from .classical import classical_impact
from .hinge import ROCKING_SIDES, Hinge
from .impulse_line import ImpulseLine, four_hinge_impulse_line
from .mechanism import Mechanism
from .restricted import MAX_EXHAUSTIVE_JOINTS, best_four_hinge_continuous, best_four_hinge_discrete

__all__ = ["FourHingeImpact", "four_hinge_impact", "hinge_zones", "MODELS", "DEFAULT_SECTIONS", "SizeLimit",
           "SIZE_LIMITS"]

MODELS = ("restricted", "prescribed", "classical")
DEFAULT_SECTIONS = 720   # continuous arch: impulse line checked at 720 + 1 sections (+ the hinges)

# units of the JSON of ``fembeam impact`` (per metre of width); the impulses and the inertia
# figures are those of the pre-impact mechanism at a rate alpha = 1 rad/s
_PER_RATE = " (pre-impact mechanism at alpha = 1 rad/s)"
UNITS = {"A_L": "g", "density": "kg/m^3", "radius": "m", "thickness": "m", "angle_deg": "deg",
         "Gamma": "kg m^2/m" + _PER_RATE, "Lambda": "kg m^2/m" + _PER_RATE,
         "Lambda_after": "kg m^2/m (post-impact mechanism at 1 rad/s)",
         "impulse_line.I_t": "N s/m" + _PER_RATE, "impulse_line.I_n": "N s/m" + _PER_RATE,
         "impulse_line.moment": "N m s/m" + _PER_RATE, "impulse_line.eccentricity": "m"}


@dataclass(frozen=True)
class SizeLimit:
    """Allowed range of a size argument and the measurement behind its upper limit
    (one run stays under ~1 min and ~2 GB on a 2-core machine)."""

    what: str
    lowest: int
    highest: int
    basis: str

    def check(self, value) -> int:
        """``value`` as an int; InputError stating the range unless it is an integer in it."""
        if isinstance(value, (bool, np.bool_)) or not isinstance(value, (int, np.integer)) \
                or not self.lowest <= value <= self.highest:
            raise InputError(f"{self.what} must be an integer in [{self.lowest}, {self.highest}] "
                             f"({self.basis}), got {value!r}")
        return int(value)


SIZE_LIMITS = {
    "elements": SizeLimit("the number of elements", 4, 100_000, "~30 s and 0.7 GB at the limit, linear"),
    "voussoirs": SizeLimit("the number of voussoirs", 1, 100_000, "~20 s and 0.7 GB at the limit, linear"),
    "exhaustive": SizeLimit("the number of voussoirs of the exhaustive four-hinge search", 1,
                            MAX_EXHAUSTIVE_JOINTS - 1, "16 C(N+1, 4) candidates: ~30 s at the limit, growing as N^4"),
    "grid": SizeLimit("the number of voussoirs (grid) of the exhaustive start of the continuous search", 3,
                      MAX_EXHAUSTIVE_JOINTS - 1, "16 C(N+1, 4) candidates: ~30 s at the limit, growing as N^4"),
    "sections": SizeLimit("the number of sections", 4, 1_000_000,
                          "~15 s and 0.35 GB at the limit; with the fields in JSON ~25 s, 0.6 GB and 100 MB of text"),
}


def hinge_zones(hinges: list[Hinge]) -> list[dict]:
    """Runs of consecutive open joints pivoting on the same side (a QP "hinge zone"):
    ``side``, ``from_deg``, ``to_deg`` and the number of ``joints``."""
    out: list[dict] = []
    for h in hinges:
        z = out[-1] if out else None
        if z and z["side"] == h.side and h.joints[0] == z["_last"] + 1:
            z["to_deg"], z["joints"], z["_last"] = round(h.angle_deg, 4), z["joints"] + 1, h.joints[0]
        else:
            out.append({"side": h.side, "from_deg": round(h.angle_deg, 4), "to_deg": round(h.angle_deg, 4),
                        "joints": 1, "_last": h.joints[0]})
    for z in out:
        z.pop("_last")
    return out


@dataclass
class FourHingeImpact:
    """Result of :func:`four_hinge_impact`.

    ``analysis``: the general analysis (``r_max`` = ``analysis.r``); ``before``: the
    hinges closing at the impact, ``pre`` the field arriving (``before`` in its
    closing sense); ``after`` the mechanism after the impact (unit rate) and ``line``
    its impulse line; ``r`` the restitution coefficient of ``model``; ``extra`` the
    model's own figures (JSON keys); ``line_at(sections)`` the line at other sections.
    Without a four-hinge impact ``line`` is None and ``outcome``/``explanation`` say why:
    the arch does not rock (``analysis.outcome``, ``r`` None), its incipient mechanism
    is not four rotating hinges (``"not_four_hinge"``, ``r`` None) or no compatible
    four-hinge mechanism does positive work (``"four_hinge_arrested"``, ``r = 0``).

    Examples
    --------
    :func:`four_hinge_impact` returns it; on the paper's arch of 12 voussoirs the best
    four-hinge mechanism after the impact (hinges in deg) keeps nearly the fraction of
    the kinetic energy the general impact QP keeps:

    >>> import fembeam
    >>> from fembeam.mechanisms.four_hinge_analysis import four_hinge_impact
    >>> arch = fembeam.CircularArch(radius=1.0, thickness=0.15, embrace_deg=157.5)
    >>> res = four_hinge_impact(arch, voussoirs=12)
    >>> print(res.model, [f"{a:g}" for a in res.after.angles_deg()])
    restricted ['0', '52.5', '105', '157.5']
    >>> print(f"r = {res.r:.4f}, r_max = {res.analysis.r:.4f}")
    r = 0.6071, r_max = 0.6137
    """

    curve: MidCurve
    analysis: AnalysisResult
    model: str = ""
    r: float | None = None
    before: Mechanism | None = None
    pre: Mechanism | None = None
    after: Mechanism | None = None
    line: ImpulseLine | None = None
    extra: dict = field(default_factory=dict)
    line_at: Callable[[np.ndarray], ImpulseLine] | None = None
    picture_n: int = 200          # pieces of the pictures' uniform mesh: elements or voussoirs
    time_s: float = 0.0
    outcome: str = ""
    explanation: str = ""

    def to_dict(self, fields: bool = False) -> dict:
        """The JSON of ``fembeam impact`` (``fields``: the impulse line at every section)."""
        res = self.analysis
        out = {"command": "impact", "mode": res.mode, "geometry": res.geometry,
               "outcome": self.outcome or res.outcome, "analysis_outcome": res.outcome,
               "A_L": res.A_L if np.isfinite(res.A_L) else None}
        if self.line is None:
            r_max = res.r if np.isfinite(res.r) else None
            hb = self.before.to_list() if self.before is not None else [h.to_dict() for h in res.hinges_before]
            out.update(r=self.r, explanation=self.explanation, hinges_before=hb, hinges_after=[],
                       admissibility=None, r_max=r_max, hinges_after_qp=[h.to_dict() for h in res.hinges_after])
            if r_max is None:
                out["r_max_reason"] = f"no impact: outcome {res.outcome}"
            out["time_s"] = round(self.time_s, 3)
            out["units"] = dict(UNITS)
            return out
        out.update({
            "model": self.model,
            "r": float(self.r),
            "hinges_before": self.before.to_list(),
            "hinges_after": self.after.to_list(),
            "admissibility": self.line.admissibility(),
            "r_max": res.r,
            "r_max_minus_r": res.r - float(self.r),
            "hinges_after_qp": [h.to_dict() for h in res.hinges_after],
            "qp_hinge_zones": hinge_zones(res.impact.hinges) if res.impact is not None else [],
            "qp_elements": res.n,
            **self.extra,
        })
        if fields:
            out["impulse_line"] = self.line.to_dict()
        out["time_s"] = round(self.time_s, 3)
        out["units"] = dict(UNITS)
        return out

    def picture_fields(self) -> tuple:
        """``(disc, d0, d, hinges_before, hinges_after, impulse)`` for
        :func:`fembeam.output.export.write_fields` and the pictures: rigid elements whose
        joints are the voussoir joints (or a uniform mesh through both sets of hinges),
        the pre-impact field, the post-impact field ``alpha' x after`` and its impulse
        line at the joints (per-joint arrays)."""
        if self.line is None:
            raise InputError(f"nothing to draw: outcome {self.outcome or self.analysis.outcome}")
        curve, before, after = self.curve, self.before, self.after
        nodes = nodes_through(uniform_nodes(curve, self.picture_n), np.concatenate([before.s, after.s]),
                              keep=curve.fixed_nodes)
        disc = discretize(curve, nodes)
        line = self.line_at(disc.joint_s)
        idx = np.abs(line.s[None, :] - disc.joint_s[:, None]).argmin(1)
        impulse = {"angle_deg": disc.joint_angle_deg, "eccentricity": line.eccentricity[idx],
                   "I_t": line.I_t[idx], "I_n": line.I_n[idx], "moment": line.M[idx]}
        post = after.with_alpha(line.alpha_ratio)
        return disc, self.pre.dofs(disc), post.dofs(disc), self.pre.hinges(), post.hinges(), impulse

    @property
    def title(self) -> str:
        return f"{self.model} four-hinge impact: r = {self.r:.4f}"


def _hinges(curve: MidCurve, spec, joints, what: str) -> Mechanism:
    """A checked :class:`Mechanism` from a Mechanism or ``(angles_deg, sides)``
    (:meth:`Mechanism.from_angles`/:meth:`Mechanism.checked`: one check for every hinge list)."""
    if isinstance(spec, Mechanism):
        if spec.curve is not curve and spec.curve != curve:
            raise InputError(f"{what}: the mechanism belongs to another member")
        return Mechanism.checked(curve, spec.s, spec.sides, spec.alpha, joints, what)
    try:
        angles, sides = spec
    except (TypeError, ValueError):
        raise InputError(f"{what}: expected a Mechanism or (angles_deg, sides), got {spec!r}") from None
    return Mechanism.from_angles(curve, angles, sides, joints=joints, what=what)


def _not_four_hinge(hinges) -> str:
    listed = ", ".join(f"{h.angle_deg:.2f} {h.side}" for h in hinges) or "none"
    return (f"the incipient mechanism has {len(hinges)} hinges ({listed}), not four rotating hinges, so the "
            "four-hinge impact model (r, alpha', impulse line) does not apply; r_max of the general impact QP "
            "needs no four-hinge mechanism and is reported. Prescribe the hinges before the impact (--before) "
            "to analyse a four-hinge impact anyway.")


def four_hinge_impact(curve: MidCurve, *, voussoirs: int | None = None, elements: int | None = None,
                      direction: int = 1, before=None, after=None, model: str | None = None,
                      sections: int = DEFAULT_SECTIONS, grid: int = 31) -> FourHingeImpact:
    """Four-hinge impact of ``curve`` (continuous, or ``voussoirs`` rigid voussoirs).

    ``before``/``after``: :class:`Mechanism` or ``(angles_deg, sides)``, checked by
    :meth:`Mechanism.checked` (on a discrete arch the hinges must be at joints);
    ``before`` defaults to the incipient mechanism of the limit analysis. ``model``
    defaults to ``"prescribed"`` when ``after`` is given, else ``"restricted"``. On a
    continuous arch the impulse line is checked at ``sections + 1`` sections plus the
    hinges, on a discrete one at the joints; ``grid``: voussoirs of the exhaustive start
    of the continuous restricted search. ``elements`` is the mesh of the general QP.
    The sizes are checked against :data:`SIZE_LIMITS` before any computation.
    """
    clock = time.perf_counter()
    model = model or ("prescribed" if after is not None else "restricted")
    if model not in MODELS:
        raise InputError(f"unknown four-hinge model {model!r}: expected one of {', '.join(MODELS)}")
    if (model == "prescribed") != (after is not None):
        raise InputError("the hinges after the impact are given exactly for the prescribed model")
    if not isinstance(curve, MidCurve):
        raise InputError(f"four_hinge_impact needs a member (e.g. fembeam.CircularArch), got {type(curve).__name__}")
    discrete = voussoirs is not None
    if discrete and elements is not None:
        raise InputError("give either elements (continuous arch) or voussoirs (discrete arch), not both")
    if discrete:
        try:
            SIZE_LIMITS["exhaustive" if model == "restricted" else "voussoirs"].check(voussoirs)
        except InputError as e:
            if model != "restricted":
                raise
            raise InputError(f"{e}; prescribed or classical hinges allow up to "
                             f"{SIZE_LIMITS['voussoirs'].highest:,} voussoirs") from None
    else:
        if elements is not None:
            SIZE_LIMITS["elements"].check(elements)
        SIZE_LIMITS["sections"].check(sections)
        if model == "restricted":
            SIZE_LIMITS["grid"].check(grid)
    L = curve.length
    sec = uniform_nodes(curve, voussoirs) if discrete else np.linspace(0.0, L, sections + 1)
    if not discrete and curve.solid_spans:      # no section inside a crown wedge; the crown joint is one
        sec = np.union1d(sec[curve.admissible(sec)], curve.fixed_nodes)
    joints = sec if discrete else None
    if before is not None:
        before = _hinges(curve, before, joints, "hinges before the impact")
    if after is not None:
        after = _hinges(curve, after, joints, "hinges after the impact")

    res = analyze(curve, elements=elements, voussoirs=voussoirs, direction=direction, thrust=False)
    out = FourHingeImpact(curve, res, picture_n=voussoirs or elements or 200)
    out.time_s = time.perf_counter() - clock
    if res.outcome not in ("rocking", "arrested"):
        out.explanation = f"the arch does not rock (outcome {res.outcome}): no impact"
        return out
    if before is None:
        hb = res.hinges_before
        if len(hb) != 4 or any(h.side not in ROCKING_SIDES for h in hb):
            out.outcome, out.explanation = "not_four_hinge", _not_four_hinge(hb)
            return out
        before = Mechanism.from_hinges(curve, hb)
    sgn = before.compatible_sign()
    if sgn == 0:
        raise InputError("the hinges before the impact do not form a compatible mechanism: no sense of "
                         "rotation opens all four; choose other sides or positions")
    pre = before.closing()   # the arch returns along -u

    extra: dict = {}
    if model == "classical":
        cl = classical_impact(before, sec, alpha=-sgn)
        after, line, r = cl.after, cl.line, cl.r
        line_at = lambda s_: classical_impact(before, s_, alpha=-sgn).line  # noqa: E731
        extra = {"alpha_ratio": cl.alpha_ratio, "r_energy_same_hinges": cl.r_energy,
                 "opens_mirrored_hinges": cl.line.extra["opens_mirrored_hinges"],
                 "creates_energy": bool(cl.r > 1.0),   # r > 1: the model's impulses do positive work
                 "impulses_through": before.opposite().to_list()}
    else:
        if model == "restricted":
            if discrete:
                rr = best_four_hinge_discrete(sec, pre)
            else:
                qh = res.hinges_after
                starts = [Mechanism.from_hinges(curve, qh)] if len(qh) == 4 and all(
                    h.side in ROCKING_SIDES for h in qh) else []
                rr = best_four_hinge_continuous(pre, grid=grid, starts=starts)
            if rr.after is None:
                out.model, out.r, out.before, out.pre = model, 0.0, before, pre
                out.outcome = "four_hinge_arrested"
                out.explanation = ("no compatible four-hinge mechanism does positive work after the impact: "
                                   "within the four-hinge model the arch stops (r = 0)")
                out.time_s = time.perf_counter() - clock
                return out
            after = rr.after
            extra = {"candidates": rr.candidates, "compatible_candidates": rr.compatible, "search": rr.method,
                     "runner_up": [{"r": r_, "hinges": h.to_list()} for r_, h in rr.ranking[:3]]}
        line = four_hinge_impulse_line(pre, after, sec)
        line_at = lambda s_: four_hinge_impulse_line(pre, after, s_)  # noqa: E731
        r = line.extra["r"]
        extra.update(alpha_ratio=line.extra["alpha_ratio_15"], alpha_ratio_8_11=line.alpha_ratio,
                     alpha_gap=line.extra["alpha_gap"], compatible=line.extra["compatible"],
                     Gamma=line.extra["Gamma"], Lambda=line.extra["Lambda"], Lambda_after=line.extra["Lambda_after"])
    out.model, out.r, out.before, out.pre, out.after, out.line = model, float(r), before, pre, after, line
    out.extra, out.line_at = extra, line_at
    out.time_s = time.perf_counter() - clock
    return out
