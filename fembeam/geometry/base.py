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
import numbers
from dataclasses import dataclass

import numpy as np

from ..errors import InputError

__all__ = ["MidCurve", "finite_positive", "real_number", "length_value", "thickness_value", "density_value",
           "LENGTH_RANGE", "THICKNESS_RANGE", "DENSITY_RANGE", "DEFAULT_DENSITY"]

# Admissible magnitudes (docs/user_guide.md, "Limits"): r and A_L/g do not depend on the
# size or the density, but the mass matrix holds products like rho R^4 and the solvers'
# norms their squares; inside these ranges every such number stays far from overflow and
# underflow (A_L and r agree with R = rho = 1 to 1e-12 at every corner of the ranges).
LENGTH_RANGE = (1e-6, 1e6)       # m: radius, span, rise, block height, surveyed coordinates
THICKNESS_RANGE = (1e-9, 1e7)    # m: thicknesses and the block width (the shapes bound them further)
DENSITY_RANGE = (1e-6, 1e9)      # kg/m^3
# Default density: masonry, kg/m^3 per metre of barrel width (typical values 1800-2400).  Masses,
# forces, energies and impulses are proportional to it; A_L, r and the thresholds in g are not.
DEFAULT_DENSITY = 2000.0


class MidCurve:
    """Base class of the members: a mid-curve with a thickness law.

    Subclasses set ``length``, ``density`` and ``ends`` and implement
    :meth:`position`, :meth:`tangent`, :meth:`curvature` and :meth:`thickness_at`,
    vectorised in the arc length ``s`` (m, from the left springing). The tangent runs
    from the left end to the right one; the normal ``n`` points towards the centre of
    curvature, so the intrados is at ``y = +t/2``.

    Attributes
    ----------
    length : float
        Length of the mid-curve (m).
    density : float
        Density of the masonry (kg/m^3; masses are per metre of barrel width).
    ends : tuple of str
        What each end is: ``"joint"`` (on a rigid support) or ``"free"``.

    Examples
    --------
    Every member is one (:class:`~fembeam.CircularArch`, ...); the crown of the paper's
    arch lies half way along its mid-curve, its intrados ``t/2`` below it (m), and the
    whole arch weighs ``m`` (kg/m):

    >>> import fembeam
    >>> arch = fembeam.CircularArch(radius=1.0, thickness=0.15, embrace_deg=157.5)
    >>> print(isinstance(arch, fembeam.MidCurve), f"{arch.length:.4f} m", arch.ends)
    True 2.7489 m ('joint', 'joint')
    >>> s = arch.length / 2
    >>> crown, intrados = arch.position(s), arch.point(s, 0.075)
    >>> print(f"crown at y = {crown[1]:.3f} m, intrados at y = {intrados[1]:.3f} m")
    crown at y = 1.000 m, intrados at y = 0.925 m
    >>> m, S, J = arch.segment_inertia(0.0, arch.length)
    >>> print(f"m = {m[0]:.1f} kg/m, angle at the crown {arch.angle_deg(s):.2f} deg")
    m = 824.7 kg/m, angle at the crown 78.75 deg
    """

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

    @property
    def kinks(self) -> tuple[float, ...]:
        """Arc lengths (m, increasing, interior) where the tangent of the sections jumps
        (none of the built-in shapes: a pointed arch's crown is a joint between wedges,
        :attr:`solid_spans`).  There the tangent and normal are those of the bisector, so
        the section (joint) at a kink is the cut along the bisector of the two normals.
        Meshes put a node at every kink (:func:`~fembeam.fem.uniform_nodes`)."""
        return ()

    @property
    def fixed_nodes(self) -> tuple[float, ...]:
        """Arc lengths (m, increasing, interior) that are nodes of every mesh
        (:func:`~fembeam.fem.uniform_nodes`; :func:`~fembeam.fem.nodes_through` keeps them):
        the kinks, and the joints the member is built with, e.g. the vertical crown joint of
        a pointed arch."""
        return self.kinks

    @property
    def solid_spans(self) -> tuple[tuple[float, float], ...]:
        """Open intervals ``(a, b)`` of the arc length (m) inside which the member has no
        section: rigid pieces no joint may cut, e.g. the crown wedges of a pointed arch
        (between the last radial section of each arc and the vertical crown joint, where a
        radial cut would cross the crown joint).  No mesh node, hinge or checked section
        lies strictly inside one.  :meth:`position`, :meth:`normal`, :meth:`thickness_at`
        there still describe straight cuts through the material (e.g. a fan), so that
        :meth:`segment_inertia` of any piece is the exact material between its end cuts."""
        return ()

    def admissible(self, s) -> np.ndarray:
        """Whether each section ``s`` (m) is a section of the member: not strictly inside
        one of :attr:`solid_spans`."""
        s = np.asarray(s, float)
        ok = np.ones(s.shape, bool)
        for a, b in self.solid_spans:
            ok &= ~((s > a) & (s < b))
        return ok

    def nearest_section(self, s) -> np.ndarray:
        """``s`` (m) with every value strictly inside a solid span moved to the nearer of
        its ends (sections of the member)."""
        out = np.array(s, float)
        for a, b in self.solid_spans:
            inside = (out > a) & (out < b)
            out = np.where(inside, np.where(out - a <= b - out, a, b), out)
        return out

    @property
    def polynomial_in_thickness(self) -> bool:
        """Whether scaling the thickness by ``k`` keeps the sections (``X``, ``n``, the
        fibres at ``X +- k t/2 n``) and makes the densities ``k`` times their terms in ``t``
        plus ``k^3`` times those in ``t^3``
        (:class:`~fembeam.fem.rigid.ThicknessFamily` relies on it).  False when the
        thickness moves the sections themselves (the crown joint of a pointed arch)."""
        return True

    @property
    def breaks(self) -> tuple[float, ...]:
        """Arc lengths (m, increasing, interior) where the densities of
        :meth:`inertia_densities` are not smooth: the kinks, plus e.g. the crown of a
        thickness law linear from each springing, or the knots of a spline.
        :meth:`segment_inertia` splits its Gauss rule there."""
        return self.kinks

    def angle_deg(self, s: np.ndarray) -> np.ndarray:
        """Reporting coordinate of a section (deg from the left end for arches)."""
        return np.asarray(s, dtype=float)

    def s_at_angle(self, angle_deg) -> np.ndarray:
        """Inverse of :meth:`angle_deg`: the arc length (m) of the section reported at
        ``angle_deg``.  Default: linear in ``s`` (shapes whose coordinate is not linear
        override it; where the coordinate jumps, at a kink, they return the kink)."""
        return np.asarray(angle_deg, float) * (self.length / float(self.angle_deg(self.length)))

    def inertia_densities(self, s: np.ndarray, power: int | None = None):
        """Mass, first and second moment (about the origin) per unit arc length.

        Exact for a thin annular-sector slice ``[s, s + ds]`` of thickness ``t``:
        ``mu0 = rho t``, ``mu1 = rho (t X - kappa t^3/12 n)`` (the centroid sits
        ``kappa t^2/12`` outward of the mid-curve point ``X``) and
        ``mu2 = rho (t |X|^2 - 2 kappa t^3/12 X.n + t^3/12)``.  ``power`` 1 or 3: only the
        terms in ``t`` or in ``t^3`` (a thickness scaled by ``k`` scales them by ``k``, ``k^3``).
        """
        X, n = self.position(s), self.normal(s)
        t, kap = self.thickness_at(s), self.curvature(s)
        one = self.density * t if power in (None, 1) else np.zeros(np.shape(s))
        i3 = self.density * t**3 / 12.0 if power in (None, 3) else np.zeros(np.shape(s))
        mu0 = one * np.ones(np.shape(s))
        mu1 = one * X - kap * i3 * n
        mu2 = one * np.sum(X * X, 0) - 2 * kap * i3 * np.sum(X * n, 0) + i3
        return mu0, mu1, mu2

    def segment_inertia(self, sa, sb, order: int = 24, power: int | None = None):
        """Mass ``m``, first moment ``S`` (2-vector) and polar moment ``J`` about the
        origin of the member pieces ``[sa, sb]`` (arrays), by Gauss-Legendre quadrature
        (``order`` points; a piece containing one of :attr:`breaks` is integrated as the
        sum of its smooth parts, so the rule never spans a kink); ``power``: the terms in
        ``t`` or ``t^3`` only (:meth:`inertia_densities`)."""
        sa, sb = np.atleast_1d(np.asarray(sa, float)), np.atleast_1d(np.asarray(sb, float))
        m, S, J = self._distributed_inertia(sa, sb, order, power)
        pts = self.point_inertia(sa, sb)
        if pts is None:
            return m, S, J
        return m + pts[0], S + pts[1], J + pts[2]

    def point_inertia(self, sa, sb):
        """Mass, first and polar moment (about the origin) of the masses concentrated at points
        of the pieces ``[sa, sb]`` (a point at ``s`` belongs to the piece with ``sa <= s < sb``,
        the right springing to the last piece; signed like :meth:`segment_inertia`), or None
        when the member has none (:func:`~fembeam.geometry.asbuilt.as_built` adds them)."""
        return None

    def _distributed_inertia(self, sa, sb, order, power):
        br = np.asarray(self.breaks, float)
        if br.size:
            sa, sb = np.broadcast_arrays(sa, sb)
            tol = 1e-13 * self.length
            lo, hi = np.minimum(sa, sb), np.maximum(sa, sb)
            inside = (br[None, :] > lo[:, None] + tol) & (br[None, :] < hi[:, None] - tol)
            if inside.any():
                return self._split_inertia(sa, sb, br, inside, order, power)
        return self._smooth_inertia(sa, sb, order, power)

    def _split_inertia(self, sa, sb, br, inside, order, power=None):
        """:meth:`segment_inertia` of pieces cut at the breaks ``br[inside[i]]`` of piece ``i``."""
        rows, cols = np.nonzero(inside)
        n = sa.size
        desc = sb < sa                                      # signed pieces: walk from sa to sb
        seg = np.concatenate([np.arange(n), rows])
        start = np.concatenate([sa, br[cols]])
        first = np.concatenate([np.zeros(n), np.ones(rows.size)])
        along = np.concatenate([np.zeros(n), np.where(desc[rows], -br[cols], br[cols])])
        order_ = np.lexsort((along, first, seg))
        seg, start = seg[order_], start[order_]
        end = np.empty_like(start)
        end[:-1] = start[1:]
        last = np.r_[seg[1:] != seg[:-1], True]
        end[last] = sb[seg[last]]
        m, S, J = self._smooth_inertia(start, end, order, power)
        return (np.bincount(seg, m, n), np.array([np.bincount(seg, S[0], n), np.bincount(seg, S[1], n)]),
                np.bincount(seg, J, n))

    def _smooth_inertia(self, sa, sb, order, power=None):
        xg, wg = _gauss(order)
        half = 0.5 * (sb - sa)
        s = 0.5 * (sa + sb)[:, None] + half[:, None] * xg[None, :]
        mu0, mu1, mu2 = self.inertia_densities(s, power)
        wq = half[:, None] * wg[None, :]
        return np.sum(mu0 * wq, 1), np.sum(mu1 * wq, 2), np.sum(mu2 * wq, 1)


@functools.lru_cache(maxsize=8)
def _gauss(order: int):
    return np.polynomial.legendre.leggauss(order)


def real_number(name: str, value, allowed: str) -> float:
    """``value`` as a float when it is a finite real number (an int, a float or a numpy
    scalar; not a bool, a string or an array); InputError saying ``allowed`` otherwise."""
    if isinstance(value, (bool, np.bool_)) or not isinstance(value, numbers.Real):
        raise InputError(f"{name} must be a number ({allowed}), got {value!r}")
    value = float(value)
    if not math.isfinite(value):
        raise InputError(f"{name} must be a finite number ({allowed}), got {value}")
    return value


def finite_positive(name: str, value, allowed: str) -> float:
    value = real_number(name, value, allowed)
    if value <= 0:
        raise InputError(f"{name} must be {allowed}, got {value}")
    return value


def _in_range(name: str, value, bounds: tuple[float, float], unit: str) -> float:
    lo, hi = bounds
    allowed = f"from {lo:g} to {hi:g} {unit}"
    value = real_number(name, value, allowed)
    if not lo * (1 - 1e-9) <= value <= hi * (1 + 1e-9):   # a ratio times a bound may round past it
        raise InputError(f"{name} must be {allowed}, got {value}")
    return value


def length_value(name: str, value) -> float:
    """A size of the member (m) inside :data:`LENGTH_RANGE`, else InputError."""
    return _in_range(name, value, LENGTH_RANGE, "m")


def thickness_value(name: str, value) -> float:
    """A thickness (m) inside :data:`THICKNESS_RANGE`, else InputError."""
    return _in_range(name, value, THICKNESS_RANGE, "m")


def density_value(value) -> float:
    """A density (kg/m^3) inside :data:`DENSITY_RANGE`, else InputError."""
    return _in_range("density", value, DENSITY_RANGE, "kg/m^3")
