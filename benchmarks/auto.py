"""Benchmark of ``--model auto`` against ``rock`` and ``simulate``: the cost of one run, and of a
spectrum.

    python benchmarks/auto.py [--repeat 3] [--spectrum] [--workers 2] [--periods 0.1:2.05:0.05] [--elcentro]

The paper's arch in 7 voussoirs (beta = 157.5 deg, t/R = 0.15, R = 5 m).  Runs: one-sine pulses
(0.56 s; 0.45, 0.6, 0.8 g) to 4.06 s and the El Centro record at PGA 0.6 g to its default end, each
model set up once and run ``--repeat`` times (best CPU time; the impact transitions of rock are
solved in the first, untimed run).  ``--spectrum``: the overturning spectrum of one-sine pulses
(40 periods, default amplitude grid) with each model on ``--workers`` local processes (wall time,
CPU in the cases, runs).  ``--elcentro``: auto and simulate at scale factors of El Centro (its
first 15 s, as docs/comparison.md) around simulate's collapse factor.  Prints sizes, timings and
the peak resident memory.
"""
from __future__ import annotations

import argparse
import resource
import time

import numpy as np

from fembeam import CircularArch
from fembeam.auto import AutoModel
from fembeam.dynamics import GroundMotion, Rocker
from fembeam.simulation import Simulator
from fembeam.studies.spectrum import spectrum

ARCH = CircularArch.from_ratio(157.5, 0.15, radius=5.0)


def _best(fun, repeat: int) -> tuple[float, object]:
    fun()                                     # set-up, transitions, compiled kernel: not timed
    best, out = np.inf, None
    for _ in range(repeat):
        c = time.process_time()
        out = fun()
        best = min(best, time.process_time() - c)
    return best, out


def runs(repeat: int) -> None:
    rk = Rocker(ARCH, voussoirs=7, qp=False)
    sim = Simulator(ARCH, voussoirs=7)
    am = AutoModel(ARCH, voussoirs=7)
    cases = [(f"sine {a:g} g, 0.56 s", GroundMotion.sine(a, 0.56), 4.06) for a in (0.45, 0.6, 0.8)]
    cases.append(("El Centro, PGA 0.6 g", GroundMotion.record("elcentro").to_pga(0.6), None))
    print(f"one run, CPU s (best of {repeat}); 7 voussoirs, R = 5 m")
    print(f"  {'ground motion':24s} {'rock':>8s} {'simulate':>9s} {'auto':>8s}  outcomes (rock / simulate / auto); "
          f"auto: segments, simulated share")
    for name, g, t_end in cases:
        t_r, r = _best(lambda: rk.run(g, t_end=t_end, thrust_check=True, history=False), repeat)
        t_s, s = _best(lambda: sim.run(g, t_end=t_end), repeat)
        t_a, a = _best(lambda: am.run(g, t_end=t_end, history=False), repeat)
        share = sum(x.t_end - x.t_start for x in a.segments if x.model == "simulate") / (a.t_end - float(g.t[0]))
        print(f"  {name:24s} {t_r:8.3f} {t_s:9.3f} {t_a:8.3f}  {r.outcome} / {s.outcome} / {a.outcome}; "
              f"{len(a.segments)}, {100 * share:.0f} %")


def spectra(workers: int, periods: str, models=("rock", "auto", "simulate")) -> None:
    lo, hi, step = (float(x) for x in periods.split(":"))
    ps = [round(p, 10) for p in np.arange(lo, hi + 0.5 * step, step)]
    print(f"spectrum, one-sine pulses, {len(ps)} periods {ps[0]:g} to {ps[-1]:g} s, {workers} workers")
    found = {}
    for model in models:
        clock, cpu0 = time.perf_counter(), time.process_time()
        res = spectrum(ARCH, "sine", ps, voussoirs=7, workers=workers, progress=False, model=model)
        wall, own = time.perf_counter() - clock, time.process_time() - cpu0
        cases = sum(r["time_s"] for r in res.rows)
        n = sum(r["runs"] for r in res.rows)
        found[model] = [r["first_overturning"] for r in res.rows]
        cpu = f", CPU {own:.1f} s ({1e3 * own / max(n, 1):.0f} ms a run)" if workers == 1 else ""
        print(f"  {model:8s} wall {wall:7.1f} s, wall in cases {cases:7.1f} s, {n} runs{cpu}")
    pairs = [(a, s) for a, s in zip(found.get("auto", []), found.get("simulate", [])) if a is not None and s is not None]
    if pairs:
        dev = max(abs(a / s - 1) for a, s in pairs)
        print(f"  thresholds: auto against simulate, largest relative difference {dev:.2e} over {len(pairs)} periods")
    if "rock" in found and "simulate" in found:
        ratios = [r / s for r, s in zip(found["rock"], found["simulate"]) if r and s]
        print(f"  rock over simulate from {min(ratios):.2f} to {max(ratios):.2f}")


def elcentro() -> None:
    import math
    g0 = GroundMotion.record("elcentro")
    keep = g0.t <= 15.0
    rec = GroundMotion(g0.t[keep], g0.a[keep], name="El Centro, first 15 s")
    t_end = 15.0 + 3.0 * math.sqrt(ARCH.length / 9.81)
    am, sim = AutoModel(ARCH, voussoirs=7), Simulator(ARCH, voussoirs=7)
    print("El Centro (first 15 s), 7 voussoirs, dt = 1 ms: factor, auto, simulate (outcome, t_overturn)")
    for f in (3.0055, 3.0063, 3.0067, 3.0075, 3.1, 3.2):
        a = am.run(rec.scaled(f), t_end=t_end, history=False)
        s = sim.run(rec.scaled(f), dt=1e-3, t_end=t_end)
        print(f"  {f:7.4f}  auto {a.outcome:10s} {a.t_overturn}  simulate {s.outcome:10s} {s.t_overturn}  "
              f"(auto: {len(a.segments)} segments)")


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--repeat", type=int, default=3)
    ap.add_argument("--spectrum", action="store_true")
    ap.add_argument("--workers", type=int, default=2)
    ap.add_argument("--periods", default="0.1:2.05:0.05", help="start:stop:step (s), stop included")
    ap.add_argument("--elcentro", action="store_true")
    ap.add_argument("--models", default="rock,auto,simulate", help="--spectrum: the models, comma-separated")
    ap.add_argument("--no-runs", action="store_true", help="skip the single runs")
    args = ap.parse_args()
    if args.elcentro:
        elcentro()
        return
    if not args.no_runs:
        runs(args.repeat)
    if args.spectrum:
        spectra(args.workers, args.periods, tuple(args.models.split(",")))
    print(f"peak resident memory {resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024:.0f} MB (this process)")


if __name__ == "__main__":
    main()
