"""Meshes of the mid-curve: node arc lengths (m) for :func:`~fembeam.fem.discretize`."""
from __future__ import annotations

import numpy as np

from ..errors import InputError
from ..geometry import MidCurve

__all__ = ["uniform_nodes", "nodes_through", "check_nodes"]


def _check_curve(curve) -> None:
    if not isinstance(curve, MidCurve):
        raise InputError(f"expected a member (a fembeam.geometry.MidCurve such as CircularArch), got "
                         f"{type(curve).__name__}")


def check_nodes(curve: MidCurve, nodes_s) -> np.ndarray:
    """``nodes_s`` as a float array when it is a mesh of ``curve``: finite arc lengths (m),
    strictly increasing, from 0 to ``curve.length`` (to 1e-9 of the length); InputError
    saying so otherwise."""
    _check_curve(curve)
    try:
        nodes = np.asarray(nodes_s, dtype=float)
    except (TypeError, ValueError):
        raise InputError("mesh nodes must be a sequence of numbers (arc lengths, m)") from None
    L = float(curve.length)
    if (nodes.ndim != 1 or nodes.size < 2 or not np.all(np.isfinite(nodes)) or np.any(np.diff(nodes) <= 0)
            or abs(nodes[0]) > 1e-9 * L or abs(nodes[-1] - L) > 1e-9 * L):
        raise InputError(f"mesh nodes must be finite arc lengths, strictly increasing from 0 to the member's "
                         f"length {L:.17g} m (at least 2 nodes)")
    bad = np.flatnonzero(~curve.admissible(nodes))
    if bad.size:
        s = float(nodes[bad[0]])
        a, b = next((a, b) for a, b in curve.solid_spans if a < s < b)
        raise InputError(f"a mesh node at s = {s:.10g} m lies inside a part of the member that has no section "
                         f"(s in ({a:.10g}, {b:.10g}) m: a crown wedge, where a joint would cross the crown joint); "
                         f"see MidCurve.solid_spans")
    return nodes


def uniform_nodes(curve: MidCurve, n_elements: int) -> np.ndarray:
    """Arc lengths of ``n_elements + 1`` equally spaced nodes of a member.

    Parameters
    ----------
    curve : MidCurve
        The member.
    n_elements : int
        Number of elements, >= 1.

    Returns
    -------
    ndarray
        Arc lengths of the nodes (m), from 0 to ``curve.length``.

    Raises
    ------
    InputError
        ``n_elements`` not a positive integer.

    Notes
    -----
    A curve with fixed nodes (:attr:`MidCurve.fixed_nodes`: its kinks, the crown joint of a
    pointed arch) gets a node at each: each piece between them is meshed uniformly, the
    elements shared out in proportion to the lengths (largest remainders, ties to the
    left, at least one per piece; so the count is kept unless it is below the number of
    pieces).  Nodes that fall inside one of the curve's :attr:`MidCurve.solid_spans` (the
    crown wedges of a pointed arch, where a joint would cross the crown joint) are left
    out: their two elements are one, and the mesh has that many elements fewer.
    Without either: ``numpy.linspace(0, length, n_elements + 1)``.

    Examples
    --------
    >>> import fembeam
    >>> arch = fembeam.CircularArch(radius=1.0, thickness=0.15, embrace_deg=180.0)
    >>> print(fembeam.uniform_nodes(arch, 4).round(4))
    [0.     0.7854 1.5708 2.3562 3.1416]
    """
    _check_curve(curve)
    if isinstance(n_elements, bool) or not isinstance(n_elements, (int, np.integer)) or n_elements < 1:
        raise InputError(f"the number of elements must be a positive integer, got {n_elements!r}")
    fixed = np.asarray(curve.fixed_nodes, float)
    if fixed.size == 0:
        nodes = np.linspace(0.0, curve.length, int(n_elements) + 1)
    else:
        edges = np.concatenate([[0.0], fixed, [curve.length]])
        counts = _share(int(n_elements), np.diff(edges))
        nodes = np.concatenate([np.linspace(a, b, k + 1)[:-1] for a, b, k in zip(edges[:-1], edges[1:], counts)]
                               + [edges[-1:]])
    return nodes[curve.admissible(nodes)] if curve.solid_spans else nodes


def _share(n: int, lengths: np.ndarray) -> np.ndarray:
    """``n`` elements shared out over pieces of ``lengths``: at least one each, the rest by
    largest remainder of the proportional share (ties to the first piece)."""
    k = lengths.size
    if n <= k:
        return np.ones(k, int)
    quota = (n - k) * lengths / np.sum(lengths)
    counts = 1 + np.floor(quota).astype(int)
    rest = n - int(np.sum(counts))
    counts[np.argsort(-(quota - np.floor(quota)), kind="stable")[:rest]] += 1
    return counts


def nodes_through(nodes_s: np.ndarray, points_s, keep=()) -> np.ndarray:
    """Copy of a mesh with a node on each of the given points.

    The nearest node is moved onto a point when it is an interior node not yet used (the
    element count stays), else a node is inserted. Points within 1e-10 of the length of
    a node are already there.

    Parameters
    ----------
    nodes_s : array_like
        Arc lengths of the nodes (m), strictly increasing.
    points_s : float or array_like
        Arc lengths (m) that must be nodes, e.g. the hinges of a mechanism.
    keep : array_like, optional
        Arc lengths of nodes never moved (e.g. the curve's
        :attr:`~fembeam.geometry.MidCurve.fixed_nodes`); a point next to one of them but
        not on it (a kink's one-sided cut, one ulp off) gets a node of its own.

    Returns
    -------
    ndarray
        The new nodes (m), strictly increasing.

    Raises
    ------
    InputError
        Nodes not strictly increasing, or a point outside the mesh.

    Examples
    --------
    >>> import numpy as np
    >>> import fembeam
    >>> print(fembeam.nodes_through(np.linspace(0.0, 2.0, 5), [0.6]))
    [0.  0.6 1.  1.5 2. ]
    """
    out = np.array(nodes_s, float)
    if out.ndim != 1 or out.size < 2 or not np.all(np.isfinite(out)) or np.any(np.diff(out) <= 0):
        raise InputError("mesh nodes must be finite arc lengths, strictly increasing (at least 2 nodes)")
    tol = 1e-10 * (out[-1] - out[0])
    pts = np.atleast_1d(np.asarray(points_s, float))
    if not np.all((pts >= out[0] - tol) & (pts <= out[-1] + tol)):
        raise InputError(f"the points to mesh through must be finite arc lengths in [{out[0]:g}, {out[-1]:g}] m")
    moved = np.zeros(out.size, bool)
    moved[[0, -1]] = True
    keep = np.atleast_1d(np.asarray(keep, float))
    for k in keep:
        moved |= np.abs(out - k) <= tol
    beside = np.array([np.any((np.abs(keep - p) <= tol) & (keep != p)) for p in pts], bool)
    if beside.any():
        fixed = out[moved]
        out = np.unique(np.concatenate([out, pts[beside]]))
        moved = np.isin(out, fixed) | np.isin(out, pts[beside])
        pts = pts[~beside]
    # closest first: the result does not depend on the order of the points, and the
    # mesh of the mirror image is the mirror image of the mesh
    for p in pts[np.argsort([np.min(np.abs(out - q)) for q in pts], kind="stable")]:
        d = np.abs(out - p)
        if np.min(d) <= tol:
            moved[np.argmin(d)] = True
            continue
        i = int(np.argmin(d))             # the nearest node: moved only if free to move
        if not moved[i] and out[i - 1] < p < out[i + 1]:
            out[i], moved[i] = p, True
        else:
            j = int(np.searchsorted(out, p))
            out, moved = np.insert(out, j, p), np.insert(moved, j, True)
    return out
