"""Meshes of the mid-curve: node arc lengths (m) for :func:`~fembeam.fem.discretize`."""
from __future__ import annotations

import numpy as np

from ..errors import InputError
from ..geometry import MidCurve

__all__ = ["uniform_nodes", "nodes_through"]


def uniform_nodes(curve: MidCurve, n_elements: int) -> np.ndarray:
    """Arc-length coordinates of ``n_elements + 1`` equally spaced nodes."""
    if not isinstance(n_elements, (int, np.integer)) or n_elements < 1:
        raise InputError(f"the number of elements must be a positive integer, got {n_elements!r}")
    return np.linspace(0.0, curve.length, int(n_elements) + 1)


def nodes_through(nodes_s: np.ndarray, points_s) -> np.ndarray:
    """Copy of ``nodes_s`` with a node on each of ``points_s``: the nearest node is moved
    there when it is an interior node not yet used (the element count stays), else a node
    is inserted.  Points within 1e-10 of the length of a node are already there."""
    out = np.array(nodes_s, float)
    tol = 1e-10 * (out[-1] - out[0])
    moved = np.zeros(out.size, bool)
    moved[[0, -1]] = True
    pts = np.atleast_1d(np.asarray(points_s, float))
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
