"""Physical units by default: the density of masonry (2000 kg/m^3 per metre of barrel width);
masses, forces, energies and impulses proportional to it, A_L and r not; every JSON output
states the units of what it reports (forces in kN/m, energies in J/m, impulses in N s/m)."""
import json

import matplotlib

matplotlib.use("Agg")

import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
import pytest  # noqa: E402

from fembeam import (CatenaryArch, CircularArch, EllipticalArch, ParabolicArch, PointedArch,  # noqa: E402
                     StraightMember, SurveyedArch, analyze)
from fembeam.cli.main import build_parser, main  # noqa: E402
from fembeam.dynamics.ground import GroundMotion  # noqa: E402
from fembeam.dynamics.rocking import rock  # noqa: E402
from fembeam.geometry.base import DEFAULT_DENSITY, DENSITY_RANGE  # noqa: E402
from fembeam.mechanisms.four_hinge_analysis import four_hinge_impact  # noqa: E402
from fembeam.output.motion import history_figure  # noqa: E402
from fembeam.units import GRAVITY, kN  # noqa: E402


def test_the_default_density_is_that_of_masonry(tmp_path):
    assert DEFAULT_DENSITY == 2000.0 and DENSITY_RANGE[0] < 1800 < 2400 < DENSITY_RANGE[1]
    csv = tmp_path / "m.csv"
    csv.write_text("x,y\n" + "\n".join(f"{x},{1 - x * x}" for x in np.linspace(-1, 1, 9)) + "\n")
    members = [CircularArch(), CircularArch.from_ratio(157.5, 0.15), StraightMember(),
               PointedArch(span=2.0, rise=1.5, thickness=0.15), EllipticalArch(span=2.0, rise=0.8, thickness=0.1),
               ParabolicArch(span=2.0, rise=0.8, thickness=0.1), CatenaryArch(span=2.0, rise=0.8, thickness=0.1),
               SurveyedArch.from_csv(csv, thickness=0.1)]
    assert all(m.density == DEFAULT_DENSITY for m in members)
    assert all(m.describe()["density"] == DEFAULT_DENSITY for m in members)


def test_density_option_default_and_help():
    p = build_parser(only="analyze", full=False)
    sub = p._subparsers._group_actions[0].choices["analyze"]
    assert sub.parse_args([]).density == DEFAULT_DENSITY
    text = " ".join(sub.format_help().split())
    assert "kg/m^3 per metre of barrel width (default 2000; typical 1800-2400)" in text
    assert "A_L, r and the thresholds in g of a bare arch do not depend on it" in text


def test_forces_and_impulses_scale_with_the_density_A_L_and_r_do_not():
    """The same arch at density 1 and at the default: A_L and r to 1e-9, the joint forces (kN/m)
    and the impulses (N s/m) 2000 times larger, the masses too."""
    one = analyze(CircularArch.from_ratio(157.5, 0.15, density=1.0), elements=60)
    mas = analyze(CircularArch.from_ratio(157.5, 0.15), elements=60)
    assert mas.A_L == pytest.approx(one.A_L, rel=1e-9) and mas.r == pytest.approx(one.r, rel=1e-9)
    d1, d2 = one.to_dict(fields=True), mas.to_dict(fields=True)
    n1, n2 = np.array(d1["thrust_line"]["N"]), np.array(d2["thrust_line"]["N"])
    assert np.allclose(n2, DEFAULT_DENSITY * n1, rtol=1e-8, atol=1e-8 * n2.max())
    lim = mas.limit
    assert np.allclose(n2, (lim.N[0] + lim.N[1]) * GRAVITY / 1000.0, rtol=1e-14)   # per g in kg/m -> kN/m
    i1, i2 = np.array(d1["impulse_line"]["I_t"]), np.array(d2["impulse_line"]["I_t"])
    assert np.allclose(i2, DEFAULT_DENSITY * i1, rtol=1e-8, atol=1e-8 * np.abs(i2).max())
    m1, m2 = (c.segment_inertia(0.0, c.length)[0][0] for c in (one.limit.disc.curve, lim.disc.curve))
    assert m2 == pytest.approx(DEFAULT_DENSITY * m1, rel=1e-12)
    # the weight of the default arch in kN/m: rho g beta R t (beta = 157.5 deg, R = 1 m, t = 0.15 m)
    assert kN(m2) == pytest.approx(2000 * 9.81 / 1000 * np.radians(157.5) * 1.0 * 0.15, rel=1e-12)


def test_analyze_json_states_its_units(capsys):
    assert main(["analyze", "--voussoirs", "7", "--json", "--fields"]) == 0
    d = json.loads(capsys.readouterr().out)
    u = d["units"]
    assert u["A_L"] == "g" and u["density"] == "kg/m^3" and u["thrust_line.N"] == "kN/m"
    assert u["impulse_line.I_t"].startswith("N s/m") and u["impulse_line.moment"].startswith("N m s/m")
    assert d["geometry"]["density"] == DEFAULT_DENSITY
    assert all(k.split(".")[0] in d or k in ("radius", "thickness", "density", "angle_deg") for k in u)


def test_impact_json_states_its_units_and_scales():
    one = four_hinge_impact(CircularArch.from_ratio(157.5, 0.15, density=1.0), voussoirs=9)
    mas = four_hinge_impact(CircularArch.from_ratio(157.5, 0.15), voussoirs=9)
    d1, d2 = one.to_dict(fields=True), mas.to_dict(fields=True)
    assert d2["r"] == pytest.approx(d1["r"], rel=1e-9)
    for k in ("Gamma", "Lambda", "Lambda_after"):
        assert d2[k] == pytest.approx(DEFAULT_DENSITY * d1[k], rel=1e-9)
        assert d2["units"][k].startswith("kg m^2/m")
    assert d2["units"]["impulse_line.I_n"].startswith("N s/m")
    json.dumps(d2, allow_nan=False)


def test_rock_energies_in_J_per_metre():
    """A block under a sine pulse at density 1 and at the default: the same motion, energies
    2000 times larger (J/m), the JSON and the figure say so."""
    ground = GroundMotion.sine(0.5, 0.5)
    one = rock(StraightMember(height=2.0, width=0.5, density=1.0), ground, voussoirs=1, t_end=3.0,
               thrust_check=False)
    mas = rock(StraightMember(height=2.0, width=0.5), ground, voussoirs=1, t_end=3.0, thrust_check=False)
    assert mas.outcome == one.outcome and mas.peak_rotation == pytest.approx(one.peak_rotation, rel=1e-9)
    e1, e2 = one.to_dict()["energy"], mas.to_dict()["energy"]
    for k in ("K_end", "ground_work", "dissipated"):
        assert e2[k] == pytest.approx(DEFAULT_DENSITY * e1[k], rel=1e-8)
    u = mas.to_dict(history=True)["units"]
    assert u["energy"] == u["history.K"] == u["history.V"] == "J/m" and u["A_L"] == "g"
    fig = history_figure(mas)
    try:
        assert "energy (J/m)" in [ax.get_ylabel() for ax in fig.axes]
    finally:
        plt.close(fig)


def test_rock_text_and_json_say_their_units(capsys):
    argv = ["rock", "--block", "0.5", "2.0", "--pulse", "sine", "--amplitude", "0.5", "--period", "0.5",
            "--t-end", "3"]
    assert main(argv) == 0
    out = capsys.readouterr().out
    assert " J/m, dissipated by the impacts " in out and "J per" not in out
    assert main(argv + ["--json"]) == 0
    d = json.loads(capsys.readouterr().out)
    assert d["units"]["energy"] == "J/m" and d["geometry"]["density"] == DEFAULT_DENSITY


def test_simulate_and_auto_json_state_their_units(capsys):
    from fembeam.simulation import Simulator

    res = Simulator(StraightMember(height=2.0, width=0.5), voussoirs=1).run(GroundMotion.sine(0.5, 0.5), t_end=1.0)
    u = res.to_dict()["units"]
    assert u["energy"] == u["history.K"] == u["history.W_ground"] == u["history.dissipated"] == "J/m"
    assert main(["rock", "--block", "0.5", "2.0", "--pulse", "sine", "--amplitude", "0.5", "--period", "0.5",
                 "--t-end", "1", "--model", "auto", "--json"]) == 0
    d = json.loads(capsys.readouterr().out)
    assert d["units"]["segments.handback_energy_dropped"] == d["units"]["history.K"] == "J/m"
