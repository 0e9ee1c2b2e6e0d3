"""The command-line fuzzer: its judge catches each broken promise, and a bounded run of
every command finds none (the long runs: ``python -m fembeam.fuzz --runs 1000``)."""
from __future__ import annotations

import argparse
import os
import random
import signal
import sys
import threading

import pytest

from fembeam.cli.main import build_parser
from fembeam.fuzz import _commands, check, draw, fuzz, run_one

# A hang guard, not a time limit: every run of the bounded sample takes under 1 s on an idle
# 2-core machine (the slowest, ``report --quick``, 0.6 s), so a run still going after this
# long is stuck, whatever the load.
HANG_GUARD_S = 300.0


@pytest.mark.parametrize("code, out, err, argv, why", [
    (ValueError("x"), "", "Traceback ...", [], "exception"),
    (1, "", "fembeam: error: x", [], "exit code 1"),
    (2, "", "line one\nline two", [], "2 stderr lines"),
    (2, "", "", [], "0 stderr lines"),
    (0, "", "/x.py:1: RuntimeWarning: overflow", [], "warning"),
    (3, "", "some noise", [], "fembeam's message"),
    (0, '{"a": NaN}', "", ["--json"], "strict JSON"),
    (0, "A_L = 0.35", "", ["--json"], "strict JSON"),
    (0, "[1, 2]", "", ["--json"], "one JSON object"),
])
def test_the_judge_catches_broken_promises(code, out, err, argv, why):
    assert why in check("analyze", argv, code, out, err)


def test_the_judge_accepts_kept_promises():
    assert check("analyze", ["--json"], 0, '{"r": null}', "") is None
    assert check("analyze", [], 2, "", "fembeam: error: --elements must be >= 4\n") is None
    assert check("report", [], 1, "table", "") is None and check("analyze", [], "timeout", "", "") is None


# ---------------------------------------------------------------- one run, in a child process
def _hangs(argv):
    threading.Event().wait()                   # never returns: the outcome cannot depend on speed


def _starts_a_process_then_hangs(argv):
    pid = os.fork()
    if pid == 0:
        signal.pause()
        os._exit(0)
    with open(argv[0], "w") as f:
        f.write(str(pid))
    _hangs(argv)


class _Unpicklable(Exception):
    def __init__(self, a, b):                  # pickles, but cannot be built back from its args
        super().__init__(f"{a} {b}")


def _raises(argv):
    raise {"value": ValueError("bad value"), "odd": _Unpicklable(1, 2)}[argv[0]]


def _dies(argv):
    if argv[0] == "signal":
        os.kill(os.getpid(), signal.SIGKILL)
    os._exit(5)


def _prints(argv):
    print("x" * 3_000_000)                     # more than a pipe holds
    print("on stderr", file=sys.stderr)
    return 0


def test_a_run_past_its_timeout_is_killed_and_nothing_is_raised_here():
    """No alarm and no signal handler in this process: a run that does not finish is killed
    and counted, nothing can fire later (the old alarm raised in a finaliser escaped as
    "Exception ignored")."""
    before = signal.getsignal(signal.SIGALRM), signal.getitimer(signal.ITIMER_REAL), sys.unraisablehook
    assert run_one(["x"], timeout=0.5, command=_hangs) == ("timeout", "", "")
    assert (signal.getsignal(signal.SIGALRM), signal.getitimer(signal.ITIMER_REAL), sys.unraisablehook) == before


def test_a_timed_out_run_takes_the_processes_it_started_with_it(tmp_path):
    path = str(tmp_path / "pid")
    assert run_one([path], timeout=0.5, command=_starts_a_process_then_hangs)[0] == "timeout"
    pid = int(open(path).read())
    # SIGKILL was sent to its group; wait (a hang guard, not a time limit) for it to be gone
    stat = f"/proc/{pid}/stat"
    for _ in range(int(HANG_GUARD_S / 0.05)):
        try:
            with open(stat) as f:
                if f.read().rsplit(")", 1)[1].split()[0] in "ZX":
                    break
        except FileNotFoundError:
            break
        threading.Event().wait(0.05)
    else:
        pytest.fail(f"process {pid} started by a timed-out run still runs after {HANG_GUARD_S:.0f} s")


def test_a_run_reports_what_happened_in_its_child():
    code, out, err = run_one(["value"], timeout=None, command=_raises)
    assert isinstance(code, ValueError) and "Traceback" in err and "bad value" in err
    assert check("analyze", [], code, out, err) == "exception ValueError"
    code, out, err = run_one(["odd"], timeout=None, command=_raises)
    assert check("analyze", [], code, out, err) == "exception _Unpicklable"
    assert run_one(["signal"], timeout=None, command=_dies)[0] == "killed by signal 9"
    assert run_one(["exit"], timeout=None, command=_dies)[0] == "died with exit status 5 and no result"
    assert check("analyze", [], "killed by signal 9", "", "") == "killed by signal 9"
    assert run_one([], timeout=None, command=_prints) == (0, "x" * 3_000_000 + "\n", "on stderr\n")


def test_options_are_drawn_from_the_parsers():
    """Every option of every command is drawn, with a value of its kind, without the
    fuzzer naming it: a new option is covered as soon as it exists; an option hidden from the
    help (a replaced one, kept only to refuse it) never is."""
    cmds = _commands(build_parser())
    rng = random.Random(0)
    for name, parser in cmds.items():
        seen = set()
        for _ in range(400):
            seen |= {w for w in draw(parser, rng) if w.startswith("--")}
        options = {a.option_strings[-1] for a in parser._actions
                   if a.option_strings and not isinstance(a, argparse._HelpAction) and a.help != argparse.SUPPRESS}
        hidden = {a.option_strings[-1] for a in parser._actions if a.option_strings and a.help == argparse.SUPPRESS}
        assert len(seen) >= 0.9 * len(options), (name, options - seen)
        assert not seen & hidden, (name, seen & hidden)
        if name == "assess":
            assert "--resolution" in seen and not {"--factors", "--bisect-tol"} & seen


def test_a_bounded_fuzz_run_finds_nothing():
    rep = fuzz(runs=15, seed=7, timeout=HANG_GUARD_S)
    assert not rep.timeouts, (f"a run was still going after {HANG_GUARD_S:.0f} s (each takes under 1 s on an idle "
                              f"machine): it hangs\n{rep.summary()}")
    assert rep.runs == 15 and not rep.failures, rep.summary()
    assert rep.codes.get(2, 0) > 0 and rep.codes.get(0, 0) > 0     # it reached both kinds of run


def test_every_class_of_hostile_study_input_gives_its_exit_code():
    """The fixed command lines of the classes of hostile input of the study commands (suite folders
    with special files, CSV records with bad lines, two outputs naming one file, an empty scheduler,
    a member that cannot stand in every study command): refused with one line, or answered."""
    from fembeam.fuzz import CLASSES
    rep = fuzz(runs=0, timeout=HANG_GUARD_S, classes=True)
    assert rep.runs == len(CLASSES) and not rep.timeouts and not rep.failures, rep.summary()


@pytest.mark.parametrize("argv, words", [
    (["analyze", "--midcurve", "BIN", "--thickness", "0.3"], "not a text CSV file"),
    (["spectrum", "--voussoirs", "7", "--pulse", "sine", "--periods", "0.3", "--scheduler", "out.xyz", "--quiet"],
     "cannot connect to the Dask scheduler"),
    (["sweep", "--embrace", "90", "--t-over-r", "0.2", "--scheduler", "out.xyz", "--quiet"],
     "cannot connect to the Dask scheduler"),
])
def test_what_the_fuzzer_found(tmp_path, capsys, argv, words):
    """Two findings of ``python -m fembeam.fuzz --runs 1000 --seed 2026``: a binary file given as
    a surveyed mid-curve, and a scheduler address that is not one (both were tracebacks)."""
    from fembeam.cli.main import main

    binary = tmp_path / "figure.pdf"
    binary.write_bytes(b"%PDF-1.4\n\xac\xff\xfe binary")
    code = main([str(binary) if a == "BIN" else a for a in argv])
    err = capsys.readouterr().err
    assert code == 2 and words in err and len(err.strip().splitlines()) == 1, err


# ---------------------------------------------------------------- process-level scenarios
def test_the_scenario_judge_catches_what_is_left_behind(tmp_path):
    """Temporary files, an index naming a missing frame, a half-written output, the wrong
    exit code or more than one line after a signal: each is a finding."""
    import subprocess

    from fembeam.fuzz_scenarios import _complete, _judge_signal, _leftovers

    (tmp_path / ".h.csv.a1b2c3d4.csv").write_text("t\n")
    (tmp_path / ".s.csv.spectrum-journal.jsonl").write_text("")      # a study's journal is kept: not a finding
    (tmp_path / "r.pvd").write_text('<DataSet file="r_0000.vtu"/><DataSet file="r_0001.vtu"/>')
    (tmp_path / "r_0000.vtu").write_text("")
    assert sorted(_leftovers(str(tmp_path))) == [".h.csv.a1b2c3d4.csv", "r.pvd -> r_0001.vtu (missing)"]
    (tmp_path / "h.csv").write_text("a,b\n1,2\n3\n")
    (tmp_path / "h.png").write_bytes(b"\x89PNG\r\n\x1a\n cut short")
    assert "rows of different lengths" in _complete(str(tmp_path / "h.csv"))
    assert "cannot be read back" in _complete(str(tmp_path / "h.png"))
    clean = tmp_path / "clean"
    clean.mkdir()
    done = subprocess.CompletedProcess([], 130)
    assert _judge_signal(done, [], signal.SIGINT, True, "", "fembeam: interrupted\n", str(clean)) is None
    assert "expected 143" in _judge_signal(done, [], signal.SIGTERM, True, "", "fembeam: interrupted\n", str(clean))
    assert "2 stderr lines" in _judge_signal(done, [], signal.SIGINT, True, "", "x\nfembeam: interrupted\n",
                                            str(clean))
    assert "traceback" in _judge_signal(done, [], signal.SIGINT, True, "", "Traceback\nKeyboardInterrupt", str(clean))
    assert "left behind" in _judge_signal(done, [], signal.SIGINT, True, "", "fembeam: interrupted\n", str(tmp_path))


@pytest.mark.skipif(not os.path.exists("/proc/self/status"), reason="reads /proc/PID/status")
def test_a_bounded_sample_of_every_scenario_finds_nothing():
    """One scenario of each kind (``python -m fembeam.fuzz --scenarios N`` draws many):
    signals early and late, the parent of a study killed, stdout closed, an ASCII locale, a
    re-run over complete outputs interrupted.  Hang guards only: no time is judged."""
    from fembeam.fuzz import draw_command
    from fembeam.fuzz_scenarios import SCENARIOS, run_scenarios

    rep = run_scenarios(0, random.Random(4), draw_command, plan=list(SCENARIOS))
    assert sum(rep.counts.values()) == len(SCENARIOS) and not rep.failures, rep.summary()
