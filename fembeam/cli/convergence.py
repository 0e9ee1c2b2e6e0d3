"""``fembeam convergence``: mesh-refinement study of A_L, r and the hinges."""
from __future__ import annotations

import argparse
import json

from ..studies.convergence import ConvergenceStudy, convergence_study, plot_convergence
from ..errors import InputError
from ..mechanisms.hinge import side_of
from ..analysis.impact import IMPACT_BACKENDS
from .args import add_arch, arch_from, arch_title, check_outputs, finite_float, int_list, write_outputs

DEFAULT_ELEMENTS = [50, 100, 200, 400, 800, 1600]


def register(sub) -> None:
    p = sub.add_parser("convergence", help="mesh-refinement study: A_L, r, hinges, errors and observed rates",
                       description="Runs analyze on a sequence of meshes; errors against a Richardson-extrapolated "
                                   "value (continuous arch) or against the continuous arch (voussoirs); observed "
                                   "rates by a least-squares fit of log(err) on log(h). Progress on stderr.")
    add_arch(p)
    g = p.add_argument_group("meshes and solver")
    m = g.add_mutually_exclusive_group()
    m.add_argument("--elements", type=int_list, default=None, metavar="N,N,..",
                   help="rigid elements of the continuous arch (default 50,100,200,400,800,1600)")
    m.add_argument("--voussoirs", type=int_list, default=None, metavar="N,N,..",
                   help="discrete arches of N voussoirs, converging to the continuous arch (e.g. 7,15,31,63,127)")
    g.add_argument("--order", type=finite_float, default=2.0, metavar="P",
                   help="order assumed in the Richardson extrapolation (default 2; the fitted order is reported too)")
    g.add_argument("--reference-elements", type=int, default=1600, metavar="N",
                   help="with --voussoirs: elements of the continuous reference arch (default 1600)")
    g.add_argument("--direction", type=int, choices=(1, -1), default=1, help="load direction (default +1)")
    g.add_argument("--backend", choices=IMPACT_BACKENDS, default="auto", help="impact QP solver (default auto)")
    g.add_argument("--no-refine", action="store_true", help="no continuous refinement of the hinges before impact")
    g.add_argument("--tmin", action="store_true",
                   help="also the minimum thickness on every mesh (factor of the thickness law; ~20 LPs a mesh)")
    o = p.add_argument_group("output")
    o.add_argument("--json", action="store_true", help="print one JSON object on stdout instead of the table")
    o.add_argument("--csv", metavar="PATH", help="write the table as CSV")
    o.add_argument("--plot", metavar="PATH", help="write a log-log PNG of the errors with the fitted rates")
    o.add_argument("--out-dir", metavar="DIR",
                   help="write convergence.csv, convergence.json and convergence.png in DIR (unless given above)")
    o.add_argument("--quiet", action="store_true", help="no progress lines on stderr")
    p.set_defaults(func=run)


def run(args: argparse.Namespace) -> int:
    check_outputs(args, "convergence")
    elements = args.elements
    if elements is None and args.voussoirs is None:
        elements = DEFAULT_ELEMENTS
    levels = elements if elements is not None else args.voussoirs
    low = 4 if elements is not None else 1
    if any(n < low for n in levels):
        raise InputError(f"every mesh needs at least {low} {'elements' if elements is not None else 'voussoirs'}, "
                         f"got {levels}")
    if args.reference_elements < 4:
        raise InputError(f"--reference-elements must be >= 4, got {args.reference_elements}")
    study = convergence_study(arch_from(args), elements=elements, voussoirs=args.voussoirs, order=args.order,
                              reference_elements=args.reference_elements, direction=args.direction,
                              backend=args.backend, refine_hinges=not args.no_refine, progress=not args.quiet,
                              tmin=args.tmin)
    write_outputs(study, args, "convergence", plot_convergence)
    print(json.dumps(study.to_dict()) if args.json else table(study))
    return 0


def _f(x, fmt):
    return "-" if x is None else format(x, fmt)


def _hinges(hs) -> str:
    return " ".join(f"{h['angle_deg']:.3f}{side_of(h['side']).initial}" for h in hs) or "none"


def table(study: ConvergenceStudy) -> str:
    """Readable table: one row per mesh, then limits, errors and rates per quantity."""
    g, what = study.geometry, ("elements" if study.mode == "continuous" else "voussoirs")
    title = (f"circular arch, embrace {g.get('embrace_deg'):g} deg, t/R = {g.get('t_over_R'):g}"
             if g.get("shape") == "circular" else arch_title(g))
    circ = "h_over_R" in study.rows[0]
    tm = "t_min_factor" in study.rows[0]
    out = [f"fembeam convergence: {title}, {what} {','.join(map(str, study.levels))}",
           f"  {'N':>5} " + (f"{'h/R':>9} {'h deg':>7}" if circ else f"{'h/span':>9}") + f" {'A_L':>11} {'A_L_mesh':>11} {'r':>10} "
           + (f"{'t_min fac':>12} " if tm else "") +
           f"{'err r':>9} {('err A_Lm' if study.mode == 'continuous' else 'err A_L'):>9} {'eq.res':>8} {'tensile':>8} {'work':>8} {'t [s]':>6} {'LP':>5} {'QP':>5}"]
    qr = study.quantities.get("r", {})
    qm = study.quantities.get("A_L_mesh", study.quantities.get("A_L", {}))
    for i, row in enumerate(study.rows):
        er = qr.get("errors", [None] * len(study.rows))[i]
        em = qm.get("errors", [None] * len(study.rows))[i]
        size = f"{row['h_over_R']:9.6f} {row['h_deg']:7.4f}" if circ else f"{row['h_over_span']:9.6f}"
        out.append(f"  {row['n']:5d} {size} {_f(row['A_L'], '11.8f')} "
                   f"{_f(row['A_L_mesh'], '11.8f')} {_f(row['r'], '10.7f')} "
                   + (f"{_f(row['t_min_factor'], '12.9f')} " if tm else "") + f"{_f(er, '9.2e')} {_f(em, '9.2e')} "
                   f"{_f(row['qp_equilibrium_residual'], '8.1e')} {_f(row['max_tensile_impulse'], '8.1e')} "
                   f"{_f(row['impulse_work'], '8.1e')} {row['time_total_s']:6.3f} {row['time_lp_s']:5.3f} "
                   f"{row['time_qp_s']:5.3f}" + ("" if row["outcome"] == "rocking" else f"  [{row['outcome']}]"))
    out.append("  hinges (deg from the left springing; i = intrados, e = extrados):")
    for row in study.rows:
        out.append(f"  {row['n']:5d} before: {_hinges(row['hinges_before'])}   after: {_hinges(row['hinges_after'])}")
    if study.mode == "continuous":
        out.append(f"  limits: Richardson from the two finest meshes with assumed order p = {study.assumed_order:g}")
    else:
        out.append(f"  limits: the continuous arch on {study.reference['elements']} elements")
    out.append(f"  {'quantity':22s} {'limit':>14s} {'rate (LSQ)':>10s} {'fitted p':>9s} {'3-level p':>9s}")
    for name, q in study.quantities.items():
        lim = q.get("extrapolated", q.get("reference"))
        if q.get("exact"):
            out.append(f"  {name:22s} {_f(lim, '14.9f')}   mesh-independent (to round-off / the LP tolerance)")
            continue
        out.append(f"  {name:22s} {_f(lim, '14.9f')} {_f(q['rate'], '10.2f')} {_f(q['fitted_order'], '9.2f')} "
                   f"{_f(q['observed_order_3'], '9.2f')}")
    out.append(f"  wall time {study.wall_time:.2f} s")
    return "\n".join(out)
