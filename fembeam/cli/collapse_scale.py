"""``fembeam collapse-scale``: the scale factor at which a record first collapses the member.

The search is hunt and fill at a stated resolution (:mod:`fembeam.studies.huntfill`): the first
collapsing factor found, the safe factors found above it, and "the smallest" only when the scan
below it reached the resolution.  The computation is
:func:`fembeam.studies.collapse.collapse_scale`; ``--model simulate`` decides every run with the
multi-block simulation.
"""
from __future__ import annotations

import argparse
import json
import sys

from ..dynamics.ground import RECORDS, GroundMotion
from ..errors import InputError
from ..studies.collapse import MAX_RUNS, RESOLUTION, SPAN, collapse_scale
from ..studies.models import MODELS, check_model
from ..studies.runs import DT
from .args import add_member, coulomb, finite_float, member_from, MODEL_HELP, model_line, note_records


def register(sub) -> None:
    p = sub.add_parser("collapse-scale", help="scale factor at which a record first collapses the member (hunt and "
                                              "fill)",
                       description="Hunt and fill over the scale factors of a ground-motion record (incremental "
                                   "dynamic analysis): factors growing from the onset until one collapses the "
                                   "member, then the gaps below the lowest collapse filled until none is wider than "
                                   "--resolution. Reports the first collapsing factor found, whether it is the "
                                   "smallest at that resolution, and the safe factors found above it (the safe set "
                                   "need not be an interval). --model simulate runs the multi-block simulation "
                                   "instead of rock (docs/fragility.md).")
    add_member(p)
    g = p.add_argument_group("model of each run")
    g.add_argument("--model", choices=MODELS, default="rock", help=MODEL_HELP)
    g.add_argument("--dt", type=finite_float, default=None, metavar="S",
                   help=f"--model simulate or auto: time step (s; default {DT:g})")
    g.add_argument("--friction", type=coulomb, default=None, metavar="MU",
                   help="--model simulate or auto: Coulomb coefficient at every joint (default, or inf: joints never slide); a "
                        "joint may then slide below A_L, where the search does not look, so no factor is called "
                        "the smallest")
    g = p.add_argument_group("record and search")
    g.add_argument("--record", required=True, metavar="FILE",
                   help=f"PEER .AT2 file or CSV (time s, acceleration g), or a shipped record: {', '.join(RECORDS)}")
    g.add_argument("--sign", type=int, choices=(1, -1), default=1, help="+1: the record as given; -1: mirrored")
    g.add_argument("--resolution", type=finite_float, default=RESOLUTION, metavar="R",
                   help=f"relative step the scan must reach below a collapse before calling it the smallest "
                        f"(default {RESOLUTION:g})")
    g.add_argument("--factor-span", type=finite_float, default=SPAN, metavar="S",
                   help=f"largest factor, in onset factors (default {SPAN:g})")
    g.add_argument("--max-runs", type=int, default=MAX_RUNS, metavar="N",
                   help=f"time histories at most (default {MAX_RUNS})")
    g.add_argument("--t-end", type=finite_float, default=None, metavar="S",
                   help="end of each run (s; default: end of the record + 20 sqrt(L/g))")
    o = p.add_argument_group("output")
    o.add_argument("--json", action="store_true", help="print one JSON object on stdout")
    o.add_argument("--quiet", action="store_true", help="no progress bar on stderr")
    p.set_defaults(func=run)


def run(args: argparse.Namespace) -> int:
    if args.elements is not None and args.elements < 4:
        raise InputError(f"--elements must be >= 4, got {args.elements}")
    if args.voussoirs is not None and args.voussoirs < 1:
        raise InputError(f"--voussoirs must be >= 1, got {args.voussoirs}")
    dt, friction = check_model(args.model, args.dt, args.friction, names=("--model", "--dt", "--friction"))
    curve, voussoirs, elements = member_from(args, args.model)
    ground = GroundMotion.record(args.record)
    note_records([ground])
    bar = None
    if not args.quiet and sys.stderr.isatty():
        from tqdm import tqdm
        bar = tqdm(desc="collapse-scale: runs", unit="run", file=sys.stderr, leave=False)
    try:
        res = collapse_scale(curve, ground, voussoirs=voussoirs, elements=elements, t_end=args.t_end,
                             resolution=args.resolution, span=args.factor_span, max_runs=args.max_runs,
                             sign=args.sign, backend=args.backend,
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
    if res.get("model") != "rock":
        lines.append("  " + model_line(res["dt"], res["friction"], res["model"]))
    f0, top = res["onset_factor"], res["max_factor"]
    lines += [f"  A_L = {A['+1']:.6g} g (+1), {A['-1']:.6g} g (-1); the record first moves the member at factor "
              f"{f0:.6g}",
              f"  hunt and fill: resolution {res['resolution']:g} (relative), factors up to {top:.4g} "
              f"({top / f0:g} x the onset factor)"]
    f = res["first_collapse"]
    lo, hi = res["bracket"]
    reached = res["resolution_reached"]
    if f is None:
        if res["none_up_to_max"]:
            lines.append(f"  no collapse up to factor {top:.6g} (PGA {top * res['pga']:.4g} g) at this resolution")
        else:
            lines.append(f"  no collapse found up to factor {lo:.6g}; factors run are up to {100 * reached:.3g} % "
                         "apart, more than the resolution")
    else:
        how = " (collapses by sliding)" if res.get("collapse") == "collapsed_by_sliding" else ""
        lines.append(f"  first collapse found: factor {f:.6g} (PGA {res['pga_at_first_collapse']:.6g} g){how}")
        if res["smallest"]:
            lines.append(f"  the smallest at resolution {res['resolution']:g}: every factor run below it stands, "
                         f"consecutive factors from the onset to {lo:.6g} at most {100 * reached:.3g} % apart")
        elif res.get("friction") is not None:
            lines.append("  not called the smallest: with friction a joint may slide below A_L, which is not searched")
        else:
            lines.append(f"  NOT the smallest at resolution {res['resolution']:g}: factors run below it are up to "
                         f"{100 * reached:.3g} % apart (a collapse may lie between them)")
        if res["safe_factors_above"]:
            lines.append("  safe factors found above it: " + ", ".join(f"{x:.4g}" for x in res["safe_factors_above"]))
    for e in res["errors"]:
        lines.append(f"  search stopped at factor {e['factor']:.6g}: {e.get('error') or e['outcome']}")
    if res["budget_exhausted"]:
        lines.append(f"  stopped at the run budget ({res['runs']} runs): raise --max-runs")
    steps = f" ({res['steps']} time steps)" if res.get("steps") else ""
    lines.append(f"  {res['runs']} time histories{steps} in {res['time_s']:.1f} s")
    return "\n".join(lines)
