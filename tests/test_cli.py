"""The command line as a user meets it: one JSON object, one-line errors, exit codes."""
import json
import subprocess
import sys

import pytest

from fembeam.cli import main

from inprocess import fembeam


def run(*args):
    return subprocess.run([sys.executable, "-m", "fembeam.cli", *args], capture_output=True, text=True)


def test_analyze_json_keys_and_values():
    p = run("analyze", "--embrace", "157.5", "--t-over-r", "0.15", "--elements", "100", "--json")
    assert p.returncode == 0, p.stderr
    out = json.loads(p.stdout)  # exactly one JSON object on stdout
    for key in ("A_L", "r", "elements", "hinges_before", "hinges_after", "verification"):
        assert key in out
    assert out["elements"] == 100
    assert out["A_L"] == pytest.approx(0.353, abs=0.002) and out["r"] == pytest.approx(0.606, abs=0.002)
    for h in out["hinges_before"] + out["hinges_after"]:
        assert set(h) == {"angle_deg", "side"} and h["side"] in ("intrados", "extrados")
        assert 0.0 <= h["angle_deg"] <= 157.5
    for k in ("equilibrium_residual", "impulse_line_outside", "max_tensile_impulse", "impulse_work",
              "max_shear_ratio"):
        assert out["verification"][k] == out["verification"]["impact"][k]
    assert out["verification"]["equilibrium_residual"] < 1e-10 and out["verification"]["impulse_work"] < 1e-8


def test_summary_is_readable(capsys):
    assert main(["analyze", "--voussoirs", "7", "--embrace", "150"]) == 0
    out = capsys.readouterr().out
    assert "A_L = 0.444" in out and "r = K'/K = 0.532" in out and "hinges after impact" in out


@pytest.mark.parametrize("args, words", [
    (["--t-over-r", "-0.1"], "t/R"), (["--t-over-r", "0"], "t/R"), (["--t-over-r", "2.5"], "in [0.001, 2)"), (["--t-over-r", "1e-4"], "in [0.001, 2)"),
    (["--embrace", "0"], "embrace"), (["--embrace", "400"], "(0, 360)"), (["--embrace", "nan"], "finite"),
    (["--elements", "2"], "in [4, 200000]"), (["--voussoirs", "0"], "in [1, 200000]"), (["--radius", "-3"], "radius"),
    (["--t-over-r", "abc"], "number"),
])
def test_bad_input_one_line_no_traceback(args, words):
    p = fembeam("analyze", *args)
    assert p.returncode == 2
    lines = p.stderr.strip().splitlines()
    assert len(lines) == 1 and words in lines[0] and "Traceback" not in p.stderr
    assert p.stdout == ""


def test_bad_input_exits_2_from_the_process():
    """The same one line and exit code 2 from ``python -m fembeam.cli``, the process (the cases
    above: ``main`` in this one)."""
    p = run("analyze", "--t-over-r", "-0.1")
    assert p.returncode == 2 and p.stdout == ""
    lines = p.stderr.strip().splitlines()
    assert len(lines) == 1 and "t/R" in lines[0] and "Traceback" not in p.stderr


def test_physical_outcomes_in_json(capsys):
    assert main(["analyze", "--embrace", "180", "--t-over-r", "0.08", "--elements", "60", "--json"]) == 0
    out = json.loads(capsys.readouterr().out)
    assert out["outcome"] == "cannot_stand" and out["t_min_over_R"] == pytest.approx(0.1075, abs=1e-3)
    assert main(["analyze", "--embrace", "80", "--t-over-r", "0.15", "--elements", "60", "--json"]) == 0
    out = json.loads(capsys.readouterr().out)
    assert out["outcome"] == "arrested" and out["r"] == 0.0


def test_help_lists_every_command_without_importing_them():
    """``fembeam --help`` names every sub-command with the help line of its module, which it
    does not import (the command runs import only themselves)."""
    import argparse
    import subprocess
    import sys

    from fembeam.cli.main import COMMANDS, build_parser

    full = build_parser()
    sub = next(a for a in full._actions if isinstance(a, argparse._SubParsersAction))
    helps = {c.dest: c.help for c in sub._choices_actions}
    assert helps == {name: h for name, (_, h) in COMMANDS.items()}
    code = ("import sys; from fembeam.cli.main import main\n"
            "try: main(['--help'])\nexcept SystemExit: pass\n"
            "print(sorted(m for m in sys.modules if m.startswith(('scipy', 'skfem', 'fembeam.analysis'))))")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True).stdout
    assert out.strip().splitlines()[-1] == "[]"
