"""The static limit LP in the redundants: checked against the kinematic LP over element
velocities (an independent formulation), the equilibrium of the pieces, the continuum
bounds and the closed-form four-hinge load factor; certificates of every outcome."""
import numpy as np
import pytest
import scipy.sparse as sp
from scipy.optimize import linprog

from fembeam import CircularArch, StraightMember, analyze, discretize, limit_analysis, minimum_thickness, uniform_nodes
from fembeam.analysis import THRESHOLDS, continuum_limit
from fembeam.analysis.statics import section_forces, statics
from fembeam.analysis.verification import failures
from fembeam.fem import dof_scaling


def kinematic_A_L(disc, direction=1):
    """min f_y.u  s.t.  direction f_x.u = m, B_slide u = 0, B_open u >= 0 (HiGHS)."""
    D = dof_scaling(disc)
    fx, fy = disc.load_vectors()
    m = float(fx @ disc.rigid(V=(1.0, 0.0)))
    A_eq = sp.vstack([disc.B_slide @ D, sp.csr_matrix(direction * (D @ fx) / m)]).tocsr()
    b_eq = np.zeros(A_eq.shape[0])
    b_eq[-1] = 1.0
    res = linprog(D @ fy / m, A_ub=-(disc.B_open @ D), b_ub=np.zeros(disc.B_open.shape[0]), A_eq=A_eq, b_eq=b_eq,
                  bounds=(None, None), method="highs")
    return res


@pytest.mark.parametrize("beta, tr, n, direction", [(157.5, 0.15, 200, 1), (157.5, 0.15, 200, -1), (120, 0.1, 37, 1),
                                                    (200, 0.3, 80, 1), (90, 0.12, 7, -1)])
def test_static_equals_kinematic(beta, tr, n, direction):
    disc = discretize(CircularArch.from_ratio(beta, tr), uniform_nodes(CircularArch.from_ratio(beta, tr), n))
    lim = limit_analysis(disc, direction)
    kin = kinematic_A_L(disc, direction)
    assert kin.status == 0 and lim.status == "ok"
    assert lim.A_L == pytest.approx(kin.fun, rel=1e-9)
    # the static LP's mechanism does the kinematic LP's work
    fx, fy = disc.load_vectors()
    assert float(fy @ lim.u) / (direction * float(fx @ lim.u)) == pytest.approx(kin.fun, rel=1e-9)


def test_self_stress_states_span_the_null_space_and_pieces_agree():
    arch = CircularArch.from_ratio(140, 0.12)
    disc = discretize(arch, np.sort(np.r_[uniform_nodes(arch, 30), 0.777]))   # an irregular mesh
    st = statics(disc)
    Bt = sp.vstack([disc.B_slide, disc.B_open]).T.tocsr()
    for i in range(3):   # B^T g = 0 for every self-stress state (scaled by the load's size)
        g = st.G_x[:, :, i]
        assert np.linalg.norm(Bt @ np.r_[g[0], g[1], g[2]]) < 1e-12 * np.abs(g).max() * st.mass
    x, lam = np.array([0.1, 0.4, 0.2]), 0.3
    g = st.forces(x, lam)
    gs = section_forces(st, disc.joint_s, x, lam)   # equilibrium of the part left of each joint
    assert np.abs(gs - g).max() < 1e-12 * np.abs(g).max()


def test_housner_block_is_statically_determinate():
    disc = discretize(StraightMember(2.0, 0.6), np.array([0.0, 2.0]))
    lim = limit_analysis(disc)
    assert statics(disc).k == 0 and lim.A_L == pytest.approx(0.3, rel=1e-12)


def test_cannot_stand_certificate_is_a_collapse_mechanism_under_gravity():
    arch = CircularArch.from_ratio(180, 0.09)
    disc = discretize(arch, uniform_nodes(arch, 7))
    lim = limit_analysis(disc)
    assert lim.status == "cannot_stand" and lim.margin < 0
    fx, fy = disc.load_vectors()
    eps = disc.B_open @ lim.u
    assert eps.min() > -1e-12 * eps.max() and np.abs(disc.B_slide @ lim.u).max() < 1e-12 * eps.max()
    assert float(fy @ lim.u) < 0             # the weight goes down along it
    assert kinematic_A_L(disc).status == 3   # independently: the kinematic LP is unbounded below... or
    assert len(lim.hinges) >= 4


def test_no_mechanism_certificate_is_an_admissible_ray():
    arch = CircularArch.from_ratio(60, 0.5)
    disc = discretize(arch, uniform_nodes(arch, 20))
    lim = limit_analysis(disc)
    assert lim.status == "no_mechanism" and lim.verification["ray_residual"] < 1e-9
    assert kinematic_A_L(disc).status == 2   # independently: no mechanism moves in the load direction


def test_continuum_is_mesh_independent_bracketed_and_below_every_mesh():
    arch = CircularArch.from_ratio(157.5, 0.15)
    vals = []
    for n in (20, 50, 200, 800):
        disc = discretize(arch, uniform_nodes(arch, n))
        c = continuum_limit(disc)
        mesh = limit_analysis(disc).A_L
        assert c.A_L_lower <= c.A_L <= mesh and c.exact_hinges and c.violation < 1e-12
        vals.append(c.A_L)
    assert np.ptp(vals) < 1e-11 and vals[0] == pytest.approx(0.3533839, abs=5e-8)   # the paper: 0.3533839


@pytest.mark.parametrize("beta, tr", [(157.5, 0.15), (157.5, 0.6), (120.0, 0.25), (120.0, 0.4)])
def test_coarse_meshes_find_the_continuum_hinges(beta, tr):
    """On 4 to 12 elements (two elements: 17 to 50 % of the length; on 4, two hinges of one
    edge of the thick arch lie within two elements, 0.50 of the length apart, and are not
    merged into one cluster) the continuum's hinges are solved exactly, at the sections found on 200 elements (their
    closest pair 14 to 26 % of the length apart), and their mechanism's own load factor (virtual work, an
    independent route) is ``A_L``; before, 4 to 7 elements kept the mesh's mechanism, whose
    load factor is 5 to 12 % higher."""
    from fembeam.mechanisms import Mechanism
    from fembeam.mechanisms.energy import load_factor
    from fembeam.mechanisms.hinge import Hinge

    arch = CircularArch.from_ratio(beta, tr)
    fine = continuum_limit(discretize(arch, uniform_nodes(arch, 200)))
    assert fine.exact_hinges
    for n in range(4, 13):
        disc = discretize(arch, uniform_nodes(arch, n))
        c = continuum_limit(disc)
        assert c.exact_hinges, n
        assert c.A_L == pytest.approx(fine.A_L, rel=1e-10), n
        assert np.allclose(c.hinge_s, fine.hinge_s, rtol=0, atol=1e-7 * arch.length), n
    res = analyze(arch, elements=5, thrust=False)
    mech = Mechanism.from_hinges(arch, res.hinges_before)
    assert load_factor(mech, 1) == pytest.approx(res.A_L, rel=1e-9) and res.A_L < res.A_L_mesh * (1 - 1e-3)
    assert all(isinstance(h, Hinge) for h in res.hinges_before)


@pytest.mark.parametrize("beta, tr, direction", [(157.5, 0.15, 1), (180.0, 0.1, -1), (60.0, 0.05, 1)])
def test_continuum_takes_the_first_round_from_the_limit_analysis(beta, tr, direction, monkeypatch):
    """The continuum search's first LPs (the joints' rows alone) are the limit analysis's:
    taken from it, the result is the same bit for bit and two LPs fewer are solved (the
    stand LP only for a member that cannot stand)."""
    import fembeam.analysis.continuum as continuum_mod

    arch = CircularArch.from_ratio(beta, tr)
    disc = discretize(arch, uniform_nodes(arch, 60))
    lim = limit_analysis(disc, direction)
    calls = []
    for name in ("stand_lp", "main_lp"):
        real = getattr(continuum_mod, name)
        monkeypatch.setattr(continuum_mod, name, lambda *a, _f=real, _n=name, **k: (calls.append(_n), _f(*a, **k))[1])
    alone = continuum_limit(disc, direction)
    n_alone = len(calls)
    reused = continuum_limit(disc, direction, lim=lim)
    assert len(calls) - n_alone == n_alone - (2 if lim.status != "cannot_stand" else 1)
    assert lim.status == alone.status
    for f in ("status", "A_L", "A_L_lower", "margin", "violation", "rounds", "exact_hinges"):
        assert getattr(reused, f) == getattr(alone, f) or (np.isnan(getattr(alone, f)) and np.isnan(getattr(reused, f)))
    assert np.array_equal(reused.hinge_s, alone.hinge_s) and np.array_equal(reused.cuts, alone.cuts)
    # another direction's limit analysis is not taken
    other = limit_analysis(disc, -direction)
    n0 = len(calls)
    continuum_limit(disc, direction, lim=other)
    assert len(calls) - n0 == n_alone


@pytest.mark.parametrize("beta, tr, direction", [(157.5, 0.15, 1), (90.0, 0.1, -1), (180.0, 0.2, 1)])
def test_hinge_polish_newton_and_minpack_agree(beta, tr, direction, monkeypatch):
    """The exact hinges come from Newton's method on the optimality conditions; MINPACK's
    trust region (taken when Newton fails) finds the same point."""
    import fembeam.analysis.continuum as cont

    arch = CircularArch.from_ratio(beta, tr)
    disc = discretize(arch, uniform_nodes(arch, 80))
    newton = continuum_limit(disc, direction)
    monkeypatch.setattr(cont, "_newton", lambda FJ, p0, inside, **kw: p0)   # no progress: MINPACK
    minpack = continuum_limit(disc, direction)
    assert newton.exact_hinges and minpack.exact_hinges
    assert newton.A_L == pytest.approx(minpack.A_L, rel=1e-13)
    assert np.allclose(newton.hinge_s, minpack.hinge_s, rtol=0, atol=1e-9 * arch.length)


def test_a_polish_ending_on_nan_is_refused(monkeypatch):
    """Newton's and MINPACK's points are judged, NaN included: the hinges then stay
    those of the LP (not exact), with A_L still bracketed."""
    import types

    import scipy.optimize

    import fembeam.analysis.continuum as cont

    arch = CircularArch.from_ratio(157.5, 0.15)
    disc = discretize(arch, uniform_nodes(arch, 40))
    monkeypatch.setattr(cont, "_newton", lambda FJ, p0, inside, **kw: np.full_like(p0, np.nan))
    monkeypatch.setattr(scipy.optimize, "root", lambda *a, **k: types.SimpleNamespace(x=np.full_like(a[1], np.nan)))
    c = continuum_limit(disc)
    assert c.status == "ok" and not c.exact_hinges and np.all(np.isfinite(c.hinge_s))
    assert c.A_L_lower <= c.A_L == pytest.approx(0.353383858, rel=1e-9)


def test_newton_halves_its_steps_and_stops_at_the_noise_floor():
    """On a scalar equation with a Jacobian: converges from a start where a full step
    overshoots out of the admitted interval, and returns where no step decreases |F|."""
    from fembeam.analysis.continuum import _newton

    calls = []

    def FJ(p):            # arctan: full Newton steps diverge from |p| > 1.39
        calls.append(p[0])
        return np.array([np.arctan(p[0])]), np.array([[1.0 / (1.0 + p[0] ** 2)]])

    p = _newton(FJ, np.array([3.0]), lambda q: abs(q[0]) <= 5.0)
    assert abs(p[0]) < 1e-15 and all(abs(c) <= 5.0 for c in calls)
    flat = _newton(lambda q: (np.array([1.0 + 0 * q[0]]), np.array([[1.0]])), np.array([0.5]), lambda q: True)
    assert flat[0] == 0.5      # no step decreases the residual: the start comes back


def test_continuum_hinges_give_the_closed_form_load_factor():
    """Four hinges at the continuum optimum: the exact four-hinge load factor (inertia
    integrals of the pieces, Appendix A) equals the LP's A_L."""
    from fembeam.mechanisms import Mechanism, load_factor   # noqa: F401  (the one mechanism type)

    arch = CircularArch.from_ratio(157.5, 0.15)
    c = continuum_limit(discretize(arch, uniform_nodes(arch, 100)))
    res = analyze(arch, elements=100)
    mech = Mechanism.from_hinges(arch, res.hinges_before)
    assert load_factor(mech) == pytest.approx(c.A_L, rel=1e-10)


@pytest.mark.parametrize("voussoirs, expected", [(7, 0.0962), (None, 0.1075)])
def test_minimum_thickness_of_the_arch_analysed(voussoirs, expected):
    arch = CircularArch.from_ratio(180.0, 0.3)
    th = minimum_thickness(arch, voussoirs=voussoirs, elements=None if voussoirs else 60, tol=1e-7)
    assert th.t_over_R == pytest.approx(expected, abs=2e-4) and th.solves <= 60
    for f, outcome in ((1 + 1e-5, "rocking"), (1 - 1e-5, "cannot_stand")):
        kw = {"voussoirs": voussoirs} if voussoirs else {"elements": 60}
        res = analyze(CircularArch.from_ratio(180.0, th.t_over_R * f), tmin_tol=1e-3, **kw)
        assert (res.outcome == "cannot_stand") == (outcome == "cannot_stand")
        if res.outcome == "cannot_stand":
            assert res.t_min_over_R > th.t_over_R * f   # consistent with the verdict


def test_minimum_thickness_iterations_are_bounded():
    th = minimum_thickness(CircularArch.from_ratio(180.0, 0.3), voussoirs=9, tol=1e-12)
    assert th.solves <= 60 and th.scale - th.lower <= 1e-12 * th.scale


def test_a_failed_figure_fails_the_result():
    assert failures({"duality_gap": 1e-3, "max_shear_ratio": 10.0}) == {"duality_gap": 1e-3}
    assert failures({"equilibrium_residual": float("nan")})   # not a number: failed
    assert set(THRESHOLDS) >= {"statics_mismatch", "impulse_mismatch", "continuum_violation"}


def test_free_self_stress_and_huge_thrust_are_not_mistaken_for_no_mechanism():
    """A one-voussoir semicircle leaves the shear redundant free (horizontal springing faces):
    the simplex may park it at its bound, which must not read as an unbounded load factor."""
    for tr in (0.1, 0.3):
        disc = discretize(CircularArch.from_ratio(180, tr), np.array([0.0, np.pi]))
        lim = limit_analysis(disc)
        kin = kinematic_A_L(disc)
        assert lim.status == "ok" and lim.A_L == pytest.approx(kin.fun, rel=1e-9)


def test_members_that_stand_at_any_thickness_say_so():
    th = minimum_thickness(CircularArch.from_ratio(180.0, 0.3), voussoirs=3)
    assert th.outcome == "stands_at_any_thickness" and th.scale == 0.0


def test_continuum_needs_rigid_elements_and_a_direction():
    from fembeam.errors import InputError
    from fembeam.fem import discretize_p1

    arch = CircularArch.from_ratio(157.5, 0.15)
    with pytest.raises(InputError, match="rigid elements"):
        continuum_limit(discretize_p1(arch, uniform_nodes(arch, 20)))
    with pytest.raises(InputError, match="direction"):
        continuum_limit(discretize(arch, uniform_nodes(arch, 20)), direction=2)


def test_block_on_a_mesh_of_elements():
    res = analyze(StraightMember(2.0, 0.6), elements=8)
    a = np.arctan(0.3)
    assert res.A_L == pytest.approx(0.3, rel=1e-12) and res.r == pytest.approx((1 - 1.5 * np.sin(a) ** 2) ** 2, abs=1e-8)


def test_lp_prints_nothing_on_stdout():
    """HiGHS (>= 1.16) prints a banner on the first construction of a solver in a process:
    the LP keeps stdout silent (the commands print one JSON object there)."""
    import subprocess
    import sys

    code = ("import numpy as np; from fembeam.analysis.lp import maximise; "
            "s = maximise(np.array([1.0]), np.array([[-1.0], [1.0]]), np.array([2.0, 1.0]), [(None, None)]); "
            "assert abs(s.value - 2.0) < 1e-12 and abs(s.y[0] - 1.0) < 1e-12")
    p = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True)
    assert p.returncode == 0, p.stderr
    assert p.stdout == ""


def test_lp_without_a_stdout_still_solves():
    """The banner's redirect is best effort: with fd 1 closed the LP still solves."""
    import subprocess
    import sys

    code = ("import os, sys; os.close(1); sys.stdout = None; import numpy as np; "
            "from fembeam.analysis.lp import maximise; "
            "s = maximise(np.array([1.0]), np.array([[-1.0]]), np.array([2.0]), [(None, None)]); "
            "assert abs(s.value - 2.0) < 1e-12")
    p = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True)
    assert p.returncode == 0, p.stderr


def test_rows_of_any_scale_are_solved():
    """Rows are equilibrated before HiGHS sees them: a row with entries of 1e16 (which HiGHS
    rejects as given) and the rows of a very thin section (entries ~1/t, which left HiGHS's
    absolute tolerances unreachable: model status Unknown) are solved, with the duals of the
    rows as given (A^T y = -c)."""
    from fembeam import CatenaryArch, discretize, uniform_nodes
    from fembeam.analysis.lp import maximise
    from fembeam.analysis.thickness import _margin
    from fembeam.fem.rigid import ThicknessFamily

    A, b, c = np.array([[-1.0, 0.0], [0.0, -1e16]]), np.array([1.0, 1e16]), np.array([1.0, 1.0])
    s = maximise(c, A, b, [(-5, 5)] * 2, initial=1)
    assert s.value == pytest.approx(2.0, rel=1e-12) and np.allclose(A.T @ s.y, -c, rtol=1e-12, atol=0)
    arch = CatenaryArch(span=10.0, rise=4.0, thickness=0.5)
    nodes = uniform_nodes(arch, 200)
    assembled = _margin(discretize(arch.with_thickness_scaled(0.01), nodes), True)
    # (rows held to 1e-10 of their largest entry, ~2e3 here, when the equilibrated retry runs)
    assert _margin(ThicknessFamily.of(arch, nodes).at(0.01), True) == pytest.approx(assembled, rel=1e-6)
