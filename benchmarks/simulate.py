"""Timing of ``fembeam simulate``: a 7-voussoir arch and a 100-element arch through 10 s of the
El Centro record (scaled to PGA 0.6 g) at dt = 1e-3 s.  Prints sizes, timings (wall and CPU: the
CPU time is the steadier figure on a shared machine), steps per second, the outcome and the peak rotation.
``solves`` counts the banded solves of the pivots and the interior point's iterations.

    python benchmarks/simulate.py [--seconds 10] [--dt 1e-3]
"""
from __future__ import annotations

import argparse
import time

from fembeam import CircularArch
from fembeam.dynamics import GroundMotion
from fembeam.simulation import Simulator


def main() -> None:
    p = argparse.ArgumentParser(description=__doc__)
    p.add_argument("--seconds", type=float, default=10.0)
    p.add_argument("--dt", type=float, default=1e-3)
    p.add_argument("--sizes", type=int, nargs="+", default=[7, 100])
    args = p.parse_args()
    arch = CircularArch.from_ratio(157.5, 0.15, radius=5.0)
    ground = GroundMotion.record("elcentro").to_pga(0.6)
    print(f"simulate benchmark: beta = 157.5 deg, t/R = 0.15, R = 5 m, El Centro to PGA 0.6 g, "
          f"{args.seconds:g} s at dt = {args.dt:g} s")
    print(f"{'bodies':>7} {'rows':>5} {'setup s':>8} {'run s':>8} {'steps':>7} {'cut':>6} {'impacts':>8} "
          f"{'solves':>8} {'steps/s':>8} {'cpu s':>7} {'outcome':>11} {'t_end':>7} {'peak rad':>9}")
    for n in args.sizes:
        t0 = time.perf_counter()
        sim = Simulator(arch, voussoirs=n)
        setup = time.perf_counter() - t0
        t0, c0 = time.perf_counter(), time.process_time()
        res = sim.run(ground, dt=args.dt, t_end=args.seconds)
        run, cpu = time.perf_counter() - t0, time.process_time() - c0
        print(f"{n:7d} {3 * sim.contacts.J:5d} {setup:8.3f} {run:8.2f} {res.steps:7d} {res.cut_steps:6d} "
              f"{len(res.impacts):8d} {res.pivots:8d} {res.steps / run:8.0f} {cpu:7.2f} {res.outcome:>11} {res.t_end:7.3f} "
              f"{res.peak_rotation:9.6f}")


if __name__ == "__main__":
    main()
