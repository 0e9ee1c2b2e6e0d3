"""Paper-style figure (fembeam.output.plotting): what is drawn where, and a non-blank file."""
import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
import pytest  # noqa: E402

from fembeam.output.plotting import draw_paper_figure, plot_paper_figure  # noqa: E402


@pytest.fixture(scope="module")
def axes(paper_result):
    res = paper_result
    fig, ax = plt.subplots()
    draw_paper_figure(ax, res.impact.disc, res.hinges_before, res.hinges_after,
                      res.impact.eccentricity, res.limit.eccentricity, "title")
    yield ax
    plt.close(fig)


def _by_label(ax, label):
    (line,) = [ln for ln in ax.get_lines() if ln.get_label() == label]
    return np.asarray(line.get_xydata())


def test_hinges_on_their_edges(axes, paper_result):
    R, t = 1.0, 0.15
    for label, hinges in (("hinges before impact", paper_result.hinges_before),
                          ("hinges after impact", paper_result.hinges_after)):
        xy = _by_label(axes, label)
        assert len(xy) == len(hinges) == 4
        expect = [R - t / 2 if h.side == "intrados" else R + t / 2 for h in hinges]
        assert np.allclose(np.hypot(xy[:, 0], xy[:, 1]), expect, atol=1e-12)
        # polar angle of a section at angle a from the left springing: 90 + beta/2 - a
        ang = np.degrees(np.arctan2(xy[:, 1], xy[:, 0]))
        assert np.allclose(ang, [90 + 78.75 - h.angle_deg for h in hinges], atol=1e-9)


def test_lines_inside_thickness_and_through_hinges(axes):
    imp, thr = _by_label(axes, "impulse line"), _by_label(axes, "thrust line (limit analysis)")
    for xy in (imp, thr):
        r = np.hypot(xy[:, 0], xy[:, 1])
        assert np.all(np.abs(r - 1.0) <= 0.075 + 1e-9)
    # the impulse line touches the edges (|e| = t/2) at the post-impact hinges
    for h in _by_label(axes, "hinges after impact"):
        assert np.min(np.linalg.norm(imp - h, axis=1)) < 0.015   # within one element (0.79 deg)
    assert axes.get_aspect() == 1.0
    styles = {ln.get_label(): (ln.get_color(), ln.get_linestyle()) for ln in axes.get_lines()}
    assert styles["impulse line"] == ("red", "-") and styles["thrust line (limit analysis)"][1] == "--"


def test_figure_file_not_blank(paper_result, tmp_path):
    from PIL import Image

    path = plot_paper_figure(paper_result, tmp_path / "fig12.png")
    img = np.asarray(Image.open(path).convert("RGB")).astype(int)
    ink = ~np.all(img > 245, axis=-1)
    assert 0.01 < ink.mean() < 0.3
    red = (img[..., 0] > 200) & (img[..., 1] < 80) & (img[..., 2] < 80)
    assert red.sum() > 200
