"""Arches whose mid-curve is the graph of a function ``y(x)`` over the span, symmetric
about ``x = 0`` with springings at ``(-+span/2, 0)`` (parabola, catenary)."""
from __future__ import annotations

import numpy as np

from .arch import SymmetricArch
from .parametric import ParametricCurve

__all__ = ["GraphArch"]


class GraphArch(ParametricCurve, SymmetricArch):
    """A :class:`~fembeam.geometry.parametric.ParametricCurve` parametrised by ``x`` (m) on
    ``[-span/2, span/2]``: a subclass gives ``_y``, ``_dy``, ``_ddy`` (vectorised, m, -,
    1/m) in terms of ``span`` and ``rise``."""

    def _geometry_key(self):
        return (float(self.span), float(self.rise))

    def _u_breaks(self):
        return np.array([-0.5 * self.span, 0.5 * self.span])

    def _r(self, u):
        u = np.asarray(u, float)
        return np.array([u, self._y(u)])

    def _dr(self, u):
        u = np.asarray(u, float)
        return np.array([np.ones_like(u), self._dy(u)])

    def _ddr(self, u):
        u = np.asarray(u, float)
        return np.array([np.zeros_like(u), self._ddy(u)])
