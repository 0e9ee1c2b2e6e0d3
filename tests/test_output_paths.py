"""Output files of every command: checked before any computation (exit 2, one line), and
written atomically (a failure or an interrupt leaves neither a half-written file nor a
temporary one)."""
from __future__ import annotations

import json
import os

import pytest

from fembeam import CircularArch, analyze
from fembeam.cli.main import main
from fembeam.errors import InputError
from fembeam.output.files import atomic_group, check_dir, check_output


def _exit(capsys, argv):
    try:
        code = main(argv)
    except SystemExit as e:
        code = e.code
    return code, capsys.readouterr()


@pytest.fixture
def afile(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    (tmp_path / "afile").write_text("x")
    (tmp_path / "adir").mkdir()
    return tmp_path


@pytest.mark.parametrize("argv, words", [
    (["analyze", "--vtk", "afile/a.vtu"], "--vtk"),
    (["analyze", "--vtk", "a.vtk"], ".vtu"),
    (["analyze", "--vtk", "adir"], "--vtk"),
    (["analyze", "--png", "afile/a.png"], "--png"),
    (["analyze", "--figure", "a.xyz"], "--figure"),
    (["analyze", "--figure", "missing/a.png"], "does not exist"),
    (["convergence", "--plot", "x.xyz", "--elements", "10,20"], ".png"),
    (["convergence", "--csv", "afile/x.csv", "--elements", "10,20"], "--csv"),
    (["convergence", "--out-dir", "afile", "--elements", "10,20"], "not a directory"),
    (["sweep", "--out-dir", "afile/sub", "--embrace", "90", "--t-over-r", "0.2"], "cannot be created"),
    (["sweep", "--plot", "adir", "--embrace", "90", "--t-over-r", "0.2"], "--plot"),
    (["report", "--out-dir", "afile"], "not a directory"),
    (["rock", "--pulse", "sine", "--amplitude", "1", "--period", "0.5", "--csv", "afile/x.csv"], "--csv"),
    (["spectrum", "--pulse", "sine", "--periods", "0.5", "--voussoirs", "7", "--plot", "x.txt"], "--plot"),
])
def test_bad_output_paths_exit_2_before_computing(afile, capsys, argv, words):
    code, out = _exit(capsys, argv)
    assert code == 2 and words in out.err and len(out.err.strip().splitlines()) == 1, out.err
    assert out.out == ""                                   # nothing computed, nothing printed
    assert sorted(os.listdir(afile)) == ["adir", "afile"]


@pytest.mark.skipif(os.geteuid() != 0 and not os.path.isdir("/proc"), reason="needs an unwritable directory")
def test_unwritable_directory_is_probed(tmp_path):
    """Permission bits say nothing to the superuser: the directory is probed with a file."""
    with pytest.raises(InputError, match="cannot write"):
        check_output("/proc/fembeam.csv", "--csv")
    with pytest.raises(InputError, match="cannot write"):
        check_dir("/proc/fembeam-out", "--out-dir")
    assert check_dir(tmp_path / "new" / "deeper", "--out-dir") == tmp_path / "new" / "deeper"
    assert not (tmp_path / "new").exists()                  # checking creates nothing


def test_interrupted_vtk_export_leaves_nothing(tmp_path, monkeypatch):
    """Ctrl-C while the third part is written: no .vtu, no .vtm, no temporary file."""
    import meshio

    res = analyze(CircularArch.from_ratio(157.5, 0.15), elements=20)
    calls = {"n": 0}
    real = meshio.Mesh.write

    def write(self, *a, **k):
        calls["n"] += 1
        if calls["n"] == 3:
            raise KeyboardInterrupt
        return real(self, *a, **k)

    monkeypatch.setattr(meshio.Mesh, "write", write)
    from fembeam.output.export import write_vtk
    with pytest.raises(KeyboardInterrupt):
        write_vtk(res, tmp_path / "a.vtu")
    assert os.listdir(tmp_path) == []
    monkeypatch.setattr(meshio.Mesh, "write", real)
    files = write_vtk(res, tmp_path / "a.vtu")
    assert sorted(os.listdir(tmp_path)) == sorted(p.name for p in files.values())


def test_atomic_group_renames_all_or_nothing(tmp_path):
    (tmp_path / "b.txt").write_text("old")
    with pytest.raises(RuntimeError):
        with atomic_group([tmp_path / "a.txt", tmp_path / "b.txt"]) as (ta, tb):
            open(ta, "w").write("new a")
            raise RuntimeError("writer failed")
    assert sorted(os.listdir(tmp_path)) == ["b.txt"] and (tmp_path / "b.txt").read_text() == "old"
    with atomic_group([tmp_path / "a.txt", tmp_path / "b.txt"]) as (ta, tb):
        open(ta, "w").write("new a")
        open(tb, "w").write("new b")
    assert (tmp_path / "a.txt").read_text() == "new a" and (tmp_path / "b.txt").read_text() == "new b"
    assert sorted(os.listdir(tmp_path)) == ["a.txt", "b.txt"]


def test_out_dir_files_are_valid_json(afile, capsys):
    code, out = _exit(capsys, ["convergence", "--elements", "8,16", "--out-dir", "res/conv", "--quiet"])
    assert code == 0
    d = json.loads((afile / "res" / "conv" / "convergence.json").read_text(),
                   parse_constant=lambda c: (_ for _ in ()).throw(ValueError(c)))
    assert d["levels"] == [8, 16]
    assert sorted(os.listdir(afile / "res" / "conv")) == ["convergence.csv", "convergence.json", "convergence.png"]


def test_report_output_in_the_way_fails_before_computing(tmp_path, capsys):
    (tmp_path / "paper.png").mkdir()
    code, out = _exit(capsys, ["report", "--out-dir", str(tmp_path), "--quick"])
    assert code == 2 and "paper.png" in out.err and "is a directory" in out.err and out.out == ""


# ------------------------------------------------------------------ names, links, sets
ROCK = ["rock", "--voussoirs", "7", "--pulse", "sine", "--amplitude", "0.45", "--period", "1"]


def test_a_name_the_file_system_takes_is_written_one_it_refuses_is_refused_first(afile, capsys):
    """The temporary name is short whatever the target's length: a 255-byte name is
    written; a 256-byte one, or a ParaView series whose frame names would exceed 255 bytes,
    is refused before computing."""
    longest = "b" * 251 + ".csv"
    code, out = _exit(capsys, ROCK + ["--csv", longest])
    assert code == 0 and sorted(os.listdir(afile)) == ["adir", "afile", longest]
    for argv, words in ((["--csv", "c" * 252 + ".csv"], "has 256 bytes; at most 255"),
                        (["--vtk", "v" * 247 + ".pvd"], "_0199.vtu' has 256 bytes"),
                        (["--vtk", "v" * 246 + ".pvd", "--frames", "20000"], "_19999.vtu' has 256 bytes")):
        code, out = _exit(capsys, ROCK + argv)
        assert code == 2 and words in out.err and len(out.err.strip().splitlines()) == 1 and out.out == ""
    assert sorted(os.listdir(afile)) == ["adir", "afile", longest]


def test_an_output_link_is_written_through_and_stays_a_link(afile, capsys):
    os.symlink("data/h.csv", "h.csv")
    os.mkdir("data")
    code, out = _exit(capsys, ROCK + ["--csv", "h.csv"])
    assert code == 0 and os.path.islink("h.csv") and (afile / "data" / "h.csv").read_text().startswith("t,")
    assert os.listdir(afile / "data") == ["h.csv"]


@pytest.mark.parametrize("argv", [
    ROCK + ["--csv", "link.csv", "--plot", "real.png"],
    ["analyze", "--png", "a.png", "--figure", "a.png"],
    ["spectrum", "--voussoirs", "7", "--pulse", "sine", "--periods", "0.3", "--csv", "link.csv", "--plot", "real.png"],
    ["sweep", "--csv", "link.csv", "--plot", "real.png", "--embrace", "90", "--t-over-r", "0.2"],
])
def test_two_outputs_naming_one_file_are_refused(afile, capsys, argv):
    (afile / "real.png").write_bytes(b"")
    os.symlink("real.png", "link.csv")
    code, out = _exit(capsys, argv)
    assert code == 2 and "name the same file" in out.err and len(out.err.strip().splitlines()) == 1, out.err
    assert (afile / "real.png").read_bytes() == b""


def test_a_rerun_interrupted_leaves_the_previous_series_whole(afile, capsys, monkeypatch):
    """Re-running ``rock --vtk`` over a complete series and interrupting it while the new
    frames are written leaves the old index and every file it names; a finished re-run with
    fewer frames removes the old frames it does not list."""
    import re

    import meshio

    code, _ = _exit(capsys, ROCK + ["--vtk", "r.pvd", "--frames", "30"])
    assert code == 0
    before = {f: (afile / f).read_bytes() for f in os.listdir(afile) if f.startswith("r")}
    assert len(before) == 31
    real, calls = meshio.write, []

    def interrupted(path, mesh, *a, **k):
        calls.append(path)
        if len(calls) == 7:
            raise KeyboardInterrupt
        return real(path, mesh, *a, **k)

    monkeypatch.setattr(meshio, "write", interrupted)
    code, out = _exit(capsys, ROCK + ["--vtk", "r.pvd", "--frames", "12", "--amplitude", "0.5"])
    assert code == 130 and len(calls) == 7
    assert {f: (afile / f).read_bytes() for f in os.listdir(afile) if f.startswith(("r", ".r"))} == before
    monkeypatch.setattr(meshio, "write", real)
    code, _ = _exit(capsys, ROCK + ["--vtk", "r.pvd", "--frames", "12"])
    names = re.findall(r'file="([^"]+)"', (afile / "r.pvd").read_text())
    assert code == 0 and sorted(f for f in os.listdir(afile) if f.startswith("r")) == sorted(names + ["r.pvd"])
    assert len(names) == 12
