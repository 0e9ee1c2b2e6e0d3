"""Parabolic arch: ``y = rise (1 - (2x/span)^2)``, the funicular of a load uniform
along the span."""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .arch import SymmetricArch
from .parametric import ParametricCurve

__all__ = ["ParabolicArch"]


@dataclass(frozen=True)
class ParabolicArch(ParametricCurve, SymmetricArch):
    """Parabola ``y = H (1 - (2x/L)^2)`` for ``x`` in ``[-L/2, L/2]`` (``L = span``,
    ``H = rise``, m), parametrised by ``x``; the springing tangents have slope
    ``-+4H/L``.  Arc length computed numerically (closed form ``L/2 sqrt(1 + q^2) +
    L/(2q) asinh q`` with ``q = 4H/L``, used by the tests).  Thickness and density as
    :class:`~fembeam.geometry.arch.SymmetricArch`."""

    shape = "parabolic"

    def _build(self) -> None:
        self._setup_arc_length()

    def _geometry_key(self):
        return (float(self.span), float(self.rise))

    def _u_breaks(self):
        return np.array([-0.5 * self.span, 0.5 * self.span])

    def _r(self, u):
        u = np.asarray(u, float)
        return np.array([u, self.rise * (1.0 - (2.0 * u / self.span) ** 2)])

    def _dr(self, u):
        u = np.asarray(u, float)
        return np.array([np.ones_like(u), -8.0 * self.rise * u / self.span**2])

    def _ddr(self, u):
        u = np.asarray(u, float)
        return np.array([np.zeros_like(u), np.full(u.shape, -8.0 * self.rise / self.span**2)])
