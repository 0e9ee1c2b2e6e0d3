"""Mid-curve descriptions of arch-like members.

The finite elements only ever ask a member for its mid-curve as functions of the
arc length ``s`` (m, from the left end): position, unit tangent, curvature and
thickness, plus the density and what its two ends rest on.  Conventions (docs/theory.md):

* the tangent ``t`` points from the left end to the right end, ``k`` is out of
  plane and the normal ``n = t x k = (t_y, -t_x)`` points to the centre of
  curvature of a circular arch (inward); ``kappa > 0`` when it does;
* ``y`` is the signed distance from the mid-curve along ``n``; the **intrados**
  fibre is at ``y = +t/2`` and the **extrados** at ``y = -t/2``;
* an end is a ``"joint"`` (no-tension, no-sliding contact with a rigid abutment at
  rest) or ``"free"``.
"""
from __future__ import annotations

import dataclasses
import functools
import math
from dataclasses import dataclass

import numpy as np

from ..errors import InputError

__all__ = ["MidCurve", "finite_positive"]


class MidCurve:
    """Base class: subclasses set ``length``, ``density``, ``ends`` and implement
    ``position``, ``tangent``, ``curvature``, ``thickness_at`` (vectorised in ``s``)."""

    length: float
    density: float
    ends: tuple[str, str] = ("joint", "joint")

    def position(self, s: np.ndarray) -> np.ndarray:  # (2, *s.shape), m
        raise NotImplementedError

    def tangent(self, s: np.ndarray) -> np.ndarray:  # (2, *s.shape), unit
        raise NotImplementedError

    def curvature(self, s: np.ndarray) -> np.ndarray:  # 1/m, > 0 towards n
        raise NotImplementedError

    def thickness_at(self, s: np.ndarray) -> np.ndarray:  # m
        raise NotImplementedError

    def with_thickness_scaled(self, factor: float) -> "MidCurve":
        """The same mid-curve with every thickness multiplied by ``factor``."""
        raise NotImplementedError

    @property
    def max_thickness_scale(self) -> float:
        """Largest thickness factor the shape admits (e.g. intrados radius > 0)."""
        return math.inf

    @property
    def min_thickness_scale(self) -> float:
        """Smallest thickness factor the shape admits."""
        return 1e-9

    def normal(self, s: np.ndarray) -> np.ndarray:
        t = self.tangent(s)
        return np.array([t[1], -t[0]])

    def point(self, s: np.ndarray, y) -> np.ndarray:
        """Points ``X(s) + y n(s)`` of the sections at ``s``, ``y`` (m) along the normal."""
        return self.position(s) + np.asarray(y, float) * self.normal(s)

    def angle_deg(self, s: np.ndarray) -> np.ndarray:
        """Reporting coordinate of a section (deg from the left end for arches)."""
        return np.asarray(s, dtype=float)

    def inertia_densities(self, s: np.ndarray):
        """Mass, first and second moment (about the origin) per unit arc length.

        Exact for a thin annular-sector slice ``[s, s + ds]`` of thickness ``t``:
        ``mu0 = rho t``, ``mu1 = rho (t X - kappa t^3/12 n)`` (the centroid sits
        ``kappa t^2/12`` outward of the mid-curve point ``X``) and
        ``mu2 = rho (t |X|^2 - 2 kappa t^3/12 X.n + t^3/12)``.
        """
        X, n = self.position(s), self.normal(s)
        t, kap = self.thickness_at(s), self.curvature(s)
        i3 = t**3 / 12.0
        mu0 = self.density * t
        mu1 = self.density * (t * X - kap * i3 * n)
        mu2 = self.density * (t * np.sum(X * X, 0) - 2 * kap * i3 * np.sum(X * n, 0) + i3)
        return mu0, mu1, mu2

    def segment_inertia(self, sa, sb, order: int = 24):
        """Mass ``m``, first moment ``S`` (2-vector) and polar moment ``J`` about the
        origin of the member pieces ``[sa, sb]`` (arrays), by Gauss-Legendre quadrature."""
        sa, sb = np.atleast_1d(np.asarray(sa, float)), np.atleast_1d(np.asarray(sb, float))
        xg, wg = _gauss(order)
        half = 0.5 * (sb - sa)
        s = 0.5 * (sa + sb)[:, None] + half[:, None] * xg[None, :]
        mu0, mu1, mu2 = self.inertia_densities(s)
        wq = half[:, None] * wg[None, :]
        return np.sum(mu0 * wq, 1), np.sum(mu1 * wq, 2), np.sum(mu2 * wq, 1)


@functools.lru_cache(maxsize=8)
def _gauss(order: int):
    return np.polynomial.legendre.leggauss(order)


def finite_positive(name: str, value: float, allowed: str) -> float:
    try:
        value = float(value)
    except (TypeError, ValueError):
        raise InputError(f"{name} must be a number ({allowed}), got {value!r}") from None
    if not math.isfinite(value) or value <= 0:
        raise InputError(f"{name} must be {allowed}, got {value}")
    return value
