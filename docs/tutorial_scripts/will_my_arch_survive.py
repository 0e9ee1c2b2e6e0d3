"""
Will my arch survive?
=====================

A stone arch has been surveyed: 21 points of its mid-curve, from springing to springing, with
the thickness at each point, and its 13 voussoirs counted. The question is whether it survives
the ground motion the site must withstand, and by what margin. This tutorial answers it with
fembeam's commands, one step at a time:

1. **the survey**, as a CSV file;
2. **the static answers**: the acceleration at which the arch starts to rock, the mechanism,
   what an impact keeps of the motion, and the geometric factor of safety;
3. **the dynamic verdict**: the whole motion under the design ground motion, along one
   mechanism (``fembeam rock``) and with the voussoirs as rigid bodies in contact
   (``fembeam simulate``);
4. **the margin**: the smallest scale factor of the record that overturns the arch
   (``fembeam collapse-scale``), by both models;
5. **the verdict** in one table, from the JSON files the commands wrote;
6. **the record**: the JSON files, the verification report of the fembeam that answered, and
   the ParaView files of the arch and of its motion.

Every output below was printed by the command shown above it when this page was built. The
script runs as it is (``python will_my_arch_survive.py``, with fembeam installed) and writes
its files into the current directory.
"""

# %%
# The commands, from this script
# ------------------------------
# Each step runs one fembeam command in a subprocess, as it would run typed in a shell, and
# prints the command line and what the command printed. With ``--json`` the command prints one
# JSON object instead of its text; the script saves it in ``record/`` and prints the entries
# the step needs, each under its key in the JSON, with its unit.
import json
import pathlib
import shlex
import subprocess
import sys

RECORD = pathlib.Path("record")
RECORD.mkdir(exist_ok=True)


def fembeam(command: str, json_to: str | None = None, last: int | None = None) -> dict | None:
    """Run ``fembeam COMMAND`` as on the command line and print what it prints, the command
    first (``last``: only its last lines). With ``json_to``, ``--json`` is added, stdout is
    saved to that file of the record and returned as a dict instead of printed."""
    args = shlex.split(command) + (["--json"] if json_to else [])
    print("$ fembeam " + command + (f" --json > {RECORD / json_to}" if json_to else ""))
    done = subprocess.run([sys.executable, "-m", "fembeam", *args], capture_output=True, text=True, check=False)
    if done.returncode != 0:
        raise SystemExit(f"fembeam {args[0]} exited with {done.returncode}: {done.stderr.strip()}")
    if json_to is None:
        out = done.stdout.splitlines()
        if last is not None and len(out) > last:
            print(f"[{len(out) - last} lines]")
            out = out[-last:]
        print("\n".join(out))
        return None
    (RECORD / json_to).write_text(done.stdout)
    return json.loads(done.stdout)


UNITS = {"peak_rotation": "rad", "t_peak": "s", "thrust_line_exits_at": "s", "sliding.max_slip": "m",
         "pga_at_first_overturning": "g"}


def show(d: dict, *keys: str) -> None:
    """Print the named entries of a command's JSON, one per line, with their units."""
    for key in keys:
        value = d
        for part in key.split("."):
            value = value[part]
        if isinstance(value, list):
            value = "[" + ", ".join(f"{v:.6g}" if isinstance(v, float) else str(v) for v in value) + "]"
        text = f"{value:.6g}" if isinstance(value, float) else str(value)
        print(f"  {key}: {text} {UNITS.get(key, '')}".rstrip())


# %%
# 1. The survey
# -------------
# The mid-curve is given by points ``x, y`` (m) from the left springing to the right one, in
# any coordinate system (here the survey's grid: fembeam places the arch with the midpoint of
# its springings at the origin), and the thickness ``t`` (m) at each point. fembeam
# interpolates them with a spline (quintic from 12 points on), so the points need not be evenly
# spaced; the curve it builds must not loop or fold back.
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
ARCH = "--midcurve survey.csv --voussoirs 13"

# %%
# 2. The static answers
# ---------------------
# ``fembeam analyze`` solves the limit analysis: ``A_L`` is the horizontal ground acceleration
# (in g) at which the arch starts to rock, on the four-hinge mechanism printed (angles along
# the arch from the left springing, each hinge on the edge it pivots on); a thrust line inside
# the arch is the certificate that it stands below ``A_L``. Then the impact: ``r = K'/K`` is the
# fraction of its kinetic energy the arch keeps when it swings back through its shape at rest.
# The figure (``--figure``) draws the thrust line at the onset and the impulse line of the
# impact on the arch. Each line of ``verification`` is a figure recomputed from the solution
# and checked against a threshold: a failing one makes the command exit with code 3 instead of
# printing a number.
fembeam(f"analyze {ARCH} --figure arch.png")

# %%
# How much thinner could the arch be and still stand under its own weight?
# ``fembeam min-thickness`` scales the surveyed thickness until no thrust line fits; the
# inverse of that factor is the geometric factor of safety (Heyman's), and the hinges are
# those of the collapse mechanism just below it.
thickness = fembeam(f"min-thickness {ARCH}", json_to="min_thickness.json")
show(thickness, "thickness_scale", "geometric_safety_factor")
print("  hinges:", ", ".join(f"{h['angle_deg']:.2f} deg {h['side']}" for h in thickness["hinges"]))

# %%
# 3. The dynamic verdict
# ----------------------
# The design ground motion here is the 1940 El Centro record shipped with fembeam, scaled to a
# peak ground acceleration of 0.5 g (give the site's own record with ``--record FILE.AT2`` or a
# two-column CSV of time in s and acceleration in g). ``fembeam rock`` follows the arch from rest
# through the onset, the rocking along one mechanism, every impact, to rest or overturning; it
# also says when the dynamic thrust line first leaves the section (from then on other hinges
# would open and the one-mechanism motion is a model, not a proof) and whether the joints
# would need more friction than ``--friction`` gives. ``--plot`` draws the history and
# ``--vtk`` writes it for ParaView.
MOTION = "--record elcentro --pga 0.5"
rock = fembeam(f"rock {ARCH} {MOTION} --friction 0.6 --plot rock.png --vtk {RECORD / 'motion.pvd'}",
               json_to="rock.json")
show(rock, "outcome", "peak_rotation", "t_peak", "n_impacts", "thrust_line_exits_at",
     "friction_demand.max_ratio", "friction_demand.sliding_risk")

# %%
# ``fembeam simulate`` moves the 13 voussoirs as rigid bodies in contact (Moreau-Jean time
# steps): hinges open and close at any joint, as many as the motion asks for. It is the check
# of ``rock`` once the thrust line has left the section. The joints do not slide unless
# ``--friction`` is given.
sim = fembeam(f"simulate {ARCH} {MOTION}", json_to="simulate.json")
show(sim, "outcome", "peak_rotation", "t_peak", "n_impacts", "max_hinges", "friction_demand.max_ratio")

# %%
# The friction demand of an impact (the largest ratio of tangential to normal impulse at a
# joint) may exceed what mortar joints offer. With ``--friction 0.6`` the joints obey Coulomb's
# law and may slide; ``sliding.max_slip`` is the largest slip of a joint (m).
slide = fembeam(f"simulate {ARCH} {MOTION} --friction 0.6", json_to="simulate_friction.json")
show(slide, "outcome", "peak_rotation", "sliding.max_slip")

# %%
# 4. The margin
# -------------
# By what factor may the record grow before the arch overturns? ``fembeam collapse-scale``
# runs the record at 40 scale factors, from the one at which it first moves the arch to 20
# times that, bisects below the first one that overturns it, and lists the scanned factors
# above it that do not (the set of safe factors need not be an interval). ``--model simulate``
# does the same with the voussoirs as rigid bodies.
margins = {}
for model in ("rock", "simulate"):
    margins[model] = fembeam(f"collapse-scale {ARCH} --record elcentro --model {model} --quiet",
                             json_to=f"collapse_scale_{model}.json")
    show(margins[model], "first_overturning", "pga_at_first_overturning", "safe_factors_above")

# %%
# 5. The verdict
# --------------
# The answers of steps 2 to 4, read from the JSON files of the record. The margin is the
# smaller of the two models' peak ground accelerations at the first overturning, over the
# design one.
#
# .. The verdict table: steps 2 to 4 in one command's output, when the package has one.
design_pga = 0.5
governing = min(margins, key=lambda m: margins[m]["pga_at_first_overturning"])
rows = [
    ("incipient rocking acceleration A_L (g)", (f"{margins['rock']['A_L']['+1']:.4f} (+x), "
                                                f"{margins['rock']['A_L']['-1']:.4f} (-x)")),
    ("geometric factor of safety", f"{thickness['geometric_safety_factor']:.3f}"),
    (f"El Centro at {design_pga:g} g, rock", f"{rock['outcome']}, peak rotation {rock['peak_rotation']:.4g} rad"),
    (f"El Centro at {design_pga:g} g, simulate", f"{sim['outcome']}, peak rotation {sim['peak_rotation']:.4g} rad"),
    (f"El Centro at {design_pga:g} g, simulate, mu = 0.6",
     f"{slide['outcome']}, largest slip {slide['sliding']['max_slip'] * 1e3:.2f} mm"),
]
rows += [(f"PGA that first overturns it, {m}", f"{margins[m]['pga_at_first_overturning']:.3f} g")
         for m in margins]
rows.append(("margin on the design PGA",
             f"{margins[governing]['pga_at_first_overturning'] / design_pga:.2f} ({governing} governs)"))
width = max(len(a) for a, _ in rows)
for a, b in rows:
    print(f"{a:<{width}}  {b}")

# %%
# 6. The record
# -------------
# The JSON of every command above is in ``record/``. ``fembeam report`` adds the
# verification report of the fembeam that answered: its checks against exact solutions and the
# paper's published values (``--quick``: coarser meshes, a few seconds; without it, about half
# a minute): one line per check, then the count and the report's path (shown here); the same
# as Markdown and JSON in ``record/verification``. Exit code 1 if any check fails.
fembeam(f"report --quick --out-dir {RECORD / 'verification'} --quiet", last=2)

# %%
# The ParaView files of the arch: ``fembeam analyze --vtk`` writes the body with the
# mechanisms' velocity fields, the joints with the impulses, the thrust and impulse lines and
# the hinges, each a ``.vtu`` file, and ``arch.vtm`` that opens them together (with
# ``--json`` too, the files are written all the same). The motion of step 3 is ``record/motion.pvd``, a time series of one ``.vtu`` per frame:
# open it in ParaView (File > Open) and play it; colour by ``piece`` to see the rigid pieces.
fembeam(f"analyze {ARCH} --vtk {RECORD / 'arch.vtu'}", json_to="analyze.json")
files = sorted(p.relative_to(RECORD).as_posix() for p in RECORD.rglob("*") if p.is_file())
frames = [f for f in files if f.startswith("motion_")]
print(f"{len(files)} files in {RECORD}/:")
print("\n".join(f"  {f}" for f in files if not f.startswith("motion_")))
print(f"  {frames[0]} ... {frames[-1]} ({len(frames)} frames of motion.pvd)")
