"""The friction demand of ``fembeam rock`` (``friction_demand``: the largest |S|/N of the motion
and |P_t|/P_n of the impacts) against closed forms and independent routes.

* a block's impact: Housner's percussion at the new corner, ``P_n = m w/2 omega (1 + r_v)``,
  ``P_t = m h/2 omega (1 - r_v)``, so ``|P_t|/P_n = 1.5 sin a cos a / (2 - 1.5 sin^2 a)``;
* a rocking block's base: Newton's law for the centroid along Housner's equation integrated
  independently (solve_ivp), the reaction resolved on the base turned with the block;
* an arch's impact: the percussions at the springings balance the jump of the momentum and of
  its moment, computed from the finite-element mass matrix;
* no motion: no demand; a mirrored pulse: the same demand at the mirrored section;
* ``friction`` below the demand: sliding risk, above: none; bad coefficients exit 2.
"""
import json
import math

import numpy as np
import pytest

from fembeam import CircularArch, StraightMember, discretize, nodes_through, uniform_nodes
from fembeam.cli.main import main
from fembeam.dynamics import GroundMotion, Rocker
from fembeam.dynamics.equation import GRAVITY
from fembeam.dynamics.admissibility import motion_sections
from fembeam.dynamics.thrust import friction_ratio, impact_impulses
from fembeam.errors import InputError

BLOCK = StraightMember(height=2.0, width=0.5)      # tan alpha = 0.25, density 1
PAPER = CircularArch.from_ratio(157.5, 0.15, radius=5.0)


def housner_ratio(a):
    return 1.5 * math.sin(a) * math.cos(a) / (2 - 1.5 * math.sin(a) ** 2)


def test_impact_percussion_of_a_block():
    rk = Rocker(BLOCK, voussoirs=1, qp=False)
    k = rk.index(rk.start[1])
    eq = rk.equations[k]
    tr = rk.model(rk.mechanisms[k])
    k2 = rk.index(tr.after)
    omega = -eq.sign * 1.7                         # closing at 1.7 rad/s
    f = impact_impulses(eq, rk.equations[k2], omega, 1.7 * tr.alpha_ratio, [0.0])
    a, w, h, m = math.atan(0.25), BLOCK.width, BLOCK.height, BLOCK.density * BLOCK.width * BLOCK.height
    rv = 1 - 1.5 * math.sin(a) ** 2
    assert f.residual < 1e-14
    assert f.N[0] == pytest.approx(m * w / 2 * 1.7 * (1 + rv), rel=1e-12)
    assert abs(f.V[0]) == pytest.approx(m * h / 2 * 1.7 * (1 - rv), rel=1e-12)
    assert abs(f.eccentricity[0]) == pytest.approx(w / 2, rel=1e-12)        # through the new corner
    assert friction_ratio(f)[1][0] == pytest.approx(housner_ratio(a), rel=1e-12)


def housner_base_demand(A, period, w, h, t_end, n=4001):
    """The largest |S|/N at the base of a block rocking under one sine pulse ``A sin(2 pi t/T)``
    (g): Housner's equation about the corner (solve_ivp, rtol 1e-12), the rate times
    ``1 - 1.5 sin^2 a`` at each impact; the ground's reaction ``R = m (a_G - b)`` (``b``: gravity
    and ground inertia per unit mass) resolved on the base turned with the block, on ``n``
    instants of every excursion.  Returns (ratio, time, impacts)."""
    from scipy.integrate import solve_ivp

    m, g = w * h, GRAVITY
    inertia, alpha = m * (w * w + h * h) / 3, math.atan(w / h)
    rv = 1 - 1.5 * math.sin(alpha) ** 2

    side = [1.0 if A > 0 else -1.0]              # theta > 0: turning about the corner at -w/2

    def motion(t, th, rate):                     # arrays of instants
        c, s = np.cos(th), np.sin(th)
        x0, y0 = side[0] * w / 2, h / 2
        r = np.array([c * x0 - s * y0, s * x0 + c * y0])                  # G - C
        b = np.array([-np.where(t <= period, A * np.sin(2 * np.pi * t / period), 0.0) * g, np.full_like(t, -g)])
        acc = (r[0] * b[1] - r[1] * b[0]) * m / inertia
        R = m * (acc * np.array([-r[1], r[0]]) - rate * rate * r - b)
        return acc, np.abs(R[0] * c + R[1] * s) / (-R[0] * s + R[1] * c)   # on the turned base

    def back(t, y):
        return side[0] * y[0]
    back.terminal, back.direction = True, -1
    t, y = period / (2 * math.pi) * math.asin((w / h) / abs(A)), [0.0, 0.0]
    best, t_best, impacts = 0.0, None, 0
    while t < t_end:
        tb = period if t < period else t_end
        s = solve_ivp(lambda t_, y_: [y_[1], float(motion(np.array(t_), y_[0], y_[1])[0])], (t, tb), y,
                      events=(back,), method="DOP853", rtol=1e-12, atol=1e-14, dense_output=True)
        te = s.t_events[0][0] if s.t_events[0].size else tb
        ts = np.linspace(t, te, n)
        ratio = motion(ts, *s.sol(ts))[1]
        if ratio.max() > best:
            best, t_best = float(ratio.max()), float(ts[np.argmax(ratio)])
        if not s.t_events[0].size:
            t, y = tb, s.y[:, -1]
            continue
        rate, impacts = rv * s.y_events[0][0][1], impacts + 1
        if te > period and 0.5 * inertia * rate ** 2 < 1e-12 * m * g * (math.hypot(w, h) - h) / 2:
            break
        side[0], t, y = -side[0], te, [0.0, rate]
    return best, t_best, impacts


@pytest.mark.parametrize("amplitude", [0.3, -0.3])
def test_rocking_block_against_newton_along_housner(amplitude):
    """A block rocking to rest under a 0.5 s sine pulse (either sign: the mirror image): the
    motion's largest |S|/N at the base against the independent route to 1e-6 (its sampling),
    the impacts' |P_t|/P_n in closed form; the larger is the motion's."""
    rk = Rocker(BLOCK, voussoirs=1, qp=False)
    res = rk.run(GroundMotion.sine(amplitude, 0.5))
    ref, t_ref, impacts = housner_base_demand(amplitude, 0.5, BLOCK.width, BLOCK.height, res.t_end)
    assert res.outcome == "rest" and len(res.impacts) == impacts
    ratio, t, s = res.friction_motion
    assert ratio == pytest.approx(ref, rel=1e-6) and ratio >= ref * (1 - 1e-12) and s == 0.0
    assert t == pytest.approx(t_ref, abs=1e-3)
    assert res.friction_impact[0] == pytest.approx(housner_ratio(math.atan(0.25)), rel=1e-12)
    assert res.friction_impact[1] == res.impacts[0].t                 # every impact alike: the first
    fd = res.to_dict()["friction_demand"]
    assert fd == {"max_ratio": ratio, "t": t, "s": 0.0, "at": "motion", "mu": None, "sliding_risk": None}


def test_no_motion_no_demand_and_the_sliding_risk():
    rk = Rocker(BLOCK, voussoirs=1, qp=False)
    quiet = rk.run(GroundMotion.sine(0.2, 0.5), friction=0.01).to_dict()["friction_demand"]
    assert quiet == {"max_ratio": 0.0, "t": None, "s": None, "at": None, "mu": 0.01, "sliding_risk": False}
    ground = GroundMotion.sine(0.3, 0.5)
    demand = rk.run(ground).friction_demand["max_ratio"]
    assert rk.run(ground, friction=demand * (1 - 1e-6)).friction_demand["sliding_risk"] is True
    assert rk.run(ground, friction=demand * (1 + 1e-6)).friction_demand["sliding_risk"] is False
    for bad in (0.0, -0.2, math.inf, math.nan, True, "0.3"):
        with pytest.raises(InputError, match="friction coefficient"):
            rk.run(ground, friction=bad)
    with pytest.raises(InputError, match="thrust-line check"):
        rk.run(ground, friction=0.3, thrust_check=False)
    assert rk.run(ground, thrust_check=False).to_dict()["friction_demand"] is None


def test_arch_impact_percussions_balance_the_momentum():
    """The percussions at the springings (post-impact hinges there) equal the jump of the
    momentum and of its moment about the origin, from the finite-element mass matrix and the
    two mechanisms' fields on a mesh through both sets of hinges."""
    rk = Rocker(PAPER, voussoirs=7, qp=False)
    k = rk.index(rk.start[1])
    eq = rk.equations[k]
    tr = rk.model(rk.mechanisms[k])
    k2 = rk.index(tr.after)
    L = PAPER.length
    assert tr.after.s[0] == 0.0 and tr.after.s[-1] == pytest.approx(L, rel=1e-12)
    f = impact_impulses(eq, rk.equations[k2], -eq.sign, tr.alpha_ratio, [0.0, L])
    assert f.residual < 1e-12
    disc = discretize(PAPER, nodes_through(uniform_nodes(PAPER, 7), np.asarray(tr.after.s)))
    jump = tr.alpha_ratio * tr.after.dofs(disc) - (-eq.sign) * rk.mechanisms[k].dofs(disc)
    momentum = [disc.rigid(V=(1.0, 0.0)) @ disc.M @ jump, disc.rigid(V=(0.0, 1.0)) @ disc.M @ jump,
                disc.rigid(omega=1.0) @ disc.M @ jump]
    T = PAPER.tangent(np.array([0.0, L])) * f.N + PAPER.normal(np.array([0.0, L])) * f.V   # (2, 2)
    X = PAPER.position(np.array([0.0, L]))
    # the ground acts with T(0) at the left springing and -T(L) at the right one
    impulse = [T[0, 0] - T[0, 1], T[1, 0] - T[1, 1],
               X[0, 0] * T[1, 0] - X[1, 0] * T[0, 0] + f.M[0] - (X[0, 1] * T[1, 1] - X[1, 1] * T[0, 1] + f.M[1])]
    scale = max(abs(x) for x in momentum)
    assert impulse == pytest.approx(momentum, abs=1e-10 * scale)


@pytest.mark.parametrize("voussoirs", [7, None])
def test_mirrored_pulse_gives_the_mirrored_demand(voussoirs):
    """The demand of the mirrored pulse: the same ratios (1e-9) and times (1e-6 s) at the mirrored
    sections, for the motion and for the impacts (the largest impact ratio ties between mirrored
    transitions: the first impact within rounding of it is reported)."""
    rk = Rocker(PAPER, voussoirs=voussoirs, qp=False)
    # the continuous member to 1.2 s: its two first impacts, past both largest ratios (t = 0.43 s
    # and 1.09 s, the same as over the whole motion of 59 impacts and 20 transitions per side)
    t_end = None if voussoirs else 1.2
    plus, minus = (rk.run(GroundMotion.sine(a, 0.56), t_end=t_end) for a in (0.6, -0.6))
    L = PAPER.length
    for p, m in ((plus.friction_motion, minus.friction_motion), (plus.friction_impact, minus.friction_impact)):
        assert m[0] == pytest.approx(p[0], rel=1e-9)
        assert m[1] == pytest.approx(p[1], abs=1e-6)
        assert m[2] == pytest.approx(L - p[2], abs=1e-9 * L)
    assert plus.friction_demand["max_ratio"] == pytest.approx(minus.friction_demand["max_ratio"], rel=1e-9)
    # every section checked is in compression or counted out; the ratio is a section's
    assert all(0 <= s_ <= L for s_ in motion_sections(rk.equations[0], rk.joints))


def test_cli_friction(capsys):
    argv = ["rock", "--block", "0.5", "2.0", "--pulse", "sine", "--amplitude", "0.3", "--period", "0.5", "--json"]
    assert main(argv) == 0
    demand = json.loads(capsys.readouterr().out)["friction_demand"]["max_ratio"]
    for mu, risk in ((0.9 * demand, True), (1.1 * demand, False)):
        assert main(argv + ["--friction", repr(mu)]) == 0
        fd = json.loads(capsys.readouterr().out)["friction_demand"]
        assert fd["mu"] == mu and fd["sliding_risk"] is risk and fd["max_ratio"] == demand
    assert main(argv[:-1] + ["--friction", "0.1"]) == 0
    out = capsys.readouterr().out
    assert f"friction demand: largest |S|/N during the motion = {demand:.4f} at s = 0 m" in out
    assert "SLIDING RISK (above mu = 0.1)" in out
