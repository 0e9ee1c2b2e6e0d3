"""docs/compare_rock_simulate.py: the quick row of the rock / simulate comparison, and the drift
check of the committed docs/data/comparison_spectra.csv against what the script computes."""
import csv
import importlib.util
import math
from pathlib import Path

import pytest

DOCS = Path(__file__).resolve().parents[1] / "docs"
SPECTRA = DOCS / "data" / "comparison_spectra.csv"


def _script():
    spec = importlib.util.spec_from_file_location("compare_rock_simulate", DOCS / "compare_rock_simulate.py")
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    return mod


@pytest.fixture(scope="module")
def script():
    return _script()


@pytest.fixture(scope="module")
def quick_row(script):
    return script.quick()


def test_quick_both_models_finite_and_close(script, quick_row):
    r = quick_row
    assert math.isfinite(r["rock_A_g"]) and r["rock_A_g"] > 0
    assert math.isfinite(r["sim_A_g"]) and r["sim_A_g"] > 0
    assert 0.5 < r["sim_A_g"] / r["rock_A_g"] < 2.0
    assert r["errors"] == 0
    # the brackets are real brackets: lo safe, hi collapsing, lo < hi; no collapse on the scan below
    assert r["lo_0.25ms_g"] < r["hi_0.25ms_g"] == r["sim_A_g"]
    mu = f"{script.FRICTIONS[0]:g}"
    assert r[f"lo_mu{mu}_g"] < r[f"hi_mu{mu}_g"]
    assert r[f"collapse_mu{mu}"] in script.COLLAPSE
    assert math.isnan(r["scan_first_g"])


def test_committed_csv_matches_script(script, quick_row):
    with open(SPECTRA) as f:
        assert next(csv.reader(f)) == script.FIELDS, "the committed CSV's columns are not the script's"
    rows = script.read_csv(SPECTRA)
    row = [x for x in rows if x["arch"] == "paper" and x["kind"] == "rect" and abs(x["period_s"] - 0.4) < 1e-9]
    assert row, "the committed CSV has no row for the paper's arch, rect 0.4 s"
    row, q = row[0], quick_row
    # rock: same search, same tolerance
    assert row["rock_A_g"] == pytest.approx(q["rock_A_g"], rel=2 * script.ROCK_TOL)
    # simulate, no sliding and with friction at the same dt: the committed (fine) bracket lies in the
    # quick (coarse) one, whose bisection starts from the same bracket
    mu = f"{script.FRICTIONS[0]:g}"
    for lo, hi in (("lo_0.25ms_g", "hi_0.25ms_g"), (f"lo_mu{mu}_g", f"hi_mu{mu}_g")):
        assert q[lo] * (1 - 1e-3) <= row[lo] < row[hi] <= q[hi] * (1 + 1e-3), (lo, hi)
    assert row["sim_A_g"] == row["hi_0.25ms_g"]
    assert row["ratio"] == pytest.approx(row["sim_A_g"] / row["rock_A_g"], rel=1e-12)
    assert row[f"collapse_mu{mu}"] == q[f"collapse_mu{mu}"]
