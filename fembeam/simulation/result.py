"""The result of ``fembeam simulate``: outcome, figures, the sampled history; JSON and CSV rows."""
from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from ..dynamics.ground import GroundMotion
from ..dynamics.outcomes import friction_demand
from ..geometry import MidCurve
from .bodies import Bodies
from .constants import OPEN_TOL

__all__ = ["SimulationResult", "OUTCOMES", "HISTORY_COLUMNS"]

OUTCOMES = ("rest", "survived", "overturned", "collapsed_by_sliding", "cannot_stand")
HISTORY_COLUMNS = ("t", "K", "V", "W_ground", "dissipated", "a_g", "hinges", "separated", "max_rotation")


@dataclass
class SimulationResult:
    """Outcome and history of :meth:`Simulator.run`.

    Energies are per metre of barrel width (J/m). ``outcome``
    (:data:`fembeam.dynamics.outcomes.OUTCOMES`): ``"rest"`` (at rest at ``t_end``),
    ``"survived"`` (still moving at ``t_end``), ``"overturned"`` (the centroid of the member fell
    ``OVERTURN_DROP`` of its mean thickness below its height at rest, at ``t_overturn``: past the
    unstable equilibrium of whatever mechanism it moved on, the joints opening more than they
    slid), ``"collapsed_by_sliding"`` (at ``t_overturn`` a joint's faces no longer overlap, or
    the centroid fell to that level while the largest slip a joint carried exceeded the largest
    opening of a joint's end, m) or ``"cannot_stand"`` (the pieces do not carry their own
    weight on joints that do not slide: nothing computed).
    ``peak_rotation`` (rad): the largest ``|phi|`` of any body, as ``fembeam rock``'s.
    ``friction_ratio``: the largest ``|P_t| / N`` of a joint over the steps and impacts (at
    ``t_friction``, joint at arc length ``s_friction``); ``max_slip`` (m) the largest slip carried
    by a joint (friction only).  ``history`` columns
    (:data:`HISTORY_COLUMNS`): ``t`` (s), ``K``, ``V``, ``W_ground``, ``dissipated``
    (J/m), ``a_g`` (g), ``hinges`` (joints with exactly one corner open), ``separated`` (joints with
    both corners open), ``max_rotation`` (rad); ``positions`` the ``(n, 3)`` states ``x, y, phi`` at
    the same times.  With a prescribed support motion (``support_motion``) the history also has
    :data:`~.support_motion.SUPPORT_COLUMNS`: ``support_displacement`` (m, the ``delta`` of
    ``fembeam supports``), ``H_left``, ``H_right`` (kN/m: the mean horizontal force of the arch on
    each support since the previous row, positive outward) and ``V_left``, ``V_right`` (kN/m, the
    vertical ones, positive downward).

    Attributes
    ----------
    outcome : {"rest", "survived", "overturned", "collapsed_by_sliding", "cannot_stand"}
        What happened, as above.
    t_end : float
        End of the run (s).
    t_collapse : float or None
        Time of the collapse, by overturning or by sliding (s); None without one.
    t_overturn : float or None
        The former name of ``t_collapse`` (the field it reads), kept one release.
    peak_rotation : float
        Largest ``|phi|`` of any body (rad), at ``t_peak`` (s).
    max_hinges : int
        Most joints open at once.
    energy_balance_error : float
        Relative error of the energy balance.
    dissipated, ground_work, friction_work : float
        Energy lost in impacts, work of the ground, work of friction (J/m).
    friction_ratio : float
        Largest ``|P_t| / N`` of a joint, at ``t_friction`` (s) and ``s_friction`` (m).
    max_slip : float or None
        Largest slip of a joint (m, friction only).
    history : dict
        The columns above, sampled every ``dt_out``.
    positions : list of ndarray
        ``(n, 3)`` states ``x, y, phi`` (m, m, rad) at the history's times.
    impacts : list of tuple
        ``(t, K before, K after)`` (s, J/m, J/m) of each impact.
    q_end, v_end : ndarray or None
        ``(n + 1, 3)`` positions and velocities at ``t_end`` (last row the ground's
        zeros): a later run may start from them.

    Examples
    --------
    :meth:`Simulator.run` (or :func:`~fembeam.simulation.simulate`) returns it; the first
    0.3 s of a block 2 m high and 0.4 m wide under a 0.4 g sine pulse of 0.5 s, by the
    NumPy reference engine:

    >>> import fembeam
    >>> from fembeam.dynamics import GroundMotion
    >>> from fembeam.simulation import Simulator
    >>> sim = Simulator(fembeam.StraightMember(height=2.0, width=0.4))
    >>> res = sim.run(GroundMotion.sine(0.4, 0.5), dt=2e-3, t_end=0.3, engine="reference")
    >>> print(res.outcome, f"at {res.t_end:.1f} s, peak {res.peak_rotation:.4f} rad")
    survived at 0.3 s, peak 0.0238 rad
    >>> print(f"ground work {res.ground_work:.2f} J/m, K = {res.history['K'][-1]:.3f} J/m")
    ground work 71.23 J/m, K = 0.937 J/m
    """

    curve: MidCurve
    ground: GroundMotion
    bodies: Bodies
    mode: str = "voussoirs"
    dt: float = 1e-3
    outcome: str = "rest"
    t_end: float = 0.0
    t_overturn: float | None = None
    peak_rotation: float = 0.0
    t_peak: float | None = None
    max_hinges: int = 0
    energy_balance_error: float = 0.0
    dissipated: float = 0.0
    ground_work: float = 0.0
    projection_drift: float = 0.0
    friction: float | None = None
    friction_ratio: float = 0.0
    t_friction: float | None = None
    s_friction: float | None = None
    friction_at: str | None = None
    max_slip: float | None = None
    t_slip: float | None = None
    s_slip: float | None = None
    sliding_steps: int = 0
    redistributed: int = 0
    loose_steps: int = 0
    solved_by: dict = field(default_factory=dict)
    friction_work: float = 0.0
    coulomb_residual: float = 0.0
    V_min: float = 0.0
    timings: dict = field(default_factory=dict)
    steps: int = 0
    cut_steps: int = 0
    pivots: int = 0
    time: float = 0.0
    history: dict = field(default_factory=lambda: {k: [] for k in HISTORY_COLUMNS})
    positions: list = field(default_factory=list)
    impacts: list = field(default_factory=list)     # (t, K before, K after) of each impact (a corner closes)
    q_end: np.ndarray | None = None                 # (n + 1, 3) positions and velocities at t_end (the last
    v_end: np.ndarray | None = None                 # row the ground's zeros): a later run may start from them
    support_motion: object = None                   # the SupportMotion of the run (None: supports fixed)
    support_t0: float = 0.0                         # s: when the supports started to move
    support_q_end: np.ndarray | None = None         # (2, 2) m: the supports' displacements at t_end

    def record(self, t, q, v, K, V, W_ground, D, a_g, gap, thickness) -> None:
        """Append one history row (``gap`` ``(J, 2)`` and ``thickness`` ``(J, 1)``, m)."""
        opened = gap > OPEN_TOL * thickness
        k = opened.sum(axis=1)
        row = (t, K, V, W_ground, D, a_g, int(np.sum(k == 1)), int(np.sum(k == 2)), float(np.max(np.abs(q[:-1, 2]))))
        for key, x in zip(HISTORY_COLUMNS, row):
            self.history[key].append(float(x) if key not in ("hinges", "separated") else x)
        self.positions.append(q[:-1].copy())

    def finish(self, **kw) -> None:
        for k, x in kw.items():
            setattr(self, k, x)
        self.history = {k: np.asarray(x, float) for k, x in self.history.items()}
        self.max_hinges = int(np.max(self.history["hinges"], initial=0))

    @property
    def t_collapse(self) -> float | None:
        """The time of the collapse, by overturning or by sliding (s); None without one."""
        return self.t_overturn

    @property
    def friction_demand(self) -> dict:
        """The JSON block of :func:`fembeam.dynamics.outcomes.friction_demand`: ``sliding_risk`` is
        ``max_ratio >= mu``.  With friction modelled, a joint that slid (sliding rate above the
        solver's tolerance, normal percussion resolved) counts with a ratio of at least ``mu``: it
        needed more friction than ``mu`` to stick; the steps whose only sliding joints carry an
        unresolved normal percussion (a corner lifting off at a landing) are counted in
        ``sliding.sliding_steps`` and are no sliding risk."""
        out = friction_demand(self.friction_ratio, self.t_friction, self.s_friction, self.friction_at, self.friction)
        if self.friction is not None:
            out["sliding_risk"] = bool(self.friction_ratio >= self.friction)
        return out

    @property
    def n_bodies(self) -> int:
        return self.bodies.n

    def to_dict(self, history: bool = False) -> dict:
        """The JSON of ``fembeam simulate`` (strict: no NaN or infinity)."""
        def num(x):
            return None if x is None or not math.isfinite(x) else float(x)

        h = self.history
        out = {
            "command": "simulate",
            "outcome": self.outcome,
            "geometry": self.curve.describe() if hasattr(self.curve, "describe") else {},
            "mode": self.mode,
            "bodies": self.n_bodies,
            "joints": self.bodies.n_joints,
            "ground_motion": {"name": self.ground.name, "duration_s": self.ground.duration, "pga_g": self.ground.pga},
            "dt": self.dt,
            "t_end": self.t_end,
            "t_collapse": num(self.t_overturn),
            "t_overturn": num(self.t_overturn),
            "overturn_reason": ("below_rest" if self.outcome == "overturned" else
                                "slid_out" if self.outcome == "collapsed_by_sliding" else None),
            "peak_rotation": num(self.peak_rotation),
            "t_peak": num(self.t_peak),
            "max_hinges": self.max_hinges,
            "hinges_over_time": {"t": [float(x) for x in h["t"]], "hinges": [int(x) for x in h["hinges"]],
                                 "separated": [int(x) for x in h["separated"]]},
            "energy": {"K_end": num(h["K"][-1]) if len(h["K"]) else 0.0,
                       "V_end": num(h["V"][-1]) if len(h["V"]) else 0.0,
                       "ground_work": num(self.ground_work), "dissipated": num(self.dissipated),
                       "projection_drift": num(self.projection_drift), "V_min": num(self.V_min),
                       "friction_work": num(self.friction_work)},
            "energy_balance_error": num(self.energy_balance_error),
            "n_impacts": len(self.impacts),
            "impacts": [{"t": float(t), "r": float(b / a) if a > 0 else 0.0} for t, a, b in self.impacts],
            "friction_demand": self.friction_demand,
            "sliding": {"mu": num(self.friction), "max_slip": num(self.max_slip), "t": num(self.t_slip),
                        "s": num(self.s_slip), "sliding_steps": self.sliding_steps,
                        "self_stress_steps": self.redistributed, "loose_steps": self.loose_steps,
                        "solved_by": self.solved_by,
                        "coulomb_residual_max": num(self.coulomb_residual)},
            "steps": self.steps,
            "cut_steps": self.cut_steps,
            "pivots": self.pivots,
            "timings_s": {k: round(v, 4) for k, v in (self.timings or {"total": self.time}).items()},
            "units": {"density": "kg/m^3", "t": "s", "dt": "s", "peak_rotation": "rad", "energy": "J/m",
                      "energy_balance_error": "relative", "history.K": "J/m", "history.V": "J/m",
                      "history.W_ground": "J/m", "history.dissipated": "J/m", "history.a_g": "g",
                      "history.max_rotation": "rad", "sliding.max_slip": "m", "friction_demand.s": "m"},
        }
        if self.support_motion is not None:
            out["support_motion"] = self.support_block()
            out["units"].update({"support_motion.rate_m_per_s": "m/s", "support_motion.up_to_m": "m",
                                 "support_motion.start_m": "m", "support_displacement_at_collapse": "m",
                                 "history.support_displacement": "m", "history.H_left": "kN/m",
                                 "history.V_left": "kN/m", "history.H_right": "kN/m", "history.V_right": "kN/m"})
            out["support_displacement_at_collapse"] = out["support_motion"]["displacement_at_collapse"]
        if history:
            out["history"] = {k: [float(x) for x in v] for k, v in h.items()}
        return out

    def support_block(self) -> dict:
        """The JSON block of a prescribed support motion: the motion, the support displacement
        (m) at the collapse (None if it did not collapse) and at the end, and the last sampled
        forces on the supports (kN/m)."""
        mo = self.support_motion
        collapsed = self.outcome in ("overturned", "collapsed_by_sliding") and self.t_overturn is not None
        h = self.history
        last = {k: (float(h[k][-1]) if len(h.get(k, ())) else None) for k in ("H_left", "V_left", "H_right", "V_right")}
        return {**mo.describe(),
                "displacement_at_collapse": float(mo.displacement(self.t_overturn - self.support_t0)) if collapsed
                else None,
                "displacement_end": float(mo.displacement(self.t_end - self.support_t0)),
                "last_forces_kN_per_m": last}

    def csv_rows(self) -> list[dict]:
        h = self.history
        return [{k: (int(x) if k in ("hinges", "separated") else float(x)) for k, x in zip(h, row)}
                for row in zip(*(h[k] for k in h))]
