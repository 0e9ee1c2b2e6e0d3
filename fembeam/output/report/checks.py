"""The report's vocabulary: published references and tolerances, the :class:`Check`,
:class:`ReportSettings` and :class:`Report` dataclasses, and the small constructors
that turn a computed value into a PASS/FAIL/INFO :class:`Check`."""
from __future__ import annotations

from dataclasses import asdict, dataclass, field

import numpy as np

from ...analysis import THRESHOLDS


@dataclass(frozen=True)
class Reference:
    """A published value with the tolerance it is checked to (absolute) and its source."""

    value: float
    tol: float
    source: str


_PAPER_TOL = ("one unit of the last published digit (the paper rounds to three decimals and "
              "solves its own discretisation)")

# published values: the paper (impact of rocking masonry arches), Milankovitch, Housner
REFERENCES: dict[str, Reference] = {
    "oppenheim150.A_L": Reference(0.444, 1e-3, "paper Sect. 6.1: A_L = 0.444 g, beta = 150 deg"),
    "oppenheim150.r": Reference(0.532, 1e-3, "paper Sect. 6.1, Fig. 10: r_max = 0.532, beta = 150 deg"),
    "oppenheim157.A_L": Reference(0.370, 1e-3, "paper Sect. 6.1: A_L = 0.370 g, beta = 157.5 deg"),
    "oppenheim157.r_4hinge": Reference(0.557, 1e-3, "paper Sect. 6.1, Fig. 11b: r = 0.557 (four-hinge)"),
    "oppenheim157.r_max": Reference(0.560, 1e-3, "paper Sect. 6.1, Fig. 11c: r_max = 0.560 (five hinges)"),
    "continuous157.A_L": Reference(0.353, 1e-3, "paper Sect. 6.2: A_L = 0.353 g, beta = 157.5 deg, t/R = 0.15"),
    "continuous157.r": Reference(0.606, 1e-3, "paper Sect. 6.2, Fig. 12: r_max = 0.606"),
    "milankovitch.t_min": Reference(0.1075, 1e-4, "Milankovitch (1907): semicircle t_min/R = 0.1075"),
}

# tolerances of the checks against exact formulas and of the qualitative checks: (value, reason)
TOLERANCES: dict[str, tuple[float, str]] = {
    "kernel": (1e-12, "round-off: |B d| / max|d| of a rigid motion is a sum of O(10) products of O(1) numbers"),
    "sector": (1e-12, "relative; 12-point Gauss on each element integrates the sector exactly up to round-off"),
    "housner_r": (1e-8, "absolute; the QP is solved to 1e-10 (fembeam.impact), r is a ratio of two energies"),
    "housner_A_L": (1e-9, "relative; HiGHS LP tolerances"),
    "rate": (1.5, "fitted rate at least 1.5 where second order is expected (tests/test_limit.py)"),
    "mesh_independent": (1e-10, "relative spread of the hinge-refined A_L over the meshes (four-hinge optimum)"),
    "monotone": (1e-6, "r may move against the trend by at most this (the tests' relative accuracy of r)"),
}

SECTIONS = ("exact", "paper", "kkt", "convergence", "fig13")
SECTION_TITLES = {"exact": "1. Exact solutions", "paper": "2. Paper, Sect. 6", "kkt": "3. Appendix B: KKT checks",
                  "convergence": "4. Mesh convergence", "fig13": "5. Fig. 13 trends"}


@dataclass
class Check:
    """One line of the report: ``status`` is PASS, FAIL or INFO (reported, not judged)."""

    section: str
    name: str
    value: object
    expected: str
    status: str
    source: str
    diff: float | None = None
    detail: str = ""


@dataclass
class ReportSettings:
    """What each section computes; :meth:`quick` is the ~10 s variant."""

    quick: bool = False
    housner_tan_a: tuple = (0.05, 0.1, 0.2, 0.3, 0.45, 0.6, 0.8, 1.0, 1.2, 1.35, 1.41)
    stocky_tan_a: tuple = (1.5, 2.0, 3.0)
    tmin_elements: int = 400
    tmin_tol: float = 1e-6
    kkt_cases: tuple = (("continuous", 157.5, 0.15, 200), ("continuous", 157.5, 0.15, 1600),
                        ("continuous", 180.0, 0.12, 200), ("continuous", 120.0, 0.12, 200),
                        ("continuous", 140.0, 0.25, 200), ("continuous", 100.0, 0.20, 200),
                        ("voussoirs", 157.5, 0.15, 7), ("voussoirs", 150.0, 0.15, 15), ("block", 0.3, None, 1))
    elements: tuple = (50, 100, 200, 400, 800, 1600)
    voussoirs: tuple = (7, 15, 31, 63, 127, 255)
    reference_elements: int = 1600
    fig13_embrace: tuple = (80.0, 100.0, 120.0, 140.0, 160.0, 180.0)
    fig13_t_over_r: tuple = (0.02, 0.05, 0.08, 0.11, 0.14, 0.17, 0.20, 0.23)
    sweep_tmin_elements: int = 400
    workers: int | None = None

    @classmethod
    def make(cls, quick: bool = False, workers: int | None = None) -> "ReportSettings":
        if not quick:
            return cls(workers=workers)
        return cls(quick=True, tmin_elements=200, tmin_tol=1e-5,
                   kkt_cases=(("continuous", 157.5, 0.15, 200), ("continuous", 100.0, 0.20, 100),
                              ("voussoirs", 157.5, 0.15, 7), ("block", 0.3, None, 1)),
                   elements=(50, 100, 200, 400), voussoirs=(7, 15, 31, 63), reference_elements=400,
                   fig13_embrace=(100.0, 140.0, 180.0), fig13_t_over_r=(0.12, 0.18, 0.24),
                   sweep_tmin_elements=200, workers=workers)


@dataclass
class Report:
    settings: ReportSettings
    checks: list[Check] = field(default_factory=list)
    data: dict = field(default_factory=dict)
    images: dict = field(default_factory=dict)
    timings: dict = field(default_factory=dict)

    @property
    def failures(self) -> list[Check]:
        return [c for c in self.checks if c.status == "FAIL"]

    @property
    def passed(self) -> bool:
        return not self.failures

    def to_dict(self) -> dict:
        from ... import __version__
        return {"report": "verification", "fembeam_version": __version__,
                "mode": "quick" if self.settings.quick else "full", "all_pass": self.passed,
                "counts": {s: sum(c.status == s for c in self.checks) for s in ("PASS", "FAIL", "INFO")},
                "failures": [c.name for c in self.failures],
                "references": {k: asdict(v) for k, v in REFERENCES.items()},
                "tolerances": {k: {"value": v, "reason": r} for k, (v, r) in TOLERANCES.items()},
                "thresholds": THRESHOLDS, "settings": _jsonable(asdict(self.settings)),
                "checks": [_jsonable(asdict(c)) for c in self.checks], "sections": _jsonable(self.data),
                "images": self.images, "timings_s": {k: round(v, 2) for k, v in self.timings.items()}}


# ---------------------------------------------------------------------------- checks
def _against(section: str, name: str, value: float, key: str, detail: str = "") -> Check:
    ref = REFERENCES[key]
    ok = value is not None and np.isfinite(value) and abs(value - ref.value) <= ref.tol
    return Check(section, name, value, f"{ref.value:g} ± {ref.tol:g}", "PASS" if ok else "FAIL", ref.source,
                 None if value is None else float(value - ref.value), detail)


def _close(section: str, name: str, value: float, exact: float, tol_key: str, rel: bool = False,
           source: str = "", detail: str = "") -> Check:
    tol = TOLERANCES[tol_key][0]
    diff = float(value - exact)
    err = abs(diff) / (abs(exact) if rel and exact != 0 else 1.0)
    return Check(section, name, float(value), f"{exact:.10g} ({'rel.' if rel else 'abs.'} tol {tol:g})",
                 "PASS" if err <= tol else "FAIL", source or TOLERANCES[tol_key][1], diff, detail)


def _at_most(section: str, name: str, value: float, limit: float, source: str, detail: str = "") -> Check:
    ok = value is not None and value <= limit
    return Check(section, name, value, f"<= {limit:g}", "PASS" if ok else "FAIL", source, None, detail)


def _at_least(section: str, name: str, value: float, limit: float, source: str, detail: str = "") -> Check:
    ok = value is not None and np.isfinite(value) and value >= limit
    return Check(section, name, value, f">= {limit:g}", "PASS" if ok else "FAIL", source, None, detail)


def _holds(section: str, name: str, ok: bool, value, expected: str, source: str, detail: str = "") -> Check:
    return Check(section, name, value, expected, "PASS" if ok else "FAIL", source, None, detail)


def _info(section: str, name: str, value, source: str, detail: str = "") -> Check:
    return Check(section, name, value, "-", "INFO", source, None, detail)


def _jsonable(x):
    if isinstance(x, dict):  # keys starting with "_" hold live objects for the plots
        return {str(k): _jsonable(v) for k, v in x.items() if not str(k).startswith("_")}
    if isinstance(x, (list, tuple)):
        return [_jsonable(v) for v in x]
    if isinstance(x, (bool, np.bool_)):
        return bool(x)
    if isinstance(x, (int, np.integer)):
        return int(x)
    if isinstance(x, (float, np.floating)):
        return float(x) if np.isfinite(x) else None
    if isinstance(x, np.ndarray):
        return _jsonable(x.tolist())
    return x
