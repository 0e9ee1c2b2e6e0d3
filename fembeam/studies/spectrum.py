"""Overturning spectra: the smallest pulse amplitude (or record scale factor) that overturns.

Sign convention (that of :mod:`fembeam.dynamics.rocking`): accelerations are in g, positive
along +x; a positive ``a_g`` loads the member to the *left* (inertia along -x), against the
threshold ``A_L(-1)``; a negative one loads it to the right, against ``A_L(+1)``.  ``sign = +1``
applies a pulse as defined (positive first for rect, sine and Ricker), ``sign = -1`` its mirror
image; a symmetric member gives the same answer for both.

The safe set is not an interval in general: a rocking member can overturn at some amplitude
and survive a larger one (the larger pulse reverses the motion in time).  So
:func:`overturning_amplitude` scans a whole increasing grid, takes the first grid amplitude
that overturns, bisects between it and the safe grid point below it to a relative tolerance,
and reports the scanned amplitudes *above* it that do not overturn (``safe_above``).  Amplitudes
at or below the onset (the member cannot move: ``max(a_g) <= A_L(-1)`` and
``max(-a_g) <= A_L(+1)``) are safe without a run.  The grid's resolution limits what the scan can
see: a safe or an overturning window narrower than a grid step can be missed.

A run counts as overturning when :meth:`Rocker.run` reports ``"overturned"`` before ``t_end``;
motions still under way at ``t_end`` count as safe.  One shortcut is exact
(:meth:`Rocker.settles`, ``"below_barrier"``): once the ground motion is over, ``K + V`` is
conserved along a mechanism and each impact leads to a fixed mechanism with ``K' = r K``, so the
free motion's energies at the impacts follow from the energy at the end of the ground motion
without integration; if each stays below the barrier of its mechanism until the member is at rest,
it cannot overturn.  This avoids the tens to thousands of impacts of a member rocking to rest.

:func:`spectrum` repeats the search per pulse period (sine, Ricker) or duration (rect), one task
per period on local processes or Dask (:mod:`fembeam.studies.parallel`); each task builds its
own :class:`Rocker`, so results do not depend on the executor.  The scale factors of a record
(``fembeam collapse-scale``, ``fembeam assess``'s margins, ``fembeam fragility``) are searched by
hunt and fill at a stated resolution instead (:mod:`fembeam.studies.collapse`).

``model="simulate"`` decides each run with the multi-block simulation instead
(:class:`MultiBody`: :meth:`fembeam.simulation.Simulator.run` with time step ``dt``, stopped at
overturning; optional Coulomb ``friction``).  A run then collapses when its outcome is
``"overturned"`` or ``"collapsed_by_sliding"`` (:data:`COLLAPSE`); the amplitudes are still
called overturning amplitudes, and each row's ``collapse`` says which outcome the upper end of its
bracket had.  There is no energy shortcut (every run lasts to ``t_end`` unless it collapses), and
the no-motion shortcut below ``A_L`` holds only without friction (a joint may slide below
``A_L``).  The :class:`~fembeam.simulation.Simulator` is built once per worker (thread) and
reused by every run of the tasks that worker runs on the same member.
"""
from __future__ import annotations

import functools
import math
import time
from dataclasses import dataclass, field
from typing import Callable, Sequence

import numpy as np

from ..dynamics.equation import GRAVITY
from ..dynamics.ground import PERIOD_RANGE, GroundMotion
from ..dynamics.rocking import Rocker
from ..errors import CannotStandError, InputError, SolverError
from ..geometry import MidCurve
from .models import MultiBody, check_model
from .parallel import Journal, executor_label, run_tasks
from .runs import T_END_FACTOR, check_runs, json_safe, onset_amplitude

__all__ = ["overturning_amplitude", "spectrum", "spectrum_case", "SpectrumResult", "plot_spectrum",
           "pulse", "pulse_end", "geometric_grid", "PULSES", "SAFE", "COLLAPSE"]

PULSES = ("rect", "sine", "ricker")
SAFE = ("no_motion", "rest", "survived", "below_barrier")   # outcomes that are not overturning
COLLAPSE = ("overturned", "collapsed_by_sliding")           # outcomes that count as collapse (sliding: simulate
                                                            # with friction only)
N_GRID = 40             # default grid points (amplitudes)
AMPLITUDE_SPAN = 10.0   # default amplitude grid: onset .. 10 x onset (geometric)
MAX_BISECT = 60         # bound on the bisection steps
MAX_CASES = 10_000      # bound on the scanned (period, amplitude) points of one study


# --------------------------------------------------------------------------- helpers
def pulse(kind: str, amplitude: float, period: float) -> GroundMotion:
    """The pulse ``kind`` (``rect``: ``period`` is its duration) of ``amplitude`` g."""
    if kind == "rect":
        return GroundMotion.rectangular(amplitude, period)
    if kind == "sine":
        return GroundMotion.sine(amplitude, period)
    if kind == "ricker":
        return GroundMotion.ricker(amplitude, period)
    raise InputError(f"the pulse must be one of {', '.join(PULSES)}, got {kind!r}")


def pulse_end(kind: str, period: float) -> float:
    """End of the pulse (s): rect and sine ``period``, Ricker ``3 period``."""
    return 3.0 * period if kind == "ricker" else float(period)


def geometric_grid(lo: float, span: float, n: int) -> list[float]:
    """``n`` points from ``lo`` to ``span * lo``, equal ratios."""
    return [float(x) for x in lo * np.geomspace(1.0, span, n)]


def _cannot_move(ground: GroundMotion, A: dict) -> bool:
    """The ground never exceeds the thresholds (strictly, with 1e-9 relative margin)."""
    return bool(np.max(ground.a) <= A[-1] * (1 + 1e-9) and np.max(-ground.a) <= A[1] * (1 + 1e-9))


def _check_grid(values, name: str) -> list[float]:
    v = [float(x) for x in values]
    if not v:
        raise InputError(f"{name}: give at least one value")
    if len(v) > MAX_CASES:
        raise InputError(f"{name}: at most {MAX_CASES} values, got {len(v)}")
    if not all(math.isfinite(x) and x > 0 for x in v):
        raise InputError(f"{name} must be positive finite numbers, got {values}")
    if any(b <= a for a, b in zip(v, v[1:])):
        raise InputError(f"{name} must be strictly increasing")
    return v


class _Decider:
    """Overturns or not, for one member (a :class:`Rocker` or a :class:`MultiBody`) and one family
    of ground motions."""

    def __init__(self, member, make_ground: Callable[[float], GroundMotion], t_end, sign: int, progress=None):
        self.member, self.make_ground, self.t_end, self.sign, self.progress = member, make_ground, t_end, sign, progress
        self.shortcut = getattr(member, "still_below_onset", True)
        self.runs, self.errors = 0, []

    def __call__(self, a: float) -> str:
        out = self._decide(a)
        if self.progress is not None:
            self.progress(a, out)
        return out

    def _decide(self, a: float) -> str:
        ground = self.make_ground(self.sign * a)
        m = self.member
        if self.shortcut and _cannot_move(ground, m.A):
            return "no_motion"
        self.runs += 1
        try:
            if isinstance(m, MultiBody):
                return m.outcome(ground, self.t_end)
            res = m.run(ground, t_end=self.t_end, thrust_check=False, history=False, settle=True)
            return "below_barrier" if res.settled_at is not None else res.outcome
        except SolverError as e:      # kept, reported; bad input (InputError) propagates
            self.errors.append({"amplitude": float(a), "error": f"{type(e).__name__}: {e}"})
            return "solver_error"


# --------------------------------------------------------------------------- one search
def overturning_amplitude(rocker: Rocker | MultiBody, make_ground: Callable[[float], GroundMotion],
                          amplitudes: Sequence[float], t_end: float | None = None, bisect_tol: float = 1e-3,
                          sign: int = 1, onset: float | None = None, progress: Callable | None = None) -> dict:
    """The smallest amplitude of ``make_ground`` that overturns the member of ``rocker`` (a
    :class:`Rocker`, or a :class:`MultiBody` for the multi-block simulation, whose collapse by
    sliding counts as overturning: :data:`COLLAPSE`).

    ``make_ground(a)``: the ground motion of amplitude ``a`` (g for pulses, a factor for
    records), called with ``sign * a``; ``amplitudes``: the increasing scan grid (> 0);
    ``t_end`` (s): end of each run (None: the end of the ground motion + ``20 sqrt(L/g)``);
    ``bisect_tol``: relative width of the final bracket (at most ``MAX_BISECT`` steps);
    ``onset``: amplitudes up to it cannot move the member (default ``min(A_L(+1), A_L(-1))``,
    right when ``a`` is the peak ``|a_g|``); ``progress(a, outcome)`` after each decision.

    Returns ``first_collapse`` (upper end of the bracket; None if no scanned amplitude
    collapses; ``first_overturning``: a deprecated alias with the same value, kept for one
    release), ``bracket`` ``[lo, hi]`` (lo safe, hi overturning; ``[largest safe, None]``
    without overturning), ``safe_above`` and ``safe_amplitudes_above`` (scanned amplitudes above
    the first overturning one that do not overturn), ``collapse`` (the outcome at the upper end of
    the bracket: ``"overturned"`` or ``"collapsed_by_sliding"``; None without one), ``runs`` (time
    histories computed), ``scan`` (amplitude, outcome) and ``bisection`` steps, ``converged``,
    ``errors``.  Amplitudes up to ``onset`` are not run (``no_motion``) unless the member may slide
    below it (a :class:`MultiBody` with friction)."""
    amps = _check_grid(amplitudes, "the amplitudes")
    if sign not in (1, -1):
        raise InputError(f"sign must be +1 or -1, got {sign!r}")
    if not (0 < bisect_tol < 1):
        raise InputError(f"bisect_tol must be in (0, 1), got {bisect_tol!r}")
    if not rocker.stands:
        raise CannotStandError("the member does not stand under its own weight (fembeam analyze)")
    if onset is None:
        onset = min(rocker.A[1], rocker.A[-1])
    decide = _Decider(rocker, make_ground, t_end, sign, progress)
    scan = [(a, "no_motion" if a <= onset and decide.shortcut else decide(a)) for a in amps]
    over = [i for i, (_, o) in enumerate(scan) if o in COLLAPSE]
    safe = [a for a, o in scan if o in SAFE]
    out = {"first_collapse": None, "first_overturning": None, "bracket": [safe[-1] if safe else None, None],
           "safe_above": False,
           "safe_amplitudes_above": [], "converged": False, "collapse": None, "onset": float(onset), "bisection": []}
    if over:
        i = over[0]
        hi, how = scan[i]
        below = [a for a, o in scan[:i] if o in SAFE]
        if below:
            lo = below[-1]
        else:       # nothing scanned below: the onset if it is safe, else zero ground
            lo = onset if 0 < onset < hi and decide(onset) in SAFE else 0.0
        steps = []
        while hi - lo > bisect_tol * hi and len(steps) < MAX_BISECT:
            mid = 0.5 * (lo + hi)
            o = decide(mid)
            steps.append({"amplitude": mid, "outcome": o})
            if o in COLLAPSE:
                hi, how = mid, o
            elif o in SAFE:
                lo = mid
            else:
                break
        above = [a for a, o in scan[i + 1:] if o in SAFE]
        out.update(first_collapse=hi, first_overturning=hi, bracket=[lo, hi], safe_above=bool(above),
                   safe_amplitudes_above=above,
                   converged=hi - lo <= bisect_tol * hi, collapse=how, bisection=steps)
    out.update(runs=decide.runs, scan=[{"amplitude": a, "outcome": o} for a, o in scan], errors=decide.errors)
    return out


# --------------------------------------------------------------------------- spectrum
def spectrum_case(curve: MidCurve, kind: str, period: float, amplitudes: list[float], t_end: float,
                  voussoirs: int | None = None, elements: int = 200, backend: str = "clarabel",
                  bisect_tol: float = 1e-3, sign: int = 1, onset: float | None = None, model: str = "rock",
                  dt: float | None = None, friction: float | None = None,
                  thresholds: Sequence[float] | None = None) -> dict:
    """One period (a task of :func:`spectrum`): its own :class:`Rocker` (``model="rock"``) or the
    worker's :class:`MultiBody` (``"simulate"``, with ``dt``, ``friction`` and ``thresholds``
    ``[A_L(+1), A_L(-1)]``), then :func:`overturning_amplitude` of ``pulse(kind, a, period)``; a row
    with ``period`` (s), ``t_end`` (s), ``time_s`` and for simulate ``steps`` (time steps run)."""
    clock = time.perf_counter()
    if model != "rock":
        member = MultiBody(curve, {1: thresholds[0], -1: thresholds[1]}, voussoirs=voussoirs, elements=elements,
                           dt=dt, friction=friction, model=model)
    else:
        member = Rocker(curve, voussoirs=voussoirs, elements=elements, backend=backend, qp=False)
    res = overturning_amplitude(member, functools.partial(_pulse_of, kind, period), amplitudes, t_end=t_end,
                                bisect_tol=bisect_tol, sign=sign, onset=onset)
    extra = {"steps": member.steps} if model != "rock" else {}
    return {"period": float(period), **res, "t_end": float(t_end), **extra, "time_s": time.perf_counter() - clock}


def _pulse_of(kind: str, period: float, amplitude: float) -> GroundMotion:
    return pulse(kind, amplitude, period)


@dataclass
class SpectrumResult:
    """What :func:`spectrum` found: the overturning amplitude of each pulse period.

    :meth:`to_dict` is its JSON, :meth:`csv_rows` its CSV table. Amplitudes are in g,
    positive along ``+x`` (see :mod:`fembeam.studies.spectrum` for the sign convention).

    Attributes
    ----------
    kind : {"rect", "sine", "ricker"}
        The pulse.
    sign : {1, -1}
        The pulse as defined (+1: positive first) or its mirror image (-1).
    rows : list of dict
        One per period: ``period`` (s; the duration of rect pulses), ``first_collapse``
        (g: the smallest amplitude found to overturn, the upper end of ``bracket``; None
        if none up to the grid's largest; ``first_overturning``: a deprecated alias with
        the same value), ``bracket`` ``[safe, overturning]`` (g), ``converged``,
        ``safe_above`` and ``safe_amplitudes_above`` (g: scanned amplitudes above the
        first overturning one that do not overturn), ``collapse`` (the outcome at the
        upper end), ``runs``, ``scan`` and ``bisection`` (amplitude and outcome of each
        decision), ``errors``, ``t_end`` (s) and ``time_s``.
    A_L : dict
        ``A_L`` (g) of the member both ways, keys ``1`` and ``-1``.
    onset : float
        The amplitude (g) at which the pulse first moves the member (NaN when it cannot
        stand).
    amplitudes : list of float
        The scanned grid (g).
    geometry : dict
        The member's description (its ``describe()``: shape and dimensions in m).
    settings : dict
        Model, mesh, solver, tolerances, grid and executor.
    wall_time : float
        Wall time of the study (s).
    timing : dict
        Wall and CPU time (s), runs (and time steps of ``simulate``).
    model : {"rock", "simulate", "auto"}
        The model of each run.
    outcome : {"computed", "cannot_stand"}
        ``"cannot_stand"``: the member does not stand under its own weight (rows without
        runs).

    Examples
    --------
    One period, three amplitudes (g) given, a coarse bisection:

    >>> import fembeam
    >>> from fembeam.studies.spectrum import spectrum
    >>> arch = fembeam.CircularArch(radius=1.0, thickness=0.15, embrace_deg=157.5)
    >>> res = spectrum(arch, "sine", [0.5], voussoirs=12, amplitudes=[0.4, 0.5, 0.6],
    ...                bisect_tol=0.05, t_end_factor=5.0, workers=1, progress=False)
    >>> row = res.rows[0]
    >>> for step in row["scan"] + row["bisection"]:
    ...     print(f"{step['amplitude']:.4f} g: {step['outcome']}")
    0.4000 g: below_barrier
    0.5000 g: overturned
    0.6000 g: overturned
    0.4500 g: below_barrier
    0.4750 g: overturned
    0.4625 g: below_barrier
    >>> csv = res.csv_rows()[0]
    >>> print(csv["period_s"], csv["first_collapse_g"], csv["outcome"])
    0.5 0.475 overturns
    """

    kind: str
    sign: int
    rows: list[dict]
    A_L: dict
    onset: float
    amplitudes: list[float]
    geometry: dict
    settings: dict
    wall_time: float = 0.0
    timing: dict = field(default_factory=dict)
    model: str = "rock"
    outcome: str = "computed"     # or "cannot_stand": the member does not stand (rows without runs)

    def to_dict(self) -> dict:
        """JSON-safe (null for undefined or non-finite numbers)."""
        return json_safe({"study": "spectrum", "outcome": self.outcome, "model": self.model,
                           "collapse_outcomes": _collapse_outcomes(self.model),
                           "pulse": self.kind, "sign": self.sign,
                           "abscissa": "duration_s" if self.kind == "rect" else "period_s",
                           "geometry": self.geometry, "A_L": {"+1": self.A_L[1], "-1": self.A_L[-1]},
                           "onset_g": self.onset, "amplitudes_g": self.amplitudes, "settings": self.settings,
                           "rows": self.rows, "wall_time_s": round(self.wall_time, 3), "timing_s": self.timing})

    def csv_rows(self) -> list[dict]:
        """One row per period: amplitudes in g and over the onset; empty cells for none.

        Returns
        -------
        list of dict
            ``first_collapse_g`` and ``first_collapse_over_onset`` name the first collapse;
            ``first_overturning_g`` and ``first_overturning_over_onset`` are deprecated aliases
            with the same values, kept for one release.
        """
        out = []
        for r in self.rows:
            a, (lo, hi) = r["first_collapse"], r["bracket"]
            over = None if a is None else a / self.onset
            out.append({"period_s": r["period"], "first_collapse_g": a, "first_collapse_over_onset": over,
                        "first_overturning_g": a, "first_overturning_over_onset": over,
                        "bracket_lo_g": lo, "bracket_hi_g": hi, "safe_above": r["safe_above"],
                        "safe_amplitudes_above_g": ";".join(f"{x:.6g}" for x in r["safe_amplitudes_above"]),
                        "runs": r["runs"], "errors": len(r["errors"]), "time_s": round(r["time_s"], 4)})
            if self.model != "rock":
                out[-1].update(collapse=r.get("collapse") or "", steps=r.get("steps", 0))
            out[-1]["outcome"] = r.get("outcome") or ("overturns" if a is not None else "no_overturning")
        return out


def _collapse_outcomes(model: str) -> list[str]:
    """The outcomes a search counts as collapse (rock has no sliding)."""
    return list(COLLAPSE) if model != "rock" else ["overturned"]


def _check_spectrum(kind, periods, voussoirs, elements, amplitudes, bisect_tol, t_end_factor, sign, n_amplitudes,
                    span) -> list[float]:
    if kind not in PULSES:
        raise InputError(f"the pulse must be one of {', '.join(PULSES)}, got {kind!r}")
    ps = [float(p) for p in periods]
    if not ps:
        raise InputError("give at least one pulse period (duration for rect)")
    lo, hi = PERIOD_RANGE
    if not all(math.isfinite(p) and lo <= p <= hi for p in ps):
        raise InputError(f"pulse periods (durations) must be in [{lo:g}, {hi:g}] s, got {periods}")
    if voussoirs is not None and voussoirs < 1:
        raise InputError(f"voussoirs must be >= 1, got {voussoirs}")
    if voussoirs is None and elements < 4:
        raise InputError(f"elements must be >= 4, got {elements}")
    if not (0 < bisect_tol <= 0.1):
        raise InputError(f"the bisection tolerance must be in (0, 0.1], got {bisect_tol!r}")
    if not (math.isfinite(t_end_factor) and 0 < t_end_factor <= 1000):
        raise InputError(f"the t_end factor must be in (0, 1000] (units of sqrt(L/g)), got {t_end_factor!r}")
    if sign not in (1, -1):
        raise InputError(f"sign must be +1 or -1, got {sign!r}")
    if amplitudes is not None:
        n_amplitudes = len(_check_grid(amplitudes, "the amplitudes"))
    elif not (2 <= n_amplitudes <= MAX_CASES and math.isfinite(span) and span > 1):
        raise InputError(f"the default amplitude grid needs 2..{MAX_CASES} points and a span > 1")
    if len(ps) * n_amplitudes > MAX_CASES:
        raise InputError(f"{len(ps)} periods x {n_amplitudes} amplitudes = {len(ps) * n_amplitudes} scanned cases: "
                         f"at most {MAX_CASES}")
    return ps


def spectrum(curve: MidCurve, kind: str, periods: Sequence[float], voussoirs: int | None = None,
             elements: int = 200, amplitudes: Sequence[float] | None = None, workers: int | None = None,
             scheduler=None, progress: bool = True, bisect_tol: float = 1e-3, t_end_factor: float = T_END_FACTOR,
             *, sign: int = 1, backend: str = "clarabel", n_amplitudes: int = N_GRID,
             span: float = AMPLITUDE_SPAN, journal: Journal | None = None, model: str = "rock",
             dt: float | None = None, friction: float | None = None) -> SpectrumResult:
    """Overturning spectrum: the smallest pulse amplitude that overturns, per period.

    For each period the whole amplitude grid is scanned (the safe set is not an interval in
    general: a larger pulse can reverse the motion in time), the first amplitude that
    overturns is bisected against the safe one below it, and the safe amplitudes above it
    are reported. The search, its shortcuts and the sign convention are those of
    :mod:`fembeam.studies.spectrum`. One task per period, on local processes or Dask.

    Parameters
    ----------
    curve : MidCurve
        The member (lengths in m, density in kg/m^3).
    kind : {"rect", "sine", "ricker"}
        The pulse.
    periods : sequence of float
        Pulse periods (s; durations of rect pulses), within
        :data:`~fembeam.dynamics.ground.PERIOD_RANGE`.
    voussoirs : int, optional
        Discrete arch of this many voussoirs; otherwise the continuous member on
        ``elements`` rigid elements (default 200).
    elements : int, optional
        See ``voussoirs``.
    amplitudes : sequence of float, optional
        The scanned amplitudes (g, > 0, increasing). Default: ``n_amplitudes`` geometric
        points from the onset amplitude (``A_L`` of the direction the pulse loads first) to
        ``span`` times it.
    workers : int, optional
        Local worker processes (default: the cores this process may use; 1 runs in this
        process).
    scheduler : str or distributed.Client, optional
        A Dask scheduler address or client, instead of local processes.
    progress : bool, optional
        A progress bar on stderr, when it is a terminal (default True).
    bisect_tol : float, optional
        Relative width of the final bracket, in (0, 0.1] (default 1e-3).
    t_end_factor : float, optional
        Each run lasts to the end of the pulse plus ``t_end_factor sqrt(L/g)`` (default
        20), in (0, 1000].
    sign : {1, -1}, optional
        The pulse as defined (positive first: it loads the member to the left, against
        ``A_L(-1)``) or its mirror image.
    backend : str, optional
        Solver of the impact QP (default ``"clarabel"``).
    n_amplitudes : int, optional
        Points of the default grid (default 40).
    span : float, optional
        Largest amplitude of the default grid over the onset amplitude (> 1, default 10).
    journal : Journal, optional
        Finished periods are kept there and taken from there
        (:class:`~fembeam.studies.parallel.Journal`): an interrupted spectrum resumes. The
        tasks' keys hold the model and its ``dt`` and ``friction``.
    model : {"rock", "simulate", "auto"}, optional
        The model of each run (default ``"rock"``); with ``"simulate"``
        (:class:`~fembeam.studies.models.MultiBody`) a collapse by sliding counts as
        overturning.
    dt : float, optional
        Time step of ``simulate`` and ``auto`` (s, default 1e-3).
    friction : float, optional
        Coulomb coefficient of the joints of ``simulate`` and ``auto`` (default None: no
        sliding).

    Returns
    -------
    SpectrumResult
        One row per period; a member that cannot stand is an answer (``outcome``
        ``"cannot_stand"``, rows without runs), not an exception.

    Raises
    ------
    InputError
        Bad input, before any run: an unknown pulse, a period out of range, a bad grid or
        tolerance, too many scanned cases, ``dt`` or ``friction`` with ``model="rock"``, or
        a member that no pulse can set moving.

    See Also
    --------
    overturning_amplitude : the search of one period.

    Examples
    --------
    Sine pulses of periods 0.5 s and 1 s on the paper's arch of 12 voussoirs, a coarse
    grid from the onset (``A_L``, 0.3593 g) to three times it:

    >>> import fembeam
    >>> from fembeam.studies.spectrum import spectrum
    >>> arch = fembeam.CircularArch(radius=1.0, thickness=0.15, embrace_deg=157.5)
    >>> res = spectrum(arch, "sine", [0.5, 1.0], voussoirs=12, n_amplitudes=6, span=3.0,
    ...                bisect_tol=0.01, t_end_factor=5.0, workers=1, progress=False)
    >>> print(f"onset {res.onset:.4f} g")
    onset 0.3593 g
    >>> for row in res.rows:
    ...     lo, hi = row["bracket"]
    ...     print(f"T = {row['period']} s: overturns from {hi:.3f} g (safe at {lo:.3f} g)")
    T = 0.5 s: overturns from 0.475 g (safe at 0.472 g)
    T = 1.0 s: overturns from 0.414 g (safe at 0.412 g)
    """
    dt, friction = check_model(model, dt, friction)
    ps = _check_spectrum(kind, periods, voussoirs, elements, amplitudes, bisect_tol, t_end_factor, sign,
                         n_amplitudes, span)
    check_runs(model, dt, max(pulse_end(kind, p) for p in ps) + t_end_factor * math.sqrt(curve.length / GRAVITY),
                curve, voussoirs, elements)
    clock = time.perf_counter()
    rk = Rocker(curve, voussoirs=voussoirs, elements=elements, backend=backend, qp=False)
    settings = {"model": model, "voussoirs": voussoirs, "elements": elements if voussoirs is None else None,
                "backend": backend, "bisect_tol": bisect_tol, "t_end_factor": t_end_factor,
                "t_end": "pulse end + t_end_factor sqrt(L/g)",
                "grid": "given" if amplitudes is not None else f"geometric, {n_amplitudes} points, onset to {span:g} x",
                "executor": executor_label(workers, scheduler, len(ps))}
    if model != "rock":
        settings.update(dt=dt, friction=friction)
    geo = curve.describe() if hasattr(curve, "describe") else {}
    if not rk.stands:             # a physical outcome, the answer for every period
        wall = time.perf_counter() - clock
        return SpectrumResult(kind, sign, [_cannot_stand_row(p, model) for p in ps], dict(rk.A), math.nan, [], geo,
                              settings, wall, {"wall": round(wall, 3), "cases_cpu": 0.0, "runs": 0}, model,
                              "cannot_stand")
    onset = onset_amplitude(rk.A, pulse(kind, float(sign), 1.0))
    if not math.isfinite(onset):
        raise InputError("no pulse of this kind can set the member moving (no mechanism: A_L infinite)")
    grid = [float(a) for a in amplitudes] if amplitudes is not None else geometric_grid(onset, span, n_amplitudes)
    free = t_end_factor * math.sqrt(curve.length / rk.g)
    common = {"curve": curve, "kind": kind, "amplitudes": grid, "voussoirs": voussoirs, "elements": elements,
              "backend": backend, "bisect_tol": bisect_tol, "sign": sign, "onset": onset, "model": model}
    if model != "rock":
        common.update(dt=dt, friction=friction, thresholds=[rk.A[1], rk.A[-1]])
    rows = run_tasks([(spectrum_case, {**common, "period": p, "t_end": pulse_end(kind, p) + free}) for p in ps],
                     workers=workers, scheduler=scheduler, progress=progress,
                     desc=f"spectrum: {kind} pulses" + (f" ({model})" if model != "rock" else ""),
                     journal=journal, lost=_lost_period)
    wall = time.perf_counter() - clock
    timing = {"wall": round(wall, 3), "cases_cpu": round(sum(r["time_s"] for r in rows), 3),
              "runs": sum(r["runs"] for r in rows)}
    if model != "rock":
        timing["steps"] = sum(r.get("steps", 0) for r in rows)
    return SpectrumResult(kind, sign, rows, dict(rk.A), onset, grid, geo, settings, wall, timing, model)


def _cannot_stand_row(period: float, model: str) -> dict:
    """The row of a period for a member that cannot stand: no run, no amplitude."""
    return {"period": float(period), "outcome": "cannot_stand", "first_collapse": None,
            "first_overturning": None, "bracket": [None, None],
            "safe_above": False, "safe_amplitudes_above": [], "converged": False, "collapse": None, "onset": None,
            "scan": [], "bisection": [], "runs": 0, "errors": [], "time_s": 0.0,
            **({"steps": 0} if model != "rock" else {})}


def _lost_period(task, message: str) -> dict:
    """The row of a period whose worker process died twice: undecided, with the error."""
    kw = task[1]
    extra = {"steps": 0} if kw.get("model", "rock") != "rock" else {}
    return {"period": float(kw["period"]), "first_collapse": None, "first_overturning": None, "bracket": [None, None],
            "safe_above": False,
            "safe_amplitudes_above": [], "converged": False, "collapse": None, "onset": kw["onset"], "bisection": [],
            "runs": 0, "errors": [f"the worker process died twice ({message})"], "t_end": float(kw["t_end"]),
            **extra, "time_s": 0.0}


def plot_spectrum(result: SpectrumResult, path) -> None:
    """Overturning amplitude over the onset against period (duration for rect): the bisected
    curve, the scanned amplitudes that overturn (red) and the safe ones above the first
    overturning amplitude (green: safe regions above)."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    A0 = result.onset
    rows = sorted(result.rows, key=lambda r: r["period"])
    fig, ax = plt.subplots(figsize=(8.0, 5.0))
    if result.outcome == "cannot_stand":
        ax.text(0.5, 0.5, "the member does not stand under its own weight", ha="center", va="center",
                transform=ax.transAxes)
        ax.set_axis_off()
        fig.savefig(path, dpi=130)
        plt.close(fig)
        return
    over = [(r["period"], s["amplitude"] / A0) for r in rows for s in r["scan"] if s["outcome"] == "overturned"]
    slid = [(r["period"], s["amplitude"] / A0) for r in rows for s in r["scan"]
            if s["outcome"] == "collapsed_by_sliding"]
    above = [(r["period"], a / A0) for r in rows for a in r["safe_amplitudes_above"]]
    if over:
        ax.plot(*zip(*over), ".", color="tab:red", ms=3, alpha=0.5, label="scanned: overturns")
    if slid:
        ax.plot(*zip(*slid), "x", color="tab:purple", ms=4, alpha=0.7, label="scanned: collapses by sliding")
    if above:
        ax.plot(*zip(*above), "o", color="tab:green", mfc="none", ms=5,
                label="scanned: safe above the first overturning")
    x = [r["period"] for r in rows]
    y = [np.nan if r["first_collapse"] is None else r["first_collapse"] / A0 for r in rows]
    ax.plot(x, y, "k-o", ms=3.5, lw=1.3, label="first overturning amplitude (bisected)")
    none = [r["period"] for r in rows if r["first_collapse"] is None]
    if none:
        top = max(result.amplitudes) / A0
        ax.plot(none, [top] * len(none), "^", color="k", mfc="none", ms=6,
                label=f"no overturning up to {top:.3g} x onset")
    ax.set_xlabel("pulse duration (s)" if result.kind == "rect" else "pulse period (s)")
    ax.set_ylabel(f"amplitude / onset ({A0:.4g} g)")
    ax.set_ylim(bottom=0.0)
    model = "" if result.model == "rock" else (f", simulate (dt = {result.settings['dt']:g} s"
                                               + ("" if result.settings.get("friction") is None
                                                  else f", friction {result.settings['friction']:g}") + ")")
    ax.set_title(f"Overturning spectrum, {result.kind} pulses (sign {result.sign:+d}){model}", fontsize=10)
    ax.grid(True, alpha=0.3)
    ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(path, dpi=130)
    plt.close(fig)
