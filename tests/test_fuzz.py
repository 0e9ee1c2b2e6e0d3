"""The command-line fuzzer: its judge catches each broken promise, and a bounded run of
every command finds none (the long runs: ``python -m fembeam.fuzz --runs 1000``)."""
from __future__ import annotations

import argparse
import random

import pytest

from fembeam.cli.main import build_parser
from fembeam.fuzz import _commands, check, draw, fuzz


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


def test_options_are_drawn_from_the_parsers():
    """Every option of every command is drawn, with a value of its kind, without the
    fuzzer naming it: a new option is covered as soon as it exists."""
    cmds = _commands(build_parser())
    rng = random.Random(0)
    for name, parser in cmds.items():
        seen = set()
        for _ in range(400):
            seen |= {w for w in draw(parser, rng) if w.startswith("--")}
        options = {a.option_strings[-1] for a in parser._actions
                   if a.option_strings and not isinstance(a, argparse._HelpAction)}
        assert len(seen) >= 0.9 * len(options), (name, options - seen)


def test_a_bounded_fuzz_run_finds_nothing():
    rep = fuzz(runs=30, seed=7, timeout=10.0)
    assert rep.runs == 30 and not rep.failures, rep.summary()
    assert rep.codes.get(2, 0) > 0 and rep.codes.get(0, 0) > 0     # it reached both kinds of run


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
