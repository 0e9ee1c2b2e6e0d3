"""The inputs the study commands share: suite folders, CSV records, the scheduler option, notes.

Each class of input is checked once for every command that reads it; nothing here runs a
dynamic analysis (every case is refused, or read, before computing).
"""
from __future__ import annotations

import os
import shutil
from pathlib import Path

import numpy as np
import pytest

from fembeam.cli.main import main
from fembeam.dynamics.ground import PLAUSIBLE_PGA, GroundMotion, unit_note
from fembeam.studies.parallel import default_workers, executor_label
from fembeam.studies.suites import folder_suite

SHIPPED = Path(__file__).resolve().parents[1] / "fembeam" / "data" / "ground_motions"
BLOCK = ["--block", "0.4", "1.6"]


def _one_line(capsys, argv, *words):
    code = main(argv)
    err = capsys.readouterr().err
    assert code == 2 and len(err.strip().splitlines()) == 1, err
    for w in words:
        assert w in err, err


def _suite(tmp_path) -> Path:
    d = tmp_path / "suite"
    d.mkdir()
    shutil.copy(SHIPPED / "RSN6_IMPVALL.I_I-ELC180.AT2", d)
    return d


@pytest.mark.parametrize("kind", ["fifo", "loop", "broken", "directory"])
@pytest.mark.parametrize("command", ["fragility", "assess"])
def test_a_suite_entry_that_is_not_a_record_file_refuses_the_suite(tmp_path, capsys, kind, command):
    d = _suite(tmp_path)
    name = {"fifo": "fifo.AT2", "loop": "loop.csv", "broken": "gone.csv", "directory": "dir.csv"}[kind]
    p = d / name
    if kind == "fifo":
        os.mkfifo(p)
    elif kind == "loop":
        p.symlink_to(name)
    elif kind == "broken":
        p.symlink_to("nowhere.csv")
    else:
        p.mkdir()
    option = "--suite" if command == "fragility" else "--records"
    _one_line(capsys, [command, *BLOCK, option, str(d)], name)


def test_the_folder_reader_names_what_it_cannot_read(tmp_path):
    d = _suite(tmp_path)
    os.mkfifo(d / "b.AT2")
    with pytest.raises(Exception, match="b.AT2' is a FIFO"):
        folder_suite(d)


@pytest.mark.parametrize("command", [["fragility", *BLOCK, "--suite", "SUITE"],
                                     ["spectrum", "--voussoirs", "7", "--pulse", "sine", "--periods", "0.5"],
                                     ["sweep"]])
@pytest.mark.parametrize("address", ["", "  "])
def test_an_empty_scheduler_address_is_one_line(tmp_path, capsys, command, address):
    argv = [str(_suite(tmp_path)) if a == "SUITE" else a for a in command]
    _one_line(capsys, [*argv, "--scheduler", address], "--scheduler")


def test_a_record_in_m_per_s2_gets_a_note_and_runs_as_given(tmp_path, capsys):
    f = tmp_path / "ms2.csv"
    t = np.arange(0, 2.0, 0.01)
    f.write_text("time,acc\n" + "".join(f"{x:.2f},{2.75 * np.sin(2 * np.pi * x):.6f}\n" for x in t))
    g = GroundMotion.record(f)
    assert g.pga == pytest.approx(2.75, rel=1e-6) and g.pga > PLAUSIBLE_PGA
    assert "divide them by 9.81" in unit_note(g)
    assert unit_note(GroundMotion.record("elcentro")) is None
    code = main(["rock", "--voussoirs", "5", "--record", str(f), "--t-end", "0.05"])
    err = capsys.readouterr().err
    assert code == 0 and "fembeam: note: ms2.csv: peak ground acceleration 2.75 g" in err


def test_an_uneven_record_has_no_single_time_step(tmp_path):
    f = tmp_path / "uneven.csv"
    f.write_text("0,0\n0.01,0.1\n0.03,0\n0.04,-0.1\n")
    d = tmp_path / "s"
    d.mkdir()
    shutil.copy(f, d)
    meta = folder_suite(d).records[0].metadata()
    assert meta["dt_s"] is None and meta["dt_min_s"] == pytest.approx(0.01) and meta["dt_max_s"] == pytest.approx(0.02)
    even = folder_suite(_suite(tmp_path)).records[0].metadata()
    assert even["dt_s"] == pytest.approx(0.01) and even["dt_min_s"] == pytest.approx(0.01)


def test_the_executor_says_the_processes_it_starts():
    assert executor_label(256, None, 4) == "local (4 workers)"
    assert executor_label(None, None, 1) == "local (1 worker)"
    assert executor_label(None, None, 10 ** 6) == f"local ({default_workers()} worker{'s' * (default_workers() > 1)})"
    assert executor_label(3, "tcp://x:1", 4) == "dask"


def _square(x):
    return x * x


def test_no_progress_bar_on_a_stderr_that_is_not_a_terminal(capsys):
    from fembeam.studies.parallel import run_tasks
    assert run_tasks([(_square, {"x": k}) for k in range(3)], workers=1, progress=True) == [0, 1, 4]
    assert capsys.readouterr().err == ""


def test_the_friction_range_message_is_the_range_checked(capsys):
    for command in ("simulate", "assess"):
        for mu in ("0", "1000.0001"):
            with pytest.raises(SystemExit) as e:      # argparse's exit
                main([command, "--voussoirs", "5", "--pulse", "sine", "--amplitude", "1", "--period", "0.5",
                      "--friction", mu])
            err = capsys.readouterr().err
            assert e.value.code == 2 and "[0.001, 1000]" in err and f"got '{mu}'" in err
