"""The whole motion: rest, onset, rocking along one mechanism, impacts, overturning.

:func:`rock` follows a member through a ground motion ``a_g(t)`` (g, positive along +x):

* **rest**: the member stays undeformed while ``-a_g <= A_L(+1)`` and ``a_g <= A_L(-1)``
  (``A_L(d)``: the limit analysis with the inertia load along ``d x``; computed once; where the
  analysis knows the continuum's ``A_L`` but not its hinges, the load factor of the mechanism it
  gives, :func:`~.onset.onset_load`, so that the mechanism opens when the load exceeds it);
* **onset**: when the inertia load first exceeds ``A_L`` in one direction (crossing located
  on the piecewise-linear signal), the member starts from rest on that direction's mechanism;
* **rocking**: Lagrange's equation of the mechanism at finite rotation
  (:class:`~fembeam.dynamics.equation.EquationOfMotion`), integrated by DOP853 (:mod:`.dop853`,
  rtol 1e-10) with steps ending on the kinks of the signal and events located on each step's
  interpolant (:mod:`.episode`, :mod:`.events`);
* **impact**: the member returns to ``theta = 0``; the mechanism after it and its rate come from
  the impact model (:class:`~fembeam.dynamics.transitions.ImpactModel`, computed once per
  mechanism); an impact that arrests the member (r = 0), or a post-impact kinetic energy below
  ``REST_BARRIER_FRACTION`` of the energy barrier (the accumulation of infinitely many impacts in finite
  time, whose times form a geometric series), ends the episode at rest;
* **overturning** (the rule shared with ``fembeam simulate``, :mod:`.outcomes`): the potential
  energy falls below ``-0.1 m g t`` (the member's centroid a tenth of its mean thickness below its
  height at rest: reason ``"below_rest"``), the integration going on past the unstable
  equilibrium (``V' = 0``), where the ground may still push the member back; or the four-bar
  linkage locks first (``"linkage_locked"``).

Along the motion the ground's work is integrated as a third state, so that
``K + V = E_start + W_ground - impact losses`` is checked (``energy_balance_error``).

The modules: :mod:`.onset` (rest to motion), :mod:`.episode` (one mechanism to its next event),
:mod:`.transitions` (the impact model), :mod:`.admissibility` (thrust line and friction demand
along the motion), :mod:`.result` (what a run returns); this one runs them in turn.
"""
from __future__ import annotations

import math
import time
from bisect import bisect_right
from dataclasses import replace

import numpy as np

from ..analysis import analyze
from ..errors import InputError, SolverError
from ..fem import uniform_nodes
from ..geometry import MidCurve
from ..mechanisms import Mechanism
from .admissibility import impact_friction, thrust_scan
from .episode import Signal, episode
from .equation import GRAVITY, EquationOfMotion
from .events import brentq
from .ground import GroundMotion
from .onset import below_time, onset_load, onset_time
from .outcomes import OUTCOMES, overturn_level, overturning
from .result import ImpactEvent, RockingResult, Track
from .transitions import ImpactModel, Transition

__all__ = ["rock", "Rocker", "RockingResult", "ImpactEvent", "onset_time", "REST_BARRIER_FRACTION", "OUTCOMES"]

REST_BARRIER_FRACTION = 1e-12   # post-impact K / energy barrier below which the member is at rest
MAX_EPISODES = 100_000  # bound on the number of episodes (impacts + onsets) of one run
MAX_OUTPUT_STEPS = 10_000_000   # history rows (about 0.5 GB)
IMPACT_GAP = 1e-5       # stop_at_violation: an impact whose friction fails is handed over at this theta (rad)


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
    """A member's rocking dynamics, set up once and run under any number of ground motions.

    The set-up holds the limit analyses in both directions (onset thresholds ``A`` and
    mechanisms), the impact model (transitions cached) and the equations of motion of
    the mechanisms met so far; :meth:`run` follows the member through a ground motion
    (rest, onset, rocking, impacts, overturning).

    Parameters
    ----------
    curve : MidCurve
        The member (lengths in m, density in kg/m^3).
    voussoirs : int, optional
        Discrete arch of this many voussoirs (hinges at the joints only).
    elements : int, optional
        Otherwise the continuous member, with this many rigid elements for the limit
        analysis and the general impact QP (default 200).
    backend : str, optional
        Solver of the impact QP (:func:`~fembeam.analysis.impact.impact`).
    qp : bool, optional
        Also report the general impact QP's ``r_qp`` at each impact (default True).
    g : float, optional
        Acceleration of gravity (m/s^2), default :data:`~fembeam.units.GRAVITY`.

    Attributes
    ----------
    A : dict
        Onset thresholds ``{+1: A, -1: A}`` (g) of the inertia load along ``+x`` and
        ``-x`` (``inf``: no mechanism; NaN when the member cannot stand).
    stands : bool
        Whether the member stands under its own weight.
    mass : float
        Mass of the member (kg/m).
    mechanisms : list of Mechanism
        The mechanisms met so far (their index is the history's ``mechanism``).

    Raises
    ------
    InputError
        ``curve`` is no member, or a count out of range.

    See Also
    --------
    rock : one run.

    Examples
    --------
    >>> import fembeam
    >>> from fembeam.dynamics import GroundMotion
    >>> arch = fembeam.CircularArch(radius=1.0, thickness=0.15, embrace_deg=157.5)
    >>> rk = Rocker(arch, voussoirs=12)
    >>> print(f"A_L = {rk.A[1]:.4f} g")
    A_L = 0.3593 g
    >>> for amplitude in (0.4, 0.8):
    ...     res = rk.run(GroundMotion.sine(amplitude, 0.5))
    ...     print(f"{amplitude} g:", res.outcome)
    0.4 g: rest
    0.8 g: overturned
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
                          direction=d, backend=backend, thrust=False)
            if res.outcome == "cannot_stand":
                self.stands = False
                self.A = {1: math.nan, -1: math.nan}
                break
            self.A[d] = res.A_L if res.outcome in ("rocking", "arrested") else math.inf
            if math.isfinite(self.A[d]):
                self.start[d] = Mechanism.from_hinges(curve, res.hinges_before)
                self.A[d] = onset_load(self.start[d], d, self.A[d])
        self.model = ImpactModel(curve, voussoirs=voussoirs, elements=elements, backend=backend, qp=qp)
        self.joints = uniform_nodes(curve, voussoirs) if voussoirs is not None else None
        self.mass = float(curve.segment_inertia(0.0, curve.length)[0][0])     # kg/m
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
        """Index of mechanism ``m`` in :attr:`mechanisms` (its equation of motion and overturning
        angle set up on first use), by its canonical key (:attr:`~fembeam.mechanisms.Mechanism.key`,
        the key of the impact model's cache too)."""
        key = m.key
        if key not in self._index:
            self._index[key] = len(self.mechanisms)
            m = m.canonical()
            self.mechanisms.append(m)
            eq = EquationOfMotion(m, self.g)
            self.equations.append(eq)
            top, event, barrier = overturning(eq, self.level)
            self.tops.append(top)
            self.events.append(event)
            self.barriers.append(barrier)
        return self._index[key]

    def impact_friction(self, before: int, after: int, rate_in: float) -> tuple[float, float | None]:
        """:func:`~fembeam.dynamics.admissibility.impact_friction` of the impact from mechanism
        ``before`` to ``after`` at incoming rate ``rate_in``, cached per pair and sign."""
        key = (before, after, rate_in > 0)
        if key not in self._impact_friction:
            tr = self.model(self.mechanisms[before])
            self._impact_friction[key] = impact_friction(self.equations[before], self.equations[after],
                                                         tr.alpha_ratio, rate_in, self.joints)
        return self._impact_friction[key]

    def run(self, ground: GroundMotion, *, t_end: float | None = None, dt_out: float | None = None,
            thrust_check: bool = True, progress=None, history: bool = True, settle: bool = False,
            friction: float | None = None, t_start: float | None = None,
            state: tuple | None = None, rest_limit: dict | None = None,
            stop_at_violation: bool = False) -> RockingResult:
        """Time history of the member under a ground motion.

        Parameters
        ----------
        ground : GroundMotion
            The ground acceleration ``a_g(t)`` (g, positive along ``+x``; the inertia
            load is ``-a_g``).
        t_end : float, optional
            End of the run (s); default the end of the ground motion plus
            ``20 sqrt(L/g)`` (``L``: the member's length).
        dt_out : float, optional
            Sampling step of the history (s), default ``(t_end - t_0) / 4000``.
        thrust_check : bool, optional
            Find the first time the thrust line leaves a section, and the friction
            demand (:func:`thrust_scan`, :func:`impact_friction`).
        progress : callable, optional
            ``progress(t)`` is called after each episode (``t`` in s).
        history : bool, optional
            False: only the rows at events and at the end.
        settle : bool, optional
            At the end of the ground motion, stop if the free motion is known to come
            to rest without overturning (:meth:`settles`): outcome ``"rest"``,
            ``settled_at`` and ``t_end`` that time.
        friction : float, optional
            A Coulomb coefficient (> 0) for the friction demand's ``sliding_risk``,
            ``slides_at`` and ``impact_slides_at`` (the motion is not changed: the
            joints never slide in this model).
        t_start : float, optional
            Start there (s), default the start of the ground motion.
        state : tuple, optional
            ``(mechanism, theta, rate)`` at ``t_start`` (a
            :class:`~fembeam.mechanisms.Mechanism` of this member, rad, rad/s); default
            at rest.
        rest_limit : dict, optional
            ``{+1: A, -1: A}`` (g), the inertia loads the member carries at rest (e.g.
            by friction, below ``A_L``): ``rest_slides_at`` is the first time the ground
            exceeds one at rest (the motion is not changed).
        stop_at_violation : bool, optional
            End the run at the first time the mechanism is not admissible (the thrust
            line leaves a section; with ``friction``, a section's or an impact's demand
            exceeds it; with ``rest_limit``, at rest above it): ``violation`` is then
            ``(t, reason)`` (``"thrust_line"``, ``"friction_motion"``,
            ``"friction_impact"``, ``"friction_rest"``) and ``state_end`` the state
            there (an impact's: just before it).

        Returns
        -------
        RockingResult
            ``outcome`` (``"rest"``, ``"rocking"`` or ``"overturned"``), the impacts,
            the peak rotation and the history; ``state_end`` is ``(mechanism, theta,
            rate)`` at the end (None at rest).

        Raises
        ------
        InputError
            A ground motion or time out of range, ``friction`` without
            ``thrust_check``, or ``stop_at_violation`` without it.

        Examples
        --------
        A 0.4 g sine pulse of 0.5 s rocks the paper's arch of 12 voussoirs; its free
        motion after the pulse is known to come to rest:

        >>> import fembeam
        >>> from fembeam.dynamics import GroundMotion, Rocker
        >>> arch = fembeam.CircularArch(radius=1.0, thickness=0.15, embrace_deg=157.5)
        >>> rk = Rocker(arch, voussoirs=12)
        >>> res = rk.run(GroundMotion.sine(0.4, 0.5), settle=True)
        >>> print(res.outcome, f"at {res.settled_at:.2f} s, peak {res.peak_rotation:.4f} rad")
        rest at 0.50 s, peak 0.0025 rad

        The thrust line of its first mechanism leaves a section early in the motion (s):

        >>> res = rk.run(GroundMotion.sine(0.4, 0.5), stop_at_violation=True)
        >>> t, reason = res.violation
        >>> print(reason, f"at {t:.3f} s")
        thrust_line at 0.161 s
        """
        return _run(self, ground, t_end, dt_out, thrust_check, progress, history, settle, friction, t_start, state,
                    rest_limit, stop_at_violation)

    def barrier(self, k: int) -> float:
        """The energy barrier of mechanism ``k`` (J/m): the largest ``V`` from rest
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
        iterated until ``r = 0`` or ``K`` falls below ``REST_BARRIER_FRACTION`` of the barrier (True), or an
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
            if tr.after is None or tr.r * E < REST_BARRIER_FRACTION * self.barrier(k):
                return True
            k, E = self.index(tr.after), tr.r * E
            if not E < self.barrier(k) * (1.0 - margin):
                return False
        return False



def rock(curve: MidCurve, ground: GroundMotion, *, voussoirs: int | None = None, elements: int = 200,
         t_end: float | None = None, dt_out: float | None = None, backend: str = "clarabel",
         qp: bool = True, thrust_check: bool = True, g: float = GRAVITY, progress=None,
         friction: float | None = None) -> RockingResult:
    """Time history of a member under a ground motion: rest, onset, rocking, impacts,
    overturning.

    The member stays at rest while the inertia load ``-a_g`` stays within the onset
    thresholds ``A_L(+1)`` and ``A_L(-1)``; past one it rocks on that direction's
    mechanism (Lagrange's equation at finite rotation, DOP853 at rtol 1e-10); each
    return to ``theta = 0`` is an impact, whose mechanism after it and rate come from
    the impact model; it overturns when its potential energy falls below
    ``-0.1 m g t`` (the centroid a tenth of the mean thickness below its height at
    rest) or its four-bar linkage locks. ``K + V = E_start + W_ground - impact
    losses`` is checked along the motion (``energy_balance_error``).

    Parameters
    ----------
    curve : MidCurve
        The member (lengths in m, density in kg/m^3).
    ground : GroundMotion
        The ground acceleration ``a_g(t)`` (g, positive along ``+x``).
    voussoirs, elements, backend, qp, g
        As for :class:`Rocker`.
    t_end, dt_out, thrust_check, progress, friction
        As for :meth:`Rocker.run`.

    Returns
    -------
    RockingResult
        The outcome (``"rest"``, ``"rocking"`` or ``"overturned"``), impacts, peaks,
        energies (J/m) and the history.

    Raises
    ------
    InputError
        An input out of range.

    See Also
    --------
    Rocker : set up once, run under many ground motions.

    Examples
    --------
    A sine pulse of amplitude 0.4 g and period 0.5 s rocks the paper's arch of 12
    voussoirs, which comes back to rest:

    >>> import fembeam
    >>> from fembeam.dynamics import GroundMotion
    >>> arch = fembeam.CircularArch(radius=1.0, thickness=0.15, embrace_deg=157.5)
    >>> res = fembeam.dynamics.rock(arch, GroundMotion.sine(0.4, 0.5), voussoirs=12)
    >>> print(res.outcome, f"peak rotation {res.peak_rotation:.4f} rad")
    rest peak rotation 0.0025 rad
    """
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
         friction=None, t_start=None, state0=None, rest_limit=None, stop=False) -> RockingResult:
    clock = time.perf_counter()
    curve, g = rk.curve, rk.g
    t_end = _check_inputs(curve, ground, t_end)
    friction = _check_friction(friction)
    if friction is not None and not thrust_check:
        raise InputError("a friction coefficient is checked against the friction demand, which comes with the "
                         "thrust-line check: do not turn the check off")
    if stop and not thrust_check:
        raise InputError("stop_at_violation needs the thrust-line check")
    t0 = float(ground.t[0]) if t_start is None else float(t_start)
    if not math.isfinite(t0):
        raise InputError(f"t_start must be a finite time, got {t_start!r}")
    if t_end is not None and not t_end > t0:
        raise InputError(f"t_end must be after the start ({t0:g} s), got {t_end:g}")
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
        out = RockingResult(curve, ground, "cannot_stand", t_end, dict(A), mode=rk.mode, n=rk.n,
                            friction=friction)
        out.timings = {"setup": rk.setup_time, "total": time.perf_counter() - clock}
        return out
    timings = {"setup": rk.setup_time}
    t_tr = 0.0
    T_ref = math.sqrt(curve.length / g)

    track = Track(np.arange(t0, t_end + 0.5 * dt_out, dt_out) if history else np.empty(0), thrust_check)
    sig = Signal(ground)
    t_quiet = float(ground.t[-1])   # the ground is still from then on
    out = RockingResult(curve, ground, "rest", t_end, dict(A), mode=rk.mode, n=rk.n, friction=friction)
    t, state = t0, None         # state: (mechanism index, theta, rate) while moving
    if state0 is not None:
        m0, th0, w0 = state0
        if not isinstance(m0, Mechanism) or m0.curve != curve or not (math.isfinite(th0) and math.isfinite(w0)):
            raise InputError("state must be (a Mechanism of this member, theta, rate) with finite theta and rate")
        state = (mech_index(m0), float(th0), float(w0))
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
                tb = below_time(ground, t, t_end, A[1], A[-1], 1e-9 * T_ref)
                on = None if tb is None else onset_time(ground, tb, t_end, A[1], A[-1])
            if rest_limit is not None and out.rest_slides_at is None:
                slide = onset_time(ground, t, t_end, rest_limit[1], rest_limit[-1])
                if slide is not None and (on is None or slide[0] < on[0]):
                    out.rest_slides_at = slide[0]
                    if stop:
                        _rest_rows(track, ground, t, slide[0])
                        t = t_end = slide[0]
                        out.violation = (slide[0], "friction_rest")
                        break
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
        ev, t, theta, rate, err, work = episode(eq, k, sig, t, t_quiet if check else t_end, theta, rate, track,
                                                 rk.tops[k], rk.events[k])
        t_int += time.perf_counter() - ti
        balance = max(balance, err)
        out.ground_work += work
        if stop:
            bad = _episode_violation(rk, track, ground, dt_out, friction, ev, k, rate)
            if bad is not None:
                t = t_end = _cut(track, rk, out, bad, k)
                state = out.state_cut
                break
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
        at_rest = K_out < REST_BARRIER_FRACTION * barrier
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
        out.state_end = (rk.mechanisms[k], float(th), float(w))
    out.V_min = track.V_min
    out.peak_rotation, out.t_peak, out.peaks = track.peak, track.t_peak, track.peaks
    out.peak_theta, out.t_peak_theta = track.peak_theta, track.t_peak_theta
    out.energy_balance_error = balance
    out.history = {k_: np.asarray(v, float) for k_, v in track.rows.items()}
    timings.update(integration=t_int, transitions=t_tr)
    out.timings = {**timings, "total": time.perf_counter() - clock}
    if thrust_check:
        t_chk = time.perf_counter()
        out.thrust_checked = True
        if stop:        # every episode was scanned as it ended (its largest ratio on the scan grid)
            v = out.violation or (None, None)
            out.thrust_line_exits_at = v[0] if v[1] == "thrust_line" else None
            out.slides_at = v[0] if v[1] == "friction_motion" else None
            out.friction_motion = track.friction_best
        else:
            out.thrust_line_exits_at, out.friction_motion, out.slides_at = thrust_scan(
                track.pieces, eqs, ground, dt_out, rk.joints, mu=friction)
        hits = [(*rk.impact_friction(e.before, e.after, e.rate_in), e.t) for e in out.impacts if e.after is not None]
        if hits:             # the first impact within rounding of the largest (mirrored transitions tie)
            top = max(h[0] for h in hits)
            ratio, s_, t_ = next(h for h in hits if h[0] >= top * (1 - 1e-12))
            out.friction_impact = (top, t_, s_)
            if friction is not None:
                out.impact_slides_at = next((t_i for r_i, _, t_i in hits if r_i > friction), None)
        out.timings["thrust_check"] = time.perf_counter() - t_chk
    _own_mechanisms(out, rk, None if state0 is None else mech_index(state0[0]))
    out.timings["total"] = time.perf_counter() - clock
    return out


def _episode_violation(rk: Rocker, track: Track, ground, dt_out: float, mu, ev: str, k: int, rate: float):
    """The first violation of admissibility in the episode just integrated (the last piece of
    ``track``; it ended by ``ev`` at rate ``rate`` on mechanism ``k``): ``(t, reason)`` or None.  An
    impact whose percussions need more friction than ``mu`` is a violation just before it."""
    if not track.pieces:
        return None
    ta, tb, kp, sol = track.pieces[-1]
    exit_at, best, slide_at = thrust_scan([track.pieces[-1]], rk.equations, ground, dt_out, rk.joints, mu=mu,
                                          refine=False)
    if best[1] is not None and best[1] <= min(x for x in (exit_at, slide_at, tb) if x is not None) \
            and best[0] > track.friction_best[0]:
        track.friction_best = best
    cands = [(x, why) for x, why in ((exit_at, "thrust_line"), (slide_at, "friction_motion")) if x is not None]
    if not cands and mu is not None and ev == "impact":
        tr = rk.model(rk.mechanisms[k])
        if tr.after is not None and rk.impact_friction(k, rk.index(tr.after), rate)[0] > mu:
            # hand over before the impact, where the hinges are still open by IMPACT_GAP of the
            # thickness (theta = IMPACT_GAP: a joint turning about one corner opens the other by
            # theta t), so that the simulation finds the landing and computes the impact itself
            sg = rk.equations[k].sign
            top = max((p[0] for p in track.peaks if ta <= p[0] <= tb), default=ta)     # the last turning point
            if sg * sol(top)[0] <= IMPACT_GAP:
                cands = [(top, "friction_impact")]
            else:
                cands = [(brentq(lambda x: sg * sol(x)[0] - IMPACT_GAP, top, tb, xtol=1e-12 * max(1.0, tb)),
                          "friction_impact")]
    return min(cands) if cands else None


def _cut(track: Track, rk: Rocker, out: RockingResult, bad: tuple, k: int) -> float:
    """End the motion at the violation ``bad = (t, reason)`` inside the last piece of ``track``:
    the history, turning points and pieces after it dropped, the peaks recomputed; sets
    ``out.violation`` and ``out.state_cut`` (``(k, theta, rate)`` there).  Returns the time."""
    tv, why = bad
    ta, tb, kp, sol = track.pieces[-1]
    th, w = sol(tv)[:2]
    track.pieces[-1] = (ta, tv, kp, sol)
    n = bisect_right(track.rows["t"], tv)
    for col in track.rows.values():
        del col[n:]
    eq = rk.equations[k]
    track.add(tv, k, th, w, 0.5 * eq.coefficients(th)[0] * w * w, eq.potential(th), float(out.ground(tv)))
    track.peaks[:] = [p for p in track.peaks if p[0] <= tv]
    track.peak = track.peak_theta = 0.0
    track.t_peak = track.t_peak_theta = None
    track.V_min = 0.0
    for t_, k_, th_ in track.peaks:
        track.peak_at(t_, th_, rk.equations[k_])
    track.peak_at(tv, th, eq)
    out.violation = (float(tv), why)
    out.state_cut = (k, float(th), float(w))
    return float(tv)


def _own_mechanisms(out: RockingResult, rk: Rocker, k0: int | None) -> None:
    """Number the mechanisms of ``out`` as the run met them: ``out.mechanisms`` holds those of this
    run only (a Rocker run many times knows the mechanisms of all its runs), in the order the run
    met them (``k0``: the mechanism it started on, then by onset or impact), and every index of
    ``out`` (onsets, impacts, turning points, history) is
    renumbered to match."""
    met = sorted([(t, 0, k) for t, k in out.onsets] + [(e.t, 1, e.before) for e in out.impacts]
                 + [(e.t, 2, e.after) for e in out.impacts if e.after is not None])
    order = list(dict.fromkeys(([] if k0 is None else [k0]) + [k for _, _, k in met]))
    new = {k: i for i, k in enumerate(order)}
    out.mechanisms = [rk.mechanisms[k] for k in order]
    out.unstable_rotation = [e.sign * min(e.theta_unstable, e.theta_lock) for e in (rk.equations[k] for k in order)]
    out.overturn_rotation = [rk.equations[k].sign * rk.tops[k] for k in order]
    out.onsets = [(t, new[k]) for t, k in out.onsets]
    out.peaks = [(t, new[k], th) for t, k, th in out.peaks]
    out.impacts = [replace(e, before=new[e.before], after=None if e.after is None else new[e.after])
                   for e in out.impacts]
    if "mechanism" in out.history:
        h = out.history["mechanism"]
        lookup = np.full(max(order, default=-1) + 2, -1.0)
        lookup[np.asarray(order, int)] = np.arange(len(order))
        out.history["mechanism"] = lookup[h.astype(int)]     # -1 (at rest) maps to lookup[-1] = -1



def _rest_rows(track: Track, ground: GroundMotion, ta: float, tb: float):
    g = track.grid
    ts = g[(g >= ta) & (g < tb)]
    for tt, a in zip(ts.tolist(), ground(ts).tolist()):
        track.add(tt, -1, 0.0, 0.0, 0.0, 0.0, a)


