"""Mid-curve descriptions of arch-like members.

The finite elements only ever ask a member for its mid-curve as functions of the
arc length ``s`` (m, from the left end): position, unit tangent, curvature and
thickness, plus the density and what its two ends rest on.  Conventions (THEORY §1):

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

from .errors import InputError

__all__ = ["MidCurve", "CircularArch", "StraightMember"]


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


def _finite_positive(name: str, value: float, allowed: str) -> float:
    try:
        value = float(value)
    except (TypeError, ValueError):
        raise InputError(f"{name} must be a number ({allowed}), got {value!r}") from None
    if not math.isfinite(value) or value <= 0:
        raise InputError(f"{name} must be {allowed}, got {value}")
    return value


@dataclass(frozen=True)
class CircularArch(MidCurve):
    """Circular arch symmetric about the vertical axis, centre at the origin.

    Parameters
    ----------
    radius : mid-curve radius R (m), > 0.
    thickness : t (m), 0 < t < 2R.
    embrace_deg : total embrace angle beta (deg), 0 < beta < 360 (180 = semicircle).
    density : rho (kg/m^3 per unit depth), > 0.
    """

    radius: float = 1.0
    thickness: float = 0.15
    embrace_deg: float = 157.5
    density: float = 1.0

    def __post_init__(self):
        R = _finite_positive("radius", self.radius, "a positive number of metres")
        t = _finite_positive("thickness", self.thickness, "positive")
        b = _finite_positive("embrace angle", self.embrace_deg, "in (0, 360) degrees")
        _finite_positive("density", self.density, "positive")
        if t / R >= 2:
            raise InputError(f"t/R must be below 2 (intrados radius R - t/2 > 0), got {t / R:g}")
        if b >= 360:
            raise InputError(f"embrace angle must be in (0, 360) degrees, got {b:g}")

    @classmethod
    def from_ratio(cls, embrace_deg: float, t_over_r: float, radius: float = 1.0, density: float = 1.0):
        t_over_r = _finite_positive("t/R", t_over_r, "in (0, 2)")
        radius = _finite_positive("radius", radius, "a positive number of metres")
        return cls(radius=radius, thickness=t_over_r * radius, embrace_deg=embrace_deg, density=density)

    @property
    def beta(self) -> float:
        return math.radians(self.embrace_deg)

    @property
    def t_over_r(self) -> float:
        return self.thickness / self.radius

    @property
    def length(self) -> float:
        return self.radius * self.beta

    def _theta(self, s):
        # polar angle of the section; the left springing is at pi/2 + beta/2
        return 0.5 * math.pi + 0.5 * self.beta - np.asarray(s, float) / self.radius

    def position(self, s):
        th = self._theta(s)
        return self.radius * np.array([np.cos(th), np.sin(th)])

    def tangent(self, s):
        th = self._theta(s)
        return np.array([np.sin(th), -np.cos(th)])

    def curvature(self, s):
        return np.full(np.shape(s), 1.0 / self.radius)

    def thickness_at(self, s):
        return np.full(np.shape(s), self.thickness)

    def angle_deg(self, s):
        return np.degrees(np.asarray(s, float) / self.radius)

    def with_thickness_scaled(self, factor: float) -> "CircularArch":
        return dataclasses.replace(self, thickness=self.thickness * factor)

    @property
    def max_thickness_scale(self) -> float:
        return 2.0 * self.radius / self.thickness

    def describe(self) -> dict:
        return {"shape": "circular", "radius": self.radius, "thickness": self.thickness,
                "t_over_R": self.t_over_r, "embrace_deg": self.embrace_deg, "density": self.density}


@dataclass(frozen=True)
class StraightMember(MidCurve):
    """Vertical straight member of height ``height`` and width ``width`` standing on a
    rigid base (bottom end a joint, top end free): Housner's rocking block.

    The mid-curve runs upwards from the base, so ``t = (0, 1)``, ``n = (1, 0)``:
    the "intrados" fibre is on the right face, the "extrados" on the left face.
    """

    height: float = 1.0
    width: float = 0.2
    density: float = 1.0
    ends: tuple[str, str] = ("joint", "free")

    def __post_init__(self):
        _finite_positive("height", self.height, "positive")
        _finite_positive("width", self.width, "positive")
        _finite_positive("density", self.density, "positive")

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

    def with_thickness_scaled(self, factor: float) -> "StraightMember":
        return dataclasses.replace(self, width=self.width * factor)

    def describe(self) -> dict:
        return {"shape": "block", "height": self.height, "width": self.width, "density": self.density}
