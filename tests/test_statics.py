"""The equilibrium operator's factorisations (block-bidiagonal, banded, sparse) against
dense linear algebra, and the section forces of the part left of a section."""
import numpy as np
import pytest
import scipy.sparse as sp

from fembeam import CircularArch, StraightMember, discretize, uniform_nodes
from fembeam.analysis import statics as S
from fembeam.errors import SolverError
from fembeam.fem.p1 import discretize_p1


def block_bidiagonal(nb, side, rng):
    """A random matrix of 3x3 blocks on the diagonal and on the ``side`` (-1, +1) one."""
    K = np.kron(np.eye(nb), np.ones((3, 3))) * rng.uniform(0.5, 1.5, (3 * nb, 3 * nb)) + 2 * np.eye(3 * nb)
    K += np.kron(np.eye(nb, k=side), rng.uniform(-1, 1, (3, 3)))
    return K


@pytest.mark.parametrize("side", [-1, 1])
def test_block_bidiagonal_solves_like_a_dense_solve(side):
    rng = np.random.default_rng(1)
    K = block_bidiagonal(9, side, rng)
    C = sp.coo_matrix(K)
    lu = S._factorise(C.row, C.col, C.data, K.shape[0])
    assert isinstance(lu, S._BlockBidiagonal)
    for rhs in (rng.normal(size=27), rng.normal(size=(27, 4))):
        for trans, A in (("N", K), ("T", K.T)):
            x = S._refined(lu, A, rhs, trans)
            assert x.shape == rhs.shape
            assert np.abs(x - np.linalg.solve(A, rhs)).max() < 1e-13 * np.abs(x).max()


def test_factorisation_follows_the_pattern():
    rng = np.random.default_rng(2)
    tri = block_bidiagonal(6, -1, rng) + np.kron(np.eye(6, k=1), np.ones((3, 3)))   # block tridiagonal: banded
    wide = np.eye(30) + np.eye(30, k=20)                                              # neither
    for K, kind in ((tri, S._Banded), (wide, type(S.spla.splu(sp.csc_matrix(wide))))):
        C = sp.coo_matrix(K)
        lu = S._factorise(C.row, C.col, C.data, K.shape[0])
        assert isinstance(lu, kind)
        b = rng.normal(size=K.shape[0])
        assert np.abs(K @ lu.solve(b) - b).max() < 1e-12


def test_singular_block_is_a_solver_error():
    K = block_bidiagonal(4, -1, np.random.default_rng(3))
    K[3:6, 3:6] = 1.0                                                     # a rank-one diagonal block
    C = sp.coo_matrix(K)
    with pytest.raises(SolverError):
        S._factorise(C.row, C.col, C.data, K.shape[0])


@pytest.mark.parametrize("disc, kind", [
    (discretize(CircularArch(), uniform_nodes(CircularArch(), 40)), S._BlockBidiagonal),
    (discretize(StraightMember(2.0, 0.6), np.linspace(0.0, 2.0, 6)), S._BlockBidiagonal),   # free end
    (discretize_p1(CircularArch(), uniform_nodes(CircularArch(), 40)), S._BlockBidiagonal),
    (discretize_p1(CircularArch(), uniform_nodes(CircularArch(), 10), components="cartesian"), S._Banded),
])
def test_joint_forces_balance_the_loads(disc, kind):
    st = S.statics(disc)
    assert isinstance(st.lu, kind)
    B = sp.vstack([disc.B_slide, disc.B_open]).tocsr()
    fx, fy = disc.load_vectors()
    x, lam = np.array([0.3, 0.2, 0.1])[:st.k], 0.25
    g = st.forces(x, lam)
    p = fy - lam * fx
    assert np.abs(st.mass * (B.T @ g.ravel()) - p).max() < 1e-13 * np.abs(p).max() * disc.n_elements
    v = np.random.default_rng(4).normal(size=st.K.shape[0])             # and the transposed solves
    for trans, A in (("N", st.K), ("T", st.K.T)):
        assert np.abs(st.solve(A @ v, trans) - v).max() < 1e-12


def test_section_forces_are_the_rows_applied():
    arch = CircularArch()
    st = S.statics(discretize(arch, uniform_nodes(arch, 30)))
    s = np.linspace(0.0, arch.length, 101)
    x, lam = np.array([0.4, -0.1, 0.2]), 0.3
    rows = S.section_force_rows(st, s)
    assert rows.shape == (3, s.size, 5)
    f = S.section_forces(st, s, x, lam)
    assert np.abs(f - rows @ np.r_[x, lam, 1.0]).max() < 1e-14 * np.abs(f).max()
