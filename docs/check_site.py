"""Checks over the built site (run by ``.ci/docs`` after Sphinx has built it).

    python docs/check_site.py [docs/_build/html] [--max-line 88] [--api-strict]

* every line of every code block (``<pre>``: listings, transcripts, gallery code and output)
  is at most ``--max-line`` characters long;
* the landing page (``index.html``) shows a figure (an ``<img>`` in the article);
* the API pages (``api/generated/*.html``) of functions have a Parameters and a Returns (or
  Yields) section, those of classes a Parameters (a class the user builds) or an Attributes
  (a result) section (exceptions need neither). Without ``--api-strict`` this check only reports the pages
  that lack them, as a count and a list, and does not fail.

Exit code 1 if a strict check fails, 0 otherwise.
"""
from __future__ import annotations

import argparse
import re
import sys
from html.parser import HTMLParser
from pathlib import Path

MAX_LINE = 88


class _Pre(HTMLParser):
    """The text of the ``<pre>`` elements of a page, and whether its article has an ``<img>``."""

    def __init__(self) -> None:
        super().__init__(convert_charrefs=True)
        self.blocks: list[str] = []
        self._depth = 0
        self._text: list[str] = []
        self.article_imgs = 0
        self._article = 0

    def handle_starttag(self, tag, attrs):
        if tag == "pre":
            self._depth += 1
            if self._depth == 1:
                self._text = []
        elif tag == "article":
            self._article += 1
        elif tag == "img" and self._article:
            self.article_imgs += 1

    def handle_endtag(self, tag):
        if tag == "pre" and self._depth:
            self._depth -= 1
            if self._depth == 0:
                self.blocks.append("".join(self._text))
        elif tag == "article" and self._article:
            self._article -= 1

    def handle_data(self, data):
        if self._depth:
            self._text.append(data)


def parse(path: Path) -> _Pre:
    p = _Pre()
    p.feed(path.read_text(encoding="utf-8"))
    p.close()
    return p


def long_lines(site: Path, limit: int) -> tuple[int, list[tuple[str, int, int]]]:
    """The number of code blocks of the site, and ``(page, block number, longest line)`` of
    every block with a line over ``limit`` characters."""
    total, bad = 0, []
    for page in sorted(site.rglob("*.html")):
        rel = page.relative_to(site).as_posix()
        if rel.startswith(("_", "genindex", "search", "py-modindex")):
            continue
        for i, block in enumerate(parse(page).blocks, 1):
            total += 1
            longest = max((len(line.rstrip()) for line in block.splitlines()), default=0)
            if longest > limit:
                bad.append((rel, i, longest))
    return total, bad


_SECTION = re.compile(r'<dt class="field-(?:odd|even)">(Parameters|Returns|Yields|Attributes)'
                      r'<span class="colon">')


def api_sections(site: Path) -> tuple[int, list[tuple[str, str]]]:
    """The number of API pages, and ``(page, what it lacks)`` of those without their sections:
    Parameters and Returns/Yields (functions), Parameters or Attributes (classes)."""
    pages = sorted((site / "api" / "generated").glob("*.html"))
    lacking = []
    for page in pages:
        text = page.read_text(encoding="utf-8")
        found = set(_SECTION.findall(text))
        if '<dl class="py exception">' in text:
            continue        # an exception: its message says it all
        is_class = '<dl class="py class">' in text
        if is_class:    # a class the user builds: its parameters; a result: its attributes
            missing = [] if found & {"Parameters", "Attributes"} else ["Parameters or Attributes"]
        else:
            missing = [s for s in ("Parameters", "Returns") if s not in found
                       and not (s == "Returns" and "Yields" in found)]
        if missing:
            lacking.append((page.name, " and ".join(missing)))
    return len(pages), lacking


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("site", nargs="?", default=str(Path(__file__).parent / "_build" / "html"))
    ap.add_argument("--max-line", type=int, default=MAX_LINE)
    ap.add_argument("--api-strict", action="store_true",
                    help="fail (instead of reporting) on API pages without the sections")
    args = ap.parse_args(argv)
    site = Path(args.site)
    if not (site / "index.html").is_file():
        print(f"check_site: no built site in {site}", file=sys.stderr)
        return 1
    failed = False

    total, bad = long_lines(site, args.max_line)
    for rel, i, longest in bad:
        print(f"{rel}: error: code block {i} has a line of {longest} characters "
              f"(> {args.max_line})")
    print(f"check_site: {len(bad)} of {total} code blocks have lines over {args.max_line} "
          "characters")
    failed |= bool(bad)

    index = parse(site / "index.html")
    if index.article_imgs == 0:
        print("check_site: the landing page (index.html) shows no figure")
        failed = True

    n_api, lacking = api_sections(site)
    label = "error" if args.api_strict else "warning"
    for name, missing in lacking:
        print(f"api/generated/{name}: {label}: no {missing} section")
    print(f"check_site: {len(lacking)} of {n_api} API pages lack Parameters and "
          "Returns/Attributes sections" + ("" if args.api_strict else " (reported only)"))
    if args.api_strict:
        failed |= bool(lacking)

    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
