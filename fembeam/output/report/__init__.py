"""Verification report: fembeam against exact solutions and the paper, every number computed.

:func:`build_report` runs five sections and returns a :class:`Report` of checks (each
with the computed value, the reference, its tolerance and where the reference comes
from) plus the raw numbers of every section; :func:`write_report` writes
``verification_report.md``, ``verification_report.json`` and the PNGs.

1. ``exact``: rigid motions in the kernel of the strain operators, annular-sector
   inertia, Housner's block r = (1 - 1.5 sin^2 a)^2 over slenderness, Milankovitch;
2. ``paper``: Sect. 6.1 (Oppenheim's 7-voussoir arch, 150 and 157.5 deg: A_L, QP r_max,
   best four-hinge r, classical model) and Sect. 6.2 (continuous arch, 157.5 deg);
3. ``kkt``: the Appendix B optimality figures of the LP and the QP on several geometries
   against :data:`fembeam.analysis.THRESHOLDS`;
4. ``convergence``: r and A_L_mesh against N with fitted rates
   (:mod:`fembeam.studies.convergence`), voussoir arches against the continuous arch;
5. ``fig13``: a small Fig. 13 grid (:mod:`fembeam.studies.sweep`): r falls with t/R, rises with
   beta, and the minimum-thickness envelope stays below 1.

The only numbers typed in are the published references and the tolerances in
:data:`REFERENCES` and :data:`TOLERANCES`, each with its source or reason.

Modules: :mod:`.checks` (references, tolerances, the dataclasses, the check
constructors), :mod:`.sections` (the five sections and :func:`build_report`),
:mod:`.output` (formatting, plots, markdown, :func:`write_report`).
"""
from . import output
from .checks import REFERENCES, SECTION_TITLES, SECTIONS, TOLERANCES, Check, Reference, Report, ReportSettings
from .output import write_report
from .sections import build_report

__all__ = ["Reference", "Check", "Report", "REFERENCES", "TOLERANCES", "SECTIONS", "SECTION_TITLES",
           "ReportSettings", "build_report", "write_report"]

_fmt = output._fmt  # the number format of the stdout table (fembeam.cli.report)
