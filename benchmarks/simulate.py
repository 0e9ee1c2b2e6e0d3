"""Timing of ``fembeam simulate`` (the compiled Moreau-Jean loop) against the number of bodies.

The paper's arch (beta = 157.5 deg, t/R = 0.15, R = 5 m) cut into N voussoirs (N < 50) or N rigid
elements, through 10 s at dt = 1e-3 s under a ground motion (default: the one-sine pulse 0.6 g,
0.56 s; ``--record elcentro`` for El Centro scaled to ``--pga``).  Per size it prints the steps,
impacts and solves, the best of ``--repeat`` warm runs (wall and CPU seconds, microseconds per
step), the peak memory of one run (tracemalloc), the same run with Coulomb friction ``--mu``, and
for N <= 30 the NumPy reference engine; then the growth exponent of the time per step against N
(least squares on the logs) and per solve (a banded factorisation and its solves), with and without
friction, and the friction's cost (its time over the frictionless run's) with what the frictional
steps needed (steps that left the cone, and which stage solved them); then the start-up of a process on a warm
numba cache (:func:`load_times`): the wall time of ``fembeam simulate --json`` (7 voussoirs) with
its ``timings_s`` (``compile_or_load``: numba's import and the kernel's cache load), and the cache
load alone, split into numba's import, its first cached function (numba's own start-up: its
registries) and the kernel's loop (:func:`~fembeam.simulation.kernel.advance`), best of
``--repeat`` fresh processes each.  ``--load-only`` measures only that (a few seconds).

    python benchmarks/simulate.py [--sizes 7 15 30 50 100 200] [--seconds 10] [--dt 1e-3] [--mu 0.6]
    python benchmarks/simulate.py --load-only [--repeat 5]
"""
from __future__ import annotations

import argparse
import json
import subprocess
import sys
import time
import tracemalloc

import numpy as np

from fembeam import CircularArch
from fembeam.dynamics import GroundMotion
from fembeam.simulation import Simulator

# the cache load in a fresh process: numba's import, its first cached function (numba's registries,
# the same cost for any cached function: here the kernel's constants), then the kernel's loop (its
# first run of compiled_kernel(): the cache of advance() and a one-step run)
LOAD = """import json, time
from fembeam.simulation import stepper
c0, t0 = time.process_time(), time.perf_counter()
import numba
c1, t1 = time.process_time(), time.perf_counter()
from fembeam.simulation import kernel
kernel.compiled_constants()
c2, t2 = time.process_time(), time.perf_counter()
stepper.compiled_kernel()
c3, t3 = time.process_time(), time.perf_counter()
print(json.dumps([[t1 - t0, t2 - t1, t3 - t2], [c1 - c0, c2 - c1, c3 - c2]]))
"""


def timed(sim: Simulator, ground: GroundMotion, args, repeat: int, **kw):
    """``(result, best wall s, its CPU s)`` of ``repeat`` runs."""
    best = (None, np.inf, np.inf)
    for _ in range(repeat):
        t0, c0 = time.perf_counter(), time.process_time()
        res = sim.run(ground, dt=args.dt, t_end=args.seconds, **kw)
        wall, cpu = time.perf_counter() - t0, time.process_time() - c0
        if wall < best[1]:
            best = (res, wall, cpu)
    return best


def load_times(seconds: float, repeat: int) -> None:
    """Prints the wall time (s) of ``fembeam simulate --json`` in a fresh process on a warm cache
    and its ``timings_s``, then the cache load alone (:data:`LOAD`), best of ``repeat`` processes
    each (the warm cache built first)."""
    cmd = [sys.executable, "-m", "fembeam.cli", "simulate", "--voussoirs", "7", "--radius", "5", "--pulse", "sine",
           "--amplitude", "0.6", "--period", "0.56", "--t-end", f"{seconds:g}", "--json"]
    subprocess.run(cmd, capture_output=True, check=True)                 # the cache built, if it was not
    runs = []
    for _ in range(repeat):
        t0 = time.perf_counter()
        out = json.loads(subprocess.run(cmd, capture_output=True, text=True, check=True).stdout)
        runs.append((time.perf_counter() - t0, out["timings_s"]))
    wall, timings = min(runs, key=lambda r: r[0])
    each = " ".join(f"{t['compile_or_load']:.3f}" for _, t in runs)
    print(f"fembeam {' '.join(cmd[3:])} (fresh process, warm cache), best of {repeat}: wall {wall:.3f} s, "
          f"compile_or_load {timings['compile_or_load']:.3f} s, run {timings['run']:.3f} s "
          f"(compile_or_load of each: {each})")
    loads = [json.loads(subprocess.run([sys.executable, "-c", LOAD], capture_output=True, text=True,
                                       check=True).stdout) for _ in range(repeat)]
    for k, what in enumerate(("wall", "CPU")):
        best = [min(x[k][i] for x in loads) for i in range(3)]
        print(f"cache load (fresh process, warm cache), {what} s, best of {repeat}: "
              f"{min(sum(x[k]) for x in loads):.3f} = numba's import {best[0]:.3f} + its first cached function "
              f"(numba's registries; the kernel's module imported) {best[1]:.3f} + the kernel's loop {best[2]:.3f} "
              f"(best of each)")


def main() -> None:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--sizes", type=int, nargs="+", default=[7, 15, 30, 50, 100, 200])
    p.add_argument("--seconds", type=float, default=10.0)
    p.add_argument("--dt", type=float, default=1e-3)
    p.add_argument("--mu", type=float, default=0.6, help="friction coefficient of the friction column")
    p.add_argument("--record", default=None, help="a record instead of the sine pulse (e.g. elcentro)")
    p.add_argument("--pga", type=float, default=0.6)
    p.add_argument("--repeat", type=int, default=3)
    p.add_argument("--load-only", action="store_true", help="only the start-up on a warm cache (load_times)")
    args = p.parse_args()
    if args.load_only:
        load_times(args.seconds, args.repeat)
        return
    arch = CircularArch.from_ratio(157.5, 0.15, radius=5.0)
    ground = GroundMotion.sine(0.6, 0.56) if args.record is None else GroundMotion.record(args.record).to_pga(args.pga)
    print(f"simulate benchmark: beta = 157.5 deg, t/R = 0.15, R = 5 m, {ground.name}, {args.seconds:g} s at "
          f"dt = {args.dt:g} s; best of {args.repeat} warm runs")
    Simulator(arch, voussoirs=3).run(ground, dt=args.dt, t_end=0.01)       # compile or load the cache
    print(f"{'N':>5} {'rows':>5} {'steps':>6} {'impacts':>7} {'solves':>8} {'wall s':>7} {'cpu s':>7} "
          f"{'us/step':>8} {'us/solve':>8} {'MB':>6} {'mu s':>7} {'mu/none':>7} {'ref s':>7} {'speedup':>7} {'outcome':>9} {'peak rad':>9}")
    sizes, per_step, per_solve, friction = [], [], [], []
    for n in args.sizes:
        kw = {"voussoirs": n} if n < 50 else {"elements": n}
        sim = Simulator(arch, **kw)
        res, wall, cpu = timed(sim, ground, args, args.repeat)
        tracemalloc.start()
        sim.run(ground, dt=args.dt, t_end=args.seconds)
        mem = tracemalloc.get_traced_memory()[1] / 2**20
        tracemalloc.stop()
        try:
            rmu, wmu, _ = timed(Simulator(arch, friction=args.mu, **kw), ground, args, args.repeat)
            mu = f"{wmu:7.2f} {wmu / wall:7.2f}"
            friction.append((n, wall, wmu, rmu))
        except Exception as e:                    # a frictional step the solvers could not resolve
            mu = f"{'failed':>7} {'':>7}"
            print(f"  (N = {n}, mu = {args.mu:g}: {e})", file=sys.stderr)
        ref = f"{'':>7} {'':>7}"
        if n <= 30:
            t0 = time.perf_counter()
            sim.run(ground, dt=args.dt, t_end=args.seconds, engine="reference")
            wref = time.perf_counter() - t0
            ref = f"{wref:7.2f} {wref / wall:7.0f}"
        us = 1e6 * wall / res.steps
        sizes.append(n)
        per_step.append(us)
        per_solve.append(1e6 * wall / res.pivots)
        print(f"{n:5d} {3 * sim.contacts.J:5d} {res.steps:6d} {len(res.impacts):7d} {res.pivots:8d} {wall:7.3f} "
              f"{cpu:7.3f} {us:8.1f} {1e6 * wall / res.pivots:8.1f} {mem:6.1f} {mu} {ref} {res.outcome:>9} {res.peak_rotation:9.6f}", flush=True)
    if len(sizes) > 2:
        k = np.polyfit(np.log(sizes), np.log(per_step), 1)[0]
        k_big = np.polyfit(np.log(sizes[-3:]), np.log(per_step[-3:]), 1)[0]
        k_solve = np.polyfit(np.log(sizes), np.log(per_solve), 1)[0]
        print(f"growth with N of the time per step: exponent {k:.2f} over all sizes, {k_big:.2f} over the three "
              f"largest (more impacts per step); of the time per solve (one banded factorisation): {k_solve:.2f}")
    if friction:
        print(f"friction mu = {args.mu:g}: bodies, wall s without and with friction, ratio, steps that left the cone "
              f"(sliding_steps), solved by (stick in the cone after a self-stress / Newton / fixed point / Gauss-Seidel / "
              f"Lemke / loose), pivots and solves with friction")
        for n, w0, w1, r in friction:
            sb = r.solved_by
            print(f"{n:5d} {w0:8.3f} {w1:8.3f} {w1 / w0:6.2f} {r.sliding_steps:7d}   {r.redistributed}/{sb['newton']}/"
                  f"{sb['fixed_point']}/{sb['gauss_seidel']}/{sb['lemke']}/{r.loose_steps} {r.pivots:9d}")
        if len(friction) > 2:
            nb = np.log([f[0] for f in friction])
            k0 = np.polyfit(nb, np.log([f[1] for f in friction]), 1)[0]
            k1 = np.polyfit(nb, np.log([f[2] for f in friction]), 1)[0]
            print(f"growth with N of the run's wall time: exponent {k0:.2f} without friction, {k1:.2f} with")
    load_times(args.seconds, args.repeat)


if __name__ == "__main__":
    main()
