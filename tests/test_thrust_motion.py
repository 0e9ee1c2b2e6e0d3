"""Dynamic thrust line of a moving mechanism (fembeam.dynamics.thrust)."""
import numpy as np
import pytest

import fembeam
from fembeam.dynamics.equation import EquationOfMotion
from fembeam.dynamics.thrust import section_forces, thrust_line_margin
from fembeam.mechanisms import Mechanism, side_of



@pytest.fixture(scope="module")
def arch_eq(paper_arch, paper_result):
    return EquationOfMotion(Mechanism.from_hinges(paper_arch, paper_result.hinges_before))


@pytest.fixture(scope="module")
def block():
    b = fembeam.StraightMember(height=2.0, width=0.5)
    res = fembeam.analyze(b, voussoirs=1)
    return b, res, EquationOfMotion(Mechanism.from_hinges(b, res.hinges_before))


def _near_hinges(mech, d):
    """Sections ``d`` (m) on either side of every hinge of a four-hinge mechanism, inside
    the moving pieces [s1, s2], with the expected e / t there."""
    s, edge = [], []
    for sh, k in zip(mech.s, mech.sides):
        for x in (sh - d, sh + d):
            if mech.s[0] <= x <= mech.s[-1]:
                s.append(x), edge.append(side_of(k).pivot)
    return np.array(s), np.array(edge)


# ---------------------------------------------------------------------- 1. onset
def test_onset_thrust_line_inside_and_through_the_hinges(paper_arch, paper_result, arch_eq):
    a_g = -paper_result.A_L                   # inertia load +A_L g along +x (direction +1)
    t, L = paper_arch.thickness, paper_arch.length
    f = thrust_line_margin(arch_eq, 0.0, 0.0, 0.0, a_g)
    print(f"\nonset: margin {f.margin:.3e}, residual {f.residual:.3e}, min N {f.N.min():.4f}")
    assert f.margin >= -1e-9
    assert f.margin < 1e-6                    # it touches the edge at the hinges
    assert f.residual < 1e-10                 # at rest at A_L the mechanism is in equilibrium
    assert np.all(f.N > 0)
    s, edge = _near_hinges(arch_eq.mechanism, 1e-6 * L)
    near = section_forces(arch_eq, 0.0, 0.0, 0.0, a_g, s)
    dev = np.abs(near.eccentricity / t - edge)
    print(f"onset: e/t 1e-6 L inside the hinges {np.round(near.eccentricity / t, 7)}, max |e/t - edge| {dev.max():.2e}")
    assert dev.max() < 1e-4


def test_onset_thrust_line_equals_limit_analysis(paper_arch, paper_result, arch_eq):
    lim, mech, t = paper_result.limit, arch_eq.mechanism, paper_arch.thickness
    js, sh = lim.disc.joint_s, np.array(mech.s)
    far = (js > sh[0]) & (js < sh[-1]) & (np.min(np.abs(js[:, None] - sh[None, :]), 1) > 0.02 * paper_arch.length)
    f = section_forces(arch_eq, 0.0, 0.0, 0.0, -paper_result.A_L, js[far])
    de = np.max(np.abs(f.eccentricity - lim.eccentricity[far])) / t
    dN = np.max(np.abs(f.N - arch_eq.g * (lim.N[0] + lim.N[1])[far])) / f.N.max()   # limit forces per g
    print(f"\nlimit analysis: {far.sum()} joints, max |de|/t {de:.2e}, max |dN|/N {dN:.2e}")
    assert far.sum() > 50
    assert de < 1e-6 and dN < 1e-6


# ---------------------------------------------------------------------- 2. consistency
def test_residual_vanishes_only_on_the_equation_of_motion(arch_eq):
    eq = arch_eq
    theta, rate, a_g = 0.3 * eq.theta_unstable * eq.sign, 0.7, 0.2
    accel = eq.acceleration(theta, rate, a_g)
    f = thrust_line_margin(eq, theta, rate, accel, a_g)
    bad = thrust_line_margin(eq, theta, rate, 1.01 * accel, a_g)
    print(f"\nmoving arch: residual {f.residual:.2e}, with theta'' + 1 %: {bad.residual:.2e}; margin {f.margin:.4f}")
    assert f.residual < 1e-10
    assert bad.residual > 1e-4
    # the section forces integrated from each piece's left hinge reach its right hinge
    # through the pivot there (deformed configuration, d'Alembert loads included)
    mech, t = eq.mechanism, eq.mechanism.curve.thickness
    s = np.array(mech.s[1:]) - 1e-9 * mech.curve.length
    e = section_forces(eq, theta, rate, accel, a_g, s).eccentricity / t
    print(f"moving arch: e/t just left of C13, C23, C2: {e}")
    assert np.allclose(e, [side_of(k).pivot for k in mech.sides[1:]], atol=1e-6)


# ---------------------------------------------------------------------- 3. block at rest
def test_block_at_rest(block):
    b, res, eq = block
    L, w, rho, g = b.height, b.width, b.density, eq.g
    s = np.linspace(0.0, L, 9)[:-1]
    f = section_forces(eq, 0.0, 0.0, 0.0, 0.0, s)
    assert np.allclose(f.N, rho * w * (L - s) * g, rtol=1e-13)
    assert np.allclose(f.eccentricity, 0.0, atol=1e-13 * w) and np.allclose(f.V, 0.0, atol=1e-12)
    # at onset the resultant at the base passes through the hinge corner
    assert res.A_L == pytest.approx(w / L, rel=1e-9)
    on = section_forces(eq, 0.0, 0.0, 0.0, -res.A_L, [0.0, 1e-6 * L])
    m = thrust_line_margin(eq, 0.0, 0.0, 0.0, -res.A_L)
    print(f"\nblock at onset: e/t at the base {on.eccentricity / w}, margin {m.margin:.2e}, residual {m.residual:.2e}")
    assert on.eccentricity[0] / w == pytest.approx(side_of(res.hinges_before[0].side).pivot, abs=1e-12)
    assert on.eccentricity[1] / w == pytest.approx(side_of(res.hinges_before[0].side).pivot, abs=1e-6)
    assert -1e-12 <= m.margin < 1e-6 and m.residual < 1e-12


# ---------------------------------------------------------------------- 4. block in free motion
def test_block_rocking_closed_form(block):
    b, res, eq = block
    L, w, rho, g = b.height, b.width, b.density, eq.g
    C = np.array([w / 2, 0.0]) if res.hinges_before[0].side == "intrados" else np.array([-w / 2, 0.0])
    theta, rate, a_g = 0.2 * eq.sign, -0.8 * eq.sign, 0.15

    def rot(v):
        c, s = np.cos(theta), np.sin(theta)
        return np.array([c * v[0] - s * v[1], s * v[0] + c * v[1]])

    def cross(a, c):
        return a[0] * c[1] - a[1] * c[0]

    bvec = np.array([-a_g * g, -g])                        # gravity and ground inertia per unit mass
    # whole block about its corner: I_C theta'' = (G - C) x m b,  I_C = m (w^2 + L^2) / 3
    m = rho * w * L
    accel = cross(rot(np.array([0.0, L / 2]) - C), m * bvec) / (m * (w * w + L * L) / 3)
    assert eq.acceleration(theta, rate, a_g) == pytest.approx(accel, rel=1e-12)

    # the part above the section s: mass mu, centroid G, inertia about G; the lower part
    # pushes it with T = mu (a_G - b) and the moment M_P = -(G - P) x mu (b - a_G) + I_G theta''
    s = 0.7
    mu, h = rho * w * (L - s), L - s
    P, G = C + rot(np.array([0.0, s]) - C), C + rot(np.array([0.0, (L + s) / 2]) - C)
    r = G - C
    aG = accel * np.array([-r[1], r[0]]) - rate**2 * r
    T = mu * (aG - bvec)
    M = -cross(G - P, mu * (bvec - aG)) + mu * (w * w + h * h) / 12 * accel
    tn, nn = rot(np.array([0.0, 1.0])), rot(np.array([1.0, 0.0]))
    f = section_forces(eq, theta, rate, accel, a_g, [0.0, s])
    print(f"\nrocking block: N {f.N[1]:.6f} vs {T @ tn:.6f}, V {f.V[1]:.6f} vs {T @ nn:.6f}, "
          f"M {f.M[1]:.6f} vs {M:.6f}; e/t at the base {f.eccentricity[0] / w:.15f}, residual {f.residual:.1e}")
    assert f.N[1] == pytest.approx(T @ tn, rel=1e-12)
    assert f.V[1] == pytest.approx(T @ nn, rel=1e-12)
    assert f.M[1] == pytest.approx(M, rel=1e-12)
    # on the equation of motion the base resultant passes through the hinge corner
    assert f.eccentricity[0] / w == pytest.approx(side_of(res.hinges_before[0].side).pivot, abs=1e-12)
    assert f.residual < 1e-12
    off = section_forces(eq, theta, rate, 1.01 * accel, a_g, [0.0])
    assert off.residual > 1e-4 and abs(off.eccentricity[0] / w - side_of(res.hinges_before[0].side).pivot) > 1e-4


# ---------------------------------------------------------------------- 5. many instants at once
def test_many_instants_equal_one_at_a_time(arch_eq, block):
    """section_forces_many on a batch of instants = section_forces instant by instant."""
    from fembeam.dynamics.thrust import section_forces_many, uniform_sections

    for eq in (arch_eq, block[2]):
        x = eq.sign * np.array([0.0, 0.2, 0.6, 0.9]) * eq.theta_unstable
        rate, a_g = np.array([0.0, 0.7, -0.4, 1.1]), np.array([-0.1, 0.2, 0.0, 0.35])
        acc = np.array([eq.acceleration(*args) for args in zip(x, rate, a_g)])
        s = uniform_sections(eq.mechanism, 20)
        many = section_forces_many(eq, x, rate, acc, a_g, s)
        for i in range(x.size):
            one = section_forces(eq, x[i], rate[i], acc[i], a_g[i], s)
            scale = np.max(np.abs(one.N))
            for a, b in ((many.N[i], one.N), (many.V[i], one.V), (many.M[i], one.M)):
                assert np.allclose(a, b, rtol=0, atol=1e-13 * scale)
            assert many.margin[i] == pytest.approx(one.margin, abs=1e-13) and many.residual[i] < 1e-10
