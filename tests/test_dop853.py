"""The DOP853 stepper of the one-mechanism motion (fembeam/dynamics/dop853.py): its tableau's
order conditions, the observed orders of the step (8) and of the interpolant (7), and whole
integrations against ``scipy.integrate.solve_ivp(method="DOP853")``."""
from __future__ import annotations

import math
from fractions import Fraction

import numpy as np
import pytest
from scipy.integrate import solve_ivp

from fembeam.dynamics.dop853 import A, B, C, D, E3, E5, N_STAGES, Dense, Dop853, poly


def test_tableau_conditions():
    """Row sums equal the nodes; the weights integrate x^(k-1) exactly for k = 1..8 (the quadrature
    conditions of order 8); the error weights annihilate constants (``E5`` and ``E3`` are
    differences of two quadratures)."""
    for s, row in enumerate(A, start=1):
        assert sum(row) == pytest.approx(C[s], abs=1e-14)
    for k in range(1, 9):
        assert sum(b * C[i] ** (k - 1) for i, b in enumerate(B)) == pytest.approx(float(Fraction(1, k)), abs=1e-14)
    assert abs(sum(E5)) < 1e-14 and abs(sum(E3)) < 1e-14
    assert len(B) == N_STAGES and len(A) == 15 and all(len(d) == 16 for d in D)


def _fixed(fun, y0, T, n):
    st = Dop853(fun, (1.0,) * len(y0), 1.0)
    h, t, y = T / n, 0.0, tuple(y0)
    dense = Dense()
    f = fun(t, y)
    for _ in range(n):
        y1, K, _ = st.step(t, y, f, h)
        dense.add(t, h, y, st.dense(t, h, y, y1, K))
        t, y, f = t + h, y1, tuple(k[N_STAGES] for k in K)
    return y, dense


def _oscillator(t, y):
    """y'' = -y + 0.5 sin(2t), an exact solution below."""
    return y[1], -y[0] + 0.5 * math.sin(2 * t)


def _exact(t):
    # y = cos t + c sin t - sin(2t) / 6 with y(0) = 1, y'(0) = 0: c = 1/3
    return (math.cos(t) + math.sin(t) / 3 - math.sin(2 * t) / 6,
            -math.sin(t) + math.cos(t) / 3 - math.cos(2 * t) / 3)


def test_observed_orders_of_step_and_interpolant():
    """Halving a fixed step divides the global error by about 2^8 and the interpolant's error
    between the steps by at least 2^7."""
    T = 4.0
    errs, derrs = [], []
    for n in (8, 16, 32):
        y, dense = _fixed(_oscillator, (1.0, 0.0), T, n)
        errs.append(abs(y[0] - _exact(T)[0]))
        ts = np.linspace(0.0, T, 401)[1:-1]
        derrs.append(max(abs(dense(t)[0] - _exact(t)[0]) for t in ts))
    p = [math.log2(a / b) for a, b in zip(errs, errs[1:])]
    q = [math.log2(a / b) for a, b in zip(derrs, derrs[1:])]
    assert min(p) > 7.5, p
    assert min(q) > 6.5, q


def _adaptive(fun, y0, T, rtol, atol):
    st = Dop853(fun, (atol,) * len(y0), rtol)
    t, y = 0.0, tuple(y0)
    f = fun(t, y)
    h = st.first_step(t, y, f, T)
    steps = 0
    while t < T:
        h = min(h, T - t)
        rejected = False
        while True:
            y1, K, err = st.step(t, y, f, h)
            if err < 1.0:
                break
            h = st.next_step(h, err, True)
            rejected = True
        h_next = st.next_step(h, err, rejected)
        t, y, f = t + h, y1, tuple(k[N_STAGES] for k in K)
        steps += 1
        h = h_next
    return y, steps


@pytest.mark.parametrize("rtol", [1e-6, 1e-10])
def test_adaptive_run_is_scipys(rtol):
    """With the same tolerances the adaptive steps are those of ``solve_ivp``'s DOP853: the same
    number of steps and the same end state to round-off."""
    fun = lambda t, y: (y[1], -math.sin(y[0]) + 0.3 * math.cos(1.3 * t))  # noqa: E731  forced pendulum
    y, steps = _adaptive(fun, (1.0, 0.0), 10.0, rtol, 1e-12)
    ref = solve_ivp(lambda t, y: np.array(fun(t, y)), (0.0, 10.0), [1.0, 0.0], method="DOP853", rtol=rtol, atol=1e-12)
    assert steps == ref.t.size - 1
    assert np.allclose(y, ref.y[:, -1], rtol=1e-12, atol=1e-14)


def test_poly_is_the_increment():
    """``poly`` vanishes at the step's start and equals the step's increment at its end."""
    y, dense = _fixed(_oscillator, (1.0, 0.0), 1.0, 4)
    for t0, h, y0, F in dense.steps:
        assert poly(F[0], 0.0) == 0.0
        assert y0[0] + poly(F[0], 1.0) == pytest.approx(dense(t0 + h)[0], abs=1e-15)


def test_three_components_written_out_are_the_general_step():
    """The stages written out for three components (the one-mechanism motion) give bitwise the
    stages of the general loop (step and dense output), here run on the same system with a
    fourth, idle component."""
    def fun3(t, y):
        return y[1], -math.sin(y[0]) + 0.3 * math.cos(1.3 * t) - 0.05 * y[1] * abs(y[1]), -0.3 * y[1]

    def fun4(t, y):
        return (*fun3(t, y[:3]), 0.0)

    st3, st4 = Dop853(fun3, (1e-12,) * 3, 1e-10), Dop853(fun4, (1e-12,) * 4, 1e-10)
    for t, y, h in ((0.0, (1.0, 0.0, 0.0), 0.1), (2.5, (-0.3, 1.7, 0.25), 1e-4), (7.0, (3.0, -2.0, -1.0), 0.7)):
        y3, K3, _ = st3.step(t, y, fun3(t, y), h)
        y4, K4, _ = st4.step(t, (*y, 0.0), fun4(t, (*y, 0.0)), h)
        assert y3 == y4[:3] and [list(k) for k in K3] == [list(k) for k in K4[:3]]
        assert len(K3[0]) == N_STAGES + 1
        assert st3.dense(t, h, y, y3, K3) == st4.dense(t, h, (*y, 0.0), y4, K4)[:3]
