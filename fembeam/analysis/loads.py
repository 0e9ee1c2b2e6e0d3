"""Live point loads: the load whose multiple at collapse is the load factor.

A live load ``P`` (kN per metre of width) acts downward at the extrados point above the
horizontal distance ``x`` (m) from the left springing of the mid-curve, on the piece whose
extrados lies under it (a point at the section ``s`` belongs to the piece with
``s_a <= s < s_b``, as the point masses of :mod:`fembeam.geometry.asbuilt`).  Unlike a mass
it has no inertia: the dynamic models do not see it.

In the statics (:mod:`~fembeam.analysis.statics`) the load factor ``lambda`` multiplies the
live loads while the dead loads (self weight, fill, masses) keep their values::

    B^T g = f_y + lambda f_P,   f_P . d = sum_i W_i v_y(X_i)

with ``W_i = P_i / g`` (kg/m: forces per unit g, like the weights in ``f_y``) and ``v_y(X_i)``
the upward velocity of the load's point in the field ``d``.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import scipy.sparse as sp

from ..errors import InputError
from ..geometry import MidCurve
from ..geometry.asbuilt import extrados, extrados_s, plain, point_pairs, span_of, _check_advancing
from ..units import per_g

__all__ = ["PointLoads"]


@dataclass(frozen=True, eq=False)
class PointLoads:
    """Downward point loads on ``curve``: ``pairs`` ``(n, 2)`` of ``(x, P)`` (m, kN/m), the
    sections ``s`` (m) and points ``X`` (2, n) where they act (extrados), ``W = P / g`` (kg/m)."""

    curve: MidCurve
    pairs: np.ndarray
    s: np.ndarray
    X: np.ndarray
    W: np.ndarray

    @classmethod
    def of(cls, curve: MidCurve, loads) -> "PointLoads | None":
        """The loads ``[(x, P), ...]`` on ``curve`` checked (``x`` in the span, ``P > 0`` kN/m);
        None when there is none."""
        if loads is None:
            return None
        if isinstance(loads, PointLoads):
            return loads
        _, span = span_of(curve)
        pairs = point_pairs(loads, "load", "kN/m", positive=True, span=span)
        if pairs.shape[0] == 0:
            return None
        _check_advancing(plain(curve), "a point load")
        s = extrados_s(curve, pairs[:, 0])
        return cls(curve, pairs, s, extrados(curve, s), per_g(pairs[:, 1]))

    @classmethod
    def each(cls, curve: MidCurve, xs, P: float) -> list["PointLoads"]:
        """One load ``P`` (kN/m) at each of the positions ``xs`` (m): a list of single loads,
        their sections found together (a load scan)."""
        _, span = span_of(curve)
        pairs = point_pairs([(x, P) for x in xs], "load", "kN/m", positive=True, span=span)
        _check_advancing(plain(curve), "a point load")
        s = extrados_s(curve, pairs[:, 0])
        X = extrados(curve, s)
        return [cls(curve, pairs[i:i + 1], s[i:i + 1], X[:, i:i + 1], per_g(pairs[i:i + 1, 1]))
                for i in range(pairs.shape[0])]

    @property
    def key(self) -> tuple:
        return tuple(map(tuple, self.pairs.tolist()))

    @property
    def total(self) -> float:
        """Sum of the loads (kg/m: per unit g)."""
        return float(np.sum(self.W))

    def elements(self, nodes_s: np.ndarray) -> np.ndarray:
        """The element of each load on a mesh with nodes ``nodes_s``."""
        return np.clip(np.searchsorted(nodes_s, self.s, side="right") - 1, 0, nodes_s.size - 2)

    def vector(self, disc) -> np.ndarray:
        """``f_P`` (3 n): ``f_P . d = sum_i W_i v_y(X_i)`` on the rigid elements of ``disc``."""
        if getattr(disc, "element", "rigid") != "rigid":
            raise InputError("point loads need the rigid elements (fembeam.discretize)")
        e = self.elements(disc.nodes_s)
        P, te, ne = disc.frames["P"][:, e], disc.frames["t"][:, e], disc.frames["n"][:, e]
        vals = self.W * np.array([te[1], ne[1], self.X[0] - P[0]])          # v_y = w t_y + v n_y + omega dx
        cols = 3 * e[None, :] + np.arange(3)[:, None]
        return np.asarray(sp.csr_matrix((vals.ravel(), (np.zeros(cols.size, int), cols.ravel())),
                                        shape=(1, disc.M.shape[0])).todense()).ravel()

    def prefix(self, s: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Sum of ``W`` and of ``W x`` (kg/m, kg) over the loads strictly left of the sections ``s``."""
        left = self.s[None, :] < np.asarray(s, float)[:, None]
        return left @ self.W, left @ (self.W * self.X[0])

    def to_list(self) -> list[dict]:
        return [{"x": float(x), "P": float(p)} for x, p in self.pairs]
