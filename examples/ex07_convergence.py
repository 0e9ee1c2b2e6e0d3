"""
Convergence of r with the mesh
==============================

The paper's arch (``beta = 157.5`` deg, ``t/R = 0.15``) on meshes of 50 to 1600 rigid
elements, then as discrete arches of 7 to 255 voussoirs. The incipient rocking
acceleration ``A_L`` of the continuous arch does not depend on the mesh (its hinges are
placed on the continuum, between the joints); the restitution coefficient ``r``
converges at the rate ``h^2`` of the element length ``h``; the voussoir arches converge
to the continuous one.

This is ``fembeam convergence --embrace 157.5 --t-over-r 0.15 --elements 50,...,1600``
from Python: the tables below are those the command prints, their long lines folded to
the width of this page. Run as a script: ``python examples/ex07_convergence.py`` (writes
``ex07.png`` and ``ex07_voussoirs.png``).
"""
import textwrap

from fembeam import CircularArch
from fembeam.cli.convergence import table
from fembeam.studies import convergence_study
from fembeam.studies.convergence import plot_convergence


def show(text: str) -> None:
    """Print ``text``; a line wider than this page (88 characters) goes on over the next
    lines, indented."""
    for line in text.splitlines():
        print(textwrap.fill(line, 88, subsequent_indent="    ", break_long_words=False,
                            break_on_hyphens=False) or line)


arch = CircularArch.from_ratio(157.5, 0.15)

# %%
# The continuous arch
# -------------------
# Errors are measured against the Richardson extrapolation of the two finest meshes with
# the assumed order 2; the order fitted to all the meshes is printed beside it
# (``fitted p``).
study = convergence_study(arch, elements=[50, 100, 200, 400, 800, 1600], progress=False)
show(table(study))
r_rate = study.quantities["r"]["rate"]

if __name__ == "__main__":
    plot_convergence(study, "ex07.png")

# %%
# Voussoir arches converging to the continuous arch
# -------------------------------------------------
# Hinges of a voussoir arch can open only at its joints, so its ``A_L`` is higher and
# its hinges sit on joints; the errors are against the continuous arch on 1600 elements.
voussoirs = convergence_study(arch, voussoirs=[7, 15, 31, 63, 127, 255],
                              reference_elements=1600, progress=False)
show(table(voussoirs))

if __name__ == "__main__":
    plot_convergence(voussoirs, "ex07_voussoirs.png")
