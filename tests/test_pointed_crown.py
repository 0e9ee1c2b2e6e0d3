"""The crown of a pointed arch as built, against an independent voussoir model.

The arch: two concentric intrados and extrados arcs on each side, continued to the axis; a
vertical crown joint from where the intrados meet, ``(0, y_i)``, to where the extrados meet,
``(0, y_e)``; each arc's radial joints up to the one through ``(0, y_i)`` (a radial cut
beyond it would cross the crown joint), the crown wedge between that cut and the crown
joint belonging to the voussoir next to the crown.

The independent model is built here from scratch: the voussoirs of each arc as annular
sectors (area and first moment in closed form), the crown voussoirs as a sector plus the
wedge, which is the pie slice of the extrados disc between the polar angles of the two
meeting points less the triangle (centre, (0, y_i), (0, y_e)) (a polygon); the joints as
their two corner points and direction.  The limit analysis is a small LP (HiGHS): at every
joint two corner forces N >= 0 along the joint's tangent and a shear, each voussoir in
equilibrium under its weight and a horizontal inertia force lambda times it, lambda
maximised; the minimum thickness bisects the thickness at which the same equations under
gravity alone are feasible.  On the same voussoirs the package's discrete analysis agrees
to round-off; on finer ones the independent figures converge to the package's continuum
``A_L`` and ``t_min`` (every voussoir joint is a section of the continuum, so they bound
them from above and below), at a fitted rate of about 2.
"""
from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.optimize import linprog

from fembeam import PointedArch, analyze, minimum_thickness, uniform_nodes

SPAN, T = 2.0, 0.15
RISES = {"equilateral": math.sqrt(3.0),                 # e/Rp = 1/2
         "e/Rp=0.2": 2.0 * math.sqrt(0.375)}            # H^2 = 0.375 L^2: e/Rp = 0.2
# the package's continuum figures (A_L in g, t_min in m); before the crown was modelled as
# built (wedges left out, a crown joint of depth t at (0, H)) they were 0.105778 g and
# 0.0882457 m for the equilateral arch, 0.155452 g and 0.0884450 m for e/Rp = 0.2
FIGURES = {"equilateral": (0.1256596833, 0.07995217228), "e/Rp=0.2": (0.1555240981, 0.08844473480)}


# ---------------------------------------------------------------------------- independent model
def crown(span, rise, t):
    e, R = rise**2 / span - span / 4, rise**2 / span + span / 4
    a, b = R - t / 2, R + t / 2
    return dict(e=e, R=R, a=a, b=b, phi_c=math.atan2(rise, -e), phi_i=math.acos(-e / a), phi_e=math.acos(-e / b),
                y_i=math.sqrt(a * a - e * e), y_e=math.sqrt(b * b - e * e))


def _sector(r0, r1, p0, p1, cx):
    """Area and first moment of ``{(cx, 0) + r (cos p, sin p): r0 <= r <= r1, p0 <= p <= p1}``."""
    A = 0.5 * (r1 * r1 - r0 * r0) * (p1 - p0)
    k = (r1**3 - r0**3) / 3
    return A, np.array([k * (math.sin(p1) - math.sin(p0)) + A * cx, k * (math.cos(p0) - math.cos(p1))])


def _polygon(P):
    """Area (> 0) and first moment of the polygon with vertices ``P`` (n, 2)."""
    x, y = np.asarray(P, float).T
    x1, y1 = np.roll(x, -1), np.roll(y, -1)
    c = x * y1 - x1 * y
    A = 0.5 * c.sum()
    return abs(A), np.sign(A) * np.array([((x + x1) * c).sum() / 6, ((y + y1) * c).sum() / 6])


def voussoirs(span, rise, t, per_half):
    """The arch in ``2 per_half`` voussoirs of equal angle (radial joints at polar angles
    ``pi - k (pi - phi_c) / per_half`` about (e, 0)), those a crown wedge swallows left out.
    Returns the voussoirs ``(area, first moment)`` and the joints ``(intrados corner,
    extrados corner, tangent)``, both from the left springing to the right one."""
    c = crown(span, rise, t)
    e, a, b = c["e"], c["a"], c["b"]
    step = (math.pi - c["phi_c"]) / per_half
    phis = [p for p in (math.pi - k * step for k in range(per_half)) if p >= c["phi_i"]]
    C = np.array([e, 0.0])
    joints = [(C + a * np.array([math.cos(p), math.sin(p)]), C + b * np.array([math.cos(p), math.sin(p)]),
               np.array([math.sin(p), -math.cos(p)])) for p in phis]
    joints.append((np.array([0.0, c["y_i"]]), np.array([0.0, c["y_e"]]), np.array([1.0, 0.0])))
    pieces = [_sector(a, b, q, p, e) for p, q in zip(phis[:-1], phis[1:])]
    A1, S1 = _sector(a, b, c["phi_i"], phis[-1], e)                 # the crown voussoir's sector ...
    A2, S2 = _sector(0.0, b, c["phi_e"], c["phi_i"], e)             # ... and its wedge: a pie slice
    A3, S3 = _polygon([(e, 0.0), (0.0, c["y_i"]), (0.0, c["y_e"])])  # less a triangle
    pieces.append((A1 + A2 - A3, S1 + S2 - S3))

    def mirror(v):
        return np.array([-v[0], v[1]])
    pieces += [(A, mirror(S)) for A, S in reversed(pieces)]
    joints += [(mirror(i), mirror(x), np.array([tg[0], -tg[1]])) for i, x, tg in reversed(joints[:-1])]
    return pieces, joints


def _equilibrium(pieces, joints):
    """``A z = b`` for ``z`` = (per joint: N at the intrados corner, N at the extrados corner,
    shear; then lambda): the force on the voussoir right of a joint is ``+`` (on the left
    one ``-``) ``(N_i + N_e) t + S n``; each voussoir balances its weight and ``lambda``
    times it along +x; rows scaled by the total weight."""
    nv, nj = len(pieces), len(joints)
    A = np.zeros((3 * nv, 3 * nj + 1))
    b = np.zeros(3 * nv)
    for j, (pi, pe, tg) in enumerate(joints):
        nrm = np.array([tg[1], -tg[0]])
        for v, sign in ((j - 1, -1.0), (j, 1.0)):
            if 0 <= v < nv:
                for col, (P, d) in enumerate(((pi, tg), (pe, tg), (0.5 * (pi + pe), nrm))):
                    f = sign * d
                    A[3 * v:3 * v + 3, 3 * j + col] += [f[0], f[1], P[0] * f[1] - P[1] * f[0]]
    for v, (W, S) in enumerate(pieces):
        b[3 * v + 1] += W
        b[3 * v + 2] += S[0]
        A[3 * v, -1] += W
        A[3 * v + 2, -1] -= S[1]
    W = sum(p[0] for p in pieces)
    return A / W, b / W


def limit_lp(span, rise, t, per_half) -> float:
    """The largest horizontal acceleration (g) an admissible state of the voussoirs carries."""
    A, b = _equilibrium(*voussoirs(span, rise, t, per_half))
    nj = (A.shape[1] - 1) // 3
    c = np.zeros(A.shape[1])
    c[-1] = -1.0
    res = linprog(c, A_eq=A, b_eq=b, bounds=[(0, None), (0, None), (None, None)] * nj + [(None, None)],
                  method="highs")
    assert res.status == 0
    return float(res.x[-1])


def stands(span, rise, t, per_half) -> bool:
    """Whether an admissible state carries the voussoirs' weight alone: the largest ``mu``
    with every corner force ``>= mu`` (units of the weight), capped at 1, is ``>= 0``."""
    A, b = _equilibrium(*voussoirs(span, rise, t, per_half))
    nj = (A.shape[1] - 1) // 3
    A[:, -1] = 0.0                                           # lambda = 0; the last unknown is mu
    ub = np.zeros((2 * nj, A.shape[1]))
    for j in range(nj):
        ub[2 * j:2 * j + 2, 3 * j:3 * j + 2] = -np.eye(2)
        ub[2 * j:2 * j + 2, -1] = 1.0
    c = np.zeros(A.shape[1])
    c[-1] = -1.0
    res = linprog(c, A_ub=ub, b_ub=np.zeros(2 * nj), A_eq=A, b_eq=b,
                  bounds=[(None, None)] * (A.shape[1] - 1) + [(None, 1.0)], method="highs")
    assert res.status == 0
    return res.x[-1] >= 0.0


def tmin_lp(span, rise, per_half, lo=0.05, hi=0.10, tol=1e-9) -> float:
    assert not stands(span, rise, lo, per_half) and stands(span, rise, hi, per_half)
    while hi - lo > tol * hi:
        mid = 0.5 * (lo + hi)
        lo, hi = (lo, mid) if stands(span, rise, mid, per_half) else (mid, hi)
    return hi


@pytest.fixture(scope="module", params=list(RISES))
def case(request):
    return request.param, PointedArch(span=SPAN, rise=RISES[request.param], thickness=T)


# ---------------------------------------------------------------------------- the pieces
def test_voussoirs_and_joints_are_the_independent_ones(case):
    """The package's voussoirs of ``uniform_nodes`` (sector pieces, the crown voussoirs with
    their wedges) and its joints (the crown joint at its full depth) are the independent ones."""
    name, arch = case
    for n in (8, 16, 64):
        nodes = uniform_nodes(arch, n)
        pieces, joints = voussoirs(SPAN, RISES[name], T, n // 2)
        assert nodes.size == len(pieces) + 1 == len(joints)
        m, S, _ = arch.segment_inertia(nodes[:-1], nodes[1:])
        A_ref = arch.density * np.array([p[0] for p in pieces])      # masses: density times the areas
        S_ref = arch.density * np.array([p[1] for p in pieces]).T
        assert np.allclose(m, A_ref, rtol=1e-12, atol=0)
        assert np.allclose(S, S_ref, rtol=0, atol=1e-13 * SPAN * A_ref.sum())
        h = 0.5 * arch.thickness_at(nodes)
        assert np.allclose(arch.point(nodes, h), np.array([j[0] for j in joints]).T, rtol=0, atol=1e-14 * SPAN)
        assert np.allclose(arch.point(nodes, -h), np.array([j[1] for j in joints]).T, rtol=0, atol=1e-14 * SPAN)
        assert np.allclose(arch.tangent(nodes), np.array([j[2] for j in joints]).T, rtol=0, atol=1e-14)


# ---------------------------------------------------------------------------- the same voussoirs
@pytest.mark.parametrize("n", [8, 16, 32, 64])
def test_voussoir_limit_analysis_equals_the_independent_lp(case, n):
    """A_L of the voussoir arch: the package's LP on its joints against the independent LP
    (measured: 1e-14 relative)."""
    name, arch = case
    assert analyze(arch, voussoirs=n).A_L == pytest.approx(limit_lp(SPAN, RISES[name], T, n // 2), rel=1e-10)


def test_voussoir_minimum_thickness_equals_the_independent_bisection(case):
    name, arch = case
    got = minimum_thickness(arch, voussoirs=16, tol=1e-10).scale * T
    assert got == pytest.approx(tmin_lp(SPAN, RISES[name], 8, tol=1e-11), rel=1e-9)


# ---------------------------------------------------------------------------- finer voussoirs
def _rate(n, err):
    return float(np.polyfit(np.log(1.0 / np.asarray(n, float)), np.log(np.abs(err)), 1)[0])


def test_finer_voussoirs_converge_to_the_continuum(case):
    """The independent voussoir figures on 32 ... 512 voussoirs bound the package's continuum
    ones (A_L from above, t_min from below: their joints are sections of the continuum) and
    converge to them; least-squares rate over the meshes (measured: A_L 2.7 and 2.4,
    t_min 2.0 and 1.8; on 512 voussoirs within 1.8e-6 and 9.8e-6 (A_L), 1.8e-5 and 1.5e-5
    (t_min) relative).  The package's continuum figures are mesh-independent."""
    name, arch = case
    A_L, t_min = FIGURES[name]
    for el in (60, 101, 200):
        assert analyze(arch, elements=el).A_L == pytest.approx(A_L, rel=1e-9)
    assert minimum_thickness(arch, elements=101, tol=1e-10).scale * T == pytest.approx(t_min, rel=1e-9)
    n = [32, 64, 128, 256, 512]
    dA = np.array([limit_lp(SPAN, RISES[name], T, k // 2) for k in n]) / A_L - 1.0
    dt = 1.0 - np.array([tmin_lp(SPAN, RISES[name], k // 2) for k in n]) / t_min
    assert np.all(dA > -1e-9) and np.all(dt > -1e-8)
    assert dA[-1] < 2e-5 and dt[-1] < 3e-5
    assert _rate(n, dA) > 1.8 and _rate(n, dt) > 1.5


def test_equilateral_arch_hinges_on_the_crown_joint():
    """The equilateral arch's mechanism turns about the crown joint's intrados end (0, y_i),
    reported at 90 deg; the arch of e/Rp = 0.2 keeps its hinges off the crown."""
    res = analyze(PointedArch(span=SPAN, rise=RISES["equilateral"], thickness=T), elements=200)
    h = res.hinges_before
    assert [x.side for x in h] == ["intrados", "extrados", "intrados", "extrados"]
    assert h[2].angle_deg == 90.0 and h[2].s == 0.5 * res.limit.disc.curve.length
    c = crown(SPAN, RISES["equilateral"], T)
    assert np.allclose(res.limit.disc.curve.point(h[2].s, 0.5 * res.limit.disc.curve.thickness_at(h[2].s)),
                       [0.0, c["y_i"]], rtol=0, atol=1e-14)
    other = analyze(PointedArch(span=SPAN, rise=RISES["e/Rp=0.2"], thickness=T), elements=200)
    assert all(abs(x.angle_deg - 90.0) > 10.0 for x in other.hinges_before)


# ---------------------------------------------------------------------------- the same pieces elsewhere
def material(span, rise, t, sa, sb):
    """Area and first moment of the arch between its sections at ``sa < sb`` (arc lengths of
    the mid-curve, each on a radial cut or the crown joint), independently: annular sectors
    of each arc, plus each crown wedge the piece holds."""
    c = crown(span, rise, t)
    R, e, a, b = c["R"], c["e"], c["a"], c["b"]
    half = R * (math.pi - c["phi_c"])
    s_i = R * (math.pi - c["phi_i"])
    A2, S2 = _sector(0.0, b, c["phi_e"], c["phi_i"], e)
    A3, S3 = _polygon([(e, 0.0), (0.0, c["y_i"]), (0.0, c["y_e"])])

    def left(s0, s1):           # left coordinates, s0 < s1 <= half
        A, S = _sector(a, b, math.pi - min(s1, s_i) / R, math.pi - s0 / R, e)
        return (A + A2 - A3, S + S2 - S3) if s1 == half else (A, S)
    parts = []
    if sa < half:
        parts.append(left(sa, min(sb, half)))
    if sb > half:
        A, S = left(2 * half - sb, 2 * half - max(sa, half))
        parts.append((A, np.array([-S[0], S[1]])))
    return sum(p[0] for p in parts), sum(p[1] for p in parts)


def test_impact_and_dynamics_use_the_same_pieces(case):
    """The impact's mass matrix, the pieces of the mechanism (the equation of motion of
    ``rock``) and the bodies of ``simulate`` carry the crown wedges: their masses and
    centroids are the independent ones."""
    from fembeam.dynamics.equation import EquationOfMotion
    from fembeam.mechanisms import Mechanism
    from fembeam.simulation.bodies import Bodies

    name, arch = case
    rise = RISES[name]
    res = analyze(arch, elements=60)
    # the impact's mesh (through the hinges): mass and first moment
    disc = res.impact.disc
    rho = arch.density                          # the independent model's areas times the density
    W, S = (rho * x for x in material(SPAN, rise, T, 0.0, arch.length))
    ex, ey, rot = disc.rigid(V=(1.0, 0.0)), disc.rigid(V=(0.0, 1.0)), disc.rigid(omega=1.0)
    assert ex @ disc.M @ ex == pytest.approx(W, rel=1e-12)
    assert ex @ disc.M @ rot == pytest.approx(-S[1], rel=1e-12)
    assert ey @ disc.M @ rot == pytest.approx(S[0], abs=1e-13 * W * SPAN)
    # the equation of motion: the moving pieces between the hinges
    mech = Mechanism.from_hinges(arch, res.hinges_before)
    eq = EquationOfMotion(mech)
    br = np.r_[0.0, mech.s, arch.length]
    for p, k in zip(eq.pieces, np.flatnonzero(mech.moving)):
        A, Sk = (rho * x for x in material(SPAN, rise, T, br[k], br[k + 1]))
        assert p.m == pytest.approx(A, rel=1e-12) and np.allclose(p.G0, Sk / A, rtol=0, atol=1e-13 * SPAN)
    # simulate's bodies on 16 voussoirs
    pieces, _ = voussoirs(SPAN, rise, T, 8)
    bodies = Bodies.from_curve(arch, 16)
    assert np.allclose(bodies.m, [rho * p[0] for p in pieces], rtol=1e-12)
    assert np.allclose(bodies.G0, np.array([p[1] / p[0] for p in pieces]).T, rtol=0, atol=1e-13 * SPAN)


def convergence_table(counts=(16, 32, 64, 128, 256, 512, 1024)) -> str:
    """The table of docs/shapes.md: the independent voussoir figures against the package's
    continuum ones, with the package's own voussoir A_L beside them."""
    lines = []
    for name, rise in RISES.items():
        arch = PointedArch(span=SPAN, rise=rise, thickness=T)
        A_L = analyze(arch, elements=200).A_L
        t_min = minimum_thickness(arch, elements=200, tol=1e-11).scale * T
        lines.append(f"{name} arch, span {SPAN:g}, rise {rise:.6f}, t = {T:g}: continuum (200 elements) "
                     f"A_L = {A_L:.10f} g, t_min = {t_min:.10f}")
        lines.append("     N   A_L (LP here)   A_L (fembeam)   rel. error   t_min (LP here)   rel. error")
        dA, dt = [], []
        for n in counts:
            lam, own = limit_lp(SPAN, rise, T, n // 2), analyze(arch, voussoirs=n).A_L
            tm = tmin_lp(SPAN, rise, n // 2, tol=1e-11)
            dA.append(lam / A_L - 1.0)
            dt.append(1.0 - tm / t_min)
            lines.append(f"{n:6d}  {lam:.10f}    {own:.10f}    {dA[-1]:9.2e}    {tm:.10f}      {dt[-1]:9.2e}")
        lines.append(f"  least-squares rate over N = {counts[0]}..{counts[-1]}: A_L {_rate(counts, dA):.2f}, "
                     f"t_min {_rate(counts, dt):.2f}")
    return "\n".join(lines) + "\n"


if __name__ == "__main__":
    print(convergence_table(), end="")
