"""Benchmark of the start-up cost: wall time of fresh processes (best of ``--repeat``).

    python benchmarks/startup.py [--repeat 5]

Prints, per command line: the best and median wall time, and for the default ``analyze`` the
part spent in imports (``python -X importtime``: cumulative time of the ``fembeam`` import).
"""
from __future__ import annotations

import argparse
import re
import statistics
import subprocess
import sys
import time

CASES = [("python -c 'import fembeam'", [sys.executable, "-c", "import fembeam"]),
         ("fembeam --help", [sys.executable, "-m", "fembeam", "--help"]),
         ("fembeam analyze --help", [sys.executable, "-m", "fembeam", "analyze", "--help"]),
         ("fembeam analyze", [sys.executable, "-m", "fembeam", "analyze"]),
         ("fembeam rock --help", [sys.executable, "-m", "fembeam", "rock", "--help"])]


def wall(cmd: list[str]) -> float:
    t0 = time.perf_counter()
    subprocess.run(cmd, check=True, capture_output=True)
    return time.perf_counter() - t0


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--repeat", type=int, default=5)
    args = ap.parse_args()
    print(f"start-up benchmark: wall time of a fresh process, best and median of {args.repeat}")
    print(f"{'command':>26} {'best s':>8} {'median s':>9}")
    for label, cmd in CASES:
        t = [wall(cmd) for _ in range(args.repeat)]
        print(f"{label:>26} {min(t):8.3f} {statistics.median(t):9.3f}")
    err = subprocess.run([sys.executable, "-X", "importtime", "-c",
                          "from fembeam.cli.main import main; import fembeam.cli.analyze"],
                         capture_output=True, text=True).stderr
    total = max(int(m.group(1)) for m in re.finditer(r"\|\s+(\d+) \|\s+fembeam\.cli\.analyze$", err, re.M))
    print(f"imports of 'fembeam analyze' (python -X importtime, cumulative): {total / 1e6:.3f} s")


if __name__ == "__main__":
    main()
