import math
import re

import numpy as np
import pytest

from fembeam import CircularArch, InputError, StraightMember


@pytest.mark.parametrize("kwargs, words", [
    (dict(embrace_deg=157.5, t_over_r=-0.1), "t/R"),
    (dict(embrace_deg=157.5, t_over_r=0.0), "t/R"),
    (dict(embrace_deg=157.5, t_over_r=2.0), "in [0.001, 2)"), (dict(embrace_deg=157.5, t_over_r=1e-4), "in [0.001, 2)"),
    (dict(embrace_deg=0.0, t_over_r=0.1), "embrace"),
    (dict(embrace_deg=360.0, t_over_r=0.1), "(0, 360)"),
    (dict(embrace_deg=float("nan"), t_over_r=0.1), "embrace"),
    (dict(embrace_deg=120, t_over_r=0.1, radius=-1), "radius"),
])
def test_bad_input_says_what_is_allowed(kwargs, words):
    with pytest.raises(InputError, match=re.escape(words)):
        CircularArch.from_ratio(**kwargs)


def test_frame_conventions():
    c = CircularArch.from_ratio(180.0, 0.2, radius=2.0)
    s = np.linspace(0, c.length, 7)
    X, t, n = c.position(s), c.tangent(s), c.normal(s)
    assert np.allclose(X[:, 0], [-2.0, 0.0]) and np.allclose(X[:, -1], [2.0, 0.0])
    assert np.allclose(np.sum(t * t, 0), 1.0) and np.allclose(np.sum(t * n, 0), 0.0)
    assert np.allclose(n, -X / 2.0)  # n points to the centre (inward)
    # tangent is dX/ds (finite differences)
    h = 1e-6
    assert np.allclose((c.position(s + h) - c.position(s - h)) / (2 * h), t, atol=1e-8)
    assert np.allclose(c.angle_deg(s), np.linspace(0, 180, 7))


def test_segment_inertia_of_annular_sector():
    """Exact mass, first moment and polar moment of an annular sector."""
    R, t, beta, rho = 3.0, 0.6, math.radians(140), 2.5
    c = CircularArch(radius=R, thickness=t, embrace_deg=140, density=rho)
    m, S, J = c.segment_inertia(0.0, c.length)
    a, b = R - t / 2, R + t / 2
    assert m[0] == pytest.approx(rho * 0.5 * (b**2 - a**2) * beta, rel=1e-13)
    yG = rho * (b**3 - a**3) / 3 * 2 * math.sin(beta / 2)  # symmetric about the y axis
    assert S[0, 0] == pytest.approx(0.0, abs=1e-12) and S[1, 0] == pytest.approx(yG, rel=1e-13)
    assert J[0] == pytest.approx(rho * (b**4 - a**4) / 4 * beta, rel=1e-13)


def test_straight_member():
    b = StraightMember(height=2.0, width=0.4)
    assert b.length == 2.0 and b.ends == ("joint", "free")
    with pytest.raises(InputError):
        StraightMember(height=-1.0)


def test_circular_segment_inertia_in_closed_form_equals_gauss():
    """The circle's segment integrals in closed form equal the generic Gauss rule on the
    densities to round-off, for long, short, tiny and reversed pieces and each power."""
    import numpy as np
    from fembeam import CircularArch
    from fembeam.geometry.base import MidCurve

    c = CircularArch(radius=2.0, thickness=0.3, embrace_deg=157.5, density=1.7)
    rng = np.random.default_rng(1)
    sa = rng.uniform(0, c.length, 2000)
    sb = np.clip(sa + rng.normal(0, 0.5, sa.size) * rng.choice([1, 1e-4, 1e-8, 1e-13], sa.size), 0, c.length)
    for power in (None, 1, 3):
        got, ref = c.segment_inertia(sa, sb, power=power), MidCurve._smooth_inertia(c, sa, sb, 24, power)
        for x, y in zip(got, ref):
            err = np.abs(x - y).reshape(-1, sa.size).max(0) / np.maximum(np.abs(y).reshape(-1, sa.size).max(0), 1e-300)
            assert err.max() < 1e-14
