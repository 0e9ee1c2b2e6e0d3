"""The rocking time history against closed forms and independent routes.

* the equation of motion: Lambda(0) = the FE kinetic energy of the mechanism's field,
  Lambda', V', Q against differences of independently computed Lambda, V and sum m x_G;
* Housner's block: unstable equilibrium at alpha, r = (1 - 1.5 sin^2 alpha)^2, the free-rocking
  amplitude recursion and the time between impacts (quadrature of the energy integral; Housner's
  linearised period), the whole motion, its overturning time and the one-sine pulse's
  overturning threshold against Housner's equation integrated here by solve_ivp, the
  rectangular-pulse threshold in the small-angle limit;
* the arch: onset at the closed-form time, every impact and the overturning against the equation
  of motion integrated here by solve_ivp (EquationOfMotion's coefficients, ImpactModel's
  transitions as inputs); onset just above and not just below A_L; the first impact = fembeam
  impact's restricted model;
* energy: conserved to 1e-8 in free motion, balanced with the ground's work under forcing;
* invariance: time scales with sqrt(R/g) at equal slenderness, mirror image for -a_g;
* accumulation: a decaying motion comes to rest in finite time with finitely many impacts.
"""
import functools
import math

import numpy as np
import pytest
from scipy.integrate import quad, solve_ivp
from scipy.optimize import brentq

from fembeam import CircularArch, StraightMember, analyze, discretize, nodes_through, uniform_nodes
from fembeam.dynamics import GRAVITY, EquationOfMotion, GroundMotion, ImpactModel, Rocker, rock
from fembeam.dynamics.rocking import onset_time
from fembeam.mechanisms import Mechanism
from fembeam.mechanisms.four_hinge_analysis import four_hinge_impact

PAPER = CircularArch.from_ratio(157.5, 0.15)


@pytest.fixture(scope="module")
def paper_eq():
    res = analyze(PAPER)
    return res, EquationOfMotion(Mechanism.from_hinges(PAPER, res.hinges_before))


def block(width=0.5, height=2.0):
    return StraightMember(height=height, width=width)


# --------------------------------------------------------------------------- independent references
def sine_pulse(amplitude, period):
    """``a_g(t)`` (g): one period of ``amplitude sin(2 pi t / period)``, zero outside it."""
    return lambda t: amplitude * math.sin(2 * math.pi * t / period) if 0.0 <= t <= period else 0.0


def rectangular_pulse(amplitude, duration):
    return lambda t: amplitude if 0.0 <= t < duration else 0.0


def _onset(a_g, threshold, t, t_quiet):
    """First time in ``[t, t_quiet]`` at which ``|a_g|`` exceeds ``threshold`` (a grid of 4001
    points, then brentq); None if it does not."""
    grid = np.linspace(t, t_quiet, 4001)
    above = np.flatnonzero([abs(a_g(x)) > threshold for x in grid])
    if above.size == 0:
        return None
    i = int(above[0])
    if i == 0:
        return t
    t = brentq(lambda x: abs(a_g(x)) - threshold, grid[i - 1], grid[i], xtol=1e-15, rtol=1e-15)
    while abs(a_g(t)) < threshold:
        t = math.nextafter(t, math.inf)
    return t


def housner_motion(width, height, a_g, t_quiet, t_end):
    """Housner's rocking block, independently of fembeam: with ``s = sign(phi)``,
    ``phi'' = -p^2 (sin(s alpha - phi) + a_g(t) cos(s alpha - phi))``, ``p^2 = 3 g / (4 R)`` (``R``
    the half-diagonal, ``tan alpha = width / height``), integrated by solve_ivp (DOP853, rtol
    1e-12, split at ``t_quiet``, after which the ground is still) from each onset (``|a_g|`` above
    ``tan alpha``) to the next impact (``phi = 0``: ``phi' -> (1 - 1.5 sin^2 alpha) phi'``, on the
    other corner; rest below 1e-12 of the barrier ``m g R (1 - cos alpha)``) or to overturning (the
    centroid 0.1 width below its height at rest: ``R cos(alpha - |phi|) = height/2 - 0.1 width``).
    Returns the onset times, the impacts ``(t, rate in, rate out)``, the turning points
    ``(t, |phi|)`` and ``t_overturn``."""
    alpha, R = math.atan(width / height), 0.5 * math.hypot(width, height)
    p2, rv = 3 * GRAVITY / (4 * R), 1 - 1.5 * math.sin(alpha) ** 2
    top = alpha + math.acos((0.5 * height - 0.1 * width) / R)

    def f(t, y, s):
        return [y[1], -p2 * (math.sin(s * alpha - y[0]) + a_g(t) * math.cos(s * alpha - y[0]))]

    def hit(t, y, s):          # not at the start of an episode, where phi = 0
        return s * y[0] if t > t0 + 1e-9 else 1.0

    def over(t, y, s):
        return s * y[0] - top

    def turn(t, y, s):
        return y[1]
    hit.terminal, hit.direction, over.terminal, over.direction = True, -1, True, 1
    out = {"onsets": [], "impacts": [], "peaks": [], "t_overturn": None}
    t, state = 0.0, None
    while t < t_end:
        if state is None:
            t_on = _onset(a_g, math.tan(alpha), t, t_quiet) if t < t_quiet else None
            if t_on is None:
                break
            t, state = t_on, (0.0, -math.copysign(1.0, a_g(t_on + 1e-9)))
            out["onsets"].append(t)
        y, s, t0 = [0.0, state[0]], state[1], t
        for tb in (t_quiet, t_end):
            if tb <= t:
                continue
            sol = solve_ivp(f, (t, tb), y, args=(s,), method="DOP853", rtol=1e-12, atol=1e-14,
                            events=(hit, over, turn))
            out["peaks"] += [(tp, abs(yp[0])) for tp, yp in zip(sol.t_events[2], sol.y_events[2]) if tp > t]
            t, y = float(sol.t[-1]), sol.y[:, -1]
            if sol.status == 1:
                break
        else:
            break
        if sol.t_events[1].size:
            out["t_overturn"] = t
            break
        rate = rv * y[1]
        at_rest = 0.5 * 4 / 3 * R * R * rate * rate < 1e-12 * GRAVITY * R * (1 - math.cos(alpha))
        out["impacts"].append((t, float(y[1]), 0.0 if at_rest else rate))
        state = None if at_rest else (rate, -s)
    return out


def _arch_functions(eq, a_g, level, t0):
    """Right-hand side and events (impact, overturning) of an episode from ``t0`` on ``eq``."""
    def f(t, y):
        lam, dlam, dv, q = eq.coefficients(y[0])
        return [y[1], -(0.5 * dlam * y[1] ** 2 + dv + a_g(t) * q) / lam]

    def hit(t, y):            # not at the start of the episode, where theta = 0
        return eq.sign * y[0] if t > t0 + 1e-9 else 1.0

    def over(t, y):
        return eq.potential(y[0]) - level if eq.sign * y[0] > eq.theta_unstable else 1.0
    hit.terminal, hit.direction, over.terminal, over.direction = True, -1, True, -1
    return f, hit, over


def arch_motion(curve, voussoirs, a_g, t_quiet, t_end):
    """The motion of a circular voussoir arch, independently of ``rock``'s integrator and event
    location: from rest at the first time ``a_g`` exceeds ``A_L`` of its direction (fembeam
    analyze: the inertia load ``-a_g g`` opens the mechanism of ``direction = -sign(a_g)``), the
    equation ``Lambda theta'' + 0.5 Lambda' theta'^2 + V' + a_g Q = 0`` (EquationOfMotion's
    coefficients) integrated by solve_ivp (DOP853, rtol 1e-12, split at ``t_quiet``) to the next
    impact (``theta = 0``: ImpactModel's transition, the incoming rate times its ``alpha_ratio``)
    or to overturning (``V`` below ``-0.1 m g t``, ``m = rho t R beta``).  A post-impact energy
    below 1e-12 of the barrier before the impact (``V`` at the unstable equilibrium) is rest.
    Returns the onset, the impacts ``(t, rate in, rate out)``, ``t_overturn``, ``outcome`` and
    ``free``: for the state at ``t_quiet`` and after every later impact, ``(past the unstable
    equilibrium, heading out, E / barrier)``."""
    res = {d: analyze(curve, voussoirs=voussoirs, direction=d) for d in (1, -1)}
    model = ImpactModel(curve, voussoirs=voussoirs, qp=False)
    level = -0.1 * curve.density * curve.thickness * curve.length * GRAVITY * curve.thickness
    eqs = {}

    def equation(m):
        key = (m.s, m.sides)
        if key not in eqs:
            eqs[key] = EquationOfMotion(m)
        return eqs[key]
    A = min(res[1].A_L, res[-1].A_L)
    t = _onset(a_g, A, 0.0, t_quiet)
    d = -int(math.copysign(1, a_g(t + 1e-9)))
    assert abs(abs(a_g(t)) - res[d].A_L) < 1e-12 or t == 0.0
    mech, rate = Mechanism.from_hinges(curve, res[d].hinges_before), 0.0
    out = {"onset": t, "impacts": [], "t_overturn": None, "outcome": "survived", "free": []}
    while True:
        eq = equation(mech)
        barrier = eq.potential(eq.sign * eq.theta_unstable)
        f, hit, over = _arch_functions(eq, a_g, level, t)
        y = [0.0, rate]
        if t >= t_quiet:
            out["free"].append((False, True, eq.energy(0.0, rate) / barrier))
        for tb in (t_quiet, t_end):
            if tb <= t:
                continue
            sol = solve_ivp(f, (t, tb), y, method="DOP853", rtol=1e-12, atol=1e-15, events=(hit, over))
            t, y = float(sol.t[-1]), sol.y[:, -1]
            if sol.status == 1:
                break
            if tb == t_quiet:
                out["free"].append((eq.sign * y[0] > eq.theta_unstable, eq.sign * y[1] > 0,
                                    eq.energy(y[0], y[1]) / barrier))
        else:
            return out
        if sol.t_events[1].size:
            out["outcome"], out["t_overturn"] = "overturned", t
            return out
        tr = model(mech)
        assert tr.after is not None           # no arrest in these motions
        rate = abs(y[1]) * tr.alpha_ratio
        at_rest = 0.5 * equation(tr.after).coefficients(0.0)[0] * rate * rate < 1e-12 * barrier
        out["impacts"].append((t, float(y[1]), 0.0 if at_rest else rate))
        if at_rest:
            assert t >= t_quiet               # at rest only once the ground is still
            out["outcome"] = "rest"
            return out
        mech = tr.after


# --------------------------------------------------------------------------- equation of motion
def test_lambda_at_rest_is_the_fe_kinetic_energy(paper_eq):
    """Lambda(0) = d^T M d of the mechanism's field on a mesh through its hinges (the FE mass
    matrix, assembled by scikit-fem: an independent route to the integrals)."""
    _, eq = paper_eq
    m = eq.mechanism
    disc = discretize(PAPER, nodes_through(uniform_nodes(PAPER, 400), np.asarray(m.s)))
    d = m.dofs(disc)
    assert eq.coefficients(0.0)[0] == pytest.approx(float(d @ disc.M @ d), rel=1e-10)


def test_derivatives_against_differences(paper_eq):
    """Lambda' (from the four-bar's acceleration analysis), V' and Q (velocities) against
    central differences of Lambda, of V (positions of the centroids) and of sum m x_G."""
    _, eq = paper_eq
    h = 1e-5
    for th in eq.sign * np.array([0.0, 0.3, 0.8]) * eq.theta_unstable:
        lam, dlam, dv, q = eq.coefficients(th)
        assert dlam == pytest.approx((eq.coefficients(th + h)[0] - eq.coefficients(th - h)[0]) / (2 * h), rel=1e-7)
        assert dv == pytest.approx((eq.potential(th + h) - eq.potential(th - h)) / (2 * h), rel=1e-7, abs=1e-9)
        assert q == pytest.approx(GRAVITY * (eq.horizontal_moment(th + h) - eq.horizontal_moment(th - h)) / (2 * h),
                                  rel=1e-7)


def test_static_load_factor_at_rest_is_A_L(paper_eq):
    """At theta = 0 the equation's V'/Q is the load factor of the mechanism: A_L."""
    res, eq = paper_eq
    _, _, dv, q = eq.coefficients(0.0)
    assert dv / q == pytest.approx(res.A_L, rel=1e-9)
    assert eq.sign * dv > 0          # gravity restores


def test_block_unstable_equilibrium_and_impact():
    b = block()
    alpha = math.atan(0.25)
    eq = EquationOfMotion(Mechanism.from_hinges(b, analyze(b, voussoirs=1).hinges_before))
    assert eq.theta_unstable == pytest.approx(alpha, rel=1e-12)
    R = 0.5 * math.hypot(0.5, 2.0)
    assert eq.coefficients(0.0)[0] == pytest.approx(4 / 3 * b.density * 0.5 * 2.0 * R**2, rel=1e-12)   # J, corner
    res = rock(b, GroundMotion.sine(0.5, 0.5), voussoirs=1, t_end=3.0, thrust_check=False)
    assert res.impacts
    for e in res.impacts:
        assert e.r == pytest.approx((1 - 1.5 * math.sin(alpha) ** 2) ** 2, rel=1e-12)
        assert abs(e.rate_out / e.rate_in) == pytest.approx(1 - 1.5 * math.sin(alpha) ** 2, rel=1e-12)
        assert e.r_qp == pytest.approx(e.r, rel=1e-8)     # a block has one compatible mechanism


@pytest.mark.parametrize("amplitude, period", [(0.5, 0.5), (-0.4, 0.8)])
def test_block_motion_is_housners(amplitude, period):
    """The whole motion of the block against Housner's equation integrated here
    (:func:`housner_motion`): the onset at ``T/(2 pi) asin(tan alpha / A)``, every impact's time
    and incoming rate, every turning point, the overturning time (measured: 2e-11 s, 1e-11 rad)."""
    ref = housner_motion(0.5, 2.0, sine_pulse(amplitude, period), period, 3.0)
    res = rock(block(), GroundMotion.sine(amplitude, period), voussoirs=1, t_end=3.0, thrust_check=False)
    assert res.outcome == ("overturned" if ref["t_overturn"] is not None else "survived")
    if ref["t_overturn"] is not None:
        assert res.t_overturn == pytest.approx(ref["t_overturn"], abs=1e-9)
    t_on = period / (2 * math.pi) * math.asin(0.25 / abs(amplitude))
    assert [t for t, _ in res.onsets] == pytest.approx(ref["onsets"], abs=1e-12) and ref["onsets"][0] == pytest.approx(
        t_on, abs=1e-12)
    assert len(res.impacts) == len(ref["impacts"]) >= 1
    for e, (t, rate_in, rate_out) in zip(res.impacts, ref["impacts"]):
        assert e.t == pytest.approx(t, abs=1e-9)
        assert abs(e.rate_in) == pytest.approx(abs(rate_in), rel=1e-9)
        assert abs(e.rate_out) == pytest.approx(abs(rate_out), rel=1e-9)
    assert len(res.peaks) == len(ref["peaks"]) >= 1
    for (t, _, theta), (t_ref, phi) in zip(res.peaks, ref["peaks"]):
        assert t == pytest.approx(t_ref, abs=1e-8) and abs(theta) == pytest.approx(phi, rel=1e-9, abs=1e-12)


# --------------------------------------------------------------------------- Housner
def test_housner_free_rocking_amplitudes_and_intervals():
    """Free rocking after the pulse: the amplitudes follow
    ``cos(alpha - th_{n+1}) = cos(alpha) + r_v^2 (cos(alpha - th_n) - cos(alpha))``; between two
    impacts around a turning point ``th`` the block takes, from the energy integral
    ``theta'^2 = 2 p^2 (cos(alpha - theta) - cos(alpha - th))``, the time
    ``2 int_0^th dtheta / theta'`` (adaptive quadrature, measured 6e-11 relative), which
    Housner's linearised solution ``(2/p) arccosh(1 / (1 - th/alpha))`` approaches to within
    ``alpha^2 / 6`` (the relative error of ``sin x ~ x`` over ``x <= alpha``; measured 0.2-0.4 %)."""
    alpha, R = math.atan(0.25), 0.5 * math.hypot(0.5, 2.0)
    p = math.sqrt(3 * GRAVITY / (4 * R))
    rv = 1 - 1.5 * math.sin(alpha) ** 2
    res = rock(block(), GroundMotion.sine(0.5, 0.5), voussoirs=1, t_end=6.0, thrust_check=False)
    peaks = [(t, abs(th)) for t, _, th in res.peaks if t > 0.5]      # free rocking after the pulse
    assert len(peaks) >= 6
    for (_, a), (_, b) in zip(peaks, peaks[1:]):
        expected = alpha - math.acos(math.cos(alpha) + rv**2 * (math.cos(alpha - a) - math.cos(alpha)))
        assert b == pytest.approx(expected, rel=1e-8)
    t_imp = np.array([e.t for e in res.impacts])
    free = [(t, th, np.searchsorted(t_imp, t)) for t, th in peaks if t_imp[0] > 0.5 or t > t_imp[t_imp > 0.5][0]]
    assert len(free) >= 5
    for t, th, i in free:
        # theta = th (1 - v^2): the integrand without the square-root singularity at the turning point
        exact = 2 * quad(lambda v, th=th: th * v / (p * math.sqrt(math.sin(alpha - th + 0.5 * th * v * v)
                                                                   * math.sin(0.5 * th * v * v))),
                         0.0, 1.0, epsabs=0.0, epsrel=1e-13)[0]
        assert t_imp[i] - t_imp[i - 1] == pytest.approx(exact, rel=1e-9)
        linear = 2 / p * math.acosh(1 / (1 - th / alpha))
        assert abs(linear / exact - 1) < alpha**2 / 6


def test_rectangular_pulse_threshold_small_angle():
    """Overturning above a/(g alpha) = 1/(1 - exp(-p t1)), p = sqrt(3g/(4R)), as alpha -> 0:
    the nonlinear threshold differs by O(alpha^2)."""
    errs = []
    for width in (0.04, 0.02):
        b = block(width, 2.0)
        alpha, R = math.atan(width / 2.0), 0.5 * math.hypot(width, 2.0)
        p = math.sqrt(3 * GRAVITY / (4 * R))
        t1 = 1.0 / p
        formula = alpha / (1 - math.exp(-p * t1))
        rk = Rocker(b, voussoirs=1, qp=False)
        lo, hi = formula * 0.98, formula * 1.02
        # near the threshold the block creeps over its unstable equilibrium, then falls to the
        # overturning level: 40 / p after the pulse leaves every bisection step time to do so
        t_end = t1 + 40 / p
        assert rk.run(GroundMotion.rectangular(lo, t1), t_end=t_end, thrust_check=False).outcome != "overturned"
        assert rk.run(GroundMotion.rectangular(hi, t1), t_end=t_end, thrust_check=False).outcome == "overturned"
        for _ in range(18):
            mid = 0.5 * (lo + hi)
            over = rk.run(GroundMotion.rectangular(mid, t1), t_end=t_end, thrust_check=False).outcome
            lo, hi = (lo, mid) if over == "overturned" else (mid, hi)
        errs.append(abs(hi / formula - 1))
    assert errs[1] < 1e-3
    assert 3.0 < errs[0] / errs[1] < 5.0          # O(alpha^2)


# --------------------------------------------------------------------------- onset, first impact
def test_onset_just_above_and_not_below_A_L(paper_eq):
    res, _ = paper_eq
    rk = Rocker(PAPER, qp=False)
    for sign in (1, -1):         # a_g > 0 loads the arch to the left, a_g < 0 to the right
        below = rk.run(GroundMotion.rectangular(sign * res.A_L * (1 - 1e-6), 0.5), t_end=0.1, thrust_check=False)
        above = rk.run(GroundMotion.rectangular(sign * res.A_L * (1 + 1e-6), 0.5), t_end=0.1, thrust_check=False)
        assert not below.onsets and below.peak_rotation == 0.0 and below.outcome == "rest"
        assert above.onsets and above.onsets[0][0] == 0.0 and above.peak_rotation > 0


def test_onset_time_on_a_ramp():
    gm = GroundMotion(np.array([0.0, 1.0, 2.0]), np.array([0.0, 1.0, -1.0]))
    assert onset_time(gm, 0.0, 3.0, 0.5, 0.25) == (pytest.approx(0.25), -1)
    assert onset_time(gm, 0.5, 3.0, 0.5, 2.0) == (pytest.approx(1.75), 1)
    assert onset_time(gm, 0.0, 3.0, 2.0, 2.0) is None


@pytest.mark.parametrize("voussoirs", [7, None])
def test_first_impact_is_the_restricted_impact(voussoirs):
    """The first impact after an onset on the +1 mechanism reproduces fembeam impact's
    restricted r and alpha' (voussoirs: to 1e-11, the motion's hinges being at their canonical
    positions, rounded to 1e-12 of the length; continuous: hinges snapped to L/100000)."""
    ref = four_hinge_impact(PAPER, voussoirs=voussoirs, model="restricted")
    # to 0.3 s: the first impact (0.22 s, 7 voussoirs; 0.24 s, continuous), not the 55 that follow by 1 s
    res = rock(PAPER, GroundMotion.rectangular(-0.5, 0.1), voussoirs=voussoirs, t_end=0.3, thrust_check=False)
    first = res.impacts[0]
    assert res.onsets[0][1] == first.before == 0
    tol = 1e-11 if voussoirs else 1e-5
    assert first.r == pytest.approx(ref.r, rel=tol)
    assert abs(first.rate_out / first.rate_in) == pytest.approx(abs(ref.extra["alpha_ratio"]), rel=tol)
    assert first.r <= first.r_qp * (1 + 1e-6)
    assert np.allclose(res.mechanisms[first.after].s, ref.after.s, atol=PAPER.length * 1e-4)


# --------------------------------------------------------------------------- energy
def test_energy_conserved_in_free_motion_and_balanced_under_forcing():
    res = rock(PAPER, GroundMotion.sine(0.6, 0.3), voussoirs=7, t_end=2.0, thrust_check=False)
    h = res.history
    eqs = [EquationOfMotion(m) for m in res.mechanisms]
    barrier = max(abs(e.potential(e.sign * e.theta_unstable)) for e in eqs)
    assert res.energy_balance_error < 1e-8
    E = h["K"] + h["V"]
    t_imp = np.array([e.t for e in res.impacts])
    free = (h["t"] > 0.3) & (h["mechanism"] >= 0)
    episode = np.searchsorted(t_imp, h["t"])
    for k in np.unique(episode[free]):
        sel = free & (episode == k)
        if sel.sum() > 2:
            assert np.ptp(E[sel]) < 1e-8 * barrier
    # at each impact K' = r K
    for e in res.impacts:
        eb, ea = eqs[e.before], eqs[e.after] if e.after is not None else None
        K_in = 0.5 * eb.coefficients(0.0)[0] * e.rate_in**2
        if ea is not None and not e.at_rest:
            assert 0.5 * ea.coefficients(0.0)[0] * e.rate_out**2 == pytest.approx(e.r * K_in, rel=1e-10)


@pytest.mark.parametrize("case", ["rest", "pushed_back", "overturned", "survived"])
def test_energy_block(case):
    """``energy``: ``K_end + V_end = ground_work - dissipated`` (from rest); ``dissipated`` the sum
    of ``K_in - K_out`` over the impacts (``Lambda(0)`` of each mechanism, its rates); the ground's
    work against ``-int a_g Q theta' dt`` by the trapezoidal rule on a fine history; ``V_min``
    against the history's smallest V (and the level -0.1 m g w of a block that overturns)."""
    if case == "overturned":
        b = block(0.5, 2.0)
        rk, ground, t_end = Rocker(b, voussoirs=1, qp=False), GroundMotion.rectangular(0.6, 1.0), None
    else:
        rk = Rocker(PAPER, voussoirs=7, qp=False)
        ground, t_end = {"rest": (GroundMotion.sine(0.6, 0.3), 3.0),
                         "pushed_back": (GroundMotion.sine(1.0095, 0.45), 3.0),
                         "survived": (GroundMotion.sine(0.6, 0.3), 0.5)}[case]
    res = rk.run(ground, t_end=t_end, dt_out=1e-4, thrust_check=False)
    assert res.outcome == {"pushed_back": "rest"}.get(case, case)
    d = res.to_dict()
    e = d["energy"]
    assert set(e) == {"K_end", "V_end", "V_min", "ground_work", "dissipated"}
    assert d["n_impacts"] == len(res.impacts) and all({"t", "r"} <= set(i) for i in d["impacts"])
    scale = max(rk.barriers)
    assert e["K_end"] + e["V_end"] == pytest.approx(e["ground_work"] - e["dissipated"], abs=1e-8 * scale)
    eqs = [EquationOfMotion(m) for m in res.mechanisms]
    lam = [eq.coefficients(0.0)[0] for eq in eqs]
    lost = sum(0.5 * lam[i.before] * i.rate_in ** 2
               - (0.5 * lam[i.after] * i.rate_out ** 2 if i.after is not None else 0.0) for i in res.impacts)
    assert e["dissipated"] == pytest.approx(lost, abs=1e-12 * scale)
    h = res.history
    moving = h["mechanism"] >= 0
    Q = np.array([eqs[int(k)].coefficients(th)[3] if k >= 0 else 0.0 for k, th in zip(h["mechanism"], h["theta"])])
    power = np.where(moving, -h["a_g"] * Q * h["rate"], 0.0)
    keep = np.r_[True, np.diff(h["t"]) > 0]          # an event row repeats its time: one side of a jump
    W = np.trapezoid(power[keep], h["t"][keep])
    assert e["ground_work"] == pytest.approx(W, rel=1e-3, abs=1e-6 * scale)
    assert e["V_min"] <= h["V"].min() + 1e-12 * scale and e["V_min"] >= h["V"].min() - 1e-6 * scale
    if case == "overturned":
        assert e["V_min"] == pytest.approx(-0.1 * b.density * 0.5 * 2.0 * GRAVITY * 0.5, rel=1e-9)
        assert e["V_end"] == e["V_min"] and e["K_end"] > 0
    if case == "pushed_back":         # past the unstable equilibrium of the first mechanism, and back
        assert res.peak_theta > rk.equations[0].theta_unstable and e["V_min"] >= -1e-12 * scale
    if case == "rest":
        assert e["K_end"] == e["V_end"] == 0.0 and abs(e["V_min"]) <= 1e-12 * scale
        assert e["dissipated"] == pytest.approx(e["ground_work"], abs=1e-8 * scale)
    if case == "survived":
        assert e["K_end"] > 0


# --------------------------------------------------------------------------- invariance
def test_time_scales_with_sqrt_R_over_g():
    small = rock(CircularArch.from_ratio(157.5, 0.15, radius=1.0), GroundMotion.sine(0.6, 0.3), voussoirs=7,
                 t_end=2.0, thrust_check=False)
    big = rock(CircularArch.from_ratio(157.5, 0.15, radius=4.0), GroundMotion.sine(0.6, 0.6), voussoirs=7,
               t_end=4.0, thrust_check=False)
    assert small.outcome == big.outcome
    ts, tb = np.array([e.t for e in small.impacts]), np.array([e.t for e in big.impacts])
    n = min(len(ts), len(tb), 20)
    assert n >= 5
    assert np.allclose(tb[:n], 2 * ts[:n], rtol=1e-7)
    assert big.peak_rotation == pytest.approx(small.peak_rotation, rel=1e-7)
    assert [e.r for e in big.impacts[:n]] == pytest.approx([e.r for e in small.impacts[:n]], rel=1e-10)


def test_mirror_symmetry_of_the_pulse_direction():
    plus = rock(PAPER, GroundMotion.sine(0.6, 0.3), voussoirs=7, t_end=2.0, thrust_check=False)
    minus = rock(PAPER, GroundMotion.sine(-0.6, 0.3), voussoirs=7, t_end=2.0, thrust_check=False)
    assert plus.outcome == minus.outcome
    # theta is the rotation of the first piece from the left: mirrored, that is another piece
    assert plus.peak_rotation == pytest.approx(minus.peak_rotation, rel=1e-6)   # integration error
    n = min(len(plus.impacts), len(minus.impacts), 20)
    assert n >= 5
    for a, b in zip(plus.impacts[:n], minus.impacts[:n]):
        assert b.t == pytest.approx(a.t, rel=1e-6)
        assert b.r == pytest.approx(a.r, rel=1e-10)
        ma, mb = plus.mechanisms[a.after], minus.mechanisms[b.after]
        assert np.allclose(mb.mirrored().s, ma.s, atol=1e-12) and mb.mirrored().sides == ma.sides


def _sampled_peaks(rk, res):
    """Largest |rotation| of any piece and largest |theta| over the history's rows, each piece's
    rotation recomputed from the row's theta (EquationOfMotion.piece_rotations)."""
    h = res.history
    eqs = [rk.equations[rk.index(m)] for m in res.mechanisms]      # the run's own numbering
    rot = np.array([0.0 if k < 0 else max(abs(x) for x in eqs[int(k)].piece_rotations(th))
                    for k, th in zip(h["mechanism"], h["theta"])])
    i = int(np.argmax(rot))
    return rot[i], h["t"][i], float(np.max(np.abs(h["theta"])))


def test_peak_rotation_is_the_largest_piece_rotation_and_mirror_invariant():
    """``peak_rotation`` is the largest rotation of any piece (the sampled history's, recomputed
    from theta row by row, to within one sampling step of the peak) and does not depend on the
    direction of the pulse (1e-9); ``peak_theta`` is the largest |theta| (the first moving piece
    from the left: after mirroring, another piece)."""
    rk = Rocker(CircularArch.from_ratio(157.5, 0.15, radius=5.0), voussoirs=7, qp=False)
    dt = 1e-4
    runs = [rk.run(GroundMotion.sine(a, 0.56), thrust_check=False, dt_out=dt) for a in (0.6, -0.6)]
    for res in runs:
        rot, t_rot, theta = _sampled_peaks(rk, res)
        # near a peak a rotation differs from it by O(rate^2 dt^2): here well below 1e-6 of it
        assert res.peak_rotation * (1 - 1e-6) <= rot <= res.peak_rotation * (1 + 1e-12)
        assert abs(t_rot - res.t_peak) <= dt
        assert res.peak_theta * (1 - 1e-6) <= theta <= res.peak_theta * (1 + 1e-12)
        assert res.peak_theta <= res.peak_rotation
        d = res.to_dict()
        assert d["peak_rotation"] == res.peak_rotation and d["peak_theta"] == res.peak_theta
        assert "peak_piece_rotation" not in d
    plus, minus = runs
    assert abs(plus.peak_rotation - minus.peak_rotation) <= 1e-9
    assert abs(plus.t_peak - minus.t_peak) <= 1e-9
    # the first moving piece of one run is the last of the other: their theta peaks differ
    assert abs(plus.peak_theta - minus.peak_theta) > 1e-3 * plus.peak_rotation


# --------------------------------------------------------------------------- accumulation, overturning
def test_accumulation_ends_at_rest_in_finite_time():
    res = rock(PAPER, GroundMotion.sine(0.6, 0.3), voussoirs=7, t_end=10.0, thrust_check=False)
    assert res.outcome == "rest"
    t = np.array([e.t for e in res.impacts])
    assert res.impacts[-1].at_rest and t[-1] < 5.0
    dt = np.diff(t)[-10:]
    assert np.all(dt[1:] < dt[:-1])              # a converging (geometric) series of impact times


def test_overturning_reported_with_its_time():
    """The block overturns when its centroid is a tenth of its width below its height at rest:
    ``R cos(theta - alpha) = h/2 - 0.1 w`` (R: half-diagonal), V = -0.1 m g w there; the time
    is Housner's equation's, integrated here (:func:`housner_motion`; measured 5e-12 s)."""
    w, h = 0.5, 2.0
    res = rock(block(w, h), GroundMotion.rectangular(0.6, 1.0), voussoirs=1, thrust_check=False)
    assert res.outcome == "overturned" and res.overturn_reason == "below_rest"
    ref = housner_motion(w, h, rectangular_pulse(0.6, 1.0), 1.0, 10.0)
    assert ref["onsets"] == [0.0] and not ref["impacts"]
    assert res.t_overturn == pytest.approx(ref["t_overturn"], abs=1e-9)
    alpha, R = math.atan(w / h), 0.5 * math.hypot(w, h)
    assert res.peak_rotation == pytest.approx(alpha + math.acos((h / 2 - 0.1 * w) / R), rel=1e-9)
    assert res.t_peak == res.t_overturn and res.history["t"][-1] == res.t_overturn
    rho = block(w, h).density                                     # the default, 2000 kg/m^3
    assert res.history["V"][-1] == pytest.approx(-0.1 * (rho * w * h) * GRAVITY * w, rel=1e-9)


def test_barrier_and_settles_agree_with_the_overturning_event():
    """The overturning level is -0.1 m g t (m = rho R t beta, the annular sector); the barrier
    is the largest V from rest to the overturning rotation (a 20001-point grid of V); a free
    motion from rest with 1 -+ 1e-6 of the barrier as kinetic energy returns to an impact (and
    ``settles`` says so) or reaches the overturning rotation with V at the level (and
    ``settles`` says it cannot tell)."""
    from fembeam.dynamics.episode import Signal as _Signal, episode as _episode
    from fembeam.dynamics.result import Track as _Track

    rk = Rocker(PAPER, voussoirs=7, qp=False)
    mass = PAPER.density * PAPER.radius * PAPER.thickness * math.radians(PAPER.embrace_deg)
    assert rk.level == pytest.approx(-0.1 * mass * GRAVITY * PAPER.thickness, rel=1e-12)
    k = rk.index(rk.start[1])
    eq, top = rk.equations[k], rk.tops[k]
    V = np.array([eq.potential(eq.sign * x) for x in np.linspace(0.0, top, 20001)])
    assert V.max() <= rk.barrier(k) <= V.max() * (1 + 1e-8) and rk.events[k] == "overturn"
    assert eq.potential(eq.sign * top) == pytest.approx(rk.level, rel=1e-12) and np.all(V[:-1] > rk.level)
    still = GroundMotion(np.array([0.0, 1.0]), np.zeros(2))
    for f, event in ((1 - 1e-6, "impact"), (1 + 1e-6, "overturn")):
        rate = eq.sign * math.sqrt(2 * f * rk.barrier(k) / eq.coefficients(0.0)[0])
        ev, t, theta, _, err, _ = _episode(eq, k, _Signal(still), 0.0, 30.0, 0.0, rate, _Track(np.empty(0), False),
                                        top, rk.events[k])
        assert ev == event and err < 1e-8
        assert rk.settles(k, 0.0, rate) == (event == "impact")
        if event == "overturn":
            assert eq.potential(theta) == pytest.approx(rk.level, rel=1e-9)


def test_a_linkage_that_locks_before_the_level_overturns():
    """With a level the mechanisms cannot reach before their four-bar locks (1e6 times the
    member's weight times its thickness below rest), overturning is the lock: the rotation stops
    just short of the lock angle and the reason is ``linkage_locked``."""
    from fembeam.dynamics.outcomes import overturning

    rk = Rocker(PAPER, voussoirs=7, qp=False)
    eq = rk.equations[rk.index(rk.start[1])]
    top, event, barrier = overturning(eq, -1e6 * rk.mass * GRAVITY * PAPER.thickness)
    assert event == "locked" and top == eq.theta_lock * (1 - 1e-9) and math.isfinite(top)
    assert barrier == pytest.approx(eq.potential(eq.sign * eq.theta_unstable), rel=1e-12)
    locked = Rocker(PAPER, voussoirs=7, qp=False)
    locked.level = -1e6 * locked.mass * GRAVITY * PAPER.thickness      # before any mechanism is set up
    res = locked.run(GroundMotion.rectangular(2.0, 1.0), thrust_check=False)
    k = int(res.history["mechanism"][-1])
    assert res.outcome == "overturned" and res.overturn_reason == "linkage_locked"
    assert locked.equations[k].sign * res.history["theta"][-1] == pytest.approx(locked.equations[k].theta_lock,
                                                                                rel=1e-8)


def _housner_overturns_at_alpha(A, alpha, p, t1, t_end):
    """The former rule by an independent route: Housner's equation about the corner,
    ``phi'' = p^2 (A cos(alpha - phi) - sin(alpha - phi))`` (``A`` in g during the pulse, 0 after),
    from rest; overturned when ``phi`` reaches ``alpha`` before ``t_end``; safe when it returns to
    0 after the pulse (the impact then leaves less energy than the barrier)."""
    from scipy.integrate import solve_ivp

    def f(t, y, a):
        return [y[1], p * p * (a * math.cos(alpha - y[0]) - math.sin(alpha - y[0]))]

    def up(t, y, a):
        return y[0] - alpha

    def back(t, y, a):
        return y[0]
    up.terminal, up.direction, back.terminal, back.direction = True, 1, True, -1
    y = [0.0, 0.0]
    for (t0, t1_, a) in ((0.0, t1, A), (t1, t_end, 0.0)):
        s = solve_ivp(f, (t0, t1_), y, args=(a,), events=(up, back), method="DOP853", rtol=1e-12, atol=1e-14)
        if s.t_events[0].size:
            return True
        if s.t_events[1].size:
            assert a == 0.0          # back at rest after the pulse, never during it
            return False
        y = s.y[:, -1]
    return False


@pytest.mark.parametrize("width", [0.5, 0.04])
def test_rectangular_pulse_threshold_same_under_the_former_rule(width):
    """A rectangular pulse that ends before the block reaches its unstable equilibrium: the
    overturning amplitude bisected with the overturning rule (centroid 0.1 w below rest) and
    with the former one (the rotation reaches alpha, integrated independently) fall in the same
    bracket of the bisection (18 steps from [0.9, 1.3] x the small-angle formula: 1.5e-6 wide)."""
    b = block(width, 2.0)
    alpha, R = math.atan(width / 2.0), 0.5 * math.hypot(width, 2.0)
    p = math.sqrt(3 * GRAVITY / (4 * R))
    t1 = 1.0 / p
    t_end = t1 + 40 / p
    formula = alpha / (1 - math.exp(-p * t1))      # small-angle threshold: the bracket's scale
    rk = Rocker(b, voussoirs=1, qp=False)

    def bisect(overturns, lo, hi):
        assert not overturns(lo) and overturns(hi)
        for _ in range(18):
            mid = 0.5 * (lo + hi)
            lo, hi = (lo, mid) if overturns(mid) else (mid, hi)
        return lo, hi

    def new(a):
        return rk.run(GroundMotion.rectangular(a, t1), t_end=t_end, thrust_check=False).outcome == "overturned"

    lo, hi = 0.9 * formula, 1.3 * formula
    new_lo, new_hi = bisect(new, lo, hi)
    old_lo, old_hi = bisect(lambda a: _housner_overturns_at_alpha(a, alpha, p, t1, t_end), lo, hi)
    assert (new_lo, new_hi) == (old_lo, old_hi)
    # the pulse is over before the block reaches alpha at the threshold: it lingers near it
    res = rk.run(GroundMotion.rectangular(new_hi, t1), t_end=t_end, thrust_check=False)
    eq = rk.equations[res.onsets[0][1]]
    th = np.interp(t1, res.history["t"], res.history["theta"])
    assert eq.sign * th < 0.9 * alpha and res.t_overturn > t1


@pytest.mark.parametrize("ratio", [1.0, 3.0])
def test_one_sine_pulse_overturning_threshold(ratio):
    """The smallest amplitude of a one-sine pulse ``A sin(omega_p t)``, ``omega_p = ratio p``,
    that overturns the block (tan alpha = 0.25), bisected (16 steps from [1, 20] tan alpha) with
    ``rock`` and with Housner's equation integrated here (:func:`housner_motion`, impacts
    included): the same bracket (measured: [1.10582, 1.10611] and [1.40009, 1.40038] tan alpha)."""
    w, h = 0.5, 2.0
    alpha, R = math.atan(w / h), 0.5 * math.hypot(w, h)
    p = math.sqrt(3 * GRAVITY / (4 * R))
    period = 2 * math.pi / (ratio * p)
    t_end = period + 40 / p
    rk = Rocker(block(w, h), voussoirs=1, qp=False)

    def bisect(overturns):
        lo, hi = math.tan(alpha), 20 * math.tan(alpha)
        assert not overturns(lo * (1 + 1e-9)) and overturns(hi)
        for _ in range(16):
            mid = 0.5 * (lo + hi)
            lo, hi = (lo, mid) if overturns(mid) else (mid, hi)
        return lo, hi

    got = bisect(lambda a: rk.run(GroundMotion.sine(a, period), t_end=t_end, thrust_check=False,
                                  history=False).outcome == "overturned")
    ref = bisect(lambda a: housner_motion(w, h, sine_pulse(a, period), period, t_end)["t_overturn"] is not None)
    assert got == ref


def test_cannot_stand_is_an_outcome():
    res = rock(CircularArch.from_ratio(180.0, 0.05), GroundMotion.sine(0.1, 0.5), voussoirs=7, thrust_check=False)
    assert res.outcome == "cannot_stand" and not res.impacts


# --------------------------------------------------------------------------- validity of the one-mechanism model
def test_thrust_line_exit_is_located_on_the_joints():
    """Voussoirs are monolithic: the check is at their joints.  At the reported exit time the
    smallest joint margin is -THRUST_TOL (the crossing is bisected); just before, it is inside."""
    from fembeam.dynamics.admissibility import THRUST_TOL
    from fembeam.dynamics.thrust import section_forces

    res = rock(PAPER, GroundMotion.sine(0.6, 0.3), voussoirs=7, t_end=0.3)
    t_on, t_x = res.onsets[0][0], res.thrust_line_exits_at
    assert t_on < t_x < res.impacts[0].t
    eq = EquationOfMotion(res.mechanisms[0])
    joints = uniform_nodes(PAPER, 7)
    h = res.history

    def margin(t):
        th, w = np.interp(t, h["t"], h["theta"]), np.interp(t, h["t"], h["rate"])
        a = float(GroundMotion.sine(0.6, 0.3)(t))
        return section_forces(eq, th, w, eq.acceleration(th, w, a), a, joints).margin

    assert margin(t_on + 0.2 * (t_x - t_on)) > -THRUST_TOL
    assert margin(t_x + 0.01) < -1e-3


def test_a_block_never_leaves_its_one_piece_mechanism():
    res = rock(block(), GroundMotion.sine(0.5, 0.5), voussoirs=1, t_end=3.0)
    assert res.impacts and res.thrust_line_exits_at is None


# --------------------------------------------------------------------------- the integrator
def _reference_episode(eq, ground, t0, rate0, t_stop):
    """SciPy's solve_ivp (DOP853, rtol 1e-13) from ``theta = 0``, restarted at every sample
    of the record, to the next impact: ``(impact time, [(ta, tb, dense solution)])``."""
    from scipy.integrate import solve_ivp

    at = ground.scalar()

    def f(t, y):
        Lam, dLam, dV, Q = eq.coefficients(y[0])
        return [y[1], -(0.5 * dLam * y[1] ** 2 + dV + at(t) * Q) / Lam]

    def hit(t, y):
        return eq.sign * y[0]
    hit.terminal, hit.direction = True, -1
    edges = [t0, *ground.t[(ground.t > t0) & (ground.t < t_stop)], t_stop]
    y, pieces = [0.0, rate0], []
    for ta, tb in zip(edges[:-1], edges[1:]):
        s = solve_ivp(f, (ta, tb), y, method="DOP853", rtol=1e-13, atol=1e-16, dense_output=True, events=hit)
        pieces.append((ta, s.t[-1], s.sol))
        if s.status == 1:
            return float(s.t_events[0][0]), pieces
        y = s.y[:, -1]
    return None, pieces


def test_integrator_agrees_with_solve_ivp_on_a_record():
    """The run's own DOP853 (plain floats, steps ending on the samples without restarts)
    against solve_ivp at rtol 1e-13 restarted at every sample, episode by episode from the
    run's onset and impacts on El Centro: impact times and the rotation at the history's rows
    agree to 1e-8."""
    arch = CircularArch.from_ratio(157.5, 0.15, radius=5.0)
    ground = GroundMotion.record("elcentro").to_pga(0.8)
    rk = Rocker(arch, voussoirs=7, qp=False)
    res = rk.run(ground, t_end=3.6, thrust_check=False)
    h = res.history
    starts = [(res.onsets[0][0], res.onsets[0][1], 0.0)] + [(e.t, e.after, e.rate_out) for e in res.impacts[:9]]
    assert len(res.impacts) >= 10 and not any(e.at_rest for e in res.impacts[:10])
    for (t0, k, rate0), e in zip(starts, res.impacts[:10]):
        assert e.before == k
        t_hit, pieces = _reference_episode(rk.equations[k], ground, t0, rate0, e.t + 0.05)
        assert t_hit == pytest.approx(e.t, abs=1e-8)
        scale = max(abs(p[2](0.5 * (p[0] + p[1]))[0]) for p in pieces)
        rows = np.flatnonzero((h["t"] > t0) & (h["t"] < min(t_hit, e.t)) & (h["mechanism"] == k))
        assert rows.size
        for i in rows:
            ta, tb, sol = next(p for p in pieces if p[0] <= h["t"][i] <= p[1])
            assert abs(sol(h["t"][i])[0] - h["theta"][i]) <= 1e-8 * scale


def test_an_event_within_one_step_is_found():
    """The member crosses the unstable equilibrium by 1e-5 of it and the pulse pushes it back
    (the former stepper, restarted at each sample, missed this crossing): the run follows it
    (the overturning rule waits for the level below rest) and agrees with solve_ivp at rtol
    1e-13 on the turning point and the next impact; a return to theta = 0 within one step is an
    impact, so no turning point lies on the closed side of theta = 0 or beyond the overturning
    rotation."""
    rk = Rocker(PAPER, voussoirs=7, qp=False)
    ground = GroundMotion.sine(3.4692178537028293, 0.15)
    res = rk.run(ground, thrust_check=False)
    eq = rk.equations[0]
    (t_on, k0), (t_turn, k1, th_turn) = res.onsets[0], res.peaks[0]
    assert k0 == k1 == res.impacts[0].before == 0
    assert eq.theta_unstable < eq.sign * th_turn < eq.theta_unstable * (1 + 1e-4) and res.outcome != "overturned"
    t_hit, pieces = _reference_episode(eq, ground, t_on, 0.0, res.impacts[0].t + 0.05)
    assert t_hit == pytest.approx(res.impacts[0].t, abs=1e-8)
    sol = next(p[2] for p in pieces if p[0] <= t_turn <= p[1])
    assert sol(t_turn)[0] == pytest.approx(th_turn, abs=1e-9 * eq.theta_unstable)
    assert abs(sol(t_turn)[1]) < 1e-6 * abs(res.impacts[0].rate_in)     # a turning point
    arch = CircularArch.from_ratio(157.5, 0.15, radius=5.0)
    rk = Rocker(arch, voussoirs=7, qp=False)
    ground = GroundMotion.record("elcentro").to_pga(1.0)
    res = rk.run(ground, t_end=3.0, thrust_check=False)
    assert res.outcome != "overturned" and len(res.peaks) > 15
    for t, k, theta in res.peaks:
        eq = rk.equations[k]
        assert -1e-12 * eq.theta_unstable <= eq.sign * theta <= rk.tops[k], (t, k, theta)
    # near 2.05 s two impacts 0.1 ms apart, which a step across both crossings of theta = 0 would
    # miss: from the impact before them on, each next impact against solve_ivp on the record,
    # restarted from the run's previous impact (measured 2e-15 s)
    i = next(j for j, e in enumerate(res.impacts) if e.t > 2.05)
    predicted = []
    for prev, e in zip(res.impacts[i - 1:i + 2], res.impacts[i:i + 3]):
        t_hit, _ = _reference_episode(EquationOfMotion(res.mechanisms[prev.after]), ground, prev.t, prev.rate_out,
                                      e.t + 0.05)
        assert e.before == prev.after and t_hit == pytest.approx(e.t, abs=1e-9)
        predicted.append(t_hit)
    assert predicted[0] < 2.052 and 0 < predicted[1] - predicted[0] < 2e-4


def test_a_crossing_of_the_overturning_rotation_and_back_within_one_step():
    """One step whose interpolant rises from 0.9 top to 1.1 top and back to 0.9 top
    (``theta(x) = 0.9 top + 0.8 top x (1 - x)`` on ``x`` in [0, 1]): the overturning event is at
    ``x (1 - x) = 1/8``, before the turning point at ``x = 1/2``."""
    from fembeam.dynamics.events import step_events as _step_events

    top, h, ta = 0.4, 0.01, 2.0
    F = ((0.0, 0.8 * top, 0.0, 0.0, 0.0, 0.0, 0.0),               # theta: F0 x + F1 x (1 - x)
         (-2 * 0.8 * top / h, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0))      # rate: -2 F1 x / h
    ya = (0.9 * top, 0.8 * top / h)
    ga, gb = (0.9 * top, -0.1 * top, ya[1]), (0.9 * top, -0.1 * top, -ya[1])
    events = _step_events(ya, F, ta, ta + h, ga, gb, 1.0, top, "overturn")
    x = (1 - math.sqrt(0.5)) / 2
    assert sorted(name or "turn" for _, name in events) == ["overturn", "turn"]
    assert dict((name, t) for t, name in events)["overturn"] == pytest.approx(ta + x * h, abs=1e-14)
    assert dict((name, t) for t, name in events)[None] == pytest.approx(ta + 0.5 * h, abs=1e-14)


@functools.cache
def _paper_rocker():
    return Rocker(PAPER, voussoirs=7, qp=False)


@functools.cache
def _paper_motion(amplitude, period):
    """``rock`` (the full run) and :func:`arch_motion` of the paper's arch (7 voussoirs) under a
    one-sine pulse."""
    full = _paper_rocker().run(GroundMotion.sine(amplitude, period), thrust_check=False, history=False)
    return full, arch_motion(PAPER, 7, sine_pulse(amplitude, period), period, full.t_end)


@pytest.mark.parametrize("amplitude, period", [(0.6, 0.3), (-0.6, 0.3), (0.45, 0.45), (0.55, 0.45), (0.6, 0.45),
                                               (0.8, 0.45), (1.0, 0.45), (1.0095, 0.45)])
def test_arch_motion_against_an_independent_integration(amplitude, period):
    """The whole motion of the paper's arch (7 voussoirs) under one-sine pulses against
    :func:`arch_motion` (solve_ivp on the equation of motion, with its own event location): the
    onset at ``T/(2 pi) asin(A_L / |A|)``, the outcome, every impact's time (measured: 2e-10 s at
    most) and rates, the overturning time.  (1.0095 g, 0.45 s: the member is past its unstable
    equilibrium when the pulse ends and comes back to rest.)"""
    full, ref = _paper_motion(amplitude, period)
    A_L = analyze(PAPER, voussoirs=7).A_L
    assert [t for t, _ in full.onsets] == pytest.approx([ref["onset"]], abs=1e-12)
    assert ref["onset"] == pytest.approx(period / (2 * math.pi) * math.asin(A_L / abs(amplitude)), abs=1e-12)
    assert full.outcome == ref["outcome"]
    assert len(full.impacts) == len(ref["impacts"]) >= 1
    for e, (t, rate_in, rate_out) in zip(full.impacts, ref["impacts"]):
        assert e.t == pytest.approx(t, abs=1e-8)
        assert e.rate_in == pytest.approx(rate_in, rel=1e-7) and e.rate_out == pytest.approx(rate_out, rel=1e-7)
    if ref["outcome"] == "overturned":
        assert full.t_overturn == pytest.approx(ref["t_overturn"], abs=1e-8)
    if amplitude == 1.0095:
        assert ref["free"][0][0] and ref["outcome"] == "rest"


@pytest.mark.parametrize("amplitude", [0.45, 0.55, 0.6, 0.8, 1.0])
def test_settle_stops_only_when_the_free_motion_comes_to_rest(amplitude):
    """``settle=True`` stops at the end of the pulse exactly when the independent integration
    (:func:`arch_motion`) comes to rest with a free motion that never passes an unstable
    equilibrium: at the pulse's end short of it, and heading back or below the barrier there and
    after every later impact; otherwise it goes on to the full run's outcome."""
    full, ref = _paper_motion(amplitude, 0.45)
    short = _paper_rocker().run(GroundMotion.sine(amplitude, 0.45), thrust_check=False, history=False, settle=True)
    assert all(abs(ratio - 1) > 1e-6 for *_, ratio in ref["free"])        # none on the edge of a barrier
    provable = ref["outcome"] == "rest" and all(not past and (not out or ratio < 1) for past, out, ratio in ref["free"])
    assert (short.settled_at is not None) == provable
    if provable:
        assert short.settled_at == short.t_end == 0.45 and short.outcome == "rest"
        assert full.outcome == "rest" and len(full.impacts) > 40
    else:
        assert short.outcome == full.outcome
        assert short.t_overturn == pytest.approx(full.t_overturn, abs=1e-9)
