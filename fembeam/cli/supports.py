"""``fembeam supports``: an arch on moving supports (spreading, settlement, any movement) followed
to collapse, quasi-statically with finite displacements (docs/supports.md)."""
from __future__ import annotations

import argparse
import json
import math
from pathlib import Path

from ..errors import InputError
from .args import add_arch, arch_from, arch_title, finite_float


def _vector(text: str) -> tuple[float, float]:
    parts = text.split(",")
    if len(parts) != 2:
        raise argparse.ArgumentTypeError(f"expected DX,DY (two numbers separated by a comma), got {text!r}")
    dx, dy = finite_float(parts[0]), finite_float(parts[1])
    if dx == 0.0 and dy == 0.0:
        raise argparse.ArgumentTypeError(f"the movement DX,DY must not be zero, got {text!r}")
    if not math.isfinite(math.hypot(dx, dy)):
        raise argparse.ArgumentTypeError(f"the movement DX,DY must have a finite length, got {text!r}")
    return dx, dy


def _positive(text: str) -> float:
    x = finite_float(text)
    if not x > 0:
        raise argparse.ArgumentTypeError(f"expected a positive displacement (m), got {text!r}")
    return x


def _steps(text: str) -> int:
    from ..analysis.supports import MAX_STEPS
    try:
        n = int(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"expected an integer number of increments, got {text!r}") from None
    if not 1 <= n <= MAX_STEPS:
        raise argparse.ArgumentTypeError(f"the number of increments must be in [1, {MAX_STEPS}], got {text!r}")
    return n


def register(sub) -> None:
    from ..analysis.supports import DEFAULT_STEPS

    p = sub.add_parser("supports", help="supports that spread, settle or move, followed to collapse: capacity, "
                                        "thrust against displacement, hinge migrations",
                       description="Quasi-static large-displacement analysis of the rigid pieces of an arch whose "
                                   "supports move (no sliding, no crushing, no tension): the hinges that form, the "
                                   "thrust on the supports against the displacement, the hinge migrations, and the "
                                   "displacement at collapse (docs/supports.md).")
    add_arch(p)
    g = p.add_argument_group("discretisation")
    m = g.add_mutually_exclusive_group()
    m.add_argument("--elements", type=int, default=None, metavar="N",
                   help="rigid elements of the continuous arch (default 200); hinges at their joints, rolling "
                        "from joint to joint")
    m.add_argument("--voussoirs", type=int, default=None, metavar="N", help="discrete arch of N rigid voussoirs")
    mv = p.add_argument_group("movement (one of them)")
    one = mv.add_mutually_exclusive_group()
    one.add_argument("--spread", action="store_true",
                     help="the supports move apart horizontally, each by half the span increase")
    one.add_argument("--settle", action="store_true", help="the right support moves down")
    one.add_argument("--move", type=_vector, default=None, metavar="DX,DY",
                     help="the right support moves along (DX, DY) relative to the left one (only the direction "
                          "counts; the displacement is the length along it)")
    mv.add_argument("--left", action="store_true", help="with --settle or --move: the left support moves instead")
    mv.add_argument("--up-to", type=_positive, default=None, metavar="D",
                    help="stop at the displacement D (m) if the arch stands until then (default: to collapse, "
                         "at most half the span)")
    mv.add_argument("--steps", type=_steps, default=DEFAULT_STEPS, metavar="N",
                    help=f"increments up to --up-to (or half the span), default {DEFAULT_STEPS}; the events in "
                         "between are located by bisection")
    mv.add_argument("--snaps", choices=("dynamic", "static"), default=None,
                    help="where a snap-through ends: 'dynamic' (default with --voussoirs), where the "
                         "rigid-body simulation of the pieces with the supports held comes to rest; 'static' "
                         "(default for the continuous arch), the three-hinge state with the new hinge in place "
                         "of the nearest older one")
    o = p.add_argument_group("output")
    o.add_argument("--json", action="store_true", help="print one JSON object on stdout")
    o.add_argument("--csv", type=Path, default=None, metavar="PATH.csv", help="the path: displacement, H, V")
    o.add_argument("--plot", type=Path, default=None, metavar="PATH.png",
                   help="figure: the arch at rest and at the end with their lines of thrust; H and V against the "
                        "displacement")
    o.add_argument("--vtk", type=Path, default=None, metavar="PATH.pvd",
                   help="ParaView series of the pieces along the path (one .vtu per row next to it)")
    p.set_defaults(func=run)


def movement_of(args):
    from ..analysis.supports import Movement

    given = [o for o, v in (("--spread", args.spread), ("--settle", args.settle), ("--move", args.move is not None))
             if v]
    if not given:
        raise InputError("give a movement: --spread, --settle or --move DX,DY")
    if args.spread and args.left:
        raise InputError("--spread moves both supports apart: --left does not apply")
    if args.spread:
        return Movement.of("spread")
    if args.settle:
        return Movement.of("settle", left=args.left)
    return Movement.of("move", args.move, left=args.left)


def run(args) -> int:
    from ..output.files import PLOT_SUFFIXES, check_distinct, check_output

    movement = movement_of(args)
    check_output(args.csv, "--csv", (".csv",))
    check_output(args.plot, "--plot", PLOT_SUFFIXES)
    check_output(args.vtk, "--vtk", (".pvd",))
    check_distinct({"--csv": args.csv, "--plot": args.plot, "--vtk": args.vtk})
    from ..analysis.supports import supports

    res = supports(arch_from(args), movement, elements=args.elements, voussoirs=args.voussoirs,
                   up_to=args.up_to, steps=args.steps, snaps=args.snaps)
    written = []
    if args.csv is not None:
        from ..output.files import write_table
        rows = res.csv_rows()
        write_table(args.csv, {k: [r[k] for r in rows] for k in rows[0]}, integer=("hinges",))
        written.append(f"CSV: {args.csv}")
    if args.plot is not None:
        from ..output.supports import plot_supports
        written.append(f"figure: {plot_supports(res, args.plot)}")
    if args.vtk is not None:
        from ..output.supports import write_pvd
        k = write_pvd(res, args.vtk)
        written.append(f"VTK: {args.vtk} ({k} frames)")
    if args.json:
        print(json.dumps(res.to_dict(), allow_nan=False))
    else:
        print(summary(res))
        for w in written:
            print(f"  wrote {w}")
    return 0


def _wrapped(lines: list[str], width: int = 88) -> str:
    """``lines`` joined, each wrapped at ``width`` characters (continuations indented)."""
    import textwrap
    out = []
    for line in lines:
        lead = len(line) - len(line.lstrip())
        out += textwrap.wrap(line, width, subsequent_indent=" " * (lead + 4), break_on_hyphens=False,
                             break_long_words=False) or [line]
    return "\n".join(out)


def summary(res) -> str:
    """The text answer, lines of at most 88 characters."""
    mv = res.movement
    lines = [f"fembeam supports: {arch_title(res.geometry)}",
             f"  {res.n} {'voussoirs' if res.mode == 'voussoirs' else 'rigid elements (continuous arch)'}, "
             f"span {res.span:.6g} m; movement: {mv.describe()['displacement_means']}"]
    if res.outcome == "cannot_stand":
        lines.append("  outcome: the arch CANNOT STAND at rest: no line of thrust fits inside it")
        return _wrapped(lines)
    d0, H0, Vl0, Vr0 = res.path[0]
    lines.append(f"  at rest: H = {H0:.6g} kN/m, V left {Vl0:.6g} kN/m, V right {Vr0:.6g} kN/m"
                 + (" (the minimum thrust)" if mv.kind == "spread" else ""))
    lines.append("  hinges at the start: " + ", ".join(f"joint {h['joint']} ({h['angle_deg']:.2f} deg, {h['side']})"
                                                        for h in res.hinges))
    if res.migrations:
        lines.append(f"  hinge migrations: {len(res.migrations)}")
        for m in res.migrations[:12]:
            frm = "" if m.get("closed_joint") is None else f" from joint {m['closed_joint']}"
            snap = ", snap-through" if m.get("snap") else ""
            lines.append(f"    at {m['displacement']:.6g} m: joint {m['joint']} ({m['angle_deg']:.2f} deg, "
                         f"{m['side']}){frm}{snap}")
        if len(res.migrations) > 12:
            lines.append(f"    ... {len(res.migrations) - 12} more (--json)")
    for sn in res.snaps:
        opened = ", ".join(f"joint {h['joint']}" for h in sn["opened"])
        end = ("came to rest on " + ", ".join(f"joint {h['joint']}" for h in sn["hinges_after"])
               if sn["ended"] == "rest" else "collapsed")
        lines.append(f"  snap-through at {sn['displacement']:.6g} m ({opened}), simulated with the supports "
                     f"held: {end} after {sn['time']:.3g} s, {sn['dissipated']:.4g} J/m dissipated")
    dN, HN, VlN, VrN = res.path[-1]
    if res.outcome == "collapsed":
        lines.append(f"  CAPACITY: {res.capacity:.6g} m = {100 * res.capacity_over_span:.4g} % of the span")
        if res.last_edge is not None:
            e = res.last_edge
            lines.append(f"  edge reached last: joint {e['joint']} ({e['angle_deg']:.2f} deg, {e['side']})")
        lines.append(f"  collapse: {res.collapse.get('reason', '')}")
        lines.append(f"  at collapse: H = {HN:.6g} kN/m, V left {VlN:.6g} kN/m, V right {VrN:.6g} kN/m")
    else:
        lines.append(f"  outcome: STANDS up to {dN:.6g} m ({100 * dN / res.span:.4g} % of the span): "
                     f"H = {HN:.6g} kN/m, V left {VlN:.6g} kN/m, V right {VrN:.6g} kN/m")
    return _wrapped(lines)
