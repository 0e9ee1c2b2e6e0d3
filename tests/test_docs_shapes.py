"""docs/shapes.md against fresh runs: its transcripts are the committed tables, and the
cheapest rows of every table (and the minimum thicknesses) are recomputed."""
from __future__ import annotations

import csv
import pathlib
import re

import pytest

from fembeam import analyze, minimum_thickness
from fembeam.geometry import EllipticalArch, ParabolicArch, PointedArch

from doc_transcripts import unfold

ROOT = pathlib.Path(__file__).resolve().parents[1]
DATA = ROOT / "docs" / "data"
REL = 1e-9
ARCHES = {"pointed": PointedArch(span=10.0, rise=7.0, thickness=0.8),
          "elliptical": EllipticalArch(span=10.0, rise=3.0, thickness=0.8),
          "parabolic": ParabolicArch(span=10.0, rise=3.0, thickness=0.6)}


def rows(name: str) -> dict[int, dict]:
    with open(DATA / f"{name}.csv") as f:
        return {int(r["n"]): r for r in csv.DictReader(f)}


def test_transcripts_in_the_markdown_are_the_committed_tables():
    md = (ROOT / "docs" / "shapes.md").read_text()
    blocks = [unfold(b) for b in re.findall(r"```text\n(.*?)```", md, re.S)]
    for shape in ARCHES:
        for name in (f"shapes_{shape}", f"shapes_{shape}_voussoirs"):
            assert (DATA / f"{name}.txt").read_text() in blocks, name
    for name in ("shapes_pointed_min_thickness", "shapes_elliptical_min_thickness",
                 "shapes_parabolic_min_thickness"):
        assert (DATA / f"{name}.txt").read_text() in blocks, name
    for shape in ARCHES:
        assert (ROOT / "docs" / "img" / f"shape_{shape}.png").stat().st_size > 10_000
        assert f"img/shape_{shape}.png" in md and f"img/shapes_convergence_{shape}.png" in md


@pytest.mark.parametrize("shape", list(ARCHES))
def test_coarsest_rows_are_fresh(shape):
    arch = ARCHES[shape]
    cont, vous = rows(f"shapes_{shape}")[25], rows(f"shapes_{shape}_voussoirs")[8]
    for row, kw in ((cont, {"elements": 25}), (vous, {"voussoirs": 8})):
        res = analyze(arch, **kw)
        assert res.outcome == row["outcome"]
        for key, value in (("A_L", res.A_L), ("A_L_mesh", res.A_L_mesh), ("r", res.r)):
            assert float(row[key]) == pytest.approx(value, rel=REL), (shape, kw, key)
        th = minimum_thickness(arch, tol=1e-10, **kw)
        assert float(row["t_min_factor"]) == pytest.approx(th.scale, rel=1e-9)
        assert ";".join(f"{h.angle_deg:.6f}" for h in res.hinges_before) == row["hinges_before_deg"]


@pytest.mark.parametrize("shape", list(ARCHES))
def test_transcript_prints_the_csv(shape):
    """Each table's rows print the CSV's numbers; the minimum-thickness transcript the same
    factor as the study (the continuum's t_min is mesh-independent)."""
    table = rows(f"shapes_{shape}")
    lines = (DATA / f"shapes_{shape}.txt").read_text().splitlines()
    printed = {int(p[0]): p for p in (ln.split() for ln in lines) if len(p) > 8 and p[0].isdigit() and p[1] != "before:"}
    assert sorted(printed) == sorted(table)
    for n, r in table.items():
        p = printed[n]
        for col, key in ((2, "A_L"), (3, "A_L_mesh"), (4, "r"), (5, "t_min_factor")):
            assert abs(float(p[col]) - float(r[key])) <= 0.51 * 10.0 ** -len(p[col].split(".")[1]), (shape, n, key)
    mt = (DATA / f"shapes_{shape}_min_thickness.txt").read_text()
    factor = float(re.search(r"minimum thickness: (\S+) x", mt).group(1))
    assert factor == pytest.approx(float(table[800]["t_min_factor"]), abs=1e-6)
