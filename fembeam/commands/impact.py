"""``fembeam impact``: four-hinge impact analysis (Sects. 3-5, Appendix A).

The hinges before the impact default to the limit analysis's incipient mechanism;
the hinges after are given (``--after 0:e,45:i,112.5:e,157.5:i``: angle in degrees
from the left springing, ``i``/``e`` = the edge the hinge pivots on), or found by the
restricted problem (16)-(17) (``--restricted``, the default), or taken from the
classical model (``--classical``).  The general QP's ``r_max`` is always reported
alongside for comparison.
"""
from __future__ import annotations

import argparse
import json
import time

import numpy as np

from ..analysis import analyze
from ..classical import classical_impact
from ..errors import InputError
from ..fem import discretize, nodes_through, uniform_nodes
from ..fourhinge import FourHinge
from ..hinges import Hinge
from ..impulse_line import four_hinge_impulse_line
from ..restricted import best_four_hinge_continuous, best_four_hinge_discrete
from ._args import add_arch, arch_from, int_list
from .analyze import add_picture_options, check_picture_options

SIDE_CODES = {"i": "intrados", "e": "extrados", "intrados": "intrados", "extrados": "extrados"}
DEFAULT_SECTIONS = 720   # continuous arch: impulse line checked at 720 + 1 sections (+ the hinges)


def hinge_spec(text: str) -> tuple[list[float], list[str]]:
    """``"0:e,45:i,112.5:e,157.5:i"`` -> angles (deg) and sides."""
    angles, sides = [], []
    for item in [p for p in text.split(",") if p.strip()]:
        a, _, k = item.partition(":")
        try:
            angles.append(float(a))
        except ValueError:
            raise argparse.ArgumentTypeError(f"bad hinge {item!r}: expected ANGLE:i|e") from None
        if k.strip().lower() not in SIDE_CODES:
            raise argparse.ArgumentTypeError(f"bad hinge {item!r}: side must be i (intrados) or e (extrados)")
        sides.append(SIDE_CODES[k.strip().lower()])
    if len(angles) != 4:
        raise argparse.ArgumentTypeError(f"give exactly four hinges, got {len(angles)} in {text!r}")
    return angles, sides


def register(sub) -> None:
    p = sub.add_parser("impact", help="four-hinge impact: r, alpha', impulse line and its admissibility",
                       description="Impact of an arch arriving along a four-hinge mechanism (default: the "
                                   "incipient one) and leaving along prescribed (--after), optimal four-hinge "
                                   "(--restricted, default) or mirrored classical (--classical) hinges; "
                                   "the general QP's r_max is reported for comparison.")
    add_arch(p)
    g = p.add_argument_group("discretisation")
    m = g.add_mutually_exclusive_group()
    m.add_argument("--voussoirs", type=int, default=None, metavar="N",
                   help="discrete arch of N voussoirs: hinges only at the N+1 joints")
    m.add_argument("--elements", type=int, default=None, metavar="N",
                   help="continuous arch: elements of the general QP used for comparison (default 200)")
    g.add_argument("--sections", type=int, default=DEFAULT_SECTIONS, metavar="N",
                   help=f"continuous arch: check the impulse line at N+1 sections (default {DEFAULT_SECTIONS})")
    g.add_argument("--grid", type=int, default=31, metavar="N",
                   help="continuous --restricted: exhaustive start on N voussoirs before the smooth search (default 31)")
    g.add_argument("--direction", type=int, choices=(1, -1), default=1, help="load direction, as in analyze")
    h = p.add_argument_group("mechanisms")
    h.add_argument("--before", type=hinge_spec, default=None, metavar="A:i|e,...",
                   help="hinges before the impact (default: the incipient mechanism of the limit analysis)")
    w = h.add_mutually_exclusive_group()
    w.add_argument("--after", type=hinge_spec, default=None, metavar="A:i|e,...",
                   help="hinges after the impact, e.g. 0:e,45:i,112.5:e,157.5:i (deg from the left springing)")
    w.add_argument("--restricted", action="store_true", help="best compatible four-hinge mechanism (default)")
    w.add_argument("--classical", action="store_true",
                   help="De Lorenzis-DeJong-Ochsendorf: mirrored hinges, impulses through the points opposite C")
    p.add_argument("--series", type=int_list, default=None, metavar="N,N,...",
                   help="instead: discrete -> continuous table of A_L, r_max, r_4hinge for these voussoir counts")
    p.add_argument("--exhaustive-max", type=int, default=31, metavar="N",
                   help="with --series: exhaustive r_4hinge up to N voussoirs (default 31; 63 takes ~12 s)")
    p.add_argument("--json", action="store_true", help="print one JSON object on stdout")
    p.add_argument("--fields", action="store_true", help="with --json: add the impulse line at every section")
    add_picture_options(p)
    p.set_defaults(func=run)


def _zones(hinges: list[Hinge]) -> list[dict]:
    """Runs of consecutive open joints pivoting on the same side (a QP 'hinge zone')."""
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


def compute(args) -> dict:
    clock = time.perf_counter()
    curve = arch_from(args)
    discrete = args.voussoirs is not None
    if args.sections < 4:
        raise InputError(f"--sections must be at least 4, got {args.sections}")
    res = analyze(curve, elements=args.elements, voussoirs=args.voussoirs, direction=args.direction)
    out = {"command": "impact", "mode": res.mode, "geometry": res.geometry, "outcome": res.outcome,
           "A_L": res.A_L if np.isfinite(res.A_L) else None}
    if res.outcome not in ("rocking", "arrested"):
        out.update(r=None, hinges_before=[], hinges_after=[], admissibility=None, r_max=None)
        return out
    if args.before is not None:
        before = FourHinge.from_angles(curve, *args.before)
    else:
        hb = res.hinges_before
        if len(hb) != 4 or any(h.side == "separated" for h in hb):
            raise InputError(f"the incipient mechanism has {len(hb)} hinges, not four: give --before")
        before = FourHinge.from_hinges(hb)
    sgn = before.compatible_sign(curve)
    if sgn == 0:
        raise InputError("the hinges before the impact do not form a compatible mechanism")
    pre = before.pieces(curve, -sgn)   # the arch returns along -u
    L = curve.length
    sections = uniform_nodes(curve, args.voussoirs) if discrete else np.linspace(0.0, L, args.sections + 1)
    if discrete:
        joints = res.impact.disc.joint_s
        for s in before.s:
            if np.min(np.abs(joints - s)) > 1e-9 * L:
                raise InputError(f"hinge before at {float(curve.angle_deg(s)):g} deg is not at a voussoir joint")

    extra: dict = {}
    if args.classical:
        model = "classical"
        cl = classical_impact(curve, before, sections, alpha=-sgn)
        after, line, r = cl.after, cl.line, cl.r
        line_at = lambda sec: classical_impact(curve, before, sec, alpha=-sgn).line  # noqa: E731
        extra = {"alpha_ratio": cl.alpha_ratio, "r_energy_same_hinges": cl.r_energy,
                 "opens_mirrored_hinges": cl.line.extra["opens_mirrored_hinges"],
                 "impulses_through": before.opposite().to_list(curve)}
    else:
        if args.after is not None:
            model = "prescribed"
            after = FourHinge.from_angles(curve, *args.after)
            if discrete:
                for s in after.s:
                    if np.min(np.abs(sections - s)) > 1e-9 * L:
                        raise InputError(f"hinge after at {float(curve.angle_deg(s)):g} deg is not at a voussoir "
                                         f"joint (joints every {float(curve.angle_deg(L)) / args.voussoirs:g} deg)")
                after = FourHinge(tuple(sections[np.abs(sections[:, None] - np.array(after.s)).argmin(0)]),
                                  after.sides)
        else:
            model = "restricted"
            if discrete:
                rr = best_four_hinge_discrete(curve, sections, pre)
            else:
                qh = res.hinges_after
                starts = [FourHinge.from_hinges(qh)] if len(qh) == 4 and all(
                    h.side in ("intrados", "extrados") for h in qh) else []
                rr = best_four_hinge_continuous(curve, pre, grid=args.grid, starts=starts)
            if rr.after is None:
                raise InputError("no compatible four-hinge mechanism does positive work: r_4hinge = 0")
            after = rr.after
            extra = {"candidates": rr.candidates, "compatible_candidates": rr.compatible, "search": rr.method,
                     "runner_up": [{"r": r_, "hinges": h.to_list(curve)} for r_, h in rr.ranking[:3]]}
        line = four_hinge_impulse_line(curve, pre, after, sections)
        line_at = lambda sec: four_hinge_impulse_line(curve, pre, after, sec)  # noqa: E731
        r = line.extra["r"]
        extra.update(alpha_ratio=line.extra["alpha_ratio_15"], alpha_ratio_8_11=line.alpha_ratio,
                     alpha_gap=line.extra["alpha_gap"], compatible=line.extra["compatible"],
                     Gamma=line.extra["Gamma"], Lambda=line.extra["Lambda"], Lambda_after=line.extra["Lambda_after"])

    out.update({
        "model": model,
        "r": float(r),
        "hinges_before": before.to_list(curve),
        "hinges_after": after.to_list(curve),
        "admissibility": line.admissibility(),
        "r_max": res.r,
        "r_max_minus_r": res.r - float(r),
        "hinges_after_qp": [h.to_dict() for h in res.hinges_after],
        "qp_hinge_zones": _zones(res.impact.hinges) if res.impact is not None else [],
        "qp_elements": res.elements,
        **extra,
    })
    if args.fields:
        out["impulse_line"] = line.to_dict()
    out["time_s"] = round(time.perf_counter() - clock, 3)
    out["_pictures"] = (curve, pre, before, after, line_at, args.voussoirs or args.elements or 200)
    return out


def write_pictures(out: dict, args) -> list[str]:
    """``--vtk/--png/--figure`` for the four-hinge impact: rigid elements whose joints are
    the voussoir joints (or a uniform mesh through both sets of hinges), the pre-impact
    field, the post-impact four-hinge field ``alpha' x after`` and its impulse line."""
    wanted = [o for o in ("vtk", "png", "figure") if getattr(args, o, None) is not None]
    if not wanted or "_pictures" not in out:
        return []
    curve, pre, before, after, line_at, n = out["_pictures"]
    nodes = nodes_through(uniform_nodes(curve, n), np.concatenate([before.s, after.s]))
    disc = discretize(curve, nodes)
    line = line_at(disc.joint_s)
    idx = np.abs(line.s[None, :] - disc.joint_s[:, None]).argmin(1)
    impulse = {"angle_deg": disc.joint_angle_deg, "eccentricity": line.eccentricity[idx],
               "I_t": line.I_t[idx], "I_n": line.I_n[idx], "moment": line.M[idx]}
    post = after.pieces(curve, line.alpha_ratio)
    hb = before.hinges(curve, float(pre.motion[1, 2]))
    ha = after.hinges(curve, line.alpha_ratio)
    title = f"{out['model']} four-hinge impact: r = {out['r']:.4f}"
    written = []
    if args.vtk is not None:
        from ..export import write_fields
        files = write_fields(args.vtk, disc, pre.dofs(disc), post.dofs(disc), hb, ha, impulse)
        written.append(f"VTK: {files['multiblock']}")
    if args.png is not None:
        from ..export import meshes_of
        from ..render import render_fields
        meshes = meshes_of(disc, pre.dofs(disc), post.dofs(disc), hb, ha, impulse)
        written.append(f"rendering: {render_fields(meshes, args.png, title)}")
    if args.figure is not None:
        from ..plotting import save_paper_figure
        written.append(f"figure: {save_paper_figure(args.figure, disc, hb, ha, impulse['eccentricity'], None, title)}")
    return written


def run(args) -> int:
    if args.series is not None:
        return run_series(args)
    check_picture_options(args)
    out = compute(args)
    written = write_pictures(out, args)
    out.pop("_pictures", None)
    if args.json:
        print(json.dumps(out))
        return 0
    print(summary(out))
    for line in written:
        print(f"  wrote {line}")
    return 0


def run_series(args) -> int:
    from ..discrete_series import discrete_series

    if any(n < 1 for n in args.series):
        raise InputError("--series needs positive voussoir counts")
    curve = arch_from(args)
    rows = discrete_series(curve, args.series, exhaustive_max=args.exhaustive_max)
    if args.json:
        print(json.dumps({"command": "impact --series", "geometry": curve.describe(), "rows": rows}))
        return 0
    print(f"fembeam impact --series: embrace {curve.embrace_deg:g} deg, t/R = {curve.t_over_r:g}")
    print(f"  {'voussoirs':>10s} {'A_L':>10s} {'r_max (QP)':>11s} {'QP hinges':>9s} {'r_4hinge':>10s}")
    for r in rows:
        r4 = "-" if r["r_4hinge"] is None else f"{r['r_4hinge']:.6f}"
        print(f"  {str(r['voussoirs']):>10s} {r['A_L']:10.6f} {r['r_max']:11.6f} {r['qp_hinges']:9d} {r4:>10s}")
    return 0


def _h(hs) -> str:
    return ", ".join(f"{h['angle_deg']:.2f} {h['side']}" for h in hs) or "none"


def summary(o: dict) -> str:
    g = o["geometry"]
    head = (f"fembeam impact: circular arch, embrace {g['embrace_deg']:g} deg, t/R = {g['t_over_R']:g}, "
            f"{o['mode']}")
    if o["r"] is None:
        return head + f"\n  outcome: {o['outcome']} (no impact analysis)"
    a = o["admissibility"]
    lines = [head, f"  A_L = {o['A_L']:.6f} g   model: {o['model']}",
             f"  hinges before: {_h(o['hinges_before'])}",
             f"  hinges after:  {_h(o['hinges_after'])}",
             f"  r = {o['r']:.6f}   alpha'/alpha = {o['alpha_ratio']:.6f}"
             + ("" if o.get("compatible", True) else "   (NOT compatible: alpha' closes some new hinge, so r = 0)"),
             f"  general QP: r_max = {o['r_max']:.6f} (r_max - r = {o['r_max_minus_r']:+.2e}), "
             f"hinges {_h(o['hinges_after_qp'])}",
             f"  impulse line ({a['sections']} sections): through the new hinges: {a['passes_through_hinges']}, "
             f"inside the thickness: {a['inside_thickness']}, compressive: {a['compressive']}"]
    for f in a["failures"]:
        v = "n/a" if f["value"] is None else f"{f['value']:+.4f}"
        what = {"through_hinge": f"misses the {f.get('hinge_side')} hinge, e/t = {v}",
                "inside_thickness": f"outside the thickness, e/t = {v}",
                "compressive": f"tensile, I_t/max|I_t| = {v}"}[f["check"]]
        where = (f"{f['from_deg']:.2f}-{f['to_deg']:.2f} deg ({f['sections']} sections, worst at {f['angle_deg']:.2f})"
                 if f.get("sections", 1) > 1 else f"{f['angle_deg']:.2f} deg")
        lines.append(f"    fails at {where}: {what}")
    return "\n".join(lines)
