"""``fembeam report``: the verification report (exact solutions, paper, KKT, convergence, Fig. 13)."""
from __future__ import annotations

import argparse
import os

from ..errors import InputError
from ..output.files import check_dir
from ..output.report import SECTIONS, ReportSettings, build_report, write_report


REPORT_FILES = ("verification_report.md", "verification_report.json", "housner.png", "paper.png", "convergence.png",
                "convergence_voussoirs.png", "fig13.png")


def _sections(text: str) -> list[str]:
    names = [s.strip() for s in text.split(",") if s.strip()]
    bad = [s for s in names if s not in SECTIONS]
    if bad or not names:
        raise argparse.ArgumentTypeError(f"sections are {','.join(SECTIONS)}, got {text!r}")
    return names


def register(sub) -> None:
    p = sub.add_parser("report", help="verification report: tables and plots against exact solutions and the paper",
                       description="Computes every check (exact solutions, paper Sect. 6, Appendix B KKT figures, "
                                   "mesh convergence, Fig. 13 trends) and writes DIR/verification_report.md, "
                                   "DIR/verification_report.json and PNGs. Progress on stderr; exit code 1 if any "
                                   "check fails.")
    p.add_argument("--out-dir", required=True, metavar="DIR", help="directory for the report (created if needed)")
    p.add_argument("--quick", action="store_true", help="coarser meshes and a smaller Fig. 13 grid (~10 s)")
    p.add_argument("--only", type=_sections, default=list(SECTIONS), metavar="S,S,..",
                   help=f"run only these sections ({','.join(SECTIONS)}; default all)")
    p.add_argument("--workers", type=int, default=None, metavar="N",
                   help="local processes for the Fig. 13 grid (default: the available cores)")
    p.add_argument("--quiet", action="store_true", help="no progress lines on stderr")
    p.set_defaults(func=run)


def run(args: argparse.Namespace) -> int:
    check_dir(args.out_dir, "--out-dir")
    for name in REPORT_FILES:            # a directory in the way fails now, not after the report
        if os.path.isdir(os.path.join(args.out_dir, name)):
            raise InputError(f"--out-dir: {os.path.join(args.out_dir, name)!r} is a directory")
    if args.workers is not None and args.workers < 1:
        raise InputError(f"--workers must be >= 1, got {args.workers}")
    settings = ReportSettings.make(quick=args.quick, workers=args.workers)
    rep = build_report(settings, only=args.only, progress=not args.quiet)
    cmd = "fembeam report --out-dir " + args.out_dir + (" --quick" if args.quick else "") + \
          ("" if list(args.only) == list(SECTIONS) else " --only " + ",".join(args.only))
    path = write_report(rep, args.out_dir, command=cmd)
    print(summary(rep))
    print(path)
    return 0 if rep.passed else 1


def _short(x) -> str:
    from ..output.report import _fmt
    return _fmt(x)


def summary(rep) -> str:
    """The PASS/FAIL table printed on stdout, then the failures."""
    w = max(len(c.name) for c in rep.checks)
    lines = [f"{'section':11s} {'check':{w}s} {'fembeam':>12s}  {'reference':24s} status"]
    for c in rep.checks:
        lines.append(f"{c.section:11s} {c.name:{w}s} {_short(c.value):>12s}  {c.expected:24s} {c.status}")
    n = {s: sum(c.status == s for c in rep.checks) for s in ("PASS", "FAIL", "INFO")}
    lines.append(f"{n['PASS']} PASS, {n['FAIL']} FAIL, {n['INFO']} INFO in {rep.timings['total']:.1f} s")
    for c in rep.failures:
        lines.append(f"FAIL: {c.section}: {c.name}: {_short(c.value)} (expected {c.expected}; {c.source})")
    return "\n".join(lines)
