"""``fembeam rock`` from the command line: JSON, CSV, bad input (exit 2, one line), no partial files."""
import csv
import json
import math

import pytest

from fembeam.cli.main import main

BLOCK = ["rock", "--block", "0.5", "2.0", "--pulse", "sine", "--amplitude", "0.5", "--period", "0.5", "--t-end", "3"]


def run(argv, capsys):
    code = main(argv)
    out = capsys.readouterr()
    return code, out.out, out.err


def test_json_is_one_strict_object(capsys):
    code, out, err = run(BLOCK + ["--json", "--history"], capsys)
    assert code == 0
    d = json.loads(out, parse_constant=lambda c: pytest.fail(f"non-JSON constant {c}"))
    assert d["outcome"] == "survived" and d["t_overturn"] is None and d["thrust_line_exits_at"] is None
    assert {"t", "r", "r_qp", "hinges_before", "hinges_after"} <= set(d["impacts"][0])
    alpha = math.atan(0.25)
    assert d["impacts"][0]["r"] == pytest.approx((1 - 1.5 * math.sin(alpha) ** 2) ** 2, rel=1e-12)
    assert d["A_L"]["+1"] == pytest.approx(0.25, rel=1e-9)
    assert len(d["history"]["t"]) == len(d["history"]["theta"]) > 1000
    json.dumps(d, allow_nan=False)


def test_overturning_block_in_the_summary(capsys):
    code, out, _ = run(["rock", "--block", "0.5", "2.0", "--pulse", "rect", "--amplitude", "0.6", "--duration", "1"],
                       capsys)
    assert code == 0 and "OVERTURNED at t =" in out and "centroid a tenth of the thickness below" in out


def test_csv_history(tmp_path, capsys):
    path = tmp_path / "h.csv"
    code, out, _ = run(BLOCK + ["--csv", str(path)], capsys)
    assert code == 0 and f"CSV: {path}" in out
    rows = list(csv.DictReader(path.open()))
    assert list(rows[0]) == ["t", "mechanism", "theta", "rate", "K", "V", "a_g"]
    assert float(rows[-1]["t"]) == pytest.approx(3.0, abs=1e-3)
    assert sorted(p.name for p in tmp_path.iterdir()) == ["h.csv"]      # no temporary left


@pytest.mark.parametrize("argv, words", [
    (["rock", "--pulse", "sine", "--amplitude", "0.5"], "--period"),
    (["rock", "--pulse", "rect", "--amplitude", "0.5"], "--duration"),
    (["rock", "--pulse", "rect", "--duration", "0.5"], "--amplitude"),
    (["rock", "--pulse", "rect", "--amplitude", "1", "--duration", "-1"], "positive"),
    (["rock", "--pulse", "sine", "--amplitude", "1", "--period", "0.5", "--scale", "2"], "--record"),
    (["rock", "--record", "no_such_file.AT2"], "no ground-motion file"),
    (["rock", "--record", "elcentro", "--amplitude", "1"], "--pulse"),
    (["rock", "--record", "elcentro", "--pga", "-1"], "positive"),
    (["rock", "--block", "0.5", "2", "--pulse", "sine", "--amplitude", "1", "--period", "0.5", "--t-end", "-3"],
     "--t-end"),
    (["rock", "--block", "0.5", "2", "--pulse", "sine", "--amplitude", "1", "--period", "0.5", "--dt-out", "0"],
     "--dt-out"),
    (["rock", "--block", "0", "2", "--pulse", "sine", "--amplitude", "1", "--period", "0.5"], "width"),
    (["rock", "--pulse", "sine", "--amplitude", "1", "--period", "0.5", "--csv", "/no/such/dir/h.csv"], "does not exist"),
    (["rock", "--pulse", "sine", "--amplitude", "1", "--period", "0.5", "--plot", "h.xyz"], "--plot"),
    (["rock", "--pulse", "sine", "--amplitude", "1", "--period", "0.5", "--vtk", "m.vtu"], ".pvd"),
    (["rock", "--pulse", "sine", "--amplitude", "1", "--period", "0.5", "--history"], "--json"),
    (["rock", "--pulse", "sine", "--amplitude", "1", "--period", "0.5", "--frames", "1"], "--frames"),
    (["rock", "--pulse", "sine", "--amplitude", "nan", "--period", "0.5"], "finite"),
    (["rock"], "required"),
    (["rock", "--pulse", "sine", "--amplitude", "1", "--period", "0.5", "--friction", "0"], "[0.001, 1000]"),
    (["rock", "--pulse", "sine", "--amplitude", "1", "--period", "0.5", "--friction", "-0.3"], "[0.001, 1000]"),
    (["rock", "--pulse", "sine", "--amplitude", "1", "--period", "0.5", "--friction", "nan"], "[0.001, 1000]"),
    (["rock", "--pulse", "sine", "--amplitude", "1", "--period", "0.5", "--friction", "1e9"], "[0.001, 1000]"),
    (["rock", "--pulse", "sine", "--amplitude", "1", "--period", "0.5", "--friction", "low"], "friction coefficient"),
    (["rock", "--pulse", "sine", "--amplitude", "1", "--period", "0.5", "--friction", "0.3", "--no-thrust-check"],
     "--no-thrust-check"),
])
def test_bad_input_exits_2_with_one_line(argv, words, capsys):
    with pytest.raises(SystemExit) as e:
        raise SystemExit(main(argv))
    err = capsys.readouterr().err
    assert e.value.code == 2
    assert len(err.strip().splitlines()) == 1 and words in err, err


def test_output_directory_is_rejected_before_computing(tmp_path, capsys):
    (tmp_path / "d.csv").mkdir()
    code, out, err = run(BLOCK + ["--csv", str(tmp_path / "d.csv")], capsys)
    assert code == 2 and "is a directory" in err and out == ""
