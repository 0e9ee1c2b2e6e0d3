"""Benchmark of ``fembeam rock``: set-up, first run (impact transitions solved), second run
(transitions cached), on the first 30 s of the shipped records, for the 7-voussoir and the
continuous paper arch (beta = 157.5 deg, t/R = 0.15).

    python benchmarks/rocking.py [--radius 5] [--pga 0.8] [--repeat 3]

Prints, per case: impacts, mechanisms met, set-up time, first and second run times, and the
second run split into integration, transitions and the thrust-line check.  The second runs
(with and without the thrust-line check) are the best of ``--repeat`` runs, which makes them
less sensitive to other load on the machine.
"""
from __future__ import annotations

import argparse
import time

import numpy as np

from fembeam import CircularArch
from fembeam.dynamics import GroundMotion, Rocker


def window(gm: GroundMotion, seconds: float) -> GroundMotion:
    keep = gm.t <= gm.t[0] + seconds
    return GroundMotion(gm.t[keep], gm.a[keep], f"{gm.name}, first {seconds:g} s")


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--radius", type=float, default=5.0)
    ap.add_argument("--pga", type=float, default=0.8)
    ap.add_argument("--seconds", type=float, default=30.0)
    ap.add_argument("--repeat", type=int, default=3, help="second runs: best of this many (default 3)")
    args = ap.parse_args()
    arch = CircularArch.from_ratio(157.5, 0.15, radius=args.radius)
    print(f"rock benchmark: beta = 157.5 deg, t/R = 0.15, R = {args.radius:g} m, records scaled to PGA "
          f"{args.pga:g} g, first {args.seconds:g} s, t_end = end of the window")
    print(f"{'record':>11} {'member':>12} {'impacts':>8} {'mechs':>6} {'setup s':>8} {'1st run s':>10} "
          f"{'2nd run s':>10} {'integr. s':>10} {'transit. s':>10} {'thrust s':>9} {'2nd no-thrust s':>16}")
    for name in ("elcentro", "lomaprieta"):
        gm = window(GroundMotion.record(name).to_pga(args.pga), args.seconds)
        for label, kw in (("7 voussoirs", {"voussoirs": 7}), ("continuous", {})):
            t0 = time.perf_counter()
            rk = Rocker(arch, qp=False, **kw)
            setup = time.perf_counter() - t0
            t_end = float(gm.t[-1])
            t0 = time.perf_counter()
            rk.run(gm, t_end=t_end)
            first = time.perf_counter() - t0
            second = bare = float("inf")
            for _ in range(max(args.repeat, 1)):
                t0 = time.perf_counter()
                out = rk.run(gm, t_end=t_end)
                if time.perf_counter() - t0 < second:
                    second, res = time.perf_counter() - t0, out
                t0 = time.perf_counter()
                rk.run(gm, t_end=t_end, thrust_check=False)
                bare = min(bare, time.perf_counter() - t0)
            tm = res.timings
            print(f"{name:>11} {label:>12} {len(res.impacts):8d} {len(res.mechanisms):6d} {setup:8.3f} {first:10.3f} "
                  f"{second:10.3f} {tm['integration']:10.3f} {tm['transitions']:10.3f} "
                  f"{tm.get('thrust_check', 0.0):9.3f} {bare:16.3f}")


if __name__ == "__main__":
    np.seterr(all="ignore")
    main()
