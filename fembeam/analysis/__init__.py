"""Analyses on a discretisation: limit analysis (static LP with certificates), impact
(sparse QP whose multipliers are the impulses), their verification, and the pipeline
``analyze`` that runs them with every check."""
from .impact import ImpactResult, impact
from .limit import LimitResult, limit_analysis
from .continuum import ContinuumLimit, continuum_limit
from .pipeline import AnalysisResult, analyze
from .sizes import DEFAULT_ELEMENTS, MAX_ELEMENTS
from .thickness import MinimumThickness, minimum_thickness
from .qp import BACKENDS, QPSolution, solve_qp
from .verification import THRESHOLDS, check

__all__ = ["ImpactResult", "impact", "LimitResult", "limit_analysis", "DEFAULT_ELEMENTS", "MAX_ELEMENTS", "AnalysisResult", "ContinuumLimit", "continuum_limit", "MinimumThickness",
           "analyze", "minimum_thickness", "BACKENDS", "QPSolution", "solve_qp", "THRESHOLDS", "check"]
