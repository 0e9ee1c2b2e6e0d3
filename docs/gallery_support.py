"""What the gallery needs besides sphinx-gallery (imported by docs/conf.py).

* :func:`copy_sources`: the gallery scripts are run from a copy under ``docs/_build``, so the
  files they write (figures, CSV, ParaView series) land there and never in the checkout; the
  copy of a script the build does not run says so at the top of its page;
* :class:`FileScraper`: the figures of a gallery page are the image files the script wrote
  (``.png`` and ``.gif``, as the command line's ``--plot``, ``--gif`` and ``--figure`` write
  them), each shown below the cell that wrote it.
"""
from __future__ import annotations

import shutil
from pathlib import Path

IMAGE_SUFFIXES = (".png", ".gif")
SOURCE_SUFFIXES = (".py", ".rst", ".txt", ".csv")


NOT_RUN_NOTE = """
.. note::

   This script was **not run** when this site was built: the page shows its code without its
   output or figures. Run it from a checkout of the repository with
   ``python {path}``.
"""


def copy_sources(sources: dict[Path, str], into: Path, not_run: list[str] = ()) -> Path:
    """Copy the scripts and headers of each source folder to ``into / name``, removing
    whatever else a previous build left there; returns ``into``. The copy of a script named
    in ``not_run`` (its stem) gets :data:`NOT_RUN_NOTE` after the title of its docstring."""
    for src, name in sources.items():
        dest = into / name
        if dest.exists():
            shutil.rmtree(dest)
        dest.mkdir(parents=True)
        for f in sorted(src.iterdir()):
            if f.is_file() and f.suffix in SOURCE_SUFFIXES:
                shutil.copy2(f, dest / f.name)
                if f.suffix == ".py" and f.stem in not_run:
                    _add_note(dest / f.name, f"{src.parent.name}/{src.name}/{f.name}"
                              if src.parent.name == "docs" else f"{src.name}/{f.name}")
    return into


def _add_note(script: Path, path: str) -> None:
    """Put :data:`NOT_RUN_NOTE` under the title (the underline of ``===``) of the docstring."""
    lines = script.read_text().split("\n")
    at = next(i for i, line in enumerate(lines) if line.startswith("===") and i > 1) + 1
    lines[at:at] = NOT_RUN_NOTE.format(path=path).split("\n")
    script.write_text("\n".join(lines))


class FileScraper:
    """sphinx-gallery image scraper: the ``.png``/``.gif`` files written in the example's
    folder since the previous cell (by modification time), copied to the gallery's image
    paths and shown in the order they were written."""

    def __init__(self, root: Path):
        self.root = Path(root)
        self.seen: dict[Path, int] = {}

    def __repr__(self) -> str:          # sphinx-gallery keys its cache on the configuration's text
        return f"FileScraper({self.root.name})"

    def __call__(self, block, block_vars, gallery_conf) -> str:
        from sphinx_gallery.scrapers import figure_rst

        folder = Path(block_vars["src_file"]).parent
        found = []
        for f in folder.iterdir():
            if f.suffix.lower() in IMAGE_SUFFIXES and f.is_file():
                stamp = f.stat().st_mtime_ns
                if self.seen.get(f) != stamp:
                    self.seen[f] = stamp
                    found.append((stamp, str(f), f))
        shown = []
        for _, _, f in sorted(found):
            target = Path(next(block_vars["image_path_iterator"])).with_suffix(f.suffix.lower())
            shutil.copyfile(f, target)
            shown.append(str(target))
        return figure_rst(shown, gallery_conf["src_dir"])
