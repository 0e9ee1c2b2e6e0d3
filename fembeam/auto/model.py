"""``--model auto``: the one-mechanism model while it holds, the multi-block simulation from the
moment it does not, and back.

The multi-block model (every voussoir or element a rigid body in unilateral contact,
:mod:`fembeam.simulation`) is the truth; a one-parameter mechanism is a manifold of its state
(:mod:`.manifold`).  The run alternates two kinds of segments:

* **rock** (:class:`~fembeam.dynamics.Rocker`): rest, onset, one mechanism between impacts, the
  paper's impact model at each impact, while the mechanism is *admissible*: the dynamic thrust
  line inside every section (a thrust line outside by more than ``THRUST_TOL`` of the thickness
  means that another hinge opens), and, when a Coulomb coefficient ``mu`` is given, ``|S|/N <=
  mu`` in every section in compression along the motion and ``|P_t|/P_n <= mu`` at every impact.
  At the first violation the exact state of the mechanism (``theta``, ``theta'`` at that time; just
  before the impact for an impact's friction) is mapped onto the bodies and handed over.
* **simulate** (:class:`~fembeam.simulation.Simulator`, steps ``dt``, Coulomb friction ``mu`` when
  given), advanced in windows of ``WINDOW`` s.  One step after the first impact of a window, and at
  the end of a window, the state is handed back to the one-mechanism model when the member is at
  rest (kinetic energy below ``REST_KINETIC m g L``,
  every joint closed, none slid) or moves on a mechanism of the member (:func:`.manifold.mechanism_of`:
  its hinges and no other joint open, positions within ``POSITION_TOL`` of the thickness, velocities
  within ``VELOCITY_TOL`` of the mechanism's field in the kinetic-energy norm; the energy the
  projection drops is reported), provided the one-mechanism model is admissible from there (a
  hand-back whose mechanism is violated at once is not made: the simulation goes on).

Overturning is the rule shared by both models (:mod:`fembeam.dynamics.outcomes`).  A motion that
never violates admissibility is ``rock``'s exactly.  The result lists the segments: the model,
its interval and why it ended.
"""
from __future__ import annotations

import math
import time
from dataclasses import dataclass, field

import numpy as np

from ..dynamics.equation import GRAVITY
from ..dynamics.ground import GroundMotion
from ..dynamics.outcomes import friction_demand
from ..dynamics.rocking import Rocker
from ..errors import InputError, SolverError
from ..fem import nodes_through, uniform_nodes
from ..geometry import MidCurve
from ..simulation.constants import REST_KINETIC   # at rest: kinetic energy below this fraction of m g L
from .manifold import bodies_state, mechanism_of

__all__ = ["AutoModel", "AutoResult", "Segment", "WINDOW", "REST_KINETIC", "POSITION_TOL", "VELOCITY_TOL",
           "MAX_SEGMENTS", "DT"]

DT = 1e-3               # s: default time step of the simulation segments (that of fembeam simulate)
WINDOW = 0.1            # s: a simulation segment is advanced this long between two hand-back checks
POSITION_TOL = 1e-5     # hand-back: positions rebuilt from theta within this fraction of the thickness
VELOCITY_TOL = 1e-3     # hand-back: kinetic energy off the mechanism's field below this fraction
MAX_SEGMENTS = 10_000   # bound on the segments of one run
SIM_ELEMENTS = 100      # continuous arch: rigid bodies of a simulation segment (plus the hinges' cuts)
REASONS = {
    "thrust_line": "the dynamic thrust line left a section (another hinge opens)",
    "friction_motion": "a section's |S|/N exceeded the friction coefficient during the motion",
    "friction_impact": "an impact's |P_t|/P_n exceeded the friction coefficient",
    "friction_rest": "at rest, the ground exceeded the load the joints carry by friction (A_L with Coulomb rows)",
    "rest": "the member came to rest",
    "settled": "at rest after the ground motion in a state the one-mechanism model cannot take back "
               "(see no_handback): it stays there",
    "mechanism": "the bodies moved on one mechanism of the member again",
    "overturned": "overturned",
    "collapsed_by_sliding": "a joint slid out",
    "end": "end of the simulated time",
}


@dataclass
class Segment:
    """One segment of an :class:`AutoResult`: one model over an interval of time.

    Attributes
    ----------
    model : {"rock", "simulate"}
        The one-mechanism model or the multi-block simulation.
    t_start, t_end : float
        Its interval (s).
    end : str
        Why it ended (a key of :data:`REASONS`).
    peak_rotation : float
        Largest rotation of any piece or body over it (rad), at ``t_peak`` (s).
    impacts : int
        Impacts in it.
    dropped : float
        Kinetic energy (J/m) dropped by the hand-back that started it.

    Examples
    --------
    :attr:`AutoResult.segments` holds them; a pulse below the onset threshold leaves the
    arch at rest in one segment of the one-mechanism model, to the end of the run (s):

    >>> import fembeam
    >>> from fembeam.auto import AutoModel
    >>> from fembeam.dynamics import GroundMotion
    >>> arch = fembeam.CircularArch(radius=1.0, thickness=0.15, embrace_deg=157.5)
    >>> res = AutoModel(arch, voussoirs=12).run(GroundMotion.sine(0.3, 0.5))
    >>> seg = res.segments[0]
    >>> print(seg.model, f"from {seg.t_start:.1f} s to {seg.t_end:.2f} s:", seg.end)
    rock from 0.0 s to 11.09 s: end
    >>> print(seg.impacts, "impacts, peak rotation", seg.peak_rotation, "rad")
    0 impacts, peak rotation 0.0 rad
    """

    model: str
    t_start: float
    t_end: float
    end: str
    peak_rotation: float = 0.0
    t_peak: float | None = None
    impacts: int = 0
    dropped: float = 0.0

    def to_dict(self) -> dict:
        return {"model": self.model, "t_start": self.t_start, "t_end": self.t_end, "end": self.end,
                "why": REASONS[self.end], "peak_rotation": self.peak_rotation, "t_peak": self.t_peak,
                "impacts": self.impacts, "handback_energy_dropped": self.dropped}


@dataclass
class AutoResult:
    """The verdict of :meth:`AutoModel.run`.

    ``t_collapse`` is the time of the collapse, by overturning or by sliding
    (``t_overturn`` the same, its deprecated name kept for one release).

    Attributes
    ----------
    curve : MidCurve
        The member.
    ground : GroundMotion
        The ground motion.
    A_L : dict
        Onset thresholds ``{+1: A, -1: A}`` (g).
    mode : {"continuous", "voussoirs"}
        The one-mechanism model's member.
    n : int
        Its voussoirs or elements.
    friction : float or None
        Coulomb coefficient of the joints (None: they never slide).
    dt : float
        Step of the simulation (s).
    outcome : str
        ``"rest"``, ``"rocking"`` or ``"overturned"``
        (:data:`fembeam.dynamics.OUTCOMES`).
    t_end : float
        End of the run (s).
    t_overturn : float or None
        Time of overturning (s), with ``overturn_reason``.
    peak_rotation : float
        Largest rotation of any piece or body (rad), at ``t_peak`` (s).
    segments : list of Segment
        The segments, in time order.
    first_failure : tuple or None
        ``(t, reason)``: the first time (s) the one-mechanism model was not admissible.
    impacts : list of tuple
        ``(t, model)`` of every impact.
    friction_ratio : tuple
        ``(largest |S|/N or |P_t|/P_n, t, s, at)`` over the run.
    history : dict
        Columns ``t`` (s), ``model`` (0 rock, 1 simulate), ``K``, ``V`` (J/m), ``a_g``
        (g), ``max_rotation`` (rad).
    no_handback : tuple or None
        ``(t, why)``: the last time (s) the simulation's member was at rest but could not be
        handed back to the one-mechanism model, and why (a joint open or slid beyond the
        hand-back's tolerance of the thickness, its size said); None when every rest was handed
        back.  A member at rest after the end of the ground motion stays there: the simulation
        stops at the second such check (a :data:`WINDOW` apart) and the run ends at ``t_end``.

    Examples
    --------
    :meth:`AutoModel.run` returns it; a 0.3 g sine pulse of 0.5 s, below the onset
    threshold ``A_L`` (g), leaves the paper's arch at rest to the end of the run (s):

    >>> import fembeam
    >>> from fembeam.auto import AutoModel
    >>> from fembeam.dynamics import GroundMotion
    >>> arch = fembeam.CircularArch(radius=1.0, thickness=0.15, embrace_deg=157.5)
    >>> res = AutoModel(arch, voussoirs=12).run(GroundMotion.sine(0.3, 0.5))
    >>> print(res.outcome, f"to {res.t_end:.2f} s, A_L = {res.A_L[1]:.4f} g")
    rest to 11.09 s, A_L = 0.3593 g
    >>> print(res.handovers, "hand-overs, collapse:", res.t_collapse)
    0 hand-overs, collapse: None
    """

    curve: MidCurve
    ground: GroundMotion
    A_L: dict
    mode: str
    n: int                                              # voussoirs or elements of rock
    friction: float | None
    dt: float
    outcome: str = "rest"
    t_end: float = 0.0
    t_overturn: float | None = None
    overturn_reason: str | None = None
    peak_rotation: float = 0.0
    t_peak: float | None = None
    segments: list[Segment] = field(default_factory=list)
    first_failure: tuple | None = None
    impacts: list = field(default_factory=list)        # (t, model) of every impact
    friction_ratio: tuple = (0.0, None, None, None)    # (largest |S|/N or |P_t|/P_n, t, s, at)
    history: dict = field(default_factory=dict)
    no_handback: tuple | None = None
    timings: dict = field(default_factory=dict)
    runs: list = field(default_factory=list)           # with the history: ("rock" | "simulate", result) of
                                                       # every run made, in order (to draw the member at any time)

    @property
    def t_collapse(self) -> float | None:
        """The time of the collapse (s), by overturning or by sliding; None without one."""
        return self.t_overturn

    @property
    def handovers(self) -> int:
        """Hand-overs between the models (segments less one)."""
        return max(len(self.segments) - 1, 0)

    def to_dict(self, history: bool = False) -> dict:
        """The JSON of ``fembeam rock --model auto`` (strict: no NaN or infinity)."""
        def num(x):
            return None if x is None or not math.isfinite(x) else float(x)

        ratio, t, s, at = self.friction_ratio
        out = {
            "command": "rock",
            "model": "auto",
            "outcome": self.outcome,
            "geometry": self.curve.describe() if hasattr(self.curve, "describe") else {},
            "mode": self.mode,
            "elements": self.n,
            "ground_motion": {"name": self.ground.name, "duration_s": self.ground.duration, "pga_g": self.ground.pga},
            "dt": self.dt,
            "t_end": self.t_end,
            "A_L": {"+1": num(self.A_L.get(1)), "-1": num(self.A_L.get(-1))},
            "peak_rotation": float(self.peak_rotation),
            "t_peak": num(self.t_peak),
            "t_collapse": num(self.t_overturn),
            "t_overturn": num(self.t_overturn),
            "overturn_reason": self.overturn_reason,
            "first_failure": None if self.first_failure is None else
            {"t": self.first_failure[0], "reason": self.first_failure[1], "why": REASONS[self.first_failure[1]]},
            "handovers": self.handovers,
            "segments": [sg.to_dict() for sg in self.segments],
            "time_in": {m: float(sum(sg.t_end - sg.t_start for sg in self.segments if sg.model == m))
                        for m in ("rock", "simulate")},
            "n_impacts": len(self.impacts),
            "impacts_by_model": {m: sum(1 for _, k in self.impacts if k == m) for m in ("rock", "simulate")},
            "friction_demand": friction_demand(ratio, t, s, at, self.friction),
            "no_handback": None if self.no_handback is None else
            {"t": self.no_handback[0], "why": self.no_handback[1]},
            "timings_s": {k: round(v, 4) for k, v in self.timings.items()},
            "units": {"A_L": "g", "density": "kg/m^3", "t": "s", "dt": "s", "peak_rotation": "rad",
                      "segments.handback_energy_dropped": "J/m", "history.K": "J/m", "history.V": "J/m",
                      "history.a_g": "g", "history.max_rotation": "rad", "friction_demand.s": "m"},
        }
        if history:
            out["history"] = {k: [float(x) for x in v] for k, v in self.history.items()}
        return out


class AutoModel:
    """The one-mechanism model while it holds, the multi-block simulation when it does not.

    The member rocks on one mechanism (:class:`~fembeam.dynamics.Rocker`) while the
    mechanism is admissible (the dynamic thrust line inside every section; with
    ``friction``, the friction demand within it); at the first violation its state is
    handed over to the multi-block simulation (:class:`~fembeam.simulation.Simulator`),
    and handed back when the member comes to rest or moves on a mechanism again. Set up
    once, run under any number of ground motions.

    Parameters
    ----------
    curve : MidCurve
        The member (lengths in m, density in kg/m^3).
    voussoirs : int, optional
        Discrete arch of this many voussoirs, in both models.
    elements : int, optional
        Otherwise the continuous member, with this many rigid elements for the limit
        analysis (default 200).
    sim_elements : int, optional
        The continuous member in the simulation: this many equal bodies (2 to 2000) plus
        a cut at each hinge of the mechanism handed over.
    friction : float, optional
        Coulomb coefficient of the joints (None, the default: they never slide).
    dt : float, optional
        Step of the simulation (s).
    backend : str, optional
        Solver of the impact QP.
    qp : bool, optional
        Also report the general impact QP's ``r_qp`` at each impact.
    g : float, optional
        Acceleration of gravity (m/s^2).

    Raises
    ------
    InputError
        An input out of range.

    Notes
    -----
    The simulation's kernel is compiled by numba on its first use in a process (about
    two minutes of CPU without numba's cache, ``NUMBA_CACHE_DIR``).

    Examples
    --------
    A pulse below the onset threshold leaves the arch at rest, in the one-mechanism
    model throughout:

    >>> import fembeam
    >>> from fembeam.auto import AutoModel
    >>> from fembeam.dynamics import GroundMotion
    >>> arch = fembeam.CircularArch(radius=1.0, thickness=0.15, embrace_deg=157.5)
    >>> model = AutoModel(arch, voussoirs=12)
    >>> res = model.run(GroundMotion.sine(0.3, 0.5))
    >>> print(f"A_L = {model.A[1]:.4f} g:", res.outcome, [s.model for s in res.segments])
    A_L = 0.3593 g: rest ['rock']
    """

    def __init__(self, curve: MidCurve, *, voussoirs: int | None = None, elements: int = 200,
                 sim_elements: int = SIM_ELEMENTS, friction: float | None = None, dt: float = DT,
                 backend: str = "clarabel", qp: bool = False, g: float = GRAVITY):
        from ..simulation.stepper import DT_RANGE, check_friction
        self.rocker = Rocker(curve, voussoirs=voussoirs, elements=elements, backend=backend, qp=qp, g=g)
        self.curve, self.g, self.voussoirs = curve, float(g), voussoirs
        self.friction = check_friction(friction)
        try:
            self.dt = float(dt)
        except (TypeError, ValueError):
            raise InputError(f"dt must be a number of seconds, got {dt!r}") from None
        if not (math.isfinite(self.dt) and DT_RANGE[0] <= self.dt <= DT_RANGE[1]):
            raise InputError(f"dt must be in [{DT_RANGE[0]:g}, {DT_RANGE[1]:g}] s, got {dt!r}")
        if not (isinstance(sim_elements, (int, np.integer)) and 2 <= sim_elements <= 2000):
            raise InputError(f"sim_elements must be an integer in [2, 2000], got {sim_elements!r}")
        self.sim_elements = int(sim_elements)
        self._sims: dict = {}
        self.rest_limit = None          # with friction: the inertia load each way the joints carry at rest
        self.slides_at_rest = False     # with friction: the joints cannot carry even the weight alone
        if self.friction is not None and self.rocker.stands:
            from ..analysis import analyze
            self.rest_limit = {}
            for d in (1, -1):
                res = analyze(curve, elements=None if voussoirs is not None else elements, voussoirs=voussoirs,
                              direction=d, backend=backend, friction=self.friction, thrust=False)
                if res.outcome == "cannot_stand":
                    self.slides_at_rest = True
                self.rest_limit[d] = res.A_L if res.outcome == "sliding" else math.inf

    @property
    def A(self) -> dict:
        return self.rocker.A

    @property
    def stands(self) -> bool:
        return self.rocker.stands

    def simulator(self, mechanism=None):
        """The :class:`~fembeam.simulation.Simulator` whose bodies have a joint at every hinge of
        ``mechanism`` (voussoirs and blocks: the one simulator; a continuous member: one per set of
        cuts, kept)."""
        from ..simulation import Simulator
        if self.voussoirs is not None or self.curve.describe().get("shape") == "block":
            key = None
            make = lambda: Simulator(self.curve, voussoirs=self.voussoirs or 1, g=self.g,  # noqa: E731
                                     friction=self.friction)
        else:
            nodes = uniform_nodes(self.curve, self.sim_elements)
            if mechanism is not None:
                nodes = nodes_through(nodes, mechanism.s, keep=self.curve.fixed_nodes)
            key = tuple(np.round(nodes / self.curve.length, 12))
            make = lambda: Simulator(self.curve, nodes=nodes, g=self.g, friction=self.friction)  # noqa: E731
        if key not in self._sims:
            self._sims[key] = make()
        return self._sims[key]

    def run(self, ground: GroundMotion, *, t_end: float | None = None, dt_out: float | None = None,
            progress=None, history: bool = True) -> AutoResult:
        """The verdict under a ground motion.

        Parameters
        ----------
        ground : GroundMotion
            The ground acceleration ``a_g(t)`` (g, positive along ``+x``).
        t_end : float, optional
            End of the run (s), default the end of the ground motion plus
            ``20 sqrt(L/g)`` (``L``: the member's length).
        dt_out : float, optional
            Sampling step of the history (s), default 1/4000 of the time.
        progress : callable, optional
            ``progress(t)`` is called after each episode and window (``t`` in s).
        history : bool, optional
            False: no history.

        Returns
        -------
        AutoResult
            The outcome, the segments of each model and the history.

        Raises
        ------
        InputError
            ``t_end`` or ``dt_out`` out of range.

        Examples
        --------
        The first 2 s under a pulse below the onset threshold, the history (the model
        in use, 0 for ``rock``; the largest rotation in rad) sampled every 0.5 s:

        >>> import fembeam
        >>> from fembeam.auto import AutoModel
        >>> from fembeam.dynamics import GroundMotion
        >>> arch = fembeam.CircularArch(radius=1.0, thickness=0.15, embrace_deg=157.5)
        >>> res = AutoModel(arch, voussoirs=12).run(GroundMotion.sine(0.3, 0.5),
        ...                                         t_end=2.0, dt_out=0.5)
        >>> h = res.history
        >>> for t, model, phi in zip(h["t"], h["model"], h["max_rotation"]):
        ...     print(f"{t:.1f} s  model {model:.0f}  {phi:.4f} rad")
        0.0 s  model 0  0.0000 rad
        0.5 s  model 0  0.0000 rad
        1.0 s  model 0  0.0000 rad
        1.5 s  model 0  0.0000 rad
        2.0 s  model 0  0.0000 rad
        """
        return _run(self, ground, t_end, dt_out, progress, history)


def _violation(r) -> tuple[float, str] | None:
    """The first violation of admissibility of the rock segment ``r``: ``(t, reason)`` or None."""
    cands = [(t, why) for t, why in ((r.thrust_line_exits_at, "thrust_line"), (r.slides_at, "friction_motion"),
                                     (r.impact_slides_at, "friction_impact"), (r.rest_slides_at, "friction_rest"))
             if t is not None]
    return min(cands) if cands else None


def _run(am: AutoModel, ground: GroundMotion, t_end, dt_out, progress, history=True) -> AutoResult:
    clock = time.perf_counter()
    rk, curve, mu = am.rocker, am.curve, am.friction
    t0 = float(ground.t[0])
    if t_end is None:
        t_end = float(ground.t[-1]) + 20.0 * math.sqrt(curve.length / am.g)
    t_end = float(t_end)
    if not (math.isfinite(t_end) and t_end > t0):
        raise InputError(f"t_end must be finite and after the start of the ground motion ({t0:g} s), got {t_end:g}")
    dt_out = (t_end - t0) / 4000.0 if dt_out is None else float(dt_out)
    if not (math.isfinite(dt_out) and dt_out > 0):
        raise InputError(f"dt_out must be a positive number of seconds, got {dt_out!r}")
    from ..simulation.stepper import MIN_STEP, check_dt
    check_dt(am.dt, t0, t_end)           # the simulation's bound on the steps, over the whole run
    done = t_end - MIN_STEP * am.dt      # a simulation step cannot be shorter: the run is over from here
    keep = history
    if not history:
        dt_out = max(dt_out, WINDOW)      # the simulation's rows: one a window
    out = AutoResult(curve, ground, dict(rk.A), rk.mode, rk.n, mu, am.dt, t_end=t_end)
    if not rk.stands:
        out.outcome = "cannot_stand"
        out.timings = {"total": time.perf_counter() - clock}
        return out
    rows = {k: [] for k in ("t", "model", "K", "V", "a_g", "max_rotation")}
    t, rock_state, sim_state, dropped = t0, None, None, 0.0
    mode, resume = "rock", False
    timing = {"rock": 0.0, "simulate": 0.0}
    if am.slides_at_rest:       # the joints slide under the weight alone: the simulation from the start
        out.first_failure = (t0, "friction_rest")
        sim = am.simulator()
        sim_state, mode = (sim, sim.bodies.rest_state(), np.zeros((sim.bodies.n + 1, 3))), "simulate"
    for _ in range(MAX_SEGMENTS):
        if t >= done:
            break
        if mode == "rock":
            tick = time.perf_counter()
            r = rk.run(ground, t_end=t_end, dt_out=dt_out, t_start=t, state=rock_state, friction=mu,
                       rest_limit=am.rest_limit, progress=progress, history=keep, stop_at_violation=True)
            timing["rock"] += time.perf_counter() - tick
            bad = r.violation
            if bad is not None and sim_state is not None and bad[0] <= t + am.dt:
                # the state handed back fails at once (within a step): the simulation goes on
                mode, resume, dropped = "simulate", True, 0.0
                continue
            if keep:
                out.runs.append(("rock", r))
            if bad is None:
                _rock_segment(out, rows if keep else None, rk, r, t, dropped,
                              "overturned" if r.outcome == "overturned" else "end")
                out.outcome, out.t_overturn, out.overturn_reason = r.outcome, r.t_overturn, r.overturn_reason
                t = r.t_end
                break
            tv, why = bad
            if tv > t:
                _rock_segment(out, rows if keep else None, rk, r, t, dropped, why)
            dropped = 0.0
            if out.first_failure is None:
                out.first_failure = (float(tv), why)
            t = max(t, tv)
            state = r.state_end
            sim = am.simulator(state[0] if state is not None else None)
            if state is None:
                q, v = sim.bodies.rest_state(), np.zeros((sim.bodies.n + 1, 3))
            else:
                m, th, w = state
                q, v = bodies_state(rk.equations[rk.index(m)], th, w, sim.bodies)
            sim_state = (sim, q, v)
            mode = "simulate"
            continue
        # ---------------------------------------------------------------- simulate
        tick = time.perf_counter()
        seg_start, peak, t_peak, n_imp, drop0 = t, 0.0, None, 0, dropped
        if resume:              # the hand-back was not made: the last simulation segment goes on
            last = out.segments.pop()
            seg_start, peak, t_peak = last.t_start, last.peak_rotation, last.t_peak
            n_imp, drop0 = last.impacts, last.dropped
            resume = False
        end = "end"
        sim, q, v = sim_state
        E_unit = sim.bodies.mass * am.g * curve.length
        handback, rested = None, False
        ground_end = float(ground.t[-1])
        while t < done:
            t1 = min(t + WINDOW, t_end)
            res = sim.run(ground, dt=am.dt, t_end=t1, dt_out=dt_out, q0=q, v0=v, t_start=t)
            if res.impacts and res.outcome not in ("overturned", "collapsed_by_sliding") and not am.slides_at_rest:
                # the first impact of the window: one step after it, is the motion on one mechanism?
                # (the same steps again from the window's start, so the same state)
                t_i = float(res.impacts[0][0]) + am.dt
                if t_i < float(res.t_end):
                    early = sim.run(ground, dt=am.dt, t_end=t_i, dt_out=dt_out, q0=q, v0=v, t_start=t)
                    hb = _handback(am, sim, early.q_end, early.v_end, E_unit)
                    if hb is not None and hb[0] == "mechanism":
                        res, handback = early, hb
            if keep:
                _sim_rows(rows, res)
                out.runs.append(("simulate", res))
            if not float(res.t_end) > t:        # no step left before t_end
                t = t_end
                break
            for ti, _, _ in res.impacts:
                out.impacts.append((float(ti), "simulate"))
            n_imp += len(res.impacts)
            if res.peak_rotation > peak:
                peak, t_peak = float(res.peak_rotation), res.t_peak
            _friction(out, res.friction_ratio, res.t_friction, res.s_friction, res.friction_at)
            q, v, t = res.q_end, res.v_end, float(res.t_end)
            if progress is not None:
                progress(t)
            if res.outcome in ("overturned", "collapsed_by_sliding"):
                end = res.outcome
                out.outcome, out.t_overturn = res.outcome, res.t_overturn
                out.overturn_reason = "below_rest" if res.outcome == "overturned" else "slid_out"
                break
            if handback is None and t < done:
                handback = None if am.slides_at_rest else _handback(am, sim, q, v, E_unit)
            if handback is not None:
                end = handback[0]
                break
            if t >= done:
                break
            if sim.bodies.kinetic_energy(v) < REST_KINETIC * E_unit:
                out.no_handback = (t, _why_not_back(sim, q))
                if rested and t >= ground_end + WINDOW:     # at rest a window apart, the ground at rest
                    end, t = "settled", t_end
                    if keep:
                        _settled_row(rows, t_end)
                    break
                rested = True
            else:
                rested = False
        timing["simulate"] += time.perf_counter() - tick
        out.segments.append(Segment("simulate", seg_start, t, end, peak, t_peak, n_imp, drop0))
        _peak(out, peak, t_peak)
        sim_state = (sim, q, v)
        if end in ("overturned", "collapsed_by_sliding", "settled") or t >= done:
            if end == "settled":
                out.outcome = "rest"
            elif end == "end":
                K = sim.bodies.kinetic_energy(v)
                out.outcome = "rest" if K < REST_KINETIC * E_unit else "survived"
            break
        why, rock_state, dropped = handback
        mode = "rock"
    else:
        raise SolverError(f"the motion needed more than {MAX_SEGMENTS} hand-overs before t = {t_end:g} s")
    out.t_end = float(t_end if out.t_overturn is None else out.t_overturn)
    out.history = {k: np.asarray(x, float) for k, x in rows.items()}
    out.timings = {**timing, "total": time.perf_counter() - clock}
    return out


def _handback(am: AutoModel, sim, q, v, E_unit):
    """``(reason, rock state, dropped energy)`` when the simulation's state may go back to the
    one-mechanism model, else None."""
    K = sim.bodies.kinetic_energy(v)
    if K < REST_KINETIC * E_unit:
        gap, slip = _rest_offsets(sim, q)
        return ("rest", None, K) if max(gap.max(), slip.max()) <= POSITION_TOL else None
    on = mechanism_of(sim.bodies, sim.contacts, q, v, g=am.g, position_tol=POSITION_TOL, velocity_tol=VELOCITY_TOL)
    if on is None:
        return None
    m, theta, rate, drop = on
    return "mechanism", (m, theta, rate), drop


def _rest_offsets(sim, q) -> tuple[np.ndarray, np.ndarray]:
    """Each joint's largest opening and its slip in the simulation's state ``q``, as
    fractions of the joint's thickness: a rest the one-mechanism model can take has both within
    :data:`POSITION_TOL`."""
    geo = sim.contacts.evaluate(q)
    t = sim.bodies.thickness
    return np.max(geo.gap, axis=1) / t, np.abs(geo.slip[np.arange(t.size), geo.contact]) / t


def _why_not_back(sim, q) -> str:
    """Why the member at rest in the simulation's state ``q`` is not the one-mechanism model's
    rest: its largest joint opening or slip against the hand-back's tolerance."""
    gap, slip = _rest_offsets(sim, q)
    j, k = int(np.argmax(gap)), int(np.argmax(slip))
    size, joint, what = (gap[j], j, "open") if gap[j] >= slip[k] else (slip[k], k, "slid")
    return (f"joint {joint} is {what} by {size:.3g} of its thickness, above the hand-back's tolerance "
            f"{POSITION_TOL:g}: the one-mechanism model has no such state")


def _settled_row(rows: dict, t_end: float) -> None:
    """The history's last row at ``t_end``: the member at rest where the simulation left it."""
    if rows["t"] and rows["t"][-1] < t_end:
        rows["t"].append(t_end)
        rows["model"].append(1.0)
        rows["a_g"].append(0.0)
        for k in ("K", "V", "max_rotation"):
            rows[k].append(rows[k][-1])


def _peak(out: AutoResult, peak: float, t_peak) -> None:
    if peak > out.peak_rotation:
        out.peak_rotation, out.t_peak = float(peak), t_peak


def _friction(out: AutoResult, ratio, t, s, at) -> None:
    if t is not None and ratio > out.friction_ratio[0]:
        out.friction_ratio = (float(ratio), float(t), s, at)


def _rock_segment(out: AutoResult, rows: dict | None, rk: Rocker, r, t_start: float, dropped: float, end: str) -> None:
    """Append the rock run ``r`` (from ``t_start``) as a segment: figures, impacts and history rows."""
    out.segments.append(Segment("rock", t_start, float(r.t_overturn if r.t_overturn is not None else r.t_end), end,
                                float(r.peak_rotation), r.t_peak, len(r.impacts), dropped))
    _peak(out, r.peak_rotation, r.t_peak)
    out.impacts.extend((float(e.t), "rock") for e in r.impacts)
    fd = r.friction_demand
    if fd is not None:
        _friction(out, fd["max_ratio"], fd["t"], fd["s"], fd["at"])
    if rows is None:
        return
    h = r.history
    eqs = [rk.equations[rk.index(m)] for m in r.mechanisms]
    rot = [0.0 if k < 0 else max(abs(x) for x in eqs[int(k)].piece_rotations(th))
           for k, th in zip(h["mechanism"].tolist(), h["theta"].tolist())]
    rows["t"].extend(h["t"].tolist())
    rows["model"].extend([0.0] * len(rot))
    rows["K"].extend(h["K"].tolist())
    rows["V"].extend(h["V"].tolist())
    rows["a_g"].extend(h["a_g"].tolist())
    rows["max_rotation"].extend(rot)


def _sim_rows(rows: dict, res) -> None:
    """Append the history of a simulation window (its first row dropped when the previous window
    ended at that time: one row per time)."""
    h = res.history
    skip = 1 if rows["t"] and len(h["t"]) and rows["model"][-1] == 1.0 and float(h["t"][0]) == rows["t"][-1] else 0
    n = len(h["t"]) - skip
    rows["t"].extend(np.asarray(h["t"][skip:], float).tolist())
    rows["model"].extend([1.0] * n)
    for k in ("K", "V", "a_g", "max_rotation"):
        rows[k].extend(np.asarray(h[k][skip:], float).tolist())
