"""``fembeam min-thickness``: any shape, its collapse mechanism, the funicular case."""
from __future__ import annotations

import json
import math

import numpy as np

import pytest

from fembeam import CircularArch, minimum_thickness
from fembeam.analysis.thickness import stands_on
from fembeam.cli.main import main
from fembeam.fem import uniform_nodes
from fembeam.geometry import CatenaryArch, EllipticalArch, ParabolicArch, PointedArch

MILANKOVITCH = 0.107478   # semicircle, true centroids, radial joints (Milankovitch 1907; Ochsendorf 2002)


def _run(capsys, *argv):
    code = main(["min-thickness", *argv])
    out = capsys.readouterr()
    return code, out.out, out.err


def test_semicircle_against_milankovitch(capsys):
    code, out, _ = _run(capsys, "--embrace", "180", "--json")
    d = json.loads(out)
    assert code == 0 and d["outcome"] == "ok"
    assert d["t_min_over_R"] == pytest.approx(MILANKOVITCH, abs=1e-6)
    assert d["thickness_min"]["thickness"] == pytest.approx(d["t_min_over_R"])
    assert d["geometric_safety_factor"] == pytest.approx(0.15 / d["t_min_over_R"], rel=1e-12)
    # the collapse mechanism: springing and crown on the extrados, haunches 54.5 deg from the crown
    angles = {round(h["angle_deg"], 1): h["side"] for h in d["hinges"]}
    assert angles.get(35.5) == "intrados" and angles.get(144.5) == "intrados" and angles.get(90.0) == "extrados"


def test_bracket_is_a_certificate():
    """Independently of the bisection: the arch at the reported factor stands, just below it does not."""
    a = PointedArch(span=10.0, rise=7.0, thickness=0.5)
    th = minimum_thickness(a, elements=80, tol=1e-8)
    nodes = uniform_nodes(a, 80)
    assert stands_on(a.with_thickness_scaled(th.scale), nodes, True)
    assert not stands_on(a.with_thickness_scaled(th.lower), nodes, True)
    assert th.scale - th.lower <= 1e-8 * th.scale


def test_shapes_of_half_circle_limit_give_its_minimum_thickness():
    """Pointed and elliptical arches with rise = span / 2 are the semicircle: same t_min to 1e-9."""
    L, t = 10.0, 0.6
    ref = minimum_thickness(CircularArch(radius=L / 2, embrace_deg=180.0, thickness=t), elements=40, tol=1e-12)
    for a in (PointedArch(span=L, rise=L / 2, thickness=t), EllipticalArch(span=L, rise=L / 2, thickness=t)):
        got = minimum_thickness(a, elements=40, tol=1e-12)
        assert got.scale == pytest.approx(ref.scale, rel=1e-9)


def test_catenary_stands_at_any_thickness(capsys):
    """The uniform catenary is the funicular of its weight up to the centroid offset: it stands
    at every thickness checked (checked directly, not through the bisection); the parabola of
    the same span and rise does not, and a catenary thinning towards the crown neither."""
    a = CatenaryArch(span=10.0, rise=4.0, thickness=0.5)
    nodes = uniform_nodes(a, 100)
    for k in (1.0, 0.1, a.min_thickness_scale):
        assert stands_on(a.with_thickness_scaled(k), nodes, True)
    code, out, _ = _run(capsys, "--shape", "catenary", "--span", "10", "--rise", "4", "--thickness", "0.5", "--json")
    d = json.loads(out)
    assert code == 0 and d["outcome"] == "stands_at_any_thickness" and d["thickness_min"] == {"thickness": 0.0}
    assert d["geometric_safety_factor"] is None and "funicular" in d["explanation"]
    assert d["thickness_checked_min"]["thickness"] == pytest.approx(0.5 * a.min_thickness_scale)
    par = minimum_thickness(ParabolicArch(span=10.0, rise=4.0, thickness=0.5), elements=100)
    assert par.outcome == "ok" and 0.01 < par.scale < 1
    var = minimum_thickness(CatenaryArch(span=10.0, rise=4.0, thickness_springing=0.6, thickness_crown=0.3),
                            elements=100)
    assert var.outcome == "ok" and var.scale > 0.05


def test_variable_thickness_reports_both_ends(capsys):
    code, out, _ = _run(capsys, "--shape", "elliptical", "--span", "10", "--rise", "3",
                        "--thickness-springing", "1.2", "--thickness-crown", "0.6", "--elements", "30")
    assert code == 0
    assert "thickness springing" in out and "thickness crown" in out and "geometric factor of safety" in out
    code, out, _ = _run(capsys, "--shape", "elliptical", "--span", "10", "--rise", "3",
                        "--thickness-springing", "1.2", "--thickness-crown", "0.6", "--elements", "30", "--json")
    d = json.loads(out)
    tm = d["thickness_min"]
    assert tm["thickness_springing"] == pytest.approx(2 * tm["thickness_crown"], rel=1e-12)
    assert tm["thickness_crown"] == pytest.approx(0.6 * d["thickness_scale"], rel=1e-12)


def test_voussoirs_check_the_joints_only(capsys):
    """Fewer joints to check: a discrete arch needs no more thickness than the continuum."""
    cont = minimum_thickness(CircularArch.from_ratio(180, 0.15), elements=100)
    vous = minimum_thickness(CircularArch.from_ratio(180, 0.15), voussoirs=7)
    assert vous.scale <= cont.scale
    code, out, _ = _run(capsys, "--embrace", "180", "--voussoirs", "7", "--json")
    assert code == 0 and json.loads(out)["t_min_over_R"] == pytest.approx(vous.t_over_R, rel=1e-5)


@pytest.mark.parametrize("argv, words", [
    (["--tol", "0"], "--tol"),
    (["--elements", "2"], "--elements"),
    (["--voussoirs", "0"], "--voussoirs"),
    (["--friction", "-1"], "--friction"),
    (["--friction", "nan"], "[0, 1000]"),
    (["--friction", "1e9"], "[0, 1000]"),
    (["--shape", "parabolic", "--span", "10"], "--rise"),
])
def test_bad_input_exit_2_one_line(capsys, argv, words):
    try:
        code = main(["min-thickness", *argv])
    except SystemExit as e:      # argparse's own checks
        code = e.code
    err = capsys.readouterr().err
    assert code == 2 and words in err and len(err.strip().splitlines()) == 1


def test_never_stands_is_an_answer(capsys):
    """A near-full ring whose folding limit comes before a thrust line fits."""
    a = CircularArch.from_ratio(350, 0.05)
    th = minimum_thickness(a, elements=60)
    code, out, _ = _run(capsys, "--embrace", "350", "--t-over-r", "0.05", "--elements", "30", "--json")
    d = json.loads(out)
    assert code == 0 and th.outcome == d["outcome"] == "never_stands"
    assert d["thickness_min"] is None and d["thickness_scale"] is None and "admits a thrust line" in d["explanation"]


def _symmetric_tmin(curve_xy, n=80_000):
    """Minimum constant thickness of a symmetric arch, independently of the package: the
    half arch from the left springing to the crown cut into ``n`` slices by normal cuts,
    each slice a quadrilateral of its intrados and extrados points (shoelace area and
    first moment); a symmetric state (horizontal thrust P at height yc at the crown, which a
    symmetric arch always admits at its minimum thickness: the admissible states form a
    convex set closed under mirroring) must put the resultant inside every cut.  For a
    thickness t the largest margin over (P, m = P yc) is concave in P once m is centred (a
    golden-section search); its root in t is the minimum thickness.  ``curve_xy(u)`` gives the points and first derivatives for
    u in [0, 1] from the left springing to the crown."""
    from scipy.optimize import brentq

    u = np.linspace(0.0, 1.0, n + 1)
    X, dX = curve_xy(u)
    tx, ty = dX / np.hypot(*dX)
    nx, ny = ty, -tx                                   # normal, towards the intrados

    def margin(t):
        inn, out = X + 0.5 * t * np.array([nx, ny]), X - 0.5 * t * np.array([nx, ny])
        xs = np.array([inn[0, :-1], inn[0, 1:], out[0, 1:], out[0, :-1]])
        ys = np.array([inn[1, :-1], inn[1, 1:], out[1, 1:], out[1, :-1]])
        cross = xs * np.roll(ys, -1, 0) - np.roll(xs, -1, 0) * ys
        sgn = np.sign(cross.sum(0))
        A = 0.5 * sgn * cross.sum(0)
        Sy = sgn * (cross * (xs + np.roll(xs, -1, 0))).sum(0) / 6.0       # int x dA of each slice
        W = np.r_[np.cumsum(A[::-1])[::-1], 0.0] / A.sum()                # weight from cut i to the crown
        Wx = np.r_[np.cumsum(Sy[::-1])[::-1], 0.0] / A.sum()
        # force of the left part on [cut, crown]: F = (P, W); moment balance about the cut's
        # mid-point puts the resultant at offset e along n with e (n x F) = P y + (Wx - W x) - m,
        # m = P yc; |e| <= t/2 with n x F = nx W - ny P > 0, and the crown's own cut
        base_c, base_P = Wx - W * X[0], X[1]
        nxF_c, nxF_P = nx * W, -ny
        yc = X[1, -1]
        lo_c, lo_P = np.r_[base_c - 0.5 * t * nxF_c, 0.0], np.r_[base_P - 0.5 * t * nxF_P, yc - t / 2]
        hi_c, hi_P = np.r_[base_c + 0.5 * t * nxF_c, 0.0], np.r_[base_P + 0.5 * t * nxF_P, yc + t / 2]

        def tau(P):      # best m for this P: the middle of [max lo, min hi]; concave in P
            return 0.5 * (np.min(hi_c + hi_P * P) - np.max(lo_c + lo_P * P))

        a, b = 0.0, 1e3                                  # golden section on a concave function
        g = 0.5 * (math.sqrt(5.0) - 1.0)
        c, d = b - g * (b - a), a + g * (b - a)
        fc, fd = tau(c), tau(d)
        while b - a > 1e-15 * b:
            if fc > fd:
                b, d, fd = d, c, fc
                c = b - g * (b - a)
                fc = tau(c)
            else:
                a, c, fc = c, d, fd
                d = a + g * (b - a)
                fd = tau(d)
        return max(fc, fd)

    return brentq(margin, 1e-3, 2.0, xtol=1e-13, rtol=1e-13)


@pytest.mark.parametrize("shape", ["elliptical", "parabolic"])
def test_minimum_thickness_against_an_independent_thrust_line(shape):
    """The continuum's minimum thickness of a flat ellipse and a parabola (span 10 m, rise 3 m)
    against the symmetric thrust line on 8 10^4 shoelace slices between normal cuts
    (measured: 3e-12 and 4e-11 relative; 8e-9 and 4e-8 with 5 10^3 slices)."""
    import math as m
    L, H = 10.0, 3.0
    if shape == "elliptical":
        def xy(u):
            ph = m.pi * (1 - 0.5 * u)
            return (np.array([0.5 * L * np.cos(ph), H * np.sin(ph)]),
                    np.array([0.5 * L * np.sin(ph), -H * np.cos(ph)]) * (0.5 * m.pi))
        arch = EllipticalArch(span=L, rise=H, thickness=0.8)
    else:
        def xy(u):
            x = -0.5 * L * (1 - u)
            return np.array([x, H * (1 - (2 * x / L) ** 2)]), np.array([np.ones_like(x), -8 * H * x / L**2]) * (0.5 * L)
        arch = ParabolicArch(span=L, rise=H, thickness=0.6)
    ref = _symmetric_tmin(xy)
    got = minimum_thickness(arch, elements=40, tol=1e-10)
    t = arch.describe()["thickness"] * got.scale
    assert t == pytest.approx(ref, rel=1e-9)


def test_friction_options(capsys):
    """Large mu: the frictionless answer; mu = 0.31: a thicker arch whose collapse slides at a
    springing (hinges and slides in the JSON); mu = 0.30: below the smallest coefficient that
    lets a semicircle stand (0.3092 for the mid-curve load model), never stands."""
    free = minimum_thickness(CircularArch.from_ratio(180, 0.15), elements=40, tol=1e-8)
    code, out, _ = _run(capsys, "--embrace", "180", "--elements", "40", "--friction", "10", "--tol", "1e-8", "--json")
    assert code == 0 and json.loads(out)["thickness_scale"] == pytest.approx(free.scale, rel=1e-8)
    code, out, _ = _run(capsys, "--embrace", "180", "--elements", "40", "--friction", "0.31", "--json")
    d = json.loads(out)
    assert code == 0 and d["outcome"] == "ok" and d["t_min_over_R"] > 0.18 and d["friction"] == 0.31
    assert d["slides"] and d["slides"][0]["angle_deg"] in (0.0, 180.0) and len(d["hinges"]) >= 3
    code, out, _ = _run(capsys, "--embrace", "180", "--elements", "40", "--friction", "0.3")
    assert code == 0 and "never stands" in out and "|S| <= 0.3 N" in out


@pytest.mark.parametrize("width, height", [(0.4, 1.6), (5.0, 1.0), (2e-9, 1.0)])
def test_block_stands_at_any_width(width, height):
    """A block on a rigid base carries its weight through the middle of its base at any width:
    no minimum thickness (the search stops at the thinnest block it checks, width 1/2000 of the
    height or the smallest admitted width, without building a narrower one)."""
    from fembeam import StraightMember
    b = StraightMember(height=height, width=width)
    th = minimum_thickness(b, voussoirs=1)
    assert th.outcome == "stands_at_any_thickness" and th.scale == 0.0
    thinnest = b.with_thickness_scaled(b.min_thickness_scale)
    assert thinnest.width == pytest.approx(5e-4 * height, rel=1e-12)
    assert stands_on(thinnest, uniform_nodes(thinnest, 1), False)
