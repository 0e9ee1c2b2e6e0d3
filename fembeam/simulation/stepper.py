"""Moreau-Jean time stepping of the rigid bodies of a member under gravity and a ground motion.

State: each body's centroid ``(x, y)`` (m) and angle ``phi`` (rad, counter-clockwise, 0 at rest),
and its velocities ``(vx, vy, omega)``.  In the ground's frame every body carries its weight
``-m g e_y`` and the inertia force ``-m a_g(t) g e_x`` (``a_g`` in g, positive along +x: the sign of
``fembeam rock``).  One step of length ``h`` from ``(q_k, v_k)`` (theta = 1/2 on the positions):

1. *impact*: if a corner closes at ``t_k`` (it landed at the end of the last step, or its predicted
   landing is within ``MIN_STEP`` of the step), ``v_k`` is projected onto the compatible cone of
   this configuration (no force acts during an impact): the impact QP;
   *events*: then a corner that is open (gap above ``GAP_TOL`` of the member's thickness) and whose
   predicted gap ``g + s v_n + s^2/2 a_n`` (the velocity after the impact, the free acceleration)
   reaches 0 at ``s < h`` cuts the step to ``s``, so that it lands at the end of the step and its
   impact is computed there;
2. *midpoint*: ``q_m = q_k + h/2 v_k``; the operators ``H`` of the closed corners (gap <= GAP_TOL)
   are evaluated at ``q_m``: opening rates >= 0 at every closed corner and one sliding rate = 0 per
   joint with a closed corner, at the corner of smaller gap;
3. *free velocity*: ``v_free = v_k + h M^-1 f(t_k + h/2)``;
4. *projection*: ``v_{k+1}`` = the projection of ``v_free`` onto the compatible cone in the kinetic
   metric (:mod:`.projection`): the impact QP, so an impact keeps the most kinetic energy the
   compatible motions allow (the paper's principle, hinges anywhere), and in a smooth phase it
   supplies the contact impulses;
5. *positions*: ``q_{k+1} = q_m + h/2 v_{k+1}``, then projected (``M``-orthogonally, one
   Gauss-Newton step, velocities untouched) onto zero gap at the corners that carried an impulse
   and zero slip at their joints: the drift of the hinges is removed without an artificial
   restitution.

Energy bookkeeping (J/m): ``K``, ``V = g sum m (y - y_0)``, the ground's work
``W_ground`` (the inertia force times the displacements), the dissipation ``D`` (``K_- - K_+`` of the
impacts of step 1); ``K + V = E_0 + W_ground - D`` up to the discretisation error of the smooth
phases (their projections, step 4, and the position projections, step 5), reported as
``energy_balance_error``; ``projection_drift`` is what the position projections add to
``V - W_ground`` (minus the loads' work on them).  (``W`` alone is the Delassus operator
``H M^-1 H^T`` of :mod:`.contacts`.)  The member is at rest at the end when ``K`` is below
``REST_KINETIC`` times ``m g L``.

With Coulomb friction ``mu`` the sliding rows of step 4 are no longer equalities: each joint with a
closed corner obeys ``|P_t| <= mu N`` (:mod:`.kernel`), the slip it accumulates is carried by
the joint (the position projection keeps it instead of removing it) and reported.

The loop is compiled (:mod:`.kernel`, numba); :mod:`.reference` is the same algorithm in NumPy
(without friction), kept as the reference of the tests.
"""
from __future__ import annotations

import math
import time

import numpy as np

from ..dynamics.equation import GRAVITY
from ..dynamics.ground import GroundMotion
from ..dynamics.outcomes import overturn_level
from ..errors import InputError, SolverError
from ..geometry import MidCurve, StraightMember
from ..limits import DT_RANGE, MAX_STEPS   # admitted time steps (s); (t_end - t_0) / dt above MAX_STEPS: InputError
from .bodies import Bodies
from .constants import BLOCK_PIVOTS, COULOMB_TOL, GAP_TOL, IMPACT_PIVOTS, KKT_TOL, OPEN_TOL, REST_KINETIC
from .contacts import Contacts
from .result import SimulationResult
from .support_motion import SUPPORT_COLUMNS, SupportMotion

__all__ = ["Simulator", "simulate", "DT_RANGE", "MAX_STEPS", "GAP_TOL", "MIN_STEP", "OPEN_TOL", "REST_KINETIC",
           "check_dt", "check_friction"]

MIN_STEP = 1e-6             # shortest step cut at a landing, relative to dt
CHUNK_STEPS = 4096          # steps between two returns of the compiled loop (progress, interrupts)
CHUNK_ROWS = 512            # history rows and impacts buffered per return
MU_RANGE = (1e-3, 1e3)      # admitted friction coefficients
PEAK_TOL = 1e-12            # rad: a smaller peak rotation is round-off (no time reported for it)


_SOLVER_STATUS = {1: "did not converge", 2: "failed its KKT check", 3: "has a Delassus matrix that is not positive definite",
                  4: "with friction was not solved (Tresca fixed point, semi-smooth Newton, non-smooth "
                     "Gauss-Seidel, Lemke's pivots; smallest Coulomb residual reached)"}


class Simulator:
    """The multi-block simulation of a member: rigid bodies in unilateral contact.

    The member is cut into rigid bodies, each in contact with its neighbours (and the
    supports) at its joints, which open, close (inelastic impacts) and, with
    ``friction``, slide. Set up once, run under any number of ground motions
    (:meth:`run`).

    Parameters
    ----------
    curve : MidCurve
        The member (lengths in m, density in kg/m^3).
    voussoirs : int, optional
        Discrete arch: this many equal voussoirs. Not with ``elements``.
    elements : int, optional
        Continuous arch: this many equal rigid elements (default 100; a
        :class:`~fembeam.geometry.block.StraightMember` is one body by default).
    g : float, optional
        Acceleration of gravity (m/s^2).
    friction : float, optional
        Coulomb coefficient ``mu`` of every joint, in ``MU_RANGE``; ``math.inf`` or None (the
        default): unlimited friction, the joints stick whatever their tangential force.
    nodes : array_like, optional
        The cuts instead: arc lengths (m) from 0 to the member's length.

    Attributes
    ----------
    bodies : Bodies
        The bodies.
    contacts : Contacts
        Their joints.
    stands : bool
        Whether the bodies carry their own weight on joints that do not slide.

    Raises
    ------
    InputError
        ``voussoirs`` with ``elements``, a count or ``friction`` out of range.

    See Also
    --------
    simulate : one run.
    fembeam.dynamics.Rocker : the one-mechanism model.

    Examples
    --------
    The first 0.3 s of a block 2 m high and 0.4 m wide (``A_L = 0.2 g``) under a
    0.4 g sine pulse of 0.5 s, by the NumPy reference engine (the compiled one is
    numba's, compiled on its first use in a process):

    >>> import fembeam
    >>> from fembeam.dynamics import GroundMotion
    >>> from fembeam.simulation import Simulator
    >>> sim = Simulator(fembeam.StraightMember(height=2.0, width=0.4))
    >>> res = sim.run(GroundMotion.sine(0.4, 0.5), dt=2e-3, t_end=0.3, engine="reference")
    >>> print(res.outcome, f"peak rotation {res.peak_rotation:.3f} rad")
    survived peak rotation 0.024 rad
    """

    def __init__(self, curve: MidCurve, *, voussoirs: int | None = None, elements: int | None = None,
                 g: float = GRAVITY, friction: float | None = None, nodes=None):
        if voussoirs is not None and elements is not None:
            raise InputError("give voussoirs or elements, not both")
        if voussoirs is None and elements is None and nodes is None and isinstance(curve, StraightMember):
            voussoirs = 1                 # a block is one body
        n = voussoirs if voussoirs is not None else (elements if elements is not None else 100)
        self.mode = "voussoirs" if voussoirs is not None else "continuous"
        self.bodies = Bodies.from_curve(curve, n, nodes=nodes)
        self.contacts = Contacts(self.bodies)
        if not self.contacts.chain:
            raise InputError("simulate needs a chain of bodies with a joint at every interior cut")
        self.curve, self.g = curve, float(g)
        self.friction = check_friction(friction)
        self._stands = None

    @property
    def stands(self) -> bool:
        """Whether the bodies carry their own weight on joints that do not slide: the limit
        analysis of the same cuts (``fembeam analyze``'s LP on this mesh) is not ``cannot_stand``.
        Computed on first use (one LP), then kept.  A member that stands only with more friction
        than ``mu`` does stand: under its weight alone it collapses by sliding, which :meth:`run`
        computes."""
        if self._stands is None:
            from ..analysis.limit import limit_analysis
            from ..fem import discretize
            self._stands = limit_analysis(discretize(self.curve, self.bodies.nodes), 1, verify=False).status \
                != "cannot_stand"
        return self._stands

    def cannot_stand(self, ground: GroundMotion, dt: float = 1e-3) -> SimulationResult:
        """The answer for a member that does not stand (:attr:`stands` False): outcome
        ``"cannot_stand"``, no motion computed (no history, no steps)."""
        res = SimulationResult(self.curve, ground, self.bodies, mode=self.mode, dt=dt, friction=self.friction)
        res.finish(outcome="cannot_stand", t_end=float(ground.t[0]))
        return res

    def run(self, ground: GroundMotion, *, dt: float = 1e-3, t_end: float | None = None,
            dt_out: float | None = None, q0: np.ndarray | None = None, v0: np.ndarray | None = None,
            stop_at_overturn: bool = True, progress=None, engine: str = "compiled",
            t_start: float | None = None, support_motion: SupportMotion | None = None) -> SimulationResult:
        """Time history of the bodies under a ground motion.

        Parameters
        ----------
        ground : GroundMotion
            The ground acceleration ``a_g(t)`` (g, positive along ``+x``).
        dt : float, optional
            Time step (s), in ``DT_RANGE``.
        t_end : float, optional
            End of the run (s), default the end of the ground motion plus
            ``20 sqrt(L/g)`` (``L``: the member's length), as :func:`~fembeam.dynamics.rock`.
        dt_out : float, optional
            Sampling step of the history (s), default ``max(dt, duration / 4000)``.
        q0, v0 : ndarray, optional
            Start from these positions ``(x, y, angle)`` (m, m, rad) and velocities
            (m/s, m/s, rad/s), ``(n + 1, 3)`` arrays, the last row the ground's zeros
            (e.g. a previous result's ``q_end``, ``v_end``); default at rest.
        stop_at_overturn : bool, optional
            End the run when the member overturns (default True).
        progress : callable, optional
            ``progress(t)`` is called along the run (``t`` in s).
        engine : {"compiled", "reference"}, optional
            The numba kernel, or the NumPy reference (slower; no friction).
        t_start : float, optional
            Start there (s), default the start of the ground motion.
        support_motion : SupportMotion, optional
            The supports moved from the start on, as kinematic bodies
            (:class:`~.support_motion.SupportMotion`); the history then has the columns
            :data:`~.support_motion.SUPPORT_COLUMNS`.

        Returns
        -------
        SimulationResult
            The outcome (``"rest"``, ``"survived"``, ``"overturned"``,
            ``"collapsed_by_sliding"``), the peak rotation (rad), the energies (J/m),
            the history (``t``, ``K``, ``V``, ``W_ground``, ``dissipated``, ``a_g``,
            ``hinges``, ``separated``, ``max_rotation``), the positions of the bodies
            at the history's times, and ``q_end``, ``v_end`` to continue from.

        Raises
        ------
        InputError
            ``dt``, ``t_end`` or the initial state out of range, or ``friction`` with
            the reference engine.
        SolverError
            The reference engine met a singular system.

        Examples
        --------
        A block 2 m high and 0.4 m wide under a 0.4 g sine pulse of 0.5 s, its history
        sampled every 0.1 s (the rotation in rad), by the NumPy reference engine:

        >>> import fembeam
        >>> from fembeam.dynamics import GroundMotion
        >>> from fembeam.simulation import Simulator
        >>> sim = Simulator(fembeam.StraightMember(height=2.0, width=0.4))
        >>> res = sim.run(GroundMotion.sine(0.4, 0.5), dt=2e-3, t_end=0.3, dt_out=0.1,
        ...               engine="reference")
        >>> for t, phi in zip(res.history["t"], res.history["max_rotation"]):
        ...     print(f"{t:.1f} s  {phi:.3f} rad")
        0.0 s  0.000 rad
        0.1 s  0.001 rad
        0.2 s  0.012 rad
        0.3 s  0.024 rad
        """
        if support_motion is not None and not isinstance(support_motion, SupportMotion):
            raise InputError(f"support_motion must be a SupportMotion, got {type(support_motion).__name__}")
        if engine == "reference":
            if self.friction is not None:
                raise InputError("the reference engine has no friction")
            from .reference import run_reference
            if t_start is not None:
                raise InputError("the reference engine starts at the start of the ground motion")
            try:
                return run_reference(self, ground, dt, t_end, dt_out, q0, v0, stop_at_overturn, progress,
                                     support_motion)
            except np.linalg.LinAlgError as e:
                raise SolverError(f"the reference engine met a singular system ({e})") from e
        if engine != "compiled":
            raise InputError(f"engine must be 'compiled' or 'reference', got {engine!r}")
        return _run(self, ground, dt, t_end, dt_out, q0, v0, stop_at_overturn, progress, t_start, support_motion)


def simulate(curve: MidCurve, ground: GroundMotion, *, voussoirs: int | None = None, elements: int | None = None,
             dt: float = 1e-3, t_end: float | None = None, g: float = GRAVITY,
             friction: float | None = None, engine: str = "compiled") -> SimulationResult:
    """Multi-block simulation of a member under a ground motion, in one call.

    :meth:`Simulator.run` of a new :class:`Simulator`, or its
    :meth:`~Simulator.cannot_stand` answer for a member that does not stand under its
    own weight.

    Parameters
    ----------
    curve : MidCurve
        The member (lengths in m, density in kg/m^3).
    ground : GroundMotion
        The ground acceleration ``a_g(t)`` (g, positive along ``+x``).
    voussoirs, elements, g, friction
        As for :class:`Simulator`.
    dt, t_end
        As for :meth:`Simulator.run` (s).
    engine : {"compiled", "reference"}, optional
        As for :meth:`Simulator.run`.

    Returns
    -------
    SimulationResult
        As :meth:`Simulator.run`; outcome ``"cannot_stand"`` (nothing computed) for a
        member that does not stand.

    Examples
    --------
    The first 0.3 s of a block 2 m high and 0.4 m wide under a 0.4 g sine pulse of
    0.5 s, by the NumPy reference engine (the compiled one is numba's, compiled on its
    first use in a process):

    >>> import fembeam
    >>> from fembeam.dynamics import GroundMotion
    >>> from fembeam.simulation import simulate
    >>> block = fembeam.StraightMember(height=2.0, width=0.4)
    >>> res = simulate(block, GroundMotion.sine(0.4, 0.5), dt=2e-3, t_end=0.3,
    ...                engine="reference")
    >>> print(res.outcome, f"peak rotation {res.peak_rotation:.3f} rad")
    survived peak rotation 0.024 rad
    """
    sim = Simulator(curve, voussoirs=voussoirs, elements=elements, g=g, friction=friction)
    if not sim.stands:
        return sim.cannot_stand(ground, dt)
    return sim.run(ground, dt=dt, t_end=t_end, engine=engine)


def check_friction(mu) -> float | None:
    """``mu`` as a float in :data:`MU_RANGE`, or None for unlimited friction (``None`` or
    ``math.inf``: the joints never slide); InputError otherwise."""
    if mu is None:
        return None
    try:
        mu = float(mu)
    except (TypeError, ValueError):
        raise InputError(f"the friction coefficient must be a number, got {mu!r}") from None
    if mu == math.inf:
        return None
    lo, hi = MU_RANGE
    if not (math.isfinite(mu) and lo <= mu <= hi):
        raise InputError(f"the friction coefficient must be in [{lo:g}, {hi:g}] or inf (no sliding), "
                         f"got {mu!r}")
    return mu


def check_dt(dt, t0: float, t_end: float) -> float:
    """``dt`` (s) as a float in :data:`DT_RANGE` with at most :data:`MAX_STEPS` steps; InputError otherwise."""
    try:
        dt = float(dt)
    except (TypeError, ValueError):
        raise InputError(f"dt must be a number of seconds, got {dt!r}") from None
    lo, hi = DT_RANGE
    if not (math.isfinite(dt) and lo <= dt <= hi):
        raise InputError(f"dt must be in [{lo:g}, {hi:g}] s, got {dt:g}")
    if (t_end - t0) / dt > MAX_STEPS:
        raise InputError(f"{(t_end - t0) / dt:.3g} steps of {dt:g} s to t = {t_end:g} s; at most {MAX_STEPS:g} "
                         f"(a larger dt or an earlier t_end)")
    return dt


def compiled_kernel():
    """The module :mod:`.kernel` with its loop ready: the first call in a process compiles it (about
    25 s, once per machine) or loads it from numba's cache (about 0.2 s); it is timed apart from
    the run (``timings_s.compile_or_load``)."""
    global _KERNEL
    if _KERNEL is None:
        from . import constants, kernel
        if kernel.compiled_constants() != constants.values():
            _rebuild(kernel)              # a cache compiled with other constants (see .constants)
        _KERNEL = kernel                  # (set first: the warm-up below runs through _run)
        sim = Simulator(StraightMember(height=1.0, width=0.5), voussoirs=1)
        _run(sim, GroundMotion.rectangular(0.0, 0.1), 1e-3, 1e-3, None, None, None, True, None)
    return _KERNEL


_KERNEL = None


def _rebuild(kernel) -> None:
    """Drop numba's cache of every compiled function of ``kernel`` and recompile those already
    loaded: their cache was built with other values of :mod:`.constants` (the cache is keyed on
    the kernel's source file, not on the modules whose globals it froze)."""
    from numba.core.dispatcher import Dispatcher
    for f in vars(kernel).values():
        if isinstance(f, Dispatcher):
            f._cache.flush()
            f.recompile()


def _ground_args(ground: GroundMotion):
    """``(kind, amplitude, period, t, a)`` of :func:`.kernel.ground_at` for ``ground``."""
    p = ground.exact
    if p is None:
        return 0, 0.0, 1.0, np.ascontiguousarray(ground.t, float), np.ascontiguousarray(ground.a, float)
    kind = {"rect": 1, "sine": 2, "ricker": 3}[p.kind]
    return kind, float(p.amplitude), float(p.period), np.zeros(1), np.zeros(1)


def checked_run(sim: Simulator, ground, dt, t_end, dt_out, q0, v0, t_start=None):
    """The arguments of :meth:`Simulator.run` checked (InputError otherwise) and completed:
    ``(t0, t_end, dt, dt_out, q, v)`` with the initial positions and velocities ``(n + 1, 3)``."""
    if not isinstance(ground, GroundMotion):
        raise InputError(f"simulate needs a fembeam.dynamics.GroundMotion, got {type(ground).__name__}")
    t0 = float(ground.t[0]) if t_start is None else float(t_start)
    if not math.isfinite(t0):
        raise InputError(f"t_start must be a finite time, got {t_start!r}")
    if t_end is None:
        t_end = float(ground.t[-1]) + 20.0 * math.sqrt(sim.curve.length / sim.g)
    t_end = float(t_end)
    if not (math.isfinite(t_end) and t_end > t0):
        raise InputError(f"t_end must be finite and after the start of the ground motion ({t0:g} s), got {t_end:g}")
    dt = check_dt(dt, t0, t_end)
    dt_out = max(dt, (t_end - t0) / 4000.0) if dt_out is None else float(dt_out)
    if not (math.isfinite(dt_out) and dt_out > 0):
        raise InputError(f"dt_out must be a positive number of seconds, got {dt_out!r}")
    n = sim.bodies.n
    q = sim.bodies.rest_state() if q0 is None else np.array(q0, float)
    v = np.zeros((n + 1, 3)) if v0 is None else np.array(v0, float)
    if q.shape != (n + 1, 3) or v.shape != (n + 1, 3):
        raise InputError(f"q0 and v0 must be ({n + 1}, 3) arrays (the last row the ground)")
    if not (np.all(np.isfinite(q)) and np.all(np.isfinite(v))):
        raise InputError("q0 and v0 must be finite numbers")
    q[-1] = v[-1] = 0.0
    return t0, t_end, dt, dt_out, q, v


def supported(sim: Simulator, q: np.ndarray, v: np.ndarray, motion: SupportMotion | None):
    """The contacts with two support bodies (:meth:`.contacts.Contacts.split_supports`) and the
    positions, velocities ``(n + 2, 3)`` of ``q``, ``v`` ``(n + 1, 3)``: the supports at rest at
    their places, moving at ``motion``'s velocities (if any, and it moves at all)."""
    if getattr(sim, "_split", None) is None:
        sim._split = sim.contacts.split_supports()
    q2, v2 = np.vstack([q, np.zeros((1, 3))]), np.vstack([v, np.zeros((1, 3))])
    if motion is not None:
        q2[-2:, :2] = motion.supports_at_start()
        if motion.hold_after > 0:
            v2[-2:] = motion.velocities()
    return sim._split, q2, v2


def start_heights(bodies, q: np.ndarray, motion: SupportMotion | None) -> np.ndarray:
    """The centroids' heights (m) from which the potential energy ``V`` and the overturning are
    measured: at rest, or, on supports displaced from the start (:meth:`SupportMotion.held`),
    at the start ``q`` (the arch cannot return to its rest geometry there)."""
    if motion is not None and motion.start != 0.0:
        return q[:bodies.n, 1].copy()
    return bodies.G0[1].copy()


def support_history(res: SimulationResult, motion: SupportMotion, t0: float, F) -> None:
    """Adds :data:`.support_motion.SUPPORT_COLUMNS` to ``res.history``: the displacement (m) at
    its times and, from the mean forces ``F`` ``(rows, 4)`` (N/m) of the arch on the supports
    (x, y of the left, then of the right one), ``H`` (kN/m, outward) and ``V`` (kN/m, downward)."""
    h = res.history
    F = np.asarray(F, float).reshape(-1, 4) / 1e3
    h.update(zip(SUPPORT_COLUMNS, (motion.displacement(np.asarray(h["t"]) - t0), -F[:, 0], -F[:, 1],
                                   F[:, 2], -F[:, 3])))
    res.support_motion, res.support_t0 = motion, float(t0)


def _run(sim: Simulator, ground: GroundMotion, dt, t_end, dt_out, q0, v0, stop_at_overturn, progress,
         t_start=None, motion=None):
    clock = time.perf_counter()
    t0, t_end, dt, dt_out, q, v = checked_run(sim, ground, dt, t_end, dt_out, q0, v0, t_start)
    K = compiled_kernel()                # numba: compiled, or loaded from its cache, on first use
    t_load = time.perf_counter() - clock
    bodies, g = sim.bodies, sim.g
    con, q, v = supported(sim, q, v, motion)     # the supports: rows n (left) and n + 1 (right)
    t_hold = t0 + motion.hold_after if motion is not None and motion.hold_after > 0 else math.inf
    L = sim.curve.length
    n, J = bodies.n, con.J
    m, minv = bodies.m, con.minv
    mv = np.zeros((n + 2, 3))
    mv[:n, 0] = mv[:n, 1] = m
    mv[:n, 2] = bodies.I
    y0 = start_heights(bodies, q, motion)
    E_unit = bodies.mass * g * L
    thick = bodies.thickness.copy()
    mu = math.inf if sim.friction is None else sim.friction
    # the contact data of :class:`.contacts.Contacts` as real arrays
    ra = np.stack([con.r_a.real, con.r_a.imag], axis=-1)
    rb = np.stack([con.r_b.real, con.r_b.imag], axis=-1)
    nu0 = np.stack([con.nu0.real, con.nu0.imag], axis=-1)
    tau0 = np.stack([con.tau0.real, con.tau0.imag], axis=-1)
    mod = K.Model(*_kernel_arrays(
        (con.a, int), (con.b, int), (ra, float), (rb, float), (nu0, float), (tau0, float), (con.outward, float),
        (con.depth, float), (con.edge, float), (con.sides, int), (minv, float), (m, float), (mv, float),
        (y0, float), (thick, float), (GAP_TOL * thick, float)))
    fs = np.zeros(K.N_FLOAT)
    ist = np.zeros(K.N_INT, np.int64)
    E0 = float(0.5 * np.sum(mv * v * v)) + g * float(m @ (q[:n, 1] - y0))
    fs[K.F_T], fs[K.F_E0], fs[K.F_NEXT] = t0, E0, t0
    fs[K.F_ESEEN] = max(abs(E0), 1e-9 * E_unit)
    fs[K.F_TPEAK] = fs[K.F_TOVER] = fs[K.F_TRATIO] = fs[K.F_TSLIP] = math.nan
    fs[K.F_VMIN] = math.inf
    ist[K.I_JRATIO] = ist[K.I_JSLIP] = -1
    # the geometry of q, the closed corners, the slip the joints carry (none from rest; a run from a
    # given state, q0, keeps the state's): by the kernel's first call
    ist[K.I_START] = K.FROM_REST if q0 is None else K.FROM_STATE
    state = K.State(*_kernel_arrays(
        (q, float), (v, float), (np.zeros((J, 2)), float), (np.zeros((J, 2)), float),
        (np.zeros((J, 3, 2, 3)), float), (np.zeros(J, np.int64), int), (np.zeros((J, 2), bool), bool),
        (np.zeros(3 * J, bool), bool), (np.zeros(3 * J, bool), bool), (np.zeros(3 * J, np.int64), int),
        (np.zeros(3 * J, np.int64), int), (np.zeros(J), float), (fs, float), (ist, int), (np.zeros(6), float)))
    q, v, s_ref, fs, ist = state.q, state.v, state.s_ref, state.fs, state.ist
    kind, amp, period, ts, av = _ground_args(ground)
    V_over = overturn_level(sim.curve, bodies.mass, g)
    settings = K.Run(float(dt), float(t0), float(dt_out), float(g), float(MIN_STEP * dt), float(V_over), float(mu),
                     bool(stop_at_overturn), int(kind), float(amp), float(period),
                     *_kernel_arrays((ts, float), (av, float)), int(IMPACT_PIVOTS), int(BLOCK_PIVOTS),
                     float(KKT_TOL), float(COULOMB_TOL))
    out = K.Buffers(np.zeros((CHUNK_ROWS, K.HISTORY_COLUMNS)), np.zeros((CHUNK_ROWS, n, 3)), np.zeros((CHUNK_ROWS, 3)),
                    np.zeros((6, 3 * J)), np.zeros(3 * J), np.zeros(3 * J), np.zeros((J, 2), bool))
    hist, pos, imp = out.hist, out.pos, out.imp
    res = SimulationResult(sim.curve, ground, bodies, mode=sim.mode, dt=dt, friction=sim.friction)
    t_start = time.perf_counter()
    h_rows, p_rows, impacts = [], [], []
    while True:
        t_stop = t_hold if t_hold < t_end else t_end     # the supports stop at t_hold: a step ends there
        try:
            status, nh, ni = K.advance(mod, state, settings, out, t_stop, CHUNK_STEPS)
        except (np.linalg.LinAlgError, ZeroDivisionError) as e:
            # a singular dense system inside a solver (numba raises numpy's LinAlgError): the step
            # from the state it started from (positions; velocities after its impact, if any)
            err = SolverError(f"the contact problem of the step at t = {fs[K.F_T]:.9g} s met a singular system "
                              f"({type(e).__name__}: {e})")
            err.problem = {"t": float(fs[K.F_T]), "q": _public(q), "v": _public(v), "mu": mu, "dt": dt,
                           "slip_carried": s_ref.copy(), "error": f"{type(e).__name__}: {e}"}
            raise err from e
        h_rows.append(hist[:nh].copy())
        p_rows.extend(pos[:nh].copy())
        impacts.extend(map(tuple, imp[:ni].tolist()))
        if status == K.SOLVER_FAILED:
            err = SolverError(f"the contact problem of the step at t = {fs[K.F_T]:.9g} s "
                              f"{_SOLVER_STATUS.get(int(ist[K.I_STATUS]), 'failed')} "
                              f"(residual {fs[K.F_KKT]:.3g})")
            # the problem, for a report: the state the step started from, and the frictional problem
            err.problem = {"t": float(fs[K.F_T]), "q": _public(q), "v": _public(v), "mu": mu, "dt": dt,
                           "slip_carried": s_ref.copy()}
            if ist[K.I_STATUS] == 4:
                err.problem.update({"W_banded": out.dump_ab, "c": out.dump_c, "P_stick": out.dump_P,
                                    "closed": out.dump_closed,
                                    "vscale": float(fs[K.F_VSCALE])})
            raise err
        if progress is not None:
            progress(float(fs[K.F_T]))
        if status == K.FINISHED and t_stop < t_end:     # the supports held from here on
            v[-2:] = 0.0
            q[-2:] = 0.0
            q[-2:, :2] = motion.up_to * np.array([motion.left, motion.right])
            t_hold = math.inf
            continue
        if status in (K.FINISHED, K.STOPPED):
            break
    t_run = time.perf_counter() - t_start
    H = np.vstack(h_rows) if h_rows else np.zeros((0, K.HISTORY_COLUMNS))
    from .result import HISTORY_COLUMNS
    res.history = {k: H[:, i].astype(float) for i, k in enumerate(HISTORY_COLUMNS)}
    if motion is not None:
        support_history(res, motion, t0, H[:, len(HISTORY_COLUMNS):len(HISTORY_COLUMNS) + 4])
    res.positions = p_rows
    res.impacts = impacts
    code = int(ist[K.I_OUTCOME])
    kin = float(0.5 * np.sum(mv * v * v))
    outcome = ("overturned" if code == K.OVERTURNED else "collapsed_by_sliding" if code == K.SLID_OUT
               else "rest" if kin < REST_KINETIC * E_unit else "survived")

    def opt(x):
        return None if not math.isfinite(x) else float(x)

    jr, js = int(ist[K.I_JRATIO]), int(ist[K.I_JSLIP])
    res.finish(outcome=outcome, t_end=float(fs[K.F_T]), t_overturn=opt(fs[K.F_TOVER]),
               peak_rotation=float(fs[K.F_PEAK]), t_peak=opt(fs[K.F_TPEAK]) if fs[K.F_PEAK] > PEAK_TOL else None,
               energy_balance_error=float(fs[K.F_BAL]), dissipated=float(fs[K.F_D]), ground_work=float(fs[K.F_W_GROUND]),
               projection_drift=float(fs[K.F_DRIFT]), steps=int(ist[K.I_STEPS]), cut_steps=int(ist[K.I_CUTS]),
               pivots=int(ist[K.I_PIVOTS]), V_min=float(fs[K.F_VMIN]),
               friction_ratio=float(fs[K.F_RATIO]), t_friction=opt(fs[K.F_TRATIO]),
               s_friction=None if jr < 0 else float(bodies.joint_s[jr]),
               friction_at=None if jr < 0 else ("impact" if ist[K.I_ATRATIO] else "motion"),
               max_slip=None if sim.friction is None else float(fs[K.F_SLIP]), t_slip=opt(fs[K.F_TSLIP]),
               s_slip=None if js < 0 else float(bodies.joint_s[js]), sliding_steps=int(ist[K.I_SLIDING]), redistributed=int(ist[K.I_REDIST]), loose_steps=int(ist[K.I_LOOSE]),
               solved_by={"fixed_point": int(ist[K.I_BY_FP]), "newton": int(ist[K.I_BY_SSN]),
                          "gauss_seidel": int(ist[K.I_BY_NSGS]), "lemke": int(ist[K.I_BY_LEMKE])},
               friction_work=float(fs[K.F_FRICTION]), coulomb_residual=float(fs[K.F_COULOMB]),
               time=time.perf_counter() - clock,
               timings={"compile_or_load": t_load, "run": t_run, "total": time.perf_counter() - clock})
    res.q_end, res.v_end = _public(q), _public(v)
    if motion is not None:
        res.support_q_end = q[-2:, :2].copy()
    return res


def _kernel_arrays(*pairs):
    """The arrays ``(array, dtype)`` of :func:`.kernel.advance`'s arguments as C-contiguous arrays
    of that dtype (float64, int64, bool), the same objects when they are already: numba compiles
    one :func:`~.kernel.advance` per combination of dtypes and layouts, so a view or an int32
    array would cost a compilation."""
    kinds = {float: np.float64, int: np.int64, bool: np.bool_}
    return tuple(np.ascontiguousarray(a, dtype=kinds[k]) for a, k in pairs)


def _public(x: np.ndarray) -> np.ndarray:
    """The kernel's state ``x`` (bodies, then the two supports) in :meth:`Simulator.run`'s
    layout: ``(n + 1, 3)``, the bodies and a last row of the ground's zeros."""
    out = x[:-1].copy()
    out[-1] = 0.0
    return out
