"""The collapse scale factor of one record (and sign) by the hunt-and-fill search.

:func:`record_collapse` runs :func:`~fembeam.studies.huntfill.hunt_and_fill` over the scale
factors of a record with the runner of a model (:mod:`fembeam.studies.models`); it is one task of
a fragility study and the whole of :func:`collapse_scale` (``fembeam collapse-scale``).

Sign convention (that of :mod:`fembeam.dynamics.rocking`): accelerations in g, positive along +x;
``sign = -1`` runs the mirrored record.  The onset factor is the smallest at which the record
exceeds ``A_L`` either way (``min(A_L(-1) / max(a), A_L(+1) / max(-a))``): below it nothing moves
and no run is made.  Each run lasts to ``t_end`` (default: the end of the record plus
:data:`~fembeam.studies.runs.T_END_FACTOR` ``sqrt(L/g)``); a motion still under way then counts
as safe.
"""
from __future__ import annotations

import math
import time
from typing import Callable

from ..dynamics.equation import GRAVITY
from ..dynamics.ground import MAX_PGA, GroundMotion
from ..dynamics.rocking import Rocker
from ..errors import CannotStandError, InputError
from ..geometry import MidCurve
from .huntfill import hunt_and_fill
from .models import check_model, runner
from .runs import T_END_FACTOR, check_runs, json_safe, onset_amplitude

__all__ = ["record_collapse", "collapse_scale", "onset_and_top", "RESOLUTION", "SPAN", "MAX_RUNS", "default_t_end"]

RESOLUTION = 0.05     # default relative step between factors the search must reach below a collapse
SPAN = 20.0           # default largest factor, in onset factors
MAX_RUNS = 200        # default run budget of one search


def default_t_end(ground: GroundMotion, curve: MidCurve, t_end_factor: float = T_END_FACTOR) -> float:
    """End of the record plus ``t_end_factor sqrt(L/g)`` (s; L the member's length)."""
    return float(ground.t[-1]) + t_end_factor * math.sqrt(curve.length / GRAVITY)


def check_search(resolution: float, span: float, max_runs: int) -> None:
    """InputError for a search setting out of range (before any run)."""
    if not (isinstance(resolution, (int, float)) and math.isfinite(resolution) and 1e-4 <= resolution <= 1.0):
        raise InputError(f"the resolution must be in [1e-4, 1] (relative step between factors), got {resolution!r}")
    if not (isinstance(span, (int, float)) and math.isfinite(span) and 1.0 < span <= 1000.0):
        raise InputError(f"the span must be in (1, 1000] (largest factor over the onset factor), got {span!r}")
    if isinstance(max_runs, bool) or not isinstance(max_runs, int) or not 1 <= max_runs <= 100_000:
        raise InputError(f"the run budget must be an integer in [1, 100000], got {max_runs!r}")


def onset_and_top(ground: GroundMotion, thresholds, sign: int, span: float) -> tuple[float, float]:
    """The onset factor of ``ground`` times ``sign`` and the largest factor ``span`` times it;
    InputError if the record cannot move the member or if the largest factor's PGA exceeds the
    admitted ``MAX_PGA`` (before any run)."""
    A = {1: float(thresholds[0]), -1: float(thresholds[1])}
    f0 = onset_amplitude(A, ground.scaled(sign))
    if not math.isfinite(f0):
        raise InputError(f"{ground.name}: no scale factor can set the member moving (A_L infinite)")
    if span * f0 * ground.pga > MAX_PGA:
        raise InputError(f"{ground.name}: the largest factor, {span:g} x the onset factor {f0:.4g}, gives a PGA of "
                         f"{span * f0 * ground.pga:.4g} g; at most {MAX_PGA:g} g is admitted (accelerations are in "
                         "g): lower the span")
    return f0, span * f0


def record_collapse(curve: MidCurve, ground: GroundMotion, *, sign: int, model: str, thresholds,
                    voussoirs: int | None = None, elements: int = 200, backend: str = "clarabel",
                    dt: float | None = None, friction: float | None = None, resolution: float = RESOLUTION,
                    span: float = SPAN, max_runs: int = MAX_RUNS, t_end: float | None = None,
                    progress: Callable | None = None) -> dict:
    """The hunt-and-fill search over the scale factors of ``ground`` (times ``sign``) with the
    runner of ``model``; ``thresholds`` ``[A_L(+1), A_L(-1)]`` (g) of the member.  Factors from the
    onset factor to ``span`` times it.  The dict of :func:`~fembeam.studies.huntfill.hunt_and_fill`
    with each run's ``outcome``, ``peak_rotation`` (rad) and ``steps``, plus ``sign``, ``t_end``
    (s), ``steps`` (all runs), ``time_s``.  ``progress(factor, outcome)`` after each run.  With
    ``friction`` a joint may slide below ``A_L``: the onset factor is run, nothing below it is
    searched and no factor is called the smallest."""
    clock = time.perf_counter()
    f0, top = onset_and_top(ground, thresholds, sign, span)
    t_end = default_t_end(ground, curve) if t_end is None else float(t_end)
    one = runner(model, curve, voussoirs=voussoirs, elements=elements, thresholds=thresholds, dt=dt,
                 friction=friction, backend=backend)

    def run(f: float) -> dict:
        out = one(ground.scaled(sign * f), t_end)
        if progress is not None:
            progress(f, out["outcome"])
        return out

    res = hunt_and_fill(run, f0, resolution=resolution, max_factor=top, max_runs=max_runs,
                        onset_safe=friction is None)
    res.update(sign=int(sign), t_end=t_end, steps=sum(r["steps"] for r in res["scan"]),
               time_s=time.perf_counter() - clock)
    return res


def collapse_scale(curve: MidCurve, ground: GroundMotion, voussoirs: int | None = None, elements: int = 200, *,
                   t_end: float | None = None, resolution: float = RESOLUTION, span: float = SPAN,
                   max_runs: int = MAX_RUNS, sign: int = 1, backend: str = "clarabel", progress: Callable | None = None,
                   model: str = "rock", dt: float | None = None, friction: float | None = None) -> dict:
    """The smallest scale factor of a ground motion at which a member collapses.

    ``first_collapse`` and ``pga_at_first_collapse`` (g) name the first collapse, by
    overturning or by sliding; ``first_overturning`` and ``pga_at_first_overturning`` are
    deprecated aliases with the same values, kept for one release.

    A hunt-and-fill search (:func:`record_collapse`) over the factors of the motion, from
    the onset factor (where the inertia load first reaches ``A_L``) up to ``span``
    onset factors.

    Parameters
    ----------
    curve : MidCurve
        The member (lengths in m, density in kg/m^3).
    ground : GroundMotion
        The motion as given (g, positive along ``+x``); factors scale it.
    voussoirs : int, optional
        Discrete arch of this many voussoirs; otherwise the continuous member on
        ``elements`` rigid elements (default 200).
    elements : int, optional
        See ``voussoirs``.
    t_end : float, optional
        End of every run (s), default the end of the motion plus ``20 sqrt(L/g)``.
    resolution : float, optional
        Relative step between factors at which the search stops, in [1e-4, 1].
    span : float, optional
        Largest factor searched, in onset factors.
    max_runs : int, optional
        Most runs of the search.
    sign : {1, -1}, optional
        The motion as given or mirrored.
    backend : str, optional
        Solver of the impact QP.
    progress : callable, optional
        ``progress(factor, outcome)`` after each run.
    model : {"rock", "auto", "simulate"}, optional
        The model of each run.
    dt : float, optional
        Step of the simulation (s; ``auto`` and ``simulate``).
    friction : float, optional
        Coulomb coefficient of the joints (``auto`` and ``simulate``; None: no sliding).

    Returns
    -------
    dict
        JSON-safe: ``outcome`` (``"computed"``, or ``"cannot_stand"``: no run, no
        factor), ``first_collapse`` (the factor, or None), its ``bracket``,
        ``pga_at_first_collapse`` (g), the member's ``A_L`` both ways (g), each run
        (``scan``: factor, outcome, peak rotation in rad) and the settings.

    Raises
    ------
    InputError
        Bad input, before any run.

    Examples
    --------
    >>> import fembeam
    >>> from fembeam.dynamics import GroundMotion
    >>> from fembeam.studies.collapse import collapse_scale
    >>> arch = fembeam.CircularArch(radius=1.0, thickness=0.15, embrace_deg=157.5)
    >>> out = collapse_scale(arch, GroundMotion.sine(0.2, 0.5), voussoirs=12,
    ...                      resolution=0.1, t_end=2.0)
    >>> print(f"factor {out['first_collapse']:.2f},",
    ...       f"PGA {out['pga_at_first_collapse']:.2f} g")
    factor 2.59, PGA 0.52 g
    """
    dt, friction = check_model(model, dt, friction)
    if not isinstance(ground, GroundMotion):
        raise InputError(f"collapse_scale needs a GroundMotion, got {type(ground).__name__}")
    if ground.pga == 0:
        raise InputError(f"{ground.name} is zero everywhere: no scale factor moves the member")
    if sign not in (1, -1):
        raise InputError(f"sign must be +1 or -1, got {sign!r}")
    check_search(resolution, span, max_runs)
    if t_end is not None and not (math.isfinite(t_end) and t_end > ground.t[0]):
        raise InputError(f"t_end must be finite and after the start of the record ({ground.t[0]:g} s), got {t_end}")
    check_runs(model, dt, (t_end if t_end is not None else default_t_end(ground, curve)) - float(ground.t[0]),
                curve, voussoirs, elements)
    rk = Rocker(curve, voussoirs=voussoirs, elements=elements, backend=backend, qp=False)
    if not rk.stands:             # a physical outcome: the answer, without a run
        return json_safe({"outcome": "cannot_stand", "record": ground.name, "pga": ground.pga, "sign": sign,
                           "first_collapse": None, "pga_at_first_collapse": None,
                           "first_overturning": None, "pga_at_first_overturning": None,
                           "A_L": {"+1": None, "-1": None}, "geometry": curve.describe() if hasattr(curve, "describe")
                           else {}, "voussoirs": voussoirs, "elements": elements if voussoirs is None else None,
                           "model": model, "dt": dt, "friction": friction, "runs": 0})
    onset_and_top(ground, [rk.A[1], rk.A[-1]], sign, span)
    res = record_collapse(curve, ground, sign=sign, model=model, thresholds=[rk.A[1], rk.A[-1]],
                          voussoirs=voussoirs, elements=elements, backend=backend, dt=dt, friction=friction,
                          resolution=resolution, span=span, max_runs=max_runs, t_end=t_end, progress=progress)
    f = res["first_collapse"]
    pga_f = None if f is None else f * ground.pga
    res.update(outcome="computed", record=ground.name, pga=ground.pga, pga_at_first_collapse=pga_f,
               pga_at_first_overturning=pga_f,
               A_L={"+1": rk.A[1], "-1": rk.A[-1]}, geometry=curve.describe() if hasattr(curve, "describe") else {},
               voussoirs=voussoirs, elements=elements if voussoirs is None else None, model=model, dt=dt,
               friction=friction)
    return json_safe(res)
