"""The whole motion on arches of other shapes: rock, spectrum and the motion's files run on a
pointed and a parabolic arch with the same checks as on the circle."""
from __future__ import annotations

import json

import pytest

from fembeam import analyze
from fembeam.cli.main import main
from fembeam.geometry import ParabolicArch, PointedArch

POINTED = ["--shape", "pointed", "--span", "10", "--rise", "7", "--thickness", "0.8"]
PARABOLIC = ["--shape", "parabolic", "--span", "10", "--rise", "3", "--thickness", "0.6"]


def _strict(text: str) -> dict:
    return json.loads(text, parse_constant=lambda c: (_ for _ in ()).throw(ValueError(c)))


@pytest.mark.parametrize("arch, member, argv", [
    (PointedArch(span=10, rise=7, thickness=0.8), {"voussoirs": 10}, POINTED + ["--voussoirs", "10"]),
    (ParabolicArch(span=10, rise=3, thickness=0.6), {"elements": 60}, PARABOLIC + ["--elements", "60"]),
])
def test_rock_on_other_shapes(tmp_path, capsys, arch, member, argv):
    """Onset at analyze's A_L in both directions (equal: the arch and its mesh are symmetric),
    energy balanced to 1e-8, strict JSON, and the motion's files written."""
    pvd, csv = tmp_path / "m.pvd", tmp_path / "m.csv"
    # to 1.5 s: the onset, the largest rotation and the first impact (to rest the continuous
    # parabola meets 30 impacts and new transitions, seven times as long)
    code = main(["rock", *argv, "--pulse", "sine", "--amplitude", "0.9", "--period", "0.8", "--t-end", "1.5",
                 "--json", "--vtk", str(pvd), "--csv", str(csv)])
    d = _strict(capsys.readouterr().out)
    assert code == 0 and d["outcome"] in ("rest", "overturned", "survived")
    ref = analyze(arch, **member)
    assert d["A_L"]["+1"] == pytest.approx(ref.A_L, rel=1e-9)
    assert d["A_L"]["-1"] == pytest.approx(ref.A_L, rel=1e-9)
    assert d["energy_balance_error"] < 1e-8 and d["peak_rotation"] > 0
    assert pvd.stat().st_size > 0 and csv.read_text().count("\n") > 10


def test_spectrum_on_a_pointed_arch(capsys):
    code = main(["spectrum", *POINTED, "--voussoirs", "10", "--pulse", "sine", "--periods", "0.5,1",
                 "--workers", "1", "--quiet", "--json"])
    d = _strict(capsys.readouterr().out)
    assert code == 0 and len(d["rows"]) == 2
    for row in d["rows"]:      # a first overturning amplitude above the onset, bracketed
        lo, hi = row["bracket"]
        assert row["first_overturning"] is None or lo <= row["first_overturning"] <= hi
