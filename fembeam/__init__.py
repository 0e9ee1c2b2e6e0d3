"""fembeam: curved-beam finite elements for the impact of rocking masonry arches.

Pipeline: a :class:`MidCurve` (``CircularArch``, ``PointedArch``, ``EllipticalArch``,
``ParabolicArch``, ``CatenaryArch``, ``SurveyedArch``) -> :func:`discretize` (rigid
elements on a scikit-fem mesh) -> :func:`limit_analysis` (A_L, mechanism) ->
:func:`impact` (r, impulses); :func:`analyze` runs it all with its checks.
"""
from .analysis import AnalysisResult, analyze, minimum_thickness
from .errors import CannotStandError, FembeamError, InputError, SolverError
from .fem import Discretization, discretize, nodes_through, uniform_nodes
from .mechanisms import Hinge, Mechanism
from .geometry import (CatenaryArch, CircularArch, EllipticalArch, MidCurve, ParabolicArch, PointedArch,
                       StraightMember, SurveyedArch)
from .analysis import ImpactResult, impact
from .analysis import LimitResult, limit_analysis

__all__ = ["AnalysisResult", "analyze", "minimum_thickness", "CannotStandError", "FembeamError",
           "InputError", "SolverError", "Discretization", "discretize", "nodes_through", "uniform_nodes",
           "Hinge", "Mechanism", "CircularArch", "MidCurve", "StraightMember", "PointedArch", "EllipticalArch",
           "ParabolicArch", "CatenaryArch", "SurveyedArch", "ImpactResult", "impact",
           "LimitResult", "limit_analysis"]
__version__ = "0.1.0"
