"""``fembeam analyze``: limit analysis and impact of an arch (any shape of :func:`.args.add_arch`)."""
from __future__ import annotations

import json
import sys
from pathlib import Path

from ..analysis import AnalysisResult, analyze
from ..errors import InputError
from ..units import kN
from .args import (add_arch, add_friction, add_loads, add_picture_options, add_solver, arch_from, arch_title,
                   check_picture_options, finite_float, friction_lines, points_of)


def register(sub) -> None:
    p = sub.add_parser("analyze", help="A_L, mechanism before the impact, r and the impulse line",
                       description="Equivalent static analysis (A_L, incipient mechanism) then the impact "
                                   "QP (restitution coefficient r, post-impact hinges, impulse line).")
    add_arch(p)
    add_loads(p)
    add_solver(p)
    add_friction(p, "limit analysis with Coulomb friction MU >= 0 at the joints; its flow is associative (dilatant "
                    "sliding), so A_L is an UPPER bound: joints that slide without dilatancy can collapse below it. "
                    "The safe LOWER bound (frictionless joints, Radenkovic's second theorem) is printed beside it. "
                    "Joints needing more friction are flagged (default: no sliding; docs/friction.md)")
    p.add_argument("--json", action="store_true", help="print one JSON object on stdout")
    p.add_argument("--fields", action="store_true", help="with --json: add the impulse and thrust lines")
    add_picture_options(p)
    p.add_argument("--thrust-figure", type=Path, metavar="PATH.png",
                   help="figure of the arch as built: fill, loads, the minimum and maximum thrust lines under the "
                        "dead loads and, with --load, the collapse under the live loads")
    s = p.add_argument_group("load scan (instead of the analysis: as fembeam load-scan)")
    s.add_argument("--load-scan", type=finite_float, default=None, metavar="P",
                   help="move one point load of P kN/m across the span: its smallest load factor and where")
    s.add_argument("--positions", type=int, default=101, metavar="N",
                   help="with --load-scan: positions from springing to springing (default 101; 2 to 2000)")
    s.add_argument("--csv", metavar="PATH", help="with --load-scan: the curve as CSV")
    s.add_argument("--plot", metavar="PATH", help="with --load-scan: the figure (PNG)")
    s.add_argument("--out-dir", metavar="DIR", help="with --load-scan: load_scan.csv/.json/.png in DIR")
    p.set_defaults(func=run)


def write_pictures(res, args) -> list[str]:
    """Write what ``--vtk/--png/--figure`` ask for; returns one line per file written.
    Results without a mechanism (cannot stand, no mechanism) have nothing to draw: a
    note goes to stderr."""
    wanted = [o for o in ("vtk", "png", "figure") if getattr(args, o, None) is not None]
    if not wanted:
        return []
    if res.outcome not in ("rocking", "arrested"):
        print(f"fembeam: note: outcome {res.outcome}: no incipient mechanism, nothing written for "
              + ", ".join(f"--{o}" for o in wanted), file=sys.stderr)
        return []
    out = []
    if args.vtk is not None:
        from ..output.export import write_vtk
        files = write_vtk(res, args.vtk)
        out.append(f"VTK: {files['multiblock']} -> " + ", ".join(str(p) for k, p in files.items()
                                                                if k != "multiblock"))
    if args.png is not None:
        from ..output.render import render_png
        out.append(f"rendering: {render_png(res, args.png)}")
    if args.figure is not None:
        from ..output.plotting import plot_paper_figure
        out.append(f"figure: {plot_paper_figure(res, args.figure)}")
    return out


def run(args) -> int:
    if args.load_scan is not None:
        if points_of(args, "load"):
            raise InputError("--load-scan moves one load across the span: drop --load")
        other = [o for o, v in (("--friction", args.friction is not None), ("--direction", args.direction != 1),
                                ("--vtk", args.vtk), ("--png", args.png), ("--figure", args.figure),
                                ("--thrust-figure", args.thrust_figure), ("--fields", args.fields),
                                ("--no-refine", args.no_refine), ("--backend", args.backend != "auto")) if v]
        if other:
            raise InputError(f"{other[0]} does not apply to --load-scan (its outputs: --json, --csv, --plot, "
                             "--out-dir)")
        from .load_scan import scan
        return scan(args, args.load_scan)
    for opt in ("csv", "plot", "out_dir"):
        if getattr(args, opt) is not None:
            raise InputError(f"--{opt.replace('_', '-')} goes with --load-scan")
    check_picture_options(args)
    from ..output.files import check_output
    check_output(args.thrust_figure, "--thrust-figure", (".png", ".pdf", ".svg"))
    res = analyze(arch_from(args), elements=args.elements, voussoirs=args.voussoirs,
                  direction=args.direction, backend=args.backend, refine_hinges=not args.no_refine,
                  friction=args.friction, loads=points_of(args, "load"))
    written = write_pictures(res, args)
    if args.thrust_figure is not None:
        if res.thrust is None:
            print(f"fembeam: note: outcome {res.outcome}: no thrust range, nothing written for --thrust-figure",
                  file=sys.stderr)
        else:
            from ..output.asbuilt import plot_thrust_range
            written.append(f"thrust figure: {plot_thrust_range(res, args.thrust_figure)}")
    if args.json:  # stdout carries the JSON object only
        print(json.dumps(res.to_dict(fields=args.fields), allow_nan=False))
    else:
        print(summary(res))
        for line in written:
            print(f"  wrote {line}")
    return 0


def _hinges(hs) -> str:
    return ", ".join(f"{h.angle_deg:.2f} deg {h.side}" for h in hs) or "none"


def friction_bound_lines(fb: dict | None) -> list[str]:
    """Text of :attr:`AnalysisResult.friction_bounds`: the associative load factor with mu (an
    upper bound for joints that slide without dilatancy) and the frictionless one (a lower bound)."""
    if fb is None:
        return []
    up, lo = fb["upper"], fb["lower"]
    lines = ["  collapse load of joints that slide without dilatancy (docs/friction.md, section 3):"]
    if up["friction"] == lo["friction"]:
        what = f"{up['A_L']:.6f} g" if up["A_L"] is not None else up["outcome"].replace("_", " ")
        return lines + [f"    exact: {what} (mu = 0: the associative flow has no dilatancy)"]
    if up["A_L"] is not None:
        lines.append(f"    upper bound  {up['A_L']:.6f} g   (associative flow with mu = {up['friction']:g}: "
                     "sliding without dilatancy can collapse below it)")
    elif up["outcome"] == "no_mechanism":
        lines.append(f"    upper bound  none: no associative mechanism with mu = {up['friction']:g}")
    if lo["A_L"] is not None:
        lines.append(f"    lower bound  {lo['A_L']:.6f} g   (safe: frictionless joints, mu* = 0, "
                     "Radenkovic's second theorem)")
    elif lo["outcome"] == "cannot_stand":
        lines.append("    lower bound  none: with frictionless joints (mu* = 0, Radenkovic's second theorem) the arch "
                     "cannot stand, so no safe load factor follows")
    else:
        lines.append("    lower bound  infinite: with frictionless joints no horizontal acceleration makes a mechanism")
    if fb["determinate"]:
        lines.append("    statically determinate member: the collapse load equals the upper value")
    return lines


def summary(res: AnalysisResult) -> str:
    lines = [f"fembeam analyze: {arch_title(res.geometry)}",
             f"  mesh: {res.n} {'voussoirs' if res.mode == 'voussoirs' else 'rigid elements'}"
             f" ({res.mode}), load direction {res.direction:+d}"
             + ("" if res.friction is None else f", Coulomb friction mu = {res.friction:g} at the joints")]
    lines += as_built_lines(res)
    if res.outcome == "cannot_stand":
        lines.append("  outcome: the arch CANNOT STAND under its own weight: no thrust line fits inside it"
                     + (" (no load factor)" if res.loads is not None else ""))
        lines.append(f"  collapse mechanism under gravity alone: {_hinges(res.limit.hinges)}")
        th = res.thickness
        if th is not None and th.outcome == "ok":
            what = "the continuous arch" if th.continuum else f"these {res.n} voussoirs"
            if th.t_over_R is not None:
                lines.append(f"  minimum thickness of {what}: t/R >= {th.t_over_R:.6f} (bracket "
                             f"[{th.lower * th.curve.t_over_r:.6f}, {th.t_over_R:.6f}], {th.solves} margin LPs)")
            else:
                lines.append(f"  minimum thickness of {what}: {th.scale:.6f} times the given thickness "
                             f"(bracket [{th.lower:.6f}, {th.scale:.6f}], {th.solves} margin LPs)")
        elif th is not None:
            lines.append("  no thickness below t/R = 2 lets it stand" if th.t_over_R is not None or
                         hasattr(th.curve, "t_over_r") else
                         f"  no thickness up to the shape's limit ({th.curve.max_thickness_scale:.6g} times the "
                         "given one) lets it stand")
        return "\n".join(lines)
    lines += thrust_and_load_lines(res)
    if res.outcome == "no_mechanism":
        if res.friction is None or res.friction == 0.0:
            lines.append("  outcome: NO MECHANISM: no horizontal acceleration can turn this arch into a mechanism")
        else:
            lines.append("  outcome: NO MECHANISM with associative friction (dilatant sliding); joints that slide "
                         "without dilatancy may still collapse")
        lines += friction_bound_lines(res.friction_bounds)
        return "\n".join(lines)
    if res.outcome == "sliding":
        slides = ", ".join(f"{d['angle_deg']:.2f} deg" for d in res.limit.slides)
        lines += [f"  A_L = {res.A_L:.6f} g   (uniform-mesh LP: {res.A_L_mesh:.6f} g; associative friction"
                  f"{'' if res.friction == 0.0 else ': an UPPER bound'})",
                  f"  outcome: SLIDING: the associative mechanism slides at {slides} "
                  f"(hinges: {_hinges(res.hinges_before)}); no rocking impact is computed"]
        lines += friction_bound_lines(res.friction_bounds)
        lines += friction_lines(res.required_friction(), res.friction, {"limit": "|S|/N"})
        return "\n".join(lines)
    bounds = ""
    if res.continuum is not None and res.continuum.status == "ok":
        bounds = f", continuum bounds [{res.A_L_lower:.9f}, {res.A_L:.9f}]"
    upper = "" if res.friction is None or res.friction == 0.0 else "; associative friction: an UPPER bound"
    lines += [f"  A_L = {res.A_L:.6f} g   (uniform-mesh LP: {res.A_L_mesh:.6f} g{bounds}{upper})"]
    lines += friction_bound_lines(res.friction_bounds)
    lines += [f"  hinges before impact: {_hinges(res.hinges_before)}"]
    if res.outcome == "arrested":
        lines.append("  outcome: ARRESTED: no compatible motion does positive work after the impact, r = 0")
    else:
        lines += [f"  r = K'/K = {res.r:.6f}",
                  f"  hinges after impact:  {_hinges(res.hinges_after)}"]
    lines += friction_lines(res.required_friction(), res.friction, {"limit": "|S|/N", "impact": "|I_n|/|I_t|"})
    v = res.verification.get("impact", {})
    lines.append("  verification (relative; thresholds in docs/verification.md):")
    for k, x in v.items():
        lines.append(f"    {k:24s} {x:.2e}")
    for k in ("duality_gap", "statics_mismatch", "thrust_line_outside"):
        lines.append(f"    {'limit ' + k:24s} {res.verification['limit'][k]:.2e}")
    for k in ("continuum_violation", "hinge_refinement_gap"):
        if k in res.verification:
            lines.append(f"    {k:24s} {res.verification[k]:.2e}")
    if res.continuum is not None and not res.continuum.exact_hinges:
        lines.append("  note: degenerate continuum optimum (hinges merging); mechanism and impact on the uniform mesh")
    t = res.timings
    lines.append(f"  time: total {t.get('total', 0):.3f} s (assembly {t.get('assembly', 0):.3f} s, "
                 f"LP {t.get('limit', 0):.3f} s, continuum {t.get('continuum', 0):.3f} s, QP {t.get('impact', 0):.3f} s, "
                 f"{res.backend} {res.impact.iterations if res.impact else 0} iterations)")
    return "\n".join(lines)


def as_built_lines(res: AnalysisResult) -> list[str]:
    """The member as built: density, fill, point masses, live loads and the weight (per metre of width)."""
    g = res.geometry
    parts = [f"masonry {g.get('density', float('nan')):g} kg/m^3"]
    fill = g.get("fill")
    if fill:
        parts.append(f"fill {fill['density']:g} kg/m^3 up to a road {fill['depth']:g} m above the crown's extrados "
                     f"(y = {fill['road_level']:.4g} m)")
    masses = g.get("masses") or []
    if masses:
        parts.append("masses " + ", ".join(f"{m['M']:g} kg/m at x = {m['x']:g} m" for m in masses))
    lines = [f"  as built (per metre of width): {'; '.join(parts)}; weight {kN(res.mass):.6g} kN/m"]
    if res.loads is not None:
        lines.append("  live loads: " + ", ".join(f"{p:g} kN/m at x = {x:g} m" for x, p in res.loads.pairs))
    return lines


def thrust_and_load_lines(res: AnalysisResult) -> list[str]:
    """The thrust range under the dead loads and the load factor of the live loads."""
    lines = []
    if res.thrust is not None:
        tr = res.thrust
        top = (f"{tr.H_max:.6g} kN/m" if tr.H_max < float("inf")
               else "unbounded (a straight line of thrust fits inside the arch)")
        lines.append(f"  thrust range (dead loads): H_min = {tr.H_min:.6g} kN/m, H_max = {top} "
                     f"(horizontal thrust on each springing)")
    lf = res.load
    if lf is not None:
        if lf.status == "ok":
            bounds = "" if not lf.lower == lf.lower else f", continuum bounds [{lf.lower:.9g}, {lf.value:.9g}]"
            at = ", ".join(f"{p:.6g}" for p in lf.collapse_loads_kN)
            lines.append(f"  load factor = {lf.value:.6g}   (collapse at {at} kN/m{bounds})")
            lines.append(f"  collapse mechanism under the live loads: {_hinges(lf.hinges)}")
        elif lf.status == "no_mechanism":
            lines.append("  load factor: NO MECHANISM: no multiple of the live loads collapses the arch")
        else:
            lines.append(f"  load factor: none ({lf.status.replace('_', ' ')})")
    return lines
