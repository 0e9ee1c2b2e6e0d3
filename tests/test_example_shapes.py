"""examples/ex06_shapes.py runs and prints what independent values say it should."""
import re

import pytest

from fembeam import CircularArch, analyze
from test_examples import run_script


def test_ex06_shapes(tmp_path, monkeypatch, capsys):
    out = run_script("ex06_shapes", tmp_path, monkeypatch, capsys)
    rows = re.findall(r"rise\s+(\S+) m: A_L = (\S+) g, r = (\S+), t_min = (\S+) m", out)
    assert [float(h) for h, *_ in rows] == [5.0, 6.0, 7.0, 8.66]
    # rise = span/2 is the semicircle of radius 5 m, t/R = 0.16: its A_L and r, and
    # Milankovitch's t_min/R = 0.107478
    semi = analyze(CircularArch.from_ratio(180.0, 0.16, radius=5.0), elements=60)
    assert float(rows[0][1]) == pytest.approx(semi.A_L, abs=5e-5) and float(rows[0][2]) == pytest.approx(semi.r, abs=5e-5)
    assert float(rows[0][3]) == pytest.approx(0.107478 * 5.0, abs=5e-5)
    # the equilateral arch: t_min = 0.3997609 m (independent radial-section thrust line, tests/test_shapes.py)
    assert float(rows[3][3]) == pytest.approx(0.3997609, abs=5e-5)
    survey = re.findall(r"(ideal parabola|surveyed \(5 cm sag\)): A_L = (\S+) g, r = (\S+), t_min = (\S+) m", out)
    assert [s[0] for s in survey] == ["ideal parabola", "surveyed (5 cm sag)"]
    assert float(survey[0][1]) == pytest.approx(0.609750, abs=5e-5)        # docs/shapes.md, any mesh
    assert float(survey[0][3]) == pytest.approx(0.0536, abs=5e-5)
    assert float(survey[1][3]) < float(survey[0][3])                       # the sag changes the answer
