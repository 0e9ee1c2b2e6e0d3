"""Member geometry: mid-curves as functions of the arc length (position, tangent,
curvature, thickness) and the exact inertia of the region between normal cuts."""
from .base import MidCurve
from .block import StraightMember
from .circular import CircularArch

__all__ = ["MidCurve", "CircularArch", "StraightMember"]
