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
    """Elliptical arch: the half-ellipse ``(x / a)^2 + (y / b)^2 = 1``, ``y >= 0``.

    ``a = span/2`` and ``b = rise`` (m), parametrised by the eccentric angle ``u`` in
    ``[0, pi]``: ``r(u) = (-a cos u, b sin u)`` (vertical tangents at the springings).
    The arc length is the incomplete elliptic integral of the second kind, computed
    numerically (:mod:`~fembeam.geometry.parametric`).

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
    >>> import fembeam
    >>> arch = fembeam.EllipticalArch(span=4.0, rise=1.5, thickness=0.3)
    >>> print(f"L = {arch.length:.4f} m")
    L = 5.5259 m
    """

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
