"""Parabolic arch: ``y = rise (1 - (2x/span)^2)``, the funicular of a load uniform
along the span."""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .graph import GraphArch

__all__ = ["ParabolicArch"]


@dataclass(frozen=True)
class ParabolicArch(GraphArch):
    """Parabola ``y = H (1 - (2x/L)^2)`` for ``x`` in ``[-L/2, L/2]`` (``L = span``,
    ``H = rise``, m), parametrised by ``x``; the springing tangents have slope
    ``-+4H/L``.  Arc length computed numerically (closed form ``L/2 sqrt(1 + q^2) +
    L/(2q) asinh q`` with ``q = 4H/L``, used by the tests).  Thickness and density as
    :class:`~fembeam.geometry.arch.SymmetricArch`."""

    shape = "parabolic"

    def _build(self) -> None:
        self._setup_arc_length()

    def _y(self, x):
        return self.rise * (1.0 - (2.0 * x / self.span) ** 2)

    def _dy(self, x):
        return -8.0 * self.rise * x / self.span**2

    def _ddy(self, x):
        return np.full(x.shape, -8.0 * self.rise / self.span**2)
