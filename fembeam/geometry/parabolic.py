"""Parabolic arch: ``y = rise (1 - (2x/span)^2)``, the funicular of a load uniform
along the span."""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .graph import GraphArch

__all__ = ["ParabolicArch"]


@dataclass(frozen=True)
class ParabolicArch(GraphArch):
    """Parabolic arch: ``y = H (1 - (2x/L)^2)`` for ``x`` in ``[-L/2, L/2]``.

    ``L = span``, ``H = rise`` (m), parametrised by ``x``; the springing tangents have
    slope ``-+4H/L``. Arc length computed numerically (closed form ``L/2 sqrt(1 + q^2) +
    L/(2q) asinh q`` with ``q = 4H/L``, used by the tests).

    Parameters
    ----------
    span : float
        Distance between the springings (m), in
        :data:`~fembeam.geometry.base.LENGTH_RANGE`.
    rise : float
        Height of the crown's mid-curve above the springings (m).
    thickness : float, optional
        Constant thickness (m). Or, instead:
    thickness_springing, thickness_crown : float, optional
        Thickness at the springings and at the crown (m), linear in the arc length in
        between.
    density : float, optional
        Density of the masonry (kg/m^3; masses are per metre of barrel width), default
        :data:`~fembeam.geometry.base.DEFAULT_DENSITY` (2000).

    Raises
    ------
    InputError
        A value out of its range, or a thickness law given twice or not at all.

    Examples
    --------
    A parabolic arch 0.4 m thick at the springings and 0.3 m at the crown:

    >>> import fembeam
    >>> arch = fembeam.ParabolicArch(span=4.0, rise=1.0, thickness_springing=0.4,
    ...                              thickness_crown=0.3)
    >>> print(f"L = {arch.length:.4f} m")
    L = 4.5912 m
    """

    shape = "parabolic"

    def _build(self) -> None:
        self._setup_arc_length()

    def _y(self, x):
        return self.rise * (1.0 - (2.0 * x / self.span) ** 2)

    def _dy(self, x):
        return -8.0 * self.rise * x / self.span**2

    def _ddy(self, x):
        return np.full(x.shape, -8.0 * self.rise / self.span**2)
