"""``fembeam min-thickness``: the smallest thickness at which an arch (any shape) stands
under its own weight, with its collapse mechanism.

The thickness law of the arch is scaled by a factor ``k`` (a constant thickness, or both
ends of a linear springing-to-crown law); the smallest ``k`` that stands is bisected
(:func:`fembeam.minimum_thickness`).  The mechanism is the certificate of collapse just
below it: the compatible motion on which gravity does positive work.  Its inverse
``1/k`` is the geometric factor of safety of the arch as given.
"""
from __future__ import annotations

import json
import math

from ..analysis import analyze, minimum_thickness
from ..analysis.friction import EXACT_WITHOUT_FRICTION, REDUCED_FRICTION, THICKNESS_BOUND
from ..errors import InputError
from ..geometry import MidCurve
from .args import add_arch, arch_from, arch_title, finite_float, friction_coefficient


def register(sub) -> None:
    p = sub.add_parser("min-thickness", help="smallest thickness at which the arch stands, and its mechanism",
                       description="Minimum thickness under self-weight (any --shape or --midcurve): the smallest "
                                   "factor of the thickness law that admits a thrust line inside the arch, the "
                                   "collapse mechanism just below it and the geometric factor of safety.")
    add_arch(p)
    g = p.add_argument_group("discretisation")
    m = g.add_mutually_exclusive_group()
    m.add_argument("--elements", type=int, default=None, metavar="N",
                   help="rigid elements of the continuous arch, every section checked (default 200)")
    m.add_argument("--voussoirs", type=int, default=None, metavar="N",
                   help="discrete arch of N voussoirs: the joints only are checked")
    g.add_argument("--tol", type=finite_float, default=1e-6, metavar="TOL",
                   help="relative bisection tolerance on the thickness factor, in [1e-12, 0.1] (default 1e-6)")
    g.add_argument("--friction", type=friction_coefficient, default=None, metavar="MU",
                   help="Coulomb coefficient of the joints, in [0, 1000], associative flow (dilatant sliding): the "
                        "thickness found is then a LOWER bound, joints that slide without dilatancy may need more "
                        "(default: no sliding; docs/friction.md)")
    p.add_argument("--json", action="store_true", help="print one JSON object on stdout")
    p.set_defaults(func=run)


def _check(args) -> None:
    for opt in ("elements", "voussoirs"):
        n = getattr(args, opt)
        if n is not None and n < (4 if opt == "elements" else 1):
            raise InputError(f"--{opt} must be >= {4 if opt == 'elements' else 1}, got {n}")
    if not 1e-12 <= args.tol <= 0.1:
        raise InputError(f"--tol must be in [1e-12, 0.1], got {args.tol:g}")


def min_thickness(curve: MidCurve, elements: int | None = None, voussoirs: int | None = None,
                  tol: float = 1e-6, friction: float | None = None) -> dict:
    """Everything ``min-thickness --json`` prints (see :func:`run`)."""
    th = minimum_thickness(curve, elements=elements, voussoirs=voussoirs, tol=tol, friction=friction)
    desc = curve.describe() if hasattr(curve, "describe") else {}
    n = voussoirs if voussoirs is not None else (elements or 200)
    out = {"geometry": desc, "mode": "voussoirs" if voussoirs is not None else "continuous", "elements": n,
           "friction": friction, "bound": _bound(friction), **th.to_dict(), "thickness_min": None, "geometric_safety_factor": None,
           "hinges": [], "slides": [], "explanation": None}
    law = _law(desc)
    if th.outcome == "ok":
        out["thickness_min"] = {k: th.scale * v for k, v in law.items()}
        out["geometric_safety_factor"] = 1.0 / th.scale
        span = desc.get("span")
        if span and "thickness" in law:
            out["t_min_over_span"] = th.scale * law["thickness"] / span
        # the collapse certificate just below, on the mesh refined through its hinges (analyze's)
        lim = analyze(curve.with_thickness_scaled(th.lower), elements=elements, voussoirs=voussoirs,
                      friction=friction, tmin_tol=0.1, thrust=False).limit
        if lim.status == "cannot_stand":
            out["hinges"] = [h.to_dict() for h in lim.hinges]
            out["slides"] = list(lim.slides)
    elif th.outcome == "stands_at_any_thickness":
        floor = curve.min_thickness_scale
        out["thickness_min"] = {k: 0.0 for k in law}
        out["thickness_checked_min"] = {k: floor * v for k, v in law.items()}
        thinnest = ", ".join(f"{k.replace('_', ' ')} {v:.3g} m" for k, v in out["thickness_checked_min"].items())
        out["explanation"] = (f"a thrust line fits inside the arch at every thickness checked, down to {thinnest} "
                              f"({floor:.3g} times the given law; the check stops where the thickest section is "
                              "1/2000 of the span): the mid-curve is (close to) a funicular of the weight, so "
                              "the thrust line strays from it by an amount of order t^2 x curvature, which fits "
                              "inside the half-thickness t/2 for every small t; the minimum thickness is zero")
    else:
        cap = th.lower if math.isfinite(th.lower) else th.curve.max_thickness_scale
        out["explanation"] = (f"no thickness up to {cap:.6g} times the given law (the largest checked: where the "
                              "intrados folds, t |curvature| = 2, or 2^40) admits a thrust line"
                              + ("" if friction is None else f" with |S| <= {friction:g} N at every joint"))
    return out


def _bound(friction: float | None) -> str | None:
    """What the thickness found is for joints that slide without dilatancy (None: joints that never slide)."""
    if friction is None:
        return None
    return EXACT_WITHOUT_FRICTION if friction == REDUCED_FRICTION else THICKNESS_BOUND


def _law(desc: dict) -> dict:
    if isinstance(desc.get("thickness"), (int, float)):
        return {"thickness": float(desc["thickness"])}
    if "thickness_springing" in desc:
        return {"thickness_springing": float(desc["thickness_springing"]),
                "thickness_crown": float(desc["thickness_crown"])}
    if "t_over_R" in desc:
        return {"thickness": float(desc["t_over_R"] * desc["radius"])}
    return {}


def summary(out: dict) -> str:
    g = out["geometry"]
    what = (f"{out['elements']} rigid elements (continuous: every section checked)" if out["mode"] == "continuous"
            else f"{out['elements']} voussoirs (joints checked)")
    lines = [f"fembeam min-thickness: {arch_title(g)}", f"  mesh: {what}"
             + ("" if out["friction"] is None else f", friction coefficient {out['friction']:g}")]
    if out["outcome"] == "ok":
        tm = out["thickness_min"]
        size = ", ".join(f"{k.replace('_', ' ')} {v:.6g} m" for k, v in tm.items())
        lines.append(f"  minimum thickness: {out['thickness_scale']:.6f} x the given law ({size})")
        extra = []
        if out.get("t_min_over_R") is not None:
            extra.append(f"t/R = {out['t_min_over_R']:.6f}")
        if out.get("t_min_over_span") is not None:
            extra.append(f"t/span = {out['t_min_over_span']:.6f}")
        if extra:
            lines.append("    " + ", ".join(extra))
        lines.append(f"    bracket [{out['lower']:.8f}, {out['thickness_scale']:.8f}] of the factor, "
                     f"{out['solves']} margin LPs")
        if out.get("bound") == THICKNESS_BOUND:
            lines.append(f"    with mu = {out['friction']:g} (associative flow) a LOWER bound: joints that slide without "
                         "dilatancy may need more (docs/friction.md)")
        lines.append(f"  geometric factor of safety of the arch as given: {out['geometric_safety_factor']:.4f}"
                     + (" (an upper bound)" if out.get("bound") == THICKNESS_BOUND else ""))
        hs = ", ".join(f"{h['angle_deg']:.2f} deg {h['side']}" for h in out["hinges"]) or "none found"
        lines.append(f"  collapse mechanism just below it: {hs}")
        if out.get("slides"):
            lines.append("    sliding at " + ", ".join(f"{sl['angle_deg']:.2f} deg" for sl in out["slides"]))
    elif out["outcome"] == "stands_at_any_thickness":
        lines.append("  minimum thickness: 0 (stands at any thickness)")
        lines.append(f"  why: {out['explanation']}")
    else:
        lines.append("  the arch never stands")
        lines.append(f"  why: {out['explanation']}")
    return "\n".join(lines)


def run(args) -> int:
    _check(args)
    out = min_thickness(arch_from(args), elements=args.elements, voussoirs=args.voussoirs, tol=args.tol,
                        friction=args.friction)
    print(json.dumps(out, allow_nan=False) if args.json else summary(out))
    return 0
