"""The whole motion: rest, onset, rocking along one mechanism, impacts, overturning.

:func:`rock` follows a member through a ground motion ``a_g(t)`` (g, positive along +x):

* **rest**: the member stays undeformed while ``-a_g <= A_L(+1)`` and ``a_g <= A_L(-1)``
  (``A_L(d)``: the limit analysis with the inertia load along ``d x``; computed once);
* **onset**: when the inertia load first exceeds ``A_L`` in one direction (crossing located
  on the piecewise-linear signal), the member starts from rest on that direction's mechanism;
* **rocking**: Lagrange's equation of the mechanism at finite rotation
  (:class:`~fembeam.dynamics.equation.EquationOfMotion`), integrated by ``solve_ivp`` (DOP853,
  tight tolerances) with event location;
* **impact**: the member returns to ``theta = 0``; the mechanism after it and its rate come from
  the impact model (:class:`~fembeam.dynamics.transitions.ImpactModel`, computed once per
  mechanism); an impact that arrests the member (r = 0), or a post-impact kinetic energy below
  ``REST_ENERGY`` of the energy barrier (the accumulation of infinitely many impacts in finite
  time, whose times form a geometric series), ends the episode at rest;
* **overturning**: the rotation passes the unstable equilibrium of the mechanism under gravity
  (``V' = 0``), or the four-bar linkage locks first.

Along the motion the ground's work is integrated as a third state, so that
``K + V = E_start + W_ground - impact losses`` is checked (``energy_balance_error``).
"""
from __future__ import annotations

import math
import time
from dataclasses import dataclass, field

import numpy as np
from scipy.integrate import DOP853, OdeSolution
from scipy.optimize import brentq

from ..analysis import analyze
from ..errors import InputError, SolverError
from ..fem import uniform_nodes
from ..geometry import MidCurve
from ..mechanisms import Mechanism
from .equation import GRAVITY, EquationOfMotion
from .ground import GroundMotion
from .thrust import section_forces, thrust_line_margin
from .transitions import ImpactModel, Transition

__all__ = ["rock", "Rocker", "RockingResult", "ImpactEvent", "onset_time", "REST_ENERGY", "OUTCOMES"]

REST_ENERGY = 1e-12     # post-impact K / energy barrier below which the member is at rest
MAX_EPISODES = 100_000  # bound on the number of episodes (impacts + onsets) of one run
OUTCOMES = ("rest", "survived", "overturned", "cannot_stand")
RTOL = 1e-10
EPS = np.finfo(float).eps
MAX_OUTPUT_STEPS = 10_000_000   # history rows (about 0.5 GB)
THRUST_TOL = 1e-6       # thrust line outside the section by more than this fraction of t: exit


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
    peak_rotation: float = 0.0                  # largest |theta| (rotation of the first moving piece)
    t_peak: float | None = None
    peak_piece_rotation: float = 0.0            # largest rotation of any piece (mirror invariant)
    peaks: list = field(default_factory=list)   # (t, mechanism index, theta): every turning point
    t_overturn: float | None = None
    overturn_reason: str | None = None      # "unstable_equilibrium" or "linkage_locked"
    thrust_line_exits_at: float | None = None
    energy_balance_error: float = 0.0
    history: dict = field(default_factory=dict)
    unstable_rotation: list[float] = field(default_factory=list)   # per mechanism (rad, signed)
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
            "peak_piece_rotation": float(self.peak_piece_rotation),
            "turning_points": [{"t": t, "mechanism": k, "theta": th} for t, k, th in self.peaks],
            "t_overturn": num(self.t_overturn),
            "overturn_reason": self.overturn_reason,
            "thrust_line_exits_at": num(self.thrust_line_exits_at),
            "onsets": [{"t": t, "mechanism": k} for t, k in self.onsets],
            "impacts": [{"t": e.t, "r": e.r, "r_qp": num(e.r_qp), "rate_in": e.rate_in, "rate_out": e.rate_out,
                         "hinges_before": self.mechanisms[e.before].to_list(),
                         "hinges_after": self.mechanisms[e.after].to_list() if e.after is not None else [],
                         "mechanism_before": e.before, "mechanism_after": e.after, "at_rest": e.at_rest}
                        for e in self.impacts],
            "mechanisms": [{"index": i, "hinges": m.to_list(), "unstable_rotation": num(u)}
                           for i, (m, u) in enumerate(zip(self.mechanisms, self.unstable_rotation))],
            "energy_balance_error": float(self.energy_balance_error),
            "timings_s": {k: round(v, 4) for k, v in self.timings.items()},
        }
        if history:
            out["history"] = {k: [float(x) for x in v] for k, v in self.history.items()}
        return out

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
                    tc = brentq(ex, ts[i - 1], ts[i], xtol=1e-15, rtol=8 * EPS)
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
    rows: dict = field(default_factory=lambda: {k: [] for k in ("t", "mechanism", "theta", "rate", "K", "V", "a_g")})
    peak: float = 0.0
    t_peak: float | None = None
    peak_piece: float = 0.0
    pieces: list = field(default_factory=list)   # (ta, tb, mechanism, dense solution) of the motion
    peaks: list = field(default_factory=list)    # (t, mechanism, theta) where the rate vanishes

    def add(self, t, k, theta, rate, K, V, a):
        for key, v in zip(self.rows, (t, k, theta, rate, K, V, a)):
            self.rows[key].append(v)

    def peak_at(self, t: float, theta: float, eq: EquationOfMotion):
        if abs(theta) > self.peak:
            self.peak, self.t_peak = abs(theta), float(t)
        self.peak_piece = max(self.peak_piece, max(abs(x) for x in eq.piece_rotations(theta)))


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
        self.mechanisms: list[Mechanism] = []
        self.equations: list[EquationOfMotion] = []
        self._index: dict = {}
        self.setup_time = time.perf_counter() - clock

    def index(self, m: Mechanism) -> int:
        """Index of mechanism ``m`` (its equation of motion set up on first use)."""
        key = (m.s, m.sides)
        if key not in self._index:
            self._index[key] = len(self.mechanisms)
            self.mechanisms.append(m.with_alpha(1.0))
            self.equations.append(EquationOfMotion(m, self.g))
        return self._index[key]

    def run(self, ground: GroundMotion, *, t_end: float | None = None, dt_out: float | None = None,
            thrust_check: bool = True, progress=None) -> RockingResult:
        """Time history under ``ground``.  ``t_end`` (s): default the end of the ground
        motion plus ``20 sqrt(L/g)`` (L: the member's length); ``dt_out`` (s): history
        sampling step (default ``(t_end - t_0) / 4000``); ``thrust_check``: find the first
        time the thrust line leaves the section; ``progress(t)`` is called after each episode."""
        return _run(self, ground, t_end, dt_out, thrust_check, progress)


def rock(curve: MidCurve, ground: GroundMotion, *, voussoirs: int | None = None, elements: int = 200,
         t_end: float | None = None, dt_out: float | None = None, backend: str = "clarabel",
         qp: bool = True, thrust_check: bool = True, g: float = GRAVITY, progress=None) -> RockingResult:
    """Time history of ``curve`` under ``ground`` (see the module docstring, :class:`Rocker`)."""
    return Rocker(curve, voussoirs=voussoirs, elements=elements, backend=backend, qp=qp, g=g).run(
        ground, t_end=t_end, dt_out=dt_out, thrust_check=thrust_check, progress=progress)


def _run(rk: Rocker, ground, t_end, dt_out, thrust_check, progress) -> RockingResult:
    clock = time.perf_counter()
    curve, g = rk.curve, rk.g
    t_end = _check_inputs(curve, ground, t_end)
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
        out = RockingResult(curve, ground, "cannot_stand", t_end, dict(A), mode=rk.mode, elements=rk.n)
        out.timings = {"setup": rk.setup_time, "total": time.perf_counter() - clock}
        return out
    timings = {"setup": rk.setup_time}
    t_tr = 0.0
    T_ref = math.sqrt(curve.length / g)

    track = _Track(np.arange(t0, t_end + 0.5 * dt_out, dt_out))
    # the integrator never steps across a kink: every sample of a record or of a short pulse
    # (rectangular), the ends of a finely sampled smooth pulse
    breaks = ground.t if not ground.smooth or ground.t.size <= 8 else ground.t[[0, -1]]
    out = RockingResult(curve, ground, "rest", t_end, dict(A), mode=rk.mode, elements=rk.n)
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
        ev, t, theta, rate, err = _episode(eq, k, ground, t, t_end, theta, rate, breaks, track)
        t_int += time.perf_counter() - ti
        balance = max(balance, err)
        if ev == "end":
            state = (k, theta, rate)
            break
        if ev in ("overturn", "locked"):
            out.outcome = "overturned"
            out.t_overturn = t
            out.overturn_reason = "unstable_equilibrium" if ev == "overturn" else "linkage_locked"
            state = (k, theta, rate)
            break
        # impact at theta = 0
        tt = time.perf_counter()
        tr: Transition = model(mechs[k])
        t_tr += time.perf_counter() - tt
        top = min(eq.theta_unstable, eq.theta_lock)
        barrier = eq.potential(eq.sign * top) if math.isfinite(top) else math.inf
        K_in = 0.5 * eq.coefficients(0.0)[0] * rate * rate
        if tr.after is None:
            out.impacts.append(ImpactEvent(t, k, None, rate, 0.0, 0.0, tr.r_qp, True))
            state = None
            continue
        k2 = mech_index(tr.after)
        rate2 = abs(rate) * tr.alpha_ratio
        K_out = 0.5 * eqs[k2].coefficients(0.0)[0] * rate2 * rate2
        if abs(K_out - tr.r * K_in) > 1e-9 * K_in:
            raise SolverError(f"impact at t = {t:g} s: K'/K = {K_out / K_in:.12g} differs from r = {tr.r:.12g}")
        at_rest = K_out < REST_ENERGY * barrier
        out.impacts.append(ImpactEvent(t, k, k2, rate, 0.0 if at_rest else rate2, tr.r, tr.r_qp, at_rest))
        state = None if at_rest else (k2, 0.0, rate2)
    else:
        raise SolverError(f"the motion needed more than {MAX_EPISODES} episodes (impacts and onsets) before "
                          f"t = {t_end:g} s; stopped at t = {t:g} s")
    if out.outcome != "overturned":
        out.outcome = "rest" if state is None or (state[2] == 0.0 and state[1] == 0.0) else "survived"
        if not track.rows["t"] or track.rows["t"][-1] < t_end:     # the history ends at t_end
            a_end = float(ground(t_end))
            if state is None:
                track.add(t_end, -1, 0.0, 0.0, 0.0, 0.0, a_end)
            else:
                k, th, w = state
                track.add(t_end, k, th, w, 0.5 * eqs[k].coefficients(th)[0] * w * w, eqs[k].potential(th), a_end)
    out.mechanisms = list(mechs)
    out.unstable_rotation = [e.sign * min(e.theta_unstable, e.theta_lock) for e in eqs]
    out.peak_rotation, out.t_peak, out.peaks = track.peak, track.t_peak, track.peaks
    out.peak_piece_rotation = track.peak_piece
    out.energy_balance_error = balance
    out.history = {k_: np.asarray(v, float) for k_, v in track.rows.items()}
    timings.update(integration=t_int, transitions=t_tr)
    out.timings = {**timings, "total": time.perf_counter() - clock}
    if thrust_check and track.pieces:
        t_chk = time.perf_counter()
        out.thrust_line_exits_at = first_exit(track.pieces, eqs, ground, dt_out, rk.joints)
        out.timings["thrust_check"] = time.perf_counter() - t_chk
    return out


def first_exit(pieces, eqs: list[EquationOfMotion], ground: GroundMotion, dt: float,
               joints: np.ndarray | None = None, tol: float = THRUST_TOL) -> float | None:
    """First time (s) at which the thrust line, inertia forces included, leaves the section
    by more than ``tol`` of the thickness anywhere in the moving pieces (from then on other
    hinges would open); None if it never does.  ``joints`` (m): a voussoir arch, whose
    voussoirs are monolithic, is checked at its joints only; otherwise at uniform sections of
    every moving piece and next to its hinges.  Each piece of motion is scanned every
    ``dt`` (at least 5, at most 400 instants), then the first crossing is bisected to 2^-32
    of a scan interval."""
    def sections(eq):     # the joints of the moving pieces, not a free end (it carries nothing)
        m = eq.mechanism
        br = m.breaks[np.flatnonzero(m.moving)[[0, -1]] + [0, 1]]
        keep = (joints >= br[0]) & (joints <= br[1])
        for end, s_end in zip(m.curve.ends, (0.0, m.curve.length)):
            keep &= ~((end == "free") & (joints == s_end))
        return joints[keep]

    cuts = [None if joints is None else sections(eq) for eq in eqs]

    at = ground.scalar()

    def margin(k, sol, tt):
        theta, rate = sol(tt)[:2]
        a = at(tt)
        acc = eqs[k].acceleration(theta, rate, a)
        if cuts[k] is None:
            return thrust_line_margin(eqs[k], theta, rate, acc, a, sections=50).margin + tol
        return section_forces(eqs[k], theta, rate, acc, a, cuts[k]).margin + tol

    for ta, tb, k, sol in pieces:
        ts = np.linspace(ta, tb, int(np.clip(np.ceil((tb - ta) / dt), 5, 400)))
        prev = ta
        for tt in ts:
            if margin(k, sol, tt) < 0:
                if tt == ta:
                    return float(ta)
                lo, hi = prev, tt
                for _ in range(32):    # to 2^-32 of a scan interval
                    mid = 0.5 * (lo + hi)
                    lo, hi = (mid, hi) if margin(k, sol, mid) >= 0 else (lo, mid)
                return float(hi)
            prev = tt
    return None


def _rest_rows(track: _Track, ground: GroundMotion, ta: float, tb: float):
    g = track.grid
    ts = g[(g >= ta) & (g < tb)]
    for tt in ts:
        track.add(tt, -1, 0.0, 0.0, 0.0, 0.0, float(ground(tt)))


def _episode(eq: EquationOfMotion, k: int, ground: GroundMotion, t: float, t_end: float, theta: float,
             rate: float, breaks: np.ndarray, track: _Track):
    """Integrate along ``eq`` from ``(t, theta, rate)`` to the first event.  Returns
    ``(event, t, theta, rate, energy_balance_error)`` with event ``"impact"``,
    ``"overturn"``, ``"locked"`` or ``"end"``.

    The signal is smooth between consecutive ``breaks`` (a record: its samples), so the
    integrator (SciPy's DOP853 stepper, restarted at every break with the last step size) never
    steps across a kink; events are located on each step's dense output (``brentq``) with the
    conventions of ``solve_ivp``."""
    sg = eq.sign
    top = min(eq.theta_unstable, eq.theta_lock * (1 - 1e-9))
    reason = "overturn" if eq.theta_unstable <= eq.theta_lock else "locked"
    scale_th = max(top if math.isfinite(top) else 1.0, 1e-6)
    scale_w = scale_th * math.sqrt(eq.g / eq.mechanism.curve.length)
    E0 = eq.energy(theta, rate)
    E_scale = max(abs(eq.potential(sg * top)) if math.isfinite(top) else abs(E0), abs(E0), 1e-300)
    atol = np.array([1e-12 * scale_th, 1e-12 * scale_w, 1e-12 * E_scale])
    at = ground.scalar()
    coef = eq.coefficients

    def f(tt, y):
        a = at(tt)
        Lam, dLam, dV, Q = coef(y[0])
        return np.array([y[1], -(0.5 * dLam * y[1] * y[1] + dV + a * Q) / Lam, -a * Q * y[1]])

    # events: (function of y, direction as in solve_ivp, terminal)
    events = ((lambda y: sg * y[0], -1, "impact"), (lambda y: sg * y[0] - top, 1, reason), (lambda y: y[1], 0, None))
    y = np.array([theta, rate, 0.0])
    i0 = int(np.searchsorted(breaks, t, side="right"))
    i1 = int(np.searchsorted(breaks, t_end, side="left"))
    edges = [t, *breaks[i0:i1].tolist(), t_end]
    ts_all, dense_all = [t], []
    h = None
    hit = None
    g_prev = [ev(y) for ev, _, _ in events]
    for ta, tb in zip(edges[:-1], edges[1:]):
        if tb <= ta:
            continue
        solver = DOP853(f, ta, y, tb, rtol=RTOL, atol=atol, first_step=None if h is None else min(h, tb - ta))
        while solver.status == "running":
            if solver.step() is not None or solver.status == "failed":
                raise SolverError(f"time integration failed at t = {solver.t:g} s")
            t_old, t_new = solver.t_old, solver.t
            dense = solver.dense_output()
            g_new = [ev(solver.y) for ev, _, _ in events]
            roots = []
            for (ev, direction, name), gp, gn in zip(events, g_prev, g_new):
                up, down = gp <= 0 <= gn, gp >= 0 >= gn
                if (direction > 0 and up) or (direction < 0 and down) or (direction == 0 and (up or down)):
                    if gp == gn:
                        continue
                    tr = t_new if gn == 0 else (t_old if gp == 0 else
                                                brentq(lambda x: ev(dense(x)), t_old, t_new, xtol=4 * EPS * abs(t_new)))
                    roots.append((tr, name))
            g_prev = g_new
            stop = min((r for r in roots if r[1] is not None), default=None)
            for tr, name in roots:
                if name is None and tr > t and (stop is None or tr <= stop[0]):
                    yp = dense(tr)
                    track.peaks.append((float(tr), k, float(yp[0])))
                    track.peak_at(tr, yp[0], eq)
            t_stop = stop[0] if stop is not None else t_new
            ts_all.append(t_stop)
            dense_all.append(dense)
            if stop is not None:
                hit = (stop[1], t_stop, dense(t_stop))
                break
        if hit is not None:
            break
        h = solver.step_size
        y = solver.y.copy()
    sol = OdeSolution(ts_all, dense_all) if dense_all else None
    te, y = (hit[1], hit[2]) if hit is not None else (t_end, y)
    if sol is not None:
        track.pieces.append((t, float(te), k, sol))
        g = track.grid
        ts = g[(g >= t) & (g < te)]
        if ts.size:
            Y = sol(ts)
            for tt, th, w in zip(ts, Y[0], Y[1]):
                Lam = coef(th)[0]
                track.add(tt, k, th, w, 0.5 * Lam * w * w, eq.potential(th), at(tt))
    track.peak_at(te, y[0], eq)
    err = abs(eq.energy(y[0], y[1]) - E0 - y[2]) / E_scale
    if hit is None:
        return "end", t_end, float(y[0]), float(y[1]), err
    Lam = coef(y[0])[0]
    track.add(te, k, y[0], y[1], 0.5 * Lam * y[1] ** 2, eq.potential(y[0]), at(te))
    if hit[0] == "impact":
        return "impact", te, 0.0, float(y[1]), err
    return hit[0], te, float(y[0]), float(y[1]), err
