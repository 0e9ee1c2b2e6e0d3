"""Elliptical arch: the upper half of an ellipse with semi-axes ``span/2`` (horizontal)
and ``rise`` (vertical); ``rise = span/2`` is the semicircle."""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .arch import SymmetricArch
from .parametric import ParametricCurve

__all__ = ["EllipticalArch"]


@dataclass(frozen=True)
class EllipticalArch(ParametricCurve, SymmetricArch):
    """Half-ellipse ``(x / a)^2 + (y / b)^2 = 1``, ``y >= 0``, with ``a = span/2`` and
    ``b = rise`` (m), parametrised by the eccentric angle ``u`` in ``[0, pi]``:
    ``r(u) = (-a cos u, b sin u)`` (vertical tangents at the springings).  The arc length
    is the incomplete elliptic integral of the second kind, computed numerically
    (:mod:`~fembeam.geometry.parametric`).  Thickness and density as
    :class:`~fembeam.geometry.arch.SymmetricArch`."""

    shape = "elliptical"

    def _build(self) -> None:
        self._setup_arc_length()

    def _geometry_key(self):
        return (float(self.span), float(self.rise))

    def _u_breaks(self):
        return np.array([0.0, np.pi])

    def _r(self, u):
        return np.array([-0.5 * self.span * np.cos(u), self.rise * np.sin(u)])

    def _dr(self, u):
        return np.array([0.5 * self.span * np.sin(u), self.rise * np.cos(u)])

    def _ddr(self, u):
        return np.array([0.5 * self.span * np.cos(u), -self.rise * np.sin(u)])
