"""The result of a one-mechanism motion (:func:`~fembeam.dynamics.rocking.rock`): its outcome,
impacts, onsets, peaks, energies and history, and the JSON of ``fembeam rock``."""
from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from ..geometry import MidCurve
from ..mechanisms import Mechanism
from .equation import EquationOfMotion
from .ground import GroundMotion
from .outcomes import friction_demand

__all__ = ["ImpactEvent", "RockingResult", "Track"]


@dataclass(frozen=True)
class ImpactEvent:
    """An impact of a rocking motion (:attr:`RockingResult.impacts`).

    Attributes
    ----------
    t : float
        Time of the impact (s).
    before : int
        Mechanism before it (index into :attr:`RockingResult.mechanisms`).
    after : int or None
        Mechanism after it (None: arrested).
    rate_in : float
        Incoming rate of ``before``'s free parameter (rad/s).
    rate_out : float
        Outgoing rate on ``after`` (rad/s).
    r : float
        ``K'/K`` of the impact model.
    r_qp : float or None
        ``K'/K`` of the general impact QP (None unless asked for).
    at_rest : bool
        The episode ended at rest (arrested, or an accumulation of impacts).

    Examples
    --------
    A 0.8 g sine pulse of 0.5 s overturns the paper's arch of 12 voussoirs after one
    impact, at a time ``t`` (s) with incoming and outgoing rates (rad/s):

    >>> import fembeam
    >>> from fembeam.dynamics import GroundMotion
    >>> arch = fembeam.CircularArch(radius=1.0, thickness=0.15, embrace_deg=157.5)
    >>> res = fembeam.dynamics.rock(arch, GroundMotion.sine(0.8, 0.5), voussoirs=12)
    >>> e = res.impacts[0]
    >>> print(f"t = {e.t:.3f} s, r = {e.r:.3f}, mechanism {e.before} -> {e.after}")
    t = 0.536 s, r = 0.607, mechanism 0 -> 1
    >>> print(f"rate {e.rate_in:.3f} -> {e.rate_out:.3f} rad/s")
    rate -2.057 -> -0.751 rad/s
    """

    t: float
    before: int
    after: int | None
    rate_in: float
    rate_out: float
    r: float
    r_qp: float | None
    at_rest: bool          # the episode ended at rest (arrested, or accumulation)


@dataclass
class RockingResult:
    """Outcome and history of :func:`rock` (and :meth:`Rocker.run`).

    ``t_collapse`` is the time of the collapse (s; one mechanism collapses by
    overturning only); ``t_overturn`` is the same, its deprecated name kept for one release.

    Energies are per metre of barrel width (J/m); rotations in rad, positive
    counter-clockwise.

    Attributes
    ----------
    curve : MidCurve
        The member.
    ground : GroundMotion
        The ground motion.
    outcome : {"rest", "rocking", "overturned"}
        At rest at the end, still rocking at ``t_end``, or overturned.
    t_end : float
        End of the run (s).
    A_L : dict
        ``{+1: A_L, -1: A_L}`` (g; ``inf``: no mechanism).
    mechanisms : list of Mechanism
        The mechanisms met (``history["mechanism"]`` indexes them).
    impacts : list of ImpactEvent
        The impacts, in time order.
    onsets : list of (float, int)
        ``(t, mechanism index)`` of each start from rest.
    peak_rotation : float
        Largest ``|rotation|`` of any piece (rad; mirror invariant), at ``t_peak`` (s).
    peak_theta : float
        Largest ``|theta|`` (rad, the rotation of the first moving piece), at
        ``t_peak_theta`` (s).
    t_overturn : float or None
        Time of overturning (s), with ``overturn_reason`` (``"below_rest"`` or
        ``"linkage_locked"``).
    thrust_line_exits_at : float or None
        First time the thrust line leaves a section (s).
    energy_balance_error : float
        Relative error of ``K + V = E_start + W_ground - impact losses``.
    K_end, V_end : float
        Kinetic and potential energy at the end (J/m).
    ground_work, dissipated : float
        Work of the ground on the member, and energy lost in the impacts (J/m).
    history : dict
        Columns ``t`` (s), ``mechanism`` (index, -1 at rest), ``theta`` (rad),
        ``rate`` (rad/s), ``K``, ``V`` (J/m), ``a_g`` (g).
    state_end : tuple or None
        ``(mechanism, theta, rate)`` at the end (None at rest).

    Examples
    --------
    :func:`~fembeam.dynamics.rock` returns it. A 0.4 g sine pulse of 0.5 s rocks the
    paper's arch of 12 voussoirs, which comes back to rest; the energy the ground put in
    (J/m) is lost in the impacts:

    >>> import fembeam
    >>> from fembeam.dynamics import GroundMotion
    >>> arch = fembeam.CircularArch(radius=1.0, thickness=0.15, embrace_deg=157.5)
    >>> res = fembeam.dynamics.rock(arch, GroundMotion.sine(0.4, 0.5), voussoirs=12)
    >>> print(res.outcome, f"peak {res.peak_rotation:.4f} rad at {res.t_peak:.3f} s")
    rest peak 0.0025 rad at 0.200 s
    >>> print(f"ground work {res.ground_work:.3f} J/m, dissipated {res.dissipated:.3f} J/m")
    ground work 2.027 J/m, dissipated 2.027 J/m

    A 0.8 g pulse overturns it:

    >>> res = fembeam.dynamics.rock(arch, GroundMotion.sine(0.8, 0.5), voussoirs=12)
    >>> print(res.outcome, f"at t = {res.t_collapse:.3f} s")
    overturned at t = 1.052 s
    """

    curve: MidCurve
    ground: GroundMotion
    outcome: str
    t_end: float
    A_L: dict                               # {+1: A_L(+1), -1: A_L(-1)} (g; inf: no mechanism)
    mechanisms: list[Mechanism] = field(default_factory=list)
    impacts: list[ImpactEvent] = field(default_factory=list)
    onsets: list[tuple[float, int]] = field(default_factory=list)   # (t, mechanism index)
    peak_rotation: float = 0.0                  # largest |rotation| of any piece (rad; mirror invariant)
    t_peak: float | None = None                 # its time (s)
    peak_theta: float = 0.0                     # largest |theta| (the rotation of the first moving piece)
    t_peak_theta: float | None = None
    peaks: list = field(default_factory=list)   # (t, mechanism index, theta): every turning point
    t_overturn: float | None = None        # deprecated name of t_collapse, kept for one release
    settled_at: float | None = None         # Rocker.run(settle=True): the free motion ends at rest
    overturn_reason: str | None = None      # "below_rest" or "linkage_locked"
    thrust_line_exits_at: float | None = None
    energy_balance_error: float = 0.0
    K_end: float = 0.0                      # J/m, at the end (t_end or t_overturn)
    V_end: float = 0.0
    V_min: float = 0.0                      # the smallest V of the motion
    ground_work: float = 0.0                # the ground's work on the member
    dissipated: float = 0.0                 # sum over the impacts of K_in - K_out
    thrust_checked: bool = False            # the thrust line and the friction demand were checked
    friction: float | None = None           # Coulomb coefficient given (None: unlimited)
    friction_motion: tuple | None = None    # (largest |S|/N, t, s) over the motion
    friction_impact: tuple | None = None    # (largest |P_t|/P_n, t, s) over the impacts
    slides_at: float | None = None          # with a friction coefficient: first time |S|/N exceeds it in the motion
    impact_slides_at: float | None = None   # ... and first impact whose |P_t|/P_n exceeds it
    state_end: tuple | None = None          # (mechanism, theta, rate) at the end; None at rest
    rest_slides_at: float | None = None     # Rocker.run(rest_limit=...): first time at rest above that limit
    violation: tuple | None = None          # Rocker.run(stop_at_violation=True): (t, reason) where it stopped
    state_cut: tuple | None = None          # (mechanism index, theta, rate) there (internal)
    history: dict = field(default_factory=dict)
    unstable_rotation: list[float] = field(default_factory=list)   # per mechanism: V' = 0 (rad, signed)
    overturn_rotation: list[float] = field(default_factory=list)   # per mechanism: overturned there (rad, signed)
    mode: str = "continuous"
    n: int = 0                              # pieces of the discretisation: voussoirs or elements
    timings: dict = field(default_factory=dict)

    @property
    def t_collapse(self) -> float | None:
        """The time of the collapse (s); None without one."""
        return self.t_overturn

    @property
    def elements(self) -> int:
        """:attr:`n` (the JSON's ``elements``: voussoirs or elements, as ``mode`` says)."""
        return self.n

    def to_dict(self, history: bool = False) -> dict:
        """The JSON of ``fembeam rock`` (no NaN or infinity: null where undefined)."""
        def num(x):
            return None if x is None or not math.isfinite(x) else float(x)

        desc = self.curve.describe() if hasattr(self.curve, "describe") else {}
        out = {
            "command": "rock",
            "outcome": self.outcome,
            "geometry": desc,
            "mode": self.mode,
            "elements": self.n,
            "ground_motion": {"name": self.ground.name, "duration_s": self.ground.duration,
                              "pga_g": self.ground.pga},
            "t_end": self.t_end,
            "A_L": {"+1": num(self.A_L.get(1)), "-1": num(self.A_L.get(-1))},
            "peak_rotation": float(self.peak_rotation),
            "t_peak": num(self.t_peak),
            "peak_theta": float(self.peak_theta),
            "t_peak_theta": num(self.t_peak_theta),
            "turning_points": [{"t": t, "mechanism": k, "theta": th} for t, k, th in self.peaks],
            "t_collapse": num(self.t_overturn),
            "t_overturn": num(self.t_overturn),
            "overturn_reason": self.overturn_reason,
            "thrust_line_exits_at": num(self.thrust_line_exits_at),
            "friction_demand": self.friction_demand,
            "onsets": [{"t": t, "mechanism": k} for t, k in self.onsets],
            "n_impacts": len(self.impacts),
            "impacts": [{"t": e.t, "r": e.r, "r_qp": num(e.r_qp), "rate_in": e.rate_in, "rate_out": e.rate_out,
                         "hinges_before": self.mechanisms[e.before].to_list(),
                         "hinges_after": self.mechanisms[e.after].to_list() if e.after is not None else [],
                         "mechanism_before": e.before, "mechanism_after": e.after, "at_rest": e.at_rest}
                        for e in self.impacts],
            "mechanisms": [{"index": i, "hinges": m.to_list(), "unstable_rotation": num(u), "overturn_rotation": num(o)}
                           for i, (m, u, o) in enumerate(zip(self.mechanisms, self.unstable_rotation,
                                                             self.overturn_rotation))],
            "energy": {"K_end": float(self.K_end), "V_end": float(self.V_end), "V_min": float(self.V_min),
                       "ground_work": float(self.ground_work), "dissipated": float(self.dissipated)},
            "energy_balance_error": float(self.energy_balance_error),
            "timings_s": {k: round(v, 4) for k, v in self.timings.items()},
            "units": {"A_L": "g", "density": "kg/m^3", "t": "s", "theta": "rad", "peak_rotation": "rad",
                      "rate": "rad/s", "energy": "J/m", "energy_balance_error": "relative", "history.K": "J/m",
                      "history.V": "J/m", "history.a_g": "g", "friction_demand.s": "m"},
        }
        if history:
            out["history"] = {k: [float(x) for x in v] for k, v in self.history.items()}
        return out

    @property
    def friction_demand(self) -> dict | None:
        """The block ``friction_demand`` (:func:`.outcomes.friction_demand`): the larger of the
        motion's ``|S|/N`` and the impacts' ``|P_t|/P_n`` (``at``: ``"motion"`` or ``"impact"``),
        ``sliding_risk`` against :attr:`friction`; None when the thrust line was not checked."""
        if not self.thrust_checked:
            return None
        ratio, t, s = self.friction_motion or (0.0, None, None)
        at = None if t is None else "motion"
        if self.friction_impact is not None and self.friction_impact[0] > ratio:
            (ratio, t, s), at = self.friction_impact, "impact"
        return friction_demand(ratio, t, s, at, self.friction)

    def csv_rows(self) -> list[dict]:
        h = self.history
        return [dict(zip(h, row)) for row in zip(*(h[k] for k in h))]




@dataclass
class Track:
    """The history under construction and the running figures."""

    grid: np.ndarray
    keep: bool = True            # keep the dense output of the motion (for the thrust-line check)
    rows: dict = field(default_factory=lambda: {k: [] for k in ("t", "mechanism", "theta", "rate", "K", "V", "a_g")})
    peak: float = 0.0            # largest |rotation| of any piece, and its time
    t_peak: float | None = None
    peak_theta: float = 0.0      # largest |theta|, and its time
    t_peak_theta: float | None = None
    V_min: float = 0.0           # smallest V at the turning points and ends of the episodes
    pieces: list = field(default_factory=list)   # (ta, tb, mechanism, dense solution) of the motion
    peaks: list = field(default_factory=list)    # (t, mechanism, theta) where the rate vanishes
    friction_best: tuple = (0.0, None, None)     # largest |S|/N scanned episode by episode (stop at violation)

    def __post_init__(self):
        self.grid_list = self.grid.tolist()

    def add(self, t, k, theta, rate, K, V, a):
        for key, v in zip(self.rows, (t, k, theta, rate, K, V, a)):
            self.rows[key].append(v)

    def peak_at(self, t: float, theta: float, eq: EquationOfMotion):
        """A turning point or the end of an episode at ``t``: the running peaks.  The pieces'
        rotations are taken where ``|theta|`` peaks: exact while each grows with ``|theta|`` along
        the mechanism (the four-bar's rates ``w3``, ``w2`` keep their sign; so on every mechanism
        of the tests), otherwise a lower bound.  So is the smallest ``V`` (``V`` rises to the
        unstable equilibrium, then falls: over an excursion its smallest value is at an end).
        At ``theta = 0`` (the rest shape) every piece is at rest: nothing is recorded (the
        four-bar's closure gives the coupler and rocker rotations of about 1e-15 rad there)."""
        if theta == 0.0:
            return
        if abs(theta) > self.peak_theta:
            self.peak_theta, self.t_peak_theta = abs(theta), float(t)
        self.V_min = min(self.V_min, eq.potential(theta))
        rot = max(abs(x) for x in eq.piece_rotations(theta))
        if rot > self.peak:
            self.peak, self.t_peak = rot, float(t)

