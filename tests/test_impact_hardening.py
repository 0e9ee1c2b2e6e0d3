"""``fembeam impact`` and the four-hinge API: bad input is exit 2 with one line saying
what is allowed, sizes are bounded before any computation, the JSON is strict, physical
outcomes are answers, and ``r`` stays in [0, 1]."""
from __future__ import annotations

import json

import numpy as np
import pytest

import fembeam as fb
from fembeam import CircularArch, discretize, uniform_nodes
from fembeam.cli.main import main
from fembeam.errors import InputError
from fembeam.mechanisms.discrete_series import discrete_series
from fembeam.mechanisms.four_hinge_analysis import SIZE_LIMITS, four_hinge_impact
from fembeam.mechanisms.mechanism import Mechanism

SIDES = ["extrados", "intrados", "extrados", "intrados"]
SEPARATED = ["--embrace", "95.54", "--t-over-r", "0.34184", "--direction", "-1"]   # 3 incipient hinges
FAST = ["--elements", "40", "--grid", "7", "--sections", "60"]                      # small continuous runs


def run(capsys, *argv) -> tuple[int, str, list[str]]:
    try:
        rc = main(["impact", *argv])
    except SystemExit as e:   # argparse errors
        rc = e.code
    out, err = capsys.readouterr()
    return rc, out, err.splitlines()


def strict_json(text: str) -> dict:
    def bad(c):
        raise ValueError(f"non-finite number {c} in JSON")
    return json.loads(text, parse_constant=bad)


@pytest.fixture
def no_analysis(monkeypatch):
    """The analysis (limit LP, impact QP) fails the test if it runs: bad input is rejected
    before any heavy computation, however fast the machine."""
    from fembeam.mechanisms import discrete_series as series, four_hinge_analysis as four_hinge

    def refuse(*args, **kw):
        raise AssertionError("the analysis ran: the input was not rejected before the computation")

    for module in (four_hinge, series):
        monkeypatch.setattr(module, "analyze", refuse)


def assert_error(capsys, argv, *words):
    rc, out, err = run(capsys, *argv)
    assert rc == 2 and out == ""
    assert len(err) == 1, err
    assert all(w in err[0] for w in words), err[0]


# ---------------------------------------------------------------------------- hinge lists
@pytest.mark.parametrize("argv, words", [
    (["--after", "0:e,45:i,45:i,157.5:i"], ["after", "strictly increasing"]),
    (["--after", "112.5:e,45:i,0:e,157.5:i"], ["strictly increasing"]),
    (["--after", "nan:e,45:i,112.5:e,157.5:i"], ["finite", "[0, 157.5]"]),
    (["--voussoirs", "7", "--after", "nan:e,45:i,112.5:e,157.5:i"], ["finite"]),
    (["--after", "0:e,45:i,112.5:e,inf:i"], ["finite"]),
    (["--after", "0:e,0:e,0:e,0:e"], ["distinct"]),
    (["--after", "0:e,45:i,112.5:e,160:i"], ["[0, 157.5]"]),
    (["--after", "0:e,45:i,157.5:i"], ["exactly 4"]),
    (["--after", "0:e,45:i,90:e,112.5:i,157.5:e"], ["exactly 4"]),
    (["--after", "0:x,45:i,112.5:e,157.5:i"], ["side must be i", "or e"]),
    (["--voussoirs", "7", "--after", "0:e,45:i,113:e,157.5:i"], ["113", "not at a voussoir joint", "22.5"]),
    (["--voussoirs", "7", "--before", "0:e,45:i,113:e,157.5:i"], ["before", "not at a voussoir joint"]),
    (["--before", "0:e,45:i,45:i,157.5:i"], ["before", "strictly increasing"]),
    (["--after", "0:e,40:i,152.28840633067898:i,157.5:e"], ["degenerate", "aligned"]),
    (["--after", "0:e,60:i,152.96511631919105:e,157.5:i"], ["degenerate", "parallel"]),
])
def test_bad_hinge_lists(capsys, no_analysis, argv, words):
    assert_error(capsys, argv, *words)


def test_hinge_list_api():
    c = CircularArch.from_ratio(157.5, 0.15)
    for angles in ([np.nan, 45, 112.5, 157.5], [0, 45, 45, 157.5], [0, 45, 112.5, 170]):
        with pytest.raises(InputError, match="hinges"):
            Mechanism.from_angles(c, angles, SIDES)
    js = uniform_nodes(c, 7)
    m = Mechanism.from_angles(c, [0, 45.00001, 112.5, 157.5], SIDES, joints=js)   # snapped onto the joint
    assert m.s[1] == js[2]
    with pytest.raises(InputError, match="not at a voussoir joint"):
        four_hinge_impact(c, voussoirs=7, after=([0, 50, 112.5, 157.5], SIDES))


# ---------------------------------------------------------------------------- sizes
@pytest.mark.parametrize("argv, words", [
    (["--sections", "20000000"], ["sections", "[4, 1000000]"]),
    (["--sections", "3"], ["sections", "[4, 1000000]"]),
    (["--voussoirs", "300"], ["exhaustive", "[1, 80]", "100,000"]),
    (["--voussoirs", "200000", "--classical"], ["voussoirs", "[1, 100000]"]),
    (["--elements", "200000"], ["elements", "[4, 100000]"]),
    (["--grid", "200"], ["grid", "[3, 80]"]),
    (["--series", "100001"], ["voussoirs", "[1, 100000]"]),
    (["--series", "90000,20000"], ["adding up to at most 100,000"]),
    (["--series", "7", "--exhaustive-max", "81"], ["exhaustive_max", "[0, 80]"]),
    (["--series", "80,79,78", "--exhaustive-max", "80"], ["candidates"]),
])
def test_size_limits(capsys, no_analysis, argv, words):
    assert_error(capsys, argv, *words)


def test_size_limits_documented(capsys):
    with pytest.raises(SystemExit):
        main(["impact", "--help"])
    text = " ".join(capsys.readouterr().out.split())
    for lim in SIZE_LIMITS.values():
        assert f"{lim.highest:,}" in text or f"{lim.highest}" in text


def test_series_api_limits():
    c = CircularArch.from_ratio(157.5, 0.15)
    with pytest.raises(InputError, match="voussoirs"):
        discrete_series(c, [0])
    with pytest.raises(InputError, match="exhaustive_max"):
        discrete_series(c, [7], exhaustive_max=1000)


# ---------------------------------------------------------------------------- JSON
@pytest.mark.parametrize("argv", [
    ["--voussoirs", "7"],
    ["--voussoirs", "7", "--classical", "--fields"],
    ["--voussoirs", "7", "--after", "0:e,45:i,112.5:e,157.5:i", "--fields", "--friction", "0.3"],
    ["--voussoirs", "1"],
    [*FAST],
    [*FAST, "--classical"],
    [*FAST, "--after", "0:e,45:i,112.5:e,157.5:i", "--fields"],
    ["--voussoirs", "7", *SEPARATED],
    ["--series", "1,2,7"],
])
def test_json_is_strict(capsys, argv):
    rc, out, err = run(capsys, *argv, "--json")
    assert rc == 0 and err == []
    o = strict_json(out)
    if "rows" in o:   # --series: a null number comes with the reason
        assert all("reason" in r for r in o["rows"] if None in (r["A_L"], r["r_max"], r["r_4hinge"]))
    elif o["r"] is None:
        assert o["explanation"]


# ---------------------------------------------------------------------------- physical outcome
def test_not_four_hinge_is_an_answer(capsys):
    rc, out, err = run(capsys, *SEPARATED, "--elements", "60")
    assert rc == 0 and err == []
    assert "not_four_hinge" in out and "separated" in out and "r_max" in out
    rc, out, err = run(capsys, *SEPARATED, "--elements", "60", "--json")
    o = strict_json(out)
    assert rc == 0 and o["outcome"] == "not_four_hinge" and o["r"] is None
    assert [h["side"] for h in o["hinges_before"]].count("separated") == 1 and len(o["hinges_before"]) == 3
    assert "does not apply" in o["explanation"] and isinstance(o["r_max"], float)
    # a prescribed four-hinge mechanism before the impact still gives the four-hinge analysis
    rc, out, err = run(capsys, *SEPARATED, "--elements", "60", "--before", "0:e,30:i,65:e,95.54:e", "--classical",
                       "--json")
    assert rc == 0 and err == []
    o = strict_json(out)
    assert o["outcome"] != "not_four_hinge" and 0 <= o["r"]


# ---------------------------------------------------------------------------- r in [0, 1]
def test_compatible_pre_impact_field_keeps_its_energy():
    c = CircularArch.from_ratio(157.5, 0.15)
    disc = discretize(c, uniform_nodes(c, 40))
    u = fb.limit_analysis(disc).u
    opened = fb.impact(disc, u)            # +u opens its hinges: nothing is struck
    assert opened.r == 1.0 and np.array_equal(opened.d, u)
    assert np.all(opened.mu == 0) and len(opened.hinges) == 4
    closed = fb.impact(disc, -u)
    assert 0.0 < closed.r < 1.0
    with pytest.raises(InputError, match="backend"):
        fb.impact(disc, u, backend="nope")
