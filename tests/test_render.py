"""Off-screen pyvista rendering (fembeam.output.render): really renders (EGL/llvmpipe in CI),
and the picture shows the arch, the red impulse line and the hinges where they are."""
import numpy as np
import pytest
from PIL import Image

from fembeam.output.render import render_png

SIZE = (800, 450)


@pytest.fixture(scope="module")
def picture(paper_result, tmp_path_factory):
    path = render_png(paper_result, tmp_path_factory.mktemp("render") / "arch.png", size=SIZE)
    return np.asarray(Image.open(path).convert("RGB")).astype(int)


def test_not_blank(picture):
    assert picture.shape == (SIZE[1], SIZE[0], 3)
    white = np.all(picture > 245, axis=-1)
    # the arch (t/R = 0.15, 157.5 deg) covers a band of the frame, not nothing, not all
    assert 0.05 < 1 - white.mean() < 0.6
    assert picture.std() > 30


def test_colours_of_lines_and_hinges(picture):
    r, g, b = picture[..., 0], picture[..., 1], picture[..., 2]
    red = (r > 200) & (g < 60) & (b < 60)
    blue = (b > 200) & (r < 60) & (g < 60)
    grey = (np.abs(r - 128) < 20) & (np.abs(g - 128) < 20) & (np.abs(b - 128) < 20)
    assert red.sum() > 300          # impulse line, ~4 px wide over the span
    assert blue.sum() > 4 * 20      # four post-impact hinges
    assert grey.sum() > 4 * 40      # four hinges before the impact (larger)
    # viridis body: many distinct colours (the speed field varies along the arch)
    body = ~(red | blue | grey | np.all(picture > 245, -1) | np.all(picture < 40, -1))
    assert len(np.unique(picture[body].reshape(-1, 3), axis=0)) > 200


def test_equal_aspect_and_symmetric_span(picture):
    """Parallel projection with equal aspect: the arch's drawn width over height equals
    the true one, (2 (R + t/2) sin(beta/2)) / ((R + t/2) - (R - t/2) cos(beta/2))."""
    p = picture
    coloured = np.abs(p[..., 0] - p[..., 1]) + np.abs(p[..., 1] - p[..., 2]) > 40   # not text, not grey
    coloured[:, int(0.85 * SIZE[0]):] = False      # scalar bar on the right
    rows, cols = np.nonzero(coloured)
    w, h = cols.max() - cols.min(), rows.max() - rows.min()
    beta = np.radians(157.5 / 2)
    true = 2 * 1.075 * np.sin(beta) / (1.075 - 0.925 * np.cos(beta))
    assert w / h == pytest.approx(true, rel=0.05)
