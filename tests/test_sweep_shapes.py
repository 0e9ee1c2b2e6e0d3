"""``fembeam sweep --shape``: sweeps over pointed, elliptical, parabolic and catenary arches
(span 1, rise/span x t/span), checked against the circular sweep and direct analyses."""
from __future__ import annotations

import csv
import importlib
import json
import math

import pytest

from fembeam import analyze, minimum_thickness
from fembeam.analysis.thickness import MinimumThickness
from fembeam.cli.main import main
from fembeam.geometry import ParabolicArch
from fembeam.studies.sweep import envelope_case, sweep, sweep_shape

sweep_module = importlib.import_module("fembeam.studies.sweep")

FAST = {"elements": 40, "tmin_elements": 40, "tmin_tol": 1e-4, "workers": 2, "progress": False}
CLI_FAST = ["--elements", "40", "--tmin-elements", "40", "--tmin-tol", "1e-3", "--workers", "1", "--quiet"]


def strict_json(text: str):
    """``json.loads`` that fails on NaN and Infinity."""
    def bad(name):
        raise ValueError(f"non-finite number {name} in the JSON")
    return json.loads(text, parse_constant=bad)


@pytest.fixture(scope="module")
def semicircle():
    # t/R = 0.10 cannot stand (t_min/R = 0.1075), 0.20 rocks
    return sweep([180.0], [0.10, 0.20], **FAST)


@pytest.mark.parametrize("shape", ["pointed", "elliptical"])
def test_rise_over_span_one_half_is_the_semicircle(semicircle, shape):
    """span = 2R: t/span = (t/R) / 2; r, A_L, hinges and t_min as the circular sweep."""
    res = sweep_shape(shape, [0.5], [0.05, 0.10], **FAST)
    assert res.to_dict()["shape"] == res.settings["shape"] == shape
    for tr in (0.10, 0.20):
        c, s = semicircle.case(180.0, tr), res.case(0.5, tr / 2)
        assert s["outcome"] == c["outcome"]
        for key in ("r", "A_L"):
            assert (s[key] is None) == (c[key] is None)
            if c[key] is not None:
                assert s[key] == pytest.approx(c[key], rel=1e-9, abs=1e-12)
        assert [h["angle_deg"] for h in s["hinges_before"]] == pytest.approx(
            [h["angle_deg"] for h in c["hinges_before"]], abs=1e-6)
    assert res.case(0.5, 0.05)["t_min_over_span"] == pytest.approx(
        semicircle.case(180.0, 0.10)["t_min_over_R"] / 2, rel=1e-9)
    (ec,), (es,) = semicircle.envelope, res.envelope
    assert es["t_min_over_span"] == pytest.approx(ec["t_min_over_R"] / 2, rel=1e-9)
    assert es["t_over_span"] == pytest.approx(ec["t_over_R"] / 2, rel=1e-9)
    assert (es["outcome"], es["r"], es["A_L"]) == ("rocking", pytest.approx(ec["r"], rel=1e-9),
                                                    pytest.approx(ec["A_L"], rel=1e-9))


def test_circular_sweep_keeps_its_keys(semicircle):
    data = semicircle.to_dict()
    assert "shape" not in data and "shape" not in data["settings"] and "embrace_deg" in data
    assert list(semicircle.csv_rows()[0])[:8] == ["kind", "embrace_deg", "t_over_R", "outcome", "r", "A_L",
                                                  "A_L_mesh", "t_min_over_R"]


def test_command_files_and_a_case_equal_to_analyze(tmp_path, capsys):
    out = tmp_path / "par"
    assert main(["sweep", "--shape", "parabolic", "--rise-over-span", "0.3", "--t-over-span", "0.05", *CLI_FAST,
                 "--csv", str(tmp_path / "p.csv"), "--plot", str(tmp_path / "p.png"), "--out-dir", str(out),
                 "--json"]) == 0
    data = strict_json(capsys.readouterr().out)
    assert (data["study"], data["shape"], data["rise_over_span"], data["t_over_span"]) == (
        "sweep", "parabolic", [0.3], [0.05])
    (case,), (env,) = data["cases"], data["envelope"]
    res = analyze(ParabolicArch(span=1.0, rise=0.3, thickness=0.05), elements=40)
    assert (case["outcome"], case["A_L"], case["A_L_mesh"], case["r"]) == (res.outcome, res.A_L, res.A_L_mesh, res.r)
    assert [h["angle_deg"] for h in case["hinges_before"]] == [h["angle_deg"] for h in res.to_dict()["hinges_before"]]
    th = minimum_thickness(ParabolicArch(span=1.0, rise=0.3, thickness=0.05), elements=40, tol=1e-3)
    assert env["outcome"] == "rocking" and env["t_min_over_span"] == pytest.approx(th.scale * 0.05, rel=2e-3)
    assert env["t_over_span"] == pytest.approx(env["t_min_over_span"] * 1.001, rel=1e-12)
    with open(tmp_path / "p.csv") as f:
        rows = list(csv.DictReader(f))
    assert list(rows[0])[:5] == ["kind", "shape", "rise_over_span", "t_over_span", "outcome"]
    assert "t_min_over_span" in rows[0] and [r["kind"] for r in rows] == ["envelope", "case"]
    assert (tmp_path / "p.png").stat().st_size > 10_000
    assert strict_json((out / "sweep.json").read_text())["cases"] == data["cases"]
    assert main(["sweep", "--shape", "parabolic", "--rise-over-span", "0.3", "--t-over-span", "0.05",
                 *CLI_FAST]) == 0
    text = capsys.readouterr().out
    assert "parabolic arches" in text and "t/span" in text and "rise/span t_min/span" in text


def test_uniform_catenary_stands_at_any_thickness():
    res = sweep_shape("catenary", [0.3], [0.05], **{**FAST, "workers": 1})
    (env,) = res.envelope
    assert env["outcome"] == "stands_at_any_thickness" and env["t_min_over_span"] == 0.0
    assert env["r"] is None and env["t_over_span"] is None
    assert res.case(0.3, 0.05)["outcome"] == "rocking"
    assert strict_json(json.dumps(res.to_dict()))["envelope"][0]["t_min_over_span"] == 0.0


def test_never_stands_is_reported(monkeypatch):
    """No thickness stands: outcome never_stands, t_min null, no case at t_min."""
    monkeypatch.setattr(sweep_module, "minimum_thickness",
                        lambda curve, **kw: MinimumThickness(curve, math.inf, 8.0, 3, True))
    env = envelope_case(0.3, elements=40, tmin_elements=40, shape="parabolic")
    assert (env["outcome"], env["t_min_over_span"], env["r"]) == ("never_stands", None, None)
    strict_json(json.dumps(env))


@pytest.mark.parametrize("argv, words", [
    (["--shape", "pointed", "--rise-over-span", "0.4", "--t-over-span", "0.1"], "rise >= span/2"),
    (["--shape", "pointed", "--embrace", "180", "--rise-over-span", "0.5", "--t-over-span", "0.1"], "--embrace"),
    (["--shape", "elliptical", "--t-over-r", "0.1", "--rise-over-span", "0.5", "--t-over-span", "0.1"],
     "--t-over-r"),
    (["--rise-over-span", "0.5", "--t-over-span", "0.1"], "--rise-over-span"),
    (["--shape", "circular", "--t-over-span", "0.1"], "--t-over-span"),
    (["--shape", "catenary", "--rise-over-span", "0.3"], "needs --rise-over-span and --t-over-span"),
    (["--shape", "parabolic", "--rise-over-span", "0,0.3", "--t-over-span", "0.1"], "must be positive"),
    (["--shape", "parabolic", "--rise-over-span", "0.3", "--t-over-span", "-0.1"], "must be positive"),
    (["--shape", "elliptical", "--rise-over-span", "0.1", "--t-over-span", "0.1"], "radius of curvature"),
])
def test_bad_input_is_one_line(capsys, argv, words):
    assert main(["sweep", *argv, "--quiet"]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and words in err
