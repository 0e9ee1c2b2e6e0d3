"""What the arch shapes other than the circle share: a thickness law, the reporting
coordinate (the turning of the tangent) and the thickness limits.

The mid-curve functions (``position``, ``tangent``, ``curvature``) and ``length`` come
from the shape; this module adds, in terms of a ``_law`` (:class:`ThicknessLaw`) and the
arc length ``_crown_s`` of the crown (m):

* ``thickness_at``, ``with_thickness_scaled``, :attr:`breaks`;
* the admissible thickness factors: the intrados (extrados where the curvature is
  negative) folds where ``t(s) |kappa(s)| >= 2``; :attr:`max_thickness_scale` is
  ``2 / max_s t |kappa|`` and every section must satisfy it at construction;
  :attr:`min_thickness_scale` keeps the thickest section above ``MIN_T_OVER_SPAN`` of
  the span (the circle's ``t/R >= 1e-3`` for a semicircle);
* the reporting coordinate :meth:`angle_deg`: the **turning of the tangent** from the
  left springing, ``int_0^s |kappa| ds`` plus the jumps at the kinks, in degrees.  For a
  convex arch (every shape here) it is the rotation of the tangent, monotonic in ``s``;
  it jumps at a kink and reads the bisector's rotation at the kink itself.
  :meth:`s_at_angle` inverts it (the kink for every angle of its jump).
"""
from __future__ import annotations

import dataclasses
import math

import numpy as np

from ..errors import InputError
from .base import DEFAULT_DENSITY, THICKNESS_RANGE, MidCurve, density_value, finite_positive, length_value
from .thickness import ThicknessLaw, thickness_law

__all__ = ["ShapedArch", "SymmetricArch", "MIN_T_OVER_SPAN"]

MIN_T_OVER_SPAN = 5e-4


class ShapedArch(MidCurve):
    """Mixin of the non-circular arches (see the module docstring).  Subclasses set
    ``_law``, ``_crown_s`` and ``length`` and implement the mid-curve, ``_span`` and
    ``_max_t_kappa()`` (the largest ``t |kappa|``) or rely on the sampled default."""

    _law: ThicknessLaw
    _crown_s: float

    # ------------------------------------------------------------------ thickness
    def thickness_at(self, s):
        return self._law.at(s, self.length, self._crown_s)

    @property
    def breaks(self) -> tuple[float, ...]:
        out = self.__dict__.get("_breaks")
        if out is None:
            pts = set(self.kinks) | set(self._smooth_breaks())
            if self._law is not None:
                pts |= set(self._law.breaks(self._crown_s))
            out = self.__dict__["_breaks"] = tuple(sorted(p for p in pts if 0.0 < p < self.length))
        return out

    def _smooth_breaks(self) -> tuple[float, ...]:
        """Further points where the mid-curve is not analytic (e.g. spline knots)."""
        return ()

    def with_thickness_scaled(self, factor: float):
        factor = finite_positive("thickness factor", factor, "positive")
        return dataclasses.replace(self, **self._thickness_fields(self._law.scaled(factor)))

    def _thickness_fields(self, law: ThicknessLaw) -> dict:
        if law.constant:
            return {"thickness": law.springing, "thickness_springing": None, "thickness_crown": None}
        return {"thickness": None, "thickness_springing": law.springing, "thickness_crown": law.crown}

    @property
    def max_thickness_scale(self) -> float:
        return self.__dict__["_max_scale"]

    @property
    def min_thickness_scale(self) -> float:
        return max(MIN_T_OVER_SPAN * self._span / self._thickest(), THICKNESS_RANGE[0] / self._thinnest())

    def _thickest(self) -> float:
        """Largest thickness of the member (m)."""
        return self._law.maximum

    def _thinnest(self) -> float:
        """Smallest thickness of the member (m)."""
        return min(self._law.springing, self._law.crown)

    def _check_thickness(self) -> None:
        """Store the thickness limits; InputError when the given law is outside them."""
        tk = self._max_t_kappa()
        object.__setattr__(self, "_max_scale", min(math.inf if tk <= 0 else 2.0 / tk,
                                                   THICKNESS_RANGE[1] / self._thickest()))
        if tk >= 2.0:
            raise InputError(f"the thickness must stay below twice the radius of curvature (the intrados folds "
                             f"where t |kappa| >= 2): max t |kappa| = {tk:.6g}; make the section at most "
                             f"{1.0 / tk:.6g} times as thick")
        if self._thickest() < MIN_T_OVER_SPAN * self._span * (1 - 1e-9):
            raise InputError(f"the thickest section must be at least {MIN_T_OVER_SPAN:g} of the span "
                             f"(outside masonry practice below), got {self._thickest() / self._span:.3g}")

    def _max_t_kappa(self) -> float:
        """``max_s t(s) |kappa(s)|``: dense samples, the best refined by a bounded search."""
        L = self.length
        s = np.unique(np.concatenate([np.linspace(0.0, L, 2049), np.asarray(self.breaks, float)]))
        f = self.thickness_at(s) * np.abs(self.curvature(s))
        i = int(np.argmax(f))
        a, b = s[max(i - 1, 0)], s[min(i + 1, s.size - 1)]
        best = float(f[i])
        if b > a:
            from scipy.optimize import minimize_scalar   # here: its import costs 0.2 s

            r = minimize_scalar(lambda x: -float(self.thickness_at(x) * abs(self.curvature(x))),
                                bounds=(a, b), method="bounded", options={"xatol": 1e-12 * L})
            best = max(best, -float(r.fun))
        return best

    # ------------------------------------------------------------------ reporting coordinate
    def angle_deg(self, s):
        return np.degrees(self._turning(np.asarray(s, float)))

    def _turning(self, s: np.ndarray) -> np.ndarray:
        """Turning of the tangent (rad) from the left springing to the sections ``s``."""
        raise NotImplementedError

    def s_at_angle(self, angle_deg) -> np.ndarray:
        """Arc length (m) of the section reported at ``angle_deg`` (bisection on the
        monotonic turning; a kink for every angle of its jump)."""
        a = np.radians(np.asarray(angle_deg, float))
        lo, hi = np.zeros(a.shape), np.full(a.shape, float(self.length))
        for _ in range(64):
            mid = 0.5 * (lo + hi)
            below = self._turning(mid) < a
            lo, hi = np.where(below, mid, lo), np.where(below, hi, mid)
            if np.all(hi - lo <= 1e-15 * self.length):
                break
        out = 0.5 * (lo + hi)
        for k in self.kinks:   # the kink itself, not a point next to it, inside its jump
            out = np.where(np.abs(out - k) <= 1e-12 * self.length, k, out)
        return out

    # ------------------------------------------------------------------ report
    def describe(self) -> dict:
        return {"shape": self.shape, **self._describe_geometry(), **self._law.describe(),
                "density": self.density, "length": self.length}

    def _describe_geometry(self) -> dict:
        return {}


@dataclasses.dataclass(frozen=True)
class SymmetricArch(ShapedArch):
    """An arch symmetric about the vertical axis, springings at ``(-span/2, 0)`` and
    ``(span/2, 0)``, crown at ``(0, rise)``; lengths in m, ``density`` in kg/m^3 per metre of
    barrel width (default masonry, 2000).  Thickness: ``thickness`` (constant) or ``thickness_springing`` and
    ``thickness_crown`` (linear in the arc length from each springing to the crown)."""

    span: float = 1.0
    rise: float = 0.5
    thickness: float | None = None
    thickness_springing: float | None = None
    thickness_crown: float | None = None
    density: float = DEFAULT_DENSITY

    shape = "symmetric"

    def __post_init__(self):
        object.__setattr__(self, "span", length_value("span", self.span))
        object.__setattr__(self, "rise", length_value("rise", self.rise))
        object.__setattr__(self, "density", density_value(self.density))
        object.__setattr__(self, "_law", thickness_law(self.thickness, self.thickness_springing, self.thickness_crown))
        self._build()
        object.__setattr__(self, "_crown_s", 0.5 * self.length)
        self._check_thickness()

    def _build(self) -> None:
        """Validate the shape and set up the mid-curve (``length`` and what it needs)."""
        raise NotImplementedError

    @property
    def _span(self) -> float:
        return float(self.span)

    def _describe_geometry(self) -> dict:
        return {"span": self.span, "rise": self.rise}
