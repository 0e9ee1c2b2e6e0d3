"""``fembeam analyze``: limit analysis and impact of a circular arch."""
from __future__ import annotations

import json

from ..analysis import AnalysisResult, analyze
from ._args import add_arch, add_solver, arch_from


def register(sub) -> None:
    p = sub.add_parser("analyze", help="A_L, mechanism before the impact, r and the impulse line",
                       description="Equivalent static analysis (A_L, incipient mechanism) then the impact "
                                   "QP (restitution coefficient r, post-impact hinges, impulse line).")
    add_arch(p)
    add_solver(p)
    p.add_argument("--json", action="store_true", help="print one JSON object on stdout")
    p.add_argument("--fields", action="store_true", help="with --json: add the impulse and thrust lines")
    p.set_defaults(func=run)


def run(args) -> int:
    res = analyze(arch_from(args), elements=args.elements, voussoirs=args.voussoirs,
                  direction=args.direction, backend=args.backend, refine_hinges=not args.no_refine)
    if args.json:
        print(json.dumps(res.to_dict(fields=args.fields)))
    else:
        print(summary(res))
    return 0


def _hinges(hs) -> str:
    return ", ".join(f"{h.angle_deg:.2f} deg {h.side}" for h in hs) or "none"


def summary(res: AnalysisResult) -> str:
    g = res.geometry
    lines = [f"fembeam analyze: circular arch, embrace {g['embrace_deg']:g} deg, t/R = {g['t_over_R']:g}, "
             f"R = {g['radius']:g} m",
             f"  mesh: {res.elements} {'voussoirs' if res.mode == 'voussoirs' else 'rigid elements'}"
             f" ({res.mode}), load direction {res.direction:+d}"]
    if res.outcome == "cannot_stand":
        tmin = f"; it needs t/R >= {res.t_min_over_R:.4f}" if res.t_min_over_R else ""
        lines.append(f"  outcome: the arch CANNOT STAND under its own weight (A_L <= 0){tmin}")
        return "\n".join(lines)
    if res.outcome == "no_mechanism":
        lines.append("  outcome: NO MECHANISM: no horizontal acceleration can turn this arch into a mechanism")
        return "\n".join(lines)
    lines += [f"  A_L = {res.A_L:.6f} g   (uniform-mesh LP: {res.A_L_mesh:.6f} g)",
              f"  hinges before impact: {_hinges(res.hinges_before)}"]
    if res.outcome == "arrested":
        lines.append("  outcome: ARRESTED: no compatible motion does positive work after the impact, r = 0")
    else:
        lines += [f"  r = K'/K = {res.r:.6f}",
                  f"  hinges after impact:  {_hinges(res.hinges_after)}"]
    v = res.verification.get("impact", {})
    lines.append("  verification (relative; thresholds in docs/verification.md):")
    for k, x in v.items():
        lines.append(f"    {k:24s} {x:.2e}")
    if "hinge_refinement_gap" in res.verification:
        lines.append(f"    {'hinge_refinement_gap':24s} {res.verification['hinge_refinement_gap']:.2e}")
    t = res.timings
    lines.append(f"  time: total {t.get('total', 0):.3f} s (LP {t.get('limit', 0):.3f} s, QP {t.get('impact', 0):.3f} s, "
                 f"{res.backend} {res.impact.iterations if res.impact else 0} iterations)")
    return "\n".join(lines)
