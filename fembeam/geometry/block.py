"""Straight member on a rigid base: Housner's rocking block."""
from __future__ import annotations

import dataclasses
from dataclasses import dataclass

import numpy as np

from .base import DEFAULT_DENSITY, THICKNESS_RANGE, MidCurve, density_value, length_value, thickness_value

__all__ = ["StraightMember", "MIN_WIDTH_OVER_HEIGHT"]

MIN_WIDTH_OVER_HEIGHT = 5e-4    # thinnest block a minimum-thickness search checks (as the arches' 1/2000 of the span)


@dataclass(frozen=True)
class StraightMember(MidCurve):
    """Vertical straight member standing on a rigid base: Housner's rocking block.

    The bottom end is a joint, the top end free. The mid-curve runs upwards from the
    base, so ``t = (0, 1)``, ``n = (1, 0)``: the "intrados" fibre is on the right face,
    the "extrados" on the left face.

    Parameters
    ----------
    height : float, optional
        Height (m).
    width : float, optional
        Width of the base, in the plane (m).
    density : float, optional
        Density (kg/m^3; masses are per metre of width out of the plane), default
        :data:`~fembeam.geometry.base.DEFAULT_DENSITY` (2000).

    Raises
    ------
    InputError
        A value out of its range.

    Examples
    --------
    A block 2 m high and 0.4 m wide starts to rock at ``A_L = width / height``:

    >>> import fembeam
    >>> block = fembeam.StraightMember(height=2.0, width=0.4)
    >>> lim = fembeam.limit_analysis(fembeam.discretize(block, [0.0, 2.0]))
    >>> print(lim.status, f"A_L = {lim.A_L:.4f} g")
    ok A_L = 0.2000 g
    """

    height: float = 1.0
    width: float = 0.2
    density: float = DEFAULT_DENSITY
    ends: tuple[str, str] = ("joint", "free")

    def __post_init__(self):
        object.__setattr__(self, "height", length_value("height", self.height))
        object.__setattr__(self, "width", thickness_value("width", self.width))
        object.__setattr__(self, "density", density_value(self.density))

    @property
    def length(self) -> float:
        return self.height

    def position(self, s):
        s = np.asarray(s, float)
        return np.array([np.zeros_like(s), s])

    def tangent(self, s):
        s = np.asarray(s, float)
        return np.array([np.zeros_like(s), np.ones_like(s)])

    def curvature(self, s):
        return np.zeros(np.shape(s))

    def thickness_at(self, s):
        return np.full(np.shape(s), self.width)

    @property
    def min_thickness_scale(self) -> float:
        """Smallest width factor checked: the width stays above ``MIN_WIDTH_OVER_HEIGHT`` of the
        height and inside ``THICKNESS_RANGE`` (a block on its base stands at any width)."""
        return max(MIN_WIDTH_OVER_HEIGHT * self.height, THICKNESS_RANGE[0]) / self.width

    def with_thickness_scaled(self, factor: float) -> "StraightMember":
        return dataclasses.replace(self, width=self.width * factor)

    def describe(self) -> dict:
        return {"shape": "block", "height": self.height, "width": self.width, "density": self.density}
