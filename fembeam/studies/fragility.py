"""Collapse fragility of a member over a record suite (incremental dynamic analysis, FEMA P695).

Every record of the suite, with both signs (rocking is not symmetric in the record's sign unless the
member is), is one task: the hunt-and-fill search of its collapse scale factor
(:func:`~fembeam.studies.collapse.record_collapse`) with the runner of the chosen model.  The
intensity measure (:mod:`~fembeam.studies.intensity`) at collapse is the factor times the record's
own; the lognormal fit and its bootstrap intervals (:mod:`~fembeam.studies.lognormal`) follow,
and, given a design intensity, the collapse margin ratio and the probability of collapse there.

**Mirror.**  For a member, loads and model cuts symmetric about a vertical axis
(:func:`~fembeam.geometry.symmetry.is_symmetric`, decided from the geometry to round-off; and
``A_L(+1) = A_L(-1)`` to round-off) the motion under ``-a_g`` is the mirror image of that under
``a_g``: sign +1 is run and the row of sign -1 is its mirror (``mirrored: true``; the same search,
no run of its own).  Asymmetric members run both signs; ``mirror=False`` runs both anyway.

**What each record-sign tells the fit** (``status``, and ``im_interval`` in the intensity's unit):

* ``collapsed``: the first collapse lies in ``[IM at the last safe factor run below the first
  collapse found, IM at that collapse]`` (``smallest`` says whether the scan below it reached the
  resolution);
* ``censored``: no collapse up to the largest factor run: right-censored there, ``[IM there, inf)``;
* ``error``: the search stopped at a run that is neither safe nor a collapse (a solver error, or a
  worker process lost twice) before finding a collapse: right-censored at its last safe factor
  (the onset factor if none), counted in the fit, the error listed.

The fit is the interval-censored maximum likelihood of those intervals
(:func:`~fembeam.studies.lognormal.fit_interval`, ``method: interval_censored``).  The bootstrap
resamples the records' groups (recordings); a record without a group is a group of its own, and
the result says how many there were.

Tasks run on local processes or a Dask cluster (:func:`~fembeam.studies.parallel.run_tasks`): each
is computed on its own, so the table is the same whatever the executor and the number of workers;
with a journal, finished tasks are kept as they finish and an interrupted study resumes.
"""
from __future__ import annotations

import math
import time
from dataclasses import dataclass, field

import numpy as np

from ..dynamics.rocking import Rocker
from ..limits import check_run_count
from ..errors import InputError, SolverError
from ..fem import uniform_nodes
from ..geometry import MidCurve
from ..geometry.symmetry import is_symmetric
from . import lognormal
from .collapse import MAX_RUNS, RESOLUTION, SPAN, check_search, default_t_end, onset_and_top, record_collapse
from .intensity import IntensityMeasure, parse_im
from .models import DEFAULT_MODEL, check_model
from .parallel import Journal, executor_label, run_tasks
from .runs import T_END_FACTOR, check_runs, json_safe
from .suites import Record, Suite

__all__ = ["fragility", "fragility_case", "FragilityResult", "plot_fragility", "plot_ida", "SIGNS", "symmetric_model"]

SIGNS = (1, -1)
BOOTSTRAP = 1000        # default resamples
LEVEL = 0.9             # default confidence level of the intervals


def fragility_case(curve: MidCurve, record: Record, sign: int, model: str, thresholds, voussoirs: int | None,
                   elements: int, backend: str, dt: float | None, resolution: float, span: float, max_runs: int,
                   t_end_factor: float) -> dict:
    """One record-sign (a task of :func:`fragility`): :func:`record_collapse` to the end of the record
    plus ``t_end_factor sqrt(L/g)``."""
    res = record_collapse(curve, record.ground, sign=sign, model=model, thresholds=thresholds, voussoirs=voussoirs,
                          elements=elements, backend=backend, dt=dt, resolution=resolution, span=span,
                          max_runs=max_runs, t_end=default_t_end(record.ground, curve, t_end_factor))
    return json_safe({"record": record.name, **res})


def _lost_case(task, message: str) -> dict:
    """The row of a record-sign whose worker process died twice: no run kept, the error listed;
    its last safe factor is the onset factor (nothing moves below it)."""
    kw = task[1]
    onset, top = onset_and_top(kw["record"].ground, kw["thresholds"], kw["sign"], kw["span"])
    return {"record": kw["record"].name, "sign": kw["sign"], "first_collapse": None, "first_overturning": None,
            "smallest": False, "none_up_to_max": False, "collapse": None, "bracket": [onset, None],
            "resolution": kw["resolution"], "resolution_reached": None, "safe_above": False, "safe_factors_above": [],
            "budget_exhausted": False, "errors": [{"factor": None, "outcome": "lost",
                                                   "error": f"the worker process died twice ({message})"}],
            "onset_factor": onset, "max_factor": top, "runs": 0, "scan": [], "t_end": None, "steps": 0, "time_s": 0.0}


def _status(row: dict) -> str:
    if row["first_collapse"] is not None:
        return "collapsed"
    return "error" if row["errors"] else "censored"


def _mirror(row: dict) -> dict:
    """The row of sign -1 given by the mirror image of ``row`` (sign +1): the same search."""
    import copy
    out = copy.deepcopy(row)
    out.update(sign=-int(row["sign"]), mirrored=True, time_s=0.0)
    return out


def symmetric_model(curve: MidCurve, voussoirs: int | None, elements: int, A_L: dict) -> bool:
    """Whether the member as modelled is its own mirror image: the shape, its as-built fill and
    masses and the cuts of ``voussoirs`` voussoirs (else ``elements`` elements) symmetric about a
    vertical axis (:func:`~fembeam.geometry.symmetry.is_symmetric`), and ``A_L`` (g, ``{+1, -1}``)
    the same both ways to 1e-9 (relative)."""
    a, b = float(A_L[1]), float(A_L[-1])
    if not abs(a - b) <= 1e-9 * max(abs(a), abs(b)):
        return False
    return is_symmetric(curve, nodes=uniform_nodes(curve, voussoirs if voussoirs is not None else elements))


@dataclass
class FragilityResult:
    """The record-signs' searches, the lognormal fit, its intervals and the design margin.

    What :func:`fragility` found: the collapse search of each record-sign and the lognormal
    fit of the intensities at collapse. :meth:`to_dict` is its JSON, :meth:`csv_rows` its
    table (one row per record-sign), :meth:`ida_rows` the runs of the IDA curves.
    Intensities are in the measure's unit (``im.unit``: g, or m/s for PGV).

    Attributes
    ----------
    suite : str
        The suite's name.
    im : IntensityMeasure
        The intensity measure (:func:`~fembeam.studies.intensity.parse_im`).
    rows : list of dict
        One per record-sign: the search's dict (``first_collapse`` factor, ``bracket``,
        ``smallest``, ``scan``, ``runs``, ...), the record's metadata, ``im_record`` (the
        record's own intensity), ``im_at_collapse`` (the first collapse found),
        ``im_interval`` (``[lower, upper]``, what the fit takes; upper None when
        censored), ``censored_at``, ``status`` (``"collapsed"``, ``"censored"`` or
        ``"error"``) and ``mirrored`` (the row of sign -1 given by the mirror image of
        sign +1's, for a symmetric member).
    fit : dict or None
        The interval-censored lognormal fit: ``theta`` (median, the measure's unit),
        ``beta`` (dispersion), ``n_collapsed``, ``n_censored``, ``method``; None when it
        does not exist.
    fit_error : str or None
        Why there is no fit.
    bootstrap : dict or None
        Percentile intervals of ``theta`` and ``beta`` (and of the margin and probability
        with a design intensity) over resamples of the records' groups
        (:func:`~fembeam.studies.lognormal.bootstrap`), or its ``error``.
    design : dict or None
        At the design intensity: ``intensity``, ``margin_ratio`` (``theta / intensity``)
        and ``probability_of_collapse``.
    A_L : dict
        ``A_L`` of the member (g), keys ``"+1"`` and ``"-1"``.
    geometry : dict
        The member's description (its ``describe()``: shape and dimensions in m).
    settings : dict
        Model, time step (s), search, mesh, bootstrap, ``symmetric`` and ``signs_run``.
    timing : dict
        Wall and CPU time (s), runs and time steps.
    outcome : {"computed", "cannot_stand"}
        ``"cannot_stand"``: the member does not stand under its own weight (no rows).

    Examples
    --------
    Two short records (sine cycles of periods 0.5 s and 0.25 s, 0.2 g), a coarse search:
    the arch is symmetric, so sign -1 is the mirror image of sign +1.

    >>> import pathlib, tempfile
    >>> import numpy as np
    >>> import fembeam
    >>> from fembeam.studies.fragility import fragility
    >>> from fembeam.studies.suites import load_suite
    >>> folder = pathlib.Path(tempfile.mkdtemp())
    >>> t = np.linspace(0.0, 0.5, 101)                   # s
    >>> for k, period in enumerate((0.5, 0.25)):         # s
    ...     a = 0.2 * np.sin(2.0 * np.pi * t / period)    # g
    ...     np.savetxt(folder / f"rec{k}.csv", np.c_[t, a], delimiter=",",
    ...                header="time,acceleration", comments="")
    >>> arch = fembeam.CircularArch(radius=1.0, thickness=0.15, embrace_deg=157.5)
    >>> res = fragility(arch, load_suite(str(folder)), voussoirs=12, model="rock",
    ...                 resolution=0.25, t_end_factor=1.0, bootstrap=10, design=0.5,
    ...                 workers=1, progress=False)
    >>> for row in res.rows:
    ...     lo, hi = row["im_interval"]
    ...     print(row["record"], f"{row['sign']:+d}", row["status"],
    ...           f"PGA at collapse in [{lo:.3f}, {hi:.3f}] g",
    ...           "(mirrored)" * row["mirrored"])
    rec0.csv +1 collapsed PGA at collapse in [0.474, 0.541] g
    rec0.csv -1 collapsed PGA at collapse in [0.474, 0.541] g (mirrored)
    rec1.csv +1 collapsed PGA at collapse in [1.057, 1.295] g
    rec1.csv -1 collapsed PGA at collapse in [1.057, 1.295] g (mirrored)
    """

    suite: str
    im: IntensityMeasure
    rows: list[dict]
    fit: dict | None
    fit_error: str | None
    bootstrap: dict | None
    design: dict | None
    A_L: dict
    geometry: dict
    settings: dict
    timing: dict = field(default_factory=dict)
    outcome: str = "computed"

    @property
    def _unit(self) -> str:
        """The intensity's unit in a column name (``g``, ``m_s``)."""
        return self.im.unit.replace("/", "_")

    def counts(self) -> dict:
        """The number of record-signs of each status, ``smallest`` and ``mirrored``."""
        out = {"collapsed": 0, "censored": 0, "error": 0}
        for r in self.rows:
            out[r["status"]] += 1
        out["smallest"] = sum(1 for r in self.rows if r["smallest"])
        out["mirrored"] = sum(1 for r in self.rows if r["mirrored"])
        return out

    def to_dict(self) -> dict:
        """Strict JSON (null for undefined or non-finite numbers)."""
        return json_safe({"study": "fragility", "outcome": self.outcome, "suite": self.suite, "im": self.im.name, "im_unit": self.im.unit,
                           "geometry": self.geometry, "A_L": self.A_L, "settings": self.settings,
                           "counts": self.counts(), "method": "interval_censored", "fit": self.fit,
                           "fit_error": self.fit_error,
                           "bootstrap": self.bootstrap, "design": self.design, "rows": self.rows,
                           "timing_s": self.timing})

    def csv_rows(self) -> list[dict]:
        """One row per record-sign (factors, intensities in the measure's unit)."""
        out = []
        for r in self.rows:
            out.append({"record": r["record"], "sign": r["sign"], "event": r["event"], "station": r["station"],
                        "component": r["component"], "group": r["group"], "normalisation": r["normalisation"],
                        "pga_g": r["pga_g"], "pgv_m_s": r["pgv_m_s"], f"im_record_{self._unit}": r["im_record"],
                        "status": r["status"], "mirrored": r["mirrored"], "onset_factor": r["onset_factor"],
                        "first_collapse": r["first_collapse"], "first_overturning": r["first_collapse"],
                        "smallest": r["smallest"],
                        "resolution_reached": r["resolution_reached"], "bracket_lo": r["bracket"][0],
                        f"im_at_collapse_{self._unit}": r["im_at_collapse"],
                        f"im_lower_{self._unit}": r["im_interval"][0], f"im_upper_{self._unit}": r["im_interval"][1],
                        "censored_at": r["censored_at"], "safe_factors_above": ";".join(
                            f"{x:.6g}" for x in r["safe_factors_above"]),
                        "runs": r["runs"], "steps": r["steps"], "time_s": round(r["time_s"], 4),
                        "errors": ";".join(str(e.get("error") or e["outcome"]) for e in r["errors"])})
        return out

    def ida_rows(self) -> list[dict]:
        """One row per run: record, sign, factor, intensity, outcome, peak rotation (rad), order."""
        return [{"record": r["record"], "sign": r["sign"], "factor": s["factor"],
                 f"im_{self._unit}": s["factor"] * r["im_record"], "outcome": s["outcome"],
                 "peak_rotation_rad": s.get("peak_rotation"), "order": s["order"]}
                for r in self.rows for s in r["scan"]]


def _check(design, n_boot, level, t_end_factor) -> None:
    if design is not None and not (isinstance(design, (int, float)) and math.isfinite(design) and design > 0):
        raise InputError(f"the design intensity must be a positive finite number, got {design!r}")
    if isinstance(n_boot, bool) or not isinstance(n_boot, int) or not 10 <= n_boot <= 100_000:
        raise InputError(f"the bootstrap needs 10 to 100000 resamples, got {n_boot!r}")
    if not (isinstance(level, (int, float)) and 0.5 <= level < 1):
        raise InputError(f"the confidence level must be in [0.5, 1), got {level!r}")
    if not (isinstance(t_end_factor, (int, float)) and math.isfinite(t_end_factor) and 0 < t_end_factor <= 1000):
        raise InputError(f"the t_end factor must be in (0, 1000] (units of sqrt(L/g)), got {t_end_factor!r}")


def fragility(curve: MidCurve, suite: Suite, *, voussoirs: int | None = None, elements: int = 200,
              model: str = DEFAULT_MODEL, dt: float | None = None, im: str = "pga", resolution: float = RESOLUTION,
              span: float = SPAN, max_runs: int = MAX_RUNS, t_end_factor: float = T_END_FACTOR,
              design: float | None = None, bootstrap: int = BOOTSTRAP, seed: int = 0, level: float = LEVEL,
              backend: str = "clarabel", workers: int | None = None, scheduler=None, progress: bool = True,
              journal: Journal | None = None, mirror: bool = True) -> FragilityResult:
    """Collapse fragility of a member over a record suite: IDA, lognormal fit, margin.

    Every record, with both signs, is one task: the hunt-and-fill search of its collapse
    scale factor with the runner of ``model``. The intensities at collapse are fitted by an
    interval-censored lognormal, with bootstrap intervals over the records' groups and,
    given a design intensity, the collapse margin ratio and the probability of collapse
    there. For a symmetric member sign -1 is the mirror image of sign +1, not run. The
    method is described in :mod:`fembeam.studies.fragility`.

    Parameters
    ----------
    curve : MidCurve
        The member (lengths in m, density in kg/m^3).
    suite : Suite
        The records (:func:`~fembeam.studies.suites.load_suite`), accelerations in g.
    voussoirs : int, optional
        Discrete arch of this many voussoirs; otherwise the continuous member on
        ``elements`` rigid elements (default 200).
    elements : int, optional
        See ``voussoirs``.
    model : {"simulate", "rock", "auto"}, optional
        The model of each run (default ``"simulate"``; :mod:`fembeam.studies.models`).
    dt : float, optional
        Time step of ``simulate`` and ``auto`` (s, default 1e-3); none with ``rock``.
    im : str, optional
        The intensity measure: ``"pga"`` (g, the default), ``"pgv"`` (m/s) or ``"sa:T"``
        (g, the 5 %-damped pseudo-spectral acceleration at the period ``T`` in s).
    resolution : float, optional
        Relative step between factors the search must reach below a collapse to call it the
        smallest, in [1e-4, 1] (default 0.05).
    span : float, optional
        Largest factor searched, in onset factors (default 20).
    max_runs : int, optional
        Most runs of each record-sign's search (default 200).
    t_end_factor : float, optional
        Each run lasts to the end of the record plus ``t_end_factor sqrt(L/g)`` (default
        20), in (0, 1000].
    design : float, optional
        A design intensity in the measure's unit (g, or m/s for PGV): the collapse margin
        ratio and the probability of collapse there.
    bootstrap : int, optional
        Resamples of the records' groups for the intervals, in [10, 100000] (default 1000).
    seed : int, optional
        Seed of the resampling (default 0).
    level : float, optional
        Confidence level of the intervals, in [0.5, 1) (default 0.9).
    backend : str, optional
        Solver of the impact QP (default ``"clarabel"``).
    workers : int, optional
        Local worker processes (default: the cores this process may use; 1 runs in this
        process).
    scheduler : str or distributed.Client, optional
        A Dask scheduler address or client, instead of local processes.
    progress : bool, optional
        A progress bar on stderr, when it is a terminal (default True).
    journal : Journal, optional
        Finished record-signs are kept there and taken from there
        (:class:`~fembeam.studies.parallel.Journal`): an interrupted study resumes.
    mirror : bool, optional
        For a symmetric member (:func:`symmetric_model`) run sign +1 only and give sign -1
        as its mirror image (default True); False runs both signs whatever the member.

    Returns
    -------
    FragilityResult
        The rows of the record-signs, the fit, its intervals and the margin; a member that
        cannot stand is an answer (``outcome`` ``"cannot_stand"``), not an exception.

    Raises
    ------
    InputError
        Bad input, before any run.

    Examples
    --------
    Two short records (sine cycles of 0.2 g), a coarse search and few resamples:

    >>> import pathlib, tempfile
    >>> import numpy as np
    >>> import fembeam
    >>> from fembeam.studies.fragility import fragility
    >>> from fembeam.studies.suites import load_suite
    >>> folder = pathlib.Path(tempfile.mkdtemp())
    >>> t = np.linspace(0.0, 0.5, 101)                   # s
    >>> for k, period in enumerate((0.5, 0.25)):         # s
    ...     a = 0.2 * np.sin(2.0 * np.pi * t / period)    # g
    ...     np.savetxt(folder / f"rec{k}.csv", np.c_[t, a], delimiter=",",
    ...                header="time,acceleration", comments="")
    >>> arch = fembeam.CircularArch(radius=1.0, thickness=0.15, embrace_deg=157.5)
    >>> res = fragility(arch, load_suite(str(folder)), voussoirs=12, model="rock",
    ...                 resolution=0.25, t_end_factor=1.0, bootstrap=10, design=0.5,
    ...                 workers=1, progress=False)
    >>> fit = res.fit
    >>> print(f"median PGA at collapse {fit['theta']:.3f} g, beta {fit['beta']:.3f}")
    median PGA at collapse 0.768 g, beta 0.416
    >>> d = res.design
    >>> print(f"at 0.5 g: margin ratio {d['margin_ratio']:.2f},",
    ...       f"P(collapse) {d['probability_of_collapse']:.3f}")
    at 0.5 g: margin ratio 1.54, P(collapse) 0.151
    """
    dt = check_model(model, dt)[0]
    check_search(resolution, span, max_runs)
    measure = parse_im(im)
    _check(design, bootstrap, level, t_end_factor)
    if not isinstance(suite, Suite):
        raise InputError(f"fragility needs a Suite (fembeam.studies.suites.load_suite), got {type(suite).__name__}")
    if not isinstance(mirror, bool):
        raise InputError(f"mirror must be True or False, got {mirror!r}")
    if voussoirs is not None and voussoirs < 1:
        raise InputError(f"voussoirs must be >= 1, got {voussoirs}")
    if voussoirs is None and elements < 4:
        raise InputError(f"elements must be >= 4, got {elements}")
    im_of = {r.name: measure(r.ground) for r in suite.records}
    meta = {r.name: r.metadata() for r in suite.records}
    longest = max(suite.records, key=lambda r: default_t_end(r.ground, curve, t_end_factor) - r.ground.t[0])
    check_runs(model, dt, default_t_end(longest.ground, curve, t_end_factor) - float(longest.ground.t[0]),
                curve, voussoirs, elements)
    clock = time.perf_counter()
    rk = Rocker(curve, voussoirs=voussoirs, elements=elements, backend=backend, qp=False)
    geo = curve.describe() if hasattr(curve, "describe") else {}
    if not rk.stands:             # a physical outcome: the answer, without a run
        settings = {"model": model, "dt": dt, "im": measure.name, "voussoirs": voussoirs,
                    "elements": elements if voussoirs is None else None, "backend": backend}
        return FragilityResult(suite.name, measure, [], None, "the member does not stand under its own weight",
                               None, None, {"+1": None, "-1": None}, geo, settings, {"runs": 0},
                               outcome="cannot_stand")
    for r in suite.records:
        for sign in SIGNS:
            onset_and_top(r.ground, [rk.A[1], rk.A[-1]], sign, span)      # bad input before any run
    symmetric = symmetric_model(curve, voussoirs, elements, rk.A)
    signs = (1,) if symmetric and mirror else SIGNS
    check_run_count(len(suite.records) * len(signs), max_runs,
                    f"{len(suite.records)} records x {len(signs)} sign{'s' if len(signs) > 1 else ''}")
    common = {"curve": curve, "model": model, "thresholds": [rk.A[1], rk.A[-1]], "voussoirs": voussoirs,
              "elements": elements, "backend": backend, "dt": dt, "resolution": resolution, "span": span,
              "max_runs": max_runs, "t_end_factor": t_end_factor}
    tasks = [(fragility_case, {**common, "record": r, "sign": s}) for r in suite.records for s in signs]
    ran = run_tasks(tasks, workers=workers, scheduler=scheduler, progress=progress,
                    desc=f"fragility: {len(suite.records)} records x {len(signs)} sign{'s' if len(signs) > 1 else ''} "
                         f"({model})", journal=journal, lost=_lost_case)
    wall = time.perf_counter() - clock
    rows = []
    for r in ran:
        r["mirrored"] = False
        rows += [r] if len(signs) == 2 else [r, _mirror(r)]
    for r in rows:
        x = im_of[r["record"]]
        f, lo = r["first_collapse"], r["bracket"][0]
        r.update({k: v for k, v in meta[r["record"]].items() if k != "record"}, im_record=x,
                 status=_status(r), im_at_collapse=None if f is None else f * x)
        r["im_interval"] = [lo * x, None if f is None else f * x]
        r["censored_at"] = lo * x if f is None else None
    fit, fit_error, boot, margin = _fit(rows, design, bootstrap, seed, level)
    settings = {"model": model, "dt": dt, "im": measure.name, "resolution": resolution, "span": span,
                "max_runs": max_runs, "t_end": f"end of the record + {t_end_factor:g} sqrt(L/g)",
                "voussoirs": voussoirs, "elements": elements if voussoirs is None else None, "backend": backend,
                "signs": list(SIGNS), "symmetric": symmetric, "signs_run": list(signs), "bootstrap": bootstrap,
                "seed": seed, "level": level, "design": design, "fit": "interval_censored",
                "executor": executor_label(workers, scheduler, len(tasks))}
    timing = {"wall": round(wall, 3), "cases_cpu": round(sum(r["time_s"] for r in ran), 3),
              "runs": sum(r["runs"] for r in ran), "steps": sum(r["steps"] for r in ran)}
    return FragilityResult(suite.name, measure, rows, fit, fit_error, boot, margin, {"+1": rk.A[1], "-1": rk.A[-1]},
                           geo, settings, timing)


def _fit(rows: list[dict], design, n_boot: int, seed: int, level: float):
    """The interval-censored lognormal fit of the rows' ``im_interval``, its bootstrap intervals
    over the groups (a record without a group its own) and the design margin (None where
    undefined)."""
    lower = [r["im_interval"][0] for r in rows]
    upper = [r["im_interval"][1] for r in rows]
    try:
        f = lognormal.fit_interval(lower, upper)
    except (InputError, SolverError) as e:
        return None, str(e), None, None
    alone = sorted({r["record"] for r in rows if not r["group"]})
    samples = [(f"group {r['group']}" if r["group"] else f"record {r['record']}", lo, up)
               for r, lo, up in zip(rows, lower, upper)]
    try:
        boot = lognormal.bootstrap(samples, n=n_boot, seed=seed, level=level, design=design)
    except InputError as e:                 # one group, or every resample without a fit: no interval, the fit stands
        boot = {"error": str(e)}
    boot["records_without_group"] = len(alone)
    if alone:
        boot["grouping"] = (f"{len(alone)} record{'s' if len(alone) > 1 else ''} without a group: each resampled as a "
                            "group of its own (its two signs together)")
    fit = {"theta": f.theta, "beta": f.beta, "n_collapsed": f.n_collapsed, "n_censored": f.n_censored,
           "method": f.method}
    margin = None
    if design is not None:
        margin = {"intensity": float(design), "margin_ratio": f.theta / design,
                  "probability_of_collapse": float(f.probability(design))}
    return fit, None, boot, margin


# --------------------------------------------------------------------------- figures
def plot_fragility(result: FragilityResult, path) -> None:
    """The first collapses found (Kaplan-Meier fraction collapsed, each with its bracket down to
    the last safe intensity), the censored record-signs, the fitted lognormal curve and the
    design intensity if given."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    rows = result.rows
    col = [r["im_at_collapse"] for r in rows if r["status"] == "collapsed"]
    cen = [r["censored_at"] for r in rows if r["status"] != "collapsed"]
    fig, ax = plt.subplots(figsize=(7.0, 4.6))
    if col:
        x, F = lognormal.empirical(col, cen)
        ax.plot(x, F, "o", ms=4, color="tab:blue", mfc="none", label=f"record-signs: first collapse ({len(col)})")
        los = {r["im_at_collapse"]: r["im_interval"][0] for r in rows if r["status"] == "collapsed"}
        ax.hlines(F, [los[v] for v in x], x, color="tab:blue", lw=0.8, alpha=0.6)
    top = max(col + cen + ([result.design["intensity"]] if result.design else []) + [1e-12])
    if result.fit is not None:
        th, be = result.fit["theta"], result.fit["beta"]
        xs = np.linspace(0.0, 1.15 * max(top, th * math.exp(2 * be)), 400)[1:]
        ax.plot(xs, lognormal.probability(xs, th, be), "k-", lw=1.5,
                label=f"lognormal (interval-censored ML): median {th:.4g} {result.im.unit}, beta {be:.3g}")
    if cen:
        ax.plot(cen, [1.02] * len(cen), "^", color="tab:green", ms=5, label=f"no collapse up to ({len(cen)})")
    if result.design is not None:
        d = result.design
        ax.axvline(d["intensity"], color="tab:red", lw=1, ls="--",
                   label=f"design {d['intensity']:g} {result.im.unit}: P = {d['probability_of_collapse']:.3g}, "
                         f"CMR = {d['margin_ratio']:.3g}")
    ax.set_xlabel(f"{result.im.label} at collapse ({result.im.unit})")
    ax.set_ylabel("probability of collapse")
    ax.set_ylim(0.0, 1.06)
    ax.set_xlim(left=0.0)
    ax.set_title(f"Collapse fragility, {result.suite} ({result.settings['model']})", fontsize=10)
    ax.grid(True, alpha=0.3)
    ax.legend(fontsize=8, loc="lower right")
    fig.tight_layout()
    fig.savefig(path, dpi=130)
    plt.close(fig)


def plot_ida(result: FragilityResult, path) -> None:
    """IDA curves: intensity against the peak rotation of every run, per record-sign (safe runs
    joined in order of factor up to the first collapse; collapses as crosses on the flatline at
    the right)."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(7.0, 4.6))
    peaks = [s["peak_rotation"] for r in result.rows for s in r["scan"]
             if s["outcome"] not in ("overturned", "collapsed_by_sliding") and s.get("peak_rotation") is not None]
    edge = 1.1 * max(peaks + [1e-3])
    for r in result.rows:
        x = r["im_record"]
        first = r["first_collapse"]
        safe = [(s["peak_rotation"], s["factor"] * x) for s in r["scan"] if s.get("peak_rotation") is not None
                and s["outcome"] not in ("overturned", "collapsed_by_sliding")
                and (first is None or s["factor"] < first)]
        if safe:
            ax.plot(*zip(*safe), "-", lw=0.6, alpha=0.6)
        if first is not None:
            ax.plot([safe[-1][0] if safe else 0.0, edge], [first * x] * 2, ":", color="0.5", lw=0.6)
        coll = [s["factor"] * x for s in r["scan"] if s["outcome"] in ("overturned", "collapsed_by_sliding")]
        ax.plot([edge] * len(coll), coll, "x", color="tab:red", ms=3)
    ax.set_xlabel("peak rotation of any piece (rad); collapses at the right edge")
    ax.set_ylabel(f"{result.im.label} ({result.im.unit})")
    ax.set_xlim(0.0, edge * 1.05)
    ax.set_ylim(bottom=0.0)
    ax.set_title(f"IDA curves, {result.suite} ({result.settings['model']}, {len(result.rows)} record-signs)",
                 fontsize=10)
    ax.grid(True, alpha=0.3)
    fig.tight_layout()
    fig.savefig(path, dpi=130)
    plt.close(fig)

