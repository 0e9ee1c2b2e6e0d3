"""One mechanism type (fembeam.mechanisms): side table, Appendix A kinematics, DOFs and
hinges round trips, and the finite motion (four-bar linkage, rocking block)."""
import numpy as np
import pytest

from fembeam import CircularArch, StraightMember, analyze, discretize, nodes_through, uniform_nodes
from fembeam.errors import InputError
from fembeam.mechanisms import (EDGES, SIDES, Mechanism, find_hinges, pivot_sides, post_impact, side_from_text,
                                side_of)
from fembeam.simulation.bodies import Bodies

SIDES4 = ("intrados", "extrados", "intrados", "extrados")


@pytest.fixture(scope="module")
def arch():
    return CircularArch.from_ratio(157.5, 0.15)


@pytest.fixture(scope="module")
def mech(arch):
    """The incipient mechanism of the paper's arch (hinges of docs/four_hinge.md)."""
    return Mechanism.from_angles(arch, [1.5135, 59.2874, 117.0613, 157.5], SIDES4)


def block(tan_a, h=1.0):
    return StraightMember(height=2 * h, width=2 * tan_a * h)


def test_side_table():
    assert SIDES["intrados"].opposite.name == "extrados" and SIDES["extrados"].opposite.name == "intrados"
    for k in ("intrados", "extrados"):
        sd = side_of(k)
        assert sd.pivot == 0.5 * sd.code and sd.opening == -sd.code   # pivot on y = +-t/2, opens the far edge
    assert side_of("separated").code == 0
    with pytest.raises(InputError):
        side_of("middle")


def test_side_table_against_the_geometry(arch):
    """The table's numbers from the arch itself (R = 1, t = 0.15: intrados radius 0.925,
    extrados 1.075): the pivot offsets, the edge order of the simulation's joint corners, the
    side a joint pivots on when one edge opens, and the side names read from text."""
    s = np.linspace(0.0, arch.length, 5)
    for k, radius in (("intrados", 0.925), ("extrados", 1.075)):
        assert np.allclose(np.hypot(*arch.point(s, side_of(k).pivot * 0.15)), radius, rtol=0, atol=1e-14)
    assert EDGES == ("intrados", "extrados")
    corners = Bodies.from_curve(arch, 6).corners                      # (J, edge, xy)
    assert np.allclose(np.hypot(corners[:, 0, 0], corners[:, 0, 1]), 0.925, rtol=0, atol=1e-14)
    assert np.allclose(np.hypot(corners[:, 1, 0], corners[:, 1, 1]), 1.075, rtol=0, atol=1e-14)
    # an open extrados (eps- > 0) turns the joint about its intrados, and vice versa
    opened = pivot_sides(np.array([True, False, True]), np.array([False, True, True]))
    assert list(opened) == ["extrados", "intrados", "separated"]
    assert [side_of(k).initial for k in SIDES] == ["i", "e", "s"]
    assert [side_from_text(x) for x in ("i", " E ", "intrados", "Extrados")] == ["intrados", "extrados"] * 2
    for bad in ("s", "separated", "x", "", None):
        with pytest.raises(InputError):
            side_from_text(bad)


def test_appendix_a_centres_and_continuity(mech):
    """C3 is on lines C1-C13 and C2-C23; the field is continuous at the pivot points
    (the hinges turn about them), and zero at C1, C2."""
    om, C = mech.omegas()
    C1, C13, C23, C2 = mech.points().T
    C3 = C[:, 1]
    cross = lambda a, b: a[0] * b[1] - a[1] * b[0]   # noqa: E731
    assert abs(cross(C13 - C1, C3 - C1)) < 1e-12 and abs(cross(C23 - C2, C3 - C2)) < 1e-12
    assert np.allclose(C[:, [0, 2]], np.array([C1, C2]).T, atol=1e-15)
    y = mech.pivot_y()
    for i, s in enumerate(mech.s):
        k = mech.piece_of(np.array([s]))[0]
        left, right = mech.motion()[[k, k + 1]]
        X = mech.curve.point(np.array(s), y[i])
        vl = left[:2] + left[2] * np.array([-X[1], X[0]])
        vr = right[:2] + right[2] * np.array([-X[1], X[0]])
        assert np.max(np.abs(vl - vr)) < 1e-14
    assert mech.compatible_sign() == -1.0    # the incipient mechanism opens for alpha < 0
    assert np.allclose(mech.jumps(), [om[0], om[1] - om[0], om[2] - om[1], -om[2]], rtol=0, atol=1e-15)


def test_dofs_and_hinges_round_trip(mech):
    """Mechanism -> element DOFs -> find_hinges -> Mechanism: same hinges, sides and rate;
    the DOFs are compatible (no sliding, openings >= 0) and open only at the hinges."""
    c = mech.curve
    disc = discretize(c, nodes_through(uniform_nodes(c, 60), mech.s))
    d = mech.with_alpha(-0.7).dofs(disc)
    assert np.max(np.abs(disc.B_slide @ d)) < 1e-13
    assert np.min(disc.B_open @ d) > -1e-13
    hs = find_hinges(disc, d)
    assert [h.side for h in hs] == list(mech.sides)
    assert np.allclose([h.s for h in hs], mech.s, rtol=0, atol=1e-12)
    assert np.allclose([h.rotation for h in hs], [h.rotation for h in mech.with_alpha(-0.7).hinges()],
                       rtol=1e-12, atol=1e-14)
    back = Mechanism.from_dofs(disc, d)
    assert back.sides == mech.sides and np.allclose(back.s, mech.s, rtol=0, atol=1e-12)
    assert back.alpha == pytest.approx(-0.7, rel=1e-12)
    assert np.max(np.abs(back.dofs(disc) - d)) < 1e-12 * np.max(np.abs(d))


def test_from_dofs_of_the_limit_analysis():
    """The limit analysis's mechanism of a voussoir arch is a Mechanism, exactly."""
    res = analyze(CircularArch.from_ratio(157.5, 0.15), voussoirs=7)
    disc, u = res.limit.disc, res.limit.u
    m = Mechanism.from_dofs(disc, u)
    assert m.sides == tuple(h.side for h in res.hinges_before)
    assert np.max(np.abs(m.dofs(disc) - u)) < 1e-9 * np.max(np.abs(u))
    assert m.alpha * m.compatible_sign() > 0


def test_opposite_and_mirrored(arch, mech):
    assert mech.opposite().sides == ("extrados", "intrados", "extrados", "intrados")
    assert mech.opposite().opposite() == mech
    mi = mech.mirrored()
    assert np.allclose(mi.angles_deg(), 157.5 - mech.angles_deg()[::-1], atol=1e-12)
    assert mi.sides == mech.sides[::-1] and np.allclose(mi.mirrored().s, mech.s, rtol=0, atol=1e-15)
    # the mirror image of a mechanism opens for the mirrored load: same kinetic energy shape
    assert mi.compatible_sign() != 0
    b = Mechanism(block(0.3), (0.0,), ("intrados",))
    assert b.mirrored().sides == ("extrados",)


def test_bad_mechanisms(arch):
    with pytest.raises(InputError):
        Mechanism(arch, (0.0, 1.0, 2.0), ("intrados",) * 3)
    with pytest.raises(InputError):
        Mechanism(arch, (0.0, 2.0, 1.0, 2.7), SIDES4)
    with pytest.raises(InputError):
        Mechanism(arch, (0.0, 1.0, 2.0, 2.7), ("intrados", "separated", "intrados", "extrados"))
    with pytest.raises(InputError):
        Mechanism(block(0.3), (0.0, 1.0), ("intrados", "extrados"))


def _fd_velocity(m, s, y, h=1e-6):
    return (m.configuration(h).displace(s, y) - m.configuration(-h).displace(s, y)) / (2 * h)


@pytest.mark.parametrize("which", ["arch", "block"])
def test_configuration_derivative_is_the_velocity_field(which, mech):
    """d(config)/d theta at theta = 0 (central differences) = the unit velocity field."""
    m = mech if which == "arch" else Mechanism(block(0.4), (0.0,), ("intrados",))
    L = m.curve.length
    rng = np.random.default_rng(1)
    s = rng.uniform(0, L, 200)
    y = rng.uniform(-0.5, 0.5, 200) * m.curve.thickness_at(s)
    v = m.velocity(s, y)
    assert np.max(np.abs(_fd_velocity(m, s, y) - v)) < 1e-7 * np.max(np.abs(v))


@pytest.mark.parametrize("theta", [-0.02, -0.3, -1.0, -1.9, 0.03])
def test_four_bar_lengths_and_rigidity(mech, theta):
    """At a finite rotation the links keep their lengths, the pivot points are shared
    by neighbouring pieces and every piece moves rigidly (to 1e-12)."""
    cfg = mech.configuration(theta)
    assert not cfg.locked
    P0, P1 = mech.points(), cfg.hinge_points()
    for i, j in ((0, 1), (1, 2), (2, 3)):
        assert abs(np.linalg.norm(P1[:, j] - P1[:, i]) - np.linalg.norm(P0[:, j] - P0[:, i])) < 1e-12
    assert np.allclose(P1[:, [0, 3]], P0[:, [0, 3]], rtol=0, atol=1e-15)     # C1, C2 on the abutments
    y = mech.pivot_y()
    for i in (1, 2):           # C13 (pieces I, III) and C23 (III, II): one point for both pieces
        a = cfg.displace(mech.s[i], y[i], piece=i)
        b = cfg.displace(mech.s[i], y[i], piece=i + 1)
        assert np.max(np.abs(a - b)) < 1e-12
    assert cfg.rotation[1] == theta
    br = mech.breaks
    rng = np.random.default_rng(2)
    for k in range(5):
        s = rng.uniform(br[k], br[k + 1], 30)
        yy = rng.uniform(-0.075, 0.075, 30)
        X0, X1 = mech.curve.point(s, yy), cfg.displace(s, yy)
        D0 = np.linalg.norm(X0[:, :, None] - X0[:, None, :], axis=0)
        D1 = np.linalg.norm(X1[:, :, None] - X1[:, None, :], axis=0)
        assert np.max(np.abs(D1 - D0)) < 1e-12
        if k in (0, 4) and br[k + 1] > br[k]:
            assert np.max(np.abs(X1 - X0)) == 0.0     # the parts on the abutments stay


def test_four_bar_locks(mech):
    """Beyond a toggle position the loop cannot close: locked, with NaN positions. The
    paper's arch locks after ~0.055 rad in the closing sense and ~2.1 rad in the opening one."""
    for theta in (-2.5, 0.1, 3.0):
        cfg = mech.configuration(theta)
        assert cfg.locked and not cfg.opens
        assert np.all(np.isnan(cfg.displace(np.array([1.0]))))
    lo, hi = 0.0, 0.1                          # bisect the toggle in the closing sense
    for _ in range(60):
        mid = 0.5 * (lo + hi)
        lo, hi = (mid, hi) if not mech.configuration(mid).locked else (lo, mid)
    assert 0.04 < lo < 0.07
    P = mech.configuration(lo).hinge_points()
    C13, C23, C2 = P[:, 1], P[:, 2], P[:, 3]
    # at the toggle C13, C23 and C2 are aligned
    u, w = C23 - C2, C13 - C2
    assert abs(u[0] * w[1] - u[1] * w[0]) / (np.linalg.norm(u) * np.linalg.norm(w)) < 1e-6
    assert mech.configuration(-0.5).opens


def test_block_rotation_is_exact():
    """Housner's block of half-width b, half-height h on its right corner (b, 0): after
    turning by phi clockwise the centre is at (b - R sin(a - phi), R cos(a - phi))."""
    tan_a, h = 0.25, 1.5
    mb = Mechanism(block(tan_a, h), (0.0,), ("intrados",))
    b, R, a = tan_a * h, np.hypot(tan_a * h, h), np.arctan(tan_a)
    assert mb.compatible_sign() == -1.0                 # tips to the right: clockwise
    assert np.allclose(mb.points()[:, 0], [b, 0.0], atol=1e-15)
    for phi in (0.1, a, 1.0):
        cfg = mb.configuration(-phi)
        G = cfg.displace(np.array([h]), 0.0)[:, 0]
        assert np.allclose(G, [b - R * np.sin(a - phi), R * np.cos(a - phi)], rtol=0, atol=1e-14)
        corner = cfg.displace(np.array([2 * h]), -b)[:, 0]          # top left corner
        assert np.allclose(corner, [b - 2 * R * np.sin(a - phi), 2 * R * np.cos(a - phi)], rtol=0, atol=1e-14)
        assert cfg.opens and not cfg.locked
    G = mb.configuration(-a).displace(np.array([h]), 0.0)[:, 0]
    assert abs(G[0] - b) < 1e-15                                    # overturning: G above the pivot


@pytest.mark.parametrize("tan_a", [0.1, 0.3, 0.8, 1.4])
def test_block_impact_closed_form(tan_a):
    """Energy of the one-hinge mechanisms: rocking from the right corner onto the left one
    gives Housner's alpha'/alpha = 1 - 1.5 sin^2 a and r = (1 - 1.5 sin^2 a)^2."""
    blk = block(tan_a)
    pre = Mechanism(blk, (0.0,), ("intrados",)).closing()
    fig = post_impact(pre, pre.opposite())
    q = 1.0 - 1.5 * np.sin(np.arctan(tan_a)) ** 2
    assert fig.compatible
    assert fig.alpha_ratio == pytest.approx(q, rel=1e-12)
    assert fig.r == pytest.approx(q**2, rel=1e-12)


def test_the_cached_motion_is_never_exposed():
    """``motion`` is computed once per mechanism; what callers get (scalar or array sections)
    are copies: writing into them leaves the mechanism's motion unchanged."""
    import fembeam
    arch = fembeam.CircularArch(radius=1.0, thickness=0.15, embrace_deg=157.5)
    m = fembeam.Mechanism.from_angles(arch, [0.0, 52.5, 118.125, 157.5],
                                      ["intrados", "extrados", "intrados", "extrados"])
    before = m.motion()
    for got in (m.motion_at(1.5), m.motion_at(np.array([0.5, 1.5])), m.motion()):
        got[...] = 99.0
    assert np.array_equal(m.motion(), before) and m.motion_at(1.5).shape == (3,)
