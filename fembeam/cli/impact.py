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

import numpy as np

from ..mechanisms.discrete_series import SERIES_ROWS, discrete_series
from ..mechanisms.four_hinge_analysis import DEFAULT_SECTIONS, SIZE_LIMITS, FourHingeImpact, four_hinge_impact
from ..errors import InputError
from ..mechanisms.hinge import side_from_text
from ..geometry import CircularArch
from .args import (add_arch, add_friction, add_picture_options, arch_from, arch_title, check_picture_options,
                   friction_lines, int_list)
from ..analysis.friction import required_friction

def hinge_spec(text: str) -> tuple[list[float], list[str]]:
    """``"0:e,45:i,112.5:e,157.5:i"`` -> angles (deg) and sides.  Only the syntax is
    checked here; the values (finite, on the arch, increasing, at joints, a four-bar) are
    checked with the arch by :meth:`fembeam.mechanisms.mechanism.Mechanism.checked`."""
    angles, sides = [], []
    for item in [p for p in text.split(",") if p.strip()]:
        a, _, k = item.partition(":")
        try:
            angles.append(float(a))
        except ValueError:
            raise argparse.ArgumentTypeError(f"bad hinge {item!r}: expected ANGLE:i|e") from None
        try:
            sides.append(side_from_text(k))
        except InputError:
            raise argparse.ArgumentTypeError(f"bad hinge {item!r}: side must be i (intrados) or e (extrados)") from None
    return angles, sides


def finite_json(obj) -> str:
    """One line of JSON without NaN or infinity: a non-finite number becomes null and
    its key path is listed under ``"undefined"`` (the reason: not a finite number)."""
    paths: list[str] = []

    def clean(x, path):
        if isinstance(x, dict):
            return {k: clean(v, f"{path}.{k}" if path else str(k)) for k, v in x.items()}
        if isinstance(x, (list, tuple)):
            return [clean(v, f"{path}[{i}]") for i, v in enumerate(x)]
        if isinstance(x, (float, np.floating)) and not np.isfinite(x):
            paths.append(path)
            return None
        return x.item() if isinstance(x, np.generic) else x

    out = clean(obj, "")
    if paths and isinstance(out, dict):
        out["undefined"] = {"keys": paths, "reason": "not a finite number for this arch and mechanism"}
    return json.dumps(out, allow_nan=False)


def register(sub) -> None:
    p = sub.add_parser("impact", help="four-hinge impact: r, alpha', impulse line and its admissibility",
                       description="Impact of an arch arriving along a four-hinge mechanism (default: the "
                                   "incipient one) and leaving along prescribed (--after), optimal four-hinge "
                                   "(--restricted, default) or mirrored classical (--classical) hinges; "
                                   "the general QP's r_max is reported for comparison.")
    add_arch(p)
    ex, vo = SIZE_LIMITS["exhaustive"].highest, SIZE_LIMITS["voussoirs"].highest
    g = p.add_argument_group("discretisation", "size limits keep a run under ~1 min and ~2 GB (docs/user_guide.md)")
    m = g.add_mutually_exclusive_group()
    m.add_argument("--voussoirs", type=int, default=None, metavar="N",
                   help=f"discrete arch of N voussoirs: hinges only at the N+1 joints; N <= {ex} with "
                        f"--restricted (exhaustive search, time ~N^4), N <= {vo:,} with --after or --classical")
    m.add_argument("--elements", type=int, default=None, metavar="N",
                   help=f"continuous arch: elements of the general QP used for comparison (default 200, "
                        f"at most {SIZE_LIMITS['elements'].highest:,})")
    g.add_argument("--sections", type=int, default=DEFAULT_SECTIONS, metavar="N",
                   help=f"continuous arch: check the impulse line at N+1 sections (default {DEFAULT_SECTIONS}, "
                        f"at most {SIZE_LIMITS['sections'].highest:,})")
    g.add_argument("--grid", type=int, default=31, metavar="N",
                   help="continuous --restricted: exhaustive start on N voussoirs before the smooth search "
                        f"(default 31, at most {ex})")
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
                   help="instead: discrete -> continuous table of A_L, r_max, r_4hinge for these voussoir counts "
                        f"(at most {SERIES_ROWS} counts adding up to at most {vo:,} voussoirs)")
    p.add_argument("--exhaustive-max", type=int, default=31, metavar="N",
                   help=f"with --series: exhaustive r_4hinge up to N voussoirs (default 31, at most {ex}: "
                        "~1 us per candidate, 16 C(N+1, 4) candidates: 63 takes ~10 s)")
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
    if not wanted or result.line is None:
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
                    if line is not None else {"max": None, "reason": "no four-hinge impact (outcome "
                                              f"{result.outcome or res.outcome})"})
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
        print(finite_json(out))
        return 0
    print(summary(out))
    for line in written:
        print(f"  wrote {line}")
    return 0


def run_series(args) -> int:
    curve = arch_from(args)
    rows = discrete_series(curve, args.series, exhaustive_max=args.exhaustive_max)
    if args.json:
        print(finite_json({"command": "impact --series", "geometry": curve.describe(), "rows": rows}))
        return 0
    print(f"fembeam impact --series: embrace {curve.embrace_deg:g} deg, t/R = {curve.t_over_r:g}"
          if isinstance(curve, CircularArch) else f"fembeam impact --series: {arch_title(curve.describe())}")
    print(f"  {'voussoirs':>10s} {'A_L':>10s} {'r_max (QP)':>11s} {'QP hinges':>9s} {'r_4hinge':>10s}  note")

    def num(x, w):
        return f"{'-':>{w}s}" if x is None else f"{x:{w}.6f}"
    for r in rows:
        print(f"  {str(r['voussoirs']):>10s} {num(r['A_L'], 10)} {num(r['r_max'], 11)} {r['qp_hinges']:9d} "
              f"{num(r['r_4hinge'], 10)}  {r.get('reason', '')}".rstrip())
    return 0


def _h(hs) -> str:
    return ", ".join(f"{h['angle_deg']:.2f} {h['side']}" for h in hs) or "none"


def summary(o: dict) -> str:
    g = o["geometry"]
    head = (f"fembeam impact: circular arch, embrace {g['embrace_deg']:g} deg, t/R = {g['t_over_R']:g}, "
            f"{o['mode']}" if g.get("shape") == "circular" else f"fembeam impact: {arch_title(g)}, {o['mode']}")
    if o["admissibility"] is None:   # no four-hinge impact: say why, and what the general QP gives
        lines = [head, f"  outcome: {o['outcome']}: {o.get('explanation', '')}"]
        if o.get("A_L") is not None:
            lines.append(f"  A_L = {o['A_L']:.6f} g")
        if o["hinges_before"]:
            lines.append(f"  hinges before: {_h(o['hinges_before'])}")
        if o["r"] is not None:
            lines.append(f"  r = {o['r']:.6f} (four-hinge model)")
        if o.get("r_max") is not None:
            lines.append(f"  general QP: r_max = {o['r_max']:.6f}, hinges {_h(o.get('hinges_after_qp', []))}")
        lines += friction_lines(o.get("required_friction", {}), o.get("friction"),
                                {"limit": "|S|/N", "impact": "|I_n|/|I_t|", "impact_qp": "|I_n|/|I_t|"})
        return "\n".join(lines)
    a = o["admissibility"]
    lines = [head, f"  A_L = {o['A_L']:.6f} g   model: {o['model']}",
             f"  hinges before: {_h(o['hinges_before'])}",
             f"  hinges after:  {_h(o['hinges_after'])}",
             f"  r = {o['r']:.6f}   alpha'/alpha = {o['alpha_ratio']:.6f}"
             + ("" if o.get("compatible", True) else "   (NOT compatible: alpha' closes some new hinge, so r = 0)")
             + ("   (r > 1: the classical model creates energy here; not physical)" if o.get("creates_energy") else ""),
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
