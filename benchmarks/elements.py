"""Benchmark: rigid (DG0) curved-beam elements vs continuous P1 elements.

For each geometry and mesh size N, four discretisations of the continuous arch:

  rigid       rigid elements on the uniform mesh: limit_analysis + impact on
              discretize(curve, uniform_nodes(curve, N))
  rigid+ref   the pipeline fembeam.analyze(curve, elements=N): uniform LP, the
              continuum limit analysis (weakest sections, Newton on the hinges), nodes
              put at its hinges
  p1          continuous P1 fields (fembeam.fem.p1) on the uniform mesh
  p1-cart     P1 interpolating the Cartesian velocity (components="cartesian"), uniform mesh
  p1+ref      P1 with an element midpoint moved onto each optimal hinge position
              (the closed-form four-hinge optimum, started from the P1 LP's hinges)

Prints A_L, r, their errors against the reference (A_L: the continuum value of
rigid+ref, which is mesh independent; r: Richardson extrapolation of the
rigid+ref r at the two finest meshes with the observed rate), problem sizes and timings
(best of ``--repeat`` runs, seconds).  Usage::

    python benchmarks/elements.py [--sizes 50,100,200,400,800,1600] [--repeat 3]
"""
from __future__ import annotations

import argparse
import time

import numpy as np

from fembeam import analyze
from fembeam.errors import SolverError
from fembeam.fem import discretize, uniform_nodes
from fembeam.fem.p1 import discretize_p1, midpoints_through
from fembeam.geometry import CircularArch
from fembeam.mechanisms import Mechanism, merge_adjacent
from fembeam.mechanisms.energy import optimise_load_factor
from fembeam.analysis.impact import impact
from fembeam.analysis.limit import limit_analysis

GEOMETRIES = ((157.5, 0.15), (180.0, 0.20))
VARIANTS = ("rigid", "rigid+ref", "p1", "p1-cart", "p1+ref")


def _sizes(disc) -> dict:
    return {"dofs": disc.M.shape[0], "rows": disc.B_open.shape[0] + disc.B_slide.shape[0],
            "nnz": disc.M.nnz + disc.B_open.nnz + disc.B_slide.nnz}


def _pipeline(curve, nodes, assemble) -> dict:
    t0 = time.perf_counter()
    disc = assemble(curve, nodes)
    t1 = time.perf_counter()
    lim = limit_analysis(disc)
    t2 = time.perf_counter()
    imp = impact(disc, -lim.u)
    t3 = time.perf_counter()
    return {"A_L": lim.A_L, "r": imp.r, "asm": t1 - t0, "lp": t2 - t1, "refine": 0.0,
            "qp": imp.solve_time, "total": t3 - t0, "its": imp.iterations, "disc": disc, "lim": lim,
            "note": ""}


def run_rigid(curve, N):
    return _pipeline(curve, uniform_nodes(curve, N), discretize)


def run_rigid_ref(curve, N):
    note = ""
    t0 = time.perf_counter()
    try:
        res = analyze(curve, elements=N)
    except SolverError as err:           # record it, then measure without the checks
        note = "verify failed: " + str(err).split("(")[-1].rstrip(")")
        t0 = time.perf_counter()
        res = analyze(curve, elements=N, verify=False)
    total = time.perf_counter() - t0
    tm = res.timings
    return {"A_L": res.A_L, "r": res.r, "asm": np.nan, "lp": tm["limit"], "refine": tm.get("continuum", 0.0),
            "qp": tm["impact_solver"], "total": total, "its": res.impact.iterations, "disc": res.impact.disc,
            "note": note}


def run_p1(curve, N):
    return _pipeline(curve, uniform_nodes(curve, N), discretize_p1)


def run_p1_cart(curve, N):
    return _pipeline(curve, uniform_nodes(curve, N),
                     lambda c, n: discretize_p1(c, n, components="cartesian"))


def run_p1_ref(curve, N):
    t0 = time.perf_counter()
    first = run_p1(curve, N)
    hs = merge_adjacent(first["disc"], first["lim"].hinges)
    if len(hs) != 4:
        return dict(first, note=f"{len(hs)} hinges: not refined")
    best, _ = optimise_load_factor(Mechanism.from_hinges(curve, hs))
    t1 = time.perf_counter()
    out = _pipeline(curve, midpoints_through(uniform_nodes(curve, N), best.s), discretize_p1)
    out["refine"] = t1 - t0 - first["qp"]
    out["total"] = time.perf_counter() - t0
    return out


RUNNERS = {"rigid": run_rigid, "rigid+ref": run_rigid_ref, "p1": run_p1, "p1-cart": run_p1_cart, "p1+ref": run_p1_ref}


def best_of(fn, curve, N, repeat):
    runs = [fn(curve, N) for _ in range(repeat)]
    out = dict(runs[0])
    for k in ("asm", "lp", "refine", "qp", "total"):
        out[k] = min(r[k] for r in runs)
    return out


def rate(Ns, err):
    """Least-squares slope of log|err| against log h = -log N."""
    Ns, err = np.asarray(Ns, float), np.abs(np.asarray(err, float))
    ok = err > 0
    return float(-np.polyfit(np.log(Ns[ok]), np.log(err[ok]), 1)[0]) if ok.sum() >= 2 else np.nan


def study(beta, t_over_r, sizes, repeat):
    curve = CircularArch.from_ratio(beta, t_over_r)
    rows = {v: [best_of(RUNNERS[v], curve, N, repeat) for N in sizes] for v in VARIANTS}
    ref = rows["rigid+ref"]
    A_ref = ref[-1]["A_L"]
    r_ref_rows = [x["r"] for x in ref]
    p = rate(sizes[1:], np.diff(r_ref_rows))       # observed rate of the increments
    r_ref = r_ref_rows[-1] + (r_ref_rows[-1] - r_ref_rows[-2]) / ((sizes[-1] / sizes[-2]) ** p - 1)
    print(f"\n## beta = {beta:g} deg, t/R = {t_over_r:g}   reference A_L = {A_ref:.9f} "
          f"(continuum), r = {r_ref:.9f} (rigid+ref, Richardson p = {p:.2f})\n")
    head = (f"| {'variant':9s} | {'N':>5s} | {'A_L':>11s} | {'err A_L':>9s} | {'r':>11s} | {'err r':>9s} | "
            f"{'dofs':>5s} | {'rows':>5s} | {'nnz':>6s} | {'t_asm':>6s} | {'t_LP':>6s} | {'t_ref':>6s} | "
            f"{'t_QP':>6s} | {'its':>3s} | {'t_tot':>6s} |")
    print(head)
    print("|" + "|".join("-" * (len(c)) for c in head.split("|")[1:-1]) + "|")
    summary = []
    for v in VARIANTS:
        for N, x in zip(sizes, rows[v]):
            sz = _sizes(x["disc"])
            asm = "   -  " if not np.isfinite(x["asm"]) else f"{x['asm']:6.3f}"
            print(f"| {v:9s} | {N:5d} | {x['A_L']:.9f} | {x['A_L'] - A_ref:9.2e} | {x['r']:.9f} | "
                  f"{x['r'] - r_ref:9.2e} | {sz['dofs']:5d} | {sz['rows']:5d} | {sz['nnz']:6d} | {asm} | "
                  f"{x['lp']:6.3f} | {x['refine']:6.3f} | {x['qp']:6.3f} | {x['its']:3d} | {x['total']:6.3f} |"
                  + (f" {x['note']}" if x["note"] else ""))
        eA = [x["A_L"] - A_ref for x in rows[v]]
        er = [x["r"] - r_ref for x in rows[v]]
        tail = slice(len(sizes) // 2, None)
        summary.append((v, rate(sizes, eA) if v != "rigid+ref" else np.nan, rate(sizes, er),
                        float(np.max(np.abs(er[tail]))), np.sum(np.diff(np.sign(er)) != 0)))
    print(f"\nobserved rates (slope of log|err| vs log h over N = {sizes[0]}..{sizes[-1]}); "
          f"max |err r| over N >= {sizes[len(sizes) // 2]}; sign changes of err r")
    for v, ra, rr, mx, sc in summary:
        print(f"  {v:9s}  A_L rate {ra:5.2f}   r rate {rr:5.2f}   max|err r| {mx:8.1e}   sign changes {sc}")
    return rows


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--sizes", default="50,100,200,400,800,1600")
    ap.add_argument("--repeat", type=int, default=3)
    args = ap.parse_args(argv)
    sizes = [int(s) for s in args.sizes.split(",")]
    print(f"elements benchmark: sizes {sizes}, timings best of {args.repeat} (s); "
          "t_LP for rigid+ref includes the uniform-mesh assembly, t_ref = continuum refinement "
          "(weakest sections + Newton + re-assembly + LP)")
    for beta, tr in GEOMETRIES:
        study(beta, tr, sizes, args.repeat)


if __name__ == "__main__":
    main()
