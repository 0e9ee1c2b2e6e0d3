"""Benchmark: Clarabel vs OSQP on the impact QP (projection form, docs/theory.md).

For beta = 157.5 deg, t/R = 0.15 and N = 100 ... 6400 rigid elements (the
pipeline: ``fembeam.analyze`` gives the hinge-refined mesh and the mechanism ``u``),
the impact QP with ``d0 = -u`` is solved by

  clarabel         ``impact(disc, d0, backend="clarabel")`` (default, tol 1e-10)
  osqp             ``impact(disc, d0, backend="osqp")`` (fembeam's settings: eps 1e-10,
                   polishing, adaptive rho every 25 iterations)
  osqp-e6-pol      eps_abs = eps_rel = 1e-6, polishing, OSQP's default rho adaptivity
  osqp-e6          the same without polishing (OSQP's out-of-the-box accuracy)
  osqp-e6-pol-ws   as osqp-e6-pol, warm-started from the N/2 solution (primal and dual)
                   transferred to the finer mesh

and compared with a tight reference (Clarabel, tol 1e-12; 1e-11 if that stalls):
``dr`` = |r - r_ref|, ``dd`` = ||d - d_ref||_M / ||d_ref||_M, ``dmu`` = max |impulse -
impulse_ref| / max |impulse_ref| over fibre and shear impulses, ``verif`` = the largest
of the verification figures of ``res.verification`` (relative; max_shear_ratio left
out: it is physics, not an error) with the name of the worst one, and ``ok`` whether all
pass fembeam's thresholds.  OSQP runs with a 60 s time limit; once an OSQP setting takes
more than 10 s, its larger sizes are skipped.  Usage::

    python benchmarks/qp_backends.py [--sizes 100,200,...,6400]
"""
from __future__ import annotations

import argparse
import time

import numpy as np
import scipy.sparse as sp

from fembeam import analyze
from fembeam.analysis import THRESHOLDS
from fembeam.errors import SolverError
from fembeam.geometry import CircularArch
from fembeam.mechanisms.hinge import find_hinges
from fembeam.analysis.impact import ImpactResult, _verify, impact
from fembeam.fem import dof_scaling

TIME_LIMIT = 60.0
SKIP_AFTER = 10.0
OSQP_VARIANTS = {
    "osqp-e6-pol": dict(eps_abs=1e-6, eps_rel=1e-6, polishing=True, polish_refine_iter=20),
    "osqp-e6": dict(eps_abs=1e-6, eps_rel=1e-6, polishing=False),
    "osqp-e6-pol-ws": dict(eps_abs=1e-6, eps_rel=1e-6, polishing=True, polish_refine_iter=20, warm=True),
}


def scaled_problem(disc, d0):
    """The scaled QP exactly as :func:`fembeam.impact.impact` builds it."""
    D = dof_scaling(disc)
    M = disc.M
    m = float(disc.rigid(V=(1.0, 0.0)) @ M @ disc.rigid(V=(1.0, 0.0)))
    sigma = np.sqrt(float(d0 @ M @ d0) / m)
    P = (D @ M @ D / m).tocsc()
    q = -(D @ (M @ d0)) / (m * sigma)
    return D, m, sigma, P, q


def osqp_impact(disc, d0, settings, warm=None):
    """Impact QP by OSQP with ``settings``; ``warm`` = (x, y) in OSQP's variables."""
    import osqp

    D, m, sigma, P, q = scaled_problem(disc, d0)
    Aeq, Ain = disc.B_slide @ D, disc.B_open @ D
    A = sp.vstack([Aeq, Ain]).tocsc()
    lo = np.zeros(A.shape[0])
    hi = np.r_[np.zeros(Aeq.shape[0]), np.full(Ain.shape[0], np.inf)]
    s = osqp.OSQP()
    s.setup(sp.triu(P).tocsc(), q, A, lo, hi, verbose=False, max_iter=1_000_000, time_limit=TIME_LIMIT,
            **settings)
    if warm is not None:
        s.warm_start(x=warm[0], y=warm[1])
    t0 = time.perf_counter()
    res = s.solve()
    dt = time.perf_counter() - t0
    y = -res.y
    J = disc.n_joints
    d = sigma * (D @ res.x)
    two_k = float(d0 @ disc.M @ d0)
    out = ImpactResult(disc, d0, d, float(d @ disc.M @ d) / two_k, m * sigma * y[J:].reshape(2, J),
                       m * sigma * y[:J], find_hinges(disc, d), "osqp", int(res.info.iter), dt)
    out.verification = _verify(out, two_k)
    out.status = f"{res.info.status}" + ("" if not settings.get("polishing") else
                                         f"/pol{'+' if res.info.status_polish == 1 else '-'}")
    out.osqp_vars = (res.x, res.y)
    return out


def transfer(coarse, fine, x_c, y_c):
    """OSQP warm start on ``fine`` from the coarse solution: each fine element takes the
    rigid motion of the coarse element containing its midpoint; multipliers are
    interpolated in arc length (joint forces are point values)."""
    Dc, Df = dof_scaling(coarse).diagonal(), dof_scaling(fine).diagonal()
    dc = (Dc * x_c).reshape(-1, 3)
    Pc, tc, nc = coarse.frames["P"], coarse.frames["t"], coarse.frames["n"]
    Pf, tf, nf = fine.frames["P"], fine.frames["t"], fine.frames["n"]
    e = np.clip(np.searchsorted(coarse.nodes_s, fine.frames["s"]) - 1, 0, coarse.n_elements - 1)
    w, v, om = dc[e, 0], dc[e, 1], dc[e, 2]
    vx = w * tc[0, e] + v * nc[0, e] - om * (Pf[1] - Pc[1, e])
    vy = w * tc[1, e] + v * nc[1, e] + om * (Pf[0] - Pc[0, e])
    df = np.c_[vx * tf[0] + vy * tf[1], vx * nf[0] + vy * nf[1], om].ravel()
    Jc, Jf = coarse.n_joints, fine.n_joints
    sc, sf = coarse.joint_s, fine.joint_s
    ys = [np.interp(sf, sc, y_c[:Jc])] + [np.interp(sf, sc, y_c[Jc + k * Jc: Jc + (k + 1) * Jc]) for k in (0, 1)]
    return df / Df, np.concatenate(ys)


def compare(res, ref) -> dict:
    M = ref.disc.M
    dd = res.d - ref.d
    imp = np.r_[res.mu.ravel(), res.lam]
    imp_ref = np.r_[ref.mu.ravel(), ref.lam]
    figs = {k: v for k, v in res.verification.items() if k != "max_shear_ratio"}
    worst = max(figs, key=figs.get)
    ok = all(v <= THRESHOLDS.get(k, np.inf) for k, v in figs.items())
    return {"dr": abs(res.r - ref.r), "dd": float(np.sqrt(dd @ M @ dd / (ref.d @ M @ ref.d))),
            "dmu": float(np.max(np.abs(imp - imp_ref)) / np.max(np.abs(imp_ref))),
            "verif": figs[worst], "worst": worst, "ok": ok}


def reference(disc, d0):
    for tol in (1e-12, 1e-11):
        try:
            return impact(disc, d0, backend="clarabel", tol=tol), tol
        except SolverError:
            continue
    raise SolverError("no tight Clarabel reference")


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--sizes", default="100,200,400,800,1600,3200,6400")
    ap.add_argument("--embrace", type=float, default=157.5)
    ap.add_argument("--t-over-r", type=float, default=0.15)
    args = ap.parse_args(argv)
    sizes = [int(s) for s in args.sizes.split(",")]
    curve = CircularArch.from_ratio(args.embrace, args.t_over_r)
    print(f"impact QP backends: beta = {args.embrace:g} deg, t/R = {args.t_over_r:g}, rigid elements with "
          "hinge refinement; times are the solver's own (s)\n")
    head = (f"| {'N':>5s} | {'vars':>6s} | {'rows':>6s} | {'backend':14s} | {'status':14s} | {'iter':>7s} | "
            f"{'time':>7s} | {'r':>11s} | {'dr':>8s} | {'dd':>8s} | {'dmu':>8s} | {'verif':>8s} | "
            f"{'worst figure':20s} | ok |")
    print(head)
    print("|" + "|".join("-" * len(c) for c in head.split("|")[1:-1]) + "|")
    skip: dict[str, bool] = {}
    prev = None      # (disc, {variant: (x, y)}) of the previous size, for warm starts
    for N in sizes:
        try:
            an = analyze(curve, elements=N)
        except SolverError:
            an = analyze(curve, elements=N, verify=False)
        disc, d0 = an.impact.disc, -an.limit.u
        ref, rtol = reference(disc, d0)
        rows = [(f"clarabel-{rtol:.0e}", ref, "reference")]
        res = impact(disc, d0, backend="clarabel")
        rows.append(("clarabel", res, "Solved"))
        store = {}
        for name in ("osqp",) + tuple(OSQP_VARIANTS):
            if skip.get(name):
                rows.append((name, None, "skipped (>60 s)"))
                continue
            try:
                if name == "osqp":
                    res = impact(disc, d0, backend="osqp")
                    status = "solved/pol"
                else:
                    cfg = dict(OSQP_VARIANTS[name])
                    warm = cfg.pop("warm", False)
                    ws = None
                    if warm and prev is not None and name in prev[1]:
                        ws = transfer(prev[0], disc, *prev[1][name])
                    elif warm:
                        rows.append((name, None, "no coarser solution"))
                        res = osqp_impact(disc, d0, cfg)
                        store[name] = res.osqp_vars
                        continue
                    res = osqp_impact(disc, d0, cfg, ws)
                    status = res.status
                    store[name] = res.osqp_vars
            except SolverError as err:
                rows.append((name, None, str(err)[:60]))
                skip[name] = True
                continue
            if res.solve_time > SKIP_AFTER:
                skip[name] = True
            rows.append((name, res, status))
        for name, res, status in rows:
            if res is None:
                print(f"| {N:5d} | {disc.M.shape[0]:6d} | {disc.B.shape[0]:6d} | {name:14s} | {status} |")
                continue
            c = compare(res, ref)
            print(f"| {N:5d} | {disc.M.shape[0]:6d} | {disc.B.shape[0]:6d} | {name:14s} | {status:14s} | "
                  f"{res.iterations:7d} | {res.solve_time:7.3f} | {res.r:.9f} | {c['dr']:8.1e} | {c['dd']:8.1e} | "
                  f"{c['dmu']:8.1e} | {c['verif']:8.1e} | {c['worst']:20s} | {'y' if c['ok'] else 'n':2s} |")
        prev = (disc, store)
    print(f"\nthresholds (fembeam.analysis.THRESHOLDS): "
          + ", ".join(f"{k} {v:.0e}" for k, v in THRESHOLDS.items() if "thrust" not in k and "force" not in k))


if __name__ == "__main__":
    main()
