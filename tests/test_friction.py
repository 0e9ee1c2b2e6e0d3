"""Coulomb friction at the joints: the limit LP with friction rows and its certificates
(sliding with associative dilatancy), the friction each result needs, the command line,
and the minimum thickness of the semicircular arch against Cocchetti & Rizzi (2020)."""
import json
import math
import re

import numpy as np
import pytest

from fembeam import CircularArch, analyze, discretize, limit_analysis, minimum_thickness, uniform_nodes
from fembeam.analysis.friction import mass_on_midcurve
from fembeam.analysis.limit import FRICTION_TOL
from fembeam.analysis.continuum import margin_search
from fembeam.analysis.rows import joint_rows
from fembeam.analysis.statics import section_forces, statics
from fembeam.cli.main import main
from fembeam.errors import InputError

from inprocess import fembeam

PAPER = CircularArch.from_ratio(157.5, 0.15)


def disc_of(arch, n=200):
    return discretize(arch, uniform_nodes(arch, n))


@pytest.mark.parametrize("beta, tr, direction", [(157.5, 0.15, 1), (180.0, 0.15, -1), (120.0, 0.1, 1)])
def test_large_friction_is_frictionless(beta, tr, direction):
    disc = disc_of(CircularArch.from_ratio(beta, tr))
    free = limit_analysis(disc, direction)
    need = free.verification["max_shear_ratio"]
    for mu in (2 * need, 10.0, 1e3):
        lim = limit_analysis(disc, direction, friction=mu)
        assert lim.status == "ok" and lim.slides == []
        assert abs(lim.A_L - free.A_L) <= 1e-9 * free.A_L
        assert [(h.angle_deg, h.side) for h in lim.hinges] == [(h.angle_deg, h.side) for h in free.hinges]


def test_pipeline_and_thickness_with_large_friction():
    a, b = analyze(PAPER), analyze(PAPER, friction=10.0)
    assert b.outcome == "rocking" and abs(b.A_L - a.A_L) <= 1e-9 * a.A_L
    assert b.r == pytest.approx(a.r, abs=1e-6)   # the meshes through the hinges differ by ~1e-7 L
    t0 = minimum_thickness(CircularArch.from_ratio(180, 0.15), tol=1e-9)
    t1 = minimum_thickness(CircularArch.from_ratio(180, 0.15), tol=1e-9, friction=10.0)
    assert abs(t1.t_over_R - t0.t_over_R) <= 1e-9 * t0.t_over_R and t1.to_dict()["friction"] == 10.0


def test_load_factor_is_monotone_and_drops_when_a_springing_slides():
    disc = disc_of(PAPER)
    free = limit_analysis(disc).A_L
    mus = [0.2, 0.3, 0.35, 0.4, 0.45, 0.5, 0.6, 1.0]
    res = [limit_analysis(disc, friction=mu) for mu in mus]
    A = [r.A_L if r.status == "ok" else -np.inf for r in res]
    assert res[0].status == "cannot_stand"
    assert all(a2 >= a1 - 1e-12 for a1, a2 in zip(A, A[1:])) and A[-1] == pytest.approx(free, rel=1e-12)
    slid = res[mus.index(0.4)]
    assert slid.A_L < 0.75 * free                       # 0.254 g against 0.353 g
    assert [s["angle_deg"] for s in slid.slides] == [157.5]   # the springing the load pushes slides
    assert slid.verification["max_shear_ratio"] == pytest.approx(0.4, rel=1e-9)


def test_shallow_arch_slides_at_its_springings():
    disc = disc_of(CircularArch.from_ratio(60.0, 0.1), 100)
    free = limit_analysis(disc).A_L
    lim = limit_analysis(disc, friction=0.4)
    assert lim.status == "ok" and lim.A_L < 0.8 * free
    assert lim.slides and {s["angle_deg"] for s in lim.slides} <= {0.0, 60.0}   # the springings slide


@pytest.mark.parametrize("mu", [0.3, 0.4, 0.45])
def test_sliding_certificate(mu):
    """The mechanism of the duals: jumps in the dual cone eps+- >= mu |gamma| (sliding
    with dilatancy mu |gamma| on both fibres), closed on the abutments, doing the work of
    the static load factor, and the joint forces inside the friction cone."""
    disc = disc_of(PAPER)
    lim = limit_analysis(disc, friction=mu)
    u = lim.u
    gam, eps = disc.B_slide @ u, (disc.B_open @ u).reshape(2, -1)
    scale = np.abs(eps).max()
    assert np.abs(gam).max() > 0.1 * scale                                 # it slides
    assert np.min(eps - mu * np.abs(gam)) >= -1e-9 * scale                 # associative cone
    k = np.flatnonzero(np.abs(gam) > 1e-6 * scale)
    assert np.allclose(eps[:, k], mu * np.abs(gam[k]), atol=1e-9 * scale) or lim.hinges  # pure slide: dilatancy only
    fx, fy = disc.load_vectors()
    assert float(fy @ u) / float(fx @ u) == pytest.approx(lim.A_L, rel=1e-9)   # kinematic = static
    N, S = lim.N[0] + lim.N[1], lim.S
    assert np.all(np.abs(S) <= mu * N + 1e-9 * N.max()) and lim.N.min() >= -1e-9 * N.max()
    # the work of the joint forces on the jumps vanishes (complementarity / no dissipation)
    work = S @ gam + lim.N[0] @ eps[0] + lim.N[1] @ eps[1]
    assert abs(work) <= 1e-9 * N.max() * scale * disc.n_joints
    v = lim.verification
    assert v["duality_gap"] < 1e-9 and v["incompatibility"] < 1e-9 and v["friction_excess"] <= FRICTION_TOL


def test_cannot_stand_with_friction_certificate():
    disc = disc_of(CircularArch.from_ratio(180.0, 0.15))
    lim = limit_analysis(disc, friction=0.3)
    assert lim.status == "cannot_stand" and lim.slides
    fx, fy = disc.load_vectors()
    gam, eps = disc.B_slide @ lim.u, (disc.B_open @ lim.u).reshape(2, -1)
    assert float(fy @ lim.u) < 0 and np.min(eps - 0.3 * np.abs(gam)) >= -1e-9 * np.abs(eps).max()


def test_friction_rows_are_the_coulomb_cone():
    st = statics(disc_of(PAPER, 20))
    R = joint_rows(st, 1, 0.5)
    x, lam = np.array([0.2, 0.3, 0.1]), 0.1
    g = st.forces(x, lam)
    r = R @ np.r_[x, lam, 1.0]
    J = g.shape[1]
    N = g[1] + g[2]
    assert np.allclose(r[:J], g[1]) and np.allclose(r[J:2 * J], g[2])
    assert np.allclose(r[2 * J:3 * J], (0.5 * N - g[0]) / 1.5) and np.allclose(r[3 * J:], (0.5 * N + g[0]) / 1.5)


@pytest.mark.parametrize("bad", [-0.1, float("nan"), float("inf"), "0.3", True])
def test_bad_friction_api(bad):
    with pytest.raises(InputError):
        limit_analysis(disc_of(PAPER, 20), friction=bad)
    with pytest.raises(InputError):
        minimum_thickness(PAPER, friction=bad)


def test_required_friction_reported():
    res = analyze(PAPER)
    d = res.to_dict()
    rf = d["required_friction"]
    assert d["friction"] is None and d["sliding_risk"] is None
    assert rf["limit"]["max"] == pytest.approx(res.limit.verification["max_shear_ratio"], rel=1e-12)
    assert rf["impact"]["max"] == pytest.approx(res.impact.verification["max_shear_ratio"], rel=1e-12)
    assert rf["limit"]["at_deg"] == 157.5 and rf["impact"]["at_deg"] == 0.0   # the springings
    flagged = analyze(PAPER, friction=0.48).to_dict()       # the limit state needs 0.489: the springing slides
    assert flagged["outcome"] == "sliding" and flagged["sliding_risk"] is True


def _cli_json(capsys, *argv):
    assert main(list(argv)) == 0
    out = capsys.readouterr().out

    def no_nan(c):
        raise ValueError(f"non-JSON constant {c}")
    return json.loads(out, parse_constant=no_nan)


def test_cli_analyze_friction_json(capsys):
    d = _cli_json(capsys, "analyze", "--friction", "0.3", "--json")
    assert d["friction"] == 0.3 and d["outcome"] == "sliding" and d["sliding_risk"] is True
    assert d["required_friction"]["limit"]["max"] == pytest.approx(0.3, rel=1e-9)
    assert d["required_friction"]["impact"]["max"] is None and d["required_friction"]["impact"]["reason"]
    assert [s["angle_deg"] for s in d["sliding_before"]] == [157.5]
    d = _cli_json(capsys, "analyze", "--friction", "0.6", "--json")
    assert d["outcome"] == "rocking" and d["sliding_risk"] is False
    assert d["required_friction"]["impact"]["above"] == []


def test_cli_analyze_friction_text(capsys):
    """Without friction the rocking limit state needs |S|/N = 0.4894 at the right springing (157.5
    deg): with mu = 0.47 below it the text says the associative mechanism slides there, with 0.50
    above it that the arch rocks."""
    assert main(["analyze", "--json"]) == 0
    need = json.loads(capsys.readouterr().out)["required_friction"]["limit"]
    assert 0.47 < need["max"] < 0.50 and need["at_deg"] == pytest.approx(157.5)
    assert main(["analyze", "--friction", "0.47"]) == 0
    out = capsys.readouterr().out
    assert re.search(r"outcome: SLIDING: the associative mechanism slides at 157\.50 deg", out), out
    assert main(["analyze", "--friction", "0.50"]) == 0
    out = capsys.readouterr().out
    assert "outcome: SLIDING" not in out and "r = K'/K" in out, out


def test_cli_impact_friction_json(capsys):
    d = _cli_json(capsys, "impact", "--voussoirs", "7", "--friction", "0.3", "--json")
    rf = d["required_friction"]
    assert set(rf) == {"limit", "impact", "impact_qp"} and d["sliding_risk"] is True
    assert rf["impact"]["max"] > 0.3 and rf["impact"]["above"]
    d = _cli_json(capsys, "impact", "--voussoirs", "7", "--json")
    assert d["friction"] is None and d["sliding_risk"] is None and d["required_friction"]["impact"]["max"] > 0


@pytest.mark.parametrize("bad", ["-1", "nan", "abc", "inf"])
@pytest.mark.parametrize("cmd", ["analyze", "impact"])
def test_cli_bad_friction(bad, cmd):
    p = fembeam(cmd, "--friction", bad)
    assert p.returncode == 2 and p.stdout == "" and len(p.stderr.strip().splitlines()) == 1
    assert "--friction" in p.stderr


# --- Cocchetti & Rizzi (2020): semicircle, radial joints, weight on the mid-curve ---------------------

HEYMAN = mass_on_midcurve(CircularArch.from_ratio(180.0, 0.15))


def test_mass_on_midcurve_moves_only_the_first_moment():
    arch = CircularArch.from_ratio(180.0, 0.3)
    h = mass_on_midcurve(arch)
    s = np.linspace(0, arch.length, 7)
    (m0, m1, m2), (h0, h1, h2) = arch.inertia_densities(s), h.inertia_densities(s)
    assert np.allclose(m0, h0) and np.allclose(m2, h2) and np.allclose(h1, arch.density * arch.thickness * arch.position(s))
    assert type(h.with_thickness_scaled(0.5)) is type(h) and h.with_thickness_scaled(0.5).t_over_r == 0.15


def test_cocchetti_rizzi_frictionless_and_true_centroids():
    t_h = minimum_thickness(HEYMAN, elements=200, tol=1e-10).t_over_R
    t_c = minimum_thickness(CircularArch.from_ratio(180, 0.15), elements=200, tol=1e-10).t_over_R
    assert t_h == pytest.approx(0.107426, abs=5e-7)          # Cocchetti & Rizzi
    assert t_c == pytest.approx(0.107478, abs=5e-7)          # true centroids (Milankovitch)
    # the same root, each bracketed to tol = 1e-10 (the root finder's points depend on the margins,
    # which the friction rows change, so the brackets need not coincide)
    assert minimum_thickness(HEYMAN, elements=200, tol=1e-10, friction=0.4).t_over_R == pytest.approx(t_h, rel=1e-10)


def test_cocchetti_rizzi_mixed_range_and_no_equilibrium_below():
    # mixed sliding-rotation range: the springing slides, so the thrust is h = (pi/2) mu
    th = minimum_thickness(HEYMAN, elements=200, tol=1e-10, friction=0.35)
    assert 0.107426 < th.t_over_R < 0.200637
    st = statics(disc_of(HEYMAN.with_thickness_scaled(th.scale), 200))
    stand, *_ = margin_search(st, 1, joint_rows(st, 1, 0.35), np.empty(0), np.empty(0, int), 1e-10, 50)
    g = section_forces(st, np.array([0.0, 0.5 * st.disc.curve.length]), stand.z[:3], 0.0)
    h = np.pi * (g[1, 1] + g[2, 1])                       # crown thrust in units of w r
    assert h == pytest.approx(0.5 * np.pi * 0.35, rel=1e-5)
    assert abs(g[0, 0]) == pytest.approx(0.35 * (g[1, 0] + g[2, 0]), rel=1e-6)   # the springing at its limit
    assert math.isinf(minimum_thickness(HEYMAN, elements=100, friction=0.30).scale)   # below mu = 0.309215
    assert math.isfinite(minimum_thickness(HEYMAN, elements=100, friction=0.31).scale)
