"""``fembeam load-scan``: one live point load moved across the span; the smallest load factor
and where (also ``fembeam analyze --load-scan P --positions N``)."""
from __future__ import annotations

import argparse
import json
import sys

from ..errors import InputError
from .args import add_arch, arch_from, arch_title, check_outputs, finite_float, write_outputs

STEM = "load_scan"


def register(sub) -> None:
    p = sub.add_parser("load-scan", help="one point load moved across the span: smallest load factor and where",
                       description="Moves one downward point load of P kN per metre of width across the span "
                                   "(on the extrados) and computes its load factor at every position (dead loads: "
                                   "self weight, fill, masses, at their values): the smallest factor, the critical "
                                   "position and its mechanism, the curve of load factor against position.")
    add_arch(p)
    p.add_argument("--load", "--load-scan", dest="load", type=finite_float, required=True, metavar="P",
                   help="the moving point load, kN per metre of width (> 0)")
    add_scan_options(p)
    add_mesh(p)
    add_files(p)
    p.set_defaults(func=run)


def add_scan_options(p) -> None:
    p.add_argument("--positions", type=int, default=101, metavar="N",
                   help="positions from the left springing to the right one, equally spaced (default 101; 2 to 2000)")


def add_mesh(p) -> None:
    g = p.add_argument_group("discretisation")
    m = g.add_mutually_exclusive_group()
    m.add_argument("--elements", type=int, default=None, metavar="N",
                   help="rigid elements of the continuous arch, every section checked (default 200)")
    m.add_argument("--voussoirs", type=int, default=None, metavar="N",
                   help="discrete arch of N voussoirs (joints only)")


def add_files(p) -> None:
    o = p.add_argument_group("output")
    o.add_argument("--json", action="store_true", help="print one JSON object on stdout instead of the table")
    o.add_argument("--csv", metavar="PATH", help="write the curve as CSV (x_m, load_factor, collapse load, outcome)")
    o.add_argument("--plot", metavar="PATH", help="write a PNG of the load factor against the position")
    o.add_argument("--out-dir", metavar="DIR",
                   help=f"write {STEM}.csv, {STEM}.json and {STEM}.png in DIR (unless given above)")
    o.add_argument("--quiet", action="store_true", help="no progress on stderr")


def scan(args: argparse.Namespace, P: float) -> int:
    """Run the scan of ``P`` (kN/m) with the options of :func:`register` and print it."""
    from ..studies.load_scan import MAX_POSITIONS, load_scan
    from ..output.load_scan import plot_load_scan

    if not P > 0:
        raise InputError(f"the moving load P must be > 0 kN/m, got {P:g}")
    if not 2 <= args.positions <= MAX_POSITIONS:
        raise InputError(f"--positions must be from 2 to {MAX_POSITIONS}, got {args.positions}")
    for opt in ("csv", "plot", "out_dir"):
        setattr(args, opt, getattr(args, opt, None))
    check_outputs(args, STEM)
    progress = None
    if not getattr(args, "quiet", False) and sys.stderr.isatty():
        def progress(i, n):
            print(f"\rload-scan: {i}/{n} positions", end="" if i < n else "\n", file=sys.stderr, flush=True)
    res = load_scan(arch_from(args), P, positions=args.positions, voussoirs=args.voussoirs,
                    elements=args.elements, progress=progress)
    write_outputs(res, args, STEM, plot_load_scan)
    print(json.dumps(res.to_dict(), allow_nan=False) if args.json else table(res))
    return 0


def run(args: argparse.Namespace) -> int:
    return scan(args, args.load)


def table(res) -> str:
    d = res.to_dict()
    lines = [f"fembeam load-scan: {arch_title(res.geometry)}",
             f"  {res.n} {'voussoirs' if res.mode == 'voussoirs' else 'rigid elements (continuous)'}; a point load "
             f"of {res.P:g} kN/m at {len(res.x)} positions from x = 0 to {res.x[-1]:.6g} m"]
    if d["min_load_factor"] is None and "cannot_stand" in res.status:
        lines.append("  the arch CANNOT STAND under its dead loads: no load factor at any position")
    elif d["min_load_factor"] is None:
        lines.append("  no position collapses the arch (no mechanism at any position)")
    else:
        hinges = ", ".join(f"{h['angle_deg']:.2f} deg {h['side']}" for h in d["load_mechanism"])
        lines += [f"  smallest load factor {d['min_load_factor']:.6f} at x = {d['critical_x']:.6g} m "
                  f"(collapse load {d['collapse_load_kN_per_m']:.6g} kN/m)",
                  f"  mechanism: {hinges}"]
    lines.append("        x [m]   load factor   outcome")
    for p in d["positions"]:
        f = "-" if p["load_factor"] is None else f"{p['load_factor']:.6f}"
        lines.append(f"  {p['x']:11.5g}  {f:>12s}   {p['outcome']}")
    return "\n".join(lines)
