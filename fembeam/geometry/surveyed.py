"""Surveyed arch: a mid-curve (and optionally its thickness) measured at points from
springing to springing, interpolated by a smooth spline.

**Spline.** ``x``, ``y`` (and ``t``) are interpolated as functions of the cumulative
chord length ``u`` (m) of the points by ``scipy.interpolate.make_interp_spline`` with
not-a-knot ends: **quintic** (C4) from ``QUINTIC_FROM`` points on, cubic (C2) below.
Why: the curvature (second derivatives) must be continuous -- it enters the inertia
of every section and the normal cuts turn with it -- and the quintic's interpolation
error is far smaller (50 points of a parabola: positions to ~7e-8 of the span and
curvature to ~3e-5, against ~5e-6 and ~1.4e-3 for a cubic spline), while with few
points its end conditions overshoot (below ~12 points a cubic does better).  A
chord-length parameter (not ``x``) lets the curve be vertical or overhang at the
springings.  The spline's knots are :attr:`breaks`: Gauss rules never span them.

**Input** (:class:`~fembeam.errors.InputError` otherwise): 4 to 5000 points, finite,
consecutive points distinct, the polyline of the points without self-intersection and
the spline without loops or reversals between points (its tangent makes less than 90
degrees with each chord and turns by less than 90 degrees between two points).  Points
given from right to left are reversed (the mid-curve runs from the left springing).
The springings are the first and last points, at whatever height they are.

**Placement.** The spline is built in coordinates relative to the midpoint of the two
springings, which is the origin of :meth:`position` (as for the symmetric shapes): the
results do not depend on where the survey's coordinate system puts the arch (national-grid
coordinates lose no precision).  The span and the extent of the points must lie in
:data:`~fembeam.geometry.base.LENGTH_RANGE`, the ``t`` column in
:data:`~fembeam.geometry.base.THICKNESS_RANGE`.

**Thickness.** The ``t`` column (m, interpolated by the same spline) if given, else a
law (:mod:`~fembeam.geometry.thickness`) whose crown is the highest point of the
mid-curve.
"""
from __future__ import annotations

import csv
import dataclasses
import math
from dataclasses import dataclass

import numpy as np

from ..errors import InputError
from ..readers import read_text
from .arch import ShapedArch
from .base import DEFAULT_DENSITY, LENGTH_RANGE, THICKNESS_RANGE, density_value, finite_positive
from .parametric import ParametricCurve
from .thickness import thickness_law

__all__ = ["SurveyedArch", "QUINTIC_FROM", "MAX_POINTS", "read_midcurve_csv"]

QUINTIC_FROM = 12
MIN_POINTS = 4
MAX_POINTS = 5000                # the self-intersection check is quadratic: 5000 points build in ~2 s
MAX_FILE_BYTES = 16 * 2 ** 20    # 16 MiB: 5000 rows of numbers with room for comments


def read_midcurve_csv(path) -> dict:
    """Columns ``x,y`` and optionally ``t`` (m) of a CSV file, with a header naming them
    (any order, case-insensitive; other columns ignored) or without a header (two or
    three numeric columns in the order x, y, t).  Blank lines and lines starting with
    ``#`` are skipped.  Returns ``{"x": [...], "y": [...], "t": [...] or None}``.

    The file is read by :func:`fembeam.readers.read_text`: a regular UTF-8 file of at most
    :data:`MAX_FILE_BYTES`, with at most :data:`MAX_POINTS` points (counted before any is
    parsed)."""
    expect = "columns x,y and optionally t, in metres"
    text = read_text(path, "the mid-curve file", MAX_FILE_BYTES, kind="CSV", expect=expect)
    lines = [line for line in text.splitlines() if line.strip() and not line.lstrip().startswith("#")]
    if len(lines) > MAX_POINTS + 1:                  # + 1: a header
        raise InputError(f"the mid-curve file {str(path)!r} has {len(lines)} lines of data; a surveyed mid-curve "
                         f"has at most {MAX_POINTS} points (keep every k-th point)")
    try:
        rows = list(csv.reader(lines))
    except csv.Error:
        raise InputError(f"the mid-curve file {str(path)!r} is not a text CSV file (expected {expect})") from None
    if not rows:
        raise InputError(f"the mid-curve file {str(path)!r} is empty: expected columns x,y (and optionally t)")

    def number(text, line):
        try:
            return float(text)
        except ValueError:
            raise InputError(f"{str(path)!r} line {line}: expected a number, got {text.strip()!r} "
                             "(columns x,y and optionally t, in metres)") from None

    head = [c.strip().lower() for c in rows[0]]
    try:
        [float(c) for c in head]
        cols, body, first = {"x": 0, "y": 1, "t": 2 if len(head) > 2 else None}, rows, 1
    except ValueError:
        if "x" not in head or "y" not in head:
            raise InputError(f"{str(path)!r}: the header must name columns x and y (and optionally t), "
                             f"got {', '.join(rows[0])}") from None
        cols = {"x": head.index("x"), "y": head.index("y"), "t": head.index("t") if "t" in head else None}
        body, first = rows[1:], 2
    out = {k: [] for k in ("x", "y", "t")}
    for i, r in enumerate(body):
        for k, c in cols.items():
            if c is None:
                continue
            if c >= len(r):
                raise InputError(f"{str(path)!r} line {first + i}: missing column {k}")
            out[k].append(number(r[c], first + i))
    out["t"] = out["t"] if cols["t"] is not None else None
    return out


def _segments_cross(P: np.ndarray) -> bool:
    """Whether two non-adjacent segments of the polyline ``P`` (n, 2) intersect."""
    A, B = P[:-1], P[1:]
    n = A.shape[0]

    def orient(p, q, r):
        return (q[..., 0] - p[..., 0]) * (r[..., 1] - p[..., 1]) - (q[..., 1] - p[..., 1]) * (r[..., 0] - p[..., 0])

    for i0 in range(0, n, 256):
        i = np.arange(i0, min(n, i0 + 256))[:, None]
        j = np.arange(n)[None, :]
        a, b, c, d = A[i], B[i], A[j], B[j]
        d1, d2 = orient(c, d, a), orient(c, d, b)
        d3, d4 = orient(a, b, c), orient(a, b, d)
        hit = (d1 * d2 <= 0) & (d3 * d4 <= 0) & (j > i + 1)
        if hit.any():
            return True
    return False


@dataclass(frozen=True)
class SurveyedArch(ParametricCurve, ShapedArch):
    """Surveyed arch: a smooth spline through measured points of its mid-curve.

    ``x``, ``y`` (and ``t``) are interpolated as functions of the cumulative chord length
    of the points (quintic spline from ``QUINTIC_FROM`` points on, cubic below); the
    springings are the first and last points, at whatever height they are; points given
    from right to left are reversed. Arrays are stored as tuples (the member is hashable
    and comparable).

    Parameters
    ----------
    x, y : array_like
        Points of the mid-curve (m), springing to springing: 4 to 5000 of them, finite,
        consecutive points distinct, the polyline without self-intersection.
    t : array_like, optional
        Thickness at each point (m), interpolated by the same spline. Or, instead:
    thickness : float, optional
        Constant thickness (m). Or:
    thickness_springing, thickness_crown : float, optional
        Thickness at the springings and at the crown (m, the highest point of the
        mid-curve), linear in the arc length in between.
    density : float, optional
        Density of the masonry (kg/m^3; masses are per metre of barrel width), default
        :data:`~fembeam.geometry.base.DEFAULT_DENSITY` (2000).

    Raises
    ------
    InputError
        Points or thickness out of range, a spline with loops or reversals, or a
        thickness given twice or not at all.

    Examples
    --------
    Nine points of a parabola of span 4 m and rise 1 m:

    >>> import numpy as np
    >>> import fembeam
    >>> x = np.linspace(-2.0, 2.0, 9)
    >>> arch = fembeam.SurveyedArch(x=x, y=1.0 - (x / 2.0) ** 2, thickness=0.3)
    >>> print(f"L = {arch.length:.4f} m")
    L = 4.5911 m
    """

    x: tuple = ()
    y: tuple = ()
    t: tuple | None = None
    thickness: float | None = None
    thickness_springing: float | None = None
    thickness_crown: float | None = None
    density: float = DEFAULT_DENSITY

    shape = "surveyed"

    @classmethod
    def from_csv(cls, path, thickness=None, thickness_springing=None, thickness_crown=None,
                 density: float = DEFAULT_DENSITY) -> "SurveyedArch":
        """From a CSV file with columns ``x,y`` and optionally ``t`` (:func:`read_midcurve_csv`)."""
        d = read_midcurve_csv(path)
        return cls(d["x"], d["y"], d["t"], thickness, thickness_springing, thickness_crown, density)

    def __post_init__(self):
        object.__setattr__(self, "density", density_value(self.density))
        x, y = self._column("x", self.x), self._column("y", self.y)
        t = None if self.t is None else self._column("t", self.t)
        if x.size != y.size or (t is not None and t.size != x.size):
            raise InputError(f"the columns x, y{', t' if t is not None else ''} must have as many values, got "
                             f"{x.size}, {y.size}{', ' + str(t.size) if t is not None else ''}")
        if not MIN_POINTS <= x.size <= MAX_POINTS:
            raise InputError(f"a surveyed mid-curve needs at least {MIN_POINTS} points and has at most {MAX_POINTS}, "
                             f"got {x.size}")
        if x[-1] < x[0]:                       # given from right to left: run from the left springing
            x, y, t = x[::-1], y[::-1], (None if t is None else t[::-1])
        object.__setattr__(self, "x", tuple(map(float, x)))
        object.__setattr__(self, "y", tuple(map(float, y)))
        object.__setattr__(self, "t", None if t is None else tuple(map(float, t)))
        if t is not None:
            if any(v is not None for v in (self.thickness, self.thickness_springing, self.thickness_crown)):
                raise InputError("the thickness is given twice: by the t column and by a thickness law; give one")
            lo, hi = THICKNESS_RANGE
            if np.any(t <= 0):
                raise InputError(f"the t column must be positive (m), got min {np.min(t):g}")
            if not (lo * (1 - 1e-9) <= np.min(t) and np.max(t) <= hi * (1 + 1e-9)):
                raise InputError(f"the t column must be from {lo:g} to {hi:g} m, got {np.min(t):g} to {np.max(t):g}")
            law = None
        else:
            law = thickness_law(self.thickness, self.thickness_springing, self.thickness_crown)
        P = np.column_stack([x, y])
        with np.errstate(over="ignore"):       # inf: far too large
            extent, (lo, hi) = float(np.max(np.ptp(P, axis=0))), LENGTH_RANGE
        if not extent <= hi:
            raise InputError(f"the surveyed points must lie within {hi:g} m of each other, got an extent of "
                             f"{extent:g} m")
        chord = np.hypot(*np.diff(P, axis=0).T)
        total = float(np.sum(chord))
        if not total > 0 or np.min(chord) <= 1e-9 * total:
            k = int(np.argmin(chord))
            raise InputError(f"consecutive points must be distinct: points {k + 1} and {k + 2} coincide")
        if abs(x[-1] - x[0]) <= 1e-9 * total:
            raise InputError("the springings (first and last points) must be apart horizontally")
        if abs(x[-1] - x[0]) < lo:
            raise InputError(f"the span of the surveyed arch must be from {lo:g} to {hi:g} m, "
                             f"got {abs(x[-1] - x[0]):g} m")
        if _segments_cross(P):
            raise InputError("the polyline of the points intersects itself: give the points in order "
                             "along the mid-curve, from springing to springing")
        P = P - 0.5 * (P[0] + P[-1])           # the origin at the midpoint of the springings
        u = np.concatenate([[0.0], np.cumsum(chord)])
        from scipy.interpolate import make_interp_spline   # imported here: only surveyed shapes use it

        k = 5 if x.size >= QUINTIC_FROM else 3
        object.__setattr__(self, "_u_pts", u)
        object.__setattr__(self, "_degree", k)
        object.__setattr__(self, "_spline", make_interp_spline(u, P, k=k))
        object.__setattr__(self, "_tspline", None if t is None else make_interp_spline(u, t, k=k))
        self._check_spline(u, P)
        self._setup_arc_length()
        object.__setattr__(self, "_law", law)
        object.__setattr__(self, "_crown_s", self._highest_s())
        if law is not None and not law.constant and not 1e-6 < self._crown_s / self.length < 1 - 1e-6:
            raise InputError("a thickness linear from the springings to the crown needs a crown (the highest "
                             "point) between the springings; give a constant thickness or a t column")
        if t is not None:
            ts = self._tspline(np.linspace(0.0, u[-1], 16 * u.size))
            if np.min(ts) <= 0:
                raise InputError("the thickness interpolated between the points of the t column drops to "
                                 f"{np.min(ts):.3g} m: give more points where it varies quickly")
        self._check_thickness()

    @staticmethod
    def _column(name, values) -> np.ndarray:
        try:
            if isinstance(values, (str, bytes)) or any(isinstance(v, (bool, np.bool_, str, bytes)) for v in values):
                raise TypeError
            a = np.asarray(values, dtype=float)
        except (TypeError, ValueError):
            raise InputError(f"column {name} must be numbers (m)") from None
        if a.ndim != 1:
            raise InputError(f"column {name} must be a sequence of numbers (m)")
        if not np.all(np.isfinite(a)):
            raise InputError(f"column {name} must be finite, got {a[~np.isfinite(a)][0]}")
        return a

    def _check_spline(self, u, P) -> None:
        q = np.linspace(0.0, 1.0, 9)[:-1]
        uu = (u[:-1, None] + np.diff(u)[:, None] * q).ravel()
        d = self._dr(uu).reshape(2, u.size - 1, q.size)
        c = np.diff(P, axis=0).T[:, :, None]
        cosang = np.sum(d * c, 0) / (np.hypot(d[0], d[1]) * np.hypot(c[0], c[1]))
        if np.min(cosang) <= 0:
            i = int(np.argmin(np.min(cosang, 1)))
            raise InputError(f"the spline through the points turns back between points {i + 1} and {i + 2} "
                             "(points out of order, or too sparse where the curve bends)")
        th = np.unwrap(np.arctan2(d[1], d[0]).ravel()).reshape(d.shape[1:])
        ends = self._dr(u)
        th_end = np.unwrap(np.arctan2(ends[1], ends[0]))
        turn = np.abs(np.diff(th_end))
        if np.max(turn) >= 0.5 * math.pi or np.any(np.abs(th - th[:, :1]) >= 0.5 * math.pi):
            i = int(np.argmax(turn))
            raise InputError(f"the mid-curve turns by 90 degrees or more between points {i + 1} and {i + 2}: "
                             "give more points there")

    # ------------------------------------------------------------------ parametrisation
    def _geometry_key(self):
        return (self.x, self.y)

    def _u_breaks(self):
        kn = np.unique(self._spline.t)
        return kn[(kn >= 0.0) & (kn <= self._u_pts[-1])]

    def _min_panels(self) -> int:
        return max(512, 8 * len(self.x))

    def _smooth_breaks(self):
        kn = self._u_breaks()[1:-1]
        return tuple(float(v) for v in self._s_of_u(kn))

    def _r(self, u):
        return np.moveaxis(self._spline(np.asarray(u, float)), -1, 0)

    def _dr(self, u):
        return np.moveaxis(self._spline(np.asarray(u, float), 1), -1, 0)

    def _ddr(self, u):
        return np.moveaxis(self._spline(np.asarray(u, float), 2), -1, 0)

    def _highest_s(self) -> float:
        uu = np.linspace(0.0, self._u_pts[-1], 64 * len(self.x) + 1)
        i = int(np.argmax(self._r(uu)[1]))
        a, b = uu[max(i - 1, 0)], uu[min(i + 1, uu.size - 1)]
        from scipy.optimize import minimize_scalar

        r = minimize_scalar(lambda v: -float(self._r(v)[1]), bounds=(a, b), method="bounded",
                            options={"xatol": 1e-13 * self._u_pts[-1]})
        return float(self._s_of_u(r.x))

    # ------------------------------------------------------------------ thickness
    @property
    def _span(self) -> float:
        return abs(self.x[-1] - self.x[0])

    def thickness_at(self, s):
        if self._law is not None:
            return ShapedArch.thickness_at(self, s)
        return self._tspline(self._u(s))

    def with_thickness_scaled(self, factor: float) -> "SurveyedArch":
        if self._law is not None:
            return ShapedArch.with_thickness_scaled(self, factor)
        factor = finite_positive("thickness factor", factor, "positive")
        return dataclasses.replace(self, t=tuple(v * factor for v in self.t))

    def _thickest(self) -> float:
        if self._law is not None:
            return self._law.maximum
        return float(np.max(self._tspline(np.linspace(0.0, self._u_pts[-1], 16 * len(self.x)))))

    def _thinnest(self) -> float:
        if self._law is not None:
            return ShapedArch._thinnest(self)
        return float(np.min(self._tspline(np.linspace(0.0, self._u_pts[-1], 16 * len(self.x)))))

    def describe(self) -> dict:
        xy = self._r(np.array([self._u(0.0), self._u(self.length)]))
        rise = float(self._r(self._u(self._crown_s))[1] - 0.5 * (xy[1][0] + xy[1][1]))
        th = (self._law.describe() if self._law is not None else
              {"thickness": "t column", "thickness_min": min(self.t), "thickness_max": max(self.t)})
        return {"shape": "surveyed", "span": self._span, "rise": rise, "points": len(self.x),
                "spline": "quintic" if self._degree == 5 else "cubic", **th, "density": self.density,
                "length": self.length}
