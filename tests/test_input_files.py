"""Input files (surveyed mid-curves, ground-motion records) are read with bounds: a special
file, a file too large or with too many rows, or a header that does not parse is refused
before anything is allocated, with exit 2 and one line; nothing hangs."""
from __future__ import annotations

import os

import numpy as np
import pytest

from fembeam.cli.main import main
from fembeam.dynamics.ground import MAX_RECORD_SAMPLES, GroundMotion
from fembeam.errors import InputError
from fembeam.geometry.surveyed import MAX_POINTS, read_midcurve_csv
from fembeam.readers import read_bytes, read_text

SINE = ["--pulse", "sine", "--amplitude", "1", "--period", "0.5"]


def _one_line(capsys, argv, words):
    code = main(argv)
    err = capsys.readouterr().err
    assert code == 2 and words in err and len(err.strip().splitlines()) == 1, err


@pytest.fixture
def special(tmp_path):
    """A FIFO (opening it for reading would block for ever), a sparse 5 GB file (reading it
    would allocate 5 GB) and a directory."""
    fifo = tmp_path / "fifo.csv"
    os.mkfifo(fifo)
    sparse = tmp_path / "sparse.csv"
    with open(sparse, "wb") as f:
        f.truncate(5 * 2 ** 30)
    (tmp_path / "dir.csv").mkdir()
    return {"fifo": fifo, "sparse": sparse, "dir": tmp_path / "dir.csv", "zero": "/dev/zero"}


@pytest.mark.parametrize("which, words", [("fifo", "is a FIFO"), ("zero", "is a character device"),
                                          ("dir", "is a directory"), ("sparse", "at most 64 MB")])
def test_special_and_huge_files_are_refused_unread(special, which, words):
    with pytest.raises(InputError, match=words):
        read_bytes(special[which], "the file")


@pytest.mark.parametrize("option", ["--midcurve", "--record"])
@pytest.mark.parametrize("which, words", [("fifo", "is a FIFO"), ("zero", "is a character device"),
                                          ("sparse", "at most")])
def test_commands_refuse_special_files(special, capsys, option, which, words):
    member = ["--thickness", "0.3"] if option == "--midcurve" else ["--voussoirs", "7"]
    ground = SINE if option == "--midcurve" else []
    _one_line(capsys, ["rock", option, str(special[which]), *member, *ground], words)


def test_text_files_are_utf8_without_nul(tmp_path):
    f = tmp_path / "x.csv"
    f.write_bytes(b"x,y\n\x00\x01")
    with pytest.raises(InputError, match="not a text CSV file"):
        read_text(f, "the file", kind="CSV")
    f.write_bytes(b"x,y\n\xff\xfe")
    with pytest.raises(InputError, match="not a text file"):
        read_text(f, "the file")
    assert read_text(f, "the file", errors="replace") == "x,y\n\ufffd\ufffd"


def test_a_midcurve_has_at_most_max_points_counted_before_parsing(tmp_path):
    f = tmp_path / "many.csv"
    th = np.linspace(0.2, 2.9, MAX_POINTS + 1)
    np.savetxt(f, np.c_[-np.cos(th), np.sin(th)], delimiter=",", header="x,y", comments="")
    with pytest.raises(InputError, match=f"at most {MAX_POINTS} points"):
        read_midcurve_csv(f)
    with open(f, "a") as fh:                       # a row that does not parse, after the cap: never reached
        fh.write("abc,def\n")
    with pytest.raises(InputError, match=f"at most {MAX_POINTS} points"):
        read_midcurve_csv(f)


def _at2(tmp_path, header: str, values: str = "0.1 0.2 0.1 0.0") -> str:
    f = tmp_path / "r.AT2"
    f.write_text(f"PEER\nx\nunits of g\n{header}\n{values}\n")
    return str(f)


@pytest.mark.parametrize("header, words", [
    ("NPTS=   4, DT= 0.01.5 SEC", "DT a number of seconds"),
    ("NPTS=   4, DT= - SEC", "DT a number of seconds"),
    ("NPTS=   4, DT= e SEC", "DT a number of seconds"),
    ("NPTS=   4.5, DT= 0.01 SEC", "NPTS must be an integer"),
    ("NPTS=   4, DT= 0 SEC", "[1e-05, 1] s, got 0 s"),
    ("NPTS=   4, DT= 1e300 SEC", "[1e-05, 1] s, got 1e+300 s"),
    ("NPTS=   4, DT= nan SEC", "[1e-05, 1] s"),
    ("NPTS=   40000000000, DT= 0.01 SEC", f"from 2 to {MAX_RECORD_SAMPLES} samples"),
    ("NPTS=   900000, DT= 0.5 SEC", "within 10000 s"),
])
def test_at2_headers_are_checked_before_allocating(tmp_path, header, words):
    with pytest.raises(InputError, match=words.replace("[", r"\[").replace("+", r"\+")):
        GroundMotion.record(_at2(tmp_path, header))


@pytest.mark.parametrize("rows, words", [
    ("0,0\n1e-,0.1\n", "'1e-,0.1'"),
    ("0,0\n0.01\n", "'0.01'"),
    ("0,0\n0.01,nan\n", "finite"),
    ("0,0\n0.01,0\n0.01,0.1\n", "strictly increasing"),
    ("0,0\n5,0.1\n", "[1e-05, 1] s"),
    ("0,0\n", "at least two lines"),
    ("20000,0\n20000.01,0.1\n", "within 10000 s"),
])
def test_csv_records_say_what_is_wrong(tmp_path, rows, words):
    f = tmp_path / "r.csv"
    f.write_text("time,acc\n" + rows)
    with pytest.raises(InputError, match=words.replace("[", r"\[")):
        GroundMotion.record(f)


@pytest.mark.parametrize("text, words", [
    ("time,acc\n0,0\n0.01,0.1\nNaN,NaN\n0.03,0\n", "line 4: times and accelerations must be finite"),
    ("time,acc\n0,0\nabc,def\n0.02,0\n", "line 3: a data line is 'time,acceleration'"),
    ("0,0\n0.01,0.1\ntime,acc\n", "line 3: a data line"),        # a header after the data
    ("time,acc\nunits,s\n0,0\n0.01,0\n", "line 2: a data line"),  # one header only
    ("0,0\n0.01,0.1,0.2\n", "line 2: a data line"),
    ("0,0\n 0.01 , 0.1 \n0.01,0\n", "line 3: times must be strictly increasing"),
])
def test_a_csv_line_that_is_not_data_is_named(tmp_path, text, words):
    f = tmp_path / "r.csv"
    f.write_text(text)
    with pytest.raises(InputError, match=words):
        GroundMotion.record(f)


def test_comments_blank_lines_and_one_header_are_not_data(tmp_path):
    f = tmp_path / "r.csv"
    f.write_text("# El Centro, scaled\n\ntime (s), acc (g)\n0,0\n# mid-file note\n0.01,-0.5\n\n0.02,0.25\n")
    g = GroundMotion.record(f)
    assert list(g.t) == [0.0, 0.01, 0.02] and list(g.a) == [0.0, -0.5, 0.25]
    assert g.pga == 0.5


def test_a_record_longer_than_the_cap_is_refused_after_counting(tmp_path):
    f = tmp_path / "long.csv"
    n = MAX_RECORD_SAMPLES + 1
    f.write_text("".join(f"{i * 1e-3:.3f},0\n" for i in range(n)))
    with pytest.raises(InputError, match=f"at most {MAX_RECORD_SAMPLES}"):
        GroundMotion.record(f)


def test_the_wavelet_period_is_range_checked(capsys):
    _one_line(capsys, ["rock", "--voussoirs", "7", "--pulse", "ricker", "--amplitude", "1", "--period", "1e300"],
              "[0.0001, 10000] s")
