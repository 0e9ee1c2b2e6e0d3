"""``fembeam sweep``: r_max against the thickness for several arches of one shape (paper Fig. 13)."""
from __future__ import annotations

import argparse
import json

from ..analysis import DEFAULT_ELEMENTS
from ..errors import InputError
from ..limits import MAX_WORKERS, check_workers
from ..analysis.impact import IMPACT_BACKENDS
from ..studies.sweep import FIG13_EMBRACE, FIG13_T_OVER_R, SweepResult, family, plot_sweep, sweep
from .args import SHAPES, check_outputs, check_scheduler, finite_float, float_list, study_journal, write_outputs

CODES = {"rocking": "", "arrested": "A", "cannot_stand": "C", "no_mechanism": "N", "solver_error": "E"}
_CIRCULAR = ("--embrace", "--t-over-r", "--envelope-embrace")
_SHAPED = ("--rise-over-span", "--t-over-span", "--envelope-rise-over-span")


def register(sub) -> None:
    p = sub.add_parser("sweep", help="parametric study: r_max vs t/R per embrace angle (or t/span per rise/span of "
                                     "another --shape), minimum-thickness envelope",
                       description="Paper Fig. 13: every (beta, t/R) case of the grid (continuous arch) with its "
                                   "outcome, plus for each beta the minimum thickness and r_max just above it. "
                                   "With --shape pointed|elliptical|parabolic|catenary the grid is (rise/span, "
                                   "t/span) instead: arches of span 1 m and constant thickness. "
                                   "Runs on local cores (default) or on a Dask cluster (--scheduler).")
    g = p.add_argument_group("grid")
    g.add_argument("--shape", choices=SHAPES, default=None,
                   help="arch shape: circular (default; --embrace, --t-over-r) or pointed (rise/span >= 0.5), "
                        "elliptical, parabolic, catenary (--rise-over-span, --t-over-span)")
    g.add_argument("--embrace", type=float_list, default=None, metavar="DEG[,DEG..|A:B:STEP]",
                   help="circular: embrace angles in degrees (default 80,100,...,180)")
    g.add_argument("--t-over-r", type=float_list, default=None, metavar="X[,X..|A:B:STEP]",
                   help="circular: thickness over radius values (default 0.10:0.30:0.01)")
    g.add_argument("--rise-over-span", type=float_list, default=None, metavar="A[,B..|A:B:STEP]",
                   help="--shape other than circular: rise over span values (required)")
    g.add_argument("--t-over-span", type=float_list, default=None, metavar="X[,Y..|A:B:STEP]",
                   help="--shape other than circular: constant thickness over span values (required)")
    g.add_argument("--elements", type=int, default=DEFAULT_ELEMENTS, metavar="N",
                   help=f"rigid elements per arch (default {DEFAULT_ELEMENTS}; hinges before impact are refined)")
    g.add_argument("--direction", type=int, choices=(1, -1), default=1, help="load direction (default +1)")
    g.add_argument("--fill-density", type=finite_float, default=None, metavar="RHO_F",
                   help="fill on every arch (kg/m^3) up to a road --fill-depth above the crown's extrados; the "
                        "arches have R = 1 m (circular) or a span of 1 m, masonry 2000 kg/m^3")
    g.add_argument("--fill-depth", type=finite_float, default=None, metavar="D",
                   help="with --fill-density: the road's height above the crown's extrados (m, default 0)")
    g.add_argument("--backend", choices=IMPACT_BACKENDS, default="auto", help="impact QP solver (default auto)")
    e = p.add_argument_group("minimum-thickness envelope")
    e.add_argument("--no-envelope", action="store_true", help="skip the envelope")
    e.add_argument("--envelope-embrace", type=float_list, default=None, metavar="DEG[,DEG..|A:B:STEP]",
                   help="embrace angles of the envelope points (default: those of the grid)")
    e.add_argument("--envelope-rise-over-span", type=float_list, default=None, metavar="A[,B..|A:B:STEP]",
                   help="--shape other than circular: rise/span of the envelope points (default: those of the grid)")
    e.add_argument("--tmin-elements", type=int, default=400, metavar="N",
                   help="elements of the LP bisected for t_min (default 400)")
    e.add_argument("--tmin-tol", type=finite_float, default=1e-6, metavar="TOL",
                   help="relative bisection tolerance on t_min (default 1e-6)")
    e.add_argument("--above", type=finite_float, default=1e-3, metavar="EPS",
                   help="envelope arch at t = t_min (1 + EPS) (default 1e-3)")
    x = p.add_argument_group("execution and output")
    x.add_argument("--workers", type=int, default=None, metavar="N",
                   help=f"local worker processes (default: all cores; at most {MAX_WORKERS}, never more than cases)")
    x.add_argument("--scheduler", metavar="ADDRESS", help="run on this Dask distributed scheduler (tcp://host:8786)")
    x.add_argument("--json", action="store_true", help="print one JSON object on stdout instead of the tables")
    x.add_argument("--csv", metavar="PATH", help="write cases and envelope points as CSV (column kind)")
    x.add_argument("--plot", metavar="PATH", help="write the Fig. 13 plot as PNG")
    x.add_argument("--out-dir", metavar="DIR", help="write sweep.csv, sweep.json and sweep.png in DIR (unless given above)")
    x.add_argument("--quiet", action="store_true", help="no progress bar on stderr")
    p.set_defaults(func=run)


def grid(args: argparse.Namespace) -> tuple[str, list[float], list[float], list[float] | None]:
    """Shape, grid values ``a`` and ``b`` and envelope values of the options; InputError
    for options of the other kind of sweep."""
    shape = args.shape or "circular"
    values = {opt: getattr(args, opt[2:].replace("-", "_")) for opt in _CIRCULAR + _SHAPED}
    own, other = (_CIRCULAR, _SHAPED) if shape == "circular" else (_SHAPED, _CIRCULAR)
    wrong = [opt for opt in other if values[opt] is not None]
    if wrong and shape == "circular":
        raise InputError(f"{wrong[0]} applies to --shape pointed|elliptical|parabolic|catenary; the circular sweep "
                         "takes --embrace and --t-over-r")
    if wrong:
        raise InputError(f"{wrong[0]} applies to the circular sweep only; --shape {shape} takes --rise-over-span "
                         "and --t-over-span")
    a, b, env = (values[opt] for opt in own)
    if shape == "circular":
        a, b = (FIG13_EMBRACE if a is None else a), (FIG13_T_OVER_R if b is None else b)
    elif a is None or b is None:
        raise InputError(f"--shape {shape} needs --rise-over-span and --t-over-span (lists or A:B:STEP ranges)")
    fam = family(shape)
    if not a or not b:
        raise InputError(f"give at least one {fam.a_name} and one {fam.b_label}")
    return shape, a, b, env


def run(args: argparse.Namespace) -> int:
    check_outputs(args, "sweep")
    shape, a, b, env = grid(args)
    if args.elements < 4 or args.tmin_elements < 4:
        raise InputError(f"--elements and --tmin-elements must be >= 4, got {args.elements}, {args.tmin_elements}")
    check_workers(args.workers)
    if not (0 < args.tmin_tol < 0.01) or not (0 < args.above < 1):
        raise InputError("--tmin-tol must be in (0, 0.01) and --above in (0, 1)")
    check_scheduler(args.scheduler)
    fill = None
    if args.fill_density is not None or args.fill_depth is not None:
        from ..geometry.asbuilt import Fill
        if args.fill_density is None:
            raise InputError("--fill-depth needs --fill-density (the fill's density, kg/m^3)")
        f = Fill(args.fill_density, 0.0 if args.fill_depth is None else args.fill_depth)
        fill = None if f.density == 0 else (f.density, f.depth)
    journal = study_journal(args, "sweep")
    res = sweep(a, b, elements=args.elements, backend=args.backend, direction=args.direction,
                envelope=not args.no_envelope, envelope_embrace=env,
                tmin_elements=args.tmin_elements, tmin_tol=args.tmin_tol, above=args.above, workers=args.workers,
                scheduler=args.scheduler, progress=not args.quiet, shape=shape, journal=journal, fill=fill)
    write_outputs(res, args, "sweep", plot_sweep)
    if journal is not None:
        journal.remove()
    print(json.dumps(res.to_dict()) if args.json else table(res))
    return 0


def table(res: SweepResult) -> str:
    """r_max grid (rows: thickness, columns: arches; letters for the other outcomes) and envelope."""
    fam = res.family
    what = f"{fam.shape} arches of span 1 m, " if fam.ident else ""
    w = max(7, len(fam.a_label))
    out = [f"fembeam sweep: {what}{len(res.embrace)} {fam.a_name}s x {len(res.t_over_r)} thicknesses, "
           f"{res.settings['elements']} elements, {res.settings['executor']}",
           "  r_max (A = arrested, r = 0; C = cannot stand; N = no mechanism; E = solver error)",
           f"  {fam.b_label:<5} " + "".join(f"{a:>9g}" for a in res.embrace)]
    for t in res.t_over_r:
        cells = []
        for a in res.embrace:
            c = res.case(a, t)
            cells.append(f"{c['r']:9.4f}" if c["outcome"] == "rocking" else f"{CODES[c['outcome']]:>9s}")
        out.append(f"  {t:5.3f} " + "".join(cells))
    if res.envelope:
        out.append(f"  minimum-thickness envelope (r_max at {fam.b_label} = t_min (1 + {res.settings['above']:g})):")
        out.append(f"  {fam.a_label:>{w}} {'t_min/' + fam.b_label[2:]:>10} {'r_max':>8} {'A_L':>9} outcome")
        for e in sorted(res.envelope, key=lambda e: e[fam.a_key]):
            tmin = e.get(fam.tmin_key)
            tmin = "-" if tmin is None else f"{tmin:.6f}"
            r = "-" if e.get("r") is None else f"{e['r']:.4f}"
            al = "-" if e.get("A_L") is None else f"{e['A_L']:.2e}"
            out.append(f"  {e[fam.a_key]:{w}g} {tmin:>10} {r:>8} {al:>9} {e['outcome']}")
    errors = [c for c in res.cases + res.envelope if c["outcome"] == "solver_error"]
    for c in errors:
        out.append(f"  solver error at {fam.a_label} = {c[fam.a_key]:g}, {fam.b_label} = {c[fam.b_key]}: "
                   f"{c['error']}")
    tm = res.timing
    out.append(f"  outcomes: {res.outcomes()}")
    out.append(f"  wall time {tm['wall']:.1f} s; CPU in cases {tm['cases_cpu']:.1f} s (LP {tm['lp']:.1f}, "
               f"hinge refinement {tm['hinge_refinement']:.1f}, QP {tm['qp']:.1f}), envelope {tm['envelope_cpu']:.1f} s")
    return "\n".join(out)
