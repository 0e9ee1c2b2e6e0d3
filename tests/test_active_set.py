"""The banded active-set solver of the impact QP against Clarabel, and its fallback."""
import numpy as np
import pytest

from fembeam import CircularArch, analyze
from fembeam.analysis.active_set import project_chain
from fembeam.analysis.impact import impact
from fembeam.analysis.verification import THRESHOLDS
from fembeam.geometry import EllipticalArch, ParabolicArch, PointedArch, StraightMember

CASES = [
    (CircularArch.from_ratio(157.5, 0.15), dict(elements=200)),
    (CircularArch.from_ratio(157.5, 0.15), dict(voussoirs=7)),
    (CircularArch.from_ratio(180.0, 0.2), dict(elements=1500)),
    (PointedArch(span=10.0, rise=7.0, thickness=0.8), dict(elements=300)),
    (EllipticalArch(span=10.0, rise=3.0, thickness=0.8), dict(elements=400)),
    (ParabolicArch(span=10.0, rise=3.0, thickness=0.6), dict(voussoirs=12)),
    (StraightMember(height=2.0, width=0.5), dict(voussoirs=1)),
]


@pytest.mark.parametrize("curve, kw", CASES, ids=lambda x: type(x).__name__ if not isinstance(x, dict) else str(x))
@pytest.mark.parametrize("direction", [1, -1])
def test_active_set_equals_clarabel(curve, kw, direction):
    """Same r, impulses and hinges as the interior-point QP; the KKT conditions hold to
    round-off and every verification figure is below its threshold."""
    res = analyze(curve, direction=direction, backend="clarabel", **kw)
    assert res.outcome == "rocking"
    disc, d0 = res.impact.disc, res.impact.d0
    a = impact(disc, d0, backend="active-set")
    b = res.impact
    assert a.backend == "active-set"
    assert a.r == pytest.approx(b.r, abs=1e-9)
    assert np.max(np.abs(a.mu - b.mu)) <= 1e-6 * np.max(np.abs(b.mu))
    assert [(h.joints, h.side) for h in a.hinges] == [(h.joints, h.side) for h in b.hinges]
    for k, v in a.verification.items():
        if k in THRESHOLDS:
            assert v <= THRESHOLDS[k] * 1e-2, k        # well inside the thresholds
    chain = project_chain(disc, d0)
    assert max(chain.kkt.values()) < 1e-9
    assert np.all(chain.mu >= 0) and np.all(chain.mu[chain.open] == 0)
    assert np.all((disc.B_open @ chain.d).reshape(2, -1)[~chain.open] == pytest.approx(0.0, abs=1e-12))


def test_arrested_block_is_certified():
    """A stocky block stops dead (r = 0): the block on one abutment is determinate, every
    row stays closed and the impulses certify that no compatible motion does work."""
    res = analyze(StraightMember(height=1.0, width=2.0), voussoirs=1, backend="clarabel")
    disc, d0 = res.impact.disc, res.impact.d0
    chain = project_chain(disc, d0)
    assert np.all(chain.d == 0.0) and not chain.open.any() and np.all(chain.mu > 0)
    a = impact(disc, d0, backend="active-set")
    assert a.backend == "active-set" and a.r == 0.0


def test_arrested_arch_falls_back_to_clarabel():
    """A thick shallow arch is arrested: with every row closed between two abutments the
    impulses are not unique (self-stress), the active set has no certified answer and the
    interior-point QP decides."""
    res = analyze(CircularArch.from_ratio(80.0, 0.15), elements=60, backend="clarabel")
    assert res.outcome == "arrested"
    disc, d0 = res.impact.disc, res.impact.d0
    assert project_chain(disc, d0) is None
    a = impact(disc, d0, backend="active-set")
    assert a.backend == "clarabel" and a.r < 1e-9


def test_auto_uses_the_active_set_on_fine_meshes():
    """``auto``: Clarabel up to 5000 elements, the active set above; same r."""
    arch = CircularArch.from_ratio(157.5, 0.15)
    fine = analyze(arch, elements=6000)
    assert fine.impact.backend == "active-set"
    ref = impact(fine.impact.disc, fine.impact.d0, backend="clarabel")
    assert fine.r == pytest.approx(ref.r, abs=1e-9)
    assert analyze(arch, elements=200).impact.backend == "clarabel"


def test_unknown_backend_is_an_input_error():
    from fembeam.errors import InputError
    res = analyze(CircularArch.from_ratio(157.5, 0.15), voussoirs=7)
    with pytest.raises(InputError, match="active-set"):
        impact(res.impact.disc, res.impact.d0, backend="simplex")


def test_glued_chain_is_the_coarse_mesh():
    """Elements glued in groups of K are the rigid pieces of the mesh of the group
    boundaries: the dual operator Q = B M^-1 B^T (invariant under a change of the
    pieces' DOFs) equals that of the coarse mesh assembled directly, and the glued
    pre-impact field keeps the momentum of d0."""
    from fembeam.analysis.active_set import _Dual, _glued
    from fembeam.fem import discretize, uniform_nodes

    arch = CircularArch.from_ratio(157.5, 0.15)
    disc = discretize(arch, uniform_nodes(arch, 203))          # 203 = 12 x 16 + 11: a short last group
    d0 = np.random.default_rng(0).normal(size=disc.M.shape[0])
    chain, q0 = _glued(disc, d0, 16)
    coarse = discretize(arch, disc.nodes_s[chain.joints])
    assert coarse.n_elements == 13 and chain.n_joints == coarse.n_joints
    a, b = _Dual(chain, q0), _Dual(coarse, coarse.rigid(V=(1.0, 0.0)))
    assert np.max(np.abs((a.Q - b.Q).toarray())) <= 1e-10 * np.max(np.abs(b.Q.toarray()))
    lead = np.arange(0, disc.n_elements, 16)
    t, n = disc.frames["t"][:, lead], disc.frames["n"][:, lead]
    for V in [np.array([1.0, 0.0]), np.array([0.0, 1.0])]:
        rigid_q = np.stack([V @ t, V @ n, np.zeros(lead.size)], 1).ravel()   # translation V, glued DOFs
        assert float(rigid_q @ chain.M @ q0) == pytest.approx(float(disc.rigid(V=V) @ disc.M @ d0), rel=1e-12)


@pytest.mark.parametrize("beta, t_over_r, direction", [(157.5, 0.15, 1), (180.0, 0.2, -1), (100.0, 0.1, 1)])
def test_multilevel_start_gives_the_same_projection(monkeypatch, beta, t_over_r, direction):
    """The open rows guessed on glued chains (coarsest 62 pieces of 64 elements and a short
    last one, here) lead the active set to the same certified projection as the interior
    point's rows, without an interior point on the mesh itself."""
    import fembeam.analysis.active_set as A

    res = analyze(CircularArch.from_ratio(beta, t_over_r), elements=4001, direction=direction, backend="clarabel")
    disc, d0 = res.impact.disc, res.impact.d0
    monkeypatch.setattr(A, "MULTILEVEL_ELEMENTS", 10 ** 9)
    ref = A.project_chain(disc, d0)
    monkeypatch.setattr(A, "MULTILEVEL_ELEMENTS", 1000)
    monkeypatch.setattr(A, "COARSE_ELEMENTS", 60)
    sizes = []
    ipm = A._Dual.interior_point
    monkeypatch.setattr(A._Dual, "interior_point", lambda self, *a, **k: sizes.append(self.J) or ipm(self, *a, **k))
    ml = A.project_chain(disc, d0)
    assert sizes == [64]                      # the coarsest glued chain only: joints 0, 64, ..., 3968, 4001
    assert ml is not None and max(ml.kkt.values()) < 1e-9
    assert np.array_equal(ml.open, ref.open)
    assert np.max(np.abs(ml.d - ref.d)) <= 1e-9 * np.max(np.abs(ref.d))
    assert np.max(np.abs(ml.mu - ref.mu)) <= 1e-8 * np.max(np.abs(ref.mu))
    assert float(ml.d @ disc.M @ ml.d) / float(d0 @ disc.M @ d0) == pytest.approx(res.r, abs=1e-9)


def test_a_failed_guess_hands_over_to_the_interior_point(monkeypatch):
    """A guess that leads nowhere (every row closed: the zones would have to grow joint by
    joint) is dropped and the interior point on the mesh decides: the same projection."""
    import fembeam.analysis.active_set as A

    res = analyze(CircularArch.from_ratio(157.5, 0.15), elements=4001, backend="clarabel")
    disc, d0 = res.impact.disc, res.impact.d0
    ref = A.project_chain(disc, d0)
    monkeypatch.setattr(A, "MULTILEVEL_ELEMENTS", 1000)
    monkeypatch.setattr(A, "_coarse_open", lambda disc, d0, m, **k: (np.zeros(3 * disc.n_joints, bool), 0))
    sizes = []
    ipm = A._Dual.interior_point
    monkeypatch.setattr(A._Dual, "interior_point", lambda self, *a, **k: sizes.append(self.J) or ipm(self, *a, **k))
    out = A.project_chain(disc, d0)
    assert sizes == [disc.n_joints]
    assert np.array_equal(out.open, ref.open) and out.steps == ref.steps


def test_prolong_opens_between_open_coarse_joints():
    from fembeam.analysis.active_set import _prolong

    coarse = np.array([0, 4, 8, 10])
    o = np.zeros((4, 3), bool)
    o[1, 1] = o[2, 1] = True          # fibre 1 open at joints 4 and 8
    o[3, 2] = True                    # fibre 2 open at the last joint only
    out = _prolong(o.ravel(), coarse, np.arange(11)).reshape(11, 3)
    assert not out[:, 0].any()
    assert np.flatnonzero(out[:, 1]).tolist() == [4, 5, 6, 7, 8]
    assert np.flatnonzero(out[:, 2]).tolist() == [10]


def test_primal_dual_steps_only_on_large_chains(monkeypatch):
    """Chains above the size where Q's round-off reaches the rates take primal-dual steps
    only (glued levels and the mesh): the same certified projection (the thresholds are
    lowered here so that a 4001-element mesh takes those routes)."""
    import fembeam.analysis.active_set as A

    res = analyze(CircularArch.from_ratio(157.5, 0.15), elements=4001, backend="clarabel")
    disc, d0 = res.impact.disc, res.impact.d0
    ref = A.project_chain(disc, d0)
    for name, value in (("MULTILEVEL_ELEMENTS", 1000), ("COARSE_ELEMENTS", 60), ("GUESS_Q_JOINTS", 100),
                        ("Q_JOINTS", 1000)):
        monkeypatch.setattr(A, name, value)
    kkt_sizes = []
    solve = A._KKT.solve
    monkeypatch.setattr(A._KKT, "solve", lambda self, o: kkt_sizes.append(self.J) or solve(self, o))
    out = A.project_chain(disc, d0)
    assert {252, 1002, 4002} <= set(kkt_sizes)    # joints of the glued chains (K = 16, 4) and of the mesh
    assert out is not None and max(out.kkt.values()) < 1e-9 and np.array_equal(out.open, ref.open)
    assert np.max(np.abs(out.d - ref.d)) <= 1e-9 * np.max(np.abs(ref.d))


def _chain(curve, elements, K=1):
    """A mesh of ``elements`` (glued in groups of ``K``) and a random pre-impact field."""
    from fembeam.analysis.active_set import _glued
    from fembeam.fem import discretize, uniform_nodes

    disc = discretize(curve, uniform_nodes(curve, elements))
    d0 = np.random.default_rng(0).normal(size=disc.M.shape[0])
    return _glued(disc, d0, K) if K > 1 else (disc, d0)


@pytest.mark.parametrize("curve, elements, K", [
    (CircularArch.from_ratio(157.5, 0.15), 203, 1),
    (CircularArch.from_ratio(157.5, 0.15), 203, 16),              # a glued chain (short last piece)
    (PointedArch(span=10.0, rise=7.0, thickness=0.8), 300, 1),
    (StraightMember(height=2.0, width=0.5), 5, 1),                # a free end: J = n
    (StraightMember(height=2.0, width=0.5), 1, 1),                # one element, one joint
])
def test_chain_band_equals_the_sparse_product(curve, elements, K):
    """Q summed element by element (the chain's blocks) is the sparse product
    m B M^-1 B^T to round-off, in the same band storage."""
    from fembeam.analysis.active_set import _Dual, _product_q

    disc, d0 = _chain(curve, elements, K)
    P = _Dual(disc, d0)
    assert P.blocks is not None
    ref = _product_q(P.B, disc.M.tocsr(), P.m)
    assert P.lower.shape == ref.shape
    assert np.max(np.abs(P.lower - ref)) <= 1e-12 * np.max(np.abs(ref))
    g = np.random.default_rng(1).normal(size=3 * P.J)
    assert np.max(np.abs(P.rates(g) - (P.Q @ g + P.c))) <= 1e-12 * np.max(np.abs(P.rates(g)))


@pytest.mark.parametrize("K", [1, 16])
def test_kkt_band_from_blocks_equals_the_entries(K):
    """The primal-dual band built from a chain's blocks is the one scattered from the
    sparse entries (any pattern), and both solve alike."""
    import copy

    from fembeam.analysis.active_set import _KKT, _Dual

    disc, d0 = _chain(CircularArch.from_ratio(157.5, 0.15), 203, K)
    P = _Dual(disc, d0)
    Q = copy.copy(P)
    Q.blocks = None
    a, b = _KKT(disc, d0, P), _KKT(disc, d0, Q)
    assert a.chain is not None and b.chain is None and (a.l, a.u) == (b.l, b.u) == (5, 5)
    assert np.max(np.abs(a.band() - b.band())) <= 1e-15 * np.max(np.abs(b.band()))
    open_ = P.fibre & (np.random.default_rng(2).random(3 * P.J) < 0.3)
    for x, y in zip(a.solve(open_), b.solve(open_)):
        assert np.max(np.abs(x - y)) <= 1e-12 * np.max(np.abs(y))


def test_elements_out_of_order_take_the_general_path():
    """With the elements numbered out of order the pattern is not a chain's: Q comes from
    the sparse product (it does not depend on the numbering) and the primal-dual band
    from the entries; the projection is the same."""
    from types import SimpleNamespace

    from fembeam.analysis.active_set import _Dual
    from fembeam.analysis.limit import limit_analysis
    from fembeam.fem import discretize, uniform_nodes

    arch = CircularArch.from_ratio(157.5, 0.15)
    disc = discretize(arch, uniform_nodes(arch, 40))
    d0 = -limit_analysis(disc).u                                 # the collapse mechanism, reversed
    order = np.random.default_rng(3).permutation(disc.n_elements)
    dofs = (3 * order[:, None] + np.arange(3)).ravel()           # new DOF i is old DOF dofs[i]
    mixed = SimpleNamespace(M=disc.M.tocsr()[dofs][:, dofs], B_slide=disc.B_slide.tocsr()[:, dofs],
                            B_open=disc.B_open.tocsr()[:, dofs], curve=disc.curve,
                            n_joints=disc.n_joints, n_elements=disc.n_elements)
    P, R = _Dual(mixed, d0[dofs]), _Dual(disc, d0)
    assert P.blocks is None and R.blocks is not None
    assert np.max(np.abs(P.lower - R.lower)) <= 1e-12 * np.max(np.abs(R.lower))
    a, b = project_chain(mixed, d0[dofs]), project_chain(disc, d0)
    assert np.array_equal(a.open, b.open) and a.steps == b.steps
    assert np.max(np.abs(a.d - b.d[dofs])) <= 1e-10 * np.max(np.abs(b.d))
    assert np.max(np.abs(a.mu - b.mu)) <= 1e-10 * np.max(np.abs(b.mu))


def test_glued_twice_is_glued_once():
    """Gluing a glued chain in groups of 4 is gluing the mesh in groups of 16 (the levels
    of the multilevel guess are built so): same joints, operators and field."""
    from fembeam.analysis.active_set import _glued

    disc, d0 = _chain(CircularArch.from_ratio(157.5, 0.15), 203, 1)
    once, q = _glued(disc, d0, 16)
    twice, q2 = _glued(*_glued(disc, d0, 4), 4)
    assert np.array_equal(once.joints, twice.joints)
    for x, y in ((once.M, twice.M), (once.B, twice.B)):
        assert abs(x - y).max() <= 1e-12 * abs(x).max()
    assert np.max(np.abs(q - q2)) <= 1e-12 * np.max(np.abs(q))


def test_a_member_without_abutment_is_an_input_error():
    """Free at both ends: its rigid motions are not held, and the projection says so
    instead of indexing past its band."""
    from fembeam import discretize, uniform_nodes
    from fembeam.errors import InputError

    m = StraightMember(ends=("free", "free"))
    disc = discretize(m, uniform_nodes(m, 10))
    with pytest.raises(InputError, match="abutment"):
        project_chain(disc, np.ones(disc.M.shape[0]))
