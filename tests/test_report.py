"""``fembeam report``: the generated verification report (quick variant)."""
import dataclasses
import json

import pytest

from fembeam.output import report
from fembeam.cli import main


@pytest.fixture(scope="module")
def quick(tmp_path_factory):
    out = tmp_path_factory.mktemp("report")
    code = main(["report", "--quick", "--quiet", "--out-dir", str(out)])
    return code, out


def test_quick_report_all_pass(quick):
    code, out = quick
    assert code == 0
    data = json.loads((out / "verification_report.json").read_text())
    assert data["all_pass"] and data["counts"]["FAIL"] == 0 and not data["failures"]
    statuses = {c["status"] for c in data["checks"]}
    assert statuses <= {"PASS", "INFO"} and data["counts"]["PASS"] >= 35
    assert set(data["sections"]) == set(report.SECTIONS)
    # every published reference is used by at least one check, with its own value and tolerance
    used = {c["expected"] for c in data["checks"]}
    for ref in report.REFERENCES.values():
        assert f"{ref.value:g} ± {ref.tol:g}" in used
    # the numbers are computed: the paper's continuous arch as analyze() gives it
    paper = data["sections"]["paper"]["continuous_157.5"]
    assert abs(paper["A_L"] - 0.353) < 1e-3 and abs(paper["r_max"] - 0.606) < 1e-3
    md = (out / "verification_report.md").read_text()
    assert "0 FAIL" in md and "**FAIL**" not in md
    for title in report.SECTION_TITLES.values():
        assert f"## {title}" in md
    for name in data["images"].values():
        png = out / name
        assert png.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n" and 3_000 < png.stat().st_size < 200_000
        assert f"]({name})" in md


def test_wrong_reference_fails(tmp_path, monkeypatch, capsys):
    """A deliberately wrong published value: FAIL in the table, the JSON, and exit code 1."""
    ref = report.REFERENCES["oppenheim150.A_L"]
    monkeypatch.setitem(report.REFERENCES, "oppenheim150.A_L", dataclasses.replace(ref, value=0.5))
    code = main(["report", "--quick", "--quiet", "--only", "paper", "--out-dir", str(tmp_path)])
    assert code == 1
    out = capsys.readouterr().out
    assert "FAIL: paper: Oppenheim 150: A_L: 0.444208 (expected 0.5 ± 0.001" in out
    data = json.loads((tmp_path / "verification_report.json").read_text())
    assert not data["all_pass"] and data["failures"] == ["Oppenheim 150: A_L"]
    assert "**FAIL**" in (tmp_path / "verification_report.md").read_text()


def test_bad_section_is_an_input_error(tmp_path, capsys):
    with pytest.raises(SystemExit) as e:
        main(["report", "--only", "nonsense", "--out-dir", str(tmp_path)])
    assert e.value.code == 2
