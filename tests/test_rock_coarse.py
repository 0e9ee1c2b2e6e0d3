"""``rock`` on coarse meshes of a continuous arch, against the multi-body simulation.

The one-mechanism model of a continuous arch places its hinges anywhere (the continuum's limit
analysis, the mesh only discretising its LP), so on 4 to 12 elements it follows the same
mechanism from the same ``A_L`` as on 200.  The simulation (``fembeam simulate``) cuts the arch
into the elements themselves, with hinges at their joints only and any number of them open: an
independent model, stronger on a coarse mesh (its onset load is the mesh's, up to 12 % above
``A_L`` on 4 elements), that the one-mechanism motion must match in kind and in size:

* a sine pulse of 1.6 g and 0.2 s, up to 0.22 s (the first swing, before the first impact of
  ``rock``): the largest horizontal drift of the centroid (an integral of the motion, not the
  rotation of a chosen piece), and its sense; the largest rotation of any piece;
* a sine pulse of 0.5 g and 0.5 s: both overturn;
* the onset: ``rock`` starts where the ground crosses the continuum's ``A_L`` (the paper's
  0.3533839 g; the crossing from the pulse's formula), the simulation not before it (no mesh
  of the continuum moves below ``A_L``).

Before, 4 to 7 elements left ``rock`` at rest under any pulse (its mechanism was the mesh's, its
onset load the continuum's: started below its own load factor, the mechanism closed at once).
"""
from __future__ import annotations

import math

import numpy as np
import pytest

from fembeam import CircularArch
from fembeam.dynamics import GroundMotion, Rocker
from fembeam.dynamics.equation import EquationOfMotion
from fembeam.mechanisms.energy import load_factor
from fembeam.simulation import Simulator

A_L = 0.3533839          # g: the paper arch (157.5 deg, t/R = 0.15) on the continuum
SWING = (1.6, 0.2, 0.22)  # amplitude (g), period (s), end (s): the first swing
COLLAPSE = (0.5, 0.5, 3.0)


def _rock_drift(res) -> np.ndarray:
    """Horizontal drift (m) of the member's centroid along ``res``'s history (one mechanism)."""
    eq = EquationOfMotion(res.mechanisms[0])
    x0 = eq.horizontal_moment(0.0)
    moving = res.history["mechanism"] >= 0
    return np.array([(eq.horizontal_moment(th) - x0) / eq.mass if on else 0.0
                     for th, on in zip(res.history["theta"], moving)])


def _sim_drift(sim, res) -> np.ndarray:
    """The same of a simulation: the bodies' centroids, mass-weighted."""
    m = sim.bodies.m
    P = np.asarray(res.positions)
    return ((P[:, :, 0] - sim.bodies.G0[0]) * m).sum(1) / m.sum()


@pytest.mark.parametrize("n", range(4, 13))
def test_rock_moves_every_coarse_mesh_as_the_simulation(n):
    arch = CircularArch()
    rk = Rocker(arch, elements=n, qp=False)
    sim = Simulator(arch, elements=n)
    assert rk.A[1] == pytest.approx(A_L, abs=5e-8) and rk.A[-1] == pytest.approx(A_L, abs=5e-8)

    amp, period, t_end = SWING
    ground = GroundMotion.sine(amp, period)
    r = rk.run(ground, thrust_check=False, t_end=t_end)
    s = sim.run(ground, t_end=t_end)
    # onset where the ground crosses A_L (a_g > 0 first: the inertia load to the left)
    t_on = math.asin(A_L / amp) * period / (2 * math.pi)
    assert r.onsets and r.onsets[0][0] == pytest.approx(t_on, abs=1e-6)
    assert r.outcome == "survived" and r.peak_rotation > 0.05 and not r.impacts, (r.outcome, r.peak_rotation)
    moved = np.asarray(s.history["t"])[np.asarray(s.history["max_rotation"]) > 1e-6]
    assert moved.size and moved[0] >= t_on - s.dt
    # the first swing: same sense, same size
    d_rock, d_sim = _rock_drift(r), _sim_drift(sim, s)
    far_rock, far_sim = d_rock[np.argmax(np.abs(d_rock))], d_sim[np.argmax(np.abs(d_sim))]
    assert far_rock < -0.02 and far_sim < -0.02, (far_rock, far_sim)     # to the left, some centimetres
    assert 0.75 <= far_sim / far_rock <= 1.33, (far_rock, far_sim)
    assert 0.7 <= s.peak_rotation / r.peak_rotation <= 1.4, (r.peak_rotation, s.peak_rotation)
    assert r.ground_work > 0

    amp, period, t_end = COLLAPSE
    ground = GroundMotion.sine(amp, period)
    r, s = rk.run(ground, thrust_check=False, t_end=t_end), sim.run(ground, t_end=t_end)
    assert r.outcome == s.outcome == "overturned"


def test_onset_load_is_that_of_the_mechanism_followed():
    """A degenerate continuum optimum (a semicircle with t/R = 1: two hinges of one edge merging)
    keeps the hinges at the joints of the 200-element mesh, whose mechanism needs 1.70262 g where
    the continuum's ``A_L`` is 1.70253 g.  ``rock`` starts it at its own load factor (virtual work:
    :func:`~fembeam.mechanisms.energy.load_factor`), so that it moves; started at ``A_L`` it closed
    at once, and a 4 g pulse (2.35 times the onset) left the arch at rest."""
    arch = CircularArch.from_ratio(180.0, 1.0)
    rk = Rocker(arch, elements=200, qp=False)
    for d in (1, -1):
        own = load_factor(rk.start[d], d)
        assert rk.A[d] == own and own == pytest.approx(1.7026218, abs=1e-6)
    r = rk.run(GroundMotion.sine(4.0, 0.5), thrust_check=False)
    assert r.outcome == "overturned" and r.ground_work > 0 and r.peak_rotation > 0.1
    # just below the onset load nothing moves, just above the mechanism opens
    assert rk.run(GroundMotion.sine(0.999 * rk.A[-1], 0.5), thrust_check=False).onsets == []
    above = rk.run(GroundMotion.sine(1.05 * rk.A[-1], 0.5), thrust_check=False, t_end=0.4)
    assert above.onsets and above.peak_rotation > 1e-6


def test_the_rest_shape_is_no_peak():
    """An episode that ends where it started (``theta = 0``: a load that only touches the onset
    load) records no peak: the four-bar's closure there gives rotations of round-off size (about
    1e-15 rad), which made a peak without its ``theta`` and a summary that could not be printed."""
    from fembeam.dynamics.result import Track

    rk = Rocker(CircularArch(), elements=5, qp=False)
    eq = EquationOfMotion(rk.start[1])
    track = Track(np.empty(0))
    track.peak_at(0.1, 0.0, eq)
    assert track.peak == 0.0 and track.t_peak is None and track.t_peak_theta is None
    track.peak_at(0.2, 1e-3 * eq.sign, eq)
    assert track.peak >= 1e-3 and track.t_peak == 0.2 and track.t_peak_theta == 0.2
