"""Output of a rocking time history (:func:`fembeam.dynamics.rocking.rock`).

* :func:`plot_history` / :func:`history_figure`: ground acceleration ``a_g`` (g), rotation
  ``theta`` (rad) with the impacts, the overturning and the exit of the thrust line, and the
  energies ``K``, ``V``, ``K + V`` (J/m) against time (s);
* :func:`outline`: the moved outline of the member, a closed polygon (extrados from ``s = 0``
  to ``s = L``, then intrados back), rigid pieces sampled separately so that the joints open;
* :func:`write_pvd`: a ParaView time series (one ``.vtu`` per frame and a ``.pvd`` index);
* :func:`write_gif`: an animation of the moving outline.

Conventions: positions in m (``y`` along the normal ``n``, intrados at ``y = +t/2``), time
in s, rotations in rad, energies in J/m, ground acceleration in g.  The pieces
of a mechanism are numbered as the intervals between its ``breaks`` ``[0, *s, L]``; the
zero-length pieces of hinges at the ends of the member (the abutment faces) are not drawn.
Every file is written through :func:`~fembeam.output.files.atomic`.
"""
from __future__ import annotations

from pathlib import Path
from typing import TYPE_CHECKING, Sequence

import numpy as np

from ..errors import InputError
from ..geometry import MidCurve
from ..mechanisms.mechanism import Configuration, Mechanism
from .files import atomic, atomic_group, check_output, target

if TYPE_CHECKING:  # pragma: no cover
    from ..dynamics.result import RockingResult

__all__ = ["history_figure", "plot_history", "outline", "section_layout", "frame_rows", "frame_mesh",
           "write_pvd", "write_gif"]

SECTIONS = 101          # default number of evenly spaced sections over the length (hinges added)
PLOT_SUFFIXES = (".png", ".pdf", ".svg")


# --------------------------------------------------------------------------- helpers
def _pyplot():
    """matplotlib.pyplot on the Agg backend (as :mod:`fembeam.output.plotting`)."""
    import matplotlib
    matplotlib.use("Agg", force=False) if matplotlib.get_backend().lower() != "agg" else None
    import matplotlib.pyplot as plt
    return plt


def _history(result: "RockingResult") -> dict:
    h = result.history
    if not h or len(h.get("t", ())) == 0:
        raise InputError(f"nothing to show: the time history is empty (outcome {result.outcome})")
    return {k: np.asarray(v, float) for k, v in h.items()}


def frame_rows(t: np.ndarray, frames: int) -> np.ndarray:
    """Indices of at most ``frames`` history rows, evenly spread over the rows, always with
    the first and the last; of rows sharing one time ``t`` (s) only the last is kept."""
    try:
        frames = int(frames)
    except (TypeError, ValueError):
        raise InputError(f"frames must be a positive integer, got {frames!r}") from None
    if frames < 1:
        raise InputError(f"frames must be a positive integer, got {frames}")
    t = np.asarray(t, float)
    rows = np.flatnonzero(np.append(t[:-1] < t[1:], True)) if t.size else np.zeros(0, int)
    if rows.size <= frames:
        return rows
    if frames == 1:
        return rows[-1:]
    return rows[np.unique(np.round(np.linspace(0, rows.size - 1, frames)).astype(int))]


def section_layout(curve: MidCurve, breaks: Sequence[float], sections: int = SECTIONS):
    """Sections of the member for drawing rigid pieces: ``sections`` arc lengths evenly
    spaced over ``[0, L]`` (m) and every break (m), sorted into the segments between
    consecutive distinct ``breaks`` (0 and L added), each segment holding its two ends, so
    that a break is sampled twice (once for each side).  Returns ``(s, segment, ends)``:
    arc lengths (m), the segment of each section, and the (k + 1,) segment ends."""
    try:
        sections = int(sections)
    except (TypeError, ValueError):
        raise InputError(f"sections must be an integer >= 2, got {sections!r}") from None
    if sections < 2:
        raise InputError(f"sections must be an integer >= 2, got {sections}")
    L = float(curve.length)
    ends = np.unique(np.clip(np.concatenate([[0.0, L], np.asarray(breaks, float)]), 0.0, L))
    base = np.linspace(0.0, L, sections)
    base = base[np.min(np.abs(base[:, None] - ends[None, :]), axis=1) > 1e-9 * L]
    s = np.concatenate([base, ends, ends[1:-1]])
    nseg = ends.size - 1
    seg = np.concatenate([np.clip(np.searchsorted(ends, base, side="right") - 1, 0, nseg - 1),
                          np.minimum(np.arange(ends.size), nseg - 1), np.arange(nseg - 1)])
    order = np.lexsort((s, seg))
    return s[order], seg[order], ends


def _pieces_of_segments(mechanism: Mechanism | None, ends: np.ndarray) -> np.ndarray:
    """Piece of ``mechanism`` containing each segment (-1 for all at rest)."""
    if mechanism is None:
        return np.full(ends.size - 1, -1)
    return mechanism.piece_of(0.5 * (ends[:-1] + ends[1:]))


def _place(curve: MidCurve, conf: Configuration | None, s: np.ndarray, y: np.ndarray,
           piece: np.ndarray) -> np.ndarray:
    """(2, n) positions (m) of the material points ``X(s) + y n(s)`` on the pieces ``piece``
    of the configuration ``conf`` (None: at rest).  One vectorised call per piece."""
    if conf is None:
        return curve.point(s, y)
    out = np.empty((2, s.size))
    for p in np.unique(piece):
        m = piece == p
        out[:, m] = conf.displace(s[m], y[m], piece=int(p))
    return out


def _resolve(result_or_curve, mechanism) -> tuple[MidCurve, Mechanism | None]:
    """The curve and the mechanism (a Mechanism, an index into the result's mechanisms, or
    None / -1 for the member at rest)."""
    if isinstance(result_or_curve, MidCurve):
        curve, mechs = result_or_curve, None
    elif hasattr(result_or_curve, "curve") and hasattr(result_or_curve, "mechanisms"):
        curve, mechs = result_or_curve.curve, result_or_curve.mechanisms
    else:
        raise InputError(f"outline needs a RockingResult or a member, got {type(result_or_curve).__name__}")
    if mechanism is None or isinstance(mechanism, Mechanism):
        m = mechanism
    else:
        try:
            k = int(mechanism)
        except (TypeError, ValueError):
            raise InputError(f"mechanism must be a Mechanism, an index or None, got {mechanism!r}") from None
        if k == -1:
            m = None
        elif mechs is None:
            raise InputError("a mechanism index needs a RockingResult (a member alone has no mechanisms)")
        elif not 0 <= k < len(mechs):
            raise InputError(f"mechanism index {k} out of range: the result has {len(mechs)} mechanisms")
        else:
            m = mechs[k]
    if m is not None and m.curve != curve:
        raise InputError("the mechanism belongs to another member than the one given")
    return curve, m


# --------------------------------------------------------------------------- outline
def outline(result_or_curve, mechanism: Mechanism | int | None = None, theta: float = 0.0,
            sections: int = SECTIONS) -> np.ndarray:
    """(2, n) closed polygon (m, last vertex not repeated) of the member moved by a rotation
    ``theta`` (rad) of the free parameter of ``mechanism``: the extrados (``y = -t/2``) from
    ``s = 0`` to ``s = L``, then the intrados (``y = +t/2``) back to ``s = 0``.

    ``result_or_curve``: a :class:`~fembeam.dynamics.rocking.RockingResult` or a member
    (:class:`~fembeam.geometry.MidCurve`); ``mechanism``: a
    :class:`~fembeam.mechanisms.mechanism.Mechanism`, an index into the result's
    ``mechanisms``, or None (or -1) for the member at rest (``theta`` ignored).
    ``sections`` evenly spaced sections over the length are sampled plus the hinges; each
    rigid piece is sampled up to its ends, so at an interior hinge the section appears twice
    (left piece, then right piece) and the opening joint shows.  A locked configuration
    (the four-bar loop cannot close) gives NaN."""
    curve, m = _resolve(result_or_curve, mechanism)
    s, seg, ends = section_layout(curve, m.s if m is not None else (), sections)
    piece = _pieces_of_segments(m, ends)[seg]
    conf = m.configuration(float(theta)) if m is not None else None
    half = 0.5 * np.asarray(curve.thickness_at(s), float)
    E = _place(curve, conf, s, -half, piece)
    Ip = _place(curve, conf, s, half, piece)
    return np.hstack([E, Ip[:, ::-1]])


# --------------------------------------------------------------------------- history figure
def history_figure(result: "RockingResult"):
    """The matplotlib figure of a rocking time history: ground, rotation and energies.

    Three panels sharing the time axis ``t`` (s): the ground acceleration ``a_g`` (g,
    positive along ``+x``); the rotation ``theta`` (rad) of the mechanism's free parameter
    with the impacts (markers at ``theta = 0``), the overturning and the first exit of the
    thrust line (vertical lines); the energies ``K``, ``V`` and ``K + V`` (J/m).

    Parameters
    ----------
    result : RockingResult
        A time history (:func:`fembeam.dynamics.rock`, with its history).

    Returns
    -------
    matplotlib.figure.Figure
        The figure (on the Agg backend); the caller closes it (``plt.close(fig)``).

    Raises
    ------
    InputError
        The history is empty.

    See Also
    --------
    plot_history : the figure saved to a file.

    Examples
    --------
    >>> import fembeam
    >>> import matplotlib.pyplot as plt
    >>> from fembeam.dynamics import GroundMotion, rock
    >>> from fembeam.output.motion import history_figure
    >>> arch = fembeam.CircularArch(radius=1.0, thickness=0.15, embrace_deg=157.5)
    >>> res = rock(arch, GroundMotion.sine(0.4, 0.5), voussoirs=12)
    >>> fig = history_figure(res)
    >>> for ax in fig.axes:
    ...     print(ax.get_ylabel())
    ground acceleration $a_g$ (g)
    rotation $\\theta$ (rad)
    energy (J/m)
    >>> plt.close(fig)
    """
    h = _history(result)
    plt = _pyplot()
    fig, (ax_a, ax_th, ax_e) = plt.subplots(3, 1, sharex=True, figsize=(8.0, 7.5))
    t = h["t"]
    ax_a.plot(t, h["a_g"], color="tab:gray", lw=1.0, label="a_g")
    ax_a.axhline(0.0, color="black", lw=0.5)
    ax_a.set_ylabel(r"ground acceleration $a_g$ (g)")

    ax_th.plot(t, h["theta"], color="tab:blue", lw=1.2, label=r"$\theta$")
    ax_th.axhline(0.0, color="black", lw=0.5)
    if result.impacts:
        ti = np.array([e.t for e in result.impacts], float)
        ax_th.plot(ti, np.zeros_like(ti), "o", ms=4, mfc="none", mec="tab:red", ls="none",
                   label=f"impacts ({ti.size})")
    if result.t_overturn is not None:
        ax_th.axvline(result.t_overturn, color="black", lw=1.5, ls="-",
                      label=f"overturned, t = {result.t_overturn:.3f} s")
    if result.thrust_line_exits_at is not None:
        ax_th.axvline(result.thrust_line_exits_at, color="tab:orange", lw=1.5, ls="--",
                      label=f"thrust line leaves the section, t = {result.thrust_line_exits_at:.3f} s")
    ax_th.set_ylabel(r"rotation $\theta$ (rad)")
    ax_th.legend(loc="best", fontsize=8)

    _energy_panel(fig, (ax_a, ax_th, ax_e), t, h["K"], h["V"], f"{result.outcome} - {result.ground.name}", total=True)
    return fig


def _energy_panel(fig, axes, t, K, V, title: str, total: bool = False) -> None:
    """The last of ``axes``: ``K``, ``V`` (and ``K + V``) against ``t``; grids, the time range and the
    title of the figure."""
    ax_e = axes[-1]
    ax_e.plot(t, K, color="tab:red", lw=1.0, label="K (kinetic)")
    ax_e.plot(t, V, color="tab:green", lw=1.0, label="V (potential)")
    if total:
        ax_e.plot(t, K + V, color="black", lw=1.2, label="K + V")
    ax_e.set_ylabel("energy (J/m)")
    ax_e.set_xlabel("time t (s)")
    ax_e.legend(loc="best", fontsize=8)
    for ax in axes:
        ax.grid(True, lw=0.3, alpha=0.5)
    ax_e.set_xlim(t[0], t[-1] if t[-1] > t[0] else t[0] + 1.0)
    fig.suptitle(title)
    fig.tight_layout()


def plot_history(result: "RockingResult", path: str | Path, dpi: int = 150) -> None:
    """Save the figure of a rocking time history (:func:`history_figure`) to a file.

    Parameters
    ----------
    result : RockingResult
        A time history (:func:`fembeam.dynamics.rock`, with its history).
    path : str or pathlib.Path
        The file, ending in ``.png``, ``.pdf`` or ``.svg`` (the format); written
        atomically, in a directory that exists.
    dpi : int, optional
        Resolution of a PNG (dots per inch, default 150).

    Returns
    -------
    None
        The figure is written to ``path``.

    Raises
    ------
    InputError
        Another suffix, a directory that does not exist or cannot be written, or an empty
        history.

    Examples
    --------
    >>> import pathlib, tempfile
    >>> import fembeam
    >>> from fembeam.dynamics import GroundMotion, rock
    >>> arch = fembeam.CircularArch(radius=1.0, thickness=0.15, embrace_deg=157.5)
    >>> res = rock(arch, GroundMotion.sine(0.4, 0.5), voussoirs=12)
    >>> from fembeam.output.motion import plot_history
    >>> path = pathlib.Path(tempfile.mkdtemp()) / "history.png"
    >>> plot_history(res, path, dpi=50)
    >>> print(path.name, path.stat().st_size > 0)
    history.png True
    """
    _save(history_figure, result, path, "plot_history", dpi)


def _save(figure, result, path, name: str, dpi: int) -> None:
    """``figure(result)`` saved to ``path`` (checked as ``name``: .png, .pdf or .svg), atomically."""
    p = check_output(path, name, PLOT_SUFFIXES)
    fig = figure(result)
    plt = _pyplot()
    try:
        with atomic(p) as tmp:
            fig.savefig(tmp, dpi=dpi, format=p.suffix[1:].lower())
    finally:
        plt.close(fig)


def auto_figure(result):
    """matplotlib Figure of a ``--model auto`` run (:class:`fembeam.auto.AutoResult`), 3 panels
    sharing ``t`` (s): ``a_g`` (g); the largest rotation of any piece or body (rad) with the
    intervals of the multi-block simulation shaded and the first failure of the one-mechanism
    model marked; ``K``, ``V`` (J/m).  The caller closes it."""
    h = result.history
    if len(h.get("t", ())) == 0:
        raise InputError("the result has no history to plot")
    plt = _pyplot()
    fig, (ax_a, ax_r, ax_e) = plt.subplots(3, 1, sharex=True, figsize=(8.0, 7.5))
    t = h["t"]
    ax_a.plot(t, h["a_g"], color="tab:gray", lw=1.0)
    ax_a.set_ylabel(r"ground acceleration $a_g$ (g)")
    ax_r.plot(t, h["max_rotation"], color="tab:blue", lw=1.2, label="largest rotation")
    first = True
    for sg in result.segments:
        if sg.model == "simulate":
            for ax in (ax_a, ax_r, ax_e):
                ax.axvspan(sg.t_start, sg.t_end, color="tab:orange", alpha=0.15,
                           label="multi-block simulation" if (first and ax is ax_r) else None)
            first = False
    if result.first_failure is not None:
        ax_r.axvline(result.first_failure[0], color="tab:red", ls="--", lw=1.2,
                     label=f"one-mechanism model fails ({result.first_failure[1]}), "
                           f"t = {result.first_failure[0]:.3f} s")
    if result.t_overturn is not None:
        ax_r.axvline(result.t_overturn, color="black", lw=1.5, label=f"{result.outcome}, t = {result.t_overturn:.3f} s")
    ax_r.set_ylabel("largest rotation (rad)")
    ax_r.legend(loc="best", fontsize=8)
    _energy_panel(fig, (ax_a, ax_r, ax_e), t, h["K"], h["V"], f"--model auto: {result.outcome} - {result.ground.name}")
    return fig


def plot_auto(result, path: str | Path, dpi: int = 150) -> None:
    """:func:`auto_figure` saved to ``path`` (.png, .pdf or .svg), written atomically."""
    _save(auto_figure, result, path, "plot_auto", dpi)


# --------------------------------------------------------------------------- ParaView
def frame_mesh(curve: MidCurve, mechanism: Mechanism | None, theta: float, layout):
    """meshio Mesh of the member in one configuration on the fixed ``layout``
    (:func:`section_layout`): points ``[extrados(s), intrados(s)]`` (m, z = 0), one quad
    (counter-clockwise) between consecutive sections of a segment, point data
    ``displacement`` (m, 3 components: moved minus rest position) and cell data ``piece``
    (index of the rigid piece, -1 at rest)."""
    import meshio

    s, seg, ends = layout
    n = s.size
    piece_seg = _pieces_of_segments(mechanism, ends)
    piece = piece_seg[seg]
    conf = mechanism.configuration(float(theta)) if mechanism is not None else None
    half = 0.5 * np.asarray(curve.thickness_at(s), float)
    S, Y, P = np.concatenate([s, s]), np.concatenate([-half, half]), np.concatenate([piece, piece])
    rest = curve.point(S, Y)
    moved = _place(curve, conf, S, Y, P)
    a = np.flatnonzero(seg[:-1] == seg[1:])           # sections followed by one of the same segment
    quads = np.column_stack([a, n + a, n + a + 1, a + 1])
    z = np.zeros(2 * n)
    points = np.column_stack([moved[0], moved[1], z])
    disp = np.column_stack([moved[0] - rest[0], moved[1] - rest[1], z])
    return meshio.Mesh(points, [("quad", quads)], point_data={"displacement": disp},
                       cell_data={"piece": [piece[a].astype(np.int32)]})


def _pvd_text(entries) -> str:
    lines = ['<?xml version="1.0"?>',
             '<VTKFile type="Collection" version="0.1" byte_order="LittleEndian">',
             "  <Collection>"]
    lines += [f'    <DataSet timestep="{float(t)!r}" group="" part="0" file="{name}"/>' for t, name in entries]
    lines += ["  </Collection>", "</VTKFile>", ""]
    return "\n".join(lines)


def write_pvd(result: "RockingResult", path: str | Path, frames: int = 200,
              sections: int = SECTIONS) -> list[Path]:
    """Write a rocking motion as a ParaView time series: ``.vtu`` frames, a ``.pvd`` index.

    Every frame is an unstructured grid of quads between extrados and intrados (see
    :func:`frame_mesh`) on one section layout for the whole run: ``sections`` evenly spaced
    sections plus the hinges of every mechanism of the result, each sampled on both sides,
    so all frames have the same points and cells. Point data ``displacement`` (m, moved
    minus rest position), cell data ``piece`` (the rigid piece, -1 at rest). The ``.pvd``
    (``timestep``: the history's time, s) is written last. The series replaces the one
    there as a whole (:func:`~fembeam.output.files.atomic_group`): on a failure or an
    interrupt nothing is touched; after it, frames of the previous series that this one
    lacks are removed.

    Parameters
    ----------
    result : RockingResult
        A time history (:func:`fembeam.dynamics.rock`, with its history).
    path : str or pathlib.Path
        The index, ending in ``.pvd``; the frames ``<stem>_0000.vtu``, ... are written
        next to it.
    frames : int, optional
        Most frames (default 200): the history subsampled evenly by :func:`frame_rows`,
        the first and the last row always included.
    sections : int, optional
        Evenly spaced sections over the length (default 101), the hinges added.

    Returns
    -------
    list of pathlib.Path
        The files written: the ``.vtu`` frames in time order, then the ``.pvd``.

    Raises
    ------
    InputError
        A ``path`` not ending in ``.pvd`` or that cannot be written, ``frames`` or
        ``sections`` out of range, or an empty history.

    Examples
    --------
    >>> import pathlib, tempfile
    >>> import fembeam
    >>> from fembeam.dynamics import GroundMotion, rock
    >>> arch = fembeam.CircularArch(radius=1.0, thickness=0.15, embrace_deg=157.5)
    >>> res = rock(arch, GroundMotion.sine(0.4, 0.5), voussoirs=12)
    >>> from fembeam.output.motion import write_pvd
    >>> files = write_pvd(res, pathlib.Path(tempfile.mkdtemp()) / "motion.pvd", frames=5)
    >>> print(len(files), "files:", files[0].name, "...", files[-2].name, files[-1].name)
    6 files: motion_0000.vtu ... motion_0004.vtu motion.pvd
    """
    import meshio

    p = check_output(path, "write_pvd", (".pvd",))
    h = _history(result)
    rows = frame_rows(h["t"], frames)
    curve, mechs = result.curve, list(result.mechanisms)
    hinges = np.concatenate([np.asarray(m.s, float) for m in mechs]) if mechs else np.zeros(0)
    layout = section_layout(curve, hinges, sections)
    width = max(4, len(str(rows.size - 1)))
    names = [p.with_name(f"{p.stem}_{j:0{width}d}.vtu") for j in range(rows.size)]
    with atomic_group(names + [p], replaces=previous_series(p)) as tmps:
        entries = []
        for j, i in enumerate(rows):
            k = int(h["mechanism"][i])
            mesh = frame_mesh(curve, mechs[k] if k >= 0 else None, float(h["theta"][i]), layout)
            meshio.write(tmps[j], mesh, file_format="vtu")
            entries.append((float(h["t"][i]), names[j].name))
        Path(tmps[-1]).write_text(_pvd_text(entries), encoding="utf-8")
    return names + [p]


def previous_series(path) -> list[Path]:
    """The frames ``<stem>_NNNN.vtu`` next to ``path`` that an existing ``.pvd`` there lists
    (the set a new series replaces as a whole); none if it cannot be read."""
    import re

    from ..readers import read_text
    p = target(path)
    try:
        text = read_text(p, "the ParaView series", 16 * 2 ** 20) if p.exists() else ""
    except InputError:
        return []
    pattern = re.compile(r'file="(' + re.escape(Path(path).stem) + r'_[0-9]+\.vtu)"')
    return [p.with_name(n) for n in dict.fromkeys(pattern.findall(text))]


# --------------------------------------------------------------------------- animation
def write_gif(result: "RockingResult", path: str | Path, frames: int = 120, fps: int = 20,
              sections: int = 61, dpi: int = 80) -> None:
    """Write a GIF animation of a rocking motion: the outline moving over the ground.

    Equal aspect, fixed axis limits covering every frame, the rest outline dashed, the
    ground line at the lowest point of the member at rest, the hinges of the current
    mechanism as dots, the fill of an arch as built moving with its pieces, a scale bar (m)
    in place of the axes (tick labels would dominate the drawing time), and a text with
    ``t`` (s) and ``a_g`` (g). Written atomically.

    Parameters
    ----------
    result : RockingResult
        A time history (:func:`fembeam.dynamics.rock`, with its history).
    path : str or pathlib.Path
        The file, ending in ``.gif``.
    frames : int, optional
        Most frames (default 120): the history subsampled evenly by :func:`frame_rows`,
        the first and the last row always included.
    fps : float, optional
        Frames per second of the animation (default 20).
    sections : int, optional
        Evenly spaced sections of the outline over the length (default 61), the hinges
        added.
    dpi : int, optional
        Pixels per inch of the 6 x 4.5 in frames (default 80).

    Returns
    -------
    None
        The animation is written to ``path``.

    Raises
    ------
    InputError
        A ``path`` not ending in ``.gif`` or that cannot be written, ``frames``, ``fps``
        or ``sections`` out of range, or an empty history.

    Examples
    --------
    >>> import pathlib, tempfile
    >>> import fembeam
    >>> from fembeam.dynamics import GroundMotion, rock
    >>> arch = fembeam.CircularArch(radius=1.0, thickness=0.15, embrace_deg=157.5)
    >>> res = rock(arch, GroundMotion.sine(0.4, 0.5), voussoirs=12)
    >>> from fembeam.output.motion import write_gif
    >>> path = pathlib.Path(tempfile.mkdtemp()) / "motion.gif"
    >>> write_gif(res, path, frames=5, dpi=40)
    >>> print(path.name, path.stat().st_size > 0)
    motion.gif True
    """
    p = check_output(path, "write_gif", (".gif",))
    try:
        fps = float(fps)
    except (TypeError, ValueError):
        raise InputError(f"fps must be a positive number, got {fps!r}") from None
    if not (np.isfinite(fps) and fps > 0):
        raise InputError(f"fps must be a positive number, got {fps!r}")
    h = _history(result)
    rows = frame_rows(h["t"], frames)
    curve, mechs = result.curve, list(result.mechanisms)
    from .asbuilt import moving_fill

    polys, pivots, fills = [], [], []
    for i in rows:
        k = int(h["mechanism"][i])
        m = mechs[k] if k >= 0 else None
        polys.append(outline(curve, m, float(h["theta"][i]), sections))
        fills.append(moving_fill(curve, m, float(h["theta"][i])))
        pivots.append(m.configuration(float(h["theta"][i])).hinge_points() if m is not None else np.zeros((2, 0)))
    rest = outline(curve, None, 0.0, sections)
    allp = np.hstack([rest, *polys, *(f.T for fs in fills for f in fs)])
    allp = allp[:, np.all(np.isfinite(allp), axis=0)]
    lo, hi = allp.min(axis=1), allp.max(axis=1)
    ground_y = float(rest[1].min())
    pad = 0.08 * float(max(hi[0] - lo[0], hi[1] - lo[1]))
    xlim = (lo[0] - pad, hi[0] + pad)
    ylim = (min(lo[1], ground_y) - 1.6 * pad, hi[1] + pad)
    span = 0.25 * (xlim[1] - xlim[0])
    bar = min((f * 10.0 ** np.floor(np.log10(span)) for f in (1.0, 2.0, 5.0, 10.0)),
              key=lambda x: abs(np.log(x / span)))

    plt = _pyplot()
    from .animation import save_gif

    fig, ax = plt.subplots(figsize=(6.0, 4.5))
    try:
        ax.set_aspect("equal")
        ax.set_xlim(*xlim)
        ax.set_ylim(*ylim)
        ax.set_axis_off()
        ax.axhline(ground_y, color="saddlebrown", lw=2.0)
        ax.axhspan(ylim[0], ground_y, color="tan", alpha=0.35, lw=0)
        xb, yb = xlim[1] - 0.5 * pad - bar, 0.5 * (ylim[0] + ground_y)
        ax.plot([xb, xb + bar], [yb, yb], color="black", lw=3, solid_capstyle="butt")
        ax.text(xb - 0.2 * pad, yb, f"{bar:g} m", ha="right", va="center", fontsize=8)
        closed = np.hstack([rest, rest[:, :1]])
        ax.plot(closed[0], closed[1], color="grey", lw=0.8, ls="--")
        from matplotlib.collections import PolyCollection
        fill = PolyCollection(fills[0], facecolor="#e8d9b5", edgecolor="#b89f6a", lw=0.6)   # moves with its piece
        ax.add_collection(fill)
        (body,) = ax.fill(polys[0][0], polys[0][1], facecolor="lightsteelblue", edgecolor="black", lw=1.2)
        (dots,) = ax.plot([], [], "o", color="tab:red", ms=4, ls="none")
        # title and the running text in a strip above the axes: they never cover the member
        fig.subplots_adjust(left=0.02, right=0.98, bottom=0.02, top=0.84)
        fig.suptitle(f"{result.outcome} - {result.ground.name}", fontsize=10, y=0.975)
        text = fig.text(0.5, 0.89, "", ha="center", va="center", family="monospace", fontsize=9)

        def draw(j):
            i = rows[j]
            body.set_xy(polys[j].T)
            fill.set_verts(fills[j])
            dots.set_data(pivots[j][0], pivots[j][1])
            text.set_text(f"t = {h['t'][i]:.4f} s    a_g = {h['a_g'][i]:+.3f} g")
            return body, fill, dots, text

        save_gif(fig, draw, len(rows), p, fps, dpi)
    finally:
        plt.close(fig)
