"""``fembeam assess``: each number against an independent route.

* statics: A_L and hinges equal ``analyze``'s; the friction needed is the coefficient at which the
  associative limit analysis stops sliding and rocks at the frictionless A_L; the minimum thickness
  brackets where ``analyze`` says the arch stands; a block's A_L and friction needed are b/h;
* verdict: equal to :meth:`AutoModel.run`'s, and the configuration drawn is the state at the peak;
* margin: the factor of ``fembeam collapse-scale --model auto`` (and ``rock``) on the same member and
  record, through both command lines; its bracket checked by runs of its own; a block (one
  mechanism: ``auto`` is ``rock``) against Housner's rectangular-pulse threshold, by quadrature of
  the nonlinear equation (finite angle), itself against his closed form (small angle);
* bad input exits 2 with one line, outputs are checked before computing, the report's links resolve.
"""
from __future__ import annotations

import contextlib
import io
import json
import math
import re

import pytest
from scipy.integrate import quad
from scipy.optimize import brentq

from fembeam import CircularArch, analyze
from fembeam.auto import AutoModel
from fembeam.cli.main import main
from fembeam.dynamics.equation import GRAVITY
from fembeam.dynamics.ground import GroundMotion
from fembeam.dynamics.rocking import Rocker

ARCH = ["--voussoirs", "7", "--radius", "5"]            # the paper's arch: embrace 157.5 deg, t/R = 0.15
PAPER = CircularArch.from_ratio(157.5, 0.15, radius=5.0)
SINE = ["--pulse", "sine", "--amplitude", "0.5", "--period", "0.5"]
RESOLUTION = 0.1


def _strict(text: str) -> dict:
    def bad(x):
        raise AssertionError(f"non-finite number {x} in the JSON")
    return json.loads(text, parse_constant=bad)


def _assess(*argv: str) -> tuple[int, str, str]:
    out, err = io.StringIO(), io.StringIO()
    with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
        try:
            code = main(["assess", *argv])
        except SystemExit as e:         # argparse's errors
            code = e.code
    return code, out.getvalue(), err.getvalue()


@pytest.fixture(scope="module")
def paper():
    code, out, err = _assess(*ARCH, *SINE, "--resolution", str(RESOLUTION), "--json")
    assert code == 0, err
    return _strict(out)


# --------------------------------------------------------------------------- statics
def test_statics_are_analyze_s(paper):
    st = paper["static"]
    for d, key in ((1, "+1"), (-1, "-1")):
        res = analyze(PAPER, voussoirs=7, direction=d)
        assert st["A_L"][key] == res.A_L and st["outcome"][key] == "rocking"
        assert st["hinges"][key] == [h.to_dict() for h in res.hinges_before]


def test_friction_needed_is_where_rocking_governs(paper):
    """Just above the friction needed the limit analysis with Coulomb joints rocks at the frictionless
    A_L; just below it slides, at a smaller load factor."""
    fn, A = paper["static"]["friction_needed"], paper["static"]["A_L"]
    assert fn["max"] == max(fn["+1"]["max"], fn["-1"]["max"]) and fn["sliding_risk"] is None
    for d, key in ((1, "+1"), (-1, "-1")):
        mu = fn[key]["max"]
        above = analyze(PAPER, voussoirs=7, direction=d, friction=mu * (1 + 1e-3))
        below = analyze(PAPER, voussoirs=7, direction=d, friction=mu * (1 - 1e-3))
        assert above.outcome == "rocking" and above.A_L == pytest.approx(A[key], rel=1e-9)
        assert below.outcome == "sliding" and below.A_L < A[key] * (1 - 1e-4)


def test_minimum_thickness_brackets_standing(paper):
    mt = paper["static"]["minimum_thickness"]
    k = mt["thickness_scale"]
    assert mt["outcome"] == "ok" and mt["geometric_safety_factor"] == pytest.approx(1 / k, rel=1e-15)
    assert mt["thickness_min"]["thickness"] == pytest.approx(k * 0.75, rel=1e-12)
    assert analyze(PAPER.with_thickness_scaled(k * (1 + 1e-5)), voussoirs=7).outcome == "rocking"
    assert analyze(PAPER.with_thickness_scaled(k * (1 - 1e-5)), voussoirs=7).outcome == "cannot_stand"
    out = io.StringIO()
    with contextlib.redirect_stdout(out):
        assert main(["min-thickness", *ARCH, "--json"]) == 0
    assert _strict(out.getvalue())["geometric_safety_factor"] == pytest.approx(mt["geometric_safety_factor"],
                                                                               rel=1e-12)


# --------------------------------------------------------------------------- verdict
def test_verdict_is_automodel_s(paper):
    m = paper["motions"][0]
    ground = GroundMotion.sine(0.5, 0.5)
    res = AutoModel(PAPER, voussoirs=7).run(ground)
    d = res.to_dict()
    for key in ("outcome", "peak_rotation", "t_peak", "t_overturn", "first_failure", "handovers", "segments",
                "time_in", "n_impacts"):
        assert m[key] == d[key], key
    assert m["verdict"] == "survives" and m["outcome"] in ("rest", "survived")
    assert m["first_failure"]["reason"] == "thrust_line"       # the paper's arch: another hinge opens
    # the configuration drawn: the history row nearest the peak, and its rotation the peak's
    t = res.history["t"]
    step = float(max(t[1:] - t[:-1]))
    cf = m["configuration"]
    assert cf["at"] == "peak rotation" and abs(cf["t"] - m["t_peak"]) <= step
    assert cf["max_rotation"] == pytest.approx(m["peak_rotation"], rel=1e-2)


# --------------------------------------------------------------------------- margin
def test_margin_bracket_by_runs_of_its_own(paper):
    """The margins at the resolution asked, each the smallest there, their brackets checked by
    ``AutoModel`` runs of this test: safe at the lower end, overturns at the upper end."""
    mg = paper["motions"][0]["margin"]
    assert paper["settings"]["resolution"] == RESOLUTION
    ground = GroundMotion.sine(0.5, 0.5)
    for model in ("auto", "rock"):
        e = mg[model]
        assert e["resolution"] == RESOLUTION and e["smallest"] and "converged" not in e and e["collapse"] == "overturned"
        lo, hi = e["bracket"]
        assert hi == e["factor"] and hi / lo <= 1 + RESOLUTION * (1 + 1e-9)
        assert 0 < e["resolution_reached"] <= RESOLUTION * (1 + 1e-9) and e["onset_factor"] < lo
        assert e["pga_g"] == pytest.approx(0.5 * e["factor"], rel=1e-15)
    lo, hi = mg["auto"]["bracket"]
    am = AutoModel(PAPER, voussoirs=7)
    assert am.run(ground.scaled(lo), history=False).outcome in ("rest", "survived")
    assert am.run(ground.scaled(hi), history=False).outcome == "overturned"
    lo_r, hi_r = mg["rock"]["bracket"]
    rocker = Rocker(PAPER, voussoirs=7)
    assert rocker.run(ground.scaled(lo_r)).outcome not in ("overturned", "collapsed_by_sliding")
    assert rocker.run(ground.scaled(hi_r)).outcome == "overturned"
    # the one-mechanism model alone claims more than twice the margin of this arch: the auto
    # model's collapse lies below half the largest factor that rock survives
    assert hi < 0.5 * lo_r


def _command(*argv: str) -> dict:
    out, err = io.StringIO(), io.StringIO()
    with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
        code = main(list(argv))
    assert code == 0, err.getvalue()
    return _strict(out.getvalue())


def test_margin_is_the_factor_of_collapse_scale(tmp_path, resolution=None):
    """``assess --json`` and ``collapse-scale --model auto --json`` (and ``--model rock``) on the same
    member and record give the same factor and the same claims, bit for bit: one search."""
    rec = GroundMotion.record("elcentro")
    keep = rec.t <= 6.0
    path = tmp_path / "elcentro_6s.csv"
    path.write_text("time,acceleration\n" + "".join(f"{float(t)!r},{float(a)!r}\n"
                                                    for t, a in zip(rec.t[keep], rec.a[keep])))
    member = ["--block", "0.3", "1.5", "--record", str(path), "--t-end", "8"]
    search = [] if resolution is None else ["--resolution", resolution]
    d = _command("assess", *member, *search, "--json", "--quiet")
    mg = d["motions"][0]["margin"]
    assert d["settings"]["resolution"] == (0.05 if resolution is None else float(resolution))
    for model in ("auto", "rock"):
        cs = _command("collapse-scale", *member, "--model", model, *search, "--json", "--quiet")
        e = mg[model]
        assert e["factor"] == cs["first_collapse"] and e["factor"] is not None
        assert e["pga_g"] == cs["pga_at_first_collapse"]
        for key in ("bracket", "smallest", "resolution", "resolution_reached", "safe_factors_above", "runs",
                    "onset_factor", "max_factor", "none_up_to_max", "budget_exhausted"):
            assert e[key] == cs[key], key
        assert e["smallest"]


def _housner_exact(b: float, h: float, t1: float) -> float:
    """Smallest amplitude (g) of a rectangular pulse of duration ``t1`` that overturns a block
    ``b`` x ``h`` (Housner's equation, not linearised): during the pulse the block turns by
    ``theta(t1)`` found from the energy integral ``theta'^2 = 4 p^2 sin(theta/2) (A cos(alpha -
    theta/2) - sin(alpha - theta/2))`` and the quadrature of ``dt = d theta / theta'``; after it, it
    overturns when its kinetic energy reaches the barrier ``p^2 (1 - cos(alpha - theta))``."""
    alpha, R = math.atan(b / h), 0.5 * math.hypot(b, h)
    p = math.sqrt(3 * GRAVITY / (4 * R))

    def w2(th, A):
        return 4 * p * p * math.sin(th / 2) * (A * math.cos(alpha - th / 2) - math.sin(alpha - th / 2))

    def time_to(th, A):       # theta = u^2 removes the 1/sqrt singularity at rest
        lim0 = 2 / math.sqrt(2 * p * p * (A * math.cos(alpha) - math.sin(alpha)))
        return quad(lambda u: 2 * u / math.sqrt(w2(u * u, A)) if u > 0 else lim0, 0, math.sqrt(th),
                    epsabs=1e-14, epsrel=1e-12, limit=200)[0]

    def excess(A):
        if time_to(alpha, A) <= t1:
            return 1.0
        th = brentq(lambda x: time_to(x, A) - t1, 0.0, alpha, xtol=1e-15)
        return 0.5 * w2(th, A) - p * p * (1 - math.cos(alpha - th))

    return brentq(excess, math.tan(alpha) * (1 + 1e-6), 20.0, xtol=1e-13)


@pytest.mark.parametrize("b, amplitude", [(0.4, 0.3), (0.04, 0.03)])
def test_block_against_housner(b, amplitude):
    """A block has one mechanism: auto is rock, A_L = b/h, the friction needed b/h, and the margin
    times the amplitude is Housner's overturning threshold, within the resolution asked."""
    h, t1, resolution = 1.6, 0.5, 0.01
    code, out, err = _assess("--block", str(b), str(h), "--pulse", "rect", "--amplitude", str(amplitude),
                             "--duration", str(t1), "--resolution", str(resolution), "--json")
    assert code == 0, err
    d = _strict(out)
    st, m = d["static"], d["motions"][0]
    for key in ("+1", "-1"):
        assert st["A_L"][key] == pytest.approx(b / h, rel=1e-14)
        assert st["friction_needed"][key]["max"] == pytest.approx(b / h, rel=1e-14)
    assert st["minimum_thickness"]["outcome"] == "stands_at_any_thickness"
    assert st["minimum_thickness"]["thickness_min"] == {"width": 0.0}
    assert m["first_failure"] is None and m["handovers"] == 0
    mg = m["margin"]
    assert mg["auto"]["factor"] == pytest.approx(mg["rock"]["factor"], rel=1e-12) and mg["ratio"] == pytest.approx(1)
    exact = _housner_exact(b, h, t1)
    for model in ("auto", "rock"):
        assert mg[model]["smallest"] and mg[model]["resolution"] == resolution
        lo, hi = (amplitude * f for f in mg[model]["bracket"])
        assert lo <= exact * (1 + 1e-9) and exact <= hi * (1 + 1e-9) and hi / lo <= 1 + resolution * (1 + 1e-9)
    # Housner's closed form (small angle): within 0.1 % of the exact threshold for the slender
    # block; O(alpha^2) off the stocky one
    alpha, R = math.atan(b / h), 0.5 * math.hypot(b, h)
    closed = alpha / (1 - math.exp(-math.sqrt(3 * GRAVITY / (4 * R)) * t1))
    if b / h < 0.05:
        assert exact == pytest.approx(closed, rel=1e-3)
    else:
        assert 0.01 < exact / closed - 1 < 0.03


# --------------------------------------------------------------------------- outputs
def _record(path, amplitude: float, period: float) -> None:
    t = [i * 0.01 for i in range(int(period / 0.01) + 1)]
    path.write_text("time,acceleration\n" + "".join(f"{x:.4f},{amplitude * math.sin(2 * math.pi * x / period):.6f}\n"
                                                    for x in t))


def test_records_folder_and_report(tmp_path):
    recs = tmp_path / "records"
    recs.mkdir()
    _record(recs / "b_strong.csv", 1.2, 0.5)
    _record(recs / "a_weak.CSV", 0.5, 0.5)
    (recs / "notes.txt").write_text("not a record")
    rep = tmp_path / "out" / "rep"
    code, out, err = _assess(*ARCH, "--records", str(recs), "--no-margin", "--report", str(rep))
    assert code == 0, err
    assert "ground motion 1: a_weak.CSV" in out and "ground motion 2: b_strong.csv" in out
    assert "verdict (auto): SURVIVES" in out and "verdict (auto): OVERTURNS at t = " in out
    names = sorted(p.name for p in rep.iterdir())
    assert names == sorted(["report.md", "assess.json", "statics.png", "motion_01_history.png",
                            "motion_01_configuration.png", "motion_02_history.png", "motion_02_configuration.png"])
    md = (rep / "report.md").read_text()
    links = re.findall(r"\]\(([^)]+)\)", md)
    assert len(links) == 6 and all((rep / link).is_file() for link in links)
    for link in links:
        if link.endswith(".png"):
            assert (rep / link).read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    d = _strict((rep / "assess.json").read_text())
    assert [m["verdict"] for m in d["motions"]] == ["survives", "overturns"]
    assert d["motions"][1]["configuration"]["at"] == "overturning"
    assert d["motions"][1]["configuration"]["t"] == pytest.approx(d["motions"][1]["t_overturn"], abs=0.01)
    assert all(m["margin"]["skipped"] == "not searched" for m in d["motions"])


def test_cannot_stand_is_an_answer():
    code, out, err = _assess("--voussoirs", "7", "--t-over-r", "0.05", *SINE, "--json")
    assert code == 0, err
    d = _strict(out)
    assert d["static"]["outcome"] == {"+1": "cannot_stand", "-1": "cannot_stand"}
    assert d["static"]["A_L"] == {"+1": None, "-1": None}
    assert d["static"]["minimum_thickness"]["geometric_safety_factor"] < 1
    assert d["motions"][0]["verdict"] == "cannot_stand"
    assert d["motions"][0]["margin"]["skipped"] == "the member cannot stand"


@pytest.mark.parametrize("argv, words", [
    (ARCH, "required"),
    ([*ARCH, "--records", "/nonexistent/dir"], "not a directory"),
    ([*ARCH, "--records", "EMPTY"], "no .AT2 or .csv"),
    ([*ARCH, "--records", "BAD"], "bad.csv"),
    ([*ARCH, *SINE, "--dt", "0"], "dt must be in"),
    ([*ARCH, *SINE, "--friction", "-1"], "friction coefficient"),
    ([*ARCH, *SINE, "--factors", "1,2"], "--factors was replaced by --resolution"),
    ([*ARCH, *SINE, "--factors"], "--factors was replaced by --resolution"),
    ([*ARCH, *SINE, "--bisect-tol", "1e-3"], "--bisect-tol was replaced by --resolution"),
    ([*ARCH, *SINE, "--resolution", "2"], "--resolution must be in [1e-4, 1]"),
    ([*ARCH, *SINE, "--resolution", "1e-5"], "--resolution must be in [1e-4, 1]"),
    ([*ARCH, *SINE, "--resolution", "nan"], "--resolution"),
    ([*ARCH, *SINE, "--max-runs", "0"], "--max-runs"),
    ([*ARCH, *SINE, "--no-margin", "--resolution", "0.1"], "--no-margin"),
    ([*ARCH, *SINE, "--report", "FILE"], "not a directory"),
    ([*ARCH, "--pulse", "rect", "--amplitude", "0.3"], "--duration"),
    ([*ARCH, "--records", "EMPTY", "--amplitude", "0.3"], "--pulse"),
    (["--voussoirs", "0", *SINE], "--voussoirs"),
    ([*ARCH, *SINE, "--t-end", "-1"], "--t-end"),
])
def test_bad_input_exit_2_one_line(tmp_path, argv, words):
    (tmp_path / "EMPTY").mkdir()
    (tmp_path / "BAD").mkdir()
    (tmp_path / "BAD" / "bad.csv").write_text("0,0.1\n0.01,abc\n")
    (tmp_path / "FILE").write_text("keep me")
    argv = [str(tmp_path / a) if a in ("EMPTY", "BAD", "FILE") else a for a in argv]
    code, out, err = _assess(*argv)
    assert code == 2 and out == ""
    assert len(err.strip().splitlines()) == 1 and words in err, err
    assert (tmp_path / "FILE").read_text() == "keep me"
