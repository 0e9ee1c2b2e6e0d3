"""Benchmark: HiGHS methods on the limit-analysis LP (times and sizes; not run by CI).

    python benchmarks/lp_methods.py [--sizes 200,400,800,1600,3200,6400]

Prints, per mesh size, the LP size and for each method the solve time, A_L and the
equilibrium residual of the duals (the figure fembeam checks), for beta = 157.5 deg,
t/R = 0.15 on uniform meshes of rigid elements.
"""
import argparse
import time

import numpy as np
import scipy.sparse as sp
from scipy.optimize import linprog

from fembeam import CircularArch, discretize, uniform_nodes
from fembeam.fem import dof_scaling


def run(N: int, method: str):
    c = CircularArch.from_ratio(157.5, 0.15)
    disc = discretize(c, uniform_nodes(c, N))
    D = dof_scaling(disc)
    fx, fy = disc.load_vectors()
    m = fx @ disc.rigid((1.0, 0.0))
    Bs, Bo = disc.B_slide @ D, disc.B_open @ D
    A_eq = sp.vstack([Bs, sp.csr_matrix((D @ fx) / m)]).tocsr()
    b_eq = np.zeros(A_eq.shape[0])
    b_eq[-1] = 1.0
    t0 = time.perf_counter()
    res = linprog(D @ fy / m, A_ub=-Bo, b_ub=np.zeros(Bo.shape[0]), A_eq=A_eq, b_eq=b_eq,
                  bounds=(None, None), method=method)
    dt = time.perf_counter() - t0
    N_ = -m * res.ineqlin.marginals
    S = m * res.eqlin.marginals[:-1]
    eq = fy - res.fun * fx - disc.B_open.T @ N_ - disc.B_slide.T @ S
    return A_eq.shape[1], A_eq.shape[0] + Bo.shape[0], dt, res.fun, np.linalg.norm(eq) / np.linalg.norm(fy)


if __name__ == "__main__":
    ap = argparse.ArgumentParser()
    ap.add_argument("--sizes", default="200,400,800,1600,3200,6400")
    sizes = [int(x) for x in ap.parse_args().sizes.split(",")]
    print(f"{'N':>6s} {'vars':>6s} {'rows':>6s} {'method':>10s} {'time [s]':>9s} {'A_L':>12s} {'eq. residual':>13s}")
    for N in sizes:
        for method in ("highs-ds", "highs-ipm"):
            n, rows, dt, lam, eq = run(N, method)
            print(f"{N:6d} {n:6d} {rows:6d} {method:>10s} {dt:9.3f} {lam:12.9f} {eq:13.2e}", flush=True)
