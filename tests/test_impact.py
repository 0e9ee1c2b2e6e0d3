"""Impact QP: r, post-impact field, impulses (paper Sect. 5-6, Appendix B)."""
import numpy as np
import pytest

from fembeam import CircularArch, StraightMember, analyze, discretize, impact, limit_analysis, uniform_nodes
from fembeam.analysis import THRESHOLDS


def test_paper_continuous_r(paper_result):
    """Paper Sect. 6.2 (r = 0.606): 0.606517 on 200 elements with nodes at the continuum hinges."""
    assert paper_result.outcome == "rocking"
    assert paper_result.r == pytest.approx(0.606517, abs=1e-6)
    after = [(round(h.angle_deg, 2), h.side) for h in paper_result.hinges_after]
    assert after == [(0.0, "extrados"), (49.92, "intrados"), (111.40, "extrados"), (157.5, "intrados")]


def test_verification_figures_small(paper_result):
    v = paper_result.verification["impact"]
    for k, x in v.items():
        if k in THRESHOLDS:
            assert x <= THRESHOLDS[k], k


@pytest.mark.parametrize("b_over_h", [0.05, 0.15, 0.3, 0.6, 1.0, 1.3])
def test_housner_block(b_over_h):
    """Single block rocking on a rigid base: r = (1 - 1.5 sin^2 a)^2, tan a = b/h."""
    res = analyze(StraightMember(height=2.0, width=2.0 * b_over_h), voussoirs=1)
    a = np.arctan(b_over_h)
    assert res.A_L == pytest.approx(np.tan(a), rel=1e-10)
    assert res.r == pytest.approx((1 - 1.5 * np.sin(a) ** 2) ** 2, abs=1e-8)
    assert [h.side for h in res.hinges_before] == ["intrados"] and [h.side for h in res.hinges_after] == ["extrados"]


def test_stocky_block_stops_dead():
    """tan a > sqrt(2): Housner's alpha' changes sign; no compatible motion does work."""
    res = analyze(StraightMember(height=1.0, width=2.0), voussoirs=1)
    assert res.outcome == "arrested" and res.r == 0.0


def test_thick_shallow_arch_is_arrested():
    res = analyze(CircularArch.from_ratio(80, 0.15), elements=60)
    assert res.outcome == "arrested" and res.r == 0.0 and res.A_L > 0


@pytest.fixture(scope="module")
def setup():
    c = CircularArch.from_ratio(140, 0.12)
    disc = discretize(c, uniform_nodes(c, 80))
    return disc, -limit_analysis(disc).u


def test_backends_agree_on_primal_and_dual(setup):
    disc, d0 = setup
    a, b = impact(disc, d0, backend="clarabel"), impact(disc, d0, backend="osqp")
    scale_mu = np.abs(a.mu).max()
    assert b.r == pytest.approx(a.r, abs=1e-8)
    assert np.abs(a.d - b.d).max() < 1e-6 * np.abs(a.d).max()
    assert np.abs(a.mu - b.mu).max() < 1e-5 * scale_mu
    assert np.abs(a.lam - b.lam).max() < 1e-5 * scale_mu


def test_energy_maximisation_form_gives_the_same_r(setup):
    """The W = 1 form: min e^T M e s.t. compatibility and (M d0)^T e = 1 (the W = 1 form of
    (B.7), with the dense virtual-work row) gives r = 1 / (Q_min 2K) and d' = e / Q_min."""
    import scipy.sparse as sp

    from fembeam.analysis.qp import solve_qp

    disc, d0 = setup
    proj = impact(disc, d0)
    M, p0 = disc.M, disc.M @ d0
    A_eq = sp.vstack([disc.B_slide, sp.csr_matrix(p0[None, :])]).tocsr()
    b_eq = np.zeros(A_eq.shape[0])
    b_eq[-1] = 1.0
    sol = solve_qp(M.tocsc(), np.zeros(M.shape[0]), A_eq, disc.B_open, b_eq=b_eq, tol=1e-12)
    Q = sol.x @ M @ sol.x
    assert 1.0 / (Q * (d0 @ p0)) == pytest.approx(proj.r, rel=1e-7)
    assert np.allclose(sol.x / Q, proj.d, atol=1e-6 * np.abs(proj.d).max())
    # its multipliers, scaled by 1/Q_min, are the same impulses
    assert np.allclose(sol.mu / Q, proj.mu.ravel(), atol=1e-5 * np.abs(proj.mu).max())


def test_r_bounded_and_positive_A_L_over_the_range():
    """r <= 1 (Remark 1) and A_L > 0 from just above the minimum thickness to t/R = 0.4."""
    for beta in (60, 90, 120, 150, 180):
        from fembeam import minimum_thickness

        tmin = minimum_thickness(CircularArch.from_ratio(beta, 0.3), elements=60, tol=1e-4).t_over_R
        for tr in np.linspace(tmin * 1.05, 0.4, 4):
            res = analyze(CircularArch.from_ratio(beta, tr), elements=60)
            assert res.outcome in ("rocking", "arrested", "no_mechanism"), (beta, tr, res.outcome)
            if res.outcome != "no_mechanism":
                assert res.A_L > 0 and 0.0 <= res.r <= 1.0
