"""Mirror images give mirrored answers in the motion commands: a surveyed mid-curve given
from either springing, and its mirror image under the mirrored pulse, rock the same way
(thresholds swapped, the same outcome and impact times, hinges at mirrored arc lengths)."""
from __future__ import annotations

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings, strategies as st

from fembeam.dynamics.ground import GroundMotion
from fembeam.dynamics.rocking import Rocker
from fembeam.geometry import CircularArch, SurveyedArch
from fembeam.mechanisms.mechanism import END_TOL, Mechanism


def _points(seed: int, n: int):
    """An asymmetric arch through n points: a sine bump on a sloping chord, springings at
    different heights (m)."""
    rng = np.random.default_rng(seed)
    span = rng.uniform(6.0, 14.0)
    u = np.linspace(0.0, 1.0, n)
    return span * u, span * (rng.uniform(0.35, 0.5) * np.sin(np.pi * u) + rng.uniform(-0.08, 0.08) * u)


def _run(rk, amplitude):
    """The first 1.6 s: the 1-s pulse and the first impact (each new mechanism of a surveyed
    arch costs about a second to set up; to rest would take 10-30 s and tens of impacts)."""
    return rk.run(GroundMotion.sine(amplitude, 1.0), thrust_check=False, t_end=1.6)


@settings(max_examples=3, deadline=None, derandomize=True, database=None,
          suppress_health_check=[HealthCheck.too_slow])
@given(seed=st.integers(0, 10_000), n=st.sampled_from([7, 15, 23]), elements=st.sampled_from([40, 63, 100]),
       sign=st.sampled_from([1, -1]), reverse=st.booleans())
def test_a_mirrored_surveyed_arch_rocks_mirrored(seed, n, elements, sign, reverse):
    x, y = _points(seed, n)
    arch = SurveyedArch(x, y, thickness=0.08 * x[-1])
    mx, my = -x, y                                    # the mirror image, given from its right springing
    if reverse:
        mx, my = mx[::-1], my[::-1]                  # ... or from its left one
    mirror = SurveyedArch(mx, my, thickness=0.08 * x[-1])
    assert mirror.length == pytest.approx(arch.length, rel=1e-12)
    rk, mk = Rocker(arch, elements=elements, qp=False), Rocker(mirror, elements=elements, qp=False)
    A = rk.A[-1] if sign > 0 else rk.A[1]           # a positive pulse loads to the left, against A_L(-1)
    res, mres = _run(rk, sign * 1.6 * A), _run(mk, -sign * 1.6 * A)
    assert mk.A[1] == pytest.approx(rk.A[-1], rel=1e-7) and mk.A[-1] == pytest.approx(rk.A[1], rel=1e-7)
    assert mres.outcome == res.outcome and len(mres.impacts) == len(res.impacts) >= 1
    for a, b in zip(res.impacts[:5], mres.impacts[:5]):
        assert b.t == pytest.approx(a.t, rel=1e-6, abs=1e-9) and b.r == pytest.approx(a.r, rel=1e-6)
    L = arch.length
    for m in res.mechanisms[:3]:
        mirrored = sorted(L - s for s in m.s)
        assert any(np.allclose(sorted(mm.s), mirrored, atol=1e-7 * L) for mm in mres.mechanisms)


def test_a_hinge_past_an_end_by_round_off_is_at_the_end():
    """A hinge one rounding past the end (the end's arc length summed the other way) is the
    end; beyond the tolerance it is refused."""
    arch = CircularArch.from_ratio(157.5, 0.15, radius=7.0)
    L, sides = arch.length, ("extrados", "intrados", "extrados", "intrados")
    m = Mechanism(arch, (-1e-14 * L, 0.3 * L, 0.6 * L, L * (1 + 4e-16)), sides)
    assert m.s[0] == 0.0 and m.s[-1] == L
    with pytest.raises(Exception, match="hinges must lie on the member"):
        Mechanism(arch, (0.0, 0.3 * L, 0.6 * L, L * (1 + 10 * END_TOL)), sides)
