"""Benchmark of ``fembeam spectrum``: the overturning spectrum of docs/dynamics.md (7-voussoir
paper arch, beta = 157.5 deg, t/R = 0.15, R = 1 m; one-sine pulses of periods 0.1 to 2.05 s,
40 periods, default amplitude grid), one task per period on local worker processes.

    python benchmarks/spectrum.py [--workers 2] [--periods 0.1:2.05:0.05]

Prints the wall time, the CPU time spent in the cases and the number of time histories.
"""
from __future__ import annotations

import argparse
import time

import numpy as np

from fembeam import CircularArch
from fembeam.studies.spectrum import spectrum


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--workers", type=int, default=2)
    ap.add_argument("--periods", default="0.1:2.05:0.05", help="start:stop:step (s), stop included")
    args = ap.parse_args()
    a, b, s = (float(x) for x in args.periods.split(":"))
    periods = [round(p, 10) for p in np.arange(a, b + 0.5 * s, s)]
    arch = CircularArch.from_ratio(157.5, 0.15)
    clock = time.perf_counter()
    res = spectrum(arch, "sine", periods, voussoirs=7, workers=args.workers, progress=False)
    wall = time.perf_counter() - clock
    cpu = sum(r["time_s"] for r in res.rows)
    runs = sum(r["runs"] for r in res.rows)
    print(f"spectrum benchmark: 7 voussoirs, beta = 157.5 deg, t/R = 0.15, sine pulses, {len(periods)} periods "
          f"{periods[0]:g} to {periods[-1]:g} s, {len(res.amplitudes)} amplitudes, {args.workers} workers")
    print(f"  {runs} time histories; wall time {wall:.1f} s, CPU in cases {cpu:.1f} s "
          f"({1e3 * cpu / max(runs, 1):.1f} ms per run)")


if __name__ == "__main__":
    main()
