"""Arches as built: the fill's and the point masses' inertia, the load factor and the thrust
range on the continuous arch, the load scan, every dynamic model carrying the fill, outputs."""
import json
import pickle

import meshio
import numpy as np
import pytest

from fembeam import CircularArch, analyze, discretize, uniform_nodes
from fembeam.analysis.load_factor import load_factor
from fembeam.analysis.thrust_range import thrust_range
from fembeam.dynamics import EquationOfMotion, GroundMotion, Rocker
from fembeam.errors import InputError
from fembeam.geometry import PointedArch, ParabolicArch
from fembeam.geometry.asbuilt import Fill, as_built, build, extrados
from fembeam.simulation import Simulator
from fembeam.studies.load_scan import load_scan

from inprocess import fembeam

R, T = 5.0, 0.75            # a semicircle of 10 m span, t/R = 0.15
RHO, RHO_F, D = 2000.0, 1800.0, 0.5


@pytest.fixture(scope="module")
def bare():
    return CircularArch.from_ratio(180.0, T / R, radius=R, density=RHO)


@pytest.fixture(scope="module")
def filled(bare):
    return build(bare, fill_density=RHO_F, fill_depth=D)


def test_fill_columns_of_a_semicircle_exactly(bare, filled):
    """Mass, first and polar moment of the fill over the whole span against the closed form of
    the region between the extrados circle (radius Re) and the road y = Re + D."""
    Re, H = R + T / 2, R + T / 2 + D
    m, S, J = (a - b for a, b in zip(filled.segment_inertia(0.0, filled.length), bare.segment_inertia(0.0, bare.length)))
    area = 2 * Re * H - np.pi * Re**2 / 2
    Sy = (2 * Re * H**2 - 4 * Re**3 / 3) / 2                  # int (H^2 - ye^2)/2 dx
    Jx = (2 * Re**3 / 3) * H - (np.pi * Re**4 / 8)              # int x^2 (H - ye) dx
    ye3 = 3 * np.pi * Re**4 / 8                                 # int ye^3 dx over [-Re, Re]
    Jy = (2 * Re * H**3 - ye3) / 3                              # int (H^3 - ye^3) / 3 dx
    assert m[0] == pytest.approx(RHO_F * area, rel=1e-12)
    assert S[0, 0] == pytest.approx(0.0, abs=1e-9 * m[0] * R)
    assert S[1, 0] == pytest.approx(RHO_F * Sy, rel=1e-12)
    assert J[0] == pytest.approx(RHO_F * (Jx + Jy), rel=1e-12)


def test_pieces_add_up_and_a_point_mass_sits_on_one_piece(filled):
    c = as_built(filled, filled.fill, masses=[(2.0, 300.0)])
    m, S, J = c.segment_inertia(0.0, c.length)
    s = np.linspace(0.0, c.length, 8)
    mi, Si, Ji = c.segment_inertia(s[:-1], s[1:])
    assert mi.sum() == pytest.approx(m[0], rel=1e-12) and Ji.sum() == pytest.approx(J[0], rel=1e-12)
    assert np.allclose(Si.sum(1), S[:, 0], rtol=1e-12, atol=1e-9 * abs(S).max())
    # the mass on the extrados above x = 2 m from the left springing (x = -3 m)
    X = extrados(c, c._built["s_m"])[:, 0]
    assert X[0] == pytest.approx(-3.0, abs=1e-12) and X[1] == pytest.approx(np.sqrt((R + T / 2)**2 - 9), rel=1e-12)
    e = np.searchsorted(s, c._built["s_m"][0], side="right") - 1
    dm = mi - filled.segment_inertia(s[:-1], s[1:])[0]
    assert dm[e] == pytest.approx(300.0, rel=1e-12) and np.allclose(np.delete(dm, e), 0.0, atol=1e-9)
    # the mass matrix carries it too (the rigid elements' blocks)
    disc = discretize(c, s)
    assert disc.M.diagonal()[::3].sum() == pytest.approx(m[0], rel=1e-12)


def test_as_built_member_pickles_and_scales(filled):
    c = as_built(filled, filled.fill, masses=[(7.0, 500.0)])
    d = pickle.loads(pickle.dumps(c))
    assert d.describe() == c.describe()
    assert d.segment_inertia(0.0, d.length)[0][0] == c.segment_inertia(0.0, c.length)[0][0]
    thin = c.with_thickness_scaled(0.5)
    top = np.max(extrados(thin, np.linspace(0.0, thin.length, 20001))[1])
    assert thin.fill == c.fill and thin.road_level == pytest.approx(top + D, abs=1e-9)   # D above the new crown
    assert thin != c and c == pickle.loads(pickle.dumps(c)) and hash(c) == hash(pickle.loads(pickle.dumps(c)))
    assert build(filled, fill_density=1000.0) != build(filled, fill_density=2000.0)
    direct = build(c._built["plain"].with_thickness_scaled(0.5), fill_density=RHO_F, fill_depth=D, masses=[(7.0, 500.0)])
    assert thin == direct
    assert thin.segment_inertia(0.0, thin.length)[0][0] == direct.segment_inertia(0.0, direct.length)[0][0]


def test_nothing_added_is_the_member_itself(bare):
    assert build(bare) is bare and as_built(bare, Fill(0.0, 1.0)) is bare and as_built(bare, None, [(1.0, 0.0)]) is bare


@pytest.mark.parametrize("shape", ["pointed", "parabolic", "surveyed"])
def test_fill_on_other_shapes_by_quadrature_of_the_columns(shape, tmp_path):
    """The fill's mass of any shape against the area under the road above its extrados (trapezoid
    rule on a fine polyline of the extrados)."""
    if shape == "pointed":
        c = PointedArch(span=8.0, rise=6.0, thickness=0.6, density=RHO)
    elif shape == "parabolic":
        c = ParabolicArch(span=8.0, rise=2.5, thickness_springing=0.7, thickness_crown=0.5, density=RHO)
    else:
        from fembeam.geometry import SurveyedArch
        x = np.linspace(-4, 4, 41)
        p = tmp_path / "mid.csv"
        p.write_text("x,y\n" + "\n".join(f"{a},{3.0 * (1 - (a / 4) ** 2) + 0.1 * np.sin(a)}" for a in x))
        c = SurveyedArch.from_csv(str(p), thickness=0.5, density=RHO)
    f = build(c, fill_density=RHO_F, fill_depth=0.3)
    s = np.linspace(0.0, c.length, 200001)
    E = extrados(c, s)
    road = E[1].max() + 0.3
    area = np.trapezoid(road - E[1], E[0])
    dm = f.segment_inertia(0.0, f.length)[0][0] - c.segment_inertia(0.0, c.length)[0][0]
    assert f.road_level == pytest.approx(road, abs=1e-9)
    assert dm == pytest.approx(RHO_F * area, rel=1e-8)


def test_continuous_load_factor_and_thrust_range_converge(filled):
    """The continuum's load factor is mesh independent (bounds closed) and below every voussoir
    arch's (a voussoir arch has fewer places to hinge); the continuum's thrust range lies inside
    that of the joints of its own mesh."""
    loads = [(2.5, 100.0)]
    lf = [load_factor(filled, loads, elements=n) for n in (50, 200)]
    assert all(x.status == "ok" for x in lf)
    assert lf[0].value == pytest.approx(lf[1].value, rel=1e-9)
    assert lf[1].lower == pytest.approx(lf[1].value, rel=1e-9)
    vous = [load_factor(filled, loads, voussoirs=n).value for n in (12, 24, 48)]
    assert np.all(np.diff(vous) < 0) and vous[-1] > lf[1].value
    disc = discretize(filled, uniform_nodes(filled, 100))
    joints, cont = thrust_range(disc), thrust_range(disc, continuum=True)
    assert joints.H_min <= cont.H_min <= cont.H_max <= joints.H_max
    assert cont.H_min > joints.H_min * (1 + 1e-6)


def test_thrust_range_of_a_flat_arch_is_unbounded_above():
    res = analyze(CircularArch.from_ratio(60.0, 0.2, radius=2.0, density=RHO), elements=60)
    d = res.to_dict()["thrust_range"]
    assert d["H_max"] is None and d["H_max_unbounded"] and d["H_min"] > 0


def test_a_load_at_the_springing_is_no_mechanism_and_larger_fill_raises_the_factor(filled):
    assert load_factor(filled, [(0.0, 100.0)], voussoirs=12).status == "no_mechanism"
    f = [load_factor(build(filled, fill_density=RHO_F, fill_depth=d), [(2.5, 100.0)], voussoirs=12).value
         for d in (0.0, 1.0)]
    assert f[1] > f[0]


def test_load_scan_minimum_is_the_load_factor_there(filled):
    sc = load_scan(filled, 100.0, positions=21, voussoirs=16)
    i = sc.critical
    assert sc.min_factor == np.nanmin(sc.factor)
    direct = load_factor(filled, [(float(sc.x[i]), 100.0)], voussoirs=16)
    assert direct.value == pytest.approx(sc.min_factor, rel=1e-12)
    # a symmetric arch: the curve is symmetric about mid-span
    assert np.allclose(sc.factor, sc.factor[::-1], rtol=1e-8, equal_nan=True)
    with pytest.raises(InputError, match="positions"):
        load_scan(filled, 100.0, positions=1, voussoirs=16)


def test_impact_with_fill_qp_against_the_best_four_hinge_mechanism(filled):
    """r of the general QP (any compatible field) is at least the best four-hinge mechanism's,
    within the known gap of the restricted problem (a few 1e-3 on voussoir arches)."""
    from fembeam.mechanisms.four_hinge_analysis import four_hinge_impact

    out = four_hinge_impact(filled, voussoirs=9)
    res = analyze(filled, voussoirs=9)
    bare = analyze(CircularArch.from_ratio(180.0, T / R, radius=R, density=RHO), voussoirs=9)
    assert res.r >= float(out.r) - 1e-9
    assert res.r - float(out.r) < 5e-3
    assert abs(res.r - bare.r) > 1e-2         # the fill's inertia changes the impact


def test_rock_and_simulate_agree_on_a_filled_arch_while_one_mechanism_holds():
    """The fill moves with its voussoir in both models: the same motion (to 1e-6 rad) up to the
    moment rock's dynamic thrust line leaves the section."""
    arch = build(CircularArch.from_ratio(157.5, 0.15, density=RHO), fill_density=RHO_F, fill_depth=0.1)
    rk = Rocker(arch, voussoirs=7, qp=False)
    gm = GroundMotion.rectangular(-1.1 * rk.A[1], 0.2)
    ref = rk.run(gm, t_end=0.5, dt_out=1e-3)
    eqs = [EquationOfMotion(m) for m in ref.mechanisms]
    h = ref.history
    rock_rot = np.array([max(abs(x) for x in eqs[int(k)].piece_rotations(th)) if k >= 0 else 0.0
                         for k, th in zip(h["mechanism"], h["theta"])])
    res = Simulator(arch, voussoirs=7).run(gm, dt=1e-4, t_end=0.5, dt_out=1e-3)
    s = res.history
    t_exit = ref.thrust_line_exits_at if ref.thrust_line_exits_at is not None else 0.5
    before = s["t"] <= t_exit
    assert before.sum() > 50 and np.max(s["max_rotation"][before]) > 1e-3
    assert np.max(np.abs(s["max_rotation"][before] - np.interp(s["t"][before], h["t"], rock_rot))) < 1e-5
    # the bare arch moves differently: the fill's mass matters
    bare = Rocker(CircularArch.from_ratio(157.5, 0.15, density=RHO), voussoirs=7, qp=False)
    assert abs(bare.A[1] - rk.A[1]) > 1e-3


def _cli(*args):
    return fembeam(*args)


def test_cli_json_keys_and_the_thrust_figure_and_vtk(tmp_path):
    p = _cli("analyze", "--embrace", "180", "--t-over-r", "0.15", "--radius", "5", "--density", "2000",
             "--fill-density", "1800", "--fill-depth", "0.5", "--load", "2.5,100", "--mass", "7,500",
             "--voussoirs", "12", "--json", "--thrust-figure", str(tmp_path / "t.png"), "--vtk",
             str(tmp_path / "a.vtu"))
    assert p.returncode == 0, p.stderr
    d = json.loads(p.stdout)
    assert d["geometry"]["density"] == 2000.0
    assert d["geometry"]["fill"]["density"] == 1800.0 and d["geometry"]["fill"]["depth"] == 0.5
    assert d["loads"] == [{"x": 2.5, "P": 100.0}] and d["masses"] == [{"x": 7.0, "M": 500.0}]
    assert d["load_factor"] > 0 and len(d["load_mechanism"]) == 4
    assert 0 < d["thrust_range"]["H_min"] < d["thrust_range"]["H_max"]
    assert d["collapse_loads_kN_per_m"] == [pytest.approx(100.0 * d["load_factor"])]
    assert (tmp_path / "t.png").read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    fill = meshio.read(tmp_path / "a_fill.vtu")
    assert sorted(fill.cell_data["piece"][0].tolist()) == list(range(12))
    for part in ("thrust_min", "thrust_max"):
        assert len(meshio.read(tmp_path / f"a_{part}.vtu").points) == 13


def test_cli_load_scan(tmp_path):
    p = _cli("load-scan", "--embrace", "180", "--t-over-r", "0.15", "--radius", "5", "--fill-density", "1800",
             "--load", "100", "--voussoirs", "12", "--positions", "11", "--json", "--out-dir", str(tmp_path))
    assert p.returncode == 0, p.stderr
    d = json.loads(p.stdout)
    assert len(d["positions"]) == 11 and d["critical_x"] is not None
    assert d["min_load_factor"] == min(x["load_factor"] for x in d["positions"] if x["load_factor"] is not None)
    assert {f.name for f in tmp_path.iterdir()} == {"load_scan.csv", "load_scan.json", "load_scan.png"}
    q = _cli("analyze", "--embrace", "180", "--t-over-r", "0.15", "--radius", "5", "--fill-density", "1800",
             "--load-scan", "100", "--voussoirs", "12", "--positions", "11", "--json")
    assert q.returncode == 0 and json.loads(q.stdout)["min_load_factor"] == d["min_load_factor"]
    for bad in (["--load", "0"], ["--load", "100", "--positions", "1"], ["--load", "-5"]):
        r = _cli("load-scan", "--voussoirs", "12", *bad)
        assert r.returncode == 2 and r.stdout == "" and len(r.stderr.strip().splitlines()) == 1, bad


def test_block_refuses_fill():
    r = _cli("rock", "--block", "0.3", "1.0", "--fill-density", "1800", "--pulse", "sine", "--amplitude", "1",
             "--period", "1")
    assert r.returncode == 2 and "not to a --block" in r.stderr


def test_point_masses_counted_once_on_elements_across_breaks_and_over_a_crown_wedge():
    """A pointed arch (crown wedges: elements integrated by segment_inertia) with a mass over its
    crown: the mass matrix carries the mass once; the continuous arch meshes around the wedge."""
    c = PointedArch(span=10.0, rise=7.0, thickness=0.6, density=RHO)
    built = build(c, masses=[(5.0, 1000.0), (2.0, 300.0)])
    for nodes in (uniform_nodes(built, 10), uniform_nodes(built, 7)):
        disc = discretize(built, nodes)
        total = built.segment_inertia(0.0, built.length)[0][0]
        assert disc.M.diagonal()[::3].sum() == pytest.approx(total, rel=1e-12)
        assert total == pytest.approx(c.segment_inertia(0.0, c.length)[0][0] + 1300.0, rel=1e-12)
    res = analyze(c, elements=40, loads=[(5.0, 10.0)], masses=[(5.0, 500.0)])
    assert res.load.status == "ok" and res.load.lower == pytest.approx(res.load_factor, rel=1e-9)


def test_the_load_mechanism_is_that_of_the_reported_factor(filled):
    """On the continuous arch the mechanism printed with the load factor has the same factor (its
    hinges polished onto the corner under the load): the limit LP on a mesh through its hinges."""
    res = analyze(filled, elements=40, loads=[(2.0, 50.0)])
    assert res.to_dict()["verification"]["load_factor"]["hinge_refinement_gap"] < 1e-7
    assert res.load.limit.A_L == pytest.approx(res.load_factor, rel=1e-7)
