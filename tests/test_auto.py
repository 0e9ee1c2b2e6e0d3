"""``--model auto``: the one-mechanism model while its mechanism is admissible, the multi-block
simulation from the first violation (fembeam/auto).

Independent routes: the mechanism's own energies (``1/2 Lambda theta'^2``, ``V(theta)``) for the
bodies placed on it; ``rock`` itself where nothing is violated (a block has no inner section);
``simulate`` itself where the one-mechanism model fails from the start (the friction limit load
at rest, reached at a time known in closed form); the overturning outcomes of ``simulate`` on
both sides of its threshold.
"""
from __future__ import annotations

import json
import math

import numpy as np
import pytest

from fembeam import CircularArch
from fembeam.auto import AutoModel, bodies_state, mechanism_of
from fembeam.auto.model import VELOCITY_TOL
from fembeam.dynamics import EquationOfMotion, GroundMotion, Rocker
from fembeam.fem import nodes_through, uniform_nodes
from fembeam.geometry import StraightMember
from fembeam.simulation import Simulator
from fembeam.simulation.bodies import Bodies

from inprocess import fembeam

ARCH = CircularArch.from_ratio(157.5, 0.15, radius=5.0)
BLOCK = StraightMember(height=2.0, width=0.5)


def _energies(bodies: Bodies, q, v, g=9.81):
    K = bodies.kinetic_energy(v)
    V = g * float(bodies.m @ (q[:-1, 1] - bodies.G0[1]))
    return K, V


@pytest.mark.parametrize("case", ["voussoirs", "continuous", "block"])
@pytest.mark.parametrize("theta", [0.0, 0.02, 0.08])
def test_bodies_on_a_mechanism_carry_its_energy(case, theta):
    """The bodies placed on a mechanism at ``theta`` moving at ``theta'`` have the mechanism's
    kinetic energy ``1/2 Lambda theta'^2`` and potential ``V(theta)`` to round-off (1e-12 of the
    larger), and a joint at each hinge open on the side opposite the pivot."""
    if case == "voussoirs":
        rk, nodes = Rocker(ARCH, voussoirs=7, qp=False), uniform_nodes(ARCH, 7)
    elif case == "continuous":
        rk = Rocker(ARCH, qp=False)
        nodes = nodes_through(uniform_nodes(ARCH, 60), rk.start[1].s, keep=ARCH.fixed_nodes)
    else:
        rk, nodes = Rocker(BLOCK, voussoirs=1, qp=False), uniform_nodes(BLOCK, 1)
    curve = rk.curve
    mech = rk.start[1]
    eq = EquationOfMotion(mech)
    th = eq.sign * theta
    rate = eq.sign * 0.7
    bodies = Bodies.from_curve(curve, nodes=nodes)
    q, v = bodies_state(eq, th, rate, bodies)
    K, V = _energies(bodies, q, v)
    K_ref, V_ref = 0.5 * eq.coefficients(th)[0] * rate ** 2, eq.potential(th)
    scale = max(abs(K_ref), abs(V_ref))
    assert abs(K - K_ref) <= 1e-12 * scale and abs(V - V_ref) <= 1e-12 * scale + 1e-15


@pytest.mark.parametrize("case", ["voussoirs", "continuous"])
def test_mechanism_of_the_bodies_is_the_mechanism(case):
    """Back from the bodies: the same hinges and sides, ``theta`` and ``theta'`` to round-off,
    nothing dropped by the projection."""
    if case == "voussoirs":
        rk, nodes = Rocker(ARCH, voussoirs=7, qp=False), uniform_nodes(ARCH, 7)
    else:
        rk = Rocker(ARCH, qp=False)
        nodes = nodes_through(uniform_nodes(ARCH, 60), rk.start[1].s, keep=ARCH.fixed_nodes)
    mech = rk.start[1]
    eq = EquationOfMotion(mech)
    sim = Simulator(ARCH, nodes=nodes)
    th, rate = eq.sign * 0.03, eq.sign * 0.4
    q, v = bodies_state(eq, th, rate, sim.bodies)
    m, th2, rate2, dropped = mechanism_of(sim.bodies, sim.contacts, q, v, g=9.81)
    assert m.sides == mech.sides
    assert np.allclose(m.s, mech.s, rtol=0, atol=1e-9 * ARCH.length)
    assert th2 == pytest.approx(th, rel=1e-12) and rate2 == pytest.approx(rate, rel=1e-10)
    assert dropped <= 1e-20 * max(1.0, 0.5 * eq.coefficients(th)[0] * rate ** 2)


def test_state_off_the_manifold_is_refused():
    """A velocity field that is not the mechanism's (a body spinning on its own) is not handed back."""
    rk = Rocker(ARCH, voussoirs=7, qp=False)
    eq = EquationOfMotion(rk.start[1])
    sim = Simulator(ARCH, voussoirs=7)
    q, v = bodies_state(eq, eq.sign * 0.03, eq.sign * 0.4, sim.bodies)
    v = v.copy()
    v[3, 2] += 2.0      # the third voussoir spins by itself: 2 rad/s against 0.4 of the crank
    assert mechanism_of(sim.bodies, sim.contacts, q, v, g=9.81, velocity_tol=VELOCITY_TOL) is None


def test_block_never_violates_so_auto_is_rock():
    """A block has no section inside its one moving piece and, without friction, nothing to
    violate: auto is rock's motion (same outcome, impacts, peak), one segment."""
    g = GroundMotion.sine(0.5, 0.5)
    res = AutoModel(BLOCK, voussoirs=1).run(g, t_end=6.0)
    ref = Rocker(BLOCK, voussoirs=1, qp=False).run(g, t_end=6.0)
    assert [s.model for s in res.segments] == ["rock"] and res.first_failure is None
    assert res.outcome == ref.outcome
    assert [t for t, _ in res.impacts] == [e.t for e in ref.impacts] and len(ref.impacts) > 5
    assert res.peak_rotation == ref.peak_rotation


def test_handover_keeps_the_energy_and_thresholds_are_simulates():
    """Paper arch, 7 voussoirs, one-sine pulse 0.56 s: the thrust line leaves a section early and the
    motion is handed over with its energy (the last rock row and the first simulation row at the
    hand-over time agree to 1e-9); simulate's own threshold lies between 0.74 g (survives) and
    0.765 g (overturns), and so does auto's, where rock alone survives both."""
    model = AutoModel(ARCH, voussoirs=7)
    res = model.run(GroundMotion.sine(0.6, 0.56), t_end=4.0)
    assert res.first_failure[1] == "thrust_line" and res.segments[1].model == "simulate"
    h = res.history
    t_h = res.segments[0].t_end
    i_rock = np.flatnonzero((h["model"] == 0) & np.isclose(h["t"], t_h, rtol=0, atol=1e-12))[-1]
    i_sim = np.flatnonzero((h["model"] == 1) & np.isclose(h["t"], t_h, rtol=0, atol=1e-12))[0]
    E_rock, E_sim = h["K"][i_rock] + h["V"][i_rock], h["K"][i_sim] + h["V"][i_sim]
    assert abs(E_sim - E_rock) <= 1e-9 * abs(E_rock)
    sim = Simulator(ARCH, voussoirs=7)
    rk = Rocker(ARCH, voussoirs=7, qp=False)
    for a, expect in ((0.74, False), (0.765, True)):
        g = GroundMotion.sine(a, 0.56)
        assert (sim.run(g, t_end=4.06).outcome == "overturned") is expect
        assert (model.run(g, t_end=4.06, history=False).outcome == "overturned") is expect
        assert rk.run(g, t_end=4.06, thrust_check=False).outcome != "overturned"


def test_friction_at_rest_hands_over_when_closed_form_says():
    """mu = 0.3: the joints carry at most A_f = 0.1472 g at rest (the limit analysis with Coulomb
    rows, below A_L = 0.37 g), so the one-mechanism model fails at rest when the one-sine pulse
    0.6 g, 0.56 s first reaches A_f: t = T/(2 pi) asin(A_f / 0.6) (sign of the first half-sine); from
    there on it is simulate's motion: collapse by sliding within a step of simulate's own."""
    mu, a, T = 0.3, 0.6, 0.56
    model = AutoModel(ARCH, voussoirs=7, friction=mu)
    A_f = model.rest_limit[-1]
    assert A_f < model.A[-1]
    res = model.run(GroundMotion.sine(a, T), t_end=4.0)
    t_f, why = res.first_failure
    assert why == "friction_rest"
    assert t_f == pytest.approx(T / (2 * math.pi) * math.asin(A_f / a), abs=1e-9)
    ref = Simulator(ARCH, voussoirs=7, friction=mu).run(GroundMotion.sine(a, T), t_end=4.0)
    assert res.outcome == ref.outcome == "collapsed_by_sliding"
    assert res.t_overturn == pytest.approx(ref.t_overturn, abs=2e-3)


def test_record_hands_back_on_a_mechanism():
    """El Centro at 0.6 g: the simulation hands back at rest and on a mechanism; a hand-back on a
    mechanism drops less than VELOCITY_TOL of the kinetic energy."""
    res = AutoModel(ARCH, voussoirs=7).run(GroundMotion.record("elcentro").to_pga(0.6), t_end=8.0)
    ends = [s.end for s in res.segments]
    assert "rest" in ends and "mechanism" in ends
    h = res.history
    for prev, seg in zip(res.segments, res.segments[1:]):
        assert prev.t_end == seg.t_start
        if prev.end == "mechanism":
            # the kinetic energy reported dropped is the jump of K in the history at the hand-back
            at = np.isclose(h["t"], seg.t_start, rtol=0, atol=1e-12)
            K_sim = h["K"][np.flatnonzero(at & (h["model"] == 1))[-1]]
            K_rock = h["K"][np.flatnonzero(at & (h["model"] == 0))[0]]
            assert K_sim - K_rock == pytest.approx(seg.dropped, rel=1e-6, abs=1e-9 * K_sim)
            assert seg.dropped <= VELOCITY_TOL * K_sim


def test_a_rest_that_cannot_be_handed_back_stays_and_says_why():
    """El Centro x 1.5 with a coarse step (0.05 s): the simulation brings the arch to rest with a
    joint slid beyond the hand-back's tolerance, so it is never handed back.  After the ground
    motion the member stays at rest (checked here by simulating on from that state), so the run to
    1e4 s stops there with the answer of a run to the end of the record plus a few seconds, and
    says which joint holds the hand-back back."""
    ground = GroundMotion.record("elcentro").scaled(1.5)
    am = AutoModel(ARCH, voussoirs=7, dt=0.05)
    long = am.run(ground, t_end=1e4)
    short = am.run(ground, t_end=float(ground.t[-1]) + 5.0, history=False)
    assert long.outcome == short.outcome == "rest" and long.t_end == 1e4
    assert long.segments[-1].end == "settled" and long.segments[-1].t_end == 1e4
    assert long.peak_rotation == short.peak_rotation and long.t_peak == short.t_peak
    t, why = long.no_handback
    assert ground.t[-1] <= t < ground.t[-1] + 1.0 and "slid" in why and "tolerance 1e-05" in why
    assert long.to_dict()["no_handback"] == {"t": t, "why": why}
    # independent: the state left at rest stays at rest under gravity alone, to the same end
    sim_res = [r for kind, r in long.runs if kind == "simulate"][-1]
    sim = am.simulator()
    on = sim.run(GroundMotion.sine(0.0, 1.0), dt=0.05, t_end=20.0, q0=sim_res.q_end, v0=sim_res.v_end)
    assert on.outcome == "rest" and on.peak_rotation <= sim_res.peak_rotation + 1e-9
    assert np.max(np.abs(on.q_end - sim_res.q_end)) < 1e-9
    assert long.history["t"][-1] == 1e4


def _cli(*args):
    return fembeam(*args)


def test_cli_auto_json_and_errors(tmp_path):
    out = _cli("rock", "--model", "auto", "--voussoirs", "7", "--radius", "5", "--pulse", "sine", "--amplitude",
               "0.8", "--period", "0.56", "--json", "--plot", str(tmp_path / "a.png"))
    assert out.returncode == 0, out.stderr
    d = json.loads(out.stdout)
    assert d["model"] == "auto" and d["outcome"] == "overturned" and d["handovers"] >= 1
    assert d["first_failure"]["reason"] == "thrust_line" and (tmp_path / "a.png").stat().st_size > 0
    segs = d["segments"]
    assert segs[0]["model"] == "rock" and segs[-1]["end"] == "overturned" and segs[-1]["model"] == "simulate"
    assert all(a["t_end"] == b["t_start"] for a, b in zip(segs, segs[1:]))
    assert d["time_in"]["rock"] + d["time_in"]["simulate"] == pytest.approx(d["t_end"])
    for bad in (["--dt", "0.001"], ["--model", "auto", "--vtk", str(tmp_path / "x.pvd")],
                ["--model", "auto", "--friction", "1e-6"], ["--model", "auto", "--dt", "1"]):
        r = _cli("rock", "--voussoirs", "7", "--pulse", "sine", "--amplitude", "0.8", "--period", "0.56", *bad)
        assert r.returncode == 2 and len(r.stderr.strip().splitlines()) == 1, (bad, r.stderr)


def test_spectrum_auto_threshold_is_simulates():
    """``spectrum(model="auto")`` on one period: the same collapse threshold as ``model="simulate"``
    within 2 % (here within the bisection's 1 %), where ``rock``'s is 2.9 times larger."""
    from fembeam.studies.spectrum import spectrum
    kw = dict(voussoirs=7, amplitudes=[0.6, 0.7, 0.8, 0.9], bisect_tol=1e-2, t_end_factor=3.0, workers=1,
              progress=False)
    a = spectrum(ARCH, "sine", [0.56], model="auto", **kw).rows[0]["first_overturning"]
    s = spectrum(ARCH, "sine", [0.56], model="simulate", **kw).rows[0]["first_overturning"]
    assert a == pytest.approx(s, rel=0.02)
    assert 0.74 < s < 0.77


def test_simulation_finds_the_impact_it_is_handed():
    """An impact whose friction fails is handed over before it, at theta = IMPACT_GAP: the simulation
    then finds the landing and computes the impact itself (a block: Housner's r = (1 - 3/2 sin^2
    alpha)^2, to 1e-5); handed over 1e-9 rad before, the corner counts as closed and the impact is
    lost (the reason for the gap)."""
    from fembeam.dynamics.rocking import IMPACT_GAP
    rk = Rocker(BLOCK, voussoirs=1, qp=False)
    eq = EquationOfMotion(rk.start[1])
    sim = Simulator(BLOCK, voussoirs=1)
    r_housner = (1 - 1.5 * math.sin(math.atan(0.25)) ** 2) ** 2
    still = GroundMotion.rectangular(0.0, 0.01)
    q, v = bodies_state(eq, eq.sign * IMPACT_GAP, -eq.sign * 0.5, sim.bodies)
    res = sim.run(still, dt=1e-3, t_end=0.05, q0=q, v0=v, t_start=0.0)
    assert len(res.impacts) == 1
    _, K0, K1 = res.impacts[0]
    assert K1 / K0 == pytest.approx(r_housner, rel=1e-5)
    q, v = bodies_state(eq, eq.sign * 1e-9, -eq.sign * 0.5, sim.bodies)
    assert len(sim.run(still, dt=1e-3, t_end=0.05, q0=q, v0=v, t_start=0.0).impacts) == 0


def test_joints_that_cannot_carry_the_weight_are_simulated_from_the_start():
    """mu = 0.2: the limit analysis with Coulomb rows says the arch cannot stand (its joints slide
    under the weight alone); auto hands over at once and is simulate's motion."""
    model = AutoModel(ARCH, voussoirs=7, friction=0.2)
    assert model.slides_at_rest
    g = GroundMotion.sine(0.05, 0.56)
    res = model.run(g, t_end=3.0)
    ref = Simulator(ARCH, voussoirs=7, friction=0.2).run(g, t_end=3.0)
    assert res.first_failure == (0.0, "friction_rest") and [s.model for s in res.segments] == ["simulate"]
    assert res.outcome == ref.outcome and res.t_overturn == pytest.approx(ref.t_overturn, abs=2e-3)


@pytest.mark.parametrize("t_end", ["0.352062478", "0.0520624775"])
def test_runs_ending_within_a_step_of_a_handover_end(t_end):
    """t_end a fraction of a simulation step after a window or the hand-over: the run ends (a step
    cannot be shorter than MIN_STEP dt; it used to loop)."""
    out = _cli("rock", "--model", "auto", "--voussoirs", "7", "--radius", "5", "--pulse", "sine", "--amplitude",
               "0.8", "--period", "0.56", "--t-end", t_end, "--json")
    assert out.returncode == 0, out.stderr
    d = json.loads(out.stdout)
    assert d["segments"][-1]["t_end"] == pytest.approx(float(t_end), abs=1e-8)
