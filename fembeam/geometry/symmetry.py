"""Whether a member and its loads are symmetric about a vertical axis (to round-off).

A member symmetric about a vertical axis moves under the ground acceleration ``-a_g(t)`` as the
mirror image of its motion under ``a_g(t)``: a study that would run both signs of a record can run
one and mirror it.  The question is decided here, once, from the geometry:

* **the mid-curve and its thickness**: either the mirror maps the member onto itself with its
  arc length reversed (an arch: ``X(L - s)`` is the mirror of ``X(s)`` and ``t(L - s) = t(s)``,
  both ends of the same kind), or it maps every section onto itself (a vertical straight member:
  ``X_x(s)`` constant, a block);
* **what the shape is built with**: its kinks, fixed nodes, solid spans and breaks mirrored onto
  themselves (``s -> L - s``);
* **the cuts of the model** (``nodes``, the arc lengths of the voussoirs' or elements' ends, when
  given): a mesh that puts one more piece on one side (a pointed arch with an odd number of
  voussoirs) is not symmetric, whatever the shape;
* **as built** (:mod:`~fembeam.geometry.asbuilt`): a fill up to a horizontal road on a symmetric
  arch is symmetric; the point masses ``(x, M)`` must be the same at ``x`` and ``span - x``;
* **live loads** (``loads``: a :class:`~fembeam.analysis.loads.PointLoads` or pairs ``(x, P)``):
  the same rule as the masses.

Round-off: positions and thicknesses agree to ``tol`` times the member's length (default
:data:`TOL`), masses and loads to ``tol`` relatively.  The shapes fembeam builds from
parameters (blocks, circular, pointed, elliptical, parabolic, catenary arches) agree to about
1e-15; a surveyed arch is symmetric only if its spline is, to that tolerance (a real survey is not).
"""
from __future__ import annotations

import numpy as np

from ..errors import InputError
from .base import MidCurve

__all__ = ["is_symmetric", "TOL", "SAMPLES"]

TOL = 1e-9          # relative to the member's length (positions, thicknesses), or to the value (masses, loads)
SAMPLES = 2001      # sections compared along the mid-curve (plus the shape's own marks)


def _mirrored(values, L: float, tol: float) -> bool:
    v = np.sort(np.asarray(values, float).ravel())
    return v.size == 0 or bool(np.allclose(np.sort(L - v), v, rtol=0.0, atol=tol * L))


def _pairs_mirrored(pairs, span: float, tol: float) -> bool:
    """Whether the pairs ``(x, value)`` (m, any unit) are the same at ``x`` and ``span - x``."""
    p = np.asarray(pairs, float).reshape(-1, 2)
    if p.shape[0] == 0:
        return True
    used = np.zeros(p.shape[0], bool)
    for x, v in p:
        hit = np.nonzero(~used & (np.abs(p[:, 0] - (span - x)) <= tol * max(span, 1e-300))
                         & (np.abs(p[:, 1] - v) <= tol * abs(v)))[0]
        if hit.size == 0:
            return False
        used[hit[0]] = True
    return True


def is_symmetric(curve: MidCurve, loads=None, nodes=None, tol: float = TOL) -> bool:
    """Whether ``curve`` (with its fill and point masses), the live ``loads`` and the model's
    cuts ``nodes`` (arc lengths, m) are symmetric about a vertical axis, to ``tol`` (module
    docstring).  :class:`InputError` for something that is not a member."""
    from .asbuilt import plain, span_of

    if not isinstance(curve, MidCurve):
        raise InputError(f"is_symmetric needs a member (e.g. fembeam.CircularArch), got {type(curve).__name__}")
    if not (isinstance(tol, (int, float)) and 0 < tol < 1):
        raise InputError(f"the tolerance must be in (0, 1), got {tol!r}")
    base = plain(curve)
    L = float(base.length)
    marks = [np.asarray(base.kinks, float), np.asarray(base.fixed_nodes, float), np.asarray(base.breaks, float),
             np.asarray([x for span in base.solid_spans for x in span], float)]
    s = np.unique(np.concatenate([np.linspace(0.0, L, SAMPLES)] + [m for m in marks if m.size]))
    X, t = base.position(s), np.asarray(base.thickness_at(s), float) * np.ones(s.shape)
    atol = tol * L
    if np.allclose(X[0], X[0, 0], rtol=0.0, atol=atol):
        # every section its own mirror image (a vertical straight member); fembeam puts no load on one
        return len(_pairs_of(loads)) == 0
    if base.ends[0] != base.ends[-1]:
        return False
    Xr, tr = base.position(L - s), np.asarray(base.thickness_at(L - s), float) * np.ones(s.shape)
    axis = 0.5 * (X[0, 0] + X[0, -1])
    if not (np.allclose(X[0] + Xr[0], 2 * axis, rtol=0.0, atol=atol) and np.allclose(X[1], Xr[1], rtol=0.0, atol=atol)
            and np.allclose(t, tr, rtol=0.0, atol=atol)):
        return False
    if not all(_mirrored(m, L, tol) for m in marks):
        return False
    if nodes is not None and not _mirrored(nodes, L, tol):
        return False
    masses = getattr(curve, "masses", None)
    _, span = span_of(base)
    if masses is not None and not _pairs_mirrored(masses, span, tol):
        return False
    return _pairs_mirrored(_pairs_of(loads), span, tol)


def _pairs_of(loads) -> np.ndarray:
    """The pairs ``(x, P)`` of live ``loads`` (None, a PointLoads or pairs)."""
    if loads is None:
        return np.empty((0, 2))
    try:
        return np.asarray(getattr(loads, "pairs", loads), float).reshape(-1, 2)
    except (TypeError, ValueError):
        raise InputError(f"loads must be pairs (x in m, P in kN/m), got {loads!r}") from None
