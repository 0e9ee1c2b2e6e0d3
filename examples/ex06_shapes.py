"""Example 6: arch shapes.  Pointed arches of span 10 m and thickness 0.8 m, from the
semicircle (rise 5 m) to the equilateral arch (rise 8.66 m): A_L, r and the minimum
thickness; then a surveyed arch: 40 points of a parabola (span 10 m, rise 3 m) whose
crown has sagged by 5 cm, read from a CSV file, against the ideal parabola.
"""
import math
import pathlib
import tempfile

import numpy as np

from fembeam import analyze, minimum_thickness
from fembeam.geometry import ParabolicArch, PointedArch, SurveyedArch

SPAN, T, ELEMENTS = 10.0, 0.8, 60
RISES = (5.0, 6.0, 7.0, SPAN * math.sqrt(3) / 2)


def pointed_row(rise: float) -> tuple:
    arch = PointedArch(span=SPAN, rise=rise, thickness=T)
    res = analyze(arch, elements=ELEMENTS)
    t_min = minimum_thickness(arch, elements=ELEMENTS).scale * T
    return rise, res.A_L, res.r, t_min


def surveyed_parabola(sag: float = 0.05, points: int = 40) -> tuple:
    """The ideal parabola and the surveyed one (crown lowered by ``sag`` m, smoothly)."""
    x = np.linspace(-SPAN / 2, SPAN / 2, points)
    y = 3.0 * (1 - (2 * x / SPAN) ** 2) - sag * np.cos(math.pi * x / SPAN) ** 2
    path = pathlib.Path(tempfile.mkdtemp()) / "surveyed.csv"
    path.write_text("x,y\n" + "".join(f"{a:.6f},{b:.6f}\n" for a, b in zip(x, y)))
    ideal = ParabolicArch(span=SPAN, rise=3.0, thickness=0.6)
    surveyed = SurveyedArch.from_csv(path, thickness=0.6)
    return [(analyze(a, elements=ELEMENTS), minimum_thickness(a, elements=ELEMENTS).scale * 0.6)
            for a in (ideal, surveyed)]


rows = [pointed_row(h) for h in RISES]
survey = surveyed_parabola()

if __name__ == "__main__":
    print(f"pointed arches, span {SPAN:g} m, thickness {T:g} m ({ELEMENTS} elements):")
    for rise, A_L, r, t_min in rows:
        print(f"  rise {rise:5.2f} m: A_L = {A_L:.4f} g, r = {r:.4f}, t_min = {t_min:.4f} m")
    for name, (res, t_min) in zip(("ideal parabola", "surveyed (5 cm sag)"), survey):
        print(f"{name:>20}: A_L = {res.A_L:.4f} g, r = {res.r:.4f}, t_min = {t_min:.4f} m")
