"""Arches on moving supports (fembeam.analysis.supports, ``fembeam supports``)."""
from __future__ import annotations

import json
import math

import numpy as np
import pytest

from fembeam import CircularArch
from fembeam.analysis.supports import Movement, supports
from fembeam.analysis.thrust_range import thrust_range
from fembeam.cli.main import main
from fembeam.errors import InputError
from fembeam.fem import discretize, uniform_nodes
from fembeam.units import kN

ARCH = CircularArch.from_ratio(157.5, 0.15)


@pytest.fixture(scope="module")
def spread24():
    return supports(ARCH, Movement.of("spread"), voussoirs=24)


def test_rest_thrust_is_the_minimum_thrust(spread24):
    H_min = thrust_range(discretize(ARCH, uniform_nodes(ARCH, 24))).H_min
    assert spread24.path[0][1] == pytest.approx(H_min, rel=1e-9)
    assert spread24.H_min == pytest.approx(H_min, rel=1e-9)


def test_symmetric_arch_spreads_symmetrically(spread24):
    res = spread24
    J = res.chain.J
    joints = sorted(h["joint"] for h in res.hinges)
    assert joints == sorted(J - 1 - j for j in joints)
    for i in (len(res.frames) // 2, len(res.frames) - 1):
        d, th, _, side, _ = res.frames[i]
        uL, _ = res.movement_supports(d)
        C = res.chain.centroids(th, side, uL)
        assert np.allclose(C[0], -C[0][::-1], atol=1e-10)      # mirror image about x = 0
        assert np.allclose(C[1], C[1][::-1], atol=1e-10)
    assert res.path[-1][2] == pytest.approx(res.path[-1][3], rel=1e-9)   # equal vertical reactions
    assert res.outcome == "collapsed" and 0.02 < res.capacity_over_span < 0.15


def test_three_hinge_arch_against_closed_form():
    """Two voussoirs: a three-hinge arch (springings on the intrados, crown on the extrados).  The
    half turns about its springing pivot, which moves out by delta/2, with the crown pivot on the
    axis; the thrust from the moments about the crown pivot of the half."""
    res = supports(ARCH, Movement.of("spread"), voussoirs=2, steps=40)
    assert [(h["joint"], h["side"]) for h in res.hinges] == [(0, "intrados"), (1, "extrados"), (2, "intrados")]
    ch = res.chain
    PL0, PC0 = ch.I[:, 0], ch.E[:, 1]
    ell = float(np.hypot(*(PC0 - PL0)))
    Wh = ch.W[0]
    G0 = ch.C[:, 0]
    for d, H, Vl, Vr in res.path[1:]:
        if d > 0.9 * res.capacity:       # near the collinear pivots the thrust is ill-conditioned
            continue
        PL = PL0 + np.array([-d / 2, 0.0])
        PC = np.array([0.0, PL[1] + math.sqrt(ell ** 2 - PL[0] ** 2)])
        a0 = math.atan2(*(PC0 - PL0)[::-1])
        a = math.atan2(*(PC - PL)[::-1])
        R = np.array([[math.cos(a - a0), -math.sin(a - a0)], [math.sin(a - a0), math.cos(a - a0)]])
        G = PL + R @ (G0 - PL0)
        H_exact = kN(Wh * (PL[0] - G[0]) / (PL[1] - PC[1]))
        assert H == pytest.approx(H_exact, rel=1e-9)
        assert Vl == pytest.approx(kN(Wh), rel=1e-9)
    # collapse: the three pivots in line (the thrust grows without bound)
    capacity = 2 * (ell - abs(PL0[0]))
    assert res.outcome == "collapsed" and res.last_edge is None
    assert res.capacity == pytest.approx(capacity, rel=1e-3)


def test_capacity_converges_with_the_increments():
    """Events located inside the increments: the capacity does not depend on their number; put at
    the end of the increment where they are seen, it converges at first order."""
    exact = [supports(ARCH, Movement.of("spread"), voussoirs=12, steps=n).capacity for n in (20, 80)]
    assert exact[0] == pytest.approx(exact[1], rel=1e-9)
    errs = []
    for n in (20, 40, 80, 160):
        c = supports(ARCH, Movement.of("spread"), voussoirs=12, steps=n, refine=False).capacity
        assert c >= exact[1] - 1e-12
        errs.append(c - exact[1])
    rates = [math.log2(errs[i] / errs[i + 1]) for i in range(3) if errs[i + 1] > 0]
    assert rates and 0.5 < float(np.mean(rates)) < 1.6


def test_continuous_arch_capacity_converges_with_the_elements():
    c = [supports(ARCH, Movement.of("spread"), elements=n).capacity_over_span for n in (25, 50)]
    assert c[0] == pytest.approx(c[1], rel=1e-3)
    assert 0.05 < c[1] < 0.15


def test_settlement_and_up_to():
    res = supports(ARCH, Movement.of("settle"), voussoirs=12, up_to=0.01, steps=5)
    assert res.outcome == "reached_up_to" and res.capacity is None
    assert res.path[-1][0] == pytest.approx(0.01)
    W = kN(res.chain.Wtot)
    for d, H, Vl, Vr in res.path:                 # the weight on the two supports
        assert Vl + Vr == pytest.approx(W, rel=1e-9)


def _cli(argv, capsys):
    try:
        code = main(argv)
    except SystemExit as e:                      # argparse's errors
        code = e.code
    out = capsys.readouterr()
    return code, out.out, out.err


@pytest.mark.parametrize("argv", [
    ["supports", "--voussoirs", "8"],
    ["supports", "--move", "0,0"],
    ["supports", "--move", "nan,1"],
    ["supports", "--move", "1"],
    ["supports", "--spread", "--left"],
    ["supports", "--spread", "--settle"],
    ["supports", "--spread", "--up-to", "0"],
    ["supports", "--spread", "--up-to", "inf"],
    ["supports", "--spread", "--steps", "0"],
    ["supports", "--spread", "--snaps", "quasi"],
])
def test_bad_input_exits_2_with_one_line(argv, capsys):
    code, out, err = _cli(argv, capsys)
    assert code == 2
    assert out == "" and err.count("\n") == 1 and "error" in err


def test_json_interface_and_up_to_beyond_capacity(capsys, tmp_path):
    code, out, err = _cli(["supports", "--voussoirs", "12", "--spread", "--up-to", "5", "--json",
                           "--csv", str(tmp_path / "p.csv")], capsys)
    assert code == 0
    d = json.loads(out)
    for key in ("capacity", "capacity_over_span", "hinges", "migrations", "last_edge", "path", "units", "outcome",
                "settings"):
        assert key in d
    assert d["outcome"] == "collapsed" and d["capacity"] < 5
    assert d["capacity_over_span"] == pytest.approx(d["capacity"] / d["span"])
    assert set(d["path"][0]) >= {"displacement", "H", "V"}
    assert d["units"]["H"] == "kN/m" and d["units"]["capacity"] == "m"
    assert (tmp_path / "p.csv").read_text().startswith("displacement_m,H_kN_per_m")
    # voussoirs: snaps simulated; the collapse is the last one, which ended in a fall
    assert d["settings"]["snaps"] == "dynamic" and d["snaps"][-1]["ended"] == "collapse"
    assert d["snaps"][-1]["displacement"] == d["capacity"] and d["units"]["snaps.dissipated"] == "J/m"


def test_continuous_arch_snaps_statically_by_default():
    """The continuous arch's hinges roll; its unstable events snap statically unless asked."""
    a = supports(ARCH, Movement.of("spread"), elements=25)
    b = supports(ARCH, Movement.of("spread"), elements=25, snaps="dynamic")
    assert a.snap_model == "static" and a.snaps == [] and a.to_dict()["settings"]["snaps"] == "static"
    assert b.snap_model == "dynamic" and b.snaps[-1]["ended"] == "collapse"
    assert b.capacity == a.capacity        # its collapse: the fourth hinge at the springing, which falls


@pytest.mark.parametrize("snaps", ["static", "dynamic"])
def test_mirror_events_at_one_displacement(snaps):
    """A symmetric arch of thin voussoirs: the haunch hinges of both halves reach their next
    joints at the same displacement.  Static snaps: each snaps in turn (the other half's row at
    its edge is the next event, not a bar to the snap), the migrations come in mirror pairs and
    the capacity is the continuous arch's at the same pieces (0.10480 of the span on 100).
    Dynamic snaps: both halves snap together and come to rest on mirror joints."""
    arch = CircularArch()
    v = supports(arch, Movement.of("spread"), voussoirs=100, snaps=snaps)
    assert v.outcome == "collapsed" and len(v.migrations) % 2 == 0 and v.migrations
    for a, b in zip(v.migrations[::2], v.migrations[1::2]):
        assert a["displacement"] == b["displacement"] and a["joint"] + b["joint"] == 100
    if snaps == "static":
        c = supports(arch, Movement.of("spread"), elements=100)
        assert v.capacity_over_span == pytest.approx(0.10480, abs=1e-5)
        assert v.capacity == pytest.approx(c.capacity, rel=1e-6)
        assert v.snaps == []
    else:
        first = v.snaps[0]
        assert first["ended"] == "rest" and len(first["opened"]) == 2
        assert sorted(h["joint"] for h in first["opened"]) == [14, 86]
        after = [h["joint"] for h in first["hinges_after"]]
        assert after[1] == 50 and after[0] + after[2] == 100


@pytest.fixture(scope="module")
def snapping48():
    return supports(CircularArch(), Movement.of("spread"), voussoirs=48)


def test_dynamic_snap_energy_and_symmetry(snapping48):
    """A snap of 48 voussoirs with the supports held: the energy its impacts dissipate is the
    potential energy it releases (the simulation's energy balance against the chain's potential
    of the two exact equilibria), and both halves end on mirror joints."""
    res = snapping48
    first = res.snaps[0]
    assert first["ended"] == "rest" and first["potential_drop"] > 0
    assert first["dissipated"] == pytest.approx(first["potential_drop"], rel=2e-3)
    joints = [h["joint"] for h in first["hinges_after"]]
    assert joints[0] + joints[2] == 48 and joints[1] == 24
    assert [m["joint"] for m in res.migrations if m["displacement"] == first["displacement"]] == [joints[0], joints[2]]
    assert res.snaps[-1]["ended"] == "collapse" and res.capacity == res.snaps[-1]["displacement"]


def test_dynamic_snaps_agree_with_the_slow_simulation(snapping48):
    """The independent route: the multi-block simulation with the supports spread at 2.5 mm/s
    from rest collapses within 2 % of the capacity with dynamic snaps (measured +0.9 %; the
    simulation declares a collapse once the pieces have fallen, a little later), where the
    static rule (the next joint) is 14 % off."""
    from fembeam.dynamics import GroundMotion
    from fembeam.simulation import Simulator
    from fembeam.simulation.support_motion import SupportMotion
    still = GroundMotion(np.array([0.0, 1.0]), np.zeros(2), "none", True)
    rate = 0.0025
    sim = Simulator(CircularArch(), voussoirs=48).run(still, dt=1e-3, t_end=0.25 / rate, dt_out=1.0,
                                                      support_motion=SupportMotion.of("spread", rate))
    assert sim.outcome == "overturned"
    d_sim = rate * sim.t_collapse
    assert d_sim == pytest.approx(snapping48.capacity, rel=0.02)
    static = supports(CircularArch(), Movement.of("spread"), voussoirs=48, snaps="static")
    assert abs(static.capacity / d_sim - 1) > 0.1


def test_snaps_input():
    with pytest.raises(InputError, match="snaps must be one of"):
        supports(ARCH, Movement.of("spread"), voussoirs=12, snaps="quasi")


def test_move_with_a_negative_component(capsys):
    """``--move -1,0.5`` is a value, not an option: the same answer as ``--move=-1,0.5``."""
    a = _cli(["supports", "--voussoirs", "7", "--move", "-1,0.5", "--json"], capsys)
    b = _cli(["supports", "--voussoirs", "7", "--move=-1,0.5", "--json"], capsys)
    assert a[0] == b[0] == 0
    da, db = json.loads(a[1]), json.loads(b[1])
    assert da["capacity"] == db["capacity"] and da["settings"]["movement"]["direction"][0] < 0


def test_a_chattering_snap_is_read_from_its_three_hinges():
    """3 voussoirs settling: after its snap the simulated arch stands in a three-hinge state
    while a closed joint keeps chattering (kinetic energy ~1e-3 J/m, rotation ~1e-4 rad): the
    snap is read from the three joints turned most, and the path goes on to the capacity of the
    static snap, which ends in the same state."""
    a = supports(CircularArch(), Movement.of("settle"), voussoirs=3)
    b = supports(CircularArch(), Movement.of("settle"), voussoirs=3, snaps="static")
    assert a.snaps[0]["ended"] == "rest" and [h["joint"] for h in a.snaps[0]["hinges_after"]] == [0, 1, 3]
    assert a.capacity == pytest.approx(b.capacity, rel=1e-9)


def test_a_snap_that_does_not_end_is_an_error(monkeypatch, capsys):
    """A snap neither at rest nor fallen within the checks allowed is a SolverError (exit 3, one
    line naming --snaps static), not a collapse."""
    from fembeam.analysis import snaps
    from fembeam.errors import SolverError
    monkeypatch.setattr(snaps, "MAX_CHECKS", 1)
    with pytest.raises(SolverError, match="neither came to rest nor fell"):
        supports(CircularArch(), Movement.of("spread"), voussoirs=48)
    code, out, err = _cli(["supports", "--voussoirs", "48", "--spread"], capsys)
    assert code == 3 and out == "" and err.count("\n") == 1 and "--snaps static" in err
