"""The continuum's line search (vectorised Brent) and the minimum thickness's root finder
(regula falsi, Anderson-Bjorck): same answers as dense sampling / bisection, fewer evaluations."""
from __future__ import annotations

import math

import numpy as np
import pytest

from fembeam import CircularArch, PointedArch
from fembeam.analysis import continuum as cont
from fembeam.analysis.continuum import brent_minimise, weakest_sections
from fembeam.analysis.rows import joint_rows, main_lp, solve_unboxed
from fembeam.analysis.statics import statics
from fembeam.analysis.thickness import shrink_bracket, stands_on, thickness_on
from fembeam.fem import discretize, uniform_nodes


def test_brent_finds_the_minima_of_a_batch_in_few_steps():
    """Unimodal functions with interior minima, a quartic (flat) one and a minimum at the end
    of the bracket: each found to the bracket width, in far fewer steps than the ~25 of a
    golden-section search to that width."""
    c = np.array([0.3, 0.55, 0.5, 1.0])             # minimisers (the last one past the bracket's end)
    p = np.array([2.0, 2.0, 4.0, 2.0])
    calls = []

    def f(u, sel):
        calls.append(u.size)
        return np.abs(u - c[sel]) ** p[sel] + 0.1 * np.sin(u)      # sin: asymmetric, smooth

    a, b = np.zeros(4), np.full(4, 0.9)
    x = np.full(4, 0.45)
    w, v = np.full(4, 0.25), np.full(4, 0.65)
    width = 1e-7
    s, val = brent_minimise(f, a, b, x, f(x, np.arange(4)), w, f(w, np.arange(4)), v, f(v, np.arange(4)), width)
    dense = np.linspace(0.0, 0.9, 900_001)
    for i in range(4):
        fd = np.abs(dense - c[i]) ** p[i] + 0.1 * np.sin(dense)
        assert abs(s[i] - dense[np.argmin(fd)]) <= width + 1e-6      # the dense grid's own spacing
        # at an interior minimum f(s) - f* ~ f'' width^2; at the end of the bracket |f'| width
        j = np.argmin(fd)
        assert (0 < j < dense.size - 1) == (i < 3)
        slope = abs(np.gradient(fd, dense)[j]) if i == 3 else 0.0
        assert val[i] <= fd.min() + 1e-12 + slope * width
    assert len(calls) - 3 <= 40            # the quartic and the end minimum are the slow ones
    assert np.sum(np.array(calls[3:]) == 4) <= 10   # all four searches together only a few steps


@pytest.mark.parametrize("beta, t", [(120.0, 0.2), (180.0, 0.12), (160.0, 0.25)])
def test_weakest_sections_agree_with_dense_sampling(beta, t):
    """At the mesh LP's optimum: every minimum reported is the element's minimum of that fibre
    (dense sampling, 4001 points per element, and no lower), in at most 12 evaluations."""
    arch = CircularArch.from_ratio(beta, t)
    disc = discretize(arch, uniform_nodes(arch, 40))
    st = statics(disc)
    lp = solve_unboxed(main_lp, joint_rows(st, 1), st.k)
    z = np.r_[lp.z[:st.k], lp.z[st.k], 1.0]
    n_calls = []
    fibres = cont._fibres

    def counting(st_, s_, z_):
        n_calls.append(np.size(s_))
        return fibres(st_, s_, z_)

    cont._fibres = counting
    try:
        s, fib, v = weakest_sections(st, z)
    finally:
        cont._fibres = fibres
    assert s.size > 0 and len(n_calls) <= 12
    nodes = disc.nodes_s
    width = 1e-7 * nodes[-1]
    for si, fi, vi in zip(s, fib, v):
        e = min(np.searchsorted(nodes, si, side="right") - 1, nodes.size - 2)
        dense = np.linspace(nodes[e], nodes[e + 1], 4001)
        fd = fibres(st, dense, z)[fi]
        j = np.argmin(fd)
        # not above the sampled minimum (by |f'| width when it is at a node), nor below it
        # by more than a fibre force dips between two samples
        slope = abs(np.gradient(fd, dense)[j]) if j in (0, dense.size - 1) else 0.0
        assert fd[j] - np.max(np.abs(np.diff(fd, 2))) <= vi <= fd[j] + 1e-12 + slope * width
        assert fibres(st, np.array([si]), z)[fi, 0] == pytest.approx(vi, abs=1e-15)


def _bisection_solves(lo, hi, tol):
    n = 0
    while hi - lo > tol * hi:
        lo, hi, n = 0.5 * (lo + hi), hi, n + 1
    return n


def test_shrink_bracket_keeps_the_bracket_with_fewer_solves():
    root = 0.7318

    bisection = _bisection_solves(0.5, 1.0, 1e-9)          # 29
    for g, most in ((lambda k: 3.0 * (k - root), 4),                        # linear: exact secant
                    (lambda k: math.expm1(5.0 * (k - root)), 8),           # curved
                    (lambda k: (k - root) ** 3 + 1e-4 * (k - root), bisection + 5)):  # inflection: fallback
        evals = []

        def counted(k, g=g):
            evals.append(k)
            return g(k)

        lo, hi = shrink_bracket(counted, 0.5, g(0.5), 1.0, g(1.0), 1e-9)
        assert g(lo) < 0 <= g(hi) and hi - lo <= 1e-9 * hi and lo < root <= hi
        assert len(evals) <= most


def test_shrink_bracket_falls_back_to_bisection_on_a_step_function():
    """A margin with no useful slope (only its sign): the bracket still holds, and after
    ``max_slow`` slow steps bisection bounds the count."""
    evals = []

    def g(k):
        evals.append(k)
        return 1.0 if k >= 0.6180339 else -1.0

    lo, hi = shrink_bracket(g, 0.5, -1.0, 1.0, 1.0, 1e-8)
    assert lo < 0.6180339 <= hi and hi - lo <= 1e-8 * hi
    assert len(evals) <= _bisection_solves(0.5, 1.0, 1e-8) + 8


@pytest.mark.parametrize("arch", [CircularArch.from_ratio(180.0, 0.15),
                                  PointedArch(span=10.0, rise=7.0, thickness=0.5)])
def test_minimum_thickness_root_finder_certificate_and_solves(arch):
    """The bracket is a certificate (checked by the independent verdict) and takes fewer
    than half the margin solves of a bisection to the same tolerance."""
    nodes = uniform_nodes(arch, 60)
    th = thickness_on(arch, nodes, True, 1e-8)
    assert stands_on(arch.with_thickness_scaled(th.scale), nodes, True)
    assert not stands_on(arch.with_thickness_scaled(th.lower), nodes, True)
    assert th.scale - th.lower <= 1e-8 * th.scale
    bracketing = 2 + math.ceil(abs(math.log2(th.scale)))    # doublings or halvings from 1
    assert th.solves < bracketing + 0.5 * math.log2(1e8)


def test_shrink_bracket_with_a_zero_margin_and_a_nan():
    """A margin exactly zero where it stands keeps the bracket (no division by zero); a
    margin that is not a number is an error, not a bracket of NaN."""
    from fembeam.analysis.thickness import shrink_bracket
    from fembeam.errors import SolverError

    lo, hi = shrink_bracket(lambda k: 0.0 if k >= 0.7 else -1.0, 0.5, -1.0, 1.0, 0.0, 1e-6)
    assert lo < 0.7 <= hi and hi - lo <= 1e-6 * hi
    with pytest.raises(SolverError, match="margin"):
        shrink_bracket(lambda k: float("nan"), 0.5, -1.0, 1.0, 1.0, 1e-6)


def test_brent_out_of_steps_is_finished_by_golden_sections():
    """With the step budget cut to 2 (a kinked minimum takes Brent many steps), the searches
    still wider than ``width`` are finished by golden sections, down to that width."""
    m = np.array([0.37, 0.61])

    def f(u, sel):
        return np.abs(u - m[sel]) + 0.01 * u

    a, b = np.zeros(2), np.ones(2)
    x, w, v = np.full(2, 0.5), np.full(2, 0.2), np.full(2, 0.8)
    idx = np.arange(2)
    width = 1e-7
    s, val = brent_minimise(f, a, b, x, f(x, idx), w, f(w, idx), v, f(v, idx), width, max_steps=2)
    assert np.all(np.abs(s - m) <= width)
    assert np.allclose(val, 0.01 * m, atol=2 * width)


def test_continuum_rounds_run_out_with_an_error_not_a_wrong_answer():
    """A round budget too small for the exchange method: the margin search stops with the
    cuts of its last LP (a bound), the limit analysis with a SolverError."""
    from fembeam import CircularArch, discretize, uniform_nodes
    from fembeam.analysis.continuum import continuum_limit
    from fembeam.errors import SolverError

    arch = CircularArch.from_ratio(180.0, 0.1075)
    disc = discretize(arch, uniform_nodes(arch, 100))
    assert continuum_limit(disc, 1).status == "ok"
    with pytest.raises(SolverError, match="after 1 rounds"):
        continuum_limit(disc, 1, max_rounds=1)


def test_standing_undecided_when_rounds_run_out():
    """A margin search stopped by its round budget while the joints stand and a section
    between them does not: an error saying so (not "stands", not an infeasible LP); a
    budget below one round is bad input."""
    from fembeam import CircularArch, discretize, uniform_nodes
    from fembeam.analysis.continuum import continuum_limit
    from fembeam.errors import InputError, SolverError

    arch = CircularArch.from_ratio(180.0, 0.107)
    disc = discretize(arch, uniform_nodes(arch, 6))
    assert continuum_limit(disc, 1).status == "cannot_stand"
    with pytest.raises(SolverError, match="undecided after 1 rounds"):
        continuum_limit(disc, 1, max_rounds=1)
    with pytest.raises(InputError, match="max_rounds"):
        continuum_limit(disc, 1, max_rounds=0)
