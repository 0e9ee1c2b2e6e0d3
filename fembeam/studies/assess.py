"""One page for a member and its ground motions: static answers, the dynamic verdict, the margin.

* **statics** (:func:`fembeam.analysis.analyze` both ways, :func:`fembeam.analysis.minimum_thickness`):
  ``A_L(+1)``, ``A_L(-1)`` (g) and their hinges; the minimum thickness and the geometric factor of
  safety ``t / t_min`` (the inverse of the smallest thickness factor that stands); the friction
  the limit state needs, ``max |S| / N`` over the joints at ``A_L`` (either way): with a larger
  Coulomb coefficient the rocking mechanism governs, with a smaller one the joints slide first.
* **verdict** (:class:`fembeam.auto.AutoModel`) under each ground motion: survives, overturns or
  collapses by sliding; the peak rotation (rad, of any piece or body), the first time the
  one-mechanism model failed and why, the time spent in each model.
* **margin** (:func:`fembeam.studies.collapse.collapse_scale`, the hunt and fill of ``fembeam
  collapse-scale``): the first scale factor of the motion found to collapse the member by
  ``auto``, whether it is the smallest at the search's resolution (relative step between
  factors), beside ``rock``'s (what the one-mechanism model alone would claim) and their ratio
  ``auto / rock`` (below 1: the one-mechanism model overstates the margin).

Units: accelerations in g (positive along +x; ``A_L(+1)`` is the threshold of an inertia load to
the right, i.e. of ``a_g < 0``), times in s, rotations in rad, thicknesses in m, energies in J per
metre of width (the JSON's ``units``).
"""
from __future__ import annotations

import math
import time
from dataclasses import dataclass, field
from typing import Callable, Sequence

import numpy as np

from ..analysis import analyze, minimum_thickness
from ..dynamics.ground import GroundMotion
from ..units import kN
from ..limits import check_run_count
from ..errors import InputError
from ..geometry import MidCurve
from ..dynamics.ground import MAX_PGA
from .runs import json_safe, onset_amplitude
from .collapse import MAX_RUNS, RESOLUTION, SPAN, check_search, collapse_scale

__all__ = ["assess", "margin", "AssessResult", "Snapshot", "VERDICTS", "MARGIN_KEYS"]

VERDICTS = {"rest": "survives", "survived": "survives", "overturned": "overturns",
            "collapsed_by_sliding": "collapsed_by_sliding", "cannot_stand": "cannot_stand"}
_THICKNESS_KEYS = ("thickness", "thickness_springing", "thickness_crown", "width")
_VERDICT_KEYS = ("outcome", "t_end", "t_collapse", "t_overturn", "overturn_reason", "peak_rotation", "t_peak",
                 "first_failure", "handovers", "time_in", "n_impacts", "friction_demand", "segments")


@dataclass
class Snapshot:
    """The member at time ``t`` (s) of a verdict's motion, as the model in use (``model``) had it:
    ``polygons`` (each ``(2, k)``, m: one per rigid body, or one outline of a mechanism's pieces),
    ``pivots`` ``(2, n)`` (m, the hinges of a mechanism; none for the bodies) and the largest
    rotation of a piece or body ``max_rotation`` (rad).

    Examples
    --------
    :func:`assess` keeps one per motion in :attr:`AssessResult.snapshots` (the member at its
    peak rotation, or at overturning), taken by :func:`snapshot` from the runs. A block of
    0.5 m x 2 m rocking on its right corner under a 0.4 g sine pulse of 0.5 s, at its peak:

    >>> import fembeam
    >>> from fembeam.auto.model import Segment
    >>> from fembeam.dynamics import GroundMotion, Rocker
    >>> from fembeam.studies.assess import snapshot
    >>> block = fembeam.StraightMember(height=2.0, width=0.5)
    >>> run = Rocker(block, voussoirs=1, qp=False).run(GroundMotion.sine(0.4, 0.5), t_end=1.0)
    >>> snap = snapshot([("rock", run)], [Segment("rock", 0.0, 1.0, "end")], run.t_peak)
    >>> print(snap.model, f"t = {snap.t:.2f} s, max rotation {snap.max_rotation:.4f} rad")
    rock t = 0.77 s, max rotation 0.0895 rad
    >>> print(len(snap.polygons), "outline, pivot at", snap.pivots[:, 0].round(3) + 0.0, "m")
    1 outline, pivot at [0.25 0.  ] m
    """

    t: float
    model: str
    polygons: list
    pivots: np.ndarray
    max_rotation: float

    def to_dict(self) -> dict:
        return {"t": float(self.t), "model": self.model, "max_rotation": float(self.max_rotation)}


@dataclass
class AssessResult:
    """What :func:`assess` found (:meth:`to_dict` is its JSON).

    Attributes
    ----------
    curve : MidCurve
        The member.
    mode : {"continuous", "voussoirs"}
        Its mesh.
    elements : int
        Its voussoirs or elements.
    settings : dict
        The settings of the runs.
    static : dict
        ``A_L`` both ways (g), hinges, friction needed, thrust range (kN/m).
    motions : list of dict
        One per ground motion: verdict, outcome, peak rotation (rad), margin.
    analyses : dict
        The :class:`~fembeam.analysis.AnalysisResult` of each load direction.
    grounds : list of GroundMotion
        The motions.
    runs : list of AutoResult
        The run of each motion.
    snapshots : list
        The member at the peak or at overturning of each motion, or None.

    Examples
    --------
    :func:`assess` returns it; the paper's arch of 12 voussoirs stands in a range of
    thrust (kN/m) and survives a 0.3 g sine pulse of 0.5 s, below its ``A_L`` (g):

    >>> import fembeam
    >>> from fembeam.dynamics import GroundMotion
    >>> from fembeam.studies.assess import assess
    >>> arch = fembeam.CircularArch(radius=1.0, thickness=0.15, embrace_deg=157.5)
    >>> res = assess(arch, GroundMotion.sine(0.3, 0.5), voussoirs=12, margin_search=False)
    >>> H = res.static["thrust_range"]
    >>> print(f"A_L = {res.static['A_L']['+1']:.4f} g,",
    ...       f"H in [{H['H_min']:.3f}, {H['H_max']:.3f}] kN/m")
    A_L = 0.3593 g, H in [1.612, 2.643] kN/m
    >>> m = res.motions[0]
    >>> print(m["verdict"], m["outcome"], f"peak rotation {m['peak_rotation']:.4f} rad")
    survives rest peak rotation 0.0000 rad
    """

    curve: MidCurve
    mode: str
    elements: int
    settings: dict
    static: dict
    motions: list = field(default_factory=list)
    analyses: dict = field(default_factory=dict)
    grounds: list = field(default_factory=list)
    runs: list = field(default_factory=list)
    snapshots: list = field(default_factory=list)
    timings: dict = field(default_factory=dict)

    def to_dict(self) -> dict:
        """Strict JSON (null for undefined or non-finite numbers)."""
        geo = self.curve.describe() if hasattr(self.curve, "describe") else {}
        return json_safe({"command": "assess", "geometry": geo, "mode": self.mode,
                        "elements": self.elements, "settings": self.settings, "static": self.static,
                        "motions": self.motions,
                        "timings_s": {k: round(v, 4) for k, v in self.timings.items()},
                        "units": {"A_L": "g", "density": "kg/m^3", "thickness": "m", "t": "s", "pga_g": "g",
                                  "peak_rotation": "rad",
                                  "motions.segments.handback_energy_dropped": "J/m"}})


# --------------------------------------------------------------------------- statics
def static_answers(curve: MidCurve, voussoirs: int | None, elements: int, friction: float | None = None,
                   tol: float = 1e-6) -> tuple[dict, dict]:
    """``(answers, analyses)``: A_L, hinges and the friction needed each way, the minimum
    thickness and the geometric factor of safety (see the module docstring); ``friction``: the
    joints' coefficient, flagged when the limit state needs more."""
    n = None if voussoirs is not None else elements
    res = {d: analyze(curve, elements=n, voussoirs=voussoirs, direction=d) for d in (1, -1)}
    key = {1: "+1", -1: "-1"}
    out: dict = {"outcome": {key[d]: r.outcome for d, r in res.items()},
                 "A_L": {key[d]: r.A_L for d, r in res.items()},
                 "hinges": {key[d]: [h.to_dict() for h in r.hinges_before] for d, r in res.items()}}
    need = {key[d]: r.required_friction(friction)["limit"] for d, r in res.items()}
    both = [x["max"] for x in need.values()]
    need["max"] = None if None in both else max(both)
    need["friction"] = friction
    need["sliding_risk"] = None if friction is None or need["max"] is None else bool(need["max"] > friction)
    out["friction_needed"] = need
    tr = res[1].thrust                      # the thrust range does not depend on the direction
    out["thrust_range"] = None if tr is None else {"H_min": tr.H_min, "H_max": tr.H_max if tr.H_max < float("inf")
                                                   else None, "unit": "kN/m"}
    out["weight_kN_per_m"] = kN(res[1].mass)
    th = minimum_thickness(curve, elements=n, voussoirs=voussoirs, tol=tol)
    mt = th.to_dict()
    law = curve.describe() if hasattr(curve, "describe") else {}
    law = {k: float(law[k]) for k in _THICKNESS_KEYS if isinstance(law.get(k), (int, float))}
    if th.outcome == "ok":
        mt["thickness_min"] = {k: th.scale * v for k, v in law.items()}
        mt["geometric_safety_factor"] = 1.0 / th.scale
    else:
        mt["thickness_min"] = {k: 0.0 for k in law} if th.outcome == "stands_at_any_thickness" else None
        mt["geometric_safety_factor"] = None        # infinite (stands at any thickness) or none (never stands)
    out["minimum_thickness"] = mt
    return out, res


# --------------------------------------------------------------------------- the verdict's states
def snapshot(runs: list, segments, t: float) -> Snapshot | None:
    """The member at the history row nearest ``t`` (s) of the last recorded run of the model in use
    at ``t`` (by ``segments``) whose history covers it; None if none does."""
    from ..output.motion import outline
    seg = [s for s in segments if s.t_start <= t <= s.t_end]
    if not seg:
        return None
    model = seg[-1].model
    for kind, r in reversed(runs):
        h = r.history
        ts = np.asarray(h.get("t", ()), float)
        if kind != model or ts.size == 0 or not ts[0] - 1e-12 <= t <= ts[-1] + 1e-12:
            continue
        i = int(np.argmin(np.abs(ts - t)))
        if kind == "rock":
            k, theta = int(h["mechanism"][i]), float(h["theta"][i])
            m = r.mechanisms[k] if k >= 0 else None
            conf = m.configuration(theta) if m is not None else None
            pivots = conf.hinge_points() if conf is not None else np.zeros((2, 0))
            rot = float(np.max(np.abs(conf.rotation))) if conf is not None else 0.0
            return Snapshot(float(ts[i]), kind, [outline(r, m, theta)], pivots, rot)
        q = np.asarray(r.positions[i], float)
        polys = []
        for (x, y, phi), poly in zip(q, r.bodies.outlines()):
            c, s = math.cos(phi), math.sin(phi)
            polys.append(np.array([x + c * poly[0] - s * poly[1], y + s * poly[0] + c * poly[1]]))
        return Snapshot(float(ts[i]), kind, polys, np.zeros((2, 0)), float(np.max(np.abs(q[:, 2]))))
    return None


# --------------------------------------------------------------------------- margin
MARGIN_KEYS = ("factor", "pga_g", "bracket", "smallest", "resolution", "resolution_reached", "collapse",
               "safe_above", "safe_factors_above", "none_up_to_max", "budget_exhausted", "onset_factor", "max_factor",
               "runs", "errors")


def _margin_entry(res: dict) -> dict:
    """The margin of one model from a :func:`~fembeam.studies.collapse.collapse_scale` dict.

    Parameters
    ----------
    res : dict
        The search's result (scale factors; PGA in g).

    Returns
    -------
    dict
        The keys :data:`MARGIN_KEYS`: the first collapsing factor found (``factor``, its PGA
        ``pga_g`` in g), whether it is the smallest at ``resolution`` (``smallest``) and the claims of
        :func:`~fembeam.studies.huntfill.hunt_and_fill` that qualify it.
    """
    out = {"factor": res["first_collapse"], "pga_g": res["pga_at_first_collapse"]}
    out.update({k: res[k] for k in MARGIN_KEYS if k not in out})
    return out


def margin_span(A: dict, ground: GroundMotion, span: float = SPAN) -> float | None:
    """The largest factor of a margin search, in onset factors.

    Parameters
    ----------
    A : dict
        ``A_L`` of the member (g), keyed by direction ``1`` and ``-1``.
    ground : GroundMotion
        The motion as given (accelerations in g).
    span : float
        The largest factor wanted, in onset factors (default :data:`~fembeam.studies.collapse.SPAN`).

    Returns
    -------
    float or None
        ``span``, or less where the PGA would exceed the admitted
        :data:`~fembeam.dynamics.ground.MAX_PGA` (g); None when no factor sets the member moving
        (the motion is zero, or ``A_L`` infinite the way it loads) or only one above that PGA does.
    """
    f0 = onset_amplitude(A, ground)
    if not math.isfinite(f0) or ground.pga == 0:
        return None
    top = min(span, MAX_PGA / (f0 * ground.pga) * (1 - 1e-9))
    return top if top > 1.0 else None


def margin(curve: MidCurve, ground: GroundMotion, A: dict, *, voussoirs: int | None, elements: int,
           friction: float | None, dt: float, t_end: float | None, resolution: float = RESOLUTION,
           max_runs: int = MAX_RUNS, progress: Callable | None = None) -> dict:
    """The smallest scale factor of ``ground`` that collapses the member, by ``auto`` and by ``rock``.

    Each is the search of ``fembeam collapse-scale``
    (:func:`fembeam.studies.collapse.collapse_scale`: hunt and fill over the factors of the motion
    as given, from the onset factor up to :func:`margin_span` onset factors), so that both commands
    give the same factor for the same member, motion and settings.

    Parameters
    ----------
    curve : MidCurve
        The member.
    ground : GroundMotion
        The motion as given (accelerations in g); factors scale it.
    A : dict
        ``A_L`` both ways (g, keys ``1`` and ``-1``), to tell a motion that no factor sets moving.
    voussoirs, elements : int or None, int
        The mesh: ``voussoirs`` pieces, or the continuous member on ``elements`` elements.
    friction : float or None
        Coulomb coefficient of the joints in ``auto`` (None: they never slide; with one, no factor of
        ``auto`` is called the smallest: a joint may slide below ``A_L``, where nothing is run).
    dt : float
        Time step of ``auto``'s multi-block simulation (s).
    t_end : float or None
        End of every run (s; None: the end of the motion plus ``20 sqrt(L/g)``).
    resolution : float
        Relative step between factors the search must reach below a collapse to call it the
        smallest, in [1e-4, 1] (default 0.05).
    max_runs : int
        Time histories at most in each search (default 200).
    progress : callable, optional
        ``progress(message)`` after each run and at the end of each search.

    Returns
    -------
    dict
        ``auto`` and ``rock``: each the keys :data:`MARGIN_KEYS` (``factor`` and ``bracket`` are
        scale factors, ``pga_g`` in g, ``resolution`` and ``resolution_reached`` relative);
        ``ratio`` ``auto / rock`` (None unless both are found); ``skipped``: why nothing was
        searched, or None.

    Examples
    --------
    A motion that no scale factor sets moving is not searched (the search of a motion
    that does is that of :func:`~fembeam.studies.collapse.collapse_scale`, run by
    ``auto``, whose multi-block simulation is compiled on its first use, and by
    ``rock``):

    >>> import fembeam
    >>> from fembeam.dynamics import GroundMotion
    >>> from fembeam.studies.assess import margin
    >>> arch = fembeam.CircularArch(radius=1.0, thickness=0.15, embrace_deg=157.5)
    >>> out = margin(arch, GroundMotion.sine(0.0, 0.5), {1: 0.359, -1: 0.359},
    ...              voussoirs=12, elements=200, friction=None, dt=1e-3, t_end=None)
    >>> print(out["auto"], out["rock"], out["skipped"])
    None None no scale factor sets the member moving (the motion is zero, ...)
    """
    out = {"auto": None, "rock": None, "ratio": None, "skipped": None}
    span = margin_span(A, ground)
    if span is None:
        out["skipped"] = ("no scale factor sets the member moving (the motion is zero, or A_L is infinite in "
                          f"the direction it loads, or only a PGA above {MAX_PGA:g} g would)")
        return out
    for model in ("auto", "rock"):
        extra = {"dt": dt, "friction": friction} if model == "auto" else {}
        count = [0]

        def cb(f, o, m=model, count=count):
            count[0] += 1
            progress(f"margin ({m}, resolution {resolution:g}): run {count[0]}, factor {f:.4g} {o}")
        res = collapse_scale(curve, ground, voussoirs=voussoirs, elements=elements, t_end=t_end,
                             resolution=resolution, span=span, max_runs=max_runs, model=model,
                             progress=cb if progress else None, **extra)
        out[model] = e = _margin_entry(res)
        if progress:
            progress(f"margin ({model}): " + ("no collapse found" if e["factor"] is None else
                                              f"factor {e['factor']:.6g}, " + ("the smallest" if e["smallest"] else
                                                                              "not called the smallest")
                                              + f" at resolution {resolution:g}") + f" ({e['runs']} runs)")
    fa, fr = out["auto"]["factor"], out["rock"]["factor"]
    out["ratio"] = fa / fr if fa is not None and fr is not None else None
    return out


# --------------------------------------------------------------------------- the page
def assess(curve: MidCurve, grounds: GroundMotion | Sequence[GroundMotion], *, voussoirs: int | None = None,
           elements: int = 200, friction: float | None = None, dt: float | None = None, t_end: float | None = None,
           margin_search: bool = True, resolution: float = RESOLUTION, max_runs: int = MAX_RUNS,
           sources: Sequence[str] | None = None, progress: Callable[[str], None] | None = None) -> AssessResult:
    """Static answers, the ``auto`` verdict and the margin of a member under ground motions.

    Parameters
    ----------
    curve : MidCurve
        The member (lengths in m, density in kg/m^3).
    grounds : GroundMotion or sequence of GroundMotion
        The motions (g, positive along ``+x``).
    voussoirs : int, optional
        Discrete arch of this many voussoirs; otherwise the continuous member on
        ``elements`` rigid elements (default 200).
    elements : int, optional
        See ``voussoirs``.
    friction : float, optional
        Coulomb coefficient of the joints in ``auto`` (None: they never slide).
    dt : float, optional
        Simulation step (s), default :data:`fembeam.auto.model.DT`.
    t_end : float, optional
        End of every run (s), default the end of the motion plus ``20 sqrt(L/g)``.
    margin_search : bool, optional
        False skips the margins (the smallest collapsing factor of each motion).
    resolution : float, optional
        Relative step between factors of the margins' search, in [1e-4, 1].
    max_runs : int, optional
        Most runs of each margin's search.
    sources : sequence of str, optional
        Where each motion came from (reported).
    progress : callable, optional
        ``progress(message)`` at each stage and margin run.

    Returns
    -------
    AssessResult
        ``static`` (``A_L`` both ways in g, hinges, friction needed, thrust range in
        kN/m) and one entry per motion in ``motions`` (verdict, outcome, peak rotation
        in rad, margin).

    Raises
    ------
    InputError
        Bad input, before any run.

    Examples
    --------
    >>> import fembeam
    >>> from fembeam.dynamics import GroundMotion
    >>> from fembeam.studies.assess import assess
    >>> arch = fembeam.CircularArch(radius=1.0, thickness=0.15, embrace_deg=157.5)
    >>> res = assess(arch, GroundMotion.sine(0.3, 0.5), voussoirs=12, margin_search=False)
    >>> print(f"A_L = {res.static['A_L']['+1']:.4f} g;", res.motions[0]["verdict"])
    A_L = 0.3593 g; survives
    """
    from ..auto import AutoModel
    from ..auto.model import DT

    clock = time.perf_counter()
    grounds = [grounds] if isinstance(grounds, GroundMotion) else list(grounds)
    if not grounds or not all(isinstance(g, GroundMotion) for g in grounds):
        raise InputError("assess needs one or more ground motions (GroundMotion)")
    if sources is not None and len(sources) != len(grounds):
        raise InputError("sources: one per ground motion")
    check_search(resolution, SPAN, max_runs)
    if margin_search:
        check_run_count(2 * len(grounds), max_runs, f"{len(grounds)} ground motions x 2 models")
    dt = DT if dt is None else dt
    say = progress or (lambda message: None)
    say("statics: limit analysis both ways, minimum thickness")
    am = AutoModel(curve, voussoirs=voussoirs, elements=elements, friction=friction, dt=dt)   # checks dt, friction
    static, analyses = static_answers(curve, voussoirs, elements, friction)
    mode = "voussoirs" if voussoirs is not None else "continuous"
    settings = {"friction": friction, "dt": am.dt, "t_end": t_end, "margin": bool(margin_search),
                "resolution": float(resolution), "max_runs": int(max_runs), "span": SPAN,
                "sim_elements": None if voussoirs is not None else am.sim_elements}
    out = AssessResult(curve, mode, voussoirs if voussoirs is not None else elements, settings, static,
                       analyses=analyses, grounds=grounds)
    out.timings["statics"] = time.perf_counter() - clock
    for k, ground in enumerate(grounds):
        tick = time.perf_counter()
        say(f"motion {k + 1}/{len(grounds)} ({ground.name}): auto run")
        res = am.run(ground, t_end=t_end)
        d = res.to_dict()
        entry = {"name": ground.name, "source": None if sources is None else sources[k], "pga_g": ground.pga,
                 "duration_s": ground.duration, "verdict": VERDICTS.get(res.outcome, res.outcome),
                 **{key: d[key] for key in _VERDICT_KEYS if key in d}}
        t_shown = res.t_overturn if res.t_overturn is not None else res.t_peak
        snap = snapshot(res.runs, res.segments, t_shown) if t_shown is not None else None
        entry["configuration"] = None if snap is None else {**snap.to_dict(),
                                                            "at": "overturning" if res.t_overturn is not None
                                                            else "peak rotation"}
        if margin_search and res.outcome != "cannot_stand":
            entry["margin"] = margin(curve, ground, am.A, voussoirs=voussoirs, elements=elements, friction=friction,
                                     dt=am.dt, t_end=t_end, resolution=resolution, max_runs=max_runs, progress=progress)
        else:
            entry["margin"] = {"auto": None, "rock": None, "ratio": None,
                               "skipped": "not searched" if not margin_search else "the member cannot stand"}
        entry["time_s"] = time.perf_counter() - tick
        out.motions.append(entry)
        out.runs.append(res)
        out.snapshots.append(snap)
    out.timings["total"] = time.perf_counter() - clock
    return out
