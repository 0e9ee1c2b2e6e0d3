"""Pointed (two-centred, Gothic) arch: two circular arcs meeting at a crown kink."""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..errors import InputError
from .arch import SymmetricArch

__all__ = ["PointedArch"]


@dataclass(frozen=True)
class PointedArch(SymmetricArch):
    """Two circular arcs of radius ``Rp = H^2/L + L/4`` (m) centred at ``(e, 0)`` (left
    arc) and ``(-e, 0)`` (right arc), ``e = H^2/L - L/4``, springing with vertical
    tangents at ``(-+L/2, 0)`` and meeting at the crown ``(0, H)`` (``L = span``,
    ``H = rise >= L/2``).  ``H = L/2`` is the semicircle (``e = 0``, no kink);
    ``e/Rp = 1/2`` (``H = L sqrt(3)/2``) the equilateral arch.

    Closed form in the arc length: each arc has length ``Rp (pi - phi_c)`` with
    ``phi_c = atan2(H, -e)`` the polar angle of the crown seen from the left centre.
    The crown is a **kink** (:attr:`kinks`, for ``H > L/2``): the tangent turns by
    ``2 phi_c - pi`` there; at the kink itself the tangent is the bisector ``(1, 0)``,
    so the crown joint is the vertical cut through the kink, of the thickness the law
    gives there.  The member is the union of the two arcs' regions between normal
    (radial) cuts -- the radial stereotomy of the thrust-line literature -- so the
    sections at the crown are three: the left arc's radial cut (one ulp left of the
    kink, reported at ``180 - phi_c``, ``phi_c`` in degrees), the vertical cut (90) and
    the right arc's radial cut (``phi_c``); the continuum analysis checks all three and a hinge may
    sit on any (the refined mesh then has a one-ulp, massless element between two of
    them).  The small wedges, of order ``t^2 tan(phi_c - pi/2)``, by which the two
    radial cuts at the crown differ from the vertical one are not modelled.

    Reporting coordinate: ``s/Rp`` in degrees on the left arc, ``180 - (length - s)/Rp``
    on the right one, 90 at the crown (it jumps from ``180 - phi_c`` to ``phi_c`` deg
    there).  Thickness and density as :class:`~fembeam.geometry.arch.SymmetricArch`.
    """

    shape = "pointed"

    def _build(self) -> None:
        L, H = float(self.span), float(self.rise)
        if H < 0.5 * L:
            raise InputError(f"a pointed arch needs rise >= span/2 (rise = span/2 is the semicircle; flatter "
                             f"arches: elliptical, parabolic, catenary), got rise/span = {H / L:g}")
        if H == 0.5 * L:
            e, R = 0.0, 0.5 * L
        else:
            e, R = H * H / L - 0.25 * L, H * H / L + 0.25 * L
        phi_c = math.atan2(H, -e)
        half = R * (math.pi - phi_c)
        object.__setattr__(self, "_e", e)
        object.__setattr__(self, "_R", R)
        object.__setattr__(self, "_phi_c", phi_c)
        object.__setattr__(self, "_half", half)
        object.__setattr__(self, "length", 2.0 * half if e > 0 else R * math.pi)

    @property
    def radius(self) -> float:
        """Radius of the two arcs, ``Rp`` (m)."""
        return self._R

    @property
    def centre_offset(self) -> float:
        """``e`` (m): the arcs are centred at ``(+-e, 0)``."""
        return self._e

    @property
    def kinks(self) -> tuple[float, ...]:
        return (self._half,) if self._e > 0 else ()

    def _sides(self, s):
        s = np.asarray(s, float)
        if self._e == 0:
            return s, np.ones(s.shape, bool), np.zeros(s.shape, bool)
        return s, s < self._half, s > self._half

    def position(self, s):
        s, left, right = self._sides(s)
        R, e = self._R, self._e
        phi = np.pi - np.where(right, self.length - s, s) / R
        x = e + R * np.cos(phi)
        crown = ~(left | right)
        return np.array([np.where(crown, 0.0, np.where(right, -x, x)), np.where(crown, self.rise, R * np.sin(phi))])

    def tangent(self, s):
        s, left, right = self._sides(s)
        phi = np.pi - np.where(right, self.length - s, s) / self._R
        crown = ~(left | right)
        return np.array([np.where(crown, 1.0, np.sin(phi)),
                         np.where(crown, 0.0, np.where(right, np.cos(phi), -np.cos(phi)))])

    def curvature(self, s):
        return np.full(np.shape(s), 1.0 / self._R)

    def _turning(self, s):
        s, left, right = self._sides(s)
        if self._e == 0:
            return s / self._R
        return np.where(left, s / self._R, np.where(right, np.pi - (self.length - s) / self._R, 0.5 * np.pi))

    def angle_deg(self, s):
        if self._e == 0:   # the semicircle: as CircularArch
            return np.degrees(np.asarray(s, float) / self._R)
        return np.degrees(self._turning(s))

    def s_at_angle(self, angle_deg):
        """Arc length (m) of the section reported at ``angle_deg``: on the left arc below
        the crown's jump, on the right arc above it, the kink inside the jump; the jump's
        ends (to 1e-10 deg) are the one-sided crown cuts, one ulp off the kink (as
        reported for a hinge there)."""
        deg = np.asarray(angle_deg, float)
        a = np.radians(deg)
        if self._e == 0:
            return a * self._R
        k = self._half
        top = np.pi - self._phi_c          # turning of the left arc up to the crown
        left = np.minimum(a * self._R, np.nextafter(k, -np.inf))
        right = np.maximum(self.length - (np.pi - a) * self._R, np.nextafter(k, np.inf))
        lo, hi = np.degrees(top), np.degrees(self._phi_c)
        return np.where(deg <= lo + 1e-10, left, np.where(deg >= hi - 1e-10, right, k))

    def _max_t_kappa(self) -> float:
        # the intrados of each arc folds at t = 2 Rp; the two intrados arcs must meet above
        # the springing line (Rp - t/2 > e, i.e. t < span)
        return self._law.maximum * max(1.0 / self._R, 2.0 / self.span)

    def _describe_geometry(self) -> dict:
        return {"span": self.span, "rise": self.rise, "radius": self._R, "centre_offset": self._e}
