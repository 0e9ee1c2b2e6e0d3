"""``fembeam fragility``: collapse fragility of a member over a record suite.

The computation is :func:`fembeam.studies.fragility.fragility`; this module parses, prints and
writes (``fragility.csv``, ``fragility.json``, ``fragility.png``, ``ida.csv``, ``ida.png``).
"""
from __future__ import annotations

import argparse
import csv
import json
import os

from ..errors import InputError
from ..output.files import PLOT_SUFFIXES, atomic, check_dir, check_output
from ..studies.collapse import MAX_RUNS, RESOLUTION, SPAN
from ..studies.fragility import BOOTSTRAP, LEVEL, FragilityResult, fragility, plot_fragility, plot_ida
from ..studies.models import DEFAULT_MODEL, MODELS
from ..studies.parallel import journal_for
from ..studies.spectrum import DT, T_END_FACTOR
from ..studies.suites import FEMA_SUITES, load_suite
from .args import arch_title, finite_float, print_result
from .rock import add_member, member_from

FILES = {"csv": "fragility.csv", "json": "fragility.json", "plot": "fragility.png", "ida_csv": "ida.csv",
         "ida_plot": "ida.png"}


def register(sub) -> None:
    p = sub.add_parser("fragility", help="collapse fragility over a record suite: IDA of every record and sign, "
                                         "lognormal fit, collapse margin ratio",
                       description="Incremental dynamic analysis of the member under every record of a suite, both "
                                   "signs: the scale factor at which each first collapses (hunt-and-fill search at a "
                                   "stated resolution), the intensity at collapse, the lognormal fragility fitted by "
                                   "interval-censored maximum likelihood (each first collapse known between the last "
                                   "safe intensity and the collapse found; no collapse, or a solver error, censored "
                                   "at the last safe intensity) with bootstrap intervals over the recordings, and "
                                   "with --design the collapse margin ratio and the probability of collapse there "
                                   "(docs/fragility.md). A member symmetric about its vertical axis runs sign +1 and "
                                   "gives sign -1 as its mirror image (--both-signs runs both). Runs on "
                                   "local processes or a Dask cluster; with output files, finished records are kept "
                                   "in a journal and a re-run resumes.")
    add_member(p)
    g = p.add_argument_group("suite and intensity")
    g.add_argument("--suite", required=True, metavar="DIR|NAME",
                   help=f"a folder of PEER .AT2 / CSV (time s, acceleration g) records, or {', '.join(FEMA_SUITES)} "
                        "(pip install 'fembeam[suites]')")
    g.add_argument("--im", default="pga", metavar="pga|pgv|sa:T",
                   help="intensity measure: PGA (g, default), PGV (m/s) or the 5%%-damped pseudo-spectral "
                        "acceleration at T s (g)")
    g.add_argument("--design", type=finite_float, default=None, metavar="X",
                   help="design intensity (the measure's unit): collapse margin ratio and probability of collapse")
    m = p.add_argument_group("model of each run")
    m.add_argument("--model", choices=MODELS, default=DEFAULT_MODEL,
                   help="simulate (default): the pieces as rigid bodies in contact, hinges anywhere; rock: one "
                        "mechanism between impacts; auto: rock while its mechanism is admissible, simulate from "
                        "the first violation")
    m.add_argument("--dt", type=finite_float, default=None, metavar="S",
                   help=f"--model simulate or auto: time step (s; default {DT:g})")
    s = p.add_argument_group("search (hunt and fill)")
    s.add_argument("--resolution", type=finite_float, default=RESOLUTION, metavar="R",
                   help=f"relative step the scan must reach below a collapse before calling it the smallest "
                        f"(default {RESOLUTION:g})")
    s.add_argument("--factor-span", type=finite_float, default=SPAN, metavar="S",
                   help=f"largest factor, in onset factors (default {SPAN:g})")
    s.add_argument("--max-runs", type=int, default=MAX_RUNS, metavar="N",
                   help=f"time histories per record and sign at most (default {MAX_RUNS})")
    s.add_argument("--both-signs", action="store_true",
                   help="run sign -1 even for a symmetric member (default: its rows are the mirror images of +1's)")
    s.add_argument("--t-end-factor", type=finite_float, default=T_END_FACTOR, metavar="F",
                   help=f"each run lasts to the end of the record + F sqrt(L/g) (default {T_END_FACTOR:g})")
    f = p.add_argument_group("fit")
    f.add_argument("--bootstrap", type=int, default=BOOTSTRAP, metavar="N",
                   help=f"bootstrap resamples of the recordings (the records' groups; a record without a group "
                        f"is its own; default {BOOTSTRAP})")
    f.add_argument("--level", type=finite_float, default=LEVEL, metavar="P",
                   help=f"confidence level of the intervals (default {LEVEL:g})")
    f.add_argument("--seed", type=int, default=0, help="seed of the bootstrap (default 0)")
    x = p.add_argument_group("execution and output")
    x.add_argument("--workers", type=int, default=None, metavar="N", help="local worker processes (default: all cores)")
    x.add_argument("--scheduler", metavar="ADDRESS", help="run on this Dask distributed scheduler (tcp://host:8786)")
    x.add_argument("--json", action="store_true", help="print one JSON object on stdout instead of the table")
    x.add_argument("--csv", metavar="PATH.csv", help="one row per record and sign")
    x.add_argument("--plot", metavar="PATH.png", help="figure: collapse intensities and the fitted curve")
    x.add_argument("--ida-plot", metavar="PATH.png", help="figure: the IDA curves")
    x.add_argument("--out-dir", metavar="DIR", help=f"write {', '.join(FILES.values())} in DIR (unless given above)")
    x.add_argument("--quiet", action="store_true", help="no progress bar on stderr")
    p.set_defaults(func=run)


def _paths(args) -> dict:
    """Output paths, checked before any computation."""
    paths = {"csv": check_output(args.csv, "--csv", (".csv",)),
             "plot": check_output(args.plot, "--plot", PLOT_SUFFIXES),
             "ida_plot": check_output(args.ida_plot, "--ida-plot", PLOT_SUFFIXES), "json": None, "ida_csv": None}
    if check_dir(args.out_dir, "--out-dir") is not None:
        for key, name in FILES.items():
            full = os.path.join(args.out_dir, name)
            if os.path.isdir(full):
                raise InputError(f"--out-dir: {full!r} is a directory")
            paths[key] = paths[key] or full
    return paths


def run(args: argparse.Namespace) -> int:
    paths = _paths(args)
    if args.workers is not None and args.workers < 1:
        raise InputError(f"--workers must be >= 1, got {args.workers}")
    if args.elements is not None and args.elements < 4:
        raise InputError(f"--elements must be >= 4, got {args.elements}")
    if args.voussoirs is not None and args.voussoirs < 1:
        raise InputError(f"--voussoirs must be >= 1, got {args.voussoirs}")
    if args.scheduler:
        try:
            import distributed  # noqa: F401
        except ImportError:
            raise InputError("--scheduler needs Dask: pip install 'fembeam[dask]'") from None
    from ..studies.intensity import parse_im
    from ..studies.models import check_model
    check_model(args.model, args.dt, names=("--model", "--dt", "--friction"))
    parse_im(args.im)
    curve, voussoirs, elements = member_from(args)
    suite = load_suite(args.suite)
    journal = (journal_for(args.out_dir, "fragility", directory=True) if args.out_dir else
               journal_for(paths["csv"] or paths["plot"] or paths["ida_plot"], "fragility"))
    res = fragility(curve, suite, voussoirs=voussoirs, elements=elements, model=args.model, dt=args.dt, im=args.im,
                    resolution=args.resolution, span=args.factor_span, max_runs=args.max_runs,
                    t_end_factor=args.t_end_factor, design=args.design, bootstrap=args.bootstrap, seed=args.seed,
                    level=args.level, backend=args.backend, workers=args.workers, scheduler=args.scheduler,
                    progress=not args.quiet, journal=journal, mirror=not args.both_signs)
    written = write(res, paths)
    if journal is not None:
        journal.remove()
    return print_result(args.json, res.to_dict, lambda: table(res), written)


def _write_csv(rows: list[dict], path) -> None:
    with atomic(path) as tmp, open(tmp, "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=list(rows[0]))
        w.writeheader()
        w.writerows(rows)


def write(res: FragilityResult, paths: dict) -> list[str]:
    """The files asked for, each atomically; their descriptions."""
    for path in paths.values():
        if path:
            os.makedirs(os.path.dirname(os.fspath(path)) or ".", exist_ok=True)
    done = []
    if paths["csv"]:
        _write_csv(res.csv_rows(), paths["csv"])
        done.append(f"table: {paths['csv']}")
    if paths["ida_csv"] and res.ida_rows():
        _write_csv(res.ida_rows(), paths["ida_csv"])
        done.append(f"IDA runs: {paths['ida_csv']}")
    if paths["json"]:
        with atomic(paths["json"]) as tmp, open(tmp, "w") as f:
            json.dump(res.to_dict(), f, indent=1, allow_nan=False)
        done.append(f"JSON: {paths['json']}")
    for key, plot, what in (("plot", plot_fragility, "fragility figure"), ("ida_plot", plot_ida, "IDA figure")):
        if paths[key]:
            with atomic(paths[key]) as tmp:
                plot(res, tmp)
            done.append(f"{what}: {paths[key]}")
    return done


def _num(x, fmt: str = ".4g") -> str:
    return "-" if x is None else format(x, fmt)


def _interval(boot: dict | None, key: str, fmt: str = ".4g") -> str:
    if not boot or key not in boot:
        return ""
    lo, hi = boot[key]
    return f" [{lo:{fmt}}, {hi:{fmt}}]"


def table(res: FragilityResult) -> str:
    st, u = res.settings, res.im.unit
    disc = (f"{st['voussoirs']} voussoirs" if st["voussoirs"] else f"{st['elements']} elements")
    geo = res.geometry
    head = (f"block {geo['width']:g} m x {geo['height']:g} m" if geo.get("shape") == "block"
            else f"{arch_title(geo)}, {disc}")
    model = {"simulate": f"simulate (rigid bodies in contact, dt = {st['dt']:g} s)",
             "auto": f"auto (rock while its mechanism is admissible, then rigid bodies in contact, dt = "
                     f"{st['dt']:g} s)"}.get(st["model"], st["model"]) if st["dt"] is not None else st["model"]
    n = res.counts()
    mirrored = "; -1 the mirror image of +1" if n["mirrored"] else ""
    out = [f"fembeam fragility: {head}; suite {res.suite} ({len(res.rows) // 2} records x 2 signs{mirrored})",
           f"  model: {model}; intensity: {res.im.label} ({u}); A_L = {res.A_L['+1']:.6g} g (+1), "
           f"{res.A_L['-1']:.6g} g (-1)",
           f"  search: hunt and fill, resolution {st['resolution']:g} (relative), factors up to {st['span']:g} x the "
           f"onset factor, at most {st['max_runs']} runs a record-sign; runs to {st['t_end']}",
           f"  {'record':<28} {'sign':>4} {'onset':>7} {'first':>8} {'smallest':>8} {'IM at collapse':>14} "
           f"{'safe above':>10} {'runs':>6}"]
    for r in res.rows:
        if r["status"] == "collapsed":
            first, im = _num(r["first_overturning"], ".5g"), _num(r["im_at_collapse"], ".5g")
            smallest = "yes" if r["smallest"] else f"no ({_num(r['resolution_reached'], '.2g')})"
        elif r["status"] == "censored":
            first, im, smallest = "none", f"> {r['censored_at']:.5g}", "-"
        else:
            first, im, smallest = "error", f"> {r['censored_at']:.5g}", "-"
        safe = str(len(r["safe_factors_above"])) if r["safe_factors_above"] else "-"
        runs = "mirror" if r["mirrored"] else str(r["runs"])
        out.append(f"  {r['record'][:28]:<28} {r['sign']:+4d} {_num(r['onset_factor'], '7.4g')} {first:>8} "
                   f"{smallest:>8} {im:>14} {safe:>10} {runs:>6}")
    for r in res.rows:
        for e in ([] if r["mirrored"] else r["errors"]):
            where = "" if e["factor"] is None else f" at factor {e['factor']:.6g}"
            out.append(f"  {r['record']} sign {r['sign']:+d}: search stopped{where}: {e.get('error') or e['outcome']}")
    out.append(f"  collapsed {n['collapsed']} (the smallest at the resolution: {n['smallest']}), censored "
               f"{n['censored']} (no collapse up to the largest factor run), error {n['error']} (censored at the last "
               "safe factor)")
    if n["mirrored"]:
        out.append(f"  the member is symmetric about its vertical axis: sign +1 run, the {n['mirrored']} rows of "
                   "sign -1 its mirror images (runs marked 'mirror'; --both-signs runs them)")
    elif st.get("symmetric"):
        out.append("  the member is symmetric about its vertical axis; both signs run (--both-signs)")
    b = res.bootstrap if res.bootstrap and "error" not in res.bootstrap else None
    if res.fit is None:
        out.append(f"  no lognormal fit: {res.fit_error}")
    else:
        lv = (f"{100 * b['level']:g} % bootstrap intervals, {b['fitted']} of {b['resamples']} resamples of "
              f"{b['groups']} groups" if b else f"no bootstrap interval: {res.bootstrap['error']}")
        out.append(f"  lognormal fit (interval-censored maximum likelihood): median {res.fit['theta']:.4g} {u}"
                   f"{_interval(b, 'theta')}, beta {res.fit['beta']:.3g}{_interval(b, 'beta', '.3g')} ({lv})")
    if res.bootstrap and res.bootstrap.get("grouping"):
        out.append(f"  bootstrap groups: {res.bootstrap['grouping']}")
    if res.design is not None:
        d = res.design
        out.append(f"  design {d['intensity']:g} {u}: collapse margin ratio {d['margin_ratio']:.4g}"
                   f"{_interval(b, 'margin')}, probability of collapse {d['probability_of_collapse']:.3g}"
                   f"{_interval(b, 'probability', '.3g')}")
    tm = res.timing
    steps = f" ({tm['steps']} time steps)" if tm["steps"] else ""
    out.append(f"  {tm['runs']} time histories{steps}; wall time {tm['wall']:.1f} s, CPU in tasks {tm['cases_cpu']:.1f}"
               f" s, {st['executor']}")
    return "\n".join(out)
