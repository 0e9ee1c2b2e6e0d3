"""The bounds of the motion commands (fembeam.limits): every accepted input has a bounded
number of steps, rows and processes; an input beyond a bound is refused before anything is
computed, with exit 2 and one line naming the bound; a member that cannot stand is an answer
in every command."""
from __future__ import annotations

import json
import math

import pytest

from fembeam import limits
from fembeam.cli.main import main

SINE = ["--pulse", "sine", "--amplitude", "0.5", "--period", "1"]


def _refused(capsys, monkeypatch, argv, words):
    """Exit 2 with one line holding ``words``, and no limit analysis run (it would fail)."""
    import fembeam.analysis.pipeline as pipeline

    def no_analysis(*a, **k):
        raise AssertionError("computed before refusing")

    monkeypatch.setattr(pipeline, "analyze", no_analysis)
    code = main(argv)
    err = capsys.readouterr().err
    assert code == 2 and words in err and len(err.strip().splitlines()) == 1, err


@pytest.mark.parametrize("argv, words", [
    (["rock", "--block", "1e-9", "1e6", *SINE], "width / height must be in [0.001, 1000]"),
    (["rock", "--block", "1", "1e-6", *SINE], "width / height must be in [0.001, 1000]"),
    (["simulate", "--block", "1e-8", "1", *SINE], "width / height must be in [0.001, 1000]"),
    (["simulate", "--t-end", "1e4", "--dt", "0.05", *SINE], "x 200 bodies = 4e+07; at most 2e+07"),
    (["simulate", "--voussoirs", "7", "--t-end", "2e4", "--dt", "1e-3", *SINE], "at most 1e+07"),
    (["simulate", "--elements", "1000000", *SINE], "--elements must be in [4, 1000]"),
    (["rock", "--t-end", "1e4", "--dt-out", "1e-3", "--json", "--history", *SINE], "at most 1e+06"),
    (["simulate", "--voussoirs", "7", "--dt-out", "1e-6", *SINE], "history rows"),
    (["rock", "--t-end", "1e300", *SINE], "at most 100000 s"),
    (["rock", "--voussoirs", "2", *SINE], "--voussoirs must be in [3, 80]"),
    (["rock", "--voussoirs", "200000", *SINE], "--voussoirs must be in [3, 80]"),
    (["rock", "--elements", "30000", *SINE], "--elements must be in [4, 20000]"),
    (["spectrum", "--voussoirs", "7", "--pulse", "sine", "--periods", "0.3", "--workers", "300"],
     "--workers must be in [1, 256]"),
    (["sweep", "--embrace", "90", "--t-over-r", "0.2", "--workers", "0"], "--workers must be in [1, 256]"),
    (["collapse-scale", "--record", "elcentro", "--voussoirs", "100"], "--voussoirs must be in [3, 80]"),
    (["collapse-scale", "--record", "elcentro", "--model", "simulate", "--elements", "400"], "at most 2e+07"),
])
def test_beyond_a_bound_is_refused_before_computing(capsys, monkeypatch, argv, words):
    _refused(capsys, monkeypatch, argv, words)


def test_the_bounds_admit_the_common_runs():
    """The default arch (200 elements) through El Centro at the default step, and a 10^4-s
    rock history at 10 ms, are inside the bounds."""
    duration = 53.71 + 20 * (2.7489 / 9.81) ** 0.5                 # El Centro + 20 sqrt(L/g), L of the arch
    assert limits.check_steps(1e-3, duration, 200) == math.ceil(duration / 1e-3)
    limits.check_history(1e4, 1e-2)
    limits.check_block(0.2, 2.0)
    limits.check_discretisation("rock", 80, None)
    limits.check_discretisation("simulate", None, 1000)


def _negate(x: int) -> int:
    return -x


def test_never_more_workers_than_tasks(monkeypatch):
    """A pool gets at most one process per task, whatever --workers asks."""
    import fembeam.studies.parallel as parallel

    sizes = []
    real = parallel._new_pool
    monkeypatch.setattr(parallel, "_new_pool", lambda n: sizes.append(n) or real(n))
    out = parallel.run_tasks([(_negate, {"x": -i}) for i in range(3)], workers=200, progress=False)
    assert out == [0, 1, 2] and sizes == [3]


@pytest.mark.parametrize("argv", [
    ["rock", "--embrace", "359.9", "--voussoirs", "7", *SINE, "--json"],
    ["spectrum", "--embrace", "359.9", "--voussoirs", "7", "--pulse", "sine", "--periods", "0.3,0.5", "--json",
     "--quiet"],
    ["collapse-scale", "--embrace", "359.9", "--voussoirs", "7", "--record", "elcentro", "--json", "--quiet"],
])
def test_a_member_that_cannot_stand_is_an_answer_everywhere(capsys, argv):
    assert main(argv) == 0
    d = json.loads(capsys.readouterr().out, parse_constant=lambda c: (_ for _ in ()).throw(ValueError(c)))
    assert d["outcome"] == "cannot_stand"
    if argv[0] == "spectrum":
        assert [r["outcome"] for r in d["rows"]] == ["cannot_stand"] * 2 and d["timing_s"]["runs"] == 0
    if argv[0] == "collapse-scale":
        assert d["runs"] == 0 and d["first_overturning"] is None


def test_a_three_hinge_collapse_says_what_is_allowed(capsys):
    """At t/R = 1.9999999 the intrados hinges of the collapse mechanism meet: the motion
    commands say they follow four-hinge mechanisms."""
    code = main(["rock", "--embrace", "180", "--t-over-r", "1.9999999", "--pulse", "sine", "--amplitude", "95",
                 "--period", "0.5"])
    err = capsys.readouterr().err
    assert code == 2 and "got 3 hinges" in err and "give a member whose collapse mechanism has 4" in err
