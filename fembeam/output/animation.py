"""GIF animations of a matplotlib figure, written atomically and stopped at once by Ctrl-C.

:func:`save_gif` renders the frames one by one into memory (``draw(j)`` updates the
figure's artists for frame ``j``), then encodes them with Pillow into a temporary file
renamed onto the target (:func:`~fembeam.output.files.atomic`).  Unlike matplotlib's
animation writers, an error or an interrupt is not followed by the encoding of the frames
drawn so far (seconds of work on the way out): it propagates at once and leaves no file.
"""
from __future__ import annotations

import io
from typing import Callable

from .files import atomic

__all__ = ["save_gif"]


def save_gif(fig, draw: Callable[[int], object], frames: int, path, fps: float, dpi: float) -> None:
    """Write ``frames`` frames of ``fig`` (``draw(j)`` before frame ``j``) to the GIF ``path``,
    ``fps`` frames per second, ``dpi`` pixels per inch of the figure's size, looping."""
    from PIL import Image

    w, h = fig.get_size_inches()
    size = int(w * dpi), int(h * dpi)
    images = []
    for j in range(frames):
        draw(j)
        buf = io.BytesIO()
        fig.savefig(buf, format="rgba", dpi=dpi)
        im = Image.frombuffer("RGBA", size, buf.getbuffer(), "raw", "RGBA", 0, 1)
        # opaque frames as RGB: Pillow's conversion to a GIF palette does better from RGB
        images.append(im.convert("RGB") if im.getextrema()[3][0] == 255 else im.copy())
    with atomic(path) as tmp:
        images[0].save(tmp, format="GIF", save_all=True, append_images=images[1:], duration=int(1000 / fps), loop=0)
