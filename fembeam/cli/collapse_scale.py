"""``fembeam collapse-scale``: the smallest scale factor of a record that overturns the member.

The factor grid is scanned in full, the first overturning factor bisected, and scanned factors
above it that do not overturn are reported.  The computation is
:func:`fembeam.studies.spectrum.collapse_scale`; ``--model simulate`` decides every run with the
multi-block simulation.
"""
from __future__ import annotations

import argparse
import json
import sys

from ..dynamics.ground import RECORDS, GroundMotion
from ..errors import InputError
from ..studies.spectrum import FACTOR_SPAN, N_GRID, collapse_scale
from .args import finite_float, float_list
from .rock import add_member, member_from
from .spectrum import add_model, model_from, model_line


def register(sub) -> None:
    p = sub.add_parser("collapse-scale", help="smallest scale factor of a record that overturns the member",
                       description="Scans scale factors of a ground-motion record, bisects below the first one that "
                                   "overturns the member, and reports scanned factors above it that do not overturn "
                                   "(the safe set need not be an interval). --model simulate runs the multi-block "
                                   "simulation instead of rock: each run then costs (t_end - record start) / dt "
                                   "time steps unless it collapses earlier, each dearer with more bodies (see "
                                   "docs/studies.md).")
    add_member(p)
    add_model(p)
    g = p.add_argument_group("record and search")
    g.add_argument("--record", required=True, metavar="FILE",
                   help=f"PEER .AT2 file or CSV (time s, acceleration g), or a shipped record: {', '.join(RECORDS)}")
    g.add_argument("--factors", type=float_list, default=None, metavar="F[,F..|A:B:STEP]",
                   help=f"increasing scale factors (default: {N_GRID} geometric points from the factor at which the "
                        f"record first exceeds A_L to {FACTOR_SPAN:g} times it)")
    g.add_argument("--sign", type=int, choices=(1, -1), default=1, help="+1: the record as given; -1: mirrored")
    g.add_argument("--bisect-tol", type=finite_float, default=1e-3, metavar="TOL",
                   help="relative width of the final bracket (default 1e-3)")
    g.add_argument("--t-end", type=finite_float, default=None, metavar="S",
                   help="end of each run (s; default: end of the record + 20 sqrt(L/g))")
    o = p.add_argument_group("output")
    o.add_argument("--json", action="store_true", help="print one JSON object on stdout")
    o.add_argument("--quiet", action="store_true", help="no progress bar on stderr")
    p.set_defaults(func=run)


def run(args: argparse.Namespace) -> int:
    if not (0 < args.bisect_tol <= 0.1):
        raise InputError(f"--bisect-tol must be in (0, 0.1], got {args.bisect_tol:g}")
    if args.factors is not None and not args.factors:
        raise InputError("--factors: give at least one factor")
    dt, friction = model_from(args)
    curve, voussoirs, elements = member_from(args, args.model)
    ground = GroundMotion.record(args.record)
    bar = None
    if not args.quiet and sys.stderr.isatty():
        from tqdm import tqdm
        bar = tqdm(desc="collapse-scale: runs", unit="run", file=sys.stderr, leave=False)
    try:
        res = collapse_scale(curve, ground, voussoirs=voussoirs, elements=elements, factors=args.factors,
                             t_end=args.t_end, bisect_tol=args.bisect_tol, sign=args.sign, backend=args.backend,
                             progress=(lambda a, o: bar.update()) if bar is not None else None, model=args.model,
                             dt=dt, friction=friction)
    finally:
        if bar is not None:
            bar.close()
    if args.json:
        print(json.dumps({"command": "collapse-scale", **res}, allow_nan=False))
    else:
        print(summary(res))
    return 0


def summary(res: dict) -> str:
    A = res["A_L"]
    lines = [f"fembeam collapse-scale: {res['record']} (PGA {res['pga']:.4g} g), sign {res['sign']:+d}"]
    if res.get("outcome") == "cannot_stand":
        return "\n".join(lines + ["  outcome: cannot_stand (the member does not stand under its own weight: "
                                  "fembeam analyze); no run was made"])
    if res.get("model") in ("simulate", "auto"):
        lines.append("  " + model_line(res["dt"], res["friction"], res["model"]))
    lines += [f"  A_L = {A['+1']:.6g} g (+1), {A['-1']:.6g} g (-1); the record first moves the member at factor "
             f"{res['onset_factor']:.6g}",
             f"  factors: {len(res['factors'])} from {res['factors'][0]:.4g} to {res['factors'][-1]:.4g}"]
    f = res["first_overturning"]
    lo, hi = res["bracket"]
    if f is None:
        lines.append(f"  no scanned factor overturns the member (up to {res['factors'][-1]:.6g}, PGA "
                     f"{res['factors'][-1] * res['pga']:.4g} g)")
    else:
        how = " (collapses by sliding)" if res.get("collapse") == "collapsed_by_sliding" else ""
        lines.append(f"  first overturning factor: {f:.6g} (PGA {res['pga_at_first_overturning']:.6g} g){how}")
        lines.append(f"  bracket: [{lo:.6g}, {hi:.6g}] (safe, overturns)"
                     + ("" if res["converged"] else "  NOT converged"))
        if res["safe_above"]:
            lines.append("  safe factors above it: " + ", ".join(f"{x:.4g}" for x in res["safe_factors_above"]))
        else:
            lines.append("  every scanned factor above it overturns the member")
    for e in res["errors"]:
        lines.append(f"  factor {e['factor']:.6g}: {e['error']}")
    steps = f" ({res['steps']} time steps)" if "steps" in res else ""
    lines.append(f"  {res['runs']} time histories{steps} in {res['time_s']:.1f} s")
    return "\n".join(lines)
