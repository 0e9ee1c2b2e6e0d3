"""Plane mid-curves given by a parametrisation ``r(u)``, with the arc length computed
numerically.

A subclass gives ``r(u)`` and its first two derivatives (vectorised, m, m per unit of
``u``, ...) and the parameter breakpoints ``u_0 < ... < u_m`` between which ``r`` is
analytic.  This module then provides the functions of the arc length ``s`` (m, from
``r(u_0)``) that :class:`~fembeam.geometry.MidCurve` asks for:

* a table ``(u_i, s_i)`` of panel ends: composite Gauss-Legendre (``GL_ORDER`` points)
  of the speed ``|r'(u)|`` on panels bisected until each panel's integral agrees with
  the sum of its halves to ``1e-15`` of the length (so ``s_i`` is exact to ~1e-15 L);
* ``u(s)`` by Newton's method inside the panel of ``s``, ``F(u) = s_i + int_{u_i}^u
  |r'| - s`` with ``NEWTON_ORDER`` Gauss points on ``[u_i, u]`` (at least 512 panels:
  round-off accurate) and ``F' = |r'(u)|``, from the linear interpolation of the
  table, to ``|F| <= 4 eps L`` (two or three steps);
* position ``r(u(s))``, tangent ``r'/|r'|`` and curvature from the exact derivatives,
  ``kappa = -(x' y'' - y' x'') / |r'|^3`` (positive when the curve turns clockwise,
  i.e. towards the normal ``n = (t_y, -t_x)``, as an arch traversed left to right);
* the turning of the tangent (:class:`~fembeam.geometry.arch.ShapedArch`'s reporting
  coordinate): the rotation ``theta(u_0) - theta(u)`` of ``theta = atan2(y', x')`` when
  the curvature never changes sign (convex), else ``int |kappa| ds`` (table plus Gauss).

The last few ``u(s)`` are memoised (the analyses ask for position, normal, curvature and
thickness at the same sections in a row).
"""
from __future__ import annotations

import functools

import numpy as np

from ..errors import InputError

__all__ = ["ParametricCurve", "GL_ORDER"]

GL_ORDER = 20
NEWTON_ORDER = 10     # Gauss points of int_{u_i}^u |r'| in Newton's steps (panels are short)
_MAX_LEVELS = 40
_MEMO = 6            # arrays of u(s) remembered ...
_MEMO_SIZE = 200_000  # ... up to this many sections each
_TABLES: dict = {}


@functools.lru_cache(maxsize=4)
def _gl(order: int):
    return np.polynomial.legendre.leggauss(order)


class ParametricCurve:
    """Mixin: the arc-length machinery of the module docstring.  Subclasses implement
    ``_r(u)``, ``_dr(u)``, ``_ddr(u)`` (arrays ``(2, *u.shape)``) and ``_u_breaks()``
    (increasing parameter values, ends included), and call :meth:`_setup_arc_length`."""

    # ------------------------------------------------------------------ subclass API
    def _r(self, u):
        raise NotImplementedError

    def _dr(self, u):
        raise NotImplementedError

    def _ddr(self, u):
        raise NotImplementedError

    def _u_breaks(self) -> np.ndarray:
        raise NotImplementedError

    def _min_panels(self) -> int:
        return 512

    def _geometry_key(self):
        """Hashable description of the mid-curve (not of the thickness), under which the
        arc-length table is shared by the copies :meth:`with_thickness_scaled` makes;
        None: not shared."""
        return None

    # ------------------------------------------------------------------ arc length
    def _speed(self, u):
        d = self._dr(u)
        return np.hypot(d[0], d[1])

    def _panel_integral(self, f, a, b, order: int = GL_ORDER):
        """Gauss-Legendre of ``f`` (``order`` points) on the intervals ``[a, b]`` (arrays)."""
        xg, wg = _gl(order)
        half = 0.5 * (b - a)
        u = 0.5 * (a + b)[..., None] + half[..., None] * xg
        return half * np.sum(f(u) * wg, -1)

    def _setup_arc_length(self) -> None:
        """Build (or fetch) the table ``(u_i, s_i)``; set ``length`` and the convexity flag."""
        key = self._geometry_key()
        key = None if key is None else (type(self).__qualname__, key)
        table = _TABLES.get(key) if key is not None else None
        if table is None:
            table = self._arc_table()
            if key is not None:
                if len(_TABLES) >= 32:
                    _TABLES.pop(next(iter(_TABLES)))
                _TABLES[key] = table
        for name, value in table.items():
            object.__setattr__(self, name, value)
        object.__setattr__(self, "length", float(table["_s_tab"][-1]))
        object.__setattr__(self, "_memo", {})

    def _arc_table(self) -> dict:
        ub = np.asarray(self._u_breaks(), float)
        if ub.ndim != 1 or ub.size < 2 or np.any(np.diff(ub) <= 0):
            raise InputError("the parameter breakpoints of a curve must increase")
        per = max(1, -(-self._min_panels() // (ub.size - 1)))
        edges = np.concatenate([np.linspace(a, b, per + 1)[:-1] for a, b in zip(ub[:-1], ub[1:])] + [ub[-1:]])
        coarse = self._panel_integral(self._speed, edges[:-1], edges[1:])
        for _ in range(_MAX_LEVELS):
            mid = 0.5 * (edges[:-1] + edges[1:])
            left = self._panel_integral(self._speed, edges[:-1], mid)
            right = self._panel_integral(self._speed, mid, edges[1:])
            bad = np.abs(left + right - coarse) > 1e-15 * np.sum(coarse)
            if not bad.any():
                break
            # bisect the panels that have not converged; keep the halves' values
            new_edges, new_vals = [edges[0]], []
            for i in range(coarse.size):
                if bad[i]:
                    new_edges += [mid[i], edges[i + 1]]
                    new_vals += [left[i], right[i]]
                else:
                    new_edges.append(edges[i + 1])
                    new_vals.append(left[i] + right[i])
            edges, coarse = np.array(new_edges), np.array(new_vals)
        else:
            raise InputError("the arc length of the mid-curve does not converge (is the curve smooth "
                             "between its breakpoints?)")
        s_tab = np.concatenate([[0.0], np.cumsum(coarse)])
        # convex: the curvature has one sign (clockwise turning) at every Gauss node
        xg, _ = _gl(GL_ORDER)
        u = 0.5 * (edges[:-1] + edges[1:])[:, None] + 0.5 * np.diff(edges)[:, None] * xg
        k = self._kappa_u(np.concatenate([edges, u.ravel()]))
        convex = bool(np.all(k >= -1e-12 * np.max(np.abs(k))))
        turn = None
        if not convex:
            turn = self._panel_integral(lambda x: np.abs(self._kappa_u(x)) * self._speed(x), edges[:-1], edges[1:])
            turn = np.concatenate([[0.0], np.cumsum(turn)])
        for a in (edges, s_tab, turn):
            if a is not None:
                a.setflags(write=False)
        return {"_u_tab": edges, "_s_tab": s_tab, "_convex": convex, "_turn_tab": turn}

    def _u(self, s) -> np.ndarray:
        """Parameter of the sections at arc lengths ``s`` (m), clipped to the curve."""
        s = np.asarray(s, float)
        memo = self.__dict__["_memo"]
        key = (s.shape, s.tobytes()) if s.size <= _MEMO_SIZE else None
        hit = memo.get(key)
        if hit is not None:
            return hit
        ut, st = self._u_tab, self._s_tab
        L = st[-1]
        sf = np.clip(s.ravel(), 0.0, L)
        i = np.clip(np.searchsorted(st, sf, side="right") - 1, 0, st.size - 2)
        ua, ub, sa = ut[i], ut[i + 1], st[i]
        u = ua + (sf - sa) / (st[i + 1] - sa) * (ub - ua)
        tol = 4 * np.finfo(float).eps * L
        for _ in range(30):
            F = sa + self._panel_integral(self._speed, ua, u, NEWTON_ORDER) - sf
            u = np.clip(u - F / self._speed(u), ua, ub)
            if np.max(np.abs(F), initial=0.0) <= tol:
                break
        out = u.reshape(s.shape)
        out.setflags(write=False)
        if s.size <= _MEMO_SIZE:
            if len(memo) >= _MEMO:
                memo.pop(next(iter(memo)))
            memo[key] = out
        return out

    def _s_of_u(self, u) -> np.ndarray:
        """Arc length (m) at the parameters ``u`` (inverse of :meth:`_u`)."""
        u = np.asarray(u, float)
        ut, st = self._u_tab, self._s_tab
        uf = np.clip(u.ravel(), ut[0], ut[-1])
        i = np.clip(np.searchsorted(ut, uf, side="right") - 1, 0, ut.size - 2)
        return (st[i] + self._panel_integral(self._speed, ut[i], uf)).reshape(u.shape)

    # ------------------------------------------------------------------ MidCurve functions
    def position(self, s):
        return self._r(self._u(s))

    def tangent(self, s):
        d = self._dr(self._u(s))
        return d / np.hypot(d[0], d[1])

    def _kappa_u(self, u):
        d1, d2 = self._dr(u), self._ddr(u)
        return -(d1[0] * d2[1] - d1[1] * d2[0]) / np.hypot(d1[0], d1[1]) ** 3

    def curvature(self, s):
        return self._kappa_u(self._u(s))

    def _theta_u(self, u):
        d = self._dr(u)
        return np.arctan2(d[1], d[0])

    def _turning(self, s):
        u = self._u(s)
        if self._convex:
            return self._theta_u(np.asarray(self._u_tab[0])) - self._theta_u(u)
        ut, tt = self._u_tab, self._turn_tab
        i = np.clip(np.searchsorted(ut, u, side="right") - 1, 0, ut.size - 2)
        return tt[i] + self._panel_integral(lambda x: np.abs(self._kappa_u(x)) * self._speed(x), ut[i], u)
