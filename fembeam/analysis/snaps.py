"""A snap-through of an arch on moved supports, followed by the rigid-body dynamics.

When the line of thrust of a three-hinge state reaches a fourth edge and the four-hinge chain
is unstable with the supports held (the potential energy has a maximum along its free mode), the
pieces turn at once: the quasi-static path has no say in where they stop.  Here the pieces are
put, at that displacement, into the multi-block simulation (:mod:`fembeam.simulation`: rigid
bodies in unilateral contact, inelastic impacts, joints that do not slide) with the supports
held, and set moving along the free mode, downhill, with a kinetic energy of ``SEED`` times
``W g L`` (``W``: the weight, ``L``: the span): the snap ends where the simulated arch comes to
rest (kinetic energy below ``REST_KINETIC`` times ``W g`` times the arch's length, as
:mod:`fembeam.simulation`'s rest; its hinges are the new state, refined to exact equilibrium), or the arch collapses when
its pieces fall (the potential energy ``OVERTURN_DROP`` times ``W g t`` below the start's, ``t``
the mean thickness) or do not come to rest within ``MAX_TIME`` periods ``sqrt(L / g)``.
"""
from __future__ import annotations

import math

import numpy as np

from ..dynamics.ground import GroundMotion
from ..errors import SolverError
from ..dynamics.outcomes import OVERTURN_DROP, mean_thickness
from ..simulation.constants import REST_KINETIC
from ..units import GRAVITY

__all__ = ["dynamic_snap", "SnapEnd"]

SEED = 1e-8          # kinetic energy given along the free mode (units of W g L)
CHUNK = 1.0          # the simulation is checked every CHUNK periods sqrt(L / g)
MAX_TIME = 60.0      # not at rest after this many periods: taken as a collapse
HINGE_ROT = 1e-6     # a joint of the state at rest is a hinge above this rotation (rad)
DT = 1e-3            # time step (s) for L = 2 m, scaled with sqrt(L / 2 m)


class SnapEnd:
    """Where a snap ended: ``side`` (J,) and ``theta`` (J,) of the simulated arch at rest (hinge
    sides as :class:`~fembeam.analysis.supports.Chain`), or ``collapsed``; ``time`` (s) of the
    simulated snap, ``dissipated`` (J/m) by its impacts."""

    def __init__(self, side, theta, collapsed: bool, time: float, dissipated: float, reason: str = ""):
        self.side, self.theta, self.collapsed = side, theta, collapsed
        self.time, self.dissipated, self.reason = time, dissipated, reason


def _state(ch, theta, side, uL, rates):
    """Positions and velocities ``(n + 1, 3)`` of the simulation's bodies (the last row the
    ground) for the chain placed by ``theta`` and turning at the hinge rates ``rates`` (J,)."""
    phi, c, Rj, P = ch.place(theta, side, uL)
    n = ch.W.size
    G = np.einsum("ijk,jk->ik", Rj[:, :, :-1], ch.C) + c[:, :-1]
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
    K1 = sim.bodies.kinetic_energy(v)
    WgL = sim.bodies.mass * g * ch.L
    v *= math.sqrt(SEED * WgL / K1)
    motion = SupportMotion.held(mv.kind, d, vector=mv.direction if mv.kind == "move" else None, left=mv.left)
    period = math.sqrt(ch.L / g)
    dt = DT * math.sqrt(ch.L / 2.0)
    still = GroundMotion(np.array([0.0, 1.0]), np.zeros(2), "none", True)
    y0 = float(sim.bodies.m @ q[:-1, 1])
    drop = OVERTURN_DROP * sim.bodies.mass * mean_thickness(ch.curve)
    t, dissipated = 0.0, 0.0
    while t < MAX_TIME * period:
        try:
            res = sim.run(still, dt=dt, t_start=t, t_end=t + CHUNK * period, dt_out=CHUNK * period, q0=q, v0=v,
                          stop_at_overturn=False, support_motion=motion)
        except SolverError as e:
            raise SolverError(f"the simulation of the snap-through at {d:.6g} m failed ({e}); --snaps static "
                              "follows it without the simulation") from e
        q, v, t = res.q_end, res.v_end, res.t_end
        dissipated += res.dissipated
        if float(sim.bodies.m @ q[:-1, 1]) < y0 - drop:
            return SnapEnd(None, None, True, t, dissipated, "the pieces fell")
        if sim.bodies.kinetic_energy(v) < REST_KINETIC * sim.bodies.mass * g * sim.curve.length:
            phi = np.r_[0.0, q[:-1, 2], 0.0]
            th = np.diff(phi)
            side = np.where(th < -HINGE_ROT, 1, np.where(th > HINGE_ROT, -1, 0))
            th = np.where(side != 0, th, 0.0)
            return SnapEnd(side, th, False, t, dissipated)
    return SnapEnd(None, None, True, t, dissipated, f"not at rest after {t:.3g} s")
