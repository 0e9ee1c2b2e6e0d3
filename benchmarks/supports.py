"""Timing of ``fembeam supports``: the capacity under spreading of the default arch (embrace 157.5
deg, t/R = 0.15) on voussoirs and on rigid elements, and of a semicircle.  Prints the sizes, the
number of rows of the path, the migrations, the capacity and the wall and CPU times of each run
(one process, warm imports; the CPU time is the one to compare on a shared machine), and the
targets: the 24-voussoir arch spreading under 2 s, 200 elements under 10 s.
Run: ``python benchmarks/supports.py``."""
from __future__ import annotations

import time

from fembeam import CircularArch
from fembeam.analysis.supports import Movement, supports


def main() -> None:
    supports(CircularArch.from_ratio(157.5, 0.15), Movement.of("spread"), voussoirs=6)   # imports, HiGHS
    print(f"{'arch':>10} {'movement':>8} {'mesh':>14} {'rows':>5} {'migr':>5} {'capacity m':>11} "
          f"{'% span':>7} {'time s':>7} {'cpu s':>6}")
    targets = {("spread", "voussoirs", 24): 2.0, ("spread", "elements", 200): 10.0}
    worst: dict = {}
    for emb in (157.5, 180.0):
        arch = CircularArch.from_ratio(emb, 0.15)
        for kind in ("spread", "settle"):
            for kw in ({"voussoirs": 24}, {"elements": 200}, {"elements": 400}):
                t, c = time.perf_counter(), time.process_time()
                r = supports(arch, Movement.of(kind), **kw)
                dt, dc = time.perf_counter() - t, time.process_time() - c
                mesh = f"{next(iter(kw.values()))} {next(iter(kw))}"
                cap = "-" if r.capacity is None else f"{r.capacity:.6f}"
                pct = "-" if r.capacity is None else f"{100 * r.capacity_over_span:.3f}"
                print(f"{emb:>10g} {kind:>8} {mesh:>14} {len(r.path):>5} {len(r.migrations):>5} {cap:>11} "
                      f"{pct:>7} {dt:>7.2f} {dc:>6.2f}")
                key = (kind, *next(iter(kw.items())))
                if key in targets:
                    worst[key] = max(worst.get(key, 0.0), dt)
    for (kind, what, n), limit in targets.items():
        t = worst[kind, what, n]
        print(f"target: {n} {what}, {kind}: {t:.2f} s of wall time, under {limit:g} s: "
              f"{'yes' if t < limit else 'NO'}")


if __name__ == "__main__":
    main()
