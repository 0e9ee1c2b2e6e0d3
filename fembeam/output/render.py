"""Off-screen 3D-engine picture of an impact solution with pyvista (VTK).

Draws the meshes of :mod:`fembeam.output.export`: the arch body coloured by the post-impact
speed, the impulse line (red), the thrust line (dashed black), hinges before the impact (grey)
and after it (blue), in the x-y plane with a parallel projection (equal aspect).

Headless machines: VTK >= 9.4 wheels load libGL/libEGL at run time and fall back from
X11 to EGL to OSMesa; with no ``DISPLAY`` we ask for EGL directly (Mesa's llvmpipe
renders on the CPU; Debian packages ``libegl1 libegl-mesa0 libgl1-mesa-dri``, installed
by ``.ci/run``), which also avoids VTK's "bad X server connection" warning.
"""
from __future__ import annotations

import os
from pathlib import Path

import numpy as np

from .files import atomic

__all__ = ["render_png", "render_fields", "title_of"]


def _headless_setup() -> None:
    """Ask VTK for EGL when there is no display; fail with one clear line (instead of VTK
    ending the process) when neither libEGL nor libOSMesa is on the machine."""
    if os.environ.get("DISPLAY") or os.environ.get("WAYLAND_DISPLAY"):
        return
    from ctypes.util import find_library

    if find_library("EGL") is None and find_library("OSMesa") is None:
        from ..errors import FembeamError
        raise FembeamError("off-screen rendering needs libEGL or libOSMesa (Debian: apt-get install "
                           "libegl1 libegl-mesa0 libgl1 libgl1-mesa-dri libosmesa6; see docs/visualisation.md)")
    os.environ.setdefault("VTK_DEFAULT_OPENGL_WINDOW", "vtkEGLRenderWindow")


def title_of(result) -> str:
    """``"r = 0.6065, A_L = 0.3534 g"`` plus the geometry, for picture titles."""
    g = result.geometry or {}
    geo = (f"beta = {g['embrace_deg']:g} deg, t/R = {g['t_over_R']:g}: " if "embrace_deg" in g else "")
    r = f"r = {result.r:.4f}" if np.isfinite(result.r) else f"outcome {result.outcome}"
    return f"{geo}{r}, A_L = {result.A_L:.4f} g"


def _dashed(points: np.ndarray, dash: float) -> np.ndarray:
    """Segments (2k, 3) of a dashed version of the polyline ``points`` (dash length m)."""
    seg = np.linalg.norm(np.diff(points, axis=0), axis=1)
    arc = np.concatenate([[0.0], np.cumsum(seg)])
    n = max(2, int(np.ceil(arc[-1] / dash)))
    a = np.linspace(0.0, arc[-1], 4 * n + 1)
    p = np.column_stack([np.interp(a, arc, points[:, i]) for i in range(3)])
    ends = np.arange(0, 4 * n, 2)                        # dash, gap, dash, ... of length/2 dash
    return np.stack([p[ends], p[ends + 1]], 1).reshape(-1, 3)


def _outline(meshes: dict) -> np.ndarray:
    """Segments (2k, 3) of the body outline: extrados, intrados and the two end sections,
    plus every joint section when there are few (voussoirs)."""
    j = np.asarray(meshes["joints"].points).reshape(-1, 2, 3)      # (J, extrados/intrados, 3)
    b = meshes["body"]
    pts, s = np.asarray(b.points), np.asarray(b.point_data["s"])
    y, t = np.asarray(b.point_data["y"]), np.asarray(b.point_data["thickness"])
    segs = []
    for side in (-1, 1):
        sel = np.flatnonzero(np.abs(2 * side * y - t) <= 1e-9 * t)
        q = pts[sel[np.argsort(s[sel], kind="stable")]]
        segs.append(np.stack([q[:-1], q[1:]], 1).reshape(-1, 3))
    if j.shape[0] <= 30:                                        # voussoir joints
        segs.append(j.reshape(-1, 3))
    for end in (s.min(), s.max()):                              # end sections (free ends too)
        q = pts[np.flatnonzero(np.isclose(s, end, rtol=0, atol=1e-12) & (np.abs(2 * np.abs(y) - t) <= 1e-9 * t))]
        segs.append(q[np.argsort(q[:, 0] + q[:, 1])][[0, -1]])
    return np.concatenate(segs)


def _fit_camera(pl, bounds, size, margin: float = 1.25, room: float = 0.82) -> None:
    """Parallel projection of the x-y plane, equal aspect, with the whole body in the left
    ``room`` of the window (the scalar bar takes the right) and ``margin`` around it."""
    x0, x1, y0, y1 = bounds[:4]
    aspect = size[0] / size[1]
    half_h = 0.5 * margin * max(y1 - y0, (x1 - x0) / (room * aspect))
    half_w = half_h * aspect
    cx = 0.5 * (x0 + x1) + half_w * (1.0 - room)                 # body centred in the left part
    cy = 0.5 * (y0 + y1) + 0.03 * half_h                         # a little room for the title
    cam = pl.camera
    cam.parallel_projection = True
    cam.focal_point = (cx, cy, 0.0)
    cam.position = (cx, cy, 10.0 * max(x1 - x0, y1 - y0, 1e-9))
    cam.up = (0.0, 1.0, 0.0)
    cam.parallel_scale = half_h
    pl.renderer.ResetCameraClippingRange()


def render_fields(meshes: dict, path: str | Path, title: str = "", size=(1600, 900),
                  scalars: str = "speed_after") -> Path:
    """Render the meshes of :func:`fembeam.output.export.meshes_of` to the PNG ``path``."""
    _headless_setup()
    import pyvista as pv

    body = pv.from_meshio(meshes["body"])
    f = (size[0] / 1600.0) ** 0.5                         # sizes below are tuned for 1600 px
    pl = pv.Plotter(off_screen=True, window_size=list(size))
    pl.set_background("white")
    pl.add_mesh(body, scalars=scalars, cmap="viridis", show_edges=False, lighting=False,
                clim=[0.0, max(float(np.max(body[scalars])), 1e-12)],
                scalar_bar_args={"title": "speed after (m/s)" if scalars == "speed_after" else scalars,
                                 "color": "black", "vertical": True, "position_x": 0.87,
                                 "position_y": 0.15, "height": 0.7, "width": 0.05,
                                 "title_font_size": max(8, round(20 * f)),
                                 "label_font_size": max(8, round(16 * f))})
    pl.add_lines(_outline(meshes), color="black", width=max(1, 2 * f))
    size_ = float(np.ptp(np.asarray(body.points)[:, :2], axis=0).max())
    if "thrust" in meshes and len(meshes["thrust"].points) > 1:
        pl.add_lines(_dashed(np.asarray(meshes["thrust"].points), size_ / 35), color="black", width=max(1, 3 * f))
    if "impulse" in meshes and len(meshes["impulse"].points) > 1:
        pl.add_mesh(pv.from_meshio(meshes["impulse"]), color="red", line_width=max(2, 4 * f), lighting=False)
    h = meshes["hinges"]
    if len(h.points):
        after = np.asarray(h.point_data["after"]) == 1
        for sel, color, ps in ((~after, "grey", 22), (after, "blue", 14)):
            if sel.any():
                pl.add_points(np.asarray(h.points)[sel], color=color, point_size=max(4, ps * f),
                              render_points_as_spheres=True, lighting=False)
    if title:
        pl.add_text(title, position="upper_left", font_size=max(7, round(14 * f)), color="black")
    _fit_camera(pl, body.bounds, size)
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    try:
        with atomic(path) as tmp:
            pl.screenshot(tmp)
    finally:
        pl.close()
    return path


def render_png(result, path: str | Path, size=(1600, 900)) -> Path:
    """Render an analysis off-screen with pyvista (VTK) to a PNG picture.

    The meshes of :func:`~fembeam.output.export.write_vtk`: the arch body coloured by the
    speed after the impact (m/s, normalised mechanism), the impulse line (red), the thrust
    line (dashed black), the hinges before the impact (grey) and after it (blue), in the
    x-y plane (m) with a parallel projection and a title with ``r`` and ``A_L`` (g). On a
    machine without a display it renders through EGL (see :mod:`fembeam.output.render`).

    Parameters
    ----------
    result : AnalysisResult
        An analysis with a limit-analysis mechanism (:func:`fembeam.analyze`).
    path : str or pathlib.Path
        The PNG file; its directory is created if needed; written atomically.
    size : tuple of (int, int), optional
        Width and height of the picture in pixels (default ``(1600, 900)``).

    Returns
    -------
    pathlib.Path
        The file written.

    Raises
    ------
    InputError
        The analysis found no mechanism (nothing to render).
    FembeamError
        No display and neither libEGL nor libOSMesa on the machine.

    Examples
    --------
    >>> import pathlib, tempfile
    >>> import fembeam
    >>> arch = fembeam.CircularArch(radius=1.0, thickness=0.15, embrace_deg=157.5)
    >>> from fembeam.output.render import render_png
    >>> res = fembeam.analyze(arch, voussoirs=12)
    >>> path = pathlib.Path(tempfile.mkdtemp()) / "arch.png"
    >>> path = render_png(res, path, size=(320, 180))
    >>> print(path.name, path.stat().st_size > 0)
    arch.png True
    """
    from .export import fields_of, meshes_of

    meshes = meshes_of(*fields_of(result, "render"))
    return render_fields(meshes, path, title_of(result), size)
