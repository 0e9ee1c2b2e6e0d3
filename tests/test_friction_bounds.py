"""Coulomb friction without dilatancy: the associative limit load with mu is an upper bound of
the collapse load, the associative one with frictionless joints (Radenkovic's reduced
coefficient mu* = 0) a lower bound (docs/friction.md, section 3).  Checked against collapse
loads known in closed form: one voussoir on two radial skewbacks (statically indeterminate:
the associative value can lie strictly above the true one) and blocks on a base (statically
determinate: the true value is the associative one)."""
import itertools
import json
import math

import numpy as np
import pytest
from scipy.optimize import linprog

from fembeam import CircularArch, analyze, discretize, limit_analysis, uniform_nodes
from fembeam.analysis.friction import EXACT_WITHOUT_FRICTION, LOWER_BOUND, THICKNESS_BOUND, UPPER_BOUND
from fembeam.cli.main import main
from fembeam.geometry.block import StraightMember

BETA, TR = 90.0, 0.3          # one voussoir: an annular sector of 90 deg, t/R = 0.3, on two skewbacks at 45 deg
SECTOR = CircularArch.from_ratio(BETA, TR)


def sector(beta=BETA, tr=TR, R=1.0):
    """Intrados and extrados radii, height of the centroid above the centre, half-angle."""
    h = math.radians(beta) / 2
    ri, re = R * (1 - tr / 2), R * (1 + tr / 2)
    yg = 2 / 3 * (re ** 3 - ri ** 3) / (re ** 2 - ri ** 2) * math.sin(h) / h
    return ri, re, yg, h


def frictionless_load(beta=BETA, tr=TR, R=1.0):
    """Largest horizontal load factor with S = 0 at both skewbacks: the joint forces lie on the
    tangents of the arch at the windward extrados and the leeward intrados corners, which meet
    at Q = (-t / (2 sin h), R / cos h); the resultant of the load passes through Q."""
    ri, re, yg, h = sector(beta, tr, R)
    return (re - ri) / (2 * math.sin(h)) / (R / math.cos(h) - yg)


def collapse_load(mu, beta=BETA, tr=TR):
    """Collapse load without dilatancy once the voussoir leaves the windward skewback (here
    mu >= 0.4): it slides up the leeward skewback (inclined at alpha = 90 deg - h) when the
    resultant reaches the friction angle, tan(alpha + phi), or rocks on its extrados corner,
    r_e sin h / (y_G - r_e cos h), whichever comes first."""
    ri, re, yg, h = sector(beta, tr)
    slide = math.tan(math.pi / 2 - h + math.atan(mu))
    slide = slide if slide > 0 else math.inf            # alpha + phi >= 90 deg: it cannot slide up
    return min(slide, re * math.sin(h) / (yg - re * math.cos(h)))


def enumerated_collapse(mu, beta=BETA, tr=TR):
    """The smallest load factor >= 0 at which the voussoir has a collapse state without
    dilatancy, by exhausting the states of both joints (each fibre open with no force, or
    closed with no opening; the joint sticking, or sliding either way with S = -+mu N): an
    LP for the motion (rigid, with positive power of the horizontal load) and one for the
    forces per state.  Written from the geometry, independent of fembeam's operators."""
    ri, re, yg, h = sector(beta, tr)
    joints = []
    for a, side in ((math.pi / 2 + h, -1.0), (math.pi / 2 - h, 1.0)):
        e = np.array([math.cos(a), math.sin(a)])
        joints.append((ri * e, re * e, side * np.array([-e[1], e[0]]), e))   # corners, normal into it, tangent

    def cross(p, f):
        return p[0] * f[1] - p[1] * f[0]

    def rate(p, d):              # rate along d at p of the rigid motion (vx, vy, omega)
        return np.array([d[0], d[1], -p[1] * d[0] + p[0] * d[1]])

    # forces (N_in, N_out, S) of each joint and lambda; weight 1 at (0, yg), load (lambda, -1)
    A = np.zeros((3, 7))
    for j, (pi, pe, n, t) in enumerate(joints):
        for c, p in enumerate((pi, pe)):
            A[:2, 3 * j + c], A[2, 3 * j + c] = n, cross(p, n)
        A[:2, 3 * j + 2], A[2, 3 * j + 2] = t, cross(pi, t)
    A[0, 6], A[2, 6] = 1.0, -yg
    b = np.array([0.0, 1.0, 0.0])
    states = list(itertools.product((False, True), (False, True), (0, 1, -1)))   # open in, open out, slide
    best = math.inf
    for st in itertools.product(states, states):
        eq, ub = [], []
        for (pi, pe, n, t), (oi, oe, sl) in zip(joints, st):
            for p, op in ((pi, oi), (pe, oe)):
                (ub if op else eq).append(-rate(p, n) if op else rate(p, n))
            if sl == 0:
                eq.append(rate(pi, t))
            else:
                ub.append(-sl * rate(pi, t))
        motion = linprog(np.zeros(3), A_ub=np.array(ub) if ub else None, b_ub=np.zeros(len(ub)) if ub else None,
                         A_eq=np.array(eq + [[1.0, 0.0, -yg]]), b_eq=np.r_[np.zeros(len(eq)), 1.0],
                         bounds=[(None, None)] * 3, method="highs")
        if motion.status != 0:
            continue
        Aeq, beq, Aub = [A], [b], []
        bounds = [(0, None), (0, None), (None, None)] * 2 + [(0, None)]
        for j, (oi, oe, sl) in enumerate(st):
            bounds[3 * j] = (0, 0) if oi else bounds[3 * j]
            bounds[3 * j + 1] = (0, 0) if oe else bounds[3 * j + 1]
            N = np.zeros(7)
            N[3 * j:3 * j + 2] = mu
            S = np.zeros(7)
            S[3 * j + 2] = 1.0
            if sl == 0:
                Aub += [S - N, -S - N]
            else:                                         # friction opposes the sliding
                Aeq.append((S + sl * N)[None])
                beq.append([0.0])
        forces = linprog(np.eye(7)[6], A_ub=np.array(Aub) if Aub else None,
                         b_ub=np.zeros(len(Aub)) if Aub else None, A_eq=np.vstack(Aeq),
                         b_eq=np.concatenate(beq), bounds=bounds, method="highs")
        if forces.status == 0:
            best = min(best, forces.fun)
    return best


def bounds_of(res):
    fb = res.friction_bounds
    up = fb["upper"]["A_L"] if fb["upper"]["outcome"] == "ok" else math.inf
    return fb["lower"]["A_L"], up, fb


@pytest.mark.parametrize("mu", [0.5, 0.8, 0.9, 3.0])
def test_voussoir_on_two_skewbacks(mu):
    true = collapse_load(mu)
    assert enumerated_collapse(mu) == pytest.approx(true, rel=1e-9)
    lower, upper, fb = bounds_of(analyze(SECTOR, voussoirs=1, friction=mu))
    assert lower == pytest.approx(frictionless_load(), rel=1e-9) == pytest.approx(0.418287, abs=1e-6)
    assert lower <= true <= upper * (1 + 1e-12)
    assert fb["determinate"] is False and fb["upper"]["bound"] == UPPER_BOUND and fb["lower"]["bound"] == LOWER_BOUND
    if mu == 0.5:     # it slides up the leeward skewback: the associative mechanism is the true one
        assert true == pytest.approx(3.0, rel=1e-12) and upper == pytest.approx(true, rel=1e-9)
    if mu == 0.8:     # it rocks on the extrados corner (8.660366 g), the associative value is 8.737301 g
        assert true == pytest.approx(8.660366, abs=1e-6) and upper == pytest.approx(8.737301, abs=1e-6)
    if mu == 3.0:     # no associative mechanism at all, yet it rocks at 8.66 g
        assert fb["upper"]["outcome"] == "no_mechanism" and fb["upper"]["A_L"] is None


def test_reduced_coefficients_that_are_not_safe():
    """Davis's reduction for zero dilatancy, tan phi* = sin phi, is not a lower bound at a
    joint: with mu = 3 it gives mu* = 0.9487, whose associative load factor, 22.8 g, is far
    above the collapse load 8.66 g; Radenkovic's mu* = 0 (0.418 g) is below it."""
    mu = 3.0
    davis = math.sin(math.atan(mu))
    lim = limit_analysis(discretize(SECTOR, uniform_nodes(SECTOR, 1)), friction=davis)
    assert lim.status == "ok" and lim.A_L > 2.5 * collapse_load(mu)


def test_frictionless_joints_are_exact():
    """mu = 0: the associative flow has no dilatancy, the analysis is exact."""
    res = analyze(SECTOR, voussoirs=1, friction=0.0)
    lower, upper, fb = bounds_of(res)
    assert lower == upper == res.A_L == pytest.approx(frictionless_load(), rel=1e-9)
    assert enumerated_collapse(0.0) == pytest.approx(res.A_L, rel=1e-9)
    assert fb["known"] == EXACT_WITHOUT_FRICTION and res.to_dict()["bound"] == EXACT_WITHOUT_FRICTION


@pytest.mark.parametrize("blocks", [1, 2])
@pytest.mark.parametrize("mu", [0.1, 0.5])
def test_blocks_on_a_base_are_determinate(blocks, mu):
    """A block of width b and height H (or two stacked blocks) under a horizontal load: it
    slides at mu or rocks at b / H, whichever comes first, whatever the flow rule (the joint
    forces follow from equilibrium); frictionless joints slide at once."""
    block = StraightMember(height=1.0, width=0.2)
    lower, upper, fb = bounds_of(analyze(block, voussoirs=blocks, friction=mu))
    true = min(mu, 0.2 / 1.0)
    assert fb["determinate"] is True and "equals the upper value" in fb["known"]
    assert lower == 0.0 and upper == pytest.approx(true, rel=1e-9)


def test_large_friction_closes_only_the_upper_side():
    """Ample friction: the upper bound is the no-sliding A_L (tests/test_friction.py), the
    lower bound does not move.  The gap does not close: for the paper's arch (radial joints)
    frictionless joints cannot stand, and for the voussoir the no-sliding model finds no
    mechanism at all while it rocks at 8.66 g (a joint that separates may also slide)."""
    arch = CircularArch.from_ratio(157.5, 0.15)
    free = analyze(arch)
    lower, upper, fb = bounds_of(analyze(arch, friction=10.0))
    assert upper == pytest.approx(free.A_L, rel=1e-9)
    assert lower is None and fb["lower"]["outcome"] == "cannot_stand" and fb["lower"]["reason"]
    assert analyze(SECTOR, voussoirs=1).outcome == "no_mechanism"
    for mu in (2.0, 1000.0):
        lower, upper, _ = bounds_of(analyze(SECTOR, voussoirs=1, friction=mu))
        assert lower == pytest.approx(frictionless_load(), rel=1e-9) and upper == math.inf
        assert lower < collapse_load(mu) < upper


def _cli(capsys, *argv):
    assert main(list(argv)) == 0
    return capsys.readouterr().out


def test_cli_reports_both_bounds(capsys):
    argv = ["analyze", "--voussoirs", "1", "--embrace", "90", "--t-over-r", "0.3", "--friction", "0.8"]
    d = json.loads(_cli(capsys, *argv, "--json"))
    assert d["bound"] == UPPER_BOUND and d["A_L"] == pytest.approx(8.737301, abs=1e-6)
    assert d["friction_bounds"]["lower"]["A_L"] == pytest.approx(0.418287, abs=1e-6)
    assert d["friction_bounds"]["upper"]["A_L"] == d["A_L"]
    out = _cli(capsys, *argv)
    assert "an UPPER bound" in out and "upper bound  8.737301 g" in out and "lower bound  0.418287 g" in out
    out = _cli(capsys, *argv[:-1], "3")
    assert "NO MECHANISM with associative friction" in out and "lower bound  0.418287 g" in out
    d = json.loads(_cli(capsys, "analyze", "--voussoirs", "5", "--json"))
    assert d["bound"] is None and d["friction_bounds"] is None
    assert "UPPER bound" in _cli_help(capsys, "analyze") and "LOWER bound" in _cli_help(capsys, "min-thickness")


def _cli_help(capsys, cmd):
    with pytest.raises(SystemExit):
        main([cmd, "--help"])
    return " ".join(capsys.readouterr().out.split())


def test_cli_min_thickness_is_a_lower_bound(capsys):
    d = json.loads(_cli(capsys, "min-thickness", "--embrace", "180", "--elements", "40", "--friction", "0.4",
                        "--json"))
    assert d["bound"] == THICKNESS_BOUND
    out = _cli(capsys, "min-thickness", "--embrace", "180", "--elements", "40", "--friction", "0.4")
    assert "a LOWER bound" in out
    assert json.loads(_cli(capsys, "min-thickness", "--embrace", "180", "--elements", "40", "--json"))["bound"] is None
