"""Sphinx configuration of the fembeam documentation site.

Build (from the repository root; warnings are errors, every internal reference checked):

    python -m pip install -e ".[docs]"
    python -m sphinx -W --keep-going -n -b html docs docs/_build/html

The gallery runs every script of ``examples/`` and every tutorial of ``docs/tutorial_scripts/``
while the site is built. ``FEMBEAM_DOCS_GALLERY=fast`` (what ``.ci/docs`` builds) leaves out the
scripts listed in ``SLOW`` below, none at present: each of those is shown without output, under
a note on its page saying that it was not run and how to run it.
"""
from __future__ import annotations

import os
import re
import sys
from pathlib import Path

DOCS = Path(__file__).resolve().parent
ROOT = DOCS.parent
sys.path.insert(0, str(ROOT))          # document the checkout, not an installed copy
sys.path.insert(0, str(DOCS))

from gallery_support import FileScraper, copy_sources

import fembeam

project = "fembeam"
author = "the fembeam authors"
copyright = "the fembeam authors"
release = version = fembeam.__version__

extensions = [
    "sphinx.ext.autodoc",
    "sphinx.ext.autosummary",
    "sphinx.ext.mathjax",
    "numpydoc",
    "myst_parser",
    "sphinx_gallery.gen_gallery",
    "sphinx_design",
    "sphinxcontrib.programoutput",
    "xref",
]

source_suffix = {".rst": "restructuredtext", ".md": "markdown"}
root_doc = "index"
exclude_patterns = ["_build", "**/GALLERY_HEADER.rst", "tutorial_scripts"]
templates_path = ["_templates"]

# ------------------------------------------------------------------ Markdown pages
# The pages of docs/ are Markdown, read as they are on a code host; headings up to ### get
# anchors so that links like shapes.md#the-crown-of-a-pointed-arch resolve; ``$$ ... $$`` blocks
# are display math (MathJax), as a code host renders them.
myst_heading_anchors = 3
myst_enable_extensions = ["colon_fence", "dollarmath"]

# ------------------------------------------------------------------ API reference
autosummary_generate = True
autodoc_default_options = {"members": True, "member-order": "bysource"}
autodoc_typehints = "none"             # the signatures stay readable; types are in the docstrings
numpydoc_show_class_members = False    # autosummary lists the members
numpydoc_validation_checks: set[str] = set()
numpydoc_xref_param_type = False

# ------------------------------------------------------------------ gallery
GALLERY_MODE = os.environ.get("FEMBEAM_DOCS_GALLERY", "full")
if GALLERY_MODE not in ("fast", "full"):
    raise SystemExit(f"FEMBEAM_DOCS_GALLERY must be 'fast' or 'full', got {GALLERY_MODE!r}")
# the scripts the fast build (CI) does not run. Every script runs at present: the ten examples
# take ~110 s of CPU together (ex04, the El Centro runs: ~50 s), the tutorial ~30 s; the
# multi-block kernel is compiled once and cached by numba (NUMBA_CACHE_DIR, .ci/docs)
SLOW: list[str] = []
NOT_RUN = SLOW if GALLERY_MODE == "fast" else []

GALLERY_SOURCES = copy_sources({ROOT / "examples": "examples", DOCS / "tutorial_scripts": "tutorials"},
                               DOCS / "_build" / "gallery_src", not_run=NOT_RUN)

sphinx_gallery_conf = {
    "examples_dirs": [str(GALLERY_SOURCES / "examples"), str(GALLERY_SOURCES / "tutorials")],
    "gallery_dirs": ["gallery", "tutorials"],
    # a script runs unless it is one of NOT_RUN
    "filename_pattern": (r"/(?!(?:" + "|".join(map(re.escape, NOT_RUN)) + r")\.py$)[^/]+\.py$"
                         if NOT_RUN else r"\.py$"),
    "ignore_pattern": r"__init__\.py",
    "within_subsection_order": "FileNameSortKey",
    "image_scrapers": (FileScraper(GALLERY_SOURCES),),
    "download_all_examples": False,
    "show_memory": False,
    "remove_config_comments": True,
    "abort_on_example_error": True,
    "only_warn_on_example_error": False,
    "capture_repr": (),
    "min_reported_time": 1e9,          # no timings in the pages (they vary from run to run)
    "show_signature": False,
    "write_computation_times": False,
}

# ------------------------------------------------------------------ HTML
html_theme = "pydata_sphinx_theme"
html_title = f"fembeam {version}"
html_static_path = ["_static"]
html_css_files = ["fembeam.css"]
html_theme_options = {
    "navigation_with_keys": False,
    "show_toc_level": 2,
    "header_links_before_dropdown": 7,
    "secondary_sidebar_items": ["page-toc"],
}
html_show_sourcelink = False
# the pages without sub-pages have no navigation to show on the left
html_sidebars = {"index": [], "getting_started": []}


# ------------------------------------------------------------------ command output
# ``command-output`` blocks and the tutorial's commands run fembeam from this checkout, with the
# Python that builds the site
os.environ["PYTHONPATH"] = os.pathsep.join([str(ROOT), *filter(None, [os.environ.get("PYTHONPATH")])])
os.environ["PATH"] = os.pathsep.join([str(Path(sys.executable).parent), os.environ.get("PATH", "")])
programoutput_use_ansi = False


# Lines of a command's output longer than the site's limit (88 characters, docs/check_site.py)
# are cut there and end with "…", in the ``command-output`` blocks given ``:class: cut-lines``.
MAX_LINE = 88


def _cut_long_lines(app, doctree):
    from docutils import nodes

    for block in doctree.findall(nodes.literal_block):
        if "cut-lines" in block["classes"]:
            text = "\n".join(line if len(line) <= MAX_LINE else line[:MAX_LINE - 1] + "…"
                             for line in block.astext().splitlines())
            block.children = [nodes.Text(text)]
            block.rawsource = text


def setup(app):
    app.connect("doctree-read", _cut_long_lines, priority=600)   # after sphinxcontrib-programoutput
