"""Benchmark: the cost of an arch as built against the bare arch, and of a load scan.

1. For N = 10^2 .. 10^5 rigid elements of a 10 m semicircular arch (t/R = 0.15, 2000 kg/m^3)
   it times ``fembeam.analyze`` (assembly, limit analysis of the continuum, thrust range,
   impact QP on the banded active set) bare and with fill (1800 kg/m^3, road 0.5 m above the
   crown's extrados), the same with one live load (its load factor: a second limit analysis
   of the continuum on the same mesh and factorised statics), and the load factor alone (on
   its own mesh): the ratios to the bare analysis, the peak memory and the growth exponents
   fitted to log(time) against log(N).
2. A load scan over 100 positions on 24 voussoirs of the same filled arch: wall time.

    python benchmarks/asbuilt.py [--max 100000] [--repeat 3]
"""
from __future__ import annotations

import argparse
import resource
import time

import numpy as np

from fembeam import CircularArch
from fembeam.analysis.load_factor import load_factor
from fembeam.analysis.pipeline import analyze
from fembeam.geometry.asbuilt import build
from fembeam.studies.load_scan import load_scan


def peak_mb() -> float:
    return resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024.0


def best(f, repeat: int) -> float:
    out = []
    for _ in range(repeat):
        t0 = time.perf_counter()
        f()
        out.append(time.perf_counter() - t0)
    return min(out)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--max", type=int, default=100_000)
    ap.add_argument("--repeat", type=int, default=3)
    a = ap.parse_args()
    bare = CircularArch.from_ratio(180.0, 0.15, radius=5.0, density=2000.0)
    filled = build(bare, fill_density=1800.0, fill_depth=0.5)
    sizes = [n for n in (100, 1000, 10_000, 100_000) if n <= a.max]
    print(f"{'N':>7} {'bare [s]':>10} {'filled [s]':>11} {'ratio':>6} {'+ 1 load [s]':>13} {'ratio':>6} "
          f"{'alone [s]':>10} {'peak MB':>8}")
    rows = []
    for n in sizes:
        tb = best(lambda: analyze(bare, elements=n, backend="active-set"), a.repeat)
        tf = best(lambda: analyze(filled, elements=n, backend="active-set"), a.repeat)
        tfl = best(lambda: analyze(filled, elements=n, backend="active-set", loads=[(2.5, 100.0)]), a.repeat)
        tl = best(lambda: load_factor(filled, [(2.5, 100.0)], elements=n), a.repeat)
        rows.append((n, tb, tf, tfl, tl))
        print(f"{n:7d} {tb:10.3f} {tf:11.3f} {tf / tb:6.2f} {tfl:13.3f} {tfl / tb:6.2f} {tl:10.3f} {peak_mb():8.0f}",
              flush=True)
    if len(rows) >= 2:
        N = np.log([r[0] for r in rows])
        for j, name in ((1, "bare"), (2, "filled"), (3, "filled with one load"), (4, "load factor alone")):
            k = np.polyfit(N, np.log([r[j] for r in rows]), 1)[0]
            print(f"growth exponent ({name}): {k:.2f}")
    t = best(lambda: load_scan(filled, 100.0, positions=100, voussoirs=24), a.repeat)
    print(f"load scan: 100 positions on 24 voussoirs: {t:.3f} s (best of {a.repeat})")


if __name__ == "__main__":
    main()
