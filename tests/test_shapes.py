"""Arch shapes other than the circle: pointed, elliptical, parabolic, catenary, surveyed.

Frames against finite differences, arc lengths against closed forms and independent
quadrature, the circle recovered exactly as a limit, the pointed arch's crown kink in
meshes, inertia and joints, variable thickness, the reporting coordinate, the surveyed
spline and the command line."""
import json
import math
import subprocess
import sys

import numpy as np
import pytest
from scipy.integrate import quad
from scipy.special import ellipeinc

from fembeam import (CatenaryArch, CircularArch, EllipticalArch, InputError, Mechanism, ParabolicArch, PointedArch,
                     SurveyedArch, analyze, discretize, uniform_nodes)
from fembeam.cli import main
from fembeam.geometry.catenary import catenary_parameter

L, T = 10.0, 0.8


def _surveyed():
    u = np.linspace(0.0, np.pi, 40)            # a tall half-ellipse, surveyed at 40 points
    return SurveyedArch(-0.5 * L * np.cos(u), 7.0 * np.sin(u), thickness=T)


SHAPES = {
    "pointed": lambda: PointedArch(span=L, rise=6.0, thickness=T),
    "equilateral-haunched": lambda: PointedArch(span=L, rise=L * math.sqrt(3) / 2, thickness_springing=1.0,
                                                thickness_crown=0.5),
    "elliptical-flat": lambda: EllipticalArch(span=L, rise=3.0, thickness=T),
    "elliptical-tall": lambda: EllipticalArch(span=L, rise=7.0, thickness_springing=1.0, thickness_crown=0.6),
    "parabolic": lambda: ParabolicArch(span=L, rise=4.0, thickness=T),
    "catenary": lambda: CatenaryArch(span=L, rise=4.0, thickness_springing=0.9, thickness_crown=0.7),
    "surveyed": _surveyed,
}


@pytest.fixture(scope="module", params=list(SHAPES))
def arch(request):
    return SHAPES[request.param]()


def _away_from_kinks(a, s, h):
    """The sections ``s`` more than ``2 h`` from the kinks and outside the solid spans (inside
    a pointed arch's crown wedges the sections are a fan from the intrados meeting point,
    not the normal cuts of a curve parametrised by its arc length)."""
    ok = np.all([np.abs(s - k) > 2 * h for k in a.kinks], 0) if a.kinks else np.ones(s.shape, bool)
    for lo, hi in a.solid_spans:
        ok &= (s < lo - 2 * h) | (s > hi + 2 * h)
    return s[ok]


def test_frames_against_finite_differences(arch):
    """|t| = 1, n = (t_y, -t_x), dX/ds = t and dt/ds = kappa n (kappa > 0 towards n)."""
    a = arch
    h = 1e-5 * a.length
    s = _away_from_kinks(a, np.linspace(2 * h, a.length - 2 * h, 41), h)
    X, t, n, k = a.position(s), a.tangent(s), a.normal(s), a.curvature(s)
    assert np.max(np.abs(np.hypot(*t) - 1)) < 1e-14
    assert np.allclose(n, [t[1], -t[0]], atol=0, rtol=0)
    dX = (a.position(s + h) - a.position(s - h)) / (2 * h)
    dt = (a.tangent(s + h) - a.tangent(s - h)) / (2 * h)
    assert np.max(np.abs(dX - t)) < 1e-8
    assert np.max(np.abs(dt - k * n)) < 1e-6 * np.max(k)
    assert np.all(k > 0)                                 # convex arches: centre of curvature inside
    assert np.max(np.abs(a.position(np.array([0.0, a.length])) - [[-L / 2, L / 2], [0, 0]])) < 1e-13 * L


def test_arc_length_by_independent_quadrature(arch):
    """The arc length between sections equals the length of the polyline through many
    points in between (Richardson on two samplings): s is the arc length."""
    a = arch
    sa = np.linspace(0.0, a.length, 7)
    pieces = list(zip(sa[:-1], sa[1:]))
    if a.solid_spans:        # the arcs of a pointed arch (inside its crown wedges the sections are a fan)
        s_i = a.solid_spans[0][0]
        pieces = [(0.0, s_i / 3), (s_i / 3, s_i), (a.length - s_i, a.length)]
    for lo, hi in pieces:
        def chord(n):
            X = a.position(np.linspace(lo, hi, n + 1))
            return np.sum(np.hypot(*np.diff(X, axis=1)))
        assert (4 * chord(4000) - chord(2000)) / 3 == pytest.approx(hi - lo, rel=1e-12, abs=1e-12 * a.length)


def test_closed_form_lengths():
    a, b = 0.5 * L, 3.0
    # ellipse: s(u) = int_0^u sqrt(a^2 sin^2 + b^2 cos^2) = b E(u | 1 - a^2/b^2) (eccentric angle u)
    e = EllipticalArch(span=L, rise=b, thickness=T)
    u = np.linspace(0.0, np.pi, 13)
    s_exact = b * ellipeinc(u, 1.0 - (a / b) ** 2)
    assert e.length == pytest.approx(s_exact[-1], rel=1e-13)
    X = e.position(s_exact)
    assert np.max(np.abs(X - [-a * np.cos(u), b * np.sin(u)])) < 1e-13 * L
    assert np.max(np.abs(e.s_at_angle(e.angle_deg(s_exact)) - s_exact)) < 1e-12 * L
    # parabola y = H (1 - (2x/L)^2): L/2 sqrt(1 + q^2) + L/(2q) asinh(q), q = 4H/L
    H = 4.0
    q = 4 * H / L
    assert ParabolicArch(span=L, rise=H, thickness=T).length == pytest.approx(
        0.5 * L * math.sqrt(1 + q * q) + L / (2 * q) * math.asinh(q), rel=1e-14)
    # catenary: 2 c sinh(L / 2c), and the curve passes through the crown
    c = catenary_parameter(L, H)
    assert c * (math.cosh(L / (2 * c)) - 1) == pytest.approx(H, rel=1e-14)
    cat = CatenaryArch(span=L, rise=H, thickness=T)
    assert cat.length == pytest.approx(2 * c * math.sinh(L / (2 * c)), rel=1e-14)
    assert cat.position(0.5 * cat.length)[1] == pytest.approx(H, rel=1e-14)
    # an independent quadrature of sqrt(x'^2 + y'^2) on the parameter
    ref = quad(lambda x: math.sqrt(1 + (8 * H * x / L**2) ** 2), -L / 2, L / 2, epsabs=1e-15, epsrel=1e-13)[0]
    assert ParabolicArch(span=L, rise=H, thickness=T).length == pytest.approx(ref, rel=1e-13)


# ---------------------------------------------------------------------------- the circle as a limit
@pytest.fixture(scope="module")
def semicircles():
    circle = CircularArch(radius=L / 2, thickness=T, embrace_deg=180.0)
    return circle, PointedArch(span=L, rise=L / 2, thickness=T), EllipticalArch(span=L, rise=L / 2, thickness=T)


def test_limits_are_the_semicircle_pointwise(semicircles):
    c, p, e = semicircles
    assert p.kinks == () and p.length == c.length and e.length == pytest.approx(c.length, rel=1e-15)
    s = np.linspace(0.0, c.length, 401)
    nodes = uniform_nodes(c, 100)
    for a in (p, e):
        assert np.array_equal(uniform_nodes(a, 100), nodes) if a is p else np.allclose(uniform_nodes(a, 100), nodes)
        assert np.max(np.abs(a.position(s) - c.position(s))) < 1e-13 * L
        assert np.max(np.abs(a.tangent(s) - c.tangent(s))) < 1e-14
        assert np.max(np.abs(a.curvature(s) - c.curvature(s))) < 1e-14 / L
        assert np.max(np.abs(a.angle_deg(s) - c.angle_deg(s))) < 1e-12
        for x, y in zip(a.segment_inertia(nodes[:-1], nodes[1:]), c.segment_inertia(nodes[:-1], nodes[1:])):
            assert np.max(np.abs(x - y)) < 1e-12 * np.max(np.abs(y))


def test_limits_reproduce_the_semicircle_analysis(semicircles):
    """A_L and r of the semicircle recovered by the pointed (H = L/2) and elliptical
    (H = L/2) arches to 1e-9 (measured: A_L 1e-14, r 6e-12), the hinges to 1e-8 degrees
    (measured 1.7e-9: the hinges' Newton step ends at the noise floor of its central
    differences, ~1e-11 of the length, from starting points that differ with round-off)."""
    res = [analyze(a, elements=100) for a in semicircles]
    ref = res[0]
    assert ref.outcome == "rocking"
    for r in res[1:]:
        assert r.outcome == ref.outcome
        assert abs(r.A_L - ref.A_L) < 1e-9 * ref.A_L and abs(r.r - ref.r) < 1e-9 * ref.r
        for hs, hr in ((r.hinges_before, ref.hinges_before), (r.hinges_after, ref.hinges_after)):
            assert [h.side for h in hs] == [h.side for h in hr]
            assert np.allclose([h.angle_deg for h in hs], [h.angle_deg for h in hr], atol=1e-8, rtol=0)


# ---------------------------------------------------------------------------- the pointed crown
@pytest.fixture(scope="module")
def pointed():
    return PointedArch(span=L, rise=L * math.sqrt(3) / 2, thickness=T)     # equilateral: e/Rp = 1/2


def _crown(span, rise, t):
    """The crown of a pointed arch of constant thickness, from scratch: ``R``, ``e``, the
    polar angles (about the left centre) of the crown ``phi_c``, of the intrados and
    extrados meeting points ``phi_i``, ``phi_e``, and their heights ``y_i``, ``y_e``."""
    e, R = rise**2 / span - span / 4, rise**2 / span + span / 4
    a, b = R - t / 2, R + t / 2
    return dict(R=R, e=e, a=a, b=b, phi_c=math.atan2(rise, -e), phi_i=math.acos(-e / a), phi_e=math.acos(-e / b),
                y_i=math.sqrt(a * a - e * e), y_e=math.sqrt(b * b - e * e))


def test_pointed_geometry(pointed):
    """The crown joint is the vertical segment from where the intrados meet to where the
    extrados meet; the left arc's radial cuts are sections up to the one through the
    intrados meeting point; inside the crown wedges the sections are cuts from that point
    to the extrados."""
    p = pointed
    c = _crown(L, p.rise, T)
    Rp, e, half = p.radius, p.centre_offset, 0.5 * p.length
    assert e / Rp == pytest.approx(0.5, rel=1e-14) and Rp == pytest.approx(L, rel=1e-14)
    assert p.kinks == () and p.fixed_nodes == (half,)
    assert p.crown_joint == pytest.approx((c["y_i"], c["y_e"]), rel=1e-15)
    s_i = p.last_radial_section
    assert s_i == pytest.approx(Rp * (math.pi - c["phi_i"]), rel=1e-15)
    assert p.solid_spans == ((s_i, half), (half, p.length - s_i))
    # the crown joint: vertical, from (0, y_i) to (0, y_e), deeper than the thickness (~ t / sin phi_c)
    assert np.allclose(p.position(half), [0.0, 0.5 * (c["y_i"] + c["y_e"])], rtol=1e-15, atol=0)
    assert np.array_equal(p.tangent(half), [1.0, 0.0]) and np.array_equal(p.normal(half), [0.0, -1.0])
    assert float(p.thickness_at(half)) == pytest.approx(c["y_e"] - c["y_i"], rel=1e-14)
    assert float(p.thickness_at(half)) == pytest.approx(T / math.sin(c["phi_c"]), rel=2e-3)
    # the last radial section's intrados end is the crown joint's
    assert np.allclose(p.point(s_i, T / 2), [0.0, c["y_i"]], rtol=0, atol=1e-14 * L)
    # the arcs up to it: circles about (+-e, 0)
    s = np.linspace(0, s_i, 9)
    for sgn, ss in ((1, s), (-1, p.length - s)):
        X = p.position(ss)
        assert np.allclose(np.hypot(X[0] - sgn * e, X[1]), Rp, rtol=1e-14)
        assert np.allclose(p.thickness_at(ss), T, rtol=1e-15)
    # inside the wedges: cuts from (0, y_i) to the extrados circle, on their own side of the axis
    s = np.linspace(s_i, p.length - s_i, 13)
    h = 0.5 * p.thickness_at(s)
    assert np.allclose(p.point(s, h), [[0.0], [c["y_i"]]], rtol=0, atol=1e-14 * L)
    E = p.point(s, -h)
    left = s <= half
    assert np.allclose(np.hypot(E[0] - np.where(left, e, -e), E[1]), Rp + T / 2, rtol=1e-14)
    assert np.all(np.where(left, E[0] <= 1e-15 * L, E[0] >= -1e-15 * L))
    assert np.allclose(p.point(half, -0.5 * p.thickness_at(half)), [0.0, c["y_e"]], rtol=1e-15, atol=0)


def test_pointed_crown_is_a_node_of_every_mesh(pointed):
    """The crown joint is a node of every mesh; the nodes a crown wedge swallows are left out."""
    half = 0.5 * pointed.length
    for n in list(range(1, 40)) + [100, 101, 400, 999]:
        nodes = uniform_nodes(pointed, n)
        assert half in nodes and np.all(pointed.admissible(nodes))
        assert np.all(np.diff(nodes) > 0) and nodes[0] == 0.0 and nodes[-1] == pointed.length
        # the uniform nodes of each half, less those inside a wedge
        k = max(n, 2) // 2 + (max(n, 2) % 2)
        left = np.linspace(0.0, half, k + 1)
        right = np.linspace(half, pointed.length, max(n, 2) - k + 1)
        every = np.unique(np.concatenate([left, right]))
        assert np.allclose(nodes, every[pointed.admissible(every)], rtol=0, atol=1e-14 * L)
    # elements of 0.21 m: each wedge (0.24 m of the mid-curve) swallows one node
    nodes = uniform_nodes(pointed, 100)
    assert nodes.size == 101 - 2 and np.allclose(np.diff(nodes[:49]), pointed.length / 100, rtol=1e-13)
    assert uniform_nodes(pointed, 999).size == 1000 - 22          # elements of 0.021 m: 11 each
    with pytest.raises(InputError, match="crown wedge"):
        discretize(pointed, np.linspace(0.0, pointed.length, 999))


def _left_half_closed_form(span, rise, t, rho=1.0):
    """Mass, first moment and polar moment (about the origin) of the left half of a pointed
    arch as built: the annular sector between the springing and the last radial cut
    (polar angles phi_i..pi about (e, 0)), plus the crown wedge, which is the pie slice of
    the extrados disc between phi_e and phi_i less the triangle (centre, (0, y_i), (0, y_e))."""
    c = _crown(span, rise, t)
    e, a, b = c["e"], c["a"], c["b"]

    def sector(r0, r1, p0, p1):
        m = 0.5 * (r1 * r1 - r0 * r0) * (p1 - p0)
        k = (r1**3 - r0**3) / 3
        Sx, Sy = k * (math.sin(p1) - math.sin(p0)), k * (math.cos(p0) - math.cos(p1))   # about the centre
        J = (r1**4 - r0**4) / 4 * (p1 - p0)
        return m, np.array([Sx + m * e, Sy]), J + 2 * e * Sx + m * e * e

    m1, S1, J1 = sector(a, b, c["phi_i"], math.pi)
    m2, S2, J2 = sector(0.0, b, c["phi_e"], c["phi_i"])
    m3, S3, J3 = _polygon_moments(np.array([[e, 0.0, 0.0], [0.0, c["y_i"], c["y_e"]]]))    # clockwise: negative
    wedge = (m2 + m3, S2 + S3, J2 + J3)
    return tuple(rho * x for x in (m1 + m2 + m3, S1 + S2 + S3, J1 + J2 + J3)), tuple(rho * x for x in wedge)


def test_pointed_inertia_across_the_crown(pointed):
    """Across the crown = sum of the two sides (the Gauss rule never spans a break), and
    both equal the closed form of the half as built (sector, pie slice and triangle)."""
    p = pointed
    k = 0.5 * p.length
    whole = p.segment_inertia(0.0, p.length)
    left, right = p.segment_inertia(0.0, k), p.segment_inertia(k, p.length)
    for w, a, b in zip(whole, left, right):
        assert np.allclose(w, a + b, rtol=1e-14, atol=1e-14 * np.max(np.abs(w)))
    piece = p.segment_inertia(0.3 * p.length, 0.8 * p.length)
    parts = [p.segment_inertia(0.3 * p.length, k), p.segment_inertia(k, 0.8 * p.length)]
    for w, a, b in zip(piece, *parts):
        assert np.allclose(w, a + b, rtol=1e-14, atol=1e-14 * np.max(np.abs(w)))
    # reversed pieces are signed
    assert np.allclose(p.segment_inertia(0.8 * p.length, 0.3 * p.length)[0], -piece[0], rtol=1e-14)
    (m, S, J), (mw, Sw, Jw) = _left_half_closed_form(L, p.rise, T, p.density)
    assert left[0][0] == pytest.approx(m, rel=1e-14)
    assert left[1][0, 0] == pytest.approx(S[0], rel=1e-13) and left[1][1, 0] == pytest.approx(S[1], rel=1e-13)
    assert left[2][0] == pytest.approx(J, rel=1e-13)
    wedge = p.segment_inertia(p.last_radial_section, k)
    assert wedge[0][0] == pytest.approx(mw, rel=1e-12) and np.allclose(wedge[1][:, 0], Sw, rtol=1e-12)
    assert wedge[2][0] == pytest.approx(Jw, rel=1e-12)
    assert whole[1][0, 0] == pytest.approx(0.0, abs=1e-13 * abs(S[1]))
    assert whole[2][0] == pytest.approx(2 * J, rel=1e-13)


def test_pointed_crown_joint_is_the_vertical_cut(pointed):
    """Right half turning about the crown joint's extrados end (0, y_e): at the crown the
    extrados does not open, the intrados opens by omega (y_e - y_i) and nothing slides;
    rigid motions of the whole arch open nothing."""
    p = pointed
    disc = discretize(p, uniform_nodes(p, 40))
    k = 0.5 * p.length
    y_i, y_e = p.crown_joint
    j = int(np.flatnonzero(disc.joint_s == k)[0])
    J = disc.n_joints
    omega = 0.7
    d = disc.rigid(omega=omega, about=(0.0, y_e)).reshape(-1, 3)
    d[disc.frames["s"] < k] = 0.0
    d = d.ravel()
    op, sl = disc.B_open @ d, disc.B_slide @ d
    assert op[j] == pytest.approx(omega * (y_e - y_i), rel=1e-13)   # intrados
    assert abs(op[J + j]) < 1e-14 and abs(sl[j]) < 1e-14           # extrados, sliding
    # elsewhere nothing opens, but the right springing (the right half moves off its abutment)
    assert np.max(np.abs(np.delete(op, [j, J + j, J - 1, 2 * J - 1]))) < 1e-14
    r = disc.rigid(V=(0.3, -1.0), omega=0.4, about=(1.0, 2.0))
    interior = np.r_[1:J - 1, J + 1:2 * J - 1]
    assert np.max(np.abs((disc.B_open @ r)[interior])) < 1e-13 and np.max(np.abs((disc.B_slide @ r)[1:-1])) < 1e-13


def _radial_stereotomy_tmin(span, rise, n=100_000):
    """Minimum thickness (m) of a pointed arch under its own weight, independently: the left
    arc's radial sections from the springing to the one through the intrados meeting point
    (polar angles phi in [phi_i, pi] about (e, 0)) and the crown joint (x = 0, y_i <= y <=
    y_e), a symmetric state (horizontal thrust P at height yc on the crown joint).  The part
    between the crown joint and the section phi (crown wedge plus annular sector, area A,
    first moment Sx) is balanced by the section force (P, A), whose line crosses the
    section at radius r = (P yc - Sx + e A) / N, N = P sin phi - A cos phi; for a thickness
    t the thrust must lie inside every section for some (P, m = P yc): m between a convex
    and a concave piecewise-linear function of P, whose largest gap (a concave function of
    P, golden sections to round-off) must be >= 0."""
    from scipy.optimize import brentq

    def slack(t):
        c = _crown(span, rise, t)
        e, a, b = c["e"], c["a"], c["b"]
        phi = np.linspace(c["phi_i"], math.pi, n + 1)
        pie = 0.5 * b * b * (c["phi_i"] - c["phi_e"])                     # extrados disc, phi_e..phi_i
        pie_x = e * pie + b**3 / 3 * (math.sin(c["phi_i"]) - math.sin(c["phi_e"]))
        tri = 0.5 * e * (c["y_e"] - c["y_i"])                              # (e, 0), (0, y_i), (0, y_e)
        A = pie - tri + 0.5 * (b * b - a * a) * (phi - c["phi_i"])
        Sx = pie_x - tri * e / 3 + e * 0.5 * (b * b - a * a) * (phi - c["phi_i"]) \
            + (b**3 - a**3) / 3 * (np.sin(phi) - math.sin(c["phi_i"]))

        def gap(P):
            N = P * np.sin(phi) - A * np.cos(phi)
            lo = max(np.max(a * N + Sx - e * A), P * c["y_i"])
            hi = min(np.min(b * N + Sx - e * A), P * c["y_e"])
            return hi - lo
        g = 0.5 * (math.sqrt(5.0) - 1.0)
        lo, hi = 1e-6 * A[-1], 1e6 * A[-1]
        x1, x2 = hi - g * (hi - lo), lo + g * (hi - lo)
        f1, f2 = gap(x1), gap(x2)
        while hi - lo > 1e-15 * hi:
            if f1 < f2:
                lo, x1, f1 = x1, x2, f2
                x2 = lo + g * (hi - lo)
                f2 = gap(x2)
            else:
                hi, x2, f2 = x2, x1, f1
                x1 = hi - g * (hi - lo)
                f1 = gap(x1)
        return max(f1, f2) / A[-1]

    return brentq(slack, 0.01 * span, 0.2 * span, xtol=1e-13 * span, rtol=1e-14)


@pytest.mark.parametrize("rise", [6.0, L * math.sqrt(3) / 2])
def test_pointed_minimum_thickness_against_radial_stereotomy(rise):
    """The continuum's minimum thickness (every radial section up to the crown wedges, and
    the crown joint at its full depth) against an independent thrust-line computation on
    10^5 radial sections (measured: 2e-12 and 8e-11 relative; equilateral arch t_min =
    0.3997609 m)."""
    from fembeam import minimum_thickness

    ref = _radial_stereotomy_tmin(L, rise)
    got = minimum_thickness(PointedArch(span=L, rise=rise, thickness=0.3), elements=100, tol=1e-10)
    assert got.scale * 0.3 == pytest.approx(ref, rel=1e-9)


def test_pointed_hinge_at_the_crown_joint(pointed):
    """Thin equilateral arch: the incipient mechanism pivots on the crown joint's intrados
    end (reported at 90 deg), solved exactly, the same on any mesh; just below the minimum
    thickness the analysis says cannot_stand."""
    a = PointedArch(span=L, rise=L * math.sqrt(3) / 2, thickness=0.5)
    k = 0.5 * a.length
    res = [analyze(a, elements=n) for n in (100, 101, 37)]
    for r in res:
        assert r.outcome == "rocking" and r.continuum.exact_hinges
        assert r.verification["hinge_refinement_gap"] < 1e-10
        assert [h.side for h in r.hinges_before] == ["intrados", "extrados", "intrados", "extrados"]
        assert r.hinges_before[2].s == k and r.hinges_before[2].angle_deg == 90.0
        assert r.A_L == pytest.approx(res[0].A_L, rel=1e-10) and r.A_L == pytest.approx(r.A_L_lower, rel=1e-10)
    thin = analyze(PointedArch(span=L, rise=L * math.sqrt(3) / 2, thickness=0.39), elements=100)
    assert thin.outcome == "cannot_stand" and thin.thickness.scale * 0.39 == pytest.approx(0.3997609, rel=1e-5)


def test_nodes_through_keeps_kinks():
    from fembeam import nodes_through

    nodes = np.linspace(0.0, 10.0, 11)
    assert np.array_equal(nodes_through(nodes, [5.2]), np.r_[0:5, 5.2, 6:11])        # moves the node at 5
    assert np.array_equal(nodes_through(nodes, [5.2], keep=[5.0]), np.r_[0:6, 5.2, 6:11])  # inserts
    one_sided = np.nextafter(5.0, 0)
    out = nodes_through(nodes, [one_sided, 5.2], keep=[5.0])
    assert out.size == 13 and one_sided in out and 5.0 in out and 5.2 in out


@pytest.mark.parametrize("make", [
    lambda: PointedArch(span=L, rise=7.0, thickness=T),
    lambda: EllipticalArch(span=L, rise=3.0, thickness_springing=0.9, thickness_crown=0.5),
])
def test_mass_matrix_exact_when_elements_straddle_a_break(make):
    """Nodes not at the crown (kink or crown of the thickness law): the element across it
    still gets its exact mass, first and polar moments."""
    a = make()
    nodes = np.linspace(0.0, a.length, 16)            # 15 elements: the crown is inside the 8th
    disc = discretize(a, nodes)
    m, S, Jo = a.segment_inertia(0.0, a.length)
    ex, ey, rot = disc.rigid(V=(1.0, 0.0)), disc.rigid(V=(0.0, 1.0)), disc.rigid(omega=1.0)
    assert ex @ disc.M @ ex == pytest.approx(m[0], rel=1e-13) and ey @ disc.M @ ey == pytest.approx(m[0], rel=1e-13)
    assert ex @ disc.M @ rot == pytest.approx(-S[1, 0], rel=1e-12)
    assert ey @ disc.M @ rot == pytest.approx(S[0, 0], abs=1e-12 * m[0])
    assert rot @ disc.M @ rot == pytest.approx(Jo[0], rel=1e-12)


# ---------------------------------------------------------------------------- reporting coordinate
def test_reporting_coordinate_and_its_inverse(arch):
    a = arch
    s = np.linspace(0.0, a.length, 201)
    ang = a.angle_deg(s)
    assert ang[0] == 0.0 and np.all(np.diff(ang) > 0)
    # the clockwise rotation of the tangent from the left springing (below 180 degrees)
    t0, t = a.tangent(0.0), a.tangent(s)
    rot = np.degrees(np.arctan2(t0[1] * t[0] - t0[0] * t[1], t0 @ t))
    ok = ang < 170
    assert np.max(np.abs(ang[ok] - rot[ok])) < 1e-10
    back = a.s_at_angle(ang)
    assert np.max(np.abs(back - s)) < 1e-12 * a.length


def test_pointed_coordinate_through_the_crown(pointed):
    """The turning of the tangent: s/Rp on the left arc up to its last radial section
    (180 - phi_i deg), the fan inside the wedge (no section is reported there), 90 at the
    crown joint; sections inside a wedge are no hinges."""
    p = pointed
    k, s_i = 0.5 * p.length, p.last_radial_section
    c = _crown(L, p.rise, T)
    top = 180.0 - math.degrees(c["phi_i"])                # 58.6 deg: the rotation of the last radial cut
    assert float(p.angle_deg(k)) == 90.0
    assert float(p.angle_deg(s_i)) == pytest.approx(top, abs=1e-12)
    assert float(p.angle_deg(p.length - s_i)) == pytest.approx(180.0 - top, abs=1e-12)
    assert p.s_at_angle(90.0) == k and p.s_at_angle(top) == pytest.approx(s_i, rel=1e-15)
    s = np.linspace(s_i, p.length - s_i, 101)
    assert np.all(np.diff(p.angle_deg(s)) > 0)
    assert np.max(np.abs(p.s_at_angle(p.angle_deg(s)) - s)) < 1e-13 * L
    m = Mechanism.from_angles(p, [0.0, 40.0, 90.0, 180.0], ["intrados", "extrados", "intrados", "extrados"])
    assert m.s[2] == k and m.s[1] == pytest.approx(math.radians(40.0) * p.radius, rel=1e-14)
    assert m.s[3] == p.length
    m = Mechanism.from_angles(p, [0.0, 40.0, top, 180.0], ["intrados", "extrados", "intrados", "extrados"])
    assert m.s[2] == pytest.approx(s_i, rel=1e-15)
    with pytest.raises(InputError, match="inside a crown wedge"):
        Mechanism.from_angles(p, [0.0, 40.0, 75.0, 180.0], ["intrados", "extrados", "intrados", "extrados"])
    with pytest.raises(InputError, match=r"\[0, 180\]"):
        Mechanism.from_angles(p, [0.0, 40.0, 90.0, 181.0], ["intrados", "extrados", "intrados", "extrados"])


# ---------------------------------------------------------------------------- thickness
def _polygon_moments(P):
    """Area, first moments and polar moment about the origin of the simple polygon P (2, n)."""
    x, y = P
    x1, y1 = np.roll(x, -1), np.roll(y, -1)
    c = x * y1 - x1 * y
    A = 0.5 * np.sum(c)
    Sx = np.sum((x + x1) * c) / 6
    Sy = np.sum((y + y1) * c) / 6
    Ixx = np.sum((y * y + y * y1 + y1 * y1) * c) / 12
    Iyy = np.sum((x * x + x * x1 + x1 * x1) * c) / 12
    return A, np.array([Sx, Sy]), Ixx + Iyy


@pytest.mark.parametrize("make", [
    lambda: EllipticalArch(span=L, rise=3.0, thickness_springing=0.9, thickness_crown=0.5, density=2.5),
    lambda: CatenaryArch(span=L, rise=6.0, thickness_springing=0.5, thickness_crown=1.1, density=2.5),
    lambda: SurveyedArch(np.linspace(-5, 5, 30), 4 * (1 - (np.linspace(-5, 5, 30) / 5) ** 2),
                         t=0.6 + 0.3 * (np.linspace(-5, 5, 30) / 5) ** 2, density=2.5),
    lambda: PointedArch(span=L, rise=L * math.sqrt(3) / 2, thickness_springing=1.0, thickness_crown=0.5, density=2.5),
    lambda: PointedArch(span=L, rise=7.0, thickness_springing=0.5, thickness_crown=1.1, density=2.5),
])
def test_variable_thickness_inertia_against_the_region(make):
    """Mass, first and polar moments of the member against those of the polygon bounded
    by its intrados, extrados and end cuts (densely sampled; Richardson on two samplings).
    A pointed arch's outline runs along the intrados and extrados of its arcs (and of their
    continuation past the crown) to the crown joint's ends."""
    a = make()
    m, S, J = a.segment_inertia(0.0, a.length)

    def region(n):
        s = np.unique(np.concatenate([np.linspace(0, a.length, n + 1), a.breaks]))
        h = 0.5 * a.thickness_at(s)
        ext, intr = a.point(s, -h), a.point(s, h)
        return _polygon_moments(np.concatenate([ext, intr[:, ::-1]], axis=1))

    (A1, S1, J1), (A2, S2, J2) = region(4000), region(8000)
    A, Sr, Jr = (4 * A2 - A1) / 3, (4 * S2 - S1) / 3, (4 * J2 - J1) / 3
    rho = a.density
    assert m[0] == pytest.approx(rho * abs(A), rel=1e-10)
    assert np.allclose(S[:, 0], rho * np.sign(A) * Sr, rtol=1e-9, atol=1e-10 * abs(m[0]) * L)
    assert J[0] == pytest.approx(rho * np.sign(A) * Jr, rel=1e-9)
    # mass = rho int t ds exactly; the law at the springings and the crown
    if a._law is not None and not a._law.constant and not a.solid_spans:
        ts, tc = a._law.springing, a._law.crown
        assert m[0] == pytest.approx(rho * a.length * (ts + tc) / 2, rel=1e-14)
        assert np.allclose(a.thickness_at([0.0, a.length / 4, a.length / 2, a.length]),
                           [ts, (ts + tc) / 2, tc, ts], rtol=1e-14)
    # the mass matrix of any mesh carries the same mass
    disc = discretize(a, uniform_nodes(a, 25))
    e = disc.rigid(V=(1.0, 0.0))
    assert e @ disc.M @ e == pytest.approx(m[0], rel=1e-12)


def test_thickness_limits_and_scaling():
    e = EllipticalArch(span=L, rise=3.0, thickness=T)
    assert e.max_thickness_scale == pytest.approx(2 * 3.0**2 / (L / 2) / T, rel=1e-9)   # b^2/a at the springings
    p = ParabolicArch(span=L, rise=4.0, thickness=T)
    assert p.max_thickness_scale == pytest.approx(2 * L**2 / (8 * 4.0) / T, rel=1e-9)   # crown radius L^2/(8H)
    c = PointedArch(span=L, rise=6.0, thickness=T)
    assert c.max_thickness_scale == pytest.approx(L / T, rel=1e-14)                    # intrados arcs meet above y = 0
    f = 1.7
    v = EllipticalArch(span=L, rise=7.0, thickness_springing=1.0, thickness_crown=0.6)
    s = np.linspace(0, v.length, 11)
    assert np.allclose(v.with_thickness_scaled(f).thickness_at(s), f * v.thickness_at(s), rtol=1e-15)
    assert v.with_thickness_scaled(f).length == v.length
    with pytest.raises(InputError, match="twice the radius of curvature"):
        e.with_thickness_scaled(1.01 * e.max_thickness_scale)
    assert e.with_thickness_scaled(0.99 * e.max_thickness_scale).thickness == pytest.approx(0.99 * 3.6)
    assert e.with_thickness_scaled(e.min_thickness_scale).thickness == pytest.approx(5e-4 * L)


@pytest.mark.parametrize("kwargs, words", [
    (dict(span=L, rise=4.0, thickness=T), "rise >= span/2"),
    (dict(span=L, rise=6.0), "give a thickness"),
    (dict(span=L, rise=6.0, thickness=T, thickness_crown=0.5), "not both"),
    (dict(span=L, rise=6.0, thickness_springing=1.0), "both thickness_springing and thickness_crown"),
    (dict(span=-L, rise=6.0, thickness=T), "span"),
    (dict(span=L, rise=float("nan"), thickness=T), "rise"),
    (dict(span=L, rise=6.0, thickness=12.0), "twice the radius"),
    (dict(span=L, rise=6.0, thickness=1e-4), "at least 0.0005 of the span"),
])
def test_bad_shapes_say_what_is_allowed(kwargs, words):
    with pytest.raises(InputError, match=words.replace("(", r"\(").replace(")", r"\)")):
        PointedArch(**kwargs)


# ---------------------------------------------------------------------------- surveyed
def test_surveyed_parabola_reproduces_the_parabolic_arch(tmp_path):
    """50 points of the parabola, a quintic spline: analyze's A_L and r agree with
    ParabolicArch's to 1e-4 (measured ~3e-9 and ~4e-8)."""
    H = 4.0
    x = np.linspace(-L / 2, L / 2, 50)
    y = H * (1 - (2 * x / L) ** 2)
    f = tmp_path / "arch.csv"
    f.write_text("# surveyed\nx,y,t\n" + "".join(f"{a:.17g},{b:.17g},{T}\n" for a, b in zip(x, y)))
    s = SurveyedArch.from_csv(f)
    assert s.describe()["spline"] == "quintic" and s.describe()["points"] == 50
    assert s.length == pytest.approx(ParabolicArch(span=L, rise=H, thickness=T).length, rel=1e-9)
    rs = analyze(s, elements=100)
    rp = analyze(ParabolicArch(span=L, rise=H, thickness=T), elements=100)
    assert rs.outcome == rp.outcome == "rocking"
    assert abs(rs.A_L - rp.A_L) < 1e-4 * rp.A_L and abs(rs.r - rp.r) < 1e-4 * rp.r
    assert [h.side for h in rs.hinges_before] == [h.side for h in rp.hinges_before]
    assert np.allclose([h.angle_deg for h in rs.hinges_before], [h.angle_deg for h in rp.hinges_before], atol=1e-2)
    # the same points right to left, without a t column but with --thickness: the same member
    s2 = SurveyedArch(x[::-1], y[::-1], thickness=T)
    assert s2.x == s.x and s2.length == s.length


def test_surveyed_t_column_that_cannot_stand_gets_its_minimum_thickness():
    """A surveyed arch whose thickness is a t column and which cannot stand: the minimum
    thickness factor is found between the thinnest section the shape admits and its limit,
    and it equals that of the same member given by one constant thickness."""
    x = np.linspace(-5.0, 5.0, 21)
    y = 4.0 * (1 - (x / 5.0) ** 2)
    col = SurveyedArch(x, y, t=np.full(21, 0.05))
    const = SurveyedArch(x, y, thickness=0.05)
    assert col.min_thickness_scale == pytest.approx(const.min_thickness_scale, rel=1e-12)
    a, b = analyze(col, elements=60), analyze(const, elements=60)
    assert a.outcome == b.outcome == "cannot_stand"
    assert a.thickness.scale == pytest.approx(b.thickness.scale, rel=1e-5) and a.thickness.scale > 1.0


@pytest.mark.parametrize("x, y, kw, words", [
    ([0, 1, 2], [0, 1, 0], dict(thickness=0.1), "at least 4 points"),
    ([0, 1, 2, 3], [0, 1, float("nan"), 0], dict(thickness=0.1), "finite"),
    ([0, 1, 1, 3], [0, 1, 1, 0], dict(thickness=0.1), "points 2 and 3 coincide"),
    ([0, 1, 2, 3], [0, 1, 1], dict(thickness=0.1), "as many values"),
    ([0, 2, 2, 1, 1, 3], [0, 0, 1, 1, -1, 0], dict(thickness=0.1), "intersects itself"),
    ([0, 1, 2, 3], [0, 1, 1, 0], dict(t=[0.1, 0.1, -0.1, 0.1]), "t column must be positive"),
    ([0, 1, 2, 3], [0, 1, 1, 0], dict(t=[0.1] * 4, thickness=0.1), "given twice"),
    ([0, 1, 2, 3], [0, 1, 1, 0], {}, "give a thickness"),
    ([0, 0, 1, 0], [0, 1, 2, 3], dict(thickness=0.1), "apart horizontally"),
    ([0, 1, 0.9, 2, 3], [0, 1, 1.02, 1, 0], dict(thickness=0.1), "turns back"),
    ([0, 1, 2, 3], [0, 1, 2, 3.5], dict(thickness_springing=0.2, thickness_crown=0.1), "needs a crown"),
])
def test_surveyed_input_validation(x, y, kw, words):
    with pytest.raises(InputError, match=words):
        SurveyedArch(x, y, **kw)


def test_surveyed_csv_errors(tmp_path):
    f = tmp_path / "bad.csv"
    f.write_text("a,b\n1,2\n")
    with pytest.raises(InputError, match="header must name columns x and y"):
        SurveyedArch.from_csv(f, thickness=0.1)
    f.write_text("x,y\n0,0\n1,abc\n")
    with pytest.raises(InputError, match="line 3: expected a number"):
        SurveyedArch.from_csv(f, thickness=0.1)
    f.write_text("0,0\n1,1\n2,1.2\n3,1\n4,0\n")           # no header: x, y
    assert SurveyedArch.from_csv(f, thickness=0.2).describe()["spline"] == "cubic"
    with pytest.raises(InputError, match="cannot read"):
        SurveyedArch.from_csv(tmp_path / "missing.csv", thickness=0.1)


# ---------------------------------------------------------------------------- command line
def test_cli_pointed_json():
    p = subprocess.run([sys.executable, "-m", "fembeam.cli", "analyze", "--shape", "pointed", "--span", "10",
                        "--rise", "6", "--thickness", "0.8", "--json"], capture_output=True, text=True)
    assert p.returncode == 0, p.stderr
    out = json.loads(p.stdout)
    assert out["outcome"] == "rocking" and 0 < out["A_L"] < 1 and 0 < out["r"] < 1
    assert out["geometry"]["shape"] == "pointed" and out["geometry"]["rise"] == 6.0
    assert out["hinges_before"][-1]["angle_deg"] == 180.0


def test_cli_shapes_summary_and_midcurve(capsys, tmp_path):
    assert main(["analyze", "--shape", "elliptical", "--span", "10", "--rise", "4", "--thickness-springing", "0.9",
                 "--thickness-crown", "0.6", "--elements", "40"]) == 0
    first = capsys.readouterr().out.splitlines()[0]
    assert first == ("fembeam analyze: elliptical arch, span 10 m, rise 4 m, thickness 0.9 m at the springings "
                     "to 0.6 m at the crown")
    f = tmp_path / "m.csv"
    x = np.linspace(-5, 5, 20)
    f.write_text("x,y\n" + "".join(f"{a},{4 * (1 - (a / 5) ** 2)}\n" for a in x))
    assert main(["analyze", "--midcurve", str(f), "--thickness", "0.8", "--elements", "40", "--json"]) == 0
    out = json.loads(capsys.readouterr().out)
    assert out["geometry"]["shape"] == "surveyed" and out["outcome"] == "rocking"
    # the circle's header is unchanged
    assert main(["analyze", "--voussoirs", "7", "--embrace", "150"]) == 0
    first = capsys.readouterr().out.splitlines()[0]
    assert first == "fembeam analyze: circular arch, embrace 150 deg, t/R = 0.15, R = 1 m"


@pytest.mark.parametrize("args, words", [
    (["--span", "10"], "--span applies to --shape"),
    (["--shape", "circular", "--thickness", "0.3"], "--thickness applies to --shape"),
    (["--shape", "pointed", "--span", "10", "--thickness", "0.8"], "needs --rise"),
    (["--shape", "pointed", "--span", "10", "--rise", "6"], "needs --thickness T"),
    (["--shape", "pointed", "--span", "10", "--rise", "6", "--thickness", "1", "--thickness-crown", "1"], "not both"),
    (["--shape", "pointed", "--span", "10", "--rise", "6", "--thickness-crown", "1"], "go together"),
    (["--shape", "pointed", "--span", "10", "--rise", "4", "--thickness", "0.8"], "rise >= span/2"),
    (["--shape", "elliptical", "--span", "10", "--rise", "6", "--thickness", "1", "--embrace", "120"],
     "--embrace applies to the circular arch only"),
    (["--shape", "parabolic", "--span", "10", "--rise", "4", "--thickness", "1", "--radius", "3"], "--radius"),
    (["--midcurve", "x.csv", "--shape", "pointed"], "drop --shape"),
    (["--midcurve", "x.csv", "--rise", "3"], "--rise does not apply to --midcurve"),
    (["--midcurve", "/nonexistent/x.csv", "--thickness", "1"], "cannot read"),
])
def test_cli_bad_combinations_exit_2_with_one_line(capsys, args, words):
    assert main(["analyze", *args]) == 2
    io = capsys.readouterr()
    lines = io.err.strip().splitlines()
    assert len(lines) == 1 and words in lines[0] and io.out == ""


def test_cli_unknown_shape_is_an_argparse_error(capsys):
    with pytest.raises(SystemExit) as e:
        main(["analyze", "--shape", "gothic"])
    assert e.value.code == 2 and len(capsys.readouterr().err.strip().splitlines()) == 1
