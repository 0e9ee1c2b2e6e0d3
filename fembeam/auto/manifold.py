"""A one-parameter mechanism as a manifold of the multi-block state, and back.

The multi-block model (:mod:`fembeam.simulation`) is the truth: every body ``i`` has its centroid
``x_i`` (m), angle ``phi_i`` (rad, counter-clockwise, 0 at rest) and velocities ``(v_i, omega_i)``.
A mechanism (:class:`~fembeam.mechanisms.Mechanism`) moving with coordinate ``theta`` and rate
``theta'`` is one curve in that state space: the bodies of a piece move with it,

* crank (first moving piece) about its first hinge ``C1``: ``phi = theta``,
  ``x = C1 + R(theta) (G0 - C1)``, ``v = theta' k x (x - C1)``;
* coupler from the moved second hinge ``B``: ``phi = psi3``, ``x = B + R(psi3) (G0 - C13)``,
  ``v = B' + psi3' k x (x - B)`` with ``B' = theta' k x (B - C1)``;
* rocker about the last hinge ``C2``: ``phi = psi2``, ``x = C2 + R(psi2) (G0 - C2)``,
  ``v = psi2' k x (x - C2)``;

with ``psi3(theta)``, ``psi2(theta)`` and their rates ``psi' = w theta'`` from the four-bar's loop
closure (:class:`~fembeam.dynamics.equation.EquationOfMotion`); a block turns about its corner.
Bodies outside the outer hinges stay at rest.  :func:`bodies_state` is this map (the bodies must
have joints at the hinges); its kinetic and potential energies are the mechanism's
``1/2 Lambda theta'^2`` and ``V(theta)`` exactly (``tests/test_auto.py``).

:func:`mechanism_of` goes back: the joints with one corner open are the hinges (pivoting on the
closed corner); with as many as a mechanism of the member has, no joint separated and none slid,
``theta`` is the crank's angle and ``theta'`` the kinetic-metric projection of the velocities on
the mechanism's field, accepted when that field and the rebuilt positions match the state to the
tolerances given (what is left is reported: the kinetic energy the projection drops).
"""
from __future__ import annotations

import math

import numpy as np

from ..dynamics.equation import EquationOfMotion
from ..errors import InputError, SolverError
from ..mechanisms import Mechanism
from ..simulation.bodies import Bodies
from ..simulation.constants import OPEN_TOL    # a corner open by more than this fraction of the joint's thickness
from ..simulation.contacts import Contacts

__all__ = ["bodies_state", "mechanism_of", "OPEN_TOL"]



def _rot(phi: np.ndarray, v: np.ndarray) -> np.ndarray:
    """Rotate the columns ``v`` (2, n) by the angles ``phi`` (n,)."""
    c, s = np.cos(phi), np.sin(phi)
    return np.array([c * v[0] - s * v[1], s * v[0] + c * v[1]])


def _cross_k(w: np.ndarray, r: np.ndarray) -> np.ndarray:
    """``w k x r`` for angular rates ``w`` (n,) and vectors ``r`` (2, n)."""
    return np.array([-w * r[1], w * r[0]])


def _pieces(mech: Mechanism, bodies: Bodies) -> np.ndarray:
    """The piece of each body (by its mid arc length); every body must lie within one piece."""
    nodes = bodies.nodes
    br = mech.breaks
    L = mech.curve.length
    tol = 1e-9 * L
    inner = br[1:-1]
    if not all(np.min(np.abs(nodes - s)) <= tol for s in inner if tol < s < L - tol):
        raise InputError("the bodies need a joint at every hinge of the mechanism")
    return mech.piece_of(0.5 * (nodes[:-1] + nodes[1:]))


def bodies_state(eq: EquationOfMotion, theta: float, rate: float, bodies: Bodies) -> tuple[np.ndarray, np.ndarray]:
    """The multi-block state of a mechanism's motion.

    Parameters
    ----------
    eq : EquationOfMotion
        The mechanism's equation of motion.
    theta : float
        Rotation of its first moving piece (rad).
    rate : float
        Its angular velocity (rad/s).
    bodies : Bodies
        The simulation's bodies.

    Returns
    -------
    q, v : ndarray
        Positions ``(x, y, angle)`` (m, m, rad) and velocities (m/s, m/s, rad/s) of the
        bodies, ``(n + 1, 3)`` (last row: the ground).

    Examples
    --------
    The paper's four-hinge mechanism opened by 0.01 rad at 0.1 rad/s, as the state of
    the 12 voussoirs of a :class:`~fembeam.simulation.Simulator`:

    >>> import fembeam
    >>> from fembeam.auto import bodies_state
    >>> from fembeam.dynamics import EquationOfMotion
    >>> from fembeam.simulation import Simulator
    >>> arch = fembeam.CircularArch(radius=1.0, thickness=0.15, embrace_deg=157.5)
    >>> sides = ["intrados", "extrados", "intrados", "extrados"]
    >>> mech = fembeam.Mechanism.from_angles(arch, [0.0, 52.5, 118.125, 157.5], sides)
    >>> eq = EquationOfMotion(mech)
    >>> sim = Simulator(arch, voussoirs=12)
    >>> q, v = bodies_state(eq, 0.01 * eq.sign, 0.1 * eq.sign, sim.bodies)
    >>> print(q.shape, f"first voussoir at ({q[0, 0]:.3f}, {q[0, 1]:.3f}) m,",
    ...       f"turned {q[0, 2]:.2f} rad at {v[0, 2]:.2f} rad/s")
    (13, 3) first voussoir at (-0.951, 0.306) m, turned -0.01 rad at -0.10 rad/s
    """
    mech = eq.mechanism
    piece = _pieces(mech, bodies)
    moving = np.flatnonzero(mech.moving)
    G0 = bodies.G0
    n = bodies.n
    q = np.zeros((n + 1, 3))
    v = np.zeros((n + 1, 3))
    q[:-1, :2] = G0.T
    if mech.n_hinges == 1:
        roles = {int(moving[0]): "block"}
    else:
        roles = dict(zip(map(int, moving), ("crank", "coupler", "rocker")))
        k = eq._scalars(theta)
        if k is None:
            raise InputError(f"the mechanism's linkage cannot reach theta = {theta:g} rad")
        B, D, psi3, psi2, w3, w2 = np.array(k[0]), np.array(k[1]), k[2], k[3], k[4], k[5]
    for p, role in roles.items():
        sel = np.flatnonzero(piece == p)
        if sel.size == 0:
            continue
        g0 = G0[:, sel]
        m = sel.size
        if role in ("block", "crank"):
            C = eq.C if role == "block" else eq.C1
            phi, w, x = np.full(m, theta), np.full(m, rate), None
            x = C[:, None] + _rot(phi, g0 - C[:, None])
            vel = _cross_k(w, x - C[:, None])
        elif role == "coupler":
            phi, w = np.full(m, psi3), np.full(m, w3 * rate)
            x = B[:, None] + _rot(phi, g0 - eq.C13[:, None])
            dB = _cross_k(np.array([rate]), (B - eq.C1)[:, None])
            vel = dB + _cross_k(w, x - B[:, None])
        else:
            phi, w = np.full(m, psi2), np.full(m, w2 * rate)
            x = eq.C2[:, None] + _rot(phi, g0 - eq.C2[:, None])
            vel = _cross_k(w, x - eq.C2[:, None])
        q[sel, :2], q[sel, 2] = x.T, phi
        v[sel, :2], v[sel, 2] = vel.T, w
    return q, v


def mechanism_of(bodies: Bodies, contacts: Contacts, q: np.ndarray, v: np.ndarray, *, g: float,
                 position_tol: float = 1e-5, velocity_tol: float = 1e-2):
    """The mechanism a multi-block state moves on, if any.

    Parameters
    ----------
    bodies : Bodies
        The simulation's bodies.
    contacts : Contacts
        Their contacts.
    q, v : ndarray
        Positions (m, m, rad) and velocities (m/s, m/s, rad/s), ``(n + 1, 3)``.
    g : float
        Acceleration of gravity (m/s^2).
    position_tol : float, optional
        Tolerance on the positions, relative to the thickness.
    velocity_tol : float, optional
        Tolerance on the velocities, relative, in the kinetic-energy norm.

    Returns
    -------
    tuple or None
        ``(mechanism, theta, rate, dropped)``: the mechanism, its rotation (rad) and
        rate (rad/s), and ``dropped`` the kinetic energy (J/m) the projection on the
        mechanism's field leaves out. None when the state is not on a mechanism of the
        member: hinges not as many as the member's mechanisms have, a joint separated
        or slid (by ``position_tol`` of its thickness), the positions rebuilt from
        ``theta`` off by more than ``position_tol`` of the thickness, or the velocities
        off the mechanism's field by more than ``velocity_tol``.

    Examples
    --------
    Back from the state :func:`bodies_state` makes of the paper's mechanism: the same
    hinges (deg), rotation (rad) and rate (rad/s), no kinetic energy dropped (J/m):

    >>> import fembeam
    >>> from fembeam.auto import bodies_state, mechanism_of
    >>> from fembeam.dynamics import EquationOfMotion
    >>> from fembeam.simulation import Simulator
    >>> arch = fembeam.CircularArch(radius=1.0, thickness=0.15, embrace_deg=157.5)
    >>> sides = ["intrados", "extrados", "intrados", "extrados"]
    >>> mech = fembeam.Mechanism.from_angles(arch, [0.0, 52.5, 118.125, 157.5], sides)
    >>> sim = Simulator(arch, voussoirs=12)
    >>> q, v = bodies_state(EquationOfMotion(mech), -0.01, -0.1, sim.bodies)
    >>> found, theta, rate, dropped = mechanism_of(sim.bodies, sim.contacts, q, v, g=9.81)
    >>> print([f"{a:g}" for a in found.angles_deg()], f"{theta:.3f} rad, {rate:.3f} rad/s")
    ['0', '52.5', '118.125', '157.5'] -0.010 rad, -0.100 rad/s
    >>> print(f"dropped {abs(dropped):.4f} J/m")
    dropped 0.0000 J/m
    """
    curve = bodies.curve
    geo = contacts.evaluate(q)
    t = bodies.thickness
    opened = geo.gap > OPEN_TOL * t[:, None]
    n_open = opened.sum(axis=1)
    slip = geo.slip[np.arange(t.size), geo.contact]           # at the closed (or closer) corner
    if np.any(n_open == 2) or np.any(np.abs(slip) > position_tol * t):
        return None
    hinge = np.flatnonzero(n_open == 1)
    if hinge.size != Mechanism.n_hinges_expected(curve):
        return None
    sides = tuple("extrados" if opened[j, 0] else "intrados" for j in hinge)     # pivots on the closed corner
    try:
        mech = Mechanism(curve, tuple(float(s) for s in bodies.joint_s[hinge]), sides)
        eq = EquationOfMotion(mech, g)
    except (InputError, SolverError):      # not a compatible mechanism of this member: not on its manifold
        return None
    piece = _pieces(mech, bodies)
    first = np.flatnonzero(piece == np.flatnonzero(mech.moving)[0])
    if first.size == 0:
        return None
    theta = float(q[first[0], 2])
    try:
        q1, u = bodies_state(eq, theta, 1.0, bodies)
    except InputError:
        return None
    if np.max(np.abs(q1[:-1, :2] - q[:-1, :2])) > position_tol * float(np.min(t)) or \
            np.max(np.abs(q1[:-1, 2] - q[:-1, 2])) > position_tol:
        return None
    mv = np.zeros_like(v)
    mv[:-1, 0] = mv[:-1, 1] = bodies.m
    mv[:-1, 2] = bodies.I
    uu = float(np.sum(mv * u * u))
    rate = float(np.sum(mv * u * v)) / uu
    K = 0.5 * float(np.sum(mv * v * v))
    rest = v - rate * u
    dropped = 0.5 * float(np.sum(mv * rest * rest))
    if K > 0 and dropped > velocity_tol * K:
        return None
    if not math.isfinite(rate):
        return None
    return mech, theta, rate, dropped
