"""The shared banded interior point (fembeam.analysis.banded_ipm) on small random QPs."""
import numpy as np
import pytest
from scipy.linalg.blas import dsbmv

from fembeam.analysis.banded_ipm import interior_point

BW = 3


def banded_qp(n: int, seed: int):
    """A random QP with a symmetric positive definite tridiagonal Q (stored with BW = 3): the
    dense Q and its lower and upper band storage, c, and the bounded rows I (every other row)."""
    rng = np.random.default_rng(seed)
    A = np.eye(n) + np.diag(rng.standard_normal(n - 1), -1)
    Q = A @ A.T + 0.1 * np.eye(n)
    return (Q, *band(Q), rng.standard_normal(n), np.arange(0, n, 2))


def band(Q):
    """``Q`` in LAPACK lower and upper band storage (half-bandwidth BW)."""
    n = Q.shape[0]
    lower, upper = np.zeros((BW + 1, n)), np.zeros((BW + 1, n))
    for k in range(BW + 1):
        lower[k, :n - k] = np.diag(Q, -k)
        upper[BW - k, k:] = np.diag(Q, k)
    return lower, upper


def solve(ab, c, I, lower, **kw):
    def converged(g, r, mu):
        return np.max(np.abs(r)) <= 1e-12 and mu <= 1e-14
    return interior_point(lambda g: dsbmv(BW, 1.0, ab, g, lower=lower) + c, ab, I,
                          np.where(np.isin(np.arange(c.size), I), 1.0, 0.0), np.ones(I.size), converged,
                          lower=lower, **kw)


@pytest.mark.parametrize("joint", [True, False])
def test_kkt_and_storages(joint):
    """Both storages give the same iterates; the answer satisfies the KKT conditions of
    min 1/2 g^T Q g + c^T g, g_I >= 0 (z the multipliers of the bounds)."""
    Q, lo, up, c, I = banded_qp(40, 0)
    a = solve(lo, c, I, True, joint_affine_step=joint)
    b = solve(up, c, I, False, joint_affine_step=joint)
    assert a is not None and b is not None and a[2] == b[2] and a[2] < 30
    g, z, _ = a
    assert np.max(np.abs(g - b[0])) <= 1e-12 * np.max(np.abs(g))
    r = Q @ g + c
    r[I] -= z
    assert np.max(np.abs(r)) <= 1e-10 and np.min(g[I]) > 0 and np.min(z) > 0
    assert np.max(g[I] * z) <= 1e-12
    active = z > 1e-6                                          # some bounds bind, some do not
    assert active.any() and not active.all()


def test_identity_rows_stay_zero():
    """Rows outside I with an identity row and a zero rate (a caller's rows that are no
    constraint) keep g = 0 exactly, and the others solve the QP without them."""
    Q, _, _, c, I = banded_qp(30, 1)
    off = np.array([5, 17])
    Qr, cr = Q.copy(), c.copy()
    Qr[off], Qr[:, off] = 0.0, 0.0
    Qr[off, off], cr[off] = 1.0, 0.0
    g, z, _ = solve(band(Qr)[0], cr, I, True)
    assert np.all(g[off] == 0.0)
    keep = np.setdiff1d(np.arange(30), off)
    r = Q[np.ix_(keep, keep)] @ g[keep] + c[keep]
    r[np.searchsorted(keep, I)] -= z
    assert np.max(np.abs(r)) <= 1e-10


def test_semidefinite_and_indefinite():
    """A singular Q whose null space is a bounded row with a positive cost converges (the
    Newton matrix is definite through z/g: g_0 -> 0, z_0 -> c_0); a Q that is not
    semidefinite ends with None."""
    Q, _, _, c, I = banded_qp(20, 2)
    Q[0], Q[:, 0], c[0] = 0.0, 0.0, 1.0
    g, z, _ = solve(band(Q)[0], c, I, True)
    assert g[0] <= 1e-12 and z[0] == pytest.approx(1.0, abs=1e-12)
    assert solve(band(Q - 50 * np.eye(20))[0], c, np.arange(0), True) is None
