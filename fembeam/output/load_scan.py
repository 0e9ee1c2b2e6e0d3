"""Figure of a load scan: the arch as built with the load at its critical position (top) and
the load factor against the position of the load (bottom)."""
from __future__ import annotations

from pathlib import Path

import numpy as np

from .asbuilt import draw_as_built
from .files import atomic

__all__ = ["plot_load_scan"]


def plot_load_scan(res, path: str | Path, dpi: int = 150) -> Path:
    """Save the figure of a :class:`~fembeam.studies.load_scan.LoadScan` to ``path``."""
    import matplotlib
    matplotlib.use("Agg", force=False) if matplotlib.get_backend().lower() != "agg" else None
    import matplotlib.pyplot as plt
    from .plotting import hinge_points, line_points

    fig, (ax0, ax1) = plt.subplots(2, 1, figsize=(7.5, 7.5), gridspec_kw={"height_ratios": [1.1, 1.0]})
    try:
        i = res.critical
        lf = res.results[i] if i is not None else res.results[0]
        lim = lf.limit
        curve = lim.disc.curve
        draw_as_built(ax0, curve, lim.disc.nodes_s, lf.loads, factor=lf.value if i is not None else None)
        s = np.linspace(0.0, curve.length, 721)
        X, n, t = curve.position(s), curve.normal(s), curve.thickness_at(s)
        for y in (-0.5, 0.5):
            P = X + y * t * n
            ax0.plot(P[0], P[1], color="black", lw=1.0)
        if i is not None:
            L = line_points(lim.disc, lim.eccentricity)
            ax0.plot(L[0], L[1], color="black", lw=1.2, ls=(0, (5, 3)), label="thrust line at collapse")
            H = hinge_points(lim.disc, lim.hinges)
            ax0.plot(H[0], H[1], "o", ms=10, mfc="none", mec="tab:green", mew=2.0, label="hinges")
            ax0.set_title(f"critical position x = {res.x[i]:.4g} m: load factor {res.factor[i]:.4g}", pad=28)
        ax0.set_aspect("equal")
        ax0.axis("off")
        ax0.legend(loc="upper center", bbox_to_anchor=(0.5, -0.02), ncol=3, frameon=False, fontsize=8)
        ok = np.isfinite(res.factor)
        ax1.plot(res.x[ok], res.factor[ok], "-o", ms=3, color="tab:blue")
        if i is not None:
            ax1.plot([res.x[i]], [res.factor[i]], "o", ms=9, mfc="none", mec="tab:red", mew=2)
        top = 1.0
        if ok.any():
            top = max(2.5 * np.nanmin(res.factor), np.nanpercentile(res.factor[ok], 80))
        ax1.set_ylim(0.0, top)
        none = ~ok
        if none.any():     # drawn at the top of the axis: no multiple of the load collapses the arch there
            ax1.plot(res.x[none], np.full(none.sum(), 0.97 * top), "x", color="grey", clip_on=False,
                     label="no mechanism (no load factor)")
            ax1.legend(frameon=False, fontsize=8, loc="upper center")
        ax1.set_xlabel("position of the load x (m from the left springing)")
        ax1.set_ylabel(f"load factor (multiple of P = {res.P:g} kN/m)")
        ax1.grid(alpha=0.3)
        fig.tight_layout()
        path = Path(path)
        with atomic(path) as tmp:
            fig.savefig(tmp, dpi=dpi, format=path.suffix[1:].lower() or "png")
    finally:
        plt.close(fig)
    return path
