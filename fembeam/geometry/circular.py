"""Circular arch: the paper's member, symmetric about the vertical axis."""
from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass

import numpy as np

from ..errors import InputError
from .base import DEFAULT_DENSITY, MidCurve, density_value, length_value, thickness_value
from .base import finite_positive as _finite_positive

__all__ = ["CircularArch", "MIN_T_OVER_R"]

MIN_T_OVER_R = 1e-3


@dataclass(frozen=True)
class CircularArch(MidCurve):
    """Circular arch of constant thickness, symmetric about the vertical axis.

    The centre of the mid-curve is at the origin; the arc length ``s`` runs from the
    left springing, and angles are reported in degrees from it (0 to ``embrace_deg``).

    Parameters
    ----------
    radius : float, optional
        Radius ``R`` of the mid-curve (m), in
        :data:`~fembeam.geometry.base.LENGTH_RANGE`.
    thickness : float, optional
        Thickness ``t`` (m), ``1e-3 R <= t < 2 R``.
    embrace_deg : float, optional
        Total embrace angle ``beta`` (deg), ``0 < beta < 360`` (180: a semicircle).
    density : float, optional
        Density ``rho`` of the masonry (kg/m^3; masses are per metre of barrel width),
        in :data:`~fembeam.geometry.base.DENSITY_RANGE`; default
        :data:`~fembeam.geometry.base.DEFAULT_DENSITY` (2000; typical 1800-2400).

    Raises
    ------
    InputError
        A value out of its range.

    See Also
    --------
    fembeam.analyze

    Examples
    --------
    A semicircular arch of radius 2 m and thickness 0.3 m:

    >>> import fembeam
    >>> arch = fembeam.CircularArch(radius=2.0, thickness=0.3, embrace_deg=180.0)
    >>> mass = arch.segment_inertia(0.0, arch.length)[0][0]
    >>> print(f"L = {arch.length:.4f} m, t/R = {arch.t_over_r:.2f}, {mass:.1f} kg/m")
    L = 6.2832 m, t/R = 0.15, 3769.9 kg/m

    The same shape from its ratio ``t/R``:

    >>> fembeam.CircularArch.from_ratio(180.0, 0.15, radius=2.0) == arch
    True
    """

    radius: float = 1.0
    thickness: float = 0.15
    embrace_deg: float = 157.5
    density: float = DEFAULT_DENSITY

    def __post_init__(self):
        R = length_value("radius", self.radius)
        t = thickness_value("thickness", self.thickness)
        b = _finite_positive("embrace angle", self.embrace_deg, "in (0, 360) degrees")
        rho = density_value(self.density)
        if not MIN_T_OVER_R <= t / R < 2:
            raise InputError(f"t/R must be in [{MIN_T_OVER_R:g}, 2) (intrados radius R - t/2 > 0; thinner sections "
                             f"are outside masonry practice and the range the checks are calibrated for), got {t / R:g}")
        if b >= 360:
            raise InputError(f"embrace angle must be in (0, 360) degrees, got {b:g}")
        for name, value in (("radius", R), ("thickness", t), ("embrace_deg", b), ("density", rho)):
            object.__setattr__(self, name, value)

    @classmethod
    def from_ratio(cls, embrace_deg: float, t_over_r: float, radius: float = 1.0, density: float = DEFAULT_DENSITY):
        """The arch of embrace ``embrace_deg`` (deg) and ratio ``t_over_r`` (``t/R``), of
        radius ``radius`` (m) and density ``density`` (kg/m^3)."""
        t_over_r = _finite_positive("t/R", t_over_r, "in (0, 2)")
        radius = length_value("radius", radius)
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

    def _smooth_inertia(self, sa, sb, order, power=None):
        """:meth:`MidCurve.segment_inertia` of annular sectors in closed form (``order`` is
        not needed): with ``X = R (cos theta, sin theta)``, ``theta = theta_0 - s / R``, the
        densities are ``rho t``, ``rho (t + t^3 / (12 R^2)) X`` and ``rho (t R^2 + t^3 / 4)``."""
        if type(self).inertia_densities is not MidCurve.inertia_densities:   # another load model
            return super()._smooth_inertia(sa, sb, order, power)
        sa, sb = np.asarray(sa, float), np.asarray(sb, float)
        R, rho, t = self.radius, self.density, self.thickness
        one = rho * t if power in (None, 1) else 0.0
        i3 = rho * t**3 / 12.0 if power in (None, 3) else 0.0
        ta, tb = self._theta(sa), self._theta(sb)
        L = sb - sa
        m = np.full(L.shape, one) * L
        mid, half = 0.5 * (ta + tb), np.sin(0.5 * L / R)       # differences of sines without cancellation
        S = (one + i3 / R**2) * R**2 * 2.0 * half * np.array([np.cos(mid), np.sin(mid)])
        return m, S, (one * R**2 + 3.0 * i3) * L

    def with_thickness_scaled(self, factor: float) -> "CircularArch":
        return dataclasses.replace(self, thickness=self.thickness * factor)

    @property
    def max_thickness_scale(self) -> float:
        return 2.0 * self.radius / self.thickness

    @property
    def min_thickness_scale(self) -> float:
        return MIN_T_OVER_R * self.radius / self.thickness

    def describe(self) -> dict:
        return {"shape": "circular", "radius": self.radius, "thickness": self.thickness,
                "t_over_R": self.t_over_r, "embrace_deg": self.embrace_deg, "density": self.density}
