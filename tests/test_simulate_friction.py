"""``fembeam simulate`` with Coulomb friction at the joints, the compiled stepper against the NumPy
reference, and the overturning rule's margin.

* a block sliding on an accelerating base: the closed-form slip and its duration (second order in
  dt), no rotation, the friction's work ``mu m g slip``;
* the static regime boundary of a block: it slides when ``mu < b/h`` and rocks when ``mu > b/h``;
* a block slid off its base tips about the base's edge and has collapsed by sliding when its face
  no longer overlaps; an arch whose joints cannot hold it slides down: ``collapsed_by_sliding``;
* ``sliding_risk`` is a demand above mu; a landing with friction slides by the closed form;
* Lemke's pivots solve a step the iterative solvers could not, and an impact by the closed form;
* a large ``mu`` reproduces the no-sliding model;
* impacts never add kinetic energy and friction only dissipates;
* the compiled loop follows the NumPy reference step for step;
* at rest the potential energy stays far above the overturning level.
"""
import math

import numpy as np
import pytest

from fembeam import CircularArch, StraightMember
from fembeam.dynamics import GroundMotion
from fembeam.dynamics.outcomes import overturn_level
from fembeam.simulation import Simulator

G = 9.81
SQUAT = StraightMember(height=0.5, width=1.0)       # b/h = 2: slides long before it could rock
SLENDER = StraightMember(height=2.0, width=0.5)     # b/h = 0.25
ARCH = CircularArch.from_ratio(157.5, 0.15, radius=5.0)


def sliding(A: float, t1: float, mu: float) -> tuple[float, float]:
    """A rigid block on a base accelerating at ``A g`` for ``t1`` s (``A > mu``): its slip on the
    base (m) and the time it stops (s).  During the pulse the relative acceleration is
    ``(A - mu) g``, then the block decelerates at ``mu g``."""
    v1 = (A - mu) * G * t1
    return 0.5 * (A - mu) * G * t1**2 + v1**2 / (2 * mu * G), t1 + v1 / (mu * G)


def test_sliding_block_follows_the_closed_form():
    """Slip 0.0654 m, stop at 0.3333 s (A = 0.5 g, 0.2 s, mu = 0.3): relative error 5.0e-6 at dt = 1e-3,
    1.25e-6 at 5e-4 (order 2.0); no rotation; the friction's work is mu m g slip."""
    mu, A, t1 = 0.3, 0.5, 0.2
    slip, t_stop = sliding(A, t1, mu)
    errs = []
    for dt in (1e-3, 5e-4):
        r = Simulator(SQUAT, voussoirs=1, friction=mu).run(GroundMotion.rectangular(A, t1), dt=dt, t_end=0.6)
        errs.append(abs(r.max_slip / slip - 1))
        assert r.outcome == "rest" and r.peak_rotation < 1e-12
        assert abs(r.t_slip - t_stop) <= 2 * dt                  # the last step that slid
        m = SQUAT.segment_inertia(np.array([0.0]), np.array([SQUAT.length]))[0][0]
        assert r.friction_work == pytest.approx(mu * m * G * slip, rel=1e-5)
        assert r.energy_balance_error < 1e-8
    assert errs[-1] < 5e-6
    order = math.log(errs[0] / errs[1]) / math.log(2.0)
    assert 1.5 < order < 2.5, (errs, order)


@pytest.mark.parametrize("mu, A, slides", [(0.2, 0.22, True), (0.3, 0.27, False)])
def test_rocking_or_sliding_by_the_static_criterion(mu, A, slides):
    """A constant base acceleration above min(mu, b/h) moves the block by sliding if mu < b/h
    (0.25 here), by rocking otherwise."""
    r = Simulator(SLENDER, voussoirs=1, friction=mu).run(GroundMotion.rectangular(A, 0.3), dt=1e-3, t_end=0.3)
    if slides:
        assert r.max_slip > 1e-3 and r.peak_rotation < 1e-12
    else:
        assert r.peak_rotation > 1e-3 and r.max_slip < 1e-6


def test_nothing_moves_below_both_thresholds():
    r = Simulator(SLENDER, voussoirs=1, friction=0.3).run(GroundMotion.rectangular(0.2, 0.3), dt=1e-3, t_end=0.3)
    assert r.max_slip < 1e-12 and r.peak_rotation < 1e-12 and r.outcome == "rest"


def test_sliding_off_its_base_is_a_collapse():
    """The 1 x 0.5 m block on its base (mu = 0.3) under 0.9 g held slides at (A - mu) g,
    x = -(A - mu) g t^2 / 2 (the midpoint steps are exact for it: 2e-12 m), without turning while
    the resultant of the normal force, mu h / 2 = 0.075 m ahead of the centroid, is over the base:
    up to the slip w / 2 - mu h / 2 = 0.425 m (t = 0.3800 s).  Then it tips about the base's edge
    (the face's end: not about its own corner, in the air), still sliding, and has collapsed by
    sliding when its face no longer overlaps the base's (measured t = 0.588 s, slip 1.01 m,
    0.142 rad).  It was ``collapsed_by_sliding`` at half the width, t = 0.4122 s, on a face line
    without end."""
    mu, A, w, h = 0.3, 0.9, 1.0, 0.5
    r = Simulator(SQUAT, voussoirs=1, friction=mu).run(GroundMotion.rectangular(A, 3.0), dt=1e-3, t_end=1.0,
                                                       dt_out=1e-3)
    t = r.history["t"]
    x, y, phi = np.array(r.positions)[:, 0].T
    t_tip = math.sqrt(2 * (w / 2 - mu * h / 2) / ((A - mu) * G))
    before = t <= t_tip - 2e-3
    assert np.max(np.abs(x[before] + 0.5 * (A - mu) * G * t[before] ** 2)) < 1e-10
    assert np.max(np.abs(phi[before])) < 1e-12 and abs(phi[np.searchsorted(t, t_tip + 0.02)]) > 1e-5
    assert r.outcome == "collapsed_by_sliding" and t[-1] == pytest.approx(r.t_overturn, abs=1e-12)
    # the right end of the block's face (w/2, -h/2 from its centroid), at the collapse and before
    right = x + np.cos(phi) * w / 2 + np.sin(phi) * h / 2
    assert right[-1] < -w / 2 < right[-2]            # beyond the base's left edge: no overlap left
    assert 0.55 < r.t_overturn < 0.62 and r.peak_rotation > 0.05


@pytest.mark.parametrize("mu", [0.001, 0.05])
def test_an_arch_whose_joints_cannot_hold_it_collapses_by_sliding(mu):
    """The 7-voussoir arch (157.5 deg, t/R = 0.15, R = 1 m) with mu = 0.001 or 0.05: the limit
    analysis with that friction says it cannot stand (its joints need about 0.43); under gravity
    alone, and under El Centro, its voussoirs slide down without turning (peak rotation 1e-11 rad),
    and its centroid falls to the overturning level with slips of 0.04-0.05 m against openings of
    the joints below 1e-9 m: ``collapsed_by_sliding`` (El Centro: t = 0.127 and 0.148 s; it was
    ``overturned``).  The frictionless arch stands and stays at rest."""
    from fembeam import analyze
    arch = CircularArch.from_ratio(157.5, 0.15)
    assert analyze(arch, voussoirs=7, friction=mu).outcome == "cannot_stand"
    sim = Simulator(arch, voussoirs=7, friction=mu)
    assert sim.stands                                # without sliding it stands: no cannot_stand answer
    for gm in (GroundMotion.rectangular(0.0, 0.1), GroundMotion.record("elcentro")):
        r = sim.run(gm, dt=1e-3, t_end=1.0)
        assert r.outcome == "collapsed_by_sliding" and r.peak_rotation < 1e-9, (r.outcome, r.peak_rotation)
        assert r.max_slip > 0.03 and r.t_overturn < 0.5
    assert Simulator(arch, voussoirs=7).run(GroundMotion.rectangular(0.0, 0.1), dt=1e-3, t_end=1.0).outcome == "rest"


def test_sliding_risk_is_a_demand_above_mu():
    """``sliding_risk`` is ``max_ratio >= mu``: the 0.3 x 1.5 m block under El Centro rocks and
    needs |P_t| / N = 0.2192 at most, with mu = 0.25 as with mu = 1000: no risk (it said true: a
    few steps where a lifting corner's unresolved percussion could not stick counted as sliding);
    the block sliding under 0.5 g demanded mu: a risk."""
    gm = GroundMotion.record("elcentro")
    for mu in (0.25, 1000.0):
        r = Simulator(StraightMember(height=1.5, width=0.3), voussoirs=1, friction=mu).run(gm, dt=1e-3)
        fd = r.friction_demand
        assert fd["max_ratio"] == pytest.approx(0.2192, abs=1e-4) and fd["sliding_risk"] is False
    r = Simulator(SQUAT, voussoirs=1, friction=0.3).run(GroundMotion.rectangular(0.5, 0.2), dt=1e-3, t_end=0.6)
    assert r.friction_demand["max_ratio"] >= 0.3 and r.friction_demand["sliding_risk"] is True


def test_a_landing_with_friction_slides_by_the_closed_form():
    """The 1 x 0.5 m block lifted 1 cm and thrown sideways at 0.5 m/s, mu = 0.5: it lands flat at
    v_y = (2 g 0.01)^(1/2) = 0.443 m/s, the impact takes mu v_y from its horizontal speed (both
    corners pressed, no rocking), and it slides on to rest: x = 0.5 t_land + (0.5 - mu v_y)^2 /
    (2 mu g) = 22.576 + 7.906 mm, to within the error of the step in which it stops, at most
    mu g dt^2 / 8 (measured 4.1e-7 m at dt = 1e-3, bound 6.1e-7; 3.2e-9 at 1e-4, bound 6.1e-9)."""
    mu = 0.5
    sim = Simulator(SQUAT, voussoirs=1, friction=mu)
    q = sim.bodies.rest_state()
    q[0, 1] += 0.01
    v = np.zeros((2, 3))
    v[0, 0] = 0.5
    t_land = math.sqrt(2 * 0.01 / G)
    vy = G * t_land
    x = 0.5 * t_land + (0.5 - mu * vy) ** 2 / (2 * mu * G)
    for dt in (1e-3, 1e-4):
        r = sim.run(GroundMotion.rectangular(0.0, 0.1), dt=dt, t_end=0.3, q0=q, v0=v)
        assert r.outcome == "rest" and r.peak_rotation < 1e-12
        assert abs(r.positions[-1][0, 0] - x) <= mu * G * dt ** 2 / 8


def _lemke_step(ab, c, closed, mu, vscale):
    from fembeam.simulation import kernel as K
    J = closed.shape[0]
    nonneg = np.zeros(3 * J, bool)
    nonneg[0::3], nonneg[1::3] = closed[:, 0], closed[:, 1]
    cj = closed.any(axis=1)
    P, w = np.zeros(3 * J), np.zeros(3 * J)
    ok, n, res = K.lemke_friction(ab, c, nonneg, cj, mu, vscale, 0.0, P, w)
    return ok, res, P, w, nonneg, cj


def coulomb_violation(P, w, nonneg, cj, mu, vscale, pscale):
    """Coulomb's law checked independently of the kernel: the largest violation, relative."""
    J = cj.size
    Pn, wn = P.reshape(J, 3)[:, :2][nonneg.reshape(J, 3)[:, :2]], w.reshape(J, 3)[:, :2][nonneg.reshape(J, 3)[:, :2]]
    out = [max(0.0, -Pn.min(initial=0.0)) / pscale, max(0.0, -wn.min(initial=0.0)) / vscale,
           float(np.max(np.abs(Pn * wn), initial=0.0)) / (pscale * vscale)]
    for j in np.flatnonzero(cj):
        N, Pt, wt = P[3 * j] + P[3 * j + 1], P[3 * j + 2], w[3 * j + 2]
        out.append(max(0.0, abs(Pt) - mu * N) / pscale)                 # in the cone
        if abs(wt) > 1e-9 * vscale:                                     # sliding: on the cone, against w_t
            out.append(abs(Pt + mu * N * np.sign(wt)) / pscale)
    return max(out)


def test_lemke_solves_what_the_iterations_did_not():
    """A step's frictional problem from a run of the 7-voussoir arch under twice El Centro with
    mu = 10 (8 joints, 7 closed; ``tests/data/friction_step_mu10.npz``) on which the Tresca
    fixed point cycled (residual 1.4e-2), Newton stalled (1.9e-2) and Gauss-Seidel stalled after
    2000 sweeps (7.9e-3): ``simulate --friction 10`` exited 3 where mu = 5 and 20 solved.  Lemke's
    pivots on its linear complementarity form solve it: Coulomb's law checked here to 1e-12, two
    joints sliding at |P_t| = mu N."""
    from pathlib import Path
    d = np.load(Path(__file__).parent / "data" / "friction_step_mu10.npz")
    mu, vscale = float(d["mu"]), float(d["vscale"])
    ok, res, P, w, nonneg, cj = _lemke_step(d["W_banded"], d["c"], d["closed"], mu, vscale)
    pscale = max(np.max(np.abs(P)), vscale / np.max(d["W_banded"][-1]))
    assert ok and res < 1e-10
    assert coulomb_violation(P, w, nonneg, cj, mu, vscale, pscale) < 1e-12
    N = P[0::3] + P[1::3]
    sliding = cj & (np.abs(P[2::3]) >= mu * N * (1 - 1e-9)) & (N > 0)
    assert sliding.sum() == 2


def test_lemke_landing_impact_is_the_closed_form():
    """Lemke's pivots on the landing impact of the 1 x 0.5 m block (v = (0.5, -0.443) m/s, both
    corners closed, mu = 0.5): the velocity after it is (0.5 - mu 0.443, 0, 0), the closed form."""
    sim = Simulator(SQUAT, voussoirs=1, friction=0.5)
    con = sim.contacts
    geo = con.evaluate(sim.bodies.rest_state())
    v = np.zeros((2, 3))
    v[0, :2] = 0.5, -0.443
    ab, c = con.delassus(geo.rows), con.apply(geo.rows, v)
    ok, res, P, w, _, _ = _lemke_step(ab, c, np.ones((1, 2), bool), 0.5, float(np.max(np.abs(c))))
    assert ok and res < 1e-12
    vp = v + con.minv * con.apply_t(geo.rows, P)
    assert np.allclose(vp[0], [0.5 - 0.5 * 0.443, 0.0, 0.0], atol=1e-14)


def test_large_mu_is_the_no_sliding_model():
    """The same outcome, impacts and peak rotation to 1e-4 (measured 1.4e-5 on the rocking block,
    1.6e-5 on the 7-voussoir arch under 0.6 g, 0.56 s): the no-sliding model lets a closed joint
    whose corners carry no percussion (a corner lifting off at a landing) transmit a shear, which no
    finite mu allows (the block slides 3.4e-6 m in that step)."""
    gm = GroundMotion.rectangular(0.3, 0.5)
    a = Simulator(SLENDER, voussoirs=1).run(gm, dt=1e-3, t_end=2.0)
    b = Simulator(SLENDER, voussoirs=1, friction=1e3).run(gm, dt=1e-3, t_end=2.0)
    assert a.peak_rotation == pytest.approx(b.peak_rotation, rel=1e-4) and len(a.impacts) == len(b.impacts)
    assert b.sliding_steps <= 2 and b.max_slip < 1e-5
    gm = GroundMotion.sine(0.6, 0.56)
    a = Simulator(ARCH, voussoirs=7).run(gm, dt=1e-3, t_end=4.0)
    b = Simulator(ARCH, voussoirs=7, friction=1e3).run(gm, dt=1e-3, t_end=4.0)
    assert a.outcome == b.outcome
    assert b.peak_rotation == pytest.approx(a.peak_rotation, rel=1e-4)
    assert b.max_slip < 1e-4 * ARCH.thickness_at(0.0)


def test_friction_only_dissipates():
    """7 voussoirs, mu = 0.6, 0.6 g 0.56 s sine: no impact adds kinetic energy, the friction's work is
    positive and the energy balance (friction included) holds to 1e-3: measured 3.3e-4 (8.2e-5 at
    dt = 5e-4, 2.0e-5 at 2.5e-4: second order), the same for the mirrored pulse.  It was 1.9e-3 to
    6.0e-3 depending on the BLAS kernel, the density and the last bit of the input: the working set
    of a frictional step took the sign of a round-off percussion (+-1e-17) at an opening corner, and
    the position projection pulled that corner back to its face, creating energy."""
    sim = Simulator(ARCH, voussoirs=7, friction=0.6)
    r = sim.run(GroundMotion.sine(0.6, 0.56), dt=1e-3, t_end=4.0)
    assert r.sliding_steps > 0 and r.friction_work > 0
    K = np.array([(a, b) for _, a, b in r.impacts])
    assert np.all(K[:, 1] <= K[:, 0] * (1 + 1e-9))
    assert r.energy_balance_error < 1e-3
    mirrored = sim.run(GroundMotion.sine(-0.6, 0.56), dt=1e-3, t_end=4.0)
    assert mirrored.energy_balance_error == pytest.approx(r.energy_balance_error, rel=1e-2)
    assert r.friction_ratio <= 0.6 * 1.02           # the cone, to the solver's tolerance
    sb = r.solved_by            # every step that left the cone was solved by one stage or accepted loose
    assert sum(sb.values()) + r.loose_steps == r.sliding_steps, (sb, r.loose_steps, r.sliding_steps)


@pytest.mark.parametrize("case", ["block", "arch"])
def test_compiled_loop_is_the_reference(case):
    """The same steps, landings, impacts and solves; positions and energies to 1e-9."""
    if case == "block":
        sim, gm, te = Simulator(SLENDER, voussoirs=1), GroundMotion.rectangular(0.3, 0.5), 2.0
    else:
        sim, gm, te = Simulator(ARCH, voussoirs=7), GroundMotion.sine(0.45, 0.3), 1.5
    a = sim.run(gm, dt=1e-3, t_end=te)
    b = sim.run(gm, dt=1e-3, t_end=te, engine="reference")
    assert (a.steps, a.cut_steps, len(a.impacts), a.pivots) == (b.steps, b.cut_steps, len(b.impacts), b.pivots)
    assert a.peak_rotation == pytest.approx(b.peak_rotation, rel=1e-9)
    assert np.max(np.abs(a.positions[-1] - b.positions[-1])) < 1e-9
    for k in ("K", "V", "W_ground", "dissipated"):
        scale = max(np.max(np.abs(b.history[k])), 1e-12)
        assert np.max(np.abs(a.history[k] - b.history[k])) < 1e-9 * scale, k


def test_overturning_level_is_far_from_the_contact_errors():
    """A 7-voussoir arch rocking and coming to rest: the lowest potential energy of the run is within
    1e-4 of the overturning level (-0.1 m g t) of rest (measured: 2.2e-8 of it; 2.8e-5 on 100 rigid
    elements under 0.6 g, 0.56 s: a margin of 3.6e4 over the contact errors)."""
    sim = Simulator(ARCH, voussoirs=7)
    r = sim.run(GroundMotion.sine(0.45, 0.3), dt=1e-3, t_end=3.0)
    level = overturn_level(ARCH, sim.bodies.mass, G)
    assert r.outcome in ("rest", "survived")
    assert r.V_min > 1e-4 * level, (r.V_min, level)


def test_bad_friction_is_refused():
    from fembeam.errors import InputError
    for mu in (0.0, -1.0, math.nan, -math.inf, 1e9, "x"):
        with pytest.raises(InputError):
            Simulator(SQUAT, voussoirs=1, friction=mu)
    assert Simulator(SQUAT, voussoirs=1, friction=math.inf).friction is None    # unlimited: no sliding


def test_no_sliver_of_a_step_at_the_end():
    """4000 steps of 1e-3 s fall short of 4 s by round-off: the remainder (1e-13 s) was stepped, and
    at that scale the contact problem of a 200-element arch at rest failed its KKT check."""
    sim = Simulator(CircularArch.from_ratio(157.5, 0.15), elements=200)
    r = sim.run(GroundMotion.sine(0.3, 0.4), dt=1e-3, t_end=4.0)
    assert r.outcome == "rest" and r.steps == 4000 and r.t_end == pytest.approx(4.0, abs=1e-12)


@pytest.mark.parametrize("rows", [1, 5, 512])
def test_a_run_stops_at_its_outcome_across_returns(monkeypatch, rows):
    """The compiled loop returns to Python whenever its history buffer is full; an overturning decided
    in the step where it returned must still stop the run (it ran on to t_end, 3023 steps instead of
    643, when the buffer filled at that step).  dt_out = dt: a history row every step."""
    import fembeam.simulation.stepper as stepper
    monkeypatch.setattr(stepper, "CHUNK_ROWS", rows)
    sim = Simulator(SLENDER, voussoirs=1)
    ref = sim.run(GroundMotion.rectangular(0.5, 0.5), dt=1e-3, t_end=3.0, dt_out=1e-3, engine="reference")
    res = sim.run(GroundMotion.rectangular(0.5, 0.5), dt=1e-3, t_end=3.0, dt_out=1e-3)
    assert res.outcome == ref.outcome == "overturned"
    assert res.steps == ref.steps and res.t_end == pytest.approx(ref.t_overturn, abs=1e-12)
    assert res.peak_rotation == pytest.approx(ref.peak_rotation, rel=1e-9)
    slid = Simulator(SQUAT, voussoirs=1, friction=0.3).run(GroundMotion.rectangular(0.9, 3.0), dt=1e-3, t_end=1.0,
                                                            dt_out=1e-3)
    assert slid.outcome == "collapsed_by_sliding" and slid.t_end == pytest.approx(slid.t_overturn, abs=1e-12)
