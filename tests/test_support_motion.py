"""A prescribed support motion in the multi-block simulation (``simulate --support-motion``):
unchanged without it, a rigid translation of both supports equals the equivalent ground motion,
the two engines agree, and a slow spreading (or settlement) collapses at the capacity of
``fembeam supports`` with the thrust of its quasi-static path."""
from __future__ import annotations

import hashlib
import math
import json

import numpy as np
import pytest

from fembeam import CircularArch, StraightMember
from fembeam.analysis.supports import Movement, supports
from fembeam.dynamics import GroundMotion
from fembeam.dynamics.equation import GRAVITY
from fembeam.errors import InputError
from fembeam.simulation import Simulator
from fembeam.simulation.support_motion import SUPPORT_COLUMNS, SupportMotion

STILL = GroundMotion(np.array([0.0, 1.0]), np.zeros(2), "none", True)


def _md5(a) -> str:
    return hashlib.md5(np.ascontiguousarray(a).tobytes()).hexdigest()


def test_without_support_motion_unchanged():
    """The runs of the simulation before the supports could move, bit for bit (digests of the
    final state and of the kinetic energy's history recorded before the change)."""
    arch = CircularArch()
    want = {0.3: ("rest", None, 1000, "eb8364bc6a0df94fbf6ea5fda6ff2253", "1b04a0951af40d7f56340fe8ff50d4b3"),
            0.6: ("overturned", 0.75794263543762, 463, "85b09a24c2802175ea4d5646878600d2",
                  "5caf82918bbcec8d958ed47408b4df01")}
    for amp, (outcome, t_over, steps, q_md5, k_md5) in want.items():
        r = Simulator(arch, voussoirs=7).run(GroundMotion.sine(amp, 0.5), dt=2e-3, t_end=2.0)
        assert (r.outcome, r.t_overturn, r.steps) == (outcome, t_over, steps)
        assert _md5(r.q_end) == q_md5 and _md5(r.history["K"]) == k_md5
        assert r.support_motion is None and not set(SUPPORT_COLUMNS) & set(r.history)
        assert "support_motion" not in r.to_dict()
    # with friction, to 1e-6 s: the converged frictional solution (recorded before the support
    # motion as 0.7347168 s in 445 steps when the fixed point settled the steps at a Coulomb
    # residual of 1e-5; with its tolerance at 1e-7 and 1e-9 the same code gave 0.7351716 and
    # 0.7351787 s in 446 steps, and Newton's polished answers give 0.7351789 s)
    r = Simulator(arch, voussoirs=7, friction=0.5).run(GroundMotion.sine(0.6, 0.5), dt=2e-3, t_end=1.0)
    assert (r.outcome, r.steps) == ("overturned", 446)
    assert r.t_overturn == pytest.approx(0.7351787607, abs=1e-6)


@pytest.mark.parametrize("engine", ["compiled", "reference"])
@pytest.mark.parametrize("member", ["arch", "block"])
def test_rigid_translation_is_a_ground_motion(engine, member):
    """Both supports moved together at ``r`` (m/s) from rest: in the supports' frame, a ground
    whose velocity jumps by ``r``: the rectangular pulse ``r / (g dt)`` over the first step.  The
    supports already move during the first step (their displacement is ``r t`` exactly) while
    the pulse's bodies take the jump at its end: the two differ by the support offset
    ``r dt / 2`` (5e-5 m here), which the rocking then carries: agreement to ``10 r dt``."""
    dt, r, T = 2e-3, 0.05, 0.6
    sim = Simulator(CircularArch(), voussoirs=5) if member == "arch" else \
        Simulator(StraightMember(height=1.0, width=0.25), voussoirs=1)
    a = sim.run(STILL, dt=dt, t_end=T, dt_out=0.02, engine=engine, support_motion=SupportMotion.rigid((1.0, 0.0), r))
    b = sim.run(GroundMotion.rectangular(r / (GRAVITY * dt), dt), dt=dt, t_end=T, dt_out=0.02, engine=engine)
    ta, tb = np.asarray(a.history["t"]), np.asarray(b.history["t"])
    k = min(ta.size, tb.size)
    assert np.max(np.abs(ta[:k] - tb[:k])) < dt
    rel = np.array(a.positions)[:k] - np.array(b.positions)[:k]
    rel[..., 0] -= r * ta[:k, None]
    assert np.max(np.abs(rel)) < 10 * r * dt
    assert np.max(a.history["max_rotation"]) > 5e-4          # it rocked relative to the supports
    assert np.allclose(a.history["support_displacement"], r * ta)


@pytest.mark.parametrize("engine", ["compiled", "reference"])
@pytest.mark.parametrize("direction", [(1.0, 0.0), (0.0, 1.0), (0.6, -0.8)])
def test_rigid_translation_with_the_supports_is_exact(engine, direction):
    """Both supports moved together at a constant rate ``r`` with the arch already moving at
    ``r`` (``v0``): a rigid translation, which the time stepping must follow exactly (Galilean
    invariance): every body at its place at rest plus ``r t`` along the direction and unrotated
    to round-off, no hinge, and the forces on the supports those of the arch at rest with the
    supports held: ``H_left = H_right`` and ``V_left + V_right`` = the weight to round-off, and
    ``H`` the at-rest thrust (statically indeterminate: the contact problem fixes it to its
    tolerance, and it wanders by a few 1e-6 of itself at rest too)."""
    dt, r, T = 2e-3, 0.05, 0.3
    sim = Simulator(CircularArch(), voussoirs=5)
    n = sim.bodies.n
    weight = sim.bodies.mass * GRAVITY / 1e3                     # kN/m
    held = SupportMotion("rigid", (0.0, 0.0), (0.0, 0.0), r)     # the supports held: at rest
    rest = sim.run(STILL, dt=dt, t_end=T, dt_out=0.02, engine=engine, support_motion=held)
    mo = SupportMotion.rigid(direction, r)
    u = np.array(mo.left)
    v0 = np.zeros((n + 1, 3))
    v0[:n, :2] = r * u
    a = sim.run(STILL, dt=dt, t_end=T, dt_out=0.02, engine=engine, support_motion=mo, v0=v0)
    assert a.steps == rest.steps == round(T / dt) and a.cut_steps == 0
    t = np.asarray(a.history["t"])
    P = np.array(a.positions)
    moved = P - sim.bodies.rest_state()[None, :n]
    moved[..., :2] -= r * t[:, None, None] * u
    assert np.max(np.abs(moved)) < 1e-14                       # m and rad: no relative motion
    assert np.max(a.history["max_rotation"]) < 1e-14 and np.max(a.history["hinges"]) == 0
    assert np.allclose(a.history["support_displacement"], r * t, rtol=0, atol=1e-15)
    assert np.allclose(a.support_q_end, r * T * np.array([u, u]), rtol=0, atol=1e-14)
    assert a.energy_balance_error < 1e-9
    h, h0 = ({k: np.asarray(x.history[k])[1:] for k in ("H_left", "H_right", "V_left", "V_right")}
             for x in (a, rest))                               # row 0: no interval yet
    H0 = float(np.mean(h0["H_left"]))
    assert H0 > 1.0
    for x in (h, h0):
        assert np.max(np.abs(x["H_left"] - x["H_right"])) < 1e-10 * H0
        assert np.max(np.abs(x["V_left"] + x["V_right"] - weight)) < 1e-10 * weight
        assert np.max(np.abs(x["H_left"] - H0)) < 1e-5 * H0
        assert np.max(np.abs(x["V_left"] - weight / 2)) < 1e-5 * weight


@pytest.mark.parametrize("engine", ["compiled", "reference"])
def test_held_displaced_supports_keep_a_quasi_static_state(engine):
    """A run from a state of the quasi-static path (``fembeam supports``, spread by 10 cm: three
    hinges open) on supports :meth:`SupportMotion.held` there: the bodies placed by the chain's
    exact rotations rest on their pivots, in equilibrium, so nothing moves (1e-12 m, measured
    4e-16), and the mean forces on the supports are the path's thrust and weights (a
    three-hinge state is statically determinate: 1e-9, measured 3e-13)."""
    from fembeam.analysis.snaps import _state
    d = 0.10         # deep enough that the crown is below the rest's overturning level: measured from the start
    path = supports(CircularArch(), Movement.of("spread"), voussoirs=7, up_to=d, steps=10)
    _, theta, count, side, _ = path.frames[-1]
    assert count == 3 and path.path[-1][0] == pytest.approx(d)
    ch = path.chain
    q0, v0 = _state(ch, theta, side, -0.5 * d * np.array([1.0, 0.0]), np.zeros(ch.J))
    held = SupportMotion.held("spread", d)
    assert held.hold_after == 0 and np.allclose(held.supports_at_start(), [[-d / 2, 0], [d / 2, 0]])
    sim = Simulator(CircularArch(), voussoirs=7)
    res = sim.run(STILL, dt=2e-3, t_end=0.5, dt_out=0.05, q0=q0, v0=v0, engine=engine, support_motion=held)
    assert res.outcome == "rest"
    assert np.max(np.abs(np.asarray(res.positions[-1]) - q0[:-1])) < 1e-12
    assert np.allclose(res.history["support_displacement"], d, rtol=0, atol=1e-15)
    _, H, Vl, Vr = path.path[-1]
    assert np.mean(res.history["H_left"][1:]) == pytest.approx(H, rel=1e-9)     # statically determinate
    assert np.mean(res.history["V_left"][1:]) == pytest.approx(Vl, rel=1e-9)
    assert np.mean(res.history["V_right"][1:]) == pytest.approx(Vr, rel=1e-9)


def test_support_motion_start_checked():
    held = SupportMotion.held("settle", 0.2, left=True)
    assert held.is_held and held.describe()["rate_m_per_s"] is None and held.describe()["start_m"] == 0.2
    assert not SupportMotion.of("settle", 0.01).is_held
    for start in (-0.1, math.nan, 0.3):
        with pytest.raises(InputError, match="at the start"):
            SupportMotion("spread", (-0.5, 0.0), (0.5, 0.0), 1.0, 0.2, start)


def test_engines_agree_under_spreading():
    """The compiled loop and the NumPy reference: the same motion and forces on the supports."""
    sim = Simulator(CircularArch(), voussoirs=5)
    mo = SupportMotion.of("spread", 0.05, up_to=0.01)
    a = sim.run(STILL, dt=2e-3, t_end=0.5, dt_out=0.02, support_motion=mo)
    b = sim.run(STILL, dt=2e-3, t_end=0.5, dt_out=0.02, support_motion=mo, engine="reference")
    assert a.steps == b.steps
    assert np.max(np.abs(np.array(a.positions)[-1] - np.array(b.positions)[-1])) < 1e-9
    ta, tb = np.asarray(a.history["t"]), np.asarray(b.history["t"])
    for k in ("H_left", "H_right", "V_left", "V_right"):
        fb = np.interp(ta, tb, b.history[k])
        # (the compiled loop also samples the instant the supports stop: the means after it differ)
        keep = np.isin(np.round(ta, 9), np.round(tb, 9)) & (ta > 0) & (ta < mo.hold_after)
        assert np.allclose(np.asarray(a.history[k])[keep], fb[keep], rtol=1e-6, atol=1e-9), k
    assert a.history["support_displacement"][-1] == pytest.approx(0.01)     # held at up_to
    assert np.allclose(a.support_q_end, [[-0.005, 0.0], [0.005, 0.0]])


def _quasi_static(kind, voussoirs, rate, dt):
    arch = CircularArch()
    qs = supports(arch, Movement.of(kind), voussoirs=voussoirs)
    sim = Simulator(arch, voussoirs=voussoirs)
    T = 1.3 * qs.capacity / rate
    res = sim.run(STILL, dt=dt, t_end=T, dt_out=T / 400, support_motion=SupportMotion.of(kind, rate))
    return qs, res


@pytest.mark.parametrize("kind, rate", [("spread", 0.01), ("settle", 0.01)])
def test_slow_movement_follows_supports(kind, rate):
    """7 voussoirs of the default arch moved slowly: the collapse at ``fembeam supports``'s
    capacity and the thrust along its path (the mechanism may be the mirror image of the
    quasi-static one: the vertical reactions are compared as a set)."""
    qs, res = _quasi_static(kind, 7, rate, 1e-3)
    d = res.to_dict()
    assert res.outcome == "overturned"
    assert d["support_displacement_at_collapse"] == pytest.approx(qs.capacity, rel=0.03)
    P = np.array(qs.path)
    h = res.history
    u = np.asarray(h["support_displacement"])
    for frac in (0.1, 0.3, 0.5, 0.7, 0.9):
        i = int(np.argmin(np.abs(u - frac * qs.capacity)))
        H = np.interp(u[i], P[:, 0], P[:, 1])
        assert h["H_left"][i] == pytest.approx(H, rel=0.02)
        assert h["H_right"][i] == pytest.approx(H, rel=0.02)
        Vq = sorted([np.interp(u[i], P[:, 0], P[:, 2]), np.interp(u[i], P[:, 0], P[:, 3])])
        assert sorted([h["V_left"][i], h["V_right"][i]]) == pytest.approx(Vq, rel=0.02)
        assert h["K"][i] < 1e-3 * abs(h["W_ground"][i])     # quasi-static: K << the supports' work


def test_support_motion_input():
    for bad in (0.0, -1.0, float("nan"), float("inf"), "x"):
        with pytest.raises(InputError):
            SupportMotion.of("spread", bad)
    for bad in (0.0, -0.1, float("inf")):
        with pytest.raises(InputError):
            SupportMotion.of("settle", 0.1, up_to=bad)
    with pytest.raises(InputError):
        SupportMotion.of("twist", 0.1)
    with pytest.raises(InputError):
        SupportMotion.of("spread", 0.1, left=True)
    with pytest.raises(InputError):
        Simulator(CircularArch(), voussoirs=5).run(STILL, support_motion="spread")


def _cli(*argv):
    from inprocess import fembeam
    return fembeam("simulate", *argv)


@pytest.mark.parametrize("argv", [
    ["--support-motion", "twist", "--support-rate", "0.1"],
    ["--support-motion", "spread", "--support-rate", "0"],
    ["--support-motion", "spread", "--support-rate", "-0.1"],
    ["--support-motion", "spread", "--support-rate", "nan"],
    ["--support-motion", "spread", "--support-rate", "inf"],
    ["--support-motion", "spread"],
    ["--support-motion", "settle", "--support-rate", "0.1", "--support-up-to", "0"],
    ["--support-motion", "settle", "--support-rate", "0.1", "--support-up-to", "-1"],
    ["--support-motion", "0,0", "--support-rate", "0.1"],
    ["--support-motion", "spread", "--support-rate", "0.1", "--support-left"],
    ["--pulse", "sine", "--amplitude", "0.1", "--period", "0.5", "--support-rate", "0.1"],
    ["--pulse", "sine", "--amplitude", "0.1", "--period", "0.5", "--support-motion", "spread", "--support-rate", "1"],
    ["--pulse", "sine", "--amplitude", "0.1", "--period", "0.5", "--thrust-plot", "thrust.png"],
    ["--support-motion", "spread", "--support-rate", "0.1", "--thrust-plot", "thrust.txt"],
    ["--support-motion", "spread", "--support-rate", "0.1", "--thrust-plot", "/no/such/folder/thrust.png"],
    ["--support-motion", "spread", "--support-rate", "0.1", "--thrust-plot", "same.png", "--plot", "same.png"],
])
def test_cli_bad_input(argv):
    p = _cli("--voussoirs", "5", *argv)
    assert p.returncode == 2
    assert len(p.stderr.strip().splitlines()) == 1, p.stderr


def test_cli_json():
    p = _cli("--voussoirs", "5", "--support-motion", "spread", "--support-rate", "0.05", "--support-up-to", "0.01",
             "--t-end", "0.3", "--dt", "2e-3", "--json", "--history")
    assert p.returncode == 0, p.stderr
    d = json.loads(p.stdout)
    assert d["support_motion"]["kind"] == "spread" and d["support_displacement_at_collapse"] is None
    assert d["outcome"] in ("rest", "survived")
    assert set(SUPPORT_COLUMNS) <= set(d["history"])
    assert d["history"]["support_displacement"][-1] == pytest.approx(0.01)
    assert d["history"]["H_left"][-1] > 1.0 and d["units"]["history.H_left"] == "kN/m"


def test_cli_thrust_plot(tmp_path):
    """``--thrust-plot``: the forces on the supports against their displacement over the
    quasi-static path, written as a PNG and named in the text answer."""
    out = tmp_path / "thrust.png"
    p = _cli("--voussoirs", "5", "--support-motion", "spread", "--support-rate", "0.05", "--support-up-to", "0.01",
             "--t-end", "0.3", "--dt", "2e-3", "--thrust-plot", str(out))
    assert p.returncode == 0, p.stderr
    assert out.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n" and out.stat().st_size > 10_000
    line = [x for x in p.stdout.splitlines() if "thrust figure" in x]
    assert line == [f"  thrust figure: {out} (over the quasi-static path)"]


def test_thrust_figure_paths():
    """The quasi-static path of the figure: the movement of the simulation up to 1.1 times its
    largest displacement; none for a rigid translation of both supports."""
    from fembeam.cli.simulate import quasi_static
    from fembeam.output.supports import support_thrust_figure
    arch = CircularArch()
    sim = Simulator(arch, voussoirs=5)
    a = sim.run(STILL, dt=2e-3, t_end=0.3, dt_out=0.02, support_motion=SupportMotion.of("settle", 0.05, left=True,
                                                                                          up_to=0.01))
    qs, note = quasi_static(a, arch, 5, None)
    assert note is None and qs.movement == Movement.of("settle", left=True)
    assert qs.outcome == "reached_up_to" and qs.path[-1][0] == pytest.approx(0.011)
    fig = support_thrust_figure(a, qs)
    assert len(fig.axes) == 2 and len(fig.axes[0].lines) == 3
    b = sim.run(STILL, dt=2e-3, t_end=0.1, dt_out=0.02, support_motion=SupportMotion.rigid((1.0, 0.0), 0.05))
    qs, note = quasi_static(b, arch, 5, None)
    assert qs is None and "together" in note
    support_thrust_figure(b, None, note)
    with pytest.raises(ValueError):
        support_thrust_figure(sim.run(STILL, dt=2e-3, t_end=0.1))
    import matplotlib.pyplot as plt
    plt.close("all")
