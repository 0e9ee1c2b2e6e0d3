"""Matplotlib figure of an impact solution in the style of the paper's Figs. 10-12.

Arch outline (extrados, intrados, springing sections; every joint for a voussoir arch),
hinges before the impact as grey circles, hinges after it as blue dots, the impulse
line in red, the thrust line of the limit analysis dashed, equal aspect, and a title
with ``r`` and ``A_L``.  Hinges sit on the edge they pivot on (``Hinge.side``).
"""
from __future__ import annotations

from pathlib import Path
from typing import Sequence

import numpy as np

from ..fem import Discretization
from ..mechanisms.hinge import Hinge, pivot_fractions
from ..mechanisms.mechanism import Mechanism
from .export import as_hinges
from .files import atomic

__all__ = ["plot_paper_figure", "draw_paper_figure", "hinge_points", "line_points"]


def hinge_points(disc: Discretization, hinges: Sequence[Hinge] | Mechanism) -> np.ndarray:
    """(2, n) points of ``hinges`` on their pivot edge ``X + y n``, ``y = +-t/2`` (m)."""
    c = disc.curve
    hinges = as_hinges(hinges)
    s = np.array([h.s for h in hinges], float)
    return c.point(s, pivot_fractions(h.side for h in hinges) * c.thickness_at(s))


def line_points(disc: Discretization, eccentricity: np.ndarray) -> np.ndarray:
    """(2, J) points ``X_j + e_j n_j`` of a thrust/impulse line (NaN where ``e`` is)."""
    c = disc.curve
    s = disc.joint_s
    return c.point(s, eccentricity)


def draw_paper_figure(ax, disc: Discretization, hinges_before: Sequence[Hinge] | Mechanism = (),
                      hinges_after: Sequence[Hinge] | Mechanism = (), impulse_e: np.ndarray | None = None,
                      thrust_e: np.ndarray | None = None, title: str = "", loads=None) -> None:
    """Draw on the matplotlib axes ``ax`` (see the module docstring); an arch as built with its
    fill columns and point masses, and the live ``loads`` (:class:`~fembeam.analysis.loads.PointLoads`)."""
    c = disc.curve
    if getattr(c, "_built", None) is not None or loads is not None:
        from .asbuilt import draw_as_built
        draw_as_built(ax, c, disc.nodes_s, loads)
    hinges_before, hinges_after = as_hinges(hinges_before), as_hinges(hinges_after)
    s = np.linspace(0.0, c.length, 721)
    X, n, t = c.position(s), c.normal(s), c.thickness_at(s)
    kw = dict(color="black", lw=1.0)
    for y in (-0.5, 0.5):
        P = X + y * t * n
        ax.plot(P[0], P[1], **kw)
    sj = np.union1d([0.0, c.length], disc.joint_s if disc.n_elements <= 30 else [])
    for sec in sj:  # springing sections (and voussoir joints)
        P = c.position(sec)[:, None] + np.array([-0.5, 0.5]) * c.thickness_at(sec) * c.normal(sec)[:, None]
        ax.plot(P[0], P[1], **kw)
    if thrust_e is not None:
        L = line_points(disc, thrust_e)
        ax.plot(L[0], L[1], color="black", lw=1.2, ls=(0, (5, 3)), label="thrust line (limit analysis)")
    if impulse_e is not None:
        L = line_points(disc, impulse_e)
        ax.plot(L[0], L[1], color="red", lw=1.8, label="impulse line")
    if len(hinges_before):
        H = hinge_points(disc, hinges_before)
        ax.plot(H[0], H[1], "o", ms=11, mfc="none", mec="grey", mew=2.0, label="hinges before impact",
                clip_on=False)
    if len(hinges_after):
        H = hinge_points(disc, hinges_after)
        ax.plot(H[0], H[1], "o", ms=6, color="blue", label="hinges after impact", clip_on=False)
    ax.set_aspect("equal")
    ax.axis("off")
    ax.legend(loc="lower center", ncol=2, frameon=False, fontsize=9, bbox_to_anchor=(0.5, -0.12))
    if title:
        ax.set_title(title, pad=24 if loads is not None else None)


def save_paper_figure(path: str | Path, disc: Discretization, hinges_before: Sequence[Hinge] | Mechanism = (),
                      hinges_after: Sequence[Hinge] | Mechanism = (), impulse_e: np.ndarray | None = None,
                      thrust_e: np.ndarray | None = None, title: str = "", dpi: int = 150, loads=None) -> Path:
    """:func:`draw_paper_figure` on a new figure saved to ``path`` (format from the suffix)."""
    import matplotlib
    matplotlib.use("Agg", force=False) if matplotlib.get_backend().lower() != "agg" else None
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(7.5, 4.6))
    try:
        draw_paper_figure(ax, disc, hinges_before, hinges_after, impulse_e, thrust_e, title, loads)
        fig.tight_layout()
        path = Path(path)
        path.parent.mkdir(parents=True, exist_ok=True)
        with atomic(path) as tmp:
            fig.savefig(tmp, dpi=dpi, format=path.suffix[1:].lower() or None)
    finally:
        plt.close(fig)
    return path


def plot_paper_figure(result, path: str | Path, dpi: int = 150) -> Path:
    """Save the paper-style figure of an analysis (Figs. 10-12): hinges, impulse, thrust.

    The arch outline (every joint of a voussoir arch), the hinges before the impact (grey
    circles) and after it (blue dots) on the edge they pivot on, the impulse line (red), the
    thrust line of the limit analysis (dashed), equal aspect (m), and a title with ``r`` and
    ``A_L`` (g); an arch as built with its fill and point masses, and its live loads.

    Parameters
    ----------
    result : AnalysisResult
        An analysis with a limit-analysis mechanism (:func:`fembeam.analyze`).
    path : str or pathlib.Path
        The file; the format comes from its suffix (``.png``, ``.pdf``, ``.svg``, ...).
        Its directory is created if needed; the file is written atomically.
    dpi : int, optional
        Resolution of a raster format (dots per inch, default 150).

    Returns
    -------
    pathlib.Path
        The file written.

    Raises
    ------
    InputError
        The analysis found no mechanism (nothing to plot).

    Examples
    --------
    >>> import pathlib, tempfile
    >>> import fembeam
    >>> arch = fembeam.CircularArch(radius=1.0, thickness=0.15, embrace_deg=157.5)
    >>> from fembeam.output.plotting import plot_paper_figure
    >>> res = fembeam.analyze(arch, voussoirs=12)
    >>> path = plot_paper_figure(res, pathlib.Path(tempfile.mkdtemp()) / "arch.png", dpi=60)
    >>> print(path.name, path.stat().st_size > 0)
    arch.png True
    """
    from ..errors import InputError
    from .render import title_of

    lim, imp = result.limit, result.impact
    if lim is None:
        raise InputError(f"nothing to plot: the analysis has no mechanism (outcome {result.outcome})")
    disc = imp.disc if imp is not None else lim.disc
    return save_paper_figure(path, disc, result.hinges_before, result.hinges_after,
                             imp.eccentricity if imp is not None else None, lim.eccentricity,
                             title_of(result), dpi, getattr(result, "loads", None))
