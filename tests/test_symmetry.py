"""``is_symmetric``: the shapes fembeam builds from parameters are symmetric about a vertical axis
(with symmetric fill, masses, loads and cuts); a shifted load, an asymmetric mass, a surveyed
polyline, a thickness that grows from one side, an odd number of pieces around a crown joint are
not.  The check is against the geometry itself: the mirror image of sampled extrados and intrados
points, computed here, lies on the member."""
import numpy as np
import pytest

from fembeam.errors import InputError
from fembeam.fem import uniform_nodes
from fembeam.geometry import (CatenaryArch, CircularArch, EllipticalArch, Fill, ParabolicArch, PointedArch,
                              StraightMember, SurveyedArch, as_built)
from fembeam.geometry.asbuilt import span_of
from fembeam.geometry.symmetry import is_symmetric

ARCH = CircularArch.from_ratio(157.5, 0.15, radius=5.0)
SPAN = span_of(ARCH)[1]
XS = np.linspace(-3.0, 3.0, 15)
YS = 2.0 - 2.0 * (XS / 3.0) ** 2

SYMMETRIC = {
    "block": StraightMember(height=1.6, width=0.4),
    "circular": ARCH,
    "pointed": PointedArch(span=4.0, rise=3.0, thickness=0.3),
    "elliptical": EllipticalArch(span=4.0, rise=1.5, thickness=0.3),
    "parabolic, thickness from springing to crown": ParabolicArch(span=4.0, rise=1.2, thickness_springing=0.4,
                                                                  thickness_crown=0.25),
    "catenary": CatenaryArch(span=4.0, rise=1.5, thickness=0.3),
    "filled circular": as_built(ARCH, Fill(1800.0, 0.5)),
    "filled, masses at x and span - x": as_built(ARCH, Fill(1800.0, 0.5), [(1.0, 500.0), (SPAN - 1.0, 500.0),
                                                                           (SPAN / 2, 80.0)]),
    "surveyed points of a symmetric parabola": SurveyedArch(XS, YS, thickness=0.3),
}


def mirror_on_member(curve, n=41) -> bool:
    """Independent route: the mirror images of extrados and intrados points at ``n`` sections lie
    at the same distance from the mid-curve's nearest point as the originals (the member's
    outline is mapped onto itself)."""
    L = curve.length
    s = np.linspace(0.0, L, n)
    X, nrm, t = curve.position(s), curve.normal(s), np.asarray(curve.thickness_at(s), float) * np.ones(n)
    axis = 0.5 * (X[0, 0] + X[0, -1])
    fine = np.linspace(0.0, L, 20001)
    F = curve.position(fine)
    for side in (-0.5, 0.5):
        P = X + side * t * nrm
        M = np.array([2 * axis - P[0], P[1]])
        d = np.hypot(M[0][:, None] - F[0][None, :], M[1][:, None] - F[1][None, :])
        j = np.argmin(d, axis=1)
        tj = np.asarray(curve.thickness_at(fine[j]), float)
        if not np.allclose(d[np.arange(n), j], 0.5 * tj, atol=2e-4 * L):
            return False
    return True


@pytest.mark.parametrize("name", list(SYMMETRIC))
def test_symmetric_shapes(name):
    curve = SYMMETRIC[name]
    assert is_symmetric(curve)
    assert is_symmetric(curve, nodes=uniform_nodes(curve, 8))
    if not isinstance(curve, StraightMember):
        assert mirror_on_member(curve)


def test_symmetric_and_shifted_live_loads():
    assert is_symmetric(ARCH, loads=[(SPAN / 2, 10.0)])
    assert is_symmetric(ARCH, loads=[(1.0, 10.0), (SPAN - 1.0, 10.0)])
    assert not is_symmetric(ARCH, loads=[(SPAN / 2 + 0.01, 10.0)])
    assert not is_symmetric(ARCH, loads=[(1.0, 10.0), (SPAN - 1.0, 10.5)])
    from fembeam.analysis.loads import PointLoads
    assert not is_symmetric(ARCH, loads=PointLoads.of(ARCH, [(1.0, 10.0)]))
    assert not is_symmetric(StraightMember(height=1.6, width=0.4), loads=[(0.0, 1.0)])


ASYMMETRIC = {
    "one point mass": as_built(ARCH, None, [(1.0, 500.0)]),
    "masses of different weight": as_built(ARCH, Fill(1800.0, 0.5), [(1.0, 500.0), (SPAN - 1.0, 400.0)]),
    "a mass 1 mm off its mirror": as_built(ARCH, None, [(1.0, 500.0), (SPAN - 1.001, 500.0)]),
    "surveyed polyline": SurveyedArch(XS, YS + 0.01 * np.sin(XS), thickness=0.3),
    "surveyed, thickness column": SurveyedArch(XS, YS, t=tuple(0.3 + 0.01 * XS / 3.0)),
}


@pytest.mark.parametrize("name", list(ASYMMETRIC))
def test_asymmetric_members(name):
    curve = ASYMMETRIC[name]
    assert not is_symmetric(curve)
    if name.startswith("surveyed"):
        assert not mirror_on_member(curve)            # the shape itself is not its mirror image


def test_mesh_with_one_more_piece_on_one_side():
    """A pointed arch's crown joint is a node of every mesh: 7 pieces put 4 on the left."""
    arch = PointedArch(span=4.0, rise=3.0, thickness=0.3)
    assert is_symmetric(arch, nodes=uniform_nodes(arch, 8))
    assert not is_symmetric(arch, nodes=uniform_nodes(arch, 7))


def test_refuses_what_is_not_a_member():
    with pytest.raises(InputError, match="needs a member"):
        is_symmetric("arch")
    with pytest.raises(InputError, match="tolerance"):
        is_symmetric(ARCH, tol=0.0)
