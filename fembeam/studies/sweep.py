"""Parametric study of arches (paper Fig. 13): r_max against the thickness, one curve per arch.

A sweep runs over a :class:`Family` of arches, ``make(a, b)``: circular arches (``a`` the
embrace angle beta in degrees, ``b = t/R``; the paper's Fig. 13) or the pointed,
elliptical, parabolic or catenary arches of span 1 m (``a = rise/span``, ``b = t/span``,
constant thickness); A_L (in g), r and these ratios do not depend on the scale.

Every (a, b) case is one independent ``analyze`` run (continuous arch, hinge
refinement on) whose *outcome* is always reported: ``rocking`` (r > 0), ``arrested``
(r = 0), ``cannot_stand`` (A_L <= 0, with the thickness it would need), ``no_mechanism`` or
``solver_error`` (the message is kept).  The minimum-thickness envelope has, for each
``a``, t_min (bisection on the LP on ``tmin_elements`` elements) and r_max of the arch
just above it, at t = t_min (1 + ``above``); an arch that stands at every thickness (the
uniform catenary, the funicular of its weight: t_min = 0) or at none is reported with
that outcome (``stands_at_any_thickness``, t_min 0; ``never_stands``, t_min None) and no r.

Cases run in parallel (:mod:`fembeam.studies.parallel`: local processes or Dask), the envelope
first.  Reuse that pays: t_min is computed once per ``a`` and handed to the cases thinner
than it, which then need one LP instead of ``analyze``'s own bisection.  Warm starts do not: the impact QP takes 2-5 %
of a case (``timing`` in the result says how much), Clarabel cannot warm-start and the
HiGHS LP is not warm-startable through scipy.
"""
from __future__ import annotations

import math
import time
from contextlib import nullcontext
from dataclasses import dataclass, field

import numpy as np

from ..analysis import DEFAULT_ELEMENTS, analyze, minimum_thickness
from ..analysis.thickness import MinimumThickness
from ..errors import FembeamError, InputError
from ..fem import discretize, uniform_nodes
from ..geometry.asbuilt import build
from ..geometry import CatenaryArch, CircularArch, EllipticalArch, MidCurve, ParabolicArch, PointedArch
from ..geometry.arch import MIN_T_OVER_SPAN
from ..analysis import limit_analysis
from .parallel import Journal, connect, default_workers, executor_label, run_tasks, shared_pool

__all__ = ["Family", "FAMILIES", "family", "sweep_case", "envelope_case", "SweepResult", "sweep", "sweep_shape",
           "plot_sweep", "FIG13_EMBRACE", "FIG13_T_OVER_R"]

MAX_CASES = 100_000   # cases of one sweep (about 0.3 s of CPU each: 4 hours on 2 cores)
FIG13_EMBRACE = [80.0, 100.0, 120.0, 140.0, 160.0, 180.0]
FIG13_T_OVER_R = [round(0.10 + 0.01 * i, 2) for i in range(21)]

_SHAPE_CLASSES = {"pointed": PointedArch, "elliptical": EllipticalArch, "parabolic": ParabolicArch,
                  "catenary": CatenaryArch}


def _num(x):
    return None if x is None or not np.isfinite(x) else float(x)


@dataclass(frozen=True)
class Family:
    """Arches ``make(a, b)`` of a sweep, with the keys and labels of ``a`` (the curve) and
    ``b`` (the thickness ratio): circular (beta in deg, t/R) or a shape of span 1 m
    (rise/span, t/span)."""

    shape: str
    a_key: str        # JSON/CSV key of a
    b_key: str        # ... of b
    tmin_key: str     # ... of the minimum thickness, in the units of b
    a_label: str      # table and legend
    b_label: str
    a_name: str       # "embrace angle" | "rise/span value"
    a_unit: str = ""

    @property
    def ident(self) -> dict:
        """What rows and results add to name the shape (nothing for the circle, whose keys say it)."""
        return {} if self.shape == "circular" else {"shape": self.shape}

    def make(self, a: float, b: float, fill=None) -> MidCurve:
        """The arch ``a``, ``b`` (InputError if it cannot be built); ``fill``: ``(density, depth)``
        of a fill up to a road ``depth`` m above the crown's extrados (kg/m^3, m;
        :mod:`fembeam.geometry.asbuilt`)."""
        if self.shape == "circular":
            arch = CircularArch.from_ratio(a, b)
        else:
            if not (a > 0 and b > 0):
                raise InputError(f"{self.a_label} and {self.b_label} must be positive")
            arch = _SHAPE_CLASSES[self.shape](span=1.0, rise=a, thickness=b)
        return arch if fill is None else build(arch, fill_density=fill[0], fill_depth=fill[1])

    def base(self, a: float, fill=None) -> float:
        """Thickness ratio at which the minimum-thickness bisection starts: t/R = 0.5, or
        t/span = rise/span / 2 (the same arch for the semicircle), at most half the
        thickness at which the intrados folds."""
        if self.shape == "circular":
            return 0.5
        fold = MIN_T_OVER_SPAN * self.make(a, MIN_T_OVER_SPAN, fill).max_thickness_scale
        return min(0.5 * a, 0.5 * fold)

    def t_min(self, th: MinimumThickness | None, b: float) -> float | None:
        """Minimum thickness in the units of ``b`` of the arch ``th`` was computed on at ``b``:
        0 if it stands at any thickness, None if at none (or not computed)."""
        return None if th is None else _num(th.scale * b)

    def check(self, a_values: list[float], b_values: list[float], fill=None) -> None:
        """InputError, once and naming the case, if an arch of the grid cannot be built."""
        bs = sorted(set(b_values))
        for a in a_values:
            for b in (bs[0], bs[-1]) if bs else ():
                try:
                    self.make(a, b, fill)
                except InputError as e:
                    raise InputError(f"{self.a_label} = {a:g}, {self.b_label} = {b:g}: {e}") from None


FAMILIES = {"circular": Family("circular", "embrace_deg", "t_over_R", "t_min_over_R", "beta", "t/R",
                               "embrace angle", " deg"),
            **{s: Family(s, "rise_over_span", "t_over_span", "t_min_over_span", "rise/span", "t/span",
                         "rise/span value") for s in _SHAPE_CLASSES}}


def family(shape: str) -> Family:
    """The :class:`Family` of ``shape`` (circular, pointed, elliptical, parabolic, catenary)."""
    try:
        return FAMILIES[shape]
    except KeyError:
        raise InputError(f"unknown shape {shape!r}: one of {', '.join(FAMILIES)}") from None


def sweep_case(embrace_deg: float, t_over_r: float, elements: int = DEFAULT_ELEMENTS, backend: str = "auto",
               direction: int = 1, t_min_over_r: float | None = None, shape: str = "circular",
               fill=None) -> dict:
    """One case of the sweep as a flat dict (never raises on solver trouble: the outcome
    is ``"solver_error"`` with the message in ``error``).  For a ``shape`` other than the
    circle, ``embrace_deg`` and ``t_over_r`` are its rise/span and t/span.

    ``t_min_over_r``: the minimum thickness if already known (envelope).  Below it the
    uniform-mesh LP is tried first and, if the arch cannot stand, that is reported with
    this t_min, saving ``analyze`` its own bisection (0.3-0.5 s).  ``fill``: ``(density, depth)``
    of the fill (:meth:`Family.make`)."""
    fam = family(shape)
    a, b = float(embrace_deg), float(t_over_r)
    t0 = time.perf_counter()
    row = {"kind": "case", **fam.ident, fam.a_key: a, fam.b_key: b}
    try:
        arch = fam.make(a, b, fill)
        if t_min_over_r is not None and b < t_min_over_r:
            lim = limit_analysis(discretize(arch, uniform_nodes(arch, elements)), direction)
            if lim.status == "cannot_stand":
                row.update({"outcome": "cannot_stand", "A_L": None, "A_L_mesh": None, "r": None,
                            fam.tmin_key: float(t_min_over_r), "hinges_before": [], "hinges_after": [],
                            "time_s": time.perf_counter() - t0, "time_lp_s": time.perf_counter() - t0,
                            "error": None})
                return row
        res = analyze(arch, elements=elements, backend=backend, direction=direction, thrust=False)
    except FembeamError as e:
        row.update(outcome="solver_error", error=f"{type(e).__name__}: {e}", time_s=time.perf_counter() - t0)
        return row
    v = res.verification.get("impact", {})
    row.update({"outcome": res.outcome, "A_L": _num(res.A_L), "A_L_mesh": _num(res.A_L_mesh), "r": _num(res.r),
                fam.tmin_key: fam.t_min(res.thickness, b),
                "hinges_before": [h.to_dict() for h in res.hinges_before],
                "hinges_after": [h.to_dict() for h in res.hinges_after],
                "qp_equilibrium_residual": _num(v.get("equilibrium_residual", float("nan"))),
                "impulse_line_outside": _num(v.get("impulse_line_outside", float("nan"))),
                "time_s": time.perf_counter() - t0,
                "time_lp_s": res.timings.get("limit", 0.0), "time_refine_s": res.timings.get("continuum", 0.0),
                "time_qp_s": res.timings.get("impact", 0.0), "error": None})
    return row


def envelope_case(embrace_deg: float, elements: int = DEFAULT_ELEMENTS, tmin_elements: int = 400,
                  tmin_tol: float = 1e-6, above: float = 1e-3, backend: str = "auto",
                  direction: int = 1, shape: str = "circular", fill=None) -> dict:
    """Minimum thickness of the arch ``embrace_deg`` (rise/span for a ``shape``) and the
    case at t_min (1 + above); without a t_min > 0 the outcome of the bisection
    (``stands_at_any_thickness``: t_min 0, ``never_stands``: None) and no case.

    t_min from the LP on ``tmin_elements`` elements is >= the value on any coarser
    mesh whose nodes it contains, so the arch analysed just above it stands on
    ``elements`` elements too."""
    fam = family(shape)
    a = float(embrace_deg)
    t0 = time.perf_counter()
    head = {"kind": "envelope", **fam.ident, fam.a_key: a, fam.b_key: None}
    try:
        base = fam.base(a, fill)
        th = minimum_thickness(fam.make(a, base, fill), elements=tmin_elements, tol=tmin_tol)
    except FembeamError as e:
        return {**head, "outcome": "solver_error", "error": f"{type(e).__name__}: {e}",
                "time_s": time.perf_counter() - t0}
    tmin = fam.t_min(th, base)
    if th.outcome != "ok":
        return {**head, "outcome": th.outcome, "A_L": None, "r": None, fam.tmin_key: tmin, "error": None,
                "time_s": time.perf_counter() - t0}
    # just above t_min, but inside the shape's limit (where the intrados folds)
    fold = base * fam.make(a, base, fill).max_thickness_scale * (1.0 - 1e-9)
    row = sweep_case(a, min(tmin * (1.0 + above), fold), elements, backend, direction, shape=shape, fill=fill)
    row.update({"kind": "envelope", fam.tmin_key: float(tmin), "time_s": time.perf_counter() - t0})
    return row


@dataclass
class SweepResult:
    """What :func:`sweep` found: every case of the grid and the minimum-thickness envelope.

    :meth:`to_dict` is its JSON, :meth:`csv_rows` its CSV table (envelope points first).
    The keys of ``a`` and ``b`` in the rows are those of the :attr:`family`:
    ``embrace_deg`` and ``t_over_R`` for circular arches, ``rise_over_span`` and
    ``t_over_span`` for the other shapes.

    Attributes
    ----------
    embrace : list of float
        The grid's ``a`` values: embrace angles beta (deg) of circular arches, rise/span of
        another ``shape``.
    t_over_r : list of float
        The grid's ``b`` values: t/R, or t/span of another ``shape``.
    cases : list of dict
        One per ``(a, b)`` (``kind = "case"``): ``outcome`` (``"rocking"``,
        ``"arrested"``, ``"cannot_stand"``, ``"no_mechanism"`` or ``"solver_error"``
        with the message in ``error``), ``A_L`` and ``A_L_mesh`` (g), ``r``, the minimum
        thickness of an arch that cannot stand (``t_min_over_R`` or ``t_min_over_span``),
        the hinges before and after the impact (deg from the left springing), residuals
        and times (s).
    envelope : list of dict
        One per ``a`` of the envelope (``kind = "envelope"``): the minimum thickness
        (``t_min_over_R`` or ``t_min_over_span``; 0 for ``"stands_at_any_thickness"``,
        None for ``"never_stands"``) and the case just above it, at ``t_min (1 +
        above)``.
    settings : dict
        Mesh, solver, direction, envelope settings, fill and executor.
    wall_time : float
        Wall time of the sweep (s).
    timing : dict
        CPU time (s) of the cases, the envelope, and their LP, hinge refinement and QP.
    shape : str
        ``"circular"``, ``"pointed"``, ``"elliptical"``, ``"parabolic"`` or
        ``"catenary"``.
    family : Family
        The arches of the sweep: the keys and labels of ``a`` and ``b``.

    Examples
    --------
    >>> from fembeam.studies import sweep
    >>> res = sweep([160.0], [0.12, 0.15], elements=40, envelope=False, workers=1,
    ...             progress=False)
    >>> print(res.outcomes(), res.family.a_label, res.family.b_label)
    {'rocking': 2} beta t/R
    >>> print(f"r = {res.case(160.0, 0.15)['r']:.4f}")
    r = 0.6217
    >>> row = res.csv_rows()[0]
    >>> print(row["kind"], row["embrace_deg"], row["t_over_R"], row["hinges_before_side"])
    case 160.0 0.12 intrados;extrados;intrados;extrados
    """

    embrace: list[float]
    t_over_r: list[float]
    cases: list[dict]
    envelope: list[dict]
    settings: dict
    wall_time: float = 0.0
    timing: dict = field(default_factory=dict)
    shape: str = "circular"

    @property
    def family(self) -> Family:
        """The arches of the sweep: the keys and labels of ``a`` and ``b``."""
        return family(self.shape)

    def case(self, embrace_deg: float, t_over_r: float) -> dict:
        """The case at ``a``, ``b`` (beta and t/R, or rise/span and t/span)."""
        fam = self.family
        for c in self.cases:
            if math.isclose(c[fam.a_key], embrace_deg) and math.isclose(c[fam.b_key], t_over_r):
                return c
        raise KeyError((embrace_deg, t_over_r))

    def outcomes(self) -> dict:
        """The number of cases of each outcome."""
        out: dict = {}
        for c in self.cases:
            out[c["outcome"]] = out.get(c["outcome"], 0) + 1
        return out

    def to_dict(self) -> dict:
        """The sweep as JSON: grid, settings, outcomes, cases, envelope and timing."""
        fam = self.family
        return {"study": "sweep", **fam.ident, fam.a_key: self.embrace, fam.b_key: self.t_over_r,
                "settings": self.settings, "outcomes": self.outcomes(), "cases": self.cases,
                "envelope": self.envelope, "wall_time_s": round(self.wall_time, 3), "timing_s": self.timing}

    def csv_rows(self) -> list[dict]:
        """Flat rows for CSV, the envelope points first: hinge lists as ``;``-separated
        angles (deg) and sides."""
        fam = self.family
        cols = ["kind", *fam.ident, fam.a_key, fam.b_key, "outcome", "r", "A_L", "A_L_mesh", fam.tmin_key,
                "hinges_before_deg", "hinges_before_side", "hinges_after_deg", "hinges_after_side",
                "qp_equilibrium_residual", "impulse_line_outside", "time_s", "error"]
        out = []
        for c in self.envelope + self.cases:
            row = {k: c.get(k) for k in cols}
            for key in ("hinges_before", "hinges_after"):
                hs = c.get(key) or []
                row[f"{key}_deg"] = ";".join(f"{h['angle_deg']:.4f}" for h in hs)
                row[f"{key}_side"] = ";".join(h["side"] for h in hs)
            row["time_s"] = round(c.get("time_s", 0.0), 4)
            out.append(row)
        return out


def sweep(embrace: list[float], t_over_r: list[float], elements: int = DEFAULT_ELEMENTS, backend: str = "auto",
          direction: int = 1, envelope: bool = True, envelope_embrace: list[float] | None = None,
          tmin_elements: int = 400, tmin_tol: float = 1e-6, above: float = 1e-3, workers: int | None = None,
          scheduler=None, progress: bool = True, shape: str = "circular", journal: Journal | None = None,
          fill=None) -> SweepResult:
    """Parametric study of arches (the paper's Fig. 13): ``r`` against the thickness.

    Every ``(beta, t/R)`` case is one :func:`~fembeam.analyze` run of the continuous arch
    (hinges refined) whose outcome is always reported; per beta of ``envelope_embrace`` the
    minimum thickness ``t_min`` and the case just above it form the envelope. A_L, r and the
    ratios do not depend on the scale: the arches have a radius (or a span) of 1 m. The
    cases run in parallel, the envelope first; see :ref:`the sweep module <module-sweep>`.

    Parameters
    ----------
    embrace : list of float
        Embrace angles beta (deg) of circular arches; rise/span of another ``shape``.
    t_over_r : list of float
        Thickness ratios t/R; t/span of another ``shape`` (constant thickness).
    elements : int, optional
        Rigid elements of each arch (default
        :data:`~fembeam.analysis.sizes.DEFAULT_ELEMENTS`).
    backend : str, optional
        Solver of the impact QP.
    direction : {1, -1}, optional
        Direction of the inertia load (+1: along ``+x``, a ground acceleration towards
        ``-x``).
    envelope : bool, optional
        Compute the minimum-thickness envelope (default True).
    envelope_embrace : list of float, optional
        The ``a`` values of the envelope (default ``embrace``).
    tmin_elements : int, optional
        Elements of the minimum-thickness bisection (default 400).
    tmin_tol : float, optional
        Relative tolerance of ``t_min`` (default 1e-6).
    above : float, optional
        The envelope's case is at ``t_min (1 + above)`` (default 1e-3).
    workers : int, optional
        Local worker processes (default: the cores this process may use; 1 runs in this
        process).
    scheduler : str or distributed.Client, optional
        A Dask scheduler address (``"tcp://host:8786"``) or client, instead of local
        processes.
    progress : bool, optional
        A progress bar on stderr, when it is a terminal (default True).
    shape : {"circular", "pointed", "elliptical", "parabolic", "catenary"}, optional
        The arches (default ``"circular"``); the other shapes have a span of 1 m, rise
        ``a`` and thickness ``b`` (m), as :func:`sweep_shape`.
    journal : Journal, optional
        Finished cases are kept there and taken from there
        (:class:`~fembeam.studies.parallel.Journal`): an interrupted sweep resumes.
    fill : tuple of (float, float), optional
        ``(density, depth)`` of a fill on every arch: kg/m^3, and m from the crown's
        extrados to the road.

    Returns
    -------
    SweepResult
        The cases and the envelope points; a case that fails to solve is a
        ``"solver_error"`` row, not an exception.

    Raises
    ------
    InputError
        More than 100000 cases, or an arch of the grid that cannot be built (raised
        before any run).

    See Also
    --------
    sweep_case : one case.

    Examples
    --------
    Two embrace angles and two thicknesses, the envelope of the first only:

    >>> from fembeam.studies import sweep
    >>> res = sweep([160.0, 140.0], [0.12, 0.15], elements=40, envelope_embrace=[160.0],
    ...             tmin_elements=80, workers=1, progress=False)
    >>> for c in res.cases:
    ...     print(f"beta {c['embrace_deg']:g} deg, t/R {c['t_over_R']:.2f}:", c["outcome"],
    ...           f"A_L = {c['A_L']:.4f} g, r = {c['r']:.4f}")
    beta 160 deg, t/R 0.12: rocking A_L = 0.2243 g, r = 0.7036
    beta 160 deg, t/R 0.15: rocking A_L = 0.3290 g, r = 0.6217
    beta 140 deg, t/R 0.12: rocking A_L = 0.4213 g, r = 0.5843
    beta 140 deg, t/R 0.15: rocking A_L = 0.5532 g, r = 0.4209
    >>> e = res.envelope[0]
    >>> print(f"beta 160 deg: t_min/R = {e['t_min_over_R']:.4f},",
    ...       f"r just above = {e['r']:.4f}")
    beta 160 deg: t_min/R = 0.0687, r just above = 0.8067
    """
    fam = family(shape)
    n_cases = len(embrace) * len(t_over_r) + (len(envelope_embrace or embrace) if envelope else 0)
    if n_cases > MAX_CASES:
        raise InputError(f"{len(embrace)} x {len(t_over_r)} cases plus the envelope: {n_cases}; a sweep has at most "
                         f"{MAX_CASES} (about 0.3 s of CPU each)")
    fill = None if fill is None else [float(fill[0]), float(fill[1])]
    fam.check(list(embrace) + list(envelope_embrace or []), list(t_over_r), fill)  # bad input fails here, once
    env_as = list(envelope_embrace or embrace) if envelope else []
    # never more local workers than the tasks of the larger phase
    workers = min(workers or default_workers(), max(len(env_as), len(embrace) * len(t_over_r), 1))
    common = {"elements": elements, "backend": backend, "direction": direction, "shape": shape,
              **({} if fill is None else {"fill": fill})}
    clock = time.perf_counter()
    client = None
    if isinstance(scheduler, str):  # one connection for both phases
        client = scheduler = connect(scheduler)
    try:
        with shared_pool(workers) if scheduler is None else nullcontext():   # workers started once
            env = run_tasks([(envelope_case, {"embrace_deg": a, "tmin_elements": tmin_elements, "tmin_tol": tmin_tol,
                                              "above": above, **common}) for a in env_as],
                            workers=workers, scheduler=scheduler, progress=progress, desc="sweep: t_min envelope",
                            journal=journal, lost=_lost_row)
            tmin = {e[fam.a_key]: e.get(fam.tmin_key) for e in env}
            cases = run_tasks([(sweep_case, {"embrace_deg": a, "t_over_r": b, "t_min_over_r": tmin.get(float(a)),
                                             **common}) for a in embrace for b in t_over_r],
                              workers=workers, scheduler=scheduler, progress=progress, desc="sweep: cases",
                              journal=journal, lost=_lost_row)
    finally:
        if client is not None:
            client.close()
    wall = time.perf_counter() - clock
    timing = {"wall": round(wall, 3),
              "cases_cpu": round(sum(c["time_s"] for c in cases), 3),
              "envelope_cpu": round(sum(e["time_s"] for e in env), 3),
              "lp": round(sum(c.get("time_lp_s", 0.0) for c in cases), 3),
              "hinge_refinement": round(sum(c.get("time_refine_s", 0.0) for c in cases), 3),
              "qp": round(sum(c.get("time_qp_s", 0.0) for c in cases), 3)}
    settings = {**fam.ident, "fill": None if fill is None else {"density": fill[0], "depth": fill[1]},
                "elements": elements, "backend": backend, "direction": direction,
                "tmin_elements": tmin_elements, "tmin_tol": tmin_tol, "above": above,
                "executor": executor_label(workers, scheduler, len(cases))}
    return SweepResult(list(embrace), list(t_over_r), cases, env, settings, wall, timing, shape)


def _lost_row(task, message: str) -> dict:
    """The row of a case whose worker process died twice: a failed case, not a crash."""
    func, kw = task
    fam = family(kw.get("shape", "circular"))
    kind = "envelope" if func is envelope_case else "case"
    return {"kind": kind, **fam.ident, fam.a_key: float(kw["embrace_deg"]),
            fam.b_key: float(kw["t_over_r"]) if "t_over_r" in kw else None, "outcome": "solver_error",
            "error": f"the worker process died twice ({message})", "time_s": 0.0}


def sweep_shape(shape: str, rise_over_span: list[float], t_over_span: list[float],
                envelope_rise_over_span: list[float] | None = None, **kwargs) -> SweepResult:
    """:func:`sweep` over the arches ``shape`` (pointed, elliptical, parabolic, catenary) of
    span 1 m, rise ``rise_over_span`` and constant thickness ``t_over_span``."""
    return sweep(rise_over_span, t_over_span, envelope_embrace=envelope_rise_over_span, shape=shape, **kwargs)


OUTCOME_MARKERS = {"arrested": ("x", "arrested (r = 0)"), "cannot_stand": ("v", "cannot stand"),
                   "no_mechanism": ("s", "no mechanism"), "solver_error": ("*", "solver error")}
ENVELOPE_NOTES = {"stands_at_any_thickness": " (stands at any thickness)", "never_stands": " (never stands)"}


def plot_sweep(result: SweepResult, path: str) -> None:
    """Fig. 13: r_max against the thickness ratio per arch, the other outcomes as markers
    on r = 0, and the minimum-thickness envelope (PNG at ``path``)."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fam = result.family
    a_key, b_key = fam.a_key, fam.b_key
    fig, ax = plt.subplots(figsize=(9.6, 5.2))
    colors = plt.cm.viridis(np.linspace(0.0, 0.85, len(result.embrace)))
    seen = set()
    for a, col in zip(result.embrace, colors):
        cs = sorted((c for c in result.cases if c[a_key] == a), key=lambda c: c[b_key])
        t = np.array([c[b_key] for c in cs])
        r = np.array([c["r"] if c["outcome"] in ("rocking", "arrested") else np.nan for c in cs], float)
        note = "".join(ENVELOPE_NOTES.get(e["outcome"], "") for e in result.envelope if e[a_key] == a)
        ax.plot(t, r, "o-", color=col, ms=3.5, lw=1.4, label=f"{fam.a_label} = {a:g}{fam.a_unit}{note}")
        for kind, (mk, lab) in OUTCOME_MARKERS.items():
            sel = [c[b_key] for c in cs if c["outcome"] == kind]
            if sel:
                ax.plot(sel, np.zeros(len(sel)) - (0.0 if kind == "arrested" else 0.03), mk, color=col, ms=6,
                        mfc="none" if kind != "arrested" else col, label=None)
                seen.add(kind)
        for e in result.envelope:
            if e[a_key] == a and e.get("r") is not None:
                ax.plot([e[b_key]], [e["r"]], "D", color=col, ms=6, mec="k", mew=0.6)
    env = sorted((e for e in result.envelope if e.get("r") is not None), key=lambda e: e[b_key])
    if env:
        ax.plot([e[b_key] for e in env], [e["r"] for e in env], "k--", lw=1.2,
                label="minimum-thickness envelope (diamonds)")
    for kind in seen:  # legend entries for the outcome markers, in black
        mk, lab = OUTCOME_MARKERS[kind]
        ax.plot([], [], mk, color="k", mfc="none" if kind != "arrested" else "k", label=lab)
    ax.axhline(1.0, color="0.5", lw=0.8, ls=":")
    ax.set_xlim(0.0, max(result.t_over_r) * 1.02)
    ax.set_ylim(-0.06, 1.05)
    ax.set_xlabel(fam.b_label.replace("/", " / "))
    ax.set_ylabel("$r_{max}$")
    ax.set_title(f"Continuous {fam.shape} arches ({result.settings['elements']} elements, hinges refined)",
                 fontsize=10)
    ax.grid(True, alpha=0.3)
    ax.legend(fontsize=8, loc="upper left", bbox_to_anchor=(1.01, 1.0))
    fig.tight_layout()
    fig.savefig(path, dpi=130)
    plt.close(fig)
