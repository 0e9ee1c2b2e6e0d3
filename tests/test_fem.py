"""The rigid curved-beam elements: strain operators and kinetic-energy form."""
import math

import numpy as np
import pytest

from fembeam import CircularArch, discretize, uniform_nodes


@pytest.fixture(scope="module")
def disc():
    c = CircularArch.from_ratio(157.5, 0.15, radius=2.0)
    rng = np.random.default_rng(0)
    nodes = np.sort(np.concatenate([[0, c.length], rng.uniform(0, c.length, 29)]))  # irregular mesh
    return discretize(c, nodes)


def interior(disc, A):
    """Rows of the interior joints (the springings are joints against fixed abutments)."""
    J = disc.n_joints
    keep = np.ones(A.shape[0], bool)
    for k in range(A.shape[0] // J):
        keep[[k * J, k * J + J - 1]] = False
    return A[keep]


@pytest.mark.parametrize("V, omega, about", [((1, 0), 0, (0, 0)), ((0, 1), 0, (0, 0)),
                                              ((0.3, -2), 1.7, (0.4, -1.1)), ((0, 0), 1, (5, 5))])
def test_rigid_motions_are_in_the_kernel(disc, V, omega, about):
    d = disc.rigid(V, omega, about)
    scale = np.abs(d).max()
    assert np.abs(interior(disc, disc.B_open @ d)).max() < 1e-14 * scale
    assert np.abs(interior(disc, disc.B_slide @ d)).max() < 1e-14 * scale


def test_springing_joint_rotation_about_a_corner(disc):
    """Rotating the whole arch about the left springing's intrados corner opens only its
    extrados there: opening 0 at the pivot, t * |omega| at the other edge, no sliding."""
    c = disc.curve
    t0 = c.thickness_at(0.0)
    corner = c.position(0.0) + 0.5 * t0 * c.normal(0.0)
    d = disc.rigid((0, 0), -1.0, corner)  # clockwise
    eps = disc.B_open @ d
    J = disc.n_joints
    assert abs(eps[0]) < 1e-14 and eps[J] == pytest.approx(t0, rel=1e-12)
    assert abs((disc.B_slide @ d)[0]) < 1e-14


def test_operators_are_sparse_and_local(disc):
    # a joint row couples the (w, v, omega) of the two elements it separates
    assert disc.B_open.getnnz(axis=1).max() <= 6 and disc.B_slide.getnnz(axis=1).max() <= 6
    assert disc.M.getnnz(axis=1).max() <= 3


def test_mass_form_reproduces_annular_sector():
    """d^T M d for rigid motions gives the exact mass, static moment and polar inertia."""
    R, t, beta, rho = 2.0, 0.3, 157.5, 1.7
    c = CircularArch(radius=R, thickness=t, embrace_deg=beta, density=rho)
    disc = discretize(c, uniform_nodes(c, 9))
    a, b, B = R - t / 2, R + t / 2, math.radians(beta)
    m = rho * 0.5 * (b**2 - a**2) * B
    Sy = rho * (b**3 - a**3) / 3 * 2 * math.sin(B / 2)   # first moment about the x axis
    Jo = rho * (b**4 - a**4) / 4 * B                      # polar moment about the centre
    tx, ty, rot = disc.rigid((1, 0)), disc.rigid((0, 1)), disc.rigid(omega=1.0)
    M = disc.M
    assert tx @ M @ tx == pytest.approx(m, rel=1e-13)
    assert ty @ M @ ty == pytest.approx(m, rel=1e-13)
    assert tx @ M @ ty == pytest.approx(0.0, abs=1e-13)
    # rotation about the origin: velocity k x X, so x-momentum = -S_y, y-momentum = S_x = 0
    assert tx @ M @ rot == pytest.approx(-Sy, rel=1e-13)
    assert ty @ M @ rot == pytest.approx(0.0, abs=1e-13)
    assert rot @ M @ rot == pytest.approx(Jo, rel=1e-13)


def test_mass_matrix_matches_segment_integrals(disc):
    """Cross-check of the scikit-fem form against the Gauss integrals of
    fembeam.mechanisms.energy, for a four-hinge field with its hinges at nodes."""
    from fembeam.mechanisms import Mechanism, product

    s = disc.nodes_s
    a = Mechanism(disc.curve, (s[0], s[8], s[19], s[-1]), ("intrados", "extrados", "intrados", "extrados"), 1.3)
    da = a.dofs(disc)
    assert da @ disc.M @ da == pytest.approx(product(a, a), rel=1e-12)


@pytest.mark.parametrize("n", [400, 2000, 20000])
def test_fine_meshes_use_fewer_gauss_points_at_round_off(n):
    """Fine meshes get 3 or 4 Gauss points: the exact mass and polar inertia of the annular
    sector still hold to round-off, and M equals that of the 20-point rule."""
    from fembeam import EllipticalArch
    from fembeam.fem.rigid import _default_order

    R, t, beta = 2.0, 0.3, 157.5
    c = CircularArch(radius=R, thickness=t, embrace_deg=beta)
    nodes = uniform_nodes(c, n)
    assert _default_order(c, nodes) in (5, 7)
    disc = discretize(c, nodes)
    a, b, B = R - t / 2, R + t / 2, math.radians(beta)
    tx, rot = disc.rigid((1, 0)), disc.rigid(omega=1.0)
    rho = c.density                                               # the default, 2000 kg/m^3
    assert tx @ disc.M @ tx == pytest.approx(rho * 0.5 * (b**2 - a**2) * B, rel=1e-13)
    assert rot @ disc.M @ rot == pytest.approx(rho * (b**4 - a**4) / 4 * B, rel=1e-13)
    flat = EllipticalArch(span=1.0, rise=0.08, thickness=0.005)   # curvature varying fast at the springings
    for curve in (c, flat):
        nodes = uniform_nodes(curve, n)
        M, ref = discretize(curve, nodes).M, discretize(curve, nodes, intorder=40).M
        assert abs(M - ref).max() <= 1e-14 * abs(ref).max()


def _same_operators(a, b):
    for A, B in ((a.M, b.M), (a.B_open, b.B_open), (a.B_slide, b.B_slide)):
        assert A.shape == B.shape and A.nnz == B.nnz
        assert abs(A - B).max() <= 1e-15 * abs(B).max()
    assert np.array_equal(a.joint_s, b.joint_s) and np.array_equal(a.nodes_s, b.nodes_s)
    for k in b.frames:
        np.testing.assert_allclose(a.frames[k], b.frames[k], rtol=0, atol=1e-15)


@pytest.mark.parametrize("make, n", [
    (lambda: CircularArch(), 300),
    (lambda: __import__("fembeam").PointedArch(span=1.0, rise=0.8, thickness=0.1), 301),   # a crown joint
    (lambda: __import__("fembeam").StraightMember(height=1.0, width=0.2), 120),            # a free end
])
def test_local_update_equals_the_full_assembly(make, n, monkeypatch):
    """discretize(..., like=old) after nodes are moved or inserted (next to the springings
    too) gives the operators of the full assembly; a mesh mostly new, or another curve,
    is assembled in full; the same mesh gives the old discretisation back."""
    import fembeam.fem.rigid as rigid
    from fembeam import nodes_through
    from fembeam.fem.rigid import _update

    monkeypatch.setattr(rigid, "UPDATE_MIN_ELEMENTS", 0)     # small meshes, the local path all the same
    curve = make()
    nodes = uniform_nodes(curve, n)
    old = discretize(curve, nodes)
    L, h = curve.length, curve.length / n
    crown = 0.5 * L + 0.2 * h
    for a, b in curve.solid_spans:      # no node inside a crown wedge: next to it
        if a < crown < b:
            crown = b + 0.2 * h
    moved = nodes_through(nodes, [0.3 * h, 0.31 * L, crown, L - 0.4 * h], keep=curve.fixed_nodes)
    inserted = nodes_through(moved, [0.7777 * L, 0.5 * h], keep=moved)      # no node may move: inserted
    assert inserted.size > moved.size
    for x in (moved, inserted):
        assert _update(old, curve, x, old.intorder) is not None          # the local path, not the fallback
        _same_operators(discretize(curve, x, like=old), discretize(curve, x))
    assert discretize(curve, nodes, like=old) is old
    coarse = uniform_nodes(curve, n // 2)
    assert _update(old, curve, coarse, old.intorder) is None
    _same_operators(discretize(curve, coarse, like=old), discretize(curve, coarse))
    other = CircularArch(thickness=0.2)
    x = nodes_through(uniform_nodes(other, n), [0.31 * other.length])
    _same_operators(discretize(other, x, like=discretize(other, uniform_nodes(other, n))), discretize(other, x))
    _same_operators(discretize(other, x, like=old), discretize(other, x))


def _facet_form_rows(curve, mesh, fr, ends):
    """The joint rows as scikit-fem assembles them: the facet form
    ``sign (a0 w + a1 v + a2 omega) q`` over the interior facets (both sides) and the
    facets ``ends``, trial P0 vector (w, v, omega), test P1 (row = point)."""
    import scipy.sparse as sp
    from skfem import (BilinearForm, ElementLineP0, ElementLineP1, ElementVector, FacetBasis,
                       InteriorFacetBasis, asm)

    a = mesh.p[0][mesh.t[0]]
    E = ElementVector(ElementLineP0(), 3)
    form = BilinearForm(lambda u, v, w: (u[0] * w.a0 + u[1] * w.a1 + u[2] * w.a2) * v)
    bases = [(InteriorFacetBasis(mesh, E, side=i), InteriorFacetBasis(mesh, ElementLineP1(), side=0))
             for i in (0, 1)]
    if len(ends):
        f = np.array([np.flatnonzero(mesh.facets[0] == n)[0] for n in ends])
        bases.append((FacetBasis(mesh, E, facets=f), FacetBasis(mesh, ElementLineP1(), facets=f)))
    out = []
    for kind, y_sign in (("open", 1.0), ("open", -1.0), ("slide", 0.0)):
        total = 0
        for trial, test in bases:
            el = np.arange(trial.nelems) if getattr(trial, "tind", None) is None else trial.tind
            s = np.asarray(trial.default_parameters()["x"])[0]
            X, tj, nj = (g(s.ravel()).reshape((2,) + s.shape) for g in (curve.position, curve.tangent, curve.normal))
            h = np.broadcast_to(np.asarray(curve.thickness_at(s.ravel()), float), s.ravel().shape).reshape(s.shape)
            P, te, ne = (fr[k][:, el][:, :, None] for k in ("P", "t", "n"))
            sg = np.where(a[el][:, None] < s, -1.0, 1.0)
            Q = X + 0.5 * y_sign * h * nj - P
            d = tj if kind == "open" else nj
            total = total + asm(form, trial, test, a0=sg * (te[0] * d[0] + te[1] * d[1]),
                                a1=sg * (ne[0] * d[0] + ne[1] * d[1]), a2=sg * (Q[0] * d[1] - Q[1] * d[0]))
        out.append(sp.csr_matrix(total))
    return out


@pytest.mark.parametrize("make, n", [
    (lambda: CircularArch(), 40),
    (lambda: __import__("fembeam").PointedArch(span=1.0, rise=0.8, thickness=0.1), 41),       # a kink at the crown
    (lambda: __import__("fembeam").StraightMember(height=1.0, width=0.2), 7),                # a free end
    (lambda: __import__("fembeam").EllipticalArch(span=1.0, rise=0.2, thickness=0.02), 33),
    (lambda: CircularArch(thickness=0.3).with_thickness_scaled(0.5), 10),
])
def test_joint_rows_are_the_facet_form_of_scikit_fem(make, n):
    """The joint rows written as point evaluations equal scikit-fem's assembly of the
    facet form, on whole meshes and on a window of separate runs of elements."""
    from skfem import MeshLine1

    from fembeam.fem.rigid import _element_frames, _joint_rows

    curve = make()
    x = uniform_nodes(curve, n)
    runs = [np.arange(n), np.unique(np.r_[0:2, 3:4, n - 2:n])]     # the mesh, and three runs of it
    for e in runs:
        a, b = x[e], x[e + 1]
        p = np.unique(np.r_[a, b])
        mesh = MeshLine1(p[None, :], np.array([np.searchsorted(p, a), np.searchsorted(p, b)]))
        fr = _element_frames(curve, a, b)
        ends = np.array([i for i, end in zip((0, p.size - 1), curve.ends) if end == "joint"
                         and p[i] in (x[0], x[-1])], int)
        mine, ref = _joint_rows(curve, mesh, fr, ends), _facet_form_rows(curve, mesh, fr, ends)
        for A, B in zip(mine, ref):
            assert A.shape == B.shape
            assert abs(A - B).max() <= 1e-15 * abs(B).max()
            assert set(zip(*A.nonzero())) == set(zip(*B.nonzero()))


@pytest.mark.parametrize("make", [lambda: CircularArch(), lambda: __import__("fembeam").PointedArch(span=1.0, rise=0.8, thickness=0.1),
                                  lambda: __import__("fembeam").CatenaryArch(span=10.0, rise=4.0, thickness=0.5)])
def test_thickness_family_equals_the_assembly(make):
    """The operators of a thickness factor k from the two assemblies of the family
    (B_open linear in k, M = k M_1 + k^3 M_3) equal those assembled at k (a pointed arch's
    family is assembled at every k, on the nodes outside that k's crown wedges)."""
    from fembeam.fem.rigid import ThicknessFamily

    curve = make()
    nodes = uniform_nodes(curve, 150)
    fam = ThicknessFamily.of(curve, nodes)
    for k in (0.01, 0.3, 1.0, 1.7):
        ck = curve.with_thickness_scaled(k)
        a, b = fam.at(k), discretize(ck, nodes[ck.admissible(nodes)])
        for A, B in ((a.M, b.M), (a.B_open, b.B_open), (a.B_slide, b.B_slide)):
            assert abs(A - B).max() <= 1e-13 * abs(B).max()
        assert a.curve == b.curve and np.array_equal(a.joint_s, b.joint_s)


def test_densities_overridden_without_power():
    """A member overriding inertia_densities(s) in the old way still discretises; one that
    ignores ``power`` cannot build a thickness family (an error, not M(k) = (k + k^3) M)."""
    import dataclasses

    from fembeam.errors import SolverError
    from fembeam.fem.rigid import ThicknessFamily

    @dataclasses.dataclass(frozen=True)
    class Old(CircularArch):
        def inertia_densities(self, s):
            return CircularArch.inertia_densities(self, s)

    @dataclasses.dataclass(frozen=True)
    class Deaf(CircularArch):
        def inertia_densities(self, s, power=None):
            return CircularArch.inertia_densities(self, s)

    nodes = uniform_nodes(CircularArch(), 20)
    assert abs(discretize(Old(), nodes).M - discretize(CircularArch(), nodes).M).max() == 0.0
    with pytest.raises(SolverError, match="do not add up"):
        ThicknessFamily.of(Deaf(), nodes)
