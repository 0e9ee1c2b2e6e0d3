#!/usr/bin/env bash
# Regenerate every committed figure and table of docs/ from the commands that produce them;
# the list, file by file, is in docs/studies.md ("Regenerating the committed figures").
# tests/test_docs_figures.py re-runs a cheap subset and compares it with what is committed.
# About 20 minutes on 2 cores.  Run from anywhere with fembeam installed.
#
#   docs/regenerate.sh              everything
#   docs/regenerate.sh studies      one group: studies | report | benchmarks | dynamics | fragility | shapes | simulation | pictures | splice
#
# After a run, read the diff: the prose of docs/studies.md, docs/elements.md and docs/solvers.md
# quotes numbers of these tables (the drift test names any quote that no longer matches).
set -euo pipefail
cd "$(dirname "$0")/.."
what="${1:-all}"

studies() {
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
}

report() {
    fembeam report --out-dir docs/report
}

benchmarks() {
    python benchmarks/elements.py > docs/data/elements.txt
    python benchmarks/qp_backends.py > docs/data/qp_backends.txt
    python benchmarks/limit_scaling.py --max 1000000 --analyze 100000 --kinematic 10000 > docs/data/limit_scaling.txt
    python benchmarks/rocking.py > docs/data/rocking_benchmark.txt
    python benchmarks/spectrum.py > docs/data/spectrum_benchmark.txt
    python benchmarks/startup.py > docs/data/startup_benchmark.txt
    python benchmarks/pipeline_scaling.py --max 1000000 --analyze 100000 > docs/data/pipeline_benchmark.txt
    fembeam sweep --quiet | tail -2 > docs/data/sweep_benchmark.txt
    python benchmarks/simulate.py > docs/data/simulate_benchmark.txt
    python benchmarks/fragility.py --model rock,simulate,auto --workers 2 > docs/data/fragility_benchmark.txt
    python benchmarks/fragility.py --model rock,simulate,auto --workers 1,2 --records 10 > docs/data/fragility_speedup.txt
}

simulation() {
    (cd docs/figures && python ../../examples/ex09_rock_vs_simulate.py)
    python docs/compare_rock_simulate.py
}

dynamics() {
    fembeam spectrum --voussoirs 7 --embrace 157.5 --t-over-r 0.15 --pulse sine --periods 0.1:2.05:0.05 \
        --workers 2 --quiet --csv docs/data/spectrum_sine_7v.csv --plot docs/img/spectrum_sine_7v.png \
        > docs/data/spectrum_sine_7v.txt
}

fragility() {
    # needs fembeam[suites]; about 16 min on 2 busy cores (docs/fragility.md)
    fembeam fragility --voussoirs 7 --radius 5 --suite fema-p695-far-field --design 0.5 --workers 2 --quiet \
        --csv docs/data/fragility_far_field.csv --plot docs/img/fragility_far_field.png \
        --ida-plot docs/img/ida_far_field.png > docs/data/fragility_far_field.txt
}

shapes() {
    # convergence of A_L, r and t_min for one pointed, one elliptical and one parabolic arch
    for spec in "pointed 7 0.8" "elliptical 3 0.8" "parabolic 3 0.6"; do
        set -- $spec
        arch="--shape $1 --span 10 --rise $2 --thickness $3"
        fembeam convergence $arch --tmin --elements 25,50,100,200,400,800 --quiet \
            --csv docs/data/shapes_$1.csv --plot docs/img/shapes_convergence_$1.png > docs/data/shapes_$1.txt
        fembeam convergence $arch --tmin --voussoirs 8,16,32,64,128 --reference-elements 800 --quiet \
            --csv docs/data/shapes_$1_voussoirs.csv > docs/data/shapes_$1_voussoirs.txt
        fembeam analyze $arch --figure docs/img/shape_$1.png > docs/data/shapes_$1_analyze.txt
        fembeam min-thickness $arch > docs/data/shapes_$1_min_thickness.txt
    done
}

pictures() {
    python - <<'PY'
from fembeam import CircularArch, analyze
from fembeam.output.plotting import plot_paper_figure
from fembeam.output.render import render_png

paper = analyze(CircularArch.from_ratio(157.5, 0.15))            # fembeam analyze (defaults)
render_png(paper, "docs/img/paper_arch_render.png", size=(900, 506))
plot_paper_figure(paper, "docs/img/paper_arch_figure.png", dpi=120)
oppenheim = analyze(CircularArch.from_ratio(150.0, 0.15), voussoirs=7)
plot_paper_figure(oppenheim, "docs/img/oppenheim_150_figure.png", dpi=120)
PY
    python -m fembeam.output.plot_four_hinge docs/img/four_hinge_zone.png
}

splice() {
    # paste the transcripts in docs/data/*.txt into the Markdown that shows them, their long
    # lines folded to the site's 88 characters (docs/transcript.py)
    python - <<'PY'
import pathlib
import re
import sys

sys.path.insert(0, "docs")
from transcript import fold  # noqa: E402

data = pathlib.Path("docs/data")


def replace_block(md_path, opening, new_text, fence):
    """Replace the fenced block of md_path whose first line is `opening` (a transcript's
    header line, fixed by the command's arguments) by new_text, both folded."""
    first, new_text = fold(opening).splitlines()[0], fold(new_text)
    md = pathlib.Path(md_path)
    text = md.read_text()
    pattern = re.compile(re.escape(fence) + r"\n(?:" + re.escape(first) + "|" + re.escape(opening)
                         + r")\n.*?```", re.S)
    text, n = pattern.subn(lambda _: fence + "\n" + new_text + "```", text, count=1)
    if n != 1:
        raise SystemExit(f"{md_path}: no block starting with {opening!r}")
    md.write_text(text)


for name in ("convergence_157.5_0.15", "convergence_voussoirs_157.5_0.15", "sweep_fig13"):
    new = (data / f"{name}.txt").read_text()
    replace_block("docs/studies.md", new.splitlines()[0], new, "```text")
for shape in ("pointed", "elliptical", "parabolic"):
    for name in (f"shapes_{shape}", f"shapes_{shape}_voussoirs", f"shapes_{shape}_min_thickness"):
        new = (data / f"{name}.txt").read_text()
        replace_block("docs/shapes.md", new.splitlines()[0], new, "```text")
for md_path, name in (("docs/elements.md", "elements"), ("docs/solvers.md", "qp_backends")):
    new = (data / f"{name}.txt").read_text()
    replace_block(md_path, new.splitlines()[0], new, "```")
PY
}

case "$what" in
    all) studies; report; benchmarks; dynamics; fragility; shapes; simulation; pictures; splice ;;
    studies|report|benchmarks|dynamics|fragility|shapes|simulation|pictures|splice) "$what" ;;
    *) echo "usage: $0 [all|studies|report|benchmarks|dynamics|fragility|shapes|simulation|pictures|splice]" >&2; exit 2 ;;
esac
