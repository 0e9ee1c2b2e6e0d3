"""Transcripts folded to the site's code-line width.

The pages show program outputs (``docs/data/*.txt`` and pasted runs) whose lines may be wider
than the 88 characters ``docs/check_site.py`` allows.  :func:`fold` breaks such a line at a
space (or a table's ``|``), ends the first part with `` \\`` and carries the rest on the next
line after an indent of four spaces, as often as it takes.  Consecutive long lines of the same length (the rows of
a table) are broken at the same column, so their continuations stay aligned.  Nothing is
dropped or rounded: :func:`unfold` gives the transcript back, character for character.

``docs/regenerate.sh splice`` pastes ``fold(transcript)`` into the Markdown, and the tests that
compare a page with a transcript compare ``unfold(block)``.
"""
from __future__ import annotations

WIDTH = 88
INDENT = "    "
MARK = " \\"


def _cuts(line: str, width: int) -> set[int]:
    """The columns at which ``line`` may be cut: before a space or a ``|`` with text before it,
    leaving room for the mark."""
    return {c for c in range(1, min(width - len(MARK), len(line) - 1) + 1)
            if line[c] in " |" and line[:c].strip()}


def _fold_run(lines: list[str], width: int) -> list[str]:
    """Fold the long lines ``lines`` (of one length: one cut for all, if there is one)."""
    common = set.intersection(*(_cuts(line, width) for line in lines))
    cuts = [max(common)] * len(lines) if common and len(lines) > 1 else \
        [max(_cuts(line, width), default=None) for line in lines]
    out = []
    for line, c in zip(lines, cuts):
        if c is None:          # no space to cut at: left as it is
            out.append(line)
            continue
        out.append(line[:c] + MARK)
        out.extend(_fold_lines([INDENT + line[c:]], width))
    return out


def _fold_lines(lines: list[str], width: int) -> list[str]:
    out, i = [], 0
    while i < len(lines):
        if len(lines[i]) <= width:
            out.append(lines[i])
            i += 1
            continue
        j = i + 1
        while j < len(lines) and len(lines[j]) == len(lines[i]):
            j += 1
        out.extend(_fold_run(lines[i:j], width))
        i = j
    return out


def fold(text: str, width: int = WIDTH) -> str:
    """``text`` with every line longer than ``width`` folded (see the module's docstring)."""
    end = "\n" if text.endswith("\n") else ""
    return "\n".join(_fold_lines([ln.rstrip() for ln in text.splitlines()], width)) + end


def unfold(text: str) -> str:
    """The inverse of :func:`fold`: each line ending in `` \\`` joined with the next."""
    end = "\n" if text.endswith("\n") else ""
    out: list[str] = []
    join = False
    for line in text.splitlines():
        if join and line.startswith(INDENT):
            out[-1] = out[-1][:-len(MARK)] + line[len(INDENT):]
        else:
            out.append(line)
        join = out[-1].endswith(MARK)
    return "\n".join(out) + end
