"""Committed figures stay true: a cheap subset of the commands behind docs/ is re-run and
compared with what is committed (docs/regenerate.sh rewrites all of it)."""
import csv
import json
import pathlib
import re

import pytest

from fembeam import CircularArch, analyze
from fembeam.studies import sweep_case

DOCS = pathlib.Path(__file__).resolve().parents[1] / "docs"


def csv_rows(name):
    with open(DOCS / "data" / name) as f:
        return list(csv.DictReader(f))


@pytest.mark.parametrize("n", [50, 200])
def test_convergence_csv_and_table(n):
    res = analyze(CircularArch.from_ratio(157.5, 0.15), elements=n)
    row = next(r for r in csv_rows("convergence_157.5_0.15.csv") if int(r["n"]) == n)
    for key, fresh in (("A_L", res.A_L), ("A_L_mesh", res.A_L_mesh), ("r", res.r)):
        assert float(row[key]) == pytest.approx(fresh, rel=1e-9), key
    # the table printed in docs/studies.md: N ... A_L A_L_mesh r
    line = re.search(rf"^\s+{n}\s+\S+\s+\S+\s+(\S+)\s+(\S+)\s+(\S+)\s", (DOCS / "studies.md").read_text(), re.M)
    assert line, f"no row {n} in docs/studies.md"
    assert line.groups() == (f"{res.A_L:.8f}", f"{res.A_L_mesh:.8f}", f"{res.r:.7f}")


def test_voussoir_convergence_csv():
    row = next(r for r in csv_rows("convergence_voussoirs_157.5_0.15.csv") if int(r["n"]) == 7)
    res = analyze(CircularArch.from_ratio(157.5, 0.15), voussoirs=7)
    assert (float(row["A_L"]), float(row["r"])) == pytest.approx((res.A_L, res.r), rel=1e-9)


@pytest.mark.parametrize("beta, tr", [(180.0, 0.20), (120.0, 0.15), (80.0, 0.10), (180.0, 0.10)])
def test_sweep_csv(beta, tr):
    row = next(r for r in csv_rows("sweep_fig13.csv")
               if r["kind"] == "case" and float(r["embrace_deg"]) == beta and abs(float(r["t_over_R"]) - tr) < 1e-12)
    fresh = sweep_case(beta, tr)
    assert row["outcome"] == fresh["outcome"]
    for key, rel in (("A_L", 1e-9), ("r", 1e-9), ("t_min_over_R", 2e-6)):   # t_min: bisection to 1e-6
        if fresh.get(key) is None:
            assert row[key] == "", key
        else:
            assert float(row[key]) == pytest.approx(fresh[key], rel=rel), key


def test_report_json_paper_values():
    rep = json.loads((DOCS / "report" / "verification_report.json").read_text())
    numbers = []

    def walk(x):
        if isinstance(x, dict):
            for v in x.values():
                walk(v)
        elif isinstance(x, list):
            for v in x:
                walk(v)
        elif isinstance(x, float):
            numbers.append(x)

    walk(rep)
    res = analyze(CircularArch.from_ratio(157.5, 0.15))
    # the report's continuous paper case (200 elements): A_L and r as a fresh run gives them
    assert min(abs(v - res.r) for v in numbers) < 1e-9 * res.r
    assert min(abs(v - res.A_L) for v in numbers) < 1e-9 * res.A_L
