"""A snap-through of an arch on moved supports, followed by the rigid-body dynamics.

When the line of thrust of a three-hinge state reaches a fourth edge and the four-hinge chain
is unstable with the supports held (the potential energy has a maximum along its free mode), the
pieces turn at once: the quasi-static path has no say in where they stop.  Here the pieces are
put, at that displacement, into the multi-block simulation (:mod:`fembeam.simulation`: rigid
bodies in unilateral contact, inelastic impacts, joints that do not slide) with the supports
held, and set moving along the free mode, downhill, with a kinetic energy of ``SEED`` times
``W g L`` (``W``: the weight, ``L``: the span).  The run is checked every ``sqrt(L / g)``
seconds.  The snap has ended when the arch is at rest (kinetic energy below ``REST_KINETIC``
times ``W g`` times the arch's length, the simulation's own rest) or quiet (below ``QUIET``
times ``W g L``, its joints' rotations steady within ``STEADY`` rad over the last check: a
simulated arch can keep chattering at a closed joint); its hinges are then the joints turned
by more than ``HINGE_ROT`` (or, if that reading is not an admissible state, the three turned
most, or the joints turned by more than ``HINGE_ROT_FINE``).  The arch has collapsed when its pieces fall (the simulation's
overturning: the potential energy ``OVERTURN_DROP`` times ``W g t`` below the start's, ``t``
the mean thickness).  Neither within ``MAX_CHECKS`` checks: a :class:`~fembeam.errors.SolverError`.
"""
from __future__ import annotations

import math

import numpy as np

from ..dynamics.ground import GroundMotion
from ..errors import SolverError
from ..simulation.constants import REST_KINETIC
from ..units import GRAVITY

__all__ = ["dynamic_snap", "SnapEnd"]

SEED = 1e-8            # kinetic energy given along the free mode (units of W g L)
MAX_CHECKS = 60        # checks, one every sqrt(L / g) s, before the snap is given up
QUIET = 1e-6           # kinetic energy (units of W g L) below which steady rotations are at rest
STEADY = 1e-4          # rad: the largest change of a joint's rotation over a check when quiet
HINGE_ROT = 1e-4       # rad: a joint of the arch at rest is a hinge above this rotation ...
HINGE_ROT_FINE = 1e-7  # ... or, when that reading is not admissible, above this one
DT = 1e-3              # time step (s) for L = 2 m, scaled with sqrt(L / 2 m)


class SnapEnd:
    """Where a snap ended: ``readings``, the hinge sides (J,) and rotations (J,) of the simulated
    arch at rest read in three ways (:func:`_readings`; sides as
    :class:`~fembeam.analysis.supports.Chain`), or ``collapsed``; ``time`` (s), the simulated
    time at the check that found it at rest or fallen; ``dissipated`` (J/m) by its impacts."""

    def __init__(self, readings: list, collapsed: bool, time: float, dissipated: float, reason: str = ""):
        self.readings, self.collapsed = readings, collapsed
        self.time, self.dissipated, self.reason = time, dissipated, reason


def _readings(q: np.ndarray) -> list:
    """``(side, theta)`` of the bodies' positions ``q``: the joints turned by more than
    ``HINGE_ROT``, the three turned most (a closed joint still chattering), and the joints
    turned by more than ``HINGE_ROT_FINE``."""
    th = np.diff(np.r_[0.0, q[:-1, 2], 0.0])
    three = np.zeros(th.size, bool)
    three[np.argsort(-np.abs(th))[:3]] = True
    out = []
    for keep in (np.abs(th) > HINGE_ROT, three, np.abs(th) > HINGE_ROT_FINE):
        side = np.where(keep, np.where(th < 0, 1, -1), 0)
        out.append((side, np.where(keep, th, 0.0)))
    return out


def _state(ch, theta, side, uL, rates):
    """Positions and velocities ``(n + 1, 3)`` of the simulation's bodies (the last row the
    ground) for the chain placed by ``theta`` and turning at the hinge rates ``rates`` (J,)."""
    phi, _, _, P = ch.place(theta, side, uL)
    n = ch.W.size
    G = ch.centroids(theta, side, uL)
    q = np.zeros((n + 1, 3))
    v = np.zeros((n + 1, 3))
    q[:n, :2], q[:n, 2] = G.T, phi[:-1]
    for j in np.flatnonzero(rates):          # a rate at joint j turns the pieces e >= j about P_j
        w = rates[j]
        v[j:n, 0] += -w * (G[1, j:] - P[1, j])
        v[j:n, 1] += w * (G[0, j:] - P[0, j])
        v[j:n, 2] += w
    return q, v


def dynamic_snap(path, d: float, theta: np.ndarray, side: np.ndarray, new: list[int]) -> SnapEnd:
    """The snap at the displacement ``d`` (m) of ``path`` (:class:`~.supports._Path`) from the
    state ``theta`` with the hinge sides ``side`` (J,), of which the joints ``new`` have just
    reached their edges (zero rotation): each new hinge's free mode (the chain with the older
    hinges and that one, the supports held) opening it, the seed the sum of these unit modes."""
    from ..simulation.stepper import Simulator
    from ..simulation.support_motion import SupportMotion

    ch, mv = path.ch, path.mv
    uL, _ = path.supports_at(d)
    rates = np.zeros(ch.J)
    for j in new:
        one = np.where(np.isin(np.arange(ch.J), new) & (np.arange(ch.J) != j), 0, side)
        hs = np.flatnonzero(one)
        z = np.linalg.svd(ch.closure_jacobian(theta, one, uL, hs))[2][-1]    # the free mode (unit, rad)
        k = int(np.flatnonzero(hs == j)[0])
        rates[hs] += z if z[k] * side[j] < 0 else -z                          # the new hinge opens on its side
    g = GRAVITY
    sim = Simulator(ch.curve, nodes=ch.nodes)
    q, v = _state(ch, theta, side, uL, rates)
    WgL = sim.bodies.mass * g * ch.L
    v *= math.sqrt(SEED * WgL / sim.bodies.kinetic_energy(v))
    motion = SupportMotion.held(mv.kind, d, vector=mv.direction if mv.kind == "move" else None, left=mv.left)
    period = math.sqrt(ch.L / g)
    dt = DT * math.sqrt(ch.L / 2.0)
    still = GroundMotion(np.array([0.0, 1.0]), np.zeros(2), "none", True)
    rest = REST_KINETIC * sim.bodies.mass * g * sim.curve.length
    dissipated = 0.0
    for k in range(MAX_CHECKS):
        before = q[:-1, 2].copy()
        try:
            res = sim.run(still, dt=dt, t_start=k * period, t_end=(k + 1) * period, dt_out=period, q0=q, v0=v,
                          support_motion=motion)
        except SolverError as e:
            raise SolverError(f"the simulation of the snap-through at {d:.6g} m failed ({e}); --snaps static "
                              "follows it without the simulation") from e
        q, v = res.q_end, res.v_end
        dissipated += res.dissipated
        if res.outcome in ("overturned", "collapsed_by_sliding"):
            return SnapEnd([], True, res.t_end, dissipated, "the pieces fell")
        K = sim.bodies.kinetic_energy(v)
        if K < rest or (K < QUIET * WgL and np.max(np.abs(q[:-1, 2] - before)) < STEADY):
            return SnapEnd(_readings(q), False, res.t_end, dissipated)
    raise SolverError(f"the simulation of the snap-through at {d:.6g} m neither came to rest nor fell within "
                      f"{MAX_CHECKS * period:.3g} s; --snaps static follows it without the simulation")
