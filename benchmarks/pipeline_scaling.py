"""Benchmark: every stage of ``analyze`` against the number of elements, with its memory.

For N = 10^3 .. 10^6 rigid elements of the paper's arch (157.5 deg, t/R = 0.15) it runs the
stages of ``fembeam analyze`` one by one on the uniform mesh and prints, per stage, the
wall time and the peak resident memory reached during the stage above the memory held
before it (the kernel's high-water mark, reset before each stage through
``/proc/self/clear_refs``, so that it counts every allocation: NumPy, SciPy, LAPACK,
HiGHS, Clarabel):

* ``assembly``: ``discretize`` (scikit-fem forms: mass, opening and sliding operators);
* ``statics``: banded LU of the equilibrium operator and the self-stress states;
* ``limit LP``: the static LP in the three redundants (constraint generation);
* ``limit verif.``: the certificate's figures (equilibrium by two routes, admissibility,
  duality gap, compatibility of the mechanism);
* ``continuum``: the weakest sections between the joints and the bracket of ``A_L``;
* ``impact QP``: the post-impact projection (``--backend``, default ``auto``);
* ``impact verif.``: the impulse line recomputed from the momentum balance, work, gaps.

Then the growth exponent of each stage fitted by least squares to log(time) against
log(N) (all sizes, and N >= 10^4 where fixed costs no longer dominate), and ``analyze``
end to end at ``--analyze`` elements with its ``timings_s``.

    python benchmarks/pipeline_scaling.py [--max 1000000] [--analyze 100000] [--backend auto]
"""
from __future__ import annotations

import argparse
import time

import importlib

import numpy as np

from fembeam import CircularArch, analyze, discretize, uniform_nodes
from fembeam.analysis import continuum_limit
from fembeam.analysis.statics import statics

impact_mod = importlib.import_module("fembeam.analysis.impact")   # the modules, not the functions
limit_mod = importlib.import_module("fembeam.analysis.limit")     # of the same names
STAGES = ("assembly", "statics", "limit LP", "limit verif.", "continuum", "impact QP", "impact verif.")


def _status(key: str) -> float:
    with open("/proc/self/status") as f:
        for line in f:
            if line.startswith(key):
                return int(line.split()[1]) / 1024.0
    return float("nan")


def reset_peak() -> float:
    """Reset the high-water mark; returns the resident memory now (MB)."""
    try:
        with open("/proc/self/clear_refs", "w") as f:
            f.write("5")
    except OSError:
        pass
    return _status("VmRSS")


def peak() -> float:
    return _status("VmHWM")


class Timed:
    """Wraps a module function and accumulates its wall time."""

    def __init__(self, module, name: str):
        self.module, self.name, self.f = module, name, getattr(module, name)
        self.t = 0.0
        setattr(module, name, self)

    def __call__(self, *a, **k):
        t0 = time.perf_counter()
        try:
            return self.f(*a, **k)
        finally:
            self.t += time.perf_counter() - t0


def run(arch, n: int, backend: str) -> tuple[dict, dict, dict]:
    times, mem = {}, {}
    lim_fig = Timed(limit_mod, "_static_figures")
    inc_fig = Timed(limit_mod, "_incompatibility")
    imp_fig = Timed(impact_mod, "_verify")
    try:
        def stage(name, f):
            base = reset_peak()
            t0 = time.perf_counter()
            out = f()
            times[name] = time.perf_counter() - t0
            mem[name] = max(peak() - base, 0.0)
            return out

        disc = stage("assembly", lambda: discretize(arch, uniform_nodes(arch, n)))
        stage("statics", lambda: statics(disc))
        lim = stage("limit LP", lambda: limit_mod.limit_analysis(disc))
        times["limit verif."] = lim_fig.t + inc_fig.t
        times["limit LP"] -= times["limit verif."]
        mem["limit verif."] = float("nan")
        cont = stage("continuum", lambda: continuum_limit(disc))
        imp = stage("impact QP", lambda: impact_mod.impact(disc, -lim.u, backend=backend))
        times["impact verif."] = imp_fig.t
        times["impact QP"] -= imp_fig.t
        mem["impact verif."] = float("nan")
    finally:
        for w in (lim_fig, inc_fig, imp_fig):
            setattr(w.module, w.name, w.f)
    info = {"A_L": cont.A_L, "r": imp.r, "backend": imp.backend, "iterations": imp.iterations}
    return times, mem, info


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--max", type=int, default=1_000_000)
    ap.add_argument("--analyze", type=int, default=100_000)
    ap.add_argument("--backend", default="auto")
    args = ap.parse_args()
    arch = CircularArch.from_ratio(157.5, 0.15)
    sizes = [n for n in (1_000, 3_000, 10_000, 30_000, 100_000, 300_000, 1_000_000) if n <= args.max]
    print("stage times in s; in brackets the peak memory of the stage above what was held before it, MB "
          "(verification runs inside its stage)")
    print(f"{'N':>9} " + " ".join(f"{s:>17}" for s in STAGES) + f" {'A_L':>12} {'r':>9} {'QP':>16}")
    T = []
    for n in sizes:
        times, mem, info = run(arch, n, args.backend)
        T.append([times[s] for s in STAGES])
        cells = [f"{times[s]:8.3f} ({mem[s]:5.0f})" if np.isfinite(mem[s]) else f"{times[s]:8.3f}        "
                 for s in STAGES]
        print(f"{n:9d} " + " ".join(f"{c:>17}" for c in cells)
              + f" {info['A_L']:12.9f} {info['r']:9.6f} {info['backend']:>11} {info['iterations']:4d}", flush=True)
    T = np.array(T)
    N = np.array(sizes, float)
    big = N >= 10_000
    print("fitted growth exponents (log time against log N):")
    for j, s in enumerate(STAGES):
        p = np.polyfit(np.log(N), np.log(T[:, j]), 1)[0]
        line = f"  {s:14s} {p:5.2f} (N = {sizes[0]}..{sizes[-1]})"
        if big.sum() >= 2:
            q = np.polyfit(np.log(N[big]), np.log(T[big, j]), 1)[0]
            line += f", {q:5.2f} (N >= 10^4)"
        print(line)
    if args.analyze:
        base = reset_peak()
        t0 = time.perf_counter()
        res = analyze(arch, elements=args.analyze, backend=args.backend)
        print(f"analyze --elements {args.analyze}: {time.perf_counter() - t0:.2f} s end to end, outcome {res.outcome}, "
              f"A_L = {res.A_L:.9f}, r = {res.r:.6f} ({res.impact.backend}); timings_s "
              + ", ".join(f"{k} {v:.2f}" for k, v in res.timings.items())
              + f"; peak {peak() - base:.0f} MB above {base:.0f} MB")


if __name__ == "__main__":
    main()
