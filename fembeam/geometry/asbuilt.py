"""Arches as built: fill up to a road and permanent point masses carried by the pieces.

The model (stated once; the docs page "Arches as built" repeats it):

* **Fill.**  A fill of density ``rho_f`` (kg/m^3) lies on the extrados up to a horizontal road
  at height ``y_road = y_crown + D``, ``D`` (m) above the highest point of the extrados (the
  crown's extrados).  The column of fill above each piece's extrados, between the verticals
  through the two ends of that extrados, up to the road, is carried by that piece: its weight
  acts at the column's centroid and, in every dynamic model, it moves rigidly with the piece
  (its mass, first moment and polar moment are added to the piece's).  Left out: the spread of
  load through the fill, the passive pressure of the fill on the arch, the fill's own
  strength and its friction on the extrados.
* **Point masses.**  A mass ``M`` (kg per metre of width) at the horizontal distance ``x`` (m)
  from the left springing of the mid-curve, on the extrados point above it, is carried by the
  piece whose extrados lies under it: a dead load in the statics, a mass moving with its piece
  in the dynamics.

Everything is per metre of barrel width.  Both enter through the member's inertia only: the
fill as densities per unit arc length (:meth:`MidCurve.inertia_densities`), the masses as
concentrated terms of :meth:`MidCurve.point_inertia`, so that every model built on
:meth:`MidCurve.segment_inertia` and on the mass matrix carries them.

Fill densities.  With the extrados point ``E(s) = X(s) - t(s)/2 n(s)`` of the section at
``s``, the column over the slice ``[s, s + ds]`` has width ``E_x'(s) ds`` (the extrados must
advance to the right: ``E_x' >= 0``, i.e. no horseshoe) and spans ``E_y <= y <= y_road``::

    mu0 = rho_f h E_x',   mu1 = mu0 (E_x, (y_road + E_y) / 2),
    mu2 = rho_f E_x' (h E_x^2 + (y_road^3 - E_y^3) / 3),   h = y_road - E_y,

exact for the column; ``E_x'`` by a fourth-order one-sided difference inside the smooth part
of the curve (never across one of its breaks).
"""
from __future__ import annotations

import copy
import dataclasses
import math
from dataclasses import dataclass

import numpy as np

from ..errors import InputError
from .base import MidCurve, real_number
from .block import StraightMember

__all__ = ["Fill", "as_built", "build", "is_built", "plain", "point_sections", "extrados_s", "extrados", "span_of", "point_pairs", "FILL_DENSITY_RANGE"]

FILL_DENSITY_RANGE = (0.0, 1e5)   # kg/m^3
MASS_MAX = 1e12                   # kg per metre of width
LOAD_RANGE = (1e-6, 1e9)          # kN per metre of width


@dataclass(frozen=True)
class Fill:
    """Fill of ``density`` (kg/m^3) up to a road ``depth`` (m) above the crown's extrados."""

    density: float
    depth: float = 0.0

    def __post_init__(self):
        lo, hi = FILL_DENSITY_RANGE
        d = real_number("fill density", self.density, f"from {lo:g} to {hi:g} kg/m^3")
        if not lo <= d <= hi:
            raise InputError(f"fill density must be from {lo:g} to {hi:g} kg/m^3, got {d:g}")
        h = real_number("fill depth", self.depth, "a height in m >= 0 of the road above the crown's extrados")
        if not 0.0 <= h <= 1e6:
            raise InputError(f"fill depth must be from 0 to 1e6 m (the road above the crown's extrados; "
                             f"a road below it is not allowed), got {h:g}")
        object.__setattr__(self, "density", d)
        object.__setattr__(self, "depth", h)

    def to_dict(self) -> dict:
        return {"density": self.density, "depth": self.depth}


def extrados(curve: MidCurve, s) -> np.ndarray:
    """Extrados points ``E(s) = X - t/2 n`` (2, ...) of the sections at ``s`` (m)."""
    s = np.asarray(s, float)
    return curve.point(s, -0.5 * np.asarray(curve.thickness_at(s), float))


def span_of(curve: MidCurve) -> tuple[float, float]:
    """``(x0, span)``: the left springing's x and the horizontal span of the mid-curve (m)."""
    a, b = curve.position(np.array([0.0, curve.length]))[0]
    return float(a), float(b - a)


def _check_advancing(curve: MidCurve, what: str) -> None:
    s = np.linspace(0.0, curve.length, 4001)
    ex = extrados(curve, s)[0]
    if np.any(np.diff(ex) < -1e-9 * curve.length):
        raise InputError(f"{what} needs an extrados that advances from the left springing to the right one "
                         f"(its x increasing: no horseshoe arch, embrace <= 180 deg)")


def extrados_s(curve: MidCurve, x) -> np.ndarray:
    """Arc lengths (m) of the sections whose extrados point lies above the horizontal
    distances ``x`` (m) from the left springing of the mid-curve (bisection on ``E_x``)."""
    x0, _ = span_of(curve)
    target = x0 + np.atleast_1d(np.asarray(x, float))
    lo, hi = np.zeros(target.shape), np.full(target.shape, float(curve.length))
    for _ in range(200):
        mid = 0.5 * (lo + hi)
        left = extrados(curve, mid)[0] < target
        lo, hi = np.where(left, mid, lo), np.where(left, hi, mid)
        if np.all(hi - lo <= 4e-16 * curve.length):
            break
    return 0.5 * (lo + hi)


def point_pairs(pairs, what: str, unit: str, positive: bool, span: float) -> np.ndarray:
    """``pairs`` ``[(x, value), ...]`` checked: ``x`` in ``[0, span]`` m, ``value`` > 0 (``positive``)
    or >= 0; an array ``(n, 2)``."""
    out = []
    for item in pairs:
        try:
            x, v = item
        except (TypeError, ValueError):
            raise InputError(f"a {what} is a pair (x in m, value in {unit}), got {item!r}") from None
        x = real_number(f"{what} position x", x, f"from 0 to the span {span:g} m")
        v = real_number(f"{what} value", v, f"{'> 0' if positive else '>= 0'} {unit}")
        if not -1e-12 * span <= x <= span * (1 + 1e-12):
            raise InputError(f"{what} at x = {x:g} m is outside the span: x must be from 0 to {span:g} m "
                             f"(horizontal distance from the left springing of the mid-curve)")
        lo, hi = (LOAD_RANGE if positive else (0.0, MASS_MAX))
        if not lo <= v <= hi:
            raise InputError(f"{what} value must be from {lo:g} to {hi:g} {unit}, got {v:g}")
        out.append((min(max(x, 0.0), span), v))
    return np.array(out, float).reshape(-1, 2)


def point_sections(curve: MidCurve) -> np.ndarray:
    """Arc lengths (m) of the point masses of ``curve`` (where its internal forces jump)."""
    b = getattr(curve, "_built", None)
    return np.empty(0) if b is None else np.array(b["s_m"], float)


def is_built(curve: MidCurve) -> bool:
    """Whether ``curve`` carries fill or point masses (:func:`as_built`)."""
    return getattr(curve, "_built", None) is not None


def plain(curve: MidCurve) -> MidCurve:
    """The bare member under ``curve``'s fill and masses (``curve`` itself if it has none)."""
    b = getattr(curve, "_built", None)
    return curve if b is None else b["plain"]


def as_built(curve: MidCurve, fill: Fill | None = None, masses=(), road_level: float | None = None) -> MidCurve:
    """``curve`` carrying ``fill`` (:class:`Fill`) and point ``masses`` ``[(x, M), ...]`` (m from
    the left springing, kg per metre of width): a copy whose inertia includes them (the
    module docstring).  ``curve`` itself when there is neither.  ``road_level`` (m): the road's
    height, kept when the thickness is scaled (default: ``fill.depth`` above the extrados's
    highest point)."""
    if not isinstance(curve, MidCurve):
        raise InputError(f"as_built needs a member (e.g. fembeam.CircularArch), got {type(curve).__name__}")
    base = plain(curve)
    if fill is not None and not isinstance(fill, Fill):
        raise InputError(f"fill must be a fembeam.geometry.Fill, got {type(fill).__name__}")
    if fill is not None and fill.density == 0:
        fill = None
    x0, span = span_of(base)
    pairs = point_pairs(masses, "mass", "kg/m", positive=False, span=span)
    pairs = pairs[pairs[:, 1] > 0] if pairs.size else pairs
    if fill is None and pairs.shape[0] == 0:
        return base
    if isinstance(base, StraightMember):
        raise InputError("fill and point masses apply to arches, not to a block")
    _check_advancing(base, "fill or a point mass")
    s_m = extrados_s(base, pairs[:, 0]) if pairs.shape[0] else np.empty(0)
    X_m = extrados(base, s_m) if pairs.shape[0] else np.empty((2, 0))
    road = None
    if fill is not None:
        if fill.depth > 10.0 * span:
            raise InputError(f"fill depth must be at most 10 spans ({10.0 * span:g} m) above the crown's extrados, "
                             f"got {fill.depth:g} m")
        road = float(road_level) if road_level is not None else _top_of_extrados(base) + fill.depth
    built = {"plain": base, "fill": fill, "road": road, "pairs": pairs, "s_m": s_m, "X_m": X_m,
             "M": pairs[:, 1] if pairs.shape[0] else np.empty(0)}
    cls = _built_class(type(base))
    out = copy.copy(base)
    object.__setattr__(out, "__class__", cls)   # frozen dataclasses: bypass their __setattr__
    object.__setattr__(out, "_built", built)
    return out


def _top_of_extrados(curve: MidCurve) -> float:
    """Height (m) of the highest point of the extrados (sampled, then golden-section search)."""
    s = np.linspace(0.0, curve.length, 4001)
    y = extrados(curve, s)[1]
    i = int(np.argmax(y))
    a, b = s[max(i - 1, 0)], s[min(i + 1, s.size - 1)]
    g = (math.sqrt(5) - 1) / 2
    for _ in range(80):
        c, d = b - g * (b - a), a + g * (b - a)
        if extrados(curve, c)[1] >= extrados(curve, d)[1]:
            b = d
        else:
            a = c
    return float(max(y[i], extrados(curve, 0.5 * (a + b))[1]))


_CLASSES: dict = {}


def _built_class(base: type) -> type:
    cls = _CLASSES.get(base)
    if cls is None:
        cls = type(f"{base.__name__}AsBuilt", (_AsBuilt, base), {"__module__": __name__})
        _CLASSES[base] = cls
    return cls


class _AsBuilt:
    """Mixed in before a member's class by :func:`as_built`: its inertia with fill and masses."""

    _built: dict

    @property
    def polynomial_in_thickness(self) -> bool:
        return False           # the extrados, hence the columns and the masses, move with the thickness

    @property
    def fill(self) -> Fill | None:
        return self._built["fill"]

    @property
    def road_level(self) -> float | None:
        return self._built["road"]

    @property
    def masses(self) -> np.ndarray:
        """``(n, 2)``: the point masses ``(x, M)`` (m from the left springing, kg/m)."""
        return self._built["pairs"]

    def __reduce__(self):          # picklable (worker processes): rebuilt from the bare member
        b = self._built
        return as_built, (b["plain"], b["fill"], b["pairs"], b["road"])

    def __eq__(self, other):
        if not isinstance(other, _AsBuilt):
            return NotImplemented
        a, b = self._built, other._built
        return (a["plain"] == b["plain"] and a["fill"] == b["fill"] and a["road"] == b["road"]
                and np.array_equal(a["pairs"], b["pairs"]))

    def __hash__(self):
        b = self._built
        return hash((b["plain"], b["fill"], b["road"], b["pairs"].tobytes()))

    def with_thickness_scaled(self, factor: float) -> MidCurve:
        """The same arch with its thickness law scaled by ``factor``, the fill up to a road the
        same depth above the scaled crown's extrados (a family of arches defined by the depth),
        the masses at the same ``x``."""
        b = self._built
        return as_built(b["plain"].with_thickness_scaled(factor), b["fill"], b["pairs"])

    def inertia_densities(self, s, power: int | None = None):
        mu0, mu1, mu2 = super().inertia_densities(s, power)
        fill = self._built["fill"]
        if fill is None:
            return mu0, mu1, mu2
        if power is not None:
            raise InputError("a filled arch's densities are not polynomial in the thickness")
        s = np.asarray(s, float)
        E, dEx = self._extrados_rate(s)
        H = self._built["road"]
        top = np.maximum(H, E[1])
        f0 = fill.density * (top - E[1]) * dEx
        c1 = np.array([E[0], 0.5 * (top + E[1])])
        f2 = fill.density * dEx * ((top - E[1]) * E[0] ** 2 + (top ** 3 - E[1] ** 3) / 3.0)
        return mu0 + f0, mu1 + f0 * c1, mu2 + f2

    def point_inertia(self, sa, sb):
        b = self._built
        if b["M"].size == 0:
            return None
        sa, sb = np.broadcast_arrays(np.atleast_1d(np.asarray(sa, float)), np.atleast_1d(np.asarray(sb, float)))
        lo, hi = np.minimum(sa, sb)[:, None], np.maximum(sa, sb)[:, None]
        s_m, L = b["s_m"][None, :], float(self.length)
        inside = (s_m >= lo) & ((s_m < hi) | ((s_m == hi) & (hi >= L)))
        w = np.where(sb < sa, -1.0, 1.0)[:, None] * inside * b["M"][None, :]
        X = b["X_m"]
        return w.sum(1), np.array([w @ X[0], w @ X[1]]), w @ np.sum(X * X, 0)

    def describe(self) -> dict:
        out = dict(super().describe())
        b = self._built
        out["fill"] = None if b["fill"] is None else {**b["fill"].to_dict(), "road_level": b["road"]}
        out["masses"] = [{"x": float(x), "M": float(m)} for x, m in b["pairs"]]
        return out

    def _extrados_rate(self, s: np.ndarray):
        """``E(s)`` and ``E_x'(s)``.  On sections normal to the mid-curve
        ``E' = (1 + kappa t / 2) T - t' / 2 n`` (``dT/ds = kappa n``, ``dn/ds = -kappa T``), with
        ``t'`` zero for a constant thickness; elsewhere (a pointed arch's crown wedges, a thickness
        that varies) by :meth:`_difference`."""
        s = np.asarray(s, float)
        T, kap, t = self.tangent(s), self.curvature(s), np.asarray(self.thickness_at(s), float)
        n = np.array([T[1], -T[0]])
        E = self.position(s) - 0.5 * t * n
        if not self._built.setdefault("constant_t", _constant_thickness(self)):
            return E, self._difference(s, E)
        d = (1.0 + 0.5 * kap * t) * T[0]
        fan = ~self.admissible(s)
        if np.any(fan):
            d = np.array(d, float)
            d[fan] = self._difference(s[fan], E[:, fan])
        return E, np.maximum(d, 0.0)

    def _difference(self, s: np.ndarray, E: np.ndarray) -> np.ndarray:
        """``E_x'(s)`` by fourth-order one-sided differences on the side of ``s`` with more room
        before the next break or end (the stencil inside the smooth part of the curve)."""
        L = float(self.length)
        marks = np.concatenate([[0.0], np.asarray(self.breaks, float), [L]])
        j = np.clip(np.searchsorted(marks, s, side="right"), 1, marks.size - 1)
        room_r, room_l = marks[j] - s, s - marks[j - 1]
        forward = room_r >= room_l
        h = np.minimum(2e-4 * L, np.maximum(room_r, room_l) / 4.5)
        h = np.where(forward, h, -h)
        ex = [extrados(self, s + i * h)[0] for i in range(1, 5)]
        d = (-25.0 * E[0] + 48.0 * ex[0] - 36.0 * ex[1] + 16.0 * ex[2] - 3.0 * ex[3]) / (12.0 * h)
        return np.maximum(d, 0.0)


def _constant_thickness(curve: MidCurve) -> bool:
    """Whether the thickness of ``curve``'s normal sections is one constant (sampled exactly)."""
    s = np.linspace(0.0, curve.length, 1001)
    s = s[curve.admissible(s)]
    t = np.asarray(curve.thickness_at(s), float)
    return bool(np.all(t == t[0]))


def build(curve: MidCurve, density: float | None = None, fill_density: float | None = None,
          fill_depth: float | None = None, masses=()) -> MidCurve:
    """``curve`` as built, from the keyword arguments of the Python API (the options of the
    command line): ``density`` (kg/m^3, replaces the member's), ``fill_density`` (kg/m^3) and
    ``fill_depth`` (m, the road above the crown's extrados; default 0), ``masses``
    ``[(x, M), ...]`` (m, kg/m)."""
    if density is not None:
        base = plain(curve)
        if not dataclasses.is_dataclass(base):
            raise InputError(f"{type(base).__name__} does not take a density")
        curve = as_built(dataclasses.replace(base, density=density),
                         getattr(curve, "fill", None), getattr(curve, "masses", ()))
    if fill_depth is not None and fill_density is None:
        raise InputError("--fill-depth needs --fill-density (the fill's density, kg/m^3)")
    fill = None if fill_density is None else Fill(fill_density, 0.0 if fill_depth is None else fill_depth)
    if fill is None and len(masses) == 0:
        return curve
    if is_built(curve):
        fill = fill if fill is not None else curve.fill
        masses = list(map(tuple, curve.masses)) + list(masses)
    return as_built(curve, fill, masses)
