"""The whole motion: rest, onset, rocking along one mechanism, impacts, overturning.

:func:`rock` follows a member through a ground motion ``a_g(t)`` (g, positive along +x):

* **rest**: the member stays undeformed while ``-a_g <= A_L(+1)`` and ``a_g <= A_L(-1)``
  (``A_L(d)``: the limit analysis with the inertia load along ``d x``; computed once);
* **onset**: when the inertia load first exceeds ``A_L`` in one direction (crossing located
  on the piecewise-linear signal), the member starts from rest on that direction's mechanism;
* **rocking**: Lagrange's equation of the mechanism at finite rotation
  (:class:`~fembeam.dynamics.equation.EquationOfMotion`), integrated by DOP853 (SciPy's
  tableau, error norm and step control at rtol 1e-10, in plain floats: :class:`_Dop853`) with
  steps ending on the kinks of the signal and event location on each step's interpolant;
* **impact**: the member returns to ``theta = 0``; the mechanism after it and its rate come from
  the impact model (:class:`~fembeam.dynamics.transitions.ImpactModel`, computed once per
  mechanism); an impact that arrests the member (r = 0), or a post-impact kinetic energy below
  ``REST_ENERGY`` of the energy barrier (the accumulation of infinitely many impacts in finite
  time, whose times form a geometric series), ends the episode at rest;
* **overturning** (the rule shared with ``fembeam simulate``, :mod:`.outcomes`): the potential
  energy falls below ``-0.1 m g t`` (the member's centroid a tenth of its mean thickness below its
  height at rest: reason ``"below_rest"``), the integration going on past the unstable
  equilibrium (``V' = 0``), where the ground may still push the member back; or the four-bar
  linkage locks first (``"linkage_locked"``).

Along the motion the ground's work is integrated as a third state, so that
``K + V = E_start + W_ground - impact losses`` is checked (``energy_balance_error``).
"""
from __future__ import annotations

import math
import time
from bisect import bisect_left, bisect_right
from dataclasses import dataclass, field
from operator import mul

import numpy as np

from ..analysis import analyze
from ..errors import InputError, SolverError
from ..fem import uniform_nodes
from ..geometry import MidCurve
from ..mechanisms import Mechanism
from .equation import GRAVITY, EquationOfMotion
from .ground import GroundMotion
from .outcomes import OUTCOMES, friction_demand, overturn_level
from .thrust import friction_ratio, impact_impulses, section_forces_many, uniform_sections
from .transitions import ImpactModel, Transition

__all__ = ["rock", "Rocker", "RockingResult", "ImpactEvent", "onset_time", "REST_ENERGY", "OUTCOMES"]

REST_ENERGY = 1e-12     # post-impact K / energy barrier below which the member is at rest
MAX_EPISODES = 100_000  # bound on the number of episodes (impacts + onsets) of one run
RTOL = 1e-10
EPS = np.finfo(float).eps
MAX_OUTPUT_STEPS = 10_000_000   # history rows (about 0.5 GB)
THRUST_TOL = 1e-6       # thrust line outside the section by more than this fraction of t: exit
SECTIONS = 50           # continuous member: sections checked per moving piece (and one next to each hinge)


@dataclass(frozen=True)
class ImpactEvent:
    """An impact at time ``t`` (s): incoming rate ``rate_in`` (rad/s) on mechanism ``before``
    (index into :attr:`RockingResult.mechanisms`), outgoing ``rate_out`` on ``after`` (None:
    arrested), ``r = K'/K`` of the impact model and ``r_qp`` of the general QP."""

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
    """Outcome and history of :func:`rock`.  ``history`` columns: ``t`` (s), ``mechanism``
    (index, -1 at rest), ``theta`` (rad), ``rate`` (rad/s), ``K``, ``V`` (J per unit depth),
    ``a_g`` (g)."""

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
    t_overturn: float | None = None
    settled_at: float | None = None         # Rocker.run(settle=True): the free motion ends at rest
    overturn_reason: str | None = None      # "below_rest" or "linkage_locked"
    thrust_line_exits_at: float | None = None
    energy_balance_error: float = 0.0
    K_end: float = 0.0                      # J per unit depth, at the end (t_end or t_overturn)
    V_end: float = 0.0
    V_min: float = 0.0                      # the smallest V of the motion
    ground_work: float = 0.0                # the ground's work on the member
    dissipated: float = 0.0                 # sum over the impacts of K_in - K_out
    thrust_checked: bool = False            # the thrust line and the friction demand were checked
    friction: float | None = None           # Coulomb coefficient given (None: unlimited)
    friction_motion: tuple | None = None    # (largest |S|/N, t, s) over the motion
    friction_impact: tuple | None = None    # (largest |P_t|/P_n, t, s) over the impacts
    history: dict = field(default_factory=dict)
    unstable_rotation: list[float] = field(default_factory=list)   # per mechanism: V' = 0 (rad, signed)
    overturn_rotation: list[float] = field(default_factory=list)   # per mechanism: overturned there (rad, signed)
    mode: str = "continuous"
    elements: int = 0
    timings: dict = field(default_factory=dict)

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
            "elements": self.elements,
            "ground_motion": {"name": self.ground.name, "duration_s": self.ground.duration,
                              "pga_g": self.ground.pga},
            "t_end": self.t_end,
            "A_L": {"+1": num(self.A_L.get(1)), "-1": num(self.A_L.get(-1))},
            "peak_rotation": float(self.peak_rotation),
            "t_peak": num(self.t_peak),
            "peak_theta": float(self.peak_theta),
            "t_peak_theta": num(self.t_peak_theta),
            "turning_points": [{"t": t, "mechanism": k, "theta": th} for t, k, th in self.peaks],
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


# --------------------------------------------------------------------------- onset
def onset_time(ground: GroundMotion, t0: float, t1: float, A_plus: float, A_minus: float):
    """First time in ``[t0, t1]`` at which ``-a_g > A_plus`` (returns ``(t, +1)``) or
    ``a_g > A_minus`` (``(t, -1)``), exact on the piecewise-linear signal (zero outside its
    samples), refined on the formula of a pulse; None if the ground stays below both
    thresholds."""
    t, a = ground.t, ground.a
    # the signal on [t0, t1]: its samples inside, with the values at t0 and t1
    inside = (t > t0) & (t < t1)
    ts = np.concatenate([[t0], t[inside], [t1]])
    av = np.concatenate([[float(ground(t0))], a[inside], [float(ground(t1))]])
    if t0 < t[0] < t1:      # the jump from zero to the first sample
        k = np.searchsorted(ts, t[0])
        ts, av = np.insert(ts, k, t[0]), np.insert(av, k, 0.0)
    best = None
    for d, f in ((1, -av - A_plus), (-1, av - A_minus)):
        if not np.isfinite(f).all() or not np.any(f > 0):
            continue
        i = int(np.argmax(f > 0))
        if i == 0:
            tc = ts[0]
        else:
            f0, f1 = f[i - 1], f[i]
            tc = ts[i - 1] + (ts[i] - ts[i - 1]) * (-f0) / (f1 - f0)
            tc = min(max(tc, ts[i - 1]), ts[i])
            if ground.exact is not None:     # the crossing of the pulse's formula in this interval
                ex = (lambda x: -ground.exact.at(x) - A_plus) if d == 1 else (lambda x: ground.exact.at(x) - A_minus)
                if ex(ts[i - 1]) <= 0 < ex(ts[i]):
                    tc = _brentq()(ex, ts[i - 1], ts[i], xtol=1e-15, rtol=8 * EPS)
                    while ex(tc) <= 0 and tc < ts[i]:    # just inside the exceedance
                        tc = np.nextafter(tc, np.inf)
        if best is None or tc < best[0]:
            best = (float(tc), d)
    return best


def _below_time(ground: GroundMotion, t0: float, t1: float, A_plus: float, A_minus: float, eps: float):
    """First sample time in ``(t0, t1]`` where the ground is within both thresholds
    (``-a_g <= A_plus`` and ``a_g <= A_minus``), or just after the last sample (where the
    signal is zero); None if there is none before ``t1``."""
    t, a = ground.t, ground.a
    ok = np.flatnonzero((t > t0) & (t <= t1) & (-a <= A_plus) & (a <= A_minus))
    if ok.size:
        return float(t[ok[0]])
    after = max(float(t[-1]), t0) + eps
    return after if after <= t1 else None


# --------------------------------------------------------------------------- the run
@dataclass
class _Track:
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
        unstable equilibrium, then falls: over an excursion its smallest value is at an end)."""
        if abs(theta) > self.peak_theta:
            self.peak_theta, self.t_peak_theta = abs(theta), float(t)
        self.V_min = min(self.V_min, eq.potential(theta))
        rot = max(abs(x) for x in eq.piece_rotations(theta))
        if rot > self.peak:
            self.peak, self.t_peak = rot, float(t)


def _check_inputs(curve, ground, t_end):
    if not isinstance(ground, GroundMotion):
        raise InputError(f"rock needs a fembeam.dynamics.GroundMotion, got {type(ground).__name__}")
    if t_end is not None:
        try:
            t_end = float(t_end)
        except (TypeError, ValueError):
            raise InputError(f"t_end must be a number of seconds, got {t_end!r}") from None
        if not math.isfinite(t_end) or t_end <= ground.t[0]:
            raise InputError(f"t_end must be finite and after the start of the ground motion "
                             f"({ground.t[0]:g} s), got {t_end:g}")
    return t_end


class Rocker:
    """A member's dynamics, set up once and run under any number of ground motions: the
    limit analyses in both directions (onset thresholds ``A`` and mechanisms), the impact
    model (transitions cached) and the equations of motion of the mechanisms met so far.

    ``voussoirs``: discrete arch (hinges at joints only); otherwise the continuous member with
    ``elements`` rigid elements for the limit analysis and the general impact QP.  ``qp``:
    report the general QP's ``r_qp`` at each impact.
    """

    def __init__(self, curve: MidCurve, *, voussoirs: int | None = None, elements: int = 200,
                 backend: str = "clarabel", qp: bool = True, g: float = GRAVITY):
        if not isinstance(curve, MidCurve):
            raise InputError(f"rock needs a member (e.g. fembeam.CircularArch), got {type(curve).__name__}")
        clock = time.perf_counter()
        self.curve, self.g = curve, float(g)
        self.mode = "voussoirs" if voussoirs is not None else "continuous"
        self.n = voussoirs if voussoirs is not None else elements
        self.A: dict[int, float] = {}
        self.start: dict[int, Mechanism] = {}
        self.stands = True
        for d in (1, -1):
            res = analyze(curve, elements=None if voussoirs is not None else elements, voussoirs=voussoirs,
                          direction=d, backend=backend)
            if res.outcome == "cannot_stand":
                self.stands = False
                self.A = {1: math.nan, -1: math.nan}
                break
            self.A[d] = res.A_L if res.outcome in ("rocking", "arrested") else math.inf
            if math.isfinite(self.A[d]):
                self.start[d] = Mechanism.from_hinges(curve, res.hinges_before)
        self.model = ImpactModel(curve, voussoirs=voussoirs, elements=elements, backend=backend, qp=qp)
        self.joints = uniform_nodes(curve, voussoirs) if voussoirs is not None else None
        self.mass = float(curve.segment_inertia(0.0, curve.length)[0][0])     # kg per unit depth
        self.level = overturn_level(curve, self.mass, self.g)                 # V below it: overturned
        self.mechanisms: list[Mechanism] = []
        self.equations: list[EquationOfMotion] = []
        self.tops: list[float] = []        # per mechanism: sign * theta where it has overturned
        self.events: list[str] = []        # per mechanism: "overturn" (V falls to the level) or "locked"
        self.barriers: list[float] = []    # per mechanism: the largest V up to its top
        self._index: dict = {}
        self._impact_friction: dict = {}   # (before, after, sign of the rate): (|P_t|/P_n, s)
        self.setup_time = time.perf_counter() - clock

    def index(self, m: Mechanism) -> int:
        """Index of mechanism ``m`` (its equation of motion and overturning angle set up on
        first use)."""
        key = (m.s, m.sides)
        if key not in self._index:
            self._index[key] = len(self.mechanisms)
            self.mechanisms.append(m.with_alpha(1.0))
            eq = EquationOfMotion(m, self.g)
            self.equations.append(eq)
            top, event, barrier = overturning(eq, self.level)
            self.tops.append(top)
            self.events.append(event)
            self.barriers.append(barrier)
        return self._index[key]

    def run(self, ground: GroundMotion, *, t_end: float | None = None, dt_out: float | None = None,
            thrust_check: bool = True, progress=None, history: bool = True, settle: bool = False,
            friction: float | None = None) -> RockingResult:
        """Time history under ``ground``.  ``t_end`` (s): default the end of the ground
        motion plus ``20 sqrt(L/g)`` (L: the member's length); ``dt_out`` (s): history
        sampling step (default ``(t_end - t_0) / 4000``); ``thrust_check``: find the first
        time the thrust line leaves the section and the friction demand (:func:`thrust_scan`,
        :func:`impact_friction`); ``progress(t)`` is called after each episode.
        ``history=False``: only the rows at events and at the end.  ``settle``: at the end of
        the ground motion, stop if the free motion is known to come to rest without
        overturning (:meth:`settles`): outcome ``"rest"``, ``settled_at`` and ``t_end`` that time.
        ``friction``: a Coulomb coefficient (> 0) for ``friction_demand``'s ``sliding_risk``
        (it does not change the motion: the joints never slide in this model)."""
        return _run(self, ground, t_end, dt_out, thrust_check, progress, history, settle, friction)

    def barrier(self, k: int) -> float:
        """The energy barrier of mechanism ``k`` (J per unit depth): the largest ``V`` from rest
        to its overturning angle (:func:`overturning`; ``V`` at the unstable equilibrium, or
        just before the linkage locks if it locks first).  A free motion whose energy stays
        below it turns back; one above it reaches the overturning angle."""
        return self.barriers[k]

    def settles(self, k: int, theta: float, rate: float, margin: float = 1e-8) -> bool:
        """True when the free motion (no ground acceleration) from ``theta``, ``rate`` on
        mechanism ``k`` comes to rest without overturning.  Along a mechanism ``E = K + V`` is
        conserved and ``V`` rises from 0 to the unstable equilibrium, then falls to the
        overturning level (:func:`overturning`; the barrier, :meth:`barrier`, is the largest ``V``
        on the way).  So a member short of the unstable equilibrium heading back, or heading out
        with ``E`` below the barrier, returns to ``theta = 0`` with ``K = E``, while one heading
        out with ``E`` above the barrier reaches the overturning angle.  Each impact leads to a
        fixed mechanism (the impact model's, solved once) with ``K' = r K``.  This map is
        iterated until ``r = 0`` or ``K`` falls below ``REST_ENERGY`` of the barrier (True), or an
        energy heading out comes within ``margin`` of its barrier (False: only the integration
        can tell; so too a member past the unstable equilibrium)."""
        eq = self.equations[k]
        if eq.sign * theta > eq.theta_unstable:
            return False
        E = eq.energy(theta, rate)
        if eq.sign * rate > 0 and not E < self.barrier(k) * (1.0 - margin):
            return False
        for _ in range(MAX_EPISODES):       # an impact with K = E on mechanism k
            tr = self.model(self.mechanisms[k])
            if tr.after is None or tr.r * E < REST_ENERGY * self.barrier(k):
                return True
            k, E = self.index(tr.after), tr.r * E
            if not E < self.barrier(k) * (1.0 - margin):
                return False
        return False


OVERTURN_GRID = 256     # steps from the unstable equilibrium to the lock (or pi) scanning for the level


def overturning(eq: EquationOfMotion, level: float) -> tuple[float, str, float]:
    """Where mechanism ``eq`` has overturned under the shared rule (:mod:`.outcomes`: ``V`` below
    ``level`` < 0): ``(top, event, barrier)`` with ``top`` the smallest ``sign * theta`` at which
    ``V = level`` (``event`` ``"overturn"``), or just before the four-bar locks if it locks
    first (``"locked"``); ``barrier`` the largest ``V`` on ``[0, top]``.

    ``V`` rises from 0 to the unstable equilibrium ``theta_unstable`` (the first ``V' = 0``), so the
    level is looked for beyond it: on ``OVERTURN_GRID`` steps up to the lock (or pi), the first
    step that ends below it is bisected (``brentq``).  ``V`` past the unstable equilibrium is
    scanned on the same steps for a higher hump; one found is maximised (bounded Brent)."""
    sg = eq.sign
    lock = eq.theta_lock * (1 - 1e-9)

    def V(x):
        return eq.potential(sg * x)

    xu = eq.theta_unstable
    if not math.isfinite(xu):                       # V rises all the way to the lock
        if not math.isfinite(lock):
            raise SolverError("gravity restores the mechanism at every rotation: it cannot overturn")
        return lock, "locked", V(lock)
    barrier, hump = V(xu), None
    hi = min(lock, math.pi)
    prev, v_prev = xu, barrier
    for i in range(1, OVERTURN_GRID + 1):
        x = xu + (hi - xu) * i / OVERTURN_GRID
        v = V(x)
        if v <= level:
            top = _brentq()(lambda y: V(y) - level, prev, x, xtol=1e-15, rtol=1e-14)
            break
        if v > barrier and (hump is None or v > hump[1]):
            hump = (x, v)
        prev, v_prev = x, v
    else:
        if hi < lock:
            raise SolverError(f"the mechanism neither falls to the overturning level nor locks up to a rotation "
                              f"of pi (V = {v_prev:g} J/m at pi, level {level:g} J/m)")
        top = lock
    if hump is not None:                            # a higher hump past the unstable equilibrium
        from scipy.optimize import minimize_scalar

        step = (hi - xu) / OVERTURN_GRID
        r = minimize_scalar(lambda y: -V(y), bounds=(max(xu, hump[0] - step), min(top, hump[0] + step)),
                            method="bounded", options={"xatol": 1e-12})
        barrier = max(hump[1], -float(r.fun))
    return float(top), ("overturn" if top < lock else "locked"), float(barrier)


def rock(curve: MidCurve, ground: GroundMotion, *, voussoirs: int | None = None, elements: int = 200,
         t_end: float | None = None, dt_out: float | None = None, backend: str = "clarabel",
         qp: bool = True, thrust_check: bool = True, g: float = GRAVITY, progress=None,
         friction: float | None = None) -> RockingResult:
    """Time history of ``curve`` under ``ground`` (see the module docstring, :class:`Rocker`)."""
    return Rocker(curve, voussoirs=voussoirs, elements=elements, backend=backend, qp=qp, g=g).run(
        ground, t_end=t_end, dt_out=dt_out, thrust_check=thrust_check, progress=progress, friction=friction)


def _check_friction(mu) -> float | None:
    """None, or a Coulomb coefficient: a finite number > 0 (InputError otherwise)."""
    if mu is None:
        return None
    if isinstance(mu, bool) or not isinstance(mu, (int, float, np.integer, np.floating)) \
            or not (math.isfinite(mu) and mu > 0):
        raise InputError(f"the friction coefficient must be a finite number > 0, got {mu!r}")
    return float(mu)


def _run(rk: Rocker, ground, t_end, dt_out, thrust_check, progress, history=True, settle=False,
         friction=None) -> RockingResult:
    clock = time.perf_counter()
    curve, g = rk.curve, rk.g
    t_end = _check_inputs(curve, ground, t_end)
    friction = _check_friction(friction)
    if friction is not None and not thrust_check:
        raise InputError("a friction coefficient is checked against the friction demand, which comes with the "
                         "thrust-line check: do not turn the check off")
    t0 = float(ground.t[0])
    if t_end is None:
        t_end = float(ground.t[-1]) + 20.0 * math.sqrt(curve.length / g)
    if dt_out is None:
        dt_out = (t_end - t0) / 4000.0
    try:
        dt_out = float(dt_out)
    except (TypeError, ValueError):
        raise InputError(f"dt_out must be a number of seconds, got {dt_out!r}") from None
    if not (math.isfinite(dt_out) and dt_out > 0) or (t_end - t0) / dt_out > MAX_OUTPUT_STEPS:
        raise InputError(f"dt_out must be positive with at most {MAX_OUTPUT_STEPS:g} output steps, got {dt_out:g}")
    A, start, model, mechs, eqs = rk.A, rk.start, rk.model, rk.mechanisms, rk.equations
    mech_index = rk.index
    if not rk.stands:
        out = RockingResult(curve, ground, "cannot_stand", t_end, dict(A), mode=rk.mode, elements=rk.n,
                            friction=friction)
        out.timings = {"setup": rk.setup_time, "total": time.perf_counter() - clock}
        return out
    timings = {"setup": rk.setup_time}
    t_tr = 0.0
    T_ref = math.sqrt(curve.length / g)

    track = _Track(np.arange(t0, t_end + 0.5 * dt_out, dt_out) if history else np.empty(0), thrust_check)
    sig = _Signal(ground)
    t_quiet = float(ground.t[-1])   # the ground is still from then on
    out = RockingResult(curve, ground, "rest", t_end, dict(A), mode=rk.mode, elements=rk.n, friction=friction)
    t, state = t0, None         # state: (mechanism index, theta, rate) while moving
    balance = 0.0               # largest |K + V - E_start - W_ground| of an episode (relative)
    t_int = 0.0
    for _ in range(MAX_EPISODES):
        if progress is not None:
            progress(t)
        if t >= t_end:
            break
        if state is None:       # at rest: wait for the next onset
            on = onset_time(ground, t, t_end, A[1], A[-1])
            if on is not None and out.onsets and t - out.onsets[-1][0] <= 1e-9 * T_ref:
                # the last onset led back to rest at once (a load that only touches A_L):
                # wait until the ground is back below both thresholds, then for a new crossing
                tb = _below_time(ground, t, t_end, A[1], A[-1], 1e-9 * T_ref)
                on = None if tb is None else onset_time(ground, tb, t_end, A[1], A[-1])
            _rest_rows(track, ground, t, t_end if on is None else on[0])
            if on is None:
                t = t_end
                break
            t, d = on
            k = mech_index(start[d])
            out.onsets.append((t, k))
            state = (k, 0.0, 0.0)
        k, theta, rate = state
        eq = eqs[k]
        ti = time.perf_counter()
        check = settle and t < t_quiet < t_end
        ev, t, theta, rate, err, work = _episode(eq, k, sig, t, t_quiet if check else t_end, theta, rate, track,
                                                 rk.tops[k], rk.events[k])
        t_int += time.perf_counter() - ti
        balance = max(balance, err)
        out.ground_work += work
        if ev == "end":
            state = (k, theta, rate)
            if check and t < t_end:     # the end of the ground motion
                if rk.settles(k, theta, rate):
                    out.settled_at = t_end = t
                    break
                continue
            break
        if ev in ("overturn", "locked"):
            out.outcome = "overturned"
            out.t_overturn = t
            out.overturn_reason = "below_rest" if ev == "overturn" else "linkage_locked"
            state = (k, theta, rate)
            break
        # impact at theta = 0
        tt = time.perf_counter()
        tr: Transition = model(mechs[k])
        t_tr += time.perf_counter() - tt
        barrier = rk.barriers[k]
        K_in = 0.5 * eq.coefficients(0.0)[0] * rate * rate
        if tr.after is None:
            out.impacts.append(ImpactEvent(t, k, None, rate, 0.0, 0.0, tr.r_qp, True))
            out.dissipated += K_in
            state = None
            continue
        k2 = mech_index(tr.after)
        rate2 = abs(rate) * tr.alpha_ratio
        K_out = 0.5 * eqs[k2].coefficients(0.0)[0] * rate2 * rate2
        if abs(K_out - tr.r * K_in) > 1e-9 * K_in:
            raise SolverError(f"impact at t = {t:g} s: K'/K = {K_out / K_in:.12g} differs from r = {tr.r:.12g}")
        at_rest = K_out < REST_ENERGY * barrier
        out.impacts.append(ImpactEvent(t, k, k2, rate, 0.0 if at_rest else rate2, tr.r, tr.r_qp, at_rest))
        out.dissipated += K_in - (0.0 if at_rest else K_out)      # at rest: what is left is lost too
        state = None if at_rest else (k2, 0.0, rate2)
    else:
        raise SolverError(f"the motion needed more than {MAX_EPISODES} episodes (impacts and onsets) before "
                          f"t = {t_end:g} s; stopped at t = {t:g} s")
    if out.outcome != "overturned":
        out.outcome = "rest" if state is None or (state[2] == 0.0 and state[1] == 0.0) \
            or out.settled_at is not None else "survived"
        out.t_end = t_end
        if not track.rows["t"] or track.rows["t"][-1] < t_end:     # the history ends at t_end
            a_end = float(ground(t_end))
            if state is None:
                track.add(t_end, -1, 0.0, 0.0, 0.0, 0.0, a_end)
            else:
                k, th, w = state
                track.add(t_end, k, th, w, 0.5 * eqs[k].coefficients(th)[0] * w * w, eqs[k].potential(th), a_end)
    if state is not None:
        k, th, w = state
        out.K_end, out.V_end = 0.5 * eqs[k].coefficients(th)[0] * w * w, eqs[k].potential(th)
    out.V_min = track.V_min
    out.mechanisms = list(mechs)
    out.unstable_rotation = [e.sign * min(e.theta_unstable, e.theta_lock) for e in eqs]
    out.overturn_rotation = [e.sign * x for e, x in zip(eqs, rk.tops)]
    out.peak_rotation, out.t_peak, out.peaks = track.peak, track.t_peak, track.peaks
    out.peak_theta, out.t_peak_theta = track.peak_theta, track.t_peak_theta
    out.energy_balance_error = balance
    out.history = {k_: np.asarray(v, float) for k_, v in track.rows.items()}
    timings.update(integration=t_int, transitions=t_tr)
    out.timings = {**timings, "total": time.perf_counter() - clock}
    if thrust_check:
        t_chk = time.perf_counter()
        out.thrust_checked = True
        out.thrust_line_exits_at, out.friction_motion = thrust_scan(track.pieces, eqs, ground, dt_out, rk.joints)
        hits = [(*impact_friction(rk, e.before, e.after, e.rate_in), e.t) for e in out.impacts if e.after is not None]
        if hits:             # the first impact within rounding of the largest (mirrored transitions tie)
            top = max(h[0] for h in hits)
            ratio, s_, t_ = next(h for h in hits if h[0] >= top * (1 - 1e-12))
            out.friction_impact = (top, t_, s_)
        out.timings["thrust_check"] = time.perf_counter() - t_chk
    out.timings["total"] = time.perf_counter() - clock
    return out


def motion_sections(eq: EquationOfMotion, joints: np.ndarray | None) -> np.ndarray:
    """The sections checked on mechanism ``eq``: a voussoir arch's joints in its moving pieces
    (the voussoirs are monolithic), not a free end (it carries nothing); otherwise
    :func:`~fembeam.dynamics.thrust.uniform_sections` (``SECTIONS`` per moving piece and one next to
    each hinge)."""
    m = eq.mechanism
    if joints is None:
        return uniform_sections(m, SECTIONS)
    br = m.breaks[np.flatnonzero(m.moving)[[0, -1]] + [0, 1]]
    keep = (joints >= br[0]) & (joints <= br[1])
    for end, s_end in zip(m.curve.ends, (0.0, m.curve.length)):
        keep &= ~((end == "free") & (joints == s_end))
    return joints[keep]


def thrust_scan(pieces, eqs: list[EquationOfMotion], ground: GroundMotion, dt: float,
                joints: np.ndarray | None = None, tol: float = THRUST_TOL):
    """The dynamic thrust line along the motion (``pieces``: ``(ta, tb, mechanism, dense
    solution)``) at the sections of :func:`motion_sections`: ``(exit, (ratio, t, s))``.

    ``exit``: the first time (s) at which it leaves the section by more than ``tol`` of the
    thickness anywhere (from then on other hinges would open); None if it never does.
    ``(ratio, t, s)``: the largest ``|S| / N`` over the sections in compression (S the shear, N
    the normal force) and its time and section (m); ``(0, None, None)`` without motion.

    Each piece of motion is evaluated every ``dt`` (at least 5, at most 400 instants; all the
    instants of a mechanism at once: :func:`~fembeam.dynamics.thrust.section_forces_many`); the first exit is located
    (``brentq``) to 2^-32 of a scan interval, the largest ratio refined by bounded Brent on the
    scan intervals either side of its best instant."""
    cuts: dict[int, np.ndarray] = {}
    at = ground.scalar()

    def state(k, instants):
        """The forces on mechanism ``k`` at the ``(dense solution, t)`` pairs ``instants``."""
        y = np.array([sol(tt)[:2] for sol, tt in instants]).reshape(-1, 2)
        a = np.array([at(tt) for _, tt in instants])
        acc = np.array([eqs[k].acceleration(th, w, x) for (th, w), x in zip(y.tolist(), a.tolist())])
        return section_forces_many(eqs[k], y[:, 0], y[:, 1], acc, a, cuts[k])

    def margin(k, sol, tt):
        return float(state(k, [(sol, tt)]).margin[0]) + tol

    def ratio(k, sol, tt):
        _, best, i = friction_ratio(state(k, [(sol, tt)]))
        return float(best[0]), (float(cuts[k][i[0]]) if i[0] >= 0 else None)

    grids = [np.linspace(ta, tb, int(np.clip(np.ceil((tb - ta) / dt), 5, 400))) for ta, tb, _, _ in pieces]
    results: list = [None] * len(pieces)
    for k in sorted({p[2] for p in pieces}):     # every instant of a mechanism in one evaluation
        cuts[k] = motion_sections(eqs[k], joints)
        idx = [i for i, p in enumerate(pieces) if p[2] == k]
        f = state(k, [(pieces[i][3], tt) for i in idx for tt in grids[i].tolist()])
        _, best, _ = friction_ratio(f)
        ends = np.cumsum([0] + [grids[i].size for i in idx])
        for i, lo, hi in zip(idx, ends[:-1], ends[1:]):
            results[i] = (f.margin[lo:hi], best[lo:hi])
    exit_at, top = None, (0.0, None, None, None)       # ratio, time, piece, scan interval
    for (ta, tb, k, sol), ts, (margins, best) in zip(pieces, grids, results):
        if exit_at is None:
            out = np.flatnonzero(margins + tol < 0)
            if out.size:
                i = int(out[0])
                if i == 0:
                    exit_at = float(ta)
                else:
                    prev, tt = ts[i - 1], ts[i]
                    xtol = (tt - prev) * 2.0 ** -32     # to 2^-32 of a scan interval, on the exit side
                    x = _brentq()(lambda x_: margin(k, sol, x_), prev, tt, xtol=xtol)
                    while x < tt and margin(k, sol, x) >= 0:
                        x = min(x + xtol, tt)
                    exit_at = float(x)
        i = int(np.argmax(best))
        if best[i] > top[0]:
            top = (float(best[i]), float(ts[i]), (k, sol), (ts[max(i - 1, 0)], ts[min(i + 1, ts.size - 1)]))
    if top[1] is None:
        return exit_at, (0.0, None, None)
    value, t_best, (k, sol), (lo, hi) = top
    s_best = ratio(k, sol, t_best)[1]
    if hi > lo:
        from scipy.optimize import minimize_scalar

        r = minimize_scalar(lambda x: -ratio(k, sol, x)[0], bounds=(lo, hi), method="bounded",
                            options={"xatol": 1e-10 * (hi - lo)})
        if -r.fun > value:
            value, t_best = float(-r.fun), float(r.x)
            s_best = ratio(k, sol, t_best)[1]
    return exit_at, (value, t_best, s_best)


def impact_friction(rk: "Rocker", before: int, after: int, rate_in: float) -> tuple[float, float | None]:
    """The largest ``|P_t| / P_n`` of the percussions (:func:`~fembeam.dynamics.thrust.impact_impulses`)
    over the sections in compression (:func:`motion_sections` of the mechanism after) of an impact
    from mechanism ``before`` to ``after`` (rate ``rate_in``, sign only: the ratios do not depend on
    its size), and its section (m); cached per pair."""
    key = (before, after, rate_in > 0)
    if key not in rk._impact_friction:
        eq, eq2 = rk.equations[before], rk.equations[after]
        tr = rk.model(rk.mechanisms[before])
        cuts = motion_sections(eq2, rk.joints)
        f = impact_impulses(eq, eq2, math.copysign(1.0, rate_in), tr.alpha_ratio, cuts)
        if not f.residual < 1e-8:
            raise SolverError(f"the impulses of the impact from mechanism {before} to {after} do not balance "
                              f"(relative residual {f.residual:.1e})")
        _, best, i = friction_ratio(f)
        rk._impact_friction[key] = (float(best[0]), float(cuts[i[0]]) if i[0] >= 0 else None)
    return rk._impact_friction[key]


def _rest_rows(track: _Track, ground: GroundMotion, ta: float, tb: float):
    g = track.grid
    ts = g[(g >= ta) & (g < tb)]
    for tt, a in zip(ts.tolist(), ground(ts).tolist()):
        track.add(tt, -1, 0.0, 0.0, 0.0, 0.0, a)


# --------------------------------------------------------------------------- the integrator
# Hairer's DOP853 (SciPy's tableau): stage rows A[s] (s = 1..15, length s), nodes C, weights B,
# error weights E3, E5 and the dense-output matrix D, as plain floats; read by the first
# integrator made (scipy.integrate takes 0.6 s to import: `fembeam rock --help` need not)
_NS = _A = _C = _B = _E3 = _E5 = _D = None


def _brentq():
    """``scipy.optimize.brentq``, imported on first use (0.2 s)."""
    from scipy.optimize import brentq

    return brentq


def _load_tableau() -> None:
    global _NS, _A, _C, _B, _E3, _E5, _D
    if _NS is None:
        from scipy.integrate._ivp import dop853_coefficients as dop

        _A = [dop.A[s, :s].tolist() for s in range(1, dop.N_STAGES_EXTENDED)]
        _C, _B, _E3, _E5, _D = (x.tolist() for x in (dop.C, dop.B, dop.E3, dop.E5, dop.D))
        _NS = dop.N_STAGES
_SAFETY, _MIN_FACTOR, _MAX_FACTOR, _EXPONENT = 0.9, 0.2, 10.0, -1.0 / 8.0


def _poly(F, x: float) -> float:
    """The DOP853 interpolant's increment at ``x`` in [0, 1] of its step (SciPy's form)."""
    F0, F1, F2, F3, F4, F5, F6 = F
    u = 1.0 - x
    return x * (F0 + u * (F1 + x * (F2 + u * (F3 + x * (F4 + u * (F5 + x * F6))))))


# the interpolant's terms beyond the chord, x u, x^2 u, x^2 u^2, x^3 u^2, x^3 u^3, x^4 u^3 (u = 1 - x),
# are at most a^a b^b / (a + b)^(a + b) on [0, 1] for x^a u^b
_BOUNDS = (1 / 4, 4 / 27, 1 / 16, 108 / 3125, 1 / 64, 6912 / 823543)
# the largest |d/dx| and |d^2/dx^2| on [0, 1] of the terms from x^2 u^2 on (at the ends or where the next
# derivative vanishes), rounded up
_SLOPES = (0.19245009, 0.13557551, 0.05366564, 0.03358307)
_CURVES = (2.0, 2.0, 0.37500001, 0.2425993)
_DERIV = None     # 7 x 7: the power coefficients (x^0 .. x^6, rows) of the derivative of each term of _poly


def _deviation(F) -> float:
    """A bound on ``|_poly(F, x) - x F[0]|`` for ``x`` in [0, 1]: how far the interpolant may
    stray from the chord of its step (the terms of :data:`_BOUNDS`, written out: this runs at
    every step)."""
    _, f1, f2, f3, f4, f5, f6 = F
    b1, b2, b3, b4, b5, b6 = _BOUNDS
    return b1 * abs(f1) + b2 * abs(f2) + b3 * abs(f3) + b4 * abs(f4) + b5 * abs(f5) + b6 * abs(f6)


def _monotone(F) -> bool:
    """Whether ``_poly(F, x)`` is monotone for ``x`` in [0, 1]: its slope is that of the first three
    terms, ``F0 + F1 (1 - 2x) + F2 (2x - 3x^2)`` (a quadratic: its range on [0, 1] is that of its
    ends and vertex), give or take the slopes of the others (at most :data:`_SLOPES`)."""
    f0, f1, f2, f3, f4, f5, f6 = F
    s3, s4, s5, s6 = _SLOPES
    r = s3 * abs(f3) + s4 * abs(f4) + s5 * abs(f5) + s6 * abs(f6)
    a, b = f0 + f1, f0 - f1 - f2
    lo, hi = (a, b) if a < b else (b, a)
    if f2 != 0.0:
        x = (f2 - f1) / (3.0 * f2)
        if 0.0 < x < 1.0:
            q = f0 + f1 * (1.0 - 2.0 * x) + f2 * x * (2.0 - 3.0 * x)
            lo, hi = min(lo, q), max(hi, q)
    return lo > r or hi < -r


def _one_extremum(F) -> bool:
    """Whether the slope of ``_poly(F, x)`` is monotone for ``x`` in [0, 1] (at most one extremum):
    its second derivative is ``-2 F1 + F2 (2 - 6x)`` give or take that of the terms from ``x^2
    u^2`` on (at most :data:`_CURVES`)."""
    _, f1, f2, f3, f4, f5, f6 = F
    c3, c4, c5, c6 = _CURVES
    r = c3 * abs(f3) + c4 * abs(f4) + c5 * abs(f5) + c6 * abs(f6)
    a, b = 2.0 * (f2 - f1), -2.0 * (f1 + 2.0 * f2)
    return (a > r and b > r) or (a < -r and b < -r)


def _extrema(F) -> list[float]:
    """The points ``x`` in (0, 1) where ``d/dx _poly(F, x)`` may vanish, sorted: the real roots
    of this polynomial of degree 6 (eigenvalues of its companion matrix), and the real parts of
    nearly real ones (an extra point is harmless: between two consecutive points, and the ends,
    the interpolant is monotone)."""
    global _DERIV
    if _DERIV is None:
        from numpy.polynomial import polynomial as P

        terms = [(1, 0), (1, 1), (2, 1), (2, 2), (3, 2), (3, 3), (4, 3)]     # x^a (1 - x)^b
        rows = [np.pad(P.polyder(P.polymul(P.polypow([0, 1], a), P.polypow([1, -1], b))), (0, 7))[:7]
                for a, b in terms]
        _DERIV = np.array(rows).T.tolist()
    c = [sum(map(mul, F, col)) for col in _DERIV]
    n = 6
    while n and c[n] == 0.0:
        n -= 1
    if n == 0:
        return []
    A = np.eye(n, k=-1)          # the companion matrix of c[0] + c[1] x + ... + c[n] x^n
    A[0] = c[n - 1::-1]
    A[0] /= -c[n]
    return sorted(z.real for z in np.linalg.eigvals(A).tolist() if abs(z.imag) <= 1e-6 and 0.0 < z.real < 1.0)


class _Signal:
    """The ground acceleration for the integrator: ``breaks`` (kinks: every sample of a record
    or of a short pulse, the ends of a finely sampled smooth pulse) and, on each interval
    between them, ``a_g(t)`` as a cheap scalar function (a record: the line of that interval)."""

    def __init__(self, ground: GroundMotion):
        self.at = ground.scalar()
        smooth = ground.smooth and ground.t.size > 8
        self.breaks = (ground.t[[0, -1]] if smooth else ground.t).tolist()
        self.linear = ground.exact is None and not smooth     # a_g linear between breaks
        self.values = ground.a.tolist()

    def jumps(self, t: float) -> bool:
        """``a_g`` may jump at the break ``t`` (a record is continuous between its ends)."""
        return not self.linear or t == self.breaks[0] or t == self.breaks[-1]

    def interval(self, t: float):
        """``(tb, a_g)``: the first break after ``t`` (inf: none) and ``a_g`` up to it."""
        br = self.breaks
        i = bisect_right(br, t)
        tb = br[i] if i < len(br) else math.inf
        if not self.linear:
            return tb, self.at
        if i == 0 or i == len(br):
            return tb, lambda x: 0.0
        ta, a0, da = br[i - 1], self.values[i - 1], self.values[i] - self.values[i - 1]
        dt = tb - ta
        return tb, lambda x: a0 + da * (x - ta) / dt


class _Dop853:
    """DOP853 with SciPy's error norm and step-size control, in plain floats, for the equation
    of motion ``theta'' = -(Lambda'/2 theta'^2 + V' + a_g Q) / Lambda`` with the ground's work
    ``W' = -a_g Q theta'`` as a third state.  ``ag``: ``a_g(t)`` on the current interval."""

    def __init__(self, coef, atol: tuple[float, float, float], ag):
        _load_tableau()
        self.coef, self.atol, self.ag = coef, atol, ag

    def rhs(self, t: float, th: float, w: float) -> tuple[float, float]:
        """``(theta'', W')`` at ``(t, theta, theta')``."""
        Lam, dLam, dV, Q = self.coef(th)
        a = self.ag(t)
        return -(0.5 * dLam * w * w + dV + a * Q) / Lam, -a * Q * w

    def first_step(self, t: float, y: tuple, f: tuple, span: float) -> float:
        """Hairer's starting step (SciPy's ``select_initial_step``, order 7)."""
        sc = [a + abs(v) * RTOL for a, v in zip(self.atol, y)]
        d0 = math.sqrt(sum((v / s) ** 2 for v, s in zip(y, sc)) / 3)
        d1 = math.sqrt(sum((v / s) ** 2 for v, s in zip(f, sc)) / 3)
        h0 = min(1e-6 if d0 < 1e-5 or d1 < 1e-5 else 0.01 * d0 / d1, span)
        th1, w1 = y[0] + h0 * f[0], y[1] + h0 * f[1]
        f1 = (w1, *self.rhs(t + h0, th1, w1))
        d2 = math.sqrt(sum(((b - a) / s) ** 2 for a, b, s in zip(f, f1, sc)) / 3) / h0
        h1 = max(1e-6, h0 * 1e-3) if max(d1, d2) <= 1e-15 else (0.01 / max(d1, d2)) ** (1 / 8)
        return min(100 * h0, h1, span)

    def step(self, t: float, y: tuple, f: tuple, h: float):
        """One step ``h`` from ``(t, y)`` (``f``: the derivatives there): ``(y_new, K, error
        norm)``, ``K``: the 13 stage derivatives of each component (the last at ``t + h``)."""
        coef, ag = self.coef, self.ag
        th, w, W = y
        Kt, Kw, KW = [f[0]], [f[1]], [f[2]]
        for a, c in zip(_A[:_NS - 1], _C[1:_NS]):      # self.rhs inlined
            ws = w + h * sum(map(mul, a, Kw))
            Lam, dLam, dV, Q = coef(th + h * sum(map(mul, a, Kt)))
            aQ = ag(t + c * h) * Q
            Kt.append(ws)
            Kw.append(-(0.5 * dLam * ws * ws + dV + aQ) / Lam)
            KW.append(-aQ * ws)
        y1 = (th + h * sum(map(mul, _B, Kt)), w + h * sum(map(mul, _B, Kw)), W + h * sum(map(mul, _B, KW)))
        acc, dW = self.rhs(t + h, y1[0], y1[1])
        Kt.append(y1[1])
        Kw.append(acc)
        KW.append(dW)
        e5 = e3 = 0.0
        for K, a, u, v in zip((Kt, Kw, KW), self.atol, y, y1):
            sc = a + max(abs(u), abs(v)) * RTOL
            e5 += (sum(map(mul, _E5, K)) / sc) ** 2
            e3 += (sum(map(mul, _E3, K)) / sc) ** 2
        err = 0.0 if e5 == 0.0 and e3 == 0.0 else abs(h) * e5 / math.sqrt((e5 + 0.01 * e3) * 3)
        return y1, (Kt, Kw, KW), err

    def dense(self, t: float, h: float, y: tuple, y1: tuple, K: tuple) -> tuple:
        """The interpolant's coefficients (7 per component, :func:`_poly`) on the step: three
        more stages (SciPy's ``Dop853DenseOutput``)."""
        Kt, Kw, KW = (list(k) for k in K)
        th, w = y[0], y[1]
        for a, c in zip(_A[_NS:], _C[_NS + 1:]):
            ws = w + h * sum(map(mul, a, Kw))
            acc, dW = self.rhs(t + c * h, th + h * sum(map(mul, a, Kt)), ws)
            Kt.append(ws)
            Kw.append(acc)
            KW.append(dW)
        out = []
        for K_, u, v in zip((Kt, Kw, KW), y, y1):
            dy = v - u
            out.append((dy, h * K_[0] - dy, 2 * dy - h * (K_[_NS] + K_[0]), *(h * sum(map(mul, d, K_)) for d in _D)))
        return tuple(out)


class _Dense:
    """Dense output of one episode: ``sol(t) -> (theta, rate, W)`` (the steps' interpolants)."""

    def __init__(self):
        self.t: list[float] = []
        self.steps: list[tuple] = []

    def add(self, t: float, h: float, y: tuple, F: tuple):
        self.t.append(t)
        self.steps.append((t, h, y, F))

    def __call__(self, t: float) -> tuple[float, float, float]:
        t0, h, y, F = self.steps[max(bisect_right(self.t, t) - 1, 0)]
        x = (t - t0) / h
        return tuple(u + _poly(f, x) for u, f in zip(y, F))


_DIRECTIONS = (False, True, None)     # impact: falling; overturning: rising; turning point: either


def _crosses(g0: float, g1: float, up: bool | None) -> bool:
    """``g`` reaches 0 from ``g0`` to ``g1`` rising (``up``), falling (False) or either (None),
    as ``solve_ivp`` finds events."""
    if g0 == g1:
        return False
    rise, fall = g0 <= 0 <= g1, g0 >= 0 >= g1
    return rise if up else fall if up is False else rise or fall


def _step_events(ya: tuple, F: tuple, ta: float, tb: float, ga: tuple, gb: tuple, sg: float, top: float,
                 reason: str) -> list:
    """Events in the step ``[ta, tb]`` (``ya``, ``F``: its start and interpolant; ``ga``, ``gb``: the event
    functions ``sg theta``, ``sg theta - top``, ``rate`` at its ends): ``(t, name)`` with name
    ``"impact"`` (``sg theta`` falls to 0), ``reason`` (it rises to ``top``) or None (a turning
    point, ``rate = 0``).

    A small swing may fit inside one step: ``theta`` can cross 0 (or ``top``) and come back, with
    two turning points between, so that neither ``theta`` nor the rate changes sign from one end
    of the step to the other.  So the interpolants are bounded first (:func:`_deviation`: how far
    from the chord of the step; :func:`_monotone`, :func:`_one_extremum`: whether monotone, whether the
    slope is): a step where ``theta`` cannot reach 0 or ``top`` and the rate cannot vanish holds
    no event.  Where ``theta`` may reach 0 or ``top``, the step is cut at every extremum of its
    interpolant (none where it is monotone; where its slope is monotone, at most one: at the
    turning point; otherwise the real roots of its derivative, :func:`_extrema`): between two
    cuts ``theta`` is monotone, so the first piece whose ends show a crossing holds the first
    crossing, located by ``brentq`` (the endpoint conventions of ``solve_ivp``).  An extremum
    within round-off of 0 (or of ``top``) is no crossing (a member starting from rest at ``theta =
    0`` must not hit it).  The turning points are the sign changes of the rate's interpolant: at
    most one where it is monotone, otherwise bracketed between the midpoints of the extrema of
    ``theta``."""
    Ft, Fw = F[0], F[1]
    w0, w1 = ga[2], gb[2]
    dev = _deviation(Ft) * (1 + 1e-12) + 16 * EPS * (abs(ga[0]) + abs(ga[1]))
    near = min(ga[0], gb[0]) <= dev or max(ga[1], gb[1]) >= -dev       # theta may reach 0 or top
    turn = w0 * w1 <= 0.0 or min(abs(w0), abs(w1)) <= _deviation(Fw) * (1 + 1e-12) + 16 * EPS * abs(w0)
    if not (near or turn):
        return []
    h = tb - ta

    def theta(x):
        return ya[0] + _poly(Ft, (x - ta) / h)

    def rate(x):
        return ya[1] + _poly(Fw, (x - ta) / h)

    def root(fun, t0, t1, g0, g1):
        if g1 == 0 or g0 == 0:
            return t1 if g1 == 0 else t0
        f0, f1 = fun(t0), fun(t1)
        if f0 * f1 > 0.0:       # the interpolant differs from the step's end values in the last bits
            return t1 if abs(f1) < abs(f0) else t0
        return _brentq()(fun, t0, t1, xtol=4 * EPS * abs(tb))

    out, ext, turns = [], None, []
    if turn:
        points = [(ta, w0), (tb, w1)]
        if not _monotone(Fw):                     # the rate may not be monotone
            ext = _extrema(Ft)
            points[1:1] = [(tm, rate(tm)) for tm in (ta + 0.5 * h * (x0 + x1) for x0, x1 in zip(ext, ext[1:]))]
        for (t0, g0), (t1, g1) in zip(points, points[1:]):
            if _crosses(g0, g1, None):
                turns.append(root(rate, t0, t1, g0, g1))
        out += [(tw, None) for tw in turns]
    if near:
        if _monotone(Ft):                         # theta monotone: no cut
            cuts = []
        elif ext is None and _one_extremum(Ft) and (
                (Ft[0] + Ft[1]) * (Ft[0] - Ft[1] - Ft[2]) > 0 or len(turns) == 1):
            # its slope monotone: no extremum where the slopes at the ends (h theta') agree,
            # otherwise one, at the turning point
            cuts = turns if (Ft[0] + Ft[1]) * (Ft[0] - Ft[1] - Ft[2]) <= 0 else []
        else:
            ext = _extrema(Ft) if ext is None else ext
            cuts = [ta + x * h for x in ext]
        inner = [(tc, sg * theta(tc)) for tc in cuts]
        tol = 8 * EPS * (abs(ya[0]) + sum(map(abs, Ft)))       # round-off of theta on the interpolant
        for i, name, c in ((0, "impact", 0.0), (1, reason, top)):
            pts = [(ta, ga[i]), *((tc, v - c) for tc, v in inner if abs(v - c) > tol + 4 * EPS * c), (tb, gb[i])]
            for (t0, g0), (t1, g1) in zip(pts, pts[1:]):
                if _crosses(g0, g1, _DIRECTIONS[i]):
                    out.append((root(lambda x: sg * theta(x) - c, t0, t1, g0, g1), name))
                    break
    return out


def _may_cross_stages(ga: tuple, gb: tuple, h: float, Kw: list) -> bool:
    """Whether a step may hold an event (:func:`_step_events`), asked before its interpolant is
    made (three more evaluations of the equation of motion) from the accelerations ``Kw`` at its
    stages (both ends among them).  Yes where an event function changes sign from one end of the
    step to the other.  Otherwise an event needs two turning points inside the step (a crossing
    of 0 or ``top`` and back around one turning point changes the sign of the rate): ``theta''``
    vanishes inside, and so does the rate, which then comes within ``h/2 max |theta''|`` of 0 at
    one end.  Between the stages the acceleration strays from their range by a few per cent of
    it (6 % at most, measured on the shipped records and on sine pulses): ``theta''`` may vanish
    where the stages change sign or come within half their range of 0, the rate where one end is
    within ``h max |Kw|`` of 0."""
    a0, a1, aw = ga
    b0, b1, bw = gb
    if (a0 >= 0.0 >= b0 and a0 != b0) or (a1 <= 0.0 <= b1 and a1 != b1) or \
            (aw != bw and (aw <= 0.0 <= bw or aw >= 0.0 >= bw)):      # _crosses, written out
        return True
    lo, hi = min(Kw), max(Kw)
    if lo * hi > 0.0 and min(abs(lo), abs(hi)) > 0.5 * (hi - lo):
        return False
    return min(abs(ga[2]), abs(gb[2])) <= h * max(-lo, hi)


def _episode(eq: EquationOfMotion, k: int, sig: _Signal, t: float, t_end: float, theta: float,
             rate: float, track: _Track, top: float, reason: str):
    """Integrate along ``eq`` from ``(t, theta, rate)`` to the first event.  Returns
    ``(event, t, theta, rate, energy_balance_error, ground_work)`` with event ``"impact"``,
    ``reason`` (the rotation ``sign * theta`` reaches ``top``: ``"overturn"`` or ``"locked"``,
    :func:`overturning`) or ``"end"``; ``ground_work`` (J per unit depth): the ground's work over
    the episode.

    :class:`_Dop853` steps never cross a break of the signal (a kink): a step that would is
    shortened to end on it, and the steps left to it are made equal; the step-size control
    carries on across breaks (no restart).  Events are located on the interpolant of the
    step (``brentq``) with the conventions of ``solve_ivp``, inside the step too (a swing with
    two turning points in one step, :func:`_step_events`); the interpolant is made where the
    history or the thrust-line check needs it, or where the stages say that the step may hold an
    event (:func:`_may_cross_stages`)."""
    sg = eq.sign
    # the scales of the tolerances and of the energy error: the unstable equilibrium (or the lock)
    hump = min(eq.theta_unstable, eq.theta_lock * (1 - 1e-9))
    scale_th = max(hump if math.isfinite(hump) else 1.0, 1e-6)
    scale_w = scale_th * math.sqrt(eq.g / eq.mechanism.curve.length)
    E0 = eq.energy(theta, rate)
    E_scale = max(abs(eq.potential(sg * hump)) if math.isfinite(hump) else abs(E0), abs(E0), 1e-300)
    coef, at = eq.coefficients, sig.at
    tb, ag = sig.interval(t)
    st = _Dop853(coef, (1e-12 * scale_th, 1e-12 * scale_w, 1e-12 * E_scale), ag)
    keep = track.keep
    sol = _Dense() if keep else None
    grid = track.grid_list
    gi = bisect_left(grid, t)
    y = (theta, rate, 0.0)
    f = (rate, *st.rhs(t, theta, rate))
    bound = min(tb, t_end)
    hp = st.first_step(t, y, f, bound - t) if bound > t else 0.0
    t_start, hit = t, None
    g_prev = (sg * theta, sg * theta - top, rate)
    while t < t_end:
        if t >= bound:                # a break: the signal's next interval
            tb, st.ag = sig.interval(t)
            bound = min(tb, t_end)
            if sig.jumps(t):
                f = (y[1], *st.rhs(t, y[0], y[1]))
        span = bound - t
        rejected = False
        while True:                   # one accepted step
            h = span if hp >= span else span / math.ceil(span / hp)
            y1, K, err = st.step(t, y, f, h)
            if err < 1.0:
                break
            hp = h * max(_MIN_FACTOR, _SAFETY * err ** _EXPONENT)
            rejected = True
            if hp < 10 * (math.nextafter(t, math.inf) - t):
                raise SolverError(f"time integration failed at t = {t:g} s (step size too small)")
        factor = _MAX_FACTOR if err == 0.0 else min(_MAX_FACTOR, _SAFETY * err ** _EXPONENT)
        if rejected:
            factor = min(1.0, factor)
        hp = max(h * factor, hp) if factor == _MAX_FACTOR else h * factor
        t_old, y_old = t, y
        t, y = (bound if h == span else t_old + h), y1
        f = (K[0][_NS], K[1][_NS], K[2][_NS])
        hh = t - t_old
        g_new = (sg * y[0], sg * y[0] - top, y[1])
        need = keep or (gi < len(grid) and grid[gi] < t)
        F = st.dense(t_old, hh, y_old, y, K) if need or _may_cross_stages(g_prev, g_new, hh, K[1]) else None

        def at_(x):
            return tuple(u + _poly(c, (x - t_old) / hh) for u, c in zip(y_old, F))

        roots = _step_events(y_old, F, t_old, t, g_prev, g_new, sg, top, reason) if F is not None else []
        g_prev = g_new
        stop = min((r for r in roots if r[1] is not None), default=None)
        t_stop = stop[0] if stop is not None else t
        for tr, name in roots:
            if name is None and tr > t_start and (stop is None or tr <= stop[0]):
                yp = at_(tr)
                track.peaks.append((float(tr), k, float(yp[0])))
                track.peak_at(tr, yp[0], eq)
        while gi < len(grid) and grid[gi] < t_stop:
            tt = grid[gi]
            th, w = at_(tt)[:2]
            track.add(tt, k, th, w, 0.5 * coef(th)[0] * w * w, eq.potential(th), at(tt))
            gi += 1
        if keep:
            sol.add(t_old, hh, y_old, F)
        if stop is not None:
            hit = (stop[1], t_stop, at_(t_stop))
            break
    if keep and sol.steps:
        track.pieces.append((t_start, float(hit[1] if hit is not None else t_end), k, sol))
    te, y = (hit[1], hit[2]) if hit is not None else (t_end, y)
    track.peak_at(te, y[0], eq)
    err = abs(eq.energy(y[0], y[1]) - E0 - y[2]) / E_scale
    if hit is None:
        return "end", t_end, float(y[0]), float(y[1]), err, float(y[2])
    Lam = coef(y[0])[0]
    track.add(te, k, y[0], y[1], 0.5 * Lam * y[1] ** 2, eq.potential(y[0]), at(te))
    if hit[0] == "impact":
        return "impact", te, 0.0, float(y[1]), err, float(y[2])
    return hit[0], te, float(y[0]), float(y[1]), err, float(y[2])
