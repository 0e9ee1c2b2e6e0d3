"""Output of rocking time histories (fembeam.output.motion): moved outlines against closed
forms, the ParaView series read back with meshio, the history figure's lines against the
history columns, the GIF's frames, and atomic writing."""
import dataclasses
import xml.etree.ElementTree as ET

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import meshio  # noqa: E402
import numpy as np  # noqa: E402
import pytest  # noqa: E402
from PIL import Image  # noqa: E402

from fembeam import CircularArch, StraightMember  # noqa: E402
from fembeam.dynamics.ground import GroundMotion  # noqa: E402
from fembeam.dynamics.rocking import rock  # noqa: E402
from fembeam.errors import InputError  # noqa: E402
from fembeam.mechanisms import Mechanism  # noqa: E402
from fembeam.output import motion  # noqa: E402
from fembeam.output.motion import frame_rows, history_figure, outline, plot_history, section_layout, \
    write_gif, write_pvd  # noqa: E402

H, W = 2.0, 0.5


@pytest.fixture(scope="module")
def block():
    return StraightMember(height=H, width=W)


@pytest.fixture(scope="module")
def block_res(block):
    """Housner block under a one-sine pulse: rocks on both corners, a few impacts, survives."""
    return rock(block, GroundMotion.sine(0.5, 0.5), voussoirs=1, t_end=3.0, thrust_check=False)


@pytest.fixture(scope="module")
def over_res(block):
    """The same block under a rectangular pulse: overturns."""
    return rock(block, GroundMotion.rectangular(0.6, 1.0), voussoirs=1, thrust_check=False)


@pytest.fixture(scope="module")
def arch_res():
    """Oppenheim's arch, 7 voussoirs, El Centro at PGA 0.5 g: four-hinge mechanisms."""
    return rock(CircularArch.from_ratio(157.5, 0.15), GroundMotion.record("elcentro").to_pga(0.5),
                voussoirs=7, t_end=8.0, thrust_check=False)


def _rotated_block(side, theta, s):
    """Closed form: the faces x = -W/2 (extrados) and x = +W/2 (intrados) at heights s,
    turned by theta about the base corner the block pivots on."""
    b = W / 2
    px = -b if side == "extrados" else b
    c, sn = np.cos(theta), np.sin(theta)
    out = []
    for x in (-b, b):
        rx, ry = x - px, s
        out.append(np.array([px + c * rx - sn * ry, sn * rx + c * ry]))
    return out


def _area(P):
    x, y = P
    return 0.5 * abs(np.dot(x, np.roll(y, -1)) - np.dot(y, np.roll(x, -1)))


# --------------------------------------------------------------------------- outline
def test_outline_at_rest_is_extrados_then_intrados():
    arch = CircularArch.from_ratio(157.5, 0.15)
    s = np.linspace(0.0, arch.length, 33)
    t = arch.thickness_at(s)
    expect = np.hstack([arch.point(s, -t / 2), arch.point(s[::-1], t[::-1] / 2)])
    P = outline(arch, None, 0.7, sections=33)
    assert P.shape == (2, 66)
    assert np.max(np.abs(P - expect)) < 1e-14
    # extrados radius R + t/2 from the left springing (x < 0) to the right, intrados back
    r = np.hypot(*P)
    assert np.allclose(r[:33], 1.075, atol=1e-14) and np.allclose(r[33:], 0.925, atol=1e-14)
    assert P[0, 0] < 0 < P[0, 32]


def test_outline_of_result_index_and_rest(block_res):
    P_rest = outline(block_res, -1, 0.3, sections=11)
    assert np.max(np.abs(P_rest - outline(block_res.curve, None, sections=11))) == 0
    m = block_res.mechanisms[1]
    assert np.array_equal(outline(block_res, 1, 0.2, sections=11), outline(block_res.curve, m, 0.2, sections=11))
    with pytest.raises(InputError):
        outline(block_res, len(block_res.mechanisms), 0.1)
    with pytest.raises(InputError):
        outline(block_res.curve, 0, 0.1)          # an index needs a result
    with pytest.raises(InputError):
        outline(CircularArch(), m, 0.1)           # mechanism of another member


@pytest.mark.parametrize("side", ["extrados", "intrados"])
@pytest.mark.parametrize("theta", [0.1, -0.35, 1.2])
def test_block_outline_is_the_rotated_rectangle(block, side, theta):
    m = Mechanism(block, (0.0,), (side,))
    P = outline(block, m, theta, sections=9)
    s = np.linspace(0.0, H, 9)
    left, right = _rotated_block(side, theta, s)
    assert P.shape == (2, 18)                      # the zero-length base piece is not drawn
    assert np.max(np.abs(P[:, :9] - left)) < 1e-14
    assert np.max(np.abs(P[:, 9:] - right[:, ::-1])) < 1e-14
    assert _area(P) == pytest.approx(W * H, rel=1e-13)
    # the pivot corner stays on the base, the other base corner is lifted by W |sin theta|
    pivot = 0 if side == "extrados" else 17
    assert np.allclose(P[:, pivot], [-W / 2 if side == "extrados" else W / 2, 0.0], atol=1e-15)
    assert abs(P[1, 17 - pivot]) == pytest.approx(W * abs(np.sin(theta)), rel=1e-13)


def test_four_hinge_outline_keeps_the_pivots_shared(arch_res):
    curve = arch_res.curve
    L = curve.length
    n_checked = 0
    for k, m in enumerate(arch_res.mechanisms):
        assert m.n_hinges == 4
        theta = 0.03 * m.compatible_sign()
        conf = m.configuration(theta)
        assert conf.opens and not conf.locked
        P = outline(arch_res, k, theta, sections=41)
        s, seg, ends = section_layout(curve, m.s, 41)
        n = s.size
        assert P.shape == (2, 2 * n)
        E, I = P[:, :n], P[:, n:][:, ::-1]
        rest = outline(curve, None, sections=41)
        rest_s = np.linspace(0, L, 41)
        piv = conf.hinge_points()
        for h, (sh, side) in enumerate(zip(m.s, m.sides)):
            on, off = (E, I) if side == "extrados" else (I, E)
            idx = np.flatnonzero(np.abs(s - sh) < 1e-12)
            if 0 < sh < L:
                # the section is drawn twice: left piece then right piece; they meet at the pivot
                assert idx.size == 2 and seg[idx[0]] + 1 == seg[idx[1]]
                assert np.max(np.abs(on[:, idx] - piv[:, [h, h]])) < 1e-13
                gap = np.linalg.norm(off[:, idx[0]] - off[:, idx[1]])
                # the joint opens by about t |relative rotation| on the other edge
                dphi = abs(conf.hinge_rotations()[h])
                assert gap == pytest.approx(curve.thickness * 2 * np.sin(dphi / 2), rel=1e-9)
                assert gap > 1e-4
                n_checked += 1
            else:
                # springing pivot: stays at its rest position on the abutment
                assert idx.size == 1
                j = idx[0]
                assert np.max(np.abs(on[:, j] - piv[:, h])) < 1e-13
                rest_pt = curve.point(sh, (0.5 if side == "intrados" else -0.5) * curve.thickness)
                assert np.max(np.abs(on[:, j] - rest_pt)) < 1e-13
        # each piece moves rigidly: distances between its extrados points are those at rest
        for p in range(ends.size - 1):
            j = np.flatnonzero(seg == p)
            ref = curve.point(s[j], -0.5 * curve.thickness)
            d = np.linalg.norm(E[:, j[:, None]] - E[:, j[None, :]], axis=0)
            d0 = np.linalg.norm(ref[:, :, None] - ref[:, None, :], axis=0)
            assert np.max(np.abs(d - d0)) < 1e-13
        assert rest.shape == (2, 82) and np.allclose(rest[:, :41], curve.point(rest_s, -0.075))
    assert n_checked >= 4


def test_frame_rows():
    t = np.arange(10.0)
    assert np.array_equal(frame_rows(t, 20), np.arange(10))
    r = frame_rows(t, 4)
    assert r.size == 4 and r[0] == 0 and r[-1] == 9 and np.all(np.diff(r) > 0)
    assert np.array_equal(frame_rows(t, 1), [9])
    # of rows sharing one time only the last is kept
    assert np.array_equal(frame_rows(np.array([0.0, 1.0, 1.0, 2.0]), 10), [0, 2, 3])
    with pytest.raises(InputError):
        frame_rows(t, 0)


# --------------------------------------------------------------------------- ParaView
def _read_pvd(path):
    root = ET.parse(path).getroot()
    assert root.tag == "VTKFile" and root.get("type") == "Collection"
    ds = root.findall("./Collection/DataSet")
    return [float(d.get("timestep")) for d in ds], [d.get("file") for d in ds]


def test_write_pvd_block(block_res, tmp_path):
    res = block_res
    h = res.history
    path = tmp_path / "block.pvd"
    files = write_pvd(res, path, frames=25, sections=9)
    assert len(files) == 26 and files[-1] == path and all(f.exists() for f in files)
    assert sorted(p.name for p in tmp_path.iterdir()) == sorted(f.name for f in files)   # nothing else
    times, names = _read_pvd(path)
    assert names == [f"block_{j:04d}.vtu" for j in range(25)] == [f.name for f in files[:-1]]
    rows = frame_rows(h["t"], 25)
    assert np.all(np.diff(times) > 0)
    assert times == [float(x) for x in h["t"][rows]]       # exact: the history's times
    assert times[-1] == h["t"][-1] and times[0] == h["t"][0]
    moving = 0
    for name, i in zip(names, rows):
        m = meshio.read(tmp_path / name)
        quads = m.cells_dict["quad"]
        assert m.points.shape == (18, 3) and quads.shape == (8, 4)
        d = m.point_data["displacement"]
        rest = m.points - d
        k = int(h["mechanism"][i])
        # rest positions: the two faces x = -+W/2 at the 9 heights
        s = np.linspace(0, H, 9)
        assert np.max(np.abs(rest[:, :2] - np.column_stack([np.r_[np.full(9, -W / 2), np.full(9, W / 2)],
                                                             np.r_[s, s]]))) < 1e-14
        assert np.all(m.points[:, 2] == 0) and np.all(d[:, 2] == 0)
        piece = m.cell_data["piece"][0]
        if k < 0:
            assert np.all(d == 0) and np.all(piece == -1)
        else:
            moving += 1
            side = res.mechanisms[k].sides[0]
            left, right = _rotated_block(side, h["theta"][i], s)
            assert np.max(np.abs(m.points[:, :2] - np.hstack([left, right]).T)) < 1e-13
            assert np.all(piece == 1)
        # quads counter-clockwise, total area W H
        x, y = m.points[quads, 0], m.points[quads, 1]
        a = 0.5 * np.sum(x * np.roll(y, -1, axis=1) - y * np.roll(x, -1, axis=1), axis=1)
        assert np.all(a > 0) and a.sum() == pytest.approx(W * H, rel=1e-12)
    assert moving >= 5


def test_write_pvd_arch_same_mesh_every_frame(arch_res, tmp_path):
    res = arch_res
    files = write_pvd(res, tmp_path / "arch.pvd", frames=30, sections=41)
    assert len(files) == 31
    times, names = _read_pvd(files[-1])
    meshes = [meshio.read(tmp_path / n) for n in names]
    hinges = np.concatenate([m.s for m in res.mechanisms])
    s, seg, ends = section_layout(res.curve, hinges, 41)
    n = s.size
    rest = np.column_stack([*res.curve.point(np.r_[s, s], np.r_[np.full(n, -0.075), np.full(n, 0.075)])])
    area0 = None
    pieces = set()
    for m in meshes:
        assert m.points.shape == (2 * n, 3)
        assert len(m.cells_dict["quad"]) == n - (ends.size - 1)
        assert np.max(np.abs(m.points[:, :2] - m.point_data["displacement"][:, :2] - rest)) < 1e-13
        q = m.cells_dict["quad"]
        x, y = m.points[q, 0], m.points[q, 1]
        a = 0.5 * np.sum(x * np.roll(y, -1, axis=1) - y * np.roll(x, -1, axis=1), axis=1)
        area0 = a.sum() if area0 is None else area0
        assert np.all(a > 0) and a.sum() == pytest.approx(area0, rel=1e-12)   # rigid pieces
        pieces.update(np.unique(m.cell_data["piece"][0]).tolist())
    assert pieces == {-1, 1, 2, 3}
    assert np.max([np.abs(m.point_data["displacement"]).max() for m in meshes]) > 1e-3


# --------------------------------------------------------------------------- figure
def _line(ax, label):
    (ln,) = [x for x in ax.get_lines() if x.get_label() == label]
    return ln


def test_history_figure_lines_are_the_history(block_res):
    res = dataclasses.replace(block_res, thrust_line_exits_at=0.75)
    h = res.history
    fig = history_figure(res)
    try:
        ax_a, ax_th, ax_e = fig.axes[:3]
        assert "(g)" in ax_a.get_ylabel() and "(rad)" in ax_th.get_ylabel() and "(J" in ax_e.get_ylabel()
        assert ax_e.get_xlabel() == "time t (s)"
        assert ax_a.get_shared_x_axes().joined(ax_a, ax_e)
        assert np.array_equal(_line(ax_a, "a_g").get_xdata(), h["t"])
        assert np.array_equal(_line(ax_a, "a_g").get_ydata(), h["a_g"])
        assert np.array_equal(_line(ax_th, r"$\theta$").get_ydata(), h["theta"])
        assert np.array_equal(_line(ax_e, "K (kinetic)").get_ydata(), h["K"])
        assert np.array_equal(_line(ax_e, "V (potential)").get_ydata(), h["V"])
        assert np.array_equal(_line(ax_e, "K + V").get_ydata(), h["K"] + h["V"])
        imp = _line(ax_th, f"impacts ({len(res.impacts)})")
        assert len(res.impacts) >= 2
        assert np.array_equal(imp.get_xdata(), [e.t for e in res.impacts]) and np.all(imp.get_ydata() == 0)
        ex = [x for x in ax_th.get_lines() if x.get_label().startswith("thrust line leaves")]
        assert len(ex) == 1 and np.all(np.asarray(ex[0].get_xdata()) == 0.75) and ex[0].get_linestyle() == "--"
        assert not [x for x in ax_th.get_lines() if x.get_label().startswith("overturned")]
        legend = [t.get_text() for t in ax_th.get_legend().get_texts()]
        assert any(t.startswith("thrust line leaves") for t in legend)
        assert fig._suptitle.get_text() == f"survived - {res.ground.name}"
    finally:
        plt.close(fig)


def test_history_figure_marks_overturning(over_res):
    assert over_res.outcome == "overturned"
    fig = history_figure(over_res)
    try:
        ov = [x for x in fig.axes[1].get_lines() if x.get_label().startswith("overturned")]
        assert len(ov) == 1 and np.all(np.asarray(ov[0].get_xdata()) == over_res.t_overturn)
        assert "overturned" in fig._suptitle.get_text()
    finally:
        plt.close(fig)


@pytest.mark.parametrize("suffix,magic", [(".png", b"\x89PNG"), (".pdf", b"%PDF"), (".svg", b"<?xml")])
def test_plot_history_files(block_res, tmp_path, suffix, magic):
    p = tmp_path / f"h{suffix}"
    assert plot_history(block_res, p) is None
    assert p.read_bytes()[:len(magic)] == magic
    assert [x.name for x in tmp_path.iterdir()] == [p.name]
    if suffix == ".png":
        im = Image.open(p)
        assert im.size[0] > 500 and np.unique(np.asarray(im.convert("L"))).size > 10   # not blank


# --------------------------------------------------------------------------- GIF
def test_write_gif_frames(over_res, tmp_path):
    p = tmp_path / "over.gif"
    assert write_gif(over_res, p, frames=9, fps=10, sections=11) is None
    im = Image.open(p)
    assert im.format == "GIF" and im.n_frames == 9
    assert im.info["duration"] == 100
    # the first frame (at rest) and the last (tilted) differ
    first = np.asarray(im.convert("RGB"))
    im.seek(8)
    assert np.any(first != np.asarray(im.convert("RGB")))
    assert [x.name for x in tmp_path.iterdir()] == ["over.gif"]


# --------------------------------------------------------------------------- failures
def test_missing_directory_and_bad_suffix(block_res, tmp_path):
    missing = tmp_path / "nope"
    for f, name in ((plot_history, "h.png"), (write_pvd, "s.pvd"), (write_gif, "a.gif")):
        with pytest.raises(InputError, match="does not exist"):
            f(block_res, missing / name)
    for f, name in ((plot_history, "h.jpg"), (write_pvd, "s.vtu"), (write_gif, "a.mp4")):
        with pytest.raises(InputError):
            f(block_res, tmp_path / name)
    assert not missing.exists() and list(tmp_path.iterdir()) == []
    empty = dataclasses.replace(block_res, history={})
    with pytest.raises(InputError, match="empty"):
        write_pvd(empty, tmp_path / "e.pvd")
    assert list(tmp_path.iterdir()) == []


def test_failures_leave_no_files(block_res, tmp_path, monkeypatch):
    real = meshio.write
    calls = []

    def flaky(path, mesh, *a, **k):
        calls.append(path)
        if len(calls) == 3:
            raise OSError("disk full")
        return real(path, mesh, *a, **k)

    monkeypatch.setattr(meshio, "write", flaky)
    with pytest.raises(OSError, match="disk full"):
        write_pvd(block_res, tmp_path / "x.pvd", frames=5, sections=5)
    assert list(tmp_path.iterdir()) == []
    monkeypatch.setattr(meshio, "write", real)

    from PIL import Image

    def broken(self, fp, *a, **k):
        open(fp, "wb").write(b"GIF89a partial")
        raise RuntimeError("encoder failed")

    monkeypatch.setattr(Image.Image, "save", broken)
    with pytest.raises(RuntimeError, match="encoder failed"):
        write_gif(block_res, tmp_path / "x.gif", frames=3, sections=5)
    assert list(tmp_path.iterdir()) == []

    def bad_savefig(self, fname, **kw):
        open(fname, "wb").write(b"partial")
        raise RuntimeError("render failed")

    monkeypatch.setattr(motion, "history_figure", lambda r: plt.figure())
    monkeypatch.setattr(matplotlib.figure.Figure, "savefig", bad_savefig)
    with pytest.raises(RuntimeError, match="render failed"):
        plot_history(block_res, tmp_path / "x.png")
    assert list(tmp_path.iterdir()) == []
