"""The impact transitions and the numbering of mechanisms do not depend on history.

A transition is a function of the mechanism's canonical key alone (whatever was solved before
it, in whatever order), and a run's result lists the mechanisms of that run only, numbered as
the run met them, whatever the Rocker ran before.
"""
from __future__ import annotations

import numpy as np
import pytest

from fembeam import CircularArch
from fembeam.dynamics import GroundMotion, ImpactModel, Rocker
from fembeam.mechanisms import Mechanism

ARCH = CircularArch.from_ratio(157.5, 0.15, radius=5.0)


def _same(a, b):
    assert a.before.key == b.before.key
    assert (a.after is None) == (b.after is None)
    if a.after is not None:
        assert a.after.key == b.after.key
    assert (a.r, a.alpha_ratio) == (b.r, b.alpha_ratio)


def test_key_is_canonical():
    """Hinges equal to 1e-13 of the length share a key, and the canonical mechanism has that key."""
    L = ARCH.length
    m = Mechanism(ARCH, (0.01 * L, 0.3 * L, 0.7 * L, 0.99 * L), ("intrados", "extrados", "intrados", "extrados"))
    m2 = Mechanism(ARCH, tuple(s + 1e-13 * L for s in m.s), m.sides)
    assert m.key == m2.key and m.canonical().key == m.key
    assert m.canonical() == m2.canonical()
    assert np.allclose(m.canonical().s, m.s, rtol=0, atol=1e-12 * L)


def test_continuous_transition_does_not_depend_on_what_was_solved_before():
    """Continuous member: the transition of the onset mechanism solved in a fresh model equals the
    one solved after a neighbour (the inner hinges moved by -4.5 % and +2.07 % of the length, same
    sides): no warm start from a solved mechanism moves the optimum to another grid cell (a local
    search started from this neighbour's optimum, accepted without the global one, ended a grid
    cell away with alpha' off by 1.8e-5)."""
    start = Rocker(ARCH, qp=False).start[1]
    L = ARCH.length
    s = np.asarray(start.s) + np.array([0.0, -0.045, 0.0207, 0.0]) * L
    neighbour = Mechanism(ARCH, tuple(s), start.sides)
    fresh = ImpactModel(ARCH, qp=False)(start)
    warm = ImpactModel(ARCH, qp=False)
    warm(neighbour)
    _same(fresh, warm(start))
    # and a mechanism equal to the start to round-off is the same mechanism
    jitter = Mechanism(ARCH, tuple(min(x + 1e-14 * L, L) for x in start.s), start.sides)
    assert warm(jitter) is warm(start)


def test_voussoir_transitions_in_any_order():
    """Seven voussoirs: the mechanisms met under El Centro (0.8 g, 8 s) solved in the order met, in
    reverse and shuffled give identical transitions."""
    rk = Rocker(ARCH, voussoirs=7, qp=False)
    res = rk.run(GroundMotion.record("elcentro").to_pga(0.8), t_end=8.0, thrust_check=False, history=False)
    mechs = list(res.mechanisms)
    assert len(mechs) >= 3
    orders = [mechs, mechs[::-1], list(np.random.default_rng(1).permutation(len(mechs)))]
    orders[2] = [mechs[i] for i in orders[2]]
    models = []
    for order in orders:
        model = ImpactModel(ARCH, voussoirs=7, qp=False)
        for m in order:
            model(m)
        models.append(model)
    for m in mechs:
        _same(models[0](m), models[1](m))
        _same(models[0](m), models[2](m))


@pytest.mark.parametrize("first", [0.6, -0.6])
def test_result_lists_the_runs_own_mechanisms(first):
    """A Rocker run first under one pulse, then under the mirrored pulse, returns for the second
    run exactly what a fresh Rocker returns: the same impacts (times, rates, r) and mechanisms,
    numbered from 0 in the order met, every index in range."""
    a, b = GroundMotion.sine(first, 0.56), GroundMotion.sine(-first, 0.56)
    used = Rocker(ARCH, voussoirs=7, qp=False)
    used.run(a, t_end=4.0, thrust_check=False)
    again = used.run(b, t_end=4.0, thrust_check=False)
    fresh = Rocker(ARCH, voussoirs=7, qp=False).run(b, t_end=4.0, thrust_check=False)
    assert len(used.mechanisms) > len(again.mechanisms)          # the Rocker knows both runs' mechanisms
    assert [m.key for m in again.mechanisms] == [m.key for m in fresh.mechanisms]
    assert [(e.t, e.before, e.after, e.rate_in, e.rate_out, e.r) for e in again.impacts] == \
        [(e.t, e.before, e.after, e.rate_in, e.rate_out, e.r) for e in fresh.impacts]
    assert again.onsets == fresh.onsets and again.peaks == fresh.peaks
    assert np.array_equal(again.history["mechanism"], fresh.history["mechanism"])
    n = len(again.mechanisms)
    ks = [k for _, k in again.onsets] + [k for e in again.impacts for k in (e.before, e.after) if k is not None]
    assert set(ks) | {int(k) for k in again.history["mechanism"] if k >= 0} == set(range(n))
    assert len(again.unstable_rotation) == len(again.overturn_rotation) == n
    d = again.to_dict()
    assert [m["index"] for m in d["mechanisms"]] == list(range(n))
