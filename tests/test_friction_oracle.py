"""The frictional step's solvers against an exact oracle on small contact problems.

A step's contact problem is ``w = W P + c`` (``W = H M^-1 H^T``, rows ``3 j``, ``3 j + 1`` the
opening rates of joint ``j``'s corners, ``3 j + 2`` its sliding rate; m/s and N s/m).  With up to
three joints Coulomb's law has finitely many cases: each closed corner pressed (``w = 0``) or
open (``P = 0``), each closed joint sticking (``w_t = 0``) or sliding either way
(``P_t = -+ mu N``).  Every case is one linear system; the oracle solves them all (NumPy) and keeps
the solutions that satisfy all of Coulomb's conditions.  Each stage of the kernel (the sticking
MLCP, the self-stress redistribution, the Tresca fixed point, semi-smooth Newton, non-smooth
Gauss-Seidel, Lemke's pivots) and the whole step (:func:`fembeam.simulation.kernel._project`
with its counters ``solved_by``, ``loose_steps`` and the Coulomb residual) are compared with it on
random problems: the same percussions where the oracle's solution is unique, else one of its
solutions' rates and an independent check of Coulomb's law.
"""
from itertools import product

import numpy as np
import pytest
from scipy.linalg import null_space
from scipy.optimize import linprog

from fembeam.simulation import constants as C
from fembeam.simulation import kernel as K

SEEDS = range(40)
REL = 1e-8            # the oracle's tolerance on its own conditions (relative to the scales)


# ----------------------------------------------------------------------------------------- problems
def problem(seed: int, redundant: bool = False):
    """A random chain of rigid bodies with 1-3 joints, in the kernel's storage: ``rows``
    ``(J, 3, 2, 3)``, ``sides`` ``(J, 2)`` (body ``n`` the ground), ``minv`` ``(n + 1, 3)``, the free
    velocities ``v`` ``(n + 1, 3)`` (m/s, rad/s), the closed corners ``(J, 2)`` and ``mu``.
    ``redundant``: both ends on the ground (J - 1 bodies between two abutments: ``W`` singular,
    three self-stress states when every joint is closed)."""
    rng = np.random.default_rng(seed)
    J = int(rng.integers(2 if redundant else 1, 4))
    n = J - 1 if redundant else J
    sides = np.empty((J, 2), np.int64)
    for j in range(J):
        sides[j] = (n if j == 0 else j - 1, j if j < n else n)
    rows = rng.normal(size=(J, 3, 2, 3))
    minv = np.zeros((n + 1, 3))
    minv[:n] = rng.uniform(0.5, 2.0, size=(n, 3))
    v = np.zeros((n + 1, 3))
    v[:n] = rng.normal(size=(n, 3))
    closed = rng.random((J, 2)) < 0.8
    closed[0, 0] = True                        # at least one closed corner
    if redundant:
        closed[:] = True
    mu = float(rng.choice([0.1, 0.3, 0.6, 1.0, 2.0]))
    return rows, sides, minv, v, closed, mu


def operators(rows, sides, minv, v):
    """``W`` (dense), its band ``ab`` and ``c = H v`` built here in NumPy (not by the kernel)."""
    J, n1 = sides.shape[0], minv.shape[0]
    H = np.zeros((3 * J, 3 * n1))
    for j in range(J):
        for s in range(2):
            b = sides[j, s]
            H[3 * j:3 * j + 3, 3 * b:3 * b + 3] += rows[j, :, s, :]
    W = H @ np.diag(minv.ravel()) @ H.T
    m = 3 * J
    ab = np.zeros((C.BAND + 1, m))
    for k in range(m):
        for i in range(max(0, k - C.BAND), k + 1):
            ab[C.BAND + i - k, k] = W[i, k]
    return W, ab, H @ v.ravel()


def masks(closed):
    J = closed.shape[0]
    nonneg = np.zeros(3 * J, bool)
    nonneg[0::3], nonneg[1::3] = closed[:, 0], closed[:, 1]
    cj = closed.any(axis=1)
    free = np.zeros(3 * J, bool)
    free[2::3] = cj
    return nonneg, cj, free


# ------------------------------------------------------------------------------------------- oracle
def violation(P, w, closed, mu, vscale, pscale):
    """The largest violation of Coulomb's law by ``P``, ``w`` (relative to ``vscale`` m/s and
    ``pscale`` N s/m): signs and complementarity at the closed corners, no percussion at the open
    ones, the cone, no sliding inside it and sliding against ``P_t`` on it."""
    J = closed.shape[0]
    out = 0.0
    for j in range(J):
        for r in range(2):
            i = 3 * j + r
            if closed[j, r]:
                out = max(out, -P[i] / pscale, -w[i] / vscale, min(abs(P[i]) / pscale, abs(w[i]) / vscale))
            else:
                out = max(out, abs(P[i]) / pscale)
        Pt, wt = P[3 * j + 2], w[3 * j + 2]
        if not closed[j].any():
            out = max(out, abs(Pt) / pscale)
            continue
        if np.isinf(mu):                                           # no sliding
            out = max(out, abs(wt) / vscale)
            continue
        N = P[3 * j] + P[3 * j + 1]
        out = max(out, (abs(Pt) - mu * N) / pscale)
        slack = (mu * N - abs(Pt)) / pscale                        # inside the cone: w_t = 0
        out = max(out, min(slack, abs(wt) / vscale))
        if abs(wt) > 0:                                            # sliding: P_t = -mu N sign(w_t)
            out = max(out, min(abs(Pt + mu * N * np.sign(wt)) / pscale, abs(wt) / vscale))
    return out


def oracle(W, c, closed, mu):
    """Every solution ``(P, w)`` of the frictional problem, by enumeration of its cases (``mu``
    inf: the joints stick).  Singular cases are solved in the least-squares sense and kept only if
    consistent."""
    J = closed.shape[0]
    m = 3 * J
    corners = [(0, 1) if closed[j, r] else (0,) for j in range(J) for r in range(2)]
    slides = [((0,) if np.isinf(mu) else (0, 1, -1)) if closed[j].any() else (0,) for j in range(J)]
    vscale = max(np.max(np.abs(c)), 1e-300)
    found = []
    for press in product(*corners):
        for slide in product(*slides):
            A, b = np.zeros((m, m)), np.zeros(m)
            for j in range(J):
                for r in range(2):
                    i = 3 * j + r
                    if press[2 * j + r]:
                        A[i], b[i] = W[i], -c[i]              # pressed: w_i = 0
                    else:
                        A[i, i] = 1.0                         # open: P_i = 0
                i = 3 * j + 2
                if not closed[j].any():
                    A[i, i] = 1.0
                elif slide[j] == 0:
                    A[i], b[i] = W[i], -c[i]                  # stick: w_t = 0
                else:                                         # slide: P_t = s mu N
                    A[i, i], A[i, i - 1], A[i, i - 2] = 1.0, -slide[j] * mu, -slide[j] * mu
            P = np.linalg.lstsq(A, b, rcond=None)[0]
            w = W @ P + c
            pscale = max(np.max(np.abs(P)), vscale / np.max(np.diag(W)))
            if np.max(np.abs(A @ P - b)) > 1e-9 * max(vscale, pscale * np.max(np.abs(A))):
                continue
            if violation(P, w, closed, mu, vscale, pscale) <= REL:
                if not any(np.allclose(P, Q, atol=1e-9 * pscale) for Q, _ in found):
                    found.append((P, w))
    return found


def matches(P, w, found, pscale, vscale, tol):
    """``P``, ``w`` is one of the oracle's solutions: the same percussions if it has one solution,
    else the same rates as one of them."""
    if len(found) == 1:
        return np.max(np.abs(P - found[0][0])) <= tol * pscale and np.max(np.abs(w - found[0][1])) <= tol * vscale
    return any(np.max(np.abs(w - wf)) <= tol * vscale for _, wf in found)


# ------------------------------------------------------------------------------------------- stages
def stick(ab, c, closed):
    """The sticking solution by the kernel's MLCP solver (:func:`~fembeam.simulation.kernel.solve_mlcp`)."""
    nonneg, _, free = masks(closed)
    m = c.size
    F, U, P, w = np.zeros(m, bool), np.zeros((m, C.BAND + 1)), np.zeros(m), np.zeros(m)
    vscale = float(np.max(np.abs(c)))
    status, _, _ = K.solve_mlcp(ab, c, free, nonneg, F, False, vscale, C.BLOCK_PIVOTS, U, P, w, C.KKT_TOL)
    return status, P, w, F


@pytest.mark.parametrize("seed", SEEDS)
def test_the_oracle_finds_the_solution_of_a_positive_definite_problem(seed):
    """A positive definite ``W`` has a solution for every ``mu`` (the oracle must find at least one),
    and without friction exactly one."""
    rows, sides, minv, v, closed, mu = problem(seed)
    W, ab, c = operators(rows, sides, minv, v)
    assert len(oracle(W, c, closed, mu)) >= 1
    assert len(oracle(W, c, closed, np.inf)) == 1


@pytest.mark.parametrize("seed", SEEDS)
def test_stick_is_the_oracle_without_sliding(seed):
    """The sticking MLCP is the oracle's unique solution with ``mu = inf``: percussions to 1e-6 (the
    solver stops at a KKT residual of ``KKT_TOL`` = 1e-8; measured up to 1.5e-8, seed 17)."""
    rows, sides, minv, v, closed, mu = problem(seed)
    W, ab, c = operators(rows, sides, minv, v)
    status, P, w, _ = stick(ab, c, closed)
    (Po, wo), = oracle(W, c, closed, np.inf)
    assert status == 0
    pscale = max(np.max(np.abs(Po)), 1e-300)
    assert np.max(np.abs(P - Po)) <= 1e-6 * pscale
    assert np.max(np.abs(w - wo)) <= 1e-6 * np.max(np.abs(c))


@pytest.mark.parametrize("seed", SEEDS)
def test_redistribution_is_a_self_stress_into_the_cone(seed):
    """Between two abutments (``W`` singular) the sticking percussions are determined up to the
    self-stress states.  :func:`~fembeam.simulation.kernel.redistribute` must find a combination
    inside the cone exactly when one exists with a margin (decided here by a linear program on
    SciPy's null space of ``W``), and leave the rates unchanged."""
    rows, sides, minv, v, closed, mu = problem(seed, redundant=True)
    W, ab, c = operators(rows, sides, minv, v)
    nonneg, cj, _ = masks(closed)
    status, P, w, F = stick(ab, c, closed)
    assert status == 0
    m = c.size
    dmax = float(np.max(np.diag(W)))
    vscale = float(np.max(np.abs(c)))
    pscale = max(np.max(np.abs(P)), vscale / dmax)
    margin = 1e-9 * pscale
    U, Z = np.zeros((m, C.BAND + 1)), np.zeros((m, 4))
    k = K.self_stress(ab, F, C.REG * dmax, U, Z)
    # the LP: P + Z s with P_n >= 1e-6 pscale on F, |P_t| <= mu N - 1e-6 pscale (a margin well
    # above the kernel's) is feasible => the kernel must succeed
    Zs = null_space(W[np.ix_(F, F)])
    Zf = np.zeros((m, Zs.shape[1]))
    Zf[F] = Zs
    A, b = [], []
    big = 1e-6 * pscale
    for j in range(closed.shape[0]):
        for r in range(2):
            i = 3 * j + r
            if nonneg[i] and F[i]:
                A.append(-Zf[i]), b.append(P[i] - big)
        if cj[j]:
            for s in (1.0, -1.0):
                A.append(s * Zf[3 * j + 2] - mu * (Zf[3 * j] + Zf[3 * j + 1]))
                b.append(-s * P[3 * j + 2] + mu * (P[3 * j] + P[3 * j + 1]) - big)
    lp = linprog(np.zeros(Zf.shape[1]), A_ub=np.array(A), b_ub=np.array(b), bounds=(None, None)) \
        if Zf.shape[1] else None
    assert k == Zs.shape[1]
    Q = P.copy()
    ok = K.redistribute(Q, Z, k, nonneg, F, cj, mu, margin)
    if lp is not None and lp.status == 0:
        assert ok
    if ok:
        assert np.max(np.abs(W @ Q + c - w)) <= 1e-9 * vscale                 # the same rates
        assert violation(Q, W @ Q + c, closed, mu, vscale, pscale) <= 1e-8    # a Coulomb solution
        assert matches(Q, W @ Q + c, oracle(W, c, closed, mu), pscale, vscale, 1e-7)


def _stage(name, ab, c, closed, mu, P):
    nonneg, cj, _ = masks(closed)
    m = c.size
    vscale = float(np.max(np.abs(c)))
    dmax = float(np.max(ab[C.BAND]))
    w = np.zeros(m)
    if name == "fixed_point":
        box = np.zeros(m, np.int64)
        st, _, res = K.solve_friction(ab, c, nonneg, cj, mu, vscale, box, np.zeros((m, C.BAND + 1)), P, w,
                                      C.COULOMB_TOL)
        ok = st == 0
    elif name == "newton":
        ok, _, res = K.semismooth_newton(ab, c, nonneg, cj, mu, vscale, 1e-9 * dmax, C.COULOMB_TOL, P, w)
    elif name == "gauss_seidel":
        ok, _, res = K.nsgs(ab, c, nonneg, cj, mu, vscale, C.REG * dmax, C.COULOMB_TOL, P, w)
    else:
        ok, _, res = K.lemke_friction(ab, c, nonneg, cj, mu, vscale, C.REG * dmax, P, w)
        ok = ok and res <= C.COULOMB_TOL
    return bool(ok), float(res), P, w


STAGES = ["fixed_point", "newton", "gauss_seidel", "lemke"]


@pytest.mark.parametrize("name", STAGES)
def test_each_frictional_stage_against_the_oracle(name):
    """Each stage from the sticking solution (as the step calls them) on 40 random positive definite
    problems: a solution it reports is the oracle's (percussions to 1e-4 relative where unique:
    the stages stop at a Coulomb residual of 1e-5), and its reported residual is the independent
    one within a factor 10.  Lemke's pivots, exact in the plane, solve every one."""
    solved = 0
    for seed in SEEDS:
        rows, sides, minv, v, closed, mu = problem(seed)
        W, ab, c = operators(rows, sides, minv, v)
        _, P, _, _ = stick(ab, c, closed)
        ok, res, P, w = _stage(name, ab, c, closed, mu, P.copy())
        vscale = float(np.max(np.abs(c)))
        pscale = max(np.max(np.abs(P)), vscale / float(np.max(np.diag(W))))
        mine = violation(P, W @ P + c, closed, mu, vscale, pscale)
        if ok:                          # (a stage that gives up may leave the rates of an earlier iterate)
            assert np.allclose(w, W @ P + c, atol=1e-12 * vscale)
            solved += 1
            assert mine <= 10 * C.COULOMB_TOL, (seed, mine, res)
            assert matches(P, w, oracle(W, c, closed, mu), pscale, vscale, 1e-4), seed
    assert solved >= (len(SEEDS) if name == "lemke" else len(SEEDS) // 2), solved


@pytest.mark.parametrize("redundant", [False, True])
def test_the_step_reports_what_solved_it(redundant):
    """The whole frictional step (:func:`~fembeam.simulation.kernel._project`): a solved step is the
    oracle's solution (positive definite: its percussions; redundant: its rates), the counters
    say which stage solved it (exactly one of stick in the cone, redistribution, fixed point,
    Newton, Gauss-Seidel, Lemke, or a loose step), and the reported Coulomb residual bounds the
    independent one up to the factor between the two scalings (10)."""
    keys = [K.I_REDIST, K.I_BY_FP, K.I_BY_SSN, K.I_BY_NSGS, K.I_BY_LEMKE, K.I_LOOSE]
    for seed in SEEDS:
        rows, sides, minv, v, closed, mu = problem(seed, redundant)
        W, ab, c = operators(rows, sides, minv, v)
        J, m = closed.shape[0], c.size
        ab_k, U, P, w, cc, Z = (np.zeros((C.BAND + 1, m)), np.zeros((m, C.BAND + 1)), np.zeros(m), np.zeros(m),
                                np.zeros(m), np.zeros((m, 4)))
        dump = (np.zeros((C.BAND + 1, m)), np.zeros(m), np.zeros(m), np.zeros((J, 2), bool))
        fs, ist = np.zeros(K.N_FLOAT), np.zeros(K.N_INT, np.int64)
        F, box = np.zeros(m, bool), np.zeros(m, np.int64)
        st = K._project(rows, sides, minv, v, closed, F, False, box, mu, 0.0, C.BLOCK_PIVOTS, ab_k, U, P, w, cc, Z,
                        *dump, fs, ist, 0.0, 0, C.KKT_TOL, C.COULOMB_TOL)
        assert np.allclose(ab_k, ab, atol=1e-12 * np.max(np.abs(ab))) and np.allclose(cc, c)
        assert st == 0, seed
        vscale = float(np.max(np.abs(c)))
        pscale = max(np.max(np.abs(P)), vscale / float(np.max(np.diag(W))))
        counted = ist[keys]
        assert counted.sum() <= 1 and ist[K.I_SLIDING] == counted[1:].sum()
        mine = violation(P, W @ P + c, closed, mu, vscale, pscale)
        if counted.sum() == 0:                       # the sticking solution lies in the cone
            assert mine <= 1e-8 and fs[K.F_COULOMB] == 0.0
        elif ist[K.I_LOOSE]:
            assert C.COULOMB_TOL < fs[K.F_COULOMB] <= C.LOOSE * C.COULOMB_TOL
        else:
            assert fs[K.F_COULOMB] <= C.COULOMB_TOL and mine <= 10 * C.COULOMB_TOL
        if not ist[K.I_LOOSE]:
            assert matches(P, w, oracle(W, c, closed, mu), pscale, vscale, 1e-4), seed


def test_newtons_banded_elimination_is_a_dense_solve():
    """Newton's systems (:func:`~fembeam.simulation.kernel._band_solve`: threshold pivoting in band
    storage, each row's last nonzero tracked) against NumPy's dense solve, on random band matrices
    with rows of ``W``'s scales (a tangential row a quarter of the normal ones), identity rows
    (``P_i = 0``) and sliding rows (``P_t -+ mu N = 0``), in the proportions of a step."""
    rng = np.random.default_rng(0)
    kl = C.BAND
    for trial in range(200):
        m = 3 * int(rng.integers(1, 40))
        D = np.zeros((m, m))
        for i in range(m):
            for k in range(max(0, i - kl), min(m, i + kl + 1)):
                D[i, k] = rng.normal() * (0.25 if (i % 3 == 2) != (k % 3 == 2) else 1.0)
            D[i, i] += 3.0
            u = rng.random()
            if u < 0.2:
                D[i] = 0.0
                D[i, i] = 1.0
            elif u < 0.35 and i % 3 == 2:
                D[i] = 0.0
                D[i, i], D[i, i - 1], D[i, i - 2] = 1.0, -0.6, -0.6
        A = np.zeros((m, 3 * kl + 1))
        for i in range(m):
            for k in range(max(0, i - kl), min(m, i + kl + 1)):
                A[i, kl + k - i] = D[i, k]
        b = rng.normal(size=m)
        x = np.zeros(m)
        assert K._band_solve(A, b.copy(), kl, x)
        exact = np.linalg.solve(D, b)
        assert np.max(np.abs(x - exact)) <= 1e-12 * np.linalg.cond(D) * max(1.0, np.max(np.abs(exact))), trial


def test_a_resumed_banded_factorisation_is_a_dense_solve():
    """Newton's iterations change a few rows of their system (a corner pressed or released, a joint
    sliding or sticking): :func:`~fembeam.simulation.kernel._band_factor` resumes the last
    elimination at the checkpoint before the first changed row less the bandwidth.  On random
    band matrices as above, after rows of the matrix and the right-hand side replaced from a
    random row on (1-3 of them, rank-k changes, and once all rows from there), the resumed
    elimination solves as NumPy's dense solve of the new system does and is bitwise the
    elimination from column 0."""
    rng = np.random.default_rng(1)
    kl, width, S = C.BAND, 3 * C.BAND + 1, K.CHECKPOINT

    def band_rows(m):
        D = np.zeros((m, m))
        for i in range(m):
            u = rng.random()
            if u < 0.2:
                D[i, i] = 1.0                                  # P_i = 0
            elif u < 0.35 and i % 3 == 2:
                D[i, i], D[i, i - 1], D[i, i - 2] = 1.0, -0.6, -0.6  # sliding
            else:
                for k in range(max(0, i - kl), min(m, i + kl + 1)):
                    D[i, k] = rng.normal() * (0.25 if (i % 3 == 2) != (k % 3 == 2) else 1.0)
                D[i, i] += 3.0
        return D

    def eliminate(D, b, A, y, j0, last, saved, saved_last):
        """Rows j0.. of D and b stored (as Newton assembles them), the elimination resumed at j0."""
        m = D.shape[0]
        for i in range(j0, m):
            A[i] = 0.0
            for k in range(max(0, i - kl), min(m, i + kl + 1)):
                A[i, kl + k - i] = D[i, k]
        y[j0:] = b[j0:]
        last[j0:] = np.minimum(np.arange(j0, m) + kl + 1, m)
        assert K._band_factor(A, y, kl, j0, last, saved, saved_last)

    for trial in range(100):
        m = 3 * int(rng.integers(4, 60))
        D, b = band_rows(m), rng.normal(size=m)
        A, y, last = np.zeros((m, width)), np.zeros(m), np.zeros(m, np.int64)
        saved, saved_last = np.zeros((m // S + 1, kl, width + 1)), np.zeros((m // S + 1, kl), np.int64)
        eliminate(D, b, A, y, 0, last, saved, saved_last)
        for change in range(3):
            first = int(rng.integers(0, m))
            new = band_rows(m)
            rows = np.arange(first, m) if change == 2 else \
                np.unique(np.r_[first, rng.integers(first, m, size=int(rng.integers(0, 3)))])
            D[rows] = new[rows]
            b[rows] = rng.normal(size=rows.size)
            eliminate(D, b, A, y, max(first - kl, 0) // S * S, last, saved, saved_last)
            x = np.zeros(m)
            K._band_back(A, kl, last, y, x)
            exact = np.linalg.solve(D, b)
            assert np.max(np.abs(x - exact)) <= 1e-12 * np.linalg.cond(D) * max(1.0, np.max(np.abs(exact))), trial
            A0 = np.zeros((m, width))
            for i in range(m):
                for k in range(max(0, i - kl), min(m, i + kl + 1)):
                    A0[i, kl + k - i] = D[i, k]
            x0 = np.zeros(m)
            assert K._band_solve(A0, b.copy(), kl, x0)
            assert np.array_equal(x, x0), trial


def test_a_resumed_cholesky_factor_is_a_dense_solve():
    """The box pivots of the Tresca fixed point change the free rows a few at a time:
    :func:`~fembeam.simulation.kernel.factor` resumed at the first changed row less the bandwidth
    solves ``W`` restricted to the new free rows (identity rows elsewhere) as NumPy's dense solve
    does, and is bitwise the factor from row 0, on random positive definite band matrices."""
    rng = np.random.default_rng(2)
    kl = C.BAND
    for trial in range(100):
        m = 3 * int(rng.integers(4, 60))
        H = np.zeros((m, m + kl))
        for i in range(m):
            H[i, i:i + kl + 1] = rng.normal(size=kl + 1)
        W = H @ H.T + 0.1 * np.eye(m)                    # half-bandwidth kl
        ab = np.zeros((kl + 1, m))
        for k in range(m):
            for i in range(max(0, k - kl), k + 1):
                ab[kl + i - k, k] = W[i, k]
        keep = rng.random(m) < 0.7
        U = np.zeros((m, kl + 1))
        zero = np.zeros(m)
        assert K.factor(ab, keep, 1e-9, zero, U)
        for change in range(3):
            first = int(rng.integers(0, m))
            keep[first] = not keep[first]
            flip = rng.integers(first, m, size=int(rng.integers(0, 3)))
            keep[flip] = ~keep[flip]
            assert K.factor(ab, keep, 1e-9, zero, U, max(first - kl, 0))
            U0 = np.zeros((m, kl + 1))
            assert K.factor(ab, keep, 1e-9, zero, U0)
            assert np.array_equal(U, U0), trial
            D = np.where(np.outer(keep, keep), W + 1e-9 * np.eye(m), np.diag((~keep).astype(float)))
            b = rng.normal(size=m)
            x = np.zeros(m)
            K.solve(U, b, x)
            assert np.allclose(x, np.linalg.solve(D, b), rtol=1e-9, atol=1e-12 * np.linalg.cond(D)), trial


def test_the_kernel_was_compiled_with_the_constants():
    """Numba froze :mod:`fembeam.simulation.constants` into the kernel; a stale cache would not
    see a change (the stepper rebuilds it; here it must agree)."""
    assert K.compiled_constants() == C.values()


def test_a_step_of_a_sliding_arch_is_its_cold_solution():
    """Steps of the 30-voussoir arch (R = 5 m) from its state at 0.85 s of the 0.6 g, 0.56 s sine
    with mu = 0.6, under a horizontal acceleration of 0 or 1.2 g, with mu = 0.6 (the sticking
    solution is in the cone) or 0.3 (it is not; a joint slides): the whole step
    (:func:`~fembeam.simulation.kernel._project`) against cold solves of the same problem.  Where
    the sticking solution is in the cone it is returned as it is (nothing counted); where it is
    not, the answer (the semi-smooth Newton method from the sticking solution, polished) has the
    rates of Lemke's pivots and of the Tresca fixed point from the sticking solution, to the
    tolerance of Coulomb's law, and satisfies the law independently checked."""
    from fembeam import CircularArch
    from fembeam.dynamics import GroundMotion
    from fembeam.simulation import Simulator
    arch = CircularArch.from_ratio(157.5, 0.15, radius=5.0)
    sim = Simulator(arch, voussoirs=30, friction=0.6)
    r = sim.run(GroundMotion.sine(0.6, 0.56), dt=1e-3, t_end=0.85)
    assert r.sliding_steps > 0
    con, h, g = sim.contacts, 1e-3, 9.81
    geo = con.evaluate(r.q_end)
    closed = geo.gap <= C.GAP_TOL * sim.bodies.thickness[:, None]
    nonneg, cj, _ = masks(closed)
    n, J = sim.bodies.n, closed.shape[0]
    m = 3 * J
    kinds = set()
    for mu, a_g in product((0.6, 0.3), (0.0, 1.2)):
        v = r.v_end.copy()
        v[:n, 0] -= h * a_g * g
        v[:n, 1] -= h * g
        ab, c = con.delassus(geo.rows), con.apply(geo.rows, v)
        ab_k, U, P, w, cc, Z = (np.zeros((C.BAND + 1, m)), np.zeros((m, C.BAND + 1)), np.zeros(m), np.zeros(m),
                                np.zeros(m), np.zeros((m, 4)))
        dump = (np.zeros((C.BAND + 1, m)), np.zeros(m), np.zeros(m), np.zeros((J, 2), bool))
        fs, ist = np.zeros(K.N_FLOAT), np.zeros(K.N_INT, np.int64)
        F, box = np.zeros(m, bool), np.zeros(m, np.int64)
        st = K._project(geo.rows, con.sides.astype(np.int64), con.minv, v, closed, F, False, box, mu, g * h,
                        C.BLOCK_PIVOTS, ab_k, U, P, w, cc, Z, *dump, fs, ist, 0.0, 0, C.KKT_TOL, C.COULOMB_TOL)
        assert st == 0 and ist[K.I_LOOSE] == 0
        vscale = max(float(np.max(np.abs(c))), g * h)
        dmax = float(np.max(ab[C.BAND]))
        _, Ps, _, _ = stick(ab, c, closed)
        pscale = max(np.max(np.abs(P)), np.max(np.abs(Ps)), vscale / dmax)
        W = np.zeros((m, m))
        for k in range(m):
            for i in range(max(0, k - C.BAND), k + 1):
                W[i, k] = W[k, i] = ab[C.BAND + i - k, k]
        assert np.allclose(W @ P + c, w, atol=1e-12 * vscale)
        assert violation(P, w, closed, mu, vscale, pscale) <= 10 * C.COULOMB_TOL
        if ist[K.I_SLIDING] == 0:                 # the sticking solution is the frictional one
            kinds.add("stick")
            assert fs[K.F_COULOMB] == 0.0
            assert np.max(np.abs(P - Ps)) <= 1e-6 * pscale
            continue
        kinds.add("slide")
        assert ist[K.I_BY_SSN] == 1
        for cold in ("lemke", "fixed_point"):
            ok, res, Pc, wc = _stage(cold, ab, c, closed, mu, Ps.copy())
            assert ok, cold
            assert np.max(np.abs(wc - w)) <= 1e-4 * vscale, (a_g, cold, np.max(np.abs(wc - w)) / vscale)
    assert kinds == {"stick", "slide"}, kinds
