"""fembeam: curved-beam finite elements for the impact of rocking masonry arches.

Pipeline: a :class:`MidCurve` (``CircularArch``, ``PointedArch``, ``EllipticalArch``,
``ParabolicArch``, ``CatenaryArch``, ``SurveyedArch``) -> :func:`discretize` (rigid
elements on a scikit-fem mesh) -> :func:`limit_analysis` (A_L, mechanism) ->
:func:`impact` (r, impulses); :func:`analyze` runs it all with its checks.
"""
import importlib

# public name -> module: imported on first use, so that ``fembeam --help`` or a script using
# one part does not pay for the others (PEP 562)
_WHERE = {
    **dict.fromkeys(["AnalysisResult", "analyze", "minimum_thickness", "ImpactResult", "impact", "LimitResult",
                     "limit_analysis"], ".analysis"),
    **dict.fromkeys(["CannotStandError", "FembeamError", "InputError", "SolverError"], ".errors"),
    **dict.fromkeys(["Discretization", "discretize", "nodes_through", "uniform_nodes"], ".fem"),
    **dict.fromkeys(["Hinge", "Mechanism"], ".mechanisms"),
    **dict.fromkeys(["CatenaryArch", "CircularArch", "EllipticalArch", "MidCurve", "ParabolicArch", "PointedArch",
                     "StraightMember", "SurveyedArch"], ".geometry"),
}
__all__ = sorted(_WHERE)


def __getattr__(name: str):
    if name in _WHERE:
        value = getattr(importlib.import_module(_WHERE[name], __name__), name)
        globals()[name] = value
        return value
    raise AttributeError(f"module 'fembeam' has no attribute {name!r}")


def __dir__():
    return sorted(set(globals()) | set(_WHERE))


__version__ = "0.1.0"
