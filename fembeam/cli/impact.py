"""``fembeam impact``: four-hinge impact analysis (Sects. 3-5, Appendix A).

The hinges before the impact default to the limit analysis's incipient mechanism;
the hinges after are given (``--after 0:e,45:i,112.5:e,157.5:i``: angle in degrees
from the left springing, ``i``/``e`` = the edge the hinge pivots on), or found by the
restricted problem (16)-(17) (``--restricted``, the default), or taken from the
classical model (``--classical``).  The general QP's ``r_max`` is always reported
alongside for comparison.  The analysis is
:func:`fembeam.mechanisms.four_hinge_analysis.four_hinge_impact`; this module parses,
prints and writes.
"""
from __future__ import annotations

import argparse
import json

from ..errors import InputError
from ..mechanisms.discrete_series import discrete_series
from ..mechanisms.four_hinge_analysis import DEFAULT_SECTIONS, FourHingeImpact, four_hinge_impact
from ..mechanisms.hinge import ROCKING_SIDES
from ..geometry import CircularArch
from .args import add_arch, arch_from, arch_title, int_list
from ..analysis.friction import required_friction
from .analyze import add_friction, add_picture_options, check_picture_options, friction_lines

SIDE_CODES = {**{k[0]: k for k in ROCKING_SIDES}, **{k: k for k in ROCKING_SIDES}}


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
    add_friction(p, "Coulomb coefficient MU >= 0 of the joints: the sections whose impulses (or limit-state "
                    "forces) need more friction are flagged; the impact itself stays frictionless (default: none)")
    p.add_argument("--json", action="store_true", help="print one JSON object on stdout")
    p.add_argument("--fields", action="store_true", help="with --json: add the impulse line at every section")
    add_picture_options(p)
    p.set_defaults(func=run)


def compute(args) -> FourHingeImpact:
    model = "classical" if args.classical else ("prescribed" if args.after is not None else "restricted")
    return four_hinge_impact(arch_from(args), voussoirs=args.voussoirs, elements=args.elements,
                             direction=args.direction, before=args.before, after=args.after, model=model,
                             sections=args.sections, grid=args.grid)


def write_pictures(result: FourHingeImpact, args) -> list[str]:
    """``--vtk/--png/--figure`` for the four-hinge impact."""
    wanted = [o for o in ("vtk", "png", "figure") if getattr(args, o, None) is not None]
    if not wanted or result.r is None:
        return []
    disc, d0, d, hb, ha, impulse = result.picture_fields()
    written = []
    if args.vtk is not None:
        from ..output.export import write_fields
        files = write_fields(args.vtk, disc, d0, d, hb, ha, impulse)
        written.append(f"VTK: {files['multiblock']}")
    if args.png is not None:
        from ..output.export import meshes_of
        from ..output.render import render_fields
        written.append(f"rendering: {render_fields(meshes_of(disc, d0, d, hb, ha, impulse), args.png, result.title)}")
    if args.figure is not None:
        from ..output.plotting import save_paper_figure
        written.append(f"figure: {save_paper_figure(args.figure, disc, hb, ha, impulse['eccentricity'], None, result.title)}")
    return written


def friction_report(result: FourHingeImpact, mu: float | None) -> dict:
    """JSON keys ``friction``, ``required_friction`` (``"impact"``: ``|I_n| / |I_t|`` along the
    four-hinge impulse line, at its sections; ``"impact_qp"``: at the joints of the general
    QP; ``"limit"``: ``|S| / N`` of the limit state) and ``sliding_risk`` (None without ``mu``)."""
    res = result.analysis
    rf = res.required_friction(mu)
    rf = {"limit": rf["limit"], "impact_qp": rf["impact"]}
    line = result.line
    rf["impact"] = (required_friction(line.angle_deg, line.s, line.I_n, -line.I_t, mu, "impulse")
                    if line is not None else {"max": None, "reason": f"no impact (outcome {res.outcome})"})
    risk = None if mu is None else bool(any(d.get("above") for d in rf.values()))
    return {"friction": mu, "required_friction": rf, "sliding_risk": risk}


def run(args) -> int:
    if args.series is not None:
        return run_series(args)
    check_picture_options(args)
    result = compute(args)
    written = write_pictures(result, args)
    out = result.to_dict(fields=args.fields)
    out.update(friction_report(result, args.friction))
    if args.json:
        print(json.dumps(out, allow_nan=False))
        return 0
    print(summary(out))
    for line in written:
        print(f"  wrote {line}")
    return 0


def run_series(args) -> int:
    if any(n < 1 for n in args.series):
        raise InputError("--series needs positive voussoir counts")
    curve = arch_from(args)
    rows = discrete_series(curve, args.series, exhaustive_max=args.exhaustive_max)
    if args.json:
        print(json.dumps({"command": "impact --series", "geometry": curve.describe(), "rows": rows}))
        return 0
    print(f"fembeam impact --series: embrace {curve.embrace_deg:g} deg, t/R = {curve.t_over_r:g}"
          if isinstance(curve, CircularArch) else f"fembeam impact --series: {arch_title(curve.describe())}")
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
            f"{o['mode']}" if g.get("shape") == "circular" else f"fembeam impact: {arch_title(g)}, {o['mode']}")
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
    lines += friction_lines(o.get("required_friction", {}), o.get("friction"),
                            {"limit": "|S|/N", "impact": "|I_n|/|I_t|", "impact_qp": "|I_n|/|I_t|"})
    return "\n".join(lines)
