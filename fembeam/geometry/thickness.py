"""Thickness laws of an arch: constant, or linear in the arc length from each springing
to the crown (symmetric haunching).

A law gives the thickness ``t(s)`` (m, measured along the normal of the mid-curve, half
of it on each side) of the section at arc length ``s`` (m, from the left springing) of a
member of length ``length`` whose crown is at ``crown_s``.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..errors import InputError
from .base import thickness_value

__all__ = ["ThicknessLaw", "thickness_law"]


@dataclass(frozen=True)
class ThicknessLaw:
    """``t(s) = springing + (crown - springing) * d(s)``, with ``d`` growing linearly in the
    arc length from 0 at each springing to 1 at the crown (m); ``springing == crown`` is the
    constant law."""

    springing: float
    crown: float

    @property
    def constant(self) -> bool:
        return self.springing == self.crown

    @property
    def maximum(self) -> float:
        return max(self.springing, self.crown)

    def at(self, s, length: float, crown_s: float) -> np.ndarray:
        """Thickness (m) at the arc lengths ``s`` (m)."""
        s = np.asarray(s, float)
        if self.constant:
            return np.full(s.shape, self.springing)
        d = np.where(s <= crown_s, s / crown_s, (length - s) / (length - crown_s))
        return self.springing + (self.crown - self.springing) * np.clip(d, 0.0, 1.0)

    def breaks(self, crown_s: float) -> tuple[float, ...]:
        """Where the law is not smooth: the crown, unless the law is constant."""
        return () if self.constant else (float(crown_s),)

    def scaled(self, factor: float) -> "ThicknessLaw":
        return ThicknessLaw(self.springing * factor, self.crown * factor)

    def describe(self) -> dict:
        if self.constant:
            return {"thickness": self.springing}
        return {"thickness_springing": self.springing, "thickness_crown": self.crown}


def thickness_law(thickness=None, thickness_springing=None, thickness_crown=None) -> ThicknessLaw:
    """The law of the constructor arguments of the arch shapes: ``thickness`` (m, constant)
    or both ``thickness_springing`` and ``thickness_crown`` (m); InputError otherwise."""
    linear = (thickness_springing, thickness_crown)
    if thickness is not None:
        if any(x is not None for x in linear):
            raise InputError("give either a constant thickness or thickness_springing and thickness_crown, not both")
        t = thickness_value("thickness", thickness)
        return ThicknessLaw(t, t)
    if any(x is None for x in linear):
        raise InputError("give a thickness (constant) or both thickness_springing and thickness_crown "
                         "(linear in the arc length from each springing to the crown)")
    return ThicknessLaw(thickness_value("thickness_springing", thickness_springing),
                        thickness_value("thickness_crown", thickness_crown))
