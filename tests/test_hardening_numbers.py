"""Numbers at the edges: list options, extreme magnitudes, warnings, argument checks of the
public API and an unwritable stdout -- always one line on stderr and the right exit code."""
import importlib
import math
import os
import subprocess
import sys
import warnings

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings, strategies as st

from fembeam import analyze
from fembeam.cli.args import MAX_LIST_VALUES, float_list, int_list
from fembeam.cli.main import main
from fembeam.errors import InputError, SolverError
from fembeam.fem import discretize, discretize_p1, nodes_through, uniform_nodes
from fembeam.geometry import (CatenaryArch, CircularArch, EllipticalArch, ParabolicArch, PointedArch,
                              StraightMember, SurveyedArch)
from fembeam.geometry.base import DENSITY_RANGE, LENGTH_RANGE, THICKNESS_RANGE

cli_main = importlib.import_module("fembeam.cli.main")   # the module (fembeam.cli.main is also the function)
# capsys is read out at every example; no health check measures time (deadline=None everywhere)
FIXTURE_OK = [HealthCheck.function_scoped_fixture, HealthCheck.too_slow]


def one_line_error(capsys, argv, code=2):
    """Run the CLI in-process; argparse errors raise SystemExit(2), the others return."""
    try:
        rc = main(argv)
    except SystemExit as e:
        rc = e.code
    err = capsys.readouterr().err
    assert rc == code, err
    assert len(err.splitlines()) == 1 and err.endswith("\n"), err
    return err


# ---------------------------------------------------------------- 1. list options
@pytest.mark.parametrize("argv, words", [
    (["sweep", "--embrace", "0:1e308:1e-308", "--t-over-r", "0.2"], "step"),
    (["sweep", "--embrace=-1e308:1e308:1e300", "--t-over-r", "0.2"], "at most"),
    (["sweep", "--embrace", "90", "--t-over-r", "0.1:0.3:1e-300"], "step"),
    (["sweep", "--embrace", "90", "--t-over-r", "0.1:0.3:1e-6"], f"at most {MAX_LIST_VALUES}"),
    (["spectrum", "--pulse", "sine", "--periods", "0:1:1e-300"], "step"),
    (["sweep", "--embrace", "90", "--t-over-r", "0.1:0.3:0"], "step > 0"),
    (["sweep", "--embrace", "90", "--t-over-r", "0.1:0.3:-0.1"], "step > 0"),
    (["sweep", "--embrace", "90", "--t-over-r", "0.1:0.3:nan"], "finite"),
    (["sweep", "--embrace", "90", "--t-over-r", "0.1:inf:0.1"], "finite"),
    (["sweep", "--embrace", "90", "--t-over-r", "0.3:0.1:0.1"], "stop >= start"),
    (["sweep", "--embrace", "90", "--t-over-r", "0.1:0.2"], "start:stop:step"),
    (["sweep", "--embrace", "90", "--t-over-r", ","], "numbers"),
    (["sweep", "--embrace", "90", "--t-over-r", ",".join(["0.1"] * (MAX_LIST_VALUES + 1))], "at most"),
    (["convergence", "--elements", ",".join(["10"] * (MAX_LIST_VALUES + 1))], "at most"),
    (["convergence", "--elements", "1e3"], "integers"),
])
def test_list_options_one_line(capsys, argv, words):
    assert words in one_line_error(capsys, argv)


def test_ranges_keep_their_values():
    assert float_list("0:1:0.1") == [round(0.1 * i, 12) for i in range(11)]
    assert float_list("1e-13:5e-13:1e-13") == [1e-13, 2e-13, 3e-13, 4e-13, 5e-13]   # not rounded to 0
    assert float_list("-0.3:0.3:0.1")[3] == 0.0
    assert len(float_list(f"1:{MAX_LIST_VALUES}:1")) == MAX_LIST_VALUES
    assert int_list("10,20") == [10, 20]


def test_help_states_the_list_limit(capsys):
    with pytest.raises(SystemExit):
        main(["sweep", "--help"])
    assert f"at most {MAX_LIST_VALUES} values per list" in capsys.readouterr().out


# ---------------------------------------------------------------- 2. magnitudes
@pytest.mark.parametrize("argv, words", [
    (["--radius", "1e100"], "radius must be from 1e-06 to 1e+06 m"),
    (["--radius", "1e-100"], "radius must be from"),
    (["--density", "1e200"], "density must be from 1e-06 to 1e+09 kg/m^3"),
    (["--density", "1e-200"], "density must be from"),
    (["--shape", "parabolic", "--span", "1e7", "--rise", "1", "--thickness", "0.1"], "span must be from"),
    (["--shape", "parabolic", "--span", "10", "--rise", "4", "--thickness", "1e8"], "thickness must be from"),
])
def test_magnitudes_outside_the_range(capsys, argv, words):
    assert words in one_line_error(capsys, ["analyze", *argv])


def _AL_r(curve):
    res = analyze(curve, elements=20)
    return res.A_L, res.r


_REF = {}


def _reference():
    if not _REF:
        _REF["circle"] = _AL_r(CircularArch.from_ratio(157.5, 0.15))
    return _REF["circle"]


def _log_uniform(lo, hi):
    return st.floats(math.log10(lo), math.log10(hi)).map(lambda e: 10.0 ** e)


@settings(max_examples=12, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(_log_uniform(*LENGTH_RANGE), _log_uniform(*DENSITY_RANGE))
def test_AL_and_r_do_not_depend_on_size_or_density(radius, density):
    a, r = _AL_r(CircularArch.from_ratio(157.5, 0.15, radius=radius, density=density))
    a0, r0 = _reference()
    assert abs(a - a0) < 1e-9 and abs(r - r0) < 1e-9


@pytest.mark.parametrize("radius, density", [(1e-6, 1e-6), (1e-6, 1e9), (1e6, 1e-6), (1e6, 1e9)])
def test_range_corners_via_cli(capsys, radius, density):
    import json
    assert main(["analyze", "--json", "--elements", "20", "--radius", repr(radius), "--density", repr(density)]) == 0
    out = capsys.readouterr()
    assert out.err == ""
    d = json.loads(out.out)
    a0, r0 = _reference()
    assert abs(d["A_L"] - a0) < 1e-9 and abs(d["r"] - r0) < 1e-9


def test_surveyed_arch_far_from_the_origin():
    x = np.linspace(-1.0, 1.0, 30)
    y = 0.8 * (1 - x**2)
    base = _AL_r(SurveyedArch(x, y, thickness=0.15))
    moved = _AL_r(SurveyedArch(x + 1e5, y + 1e5, thickness=0.15))   # e.g. national-grid coordinates
    assert np.allclose(base, moved, rtol=0, atol=1e-9)


# ---------------------------------------------------------------- 3. warnings
def test_warnings_never_leak(capsys, monkeypatch):
    build = cli_main.build_parser

    def noisy(args):
        np.float64(1e308) * 10.0                                  # overflow: RuntimeWarning
        warnings.warn("a library's warning", UserWarning)
        raise SolverError("the solution failed verification")

    def parser(**kw):
        p = build(**kw)
        p.set_defaults(func=noisy)
        for action in p._actions:
            if action.choices and isinstance(action.choices, dict):
                for sub in action.choices.values():
                    sub.set_defaults(func=noisy)
        return p

    monkeypatch.setattr(cli_main, "build_parser", parser)
    before = list(warnings.filters)
    assert "SolverError" in one_line_error(capsys, ["analyze"], code=3)
    assert warnings.filters == before            # the filters are restored after the command


# ---------------------------------------------------------------- 4. API validation
@pytest.mark.parametrize("nodes", [
    [0.0, np.nan, 1.0], [0.0, 0.5, 0.5, 1.0], [0.1, 0.5, 1.0], [0.0, 0.5, 0.9], [0.0, np.inf], [0.0], [[0.0, 1.0]],
    ["a", "b"],
])
def test_discretize_checks_the_nodes(nodes):
    c = StraightMember(height=1.0, width=0.2)
    for f in (discretize, discretize_p1):
        with pytest.raises(InputError, match="strictly increasing|numbers"):
            f(c, nodes)


def test_mesh_functions_check_their_arguments():
    c = CircularArch()
    with pytest.raises(InputError):
        discretize("arch", [0.0, 1.0])
    with pytest.raises(InputError):
        uniform_nodes(c, True)
    with pytest.raises(InputError):
        discretize(c, uniform_nodes(c, 4), intorder=0)
    with pytest.raises(InputError):
        nodes_through(uniform_nodes(c, 4), [np.nan])
    with pytest.raises(InputError):
        nodes_through(uniform_nodes(c, 4), [2 * c.length])


BAD = ["1", True, np.bool_(True), None, float("nan"), float("inf"), -1.0, 0.0, [1.0], 1e300]


@pytest.mark.parametrize("make", [
    lambda v: CircularArch(radius=v), lambda v: CircularArch(thickness=v), lambda v: CircularArch(embrace_deg=v),
    lambda v: CircularArch(density=v), lambda v: CircularArch.from_ratio(157.5, v),
    lambda v: StraightMember(height=v), lambda v: StraightMember(width=v), lambda v: StraightMember(density=v),
    lambda v: PointedArch(span=v, rise=7.0, thickness=0.8), lambda v: EllipticalArch(span=10.0, rise=v, thickness=0.8),
    lambda v: ParabolicArch(span=10.0, rise=4.0, thickness=v),
    lambda v: CatenaryArch(span=10.0, rise=4.0, thickness=0.8, density=v),
    lambda v: ParabolicArch(span=10.0, rise=4.0, thickness_springing=v, thickness_crown=0.8),
    lambda v: SurveyedArch(np.linspace(-1, 1, 8), 1 - np.linspace(-1, 1, 8) ** 2, thickness=0.1, density=v),
    lambda v: SurveyedArch(np.linspace(-1, 1, 8), 1 - np.linspace(-1, 1, 8) ** 2, thickness=v),
    lambda v: SurveyedArch([v] + list(np.linspace(-0.7, 1, 7)), 1 - np.linspace(-1, 1, 8) ** 2, thickness=0.1),
])
@pytest.mark.parametrize("value", BAD, ids=repr)
def test_constructors_check_their_numbers(make, value):
    try:
        make(value)
    except InputError as e:
        assert "\n" not in str(e)
    else:   # a negative coordinate of a surveyed point is a coordinate, not an error
        assert value == -1.0


def test_numbers_are_stored_as_floats():
    c = CircularArch(radius=np.float32(2), thickness=1, embrace_deg=np.int64(180), density=2)
    assert all(type(v) is float for v in (c.radius, c.thickness, c.embrace_deg, c.density))
    assert c == CircularArch(radius=2.0, thickness=1.0, embrace_deg=180.0, density=2.0)


def test_range_ends_are_admitted():
    CircularArch.from_ratio(157.5, 1e-3, radius=LENGTH_RANGE[0], density=DENSITY_RANGE[0])
    CircularArch.from_ratio(157.5, 1.9, radius=LENGTH_RANGE[1], density=DENSITY_RANGE[1])
    StraightMember(height=LENGTH_RANGE[1], width=THICKNESS_RANGE[0])
    with pytest.raises(InputError, match="from 1e-09 to 1e"):
        StraightMember(height=1.0, width=THICKNESS_RANGE[1] * 2)


# ---------------------------------------------------------------- hypothesis: any text, any non-finite
NUMERIC = ["--radius", "--density", "--embrace", "--t-over-r"]


def _not_a_finite_number(text):
    try:
        return not math.isfinite(float(text))
    except ValueError:
        return True


@settings(max_examples=60, deadline=None, suppress_health_check=FIXTURE_OK)
@given(st.sampled_from(NUMERIC), st.text(max_size=40).filter(_not_a_finite_number))
def test_any_text_for_a_number_is_one_line(capsys, option, text):
    capsys.readouterr()
    one_line_error(capsys, ["analyze", f"{option}={text}"])


@settings(max_examples=30, deadline=None, suppress_health_check=FIXTURE_OK)
@given(st.sampled_from(NUMERIC + ["--span", "--rise", "--thickness"]),
       st.sampled_from(["nan", "NaN", "inf", "-inf", "Infinity", "1e400", "-1e400", "1e100", "-1", "0"]))
def test_non_finite_or_out_of_range_is_one_line(capsys, option, text):
    capsys.readouterr()
    shape = ["--shape", "parabolic", "--span", "10", "--rise", "4", "--thickness", "0.8"] \
        if option in ("--span", "--rise", "--thickness") else []
    one_line_error(capsys, ["analyze", *shape, f"{option}={text}"])


# ---------------------------------------------------------------- 5. unwritable stdout
@pytest.mark.skipif(not os.path.exists("/dev/full"), reason="no /dev/full")
@pytest.mark.parametrize("argv", [["analyze", "--elements", "20"], ["analyze", "--help"]])
def test_stdout_on_a_full_device(argv):
    with open("/dev/full", "w") as full:
        try:      # a hang guard: the run takes under 1 s on an idle machine
            p = subprocess.run([sys.executable, "-m", "fembeam.cli", *argv], stdout=full, stderr=subprocess.PIPE,
                               text=True, timeout=600)
        except subprocess.TimeoutExpired:
            pytest.fail(f"fembeam {' '.join(argv)} > /dev/full still running after 600 s: it hangs")
    assert p.returncode == 2, p.stderr
    assert p.stderr == "fembeam: error: cannot write the output: No space left on device\n"
