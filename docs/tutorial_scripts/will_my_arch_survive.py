"""
Will my arch survive?
=====================

A stone arch has been surveyed: 21 points of its mid-curve, from springing to springing, with
the thickness at each point, and its 13 voussoirs counted. The question is whether it survives
the ground motion the site must withstand, and by what margin. This tutorial answers it with
fembeam's Python API, one step at a time:

1. **the survey**, as a CSV file, read into an arch;
2. **the static answers**: the acceleration at which the arch starts to rock, the mechanism,
   what an impact keeps of the motion, and the geometric factor of safety;
3. **the dynamic verdict**: the whole motion under the design ground motion, along one
   mechanism (:func:`~fembeam.dynamics.rock`) and with the voussoirs as rigid bodies in
   contact (:func:`~fembeam.simulation.simulate`);
4. **the margin**: the smallest scale factor of the record that overturns the arch
   (:func:`~fembeam.studies.collapse.collapse_scale`), by both models;
5. **the verdict** in one table;
6. **the record**: the JSON of every answer and the ParaView files of the arch and of its
   motion;
7. **a settlement of the right support**: how far it may settle before the arch collapses,
   the thrust on the supports on the way, and the hinges
   (:func:`~fembeam.analysis.supports.supports`).

The last section gives the same steps as commands. Every output below was printed by the code
above it when this page was built. The script runs as it is (``python will_my_arch_survive.py``,
with fembeam installed) and writes its files into the current directory. Units: lengths in m,
accelerations in g, angles in degrees from the left springing, rotations in rad, times in s
(:ref:`units-and-conventions`).
"""

# %%
# 1. The survey
# -------------
# The mid-curve is given by points ``x, y`` (m) from the left springing to the right one, in
# any coordinate system (here the survey's grid: fembeam places the arch with the midpoint of
# its springings at the origin), and the thickness ``t`` (m) at each point. fembeam
# interpolates them with a spline (quintic from 12 points on), so the points need not be evenly
# spaced; the curve it builds must not loop or fold back. The density of the masonry is
# 2000 kg/m^3 unless ``density=`` is given.
import json
import pathlib
import textwrap

import matplotlib.pyplot as plt

from fembeam import SurveyedArch, analyze, minimum_thickness
from fembeam.dynamics import GroundMotion, rock
from fembeam.simulation import simulate

pathlib.Path("survey.csv").write_text("""\
x,y,t
409.042,57.300,0.500
409.142,57.702,0.499
409.297,58.084,0.495
409.505,58.441,0.490
409.762,58.765,0.483
410.063,59.050,0.475
410.402,59.292,0.467
410.773,59.486,0.460
411.168,59.629,0.455
411.580,59.717,0.451
412.000,59.749,0.450
412.420,59.724,0.451
412.832,59.643,0.455
413.227,59.506,0.460
413.598,59.315,0.467
413.937,59.074,0.475
414.238,58.787,0.483
414.495,58.460,0.490
414.703,58.098,0.495
414.858,57.709,0.499
414.958,57.300,0.500
""")
arch = SurveyedArch.from_csv("survey.csv")
VOUSSOIRS = 13
RECORD = pathlib.Path("record")          # the JSON and ParaView files of the answers
RECORD.mkdir(exist_ok=True)


def save(name: str, d: dict) -> None:
    """Write one answer (``to_dict()``) to the record as JSON."""
    (RECORD / name).write_text(json.dumps(d, indent=1, allow_nan=False))


def hinges(hs) -> str:
    """The hinges' angles (deg from the left springing) and sides, indented, wrapped."""
    return textwrap.fill(", ".join(f"{h.angle_deg:.2f} {h.side}" for h in hs), 86,
                         initial_indent="  ", subsequent_indent="  ")


# %%
# 2. The static answers
# ---------------------
# :func:`~fembeam.analyze` solves the limit analysis: ``A_L`` is the horizontal ground
# acceleration (in g) at which the arch starts to rock, on the four-hinge mechanism printed
# (angles along the arch from the left springing, each hinge on the edge it pivots on); a
# thrust line inside the arch is the certificate that it stands below ``A_L``. Then the
# impact: ``r = K'/K`` is the fraction of its kinetic energy the arch keeps when it swings back
# through its shape at rest. Both results check themselves and raise an error rather than
# return a number that fails a check. The arch is not symmetric, so the ground pulse from left
# to right (``direction=-1``) has its own ``A_L``.
static = analyze(arch, voussoirs=VOUSSOIRS)
mirror = analyze(arch, voussoirs=VOUSSOIRS, direction=-1)
print(f"A_L = {static.A_L:.4f} g (direction +1), {mirror.A_L:.4f} g (direction -1)")
print(f"r = K'/K = {static.r:.4f}")
print("hinges before the impact (deg, side):", hinges(static.hinges_before), sep="\n")
print("hinges after the impact:", hinges(static.hinges_after), sep="\n")
save("analyze.json", static.to_dict())

# %%
# The thrust line at the onset and the impulse line of the impact, drawn on the arch:
# the hinges before the impact as rings, after it as dots.
from fembeam.output.plotting import plot_paper_figure  # noqa: E402

plot_paper_figure(static, "arch.png", dpi=100)

# %%
# How much thinner could the arch be and still stand under its own weight?
# :func:`~fembeam.minimum_thickness` scales the surveyed thickness until no thrust line fits;
# the inverse of that factor is the geometric factor of safety (Heyman's).
thin = minimum_thickness(arch, voussoirs=VOUSSOIRS)
print(f"minimum thickness: {thin.scale:.4f} x the surveyed one")
print(f"geometric factor of safety: {1 / thin.scale:.3f}")
save("min_thickness.json", thin.to_dict())

# %%
# 3. The dynamic verdict
# ----------------------
# The design ground motion here is the 1940 El Centro record shipped with fembeam, scaled to a
# peak ground acceleration of 0.5 g (the site's own record: ``GroundMotion.record(path)``, a
# PEER ``.AT2`` file or a two-column CSV of time in s and acceleration in g).
# :func:`~fembeam.dynamics.rock` follows the arch from rest through the onset, the rocking
# along one mechanism, every impact, to rest or overturning; it also says when the dynamic
# thrust line first leaves the section (from then on other hinges would open and the
# one-mechanism motion is a model, not a proof) and whether the joints would need more
# friction than ``friction=`` gives.
DESIGN_PGA = 0.5
ground = GroundMotion.record("elcentro").to_pga(DESIGN_PGA)
motion = rock(arch, ground, voussoirs=VOUSSOIRS, friction=0.6)
demand = motion.friction_demand
print(f"outcome: {motion.outcome}")
print(f"peak rotation: {motion.peak_rotation:.4g} rad at t = {motion.t_peak:.3f} s")
print(f"impacts: {len(motion.impacts)}")
exits = motion.thrust_line_exits_at
print("thrust line leaves the section:",
      "never" if exits is None else f"t = {exits:.3f} s")
print(f"friction demand: {demand['max_ratio']:.3f} "
      f"(sliding risk: {demand['sliding_risk']})")
save("rock.json", motion.to_dict())

# %%
# The history of the motion: the ground acceleration, the rotation of the mechanism with its
# impacts, and the energies (J per metre of barrel width), from the onset of rocking to the
# time the arch is at rest again, titled by what happened.
from fembeam.output.motion import history_figure  # noqa: E402

fig = history_figure(motion)
t0 = min(t for t, _ in motion.onsets) if motion.onsets else 0.0
last_impact = motion.impacts[-1].t if motion.impacts else t0
t1 = motion.t_overturn or motion.settled_at or last_impact
for ax in fig.axes:
    ax.set_xlim(max(t0 - 0.5, 0.0), t1 + 0.5)
if motion.t_overturn is not None:
    event = f"overturns at t = {motion.t_overturn:.2f} s"
else:
    event = f"rocks from {t0:.2f} s to {t1:.2f} s, {len(motion.impacts)} impacts"
fig.suptitle(f"El Centro 1940 at {DESIGN_PGA:g} g: the arch {event}")
fig.savefig("rock.png", dpi=100, bbox_inches="tight")
plt.close(fig)

# %%
# :func:`~fembeam.simulation.simulate` moves the 13 voussoirs as rigid bodies in contact
# (Moreau-Jean time steps): hinges open and close at any joint, as many as the motion asks
# for. It is the check of ``rock`` once the thrust line has left the section. The joints do
# not slide unless ``friction=`` is given; with ``friction=0.6`` they obey Coulomb's law and
# may slide.
sim = simulate(arch, ground, voussoirs=VOUSSOIRS)
print(f"outcome: {sim.outcome}, peak rotation {sim.peak_rotation:.4g} rad "
      f"at t = {sim.t_peak:.3f} s, at most {sim.max_hinges} hinges open")
slide = simulate(arch, ground, voussoirs=VOUSSOIRS, friction=0.6)
print(f"with friction 0.6: {slide.outcome}, "
      f"peak rotation {slide.peak_rotation:.4g} rad, "
      f"largest slip {slide.max_slip * 1e3:.2f} mm")
save("simulate.json", sim.to_dict())
save("simulate_friction.json", slide.to_dict())

# %%
# 4. The margin
# -------------
# By what factor may the record grow before the arch overturns?
# :func:`~fembeam.studies.collapse.collapse_scale` runs the record at 40 scale factors, from
# the one at which it first moves the arch to 20 times that, bisects below the first one that
# overturns it, and lists the scanned factors above it that do not (the set of safe factors
# need not be an interval). ``model="simulate"`` does the same with the voussoirs as rigid
# bodies.
from fembeam.studies.collapse import collapse_scale  # noqa: E402

elcentro = GroundMotion.record("elcentro")
margins = {}
for model in ("rock", "simulate"):
    margins[model] = collapse_scale(arch, elcentro, voussoirs=VOUSSOIRS, model=model)
    m = margins[model]
    above = ", ".join(f"{f:.3g}" for f in m["safe_factors_above"]) or "none"
    print(f"{model}: first collapse at factor {m['first_collapse']:.4g}, "
          f"PGA {m['pga_at_first_collapse']:.3f} g; safe above it: {above}")
    save(f"collapse_scale_{model}.json", m)

# %%
# 5. The verdict
# --------------
# The answers of steps 2 to 4 in one table. The margin is the smaller of the two models' peak
# ground accelerations at the first overturning, over the design one.
governing = min(margins, key=lambda m: margins[m]["pga_at_first_collapse"])
rows = [
    ("incipient rocking acceleration A_L",
     f"{static.A_L:.4f} g (+x), {mirror.A_L:.4f} g (-x)"),
    ("geometric factor of safety", f"{1 / thin.scale:.3f}"),
    (f"El Centro at {DESIGN_PGA:g} g, rock",
     f"{motion.outcome}, peak rotation {motion.peak_rotation:.4g} rad"),
    (f"El Centro at {DESIGN_PGA:g} g, simulate",
     f"{sim.outcome}, peak rotation {sim.peak_rotation:.4g} rad"),
    (f"El Centro at {DESIGN_PGA:g} g, simulate, mu = 0.6",
     f"{slide.outcome}, largest slip {slide.max_slip * 1e3:.2f} mm"),
]
rows += [(f"PGA that first overturns it, {m}",
          f"{margins[m]['pga_at_first_collapse']:.3f} g") for m in margins]
rows.append(("margin on the design PGA",
             f"{margins[governing]['pga_at_first_collapse'] / DESIGN_PGA:.2f} "
             f"({governing} governs)"))
width = max(len(a) for a, _ in rows)
for a, b in rows:
    print(f"{a:<{width}}  {b}")

# %%
# 6. The record
# -------------
# The JSON of every answer above is in ``record/``. The ParaView files of the arch:
# :func:`~fembeam.output.export.write_vtk` writes the body with the mechanisms' velocity
# fields, the joints with the impulses, the thrust and impulse lines and the hinges, each a
# ``.vtu`` file, and ``arch.vtm`` that opens them together; the motion of step 3 is
# ``motion.pvd`` (:func:`~fembeam.output.motion.write_pvd`), a time series of one ``.vtu``
# per frame: open it in ParaView (File > Open) and play it; colour by ``piece`` to see the
# rigid pieces.
from fembeam.output.export import write_vtk  # noqa: E402
from fembeam.output.motion import write_pvd  # noqa: E402

write_vtk(static, RECORD / "arch.vtu")
write_pvd(motion, RECORD / "motion.pvd")
files = sorted(p.relative_to(RECORD).as_posix()
               for p in RECORD.rglob("*") if p.is_file())
frames = [f for f in files if f.startswith("motion_")]
print(f"{len(files)} files in {RECORD}/:")
print("\n".join(f"  {f}" for f in files if not f.startswith("motion_")))
print(f"  {frames[0]} ... {frames[-1]} ({len(frames)} frames of motion.pvd)")

# %%
# 7. A settlement of the right support
# ------------------------------------
# Abutments move too. :func:`~fembeam.analysis.supports.supports` follows the arch while its
# right support settles, with finite displacements, quasi-statically, from rest to collapse:
# the voussoirs rigid, the joints neither sliding nor crushing nor carrying tension
# (:doc:`/supports`). It reports the hinges that form at the start, every hinge migration,
# the thrust on the supports against the settlement (``H``, and ``V`` on each support, in
# kN per metre of barrel width) and the settlement at which the arch collapses: the
# **capacity**.
import numpy as np  # noqa: E402

from fembeam.analysis.supports import Movement, supports  # noqa: E402
from fembeam.output.supports import plot_supports  # noqa: E402

settle = supports(arch, Movement.of("settle"), voussoirs=VOUSSOIRS)
print(f"capacity: {settle.capacity:.4f} m of settlement, "
      f"{100 * settle.capacity_over_span:.2f} % of the span ({settle.span:.3f} m)")
print("hinges at the start (deg, side):")
print("\n".join(f"  joint {h['joint']}: {h['angle_deg']:.2f} {h['side']}"
                for h in settle.hinges))
print(f"hinge migrations: {len(settle.migrations)}")
last = settle.last_edge
print(f"edge reached last: joint {last['joint']},",
      f"{last['angle_deg']:.2f} {last['side']}")
path = np.array(settle.path)          # rows: settlement (m), H, V left, V right (kN/m)
print(f"{'settlement m':>12} {'H kN/m':>8} {'V left':>8} {'V right':>8}")
for d in np.linspace(0.0, settle.capacity, 5):
    H, Vl, Vr = (np.interp(d, path[:, 0], path[:, k]) for k in (1, 2, 3))
    print(f"{d:12.4f} {H:8.3f} {Vl:8.3f} {Vr:8.3f}")

# %%
# The arch at rest and at collapse with their lines of thrust (the hinges as dots), and the
# thrust on the supports against the settlement.
plot_supports(settle, "settle.png", dpi=100)

# %%
# The arch stands until its right support has settled by 1.866 m, 31.55 % of its span. On its
# 13 voussoirs the three hinges that form at the start (25.27 deg on the intrados, 85.66 deg
# on the extrados, the right springing on the extrados) stay where they are, and the arch
# collapses when the line of thrust reaches the extrados at the left springing: a fourth
# hinge, on which gravity does positive work with the supports held. On the way the thrust
# rises from 18.04 to 21.56 kN/m and the load passes from the left support to the settling
# one (``V`` right from 36.78 to 48.30 kN/m). The capacity belongs to the voussoirs as
# counted: on the continuous arch (``elements=200``: hinges anywhere) the hinge near the
# crown rolls back from 89.77 to 83.61 deg in 8 steps and the arch collapses at 1.669 m
# (28.22 % of the span). The joints are assumed not to slide. The voussoirs as rigid bodies
# in contact (``fembeam simulate --support-motion settle --support-rate 0.01``, the right
# support settling at 1 cm/s) collapse at 1.886 m, 1.0 % later, with the same thrust on the
# way (``--thrust-plot``).
#
# The same on the command line (``--json`` prints ``settle.to_dict()``):
#
# .. code-block:: console
#
#    $ fembeam supports --midcurve survey.csv --voussoirs 13 --settle --plot settle.png
#    fembeam supports: surveyed arch (21 points, quintic spline), span 5.916 m, rise 2.44911
#        m, thickness 0.45-0.5 m (t column)
#      13 voussoirs, span 5.916 m; movement: settlement of the right support
#      at rest: H = 18.043 kN/m, V left 41.0646 kN/m, V right 36.7772 kN/m
#      hinges at the start: joint 2 (25.27 deg, intrados), joint 7 (85.66 deg, extrados),
#          joint 13 (160.36 deg, extrados)
#      CAPACITY: 1.86623 m = 31.55 % of the span
#      edge reached last: joint 0 (0.00 deg, extrados)
#      collapse: a hinge formed at joint 0 (extrados, 0.00 deg): with the supports held the
#          pieces form a mechanism on which gravity does positive work
#      at collapse: H = 21.5589 kN/m, V left 29.5461 kN/m, V right 48.2956 kN/m
#      wrote figure: settle.png

# %%
# The same on the command line
# ----------------------------
# Every step above is one ``fembeam`` command (``--json`` prints the JSON saved above, and
# ``fembeam COMMAND --help`` lists the options). ``fembeam report`` adds the verification
# report of the fembeam that answered: its checks against exact solutions and the paper's
# published values, as Markdown and JSON.
#
# .. code-block:: bash
#
#    ARCH="--midcurve survey.csv --voussoirs 13"
#    fembeam analyze $ARCH --figure arch.png --vtk record/arch.vtu
#    fembeam analyze $ARCH --direction -1
#    fembeam min-thickness $ARCH
#    fembeam rock $ARCH --record elcentro --pga 0.5 --friction 0.6 \
#        --plot rock.png --vtk record/motion.pvd
#    fembeam simulate $ARCH --record elcentro --pga 0.5
#    fembeam simulate $ARCH --record elcentro --pga 0.5 --friction 0.6
#    fembeam collapse-scale $ARCH --record elcentro --model rock
#    fembeam collapse-scale $ARCH --record elcentro --model simulate
#    fembeam supports $ARCH --settle --plot settle.png
#    fembeam simulate $ARCH --support-motion settle --support-rate 0.01 --t-end 200 \
#        --thrust-plot thrust.png
#    fembeam report --quick --out-dir record/verification
#
# ``fembeam assess`` runs steps 2 to 4 in one command and writes them on one page
# (:doc:`/assess`).
