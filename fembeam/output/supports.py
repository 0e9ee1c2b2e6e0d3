"""Pictures of an arch on moving supports (:mod:`fembeam.analysis.supports`): a figure of the
arch at rest and at the end of the path with their lines of thrust and of the thrust against
the displacement, and a ParaView series of the pieces along the path; and the figure of the
forces on the supports of a simulation whose supports move (``simulate --support-motion``)
against their displacement, over the quasi-static path."""
from __future__ import annotations

from pathlib import Path

import numpy as np

from .files import atomic, atomic_group, check_output

__all__ = ["plot_supports", "write_pvd", "support_thrust_figure", "plot_support_thrust"]


def plot_supports(res, path, dpi: int = 150) -> Path:
    """Two panels: the arch at rest (grey) and at the last row of the path (the collapse, or
    ``--up-to``) with their lines of thrust and hinges; ``H`` and ``V`` (kN/m) against the
    displacement (m), the migrations marked.  Written atomically; returns the path."""
    from .motion import _pyplot

    p = Path(path)
    plt = _pyplot()
    fig, (a1, a2) = plt.subplots(1, 2, figsize=(11, 4.4))
    for i, colour, label in ((0, "0.6", "at rest"), (len(res.frames) - 1, "C3", "at the end")):
        for k, poly in enumerate(res.placed(i)):
            a1.fill(poly[0], poly[1], facecolor="none", edgecolor=colour, lw=0.6)
        tp = res.thrust_points(i)
        a1.plot(tp[0], tp[1], "-", color="C0" if i == 0 else "C1", lw=1.2,
                label=f"line of thrust {label} ({res.frames[i][0]:.4g} m)")
        side = res.frames[i][3]
        hs = np.flatnonzero(side)
        if hs.size:
            a1.plot(tp[0, hs], tp[1, hs], "o", color="k", ms=4)
    a1.set_aspect("equal")
    a1.set_title(f"{res.movement.kind}: {res.outcome.replace('_', ' ')}")
    a1.legend(loc="lower center", fontsize=7)
    a1.set_xlabel("x [m]")
    a1.set_ylabel("y [m]")
    P = np.array(res.path)
    a2.plot(P[:, 0], P[:, 1], "-", label="H")
    a2.plot(P[:, 0], P[:, 2], "--", label="V left")
    a2.plot(P[:, 0], P[:, 3], ":", label="V right")
    for m in res.migrations:
        a2.axvline(m["displacement"], color="0.8", lw=0.5)
    if res.capacity is not None:
        a2.axvline(res.capacity, color="C3", lw=1.0, label=f"collapse {res.capacity:.4g} m")
    a2.set_xlabel("displacement [m]")
    a2.set_ylabel("force on the support [kN/m]")
    a2.legend(fontsize=8)
    fig.tight_layout()
    with atomic(p) as tmp:
        fig.savefig(tmp, dpi=dpi, format=p.suffix.lstrip(".") or "png")
    plt.close(fig)
    return p


def write_pvd(res, path) -> int:
    """``path`` (.pvd) and one ``.vtu`` per row of the path next to it: the pieces' outlines as
    polygons (cell data ``piece``), the line of thrust as a polyline (cell data ``piece`` -1),
    ``timestep`` = the displacement (m); the series replaces the one there as a whole.  Returns
    the number of frames."""
    import meshio

    from .motion import _pvd_text, previous_series
    p = check_output(path, "--vtk", (".pvd",))
    n = len(res.frames)
    width = max(4, len(str(n - 1)))
    names = [p.with_name(f"{p.stem}_{j:0{width}d}.vtu") for j in range(n)]
    with atomic_group(names + [p], replaces=previous_series(p)) as tmps:
        for j in range(n):
            polys = res.placed(j)
            tp = res.thrust_points(j)
            pts = np.hstack(polys + [tp]).T
            offsets = np.cumsum([0] + [q.shape[1] for q in polys])
            cells = [("polygon", np.arange(a, b)[None, :]) for a, b in zip(offsets[:-1], offsets[1:])]
            cells.append(("line", np.column_stack([offsets[-1] + np.arange(tp.shape[1] - 1),
                                                   offsets[-1] + np.arange(1, tp.shape[1])])))
            data = [np.array([k], np.int32) for k in range(len(polys))] + [np.full(tp.shape[1] - 1, -1, np.int32)]
            mesh = meshio.Mesh(np.column_stack([pts, np.zeros(len(pts))]), cells, cell_data={"piece": data})
            meshio.write(tmps[j], mesh, file_format="vtu")
        entries = [(res.frames[j][0], names[j].name) for j in range(n)]
        Path(tmps[-1]).write_text(_pvd_text(entries), encoding="utf-8")
    return n


def support_thrust_figure(res, quasi_static=None, note: str | None = None):
    """The forces of the arch on its supports in a simulation with a support motion
    (:class:`~fembeam.simulation.result.SimulationResult` run with ``support_motion``) against
    the support displacement ``D`` (m): ``H`` (kN/m, outward) of the left and right supports
    above, ``V`` (kN/m, downward) below, each the mean force since the previous row of the
    history; over them the quasi-static path of ``quasi_static`` (a
    :class:`~fembeam.analysis.supports.SupportsResult` of the same movement, dashed), the
    simulated collapse and the quasi-static capacity as vertical lines.  ``note``: a line
    under the title (e.g. why there is no quasi-static path).  Returns the figure."""
    from .motion import _pyplot

    if res.support_motion is None:
        raise ValueError("the simulation has no support motion: no forces on moving supports")
    plt = _pyplot()
    h = res.history
    t = np.asarray(h["t"], float)
    keep = t > res.support_t0          # the first row closes no interval: no mean force yet
    u = np.asarray(h["support_displacement"], float)[keep]
    fig, (aH, aV) = plt.subplots(2, 1, figsize=(7.5, 6.5), sharex=True)
    for ax, (a, b), what in ((aH, ("H_left", "H_right"), "H"), (aV, ("V_left", "V_right"), "V")):
        ax.plot(u, np.asarray(h[a], float)[keep], "-", color="C0", lw=1.0, label=f"{what} left, simulation")
        ax.plot(u, np.asarray(h[b], float)[keep], "-", color="C1", lw=1.0, label=f"{what} right, simulation")
    d_sim = res.to_dict().get("support_displacement_at_collapse")
    if quasi_static is not None and len(quasi_static.path):
        P = np.array(quasi_static.path, float)
        aH.plot(P[:, 0], P[:, 1], "--", color="k", lw=1.2, label="H, quasi-static (fembeam supports)")
        aV.plot(P[:, 0], P[:, 2], "--", color="k", lw=1.2, label="V left, quasi-static")
        aV.plot(P[:, 0], P[:, 3], ":", color="k", lw=1.4, label="V right, quasi-static")
        if quasi_static.capacity is not None:
            for ax in (aH, aV):
                ax.axvline(quasi_static.capacity, color="k", lw=0.8, ls="-.",
                           label=f"capacity, quasi-static {quasi_static.capacity:.4g} m" if ax is aH else None)
    if d_sim is not None:
        for ax in (aH, aV):
            ax.axvline(d_sim, color="C3", lw=0.8,
                       label=f"collapse, simulation {d_sim:.4g} m" if ax is aH else None)
    aH.set_ylabel("H on the support [kN/m]")
    aV.set_ylabel("V on the support [kN/m]")
    aV.set_xlabel("support displacement D [m]")
    aH.legend(fontsize=7, loc="best")
    aV.legend(fontsize=7, loc="best")
    mo = res.support_motion
    title = f"fembeam simulate: supports moved ({mo.kind}, {mo.rate:g} m/s): {res.outcome}"
    fig.suptitle(title if note is None else f"{title}\n{note}", fontsize=9)
    fig.tight_layout()
    return fig


def plot_support_thrust(res, path, quasi_static=None, note: str | None = None, dpi: int = 120) -> Path:
    """:func:`support_thrust_figure` written atomically to ``path`` (.png, .pdf or .svg);
    returns the path."""
    from .motion import _pyplot

    p = Path(path)
    fig = support_thrust_figure(res, quasi_static, note)
    try:
        with atomic(p) as tmp:
            fig.savefig(tmp, dpi=dpi, format=p.suffix.lstrip(".") or "png")
    finally:
        _pyplot().close(fig)
    return p
