"""Catenary arch: the inverted hanging chain through the springings and the crown,
the funicular of a load uniform along the arc."""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from .graph import GraphArch

__all__ = ["CatenaryArch", "catenary_parameter"]


def catenary_parameter(span: float, rise: float) -> float:
    """The parameter ``c`` (m) of the catenary ``y = H - c (cosh(x/c) - 1)`` through
    ``(-+L/2, 0)`` and ``(0, H)``: ``q = L/(2c)`` solves ``(cosh q - 1) / (2q) = H/L``
    (the left side increases from 0 to infinity with ``q``)."""
    from scipy.optimize import brentq   # imported here: scipy.optimize takes 0.2 s to import

    ratio = rise / span

    def f(q):
        return 2.0 * math.sinh(0.5 * q) ** 2 / (2.0 * q) - ratio

    q = brentq(f, 1e-12, 700.0, xtol=1e-300, rtol=4 * np.finfo(float).eps, maxiter=500)
    return span / (2.0 * q)


@dataclass(frozen=True)
class CatenaryArch(GraphArch):
    """Catenary arch: ``y = H - c (cosh(x/c) - 1)``, ``x`` in ``[-L/2, L/2]``.

    ``L = span``, ``H = rise`` (m), ``c`` (m) from :func:`catenary_parameter`;
    parametrised by ``x`` (arc length numerically; closed form ``2 c sinh(L/(2c))``).

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
    >>> arch = fembeam.CatenaryArch(span=4.0, rise=2.0, thickness=0.3)
    >>> res = fembeam.analyze(arch, voussoirs=10)
    >>> print(f"L = {arch.length:.4f} m", res.outcome, f"A_L = {res.A_L:.4f} g")
    L = 5.9833 m rocking A_L = 0.3272 g
    """

    shape = "catenary"

    def _build(self) -> None:
        object.__setattr__(self, "_c", catenary_parameter(float(self.span), float(self.rise)))
        self._setup_arc_length()

    def _y(self, x):
        return self.rise - 2.0 * self._c * np.sinh(0.5 * x / self._c) ** 2

    def _dy(self, x):
        return -np.sinh(x / self._c)

    def _ddy(self, x):
        return -np.cosh(x / self._c) / self._c

    def _describe_geometry(self) -> dict:
        return {"span": self.span, "rise": self.rise, "catenary_parameter": self._c}
