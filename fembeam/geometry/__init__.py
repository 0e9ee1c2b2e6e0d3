"""Member geometry: mid-curves as functions of the arc length (position, tangent,
curvature, thickness) and the exact inertia of the region between normal cuts."""
from .asbuilt import Fill, as_built
from .base import MidCurve
from .block import StraightMember
from .catenary import CatenaryArch
from .circular import CircularArch
from .elliptical import EllipticalArch
from .parabolic import ParabolicArch
from .pointed import PointedArch
from .surveyed import SurveyedArch
from .symmetry import is_symmetric

__all__ = ["Fill", "as_built", "MidCurve", "CircularArch", "StraightMember", "PointedArch", "EllipticalArch", "ParabolicArch",
           "CatenaryArch", "SurveyedArch", "is_symmetric"]
