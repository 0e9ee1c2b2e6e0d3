"""Housner's rocking block as the one-joint special case of the general machinery."""
import numpy as np
import pytest

from fembeam import StraightMember, analyze


def housner_r(tan_a: float) -> float:
    a = np.arctan(tan_a)
    return (1.0 - 1.5 * np.sin(a) ** 2) ** 2


@pytest.mark.parametrize("tan_a", [0.05, 0.1, 0.2, 0.35, 0.5, 0.8, 1.0, 1.2, 1.4])
def test_slender_block_restitution(tan_a):
    """r = (1 - 1.5 sin^2 a)^2, A_L = tan a, rocking onto the opposite corner."""
    h = 1.0
    res = analyze(StraightMember(height=2 * h, width=2 * tan_a * h), voussoirs=1)
    assert res.outcome == "rocking"
    assert abs(res.r - housner_r(tan_a)) < 1e-6
    assert abs(res.A_L - tan_a) < 1e-9
    # pivots on the right corner ("intrados" face) before, on the left one after
    assert [h_.side for h_ in res.hinges_before] == ["intrados"]
    assert [h_.side for h_ in res.hinges_after] == ["extrados"]
    # post/pre angular velocity = 1 - 1.5 sin^2 a (conservation of angular momentum about C')
    omega0, omega1 = res.impact.d0[2], res.impact.d[2]
    a = np.arctan(tan_a)
    assert abs(omega1 / omega0 - (1 - 1.5 * np.sin(a) ** 2)) < 1e-6


@pytest.mark.parametrize("size", [0.01, 1.0, 30.0])
def test_block_size_does_not_matter(size):
    """r depends on the slenderness only (Housner's model has no size effect at impact)."""
    res = analyze(StraightMember(height=2 * size, width=0.6 * size, density=2400.0), voussoirs=1)
    assert abs(res.r - housner_r(0.3)) < 1e-6


@pytest.mark.parametrize("tan_a", [1.4143, 1.5, 2.0, 3.0, 10.0])
def test_stocky_block_stops_dead(tan_a):
    """tan a > sqrt 2: alpha' = (1 - 1.5 sin^2 a) alpha would rotate the block about C'
    in the closing sense (not compatible); no compatible motion does positive work, so
    the energy principle gives K' = 0: the block stops at the first impact (r = 0, not
    the squared formula's positive value)."""
    assert 1.0 - 1.5 * np.sin(np.arctan(tan_a)) ** 2 < 0     # Housner's alpha'/alpha
    res = analyze(StraightMember(height=2.0, width=2.0 * tan_a), voussoirs=1)
    assert res.outcome == "arrested"
    assert res.r == 0.0
    assert res.hinges_after == []
    assert np.max(np.abs(res.impact.d)) < 1e-6 * np.max(np.abs(res.impact.d0))


def test_mirrored_load_gives_the_same_r():
    res_p = analyze(StraightMember(height=2.0, width=0.5), voussoirs=1, direction=1)
    res_m = analyze(StraightMember(height=2.0, width=0.5), voussoirs=1, direction=-1)
    assert abs(res_p.r - res_m.r) < 1e-9
    assert [h.side for h in res_m.hinges_before] == ["extrados"]


def test_qp_fields_are_one_hinge_mechanisms():
    """The QP's pre- and post-impact fields are the block rocking on one corner
    (fembeam.mechanisms.Mechanism with one hinge), with Housner's ratio of the rates."""
    from fembeam.mechanisms import Mechanism

    tan_a = 0.3
    res = analyze(StraightMember(height=2.0, width=2.0 * tan_a), voussoirs=1)
    disc = res.impact.disc
    u = Mechanism.from_dofs(disc, -res.impact.d0)          # the block arrives along -u (closing)
    pre, post = u.with_alpha(-u.alpha), Mechanism.from_dofs(disc, res.impact.d)
    assert pre.sides == ("intrados",) and post == Mechanism(pre.curve, (0.0,), ("extrados",), post.alpha)
    assert np.max(np.abs(pre.dofs(disc) - res.impact.d0)) < 1e-12 * np.max(np.abs(res.impact.d0))
    assert np.max(np.abs(post.dofs(disc) - res.impact.d)) < 1e-9 * np.max(np.abs(res.impact.d))
    assert abs(post.alpha / pre.alpha - (1 - 1.5 * np.sin(np.arctan(tan_a)) ** 2)) < 1e-6
