"""``fembeam assess``: one page for a member and a ground motion (a pulse, a record or a folder of
records): static answers, the ``auto`` verdict and the margin.

The computation is :func:`fembeam.studies.assess.assess`, the page, figures and report
:mod:`fembeam.output.assess`; this module parses, checks (inputs and outputs, before computing)
and prints.
"""
from __future__ import annotations

import argparse
import json
import shlex
import sys
from pathlib import Path

from ..dynamics.ground import GroundMotion
from ..limits import MAX_COMMAND_RUNS
from ..errors import InputError
from ..studies.collapse import MAX_RUNS, RESOLUTION
from ..studies.suites import record_files
from .args import add_ground, add_member, arch_title, coulomb, finite_float, ground_from, member_from, note_records

REPLACED = ("--factors", "--bisect-tol")      # the former grid search of the margins: refused with one line


def register(sub) -> None:
    p = sub.add_parser("assess", help="one page: A_L, minimum thickness, friction needed, auto verdict and margin",
                       description="Static answers (A_L both ways, minimum thickness and the geometric factor of "
                                   "safety, the friction the limit state needs), the verdict of the auto model "
                                   "(one mechanism while it holds, the multi-block simulation from its first failure) "
                                   "under each ground motion, and the margin: the smallest scale factor of the motion "
                                   "that collapses the member by auto, beside rock's, each by the hunt and fill of "
                                   "collapse-scale at --resolution (docs/assess.md).")
    add_member(p, solver=False)
    w = add_ground(p)
    w.add_argument("--records", metavar="DIR",
                   help="every .AT2 and .csv record of the folder DIR (time s, acceleration g), one after another "
                        "(--scale and --pga apply to each)")
    a = p.add_argument_group("auto model and margin")
    a.add_argument("--friction", type=coulomb, default=None, metavar="MU",
                   help="Coulomb coefficient of the joints in the auto model's simulation and admissibility "
                        "(default, or inf: joints never slide); the statics flag it against the friction needed")
    a.add_argument("--dt", type=finite_float, default=None, metavar="S",
                   help="time step of the multi-block simulation (s; default 1e-3)")
    a.add_argument("--t-end", type=finite_float, default=None, metavar="S",
                   help="end of every run (s; default: end of the motion + 20 sqrt(L/g))")
    a.add_argument("--no-margin", action="store_true", help="skip the margin searches")
    a.add_argument("--resolution", type=finite_float, default=None, metavar="R",
                   help=f"relative step the margin searches (hunt and fill, as collapse-scale) must reach below a "
                        f"collapse before calling it the smallest, in [1e-4, 1] (default {RESOLUTION:g})")
    a.add_argument("--max-runs", type=int, default=None, metavar="N",
                   help=f"time histories at most in each margin search (default {MAX_RUNS}); a finer --resolution "
                        f"needs more; ground motions x 2 models x N is at most {MAX_COMMAND_RUNS}")
    for gone in REPLACED:
        a.add_argument(gone, nargs="?", const="", default=None, help=argparse.SUPPRESS)
    o = p.add_argument_group("output")
    o.add_argument("--json", action="store_true", help="print one JSON object on stdout")
    o.add_argument("--report", metavar="DIR",
                   help="write DIR/report.md with its figures and DIR/assess.json (all or none)")
    o.add_argument("--quiet", action="store_true", help="no progress on stderr")
    p.set_defaults(func=run)


def grounds_from(args) -> tuple[list[GroundMotion], list[str]]:
    """The ground motions of the options and where each came from (a pulse, a file)."""
    if args.records is None:
        g = ground_from(args)
        return [g], ["pulse" if args.pulse is not None else str(args.record)]
    if args.amplitude is not None or args.duration is not None or args.period is not None:
        raise InputError("--amplitude, --duration and --period describe a --pulse, not --records")
    folder = Path(args.records)
    if not folder.is_dir():
        raise InputError(f"--records: {args.records!r} is not a directory")
    files = record_files(folder)
    if not files:
        raise InputError(f"--records: no .AT2 or .csv file in {args.records!r}")
    grounds = []
    for f in files:
        gm = GroundMotion.record(f)
        note_records([gm])
        if args.scale is not None:
            gm = gm.scaled(args.scale)
        if args.pga is not None:
            gm = gm.to_pga(args.pga)
        grounds.append(gm)
    return grounds, [str(f) for f in files]


def _check(args) -> None:
    if args.voussoirs is not None and args.voussoirs < 1:
        raise InputError(f"--voussoirs must be >= 1, got {args.voussoirs}")
    if args.elements is not None and args.elements < 4:
        raise InputError(f"--elements must be >= 4, got {args.elements}")
    for gone in REPLACED:
        if getattr(args, gone.lstrip("-").replace("-", "_")) is not None:
            raise InputError(f"{gone} was replaced by --resolution (the margins are searched by hunt and fill, as in "
                             "collapse-scale)")
    if args.no_margin and (args.resolution is not None or args.max_runs is not None):
        raise InputError("--resolution and --max-runs set the margin searches: drop them or --no-margin")
    if args.resolution is None:
        args.resolution = RESOLUTION
    if args.max_runs is None:
        args.max_runs = MAX_RUNS
    if not 1e-4 <= args.resolution <= 1.0:
        raise InputError(f"--resolution must be in [1e-4, 1] (relative step between factors), got {args.resolution:g}")
    if not 1 <= args.max_runs <= 100_000:
        raise InputError(f"--max-runs must be in [1, 100000], got {args.max_runs}")
    if args.t_end is not None and not args.t_end > 0:
        raise InputError(f"--t-end must be a positive number of seconds, got {args.t_end:g}")


def member_title(d: dict) -> str:
    """One line describing the member of :meth:`AssessResult.to_dict`."""
    g = d["geometry"]
    if g.get("shape") == "block":
        return f"block {g['width']:g} m x {g['height']:g} m on a rigid base"
    what = "voussoirs" if d["mode"] == "voussoirs" else "rigid elements (continuous arch)"
    return f"{arch_title(g)}; {d['elements']} {what}"


def _progress(quiet: bool):
    """A one-line status on stderr when it is a terminal (None otherwise), and its closer."""
    if quiet or not sys.stderr.isatty():
        return None, lambda: None

    def say(message: str) -> None:
        sys.stderr.write("\r\033[K" + message[:110])
        sys.stderr.flush()
    return say, lambda: say("")


def _check_runs(args, curve, voussoirs, elements, grounds) -> None:
    """Each run of the auto model within the bounds of :mod:`fembeam.limits` (the simulation
    may take over from the start: its steps times its bodies)."""
    import math

    from ..auto.model import DT
    from ..dynamics.equation import GRAVITY
    from ..geometry import StraightMember
    from ..limits import bodies, check_steps
    n = bodies(voussoirs, elements, isinstance(curve, StraightMember))
    for g in grounds:
        end = args.t_end if args.t_end is not None else float(g.t[-1]) + 20.0 * math.sqrt(curve.length / GRAVITY)
        check_steps(DT if args.dt is None else args.dt, end - float(g.t[0]), n)


def run(args) -> int:
    from ..output.assess import check_report, page, write_report
    from ..studies.assess import assess

    _check(args)
    curve, voussoirs, elements = member_from(args, "auto")
    grounds, sources = grounds_from(args)
    _check_runs(args, curve, voussoirs, elements, grounds)
    report = check_report(args.report, len(grounds)) if args.report is not None else None
    say, done = _progress(args.quiet)
    try:
        res = assess(curve, grounds, voussoirs=voussoirs, elements=elements, friction=args.friction, dt=args.dt,
                     t_end=args.t_end, margin_search=not args.no_margin,
                     resolution=args.resolution, max_runs=args.max_runs, sources=sources, progress=say)
    finally:
        done()
    d = res.to_dict()
    member = member_title(d)
    if report is not None:
        command = "fembeam " + " ".join(shlex.quote(a) for a in sys.argv[1:]) if sys.argv[1:2] == ["assess"] else None
        write_report(res, report, member, command)
    if args.json:
        print(json.dumps(d, allow_nan=False))
    else:
        print(page(d, member))
        if report is not None:
            print(f"  report: {report / 'report.md'}")
    return 0
