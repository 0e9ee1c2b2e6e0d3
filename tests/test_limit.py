"""Equivalent static analysis: A_L, mechanism, thrust line (paper Sect. 6)."""
import numpy as np
import pytest

from fembeam import CannotStandError, CircularArch, analyze, discretize, limit_analysis, minimum_thickness, uniform_nodes
from fembeam.analysis import THRESHOLDS
from fembeam.mechanisms import side_of


def test_paper_continuous_A_L(paper_result):
    """Paper Sect. 6.2: A_L = 0.353 g; the continuum value 0.3533839, bracketed to 1e-11."""
    assert paper_result.A_L == pytest.approx(0.3533839, abs=5e-8)
    assert paper_result.A_L - paper_result.A_L_lower < 1e-11
    before = [(round(h.angle_deg, 3), h.side) for h in paper_result.hinges_before]
    assert before == [(1.514, "intrados"), (59.287, "extrados"), (117.061, "intrados"), (157.5, "extrados")]


@pytest.mark.parametrize("beta, A_L", [(150.0, 0.444), (157.5, 0.370)])
def test_oppenheim_A_L(beta, A_L):
    r = analyze(CircularArch.from_ratio(beta, 0.15, radius=10.0), voussoirs=7)
    assert r.A_L == pytest.approx(A_L, abs=0.001)
    assert len(r.hinges_before) == 4


def test_refined_A_L_is_mesh_independent_and_below_the_mesh_LP(paper_arch):
    """A_L is a minimum over mechanisms: the uniform-mesh LP is above the continuous
    optimum and converges to it at second order; the refined value does not move."""
    res = [analyze(paper_arch, elements=n) for n in (50, 100, 200, 400)]
    refined = np.array([r.A_L for r in res])
    mesh = np.array([r.A_L_mesh for r in res])
    assert np.ptp(refined) < 1e-10
    err = mesh - refined[-1]
    assert np.all(err > 0)
    rate = np.polyfit(np.log([50, 100, 200, 400]), np.log(err), 1)[0]
    assert rate < -1.5


def test_milankovitch_minimum_thickness():
    assert minimum_thickness(CircularArch.from_ratio(180.0, 0.2)).t_over_R == pytest.approx(0.1075, abs=5e-4)


def test_thrust_line_from_duals_is_admissible_and_through_hinges(paper_arch):
    disc = discretize(paper_arch, uniform_nodes(paper_arch, 100))
    lim = limit_analysis(disc)
    for k in ("equilibrium_residual", "thrust_line_outside", "max_tensile_force", "complementarity"):
        assert lim.verification[k] <= THRESHOLDS[k]
    t = disc.joint_thickness
    e = lim.eccentricity
    assert np.all(np.abs(e) <= 0.5 * t * (1 + 1e-9))
    for h in lim.hinges:  # the thrust line touches the edge the hinge pivots on
        j = h.joints[0]
        assert e[j] == pytest.approx(side_of(h.side).pivot * t[j], rel=1e-8)


@pytest.mark.parametrize("beta, tr", [(100, 0.1), (157.5, 0.15), (180, 0.2)])
def test_independent_of_radius_and_mirrored_by_direction(beta, tr):
    a = analyze(CircularArch.from_ratio(beta, tr, radius=1.0), elements=60)
    b = analyze(CircularArch.from_ratio(beta, tr, radius=37.0, density=2400.0), elements=60)
    m = analyze(CircularArch.from_ratio(beta, tr), elements=60, direction=-1)
    assert b.A_L == pytest.approx(a.A_L, rel=1e-9) and b.r == pytest.approx(a.r, rel=1e-9)
    assert m.A_L == pytest.approx(a.A_L, rel=1e-9) and m.r == pytest.approx(a.r, rel=1e-9)
    for h, hm in zip(a.hinges_before, m.hinges_before[::-1]):
        assert hm.angle_deg == pytest.approx(beta - h.angle_deg, abs=1e-8) and hm.side == h.side
    for h, hm in zip(a.hinges_after, m.hinges_after[::-1]):
        assert hm.angle_deg == pytest.approx(beta - h.angle_deg, abs=1e-8) and hm.side == h.side


def test_too_thin_and_too_thick_are_outcomes():
    thin = analyze(CircularArch.from_ratio(180, 0.08), elements=60)
    assert thin.outcome == "cannot_stand" and thin.t_min_over_R == pytest.approx(0.1075, abs=1e-3)
    flat = analyze(CircularArch.from_ratio(60, 0.2), elements=60)  # a straight strut fits inside
    assert flat.outcome == "no_mechanism"


def test_strict_limit_analysis_names_the_problem():
    c = CircularArch.from_ratio(180, 0.08)
    with pytest.raises(CannotStandError, match="cannot stand under its own weight"):
        limit_analysis(discretize(c, uniform_nodes(c, 40)), strict=True)


def test_nearly_locked_arch_is_an_outcome_not_a_solver_failure():
    """80 deg, t/R 0.28: a straight strut almost fits inside the thickness; the certificate
    is an admissible ray of self-stress plus horizontal load."""
    res = analyze(CircularArch.from_ratio(80, 0.28), elements=200)
    assert res.outcome == "no_mechanism"


def test_nearly_closed_ring_cannot_stand_at_any_thickness():
    """350 deg: no t/R below 2 lets such a ring stand on its springings."""
    res = analyze(CircularArch.from_ratio(350, 0.005), elements=60)
    assert res.outcome == "cannot_stand" and res.t_min_over_R == float("inf")
    assert res.to_dict()["t_min_over_R"] is None
    assert minimum_thickness(CircularArch.from_ratio(300.0, 0.5), elements=60, tol=1e-3).t_over_R == pytest.approx(1.18, abs=0.02)
