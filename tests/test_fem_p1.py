"""Continuous P1 curved-beam elements (fembeam.fem.p1): kernel, mass, convergence."""
import numpy as np
import pytest

from fembeam.fem import uniform_nodes
from fembeam.fem.p1 import discretize_p1
from fembeam.geometry import CircularArch
from fembeam.analysis.impact import impact
from fembeam.analysis.limit import limit_analysis

ARCH = CircularArch.from_ratio(157.5, 0.15, radius=2.0, density=3.0)


def _sector(curve):
    """Exact mass, first moment S_y and polar inertia (about the centre) of the annular sector."""
    rho, b = curve.density, curve.beta
    re, ri = curve.radius + curve.thickness / 2, curve.radius - curve.thickness / 2
    return (rho * b * (re**2 - ri**2) / 2, rho * (re**3 - ri**3) / 3 * 2 * np.sin(b / 2),
            rho * b * (re**4 - ri**4) / 4)


def _rate(h, err):
    return np.polyfit(np.log(h), np.log(err), 1)[0]


def test_layout_and_sizes():
    N = 12
    d = discretize_p1(ARCH, uniform_nodes(ARCH, N))
    assert d.M.shape == (3 * (N + 1),) * 2
    assert d.B_open.shape == (2 * (N + 2), 3 * (N + 1)) and d.B_slide.shape == (N + 2, 3 * (N + 1))
    assert np.allclose(d.frames["s"], d.nodes_s)
    mid = 0.5 * (d.nodes_s[:-1] + d.nodes_s[1:])
    assert np.allclose(d.joint_s, np.r_[0.0, mid, ARCH.length])


def test_rigid_motions_in_kernel_to_second_order():
    """Interior strain rows (per unit length) of rigid motions vanish like h^2; the
    springing rows are exactly the end section's opening against the abutment."""
    Ns = np.array([10, 20, 40, 80])
    motions = [((1.0, 0.0), 0.0), ((0.0, 1.0), 0.0), ((0.3, -0.7), 1.3)]
    errs = []
    for N in Ns:
        d = discretize_p1(ARCH, uniform_nodes(ARCH, N))
        h = ARCH.length / N
        J = d.n_joints
        worst = 0.0
        for V, om in motions:
            u = d.rigid(V=V, omega=om, about=(0.4, -0.1))
            speed = np.hypot(*V) + abs(om) * ARCH.radius
            inner = np.r_[d.B_open[1:J - 1] @ u, d.B_open[J + 1:2 * J - 1] @ u, d.B_slide[1:J - 1] @ u]
            worst = max(worst, np.max(np.abs(inner)) / (h * speed))
        errs.append(worst)
        # rotation about the centre is represented exactly (w = -R omega, v = 0): no strain
        rot = d.rigid(omega=1.0)
        assert np.max(np.abs(d.B_open[1:J - 1] @ rot)) < 1e-12
        # rotation about the left intrados corner: that corner's opening is exactly 0,
        # the extrados one is t * omega (the section swings away from the abutment)
        corner = ARCH.position(0.0) + 0.5 * ARCH.thickness * ARCH.normal(0.0)
        piv = d.rigid(omega=-1.0, about=corner)
        assert abs((d.B_open @ piv)[0]) < 1e-12
        assert (d.B_open @ piv)[J] == pytest.approx(ARCH.thickness, rel=1e-12)
    order = _rate(ARCH.length / Ns, np.array(errs))
    assert 1.9 < order < 2.1, (errs, order)


def test_mass_first_moment_polar_inertia():
    m, Sy, Jc = _sector(ARCH)
    # exactly represented fields: uniform unit tangential velocity, rotation about the centre
    d = discretize_p1(ARCH, uniform_nodes(ARCH, 7))
    tang = np.tile([1.0, 0.0, 0.0], 8)
    rot = d.rigid(omega=1.0)
    assert tang @ d.M @ tang == pytest.approx(m, rel=1e-13)
    assert rot @ d.M @ rot == pytest.approx(Jc, rel=1e-13)
    # translations are interpolated (intrinsic components): O(h^2) towards m and S
    Ns = np.array([8, 16, 32, 64])
    em, eS, ec = [], [], []
    for N in Ns:
        d = discretize_p1(ARCH, uniform_nodes(ARCH, N))
        tx, ty, rot = d.rigid(V=(1.0, 0.0)), d.rigid(V=(0.0, 1.0)), d.rigid(omega=1.0)
        em.append(abs(ty @ d.M @ ty - m) / m)
        eS.append(abs(-(tx @ d.M @ rot) - Sy) / Sy)   # int rho v_x of rotation = -S_y
        ec.append(abs(ty @ d.M @ rot) / Sy)           # = S_x = 0 by symmetry
    assert em[-1] < 1e-3 and eS[-1] < 1e-3 and max(ec) < 1e-13
    assert 1.95 < _rate(1.0 / Ns, np.array(em)) < 2.05
    assert 1.95 < _rate(1.0 / Ns, np.array(eS)) < 2.05


def test_load_factor_converges_second_order():
    """A_L for beta = 157.5 deg, t/R = 0.15 tends to the continuous 0.3533839."""
    arch = CircularArch.from_ratio(157.5, 0.15)
    Ns = np.array([50, 100, 200, 400])
    AL = np.array([limit_analysis(discretize_p1(arch, uniform_nodes(arch, N))).A_L for N in Ns])
    err = AL - 0.353384
    assert np.all(err > 0)                       # upper bound (kinematic) on every mesh
    assert abs(err[-1]) < 3e-5
    assert 1.8 < _rate(1.0 / Ns, err) < 2.3


def test_impact_runs_unchanged_and_verifies():
    arch = CircularArch.from_ratio(157.5, 0.15)
    d = discretize_p1(arch, uniform_nodes(arch, 200))
    lim = limit_analysis(d)
    imp = impact(d, -lim.u)
    assert imp.r == pytest.approx(0.606, abs=2e-3)
    v = imp.verification
    assert v["equilibrium_residual"] < 1e-8 and v["impulse_work"] < 1e-7
    assert v["max_tensile_impulse"] < 1e-6 and v["impulse_line_outside"] < 1e-6
    assert [h.side for h in imp.hinges][:1] == ["extrados"] and len(imp.hinges) >= 4


def test_cartesian_components_variant():
    """Interpolating (v_x, v_y): translations exact, fibre rows of rigid motions exactly 0
    on a circle, sliding rows O(h^2); rotations are interpolated, so the first moment and
    polar inertia (paired with a rotation) are the O(h^2) ones."""
    m, Sy, Jc = _sector(ARCH)
    Ns = np.array([10, 20, 40, 80])
    eg, eS, eJ = [], [], []
    for N in Ns:
        d = discretize_p1(ARCH, uniform_nodes(ARCH, N), components="cartesian")
        J = d.n_joints
        u = d.rigid(V=(0.3, -0.7), omega=1.3, about=(0.4, -0.1))
        inner = np.r_[1:J - 1, J + 1:2 * J - 1]
        assert np.max(np.abs((d.B_open @ u)[inner])) < 1e-13
        eg.append(np.max(np.abs((d.B_slide @ u)[1:J - 1])) * N / ARCH.length)
        tx, ty, rot = d.rigid(V=(1.0, 0.0)), d.rigid(V=(0.0, 1.0)), d.rigid(omega=1.0)
        assert tx @ d.M @ tx == pytest.approx(m, rel=1e-13)
        assert ty @ d.M @ ty == pytest.approx(m, rel=1e-13) and abs(tx @ d.M @ ty) < 1e-13 * m
        eS.append(abs(-(tx @ d.M @ rot) - Sy) / Sy)
        eJ.append(abs(rot @ d.M @ rot - Jc) / Jc)
    assert 1.9 < _rate(1.0 / Ns, np.array(eg)) < 2.1
    assert 1.9 < _rate(1.0 / Ns, np.array(eS)) < 2.1
    assert 1.9 < _rate(1.0 / Ns, np.array(eJ)) < 2.1
    arch = CircularArch.from_ratio(157.5, 0.15)
    AL = limit_analysis(discretize_p1(arch, uniform_nodes(arch, 400), components="cartesian")).A_L
    assert 0 < AL - 0.353384 < 3e-5
