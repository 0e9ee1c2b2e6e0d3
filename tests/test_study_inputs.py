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


def test_infinite_friction_is_joints_that_never_slide(capsys):
    """``--friction inf`` (``math.inf`` in Python) is unlimited friction: the same answer as
    without the option, bit for bit, in the simulation and in the studies."""
    import json
    import math

    from fembeam.dynamics.ground import GroundMotion
    from fembeam.geometry import CircularArch
    from fembeam.simulation import Simulator

    g = GroundMotion.sine(0.6, 0.5)
    a = Simulator(CircularArch(), voussoirs=5, friction=math.inf).run(g, dt=2e-3, t_end=1.0)
    b = Simulator(CircularArch(), voussoirs=5).run(g, dt=2e-3, t_end=1.0)
    assert a.friction is None and (a.outcome, a.t_collapse, a.steps) == (b.outcome, b.t_collapse, b.steps)
    assert a.to_dict()["t_collapse"] == a.to_dict()["t_overturn"] == a.t_overturn
    base = ["collapse-scale", "--voussoirs", "5", "--record", "elcentro", "--model", "simulate",
            "--dt", "0.002", "--resolution", "0.2", "--json"]
    out = []
    for extra in ([], ["--friction", "inf"]):
        assert main(base + extra) == 0
        d = json.loads(capsys.readouterr().out)
        out.append((d["first_collapse"], d["friction"]))
    assert out[0] == out[1] and out[0][1] is None


@pytest.mark.parametrize("extra, words", [
    (["--plot", "same.png", "--ida-plot", "same.png"], "same"),
    (["--out-dir", "D", "--plot", "D/ida.png"], "ida.png"),
    (["--out-dir", "D", "--csv", "D/ida.csv"], "ida.csv"),
])
def test_two_outputs_of_fragility_naming_one_file_are_refused(tmp_path, capsys, monkeypatch, extra, words):
    monkeypatch.chdir(tmp_path)
    (tmp_path / "D").mkdir()
    _one_line(capsys, ["fragility", *BLOCK, "--suite", str(_suite(tmp_path)), *extra], words)


@pytest.mark.parametrize("extra", [["--out-dir", "SUITE"], ["--csv", "SUITE/f.csv"]])
def test_a_csv_output_in_the_suite_folder_is_refused(tmp_path, capsys, extra):
    d = _suite(tmp_path)
    _one_line(capsys, ["fragility", *BLOCK, "--suite", str(d), *[a.replace("SUITE", str(d)) for a in extra]],
              "would be read as a record")


class _Result:
    def __init__(self, ida: bool):
        self.ida = ida

    def csv_rows(self):
        return [{"record": "a", "collapse": 1.0}]

    def ida_rows(self):
        return [{"record": "a", "factor": 1.0}] if self.ida else []

    def to_dict(self):
        return {"n": 1}


def test_a_fragility_out_dir_is_swapped_in_whole(tmp_path, monkeypatch):
    import fembeam.cli.fragility as cli

    out = tmp_path / "out"

    def paths():
        return {k: str(out / n) for k, n in cli.FILES.items()}

    def figure(res, path):
        Path(path).write_text("figure")
    monkeypatch.setattr(cli, "plot_fragility", figure)
    monkeypatch.setattr(cli, "plot_ida", figure)
    cli.write(_Result(ida=True), paths(), str(out))
    assert sorted(os.listdir(out)) == sorted(cli.FILES.values())

    def broken(res, path):
        raise KeyboardInterrupt
    monkeypatch.setattr(cli, "plot_ida", broken)     # interrupted while writing: the old set stays
    (out / "fragility.json").write_text("old")
    with pytest.raises(KeyboardInterrupt):
        cli.write(_Result(ida=True), paths(), str(out))
    assert (out / "fragility.json").read_text() == "old" and sorted(os.listdir(out)) == sorted(cli.FILES.values())
    fresh = tmp_path / "fresh"
    with pytest.raises(KeyboardInterrupt):               # a new folder: not created at all
        cli.write(_Result(ida=True), {k: str(fresh / n) for k, n in cli.FILES.items()}, str(fresh))
    assert not fresh.exists() and [p.name for p in tmp_path.iterdir() if p.name.startswith(".")] == []
    monkeypatch.setattr(cli, "plot_ida", figure)
    cli.write(_Result(ida=False), paths(), str(out))     # a study without IDA runs: no stale ida.csv
    assert sorted(os.listdir(out)) == ["fragility.csv", "fragility.json", "fragility.png", "ida.png"]


def test_an_assess_report_leaves_no_stale_motion_and_no_empty_folder(tmp_path, monkeypatch):
    from fembeam.output.files import atomic_dir
    d = tmp_path / "report"
    with atomic_dir(d, ["a.png", "motion_01_x.png", "motion_02_x.png"], stale=["motion_*.png"]) as tmps:
        for t in tmps:
            Path(t).write_text("1")
    (d / "notes.txt").write_text("the user's")
    with atomic_dir(d, ["a.png", "motion_01_x.png"], stale=["motion_*.png"]) as tmps:
        for t in tmps:
            Path(t).write_text("2")
    assert sorted(os.listdir(d)) == ["a.png", "motion_01_x.png", "notes.txt"]
    e = tmp_path / "new" / "report"
    with pytest.raises(KeyboardInterrupt):
        with atomic_dir(e, ["a.png"]) as tmps:
            raise KeyboardInterrupt
    assert not e.exists() and os.listdir(e.parent) == []
    with atomic_dir(e, ["a.png"]) as (tmp,):
        Path(tmp).write_text("3")
    assert (e / "a.png").read_text() == "3" and oct(e.stat().st_mode & 0o777) != oct(0o700)


@pytest.mark.parametrize("argv, words", [
    (["fragility", *BLOCK, "--suite", "SUITE", "--max-runs", "100000", "--both-signs"],
     "1 records x 2 signs x --max-runs 100000 = 200000"),
    (["assess", *BLOCK, "--record", "elcentro", "--max-runs", "60000"],
     "1 ground motions x 2 models x --max-runs 60000 = 120000"),
])
def test_a_study_bounds_the_runs_it_will_make_before_computing(tmp_path, capsys, argv, words):
    _one_line(capsys, [str(_suite(tmp_path)) if a == "SUITE" else a for a in argv], words, "at most 100000")
