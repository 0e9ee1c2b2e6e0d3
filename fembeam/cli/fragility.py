"""``fembeam fragility``: collapse fragility of a member over a record suite.

The computation is :func:`fembeam.studies.fragility.fragility`; this module parses, prints and
writes (``fragility.csv``, ``fragility.json``, ``fragility.png``, ``ida.csv``, ``ida.png``).
"""
from __future__ import annotations

import argparse
import csv
import json
import os
import sys

from ..limits import MAX_COMMAND_RUNS
from ..errors import InputError
from ..output.files import PLOT_SUFFIXES, atomic, atomic_dir, check_dir, check_distinct, check_output
from ..studies.collapse import MAX_RUNS, RESOLUTION, SPAN
from ..studies.fragility import BOOTSTRAP, LEVEL, FragilityResult, fragility, plot_fragility, plot_ida
from ..studies.models import DEFAULT_MODEL, MODELS
from ..studies.parallel import journal_for
from ..studies.runs import DT, T_END_FACTOR
from ..studies.suites import FEMA_SUITES, load_suite
from .args import add_member, arch_title, check_scheduler, finite_float, member_from, note_records, noted, print_result

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
                   help=f"time histories per record and sign at most (default {MAX_RUNS}); records x signs x N "
                        f"is at most {MAX_COMMAND_RUNS}")
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
    check_distinct({f"--{k.replace('_', '-')}" if k in ("csv", "plot", "ida_plot") else f"--out-dir ({FILES[k]})": v
                    for k, v in paths.items()})
    _outside_suite(args.suite, paths)
    return paths


def _outside_suite(suite: str, paths: dict) -> None:
    """InputError if a CSV output would land in the suite folder, where the next run would read it
    as a record."""
    if suite is None or not os.path.isdir(suite):
        return
    folder = os.path.realpath(suite)
    for key, path in paths.items():
        if path and str(path).lower().endswith(".csv") and os.path.dirname(os.path.realpath(path)) == folder:
            raise InputError(f"{path}: a CSV output in the suite folder {suite!r} would be read as a record by "
                             f"the next run; write it elsewhere")


def run(args: argparse.Namespace) -> int:
    paths = _paths(args)
    if args.workers is not None and args.workers < 1:
        raise InputError(f"--workers must be >= 1, got {args.workers}")
    if args.elements is not None and args.elements < 4:
        raise InputError(f"--elements must be >= 4, got {args.elements}")
    if args.voussoirs is not None and args.voussoirs < 1:
        raise InputError(f"--voussoirs must be >= 1, got {args.voussoirs}")
    check_scheduler(args.scheduler)
    from ..studies.intensity import parse_im
    from ..studies.models import check_model
    check_model(args.model, args.dt, names=("--model", "--dt", "--friction"))
    parse_im(args.im)
    curve, voussoirs, elements = member_from(args)
    suite = load_suite(args.suite)
    note_records([r.ground for r in suite.records])
    journal = noted(journal_for(args.out_dir, "fragility", directory=True) if args.out_dir else
                    journal_for(paths["csv"] or paths["plot"] or paths["ida_plot"], "fragility"))
    res = fragility(curve, suite, voussoirs=voussoirs, elements=elements, model=args.model, dt=args.dt, im=args.im,
                    resolution=args.resolution, span=args.factor_span, max_runs=args.max_runs,
                    t_end_factor=args.t_end_factor, design=args.design, bootstrap=args.bootstrap, seed=args.seed,
                    level=args.level, backend=args.backend, workers=args.workers, scheduler=args.scheduler,
                    progress=not args.quiet, journal=journal, mirror=not args.both_signs)
    if res.outcome == "cannot_stand":        # no run: only the JSON answer is a file
        files = [f"--{k.replace('_', '-')}" for k in ("csv", "plot", "ida_plot") if getattr(args, k)]
        if files:
            print(f"fembeam: note: outcome cannot_stand: nothing written for {', '.join(files)}", file=sys.stderr)
        paths = {k: (v if k == "json" else None) for k, v in paths.items()}
    written = write(res, paths, args.out_dir)
    if journal is not None:
        journal.remove()
    return print_result(args.json, res.to_dict, lambda: table(res), written)


def write(res: FragilityResult, paths: dict, out_dir: str | None = None) -> list[str]:
    """The files asked for; those of ``out_dir`` swapped in together (an earlier study's files
    the new set lacks, such as ``ida.png``, removed), the others each atomically; their
    descriptions."""
    def table_writer(rows):
        def write_csv(tmp):
            with open(tmp, "w", newline="") as f:
                w = csv.DictWriter(f, fieldnames=list(rows[0]))
                w.writeheader()
                w.writerows(rows)
        return write_csv

    def write_json(tmp):
        with open(tmp, "w") as f:
            json.dump(res.to_dict(), f, indent=1, allow_nan=False)

    ida = res.ida_rows()
    writers = {"csv": (table_writer(res.csv_rows()), "table"), "ida_csv": (table_writer(ida), "IDA runs") if ida else None,
               "json": (write_json, "JSON"), "plot": (lambda tmp: plot_fragility(res, tmp), "fragility figure"),
               "ida_plot": (lambda tmp: plot_ida(res, tmp), "IDA figure")}
    todo = {k: paths[k] for k in ("csv", "ida_csv", "json", "plot", "ida_plot") if paths[k] and writers[k]}
    inside = {k: p for k, p in todo.items()
              if out_dir is not None and os.path.realpath(os.path.dirname(os.fspath(p)) or ".")
              == os.path.realpath(out_dir) and os.path.basename(os.fspath(p)) == FILES[k]}
    if inside:
        with atomic_dir(out_dir, [FILES[k] for k in inside], stale=list(FILES.values())) as tmps:
            for k, tmp in zip(inside, tmps):
                writers[k][0](tmp)
    for k, path in todo.items():
        if k not in inside:
            os.makedirs(os.path.dirname(os.fspath(path)) or ".", exist_ok=True)
            with atomic(path) as tmp:
                writers[k][0](tmp)
    return [f"{writers[k][1]}: {p}" for k, p in todo.items()]


def _num(x, fmt: str = ".4g") -> str:
    return "-" if x is None else format(x, fmt)


def _interval(boot: dict | None, key: str, fmt: str = ".4g") -> str:
    if not boot or key not in boot:
        return ""
    lo, hi = boot[key]
    return f" [{lo:{fmt}}, {hi:{fmt}}]"


def table(res: FragilityResult) -> str:
    if res.outcome == "cannot_stand":
        geo = res.geometry
        head = (f"block {geo['width']:g} m x {geo['height']:g} m" if geo.get("shape") == "block" else arch_title(geo))
        return "\n".join([f"fembeam fragility: {head}; suite {res.suite}",
                          "  outcome: cannot_stand (the member does not stand under its own weight: fembeam analyze); "
                          "no run, no fragility"])
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
            first, im = _num(r["first_collapse"], ".5g"), _num(r["im_at_collapse"], ".5g")
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
