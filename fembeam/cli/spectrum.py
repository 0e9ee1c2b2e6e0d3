"""``fembeam spectrum``: overturning amplitude of an arch or a block against pulse period.

For each period (sine, Ricker) or duration (rect) the amplitude grid is scanned in full, the
first overturning amplitude bisected, and scanned amplitudes above it that do not overturn are
reported (safe regions above).  The computation is :func:`fembeam.studies.spectrum.spectrum`.
``--model simulate`` decides every run with the multi-block simulation (``fembeam simulate``)
instead of ``rock``; :func:`add_model` and :func:`model_from` serve ``collapse-scale`` too.
"""
from __future__ import annotations

import argparse
import csv

from ..limits import MAX_WORKERS, check_workers
from ..output.files import atomic, check_distinct, check_output
from ..studies.parallel import journal_for
from ..studies.runs import T_END_FACTOR
from ..studies.spectrum import AMPLITUDE_SPAN, N_GRID, PULSES, SpectrumResult, plot_spectrum, spectrum
from .args import (add_member, add_model, check_scheduler, finite_float, float_list, member_from, model_from,
                   model_line, noted, print_result)

def register(sub) -> None:
    p = sub.add_parser("spectrum", help="overturning amplitude against pulse period (safe regions above it too)",
                       description="For each pulse period (duration for rect) the smallest amplitude that overturns "
                                   "the member: a scan of the amplitude grid, then bisection below the first "
                                   "overturning grid point. Scanned amplitudes above it that do not overturn are "
                                   "reported (the safe set need not be an interval). Amplitudes in g; a positive "
                                   "pulse loads the member to the left (--sign -1: mirrored pulse). --model "
                                   "simulate runs the multi-block simulation instead of rock: each run then costs "
                                   "(pulse end + F sqrt(L/g)) / dt time steps unless it collapses earlier, each "
                                   "dearer with more bodies (see docs/studies.md).")
    add_member(p)
    add_model(p)
    g = p.add_argument_group("pulses")
    g.add_argument("--pulse", choices=PULSES, required=True, help="rectangular, one-sine or Ricker pulse")
    g.add_argument("--periods", type=float_list, required=True, metavar="S[,S..|A:B:STEP]",
                   help="pulse periods in s (durations for --pulse rect)")
    g.add_argument("--amplitudes", type=float_list, default=None, metavar="G[,G..|A:B:STEP]",
                   help=f"increasing amplitude grid in g (default: {N_GRID} geometric points from the onset A_L "
                        f"to {AMPLITUDE_SPAN:g} A_L)")
    g.add_argument("--sign", type=int, choices=(1, -1), default=1,
                   help="+1: the pulse as defined (positive first, loading to the left); -1: mirrored")
    g.add_argument("--bisect-tol", type=finite_float, default=1e-3, metavar="TOL",
                   help="relative width of the final bracket (default 1e-3)")
    g.add_argument("--t-end-factor", type=finite_float, default=T_END_FACTOR, metavar="F",
                   help=f"each run lasts to the end of the pulse + F sqrt(L/g) (default {T_END_FACTOR:g})")
    x = p.add_argument_group("execution and output")
    x.add_argument("--workers", type=int, default=None, metavar="N",
                   help=f"local worker processes (default: all cores; at most {MAX_WORKERS}, never more than periods)")
    x.add_argument("--scheduler", metavar="ADDRESS", help="run on this Dask distributed scheduler (tcp://host:8786)")
    x.add_argument("--json", action="store_true", help="print one JSON object on stdout instead of the table")
    x.add_argument("--csv", metavar="PATH.csv", help="one row per period")
    x.add_argument("--plot", metavar="PATH.png", help="figure: amplitude / onset against period, safe regions above")
    x.add_argument("--quiet", action="store_true", help="no progress bar on stderr")
    p.set_defaults(func=run)


def run(args: argparse.Namespace) -> int:
    csv_path = check_output(args.csv, "--csv", (".csv",))
    plot_path = check_output(args.plot, "--plot", (".png", ".pdf", ".svg"))
    check_distinct({"--csv": csv_path, "--plot": plot_path})
    check_workers(args.workers)
    check_scheduler(args.scheduler)
    dt, friction = model_from(args)
    curve, voussoirs, elements = member_from(args, args.model)
    journal = noted(journal_for(csv_path or plot_path, "spectrum"))    # finished periods kept: a re-run resumes
    res = spectrum(curve, args.pulse, args.periods, voussoirs=voussoirs, elements=elements,
                   amplitudes=args.amplitudes, workers=args.workers, scheduler=args.scheduler,
                   progress=not args.quiet, bisect_tol=args.bisect_tol, t_end_factor=args.t_end_factor,
                   sign=args.sign, backend=args.backend, journal=journal, model=args.model, dt=dt,
                   friction=friction)
    written = []
    if csv_path:
        write_csv(res, csv_path)
        written.append(f"CSV: {csv_path}")
    if plot_path:
        with atomic(plot_path) as tmp:
            plot_spectrum(res, tmp)
        written.append(f"figure: {plot_path}")
    if journal is not None:
        journal.remove()
    return print_result(args.json, res.to_dict, lambda: table(res), written)


def write_csv(res: SpectrumResult, path) -> None:
    rows = res.csv_rows()
    with atomic(path) as tmp, open(tmp, "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=list(rows[0]))
        w.writeheader()
        w.writerows(rows)


def _num(x, fmt: str = ".6g") -> str:
    return "-" if x is None else format(x, fmt)


def table(res: SpectrumResult) -> str:
    geo = res.geometry
    if geo.get("shape") == "block":
        head = f"block {geo['width']:g} m x {geo['height']:g} m"
    else:
        n = res.settings["voussoirs"]
        disc = f"{n} voussoirs" if n else f"continuous, {res.settings['elements']} elements"
        if "embrace_deg" in geo:
            shape = f"embrace {geo['embrace_deg']:g} deg, t/R = {geo.get('t_over_R', 0):g}"
        else:
            shape = ", ".join(f"{k} = {v:g}" for k, v in geo.items()
                              if isinstance(v, (int, float)) and not isinstance(v, bool) and k != "density")
        head = f"{geo.get('shape', 'member')} arch, {shape}, {disc}"
    A0, amps = res.onset, res.amplitudes
    col = "duration" if res.kind == "rect" else "period"
    out = [f"fembeam spectrum: {head}; {res.kind} pulses, sign {res.sign:+d}"]
    if res.outcome == "cannot_stand":
        return "\n".join(out + ["  outcome: cannot_stand (the member does not stand under its own weight: "
                                "fembeam analyze); no pulse was run"])
    if res.model != "rock":
        out.append("  " + model_line(res.settings["dt"], res.settings["friction"], res.model))
    out += [f"  A_L = {res.A_L[1]:.6g} g (+1), {res.A_L[-1]:.6g} g (-1); onset amplitude {A0:.6g} g",
           f"  amplitudes: {len(amps)} from {amps[0]:.4g} to {amps[-1]:.4g} g ({res.settings['grid']}); "
           f"runs to pulse end + {res.settings['t_end_factor']:g} sqrt(L/g)",
           f"  {col + ' [s]':>12} {'a_over [g]':>11} {'a/onset':>8} {'bracket [g]':>23} {'safe above':>10} {'runs':>5}"]
    for r in res.rows:
        a, (lo, hi) = r["first_collapse"], r["bracket"]
        if a is None:
            br, ratio = f"none up to {amps[-1]:.4g}", "-"
        else:
            br, ratio = f"[{lo:.5g}, {hi:.5g}]", f"{a / A0:.4f}"
        safe = f"yes ({len(r['safe_amplitudes_above'])})" if r["safe_above"] else "no"
        out.append(f"  {r['period']:12.5g} {_num(a, '11.6g'):>11} {ratio:>8} {br:>23} {safe:>10} {r['runs']:5d}"
                   + ("  collapses by sliding" if r.get("collapse") == "collapsed_by_sliding" else "")
                   + (f"  {len(r['errors'])} solver error(s)" if r["errors"] else ""))
    for r in res.rows:
        if r["safe_above"]:
            out.append(f"  {col} {r['period']:g} s: safe above the first overturning amplitude at "
                       + ", ".join(f"{x:.4g}" for x in r["safe_amplitudes_above"]) + " g")
        for e in r["errors"]:
            if isinstance(e, dict):
                out.append(f"  {col} {r['period']:g} s, amplitude {e['amplitude']:.6g} g: {e['error']}")
            else:                                    # a period lost with its worker process
                out.append(f"  {col} {r['period']:g} s: {e}")
    tm = res.timing
    steps = f" ({tm['steps']} time steps)" if "steps" in tm else ""
    out.append(f"  {tm['runs']} time histories{steps}; wall time {tm['wall']:.1f} s, CPU in cases "
               f"{tm['cases_cpu']:.1f} s, {res.settings['executor']}")
    return "\n".join(out)


