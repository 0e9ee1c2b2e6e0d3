#!/usr/bin/env bash
# Regenerate every committed figure and table of docs/ from the commands that produce them
# (tests/test_docs_figures.py checks a cheap subset against a fresh run).  About 10 minutes
# on 2 cores.  Run from the repository root with fembeam installed.
set -euo pipefail
cd "$(dirname "$0")/.."
fembeam convergence --embrace 157.5 --t-over-r 0.15 --elements 50,100,200,400,800,1600 \
    --csv docs/data/convergence_157.5_0.15.csv --plot docs/img/convergence_157.5_0.15.png \
    > docs/data/convergence_157.5_0.15.txt
fembeam convergence --embrace 157.5 --t-over-r 0.15 --voussoirs 7,15,31,63,127,255 \
    --csv docs/data/convergence_voussoirs_157.5_0.15.csv --plot docs/img/convergence_voussoirs_157.5_0.15.png \
    > docs/data/convergence_voussoirs_157.5_0.15.txt
fembeam sweep --embrace 80,100,120,140,160,180 --t-over-r 0.10:0.30:0.01 \
    --plot docs/img/sweep_fig13.png --csv docs/data/sweep_fig13.csv > docs/data/sweep_fig13.txt
fembeam sweep --embrace 80,100,120,140,160,180 --t-over-r 0.005:0.30:0.005 --envelope-embrace 60:180:5 \
    --plot docs/img/sweep_fig13_full.png --csv docs/data/sweep_fig13_full.csv > docs/data/sweep_fig13_full.txt
fembeam report --out-dir docs/report
python benchmarks/limit_scaling.py --max 1000000 --analyze 100000 --kinematic 10000 > docs/data/limit_scaling.txt
