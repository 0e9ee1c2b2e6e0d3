"""Benchmark: cost of the limit analysis against the number of elements.

For N = 10^3 .. 10^6 rigid elements of the paper's arch (157.5 deg, t/R = 0.15) it
prints the time of the assembly (``discretize``), of ``limit_analysis`` (factorisation
of the equilibrium operator, constraint generation, certificate and checks) and of the
continuum refinement, the peak memory of the process, and the growth exponents fitted
by least squares to log(time) against log(N).  With ``--analyze N`` it also runs
``fembeam.analyze`` end to end on N elements; with ``--kinematic N`` it times, up to N
elements, the kinematic LP over the 3N element velocities (HiGHS, interior point with
crossover), the formulation the static LP replaced.

    python benchmarks/limit_scaling.py [--max 1000000] [--analyze 100000] [--kinematic 30000]
"""
from __future__ import annotations

import argparse
import resource
import time

import numpy as np

from fembeam import CircularArch, analyze, discretize, limit_analysis, uniform_nodes
from fembeam.analysis import continuum_limit


def peak_mb() -> float:
    return resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024.0


def kinematic(disc) -> float:
    """min f_y.u s.t. f_x.u = m, B_slide u = 0, B_open u >= 0 over the element velocities."""
    import scipy.sparse as sp
    from scipy.optimize import linprog

    from fembeam.fem import dof_scaling

    D = dof_scaling(disc)
    fx, fy = disc.load_vectors()
    m = float(fx @ disc.rigid(V=(1.0, 0.0)))
    A_eq = sp.vstack([disc.B_slide @ D, sp.csr_matrix((D @ fx) / m)]).tocsr()
    b_eq = np.zeros(A_eq.shape[0])
    b_eq[-1] = 1.0
    res = linprog(D @ fy / m, A_ub=-(disc.B_open @ D), b_ub=np.zeros(disc.B_open.shape[0]), A_eq=A_eq, b_eq=b_eq,
                  bounds=(None, None), method="highs-ipm")
    return float(res.fun)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--max", type=int, default=1_000_000)
    ap.add_argument("--analyze", type=int, default=100_000)
    ap.add_argument("--kinematic", type=int, default=0)
    args = ap.parse_args()
    arch = CircularArch.from_ratio(157.5, 0.15)
    sizes = [n for n in (1_000, 3_000, 10_000, 30_000, 100_000, 300_000, 1_000_000) if n <= args.max]
    rows = []
    print(f"{'N':>9} {'assembly s':>11} {'limit s':>9} {'continuum s':>12} {'LP rounds':>10} {'A_L':>12} {'peak MB':>9}")
    for n in sizes:
        t0 = time.perf_counter()
        disc = discretize(arch, uniform_nodes(arch, n))
        t1 = time.perf_counter()
        lim = limit_analysis(disc)
        t2 = time.perf_counter()
        cont = continuum_limit(disc)
        t3 = time.perf_counter()
        rows.append((n, t1 - t0, t2 - t1, t3 - t2))
        kin = ""
        if n <= args.kinematic:
            t4 = time.perf_counter()
            lam = kinematic(disc)
            kin = f"   kinematic LP {time.perf_counter() - t4:.3f} s, A_L {lam:.9f}"
        print(f"{n:9d} {t1 - t0:11.3f} {t2 - t1:9.3f} {t3 - t2:12.3f} {lim.lp_rounds:10d} {lim.A_L:12.9f} {peak_mb():9.0f}"
              + kin, flush=True)
    a = np.array(rows)
    big = a[:, 0] >= 10_000
    for j, name in ((1, "assembly"), (2, "limit_analysis"), (3, "continuum")):
        p = np.polyfit(np.log(a[:, 0]), np.log(a[:, j]), 1)[0]
        line = f"fitted growth exponent, {name}: {p:.2f} (N = {sizes[0]}..{sizes[-1]})"
        if big.sum() >= 2:   # without the sizes where fixed costs dominate
            q = np.polyfit(np.log(a[big, 0]), np.log(a[big, j]), 1)[0]
            line += f", {q:.2f} (N >= 10^4)"
        print(line)
    if args.analyze:
        t0 = time.perf_counter()
        res = analyze(arch, elements=args.analyze)
        print(f"analyze --elements {args.analyze}: {time.perf_counter() - t0:.2f} s end to end, outcome {res.outcome}, "
              f"A_L = {res.A_L:.9f}, r = {res.r:.6f}; timings "
              + ", ".join(f"{k} {v:.2f} s" for k, v in res.timings.items()) + f"; peak {peak_mb():.0f} MB")


if __name__ == "__main__":
    main()
