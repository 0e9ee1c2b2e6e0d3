"""``fembeam sweep``: r_max against t/R for several embrace angles (paper Fig. 13)."""
from __future__ import annotations

import argparse
import json

from ..analysis import DEFAULT_ELEMENTS
from ..errors import InputError
from ..analysis.qp import BACKENDS
from ..studies.sweep import FIG13_EMBRACE, FIG13_T_OVER_R, SweepResult, plot_sweep, sweep
from .args import finite_float, float_list, write_outputs

CODES = {"rocking": "", "arrested": "A", "cannot_stand": "C", "no_mechanism": "N", "solver_error": "E"}


def register(sub) -> None:
    p = sub.add_parser("sweep", help="parametric study: r_max vs t/R per embrace angle, minimum-thickness envelope",
                       description="Paper Fig. 13: every (beta, t/R) case of the grid (continuous arch) with its "
                                   "outcome, plus for each beta the minimum thickness and r_max just above it. "
                                   "Runs on local cores (default) or on a Dask cluster (--scheduler).")
    g = p.add_argument_group("grid")
    g.add_argument("--embrace", type=float_list, default=FIG13_EMBRACE, metavar="DEG[,DEG..|A:B:STEP]",
                   help="embrace angles in degrees (default 80,100,...,180)")
    g.add_argument("--t-over-r", type=float_list, default=FIG13_T_OVER_R, metavar="X[,X..|A:B:STEP]",
                   help="thickness over radius values (default 0.10:0.30:0.01)")
    g.add_argument("--elements", type=int, default=DEFAULT_ELEMENTS, metavar="N",
                   help=f"rigid elements per arch (default {DEFAULT_ELEMENTS}; hinges before impact are refined)")
    g.add_argument("--direction", type=int, choices=(1, -1), default=1, help="load direction (default +1)")
    g.add_argument("--backend", choices=BACKENDS, default="clarabel", help="impact QP solver (default clarabel)")
    e = p.add_argument_group("minimum-thickness envelope")
    e.add_argument("--no-envelope", action="store_true", help="skip the envelope")
    e.add_argument("--envelope-embrace", type=float_list, default=None, metavar="DEG[,DEG..|A:B:STEP]",
                   help="embrace angles of the envelope points (default: those of the grid)")
    e.add_argument("--tmin-elements", type=int, default=400, metavar="N",
                   help="elements of the LP bisected for t_min (default 400)")
    e.add_argument("--tmin-tol", type=finite_float, default=1e-6, metavar="TOL",
                   help="bisection tolerance on t_min/R (default 1e-6)")
    e.add_argument("--above", type=finite_float, default=1e-3, metavar="EPS",
                   help="envelope arch at t/R = t_min (1 + EPS) (default 1e-3)")
    x = p.add_argument_group("execution and output")
    x.add_argument("--workers", type=int, default=None, metavar="N", help="local worker processes (default: all cores)")
    x.add_argument("--scheduler", metavar="ADDRESS", help="run on this Dask distributed scheduler (tcp://host:8786)")
    x.add_argument("--json", action="store_true", help="print one JSON object on stdout instead of the tables")
    x.add_argument("--csv", metavar="PATH", help="write cases and envelope points as CSV (column kind)")
    x.add_argument("--plot", metavar="PATH", help="write the Fig. 13 plot as PNG")
    x.add_argument("--out-dir", metavar="DIR", help="write sweep.csv, sweep.json and sweep.png in DIR (unless given above)")
    x.add_argument("--quiet", action="store_true", help="no progress bar on stderr")
    p.set_defaults(func=run)


def run(args: argparse.Namespace) -> int:
    if not args.embrace or not args.t_over_r:
        raise InputError("give at least one embrace angle and one t/R")
    if args.elements < 4 or args.tmin_elements < 4:
        raise InputError(f"--elements and --tmin-elements must be >= 4, got {args.elements}, {args.tmin_elements}")
    if args.workers is not None and args.workers < 1:
        raise InputError(f"--workers must be >= 1, got {args.workers}")
    if not (0 < args.tmin_tol < 0.01) or not (0 < args.above < 1):
        raise InputError("--tmin-tol must be in (0, 0.01) and --above in (0, 1)")
    if args.scheduler:
        try:
            import distributed  # noqa: F401
        except ImportError:
            raise InputError("--scheduler needs Dask: pip install 'fembeam[dask]'") from None
    res = sweep(args.embrace, args.t_over_r, elements=args.elements, backend=args.backend, direction=args.direction,
                envelope=not args.no_envelope, envelope_embrace=args.envelope_embrace,
                tmin_elements=args.tmin_elements, tmin_tol=args.tmin_tol, above=args.above, workers=args.workers,
                scheduler=args.scheduler, progress=not args.quiet)
    write_outputs(res, args, "sweep", plot_sweep)
    print(json.dumps(res.to_dict()) if args.json else table(res))
    return 0


def table(res: SweepResult) -> str:
    """r_max grid (rows t/R, columns beta; letters for the other outcomes) and envelope."""
    out = [f"fembeam sweep: {len(res.embrace)} embrace angles x {len(res.t_over_r)} thicknesses, "
           f"{res.settings['elements']} elements, {res.settings['executor']}",
           "  r_max (A = arrested, r = 0; C = cannot stand; N = no mechanism; E = solver error)",
           "  t/R   " + "".join(f"{b:>9g}" for b in res.embrace)]
    for t in res.t_over_r:
        cells = []
        for b in res.embrace:
            c = res.case(b, t)
            cells.append(f"{c['r']:9.4f}" if c["outcome"] == "rocking" else f"{CODES[c['outcome']]:>9s}")
        out.append(f"  {t:5.3f} " + "".join(cells))
    if res.envelope:
        out.append("  minimum-thickness envelope (r_max at t/R = t_min (1 + %g)):" % res.settings["above"])
        out.append(f"  {'beta':>7} {'t_min/R':>10} {'r_max':>8} {'A_L':>9} outcome")
        for e in sorted(res.envelope, key=lambda e: e["embrace_deg"]):
            r = "-" if e.get("r") is None else f"{e['r']:.4f}"
            al = "-" if e.get("A_L") is None else f"{e['A_L']:.2e}"
            out.append(f"  {e['embrace_deg']:7g} {e.get('t_min_over_R') or float('nan'):10.6f} {r:>8} {al:>9} "
                       f"{e['outcome']}")
    errors = [c for c in res.cases + res.envelope if c["outcome"] == "solver_error"]
    for c in errors:
        out.append(f"  solver error at beta = {c['embrace_deg']:g}, t/R = {c['t_over_R']}: {c['error']}")
    tm = res.timing
    out.append(f"  outcomes: {res.outcomes()}")
    out.append(f"  wall time {tm['wall']:.1f} s; CPU in cases {tm['cases_cpu']:.1f} s (LP {tm['lp']:.1f}, "
               f"hinge refinement {tm['hinge_refinement']:.1f}, QP {tm['qp']:.1f}), envelope {tm['envelope_cpu']:.1f} s")
    return "\n".join(out)
