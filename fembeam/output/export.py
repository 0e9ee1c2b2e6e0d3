"""VTK export of an impact solution with meshio (files described in docs/visualisation.md).

:func:`write_fields` takes the raw ingredients (discretisation, pre-impact field
``d0``, post-impact field ``d``, hinges before/after, impulse line, thrust line) so
that any result type can use it; :func:`write_vtk` feeds it an :class:`AnalysisResult`.
One call writes an unstructured grid per part and a ParaView multiblock index::

    out.vtu           arch body: quads across the thickness, rigid velocity fields
    out_joints.vtu    joint sections (extrados -> intrados segments): impulses, thrust
    out_impulse.vtu   impulse line, polyline through X_j + e_j n_j
    out_thrust.vtu    thrust line (limit analysis), polyline through X_j + e_j n_j
    out_hinges.vtu    hinges before/after as vertex cells on the edge they pivot on
    out_fill.vtu      (an arch with fill) the fill columns, cell data ``piece``: the
                      element or voussoir each column moves with
    out_thrust_min.vtu, out_thrust_max.vtu   (an arch on two abutments) the thrust lines of
                      the minimum and maximum thrust under the dead loads
    out.vtm           multiblock index of the parts written (ParaView and pyvista open
                      it at once)

Conventions (docs/theory.md, Sect. 1): ``y`` is the offset along the inward normal ``n``, intrados at
``y = +t/2``; eccentricities are ``y`` of the line (m); velocities in m/s for the
normalised mechanism (unit mean horizontal speed of ``u = -d0``); impulses in N s/m
(per metre of width) for that velocity scale (paper sign: ``I_t < 0`` is compression); thrust
forces in kN/m.  Points are stored as ``(npoints, 3)`` with ``z = 0``.  A field may
be given as element DOFs or as a :class:`~fembeam.mechanisms.mechanism.Mechanism`
(evaluated on the mesh), hinges as :class:`~fembeam.mechanisms.hinge.Hinge` objects or
as a Mechanism (its hinges).
"""
from __future__ import annotations

from pathlib import Path
from typing import Mapping, Sequence

import numpy as np

from ..fem import Discretization
from ..mechanisms.hinge import Hinge, pivot_fractions, side_of
from ..mechanisms.mechanism import Mechanism
from ..units import kN

__all__ = ["as_dofs", "as_hinges", "rigid_velocity", "body_mesh", "joints_mesh", "line_mesh", "hinges_mesh",
           "impulse_line", "thrust_line", "write_fields", "write_vtk", "meshes_of", "output_paths"]

PARTS = ("body", "joints", "impulse", "thrust", "hinges", "fill", "thrust_min", "thrust_max")


def as_dofs(disc: Discretization, field) -> np.ndarray:
    """Element DOFs of ``field``: DOFs as they are, or a Mechanism evaluated on ``disc``."""
    return field.dofs(disc) if isinstance(field, Mechanism) else np.asarray(field, float)


def as_hinges(hinges) -> list[Hinge]:
    """Hinges as they are, or the hinges of a Mechanism (rotations at its rate)."""
    return hinges.hinges() if isinstance(hinges, Mechanism) else list(hinges)


def rigid_velocity(disc: Discretization, d: np.ndarray, elem: np.ndarray, X: np.ndarray) -> np.ndarray:
    """Velocity (2, n) of element ``elem[i]``'s rigid field at the point ``X[:, i]``:
    ``w t_e + v n_e + omega k x (X - P_e)`` (m/s)."""
    fr = disc.frames
    w, v, om = np.asarray(d, float).reshape(-1, 3)[elem].T
    P, t, n = fr["P"][:, elem], fr["t"][:, elem], fr["n"][:, elem]
    r = X - P
    return w * t + v * n + om * np.array([-r[1], r[0]])


def _section_points(disc: Discretization, s: np.ndarray, y_frac: np.ndarray) -> np.ndarray:
    """Points ``X(s) + y n(s)`` with ``y = y_frac t(s)``, broadcast over ``s`` and ``y_frac``."""
    c = disc.curve
    return c.point(s, y_frac * c.thickness_at(s))


def _xyz(p2: np.ndarray) -> np.ndarray:
    """(2, n) -> (n, 3) with z = 0."""
    return np.column_stack([p2[0], p2[1], np.zeros(p2.shape[1])])


def body_mesh(disc: Discretization, fields: Mapping[str, np.ndarray], layers: int = 2,
              max_cell: float | None = None):
    """Quads of each rigid element, ``layers`` through the thickness and as many along the
    element as keep cells shorter than ``max_cell`` (m, default min(L/200, t/2)).

    Points are not shared between elements, so each element's rigid field is evaluated at
    its own corners and jumps at open joints show.  ``fields`` maps a name to element DOFs
    (length 3 x elements); each gives point data ``velocity_<name>`` (m/s, 3 comps),
    ``speed_<name>`` and cell data ``omega_<name>`` (rad/s, counter-clockwise).
    """
    import meshio

    c = disc.curve
    sn = disc.nodes_s
    h = np.diff(sn)
    if max_cell is None:
        max_cell = min(c.length / 200.0, 0.5 * float(np.min(c.thickness_at(sn))))
    na = np.maximum(1, np.ceil(h / max_cell - 1e-9).astype(int))       # cells along each element
    ne, nl = h.size, int(layers)
    # along-element parameter of every point column, element by element
    col_elem = np.repeat(np.arange(ne), na + 1)
    col_start = np.concatenate([[0], np.cumsum(na + 1)[:-1]])
    k = np.arange(col_elem.size) - col_start[col_elem]
    s_col = sn[col_elem] + h[col_elem] * k / na[col_elem]
    y_frac = np.linspace(-0.5, 0.5, nl + 1)                            # extrados -> intrados
    S = np.repeat(s_col, nl + 1)
    Y = np.tile(y_frac, s_col.size)
    elem = np.repeat(col_elem, nl + 1)
    X = _section_points(disc, S, Y)
    # quads between consecutive columns of the same element
    cols = np.flatnonzero(np.diff(col_elem) == 0)                      # left column of each strip
    base = cols[:, None] * (nl + 1) + np.arange(nl)[None, :]
    quads = np.stack([base, base + nl + 1, base + nl + 2, base + 1], -1).reshape(-1, 4)
    cell_elem = np.repeat(col_elem[cols], nl)
    T = c.thickness_at(S)
    point_data = {"s": S, "y": Y * T, "thickness": T, "angle_deg": c.angle_deg(S).astype(float),
                  "element": elem.astype(np.int32)}
    cell_data = {"element": [cell_elem.astype(np.int32)]}
    for name, d in fields.items():
        vel = rigid_velocity(disc, d, elem, X)
        point_data[f"velocity_{name}"] = _xyz(vel)
        point_data[f"speed_{name}"] = np.hypot(vel[0], vel[1])
        cell_data[f"omega_{name}"] = [np.asarray(d, float).reshape(-1, 3)[cell_elem, 2]]
    return meshio.Mesh(_xyz(X), [("quad", quads)], point_data=point_data, cell_data=cell_data)


def joints_mesh(disc: Discretization, fields: Mapping[str, np.ndarray], data: Mapping[str, np.ndarray]):
    """One line cell per joint, from the extrados (``y = -t/2``) to the intrados point.

    Cell data: ``angle_deg``, ``s`` (m), ``thickness`` (m), the opening rates
    ``opening_intrados_<name>``/``opening_extrados_<name>`` (m/s) of each field and every
    per-joint array of ``data`` (length J)."""
    import meshio

    J = disc.n_joints
    s = disc.joint_s
    pts = np.stack([_section_points(disc, s, -0.5), _section_points(disc, s, 0.5)], -1)  # (2, J, 2)
    X = pts.reshape(2, -1)                                    # joint by joint: extrados, intrados
    lines = np.arange(2 * J).reshape(J, 2)
    cd = {"angle_deg": disc.joint_angle_deg.astype(float), "s": s, "thickness": disc.joint_thickness}
    for name, d in fields.items():
        eps = disc.B_open @ np.asarray(d, float)
        cd[f"opening_intrados_{name}"], cd[f"opening_extrados_{name}"] = eps[:J], eps[J:]
    for k, v in data.items():
        cd[k] = np.asarray(v, float)
    return meshio.Mesh(_xyz(X), [("line", lines)], cell_data={k: [v] for k, v in cd.items()},
                       point_data={"y": np.tile([-0.5, 0.5], J) * np.repeat(disc.joint_thickness, 2)})


def line_mesh(disc: Discretization, line: Mapping[str, np.ndarray]):
    """Polyline through ``X_j + e_j n_j`` at the joints (``line["eccentricity"]``, m);
    joints where ``e`` is NaN (nothing transmitted) split it into pieces, and a joint with
    no neighbour on the line (a block on its base) is a vertex cell.  Every other
    array of ``line`` of length J becomes point data, with ``angle_deg`` and ``s``."""
    import meshio

    e = np.asarray(line["eccentricity"], float)
    ok = np.flatnonzero(np.isfinite(e))
    s = disc.joint_s[ok]
    c = disc.curve
    X = c.point(s, e[ok])
    consecutive = np.flatnonzero(np.diff(ok) == 1)
    segs = np.column_stack([consecutive, consecutive + 1])
    pd = {"angle_deg": disc.joint_angle_deg[ok].astype(float), "s": s,
          "thickness": disc.joint_thickness[ok]}
    for k, v in line.items():
        v = np.asarray(v, float)
        if k != "angle_deg" and v.shape == e.shape:
            pd[k] = v[ok]
    alone = np.setdiff1d(np.arange(ok.size), segs.ravel())      # isolated joints: vertices
    cells = [(kind, c) for kind, c in (("line", segs.reshape(-1, 2)), ("vertex", alone.reshape(-1, 1)))
             if len(c)]
    return meshio.Mesh(_xyz(X), cells, point_data=pd)


def hinges_mesh(disc: Discretization, before: Sequence[Hinge], after: Sequence[Hinge]):
    """Vertex cells on the pivot edge of each hinge (mid-curve for a separated joint).

    Point data: ``after`` (0 = before the impact, 1 = after), ``side`` (+1 intrados,
    -1 extrados, 0 separated), ``angle_deg``, ``s`` (m), ``rotation`` (rad/s)."""
    import meshio

    before, after = as_hinges(before), as_hinges(after)
    hs = before + after
    s = np.array([h.s for h in hs], float)
    side = np.array([side_of(h.side).code for h in hs], np.int32)
    X = _section_points(disc, s, pivot_fractions(h.side for h in hs)) if hs else np.zeros((2, 0))
    pd = {"after": np.array([0] * len(before) + [1] * len(after), np.int32), "side": side,
          "angle_deg": np.array([h.angle_deg for h in hs], float), "s": s,
          "rotation": np.array([h.rotation for h in hs], float)}
    return meshio.Mesh(_xyz(X), [("vertex", np.arange(len(hs)).reshape(-1, 1))], point_data=pd)


def impulse_line(imp) -> dict:
    """Impulse-line arrays of an :class:`~fembeam.analysis.impact.ImpactResult` (per joint):
    ``eccentricity`` (m), ``I_t``, ``I_n`` (N s/m), ``moment`` (N m s/m), ``mu_intrados``,
    ``mu_extrados`` (fibre impulses >= 0, compression, N s/m)."""
    return {"angle_deg": imp.disc.joint_angle_deg, "eccentricity": imp.eccentricity,
            "I_t": imp.I_t, "I_n": imp.I_n, "moment": imp.moment,
            "mu_intrados": imp.mu[0], "mu_extrados": imp.mu[1]}


def thrust_line(lim) -> dict:
    """Thrust-line arrays of a :class:`~fembeam.analysis.limit.LimitResult`: ``eccentricity`` (m),
    ``N`` (total normal force >= 0 compression, kN/m), ``S`` (shear, kN/m)."""
    return {"angle_deg": lim.disc.joint_angle_deg, "eccentricity": lim.eccentricity,
            "N": kN(lim.N[0] + lim.N[1]), "S": kN(lim.S)}


def meshes_of(disc: Discretization, d0, d, hinges_before: Sequence[Hinge] | Mechanism = (),
              hinges_after: Sequence[Hinge] | Mechanism = (), impulse: Mapping | None = None,
              thrust: Mapping | None = None, layers: int = 2) -> dict:
    """The meshio meshes written by :func:`write_fields`, keyed by part name."""
    fields = {"before": as_dofs(disc, d0), "after": as_dofs(disc, d)}
    jdata = {}
    if impulse is not None:
        jdata.update({f"{k}_impulse" if k == "eccentricity" else k: v
                      for k, v in impulse.items() if k != "angle_deg"})
    if thrust is not None:
        jdata.update({f"{k}_thrust" if k == "eccentricity" else k: v
                      for k, v in thrust.items() if k != "angle_deg"})
    out = {"body": body_mesh(disc, fields, layers), "joints": joints_mesh(disc, fields, jdata),
           "hinges": hinges_mesh(disc, hinges_before, hinges_after)}
    if impulse is not None:
        out["impulse"] = line_mesh(disc, impulse)
    if thrust is not None:
        out["thrust"] = line_mesh(disc, thrust)
    return out


def output_paths(path: str | Path) -> dict[str, Path]:
    """File of each part for the main file ``path`` (``.vtu`` added if missing)."""
    p = Path(path)
    if p.suffix.lower() != ".vtu":
        p = p.with_name(p.name + ".vtu")
    stem = p.with_suffix("")
    out = {"body": p}
    out.update({k: stem.with_name(f"{stem.name}_{k}.vtu") for k in PARTS[1:]})
    out["multiblock"] = stem.with_suffix(".vtm")
    return out


def write_fields(path: str | Path, disc: Discretization, d0, d,
                 hinges_before: Sequence[Hinge] | Mechanism = (), hinges_after: Sequence[Hinge] | Mechanism = (),
                 impulse: Mapping | None = None, thrust: Mapping | None = None,
                 layers: int = 2, extra: Mapping | None = None) -> dict[str, Path]:
    """Write the parts of :func:`meshes_of` next to ``path`` and a ``.vtm`` index; returns
    the written files by part name (see the module docstring).  A part with nothing in
    it (no hinges, no impulse line) is not written, and the index leaves it out."""
    from .files import atomic_group

    paths = output_paths(path)
    paths["body"].parent.mkdir(parents=True, exist_ok=True)
    meshes = meshes_of(disc, d0, d, hinges_before, hinges_after, impulse, thrust, layers)
    meshes.update({k: m for k, m in (extra or {}).items() if m is not None})
    # empty parts are not written (meshio cannot read an empty appended array back)
    parts = [k for k in PARTS if k in meshes and len(meshes[k].points)]
    written = {k: paths[k] for k in parts}
    blocks = "\n".join(f'    <DataSet index="{i}" name="{k}" file="{p.name}"/>'
                       for i, (k, p) in enumerate(written.items()))
    with atomic_group([paths[k] for k in parts] + [paths["multiblock"]]) as tmps:   # the index last
        for k, tmp in zip(parts, tmps):
            meshes[k].write(tmp, file_format="vtu", binary=True)
        Path(tmps[-1]).write_text('<?xml version="1.0"?>\n<VTKFile type="vtkMultiBlockDataSet" '
                                  'version="1.0" byte_order="LittleEndian">\n  <vtkMultiBlockDataSet>\n'
                                  f"{blocks}\n  </vtkMultiBlockDataSet>\n</VTKFile>\n")
    for k in PARTS:
        if k not in written and paths[k].exists():   # stale file of an earlier export
            paths[k].unlink()
    written["multiblock"] = paths["multiblock"]
    return written


def fields_of(result, what: str = "export") -> tuple:
    """Arguments of :func:`write_fields` / :func:`meshes_of` (after ``path``) for an
    :class:`~fembeam.analysis.AnalysisResult`; the impact fields are zero/absent when there
    was no impact. Raises InputError when the analysis found no mechanism."""
    from ..errors import InputError

    lim, imp = result.limit, result.impact
    if lim is None:
        raise InputError(f"nothing to {what}: the analysis has no mechanism (outcome {result.outcome})")
    disc = imp.disc if imp is not None else lim.disc
    d0 = imp.d0 if imp is not None else -lim.u
    d = imp.d if imp is not None else np.zeros_like(d0)
    return (disc, d0, d, result.hinges_before, result.hinges_after,
            impulse_line(imp) if imp is not None else None, thrust_line(lim))


def write_vtk(result, path: str | Path, layers: int = 2) -> dict[str, Path]:
    """Write an analysis to VTK files for ParaView: arch, joints, lines and hinges.

    One unstructured grid per part next to ``path`` (``out.vtu`` the body,
    ``out_joints.vtu``, ``out_impulse.vtu``, ``out_thrust.vtu``, ``out_hinges.vtu``, and for
    an arch as built ``out_fill.vtu``, ``out_thrust_min.vtu``, ``out_thrust_max.vtu``) and a
    ParaView multiblock index ``out.vtm``; the parts and their fields are listed in
    :mod:`fembeam.output.export`. Points are ``(x, y, 0)`` in m; velocities in m/s for the
    normalised mechanism (unit mean horizontal speed of ``u = -d0``), impulses in N s/m
    (``I_t < 0`` is compression), thrust forces in kN/m, eccentricities in m along the
    inward normal (intrados at ``+t/2``). A part with nothing in it is not written.

    Parameters
    ----------
    result : AnalysisResult
        An analysis with a limit-analysis mechanism (:func:`fembeam.analyze`); without an
        impact the post-impact fields are zero and there is no impulse line.
    path : str or pathlib.Path
        The body's file; ``.vtu`` is added if missing, the other parts are named after it.
    layers : int, optional
        Cells of the body through the thickness (default 2).

    Returns
    -------
    dict of str to pathlib.Path
        The files written by part: ``"body"``, ``"joints"``, ``"impulse"``, ``"thrust"``,
        ``"hinges"``, ``"fill"``, ``"thrust_min"``, ``"thrust_max"`` (those written), and
        ``"multiblock"`` (the ``.vtm`` index).

    Raises
    ------
    InputError
        The analysis found no mechanism (nothing to export).

    Examples
    --------
    >>> import pathlib, tempfile
    >>> import fembeam
    >>> arch = fembeam.CircularArch(radius=1.0, thickness=0.15, embrace_deg=157.5)
    >>> from fembeam.output.export import write_vtk
    >>> res = fembeam.analyze(arch, voussoirs=12)
    >>> files = write_vtk(res, pathlib.Path(tempfile.mkdtemp()) / "arch.vtu")
    >>> for part, path in files.items():
    ...     print(f"{part:10s} {path.name}")
    body       arch.vtu
    joints     arch_joints.vtu
    impulse    arch_impulse.vtu
    thrust     arch_thrust.vtu
    hinges     arch_hinges.vtu
    thrust_min arch_thrust_min.vtu
    thrust_max arch_thrust_max.vtu
    multiblock arch.vtm
    """
    return write_fields(path, *fields_of(result), layers, extra=as_built_parts(result))


def as_built_parts(result) -> dict:
    """The parts of an arch as built: its fill columns and the two extreme thrust lines."""
    from .asbuilt import fill_mesh

    disc = result.limit.disc
    out = {"fill": fill_mesh(disc)}
    tr = getattr(result, "thrust", None)
    if tr is not None:
        for which in ("min", "max"):
            e = tr.eccentricity(which) if (which == "min" or np.isfinite(tr.H_max)) else None
            if e is not None:
                out[f"thrust_{which}"] = line_mesh(tr.disc, {"eccentricity": e})
    return out
