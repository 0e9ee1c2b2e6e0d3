"""
A pointed arch's minimum thickness, and a surveyed arch
=======================================================

Pointed arches of span 10 m and thickness 0.8 m, from the semicircle (rise 5 m) to the
equilateral arch (rise 8.66 m): the incipient rocking acceleration ``A_L``, the
restitution coefficient ``r`` and the minimum thickness ``t_min`` (the smallest
thickness, scaling the given one, at which a thrust line fits inside the arch under its
own weight). Then a surveyed arch: 40 points of a parabola (span 10 m, rise 3 m) whose
crown has sagged by 5 cm, read from a CSV file, against the ideal parabola.

Run as a script: ``python examples/ex06_shapes.py``.
"""
import math
import pathlib
import tempfile

import numpy as np

from fembeam import analyze, minimum_thickness
from fembeam.geometry import ParabolicArch, PointedArch, SurveyedArch

SPAN, T, ELEMENTS = 10.0, 0.8, 60
RISES = (5.0, 6.0, 7.0, SPAN * math.sqrt(3) / 2)


# %%
# Pointed arches
# --------------
# ``minimum_thickness`` bisects on the factor of the thickness with a margin LP at each
# step, every section checked (``fembeam min-thickness --shape pointed ...``). The
# semicircle's ``t_min`` is Milankovitch's ``0.1075 R``; the pointed arches need less.
def pointed_row(rise: float) -> tuple:
    arch = PointedArch(span=SPAN, rise=rise, thickness=T)
    res = analyze(arch, elements=ELEMENTS)
    t_min = minimum_thickness(arch, elements=ELEMENTS).scale * T
    return rise, res.A_L, res.r, t_min


rows = [pointed_row(h) for h in RISES]
print(f"pointed arches, span {SPAN:g} m, thickness {T:g} m ({ELEMENTS} elements):")
for rise, A_L, r, t_min in rows:
    print(f"  rise {rise:5.2f} m: A_L = {A_L:.4f} g, r = {r:.4f}, "
          f"t_min = {t_min:.4f} m")

# %%
# The equilateral arch just above its minimum thickness (2 % thicker): the thrust line
# touches the edges at the hinges of the collapse mechanism, and the arch starts to rock
# at almost no acceleration.
if __name__ == "__main__":
    from fembeam.output.plotting import plot_paper_figure

    equilateral = PointedArch(span=SPAN, rise=RISES[-1], thickness=1.02 * rows[-1][3])
    plot_paper_figure(analyze(equilateral, elements=ELEMENTS), "ex06_pointed.png",
                      dpi=100)


# %%
# A surveyed arch
# ---------------
# A surveyed mid-curve is read from a CSV file (columns ``x,y`` and optionally ``t``, in
# m) and interpolated by a spline (``fembeam analyze --midcurve points.csv``). A sag of
# 5 cm at the crown, under 2 % of the rise, changes every answer: here it raises ``A_L``
# and lowers the minimum thickness.
def surveyed_parabola(sag: float = 0.05, points: int = 40) -> tuple:
    """The ideal parabola and the surveyed one (crown lowered smoothly by ``sag`` m)."""
    x = np.linspace(-SPAN / 2, SPAN / 2, points)
    y = 3.0 * (1 - (2 * x / SPAN) ** 2) - sag * np.cos(math.pi * x / SPAN) ** 2
    path = pathlib.Path(tempfile.mkdtemp()) / "surveyed.csv"
    path.write_text("x,y\n" + "".join(f"{a:.6f},{b:.6f}\n" for a, b in zip(x, y)))
    ideal = ParabolicArch(span=SPAN, rise=3.0, thickness=0.6)
    surveyed = SurveyedArch.from_csv(path, thickness=0.6)
    return [(analyze(a, elements=ELEMENTS),
             minimum_thickness(a, elements=ELEMENTS).scale * 0.6)
            for a in (ideal, surveyed)]


survey = surveyed_parabola()
for name, (res, t_min) in zip(("ideal parabola", "surveyed (5 cm sag)"), survey):
    print(f"{name:>20}: A_L = {res.A_L:.4f} g, r = {res.r:.4f}, t_min = {t_min:.4f} m")
