"""Pointed (two-centred, Gothic) arch: two circular arcs meeting at a vertical crown joint."""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..errors import InputError
from .arch import SymmetricArch

__all__ = ["PointedArch"]

WEDGE_ORDER = 12   # Gauss points at least on a piece of a crown wedge


@dataclass(frozen=True)
class PointedArch(SymmetricArch):
    """Pointed arch: two circular arcs meeting at the crown joint.

    Parameters
    ----------
    span : float
        Distance between the springings (m), in
        :data:`~fembeam.geometry.base.LENGTH_RANGE`.
    rise : float
        Height of the crown ``(0, H)`` above the springings (m), ``H >= span/2``.
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

    Notes
    -----
    The arcs, of radius ``Rp = H^2/L + L/4`` (m), are centred at ``(e, 0)`` (left
    arc) and ``(-e, 0)`` (right arc), ``e = H^2/L - L/4``, springing with vertical
    tangents at ``(-+L/2, 0)`` and meeting at the crown ``(0, H)`` (``L = span``,
    ``H = rise >= L/2``).  ``H = L/2`` is the semicircle (``e = 0``, no crown joint);
    ``e/Rp = 1/2`` (``H = L sqrt(3)/2``) the equilateral arch.

    **The arch as built.**  Each half is the band between the intrados and the extrados of
    its arc (the offset curves ``X +- t/2 n`` of the thickness law, continued past the
    crown by the same circle and the same linear law) on its own side of the vertical
    line ``x = 0``; the two halves meet along the **crown joint**, the vertical segment
    from the point where the two intrados meet, ``I = (0, y_i)``, to the point where the
    two extrados meet, ``E_c = (0, y_e)``: deeper than the thickness (about
    ``t / sin(phi_c)``), its middle a little off ``(0, H)``.  The radial (normal) cuts of
    the left arc are sections of the member up to the one whose intrados end is ``I``, at
    ``s_i`` (:attr:`last_radial_section`); beyond it a radial cut would cross the crown
    joint.  Between that cut and the crown joint lies the **crown wedge**, bounded by the
    cut, the extrados from its end to ``E_c`` and the crown joint: a rigid part of the
    voussoir next to the crown joint, with no section of its own
    (:attr:`~fembeam.geometry.MidCurve.solid_spans`: ``(s_i, length/2)`` and its mirror
    image, arc lengths of the mid-curve).  The right half is the mirror image.

    **Sections.**  ``s`` is the arc length of the mid-curve on each arc; inside the left
    wedge (``s_i < s <= length/2``) the sections are the straight cuts from ``I`` to the
    extrados, a fan turning from the radial cut at ``s_i`` to the crown joint at
    ``length/2`` (the extrados point's own arc length running linearly from ``s_i`` to
    ``s_e``, where the extrados meets ``x = 0``), so that :meth:`position`,
    :meth:`tangent`, :meth:`normal` and :meth:`thickness_at` are continuous, the crown
    section at ``s = length/2`` is the crown joint (tangent ``(1, 0)``, thickness
    ``y_e - y_i``, middle ``(0, (y_i + y_e)/2)``), and :meth:`segment_inertia` of any
    piece is the exact material between its end cuts: the wedge's slices between fan cuts
    are thin triangles from ``I`` (mass, first and polar moment of each in closed form,
    integrated by Gauss-Legendre in ``s``).  Every mesh has a node at the crown joint and
    none inside a wedge; hinges form on the radial cuts up to ``s_i`` (its intrados end is
    ``I``) and at the two ends of the crown joint.

    Reporting coordinate: the turning of the tangent, ``s/Rp`` in degrees on the left arc
    (``180 - phi_i`` at ``s_i``, ``phi_i`` the polar angle of ``I`` about the left
    centre), 90 at the crown joint, symmetric on the right; inside the wedges it is the
    fan's (no section is reported there).

    Examples
    --------
    >>> import fembeam
    >>> arch = fembeam.PointedArch(span=4.0, rise=3.0, thickness=0.4)
    >>> print(f"L = {arch.length:.4f} m")
    L = 7.6440 m
    """

    shape = "pointed"

    def __post_init__(self):
        super().__post_init__()
        self._build_crown()

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

    # ------------------------------------------------------------------ the crown joint
    def _left_law(self, sigma):
        """Thickness (m) of the left arc's law at its arc length ``sigma`` (m), continued
        linearly past the crown."""
        law = self._law
        return law.springing + (law.crown - law.springing) * np.asarray(sigma, float) / self._half

    def _fibre_x(self, sigma, side: float):
        """``x`` (m) of the left arc's intrados (``side = -1``) or extrados (``+1``) at its
        arc length ``sigma``, the circle and the law continued past the crown."""
        r = self._R + 0.5 * side * self._left_law(sigma)
        return self._e - r * np.cos(np.asarray(sigma, float) / self._R)

    def _meets_axis(self, side: float, lo: float, hi: float) -> float:
        """Arc length (m) of the left arc's fibre where it meets ``x = 0``: the first sign
        change of its ``x`` from the crown towards ``lo`` (intrados) or ``hi`` (extrados),
        then bisection to adjacent floating-point numbers."""
        half = self._half
        far = lo if side < 0 else hi
        grid = np.linspace(half, far, 257)
        x = self._fibre_x(grid, side)
        change = np.flatnonzero(np.sign(x[1:]) != np.sign(x[:-1]))
        if change.size == 0:
            raise InputError("the intrados and extrados of a pointed arch must meet on its axis above the "
                             "springings; this thickness law does not")
        a, b = grid[change[0]], grid[change[0] + 1]
        fa = self._fibre_x(a, side)
        for _ in range(200):
            m = 0.5 * (a + b)
            if m in (a, b):
                break
            fm = self._fibre_x(m, side)
            if np.sign(fm) == np.sign(fa):
                a, fa = m, fm
            else:
                b = m
        return float(0.5 * (a + b))

    def _build_crown(self) -> None:
        if self._e == 0:
            return
        R, e, half = self._R, self._e, self._half
        law = self._law
        if law.constant:
            ri, re = R - 0.5 * law.springing, R + 0.5 * law.springing
            s_i = R * (math.pi - math.acos(-e / ri))
            s_e = R * (math.pi - math.acos(-e / re))
            y_i, y_e = math.sqrt((ri - e) * (ri + e)), math.sqrt((re - e) * (re + e))
        else:
            s_i = self._meets_axis(-1.0, 0.0, half)
            hi = 0.5 * math.pi * R
            slope = (law.crown - law.springing) / half
            if slope < 0:            # the continued law must stay positive
                hi = min(hi, -law.springing / slope)
            s_e = self._meets_axis(1.0, half, hi)
            y_i = float((R - 0.5 * self._left_law(s_i)) * math.sin(s_i / R))
            y_e = float((R + 0.5 * self._left_law(s_e)) * math.sin(s_e / R))
            if not 0.0 < self._left_law(s_e):
                raise InputError("the extrados of a pointed arch must meet on its axis with a positive "
                                 "thickness; this thickness law does not")
        if not 0.0 < s_i < half < s_e:
            raise InputError("the intrados and extrados of a pointed arch must meet on its axis above the "
                             "springings")
        object.__setattr__(self, "_s_i", s_i)
        object.__setattr__(self, "_s_e", s_e)
        object.__setattr__(self, "_y_i", y_i)
        object.__setattr__(self, "_y_e", y_e)

    @property
    def radius(self) -> float:
        """Radius of the two arcs, ``Rp`` (m)."""
        return self._R

    @property
    def centre_offset(self) -> float:
        """``e`` (m): the arcs are centred at ``(+-e, 0)``."""
        return self._e

    @property
    def crown_joint(self) -> tuple[float, float] | None:
        """``(y_i, y_e)`` (m): the crown joint is the vertical segment from ``(0, y_i)``, where
        the intrados meet, to ``(0, y_e)``, where the extrados meet (None for the semicircle)."""
        return None if self._e == 0 else (self._y_i, self._y_e)

    @property
    def last_radial_section(self) -> float | None:
        """``s_i`` (m): the left arc's last radial cut, whose intrados end is the crown
        joint's intrados end; the right arc's first one is at ``length - s_i`` (None for the
        semicircle)."""
        return None if self._e == 0 else self._s_i

    @property
    def kinks(self) -> tuple[float, ...]:
        return ()

    @property
    def fixed_nodes(self) -> tuple[float, ...]:
        return (self._half,) if self._e > 0 else ()

    @property
    def solid_spans(self) -> tuple[tuple[float, float], ...]:
        if self._e == 0:
            return ()
        return ((self._s_i, self._half), (self._half, self.length - self._s_i))

    @property
    def polynomial_in_thickness(self) -> bool:
        return self._e == 0

    def _smooth_breaks(self) -> tuple[float, ...]:
        if self._e == 0:
            return ()
        return (self._s_i, self._half, self.length - self._s_i)

    # ------------------------------------------------------------------ sections
    def _fan(self, q):
        """The left wedge's fan at the left coordinates ``q`` (m, clipped to ``[s_i, length/2]``):
        ``w = E - I`` (2, n), the extrados point ``E`` and ``dE/ds``; ``E`` runs along the
        extrados, its own arc length ``sigma`` linear in ``q`` from ``s_i`` to ``s_e``."""
        R, e, half, s_i = self._R, self._e, self._half, self._s_i
        rate = (self._s_e - s_i) / (half - s_i)
        sig = s_i + (np.clip(q, s_i, half) - s_i) * rate
        r = self._R + 0.5 * self._left_law(sig)
        dr = 0.5 * (self._law.crown - self._law.springing) / half
        a = sig / R
        c, sn = np.cos(a), np.sin(a)
        top = q >= half                 # the crown joint's extrados end, exactly on the axis
        E = np.array([np.where(top, 0.0, e - r * c), np.where(top, self._y_e, r * sn)])
        dE = np.array([-dr * c + r * sn / R, dr * sn + r * c / R]) * rate
        w = E - np.array([0.0, self._y_i]).reshape((2,) + (1,) * np.ndim(q))
        return w, E, dE

    def _left(self, q):
        """Frames of the left half at the left coordinates ``q`` (m, in ``[0, length/2]``):
        position, tangent (2, n), curvature and thickness; arcs and fan."""
        R, e = self._R, self._e
        q = np.asarray(q, float)
        phi = np.pi - q / R
        c, sn = np.cos(phi), np.sin(phi)
        X = np.array([e + R * c, R * sn])
        t = np.array([sn, -c])
        kap = np.full(q.shape, 1.0 / R)
        if self._e == 0:
            return X, t, kap
        wedge = q > self._s_i
        if np.any(wedge):
            w, E, dE = self._fan(q[wedge])
            ell = np.hypot(w[0], w[1])
            X[:, wedge] = np.array([0.5 * w[0], self._y_i + 0.5 * w[1]])
            t[:, wedge] = np.array([w[1], 0.0 - w[0]]) / ell       # (1, 0) at the crown joint, not (1, -0)
            kap[wedge] = -(w[0] * dE[1] - w[1] * dE[0]) / (ell * ell)
        return X, t, kap

    def _split(self, s):
        s = np.asarray(s, float)
        right = s > 0.5 * self.length if self._e > 0 else np.zeros(s.shape, bool)
        return s, np.where(right, self.length - s, s), right

    def _frames(self, s):
        """Position, tangent and curvature at the sections ``s`` (the right half mirrored)."""
        s, q, right = self._split(s)
        if self._e == 0:
            return self._left(s)
        X, t, kap = self._left(q)
        X[0] = np.where(right, -X[0], X[0])
        t[1] = np.where(right, -t[1], t[1])
        return X, t, kap

    def position(self, s):
        return self._frames(s)[0]

    def tangent(self, s):
        return self._frames(s)[1]

    def curvature(self, s):
        s, q, _ = self._split(s)
        kap = np.full(q.shape, 1.0 / self._R)
        if self._e > 0:
            wedge = q > self._s_i
            if np.any(wedge):
                w, _, dE = self._fan(q[wedge])
                kap[wedge] = -(w[0] * dE[1] - w[1] * dE[0]) / (w[0] ** 2 + w[1] ** 2)
        return kap

    def thickness_at(self, s):
        s, q, _ = self._split(s)
        t = self._law.at(s, self.length, self._crown_s)
        if self._e == 0:
            return t
        wedge = q > self._s_i
        if np.any(wedge):
            w = self._fan(q[wedge])[0]
            t = np.array(t, float)
            t[wedge] = np.hypot(w[0], w[1])
        return t

    def inertia_densities(self, s, power: int | None = None):
        """As :meth:`MidCurve.inertia_densities` on the arcs; inside the crown wedges the
        slice between the fan cuts at ``s`` and ``s + ds`` is the thin triangle from ``I``
        to the extrados points ``E`` and ``E + dE``: mass ``rho |w x dE| / 2`` (``w = E -
        I``), centroid ``(I + 2E)/3``, polar moment about the origin
        ``mass (|I|^2 + 3|E|^2 + 2 I.E) / 6``.  Those are not polynomial in the thickness:
        ``power`` (1 or 3) is refused there."""
        s = np.asarray(s, float)
        X, tg, kap = self._frames(s)
        n = np.array([tg[1], -tg[0]])
        t = self.thickness_at(s)
        one = self.density * t if power in (None, 1) else np.zeros(s.shape)
        i3 = self.density * t**3 / 12.0 if power in (None, 3) else np.zeros(s.shape)
        mu0 = one * np.ones(s.shape)
        mu1 = one * X - kap * i3 * n
        mu2 = one * np.sum(X * X, 0) - 2 * kap * i3 * np.sum(X * n, 0) + i3
        if self._e == 0:
            return mu0, mu1, mu2
        s, q, right = self._split(s)
        wedge = q > self._s_i
        if not np.any(wedge):
            return mu0, mu1, mu2
        if power is not None:
            raise InputError("the crown wedges of a pointed arch are not polynomial in the thickness (its "
                             "terms in t and t^3 do not exist there)")
        w, E, dE = self._fan(q[wedge])
        f0 = -0.5 * self.density * (w[0] * dE[1] - w[1] * dE[0])      # rho |w x dE| / 2
        cx, cy = 2.0 * E[0] / 3.0, (self._y_i + 2.0 * E[1]) / 3.0       # (I + 2E) / 3
        mu0, mu1, mu2 = np.array(mu0, float), np.array(mu1, float), np.array(mu2, float)
        mu0[wedge] = f0
        mu1[:, wedge] = f0 * np.array([np.where(right[wedge], -cx, cx), cy])
        mu2[wedge] = f0 * (self._y_i ** 2 + 3.0 * np.sum(E * E, 0) + 2.0 * self._y_i * E[1]) / 6.0
        return mu0, mu1, mu2

    def _smooth_inertia(self, sa, sb, order, power=None):
        # a piece of a crown wedge (segment_inertia splits pieces at the wedges' edges) on at
        # least WEDGE_ORDER points: its densities are smooth in the extrados point's arc
        # length (7 points reach round-off on every wedge tried), whatever the mesh's rule
        m, S, J = super()._smooth_inertia(sa, sb, order, power)
        if self._e == 0 or order >= WEDGE_ORDER:
            return m, S, J
        tol = 1e-13 * self.length
        lo, hi = np.minimum(sa, sb), np.maximum(sa, sb)
        w = (lo >= self._s_i - tol) & (hi <= self.length - self._s_i + tol)
        if np.any(w):
            m, S, J = m.copy(), S.copy(), J.copy()
            m[w], S[:, w], J[w] = super()._smooth_inertia(sa[w], sb[w], WEDGE_ORDER, power)
        return m, S, J

    # ------------------------------------------------------------------ reporting coordinate
    def _turning(self, s):
        s, q, right = self._split(s)
        if self._e == 0:
            return s / self._R
        tau = np.array(q / self._R, float)
        wedge = q > self._s_i
        if np.any(wedge):
            w = self._fan(q[wedge])[0]
            tau[wedge] = np.pi - np.arctan2(w[1], w[0])
        return np.where(right, np.pi - tau, tau)

    def angle_deg(self, s):
        if self._e == 0:   # the semicircle: as CircularArch
            return np.degrees(np.asarray(s, float) / self._R)
        return np.degrees(self._turning(s))

    def s_at_angle(self, angle_deg):
        """Arc length (m) of the section reported at ``angle_deg``: on the arcs in closed
        form, 90 at the crown joint, inside the wedges (no section there) the fan's cut,
        by bisection on its monotonic turning."""
        deg = np.asarray(angle_deg, float)
        a = np.radians(deg)
        if self._e == 0:
            return a * self._R
        R, half, s_i, L = self._R, self._half, self._s_i, self.length
        top = s_i / R                           # turning at the last radial section
        q = np.where(a <= 0.5 * np.pi, a, np.pi - a)      # the left half's turning
        out = q * R
        fan = q > top
        if np.any(fan):
            lo, hi = np.full(q.shape, s_i), np.full(q.shape, half)
            for _ in range(200):
                mid = 0.5 * (lo + hi)
                below = self._turning(mid) < q
                lo, hi = np.where(below, mid, lo), np.where(below, hi, mid)
                if np.all((hi - lo)[fan] <= 2e-16 * L):
                    break
            out = np.where(fan, np.where(deg == 90.0, half, 0.5 * (lo + hi)), out)
        return np.where(a <= 0.5 * np.pi, out, L - out)

    def _max_t_kappa(self) -> float:
        # the intrados of each arc folds at t = 2 Rp; the two intrados arcs must meet above
        # the springing line (Rp - t/2 > e, i.e. t < span)
        return self._law.maximum * max(1.0 / self._R, 2.0 / self.span)

    def _describe_geometry(self) -> dict:
        return {"span": self.span, "rise": self.rise, "radius": self._R, "centre_offset": self._e}
