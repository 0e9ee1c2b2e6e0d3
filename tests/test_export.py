"""VTK export (fembeam.output.export): read the files back with meshio and check the fields
against the rigid-element fields, the impulses and the hinges of the solution."""
import json

import meshio
import numpy as np
import pytest

from fembeam import CircularArch, analyze
from fembeam.cli import main
from fembeam.fem import discretize, uniform_nodes
from fembeam.mechanisms import side_of
from fembeam.output.export import write_fields, write_vtk


@pytest.fixture(scope="module")
def oppenheim():
    """Oppenheim's arch, 7 voussoirs, beta = 157.5 deg (paper: 5 hinges after, r = 0.560)."""
    return analyze(CircularArch.from_ratio(157.5, 0.15), voussoirs=7)


def _read(files):
    return {k: meshio.read(p) for k, p in files.items() if k != "multiblock"}


def test_rigid_motion_is_exact_and_continuous(tmp_path):
    """A global rigid motion V + omega k x (X - A): every exported point velocity equals it."""
    arch = CircularArch.from_ratio(120.0, 0.2, radius=2.0)
    disc = discretize(arch, uniform_nodes(arch, 9))
    V, om, A = np.array([0.3, -0.2]), 0.7, np.array([0.1, 0.2])
    d = disc.rigid(V=V, omega=om, about=A)
    m = _read(write_fields(tmp_path / "rigid.vtu", disc, d, 2 * d, layers=3))["body"]
    X = m.points[:, :2]
    exact = V + om * np.column_stack([-(X[:, 1] - A[1]), X[:, 0] - A[0]])
    assert np.max(np.abs(m.point_data["velocity_before"][:, :2] - exact)) < 1e-13
    assert np.allclose(m.point_data["velocity_after"][:, :2], 2 * exact, atol=1e-13)
    assert np.all(m.point_data["velocity_after"][:, 2] == 0)
    assert np.allclose(m.cell_data["omega_before"][0], om)
    # geometry: points between intrados (R - t/2) and extrados (R + t/2) radii, quads 3 thick
    r = np.hypot(X[:, 0], X[:, 1])
    assert r.min() == pytest.approx(2.0 - 0.2, abs=1e-12) and r.max() == pytest.approx(2.0 + 0.2, abs=1e-12)
    h = np.diff(disc.nodes_s)
    max_cell = min(arch.length / 200, 0.5 * arch.thickness)
    assert len(m.cells_dict["quad"]) == 3 * int(np.sum(np.ceil(h / max_cell - 1e-9)))


def test_body_fields_are_the_rigid_element_fields(paper_result, tmp_path):
    res = paper_result
    imp = res.impact
    disc = imp.disc
    m = _read(write_vtk(res, tmp_path / "paper.vtu"))["body"]
    e = m.point_data["element"]
    X = m.points[:, :2].T
    for name, d in (("before", imp.d0), ("after", imp.d)):
        w, v, om = d.reshape(-1, 3)[e].T
        P, t, n = (disc.frames[k][:, e] for k in ("P", "t", "n"))
        direct = w * t + v * n + om * np.array([-(X[1] - P[1]), X[0] - P[0]])
        assert np.allclose(m.point_data[f"velocity_{name}"][:, :2].T, direct, rtol=0, atol=1e-12)
        assert np.allclose(m.point_data[f"speed_{name}"], np.hypot(*direct), atol=1e-12)
    # cells: one strip per element at least, 2 layers; every element present
    assert len(m.cells_dict["quad"]) >= 2 * disc.n_elements
    assert set(np.unique(m.cell_data["element"][0])) == set(range(disc.n_elements))


def _edge_jumps(m, disc, d_name):
    """Velocity jump (right minus left element) at the intrados/extrados points of every
    interior joint, from the exported points alone."""
    e, s, y = m.point_data["element"], m.point_data["s"], m.point_data["y"]
    vel = m.point_data[f"velocity_{d_name}"][:, :2]
    jumps = np.zeros((disc.n_elements - 1, 2))
    for k, side in enumerate((+1, -1)):
        edge = np.isclose(2 * side * y, m.point_data["thickness"])
        right_end = edge & np.isclose(s, disc.nodes_s[e + 1])
        left_end = edge & np.isclose(s, disc.nodes_s[e])
        vr = np.zeros((disc.n_elements, 2)); vr[e[right_end]] = vel[right_end]   # noqa: E702
        vl = np.zeros((disc.n_elements, 2)); vl[e[left_end]] = vel[left_end]     # noqa: E702
        jumps[:, k] = np.linalg.norm(vl[1:] - vr[:-1], axis=1)
    return jumps


def test_jumps_only_at_post_impact_hinges(oppenheim, tmp_path):
    """Closed joints: no jump at either edge; hinges: no jump at the pivot edge, a jump
    at the opposite edge (the field is a relative rotation about the pivot)."""
    res = oppenheim
    disc = res.impact.disc
    m = _read(write_vtk(res, tmp_path / "opp.vtu"))["body"]
    jumps = _edge_jumps(m, disc, "after")          # (interior joints, [intrados, extrados])
    scale = np.max(m.point_data["speed_after"])
    interior = {h.joints[0] - 1: h.side for h in res.hinges_after if 0 < h.joints[0] < disc.n_joints - 1}
    assert len(interior) == 3                      # 45, 67.5 (intrados) and 112.5 deg (extrados)
    for j in range(disc.n_elements - 1):
        pivot, other = (0, 1) if interior.get(j) == "intrados" else (1, 0)
        assert jumps[j, pivot] < 1e-9 * scale
        assert (jumps[j, other] > 1e-3 * scale) == (j in interior)


def test_impulse_line_hinges_and_joint_data(oppenheim, tmp_path):
    res = oppenheim
    imp, lim = res.impact, res.limit
    R, t = 1.0, 0.15
    parts = _read(write_vtk(res, tmp_path / "opp.vtu"))
    line, hinges, joints = parts["impulse"], parts["hinges"], parts["joints"]
    # the impulse line passes through the post-impact hinges: |e| = t/2 on the pivot side
    after = hinges.point_data["after"] == 1
    assert after.sum() == len(res.hinges_after) == 5
    assert (~after).sum() == len(res.hinges_before) == 4
    for X, side in zip(hinges.points[after], hinges.point_data["side"][after]):
        dist = np.linalg.norm(line.points - X, axis=1)
        k = int(np.argmin(dist))
        assert dist[k] < 1e-8 * R
        assert line.point_data["eccentricity"][k] == pytest.approx(side * t / 2, abs=1e-8)
        assert np.hypot(*X[:2]) == pytest.approx(R - side * t / 2, abs=1e-12)   # intrados inside
    assert [side_of(h.side).code for h in res.hinges_after] == list(hinges.point_data["side"][after])
    # the line stays within the thickness: R - t/2 <= |X| <= R + t/2
    r = np.hypot(line.points[:, 0], line.points[:, 1])
    assert np.all(np.abs(r - R) <= t / 2 + 1e-9)
    assert np.all(np.isfinite(imp.eccentricity)) and len(line.cells_dict["line"]) == 7
    # joint sections carry the impulses and the thrust of the solution
    assert np.allclose(joints.cell_data["I_t"][0], imp.I_t)
    assert np.allclose(joints.cell_data["moment"][0], imp.moment)
    assert np.allclose(joints.cell_data["N"][0], (lim.N[0] + lim.N[1]) * 9.81 / 1000)   # kN/m: the LP's are per g
    assert len(joints.cells_dict["line"]) == imp.disc.n_joints == 8
    # thrust line: inside the thickness, on the edge at the hinges before the impact
    th = parts["thrust"]
    rt = np.hypot(th.points[:, 0], th.points[:, 1])
    assert np.all(np.abs(rt - R) <= t / 2 + 1e-9)
    for X in hinges.points[~after]:
        assert np.min(np.linalg.norm(th.points - X, axis=1)) < 1e-8


def test_continuous_hinges_on_edges_and_multiblock(paper_result, tmp_path):
    import pyvista as pv

    res = paper_result
    files = write_vtk(res, tmp_path / "c" / "arch")       # suffix added
    assert files["body"].name == "arch.vtu" and files["multiblock"].name == "arch.vtm"
    mb = pv.read(files["multiblock"])
    # body, joints, impulse, thrust, hinges, and the thrust lines of H_min and H_max
    assert mb.n_blocks == 7 and "velocity_after" in mb["body"].point_data
    assert {"thrust_min", "thrust_max"} <= set(mb.keys())
    h = meshio.read(files["hinges"])
    r = np.hypot(h.points[:, 0], h.points[:, 1])
    assert np.allclose(r, 1.0 - h.point_data["side"] * 0.075, atol=1e-12)
    assert np.allclose(np.sort(h.point_data["angle_deg"][h.point_data["after"] == 1]),
                       sorted(x.angle_deg for x in res.hinges_after))


def test_cli_json_stdout_untouched(tmp_path, capsys):
    out = tmp_path / "cli.vtu"
    fig = tmp_path / "cli.svg"
    assert main(["analyze", "--voussoirs", "7", "--json", "--vtk", str(out), "--figure", str(fig)]) == 0
    stdout = capsys.readouterr().out
    d = json.loads(stdout)                         # the whole of stdout is one JSON object
    assert d["r"] == pytest.approx(0.55924, abs=5e-5)
    assert out.exists() and (tmp_path / "cli_impulse.vtu").exists() and fig.stat().st_size > 1000
    assert main(["analyze", "--png", str(tmp_path / "x.jpg")]) == 2


def test_rocking_block(tmp_path):
    """Housner's block: one joint, so each line is one point (a vertex) on the base; the
    hinges sit on the base corners (before: right corner, after: left corner)."""
    from fembeam.geometry import StraightMember

    res = analyze(StraightMember(1.0, 0.3), voussoirs=1)
    parts = _read(write_vtk(res, tmp_path / "block.vtu"))
    for key in ("impulse", "thrust"):
        assert [c.type for c in parts[key].cells] == ["vertex"] and len(parts[key].points) == 1
    h = parts["hinges"]
    # the thrust passes through the pivot before the impact, the impulse through the new one
    assert np.allclose(parts["thrust"].points[0], h.points[h.point_data["after"] == 0][0], atol=1e-9)
    assert np.allclose(parts["impulse"].points[0], h.points[h.point_data["after"] == 1][0], atol=1e-9)
    assert np.allclose(h.points[:, :2], [[0.15, 0.0], [-0.15, 0.0]], atol=1e-12)
    b = parts["body"]
    assert np.allclose([b.points[:, 0].min(), b.points[:, 0].max(), b.points[:, 1].max()], [-0.15, 0.15, 1.0])
