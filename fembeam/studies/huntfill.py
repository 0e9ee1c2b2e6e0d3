"""Hunt-and-fill search for the scale factor at which a record first collapses a member.

The search of incremental dynamic analysis (Vamvatsikos and Cornell 2002, 2004), made to state
what it has seen.  Factors are positive; below the onset factor ``f0`` the ground never exceeds
``A_L`` either way, so nothing moves (safe without a run).

* **Hunt**: runs at ``f0 (1 + s)``, then each factor ``1 + k s`` times the previous one
  (``k = 2, 3, ...``; ``s`` = :data:`HUNT_STEP`), up to ``max_factor`` (run last), until one
  collapses: ``max_factor / f0 = 20`` takes 9 runs.
* **Fill**: the decided factors from ``f0`` up to the lowest collapse found (``max_factor``
  without one) split the range into gaps; the widest gap (in ratio) is split first, lowest first
  among equals, until every gap is at most ``1 + resolution``.  A gap of ratio ``R`` needs
  ``n = ceil(ln R / ln(1 + resolution))`` equal steps; it is split at the ratio point that leaves
  ``floor(n / 2)`` of them below, so the search stays coarse-to-fine and a gap costs ``n - 1``
  runs.  A collapse met while filling becomes the lowest collapse: the gaps above it leave the fill.

Claims, in the returned dict:

* ``first_collapse``: the lowest collapsing factor found, by overturning or by sliding (None:
  none up to ``max_factor``); ``first_overturning`` is a deprecated alias with the same value,
  kept for one release;
* ``smallest`` (bool): every gap from
  ``f0`` up to it is at most ``1 + resolution`` and every run below it is safe, so no collapsing
  window wider than ``resolution`` (relative) lies below it.  A narrower window can (the safe set
  of a rocking member has gaps of a fraction of a per cent), and the true first collapse lies in
  ``(f / (1 + resolution), f]`` only if there is none;
* ``safe_factors_above`` (``safe_above``: any): safe factors found above it (runs of the hunt, or
  of the fill before a lower collapse was found);
* ``resolution_reached``: the widest gap below it (or below ``max_factor``) minus 1;
* ``bracket``: ``[last safe factor below it, it]``; the lower end is the onset factor when
  nothing below it was run (safe without a run), None with ``onset_safe=False`` when the onset
  factor itself collapses (no safe factor seen);
* ``runs`` (the number of runs) and ``scan`` (every run's dict, by factor).

The search stops early, with ``smallest`` False, at ``max_runs`` runs or at a run that is
neither safe nor a collapse (a solver error, listed in ``errors``).
"""
from __future__ import annotations

import math
from typing import Callable

from ..errors import InputError

__all__ = ["hunt_and_fill", "HUNT_STEP", "SAFE", "COLLAPSE"]

HUNT_STEP = 0.1            # the hunt's first relative step; the k-th is k times it
SAFE = ("no_motion", "rest", "survived", "below_barrier")
COLLAPSE = ("overturned", "collapsed_by_sliding")


def _check(onset: float, resolution: float, max_factor: float, max_runs: int) -> None:
    if not (math.isfinite(onset) and onset > 0):
        raise InputError(f"the onset factor must be a positive finite number, got {onset!r}")
    if not (isinstance(resolution, (int, float)) and 1e-4 <= resolution <= 1.0):
        raise InputError(f"the resolution must be in [1e-4, 1] (relative step between factors), got {resolution!r}")
    if not (math.isfinite(max_factor) and max_factor > 0):
        raise InputError(f"the largest factor must be a positive finite number, got {max_factor!r}")
    if not (isinstance(max_runs, int) and 1 <= max_runs <= 100_000):
        raise InputError(f"the run budget must be an integer in [1, 100000], got {max_runs!r}")


def _split_point(a: float, b: float, resolution: float) -> float:
    """The factor that splits the gap ``(a, b)`` into ``floor(n/2)`` and ``ceil(n/2)`` of its
    ``n`` equal ratio steps of at most ``1 + resolution``."""
    n = math.ceil(math.log(b / a) / math.log1p(resolution) - 1e-12)
    return a * (b / a) ** ((n // 2) / n)


def _top(done: dict, default: float | None) -> float | None:
    """The lowest collapsing factor run (``default`` if none)."""
    return min((f for f, r in done.items() if r["outcome"] in COLLAPSE), default=default)


def _ends(onset: float, done: dict, top: float) -> list[float]:
    """The onset, the factors run above it and below ``top``, and ``top``: the ends of the gaps."""
    return [onset] + sorted(x for x in done if onset < x < top) + ([top] if top > onset else [])


def _gaps(onset: float, done: dict, top: float, resolution: float) -> list[tuple[float, float]]:
    ends = _ends(onset, done, top)
    return [(a, b) for a, b in zip(ends, ends[1:]) if b / a > 1.0 + resolution * (1 + 1e-9)]


def hunt_and_fill(run: Callable[[float], dict], onset: float, *, resolution: float, max_factor: float,
                  max_runs: int = 200, onset_safe: bool = True) -> dict:
    """The smallest scale factor of a record that collapses a member, by hunt and fill.

    The hunt steps up from the onset factor by growing ratios until a run collapses; the
    fill then splits the widest gap between the decided factors below the lowest collapse
    until every gap is at most ``1 + resolution``. The steps, and what each claim of the
    result means, are those of :mod:`fembeam.studies.huntfill`.

    Parameters
    ----------
    run : callable
        ``run(f)`` runs the member under the record scaled by ``f`` (dimensionless) and
        returns a dict with at least ``outcome``: one of :data:`SAFE` (``"no_motion"``,
        ``"rest"``, ``"survived"``, ``"below_barrier"``), one of :data:`COLLAPSE`
        (``"overturned"``, ``"collapsed_by_sliding"``), or anything else (undecided: the
        search stops).
    onset : float
        The onset factor ``f0 > 0``: below it the ground never exceeds ``A_L`` either way
        and nothing moves, so it is safe without a run.
    resolution : float
        Relative step between factors that the fill must reach below a collapse to call it
        the smallest, in [1e-4, 1].
    max_factor : float
        Largest factor run (> 0); the hunt runs it last.
    max_runs : int, optional
        Run budget, in [1, 100000] (default 200); the search stops there with ``smallest``
        False.
    onset_safe : bool, optional
        False for joints that may slide below ``A_L``: the onset factor is run first,
        nothing below it is searched, and no factor is called the smallest.

    Returns
    -------
    dict
        ``first_collapse`` (the lowest collapsing factor found, None if none up to
        ``max_factor``; ``first_overturning``: a deprecated alias with the same value),
        ``smallest`` (no collapsing window wider than ``resolution`` lies below it),
        ``collapse`` (its outcome), ``bracket`` ``[last safe factor below, first
        collapse]``, ``safe_above`` and ``safe_factors_above`` (safe factors run above
        it), ``resolution`` and ``resolution_reached`` (widest relative gap left below
        it), ``none_up_to_max``, ``budget_exhausted``, ``errors`` (the undecided runs),
        ``onset_factor``, ``max_factor``, ``runs`` and ``scan`` (every run's dict, sorted by
        factor, with ``factor`` and ``order``, its rank in time, added).

    Raises
    ------
    InputError
        ``onset``, ``resolution``, ``max_factor`` or ``max_runs`` out of range.

    See Also
    --------
    fembeam.studies.collapse.collapse_scale : the search for a member and a ground motion.

    Examples
    --------
    A stand-in for the member that collapses between factors 1.9 and 2.1 and from 3 up
    (a rocking member's safe set can have such gaps):

    >>> from fembeam.studies.huntfill import hunt_and_fill
    >>> def run(f):
    ...     return {"outcome": "overturned" if 1.9 <= f < 2.1 or f >= 3.0 else "rest"}
    >>> out = hunt_and_fill(run, 1.0, resolution=0.05, max_factor=20.0)
    >>> print(f"first collapse {out['first_collapse']:.4f}, smallest: {out['smallest']},",
    ...       f"{out['runs']} runs")
    first collapse 1.9822, smallest: True, 18 runs
    >>> print("bracket", [round(f, 4) for f in out["bracket"]])
    bracket [1.8892, 1.9822]
    >>> print("safe above it:", [round(f, 4) for f in out["safe_factors_above"]])
    safe above it: [2.4024, 2.8768]
    """
    _check(onset, resolution, max_factor, max_runs)
    done: dict[float, dict] = {}
    undecided: list[dict] = []

    def decide(f: float) -> str:
        out = dict(run(f))
        out.update(factor=float(f), order=len(done))
        done[f] = out
        if out["outcome"] not in SAFE + COLLAPSE:
            undecided.append(out)
        return out["outcome"]

    # hunt
    f, k = onset, 1
    if not onset_safe and decide(onset) in COLLAPSE:
        f = max_factor
    while f < max_factor and not undecided and len(done) < max_runs:
        f = min(f * (1.0 + k * HUNT_STEP), max_factor)
        k += 1
        if decide(f) in COLLAPSE:
            break
    # fill
    while not undecided and len(done) < max_runs:
        gaps = _gaps(onset, done, _top(done, max_factor), resolution)
        if not gaps:
            break
        a, b = max(gaps, key=lambda g: (math.log(g[1] / g[0]), -g[0]))
        decide(_split_point(a, b, resolution))
    top = _top(done, None)
    ends = _ends(onset, done, _top(done, max_factor))
    reached = max((b / a - 1.0 for a, b in zip(ends, ends[1:])), default=0.0)
    covered = not undecided and reached <= resolution * (1 + 1e-9)
    last_safe = max((x for x, r in done.items() if (top is None or x < top) and r["outcome"] in SAFE),
                    default=onset if onset_safe else None)
    smallest = bool(top is not None and covered and onset_safe)
    above = sorted(x for x, r in done.items() if top is not None and x > top and r["outcome"] in SAFE)
    return {"first_collapse": top, "first_overturning": top, "smallest": smallest,
            "none_up_to_max": bool(top is None and covered and max_factor > onset and onset_safe),
            "collapse": None if top is None else done[top]["outcome"],
            "bracket": [last_safe, top], "resolution": float(resolution), "resolution_reached": float(reached),
            "safe_above": bool(above), "safe_factors_above": above,
            "errors": [{"factor": u["factor"], "outcome": u["outcome"], "error": u.get("error")} for u in undecided],
            "budget_exhausted": not covered and not undecided,
            "onset_factor": float(onset), "max_factor": float(max_factor), "runs": len(done),
            "scan": [done[x] for x in sorted(done)]}
