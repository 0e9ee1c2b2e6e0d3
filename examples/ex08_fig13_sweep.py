"""
The paper's Fig. 13: r against the thickness
============================================

The restitution coefficient ``r_max`` of continuous circular arches against ``t/R`` for
six embrace angles, and the minimum-thickness envelope (each arch just above its minimum
thickness). Thick and shallow arches are arrested by the impact (``r = 0``); the
semicircle thinner than Milankovitch's ``t/R = 0.1075`` cannot stand.

This is ``fembeam sweep --embrace 80,100,120,140,160,180 --t-over-r 0.10:0.30:0.01
--plot ex08.png`` from Python: the table is the one the command prints (its long last
line folded). Each of the 126 cases is an independent ``analyze`` run; they run on the
available cores. Run as a script: ``python examples/ex08_fig13_sweep.py``.
"""
import textwrap

from fembeam.cli.sweep import table
from fembeam.studies import sweep
from fembeam.studies.sweep import FIG13_EMBRACE, FIG13_T_OVER_R, plot_sweep


def show(text: str) -> None:
    """Print ``text``; a line wider than this page (88 characters) goes on over the next
    lines, indented."""
    for line in text.splitlines():
        print(textwrap.fill(line, 88, subsequent_indent="    ", break_long_words=False,
                            break_on_hyphens=False) or line)


result = sweep(FIG13_EMBRACE, FIG13_T_OVER_R, progress=False)
show(table(result))

# %%
# The figure
# ----------
# One curve per embrace angle; the other outcomes are markers on ``r = 0``; diamonds
# mark the minimum-thickness envelope (dashed).
if __name__ == "__main__":
    plot_sweep(result, "ex08.png")
