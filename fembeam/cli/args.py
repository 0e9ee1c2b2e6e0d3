"""Argument types and option groups shared by the sub-commands.

The commands share their parsing through this module, never by importing each other: the arch
(:func:`add_arch`, :func:`arch_from`), the member of a motion (:func:`add_member`,
:func:`member_from`), the ground motion (:func:`add_ground`, :func:`ground_from`), friction
(:func:`coulomb`, :func:`friction_coefficient`), the model of each run of a study
(:func:`add_model`, :func:`model_from`), and the outputs of a time history.
"""
from __future__ import annotations

import argparse
import csv
import json
import math
import os
import sys
from pathlib import Path

from ..analysis import DEFAULT_ELEMENTS
from ..dynamics.ground import RECORDS, GroundMotion
from ..dynamics.rocking import RockingResult
from ..errors import InputError
from ..geometry import (CatenaryArch, CircularArch, EllipticalArch, MidCurve, ParabolicArch, PointedArch,
                        StraightMember, SurveyedArch)
from ..geometry.base import DEFAULT_DENSITY
from ..analysis.impact import IMPACT_BACKENDS
from ..limits import check_block, check_discretisation, check_duration
from ..output.files import check_distinct, check_name, check_output
from ..studies.models import MODELS, check_model
from ..studies.runs import DT


def finite_float(text: str) -> float:
    try:
        x = float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"expected a number, got {text!r}") from None
    if not math.isfinite(x):
        raise argparse.ArgumentTypeError(f"expected a finite number, got {text!r}")
    return x


MAX_LIST_VALUES = 10_000   # values in one list option (a range included): --help says so


def _list_size(n: float, text: str) -> None:
    if not n <= MAX_LIST_VALUES:       # also inf and NaN
        shown = text if len(text) <= 60 else text[:57] + "..."
        raise argparse.ArgumentTypeError(f"a list has at most {MAX_LIST_VALUES} values, got {shown!r}")


def float_list(text: str) -> list[float]:
    """``"a,b,c"`` or a range ``"start:stop:step"`` (stop included), at most
    :data:`MAX_LIST_VALUES` values; the range's values are rounded to 12 significant
    digits of its largest magnitude (so ``0:1:0.1`` gives 0.3, not 0.30000000000000004)."""
    if ":" in text:
        parts = [finite_float(p) for p in text.split(":")]
        if len(parts) != 3 or parts[2] <= 0 or parts[1] < parts[0]:
            raise argparse.ArgumentTypeError(f"a range is start:stop:step with step > 0 and stop >= start, "
                                             f"got {text!r}")
        a, b, step = parts
        scale = max(abs(a), abs(b))
        if step < 1e-9 * scale:
            raise argparse.ArgumentTypeError(f"the step of a range must be at least 1e-9 of its values' magnitude "
                                             f"(else the values are not distinct), got {text!r}")
        count = (b - a) / step + 1.0        # inf when b - a overflows
        _list_size(count, text)
        decimals = 12 - math.ceil(math.log10(scale)) if scale > 0 else 12
        return [round(a + i * step, decimals) for i in range(int(math.floor(count - 1.0 + 1e-9)) + 1)]
    _list_size(text.count(",") + 1, text)
    out = [finite_float(p) for p in text.split(",") if p.strip()]
    if not out:
        raise argparse.ArgumentTypeError(f"expected comma-separated numbers or start:stop:step, got {text!r}")
    return out


def int_list(text: str) -> list[int]:
    """``"a,b,c"``: at most :data:`MAX_LIST_VALUES` integers."""
    _list_size(text.count(",") + 1, text)
    try:
        out = [int(p) for p in text.split(",") if p.strip()]
    except ValueError:
        out = []
    if not out:
        raise argparse.ArgumentTypeError(f"expected comma-separated integers, got {text!r}")
    return out


def note_list_limits(parser: argparse.ArgumentParser) -> None:
    """Append the list size limit to the help of every option (of ``parser`` and its
    sub-commands) whose type is :func:`float_list` or :func:`int_list`."""
    for action in parser._actions:
        if isinstance(action, argparse._SubParsersAction):
            for sub in action.choices.values():
                note_list_limits(sub)
        elif action.type in (float_list, int_list) and action.help and "values per list" not in action.help:
            action.help += f" (at most {MAX_LIST_VALUES} values per list)"


SHAPES = ("circular", "pointed", "elliptical", "parabolic", "catenary")
_CIRCULAR_OPTIONS = ("--embrace", "--t-over-r", "--radius")
_SHAPE_OPTIONS = (("--span", "span"), ("--rise", "rise"), ("--thickness", "thickness"),
                  ("--thickness-springing", "thickness_springing"), ("--thickness-crown", "thickness_crown"))


class _Given(argparse.Action):
    """Store the value and remember that the option was given (its default is not None,
    so ``arch_from`` could not tell otherwise)."""

    def __call__(self, parser, namespace, values, option_string=None):
        setattr(namespace, self.dest, values)
        setattr(namespace, "_arch_given", set(getattr(namespace, "_arch_given", ())) | {self.option_strings[0]})


def add_arch(p: argparse.ArgumentParser, many: bool = False) -> None:
    """Options describing the arch: circular (``--embrace``, ``--t-over-r``, ``--radius``;
    ``many``: lists for studies) or another ``--shape`` (``--span``, ``--rise``, a
    thickness), or a surveyed mid-curve (``--midcurve``); :func:`arch_from` builds it."""
    g = p.add_argument_group("arch")
    g.add_argument("--shape", choices=SHAPES, default=None,
                   help="mid-curve: circular (default; --embrace, --t-over-r, --radius), pointed (two arcs, "
                        "rise >= span/2), elliptical, parabolic or catenary (--span, --rise and a thickness)")
    if many:
        g.add_argument("--embrace", type=float_list, default=[157.5], action=_Given, metavar="DEG[,DEG..|A:B:STEP]",
                       help="embrace angle(s) beta in degrees, in (0, 360) (default 157.5)")
        g.add_argument("--t-over-r", type=float_list, default=[0.15], action=_Given, metavar="X[,X..|A:B:STEP]",
                       help="thickness over mid-curve radius, in (0, 2) (default 0.15)")
    else:
        g.add_argument("--embrace", type=finite_float, default=157.5, action=_Given, metavar="DEG",
                       help="embrace angle beta in degrees, in (0, 360) (default 157.5)")
        g.add_argument("--t-over-r", type=finite_float, default=0.15, action=_Given, metavar="X",
                       help="thickness over mid-curve radius t/R, in (0, 2) (default 0.15)")
    g.add_argument("--radius", type=finite_float, default=1.0, action=_Given, metavar="M",
                   help="mid-curve radius R in metres (default 1; r and A_L/g do not depend on it)")
    g.add_argument("--span", type=finite_float, default=None, metavar="M",
                   help="--shape other than circular: span L between the springings (m)")
    g.add_argument("--rise", type=finite_float, default=None, metavar="M",
                   help="--shape other than circular: rise H of the mid-curve's crown above the springings (m)")
    g.add_argument("--thickness", type=finite_float, default=None, metavar="M",
                   help="constant thickness (m) of a --shape other than circular or of a --midcurve")
    g.add_argument("--thickness-springing", type=finite_float, default=None, metavar="TS",
                   help="with --thickness-crown: thickness linear in the arc length from TS (m) at each "
                        "springing ...")
    g.add_argument("--thickness-crown", type=finite_float, default=None, metavar="TC",
                   help="... to TC (m) at the crown (the highest point of a --midcurve)")
    g.add_argument("--midcurve", default=None, metavar="FILE.csv",
                   help="surveyed mid-curve: CSV columns x,y (m, springing to springing) and optionally t "
                        "(thickness, m; else give --thickness or --thickness-springing/--thickness-crown); "
                        "interpolated by a spline (docs: fembeam.geometry.surveyed); a regular file of at most "
                        "16 MB and 5000 points")
    g.add_argument("--density", type=finite_float, default=DEFAULT_DENSITY, metavar="RHO",
                   help=f"masonry density in kg/m^3 per metre of barrel width (default {DEFAULT_DENSITY:g}; typical "
                        "1800-2400); A_L, r and the thresholds in g of a bare arch do not depend on it (with fill "
                        "or masses they depend on the ratio of the densities)")
    add_as_built(g)


FILL_MODEL = ("fill model: the column of fill above each voussoir's (element's) extrados, between the verticals "
              "through the ends of that extrados, up to a horizontal road, is a dead load on that piece (its weight "
              "at the column's centroid) and moves rigidly with it in every dynamic model (its mass, centroid and "
              "inertia added to the piece's); left out: the spread of load through the fill and the fill's "
              "passive pressure on the arch")


def pair(text: str) -> tuple[float, float]:
    """``"X,V"``: two finite numbers (argparse type of ``--load`` and ``--mass``)."""
    parts = text.split(",")
    if len(parts) != 2:
        raise argparse.ArgumentTypeError(f"expected X,VALUE (two numbers separated by a comma), got {text!r}")
    return finite_float(parts[0]), finite_float(parts[1])


MAX_POINTS = 1000   # --load and --mass given at most this many times


def add_as_built(g) -> None:
    """``--fill-density``, ``--fill-depth`` and ``--mass`` (the arch as built)."""
    g.add_argument("--fill-density", type=finite_float, default=None, metavar="RHO_F",
                   help="density of the fill (kg/m^3, typical 1800-2000) up to the road; " + FILL_MODEL)
    g.add_argument("--fill-depth", type=finite_float, default=None, metavar="D",
                   help="with --fill-density: height (m, >= 0) of the horizontal road surface above the crown's "
                        "extrados (default 0: fill up to the crown)")
    g.add_argument("--mass", type=pair, action="append", default=[], metavar="X,M",
                   help="permanent point mass of M kg per metre of width on the extrados above the horizontal "
                        "distance X (m) from the left springing of the mid-curve: a dead load in the statics, a "
                        f"mass moving with its piece in the dynamics (repeatable, at most {MAX_POINTS})")


def add_loads(p) -> None:
    """``--load X,P`` (repeatable): the live loads of the load factor."""
    p.add_argument("--load", type=pair, action="append", default=[], metavar="X,P",
                   help="live point load of P kN per metre of width (> 0), downward, on the extrados above the "
                        "horizontal distance X (m) from the left springing of the mid-curve; the load factor is "
                        "the multiple of the live loads at collapse, dead loads at their values (repeatable, "
                        f"at most {MAX_POINTS})")


def points_of(args, name: str) -> list:
    values = getattr(args, name, None) or []
    if len(values) > MAX_POINTS:
        raise InputError(f"--{name} is given {len(values)} times: at most {MAX_POINTS}")
    return values


def add_solver(p: argparse.ArgumentParser, elements_default: int | None = DEFAULT_ELEMENTS) -> None:
    g = p.add_argument_group("discretisation and solver")
    m = g.add_mutually_exclusive_group()
    m.add_argument("--elements", type=int, default=None, metavar="N",
                   help=f"rigid elements on the continuous arch (default {elements_default})")
    m.add_argument("--voussoirs", type=int, default=None, metavar="N",
                   help="discrete arch of N rigid voussoirs, hinges only at the N+1 joints")
    g.add_argument("--direction", type=int, choices=(1, -1), default=1,
                   help="+1: ground pulse from right to left, arch starts moving left to right (default); -1: mirrored")
    g.add_argument("--backend", choices=IMPACT_BACKENDS, default="auto",
                   help="solver of the impact QP: auto (default: clarabel up to 5000 elements, active-set above), "
                        "clarabel (interior point), osqp (ADMM), active-set (banded, O(N)); see docs/solvers.md")
    g.add_argument("--no-refine", action="store_true",
                   help="keep the incipient mechanism's hinges on the uniform mesh (no continuous refinement)")


def arch_from(args) -> MidCurve:
    """The member of the :func:`add_arch` options, as built (fill and masses); InputError (exit
    2) for options that do not fit together (e.g. ``--span`` with a circular arch, ``--shape
    pointed`` without ``--rise``)."""
    from ..geometry.asbuilt import build

    return build(_bare_arch(args), fill_density=getattr(args, "fill_density", None),
                 fill_depth=getattr(args, "fill_depth", None), masses=points_of(args, "mass"))


def _bare_arch(args) -> MidCurve:
    shape = getattr(args, "shape", None)
    midcurve = getattr(args, "midcurve", None)
    given = sorted(set(getattr(args, "_arch_given", ())) & set(_CIRCULAR_OPTIONS), key=_CIRCULAR_OPTIONS.index)
    new = {opt: getattr(args, dest, None) for opt, dest in _SHAPE_OPTIONS}
    new_given = [opt for opt, v in new.items() if v is not None]
    density = getattr(args, "density", DEFAULT_DENSITY)
    if midcurve is not None:
        if shape is not None:
            raise InputError("--midcurve gives the shape of the arch: drop --shape")
        bad = given + [o for o in ("--span", "--rise") if new[o] is not None]
        if bad:
            raise InputError(f"{bad[0]} does not apply to --midcurve (the file gives the mid-curve); "
                             "thickness: the file's t column, --thickness or --thickness-springing/--thickness-crown")
        _check_thickness_options(new, "--midcurve", required=False)
        return SurveyedArch.from_csv(midcurve, thickness=new["--thickness"],
                                     thickness_springing=new["--thickness-springing"],
                                     thickness_crown=new["--thickness-crown"], density=density)
    if shape in (None, "circular"):
        if new_given:
            raise InputError(f"{new_given[0]} applies to --shape pointed|elliptical|parabolic|catenary or --midcurve; "
                             "a circular arch takes --embrace, --t-over-r and --radius")
        return CircularArch.from_ratio(args.embrace, args.t_over_r, radius=args.radius, density=density)
    if given:
        raise InputError(f"{given[0]} applies to the circular arch only; --shape {shape} takes --span, --rise and "
                         "--thickness (or --thickness-springing and --thickness-crown)")
    missing = [o for o in ("--span", "--rise") if new[o] is None]
    if missing:
        raise InputError(f"--shape {shape} needs {' and '.join(missing)} (m)")
    _check_thickness_options(new, f"--shape {shape}", required=True)
    return _SHAPE_CLASSES[shape](span=new["--span"], rise=new["--rise"], thickness=new["--thickness"],
                                 thickness_springing=new["--thickness-springing"],
                                 thickness_crown=new["--thickness-crown"], density=density)


_SHAPE_CLASSES = {"pointed": PointedArch, "elliptical": EllipticalArch, "parabolic": ParabolicArch,
                  "catenary": CatenaryArch}


def _check_thickness_options(new: dict, what: str, required: bool) -> None:
    t, ts, tc = new["--thickness"], new["--thickness-springing"], new["--thickness-crown"]
    if t is not None and (ts is not None or tc is not None):
        raise InputError("give either --thickness or --thickness-springing with --thickness-crown, not both")
    if (ts is None) != (tc is None):
        raise InputError("--thickness-springing and --thickness-crown go together (thickness linear in the arc "
                         "length from each springing to the crown)")
    if required and t is None and ts is None:
        raise InputError(f"{what} needs --thickness T, or --thickness-springing TS and --thickness-crown TC (m)")


def arch_title(geometry: dict) -> str:
    """One line describing the member of ``describe()``: the circular arch's words as
    ever (``circular arch, embrace 157.5 deg, t/R = 0.15, R = 1 m``), else the shape,
    span, rise and thickness."""
    g = geometry
    shape = g.get("shape", "member")
    if shape == "circular":
        return f"circular arch, embrace {g['embrace_deg']:g} deg, t/R = {g['t_over_R']:g}, R = {g['radius']:g} m"
    if "thickness_springing" in g:
        th = f"thickness {g['thickness_springing']:g} m at the springings to {g['thickness_crown']:g} m at the crown"
    elif isinstance(g.get("thickness"), (int, float)):
        th = f"thickness {g['thickness']:g} m"
    elif "thickness_min" in g:
        th = f"thickness {g['thickness_min']:g}-{g['thickness_max']:g} m (t column)"
    else:
        th = ""
    what = (f"{shape} arch" if shape != "surveyed"
            else f"surveyed arch ({g.get('points')} points, {g.get('spline')} spline)")
    sizes = [f"{k} {g[k]:g} m" for k in ("span", "rise") if isinstance(g.get(k), (int, float))]
    return ", ".join([what] + sizes + ([th] if th else []))


def check_outputs(args, stem: str) -> None:
    """Reject the files of :func:`write_outputs` before any computation (exit 2)."""
    from ..output.files import PLOT_SUFFIXES, check_dir, check_distinct, check_output

    check_output(args.csv, "--csv", (".csv",))
    check_output(args.plot, "--plot", PLOT_SUFFIXES)
    outputs = {"--csv": args.csv, "--plot": args.plot}
    if check_dir(args.out_dir, "--out-dir") is not None:
        for name in (f"{stem}.csv", f"{stem}.json", f"{stem}.png"):
            if os.path.isdir(os.path.join(args.out_dir, name)):
                raise InputError(f"--out-dir: {os.path.join(args.out_dir, name)!r} is a directory")
        outputs[f"--out-dir ({stem}.json)"] = os.path.join(args.out_dir, f"{stem}.json")
    check_distinct(outputs)


def study_journal(args, command: str):
    """The journal of a study writing files (``--out-dir``, else ``--csv``, else ``--plot``):
    finished cases are kept there, and a re-run with the same output resumes from them
    (:class:`~fembeam.studies.parallel.Journal`); None when the study writes no file."""
    from ..studies.parallel import journal_for

    if args.out_dir:
        return noted(journal_for(args.out_dir, command, directory=True))
    return noted(journal_for(args.csv or args.plot, command))


def check_scheduler(address: str | None) -> None:
    """``--scheduler``: None (local cores) or a non-empty address, with Dask installed; InputError
    otherwise (whether the scheduler answers is checked when the study connects)."""
    if address is None:
        return
    if not address.strip():
        raise InputError("--scheduler needs the address of a Dask scheduler (tcp://host:8786), got an empty string")
    try:
        import distributed  # noqa: F401,F811
    except ImportError:
        raise InputError("--scheduler needs Dask, which is not installed: pip install 'fembeam[dask]'") from None


def note_records(grounds) -> None:
    """Say on stderr, one line each, which records look like m/s^2 rather than g
    (:func:`~fembeam.dynamics.ground.unit_note`); they are run as given."""
    from ..dynamics.ground import unit_note
    from .main import one_line

    for g in grounds:
        text = unit_note(g)
        if text:
            print(f"fembeam: note: {one_line(text)}", file=sys.stderr)


def noted(journal):
    """``journal``, its note (what of it was ignored) said in one line on stderr."""
    if journal is not None and journal.note:
        from .main import one_line
        print(f"fembeam: note: {one_line(journal.note)}", file=sys.stderr)
    return journal


def write_outputs(result, args, stem: str, plot) -> None:
    """Write ``result`` (with ``to_dict()`` and ``csv_rows()``) where ``--csv``, ``--plot``
    and ``--out-dir`` (``stem``.csv/.json/.png) ask, each file atomically; ``plot(result,
    path)`` draws the figure.  Call :func:`check_outputs` before computing."""
    from ..output.files import atomic

    csv_path, plot_path, json_path = args.csv, args.plot, None
    if args.out_dir:
        os.makedirs(args.out_dir, exist_ok=True)
        csv_path = csv_path or os.path.join(args.out_dir, f"{stem}.csv")
        plot_path = plot_path or os.path.join(args.out_dir, f"{stem}.png")
        json_path = os.path.join(args.out_dir, f"{stem}.json")
    if csv_path:
        rows = result.csv_rows()
        with atomic(csv_path) as tmp, open(tmp, "w", newline="") as f:
            w = csv.DictWriter(f, fieldnames=list(rows[0]))
            w.writeheader()
            w.writerows(rows)
    if json_path:
        with atomic(json_path) as tmp, open(tmp, "w") as f:
            json.dump(result.to_dict(), f, indent=1, allow_nan=False)
    if plot_path:
        with atomic(plot_path) as tmp:
            plot(result, tmp)


def print_result(as_json: bool, data, page, written=()) -> int:
    """Print a command's result: ``data()`` as one strict JSON object (``--json``), or the text
    ``page()`` followed by the files written; exit code 0."""
    import json

    if as_json:
        print(json.dumps(data(), allow_nan=False))
    else:
        print(page())
        for w in written:
            print(f"  {w}")
    return 0


# --------------------------------------------------------------------------- members, ground motions, models
PULSES = ("rect", "sine", "ricker")



def add_member(p: argparse.ArgumentParser, solver: bool = True) -> None:
    """Arch options of ``analyze``, ``--voussoirs``/``--elements``, or ``--block``; ``solver``:
    also ``--backend`` and ``--no-qp`` (the general QP at each impact)."""
    add_arch(p)
    g = p.add_argument_group("discretisation")
    m = g.add_mutually_exclusive_group()
    m.add_argument("--voussoirs", type=int, default=None, metavar="N",
                   help="discrete arch of N voussoirs: hinges only at the N+1 joints (rock: 3 to 80; simulate: at "
                        "most 1000)")
    m.add_argument("--elements", type=int, default=None, metavar="N",
                   help="continuous arch: rigid elements of the limit analysis and the general QP (default 200; "
                        "rock: at most 20000; simulate: at most 1000)")
    m.add_argument("--block", type=finite_float, nargs=2, default=None, metavar=("WIDTH", "HEIGHT"),
                   help="instead of an arch: a rectangular block WIDTH x HEIGHT (m) rocking on a rigid base, "
                        "WIDTH / HEIGHT in [1e-3, 1e3]")
    if solver:
        g.add_argument("--backend", choices=("clarabel", "osqp"), default="clarabel",
                       help="QP solver of the general QP")
        g.add_argument("--no-qp", action="store_true", help="skip the general QP's r_qp at each impact")



def add_ground(p: argparse.ArgumentParser, pulse_required: bool = False):
    """``--pulse`` with ``--amplitude``/``--duration``/``--period``, or ``--record``; returns the
    (required) group of mutually exclusive sources, to which a command may add its own."""
    g = p.add_argument_group("ground motion (accelerations in g, positive along +x)")
    w = g.add_mutually_exclusive_group(required=True)
    w.add_argument("--pulse", choices=PULSES, help="rectangular, one-sine or Ricker pulse")
    if not pulse_required:
        w.add_argument("--record", metavar="FILE",
                       help=f"PEER .AT2 file or CSV (time s, acceleration g; a regular file of at most 24 MB, "
                            f"10^6 samples, DT in [1e-5, 1] s), or a shipped record: "
                            f"{', '.join(RECORDS)}")
    g.add_argument("--amplitude", type=finite_float, metavar="A", help="pulse amplitude (g)")
    g.add_argument("--duration", type=finite_float, metavar="T1", help="rectangular pulse: duration (s)")
    g.add_argument("--period", type=finite_float, metavar="TP", help="sine or Ricker pulse: period (s)")
    if not pulse_required:
        s = g.add_mutually_exclusive_group()
        s.add_argument("--scale", type=finite_float, metavar="F", help="record: multiply by F")
        s.add_argument("--pga", type=finite_float, metavar="A", help="record: scale to a peak of A g")
    return w



def member_from(args, model: str = "rock"):
    """``(curve, voussoirs, elements)`` of the member options, within the bounds of ``model``
    (``"rock"``, ``"simulate"`` or ``"auto"``: :func:`fembeam.limits.check_block`,
    :func:`~fembeam.limits.check_discretisation`), checked before the member is built."""
    if args.block is not None:
        given = [o for o, v in (("--fill-density", getattr(args, "fill_density", None)),
                                ("--fill-depth", getattr(args, "fill_depth", None)),
                                ("--mass", getattr(args, "mass", None))) if v]
        if given:
            raise InputError(f"{given[0]} applies to arches, not to a --block")
        width, height = args.block
        curve = StraightMember(height=height, width=width, density=args.density)
        check_block(curve.width, curve.height)
        return curve, 1, 200
    from ..analysis.sizes import DEFAULT_ELEMENTS
    check_discretisation(model, args.voussoirs, args.elements)
    return arch_from(args), args.voussoirs, DEFAULT_ELEMENTS if args.elements is None else args.elements



def pulse_from(kind: str, amplitude: float, args) -> GroundMotion:
    if kind == "rect":
        if args.duration is None:
            raise InputError("--pulse rect needs --duration T1 (s)")
        return GroundMotion.rectangular(amplitude, args.duration)
    if args.period is None:
        raise InputError(f"--pulse {kind} needs --period TP (s)")
    return (GroundMotion.sine if kind == "sine" else GroundMotion.ricker)(amplitude, args.period)



def ground_from(args) -> GroundMotion:
    if args.pulse is not None:
        if args.amplitude is None:
            raise InputError(f"--pulse {args.pulse} needs --amplitude A (g)")
        if getattr(args, "scale", None) is not None or getattr(args, "pga", None) is not None:
            raise InputError("--scale and --pga apply to --record, not to a pulse")
        return pulse_from(args.pulse, args.amplitude, args)
    if args.amplitude is not None or args.duration is not None or args.period is not None:
        raise InputError("--amplitude, --duration and --period describe a --pulse, not a --record")
    gm = GroundMotion.record(args.record)
    note_records([gm])
    if args.scale is not None:
        gm = gm.scaled(args.scale)
    if args.pga is not None:
        gm = gm.to_pga(args.pga)
    return gm



def coulomb(text: str) -> float | None:
    """A Coulomb coefficient of the motion models, in
    :data:`~fembeam.simulation.stepper.MU_RANGE`; ``inf`` is unlimited friction (the joints
    never slide), returned as None, as without the option; argparse type: exit 2 with one line
    otherwise."""
    from ..simulation.stepper import MU_RANGE

    lo, hi = MU_RANGE
    try:
        mu = float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"expected a friction coefficient (a number in [{lo:g}, {hi:g}] "
                                         f"or inf), got {text!r}") from None
    if mu == math.inf:
        return None
    if not (math.isfinite(mu) and lo <= mu <= hi):
        raise argparse.ArgumentTypeError(f"the friction coefficient of the motion must be in [{lo:g}, {hi:g}] "
                                         f"or inf (joints that never slide), got {text!r}")
    return mu


def friction_line(res: RockingResult) -> str | None:
    """The summary's line of the friction demand (None when it was not checked)."""
    fd = res.friction_demand
    if fd is None:
        return None
    if fd["t"] is None:
        line = "  friction demand: none (no motion)"
    else:
        where = f"s = {fd['s']:.6g} m" if fd["s"] is not None else "no section in compression"
        if fd["s"] is not None and res.curve.describe().get("shape") != "block":
            where += f" ({float(res.curve.angle_deg(fd['s'])):.2f} deg)"
        what = "|S|/N during the motion" if fd["at"] == "motion" else "|P_t|/P_n of an impact"
        line = f"  friction demand: largest {what} = {fd['max_ratio']:.4f} at {where}, t = {fd['t']:.6g} s"
    if fd["mu"] is not None:
        line += (f": SLIDING RISK (above mu = {fd['mu']:g})" if fd["sliding_risk"] else f" (within mu = {fd['mu']:g})")
    return line



def time_progress(t_end: float):
    """A tqdm bar over simulated time on stderr when it is a terminal (None otherwise)."""
    if not sys.stderr.isatty():
        return None, None
    from tqdm import tqdm
    bar = tqdm(total=round(t_end, 3), unit="s", desc="simulated time", file=sys.stderr, leave=False)

    def update(t: float):
        bar.n = round(min(t, t_end), 3)
        bar.refresh()
    return update, bar



def motion_outputs(args) -> dict:
    """The outputs of a time-history command (``--csv``, ``--plot``, ``--vtk``, ``--gif``),
    ``--frames`` and ``--history``, checked before computing."""
    outputs = {"csv": check_output(args.csv, "--csv", (".csv",)),
               "plot": check_output(args.plot, "--plot", (".png", ".pdf", ".svg")),
               "vtk": check_output(args.vtk, "--vtk", (".pvd",)),
               "gif": check_output(args.gif, "--gif", (".gif",))}
    if args.frames is not None and not 2 <= args.frames <= 100_000:
        raise InputError(f"--frames must be in [2, 100000], got {args.frames}")
    if outputs["vtk"] is not None:            # the longest frame name the series will have
        n = args.frames or 200
        check_name(outputs["vtk"].with_name(f"{outputs['vtk'].stem}_{n - 1:04d}.vtu"), "--vtk")
    check_distinct({"--csv": args.csv, "--plot": args.plot, "--vtk": args.vtk, "--gif": args.gif})
    if args.history and not args.json:
        raise InputError("--history adds the history to --json output; give --json too")
    return outputs



def run_end(args, curve, ground) -> float:
    """``--t-end`` (s; default: the end of the ground motion plus ``20 sqrt(L/g)``), after the
    start of the ground motion by at most :data:`~fembeam.limits.MAX_DURATION`."""
    from ..dynamics.equation import GRAVITY

    t0 = float(ground.t[0])
    t_end = args.t_end if args.t_end is not None else float(ground.t[-1]) + 20.0 * math.sqrt(curve.length / GRAVITY)
    if not t_end > t0:
        raise InputError(f"--t-end must be after the start of the ground motion ({t0:g} s), got {t_end:g}")
    check_duration(t_end - t0)
    return t_end



def friction_coefficient(text: str) -> float:
    """A finite Coulomb coefficient >= 0 (argparse type: exit 2 with one line otherwise)."""
    try:
        mu = float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"expected a friction coefficient (a number >= 0), got {text!r}") from None
    from ..analysis.rows import MAX_FRICTION

    if not math.isfinite(mu) or not 0 <= mu <= MAX_FRICTION:
        raise argparse.ArgumentTypeError(f"the friction coefficient must be a number in [0, {MAX_FRICTION:g}] "
                                         f"(omit --friction for joints that never slide), got {text!r}")
    return mu



def add_friction(p, help_text: str) -> None:
    p.add_argument("--friction", type=friction_coefficient, default=None, metavar="MU", help=help_text)



def add_picture_options(p) -> None:
    """``--vtk``, ``--png``, ``--figure`` (docs/visualisation.md); reusable by other commands."""
    g = p.add_argument_group("files (docs/visualisation.md)")
    g.add_argument("--vtk", type=Path, metavar="PATH.vtu",
                   help="VTK export: PATH.vtu (arch body) plus PATH_joints/_impulse/_thrust/_hinges.vtu "
                        "and a PATH.vtm index that ParaView/pyvista open at once")
    g.add_argument("--png", type=Path, metavar="PATH.png",
                   help="off-screen pyvista rendering: body coloured by post-impact speed, lines, hinges")
    g.add_argument("--figure", type=Path, metavar="PATH",
                   help="paper-style matplotlib figure (Figs. 10-12); format from the suffix (png, pdf, svg)")



def check_picture_options(args) -> None:
    """Reject bad output paths before any computation (exit 2): suffix, a directory, a
    missing or read-only parent (:func:`~fembeam.output.files.check_output`)."""
    from ..output.files import check_distinct, check_name, check_output

    vtk = check_output(getattr(args, "vtk", None), "--vtk", (".vtu",))
    check_output(getattr(args, "png", None), "--png", (".png",))
    if getattr(args, "figure", None) is not None:
        from matplotlib.figure import Figure
        ok = sorted(Figure().canvas.get_supported_filetypes())
        check_output(args.figure, "--figure", tuple(f".{x}" for x in ok))
    outputs = {"--png": getattr(args, "png", None), "--figure": getattr(args, "figure", None)}
    if vtk is not None:
        from ..output.export import output_paths
        for part, path in output_paths(vtk).items():        # the files the export derives from the name
            check_name(path, "--vtk")
            outputs[f"--vtk ({part})"] = path
    check_distinct(outputs)



def friction_lines(rf: dict, mu: float | None, names: dict) -> list[str]:
    """Text of :meth:`AnalysisResult.required_friction`-like dicts: the friction each stage
    needs and, with ``mu``, the joints needing more (flagged, never silently)."""
    lines = []
    for stage, ratio in names.items():
        d = rf.get(stage)
        label = {"impact_qp": "impact (general QP)"}.get(stage, stage)
        if d is None:
            continue
        if d.get("max") is None:
            lines.append(f"  friction needed at the {label}: n/a ({d.get('reason', 'undefined')})")
            continue
        lines.append(f"  friction needed at the {label}: max {ratio} = {d['max']:.4f} at {d['at_deg']:.2f} deg")
        above = d.get("above") or []
        if mu is not None and "above" in d and not above:
            lines[-1] += f" (within mu = {mu:g})"
        if mu is not None and above:
            where = ", ".join(f"{a['angle_deg']:.2f}" for a in above[:8]) + (" ..." if len(above) > 8 else "")
            lines.append(f"    SLIDING RISK: {len(above)} joint(s) need more than mu = {mu:g}, at {where} deg")
    return lines



MODEL_HELP = ("rock: one mechanism between impacts (default); simulate: the voussoirs, rigid elements or block "
              "as rigid bodies in contact (fembeam simulate, hinges anywhere), about 10x slower; auto: rock while its "
              "mechanism is admissible, simulate from the first violation (fembeam rock --model auto); a run "
              "collapses when it overturns or, with --friction, collapses by sliding")



def add_model(p) -> None:
    """``--model``, ``--dt``, ``--friction``."""
    g = p.add_argument_group("model of each run")
    g.add_argument("--model", choices=MODELS, default="rock", help=MODEL_HELP)
    g.add_argument("--dt", type=finite_float, default=None, metavar="S",
                   help=f"--model simulate or auto: time step (s; default {DT:g}, in [1e-6, 0.05], at most 1e7 steps "
                        f"a run)")
    g.add_argument("--friction", type=coulomb, default=None, metavar="MU",
                   help="--model simulate or auto: Coulomb coefficient at every joint, the springings included (default: "
                        "joints never slide; inf says so); collapse by sliding then counts as overturning, and amplitudes "
                        "(factors) below the onset at A_L are run too")



def model_from(args) -> tuple[float | None, float | None]:
    """``(dt, friction)`` of ``--model`` (InputError, exit 2: ``--dt`` or ``--friction`` with rock, or
    out of range)."""
    return check_model(args.model, args.dt, args.friction, names=("--model", "--dt", "--friction"))



def model_line(dt: float, friction: float | None, model: str = "simulate") -> str:
    """The line naming ``--model simulate`` (or ``auto``) and what counts as collapse."""
    name = "simulate (rigid bodies in contact" if model == "simulate" else \
        "auto (rock while its mechanism is admissible, then rigid bodies in contact"
    if friction is None:
        return f"model: {name}, dt = {dt:g} s, joints never slide); collapse = overturned"
    return (f"model: {name}, dt = {dt:g} s, Coulomb friction mu = {friction:g}); "
            f"collapse = overturned or collapsed by sliding")

