"""Property-based, over random arches, against what does not come from the analysis itself:

* a voussoir arch's ``A_L`` (or that it cannot stand, or has no mechanism) is the optimum (or
  the infeasibility, or the unboundedness) of the static LP written here from closed forms:
  annular-sector voussoirs, fibre forces at the corners of the radial joints, Coulomb rows
  with friction, solved by SciPy's HiGHS (the package solves another LP, in the redundants);
* mirror image and units: the mirrored member (for a symmetric shape, the load from the other
  side; a surveyed arch that is not symmetric, mirrored point by point) with lengths times ``k``
  and the density times ``c`` gives the same outcome, ``A_L``, ``r``, the mirrored hinges and
  impulses times ``c k^2`` (the pre-impact field has unit mean horizontal velocity: impulse =
  mass per unit depth, ``rho L^2``, times a velocity);
* a thicker circular arch resists more: ``A_L`` grows with ``t/R`` (a thrust line inside the
  thinner arch fits, with room to spare, inside the thicker one);
* every result is an answer: ``r`` in [0, 1] (an impact does not create kinetic energy),
  ``A_L >= 0``, strict JSON.
"""
from __future__ import annotations

import json
import math

import numpy as np
import pytest
from hypothesis import HealthCheck, assume, given, settings, strategies as st
from scipy.optimize import linprog

from fembeam import CircularArch, InputError, analyze
from fembeam.geometry import CatenaryArch, EllipticalArch, ParabolicArch, PointedArch, SurveyedArch

SETTINGS = settings(deadline=None, derandomize=True, database=None, suppress_health_check=[HealthCheck.too_slow])


# ---------------------------------------------------------------------------- the static LP
def voussoir_lp(beta_deg: float, t_over_r: float, n: int, direction: int, mu: float | None):
    """``max lambda`` over the forces of the ``n + 1`` radial joints of a circular arch of ``n``
    equal voussoirs (R = 1, unit weight per unit area) carrying their weights and ``lambda``
    times them along ``direction * x``.  Joint ``j`` at polar angle ``th_j``: fibre forces
    ``N_i, N_e >= 0`` at the intrados and extrados corners (radii ``1 -+ t/2``) along
    ``tau = (-sin th_j, cos th_j)`` and a shear ``S`` along the joint; ``+`` on the voussoir at
    its left (larger angle), ``-`` on the one at its right.  A voussoir of angle ``d``: weight
    ``t d``, centroid at radius ``2/3 (r_e^3 - r_i^3) / (r_e^2 - r_i^2) sin(d/2) / (d/2)`` on its
    bisector.  ``mu``: ``|S| <= mu (N_i + N_e)``.  Returns scipy's OptimizeResult."""
    beta, t = math.radians(beta_deg), t_over_r
    ri, re = 1 - t / 2, 1 + t / 2
    th = 0.5 * math.pi + 0.5 * beta - beta * np.arange(n + 1) / n
    d = beta / n
    W = t * d
    rc = 2 / 3 * (re**3 - ri**3) / (re**2 - ri**2) * math.sin(d / 2) / (d / 2)
    mid = 0.5 * (th[:-1] + th[1:])
    nj = n + 1
    A = np.zeros((3 * n, 3 * nj + 1))
    tau, e = np.array([-np.sin(th), np.cos(th)]), np.array([np.cos(th), np.sin(th)])
    for j in range(nj):
        # force and moment about the centre of each unknown (the shear's line passes through it)
        unit = np.array([[*tau[:, j], ri], [*tau[:, j], re], [*e[:, j], 0.0]]).T
        for k, sign in ((j - 1, 1.0), (j, -1.0)):
            if 0 <= k < n:
                A[3 * k:3 * k + 3, 3 * j:3 * j + 3] += sign * unit
    A[0::3, -1] = direction * W                                  # lambda W along direction * x
    A[2::3, -1] = -direction * W * rc * np.sin(mid)              # its moment: -y_G lambda W
    b = np.zeros(3 * n)
    b[1::3] = W                                                  # the weight, -W along y
    b[2::3] = W * rc * np.cos(mid)                               # its moment: -x_G W
    ub = None
    if mu is not None:
        ub = np.zeros((2 * nj, 3 * nj + 1))
        for j in range(nj):
            ub[2 * j, 3 * j:3 * j + 3] = [-mu, -mu, 1.0]
            ub[2 * j + 1, 3 * j:3 * j + 3] = [-mu, -mu, -1.0]
    c = np.zeros(3 * nj + 1)
    c[-1] = -1.0
    return linprog(c, A_ub=ub, b_ub=None if ub is None else np.zeros(2 * nj), A_eq=A / (n * W), b_eq=b / (n * W),
                   bounds=[(0, None), (0, None), (None, None)] * nj + [(None, None)], method="highs")


def _answer(res) -> dict:
    """The result's JSON (strict: no NaN or infinity) with the bounds every answer obeys."""
    d = json.loads(json.dumps(res.to_dict(), allow_nan=False))
    assert d["outcome"] in ("rocking", "arrested", "cannot_stand", "no_mechanism", "sliding")
    if d["outcome"] in ("rocking", "arrested"):
        assert 0.0 <= d["r"] <= 1.0 and d["A_L"] >= 0.0 and math.isfinite(d["A_L"])
        assert (d["r"] == 0.0) == (d["outcome"] == "arrested")
    return d


@settings(SETTINGS, max_examples=60)
@given(beta=st.floats(60.0, 300.0), t_over_r=st.floats(0.02, 0.4), n=st.integers(3, 40),
       log_r=st.floats(-3.0, 4.0), log_rho=st.floats(-3.0, 4.0), direction=st.sampled_from([1, -1]),
       friction=st.sampled_from([None, None, None, 0.4, 0.7]))
def test_voussoir_limit_analysis_is_the_independent_static_lp(beta, t_over_r, n, log_r, log_rho, direction,
                                                              friction):
    """The outcome and ``A_L`` of ``analyze(voussoirs=n)`` in any units against
    :func:`voussoir_lp` (measured: 1e-14 relative)."""
    arch = CircularArch.from_ratio(beta, t_over_r, radius=10.0**log_r, density=10.0**log_rho)
    res = analyze(arch, voussoirs=n, direction=direction, friction=friction, tmin_tol=0.01)
    _answer(res)
    lp = voussoir_lp(beta, t_over_r, n, direction, friction)
    assert lp.status in (0, 2, 3), lp.message
    if lp.status == 0:
        assume(lp.x[-1] > 1e-6)                   # not on the edge of standing
        assert res.outcome in ("rocking", "arrested", "sliding")
        assert res.A_L == pytest.approx(lp.x[-1], rel=1e-8)
    else:
        assert res.outcome == {2: "cannot_stand", 3: "no_mechanism"}[lp.status]


# ---------------------------------------------------------------------------- mirror image and units
def _surveyed(k: float = 1.0, c: float = 1.0, mirrored: bool = False, lean: float = 0.4,
              taper: float = 0.02) -> SurveyedArch:
    """25 points of a parabola (span 10 m, rise 3 m) leaning to one side by ``lean`` m, its
    thickness ``0.5 + taper x`` m: not symmetric.  Lengths times ``k``, density ``c``;
    ``mirrored``: ``x -> -x``."""
    x = np.linspace(-5.0, 5.0, 25)
    y = 3.0 * (1 - (x / 5.0) ** 2) + lean * np.sin(math.pi * (x + 5.0) / 10.0) * x / 5.0
    t = 0.5 + taper * x
    return SurveyedArch(tuple(k * (-x if mirrored else x)), tuple(k * y), tuple(k * t), density=c)


SHAPES = {"pointed": PointedArch, "elliptical": EllipticalArch, "parabolic": ParabolicArch, "catenary": CatenaryArch}


@st.composite
def pairs(draw, kind):
    """A member of ``kind`` and its mirror image in other units (lengths x k, density x c),
    with k and c."""
    k, c = 10.0 ** draw(st.floats(-3.0, 3.0)), 10.0 ** draw(st.floats(-3.0, 4.0))
    if kind == "surveyed":
        lean, taper = draw(st.floats(-0.8, 0.8)), draw(st.floats(-0.03, 0.03))
        return _surveyed(lean=lean, taper=taper), _surveyed(k, c, True, lean, taper), k, c
    rise = draw(st.floats(0.5 if kind == "pointed" else 0.25, 1.0))
    ends, crown = draw(st.floats(0.04, 0.2)), draw(st.sampled_from([None, 0.6, 1.0]))
    law = {"thickness": ends} if crown is None else {"thickness_springing": ends, "thickness_crown": crown * ends}
    try:
        base = SHAPES[kind](span=1.0, rise=rise, **law)              # the default density, 2000 kg/m^3
        other = SHAPES[kind](span=k, rise=rise * k, density=c * base.density, **{key: v * k for key, v in law.items()})
    except InputError:           # thicker than the shape admits (the intrados would fold)
        assume(False)
    return base, other, k, c


@pytest.mark.parametrize("kind", ["surveyed", *SHAPES])
@settings(SETTINGS, max_examples=8)
@given(data=st.data(), mesh=st.sampled_from([("elements", 12), ("elements", 31), ("voussoirs", 5), ("voussoirs", 8)]),
       direction=st.sampled_from([1, -1]), friction=st.sampled_from([None, None, 0.4, 0.8]))
def test_mirror_image_in_other_units_gives_the_same_answer(kind, data, mesh, direction, friction):
    """Outcome, ``A_L`` and ``r`` to 1e-9 (``r`` within 1e-11), hinges at ``L - s`` on the same
    side in reverse order (to 1e-9 L), impulses times ``c k^2`` to 1e-9 of the largest (1e-6
    for the hinges, ``r`` and the impulses of a continuous member with friction); strict JSON.
    A pointed arch's mesh is its own mirror image only with an even count (the crown joint is a
    node, the elements are shared out between the halves with ties to the left)."""
    assume(kind != "pointed" or mesh[1] % 2 == 0)
    base, other, k, c = data.draw(pairs(kind))
    a = analyze(base, **{mesh[0]: mesh[1]}, direction=direction, friction=friction, tmin_tol=0.01)
    b = analyze(other, **{mesh[0]: mesh[1]}, direction=-direction, friction=friction, tmin_tol=0.01)
    _answer(a), _answer(b)
    assert a.outcome == b.outcome
    if a.outcome in ("cannot_stand", "no_mechanism"):
        return
    assert b.A_L == pytest.approx(a.A_L, rel=1e-9)
    L = base.length
    hb = [(h.s / L, h.side) for h in a.hinges_before]
    mirrored = [(1.0 - h.s / (k * L), h.side) for h in reversed(b.hinges_before)]
    assert [s for _, s in hb] == [s for _, s in mirrored]
    # with friction the continuous member's hinges come from the friction LP's support, known to
    # its tolerance (1e-10 of the weight): measured up to 4e-8 L, and r (not stationary in the
    # hinges before the impact) then within 4e-8
    tol = 1e-9 if friction is None or mesh[0] == "voussoirs" else 1e-6
    assert np.allclose([x for x, _ in hb], [x for x, _ in mirrored], rtol=0, atol=tol)
    if a.outcome == "sliding":
        return
    assert abs(b.r - a.r) <= max(tol * a.r, 1e-11)
    mu_a, mu_b = a.impact.mu, b.impact.mu[:, ::-1] / (c * k * k)
    assert mu_a.shape == mu_b.shape and np.abs(mu_b - mu_a).max() <= tol * np.abs(mu_a).max()


# ---------------------------------------------------------------------------- thickness
@settings(SETTINGS, max_examples=25)
@given(beta=st.floats(80.0, 180.0), t_over_r=st.floats(0.11, 0.3), factor=st.floats(1.05, 1.6))
def test_a_thicker_circular_arch_resists_more(beta, t_over_r, factor):
    """``A_L(t2/R) > A_L(t1/R)`` for ``t2 = factor t1`` (continuous arch, embrace up to a
    semicircle, thicker than the semicircle's minimum t/R = 0.1075: both stand); a thinner arch
    without a mechanism has a thicker one without either."""
    thin = analyze(CircularArch.from_ratio(beta, t_over_r), elements=20, tmin_tol=0.01)
    thick = analyze(CircularArch.from_ratio(beta, t_over_r * factor), elements=20, tmin_tol=0.01)
    _answer(thin), _answer(thick)
    assert "cannot_stand" not in (thin.outcome, thick.outcome)
    if thin.outcome == "no_mechanism":
        assert thick.outcome == "no_mechanism"
    elif thick.outcome != "no_mechanism":
        assert thick.A_L > thin.A_L
