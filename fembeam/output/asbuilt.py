"""Pictures of an arch as built: its fill columns, point masses and live loads; the figure
of the thrust range (the two extreme thrust lines under the dead loads) and of the collapse
under the live loads; the fill columns as VTK cells tagged with the piece they move with."""
from __future__ import annotations

from pathlib import Path

import numpy as np

from ..geometry.asbuilt import extrados
from .files import atomic

__all__ = ["fill_columns", "moving_fill", "draw_as_built", "plot_thrust_range", "fill_mesh"]


def fill_columns(curve, nodes_s: np.ndarray, samples: int = 8) -> list[np.ndarray]:
    """One polygon (k, 2) per piece ``[nodes_s[i], nodes_s[i+1]]``: its column of fill, the
    extrados from left to right, then up to the road and back (empty without fill)."""
    road = getattr(curve, "road_level", None)
    if road is None:
        return []
    out = []
    for a, b in zip(nodes_s[:-1], nodes_s[1:]):
        E = extrados(curve, np.linspace(a, b, samples))
        top = np.maximum(road, E[1])
        poly = np.concatenate([E.T, [[E[0, -1], top[-1]], [E[0, 0], top[0]]]])
        out.append(poly)
    return out


def moving_fill(curve, mechanism=None, theta: float = 0.0) -> list[np.ndarray]:
    """The fill of each piece of ``mechanism`` moved rigidly with it by a rotation ``theta``
    (rad) of its free parameter: one polygon (k, 2) per piece (at rest without a mechanism)."""
    if getattr(curve, "road_level", None) is None:
        return []
    if mechanism is None:
        return fill_columns(curve, np.array([0.0, curve.length]), 48)
    ends = np.concatenate([[0.0], np.asarray(mechanism.s, float), [curve.length]])
    polys = fill_columns(curve, np.unique(ends), 24)
    conf = mechanism.configuration(float(theta))
    k = mechanism.piece_of(0.5 * (np.unique(ends)[:-1] + np.unique(ends)[1:]))
    out = []
    for poly, p in zip(polys, k):
        c, s = np.cos(conf.rotation[p]), np.sin(conf.rotation[p])
        r = poly.T - conf.anchor[:, p:p + 1]
        out.append((conf.moved[:, p:p + 1] + np.array([c * r[0] - s * r[1], s * r[0] + c * r[1]])).T)
    return out


def draw_as_built(ax, curve, nodes_s: np.ndarray | None = None, loads=None, factor: float | None = None) -> None:
    """Draw on ``ax`` the fill columns of the pieces (``nodes_s``: their ends; default: the
    whole span as one), the point masses (squares) and the live ``loads``
    (:class:`~fembeam.analysis.loads.PointLoads`; arrows, labelled with ``factor`` times ``P``
    when given)."""
    from matplotlib.patches import Polygon

    nodes = np.array([0.0, curve.length]) if nodes_s is None else np.asarray(nodes_s, float)
    cols = fill_columns(curve, nodes if nodes.size <= 61 else np.array([0.0, curve.length]), 24)
    for poly in cols:
        ax.add_patch(Polygon(poly, closed=True, fc="#e8d9b5", ec="#b89f6a", lw=0.6, zorder=0))
    if cols:
        ax.plot([], [], "s", color="#e8d9b5", label="fill (moves with its piece)")
    b = getattr(curve, "_built", None)
    if b is not None and b["M"].size:
        ax.plot(b["X_m"][0], b["X_m"][1], "s", ms=7, color="#6b4e16", label="point masses", zorder=5)
    if loads is not None:
        span = float(curve.position(curve.length)[0] - curve.position(0.0)[0])
        h = 0.08 * span
        for (x, P), X in zip(loads.pairs, loads.X.T):
            ax.annotate("", xy=(X[0], X[1]), xytext=(X[0], X[1] + h),
                        arrowprops=dict(arrowstyle="-|>", color="darkred", lw=2.0), zorder=6)
            text = f"{P:g} kN/m" if factor is None else f"{factor:.3g} x {P:g} kN/m"
            ax.text(X[0], X[1] + 1.05 * h, text, ha="center", va="bottom", color="darkred", fontsize=9)
        ax.plot([], [], color="darkred", lw=2.0, label="live loads")


def _outline(ax, curve, joints_s) -> None:
    s = np.linspace(0.0, curve.length, 721)
    X, n, t = curve.position(s), curve.normal(s), curve.thickness_at(s)
    for y in (-0.5, 0.5):
        P = X + y * t * n
        ax.plot(P[0], P[1], color="black", lw=1.0)
    for sec in joints_s:
        P = curve.position(sec)[:, None] + np.array([-0.5, 0.5]) * curve.thickness_at(sec) * curve.normal(sec)[:, None]
        ax.plot(P[0], P[1], color="black", lw=0.6)


def plot_thrust_range(result, path: str | Path, dpi: int = 150) -> Path:
    """Figure of an :class:`~fembeam.analysis.AnalysisResult`: the arch as built with the
    minimum and maximum thrust lines under the dead loads (left) and, with live loads, the
    thrust line and hinges at collapse under the factored loads (right)."""
    import matplotlib
    matplotlib.use("Agg", force=False) if matplotlib.get_backend().lower() != "agg" else None
    import matplotlib.pyplot as plt
    from ..errors import InputError
    from .plotting import hinge_points, line_points

    tr, lf = result.thrust, result.load
    if tr is None:
        raise InputError(f"no thrust range to draw (outcome {result.outcome})")
    panels = 2 if lf is not None and lf.status == "ok" else 1
    fig, axes = plt.subplots(1, panels, figsize=(6.5 * panels, 4.6), squeeze=False)
    try:
        disc = tr.disc
        curve = disc.curve
        joints = disc.joint_s if disc.n_elements <= 30 else [0.0, curve.length]
        ax = axes[0, 0]
        draw_as_built(ax, curve, disc.nodes_s, result.loads)
        _outline(ax, curve, joints)
        for which, style, H in (("min", "-", tr.H_min), ("max", "--", tr.H_max)):
            if not np.isfinite(H):
                continue
            L = line_points(disc, tr.eccentricity(which))
            ax.plot(L[0], L[1], ls=style, lw=1.5, color="tab:blue" if which == "min" else "tab:red",
                    label=f"H_{which} = {H:.4g} kN/m")
        ax.set_title("thrust range under the dead loads")
        if panels == 2:
            ax2 = axes[0, 1]
            lim = lf.limit
            draw_as_built(ax2, curve, lim.disc.nodes_s, result.loads, factor=lf.value)
            _outline(ax2, curve, lim.disc.joint_s if lim.disc.n_elements <= 30 else [0.0, curve.length])
            L = line_points(lim.disc, lim.eccentricity)
            ax2.plot(L[0], L[1], color="black", lw=1.2, ls=(0, (5, 3)), label="thrust line at collapse")
            Hp = hinge_points(lim.disc, lim.hinges)
            ax2.plot(Hp[0], Hp[1], "o", ms=10, mfc="none", mec="tab:green", mew=2.0, label="hinges")
            ax2.set_title(f"collapse under the live loads: load factor {lf.value:.4g}")
        for a in axes[0]:
            a.set_aspect("equal")
            a.axis("off")
            a.legend(loc="upper center", bbox_to_anchor=(0.5, -0.02), ncol=2, frameon=False, fontsize=8)
        fig.tight_layout()
        path = Path(path)
        with atomic(path) as tmp:
            fig.savefig(tmp, dpi=dpi, format=path.suffix[1:].lower() or None)
    finally:
        plt.close(fig)
    return path


def fill_mesh(disc):
    """The fill columns of ``disc``'s pieces as meshio polygon cells (z = 0) with the cell
    data ``piece`` (the element or voussoir each moves with) and ``density`` (kg/m^3); None
    without fill."""
    import meshio

    curve = disc.curve
    polys = fill_columns(curve, disc.nodes_s, samples=6)
    if not polys:
        return None
    pts = np.concatenate(polys)
    k = polys[0].shape[0]
    cells = np.arange(pts.shape[0]).reshape(len(polys), k)
    xyz = np.column_stack([pts, np.zeros(pts.shape[0])])
    return meshio.Mesh(xyz, [("polygon", cells)],
                       cell_data={"piece": [np.arange(len(polys), dtype=np.int64)],
                                  "density": [np.full(len(polys), curve.fill.density)]})
